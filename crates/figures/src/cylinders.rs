//! The PNG figures of `rollstack cylinder`: the support-force curves of §3.3, the
//! plan view of a rolled trace (Figures 3.10, 3.12), and the transport of a touching
//! pair (§3.6: its forces, views, animation, Figure 3.14 and its work-precision diagram),
//! drawn from the typed
//! results of [`cylinders::studies`].

use crate::animation::write_gif;
use crate::nsga::{both_schemes_series, SchemeRun};
use crate::plot::{with_png, Dash, Legend, LinePlot, Marker, Series, Style, PALETTE};
use crate::Result;
use cylinders::kinematics::Cylinder;
use cylinders::statics::FrictionLimit;
use cylinders::studies::holonomy::PlanView;
use cylinders::studies::pair::{pair_outline, PairSample, PairSweepRow, PushRow};
use cylinders::studies::statics::StaticsFigures;
use cylinders::studies::work_precision::{PairWorkPrecision, T_END_S};
use std::ops::Range;
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

/// The two panels of the pair at one configuration: a top view (E1, E2) and a side view
/// along the direction of travel (E2, E3), each with fixed `bounds` (a moving window in
/// an animation) and the floor line in the side view.
fn pair_views(
    cylinder: &Cylinder,
    q: &[f64],
    title: &str,
    top_bounds: Window,
    side_bounds: Window,
) -> [LinePlot; 2] {
    let floor = vec![(side_bounds.0.start, 0.0), (side_bounds.0.end, 0.0)];
    let outline = pair_outline(cylinder, q);
    let mut top = LinePlot {
        equal_aspect: true,
        bounds: Some(top_bounds),
        ..LinePlot::new(format!("{title}: top view"), "E1 [m]", "E2 [m]")
    };
    let mut side = LinePlot {
        equal_aspect: true,
        bounds: Some(side_bounds),
        ..LinePlot::new("side view, along the travel", "E2 [m]", "E3 [m]")
    };
    side = side.with(Series::line("", floor).styled(Style::color(BLACK_ISH)));
    let mut labelled = [false; 2];
    for (body, line) in outline {
        let label = if labelled[body] {
            String::new()
        } else {
            labelled[body] = true;
            ["cylinder I (spun)", "cylinder II"][body].to_owned()
        };
        let style = Style::color(PALETTE[body]);
        top = top.with(
            Series::line(label.clone(), line.iter().map(|p| (p[0], p[1])).collect()).styled(style),
        );
        side = side
            .with(Series::line(label, line.iter().map(|p| (p[1], p[2])).collect()).styled(style));
    }
    [top, side]
}

/// The ranges (horizontal, vertical) of one view, in metres.
type Window = (Range<f64>, Range<f64>);

/// The colour of the floor line.
const BLACK_ISH: plotters::style::RGBColor = plotters::style::RGBColor(60, 60, 60);

/// Windows of the two views around the pair at q: 2.4 m wide in E1 centred on the
/// pair, the lean's width in E2, floor to top in E3.
fn pair_bounds(cylinder: &Cylinder, q: &[f64]) -> (Window, Window) {
    let h = cylinder.height();
    let mid = 0.5 * (q[0] + q[6]);
    let y = 0.5 * (q[1] + q[7]);
    (
        (mid - 1.2..mid + 1.2, y - 0.9 * h..y + 0.9 * h),
        (y - 0.9 * h..y + 0.9 * h, -0.1..1.1 * h),
    )
}

/// Draws the pair at configuration q (time t) at `path`: top and side views.
///
/// # Errors
/// When the file cannot be written.
pub fn plot_pair_view(path: &Path, cylinder: &Cylinder, q: &[f64], title: &str) -> Result<()> {
    let (tb, sb) = pair_bounds(cylinder, q);
    let [top, side] = pair_views(cylinder, q, title, tb, sb);
    with_png(path, (1200, 560), |root| {
        let (left, right) = root.split_horizontally(600);
        top.draw(&left)?;
        side.draw(&right)
    })
}

/// Writes an animated GIF of the pair (top and side views) through `frames` of
/// (t, q), atomically.
///
/// # Errors
/// No frame, or an unwritable file.
pub fn write_pair_animation(
    path: &Path,
    cylinder: &Cylinder,
    frames: &[(f64, Vec<f64>)],
    title: &str,
) -> Result<()> {
    write_gif(path, (900, 420), 80, frames.len(), |i, root| {
        let (t, q) = &frames[i];
        let (tb, sb) = pair_bounds(cylinder, q);
        let [top, side] = pair_views(cylinder, q, &format!("{title}, t = {t:.2} s"), tb, sb);
        let (left, right) = root.split_horizontally(450);
        top.draw(&left)?;
        side.draw(&right)
    })
}

/// The forces of one transport run against time: N/mg and F3/mg of both cylinders, the
/// normal force between them, and the smooth-floor values (3.3.10) as dotted lines.
///
/// # Errors
/// When the file cannot be written.
pub fn plot_pair_forces(
    path: &Path,
    samples: &[PairSample],
    n_static: f64,
    title: &str,
) -> Result<()> {
    let series = |f: &dyn Fn(&PairSample) -> f64| -> Vec<(f64, f64)> {
        samples.iter().map(|s| (s.t, f(s))).collect()
    };
    let (t0, t1) = (
        samples.first().map_or(0.0, |s| s.t),
        samples.last().map_or(1.0, |s| s.t),
    );
    LinePlot {
        legend: Legend::Right,
        ..LinePlot::new(title, "t [s]", "force / mg [dimensionless]")
    }
    .with(Series::line("N/mg, I", series(&|s| s.n_over_mg[0])).styled(Style::color(PALETTE[0])))
    .with(
        Series::line("N/mg, II", series(&|s| s.n_over_mg[1]))
            .styled(Style::color(PALETTE[0]).dash(Dash::Dashed)),
    )
    .with(Series::line("F3/mg, I", series(&|s| s.f3_over_mg[0])).styled(Style::color(PALETTE[1])))
    .with(
        Series::line("F3/mg, II", series(&|s| s.f3_over_mg[1]))
            .styled(Style::color(PALETTE[1]).dash(Dash::Dashed)),
    )
    .with(
        Series::line("contact normal / mg", series(&|s| s.contact_normal_force))
            .styled(Style::color(PALETTE[2])),
    )
    .with(
        Series::line("N/mg (3.3.10)", vec![(t0, n_static), (t1, n_static)])
            .styled(Style::color(PALETTE[3]).dash(Dash::Dotted)),
    )
    .with(
        Series::line(
            "F3/mg (3.3.10)",
            vec![(t0, 1.0 - n_static), (t1, 1.0 - n_static)],
        )
        .styled(Style::color(PALETTE[4]).dash(Dash::Dotted)),
    )
    .save(path, (1100, 600))
}

/// Figure 3.14: N/mg and F3/mg of both cylinders and the normal force between them
/// against ϑ, markers from the simulations, with the smooth-floor curve (3.3.10) for
/// r/h = `r_over_h` over the same range.
///
/// # Errors
/// When the file cannot be written.
pub fn plot_pair_sweep(path: &Path, rows: &[PairSweepRow], r_over_h: f64) -> Result<()> {
    let good: Vec<&PairSweepRow> = rows.iter().filter(|r| r.error.is_none()).collect();
    let deg = |r: &PairSweepRow| r.theta.to_degrees();
    let pts = |f: &dyn Fn(&PairSweepRow) -> f64| -> Vec<(f64, f64)> {
        good.iter().map(|r| (deg(r), f(r))).collect()
    };
    let lo = (2.0 * r_over_h).atan();
    let hi = rows.iter().map(|r| r.theta).fold(lo, f64::max);
    let curve: Vec<(f64, f64)> = (0..=200)
        .map(|k| lo + (hi - lo) * f64::from(k) / 200.0)
        .map(|t| (t, 0.5 * t.sin() / (t.sin() - r_over_h * t.cos())))
        .map(|(t, n)| (t.to_degrees(), n))
        .collect();
    let f3: Vec<(f64, f64)> = curve.iter().map(|&(t, n)| (t, 1.0 - n)).collect();
    LinePlot {
        legend: Legend::Right,
        ..LinePlot::new(
            format!("Fig. 3.14: forces sustaining the transport (r/h = {r_over_h:.4})"),
            THETA_DEG,
            "force / mg [dimensionless]",
        )
    }
    .with(Series::line("N/mg (3.3.10)", curve).styled(Style::color(PALETTE[0])))
    .with(Series::line("F3/mg (3.3.10)", f3).styled(Style::color(PALETTE[1])))
    .with(
        Series::markers("N/mg, I and II (nsga)", pts(&|r| r.n_over_mg[0]))
            .styled(Style::color(PALETTE[0]).marker(Marker::Circle)),
    )
    .with(
        Series::markers("F3/mg, I and II (nsga)", pts(&|r| r.f3_over_mg[0]))
            .styled(Style::color(PALETTE[1]).marker(Marker::Circle)),
    )
    .with(
        Series::markers("contact normal / mg", pts(&|r| r.contact_normal_force))
            .styled(Style::color(PALETTE[2]).marker(Marker::Square)),
    )
    .save(path, (1100, 600))
}

/// The push at which a rim starts to slip against ϑ (markers, from the simulations;
/// the last push that did not slip beside it) with the static bound for r/h =
/// `r_over_h`: μ_s N₋ of (3.3.8)₋ (corrected per errata item 9) for pushes along +e′2
/// (`direction` 1), −μ_s N₊ of (3.3.8)₊ for pushes along −e′2 (`direction` −1).
///
/// # Errors
/// When the file cannot be written.
pub fn plot_push_sweep(
    path: &Path,
    rows: &[PushRow],
    r_over_h: f64,
    mu: f64,
    direction: f64,
) -> Result<()> {
    let sign = if direction < 0.0 { -1.0 } else { 1.0 };
    let lo = rows.iter().map(|r| r.theta).fold(f64::INFINITY, f64::min);
    let hi = rows
        .iter()
        .map(|r| r.theta)
        .fold(f64::NEG_INFINITY, f64::max);
    let (lo, hi) = if lo < hi {
        (lo, hi)
    } else {
        (lo - 0.05, lo + 0.05)
    };
    let curve: Vec<(f64, f64)> = (0..=200)
        .map(|k| lo + (hi - lo) * f64::from(k) / 200.0)
        .filter_map(|t| {
            let (s, c) = t.sin_cos();
            let d = s - r_over_h * c - sign * mu * (r_over_h * s + c);
            (d > 0.0).then(|| (t.to_degrees(), sign * mu * 0.5 * s / d))
        })
        .collect();
    let onset = rows
        .iter()
        .filter_map(|r| r.onset_over_mg.map(|p| (r.theta.to_degrees(), p)))
        .collect();
    let stick = rows
        .iter()
        .filter_map(|r| r.last_stick_over_mg.map(|p| (r.theta.to_degrees(), p)))
        .collect();
    LinePlot {
        legend: Legend::Right,
        ..LinePlot::new(
            format!("Slip onset under a push along e′2 (r/h = {r_over_h:.4}, μ_s = {mu})"),
            THETA_DEG,
            "P/mg [dimensionless]",
        )
    }
    .with(
        Series::line(
            if sign > 0.0 {
                "μ_s N₋/mg, (3.3.8)−"
            } else {
                "−μ_s N₊/mg, (3.3.8)+"
            },
            curve,
        )
        .styled(Style::color(PALETTE[0])),
    )
    .with(
        Series::markers("last push that sticks (nsga)", stick)
            .styled(Style::color(PALETTE[2]).marker(Marker::Circle)),
    )
    .with(
        Series::markers("first push that slips (nsga)", onset)
            .styled(Style::color(PALETTE[1]).marker(Marker::Triangle)),
    )
    .save(path, (1100, 600))
}

/// The minimum applied force against ϑ for `cylinder` at floor friction `mu`
/// ((3.3.15)–(3.3.19) as corrected in errata items 9–11), drawn as the static curve, with
/// ‖(P*, F3)‖/mg measured by the transport at the push P* of each row of `rows` beside
/// it: discs where the transport confirms the minimum, diamonds where it does not.
///
/// # Errors
/// When the file cannot be written.
pub fn plot_minimum_force(
    path: &Path,
    rows: &[PushRow],
    cylinder: &Cylinder,
    mu: f64,
) -> Result<()> {
    let rho = cylinder.radius() / cylinder.height();
    let statics = cylinders::statics::SupportProblem::new(rho, mu).map_err(crate::err)?;
    let (lo, hi) = cylinders::transport::inclination_range(cylinder);
    let curve: Vec<(f64, f64)> = (1..200)
        .map(|k| lo + (hi - lo) * f64::from(k) / 200.0)
        .filter_map(|t| {
            let m = statics.minimum_force(t).ok()?;
            Some((t.to_degrees(), m.norm_over_mg))
        })
        .collect();
    let measured = |agrees: bool| -> Vec<(f64, f64)> {
        rows.iter()
            .filter_map(|r| {
                let m = r.minimum_force.as_ref()?;
                (m.agrees == agrees).then(|| (r.theta.to_degrees(), m.norm_over_mg))
            })
            .collect()
    };
    LinePlot {
        legend: Legend::Right,
        ..LinePlot::new(
            format!("Minimum applied force at the top (r/h = {rho:.4}, μ_s = {mu})"),
            THETA_DEG,
            "‖F_a‖/mg [dimensionless]",
        )
    }
    .with(Series::line("statics, (3.3.15)–(3.3.19)", curve).styled(Style::color(PALETTE[0])))
    .with(
        Series::markers("transport at P*, confirmed (nsga)", measured(true))
            .styled(Style::color(PALETTE[2]).marker(Marker::Circle)),
    )
    .with(
        Series::markers("transport at P*, not confirmed", measured(false))
            .styled(Style::color(PALETTE[1]).marker(Marker::Diamond)),
    )
    .save(path, (1100, 600))
}

/// The pair's work-precision diagram: the error against the reference at the end time
/// against solver time, log–log, one line with a marker per run for each scheme (failed
/// runs left out), open markers where the order was not fitted
/// ([`crate::nsga::work_precision_series`]).
///
/// # Errors
/// An unwritable file.
pub fn plot_pair_work_precision(path: &Path, study: &PairWorkPrecision) -> Result<()> {
    let title = format!(
        "Work-precision, cylinder pair spun up at ϑ = {:.1}° (error at t = {T_END_S} s against \
         Δt = {:.2e} s; {})",
        study.theta.to_degrees(),
        study.reference_dt,
        crate::nsga::FITTED_MARKERS
    );
    let mut plot = LinePlot::new(&title, "wall time [s]", "error [m, rad]");
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
