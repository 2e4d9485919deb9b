//! `rollstack cylinder support`: the steady support at one inclination
//! ([`cylinders::studies::support`]).

use crate::output::print_json;
use anyhow::Result;
use clap::Args;
use cylinders::studies::support::support_report;
use input::text::{parse_finite, RotationAngle};

/// Arguments of `rollstack cylinder support`.
#[derive(Debug, Args)]
pub struct SupportArgs {
    /// Inclination ϑ of the axis to the vertical, in (0, π/2), rad (`30deg` accepted).
    #[arg(long, allow_hyphen_values = true)]
    pub theta: RotationAngle,
    /// Aspect ratio r/h (radius over height, dimensionless, ≥ 0).
    #[arg(long, value_parser = parse_finite, default_value_t = 0.1, allow_hyphen_values = true)]
    pub r_over_h: f64,
    /// Static friction coefficient μ between cylinder and plane (dimensionless, ≥ 0).
    #[arg(long, value_parser = parse_finite, default_value_t = 0.2, allow_hyphen_values = true)]
    pub mu: f64,
    /// Mass m of the cylinder, kg: also give the forces in newtons (the /mg values times
    /// mg).
    #[arg(long, value_parser = parse_finite, allow_hyphen_values = true)]
    pub mass: Option<f64>,
    /// Gravity g, m/s², for the forces in newtons (only with --mass).
    #[arg(long, default_value_t = 9.81, value_parser = parse_finite, requires = "mass", allow_hyphen_values = true)]
    pub gravity: f64,
    /// Print one JSON object on stdout.
    #[arg(long)]
    pub json: bool,
}

pub(super) fn run(a: &SupportArgs) -> Result<()> {
    // Checked here so that the errors name the flags, not the library's ϑ, r/h, μ, mass.
    super::check_inclination(a.theta.0)?;
    input::non_negative("--r-over-h", a.r_over_h)?;
    input::non_negative("--mu", a.mu)?;
    if let Some(mass) = a.mass {
        input::positive("--mass", mass)?;
        input::positive("--gravity", a.gravity)?;
    }
    let mut rep = support_report(a.theta.0, a.r_over_h, a.mu)?;
    if let Some(mass) = a.mass {
        rep = rep.with_weight(mass, a.gravity)?;
    }
    if a.json {
        return print_json(&rep);
    }
    println!("{}", rep.summary(a.theta.0, a.r_over_h, a.mu));
    Ok(())
}
