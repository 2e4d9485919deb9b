//! `rollstack cylinder frobenius`: the Frobenius integrability test of the rolling
//! constraints ([`cylinders::studies::frobenius`]).

use crate::output::print_json;
use anyhow::Result;
use clap::{Args, ValueEnum};
use cylinders::kinematics::Cylinder;
use cylinders::studies::frobenius::{
    integrability_report, ConstraintSystem, FrobeniusCase, PairConfiguration,
};
use cylinders::CylinderError;
use input::text::{parse_finite, RotationAngle};

/// The constraint systems of `cylinder frobenius`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum SystemArg {
    /// One cylinder: 6 coordinates, v_P = 0 (3 constraints), App. D.
    Single,
    /// The pair: 12 coordinates, Π1..Π7 of (3.5.13).
    Pair7,
    /// The pair: 12 coordinates, the nine rolling constraints of App. F.
    Pair9,
}

impl From<SystemArg> for ConstraintSystem {
    fn from(s: SystemArg) -> Self {
        match s {
            SystemArg::Single => Self::Single,
            SystemArg::Pair7 => Self::Pair7,
            SystemArg::Pair9 => Self::Pair9,
        }
    }
}

/// Where the pair is evaluated.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ConfigArg {
    /// The touching configuration shifted by fixed irregular offsets (not touching).
    Generic,
    /// Touching: both on the plane, leaning towards each other, axes r1 + r2 apart.
    Touching,
}

impl From<ConfigArg> for PairConfiguration {
    fn from(c: ConfigArg) -> Self {
        match c {
            ConfigArg::Generic => Self::Generic,
            ConfigArg::Touching => Self::Touching,
        }
    }
}

/// Arguments of `rollstack cylinder frobenius`.
#[derive(Debug, Args)]
pub struct FrobeniusArgs {
    /// Which constraint system.
    #[arg(long, value_enum, default_value = "single")]
    pub system: SystemArg,
    /// Configuration of the pair.
    #[arg(long, value_enum, default_value = "generic")]
    pub config: ConfigArg,
    /// Inclination ϑ of the cylinders, in (0, π/2), rad.
    #[arg(long, allow_hyphen_values = true, default_value = "0.4")]
    pub theta: RotationAngle,
    /// Heading (precession ψ of cylinder I), rad.
    #[arg(long, allow_hyphen_values = true, default_value = "0.5")]
    pub heading: RotationAngle,
    /// Where the cylinders touch along their axes, from the centre (m* = n*), metres
    /// (default 0.3); for --system pair7 and pair9 only.
    #[arg(long, value_parser = parse_finite, allow_hyphen_values = true)]
    pub contact_at: Option<f64>,
    /// Radius r of each cylinder, metres (default: the gas cylinder of §3.6).
    #[arg(long, value_parser = parse_finite, default_value_t = 0.1143, allow_hyphen_values = true)]
    pub r: f64,
    /// Height h of each cylinder, metres.
    #[arg(long, value_parser = parse_finite, default_value_t = 1.2954, allow_hyphen_values = true)]
    pub h: f64,
    /// Aspect ratio r/h of each cylinder, instead of --h (h = r / (r/h)).
    #[arg(long, conflicts_with = "h", value_parser = parse_finite, allow_hyphen_values = true)]
    pub r_over_h: Option<f64>,
    /// Print one JSON object on stdout.
    #[arg(long)]
    pub json: bool,
}

/// Refuses a `--contact-at` off the cylinders' length: they touch within (−h/2, h/2) of
/// their centres, given in metres as the flag is.
///
/// # Errors
/// |`at`| ≥ h/2.
fn check_contact_at(at: f64, h: f64) -> Result<()> {
    anyhow::ensure!(
        at.abs() < 0.5 * h,
        "--contact-at {} m is outside (−h/2, h/2) = ({}, {}) m: the cylinders touch along \
         their length",
        super::short(at),
        super::short(-0.5 * h),
        super::short(0.5 * h)
    );
    Ok(())
}

pub(super) fn run(a: &FrobeniusArgs) -> Result<()> {
    let system = a.system.into();
    // Checked here so that the errors name the flags, not the library's ϑ, r, h and
    // contact position.
    super::check_inclination(a.theta.0)?;
    input::positive("--r", a.r)?;
    if a.r_over_h.is_none() {
        input::positive("--h", a.h)?;
    }
    let h = super::height(a.r, a.r_over_h.is_none().then_some(a.h), a.r_over_h)?;
    if let (Some(at), false) = (a.contact_at, a.system == SystemArg::Single) {
        check_contact_at(at, h)?;
    }
    let rep = integrability_report(&FrobeniusCase {
        system,
        configuration: a.config.into(),
        cylinder: Cylinder::new(a.r, h)?,
        theta: a.theta.0,
        heading: a.heading.0,
        contact_at: a.contact_at,
    })
    .map_err(|e| match e {
        CylinderError::ContactOfSingle => anyhow::anyhow!(
            "--contact-at is where the two cylinders of --system pair7 or pair9 touch; \
             --system single has one cylinder: leave --contact-at out"
        ),
        e => e.into(),
    })?;
    if a.json {
        return print_json(&rep);
    }
    println!("{}", rep.summary(system));
    Ok(())
}
