//! The PNG figures of `rollstack cylinder`: the support-force curves of §3.3 and the
//! plan view of a rolled trace (Figures 3.10, 3.12), drawn from the typed results of
//! [`cylinders::studies`].

use crate::plot::{Dash, Legend, LinePlot, Series, Style, PALETTE};
use crate::Result;
use cylinders::statics::FrictionLimit;
use cylinders::studies::holonomy::PlanView;
use cylinders::studies::statics::StaticsFigures;
use std::path::Path;

/// The y axis of the support-force figures.
const N_OVER_MG: &str = "N/mg [dimensionless]";
/// The x axis of the support-force figures.
const THETA_DEG: &str = "ϑ [deg]";

/// The line pattern of each friction limit in Figures 3.3–3.5: (+) solid, (−) dashed,
/// smooth dotted; the colour tells the parameter (r/h or μ) of the curve.
fn limit_dash(limit: FrictionLimit) -> Dash {
    match limit {
        FrictionLimit::Plus => Dash::Solid,
        FrictionLimit::Minus => Dash::Dashed,
        FrictionLimit::Smooth => Dash::Dotted,
    }
}

/// Draws fig3_3.png, fig3_4.png, fig3_5.png, fig3_7.png and fig3_8.png into `dir`.
///
/// In Figures 3.4 and 3.5 each parameter value (r/h, μ) has a colour of its own and
/// each friction limit a line pattern ((+) solid, (−) dashed, smooth dotted), so no two
/// of the 12–13 curves look alike; their legends go outside the plot, right of it.
/// Figure 3.5 draws μ = 0 once, as the smooth curve (the (+) and (−) limits coincide
/// with it there).
///
/// # Errors
/// When a file cannot be written.
pub fn plot_statics(dir: &Path, fig: &StaticsFigures) -> Result<()> {
    let (r_over_h, mu) = (fig.r_over_h, fig.mu);
    let mut plot = LinePlot::new(
        format!("Fig. 3.3: N/mg = 1 − F3/mg (r/h = {r_over_h}, μ = {mu})"),
        THETA_DEG,
        N_OVER_MG,
    );
    for (i, (label, limit)) in [
        ("i: F_f = +μN e′2 (3.3.8)+", FrictionLimit::Plus),
        ("smooth plane (3.3.10)", FrictionLimit::Smooth),
        ("ii: F_f = −μN e′2 (3.3.8)−", FrictionLimit::Minus),
    ]
    .into_iter()
    .enumerate()
    {
        plot = plot.with(
            Series::line(label, fig.figure_3_3.curve(limit))
                .styled(Style::color(PALETTE[i]).dash(limit_dash(limit))),
        );
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
        let mut plot = LinePlot {
            legend: Legend::Right,
            ..LinePlot::new(title, THETA_DEG, N_OVER_MG)
        };
        for (i, q) in family.iter().enumerate() {
            let (rho, m) = (q.r_over_h, q.mu);
            let color = PALETTE[i % PALETTE.len()];
            let param = if name == "fig3_4" {
                format!("r/h = {rho}")
            } else {
                format!("μ = {m}")
            };
            let mut limits = Vec::new();
            if m != 0.0 {
                limits.push(("(+)", FrictionLimit::Plus));
                limits.push(("(−)", FrictionLimit::Minus));
            }
            if name == "fig3_4" || m == 0.0 {
                limits.push(("smooth", FrictionLimit::Smooth));
            }
            for (which, limit) in limits {
                plot = plot.with(
                    Series::line(format!("{param}, {which}"), q.curve(limit))
                        .styled(Style::color(color).dash(limit_dash(limit))),
                );
            }
        }
        plot.save(&dir.join(format!("{name}.png")), (1100, 650))?;
    }

    // Figures 3.7 and 3.8: the minimum force.
    let s = fig.minimum_force_series();
    let (b, c) = (fig.circle.b, fig.circle.c);
    LinePlot::new(
        format!("Fig. 3.7: minimum-force locus, circle BC (r/h = {r_over_h}, μ = {mu})"),
        "F3/mg [dimensionless]",
        "F/mg [dimensionless]",
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
        THETA_DEG,
        "force / mg [dimensionless]",
    )
    .with(Series::line("‖F_a‖/mg", s.norm_over_mg))
    .with(Series::line("F/mg", s.f_over_mg))
    .with(Series::line("F3/mg", s.f3_over_mg))
    .with(Series::markers("D: ϑ = arctan(2r/h)", vec![(d, 0.0)]))
    .save(&dir.join("fig3_8.png"), (900, 600))
}

/// Draws the plan view of a rolled trace at `path`: the traces of P (i) and X (ii), the
/// centre of mass with arrows in the direction of travel, its start S and the rim
/// point's start A and end B. Lengths are in the unit of the cylinder's r and h.
///
/// # Errors
/// When the file cannot be written.
pub fn plot_trace(path: &Path, view: PlanView, title: &str) -> Result<()> {
    LinePlot {
        equal_aspect: true,
        ..LinePlot::new(title, "E1 [unit of r, h]", "E2 [unit of r, h]")
    }
    .with(Series::line("i: contact point P", view.contact).with_arrows())
    .with(Series::line("ii: rim point X", view.rim_point))
    .with(Series::line("centre of mass", view.center))
    .with(Series::markers(
        "S (centre), A → B (X)",
        vec![view.start, view.rim_start, view.rim_end],
    ))
    .save(path, (900, 800))
}
