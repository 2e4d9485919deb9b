//! Fragility of a stack under recorded ground motions (`rollstack blocks fragility`):
//! every record of a list played at every intensity level on a scene's base, one row
//! per run with its outcome, and lognormal fragility curves fitted to the outcomes
//! ([`fit`]).
//!
//! **What is run.** The scene's horizontal base motion (its x component, `[base.x]` or
//! the x keys of `[base]`) is replaced by the record, whatever it was (fixed, harmonic,
//! a pulse, another record); the vertical motion and the rotation stay as the scene
//! gives them. A record is read in g (`.AT2`, or a CSV of `t,a` rows with a in g),
//! corrected by the scene's `[base.x] baseline` when its x motion was a record (by
//! default `end-at-rest`, docs/scenes.md), then scaled. Each run lasts the record
//! (`solver.t_end` is the record's last sample time) unless a common end time is given.
//!
//! **The levels** ([`Measure`]) are either factors on the corrected record
//! ([`Measure::Scale`], the `scale` key) or target peak ground accelerations in g
//! ([`Measure::Pga`], the `scale_to_pga` key: every record scaled to the same PGA).
//! Each row records the PGA (g) and PGV (scene length per time unit: m/s in SI units
//! with g = 9.81) of the motion the base actually played, so that a curve can be drawn
//! against either whatever the levels were.
//!
//! **Outcomes** ([`FragilityRow`]):
//! - *overturned*: some block touched the floor (the `touched_floor` event,
//!   [`crate::events`]), or ended the run turned past its tipping angle atan(w/h) from
//!   upright, or ended with its centre below the top of the base (fallen off where there
//!   is no floor). A block that rocks and comes back is not overturned.
//! - *failed*: the run's failure ([`crate::events::failure`]): any event at all (a block
//!   lost its support, tipped past its tipping angle at some moment, touched the floor,
//!   or the column's height dropped by a block), with its time and kind.
//!
//! A run that stopped on an error has no outcome (its cells are empty) and is left out
//! of the fit, as are runs at zero intensity (ln 0); the fit says how many.
//!
//! ```
//! use blockstack::studies::fragility::{fit::Outcome, fit::fit_lognormal};
//!
//! let outcomes: Vec<Outcome> = [(0.1, false), (0.2, false), (0.3, true), (0.25, false),
//!     (0.28, true), (0.4, true), (0.35, false)]
//!     .iter()
//!     .map(|&(im, collapsed)| Outcome { im, collapsed })
//!     .collect();
//! let curve = fit_lognormal(&outcomes).unwrap();
//! assert!((0.2..0.4).contains(&curve.theta));
//! assert!((curve.probability(curve.theta) - 0.5).abs() < 1e-12);
//! ```

pub mod fit;
pub mod normal;

use crate::base::record_file::read_record;
use crate::base::{Accelerogram, BaseMotion};
use crate::error::BlockError;
use crate::record::{finite_text, optional_text};
use crate::scene::Scene;
use crate::scene_base::MotionFile;
use crate::scene_file::{LoadedScene, SceneFile};
use crate::simulation::{simulate, RunOptions, RunSummary};
use crate::studies::shaking::one_line;
use crate::EventKind;
use fit::{fit_lognormal, Degenerate, LognormalFit, Outcome};
use serde::{Deserialize, Serialize};
use std::fmt;
use std::path::{Path, PathBuf};

/// What the intensity levels of a study are.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Measure {
    /// Factors on each corrected record as read (`scale`; 1: the record itself).
    Scale,
    /// Target peak ground accelerations in g (`scale_to_pga`).
    Pga,
}

impl Measure {
    /// The names of the measures, as `--measure` takes them.
    pub const NAMES: [&'static str; 2] = ["scale", "pga"];

    /// The measure's name.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Scale => "scale",
            Self::Pga => "pga",
        }
    }
}

/// A record file of a study: its file name and path.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RecordFile {
    /// The file name (the row's `record`).
    pub name: String,
    /// Where it is.
    pub path: PathBuf,
}

/// Every `*.AT2` and `*.csv` file of `dir` (extensions in any case), sorted by name,
/// with absolute paths (a scene's own record paths start from its directory, these
/// from the working directory).
///
/// # Errors
/// An unreadable directory, or one without such a file.
pub fn records_in(dir: &Path) -> Result<Vec<RecordFile>, BlockError> {
    let shown = dir.display();
    let unreadable =
        |e: std::io::Error| BlockError::Record(format!("cannot read the directory {shown}: {e}"));
    let dir = std::path::absolute(dir).map_err(unreadable)?;
    let entries = std::fs::read_dir(&dir).map_err(unreadable)?;
    let mut records: Vec<RecordFile> = entries
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| p.is_file())
        .filter(|p| {
            p.extension()
                .is_some_and(|e| e.eq_ignore_ascii_case("at2") || e.eq_ignore_ascii_case("csv"))
        })
        .filter_map(|path| {
            let name = path.file_name()?.to_str()?.to_owned();
            Some(RecordFile { name, path })
        })
        .collect();
    records.sort_by(|a, b| a.name.cmp(&b.name));
    if records.is_empty() {
        return Err(BlockError::Record(format!(
            "{shown} holds no record (*.AT2 or *.csv)"
        )));
    }
    Ok(records)
}

/// One run of a study: record `record` (its index in the study's list) at `level`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FragilityPoint {
    /// The record's index in [`FragilityStudy::records`].
    pub record: usize,
    /// The intensity level ([`Measure`]).
    pub level: f64,
}

/// A scene, the records and the levels of a fragility study, checked.
#[derive(Debug, Clone)]
pub struct FragilityStudy {
    file: SceneFile,
    dir: PathBuf,
    records: Vec<RecordFile>,
    durations: Vec<f64>,
    levels: Vec<f64>,
    measure: Measure,
    t_end: Option<f64>,
}

impl FragilityStudy {
    /// The study of the scene file `text` under `records` at `levels` of `measure`.
    /// Every record is read here, so that a bad one stops the study before any run.
    ///
    /// # Errors
    /// A scene file that does not parse or whose step counts in base periods (a record
    /// has none: give `solver.dt`); no level, or a level that is not a finite number
    /// ≥ 0 (> 0 for [`Measure::Pga`]); an unreadable or malformed record, naming its
    /// file and line.
    pub fn new(
        text: &str,
        records: Vec<RecordFile>,
        levels: Vec<f64>,
        measure: Measure,
    ) -> Result<Self, BlockError> {
        let file = SceneFile::parse(text)?;
        if file.solver.dt.is_none() && file.solver.steps_per_period.is_some() {
            return Err(BlockError::Scene(
                "[solver] steps_per_period counts in periods of a harmonic base, and the study plays records on it: give [solver] dt".into(),
            ));
        }
        check_levels(&levels, measure).map_err(BlockError::Key)?;
        let durations = records
            .iter()
            .map(|r| Ok(read_record(&r.path, None)?.last().map_or(0.0, |s| s.0)))
            .collect::<Result<_, BlockError>>()?;
        Ok(Self {
            file,
            dir: PathBuf::new(),
            records,
            durations,
            levels,
            measure,
            t_end: None,
        })
    }

    /// The same study of a scene file in `dir` (where the paths of its other records
    /// start).
    #[must_use]
    pub fn in_dir(self, dir: PathBuf) -> Self {
        Self { dir, ..self }
    }

    /// The same study with every run ending at `t_end` instead of its record's end.
    #[must_use]
    pub fn ending_at(self, t_end: Option<f64>) -> Self {
        Self { t_end, ..self }
    }

    /// The records, sorted by name.
    #[must_use]
    pub fn records(&self) -> &[RecordFile] {
        &self.records
    }

    /// The levels' measure.
    #[must_use]
    pub fn measure(&self) -> Measure {
        self.measure
    }

    /// Every run: each record (in name order) at each level (in the order given).
    #[must_use]
    pub fn points(&self) -> Vec<FragilityPoint> {
        (0..self.records.len())
            .flat_map(|record| {
                self.levels
                    .iter()
                    .map(move |&level| FragilityPoint { record, level })
            })
            .collect()
    }

    /// The scene file of `point`: the x motion replaced by the record at its level,
    /// ending with the record (module docs).
    fn file(&self, point: FragilityPoint) -> SceneFile {
        let mut file = self.file.clone();
        let base = &mut file.base;
        let old = base.x.take().unwrap_or_default();
        let baseline = (old.name() == "record").then_some(old.baseline).flatten();
        // The x keys of [base] itself give way to the table.
        base.motion = "fixed".into();
        (base.amplitude, base.omega, base.v0, base.samples) = (None, None, None, None);
        let (scale, scale_to_pga) = match self.measure {
            Measure::Scale => (Some(point.level), None),
            Measure::Pga => (None, Some(point.level)),
        };
        base.x = Some(MotionFile {
            motion: Some("record".into()),
            record: Some(self.records[point.record].path.display().to_string()),
            scale,
            scale_to_pga,
            baseline,
            ..MotionFile::default()
        });
        file.solver.periods = None;
        file.solver.t_end = Some(self.t_end.unwrap_or(self.durations[point.record]));
        file
    }

    /// The scene of `point`, through the scene loader and all its checks.
    ///
    /// # Errors
    /// Every error of [`SceneFile::build`].
    pub fn scene(&self, point: FragilityPoint) -> Result<LoadedScene, BlockError> {
        self.file(point).build_at(&self.dir)
    }

    /// Runs `point` with `options` (their `t_end` is ignored: the scene's is the
    /// record's); a scene the loader refuses or a run that stops is the row's `error`.
    #[must_use]
    pub fn row(&self, point: FragilityPoint, options: &RunOptions) -> FragilityRow {
        let mut row = FragilityRow::new(&self.records[point.record].name, point.level);
        let scene = match self.scene(point) {
            Ok(l) => l.scene,
            Err(e) => {
                row.error = Some(one_line(&e.to_string()));
                return row;
            }
        };
        if let BaseMotion::Record(record) = &scene.base().motion {
            row.pga_g = Some(record.peak() / scene.solver.gravity).filter(|v| v.is_finite());
            row.pgv = Some(peak_velocity(record));
        }
        let options = RunOptions {
            t_end: None,
            ..options.clone()
        };
        let mut t_final = None;
        match simulate(&scene, &options, |r| t_final = Some(r.t)) {
            Ok(s) => {
                row.t_final = t_final;
                row.record_run(&scene, &s);
            }
            Err(e) => row.error = Some(one_line(&e.to_string())),
        }
        row
    }
}

/// Checks the levels of a study: at least one, each finite and ≥ 0 (> 0 for target
/// PGAs).
///
/// # Errors
/// The first bad level, in the units of `measure`.
pub fn check_levels(levels: &[f64], measure: Measure) -> Result<(), String> {
    if levels.is_empty() {
        return Err("no intensity level".into());
    }
    for &level in levels {
        let bad = !level.is_finite() || level < 0.0 || (measure == Measure::Pga && level == 0.0);
        if bad {
            let what = match measure {
                Measure::Scale => "a factor on the record must be finite and at least 0",
                Measure::Pga => "a target PGA (g) must be finite and positive",
            };
            return Err(format!("level {}: {what}", input::Short(level)));
        }
    }
    Ok(())
}

/// The peak |v| of a record: at a sample, or inside an interval where the (linear)
/// acceleration changes sign and v turns.
#[must_use]
pub fn peak_velocity(record: &Accelerogram) -> f64 {
    let [t, a, v, _] = record.samples();
    let mut peak = v.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    for i in 1..t.len() {
        if a[i - 1] * a[i] < 0.0 {
            let slope = (a[i] - a[i - 1]) / (t[i] - t[i - 1]);
            let tau = -a[i - 1] / slope;
            peak = peak.max((v[i - 1] + tau * (a[i - 1] + 0.5 * tau * slope)).abs());
        }
    }
    peak
}

/// Whether a run overturned a block (module docs): one touched the floor, or ended
/// past its tipping angle from upright, or below the top of the base.
#[must_use]
pub fn overturned(scene: &Scene, summary: &RunSummary) -> bool {
    let touched = summary
        .events
        .iter()
        .any(|e| e.kind == EventKind::TouchedFloor);
    let base_top = scene.base().top();
    touched
        || summary.final_poses.iter().enumerate().any(|(k, p)| {
            let size = scene.size(k + 1);
            let tilt = p.theta.sin().atan2(p.theta.cos()).abs();
            tilt > size.width.atan2(size.height) || p.y < base_top
        })
}

/// An event's name in the files, as the JSON of `blocks run` writes it.
fn event_name(kind: EventKind) -> &'static str {
    match kind {
        EventKind::SupportLost => "support_lost",
        EventKind::Tipped => "tipped",
        EventKind::HeightDropped => "height_dropped",
        EventKind::TouchedFloor => "touched_floor",
    }
}

/// One run of a fragility study.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FragilityRow {
    /// The record's file name.
    pub record: String,
    /// The level ([`Measure`]: a factor, or a target PGA in g).
    pub level: f64,
    /// Peak |a| of the motion played, g; null when the scene was refused.
    pub pga_g: Option<f64>,
    /// Peak |v| of the motion played (scene length per time unit: m/s in SI).
    pub pgv: Option<f64>,
    /// Whether a block overturned; null for a run that stopped on an error.
    pub overturned: Option<bool>,
    /// Whether the run failed (any event); null for a run that stopped on an error.
    pub failed: Option<bool>,
    /// Time of the failure (the first event), when there was one.
    pub failure_time: Option<f64>,
    /// Its kind (`support_lost`, `tipped`, `touched_floor`, `height_dropped`).
    pub failure_kind: Option<String>,
    /// Time of the last state computed.
    pub t_final: Option<f64>,
    /// Steps taken.
    pub steps: usize,
    /// Why the scene was refused, could not start or stopped early; null otherwise.
    pub error: Option<String>,
    /// Solver time (s).
    pub wall_time_s: f64,
}

impl FragilityRow {
    /// The columns of `runs.csv`.
    pub const CSV_HEADER: [&'static str; 12] = [
        "record",
        "level",
        "pga_g",
        "pgv",
        "overturned",
        "failed",
        "failure_time",
        "failure_kind",
        "t_final",
        "steps",
        "error",
        "wall_time_s",
    ];

    fn new(record: &str, level: f64) -> Self {
        Self {
            record: record.to_owned(),
            level,
            pga_g: None,
            pgv: None,
            overturned: None,
            failed: None,
            failure_time: None,
            failure_kind: None,
            t_final: None,
            steps: 0,
            error: None,
            wall_time_s: 0.0,
        }
    }

    /// The outcome of the run `summary` of `scene`.
    fn record_run(&mut self, scene: &Scene, summary: &RunSummary) {
        let failure = crate::events::failure(&summary.events);
        self.failure_time = failure.map(|f| f.t);
        self.failure_kind = failure.map(|f| event_name(f.kind).to_owned());
        self.steps = summary.steps;
        self.wall_time_s = summary.wall_time_s;
        self.error = summary.error.as_ref().map(|e| one_line(&e.to_string()));
        if self.error.is_none() {
            self.overturned = Some(overturned(scene, summary));
            self.failed = Some(failure.is_some());
        }
    }

    /// The row's cells under [`Self::CSV_HEADER`]: booleans as 0 and 1, an empty cell
    /// for a missing value.
    #[must_use]
    pub fn csv_cells(&self) -> Vec<String> {
        let flag = |b: Option<bool>| b.map_or_else(String::new, |b| u8::from(b).to_string());
        vec![
            self.record.clone(),
            finite_text(self.level),
            optional_text(self.pga_g),
            optional_text(self.pgv),
            flag(self.overturned),
            flag(self.failed),
            optional_text(self.failure_time),
            self.failure_kind.clone().unwrap_or_default(),
            optional_text(self.t_final),
            self.steps.to_string(),
            self.error.clone().unwrap_or_default(),
            finite_text(self.wall_time_s),
        ]
    }
}

/// One line: record, level, intensities and outcome.
impl fmt::Display for FragilityRow {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let num = |v: Option<f64>| v.map_or_else(|| "-".to_owned(), |v| format!("{v:.3}"));
        write!(
            f,
            "{} at {}: PGA {} g, PGV {}",
            self.record,
            input::Short(self.level),
            num(self.pga_g),
            num(self.pgv)
        )?;
        match (&self.error, self.overturned, self.failure_time) {
            (Some(e), _, _) => write!(f, ", error: {e}"),
            (None, Some(true), _) => write!(
                f,
                ", overturned (failure at t = {})",
                num(self.failure_time)
            ),
            (None, _, Some(t)) => write!(f, ", failed at t = {t:.3}, not overturned"),
            _ => write!(f, ", standing"),
        }
    }
}

/// Which outcome a curve is of.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Collapse {
    /// A block overturned.
    Overturned,
    /// The run failed (any event).
    Failed,
}

/// Which intensity a curve is against.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Intensity {
    /// Peak ground acceleration, g.
    Pga,
    /// Peak ground velocity, scene length per time unit.
    Pgv,
}

impl Intensity {
    /// The name in the files: `pga`, `pgv`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Pga => "pga",
            Self::Pgv => "pgv",
        }
    }

    /// The name and unit, for the files and the figure: `PGA (g)`.
    #[must_use]
    pub fn label(self) -> &'static str {
        match self {
            Self::Pga => "PGA (g)",
            Self::Pgv => "PGV (m/s)",
        }
    }

    fn of(self, row: &FragilityRow) -> Option<f64> {
        match self {
            Self::Pga => row.pga_g,
            Self::Pgv => row.pgv,
        }
    }
}

impl Collapse {
    /// The name in the files: `overturned`, `failed`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Overturned => "overturned",
            Self::Failed => "failed",
        }
    }

    fn of(self, row: &FragilityRow) -> Option<bool> {
        match self {
            Self::Overturned => row.overturned,
            Self::Failed => row.failed,
        }
    }
}

/// Every curve of a study, in the order of `fit.json`: overturned then failed, each
/// against PGA then PGV.
pub const CURVES: [(Collapse, Intensity); 4] = [
    (Collapse::Overturned, Intensity::Pga),
    (Collapse::Overturned, Intensity::Pgv),
    (Collapse::Failed, Intensity::Pga),
    (Collapse::Failed, Intensity::Pgv),
];

/// One fitted curve: of which outcome against which intensity, the fit or why none,
/// and the runs it counts. It serializes flat, with the same keys whether or not a
/// curve fits (the fit's keys null, and `no_fit` the reason, when none does).
#[derive(Debug, Clone, PartialEq)]
pub struct Curve {
    /// The outcome.
    pub outcome: Collapse,
    /// The intensity.
    pub intensity: Intensity,
    /// The fit, or why no curve fits.
    pub fit: Result<LognormalFit, Degenerate>,
    /// Runs fitted.
    pub runs: usize,
    /// Of them, those that collapsed.
    pub collapsed: usize,
    /// Runs left out: stopped on an error, or at zero intensity.
    pub left_out: usize,
}

/// A [`Curve`] as the files and the JSON write it.
#[derive(Serialize)]
struct CurveRecord<'a> {
    outcome: Collapse,
    intensity: Intensity,
    theta: Option<f64>,
    beta: Option<f64>,
    theta_band: Option<[f64; 2]>,
    beta_band: Option<[f64; 2]>,
    log_likelihood: Option<f64>,
    covariance: Option<&'a [[f64; 2]; 2]>,
    no_fit: Option<String>,
    runs: usize,
    collapsed: usize,
    left_out: usize,
}

impl Serialize for Curve {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let fit = self.fit.as_ref().ok();
        CurveRecord {
            outcome: self.outcome,
            intensity: self.intensity,
            theta: fit.map(|f| f.theta),
            beta: fit.map(|f| f.beta),
            theta_band: fit.map(|f| f.theta_band),
            beta_band: fit.map(|f| f.beta_band),
            log_likelihood: fit.map(|f| f.log_likelihood),
            covariance: fit.map(|f| &f.covariance),
            no_fit: self.fit.as_ref().err().map(ToString::to_string),
            runs: self.runs,
            collapsed: self.collapsed,
            left_out: self.left_out,
        }
        .serialize(s)
    }
}

/// The outcomes of `rows` for one curve, and how many rows were left out.
fn outcomes(
    rows: &[FragilityRow],
    outcome: Collapse,
    intensity: Intensity,
) -> (Vec<Outcome>, usize) {
    let kept: Vec<Outcome> = rows
        .iter()
        .filter_map(|r| {
            let im = intensity.of(r).filter(|x| *x > 0.0 && x.is_finite())?;
            Some(Outcome {
                im,
                collapsed: outcome.of(r)?,
            })
        })
        .collect();
    let left_out = rows.len() - kept.len();
    (kept, left_out)
}

/// The four curves of a study's rows ([`CURVES`]).
#[must_use]
pub fn fit_curves(rows: &[FragilityRow]) -> Vec<Curve> {
    CURVES
        .iter()
        .map(|&(outcome, intensity)| {
            let (data, left_out) = outcomes(rows, outcome, intensity);
            Curve {
                outcome,
                intensity,
                fit: fit_lognormal(&data),
                runs: data.len(),
                collapsed: data.iter().filter(|o| o.collapsed).count(),
                left_out,
            }
        })
        .collect()
}

/// Points of the fitted curve on the grid of `fragility.csv`.
pub const GRID_POINTS: usize = 60;

/// One line of `fragility.csv`: a point of a fitted curve with its band
/// (`kind = fit`), or the fraction of runs that collapsed at one level
/// (`kind = level`, at the geometric mean of its runs' intensities).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CurvePoint {
    /// The outcome.
    pub outcome: Collapse,
    /// The intensity.
    pub intensity: Intensity,
    /// `fit` or `level`.
    pub kind: &'static str,
    /// The intensity (units of [`Intensity::label`]).
    pub im: f64,
    /// Fitted P, or the fraction collapsed.
    pub p: f64,
    /// The band (fits only).
    pub band: Option<[f64; 2]>,
    /// The runs of the level (levels only).
    pub runs: Option<usize>,
}

impl CurvePoint {
    /// The columns of `fragility.csv`.
    pub const CSV_HEADER: [&'static str; 8] = [
        "outcome",
        "intensity",
        "kind",
        "im",
        "p",
        "p_low",
        "p_high",
        "runs",
    ];

    /// The point's cells under [`Self::CSV_HEADER`].
    #[must_use]
    pub fn csv_cells(&self) -> Vec<String> {
        vec![
            self.outcome.name().to_owned(),
            self.intensity.name().to_owned(),
            self.kind.to_owned(),
            finite_text(self.im),
            finite_text(self.p),
            optional_text(self.band.map(|b| b[0])),
            optional_text(self.band.map(|b| b[1])),
            self.runs.map_or_else(String::new, |n| n.to_string()),
        ]
    }
}

/// The points of every curve: for each of [`CURVES`], its fit on [`GRID_POINTS`]
/// intensities from 0 to 1.2 times the largest run (none for a degenerate fit), then
/// the fraction collapsed at each level, in the order of `levels`.
#[must_use]
pub fn curve_points(rows: &[FragilityRow], curves: &[Curve]) -> Vec<CurvePoint> {
    let mut points = Vec::new();
    for curve in curves {
        let (data, _) = outcomes(rows, curve.outcome, curve.intensity);
        let top = data.iter().map(|o| o.im).fold(0.0, f64::max) * 1.2;
        let point = |kind, im, p, band, runs| CurvePoint {
            outcome: curve.outcome,
            intensity: curve.intensity,
            kind,
            im,
            p,
            band,
            runs,
        };
        if let Ok(fit) = &curve.fit {
            for k in 1..=GRID_POINTS {
                let im = top * k as f64 / GRID_POINTS as f64;
                points.push(point(
                    "fit",
                    im,
                    fit.probability(im),
                    Some(fit.band(im)),
                    None,
                ));
            }
        }
        let mut levels: Vec<f64> = Vec::new();
        for r in rows {
            if !levels.contains(&r.level) {
                levels.push(r.level);
            }
        }
        for level in levels {
            let at: Vec<(f64, bool)> = rows
                .iter()
                .filter(|r| r.level == level)
                .filter_map(|r| {
                    let im = curve.intensity.of(r).filter(|x| *x > 0.0)?;
                    Some((im, curve.outcome.of(r)?))
                })
                .collect();
            if at.is_empty() {
                continue;
            }
            let n = at.len() as f64;
            let mean_ln = at.iter().map(|(im, _)| im.ln()).sum::<f64>() / n;
            let fraction = at.iter().filter(|(_, c)| *c).count() as f64 / n;
            points.push(point(
                "level",
                mean_ln.exp(),
                fraction,
                None,
                Some(at.len()),
            ));
        }
    }
    points
}

#[cfg(test)]
mod tests;
