//! The solver core's figures: the rotating bouncing ball of Capobianco et al. (2021)
//! and work-precision diagrams.

use crate::numerics::{Numerics, Step};
use crate::plot::{LinePlot, Series, Style};
use crate::Result;
use blockstack::studies::work_precision::StackWorkPrecision;
use nsga::studies::asymptotic::ObservedOrder;
use nsga::studies::ball::{BallRun, BallSample, Scheme};
use nsga::studies::work_precision::WorkPrecision;
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

/// What the markers of a work-precision diagram say, for its title.
pub const FITTED_MARKERS: &str = "filled: the Δt of the fitted order";

/// One run of a work-precision diagram: (wall time, error, whether the scheme's order
/// was fitted through it).
pub type WorkPoint = (f64, f64, bool);

/// The series of one scheme of a work-precision diagram, in the `i`-th style: a line
/// through its runs in the order given with a filled marker at each, and open markers
/// over the runs its order was not fitted through (other contact events than the
/// reference). Wall times are floored at 1e-9 s and errors at 1e-16 for the log axes.
#[must_use]
pub fn work_precision_series(label: String, i: usize, points: &[WorkPoint]) -> Vec<Series> {
    let style = Style::nth(i);
    let at = |p: &WorkPoint| (p.0.max(1e-9), p.1.max(1e-16));
    let mut series =
        vec![Series::line_and_markers(label, points.iter().map(at).collect()).styled(style)];
    let open: Vec<(f64, f64)> = points.iter().filter(|p| !p.2).map(at).collect();
    if !open.is_empty() {
        series.push(Series::markers("", open).styled(style.hollow()));
    }
    series
}

/// A work-precision diagram: error against wall time on log–log axes (ticks on the
/// decades, [`crate::axis`]), one line with a marker per run for each scheme and ρ∞, in
/// the order of the study's orders, labelled with its observed order; open markers
/// where the order was not fitted ([`work_precision_series`]).
///
/// # Errors
/// An unwritable file.
pub fn plot_work_precision(path: &Path, title: &str, study: &WorkPrecision) -> Result<()> {
    let mut plot = LinePlot::new(
        format!("{title} ({FITTED_MARKERS})"),
        "wall time [s]",
        "error [m]",
    );
    plot.log = (true, true);
    for (i, config) in study.orders.iter().enumerate() {
        let label = match (config.scheme, config.rho_inf) {
            (Scheme::Nsga, Some(r)) => format!("NSGA rho_inf = {r}"),
            (Scheme::Nsga, None) => "NSGA".to_owned(),
            (Scheme::Moreau, _) => "Moreau-Jean".to_owned(),
        };
        let pts: Vec<WorkPoint> = study
            .rows
            .iter()
            .filter(|r| r.rho_inf == config.rho_inf && r.scheme == config.scheme)
            .map(|r| (r.wall_time_s, r.error, r.fitted))
            .collect();
        let label = format!("{label}, order {}", order_label(&config.order));
        for series in work_precision_series(label, i, &pts) {
            plot = plot.with(series);
        }
    }
    plot.save(path, (1000, 700))
}

/// One run of a study of both schemes, for [`both_schemes_series`]: its scheme, solver
/// time, error (none when it failed) and whether its scheme's order was fitted through it.
pub type SchemeRun = (Scheme, f64, Option<f64>, bool);

/// The series of NSGA's and Moreau–Jean's `runs` (failed runs left out), each with its
/// observed order of `orders` (NSGA's, Moreau–Jean's) in its label
/// ([`work_precision_series`]).
#[must_use]
pub fn both_schemes_series(runs: &[SchemeRun], orders: [&ObservedOrder; 2]) -> Vec<Series> {
    [(Scheme::Nsga, "NSGA"), (Scheme::Moreau, "Moreau-Jean")]
        .into_iter()
        .zip(orders)
        .enumerate()
        .flat_map(|(i, ((scheme, name), order))| {
            let points: Vec<WorkPoint> = runs
                .iter()
                .filter(|r| r.0 == scheme)
                .filter_map(|r| r.2.map(|e| (r.1, e, r.3)))
                .collect();
            let label = format!("{name}, order {}", order_label(order));
            work_precision_series(label, i, &points)
        })
        .collect()
}

/// An observed order for a legend: `2.27` or `none (not in the asymptotic range)`.
#[must_use]
pub fn order_label(order: &ObservedOrder) -> String {
    order.order().map_or_else(
        || "none (not in the asymptotic range)".to_owned(),
        |p| format!("{p:.2}"),
    )
}

/// The block-stack work-precision diagram: the error at the end time against solver
/// time, log–log, one line with a marker per run for each scheme (failed runs left out),
/// open markers where the order was not fitted ([`work_precision_series`]).
///
/// # Errors
/// An unwritable file.
pub fn plot_stack_work_precision(path: &Path, study: &StackWorkPrecision) -> Result<()> {
    let title = stack_work_precision_title(study);
    let mut plot = LinePlot::new(&title, "wall time [s]", "error [length unit, rad]");
    plot.log = (true, true);
    let runs: Vec<SchemeRun> = study
        .rows
        .iter()
        .map(|r| (r.scheme, r.wall_time_s, r.error, r.fitted))
        .collect();
    for series in both_schemes_series(&runs, [&study.orders.nsga, &study.orders.moreau]) {
        plot = plot.with(series);
    }
    plot.save(path, (1000, 700))
}

/// The block-stack diagram's title, with the caption of its runs under it: the range of
/// Δt from the largest to the smallest and the benchmark's prox (both schemes use it).
#[must_use]
pub fn stack_work_precision_title(study: &StackWorkPrecision) -> String {
    let headline = format!(
        "Work-precision, {} (error at t = {} against Δt = {:.2e}; {FITTED_MARKERS})",
        study.system.name(),
        study.system.t_end(),
        study.reference_dt
    );
    let dts = study.rows.iter().map(|r| r.dt);
    let largest = dts.clone().fold(f64::NAN, f64::max);
    let smallest = dts.fold(f64::NAN, f64::min);
    match study.system.scene(study.reference_dt) {
        Ok(scene) if largest.is_finite() => Numerics {
            rule: None,
            step: Step::Range(largest, smallest),
            prox: scene.solver.prox,
        }
        .under(&headline),
        _ => headline,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use blockstack::studies::work_precision::{stack_work_precision, StackBenchmark};

    #[test]
    fn the_block_stack_diagram_names_its_steps_and_prox() {
        let study = stack_work_precision(StackBenchmark::Block, &[8e-3, 4e-3], 2.0, 1).unwrap();
        assert_eq!(
            stack_work_precision_title(&study),
            format!(
                "Work-precision, block (error at t = 2 against Δt = 2.00e-3; {FITTED_MARKERS})\nΔt = 0.008 … 0.004, prox scaled (α = 1)"
            )
        );
    }
}
