//! Steady support of an inclined rolling cylinder (§3.3), corrected per ERRATA 9–11.
//!
//! The cylinder rolls with constant ψ, ϑ and spin rate (3.3.1), its centre of mass moving
//! in a straight line (3.3.2). It is held by an applied force F_a = F e′2 + F3 E3 at the
//! centre of its top face, the plane pushes with N E3 and static friction F_f = −F e′2
//! at P (3.3.4)–(3.3.6). All forces are made dimensionless by mg and lengths by h, so the
//! only parameters are ρ = r/h and the friction coefficient μ.
//!
//! Sign convention: F is the e′2 component of the horizontal applied force, and the
//! friction force is F_f = −F e′2. The "+" limit of (3.3.8) is F_f = +μN e′2 (F = −μN),
//! the "−" limit is F_f = −μN e′2 (F = +μN).

use crate::error::CylinderError;
use input::{finite, in_range, non_negative};
use nalgebra::{Vector3, Vector6};
use serde::{Deserialize, Serialize};
use std::f64::consts::FRAC_PI_2;

/// Which limiting friction force of §3.3.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FrictionLimit {
    /// F_f = +μN e′2: (3.3.8) with the + sign (curves i in Figure 3.3, black in 3.4).
    Plus,
    /// F_f = −μN e′2: (3.3.8) with the − sign (curves ii in Figure 3.3, blue in 3.4).
    Minus,
    /// F_f = 0, the smooth plane (3.3.10) (red in Figures 3.4 and 3.5).
    Smooth,
}

impl FrictionLimit {
    /// +1, −1 or 0: the sign s in F_f = s μN e′2.
    #[must_use]
    pub fn sign(self) -> f64 {
        match self {
            Self::Plus => 1.0,
            Self::Minus => -1.0,
            Self::Smooth => 0.0,
        }
    }
}

/// The dimensionless steady-support problem: aspect ratio ρ = r/h and friction μ.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SupportProblem {
    r_over_h: f64,
    mu: f64,
}

/// How the minimum applied force was found: the four cases of §3.3.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum MinForceCase {
    /// The foot of the perpendicular from the origin to the line (3.3.12) is admissible,
    /// (3.3.15)–(3.3.17). Point A of Figure 3.6.
    Unconstrained,
    /// The minimum sits on the friction bound F = +μN, (3.3.18)₁ (F_f = −μN e′2).
    FrictionPositive,
    /// The minimum sits on the friction bound F = −μN, (3.3.18)₂ (F_f = +μN e′2).
    FrictionNegative,
    /// The minimum sits on F3 = 0, (3.3.19).
    NoVerticalForce,
    /// ϑ = 0 or π/2: the cylinder stands on its base or lies on its side and needs no
    /// force (the fourth case; points E of Figure 3.8).
    FlatContact,
}

impl MinForceCase {
    /// The thesis equation the case evaluates.
    #[must_use]
    pub fn equation(self) -> &'static str {
        match self {
            Self::Unconstrained => "(3.3.15)",
            Self::FrictionPositive => "(3.3.18)_1",
            Self::FrictionNegative => "(3.3.18)_2",
            Self::NoVerticalForce => "(3.3.19)",
            Self::FlatContact => "fourth case, §3.3",
        }
    }

    /// A short name (the `case` key of the CLI).
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Unconstrained => "unconstrained",
            Self::FrictionPositive => "friction_positive",
            Self::FrictionNegative => "friction_negative",
            Self::NoVerticalForce => "no_vertical_force",
            Self::FlatContact => "flat_contact",
        }
    }
}

/// The smallest applied force that sustains the steady motion at one inclination.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct MinimumForce {
    /// F3 / mg.
    pub f3_over_mg: f64,
    /// F / mg (horizontal component along e′2).
    pub f_over_mg: f64,
    /// ‖F_a‖ / mg.
    pub norm_over_mg: f64,
    /// Which case of §3.3 gave it.
    pub case: MinForceCase,
}

/// The circle traced by the unconstrained minimum (3.3.15) as ϑ varies: diameter BC,
/// (3.3.20), with B on every line (3.3.14) and C on every line (3.3.12) (ERRATA 11).
/// Points are (F3/mg, F/mg).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct MinimumForceCircle {
    /// B = (0, 0), common point of the perpendiculars (3.3.14).
    pub b: [f64; 2],
    /// C = ((1/2 + ρ²)/(1 + ρ²), −(ρ/2)/(1 + ρ²)), common point of the lines (3.3.12).
    pub c: [f64; 2],
    /// Centre (B + C)/2.
    pub center: [f64; 2],
    /// Radius |BC|/2.
    pub radius: f64,
}

impl SupportProblem {
    /// The problem for r/h = `r_over_h` ≥ 0 (0 is the slender rod of Figure 3.4) and
    /// μ = `mu` ≥ 0.
    ///
    /// # Errors
    /// When r/h or μ is negative (or either is not finite).
    pub fn new(r_over_h: f64, mu: f64) -> Result<Self, CylinderError> {
        Ok(Self {
            r_over_h: non_negative("r/h", r_over_h)?,
            mu: non_negative("μ", mu)?,
        })
    }

    /// ρ = r/h.
    #[must_use]
    pub fn r_over_h(&self) -> f64 {
        self.r_over_h
    }

    /// μ.
    #[must_use]
    pub fn mu(&self) -> f64 {
        self.mu
    }

    /// The denominator of (3.3.8) (corrected, ERRATA 9):
    /// sin ϑ − ρ cos ϑ + s μ (ρ sin ϑ + cos ϑ), s = +1, −1 or 0 for the smooth plane.
    fn denominator(&self, theta: f64, limit: FrictionLimit) -> f64 {
        let (s, c) = theta.sin_cos();
        let rho = self.r_over_h;
        s - rho * c + limit.sign() * self.mu * (rho * s + c)
    }

    /// N/mg = 1 − F3/mg at the friction limit, (3.3.8) corrected per ERRATA 9 (μ
    /// multiplies both terms of the ± bracket) and (3.3.10) for the smooth plane:
    /// N/mg = ½ sin ϑ / [sin ϑ − ρ cos ϑ ± μ(ρ sin ϑ + cos ϑ)].
    ///
    /// `None` when the denominator is not positive: no positive normal force meets that
    /// limit. The value may exceed 1 (then F3 < 0: the top must be pulled down).
    ///
    /// # Errors
    /// When ϑ is outside (0, π/2) (point contact, §3.2).
    pub fn normal_force(
        &self,
        theta: f64,
        limit: FrictionLimit,
    ) -> Result<Option<f64>, CylinderError> {
        crate::kinematics::check_point_contact(theta)?;
        let d = self.denominator(theta, limit);
        Ok((d > 0.0).then(|| 0.5 * theta.sin() / d))
    }

    /// The inclinations at which the limit gives 0 < N < mg (so F3 > 0), (3.3.9)
    /// corrected per ERRATA 10 (lower bounds max(0, …)); (3.3.10)'s range
    /// (arctan 2ρ, π/2) for the smooth plane. `None` when empty (the − limit with
    /// μρ ≥ ½).
    ///
    /// The + range is also the set of inclinations at which *some* steady support exists:
    /// the admissible normal forces at ϑ are [N₊, min(N₋, mg)].
    #[must_use]
    pub fn inclination_range(&self, limit: FrictionLimit) -> Option<(f64, f64)> {
        let (rho, mu) = (self.r_over_h, self.mu);
        // N < mg ⇔ D − ½ sin ϑ > 0 ⇔ sin ϑ (½ + sμρ) > cos ϑ (ρ − sμ); this also
        // implies D > 0 whenever it holds.
        let s = limit.sign();
        let lower = (rho - s * mu).atan2(0.5 + s * mu * rho);
        let lower = lower.max(0.0);
        (lower < FRAC_PI_2).then_some((lower, FRAC_PI_2))
    }

    /// The point where all + curves meet whatever ρ, (3.3.11):
    /// (ϑ, N/mg) = (arctan(1/μ), 1/(2(1 + μ²))). `None` for μ = 0.
    #[must_use]
    pub fn common_point(&self) -> Option<(f64, f64)> {
        let mu = self.mu;
        (mu > 0.0).then(|| ((1.0 / mu).atan(), 0.5 / (1.0 + mu * mu)))
    }

    /// The inclination of point D: zero applied force, ϑ = arctan(2ρ) (§3.3, Figure 3.8).
    #[must_use]
    pub fn self_balancing_inclination(&self) -> f64 {
        (2.0 * self.r_over_h).atan()
    }

    /// (α1, α2) of the line F/mg = α1 F3/mg + α2, (3.3.12)–(3.3.13).
    #[must_use]
    pub fn line(&self, theta: f64) -> (f64, f64) {
        let (s, c) = theta.sin_cos();
        let rho = self.r_over_h;
        let den = rho * s + c;
        ((rho * c - s) / den, -(rho * c - 0.5 * s) / den)
    }

    /// The foot of the perpendicular from the origin to the line (3.3.12): (F3/mg, F/mg)
    /// of (3.3.15), ignoring friction and F3 ≥ 0.
    #[must_use]
    pub fn unconstrained_minimum(&self, theta: f64) -> (f64, f64) {
        let (a1, a2) = self.line(theta);
        let q = 1.0 + a1 * a1;
        (-a1 * a2 / q, a2 / q)
    }

    /// ‖F_a‖/mg of the unconstrained minimum, (3.3.16):
    /// |ρ cos ϑ − ½ sin ϑ| / √(1 + ρ²).
    #[must_use]
    pub fn unconstrained_minimum_norm(&self, theta: f64) -> f64 {
        let rho = self.r_over_h;
        (rho * theta.cos() - 0.5 * theta.sin()).abs() / (1.0 + rho * rho).sqrt()
    }

    /// The admissibility test (3.3.17) of the unconstrained minimum:
    /// |α2| ≤ μ(α1² + α1α2 + 1), i.e. |F| ≤ μN there.
    #[must_use]
    pub fn satisfies_friction_criterion(&self, theta: f64) -> bool {
        let (a1, a2) = self.line(theta);
        a2.abs() <= self.mu * (a1 * a1 + a1 * a2 + 1.0)
    }

    /// The smallest applied force sustaining the steady motion at inclination ϑ ∈ [0, π/2]:
    /// the point of the line (3.3.12) closest to the origin among those with |F| ≤ μN,
    /// F3 ≥ 0 and N ≥ 0, found among the four cases (3.3.15), (3.3.18), (3.3.19) and
    /// ϑ ∈ {0, π/2}.
    ///
    /// The admissible part of the line is an interval of F3; the minimum is the
    /// unconstrained foot (3.3.15) clamped into it, and the bound that clamps it names
    /// the case, whose closed form is then evaluated.
    ///
    /// # Errors
    /// When ϑ is outside [0, π/2], or no admissible force exists
    /// ([`CylinderError::NoSupport`]).
    pub fn minimum_force(&self, theta: f64) -> Result<MinimumForce, CylinderError> {
        in_range("inclination ϑ", theta, 0.0..=FRAC_PI_2, "[0, π/2]")?;
        if theta == 0.0 || theta == FRAC_PI_2 {
            return Ok(MinimumForce {
                f3_over_mg: 0.0,
                f_over_mg: 0.0,
                norm_over_mg: 0.0,
                case: MinForceCase::FlatContact,
            });
        }
        let case = self.minimum_force_case(theta)?;
        let (a1, a2) = self.line(theta);
        let mu = self.mu;
        let (f3, f) = match case {
            MinForceCase::Unconstrained | MinForceCase::FlatContact => {
                self.unconstrained_minimum(theta)
            }
            MinForceCase::FrictionPositive => ((mu - a2) / (mu + a1), mu * (a1 + a2) / (mu + a1)),
            MinForceCase::FrictionNegative => ((mu + a2) / (mu - a1), mu * (a1 + a2) / (mu - a1)),
            MinForceCase::NoVerticalForce => (0.0, a2),
        };
        Ok(MinimumForce {
            f3_over_mg: f3,
            f_over_mg: f,
            norm_over_mg: f3.hypot(f),
            case,
        })
    }

    /// Which bound, if any, holds the minimum of ‖F_a‖ on the admissible interval.
    fn minimum_force_case(&self, theta: f64) -> Result<MinForceCase, CylinderError> {
        let (a1, a2) = self.line(theta);
        let mu = self.mu;
        // Each admissibility condition is a + b t ≥ 0 in t = F3/mg, listed with the case
        // its bound belongs to. Friction bounds come first so that, when μ = 0 pins the
        // interval to a point, a friction case is reported.
        let conditions = [
            (mu - a2, -(mu + a1), MinForceCase::FrictionPositive), // μN − F ≥ 0
            (mu + a2, a1 - mu, MinForceCase::FrictionNegative),    // μN + F ≥ 0
            (0.0, 1.0, MinForceCase::NoVerticalForce),             // F3 ≥ 0
            (1.0, -1.0, MinForceCase::FrictionPositive),           // N ≥ 0 (implied for μ > 0)
        ];
        let scale = 1e-12;
        let (mut lo, mut lo_case) = (f64::NEG_INFINITY, MinForceCase::Unconstrained);
        let (mut hi, mut hi_case) = (f64::INFINITY, MinForceCase::Unconstrained);
        for (a, b, case) in conditions {
            if b.abs() <= scale * (1.0 + a.abs()) {
                if a < -scale {
                    return Err(self.no_support(theta));
                }
            } else if b > 0.0 {
                let t = -a / b;
                if t > lo {
                    (lo, lo_case) = (t, case);
                }
            } else {
                let t = -a / b;
                if t < hi {
                    (hi, hi_case) = (t, case);
                }
            }
        }
        if lo > hi + scale * (1.0 + lo.abs()) {
            return Err(self.no_support(theta));
        }
        let (t_star, _) = self.unconstrained_minimum(theta);
        Ok(if t_star < lo {
            lo_case
        } else if t_star > hi {
            hi_case
        } else {
            MinForceCase::Unconstrained
        })
    }

    fn no_support(&self, theta: f64) -> CylinderError {
        CylinderError::NoSupport {
            theta,
            r_over_h: self.r_over_h,
            mu: self.mu,
        }
    }

    /// The circle of diameter BC traced by (3.3.15), (3.3.20), with B and C assigned to
    /// the line families as in ERRATA 11.
    #[must_use]
    pub fn minimum_force_circle(&self) -> MinimumForceCircle {
        let rho = self.r_over_h;
        let q = 1.0 + rho * rho;
        let c = [(0.5 + rho * rho) / q, -0.5 * rho / q];
        MinimumForceCircle {
            b: [0.0, 0.0],
            c,
            center: [0.5 * c[0], 0.5 * c[1]],
            radius: 0.5 * c[0].hypot(c[1]),
        }
    }
}

/// The balance laws (3.3.3) of the steady motion solved numerically, as an independent
/// check of the closed forms: the six scalar equations (force and moment balance about
/// the centre) for the unknowns (F_a1, F_a2, F_f1, F_f2, N), with mg = 1, h = 1, at any
/// precession ψ, for a given vertical applied force F3.
///
/// The forces at P and at the top centre X_a cannot produce a moment about the line
/// PX_a, and gravity has none about it either, so the six equations are consistent
/// with one redundant: they are solved in the least-squares sense by Householder QR
/// (exact for consistent equations). The solution is affine in F3, the one free
/// parameter of §3.3; it is stored as its values at F3 = 0 and F3 = 1.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SteadyBalance {
    /// (F_a1, F_a2, F_a3, F_f1, F_f2, N) at F3 = 0.
    particular: Vector6<f64>,
    /// Change of the same per unit F3.
    null: Vector6<f64>,
    e2p: Vector3<f64>,
    problem: SupportProblem,
    theta: f64,
}

/// The members of the solution family of [`SteadyBalance`] as lines in F3.
struct FamilyLines {
    /// Friction along e′2.
    friction: (f64, f64),
    /// Normal force N.
    normal: (f64, f64),
    /// Applied force F_a.
    applied: (Vector3<f64>, Vector3<f64>),
}

impl SteadyBalance {
    /// Builds and solves (3.3.3) for the problem at inclination ϑ ∈ (0, π/2), precession ψ.
    ///
    /// # Errors
    /// When ϑ is outside (0, π/2) or ψ is not finite.
    pub fn new(problem: &SupportProblem, theta: f64, psi: f64) -> Result<Self, CylinderError> {
        use crate::kinematics::EulerFrame;
        use nalgebra::{SMatrix, Vector5};
        crate::kinematics::check_point_contact(theta)?;
        finite("ψ", psi)?;
        let frame = EulerFrame::new(psi, theta);
        // (3.2.4) with h = 1, r = ρ.
        let pi_p = frame.e3 * -0.5 - frame.e2pp * problem.r_over_h;
        let pi_a = frame.e3 * 0.5;
        let unit = |k: usize| Vector3::ith(k, 1.0);
        // Columns: the wrench (force; moment about the centre) of a unit value of each
        // unknown: F_a1, F_a2 at X_a; F_f1, F_f2, N at P; and F3 at X_a.
        let wrench = |force: Vector3<f64>, at: &Vector3<f64>| {
            let m = at.cross(&force);
            Vector6::new(force.x, force.y, force.z, m.x, m.y, m.z)
        };
        let a = SMatrix::<f64, 6, 5>::from_columns(&[
            wrench(unit(0), &pi_a),
            wrench(unit(1), &pi_a),
            wrench(unit(0), &pi_p),
            wrench(unit(1), &pi_p),
            wrench(unit(2), &pi_p),
        ]);
        let f3_column = wrench(unit(2), &pi_a);
        // Gravity: the other forces balance mg E3 and have no net moment.
        let weight = Vector6::new(0.0, 0.0, 1.0, 0.0, 0.0, 0.0);
        let qr = a.qr();
        let (q, r) = (qr.q(), qr.r());
        let solve = |f3: f64| -> Vector6<f64> {
            let rhs: Vector5<f64> = q.transpose() * (weight - f3_column * f3);
            let x = r
                .solve_upper_triangular(&rhs)
                .unwrap_or_else(Vector5::zeros);
            Vector6::new(x[0], x[1], f3, x[2], x[3], x[4])
        };
        let particular = solve(0.0);
        let null = solve(1.0) - particular;
        Ok(Self {
            particular,
            null,
            e2p: frame.e2p,
            problem: *problem,
            theta,
        })
    }

    /// The change of (F_a1, F_a2, F_a3, F_f1, F_f2, N) per unit increase of F3/mg: the
    /// direction of the one-parameter family of solutions.
    #[must_use]
    pub fn null_direction(&self) -> Vector6<f64> {
        self.null
    }

    /// (F_a, friction along e′2, N) at F3/mg = λ.
    fn at(&self, lambda: f64) -> (Vector3<f64>, f64, f64) {
        let u = self.particular + self.null * lambda;
        let fa = Vector3::new(u[0], u[1], u[2]);
        let ff = Vector3::new(u[3], u[4], 0.0);
        (fa, ff.dot(&self.e2p), u[5])
    }

    /// The solution family as straight lines in F3: value at F3 = 0 and slope.
    fn lines(&self) -> FamilyLines {
        let (fa0, ff0, n0) = self.at(0.0);
        let (fa1, ff1, n1) = self.at(1.0);
        FamilyLines {
            friction: (ff0, ff1 - ff0),
            normal: (n0, n1 - n0),
            applied: (fa0, fa1 - fa0),
        }
    }

    /// N/mg at the friction limit F_f = s μN e′2, solved from the numerical family.
    #[must_use]
    pub fn limiting_normal_force(&self, limit: FrictionLimit) -> f64 {
        let FamilyLines {
            friction: (f0, f1),
            normal: (n0, n1),
            ..
        } = self.lines();
        let s = limit.sign() * self.problem.mu;
        let lambda = (s * n0 - f0) / (f1 - s * n1);
        n0 + lambda * n1
    }

    /// The minimum ‖F_a‖ over the admissible family, found directly in λ: returns
    /// (F3/mg, F/mg) with F = F_a · e′2.
    ///
    /// # Errors
    /// [`CylinderError::NoSupport`] when no member is admissible.
    pub fn minimum_force(&self) -> Result<(f64, f64), CylinderError> {
        let FamilyLines {
            friction: (f0, f1),
            normal: (n0, n1),
            applied: (p, d),
        } = self.lines();
        let mu = self.problem.mu;
        let no_support = CylinderError::NoSupport {
            theta: self.theta,
            r_over_h: self.problem.r_over_h,
            mu,
        };
        // |friction| ≤ μN and F3 ≥ 0, each a + b λ ≥ 0.
        let conditions = [
            (mu * n0 - f0, mu * n1 - f1),
            (mu * n0 + f0, mu * n1 + f1),
            (p.z, d.z),
            (n0, n1),
        ];
        let (mut lo, mut hi) = (f64::NEG_INFINITY, f64::INFINITY);
        for (a, b) in conditions {
            if b.abs() < 1e-14 {
                if a < -1e-12 {
                    return Err(no_support);
                }
            } else if b > 0.0 {
                lo = lo.max(-a / b);
            } else {
                hi = hi.min(-a / b);
            }
        }
        if lo > hi + 1e-12 {
            return Err(no_support);
        }
        let lambda = (-p.dot(&d) / d.norm_squared()).clamp(lo, hi.max(lo));
        let (fa, _, _) = self.at(lambda);
        Ok((fa.z, fa.dot(&self.e2p)))
    }

    /// The residual of the two equations the thesis drops, (3.3.5)₂,₃: the applied force
    /// has no e′1 component (β1 = 0), for every member of the family.
    #[must_use]
    pub fn e1_component(&self, lambda: f64) -> f64 {
        let (fa, _, _) = self.at(lambda);
        let e1p = Vector3::new(self.e2p.y, -self.e2p.x, 0.0);
        fa.dot(&e1p)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn errata_9_common_point() {
        // Only the corrected (3.3.8) passes through (3.3.11) for every ρ.
        let mu = 0.2;
        for rho in [0.0001, 0.05, 0.1, 0.15, 0.7] {
            let p = SupportProblem::new(rho, mu).unwrap();
            let (theta, n) = p.common_point().unwrap();
            let got = p.normal_force(theta, FrictionLimit::Plus).unwrap().unwrap();
            assert!((got - n).abs() < 1e-15, "{rho}: {got} vs {n}");
        }
        assert!(
            (SupportProblem::new(0.1, 0.2)
                .unwrap()
                .common_point()
                .unwrap()
                .1
                - 1.0 / 2.08)
                .abs()
                < 1e-15
        );
    }

    #[test]
    fn ranges() {
        let p = SupportProblem::new(0.1, 0.2).unwrap();
        // + case: ρ < μ, so the range starts at 0 (ERRATA 10: max, not min).
        assert_eq!(
            p.inclination_range(FrictionLimit::Plus),
            Some((0.0, FRAC_PI_2))
        );
        let (lo, _) = p.inclination_range(FrictionLimit::Minus).unwrap();
        assert!((lo - (0.3f64 / 0.48).atan()).abs() < 1e-15);
        let (lo, _) = p.inclination_range(FrictionLimit::Smooth).unwrap();
        assert!((lo - 0.2f64.atan()).abs() < 1e-15);
        // μρ ≥ ½ empties the − range.
        assert!(SupportProblem::new(1.0, 0.6)
            .unwrap()
            .inclination_range(FrictionLimit::Minus)
            .is_none());
        // Inside each range 0 < N < mg; just below its lower end N ≥ mg or no N.
        for limit in [
            FrictionLimit::Plus,
            FrictionLimit::Minus,
            FrictionLimit::Smooth,
        ] {
            let p = SupportProblem::new(0.3, 0.1).unwrap();
            let (lo, hi) = p.inclination_range(limit).unwrap();
            for k in 1..100 {
                let t = lo + (hi - lo) * f64::from(k) / 100.0;
                let n = p.normal_force(t, limit).unwrap().unwrap();
                assert!(n > 0.0 && n < 1.0, "{limit:?} {t} {n}");
            }
            if lo > 1e-3 {
                let n = p.normal_force(lo - 1e-3, limit).unwrap();
                assert!(n.is_none_or(|n| n >= 1.0));
            }
        }
    }

    #[test]
    fn point_d_zero_force() {
        let p = SupportProblem::new(0.1, 0.2).unwrap();
        let t = p.self_balancing_inclination();
        let m = p.minimum_force(t).unwrap();
        assert!(m.norm_over_mg < 1e-15);
        assert_eq!(m.case, MinForceCase::Unconstrained);
        assert_eq!(
            p.minimum_force(0.0).unwrap().case,
            MinForceCase::FlatContact
        );
        assert!(p.minimum_force(2.0).is_err());
    }

    #[test]
    fn circle_errata_11() {
        let p = SupportProblem::new(0.1, 0.2).unwrap();
        let circle = p.minimum_force_circle();
        for k in 1..50 {
            let theta = FRAC_PI_2 * f64::from(k) / 50.0;
            let (a1, a2) = p.line(theta);
            // Every line (3.3.12) passes through C; the foot lies on the circle.
            assert!((a1 * circle.c[0] + a2 - circle.c[1]).abs() < 1e-15);
            let (f3, f) = p.unconstrained_minimum(theta);
            let dist = (f3 - circle.center[0]).hypot(f - circle.center[1]);
            assert!((dist - circle.radius).abs() < 1e-15);
            assert!((f3.hypot(f) - p.unconstrained_minimum_norm(theta)).abs() < 1e-15);
        }
    }
}
