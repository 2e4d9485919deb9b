//! `rollstack sphere holonomy`: the holonomy report of one rectangle
//! ([`holonomy::studies::report`]).

use super::direction;
use crate::output::{ensure_dir, print_json, write_csv, write_run_json};
use anyhow::Result;
use clap::Args;
use figures::sphere::{plot_level_sets, plot_rectangles};
use holonomy::studies::plan::RectangleReport;
use holonomy::studies::report::{holonomy_report, HolonomySummary};
use holonomy::{PlacedRectangle, Rectangle};
use input::text::Angle;
use std::path::{Path, PathBuf};

/// The rectangle flags shared by `holonomy` and `roll`.
#[derive(Debug, Args)]
pub struct RectangleArgs {
    /// ϑ = W/R: side along A2, rad (`90deg`, `3pi/2` accepted).
    #[arg(long, allow_hyphen_values = true)]
    pub theta: Angle,
    /// φ1 = H1/R: start S measured from the corner along A1, rad, in [0, φ2].
    #[arg(long, allow_hyphen_values = true)]
    pub phi1: Angle,
    /// φ2 = H2/R: side along A1, rad.
    #[arg(long, allow_hyphen_values = true)]
    pub phi2: Angle,
    /// Travel clockwise (viewed from above); default counter-clockwise, the product (2.4.2).
    #[arg(long)]
    pub cw: bool,
}

impl RectangleArgs {
    fn rectangle(&self) -> Result<Rectangle> {
        let d = direction(self.cw);
        Ok(Rectangle::new(self.theta.0, self.phi1.0, self.phi2.0, d)?)
    }
}

/// Arguments of `rollstack sphere holonomy`.
#[derive(Debug, Args)]
pub struct HolonomyArgs {
    /// The rectangle.
    #[command(flatten)]
    pub rect: RectangleArgs,
    /// Print one JSON object on stdout.
    #[arg(long)]
    pub json: bool,
    /// Write holonomy.csv, the path (rectangle.png) and the level sets of ψ (Figure 2.5) here.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

pub(super) fn run(a: &HolonomyArgs) -> Result<()> {
    let r = a.rect.rectangle()?;
    let rep = holonomy_report(&r);
    if let Some(dir) = &a.out {
        write_files(dir, &rep.summary(&r))?;
    }
    if a.json {
        return print_json(&rep);
    }
    println!("{}", rep.summary(&r));
    Ok(())
}

/// holonomy.csv (the rectangle, ψ, s and the rows of S), rectangle.png, psi_level_sets.png
/// and run.json.
fn write_files(dir: &Path, summary: &HolonomySummary) -> Result<()> {
    ensure_dir(dir)?;
    let r = summary.rectangle;
    write_csv(
        &dir.join("holonomy.csv"),
        &HolonomySummary::CSV_HEADER,
        [summary.csv_cells()],
    )?;
    // The rectangle on its own: nothing to compare its holonomy with, so no error.
    let path = RectangleReport::new(&PlacedRectangle::at_origin(*r), 0.0, false);
    plot_rectangles(
        &dir.join("rectangle.png"),
        "Rectangular path of the centre (units of R)",
        &[path],
    )?;
    plot_level_sets(&dir.join("psi_level_sets.png"), Some((r.theta, r.phi2)))?;
    write_run_json(dir, "sphere holonomy", r, &serde_json::json!({}))
}
