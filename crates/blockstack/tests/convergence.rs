//! `blocks converge`'s verdicts on built-in scenes (short end times, so that each test
//! takes seconds in a debug build).

use blockstack::scenes;
use blockstack::simulation::RunOptions;
use blockstack::studies::convergence::verdict::VerdictKind;
use blockstack::studies::convergence::{converge, ConvergenceReport, Settings};

/// The study of a built-in scene to `t_end`.
fn study(name: &str, t_end: f64, settings: Settings) -> ConvergenceReport {
    let scene = scenes::find(name).unwrap().load().unwrap().scene;
    let options = RunOptions {
        t_end: Some(t_end),
        ..RunOptions::default()
    };
    converge(&scene, &options, settings).unwrap()
}

/// K = 2 (Δt, Δt/2, Δt/4) and `ensemble` members per magnitude.
fn settings(ensemble: usize) -> Settings {
    Settings {
        levels: 2,
        ensemble,
    }
}

#[test]
fn the_lire_collapse_converges() {
    // To t = 7, after every block has fallen: failure at 6.600 at Δt = 0.01, 6.595 at
    // Δt/2 and Δt/4 (issue 63), final poses within 1e-4.
    let r = study("lire-collapse", 7.0, settings(1));
    assert_eq!(r.failure.verdict, VerdictKind::Converged, "{r}");
    let failure: Vec<f64> = r.runs[..3]
        .iter()
        .map(|l| l.observed.failure_time.unwrap())
        .collect();
    assert!(
        (failure[0] - 6.600).abs() < 1e-9 && (failure[2] - 6.595).abs() < 1e-9,
        "{failure:?}"
    );
    // The levels agree exactly: known to the finest Δt.
    assert_eq!(r.failure.tolerance, Some(0.0025), "{r}");
    assert_eq!(r.outcome.verdict, VerdictKind::Converged, "{r}");
    assert!(r.outcome.tolerance.unwrap() < 1e-4, "{r}");
    // Three levels agree: the final poses' observed order is about 2.
    let order = r.outcome.order.unwrap();
    assert!((1.5..2.5).contains(&order), "{r}");
    assert!(r.failure.fork_times.is_empty() && r.runs.iter().all(|r| r.error.is_none()));
}

#[test]
fn the_abundance_is_not_converged() {
    // Figure 4.5's setting to t = 1: Δt/2 and Δt/4 end with blocks 1, 2, 3 fallen in
    // that order, Δt with blocks 2, 1, 3, 5, and the final poses of Δt/2 and Δt/4 differ
    // by 0.17, almost a block width; the members perturbed by 1e-10 and 1e-7 end within a
    // hundredth of that of the unperturbed run: the difference is the step's, not
    // sensitivity.
    let r = study("abundance", 1.0, settings(1));
    assert_eq!(r.outcome.verdict, VerdictKind::NotConverged, "{r}");
    let difference = r.outcome.level_difference.unwrap();
    assert!(difference > 0.1, "{r}");
    assert!(
        r.outcome.ensemble_spread.unwrap() < 1e-2 * difference,
        "{r}"
    );
    assert_ne!(
        r.runs[0].observed.outcome, r.runs[2].observed.outcome,
        "{r}"
    );
}
