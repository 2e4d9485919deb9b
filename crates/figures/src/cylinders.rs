//! The PNG figures of `rollstack cylinder`: the support-force curves of §3.3 and the
//! plan view of a rolled trace (Figures 3.10, 3.12), drawn from the typed results of
//! [`cylinders::studies`].

use crate::plot::{LinePlot, Series};
use crate::Result;
use cylinders::statics::FrictionLimit;
use cylinders::studies::holonomy::PlanView;
use cylinders::studies::statics::StaticsFigures;
use std::path::Path;

/// Draws fig3_3.png, fig3_4.png, fig3_5.png, fig3_7.png and fig3_8.png into `dir`.
///
/// # Errors
/// When a file cannot be written.
pub fn plot_statics(dir: &Path, fig: &StaticsFigures) -> Result<()> {
    let (r_over_h, mu) = (fig.r_over_h, fig.mu);
    let mut plot = LinePlot::new(
        format!("Fig. 3.3: N/mg = 1 − F3/mg (r/h = {r_over_h}, μ = {mu})"),
        "ϑ [deg]",
        "N/mg",
    );
    for (label, limit) in [
        ("i: F_f = +μN e′2 (3.3.8)+", FrictionLimit::Plus),
        ("smooth plane (3.3.10)", FrictionLimit::Smooth),
        ("ii: F_f = −μN e′2 (3.3.8)−", FrictionLimit::Minus),
    ] {
        plot = plot.with(Series::line(label, fig.figure_3_3.curve(limit)));
    }
    plot.save(&dir.join("fig3_3.png"), (900, 600))?;

    // Figures 3.4 (μ fixed, r/h varies) and 3.5 (r/h fixed, μ varies).
    let families = [
        (
            "fig3_4",
            &fig.figure_3_4,
            format!("Fig. 3.4: N/mg, μ = {mu}, r/h = 0 … 0.15"),
        ),
        (
            "fig3_5",
            &fig.figure_3_5,
            format!("Fig. 3.5: N/mg, r/h = {r_over_h}, μ = 0 … 0.6"),
        ),
    ];
    for (name, family, title) in families {
        let mut plot = LinePlot::new(title, "ϑ [deg]", "N/mg");
        for q in family {
            let (rho, m) = (q.r_over_h, q.mu);
            for (sign, limit) in [("(+)", FrictionLimit::Plus), ("(−)", FrictionLimit::Minus)] {
                let label = format!("{sign} r/h={rho}, μ={m}");
                plot = plot.with(Series::line(label, q.curve(limit)));
            }
            if name == "fig3_4" || m == 0.0 {
                let label = format!("smooth r/h={rho}");
                plot = plot.with(Series::line(label, q.curve(FrictionLimit::Smooth)));
            }
        }
        plot.save(&dir.join(format!("{name}.png")), (1000, 650))?;
    }

    // Figures 3.7 and 3.8: the minimum force.
    let s = fig.minimum_force_series();
    let (b, c) = (fig.circle.b, fig.circle.c);
    LinePlot::new(
        format!("Fig. 3.7: minimum-force locus, circle BC (r/h = {r_over_h}, μ = {mu})"),
        "F3/mg",
        "F/mg",
    )
    .with(Series::markers(
        "(3.3.15) satisfying (3.3.17)",
        s.admissible,
    ))
    .with(Series::markers(
        "(3.3.15) violating (3.3.17)",
        s.inadmissible,
    ))
    .with(Series::markers("(3.3.18)/(3.3.19) minimum", s.on_bound))
    .with(Series::line("F = μN", fig.friction_bound(1.0)))
    .with(Series::line("F = −μN", fig.friction_bound(-1.0)))
    .with(Series::markers(
        "B, C (3.3.20)",
        vec![(b[0], b[1]), (c[0], c[1])],
    ))
    .save(&dir.join("fig3_7.png"), (900, 700))?;
    let d = fig.self_balancing_theta.to_degrees();
    LinePlot::new(
        format!("Fig. 3.8: minimum applied force (r/h = {r_over_h}, μ = {mu})"),
        "ϑ [deg]",
        "force / mg",
    )
    .with(Series::line("‖F_a‖/mg", s.norm_over_mg))
    .with(Series::line("F/mg", s.f_over_mg))
    .with(Series::line("F3/mg", s.f3_over_mg))
    .with(Series::markers("D: ϑ = arctan(2r/h)", vec![(d, 0.0)]))
    .save(&dir.join("fig3_8.png"), (900, 600))
}

/// Draws the plan view of a rolled trace at `path`: the traces of P (i) and X (ii), the
/// centre of mass, its start S and the rim point's start A and end B.
///
/// # Errors
/// When the file cannot be written.
pub fn plot_trace(path: &Path, view: PlanView, title: &str) -> Result<()> {
    LinePlot {
        equal_aspect: true,
        ..LinePlot::new(title, "E1", "E2")
    }
    .with(Series::line("i: contact point P", view.contact))
    .with(Series::line("ii: rim point X", view.rim_point))
    .with(Series::line("centre of mass", view.center))
    .with(Series::markers(
        "S (centre), A → B (X)",
        vec![view.start, view.rim_start, view.rim_end],
    ))
    .save(path, (900, 800))
}
