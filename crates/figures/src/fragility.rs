//! The picture of a fragility study (`rollstack blocks fragility`): one panel per
//! intensity (PGA, PGV), in each the fitted lognormal curve of each outcome (overturned,
//! failed) as a line with its band as dashed lines of the same colour, and the fraction
//! of runs that collapsed at each level as markers. An outcome with no fit (none or all
//! collapsed, separated outcomes) keeps its markers and says so in its legend.

use crate::numerics::extend_headline;
use crate::plot::{Dash, LinePlot, Series, Style, PALETTE};
use crate::Result;
use blockstack::studies::fragility::{Curve, CurvePoint, Intensity};
use std::path::Path;

/// The two panels of `fragility.png`, side by side: `curves` and their `points`
/// ([`blockstack::studies::fragility::curve_points`]); `title` names the scene, and the
/// runs' caption on a line of its own ([`Numerics::under`](crate::numerics::Numerics::under)).
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
        extend_headline(
            title,
            &format!(": P(collapse) against {}", intensity.label()),
        ),
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

#[cfg(test)]
mod tests {
    use super::*;
    use blockstack::studies::fragility::{curve_points, fit_curves, FragilityRow};

    /// A run at `pga` (g; PGV = pga) that overturned or not.
    fn row(level: f64, pga: f64, overturned: bool) -> FragilityRow {
        FragilityRow {
            record: "r.AT2".into(),
            level,
            pga_g: Some(pga),
            pgv: Some(pga),
            overturned: Some(overturned),
            failed: Some(overturned),
            failure_time: overturned.then_some(1.0),
            failure_kind: overturned.then(|| "tipped".to_owned()),
            t_final: Some(2.0),
            steps: 10,
            error: None,
            wall_time_s: 0.0,
        }
    }

    #[test]
    fn fitted_and_unfitted_curves_are_drawn() {
        // Overlapping outcomes: a curve fits against both intensities.
        let outcomes = [
            (0.1, false),
            (0.2, false),
            (0.3, true),
            (0.25, false),
            (0.28, true),
            (0.4, true),
            (0.35, false),
        ];
        let rows: Vec<FragilityRow> = outcomes.iter().map(|&(x, o)| row(x, x, o)).collect();
        let curves = fit_curves(&rows);
        assert!(curves.iter().all(|c| c.fit.is_ok()));
        let dir = std::env::temp_dir().join(format!("figures-fragility-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("fragility.png");
        plot_fragility(&path, &curves, &curve_points(&rows, &curves), "test").unwrap();
        assert!(std::fs::metadata(&path).unwrap().len() > 1000);
        // The scene's name heads each panel, the runs' caption stays under it.
        let title = crate::numerics::Numerics::run(0.005, nsga::Prox::Scaled(1.0)).under("column");
        let points = curve_points(&rows, &curves);
        let panel = panel(&curves, &points, curves[0].intensity, &title);
        assert_eq!(
            panel.title,
            format!(
                "column: P(collapse) against {}\nΔt = 0.005, prox scaled (α = 1)",
                curves[0].intensity.label()
            )
        );
        // None collapsed: no curve, the markers only.
        let standing: Vec<FragilityRow> = rows
            .iter()
            .map(|r| row(r.level, r.pga_g.unwrap(), false))
            .collect();
        let curves = fit_curves(&standing);
        assert!(curves.iter().all(|c| c.fit.is_err()));
        plot_fragility(&path, &curves, &curve_points(&standing, &curves), "test").unwrap();
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
