//! Scene files a user might write, with any value in any field: the reader and a short
//! run never panic, a refused scene says why in one line, and an accepted one runs to a
//! finite state or stops with an error.

use blockstack::{simulate, RunOptions, Scene};
use proptest::prelude::*;

/// Values that break naive code: zero, negative, tiny, huge, non-finite, non-numbers.
fn value() -> impl Strategy<Value = String> {
    // Mostly plausible values, so that about a third of the scenes are accepted and run.
    prop_oneof![
        60 => (0.01..2.0f64).prop_map(|v| format!("{v}")),
        1 => (-10.0..10.0f64).prop_map(|v| format!("{v}")),
        1 => Just("0.0".to_owned()),
        1 => Just("-1.0".to_owned()),
        1 => Just("1e-300".to_owned()),
        1 => Just("1e300".to_owned()),
        1 => Just("nan".to_owned()),
        1 => Just("inf".to_owned()),
        1 => Just("\"x\"".to_owned()),
    ]
}

fn scene_text(v: &[String]) -> String {
    format!(
        "[base]\nwidth = {}\nheight = {}\nmotion = \"harmonic\"\namplitude = {}\nomega = {}\n\n\
         [[blocks]]\nwidth = {}\nheight = {}\nmass = {}\ncount = 2\n\n\
         [contact]\nmu = {}\ne_n = {}\ne_f = 0.0\n\n\
         [solver]\ndt = {}\nt_end = 0.05\n\n[floor]\n",
        v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7], v[8], v[9]
    )
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    #[test]
    fn any_scene_is_refused_in_one_line_or_runs(values in prop::collection::vec(value(), 10)) {
        match Scene::from_toml(&scene_text(&values)) {
            Err(e) => {
                let message = e.to_string();
                prop_assert!(!message.is_empty() && !message.contains('\n'), "{message}");
            }
            Ok(scene) => {
                // Short runs only: a tiny dt is the user's choice, not the fuzzer's.
                let options = RunOptions { t_end: Some(20.0 * scene.solver.dt), ..RunOptions::default() };
                if let Ok(summary) = simulate(&scene, &options, |_| {}) {
                    if summary.error.is_none() {
                        for p in &summary.final_poses {
                            prop_assert!(p.x.is_finite() && p.y.is_finite() && p.theta.is_finite());
                        }
                    }
                }
            }
        }
    }
}

/// The keys of [`scene_text`]'s values, as a refusal names them.
const KEYS: [&str; 10] = [
    "[base] width",
    "[base] height",
    "[base] amplitude",
    "[base] omega",
    "[[blocks]] width",
    "[[blocks]] height",
    "[[blocks]] mass",
    "[contact] mu",
    "[contact] e_n",
    "[solver] dt",
];

proptest! {
    /// A value of the wrong type is refused under its key, whichever key it is.
    #[test]
    fn a_wrong_type_names_its_key(k in 0usize..10, wrong in prop_oneof![Just("\"x\""), Just("[1.0]"), Just("true")]) {
        let mut values = vec!["0.5".to_owned(); 10];
        values[k] = wrong.to_owned();
        let e = Scene::from_toml(&scene_text(&values)).unwrap_err().to_string();
        prop_assert!(e.contains(&format!("{}: invalid type", KEYS[k])), "{e}");
    }

    /// A count may be written as a decimal when it is whole, as every number of a file.
    #[test]
    fn a_whole_decimal_count_counts(n in 1usize..5, half in proptest::bool::ANY) {
        let mut values = vec!["0.5".to_owned(); 10];
        values[9] = "0.01".to_owned(); // Δt below t_end
        let count = if half { format!("{n}.5") } else { format!("{n}.0") };
        let text = scene_text(&values).replace("count = 2", &format!("count = {count}"));
        match Scene::from_toml(&text) {
            Ok(scene) => prop_assert!(!half && scene.n_blocks() == n),
            Err(e) => prop_assert!(half && e.to_string().contains("count must be a whole number"), "{e}"),
        }
    }
}

#[test]
fn the_generator_produces_scenes_that_run() {
    let plausible: Vec<String> = [
        "1.0", "0.1", "0.2", "4.0", "0.2", "0.4", "1.0", "0.3", "0.0", "0.01",
    ]
    .iter()
    .map(|s| (*s).to_owned())
    .collect();
    let scene = Scene::from_toml(&scene_text(&plausible)).unwrap();
    let summary = simulate(&scene, &RunOptions::default(), |_| {}).unwrap();
    assert!(summary.error.is_none() && summary.steps == 5);
}

/// Block counts that break naive code: zero, the limit and one over it, huge, the
/// largest integer a scene file holds.
fn count() -> impl Strategy<Value = u64> {
    let max = blockstack::scene::MAX_BLOCKS as u64;
    prop_oneof![
        4 => 1..20u64,
        1 => Just(0),
        1 => Just(max),
        1 => Just(max + 1),
        1 => max..u64::from(u32::MAX),
        1 => Just(1_000_000_000),
        1 => Just(i64::MAX as u64),
    ]
}

/// A scene of one `[[blocks]]` entry per count.
fn counted_scene(counts: &[u64]) -> String {
    let mut text = "[base]\nwidth = 1.0\nheight = 0.1\n".to_owned();
    for c in counts {
        text += &format!("[[blocks]]\nwidth = 0.2\nheight = 0.4\ncount = {c}\n");
    }
    text + "[contact]\nmu = 0.2\n"
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    /// Counts are checked before any block is built: a scene over the limit is refused
    /// in one line naming the count and the limit, at once (nothing allocated for it).
    #[test]
    fn block_counts_are_checked_before_any_block_is_built(counts in prop::collection::vec(count(), 1..4)) {
        let total: u128 = counts.iter().map(|&c| u128::from(c)).sum();
        let clock = std::time::Instant::now();
        let loaded = Scene::from_toml(&counted_scene(&counts));
        let within = counts.iter().all(|&c| c >= 1)
            && total <= blockstack::scene::MAX_BLOCKS as u128;
        match loaded {
            Ok(scene) => prop_assert!(within && scene.n_blocks() as u128 == total),
            Err(e) => {
                let message = e.to_string();
                prop_assert!(!within, "{message}");
                prop_assert!(message.contains("count") && message.contains("[1, 10000]"), "{message}");
                prop_assert!(!message.contains('\n'), "{message}");
                prop_assert!(clock.elapsed().as_secs_f64() < 1.0, "refused only after {:?}", clock.elapsed());
            }
        }
    }
}

#[test]
fn the_block_limit_in_messages_is_the_limit() {
    assert_eq!(
        blockstack::scene::BLOCK_COUNT_RANGE,
        format!("[1, {}]", blockstack::scene::MAX_BLOCKS)
    );
}
