//! The rotating bouncing ball of the paper's first example (Capobianco et al. 2021 §5.1).
//!
//! A disc in the plane with coordinates q = (x, y, φ), mass m, radius R and the inertia
//! of a solid sphere Θ = (2/5) m R² (the paper's value: it gives the rolling speed
//! ẋ = −(2/7) R ω0 of its case 2), dropped on the ground y = 0 under gravity g.
//! Gap g_N = y − R, slip of the contact point γ_F = ẋ + R φ̇.
//!
//! Analytic answers: first impact at t = √(2(y0 − R)/g); with e_N = 0 the friction
//! percussion at impact is at most μ m v_impact and reduces the slip by it times
//! (1/m + R²/Θ); afterwards sliding friction μ m g reduces the slip at the rate
//! μ g (1 + m R²/Θ) until rolling; during sliding and rolling m ẋ − (Θ/R) φ̇ is
//! conserved (angular momentum about the contact point), so rolling ends at
//! ẋ = (m ẋ0 − (Θ/R) φ̇0)/(m + Θ/R²).

use crate::system::{Derivatives, Evaluation, FrictionLaw, Layout, Probes, Scalar, System};

/// The bouncing ball.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ball {
    /// Mass m.
    pub mass: f64,
    /// Radius R.
    pub radius: f64,
    /// Gravity g.
    pub gravity: f64,
    /// Friction coefficient μ.
    pub mu: f64,
    /// Normal restitution e_N.
    pub e_n: f64,
    /// Tangential restitution e_F.
    pub e_f: f64,
}

impl Ball {
    /// Moment of inertia Θ = (2/5) m R².
    #[must_use]
    pub fn inertia(&self) -> f64 {
        0.4 * self.mass * self.radius * self.radius
    }
    /// The conserved m ẋ − (Θ/R) φ̇ divided by m + Θ/R²: the final rolling ẋ.
    #[must_use]
    pub fn rolling_velocity(&self, xdot: f64, phidot: f64) -> f64 {
        let (m, r, th) = (self.mass, self.radius, self.inertia());
        (m * xdot - th / r * phidot) / (m + th / (r * r))
    }
}

impl System for Ball {
    fn layout(&self) -> Layout {
        Layout {
            nq: 3,
            nu: 3,
            e_n: vec![self.e_n],
            friction: vec![FrictionLaw {
                components: 1,
                mu: self.mu,
                e_f: self.e_f,
                normals: vec![0],
            }],
            ..Layout::default()
        }
    }
    fn evaluate<T: Scalar>(&self, _t: f64, q: &[T], _u: &[T], out: &mut Evaluation<T>) {
        let m = self.mass;
        out.mass.push(0, 0, T::from(m));
        out.mass.push(1, 1, T::from(m));
        out.mass.push(2, 2, T::from(self.inertia()));
        out.forces[1] = T::from(-m * self.gravity);
        out.position[0] = q[1] - self.radius;
        out.position_w.push(1, 0, T::from(1.0));
        out.velocity_w.push(0, 0, T::from(1.0));
        out.velocity_w.push(2, 0, T::from(self.radius));
    }
    /// Constant M, h and W: the only derivative is ∂g_N/∂y = 1.
    fn derivatives(&self, _t: f64, _q: &[f64], _u: &[f64], _p: &Probes<'_>, out: &mut Derivatives) {
        out.position_q.push(0, 1, 1.0);
    }
}

/// The paper's four cases (issue 4): parameters and initial state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BallCase {
    /// Case number 1–4.
    pub case: u8,
    /// The system.
    pub ball: Ball,
    /// q0 = (x0, y0, φ0).
    pub q0: [f64; 3],
    /// u0 = (ẋ0, ẏ0, φ̇0).
    pub u0: [f64; 3],
    /// Time span simulated (s).
    pub t_end: f64,
}

impl BallCase {
    /// Case 1: e_N = 0.5, ω0 = 0. Case 2: e_N = 0, ω0 = 50. Case 3: e_N = 0, ω0 = 10.
    /// Case 4: e_N = 0.5, ω0 = 50, x0 = −0.5, ẋ0 = 1. Always m = 1, R = 0.1, μ = 0.2,
    /// g = 9.81, y0 = 1, 1.5 s.
    ///
    /// # Errors
    /// A message for a case number outside 1–4.
    pub fn new(case: u8) -> Result<Self, String> {
        let (e_n, omega0, x0, xdot0) = match case {
            1 => (0.5, 0.0, 0.0, 0.0),
            2 => (0.0, 50.0, 0.0, 0.0),
            3 => (0.0, 10.0, 0.0, 0.0),
            4 => (0.5, 50.0, -0.5, 1.0),
            _ => return Err(format!("ball case {case} does not exist (1, 2, 3 or 4)")),
        };
        Ok(Self {
            case,
            ball: Ball {
                mass: 1.0,
                radius: 0.1,
                gravity: 9.81,
                mu: 0.2,
                e_n,
                e_f: 0.0,
            },
            q0: [x0, 1.0, 0.0],
            u0: [xdot0, 0.0, omega0],
            t_end: 1.5,
        })
    }
    /// Time of the first impact, √(2(y0 − R)/g).
    #[must_use]
    pub fn first_impact_time(&self) -> f64 {
        (2.0 * (self.q0[1] - self.ball.radius) / self.ball.gravity).sqrt()
    }

    /// Exact x(t) for the cases with e_N = 0 (2 and 3; None otherwise): free fall to t1;
    /// the impact stops the fall and its friction percussion, at most μ m v1, cuts the
    /// slip ẋ + Rφ̇; sliding friction μ m g then decelerates x until rolling, after which
    /// ẋ is constant (m ẋ − (Θ/R) φ̇ is conserved).
    #[must_use]
    pub fn exact_x(&self, t: f64) -> Option<f64> {
        if self.ball.e_n != 0.0 || self.ball.e_f != 0.0 {
            return None;
        }
        let b = &self.ball;
        let (m, r, g, mu) = (b.mass, b.radius, b.gravity, b.mu);
        let k = 1.0 / m + r * r / b.inertia();
        let t1 = self.first_impact_time();
        let (x0, xd0, w0) = (self.q0[0], self.u0[0], self.u0[2]);
        if t <= t1 {
            return Some(x0 + xd0 * t);
        }
        let x1 = x0 + xd0 * t1;
        let v1 = g * t1;
        let slip0 = xd0 + r * w0;
        let p_stick = slip0.abs() / k;
        let sign = slip0.signum();
        let x_roll = b.rolling_velocity(xd0, w0);
        if p_stick <= mu * m * v1 {
            return Some(x1 + x_roll * (t - t1));
        }
        let xd1 = xd0 - sign * mu * v1;
        let slip1 = slip0 - sign * mu * m * v1 * k;
        let tr = t1 + slip1.abs() / (mu * m * g * k);
        let acc = -sign * mu * g;
        if t <= tr {
            let s = t - t1;
            return Some(x1 + xd1 * s + 0.5 * acc * s * s);
        }
        let s = tr - t1;
        Some(x1 + xd1 * s + 0.5 * acc * s * s + x_roll * (t - tr))
    }
}
