//! Tour section: the rolling sphere (Ch. 2): (2.4.10) reproduced, the rectangles of
//! (2.4.12), an Euler three-rectangle plan, and rolling with both integrators. The
//! numbers come from [`holonomy::studies`], the files are those of `rollstack sphere`.

use super::{Block, Section};
use crate::commands::sphere::{
    plot_level_sets, plot_rectangle_panels, plot_rectangles, plot_traces, write_plan_csv,
    write_study, write_trajectory,
};
use anyhow::Result;
use holonomy::studies::examples::{
    rectangle_2_4_10, target_2_4_12, PRINTED_RECTANGLES_2_4_12, PRINTED_TOLERANCE_2_4_12,
};
use holonomy::studies::plan::{euler_plan_report, plan_report};
use holonomy::studies::report::holonomy_report;
use holonomy::studies::roll::{integrator_study, roll_report, ClosedPath, PathShape, StudyPath};
use holonomy::{euler_plan, Direction, Integrator, Rectangle};
use rotations::EulerSet;
use std::path::Path;

/// Builds the section.
///
/// # Errors
/// When a file cannot be written.
pub fn section(dir: &Path) -> Result<Section> {
    let mut summary = Vec::new();
    let mut blocks = Vec::new();

    // (2.4.10) and Figure 2.1.
    let r = rectangle_2_4_10();
    let rep = holonomy_report(&r);
    summary.push(format!(
        "(2.4.10): ψ = {:.4}° (printed 62.7042°), s = [{:.6}, {:.6}, {:.6}] (printed −0.389418, 0, −0.921061), e3(t1) = [{:.6}, {:.6}, {:.6}]",
        rep.angle.to_degrees(),
        rep.axis[0],
        rep.axis[1],
        rep.axis[2],
        rep.e3_final[0],
        rep.e3_final[1],
        rep.e3_final[2]
    ));
    summary.push(format!(
        "product (2.4.2) vs corrected closed form (2.4.6): {:.1e} rad; vs components (B.1.2): {:.1e}",
        rep.closed_form_error, rep.components_error
    ));
    let closed = ClosedPath::new(&PathShape::Rectangle(r))?;
    let (rolled, traj) = roll_report(&closed, Integrator::Exact, 600)?;
    write_trajectory(&dir.join("figure_2_1_roll.csv"), &traj)?;
    plot_traces(
        &dir.join("figure_2_1.png"),
        &traj,
        "Figure 2.1: traces of C (i) and X (ii), rectangle of (2.4.10)",
    )?;
    plot_level_sets(&dir.join("figure_2_5.png"), Some((r.theta, r.phi2)))?;
    blocks.push(Block::image("figure_2_1.png", "Figure 2.1: top view of the centre C and the material point X that started at the contact, for Ŝ(4π/3 − 0.5, π/2 − 0.4, 3π, ccw) of (2.4.10)"));
    blocks.push(Block::data(
        "figure_2_1_roll.csv",
        "trajectory: s, centre, X, quaternion",
    ));
    blocks.push(Block::image("figure_2_5.png", "Figure 2.5: level sets of ψ(ϑ, φ2), from (2.4.11) with the factor 2 of ERRATA item 1; dot: the rectangle of (2.4.10)"));

    // (2.4.12) and Figure 2.6.
    let plan = plan_report(&target_2_4_12()?)?;
    let mut thesis_three = Vec::new();
    for [t, p1, p2] in PRINTED_RECTANGLES_2_4_12 {
        let printed = Rectangle::new(t, p1, p2, Direction::Ccw)?;
        if let Some(found) = plan.find(&printed, PRINTED_TOLERANCE_2_4_12) {
            thesis_three.push(found.clone());
        }
    }
    summary.push(format!(
        "(2.4.12): R(3π/2, 0.1A1 + √0.98A2 + 0.1A3): {} of the 3 printed rectangles found; {} rectangles in all (both directions, both quaternion signs), max error {:.1e} rad",
        thesis_three.len(),
        plan.rectangles.len(),
        plan.max_error
    ));
    write_plan_csv(&dir.join("plan_2_4_12.csv"), &plan.rectangles)?;
    plot_rectangle_panels(
        &dir.join("figure_2_6.png"),
        "Figure 2.6: the three rectangles of (2.4.12)",
        &thesis_three,
        None,
    )?;
    blocks.push(Block::Table {
        header: [
            "ϑ",
            "φ1",
            "φ2",
            "direction",
            "path length [R]",
            "error [rad]",
        ]
        .map(String::from)
        .to_vec(),
        rows: plan
            .rectangles
            .iter()
            .map(|r| {
                vec![
                    format!("{:.5}", r.theta),
                    format!("{:.5}", r.phi1),
                    format!("{:.5}", r.phi2),
                    r.direction.as_str().to_owned(),
                    format!("{:.4}", r.path_length),
                    format!("{:.1e}", r.error),
                ]
            })
            .collect(),
    });
    blocks.push(Block::Text(
        "Every rectangle with φ2 ∈ [0, 3π] producing R(3π/2, 0.1A1 + √0.98A2 + 0.1A3). The three counter-clockwise \
         rectangles whose quaternion has q0 = cos(3π/4) are those printed in (2.4.12) (ERRATA items 2, 7); the other \
         sign of the quaternion and clockwise travel give further rectangles the thesis does not list."
            .into(),
    ));
    blocks.push(Block::image(
        "figure_2_6.png",
        "Figure 2.6: the three rectangles of (2.4.12)",
    ));
    blocks.push(Block::data("plan_2_4_12.csv", "all solutions"));

    // Euler plans, Figures 2.7–2.9.
    for (set, angles, file) in [
        ("3-2-3", [0.6, 1.1, 1.4], "figure_2_7.png"),
        ("3-1-3", [0.6, 1.1, 1.4], "figure_2_8.png"),
        ("3-2-1", [0.6, 0.5, 1.4], "figure_2_9a.png"),
        ("3-1-2", [0.6, 0.5, 1.4], "figure_2_9b.png"),
    ] {
        let plan = euler_plan_report(&euler_plan(EulerSet::from_name(set)?, angles)?);
        plot_rectangles(
            &dir.join(file),
            &format!(
                "{set} Euler angles ν = ({}, {}, {}): three rectangles",
                angles[0], angles[1], angles[2]
            ),
            &plan.rectangles,
        )?;
        summary.push(format!(
            "Euler plan {set} ν = {angles:?}: composed holonomy error {:.1e} rad",
            plan.error
        ));
        blocks.push(Block::image(
            file,
            format!(
                "{set}: rectangle 1 cw, 2 ccw, 3 cw (ERRATA item 6); composed error {:.1e} rad",
                plan.error
            ),
        ));
    }

    // Rolling: both integrators against the closed form.
    let rows = integrator_study()?;
    write_study(dir, &rows)?;
    for integrator in [Integrator::Exact, Integrator::Rk4] {
        if let Some(row) = rows
            .iter()
            .find(|x| x.path == StudyPath::Circle && x.integrator == integrator && x.steps == 256)
        {
            summary.push(format!(
                "roll around a circle of radius 2R, {}, 256 steps: error {:.1e} rad in {:.1e} s",
                integrator.as_str(),
                row.error,
                row.wall_time_s
            ));
        }
    }
    summary.push(format!(
        "roll around the rectangle of (2.4.10), exact integrator: error {:.1e} rad",
        rolled.error_vs_closed_form
    ));
    blocks.push(Block::image("roll_study.png", "Error of the final orientation against the closed form vs wall time, exact (Lie-group exponential) and RK4 integrators, 8…4096 steps"));
    blocks.push(Block::data(
        "roll_study.csv",
        "speed vs error of both integrators",
    ));

    Ok(Section {
        title: "Rolling sphere: holonomy and path planning (Ch. 2)".into(),
        summary,
        blocks,
    })
}
