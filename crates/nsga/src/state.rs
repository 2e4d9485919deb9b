//! The state the stepper carries from step to step (docs/method.md §3, "Carried over").

use crate::linalg::norm;

/// Two states closer than this ([`State::relative_distance`]) are the same continuation
/// (how branch candidates are deduplicated, docs/exploration.md).
///
/// Why 10⁻⁸: two Newton solves that reach the same solution of a step's equations from
/// different starts agree to about the Newton tolerance (10⁻¹⁰ by default, on residual
/// rows scaled to impulses), so the bound sits two orders above it and the same solution
/// found twice is one candidate. Distinct solutions differ in a contact's state (open
/// against closed, stick against slip), which changes an impulse by a finite amount:
/// the closest distinct candidates in the tests are kept apart by this bound
/// (`stepper::branch`'s tests assert it). A run with a looser `tol` than 10⁻¹⁰ can count
/// one solution twice.
pub const SAME_MOTION: f64 = 1e-8;

/// The state carried from step to step (docs/method.md §3 "Carried over").
#[derive(Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct State {
    /// Step counter k (t = t0 + k Δt, ERRATA 20).
    pub k: u64,
    /// Time t_k.
    pub t: f64,
    /// Coordinates q.
    pub q: Vec<f64>,
    /// Velocities u.
    pub u: Vec<f64>,
    /// Smooth acceleration a.
    pub a: Vec<f64>,
    /// Auxiliary acceleration ā.
    pub a_bar: Vec<f64>,
    /// Normal contact forces λ_N.
    pub lambda_n: Vec<f64>,
    /// Auxiliary λ̄_N.
    pub lambda_n_bar: Vec<f64>,
    /// Friction forces λ_F.
    pub lambda_f: Vec<f64>,
    /// Auxiliary λ̄_F.
    pub lambda_f_bar: Vec<f64>,
    /// Normal percussions P_N of the last step (eq. 95).
    pub p_n: Vec<f64>,
    /// Friction percussions P_F of the last step.
    pub p_f: Vec<f64>,
    /// The last step's unknowns x (eq. 126), the next Newton start.
    pub x: Vec<f64>,
}

/// Field by field, so that `clone_from` reuses the vectors' buffers: a caller that keeps
/// a copy of the state before each step (to undo it) then allocates nothing per step.
impl Clone for State {
    fn clone(&self) -> Self {
        let mut copy = Self {
            k: self.k,
            t: self.t,
            ..Self::default()
        };
        copy.clone_from(self);
        copy
    }

    fn clone_from(&mut self, source: &Self) {
        // The destructuring names every field: one added to the state must be copied
        // here too.
        let Self {
            k,
            t,
            q,
            u,
            a,
            a_bar,
            lambda_n,
            lambda_n_bar,
            lambda_f,
            lambda_f_bar,
            p_n,
            p_f,
            x,
        } = source;
        self.k = *k;
        self.t = *t;
        self.q.clone_from(q);
        self.u.clone_from(u);
        self.a.clone_from(a);
        self.a_bar.clone_from(a_bar);
        self.lambda_n.clone_from(lambda_n);
        self.lambda_n_bar.clone_from(lambda_n_bar);
        self.lambda_f.clone_from(lambda_f);
        self.lambda_f_bar.clone_from(lambda_f_bar);
        self.p_n.clone_from(p_n);
        self.p_f.clone_from(p_f);
        self.x.clone_from(x);
    }
}

impl State {
    /// The vectors q, u, a, ā, λ_N, λ̄_N, λ_F, λ̄_F, P_N, P_F, x, in that order.
    fn vectors_mut(&mut self) -> [&mut Vec<f64>; 11] {
        [
            &mut self.q,
            &mut self.u,
            &mut self.a,
            &mut self.a_bar,
            &mut self.lambda_n,
            &mut self.lambda_n_bar,
            &mut self.lambda_f,
            &mut self.lambda_f_bar,
            &mut self.p_n,
            &mut self.p_f,
            &mut self.x,
        ]
    }

    /// Whether two states are the same continuation: q and u agree to 1e-8 relative to
    /// 1 + ‖q‖ + ‖u‖ (how branch candidates are deduplicated, docs/method.md §4).
    #[must_use]
    pub fn same_motion(&self, other: &State) -> bool {
        self.relative_distance(other) <= SAME_MOTION
    }

    /// ‖(q, u) − (q, u)_other‖ / (1 + ‖q_other‖ + ‖u_other‖): the distance between two
    /// continuations, relative to the motion's size.
    #[must_use]
    pub fn relative_distance(&self, other: &State) -> f64 {
        let squared =
            |a: &[f64], b: &[f64]| -> f64 { a.iter().zip(b).map(|(x, y)| (x - y).powi(2)).sum() };
        let distance = (squared(&self.q, &other.q) + squared(&self.u, &other.u)).sqrt();
        distance / (1.0 + norm(&other.q) + norm(&other.u))
    }

    /// Sets the subnormal entries (0 < |v| < 2.2·10⁻³⁰⁸) of every vector to zero.
    ///
    /// A quantity whose exact value is zero, such as the vertical acceleration of a block
    /// resting or sliding on a floor, is solved each step from the last step's value and
    /// shrinks geometrically toward zero: after some hundred steps it passes into the
    /// subnormal range and stays there. Arithmetic on subnormal numbers takes a microcode
    /// assist on x86, about a hundred cycles per operation, and every later evaluation
    /// carries them. Zero is the value these numbers approximate, and it is what they
    /// become. (Measured in docs/method.md §3, "What is committed".)
    pub fn flush_subnormals(&mut self) {
        for v in self.vectors_mut() {
            // A branch-free scan first (it vectorizes): most states have none.
            let any = v.iter().fold(false, |any, &z| any | square_underflows(z));
            if any {
                v.iter_mut()
                    .filter(|z| z.is_subnormal())
                    .for_each(|z| *z = 0.0);
            }
        }
    }
}

/// Whether `z` is nonzero and its square below the smallest normal number (|z| below
/// 1.5·10⁻¹⁵⁴): true for every subnormal number, false for zeros, NaN and the
/// infinities. The scan of [`State::flush_subnormals`] tests this, two vectorized
/// comparisons, rather than [`f64::is_subnormal`] or `|z| < f64::MIN_POSITIVE`, which
/// both become a test on the bits, one entry at a time on x86-64 (the scan was 3 % of
/// the instructions of a pile of blocks at rest); only a vector that has such an entry
/// is tested exactly.
fn square_underflows(z: f64) -> bool {
    (z * z < f64::MIN_POSITIVE) & (z != 0.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The scan's test finds every subnormal number, of either sign, and no zero, NaN
    /// or infinity; the flush then zeroes exactly the subnormal entries.
    #[test]
    fn the_scan_finds_every_subnormal_entry() {
        let smallest = f64::from_bits(1);
        let largest_subnormal = f64::from_bits(f64::MIN_POSITIVE.to_bits() - 1);
        for z in [smallest, f64::MIN_POSITIVE / 4.0, largest_subnormal] {
            assert!(square_underflows(z) && square_underflows(-z), "{z:e}");
        }
        for z in [
            0.0,
            -0.0,
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            1e-150,
        ] {
            assert!(!square_underflows(z), "{z:e}");
        }
        let mut s = State {
            u: vec![
                -0.0,
                f64::NAN,
                f64::NEG_INFINITY,
                -f64::MIN_POSITIVE,
                -smallest,
                1e-200,
                largest_subnormal,
            ],
            ..State::default()
        };
        s.flush_subnormals();
        // −0.0 keeps its sign, NaN stays NaN, the normal numbers stay: only the
        // subnormal entries become +0.
        let bits: Vec<u64> = s.u.iter().map(|z| z.to_bits()).collect();
        assert_eq!(bits[0], (-0.0f64).to_bits());
        assert!(s.u[1].is_nan());
        assert_eq!(
            s.u[2..],
            [f64::NEG_INFINITY, -f64::MIN_POSITIVE, 0.0, 1e-200, 0.0]
        );
        assert_eq!(bits[4], 0.0f64.to_bits());
    }

    #[test]
    fn flushing_zeroes_only_subnormal_entries() {
        let tiny = f64::MIN_POSITIVE / 4.0;
        let mut s = State {
            u: vec![tiny, -tiny, f64::MIN_POSITIVE, 1.0, 0.0],
            x: vec![-tiny, 1e-300],
            ..State::default()
        };
        s.flush_subnormals();
        assert_eq!(s.u, vec![0.0, 0.0, f64::MIN_POSITIVE, 1.0, 0.0]);
        assert_eq!(s.x, vec![0.0, 1e-300]);
    }

    /// Every field is copied, by `clone` and by `clone_from` into a state of other sizes.
    #[test]
    fn clones_copy_every_field() {
        let ramp = |n: usize, from: f64| (0..n).map(|i| from + i as f64).collect::<Vec<_>>();
        let mut s = State {
            k: 7,
            t: 0.25,
            ..State::default()
        };
        for (i, v) in s.vectors_mut().into_iter().enumerate() {
            *v = ramp(i + 1, 10.0 * i as f64);
        }
        assert_eq!(s.clone(), s);
        let mut reused = State {
            k: 1,
            q: vec![0.0; 30],
            ..State::default()
        };
        reused.clone_from(&s);
        assert_eq!(reused, s);
    }
}
