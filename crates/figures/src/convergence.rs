//! The picture of a convergence study (`rollstack blocks converge`): the failure time
//! against Δt, the unperturbed runs at Δt/2^k joined by a line, and the ensemble of
//! perturbed runs at the finest Δt as a band between its earliest and its latest
//! failure time.

use crate::blocks::DrawnRun;
use crate::plot::{Dash, LinePlot, Marker, Series, Style, GUIDE_COLOR, PALETTE};
use crate::Result;
use blockstack::studies::convergence::{ConvergenceReport, JobKind};
use std::path::Path;

/// The failure time of the unperturbed runs against Δt (log Δt), the members' failure
/// times at the finest Δt as markers and their spread (the unperturbed finest run's
/// included) as a band across the plot; the title gives the verdict, the scene's Δt and
/// `prox`, the prox choice. Left out with a note when no run failed.
///
/// # Errors
/// An unwritable file.
pub fn plot_convergence(
    path: &Path,
    report: &ConvergenceReport,
    scene: &str,
    prox: &str,
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
    let title = format!(
        "{scene}: failure time at Δt = {:.3e}/2^k, prox {prox}: {} ({} levels, {} members)",
        report.dts.first().copied().unwrap_or(f64::NAN),
        report.failure.verdict,
        report.dts.len(),
        report.runs.len() - report.dts.len()
    );
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
    fn a_study_without_a_failure_is_left_out_with_a_note_and_one_with_is_drawn() {
        let dir = std::env::temp_dir().join(format!("figures-converge-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("converge.png");
        let standing = plot_convergence(&path, &lire_collapse(0.1), "lire", "p").unwrap();
        assert!(standing.files.is_empty() && !path.exists());
        assert_eq!(
            standing.notes,
            ["no converge.png: no run lost its support before its end"]
        );
        let fallen = plot_convergence(&path, &lire_collapse(6.7), "lire", "p").unwrap();
        assert_eq!(fallen.files, ["converge.png"]);
        assert!(path.exists() && fallen.notes.is_empty());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
