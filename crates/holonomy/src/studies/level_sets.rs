//! The level sets of the angle ψ(ϑ, φ2) of the holonomy of a rectangle: Figure 2.5.

use std::f64::consts::TAU;

/// The levels of Figure 2.5, ψ in degrees.
pub const FIGURE_2_5_LEVELS_DEG: [f64; 8] = [5.0, 45.0, 90.0, 135.0, 180.0, 225.0, 270.0, 315.0];

/// The curve ψ(ϑ, φ2) = `psi` in the square [0, 2π]² of Figure 2.5, as polylines of
/// points [ϑ, φ2], from (2.4.11) corrected by ERRATA item 1,
///
/// sin²(φ2/2) = (1 − cos(ψ/2)) / (2 sin²(ϑ/2)),
///
/// solved for φ2 at `samples + 1` evenly spaced ϑ in [0, 2π]. The right side grows away
/// from ϑ = π, so each level is one arc φ2 ∈ [0, π] over the ϑ where it is at most 1 and
/// its mirror image 2π − φ2: two branches, ordered by ϑ. (ψ is the same for every φ1
/// and for both directions.)
#[must_use]
pub fn level_set_branches(psi: f64, samples: usize) -> Vec<Vec<[f64; 2]>> {
    let k = 0.5 * (1.0 - (0.5 * psi).cos());
    let mut lower = Vec::new();
    for i in 0..=samples {
        #[allow(clippy::cast_precision_loss)]
        let t = TAU * i as f64 / samples as f64;
        let u = (0.5 * t).sin().powi(2);
        if u >= k && u > 0.0 {
            lower.push([t, 2.0 * (k / u).sqrt().min(1.0).asin()]);
        }
    }
    let upper: Vec<[f64; 2]> = lower.iter().map(|&[t, p]| [t, TAU - p]).collect();
    vec![lower, upper]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rectangle::holonomy_angle;

    #[test]
    fn level_sets_lie_on_the_level() {
        for psi in [0.3, 2.0, 5.0] {
            let branches = level_set_branches(psi, 400);
            assert_eq!(branches.len(), 2);
            for b in branches {
                assert!(!b.is_empty());
                for [t, p] in b {
                    assert!((holonomy_angle(t, p) - psi).abs() < 1e-9);
                }
            }
        }
    }

    #[test]
    fn figure_2_5_levels_all_have_curves() {
        for deg in FIGURE_2_5_LEVELS_DEG {
            let b = level_set_branches(deg.to_radians(), 400);
            assert!(b[0].len() > 1, "{deg}");
            // Symmetric about ϑ = π, to the sampling step (round-off decides the ends).
            let first = b[0].first().unwrap();
            let last = b[0].last().unwrap();
            assert!((first[0] + last[0] - TAU).abs() <= TAU / 400.0 + 1e-12);
            // The mirror branch.
            assert!((b[1][0][1] - (TAU - first[1])).abs() < 1e-15);
        }
    }
}
