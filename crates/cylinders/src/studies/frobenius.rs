//! The Frobenius integrability test of the rolling constraints of one cylinder (App. D)
//! and of a touching pair (§3.5, App. F; rank 9, ERRATA 13) at one configuration: what
//! `rollstack cylinder frobenius` prints.

use crate::error::CylinderError;
use crate::frobenius::{bilinear, frobenius_test, skew_matrices, FrobeniusReport};
use crate::kinematics::{check_point_contact, Cylinder};
use crate::pair::{CylinderPair, PairConstraints, PairSystem, SingleCylinder};
use nalgebra::DVector;
use serde::{Deserialize, Serialize};
use std::fmt;
use std::time::Instant;

/// Which constraint system is tested.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ConstraintSystem {
    /// One cylinder: 6 coordinates, v_P = 0 (3 constraints), App. D.
    Single,
    /// The pair: 12 coordinates, Π1..Π7 of (3.5.13).
    Pair7,
    /// The pair: 12 coordinates, the nine rolling constraints of App. F.
    Pair9,
}

impl ConstraintSystem {
    /// The system's name in text and JSON, as the command line spells it: `single`,
    /// `pair7` or `pair9`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Single => "single",
            Self::Pair7 => "pair7",
            Self::Pair9 => "pair9",
        }
    }
}

/// Where the pair is evaluated.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PairConfiguration {
    /// The touching configuration shifted by fixed irregular offsets (not touching),
    /// [`CylinderPair::generic_configuration`].
    Generic,
    /// Touching: both on the plane, leaning towards each other, axes r1 + r2 apart,
    /// [`CylinderPair::touching_configuration`].
    Touching,
}

/// One Frobenius test: the system, where it is evaluated, and the cylinder(s).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct FrobeniusCase {
    /// Which constraint system.
    pub system: ConstraintSystem,
    /// Configuration of the pair (ignored for [`ConstraintSystem::Single`]).
    pub configuration: PairConfiguration,
    /// The cylinder (both cylinders of the pair are this one).
    pub cylinder: Cylinder,
    /// Inclination ϑ of the cylinder(s), in (0, π/2), rad.
    pub theta: f64,
    /// Heading: the precession ψ of the single cylinder or of cylinder I, rad.
    pub heading: f64,
    /// Where the cylinders touch along their axes, from the centre (m* = n*), in
    /// (−h/2, h/2), same unit as the cylinder; `None`: [`DEFAULT_CONTACT_AT`]. Pair
    /// only: the single cylinder refuses one ([`CylinderError::ContactOfSingle`]).
    pub contact_at: Option<f64>,
}

/// Where the pair touches when the case does not say: 0.3 from the centres.
pub const DEFAULT_CONTACT_AT: f64 = 0.3;

impl Default for FrobeniusCase {
    /// The single gas cylinder of §3.6 ([`Cylinder::gas_cylinder`]) at ϑ = 0.4,
    /// heading 0.5, no contact position (a pair touches at [`DEFAULT_CONTACT_AT`]),
    /// generic configuration.
    fn default() -> Self {
        Self {
            system: ConstraintSystem::Single,
            configuration: PairConfiguration::Generic,
            cylinder: Cylinder::gas_cylinder(),
            theta: 0.4,
            heading: 0.5,
            contact_at: None,
        }
    }
}

/// The result of one Frobenius test. The field names are the keys of
/// `rollstack cylinder frobenius --json` (docs/cli.md), those of docs/cli.md first.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct IntegrabilityReport {
    /// Rank of W (ERRATA 13: 9 for the nine pair constraints, not 8).
    pub rank: usize,
    /// Number of coordinates minus the rank.
    pub nullity: usize,
    /// Per constraint: max |aᵀ S^Γ b| over unit a, b in the null space of W.
    pub max_abs_asb: Vec<f64>,
    /// Per constraint: whether that maximum vanishes (to 1e-9 relative).
    pub integrable: Vec<bool>,
    /// Whether the whole system passes the test.
    pub system_integrable: bool,
    /// Singular values of W, descending.
    pub singular_values: Vec<f64>,
    /// Coordinates q at which the test ran.
    pub q: Vec<f64>,
    /// Single cylinder only: [y1ᵀS¹y3, y1ᵀS²y3] with the basis (D.2.2), and the printed
    /// values [r sin ψ, −r cos ψ] of (D.2.4).
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub d24: Option<[[f64; 2]; 2]>,
    /// Wall time of the test (derivatives, SVD, projections), seconds.
    pub wall_time_s: f64,
}

impl IntegrabilityReport {
    /// The smallest non-zero singular value of W (the `rank`-th), a measure of how far
    /// W is from losing rank; 0 for rank 0.
    #[must_use]
    pub fn smallest_nonzero_singular_value(&self) -> f64 {
        self.rank
            .checked_sub(1)
            .map_or(0.0, |i| self.singular_values[i])
    }

    /// This report with the system it tested, for its text ([`IntegrabilitySummary`]).
    #[must_use]
    pub fn summary(&self, system: ConstraintSystem) -> IntegrabilitySummary<'_> {
        IntegrabilitySummary {
            system,
            report: self,
        }
    }
}

/// The readable text of `rollstack cylinder frobenius` (`Display`): one Frobenius test
/// with the system it tested.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IntegrabilitySummary<'a> {
    /// The constraint system tested.
    pub system: ConstraintSystem,
    /// The test's result ([`integrability_report`]).
    pub report: &'a IntegrabilityReport,
}

impl fmt::Display for IntegrabilitySummary<'_> {
    /// The system with the rank and nullity of W, one line per constraint Πᵢ with
    /// max |aᵀ S^Γ b| (D.1.5)–(D.1.6) and its verdict, and the verdict of the system.
    /// Lines are separated by `\n`, with none after the last.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let rep = self.report;
        writeln!(
            f,
            "Frobenius test ({}): rank {} nullity {}",
            self.system.name(),
            rep.rank,
            rep.nullity
        )?;
        for (i, (v, ok)) in rep.max_abs_asb.iter().zip(&rep.integrable).enumerate() {
            let verdict = if *ok { "integrable" } else { "not integrable" };
            writeln!(f, "  Π{}: max|aᵀSb| = {v:.3e}  {verdict}", i + 1)?;
        }
        write!(f, "  system integrable: {}", rep.system_integrable)
    }
}

/// The Frobenius test (D.1.5)–(D.1.6) of `case`'s constraint system with exact
/// derivatives ([`frobenius_test`]). The single cylinder is tested at
/// q = (0.1, −0.2, f2(ϑ), ψ, ϑ, 0.3), on the plane (3.2.4), and also reports
/// y1ᵀS^Γy3 for the printed null basis (D.2.2) against (D.2.4) (only Π3 is
/// integrable). The pair is tested at its touching or generic configuration: the nine
/// constraints of App. F have rank 9, not the 8 of (F.2.5) (ERRATA 13); of the seven of
/// (3.5.13), Π3, Π6 and Π7 are integrable.
///
/// # Errors
/// ϑ outside (0, π/2) ([`CylinderError::NotPointContact`]), a non-finite heading or
/// contact position, or one off the axes (pair only; [`CylinderError::Input`]); a
/// contact position for the single cylinder ([`CylinderError::ContactOfSingle`]).
pub fn integrability_report(case: &FrobeniusCase) -> Result<IntegrabilityReport, CylinderError> {
    let cylinder = case.cylinder;
    let theta = check_point_contact(case.theta)?;
    input::finite("heading", case.heading)?;
    if case.system == ConstraintSystem::Single && case.contact_at.is_some() {
        return Err(CylinderError::ContactOfSingle);
    }
    let pair = CylinderPair::identical(cylinder);
    let start = Instant::now();
    let (q, report, d24): (Vec<f64>, FrobeniusReport, _) = match case.system {
        ConstraintSystem::Single => {
            let sys = SingleCylinder { cylinder };
            let psi = case.heading;
            let q = vec![0.1, -0.2, cylinder.f2(theta), psi, theta, 0.3];
            let report = frobenius_test(&sys, &q)?;
            let skew = skew_matrices(&sys, &q)?;
            let y = sys
                .printed_null_basis(psi, theta)
                .map(|v| DVector::from_row_slice(&v));
            let d24 = [
                [
                    bilinear(&skew.s[0], &y[0], &y[2]),
                    bilinear(&skew.s[1], &y[0], &y[2]),
                ],
                [
                    cylinder.radius() * psi.sin(),
                    -cylinder.radius() * psi.cos(),
                ],
            ];
            (q, report, Some(d24))
        }
        ConstraintSystem::Pair7 | ConstraintSystem::Pair9 => {
            let (at, heading) = (case.contact_at.unwrap_or(DEFAULT_CONTACT_AT), case.heading);
            let q = match case.configuration {
                PairConfiguration::Generic => pair.generic_configuration(theta, at, heading)?,
                PairConfiguration::Touching => pair.touching_configuration(theta, at, heading)?,
            };
            let constraints = if case.system == ConstraintSystem::Pair7 {
                PairConstraints::Seven
            } else {
                PairConstraints::Nine
            };
            (
                q.to_vec(),
                frobenius_test(&PairSystem { pair, constraints }, &q)?,
                None,
            )
        }
    };
    let wall_time_s = start.elapsed().as_secs_f64();
    Ok(IntegrabilityReport {
        rank: report.rank,
        nullity: report.nullity,
        system_integrable: report.system_integrable(),
        max_abs_asb: report.max_abs_asb,
        integrable: report.integrable,
        singular_values: report.singular_values,
        q,
        d24,
        wall_time_s,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn single_cylinder_d_2_4() {
        let rep = integrability_report(&FrobeniusCase::default()).unwrap();
        assert_eq!((rep.rank, rep.nullity), (3, 3));
        assert_eq!(rep.integrable, [false, false, true]);
        assert!(!rep.system_integrable);
        let d24 = rep.d24.unwrap();
        for k in 0..2 {
            assert!((d24[0][k] - d24[1][k]).abs() < 1e-15);
        }
        assert!(rep.smallest_nonzero_singular_value() > 0.0);
        let json = serde_json::to_string(&rep).unwrap();
        assert!(json.starts_with("{\"rank\":3,\"nullity\":3,\"max_abs_asb\":"));
        assert!(json.contains(",\"d24\":[[") && json.contains(",\"wall_time_s\":"));
        let text = rep.summary(ConstraintSystem::Single).to_string();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), 1 + 3 + 1);
        assert_eq!(lines[0], "Frobenius test (single): rank 3 nullity 3");
        assert_eq!(
            lines[1],
            format!(
                "  Π1: max|aᵀSb| = {:.3e}  not integrable",
                rep.max_abs_asb[0]
            )
        );
        assert!(lines[3].ends_with("  integrable") && !lines[3].contains("not"));
        assert_eq!(lines[4], "  system integrable: false");
    }

    #[test]
    fn pair_ranks_errata_13() {
        for configuration in [PairConfiguration::Generic, PairConfiguration::Touching] {
            let case = |system| FrobeniusCase {
                system,
                configuration,
                ..FrobeniusCase::default()
            };
            let nine = integrability_report(&case(ConstraintSystem::Pair9)).unwrap();
            assert_eq!((nine.rank, nine.nullity), (9, 3), "{configuration:?}");
            assert_eq!(nine.max_abs_asb.len(), 9);
            assert_eq!(nine.d24, None);
            let text = nine.summary(ConstraintSystem::Pair9).to_string();
            assert!(text.starts_with("Frobenius test (pair9): rank 9 nullity 3\n"));
            let seven = integrability_report(&case(ConstraintSystem::Pair7)).unwrap();
            assert_eq!(seven.rank, 7);
            assert_eq!(
                seven.integrable,
                [false, false, true, false, false, true, true]
            );
            let text = serde_json::to_string(&seven).unwrap();
            assert!(!text.contains("d24"));
        }
    }

    #[test]
    fn refuses_bad_input() {
        let bad = FrobeniusCase {
            theta: 0.0,
            ..FrobeniusCase::default()
        };
        assert!(matches!(
            integrability_report(&bad),
            Err(CylinderError::NotPointContact(_))
        ));
        let off_axis = FrobeniusCase {
            system: ConstraintSystem::Pair9,
            contact_at: Some(1.0),
            ..FrobeniusCase::default()
        };
        assert_eq!(
            integrability_report(&off_axis).unwrap_err().to_string(),
            "contact position must lie in (−h/2, h/2), got 1"
        );
    }

    #[test]
    fn refuses_non_finite_input_and_a_contact_of_one_cylinder() {
        for at in [f64::NAN, f64::INFINITY] {
            let pair = FrobeniusCase {
                system: ConstraintSystem::Pair7,
                contact_at: Some(at),
                ..FrobeniusCase::default()
            };
            let err = integrability_report(&pair).unwrap_err().to_string();
            assert_eq!(err, "contact position is not finite");
            let single = FrobeniusCase {
                contact_at: Some(at),
                ..FrobeniusCase::default()
            };
            assert_eq!(
                integrability_report(&single),
                Err(CylinderError::ContactOfSingle)
            );
        }
        let single = FrobeniusCase {
            contact_at: Some(0.3),
            ..FrobeniusCase::default()
        };
        assert_eq!(
            integrability_report(&single),
            Err(CylinderError::ContactOfSingle)
        );
        let heading = FrobeniusCase {
            heading: f64::NAN,
            ..FrobeniusCase::default()
        };
        let err = integrability_report(&heading).unwrap_err().to_string();
        assert_eq!(err, "heading is not finite");
    }
}
