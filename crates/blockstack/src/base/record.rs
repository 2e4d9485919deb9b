//! A recorded acceleration (an accelerogram) as a base motion: a(t) is taken piecewise
//! linear between the samples and integrated exactly, so that the position, velocity and
//! acceleration the integrator asks for at any t agree (as the spline of a displacement
//! does, ERRATA 20).
//!
//! Before the first sample the base is at rest; after the last one its acceleration is
//! zero and it keeps its end velocity (zero after the baseline correction).
//!
//! **Baseline correction** ([`Baseline::EndAtRest`], the default). The double integral
//! of a recorded acceleration drifts: a small offset or a long-period error in a(t)
//! grows linearly in v and quadratically in d, so the raw record usually ends moving,
//! far from where it started, which no shake table and no ground does. The correction
//! subtracts from a(t) the straight line c₀ + c₁(t − t₀) for which the record ends at
//! rest where it started, v(t_end) = 0 and d(t_end) = 0. That is removing the cubic
//! c₀τ²/2 + c₁τ³/6 from the displacement: the lowest-degree correction that meets both
//! conditions, and, being linear in t, it keeps a(t) piecewise linear, so the
//! integration stays exact. It changes the record's peak acceleration by at most
//! |c₀| + |c₁|(t_end − t₀), which is small for a record that is nearly at rest at its
//! ends. [`Baseline::None`] keeps the raw record.

use super::BaseKinematics;
use crate::error::BlockError;

/// How a record is corrected before it is integrated (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Baseline {
    /// Subtract the line from a(t) that makes the record end at rest where it started.
    #[default]
    EndAtRest,
    /// The record as read.
    None,
}

impl Baseline {
    /// The corrections with their names in scene files.
    pub const ALL: [(Baseline, &'static str); 2] = [
        (Baseline::EndAtRest, "end-at-rest"),
        (Baseline::None, "none"),
    ];

    /// The correction of a name.
    ///
    /// # Errors
    /// An unknown name: the error lists the names.
    pub fn from_name(name: &str) -> Result<Self, String> {
        Self::ALL
            .iter()
            .find(|(_, n)| *n == name)
            .map(|(b, _)| *b)
            .ok_or_else(|| {
                format!("unknown baseline \"{name}\" (expected \"end-at-rest\" or \"none\")")
            })
    }
}

/// A piecewise-linear acceleration with its exact velocity and displacement at the
/// samples (from rest at the first sample).
#[derive(Debug, Clone, PartialEq)]
pub struct Accelerogram {
    t: Vec<f64>,
    a: Vec<f64>,
    v: Vec<f64>,
    d: Vec<f64>,
}

impl Accelerogram {
    /// The record through the samples (tᵢ, aᵢ), integrated from rest at t₀.
    ///
    /// # Errors
    /// Fewer than two samples, a value not finite, or times not strictly increasing
    /// (naming the sample, counted from 1).
    pub fn new(samples: &[(f64, f64)]) -> Result<Self, BlockError> {
        if samples.len() < 2 {
            return Err(BlockError::Record(format!(
                "a record needs at least two samples, got {}",
                samples.len()
            )));
        }
        for (i, &(t, a)) in samples.iter().enumerate() {
            if !t.is_finite() || !a.is_finite() {
                return Err(BlockError::Record(format!(
                    "record sample {} is not finite",
                    i + 1
                )));
            }
            if i > 0 && t <= samples[i - 1].0 {
                return Err(BlockError::Record(format!(
                    "record sample {} is at t = {}, not after the one before (t = {})",
                    i + 1,
                    input::Short(t),
                    input::Short(samples[i - 1].0)
                )));
            }
        }
        let t = samples.iter().map(|s| s.0).collect();
        let a = samples.iter().map(|s| s.1).collect();
        Ok(Self::integrated(t, a))
    }

    /// The velocity and displacement at the samples: on each interval of length h, with
    /// a linear from a₀ to a₁, v gains h(a₀ + a₁)/2 and d gains v₀h + h²(2a₀ + a₁)/6.
    fn integrated(t: Vec<f64>, a: Vec<f64>) -> Self {
        let n = t.len();
        let (mut v, mut d) = (vec![0.0; n], vec![0.0; n]);
        for i in 1..n {
            let h = t[i] - t[i - 1];
            v[i] = v[i - 1] + 0.5 * h * (a[i - 1] + a[i]);
            d[i] = d[i - 1] + v[i - 1] * h + h * h * (2.0 * a[i - 1] + a[i]) / 6.0;
        }
        Self { t, a, v, d }
    }

    /// The record corrected as `baseline` says (module docs).
    #[must_use]
    pub fn corrected(self, baseline: Baseline) -> Self {
        match baseline {
            Baseline::None => self,
            Baseline::EndAtRest => self.ending_at_rest(),
        }
    }

    /// The record minus the line c₀ + c₁τ (τ = t − t₀) whose integrals over the record's
    /// length T are its end velocity V and displacement D:
    /// c₀T + c₁T²/2 = V and c₀T²/2 + c₁T³/6 = D.
    fn ending_at_rest(self) -> Self {
        let n = self.t.len();
        let t0 = self.t[0];
        let big_t = self.t[n - 1] - t0;
        let (v, d) = (self.v[n - 1], self.d[n - 1]);
        let c0 = -2.0 * v / big_t + 6.0 * d / (big_t * big_t);
        let c1 = 6.0 * v / (big_t * big_t) - 12.0 * d / (big_t * big_t * big_t);
        let a = self
            .t
            .iter()
            .zip(&self.a)
            .map(|(&t, &a)| a - (c0 + c1 * (t - t0)))
            .collect();
        let mut at_rest = Self::integrated(self.t, a);
        // The line makes the end velocity zero; its integration leaves round-off, which
        // would move the base on after the record, slowly but for good.
        at_rest.v[n - 1] = 0.0;
        at_rest
    }

    /// The record with every acceleration (and so velocity and displacement) times k.
    #[must_use]
    pub fn scaled(mut self, k: f64) -> Self {
        for x in self.a.iter_mut().chain(&mut self.v).chain(&mut self.d) {
            *x *= k;
        }
        self
    }

    /// The peak |a| (at a sample: a is linear between them).
    #[must_use]
    pub fn peak(&self) -> f64 {
        self.a.iter().fold(0.0, |m, a| m.max(a.abs()))
    }

    /// The times, accelerations, velocities and displacements at the samples.
    #[must_use]
    pub fn samples(&self) -> [&[f64]; 4] {
        [&self.t, &self.a, &self.v, &self.d]
    }

    /// The time of the last sample.
    #[must_use]
    pub fn end(&self) -> f64 {
        self.t[self.t.len() - 1]
    }

    /// Whether the base stands still from time `s` on: at or after the last sample, with
    /// the record ending at rest (zero velocity there; [`Accelerogram::at`] then keeps
    /// the last displacement).
    #[must_use]
    pub fn at_rest_from(&self, s: f64) -> bool {
        let n = self.t.len();
        s >= self.t[n - 1] && self.v[n - 1] == 0.0
    }

    /// Displacement from the position at rest, velocity and acceleration at time s.
    #[must_use]
    pub fn at(&self, s: f64) -> BaseKinematics {
        let n = self.t.len();
        if s <= self.t[0] {
            return BaseKinematics::default();
        }
        if s >= self.t[n - 1] {
            let (v, d) = (self.v[n - 1], self.d[n - 1]);
            return BaseKinematics {
                displacement: d + v * (s - self.t[n - 1]),
                velocity: v,
                acceleration: 0.0,
            };
        }
        // t₀ < s < t_end: at least the first sample lies at or before s.
        let i = self.t.partition_point(|&ti| ti <= s).saturating_sub(1);
        let (h, tau) = (self.t[i + 1] - self.t[i], s - self.t[i]);
        let (a0, slope) = (self.a[i], (self.a[i + 1] - self.a[i]) / h);
        BaseKinematics {
            displacement: self.d[i] + tau * (self.v[i] + tau * (0.5 * a0 + tau * slope / 6.0)),
            velocity: self.v[i] + tau * (a0 + 0.5 * tau * slope),
            acceleration: a0 + tau * slope,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sampled(f: impl Fn(f64) -> f64, dt: f64, n: u32) -> Accelerogram {
        let s: Vec<(f64, f64)> = (0..=n)
            .map(|i| (dt * f64::from(i), f(dt * f64::from(i))))
            .collect();
        Accelerogram::new(&s).unwrap()
    }

    #[test]
    fn a_constant_acceleration_integrates_exactly() {
        let r = sampled(|_| 0.3, 0.01, 500);
        for t in [0.013, 1.0, 2.4567, 4.999] {
            let k = r.at(t);
            assert!((k.velocity - 0.3 * t).abs() < 1e-13, "{t}");
            assert!((k.displacement - 0.15 * t * t).abs() < 1e-13, "{t}");
            assert_eq!(k.acceleration, 0.3);
        }
        // After the record: no acceleration, the end velocity kept.
        let after = r.at(6.0);
        assert_eq!(after.acceleration, 0.0);
        assert!((after.velocity - 1.5).abs() < 1e-13);
        assert!((after.displacement - (0.15 * 25.0 + 1.5)).abs() < 1e-12);
        assert_eq!(r.at(-1.0), BaseKinematics::default());
    }

    #[test]
    fn a_sampled_sine_integrates_to_its_analytic_integrals() {
        // a = A sin ωt from rest: v = A(1 − cos ωt)/ω, d = A(t − sin(ωt)/ω)/ω.
        let (amp, om) = (0.8, 5.0);
        let r = sampled(|t| amp * (om * t).sin(), 0.001, 3000);
        for t in [0.1, 0.77, 1.5, 2.9] {
            let k = r.at(t);
            let v = amp * (1.0 - (om * t).cos()) / om;
            let d = amp * (t - (om * t).sin() / om) / om;
            assert!(
                (k.velocity - v).abs() < 1e-6,
                "v at {t}: {} vs {v}",
                k.velocity
            );
            assert!(
                (k.displacement - d).abs() < 1e-6,
                "d at {t}: {} vs {d}",
                k.displacement
            );
        }
    }

    #[test]
    fn position_velocity_and_acceleration_agree_between_samples() {
        let r = sampled(|t| (7.0 * t).sin() + 0.2, 0.05, 40);
        let h = 1e-6;
        for t in [0.111, 0.93, 1.51] {
            let (p, m, k) = (r.at(t + h), r.at(t - h), r.at(t));
            assert!(((p.displacement - m.displacement) / (2.0 * h) - k.velocity).abs() < 1e-8);
            assert!(((p.velocity - m.velocity) / (2.0 * h) - k.acceleration).abs() < 1e-7);
        }
    }

    #[test]
    fn the_baseline_correction_ends_the_record_at_rest_where_it_started() {
        let raw = sampled(|t| (3.0 * t).sin() + 0.05, 0.01, 700);
        let end = raw.end();
        assert!(raw.at(end).velocity.abs() > 0.1);
        let r = raw.corrected(Baseline::EndAtRest);
        let k = r.at(end);
        assert_eq!(k.velocity, 0.0);
        assert!(r.at_rest_from(end) && !r.at_rest_from(0.5 * end));
        assert!(k.displacement.abs() < 1e-12, "{}", k.displacement);
        assert!((r.at(end + 3.0).displacement - k.displacement).abs() < 1e-12);
        // The correction is a line: a sampled line is corrected to nothing.
        let line = sampled(|t| 0.4 - 0.1 * t, 0.1, 50).corrected(Baseline::EndAtRest);
        assert!(line.peak() < 1e-12, "{}", line.peak());
    }

    #[test]
    fn scaling_scales_every_quantity() {
        let r = sampled(|t| (2.0 * t).cos(), 0.01, 200);
        let k = r.at(1.234);
        let s = r.clone().scaled(-2.5).at(1.234);
        let same = |a: f64, b: f64| (a - b).abs() <= 1e-15 * b.abs();
        assert!(same(s.acceleration, -2.5 * k.acceleration));
        assert!(same(s.velocity, -2.5 * k.velocity));
        assert!(same(s.displacement, -2.5 * k.displacement));
        assert_eq!(r.peak(), 1.0);
    }

    #[test]
    fn bad_samples_are_refused() {
        assert!(Accelerogram::new(&[(0.0, 1.0)]).is_err());
        let e = Accelerogram::new(&[(0.0, 1.0), (0.1, 1.0), (0.1, 2.0)]).unwrap_err();
        assert!(e.to_string().contains("sample 3"), "{e}");
        assert!(Accelerogram::new(&[(0.0, 1.0), (0.1, f64::INFINITY)]).is_err());
    }
}
