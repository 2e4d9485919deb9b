//! `blocks converge`'s verdicts on built-in scenes (short end times, so that each test
//! takes seconds in a debug build).

use blockstack::scenes;
use blockstack::simulation::RunOptions;
use blockstack::studies::convergence::verdict::VerdictKind;
use blockstack::studies::convergence::{ConvergenceReport, Settings, Study};

/// The study of a built-in scene to `t_end`, its runs one after the other.
fn study(name: &str, t_end: f64, settings: Settings) -> ConvergenceReport {
    let scene = scenes::find(name).unwrap().load().unwrap().scene;
    let options = RunOptions {
        t_end: Some(t_end),
        ..RunOptions::default()
    };
    let study = Study::new(&scene, &options, settings, ["levels", "ensemble"]).unwrap();
    let levels: Vec<_> = study
        .levels()
        .iter()
        .map(|j| study.run(j, None, |_| {}).unwrap())
        .collect();
    let reference = study.reference(&levels).cloned();
    let members: Vec<_> = study
        .members()
        .iter()
        .map(|j| study.run(j, reference.as_ref(), |_| {}).unwrap())
        .collect();
    study.report(levels, members)
}

#[test]
fn the_lire_collapse_converges() {
    let r = study(
        "lire-collapse",
        7.0,
        Settings {
            levels: 2,
            ensemble: 1,
        },
    );
    println!("{r}");
    assert_eq!(r.failure.verdict, VerdictKind::Converged, "{r}");
    assert_eq!(r.outcome.verdict, VerdictKind::Converged, "{r}");
}

#[test]
fn the_abundance_is_not_converged() {
    let r = study(
        "abundance",
        1.0,
        Settings {
            levels: 2,
            ensemble: 2,
        },
    );
    println!("{r}");
    assert!(
        matches!(
            r.outcome.verdict,
            VerdictKind::Chaotic | VerdictKind::NotConverged
        ),
        "{r}"
    );
}
