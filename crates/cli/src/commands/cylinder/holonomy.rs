//! `rollstack cylinder holonomy rectangle|circle`: Δφ when P traces a rectangle or a
//! circle, checked by rolling along the path ([`cylinders::studies::holonomy`]).

use crate::output::{ensure_dir, print_json, write_csv, write_run_json};
use anyhow::{Context, Result};
use clap::{Args, Subcommand, ValueEnum};
use cylinders::holonomy::{CirclePath, Direction, PathCase, RectanglePath};
use cylinders::kinematics::{check_point_contact, Cylinder};
use cylinders::rolling::{RollingTrace, Sample};
use cylinders::studies::holonomy::{circle_report, plan_view, rectangle_report, RollSettings};
use cylinders::CylinderError;
use figures::cylinders::plot_trace;
use input::text::{parse_finite, Angle, RotationAngle};
use input::InputError;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Arguments of `rollstack cylinder holonomy`.
#[derive(Debug, Args)]
pub struct HolonomyArgs {
    /// The path traced by the contact point P.
    #[command(subcommand)]
    pub path: HolonomyPath,
}

/// The two paths of §3.4.
#[derive(Debug, Subcommand)]
pub enum HolonomyPath {
    /// P traces a rectangle of sides rφ1/2, rφ2/2: the nine-rotation product (3.4.3).
    Rectangle(RectangleArgs),
    /// P traces a circle of radius ℓ, (3.4.10)–(3.4.16).
    Circle(CircleArgs),
}

/// Case I (e′2 points out of the path) or II (in).
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum CaseArg {
    /// e′2 outward: Δφ > 0 counter-clockwise.
    #[value(name = "I", alias = "i", alias = "1")]
    One,
    /// e′2 inward: Δφ < 0 counter-clockwise.
    #[value(name = "II", alias = "ii", alias = "2")]
    Two,
}

impl From<CaseArg> for PathCase {
    fn from(c: CaseArg) -> Self {
        match c {
            CaseArg::One => PathCase::I,
            CaseArg::Two => PathCase::II,
        }
    }
}

/// The direction of travel the `--cw` flag names.
fn direction(cw: bool) -> Direction {
    if cw {
        Direction::Clockwise
    } else {
        Direction::CounterClockwise
    }
}

/// Arguments of `rollstack cylinder holonomy rectangle`.
#[derive(Debug, Args)]
pub struct RectangleArgs {
    /// Inclination ϑ, in (0, π/2), rad (`pi/10` accepted).
    #[arg(long, allow_hyphen_values = true)]
    pub theta: RotationAngle,
    /// φ1 > 0: a side of the rectangle is rφ1/2 long (rad of spin).
    #[arg(long, allow_hyphen_values = true)]
    pub phi1: Angle,
    /// φ2 > 0: the other side is rφ2/2 long (rad of spin).
    #[arg(long, allow_hyphen_values = true)]
    pub phi2: Angle,
    /// Start point S on the first side, s in [0, 1] (Figure 3.9).
    #[arg(long, value_parser = parse_finite, default_value_t = 0.0, allow_hyphen_values = true)]
    pub s: f64,
    /// Case I (e′2 outward) or II (inward).
    #[arg(long = "case", value_enum, default_value = "I")]
    pub case: CaseArg,
    /// Travel clockwise; default counter-clockwise.
    #[arg(long)]
    pub cw: bool,
    /// Initial precession ψ0, rad (sets ₀e3 of (3.4.4)).
    #[arg(long, allow_hyphen_values = true, default_value = "0")]
    pub psi0: RotationAngle,
    /// Aspect ratio r/h of the cylinder, for the rolled traces only (lengths are in units
    /// of r; default 0.12, not the 0.1 of `statics` and `support`: Figure 3.10's
    /// h = 8.3333 r).
    #[arg(long, default_value_t = 0.12, value_parser = parse_finite, allow_hyphen_values = true)]
    pub r_over_h: f64,
    /// The old form of `--r-over-h`: the height in units of r, h/r = 1/(r/h).
    #[arg(long, hide = true, conflicts_with = "r_over_h", value_parser = parse_finite, allow_hyphen_values = true)]
    pub h_over_r: Option<f64>,
    /// Largest rotation per integration step of the rolled check, rad.
    #[arg(long, value_parser = parse_finite, default_value_t = 1e-3, allow_hyphen_values = true)]
    pub max_step: f64,
    /// Print one JSON object on stdout.
    #[arg(long)]
    pub json: bool,
    /// Write rectangle_trace.csv, rectangle_trace.png (Figure 3.10) and run.json here.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// The rolled check of the command line: a sample every 20 steps, `--max-step` checked
/// here so that its error names the flag.
fn settings(max_step: f64) -> Result<RollSettings> {
    Ok(RollSettings {
        max_step: input::positive("--max-step", max_step)?,
        record_every: 20,
    })
}

/// The library's refusals that name its own parameters, under the flags: a path too long
/// for `--max-step` (the library names its `max_step`, but the path's length comes from
/// `path_flags` as much) and a trace that overflows at a `--theta` a few ulps from 0 or
/// 90° (the library names its ϑ).
fn name_flags(e: CylinderError, path_flags: &str) -> anyhow::Error {
    match e {
        CylinderError::Input(InputError::TooLarge {
            value,
            needed,
            what,
            limit,
            ..
        }) => anyhow::anyhow!(
            "{path_flags} with --max-step {} need {needed:.1e} {what}, more than the \
             {limit:.0e} allowed: take a shorter path or a larger --max-step",
            input::Short(value)
        ),
        CylinderError::NotFinite(theta) => anyhow::anyhow!(
            "--theta {}° ({} rad) is too close to 0° or 90° for double precision: the \
             rolled trace is not finite",
            super::short(theta.to_degrees()),
            super::short(theta)
        ),
        e => e.into(),
    }
}

pub(super) fn run_rectangle(a: &RectangleArgs) -> Result<()> {
    let start = Instant::now();
    // Checked here so that the errors name the flags, not the library's ϑ, φ1, φ2, s.
    let theta = check_point_contact(super::check_inclination(a.theta.0)?)?;
    let (phi1, phi2) = (
        input::positive("--phi1", a.phi1.0)?,
        input::positive("--phi2", a.phi2.0)?,
    );
    let s = input::in_range("--s", a.s, 0.0..=1.0, "[0, 1]")?;
    let path = RectanglePath::new(phi1, phi2, s, a.case.into(), direction(a.cw))?;
    let psi0 = a.psi0.0;
    let h_over_r = super::height(1.0, a.h_over_r, Some(a.r_over_h))?;
    let cylinder = Cylinder::new(1.0, h_over_r)?;
    let (rep, trace) = rectangle_report(&cylinder, theta, &path, psi0, settings(a.max_step)?)
        .map_err(|e| name_flags(e, "--phi1 and --phi2"))?;
    if let Some(dir) = &a.out {
        ensure_dir(dir)?;
        let title = format!(
            "Fig. 3.10: P traces a rectangle, Δφ = {:.4} rad",
            rep.delta_phi
        );
        write_trace(dir, "rectangle_trace", &trace, &title)?;
        write_run_json(
            dir,
            "cylinder holonomy rectangle",
            &serde_json::json!({"theta": theta, "phi1": path.phi1, "phi2": path.phi2, "s": path.s,
                "case": path.case.name(), "cw": a.cw, "psi0": psi0, "r_over_h": 1.0 / h_over_r}),
            &serde_json::json!({"total_s": start.elapsed().as_secs_f64()}),
        )?;
    }
    if a.json {
        return print_json(&rep);
    }
    println!("{}", rep.summary(&path));
    Ok(())
}

/// Arguments of `rollstack cylinder holonomy circle`.
#[derive(Debug, Args)]
#[command(group = clap::ArgGroup::new("height").required(true).args(["h", "r_over_h"]))]
pub struct CircleArgs {
    /// Radius ℓ of the circle traced by P (same unit as --r and --h).
    #[arg(long, value_parser = parse_finite, allow_hyphen_values = true)]
    pub ell: f64,
    /// Inclination ϑ, in (0, π/2), rad (`pi/10` accepted).
    #[arg(long, allow_hyphen_values = true)]
    pub theta: RotationAngle,
    /// Height h of the cylinder (or give --r-over-h).
    #[arg(long, value_parser = parse_finite, allow_hyphen_values = true)]
    pub h: Option<f64>,
    /// Aspect ratio r/h of the cylinder, instead of --h (h = r / (r/h)).
    #[arg(long, value_parser = parse_finite, allow_hyphen_values = true)]
    pub r_over_h: Option<f64>,
    /// Radius r of the cylinder (the unit of ℓ and h by default).
    #[arg(long, value_parser = parse_finite, default_value_t = 1.0, allow_hyphen_values = true)]
    pub r: f64,
    /// Case I (e′2 outward) or II (inward).
    #[arg(long = "case", value_enum, default_value = "I")]
    pub case: CaseArg,
    /// Travel clockwise; default counter-clockwise.
    #[arg(long)]
    pub cw: bool,
    /// Largest rotation per integration step of the rolled check, rad.
    #[arg(long, value_parser = parse_finite, default_value_t = 1e-3, allow_hyphen_values = true)]
    pub max_step: f64,
    /// Print one JSON object on stdout.
    #[arg(long)]
    pub json: bool,
    /// Write circle_trace.csv, circle_trace.png (Figure 3.12) and run.json here.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

pub(super) fn run_circle(a: &CircleArgs) -> Result<()> {
    let start = Instant::now();
    let h = super::height(a.r, a.h, a.r_over_h)?;
    let cylinder = Cylinder::new(a.r, h)?;
    let theta = super::check_inclination(a.theta.0)?;
    // Checked here so that the error names the flag, not the library's ℓ.
    let ell = input::positive("--ell", a.ell)?;
    let path = CirclePath::new(ell, a.case.into(), direction(a.cw))?;
    let (rep, trace) = circle_report(&cylinder, theta, &path, settings(a.max_step)?)
        .map_err(|e| name_flags(e, "--ell"))?;
    if let Some(dir) = &a.out {
        ensure_dir(dir)?;
        let title = format!(
            "Fig. 3.12: P traces a circle, Δφ = {:.4} rad",
            rep.delta_phi
        );
        write_trace(dir, "circle_trace", &trace, &title)?;
        write_run_json(
            dir,
            "cylinder holonomy circle",
            &serde_json::json!({"ell": a.ell, "theta": theta, "h": h, "r": a.r,
                "case": path.case.name(), "cw": a.cw}),
            &serde_json::json!({"total_s": start.elapsed().as_secs_f64()}),
        )?;
    }
    if a.json {
        return print_json(&rep);
    }
    println!("{}", rep.summary(&path));
    Ok(())
}

/// Writes a rolling trace as `{name}.csv` (t, centre, P, rim point X, φ) and a plan-view
/// `{name}.png` with the traces of P (i) and X (ii), the start S and the rim point's
/// start A and end B.
///
/// # Errors
/// When a file cannot be written.
pub fn write_trace(dir: &Path, name: &str, trace: &RollingTrace, title: &str) -> Result<()> {
    write_csv(
        &dir.join(format!("{name}.csv")),
        &Sample::CSV_HEADER,
        trace.samples.iter().map(Sample::csv_cells),
    )?;
    let view = plan_view(trace).context("empty trace")?;
    plot_trace(&dir.join(format!("{name}.png")), view, title)?;
    Ok(())
}
