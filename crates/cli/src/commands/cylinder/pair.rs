//! `rollstack cylinder pair`: the transport of two touching cylinders at one
//! inclination (§3.6), stepped by nsga ([`cylinders::studies::pair`]).

use crate::commands::tuning::TuningArgs;
use crate::output::{ensure_dir, print_json, write_csv, write_run_json};
use anyhow::Result;
use clap::Args;
use cylinders::studies::pair::{run_pair_with, PairReport, PairSample, PairSettings};
use cylinders::transport::SpinProfile;
use figures::cylinders::{plot_pair_forces, plot_pair_view, write_pair_animation};
use input::text::{parse_finite, parse_value, RotationAngle};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Frames of the animation.
const ANIMATION_FRAMES: usize = 60;

/// Arguments of `rollstack cylinder pair`.
#[derive(Debug, Args)]
pub struct PairArgs {
    /// Inclination ϑ of both cylinders, in (arctan(2r/h), π/2), rad (`30deg` accepted).
    #[arg(long, allow_hyphen_values = true)]
    pub theta: RotationAngle,
    /// Time step Δt, s.
    #[arg(long, default_value_t = 2e-3, value_parser = parse_finite, allow_hyphen_values = true)]
    pub dt: f64,
    /// Number of steps.
    #[arg(long, default_value_t = 2000, allow_hyphen_values = true)]
    pub steps: usize,
    /// Prescribed spin φ̇10 of cylinder I, rad/s (the thesis: −6π, written `-6pi`).
    #[arg(long, default_value_t = -6.0 * std::f64::consts::PI, value_parser = parse_value, allow_hyphen_values = true)]
    pub spin: f64,
    /// Spin up smoothly over this many seconds (from 1 % of --spin) instead of giving the
    /// spin at t = 0.
    #[arg(long, value_parser = parse_finite, allow_hyphen_values = true)]
    pub ramp: Option<f64>,
    /// Horizontal push P/mg at each top along e′2 (the applied force F of §3.3).
    #[arg(long, default_value_t = 0.0, value_parser = parse_finite, allow_hyphen_values = true)]
    pub push: f64,
    /// Floor friction coefficient μ_s (default 1, not the 0.2 of the other cylinder
    /// commands: Figure 3.14 rolls both cylinders on the floor without slip, which μ_s = 1
    /// holds; the 0.2 of Figures 3.3–3.8 may let the rims slip).
    #[arg(long, default_value_t = 1.0, value_parser = parse_finite, allow_hyphen_values = true)]
    pub mu_floor: f64,
    /// Friction coefficient μ_k between the cylinders.
    #[arg(long, default_value_t = 0.4, value_parser = parse_finite, allow_hyphen_values = true)]
    pub mu_k: f64,
    /// Write pair_trajectory.csv, pair_forces.png, pair_view.png, pair_animation.gif and
    /// run.json here.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Print one JSON object on stdout.
    #[arg(long)]
    pub json: bool,
    /// Run even when the run is estimated to take longer than ten minutes, and go on
    /// when it is projected past ten minutes as it runs (its watchdog).
    #[arg(long)]
    pub force: bool,
    #[command(flatten)]
    #[allow(missing_docs)]
    pub tuning: TuningArgs,
}

impl PairArgs {
    fn settings(&self) -> PairSettings {
        PairSettings {
            dt: self.dt,
            steps: self.steps,
            spin: self.ramp.map_or(SpinProfile::constant(self.spin), |d| {
                SpinProfile::ramp(self.spin, d)
            }),
            push_over_mg: self.push,
            mu_floor: self.mu_floor,
            mu_mutual: self.mu_k,
            time_bound: super::guard::time_bound(self.force),
            ..PairSettings::thesis(self.theta.0)
        }
    }
}

pub(super) fn run(a: &PairArgs) -> Result<()> {
    let start = Instant::now();
    let settings = a.settings();
    super::check_steps(a.dt, a.steps)?;
    // Checked here so that the errors name the flags, not the library's ramp, μ_s, μ_k.
    if let Some(ramp) = a.ramp {
        input::positive("--ramp", ramp)?;
    }
    input::non_negative("--mu-floor", a.mu_floor)?;
    input::non_negative("--mu-k", a.mu_k)?;
    super::check_theta(settings.theta, &settings.cylinder)?;
    super::guard::check_time_bound(&settings, 1, 1, a.force, super::guard::FEWER_STEPS)?;
    let busy = crate::progress::busy("cylinder pair: solving", !a.json);
    let mut options = settings.stepper_options();
    a.tuning.apply(&mut options)?;
    let never = std::sync::atomic::AtomicBool::new(false);
    let mut report = run_pair_with(&settings, options, a.out.is_some(), &never)?;
    let trajectory = report.trajectory.take();
    if let (Some(dir), Some(samples)) = (&a.out, &trajectory) {
        busy.set_message("cylinder pair: writing the files and the animation");
        ensure_dir(dir)?;
        write_pair_files(dir, &settings, &report, samples)?;
        write_run_json(
            dir,
            "cylinder pair",
            &settings,
            &serde_json::json!({"total_s": start.elapsed().as_secs_f64(), "solver_s": report.wall_time_s}),
        )?;
    }
    busy.finish_and_clear();
    if a.json {
        return print_json(&report);
    }
    println!(
        "ϑ = {:.4} rad, {} steps in {:.3} s: N/mg = {:?}, F3/mg = {:?} ((3.3.10): N/mg = {:.10}, \
         off by {:.1e}); contact normal force {:.1e} mg; drift {:.1e}; smallest gap {:.1e}",
        report.theta,
        report.steps,
        report.wall_time_s,
        report.n_over_mg,
        report.f3_over_mg,
        report.n_over_mg_static,
        report.static_error,
        report.contact_normal_force,
        report.drift,
        report.min_gap
    );
    if let Some(dir) = &a.out {
        println!(
            "wrote pair_trajectory.csv, pair_forces.png, pair_view.png, pair_animation.gif \
             and run.json into {}",
            dir.display()
        );
    }
    Ok(())
}

/// Writes the trajectory CSV, the force plot, the last frame and the animation.
fn write_pair_files(
    dir: &Path,
    settings: &PairSettings,
    report: &PairReport,
    samples: &[PairSample],
) -> Result<()> {
    let header: Vec<&str> = PairSample::CSV_HEADER.split(',').collect();
    write_csv(
        &dir.join("pair_trajectory.csv"),
        &header,
        samples.iter().map(PairSample::csv_cells),
    )?;
    let title = format!("Two cylinders, ϑ = {:.1}°", report.theta.to_degrees());
    plot_pair_forces(
        &dir.join("pair_forces.png"),
        samples,
        report.n_over_mg_static,
        &format!("{title}: support and contact forces"),
    )?;
    let last = samples.last().map_or(&[][..], |s| &s.q[..]);
    plot_pair_view(&dir.join("pair_view.png"), &settings.cylinder, last, &title)?;
    let stride = samples.len().div_ceil(ANIMATION_FRAMES).max(1);
    let frames: Vec<(f64, Vec<f64>)> = samples
        .iter()
        .step_by(stride)
        .map(|s| (s.t, s.q.clone()))
        .collect();
    write_pair_animation(
        &dir.join("pair_animation.gif"),
        &settings.cylinder,
        &frames,
        &title,
    )?;
    Ok(())
}
