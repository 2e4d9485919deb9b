//! The solver core's figures: the rotating bouncing ball of Capobianco et al. (2021)
//! and work-precision diagrams.

use crate::plot::{LinePlot, Series};
use crate::Result;
use blockstack::studies::work_precision::StackWorkPrecision;
use nsga::studies::ball::{BallRun, BallSample, Scheme};
use nsga::studies::work_precision::WorkPrecisionRow;
use std::path::Path;

/// The ball's height y, its speed ẋ and the slip ẋ + Rφ̇ of its contact point against
/// time (`radius` is the ball's R).
///
/// # Errors
/// An unwritable file.
pub fn plot_ball(path: &Path, title: &str, run: &BallRun, radius: f64) -> Result<()> {
    let pts = |f: &dyn Fn(&BallSample) -> f64| {
        run.samples.iter().map(|s| (s.t, f(s))).collect::<Vec<_>>()
    };
    LinePlot::new(title, "t [s]", "y [m]; xdot, slip [m/s]")
        .with(Series::line("y", pts(&|s| s.q[1])))
        .with(Series::line("xdot", pts(&|s| s.u[0])))
        .with(Series::line(
            "slip xdot + R phidot",
            pts(&|s| s.u[0] + radius * s.u[2]),
        ))
        .save(path, (1000, 600))
}

/// A work-precision diagram: error against wall time on log–log axes (ticks on the
/// decades, [`crate::axis`]), one line with a marker per run for each scheme and ρ∞, in
/// the order the rows first name them. Errors are floored at 1e-16.
///
/// # Errors
/// An unwritable file.
pub fn plot_work_precision(path: &Path, title: &str, rows: &[WorkPrecisionRow]) -> Result<()> {
    let mut configs: Vec<(Scheme, Option<f64>)> = Vec::new();
    for r in rows {
        if !configs.contains(&(r.scheme, r.rho_inf)) {
            configs.push((r.scheme, r.rho_inf));
        }
    }
    let mut plot = LinePlot::new(title, "wall time [s]", "error [m]");
    plot.log = (true, true);
    for (scheme, rho) in configs {
        let label = match (scheme, rho) {
            (Scheme::Nsga, Some(r)) => format!("NSGA rho_inf = {r}"),
            (Scheme::Nsga, None) => "NSGA".to_owned(),
            (Scheme::Moreau, _) => "Moreau-Jean".to_owned(),
        };
        let pts: Vec<(f64, f64)> = rows
            .iter()
            .filter(|r| r.rho_inf == rho && r.scheme == scheme)
            .map(|r| (r.wall_time_s, r.error.max(1e-16)))
            .collect();
        plot = plot.with(Series::line_and_markers(label, pts));
    }
    plot.save(path, (1000, 700))
}

/// The block-stack work-precision diagram: the error at the end time against solver
/// time, log–log, one line with a marker per run for each scheme (failed runs left out).
///
/// # Errors
/// An unwritable file.
pub fn plot_stack_work_precision(path: &Path, study: &StackWorkPrecision) -> Result<()> {
    let title = format!(
        "Work-precision, {} (error at t = {} against Δt = {:.2e})",
        study.system.name(),
        study.system.t_end(),
        study.reference_dt
    );
    let mut plot = LinePlot::new(&title, "wall time [s]", "error [length unit, rad]");
    plot.log = (true, true);
    for (scheme, label) in [(Scheme::Nsga, "NSGA"), (Scheme::Moreau, "Moreau-Jean")] {
        let pts: Vec<(f64, f64)> = study
            .rows
            .iter()
            .filter(|r| r.scheme == scheme)
            .filter_map(|r| r.error.map(|e| (r.wall_time_s.max(1e-9), e.max(1e-16))))
            .collect();
        plot = plot.with(Series::line_and_markers(label, pts));
    }
    plot.save(path, (1000, 700))
}
