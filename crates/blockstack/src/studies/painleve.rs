//! Painlevé's paradoxes for one block on a rough plane (App. I, ERRATA 18): the report
//! of `rollstack blocks painleve`.

use crate::error::BlockError;
use crate::painleve::{
    admissible_range, least_friction, least_friction_for_sign, line_contact_solutions,
};
use crate::scenarios::PainleveCorner;
use crate::simulation::{stepper_options, RunOptions};
use crate::stepping::CornerStepping;
use crate::system::StackSystem;
use nsga::Stepper;

/// The least μ_d for one slip direction.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct SignedLeast {
    /// Least μ_d (an infimum when reached at an end of the open range (I.1.3)).
    pub mu: f64,
    /// Angle (rad) where it is reached.
    pub theta: f64,
}

/// Normal forces n = N/(mg) of one solution of the line-contact LCP (I.2.10).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct LineContactForces {
    /// n_R at the right corner.
    pub n_right: f64,
    /// n_L at the left corner.
    pub n_left: f64,
}

/// The line-contact LCP (I.2.5) at ϑ = ϑ' = 0 for both slip directions.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct LineContactReport {
    /// μ_d.
    pub mu: f64,
    /// Solutions when sliding to the right, sgn ẋ = +1.
    pub sliding_right: Vec<LineContactForces>,
    /// Solutions when sliding to the left, sgn ẋ = −1.
    pub sliding_left: Vec<LineContactForces>,
}

/// The Painlevé analysis of one block (docs/cli.md: `mu_min`, `theta_min`,
/// `theta_max` first).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct PainleveReport {
    /// Least μ_d for which b ≤ 0 is possible (4/3, ERRATA 18).
    pub mu_min: f64,
    /// ϑ_min = −arctan(h/w) (rad), (I.1.3).
    pub theta_min: f64,
    /// ϑ_max = arctan(w/h) (rad), (I.1.3).
    pub theta_max: f64,
    /// Angle (rad) of the least μ_d.
    pub theta_at_mu_min: f64,
    /// sgn(ẋ_P) of the least μ_d.
    pub slip_sign_at_mu_min: f64,
    /// Least μ_d per slip direction within the admissible range, sgn ẋ_P = +1.
    pub mu_min_slip_positive: SignedLeast,
    /// Least μ_d per slip direction within the admissible range, sgn ẋ_P = −1.
    pub mu_min_slip_negative: SignedLeast,
    /// The line-contact solutions (I.2.10).
    pub line_contact: LineContactReport,
}

impl PainleveReport {
    /// The report with the aspect ratio w/h it was computed for, to print.
    #[must_use]
    pub fn summary(&self, aspect: f64) -> PainleveSummary<'_> {
        PainleveSummary {
            report: self,
            aspect,
        }
    }
}

/// A [`PainleveReport`] with its aspect ratio: the text `rollstack blocks painleve`
/// prints (the admissible angles (I.1.3), the least μ_d, the line-contact forces
/// (I.2.10); lines, no trailing newline).
#[derive(Debug, Clone, Copy)]
pub struct PainleveSummary<'a> {
    /// The report.
    pub report: &'a PainleveReport,
    /// w/h.
    pub aspect: f64,
}

impl std::fmt::Display for PainleveSummary<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let r = self.report;
        writeln!(
            f,
            "w/h = {}: admissible angles ({:.3}°, {:.3}°) (I.1.3)",
            self.aspect,
            r.theta_min.to_degrees(),
            r.theta_max.to_degrees()
        )?;
        write!(
            f,
            "least friction coefficient for a paradox: μ_d = {:.6} at ϑ = {:.3}° (sgn ẋ_P = {:+})",
            r.mu_min,
            r.theta_at_mu_min.to_degrees(),
            r.slip_sign_at_mu_min
        )?;
        let lc = &r.line_contact;
        for (name, sols) in [("right", &lc.sliding_right), ("left", &lc.sliding_left)] {
            for s in sols {
                write!(
                    f,
                    "\nline contact, μ_d = {}, sliding {name}: n_R = {:.6}, n_L = {:.6} (I.2.10)",
                    lc.mu, s.n_right, s.n_left
                )?;
            }
        }
        Ok(())
    }
}

/// The Painlevé analysis of App. I for a block of aspect w/h: the admissible angles
/// (I.1.3), the least friction coefficient for which b of (I.1.8) (ERRATA 18) can vanish,
/// per slip direction, and the line-contact LCP (I.2.10) solved for μ_d = `mu`.
///
/// # Errors
/// A bad aspect ratio or μ_d.
pub fn painleve_report(aspect: f64, mu: f64) -> Result<PainleveReport, BlockError> {
    let (theta_min, theta_max) = admissible_range(aspect)?;
    let least = least_friction(aspect)?;
    let plus = least_friction_for_sign(aspect, 1.0)?;
    let minus = least_friction_for_sign(aspect, -1.0)?;
    // Line contact: only h/w matters (w = aspect, h = 1).
    let lcp = |s: f64| -> Result<Vec<LineContactForces>, BlockError> {
        Ok(line_contact_solutions(aspect, 1.0, mu, s)?
            .into_iter()
            .map(|c| LineContactForces {
                n_right: c.n_right,
                n_left: c.n_left,
            })
            .collect())
    };
    Ok(PainleveReport {
        mu_min: least.mu,
        theta_min,
        theta_max,
        theta_at_mu_min: least.theta,
        slip_sign_at_mu_min: least.slip_sign,
        mu_min_slip_positive: SignedLeast {
            mu: plus.mu,
            theta: plus.theta,
        },
        mu_min_slip_negative: SignedLeast {
            mu: minus.mu,
            theta: minus.theta,
        },
        line_contact: LineContactReport {
            mu,
            sliding_right: lcp(1.0)?,
            sliding_left: lcp(-1.0)?,
        },
    })
}

/// What a solution of the first step of a [`PainleveCorner`] does with its corner
/// (App. I's indeterminacy, from the corner's contact state at the step's end).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, serde::Serialize)]
pub enum CornerMotion {
    /// Closed and sliding, pressed with n = −A/B (the sliding-contact solution).
    SlidingContact,
    /// Closed and sticking: the slip stopped within the step by a tangential impulse.
    Jam,
    /// Open: n = 0.
    LiftOff,
}

impl CornerMotion {
    /// The motion in the sets `sets` a step of the one-block scene was solved with: open
    /// when no normal contact is closed, else a jam when a friction law sticks (on
    /// velocity level at least), else sliding. The touching corner may be an interface
    /// corner or a corner contact (beyond |θ| = arctan(w/h)), so every contact counts.
    #[must_use]
    pub fn of(sets: &nsga::IndexSets) -> Self {
        if !sets.a.iter().any(|&a| a) {
            Self::LiftOff
        } else if sets.d.iter().any(|&d| d) {
            Self::Jam
        } else {
            Self::SlidingContact
        }
    }

    /// `sliding contact`, `jam` or `lift-off`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::SlidingContact => "sliding contact",
            Self::Jam => "jam",
            Self::LiftOff => "lift-off",
        }
    }
}

/// One solution of the first step of a [`PainleveCorner`].
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct CornerSolution {
    /// What the corner does.
    pub motion: CornerMotion,
    /// The normal force at the step's end, n = λ_N/(mg) (m = g = 1 in the scene).
    pub n: f64,
    /// The normal impulse of the step, P_N/(mg Δt).
    pub impulse: f64,
}

/// The distinct solutions of the first step of `case`, found by the flip probe (the
/// contact states of the touching corner enumerated, [`nsga::PolicyOptions::probe_flips`]),
/// converged solution first.
///
/// # Errors
/// A bad case, or a step that fails.
pub fn corner_solutions(case: &PainleveCorner) -> Result<Vec<CornerSolution>, BlockError> {
    let scene = case.scene()?;
    let run = RunOptions {
        probe_flips: true,
        ..RunOptions::default()
    };
    let options = stepper_options(&scene, &run)?;
    let dt = options.dt;
    let (q0, u0) = (scene.initial_coordinates(), scene.initial_velocities());
    let mut system = StackSystem::new(scene);
    // The corner contacts (a corner beyond the block's bottom face touching the table).
    CornerStepping::default().start(&mut system, &q0, &u0, dt);
    let mut stepper = Stepper::new(system, 0.0, &q0, &u0, options)
        .map_err(|e| BlockError::Scene(format!("the Painlevé corner cannot start: {e}")))?;
    let stats = stepper
        .step()
        .map_err(|e| BlockError::Scene(format!("the Painlevé corner's first step failed: {e}")))?
        .clone();
    let solution = |sets: &nsga::IndexSets, st: &nsga::State| CornerSolution {
        motion: CornerMotion::of(sets),
        n: st.lambda_n.iter().sum(),
        impulse: st.p_n.iter().sum::<f64>() / dt,
    };
    Ok(match &stats.branch {
        Some(point) => point
            .candidates
            .iter()
            .map(|(sets, st)| solution(sets, st))
            .collect(),
        None => vec![solution(&stats.sets, stepper.state())],
    })
}

/// One case of the corner scan ([`corner_scan`]) and its first step's solutions.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct CornerCase {
    /// The case.
    #[serde(skip)]
    pub case: PainleveCorner,
    /// B of ÿ_P = A + B n ([`PainleveCorner::response`]).
    pub b: f64,
    /// −A/B: App. I's sliding-contact force where B < 0 and A > 0.
    pub sliding_force: f64,
    /// Whether both bottom corners touch ([`PainleveCorner::line_contact`]): App. I.2,
    /// not the single point of App. I.1.
    pub line_contact: bool,
    /// The step Δt the solutions are of ([`SCAN_STEPS`]).
    pub dt: f64,
    /// The solutions found, converged solution first.
    pub solutions: Vec<CornerSolution>,
}

impl CornerCase {
    /// The columns of `painleve_corner_scan.csv`.
    pub const CSV_HEADER: [&'static str; 11] = [
        "theta_rad",
        "slip",
        "spin_sign",
        "b",
        "minus_a_over_b",
        "solutions",
        "sliding_contact_force",
        "jam_force",
        "lift_off",
        "contact",
        "dt",
    ];

    /// The solution of `motion`, if found.
    #[must_use]
    pub fn find(&self, motion: CornerMotion) -> Option<&CornerSolution> {
        self.solutions.iter().find(|s| s.motion == motion)
    }

    /// The case's cells under [`Self::CSV_HEADER`]: the forces are P_N/(mg Δt), empty
    /// where that solution was not found; `lift_off` is 0 or 1.
    #[must_use]
    pub fn csv_cells(&self) -> Vec<String> {
        let force = |m| {
            self.find(m)
                .map_or(String::new(), |s| s.impulse.to_string())
        };
        vec![
            self.case.theta.to_string(),
            self.case.slip.to_string(),
            self.case.spin_sign.to_string(),
            self.b.to_string(),
            self.sliding_force.to_string(),
            self.solutions.len().to_string(),
            force(CornerMotion::SlidingContact),
            force(CornerMotion::Jam),
            u8::from(self.find(CornerMotion::LiftOff).is_some()).to_string(),
            if self.line_contact { "line" } else { "point" }.to_string(),
            self.dt.to_string(),
        ]
    }

    /// Whether App. I.1's three solutions (sliding contact, jam, lift-off) were all found.
    #[must_use]
    pub fn all_three(&self) -> bool {
        [
            CornerMotion::SlidingContact,
            CornerMotion::Jam,
            CornerMotion::LiftOff,
        ]
        .iter()
        .all(|&m| self.find(m).is_some())
    }
}

/// The steps Δt of the corner scan, coarsest first. A single-point case in Painlevé's
/// region (B < 0, A > 0) whose first step lacks one of App. I's three solutions is solved
/// again at the next: the discrete step's B differs from App. I's by O(Δt), so near b = 0
/// a case can lie in the region for one and outside it for the other. At μ = 1.4,
/// θ = ±0.1 (B = −0.017, −A/B = 30) the step at 10⁻³ has lift-off and jam only; at 10⁻⁴
/// the sliding contact appears with P_N/(mg Δt) = 31.3, at 10⁻⁵ 30.2, at 10⁻⁶ 30.04.
pub const SCAN_STEPS: [f64; 3] = [1e-3, 1e-4, 1e-5];

/// The corner scan at friction `mu`: θ from −1.5 to 1.5 rad by 0.05, the corner sliding
/// at ±0.5, spin of either sign, A = 0.5 g ([`PainleveCorner::default`]); each case's
/// first step solved and probed ([`corner_solutions`]) at the first Δt of
/// [`SCAN_STEPS`] that finds App. I's three solutions where it should.
///
/// # Errors
/// A bad μ, or a step that fails.
pub fn corner_scan(mu: f64) -> Result<Vec<CornerCase>, BlockError> {
    input::non_negative("mu", mu)?;
    let mut out = Vec::new();
    for i in -30..=30 {
        for slip in [-0.5, 0.5] {
            for spin_sign in [-1.0, 1.0] {
                let case = PainleveCorner {
                    theta: f64::from(i) * 0.05,
                    mu,
                    slip,
                    spin_sign,
                    ..PainleveCorner::default()
                };
                out.push(scan_case(case)?);
            }
        }
    }
    Ok(out)
}

/// One case of [`corner_scan`], refined in Δt ([`SCAN_STEPS`]) while it is a single-point
/// case of Painlevé's region without its three solutions.
fn scan_case(case: PainleveCorner) -> Result<CornerCase, BlockError> {
    let b = case.response();
    let line_contact = case.line_contact();
    let paradox = !line_contact && b < 0.0 && case.free_acceleration > 0.0;
    let solve = |dt: f64| -> Result<CornerCase, BlockError> {
        let at = PainleveCorner { dt, ..case };
        Ok(CornerCase {
            case: at,
            b,
            sliding_force: -case.free_acceleration / b,
            line_contact,
            dt,
            solutions: corner_solutions(&at)?,
        })
    };
    let mut found = solve(SCAN_STEPS[0])?;
    for &dt in &SCAN_STEPS[1..] {
        if !paradox || found.all_three() {
            break;
        }
        found = solve(dt)?;
    }
    Ok(found)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_summary_names_the_least_friction_and_each_line_contact_solution() {
        let report = painleve_report(0.5, 0.2).unwrap();
        let text = report.summary(0.5).to_string();
        assert!(text.starts_with("w/h = 0.5: admissible angles (-63.435°, 26.565°)"));
        assert!(text.contains("μ_d = 1.333333"), "{text}");
        let solutions =
            report.line_contact.sliding_right.len() + report.line_contact.sliding_left.len();
        assert_eq!(text.matches("line contact").count(), solutions);
        assert!(!text.ends_with('\n'));
    }

    #[test]
    fn the_least_friction_is_four_thirds_at_half_aspect() {
        let r = painleve_report(0.5, 0.2).unwrap();
        assert!((r.mu_min - 4.0 / 3.0).abs() < 1e-6, "{}", r.mu_min);
        assert!((r.theta_max - 0.5_f64.atan()).abs() < 1e-15);
        assert!((r.theta_min + 2.0_f64.atan()).abs() < 1e-15);
        assert!((r.theta_at_mu_min.abs() - 0.5_f64.atan()).abs() < 1e-4);
        // Line contact at rest: both corners carry weight and together carry mg.
        let lc = r.line_contact.sliding_right[0];
        assert!(lc.n_right > 0.0 && lc.n_left > 0.0);
        assert!((lc.n_right + lc.n_left - 1.0).abs() < 1e-12);
        assert!(painleve_report(-1.0, 0.2).is_err());
        assert!(painleve_report(0.5, -0.2).is_err());
    }
}
