//! Real bifurcation or solver artefact: each fork checked against the contact laws and
//! re-run under refinement over a window of steps.
//!
//! A fork's candidates are solutions of one step of the time stepping scheme, not of the
//! equations of motion. A **real** non-uniqueness (Painlevé's indeterminacy, App. I: a
//! sliding corner that may keep contact with a large force or lift off) is a property of
//! the motion: it keeps distinct, self-consistent continuations when the step is refined.
//! An **artefact** of the scheme is a candidate that breaks a contact law, or candidates
//! that merge into one motion when the step is refined.
//!
//! The evidence on a fork met on the step t_n → t_n + Δt:
//! 1. each candidate's own step checked against the contact laws
//!    ([`crate::contact_laws`]): which law it breaks, and by how much;
//! 2. the **window**: from the state at t_n (or, when that state overlaps beyond the
//!    run's penetration tolerance, the last state before it that does not, at most
//!    W − 1 steps back) to t_n + W Δt (W = [`DEFAULT_WINDOW`] unless set), taken again at
//!    Δt/2 and Δt/4 ([`REFINEMENTS`]) under both branch rules, every fork inside the
//!    window followed: the distinct states at the window's end
//!    ([`nsga::State::same_motion`]) are its continuations;
//! 3. the window at Δt with the other prox choice (the thesis's constant r = 0.3 against
//!    the scaled default), self-consistent rule, reported only.
//!
//! The label ([`ForkEvidence::judge`]), with its reason:
//! - **real** when the fork has at least two self-consistent candidates and the
//!   self-consistent rule keeps at least two continuations at both Δt/2 and Δt/4;
//! - **artefact** only with evidence: a candidate breaks a contact law and, without the
//!   candidates that break one, at most one remains or the self-consistent refinements
//!   keep one continuation; or the fork has fewer than two self-consistent candidates
//!   and both self-consistent refinements keep one continuation. A fork with two
//!   self-consistent candidates that obey the laws is never an artefact;
//! - **undecided** otherwise (the evidence is in the output either way).

use crate::contact_laws::ContactCheck;
use crate::exploration::StackWalker;
use crate::overlap::deepest_penetration;
use nsga::explore::{explore, ExploreOptions, Strategy};
use nsga::{BranchPoint, BranchRule, Prox, State};
use std::collections::VecDeque;

/// The refinements of the window: Δt/2 and Δt/4.
pub const REFINEMENTS: [u32; 2] = [2, 4];

/// Coarse steps in the window unless set (`blocks explore --classify-window`): long
/// enough for a lift-off or a change of slip to show in the positions, short enough to
/// keep `--classify` to seconds.
pub const DEFAULT_WINDOW: u64 = 5;

/// Most branches of one re-run of the window.
pub const WINDOW_MAX_BRANCHES: usize = 32;

/// The thesis's constant prox parameter, compared with the scaled default.
pub const THESIS_PROX: f64 = 0.3;

/// What a fork is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ForkLabel {
    /// Distinct self-consistent continuations that survive refinement.
    Real,
    /// A candidate breaks a contact law, or the candidates merge into one motion.
    Artefact,
    /// The evidence does not decide.
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

/// Continuations at the window's end at Δt/2 and Δt/4 ([`REFINEMENTS`]); None where the
/// window could not be taken again (the stack's contacts changed within it, or every
/// state before the fork overlaps).
pub type Refined = [Option<usize>; 2];

/// What the label is judged from (see [`ForkEvidence::judge`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Counts {
    /// Distinct candidates of the fork at Δt.
    pub candidates: usize,
    /// Self-consistent candidates among them.
    pub consistent: usize,
    /// Candidates whose own step breaks a contact law ([`crate::contact_laws`]).
    pub breaking: usize,
    /// Continuations under the self-consistent rule.
    pub self_consistent: Refined,
}

/// The evidence on one fork and its label.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ForkEvidence {
    /// Self-consistent, distinct candidates of the fork at Δt.
    pub consistent: usize,
    /// Candidates whose own step breaks a contact law.
    pub breaking: usize,
    /// Coarse steps in the window.
    pub window: u64,
    /// Steps the window's start lies before the fork's (0 unless the state at t_n
    /// overlaps); None when every state in reach overlaps.
    pub stepped_back: Option<u64>,
    /// Continuations at Δt/2 and Δt/4 under the self-consistent rule.
    pub refined: Refined,
    /// Continuations at Δt/2 and Δt/4 under the converged rule (the thesis's count).
    pub refined_converged: Refined,
    /// Continuations at Δt with the other prox choice, self-consistent rule.
    pub other_prox: Option<usize>,
    /// The label.
    pub label: ForkLabel,
    /// Why, in a line.
    pub why: String,
}

impl ForkEvidence {
    /// The label from the counts, with its reason (see the module docs).
    #[must_use]
    pub fn judge(c: &Counts) -> (ForkLabel, String) {
        let sc = c.self_consistent;
        let persists = matches!(sc, [Some(a), Some(b)] if a >= 2 && b >= 2);
        let merges = matches!(sc, [Some(a), Some(b)] if a <= 1 && b <= 1);
        let lawful = c.candidates - c.breaking;
        if c.consistent >= 2 && persists {
            let why = format!(
                "{} self-consistent candidates; {} and {} self-consistent continuations at dt/2 and dt/4",
                c.consistent,
                sc[0].unwrap_or(0),
                sc[1].unwrap_or(0)
            );
            return (ForkLabel::Real, why);
        }
        if c.breaking > 0 && (lawful <= 1 || merges) {
            let how = if merges {
                "one self-consistent continuation at dt/2 and dt/4"
            } else {
                "at most one candidate obeys them"
            };
            let why = format!("{} candidate(s) break a contact law; {how}", c.breaking);
            return (ForkLabel::Artefact, why);
        }
        if c.consistent < 2 && merges {
            let why = format!(
                "{} self-consistent candidate(s); one continuation at dt/2 and dt/4",
                c.consistent
            );
            return (ForkLabel::Artefact, why);
        }
        let why = if sc.contains(&None) {
            "the window could not be taken again".to_owned()
        } else if merges {
            format!(
                "{} self-consistent candidates obey the contact laws but merge at dt/2 and dt/4",
                c.consistent
            )
        } else {
            format!(
                "{} self-consistent candidate(s); {} and {} self-consistent continuations at dt/2 and dt/4",
                c.consistent,
                sc[0].unwrap_or(0),
                sc[1].unwrap_or(0)
            )
        };
        (ForkLabel::Undecided, why)
    }
}

/// The window's recent past: the states at the start of the last W steps, oldest first.
#[derive(Debug, Clone, Default)]
pub struct History {
    states: VecDeque<State>,
    window: u64,
}

impl History {
    /// Keeps the last `window` states (at least 1).
    #[must_use]
    pub fn new(window: u64) -> Self {
        Self {
            states: VecDeque::new(),
            window: window.max(1),
        }
    }

    /// Adds the state at the start of a step, forgetting the oldest beyond the window.
    pub fn push(&mut self, st: &State) {
        if self.states.len() as u64 >= self.window {
            if let Some(mut old) = self.states.pop_front() {
                old.clone_from(st);
                self.states.push_back(old);
                return;
            }
        }
        self.states.push_back(st.clone());
    }

    /// The state at the start of the last step.
    #[must_use]
    pub fn last(&self) -> Option<&State> {
        self.states.back()
    }

    /// Coarse steps in the window.
    #[must_use]
    pub fn window(&self) -> u64 {
        self.window
    }
}

/// Checks the fork `point` met by `walker` on the step from `history`'s last state, its
/// candidates' own steps checked in `laws` (see the module docs). `walker` is the
/// branch's walker after the step.
#[must_use]
pub fn check_fork(
    walker: &StackWalker<'_>,
    history: &History,
    point: &BranchPoint,
    laws: &[ContactCheck],
) -> ForkEvidence {
    let before = history.last().expect("the forking step's start is kept");
    let end = before.k + history.window;
    let start = history.states.iter().rev().find(|s| !walker.overlaps(s));
    let window = |parts: u32, rule: BranchRule, prox: Option<Prox>| {
        start.and_then(|s| window_continuations(walker, s, end, parts, rule, prox))
    };
    let refined = REFINEMENTS.map(|m| window(m, BranchRule::SelfConsistent, None));
    let refined_converged = REFINEMENTS.map(|m| window(m, BranchRule::Converged, None));
    let other = match walker.options().prox {
        Prox::Constant(_) => Prox::Scaled(1.0),
        Prox::Scaled(_) => Prox::Constant(THESIS_PROX),
    };
    let other_prox = window(1, BranchRule::SelfConsistent, Some(other));
    let counts = Counts {
        candidates: point.candidates.len(),
        consistent: point.consistent.iter().filter(|&&c| c).count(),
        breaking: laws.iter().filter(|l| !l.broken.is_empty()).count(),
        self_consistent: refined,
    };
    let (label, mut why) = ForkEvidence::judge(&counts);
    let stepped_back = start.map(|s| before.k - s.k);
    match stepped_back {
        Some(0) => {}
        Some(b) => why.push_str(&format!(
            "; window from {b} step(s) before the fork (the state at t_n overlaps)"
        )),
        None => why.push_str("; every state in the window before the fork overlaps"),
    }
    ForkEvidence {
        consistent: counts.consistent,
        breaking: counts.breaking,
        window: history.window,
        stepped_back,
        refined,
        refined_converged,
        other_prox,
        label,
        why,
    }
}

/// The distinct states at coarse step `end` of the run from `start` with Δt/`parts`
/// (with `rule`, and `prox` when given), every fork inside followed; None when the
/// walker cannot restart from `start`.
fn window_continuations(
    walker: &StackWalker<'_>,
    start: &State,
    end: u64,
    parts: u32,
    rule: BranchRule,
    prox: Option<Prox>,
) -> Option<usize> {
    let mut options = walker.options().clone();
    options.dt /= f64::from(parts);
    options.policy.branch_rule = rule;
    if let Some(p) = prox {
        options.prox = p;
    }
    // The stepper counts on from start.k on its finer grid.
    let horizon = start.k + (end - start.k) * u64::from(parts);
    let window = walker.restarted(start, options, horizon)?;
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
            if leaf.end_at.1 == horizon && !ends.iter().any(|e| e.same_motion(s)) {
                ends.push(s.clone());
            }
        }
    }
    Some(ends.len())
}

impl StackWalker<'_> {
    /// Whether two bodies overlap at `st` beyond the run's penetration tolerance.
    #[must_use]
    pub fn overlaps(&self, st: &State) -> bool {
        deepest_penetration(self.scene(), st.t, &st.q).depth > self.penetration_tol()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn judge(
        candidates: usize,
        consistent: usize,
        breaking: usize,
        sc: Refined,
    ) -> (ForkLabel, String) {
        ForkEvidence::judge(&Counts {
            candidates,
            consistent,
            breaking,
            self_consistent: sc,
        })
    }

    #[test]
    fn real_needs_two_self_consistent_continuations_at_both_refinements() {
        let (label, why) = judge(2, 2, 0, [Some(2), Some(3)]);
        assert_eq!(label, ForkLabel::Real);
        assert!(why.contains("2 and 3"), "{why}");
        assert_eq!(judge(2, 2, 0, [Some(2), Some(1)]).0, ForkLabel::Undecided);
        assert_eq!(judge(2, 2, 0, [None, Some(2)]).0, ForkLabel::Undecided);
        // Continuations that appear only under refinement do not make a fork real.
        assert_eq!(judge(2, 1, 1, [Some(2), Some(2)]).0, ForkLabel::Artefact);
        assert_eq!(judge(3, 1, 0, [Some(2), Some(2)]).0, ForkLabel::Undecided);
    }

    #[test]
    fn two_lawful_self_consistent_candidates_are_never_an_artefact() {
        // They merge under refinement, but neither breaks a law: one-step evidence.
        let (label, why) = judge(2, 2, 0, [Some(1), Some(1)]);
        assert_eq!(label, ForkLabel::Undecided);
        assert!(why.contains("merge"), "{why}");
        // The same fork with a candidate that breaks a law is an artefact.
        let (label, why) = judge(2, 2, 1, [Some(1), Some(1)]);
        assert_eq!(label, ForkLabel::Artefact);
        assert!(why.contains("break a contact law"), "{why}");
    }

    #[test]
    fn a_candidate_that_breaks_a_law_is_evidence_of_an_artefact() {
        // The thesis's rule: one solution of the step and a converged solve that pulls.
        let (label, why) = judge(2, 1, 1, [None, None]);
        assert_eq!(label, ForkLabel::Artefact);
        assert!(why.contains("at most one candidate obeys"), "{why}");
        // Two lawful candidates beside the breaking one, refinements not merging.
        assert_eq!(judge(3, 2, 1, [Some(2), Some(1)]).0, ForkLabel::Undecided);
    }

    #[test]
    fn fewer_than_two_self_consistent_candidates_merging_are_an_artefact() {
        let (label, why) = judge(2, 1, 0, [Some(1), Some(1)]);
        assert_eq!(label, ForkLabel::Artefact);
        assert!(why.contains("one continuation"), "{why}");
        assert_eq!(judge(2, 0, 0, [Some(1), Some(1)]).0, ForkLabel::Artefact);
    }

    #[test]
    fn the_history_keeps_the_window() {
        let mut h = History::new(3);
        for k in 0..5 {
            h.push(&State {
                k,
                ..State::default()
            });
        }
        let ks: Vec<u64> = h.states.iter().map(|s| s.k).collect();
        assert_eq!(ks, vec![2, 3, 4]);
        assert_eq!(h.last().map(|s| s.k), Some(4));
    }
}
