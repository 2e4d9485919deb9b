//! The overlap check and the failure events of every run: what a reader of a run's
//! summary is told about bodies passing through each other and about how a column fails.

use blockstack::overlap::Body;
use blockstack::scenarios::{lire, lire_on_floor, Perturbation};
use blockstack::scenes::builtin;
use blockstack::simulation::{simulate, RunOptions, RunReport, RunWarning};
use blockstack::{EventKind, Scene};

fn run(scene: &Scene, t_end: f64) -> blockstack::RunSummary {
    let options = RunOptions {
        t_end: Some(t_end),
        ..Default::default()
    };
    simulate(scene, &options, |_| {}).expect("a valid scene")
}

fn penetration_warnings(scene: &Scene, summary: &blockstack::RunSummary) -> usize {
    RunWarning::of(scene, summary)
        .iter()
        .filter(|w| matches!(w, RunWarning::Penetration { .. }))
        .count()
}

#[test]
fn a_standing_tower_reports_no_penetration_and_no_event() {
    let scene = lire(4, Perturbation::None).unwrap();
    let summary = run(&scene, 1.0);
    assert!(
        summary.deepest.depth() < summary.penetration_tol,
        "{:?}",
        summary.deepest
    );
    assert!(summary.events.is_empty(), "{:?}", summary.events);
    assert_eq!(penetration_warnings(&scene, &summary), 0);
}

/// The shaken column of the tour: after it fails, its blocks fall off the base, onto the
/// floor and onto each other. Every corner meets every body it reaches (the corner
/// contacts of `blockstack::pairs`), so no two bodies overlap beyond the tolerance, and
/// the run's events say how the column failed, in order.
#[test]
fn the_shaken_column_stays_solid_and_its_failure_is_told() {
    let shaking = builtin().iter().find(|s| s.name == "shaking").unwrap();
    let scene = shaking.load().unwrap().scene;
    // As the tour runs it (`rollstack blocks run shaking`: branch points resolved).
    let options = RunOptions {
        explore_branches: true,
        ..Default::default()
    };
    let summary = simulate(&scene, &options, |_| {}).expect("a valid scene");
    assert!(summary.error.is_none(), "{:?}", summary.error);
    let deepest = summary.deepest;
    assert!(
        deepest.depth() < summary.penetration_tol,
        "no block inside another: {deepest:?}"
    );
    assert!(
        summary.corner_contacts > 0,
        "the fallen blocks met other bodies"
    );
    assert_eq!(penetration_warnings(&scene, &summary), 0);
    // Loss of support is the failure time; the other events come with it, each block
    // at most once per kind, in time order.
    let first_lost = summary
        .events
        .iter()
        .find(|e| e.kind == EventKind::SupportLost)
        .expect("the column fails");
    assert_eq!(Some(first_lost.t), summary.failure_time);
    assert!(summary.events.windows(2).all(|w| w[0].t <= w[1].t));
    for kind in [
        EventKind::SupportLost,
        EventKind::Tipped,
        EventKind::TouchedFloor,
    ] {
        let mut blocks: Vec<_> = summary
            .events
            .iter()
            .filter(|e| e.kind == kind)
            .map(|e| e.block.unwrap())
            .collect();
        let all = blocks.len();
        blocks.dedup();
        blocks.sort_unstable();
        blocks.dedup();
        assert_eq!(blocks.len(), all, "{kind:?} reported twice for a block");
    }
}

/// A penetration beyond the tolerance is said, in the warnings and in the report.
#[test]
fn a_penetration_beyond_the_tolerance_is_warned_about() {
    let scene = lire(4, Perturbation::None).unwrap();
    let mut summary = run(&scene, 0.1);
    summary.deepest.penetration = blockstack::overlap::Penetration {
        depth: 100.0 * summary.penetration_tol,
        first: Body::Block(2),
        second: Body::Base,
    };
    assert_eq!(penetration_warnings(&scene, &summary), 1);
    let report = RunReport::new(
        &summary,
        &scene,
        &RunOptions::default(),
        &Default::default(),
        0.1,
    );
    assert!(report
        .to_string()
        .contains("largest penetration between two bodies"));
}

/// The Lire collapse on a floor: the four blocks fall from the table and each lands on
/// the floor or on another block, and the check finds no overlap beyond the tolerance.
#[test]
fn the_lire_collapse_on_a_floor_reports_every_landing() {
    let scene = lire_on_floor(4, Perturbation::Bottom).unwrap();
    let summary = run(&scene, 20.0);
    assert!(summary.error.is_none(), "{:?}", summary.error);
    let mut landed: Vec<_> = summary
        .events
        .iter()
        .filter(|e| e.kind == EventKind::TouchedFloor)
        .map(|e| e.block.unwrap())
        .collect();
    landed.sort_unstable();
    assert_eq!(landed, [1, 2, 3, 4], "{:?}", summary.events);
    assert!(summary
        .events
        .iter()
        .any(|e| e.kind == EventKind::HeightDropped));
    assert!(
        summary.deepest.depth() < summary.penetration_tol,
        "{:?}",
        summary.deepest
    );
    assert_eq!(penetration_warnings(&scene, &summary), 0);
}
