//! How far two motions of the same stack are apart, and when nearby motions separate:
//! the distance of their configurations, step by step, and a finite-time Lyapunov
//! estimate from its growth.
//!
//! **Distance.** The largest displacement of any corner of any block between two
//! configurations, bounded by |Δr| + ρ|Δθ| per block (r its centre, ρ its half
//! diagonal): a length, the same for final poses and for a trajectory, and zero only
//! when the two are the same configuration.
//!
//! **Separation.** A perturbed run at the unperturbed run's Δt is compared state by state
//! with it (the same time grid). The two motions *separate* at the first step where
//! their distance reaches the pose tolerance of the verdicts
//! ([`super::verdict::POSE_TOLERANCE`] times the smallest block dimension): from then
//! on they no longer count as the same motion. The *separating window* runs from the
//! last step before that at which the distance was within [`WINDOW_GROWTH`] times its
//! first value (its first value above round-off, [`DISTANCE_FLOOR`]) to the step where
//! it separated; the finite-time Lyapunov estimate λ is the least-squares slope of
//! ln(distance) against t over the steps of that window. A window of fewer than
//! [`MIN_WINDOW_SAMPLES`] steps has no slope: the motions jumped apart within a step or
//! two, a discontinuous decision (a contact opening or not, a block tipping or not)
//! rather than exponential divergence; `largest_step_growth` says by how much one step
//! multiplied the distance.

use crate::simulation::BlockPose;

/// The distance below which two configurations count as equal to round-off, as a
/// fraction of the smallest block dimension: coordinates of order 1–10 carry errors of
/// 1e-15 to 1e-14, and the smallest perturbation of the ensemble is 1e-10 of a block.
pub const DISTANCE_FLOOR: f64 = 1e-13;

/// The separating window starts at the last step whose distance was within this factor
/// of the first distance above round-off: before it the perturbation is carried along
/// (a column resting on its base), not amplified.
pub const WINDOW_GROWTH: f64 = 10.0;

/// Fewest steps in a separating window for a least-squares slope.
pub const MIN_WINDOW_SAMPLES: usize = 3;

/// The largest corner displacement between two configurations of the same blocks
/// (module docs); `radii` are the blocks' half diagonals. Configurations of different
/// lengths are infinitely far apart.
#[must_use]
pub fn corner_distance(a: &[BlockPose], b: &[BlockPose], radii: &[f64]) -> f64 {
    if a.len() != b.len() || a.len() != radii.len() {
        return f64::INFINITY;
    }
    a.iter()
        .zip(b)
        .zip(radii)
        .map(|((p, q), r)| (p.x - q.x).hypot(p.y - q.y) + r * (p.theta - q.theta).abs())
        .fold(0.0, f64::max)
}

/// When and how fast a perturbed motion left the unperturbed one (module docs).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Separation {
    /// The first distance above round-off, and its time (None: the runs stayed equal
    /// to round-off).
    pub initial: Option<[f64; 2]>,
    /// When the motions separated (the distance reached the pose tolerance).
    pub separated_at: Option<f64>,
    /// The separating window [t₀, t₁].
    pub window: Option<[f64; 2]>,
    /// Steps in the window.
    pub window_samples: usize,
    /// λ, the slope of ln(distance) over the window (1 / model time unit).
    pub lyapunov: Option<f64>,
    /// The largest factor by which one step of the window multiplied the distance.
    pub largest_step_growth: Option<f64>,
    /// The largest distance over the compared steps.
    pub max_distance: f64,
    /// Steps compared.
    pub compared: usize,
}

impl Separation {
    /// The separation of a distance series (t, d) (module docs): `floor` the round-off
    /// distance, `separated` the pose tolerance, both lengths.
    #[must_use]
    pub fn of(series: &[(f64, f64)], floor: f64, separated: f64) -> Self {
        let max_distance = series.iter().map(|s| s.1).fold(0.0, f64::max);
        let mut out = Self {
            initial: None,
            separated_at: None,
            window: None,
            window_samples: 0,
            lyapunov: None,
            largest_step_growth: None,
            max_distance,
            compared: series.len(),
        };
        let Some(first) = series.iter().position(|s| s.1 > floor) else {
            return out;
        };
        let d0 = series[first].1;
        out.initial = Some([series[first].0, d0]);
        let Some(end) = series[first..]
            .iter()
            .position(|s| s.1 >= separated)
            .map(|i| first + i)
        else {
            return out;
        };
        out.separated_at = Some(series[end].0);
        let start = (first..end)
            .rev()
            .find(|&i| series[i].1 <= WINDOW_GROWTH * d0)
            .unwrap_or(end);
        let window = &series[start..=end];
        out.window = Some([series[start].0, series[end].0]);
        out.window_samples = window.len();
        out.largest_step_growth = window
            .windows(2)
            .filter(|w| w[0].1 > floor)
            .map(|w| w[1].1 / w[0].1)
            .reduce(f64::max);
        let logs: Vec<(f64, f64)> = window
            .iter()
            .filter(|s| s.1 > floor)
            .map(|s| (s.0, s.1.ln()))
            .collect();
        if logs.len() >= MIN_WINDOW_SAMPLES {
            out.lyapunov = slope(&logs);
        }
        out
    }
}

/// The least-squares slope of y against x (None when every x is the same).
fn slope(points: &[(f64, f64)]) -> Option<f64> {
    #[allow(clippy::cast_precision_loss)]
    let n = points.len() as f64;
    let mx = points.iter().map(|p| p.0).sum::<f64>() / n;
    let my = points.iter().map(|p| p.1).sum::<f64>() / n;
    let sxx: f64 = points.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let sxy: f64 = points.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    (sxx > 0.0).then(|| sxy / sxx)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pose(x: f64, y: f64, theta: f64) -> BlockPose {
        BlockPose { x, y, theta }
    }

    #[test]
    fn the_distance_bounds_every_corner_displacement() {
        let a = [pose(0.0, 0.0, 0.0), pose(1.0, 1.0, 0.0)];
        let b = [pose(3e-3, 4e-3, 0.0), pose(1.0, 1.0, 1e-3)];
        // Block 1: |Δr| = 5e-3; block 2: ρ|Δθ| = 0.5e-3.
        let d = corner_distance(&a, &b, &[0.5, 0.5]);
        assert!((d - 5e-3).abs() < 1e-15, "{d}");
        assert_eq!(corner_distance(&a, &b[..1], &[0.5]), f64::INFINITY);
    }

    #[test]
    fn exponential_growth_gives_its_rate() {
        // d = 1e-10 e^{3t} from t = 1 on, flat before: the window is the growth only.
        let series: Vec<(f64, f64)> = (0..800)
            .map(|i| {
                let t = f64::from(i) * 0.01;
                (t, 1e-10 * (3.0 * (t - 1.0).max(0.0)).exp())
            })
            .collect();
        let s = Separation::of(&series, 1e-14, 1e-3);
        let lambda = s.lyapunov.unwrap();
        assert!((lambda - 3.0).abs() < 1e-9, "{lambda}");
        // ln(1e7)/3 after t = 1.
        let t_sep = s.separated_at.unwrap();
        assert!(
            (t_sep - (1.0 + 1e7_f64.ln() / 3.0)).abs() < 0.011,
            "{t_sep}"
        );
        let [t0, t1] = s.window.unwrap();
        assert!(t0 > 1.7 && t0 < 1.8 && t1 == t_sep, "{t0} {t1}");
    }

    #[test]
    fn a_jump_has_no_slope_and_equal_runs_never_separate() {
        let mut series: Vec<(f64, f64)> = (0..50).map(|i| (f64::from(i), 1e-10)).collect();
        series.push((50.0, 2e-2));
        let s = Separation::of(&series, 1e-14, 1e-3);
        assert_eq!(s.separated_at, Some(50.0));
        assert_eq!(s.window_samples, 2);
        assert_eq!(s.lyapunov, None);
        assert!((s.largest_step_growth.unwrap() - 2e8).abs() < 1.0);
        let equal: Vec<(f64, f64)> = (0..10).map(|i| (f64::from(i), 0.0)).collect();
        let s = Separation::of(&equal, 1e-14, 1e-3);
        assert!(s.initial.is_none() && s.separated_at.is_none() && s.compared == 10);
    }
}
