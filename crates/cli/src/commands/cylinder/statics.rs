//! `rollstack cylinder statics`: the support-force curves of Figures 3.3, 3.4, 3.5, 3.7
//! and 3.8 as CSV and PNG ([`cylinders::studies::statics`]).

use crate::output::{ensure_dir, write_csv, write_run_json};
use anyhow::Result;
use clap::Args;
use cylinders::studies::statics::{statics_figures, NormalForceRow};
use figures::cylinders::plot_statics;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Arguments of `rollstack cylinder statics`.
#[derive(Debug, Args)]
pub struct StaticsArgs {
    /// Aspect ratio r/h of Figures 3.3, 3.5, 3.7, 3.8 (dimensionless, ≥ 0).
    #[arg(long, default_value_t = 0.1, allow_hyphen_values = true)]
    pub r_over_h: f64,
    /// Friction coefficient μ of Figures 3.3, 3.4, 3.7, 3.8 (dimensionless, ≥ 0).
    #[arg(long, default_value_t = 0.2, allow_hyphen_values = true)]
    pub mu: f64,
    /// Number of inclinations sampled in (0, 90°).
    #[arg(long, default_value_t = 721)]
    pub points: usize,
    /// Write fig3_3.csv … fig3_8.csv, their PNGs and run.json here.
    #[arg(long)]
    pub out: PathBuf,
}

pub(super) fn run(a: &StaticsArgs) -> Result<()> {
    let start = Instant::now();
    ensure_dir(&a.out)?;
    let files = write_statics(&a.out, a.r_over_h, a.mu, a.points)?;
    write_run_json(
        &a.out,
        "cylinder statics",
        &serde_json::json!({"r_over_h": a.r_over_h, "mu": a.mu, "points": a.points}),
        &serde_json::json!({"total_s": start.elapsed().as_secs_f64()}),
    )?;
    println!("wrote {} files into {}", files.len() + 1, a.out.display());
    Ok(())
}

/// A CSV cell: the number, or empty when there is none.
fn cell(v: Option<f64>) -> String {
    v.filter(|v| v.is_finite())
        .map_or_else(String::new, |v| v.to_string())
}

/// The N/mg cells of a row: (3.3.8)₊, (3.3.10), (3.3.8)₋.
fn n_cells(r: &NormalForceRow) -> [String; 3] {
    [r.n_over_mg_plus, r.n_over_mg_smooth, r.n_over_mg_minus].map(cell)
}

/// The N/mg columns.
const N_COLUMNS: [&str; 3] = ["n_over_mg_plus", "n_over_mg_smooth", "n_over_mg_minus"];

/// The files [`write_statics`] writes.
const FILES: [&str; 9] = [
    "fig3_3.csv",
    "fig3_3.png",
    "fig3_4.csv",
    "fig3_4.png",
    "fig3_5.csv",
    "fig3_5.png",
    "fig3_7_fig3_8.csv",
    "fig3_7.png",
    "fig3_8.png",
];

/// Writes the five statics figures (CSV and PNG) into `dir`; returns the file names
/// written.
///
/// # Errors
/// Bad input or a file that cannot be written.
pub fn write_statics(dir: &Path, r_over_h: f64, mu: f64, points: usize) -> Result<Vec<String>> {
    anyhow::ensure!(points >= 3, "--points must be at least 3");
    let fig = statics_figures(r_over_h, mu, points)?;
    let rows = fig.figure_3_3.rows.iter().map(|r| {
        let theta = [r.theta, r.theta.to_degrees()].map(|v| v.to_string());
        [theta.to_vec(), n_cells(r).to_vec()].concat()
    });
    let header = [&["theta", "theta_deg"][..], &N_COLUMNS].concat();
    write_csv(&dir.join("fig3_3.csv"), &header, rows)?;
    for (name, family) in [("fig3_4", &fig.figure_3_4), ("fig3_5", &fig.figure_3_5)] {
        let rows = family.iter().flat_map(|c| {
            c.rows.iter().map(|r| {
                let keys = [c.r_over_h, c.mu, r.theta].map(|v| v.to_string());
                [keys.to_vec(), n_cells(r).to_vec()].concat()
            })
        });
        let header = [&["r_over_h", "mu", "theta"][..], &N_COLUMNS].concat();
        write_csv(&dir.join(format!("{name}.csv")), &header, rows)?;
    }
    let rows = fig.minimum_force.iter().map(|r| {
        let m = r.minimum;
        vec![
            r.theta.to_string(),
            r.theta.to_degrees().to_string(),
            r.unconstrained[0].to_string(),
            r.unconstrained[1].to_string(),
            u8::from(r.admissible).to_string(),
            cell(m.map(|m| m.f3_over_mg)),
            cell(m.map(|m| m.f_over_mg)),
            cell(m.map(|m| m.norm_over_mg)),
            m.map_or_else(|| "none".to_owned(), |m| m.case.name().to_owned()),
        ]
    });
    write_csv(
        &dir.join("fig3_7_fig3_8.csv"),
        &[
            "theta",
            "theta_deg",
            "circle_f3_over_mg",
            "circle_f_over_mg",
            "satisfies_3_3_17",
            "min_f3_over_mg",
            "min_f_over_mg",
            "min_norm_over_mg",
            "case",
        ],
        rows,
    )?;
    plot_statics(dir, &fig)?;
    Ok(FILES.map(String::from).to_vec())
}
