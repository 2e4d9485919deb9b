//! Exploring every continuation of a stack (§4.4): a real non-uniqueness is found and
//! labelled real, the thesis's branches are artefacts, caps end runs cleanly, and the
//! tree and its files do not depend on the number of threads.

use blockstack::exploration::{
    branch_cells, explore_scene, fork_records, BranchSummary, WalkSettings,
};
use blockstack::fork_check::ForkLabel;
use blockstack::scenarios::{shaking_column, PainleveCorner, Shaking};
use blockstack::{RunOptions, Scene};
use nsga::explore::{BranchEnd, Exploration, ExploreOptions};
use nsga::BranchRule;

/// The lowest corner's height above the table (top at y = 0.05) for a final pose.
fn corner_gap(case: &PainleveCorner, b: &nsga::explore::Branch<BranchSummary>) -> f64 {
    let p = b.outcome.final_poses[0];
    let moved = PainleveCorner {
        theta: p.theta,
        ..*case
    };
    p.y + moved.corner().1 - 0.05
}

#[test]
fn painleves_indeterminacy_is_a_real_fork() {
    // App. I: θ = 0.9, μ = 2, sliding right, A = 0.5 g and B < 0: the corner may keep
    // contact with a large force or lift off.
    let case = PainleveCorner::default();
    assert!(case.response() < 0.0);
    let run = RunOptions {
        probe_flips: true,
        ..RunOptions::default()
    };
    let settings = WalkSettings {
        sample_every: 1,
        classify: true,
        ..WalkSettings::default()
    };
    let scene = case.scene().unwrap();
    let tree = explore_scene(&scene, &run, &ExploreOptions::default(), settings).unwrap();
    let forks = fork_records(&tree, 1);
    assert_eq!(forks.len(), 1, "{forks:?}");
    let f = &forks[0];
    assert_eq!((f.t, f.distinct, f.consistent), (0.0, 2, 2));
    let e = f.evidence.as_ref().expect("checked");
    assert_eq!(e.label, ForkLabel::Real, "{e:?}");
    assert_eq!(e.refined, [Some(2), Some(2)]);
    // One continuation keeps the corner on the table, the other lifts it off.
    let mut gaps: Vec<f64> = tree.leaves().map(|b| corner_gap(&case, b)).collect();
    gaps.sort_by(f64::total_cmp);
    assert_eq!(gaps.len(), 2);
    assert!(gaps[0].abs() < 1e-8, "{gaps:?}");
    assert!(gaps[1] > 1e-5, "{gaps:?}");
    // With little friction (B > 0) the same probe finds one motion.
    let tame = PainleveCorner { mu: 0.2, ..case };
    assert!(tame.response() > 0.0);
    let scene = tame.scene().unwrap();
    let tree = explore_scene(&scene, &run, &ExploreOptions::default(), settings).unwrap();
    assert_eq!(tree.branches.len(), 1);
}

/// Two blocks on the base of Figure 4.5 (x = sin(3πt/2), 60 steps per period), three
/// periods: the thesis's rule forks here.
fn two_blocks() -> Scene {
    shaking_column(&Shaking {
        blocks: 2,
        amplitude: 1.0,
        omega: 1.5 * std::f64::consts::PI,
        periods: 3.0,
        steps_per_period: 60.0,
        mu: 0.3,
        start_with_base: false,
    })
    .unwrap()
}

fn thesis_rule() -> RunOptions {
    RunOptions {
        branch_rule: BranchRule::Converged,
        ..RunOptions::default()
    }
}

#[test]
fn the_thesis_branches_are_artefacts_and_self_consistency_removes_them() {
    let scene = two_blocks();
    let settings = WalkSettings {
        sample_every: 10,
        classify: true,
        ..WalkSettings::default()
    };
    let tree = explore_scene(&scene, &thesis_rule(), &ExploreOptions::default(), settings).unwrap();
    let forks = fork_records(&tree, 2);
    assert!(forks.len() >= 2, "{}", forks.len());
    for f in &forks {
        let e = f.evidence.as_ref().expect("checked");
        assert!(f.consistent <= 1, "{f:?}");
        assert_ne!(e.label, ForkLabel::Real, "{f:?}");
    }
    assert!(forks
        .iter()
        .any(|f| f.evidence.as_ref().unwrap().label == ForkLabel::Artefact));
    // Only solutions of the step's equations: one motion.
    let strict = explore_scene(
        &scene,
        &RunOptions::default(),
        &ExploreOptions::default(),
        settings,
    )
    .unwrap();
    assert_eq!(strict.branches.len(), 1);
}

#[test]
fn caps_end_the_exploration_cleanly() {
    let scene = two_blocks();
    // The first fork has four candidates (three converged solves that are not
    // self-consistent, then the step the run goes on with): it fits, the later ones not.
    let capped = ExploreOptions {
        max_branches: 5,
        ..ExploreOptions::default()
    };
    let tree = explore_scene(&scene, &thesis_rule(), &capped, WalkSettings::default()).unwrap();
    assert_eq!(tree.branches.len(), 5);
    assert!(tree.branch_cap_reached);
    let t_end = scene.solver.t_end;
    for leaf in tree.leaves() {
        assert_eq!(leaf.end, BranchEnd::Horizon);
        assert!((leaf.end_at.0 - t_end).abs() < 1e-9);
    }
    let shallow = ExploreOptions {
        max_depth: 0,
        ..ExploreOptions::default()
    };
    let tree = explore_scene(&scene, &thesis_rule(), &shallow, WalkSettings::default()).unwrap();
    assert_eq!(tree.branches.len(), 1);
    assert!(tree.depth_cap_reached);
}

/// The rows of `branches.csv` and the trajectory files (name, bytes) of an exploration.
type TreeFiles = (Vec<Vec<String>>, Vec<(String, Vec<u8>)>);

/// The branch rows and every trajectory file of an exploration run on `threads` threads.
fn tree_files(threads: usize) -> TreeFiles {
    let dir = std::env::temp_dir().join(format!(
        "rollstack-explore-threads-{threads}-{}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let scene = two_blocks();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    let tree: Exploration<BranchSummary> = pool.install(|| {
        let settings = WalkSettings {
            sample_every: 10,
            trajectories: Some(&dir),
            ..WalkSettings::default()
        };
        explore_scene(&scene, &thesis_rule(), &ExploreOptions::default(), settings).unwrap()
    });
    let rows = tree.branches.iter().map(branch_cells).collect();
    let mut files: Vec<(String, Vec<u8>)> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| {
            let p = e.unwrap().path();
            (
                p.file_name().unwrap().to_string_lossy().into_owned(),
                std::fs::read(&p).unwrap(),
            )
        })
        .collect();
    files.sort();
    let _ = std::fs::remove_dir_all(&dir);
    (rows, files)
}

#[test]
fn the_tree_and_its_files_do_not_depend_on_the_thread_count() {
    let (rows1, files1) = tree_files(1);
    let (rows2, files2) = tree_files(2);
    assert!(rows1.len() >= 5, "{}", rows1.len());
    assert_eq!(rows1, rows2);
    assert_eq!(files1.len(), rows1.len());
    assert_eq!(files1, files2);
}

#[test]
fn a_frequency_row_spreads_its_failure_time_over_the_motions() {
    use blockstack::studies::shaking::{frequency_row, periods_for_horizon};
    let shaking = Shaking {
        omega: 4.0,
        periods: periods_for_horizon(5.0, 4.0),
        ..Shaking::default()
    };
    let plain = frequency_row(&shaking, &RunOptions::default());
    assert_eq!(plain.branches, 1);
    let t = plain.failure_time.expect("fails near t = 4");
    assert_eq!(plain.failure_time_min, Some(t));
    assert_eq!(plain.failure_time_max, Some(t));
    let explored = RunOptions {
        spread_branches: 20,
        ..thesis_rule()
    };
    let row = frequency_row(&shaking, &explored);
    assert!(row.branches > 1, "{row:?}");
    assert!(row.failed_branches >= 1 && row.failed_branches <= row.branches);
    let (lo, mid, hi) = (
        row.failure_time_min.unwrap(),
        row.failure_time_median.unwrap(),
        row.failure_time_max.unwrap(),
    );
    assert!(lo <= mid && mid <= hi && lo < hi, "{row:?}");
}
