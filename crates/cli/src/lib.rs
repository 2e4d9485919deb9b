//! The `rollstack` command line, as a library so that its pieces can be tested.
//!
//! Layout: one module per command family in [`commands`], the main job in [`tour`], and
//! the shared plumbing every command uses: atomic output files and JSON ([`output`]),
//! progress bars ([`progress`]) and sharded parallel sweeps ([`sweep`]). User values
//! written as text (`3pi/2`, `90deg`, `A:B:STEP`) are read by [`input::text`]; every
//! picture is drawn by the [`figures`] crate.
//!
//! The library crates compute; this crate parses, calls them, and writes files. Its
//! pieces are public so that they can be tested, and so that a command can be run from
//! Rust exactly as from a shell:
//!
//! ```
//! use clap::Parser;
//!
//! let cli = rollstack_cli::Cli::try_parse_from([
//!     "rollstack", "rotation", "--from", "axis-angle", "--values", "0,0,1,90deg", "--json",
//! ])?;
//! rollstack_cli::run(cli)?; // prints the rotation in every representation as JSON
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![warn(missing_docs)]

pub mod commands;
pub mod examples;
pub mod output;
pub mod progress;
pub mod sweep;
pub mod tour;

use clap::{Parser, Subcommand};

/// Dynamics of constrained rigid bodies: rolling spheres and cylinders, stacks of blocks.
///
/// Angles are radians unless written as `90deg` or `3pi/2`. Lengths are in the units of
/// the model (the sphere's radius R, the cylinder's radius r, block widths).
#[derive(Debug, Parser)]
#[command(name = "rollstack", version)]
pub struct Cli {
    /// What to run.
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands of `rollstack`.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Convert one rotation between axis-angle, quaternion, matrix and all 12 Euler sets.
    Rotation(commands::rotation::RotationArgs),
    /// The rolling sphere: rectangle holonomy, path planning, Euler paths, rolling (Ch. 2).
    Sphere(commands::sphere::SphereArgs),
    /// The nonsmooth generalized-α solver core: bouncing ball, work-precision (Capobianco 2021).
    Nsga(commands::nsga::NsgaArgs),
    /// A stack of blocks on a driven base (Ch. 4, App. G–I): simulations, sweeps, Painlevé analysis.
    Blocks(commands::blocks::BlocksArgs),
    /// Inclined rolling cylinders (Ch. 3, App. D–F): support forces, holonomy, Frobenius test.
    Cylinder(commands::cylinder::CylinderArgs),
    /// The main job: headline results of every system, as CSV, PNG and index.html.
    Tour(tour::TourArgs),
    /// Join the shards of a sweep (`--shard K/N` runs) into what one run writes.
    Merge(commands::cluster::MergeArgs),
    /// Write Slurm batch scripts that run a sweep as a job array and merge it.
    Slurm(commands::cluster::SlurmArgs),
}

/// Runs a parsed command line.
///
/// # Errors
/// Any failure of the command: bad input, a solver error, an unwritable file.
pub fn run(cli: Cli) -> anyhow::Result<()> {
    match cli.command {
        Command::Rotation(args) => commands::rotation::run(&args),
        Command::Sphere(args) => commands::sphere::run(&args),
        Command::Nsga(args) => commands::nsga::run(&args),
        Command::Blocks(args) => commands::blocks::run(&args),
        Command::Cylinder(args) => commands::cylinder::run(&args),
        Command::Tour(args) => tour::run(&args),
        Command::Merge(args) => commands::cluster::merge(&args),
        Command::Slurm(args) => commands::cluster::slurm(&args),
    }
}
