//! The normal gap between a corner of one body and a flat face of another, (G.2.1)/(G.2.3),
//! with its exact first derivatives (the force direction W_N) and the velocity-product
//! term ζ of its second time derivative.
//!
//! Every gap of the stack has the form of one of the distances ℓ_□ of (G.2.3),
//!
//!   g = (r_P − r_B) · n_B − d_B,   r_P = r_A + p,  p = R(θ_A) ρ_P,  n_B = R(θ_B) n̂,
//!
//! the signed distance of the corner P of body A from the face of body B whose outward
//! unit normal is n_B and which lies at distance d_B from B's centre of mass (d_B = h/2 for
//! a top or bottom face, 0 for the floor). With δ = r_P − r_B and ⊥v = E₃ × v:
//!
//!   ∂g/∂r_A = n_B,  ∂g/∂θ_A = ⊥p · n_B,  ∂g/∂r_B = −n_B,  ∂g/∂θ_B = δ · ⊥n_B,
//!
//! and, since q̇ = u for (x, y, θ), ġ = Wᵀu and g̈ = Wᵀu̇ + ζ with
//!
//!   ζ = 2 ω_B (v_A − v_B) · ⊥n_B + (2 ω_A ω_B − ω_A²) p · n_B − ω_B² δ · n_B.

use crate::coordinates::{perp, BodyState, Frame, Rotation, Scalar, Vec2};

/// A flat face of a body, described on the body's own basis {e₁, e₂}.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Face {
    /// Outward unit normal n̂ on {e₁, e₂}.
    pub normal: Vec2,
    /// Unit tangent t̂ on {e₁, e₂}: the direction along which slip is measured, (G.3.1).
    pub tangent: Vec2,
    /// Distance d from the centre of mass to the face's line.
    pub offset: f64,
}

impl Face {
    /// The top face of a block of height h: normal e₂, tangent e₁, at h/2.
    #[must_use]
    pub fn top(height: f64) -> Self {
        Self {
            normal: Vec2::new(0.0, 1.0),
            tangent: Vec2::new(1.0, 0.0),
            offset: 0.5 * height,
        }
    }

    /// The bottom face of a block of height h: normal −e₂, tangent e₁, at h/2.
    #[must_use]
    pub fn bottom(height: f64) -> Self {
        Self {
            normal: Vec2::new(0.0, -1.0),
            tangent: Vec2::new(1.0, 0.0),
            offset: 0.5 * height,
        }
    }

    /// The four faces of a w × h rectangle: top, bottom, right, left. The sides' tangent
    /// is e₂ (slip measured upwards along them).
    #[must_use]
    pub fn of_rectangle(width: f64, height: f64) -> [Self; 4] {
        let side = |sign: f64| Self {
            normal: Vec2::new(sign, 0.0),
            tangent: Vec2::new(0.0, 1.0),
            offset: 0.5 * width,
        };
        [
            Self::top(height),
            Self::bottom(height),
            side(1.0),
            side(-1.0),
        ]
    }

    /// The signed distance of the world point `p` from this face's line when the face
    /// belongs to a body with frame `frame` (positive outside).
    #[must_use]
    pub fn distance(&self, frame: &Frame, p: &Vec2) -> f64 {
        (*p - frame.r).dot(&frame.to_world(&self.normal)) - self.offset
    }

    /// The floor seen from its own reference point (0, y_floor): normal E₂, tangent E₁.
    #[must_use]
    pub fn floor() -> Self {
        Self {
            normal: Vec2::new(0.0, 1.0),
            tangent: Vec2::new(1.0, 0.0),
            offset: 0.0,
        }
    }
}

/// One scalar contact quantity between two bodies — a gap or a slip speed — with its
/// exact derivatives.
///
/// For a gap g(q): ġ = W_Aᵀu_A + W_Bᵀu_B and g̈ = W_Aᵀu̇_A + W_Bᵀu̇_B + ζ.
/// For a slip speed γ(q, u) = W_Aᵀu_A + W_Bᵀu_B: γ̇ = W_Aᵀu̇_A + W_Bᵀu̇_B + ζ.
/// W columns are on (x, y, θ) of each body.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PairRow<T = f64> {
    /// The value: the gap g or the slip speed γ.
    pub value: T,
    /// W on the first body's (x, y, θ).
    pub w_first: [T; 3],
    /// W on the second body's (x, y, θ).
    pub w_second: [T; 3],
    /// The velocity-product term ζ of the second time derivative (or of γ̇).
    pub zeta: T,
}

impl<T: Scalar> PairRow<T> {
    /// Wᵀu for the two bodies' velocities.
    #[must_use]
    pub fn rate(&self, first: &BodyState<T>, second: &BodyState<T>) -> T {
        dot3(&self.w_first, first) + dot3(&self.w_second, second)
    }

    /// The same quantity with the roles of the bodies exchanged in the storage.
    #[must_use]
    pub fn swapped(self) -> Self {
        Self {
            w_first: self.w_second,
            w_second: self.w_first,
            ..self
        }
    }

    /// The same quantity with its sign reversed.
    #[must_use]
    pub fn negated(self) -> Self {
        Self {
            value: -self.value,
            w_first: self.w_first.map(|w| -w),
            w_second: self.w_second.map(|w| -w),
            zeta: -self.zeta,
        }
    }
}

fn dot3<T: Scalar>(w: &[T; 3], s: &BodyState<T>) -> T {
    w[0] * s.twist.vx + w[1] * s.twist.vy + w[2] * s.twist.omega
}

/// A corner P of body A facing a flat face of body B: the pairing behind each ℓ_□ of
/// (G.2.3) and each slip speed of (G.3.1).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CornerOnFace<T = f64> {
    /// State of the body that owns the corner.
    pub corner_body: BodyState<T>,
    /// The corner on that body's basis (see [`crate::Corner::body_offset`]).
    pub corner: Vec2,
    /// State of the body that owns the face.
    pub face_body: BodyState<T>,
    /// The face.
    pub face: Face,
}

/// The rotations of the two bodies of a [`CornerOnFace`], evaluated once for its gap and
/// its slip (see [`Rotation`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PairRotations<T = f64> {
    /// R(θ_A) of the corner's body.
    pub corner: Rotation<T>,
    /// R(θ_B) of the face's body.
    pub face: Rotation<T>,
}

impl<T: Scalar> CornerOnFace<T> {
    /// The rotations of the corner's and the face's bodies at their states.
    #[must_use]
    pub fn rotations(&self) -> PairRotations<T> {
        PairRotations {
            corner: self.corner_body.pose.rotation(),
            face: self.face_body.pose.rotation(),
        }
    }

    /// World offset p = R(θ_A) ρ_P of the corner from A's centre of mass.
    pub(crate) fn corner_offset(&self, rotations: &PairRotations<T>) -> Vec2<T> {
        rotations.corner.apply(&self.corner)
    }

    /// The signed distance g of the corner from the face's line, positive outside,
    /// with W on (A, B) and ζ (see the module documentation). Rows are stored with
    /// `w_first` on the corner's body A and `w_second` on the face's body B.
    #[must_use]
    pub fn gap(&self) -> PairRow<T> {
        self.gap_turned(&self.rotations())
    }

    /// [`CornerOnFace::gap`] with the bodies' rotations at hand.
    #[must_use]
    pub fn gap_turned(&self, rotations: &PairRotations<T>) -> PairRow<T> {
        let (a, b) = (&self.corner_body, &self.face_body);
        let p = self.corner_offset(rotations);
        let n = rotations.face.apply(&self.face.normal);
        let delta = a.pose.r() + p - b.pose.r();
        let value = delta.dot(&n) - T::from(self.face.offset);
        let perp_n = perp(&n);
        let (wa, wb) = (a.twist.omega, b.twist.omega);
        let dv = a.twist.v() - b.twist.v();
        let zeta = wb * dv.dot(&perp_n) * 2.0 + (wa * wb * 2.0 - wa * wa) * p.dot(&n)
            - wb * wb * delta.dot(&n);
        PairRow {
            value,
            w_first: [n.x, n.y, perp(&p).dot(&n)],
            w_second: [-n.x, -n.y, delta.dot(&perp_n)],
            zeta,
        }
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::coordinates::{Pose, Twist};

    /// Central finite-difference oracle for one pair row: the gradient of `f` w.r.t. the
    /// six coordinates and the second derivative along the motion (with zero
    /// accelerations), which must equal ζ.
    pub(crate) fn fd_oracle(
        f: &dyn Fn(&BodyState, &BodyState) -> f64,
        a: &BodyState,
        b: &BodyState,
    ) -> ([f64; 3], [f64; 3], f64) {
        let h = 1e-6;
        let mut wa = [0.0; 3];
        let mut wb = [0.0; 3];
        for i in 0..3 {
            let shift = |s: &BodyState, d: f64| {
                let mut p = s.pose;
                match i {
                    0 => p.x += d,
                    1 => p.y += d,
                    _ => p.theta += d,
                }
                BodyState::new(p, s.twist)
            };
            wa[i] = (f(&shift(a, h), b) - f(&shift(a, -h), b)) / (2.0 * h);
            wb[i] = (f(a, &shift(b, h)) - f(a, &shift(b, -h))) / (2.0 * h);
        }
        let s = 1e-4;
        let z = Twist::default();
        let along = |d: f64| f(&a.advanced(d, &z), &b.advanced(d, &z));
        let second = (along(s) - 2.0 * along(0.0) + along(-s)) / (s * s);
        (wa, wb, second)
    }

    pub(crate) fn state(x: f64, y: f64, th: f64, vx: f64, vy: f64, om: f64) -> BodyState {
        BodyState::new(Pose::new(x, y, th), Twist::new(vx, vy, om))
    }

    #[test]
    fn gap_derivatives_match_finite_differences() {
        let a = state(0.2, 0.1, 0.3, 0.7, -0.4, 1.1);
        let b = state(-0.1, 0.9, -0.2, -0.3, 0.5, -0.8);
        let corner = Vec2::new(0.5, 0.2);
        let face = Face::bottom(0.4);
        let pair = |a: &BodyState, b: &BodyState| CornerOnFace {
            corner_body: *a,
            corner,
            face_body: *b,
            face,
        };
        let row = pair(&a, &b).gap();
        let (wa, wb, second) = fd_oracle(&|a, b| pair(a, b).gap().value, &a, &b);
        for i in 0..3 {
            assert!((row.w_first[i] - wa[i]).abs() < 1e-8, "W_A[{i}]");
            assert!((row.w_second[i] - wb[i]).abs() < 1e-8, "W_B[{i}]");
        }
        assert!(
            (row.zeta - second).abs() < 1e-5,
            "zeta {} vs {}",
            row.zeta,
            second
        );
    }
}
