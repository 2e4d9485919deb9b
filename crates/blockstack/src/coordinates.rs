//! The coordinates of a block, (4.2.1)–(4.2.2): the centre of mass r = x E₁ + y E₂ and the
//! angle θ of the co-rotational basis e₁ = cos θ E₁ + sin θ E₂, e₂ = −sin θ E₁ + cos θ E₂.
//!
//! Everything that depends on the coordinates is generic over a [`Scalar`]: `f64` for
//! values, a `num-dual` dual number for exact derivatives of any order (a time stepper
//! differentiates its residual through these functions). Sizes and other parameters stay
//! `f64`. Case distinctions (which corner touches which face) look at real parts only.

use num_dual::DualNum;
use std::ops::{Add, Mul, Neg, Sub};

/// A number the geometry is written in: `f64`, or a dual number over `f64`.
pub trait Scalar: DualNum<Primitive = f64> + Copy {}
impl<T: DualNum<Primitive = f64> + Copy> Scalar for T {}

/// The real part of a scalar (the value itself for `f64`).
#[must_use]
pub fn re<T: Scalar>(x: T) -> f64 {
    x.re()
}

/// A 2D vector on the fixed basis {E₁, E₂} (or on a body basis {e₁, e₂} where said).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Vec2<T = f64> {
    /// First component.
    pub x: T,
    /// Second component.
    pub y: T,
}

impl<T: Scalar> Vec2<T> {
    /// The vector (x, y).
    #[must_use]
    pub fn new(x: T, y: T) -> Self {
        Self { x, y }
    }

    /// The dot product.
    #[must_use]
    pub fn dot(&self, other: &Self) -> T {
        self.x * other.x + self.y * other.y
    }

    /// The Euclidean norm.
    #[must_use]
    pub fn norm(&self) -> T {
        self.dot(self).sqrt()
    }

    /// A constant vector lifted to the scalar type.
    #[must_use]
    pub fn lift(v: &Vec2<f64>) -> Self {
        Self::new(T::from(v.x), T::from(v.y))
    }

    /// The real parts.
    #[must_use]
    pub fn re(&self) -> Vec2<f64> {
        Vec2 {
            x: self.x.re(),
            y: self.y.re(),
        }
    }
}

impl<T: Scalar> Add for Vec2<T> {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        Self::new(self.x + o.x, self.y + o.y)
    }
}

impl<T: Scalar> Sub for Vec2<T> {
    type Output = Self;
    fn sub(self, o: Self) -> Self {
        Self::new(self.x - o.x, self.y - o.y)
    }
}

impl<T: Scalar> Neg for Vec2<T> {
    type Output = Self;
    fn neg(self) -> Self {
        Self::new(-self.x, -self.y)
    }
}

impl<T: Scalar> Mul<T> for Vec2<T> {
    type Output = Self;
    fn mul(self, s: T) -> Self {
        Self::new(self.x * s, self.y * s)
    }
}

/// E₃ × v for v in the plane: the vector v turned by +π/2.
#[must_use]
pub fn perp<T: Scalar>(v: &Vec2<T>) -> Vec2<T> {
    Vec2::new(-v.y, v.x)
}

/// The configuration (x, y, θ) of one body, (4.2.1)–(4.2.2).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Pose<T = f64> {
    /// x, the E₁ coordinate of the centre of mass.
    pub x: T,
    /// y, the E₂ coordinate of the centre of mass.
    pub y: T,
    /// θ, the angle from E₁ to e₁ (counter-clockwise positive).
    pub theta: T,
}

/// The real parts of a pose with its basis evaluated once: the centre r and e₁, e₂ of
/// (4.2.1)–(4.2.2). For the decisions that read one pose many times (which gap of
/// (G.2.2), the support test (G.2.4)), each of which [`Pose::e1`], [`Pose::e2`] and
/// [`Pose::point`] would compute sin θ and cos θ again (in the scalar type, a dual number
/// in a derivative pass). Its values equal the real parts of those methods' to the bit:
/// the same operations on the same numbers.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frame {
    /// The centre of mass r.
    pub r: Vec2<f64>,
    /// e₁ = (cos θ, sin θ).
    pub e1: Vec2<f64>,
    /// e₂ = (−sin θ, cos θ).
    pub e2: Vec2<f64>,
}

impl Frame {
    /// The frame of a pose (real parts).
    #[must_use]
    pub fn of<T: Scalar>(pose: &Pose<T>) -> Self {
        Self::turned(pose, &Rotation::of(pose.theta.re()))
    }

    /// The frame of a pose whose rotation is evaluated already (in any scalar type: its
    /// real parts are sin θ and cos θ of the real θ, the same bits).
    #[must_use]
    pub fn turned<T: Scalar, R: Scalar>(pose: &Pose<T>, rotation: &Rotation<R>) -> Self {
        let (s, c) = (rotation.sin.re(), rotation.cos.re());
        Self {
            r: Vec2::new(pose.x.re(), pose.y.re()),
            e1: Vec2::new(c, s),
            e2: Vec2::new(-s, c),
        }
    }

    /// The point r + α e₁ + β e₂ of the body with components (α, β), as
    /// [`Pose::point`].
    #[must_use]
    pub fn point(&self, body: &Vec2<f64>) -> Vec2<f64> {
        self.r + self.to_world(body)
    }

    /// A vector given by its components (α, β) on {e₁, e₂}, expressed on {E₁, E₂}, as
    /// [`Pose::to_world`].
    #[must_use]
    pub fn to_world(&self, body: &Vec2<f64>) -> Vec2<f64> {
        rotate(self.e1.y, self.e1.x, body)
    }
}

/// sin θ and cos θ of a body, evaluated once for every vector the body turns.
///
/// A contact row turns up to three of them per body (a corner, a face's normal and
/// tangent), and an interface evaluates three rows: through [`Pose::to_world`] alone that
/// is one `sin_cos` per vector, nine per interface (in a derivative pass, each on dual
/// numbers); with the others of the broad phase, `sin_cos` took 6.8 % of the samples of
/// the Lire collapse's bench. [`Rotation::apply`] is the same formula as
/// [`Pose::to_world`], so both give the same bits.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rotation<T = f64> {
    /// sin θ.
    pub sin: T,
    /// cos θ.
    pub cos: T,
}

impl<T: Scalar> Rotation<T> {
    /// The rotation by θ.
    #[must_use]
    pub fn of(theta: T) -> Self {
        let (sin, cos) = theta.sin_cos();
        Self { sin, cos }
    }

    /// R(θ) (α, β): a vector given on {e₁, e₂}, expressed on {E₁, E₂}.
    #[must_use]
    pub fn apply(&self, body: &Vec2<f64>) -> Vec2<T> {
        rotate(self.sin, self.cos, body)
    }
}

impl<T: Scalar> Default for Rotation<T> {
    /// No rotation (θ = 0, the floor's): what [`Rotation::of`] gives for a zero angle, to
    /// the bit, without the `sin_cos`.
    fn default() -> Self {
        Self {
            sin: T::zero(),
            cos: T::one(),
        }
    }
}

/// R(θ) (α, β) from s = sin θ and c = cos θ: a vector given on {e₁, e₂}, expressed on
/// {E₁, E₂} (the one formula of [`Pose::to_world`] and [`Frame::point`]).
fn rotate<T: Scalar>(s: T, c: T, body: &Vec2<f64>) -> Vec2<T> {
    Vec2::new(c * body.x - s * body.y, s * body.x + c * body.y)
}

/// The velocities (ẋ, ẏ, θ̇) of one body; ω = θ̇ E₃ is its angular velocity.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Twist<T = f64> {
    /// ẋ.
    pub vx: T,
    /// ẏ.
    pub vy: T,
    /// θ̇.
    pub omega: T,
}

impl<T: Scalar> Pose<T> {
    /// The pose (x, y, θ).
    #[must_use]
    pub fn new(x: T, y: T, theta: T) -> Self {
        Self { x, y, theta }
    }

    /// Reads a pose from three consecutive coordinates (x, y, θ).
    #[must_use]
    pub fn from_slice(q: &[T]) -> Self {
        Self::new(q[0], q[1], q[2])
    }

    /// A constant pose lifted to the scalar type.
    #[must_use]
    pub fn lift(p: &Pose<f64>) -> Self {
        Self::new(T::from(p.x), T::from(p.y), T::from(p.theta))
    }

    /// The centre of mass r, (4.2.1).
    #[must_use]
    pub fn r(&self) -> Vec2<T> {
        Vec2::new(self.x, self.y)
    }

    /// The co-rotational basis vector e₁, (4.2.2).
    #[must_use]
    pub fn e1(&self) -> Vec2<T> {
        let (s, c) = self.theta.sin_cos();
        Vec2::new(c, s)
    }

    /// The co-rotational basis vector e₂, (4.2.2).
    #[must_use]
    pub fn e2(&self) -> Vec2<T> {
        let (s, c) = self.theta.sin_cos();
        Vec2::new(-s, c)
    }

    /// A vector given by constant components (α, β) on {e₁, e₂}, expressed on {E₁, E₂}.
    #[must_use]
    pub fn to_world(&self, body: &Vec2<f64>) -> Vec2<T> {
        self.rotation().apply(body)
    }

    /// The rotation R(θ) from {e₁, e₂} to {E₁, E₂}, for turning several vectors.
    #[must_use]
    pub fn rotation(&self) -> Rotation<T> {
        Rotation::of(self.theta)
    }

    /// The point r + α e₁ + β e₂ of the body with components (α, β).
    #[must_use]
    pub fn point(&self, body: &Vec2<f64>) -> Vec2<T> {
        self.r() + self.to_world(body)
    }
}

impl<T: Scalar> Twist<T> {
    /// The velocities (ẋ, ẏ, θ̇).
    #[must_use]
    pub fn new(vx: T, vy: T, omega: T) -> Self {
        Self { vx, vy, omega }
    }

    /// Reads a twist from three consecutive velocities (ẋ, ẏ, θ̇).
    #[must_use]
    pub fn from_slice(u: &[T]) -> Self {
        Self::new(u[0], u[1], u[2])
    }

    /// A constant twist lifted to the scalar type.
    #[must_use]
    pub fn lift(v: &Twist<f64>) -> Self {
        Self::new(T::from(v.vx), T::from(v.vy), T::from(v.omega))
    }

    /// The velocity v of the centre of mass.
    #[must_use]
    pub fn v(&self) -> Vec2<T> {
        Vec2::new(self.vx, self.vy)
    }

    /// Velocity of the material point at world offset `offset` from the centre of mass,
    /// v + ω × offset (G.3.2).
    #[must_use]
    pub fn point_velocity(&self, offset: &Vec2<T>) -> Vec2<T> {
        self.v() + perp(offset) * self.omega
    }

    /// (ẋ, ẏ, θ̇) as an array.
    #[must_use]
    pub fn as_array(&self) -> [T; 3] {
        [self.vx, self.vy, self.omega]
    }
}

/// The pose and velocities of one body at one instant.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct BodyState<T = f64> {
    /// Configuration (x, y, θ).
    pub pose: Pose<T>,
    /// Velocities (ẋ, ẏ, θ̇).
    pub twist: Twist<T>,
}

impl<T: Scalar> BodyState<T> {
    /// A body at `pose` moving with `twist`.
    #[must_use]
    pub fn new(pose: Pose<T>, twist: Twist<T>) -> Self {
        Self { pose, twist }
    }

    /// A constant state lifted to the scalar type.
    #[must_use]
    pub fn lift(s: &BodyState<f64>) -> Self {
        Self::new(Pose::lift(&s.pose), Twist::lift(&s.twist))
    }
}

impl BodyState<f64> {
    /// The state at time s later with constant accelerations `accel`:
    /// q + s u + ½ s² a, u + s a (used to differentiate along a motion in tests).
    #[must_use]
    pub fn advanced(&self, s: f64, accel: &Twist<f64>) -> Self {
        let p = &self.pose;
        let v = &self.twist;
        Self {
            pose: Pose::new(
                p.x + s * v.vx + 0.5 * s * s * accel.vx,
                p.y + s * v.vy + 0.5 * s * s * accel.vy,
                p.theta + s * v.omega + 0.5 * s * s * accel.omega,
            ),
            twist: Twist::new(
                v.vx + s * accel.vx,
                v.vy + s * accel.vy,
                v.omega + s * accel.omega,
            ),
        }
    }
}

/// Whether two poses are the same to the bit (`==` would take −0 for 0, whose sine
/// differs in sign).
pub(crate) fn same_pose(a: &Pose, b: &Pose) -> bool {
    let bits = |p: &Pose| [p.x.to_bits(), p.y.to_bits(), p.theta.to_bits()];
    bits(a) == bits(b)
}

/// Whether two lists of numbers (coordinates) are the same to the bit, as
/// [`same_pose`]: whatever is computed from one is computed from the other.
pub(crate) fn same_bits(a: &[f64], b: &[f64]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits())
}

#[cfg(test)]
mod tests {
    use super::*;
    use num_dual::Dual64;

    /// The frame's numbers are the real parts of the pose's own methods, to the bit, for
    /// plain and dual scalars: the decisions it serves may not change.
    #[test]
    fn a_frame_gives_the_real_parts_of_the_pose_methods_exactly() {
        let body = Vec2::new(0.37, -0.11);
        for theta in [0.0, 0.7, -2.9, 1e-9, std::f64::consts::FRAC_PI_2] {
            let p: Pose = Pose::new(0.3, -0.2, theta);
            let d = Pose::new(
                Dual64::new(0.3, 1.0),
                Dual64::new(-0.2, 0.5),
                Dual64::new(theta, -1.0),
            );
            let turned = [
                Frame::turned(&p, &p.rotation()),
                Frame::turned(&d, &d.rotation()),
            ];
            for f in [Frame::of(&p), Frame::of(&d)].into_iter().chain(turned) {
                assert_eq!(f.r, p.r());
                assert_eq!(f.e1, p.e1());
                assert_eq!(f.e2, p.e2());
                assert_eq!(f.point(&body), p.point(&body));
                assert_eq!(f.point(&body), d.point(&body).re());
            }
            // A rotation evaluated once turns vectors as the pose does, to the bit.
            assert_eq!(p.rotation().apply(&body), p.to_world(&body));
            assert_eq!(d.rotation().apply(&body), d.to_world(&body));
        }
    }

    #[test]
    fn basis_is_orthonormal_and_positively_oriented() {
        let p: Pose = Pose::new(0.3, -0.2, 0.7);
        let (e1, e2) = (p.e1(), p.e2());
        assert!((e1.dot(&e2)).abs() < 1e-15);
        assert!((e1.norm() - 1.0).abs() < 1e-15);
        assert!((perp(&e1) - e2).norm() < 1e-15);
        assert!((p.to_world(&Vec2::new(1.0, 0.0)) - e1).norm() < 1e-15);
    }

    #[test]
    fn point_velocity_is_the_time_derivative_of_the_point() {
        let s = BodyState::new(Pose::new(0.1, 0.2, 0.3), Twist::new(0.4, -0.5, 1.3));
        let body = Vec2::new(0.5, 0.1);
        let h = 1e-6;
        let fd = (s.advanced(h, &Twist::default()).pose.point(&body)
            - s.advanced(-h, &Twist::default()).pose.point(&body))
            * (0.5 / h);
        let offset = s.pose.to_world(&body);
        assert!((fd - s.twist.point_velocity(&offset)).norm() < 1e-9);
    }

    /// A zero angle and a negative zero are different poses to the broad phase: their
    /// sines differ in sign.
    #[test]
    fn poses_are_the_same_only_to_the_bit() {
        let p = Pose::new(1.0, 2.0, 0.0);
        assert!(same_pose(&p, &Pose::new(1.0, 2.0, 0.0)));
        assert!(!same_pose(&p, &Pose::new(1.0, 2.0, -0.0)));
        assert!(same_bits(&[1.0, 0.0], &[1.0, 0.0]));
        assert!(!same_bits(&[1.0, 0.0], &[1.0, -0.0]));
        assert!(!same_bits(&[1.0], &[1.0, 0.0]));
    }
}
