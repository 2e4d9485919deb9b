//! The lognormal fragility curve fitted to binary outcomes by maximum likelihood
//! (Baker 2015, "Efficient analytical fragility function fitting using dynamic
//! structural analysis", Earthquake Spectra 31(1), eq. 11):
//!
//!   P(collapse | IM = x) = Φ(ln(x/θ)/β),
//!
//! θ the median capacity (the intensity at which half the motions collapse the stack)
//! and β the dispersion of ln capacity. Written as a probit model, Φ(a + b ln x) with
//! b = 1/β and a = −ln θ/β, the log-likelihood of the outcomes yᵢ at intensities xᵢ,
//!
//!   ℓ(a, b) = Σ yᵢ ln Φ(ηᵢ) + (1 − yᵢ) ln Φ(−ηᵢ),  ηᵢ = a + b ln xᵢ,
//!
//! is concave, so Newton's method on its exact gradient and Hessian, halving any step
//! that does not raise ℓ, finds the maximum whenever one exists.
//!
//! **The band** is the delta method from the observed Fisher information I (the
//! negative Hessian of ℓ at the maximum): Var(η(x)) = [1, ln x] I⁻¹ [1, ln x]ᵀ, and the
//! 95 % band of the curve is Φ(η(x) ± 1.96 √Var), drawn through Φ so that it stays in
//! [0, 1]; θ's and β's bands are taken the same way on ln θ and ln β. It is chosen over
//! a parametric bootstrap because it is exact arithmetic on the fit itself: no seed, no
//! resample that happens to be degenerate, the same band on every machine. Like every
//! asymptotic band it is approximate for few runs; a test checks that it covers the
//! true θ about 95 % of the time at the sizes of a study (20 records × 10 levels).
//!
//! **When no maximum exists** the fit says why instead of returning NaN or a curve the
//! data do not support ([`Degenerate`]): no run collapsed (θ beyond the intensities
//! run), every run collapsed (θ below them), or the outcomes are separated by intensity
//! (every run up to some x survived and every run from it on collapsed: β → 0).

use super::normal;
use serde::Serialize;
use std::fmt;

/// The confidence of the bands.
pub const CONFIDENCE: f64 = 0.95;

/// Newton iterations before the fit gives up (a concave ℓ converges in about ten).
const MAX_ITERATIONS: usize = 200;

/// One run's outcome at its intensity.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Outcome {
    /// The intensity measure (> 0).
    pub im: f64,
    /// Whether the stack collapsed.
    pub collapsed: bool,
}

/// A fitted lognormal fragility curve with its band.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct LognormalFit {
    /// Median θ (units of the intensity).
    pub theta: f64,
    /// Dispersion β of ln capacity.
    pub beta: f64,
    /// θ's band at [`CONFIDENCE`].
    pub theta_band: [f64; 2],
    /// β's band at [`CONFIDENCE`].
    pub beta_band: [f64; 2],
    /// ℓ at the maximum.
    pub log_likelihood: f64,
    /// Runs fitted.
    pub runs: usize,
    /// Of them, those that collapsed.
    pub collapsed: usize,
    /// The covariance of (a, b) = (−ln θ/β, 1/β): the inverse observed information.
    pub covariance: [[f64; 2]; 2],
}

/// Why no lognormal curve fits the outcomes (the maximum of ℓ does not exist).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Degenerate {
    /// No run to fit.
    NoRuns,
    /// No run collapsed, up to the largest intensity `max`.
    NoneCollapsed {
        /// Runs.
        runs: usize,
        /// The largest intensity run.
        max: f64,
    },
    /// Every run collapsed, from the smallest intensity `min`.
    AllCollapsed {
        /// Runs.
        runs: usize,
        /// The smallest intensity run.
        min: f64,
    },
    /// Every run up to `survived` survived and every run from `collapsed` on collapsed.
    Separated {
        /// The largest intensity a run survived.
        survived: f64,
        /// The smallest intensity a run collapsed at.
        collapsed: f64,
    },
    /// Collapses do not come at higher intensities than survivals (b ≤ 0 at the best
    /// fit): the fraction does not grow with the intensity.
    NotIncreasing,
}

impl fmt::Display for Degenerate {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let n = |x: f64| significant(x, 4);
        match *self {
            Self::NoRuns => write!(f, "no run to fit"),
            Self::NoneCollapsed { runs, max } => write!(
                f,
                "none of the {runs} runs collapsed (intensities up to {}): the median lies beyond them; run stronger motions",
                n(max)
            ),
            Self::AllCollapsed { runs, min } => write!(
                f,
                "all {runs} runs collapsed (intensities from {}): the median lies below them; run weaker motions",
                n(min)
            ),
            Self::Separated { survived, collapsed } => write!(
                f,
                "every run up to {} survived and every run from {} on collapsed: the outcomes are separated, so beta -> 0 and the median lies between them; run more records or intensities between them",
                n(survived),
                n(collapsed)
            ),
            Self::NotIncreasing => write!(
                f,
                "collapses do not come at higher intensities than survivals: no increasing fragility curve fits"
            ),
        }
    }
}

/// `x` to `digits` significant digits (`0.1243`, `12.43`), for messages.
fn significant(x: f64, digits: i32) -> String {
    let magnitude = if x == 0.0 {
        0
    } else {
        x.abs().log10().floor() as i32
    };
    let decimals = (digits - 1 - magnitude).max(0) as usize;
    format!("{x:.decimals$}")
}

impl LognormalFit {
    /// The fitted P(collapse | IM = x).
    #[must_use]
    pub fn probability(&self, x: f64) -> f64 {
        normal::cdf(self.eta(x))
    }

    /// The band of P at x ([`CONFIDENCE`], module docs).
    #[must_use]
    pub fn band(&self, x: f64) -> [f64; 2] {
        let u = x.ln();
        let c = &self.covariance;
        let var = c[0][0] + 2.0 * u * c[0][1] + u * u * c[1][1];
        let half = z_of_confidence() * var.max(0.0).sqrt();
        let eta = self.eta(x);
        [normal::cdf(eta - half), normal::cdf(eta + half)]
    }

    fn eta(&self, x: f64) -> f64 {
        (x / self.theta).ln() / self.beta
    }
}

/// The z of a two-sided band at [`CONFIDENCE`] (1.96).
fn z_of_confidence() -> f64 {
    normal::quantile(0.5 + CONFIDENCE / 2.0)
}

/// ℓ, its gradient and the observed information (−Hessian) at (a, b).
fn likelihood(data: &[(f64, bool)], a: f64, b: f64) -> (f64, [f64; 2], [[f64; 2]; 2]) {
    let (mut l, mut g, mut h) = (0.0, [0.0; 2], [[0.0; 2]; 2]);
    for &(u, y) in data {
        // For y = 0, ln Φ(−η): the same terms with η's sign turned.
        let (s, eta) = if y {
            (1.0, a + b * u)
        } else {
            (-1.0, -(a + b * u))
        };
        let lambda = normal::mills(eta);
        let weight = lambda * (eta + lambda);
        l += normal::ln_cdf(eta);
        g[0] += s * lambda;
        g[1] += s * lambda * u;
        h[0][0] += weight;
        h[0][1] += weight * u;
        h[1][1] += weight * u * u;
    }
    h[1][0] = h[0][1];
    (l, g, h)
}

/// The inverse of a symmetric 2 × 2 matrix, or None when singular.
fn inverse(m: [[f64; 2]; 2]) -> Option<[[f64; 2]; 2]> {
    let det = m[0][0] * m[1][1] - m[0][1] * m[1][0];
    (det > 0.0 && det.is_finite()).then(|| {
        [
            [m[1][1] / det, -m[0][1] / det],
            [-m[1][0] / det, m[0][0] / det],
        ]
    })
}

/// Why the outcomes have no maximum of ℓ, checked before any iteration.
fn degenerate(data: &[Outcome]) -> Option<Degenerate> {
    let extreme = |collapsed: bool, pick: fn(f64, f64) -> f64, start: f64| {
        data.iter()
            .filter(|o| o.collapsed == collapsed)
            .map(|o| o.im)
            .fold(start, pick)
    };
    let runs = data.len();
    let collapsed = data.iter().filter(|o| o.collapsed).count();
    let all = || data.iter().map(|o| o.im);
    if runs == 0 {
        return Some(Degenerate::NoRuns);
    }
    if collapsed == 0 {
        let max = all().fold(f64::NEG_INFINITY, f64::max);
        return Some(Degenerate::NoneCollapsed { runs, max });
    }
    if collapsed == runs {
        let min = all().fold(f64::INFINITY, f64::min);
        return Some(Degenerate::AllCollapsed { runs, min });
    }
    let (survived, collapsed_from) = (
        extreme(false, f64::max, f64::NEG_INFINITY),
        extreme(true, f64::min, f64::INFINITY),
    );
    if survived <= collapsed_from {
        return Some(Degenerate::Separated {
            survived,
            collapsed: collapsed_from,
        });
    }
    let (survived_from, collapsed_up_to) = (
        extreme(false, f64::min, f64::INFINITY),
        extreme(true, f64::max, f64::NEG_INFINITY),
    );
    (collapsed_up_to <= survived_from).then_some(Degenerate::NotIncreasing)
}

/// The maximum-likelihood lognormal fragility of `data` (module docs).
///
/// # Errors
/// [`Degenerate`] when the maximum does not exist. An intensity that is not positive
/// and finite is a caller's error: such outcomes must be left out before (the caller
/// says how many).
pub fn fit_lognormal(data: &[Outcome]) -> Result<LognormalFit, Degenerate> {
    if let Some(d) = degenerate(data) {
        return Err(d);
    }
    let points: Vec<(f64, bool)> = data.iter().map(|o| (o.im.ln(), o.collapsed)).collect();
    let n = points.len() as f64;
    let mean = points.iter().map(|p| p.0).sum::<f64>() / n;
    let spread = (points.iter().map(|p| (p.0 - mean).powi(2)).sum::<f64>() / n).sqrt();
    let collapsed = data.iter().filter(|o| o.collapsed).count();
    // Start from the line through the mean ln x at the overall fraction, with β the
    // spread of ln x: inside the basin of the concave ℓ, a few steps from its top.
    let b0 = 1.0 / spread.max(1e-3);
    let mut ab = [normal::quantile(collapsed as f64 / n) - b0 * mean, b0];
    let (mut l, mut g, mut h) = likelihood(&points, ab[0], ab[1]);
    for _ in 0..MAX_ITERATIONS {
        let Some(hi) = inverse(h) else { break };
        let step = [
            hi[0][0] * g[0] + hi[0][1] * g[1],
            hi[1][0] * g[0] + hi[1][1] * g[1],
        ];
        let mut t = 1.0;
        let mut moved = false;
        for _ in 0..60 {
            let trial = [ab[0] + t * step[0], ab[1] + t * step[1]];
            let (lt, gt, ht) = likelihood(&points, trial[0], trial[1]);
            if lt >= l {
                (ab, l, g, h, moved) = (trial, lt, gt, ht, true);
                break;
            }
            t *= 0.5;
        }
        let small = step[0].abs() + step[1].abs() < 1e-12 * (1.0 + ab[0].abs() + ab[1].abs());
        if !moved || small {
            break;
        }
    }
    let [a, b] = ab;
    if b <= 0.0 {
        return Err(Degenerate::NotIncreasing);
    }
    let covariance = inverse(h).ok_or(Degenerate::NotIncreasing)?;
    let z = z_of_confidence();
    let ln_theta = -a / b;
    // ln θ = −a/b: gradient (−1/b, a/b²); ln β = −ln b: gradient (0, −1/b).
    let grad = [-1.0 / b, a / (b * b)];
    let var_ln_theta = grad[0] * grad[0] * covariance[0][0]
        + 2.0 * grad[0] * grad[1] * covariance[0][1]
        + grad[1] * grad[1] * covariance[1][1];
    let sd_ln_theta = var_ln_theta.max(0.0).sqrt();
    let sd_ln_beta = covariance[1][1].max(0.0).sqrt() / b;
    let (theta, beta) = (ln_theta.exp(), 1.0 / b);
    Ok(LognormalFit {
        theta,
        beta,
        theta_band: [
            theta * (-z * sd_ln_theta).exp(),
            theta * (z * sd_ln_theta).exp(),
        ],
        beta_band: [
            beta * (-z * sd_ln_beta).exp(),
            beta * (z * sd_ln_beta).exp(),
        ],
        log_likelihood: l,
        runs: data.len(),
        collapsed,
        covariance,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// SplitMix64: a seeded stream of uniforms in [0, 1).
    struct Uniform(u64);

    impl Uniform {
        fn next(&mut self) -> f64 {
            self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
            let mut z = self.0;
            z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
            z ^= z >> 31;
            (z >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    /// Outcomes drawn from the curve (θ, β): `per_level` runs at each of `levels`
    /// intensities from 0.1 to 1.0.
    fn drawn(theta: f64, beta: f64, levels: usize, per_level: usize, seed: u64) -> Vec<Outcome> {
        let mut u = Uniform(seed);
        (1..=levels)
            .flat_map(|k| std::iter::repeat_n(k as f64 / levels as f64, per_level))
            .map(|im| Outcome {
                im,
                collapsed: u.next() < normal::cdf((im / theta).ln() / beta),
            })
            .collect()
    }

    #[test]
    fn a_known_curve_is_recovered_within_its_band() {
        let (theta, beta) = (0.45, 0.4);
        let fit = fit_lognormal(&drawn(theta, beta, 10, 40, 7)).unwrap();
        assert!(
            (fit.theta_band[0]..=fit.theta_band[1]).contains(&theta),
            "{fit:?}"
        );
        assert!(
            (fit.beta_band[0]..=fit.beta_band[1]).contains(&beta),
            "{fit:?}"
        );
        assert!((fit.theta / theta - 1.0).abs() < 0.1 && (fit.beta / beta - 1.0).abs() < 0.3);
        // The curve's band holds the fitted curve and the true one at the median.
        let [lo, hi] = fit.band(theta);
        assert!(lo < 0.5 && 0.5 < hi && lo < fit.probability(theta));
        assert_eq!((fit.runs, fit.probability(fit.theta)), (400, 0.5));
    }

    #[test]
    fn the_band_covers_the_true_median_about_95_percent_of_the_time() {
        let (theta, beta) = (0.5, 0.5);
        let trials = 300;
        let (mut theta_in, mut beta_in) = (0, 0);
        for seed in 0..trials {
            // 20 records at 10 levels, as a small study.
            let fit = fit_lognormal(&drawn(theta, beta, 10, 20, seed)).unwrap();
            theta_in += usize::from((fit.theta_band[0]..=fit.theta_band[1]).contains(&theta));
            beta_in += usize::from((fit.beta_band[0]..=fit.beta_band[1]).contains(&beta));
        }
        let share = |k: usize| k as f64 / f64::from(trials as u32);
        assert!((0.91..=0.98).contains(&share(theta_in)), "{theta_in}");
        assert!((0.90..=0.98).contains(&share(beta_in)), "{beta_in}");
    }

    #[test]
    fn degenerate_outcomes_are_named_not_fitted() {
        let at = |pairs: &[(f64, bool)]| -> Vec<Outcome> {
            pairs
                .iter()
                .map(|&(im, collapsed)| Outcome { im, collapsed })
                .collect()
        };
        let e = |pairs: &[(f64, bool)]| fit_lognormal(&at(pairs)).unwrap_err();
        assert_eq!(e(&[]), Degenerate::NoRuns);
        assert_eq!(
            e(&[(0.1, false), (0.3, false)]),
            Degenerate::NoneCollapsed { runs: 2, max: 0.3 }
        );
        assert_eq!(
            e(&[(0.2, true), (0.3, true)]),
            Degenerate::AllCollapsed { runs: 2, min: 0.2 }
        );
        let separated = e(&[(0.1, false), (0.2, false), (0.2, true), (0.4, true)]);
        assert_eq!(
            separated,
            Degenerate::Separated {
                survived: 0.2,
                collapsed: 0.2
            }
        );
        assert!(separated
            .to_string()
            .contains("every run up to 0.2000 survived"));
        assert_eq!(significant(0.124_296_5, 4), "0.1243");
        assert_eq!(significant(12.431, 4), "12.43");
        assert_eq!(
            e(&[(0.1, true), (0.2, true), (0.3, false), (0.4, false)]),
            Degenerate::NotIncreasing
        );
        // Overlapping outcomes whose best line falls with intensity.
        let falling = e(&[
            (0.1, true),
            (0.2, false),
            (0.2, true),
            (0.3, true),
            (0.4, false),
            (0.5, false),
        ]);
        assert_eq!(falling, Degenerate::NotIncreasing);
        for d in [Degenerate::NoRuns, falling, separated] {
            let text = d.to_string();
            assert!(!text.contains("NaN") && !text.contains('\n'), "{text}");
        }
        // One overlap is enough for a finite fit.
        let fit = fit_lognormal(&at(&[
            (0.1, false),
            (0.3, true),
            (0.2, false),
            (0.25, true),
            (0.28, false),
        ]))
        .unwrap();
        assert!(fit.theta.is_finite() && fit.beta > 0.0 && fit.band(0.2)[0] >= 0.0);
    }
}
