//! The cylinder commands agree on their defaults: a flag two of them share (or the same
//! quantity under another name) has one default, read from the clap definitions, unless
//! the command reproduces a thesis figure that needs another value and its `--help`
//! says so.

use clap::CommandFactory;
use rollstack_cli::Cli;
use std::collections::BTreeMap;

/// Flags that name the same quantity under different names in different commands:
/// `--mu` of `statics` and `support` is the floor friction μ_s of the others.
const SAME_QUANTITY: &[(&str, &str)] = &[("mu", "mu-floor")];

/// A default that differs from the other commands' on purpose: (command, flag, default,
/// what its help must say to justify it).
const EXCEPTIONS: &[(&str, &str, &str, &str)] = &[
    ("cylinder pair", "mu-floor", "1", "Figure 3.14"),
    (
        "cylinder holonomy rectangle",
        "r-over-h",
        "0.12",
        "Figure 3.10",
    ),
    ("cylinder sweep push", "steps", "100", "0.05 s"),
    // A grid of pushes, not one push.
    (
        "cylinder sweep push",
        "push",
        "0:0.5:0.01",
        "tried at each ϑ",
    ),
    ("cylinder frobenius", "r", "0.1143", "§3.6"),
    // The study measures the pair the tour runs.
    (
        "cylinder work-precision",
        "theta",
        "30deg",
        "cylinder pair --theta 30deg",
    ),
];

/// One flag with a default in one leaf command.
struct Default {
    command: String,
    value: String,
    help: String,
}

/// Every defaulted flag of every leaf command under `cmd`, by quantity.
fn collect(cmd: &clap::Command, path: &str, out: &mut BTreeMap<String, Vec<Default>>) {
    let path = format!("{path} {}", cmd.get_name()).trim().to_owned();
    if cmd.has_subcommands() {
        for sub in cmd.get_subcommands() {
            collect(sub, &path, out);
        }
        return;
    }
    for arg in cmd.get_arguments() {
        let (Some(long), [value]) = (arg.get_long(), arg.get_default_values()) else {
            continue;
        };
        if arg.is_hide_set() || !arg.get_action().takes_values() {
            continue;
        }
        let quantity = SAME_QUANTITY
            .iter()
            .find(|(alias, _)| *alias == long)
            .map_or(long, |(_, name)| name);
        out.entry(quantity.to_owned()).or_default().push(Default {
            command: path.clone(),
            value: value.to_string_lossy().into_owned(),
            help: arg.get_help().map(ToString::to_string).unwrap_or_default(),
        });
    }
}

fn cylinder_defaults() -> BTreeMap<String, Vec<Default>> {
    let cli = Cli::command();
    let cylinder = cli.find_subcommand("cylinder").expect("a cylinder command");
    let mut out = BTreeMap::new();
    collect(cylinder, "", &mut out);
    out
}

#[test]
fn shared_cylinder_flags_have_one_default_or_a_documented_exception() {
    let mut problems = Vec::new();
    for (flag, uses) in cylinder_defaults() {
        let exception = |d: &Default| {
            EXCEPTIONS
                .iter()
                .find(|(c, f, _, _)| *c == d.command && *f == flag)
        };
        let mut common: Vec<&Default> = Vec::new();
        for d in &uses {
            match exception(d) {
                Some((_, _, value, why)) => {
                    if d.value != *value {
                        problems.push(format!(
                            "{} --{flag}: default {} where the exception says {value}",
                            d.command, d.value
                        ));
                    }
                    if !d.help.contains(why) {
                        problems.push(format!(
                            "{} --{flag}: its help does not say why its default differs \
                             ({why:?} missing): {:?}",
                            d.command, d.help
                        ));
                    }
                }
                None => common.push(d),
            }
        }
        if let Some(first) = common.first() {
            for d in &common[1..] {
                if d.value != first.value {
                    problems.push(format!(
                        "--{flag}: {} in {}, {} in {}",
                        first.value, first.command, d.value, d.command
                    ));
                }
            }
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn every_exception_names_a_flag_the_commands_have() {
    let defaults = cylinder_defaults();
    for (command, flag, _, _) in EXCEPTIONS {
        let found = defaults
            .get(*flag)
            .is_some_and(|uses| uses.iter().any(|d| d.command == *command));
        assert!(found, "{command} --{flag} has no default to excuse");
    }
}
