//! The picture of a convergence study (`rollstack blocks converge`): the failure time
//! against Δt, the unperturbed runs at Δt/2^k joined by a line, and the ensemble of
//! perturbed runs at the finest Δt as a band between its earliest and its latest
//! failure time.

use crate::blocks::{with_bands, DrawnRun};
use crate::numerics::{Numerics, Step};
use crate::plot::{Dash, LinePlot, Marker, Series, Style, GUIDE_COLOR, PALETTE};
use crate::Result;
use blockstack::studies::convergence::verdict::VerdictKind;
use blockstack::studies::convergence::{ConvergenceReport, JobKind};
use nsga::Prox;
use std::path::Path;

/// A sweep row with `--convergence`, as its figure draws it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JudgedPoint {
    /// The swept parameter.
    pub x: f64,
    /// The plotted value at the finest level.
    pub y: f64,
    /// The plotted value's smallest and largest over the levels and the members.
    pub band: Option<(f64, f64)>,
    /// The verdict that marks it.
    pub verdict: VerdictKind,
}

/// The verdicts in the legend's order, each with its marker: hollow, in colours the
/// sweeps' own series (the first two of the palette) do not take.
const VERDICT_MARKERS: [(VerdictKind, Marker, usize); 4] = [
    (VerdictKind::Converged, Marker::Circle, 2),
    (VerdictKind::Chaotic, Marker::Triangle, 3),
    (VerdictKind::NonUnique, Marker::Square, 4),
    (VerdictKind::NotConverged, Marker::Diamond, 5),
];

/// `plot` with each judged row's band as a grey bar (labelled once, `band`) and a marker
/// at its finest level's value in the shape and colour of its verdict, one legend entry
/// per verdict present (`what`: the verdict's quantity, "failure time", "outcome").
#[must_use]
pub fn with_verdicts(
    mut plot: LinePlot,
    points: &[JudgedPoint],
    band: &str,
    what: &str,
) -> LinePlot {
    let bars = points
        .iter()
        .filter_map(|p| p.band.map(|(lo, hi)| (p.x, lo, hi)));
    plot = with_bands(plot, bars, band);
    for (verdict, marker, colour) in VERDICT_MARKERS {
        let at: Vec<(f64, f64)> = points
            .iter()
            .filter(|p| p.verdict == verdict)
            .map(|p| (p.x, p.y))
            .collect();
        if !at.is_empty() {
            let style = Style::color(PALETTE[colour]).marker(marker).hollow();
            let label = format!("finest Δt, {what} {verdict}");
            plot = plot.with(Series::markers(label, at).styled(style));
        }
    }
    plot
}

/// The failure time of the unperturbed runs against Δt (log Δt), the members' failure
/// times at the finest Δt as markers and their spread (the unperturbed finest run's
/// included) as a band across the plot; the title gives the verdict, the caption the
/// levels' Δt and `prox`, the prox choice ([`convergence_title`]). Left out with a note when no run failed.
///
/// # Errors
/// An unwritable file.
pub fn plot_convergence(
    path: &Path,
    report: &ConvergenceReport,
    scene: &str,
    prox: Prox,
) -> Result<DrawnRun> {
    let mut out = DrawnRun::default();
    let name = path
        .file_name()
        .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
    let failure = |kind: bool| {
        report
            .runs
            .iter()
            .filter(move |r| matches!(r.kind, JobKind::Level { .. }) == kind)
            .filter_map(|r| Some((r.dt, r.observed.failure_time?)))
            .collect::<Vec<_>>()
    };
    let (levels, members) = (failure(true), failure(false));
    if levels.is_empty() && members.is_empty() {
        out.notes
            .push(format!("no {name}: no run lost its support before its end"));
        return Ok(out);
    }
    let title = convergence_title(report, scene, prox);
    let mut plot = LinePlot::new(title, "Δt (model time)", "first loss of support t").with(
        Series::line_and_markers("unperturbed, Δt/2^k", levels.clone())
            .styled(Style::color(PALETTE[0])),
    );
    let finest = report.dts.last().copied().unwrap_or(f64::NAN);
    let band: Vec<f64> = levels
        .iter()
        .filter(|p| p.0 == finest)
        .chain(&members)
        .map(|p| p.1)
        .collect();
    if !members.is_empty() {
        plot = plot.with(
            Series::markers("perturbed, finest Δt", members)
                .styled(Style::color(PALETTE[1]).marker(Marker::Diamond)),
        );
    }
    if let (Some(lo), Some(hi)) = (
        band.iter().copied().reduce(f64::min),
        band.iter().copied().reduce(f64::max),
    ) {
        let (left, right) = (
            report.dts.iter().copied().fold(f64::INFINITY, f64::min),
            report.dts.iter().copied().fold(0.0, f64::max),
        );
        let style = Style::color(GUIDE_COLOR).dash(Dash::Dashed);
        plot = plot
            .with(
                Series::line(
                    "ensemble spread at the finest Δt",
                    vec![(left, lo), (right, lo)],
                )
                .styled(style),
            )
            .with(Series::line("", vec![(left, hi), (right, hi)]).styled(style));
    }
    plot.log = (true, false);
    plot.save(path, (1000, 620))?;
    out.files.push(name);
    Ok(out)
}

/// The title of [`plot_convergence`]: the scene, the verdict on the failure time and the
/// study's size, with the caption under it: Δt from the scene's to the finest level's,
/// and `prox`.
#[must_use]
pub fn convergence_title(report: &ConvergenceReport, scene: &str, prox: Prox) -> String {
    let headline = format!(
        "{scene}: failure time {} ({} levels, {} members)",
        report.failure.verdict,
        report.dts.len(),
        report.runs.len() - report.dts.len()
    );
    let first = report.dts.first().copied().unwrap_or(f64::NAN);
    let last = report.dts.last().copied().unwrap_or(f64::NAN);
    Numerics {
        rule: None,
        step: Step::Range(first, last),
        prox,
    }
    .under(&headline)
}

#[cfg(test)]
mod tests {
    use super::*;
    use blockstack::simulation::RunOptions;
    use blockstack::studies::convergence::{converge, Settings};

    /// The study of the Lire collapse to `t_end`, Δt and Δt/2, one member per magnitude.
    fn lire_collapse(t_end: f64) -> ConvergenceReport {
        let scene = blockstack::scenes::find("lire-collapse")
            .unwrap()
            .load()
            .unwrap()
            .scene;
        let options = RunOptions {
            t_end: Some(t_end),
            ..RunOptions::default()
        };
        let settings = Settings {
            levels: 1,
            ensemble: 1,
        };
        converge(&scene, &options, settings).unwrap()
    }

    #[test]
    fn judged_rows_get_a_bar_each_and_one_legend_entry_per_verdict_present() {
        let point = |x: f64, band: Option<(f64, f64)>, verdict| JudgedPoint {
            x,
            y: 1.0,
            band,
            verdict,
        };
        let points = [
            point(1.0, Some((0.5, 1.5)), VerdictKind::Converged),
            point(2.0, None, VerdictKind::NotConverged),
            point(3.0, Some((0.9, 1.1)), VerdictKind::Converged),
        ];
        let plot = with_verdicts(LinePlot::new("t", "x", "y"), &points, "band", "outcome");
        let labels: Vec<&str> = plot.series.iter().map(|s| s.label.as_str()).collect();
        assert_eq!(
            labels,
            [
                "band",
                "",
                "finest Δt, outcome converged",
                "finest Δt, outcome not converged"
            ]
        );
        assert_eq!(plot.series[1].points, [(3.0, 0.9), (3.0, 1.1)]);
        assert_eq!(plot.series[2].points, [(1.0, 1.0), (3.0, 1.0)]);
        let styles: Vec<Style> = plot.series[2..].iter().map(|s| s.style.unwrap()).collect();
        assert!(styles.iter().all(|s| s.hollow) && styles[0] != styles[1]);
    }

    #[test]
    fn the_title_names_the_verdict_and_its_caption_the_levels_and_the_prox() {
        let report = lire_collapse(0.1);
        assert_eq!(
            convergence_title(&report, "lire", Prox::Constant(0.3)),
            format!(
                "lire: failure time {} (2 levels, 3 members)\nΔt = 0.01 … 0.005, prox r = 0.3",
                report.failure.verdict
            )
        );
    }

    #[test]
    fn a_study_without_a_failure_is_left_out_with_a_note_and_one_with_is_drawn() {
        let dir = std::env::temp_dir().join(format!("figures-converge-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("converge.png");
        let standing =
            plot_convergence(&path, &lire_collapse(0.1), "lire", Prox::Scaled(1.0)).unwrap();
        assert!(standing.files.is_empty() && !path.exists());
        assert_eq!(
            standing.notes,
            ["no converge.png: no run lost its support before its end"]
        );
        let fallen =
            plot_convergence(&path, &lire_collapse(6.7), "lire", Prox::Scaled(1.0)).unwrap();
        assert_eq!(fallen.files, ["converge.png"]);
        assert!(path.exists() && fallen.notes.is_empty());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
