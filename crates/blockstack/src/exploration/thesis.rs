//! `--preset thesis`: the exploration as the thesis's algorithm runs it (§4.2, §4.4 and
//! its Algorithm 1, App. H, and the author's public scripts), as far as rollstack can
//! express it (docs/exploration.md, "The thesis's algorithm").
//!
//! The algorithm: each step starts one Newton attempt from the last solution, with a
//! Jacobian by forward differences (ε = 10⁻⁶), full updates and a constant prox
//! parameter r = 0.3. When it has not converged after 20 iterations, the step is a
//! branch point: it is solved again with each index set the iterates visited held fixed,
//! and every fixed-set solve that converges (within 20 iterations) starts a branch,
//! whether or not its contact laws hold. A singular Newton matrix sends the step to
//! the next ρ∞, stepped by 0.05 through [0, 1]. A branch stops at the onset of failure
//! (a block loses all contact with the one beneath it, Figure 4.6). The model: no floor,
//! a base 0.2 high, and contacts between neighbouring blocks only
//! ([`SceneFile::as_in_the_thesis_code`]).
//!
//! rollstack's stages that the author's code lacks are switched off: the predicted
//! start, the held-sets attempt, the line search, pruning, the kept factors, the step
//! without the friction shift, halving and the last resort. The
//! regularization of a singular matrix stays (it leaves the solution exact): rollstack's
//! corner contacts can close redundantly, the thesis's two gaps per interface cannot.

use super::WalkSettings;
#[cfg(doc)]
use crate::scene_file::SceneFile;
use crate::simulation::RunOptions;
use nsga::{BranchRule, Prox, THESIS_FD_EPSILON};

/// The thesis's constant prox parameter r (§4.2).
pub const PROX: f64 = 0.3;

/// Newton iterations after which the author's code takes a step as a branch point, and
/// the iterations of each fixed-set solve.
pub const NEWTON_ITERATIONS: usize = 20;

/// The step of the author's ρ∞ updates.
pub const RHO_INF_STEP: f64 = 0.05;

/// The ρ∞ the author's code tries after `rho0`, in order: up by [`RHO_INF_STEP`] to 1,
/// then from 0 up to the last value below `rho0` (0.55, 0.6, …, 1, 0, 0.05, …, 0.45 from
/// 0.5); the code gives the branch up when ρ∞ comes round to `rho0`.
///
/// ```
/// let r = blockstack::exploration::thesis::rho_inf_cycle(0.5);
/// assert_eq!(r.len(), 20);
/// assert_eq!((r[0], r[9], r[10], r[19]), (0.55, 1.0, 0.0, 0.45));
/// ```
#[must_use]
pub fn rho_inf_cycle(rho0: f64) -> Vec<f64> {
    // Whole steps, so that the values are the decimals the author's code prints.
    let steps = (1.0 / RHO_INF_STEP).round() as i64;
    let start = (rho0 / RHO_INF_STEP).round() as i64;
    (1..=steps)
        .map(|k| (start + k).rem_euclid(steps + 1))
        .map(|k| k as f64 * RHO_INF_STEP)
        .map(|r| (r * 1e9).round() / 1e9)
        .collect()
}

/// The nsga options the preset sets by name (`RunOptions::tuning`, `nsga::Options::set`),
/// for a scene whose ρ∞ is `rho0`.
#[must_use]
pub fn assignments(rho0: f64) -> Vec<String> {
    let retries: Vec<String> = rho_inf_cycle(rho0).iter().map(f64::to_string).collect();
    let n = NEWTON_ITERATIONS;
    vec![
        format!("newton.max_iter={n}"),
        "newton.max_iter_per_contact=0".into(),
        "newton.line_search=0".into(),
        "newton.max_openings_per_update=0".into(),
        "newton.prune_open_contacts=false".into(),
        format!("linear.jacobian={{\"FiniteDifference\":{THESIS_FD_EPSILON:e}}}"),
        "linear.reuse_factorization=false".into(),
        format!("policy.retry_max_iter={n}"),
        format!("policy.rho_inf_retries=[{}]", retries.join(",")),
        "policy.rho_inf_retry=SingularMatrix".into(),
        "policy.branch_on_any_failure=true".into(),
        "policy.continue_inconsistent=true".into(),
        "policy.retry_without_friction_shift=false".into(),
        "policy.max_halvings=0".into(),
    ]
}

/// `options` with the thesis's algorithm for a scene whose ρ∞ is `rho0`: r = 0.3, the
/// converged rule, no predicted start, no low-rank updates, no last resort, and
/// [`assignments`] after the options' own.
#[must_use]
pub fn run_options(options: RunOptions, rho0: f64) -> RunOptions {
    let mut tuning = assignments(rho0);
    tuning.extend(options.tuning.iter().cloned());
    RunOptions {
        prox: Some(Prox::Constant(PROX)),
        branch_rule: BranchRule::Converged,
        probe_flips: false,
        skip_last_resort: true,
        skip_low_rank_updates: true,
        skip_predicted_start: true,
        tuning,
        ..options
    }
}

/// `settings` with every branch stopped at the onset of failure, as the author's code
/// stops.
#[must_use]
pub fn walk_settings(settings: WalkSettings<'_>) -> WalkSettings<'_> {
    WalkSettings {
        stop_at_failure: true,
        ..settings
    }
}
