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
    // Lift-off, sliding contact and jam at the first step; the sliding contact meets the
    // same three at each of the 10 steps.
    assert_eq!(forks.len(), 10, "{forks:?}");
    for f in &forks {
        assert_eq!((f.distinct, f.consistent), (3, 3), "{f:?}");
        let e = f.evidence.as_ref().expect("checked");
        assert_eq!(e.label, ForkLabel::Real, "{e:?}");
    }
    assert_eq!(forks[0].t, 0.0);
    // Some continuations keep the corner on the table, others lift it off.
    let gaps: Vec<f64> = tree.leaves().map(|b| corner_gap(&case, b)).collect();
    assert!(gaps.iter().any(|g| g.abs() < 1e-8), "{gaps:?}");
    assert!(gaps.iter().any(|&g| g > 1e-5), "{gaps:?}");
    // With little friction (B > 0) the same probe finds one motion.
    let tame = PainleveCorner { mu: 0.2, ..case };
    assert!(tame.response() > 0.0);
    let scene = tame.scene().unwrap();
    let tree = explore_scene(&scene, &run, &ExploreOptions::default(), settings).unwrap();
    assert_eq!(tree.branches.len(), 1);
}

/// Without `probe_flips`, the probe runs where App. I's b ≤ 0 (nsga's `probe_painleve`,
/// on in the block stack): the same ten forks, each with its three solutions; with
/// μ = 0.2 (b > 0) it never runs, and the step costs what it did without it.
#[test]
fn painleves_indeterminacy_is_found_without_a_flag_where_b_is_negative() {
    let case = PainleveCorner::default();
    let settings = WalkSettings {
        sample_every: 1,
        ..WalkSettings::default()
    };
    let plain = RunOptions::default();
    assert!(!plain.probe_flips);
    let tree = explore_scene(
        &case.scene().unwrap(),
        &plain,
        &ExploreOptions::default(),
        settings,
    )
    .unwrap();
    let forks = fork_records(&tree, 1);
    assert_eq!(forks.len(), 10, "{forks:?}");
    assert!(
        forks.iter().all(|f| (f.distinct, f.consistent) == (3, 3)),
        "{forks:?}"
    );
    // A plain run records the branch point and goes on with Newton's solution, the
    // lift-off, after which the corner no longer touches.
    let run = blockstack::simulate(&case.scene().unwrap(), &plain, |_| {}).unwrap();
    assert_eq!(run.branch_points.len(), 1, "{:?}", run.branch_points);
    assert_eq!(run.branch_points[0].t, 0.0);
    assert_eq!(run.branch_points[0].distinct, 3);
    // Off the region nothing is probed: as many linear solves as with the probe off.
    let tame = PainleveCorner { mu: 0.2, ..case }.scene().unwrap();
    let off = RunOptions {
        tuning: vec!["policy.probe_painleve=false".into()],
        ..RunOptions::default()
    };
    let with = blockstack::simulate(&tame, &plain, |_| {}).unwrap();
    let without = blockstack::simulate(&tame, &off, |_| {}).unwrap();
    assert!(with.branch_points.is_empty());
    assert_eq!(with.linear_solves, without.linear_solves);
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

/// Figure 4.6's column at ω = 12 (a row of `blocks sweep frequency`), five periods: it
/// forks at step 468 (t = 2.4504) between two self-consistent candidates, 1.3·10⁻³ apart,
/// whose index sets differ at the top interface.
fn omega_12() -> Scene {
    shaking_column(&Shaking {
        omega: 12.0,
        periods: 5.0,
        ..Shaking::default()
    })
    .unwrap()
}

/// The rows of a CSV file as maps from its header.
fn csv_rows(path: &std::path::Path) -> Vec<std::collections::HashMap<String, String>> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    lines
        .map(|l| {
            header
                .iter()
                .zip(l.split(','))
                .map(|(h, c)| ((*h).to_owned(), c.to_owned()))
                .collect()
        })
        .collect()
}

#[test]
fn branch_csvs_show_the_contact_law_and_carry_the_columns_weight() {
    use blockstack::contact_laws::Tolerances;
    let dir = std::env::temp_dir().join(format!("rollstack-laws-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let scene = omega_12();
    let settings = WalkSettings {
        sample_every: 100,
        trajectories: Some(&dir),
        ..WalkSettings::default()
    };
    let root_only = ExploreOptions {
        max_branches: 1,
        ..ExploreOptions::default()
    };
    let run = RunOptions {
        t_end: Some(2.5),
        ..RunOptions::default()
    };
    explore_scene(&scene, &run, &root_only, settings).unwrap();
    let rows = csv_rows(&dir.join("branch_00000.csv"));
    let _ = std::fs::remove_dir_all(&dir);
    let tol = Tolerances::new(&scene, scene.solver.dt);
    let cell = |r: &std::collections::HashMap<String, String>, c: &str| -> f64 {
        r.get(c)
            .unwrap_or_else(|| panic!("no column {c}"))
            .parse()
            .unwrap()
    };
    let mu = 0.2;
    for r in &rows {
        // A self-consistent branch keeps every law to round-off.
        assert!(cell(r, "gap_violation") <= tol.gap, "{r:?}");
        for law in ["normal", "cone", "complementarity"] {
            assert!(cell(r, &format!("{law}_violation")) <= tol.impulse, "{r:?}");
        }
        for k in 1..=4 {
            let state = &r[&format!("state{k}")];
            let pn = [cell(r, &format!("pn{k}a")), cell(r, &format!("pn{k}b"))];
            let pf = cell(r, &format!("pf{k}"));
            // An open corner carries no impulse; a sliding interface's friction is on
            // the cone, a sticking one's inside it.
            for (letter, p) in state.chars().zip(pn) {
                assert!(letter == 'c' || p.abs() <= tol.impulse, "{k} {r:?}");
            }
            let bound = mu * (pn[0] + pn[1]);
            match state.chars().nth(2) {
                Some('S') => assert!((pf.abs() - bound).abs() <= tol.impulse, "{k} {r:?}"),
                Some('K' | '-') => assert!(pf.abs() <= bound + tol.impulse, "{k} {r:?}"),
                other => panic!("state {other:?}"),
            }
        }
    }
    // The interface beneath block j carries the weight of the blocks above it: over the
    // run, its impulses add up to (5 − j) m g t, the column's vertical momentum being
    // small (it rocks in place).
    let t = cell(rows.last().unwrap(), "t");
    for j in 1..=4 {
        let carried: f64 = rows
            .iter()
            .map(|r| cell(r, &format!("pn{j}a")) + cell(r, &format!("pn{j}b")))
            .sum();
        let weight = (5 - j) as f64 * t;
        assert!(
            (carried - weight).abs() < 0.01 * weight,
            "interface {j}: {carried} against {weight}"
        );
    }
    // The base slides under the rocking column (interface 1) all along; the blocks
    // above rock (a corner opens), stick and slip in turn.
    assert!(rows.iter().all(|r| r["state1"].ends_with('S')));
    for k in 2..=4 {
        let seen = |s: &str| rows.iter().any(|r| r[&format!("state{k}")] == s);
        assert!(
            seen("ccK") && seen("ccS") && (seen("ocS") || seen("coS")),
            "{k}"
        );
    }
}

#[test]
fn two_self_consistent_candidates_at_omega_12_are_not_an_artefact_without_evidence() {
    let settings = WalkSettings {
        sample_every: 100,
        classify: true,
        ..WalkSettings::default()
    };
    let run = RunOptions {
        t_end: Some(2.46),
        ..RunOptions::default()
    };
    let scene = omega_12();
    let tree = explore_scene(&scene, &run, &ExploreOptions::default(), settings).unwrap();
    let forks = fork_records(&tree, 4);
    let f = forks
        .iter()
        .find(|f| f.k == 468)
        .expect("the fork at step 468");
    assert_eq!((f.distinct, f.consistent), (2, 2), "{f:?}");
    assert!((f.t - 2.4504).abs() < 1e-4, "{f:?}");
    assert!((f.spread - 1.3e-3).abs() < 0.1e-3, "{f:?}");
    assert_eq!(f.differing_interfaces, vec![4], "{f:?}");
    // Both candidates obey the contact laws ...
    for c in &f.candidates {
        assert!(c.broken.is_empty(), "{c:?}");
    }
    let e = f.evidence.as_ref().expect("checked");
    assert_eq!((e.window, e.stepped_back, e.breaking), (5, Some(0), 0));
    // ... so, though one continuation is found at Δt/2 and Δt/4 (as the one-step check
    // found, which called the fork an artefact), the fork is not labelled an artefact.
    assert_eq!(e.refined, [Some(1), Some(1)], "{e:?}");
    assert_eq!(e.label, ForkLabel::Undecided, "{e:?}");
    assert!(
        e.why.contains("obey the contact laws but merge"),
        "{}",
        e.why
    );
}

#[test]
fn the_thesis_candidates_break_a_contact_law_and_say_which() {
    use blockstack::contact_laws::Law;
    let scene = two_blocks();
    let settings = WalkSettings {
        sample_every: 10,
        ..WalkSettings::default()
    };
    let tree = explore_scene(&scene, &thesis_rule(), &ExploreOptions::default(), settings).unwrap();
    let forks = fork_records(&tree, 2);
    assert!(!forks.is_empty());
    let mut broken = Vec::new();
    for f in &forks {
        assert_eq!(f.candidates.len(), f.distinct, "{f:?}");
        // Every candidate that is a solution of the step's equations obeys the laws.
        let lawful = f.candidates.iter().filter(|c| c.broken.is_empty()).count();
        assert!(lawful >= f.consistent, "{f:?}");
        broken.extend(f.candidates.iter().flat_map(|c| c.broken.clone()));
    }
    // The others break one, by more than round-off.
    assert!(!broken.is_empty());
    assert!(broken.iter().all(|(_, v)| *v > 1e-9), "{broken:?}");
    assert!(
        broken
            .iter()
            .any(|(l, _)| matches!(l, Law::Gap | Law::Cone | Law::Normal)),
        "{broken:?}"
    );
}

#[test]
fn a_window_starts_from_a_state_that_does_not_overlap() {
    // The thesis's rule on the Lire collapse: its branches put blocks into each other,
    // so some forks start from a state that overlaps.
    let scene = blockstack::scenes::find("lire-collapse")
        .unwrap()
        .load()
        .unwrap()
        .scene;
    let settings = WalkSettings {
        sample_every: 100,
        classify: true,
        classify_window: Some(3),
        ..WalkSettings::default()
    };
    let capped = ExploreOptions {
        max_branches: 12,
        ..ExploreOptions::default()
    };
    let tree = explore_scene(&scene, &thesis_rule(), &capped, settings).unwrap();
    let forks = fork_records(&tree, scene.n_blocks());
    let evidence: Vec<_> = forks.iter().filter_map(|f| f.evidence.as_ref()).collect();
    assert!(!evidence.is_empty());
    let back: Vec<_> = evidence
        .iter()
        .filter(|e| e.stepped_back != Some(0))
        .collect();
    assert!(!back.is_empty(), "{evidence:?}");
    for e in back {
        assert!(e.stepped_back.is_none_or(|b| b < 3), "{e:?}");
        assert!(e.why.contains("overlaps"), "{}", e.why);
    }
    // Every label here rests on a candidate that breaks a law.
    for f in &forks {
        let e = f.evidence.as_ref().unwrap();
        assert_eq!(e.label, ForkLabel::Artefact, "{e:?}");
        assert!(
            e.breaking >= 1 && e.why.contains("break a contact law"),
            "{e:?}"
        );
    }
}
