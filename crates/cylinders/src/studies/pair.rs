//! The transport of two touching cylinders (§3.6, Figure 3.14), stepped by nsga: what
//! `rollstack cylinder pair` and `rollstack cylinder sweep pair` report.
//!
//! Without a push, steady transport needs no floor friction and the support forces are
//! the smooth-floor formula (3.3.10), with zero force between the cylinders
//! (docs/errata.md, item 14); [`PairReport::static_error`] measures that.

use crate::error::CylinderError;
use crate::kinematics::Cylinder;
use crate::statics::{FrictionLimit, MinForceCase, SupportProblem};
use crate::transport::{check_inclination, top_height, PairTransport, SpinProfile};
use input::watchdog::{Clock, WallClock, Watchdog};
use nsga::{Options, PolicyOptions, Stepper, System};
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

/// What to simulate: the thesis's transport with its defaults (§3.6).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PairSettings {
    /// Inclination ϑ of both cylinders (rad), in (arctan(2r/h), π/2).
    pub theta: f64,
    /// The cylinders (default: the gas cylinders, h = 1.2954 m, r = 0.1143 m).
    pub cylinder: Cylinder,
    /// Time step Δt (s), default 2 ms.
    pub dt: f64,
    /// Number of steps, default 2000.
    pub steps: usize,
    /// ρ∞ of the generalized-α scheme, default 0.5.
    pub rho_inf: f64,
    /// The prescribed spin of cylinder I (default: −6π rad/s from t = 0).
    pub spin: SpinProfile,
    /// Floor friction μ_s (default 1; idle without a push).
    pub mu_floor: f64,
    /// Friction between the cylinders μ_k (default 0.4).
    pub mu_mutual: f64,
    /// Horizontal push P/mg at each top along e′2 (default 0).
    pub push_over_mg: f64,
    /// The run-time watchdog's bound, s ([`input::watchdog`], over steps done): a run
    /// projected past it is stopped with [`CylinderError::Stopped`]. `None` (the
    /// default, and a forced run): not watched. Not a setting of the motion: left out
    /// of the JSON.
    #[serde(skip)]
    pub time_bound: Option<f64>,
}

impl PairSettings {
    /// The thesis's settings at inclination ϑ.
    #[must_use]
    pub fn thesis(theta: f64) -> Self {
        Self {
            theta,
            cylinder: Cylinder::gas_cylinder(),
            dt: 2e-3,
            steps: 2000,
            rho_inf: 0.5,
            spin: SpinProfile::constant(-6.0 * PI),
            mu_floor: 1.0,
            mu_mutual: 0.4,
            push_over_mg: 0.0,
            time_bound: None,
        }
    }

    /// nsga's options for these settings: Δt, ρ∞ and up to four halvings.
    #[must_use]
    pub fn stepper_options(&self) -> Options {
        Options {
            dt: self.dt,
            rho_inf: self.rho_inf,
            policy: PolicyOptions {
                max_halvings: 4,
                ..PolicyOptions::default()
            },
            ..Options::default()
        }
    }

    /// The system these settings describe.
    ///
    /// # Errors
    /// A one-line message for the first bad setting: ϑ outside (arctan(2r/h), π/2),
    /// r ≥ h/2, Δt not positive, no steps, ρ∞ outside [0, 1], negative friction.
    pub fn system(&self) -> Result<PairTransport, CylinderError> {
        input::positive("time step Δt", self.dt)?;
        if self.steps == 0 {
            return Err(input::InputError::OutOfRange {
                name: "steps".into(),
                range: "at least 1",
                value: 0.0,
            }
            .into());
        }
        input::in_range("ρ∞", self.rho_inf, 0.0..=1.0, "[0, 1]")?;
        let mut sys = PairTransport::thesis(0.5);
        sys.cylinder = self.cylinder;
        sys.validate_geometry()?;
        check_inclination(&self.cylinder, self.theta)?;
        sys.top_height = [top_height(&self.cylinder, self.theta); 2];
        sys.mu_floor = self.mu_floor;
        sys.mu_mutual = self.mu_mutual;
        sys.spin = self.spin;
        sys.push_over_mg = self.push_over_mg;
        sys.validate()?;
        Ok(sys)
    }
}

/// One recorded step of the transport. Forces are divided by mg.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PairSample {
    /// Time t (s).
    pub t: f64,
    /// The 12 coordinates (x̄_I, ψ1, ϑ1, φ1, x̄_II, ψ2, ϑ2, φ2).
    pub q: Vec<f64>,
    /// Spin rates φ̇1, φ̇2 (rad/s).
    pub spin_rates: [f64; 2],
    /// Floor normal forces N1, N2 over mg.
    pub n_over_mg: [f64; 2],
    /// Top forces F3 of I and II over mg (multipliers of Π8, Π11).
    pub f3_over_mg: [f64; 2],
    /// Normal force between the cylinders over mg.
    pub contact_normal_force: f64,
    /// Floor friction forces (E1, E2 components) of I and II over mg.
    pub floor_friction: [f64; 4],
    /// Friction between the cylinders (t1, t2 components) over mg.
    pub contact_friction: [f64; 2],
    /// Gaps: floor I, floor II, mutual.
    pub gaps: [f64; 3],
}

impl PairSample {
    /// The CSV header of [`PairSample::csv_cells`].
    pub const CSV_HEADER: &'static str = "t,x_I1,x_I2,x_I3,psi1,theta1,phi1,x_II1,x_II2,x_II3,psi2,theta2,phi2,phidot1,phidot2,n1_over_mg,n2_over_mg,f3_1_over_mg,f3_2_over_mg,contact_normal_over_mg,floor1_f1,floor1_f2,floor2_f1,floor2_f2,contact_f1,contact_f2,gap_floor1,gap_floor2,gap_mutual";

    /// The row's cells, in the order of [`PairSample::CSV_HEADER`].
    #[must_use]
    pub fn csv_cells(&self) -> Vec<String> {
        std::iter::once(self.t)
            .chain(self.q.iter().copied())
            .chain(self.spin_rates)
            .chain(self.n_over_mg)
            .chain(self.f3_over_mg)
            .chain([self.contact_normal_force])
            .chain(self.floor_friction)
            .chain(self.contact_friction)
            .chain(self.gaps)
            .map(|x| x.to_string())
            .collect()
    }
}

/// The result of one transport run. The field names are the keys of
/// `rollstack cylinder pair --json` (docs/cli.md); forces are divided by mg.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PairReport {
    /// Inclination ϑ (rad).
    pub theta: f64,
    /// Floor normal forces N/mg of I and II at the last step.
    pub n_over_mg: [f64; 2],
    /// Top forces F3/mg of I and II at the last step.
    pub f3_over_mg: [f64; 2],
    /// Normal force between the cylinders over mg at the last step.
    pub contact_normal_force: f64,
    /// Steps taken.
    pub steps: usize,
    /// Wall-clock time of the stepping (s).
    pub wall_time_s: f64,
    /// N/mg of the smooth-floor formula (3.3.10) (F3/mg = 1 − N/mg).
    pub n_over_mg_static: f64,
    /// The largest |N/mg − (3.3.10)| and |F3/mg − (1 − (3.3.10))| of both cylinders at
    /// the last step.
    pub static_error: f64,
    /// The largest normal force between the cylinders over mg in the last half of the run.
    pub max_contact_normal_force: f64,
    /// The largest |g| of the bilateral constraints (top heights, headings) over all
    /// steps.
    pub drift: f64,
    /// The largest |φ̇1 − φ̇10(t)| (Π10) over all steps (rad/s).
    pub spin_error: f64,
    /// The smallest gap (floor I, floor II, mutual) over all steps.
    pub min_gap: f64,
    /// The mutual gap at the last step (positive: the cylinders have parted).
    pub final_mutual_gap: f64,
    /// The largest floor slip speed ‖v_P‖ over all steps (m/s).
    pub max_floor_slip: f64,
    /// Newton iterations over the run.
    pub newton_iterations: u64,
    /// Every step, when asked for ([`run_pair`]'s `record`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub trajectory: Option<Vec<PairSample>>,
}

/// Runs the transport of [`PairSettings`]; with `record`, keeps every step.
///
/// # Errors
/// Bad settings (see [`PairSettings::system`]) or a step of the solver that fails
/// ([`CylinderError::Solver`]).
pub fn run_pair(settings: &PairSettings, record: bool) -> Result<PairReport, CylinderError> {
    run_pair_until(settings, record, &AtomicBool::new(false))
}

/// [`run_pair`] that ends after the current step once `cancel` is set (the Python
/// module sets it on Ctrl-C); the report then covers the steps taken.
///
/// # Errors
/// As [`run_pair`].
pub fn run_pair_until(
    settings: &PairSettings,
    record: bool,
    cancel: &AtomicBool,
) -> Result<PairReport, CylinderError> {
    run_pair_with(settings, settings.stepper_options(), record, cancel)
}

/// [`run_pair_until`] with other nsga `options` than [`PairSettings::stepper_options`]
/// (to measure what a constant or a stage of the step's policy is worth).
///
/// # Errors
/// As [`run_pair`].
pub fn run_pair_with(
    settings: &PairSettings,
    options: Options,
    record: bool,
    cancel: &AtomicBool,
) -> Result<PairReport, CylinderError> {
    #[allow(clippy::cast_precision_loss)]
    let steps = settings.steps as f64;
    let bound = settings.time_bound.unwrap_or(f64::INFINITY);
    let watchdog = Watchdog::new(WallClock::start(), 0.0, steps, bound);
    run_pair_watched(settings, options, record, cancel, watchdog)
}

/// [`run_pair_with`] watched by `watchdog` over the steps done instead of one at
/// [`PairSettings::time_bound`], on any clock (a test's).
///
/// # Errors
/// As [`run_pair`]; [`CylinderError::Stopped`] when the watchdog stops the run.
pub fn run_pair_watched(
    settings: &PairSettings,
    options: Options,
    record: bool,
    cancel: &AtomicBool,
    mut watchdog: Watchdog<impl Clock>,
) -> Result<PairReport, CylinderError> {
    let sys = settings.system()?;
    let (q0, u0) = sys.initial_state(settings.theta)?;
    let mg = sys.mass * sys.gravity;
    let layout = sys.layout();
    let mut stepper = Stepper::new(sys, 0.0, &q0, &u0, options)
        .map_err(|e| CylinderError::Solver(e.to_string()))?;
    let mut eval = nsga::Evaluation::<f64>::new(&layout);
    let mut trajectory = record.then(Vec::new);
    let (mut drift, mut spin_error, mut min_gap, mut max_slip) =
        (0.0_f64, 0.0_f64, f64::MAX, 0.0_f64);
    let mut max_contact = 0.0_f64;
    let mut last = None;
    let clock = Instant::now();
    let mut observe = |stepper: &Stepper<PairTransport>, k: usize| {
        let st = stepper.state();
        eval.reset();
        stepper.system().evaluate(st.t, &st.q, &st.u, &mut eval);
        let (lg, _) = stepper.bilateral_forces();
        drift = drift.max(eval.position[..4].iter().fold(0.0, |m, g| m.max(g.abs())));
        let mut v = eval.velocity_chi.clone();
        for &(r, c, w) in &eval.velocity_w.entries {
            v[c] += w * st.u[r];
        }
        spin_error = spin_error.max(v[0].abs());
        max_slip = max_slip.max(v[1].hypot(v[2])).max(v[3].hypot(v[4]));
        let gaps = [eval.position[4], eval.position[5], eval.position[6]];
        min_gap = gaps.iter().fold(min_gap, |m, &g| m.min(g));
        let sample = PairSample {
            t: st.t,
            q: st.q.clone(),
            spin_rates: [st.u[5], st.u[11]],
            n_over_mg: [st.lambda_n[0] / mg, st.lambda_n[1] / mg],
            f3_over_mg: [lg[0] / mg, lg[2] / mg],
            contact_normal_force: st.lambda_n[2] / mg,
            floor_friction: std::array::from_fn(|i| st.lambda_f[i] / mg),
            contact_friction: [st.lambda_f[4] / mg, st.lambda_f[5] / mg],
            gaps,
        };
        if 2 * k >= settings.steps {
            max_contact = max_contact.max(sample.contact_normal_force.abs());
        }
        if let Some(t) = trajectory.as_mut() {
            t.push(sample.clone());
        }
        last = Some(sample);
    };
    observe(&stepper, 0);
    let mut steps = 0;
    for k in 1..=settings.steps {
        if cancel.load(Ordering::Relaxed) {
            break;
        }
        stepper
            .step()
            .map_err(|e| CylinderError::Solver(e.to_string()))?;
        observe(&stepper, k);
        steps = k;
        // The steps done are the run's progress: every step costs about the same.
        #[allow(clippy::cast_precision_loss)]
        let done = k as f64;
        if watchdog.check(done).is_break() {
            return Err(CylinderError::Stopped(watchdog.overrun().expect("stopped")));
        }
    }
    let wall_time_s = clock.elapsed().as_secs_f64();
    let last = last.expect("observed at least the start");
    let statics =
        SupportProblem::new(settings.cylinder.radius() / settings.cylinder.height(), 0.0)?;
    let n_static = statics
        .normal_force(settings.theta, FrictionLimit::Smooth)?
        .unwrap_or(f64::NAN);
    let static_error = (0..2)
        .map(|b| {
            (last.n_over_mg[b] - n_static)
                .abs()
                .max((last.f3_over_mg[b] - (1.0 - n_static)).abs())
        })
        .fold(0.0, f64::max);
    Ok(PairReport {
        theta: settings.theta,
        n_over_mg: last.n_over_mg,
        f3_over_mg: last.f3_over_mg,
        contact_normal_force: last.contact_normal_force,
        steps,
        wall_time_s,
        n_over_mg_static: n_static,
        static_error,
        max_contact_normal_force: max_contact,
        drift,
        spin_error,
        min_gap,
        final_mutual_gap: last.gaps[2],
        max_floor_slip: max_slip,
        newton_iterations: stepper.run_stats().newton_iterations,
        trajectory,
    })
}

/// One row of the sweep of Figure 3.14: the transport at one inclination, with the
/// smooth-floor statics (3.3.10) beside it. Forces are divided by mg. The field names
/// are the keys of `rollstack cylinder sweep pair --json` and the CSV columns.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PairSweepRow {
    /// Inclination ϑ (rad).
    pub theta: f64,
    /// Floor normal forces N/mg of I and II at the last step (NaN when the run failed).
    pub n_over_mg: [f64; 2],
    /// Top forces F3/mg of I and II at the last step.
    pub f3_over_mg: [f64; 2],
    /// Normal force between the cylinders over mg at the last step.
    pub contact_normal_force: f64,
    /// N/mg of (3.3.10); F3/mg = 1 − N/mg.
    pub n_over_mg_static: f64,
    /// [`PairReport::static_error`].
    pub static_error: f64,
    /// [`PairReport::drift`].
    pub drift: f64,
    /// [`PairReport::min_gap`].
    pub min_gap: f64,
    /// Steps taken.
    pub steps: usize,
    /// Wall-clock time of the run (s).
    pub wall_time_s: f64,
    /// Why the run failed, if it did.
    pub error: Option<String>,
}

impl PairSweepRow {
    /// The CSV header of [`PairSweepRow::csv_cells`].
    pub const CSV_HEADER: [&'static str; 13] = [
        "theta",
        "n1_over_mg",
        "n2_over_mg",
        "f3_1_over_mg",
        "f3_2_over_mg",
        "contact_normal_force",
        "n_over_mg_static",
        "static_error",
        "drift",
        "min_gap",
        "steps",
        "wall_time_s",
        "error",
    ];

    /// The row's cells, in the order of [`PairSweepRow::CSV_HEADER`] (a number a failed
    /// run lacks is an empty cell).
    #[must_use]
    pub fn csv_cells(&self) -> Vec<String> {
        let mut cells: Vec<String> = [self.theta]
            .into_iter()
            .chain(self.n_over_mg)
            .chain(self.f3_over_mg)
            .chain([
                self.contact_normal_force,
                self.n_over_mg_static,
                self.static_error,
                self.drift,
                self.min_gap,
            ])
            .map(|x| {
                if x.is_finite() {
                    x.to_string()
                } else {
                    String::new()
                }
            })
            .collect();
        cells.push(self.steps.to_string());
        cells.push(self.wall_time_s.to_string());
        cells.push(self.error.clone().unwrap_or_default());
        cells
    }
}

impl std::fmt::Display for PairSweepRow {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match &self.error {
            Some(e) => write!(f, "ϑ = {:.4} rad: failed: {e}", self.theta),
            None => write!(
                f,
                "ϑ = {:.4} rad: N/mg = {:.6}, F3/mg = {:.6} ((3.3.10): {:.6}, off by {:.1e}), \
                 contact {:.1e} mg",
                self.theta,
                self.n_over_mg[0],
                self.f3_over_mg[0],
                self.n_over_mg_static,
                self.static_error,
                self.contact_normal_force
            ),
        }
    }
}

/// The row of the sweep at `settings.theta`: a failed run is a row with its error.
#[must_use]
pub fn pair_sweep_row(settings: &PairSettings) -> PairSweepRow {
    pair_sweep_row_until(settings, &AtomicBool::new(false))
}

/// [`pair_sweep_row`] whose run ends after its current step once `cancel` is set (the
/// Python module sets it on Ctrl-C); the row then covers the steps taken.
#[must_use]
pub fn pair_sweep_row_until(settings: &PairSettings, cancel: &AtomicBool) -> PairSweepRow {
    match run_pair_until(settings, false, cancel) {
        Ok(r) => PairSweepRow {
            theta: r.theta,
            n_over_mg: r.n_over_mg,
            f3_over_mg: r.f3_over_mg,
            contact_normal_force: r.contact_normal_force,
            n_over_mg_static: r.n_over_mg_static,
            static_error: r.static_error,
            drift: r.drift,
            min_gap: r.min_gap,
            steps: r.steps,
            wall_time_s: r.wall_time_s,
            error: None,
        },
        Err(e) => PairSweepRow {
            theta: settings.theta,
            n_over_mg: [f64::NAN; 2],
            f3_over_mg: [f64::NAN; 2],
            contact_normal_force: f64::NAN,
            n_over_mg_static: f64::NAN,
            static_error: f64::NAN,
            drift: f64::NAN,
            min_gap: f64::NAN,
            steps: 0,
            wall_time_s: 0.0,
            error: Some(e.to_string()),
        },
    }
}

/// One row of the push sweep: at inclination ϑ and floor friction μ_s, the pushes P/mg
/// of a grid applied at each top along e′2 (the applied force F e′2 of §3.3) in
/// increasing order until a rim slips, against the statics of §3.3: with F = P the
/// moment balance gives the line (3.3.12), F3/mg = (F/mg − α2)/α1, N = mg − F3, and the
/// rim slips when F reaches μ_s N, i.e. at P*/mg = μ_s N₋/mg with N₋ of (3.3.8)₋
/// (corrected per errata item 9; F_f = −μN e′2). Without a positive N₋ no push
/// along +e′2 makes the rim slip. Pushes along −e′2 slip at −μ_s N₊ of (3.3.8)₊. The field names are the keys of
/// `rollstack cylinder sweep push --json` and the CSV columns.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PushRow {
    /// Inclination ϑ (rad).
    pub theta: f64,
    /// Floor friction μ_s.
    pub mu_floor: f64,
    /// The first push of the grid at which a rim slipped (over mg), or null.
    pub onset_over_mg: Option<f64>,
    /// The static slip onset μ_s N₋/mg of (3.3.8)₋ (−μ_s N₊/mg of (3.3.8)₊ for pushes
    /// along −e′2), or null when that N is not positive.
    pub static_onset_over_mg: Option<f64>,
    /// The largest grid step |ΔP|/mg.
    pub push_step: f64,
    /// Whether the measured onset is within one grid step beyond the static one (both
    /// null counts as agreement).
    pub agrees: bool,
    /// The last push that did not slip (over mg), or null when the first did.
    pub last_stick_over_mg: Option<f64>,
    /// N/mg measured at that push.
    pub n_over_mg: Option<f64>,
    /// N/mg of the statics (3.3.12) at that push.
    pub n_over_mg_static: Option<f64>,
    /// F3/mg measured at that push.
    pub f3_over_mg: Option<f64>,
    /// The largest |N/mg − statics| and |F3/mg − statics| over the sticking pushes.
    pub static_error: f64,
    /// The minimum applied force (3.3.15)–(3.3.19) at this ϑ and μ_s, checked by the
    /// transport at its push and at that push ± the grid step (null when a run failed).
    pub minimum_force: Option<MinimumForceCheck>,
    /// Runs made: the onset search's and the three of the minimum force.
    pub runs: usize,
    /// Wall-clock time of the onset search's runs (s).
    pub wall_time_s: f64,
    /// Why a run failed, if one did.
    pub error: Option<String>,
}

impl PushRow {
    /// An empty row at ϑ, μ_s (to carry an error).
    #[must_use]
    pub fn failed(theta: f64, mu_floor: f64) -> Self {
        Self {
            theta,
            mu_floor,
            onset_over_mg: None,
            static_onset_over_mg: None,
            push_step: 0.0,
            agrees: false,
            last_stick_over_mg: None,
            n_over_mg: None,
            n_over_mg_static: None,
            f3_over_mg: None,
            static_error: 0.0,
            minimum_force: None,
            runs: 0,
            wall_time_s: 0.0,
            error: None,
        }
    }
}

/// The slip speed above which a rim counts as slipping, m/s.
pub const SLIP_THRESHOLD: f64 = 1e-6;

impl PushRow {
    /// The CSV header of [`PushRow::csv_cells`].
    pub const CSV_HEADER: [&'static str; 19] = [
        "theta",
        "mu_floor",
        "onset_over_mg",
        "static_onset_over_mg",
        "push_step",
        "agrees",
        "last_stick_over_mg",
        "n_over_mg",
        "n_over_mg_static",
        "f3_over_mg",
        "static_error",
        "min_force_case",
        "min_force_push_over_mg",
        "min_force_over_mg_static",
        "min_force_over_mg",
        "min_force_agrees",
        "runs",
        "wall_time_s",
        "error",
    ];

    /// The row's cells, in the order of [`PushRow::CSV_HEADER`] (null: an empty cell).
    #[must_use]
    pub fn csv_cells(&self) -> Vec<String> {
        let opt = |x: Option<f64>| x.map_or(String::new(), |v| v.to_string());
        vec![
            self.theta.to_string(),
            self.mu_floor.to_string(),
            opt(self.onset_over_mg),
            opt(self.static_onset_over_mg),
            self.push_step.to_string(),
            u8::from(self.agrees).to_string(),
            opt(self.last_stick_over_mg),
            opt(self.n_over_mg),
            opt(self.n_over_mg_static),
            opt(self.f3_over_mg),
            self.static_error.to_string(),
            self.minimum_force
                .as_ref()
                .map_or(String::new(), |m| m.case.name().to_owned()),
            opt(self.minimum_force.as_ref().map(|m| m.push_over_mg)),
            opt(self.minimum_force.as_ref().map(|m| m.norm_over_mg_static)),
            opt(self.minimum_force.as_ref().map(|m| m.norm_over_mg)),
            self.minimum_force
                .as_ref()
                .map_or(String::new(), |m| u8::from(m.agrees).to_string()),
            self.runs.to_string(),
            self.wall_time_s.to_string(),
            self.error.clone().unwrap_or_default(),
        ]
    }
}

impl std::fmt::Display for PushRow {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let opt = |x: Option<f64>| x.map_or("none".to_owned(), |v| format!("{v:.4}"));
        write!(
            f,
            "ϑ = {:.4} rad, μ_s = {}: slip from P/mg = {} (statics (3.3.8){}: {}), {}",
            self.theta,
            self.mu_floor,
            opt(self.onset_over_mg),
            if self.static_onset_over_mg.is_some_and(|p| p < 0.0) {
                "+"
            } else {
                "−"
            },
            opt(self.static_onset_over_mg),
            if self.agrees {
                "within one step"
            } else {
                "NOT within one step"
            }
        )?;
        if let Some(m) = &self.minimum_force {
            write!(
                f,
                "; minimum force {:.6} mg at P/mg = {:.4} ({}: {:.6}), {}",
                m.norm_over_mg,
                m.push_over_mg,
                m.case.equation(),
                m.norm_over_mg_static,
                if m.agrees {
                    "confirmed"
                } else {
                    "NOT confirmed"
                }
            )?;
        }
        if let Some(e) = &self.error {
            write!(f, "; failed: {e}")?;
        }
        Ok(())
    }
}

/// The push-sweep row at `base.theta` with floor friction `base.mu_floor`: runs
/// `base` (its steps, Δt, spin) with each push of `pushes` (over mg, moving away from
/// zero) until a rim slips faster than [`SLIP_THRESHOLD`]. Pushes along +e′2 (a grid
/// ending above 0) are compared with μ_s N₋ of (3.3.8)₋, pushes along −e′2 (a grid
/// ending below 0) with −μ_s N₊ of (3.3.8)₊. Then checks the minimum applied force at
/// ϑ with [`minimum_force_check`], its neighbours one grid step away.
///
/// # Errors
/// Bad settings (before any run); a run that fails is the row's `error`.
pub fn push_row(base: &PairSettings, pushes: &[f64]) -> Result<PushRow, CylinderError> {
    push_row_until(base, pushes, &AtomicBool::new(false))
}

/// [`push_row`] whose runs end after their current step once `cancel` is set (the
/// Python module sets it on Ctrl-C): the row then holds no verdict worth keeping.
///
/// # Errors
/// As [`push_row`].
pub fn push_row_until(
    base: &PairSettings,
    pushes: &[f64],
    cancel: &AtomicBool,
) -> Result<PushRow, CylinderError> {
    base.system()?;
    let rho = base.cylinder.radius() / base.cylinder.height();
    let statics = SupportProblem::new(rho, base.mu_floor)?;
    // Pushes along +e′2 slip at F = +μN (F_f = −μN e′2, N₋); along −e′2 at F = −μN
    // (F_f = +μN e′2, N₊).
    let sign = if pushes.last().copied().unwrap_or(0.0) < 0.0 {
        -1.0
    } else {
        1.0
    };
    let limit = if sign < 0.0 {
        FrictionLimit::Plus
    } else {
        FrictionLimit::Minus
    };
    let static_onset = statics
        .normal_force(base.theta, limit)?
        .map(|n| sign * base.mu_floor * n);
    let (a1, a2) = statics.line(base.theta);
    let push_step = pushes
        .windows(2)
        .map(|w| (w[1] - w[0]).abs())
        .fold(0.0, f64::max);
    let mut row = PushRow {
        static_onset_over_mg: static_onset,
        push_step,
        ..PushRow::failed(base.theta, base.mu_floor)
    };
    for &p in pushes {
        let settings = PairSettings {
            push_over_mg: p,
            ..*base
        };
        row.runs += 1;
        let r = match run_pair_until(&settings, false, cancel) {
            Ok(r) => r,
            Err(e) => {
                row.error = Some(format!("P/mg = {p}: {e}"));
                break;
            }
        };
        row.wall_time_s += r.wall_time_s;
        if r.max_floor_slip > SLIP_THRESHOLD {
            row.onset_over_mg = Some(p);
            break;
        }
        let f3 = (p - a2) / a1;
        let err = (0..2)
            .map(|b| {
                (r.f3_over_mg[b] - f3)
                    .abs()
                    .max((r.n_over_mg[b] - (1.0 - f3)).abs())
            })
            .fold(0.0, f64::max);
        row.static_error = row.static_error.max(err);
        row.last_stick_over_mg = Some(p);
        row.n_over_mg = Some(r.n_over_mg[0]);
        row.n_over_mg_static = Some(1.0 - f3);
        row.f3_over_mg = Some(r.f3_over_mg[0]);
    }
    if row.error.is_none() {
        let delta = if push_step > 0.0 { push_step } else { 0.005 };
        match minimum_force_check_until(base, delta, cancel) {
            Ok(m) => {
                row.runs += 3;
                row.minimum_force = Some(m);
            }
            Err(e) => row.error = Some(format!("minimum force: {e}")),
        }
    }
    let last = pushes.last().copied().unwrap_or(0.0);
    row.agrees = row.error.is_none()
        && match (row.onset_over_mg, static_onset) {
            (Some(m), Some(s)) => {
                let beyond = sign * (m - s);
                beyond >= -1e-12 && beyond <= push_step + 1e-12
            }
            (None, Some(s)) => sign * (s - last) > 0.0,
            (None, None) => true,
            (Some(_), None) => false,
        };
    Ok(row)
}

/// The minimum applied force of §3.3, (3.3.15)–(3.3.19) as corrected in docs/errata.md
/// (items 9–11), checked by the transport: the push P* = F of the static minimum is
/// applied, the measured F3 gives the measured ‖(F, F3)‖/mg, and the pushes P* ± δ on
/// either side show that no admissible neighbour (rims sticking, F3 ≥ 0) needs less.
/// Each neighbour must be admissible exactly when the statics say so: beyond a bound
/// ((3.3.18)± or (3.3.19)) the rims slip, or the top would have to be pulled down.
/// The field names are the keys of the `minimum_force` object of
/// `rollstack cylinder sweep push --json`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MinimumForceCheck {
    /// Which case of §3.3 holds the static minimum.
    pub case: MinForceCase,
    /// The push P*/mg = F/mg of the static minimum, applied in the run.
    pub push_over_mg: f64,
    /// F3/mg of the static minimum.
    pub f3_over_mg_static: f64,
    /// F3/mg measured at P* (cylinder I).
    pub f3_over_mg: f64,
    /// ‖F_a‖/mg of the static minimum.
    pub norm_over_mg_static: f64,
    /// ‖(P*, F3)‖/mg measured.
    pub norm_over_mg: f64,
    /// The largest floor slip speed at P* (m/s).
    pub slip_speed: f64,
    /// The push step δ/mg to the neighbours.
    pub delta: f64,
    /// ‖(P, F3)‖/mg measured at P* − δ and P* + δ, or null where that push is not
    /// admissible (a rim slips, or F3 < 0).
    pub neighbour_norms_over_mg: [Option<f64>; 2],
    /// The run at P* sticks, its norm equals the static one to 1e-8, every admissible
    /// neighbour needs at least as much, and each neighbour is admissible exactly when
    /// the statics say so (F3 ≥ 0 and |F| ≤ μ_s N on the line (3.3.12)).
    pub agrees: bool,
}

/// Tolerance of [`MinimumForceCheck::agrees`] on the norm at P*.
pub const MINIMUM_FORCE_TOLERANCE: f64 = 1e-8;

/// Runs `base` at the push of the static minimum force and at that push ± `delta`
/// ([`MinimumForceCheck`]).
///
/// # Errors
/// Bad settings, an inclination the floor friction cannot hold, or a failed run.
pub fn minimum_force_check(
    base: &PairSettings,
    delta: f64,
) -> Result<MinimumForceCheck, CylinderError> {
    minimum_force_check_until(base, delta, &AtomicBool::new(false))
}

/// [`minimum_force_check`] whose runs end after their current step once `cancel` is set.
///
/// # Errors
/// As [`minimum_force_check`].
pub fn minimum_force_check_until(
    base: &PairSettings,
    delta: f64,
    cancel: &AtomicBool,
) -> Result<MinimumForceCheck, CylinderError> {
    input::positive("push step δ", delta)?;
    let rho = base.cylinder.radius() / base.cylinder.height();
    let problem = SupportProblem::new(rho, base.mu_floor)?;
    let statics = problem.minimum_force(base.theta)?;
    let (a1, a2) = problem.line(base.theta);
    // The statics' verdict on push p: on the line (3.3.12), F3 ≥ 0 and |F| ≤ μ_s N.
    let admissible_static = |p: f64| {
        let f3 = (p - a2) / a1;
        f3 >= 0.0 && p.abs() <= base.mu_floor * (1.0 - f3)
    };
    // (admissible, ‖(P, F3)‖/mg, F3/mg, slip speed) measured at push p.
    let measure = |p: f64| -> Result<(bool, f64, f64, f64), CylinderError> {
        let r = run_pair_until(
            &PairSettings {
                push_over_mg: p,
                ..*base
            },
            false,
            cancel,
        )?;
        let f3 = r.f3_over_mg[0];
        let admissible = r.max_floor_slip <= SLIP_THRESHOLD && f3 >= -MINIMUM_FORCE_TOLERANCE;
        Ok((admissible, p.hypot(f3), f3, r.max_floor_slip))
    };
    let p = statics.f_over_mg;
    let (sticks, norm, f3, slip_speed) = measure(p)?;
    let mut neighbours = [None; 2];
    let mut verdicts_agree = true;
    for (slot, q) in neighbours.iter_mut().zip([p - delta, p + delta]) {
        let (ok, n, _, _) = measure(q)?;
        verdicts_agree &= ok == admissible_static(q);
        *slot = ok.then_some(n);
    }
    let agrees = sticks
        && (norm - statics.norm_over_mg).abs() <= MINIMUM_FORCE_TOLERANCE
        && neighbours.iter().flatten().all(|&n| n >= norm - 1e-12)
        && verdicts_agree;
    Ok(MinimumForceCheck {
        case: statics.case,
        push_over_mg: p,
        f3_over_mg_static: statics.f3_over_mg,
        f3_over_mg: f3,
        norm_over_mg_static: statics.norm_over_mg,
        norm_over_mg: norm,
        slip_speed,
        delta,
        neighbour_norms_over_mg: neighbours,
        agrees,
    })
}

/// The outline of both cylinders at configuration q for drawing: for each, its body
/// index (0 for I, 1 for II) and polylines in space: the bottom and top rims, four
/// generators, the first of them a material line (at body angle 0, e1 = cos φ e′1 +
/// sin φ e″2) that shows the spin, and the axis.
#[must_use]
pub fn pair_outline(cylinder: &Cylinder, q: &[f64]) -> Vec<(usize, Vec<[f64; 3]>)> {
    let (r, half) = (cylinder.radius(), 0.5 * cylinder.height());
    let mut lines = Vec::new();
    for b in 0..2 {
        let o = 6 * b;
        let f = crate::kinematics::EulerFrame::new(q[o + 3], q[o + 4]);
        let c = nalgebra::Vector3::new(q[o], q[o + 1], q[o + 2]);
        let phi = q[o + 5];
        let radial = |a: f64| (f.e1p * a.cos() + f.e2pp * a.sin()) * r;
        let point = |v: nalgebra::Vector3<f64>| [v.x, v.y, v.z];
        for end in [-half, half] {
            let rim = (0..=48)
                .map(|k| point(c + f.e3 * end + radial(f64::from(k) * PI / 24.0)))
                .collect();
            lines.push((b, rim));
        }
        for k in 0..4 {
            let a = phi + f64::from(k) * PI / 2.0;
            lines.push((
                b,
                vec![
                    point(c - f.e3 * half + radial(a)),
                    point(c + f.e3 * half + radial(a)),
                ],
            ));
        }
        lines.push((b, vec![point(c - f.e3 * half), point(c + f.e3 * half)]));
    }
    lines
}

#[cfg(test)]
mod tests {
    use super::*;

    fn short(theta: f64) -> PairSettings {
        PairSettings {
            steps: 200,
            ..PairSettings::thesis(theta)
        }
    }

    /// A cancelled run ends after its current step with the steps taken (Ctrl-C in the
    /// Python module): here before its first.
    #[test]
    fn a_cancelled_run_stops_with_the_steps_taken() {
        let r = run_pair_until(&short(0.5), true, &AtomicBool::new(true)).unwrap();
        assert_eq!(r.steps, 0);
        assert_eq!(r.trajectory.map(|t| t.len()), Some(1));
        assert_eq!(run_pair(&short(0.5), false).unwrap().steps, 200);
    }

    /// The watchdog projects over the steps done: a second a step for 200 steps is
    /// 200 s, under the bound at 600 s and over it at 100 s, where the run stops once
    /// the grace time is over, naming --force.
    #[test]
    fn the_watchdog_stops_a_pair_run_projected_past_its_bound() {
        let watched = |bound| {
            let dog = Watchdog::new(input::watchdog::TickingClock::default(), 0.0, 200.0, bound);
            run_pair_watched(
                &short(0.5),
                short(0.5).stepper_options(),
                false,
                &AtomicBool::new(false),
                dog,
            )
        };
        assert_eq!(watched(600.0).unwrap().steps, 200);
        let e = watched(100.0).unwrap_err();
        let CylinderError::Stopped(o) = &e else {
            panic!("{e}")
        };
        assert!((o.projected_s - 200.0).abs() < 1e-9, "{o:?}");
        let said = e.to_string();
        assert!(said.starts_with("stopped by the watchdog") && said.contains("--force"));
        // Through the settings, on the wall clock: a microsecond is always passed.
        let bounded = PairSettings {
            time_bound: Some(1e-6),
            ..short(0.5)
        };
        let e = run_pair(&bounded, false).unwrap_err();
        assert!(matches!(e, CylinderError::Stopped(_)), "{e}");
        let row = pair_sweep_row(&bounded);
        assert!(row
            .error
            .is_some_and(|e| e.starts_with("stopped by the watchdog")));
    }

    /// A push along e′2 makes a rim slip within one grid step above μ_s N₋ of
    /// (3.3.8)₋, and below it the forces follow the line (3.3.12).
    #[test]
    fn push_slips_at_the_static_bound() {
        let base = PairSettings {
            steps: 50,
            mu_floor: 0.2,
            ..PairSettings::thesis(0.5)
        };
        let pushes: Vec<f64> = (0..=30).map(|k| 0.01 * f64::from(k)).collect();
        let row = push_row(&base, &pushes).unwrap();
        assert!(row.agrees, "{row:?}");
        assert!(row.static_error < 1e-8, "{row:?}");
        assert!(row.onset_over_mg.is_some(), "{row:?}");
    }

    /// A push along −e′2 slips within one step beyond −μ_s N₊ of (3.3.8)₊.
    #[test]
    fn pull_slips_at_the_other_static_bound() {
        let base = PairSettings {
            steps: 50,
            mu_floor: 0.2,
            ..PairSettings::thesis(0.5)
        };
        let pushes: Vec<f64> = (0..=30).map(|k| -0.005 * f64::from(k)).collect();
        let row = push_row(&base, &pushes).unwrap();
        assert!(row.agrees, "{row:?}");
        assert!(row.onset_over_mg.is_some_and(|p| p < 0.0), "{row:?}");
        assert!(row.static_error < 1e-8, "{row:?}");
    }

    /// The coarse push sweep's row at ϑ = 0.68 along −e′2: the rim that starts to slide
    /// at P/mg = −0.09 rolled a step before, so its slip velocity was round-off when the
    /// sliding row was first linearized; that step failed as singular before the slip
    /// direction was guarded (docs/method.md §3).
    #[test]
    fn pull_row_at_the_stick_slip_transition_completes() {
        let base = PairSettings {
            steps: 100,
            mu_floor: 0.2,
            ..PairSettings::thesis(0.68)
        };
        let pushes: Vec<f64> = (0..=24).map(|k| -0.005 * f64::from(k)).collect();
        let row = push_row(&base, &pushes).unwrap();
        assert!(row.error.is_none(), "{row:?}");
        assert!(row.agrees, "{row:?}");
        assert!(row.static_error < 1e-8, "{row:?}");
    }

    /// The transport confirms the minimum force of §3.3 in both cases that occur over
    /// the range: the foot of the perpendicular (3.3.15) at μ_s = 1, and the friction
    /// bound (3.3.18)₁ at μ_s = 0.05 and at the steep angles of μ_s = 0.2.
    #[test]
    fn minimum_force_is_confirmed_by_the_transport() {
        for (mu, theta, case) in [
            (1.0, 0.5, MinForceCase::Unconstrained),
            (0.2, 0.25, MinForceCase::Unconstrained),
            (0.2, 0.7, MinForceCase::FrictionPositive),
            // At its bound the floor law sticks with γ̇_F of round-off: once a singular
            // Newton matrix (docs/method.md §3).
            (0.2, 0.75, MinForceCase::FrictionPositive),
            (0.05, 0.4, MinForceCase::FrictionPositive),
        ] {
            let base = PairSettings {
                steps: 60,
                mu_floor: mu,
                ..PairSettings::thesis(theta)
            };
            let c = minimum_force_check(&base, 0.005).unwrap();
            assert_eq!(c.case, case, "{c:?}");
            assert!(c.agrees, "μ_s = {mu}, ϑ = {theta}: {c:?}");
            assert!((c.f3_over_mg - c.f3_over_mg_static).abs() < 1e-8, "{c:?}");
        }
    }

    #[test]
    fn steady_transport_is_the_smooth_floor_statics() {
        let r = run_pair(&short(0.5), false).unwrap();
        assert!(r.static_error < 1e-8, "{r:?}");
        assert!(r.max_contact_normal_force < 1e-8, "{r:?}");
        assert!(r.drift < 1e-10, "{r:?}");
        assert!(r.min_gap > -1e-10, "{r:?}");
    }
}
