//! Painlevé's paradoxes for a single block on a rough plane (App. I), self-contained.
//!
//! Point contact (§I.1): with ϑ measured as in (I.1.1) (the contact point P straight below
//! the centre at ϑ = 0), ℓ = √(w² + h²)/2 and I = m(w² + h²)/12 = mℓ²/3, the
//! dimensionless normal acceleration of P is u_P'' = a + b n (I.1.7) with
//!
//!   a = ϑ'² cos ϑ − 1,   b = 1 + 3 sin²ϑ − 3 μ_d sin ϑ cos ϑ sgn(ẋ_P),
//!
//! (I.1.8) as corrected by ERRATA 18 (sin²ϑ, not "3 cos ϑ"). The paradoxes occur where
//! b ≤ 0 (§I.1): for sgn(ẋ_P) sin ϑ cos ϑ > 0 that is μ_d ≥ (1 + 4 tan²ϑ)/(3 |tan ϑ|),
//! least, 4/3, at tan ϑ = ±1/2 (points i and ii of Figure I.2).
//!
//! Line contact (§I.2): both bottom corners on the plane, ϑ = ϑ' = 0, sliding with
//! sgn(ẋ) = s; the normal forces solve the 2 × 2 LCP (I.2.5)–(I.2.6).

use crate::error::BlockError;
use input::positive;

/// The coefficient b(ϑ, sgn ẋ_P, μ_d) of (I.1.8), corrected per ERRATA 18.
#[must_use]
pub fn b_coefficient(theta: f64, slip_sign: f64, mu_d: f64) -> f64 {
    let (s, c) = theta.sin_cos();
    1.0 + 3.0 * s * s - 3.0 * mu_d * s * c * slip_sign
}

/// The coefficient a(ϑ, ϑ') of (I.1.8): a = ϑ'² cos ϑ − 1.
#[must_use]
pub fn a_coefficient(theta: f64, theta_rate: f64) -> f64 {
    theta_rate * theta_rate * theta.cos() - 1.0
}

/// The friction coefficient at which b = 0 for the angle ϑ and slip sign s:
/// μ_d = (1 + 3 sin²ϑ)/(3 s sin ϑ cos ϑ); `None` where b > 0 for every μ_d ≥ 0
/// (s sin ϑ cos ϑ ≤ 0).
#[must_use]
pub fn critical_mu(theta: f64, slip_sign: f64) -> Option<f64> {
    let (s, c) = theta.sin_cos();
    let denom = 3.0 * s * c * slip_sign;
    (denom > 0.0).then(|| (1.0 + 3.0 * s * s) / denom)
}

/// The admissible range (ϑ_min, ϑ_max) = (−arctan(h/w), arctan(w/h)) of a block resting on
/// one corner (I.1.3).
///
/// # Errors
/// When the aspect ratio w/h is not finite and positive.
pub fn admissible_range(aspect_w_over_h: f64) -> Result<(f64, f64), BlockError> {
    let r = positive("aspect w/h", aspect_w_over_h)?;
    Ok((-(1.0 / r).atan(), r.atan()))
}

/// The solutions n = N/(mg) of the point-contact LCP (I.1.9): u_P'' = a + b n ≥ 0, n ≥ 0,
/// n u_P'' = 0. None when a < 0 and b ≤ 0 (inconsistency), two (0 and −a/b) when a > 0
/// and b < 0 (indeterminacy), otherwise one.
#[must_use]
pub fn point_contact_solutions(a: f64, b: f64) -> Vec<f64> {
    let mut out = Vec::new();
    if a >= 0.0 {
        // Lift-off: n = 0, u_P'' = a ≥ 0.
        out.push(0.0);
    }
    if b != 0.0 {
        let n = -a / b;
        if n > 0.0 {
            out.push(n);
        }
    }
    out
}

/// The least μ_d giving a paradox, and the angle where it is reached.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LeastFriction {
    /// The least μ_d (an infimum when reached at an end of the open range (I.1.3)).
    pub mu: f64,
    /// The angle ϑ where it is reached.
    pub theta: f64,
    /// sgn(ẋ_P) for which it is reached.
    pub slip_sign: f64,
}

/// The least μ_d with b ≤ 0 for one slip sign, over the angles (I.1.3) of a block of aspect
/// w/h. The function (1 + 4t²)/(3|t|), t = tan ϑ, is least at |t| = 1/2; when that angle
/// lies outside the range, the least value is at the range's end on the same side.
///
/// # Errors
/// Bad aspect ratio.
pub fn least_friction_for_sign(
    aspect_w_over_h: f64,
    slip_sign: f64,
) -> Result<LeastFriction, BlockError> {
    let (lo, hi) = admissible_range(aspect_w_over_h)?;
    let s = if slip_sign >= 0.0 { 1.0 } else { -1.0 };
    // b ≤ 0 needs s sin ϑ cos ϑ > 0: ϑ > 0 for s = +1, ϑ < 0 for s = −1 (|ϑ| < π/2).
    let best = 0.5_f64.atan();
    let theta = if s > 0.0 {
        best.min(hi)
    } else {
        (-best).max(lo)
    };
    let t = theta.tan().abs();
    Ok(LeastFriction {
        mu: (1.0 + 4.0 * t * t) / (3.0 * t),
        theta,
        slip_sign: s,
    })
}

/// The least μ_d giving a paradox for either slip sign (4/3 for every aspect, App. I).
///
/// # Errors
/// Bad aspect ratio.
pub fn least_friction(aspect_w_over_h: f64) -> Result<LeastFriction, BlockError> {
    let (lo, hi) = admissible_range(aspect_w_over_h)?;
    let plus = least_friction_for_sign(aspect_w_over_h, 1.0)?;
    let minus = least_friction_for_sign(aspect_w_over_h, -1.0)?;
    let inside = |l: &LeastFriction| l.theta > lo && l.theta < hi;
    // On a tie (4/3 on both sides) prefer the angle inside the open range (I.1.3), where
    // the least value is attained, not only approached; then sgn ẋ_P = +1.
    Ok(
        if minus.mu < plus.mu || (minus.mu == plus.mu && inside(&minus) && !inside(&plus)) {
            minus
        } else {
            plus
        },
    )
}

/// One node of the b-sign grid of Figure I.2(b).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BSample {
    /// ϑ (radians).
    pub theta: f64,
    /// μ_d.
    pub mu: f64,
    /// b for sgn(ẋ_P) = +1.
    pub b_plus: f64,
    /// b for sgn(ẋ_P) = −1.
    pub b_minus: f64,
    /// Whether ϑ lies in the admissible range (I.1.3).
    pub admissible: bool,
}

impl BSample {
    /// The columns of `painleve_b_grid.csv`.
    pub const CSV_HEADER: [&'static str; 6] = [
        "theta_rad",
        "theta_deg",
        "mu_d",
        "b_slip_positive",
        "b_slip_negative",
        "admissible",
    ];

    /// The node's cells under [`Self::CSV_HEADER`] (`admissible` as 0 or 1).
    #[must_use]
    pub fn csv_cells(&self) -> Vec<String> {
        vec![
            self.theta.to_string(),
            self.theta.to_degrees().to_string(),
            self.mu.to_string(),
            self.b_plus.to_string(),
            self.b_minus.to_string(),
            u8::from(self.admissible).to_string(),
        ]
    }
}

/// The most nodes per axis of [`b_grid`]: 2000 × 2000 nodes are 160 MB, far finer than
/// Figure I.2 needs.
pub const MAX_GRID_NODES: usize = 2000;

/// b on a grid of `n_theta` angles over (−π/2, π/2) (ends excluded) and `n_mu` values of
/// μ_d over [0, mu_max], row-major in μ_d then ϑ.
///
/// # Errors
/// Bad aspect ratio, mu_max ≤ 0, or fewer than two nodes along an axis.
pub fn b_grid(
    aspect_w_over_h: f64,
    mu_max: f64,
    n_theta: usize,
    n_mu: usize,
) -> Result<Vec<BSample>, BlockError> {
    let (lo, hi) = admissible_range(aspect_w_over_h)?;
    positive("mu_max", mu_max)?;
    if n_theta < 2 || n_mu < 2 {
        return Err(BlockError::Scene(
            "the b grid needs at least 2 nodes per axis".into(),
        ));
    }
    if n_theta > MAX_GRID_NODES || n_mu > MAX_GRID_NODES {
        return Err(BlockError::Scene(format!(
            "the b grid has at most {MAX_GRID_NODES} nodes per axis (4 million in all), got {n_theta} × {n_mu}"
        )));
    }
    let half_pi = std::f64::consts::FRAC_PI_2;
    let mut out = Vec::with_capacity(n_theta * n_mu);
    for j in 0..n_mu {
        let mu = mu_max * j as f64 / (n_mu - 1) as f64;
        for i in 0..n_theta {
            let theta = -half_pi + std::f64::consts::PI * (i as f64 + 0.5) / n_theta as f64;
            out.push(BSample {
                theta,
                mu,
                b_plus: b_coefficient(theta, 1.0, mu),
                b_minus: b_coefficient(theta, -1.0, mu),
                admissible: theta > lo && theta < hi,
            });
        }
    }
    Ok(out)
}

/// The normal forces n = N/(mg) of a block sliding on its bottom face (§I.2).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LineContact {
    /// n_R, at the right corner (front when sliding to the right).
    pub n_right: f64,
    /// n_L, at the left corner.
    pub n_left: f64,
}

/// The matrix of (I.2.6) at ϑ = ϑ' = 0, derived from (I.2.2): with κ = m w²/(4I) and
/// η = μ_d sgn(ẋ) h/w,
///
///   [u_R''; u_L''] = [[1 + κ(1 − η), 1 − κ(1 + η)], [1 − κ(1 − η), 1 + κ(1 + η)]] [n_R; n_L] − [1; 1].
///
/// Its eigenvalues are 2 and 2κ = m w²/(2I) (the thesis prints m w²/(4I) after (I.2.8); its
/// eigenvectors (I.2.9) are those of this matrix).
#[must_use]
pub fn line_contact_matrix(width: f64, height: f64, mu_d: f64, slip_sign: f64) -> [[f64; 2]; 2] {
    // m w²/(4I) with I = m(w² + h²)/12.
    let kappa = 3.0 * width * width / (width * width + height * height);
    let eta = mu_d * slip_sign * height / width;
    [
        [1.0 + kappa * (1.0 - eta), 1.0 - kappa * (1.0 + eta)],
        [1.0 - kappa * (1.0 - eta), 1.0 + kappa * (1.0 + eta)],
    ]
}

/// All solutions of the LCP (I.2.5): u'' = B n − 1 ≥ 0, n ≥ 0, u''·n = 0, for a block at
/// rest in orientation (ϑ = ϑ' = 0) sliding with sign s, by enumerating the four
/// complementary cases. With μ_d h/w < 1 the only solution is (I.2.10):
/// n_R = (1 + μ_d s h/w)/2, n_L = (1 − μ_d s h/w)/2: no paradox.
///
/// # Errors
/// Bad sizes or μ_d < 0.
pub fn line_contact_solutions(
    width: f64,
    height: f64,
    mu_d: f64,
    slip_sign: f64,
) -> Result<Vec<LineContact>, BlockError> {
    positive("width", width)?;
    positive("height", height)?;
    input::non_negative("mu", mu_d)?;
    let b = line_contact_matrix(width, height, mu_d, slip_sign);
    let tol = 1e-12;
    let mut out = Vec::new();
    let admissible = |n: [f64; 2]| {
        let u = [
            b[0][0] * n[0] + b[0][1] * n[1] - 1.0,
            b[1][0] * n[0] + b[1][1] * n[1] - 1.0,
        ];
        n.iter().all(|&x| x >= -tol) && u.iter().all(|&x| x >= -tol)
    };
    let mut push = |n: [f64; 2]| {
        if n.iter().all(|x| x.is_finite()) && admissible(n) {
            out.push(LineContact {
                n_right: n[0].max(0.0),
                n_left: n[1].max(0.0),
            });
        }
    };
    // Both corners pressed: B n = 1.
    let det = b[0][0] * b[1][1] - b[0][1] * b[1][0];
    if det.abs() > tol {
        push([(b[1][1] - b[0][1]) / det, (b[0][0] - b[1][0]) / det]);
    }
    // Only the right corner pressed, only the left, neither (free fall: u'' = −1 < 0, never).
    if b[0][0].abs() > tol {
        push([1.0 / b[0][0], 0.0]);
    }
    if b[1][1].abs() > tol {
        push([0.0, 1.0 / b[1][1]]);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_grid_beyond_the_bound_is_refused() {
        let err = b_grid(0.5, 3.0, 1_000_000, 1_000_000).unwrap_err();
        assert!(
            err.to_string().contains("at most 2000 nodes per axis"),
            "{err}"
        );
    }

    #[test]
    fn b_grid_csv_cells_match_the_header() {
        let grid = b_grid(0.5, 3.0, 3, 3).unwrap();
        for node in &grid {
            let cells = node.csv_cells();
            assert_eq!(cells.len(), BSample::CSV_HEADER.len());
            assert!(cells[5] == "0" || cells[5] == "1");
            assert_eq!(cells[2].parse::<f64>().unwrap(), node.mu);
        }
    }

    #[test]
    fn least_friction_is_four_thirds_at_tan_one_half() {
        for aspect in [0.25, 0.5, 1.0, 2.0, 5.0] {
            let l = least_friction(aspect).unwrap();
            assert!((l.mu - 4.0 / 3.0).abs() < 1e-14, "aspect {aspect}");
            assert!((l.theta.tan().abs() - 0.5).abs() < 1e-14);
            assert!(b_coefficient(l.theta, l.slip_sign, l.mu).abs() < 1e-14);
        }
        // ±26.565° (points i and ii of Figure I.2).
        assert!((0.5_f64.atan().to_degrees() - 26.565).abs() < 1e-3);
    }

    #[test]
    fn point_contact_lcp_cases() {
        // At rest (ϑ' = 0, a = −1): unique n = 1/b when b > 0, none when b ≤ 0.
        let th = 0.5_f64.atan();
        assert_eq!(
            point_contact_solutions(a_coefficient(th, 0.0), b_coefficient(th, 1.0, 0.2)).len(),
            1
        );
        assert!(point_contact_solutions(-1.0, b_coefficient(th, 1.0, 2.0)).is_empty());
        // Spinning fast enough that a > 0 with b < 0: two solutions (indeterminacy).
        let a = a_coefficient(th, 2.0);
        let b = b_coefficient(th, 1.0, 2.0);
        assert!(a > 0.0 && b < 0.0);
        let sols = point_contact_solutions(a, b);
        assert_eq!(sols.len(), 2);
        assert!((a + b * sols[1]).abs() < 1e-15);
    }

    #[test]
    fn admissible_range_of_figure_i2() {
        // ERRATA 18: ϑ_min = −63.435° for w/h = 0.5 (the caption's −64.435° is a typo).
        let (lo, hi) = admissible_range(0.5).unwrap();
        assert!((lo.to_degrees() + 63.435).abs() < 1e-3);
        assert!((hi.to_degrees() - 26.565).abs() < 1e-3);
        assert!(admissible_range(-1.0).is_err());
        assert!(admissible_range(f64::NAN).is_err());
    }

    #[test]
    fn critical_mu_is_where_b_vanishes() {
        for th in [-1.2, -0.4, 0.3, 0.9] {
            for s in [1.0, -1.0] {
                match critical_mu(th, s) {
                    Some(mu) => assert!(b_coefficient(th, s, mu).abs() < 1e-12),
                    None => assert!(b_coefficient(th, s, 10.0) > 0.0),
                }
            }
        }
    }

    #[test]
    fn b_from_the_equations_of_motion() {
        // Rebuild b from (I.1.4): with F = −μ N s, ÿ_P/g = n (1 + mℓ²/I (sin² − μ s sin cos)) + …
        let (w, h, m) = (0.3, 0.7, 2.0);
        let ell = 0.5 * f64::sqrt(w * w + h * h);
        let inertia = m * (w * w + h * h) / 12.0;
        for (th, s, mu) in [(0.4, 1.0, 0.8), (-0.7, 1.0, 2.0), (-0.2, -1.0, 1.5)] {
            let (sn, cs) = f64::sin_cos(th);
            let from_eom = 1.0 + m * ell * ell / inertia * (sn * sn - mu * s * sn * cs);
            assert!((from_eom - b_coefficient(th, s, mu)).abs() < 1e-13);
        }
    }

    #[test]
    fn line_contact_matches_i_2_10_and_is_unique() {
        for (w, h, mu, s) in [
            (1.0, 0.2, 0.3, 1.0),
            (0.2, 0.4, 0.2, -1.0),
            (1.0, 1.0, 0.9, 1.0),
        ] {
            let sols = line_contact_solutions(w, h, mu, s).unwrap();
            assert_eq!(sols.len(), 1);
            let eta = mu * s * h / w;
            assert!((sols[0].n_right - 0.5 * (1.0 + eta)).abs() < 1e-14);
            assert!((sols[0].n_left - 0.5 * (1.0 - eta)).abs() < 1e-14);
        }
        // μ h/w > 1: the back corner lifts (tipping), still a unique solution.
        let sols = line_contact_solutions(0.2, 0.4, 0.8, 1.0).unwrap();
        assert_eq!(sols.len(), 1);
        assert_eq!(sols[0].n_left, 0.0);
    }

    #[test]
    fn line_contact_eigenvalues() {
        let (w, h) = (1.0, 0.2);
        let b = line_contact_matrix(w, h, 0.3, 1.0);
        let tr = b[0][0] + b[1][1];
        let det = b[0][0] * b[1][1] - b[0][1] * b[1][0];
        let disc = (tr * tr / 4.0 - det).sqrt();
        let (l1, l2) = (tr / 2.0 + disc, tr / 2.0 - disc);
        let two_kappa = 6.0 * w * w / (w * w + h * h);
        let mut ev = [l1, l2];
        ev.sort_by(f64::total_cmp);
        let mut expect = [2.0, two_kappa];
        expect.sort_by(f64::total_cmp);
        assert!((ev[0] - expect[0]).abs() < 1e-12 && (ev[1] - expect[1]).abs() < 1e-12);
    }
}
