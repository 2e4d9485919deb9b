//! A block (point contact) on an incline whose angle β(t) = β0 + β̇ t may change in time.
//!
//! Coordinates in the incline frame: x along the slope (downhill positive), y normal to
//! it; gravity has components g (sin β, −cos β). The incline turns slowly: the
//! fictitious forces of the rotating frame are left out (a tilting table whose rate
//! β̇ is small), so the analytic answer is: stick while tan β < μ, then slide with
//! ẍ = g (sin β − μ cos β).

use crate::system::{Derivatives, Evaluation, FrictionLaw, Layout, Probes, Scalar, System};

/// The incline benchmark.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Incline {
    /// Mass m.
    pub mass: f64,
    /// Gravity g.
    pub gravity: f64,
    /// Friction coefficient μ.
    pub mu: f64,
    /// Angle β0 at t = 0 (rad).
    pub beta0: f64,
    /// Rate β̇ (rad/s).
    pub beta_rate: f64,
}

impl Incline {
    /// β(t).
    #[must_use]
    pub fn beta(&self, t: f64) -> f64 {
        self.beta0 + self.beta_rate * t
    }
    /// Sliding acceleration g(sin β − μ cos β) for a constant angle (0 when it sticks).
    #[must_use]
    pub fn sliding_acceleration(&self) -> f64 {
        let b = self.beta0;
        if b.tan() < self.mu {
            0.0
        } else {
            self.gravity * (b.sin() - self.mu * b.cos())
        }
    }
    /// Time at which a turning incline (β̇ > 0, starting below) reaches tan β = μ.
    #[must_use]
    pub fn slip_onset_time(&self) -> f64 {
        (self.mu.atan() - self.beta0) / self.beta_rate
    }
    /// Exact x(t) for a turning incline from rest at x = 0: zero until t*, then
    /// ẍ = g(sin β − μ cos β) integrated twice in closed form.
    #[must_use]
    pub fn turning_position(&self, t: f64) -> f64 {
        let ts = self.slip_onset_time();
        if t <= ts {
            return 0.0;
        }
        let (g, mu, w) = (self.gravity, self.mu, self.beta_rate);
        // F(t) = ∫ (sin β − μ cos β) dt = (−cos β − μ sin β)/w; ẋ = g (F(t) − F(t*)).
        let f = |t: f64| (-self.beta(t).cos() - mu * self.beta(t).sin()) / w;
        // G(t) = ∫ F dt = (−sin β + μ cos β)/w².
        let gg = |t: f64| (-self.beta(t).sin() + mu * self.beta(t).cos()) / (w * w);
        g * (gg(t) - gg(ts) - f(ts) * (t - ts))
    }
}

impl System for Incline {
    fn layout(&self) -> Layout {
        Layout {
            nq: 2,
            nu: 2,
            e_n: vec![0.0],
            friction: vec![FrictionLaw {
                components: 1,
                mu: self.mu,
                e_f: 0.0,
                normals: vec![0],
            }],
            ..Layout::default()
        }
    }
    fn evaluate<T: Scalar>(&self, t: f64, q: &[T], _u: &[T], out: &mut Evaluation<T>) {
        let m = self.mass;
        out.mass.push(0, 0, T::from(m));
        out.mass.push(1, 1, T::from(m));
        let b = self.beta(t);
        out.forces[0] = T::from(m * self.gravity * b.sin());
        out.forces[1] = T::from(-m * self.gravity * b.cos());
        out.position[0] = q[1];
        out.position_w.push(1, 0, T::from(1.0));
        out.velocity_w.push(0, 0, T::from(1.0));
    }
    /// Constant W, M and state-independent h: the only derivative is ∂g_N/∂y = 1.
    fn derivatives(&self, _t: f64, _q: &[f64], _u: &[f64], _p: &Probes<'_>, out: &mut Derivatives) {
        out.position_q.push(0, 1, 1.0);
    }
}
