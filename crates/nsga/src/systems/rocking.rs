//! A rigid rectangular block rocking on its two bottom corners (Housner 1963).
//!
//! q = (x, y, θ), half-width b, half-height h, half-diagonal R = √(b² + h²),
//! slenderness α = atan(b/h), Θ = m R²/3. Bottom corners s = ±1 at body point (s b, −h):
//!
//! ```text
//!     g_N,s = y + s b sin θ − h cos θ,   W_N,s = (0, 1, s b cos θ + h sin θ),
//!     γ_F,s = ẋ + (h cos θ − s b sin θ) θ̇,
//! ```
//!
//! with the curvature terms ζ from differentiating once more. W depends on θ, so this
//! system relies on the default (automatic-differentiation) derivatives.
//!
//! Rocking on one corner: θ̈ = −p² sin(α − |θ|) sgn θ, p² = 3g/(4R). A corner impact
//! with e_N = 0 and sticking friction multiplies θ̇ by 1 − (3/2) sin²α.

use crate::system::{Evaluation, FrictionLaw, Layout, Scalar, System};

/// The rocking block.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RockingBlock {
    /// Mass m.
    pub mass: f64,
    /// Half-width b.
    pub half_width: f64,
    /// Half-height h.
    pub half_height: f64,
    /// Gravity g.
    pub gravity: f64,
    /// Friction coefficient μ (large: the corners stick).
    pub mu: f64,
    /// Normal restitution e_N of both corners.
    pub e_n: f64,
}

impl RockingBlock {
    /// A slender unit block, b = 0.1, h = 0.5 (α ≈ 11.3°), g = 9.81, whose corners stick
    /// (μ = 10) and do not bounce (e_N = 0): nonlinear in θ, with impacts that change the
    /// index sets. The tests of the Newton variants and fallbacks share it.
    #[must_use]
    pub fn slender() -> Self {
        Self {
            mass: 1.0,
            half_width: 0.1,
            half_height: 0.5,
            gravity: 9.81,
            mu: 10.0,
            e_n: 0.0,
        }
    }
    /// Slenderness α = atan(b/h).
    #[must_use]
    pub fn alpha(&self) -> f64 {
        (self.half_width / self.half_height).atan()
    }
    /// Half-diagonal R.
    #[must_use]
    pub fn half_diagonal(&self) -> f64 {
        self.half_width.hypot(self.half_height)
    }
    /// p² = 3g/(4R).
    #[must_use]
    pub fn p_squared(&self) -> f64 {
        3.0 * self.gravity / (4.0 * self.half_diagonal())
    }
    /// Θ = m R²/3 about the centre.
    #[must_use]
    pub fn inertia(&self) -> f64 {
        self.mass * self.half_diagonal().powi(2) / 3.0
    }
    /// Housner's angular-velocity ratio of a corner impact, 1 − (3/2) sin²α.
    #[must_use]
    pub fn impact_ratio(&self) -> f64 {
        1.0 - 1.5 * self.alpha().sin().powi(2)
    }
    /// Initial state at rest, tilted by θ0 ∈ (0, α) on the corner s = −1 at x = 0.
    #[must_use]
    pub fn tilted(&self, theta0: f64) -> ([f64; 3], [f64; 3]) {
        let (b, h) = (self.half_width, self.half_height);
        let (s, c) = theta0.sin_cos();
        ([b * c - h * s, b * s + h * c, theta0], [0.0; 3])
    }
    /// Time from rest at θ0 to the first impact (θ = 0), by quadrature of the energy
    /// integral θ̇² = 2p² (cos(α − θ0) − cos(α − θ)); the substitution θ = θ0 (1 − w²)
    /// removes the square-root singularity at θ0 (composite Simpson, `n` even panels).
    #[must_use]
    pub fn time_to_first_impact(&self, theta0: f64, n: usize) -> f64 {
        let (a, p2) = (self.alpha(), self.p_squared());
        let f = |w: f64| {
            if w == 0.0 {
                // limit: 2θ0 w / √(2p² sin(α − θ0) θ0 w²)
                return 2.0 * theta0 / (2.0 * p2 * (a - theta0).sin() * theta0).sqrt();
            }
            let th = theta0 * (1.0 - w * w);
            2.0 * theta0 * w / (2.0 * p2 * ((a - theta0).cos() - (a - th).cos())).sqrt()
        };
        let n = n.max(2) & !1;
        let hstep = 1.0 / n as f64;
        let mut s = f(0.0) + f(1.0);
        for i in 1..n {
            s += if i % 2 == 1 { 4.0 } else { 2.0 } * f(i as f64 * hstep);
        }
        s * hstep / 3.0
    }
    /// Housner's slender-block approximation (1/p) arccosh(1/(1 − θ0/α)).
    #[must_use]
    pub fn housner_time(&self, theta0: f64) -> f64 {
        (1.0 / (1.0 - theta0 / self.alpha())).acosh() / self.p_squared().sqrt()
    }
}

impl System for RockingBlock {
    fn layout(&self) -> Layout {
        Layout {
            nq: 3,
            nu: 3,
            e_n: vec![self.e_n; 2],
            friction: vec![
                FrictionLaw {
                    components: 1,
                    mu: self.mu,
                    e_f: 0.0,
                    normals: vec![0],
                },
                FrictionLaw {
                    components: 1,
                    mu: self.mu,
                    e_f: 0.0,
                    normals: vec![1],
                },
            ],
            ..Layout::default()
        }
    }
    fn evaluate<T: Scalar>(&self, _t: f64, q: &[T], u: &[T], out: &mut Evaluation<T>) {
        let (b, h, m) = (self.half_width, self.half_height, self.mass);
        out.mass.push(0, 0, T::from(m));
        out.mass.push(1, 1, T::from(m));
        out.mass.push(2, 2, T::from(self.inertia()));
        out.forces[1] = T::from(-m * self.gravity);
        let (s, c) = (q[2].sin(), q[2].cos());
        let w2 = u[2] * u[2];
        for (k, sign) in [1.0, -1.0].into_iter().enumerate() {
            out.position[k] = q[1] + s * (sign * b) - c * h;
            out.position_w.push(1, k, T::from(1.0));
            out.position_w.push(2, k, c * (sign * b) + s * h);
            out.position_zeta[k] = (c * h - s * (sign * b)) * w2;
            out.velocity_w.push(0, k, T::from(1.0));
            out.velocity_w.push(2, k, c * h - s * (sign * b));
            out.velocity_zeta[k] = (-c * (sign * b) - s * h) * w2;
        }
    }
}
