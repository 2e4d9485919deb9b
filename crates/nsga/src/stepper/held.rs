//! The held-sets attempt at a step (docs/method.md §8.2): Newton first solves the step
//! with the previous step's index sets, and from that solution lets the contact laws
//! change the sets, opening at most a few contacts per update.
//!
//! Why: when a tall column starts to tip, the step has two solutions. The column can
//! turn about its base as one body, which is the previous step's sets with the base
//! corner opened. Or it can open a band of interfaces higher up. Free Newton finds tension
//! at a dozen corners after its first update and opens them all. From there each
//! update moves the band of openings up by one interface, so it reaches the far solution
//! after a number of updates in proportion to the column's height (276 updates for 300
//! blocks, 762 for 1000). With the sets held, the first solution is the previous motion
//! continued. From there, opening the most tensile corner first opens the base corner,
//! and Newton converges on the solution in which only that corner has lifted (4 updates
//! for 300 blocks; `cargo run --release -p blockstack --example tipping_onset`).

use super::scheme::Scheme;
use super::Stepper;
use crate::sets::IndexSets;
use crate::system::System;

/// The progress of one held-sets attempt.
#[derive(Debug, Clone)]
pub(super) struct HeldSets {
    /// The previous step's sets while they are held; None once released.
    held: Option<IndexSets>,
    /// Evaluations made while holding, and the held residual ‖R‖∞ at the last one.
    evaluations: usize,
    last_residual: f64,
    /// The sets of the last Newton update, against which openings are counted.
    last_update: IndexSets,
    /// Openings per update after the release.
    most: usize,
}

impl HeldSets {
    /// Holds `previous` (the sets the last step converged with).
    pub(super) fn new(previous: IndexSets, most: usize) -> Self {
        Self {
            held: Some(previous.clone()),
            evaluations: 0,
            last_residual: f64::INFINITY,
            last_update: previous,
            most,
        }
    }

    /// A Newton update was taken with `sets`.
    pub(super) fn updated(&mut self, sets: &IndexSets) {
        self.last_update.clone_from(sets);
    }
}

impl<S: System> Stepper<S> {
    /// Evaluates the iterate `x` under the held-sets policy: returns the sets of the next
    /// update (whose residual the stepper keeps) and the ‖R‖∞ of the contact laws' own
    /// sets, on which convergence is judged.
    ///
    /// While the previous sets are held, the update solves the step with them. They are
    /// released once that solve has converged or stalled (its residual no longer falls
    /// below [`Tuning::held_contraction`](crate::Tuning::held_contraction) times the last;
    /// a cap on its evaluations paid nothing on the reference workload, docs/method.md
    /// §8.2). From then on, the sets of an update
    /// are the laws' sets with at most `most` contacts opened since the last update.
    /// While the sets are held, the returned norm is the held solve's, so that the
    /// give-up rules judge the solve the update belongs to; it is above the tolerance,
    /// so the engine never stops on it. The attempt takes its updates whole (no line
    /// search, see `Stepper::spec`), so the norms before and after the release,
    /// which do not compare, are never weighed against each other.
    pub(super) fn evaluate_held(
        &mut self,
        x: &[f64],
        p: &Scheme,
        first: bool,
        progress: &mut HeldSets,
    ) -> (IndexSets, f64) {
        let limit = (&progress.last_update, progress.most);
        let (sets, res) = self.evaluate_at(x, None, p, first, Some(limit));
        let Some(held) = &progress.held else {
            return (sets, res);
        };
        let held = self.with_unsupported_open(held);
        if res <= self.options.tol || sets == *held {
            return (sets, res);
        }
        // The laws' residual is the update's again if the sets are released here.
        let laws = self.work.res.clone();
        self.residual(x, &held, p);
        let held_res = self.residual_norm(&held);
        progress.evaluations += 1;
        let tuning = &self.options.tuning;
        let stalled =
            progress.evaluations > 1 && held_res > tuning.held_contraction * progress.last_residual;
        if held_res <= self.options.tol || stalled {
            progress.held = None;
            self.work.res = laws;
            return (sets, res);
        }
        progress.last_residual = held_res;
        (held.into_owned(), held_res)
    }
}
