//! `rollstack.blocks`: scenes (TOML, the schema of docs/scenes.md), one simulation with
//! its trajectory as numpy arrays, the Lire, shaking and sliding presets, and the sweeps
//! of Figures 4.6 and 4.7 (Ch. 4, App. G–I), all from `blockstack`.

use crate::{guard, json_to_py, value_error};
use blockstack::scenarios::ColumnUnits;
use blockstack::scenarios::{
    lire, lire_on_floor, shaking_column, sliding_column, Perturbation, Shaking, Sliding,
};
use blockstack::scene::check_block_count;
use blockstack::scene_file::LoadedScene;
use blockstack::simulation::{simulate_until, Prox, RunOptions, RunReport, StepRecord};
use blockstack::studies::convergence::row::SWEEP_ENSEMBLE;
use blockstack::studies::convergence::{Settings, Study};
use blockstack::studies::scene_sweep::{Override, SceneSweep};
use blockstack::studies::shaking::{frequency_row_judged, periods_for_horizon};
use blockstack::studies::slide::slide_row_judged;
use blockstack::time_guard::{run_cost, wall_limit, Guard};
use blockstack::{scenes, Defaults};
use numpy::ndarray::{Array1, Array2, Array3};
use numpy::IntoPyArray;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use std::ops::ControlFlow;
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;
use std::sync::Arc;

/// A validated block-stack scene: blocks, base and its motion, contact, solver, floor.
#[pyclass(module = "rollstack.blocks", name = "Scene", frozen)]
#[derive(Debug, Clone)]
pub struct PyScene {
    scene: blockstack::Scene,
    defaults: Defaults,
    toml: Option<String>,
    title: String,
    /// Where the paths of the scene's records start (the file's directory).
    dir: PathBuf,
}

impl PyScene {
    /// The scene's TOML text (None for a preset built in code) and the directory its
    /// records' paths start from.
    pub(crate) fn source(&self) -> (Option<&str>, &std::path::Path) {
        (self.toml.as_deref(), &self.dir)
    }
}

#[pymethods]
impl PyScene {
    /// The scene as TOML text, when it was built from TOML (a file, a dict, keyword
    /// arguments or a built-in scene); `None` for the presets built in code.
    #[getter]
    fn toml(&self) -> Option<String> {
        self.toml.clone()
    }

    /// A short name of the scene.
    #[getter]
    fn title(&self) -> String {
        self.title.clone()
    }

    /// Number of free blocks.
    #[getter]
    fn n_blocks(&self) -> usize {
        self.scene.n_blocks()
    }

    /// What the scene may do unexpectedly (`Scene::warnings`), as text.
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.scene
            .warnings()
            .iter()
            .map(ToString::to_string)
            .collect()
    }

    /// The scene as used, after defaults (the `scene` object of the CLI's JSON).
    fn report<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let report = blockstack::scene_info::SceneReport::new(
            &self.scene,
            &RunOptions::default(),
            &self.defaults,
        );
        json_to_py(py, &report)
    }

    fn __repr__(&self) -> String {
        format!(
            "Scene({:?}, {} block(s))",
            self.title,
            self.scene.n_blocks()
        )
    }
}

impl PyScene {
    fn from_loaded(loaded: LoadedScene, toml: String, title: String, dir: PathBuf) -> Self {
        Self {
            scene: loaded.scene,
            defaults: loaded.defaults,
            toml: Some(toml),
            title,
            dir,
        }
    }

    fn from_scene(scene: blockstack::Scene, title: String) -> Self {
        Self {
            scene,
            defaults: Defaults::default(),
            toml: None,
            title,
            dir: PathBuf::new(),
        }
    }

    /// The validated scene, for the studies of `block_studies`.
    pub(crate) fn scene(&self) -> &blockstack::Scene {
        &self.scene
    }
}

/// Parses and validates a TOML scene (`LoadedScene::from_toml_at`); the paths of its
/// records start from `dir` (the working directory by default).
#[pyfunction]
#[pyo3(signature = (text, title = "scene".to_owned(), dir = String::new()))]
fn blocks_scene_from_toml(text: String, title: String, dir: String) -> PyResult<PyScene> {
    guard(|| {
        let dir = PathBuf::from(dir);
        let loaded = LoadedScene::from_toml_at(&text, &dir).map_err(value_error)?;
        Ok(PyScene::from_loaded(loaded, text, title, dir))
    })
}

/// A scene from the JSON text of a dict with the keys of a scene file (converted to
/// TOML, then read as a file is).
#[pyfunction]
#[pyo3(signature = (text, title = "scene".to_owned()))]
fn blocks_scene_from_json(text: String, title: String) -> PyResult<PyScene> {
    guard(|| {
        let value: serde_json::Value = serde_json::from_str(&text).map_err(value_error)?;
        if !value.is_object() {
            return Err(PyValueError::new_err("a scene must be a dict of tables"));
        }
        let toml = toml::to_string(&value).map_err(|e| value_error(format!("scene: {e}")))?;
        let loaded = LoadedScene::from_toml(&toml).map_err(value_error)?;
        Ok(PyScene::from_loaded(loaded, toml, title, PathBuf::new()))
    })
}

/// A built-in scene by name.
#[pyfunction]
fn blocks_builtin_scene(name: &str) -> PyResult<PyScene> {
    guard(|| {
        let builtin = scenes::find(name).map_err(value_error)?;
        let loaded = builtin.load().map_err(value_error)?;
        Ok(PyScene::from_loaded(
            loaded,
            builtin.toml.to_owned(),
            builtin.name.to_owned(),
            PathBuf::new(),
        ))
    })
}

/// The built-in scenes: (name, description) pairs.
#[pyfunction]
fn blocks_builtin_scenes() -> Vec<(String, String)> {
    scenes::builtin()
        .iter()
        .map(|s| (s.name.to_owned(), s.description.to_owned()))
        .collect()
}

fn perturbation(name: &str) -> PyResult<Perturbation> {
    match name {
        "none" => Ok(Perturbation::None),
        "bottom" => Ok(Perturbation::Bottom),
        "top" => Ok(Perturbation::Top),
        other => Err(PyValueError::new_err(format!(
            "perturb must be 'none', 'bottom' or 'top', got {other:?}"
        ))),
    }
}

/// Refuses 0 blocks or more than `scene::MAX_BLOCKS` before any is built.
fn at_least_one_block(blocks: usize) -> PyResult<()> {
    check_block_count("blocks", blocks).map_err(value_error)?;
    Ok(())
}

/// Refuses runs of `scenes` with `options`, shared out over the threads, estimated over
/// the ten-minute time guard (`time_guard::Guard`: the typical cost, then the cost of
/// the first steps of the first costliest run, as the CLI's sweeps), unless `force`;
/// `advice` says which parameters to change.
pub(crate) fn check_time_bound(
    scenes: &[blockstack::Scene],
    options: &RunOptions,
    force: bool,
    advice: &str,
) -> PyResult<()> {
    if force {
        return Ok(());
    }
    let costs: Vec<_> = scenes.iter().map(|s| run_cost(s, options)).collect();
    let costliest = (0..costs.len()).reduce(|best, i| {
        if costs[i].block_steps() > costs[best].block_steps() {
            i
        } else {
            best
        }
    });
    let guard = Guard {
        costs: &costs,
        threads: rayon::current_num_threads(),
        probe: costliest.map(|i| (&scenes[i], options)),
    };
    guard
        .check()
        .map_err(|e| value_error(format!("{e}: {advice}, or pass force=True")))
}

/// A branch rule by name: `"self_consistent"` (or the CLI's `"self-consistent"`) or
/// `"converged"`.
fn parse_branch_rule(name: &str) -> PyResult<nsga::BranchRule> {
    match name {
        "self_consistent" | "self-consistent" => Ok(nsga::BranchRule::SelfConsistent),
        "converged" => Ok(nsga::BranchRule::Converged),
        s => Err(value_error(format!(
            "branch_rule must be 'self_consistent' (or 'self-consistent') or 'converged', got {s:?}"
        ))),
    }
}

/// `options` with the spread of a sweep's rows over `branches` motions of each run,
/// found by `rule` (the CLI's `--branches`, `--branch-rule`).
fn with_spread(options: RunOptions, branches: usize, rule: &str) -> PyResult<RunOptions> {
    if branches == 0 {
        return Err(value_error("branches must be at least 1, got 0"));
    }
    Ok(RunOptions {
        spread_branches: branches,
        branch_rule: parse_branch_rule(rule)?,
        ..options
    })
}

/// The Leaning Tower of Lire (§4.3): `scenarios::lire` or `lire_on_floor`.
#[pyfunction]
fn blocks_lire(blocks: usize, perturb: &str, floor: bool) -> PyResult<PyScene> {
    guard(|| {
        at_least_one_block(blocks)?;
        let p = perturbation(perturb)?;
        let scene = if floor {
            lire_on_floor(blocks, p)
        } else {
            lire(blocks, p)
        }
        .map_err(value_error)?;
        Ok(PyScene::from_scene(
            scene,
            format!("Lire tower, perturbation {perturb}"),
        ))
    })
}

fn shaking_params(
    blocks: usize,
    omega: f64,
    amplitude: f64,
    mu: f64,
    steps_per_period: f64,
    periods: f64,
) -> PyResult<Shaking> {
    at_least_one_block(blocks)?;
    input::positive("omega", omega).map_err(value_error)?;
    input::non_negative("mu", mu).map_err(value_error)?;
    input::positive("periods", periods).map_err(value_error)?;
    input::positive("steps_per_period", steps_per_period).map_err(value_error)?;
    Ok(Shaking {
        blocks,
        amplitude,
        omega,
        periods,
        steps_per_period,
        mu,
        start_with_base: false,
    })
}

/// A column shaken at its base (§4.4): `scenarios::shaking_column`.
#[pyfunction]
#[pyo3(signature = (blocks, omega, amplitude, mu, steps_per_period, periods, start_with_base = false))]
fn blocks_shaking(
    blocks: usize,
    omega: f64,
    amplitude: f64,
    mu: f64,
    steps_per_period: f64,
    periods: f64,
    start_with_base: bool,
) -> PyResult<PyScene> {
    guard(|| {
        let p = Shaking {
            start_with_base,
            ..shaking_params(blocks, omega, amplitude, mu, steps_per_period, periods)?
        };
        let scene = shaking_column(&p).map_err(value_error)?;
        Ok(PyScene::from_scene(
            scene,
            format!("shaken column, x = {amplitude} sin({omega} t)"),
        ))
    })
}

fn sliding_params(blocks: usize, v0: f64, t_end: f64, mu: f64) -> PyResult<Sliding> {
    at_least_one_block(blocks)?;
    input::non_negative("mu", mu).map_err(value_error)?;
    input::positive("t_end", t_end).map_err(value_error)?;
    Ok(Sliding {
        blocks,
        v0,
        t_end,
        mu,
    })
}

/// A column on a base pulled at speed v0 (§4.5): `scenarios::sliding_column`.
#[pyfunction]
fn blocks_sliding(blocks: usize, v0: f64, t_end: f64, mu: f64) -> PyResult<PyScene> {
    guard(|| {
        let p = sliding_params(blocks, v0, t_end, mu)?;
        let scene = sliding_column(&p).map_err(value_error)?;
        Ok(PyScene::from_scene(
            scene,
            format!("sliding column, v0 = {v0}"),
        ))
    })
}

/// The library's run options from the Python keywords (the CLI's `SolverArgs`).
pub(crate) fn run_options(
    t_end: Option<f64>,
    prox_constant: Option<f64>,
    explore_branches: bool,
    last_resort: bool,
    stop_at_failure: bool,
    low_rank_updates: bool,
    force: bool,
) -> PyResult<RunOptions> {
    if let Some(t) = t_end {
        input::positive("t_end", t).map_err(value_error)?;
    }
    if let Some(r) = prox_constant {
        input::positive("prox_constant", r).map_err(value_error)?;
    }
    Ok(RunOptions {
        t_end,
        prox: prox_constant.map(Prox::Constant),
        explore_branches,
        stop_at_failure,
        skip_last_resort: !last_resort,
        skip_low_rank_updates: !low_rank_updates,
        // The watchdog stops a run projected past the time bound as it runs, unless
        // forced (the CLI's --force).
        time_bound: input::watchdog::time_bound(force),
        ..RunOptions::default()
    })
}

/// The trajectory, kept step by step.
#[derive(Debug, Default)]
struct Trajectory {
    t: Vec<f64>,
    q: Vec<f64>,
    u: Vec<f64>,
    base: Vec<f64>,
    forces: Vec<f64>,
    gaps: Vec<f64>,
    min_gap: Vec<f64>,
    energy: Vec<f64>,
    iterations: Vec<i64>,
}

impl Trajectory {
    fn push(&mut self, r: &StepRecord) {
        self.t.push(r.t);
        self.q
            .extend(r.poses.iter().flat_map(|p| [p.x, p.y, p.theta]));
        self.u.extend(r.velocities.iter().flatten());
        self.base.extend([r.base.x, r.base.y, r.base.theta]);
        self.forces.extend(
            r.forces
                .iter()
                .flat_map(|f| [f.normal[0], f.normal[1], f.friction]),
        );
        self.gaps.extend(r.gaps.iter().flatten());
        self.min_gap.push(r.min_gap);
        self.energy.push(r.energy);
        self.iterations
            .push(i64::try_from(r.iterations).unwrap_or(i64::MAX));
    }

    /// The arrays into `out` for n blocks and m interfaces: t (N,), q, u (N, n, 3), forces
    /// (N, m, 3), gaps (N, m, 2), base (N, 3), min_gap, energy (N,), iterations (N,) int64.
    fn into_dict(
        self,
        py: Python<'_>,
        (n, m): (usize, usize),
        out: &Bound<'_, PyDict>,
    ) -> PyResult<()> {
        let steps = self.t.len();
        let shape_err = |e: numpy::ndarray::ShapeError| value_error(e);
        let cube = |v: Vec<f64>, k: usize| Array3::from_shape_vec((steps, n, k), v);
        let per_interface = |v: Vec<f64>, k: usize| Array3::from_shape_vec((steps, m, k), v);
        out.set_item("t", Array1::from_vec(self.t).into_pyarray(py))?;
        out.set_item("q", cube(self.q, 3).map_err(shape_err)?.into_pyarray(py))?;
        out.set_item("u", cube(self.u, 3).map_err(shape_err)?.into_pyarray(py))?;
        out.set_item(
            "forces",
            per_interface(self.forces, 3)
                .map_err(shape_err)?
                .into_pyarray(py),
        )?;
        out.set_item(
            "gaps",
            per_interface(self.gaps, 2)
                .map_err(shape_err)?
                .into_pyarray(py),
        )?;
        out.set_item(
            "base",
            Array2::from_shape_vec((steps, 3), self.base)
                .map_err(shape_err)?
                .into_pyarray(py),
        )?;
        out.set_item("min_gap", Array1::from_vec(self.min_gap).into_pyarray(py))?;
        out.set_item("energy", Array1::from_vec(self.energy).into_pyarray(py))?;
        out.set_item(
            "iterations",
            Array1::from_vec(self.iterations).into_pyarray(py),
        )?;
        Ok(())
    }
}

/// Runs a scene (`simulation::simulate_until`) on a worker thread with the GIL released,
/// checking for Ctrl-C every 20 ms: a Ctrl-C ends the run within its current step (its
/// `cancel` flag, `nsga::Interrupt`), and the trajectory up to there is kept.
/// Returns a dict: `report_json` (the CLI's JSON of `blocks run`, without files and
/// notes, as text), `steps`, `failure_time`,
/// the trajectory arrays, `events` (list of dicts), `error` (message or None) and
/// `interrupted` (a KeyboardInterrupt to raise, or None: the caller raises it after
/// keeping the partial result).
#[pyfunction]
#[pyo3(signature = (scene, t_end = None, prox_constant = None, explore_branches = true, last_resort = true, stop_at_failure = false, low_rank_updates = true, force = false))]
#[allow(clippy::too_many_arguments)]
fn blocks_simulate<'py>(
    py: Python<'py>,
    scene: &PyScene,
    t_end: Option<f64>,
    prox_constant: Option<f64>,
    explore_branches: bool,
    last_resort: bool,
    stop_at_failure: bool,
    low_rank_updates: bool,
    force: bool,
) -> PyResult<Bound<'py, PyDict>> {
    guard(|| {
        let options = run_options(
            t_end,
            prox_constant,
            explore_branches,
            last_resort,
            stop_at_failure,
            low_rank_updates,
            force,
        )?;
        let scenes = std::slice::from_ref(&scene.scene);
        check_time_bound(scenes, &options, force, "shorten t_end")?;
        let cancel = Arc::new(AtomicBool::new(false));
        let options = RunOptions {
            cancel: Some(cancel.clone()),
            ..options
        };
        let run = &scene.scene;
        let (ran, interrupt) = crate::interruptible_keeping(py, &cancel, || {
            let mut trajectory = Trajectory::default();
            let summary = simulate_until(run, &options, |r| {
                trajectory.push(r);
                ControlFlow::Continue(())
            })
            .map_err(value_error)?;
            Ok((summary, trajectory))
        });
        let (summary, trajectory) = ran?;
        let t_final = trajectory.t.last().copied().unwrap_or(0.0);
        let report = RunReport::new(&summary, &scene.scene, &options, &scene.defaults, t_final);
        let out = PyDict::new(py);
        // The report as JSON text: the Python Result parses it when first asked for.
        out.set_item(
            "report_json",
            serde_json::to_string(&report).map_err(value_error)?,
        )?;
        out.set_item("steps", summary.steps)?;
        out.set_item("failure_time", summary.failure_time)?;
        let events = PyList::empty(py);
        let event = |kind: &str, t: f64| -> PyResult<Bound<'py, PyDict>> {
            let d = PyDict::new(py);
            d.set_item("kind", kind)?;
            d.set_item("t", t)?;
            Ok(d)
        };
        let mut timeline: Vec<(f64, Bound<'py, PyDict>)> = Vec::new();
        for b in &summary.branch_points {
            let d = event("branch_point", b.t)?;
            d.set_item("candidates", b.candidates)?;
            d.set_item("distinct", b.distinct)?;
            timeline.push((b.t, d));
        }
        if let Some(t) = summary.failure_time {
            timeline.push((t, event("failure", t)?));
        }
        if let Some(t) = summary.opening_time {
            timeline.push((t, event("opening", t)?));
        }
        for e in &summary.events {
            let kind = serde_json::to_value(e.kind).map_err(value_error)?;
            let d = event(kind.as_str().unwrap_or("event"), e.t)?;
            d.set_item("block", e.block)?;
            if let Some(on) = e.on {
                // A block resting on several bodies: the one it lost its support on.
                d.set_item("on", on.to_string())?;
            }
            timeline.push((e.t, d));
        }
        if let Some(e) = &summary.error {
            let d = event("error", t_final)?;
            d.set_item("message", e.to_string())?;
            timeline.push((t_final, d));
        }
        // Stable: events at the same time keep the order above.
        timeline.sort_by(|a, b| a.0.total_cmp(&b.0));
        for (_, d) in timeline {
            events.append(d)?;
        }
        out.set_item("events", events)?;
        out.set_item("error", summary.error.as_ref().map(ToString::to_string))?;
        let s = &scene.scene;
        trajectory.into_dict(py, (s.n_blocks(), s.n_interfaces()), &out)?;
        out.set_item("interrupted", interrupt.map(|e| e.into_value(py)))?;
        Ok(out)
    })
}

/// Rows of Figure 4.6 (`studies::shaking::frequency_row`), one per ω, in parallel on
/// rayon with the GIL released; each row as the CLI's `blocks sweep frequency --json`.
#[pyfunction]
#[pyo3(signature = (omegas, periods, amplitude, blocks, steps_per_period, mu, prox_constant = None, explore_branches = true, last_resort = true, t_max = None, low_rank_updates = true, branches = 1, branch_rule = "self_consistent", force = false, convergence = None, ensemble = None))]
#[allow(clippy::too_many_arguments)]
fn blocks_sweep_frequency<'py>(
    py: Python<'py>,
    omegas: Vec<f64>,
    periods: f64,
    amplitude: f64,
    blocks: usize,
    steps_per_period: f64,
    mu: f64,
    prox_constant: Option<f64>,
    explore_branches: bool,
    last_resort: bool,
    t_max: Option<f64>,
    low_rank_updates: bool,
    branches: usize,
    branch_rule: &str,
    force: bool,
    convergence: Option<usize>,
    ensemble: Option<usize>,
) -> PyResult<Bound<'py, PyAny>> {
    guard(|| {
        let settings = judged(convergence, ensemble)?;
        if let Some(t) = t_max {
            input::positive("t_max", t).map_err(value_error)?;
        }
        let options = run_options(
            None,
            prox_constant,
            explore_branches,
            last_resort,
            true,
            low_rank_updates,
            force,
        )?;
        let mut options = with_spread(options, branches, branch_rule)?;
        let (columns, scenes): (Vec<_>, Vec<_>) = omegas
            .iter()
            .map(|&omega| {
                // A horizon in time units, the same at every ω (as `--t-max`).
                let periods = t_max.map_or(periods, |t| periods_for_horizon(t, omega));
                let p = shaking_params(blocks, omega, amplitude, mu, steps_per_period, periods)?;
                let scene =
                    shaking_column(&p).map_err(|e| value_error(format!("omega {omega}: {e}")))?;
                Ok((p, scene))
            })
            .collect::<PyResult<Vec<_>>>()?
            .into_iter()
            .unzip();
        let advice = "shorten periods or t_max, take fewer values";
        let scenes = with_studies(scenes, &options, settings)?;
        check_time_bound(&scenes, &options, force, advice)?;
        parallel_rows(py, &columns, &mut options, |p, o| {
            frequency_row_judged(p, &ColumnUnits::default(), o, settings)
        })
    })
}

/// Rows of Figure 4.7 (`studies::slide::slide_row`), one per v0, in parallel on rayon
/// with the GIL released; each row as the CLI's `blocks sweep slide --json`.
#[pyfunction]
#[pyo3(signature = (speeds, t_end, blocks, mu, prox_constant = None, explore_branches = true, last_resort = true, low_rank_updates = true, branches = 1, branch_rule = "self_consistent", force = false, convergence = None, ensemble = None))]
#[allow(clippy::too_many_arguments)]
fn blocks_sweep_slide<'py>(
    py: Python<'py>,
    speeds: Vec<f64>,
    t_end: f64,
    blocks: usize,
    mu: f64,
    prox_constant: Option<f64>,
    explore_branches: bool,
    last_resort: bool,
    low_rank_updates: bool,
    branches: usize,
    branch_rule: &str,
    force: bool,
    convergence: Option<usize>,
    ensemble: Option<usize>,
) -> PyResult<Bound<'py, PyAny>> {
    guard(|| {
        let settings = judged(convergence, ensemble)?;
        let options = run_options(
            Some(t_end),
            prox_constant,
            explore_branches,
            last_resort,
            false,
            low_rank_updates,
            force,
        )?;
        let mut options = with_spread(options, branches, branch_rule)?;
        let (columns, scenes): (Vec<_>, Vec<_>) = speeds
            .iter()
            .map(|&v0| {
                let p = sliding_params(blocks, v0, t_end, mu)?;
                let scene = sliding_column(&p).map_err(|e| value_error(format!("v0 {v0}: {e}")))?;
                Ok((p, scene))
            })
            .collect::<PyResult<Vec<_>>>()?
            .into_iter()
            .unzip();
        let scenes = with_studies(scenes, &options, settings)?;
        check_time_bound(&scenes, &options, force, "shorten t_end, take fewer values")?;
        parallel_rows(py, &columns, &mut options, |p, o| {
            slide_row_judged(p, &ColumnUnits::default(), o, settings)
        })
    })
}

/// A scene run once per combination of the values of its swept keys
/// (`studies::scene_sweep`), in parallel on rayon with the GIL released, in input order;
/// rows as the CLI's `blocks sweep scene --json`. `overrides` are `KEY=VALUES` texts
/// (`contact.mu=0.1:0.5:0.1`, `base.omega=2,4,8`); every combination's scene is checked
/// before any run.
#[pyfunction]
#[pyo3(signature = (scene, overrides, t_end = None, stop_at_failure = false, prox_constant = None, explore_branches = true, last_resort = true, low_rank_updates = true, force = false, convergence = None, ensemble = None))]
#[allow(clippy::too_many_arguments)]
fn blocks_sweep_scene<'py>(
    py: Python<'py>,
    scene: &PyScene,
    overrides: Vec<String>,
    t_end: Option<f64>,
    stop_at_failure: bool,
    prox_constant: Option<f64>,
    explore_branches: bool,
    last_resort: bool,
    low_rank_updates: bool,
    force: bool,
    convergence: Option<usize>,
    ensemble: Option<usize>,
) -> PyResult<Bound<'py, PyAny>> {
    guard(|| {
        let settings = judged(convergence, ensemble)?;
        let text = scene.toml.as_deref().ok_or_else(|| {
            PyValueError::new_err(
                "a scene sweep needs a scene built from TOML (a file, a dict, keywords or a built-in name), not a preset",
            )
        })?;
        let overrides = overrides
            .iter()
            .map(|o| o.parse::<Override>().map_err(PyValueError::new_err))
            .collect::<PyResult<Vec<_>>>()?;
        let sweep = SceneSweep::new(text, overrides)
            .map_err(value_error)?
            .in_dir(scene.dir.clone());
        let mut options = run_options(
            t_end,
            prox_constant,
            explore_branches,
            last_resort,
            stop_at_failure,
            low_rank_updates,
            force,
        )?;
        let points = sweep.points();
        let scenes = points
            .iter()
            .map(|point| {
                sweep.scene(point).map(|loaded| loaded.scene).map_err(|e| {
                    let set: Vec<String> = point
                        .iter()
                        .map(|s| format!("{}={}", s.key, s.value))
                        .collect();
                    value_error(format!("{}: {e}", set.join(", ")))
                })
            })
            .collect::<PyResult<Vec<_>>>()?;
        let advice = "shorten t_end or solver.t_end, take fewer values";
        let scenes = with_studies(scenes, &options, settings)?;
        check_time_bound(&scenes, &options, force, advice)?;
        parallel_rows(py, &points, &mut options, |p, o| {
            sweep.row_judged(p, o, settings)
        })
    })
}

/// The settings of a sweep's `convergence` = K and `ensemble` = N keywords (default
/// [`SWEEP_ENSEMBLE`] members), or None without `convergence`.
///
/// # Errors
/// An `ensemble` without `convergence`, or either out of range, named.
fn judged(convergence: Option<usize>, ensemble: Option<usize>) -> PyResult<Option<Settings>> {
    let Some(levels) = convergence else {
        return match ensemble {
            Some(_) => Err(value_error("ensemble needs convergence (the levels K)")),
            None => Ok(None),
        };
    };
    let settings = Settings {
        levels,
        ensemble: ensemble.unwrap_or(SWEEP_ENSEMBLE),
    };
    settings
        .validate(["convergence", "ensemble"])
        .map_err(value_error)?;
    Ok(Some(settings))
}

/// `scenes` and, with `settings`, every run of each one's convergence study: what the
/// time guard counts.
///
/// # Errors
/// A member's scene the checks refuse.
fn with_studies(
    scenes: Vec<blockstack::Scene>,
    options: &RunOptions,
    settings: Option<Settings>,
) -> PyResult<Vec<blockstack::Scene>> {
    let Some(settings) = settings else {
        return Ok(scenes);
    };
    let mut all = scenes.clone();
    for scene in &scenes {
        let study = Study::new(scene, options, settings, ["convergence", "ensemble"])
            .map_err(value_error)?;
        all.extend(
            study
                .levels()
                .iter()
                .chain(study.members())
                .map(|j| j.scene.clone()),
        );
    }
    Ok(all)
}

/// [`crate::parallel_rows`] of block-stack runs with `options`, whose `cancel` flag is
/// set here: a Ctrl-C ends every run within its current step.
pub(crate) fn parallel_rows<'py, P: Sync, R: Send + serde::Serialize>(
    py: Python<'py>,
    items: &[P],
    options: &mut RunOptions,
    row: impl Fn(&P, &RunOptions) -> R + Sync + Send,
) -> PyResult<Bound<'py, PyAny>> {
    let cancel = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
    options.cancel = Some(cancel.clone());
    let options = &*options;
    crate::parallel_rows(py, items, &cancel, |p| row(p, options))
}

/// Every continuation of a scene's run (`blockstack::exploration`): the JSON of
/// `rollstack blocks explore --json`, with `branch_rows` (the rows of `branches.csv`, as
/// objects) and `fork_rows` (one object per fork: its contact states and evidence). The
/// exploration runs with the GIL released, after the time guard of its root run (as the
/// CLI's), unless `force`.
#[pyfunction]
#[pyo3(signature = (scene, t_end = None, strategy = "breadth", max_branches = 1000, max_depth = None, max_wall = None, branch_rule = "self_consistent", probe_flips = false, classify = false, prox_constant = None, force = false))]
#[allow(clippy::too_many_arguments)]
fn blocks_explore<'py>(
    py: Python<'py>,
    scene: &PyScene,
    t_end: Option<f64>,
    strategy: &str,
    max_branches: usize,
    max_depth: Option<usize>,
    max_wall: Option<f64>,
    branch_rule: &str,
    probe_flips: bool,
    classify: bool,
    prox_constant: Option<f64>,
    force: bool,
) -> PyResult<Bound<'py, PyAny>> {
    use blockstack::exploration::{
        branch_cells, explore_scene, fork_records, outcome_groups, ExplorationReport, WalkSettings,
        BRANCH_COLUMNS,
    };
    use nsga::explore::{ExploreOptions, Strategy};
    guard(|| {
        let strategy = match strategy {
            "breadth" => Strategy::Breadth,
            "depth" => Strategy::Depth,
            s => {
                return Err(value_error(format!(
                    "strategy must be 'breadth' or 'depth', got {s:?}"
                )))
            }
        };
        let rule = parse_branch_rule(branch_rule)?;
        if max_branches == 0 {
            return Err(value_error("max_branches must be at least 1"));
        }
        if let Some(w) = max_wall {
            input::non_negative("max_wall", w).map_err(value_error)?;
        }
        let options = RunOptions {
            branch_rule: rule,
            probe_flips,
            // The exploration turns the low-rank updates off itself.
            ..run_options(t_end, prox_constant, true, true, false, false, force)?
        };
        let explore_options = ExploreOptions {
            strategy,
            max_branches,
            max_depth: max_depth.unwrap_or(usize::MAX),
            max_wall: max_wall.and_then(wall_limit),
        };
        let settings = WalkSettings {
            sample_every: u64::MAX,
            classify,
            ..WalkSettings::default()
        };
        let scene = &scene.scene;
        check_time_bound(
            std::slice::from_ref(scene),
            &options,
            force,
            "shorten t_end",
        )?;
        let tree = py
            .detach(|| explore_scene(scene, &options, &explore_options, settings))
            .map_err(value_error)?;
        let forks = fork_records(&tree, scene.n_interfaces());
        let report = ExplorationReport::new(&tree, &forks, outcome_groups(&tree));
        let mut value = serde_json::to_value(&report).map_err(value_error)?;
        value["strategy"] = strategy.name().into();
        value["branch_rule"] = rule.name().into();
        value["branch_rows"] = tree
            .branches
            .iter()
            .map(|b| {
                let row: serde_json::Map<String, serde_json::Value> = BRANCH_COLUMNS
                    .iter()
                    .zip(branch_cells(b))
                    .map(|(k, v)| ((*k).to_owned(), v.into()))
                    .collect();
                serde_json::Value::Object(row)
            })
            .collect();
        value["fork_rows"] = serde_json::to_value(&forks).map_err(value_error)?;
        json_to_py(py, &value)
    })
}

pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyScene>()?;
    m.add_function(wrap_pyfunction!(blocks_scene_from_toml, m)?)?;
    m.add_function(wrap_pyfunction!(blocks_scene_from_json, m)?)?;
    m.add_function(wrap_pyfunction!(blocks_builtin_scene, m)?)?;
    m.add_function(wrap_pyfunction!(blocks_builtin_scenes, m)?)?;
    m.add_function(wrap_pyfunction!(blocks_lire, m)?)?;
    m.add_function(wrap_pyfunction!(blocks_shaking, m)?)?;
    m.add_function(wrap_pyfunction!(blocks_sliding, m)?)?;
    m.add_function(wrap_pyfunction!(blocks_simulate, m)?)?;
    m.add_function(wrap_pyfunction!(blocks_sweep_frequency, m)?)?;
    m.add_function(wrap_pyfunction!(blocks_explore, m)?)?;
    m.add_function(wrap_pyfunction!(blocks_sweep_slide, m)?)?;
    m.add_function(wrap_pyfunction!(blocks_sweep_scene, m)?)?;
    Ok(())
}
