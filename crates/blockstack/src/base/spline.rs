//! A displacement given by samples: the natural cubic spline through them, so that the
//! base's position, velocity and acceleration are continuous between the samples.

use super::BaseKinematics;
use crate::error::BlockError;
use input::finite;

/// A natural cubic spline through samples (tᵢ, xᵢ), with linear extension outside.
#[derive(Debug, Clone, PartialEq)]
pub struct CubicSpline {
    t: Vec<f64>,
    x: Vec<f64>,
    /// Second derivatives at the knots.
    m: Vec<f64>,
}

impl CubicSpline {
    /// The natural cubic spline through the samples (strictly increasing times).
    ///
    /// # Errors
    /// Fewer than two samples, non-finite values, or times not strictly increasing.
    pub fn new(samples: &[(f64, f64)]) -> Result<Self, BlockError> {
        if samples.len() < 2 {
            return Err(BlockError::Scene(
                "a displacement needs at least two samples [t, x]".into(),
            ));
        }
        for (i, &(t, x)) in samples.iter().enumerate() {
            finite(&format!("displacement sample {i} time"), t)?;
            finite(&format!("displacement sample {i} value"), x)?;
        }
        if samples.windows(2).any(|w| w[1].0 <= w[0].0) {
            return Err(BlockError::Scene(
                "displacement sample times must be strictly increasing".into(),
            ));
        }
        let t: Vec<f64> = samples.iter().map(|s| s.0).collect();
        let x: Vec<f64> = samples.iter().map(|s| s.1).collect();
        let n = t.len();
        // Tridiagonal system for the knot curvatures, natural ends m₀ = m_{n−1} = 0.
        let mut m = vec![0.0; n];
        if n > 2 {
            let mut diag = vec![0.0; n];
            let mut rhs = vec![0.0; n];
            let mut upper = vec![0.0; n];
            for i in 1..n - 1 {
                let h0 = t[i] - t[i - 1];
                let h1 = t[i + 1] - t[i];
                diag[i] = 2.0 * (h0 + h1);
                upper[i] = h1;
                rhs[i] = 6.0 * ((x[i + 1] - x[i]) / h1 - (x[i] - x[i - 1]) / h0);
                if i > 1 {
                    let w = h0 / diag[i - 1];
                    diag[i] -= w * upper[i - 1];
                    rhs[i] -= w * rhs[i - 1];
                }
            }
            for i in (1..n - 1).rev() {
                m[i] = (rhs[i] - upper[i] * m[i + 1]) / diag[i];
            }
        }
        Ok(Self { t, x, m })
    }

    /// Displacement relative to the first sample, velocity and acceleration at time s.
    #[must_use]
    pub fn at(&self, s: f64) -> BaseKinematics {
        let n = self.t.len();
        let x_first = self.x[0];
        let seg = |i: usize, s: f64| {
            let (t0, t1) = (self.t[i], self.t[i + 1]);
            let h = t1 - t0;
            let (a, b) = ((t1 - s) / h, (s - t0) / h);
            let (m0, m1) = (self.m[i], self.m[i + 1]);
            let x = a * self.x[i]
                + b * self.x[i + 1]
                + ((a * a * a - a) * m0 + (b * b * b - b) * m1) * h * h / 6.0;
            let v = (self.x[i + 1] - self.x[i]) / h
                + (-(3.0 * a * a - 1.0) * m0 + (3.0 * b * b - 1.0) * m1) * h / 6.0;
            let acc = a * m0 + b * m1;
            (x, v, acc)
        };
        let (x, v, acc) = if s <= self.t[0] {
            let (x, v, _) = seg(0, self.t[0]);
            (x + v * (s - self.t[0]), v, 0.0)
        } else if s >= self.t[n - 1] {
            let (x, v, _) = seg(n - 2, self.t[n - 1]);
            (x + v * (s - self.t[n - 1]), v, 0.0)
        } else {
            let i = self
                .t
                .partition_point(|&ti| ti <= s)
                .saturating_sub(1)
                .min(n - 2);
            seg(i, s)
        };
        BaseKinematics {
            displacement: x - x_first,
            velocity: v,
            acceleration: acc,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::base::motion::tests::check_derivatives;
    use crate::base::BaseMotion;

    #[test]
    fn spline_interpolates_and_is_smooth() {
        let samples: Vec<(f64, f64)> = (0..20)
            .map(|i| (0.1 * f64::from(i), (0.1 * f64::from(i)).sin()))
            .collect();
        let s = CubicSpline::new(&samples).unwrap();
        for &(t, x) in &samples {
            assert!((s.at(t).displacement - x).abs() < 1e-12);
        }
        let m = BaseMotion::Displacement(s);
        for t in [0.35, 0.91, 1.55] {
            check_derivatives(&m, t);
            // A sine sampled at 0.1 is reproduced closely.
            assert!((m.at(t).displacement - t.sin()).abs() < 1e-4);
        }
    }

    #[test]
    fn spline_rejects_bad_samples() {
        assert!(CubicSpline::new(&[(0.0, 0.0)]).is_err());
        assert!(CubicSpline::new(&[(0.0, 0.0), (0.0, 1.0)]).is_err());
        assert!(CubicSpline::new(&[(0.0, 0.0), (1.0, f64::NAN)]).is_err());
    }
}
