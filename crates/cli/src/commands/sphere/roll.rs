//! `rollstack sphere roll`: rolling along a closed path against the closed form, and the
//! integrators' speed-vs-error study ([`holonomy::studies::roll`]).

use super::direction;
use crate::output::{ensure_dir, print_json, write_csv, write_run_json};
use anyhow::{bail, Context, Result};
use clap::{Args, ValueEnum};
use figures::sphere::{plot_study, plot_traces};
use holonomy::roll::RollSample;
use holonomy::studies::roll::{integrator_study, roll_report, ClosedPath, PathShape, StudyRow};
use holonomy::{Integrator, Rectangle};
use input::text::{parse_finite, parse_number_list, Angle};
use std::path::PathBuf;

/// The two integrators of `sphere roll`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum IntegratorArg {
    /// Exact flow of each segment (Lie-group exponential).
    Exact,
    /// RK4 on the unit quaternion.
    Rk4,
}

impl From<IntegratorArg> for Integrator {
    fn from(a: IntegratorArg) -> Self {
        match a {
            IntegratorArg::Exact => Integrator::Exact,
            IntegratorArg::Rk4 => Integrator::Rk4,
        }
    }
}

/// Arguments of `rollstack sphere roll`.
#[derive(Debug, Args)]
pub struct RollArgs {
    /// ϑ = W/R of the rectangle, rad (ignored with --circle or --polygon).
    #[arg(long, allow_hyphen_values = true, default_value = "4pi/3")]
    pub theta: Angle,
    /// φ1 = H1/R of the rectangle, rad.
    #[arg(long, allow_hyphen_values = true, default_value = "pi/2")]
    pub phi1: Angle,
    /// φ2 = H2/R of the rectangle, rad.
    #[arg(long, allow_hyphen_values = true, default_value = "3pi")]
    pub phi2: Angle,
    /// Travel clockwise (rectangle and circle).
    #[arg(long)]
    pub cw: bool,
    /// Roll around a circle of this radius (units of R) instead of the rectangle.
    #[arg(long, value_parser = parse_finite, conflicts_with = "polygon", allow_hyphen_values = true)]
    pub circle: Option<f64>,
    /// Roll around the closed polygon `x1,y1,x2,y2,...` (units of R) instead.
    #[arg(long, allow_hyphen_values = true)]
    pub polygon: Option<String>,
    /// Number of integration steps (at least one per side).
    #[arg(long, default_value_t = 400, allow_hyphen_values = true)]
    pub steps: usize,
    /// Integrator: `exact` (Lie-group exponential per segment) or `rk4` (on the quaternion).
    #[arg(long, value_enum, default_value = "exact")]
    pub integrator: IntegratorArg,
    /// Also run the speed-vs-error study of both integrators (roll_study.csv/png in --out).
    #[arg(long)]
    pub study: bool,
    /// Print one JSON object on stdout.
    #[arg(long)]
    pub json: bool,
    /// Write roll.csv (trajectory), roll_traces.png (Figure 2.1) and run.json here.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

impl RollArgs {
    /// The path the flags name: the circle, else the polygon, else the rectangle.
    fn shape(&self) -> Result<PathShape> {
        let direction = direction(self.cw);
        if let Some(radius) = self.circle {
            return Ok(PathShape::Circle { radius, direction });
        }
        if let Some(text) = &self.polygon {
            let v = parse_number_list(text)
                .map_err(anyhow::Error::msg)
                .context("--polygon")?;
            if v.len() < 4 || v.len() % 2 != 0 {
                bail!("--polygon needs an even number (at least 4) of coordinates x1,y1,x2,y2,...");
            }
            return Ok(PathShape::Polygon(
                v.chunks(2).map(|c| [c[0], c[1]]).collect(),
            ));
        }
        let r = Rectangle::new(self.theta.0, self.phi1.0, self.phi2.0, direction)?;
        Ok(PathShape::Rectangle(r))
    }
}

pub(super) fn run(a: &RollArgs) -> Result<()> {
    let closed = ClosedPath::new(&a.shape()?)?;
    let (rep, traj) = roll_report(&closed, a.integrator.into(), a.steps)?;
    let study = a.study.then(integrator_study).transpose()?;
    let label = &closed.label;
    if let Some(dir) = &a.out {
        ensure_dir(dir)?;
        let csv = traj.samples.iter().map(RollSample::csv_cells);
        write_csv(&dir.join("roll.csv"), &RollSample::CSV_HEADER, csv)?;
        plot_traces(
            &dir.join("roll_traces.png"),
            &traj,
            &format!("Top view of the traces of C (i) and X (ii): {label}"),
        )?;
        if let Some(rows) = &study {
            let csv = rows.iter().map(StudyRow::csv_cells);
            write_csv(&dir.join("roll_study.csv"), &StudyRow::CSV_HEADER, csv)?;
            plot_study(&dir.join("roll_study.png"), rows)?;
        }
        write_run_json(
            dir,
            "sphere roll",
            &serde_json::json!({"path": label, "steps": a.steps, "integrator": rep.integrator}),
            &serde_json::json!({"integration_s": rep.wall_time_s}),
        )?;
    }
    if a.json {
        return print_json(&rep);
    }
    println!("{}", rep.summary(label, study.as_deref()));
    Ok(())
}
