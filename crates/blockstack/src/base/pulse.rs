//! Acceleration pulses: the idealised near-fault ground motions of the rocking
//! literature, given as the base's acceleration a(t), with velocity and displacement
//! their exact integrals from rest at the pulse's start t₀.
//!
//! - One-sine and one-cosine (Zhang & Makris 2001): a(t) = a_p sin(ω_p τ + ψ) for
//!   0 ≤ τ = t − t₀ ≤ T_p, ω_p = 2π/T_p, zero after; ψ = 0 (one-sine: the velocity rises
//!   and returns to zero, the base ends displaced by a_p T_p²/(2π)) or ψ = π/2
//!   (one-cosine: the acceleration starts at a_p, the velocity is one loop of a sine and
//!   the base ends where it started).
//! - The Ricker wavelet: a(t) = a_p (1 − 2s²) e^{−s²}, s = π(t − t_c)/T_p, whose Fourier
//!   spectrum peaks at the frequency 1/T_p. It never vanishes exactly, so it starts at
//!   t₀ with its centre t_c = t₀ + 2T_p, where |a| < 10⁻¹⁵ a_p: a(t) is taken as zero
//!   before t₀, and v, d are the exact integrals of that truncated wavelet (they agree
//!   with a at every t, and the base ends at rest to within 10⁻¹⁶ a_p T_p).

use super::BaseKinematics;
use crate::error::BlockError;
use input::{finite, positive};
use std::f64::consts::{FRAC_PI_2, PI};

/// Where the Ricker wavelet's centre lies after its start, in periods T_p.
pub const RICKER_DELAY: f64 = 2.0;

/// The form of a pulse.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PulseShape {
    /// a = a_p sin(ω_p τ) over one period.
    OneSine,
    /// a = a_p cos(ω_p τ) over one period.
    OneCosine,
    /// The Ricker wavelet (the second derivative of a Gaussian, "Mexican hat").
    Ricker,
}

impl PulseShape {
    /// The shapes with their names in scene files.
    pub const ALL: [(PulseShape, &'static str); 3] = [
        (PulseShape::OneSine, "one-sine"),
        (PulseShape::OneCosine, "one-cosine"),
        (PulseShape::Ricker, "ricker"),
    ];

    /// The name in scene files: `one-sine`, `one-cosine`, `ricker`.
    #[must_use]
    pub fn name(self) -> &'static str {
        Self::ALL
            .iter()
            .find(|(s, _)| *s == self)
            .map_or("", |(_, n)| n)
    }

    /// The shape of a name.
    ///
    /// # Errors
    /// An unknown name: the error lists the names.
    pub fn from_name(name: &str) -> Result<Self, String> {
        Self::ALL
            .iter()
            .find(|(_, n)| *n == name)
            .map(|(s, _)| *s)
            .ok_or_else(|| {
                let names: Vec<String> =
                    Self::ALL.iter().map(|(_, n)| format!("\"{n}\"")).collect();
                format!(
                    "unknown pulse shape \"{name}\" (expected {})",
                    names.join(", ")
                )
            })
    }
}

/// One pulse of acceleration, starting from rest at `start`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pulse {
    /// The form.
    pub shape: PulseShape,
    /// Peak acceleration a_p (length, or radians, per time unit²; may be negative).
    pub amplitude: f64,
    /// Period T_p (time units).
    pub period: f64,
    /// Start t₀ (time units): at rest before.
    pub start: f64,
}

impl Pulse {
    /// A pulse of the given shape, amplitude a_p, period T_p and start t₀.
    ///
    /// # Errors
    /// A non-finite amplitude or start, a period not finite and positive.
    pub fn new(
        shape: PulseShape,
        amplitude: f64,
        period: f64,
        start: f64,
    ) -> Result<Self, BlockError> {
        Ok(Self {
            shape,
            amplitude: finite("pulse amplitude", amplitude)?,
            period: positive("pulse period", period)?,
            start: finite("pulse start", start)?,
        })
    }

    /// Whether the pulse is over by time t: a one-sine or one-cosine pulse after its
    /// period, which leaves the base at rest ([`Pulse::at`]); never a Ricker pulse, whose
    /// tail goes on.
    #[must_use]
    pub fn ended_by(&self, t: f64) -> bool {
        match self.shape {
            PulseShape::OneSine | PulseShape::OneCosine => t - self.start >= self.period,
            PulseShape::Ricker => false,
        }
    }

    /// Displacement from the position at rest, velocity and acceleration at time t.
    #[must_use]
    pub fn at(&self, t: f64) -> BaseKinematics {
        let tau = t - self.start;
        if tau <= 0.0 {
            return BaseKinematics::default();
        }
        match self.shape {
            PulseShape::OneSine => self.cycloidal(tau, 0.0),
            PulseShape::OneCosine => self.cycloidal(tau, FRAC_PI_2),
            PulseShape::Ricker => self.ricker(tau),
        }
    }

    /// a = a_p sin(ωτ + ψ) on 0 < τ < T_p, integrated from rest; after T_p the velocity
    /// is zero again (cos(2π + ψ) = cos ψ) and the displacement stays at a_p T_p cos ψ / ω.
    fn cycloidal(&self, tau: f64, psi: f64) -> BaseKinematics {
        let omega = 2.0 * PI / self.period;
        let a = self.amplitude;
        if tau >= self.period {
            return BaseKinematics {
                displacement: a * self.period * psi.cos() / omega,
                velocity: 0.0,
                acceleration: 0.0,
            };
        }
        let (s, c) = (omega * tau + psi).sin_cos();
        BaseKinematics {
            displacement: a / omega * (tau * psi.cos() - (s - psi.sin()) / omega),
            velocity: a / omega * (psi.cos() - c),
            acceleration: a * s,
        }
    }

    /// The truncated Ricker wavelet: with s = π(t − t_c)/T_p and s₀ its value at the
    /// start, d/ds[s e^{−s²}] = (1 − 2s²) e^{−s²} and d/ds[−e^{−s²}/2] = s e^{−s²} give v
    /// and d in closed form.
    fn ricker(&self, tau: f64) -> BaseKinematics {
        let k = self.period / PI;
        let s0 = -PI * RICKER_DELAY;
        let s = s0 + tau / k;
        let (e, e0) = ((-s * s).exp(), (-s0 * s0).exp());
        let a = self.amplitude;
        BaseKinematics {
            displacement: a * k * k * (-0.5 * (e - e0) - s0 * e0 * (s - s0)),
            velocity: a * k * (s * e - s0 * e0),
            acceleration: a * (1.0 - 2.0 * s * s) * e,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Midpoint-rule integrals of a pulse's acceleration and of its velocity from 0 to
    /// `t_end`, on a grid that has the pulse's start and end among its nodes (where a
    /// may jump) and never evaluates there.
    fn integrated(p: &Pulse, t_end: f64) -> (f64, f64) {
        let mut nodes = vec![0.0, p.start, p.start + p.period, t_end];
        nodes.retain(|&t| t <= t_end);
        let n = 100_000;
        let (mut v, mut d) = (0.0, 0.0);
        for w in nodes.windows(2) {
            let h = (w[1] - w[0]) / f64::from(n);
            for i in 0..n {
                let k = p.at(w[0] + h * (f64::from(i) + 0.5));
                v += h * k.acceleration;
                d += h * k.velocity;
            }
        }
        (v, d)
    }

    #[test]
    fn velocity_and_displacement_are_the_integrals_of_the_acceleration() {
        for (shape, _) in PulseShape::ALL {
            let p = Pulse::new(shape, 0.7, 0.8, 0.3).unwrap();
            for t_end in [0.5, 0.9, 1.4, 2.9, 5.0] {
                let (v, d) = integrated(&p, t_end);
                let k = p.at(t_end);
                assert!(
                    (k.velocity - v).abs() < 1e-9,
                    "{shape:?} v at {t_end}: {} vs {v}",
                    k.velocity
                );
                assert!(
                    (k.displacement - d).abs() < 1e-9,
                    "{shape:?} d at {t_end}: {} vs {d}",
                    k.displacement
                );
            }
        }
    }

    #[test]
    fn the_classic_forms_have_their_closed_form_ends() {
        let (ap, tp) = (0.5, 2.0);
        let sine = Pulse::new(PulseShape::OneSine, ap, tp, 0.0).unwrap();
        // v = a_p T_p/(2π) (1 − cos ω_p t): the peak velocity a_p T_p/π at T_p/2.
        assert!((sine.at(1.0).velocity - ap * tp / PI).abs() < 1e-15);
        let end = sine.at(10.0);
        assert_eq!((end.velocity, end.acceleration), (0.0, 0.0));
        assert!((end.displacement - ap * tp * tp / (2.0 * PI)).abs() < 1e-15);
        let cosine = Pulse::new(PulseShape::OneCosine, ap, tp, 0.0).unwrap();
        assert!((cosine.at(0.5).velocity - ap * tp / (2.0 * PI)).abs() < 1e-15);
        assert!(cosine.at(10.0).displacement.abs() < 1e-15);
        let ricker = Pulse::new(PulseShape::Ricker, ap, tp, 0.0).unwrap();
        let centre = ricker.at(RICKER_DELAY * tp);
        assert!((centre.acceleration - ap).abs() < 1e-15);
        assert!(ricker.at(20.0 * tp).velocity.abs() < 1e-15);
    }

    #[test]
    fn a_pulse_is_at_rest_before_it_starts() {
        for (shape, _) in PulseShape::ALL {
            let p = Pulse::new(shape, 1.0, 0.5, 1.0).unwrap();
            for t in [-1.0, 0.0, 0.999, 1.0] {
                assert_eq!(p.at(t), BaseKinematics::default(), "{shape:?} at {t}");
            }
            // Just after the start, at rest still to first order: v = O(τ).
            assert!(p.at(1.0 + 1e-9).velocity.abs() < 1e-8);
        }
    }

    #[test]
    fn bad_pulses_are_refused() {
        assert!(Pulse::new(PulseShape::Ricker, 1.0, 0.0, 0.0).is_err());
        assert!(Pulse::new(PulseShape::OneSine, f64::NAN, 1.0, 0.0).is_err());
        let e = PulseShape::from_name("square").unwrap_err();
        assert!(
            e.contains("\"one-sine\", \"one-cosine\", \"ricker\""),
            "{e}"
        );
        assert_eq!(PulseShape::from_name("ricker").unwrap().name(), "ricker");
    }
}
