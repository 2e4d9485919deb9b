//! The constraint systems to which the Frobenius test is applied: one rolling cylinder
//! (App. D) and a touching pair (§3.5, App. F), with 12 coordinates (F.2.1)
//! q = (x_I, ψ1, ϑ1, φ1, x_II, ψ2, ϑ2, φ2).
//!
//! The pair's kinematics (contact offsets π_P1..π_P4, gap functions, constraint rows) are
//! generic over the scalar so that the later two-cylinder simulation of §3.6 can reuse
//! them with exact derivatives.

use crate::contact::{closest_points, ground_gap, AxisSegment, ClosestPoints};
use crate::error::CylinderError;
use crate::frobenius::PfaffianSystem;
use crate::kinematics::{contact_offset, rolling_matrix, rotation_columns, Cylinder, EulerFrame};
use input::InputError;
use nalgebra::{DMatrix, Matrix3, RealField, SMatrix, Vector3};
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// One cylinder rolling on the plane: 6 coordinates (D.1.2), the 3 constraints v_P = 0
/// (3.2.2), W of (D.1.4).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SingleCylinder {
    /// The cylinder.
    pub cylinder: Cylinder,
}

impl PfaffianSystem for SingleCylinder {
    fn coordinate_count(&self) -> usize {
        6
    }

    fn constraint_count(&self) -> usize {
        3
    }

    fn constraint_matrix<T: RealField + Copy>(&self, q: &[T]) -> DMatrix<T> {
        let w = rolling_matrix(&self.cylinder, q[3], q[4]);
        DMatrix::from_fn(3, 6, |i, j| w[(i, j)])
    }
}

impl SingleCylinder {
    /// The null-space basis (D.2.2) of W: y1 (precession), y2 (nutation), y3 (spin).
    #[must_use]
    pub fn printed_null_basis(&self, psi: f64, theta: f64) -> [[f64; 6]; 3] {
        let (f1, f2, r) = (
            self.cylinder.f1(theta),
            self.cylinder.f2(theta),
            self.cylinder.radius(),
        );
        let (s, c) = psi.sin_cos();
        [
            [-c * f1, -s * f1, 0.0, 1.0, 0.0, 0.0],
            [s * f2, -c * f2, f1, 0.0, 1.0, 0.0],
            [-r * c, -r * s, 0.0, 0.0, 0.0, 1.0],
        ]
    }
}

/// Everything about the three contacts of a pair at one configuration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PairContacts<T: RealField + Copy> {
    /// Euler frames of cylinders I and II.
    pub frames: [EulerFrame<T>; 2],
    /// π_P1, π_P2: ground contacts relative to each centre, (3.5.4), (3.5.6).
    pub ground: [Vector3<T>; 2],
    /// The closest points of the axes and the mutual contact P3, P4, (E.2.1)–(E.2.8).
    pub mutual: ClosestPoints<T>,
    /// n = e3_I × e3_II / ‖·‖, (3.5.8).
    pub normal: Vector3<T>,
    /// The gap functions (g_N1, g_N2, g_N3), (E.3.1).
    pub gaps: [T; 3],
}

/// A pair of cylinders, each rolling on the plane, touching each other (§3.5).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct CylinderPair {
    /// Cylinder I.
    pub first: Cylinder,
    /// Cylinder II.
    pub second: Cylinder,
}

impl CylinderPair {
    /// Two copies of one cylinder.
    #[must_use]
    pub fn identical(cylinder: Cylinder) -> Self {
        Self {
            first: cylinder,
            second: cylinder,
        }
    }

    /// The contacts at configuration q (12 entries, (F.2.1)).
    #[must_use]
    pub fn contacts<T: RealField + Copy>(&self, q: &[T]) -> PairContacts<T> {
        let frames = [EulerFrame::new(q[3], q[4]), EulerFrame::new(q[9], q[10])];
        let centers = [
            Vector3::new(q[0], q[1], q[2]),
            Vector3::new(q[6], q[7], q[8]),
        ];
        let ground = [
            contact_offset(&self.first, &frames[0]),
            contact_offset(&self.second, &frames[1]),
        ];
        let segment = |i: usize, c: &Cylinder| AxisSegment {
            center: centers[i],
            axis: frames[i].e3,
            half_length: nalgebra::convert(0.5 * c.height()),
            radius: nalgebra::convert(c.radius()),
        };
        let mutual = closest_points(&segment(0, &self.first), &segment(1, &self.second));
        let normal = frames[0].e3.cross(&frames[1].e3);
        let normal = normal / normal.norm();
        let gaps = [
            ground_gap(&centers[0], &ground[0]),
            ground_gap(&centers[1], &ground[1]),
            mutual.gap,
        ];
        PairContacts {
            frames,
            ground,
            mutual,
            normal,
            gaps,
        }
    }

    /// The nine rolling constraints (F.1.2) as W (9 × 12) of (F.2.3):
    /// rows v1 = 0, v2 = 0, v3 − v4 = 0 with blocks
    /// [[I, A, 0, 0], [0, 0, I, B], [I, C, −I, −D]] and A, B, C, D of (F.2.4) (A with the
    /// sign of ERRATA 12).
    #[must_use]
    pub fn rolling_matrix9<T: RealField + Copy>(&self, q: &[T]) -> SMatrix<T, 9, 12> {
        let k = self.contacts(q);
        let [f1, f2] = k.frames;
        let a = rotation_columns(&f1, &k.ground[0]);
        let b = rotation_columns(&f2, &k.ground[1]);
        let c = rotation_columns(&f1, &k.mutual.pi_p3);
        let d = rotation_columns(&f2, &k.mutual.pi_p4);
        let id = Matrix3::<T>::identity();
        let mut w = SMatrix::<T, 9, 12>::zeros();
        let mut put =
            |r: usize, col: usize, m: &Matrix3<T>| w.fixed_view_mut::<3, 3>(r, col).copy_from(m);
        put(0, 0, &id);
        put(0, 3, &a);
        put(3, 6, &id);
        put(3, 9, &b);
        put(6, 0, &id);
        put(6, 3, &c);
        put(6, 6, &(-id));
        put(6, 9, &(-d));
        w
    }

    /// The seven constraints Π1..Π7 of (3.5.13): rolling at both ground contacts and no
    /// relative normal velocity at the mutual contact, (v3 − v4) · n = 0 (3.5.11).
    #[must_use]
    pub fn rolling_matrix7<T: RealField + Copy>(&self, q: &[T]) -> SMatrix<T, 7, 12> {
        let w9 = self.rolling_matrix9(q);
        let n = self.contacts(q).normal;
        let mut w = SMatrix::<T, 7, 12>::zeros();
        w.fixed_view_mut::<6, 12>(0, 0)
            .copy_from(&w9.fixed_view::<6, 12>(0, 0));
        for col in 0..12 {
            w[(6, col)] = w9[(6, col)] * n.x + w9[(7, col)] * n.y + w9[(8, col)] * n.z;
        }
        w
    }

    /// A touching configuration of the transport of §3.5 (Figure 3.1): both cylinders on
    /// the plane at inclination ϑ, leaning towards each other (ψ1 = 0, ψ2 = π), their axes
    /// a distance r1 + r2 apart along E1, touching at the points m* = n* = `contact_at`
    /// of their axes (|contact_at| < h/2). Spins φ1 = φ2 = 0. The whole arrangement is
    /// then turned about E3 by `heading` (so ψ1 = heading, ψ2 = π + heading): a heading
    /// of 0 makes sin ψ1 = sin ψ2 = 0, which hides the S¹ and S⁴ terms of (F.4.2), (F.4.5).
    ///
    /// # Errors
    /// When ϑ is outside (0, π/2), `contact_at` is off either axis, or the cylinders
    /// differ in height or radius so that the construction does not apply.
    pub fn touching_configuration(
        &self,
        theta: f64,
        contact_at: f64,
        heading: f64,
    ) -> Result<[f64; 12], CylinderError> {
        crate::kinematics::check_point_contact(theta)?;
        input::finite("contact position", contact_at)?;
        input::finite("heading", heading)?;
        if self.first != self.second {
            let size = |c: &Cylinder| [c.radius(), c.height()];
            return Err(CylinderError::DifferentCylinders {
                first: size(&self.first),
                second: size(&self.second),
            });
        }
        let half = 0.5 * self.first.height();
        if contact_at.abs() >= half {
            return Err(InputError::OutOfRange {
                name: "contact position".into(),
                range: "(−h/2, h/2)",
                value: contact_at,
            }
            .into());
        }
        let (s, height) = (theta.sin(), self.first.f2(theta));
        let gap = self.first.radius() + self.second.radius();
        // e3_I = (0, −sin ϑ, cos ϑ), e3_II = (0, sin ϑ, cos ϑ): both axes lie in planes
        // x = const, so the common normal is E1; equal heights and y offsets ∓ m s put the
        // closest points at m* = n* = contact_at.
        let turn = nalgebra::Rotation3::from_axis_angle(&Vector3::z_axis(), heading);
        let x1 = turn * Vector3::new(0.0, contact_at * s, height);
        let x2 = turn * Vector3::new(gap, -contact_at * s, height);
        Ok([
            x1.x,
            x1.y,
            x1.z,
            heading,
            theta,
            0.0,
            x2.x,
            x2.y,
            x2.z,
            PI + heading,
            theta,
            0.0,
        ])
    }

    /// A generic configuration near a touching one: every coordinate shifted by a fixed
    /// irregular offset (the cylinders no longer touch; W is still defined).
    ///
    /// # Errors
    /// As [`CylinderPair::touching_configuration`].
    pub fn generic_configuration(
        &self,
        theta: f64,
        contact_at: f64,
        heading: f64,
    ) -> Result<[f64; 12], CylinderError> {
        const OFFSETS: [f64; 12] = [
            0.013, -0.021, 0.008, 0.31, 0.047, 1.3, -0.017, 0.029, -0.006, -0.23, -0.061, 2.1,
        ];
        let mut q = self.touching_configuration(theta, contact_at, heading)?;
        for (v, o) in q.iter_mut().zip(OFFSETS) {
            *v += o;
        }
        Ok(q)
    }
}

/// The pair with a choice of constraint set, as a [`PfaffianSystem`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PairSystem {
    /// The cylinders.
    pub pair: CylinderPair,
    /// Nine rolling constraints (App. F) or seven (rolling at the ground, normal
    /// contact between the cylinders, (3.5.11)).
    pub constraints: PairConstraints,
}

/// Which constraint set of the pair.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PairConstraints {
    /// Π1..Π7 of (3.5.13).
    Seven,
    /// Π1..Π9 of (F.1.2).
    Nine,
}

impl PfaffianSystem for PairSystem {
    fn coordinate_count(&self) -> usize {
        12
    }

    fn constraint_count(&self) -> usize {
        match self.constraints {
            PairConstraints::Seven => 7,
            PairConstraints::Nine => 9,
        }
    }

    fn constraint_matrix<T: RealField + Copy>(&self, q: &[T]) -> DMatrix<T> {
        match self.constraints {
            PairConstraints::Seven => {
                let w = self.pair.rolling_matrix7(q);
                DMatrix::from_fn(7, 12, |i, j| w[(i, j)])
            }
            PairConstraints::Nine => {
                let w = self.pair.rolling_matrix9(q);
                DMatrix::from_fn(9, 12, |i, j| w[(i, j)])
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::ClosestKind;

    #[test]
    fn touching_configuration_touches() {
        let pair = CylinderPair::identical(Cylinder::gas_cylinder());
        let q = pair.touching_configuration(0.4, 0.3, 0.7).unwrap();
        let k = pair.contacts(&q);
        assert_eq!(k.mutual.kind, ClosestKind::Interior);
        assert!(k.gaps.iter().all(|g| g.abs() < 1e-15), "{:?}", k.gaps);
        assert!((k.mutual.m - 0.3).abs() < 1e-15 && (k.mutual.n - 0.3).abs() < 1e-15);
        // u = ±n at a point contact of non-parallel axes.
        assert!((k.mutual.u.cross(&k.normal)).norm() < 1e-15);
    }
}
