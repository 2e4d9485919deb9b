//! `rollstack sphere holonomy|plan|euler-plan|roll`: the rolling sphere of Ch. 2.
//!
//! Lengths are in units of the sphere's radius R (so a side of length ϑR is given as the
//! angle ϑ). Components are on {A1, A2, A3 = E3}; for the Euler plan the ground basis E.

use crate::angles::{parse_angle_list, parse_number_list, Angle};
use crate::output::{ensure_dir, print_json, write_csv_f64, write_run_json};
use crate::plot::{err, with_png, LinePlot, Series, FONT, PALETTE};
use anyhow::{bail, Context, Result};
use clap::{Args, Subcommand, ValueEnum};
use holonomy::rectangle::{holonomy_angle, no_holonomy_family};
use holonomy::roll::{axis_angle, circle_holonomy, roll, CentrePath, Integrator, Trajectory};
use holonomy::{
    euler_plan, holonomy_components, plan_rectangles, rectangle_holonomy,
    rectangle_holonomy_closed_form, shortest, Direction, EulerPlan, PlacedRectangle,
    PlannedRectangle, Rectangle,
};
use nalgebra::{Rotation3, Unit, UnitQuaternion, Vector3};
use plotters::prelude::*;
use rotations::{quaternion_from_matrix, rotation_distance, AxisAngle, EulerSet};
use serde::Serialize;
use std::f64::consts::{PI, TAU};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Arguments of `rollstack sphere`.
#[derive(Debug, Args)]
pub struct SphereArgs {
    /// Which computation.
    #[command(subcommand)]
    pub command: SphereCommand,
}

/// The subcommands of `rollstack sphere`.
#[derive(Debug, Subcommand)]
pub enum SphereCommand {
    /// Holonomy of one rectangle (2.4.2), (2.4.6), (B.1.2).
    Holonomy(HolonomyArgs),
    /// Every rectangle (φ2 in [0, 3π]) that produces a target rotation (App. C).
    Plan(PlanArgs),
    /// Three rectangles through the Euler angles of a rotation (§2.5).
    EulerPlan(EulerPlanArgs),
    /// Integrate the rolling constraint along a rectangle, polygon or circle (2.3.4).
    Roll(RollArgs),
}

/// The rectangle flags shared by `holonomy` and `roll`.
#[derive(Debug, Args)]
pub struct RectangleArgs {
    /// ϑ = W/R: side along A2, rad (`90deg`, `3pi/2` accepted).
    #[arg(long, allow_hyphen_values = true)]
    pub theta: Angle,
    /// φ1 = H1/R: start S measured from the corner along A1, rad, in [0, φ2].
    #[arg(long, allow_hyphen_values = true)]
    pub phi1: Angle,
    /// φ2 = H2/R: side along A1, rad.
    #[arg(long, allow_hyphen_values = true)]
    pub phi2: Angle,
    /// Travel clockwise (viewed from above); default counter-clockwise, the product (2.4.2).
    #[arg(long)]
    pub cw: bool,
}

impl RectangleArgs {
    fn rectangle(&self) -> Result<Rectangle> {
        let d = if self.cw {
            Direction::Cw
        } else {
            Direction::Ccw
        };
        Ok(Rectangle::new(self.theta.0, self.phi1.0, self.phi2.0, d)?)
    }
}

/// Arguments of `rollstack sphere holonomy`.
#[derive(Debug, Args)]
pub struct HolonomyArgs {
    /// The rectangle.
    #[command(flatten)]
    pub rect: RectangleArgs,
    /// Print one JSON object on stdout.
    #[arg(long)]
    pub json: bool,
    /// Write holonomy.csv, the path (rectangle.png) and the level sets of ψ (Figure 2.5) here.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// Arguments of `rollstack sphere plan`.
#[derive(Debug, Args)]
pub struct PlanArgs {
    /// Angle of the target rotation ψ, rad (`270deg`, `3pi/2` accepted).
    #[arg(long, allow_hyphen_values = true)]
    pub angle: Angle,
    /// Axis of the target rotation, `X,Y,Z` on A1, A2, A3 (normalised; not zero).
    #[arg(long, allow_hyphen_values = true)]
    pub axis: String,
    /// Print one JSON object on stdout.
    #[arg(long)]
    pub json: bool,
    /// Write plan.csv and the rectangles (plan.png, cf. Figure 2.6) here.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// Arguments of `rollstack sphere euler-plan`.
#[derive(Debug, Args)]
pub struct EulerPlanArgs {
    /// Euler set: 3-2-3, 3-1-3, 3-2-1 or 3-1-2.
    #[arg(long)]
    pub set: String,
    /// The three Euler angles ν1,ν2,ν3, rad (`30deg`, `pi/4` accepted).
    #[arg(long, allow_hyphen_values = true)]
    pub angles: String,
    /// Print one JSON object on stdout.
    #[arg(long)]
    pub json: bool,
    /// Write euler_plan.csv and the three paths (euler_plan.png, cf. Figures 2.7–2.9) here.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// The two integrators of `sphere roll`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum IntegratorArg {
    /// Exact flow of each segment (Lie-group exponential).
    Exact,
    /// RK4 on the unit quaternion.
    Rk4,
}

impl From<IntegratorArg> for Integrator {
    fn from(a: IntegratorArg) -> Self {
        match a {
            IntegratorArg::Exact => Integrator::Exact,
            IntegratorArg::Rk4 => Integrator::Rk4,
        }
    }
}

/// Arguments of `rollstack sphere roll`.
#[derive(Debug, Args)]
pub struct RollArgs {
    /// ϑ = W/R of the rectangle, rad (ignored with --circle or --polygon).
    #[arg(long, allow_hyphen_values = true, default_value = "4pi/3")]
    pub theta: Angle,
    /// φ1 = H1/R of the rectangle, rad.
    #[arg(long, allow_hyphen_values = true, default_value = "pi/2")]
    pub phi1: Angle,
    /// φ2 = H2/R of the rectangle, rad.
    #[arg(long, allow_hyphen_values = true, default_value = "3pi")]
    pub phi2: Angle,
    /// Travel clockwise (rectangle and circle).
    #[arg(long)]
    pub cw: bool,
    /// Roll around a circle of this radius (units of R) instead of the rectangle.
    #[arg(long, conflicts_with = "polygon")]
    pub circle: Option<f64>,
    /// Roll around the closed polygon `x1,y1,x2,y2,...` (units of R) instead.
    #[arg(long, allow_hyphen_values = true)]
    pub polygon: Option<String>,
    /// Number of integration steps (at least one per side).
    #[arg(long, default_value_t = 400)]
    pub steps: usize,
    /// Integrator: `exact` (Lie-group exponential per segment) or `rk4` (on the quaternion).
    #[arg(long, value_enum, default_value = "exact")]
    pub integrator: IntegratorArg,
    /// Also run the speed-vs-error study of both integrators (roll_study.csv/png in --out).
    #[arg(long)]
    pub study: bool,
    /// Print one JSON object on stdout.
    #[arg(long)]
    pub json: bool,
    /// Write roll.csv (trajectory), roll_traces.png (Figure 2.1) and run.json here.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// Runs `rollstack sphere ...`.
///
/// # Errors
/// Bad input, or a file that cannot be written.
pub fn run(args: &SphereArgs) -> Result<()> {
    match &args.command {
        SphereCommand::Holonomy(a) => run_holonomy(a),
        SphereCommand::Plan(a) => run_plan(a),
        SphereCommand::EulerPlan(a) => run_euler_plan(a),
        SphereCommand::Roll(a) => run_roll(a),
    }
}

fn rows(m: &nalgebra::Matrix3<f64>) -> [[f64; 3]; 3] {
    [0, 1, 2].map(|i| [m[(i, 0)], m[(i, 1)], m[(i, 2)]])
}

// ---------------------------------------------------------------- holonomy

/// JSON of `sphere holonomy` (DESIGN.md keys first).
#[derive(Debug, Serialize)]
pub struct HolonomyReport {
    /// Canonical angle ψ in [0, π], rad.
    pub angle: f64,
    /// Canonical unit axis s on A1, A2, A3.
    pub axis: [f64; 3],
    /// Canonical quaternion [q0, q1, q2, q3], q0 ≥ 0.
    pub quaternion: [f64; 4],
    /// Rows of S: entry [i][k] = Aᵢ · S Aₖ.
    pub matrix: [[f64; 3]; 3],
    /// e3(t1) = S E3 on A1, A2, A3.
    pub e3_final: [f64; 3],
    /// The closed form (2.4.6) as computed (its sign, q0 may be negative).
    pub quaternion_closed_form: [f64; 4],
    /// Angle between the product (2.4.2) and the closed form (2.4.6), rad.
    pub closed_form_error: f64,
    /// Largest entry difference between the product and the components (B.1.2).
    pub components_error: f64,
    /// Path length 2(ϑ + φ2), units of R.
    pub path_length: f64,
    /// The no-holonomy family (2.4.8), if any.
    pub no_holonomy: Option<String>,
}

/// The holonomy report of one rectangle.
#[must_use]
pub fn holonomy_report(r: &Rectangle) -> HolonomyReport {
    let s = rectangle_holonomy(r);
    let aa = AxisAngle::from_rotation(&s);
    let q = quaternion_from_matrix(s.matrix());
    let qc = rectangle_holonomy_closed_form(r);
    let e3 = s * Vector3::z();
    HolonomyReport {
        angle: aa.angle,
        axis: [aa.axis.x, aa.axis.y, aa.axis.z],
        quaternion: [q.w, q.i, q.j, q.k],
        matrix: rows(s.matrix()),
        e3_final: [e3.x, e3.y, e3.z],
        quaternion_closed_form: [qc.w, qc.i, qc.j, qc.k],
        closed_form_error: rotation_distance(&qc.to_rotation_matrix(), &s),
        components_error: (holonomy_components(r) - s.matrix()).amax(),
        path_length: r.path_length(),
        no_holonomy: no_holonomy_family(r, 1e-12).map(|f| format!("{f:?}")),
    }
}

fn run_holonomy(a: &HolonomyArgs) -> Result<()> {
    let r = a.rect.rectangle()?;
    let rep = holonomy_report(&r);
    if let Some(dir) = &a.out {
        ensure_dir(dir)?;
        let s = rectangle_holonomy(&r);
        let m = s.matrix();
        write_csv_f64(
            &dir.join("holonomy.csv"),
            &[
                "theta", "phi1", "phi2", "ccw", "angle", "axis1", "axis2", "axis3", "s11", "s12",
                "s13", "s21", "s22", "s23", "s31", "s32", "s33",
            ],
            &[vec![
                r.theta,
                r.phi1,
                r.phi2,
                f64::from(u8::from(r.direction == Direction::Ccw)),
                rep.angle,
                rep.axis[0],
                rep.axis[1],
                rep.axis[2],
                m[(0, 0)],
                m[(0, 1)],
                m[(0, 2)],
                m[(1, 0)],
                m[(1, 1)],
                m[(1, 2)],
                m[(2, 0)],
                m[(2, 1)],
                m[(2, 2)],
            ]],
        )?;
        plot_rectangles(
            &dir.join("rectangle.png"),
            "Rectangular path of the centre (units of R)",
            &[placed(r)],
        )?;
        plot_level_sets(&dir.join("psi_level_sets.png"), Some((r.theta, r.phi2)))?;
        write_run_json(dir, "sphere holonomy", &r, &serde_json::json!({}))?;
    }
    if a.json {
        return print_json(&rep);
    }
    println!(
        "S = Ŝ(ϑ = {}, φ1 = {}, φ2 = {}, {})",
        r.theta,
        r.phi1,
        r.phi2,
        r.direction.as_str()
    );
    println!(
        "  ψ = {:.9} rad ({:.6}°), s = [{:.6}, {:.6}, {:.6}]",
        rep.angle,
        rep.angle.to_degrees(),
        rep.axis[0],
        rep.axis[1],
        rep.axis[2]
    );
    println!(
        "  e3(t1) = [{:.6}, {:.6}, {:.6}]",
        rep.e3_final[0], rep.e3_final[1], rep.e3_final[2]
    );
    println!(
        "  product vs closed form (2.4.6): {:.1e} rad; vs components (B.1.2): {:.1e}",
        rep.closed_form_error, rep.components_error
    );
    if let Some(f) = &rep.no_holonomy {
        println!("  no holonomy: (2.4.8) family {f}");
    }
    Ok(())
}

fn placed(r: Rectangle) -> PlacedRectangle {
    PlacedRectangle {
        rectangle: r,
        heading: 0.0,
        start: [0.0, 0.0],
    }
}

// ---------------------------------------------------------------- plan

/// One rectangle in the JSON of `sphere plan` and `sphere euler-plan`.
#[derive(Debug, Serialize)]
pub struct RectangleJson {
    /// ϑ, rad.
    pub theta: f64,
    /// φ1, rad.
    pub phi1: f64,
    /// φ2, rad.
    pub phi2: f64,
    /// `ccw` or `cw`.
    pub direction: &'static str,
    /// Angle of R_targetᵀ S (plan), or between the rectangle's holonomy and its Euler
    /// factor R(νᵢ, gᵢ) (euler-plan), rad.
    pub error: f64,
    /// Corners of the centre's path, ground coordinates in units of R, in order of travel.
    pub waypoints: Vec<[f64; 2]>,
    /// Path length 2(ϑ + φ2), units of R.
    pub path_length: f64,
    /// Heading of A1 from E1, rad (0 for `plan`).
    pub heading: f64,
    /// True when any φ1 in [0, φ2] works ((2.4.9)₂).
    pub phi1_free: bool,
}

fn rectangle_json(p: &PlacedRectangle, error: f64, phi1_free: bool) -> RectangleJson {
    let r = p.rectangle;
    RectangleJson {
        theta: r.theta,
        phi1: r.phi1,
        phi2: r.phi2,
        direction: r.direction.as_str(),
        error,
        waypoints: p.waypoints(),
        path_length: r.path_length(),
        heading: p.heading,
        phi1_free,
    }
}

/// JSON of `sphere plan`.
#[derive(Debug, Serialize)]
pub struct PlanReport {
    /// Every solution with φ2 in [0, 3π].
    pub rectangles: Vec<RectangleJson>,
    /// Index into `rectangles` of the shortest path.
    pub shortest: Option<usize>,
    /// Largest verified error, rad.
    pub max_error: f64,
}

/// Parses `--angle` and `--axis` into a target rotation.
///
/// # Errors
/// A zero, non-finite or malformed axis.
pub fn parse_target(angle: f64, axis: &str) -> Result<Rotation3<f64>> {
    let v = parse_number_list(axis)
        .map_err(anyhow::Error::msg)
        .context("--axis")?;
    if v.len() != 3 {
        bail!(
            "--axis needs three comma-separated numbers X,Y,Z, got {}",
            v.len()
        );
    }
    Ok(AxisAngle::new(angle, Vector3::new(v[0], v[1], v[2]))
        .context("--axis")?
        .to_rotation())
}

/// Writes every planned rectangle (ϑ, φ1, φ2, direction, error, path length) as CSV.
///
/// # Errors
/// When the file cannot be written.
pub fn write_plan_csv(path: &Path, plans: &[PlannedRectangle]) -> Result<()> {
    let rows: Vec<Vec<f64>> = plans
        .iter()
        .map(|p| {
            let r = p.rectangle;
            vec![
                r.theta,
                r.phi1,
                r.phi2,
                f64::from(u8::from(r.direction == Direction::Ccw)),
                p.error,
                r.path_length(),
            ]
        })
        .collect();
    write_csv_f64(
        path,
        &["theta", "phi1", "phi2", "ccw", "error", "path_length"],
        &rows,
    )
}

/// Plans and reports.
///
/// # Errors
/// An identity target.
pub fn plan_report(target: &Rotation3<f64>) -> Result<(Vec<PlannedRectangle>, PlanReport)> {
    let plans = plan_rectangles(target)?;
    let best = shortest(&plans).and_then(|b| plans.iter().position(|p| p == b));
    let rectangles = plans
        .iter()
        .map(|p| rectangle_json(&placed(p.rectangle), p.error, p.phi1_free))
        .collect();
    let max_error = plans.iter().map(|p| p.error).fold(0.0, f64::max);
    Ok((
        plans,
        PlanReport {
            rectangles,
            shortest: best,
            max_error,
        },
    ))
}

fn run_plan(a: &PlanArgs) -> Result<()> {
    let target = parse_target(a.angle.0, &a.axis)?;
    let start = Instant::now();
    let (plans, rep) = plan_report(&target)?;
    let seconds = start.elapsed().as_secs_f64();
    if let Some(dir) = &a.out {
        ensure_dir(dir)?;
        write_plan_csv(&dir.join("plan.csv"), &plans)?;
        let placed: Vec<_> = plans.iter().map(|p| placed(p.rectangle)).collect();
        plot_rectangle_panels(&dir.join("plan.png"), &placed)?;
        write_run_json(
            dir,
            "sphere plan",
            &serde_json::json!({"angle": a.angle.0, "axis": a.axis}),
            &serde_json::json!({"plan_s": seconds}),
        )?;
    }
    if a.json {
        return print_json(&rep);
    }
    println!("{} rectangle(s) with φ2 in [0, 3π]:", rep.rectangles.len());
    for (i, r) in rep.rectangles.iter().enumerate() {
        let mark = if rep.shortest == Some(i) {
            "  <- shortest"
        } else {
            ""
        };
        println!(
            "  ϑ = {:.6}, φ1 = {:.6}, φ2 = {:.6}, {:>3}, length {:.4} R, error {:.1e}{mark}",
            r.theta, r.phi1, r.phi2, r.direction, r.path_length, r.error
        );
    }
    Ok(())
}

// ---------------------------------------------------------------- euler-plan

/// JSON of `sphere euler-plan`.
#[derive(Debug, Serialize)]
pub struct EulerPlanReport {
    /// The three rectangles in order of travel (ground frame).
    pub rectangles: Vec<RectangleJson>,
    /// Angle of R_targetᵀ R_achieved, rad.
    pub error: f64,
    /// The set.
    pub set: String,
    /// The angles used (ν1, ν3 reduced to [0, 2π)).
    pub angles: [f64; 3],
    /// Rows of the target (components on E).
    pub target_matrix: [[f64; 3]; 3],
}

/// The report of an Euler plan. Each rectangle's `error` is the angle between its holonomy
/// and the elementary rotation R(νᵢ, gᵢ) it stands for; `error` is that of the composition.
#[must_use]
pub fn euler_report(plan: &EulerPlan) -> EulerPlanReport {
    EulerPlanReport {
        rectangles: plan
            .rectangles
            .iter()
            .zip(plan.rectangle_errors)
            .map(|(p, e)| rectangle_json(p, e, false))
            .collect(),
        error: plan.error,
        set: plan.set.clone(),
        angles: plan.angles,
        target_matrix: rows(plan.target.matrix()),
    }
}

fn run_euler_plan(a: &EulerPlanArgs) -> Result<()> {
    let set = EulerSet::from_name(&a.set)?;
    let v = parse_angle_list(&a.angles)
        .map_err(anyhow::Error::msg)
        .context("--angles")?;
    if v.len() != 3 {
        bail!(
            "--angles needs three comma-separated angles, got {}",
            v.len()
        );
    }
    let plan = euler_plan(set, [v[0], v[1], v[2]])?;
    let rep = euler_report(&plan);
    if let Some(dir) = &a.out {
        ensure_dir(dir)?;
        let rows: Vec<Vec<f64>> = plan
            .rectangles
            .iter()
            .enumerate()
            .map(|(i, p)| {
                let r = p.rectangle;
                #[allow(clippy::cast_precision_loss)]
                let index = (i + 1) as f64;
                vec![
                    index,
                    r.theta,
                    r.phi1,
                    r.phi2,
                    f64::from(u8::from(r.direction == Direction::Ccw)),
                    p.heading,
                ]
            })
            .collect();
        write_csv_f64(
            &dir.join("euler_plan.csv"),
            &["rectangle", "theta", "phi1", "phi2", "ccw", "heading"],
            &rows,
        )?;
        plot_rectangles(
            &dir.join("euler_plan.png"),
            &format!(
                "Three rectangles for the {} Euler angles (units of R)",
                plan.set
            ),
            &plan.rectangles,
        )?;
        write_run_json(
            dir,
            "sphere euler-plan",
            &serde_json::json!({"set": a.set, "angles": v}),
            &serde_json::json!({}),
        )?;
    }
    if a.json {
        return print_json(&rep);
    }
    println!(
        "{} angles (ν1, ν2, ν3) = ({:.6}, {:.6}, {:.6}); composed error {:.1e} rad",
        rep.set, rep.angles[0], rep.angles[1], rep.angles[2], rep.error
    );
    for (i, r) in rep.rectangles.iter().enumerate() {
        println!(
            "  {}: ϑ = {:.6}, φ1 = {:.6}, φ2 = {:.6}, {:>3}, heading {:.6}",
            i + 1,
            r.theta,
            r.phi1,
            r.phi2,
            r.direction,
            r.heading
        );
    }
    Ok(())
}

// ---------------------------------------------------------------- roll

/// JSON of `sphere roll`.
#[derive(Debug, Serialize)]
pub struct RollReport {
    /// Canonical angle of the final orientation, rad.
    pub angle: f64,
    /// Canonical axis of the final orientation on A1, A2, A3.
    pub axis: [f64; 3],
    /// Angle between the integrated and the closed-form holonomy, rad.
    pub error_vs_closed_form: f64,
    /// `exact` or `rk4`.
    pub integrator: &'static str,
    /// Steps taken.
    pub steps: usize,
    /// Path length, units of R.
    pub path_length: f64,
    /// Wall time of the integration, s.
    pub wall_time_s: f64,
}

/// The path of `sphere roll` and its closed-form holonomy.
///
/// # Errors
/// Bad path input.
pub fn roll_path(a: &RollArgs) -> Result<(CentrePath, Rotation3<f64>, String)> {
    let d = if a.cw { Direction::Cw } else { Direction::Ccw };
    if let Some(rho) = a.circle {
        let path = CentrePath::circle(rho, d)?;
        return Ok((
            path,
            circle_holonomy(rho, 1.0, d)?,
            format!("circle of radius {rho} R"),
        ));
    }
    if let Some(text) = &a.polygon {
        let v = parse_number_list(text)
            .map_err(anyhow::Error::msg)
            .context("--polygon")?;
        if v.len() < 4 || v.len() % 2 != 0 {
            bail!("--polygon needs an even number (at least 4) of coordinates x1,y1,x2,y2,...");
        }
        let verts: Vec<[f64; 2]> = v.chunks(2).map(|c| [c[0], c[1]]).collect();
        let path = CentrePath::polygon(&verts)?;
        return Ok((
            path.clone(),
            polygon_holonomy(&path),
            format!("polygon of {} sides", path.segments().len()),
        ));
    }
    let r = Rectangle::new(a.theta.0, a.phi1.0, a.phi2.0, d)?;
    Ok((
        CentrePath::rectangle(&r, 1.0)?,
        rectangle_holonomy(&r),
        "rectangle".into(),
    ))
}

/// The holonomy of a polygon as the product of its side rotations R(L, E3 × d) (2.3.5).
#[must_use]
pub fn polygon_holonomy(path: &CentrePath) -> Rotation3<f64> {
    let mut q = UnitQuaternion::identity();
    for seg in path.segments() {
        let (_, d) = seg.point_and_tangent(0.0);
        q = UnitQuaternion::from_axis_angle(
            &Unit::new_normalize(Vector3::z().cross(&d)),
            seg.length(),
        ) * q;
    }
    q.to_rotation_matrix()
}

fn roll_report(
    traj: &Trajectory,
    exact: &Rotation3<f64>,
    integrator: Integrator,
    steps: usize,
    length: f64,
    seconds: f64,
) -> RollReport {
    let q = traj.final_orientation();
    let (angle, axis) = axis_angle(&q);
    RollReport {
        angle,
        axis: [axis.x, axis.y, axis.z],
        error_vs_closed_form: rotation_distance(&q.to_rotation_matrix(), exact),
        integrator: match integrator {
            Integrator::Exact => "exact",
            Integrator::Rk4 => "rk4",
        },
        steps,
        path_length: length,
        wall_time_s: seconds,
    }
}

/// One row of the speed-vs-error study.
#[derive(Debug, Clone, Serialize)]
pub struct StudyRow {
    /// `rectangle` or `circle`.
    pub path: &'static str,
    /// `exact` or `rk4`.
    pub integrator: &'static str,
    /// Steps requested.
    pub steps: usize,
    /// Error of the final orientation vs the closed form, rad.
    pub error: f64,
    /// Median wall time of one run, s.
    pub wall_time_s: f64,
}

/// The speed-vs-error study: the rectangle of (2.4.10) and a circle of radius 2R, both
/// integrators, 8 … 4096 steps; wall time is the median of repeated runs
/// (build with `--release` for meaningful times).
///
/// # Errors
/// Never for the built-in paths.
pub fn roll_study() -> Result<Vec<StudyRow>> {
    let r = Rectangle::new(
        4.0 * PI / 3.0 - 0.5,
        PI / 2.0 - 0.4,
        3.0 * PI,
        Direction::Ccw,
    )?;
    let cases = [
        (
            "rectangle",
            CentrePath::rectangle(&r, 1.0)?,
            rectangle_holonomy(&r),
        ),
        (
            "circle",
            CentrePath::circle(2.0, Direction::Ccw)?,
            circle_holonomy(2.0, 1.0, Direction::Ccw)?,
        ),
    ];
    let mut out = Vec::new();
    for (name, path, exact) in &cases {
        for integrator in [Integrator::Exact, Integrator::Rk4] {
            for k in 3..=12 {
                let steps = 1usize << k;
                let mut times = Vec::new();
                let mut error = 0.0;
                let reps = (50_000 / steps).clamp(3, 100);
                for _ in 0..reps {
                    let t0 = Instant::now();
                    let traj = roll(path, 1.0, integrator, steps)?;
                    times.push(t0.elapsed().as_secs_f64());
                    error =
                        rotation_distance(&traj.final_orientation().to_rotation_matrix(), exact);
                }
                times.sort_by(f64::total_cmp);
                out.push(StudyRow {
                    path: name,
                    integrator: if integrator == Integrator::Exact {
                        "exact"
                    } else {
                        "rk4"
                    },
                    steps,
                    error,
                    wall_time_s: times[times.len() / 2],
                });
            }
        }
    }
    Ok(out)
}

/// Writes roll_study.csv and roll_study.png (error against wall time, log–log).
///
/// # Errors
/// When a file cannot be written.
pub fn write_study(dir: &Path, rows: &[StudyRow]) -> Result<()> {
    crate::output::write_csv(
        &dir.join("roll_study.csv"),
        &["path", "integrator", "steps", "error_rad", "wall_time_s"],
        rows.iter().map(|r| {
            vec![
                r.path.to_owned(),
                r.integrator.to_owned(),
                r.steps.to_string(),
                r.error.to_string(),
                r.wall_time_s.to_string(),
            ]
        }),
    )?;
    let mut plot = LinePlot::new(
        "Rolling integrators: error of the final orientation vs wall time",
        "log10 of the wall time [s]",
        "log10 of the error [rad] (floored at 1e-17)",
    );
    for path in ["rectangle", "circle"] {
        for integ in ["exact", "rk4"] {
            let pts = rows
                .iter()
                .filter(|r| r.path == path && r.integrator == integ)
                .map(|r| (r.wall_time_s.log10(), r.error.max(1e-17).log10()))
                .collect();
            plot = plot.with(Series::line(format!("{integ}, {path}"), pts));
        }
    }
    plot.save(&dir.join("roll_study.png"), (900, 600))
}

fn run_roll(a: &RollArgs) -> Result<()> {
    let (path, exact, label) = roll_path(a)?;
    let integrator: Integrator = a.integrator.into();
    let t0 = Instant::now();
    let traj = roll(&path, 1.0, integrator, a.steps)?;
    let seconds = t0.elapsed().as_secs_f64();
    let rep = roll_report(&traj, &exact, integrator, a.steps, path.length(), seconds);
    let study = if a.study { Some(roll_study()?) } else { None };
    if let Some(dir) = &a.out {
        ensure_dir(dir)?;
        write_trajectory(&dir.join("roll.csv"), &traj)?;
        plot_traces(
            &dir.join("roll_traces.png"),
            &traj,
            &format!("Top view of the traces of C (i) and X (ii): {label}"),
        )?;
        if let Some(rows) = &study {
            write_study(dir, rows)?;
        }
        write_run_json(
            dir,
            "sphere roll",
            &serde_json::json!({"path": label, "steps": a.steps, "integrator": rep.integrator}),
            &serde_json::json!({"integration_s": seconds}),
        )?;
    }
    if a.json {
        return print_json(&rep);
    }
    println!(
        "{label}, {} steps, {}: ψ = {:.9} rad, s = [{:.6}, {:.6}, {:.6}]",
        a.steps, rep.integrator, rep.angle, rep.axis[0], rep.axis[1], rep.axis[2]
    );
    println!(
        "  error vs closed form: {:.2e} rad; wall time {:.2e} s",
        rep.error_vs_closed_form, seconds
    );
    if let Some(rows) = &study {
        println!("  study (path, integrator, steps, error rad, wall time s):");
        for r in rows {
            println!(
                "    {:<9} {:<5} {:>5} {:>9.2e} {:>9.2e}",
                r.path, r.integrator, r.steps, r.error, r.wall_time_s
            );
        }
    }
    Ok(())
}

/// Writes a trajectory as CSV: s, centre, marked point X, quaternion.
///
/// # Errors
/// When the file cannot be written.
pub fn write_trajectory(path: &Path, traj: &Trajectory) -> Result<()> {
    let rows: Vec<Vec<f64>> = traj
        .samples
        .iter()
        .map(|s| {
            let q = s.orientation;
            vec![
                s.s,
                s.centre[0],
                s.centre[1],
                s.centre[2],
                s.marked_point[0],
                s.marked_point[1],
                s.marked_point[2],
                q.w,
                q.i,
                q.j,
                q.k,
            ]
        })
        .collect();
    write_csv_f64(
        path,
        &[
            "s", "cx", "cy", "cz", "xx", "xy", "xz", "q0", "q1", "q2", "q3",
        ],
        &rows,
    )
}

// ---------------------------------------------------------------- figures

/// Figure 2.1: top view of the traces of the centre C (i) and the marked point X (ii).
///
/// # Errors
/// When the PNG cannot be written.
pub fn plot_traces(path: &Path, traj: &Trajectory, title: &str) -> Result<()> {
    let c: Vec<(f64, f64)> = traj
        .samples
        .iter()
        .map(|s| (s.centre[0], s.centre[1]))
        .collect();
    let x: Vec<(f64, f64)> = traj
        .samples
        .iter()
        .map(|s| (s.marked_point[0], s.marked_point[1]))
        .collect();
    let ends = vec![x[0], *x.last().unwrap_or(&x[0])];
    let mut plot = LinePlot::new(title, "E1 [R]", "E2 [R]")
        .with(Series::line("i: centre C", c))
        .with(Series::line("ii: material point X", x))
        .with(Series::markers("X at t0 (A) and t1 (B)", ends));
    plot.equal_aspect = true;
    plot.save(path, (800, 800))
}

/// Draws placed rectangles (the centre's path) in one frame, numbered, with the start S
/// (the direction of travel is in the legend).
///
/// # Errors
/// When the PNG cannot be written.
pub fn plot_rectangles(path: &Path, title: &str, rects: &[PlacedRectangle]) -> Result<()> {
    let mut plot = LinePlot::new(title, "E1 [R]", "E2 [R]");
    plot.equal_aspect = true;
    for (i, p) in rects.iter().enumerate() {
        let pts = p.waypoints().into_iter().map(|w| (w[0], w[1])).collect();
        plot = plot.with(Series::line(
            format!(
                "{}: ϑ={:.3}, φ1={:.3}, φ2={:.3}, {}",
                i + 1,
                p.rectangle.theta,
                p.rectangle.phi1,
                p.rectangle.phi2,
                p.rectangle.direction.as_str()
            ),
            pts,
        ));
    }
    plot = plot.with(Series::markers("S", vec![(0.0, 0.0)]));
    plot.save(path, (900, 900))
}

/// Figure 2.6: each rectangle in its own panel (at most six), same scale.
///
/// # Errors
/// When the PNG cannot be written.
pub fn plot_rectangle_panels(path: &Path, rects: &[PlacedRectangle]) -> Result<()> {
    let rects = &rects[..rects.len().min(6)];
    let n = rects.len().max(1);
    #[allow(clippy::cast_possible_truncation)]
    let cols = n.min(3) as u32;
    #[allow(clippy::cast_possible_truncation)]
    let rows_n = n.div_ceil(3) as u32;
    with_png(path, (420 * cols, 440 * rows_n), |root| {
        let areas = root.split_evenly((rows_n as usize, cols as usize));
        for (p, area) in rects.iter().zip(areas.iter()) {
            let r = p.rectangle;
            let mut plot = LinePlot::new(
                format!(
                    "ϑ={:.4} φ1={:.4} φ2={:.4} {}",
                    r.theta,
                    r.phi1,
                    r.phi2,
                    r.direction.as_str()
                ),
                "A1 [R]",
                "A2 [R]",
            )
            .with(Series::line(
                "",
                p.waypoints().into_iter().map(|w| (w[0], w[1])).collect(),
            ))
            .with(Series::markers("", vec![(0.0, 0.0)]));
            plot.equal_aspect = true;
            plot.draw(area)?;
        }
        Ok(())
    })
}

/// Figure 2.5: level sets of ψ(ϑ, φ2) over [0, 2π]², from (2.4.11) corrected (ERRATA
/// item 1): sin²(φ2/2) = (1 − cos(ψ/2)) / (2 sin²(ϑ/2)), drawn exactly branch by branch.
/// A marked point shows `mark` if given.
///
/// # Errors
/// When the PNG cannot be written.
pub fn plot_level_sets(path: &Path, mark: Option<(f64, f64)>) -> Result<()> {
    let levels = [5.0, 45.0, 90.0, 135.0, 180.0, 225.0, 270.0, 315.0_f64];
    with_png(path, (820, 800), |root| {
        let mut chart = ChartBuilder::on(root)
            .caption(
                "Level sets of ψ(ϑ, φ2), (2.4.11) corrected (Figure 2.5)",
                (FONT, 22),
            )
            .margin(12)
            .x_label_area_size(45)
            .y_label_area_size(60)
            .build_cartesian_2d(0.0..TAU, 0.0..TAU)
            .map_err(err)?;
        chart
            .configure_mesh()
            .x_desc("ϑ [rad]")
            .y_desc("φ2 [rad]")
            .label_style((FONT, 14))
            .axis_desc_style((FONT, 16))
            .draw()
            .map_err(err)?;
        for (i, deg) in levels.iter().enumerate() {
            let color = PALETTE[i % PALETTE.len()];
            for branch in level_set_branches(deg.to_radians()) {
                chart
                    .draw_series(LineSeries::new(branch, color.stroke_width(2)))
                    .map_err(err)?;
            }
            chart
                .draw_series(std::iter::empty::<Circle<(f64, f64), i32>>())
                .map_err(err)?
                .label(format!("ψ = {deg}°"))
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 18, y)], color.stroke_width(2))
                });
        }
        if let Some((t, p)) = mark {
            let (t, p) = (t.rem_euclid(TAU), p.rem_euclid(TAU));
            chart
                .draw_series(std::iter::once(Circle::new((t, p), 5, BLACK.filled())))
                .map_err(err)?
                .label(format!(
                    "this rectangle: ψ = {:.2}°",
                    holonomy_angle(t, p).to_degrees()
                ))
                .legend(|(x, y)| Circle::new((x + 9, y), 4, BLACK.filled()));
        }
        chart
            .configure_series_labels()
            .label_font((FONT, 14))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .position(SeriesLabelPosition::UpperRight)
            .draw()
            .map_err(err)?;
        Ok(())
    })
}

/// The curves ψ(ϑ, φ2) = ψ in [0, 2π]² as polylines (four branches around (π, π)).
#[must_use]
pub fn level_set_branches(psi: f64) -> Vec<Vec<(f64, f64)>> {
    let k = 0.5 * (1.0 - (0.5 * psi).cos());
    let n = 400;
    let mut lower = Vec::new();
    for i in 0..=n {
        #[allow(clippy::cast_precision_loss)]
        let t = TAU * i as f64 / n as f64;
        let u = (0.5 * t).sin().powi(2);
        if u >= k && u > 0.0 {
            lower.push((t, 2.0 * (k / u).sqrt().min(1.0).asin()));
        }
    }
    let upper: Vec<(f64, f64)> = lower.iter().map(|&(t, p)| (t, TAU - p)).collect();
    vec![lower, upper]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn level_sets_lie_on_the_level() {
        for psi in [0.3, 2.0, 5.0] {
            for b in level_set_branches(psi) {
                for (t, p) in b {
                    assert!((holonomy_angle(t, p) - psi).abs() < 1e-9);
                }
            }
        }
    }
}
