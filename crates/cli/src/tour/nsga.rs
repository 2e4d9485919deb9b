//! Tour section: the solver core on the paper's bouncing ball, both schemes, and a
//! work-precision diagram on the linear oscillator.

use super::{Block, Section};
use crate::output::write_csv;
use anyhow::Result;
use figures::nsga::{plot_ball, plot_work_precision};
use nsga::studies::ball::{run_ball, Scheme};
use nsga::studies::work_precision::{work_precision_point, WorkPrecisionRow, WorkPrecisionSystem};
use nsga::systems::ball::BallCase;
use nsga::Prox;
use std::path::Path;

/// Builds the section: a table of the four ball cases (NSGA and Moreau–Jean), the
/// case 2 trajectory, and the oscillator's work-precision diagram.
///
/// # Errors
/// When a run fails or a file cannot be written.
pub fn section(dir: &Path) -> Result<Section> {
    let mut rows = Vec::new();
    let mut summary = Vec::new();
    let mut case2 = None;
    for case in 1..=4u8 {
        let c = BallCase::new(case).map_err(anyhow::Error::msg)?;
        for scheme in [Scheme::Nsga, Scheme::Moreau] {
            let r = run_ball(&c, scheme, 2e-3, 0.5, Prox::Scaled(1.0))?;
            let name = if scheme == Scheme::Nsga {
                "NSGA"
            } else {
                "Moreau-Jean"
            };
            let fmt = |x: Option<f64>| x.map_or("-".to_owned(), |v| format!("{v:.3}"));
            rows.push(vec![
                case.to_string(),
                name.to_owned(),
                fmt(r.first_impact_time),
                fmt(r.rolling_onset_time),
                format!("{:.4}", r.final_velocity[0]),
                format!("{:.2e}", r.min_gap),
                format!("{:.2}", r.newton_iterations_mean),
                format!("{:.2}", r.wall_time_s * 1e3),
            ]);
            if scheme == Scheme::Nsga {
                summary.push(format!(
                    "ball case {case}: final xdot {:.4} m/s, min gap {:.1e} m, {:.2} Newton it./step, {:.2} ms",
                    r.final_velocity[0],
                    r.min_gap,
                    r.newton_iterations_mean,
                    r.wall_time_s * 1e3
                ));
                if case == 2 {
                    case2 = Some((r, c.ball.radius));
                }
            }
        }
    }
    let header = [
        "case",
        "scheme",
        "first impact [s]",
        "rolling from [s]",
        "final xdot [m/s]",
        "min gap [m]",
        "Newton it./step",
        "wall [ms]",
    ];
    write_csv(&dir.join("ball_cases.csv"), &header, &rows)?;
    if let Some((r, radius)) = &case2 {
        plot_ball(
            &dir.join("ball_case2.png"),
            "Bouncing ball, case 2 (e_N = 0, omega0 = 50 rad/s)",
            r,
            *radius,
        )?;
    }
    // Work-precision on the oscillator.
    let dts = [8e-3, 4e-3, 2e-3, 1e-3, 5e-4];
    let mut points = Vec::new();
    for (scheme, rho) in [
        (Scheme::Nsga, 0.0),
        (Scheme::Nsga, 0.5),
        (Scheme::Nsga, 1.0),
        (Scheme::Moreau, 0.5),
    ] {
        for &dt in &dts {
            let (e, w) = work_precision_point(WorkPrecisionSystem::Oscillator, scheme, rho, dt)?;
            points.push(WorkPrecisionRow {
                scheme,
                rho_inf: (scheme == Scheme::Nsga).then_some(rho),
                dt,
                error: e,
                wall_time_s: w,
            });
        }
    }
    plot_work_precision(
        &dir.join("work_precision_oscillator.png"),
        "Work-precision, linear oscillator (phase-plane error at 1 s)",
        &points,
    )?;
    write_csv(
        &dir.join("work_precision_oscillator.csv"),
        &WorkPrecisionRow::CSV_HEADER,
        points.iter().map(WorkPrecisionRow::csv_cells),
    )?;
    Ok(Section {
        title: "Solver core: nonsmooth generalized-alpha (Capobianco et al. 2021)".into(),
        summary,
        blocks: vec![
            Block::Text(
                "The paper's rotating bouncing ball (m = 1, R = 0.1, mu = 0.2, dt = 2e-3, rho_inf = 0.5). \
                 Exact answers: first impact 0.4284 s; case 2 rolls from 0.728 s at xdot = -1.4286; \
                 case 3 at -0.2857; case 4 at -0.7143. Moreau-Jean sinks into the ground at impacts."
                    .into(),
            ),
            Block::Table { header: header.iter().map(|s| (*s).to_owned()).collect(), rows },
            Block::Data { file: "ball_cases.csv".into(), description: "the table above".into() },
            Block::Image { file: "ball_case2.png".into(), caption: "Case 2: falls, slides, rolls from 0.728 s".into() },
            Block::Image {
                file: "work_precision_oscillator.png".into(),
                caption: "Phase-plane error at 1 s against wall time: second order for every rho_inf and for Moreau-Jean".into(),
            },
            Block::Data { file: "work_precision_oscillator.csv".into(), description: "work-precision data".into() },
        ],
    })
}
