//! The skew tensor of a vector and its inverse.

use nalgebra::{Matrix3, Vector3};

/// skewt(a): the skew-symmetric tensor with skewt(a) b = a × b for every b, (2.2.1).
#[must_use]
pub fn skewt(a: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -a.z, a.y, a.z, 0.0, -a.x, -a.y, a.x, 0.0)
}

/// The axial vector of the skew part of `m`: axial(skewt(a)) = a.
#[must_use]
pub fn axial(m: &Matrix3<f64>) -> Vector3<f64> {
    0.5 * Vector3::new(
        m[(2, 1)] - m[(1, 2)],
        m[(0, 2)] - m[(2, 0)],
        m[(1, 0)] - m[(0, 1)],
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cross_product() {
        let a = Vector3::new(1.0, -2.0, 0.5);
        let b = Vector3::new(0.3, 0.7, -1.1);
        assert!((skewt(&a) * b - a.cross(&b)).norm() < 1e-15);
        assert!((axial(&skewt(&a)) - a).norm() < 1e-15);
    }
}
