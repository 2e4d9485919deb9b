//! The transport of two touching cylinders (§3.5–3.6, Figure 3.14) as an
//! [`nsga::System`], stepped by the nonsmooth generalized-α method (docs/method.md).
//!
//! # Coordinates and velocities
//!
//! q = (x̄_I, ψ1, ϑ1, φ1, x̄_II, ψ2, ϑ2, φ2), the centres and the 3-1-3 Euler angles of
//! (3.5.1)–(3.5.2), in the order of (F.2.1). The velocities are the coordinate rates,
//! **u = q̇** (B = I): the constraints Π9, Π10 and Π12 of (3.5.13) are Euler-angle rates,
//! so they become single entries of W, and the contact rows are the rows of (F.2.3)
//! (v = x̄̇ + Σ_k θ̇_k g_k × π with the Euler basis g = (E3, e′1, e3), (A.2.1)). The price
//! is a mass matrix that depends on ϑ and gyroscopic forces from the Lagrangian
//! T = ½ I1 (ϑ̇² + ψ̇² sin²ϑ) + ½ I3 (φ̇ + ψ̇ cos ϑ)² with the inertias (3.2.7); M is
//! singular at ϑ = 0, which the point contact of §3.2 excludes anyway.
//!
//! # Constraints (all with index sets decided by the stepper at every step)
//!
//! Position level, p = (g, g_N):
//! - g0 (Π8 integrated): the height of the top centre of I, x̄_I3 + (h/2) e3·E3, stays at
//!   its initial value; its multiplier is the supporting force F3 of cylinder I;
//! - g1 (Π9 integrated): ψ1 = ψ1(0);
//! - g2, g3: the same for cylinder II (Π11, Π12);
//! - g_N1, g_N2: the rims on the floor, x̄3 + π_P · E3 with π_P of (3.5.4), (3.5.6);
//! - g_N3: the mutual gap d − 2r of App. E, (E.2.6), from the closest points of the axes.
//!
//! Velocity level, v = (γ, γ_F):
//! - γ (Π10): φ̇1 − φ̇10(t), the prescribed spin ([`SpinProfile`]);
//! - floor slips of P1, P2 along E1, E2 (two-component Coulomb, μ_s): (3.5.3), (3.5.5);
//! - the mutual slip (v3 − v4) · t_k of (3.5.9)–(3.5.10), two components with μ_k, in the
//!   tangent plane spanned by e3_I and e3_II (3.5.8). Those two vectors are not
//!   orthogonal, so the friction basis is their Gram–Schmidt orthonormalisation against
//!   the contact normal n: t1 = e3_I − (e3_I·n) n normalised (= e3_I at a point contact,
//!   where n ⟂ e3_I), t2 = n × t1. The prox onto a disk then bounds ‖λ_F‖ ≤ μ_k λ_N.
//!
//! The contact normal is n = s e3_I × e3_II/‖·‖ of (3.5.8) with a fixed orientation s
//! ([`PairTransport::normal_sign`]), and the mutual gap is the signed distance
//! (x_II* − x_I*)·n − 2r of the closest points (E.2.6): it stays negative however deep
//! the cylinders would overlap. The unsigned ‖x_II* − x_I*‖ − 2r is zero on both sides of
//! cylinder II, and a step's position correction once found the root on the far side (I
//! jumped through II). For (nearly) parallel axes, where the cross product vanishes, n is
//! the unit vector from x_I* to x_II* (E.2.8). The gradient of every gap equals the
//! velocity Jacobian of the material points at its closest points (the closest points
//! are a minimum, so their motion drops out), so W_p = ∂p/∂q exactly.
//!
//! # Exact derivatives
//!
//! [`PairTransport::evaluate`] is generic over [`nsga::Scalar`], so the stepper's Newton
//! Jacobians come from forward-mode automatic differentiation. The curvature terms
//! ζ = (dW/dt)ᵀ u are computed exactly too, by evaluating the same W at q + ε u with a
//! nested dual number (one more pass, no finite differences).

use crate::contact::{closest_points, AxisSegment, ClosestKind};
use crate::error::CylinderError;
use crate::kinematics::Cylinder;
use crate::pair::CylinderPair;
use input::InputError;
use nalgebra::Vector3;
use nsga::{Evaluation, FrictionLaw, Layout, Scalar, System};
use num_dual::Dual;
use serde::{Deserialize, Serialize};
use std::f64::consts::{FRAC_PI_2, PI};

/// Below this ‖e3_I × e3_II‖ the axes count as parallel and the contact normal is taken
/// along the line between the closest points instead.
const PARALLEL_SINE: f64 = 1e-6;

/// Number of coordinates (and velocities) of the pair.
pub const N_COORDINATES: usize = 12;
/// Position-level constraints: 4 bilateral (Π8, Π9, Π11, Π12) and 3 gaps.
const N_POSITION: usize = 7;
/// Velocity-level constraints: Π10 and three two-component friction laws.
const N_VELOCITY: usize = 7;

/// The spin a [`SpinProfile::ramp`] starts from, as a fraction of its target.
pub const RAMP_INITIAL_FRACTION: f64 = 0.01;

/// The prescribed spin rate φ̇10(t) of cylinder I, Π10 of (3.5.13): `initial` until
/// `ramp_start`, then a smooth (C¹, 3τ² − 2τ³) ramp to `target` over `ramp_duration`.
/// With `initial = target` it is the thesis's constant spin, given at t = 0.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SpinProfile {
    /// φ̇10 before the ramp (rad/s).
    pub initial: f64,
    /// φ̇10 after the ramp (rad/s).
    pub target: f64,
    /// When the ramp starts (s).
    pub ramp_start: f64,
    /// How long it lasts (s); must be positive when `initial` ≠ `target`.
    pub ramp_duration: f64,
}

impl SpinProfile {
    /// A constant spin ω (the thesis's impulsive spin-up: ω from t = 0 on).
    #[must_use]
    pub fn constant(omega: f64) -> Self {
        Self {
            initial: omega,
            target: omega,
            ramp_start: 0.0,
            ramp_duration: 1.0,
        }
    }

    /// A smooth spin-up to ω over `duration` seconds, from a slow roll at
    /// [`RAMP_INITIAL_FRACTION`] of ω. Not from rest: at rest the mutual contact would
    /// stick, and its two friction rows on top of the twelve constraints that already
    /// fix the pair (Π1–Π12) make the consistent start's matrix singular; once rolling,
    /// the contact slides ((v3 − v4) ∝ φ̇1) as in §3.6.
    #[must_use]
    pub fn ramp(omega: f64, duration: f64) -> Self {
        Self {
            initial: RAMP_INITIAL_FRACTION * omega,
            target: omega,
            ramp_start: 0.0,
            ramp_duration: duration,
        }
    }

    /// (φ̇10, φ̈10) at time t.
    #[must_use]
    pub fn at(&self, t: f64) -> (f64, f64) {
        let span = self.target - self.initial;
        if span == 0.0 {
            return (self.initial, 0.0);
        }
        let tau = (t - self.ramp_start) / self.ramp_duration;
        if tau <= 0.0 {
            (self.initial, 0.0)
        } else if tau >= 1.0 {
            (self.target, 0.0)
        } else {
            let s = tau * tau * (3.0 - 2.0 * tau);
            let ds = 6.0 * tau * (1.0 - tau) / self.ramp_duration;
            (self.initial + span * s, span * ds)
        }
    }

    fn validate(&self) -> Result<(), CylinderError> {
        input::finite("spin rate", self.initial)?;
        input::finite("spin rate", self.target)?;
        input::finite("ramp start", self.ramp_start)?;
        if self.initial != self.target {
            input::positive("ramp duration", self.ramp_duration)?;
        }
        Ok(())
    }
}

/// The two cylinders of §3.6 held at their tops, as an [`nsga::System`] (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PairTransport {
    /// The (identical) cylinders.
    pub cylinder: Cylinder,
    /// Mass m of each (forces are reported divided by mg, so m only scales them).
    pub mass: f64,
    /// Gravity g.
    pub gravity: f64,
    /// Floor friction coefficient μ_s (both rims).
    pub mu_floor: f64,
    /// Friction coefficient μ_k between the cylinders.
    pub mu_mutual: f64,
    /// The prescribed spin of cylinder I.
    pub spin: SpinProfile,
    /// Horizontal force P/mg at each top centre along that cylinder's e′2 (the applied
    /// force F e′2 of §3.3), reached after [`PUSH_RAMP_S`]; 0 in the thesis.
    pub push_over_mg: f64,
    /// Heights of the top centres held by Π8, Π11.
    pub top_height: [f64; 2],
    /// Headings ψ held by Π9, Π12.
    pub headings: [f64; 2],
    /// The orientation s of the mutual contact normal n = s e3_I × e3_II/‖·‖ (3.5.8):
    /// the side of I on which II lies (−1 for the transport of §3.6, where II is at +E1
    /// and e3_I × e3_II points along −E1).
    pub normal_sign: f64,
}

/// A small generic 3-vector algebra over any [`Scalar`].
type V<S> = [S; 3];

fn add<S: Scalar>(a: V<S>, b: V<S>) -> V<S> {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
fn sub<S: Scalar>(a: V<S>, b: V<S>) -> V<S> {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn scale<S: Scalar>(a: V<S>, s: S) -> V<S> {
    [a[0] * s, a[1] * s, a[2] * s]
}
fn dot<S: Scalar>(a: V<S>, b: V<S>) -> S {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn cross<S: Scalar>(a: V<S>, b: V<S>) -> V<S> {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
fn unit<S: Scalar>(a: V<S>) -> V<S> {
    scale(a, dot(a, a).sqrt().recip())
}
fn constant<S: Scalar>(x: f64, y: f64, z: f64) -> V<S> {
    [S::from(x), S::from(y), S::from(z)]
}

/// The Euler vectors of one cylinder, (A.1.1)–(A.1.4), generic over the scalar.
#[derive(Debug, Clone, Copy)]
struct Frame<S> {
    e1p: V<S>,
    e2p: V<S>,
    e2pp: V<S>,
    e3: V<S>,
}

impl<S: Scalar> Frame<S> {
    fn new(psi: S, theta: S) -> Self {
        let (sp, cp) = (psi.sin(), psi.cos());
        let (st, ct) = (theta.sin(), theta.cos());
        let z = S::from(0.0);
        let e2p = [-sp, cp, z];
        Self {
            e1p: [cp, sp, z],
            e2p,
            e2pp: [e2p[0] * ct, e2p[1] * ct, st],
            e3: [-e2p[0] * st, -e2p[1] * st, ct],
        }
    }
    /// g1, g2, g3 = E3, e′1, e3 (A.1.4): ω = ψ̇ g1 + ϑ̇ g2 + φ̇ g3.
    fn basis(&self) -> [V<S>; 3] {
        [constant(0.0, 0.0, 1.0), self.e1p, self.e3]
    }
}

/// Values and force directions of all 14 constraints at one configuration.
struct Geometry<S> {
    /// p = (g, g_N), 7 values.
    position: [S; N_POSITION],
    /// Rows of W_pᵀ (7) then W_vᵀ (7), each over the 12 velocities.
    rows: [[S; N_COORDINATES]; N_POSITION + N_VELOCITY],
    /// Which bodies each row touches (bit 0: I, bit 1: II).
    bodies: [u8; N_POSITION + N_VELOCITY],
}

impl<S: Scalar> Geometry<S> {
    /// Adds to row `row` the velocity Jacobian of a force `f` applied at `pi` (relative to
    /// the centre) of body `body`: (f, g_k · (π × f)), from v = x̄̇ + Σ θ̇_k g_k × π.
    fn point(&mut self, row: usize, body: usize, frame: &Frame<S>, pi: V<S>, f: V<S>, sign: f64) {
        let o = 6 * body;
        let moment = cross(pi, f);
        for k in 0..3 {
            self.rows[row][o + k] += f[k] * sign;
        }
        for (k, g) in frame.basis().into_iter().enumerate() {
            self.rows[row][o + 3 + k] += dot(g, moment) * sign;
        }
        self.bodies[row] |= 1 << body;
    }
}

impl PairTransport {
    /// The thesis's transport (§3.6) at inclination ϑ: gas cylinders (h = 1.2954 m,
    /// r = 0.1143 m), g = 9.81, μ_k = 0.4, a floor friction μ_s = 1 (idle in steady
    /// transport), a constant spin φ̇10 = −6π rad/s, no push.
    #[must_use]
    pub fn thesis(theta: f64) -> Self {
        let cylinder = Cylinder::gas_cylinder();
        Self {
            cylinder,
            mass: 1.0,
            gravity: 9.81,
            mu_floor: 1.0,
            mu_mutual: 0.4,
            spin: SpinProfile::constant(-6.0 * PI),
            push_over_mg: 0.0,
            top_height: [top_height(&cylinder, theta); 2],
            headings: [0.0, PI],
            normal_sign: -1.0,
        }
    }

    /// Inertias (I1, I3) of a homogeneous cylinder about its centre, (3.2.7).
    #[must_use]
    pub fn inertias(&self) -> (f64, f64) {
        let (r, h, m) = (self.cylinder.radius(), self.cylinder.height(), self.mass);
        (m * (3.0 * r * r + h * h) / 12.0, 0.5 * m * r * r)
    }

    fn geometry<S: Scalar>(&self, q: &[S]) -> Geometry<S> {
        let zero = S::from(0.0);
        let mut geo = Geometry {
            position: [zero; N_POSITION],
            rows: [[zero; N_COORDINATES]; N_POSITION + N_VELOCITY],
            bodies: [0; N_POSITION + N_VELOCITY],
        };
        let (r, half) = (self.cylinder.radius(), 0.5 * self.cylinder.height());
        let frames = [Frame::new(q[3], q[4]), Frame::new(q[9], q[10])];
        let centres: [V<S>; 2] = [[q[0], q[1], q[2]], [q[6], q[7], q[8]]];
        let up = constant::<S>(0.0, 0.0, 1.0);
        for b in 0..2 {
            let f = &frames[b];
            // Π8 / Π11: top height; Π9 / Π12: heading.
            let top = scale(f.e3, S::from(half));
            geo.position[2 * b] = centres[b][2] + top[2] - self.top_height[b];
            geo.point(2 * b, b, f, top, up, 1.0);
            geo.position[2 * b + 1] = q[6 * b + 3] - self.headings[b];
            geo.rows[2 * b + 1][6 * b + 3] = S::from(1.0);
            geo.bodies[2 * b + 1] = 1 << b;
            // Floor contact P1 / P2: π_P = −(h/2) e3 − r e″2, (3.5.4), (3.5.6).
            let pi = sub(scale(f.e3, S::from(-half)), scale(f.e2pp, S::from(r)));
            geo.position[4 + b] = centres[b][2] + pi[2];
            geo.point(4 + b, b, f, pi, up, 1.0);
            geo.point(8 + 2 * b, b, f, pi, constant(1.0, 0.0, 0.0), 1.0);
            geo.point(9 + 2 * b, b, f, pi, constant(0.0, 1.0, 0.0), 1.0);
        }
        // Π10: φ̇1.
        geo.rows[7][5] = S::from(1.0);
        geo.bodies[7] = 1;
        // The mutual contact, App. E.
        let (m, n) = self.closest_parameters(&centres, &frames);
        let xi = add(centres[0], scale(frames[0].e3, m));
        let xii = add(centres[1], scale(frames[1].e3, n));
        let diff = sub(xii, xi);
        let across = cross(frames[0].e3, frames[1].e3);
        let sine = dot(across, across).sqrt();
        let normal = if sine.re() > PARALLEL_SINE {
            scale(across, S::from(self.normal_sign) / sine)
        } else {
            scale(diff, dot(diff, diff).sqrt().recip())
        };
        geo.position[6] = dot(diff, normal) - S::from(2.0 * r);
        let axis_i = scale(frames[0].e3, m);
        let axis_ii = scale(frames[1].e3, n);
        geo.point(6, 1, &frames[1], axis_ii, normal, 1.0);
        geo.point(6, 0, &frames[0], axis_i, normal, -1.0);
        let e3 = frames[0].e3;
        let t1 = unit(sub(e3, scale(normal, dot(e3, normal))));
        let t2 = cross(normal, t1);
        let pi3 = add(axis_i, scale(normal, S::from(r)));
        let pi4 = sub(axis_ii, scale(normal, S::from(r)));
        for (k, t) in [t1, t2].into_iter().enumerate() {
            geo.point(12 + k, 0, &frames[0], pi3, t, 1.0);
            geo.point(12 + k, 1, &frames[1], pi4, t, -1.0);
        }
        geo
    }

    /// The closest points m*, n* of the two axes, (E.2.1)–(E.2.4): in closed form (so
    /// that their derivatives, the rates (E.2.5), come with the scalar) when they lie
    /// inside both segments; otherwise the clamped or parallel solution of
    /// [`closest_points`], held fixed (the gap's gradient is still exact there by the
    /// envelope theorem; only its curvature misses the motion of the points).
    fn closest_parameters<S: Scalar>(&self, centres: &[V<S>; 2], frames: &[Frame<S>; 2]) -> (S, S) {
        let re = |v: &V<S>| Vector3::new(v[0].re(), v[1].re(), v[2].re());
        let segment = |b: usize| AxisSegment {
            center: re(&centres[b]),
            axis: re(&frames[b].e3),
            half_length: 0.5 * self.cylinder.height(),
            radius: self.cylinder.radius(),
        };
        let cp = closest_points(&segment(0), &segment(1));
        if cp.kind != ClosestKind::Interior {
            return (S::from(cp.m), S::from(cp.n));
        }
        let delta = sub(centres[1], centres[0]);
        let c = dot(frames[0].e3, frames[1].e3);
        let (b1, b2) = (dot(delta, frames[0].e3), dot(delta, frames[1].e3));
        let den = (S::from(1.0) - c * c).recip();
        ((b1 - c * b2) * den, (c * b1 - b2) * den)
    }

    /// The consistent state of the transport at inclination ϑ (§3.6): ψ1 = 0, ψ2 = π,
    /// touching at the centres of both axes (the closest-point solve of App. E confirms
    /// an interior point contact with zero gap), rolling at the speed the spin
    /// φ̇10(0) gives: φ̇2 = −φ̇10, x̄̇ = −r φ̇ e′1 for each (so that (v3 − v4)·n = 0).
    ///
    /// # Errors
    /// When ϑ is outside (arctan(2r/h), π/2), or the construction does not touch.
    pub fn initial_state(&self, theta: f64) -> Result<([f64; 12], [f64; 12]), CylinderError> {
        check_inclination(&self.cylinder, theta)?;
        let pair = CylinderPair::identical(self.cylinder);
        let q = pair.touching_configuration(theta, 0.0, self.headings[0])?;
        let k = pair.contacts(&q);
        if k.mutual.kind != ClosestKind::Interior || k.gaps.iter().any(|g| g.abs() > 1e-12) {
            return Err(InputError::OutOfRange {
                name: "initial contact gap".into(),
                range: "0 (an interior point contact)",
                value: k.gaps[2],
            }
            .into());
        }
        let (w, _) = self.spin.at(0.0);
        let r = self.cylinder.radius();
        let mut u = [0.0; 12];
        for (b, spin) in [(0, w), (1, -w)] {
            let psi = q[6 * b + 3];
            u[6 * b] = -r * spin * psi.cos();
            u[6 * b + 1] = -r * spin * psi.sin();
            u[6 * b + 5] = spin;
        }
        Ok((q, u))
    }

    /// Checks r < h/2 (the cylinder is taller than wide, so that it leans on one rim
    /// point with its axis crossing the other's).
    ///
    /// # Errors
    /// [`InputError::OutOfRange`] for r ≥ h/2.
    pub fn validate_geometry(&self) -> Result<(), CylinderError> {
        let (r, h) = (self.cylinder.radius(), self.cylinder.height());
        if r >= 0.5 * h {
            return Err(InputError::OutOfRange {
                name: "radius r".into(),
                range: "(0, h/2): a cylinder taller than wide",
                value: r,
            }
            .into());
        }
        Ok(())
    }

    /// Checks every parameter.
    ///
    /// # Errors
    /// A one-line message naming the first bad one.
    pub fn validate(&self) -> Result<(), CylinderError> {
        self.validate_geometry()?;
        input::positive("mass", self.mass)?;
        input::positive("gravity g", self.gravity)?;
        input::non_negative("floor friction μ_s", self.mu_floor)?;
        input::non_negative("mutual friction μ_k", self.mu_mutual)?;
        input::finite("push P/mg", self.push_over_mg)?;
        self.spin.validate()
    }
}

/// How long the push takes to reach its value, s: it rises smoothly (3τ² − 2τ³) from
/// zero, so that the run starts from the steady transport (a push at its full value at
/// t = 0 would start at a friction limit, where the consistent start's Newton matrix
/// is singular).
pub const PUSH_RAMP_S: f64 = 0.05;

/// The fraction of the push applied at time t ([`PUSH_RAMP_S`]).
#[must_use]
pub fn push_ramp(t: f64) -> f64 {
    let tau = (t / PUSH_RAMP_S).clamp(0.0, 1.0);
    tau * tau * (3.0 - 2.0 * tau)
}

/// The height of the top centre of a cylinder standing on its rim at inclination ϑ:
/// f2(ϑ) + (h/2) cos ϑ = r sin ϑ + h cos ϑ, (3.2.6).
#[must_use]
pub fn top_height(cylinder: &Cylinder, theta: f64) -> f64 {
    cylinder.radius() * theta.sin() + cylinder.height() * theta.cos()
}

/// The admissible inclinations of the transport: (arctan(2r/h), π/2), where the
/// smooth-floor support (3.3.10) needs a positive lifting force F3 and the rim touches
/// at one point (§3.2).
#[must_use]
pub fn inclination_range(cylinder: &Cylinder) -> (f64, f64) {
    (
        (2.0 * cylinder.radius() / cylinder.height()).atan(),
        FRAC_PI_2,
    )
}

/// Checks ϑ against [`inclination_range`].
///
/// # Errors
/// [`InputError::OutOfRange`] with the range in words.
pub fn check_inclination(cylinder: &Cylinder, theta: f64) -> Result<f64, CylinderError> {
    let (lo, hi) = inclination_range(cylinder);
    input::finite("inclination ϑ", theta)?;
    if theta > lo && theta < hi {
        Ok(theta)
    } else {
        Err(InputError::OutOfRange {
            name: "inclination ϑ".into(),
            range: "(arctan(2r/h), π/2)",
            value: theta,
        }
        .into())
    }
}

impl System for PairTransport {
    fn layout(&self) -> Layout {
        let law = |mu: f64, normal: usize| FrictionLaw {
            components: 2,
            mu,
            e_f: 0.0,
            normals: vec![normal],
        };
        Layout {
            nq: N_COORDINATES,
            nu: N_COORDINATES,
            n_bilateral_position: 4,
            n_bilateral_velocity: 1,
            e_n: vec![0.0; 3],
            friction: vec![
                law(self.mu_floor, 0),
                law(self.mu_floor, 1),
                law(self.mu_mutual, 2),
            ],
        }
    }

    fn evaluate<T: Scalar>(&self, t: f64, q: &[T], u: &[T], out: &mut Evaluation<T>) {
        let (i1, i3) = self.inertias();
        let m = self.mass;
        let half = 0.5 * self.cylinder.height();
        let push = self.push_over_mg * m * self.gravity * push_ramp(t);
        for b in 0..2 {
            let o = 6 * b;
            for k in 0..3 {
                out.mass.push(o + k, o + k, T::from(m));
            }
            let (s, c) = (q[o + 4].sin(), q[o + 4].cos());
            let (dpsi, dtheta, dphi) = (u[o + 3], u[o + 4], u[o + 5]);
            // M and h of the Lagrangian T = ½ I1 (ϑ̇² + ψ̇² s²) + ½ I3 (φ̇ + ψ̇ c)².
            out.mass.push(o + 3, o + 3, s * s * i1 + c * c * i3);
            out.mass.push(o + 3, o + 5, c * i3);
            out.mass.push(o + 5, o + 3, c * i3);
            out.mass.push(o + 4, o + 4, T::from(i1));
            out.mass.push(o + 5, o + 5, T::from(i3));
            out.forces[o + 3] = -dtheta * (s * c * dpsi * (2.0 * (i1 - i3)) - s * dphi * i3);
            out.forces[o + 4] = s * c * dpsi * dpsi * i1 - (dphi + c * dpsi) * dpsi * s * i3;
            out.forces[o + 5] = s * dpsi * dtheta * i3;
            out.forces[o + 2] -= T::from(m * self.gravity);
            if push != 0.0 {
                // P e′2 at the top centre (h/2) e3: force and its moments on g_k.
                let f = Frame::new(q[o + 3], q[o + 4]);
                let force = scale(f.e2p, T::from(push));
                let moment = cross(scale(f.e3, T::from(half)), force);
                for k in 0..3 {
                    out.forces[o + k] += force[k];
                }
                for (k, g) in f.basis().into_iter().enumerate() {
                    out.forces[o + 3 + k] += dot(g, moment);
                }
            }
        }
        let geo = self.geometry(q);
        out.position.copy_from_slice(&geo.position);
        // ζ = (dW/dt)ᵀ u: W at q + ε u (u held fixed), the ε part times u.
        let qd: Vec<Dual<T>> = q.iter().zip(u).map(|(&x, &v)| Dual::new(x, v)).collect();
        let moving = self.geometry(&qd);
        for (row, (values, touched)) in geo.rows.iter().zip(geo.bodies).enumerate() {
            let mut zeta = T::from(0.0);
            for b in 0..2 {
                if touched & (1 << b) == 0 {
                    continue;
                }
                for j in 6 * b..6 * b + 6 {
                    zeta += moving.rows[row][j].eps * u[j];
                    if row < N_POSITION {
                        out.position_w.push(j, row, values[j]);
                    } else {
                        out.velocity_w.push(j, row - N_POSITION, values[j]);
                    }
                }
            }
            if row < N_POSITION {
                out.position_zeta[row] = zeta;
            } else {
                out.velocity_zeta[row - N_POSITION] = zeta;
            }
        }
        let (spin, spin_rate) = self.spin.at(t);
        out.velocity_chi[0] = T::from(-spin);
        out.velocity_zeta[0] -= T::from(spin_rate);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// W_p is the gradient of p, and ζ_p = uᵀ ∇²p u (checked by central differences).
    #[test]
    fn position_rows_are_gradients_and_zeta_is_curvature() {
        let sys = PairTransport::thesis(0.4);
        let (mut q, _) = sys.initial_state(0.4).unwrap();
        // A generic nearby configuration (still an interior closest point).
        for (k, x) in q.iter_mut().enumerate() {
            *x += 1e-3 * ((k as f64) * 0.7).sin();
        }
        let u: Vec<f64> = (0..12).map(|k| ((k as f64) * 1.3).cos()).collect();
        let mut e = Evaluation::<f64>::new(&sys.layout());
        sys.evaluate(0.0, &q, &u, &mut e);
        let p = |q: &[f64]| sys.geometry(q).position;
        let h = 1e-5;
        for j in 0..12 {
            let (mut qp, mut qm) = (q, q);
            qp[j] += h;
            qm[j] -= h;
            let (pp, pm) = (p(&qp), p(&qm));
            for c in 0..N_POSITION {
                let fd = (pp[c] - pm[c]) / (2.0 * h);
                let w: f64 = e
                    .position_w
                    .entries
                    .iter()
                    .filter(|&&(r, cc, _)| r == j && cc == c)
                    .map(|e| e.2)
                    .sum();
                assert!((fd - w).abs() < 1e-8, "row {c} col {j}: {fd} vs {w}");
            }
        }
        let along = |s: f64| {
            let qs: Vec<f64> = q.iter().zip(&u).map(|(x, v)| x + s * v).collect();
            p(&qs)
        };
        let (a, b, c) = (along(h), along(0.0), along(-h));
        for k in 0..N_POSITION {
            let fd = (a[k] - 2.0 * b[k] + c[k]) / (h * h);
            assert!(
                (fd - e.position_zeta[k]).abs() < 1e-4,
                "zeta {k}: {fd} vs {}",
                e.position_zeta[k]
            );
        }
    }

    /// Parallel and nearly parallel axes (a line contact, H of (E.2.4) singular or
    /// nearly so): the gap, its normal and every row stay finite.
    #[test]
    fn nearly_parallel_axes_stay_finite() {
        let sys = PairTransport::thesis(0.4);
        let r = sys.cylinder.radius();
        for tilt in [0.0, 1e-9, 1e-6] {
            // Both lean the same way (ψ = 0), side by side along E1, 2r apart.
            let z = 0.6;
            let q = [
                0.0,
                0.0,
                z,
                0.0,
                0.4,
                0.0,
                2.0 * r,
                0.0,
                z,
                0.0,
                0.4 + tilt,
                0.0,
            ];
            let u = [0.1; 12];
            let mut e = Evaluation::<f64>::new(&sys.layout());
            sys.evaluate(0.0, &q, &u, &mut e);
            assert!(
                e.position[6].abs() < 1e-6,
                "tilt {tilt}: gap {}",
                e.position[6]
            );
            assert!(e.position_w.entries.iter().all(|w| w.2.is_finite()));
            assert!(e.velocity_w.entries.iter().all(|w| w.2.is_finite()));
            assert!(e
                .position_zeta
                .iter()
                .chain(&e.velocity_zeta)
                .all(|z| z.is_finite()));
        }
    }

    /// The gyroscopic forces are Lagrange's: h = ∂T/∂q − Ṁ u (gravity aside), with
    /// T = ½ uᵀ M(q) u, checked by central differences of M.
    #[test]
    fn gyroscopic_forces_are_lagranges() {
        let sys = PairTransport::thesis(0.4);
        let q = [0.0, 0.0, 0.6, 0.3, 0.5, 0.2, 0.0, 0.0, 0.6, 2.0, 0.7, 1.0];
        let u = [0.1, 0.2, 0.3, 0.4, -0.5, 0.6, 0.0, 0.0, 0.0, -0.3, 0.2, 1.1];
        let layout = sys.layout();
        let mass = |q: &[f64]| {
            let mut e = Evaluation::<f64>::new(&layout);
            sys.evaluate(0.0, q, &u, &mut e);
            let mut m = [[0.0; 12]; 12];
            for &(r, c, v) in &e.mass.entries {
                m[r][c] += v;
            }
            (m, e.forces)
        };
        let (_, h) = mass(&q);
        let d = 1e-6;
        let mut expect = [0.0; 12];
        for k in 0..12 {
            let (mut qp, mut qm) = (q, q);
            qp[k] += d;
            qm[k] -= d;
            let (mp, _) = mass(&qp);
            let (mm, _) = mass(&qm);
            for i in 0..12 {
                for j in 0..12 {
                    let dm = (mp[i][j] - mm[i][j]) / (2.0 * d);
                    // ∂T/∂q_k and −(∂M_ij/∂q_k u_k) u_j.
                    expect[k] += 0.5 * u[i] * dm * u[j];
                    expect[i] -= dm * u[k] * u[j];
                }
            }
        }
        let g = sys.mass * sys.gravity;
        for i in 0..12 {
            let gravity = if i % 6 == 2 { -g } else { 0.0 };
            assert!(
                (h[i] - gravity - expect[i]).abs() < 1e-7,
                "h[{i}] = {} vs {}",
                h[i] - gravity,
                expect[i]
            );
        }
    }

    /// ½ u̇ᵀ M u̇ is the kinetic energy of ω = ψ̇ E3 + ϑ̇ e′1 + φ̇ e3 with the inertia
    /// I1 (1 − e3 e3ᵀ) + I3 e3 e3ᵀ.
    #[test]
    fn mass_matrix_is_the_kinetic_energy() {
        let sys = PairTransport::thesis(0.4);
        let q = [0.0, 0.0, 0.6, 0.3, 0.5, 0.2, 0.0, 0.0, 0.6, 2.0, 0.7, 1.0];
        let u = [0.1, 0.2, 0.3, 0.4, -0.5, 0.6, 0.0, 0.0, 0.0, -0.3, 0.2, 1.1];
        let mut e = Evaluation::<f64>::new(&sys.layout());
        sys.evaluate(0.0, &q, &u, &mut e);
        let mut t = 0.0;
        for &(r, c, v) in &e.mass.entries {
            t += 0.5 * u[r] * v * u[c];
        }
        let (i1, i3) = sys.inertias();
        let mut expect = 0.0;
        for b in 0..2 {
            let o = 6 * b;
            let f = Frame::<f64>::new(q[o + 3], q[o + 4]);
            let g = f.basis();
            let w = add(
                add(scale(g[0], u[o + 3]), scale(g[1], u[o + 4])),
                scale(g[2], u[o + 5]),
            );
            let axial = dot(w, f.e3);
            expect += 0.5 * sys.mass * dot([u[o], u[o + 1], u[o + 2]], [u[o], u[o + 1], u[o + 2]]);
            expect += 0.5 * (i1 * (dot(w, w) - axial * axial) + i3 * axial * axial);
        }
        assert!((t - expect).abs() < 1e-12, "{t} vs {expect}");
    }
}
