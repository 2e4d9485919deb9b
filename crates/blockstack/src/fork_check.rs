//! Real bifurcation or solver artefact: each fork re-run under refinement.
//!
//! A fork's candidates are solutions of one step of the time stepping scheme, not of the
//! equations of motion. A **real** non-uniqueness (Painlevé's indeterminacy, App. I: a
//! sliding corner that may keep contact with a large force or lift off) is a property of
//! the motion: it keeps distinct, self-consistent continuations when the step is refined.
//! An **artefact** of the scheme (candidates that break a contact law, or that differ
//! only because the step is coarse) merges into one motion or vanishes.
//!
//! The window is the forking step itself, t_n → t_n + Δt, taken again from the state at
//! t_n (so the comparison sees the same past):
//! - with Δt/2 and Δt/4, exploring every fork inside the window, self-consistent
//!   candidates only ([`nsga::BranchRule::SelfConsistent`]);
//! - with Δt and the other prox choice (the thesis's constant r = 0.3 against the scaled
//!   default), reported as evidence.
//!
//! The distinct end states of each re-run (deduplicated by [`nsga::State::same_motion`])
//! are counted. Label: **real** when the fork has at least two self-consistent candidates
//! and both refinements keep at least two distinct continuations; **artefact** when both
//! refinements find one continuation (the candidates merge into one motion, or were not
//! solutions to begin with); **undecided** otherwise (the evidence is in the output
//! either way).

use crate::exploration::StackWalker;
use nsga::explore::{explore, ExploreOptions, Strategy};
use nsga::{BranchPoint, BranchRule, Prox, State};

/// The refinements of the window: Δt/2 and Δt/4.
pub const REFINEMENTS: [u32; 2] = [2, 4];

/// Most branches of one re-run of the window (it covers a single step).
pub const WINDOW_MAX_BRANCHES: usize = 32;

/// The thesis's constant prox parameter, compared with the scaled default.
pub const THESIS_PROX: f64 = 0.3;

/// What a fork is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ForkLabel {
    /// Distinct self-consistent continuations that survive refinement.
    Real,
    /// One motion under refinement.
    Artefact,
    /// The evidence disagrees.
    Undecided,
}

impl ForkLabel {
    /// `real`, `artefact` or `undecided`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Real => "real",
            Self::Artefact => "artefact",
            Self::Undecided => "undecided",
        }
    }
}

/// The evidence on one fork and its label.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ForkEvidence {
    /// Self-consistent, distinct candidates of the fork at Δt.
    pub consistent: usize,
    /// Distinct continuations at the window's end with Δt/2 and Δt/4 ([`REFINEMENTS`]);
    /// None where the re-run could not be made (the stack's contacts changed within the
    /// step).
    pub refined: [Option<usize>; 2],
    /// Distinct continuations at Δt with the other prox choice.
    pub other_prox: Option<usize>,
    /// The label.
    pub label: ForkLabel,
}

impl ForkEvidence {
    /// The label from the counts (see the module docs).
    #[must_use]
    pub fn judge(consistent: usize, refined: [Option<usize>; 2]) -> ForkLabel {
        match refined {
            [Some(a), Some(b)] if consistent >= 2 && a >= 2 && b >= 2 => ForkLabel::Real,
            [Some(1), Some(1)] => ForkLabel::Artefact,
            _ => ForkLabel::Undecided,
        }
    }
}

/// Checks the fork `point` met by `walker` on the step from `before` (see the module
/// docs). `walker` is the branch's walker after the step.
#[must_use]
pub fn check_fork(walker: &StackWalker<'_>, before: &State, point: &BranchPoint) -> ForkEvidence {
    let consistent = point.consistent.iter().filter(|&&c| c).count();
    let refined = REFINEMENTS.map(|m| window_continuations(walker, before, m, None));
    let other = match walker.options().prox {
        Prox::Constant(_) => Prox::Scaled(1.0),
        Prox::Scaled(_) => Prox::Constant(THESIS_PROX),
    };
    let other_prox = window_continuations(walker, before, 1, Some(other));
    ForkEvidence {
        consistent,
        refined,
        other_prox,
        label: ForkEvidence::judge(consistent, refined),
    }
}

/// The distinct end states of the step from `before` taken as `parts` substeps (with
/// `prox` when given), every fork inside followed; None when the walker cannot restart
/// from `before`.
fn window_continuations(
    walker: &StackWalker<'_>,
    before: &State,
    parts: u32,
    prox: Option<Prox>,
) -> Option<usize> {
    let mut options = walker.options().clone();
    options.dt /= f64::from(parts);
    options.policy.branch_rule = BranchRule::SelfConsistent;
    if let Some(p) = prox {
        options.prox = p;
    }
    let window = walker.restarted(before, options, before.k + u64::from(parts))?;
    let tree = explore(
        window,
        &ExploreOptions {
            strategy: Strategy::Depth,
            max_branches: WINDOW_MAX_BRANCHES,
            ..ExploreOptions::default()
        },
    );
    let mut ends: Vec<State> = Vec::new();
    for leaf in tree.leaves() {
        if let Some(s) = &leaf.outcome.end_state {
            if leaf.end_at.1 == before.k + u64::from(parts)
                && !ends.iter().any(|e| e.same_motion(s))
            {
                ends.push(s.clone());
            }
        }
    }
    Some(ends.len())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn labels_follow_the_counts() {
        assert_eq!(ForkEvidence::judge(2, [Some(2), Some(3)]), ForkLabel::Real);
        assert_eq!(
            ForkEvidence::judge(1, [Some(1), Some(1)]),
            ForkLabel::Artefact
        );
        assert_eq!(
            ForkEvidence::judge(0, [Some(1), Some(1)]),
            ForkLabel::Artefact
        );
        // Merging under refinement makes an artefact even of self-consistent candidates.
        assert_eq!(
            ForkEvidence::judge(2, [Some(1), Some(1)]),
            ForkLabel::Artefact
        );
        assert_eq!(
            ForkEvidence::judge(2, [Some(2), Some(1)]),
            ForkLabel::Undecided
        );
        assert_eq!(
            ForkEvidence::judge(1, [Some(2), Some(2)]),
            ForkLabel::Undecided
        );
        assert_eq!(
            ForkEvidence::judge(2, [None, Some(2)]),
            ForkLabel::Undecided
        );
    }
}
