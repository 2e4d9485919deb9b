//! `rollstack cylinder support|statics|holonomy|frobenius`: the inclined rolling cylinder
//! of Ch. 3 (App. D, E, F), corrected per ERRATA 8–15.
//!
//! Forces are divided by mg, angles are radians (`30deg`, `pi/10` accepted), lengths are
//! in any one unit (the cylinder's radius r for the holonomy examples).

use crate::output::{ensure_dir, print_json, write_csv, write_run_json};
use anyhow::{Context, Result};
use clap::{Args, Subcommand, ValueEnum};
use cylinders::frobenius::{bilinear, frobenius_test, skew_matrices, FrobeniusReport};
use cylinders::holonomy::{CirclePath, Direction, PathCase, RectanglePath};
use cylinders::kinematics::{Cylinder, Pose};
use cylinders::pair::{CylinderPair, PairConstraints, PairSystem, SingleCylinder};
use cylinders::rolling::{circle_motion, rectangle_segments, roll, RollingTrace};
use cylinders::statics::{FrictionLimit, MinimumForce, SteadyBalance, SupportProblem};
use figures::plot::{LinePlot, Series};
use input::text::Angle;
use nalgebra::DVector;
use rotations::{rotation_distance, AxisAngle};
use serde::Serialize;
use std::f64::consts::FRAC_PI_2;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Arguments of `rollstack cylinder`.
#[derive(Debug, Args)]
pub struct CylinderArgs {
    /// Which computation.
    #[command(subcommand)]
    pub command: CylinderCommand,
}

/// The subcommands of `rollstack cylinder`.
#[derive(Debug, Subcommand)]
pub enum CylinderCommand {
    /// Support forces of a steadily rolling inclined cylinder at one inclination (§3.3).
    Support(SupportArgs),
    /// The support-force curves of Figures 3.3, 3.4, 3.5, 3.7 and 3.8 (CSV + PNG).
    Statics(StaticsArgs),
    /// Holonomy Δφ when the contact point traces a rectangle or a circle (§3.4).
    Holonomy(HolonomyArgs),
    /// Frobenius integrability test of the rolling constraints, numerically (App. D, F).
    Frobenius(FrobeniusArgs),
}

/// Runs `rollstack cylinder ...`.
///
/// # Errors
/// Bad input, or a file that cannot be written.
pub fn run(args: &CylinderArgs) -> Result<()> {
    match &args.command {
        CylinderCommand::Support(a) => run_support(a),
        CylinderCommand::Statics(a) => run_statics(a),
        CylinderCommand::Holonomy(a) => match &a.path {
            HolonomyPath::Rectangle(r) => run_rectangle(r),
            HolonomyPath::Circle(c) => run_circle(c),
        },
        CylinderCommand::Frobenius(a) => run_frobenius(a),
    }
}

// ---------------------------------------------------------------- support

/// Arguments of `rollstack cylinder support`.
#[derive(Debug, Args)]
pub struct SupportArgs {
    /// Inclination ϑ of the axis to the vertical, in (0, π/2), rad (`30deg` accepted).
    #[arg(long, allow_hyphen_values = true)]
    pub theta: Angle,
    /// Aspect ratio r/h (radius over height, dimensionless, ≥ 0).
    #[arg(long, default_value_t = 0.1, allow_hyphen_values = true)]
    pub r_over_h: f64,
    /// Static friction coefficient μ between cylinder and plane (dimensionless, ≥ 0).
    #[arg(long, default_value_t = 0.2, allow_hyphen_values = true)]
    pub mu: f64,
    /// Print one JSON object on stdout.
    #[arg(long)]
    pub json: bool,
}

/// The minimum applied force in the JSON of `cylinder support`.
#[derive(Debug, Serialize)]
pub struct MinForceJson {
    /// F3/mg.
    pub f3_over_mg: f64,
    /// F/mg (horizontal, along e′2).
    pub f_over_mg: f64,
    /// ‖F_a‖/mg.
    pub norm_over_mg: f64,
    /// `unconstrained` (3.3.15), `friction_positive` / `friction_negative` (3.3.18),
    /// `no_vertical_force` (3.3.19) or `flat_contact`.
    pub case: String,
    /// The equation of the case.
    pub equation: String,
}

impl From<MinimumForce> for MinForceJson {
    fn from(m: MinimumForce) -> Self {
        Self {
            f3_over_mg: m.f3_over_mg,
            f_over_mg: m.f_over_mg,
            norm_over_mg: m.norm_over_mg,
            case: m.case.name().into(),
            equation: m.case.equation().into(),
        }
    }
}

/// JSON of `cylinder support` (the keys of docs/cli.md first).
#[derive(Debug, Serialize)]
pub struct SupportReport {
    /// N/mg at F_f = +μN e′2, (3.3.8)₊ corrected per ERRATA 9; null when no positive N.
    pub n_over_mg_plus: Option<f64>,
    /// N/mg at F_f = −μN e′2, (3.3.8)₋; null when no positive N.
    pub n_over_mg_minus: Option<f64>,
    /// N/mg on a smooth plane, (3.3.10); null when no positive N.
    pub n_over_mg_smooth: Option<f64>,
    /// Inclinations at which a steady support with 0 < N < mg exists: the (+) range of
    /// (3.3.9), corrected per ERRATA 10, rad.
    pub theta_range: [f64; 2],
    /// The minimum applied force, (3.3.15)–(3.3.19); null when no support exists.
    pub min_force: Option<MinForceJson>,
    /// The (−) range of (3.3.9), null when empty, rad.
    pub theta_range_minus: Option<[f64; 2]>,
    /// The range of (3.3.10), rad.
    pub theta_range_smooth: Option<[f64; 2]>,
    /// Admissible N/mg at this ϑ: [N₊, min(N₋, 1)], null when none.
    pub admissible_n_over_mg: Option<[f64; 2]>,
    /// The common point (ϑ, N/mg) of all (+) curves, (3.3.11); null for μ = 0.
    pub common_point: Option<[f64; 2]>,
    /// ϑ of point D, arctan(2r/h): zero applied force, rad.
    pub self_balancing_theta: f64,
    /// Largest difference between the closed forms and the balance laws (3.3.3) solved
    /// numerically (QR) at this ϑ.
    pub balance_law_error: f64,
}

fn range_json(r: Option<(f64, f64)>) -> Option<[f64; 2]> {
    r.map(|(a, b)| [a, b])
}

/// The support report at one inclination.
///
/// # Errors
/// Bad input (ϑ outside (0, π/2), negative r/h or μ).
pub fn support_report(theta: f64, r_over_h: f64, mu: f64) -> Result<SupportReport> {
    let p = SupportProblem::new(r_over_h, mu)?;
    let plus = p.normal_force(theta, FrictionLimit::Plus)?;
    let minus = p.normal_force(theta, FrictionLimit::Minus)?;
    let smooth = p.normal_force(theta, FrictionLimit::Smooth)?;
    let min_force = p.minimum_force(theta).ok();
    // The closed forms against the numerical balance laws, at an arbitrary heading.
    let balance = SteadyBalance::new(&p, theta, 0.7)?;
    let mut balance_law_error: f64 = 0.0;
    for (limit, closed) in [
        (FrictionLimit::Plus, plus),
        (FrictionLimit::Minus, minus),
        (FrictionLimit::Smooth, smooth),
    ] {
        if let Some(n) = closed {
            balance_law_error =
                balance_law_error.max((balance.limiting_normal_force(limit) - n).abs());
        }
    }
    if let (Some(m), Ok((f3, f))) = (min_force, balance.minimum_force()) {
        balance_law_error = balance_law_error
            .max((m.f3_over_mg - f3).abs())
            .max((m.f_over_mg - f).abs());
    }
    let upper = minus.map_or(1.0, |n| n.min(1.0));
    let admissible = plus.filter(|&n| n <= upper).map(|n| [n, upper]);
    let (lo, hi) = p
        .inclination_range(FrictionLimit::Plus)
        .unwrap_or((FRAC_PI_2, FRAC_PI_2));
    Ok(SupportReport {
        n_over_mg_plus: plus,
        n_over_mg_minus: minus,
        n_over_mg_smooth: smooth,
        theta_range: [lo, hi],
        min_force: min_force.map(MinForceJson::from),
        theta_range_minus: range_json(p.inclination_range(FrictionLimit::Minus)),
        theta_range_smooth: range_json(p.inclination_range(FrictionLimit::Smooth)),
        admissible_n_over_mg: admissible,
        common_point: p.common_point().map(|(a, b)| [a, b]),
        self_balancing_theta: p.self_balancing_inclination(),
        balance_law_error,
    })
}

fn run_support(a: &SupportArgs) -> Result<()> {
    let rep = support_report(a.theta.0, a.r_over_h, a.mu)?;
    if a.json {
        return print_json(&rep);
    }
    let show = |v: Option<f64>| v.map_or_else(|| "none".to_owned(), |v| format!("{v:.6}"));
    println!(
        "Steady support at ϑ = {:.4}° (r/h = {}, μ = {})",
        a.theta.0.to_degrees(),
        a.r_over_h,
        a.mu
    );
    println!(
        "  N/mg  F_f = +μN e′2 (3.3.8)+: {}",
        show(rep.n_over_mg_plus)
    );
    println!(
        "  N/mg  smooth plane (3.3.10):  {}",
        show(rep.n_over_mg_smooth)
    );
    println!(
        "  N/mg  F_f = −μN e′2 (3.3.8)−: {}",
        show(rep.n_over_mg_minus)
    );
    println!(
        "  feasible inclinations (3.3.9)+: ({:.4}°, {:.4}°)",
        rep.theta_range[0].to_degrees(),
        rep.theta_range[1].to_degrees()
    );
    match &rep.min_force {
        Some(m) => println!(
            "  minimum force {}: F3/mg = {:.6}, F/mg = {:.6}, ‖F_a‖/mg = {:.6}",
            m.equation, m.f3_over_mg, m.f_over_mg, m.norm_over_mg
        ),
        None => println!("  no admissible applied force at this inclination"),
    }
    println!(
        "  closed forms vs balance laws (3.3.3): {:.1e}",
        rep.balance_law_error
    );
    Ok(())
}

// ---------------------------------------------------------------- statics curves

/// Arguments of `rollstack cylinder statics`.
#[derive(Debug, Args)]
pub struct StaticsArgs {
    /// Aspect ratio r/h of Figures 3.3, 3.5, 3.7, 3.8 (dimensionless, ≥ 0).
    #[arg(long, default_value_t = 0.1, allow_hyphen_values = true)]
    pub r_over_h: f64,
    /// Friction coefficient μ of Figures 3.3, 3.4, 3.7, 3.8 (dimensionless, ≥ 0).
    #[arg(long, default_value_t = 0.2, allow_hyphen_values = true)]
    pub mu: f64,
    /// Number of inclinations sampled in (0, 90°).
    #[arg(long, default_value_t = 721)]
    pub points: usize,
    /// Write fig3_3.csv … fig3_8.csv, their PNGs and run.json here.
    #[arg(long)]
    pub out: PathBuf,
}

fn cell(v: Option<f64>) -> String {
    v.filter(|v| v.is_finite())
        .map_or_else(String::new, |v| v.to_string())
}

/// N/mg curves clipped to (0, 1] as plot points (ϑ in degrees).
fn n_curve(p: &SupportProblem, limit: FrictionLimit, thetas: &[f64]) -> Vec<(f64, f64)> {
    thetas
        .iter()
        .filter_map(|&t| {
            p.normal_force(t, limit)
                .ok()
                .flatten()
                .filter(|n| *n <= 1.0)
                .map(|n| (t.to_degrees(), n))
        })
        .collect()
}

/// A family of N/mg curves: file stem, (r/h, μ) pairs, title.
type Family<'a> = (&'a str, Vec<(f64, f64)>, String);

/// Writes the five statics figures into `dir`; returns the file names written.
///
/// # Errors
/// Bad input or a file that cannot be written.
pub fn write_statics(dir: &Path, r_over_h: f64, mu: f64, points: usize) -> Result<Vec<String>> {
    anyhow::ensure!(points >= 3, "--points must be at least 3");
    let p = SupportProblem::new(r_over_h, mu)?;
    let thetas: Vec<f64> = (1..points)
        .map(|k| FRAC_PI_2 * k as f64 / points as f64)
        .collect();
    let mut files = Vec::new();

    // Figure 3.3: N/mg for the two friction limits and the smooth plane.
    let rows = thetas.iter().map(|&t| {
        let n = |l| p.normal_force(t, l).ok().flatten();
        vec![
            t.to_string(),
            t.to_degrees().to_string(),
            cell(n(FrictionLimit::Plus)),
            cell(n(FrictionLimit::Smooth)),
            cell(n(FrictionLimit::Minus)),
        ]
    });
    write_csv(
        &dir.join("fig3_3.csv"),
        &[
            "theta",
            "theta_deg",
            "n_over_mg_plus",
            "n_over_mg_smooth",
            "n_over_mg_minus",
        ],
        rows,
    )?;
    LinePlot::new(
        format!("Fig. 3.3: N/mg = 1 − F3/mg (r/h = {r_over_h}, μ = {mu})"),
        "ϑ [deg]",
        "N/mg",
    )
    .with(Series::line(
        "i: F_f = +μN e′2 (3.3.8)+",
        n_curve(&p, FrictionLimit::Plus, &thetas),
    ))
    .with(Series::line(
        "smooth plane (3.3.10)",
        n_curve(&p, FrictionLimit::Smooth, &thetas),
    ))
    .with(Series::line(
        "ii: F_f = −μN e′2 (3.3.8)−",
        n_curve(&p, FrictionLimit::Minus, &thetas),
    ))
    .save(&dir.join("fig3_3.png"), (900, 600))?;
    files.extend(["fig3_3.csv".to_owned(), "fig3_3.png".to_owned()]);

    // Figures 3.4 (μ fixed, r/h varies) and 3.5 (r/h fixed, μ varies).
    let families: [Family<'_>; 2] = [
        (
            "fig3_4",
            [0.0, 0.05, 0.1, 0.15].map(|rho| (rho, mu)).to_vec(),
            format!("Fig. 3.4: N/mg, μ = {mu}, r/h = 0 … 0.15"),
        ),
        (
            "fig3_5",
            [0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6]
                .map(|m| (r_over_h, m))
                .to_vec(),
            format!("Fig. 3.5: N/mg, r/h = {r_over_h}, μ = 0 … 0.6"),
        ),
    ];
    for (name, params, title) in families {
        let mut rows = Vec::new();
        let mut plot = LinePlot::new(title, "ϑ [deg]", "N/mg");
        for &(rho, m) in &params {
            let q = SupportProblem::new(rho, m)?;
            for &t in &thetas {
                let n = |l| q.normal_force(t, l).ok().flatten();
                rows.push(vec![
                    rho.to_string(),
                    m.to_string(),
                    t.to_string(),
                    cell(n(FrictionLimit::Plus)),
                    cell(n(FrictionLimit::Smooth)),
                    cell(n(FrictionLimit::Minus)),
                ]);
            }
            plot = plot
                .with(Series::line(
                    format!("(+) r/h={rho}, μ={m}"),
                    n_curve(&q, FrictionLimit::Plus, &thetas),
                ))
                .with(Series::line(
                    format!("(−) r/h={rho}, μ={m}"),
                    n_curve(&q, FrictionLimit::Minus, &thetas),
                ));
            if name == "fig3_4" || m == 0.0 {
                plot = plot.with(Series::line(
                    format!("smooth r/h={rho}"),
                    n_curve(&q, FrictionLimit::Smooth, &thetas),
                ));
            }
        }
        write_csv(
            &dir.join(format!("{name}.csv")),
            &[
                "r_over_h",
                "mu",
                "theta",
                "n_over_mg_plus",
                "n_over_mg_smooth",
                "n_over_mg_minus",
            ],
            rows,
        )?;
        plot.save(&dir.join(format!("{name}.png")), (1000, 650))?;
        files.extend([format!("{name}.csv"), format!("{name}.png")]);
    }

    // Figures 3.7 and 3.8: the minimum force.
    let circle = p.minimum_force_circle();
    let (mut ok, mut bad, mut admissible) = (Vec::new(), Vec::new(), Vec::new());
    let mut rows = Vec::new();
    let (mut f3s, mut fs, mut norms) = (Vec::new(), Vec::new(), Vec::new());
    for &t in &thetas {
        let (u3, u) = p.unconstrained_minimum(t);
        let passes = p.satisfies_friction_criterion(t) && u3 >= 0.0;
        if passes {
            ok.push((u3, u));
        } else {
            bad.push((u3, u));
        }
        let m = p.minimum_force(t).ok();
        if let Some(m) = m {
            if m.case != cylinders::statics::MinForceCase::Unconstrained {
                admissible.push((m.f3_over_mg, m.f_over_mg));
            }
            let d = t.to_degrees();
            f3s.push((d, m.f3_over_mg));
            fs.push((d, m.f_over_mg));
            norms.push((d, m.norm_over_mg));
        }
        rows.push(vec![
            t.to_string(),
            t.to_degrees().to_string(),
            u3.to_string(),
            u.to_string(),
            u8::from(passes).to_string(),
            cell(m.map(|m| m.f3_over_mg)),
            cell(m.map(|m| m.f_over_mg)),
            cell(m.map(|m| m.norm_over_mg)),
            m.map_or_else(|| "none".to_owned(), |m| m.case.name().to_owned()),
        ]);
    }
    write_csv(
        &dir.join("fig3_7_fig3_8.csv"),
        &[
            "theta",
            "theta_deg",
            "circle_f3_over_mg",
            "circle_f_over_mg",
            "satisfies_3_3_17",
            "min_f3_over_mg",
            "min_f_over_mg",
            "min_norm_over_mg",
            "case",
        ],
        rows,
    )?;
    let cone: Vec<(f64, f64)> = (0..=20)
        .map(|k| f64::from(k) / 20.0)
        .map(|f3| (f3, mu * (1.0 - f3)))
        .collect();
    let cone_minus: Vec<(f64, f64)> = cone.iter().map(|&(a, b)| (a, -b)).collect();
    LinePlot::new(
        format!("Fig. 3.7: minimum-force locus, circle BC (r/h = {r_over_h}, μ = {mu})"),
        "F3/mg",
        "F/mg",
    )
    .with(Series::markers("(3.3.15) satisfying (3.3.17)", ok))
    .with(Series::markers("(3.3.15) violating (3.3.17)", bad))
    .with(Series::markers("(3.3.18)/(3.3.19) minimum", admissible))
    .with(Series::line("F = μN", cone))
    .with(Series::line("F = −μN", cone_minus))
    .with(Series::markers(
        "B, C (3.3.20)",
        vec![(circle.b[0], circle.b[1]), (circle.c[0], circle.c[1])],
    ))
    .save(&dir.join("fig3_7.png"), (900, 700))?;
    let d = p.self_balancing_inclination().to_degrees();
    LinePlot::new(
        format!("Fig. 3.8: minimum applied force (r/h = {r_over_h}, μ = {mu})"),
        "ϑ [deg]",
        "force / mg",
    )
    .with(Series::line("‖F_a‖/mg", norms))
    .with(Series::line("F/mg", fs))
    .with(Series::line("F3/mg", f3s))
    .with(Series::markers("D: ϑ = arctan(2r/h)", vec![(d, 0.0)]))
    .save(&dir.join("fig3_8.png"), (900, 600))?;
    files.extend([
        "fig3_7_fig3_8.csv".to_owned(),
        "fig3_7.png".to_owned(),
        "fig3_8.png".to_owned(),
    ]);
    Ok(files)
}

fn run_statics(a: &StaticsArgs) -> Result<()> {
    let start = Instant::now();
    ensure_dir(&a.out)?;
    let files = write_statics(&a.out, a.r_over_h, a.mu, a.points)?;
    write_run_json(
        &a.out,
        "cylinder statics",
        &serde_json::json!({"r_over_h": a.r_over_h, "mu": a.mu, "points": a.points}),
        &serde_json::json!({"total_s": start.elapsed().as_secs_f64()}),
    )?;
    println!("wrote {} files into {}", files.len() + 1, a.out.display());
    Ok(())
}

// ---------------------------------------------------------------- holonomy

/// Arguments of `rollstack cylinder holonomy`.
#[derive(Debug, Args)]
pub struct HolonomyArgs {
    /// The path traced by the contact point P.
    #[command(subcommand)]
    pub path: HolonomyPath,
}

/// The two paths of §3.4.
#[derive(Debug, Subcommand)]
pub enum HolonomyPath {
    /// P traces a rectangle of sides rφ1/2, rφ2/2: the nine-rotation product (3.4.3).
    Rectangle(RectangleArgs),
    /// P traces a circle of radius ℓ, (3.4.10)–(3.4.16).
    Circle(CircleArgs),
}

/// Case I (e′2 points out of the path) or II (in).
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum CaseArg {
    /// e′2 outward: Δφ > 0 counter-clockwise.
    #[value(name = "I", alias = "i", alias = "1")]
    One,
    /// e′2 inward: Δφ < 0 counter-clockwise.
    #[value(name = "II", alias = "ii", alias = "2")]
    Two,
}

impl From<CaseArg> for PathCase {
    fn from(c: CaseArg) -> Self {
        match c {
            CaseArg::One => PathCase::I,
            CaseArg::Two => PathCase::II,
        }
    }
}

fn direction(cw: bool) -> Direction {
    if cw {
        Direction::Clockwise
    } else {
        Direction::CounterClockwise
    }
}

/// Arguments of `rollstack cylinder holonomy rectangle`.
#[derive(Debug, Args)]
pub struct RectangleArgs {
    /// Inclination ϑ, in (0, π/2), rad (`pi/10` accepted).
    #[arg(long, allow_hyphen_values = true)]
    pub theta: Angle,
    /// φ1 > 0: a side of the rectangle is rφ1/2 long (rad of spin).
    #[arg(long, allow_hyphen_values = true)]
    pub phi1: Angle,
    /// φ2 > 0: the other side is rφ2/2 long (rad of spin).
    #[arg(long, allow_hyphen_values = true)]
    pub phi2: Angle,
    /// Start point S on the first side, s in [0, 1] (Figure 3.9).
    #[arg(long, default_value_t = 0.0)]
    pub s: f64,
    /// Case I (e′2 outward) or II (inward).
    #[arg(long = "case", value_enum, default_value = "I")]
    pub case: CaseArg,
    /// Travel clockwise; default counter-clockwise.
    #[arg(long)]
    pub cw: bool,
    /// Initial precession ψ0, rad (sets ₀e3 of (3.4.4)).
    #[arg(long, allow_hyphen_values = true, default_value = "0")]
    pub psi0: Angle,
    /// Height of the cylinder in units of r (only for the rolled traces; Figure 3.10: 8.3333).
    #[arg(long, default_value_t = 25.0 / 3.0)]
    pub h_over_r: f64,
    /// Largest rotation per integration step of the rolled check, rad.
    #[arg(long, default_value_t = 1e-3)]
    pub max_step: f64,
    /// Print one JSON object on stdout.
    #[arg(long)]
    pub json: bool,
    /// Write rectangle_trace.csv, rectangle_trace.png (Figure 3.10) and run.json here.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// JSON of `cylinder holonomy rectangle` (the keys of docs/cli.md first).
#[derive(Debug, Serialize)]
pub struct RectangleReport {
    /// Δφ = ±(φ1 + φ2), rad, (3.4.6)–(3.4.8).
    pub delta_phi: f64,
    /// Angle between the nine-rotation product (3.4.3) and A(Δφ, ₀e3), rad.
    pub product_error: f64,
    /// ₀e3 of (3.4.4) on E1, E2, E3.
    pub axis: [f64; 3],
    /// Canonical angle of the product in [0, π], rad.
    pub product_angle: f64,
    /// Quaternion of the raw product (sign kept), compare (3.4.9).
    pub product_quaternion: [f64; 4],
    /// Δφ measured on the orientation integrated along the path (unwrapped), rad.
    pub rolling_delta_phi: f64,
    /// Angle between the integrated net rotation and A(Δφ, ₀e3), rad.
    pub rolling_error: f64,
    /// ‖x̄_end − x̄_0‖ of the integrated motion (units of r).
    pub rolling_closure_error: f64,
}

fn run_rectangle(a: &RectangleArgs) -> Result<()> {
    let start = Instant::now();
    let theta = cylinders::kinematics::check_point_contact(a.theta.0)?;
    let path = RectanglePath::new(a.phi1.0, a.phi2.0, a.s, a.case.into(), direction(a.cw))?;
    let psi0 = a.psi0.0;
    let q = path.product_quaternion(theta, psi0);
    let product = q.to_rotation_matrix();
    let closed = path.closed_form(theta, psi0);
    let cylinder = Cylinder::new(1.0, a.h_over_r)?;
    let pose = Pose::on_plane(&cylinder, 0.0, 0.0, [psi0, theta, 0.0]);
    let trace = roll(&cylinder, &pose, &rectangle_segments(&path), a.max_step, 20)?;
    let axis = cylinders::holonomy::initial_axis(theta, psi0);
    let rep = RectangleReport {
        delta_phi: path.delta_phi(),
        product_error: rotation_distance(&product, &closed),
        axis: [axis.x, axis.y, axis.z],
        product_angle: AxisAngle::from_rotation(&product).angle,
        product_quaternion: [q.w, q.i, q.j, q.k],
        rolling_delta_phi: trace.delta_phi(),
        rolling_error: rotation_distance(&trace.net_rotation, &closed),
        rolling_closure_error: trace.closure_error(),
    };
    if let Some(dir) = &a.out {
        ensure_dir(dir)?;
        write_trace(
            dir,
            "rectangle_trace",
            &trace,
            &format!(
                "Fig. 3.10: P traces a rectangle, Δφ = {:.4} rad",
                rep.delta_phi
            ),
        )?;
        write_run_json(
            dir,
            "cylinder holonomy rectangle",
            &serde_json::json!({"theta": theta, "phi1": path.phi1, "phi2": path.phi2, "s": path.s,
                "case": format!("{:?}", path.case), "cw": a.cw, "psi0": psi0, "h_over_r": a.h_over_r}),
            &serde_json::json!({"total_s": start.elapsed().as_secs_f64()}),
        )?;
    }
    if a.json {
        return print_json(&rep);
    }
    println!(
        "Rectangle (3.4.3): Δφ = {:.9} rad ({:?}, {:?})",
        rep.delta_phi, path.case, path.direction
    );
    println!(
        "  product vs closed form (3.4.5): {:.1e} rad",
        rep.product_error
    );
    println!(
        "  rolled along the path: Δφ = {:.9} rad, error {:.1e} rad",
        rep.rolling_delta_phi, rep.rolling_error
    );
    Ok(())
}

/// Arguments of `rollstack cylinder holonomy circle`.
#[derive(Debug, Args)]
pub struct CircleArgs {
    /// Radius ℓ of the circle traced by P (same unit as --h and --r).
    #[arg(long)]
    pub ell: f64,
    /// Inclination ϑ, in (0, π/2), rad (`pi/10` accepted).
    #[arg(long, allow_hyphen_values = true)]
    pub theta: Angle,
    /// Height h of the cylinder.
    #[arg(long)]
    pub h: f64,
    /// Radius r of the cylinder.
    #[arg(long)]
    pub r: f64,
    /// Case I (e′2 outward) or II (inward).
    #[arg(long = "case", value_enum, default_value = "I")]
    pub case: CaseArg,
    /// Travel clockwise; default counter-clockwise.
    #[arg(long)]
    pub cw: bool,
    /// Largest rotation per integration step of the rolled check, rad.
    #[arg(long, default_value_t = 1e-3)]
    pub max_step: f64,
    /// Print one JSON object on stdout.
    #[arg(long)]
    pub json: bool,
    /// Write circle_trace.csv, circle_trace.png (Figure 3.12) and run.json here.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// JSON of `cylinder holonomy circle` (the keys of docs/cli.md first).
#[derive(Debug, Serialize)]
pub struct CircleReport {
    /// Δφ = ±2πℓ/r, rad, (3.4.16).
    pub delta_phi: f64,
    /// Radius of the circle of the centre of mass, (3.4.15).
    pub k: f64,
    /// φ̇0/ψ̇0 from (3.4.14).
    pub rate_ratio: f64,
    /// Δφ measured on the orientation integrated around the circle (unwrapped), rad.
    pub rolling_delta_phi: f64,
    /// ‖x̄_end − x̄_0‖ of the integrated motion.
    pub rolling_closure_error: f64,
}

fn run_circle(a: &CircleArgs) -> Result<()> {
    let start = Instant::now();
    let cylinder = Cylinder::new(a.r, a.h)?;
    let theta = a.theta.0;
    let path = CirclePath::new(a.ell, a.case.into(), direction(a.cw))?;
    let hol = path.holonomy(&cylinder, theta)?;
    let (pose, segment) = circle_motion(&cylinder, theta, &path)?;
    let trace = roll(&cylinder, &pose, &[segment], a.max_step, 20)?;
    let rep = CircleReport {
        delta_phi: hol.delta_phi,
        k: hol.k,
        rate_ratio: hol.rate_ratio,
        rolling_delta_phi: trace.delta_phi(),
        rolling_closure_error: trace.closure_error(),
    };
    if let Some(dir) = &a.out {
        ensure_dir(dir)?;
        write_trace(
            dir,
            "circle_trace",
            &trace,
            &format!(
                "Fig. 3.12: P traces a circle, Δφ = {:.4} rad",
                rep.delta_phi
            ),
        )?;
        write_run_json(
            dir,
            "cylinder holonomy circle",
            &serde_json::json!({"ell": a.ell, "theta": theta, "h": a.h, "r": a.r,
                "case": format!("{:?}", path.case), "cw": a.cw}),
            &serde_json::json!({"total_s": start.elapsed().as_secs_f64()}),
        )?;
    }
    if a.json {
        return print_json(&rep);
    }
    println!(
        "Circle (3.4.16): Δφ = {:.9} rad, k = {:.9} ({:?}, {:?})",
        rep.delta_phi, rep.k, path.case, path.direction
    );
    println!(
        "  rolled around the circle: Δφ = {:.9} rad",
        rep.rolling_delta_phi
    );
    Ok(())
}

/// Writes a rolling trace as CSV (t, centre, P, rim point X, φ) and a plan-view PNG with
/// the traces of P (i) and X (ii), the start S and the rim point's start A and end B.
///
/// # Errors
/// When a file cannot be written.
pub fn write_trace(dir: &Path, name: &str, trace: &RollingTrace, title: &str) -> Result<()> {
    let rows = trace.samples.iter().map(|s| {
        [
            s.t,
            s.center.x,
            s.center.y,
            s.center.z,
            s.contact.x,
            s.contact.y,
            s.rim_point.x,
            s.rim_point.y,
            s.rim_point.z,
            s.phi,
        ]
        .map(|v| v.to_string())
    });
    write_csv(
        &dir.join(format!("{name}.csv")),
        &[
            "t", "center_x", "center_y", "center_z", "p_x", "p_y", "x_x", "x_y", "x_z", "phi",
        ],
        rows,
    )?;
    let first = trace.samples.first().context("empty trace")?;
    let last = trace.samples.last().context("empty trace")?;
    LinePlot {
        equal_aspect: true,
        ..LinePlot::new(title, "E1", "E2")
    }
    .with(Series::line(
        "i: contact point P",
        trace
            .samples
            .iter()
            .map(|s| (s.contact.x, s.contact.y))
            .collect(),
    ))
    .with(Series::line(
        "ii: rim point X",
        trace
            .samples
            .iter()
            .map(|s| (s.rim_point.x, s.rim_point.y))
            .collect(),
    ))
    .with(Series::line(
        "centre of mass",
        trace
            .samples
            .iter()
            .map(|s| (s.center.x, s.center.y))
            .collect(),
    ))
    .with(Series::markers(
        "S (centre), A → B (X)",
        vec![
            (first.center.x, first.center.y),
            (first.rim_point.x, first.rim_point.y),
            (last.rim_point.x, last.rim_point.y),
        ],
    ))
    .save(&dir.join(format!("{name}.png")), (900, 800))?;
    Ok(())
}

// ---------------------------------------------------------------- Frobenius

/// The constraint systems of `cylinder frobenius`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum SystemArg {
    /// One cylinder: 6 coordinates, v_P = 0 (3 constraints), App. D.
    Single,
    /// The pair: 12 coordinates, Π1..Π7 of (3.5.13).
    Pair7,
    /// The pair: 12 coordinates, the nine rolling constraints of App. F.
    Pair9,
}

/// Where the pair is evaluated.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ConfigArg {
    /// The touching configuration shifted by fixed irregular offsets (not touching).
    Generic,
    /// Touching: both on the plane, leaning towards each other, axes r1 + r2 apart.
    Touching,
}

/// Arguments of `rollstack cylinder frobenius`.
#[derive(Debug, Args)]
pub struct FrobeniusArgs {
    /// Which constraint system.
    #[arg(long, value_enum, default_value = "single")]
    pub system: SystemArg,
    /// Configuration of the pair.
    #[arg(long, value_enum, default_value = "generic")]
    pub config: ConfigArg,
    /// Inclination ϑ of the cylinders, in (0, π/2), rad.
    #[arg(long, allow_hyphen_values = true, default_value = "0.4")]
    pub theta: Angle,
    /// Heading (precession ψ of cylinder I), rad.
    #[arg(long, allow_hyphen_values = true, default_value = "0.5")]
    pub heading: Angle,
    /// Where the cylinders touch along their axes, from the centre (m* = n*), metres.
    #[arg(long, allow_hyphen_values = true, default_value_t = 0.3)]
    pub contact_at: f64,
    /// Radius r of each cylinder, metres (default: the gas cylinder of §3.6).
    #[arg(long, default_value_t = 0.1143)]
    pub r: f64,
    /// Height h of each cylinder, metres.
    #[arg(long, default_value_t = 1.2954)]
    pub h: f64,
    /// Print one JSON object on stdout.
    #[arg(long)]
    pub json: bool,
}

/// JSON of `cylinder frobenius` (the keys of docs/cli.md first).
#[derive(Debug, Serialize)]
pub struct FrobeniusJson {
    /// Rank of W (ERRATA 13: 9 for the nine pair constraints, not 8).
    pub rank: usize,
    /// Number of coordinates minus the rank.
    pub nullity: usize,
    /// Per constraint: max |aᵀ S^Γ b| over unit a, b in the null space of W.
    pub max_abs_asb: Vec<f64>,
    /// Per constraint: whether that maximum vanishes (to 1e-9 relative).
    pub integrable: Vec<bool>,
    /// Whether the whole system passes the test.
    pub system_integrable: bool,
    /// Singular values of W, descending.
    pub singular_values: Vec<f64>,
    /// Coordinates q at which the test ran.
    pub q: Vec<f64>,
    /// Single cylinder only: [y1ᵀS¹y3, y1ᵀS²y3] with the basis (D.2.2), and the printed
    /// values [r sin ψ, −r cos ψ] of (D.2.4).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub d24: Option<[[f64; 2]; 2]>,
    /// Wall time of the test (derivatives, SVD, projections), seconds.
    pub wall_time_s: f64,
}

/// Runs the Frobenius test for the arguments.
///
/// # Errors
/// Bad input.
pub fn frobenius_json(a: &FrobeniusArgs) -> Result<FrobeniusJson> {
    let cylinder = Cylinder::new(a.r, a.h)?;
    let theta = cylinders::kinematics::check_point_contact(a.theta.0)?;
    let pair = CylinderPair::identical(cylinder);
    let start = Instant::now();
    let (q, report, d24): (Vec<f64>, FrobeniusReport, _) = match a.system {
        SystemArg::Single => {
            let sys = SingleCylinder { cylinder };
            let psi = a.heading.0;
            let q = vec![0.1, -0.2, cylinder.f2(theta), psi, theta, 0.3];
            let report = frobenius_test(&sys, &q)?;
            let skew = skew_matrices(&sys, &q)?;
            let y = sys
                .printed_null_basis(psi, theta)
                .map(|v| DVector::from_row_slice(&v));
            let d24 = [
                [
                    bilinear(&skew.s[0], &y[0], &y[2]),
                    bilinear(&skew.s[1], &y[0], &y[2]),
                ],
                [
                    cylinder.radius() * psi.sin(),
                    -cylinder.radius() * psi.cos(),
                ],
            ];
            (q, report, Some(d24))
        }
        SystemArg::Pair7 | SystemArg::Pair9 => {
            let q = match a.config {
                ConfigArg::Generic => {
                    pair.generic_configuration(theta, a.contact_at, a.heading.0)?
                }
                ConfigArg::Touching => {
                    pair.touching_configuration(theta, a.contact_at, a.heading.0)?
                }
            };
            let constraints = if a.system == SystemArg::Pair7 {
                PairConstraints::Seven
            } else {
                PairConstraints::Nine
            };
            (
                q.to_vec(),
                frobenius_test(&PairSystem { pair, constraints }, &q)?,
                None,
            )
        }
    };
    let wall_time_s = start.elapsed().as_secs_f64();
    Ok(FrobeniusJson {
        rank: report.rank,
        nullity: report.nullity,
        system_integrable: report.system_integrable(),
        max_abs_asb: report.max_abs_asb,
        integrable: report.integrable,
        singular_values: report.singular_values,
        q,
        d24,
        wall_time_s,
    })
}

fn run_frobenius(a: &FrobeniusArgs) -> Result<()> {
    let rep = frobenius_json(a)?;
    if a.json {
        return print_json(&rep);
    }
    println!(
        "Frobenius test ({:?}): rank {} nullity {}",
        a.system, rep.rank, rep.nullity
    );
    for (i, (v, ok)) in rep.max_abs_asb.iter().zip(&rep.integrable).enumerate() {
        println!(
            "  Π{}: max|aᵀSb| = {v:.3e}  {}",
            i + 1,
            if *ok { "integrable" } else { "not integrable" }
        );
    }
    println!("  system integrable: {}", rep.system_integrable);
    Ok(())
}
