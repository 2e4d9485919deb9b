//! One example per command, shown at the end of its `--help` and checked by a test to
//! parse, so that the examples cannot drift from the flags.

use crate::Cli;
use clap::{CommandFactory, FromArgMatches};

/// One example per leaf command: `rollstack`, the command's path, then its flags.
pub const EXAMPLES: &[&str] = &[
    "rollstack rotation --from euler:3-1-3 --values 30deg,45deg,-60deg --json",
    "rollstack sphere holonomy --theta 1.1 --phi1 0.3 --phi2 2.2 --out hol",
    "rollstack sphere plan --angle 3pi/2 --axis 0.1,0.98994949,0.1 --out plan",
    "rollstack sphere euler-plan --set 3-2-3 --angles 30deg,45deg,60deg --json",
    "rollstack sphere roll --theta 1 --phi1 0.2 --phi2 2 --integrator rk4 --json",
    "rollstack nsga ball --case 2 --scheme moreau --json",
    "rollstack nsga work-precision --system oscillator --out wp",
    "rollstack blocks run shaking --t-end 5 --out shaking",
    "rollstack blocks lire --perturb bottom --floor --out landing",
    "rollstack blocks shake --blocks 6 --omega 6 --amplitude 0.1 --out shake6",
    "rollstack blocks scenes shaking",
    "rollstack blocks sweep frequency --omega 2:20:2 --out freq",
    "rollstack blocks sweep slide --v0 0.05:0.5:0.05 --out slide",
    "rollstack blocks sweep scene shaking --set contact.mu=0.1:0.5:0.1 --t-end 5 --out mu",
    "rollstack blocks work-precision --system column --dts 1e-2,5e-3,2e-3 --out wp",
    "rollstack blocks painleve --aspect 0.5 --mu 0.6 --out painleve",
    "rollstack blocks explore abundance --branch-rule converged --max-branches 100 --classify --out abundance",
    "rollstack blocks converge lire-collapse --levels 3 --out lire-converge",
    "rollstack blocks fragility examples/scenes/classical-column.toml --records quakes --measure pga --scales 0.1:2:0.1 --out column-fragility",
    "rollstack cylinder support --theta 30deg --r-over-h 0.1 --mu 0.2",
    "rollstack cylinder statics --r-over-h 0.1 --mu 0.2 --out statics",
    "rollstack cylinder holonomy rectangle --theta 0.3 --phi1 13pi/3 --phi2 29pi/4 --out rect",
    "rollstack cylinder holonomy circle --ell 2 --theta 0.4 --h 1 --r 0.3 --json",
    "rollstack cylinder frobenius --system pair9 --config touching",
    "rollstack cylinder pair --theta 30deg --out pair --json",
    "rollstack cylinder sweep pair --theta 0.18:0.78:0.075 --out fig3_14",
    "rollstack cylinder sweep push --theta 0.3:0.78:0.03 --push 0:0.6:0.005 --out push",
    "rollstack cylinder work-precision --dts 8e-3,4e-3,2e-3 --out wpc",
    "rollstack tour --out tour --only sphere,cylinder",
    "rollstack merge freq-1 freq-2 --out freq",
    "rollstack slurm --tasks 8 blocks sweep frequency --omega 2:20:0.25 --out freq",
];

/// The example of the leaf command at `path` (`blocks sweep scene`).
#[must_use]
pub fn example_of(path: &str) -> Option<&'static str> {
    let prefix = format!("rollstack {path}");
    EXAMPLES.iter().copied().find(|e| {
        e.strip_prefix(&prefix)
            .is_some_and(|rest| rest.is_empty() || rest.starts_with(' '))
    })
}

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
    match example_of(path) {
        Some(example) if cmd.get_subcommands().next().is_none() => {
            cmd.after_help(format!("Example:\n  {example}"))
        }
        _ => cmd,
    }
}

/// Parses the process's arguments (exits with clap's message and status on an error).
#[must_use]
pub fn parse() -> Cli {
    let matches = command().get_matches();
    Cli::from_arg_matches(&matches).unwrap_or_else(|e| e.exit())
}
