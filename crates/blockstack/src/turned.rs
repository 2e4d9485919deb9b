//! Every body of a scene at one (t, q, u), each with its rotation R(θ) evaluated once.
//!
//! The gap functions of App. G turn the vectors of a body, ρ_P ↦ R(θ) ρ_P (a corner,
//! (G.1.1)) and n̂ ↦ R(θ) n̂ (a face's normal and tangent, (G.2.3), (G.3.1)), with the same
//! sin θ and cos θ for every contact the body takes part in: its interfaces below and
//! above, its four floor corners, the corner contacts of its lines (crate::pairs). An
//! evaluation turns each body once here and hands the turned bodies to all of them; in a
//! derivative pass the same holds for the dual numbers, whose sine and cosine cost a real
//! `sin_cos` and the products of their directions. The base's prescribed state and
//! acceleration are read once per evaluation too (a harmonic base is a `sin_cos` of ωt).
//!
//! The rotation is [`Rotation::of`] of the body's θ, the one function every caller used
//! before: the rows are the same to the bit.

use crate::coordinates::{BodyState, Frame, Pose, Rotation, Scalar, Twist, Vec2};
use crate::overlap::Body;
use crate::pairs::body_index;
use crate::scene::Scene;
use crate::stack::block_state;

/// A body's state with its rotation R(θ) = (cos θ, sin θ) evaluated.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TurnedBody<T = f64> {
    /// The pose and velocities.
    pub state: BodyState<T>,
    /// R(θ) of the pose's θ.
    pub rotation: Rotation<T>,
}

impl<T: Scalar> TurnedBody<T> {
    /// A body at `state`, turned.
    #[must_use]
    pub fn of(state: BodyState<T>) -> Self {
        Self {
            rotation: state.pose.rotation(),
            state,
        }
    }

    /// The frame of the pose (real parts, [`Frame::turned`]).
    #[must_use]
    pub fn frame(&self) -> Frame {
        Frame::turned(&self.state.pose, &self.rotation)
    }

    /// The real parts (the same numbers, without derivative directions).
    #[must_use]
    pub fn re(&self) -> TurnedBody<f64> {
        let (p, v, r) = (&self.state.pose, &self.state.twist, &self.rotation);
        TurnedBody {
            state: BodyState::new(
                Pose::new(p.x.re(), p.y.re(), p.theta.re()),
                Twist::new(v.vx.re(), v.vy.re(), v.omega.re()),
            ),
            rotation: Rotation {
                sin: r.sin.re(),
                cos: r.cos.re(),
            },
        }
    }

    /// A body of real numbers in the scalar type, without derivative directions (no
    /// `sin_cos`: its rotation is lifted too).
    #[must_use]
    pub fn lift(body: &TurnedBody<f64>) -> Self {
        Self {
            state: BodyState::lift(&body.state),
            rotation: Rotation {
                sin: T::from(body.rotation.sin),
                cos: T::from(body.rotation.cos),
            },
        }
    }

    /// The point r + R(θ) ρ of the body with components ρ = (α, β), as
    /// [`crate::coordinates::Pose::point`].
    #[must_use]
    pub fn point(&self, body: &Vec2) -> Vec2<T> {
        self.state.pose.r() + self.rotation.apply(body)
    }
}

/// The base and the blocks of a scene at one (t, q, u), turned ([`TurnedBody`]), and the
/// base's prescribed acceleration: what every contact row of one evaluation reads.
#[derive(Debug, Clone, PartialEq)]
pub struct TurnedBodies<T = f64> {
    /// Body i of the scene's numbering (base 0, blocks 1..n).
    bodies: Vec<TurnedBody<T>>,
    /// The base's acceleration at t.
    base_acc: Twist<T>,
}

impl<T: Scalar> Default for TurnedBodies<T> {
    fn default() -> Self {
        Self {
            bodies: Vec::new(),
            base_acc: Twist::lift(&Twist::default()),
        }
    }
}

impl<T: Scalar> TurnedBodies<T> {
    /// The bodies of `scene` at time t, coordinates q and velocities u (length 3n each),
    /// into this reused buffer.
    ///
    /// # Panics
    /// When q or u is shorter than 3n.
    pub fn fill(&mut self, scene: &Scene, t: f64, q: &[T], u: &[T]) {
        let (base, base_acc) = scene.base().state_and_acceleration(t);
        self.bodies.clear();
        self.bodies.push(TurnedBody::of(BodyState::lift(&base)));
        self.bodies
            .extend((0..scene.n_blocks()).map(|k| TurnedBody::of(block_state(q, u, k))));
        self.base_acc = Twist::lift(&base_acc);
    }

    /// Body `b` (the base or a block; the floor is no body here).
    ///
    /// # Panics
    /// For the floor, or a block beyond the scene's.
    #[must_use]
    pub fn get(&self, b: Body) -> &TurnedBody<T> {
        &self.bodies[body_index(b)]
    }

    /// Free block k (0-based).
    #[must_use]
    pub fn block(&self, k: usize) -> &TurnedBody<T> {
        &self.bodies[k + 1]
    }

    /// The base's prescribed acceleration.
    #[must_use]
    pub fn base_acceleration(&self) -> &Twist<T> {
        &self.base_acc
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenarios::{shaking_column, Shaking};
    use num_dual::Dual64;

    /// A turned body turns as its pose does, to the bit, in plain and dual numbers, and
    /// no rotation is the rotation by a zero angle.
    #[test]
    fn a_turned_body_gives_the_poses_points_and_frame_exactly() {
        let body = Vec2::new(0.37, -0.11);
        for theta in [0.0, 0.7, -2.9, 1e-9, std::f64::consts::FRAC_PI_2] {
            let p: Pose = Pose::new(0.3, -0.2, theta);
            let turned = TurnedBody::of(BodyState::new(p, Twist::default()));
            assert_eq!(turned.point(&body), p.point(&body));
            assert_eq!(turned.frame(), Frame::of(&p));
            let d = Pose::new(
                Dual64::new(0.3, 1.0),
                Dual64::new(-0.2, 0.5),
                Dual64::new(theta, -1.0),
            );
            let turned = TurnedBody::of(BodyState::new(d, Twist::lift(&Twist::default())));
            assert_eq!(turned.point(&body), d.point(&body));
            assert_eq!(turned.frame(), Frame::of(&d));
        }
        assert_eq!(Rotation::<f64>::default(), Rotation::of(0.0));
        assert_eq!(
            Rotation::<Dual64>::default(),
            Rotation::of(Dual64::from(0.0))
        );
    }

    /// The bodies of a shaken column at a moving base's time: the base's prescribed
    /// state and acceleration, the blocks' states from q and u, each turned.
    #[test]
    fn the_bodies_of_a_scene_are_its_base_and_blocks_turned() {
        let scene = shaking_column(&Shaking {
            blocks: 3,
            ..Shaking::default()
        })
        .unwrap();
        let q: Vec<f64> = scene
            .initial_coordinates()
            .iter()
            .enumerate()
            .map(|(i, x)| x + 0.1 * (i as f64).sin())
            .collect();
        let u: Vec<f64> = (0..q.len()).map(|i| 0.3 * (i as f64).cos()).collect();
        let mut bodies = TurnedBodies::default();
        bodies.fill(&scene, 0.7, &q, &u);
        let base = scene.base().state(0.7);
        assert_eq!(*bodies.get(Body::Base), TurnedBody::of(base));
        assert_eq!(bodies.base_acceleration(), &scene.base().acceleration(0.7));
        for k in 0..3 {
            let state = block_state(&q, &u, k);
            assert_eq!(*bodies.block(k), TurnedBody::of(state));
            assert_eq!(bodies.get(Body::Block(k + 1)), bodies.block(k));
        }
    }
}
