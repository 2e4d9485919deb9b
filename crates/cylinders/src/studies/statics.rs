//! The support-force curves of Figures 3.3, 3.4, 3.5, 3.7 and 3.8 (§3.3, corrected per
//! ERRATA 9–11) as typed rows and series, with the cells of their CSV rows: what
//! `rollstack cylinder statics` writes to CSV and plots.
//!
//! Inclinations are sampled at ϑ_k = (π/2) k / n, k = 1 … n − 1, so neither end of the
//! point-contact range (0, π/2) is evaluated.

use crate::error::CylinderError;
use crate::statics::{
    FrictionLimit, MinForceCase, MinimumForce, MinimumForceCircle, SupportProblem,
};
use serde::{Deserialize, Serialize};
use std::f64::consts::FRAC_PI_2;

/// The aspect ratios r/h of Figure 3.4 (μ fixed).
pub const FIGURE_3_4_R_OVER_H: [f64; 4] = [0.0, 0.05, 0.1, 0.15];

/// The friction coefficients μ of Figure 3.5 (r/h fixed).
pub const FIGURE_3_5_MU: [f64; 7] = [0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6];

/// N/mg at one inclination for the two friction limits and the smooth plane.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct NormalForceRow {
    /// Inclination ϑ, rad.
    pub theta: f64,
    /// N/mg at F_f = +μN e′2, (3.3.8)₊ (ERRATA 9); `None` when no positive N.
    pub n_over_mg_plus: Option<f64>,
    /// N/mg on a smooth plane, (3.3.10); `None` when no positive N.
    pub n_over_mg_smooth: Option<f64>,
    /// N/mg at F_f = −μN e′2, (3.3.8)₋; `None` when no positive N.
    pub n_over_mg_minus: Option<f64>,
}

/// A CSV cell of an optional number: the number in shortest round-trip form, or empty
/// when there is none (or it is not finite).
fn optional_cell(v: Option<f64>) -> String {
    v.filter(|v| v.is_finite())
        .map_or_else(String::new, |v| v.to_string())
}

/// The N/mg columns of the statics CSV files: (3.3.8)₊, (3.3.10), (3.3.8)₋.
const N_COLUMNS: [&str; 3] = ["n_over_mg_plus", "n_over_mg_smooth", "n_over_mg_minus"];

impl NormalForceRow {
    /// N/mg at the friction limit `limit`.
    #[must_use]
    pub fn n_over_mg(&self, limit: FrictionLimit) -> Option<f64> {
        match limit {
            FrictionLimit::Plus => self.n_over_mg_plus,
            FrictionLimit::Smooth => self.n_over_mg_smooth,
            FrictionLimit::Minus => self.n_over_mg_minus,
        }
    }

    /// The columns of fig3_3.csv: ϑ in rad and in degrees, then N/mg at F_f = +μN e′2
    /// (3.3.8)₊, on a smooth plane (3.3.10) and at F_f = −μN e′2 (3.3.8)₋.
    pub const CSV_HEADER: [&'static str; 5] = [
        "theta",
        "theta_deg",
        N_COLUMNS[0],
        N_COLUMNS[1],
        N_COLUMNS[2],
    ];

    /// The cells of this row under [`Self::CSV_HEADER`]: numbers in shortest round-trip
    /// form, an empty cell where there is no positive N.
    #[must_use]
    pub fn csv_cells(&self) -> Vec<String> {
        let theta = [self.theta, self.theta.to_degrees()].map(|v| v.to_string());
        theta.into_iter().chain(self.n_cells()).collect()
    }

    /// The three N/mg cells, in the order of [`N_COLUMNS`].
    fn n_cells(&self) -> [String; 3] {
        [
            self.n_over_mg_plus,
            self.n_over_mg_smooth,
            self.n_over_mg_minus,
        ]
        .map(optional_cell)
    }
}

/// The N/mg curves of one (r/h, μ): a panel of Figure 3.3, a member of the families of
/// Figures 3.4 and 3.5.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct NormalForceCurves {
    /// Aspect ratio r/h.
    pub r_over_h: f64,
    /// Friction coefficient μ.
    pub mu: f64,
    /// One row per sampled inclination.
    pub rows: Vec<NormalForceRow>,
}

impl NormalForceCurves {
    /// N/mg of (3.3.8) (corrected per ERRATA 9) and (3.3.10) at each of `thetas`.
    ///
    /// # Errors
    /// A negative or non-finite r/h or μ, a ϑ outside (0, π/2).
    pub fn new(r_over_h: f64, mu: f64, thetas: &[f64]) -> Result<Self, CylinderError> {
        let p = SupportProblem::new(r_over_h, mu)?;
        let rows = thetas
            .iter()
            .map(|&theta| {
                let n = |limit| p.normal_force(theta, limit);
                Ok(NormalForceRow {
                    theta,
                    n_over_mg_plus: n(FrictionLimit::Plus)?,
                    n_over_mg_smooth: n(FrictionLimit::Smooth)?,
                    n_over_mg_minus: n(FrictionLimit::Minus)?,
                })
            })
            .collect::<Result<_, CylinderError>>()?;
        Ok(Self { r_over_h, mu, rows })
    }

    /// The columns of fig3_4.csv and fig3_5.csv (one family member after another): r/h,
    /// μ, ϑ (rad), then N/mg at (3.3.8)₊, (3.3.10) and (3.3.8)₋ as in
    /// [`NormalForceRow::CSV_HEADER`].
    pub const CSV_HEADER: [&'static str; 6] = [
        "r_over_h",
        "mu",
        "theta",
        N_COLUMNS[0],
        N_COLUMNS[1],
        N_COLUMNS[2],
    ];

    /// One row of cells per sampled inclination under [`Self::CSV_HEADER`]: numbers in
    /// shortest round-trip form, an empty cell where there is no positive N.
    #[must_use]
    pub fn csv_rows(&self) -> Vec<Vec<String>> {
        self.rows
            .iter()
            .map(|r| {
                let keys = [self.r_over_h, self.mu, r.theta].map(|v| v.to_string());
                keys.into_iter().chain(r.n_cells()).collect()
            })
            .collect()
    }

    /// The curve of one limit as (ϑ in degrees, N/mg) points, clipped to N/mg ≤ 1
    /// (F3 ≥ 0: the figures' range).
    #[must_use]
    pub fn curve(&self, limit: FrictionLimit) -> Vec<(f64, f64)> {
        self.rows
            .iter()
            .filter_map(|r| {
                r.n_over_mg(limit)
                    .filter(|n| *n <= 1.0)
                    .map(|n| (r.theta.to_degrees(), n))
            })
            .collect()
    }
}

/// The minimum applied force at one inclination (Figures 3.7 and 3.8).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct MinimumForceRow {
    /// Inclination ϑ, rad.
    pub theta: f64,
    /// (F3/mg, F/mg) of the unconstrained minimum (3.3.15): a point of the circle BC
    /// (3.3.20), ERRATA 11.
    pub unconstrained: [f64; 2],
    /// Whether that point is admissible: it satisfies the friction criterion (3.3.17)
    /// and F3 ≥ 0.
    pub admissible: bool,
    /// The minimum over the admissible forces, (3.3.15)–(3.3.19); `None` when no
    /// support exists.
    pub minimum: Option<MinimumForce>,
}

impl MinimumForceRow {
    /// The columns of fig3_7_fig3_8.csv: ϑ in rad and in degrees; (F3/mg, F/mg) of the
    /// unconstrained minimum (3.3.15) on the circle (3.3.20); whether it satisfies the
    /// friction criterion (3.3.17) and F3 ≥ 0 (1 or 0); F3/mg, F/mg and ‖F_a‖/mg of the
    /// minimum over the admissible forces (3.3.15)–(3.3.19); and its case
    /// ([`MinForceCase::name`], `none` without a support).
    pub const CSV_HEADER: [&'static str; 9] = [
        "theta",
        "theta_deg",
        "circle_f3_over_mg",
        "circle_f_over_mg",
        "satisfies_3_3_17",
        "min_f3_over_mg",
        "min_f_over_mg",
        "min_norm_over_mg",
        "case",
    ];

    /// The cells of this row under [`Self::CSV_HEADER`]: numbers in shortest round-trip
    /// form, the minimum's cells empty when there is no support.
    #[must_use]
    pub fn csv_cells(&self) -> Vec<String> {
        let m = self.minimum;
        vec![
            self.theta.to_string(),
            self.theta.to_degrees().to_string(),
            self.unconstrained[0].to_string(),
            self.unconstrained[1].to_string(),
            u8::from(self.admissible).to_string(),
            optional_cell(m.map(|m| m.f3_over_mg)),
            optional_cell(m.map(|m| m.f_over_mg)),
            optional_cell(m.map(|m| m.norm_over_mg)),
            m.map_or_else(|| "none".to_owned(), |m| m.case.name().to_owned()),
        ]
    }
}

/// The data of Figures 3.3, 3.4, 3.5, 3.7 and 3.8 for one (r/h, μ).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StaticsFigures {
    /// Aspect ratio r/h of Figures 3.3, 3.5, 3.7, 3.8.
    pub r_over_h: f64,
    /// Friction coefficient μ of Figures 3.3, 3.4, 3.7, 3.8.
    pub mu: f64,
    /// Figure 3.3: N/mg for the two friction limits and the smooth plane.
    pub figure_3_3: NormalForceCurves,
    /// Figure 3.4: μ fixed, r/h = [`FIGURE_3_4_R_OVER_H`].
    pub figure_3_4: Vec<NormalForceCurves>,
    /// Figure 3.5: r/h fixed, μ = [`FIGURE_3_5_MU`].
    pub figure_3_5: Vec<NormalForceCurves>,
    /// Figures 3.7 and 3.8: the minimum applied force at each inclination.
    pub minimum_force: Vec<MinimumForceRow>,
    /// The circle BC traced by the unconstrained minimum, (3.3.20).
    pub circle: MinimumForceCircle,
    /// ϑ of point D, arctan(2r/h): zero applied force, rad.
    pub self_balancing_theta: f64,
}

/// The most inclinations [`statics_figures`] samples: far finer than a plot resolves, and
/// a bound on the work (a dozen curves of that many points).
pub const MAX_POINTS: usize = 100_000;

/// The inclinations ϑ_k = (π/2) k / `points`, k = 1 … `points` − 1, rad.
#[must_use]
pub fn sample_inclinations(points: usize) -> Vec<f64> {
    (1..points)
        .map(|k| FRAC_PI_2 * k as f64 / points as f64)
        .collect()
}

/// The support-force curves of §3.3 for r/h = `r_over_h` and μ = `mu`, at
/// [`sample_inclinations`]`(points)`: the normal forces (3.3.8) (corrected per ERRATA 9)
/// and (3.3.10) of Figures 3.3–3.5, and the minimum applied force (3.3.15)–(3.3.19) with
/// the unconstrained minimum on the circle (3.3.20) (ERRATA 11) of Figures 3.7 and 3.8.
///
/// # Errors
/// A negative or non-finite r/h or μ, fewer than 3 or more than [`MAX_POINTS`] points
/// ([`CylinderError::Input`]).
pub fn statics_figures(
    r_over_h: f64,
    mu: f64,
    points: usize,
) -> Result<StaticsFigures, CylinderError> {
    if !(3..=MAX_POINTS).contains(&points) {
        return Err(input::InputError::OutOfRange {
            name: "points".into(),
            range: "[3, 100000]",
            value: points as f64,
        }
        .into());
    }
    let p = SupportProblem::new(r_over_h, mu)?;
    let thetas = sample_inclinations(points);
    let family = |params: Vec<(f64, f64)>| {
        params
            .into_iter()
            .map(|(rho, m)| NormalForceCurves::new(rho, m, &thetas))
            .collect::<Result<Vec<_>, _>>()
    };
    let minimum_force = thetas
        .iter()
        .map(|&theta| {
            let (f3, f) = p.unconstrained_minimum(theta);
            MinimumForceRow {
                theta,
                unconstrained: [f3, f],
                admissible: p.satisfies_friction_criterion(theta) && f3 >= 0.0,
                minimum: p.minimum_force(theta).ok(),
            }
        })
        .collect();
    Ok(StaticsFigures {
        r_over_h,
        mu,
        figure_3_3: NormalForceCurves::new(r_over_h, mu, &thetas)?,
        figure_3_4: family(FIGURE_3_4_R_OVER_H.map(|rho| (rho, mu)).to_vec())?,
        figure_3_5: family(FIGURE_3_5_MU.map(|m| (r_over_h, m)).to_vec())?,
        minimum_force,
        circle: p.minimum_force_circle(),
        self_balancing_theta: p.self_balancing_inclination(),
    })
}

/// The (F3/mg, F/mg) points of Figure 3.7 and the curves of Figure 3.8.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct MinimumForceSeries {
    /// Unconstrained minima (3.3.15) that satisfy (3.3.17) and F3 ≥ 0.
    pub admissible: Vec<(f64, f64)>,
    /// Unconstrained minima that do not.
    pub inadmissible: Vec<(f64, f64)>,
    /// Minima on a bound, (3.3.18) or (3.3.19) (every case but the unconstrained one).
    pub on_bound: Vec<(f64, f64)>,
    /// (ϑ in degrees, F3/mg) of the minimum.
    pub f3_over_mg: Vec<(f64, f64)>,
    /// (ϑ in degrees, F/mg) of the minimum.
    pub f_over_mg: Vec<(f64, f64)>,
    /// (ϑ in degrees, ‖F_a‖/mg) of the minimum.
    pub norm_over_mg: Vec<(f64, f64)>,
}

impl StaticsFigures {
    /// The series of Figures 3.7 and 3.8, from [`StaticsFigures::minimum_force`].
    #[must_use]
    pub fn minimum_force_series(&self) -> MinimumForceSeries {
        let mut s = MinimumForceSeries::default();
        for row in &self.minimum_force {
            let [f3, f] = row.unconstrained;
            if row.admissible {
                s.admissible.push((f3, f));
            } else {
                s.inadmissible.push((f3, f));
            }
            if let Some(m) = row.minimum {
                if m.case != MinForceCase::Unconstrained {
                    s.on_bound.push((m.f3_over_mg, m.f_over_mg));
                }
                let d = row.theta.to_degrees();
                s.f3_over_mg.push((d, m.f3_over_mg));
                s.f_over_mg.push((d, m.f_over_mg));
                s.norm_over_mg.push((d, m.norm_over_mg));
            }
        }
        s
    }

    /// The friction bound F/mg = `sign` μ N/mg = `sign` μ(1 − F3/mg) for F3/mg in [0, 1]
    /// at 21 points: the edges of the admissible cone of Figure 3.7 (`sign` = ±1).
    #[must_use]
    pub fn friction_bound(&self, sign: f64) -> Vec<(f64, f64)> {
        (0..=20)
            .map(|k| f64::from(k) / 20.0)
            .map(|f3| (f3, sign * (self.mu * (1.0 - f3))))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_point_count_beyond_the_bound_is_refused() {
        let err = statics_figures(0.1, 0.2, 1_000_000_000_000).unwrap_err();
        assert!(err.to_string().contains("[3, 100000]"), "{err}");
    }

    #[test]
    fn figures_for_the_thesis_parameters() {
        let fig = statics_figures(0.1, 0.2, 91).unwrap();
        assert_eq!(fig.figure_3_3.rows.len(), 90);
        assert_eq!(fig.figure_3_4.len(), 4);
        assert_eq!(fig.figure_3_5.len(), 7);
        assert_eq!(fig.figure_3_5[2].mu, 0.2);
        assert_eq!(fig.minimum_force.len(), 90);
        // Every (+) curve of Figure 3.4 passes through the common point (3.3.11) at
        // ϑ = arctan 5 (not sampled): N/mg is between its neighbours' values there.
        let (theta, n) = SupportProblem::new(0.1, 0.2)
            .unwrap()
            .common_point()
            .unwrap();
        for curves in &fig.figure_3_4 {
            let k = curves.rows.iter().position(|r| r.theta > theta).unwrap();
            let (a, b) = (curves.rows[k - 1], curves.rows[k]);
            let (na, nb) = (a.n_over_mg_plus.unwrap(), b.n_over_mg_plus.unwrap());
            assert!(na.min(nb) <= n && n <= na.max(nb));
        }
        // The curves are clipped at N/mg = 1 and in degrees.
        let curve = fig.figure_3_3.curve(FrictionLimit::Minus);
        assert!(curve.iter().all(|&(d, n)| d < 90.0 && n <= 1.0));
        // Figure 3.8: zero force at D = arctan(2r/h); 3.7: points on the circle BC.
        assert!((fig.self_balancing_theta - 0.2f64.atan()).abs() < 1e-15);
        let series = fig.minimum_force_series();
        assert_eq!(series.norm_over_mg.len(), 90);
        for &(f3, f) in series.admissible.iter().chain(&series.inadmissible) {
            let [c3, c] = fig.circle.center;
            assert!(
                (((f3 - c3).powi(2) + (f - c).powi(2)).sqrt() - fig.circle.radius).abs() < 1e-12
            );
        }
        let cone = fig.friction_bound(-1.0);
        assert_eq!((cone[0], cone[20]), ((0.0, -0.2), (1.0, -0.0)));
    }

    #[test]
    fn csv_rows_have_one_cell_per_column() {
        let fig = statics_figures(0.1, 0.6, 19).unwrap();
        // 5°: no support on a smooth plane or at the (−) limit: empty cells.
        let first = fig.figure_3_3.rows[0];
        let cells = first.csv_cells();
        assert_eq!(cells.len(), NormalForceRow::CSV_HEADER.len());
        assert_eq!(cells[1], first.theta.to_degrees().to_string());
        assert_eq!(cells[2], first.n_over_mg_plus.unwrap().to_string());
        assert_eq!(&cells[3..], ["", ""]);
        let family = &fig.figure_3_5[1];
        let rows = family.csv_rows();
        assert_eq!(rows.len(), family.rows.len());
        assert!(rows
            .iter()
            .all(|r| r.len() == NormalForceCurves::CSV_HEADER.len()));
        assert_eq!(rows[0][..2], ["0.1", "0.1"]);
        assert_eq!(rows[0][3..], family.rows[0].csv_cells()[2..]);
        for row in &fig.minimum_force {
            let cells = row.csv_cells();
            assert_eq!(cells.len(), MinimumForceRow::CSV_HEADER.len());
            assert_eq!(cells[4], if row.admissible { "1" } else { "0" });
            match row.minimum {
                Some(m) => assert_eq!(cells[8], m.case.name()),
                None => assert_eq!(&cells[5..], ["", "", "", "none"]),
            }
        }
    }

    #[test]
    fn refuses_bad_input() {
        assert_eq!(
            statics_figures(0.1, 0.2, 2).unwrap_err().to_string(),
            "points must lie in [3, 100000], got 2"
        );
        assert_eq!(
            statics_figures(-0.1, 0.2, 10).unwrap_err().to_string(),
            "r/h must not be negative, got -0.1"
        );
    }
}
