//! One example per command, shown at the end of its `--help` and checked by a test to
//! parse, so that the examples cannot drift from the flags.

use crate::Cli;
use clap::{CommandFactory, FromArgMatches};

/// Each leaf command (its path below `rollstack`) and an example of it.
pub const EXAMPLES: &[(&str, &str)] = &[
    (
        "rotation",
        "rollstack rotation --from euler:3-1-3 --values 30deg,45deg,-60deg --json",
    ),
    (
        "sphere holonomy",
        "rollstack sphere holonomy --theta 1.1 --phi1 0.3 --phi2 2.2 --out hol",
    ),
    (
        "sphere plan",
        "rollstack sphere plan --angle 3pi/2 --axis 0.1,0.98994949,0.1 --out plan",
    ),
    (
        "sphere euler-plan",
        "rollstack sphere euler-plan --set 3-2-3 --angles 30deg,45deg,60deg --json",
    ),
    (
        "sphere roll",
        "rollstack sphere roll --theta 1 --phi1 0.2 --phi2 2 --integrator rk4 --json",
    ),
    (
        "nsga ball",
        "rollstack nsga ball --case 2 --scheme moreau --json",
    ),
    (
        "nsga work-precision",
        "rollstack nsga work-precision --system oscillator --out wp",
    ),
    (
        "blocks run",
        "rollstack blocks run shaking --t-end 5 --out shaking",
    ),
    (
        "blocks lire",
        "rollstack blocks lire --perturb bottom --floor --out landing",
    ),
    (
        "blocks shake",
        "rollstack blocks shake --blocks 6 --omega 6 --amplitude 0.1 --out shake6",
    ),
    ("blocks scenes", "rollstack blocks scenes shaking"),
    (
        "blocks sweep frequency",
        "rollstack blocks sweep frequency --omega 2:20:2 --out freq",
    ),
    (
        "blocks sweep slide",
        "rollstack blocks sweep slide --v0 0.05:0.5:0.05 --out slide",
    ),
    (
        "blocks sweep scene",
        "rollstack blocks sweep scene shaking --set contact.mu=0.1:0.5:0.1 --t-end 5 --out mu",
    ),
    (
        "blocks painleve",
        "rollstack blocks painleve --aspect 0.5 --mu 0.6 --out painleve",
    ),
    (
        "cylinder support",
        "rollstack cylinder support --theta 30deg --r-over-h 0.1 --mu 0.2",
    ),
    (
        "cylinder statics",
        "rollstack cylinder statics --r-over-h 0.1 --mu 0.2 --out statics",
    ),
    (
        "cylinder holonomy rectangle",
        "rollstack cylinder holonomy rectangle --theta 0.3 --phi1 13pi/3 --phi2 29pi/4 --out rect",
    ),
    (
        "cylinder holonomy circle",
        "rollstack cylinder holonomy circle --ell 2 --theta 0.4 --h 1 --r 0.3 --json",
    ),
    (
        "cylinder frobenius",
        "rollstack cylinder frobenius --system pair9 --config touching",
    ),
    ("tour", "rollstack tour --out tour --only sphere,cylinder"),
];

/// The command line with each leaf command's example at the end of its help.
#[must_use]
pub fn command() -> clap::Command {
    with_examples(Cli::command(), "")
}

fn with_examples(mut cmd: clap::Command, path: &str) -> clap::Command {
    let names: Vec<String> = cmd
        .get_subcommands()
        .map(|s| s.get_name().to_owned())
        .collect();
    for name in names.iter().filter(|n| *n != "help") {
        let sub_path = if path.is_empty() {
            name.clone()
        } else {
            format!("{path} {name}")
        };
        cmd = cmd.mut_subcommand(name, |sub| with_examples(sub, &sub_path));
    }
    match EXAMPLES.iter().find(|(p, _)| *p == path) {
        Some((_, example)) => cmd.after_help(format!("Example:\n  {example}")),
        None => cmd,
    }
}

/// Parses the process's arguments (exits with clap's message and status on an error).
#[must_use]
pub fn parse() -> Cli {
    let matches = command().get_matches();
    Cli::from_arg_matches(&matches).unwrap_or_else(|e| e.exit())
}

#[cfg(test)]
mod tests {
    use super::*;

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
            let (_, example) = EXAMPLES
                .iter()
                .find(|(p, _)| p == leaf)
                .unwrap_or_else(|| panic!("`rollstack {leaf}` has no example"));
            let args: Vec<&str> = example.split_whitespace().collect();
            assert!(
                example.starts_with(&format!("rollstack {leaf} "))
                    || *example == format!("rollstack {leaf}"),
                "{example} is not an example of {leaf}"
            );
            if let Err(e) = command().try_get_matches_from(&args) {
                panic!("{example}: {e}");
            }
        }
        for (path, _) in EXAMPLES {
            assert!(
                all.iter().any(|l| l == path),
                "an example for a command that does not exist: {path}"
            );
        }
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
}
