//! The semismooth Newton engine (paper eq. 143, docs/method.md §4 and §8).
//!
//! One iteration loop serves every nonsmooth problem of the crate: the step of the
//! generalized-α [`Stepper`](crate::Stepper), its consistent start
//! ([`consistent_start`](crate::start::consistent_start)) and the Moreau–Jean baseline
//! ([`MoreauStepper`](crate::MoreauStepper)). A problem says how to evaluate its
//! residual and index sets at an iterate and how to compute a Newton update; the engine
//! owns the rest:
//!
//! - the iteration itself: evaluate, test ‖R‖∞ against the tolerance, update;
//! - the **line search** ([`NewtonSettings::line_search`]): the update is damped by
//!   halvings where the full one overshoots;
//! - **simplified Newton updates** ([`NewtonSettings::reuse_factorization`]): the kept
//!   factors of the last Newton matrix serve while the index sets stay the same and the
//!   residual contracts by [`Tuning::reuse_contraction`](crate::Tuning::reuse_contraction), at most [`Tuning::max_reuses`](crate::Tuning::max_reuses) times in a row,
//!   or, with [`NewtonSettings::follow_sets`], on through a rise at sets a low-rank
//!   update reached first; an attempt without [`NewtonSettings::new_factors`] takes only
//!   those and stops where they no longer serve;
//! - the **give-up rules** ([`GiveUp`]): an attempt whose index sets settle into a cycle
//!   without progress, or whose residual stalls with fixed sets, stops before the
//!   iteration limit, since running on only repeats it, and one whose start is farther
//!   off than its [`NewtonSettings::start_limit`] stops there; and the other way round,
//!   an attempt may be allowed updates past its limit while it converges
//!   ([`NewtonSettings::contracting_extra`]);
//! - the **bookkeeping** a fallback policy needs: the index sets visited in first-visit
//!   order, whether they cycled, and the best iterate.

use crate::tuning::Tuning;

/// Sufficient-decrease constant of the line search (see [`NewtonSettings::line_search`]).
const ARMIJO: f64 = 1e-4;

/// When an attempt stops before its iteration limit.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GiveUp {
    /// Never: run to the iteration limit (the consistent start and Moreau–Jean).
    Never,
    /// When the index sets have settled into a cycle without progress
    /// ([`settled_cycle`]): the free step of the generalized-α stepper.
    SettledCycle,
    /// When the residual has stalled ([`stalled`]): solves with fixed index sets.
    Stall,
}

/// How one Newton attempt iterates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NewtonSettings {
    /// Tolerance on ‖R‖∞.
    pub tol: f64,
    /// Largest number of Newton updates.
    pub max_iter: usize,
    /// Halvings of an update allowed in the line search (0: full updates).
    pub line_search: usize,
    /// Whether simplified updates from kept factors may be tried.
    pub reuse_factorization: bool,
    /// Whether they may be tried again after a new factorization, once one failed to
    /// contract (otherwise not for the rest of the attempt).
    pub resume_reuse: bool,
    /// Whether the attempt may factor a Newton matrix of its own. Without, it takes
    /// simplified updates on the kept factors only and stops where none applies.
    pub new_factors: bool,
    /// Whether the kept factors follow the index sets: where a low-rank update
    /// ([`KeptUpdate::ChangedRows`]) reaches sets the attempt has not visited, its
    /// residual is not compared with the last iterate's, of other sets, the factors
    /// serve on, and [`Tuning::max_reuses`](crate::Tuning::max_reuses) counts the updates
    /// in a row from there. A rise after a simplified update at the factors' own sets, or
    /// at sets visited before, still retires them. The held-sets attempt's rule
    /// (docs/method.md §8.2, "The held-sets attempt").
    pub follow_sets: bool,
    /// When the attempt gives up early.
    pub give_up: GiveUp,
    /// Updates allowed beyond `max_iter` while the iterates converge: each of them at
    /// the same index sets as the iterate before and with its residual at most
    /// [`Tuning::reuse_contraction`](crate::Tuning::reuse_contraction) times that iterate's (0: none).
    pub contracting_extra: usize,
    /// The attempt gives up at its start, without an update, where ‖R‖∞ there exceeds
    /// this (∞: never): a start that is not worth iterating from
    /// ([`Tuning::predicted_start_residual`](crate::Tuning::predicted_start_residual)).
    pub start_limit: f64,
    /// The measured limits: reuse contraction and count, cycle periods, stall length.
    pub tuning: Tuning,
}

/// A nonsmooth problem solved by semismooth Newton: R(x) = 0 with index sets decided at
/// each iterate.
pub trait NewtonProblem {
    /// The index sets of an iterate (what makes the residual piecewise smooth).
    type Sets: Clone + PartialEq;

    /// Evaluates the iterate `x`: decides its index sets (or takes fixed ones), computes
    /// R(x) and keeps it for the next update. Returns the sets and ‖R‖∞. `first` is true
    /// for the start of the attempt (where, for example, prox parameters are updated).
    fn evaluate(&mut self, x: &[f64], first: bool) -> (Self::Sets, f64);

    /// Whether the caller asked the attempt to stop (the stepper's
    /// [`Interrupt`](crate::Interrupt)), asked before every update. Default: never.
    fn interrupted(&self) -> bool {
        false
    }

    /// Whether the attempt must be restarted at these sets (the stepper: a contact it
    /// left out of the linear solve closes). Default: never.
    fn restart(&mut self, _sets: &Self::Sets) -> bool {
        false
    }

    /// The exact Newton update dx = −J⁻¹R at the last evaluated iterate, with J
    /// assembled and factorized for `sets`.
    ///
    /// # Errors
    /// The linear solver's message when J cannot be factorized.
    fn exact_direction(
        &mut self,
        x: &[f64],
        sets: &Self::Sets,
        dx: &mut [f64],
    ) -> Result<(), String>;

    /// A simplified Newton update at `x` from kept factors, when the problem has factors
    /// that fit `sets`, and which kind it was. Default: none kept.
    fn kept_direction(&mut self, _x: &[f64], _sets: &Self::Sets, _dx: &mut [f64]) -> KeptUpdate {
        KeptUpdate::Refused
    }

    /// Takes back sets that an evaluation returned and the engine no longer needs (equal
    /// to sets visited already, or those of a damped trial the line search passed over),
    /// so that the problem can reuse their buffers. Default: dropped.
    fn recycle(&mut self, sets: Self::Sets) {
        drop(sets);
    }

    /// An empty list for the sets an attempt visits, which its outcome reports
    /// ([`Outcome::Converged`], [`Outcome::NotConverged`]): the problem may hand out one
    /// whose buffer it got back from an earlier outcome. Default: a new one.
    fn visited_list(&mut self) -> Vec<Self::Sets> {
        Vec::new()
    }

    /// A copy of visited `sets` for the outcome to report besides its visited list (the
    /// solution's, the best iterate's), which the problem may write into the buffers of
    /// sets it recycled. Default: a clone.
    fn copy_sets(&mut self, sets: &Self::Sets) -> Self::Sets {
        sets.clone()
    }
}

/// What the kept factors gave for an update ([`NewtonProblem::kept_direction`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum KeptUpdate {
    /// Nothing: none are kept, or they do not fit the iterate's sets.
    Refused,
    /// A simplified update: the factors were made at the iterate's sets.
    SameSets,
    /// A low-rank update of the factors for sets that differ from theirs in a few rows.
    ChangedRows,
}

/// The best (smallest-residual) iterate of an attempt that did not converge.
#[derive(Debug, Clone, PartialEq)]
pub struct BestIterate<S> {
    /// The iterate.
    pub x: Vec<f64>,
    /// Its ‖R‖∞.
    pub residual: f64,
    /// At which iteration it was reached.
    pub iteration: usize,
    /// Its index sets.
    pub sets: S,
}

/// How a Newton attempt ended.
#[derive(Debug, Clone, PartialEq)]
pub enum Outcome<S> {
    /// ‖R‖∞ ≤ tol at the iterate left in `x`.
    Converged {
        /// The index sets of the solution.
        sets: S,
        /// Newton updates taken.
        iterations: usize,
        /// Final ‖R‖∞.
        residual: f64,
        /// Sets visited, in first-visit order.
        visited: Vec<S>,
    },
    /// The iteration limit, a settled cycle or a stall.
    NotConverged {
        /// Sets visited, in first-visit order.
        visited: Vec<S>,
        /// Whether more than one set was visited in the last half of the iterates.
        cycling: bool,
        /// The smallest-residual iterate.
        best: Option<BestIterate<S>>,
    },
    /// A residual became NaN or infinite.
    NonFinite,
    /// The Newton matrix could not be factorized.
    Singular(String),
    /// The problem asked for a restart ([`NewtonProblem::restart`]).
    Restart,
    /// The caller asked the attempt to stop ([`NewtonProblem::interrupted`]).
    Interrupted,
}

/// Reused buffers of the engine.
#[derive(Debug, Clone, Default)]
pub struct NewtonScratch {
    dx: Vec<f64>,
    x_from: Vec<f64>,
    /// Per iterate: the id of its sets in `visited`, and ‖R‖∞.
    history: Vec<usize>,
    residuals: Vec<f64>,
    /// The best iterate's x.
    best_x: Vec<f64>,
    /// Damped trials of the line search in the last [`solve`].
    line_search_trials: u64,
}

impl NewtonScratch {
    /// The iterates the last [`solve`] evaluated (the updates it made, plus one).
    #[must_use]
    pub fn evaluations(&self) -> usize {
        self.history.len()
    }
    /// The evaluations of the last [`solve`] that were damped trials of its line search
    /// (or the full update taken again after them): the evaluations beyond one per
    /// update.
    #[must_use]
    pub fn line_search_trials(&self) -> u64 {
        self.line_search_trials
    }
}

/// Solves `problem` by semismooth Newton from `x`, which holds the last iterate at the
/// end (the solution when [`Outcome::Converged`]).
///
/// Inlined into its caller: left to itself the compiler stopped doing so as the loop
/// grew, and the resting pile's one run per step then paid for the call and the copy
/// of its outcome (callgrind: 1.9 M instructions more over 6370 steps).
#[inline(always)]
pub fn solve<P: NewtonProblem>(
    problem: &mut P,
    x: &mut [f64],
    settings: &NewtonSettings,
    scratch: &mut NewtonScratch,
) -> Outcome<P::Sets> {
    scratch.dx.clear();
    scratch.dx.resize(x.len(), 0.0);
    let mut visited = problem.visited_list();
    scratch.history.clear();
    scratch.residuals.clear();
    scratch.line_search_trials = 0;
    // Best iterate so far: (residual, iteration, visited-set id); its x in the scratch.
    let mut best: Option<(f64, usize, usize)> = None;
    // The evaluation the line search left behind, to be used by the next iteration.
    let mut pending: Option<(P::Sets, f64)> = None;
    // Simplified Newton bookkeeping: what the kept factors gave for the last update, how
    // many updates in a row they gave, and the residual before the last update.
    let (mut kept, mut reuses, mut last_res) = (KeptUpdate::Refused, 0, f64::INFINITY);
    let mut may_reuse = settings.reuse_factorization;
    let t = &settings.tuning;
    for iter in 0..=settings.max_iter + settings.contracting_extra {
        let (sets, res) = match pending.take() {
            Some(e) => e,
            None => problem.evaluate(x, iter == 0),
        };
        let (id, new_sets) = match visited.iter().position(|v| v == &sets) {
            Some(i) => {
                problem.recycle(sets);
                (i, false)
            }
            None => {
                visited.push(sets);
                (visited.len() - 1, true)
            }
        };
        let sets = &visited[id];
        scratch.history.push(id);
        if !res.is_finite() {
            return Outcome::NonFinite;
        }
        if problem.restart(sets) {
            return Outcome::Restart;
        }
        if res <= settings.tol {
            return Outcome::Converged {
                sets: problem.copy_sets(sets),
                iterations: iter,
                residual: res,
                visited,
            };
        }
        if best.as_ref().is_none_or(|b| res < b.0) {
            best = Some((res, iter, id));
            scratch.best_x.clear();
            scratch.best_x.extend_from_slice(x);
        }
        scratch.residuals.push(res);
        let hopeless = (iter == 0 && res > settings.start_limit)
            || match settings.give_up {
                GiveUp::Never => false,
                GiveUp::SettledCycle => settled_cycle(&scratch.history, &scratch.residuals, t),
                GiveUp::Stall => stalled(&scratch.residuals, t),
            };
        let converging = iter > 0
            && res <= t.reuse_contraction * last_res
            && scratch.history[scratch.history.len() - 2] == id;
        let extended = converging && iter < settings.max_iter + settings.contracting_extra;
        if (iter >= settings.max_iter && !extended) || hopeless {
            break;
        }
        // Asked before the update, which is where an attempt spends its time.
        if problem.interrupted() {
            return Outcome::Interrupted;
        }
        // Simplified Newton while it contracts, or while the factors follow the sets: at
        // sets a low-rank update reached first, the residual does not compare with the
        // last one's, and the updates in a row at one sets' residual count afresh.
        let followed = settings.follow_sets && kept == KeptUpdate::ChangedRows && new_sets;
        if followed {
            reuses = 0;
        } else if kept != KeptUpdate::Refused && res > t.reuse_contraction * last_res {
            may_reuse = false;
        }
        kept = if may_reuse && reuses < t.max_reuses {
            problem.kept_direction(x, sets, &mut scratch.dx)
        } else {
            KeptUpdate::Refused
        };
        if kept != KeptUpdate::Refused {
            reuses += 1;
        } else if !settings.new_factors {
            break;
        } else {
            reuses = 0;
            if let Err(message) = problem.exact_direction(x, sets, &mut scratch.dx) {
                return Outcome::Singular(message);
            }
            // New factors, of this iterate: worth trying again.
            may_reuse |= settings.reuse_factorization && settings.resume_reuse;
        }
        last_res = res;
        pending = Some(line_search(problem, x, settings.line_search, res, scratch));
    }
    // Cycling: more than one distinct set among the last half of the iterates.
    let history = &scratch.history;
    let tail = &history[history.len().saturating_sub(1) / 2..];
    let cycling = settings.give_up != GiveUp::Stall && tail.iter().any(|&i| i != tail[0]);
    Outcome::NotConverged {
        best: best.map(|(residual, iteration, id)| BestIterate {
            x: scratch.best_x.clone(),
            residual,
            iteration,
            sets: problem.copy_sets(&visited[id]),
        }),
        visited,
        cycling,
    }
}

/// Takes the Newton update: x ← x + α dx with the first α = 1, ½, ¼, … (at most
/// `halvings` halvings) for which ‖R‖∞ falls to (1 − 10⁻⁴α) times `res0`, its value at
/// x; when none does, the full update, since a semismooth Newton step must stay free to
/// change the index sets. Returns the sets and ‖R‖∞ at the new x, whose evaluation the
/// problem keeps.
fn line_search<P: NewtonProblem>(
    problem: &mut P,
    x: &mut [f64],
    halvings: usize,
    res0: f64,
    scratch: &mut NewtonScratch,
) -> (P::Sets, f64) {
    scratch.x_from.clear();
    scratch.x_from.extend_from_slice(x);
    let mut alpha = 1.0;
    for trial in 0..=halvings {
        scratch.line_search_trials += u64::from(trial > 0);
        step_along(x, scratch, alpha);
        let (sets, res) = problem.evaluate(x, false);
        if halvings == 0 || res <= (1.0 - ARMIJO * alpha) * res0 {
            return (sets, res);
        }
        problem.recycle(sets);
        alpha *= 0.5;
    }
    step_along(x, scratch, 1.0);
    scratch.line_search_trials += 1;
    problem.evaluate(x, false)
}

/// x = x_from + α dx (for α = 1 exactly x_from + dx).
fn step_along(x: &mut [f64], scratch: &NewtonScratch, alpha: f64) {
    for ((xi, x0), d) in x.iter_mut().zip(&scratch.x_from).zip(&scratch.dx) {
        *xi = x0 + alpha * d;
    }
}

/// Whether the Newton iterates have settled into a cycle of index sets that makes no
/// progress: the last three periods (two, for periods of [`Tuning::long_cycle`](crate::Tuning::long_cycle) or more) visit
/// the same sets in the same order, and the smallest residual of the last period is no
/// smaller than [`Tuning::progress`](crate::Tuning::progress) times that of the period before. Newton's iterates are then a discrete
/// map caught in an attractor; running on to the iteration limit only repeats it.
#[must_use]
pub fn settled_cycle(history: &[usize], residuals: &[f64], tuning: &Tuning) -> bool {
    let n = history.len();
    (2..=tuning.longest_cycle).any(|p| {
        let periods = if p >= tuning.long_cycle { 2 } else { 3 };
        n >= periods * p
            && (0..(periods - 1) * p).all(|i| history[n - 1 - i] == history[n - 1 - i - p])
            && history[n - p..].iter().any(|&id| id != history[n - 1])
            && {
                let min = |r: &[f64]| r.iter().copied().fold(f64::INFINITY, f64::min);
                min(&residuals[n - p..]) >= tuning.progress * min(&residuals[n - 2 * p..n - p])
            }
    })
}

/// Whether a Newton solve with fixed index sets has stalled: none of its last
/// [`Tuning::stall_iterations`](crate::Tuning::stall_iterations) residuals is below [`Tuning::progress`](crate::Tuning::progress) times the smallest one
/// before them. With the
/// sets fixed the residual is smooth and Newton converges quadratically near a solution;
/// a residual that stops shrinking means these sets have no solution near the iterates.
#[must_use]
pub fn stalled(residuals: &[f64], tuning: &Tuning) -> bool {
    let n = residuals.len();
    let last_n = tuning.stall_iterations;
    n > last_n && {
        let (before, last) = residuals.split_at(n - last_n);
        let floor = before.iter().copied().fold(f64::INFINITY, f64::min);
        last.iter().all(|&r| r >= tuning.progress * floor)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Plain Newton to `tol` in at most `max_iter` updates, with `line_search` halvings:
    /// no kept factors, no early give-up, no updates past the limit.
    fn plain(tol: f64, max_iter: usize, line_search: usize) -> NewtonSettings {
        NewtonSettings {
            tol,
            max_iter,
            line_search,
            reuse_factorization: false,
            resume_reuse: false,
            new_factors: true,
            follow_sets: false,
            give_up: GiveUp::Never,
            contracting_extra: 0,
            start_limit: f64::INFINITY,
            tuning: Tuning::default(),
        }
    }

    #[test]
    fn a_period_three_cycle_without_progress_is_settled() {
        // Sets 0, 1, 2 repeating; residuals repeating too.
        let history = [5, 0, 1, 2, 0, 1, 2, 0, 1, 2];
        let residuals = [
            1e-3, 2e-2, 1e-2, 4.7e-4, 2e-2, 1e-2, 4.7e-4, 2e-2, 1e-2, 4.7e-4,
        ];
        assert!(settled_cycle(&history, &residuals, &Tuning::default()));
        // Two periods are not enough evidence.
        assert!(!settled_cycle(
            &history[3..],
            &residuals[3..],
            &Tuning::default()
        ));
    }

    #[test]
    fn a_landing_cycle_of_period_seven_is_settled() {
        // As in the Lire collapse's landings: two sets that jump the residual up, then
        // five damped updates within one set, again and again.
        let period = [0, 1, 2, 2, 2, 2, 2];
        let r = [2.0e-2, 1.0e-2, 4.7e-4, 2.3e-4, 1.2e-4, 8.8e-5, 6.6e-5];
        let history: Vec<usize> = period.iter().cycle().take(14).copied().collect();
        let residuals: Vec<f64> = r.iter().cycle().take(14).copied().collect();
        // A period of 7 is long (`Tuning::long_cycle`): two repetitions settle it.
        assert!(settled_cycle(&history, &residuals, &Tuning::default()));
        assert!(!settled_cycle(
            &history[..13],
            &residuals[..13],
            &Tuning::default()
        ));
    }

    #[test]
    fn short_periods_need_three_repetitions_and_long_ones_two() {
        let run = |p: usize, len: usize| {
            let history: Vec<usize> = (0..len).map(|i| i % p).collect();
            settled_cycle(&history, &vec![1e-3; len], &Tuning::default())
        };
        let long = Tuning::default().long_cycle;
        let short = long - 1;
        assert!(!run(short, 2 * short) && !run(short, 3 * short - 1));
        assert!(run(short, 3 * short));
        assert!(!run(long, 2 * long - 1));
        assert!(run(long, 2 * long));
    }

    #[test]
    fn a_cycle_that_still_makes_progress_goes_on() {
        let history = [0, 1, 0, 1, 0, 1];
        let residuals = [1e-2, 1e-2, 1e-3, 1e-3, 1e-4, 1e-4];
        assert!(!settled_cycle(&history, &residuals, &Tuning::default()));
    }

    #[test]
    fn one_set_is_not_a_cycle() {
        // Slow convergence within one set is left to max_iter.
        let history = [3; 12];
        let residuals = [1e-3; 12];
        assert!(!settled_cycle(&history, &residuals, &Tuning::default()));
    }

    #[test]
    fn a_broken_pattern_is_not_a_cycle() {
        let history = [0, 1, 2, 0, 1, 2, 0, 1, 3];
        let residuals = [1e-2; 9];
        assert!(!settled_cycle(&history, &residuals, &Tuning::default()));
    }

    #[test]
    fn fixed_set_solves_stall_only_without_progress() {
        assert!(!stalled(&[1.0, 0.1, 0.01, 1e-4], &Tuning::default()));
        assert!(!stalled(&[1.0, 0.9, 0.8], &Tuning::default()));
        assert!(stalled(&[1.0, 0.1, 0.09, 0.2, 0.06], &Tuning::default()));
        // Quadratic convergence after a slow start.
        assert!(!stalled(&[1.0, 0.1, 0.09, 0.2, 0.04], &Tuning::default()));
    }

    /// |x| − 1 = 0 written as a two-piece problem: the sign of x is its index set.
    struct Kink {
        res: f64,
    }

    impl NewtonProblem for Kink {
        type Sets = bool;
        fn evaluate(&mut self, x: &[f64], _first: bool) -> (bool, f64) {
            self.res = x[0].abs() - 1.0;
            (x[0] >= 0.0, self.res.abs())
        }
        fn exact_direction(&mut self, x: &[f64], _: &bool, dx: &mut [f64]) -> Result<(), String> {
            let slope = if x[0] >= 0.0 { 1.0 } else { -1.0 };
            dx[0] = -self.res / slope;
            Ok(())
        }
    }

    /// [`Kink`] handing out its own list for the visited sets and its own copies.
    struct KeptKink {
        kink: Kink,
        list: Vec<bool>,
        copies: usize,
    }

    impl NewtonProblem for KeptKink {
        type Sets = bool;
        fn evaluate(&mut self, x: &[f64], first: bool) -> (bool, f64) {
            self.kink.evaluate(x, first)
        }
        fn exact_direction(&mut self, x: &[f64], s: &bool, dx: &mut [f64]) -> Result<(), String> {
            self.kink.exact_direction(x, s, dx)
        }
        fn visited_list(&mut self) -> Vec<bool> {
            std::mem::take(&mut self.list)
        }
        fn copy_sets(&mut self, sets: &bool) -> bool {
            self.copies += 1;
            *sets
        }
    }

    #[test]
    fn the_outcome_reports_in_the_problems_list_and_copies() {
        let settings = plain(1e-12, 10, 0);
        let list = Vec::with_capacity(4);
        let buffer = list.as_ptr();
        let mut problem = KeptKink {
            kink: Kink { res: 0.0 },
            list,
            copies: 0,
        };
        let out = solve(
            &mut problem,
            &mut [-3.0],
            &settings,
            &mut NewtonScratch::default(),
        );
        let Outcome::Converged { sets, visited, .. } = out else {
            panic!("{out:?}");
        };
        assert!(!sets && visited == [false]);
        assert_eq!(visited.as_ptr(), buffer);
        assert_eq!(problem.copies, 1);
    }

    /// atan x = 0, whose full Newton update from |x| > 1.4 overshoots: each
    /// evaluation's sets are its own number, so that none equals a visited one, and the
    /// sets given back are counted.
    struct Atan {
        evaluations: usize,
        recycled: usize,
    }

    impl NewtonProblem for Atan {
        type Sets = usize;
        fn evaluate(&mut self, x: &[f64], _first: bool) -> (usize, f64) {
            self.evaluations += 1;
            (self.evaluations, x[0].atan().abs())
        }
        fn exact_direction(&mut self, x: &[f64], _: &usize, dx: &mut [f64]) -> Result<(), String> {
            dx[0] = -x[0].atan() * (1.0 + x[0] * x[0]);
            Ok(())
        }
        fn recycle(&mut self, _sets: usize) {
            self.recycled += 1;
        }
    }

    #[test]
    fn the_sets_of_damped_trials_passed_over_are_given_back() {
        let settings = plain(1e-12, 20, 4);
        let mut problem = Atan {
            evaluations: 0,
            recycled: 0,
        };
        let mut scratch = NewtonScratch::default();
        let out = solve(&mut problem, &mut [3.0], &settings, &mut scratch);
        let Outcome::Converged { visited, .. } = out else {
            panic!("{out:?}");
        };
        // Every evaluation's sets are visited or given back.
        assert!(problem.recycled > 0 && scratch.line_search_trials() > 0);
        assert_eq!(visited.len() + problem.recycled, problem.evaluations);
    }

    #[test]
    fn the_engine_solves_a_piecewise_linear_problem_in_one_update() {
        let settings = plain(1e-12, 10, 0);
        let mut x = [3.0];
        let out = solve(
            &mut Kink { res: 0.0 },
            &mut x,
            &settings,
            &mut NewtonScratch::default(),
        );
        assert!(
            matches!(out, Outcome::Converged { iterations: 1, .. }),
            "{out:?}"
        );
        assert_eq!(x[0], 1.0);
    }

    /// x = 0 solved by updates that take away the fraction `1 − rate` of x (a Newton
    /// matrix off by a constant factor: simplified Newton's linear convergence): exact
    /// ones, or with `kept` simplified ones on kept factors that always serve, and no
    /// exact one.
    struct Linear {
        rate: f64,
        kept: bool,
    }

    impl NewtonProblem for Linear {
        type Sets = ();
        fn evaluate(&mut self, x: &[f64], _first: bool) -> ((), f64) {
            ((), x[0].abs())
        }
        fn exact_direction(&mut self, x: &[f64], _: &(), dx: &mut [f64]) -> Result<(), String> {
            assert!(!self.kept, "an attempt without new factors factored");
            dx[0] = -(1.0 - self.rate) * x[0];
            Ok(())
        }
        fn kept_direction(&mut self, x: &[f64], _: &(), dx: &mut [f64]) -> KeptUpdate {
            dx[0] = -(1.0 - self.rate) * x[0];
            if self.kept {
                KeptUpdate::SameSets
            } else {
                KeptUpdate::Refused
            }
        }
    }

    fn linear_updates(rate: f64, max_iter: usize, contracting_extra: usize) -> Outcome<()> {
        let settings = NewtonSettings {
            contracting_extra,
            ..plain(1e-10, max_iter, 0)
        };
        let mut scratch = NewtonScratch::default();
        let linear = &mut Linear { rate, kept: false };
        solve(linear, &mut [1.0], &settings, &mut scratch)
    }

    /// An attempt whose start is farther off than its `start_limit` gives up there,
    /// after one evaluation and no update; one that starts within it iterates as ever
    /// (the predicted attempt's rule, `Tuning::predicted_start_residual`).
    #[test]
    fn an_attempt_gives_up_at_a_start_beyond_its_limit() {
        let limited = |start_limit| NewtonSettings {
            start_limit,
            ..plain(1e-10, 10, 0)
        };
        let mut scratch = NewtonScratch::default();
        let linear = &mut Linear {
            rate: 0.01,
            kept: false,
        };
        let out = solve(linear, &mut [1e-3], &limited(1e-6), &mut scratch);
        assert!(matches!(out, Outcome::NotConverged { .. }), "{out:?}");
        assert_eq!(scratch.evaluations(), 1);
        let out = solve(linear, &mut [1e-7], &limited(1e-6), &mut scratch);
        assert!(
            matches!(out, Outcome::Converged { iterations: 2, .. }),
            "{out:?}"
        );
    }

    /// An attempt that may not factor takes simplified updates on the kept factors and
    /// stops, not converged, where they no longer serve: at its start when there are
    /// none, after `max_reuses` of them in a row otherwise.
    #[test]
    fn an_attempt_without_new_factors_stops_where_the_kept_ones_do_not_serve() {
        let settings = NewtonSettings {
            new_factors: false,
            reuse_factorization: true,
            ..plain(1e-10, 10, 0)
        };
        let mut scratch = NewtonScratch::default();
        let out = solve(
            &mut Linear {
                rate: 0.01,
                kept: false,
            },
            &mut [1.0],
            &settings,
            &mut scratch,
        );
        assert!(matches!(out, Outcome::NotConverged { .. }), "{out:?}");
        assert_eq!(scratch.evaluations(), 1);
        let out = solve(
            &mut Linear {
                rate: 0.01,
                kept: true,
            },
            &mut [1.0],
            &settings,
            &mut scratch,
        );
        assert!(matches!(out, Outcome::NotConverged { .. }), "{out:?}");
        assert_eq!(scratch.evaluations(), settings.tuning.max_reuses + 1);
        // With more contraction per update the kept factors suffice.
        let out = solve(
            &mut Linear {
                rate: 1e-3,
                kept: true,
            },
            &mut [1.0],
            &settings,
            &mut scratch,
        );
        assert!(matches!(out, Outcome::Converged { .. }), "{out:?}");
    }

    /// Iterates whose index sets and residuals follow a script, whatever the updates.
    /// The kept factors are those of the last exact update: they give simplified
    /// updates at its sets and low-rank updates at others. The exact updates are counted.
    struct Scripted {
        script: Vec<(u8, f64)>,
        at: usize,
        factored_at: Option<u8>,
        exact: usize,
    }

    impl NewtonProblem for Scripted {
        type Sets = u8;
        fn evaluate(&mut self, _x: &[f64], _first: bool) -> (u8, f64) {
            self.at += 1;
            self.script[self.at - 1]
        }
        fn exact_direction(&mut self, _: &[f64], sets: &u8, _: &mut [f64]) -> Result<(), String> {
            self.exact += 1;
            self.factored_at = Some(*sets);
            Ok(())
        }
        fn kept_direction(&mut self, _: &[f64], sets: &u8, _: &mut [f64]) -> KeptUpdate {
            match self.factored_at {
                None => KeptUpdate::Refused,
                Some(at) if at == *sets => KeptUpdate::SameSets,
                Some(_) => KeptUpdate::ChangedRows,
            }
        }
    }

    /// The exact updates a held-sets attempt's settings take over `script` (the residual
    /// must only fall), with kept factors that follow the sets or not.
    fn exact_updates(script: &[(u8, f64)], follow_sets: bool) -> usize {
        let settings = NewtonSettings {
            reuse_factorization: true,
            resume_reuse: true,
            follow_sets,
            tuning: Tuning {
                reuse_contraction: 1.0,
                ..Tuning::default()
            },
            ..plain(1e-10, 10, 0)
        };
        let mut problem = Scripted {
            script: script.to_vec(),
            at: 0,
            factored_at: None,
            exact: 0,
        };
        let out = solve(
            &mut problem,
            &mut [0.0],
            &settings,
            &mut NewtonScratch::default(),
        );
        assert!(matches!(out, Outcome::Converged { .. }), "{out:?}");
        problem.exact
    }

    /// Kept factors that follow the sets serve on where a low-rank update reaches sets
    /// not visited before, its residual higher or not (a corner climbing a column), and
    /// count the updates in a row afresh from there; a rise after a simplified update at
    /// the factors' own sets, or at visited sets, retires them as ever (the 10 000-block
    /// column diverged without the first), and `max_reuses` in a row at one sets do too.
    #[test]
    fn kept_factors_that_follow_the_sets_serve_on_only_at_new_sets_after_low_rank_updates() {
        let max_reuses = Tuning::default().max_reuses;
        let mut climbing: Vec<(u8, f64)> = (0..=max_reuses + 2)
            .map(|i| (i as u8, 1.0 - 0.5 / (i + 1) as f64))
            .collect();
        climbing.push((255, 0.0));
        assert_eq!(exact_updates(&climbing, true), 1);
        assert!(exact_updates(&climbing, false) > 1);
        let slow: Vec<(u8, f64)> = (0..=max_reuses + 1)
            .map(|i| (0, 1.0 - 0.1 * i as f64))
            .chain([(0, 0.0)])
            .collect();
        assert_eq!(exact_updates(&slow, true), 2);
        let same_sets = [(0, 1.0), (0, 0.5), (0, 0.7), (0, 0.0)];
        assert_eq!(exact_updates(&same_sets, true), 2);
        let back_to_visited = [(0, 1.0), (1, 0.5), (0, 0.7), (0, 0.0)];
        assert_eq!(exact_updates(&back_to_visited, true), 2);
    }

    #[test]
    fn an_attempt_goes_past_its_limit_only_while_it_contracts() {
        // Rate 0.01: 1e-10 after 5 updates, 2 allowed and 3 more while contracting.
        assert!(matches!(
            linear_updates(0.01, 2, 3),
            Outcome::Converged { iterations: 5, .. }
        ));
        assert!(matches!(
            linear_updates(0.01, 2, 2),
            Outcome::NotConverged { .. }
        ));
        assert!(matches!(
            linear_updates(0.01, 2, 0),
            Outcome::NotConverged { .. }
        ));
        // Rate 0.5 contracts too slowly to be extended.
        let Outcome::NotConverged { best, .. } = linear_updates(0.5, 2, 100) else {
            panic!("a slow contraction was extended");
        };
        assert_eq!(best.map(|b| b.iteration), Some(2));
    }
}
