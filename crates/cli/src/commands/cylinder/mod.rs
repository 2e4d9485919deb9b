//! `rollstack cylinder support|statics|holonomy|frobenius|pair|work-precision`: the
//! inclined rolling cylinder of Ch. 3 (App. D, E, F), corrected per ERRATA 8–15, and the
//! transport of a touching pair (§3.6) with its speed against error.
//!
//! Forces are divided by mg, angles are radians (`30deg`, `pi/10` accepted), lengths are
//! in any one unit (the cylinder's radius r for the holonomy examples). Every number
//! printed, its text and the cells of the CSV files come from [`cylinders::studies`];
//! this module reads the flags and writes the files (docs/cli.md).

mod frobenius;
mod guard;
mod holonomy;
mod pair;
mod statics;
mod support;
pub mod sweep;
mod work_precision;

pub use frobenius::{ConfigArg, FrobeniusArgs, SystemArg};
pub use holonomy::{CaseArg, CircleArgs, HolonomyArgs, HolonomyPath, RectangleArgs};
pub use pair::PairArgs;
pub use statics::StaticsArgs;
pub use support::SupportArgs;
pub use work_precision::WorkPrecisionArgs;

use anyhow::Result;
use clap::{Args, Subcommand};

/// Arguments of `rollstack cylinder`.
#[derive(Debug, Args)]
pub struct CylinderArgs {
    /// Which computation.
    #[command(subcommand)]
    pub command: CylinderCommand,
}

/// The subcommands of `rollstack cylinder`.
#[derive(Debug, Subcommand)]
pub enum CylinderCommand {
    /// Support forces of a steadily rolling inclined cylinder at one inclination (§3.3).
    Support(SupportArgs),
    /// The support-force curves of Figures 3.3, 3.4, 3.5, 3.7 and 3.8 (CSV + PNG).
    Statics(StaticsArgs),
    /// Holonomy Δφ when the contact point traces a rectangle or a circle (§3.4).
    Holonomy(HolonomyArgs),
    /// Frobenius integrability test of the rolling constraints, numerically (App. D, F).
    Frobenius(FrobeniusArgs),
    /// The transport of two touching cylinders held at their tops, stepped by nsga
    /// (§3.6): forces, trajectory, views.
    Pair(PairArgs),
    /// Sweeps of the pair's transport (Figure 3.14), in parallel and shardable.
    #[command(subcommand)]
    Sweep(sweep::CylinderSweepCommand),
    /// Speed against error for the pair spun up, NSGA beside Moreau–Jean: error against
    /// a fine reference and the statics (3.3.10), constraint drift, against solver time.
    WorkPrecision(WorkPrecisionArgs),
}

/// Runs `rollstack cylinder ...`.
///
/// # Errors
/// Bad input, or a file that cannot be written.
pub fn run(args: &CylinderArgs) -> Result<()> {
    match &args.command {
        CylinderCommand::Support(a) => support::run(a),
        CylinderCommand::Statics(a) => statics::run(a),
        CylinderCommand::Holonomy(a) => match &a.path {
            HolonomyPath::Rectangle(r) => holonomy::run_rectangle(r),
            HolonomyPath::Circle(c) => holonomy::run_circle(c),
        },
        CylinderCommand::Frobenius(a) => frobenius::run(a),
        CylinderCommand::Pair(a) => pair::run(a),
        CylinderCommand::Sweep(c) => sweep::run(c),
        CylinderCommand::WorkPrecision(a) => work_precision::run(a),
    }
}

/// The height h of a cylinder of radius `r` given as `h` or as the ratio `r_over_h`
/// (h = r / (r/h)); `h` wins when both are given.
///
/// # Errors
/// When neither is given, or the ratio is not positive or so small that r / (r/h)
/// overflows (`--r-over-h 3.6e-309` gives h = ∞).
pub fn height(r: f64, h: Option<f64>, r_over_h: Option<f64>) -> Result<f64> {
    match (h, r_over_h) {
        (Some(h), _) => Ok(h),
        (None, Some(ratio)) => {
            input::positive("--r-over-h", ratio)?;
            let h = r / ratio;
            anyhow::ensure!(
                h.is_finite(),
                "--r-over-h {ratio} is too small: the height r / (r/h) = {r} / {ratio} overflows"
            );
            Ok(h)
        }
        (None, None) => anyhow::bail!("give the height as --h or --r-over-h"),
    }
}

/// Refuses a `--theta` of the pair outside its admissible range, naming the value in
/// degrees and radians since the user may have typed either (`--theta 5° (0.0873 rad) is
/// outside (11.31°, 90°) = (arctan(2r/h), π/2)`): the library states the range only as
/// (arctan(2r/h), π/2) and the value only in radians.
///
/// # Errors
/// ϑ outside (arctan(2r/h), π/2).
fn check_theta(theta: f64, cylinder: &cylinders::kinematics::Cylinder) -> Result<()> {
    let (lo, hi) = cylinders::transport::inclination_range(cylinder);
    anyhow::ensure!(
        theta > lo && theta < hi,
        "--theta {}° ({} rad) is outside ({}°, {}°) = (arctan(2r/h), π/2), the inclinations of the pair",
        short(theta.to_degrees()),
        short(theta),
        short(lo.to_degrees()),
        short(hi.to_degrees())
    );
    Ok(())
}

/// Refuses a `--theta` outside (0, π/2), where the cylinder touches the plane at one rim
/// point (§3.2), naming the flag and the value in degrees and radians since the user may
/// have typed either: the library names its ϑ, in radians only.
///
/// # Errors
/// ϑ outside (0, π/2).
fn check_inclination(theta: f64) -> Result<f64> {
    anyhow::ensure!(
        theta > 0.0 && theta < std::f64::consts::FRAC_PI_2,
        "--theta {}° ({} rad) is outside (0°, 90°): the point-contact assumption of §3.2 \
         fails (at 0° the base lies flat, at 90° the side does)",
        short(theta.to_degrees()),
        short(theta)
    );
    Ok(theta)
}

/// Refuses a pair's time step or number of steps under its flag, before the runs of each
/// inclination would refuse it under `--theta`.
///
/// # Errors
/// `--dt` not positive, `--steps` 0.
fn check_steps(dt: f64, steps: usize) -> Result<()> {
    input::positive("--dt", dt)?;
    anyhow::ensure!(steps >= 1, "--steps must be at least 1, got 0");
    Ok(())
}

/// A number with at most four decimals, without trailing zeros (`5`, `11.3099`), or in
/// scientific notation when it is too large or too small for that.
fn short(v: f64) -> String {
    if v != 0.0 && !(1e-4..1e9).contains(&v.abs()) {
        return format!("{}", input::Short(v));
    }
    let fixed = format!("{v:.4}");
    fixed.trim_end_matches('0').trim_end_matches('.').to_owned()
}
