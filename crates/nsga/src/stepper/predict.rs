//! The predicted Newton start of a step: the smooth unknowns extrapolated from the
//! solutions of the last steps, while no contact changed state (docs/method.md §4).
//!
//! Newton's iterates start from the last step's solution x_n. While the index sets stay
//! the same from step to step, the accelerations a and the forces λ are smooth functions
//! of time, and the polynomial through the last solutions predicts the next one to
//! O(Δt³) (quadratic, three solutions) or O(Δt²) (linear, two) instead of O(Δt). The
//! impulsive unknowns (U, Q, κ, Λ) are not smooth (they answer impacts and the drift of
//! the last step) and keep their last values. An index set that changes (an impact, a
//! contact that opens, a law that starts to slip) makes the history start again.
//!
//! Measured on the Lire collapse (`rollstack blocks lire --perturb bottom --t-end 9.99
//! --json`, `newton_iterations_mean`): 1.92 Newton updates per step from x_n, 0.89 with
//! the prediction (where it applies, see [`Tuning::predicted_start_iterations`](crate::Tuning::predicted_start_iterations) and
//! docs/method.md §4).

use super::unknowns::Offsets;

/// Solutions of the last steps whose index sets were all equal: (k, Δt, x) of steps k,
/// oldest first, at most two besides the current state's.
#[derive(Debug, Clone, Default)]
pub(super) struct StartPredictor {
    history: Vec<(u64, f64, Vec<f64>)>,
    /// The buffer of the solution that left the history, for the next prediction or
    /// the next attempt's start ([`StartPredictor::buffer`]): the unknowns go round from
    /// start to state to history without an allocation.
    spare: Vec<f64>,
}

impl StartPredictor {
    /// Forgets the history (a new state, layout or time step).
    pub(super) fn clear(&mut self) {
        self.history.clear();
    }

    /// Zeroes the entries `forgotten` of every kept solution (contact slots given to
    /// other pairs of bodies, whose past unknowns belong to the old pair).
    pub(super) fn forget(&mut self, forgotten: &[usize]) {
        for (_, _, x) in &mut self.history {
            for &i in forgotten {
                x[i] = 0.0;
            }
        }
    }

    /// Records the solution `x` of step `k` (Δt `dt`) as the state advances past it;
    /// `same_sets` says whether the step that follows it kept its index sets.
    pub(super) fn record(&mut self, k: u64, dt: f64, x: Vec<f64>, same_sets: bool) {
        if !same_sets {
            self.history.clear();
            self.give_back(x);
            return;
        }
        if self.history.len() == 2 {
            let (_, _, oldest) = self.history.remove(0);
            self.give_back(oldest);
        }
        self.history.push((k, dt, x));
    }

    /// An empty buffer for unknowns: the spare one, or a new one.
    pub(super) fn buffer(&mut self) -> Vec<f64> {
        let mut b = std::mem::take(&mut self.spare);
        b.clear();
        b
    }

    /// Keeps the buffer of unknowns no longer needed for [`StartPredictor::buffer`],
    /// where it is larger than the one kept.
    pub(super) fn give_back(&mut self, x: Vec<f64>) {
        if x.capacity() > self.spare.capacity() {
            self.spare = x;
        }
    }

    /// The predicted start of the step after state `k` whose solution is `x`, for time
    /// step `dt`: a, λ of every family extrapolated, the rest as in `x`; None without a
    /// history of consecutive steps of this Δt and layout.
    pub(super) fn predict(
        &mut self,
        k: u64,
        dt: f64,
        x: &[f64],
        off: &Offsets,
    ) -> Option<Vec<f64>> {
        // The solutions of steps k − 1 and k − 2 that fit, newest first.
        let mut fitting = self
            .history
            .iter()
            .rev()
            .zip(1..)
            .take_while(|((kh, dh, xh), back)| kh + back == k && *dh == dt && xh.len() == x.len())
            .map(|((_, _, xh), _)| xh.as_slice());
        let fitting = [fitting.next()?, fitting.next().unwrap_or_default()];
        let mut predicted = std::mem::take(&mut self.spare);
        predicted.clear();
        predicted.extend_from_slice(x);
        let [lg, lga, ln, lf] = off.forces();
        let smooth = [off.a..off.a + off.nu, lg, lga, ln, lf];
        match fitting {
            // Only the newest fits (a fitting solution has x's length, so is not empty).
            [x1, []] => smooth.into_iter().flatten().for_each(|i| {
                predicted[i] = 2.0 * x[i] - x1[i];
            }),
            [x1, x2] => smooth.into_iter().flatten().for_each(|i| {
                predicted[i] = 3.0 * (x[i] - x1[i]) + x2[i];
            }),
        }
        Some(predicted)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::system::{FrictionLaw, Layout};

    fn offsets() -> Offsets {
        let layout = Layout {
            nq: 1,
            nu: 1,
            n_bilateral_position: 0,
            n_bilateral_velocity: 0,
            e_n: vec![0.0],
            friction: Vec::<FrictionLaw>::new(),
        };
        Offsets::new(&layout)
    }

    /// x of step k for a = t², λ_N = 1 + t, the impulsive unknowns k-dependent noise.
    fn solution(k: u64, dt: f64, off: &Offsets) -> Vec<f64> {
        let t = k as f64 * dt;
        let mut x = vec![0.0; off.n];
        for (i, v) in x.iter_mut().enumerate() {
            *v = (k as f64 + i as f64).sin();
        }
        x[off.a] = t * t;
        x[off.ln] = 1.0 + t;
        x
    }

    #[test]
    fn the_prediction_extrapolates_the_smooth_unknowns_of_consecutive_steps() {
        let off = offsets();
        let dt = 0.1;
        let mut p = StartPredictor::default();
        assert!(p.predict(5, dt, &solution(5, dt, &off), &off).is_none());
        p.record(3, dt, solution(3, dt, &off), true);
        p.record(4, dt, solution(4, dt, &off), true);
        let x5 = solution(5, dt, &off);
        let next = p.predict(5, dt, &x5, &off).unwrap();
        // Quadratic through t = 0.3, 0.4, 0.5: exact for t² and 1 + t at t = 0.6.
        assert!((next[off.a] - 0.36).abs() < 1e-14, "{}", next[off.a]);
        assert!((next[off.ln] - 1.6).abs() < 1e-14);
        // The impulsive unknowns keep the last solution's values.
        assert_eq!(next[off.uu], x5[off.uu]);
        assert_eq!(next[off.cn], x5[off.cn]);
        assert_eq!(next[off.kn], x5[off.kn]);
    }

    #[test]
    fn a_change_of_sets_time_step_or_step_number_leaves_no_prediction() {
        let off = offsets();
        let dt = 0.1;
        let mut p = StartPredictor::default();
        p.record(3, dt, solution(3, dt, &off), true);
        p.record(4, dt, solution(4, dt, &off), true);
        // Linear from the newest alone when the older one is not step k − 2.
        let mut gap = p.clone();
        gap.history[0].0 = 1;
        let lin = gap.predict(5, dt, &solution(5, dt, &off), &off).unwrap();
        assert!((lin[off.a] - (2.0 * 0.25 - 0.16)).abs() < 1e-14);
        // Another Δt (a split step), another step number, another size: none.
        assert!(p
            .predict(5, dt / 2.0, &solution(5, dt, &off), &off)
            .is_none());
        assert!(p.predict(7, dt, &solution(7, dt, &off), &off).is_none());
        assert!(p.predict(5, dt, &[0.0; 3], &off).is_none());
        // A step whose sets changed starts the history again.
        p.record(5, dt, solution(5, dt, &off), false);
        assert!(p.predict(6, dt, &solution(6, dt, &off), &off).is_none());
    }
}
