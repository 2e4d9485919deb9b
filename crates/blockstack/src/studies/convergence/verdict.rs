//! The verdicts on a failure time and on an outcome, from the runs at Δt/2^k and the
//! perturbation ensemble (the rules are in the parent module's docs; the thresholds are
//! the constants here).

use super::separation::corner_distance;
use crate::exploration::Outcome;
use crate::simulation::BlockPose;
use std::fmt;

/// Two failure times agree when they differ by at most this many steps of the coarser
/// of the two runs: a loss of support is seen at the end of a step, so each run knows
/// its failure time to a step, and the same motion at two step sizes may cross the
/// threshold a step apart on either side.
pub const FAILURE_TIME_STEPS: f64 = 2.0;

/// Two sets of final poses agree when no corner differs by more than this fraction of
/// the smallest block dimension ([`super::separation::corner_distance`]): 1 % of a
/// block is below what a drawing of the stack shows and far below any change of which
/// faces touch. The same distance marks two motions as separated.
pub const POSE_TOLERANCE: f64 = 1e-2;

/// The observed orders p = log₂(d₁/d₂) for which the Richardson rule trusts an
/// extrapolation. The scheme is of order 1 through impacts and 2 between them, so an
/// observed order in the asymptotic range lies near 1 or 2; below 0.5 the differences
/// barely shrink (d₁/d₂ < √2) and the extrapolated correction, at least 1/(2^p − 1) ≈ 2.4
/// times the last difference, is larger than the difference it rests on; above 3 the
/// last difference is more than eight times smaller than the one before, a near
/// coincidence rather than a rate.
pub const RICHARDSON_ORDERS: [f64; 2] = [0.5, 3.0];

/// The safety factor on the Richardson error estimate |t_K − t*|: Roache's 1.25 for a
/// grid convergence index computed from three grids with the observed order (Roache,
/// *Verification and Validation in Computational Science and Engineering*, 1998, §5.9),
/// which covers an order estimated from two differences rather than known.
pub const RICHARDSON_SAFETY: f64 = 1.25;

/// The ensemble makes levels that disagree *chaotic* when its spread at the finest Δt is
/// at least this fraction of the finest two levels' difference: the difference that
/// halving Δt makes is then no larger (within a factor of two) than what perturbations
/// of 1e-10 to 1e-4 make, so it measures sensitivity, not discretization error.
pub const CHAOS_FRACTION: f64 = 0.5;

/// The largest perturbation whose members count in the ensemble's spread: 10⁻⁷, a
/// thousandth of the error a step of these scenes makes (a local error O(Δt²) ≥ 10⁻⁶
/// at their Δt of 10⁻³ to 10⁻²). A member that changes the answer at such a size shows
/// sensitive dependence; the members at 10⁻⁴ show how smoothly the answer depends on the
/// initial state, and are reported but not judged.
pub const SENSITIVE_MAGNITUDE: f64 = 1e-7;

/// A member of the ensemble: its perturbation's size, and what it shows.
#[derive(Debug, Clone, PartialEq)]
pub struct Member {
    /// The perturbation's relative size δ.
    pub magnitude: f64,
    /// What it shows.
    pub observed: Observed,
}

/// What one run shows of the two quantities judged.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Observed {
    /// The first loss of support (§4.4), if any.
    pub failure_time: Option<f64>,
    /// Which blocks fell, in which order, which reached the floor.
    pub outcome: Outcome,
    /// Where the blocks are at the end, bottom to top.
    pub final_poses: Vec<BlockPose>,
    /// The steps (their start times) with two or more distinct self-consistent solutions.
    pub forks: Vec<f64>,
    /// Whether the run reached its end time (no error, not stopped).
    pub complete: bool,
}

impl Observed {
    /// Whether the run decided its failure time: it failed, or reached its end standing.
    #[must_use]
    pub fn failure_decided(&self) -> bool {
        self.complete || self.failure_time.is_some()
    }

    /// The forks met before the failure time was decided (all of them if it never failed).
    fn forks_before_failure(&self) -> impl Iterator<Item = f64> + '_ {
        let until = self.failure_time.unwrap_or(f64::INFINITY);
        self.forks.iter().copied().filter(move |&t| t <= until)
    }
}

/// A run at one step size.
#[derive(Debug, Clone, PartialEq)]
pub struct Level {
    /// Its Δt.
    pub dt: f64,
    /// What it shows.
    pub observed: Observed,
}

/// The four verdicts, in the order the rules are tried after `non-unique`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum VerdictKind {
    /// A run forked: distinct self-consistent solutions at a step.
    NonUnique,
    /// The finest two levels agree within the threshold.
    Converged,
    /// The levels disagree, and the ensemble spreads as far.
    Chaotic,
    /// None of the above.
    NotConverged,
}

impl VerdictKind {
    /// Its name in the JSON and the CSV: `non_unique`, `converged`, `chaotic`,
    /// `not_converged`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::NonUnique => "non_unique",
            Self::Converged => "converged",
            Self::Chaotic => "chaotic",
            Self::NotConverged => "not_converged",
        }
    }
}

impl fmt::Display for VerdictKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Self::NonUnique => "non-unique",
            Self::Converged => "converged",
            Self::Chaotic => "chaotic",
            Self::NotConverged => "not converged",
        })
    }
}

/// The rule that gave a verdict.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Rule {
    /// A run forked before the quantity was decided (`non-unique`).
    Forks,
    /// The finest two levels agree within the threshold (`converged`).
    Agreement,
    /// Three levels follow one motion and their differences shrink at an order in
    /// [`RICHARDSON_ORDERS`] (`converged`, to the Richardson estimate).
    Richardson,
    /// The ensemble spreads as far as the levels differ (`chaotic`).
    Ensemble,
    /// None applies (`not converged`).
    Disagreement,
    /// A run of the finest two levels stopped before deciding (`not converged`).
    Stopped,
}

/// The verdict on one quantity, with its numbers.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Verdict {
    /// Which.
    pub verdict: VerdictKind,
    /// The finest two levels' difference (failure time: |T_{K−1} − T_K|; outcome: the
    /// corner distance of their final poses); null when they cannot be compared (one
    /// failed, the other not; a run stopped before deciding).
    pub level_difference: Option<f64>,
    /// Whether the finest two levels agree on the discrete answer (fail or stand; which
    /// blocks fell in which order and reached the floor).
    pub levels_agree: bool,
    /// The largest difference that counts as agreement.
    pub threshold: f64,
    /// For `converged`: how far the finest level's value may lie from the limit Δt → 0.
    /// By agreement: the larger of the level difference and (failure time) the finest
    /// Δt. By Richardson: [`RICHARDSON_SAFETY`] × |t_K − t*|, at least the finest Δt.
    pub tolerance: Option<f64>,
    /// For a failure time `converged` by Richardson: the extrapolated limit
    /// t* = t_K + (t_K − t_{K−1})/(2^p − 1).
    pub extrapolated: Option<f64>,
    /// The observed order log₂(d_{K−2,K−1} / d_{K−1,K}) when the three finest levels
    /// agree (each pair as the finest two must, for `converged`) and both differences
    /// are positive, or the order the Richardson rule used.
    pub order: Option<f64>,
    /// The rule that gave the verdict.
    pub rule: Rule,
    /// The spread of the unperturbed finest run and the ensemble: failure time max − min,
    /// or the largest corner distance of a member's final poses from the unperturbed
    /// run's (null without members, or when they differ in the discrete answer).
    pub ensemble_spread: Option<f64>,
    /// Distinct discrete answers among the unperturbed finest run and the ensemble.
    pub ensemble_answers: usize,
    /// Members that decided the quantity (the others stopped early).
    pub ensemble_members: usize,
    /// The forks that make it `non-unique`: their times, over every run.
    pub fork_times: Vec<f64>,
    /// The rule that gave the verdict, in words.
    pub why: String,
}

/// The failure-time verdict (the parent module's rules).
#[must_use]
pub fn judge_failure(levels: &[Level], members: &[Member]) -> Verdict {
    let forks = fork_times(levels, members, |o| o.forks_before_failure().collect());
    let members = sensitive(members);
    let (coarse, fine) = finest_two(levels);
    let threshold = FAILURE_TIME_STEPS * coarse.dt;
    let (a, b) = (&coarse.observed, &fine.observed);
    let decided: Vec<&Observed> = members
        .into_iter()
        .filter(|m| m.failure_decided())
        .collect();
    let times = std::iter::once(b)
        .chain(decided.iter().copied())
        .map(|o| o.failure_time);
    let (answers, spread) = failure_spread(times);
    let mut v = Verdict {
        verdict: VerdictKind::NotConverged,
        level_difference: time_difference(a.failure_time, b.failure_time),
        levels_agree: a.failure_time.is_some() == b.failure_time.is_some(),
        threshold,
        tolerance: None,
        extrapolated: None,
        order: failure_order(levels),
        rule: Rule::Disagreement,
        ensemble_spread: spread,
        ensemble_answers: answers,
        ensemble_members: decided.len(),
        fork_times: forks,
        why: String::new(),
    };
    if !(a.failure_decided() && b.failure_decided()) {
        v.levels_agree = false;
        v.level_difference = None;
        return v
            .because("a run of the finest two levels stopped before failing or reaching its end");
    }
    let rule = format!(
        "the finest two levels fail within {FAILURE_TIME_STEPS} of the coarser one's steps \
         (or both stand)"
    );
    // A column that stands at both levels has no failure time to know to a tolerance.
    let resolution = b.failure_time.map(|_| fine.dt);
    decide(v, resolution, &rule, richardson(levels))
}

/// The outcome verdict (the parent module's rules); `radii`: the blocks' half
/// diagonals, `smallest`: the smallest block dimension.
#[must_use]
pub fn judge_outcome(
    levels: &[Level],
    members: &[Member],
    radii: &[f64],
    smallest: f64,
) -> Verdict {
    let forks = fork_times(levels, members, |o| o.forks.clone());
    let members = sensitive(members);
    let (coarse, fine) = finest_two(levels);
    let (a, b) = (&coarse.observed, &fine.observed);
    let distance =
        |x: &Observed, y: &Observed| corner_distance(&x.final_poses, &y.final_poses, radii);
    let done: Vec<&Observed> = members.into_iter().filter(|m| m.complete).collect();
    let mut outcomes: Vec<&Outcome> = vec![&b.outcome];
    for m in &done {
        if !outcomes.contains(&&m.outcome) {
            outcomes.push(&m.outcome);
        }
    }
    let spread = (outcomes.len() == 1 && !done.is_empty())
        .then(|| done.iter().map(|m| distance(m, b)).fold(0.0, f64::max));
    let threshold = POSE_TOLERANCE * smallest;
    // As for the failure time: an order only through levels that agree.
    let order = three_finest(levels).and_then(|[x, y, z]| {
        let (d1, d2) = (distance(x, y), distance(y, z));
        let same = x.outcome == y.outcome && y.outcome == z.outcome;
        (same && d1 <= threshold && d2 <= threshold)
            .then(|| order_of(d1, d2))
            .flatten()
    });
    let v = Verdict {
        verdict: VerdictKind::NotConverged,
        level_difference: Some(distance(a, b)).filter(|d| d.is_finite()),
        levels_agree: a.outcome == b.outcome,
        threshold,
        tolerance: None,
        extrapolated: None,
        order,
        rule: Rule::Disagreement,
        ensemble_spread: spread,
        ensemble_answers: outcomes.len(),
        ensemble_members: done.len(),
        fork_times: forks,
        why: String::new(),
    };
    if !(a.complete && b.complete) {
        let mut v = v;
        v.levels_agree = false;
        v.level_difference = None;
        return v.because("a run of the finest two levels stopped before its end");
    }
    let rule = format!(
        "the finest two levels end with the same blocks fallen in the same order, their \
         final corners within {POSE_TOLERANCE} of the smallest block dimension"
    );
    decide(v, Some(0.0), &rule, None)
}

/// The rules after the level comparison is filled in: non-unique, converged by agreement
/// (`resolution`: the least tolerance that can be claimed) or by `richardson` (the
/// failure time's extrapolation, when its conditions hold), chaotic, not converged.
fn decide(
    v: Verdict,
    resolution: Option<f64>,
    converged_rule: &str,
    richardson: Option<Richardson>,
) -> Verdict {
    if !v.fork_times.is_empty() {
        let n = v.fork_times.len();
        return v.with(
            VerdictKind::NonUnique,
            Rule::Forks,
            &format!("{n} step(s) with distinct self-consistent solutions before it was decided"),
        );
    }
    let difference = v.level_difference;
    if let Some(d) = difference.filter(|&d| v.levels_agree && d <= v.threshold) {
        let mut v = v.with(VerdictKind::Converged, Rule::Agreement, converged_rule);
        v.tolerance = resolution.map(|r| d.max(r));
        return v;
    }
    if let (Some(r), Some(resolution)) = (richardson, resolution) {
        let [lo, hi] = RICHARDSON_ORDERS;
        let mut v = v.with(
            VerdictKind::Converged,
            Rule::Richardson,
            &format!(
                "the three finest levels lose the same block first and their failure times \
                 move one way at an observed order {:.2} in [{lo}, {hi}]: Richardson's \
                 extrapolation, its error estimate times {RICHARDSON_SAFETY}",
                r.order
            ),
        );
        v.order = Some(r.order);
        v.extrapolated = Some(r.extrapolated);
        v.tolerance = Some((RICHARDSON_SAFETY * r.error).max(resolution));
        return v;
    }
    // Levels with no numeric difference (one failed, one stood): only an ensemble that
    // disagrees on the discrete answer too.
    let sensitive = v.ensemble_answers > 1
        || matches!((difference, v.ensemble_spread), (Some(d), Some(s)) if s >= CHAOS_FRACTION * d);
    if sensitive {
        return v.with(
            VerdictKind::Chaotic,
            Rule::Ensemble,
            "the levels disagree, and perturbations of 1e-10 to 1e-7 spread the finest \
             level's answer at least half as far",
        );
    }
    v.with(
        VerdictKind::NotConverged,
        Rule::Disagreement,
        "the levels disagree by more than the threshold and the ensemble does not",
    )
}

impl Verdict {
    fn with(mut self, verdict: VerdictKind, rule: Rule, why: &str) -> Self {
        self.verdict = verdict;
        self.rule = rule;
        self.why = why.to_owned();
        self
    }

    fn because(self, why: &str) -> Self {
        self.with(VerdictKind::NotConverged, Rule::Stopped, why)
    }
}

/// A failure time's Richardson extrapolation over the three finest levels.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Richardson {
    /// The observed order p = log₂(d₁/d₂).
    order: f64,
    /// t* = t_K + (t_K − t_{K−1})/(2^p − 1).
    extrapolated: f64,
    /// |t_K − t*|, the estimated error of t_K.
    error: f64,
}

/// The Richardson extrapolation of the failure times t_{K−2}, t_{K−1}, t_K, when the
/// three finest levels follow one motion (each fails, the same block falls first, no
/// run stopped) and their differences d₁ = t_{K−1} − t_{K−2}, d₂ = t_K − t_{K−1} have the
/// same sign with an observed order p = log₂(d₁/d₂) in [`RICHARDSON_ORDERS`]. A failure
/// time is seen at the end of a step, so each carries an error of up to its own Δt; the
/// rule is tried only after the agreement rule has failed, when |d₂| exceeds two steps
/// of the coarser level and the differences are larger than that noise.
fn richardson(levels: &[Level]) -> Option<Richardson> {
    let runs = three_finest(levels)?;
    let first = runs[2].outcome.fell.first()?;
    let same_motion = runs
        .iter()
        .all(|o| o.complete && o.failure_time.is_some() && o.outcome.fell.first() == Some(first));
    if !same_motion {
        return None;
    }
    let [x, y, z] = runs.map(|o| o.failure_time.unwrap_or(f64::NAN));
    let (d1, d2) = (y - x, z - y);
    if d1 * d2 <= 0.0 {
        return None;
    }
    let order = order_of(d1.abs(), d2.abs())?;
    let [lo, hi] = RICHARDSON_ORDERS;
    if !(lo..=hi).contains(&order) {
        return None;
    }
    let extrapolated = z + d2 / (order.exp2() - 1.0);
    Some(Richardson {
        order,
        extrapolated,
        error: (z - extrapolated).abs(),
    })
}

/// The coarser and the finer of the finest two levels (levels are coarsest first).
fn finest_two(levels: &[Level]) -> (&Level, &Level) {
    assert!(levels.len() >= 2, "at least two levels are compared");
    (&levels[levels.len() - 2], &levels[levels.len() - 1])
}

/// The three finest levels' observations, coarsest first.
fn three_finest(levels: &[Level]) -> Option<[&Observed; 3]> {
    let n = levels.len();
    (n >= 3).then(|| {
        [
            &levels[n - 3].observed,
            &levels[n - 2].observed,
            &levels[n - 1].observed,
        ]
    })
}

/// The members whose spread is judged: those perturbed by at most
/// [`SENSITIVE_MAGNITUDE`].
fn sensitive(members: &[Member]) -> Vec<&Observed> {
    members
        .iter()
        .filter(|m| m.magnitude <= SENSITIVE_MAGNITUDE)
        .map(|m| &m.observed)
        .collect()
}

/// The fork times of every run (every member too), sorted, as `of` lists them per run.
fn fork_times(
    levels: &[Level],
    members: &[Member],
    of: impl Fn(&Observed) -> Vec<f64>,
) -> Vec<f64> {
    let mut t: Vec<f64> = levels
        .iter()
        .map(|l| &l.observed)
        .chain(members.iter().map(|m| &m.observed))
        .flat_map(of)
        .collect();
    t.sort_by(f64::total_cmp);
    t
}

/// |a − b| when both failed, 0 when both stand, None when one did.
fn time_difference(a: Option<f64>, b: Option<f64>) -> Option<f64> {
    match (a, b) {
        (Some(a), Some(b)) => Some((a - b).abs()),
        (None, None) => Some(0.0),
        _ => None,
    }
}

/// The distinct answers (fails, stands) of these failure times and, when they agree,
/// their spread max − min (0 when all stand).
fn failure_spread(times: impl Iterator<Item = Option<f64>>) -> (usize, Option<f64>) {
    let times: Vec<Option<f64>> = times.collect();
    let failed: Vec<f64> = times.iter().filter_map(|t| *t).collect();
    let answers = usize::from(!failed.is_empty()) + usize::from(failed.len() < times.len());
    let spread = match answers {
        1 if failed.is_empty() => Some(0.0),
        1 => {
            let lo = failed.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = failed.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            Some(hi - lo)
        }
        _ => None,
    };
    (answers, spread)
}

/// The failure time's observed order over the three finest levels, when each of the
/// two pairs agrees (within [`FAILURE_TIME_STEPS`] of its coarser step): an order
/// through levels that follow different motions would fit a slope to a jump.
fn failure_order(levels: &[Level]) -> Option<f64> {
    let n = levels.len();
    let [x, y, z] = three_finest(levels)?;
    let (x, y, z) = (x.failure_time?, y.failure_time?, z.failure_time?);
    let (d1, d2) = ((x - y).abs(), (y - z).abs());
    let agree =
        d1 <= FAILURE_TIME_STEPS * levels[n - 3].dt && d2 <= FAILURE_TIME_STEPS * levels[n - 2].dt;
    agree.then(|| order_of(d1, d2)).flatten()
}

/// log₂(d₁/d₂) for two positive successive differences at halved steps.
fn order_of(d1: f64, d2: f64) -> Option<f64> {
    (d1 > 0.0 && d2 > 0.0 && d1.is_finite() && d2.is_finite()).then(|| (d1 / d2).log2())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(failure: Option<f64>, fell: &[usize], x: f64) -> Observed {
        Observed {
            failure_time: failure,
            outcome: Outcome {
                fell: fell.to_vec(),
                on_floor: Vec::new(),
            },
            final_poses: vec![BlockPose {
                x,
                y: 0.0,
                theta: 0.0,
            }],
            forks: Vec::new(),
            complete: true,
        }
    }

    /// Members perturbed by 1e-10.
    fn tiny(runs: &[Observed]) -> Vec<Member> {
        runs.iter()
            .map(|observed| Member {
                magnitude: 1e-10,
                observed: observed.clone(),
            })
            .collect()
    }

    fn levels(runs: Vec<Observed>) -> Vec<Level> {
        let mut dt = 0.01;
        runs.into_iter()
            .map(|observed| {
                let l = Level { dt, observed };
                dt /= 2.0;
                l
            })
            .collect()
    }

    const R: [f64; 1] = [0.5];

    #[test]
    fn agreeing_levels_converge_with_their_order() {
        // Differences 0.004 then 0.001: order 2; within 2 steps of 0.005.
        let l = levels(vec![
            run(Some(6.605), &[1], 1.0),
            run(Some(6.601), &[1], 1.0004),
            run(Some(6.600), &[1], 1.0005),
        ]);
        let v = judge_failure(&l, &tiny(&[run(Some(6.6001), &[1], 1.0)]));
        assert_eq!(v.verdict, VerdictKind::Converged, "{v:?}");
        assert!((v.order.unwrap() - 2.0).abs() < 1e-9);
        assert!(
            (v.tolerance.unwrap() - 0.0025).abs() < 1e-15,
            "the finest Δt"
        );
        let o = judge_outcome(&l, &[], &R, 0.2);
        assert_eq!(o.verdict, VerdictKind::Converged, "{o:?}");
        assert!((o.tolerance.unwrap() - 1e-4).abs() < 1e-12);
        assert!((o.order.unwrap() - 2.0).abs() < 1e-6, "{o:?}");
        // A coarsest level that follows another motion gives no order.
        let mut far = l.clone();
        far[0].observed.failure_time = Some(6.7);
        assert_eq!(judge_failure(&far, &[]).order, None);
        // Both standing: converged, with no failure time to know to a tolerance.
        let l = levels(vec![run(None, &[], 0.0), run(None, &[], 0.0)]);
        let v = judge_failure(&l, &[]);
        assert_eq!((v.verdict, v.tolerance), (VerdictKind::Converged, None));
    }

    #[test]
    fn disagreeing_levels_are_chaotic_only_if_the_ensemble_spreads_as_far() {
        let l = levels(vec![
            run(Some(1.0), &[2, 1], 3.0),
            run(Some(1.3), &[1, 2], -3.0),
        ]);
        // The ensemble spreads 0.2 ≥ 0.5 × 0.3: chaotic.
        let wide = [run(Some(1.2), &[1, 2], -3.0), run(Some(1.4), &[1, 2], -2.9)];
        let v = judge_failure(&l, &tiny(&wide));
        assert_eq!(v.verdict, VerdictKind::Chaotic, "{v:?}");
        assert!((v.ensemble_spread.unwrap() - 0.2).abs() < 1e-12);
        // The same spread at δ = 1e-4 is a smooth dependence, not judged.
        let smooth: Vec<Member> = tiny(&wide)
            .into_iter()
            .map(|m| Member {
                magnitude: 1e-4,
                ..m
            })
            .collect();
        let v = judge_failure(&l, &smooth);
        assert_eq!(
            (v.verdict, v.ensemble_members),
            (VerdictKind::NotConverged, 0)
        );
        // 0.01 < 0.15: not converged.
        let narrow = [run(Some(1.31), &[1, 2], -3.0)];
        assert_eq!(
            judge_failure(&l, &tiny(&narrow)).verdict,
            VerdictKind::NotConverged
        );
        // Outcome: the levels differ in order; a member with another order is chaotic,
        // members all alike are not.
        let o = judge_outcome(&l, &tiny(&[run(Some(1.2), &[2, 1], 3.0)]), &R, 0.2);
        assert_eq!((o.verdict, o.ensemble_answers), (VerdictKind::Chaotic, 2));
        let o = judge_outcome(&l, &tiny(&narrow), &R, 0.2);
        assert_eq!(o.verdict, VerdictKind::NotConverged, "{o:?}");
        // Members with the finest level's outcome but final poses 3 apart, half the
        // levels' 6: chaotic.
        let o = judge_outcome(&l, &tiny(&[run(Some(1.3), &[1, 2], 0.0)]), &R, 0.2);
        assert_eq!(
            (o.verdict, o.ensemble_answers),
            (VerdictKind::Chaotic, 1),
            "{o:?}"
        );
        // One level fails, the other stands: chaotic only if members do both.
        let l = levels(vec![run(Some(1.0), &[1], 0.0), run(None, &[], 0.0)]);
        assert_eq!(
            judge_failure(&l, &tiny(&narrow)).verdict,
            VerdictKind::Chaotic
        );
        assert_eq!(
            judge_failure(&l, &tiny(&[run(None, &[], 0.0)])).verdict,
            VerdictKind::NotConverged
        );
    }

    #[test]
    fn a_fork_before_the_answer_makes_it_non_unique() {
        let mut forked = run(Some(2.0), &[1], 0.0);
        forked.forks = vec![2.5];
        let l = levels(vec![run(Some(2.0), &[1], 0.0), forked.clone()]);
        // After the failure: the failure time is still converged, the outcome is not unique.
        assert_eq!(judge_failure(&l, &[]).verdict, VerdictKind::Converged);
        let o = judge_outcome(&l, &[], &R, 0.2);
        assert_eq!(
            (o.verdict, o.fork_times.clone()),
            (VerdictKind::NonUnique, vec![2.5])
        );
        forked.forks = vec![1.5];
        let v = judge_failure(&l, &tiny(&[forked]));
        assert_eq!(v.verdict, VerdictKind::NonUnique);
    }

    /// Failure times at Δt = 0.01, 0.005, 0.0025, 0.00125, block `first[k]` falling first.
    fn failing(times: [f64; 4], first: [usize; 4]) -> Vec<Level> {
        levels(
            times
                .iter()
                .zip(first)
                .map(|(&t, b)| run(Some(t), &[b], 0.0))
                .collect(),
        )
    }

    #[test]
    fn a_steady_first_order_failure_time_converges_by_richardson() {
        // 3.40, 3.20, 3.10, 3.05: d₁ = −0.10, d₂ = −0.05 over the three finest, order 1,
        // t* = 3.05 − 0.05/(2 − 1) = 3.00; |d₂| = 0.05 is 20 steps of 0.0025, far beyond
        // the agreement rule's 2.
        let v = judge_failure(&failing([3.40, 3.20, 3.10, 3.05], [1; 4]), &[]);
        assert_eq!(
            (v.verdict, v.rule),
            (VerdictKind::Converged, Rule::Richardson),
            "{v:?}"
        );
        assert!((v.order.unwrap() - 1.0).abs() < 1e-9, "{v:?}");
        assert!((v.extrapolated.unwrap() - 3.00).abs() < 1e-9, "{v:?}");
        assert!(
            (v.tolerance.unwrap() - RICHARDSON_SAFETY * 0.05).abs() < 1e-9,
            "{v:?}"
        );
        // Second order over the three finest (a coarsest level far off does not count):
        // 3.16, 3.04, 3.01, d = −0.12, −0.03, t* = 3.01 − 0.03/3 = 3.00.
        let v = judge_failure(&failing([9.0, 3.16, 3.04, 3.01], [1; 4]), &[]);
        assert_eq!(v.rule, Rule::Richardson, "{v:?}");
        assert!((v.order.unwrap() - 2.0).abs() < 1e-9, "{v:?}");
        assert!((v.extrapolated.unwrap() - 3.00).abs() < 1e-9, "{v:?}");
        // Agreement within two steps still comes first, without an extrapolation.
        let v = judge_failure(&failing([3.40, 3.02, 3.01, 3.008], [1; 4]), &[]);
        assert_eq!((v.rule, v.extrapolated), (Rule::Agreement, None), "{v:?}");
    }

    #[test]
    fn richardson_refuses_oscillations_jumps_and_orders_out_of_range() {
        let not = |times, first| {
            let v = judge_failure(&failing(times, first), &[]);
            assert_eq!(
                (v.verdict, v.extrapolated),
                (VerdictKind::NotConverged, None),
                "{times:?} {first:?}: {v:?}"
            );
        };
        // Oscillating differences: +0.10, −0.05.
        not([3.40, 3.20, 3.30, 3.25], [1; 4]);
        // A jump: the finest level loses block 2 first, another motion.
        not([3.40, 3.20, 3.10, 3.05], [1, 1, 1, 2]);
        not([3.40, 3.20, 3.10, 3.05], [1, 2, 1, 1]);
        // Orders out of range: d₁/d₂ = 1.2 (p = 0.26) and 10 (p = 3.3).
        not([3.40, 3.20, 3.08, 2.98], [1; 4]);
        not([3.40, 4.20, 3.20, 3.10], [1; 4]);
        // Two levels only: no third to estimate an order from.
        let v = judge_failure(
            &levels(vec![run(Some(3.1), &[1], 0.0), run(Some(3.05), &[1], 0.0)]),
            &[],
        );
        assert_eq!(v.verdict, VerdictKind::NotConverged, "{v:?}");
        // A finest level that stands is not the same motion.
        let mut l = failing([3.40, 3.20, 3.10, 3.05], [1; 4]);
        l[3].observed = run(None, &[], 0.0);
        assert_eq!(judge_failure(&l, &[]).extrapolated, None);
    }

    #[test]
    fn a_run_that_stopped_early_decides_nothing() {
        let mut stopped = run(None, &[], 0.0);
        stopped.complete = false;
        let l = levels(vec![run(None, &[], 0.0), stopped]);
        let v = judge_failure(&l, &[]);
        assert_eq!(
            (v.verdict, v.level_difference),
            (VerdictKind::NotConverged, None)
        );
        assert!(v.why.contains("stopped"), "{}", v.why);
    }
}
