//! Contact between the lateral surfaces of two cylinders (App. E): closest points of the
//! two axes (E.2.1)–(E.2.4) clamped to the finite axis segments, the gap (E.2.6), the
//! contact points (E.2.7)–(E.2.9), the gap functions (E.3.1) and the rates of the closest
//! points (E.2.5).
//!
//! The geometry is generic over the scalar (`f64` or a `num-dual` number), so a later
//! system can differentiate gaps and contact points exactly. Parallel axes (H singular,
//! a line of contact) and nearly parallel ones are handled without dividing by 1 − c².

use crate::error::CylinderError;
use input::InputError;
use nalgebra::{Matrix2, RealField, Vector2, Vector3};
use serde::{Deserialize, Serialize};

/// The axis of one cylinder as a segment: x = x̄ + m e3, m ∈ [−h/2, h/2], (E.1.1)–(E.1.2).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxisSegment<T: RealField + Copy> {
    /// Centre of mass x̄.
    pub center: Vector3<T>,
    /// Unit axis e3.
    pub axis: Vector3<T>,
    /// h/2.
    pub half_length: T,
    /// Radius r.
    pub radius: T,
}

/// How the closest points were found.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ClosestKind {
    /// The solution of H h = k (E.2.3) lies inside both segments: a point contact of the
    /// lateral surfaces when the gap is zero.
    Interior,
    /// At least one coordinate was clamped to an end of its segment: the closest points
    /// of the finite axes, where the lateral-surface model of App. E no longer describes
    /// the contact (a rim or an end face would touch first).
    Clamped,
    /// The axes are parallel (H singular) and their projections overlap: a line of
    /// contact; the midpoint of the overlap is returned.
    Parallel,
}

/// The closest points of two axis segments and what follows from them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClosestPoints<T: RealField + Copy> {
    /// m* on the first axis.
    pub m: T,
    /// n* on the second axis.
    pub n: T,
    /// d = ‖x_II* − x_I*‖, (E.2.1).
    pub distance: T,
    /// u = (x_II* − x_I*)/d, (E.2.8), from the first axis to the second; when the axes
    /// meet (d = 0) the normal e3_I × e3_II (or any normal to a parallel pair).
    pub u: Vector3<T>,
    /// π_P3 = m* e3_I + r1 u, (E.2.7), relative to the first centre.
    pub pi_p3: Vector3<T>,
    /// π_P4 = n* e3_II − r2 u, (E.2.7), relative to the second centre.
    pub pi_p4: Vector3<T>,
    /// g_N3 = d − (r1 + r2), (E.2.6): negative when they penetrate. With the surface
    /// points x3, x4 of (E.2.7), x4 − x3 = g_N3 u, so g_N3 = (x4 − x3) · u; the printed
    /// (E.3.1)₃, ‖x3 − x4‖ − (r1 + r2), would mix the axis distance with the surface
    /// points (it is |g_N3| − (r1 + r2)).
    pub gap: T,
    /// How the points were found.
    pub kind: ClosestKind,
}

/// The closest points of the two axis segments, (E.2.1)–(E.2.4), with the contact
/// points (E.2.7) and the gap (E.2.6).
///
/// H h = k is solved in closed form when 1 − c² > 1e-12 (c = e3_I · e3_II). When that
/// solution lies off a segment, or the axes are parallel, the minimum of the (convex)
/// distance over the rectangle of segment coordinates is on one of its edges, where it
/// is the clamped projection of a segment end onto the other axis: the best of the four
/// is taken. Parallel axes whose projections overlap give a line of contact; the
/// midpoint of the overlap is returned when it is as close as the best edge point.
#[must_use]
pub fn closest_points<T: RealField + Copy>(
    a: &AxisSegment<T>,
    b: &AxisSegment<T>,
) -> ClosestPoints<T> {
    let c = a.axis.dot(&b.axis);
    let delta = b.center - a.center;
    // k of (E.2.4).
    let k1 = delta.dot(&a.axis);
    let k2 = -delta.dot(&b.axis);
    let det = T::one() - c * c;
    let eps: T = nalgebra::convert(1e-12);
    let (ha, hb) = (a.half_length, b.half_length);
    let clamp = |x: T, h: T| {
        if x < -h {
            -h
        } else if x > h {
            h
        } else {
            x
        }
    };
    let dist2 = |m: T, n: T| (delta + b.axis * n - a.axis * m).norm_squared();
    let parallel = det <= eps;
    let (m, n, kind) = 'found: {
        if !parallel {
            // Solve H h = k (E.2.3) in closed form.
            let (m, n) = ((k1 + c * k2) / det, (k2 + c * k1) / det);
            if m >= -ha && m <= ha && n >= -hb && n <= hb {
                break 'found (m, n, ClosestKind::Interior);
            }
        }
        // The distance is convex in (m, n): outside the interior solution its minimum over
        // the rectangle of segment coordinates lies on an edge, where it is the clamped
        // projection of the fixed end onto the other axis.
        let candidates = [
            (-ha, clamp(k2 - c * ha, hb)),
            (ha, clamp(k2 + c * ha, hb)),
            (clamp(k1 - c * hb, ha), -hb),
            (clamp(k1 + c * hb, ha), hb),
        ];
        let mut best = candidates[0];
        for cand in &candidates[1..] {
            if dist2(cand.0, cand.1) < dist2(best.0, best.1) {
                best = *cand;
            }
        }
        if !parallel {
            break 'found (best.0, best.1, ClosestKind::Clamped);
        }
        // Parallel: n = k2 + c m keeps the distance (nearly) constant over the overlap of
        // the two segments; prefer the midpoint of the overlap when it is as close.
        let (lo_b, hi_b) = ((-hb - k2) * c, (hb - k2) * c);
        let (lo_b, hi_b) = if lo_b < hi_b {
            (lo_b, hi_b)
        } else {
            (hi_b, lo_b)
        };
        let lo = if lo_b > -ha { lo_b } else { -ha };
        let hi = if hi_b < ha { hi_b } else { ha };
        if lo > hi {
            break 'found (best.0, best.1, ClosestKind::Clamped);
        }
        let two: T = nalgebra::convert(2.0);
        let mid = (lo + hi) / two;
        let mid_n = clamp(k2 + c * mid, hb);
        let slack: T = nalgebra::convert(1e-13);
        if dist2(mid, mid_n) <= dist2(best.0, best.1) * (T::one() + slack) + slack * slack {
            (mid, mid_n, ClosestKind::Parallel)
        } else {
            (best.0, best.1, ClosestKind::Parallel)
        }
    };
    let w = delta + b.axis * n - a.axis * m;
    let distance = w.norm();
    let tiny: T = nalgebra::convert(1e-300);
    let u = if distance > tiny {
        w / distance
    } else {
        any_normal(&a.axis, &b.axis)
    };
    ClosestPoints {
        m,
        n,
        distance,
        u,
        pi_p3: a.axis * m + u * a.radius,
        pi_p4: b.axis * n - u * b.radius,
        gap: distance - (a.radius + b.radius),
        kind,
    }
}

/// A unit vector normal to both axes (their cross product), or to the first one when
/// they are parallel.
fn any_normal<T: RealField + Copy>(a: &Vector3<T>, b: &Vector3<T>) -> Vector3<T> {
    let n = a.cross(b);
    let eps: T = nalgebra::convert(1e-12);
    if n.norm() > eps {
        return n.normalize();
    }
    let trial = if a.x.abs() < nalgebra::convert(0.9) {
        Vector3::x()
    } else {
        Vector3::y()
    };
    a.cross(&trial).normalize()
}

/// The angle χ of u in the cross-section of a cylinder, u = cos χ e1 + sin χ e2, (E.2.9).
#[must_use]
pub fn rim_angle<T: RealField + Copy>(u: &Vector3<T>, e1: &Vector3<T>, e2: &Vector3<T>) -> T {
    u.dot(e2).atan2(u.dot(e1))
}

/// The gap of a cylinder–ground contact, (E.3.1)₁,₂: (x̄ + π_P) · E3.
#[must_use]
pub fn ground_gap<T: RealField + Copy>(center: &Vector3<T>, pi_p: &Vector3<T>) -> T {
    center.z + pi_p.z
}

/// The motion of one axis at an instant: what (E.2.5) needs.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct AxisMotion {
    /// x̄.
    pub center: Vector3<f64>,
    /// x̄̇.
    pub velocity: Vector3<f64>,
    /// x̄̈.
    pub acceleration: Vector3<f64>,
    /// e3 (unit).
    pub axis: Vector3<f64>,
    /// ω.
    pub angular_velocity: Vector3<f64>,
    /// ω̇.
    pub angular_acceleration: Vector3<f64>,
}

impl AxisMotion {
    /// ė3 = ω × e3 and ë3 = ω̇ × e3 + ω × (ω × e3).
    fn axis_rates(&self) -> (Vector3<f64>, Vector3<f64>) {
        let d1 = self.angular_velocity.cross(&self.axis);
        (
            d1,
            self.angular_acceleration.cross(&self.axis) + self.angular_velocity.cross(&d1),
        )
    }
}

/// h = (m*, n*) and its first and second time derivatives, (E.2.3) and (E.2.5).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ClosestPointRates {
    /// (m*, n*) of the infinite axes (not clamped).
    pub h: Vector2<f64>,
    /// ḣ = H⁻¹(k̇ − Ḣ h).
    pub h_dot: Vector2<f64>,
    /// ḧ = H⁻¹(k̈ − Ḧ h − 2 Ḣ ḣ).
    pub h_ddot: Vector2<f64>,
}

/// The rates (E.2.5) of the closest points of the two (infinite) axes.
///
/// # Errors
/// [`CylinderError::ParallelAxes`] when 1 − c² ≤ 1e-12: H is singular and the closest
/// points move along a line of contact; [`CylinderError::Input`] for NaN input.
pub fn closest_point_rates(
    a: &AxisMotion,
    b: &AxisMotion,
) -> Result<ClosestPointRates, CylinderError> {
    for m in [a, b] {
        let all = [
            m.center,
            m.velocity,
            m.acceleration,
            m.axis,
            m.angular_velocity,
            m.angular_acceleration,
        ];
        if all.iter().any(|v| v.iter().any(|x| !x.is_finite())) {
            return Err(InputError::NonFinite("axis motion".into()).into());
        }
    }
    let (ea, eb) = (a.axis, b.axis);
    let ((ea1, ea2), (eb1, eb2)) = (a.axis_rates(), b.axis_rates());
    let c = ea.dot(&eb);
    if 1.0 - c * c <= 1e-12 {
        return Err(CylinderError::ParallelAxes(c.abs()));
    }
    let c1 = ea1.dot(&eb) + ea.dot(&eb1);
    let c2 = ea2.dot(&eb) + 2.0 * ea1.dot(&eb1) + ea.dot(&eb2);
    let (d0, d1, d2) = (
        b.center - a.center,
        b.velocity - a.velocity,
        b.acceleration - a.acceleration,
    );
    // k = (Δ · e3_I, −Δ · e3_II) and its derivatives, Δ = x̄_II − x̄_I.
    let k = Vector2::new(d0.dot(&ea), -d0.dot(&eb));
    let k1 = Vector2::new(d1.dot(&ea) + d0.dot(&ea1), -(d1.dot(&eb) + d0.dot(&eb1)));
    let k2 = Vector2::new(
        d2.dot(&ea) + 2.0 * d1.dot(&ea1) + d0.dot(&ea2),
        -(d2.dot(&eb) + 2.0 * d1.dot(&eb1) + d0.dot(&eb2)),
    );
    let hm = Matrix2::new(1.0, -c, -c, 1.0);
    let h1m = Matrix2::new(0.0, -c1, -c1, 0.0);
    let h2m = Matrix2::new(0.0, -c2, -c2, 0.0);
    let inv = hm
        .try_inverse()
        .ok_or(CylinderError::ParallelAxes(c.abs()))?;
    let h = inv * k;
    let h_dot = inv * (k1 - h1m * h);
    let h_ddot = inv * (k2 - h2m * h - 2.0 * h1m * h_dot);
    Ok(ClosestPointRates { h, h_dot, h_ddot })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn seg(center: [f64; 3], axis: [f64; 3], half: f64, r: f64) -> AxisSegment<f64> {
        AxisSegment {
            center: Vector3::from(center),
            axis: Vector3::from(axis).normalize(),
            half_length: half,
            radius: r,
        }
    }

    #[test]
    fn crossing_axes() {
        let a = seg([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], 1.0, 0.1);
        let b = seg([0.3, -0.2, 0.5], [0.0, 1.0, 0.0], 1.0, 0.2);
        let cp = closest_points(&a, &b);
        assert_eq!(cp.kind, ClosestKind::Interior);
        assert!((cp.m - 0.3).abs() < 1e-15 && (cp.n - 0.2).abs() < 1e-15);
        assert!((cp.distance - 0.5).abs() < 1e-15);
        assert!((cp.gap - 0.2).abs() < 1e-15);
        assert!((cp.u - Vector3::z()).norm() < 1e-15);
        // The contact points are on the surfaces: x3 − x4 = (r1 + r2 − d) u.
        let x3 = a.center + cp.pi_p3;
        let x4 = b.center + cp.pi_p4;
        assert!(((x4 - x3) - cp.u * cp.gap).norm() < 1e-15);
    }

    #[test]
    fn parallel_and_nearly_parallel() {
        let a = seg([0.0, 0.0, 0.0], [0.0, 0.0, 1.0], 1.0, 0.5);
        let b = seg([1.0, 0.0, 0.4], [0.0, 0.0, 1.0], 1.0, 0.5);
        let cp = closest_points(&a, &b);
        assert_eq!(cp.kind, ClosestKind::Parallel);
        assert!(cp.gap.abs() < 1e-15);
        assert!((cp.m - 0.2).abs() < 1e-15 && (cp.n + 0.2).abs() < 1e-15);
        // Anti-parallel.
        let b2 = seg([1.0, 0.0, 0.4], [0.0, 0.0, -1.0], 1.0, 0.5);
        let cp2 = closest_points(&a, &b2);
        assert_eq!(cp2.kind, ClosestKind::Parallel);
        assert!(cp2.gap.abs() < 1e-15);
        // Nearly parallel: continuous with the parallel answer.
        for tilt in [1e-4, 1e-7, 1e-9] {
            let b3 = seg([1.0, 0.0, 0.4], [tilt, 0.0, 1.0], 1.0, 0.5);
            let cp3 = closest_points(&a, &b3);
            assert!(cp3.gap.abs() < 2.0 * tilt, "{tilt}: {:?}", cp3.gap);
            assert!(cp3.m.is_finite() && cp3.n.is_finite());
            assert!(cp3.m.abs() <= 1.0 && cp3.n.abs() <= 1.0);
        }
        // Parallel and not overlapping: end to end.
        let b4 = seg([0.0, 0.0, 3.0], [0.0, 0.0, 1.0], 1.0, 0.5);
        let cp4 = closest_points(&a, &b4);
        assert_eq!(cp4.kind, ClosestKind::Clamped);
        assert!((cp4.distance - 1.0).abs() < 1e-15);
    }

    #[test]
    fn clamped_ends() {
        let a = seg([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], 1.0, 0.1);
        let b = seg([3.0, 0.0, 1.0], [0.0, 1.0, 0.0], 1.0, 0.1);
        let cp = closest_points(&a, &b);
        assert_eq!(cp.kind, ClosestKind::Clamped);
        assert!((cp.m - 1.0).abs() < 1e-15 && cp.n.abs() < 1e-15);
        assert!((cp.distance - 5f64.sqrt()).abs() < 1e-15);
    }
}
