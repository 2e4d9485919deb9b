//! Bring your own system: a pendulum striking a wall, put on the nsga stepper from
//! outside the crate, and checked against its closed form.
//!
//! A point mass m on a massless rod of length L swings about the origin in the plane
//! (x to the right, y up, gravity −g ŷ). Released at rest at the angle θ0 to the right
//! of the vertical, it swings left and strikes a wall at x = 0 (the vertical through
//! the pivot) with Newton's restitution coefficient e_N; the wall is rough (Coulomb, μ).
//!
//! Written in Cartesian coordinates so that it shows every kind of constraint the
//! [`System`] trait knows:
//!
//! - q = (x, y), q̇ = u, M = diag(m, m), h = (0, −m g);
//! - one **bilateral position constraint**, the rod: g = x² + y² − L² = 0, with
//!   W = ∂g/∂q = (2x, 2y) and ġ = Wᵀu, g̈ = Wᵀa + ζ with ζ = 2(ẋ² + ẏ²);
//! - one **normal contact**, the wall: g_N = x ≥ 0, W_N = (1, 0), ζ_N = 0;
//! - one **friction law** on it, the slip along the wall: γ_F = ẏ, W_F = (0, 1).
//!
//! The closed form, from energy conservation and the impact law:
//!
//! - the first impact comes a quarter period after release,
//!   T/4 = √(L/g) K(sin(θ0/2)), K the complete elliptic integral of the first kind;
//! - the mass reaches the wall with speed v = √(2gL(1 − cos θ0)), horizontally, so the
//!   friction has nothing to do, and leaves it with e_N v;
//! - it then rises to the angle θ1 with 1 − cos θ1 = e_N² (1 − cos θ0).
//!
//! Run it with `cargo run --release -p nsga --example pendulum_wall`; the test
//! `crates/nsga/tests/bring_your_own_system.rs` runs it in CI.

use nsga::{Evaluation, FrictionLaw, Layout, Options, Scalar, StepError, Stepper, System};

/// A pendulum of length `length` with a point mass `mass`, next to a rough wall.
#[derive(Debug, Clone, Copy)]
pub struct PendulumWall {
    /// Mass m (kg).
    pub mass: f64,
    /// Rod length L (m).
    pub length: f64,
    /// Gravity g (m/s²).
    pub gravity: f64,
    /// Restitution e_N of the wall.
    pub restitution: f64,
    /// Friction coefficient μ of the wall.
    pub mu: f64,
}

impl System for PendulumWall {
    /// Sizes: 2 coordinates and velocities, 1 bilateral position constraint, 1 normal
    /// contact with its e_N, 1 friction law of 1 component bounded by μ λ_N of contact 0.
    fn layout(&self) -> Layout {
        Layout {
            nq: 2,
            nu: 2,
            n_bilateral_position: 1,
            e_n: vec![self.restitution],
            friction: vec![FrictionLaw {
                components: 1,
                mu: self.mu,
                e_f: 0.0,
                normals: vec![0],
            }],
            ..Layout::default()
        }
    }

    /// Everything at (t, q, u), generic over the scalar so that the stepper gets exact
    /// Jacobians by automatic differentiation. The position family stacks the bilateral
    /// constraints first, then the gaps: column 0 is the rod, column 1 the wall.
    fn evaluate<T: Scalar>(&self, _t: f64, q: &[T], u: &[T], out: &mut Evaluation<T>) {
        let (x, y) = (q[0], q[1]);
        let (m, l, g) = (self.mass, self.length, self.gravity);
        out.mass.push(0, 0, T::from(m));
        out.mass.push(1, 1, T::from(m));
        out.forces[1] = T::from(-m * g);
        // The rod: g = x² + y² − L², W = (2x, 2y), ζ = 2(ẋ² + ẏ²).
        out.position[0] = x * x + y * y - T::from(l * l);
        out.position_w.push(0, 0, x * 2.0);
        out.position_w.push(1, 0, y * 2.0);
        out.position_zeta[0] = (u[0] * u[0] + u[1] * u[1]) * 2.0;
        // The wall: g_N = x, W_N = (1, 0).
        out.position[1] = x;
        out.position_w.push(0, 1, T::from(1.0));
        // Slip along the wall: γ_F = ẏ, W_F = (0, 1).
        out.velocity_w.push(1, 0, T::from(1.0));
    }
}

/// K(k), the complete elliptic integral of the first kind, by the arithmetic–geometric
/// mean: K = π / (2 AGM(1, √(1 − k²))).
fn elliptic_k(k: f64) -> f64 {
    let (mut a, mut b) = (1.0_f64, (1.0 - k * k).sqrt());
    // Quadratic convergence: a handful of iterations reach round-off (a fixed count,
    // since a and b may end one ulp apart for ever).
    for _ in 0..8 {
        (a, b) = (0.5 * (a + b), (a * b).sqrt());
    }
    std::f64::consts::PI / (2.0 * a)
}

/// What the run measured beside the closed form.
#[derive(Debug, Clone, Copy)]
pub struct Comparison {
    /// Time of the first step with a wall percussion, and T/4.
    pub impact_time: (f64, f64),
    /// Largest angle after the bounce, and θ1 of the closed form (rad).
    pub rebound_angle: (f64, f64),
    /// Largest |x² + y² − L²| over the run (m²).
    pub rod_drift: f64,
    /// Smallest wall gap over the run (m).
    pub min_gap: f64,
}

/// Releases the pendulum at θ0 and runs it through the first bounce to its next apex.
///
/// # Errors
/// A step the stepper cannot resolve (none is expected).
pub fn run(p: PendulumWall, theta0: f64, dt: f64) -> Result<Comparison, StepError> {
    let q0 = [p.length * theta0.sin(), -p.length * theta0.cos()];
    let options = Options {
        dt,
        ..Options::default()
    };
    let mut s = Stepper::new(p, 0.0, &q0, &[0.0, 0.0], options)?;
    let quarter = (p.length / p.gravity).sqrt() * elliptic_k((0.5 * theta0).sin());
    let (mut impact, mut apex, mut drift, mut min_gap) = (None, 0.0_f64, 0.0_f64, f64::INFINITY);
    while s.state().t < 3.0 * quarter {
        s.step()?;
        let st = s.state();
        let (x, y) = (st.q[0], st.q[1]);
        if impact.is_none() && st.p_n[0] > 0.0 {
            impact = Some(st.t);
        }
        if impact.is_some() {
            apex = apex.max(x.atan2(-y));
        }
        drift = drift.max((x * x + y * y - p.length * p.length).abs());
        min_gap = min_gap.min(x);
    }
    let e = p.restitution;
    let theta1 = (1.0 - e * e * (1.0 - theta0.cos())).acos();
    Ok(Comparison {
        impact_time: (impact.unwrap_or(f64::NAN), quarter),
        rebound_angle: (apex, theta1),
        rod_drift: drift,
        min_gap,
    })
}

/// Runs the pendulum and compares it with its closed form.
///
/// # Errors
/// A failed step, or a disagreement beyond the tolerances below.
pub fn main() -> Result<(), Box<dyn std::error::Error>> {
    let p = PendulumWall {
        mass: 1.0,
        length: 1.0,
        gravity: 9.81,
        restitution: 0.5,
        mu: 0.3,
    };
    let theta0 = 1.0;
    let c = run(p, theta0, 1e-3)?;
    println!(
        "first impact at t = {:.4} s (closed form T/4 = {:.4} s)",
        c.impact_time.0, c.impact_time.1
    );
    println!(
        "rebound to {:.5} rad (closed form {:.5} rad)",
        c.rebound_angle.0, c.rebound_angle.1
    );
    println!(
        "rod drift {:.1e} m², smallest wall gap {:.1e} m",
        c.rod_drift, c.min_gap
    );
    // The checks the test relies on: impact within one step, rebound angle to 1e-3 rad,
    // the rod held to round-off, no penetration beyond round-off.
    if (c.impact_time.0 - c.impact_time.1).abs() > 1e-3
        || (c.rebound_angle.0 - c.rebound_angle.1).abs() > 1e-3
        || c.rod_drift > 1e-10
        || c.min_gap < -1e-10
    {
        return Err(format!("the pendulum disagrees with its closed form: {c:?}").into());
    }
    Ok(())
}
