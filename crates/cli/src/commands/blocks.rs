//! `rollstack blocks`: the stack of blocks on a driven base (Ch. 4, App. G–I).
//!
//! - `run SCENE.toml` and `lire`: one simulation (§4.3–4.5) with the JSON of DESIGN.md,
//!   a trajectory CSV written progressively (ERRATA 25), branch points, snapshots of the
//!   stack, an animation and plots of the top block;
//! - `sweep frequency` (Figure 4.6) and `sweep slide` (Figure 4.7): many runs in parallel,
//!   one CSV row per parameter value in input order;
//! - `painleve`: Painlevé's paradoxes for one block (App. I), which needs no time stepper.

use crate::angles::parse_finite;
use crate::output::{
    commit_temp, ensure_dir, print_json, write_csv, write_csv_f64, write_run_json,
};
use crate::plot::{err, with_png, LinePlot, Series, FONT, PALETTE};
use crate::sweep::{par_map_ordered, parse_range, Shard};
use anyhow::{Context, Result};
use blockstack::corners::corners;
use blockstack::painleve::{
    admissible_range, b_grid, critical_mu, least_friction, least_friction_for_sign,
    line_contact_solutions,
};
use blockstack::scenarios::{
    lire, lire_on_floor, shaking_column, sliding_column, Perturbation, Shaking,
};
use blockstack::simulation::{simulate, BlockPose, Prox, RunOptions, RunSummary, StepRecord};
use blockstack::{Pose, Scene};
use clap::{Args, Subcommand, ValueEnum};
use plotters::prelude::*;
use serde::Serialize;
use std::fs::File;
use std::io::BufWriter;
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Arguments of `rollstack blocks`.
#[derive(Debug, Args)]
pub struct BlocksArgs {
    /// Which analysis or simulation to run.
    #[command(subcommand)]
    pub command: BlocksCommand,
}

/// The subcommands of `rollstack blocks`.
#[derive(Debug, Subcommand)]
pub enum BlocksCommand {
    /// Simulates a scene file (TOML, see `blockstack::scene_file`) from t = 0 to t_end.
    Run(RunArgs),
    /// The Leaning Tower of Lire (§4.3, Figure 4.4): blocks w = 1, h = 0.2, μ = 0.3 in the
    /// harmonic maximum-overhang configuration (ERRATA 16) on a fixed table, with nothing
    /// below it as in the thesis (`--floor`: a floor at the table's bottom).
    Lire(LireArgs),
    /// Parameter sweeps: failure time against the shaking frequency (Figure 4.6), top
    /// block angle against the speed of the pulled base (Figure 4.7).
    #[command(subcommand)]
    Sweep(SweepCommand),
    /// Painlevé's paradoxes for one block on a rough plane (App. I): least friction
    /// coefficient, admissible angles, sign regions of b, line-contact forces.
    Painleve(PainleveArgs),
}

/// Arguments of `rollstack blocks painleve`.
#[derive(Debug, Args)]
pub struct PainleveArgs {
    /// Aspect ratio w/h of the block (dimensionless, > 0).
    #[arg(long, value_parser = parse_finite, allow_hyphen_values = true)]
    pub aspect: f64,
    /// Friction coefficient μ_d (dimensionless, ≥ 0) of the line-contact LCP (I.2.10).
    #[arg(long, default_value_t = 0.2, value_parser = parse_finite, allow_hyphen_values = true)]
    pub mu: f64,
    /// Largest μ_d of the b-sign grid (dimensionless).
    #[arg(long, default_value_t = 3.0, value_parser = parse_finite, allow_hyphen_values = true)]
    pub mu_max: f64,
    /// Grid nodes per axis of the b-sign grid (angle and μ_d).
    #[arg(long, default_value_t = 121)]
    pub grid: usize,
    /// Print one JSON object on stdout (otherwise a readable summary).
    #[arg(long)]
    pub json: bool,
    /// Directory for the b-sign grid (CSV), Figure I.2 (PNG) and run.json.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// Runs `rollstack blocks`.
///
/// # Errors
/// Bad input or an unwritable output directory.
pub fn run(args: &BlocksArgs) -> Result<()> {
    match &args.command {
        BlocksCommand::Run(a) => run_scene_file(a),
        BlocksCommand::Lire(a) => run_lire(a),
        BlocksCommand::Sweep(SweepCommand::Frequency(a)) => sweep_frequency(a),
        BlocksCommand::Sweep(SweepCommand::Slide(a)) => sweep_slide(a),
        BlocksCommand::Painleve(a) => painleve(a),
    }
}

/// The least μ_d for one slip direction.
#[derive(Debug, Serialize)]
pub struct SignedLeast {
    /// Least μ_d (an infimum when reached at an end of the open range (I.1.3)).
    pub mu: f64,
    /// Angle (rad) where it is reached.
    pub theta: f64,
}

/// Normal forces n = N/(mg) of one solution of the line-contact LCP.
#[derive(Debug, Serialize)]
pub struct LineContactJson {
    /// n_R at the right corner.
    pub n_right: f64,
    /// n_L at the left corner.
    pub n_left: f64,
}

/// The line-contact LCP (I.2.5) at ϑ = ϑ' = 0 for both slip directions.
#[derive(Debug, Serialize)]
pub struct LineContactReport {
    /// μ_d.
    pub mu: f64,
    /// Solutions when sliding to the right, sgn ẋ = +1.
    pub sliding_right: Vec<LineContactJson>,
    /// Solutions when sliding to the left, sgn ẋ = −1.
    pub sliding_left: Vec<LineContactJson>,
}

/// The JSON of `rollstack blocks painleve` (DESIGN.md: mu_min, theta_min, theta_max).
#[derive(Debug, Serialize)]
pub struct PainleveReport {
    /// Least μ_d for which b ≤ 0 is possible (4/3, ERRATA 18).
    pub mu_min: f64,
    /// ϑ_min = −arctan(h/w) (rad), (I.1.3).
    pub theta_min: f64,
    /// ϑ_max = arctan(w/h) (rad), (I.1.3).
    pub theta_max: f64,
    /// Angle (rad) of the least μ_d.
    pub theta_at_mu_min: f64,
    /// sgn(ẋ_P) of the least μ_d.
    pub slip_sign_at_mu_min: f64,
    /// Least μ_d per slip direction within the admissible range.
    pub mu_min_slip_positive: SignedLeast,
    /// Least μ_d per slip direction within the admissible range.
    pub mu_min_slip_negative: SignedLeast,
    /// The line-contact solutions (I.2.10).
    pub line_contact: LineContactReport,
}

/// The Painlevé analysis of App. I for a block of aspect w/h, with the line-contact LCP
/// solved for μ_d = `mu`.
///
/// # Errors
/// A bad aspect ratio or μ_d.
pub fn painleve_report(aspect: f64, mu: f64) -> Result<PainleveReport> {
    let (theta_min, theta_max) = admissible_range(aspect)?;
    let least = least_friction(aspect)?;
    let plus = least_friction_for_sign(aspect, 1.0)?;
    let minus = least_friction_for_sign(aspect, -1.0)?;
    // Line contact: only h/w matters (w = aspect, h = 1).
    let lcp = |s: f64| -> Result<Vec<LineContactJson>> {
        Ok(line_contact_solutions(aspect, 1.0, mu, s)?
            .into_iter()
            .map(|c| LineContactJson {
                n_right: c.n_right,
                n_left: c.n_left,
            })
            .collect())
    };
    Ok(PainleveReport {
        mu_min: least.mu,
        theta_min,
        theta_max,
        theta_at_mu_min: least.theta,
        slip_sign_at_mu_min: least.slip_sign,
        mu_min_slip_positive: SignedLeast {
            mu: plus.mu,
            theta: plus.theta,
        },
        mu_min_slip_negative: SignedLeast {
            mu: minus.mu,
            theta: minus.theta,
        },
        line_contact: LineContactReport {
            mu,
            sliding_right: lcp(1.0)?,
            sliding_left: lcp(-1.0)?,
        },
    })
}

fn painleve(args: &PainleveArgs) -> Result<()> {
    let start = Instant::now();
    anyhow::ensure!(
        args.grid >= 2,
        "--grid must be at least 2, got {}",
        args.grid
    );
    let report = painleve_report(args.aspect, args.mu)?;
    let (theta_min, theta_max) = (report.theta_min, report.theta_max);
    let least = least_friction(args.aspect)?;
    if let Some(dir) = &args.out {
        write_painleve_files(dir, args.aspect, args.mu_max, args.grid, &report)?;
        write_run_json(
            dir,
            "blocks painleve",
            &serde_json::json!({"aspect": args.aspect, "mu": args.mu, "mu_max": args.mu_max, "grid": args.grid}),
            &serde_json::json!({"wall_time_s": start.elapsed().as_secs_f64()}),
        )?;
    }
    if args.json {
        print_json(&report)?;
    } else {
        println!(
            "w/h = {}: admissible angles ({:.3}°, {:.3}°) (I.1.3)",
            args.aspect,
            theta_min.to_degrees(),
            theta_max.to_degrees()
        );
        println!(
            "least friction coefficient for a paradox: μ_d = {:.6} at ϑ = {:.3}° (sgn ẋ_P = {:+})",
            least.mu,
            least.theta.to_degrees(),
            least.slip_sign
        );
        for (name, sols) in [
            ("right", &report.line_contact.sliding_right),
            ("left", &report.line_contact.sliding_left),
        ] {
            for s in sols {
                println!(
                    "line contact, μ_d = {}, sliding {name}: n_R = {:.6}, n_L = {:.6} (I.2.10)",
                    args.mu, s.n_right, s.n_left
                );
            }
        }
    }
    Ok(())
}

/// Writes `painleve_b_grid.csv` (b on a (ϑ, μ_d) grid of `grid` × `grid` nodes up to
/// `mu_max`) and `painleve.png` (Figure I.2) into `dir`.
///
/// # Errors
/// Bad parameters or an unwritable directory.
pub fn write_painleve_files(
    dir: &Path,
    aspect: f64,
    mu_max: f64,
    grid: usize,
    report: &PainleveReport,
) -> Result<()> {
    // Everything that can fail on bad input comes before the first file is written.
    let samples = b_grid(aspect, mu_max, grid, grid)?;
    ensure_dir(dir)?;
    let rows = samples.iter().map(|s| {
        vec![
            format!("{}", s.theta),
            format!("{}", s.theta.to_degrees()),
            format!("{}", s.mu),
            format!("{}", s.b_plus),
            format!("{}", s.b_minus),
            format!("{}", u8::from(s.admissible)),
        ]
    });
    write_csv(
        &dir.join("painleve_b_grid.csv"),
        &[
            "theta_rad",
            "theta_deg",
            "mu_d",
            "b_slip_positive",
            "b_slip_negative",
            "admissible",
        ],
        rows,
    )?;
    // Panel (a): admissible angles against the aspect ratio w/h.
    let aspects: Vec<f64> = (1..=200).map(|i| 0.025 * f64::from(i)).collect();
    let mut lo = Vec::new();
    let mut hi = Vec::new();
    for &r in &aspects {
        let (a, b) = admissible_range(r)?;
        lo.push((r, a.to_degrees()));
        hi.push((r, b.to_degrees()));
    }
    let panel_a = LinePlot::new("(a) admissible angles (I.1.3)", "aspect w/h", "angle (deg)")
        .with(Series::line("theta_max = atan(w/h)", hi))
        .with(Series::line("theta_min = -atan(h/w)", lo))
        .with(Series::markers(
            format!("w/h = {aspect}"),
            vec![
                (aspect, report.theta_min.to_degrees()),
                (aspect, report.theta_max.to_degrees()),
            ],
        ));
    with_png(&dir.join("painleve.png"), (1400, 600), |root| {
        let (left, right) = root.split_horizontally(560);
        panel_a.draw(&left)?;
        draw_b_regions(&right, mu_max, grid, report, &samples)
    })
    .context("cannot draw the Painlevé figure")
}

/// Panel (b) of Figure I.2: where b ≤ 0 in the (ϑ, μ_d) plane, per slip direction, with
/// the loci b = 0, the admissible range and the points i, ii of least μ_d.
fn draw_b_regions(
    root: &crate::plot::Canvas<'_>,
    mu_max: f64,
    n_grid: usize,
    report: &PainleveReport,
    grid: &[blockstack::painleve::BSample],
) -> Result<()> {
    let mut chart = ChartBuilder::on(root)
        .caption("(b) Painlevé region b <= 0 (I.1.8, ERRATA 18)", (FONT, 22))
        .margin(12)
        .x_label_area_size(45)
        .y_label_area_size(60)
        .build_cartesian_2d(-90.0..90.0, 0.0..mu_max)
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc("theta (deg)")
        .y_desc("mu_d")
        .label_style((FONT, 14))
        .draw()
        .map_err(err)?;
    let (dt, dm) = (180.0 / n_grid as f64, mu_max / (n_grid - 1) as f64);
    let cells = grid.iter().filter_map(|s| {
        let color = if s.b_plus <= 0.0 {
            PALETTE[0]
        } else if s.b_minus <= 0.0 {
            PALETTE[1]
        } else {
            return None;
        };
        let alpha = if s.admissible { 0.7 } else { 0.2 };
        let (t, m) = (s.theta.to_degrees(), s.mu);
        Some(Rectangle::new(
            [(t - 0.5 * dt, m - 0.5 * dm), (t + 0.5 * dt, m + 0.5 * dm)],
            color.mix(alpha).filled(),
        ))
    });
    chart.draw_series(cells).map_err(err)?;
    for (sign, color, label) in [
        (1.0, PALETTE[0], "b = 0, sgn(x_P') = +1"),
        (-1.0, PALETTE[1], "b = 0, sgn(x_P') = -1"),
    ] {
        let locus: Vec<(f64, f64)> = (1..1800)
            .map(|i| -std::f64::consts::FRAC_PI_2 + std::f64::consts::PI * f64::from(i) / 1800.0)
            .filter_map(|th| critical_mu(th, sign).map(|m| (th.to_degrees(), m)))
            .filter(|p| p.1 <= mu_max)
            .collect();
        chart
            .draw_series(LineSeries::new(locus, color.stroke_width(2)))
            .map_err(err)?
            .label(label)
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
            });
    }
    for th in [report.theta_min, report.theta_max] {
        let d = th.to_degrees();
        chart
            .draw_series(LineSeries::new(
                vec![(d, 0.0), (d, mu_max)],
                BLACK.stroke_width(1),
            ))
            .map_err(err)?;
    }
    let points = [
        (
            report.mu_min_slip_positive.theta.to_degrees(),
            report.mu_min_slip_positive.mu,
            "i",
        ),
        (
            report.mu_min_slip_negative.theta.to_degrees(),
            report.mu_min_slip_negative.mu,
            "ii",
        ),
    ];
    chart
        .draw_series(points.iter().map(|&(t, m, name)| {
            EmptyElement::at((t, m))
                + Circle::new((0, 0), 5, BLACK.filled())
                + Text::new(name.to_string(), (8, -18), (FONT, 18))
        }))
        .map_err(err)?;
    chart
        .configure_series_labels()
        .label_font((FONT, 14))
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()
        .map_err(err)?;
    Ok(())
}

// ---------------------------------------------------------------------------------------
// Drawing the stack.

/// A square window onto the plane of the stack: x and y ranges of equal length.
#[derive(Debug, Clone, PartialEq)]
pub struct View {
    /// Horizontal range.
    pub x: Range<f64>,
    /// Vertical range.
    pub y: Range<f64>,
}

/// The base and block poses of one moment, bottom to top (base first).
#[derive(Debug, Clone)]
pub struct StackFrame {
    /// Time.
    pub t: f64,
    /// The prescribed base.
    pub base: Pose,
    /// The free blocks, bottom to top.
    pub blocks: Vec<Pose>,
}

impl StackFrame {
    fn from_record(rec: &StepRecord) -> Self {
        Self {
            t: rec.t,
            base: pose_of(&rec.base),
            blocks: rec.poses.iter().map(pose_of).collect(),
        }
    }

    /// The scene at rest at t = 0 with coordinates q = (x¹, y¹, θ¹, …).
    fn from_coordinates(scene: &Scene, q: &[f64], t: f64) -> Self {
        Self {
            t,
            base: scene.base().state(t).pose,
            blocks: q.chunks_exact(3).map(Pose::from_slice).collect(),
        }
    }

    fn is_finite(&self) -> bool {
        let ok = |p: &Pose| p.x.is_finite() && p.y.is_finite() && p.theta.is_finite();
        self.t.is_finite() && ok(&self.base) && self.blocks.iter().all(ok)
    }

    /// The outlines (four corners) of the base and the blocks, base first.
    fn outlines(&self, scene: &Scene) -> Vec<Vec<(f64, f64)>> {
        let outline = |pose: &Pose, s: blockstack::Size| {
            corners(pose, s.width, s.height)
                .iter()
                .map(|c| (c.x, c.y))
                .collect::<Vec<_>>()
        };
        std::iter::once(outline(&self.base, scene.size(0)))
            .chain(
                self.blocks
                    .iter()
                    .enumerate()
                    .map(|(k, p)| outline(p, scene.size(k + 1))),
            )
            .collect()
    }
}

fn pose_of(p: &BlockPose) -> Pose {
    Pose::new(p.x, p.y, p.theta)
}

/// A square view that holds every body of every frame and the floor, with a margin.
fn view_of(scene: &Scene, frames: &[&StackFrame]) -> View {
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for f in frames.iter().filter(|f| f.is_finite()) {
        for &(x, y) in f.outlines(scene).iter().flatten() {
            (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
        }
    }
    if x0 > x1 {
        (x0, x1, y0, y1) = (-1.0, 1.0, -1.0, 1.0);
    }
    if let Some(f) = scene.floor() {
        y0 = y0.min(f.y);
    }
    let half = 0.55 * (x1 - x0).max(y1 - y0);
    let (cx, cy) = (0.5 * (x0 + x1), 0.5 * (y0 + y1));
    View {
        x: cx - half..cx + half,
        y: cy - half..cy + half,
    }
}

/// Draws one frame of the stack onto a canvas: the floor as a line, the base black (as
/// in Figure 4.4), the blocks as rotated rectangles in colour.
fn draw_stack<DB: DrawingBackend>(
    root: &DrawingArea<DB, plotters::coord::Shift>,
    scene: &Scene,
    frame: &StackFrame,
    view: &View,
    title: &str,
) -> Result<()> {
    let mut chart = ChartBuilder::on(root)
        .caption(title, (FONT, 22))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(50)
        .build_cartesian_2d(view.x.clone(), view.y.clone())
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc("x")
        .y_desc("y")
        .label_style((FONT, 14))
        // No minor grid: cleaner pictures and a much smaller animation.
        .light_line_style(TRANSPARENT)
        .draw()
        .map_err(err)?;
    if let Some(f) = scene.floor() {
        chart
            .draw_series(LineSeries::new(
                vec![(view.x.start, f.y), (view.x.end, f.y)],
                BLACK.stroke_width(2),
            ))
            .map_err(err)?;
    }
    for (k, poly) in frame.outlines(scene).into_iter().enumerate() {
        let color = if k == 0 {
            BLACK
        } else {
            PALETTE[(k - 1) % PALETTE.len()]
        };
        let mut closed = poly.clone();
        closed.push(poly[0]);
        chart
            .draw_series(std::iter::once(Polygon::new(poly, color.mix(0.6).filled())))
            .map_err(err)?;
        chart
            .draw_series(std::iter::once(PathElement::new(
                closed,
                BLACK.stroke_width(1),
            )))
            .map_err(err)?;
    }
    Ok(())
}

/// Draws the stack at time t with coordinates q: the base black (as in Figure 4.4), the
/// blocks in colour, the floor as a line; equal scales on both axes.
///
/// # Errors
/// Non-finite coordinates or an unwritable file.
pub fn plot_stack(path: &Path, scene: &Scene, q: &[f64], t: f64, title: &str) -> Result<()> {
    let frame = StackFrame::from_coordinates(scene, q, t);
    anyhow::ensure!(
        frame.is_finite(),
        "cannot draw a stack with non-finite coordinates"
    );
    let view = view_of(scene, &[&frame]);
    with_png(path, (800, 800), |root| {
        draw_stack(root, scene, &frame, &view, title)
    })
}

/// Draws frames into one PNG each with a common view (Figure 4.4 style snapshots).
fn plot_snapshots(scene: &Scene, shots: &[(PathBuf, String, &StackFrame)]) -> Result<()> {
    let frames: Vec<&StackFrame> = shots.iter().map(|s| s.2).collect();
    let view = view_of(scene, &frames);
    for (path, title, frame) in shots {
        anyhow::ensure!(
            frame.is_finite(),
            "cannot draw a stack with non-finite coordinates"
        );
        with_png(path, (800, 800), |root| {
            draw_stack(root, scene, frame, &view, title)
        })?;
    }
    Ok(())
}

/// Writes an animated GIF of `frames` (one common view), atomically.
fn write_animation(path: &Path, scene: &Scene, frames: &[StackFrame], title: &str) -> Result<()> {
    let good: Vec<&StackFrame> = frames.iter().filter(|f| f.is_finite()).collect();
    anyhow::ensure!(!good.is_empty(), "no frame to animate");
    let view = view_of(scene, &good);
    crate::plot::register_font();
    let tmp = crate::output::temp_sibling(path);
    {
        let root = BitMapBackend::gif(&tmp, (480, 480), ANIMATION_FRAME_MS)
            .map_err(|e| anyhow::anyhow!("cannot write {}: {e}", path.display()))?
            .into_drawing_area();
        for f in good {
            root.fill(&WHITE).map_err(err)?;
            draw_stack(&root, scene, f, &view, &format!("{title}, t = {:.2}", f.t))?;
            root.present()
                .map_err(|e| anyhow::anyhow!("cannot write {}: {e}", path.display()))?;
        }
    }
    crate::output::commit_temp(path)
}

/// Delay between animation frames (ms).
const ANIMATION_FRAME_MS: u32 = 80;

// ---------------------------------------------------------------------------------------
// One simulation: options, progressive output, report.

/// Solver overrides shared by `run`, `lire` and the sweeps.
#[derive(Debug, Clone, Args)]
pub struct SolverArgs {
    /// Use one constant prox parameter r > 0 for every contact (the thesis: 0.3; model
    /// units of mass per time) instead of the scene's choice (default: scaled per
    /// constraint, r_k = 1/(w_kᵀM⁻¹w_k), NSGA-SPEC §4).
    #[arg(long, value_parser = parse_finite, allow_hyphen_values = true)]
    pub prox_constant: Option<f64>,
    /// Resolve and record branch points: on a step whose contact states alternate,
    /// re-solve with each set of index sets seen and keep the self-consistent candidates
    /// (NSGA-SPEC §4). On by default; `--explore-branches false` skips these re-solves:
    /// such a step is then only retried with other ρ∞ and as halved steps, and the run
    /// ends there if those fail too.
    #[arg(long, default_value_t = true, action = clap::ArgAction::Set, value_name = "BOOL")]
    pub explore_branches: bool,
}

impl SolverArgs {
    /// The library's run options for an end time override.
    ///
    /// # Errors
    /// A non-positive end time or prox constant.
    pub fn run_options(&self, t_end: Option<f64>, stop_at_failure: bool) -> Result<RunOptions> {
        if let Some(t) = t_end {
            anyhow::ensure!(t > 0.0, "--t-end must be positive, got {t}");
        }
        if let Some(r) = self.prox_constant {
            anyhow::ensure!(r > 0.0, "--prox-constant must be positive, got {r}");
        }
        Ok(RunOptions {
            t_end,
            prox: self.prox_constant.map(Prox::Constant),
            explore_branches: self.explore_branches,
            stop_at_failure,
        })
    }
}

/// Output options of `run` and `lire`.
#[derive(Debug, Clone, Args)]
pub struct OutputArgs {
    /// Directory for trajectory.csv, branch_points.csv, snapshots (PNG), the animation
    /// (GIF), plots of the top block and run.json (created if missing).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Print one JSON object on stdout (otherwise a readable summary).
    #[arg(long)]
    pub json: bool,
    /// Times (model time units) of the PNG snapshots of the stack, comma-separated; the
    /// nearest computed step is drawn (default: lire 0,5,6.4; run 0, t_end/2, t_end).
    #[arg(long, value_delimiter = ',', value_parser = parse_finite)]
    pub snapshots: Option<Vec<f64>>,
    /// Largest number of animation frames (one every 10th step or sparser); 0: no GIF.
    #[arg(long, default_value_t = 120)]
    pub max_frames: usize,
}

/// Arguments of `rollstack blocks run`.
#[derive(Debug, Args)]
pub struct RunArgs {
    /// The scene file (TOML): base and motion, blocks bottom to top, contact, solver,
    /// optional floor. Unknown keys are errors.
    pub scene: PathBuf,
    /// End time (model time units; overrides the scene's solver.t_end).
    #[arg(long, value_parser = parse_finite, allow_hyphen_values = true)]
    pub t_end: Option<f64>,
    #[command(flatten)]
    #[allow(missing_docs)]
    pub solver: SolverArgs,
    #[command(flatten)]
    #[allow(missing_docs)]
    pub output: OutputArgs,
}

/// Which block of the Lire tower is pushed outward by 1 % of its width.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum PerturbArg {
    /// The exact maximum-overhang configuration (an unstable equilibrium).
    None,
    /// The lowest free block: the whole column collapses (Figure 4.4).
    Bottom,
    /// The top block: it topples alone.
    Top,
}

impl From<PerturbArg> for Perturbation {
    fn from(p: PerturbArg) -> Self {
        match p {
            PerturbArg::None => Self::None,
            PerturbArg::Bottom => Self::Bottom,
            PerturbArg::Top => Self::Top,
        }
    }
}

/// Arguments of `rollstack blocks lire`.
#[derive(Debug, Args)]
pub struct LireArgs {
    /// Number of free blocks on the table (the thesis: 4).
    #[arg(long, default_value_t = 4)]
    pub blocks: usize,
    /// Which block is shifted outward by 1 % of its width.
    #[arg(long, value_enum, default_value_t = PerturbArg::None)]
    pub perturb: PerturbArg,
    /// Put a floor at the bottom of the table so that the blocks that fall land (beyond
    /// the thesis, whose blocks fall freely).
    #[arg(long)]
    pub floor: bool,
    /// End time (model time units, g = 1; the thesis: 10).
    #[arg(long, default_value_t = 10.0, value_parser = parse_finite, allow_hyphen_values = true)]
    pub t_end: f64,
    #[command(flatten)]
    #[allow(missing_docs)]
    pub solver: SolverArgs,
    #[command(flatten)]
    #[allow(missing_docs)]
    pub output: OutputArgs,
}

/// The JSON of `rollstack blocks run` and `lire` (DESIGN.md keys first, then extras).
#[derive(Debug, Serialize)]
pub struct SimulationReport {
    /// Number of time steps taken.
    pub steps: usize,
    /// First time any block loses support on the block beneath it (§4.4), or null.
    pub failure_time: Option<f64>,
    /// Final poses of the free blocks, bottom to top.
    #[serde(rename = "final")]
    pub final_poses: Vec<BlockPose>,
    /// Smallest normal gap seen (negative: penetration).
    pub min_gap: f64,
    /// Mean number of Newton iterations per step.
    pub newton_iterations_mean: f64,
    /// Solver time (s), without I/O.
    pub wall_time_s: f64,
    /// First time any interface opens completely, or null.
    pub opening_time: Option<f64>,
    /// Steps whose first Newton attempt did not converge.
    pub failed_steps: usize,
    /// Number of branch points recorded.
    pub branch_points: usize,
    /// Steps that went through only as substeps (halved Δt).
    pub split_steps: usize,
    /// Linear solves of the Newton iterations in every attempt (the run's work).
    pub linear_solves: u64,
    /// Largest energy increase between two steps (≤ ~0 in unforced runs).
    pub max_energy_increase: f64,
    /// Why the run stopped early, or null.
    pub error: Option<String>,
    /// Time reached.
    pub t_final: f64,
    /// The prox parameter used.
    pub prox: String,
    /// Files written into --out (relative names).
    pub files: Vec<String>,
}

/// Everything one simulation produced, for the commands and the tour.
#[derive(Debug)]
pub struct SimulationOutput {
    /// The library's summary.
    pub summary: RunSummary,
    /// The JSON report.
    pub report: SimulationReport,
    /// The snapshot frames drawn (requested time, frame).
    pub snapshots: Vec<(f64, StackFrame)>,
    /// Top block (t, θ, y) at every step.
    pub top: Vec<(f64, f64, f64)>,
    /// A failure while writing output during the run (the run itself went on).
    pub write_error: Option<String>,
}

/// What to write besides the JSON.
#[derive(Debug, Clone, Default)]
pub struct OutputPlan {
    /// Output directory, if any.
    pub dir: Option<PathBuf>,
    /// Snapshot times.
    pub snapshots: Vec<f64>,
    /// Largest number of GIF frames (0: none).
    pub max_frames: usize,
    /// A short name of the run for plot titles.
    pub title: String,
}

/// The trajectory CSV header: t, x1, y1, theta1, …, then n{k}a, n{k}b, f{k} per interface
/// k (k = 1 between the base and block 1), then base_x, min_gap, newton_iterations, energy.
#[must_use]
pub fn trajectory_header(n: usize) -> Vec<String> {
    let mut h = vec!["t".to_owned()];
    for k in 1..=n {
        h.extend([format!("x{k}"), format!("y{k}"), format!("theta{k}")]);
    }
    for k in 1..=n {
        h.extend([format!("n{k}a"), format!("n{k}b"), format!("f{k}")]);
    }
    h.extend(
        ["base_x", "min_gap", "newton_iterations", "energy"]
            .iter()
            .map(|s| (*s).to_owned()),
    );
    h
}

/// The trajectory CSV, written row by row into a temporary sibling and renamed into
/// place at the end, also after an error, so an interrupted run keeps its rows
/// (ERRATA 25).
struct TrajectoryWriter {
    path: PathBuf,
    csv: csv::Writer<BufWriter<File>>,
}

impl TrajectoryWriter {
    fn create(path: &Path, n: usize) -> Result<Self> {
        let tmp = crate::output::temp_sibling(path);
        let file = File::create(&tmp).with_context(|| format!("cannot write {}", tmp.display()))?;
        let mut csv = csv::Writer::from_writer(BufWriter::new(file));
        csv.write_record(trajectory_header(n))?;
        Ok(Self {
            path: path.to_owned(),
            csv,
        })
    }

    /// One row; refuses non-finite states and forces (never NaN in a file).
    fn row(&mut self, rec: &StepRecord) -> Result<()> {
        let mut cells: Vec<f64> = vec![rec.t];
        cells.extend(rec.poses.iter().flat_map(|p| [p.x, p.y, p.theta]));
        cells.extend(
            rec.forces
                .iter()
                .flat_map(|f| [f.normal[0], f.normal[1], f.friction]),
        );
        cells.extend([rec.base.x]);
        anyhow::ensure!(
            cells.iter().all(|v| v.is_finite()),
            "non-finite state or force at t = {}: trajectory stopped there",
            rec.t
        );
        let mut row: Vec<String> = cells.iter().map(|v| number_cell(*v)).collect();
        // The minimum gap is +inf when no contact is closed: left empty then.
        row.push(finite_cell(rec.min_gap));
        row.push(rec.iterations.to_string());
        row.push(finite_cell(rec.energy));
        self.csv.write_record(&row)?;
        Ok(())
    }

    fn finish(mut self) -> Result<()> {
        self.csv
            .flush()
            .with_context(|| format!("cannot write {}", self.path.display()))?;
        drop(self.csv);
        commit_temp(&self.path)
    }
}

/// Shortest round-trip text of a finite number, in exponent form when very small or
/// large (`2.7755575615628914e-17`, not 33 digits of zeros).
fn number_cell(v: f64) -> String {
    format!("{v:?}")
}

/// A finite number, or an empty cell (never NaN or inf in a file).
fn finite_cell(v: f64) -> String {
    if v.is_finite() {
        number_cell(v)
    } else {
        String::new()
    }
}

/// Collects what the output needs from the step callback.
struct Recorder {
    writer: Option<TrajectoryWriter>,
    write_error: Option<anyhow::Error>,
    snapshot_times: Vec<f64>,
    snapshots: Vec<Option<StackFrame>>,
    frames: Vec<StackFrame>,
    frame_every: usize,
    max_frames: usize,
    top: Vec<(f64, f64, f64)>,
    last: Option<StackFrame>,
    count: usize,
}

impl Recorder {
    fn on_step(&mut self, rec: &StepRecord) {
        let i = self.count;
        self.count += 1;
        if let Some(top) = rec.poses.last() {
            if rec.t.is_finite() && top.theta.is_finite() && top.y.is_finite() {
                self.top.push((rec.t, top.theta, top.y));
            }
        }
        if self.write_error.is_none() {
            if let Some(w) = &mut self.writer {
                if let Err(e) = w.row(rec) {
                    self.write_error = Some(e);
                }
            }
        }
        // Keep, for each snapshot time, the nearest step seen so far.
        for (ts, best) in self.snapshot_times.iter().zip(&mut self.snapshots) {
            if best
                .as_ref()
                .is_none_or(|b| (rec.t - ts).abs() < (b.t - ts).abs())
            {
                *best = Some(StackFrame::from_record(rec));
            }
        }
        if self.max_frames > 0
            && i.is_multiple_of(self.frame_every)
            && self.frames.len() < self.max_frames
        {
            self.frames.push(StackFrame::from_record(rec));
        }
        self.last = Some(StackFrame::from_record(rec));
    }
}

fn describe_prox(scene: &Scene, options: &RunOptions) -> String {
    match options.prox {
        Some(p) => format!("{p:?}"),
        None => format!("{:?}", scene.solver.prox),
    }
}

/// Runs one scene, writing the trajectory progressively and, afterwards, the branch
/// points, snapshots, animation, top-block plots and run.json into `plan.dir`.
///
/// # Errors
/// A bad scene or options, or an output directory that cannot be created. A step that
/// fails mid-run is not an Err: it is in `summary.error` (files are still written).
pub fn simulate_with_output(
    scene: &Scene,
    options: &RunOptions,
    plan: &OutputPlan,
    command: &str,
    inputs: &serde_json::Value,
) -> Result<SimulationOutput> {
    let start = Instant::now();
    let n = scene.n_blocks();
    let t_end = options.t_end.unwrap_or(scene.solver.t_end);
    let planned_steps = (t_end / scene.solver.dt).ceil().max(1.0);
    // A modest animation: every 10th step, sparser for long runs.
    #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
    let frame_every = if plan.max_frames == 0 {
        1
    } else {
        ((planned_steps / plan.max_frames as f64).ceil() as usize).max(10)
    };
    let writer = match &plan.dir {
        Some(dir) => {
            ensure_dir(dir)?;
            Some(TrajectoryWriter::create(&dir.join("trajectory.csv"), n)?)
        }
        None => None,
    };
    let mut rec = Recorder {
        writer,
        write_error: None,
        snapshot_times: plan.snapshots.clone(),
        snapshots: vec![None; plan.snapshots.len()],
        frames: Vec::new(),
        frame_every,
        max_frames: plan.max_frames,
        top: Vec::new(),
        last: None,
        count: 0,
    };
    let result = simulate(scene, options, |r| rec.on_step(r));
    // Keep what was computed even when the run is refused or stops (ERRATA 25).
    let finished = rec.writer.take().map(TrajectoryWriter::finish);
    let summary = result.context("cannot simulate the scene")?;
    let mut write_error = rec.write_error.take().map(|e| format!("{e:#}"));
    if let Some(Err(e)) = finished {
        write_error.get_or_insert(format!("{e:#}"));
    }
    let t_final = rec.last.as_ref().map_or(0.0, |f| f.t);
    let mut files = Vec::new();
    let snapshots: Vec<(f64, StackFrame)> = plan
        .snapshots
        .iter()
        .zip(rec.snapshots)
        .filter_map(|(ts, f)| f.map(|f| (*ts, f)))
        .collect();
    if let Some(dir) = &plan.dir {
        files.push("trajectory.csv".to_owned());
        write_branch_points(&dir.join("branch_points.csv"), &summary)?;
        files.push("branch_points.csv".to_owned());
        let shots: Vec<(PathBuf, String, &StackFrame)> = snapshots
            .iter()
            .map(|(ts, f)| {
                let name = snapshot_name(*ts);
                files.push(name.clone());
                // A run that stopped before a requested time shows its last state.
                let note = if f.t < ts - 0.5 * scene.solver.dt {
                    format!(" (run ended before t = {ts})")
                } else {
                    String::new()
                };
                (
                    dir.join(name),
                    format!("{}, t = {:.2}{note}", plan.title, f.t),
                    f,
                )
            })
            .collect();
        plot_snapshots(scene, &shots)?;
        if plan.max_frames > 0 {
            let mut frames = rec.frames;
            // Always end on the last state computed.
            if let Some(last) = rec.last {
                if frames.last().is_none_or(|f| f.t < last.t) {
                    frames.push(last);
                }
            }
            write_animation(&dir.join("animation.gif"), scene, &frames, &plan.title)?;
            files.push("animation.gif".to_owned());
        }
        plot_top_block(&dir.join("top_block.png"), &rec.top, &plan.title)?;
        files.push("top_block.png".to_owned());
        files.push("run.json".to_owned());
    }
    let report = SimulationReport {
        steps: summary.steps,
        failure_time: summary.failure_time,
        final_poses: summary.final_poses.clone(),
        min_gap: summary.min_gap,
        newton_iterations_mean: summary.newton_iterations_mean,
        wall_time_s: summary.wall_time_s,
        opening_time: summary.opening_time,
        failed_steps: summary.failed_steps,
        branch_points: summary.branch_points.len(),
        split_steps: summary.split_steps,
        linear_solves: summary.linear_solves,
        max_energy_increase: summary.max_energy_increase,
        error: summary.error.clone(),
        t_final,
        prox: describe_prox(scene, options),
        files,
    };
    if let Some(dir) = &plan.dir {
        write_run_json(
            dir,
            command,
            inputs,
            &serde_json::json!({
                "solver_s": summary.wall_time_s,
                "total_s": start.elapsed().as_secs_f64(),
                "steps": summary.steps,
                "write_error": write_error,
            }),
        )?;
    }
    Ok(SimulationOutput {
        summary,
        report,
        snapshots,
        top: rec.top,
        write_error,
    })
}

/// File name of the snapshot at requested time t, e.g. `snapshot_t6.4.png`.
#[must_use]
pub fn snapshot_name(t: f64) -> String {
    // Six decimals at most: `snapshot_t7.853982.png`, not all seventeen digits.
    format!("snapshot_t{}.png", (t * 1e6).round() / 1e6)
}

fn write_branch_points(path: &Path, summary: &RunSummary) -> Result<()> {
    let rows: Vec<Vec<f64>> = summary
        .branch_points
        .iter()
        .map(|b| vec![b.t, b.candidates as f64, b.distinct as f64])
        .collect();
    write_csv_f64(path, &["t", "candidates", "distinct"], &rows)
}

/// The top block's angle and height against time (Figures 4.5 (b), (c)).
fn plot_top_block(path: &Path, top: &[(f64, f64, f64)], title: &str) -> Result<()> {
    let angle = LinePlot::new(format!("{title}: top block angle"), "t", "theta (rad)")
        .with(Series::line("", top.iter().map(|p| (p.0, p.1)).collect()));
    let height = LinePlot::new(format!("{title}: top block height"), "t", "y")
        .with(Series::line("", top.iter().map(|p| (p.0, p.2)).collect()));
    with_png(path, (1400, 550), |root| {
        let (left, right) = root.split_horizontally(700);
        angle.draw(&left)?;
        height.draw(&right)
    })
}

/// Prints the report (JSON or text) and turns a run that stopped early or output that
/// could not be written into a non-zero exit after the output is out.
fn finish_command(out: &SimulationOutput, json: bool, dir: Option<&Path>) -> Result<()> {
    let r = &out.report;
    if json {
        print_json(r)?;
    } else {
        println!(
            "{} steps to t = {:.4} (solver {:.3} s, {:.2} Newton iterations per step, prox {})",
            r.steps, r.t_final, r.wall_time_s, r.newton_iterations_mean, r.prox
        );
        let time = |t: Option<f64>| t.map_or_else(|| "none".to_owned(), |t| format!("{t:.4}"));
        println!(
            "failure (loss of support) at t = {}, first full opening at t = {}",
            time(r.failure_time),
            time(r.opening_time)
        );
        println!(
            "min gap {:.3e}, failed Newton steps {}, branch points {}, split steps {}, linear solves {}, largest energy increase {:.3e}",
            r.min_gap, r.failed_steps, r.branch_points, r.split_steps, r.linear_solves, r.max_energy_increase
        );
        for (k, p) in r.final_poses.iter().enumerate() {
            println!(
                "block {}: x = {:.6}, y = {:.6}, theta = {:.6}",
                k + 1,
                p.x,
                p.y,
                p.theta
            );
        }
        if let Some(dir) = dir {
            println!("wrote {} files into {}", r.files.len(), dir.display());
        }
    }
    if let Some(e) = &r.error {
        anyhow::bail!(
            "the simulation stopped at t = {:.6} after {} steps: {e}{}",
            r.t_final,
            r.steps,
            dir.map_or_else(String::new, |d| format!(
                " (results up to then are in {})",
                d.display()
            ))
        );
    }
    if let Some(e) = &out.write_error {
        anyhow::bail!("{e}");
    }
    Ok(())
}

fn read_scene(path: &Path) -> Result<Scene> {
    let text = std::fs::read_to_string(path)
        .with_context(|| format!("cannot read scene {}", path.display()))?;
    Scene::from_toml(&text).with_context(|| format!("scene {}", path.display()))
}

fn run_scene_file(args: &RunArgs) -> Result<()> {
    let scene = read_scene(&args.scene)?;
    let options = args.solver.run_options(args.t_end, false)?;
    let t_end = options.t_end.unwrap_or(scene.solver.t_end);
    let plan = OutputPlan {
        dir: args.output.out.clone(),
        snapshots: args
            .output
            .snapshots
            .clone()
            .unwrap_or_else(|| vec![0.0, 0.5 * t_end, t_end]),
        max_frames: args.output.max_frames,
        title: args
            .scene
            .file_stem()
            .map_or_else(|| "scene".to_owned(), |s| s.to_string_lossy().into_owned()),
    };
    let inputs = serde_json::json!({
        "scene": args.scene.display().to_string(),
        "t_end": t_end,
        "prox_constant": args.solver.prox_constant,
        "explore_branches": args.solver.explore_branches,
        "snapshots": plan.snapshots,
    });
    let out = simulate_with_output(&scene, &options, &plan, "blocks run", &inputs)?;
    finish_command(&out, args.output.json, plan.dir.as_deref())
}

/// Snapshot times of Figure 4.4.
pub const LIRE_SNAPSHOTS: [f64; 3] = [0.0, 5.0, 6.4];

fn run_lire(args: &LireArgs) -> Result<()> {
    anyhow::ensure!(args.blocks >= 1, "--blocks must be at least 1");
    let scene = if args.floor {
        lire_on_floor(args.blocks, args.perturb.into())?
    } else {
        lire(args.blocks, args.perturb.into())?
    };
    let options = args.solver.run_options(Some(args.t_end), false)?;
    let plan = OutputPlan {
        dir: args.output.out.clone(),
        snapshots: args
            .output
            .snapshots
            .clone()
            .unwrap_or_else(|| LIRE_SNAPSHOTS.to_vec()),
        max_frames: args.output.max_frames,
        title: format!(
            "Lire tower, perturbation {}",
            format!("{:?}", args.perturb).to_lowercase()
        ),
    };
    let inputs = serde_json::json!({
        "blocks": args.blocks,
        "perturb": format!("{:?}", args.perturb).to_lowercase(),
        "floor": args.floor,
        "t_end": args.t_end,
        "prox_constant": args.solver.prox_constant,
        "explore_branches": args.solver.explore_branches,
        "snapshots": plan.snapshots,
    });
    let out = simulate_with_output(&scene, &options, &plan, "blocks lire", &inputs)?;
    finish_command(&out, args.output.json, plan.dir.as_deref())
}

// ---------------------------------------------------------------------------------------
// Sweeps.

/// The sweeps of §4.4–4.5.
#[derive(Debug, Subcommand)]
pub enum SweepCommand {
    /// Failure time T of a shaken column against the base frequency ω (Figure 4.6: four
    /// blocks w = 0.2, h = 0.4 on a base w = 1, h = 0.1, μ = 0.2, Δt = 2π/(100ω)).
    Frequency(FrequencyArgs),
    /// Angle of the top block at t_end against the speed v0 of the pulled base (Figure 4.7:
    /// base and blocks w = 0.2, h = 0.4, μ = 0.2, t_end = 3).
    Slide(SlideArgs),
}

/// Options shared by the sweeps.
#[derive(Debug, Clone, Args)]
pub struct SweepOutputArgs {
    /// Run only part K of N of the values (a contiguous block, so the parts' CSV rows
    /// concatenate in input order).
    #[arg(long, default_value = "1/1")]
    pub shard: Shard,
    /// Directory for the CSV, the PNG and run.json (created if missing).
    #[arg(long)]
    pub out: PathBuf,
    /// Also print the rows as one JSON object on stdout.
    #[arg(long)]
    pub json: bool,
}

/// Arguments of `rollstack blocks sweep frequency`.
#[derive(Debug, Args)]
pub struct FrequencyArgs {
    /// Base angular frequencies ω (rad per time unit), as A:B:STEP or one value.
    #[arg(long, allow_hyphen_values = true)]
    pub omega: String,
    /// Number of base periods simulated per run (the run stops at the failure).
    #[arg(long, default_value_t = 10.0, value_parser = parse_finite, allow_hyphen_values = true)]
    pub periods: f64,
    /// Base amplitude A (length units; the thesis's "A = w²" is ambiguous).
    #[arg(long, default_value_t = 0.2, value_parser = parse_finite, allow_hyphen_values = true)]
    pub amplitude: f64,
    /// Number of free blocks on the base.
    #[arg(long, default_value_t = 4)]
    pub blocks: usize,
    /// Steps per base period N: Δt = 2π/(Nω) (Figure 4.6: 100; ERRATA 21).
    #[arg(long, default_value_t = 100.0, value_parser = parse_finite, allow_hyphen_values = true)]
    pub steps_per_period: f64,
    /// Friction coefficient μ at every contact (dimensionless).
    #[arg(long, default_value_t = 0.2, value_parser = parse_finite, allow_hyphen_values = true)]
    pub mu: f64,
    #[command(flatten)]
    #[allow(missing_docs)]
    pub solver: SolverArgs,
    #[command(flatten)]
    #[allow(missing_docs)]
    pub output: SweepOutputArgs,
}

/// Arguments of `rollstack blocks sweep slide`.
#[derive(Debug, Args)]
pub struct SlideArgs {
    /// Base speeds v0 (length per time unit), as A:B:STEP or one value.
    #[arg(long, allow_hyphen_values = true)]
    pub v0: String,
    /// Time at which the top block's angle is read (Figure 4.7: 3; ERRATA 21).
    #[arg(long, default_value_t = 3.0, value_parser = parse_finite, allow_hyphen_values = true)]
    pub t_end: f64,
    /// Number of free blocks on the base (Figure 4.7: 4, the thesis's "five" with the base).
    #[arg(long, default_value_t = 4)]
    pub blocks: usize,
    #[command(flatten)]
    #[allow(missing_docs)]
    pub solver: SolverArgs,
    #[command(flatten)]
    #[allow(missing_docs)]
    pub output: SweepOutputArgs,
}

/// One run of the frequency sweep.
#[derive(Debug, Clone, Serialize)]
pub struct FrequencyRow {
    /// ω.
    pub omega: f64,
    /// Failure time T (loss of support), or null when the column survived.
    pub failure_time: Option<f64>,
    /// 1/T, 0 when the column survived the simulated periods.
    pub inv_failure_time: Option<f64>,
    /// First full opening of an interface, or null.
    pub opening_time: Option<f64>,
    /// Steps taken.
    pub steps: usize,
    /// Why the run stopped early (or could not start), or null.
    pub error: Option<String>,
    /// Steps whose first Newton attempt failed.
    pub failed_steps: usize,
    /// Branch points recorded.
    pub branch_points: usize,
    /// Solver time (s).
    pub wall_time_s: f64,
}

/// The shaken column of the frequency sweep at one ω.
///
/// # Errors
/// Bad parameters (ω ≤ 0, …).
pub fn frequency_scene(args: &FrequencyArgs, omega: f64) -> Result<Scene> {
    Ok(shaking_column(&Shaking {
        blocks: args.blocks,
        amplitude: args.amplitude,
        omega,
        periods: args.periods,
        steps_per_period: args.steps_per_period,
        mu: args.mu,
    })?)
}

/// Runs one ω; every failure goes into the row.
#[must_use]
pub fn frequency_row(scene: Result<Scene>, omega: f64, options: &RunOptions) -> FrequencyRow {
    let mut row = FrequencyRow {
        omega,
        failure_time: None,
        inv_failure_time: None,
        opening_time: None,
        steps: 0,
        error: None,
        failed_steps: 0,
        branch_points: 0,
        wall_time_s: 0.0,
    };
    match scene.and_then(|s| Ok(simulate(&s, options, |_| {})?)) {
        Ok(s) => {
            row.failure_time = s.failure_time;
            // Survival over the whole run: 1/T = 0 (Figure 4.6's baseline), unless the run
            // stopped early, when nothing is known.
            row.inv_failure_time = match (s.failure_time, &s.error) {
                (Some(t), _) if t > 0.0 => Some(1.0 / t),
                (None, None) => Some(0.0),
                _ => None,
            };
            row.opening_time = s.opening_time;
            row.steps = s.steps;
            row.error = s.error.map(|e| one_line(&e));
            row.failed_steps = s.failed_steps;
            row.branch_points = s.branch_points.len();
            row.wall_time_s = s.wall_time_s;
        }
        Err(e) => row.error = Some(one_line(&format!("{e:#}"))),
    }
    row
}

fn one_line(s: &str) -> String {
    s.replace(['\n', '\r'], " ")
}

fn opt_cell(v: Option<f64>) -> String {
    v.map_or_else(String::new, finite_cell)
}

fn sweep_values(text: &str, name: &str, shard: Shard) -> Result<Vec<f64>> {
    let all = parse_range(text).with_context(|| format!("--{name}"))?;
    Ok(shard.select(&all).into_iter().map(|(_, v)| v).collect())
}

fn sweep_frequency(args: &FrequencyArgs) -> Result<()> {
    let start = Instant::now();
    anyhow::ensure!(args.blocks >= 1, "--blocks must be at least 1");
    anyhow::ensure!(args.periods > 0.0, "--periods must be positive");
    anyhow::ensure!(
        args.steps_per_period > 0.0,
        "--steps-per-period must be positive"
    );
    anyhow::ensure!(args.mu >= 0.0, "--mu must not be negative");
    let options = args.solver.run_options(None, true)?;
    let omegas = sweep_values(&args.omega, "omega", args.output.shard)?;
    let rows = par_map_ordered(&omegas, "omega", |&w| {
        frequency_row(frequency_scene(args, w), w, &options)
    });
    let dir = &args.output.out;
    ensure_dir(dir)?;
    write_frequency_files(dir, &rows)?;
    finish_sweep(
        "frequency",
        &args.output,
        &args.solver,
        serde_json::json!({
            "omega": args.omega, "periods": args.periods, "amplitude": args.amplitude,
            "blocks": args.blocks, "steps_per_period": args.steps_per_period, "mu": args.mu,
        }),
        &rows,
        rows.iter().map(|r| r.wall_time_s).sum(),
        start,
        |r| {
            format!(
                "omega = {:.4}: T = {}, steps {}{}",
                r.omega,
                r.failure_time
                    .map_or_else(|| "none".to_owned(), |t| format!("{t:.4}")),
                r.steps,
                error_suffix(r.error.as_ref())
            )
        },
    )
}

/// What every sweep does once its rows are written: `run.json` (inputs, version,
/// timings), then either `{"rows": [...]}` on stdout or one line per row.
///
/// # Errors
/// An unwritable directory.
fn finish_sweep<R: Serialize>(
    name: &str,
    output: &SweepOutputArgs,
    solver: &SolverArgs,
    mut inputs: serde_json::Value,
    rows: &[R],
    solver_seconds: f64,
    start: Instant,
    line: impl Fn(&R) -> String,
) -> Result<()> {
    inputs["shard"] = format!("{}/{}", output.shard.index, output.shard.count).into();
    inputs["prox_constant"] = serde_json::json!(solver.prox_constant);
    inputs["explore_branches"] = solver.explore_branches.into();
    write_run_json(
        &output.out,
        &format!("blocks sweep {name}"),
        &inputs,
        &serde_json::json!({
            "total_s": start.elapsed().as_secs_f64(),
            "solver_s": solver_seconds,
        }),
    )?;
    if output.json {
        return print_json(&serde_json::json!({ "rows": rows }));
    }
    for r in rows {
        println!("{}", line(r));
    }
    println!(
        "wrote sweep_{name}.csv and sweep_{name}.png into {}",
        output.out.display()
    );
    Ok(())
}

/// `, error: …` after a sweep row's line, or nothing.
fn error_suffix(error: Option<&String>) -> String {
    error.map_or_else(String::new, |e| format!(", error: {e}"))
}

/// Writes `sweep_frequency.csv` and `sweep_frequency.png` (Figure 4.6).
///
/// # Errors
/// An unwritable directory.
pub fn write_frequency_files(dir: &Path, rows: &[FrequencyRow]) -> Result<()> {
    write_csv(
        &dir.join("sweep_frequency.csv"),
        &[
            "omega",
            "failure_time",
            "inv_failure_time",
            "opening_time",
            "steps",
            "error",
            "failed_steps",
            "branch_points",
            "wall_time_s",
        ],
        rows.iter().map(|r| {
            vec![
                finite_cell(r.omega),
                opt_cell(r.failure_time),
                opt_cell(r.inv_failure_time),
                opt_cell(r.opening_time),
                r.steps.to_string(),
                r.error.clone().unwrap_or_default(),
                r.failed_steps.to_string(),
                r.branch_points.to_string(),
                finite_cell(r.wall_time_s),
            ]
        }),
    )?;
    let points: Vec<(f64, f64)> = rows
        .iter()
        .filter_map(|r| r.inv_failure_time.map(|v| (r.omega, v)))
        .collect();
    LinePlot::new(
        "Figure 4.6: onset of failure of a shaken column",
        "omega (rad per time unit)",
        "1/T (failure: loss of support)",
    )
    .with(Series::line("", points.clone()))
    .with(Series::markers("1/T (0: survived)", points))
    .save(&dir.join("sweep_frequency.png"), (900, 600))
}

/// How the column on a pulled base ends (§4.5).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum SlideRegime {
    /// Small v0: the column rides along, upright, on the base.
    RidesAlong,
    /// Intermediate v0: the blocks rotate about the base's corner and topple.
    Topples,
    /// Large v0: the base is pulled out and the column drops almost straight
    /// (tablecloth trick).
    Drops,
}

impl SlideRegime {
    /// The name written to the CSV.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::RidesAlong => "rides-along",
            Self::Topples => "topples",
            Self::Drops => "drops",
        }
    }
}

/// The tipping angle atan(w/h) of a block standing on a level face: turned further, its
/// centre of mass is beyond the corner it pivots on and gravity turns it further.
#[must_use]
pub fn tipping_angle(width: f64, height: f64) -> f64 {
    width.atan2(height)
}

/// Classifies the end state: any block turned beyond its [`tipping_angle`] → topples;
/// else the lowest block still above the base's top face (its centre higher than the
/// base top) and horizontally over the base → rides along (possibly rocking); else →
/// drops.
#[must_use]
pub fn slide_regime(scene: &Scene, last: &StackFrame) -> SlideRegime {
    let toppled = last
        .blocks
        .iter()
        .zip(scene.blocks())
        .any(|(p, b)| p.theta.abs() > tipping_angle(b.width(), b.height()));
    if toppled {
        return SlideRegime::Topples;
    }
    let base = scene.base();
    let on_base = last
        .blocks
        .first()
        .is_some_and(|p| p.y > base.top() && (p.x - last.base.x).abs() < 0.5 * base.width());
    if on_base {
        SlideRegime::RidesAlong
    } else {
        SlideRegime::Drops
    }
}

/// One run of the slide sweep.
#[derive(Debug, Clone, Serialize)]
pub struct SlideRow {
    /// v0.
    pub v0: f64,
    /// Angle θ of the top block at the last step (rad).
    pub top_angle: Option<f64>,
    /// The regime, or null when the run failed.
    pub regime: Option<SlideRegime>,
    /// Steps taken.
    pub steps: usize,
    /// Why the run stopped early (or could not start), or null.
    pub error: Option<String>,
    /// Time of the last step.
    pub t_final: f64,
    /// Failure time (loss of support), or null.
    pub failure_time: Option<f64>,
    /// Steps whose first Newton attempt failed.
    pub failed_steps: usize,
    /// Solver time (s).
    pub wall_time_s: f64,
}

/// Runs the sliding column at one v0; every failure goes into the row.
#[must_use]
pub fn slide_row(blocks: usize, v0: f64, t_end: f64, options: &RunOptions) -> SlideRow {
    let mut row = SlideRow {
        v0,
        top_angle: None,
        regime: None,
        steps: 0,
        error: None,
        t_final: 0.0,
        failure_time: None,
        failed_steps: 0,
        wall_time_s: 0.0,
    };
    let scene = match sliding_column(blocks, v0, t_end) {
        Ok(s) => s,
        Err(e) => {
            row.error = Some(one_line(&e.to_string()));
            return row;
        }
    };
    let mut last: Option<StackFrame> = None;
    match simulate(&scene, options, |r| last = Some(StackFrame::from_record(r))) {
        Ok(s) => {
            row.steps = s.steps;
            row.failure_time = s.failure_time;
            row.failed_steps = s.failed_steps;
            row.wall_time_s = s.wall_time_s;
            row.error = s.error.map(|e| one_line(&e));
            if let Some(f) = last.filter(StackFrame::is_finite) {
                row.t_final = f.t;
                row.top_angle = f.blocks.last().map(|p| p.theta);
                if row.error.is_none() {
                    row.regime = Some(slide_regime(&scene, &f));
                }
            }
        }
        Err(e) => row.error = Some(one_line(&e.to_string())),
    }
    row
}

fn sweep_slide(args: &SlideArgs) -> Result<()> {
    let start = Instant::now();
    anyhow::ensure!(args.blocks >= 1, "--blocks must be at least 1");
    let options = args.solver.run_options(Some(args.t_end), false)?;
    let speeds = sweep_values(&args.v0, "v0", args.output.shard)?;
    let rows = par_map_ordered(&speeds, "v0", |&v| {
        slide_row(args.blocks, v, args.t_end, &options)
    });
    let dir = &args.output.out;
    ensure_dir(dir)?;
    write_slide_files(dir, &rows, args.t_end)?;
    finish_sweep(
        "slide",
        &args.output,
        &args.solver,
        serde_json::json!({ "v0": args.v0, "t_end": args.t_end, "blocks": args.blocks }),
        &rows,
        rows.iter().map(|r| r.wall_time_s).sum(),
        start,
        |r| {
            format!(
                "v0 = {:.4}: top angle {} at t = {:.3}, {}{}",
                r.v0,
                r.top_angle
                    .map_or_else(|| "-".to_owned(), |a| format!("{a:.4} rad")),
                r.t_final,
                r.regime.map_or("-", SlideRegime::name),
                error_suffix(r.error.as_ref())
            )
        },
    )
}

/// Writes `sweep_slide.csv` and `sweep_slide.png` (Figure 4.7).
///
/// # Errors
/// An unwritable directory.
pub fn write_slide_files(dir: &Path, rows: &[SlideRow], t_end: f64) -> Result<()> {
    write_csv(
        &dir.join("sweep_slide.csv"),
        &[
            "v0",
            "top_angle",
            "regime",
            "steps",
            "error",
            "t_final",
            "failure_time",
            "failed_steps",
            "wall_time_s",
        ],
        rows.iter().map(|r| {
            vec![
                finite_cell(r.v0),
                opt_cell(r.top_angle),
                r.regime.map_or("", SlideRegime::name).to_owned(),
                r.steps.to_string(),
                r.error.clone().unwrap_or_default(),
                finite_cell(r.t_final),
                opt_cell(r.failure_time),
                r.failed_steps.to_string(),
                finite_cell(r.wall_time_s),
            ]
        }),
    )?;
    // The curve joins the runs that reached t_end; runs that stopped early are shown
    // apart, at the angle they had when they stopped.
    let mut plot = LinePlot::new(
        format!("Figure 4.7: top block angle at t = {t_end} against base speed"),
        "v0 (length per time unit)",
        "theta of the top block (rad)",
    )
    .with(Series::line(
        "",
        rows.iter()
            .filter(|r| r.error.is_none())
            .filter_map(|r| r.top_angle.map(|a| (r.v0, a)))
            .collect(),
    ));
    for regime in [
        SlideRegime::RidesAlong,
        SlideRegime::Topples,
        SlideRegime::Drops,
    ] {
        let pts: Vec<(f64, f64)> = rows
            .iter()
            .filter(|r| r.regime == Some(regime))
            .filter_map(|r| r.top_angle.map(|a| (r.v0, a)))
            .collect();
        if !pts.is_empty() {
            plot = plot.with(Series::markers(regime.name(), pts));
        }
    }
    let stopped: Vec<(f64, f64)> = rows
        .iter()
        .filter(|r| r.error.is_some())
        .filter_map(|r| r.top_angle.map(|a| (r.v0, a)))
        .collect();
    if !stopped.is_empty() {
        plot = plot.with(Series::markers(
            "stopped early (angle at the stop)",
            stopped,
        ));
    }
    plot.save(&dir.join("sweep_slide.png"), (900, 600))
}

#[cfg(test)]
mod tests {
    use super::*;
    use blockstack::simulation::InterfaceForce;

    fn record(t: f64, x: f64) -> StepRecord {
        StepRecord {
            t,
            poses: vec![BlockPose {
                x,
                y: 0.25,
                theta: 0.0,
            }],
            base: BlockPose {
                x: 0.0,
                y: 0.0,
                theta: 0.0,
            },
            forces: vec![InterfaceForce {
                normal: [0.5, 0.5],
                friction: 0.0,
            }],
            min_gap: f64::INFINITY,
            iterations: 1,
            energy: 0.25,
        }
    }

    #[test]
    fn trajectory_keeps_the_rows_before_a_non_finite_state() {
        let dir = std::env::temp_dir().join(format!("rollstack-traj-{}", std::process::id()));
        ensure_dir(&dir).unwrap();
        let path = dir.join("trajectory.csv");
        let mut w = TrajectoryWriter::create(&path, 1).unwrap();
        w.row(&record(0.0, 0.0)).unwrap();
        w.row(&record(0.01, 1e-20)).unwrap();
        assert!(w.row(&record(0.02, f64::NAN)).is_err());
        // Nothing at the final path until the run ends; then the rows computed are kept.
        assert!(!path.exists());
        w.finish().unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        assert_eq!(
            text,
            "t,x1,y1,theta1,n1a,n1b,f1,base_x,min_gap,newton_iterations,energy\n\
             0.0,0.0,0.25,0.0,0.5,0.5,0.0,0.0,,1,0.25\n\
             0.01,1e-20,0.25,0.0,0.5,0.5,0.0,0.0,,1,0.25\n"
        );
        std::fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn slide_regimes_from_the_end_state() {
        let scene = sliding_column(2, 1.0, 3.0).unwrap();
        let frame = |base_x: f64, blocks: &[(f64, f64, f64)]| StackFrame {
            t: 3.0,
            base: Pose::new(base_x, 0.0, 0.0),
            blocks: blocks
                .iter()
                .map(|&(x, y, th)| Pose::new(x, y, th))
                .collect(),
        };
        // Upright on the base, carried along.
        let ride = frame(1.0, &[(1.0, 0.4, 0.0), (1.0, 0.8, 0.01)]);
        assert_eq!(slide_regime(&scene, &ride), SlideRegime::RidesAlong);
        // The base pulled out, the column upright on the floor.
        let drop = frame(3.0, &[(0.1, 0.0, 0.0), (0.1, 0.4, -0.05)]);
        assert_eq!(slide_regime(&scene, &drop), SlideRegime::Drops);
        // A block lying on its side.
        let topple = frame(3.0, &[(0.1, 0.0, 0.0), (0.4, -0.1, 1.5)]);
        assert_eq!(slide_regime(&scene, &topple), SlideRegime::Topples);
        // Rocking on the base within the tipping angle atan(0.2/0.4) = 26.57° rides along;
        // beyond it topples.
        let rock = frame(1.0, &[(1.0, 0.4, 0.0), (1.0, 0.8, 0.46)]);
        assert_eq!(slide_regime(&scene, &rock), SlideRegime::RidesAlong);
        let tip = frame(1.0, &[(1.0, 0.4, 0.0), (1.0, 0.8, -0.47)]);
        assert_eq!(slide_regime(&scene, &tip), SlideRegime::Topples);
        assert_eq!(snapshot_name(6.4), "snapshot_t6.4.png");
        assert_eq!(snapshot_name(0.0), "snapshot_t0.png");
        assert_eq!(
            snapshot_name(2.5 * std::f64::consts::PI),
            "snapshot_t7.853982.png"
        );
    }
}
