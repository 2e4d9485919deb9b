//! Steady support at one inclination (§3.3, corrected per ERRATA 9–11): what
//! `rollstack cylinder support` prints.

use crate::error::CylinderError;
use crate::statics::{FrictionLimit, MinimumForce, SteadyBalance, SupportProblem};
use input::positive;
use serde::{Deserialize, Serialize};
use std::f64::consts::FRAC_PI_2;
use std::fmt;

/// The heading ψ at which the closed forms are checked against the balance laws: any
/// value does, the steady support does not depend on it.
const CHECK_HEADING: f64 = 0.7;

/// The smallest applied force, (3.3.15)–(3.3.19), with its case named.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MinimumForceReport {
    /// F3/mg.
    pub f3_over_mg: f64,
    /// F/mg (horizontal, along e′2).
    pub f_over_mg: f64,
    /// ‖F_a‖/mg.
    pub norm_over_mg: f64,
    /// `unconstrained` (3.3.15), `friction_positive` / `friction_negative` (3.3.18),
    /// `no_vertical_force` (3.3.19) or `flat_contact` ([`crate::statics::MinForceCase::name`]).
    pub case: String,
    /// The equation of the case ([`crate::statics::MinForceCase::equation`]).
    pub equation: String,
}

impl From<MinimumForce> for MinimumForceReport {
    fn from(m: MinimumForce) -> Self {
        Self {
            f3_over_mg: m.f3_over_mg,
            f_over_mg: m.f_over_mg,
            norm_over_mg: m.norm_over_mg,
            case: m.case.name().into(),
            equation: m.case.equation().into(),
        }
    }
}

/// The steady support of an inclined rolling cylinder at one inclination. Forces are
/// divided by mg, angles in radians. The field names are the keys of
/// `rollstack cylinder support --json` (docs/cli.md), those of docs/cli.md first.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SupportReport {
    /// N/mg at F_f = +μN e′2, (3.3.8)₊ corrected per ERRATA 9; `None` when no positive N.
    pub n_over_mg_plus: Option<f64>,
    /// N/mg at F_f = −μN e′2, (3.3.8)₋; `None` when no positive N.
    pub n_over_mg_minus: Option<f64>,
    /// N/mg on a smooth plane, (3.3.10); `None` when no positive N.
    pub n_over_mg_smooth: Option<f64>,
    /// Inclinations at which a steady support with 0 < N < mg exists: the (+) range of
    /// (3.3.9), corrected per ERRATA 10, rad ([π/2, π/2] when empty).
    pub theta_range: [f64; 2],
    /// The minimum applied force, (3.3.15)–(3.3.19); `None` when no support exists.
    pub min_force: Option<MinimumForceReport>,
    /// The (−) range of (3.3.9), `None` when empty, rad.
    pub theta_range_minus: Option<[f64; 2]>,
    /// The range of (3.3.10), rad.
    pub theta_range_smooth: Option<[f64; 2]>,
    /// Admissible N/mg at this ϑ: [N₊, min(N₋, 1)], `None` when none.
    pub admissible_n_over_mg: Option<[f64; 2]>,
    /// The common point (ϑ, N/mg) of all (+) curves, (3.3.11); `None` for μ = 0.
    pub common_point: Option<[f64; 2]>,
    /// ϑ of point D, arctan(2r/h): zero applied force, rad.
    pub self_balancing_theta: f64,
    /// Largest difference between the closed forms and the balance laws (3.3.3) solved
    /// numerically (QR) at this ϑ.
    pub balance_law_error: f64,
    /// The same forces in newtons for a given mass and gravity
    /// ([`SupportReport::with_weight`]); absent (not serialized) otherwise.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub forces_newton: Option<SupportForces>,
}

/// The support forces of a [`SupportReport`] in newtons, for a cylinder of mass m under
/// gravity g: each value over mg times mg. The names say the directions: N pushes up
/// (along E3), F3 is the applied force's vertical component (positive up, along E3) and F
/// its horizontal one (along e′2, horizontal and perpendicular to e′1; the axis
/// e3 = −sin ϑ e′2 + cos ϑ E3 leans towards −e′2).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SupportForces {
    /// Mass m, kg.
    pub mass: f64,
    /// Gravity g, m/s².
    pub gravity: f64,
    /// The weight mg, N (vertical, down).
    pub weight: f64,
    /// Normal force N (vertical, up) at F_f = +μN e′2, N; `None` when no positive N.
    pub n_plus: Option<f64>,
    /// Normal force N (vertical, up) at F_f = −μN e′2, N; `None` when no positive N.
    pub n_minus: Option<f64>,
    /// Normal force N (vertical, up) on a smooth plane, N; `None` when no positive N.
    pub n_smooth: Option<f64>,
    /// The minimum applied force's vertical component F3 (positive up), N; `None` when no
    /// support exists.
    pub f3_up: Option<f64>,
    /// The minimum applied force's horizontal component F along e′2, N; `None` when no
    /// support exists.
    pub f_along_e2: Option<f64>,
    /// The minimum applied force's magnitude ‖F_a‖, N; `None` when no support exists.
    pub f_norm: Option<f64>,
}

impl SupportReport {
    /// This report with its forces also in newtons ([`SupportReport::forces_newton`]) for
    /// a cylinder of mass `mass` (kg) under gravity `gravity` (m/s²).
    ///
    /// # Errors
    /// A mass or gravity that is not positive ([`CylinderError::Input`]).
    pub fn with_weight(mut self, mass: f64, gravity: f64) -> Result<Self, CylinderError> {
        let mg = positive("mass", mass)? * positive("gravity", gravity)?;
        let newton = |v: Option<f64>| v.map(|v| v * mg);
        let min = self.min_force.as_ref();
        self.forces_newton = Some(SupportForces {
            mass,
            gravity,
            weight: mg,
            n_plus: newton(self.n_over_mg_plus),
            n_minus: newton(self.n_over_mg_minus),
            n_smooth: newton(self.n_over_mg_smooth),
            f3_up: newton(min.map(|m| m.f3_over_mg)),
            f_along_e2: newton(min.map(|m| m.f_over_mg)),
            f_norm: newton(min.map(|m| m.norm_over_mg)),
        });
        Ok(self)
    }

    /// This report with the inputs its text shows: the inclination ϑ (rad), the aspect
    /// ratio r/h and the friction coefficient μ it was computed for ([`SupportSummary`]).
    #[must_use]
    pub fn summary(&self, theta: f64, r_over_h: f64, mu: f64) -> SupportSummary<'_> {
        SupportSummary {
            theta,
            r_over_h,
            mu,
            report: self,
        }
    }
}

/// The readable text of `rollstack cylinder support` (`Display`): a steady support with
/// the inputs it was computed for.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SupportSummary<'a> {
    /// Inclination ϑ of the axis to the vertical, rad.
    pub theta: f64,
    /// Aspect ratio r/h.
    pub r_over_h: f64,
    /// Friction coefficient μ.
    pub mu: f64,
    /// The support at ϑ ([`support_report`]).
    pub report: &'a SupportReport,
}

impl fmt::Display for SupportSummary<'_> {
    /// ϑ (degrees), r/h and μ; N/mg at the two friction limits (3.3.8)± and on a smooth
    /// plane (3.3.10) (`none` without a positive N); the (+) range of (3.3.9) (degrees);
    /// the minimum applied force (3.3.15)–(3.3.19) over mg, each component named by its
    /// direction; the disagreement of the closed forms with the balance laws (3.3.3); and,
    /// with [`SupportReport::with_weight`], the forces in newtons. Lines are separated by
    /// `\n`, with none after the last.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let rep = self.report;
        let show = |v: Option<f64>| v.map_or_else(|| "none".to_owned(), |v| format!("{v:.6}"));
        writeln!(
            f,
            "Steady support at ϑ = {:.4}° (r/h = {}, μ = {})",
            self.theta.to_degrees(),
            self.r_over_h,
            self.mu
        )?;
        writeln!(
            f,
            "  N/mg  F_f = +μN e′2 (3.3.8)+: {}",
            show(rep.n_over_mg_plus)
        )?;
        writeln!(
            f,
            "  N/mg  smooth plane (3.3.10):  {}",
            show(rep.n_over_mg_smooth)
        )?;
        writeln!(
            f,
            "  N/mg  F_f = −μN e′2 (3.3.8)−: {}",
            show(rep.n_over_mg_minus)
        )?;
        writeln!(
            f,
            "  feasible inclinations (3.3.9)+: ({:.4}°, {:.4}°)",
            rep.theta_range[0].to_degrees(),
            rep.theta_range[1].to_degrees()
        )?;
        match &rep.min_force {
            Some(m) => writeln!(
                f,
                "  minimum force {}: F3/mg = {:.6} (vertical, up), F/mg = {:.6} (horizontal, along e′2), ‖F_a‖/mg = {:.6}",
                m.equation, m.f3_over_mg, m.f_over_mg, m.norm_over_mg
            )?,
            None => writeln!(f, "  no admissible applied force at this inclination")?,
        }
        write!(
            f,
            "  closed forms vs balance laws (3.3.3): {:.1e}",
            rep.balance_law_error
        )?;
        if let Some(n) = &rep.forces_newton {
            let show =
                |v: Option<f64>| v.map_or_else(|| "none".to_owned(), |v| format!("{v:.6} N"));
            write!(
                f,
                "\n  in newtons (m = {} kg, g = {} m/s², weight mg = {:.6} N, down): N (vertical, up) {} (+), {} (smooth), {} (−)",
                n.mass,
                n.gravity,
                n.weight,
                show(n.n_plus),
                show(n.n_smooth),
                show(n.n_minus)
            )?;
            if rep.min_force.is_some() {
                write!(
                    f,
                    "\n  minimum force in newtons: F3 = {} (vertical, up), F = {} (horizontal, along e′2), ‖F_a‖ = {}",
                    show(n.f3_up),
                    show(n.f_along_e2),
                    show(n.f_norm)
                )?;
            }
        }
        Ok(())
    }
}

fn pair(r: Option<(f64, f64)>) -> Option<[f64; 2]> {
    r.map(|(a, b)| [a, b])
}

/// The steady support at inclination `theta` of a cylinder of aspect ratio `r_over_h`
/// on a plane of friction coefficient `mu`: the limiting normal forces (3.3.8)
/// (corrected per ERRATA 9) and (3.3.10), the feasible inclinations (3.3.9) (ERRATA 10),
/// the common point (3.3.11), point D, and the minimum applied force (3.3.15)–(3.3.19)
/// (its circle (3.3.20), ERRATA 11). Every closed form is checked against the balance
/// laws (3.3.3) solved numerically ([`SteadyBalance`]); the largest disagreement is
/// [`SupportReport::balance_law_error`].
///
/// # Errors
/// ϑ outside (0, π/2) ([`CylinderError::NotPointContact`]), a negative or non-finite
/// r/h or μ ([`CylinderError::Input`]).
pub fn support_report(theta: f64, r_over_h: f64, mu: f64) -> Result<SupportReport, CylinderError> {
    let p = SupportProblem::new(r_over_h, mu)?;
    let plus = p.normal_force(theta, FrictionLimit::Plus)?;
    let minus = p.normal_force(theta, FrictionLimit::Minus)?;
    let smooth = p.normal_force(theta, FrictionLimit::Smooth)?;
    let min_force = p.minimum_force(theta).ok();
    let balance = SteadyBalance::new(&p, theta, CHECK_HEADING)?;
    let mut balance_law_error: f64 = 0.0;
    for (limit, closed) in [
        (FrictionLimit::Plus, plus),
        (FrictionLimit::Minus, minus),
        (FrictionLimit::Smooth, smooth),
    ] {
        if let Some(n) = closed {
            balance_law_error =
                balance_law_error.max((balance.limiting_normal_force(limit) - n).abs());
        }
    }
    if let (Some(m), Ok((f3, f))) = (min_force, balance.minimum_force()) {
        balance_law_error = balance_law_error
            .max((m.f3_over_mg - f3).abs())
            .max((m.f_over_mg - f).abs());
    }
    let upper = minus.map_or(1.0, |n| n.min(1.0));
    let admissible = plus.filter(|&n| n <= upper).map(|n| [n, upper]);
    let (lo, hi) = p
        .inclination_range(FrictionLimit::Plus)
        .unwrap_or((FRAC_PI_2, FRAC_PI_2));
    Ok(SupportReport {
        n_over_mg_plus: plus,
        n_over_mg_minus: minus,
        n_over_mg_smooth: smooth,
        theta_range: [lo, hi],
        min_force: min_force.map(MinimumForceReport::from),
        theta_range_minus: pair(p.inclination_range(FrictionLimit::Minus)),
        theta_range_smooth: pair(p.inclination_range(FrictionLimit::Smooth)),
        admissible_n_over_mg: admissible,
        common_point: pair(p.common_point()),
        self_balancing_theta: p.self_balancing_inclination(),
        balance_law_error,
        forces_newton: None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use input::InputError;

    #[test]
    fn thirty_degrees_matches_the_corrected_closed_forms() {
        let rep = support_report(30f64.to_radians(), 0.1, 0.2).unwrap();
        // (3.3.8) corrected (ERRATA 9): ½ sin ϑ / (sin ϑ − ρ cos ϑ ± μ(ρ sin ϑ + cos ϑ)).
        let (s, c) = (0.5, 30f64.to_radians().cos());
        let n = |sign: f64| 0.5 * s / (s - 0.1 * c + sign * 0.2 * (0.1 * s + c));
        assert!((rep.n_over_mg_plus.unwrap() - n(1.0)).abs() < 1e-14);
        assert!((rep.n_over_mg_minus.unwrap() - n(-1.0)).abs() < 1e-14);
        assert!((rep.n_over_mg_smooth.unwrap() - n(0.0)).abs() < 1e-14);
        assert!(rep.balance_law_error < 1e-12);
        // ERRATA 10: the (+) range starts at max(0, …) = 0 here.
        assert_eq!(rep.theta_range, [0.0, FRAC_PI_2]);
        // (3.3.11) and point D.
        assert!((rep.common_point.unwrap()[1] - 1.0 / 2.08).abs() < 1e-15);
        assert!((rep.self_balancing_theta - 0.2f64.atan()).abs() < 1e-15);
        let m = rep.min_force.unwrap();
        assert_eq!(
            (m.case.as_str(), m.equation.as_str()),
            ("unconstrained", "(3.3.15)")
        );
        let admissible = rep.admissible_n_over_mg.unwrap();
        assert!(admissible[0] <= admissible[1] && admissible[1] <= 1.0);
    }

    #[test]
    fn the_text_shows_the_forces() {
        let theta = 30f64.to_radians();
        let rep = support_report(theta, 0.1, 0.2).unwrap();
        let text = rep.summary(theta, 0.1, 0.2).to_string();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), 7);
        assert_eq!(
            lines[0],
            "Steady support at ϑ = 30.0000° (r/h = 0.1, μ = 0.2)"
        );
        let plus = format!("{:.6}", rep.n_over_mg_plus.unwrap());
        assert_eq!(lines[1], format!("  N/mg  F_f = +μN e′2 (3.3.8)+: {plus}"));
        assert_eq!(
            lines[4],
            "  feasible inclinations (3.3.9)+: (0.0000°, 90.0000°)"
        );
        assert!(lines[5].starts_with("  minimum force (3.3.15): F3/mg = "));
        // No smooth or (−) support at 5° with μ = 0.6.
        let theta = 5f64.to_radians();
        let rep = support_report(theta, 0.1, 0.6).unwrap();
        let text = rep.summary(theta, 0.1, 0.6).to_string();
        assert!(text.contains("  N/mg  smooth plane (3.3.10):  none\n"));
        assert!(text.ends_with(&format!("{:.1e}", rep.balance_law_error)));
    }

    #[test]
    fn forces_in_newtons_name_their_directions() {
        let theta = 30f64.to_radians();
        let rep = support_report(theta, 0.1, 0.2).unwrap();
        let json = serde_json::to_value(&rep).unwrap();
        assert!(json.get("forces_newton").is_none(), "absent without a mass");
        let heavy = rep.clone().with_weight(2.0, 9.81).unwrap();
        let n = heavy.forces_newton.as_ref().unwrap();
        assert!((n.weight - 19.62).abs() < 1e-12);
        let m = rep.min_force.as_ref().unwrap();
        assert!((n.f3_up.unwrap() - 19.62 * m.f3_over_mg).abs() < 1e-12);
        assert!((n.n_plus.unwrap() - 19.62 * rep.n_over_mg_plus.unwrap()).abs() < 1e-12);
        let text = heavy.summary(theta, 0.1, 0.2).to_string();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), 9);
        assert!(
            lines[5].contains(" (vertical, up), F/mg = "),
            "{}",
            lines[5]
        );
        assert!(lines[7].starts_with(
            "  in newtons (m = 2 kg, g = 9.81 m/s², weight mg = 19.620000 N, down): N (vertical, up) "
        ));
        assert!(lines[8].starts_with("  minimum force in newtons: F3 = "));
        assert!(lines[8].contains(" N (vertical, up), F = "));
        let keys: Vec<String> = serde_json::to_value(&heavy).unwrap()["forces_newton"]
            .as_object()
            .unwrap()
            .keys()
            .cloned()
            .collect();
        assert_eq!(keys.len(), 9);
        assert!(rep.clone().with_weight(0.0, 9.81).is_err());
        assert!(rep.with_weight(1.0, f64::NAN).is_err());
    }

    #[test]
    fn json_keys_keep_their_order() {
        let rep = support_report(0.5, 0.1, 0.2).unwrap();
        let text = serde_json::to_string(&rep).unwrap();
        let keys = [
            "n_over_mg_plus",
            "n_over_mg_minus",
            "n_over_mg_smooth",
            "theta_range",
            "min_force",
            "theta_range_minus",
            "theta_range_smooth",
            "admissible_n_over_mg",
            "common_point",
            "self_balancing_theta",
            "balance_law_error",
        ];
        let at: Vec<usize> = keys
            .iter()
            .map(|k| text.find(&format!("\"{k}\":")).unwrap())
            .collect();
        assert!(at.windows(2).all(|w| w[0] < w[1]), "{text}");
    }

    #[test]
    fn refuses_bad_input() {
        assert!(matches!(
            support_report(0.0, 0.1, 0.2),
            Err(CylinderError::NotPointContact(_))
        ));
        assert_eq!(
            support_report(0.5, 0.1, -0.1).unwrap_err(),
            CylinderError::Input(InputError::Negative {
                name: "μ".into(),
                value: -0.1
            })
        );
        assert_eq!(
            support_report(0.5, f64::NAN, 0.2).unwrap_err().to_string(),
            "r/h is not finite"
        );
    }
}
