//! The slip speed at a corner-on-face contact, (G.3.1)–(G.3.2), with its force direction
//! W_F and the velocity-product term ζ_F of its time derivative.
//!
//! With the corner P of body A on the face of body B (tangent t_B = R(θ_B) t̂, outward
//! normal n_B, distance d_B from B's centre), the slip speed is the relative tangential
//! velocity of P and of the face (any point of the face has the same tangential velocity,
//! which is why (G.3.1) may use either face corner "c/d" or "a/b"):
//!
//!   γ = σ [ (v_A − v_B) · t_B + ω_A ⊥p · t_B − ω_B d_B (⊥n_B · t_B) ],
//!
//! σ = +1 when A is the lower body, −1 when A is the upper one, so that γ is always the
//! velocity of the lower body relative to the upper one along the tangent, as (G.3.1)
//! does ("the point on block k always on the same side"), which keeps γ continuous when
//! the contact moves from one case of Figure 4.2 to another. γ = W_Aᵀu_A + W_Bᵀu_B and
//!
//!   γ̇ = Wᵀu̇ + ζ_F,  ζ_F = σ [ ω_B (v_A − v_B) · ⊥t_B + (ω_A ω_B − ω_A²) p · t_B ].

use crate::coordinates::{perp, Scalar};
use crate::gaps::{CornerOnFace, PairRotations, PairRow};

/// Which body of a corner-on-face pair is the lower one (it fixes the sign σ of the slip).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LowerBody {
    /// The corner's body is the lower one (cases (b)i, (b)ii: a corner of block k).
    Corner,
    /// The face's body is the lower one (cases (b)iii, (b)iv and the floor).
    Face,
}

impl<T: Scalar> CornerOnFace<T> {
    /// The slip speed γ (lower relative to upper, along the face tangent) with W_F and ζ_F,
    /// (G.3.1). Stored with `w_first` on the corner's body and `w_second` on the face's.
    #[must_use]
    pub fn slip(&self, lower: LowerBody) -> PairRow<T> {
        self.slip_turned(lower, &self.rotations())
    }

    /// [`CornerOnFace::slip`] with the bodies' rotations at hand.
    #[must_use]
    pub fn slip_turned(&self, lower: LowerBody, rotations: &PairRotations<T>) -> PairRow<T> {
        let sigma = match lower {
            LowerBody::Corner => 1.0,
            LowerBody::Face => -1.0,
        };
        let (a, b) = (&self.corner_body, &self.face_body);
        let p = self.corner_offset(rotations);
        let t = rotations.face.apply(&self.face.tangent);
        let n = rotations.face.apply(&self.face.normal);
        let face_arm = perp(&n).dot(&t) * self.face.offset;
        let w_first = [t.x, t.y, perp(&p).dot(&t)].map(|w| w * sigma);
        let w_second = [-t.x, -t.y, -face_arm].map(|w| w * sigma);
        let (wa, wb) = (a.twist.omega, b.twist.omega);
        let dv = a.twist.v() - b.twist.v();
        let zeta = (wb * dv.dot(&perp(&t)) + (wa * wb - wa * wa) * p.dot(&t)) * sigma;
        let mut row = PairRow {
            value: T::zero(),
            w_first,
            w_second,
            zeta,
        };
        row.value = row.rate(a, b);
        row
    }
}

/// The direction sgn(γ) of a scalar slip speed for the sliding friction force −μλ̂ sgn(γ),
/// or `None` where it is undefined: |γ| ≤ `tol`. ERRATA 24: a slip row divides by ‖γ‖ and
/// must not at zero; the caller then drops the direction term (docs/method.md §3).
#[must_use]
pub fn slip_direction(gamma: f64, tol: f64) -> Option<f64> {
    (gamma.abs() > tol && gamma.is_finite()).then(|| gamma.signum())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::coordinates::{BodyState, Twist, Vec2};
    use crate::corners::Corner;
    use crate::gaps::tests::state;
    use crate::gaps::Face;

    #[test]
    fn slip_is_the_relative_velocity_of_the_touching_points() {
        // Corner a of a lower block (w = 1, h = 0.2) touching the bottom face of the
        // block above: the slip is (v_a − v_Q)·e₁ of the upper block, Q the coincident
        // material point of the upper block.
        let lower = state(0.0, 0.0, 0.05, 0.3, -0.1, 0.7);
        let upper = state(0.2, 0.2, -0.03, -0.2, 0.4, 0.9);
        let corner = Corner::A.body_offset(1.0, 0.2);
        let pair = CornerOnFace {
            corner_body: lower,
            corner,
            face_body: upper,
            face: Face::bottom(0.2),
        };
        let row = pair.slip(LowerBody::Corner);
        let pa = lower.pose.point(&corner);
        let va = lower.twist.point_velocity(&(pa - lower.pose.r()));
        // Project P on the face line to get the face point Q.
        let e1 = upper.pose.e1();
        let e2 = upper.pose.e2();
        let face_point = upper.pose.r() - e2 * 0.1;
        let q = face_point + e1 * (pa - face_point).dot(&e1);
        let vq = upper.twist.point_velocity(&(q - upper.pose.r()));
        assert!((row.value - (va - vq).dot(&e1)).abs() < 1e-14);
    }

    #[test]
    fn zero_slip_has_no_direction() {
        assert_eq!(slip_direction(0.0, 0.0), None);
        assert_eq!(slip_direction(-0.0, 0.0), None);
        assert_eq!(slip_direction(1e-14, 1e-12), None);
        assert_eq!(slip_direction(f64::NAN, 0.0), None);
        assert_eq!(slip_direction(-2.0, 1e-12), Some(-1.0));
    }

    #[test]
    fn slip_rate_term_matches_finite_differences() {
        // With u̇ = 0, dγ/dt along the motion is ζ_F.
        let a = state(0.2, 0.1, 0.3, 0.7, -0.4, 1.1);
        let b = state(-0.1, 0.9, -0.2, -0.3, 0.5, -0.8);
        let corner = Vec2::new(-0.5, -0.2);
        for (face, lower) in [
            (Face::top(0.3), LowerBody::Face),
            (Face::bottom(0.3), LowerBody::Corner),
        ] {
            let slip = |a: &BodyState, b: &BodyState| {
                CornerOnFace {
                    corner_body: *a,
                    corner,
                    face_body: *b,
                    face,
                }
                .slip(lower)
            };
            let row = slip(&a, &b);
            let h = 1e-6;
            let z = Twist::default();
            let fd = (slip(&a.advanced(h, &z), &b.advanced(h, &z)).value
                - slip(&a.advanced(-h, &z), &b.advanced(-h, &z)).value)
                / (2.0 * h);
            assert!((row.zeta - fd).abs() < 1e-8, "{} vs {fd}", row.zeta);
            // W_F is ∂γ/∂u.
            let mut a1 = a;
            a1.twist.omega += 1.0;
            assert!((slip(&a1, &b).value - row.value - row.w_first[2]).abs() < 1e-12);
            let mut b1 = b;
            b1.twist.vx += 1.0;
            assert!((slip(&a, &b1).value - row.value - row.w_second[0]).abs() < 1e-12);
        }
    }
}
