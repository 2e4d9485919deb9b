//! The contact laws checked on a state at the end of a step: which law a branch or a
//! fork's candidate breaks, and by how much (docs/exploration.md, "Contact laws").
//!
//! A step of the scheme ends in (q, u) with the step's percussions P_N (normal) and P_F
//! (friction). The laws of a solution of the step's equations, checked here from the
//! system's own gaps and slips at the end state (not from the index sets the step was
//! solved with, which is what a converged-rule candidate gets wrong):
//! - **gap**: every gap g_N ≥ 0 (no interpenetration);
//! - **normal**: every P_N ≥ 0 (a contact pushes, never pulls);
//! - **cone**: every friction law ‖P_F‖ ≤ μ Σ P_N over its normal contacts;
//! - **complementarity**: an open gap carries no impulse (g_N > 0 ⇒ P_N = 0), and a
//!   sliding closed contact has its friction on the cone, against the slip
//!   (P_F = −μ Σ P_N · γ_F/‖γ_F‖). The slip is the one at the step's end, the law's
//!   argument when e_F = 0 (every built-in scene).
//!
//! Each law holds within a stated [`Tolerances`], relative to the scene: a gap within
//! [`LAW_TOLERANCE`] of the smallest block height, an impulse within [`LAW_TOLERANCE`]
//! of the stack's weight over one step, a slip within [`LAW_TOLERANCE`] block heights
//! per step. A self-consistent run keeps every violation at round-off, far below them.

use crate::scene::Scene;
use nsga::{Evaluation, Layout, State, System};
use std::fmt::Write;

/// The relative tolerance of every law (see the module docs).
pub const LAW_TOLERANCE: f64 = 1e-6;

/// Below this impulse tolerance (a scene without gravity) the impulse checks use it.
const SMALLEST_IMPULSE_TOL: f64 = 1e-12;

/// How far a law may be broken before it counts as broken, in the scene's units.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Tolerances {
    /// Length: [`LAW_TOLERANCE`] times the smallest block height.
    pub gap: f64,
    /// Impulse: [`LAW_TOLERANCE`] times the blocks' total weight times Δt.
    pub impulse: f64,
    /// Velocity: the gap tolerance per Δt.
    pub slip: f64,
}

impl Tolerances {
    /// The tolerances of `scene` stepped with `dt`.
    #[must_use]
    pub fn new(scene: &Scene, dt: f64) -> Self {
        let weight: f64 = scene.gravity_forces().iter().map(|f| f.abs()).sum();
        let gap = LAW_TOLERANCE * scene.smallest_block_height();
        Self {
            gap,
            impulse: (LAW_TOLERANCE * weight * dt).max(SMALLEST_IMPULSE_TOL),
            slip: gap / dt,
        }
    }
}

/// A contact law (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Law {
    /// g_N ≥ 0.
    Gap,
    /// P_N ≥ 0.
    Normal,
    /// ‖P_F‖ ≤ μ Σ P_N.
    Cone,
    /// No impulse across an open gap; sliding friction on the cone against the slip.
    Complementarity,
}

impl Law {
    /// `gap`, `normal`, `cone` or `complementarity`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Gap => "gap",
            Self::Normal => "normal",
            Self::Cone => "cone",
            Self::Complementarity => "complementarity",
        }
    }
}

/// The worst violation of each law at one state, each ≥ 0 (0: the law holds exactly).
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize)]
pub struct Violations {
    /// The deepest interpenetration, −min g_N (length).
    pub gap: f64,
    /// The most negative normal impulse, −min P_N (impulse).
    pub normal: f64,
    /// The largest ‖P_F‖ − μ Σ P_N beyond the cone (impulse).
    pub cone: f64,
    /// The largest impulse across an open gap, or distance of a sliding contact's
    /// friction from −μ Σ P_N · γ_F/‖γ_F‖ (impulse).
    pub complementarity: f64,
}

impl Violations {
    /// Each law with its violation, in [`Law`] order.
    #[must_use]
    pub fn by_law(&self) -> [(Law, f64); 4] {
        [
            (Law::Gap, self.gap),
            (Law::Normal, self.normal),
            (Law::Cone, self.cone),
            (Law::Complementarity, self.complementarity),
        ]
    }

    /// The laws broken beyond `tol`, with their violations.
    #[must_use]
    pub fn broken(&self, tol: &Tolerances) -> Vec<(Law, f64)> {
        self.by_law()
            .into_iter()
            .filter(|&(law, v)| {
                v > match law {
                    Law::Gap => tol.gap,
                    _ => tol.impulse,
                }
            })
            .collect()
    }
}

/// The contact laws at one state: their violations and each interface's state.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ContactCheck {
    /// The worst violation of each law over every contact (corner contacts included).
    pub violations: Violations,
    /// Each interface's state (bottom to top, [`interface_state`]).
    pub states: Vec<String>,
    /// The laws broken beyond the tolerances, with their violations.
    pub broken: Vec<(Law, f64)>,
}

/// Checks the contact laws at `st` (the end of a step) of `system`, whose first
/// `n_interfaces` × 2 normal contacts and `n_interfaces` friction laws are the stack's
/// interfaces (the numbering of [`crate::contact_states`]).
#[must_use]
pub fn check<S: System>(
    system: &S,
    layout: &Layout,
    st: &State,
    n_interfaces: usize,
    tol: &Tolerances,
) -> ContactCheck {
    let mut eval = Evaluation::new(layout);
    system.evaluate_real(st.t, &st.q, &st.u, &mut eval);
    let gaps = &eval.position[layout.n_bilateral_position..];
    let slips = slips(&eval, &st.u);
    let slips = &slips[layout.n_bilateral_velocity..];
    let mut v = Violations::default();
    for (&g, &p) in gaps.iter().zip(&st.p_n) {
        v.gap = v.gap.max(-g);
        v.normal = v.normal.max(-p);
        if g > tol.gap {
            v.complementarity = v.complementarity.max(p);
        }
    }
    let mut sliding = Vec::with_capacity(layout.friction.len());
    for (j, law) in layout.friction.iter().enumerate() {
        let o = layout.friction_offset(j);
        let p_f = &st.p_f[o..o + law.components];
        let slip = &slips[o..o + law.components];
        let bound = law.mu * law.normals.iter().map(|&i| st.p_n[i]).sum::<f64>();
        v.cone = v.cone.max(norm(p_f) - bound);
        let closed = law.normals.iter().any(|&i| gaps[i] <= tol.gap);
        let slides = closed && norm(slip) > tol.slip;
        if slides {
            // The friction a sliding contact must carry: on the cone, against the slip.
            let s = norm(slip);
            let off: Vec<f64> = p_f
                .iter()
                .zip(slip)
                .map(|(f, g)| f + bound * g / s)
                .collect();
            v.complementarity = v.complementarity.max(norm(&off));
        }
        sliding.push(slides);
    }
    let states = (0..n_interfaces)
        .map(|k| interface_state([gaps[2 * k], gaps[2 * k + 1]], sliding[k], tol))
        .collect();
    ContactCheck {
        broken: v.broken(tol),
        violations: v,
        states,
    }
}

/// An interface's state from its two gaps and whether it slides: a letter per corner,
/// `o` open (gap > the gap tolerance) or `c` closed, then `-` (both open), `K` (stick)
/// or `S` (slide): `ccK`, `coS`, `oo-`.
#[must_use]
pub fn interface_state(gaps: [f64; 2], slides: bool, tol: &Tolerances) -> String {
    let mut s = String::with_capacity(3);
    for g in gaps {
        s.push(if g > tol.gap { 'o' } else { 'c' });
    }
    let friction = match (s.as_str(), slides) {
        ("oo", _) => '-',
        (_, true) => 'S',
        (_, false) => 'K',
    };
    s.push(friction);
    s
}

/// What a candidate breaks, as one CSV cell: the broken laws' names joined by `+`,
/// or `none`.
#[must_use]
pub fn breaks_text(broken: &[(Law, f64)]) -> String {
    if broken.is_empty() {
        return "none".into();
    }
    broken
        .iter()
        .map(|(l, _)| l.name())
        .collect::<Vec<_>>()
        .join("+")
}

/// The amounts of [`breaks_text`]'s laws joined by `+` (`0` when none is broken).
#[must_use]
pub fn violation_text(broken: &[(Law, f64)]) -> String {
    if broken.is_empty() {
        return "0".into();
    }
    let mut s = String::new();
    for (i, (_, v)) in broken.iter().enumerate() {
        if i > 0 {
            s.push('+');
        }
        let _ = write!(s, "{v:.3e}");
    }
    s
}

/// v = W_vᵀ u + χ_v of an evaluation: the bilateral velocity constraints, then the slips.
fn slips(eval: &Evaluation<f64>, u: &[f64]) -> Vec<f64> {
    let mut v = eval.velocity_chi.clone();
    for &(i, j, w) in &eval.velocity_w.entries {
        v[j] += w * u[i];
    }
    v
}

fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tol() -> Tolerances {
        Tolerances {
            gap: 1e-6,
            impulse: 1e-8,
            slip: 1e-4,
        }
    }

    #[test]
    fn only_violations_beyond_the_tolerance_are_broken() {
        let v = Violations {
            gap: 5e-7,
            normal: 2e-8,
            cone: 0.0,
            complementarity: 3e-3,
        };
        let broken = v.broken(&tol());
        assert_eq!(
            broken.iter().map(|b| b.0).collect::<Vec<_>>(),
            vec![Law::Normal, Law::Complementarity]
        );
        assert_eq!(breaks_text(&broken), "normal+complementarity");
        assert_eq!(violation_text(&broken), "2.000e-8+3.000e-3");
        assert_eq!(breaks_text(&[]), "none");
        assert_eq!(violation_text(&[]), "0");
    }

    #[test]
    fn interface_states_read_gaps_and_slip() {
        let t = tol();
        assert_eq!(interface_state([0.0, -1e-9], false, &t), "ccK");
        assert_eq!(interface_state([0.0, 0.1], true, &t), "coS");
        assert_eq!(interface_state([0.1, 0.1], false, &t), "oo-");
    }
}
