//! Branch points: the re-solves of a step with its index sets fixed (docs/method.md §8,
//! ERRATA 22).
//!
//! When the Newton iterates alternate between index sets, the step is re-solved once per
//! set seen, with the sets fixed. A solution the step may continue with is
//! self-consistent (the sets recomputed from it are the ones it was solved with);
//! distinct solutions (deduplicated by state, [`State::same_motion`]) are distinct
//! continuations, and the step continues with the one [`System::choose_branch`] picks.
//! The [`BranchRule`] only decides what the branch point *records*: under
//! [`BranchRule::Converged`] the converged solves that are not self-consistent follow the
//! self-consistent candidates in it, and a step with none of the latter goes on to the
//! policy's later stages, as under [`BranchRule::SelfConsistent`], carrying the recorded
//! point to the trial they commit ([`record_unfollowed`]). So the run's trajectory is the
//! same under either rule.

use super::enumerate::probe_sets;
use super::spec::SetRule;
use super::Stepper;
use crate::attempt::Trial;
use crate::options::BranchRule;
use crate::report::BranchPoint;
use crate::sets::IndexSets;
use crate::state::State;
use crate::system::{FrictionLaw, System};

/// Self-consistent, distinct solutions of one step, in the order they were found.
#[derive(Debug, Default)]
struct Candidates {
    found: Vec<(IndexSets, State)>,
    consistent: Vec<bool>,
    trials: Vec<Trial>,
}

impl Candidates {
    /// Keeps `trial` (solved with `sets`, self-consistent or not) unless its state repeats
    /// one already kept; a repeat that is self-consistent marks the kept one so.
    fn offer(&mut self, sets: &IndexSets, trial: Trial, consistent: bool) {
        match self.position(&trial.state) {
            Some(i) => self.consistent[i] |= consistent,
            None => {
                self.found.push((sets.clone(), trial.state.clone()));
                self.consistent.push(consistent);
                self.trials.push(trial);
            }
        }
    }

    /// The kept candidate whose state is the same motion as `state`.
    fn position(&self, state: &State) -> Option<usize> {
        self.found.iter().position(|(_, s)| s.same_motion(state))
    }
}

/// Converged fixed-set solutions that are not self-consistent, in the order they were
/// found: recorded under [`BranchRule::Converged`], never continued with.
type Unfollowed = Vec<(IndexSets, State)>;

impl<S: System> Stepper<S> {
    /// The fixed-set re-solves of a cycling step: one per visited set, in first-visit
    /// order. The self-consistent ones, deduplicated by state, are the candidates, and
    /// the one the system chooses is returned with the branch point; under
    /// [`BranchRule::Converged`] the point also records the converged solves that are not
    /// self-consistent, after the candidates. With no self-consistent candidate the
    /// stage fails, with the point of those others when the rule records any (see the
    /// module docs).
    pub(super) fn branch_trial(
        &mut self,
        visited: &[IndexSets],
        rho0: f64,
    ) -> Result<Trial, Option<BranchPoint>> {
        let mut candidates = Candidates::default();
        let mut others = Unfollowed::new();
        for sets in visited {
            let Ok(t) = self.attempt(self.retry_spec(SetRule::Fixed(sets.clone()), rho0)) else {
                continue;
            };
            // Self-consistency: the sets recomputed from the converged x.
            if &self.sets_of(&t.state.x, rho0) == sets {
                candidates.offer(sets, t, true);
            } else if self.options.policy.continue_inconsistent {
                candidates.offer(sets, t, false);
            } else if self.options.policy.branch_rule == BranchRule::Converged {
                others.push((sets.clone(), t.state));
            }
        }
        let tried = visited.len();
        let Some(mut trial) = self.chosen(candidates, tried) else {
            let point = BranchPoint {
                t: self.state.t,
                candidates: Vec::new(),
                consistent: Vec::new(),
                tried,
                chosen: 0,
            };
            return Err(Some(with_unfollowed(point, others)).filter(|p| !p.candidates.is_empty()));
        };
        if let Some(point) = trial.stats.branch.take() {
            trial.stats.branch = Some(with_unfollowed(point, others));
        }
        Ok(trial)
    }

    /// The candidate [`System::choose_branch`] picks, carrying the branch point.
    fn chosen(&self, candidates: Candidates, tried: usize) -> Option<Trial> {
        let Candidates {
            found,
            consistent,
            mut trials,
        } = candidates;
        if trials.is_empty() {
            return None;
        }
        let chosen = self
            .system
            .choose_branch(self.state.t, &found)
            .min(trials.len() - 1);
        let mut t = trials.swap_remove(chosen);
        t.stats.branch = Some(BranchPoint {
            t: self.state.t,
            candidates: found,
            consistent,
            tried,
            chosen,
        });
        Some(t)
    }

    /// The flip probe of a converged step ([`PolicyOptions::probe_flips`]): the step re-solved
    /// with the touching normal contacts' states enumerated or flipped ([`probe_sets`]); the
    /// self-consistent solutions that differ from `converged` make a branch point whose
    /// first candidate is `converged` (the one continued).
    ///
    /// [`PolicyOptions::probe_flips`]: crate::PolicyOptions::probe_flips
    pub(super) fn probe_flips(&mut self, converged: Trial, rho0: f64) -> Trial {
        let touching = self.touching_contacts(&converged.stats.sets);
        let flips = probe_sets(&converged.stats.sets, &touching, &self.layout.friction);
        let mut candidates = Candidates::default();
        let sets = converged.stats.sets.clone();
        candidates.offer(&sets, converged, true);
        for s in &flips {
            if let Some(t) = self.probe_solution(s, rho0) {
                let solved = t.stats.sets.clone();
                candidates.offer(&solved, t, true);
            }
        }
        let more = candidates.trials.len() > 1;
        let mut first = candidates.trials.swap_remove(0);
        if more {
            first.stats.branch = Some(BranchPoint {
                t: self.state.t,
                candidates: candidates.found,
                consistent: candidates.consistent,
                tried: flips.len() + 1,
                chosen: 0,
            });
        }
        first
    }

    /// The normal contacts whose state a flip probe changes: those closed in `sets` and
    /// those whose gap at the step's start is within [`Options::start_tol`] of zero.
    ///
    /// [`Options::start_tol`]: crate::Options::start_tol
    fn touching_contacts(&mut self, sets: &IndexSets) -> Vec<usize> {
        self.state_levels();
        (0..self.off.nn)
            .filter(|&k| sets.a[k] || self.at_zero_gap(k))
            .collect()
    }

    /// Whether normal contact `k` is within [`Options::start_tol`] of zero gap at the
    /// step's start, from the levels of the current state (`Stepper::state_levels`,
    /// which the caller has made current).
    ///
    /// [`Options::start_tol`]: crate::Options::start_tol
    pub(super) fn at_zero_gap(&self, k: usize) -> bool {
        let gap = self.work.state_levels.position[self.off.ng + k];
        gap.abs() <= self.options.start_tol
    }
}

/// `point` with the converged solves that are not self-consistent appended to its
/// candidates, each unless its state repeats one already there.
fn with_unfollowed(mut point: BranchPoint, others: Unfollowed) -> BranchPoint {
    for (sets, state) in others {
        if !point.candidates.iter().any(|(_, s)| s.same_motion(&state)) {
            point.candidates.push((sets, state));
            point.consistent.push(false);
        }
    }
    point
}

/// Records on `trial`, which a later stage of a step found, the branch point `point` whose
/// fixed-set solves were none self-consistent ([`Stepper::branch_trial`] under
/// [`BranchRule::Converged`]): the trial's own state is a candidate of the point (in
/// place of one of the same motion), the one continued. A trial that carries a branch
/// point of its own keeps it.
pub(super) fn record_unfollowed(mut point: BranchPoint, trial: &mut Trial) {
    if trial.stats.branch.is_some() {
        return;
    }
    let continued = (trial.stats.sets.clone(), trial.state.clone());
    let consistent = trial.stats.converged && trial.stats.last_resort.is_none();
    let same = point
        .candidates
        .iter()
        .position(|(_, s)| s.same_motion(&trial.state));
    point.chosen = match same {
        Some(i) => {
            point.candidates[i] = continued;
            point.consistent[i] = consistent;
            i
        }
        None => {
            point.candidates.push(continued);
            point.consistent.push(consistent);
            point.candidates.len() - 1
        }
    };
    trial.stats.branch = Some(point);
}

/// The sets of a flip probe: for each of the `touching` normal contacts, `sets` with it
/// opened (when it is closed on acceleration level, C) or else closed on every level with
/// each state of the friction laws it bounds (slip, stick on velocity level only, stick).
pub(super) fn flipped_sets(
    sets: &IndexSets,
    touching: &[usize],
    laws: &[FrictionLaw],
) -> Vec<IndexSets> {
    let mut out: Vec<IndexSets> = Vec::new();
    let mut push = |s: IndexSets| {
        if &s != sets && !out.contains(&s) {
            out.push(s);
        }
    };
    for &k in touching {
        let mut s = sets.clone();
        if sets.c[k] {
            s.a[k] = false;
            s.b[k] = false;
            s.c[k] = false;
            push(s);
            continue;
        }
        s.a[k] = true;
        s.b[k] = true;
        s.c[k] = true;
        let bound: Vec<usize> = (0..laws.len())
            .filter(|&j| laws[j].normals.contains(&k))
            .collect();
        for (d, e) in [(false, false), (true, false), (true, true)] {
            let mut f = s.clone();
            for &j in &bound {
                f.d[j] = d;
                f.e[j] = e;
            }
            push(f);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::StepStats;

    fn trial(x: f64) -> Trial {
        let state = State {
            q: vec![1.0, x],
            u: vec![0.5, 0.0],
            ..State::default()
        };
        Trial {
            state,
            stats: StepStats {
                t: 0.0,
                iterations: 1,
                residual: 0.0,
                rho_inf: 0.5,
                sets: IndexSets::default(),
                retries: 0,
                converged: true,
                branch: None,
                solver: "dense".into(),
                substeps: 1,
                last_resort: None,
                unshifted: false,
            },
            visited: Vec::new(),
            cycling: false,
        }
    }

    #[test]
    fn candidates_closer_than_the_tolerance_are_one_continuation() {
        // |(q, u)| ≈ 1.6: the tolerance is 1e-8 × (1 + ‖q‖ + ‖u‖) ≈ 2.6e-8.
        let sets = IndexSets::empty(1, 0);
        let mut c = Candidates::default();
        c.offer(&sets, trial(0.0), false);
        c.offer(&sets, trial(1e-9), true);
        assert_eq!(c.found.len(), 1, "a repeat within round-off is merged");
        assert_eq!(
            c.consistent,
            [true],
            "a self-consistent repeat marks the kept one"
        );
        c.offer(&sets, trial(1e-6), true);
        assert_eq!(
            c.found.len(),
            2,
            "a candidate 1e-6 away is another continuation"
        );
        assert!(c.found[0].1.relative_distance(&c.found[1].1) > crate::state::SAME_MOTION);
    }
}
