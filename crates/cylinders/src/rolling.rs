//! Kinematic rolling along a path: integrate the orientation and the centre of mass of a
//! cylinder that rolls without slipping (v_P = 0, (3.2.2)) under a prescribed schedule
//! of precession and spin rates, and record the traces of P and of a rim point X
//! (Figures 3.9(b), 3.10 and 3.12).
//!
//! The integration does not use the Euler-angle closed forms: it advances the unit
//! quaternion of Q with the spatial angular velocity ω = ψ̇ E3 + φ̇ e3 (ϑ̇ = 0, (A.2.1))
//! and the centre with x̄̇ = −ω × π_P (3.2.3), π_P found from the current axis
//! ([`contact_offset_from_axis`]), by the classical fourth-order Runge–Kutta method
//! (the quaternion renormalised each step). The holonomy it produces is therefore an
//! independent check of §3.4.

use crate::error::CylinderError;
use crate::holonomy::{CirclePath, Motion, RectanglePath};
use crate::kinematics::{
    check_point_contact, contact_offset_from_axis, rolling_matrix, three_one_three, Cylinder, Pose,
};
use input::{finite, non_negative, positive, InputError};
use nalgebra::{Quaternion, Rotation3, UnitQuaternion, Vector3, Vector6};
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// A stretch of constant rates: precession ψ̇ and spin φ̇ (rad per unit time), ϑ̇ = 0.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Segment {
    /// Duration (≥ 0).
    pub duration: f64,
    /// ψ̇.
    pub psi_rate: f64,
    /// φ̇.
    pub phi_rate: f64,
}

impl Segment {
    /// The segment that performs one [`Motion`] at unit rate.
    #[must_use]
    pub fn from_motion(motion: Motion) -> Self {
        match motion {
            Motion::Roll(x) => Self {
                duration: x.abs(),
                psi_rate: 0.0,
                phi_rate: x.signum(),
            },
            Motion::Pivot(x) => Self {
                duration: x.abs(),
                psi_rate: x.signum(),
                phi_rate: 0.0,
            },
        }
    }
}

/// One recorded sample of a rolling motion.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Sample {
    /// Time.
    pub t: f64,
    /// Centre of mass x̄.
    pub center: Vector3<f64>,
    /// Contact point P = x̄ + π_P.
    pub contact: Vector3<f64>,
    /// The material rim point X that was at P at t = 0.
    pub rim_point: Vector3<f64>,
    /// The spin φ read from Q by the 3-1-3 set, unwrapped along the motion.
    pub phi: f64,
}

impl Sample {
    /// The columns of a rolling trace's CSV (rectangle_trace.csv, circle_trace.csv): the
    /// time t, the centre of mass x̄ (E1, E2, E3), the contact point P (E1, E2; it lies on
    /// the plane), the rim point X (E1, E2, E3) and the spin φ (rad).
    pub const CSV_HEADER: [&'static str; 10] = [
        "t", "center_x", "center_y", "center_z", "p_x", "p_y", "x_x", "x_y", "x_z", "phi",
    ];

    /// The cells of this sample's row under [`Self::CSV_HEADER`], numbers in shortest
    /// round-trip form.
    #[must_use]
    pub fn csv_cells(&self) -> Vec<String> {
        let (c, p, x) = (self.center, self.contact, self.rim_point);
        [self.t, c.x, c.y, c.z, p.x, p.y, x.x, x.y, x.z, self.phi]
            .iter()
            .map(f64::to_string)
            .collect()
    }
}

/// The result of [`roll`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RollingTrace {
    /// Samples, the first at t = 0 and the last at the end.
    pub samples: Vec<Sample>,
    /// The net rotation Q_end Q_0ᵀ (the holonomy when the path closes).
    pub net_rotation: Rotation3<f64>,
    /// The initial pose.
    pub initial: Pose,
    /// max ‖W q̇‖ over all steps, W of (3.2.5)/(D.1.4) evaluated at the Euler angles read
    /// from the integrated Q (round-off when the motion rolls without slipping).
    pub max_residual: f64,
}

impl RollingTrace {
    /// The spin change φ_end − φ_0 measured on the integrated orientation (unwrapped).
    #[must_use]
    pub fn delta_phi(&self) -> f64 {
        match (self.samples.first(), self.samples.last()) {
            (Some(a), Some(b)) => b.phi - a.phi,
            _ => 0.0,
        }
    }

    /// Whether every sample (time, centre, contact, rim point, spin) is finite.
    #[must_use]
    pub fn is_finite(&self) -> bool {
        self.samples.iter().all(|s| {
            s.t.is_finite()
                && s.phi.is_finite()
                && [s.center, s.contact, s.rim_point]
                    .iter()
                    .all(|v| v.iter().all(|x| x.is_finite()))
        })
    }

    /// ‖x̄_end − x̄_0‖: zero when the centre returns.
    #[must_use]
    pub fn closure_error(&self) -> f64 {
        match (self.samples.first(), self.samples.last()) {
            (Some(a), Some(b)) => (b.center - a.center).norm(),
            _ => 0.0,
        }
    }
}

/// The state advanced by the integrator: orientation quaternion and centre of mass.
#[derive(Debug, Clone, Copy)]
struct State {
    q: Quaternion<f64>,
    x: Vector3<f64>,
}

/// Time derivative of the state for rates (ψ̇, φ̇): q̇ = ½ (0, ω) q, x̄̇ = −ω × π_P.
fn rate(
    cylinder: &Cylinder,
    s: &State,
    psi_rate: f64,
    phi_rate: f64,
) -> (Quaternion<f64>, Vector3<f64>, Vector3<f64>) {
    let unit = UnitQuaternion::new_normalize(s.q);
    let e3 = unit * Vector3::z();
    let omega = Vector3::z() * psi_rate + e3 * phi_rate;
    let qdot = Quaternion::from_parts(0.0, omega) * s.q * 0.5;
    let xdot = -omega.cross(&contact_offset_from_axis(cylinder, &e3));
    (qdot, xdot, omega)
}

fn sample(
    cylinder: &Cylinder,
    s: &State,
    q0: &UnitQuaternion<f64>,
    pi0: &Vector3<f64>,
    t: f64,
    phi: f64,
) -> Sample {
    let unit = UnitQuaternion::new_normalize(s.q);
    let e3 = unit * Vector3::z();
    Sample {
        t,
        center: s.x,
        contact: s.x + contact_offset_from_axis(cylinder, &e3),
        rim_point: s.x + (unit * q0.inverse()) * pi0,
        phi,
    }
}

/// The most RK4 steps one rolled path may take (about ten seconds on one core; the
/// recorded samples stay below a few hundred MB).
pub const MAX_ROLL_STEPS: f64 = 1e7;

/// Rolls the cylinder from `initial` through the `segments`, with steps that turn the
/// cylinder by at most `max_angle_step` radians (|ψ̇| + |φ̇| times the time step), and
/// records a sample every `record_every` steps plus the last one.
///
/// # Errors
/// When ϑ of the initial pose is outside (0, π/2), a segment has a negative or
/// non-finite duration or rate, or `max_angle_step` is not positive.
pub fn roll(
    cylinder: &Cylinder,
    initial: &Pose,
    segments: &[Segment],
    max_angle_step: f64,
    record_every: usize,
) -> Result<RollingTrace, CylinderError> {
    check_point_contact(initial.angles[1])?;
    positive("max_angle_step", max_angle_step)?;
    let turned: f64 = segments
        .iter()
        .map(|s| s.duration.abs() * (s.psi_rate.abs() + s.phi_rate.abs()))
        .sum();
    let needed = turned / max_angle_step;
    if needed > MAX_ROLL_STEPS {
        return Err(InputError::TooLarge {
            name: "max_step".into(),
            value: max_angle_step,
            needed,
            what: "integration steps",
            limit: MAX_ROLL_STEPS,
        }
        .into());
    }
    let q0 = UnitQuaternion::from_rotation_matrix(&initial.rotation());
    let pi0 = contact_offset_from_axis(cylinder, &(q0 * Vector3::z()));
    let mut state = State {
        q: *q0.quaternion(),
        x: initial.position,
    };
    let set = three_one_three();
    let mut phi = initial.angles[2];
    let mut t = 0.0;
    let mut samples = vec![sample(cylinder, &state, &q0, &pi0, t, phi)];
    let mut max_residual = 0.0_f64;
    let mut step_count = 0usize;
    let record_every = record_every.max(1);
    for seg in segments {
        finite("segment rate", seg.psi_rate)?;
        finite("segment rate", seg.phi_rate)?;
        non_negative("segment duration", seg.duration)?;
        let angle = seg.duration * (seg.psi_rate.abs() + seg.phi_rate.abs());
        let n = (angle / max_angle_step).ceil().max(1.0) as usize;
        let dt = seg.duration / n as f64;
        for _ in 0..n {
            state = rk4_step(cylinder, &state, seg, dt);
            t += dt;
            step_count += 1;
            // Unwrap φ: the increment read from Q is brought into (−π, π].
            let unit = UnitQuaternion::new_normalize(state.q);
            let angles = set.angles(&unit.to_rotation_matrix());
            phi += wrap(angles[2] - phi);
            // Check the printed constraints (3.2.5) on the integrated state.
            let (_, xdot, _) = rate(cylinder, &state, seg.psi_rate, seg.phi_rate);
            let w = rolling_matrix(cylinder, angles[0], angles[1]);
            let qdot = Vector6::new(xdot.x, xdot.y, xdot.z, seg.psi_rate, 0.0, seg.phi_rate);
            max_residual = max_residual.max((w * qdot).norm());
            if step_count.is_multiple_of(record_every) {
                samples.push(sample(cylinder, &state, &q0, &pi0, t, phi));
            }
        }
    }
    if !step_count.is_multiple_of(record_every) {
        samples.push(sample(cylinder, &state, &q0, &pi0, t, phi));
    }
    let end = UnitQuaternion::new_normalize(state.q);
    Ok(RollingTrace {
        samples,
        net_rotation: (end * q0.inverse()).to_rotation_matrix(),
        initial: *initial,
        max_residual,
    })
}

fn rk4_step(cylinder: &Cylinder, s: &State, seg: &Segment, dt: f64) -> State {
    let f = |st: &State| {
        let (q, x, _) = rate(cylinder, st, seg.psi_rate, seg.phi_rate);
        (q, x)
    };
    let add = |st: &State, k: &(Quaternion<f64>, Vector3<f64>), h: f64| State {
        q: st.q + k.0 * h,
        x: st.x + k.1 * h,
    };
    let k1 = f(s);
    let k2 = f(&add(s, &k1, 0.5 * dt));
    let k3 = f(&add(s, &k2, 0.5 * dt));
    let k4 = f(&add(s, &k3, dt));
    let q = s.q + (k1.0 + k2.0 * 2.0 + k3.0 * 2.0 + k4.0) * (dt / 6.0);
    let x = s.x + (k1.1 + k2.1 * 2.0 + k3.1 * 2.0 + k4.1) * (dt / 6.0);
    State {
        q: q.normalize(),
        x,
    }
}

/// An angle brought into (−π, π].
fn wrap(a: f64) -> f64 {
    let w = a.rem_euclid(2.0 * PI);
    if w > PI {
        w - 2.0 * PI
    } else {
        w
    }
}

/// The segments that trace a rectangle: its nine motions at unit rate.
#[must_use]
pub fn rectangle_segments(path: &RectanglePath) -> Vec<Segment> {
    path.motions()
        .into_iter()
        .map(Segment::from_motion)
        .collect()
}

/// The start pose and segment that trace a circle: the circle of the centre of mass is
/// centred at the origin, ψ0 = 0, r̄ = ±k e′2 (3.4.12), ψ̇0 = ±1 and φ̇0 = ψ̇0 · ratio of
/// (3.4.14), for Δψ = ±2π.
///
/// # Errors
/// As [`CirclePath::holonomy`].
pub fn circle_motion(
    cylinder: &Cylinder,
    theta: f64,
    path: &CirclePath,
) -> Result<(Pose, Segment), CylinderError> {
    let hol = path.holonomy(cylinder, theta)?;
    let side = path.case.sign();
    let pose = Pose::on_plane(cylinder, 0.0, side * hol.k, [0.0, theta, 0.0]);
    let psi_rate = path.direction.sign();
    Ok((
        pose,
        Segment {
            duration: 2.0 * PI,
            psi_rate,
            phi_rate: psi_rate * hol.rate_ratio,
        },
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::holonomy::{figure_3_12, Direction, Figure310, PathCase};
    use rotations::rotation_distance;

    #[test]
    fn a_step_too_small_for_the_path_is_refused_before_rolling() {
        let fig = Figure310::new(PathCase::I);
        let pose = Pose::on_plane(&fig.cylinder, 0.0, 0.0, [0.0, fig.theta, 0.0]);
        let segments = rectangle_segments(&fig.path);
        let err = roll(&fig.cylinder, &pose, &segments, 1e-12, 50).unwrap_err();
        let text = err.to_string();
        assert!(text.starts_with("max_step = 1e-12 needs"), "{text}");
        assert!(
            text.ends_with("integration steps, more than the 1e7 allowed"),
            "{text}"
        );
    }

    #[test]
    fn rectangle_rolling_confirms_holonomy() {
        let fig = Figure310::new(PathCase::I);
        let pose = Pose::on_plane(&fig.cylinder, 0.0, 0.0, [0.0, fig.theta, 0.0]);
        let trace = roll(
            &fig.cylinder,
            &pose,
            &rectangle_segments(&fig.path),
            2e-3,
            50,
        )
        .unwrap();
        let closed = fig.path.closed_form(fig.theta, 0.0);
        assert!(rotation_distance(&trace.net_rotation, &closed) < 1e-9);
        assert!((trace.delta_phi() - fig.path.delta_phi()).abs() < 1e-9);
        assert!(trace.closure_error() < 1e-9);
        assert!(trace.max_residual < 1e-12);
        // The CSV row of a sample: P has no height column.
        let last = trace.samples.last().unwrap();
        let cells = last.csv_cells();
        assert_eq!(cells.len(), Sample::CSV_HEADER.len());
        assert_eq!(cells[0], last.t.to_string());
        assert_eq!(cells[5], last.contact.y.to_string());
        assert_eq!(cells[9], last.phi.to_string());
    }

    #[test]
    fn circle_rolling_confirms_holonomy() {
        let (cyl, theta, ell) = figure_3_12();
        for case in [PathCase::I, PathCase::II] {
            for dir in [Direction::CounterClockwise, Direction::Clockwise] {
                let path = CirclePath::new(ell, case, dir).unwrap();
                let (pose, seg) = circle_motion(&cyl, theta, &path).unwrap();
                let trace = roll(&cyl, &pose, &[seg], 2e-3, 100).unwrap();
                let expect = path.holonomy(&cyl, theta).unwrap().delta_phi;
                assert!(
                    (trace.delta_phi() - expect).abs() < 1e-8,
                    "{case:?} {dir:?}: {} vs {expect}",
                    trace.delta_phi()
                );
                assert!(
                    trace.closure_error() < 1e-8,
                    "{case:?} {dir:?}: closure {}",
                    trace.closure_error()
                );
                // P stays on the circle of radius ℓ.
                for s in &trace.samples {
                    assert!((s.contact.xy().norm() - ell).abs() < 1e-8);
                    assert!(s.contact.z.abs() < 1e-9);
                }
            }
        }
    }
}
