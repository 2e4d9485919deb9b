//! The angular velocity of a rotation given by a time-varying axis and angle, (2.2.5).

use nalgebra::Vector3;

/// ω_R = θ̇ r + sin θ ṙ + (1 − cos θ) r × ṙ for R(θ(t), r(t)), (2.2.5), from
/// skewt(ω_R) = Ṙ Rᵀ. `axis` must be a unit vector and `axis_rate` orthogonal to it.
#[must_use]
pub fn axis_angle_angular_velocity(
    angle: f64,
    angle_rate: f64,
    axis: &Vector3<f64>,
    axis_rate: &Vector3<f64>,
) -> Vector3<f64> {
    angle_rate * axis + angle.sin() * axis_rate + (1.0 - angle.cos()) * axis.cross(axis_rate)
}
