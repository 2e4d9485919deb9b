//! The README's sequences, run in order as a new user types them (shortened with
//! `--t-end` where a run's length does not matter), so that one step cannot break the
//! next.

mod common;

use common::run_in;

#[test]
fn a_run_s_output_directory_does_not_hide_the_scene_of_its_name() {
    let dir = common::temp_dir("readme-shaking");
    std::fs::create_dir_all(&dir).unwrap();
    // README: `blocks run shaking --out shaking`, then a sweep of the scene `shaking`.
    let words = |line: &'static str| line.split(' ').collect::<Vec<_>>();
    let (ok, _, err) = run_in(
        &dir,
        &words("blocks run shaking --out shaking --t-end 0.05"),
    );
    assert!(ok, "{err}");
    assert!(dir.join("shaking").is_dir());
    let sweep = "blocks sweep scene shaking --set contact.mu=0.1,0.2 --t-end 0.05";
    let (ok, out, err) = run_in(&dir, &words(sweep));
    assert!(ok, "{err}");
    assert_eq!(
        out.lines().filter(|l| l.contains("contact.mu")).count(),
        2,
        "{out}"
    );
    assert!(
        err.contains(
            "note: shaking is a directory, not a scene file: took the built-in scene shaking"
        ),
        "which scene was taken is said: {err}"
    );
    let (ok, _, err) = run_in(&dir, &["blocks", "run", "shaking", "--t-end", "0.05"]);
    assert!(
        ok && err.contains("took the built-in scene shaking"),
        "{err}"
    );
    // A directory that names no built-in scene is not read as one.
    std::fs::create_dir_all(dir.join("mine")).unwrap();
    let (ok, _, err) = run_in(&dir, &["blocks", "run", "mine"]);
    assert!(
        !ok && err.contains("cannot read scene mine: is a directory, not a scene file"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn every_command_of_the_readme_parses() {
    let readme =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../README.md")).unwrap();
    let mut commands = 0;
    let mut in_shell = false;
    for line in readme.lines() {
        if line.starts_with("```") {
            in_shell = line == "```sh";
            continue;
        }
        let Some(rest) = line.trim_start().strip_prefix("rollstack ") else {
            continue;
        };
        if !in_shell {
            continue;
        }
        // The command before a comment, a redirection or the next command of the line.
        let command = rest.split(['#', '>', '|', '&']).next().unwrap_or_default();
        let args: Vec<&str> = std::iter::once("rollstack")
            .chain(command.split_whitespace())
            .collect();
        commands += 1;
        if let Err(e) = rollstack_cli::examples::command().try_get_matches_from(&args) {
            panic!("README: {args:?}: {e}");
        }
    }
    assert!(commands > 20, "the README's commands are read ({commands})");
}
