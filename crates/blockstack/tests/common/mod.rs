//! Helpers shared by the integration tests that run built-in scenes.

use blockstack::{scenes, simulate, RunOptions, RunSummary, Scene, StepRecord};

/// The built-in scene `name`'s file with the `(from, to)` replacements made (each must
/// occur, so a renamed key fails the test rather than silently testing the original).
pub fn builtin(name: &str, edits: &[(&str, &str)]) -> String {
    let mut text = scenes::find(name).unwrap().toml.to_owned();
    for (from, to) in edits {
        assert!(text.contains(from), "{name} has no {from:?}");
        text = text.replace(from, to);
    }
    text
}

/// Runs `scene` to `t_end`, calling `each` with every record; the run must not stop on
/// an error.
pub fn run(scene: &Scene, t_end: f64, each: impl FnMut(&StepRecord)) -> RunSummary {
    let options = RunOptions {
        t_end: Some(t_end),
        ..RunOptions::default()
    };
    let summary = simulate(scene, &options, each).unwrap();
    assert!(summary.error.is_none(), "{:?}", summary.error);
    summary
}
