//! `rollstack sphere holonomy|plan|euler-plan|roll`: the rolling sphere of Ch. 2.
//!
//! Lengths are in units of the sphere's radius R (so a side of length ϑR is given as the
//! angle ϑ). Components are on {A1, A2, A3 = E3}; for the Euler plan the ground basis E.
//! Every number printed, its text and the cells of the CSV files come from
//! [`holonomy::studies`]; this module reads the flags and writes the files (docs/cli.md).

mod plan;
mod report;
mod roll;

pub use plan::{parse_target, EulerPlanArgs, PlanArgs};
pub use report::{HolonomyArgs, RectangleArgs};
pub use roll::{IntegratorArg, RollArgs};

use anyhow::Result;
use clap::{Args, Subcommand};
use holonomy::Direction;

/// Arguments of `rollstack sphere`.
#[derive(Debug, Args)]
pub struct SphereArgs {
    /// Which computation.
    #[command(subcommand)]
    pub command: SphereCommand,
}

/// The subcommands of `rollstack sphere`.
#[derive(Debug, Subcommand)]
pub enum SphereCommand {
    /// Holonomy of one rectangle (2.4.2), (2.4.6), (B.1.2).
    Holonomy(HolonomyArgs),
    /// Every rectangle (φ2 in [0, 3π]) that produces a target rotation (App. C).
    Plan(PlanArgs),
    /// Three rectangles through the Euler angles of a rotation (§2.5).
    EulerPlan(EulerPlanArgs),
    /// Integrate the rolling constraint along a rectangle, polygon or circle (2.3.4).
    Roll(RollArgs),
}

/// Runs `rollstack sphere ...`.
///
/// # Errors
/// Bad input, or a file that cannot be written.
pub fn run(args: &SphereArgs) -> Result<()> {
    match &args.command {
        SphereCommand::Holonomy(a) => report::run(a),
        SphereCommand::Plan(a) => plan::run_plan(a),
        SphereCommand::EulerPlan(a) => plan::run_euler_plan(a),
        SphereCommand::Roll(a) => roll::run(a),
    }
}

/// The direction of travel the `--cw` flag names.
fn direction(cw: bool) -> Direction {
    if cw {
        Direction::Cw
    } else {
        Direction::Ccw
    }
}
