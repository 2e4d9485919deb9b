//! Kinematic rolling of a sphere along a closed path of its centre, by integrating the
//! rolling constraint (2.3.4)–(2.3.5) in time.
//!
//! The centre moves at unit speed along a path of straight segments and circular arcs
//! (any polygon, a circle, a rectangle of §2.4), so the time is the arc length s. With the
//! sphere's radius R and the unit tangent d(s) of the path, the rolling constraint
//! v̄ = ω × R E3 with ω · E3 = 0 (no spin) gives the spatial angular velocity
//!
//! ω(s) = (1/R) E3 × d(s),   Q′(s) = skewt(ω) Q,   Q(0) = I.
//!
//! Two integrators:
//!
//! - [`Integrator::Exact`]: the exact flow of each segment, a Lie-group exponential. On
//!   a line ω is constant: Q ← exp(h ω) Q. On an arc of signed curvature κ (heading
//!   rate), ω(s) = R(κ s, E3) ω(0), and in the frame turning with the heading the
//!   angular velocity ω(0) − κ E3 is constant, so
//!   Q(s + h) = R(κ(s + h), E3) exp(h (ω(0) − κ E3)) R(−κ s, E3) Q(s).
//!   Each sample is the flow from the segment's start, so the result does not depend on
//!   the number of steps (only the output resolution) and round-off does not build up.
//! - [`Integrator::Rk4`]: the classical Runge–Kutta method on the unit quaternion,
//!   q′ = ½ (0, ω) ∘ q, renormalised after each step: a generic scheme, 4th order.
//!
//! Steps never straddle a corner: each segment gets its share of the steps by length.
//! The material point X that touched the plane at s = 0 is tracked as x = x̄ − R Q E3
//! (2.3.1), its trace is the curve ii of Figure 2.1.

use crate::rectangle::{Direction, Rectangle};
use crate::HolonomyError;
use nalgebra::{Quaternion, Rotation3, Unit, UnitQuaternion, Vector3};
use serde::{Deserialize, Serialize};
use std::f64::consts::TAU;

/// A piece of the centre's path, in the ground plane (E1, E2 components, length units).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum Segment {
    /// A straight segment.
    Line {
        /// Start point.
        from: [f64; 2],
        /// End point.
        to: [f64; 2],
    },
    /// A circular arc.
    Arc {
        /// Centre of the circle.
        center: [f64; 2],
        /// Radius of the circle (> 0).
        radius: f64,
        /// Polar angle of the start point about the centre, radians.
        start_angle: f64,
        /// Signed swept angle: > 0 counter-clockwise, radians.
        sweep: f64,
    },
}

impl Segment {
    /// Arc length.
    #[must_use]
    pub fn length(&self) -> f64 {
        match *self {
            Self::Line { from, to } => (to[0] - from[0]).hypot(to[1] - from[1]),
            Self::Arc { radius, sweep, .. } => radius * sweep.abs(),
        }
    }

    /// Position and unit tangent at arc length `s` from the segment's start.
    #[must_use]
    pub fn point_and_tangent(&self, s: f64) -> ([f64; 2], Vector3<f64>) {
        match *self {
            Self::Line { from, to } => {
                let l = self.length();
                let d = Vector3::new((to[0] - from[0]) / l, (to[1] - from[1]) / l, 0.0);
                ([from[0] + s * d.x, from[1] + s * d.y], d)
            }
            Self::Arc {
                center,
                radius,
                start_angle,
                sweep,
            } => {
                let sign = sweep.signum();
                let a = start_angle + sign * s / radius;
                let (sa, ca) = a.sin_cos();
                (
                    [center[0] + radius * ca, center[1] + radius * sa],
                    Vector3::new(-sign * sa, sign * ca, 0.0),
                )
            }
        }
    }

    /// Signed curvature: the rate of turn of the tangent per unit length (0 on a line).
    #[must_use]
    pub fn curvature(&self) -> f64 {
        match *self {
            Self::Line { .. } => 0.0,
            Self::Arc { radius, sweep, .. } => sweep.signum() / radius,
        }
    }
}

/// A closed path of the centre: segments joined end to end.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CentrePath {
    segments: Vec<Segment>,
}

impl CentrePath {
    /// A closed polygon through `vertices` (the last is joined back to the first; a
    /// repeated first vertex at the end is allowed). Zero-length edges are dropped.
    ///
    /// # Errors
    /// Non-finite coordinates, or fewer than two distinct vertices.
    pub fn polygon(vertices: &[[f64; 2]]) -> Result<Self, HolonomyError> {
        if vertices.iter().flatten().any(|v| !v.is_finite()) {
            return Err(HolonomyError::Input(input::InputError::NonFinite(
                "polygon vertex".into(),
            )));
        }
        let n = vertices.len();
        let segments: Vec<Segment> = (0..n)
            .map(|i| Segment::Line {
                from: vertices[i],
                to: vertices[(i + 1) % n],
            })
            .filter(|s| s.length() > 0.0)
            .collect();
        if segments.len() < 2 {
            return Err(HolonomyError::InvalidPath(
                "a polygon needs at least two distinct vertices".into(),
            ));
        }
        Ok(Self { segments })
    }

    /// A circle of radius `radius` through the origin, starting there along +E1 and
    /// turning left (counter-clockwise) or right (clockwise).
    ///
    /// # Errors
    /// A radius that is not finite and positive.
    pub fn circle(radius: f64, direction: Direction) -> Result<Self, HolonomyError> {
        input::positive("circle radius", radius)?;
        let (cy, start, sweep) = match direction {
            Direction::Ccw => (radius, -0.5 * std::f64::consts::PI, TAU),
            Direction::Cw => (-radius, 0.5 * std::f64::consts::PI, -TAU),
        };
        Ok(Self {
            segments: vec![Segment::Arc {
                center: [0.0, cy],
                radius,
                start_angle: start,
                sweep,
            }],
        })
    }

    /// The rectangle of §2.4 for a sphere of radius `sphere_radius`, starting at the
    /// origin (Figure 2.3): its waypoints scaled by R. Degenerate sides are dropped.
    ///
    /// # Errors
    /// A non-positive radius, or a rectangle with fewer than two non-zero sides.
    pub fn rectangle(rect: &Rectangle, sphere_radius: f64) -> Result<Self, HolonomyError> {
        check_radius(sphere_radius)?;
        let w: Vec<[f64; 2]> = rect
            .waypoints()
            .iter()
            .map(|p| [p[0] * sphere_radius, p[1] * sphere_radius])
            .collect();
        Self::polygon(&w)
    }

    /// The segments, in order.
    #[must_use]
    pub fn segments(&self) -> &[Segment] {
        &self.segments
    }

    /// Total length.
    #[must_use]
    pub fn length(&self) -> f64 {
        self.segments.iter().map(Segment::length).sum()
    }
}

fn check_radius(r: f64) -> Result<(), HolonomyError> {
    input::positive("sphere radius", r)?;
    Ok(())
}

/// How to integrate the rolling constraint.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Integrator {
    /// Exact flow per segment (Lie-group exponential).
    Exact,
    /// Classical RK4 on the unit quaternion, renormalised each step.
    Rk4,
}

impl Integrator {
    /// `"exact"` or `"rk4"`, as in the CLI's JSON.
    #[must_use]
    pub fn as_str(self) -> &'static str {
        match self {
            Self::Exact => "exact",
            Self::Rk4 => "rk4",
        }
    }
}

/// One sample of a rolling motion.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RollSample {
    /// Time = arc length travelled (unit speed).
    pub s: f64,
    /// Position of the centre C (E1, E2, E3 components; height R).
    pub centre: [f64; 3],
    /// Position of the material point X that was the contact point at s = 0.
    pub marked_point: [f64; 3],
    /// Orientation Q(s) as a unit quaternion (Q(0) = I).
    pub orientation: UnitQuaternion<f64>,
}

impl RollSample {
    /// The columns of a trajectory CSV (roll.csv): the arc length s, the centre C, the
    /// marked point X (E1, E2, E3 components; units of R) and the orientation Q as a
    /// quaternion [q0, q1, q2, q3] (scalar first).
    pub const CSV_HEADER: [&'static str; 11] = [
        "s", "cx", "cy", "cz", "xx", "xy", "xz", "q0", "q1", "q2", "q3",
    ];

    /// The cells of this sample's row under [`Self::CSV_HEADER`], numbers in shortest
    /// round-trip form.
    #[must_use]
    pub fn csv_cells(&self) -> Vec<String> {
        let q = self.orientation;
        std::iter::once(self.s)
            .chain(self.centre)
            .chain(self.marked_point)
            .chain([q.w, q.i, q.j, q.k])
            .map(|v| v.to_string())
            .collect()
    }
}

/// The result of [`roll`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Trajectory {
    /// Samples at s = 0 and after every step.
    pub samples: Vec<RollSample>,
}

impl Trajectory {
    /// The final orientation Q(L): the holonomy of the closed path.
    #[must_use]
    pub fn final_orientation(&self) -> UnitQuaternion<f64> {
        self.samples
            .last()
            .map_or_else(UnitQuaternion::identity, |s| s.orientation)
    }
}

/// The most steps [`roll`] takes: each keeps a sample of about 100 bytes, so a million
/// steps is about 100 MB, far more than any plot or error study needs.
pub const MAX_ROLL_STEPS: usize = 1_000_000;

/// The longest path [`roll`] accepts, in sphere radii: beyond it the rolled angle s/R
/// is so large that its rounding error exceeds a full turn (and squared coordinates
/// overflow long before 1e300).
pub const MAX_PATH_LENGTH: f64 = 1e9;

/// Rolls a sphere of radius `sphere_radius` once along `path` with about `steps` steps
/// (each segment gets at least one, in proportion to its length).
///
/// # Errors
/// A non-positive radius, `steps` smaller than the number of segments or above
/// [`MAX_ROLL_STEPS`], a path longer than [`MAX_PATH_LENGTH`] radii.
pub fn roll(
    path: &CentrePath,
    sphere_radius: f64,
    integrator: Integrator,
    steps: usize,
) -> Result<Trajectory, HolonomyError> {
    check_radius(sphere_radius)?;
    let n_seg = path.segments.len();
    if steps < n_seg {
        return Err(HolonomyError::TooFewSteps {
            steps,
            minimum: n_seg,
        });
    }
    if steps > MAX_ROLL_STEPS {
        return Err(input::InputError::OutOfRange {
            name: "steps".into(),
            range: "[1, 1000000]",
            value: steps as f64,
        }
        .into());
    }
    let total = path.length();
    if total.is_nan() || total > MAX_PATH_LENGTH * sphere_radius {
        return Err(HolonomyError::InvalidPath(format!(
            "the path is {total:e} long, more than {MAX_PATH_LENGTH:e} sphere radii: its rolled angle would lose every digit of the orientation"
        )));
    }
    let mut q = UnitQuaternion::identity();
    let mut s_total = 0.0;
    let start = path.segments[0].point_and_tangent(0.0).0;
    let mut samples = Vec::with_capacity(steps + n_seg + 1);
    samples.push(sample(0.0, start, &q, sphere_radius));
    for seg in &path.segments {
        let q_start = q;
        let len = seg.length();
        #[allow(
            clippy::cast_possible_truncation,
            clippy::cast_sign_loss,
            clippy::cast_precision_loss
        )]
        let n = ((steps as f64 * len / total).round() as usize).max(1);
        #[allow(clippy::cast_precision_loss)]
        let h = len / n as f64;
        for i in 0..n {
            #[allow(clippy::cast_precision_loss)]
            let s0 = i as f64 * h;
            q = match integrator {
                // The flow from the segment's start, not step by step: no round-off build-up.
                Integrator::Exact => exact_step(seg, sphere_radius, 0.0, s0 + h) * q_start,
                Integrator::Rk4 => rk4_step(seg, sphere_radius, s0, h, &q),
            };
            #[allow(clippy::cast_precision_loss)]
            let s1 = (i + 1) as f64 * h;
            samples.push(sample(
                s_total + s1,
                seg.point_and_tangent(s1).0,
                &q,
                sphere_radius,
            ));
        }
        s_total += len;
    }
    Ok(Trajectory { samples })
}

fn sample(s: f64, p: [f64; 2], q: &UnitQuaternion<f64>, radius: f64) -> RollSample {
    let centre = Vector3::new(p[0], p[1], radius);
    let x = centre - radius * (q * Vector3::z());
    RollSample {
        s,
        centre: centre.into(),
        marked_point: x.into(),
        orientation: *q,
    }
}

/// The spatial angular velocity (1/R) E3 × d of rolling without spin along tangent d.
fn omega(tangent: &Vector3<f64>, radius: f64) -> Vector3<f64> {
    Vector3::z().cross(tangent) / radius
}

/// exp(h ω) as a unit quaternion (rotation by |hω| about ω).
fn exp_step(w: &Vector3<f64>) -> UnitQuaternion<f64> {
    UnitQuaternion::from_scaled_axis(*w)
}

/// The exact flow over [s0, s0 + h] on one segment (module documentation).
fn exact_step(seg: &Segment, radius: f64, s0: f64, h: f64) -> UnitQuaternion<f64> {
    let kappa = seg.curvature();
    let (_, d0) = seg.point_and_tangent(0.0);
    let w0 = omega(&d0, radius);
    if kappa == 0.0 {
        return exp_step(&(h * w0));
    }
    let z = Vector3::z_axis();
    let turn = |a: f64| UnitQuaternion::from_axis_angle(&z, a);
    turn(kappa * (s0 + h)) * exp_step(&(h * (w0 - kappa * Vector3::z()))) * turn(-kappa * s0)
}

/// One RK4 step of q′ = ½ (0, ω(s)) ∘ q.
fn rk4_step(
    seg: &Segment,
    radius: f64,
    s0: f64,
    h: f64,
    q: &UnitQuaternion<f64>,
) -> UnitQuaternion<f64> {
    let f = |s: f64, q: &Quaternion<f64>| {
        let w = omega(&seg.point_and_tangent(s).1, radius);
        Quaternion::from_parts(0.0, w) * q * 0.5
    };
    let y = q.into_inner();
    let k1 = f(s0, &y);
    let k2 = f(s0 + 0.5 * h, &(y + k1 * (0.5 * h)));
    let k3 = f(s0 + 0.5 * h, &(y + k2 * (0.5 * h)));
    let k4 = f(s0 + h, &(y + k3 * h));
    UnitQuaternion::new_normalize(y + (k1 + k2 * 2.0 + k3 * 2.0 + k4) * (h / 6.0))
}

/// The holonomy of rolling once around a circle of radius ρ (`circle_radius`) as in
/// [`CentrePath::circle`], in closed form: in the frame turning with the heading the
/// angular velocity (1/R) E2 ∓ (1/ρ) E3 is constant, and the frame has turned by ±2π
/// at the end, so S = exp(2πρ ((1/R) E2 ∓ (1/ρ) E3)): a rotation by
/// 2π √(1 + ρ²/R²) about (ρ/R) E2 ∓ E3 (− counter-clockwise, + clockwise).
///
/// # Errors
/// Non-positive or non-finite radii.
pub fn circle_holonomy(
    circle_radius: f64,
    sphere_radius: f64,
    direction: Direction,
) -> Result<Rotation3<f64>, HolonomyError> {
    check_radius(sphere_radius)?;
    CentrePath::circle(circle_radius, direction)?;
    let sign = match direction {
        Direction::Ccw => -1.0,
        Direction::Cw => 1.0,
    };
    let w = Vector3::new(0.0, 1.0 / sphere_radius, sign / circle_radius);
    Ok(Rotation3::from_scaled_axis(TAU * circle_radius * w))
}

/// The holonomy of rolling once around a closed polygon, in closed form: the product of
/// the rotations of its sides in the order of travel, a side of length L along the
/// horizontal unit vector d turning the sphere by L/R about E3 × d ((2.3.4)–(2.3.5)),
/// S = R(Lₙ/R, E3 × dₙ) ⋯ R(L₁/R, E3 × d₁).
///
/// # Errors
/// A non-positive or non-finite sphere radius, or a path with a circular arc
/// ([`HolonomyError::InvalidPath`]): on an arc the axis turns and the product does not
/// apply (see [`circle_holonomy`]).
pub fn polygon_holonomy(
    path: &CentrePath,
    sphere_radius: f64,
) -> Result<Rotation3<f64>, HolonomyError> {
    check_radius(sphere_radius)?;
    let mut q = UnitQuaternion::identity();
    for seg in path.segments() {
        if let Segment::Arc { .. } = seg {
            return Err(HolonomyError::InvalidPath(
                "the polygon holonomy needs straight sides, not arcs".into(),
            ));
        }
        let (_, d) = seg.point_and_tangent(0.0);
        q = UnitQuaternion::from_axis_angle(
            &Unit::new_normalize(Vector3::z().cross(&d)),
            seg.length() / sphere_radius,
        ) * q;
    }
    Ok(q.to_rotation_matrix())
}

/// The unit axis and angle in [0, π] of a quaternion, for reporting.
#[must_use]
pub fn axis_angle(q: &UnitQuaternion<f64>) -> (f64, Unit<Vector3<f64>>) {
    let aa = rotations::AxisAngle::from_quaternion(q);
    (aa.angle, aa.axis)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_path_too_long_to_roll_accurately_is_refused() {
        let path = CentrePath::circle(1e300, Direction::Ccw).unwrap();
        let err = roll(&path, 1.0, Integrator::Exact, 100).unwrap_err();
        assert!(err.to_string().contains("sphere radii"), "{err}");
        let path = CentrePath::circle(1e6, Direction::Ccw).unwrap();
        let traj = roll(&path, 1.0, Integrator::Exact, 100).unwrap();
        assert!(traj
            .samples
            .iter()
            .all(|s| s.centre.iter().all(|c| c.is_finite())));
    }

    #[test]
    fn more_steps_than_memory_allows_are_refused() {
        let path = CentrePath::circle(1.0, Direction::Ccw).unwrap();
        let err = roll(&path, 1.0, Integrator::Exact, MAX_ROLL_STEPS + 1).unwrap_err();
        assert!(
            err.to_string().contains("steps must lie in [1, 1000000]"),
            "{err}"
        );
    }

    #[test]
    fn a_sample_has_one_cell_per_column() {
        let path = CentrePath::circle(1.0, Direction::Ccw).unwrap();
        let traj = roll(&path, 1.0, Integrator::Exact, 8).unwrap();
        let first = traj.samples[0].csv_cells();
        assert_eq!(first.len(), RollSample::CSV_HEADER.len());
        // s = 0, the centre at height R, Q(0) = I.
        assert_eq!(first[0], "0");
        assert_eq!(first[3], "1");
        assert_eq!(&first[7..], ["1", "0", "0", "0"]);
        let last = traj.samples.last().unwrap();
        assert_eq!(last.csv_cells()[7], last.orientation.w.to_string());
    }
}
