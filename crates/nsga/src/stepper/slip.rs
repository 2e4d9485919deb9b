//! The sliding rows of a friction law (eqs. 139–142): the direction each row takes, and
//! its derivative, guarded where the law's own vector is round-off (docs/method.md §3).

use super::iterate::Iterate;
use super::rows::RowMat;
use crate::linalg::norm;
use crate::system::FrictionLaw;

/// Below this ratio r‖ξ‖ / ‖r ξ − P_F‖ the slip velocity ξ of a two-component law outside
/// D carries no direction (it is round-off around a rolling contact): the law's sliding
/// rows then take the direction of the prox argument r ξ − P_F instead (docs/method.md
/// §3).
pub const NEGLIGIBLE_SLIP: f64 = 1e-9;

/// The vector whose direction one sliding row of a friction law takes (docs/method.md
/// §3): its own vector (ξ_F, γ_F or γ̇_F as in eqs. 139–142) while that has a direction,
/// and the prox argument of the law's level where a disk law's (two components) own
/// vector is negligible against it (r‖own‖ ≤ [`NEGLIGIBLE_SLIP`] ‖argument‖), or for an
/// interval law (one component) under
/// [`Options::interval_sign_from_prox`](crate::Options::interval_sign_from_prox).
///
/// Outside D, a = r ξ − P_F has ‖a‖ > μP̂ ≥ 0, so it always has a direction; and at a
/// solution outside D, P_F = −μP̂ a/‖a‖ gives r ξ = a (1 − μP̂/‖a‖), so ξ ∥ a and both
/// forms agree (likewise b = r γ̇ − λ_F outside E): the solutions are the same, the
/// Newton iterates are not.
///
/// - A disk law's sliding row written with ξ/‖ξ‖ when ‖ξ‖ is round-off has derivatives
///   of order P̂/‖ξ‖ (measured 1e31 at the start of a cylinder's spin-up, whose floor
///   contact rolls; and with γ̇ at a contact held on its stick–slip bound) and makes the
///   Newton matrix numerically singular; with a/‖a‖ they stay of order 1.
/// - An interval law has no such blow-up (its projector 1 − d d is zero), but its sign
///   d = ξ/|ξ| jumps where ξ crosses zero, inside the sliding region: a law held on its
///   stick–slip bound slides at a slip of round-off size, the sign follows the
///   round-off, and the row jumps by 2μP̂. The prox argument's sign changes only at
///   a = 0, inside D, where the row is r ξ.
pub(super) struct GuardedDirection {
    n: usize,
    vector: [f64; 2],
    /// Whether `vector` is the prox argument.
    pub(super) projected: bool,
}

impl GuardedDirection {
    /// The direction of `own`, or of `argument` where `own` is negligible against it or
    /// `from_prox` (an interval law under the prox-sign rule) asks for it.
    fn new(r: f64, own: &[f64], argument: &[f64; 2], from_prox: bool) -> Self {
        let n = own.len().min(2);
        let projected = from_prox || {
            let tiny = if n == 2 {
                NEGLIGIBLE_SLIP * norm(&argument[..n])
            } else {
                0.0
            };
            tiny > 0.0 && r * norm(own) <= tiny
        };
        let mut vector = *argument;
        if !projected {
            vector[..n].copy_from_slice(&own[..n]);
        }
        Self {
            n,
            vector,
            projected,
        }
    }

    pub(super) fn vector(&self) -> &[f64] {
        &self.vector[..self.n]
    }
}

/// r s − f over a law's one or two components.
fn prox_argument(r: f64, s: &[f64], f: &[f64]) -> [f64; 2] {
    let mut a = [0.0; 2];
    for (m, am) in a.iter_mut().enumerate().take(s.len()) {
        *am = r * s[m] - f[m];
    }
    a
}

/// The sliding directions of one active friction law under its sets: None for a row
/// that sticks (velocity level in D, acceleration level in E).
pub(super) struct SlidingDirections {
    pub(super) velocity: Option<GuardedDirection>,
    pub(super) acceleration: Option<GuardedDirection>,
}

impl SlidingDirections {
    /// For sets (in D, in E), with ξ_F and P_F, (γ_F, γ̇_F) and λ_F of the law;
    /// `prox_sign`: an interval law under
    /// [`Options::interval_sign_from_prox`](crate::Options::interval_sign_from_prox), whose
    /// rows then take the prox arguments' signs: a on velocity level, and outside D on
    /// acceleration level too where ξ_F is γ_F (no tangential restitution, `e_f` = 0:
    /// with it a solution's γ_F need not have a's sign), b in D ∖ E.
    pub(super) fn new(
        r: f64,
        (d, e): (bool, bool),
        (prox_sign, e_f): (bool, f64),
        xi: &[f64],
        p_f: &[f64],
        (v, acc): (&[f64], &[f64]),
        lambda_f: &[f64],
    ) -> Self {
        let a = (!d).then(|| prox_argument(r, xi, p_f));
        Self {
            velocity: a.map(|a| GuardedDirection::new(r, xi, &a, prox_sign)),
            acceleration: match a {
                Some(a) => Some(GuardedDirection::new(r, v, &a, prox_sign && e_f == 0.0)),
                None if !e => Some(GuardedDirection::new(
                    r,
                    acc,
                    &prox_argument(r, acc, lambda_f),
                    prox_sign,
                )),
                None => None,
            },
        }
    }

    /// [`Self::new`] for `law`, whose components start at `f0`, at iterate `it` and
    /// unknowns `x`: its velocities are rows `vs..` of the iterate, its λ_F the unknowns
    /// `lf + f0..`; `interval_prox_sign`: the option
    /// [`Options::interval_sign_from_prox`](crate::Options::interval_sign_from_prox).
    pub(super) fn of_law(
        it: &Iterate,
        x: &[f64],
        (r, law, interval_prox_sign): (f64, &FrictionLaw, bool),
        sets: (bool, bool),
        (vs, lf, f0): (usize, usize, usize),
    ) -> Self {
        let nc = law.components;
        Self::new(
            r,
            sets,
            (interval_prox_sign && nc == 1, law.e_f),
            &it.xi_v[vs..vs + nc],
            &it.p_f[f0..f0 + nc],
            (&it.v[vs..vs + nc], &it.acc_v[vs..vs + nc]),
            &x[lf + f0..lf + f0 + nc],
        )
    }
}

/// The derivative rows ∂v_m'/∂x of the vector a sliding row takes its direction from.
#[derive(Clone, Copy)]
pub(crate) enum SlipArgument<'a> {
    /// Rows `vs + m'` of a kept derivative matrix.
    Rows(&'a RowMat, usize),
    /// A prox argument r s − f: r times rows `vs + m'` of ∂s/∂x, minus ∂f/∂x, f_m' being
    /// the sum of coefficient times unknown over `(column of component 0, coefficient)`.
    Projected(&'a RowMat, usize, f64, &'a [(usize, f64)]),
}

impl SlipArgument<'_> {
    fn for_each(self, mp: usize, mut f: impl FnMut(usize, f64)) {
        match self {
            Self::Rows(dv, vs) => dv.row(vs + mp).for_each(|(c, v)| f(c, v)),
            Self::Projected(ds, vs, r, force) => {
                ds.row(vs + mp).for_each(|(col, v)| f(col, r * v));
                for &(col, coef) in force {
                    f(col + mp, -coef);
                }
            }
        }
    }
}

/// Component `m` of v/‖v‖, 0 when ‖v‖ = 0 (ERRATA 24: the zero norm is guarded).
pub(crate) fn direction(v: &[f64], m: usize) -> f64 {
    let n = norm(v);
    if n > 0.0 {
        v[m] / n
    } else {
        0.0
    }
}

/// Jacobian of the sliding term μ S d_m(v), S = Σ multipliers clamped at zero, d = v/‖v‖:
/// μ d_m ∂S + μ S (δ_mm' − d_m d_m')/‖v‖ ∂v_m' (docs/method.md §4).
#[allow(clippy::too_many_arguments)]
pub(crate) fn slip_row(
    jac: &mut Vec<(usize, usize, f64)>,
    row: usize,
    scale: f64,
    mu: f64,
    sum: f64,
    radius_cols: &[(usize, f64)],
    v: &[f64],
    m: usize,
    dv: SlipArgument<'_>,
) {
    let n = norm(v);
    if n <= 0.0 || sum <= 0.0 {
        return;
    }
    let dm = v[m] / n;
    for &(c, f) in radius_cols {
        jac.push((row, c, scale * mu * dm * f));
    }
    let radius = mu * sum;
    for (mp, &vmp) in v.iter().enumerate() {
        let proj = f64::from(u8::from(m == mp)) - dm * vmp / n;
        if proj == 0.0 {
            continue;
        }
        dv.for_each(mp, |c, val| {
            jac.push((row, c, scale * radius * proj / n * val));
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A law held on its friction bound slides at a round-off slip whose sign each
    /// update may flip (the leaning block of the matrix's worst run, docs/method.md §3).
    /// An interval law's sliding rows take the prox argument's sign on either side of
    /// zero, so its rows do not jump there; the paper's ξ/|ξ| jumped by 2μP̂.
    #[test]
    fn an_interval_law_keeps_its_sign_where_its_slip_crosses_zero() {
        let (r, p_f, lambda_f) = (0.7, [7.85e-3], [0.5]);
        // The law's directions for sets (in D, in E), the prox-sign rule or the paper's,
        // e_F, ξ_F and (γ_F, γ̇_F).
        let directions = |sets, rule: (bool, f64), xi: &[f64], (v, acc): (&[f64], &[f64])| {
            SlidingDirections::new(r, sets, rule, xi, &p_f, (v, acc), &lambda_f)
        };
        let sign = |d: Option<GuardedDirection>| direction(d.expect("slides").vector(), 0);
        for slip in [-1e-10, -1e-13, 0.0, 1e-13, 1e-10] {
            let xi = [slip / r];
            let outside_d = directions((false, false), (true, 0.0), &xi, (&xi, &[0.0]));
            // a = r ξ − P_F < 0 on both sides: the row is P_F − μP̂.
            assert_eq!(sign(outside_d.velocity), -1.0, "slip {slip:e}");
            assert_eq!(sign(outside_d.acceleration), -1.0, "slip {slip:e}");
            // In D ∖ E: b = r γ̇ − λ_F < 0 on both sides of a round-off γ̇.
            let in_d = directions((true, false), (true, 0.0), &xi, (&xi, &xi));
            assert_eq!(sign(in_d.acceleration), -1.0, "slip {slip:e}");
            // The paper's rows follow the slip's own sign, 0 where it is zero.
            let paper = directions((false, false), (false, 0.0), &xi, (&xi, &[0.0]));
            let own = if slip == 0.0 { 0.0 } else { slip.signum() };
            assert_eq!(sign(paper.velocity), own, "slip {slip:e}");
        }
        // With tangential restitution ξ_F need not have γ_F's sign: the acceleration row
        // keeps γ_F's own.
        let restituted = directions((false, false), (true, 0.5), &[-0.02], (&[0.01], &[0.0]));
        assert_eq!(sign(restituted.acceleration), 1.0);
    }

    /// A one-component (interval) law sliding at a round-off slip, down to where its
    /// square is subnormal: the row is μ d ∂S alone, d = ±1, since the projector 1 − d²
    /// is zero. When ‖v‖ was taken as √(v²), a slip of 1e-160 gave d ≠ ±1 and entries
    /// of order μS/‖v‖·ε ≈ 1e140 on the slip's columns, a singular Newton matrix.
    #[test]
    fn an_interval_law_has_no_projector_at_a_round_off_slip() {
        let mut dv = RowMat::default();
        dv.tmp.push((0, 3, 0.7));
        dv.tmp.push((0, 4, -0.7));
        dv.build(1);
        for slip in [1e-3, 1e-150, -1e-155, 1e-160, -3e-161, 1e-300] {
            let mut jac = Vec::new();
            let cols = [(7, 1.0), (8, 0.5)];
            slip_row(
                &mut jac,
                0,
                1.0,
                0.5,
                2.0,
                &cols,
                &[slip],
                0,
                SlipArgument::Rows(&dv, 0),
            );
            let sign = slip.signum();
            assert_eq!(
                jac,
                vec![(0, 7, 0.5 * sign), (0, 8, 0.25 * sign)],
                "slip {slip:e}"
            );
        }
    }
}
