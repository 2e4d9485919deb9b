//! docs/scenes.md against the program: the built-in scenes it lists, its worked example's
//! output (a transcript, as in docs/cli.md), and the units it gives the keys that the
//! command line's help also states.

mod common;

const DOC: &str = include_str!(concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/scenes.md"));

/// The first ```` ```toml ```` block after `heading`.
fn toml_after(heading: &str) -> &'static str {
    let from = DOC.find(heading).expect("the heading is on the page");
    let start = DOC[from..].find("```toml\n").expect("a toml block") + from + 8;
    let end = DOC[start..].find("```").unwrap() + start;
    &DOC[start..end]
}

/// The cells of the table row of `key` (`` | `r` | mass | … ``) in the section `heading`.
fn row(heading: &str, key: &str) -> Vec<&'static str> {
    let from = DOC.find(heading).expect("the heading is on the page");
    let prefix = format!("| `{key}` |");
    let line = DOC[from..]
        .lines()
        .find(|l| l.starts_with(&prefix))
        .unwrap_or_else(|| panic!("a row for {key}"));
    line.split('|')
        .map(str::trim)
        .filter(|c| !c.is_empty())
        .collect()
}

#[test]
fn the_worked_example_prints_what_the_page_shows() {
    let six = toml_after("## A worked example");
    // The malformed record of the baseline section: a scene that reads it, and the file.
    let column = "[base]\nwidth = 1.0\nheight = 0.1\n[base.x]\nmotion = \"record\"\n\
                  record = \"quake.AT2\"\n[[blocks]]\nwidth = 0.2\nheight = 0.4\n\
                  [contact]\nmu = 0.5\n";
    let quake = "PEER NGA STRONG MOTION DATABASE RECORD\nA made-up record\n\
                 ACCELERATION TIME SERIES IN UNITS OF G\nDT= .005\n 0.0 0.001 0.002\n";
    let trilith = toml_after("### Any arrangement");
    let files = [
        ("six.toml", six),
        ("column.toml", column),
        ("quake.AT2", quake),
        ("trilith.toml", trilith),
    ];
    let failures = common::transcript_failures(DOC, "scenes-doc", 1, &files);
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}

/// The trilith of "Any arrangement" is the built-in one shaken harder: the same scene
/// but for the base's amplitude.
#[test]
fn the_trilith_on_the_page_is_the_built_in_one() {
    let page = blockstack::Scene::from_toml(toml_after("### Any arrangement")).unwrap();
    let text = blockstack::scenes::find("trilith").unwrap().toml;
    let shaken = text.replace("amplitude = 0.05 ", "amplitude = 0.3 ");
    assert_ne!(shaken, text);
    assert_eq!(page, blockstack::Scene::from_toml(&shaken).unwrap());
}

#[test]
fn the_page_lists_the_built_in_scenes() {
    // The table that follows "The built-in scenes are …", up to its blank line.
    let from = DOC
        .find("The built-in scenes are")
        .expect("the built-in scenes' paragraph");
    let table = DOC[from..].split("\n\n").nth(1).expect("their table");
    let listed: Vec<&str> = table
        .lines()
        .filter_map(|l| l.strip_prefix("| `"))
        .filter_map(|l| l.split_once('`').map(|(name, _)| name))
        .collect();
    assert_eq!(
        listed,
        blockstack::scenes::names(),
        "docs/scenes.md's table of built-in scenes"
    );
}

#[test]
fn the_prox_parameter_is_a_mass_everywhere() {
    // [solver] r, `blocks run --prox-constant` and `nsga ball --prox-constant` are one
    // quantity: a mass (model units for the blocks, kg for the SI benchmarks).
    let unit = row("## `[solver]`", "r")[1];
    assert_eq!(unit, "mass", "docs/scenes.md's unit of [solver] r");
    let (_, blocks, _) = common::run(&["blocks", "run", "--help"]);
    assert!(blocks.contains(&format!("units of {unit}")), "{blocks}");
    let (_, ball, _) = common::run(&["nsga", "ball", "--help"]);
    assert!(ball.contains("prox parameter r in kg"), "{ball}");
}
