//! The picture of a fragility study (`rollstack blocks fragility`): one panel per
//! intensity (PGA, PGV), in each the fitted lognormal curve of each outcome (overturned,
//! failed) as a line with its band as dashed lines of the same colour, and the fraction
//! of runs that collapsed at each level as markers. An outcome with no fit (none or all
//! collapsed, separated outcomes) keeps its markers and says so in its legend.

use crate::plot::{Dash, LinePlot, Series, Style, PALETTE};
use crate::Result;
use blockstack::studies::fragility::{Curve, CurvePoint, Intensity};
use std::path::Path;

/// The two panels of `fragility.png`, side by side: `curves` and their `points`
/// ([`blockstack::studies::fragility::curve_points`]); `title` names the scene.
///
/// # Errors
/// An unwritable file.
pub fn plot_fragility(
    path: &Path,
    curves: &[Curve],
    points: &[CurvePoint],
    title: &str,
) -> Result<()> {
    let panels: Vec<LinePlot> = [Intensity::Pga, Intensity::Pgv]
        .into_iter()
        .map(|intensity| panel(curves, points, intensity, title))
        .collect();
    crate::plot::with_png(path, (1400, 600), |root| {
        let areas = root.split_evenly((1, 2));
        panels[0].draw(&areas[0])?;
        panels[1].draw(&areas[1])
    })
}

/// One panel: every curve against `intensity`.
fn panel(curves: &[Curve], points: &[CurvePoint], intensity: Intensity, title: &str) -> LinePlot {
    let mut plot = LinePlot::new(
        format!("{title}: P(collapse) against {}", intensity.label()),
        intensity.label(),
        "P(collapse)",
    );
    let of = |curve: &Curve, kind: &str| -> Vec<&CurvePoint> {
        points
            .iter()
            .filter(|p| p.outcome == curve.outcome && p.intensity == intensity && p.kind == kind)
            .collect()
    };
    for (i, curve) in curves
        .iter()
        .filter(|c| c.intensity == intensity)
        .enumerate()
    {
        let style = Style::color(PALETTE[i % PALETTE.len()]);
        let name = curve.outcome.name();
        let levels: Vec<(f64, f64)> = of(curve, "level").iter().map(|p| (p.im, p.p)).collect();
        if let Ok(fit) = &curve.fit {
            let grid = of(curve, "fit");
            let line = |f: fn(&CurvePoint) -> f64| grid.iter().map(|p| (p.im, f(p))).collect();
            let label = format!("{name}: theta = {:.3}, beta = {:.2}", fit.theta, fit.beta);
            plot = plot
                .with(Series::line(label, line(|p| p.p)).styled(style))
                .with(
                    Series::line(
                        format!("{name}: 95 % band"),
                        line(|p| p.band.map_or(p.p, |b| b[0])),
                    )
                    .styled(style.dash(Dash::Dashed).width(1)),
                )
                .with(
                    Series::line("", line(|p| p.band.map_or(p.p, |b| b[1])))
                        .styled(style.dash(Dash::Dashed).width(1)),
                );
        }
        let no_fit = if curve.fit.is_ok() {
            ""
        } else {
            " (no fit: fit.json says why)"
        };
        plot = plot.with(
            Series::markers(format!("{name}: fraction per level{no_fit}"), levels)
                .styled(style.hollow()),
        );
    }
    plot
}
