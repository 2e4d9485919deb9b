//! Every `--help` of a leaf command ends with an example, and every example parses, so
//! the examples cannot drift from the flags.

use clap::CommandFactory;
use rollstack_cli::examples::{command, example_of, EXAMPLES};
use rollstack_cli::Cli;

fn leaves(cmd: &clap::Command, path: &str, out: &mut Vec<String>) {
    let subs: Vec<&clap::Command> = cmd
        .get_subcommands()
        .filter(|s| s.get_name() != "help")
        .collect();
    if subs.is_empty() {
        out.push(path.to_owned());
    }
    for s in subs {
        let p = if path.is_empty() {
            s.get_name().to_owned()
        } else {
            format!("{path} {}", s.get_name())
        };
        leaves(s, &p, out);
    }
}

#[test]
fn every_command_has_an_example_that_parses() {
    let mut all = Vec::new();
    leaves(&Cli::command(), "", &mut all);
    for leaf in &all {
        let example =
            example_of(leaf).unwrap_or_else(|| panic!("`rollstack {leaf}` has no example"));
        let args: Vec<&str> = example.split_whitespace().collect();
        if let Err(e) = command().try_get_matches_from(&args) {
            panic!("{example}: {e}");
        }
    }
    assert_eq!(EXAMPLES.len(), all.len(), "one example per leaf command");
}

#[test]
fn the_help_of_a_command_ends_with_its_example() {
    let mut cmd = command();
    let lire = cmd
        .find_subcommand_mut("blocks")
        .and_then(|b| b.find_subcommand_mut("lire"))
        .unwrap();
    let help = lire.render_help().to_string();
    assert!(help
        .trim_end()
        .ends_with("rollstack blocks lire --perturb bottom --floor --out landing"));
}
