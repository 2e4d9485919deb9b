//! `rollstack sphere plan` and `euler-plan`: the rectangles of the two planners
//! ([`holonomy::studies::plan`]).

use crate::output::{ensure_dir, print_json, write_csv, write_run_json};
use anyhow::{bail, Context, Result};
use clap::Args;
use figures::sphere::{plot_rectangle_panels, plot_rectangles};
use holonomy::euler_plan;
use holonomy::studies::plan::{euler_plan_report, plan_report, EulerPlanReport, RectangleReport};
use input::text::{parse_number_list, parse_rotation_angle_list, RotationAngle};
use nalgebra::{Rotation3, Vector3};
use rotations::{AxisAngle, EulerSet};
use std::path::PathBuf;
use std::time::Instant;

/// Arguments of `rollstack sphere plan`.
#[derive(Debug, Args)]
pub struct PlanArgs {
    /// Angle of the target rotation ψ, rad (`270deg`, `3pi/2` accepted).
    #[arg(long, allow_hyphen_values = true)]
    pub angle: RotationAngle,
    /// Axis of the target rotation, `X,Y,Z` on A1, A2, A3 (normalised; not zero).
    #[arg(long, allow_hyphen_values = true)]
    pub axis: String,
    /// Print one JSON object on stdout.
    #[arg(long)]
    pub json: bool,
    /// Write plan.csv and the rectangles (plan.png, cf. Figure 2.6) here.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// Arguments of `rollstack sphere euler-plan`.
#[derive(Debug, Args)]
pub struct EulerPlanArgs {
    /// Euler set: 3-2-3, 3-1-3, 3-2-1 or 3-1-2.
    #[arg(long)]
    pub set: String,
    /// The three Euler angles ν1,ν2,ν3, rad (`30deg`, `pi/4` accepted).
    #[arg(long, allow_hyphen_values = true)]
    pub angles: String,
    /// Print one JSON object on stdout.
    #[arg(long)]
    pub json: bool,
    /// Write euler_plan.csv and the three paths (euler_plan.png, cf. Figures 2.7–2.9) here.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// Parses `--angle` and `--axis` into a target rotation.
///
/// # Errors
/// A zero, non-finite or malformed axis.
pub fn parse_target(angle: f64, axis: &str) -> Result<Rotation3<f64>> {
    let v = parse_number_list(axis)
        .map_err(anyhow::Error::msg)
        .context("--axis")?;
    if v.len() != 3 {
        bail!(
            "--axis needs three comma-separated numbers X,Y,Z, got {}",
            v.len()
        );
    }
    Ok(AxisAngle::new(angle, Vector3::new(v[0], v[1], v[2]))
        .context("--axis")?
        .to_rotation())
}

pub(super) fn run_plan(a: &PlanArgs) -> Result<()> {
    let target = parse_target(a.angle.0, &a.axis)?;
    let start = Instant::now();
    let rep = plan_report(&target)?;
    let seconds = start.elapsed().as_secs_f64();
    if let Some(dir) = &a.out {
        ensure_dir(dir)?;
        let csv = rep.rectangles.iter().map(RectangleReport::plan_csv_cells);
        write_csv(
            &dir.join("plan.csv"),
            &RectangleReport::PLAN_CSV_HEADER,
            csv,
        )?;
        let title = format!(
            "{} rectangle(s) producing the rotation by ψ = {:.4} rad about ({}){}; dot: start S",
            rep.rectangles.len(),
            a.angle.0,
            a.axis,
            rep.shortest.map_or_else(String::new, |i| format!(
                "; the shortest, no. {}, thick in vermillion",
                i + 1
            ))
        );
        plot_rectangle_panels(&dir.join("plan.png"), &title, &rep.rectangles, rep.shortest)?;
        write_run_json(
            dir,
            "sphere plan",
            &serde_json::json!({"angle": a.angle.0, "axis": a.axis}),
            &serde_json::json!({"plan_s": seconds}),
        )?;
    }
    if a.json {
        return print_json(&rep);
    }
    println!("{rep}");
    Ok(())
}

pub(super) fn run_euler_plan(a: &EulerPlanArgs) -> Result<()> {
    let set = EulerSet::from_name(&a.set)?;
    let v = parse_rotation_angle_list(&a.angles)
        .map_err(anyhow::Error::msg)
        .context("--angles")?;
    if v.len() != 3 {
        bail!(
            "--angles needs three comma-separated angles, got {}",
            v.len()
        );
    }
    let rep = euler_plan_report(&euler_plan(set, [v[0], v[1], v[2]])?);
    if let Some(dir) = &a.out {
        ensure_dir(dir)?;
        write_csv(
            &dir.join("euler_plan.csv"),
            &EulerPlanReport::CSV_HEADER,
            rep.csv_rows(),
        )?;
        plot_rectangles(
            &dir.join("euler_plan.png"),
            &format!(
                "Three rectangles for the {} Euler angles (units of R)",
                rep.set
            ),
            &rep.rectangles,
        )?;
        write_run_json(
            dir,
            "sphere euler-plan",
            &serde_json::json!({"set": a.set, "angles": v}),
            &serde_json::json!({}),
        )?;
    }
    if a.json {
        return print_json(&rep);
    }
    println!("{rep}");
    Ok(())
}
