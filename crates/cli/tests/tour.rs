//! The tour's page accounts for itself: every file the tour writes is shown or linked,
//! and the page says which rollstack made it, when, and with which command.

mod common;

use common::{run, temp_dir};
use std::path::Path;

fn files_below(root: &Path, dir: &Path, out: &mut Vec<String>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            files_below(root, &path, out);
        } else {
            out.push(
                path.strip_prefix(root)
                    .unwrap()
                    .to_string_lossy()
                    .replace('\\', "/"),
            );
        }
    }
}

#[test]
fn every_file_the_tour_writes_is_linked_and_the_page_names_its_maker() {
    let dir = temp_dir("tour-links");
    let out = dir.to_str().unwrap();
    let (ok, _, stderr) = run(&["tour", "--out", out, "--only", "rotations,nsga"]);
    assert!(ok, "{stderr}");
    let page = std::fs::read_to_string(dir.join("index.html")).unwrap();
    let mut files = Vec::new();
    files_below(&dir, &dir, &mut files);
    assert!(files.len() > 5, "{files:?}");
    for file in files.iter().filter(|f| *f != "index.html") {
        assert!(
            page.contains(&format!("\"{file}\"")),
            "{file} is not linked"
        );
    }
    assert!(page.contains(&format!("rollstack {}", env!("CARGO_PKG_VERSION"))));
    assert!(page.contains("<code>rollstack tour --out"));
    assert!(page.contains("rollstack tour --only nsga"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn every_tour_step_is_a_command_line_that_parses_and_is_documented() {
    let doc =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/cli.md")).unwrap();
    for section in rollstack_cli::tour::sections().unwrap() {
        for step in &section.steps {
            let mut args: Vec<&str> = std::iter::once("rollstack")
                .chain(step.args.split_whitespace())
                .collect();
            if !step.out.is_empty() {
                args.extend(["--out", "unused"]);
                let dir = format!("`{}/{}/`", section.name, step.out);
                assert!(doc.contains(&dir), "docs/cli.md does not name {dir}");
            }
            if let Err(e) = rollstack_cli::examples::command().try_get_matches_from(&args) {
                panic!("{args:?}: {e}");
            }
        }
    }
}

#[test]
fn a_tour_step_that_quotes_its_results_is_a_checked_transcript() {
    // A step marked `checked` may say what its run prints (which ω fail, and when):
    // docs/cli.md then shows the same command's output, which its test runs.
    let doc =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/cli.md")).unwrap();
    let shown: Vec<String> = common::transcripts(&doc)
        .into_iter()
        .map(|t| t.args.join(" "))
        .collect();
    let mut checked = 0;
    for section in rollstack_cli::tour::sections().unwrap() {
        for step in section.steps.iter().filter(|s| s.checked) {
            checked += 1;
            assert!(
                shown.contains(&step.args),
                "the tour quotes `rollstack {}`, which docs/cli.md does not show as a transcript",
                step.args
            );
        }
    }
    assert!(
        checked >= 2,
        "the sweeps that quote their results are marked"
    );
}
