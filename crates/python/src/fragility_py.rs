//! `rollstack.blocks.fragility`: a scene under every record of a list at every intensity
//! level, and the lognormal fragility curves fitted to the outcomes
//! (`blockstack::studies::fragility`, the rows and fits of `rollstack blocks fragility`).

use crate::blocks::{check_time_bound, parallel_rows, run_options, PyScene};
use crate::{guard, json_to_py, sweep_values, value_error};
use blockstack::studies::fragility::{
    check_levels, fit_curves, records_in, FragilityRow, FragilityStudy, Measure, RecordFile,
};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::{Path, PathBuf};

/// The records of `records`: every record of one directory (sorted by name), or the
/// files given, in their order.
fn record_files(records: &[String]) -> PyResult<Vec<RecordFile>> {
    if let [one] = records {
        if Path::new(one).is_dir() {
            return records_in(Path::new(one)).map_err(|e| value_error(format!("records: {e}")));
        }
    }
    if records.is_empty() {
        return Err(PyValueError::new_err("records holds no record"));
    }
    records
        .iter()
        .map(|r| {
            let path =
                std::path::absolute(r).map_err(|e| value_error(format!("records: {r}: {e}")))?;
            let name = path
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default();
            Ok(RecordFile { name, path })
        })
        .collect()
}

/// Runs a fragility study: {"rows": [...], "fits": [...]} as the CLI's `--json` prints.
#[pyfunction]
#[pyo3(signature = (scene, records, levels, measure, t_end, prox_constant, explore_branches, last_resort, low_rank_updates, force))]
fn blocks_fragility<'py>(
    py: Python<'py>,
    scene: &PyScene,
    records: Vec<String>,
    levels: &Bound<'py, PyAny>,
    measure: &str,
    t_end: Option<f64>,
    prox_constant: Option<f64>,
    explore_branches: bool,
    last_resort: bool,
    low_rank_updates: bool,
    force: bool,
) -> PyResult<Bound<'py, PyAny>> {
    guard(|| {
        let measure = match measure {
            "scale" => Measure::Scale,
            "pga" => Measure::Pga,
            other => {
                return Err(value_error(format!(
                    "measure must be 'scale' or 'pga', got {other:?}"
                )))
            }
        };
        let levels = sweep_values("scales", levels)?;
        check_levels(&levels, measure).map_err(|e| value_error(format!("scales: {e}")))?;
        let (toml, dir) = scene.source();
        let text = toml.ok_or_else(|| {
            PyValueError::new_err(
                "a fragility study needs a scene built from TOML (a file, a dict, keywords or a built-in name), not a preset",
            )
        })?;
        let study = FragilityStudy::new(text, record_files(&records)?, levels, measure)
            .map_err(value_error)?
            .in_dir(PathBuf::from(dir))
            .ending_at(t_end);
        let mut options = run_options(
            None,
            prox_constant,
            explore_branches,
            last_resort,
            false,
            low_rank_updates,
            force,
        )?;
        let points = study.points();
        let scenes = points
            .iter()
            .map(|&p| {
                study.scene(p).map(|l| l.scene).map_err(|e| {
                    let name = &study.records()[p.record].name;
                    value_error(format!("{name} at {}: {e}", input::Short(p.level)))
                })
            })
            .collect::<PyResult<Vec<_>>>()?;
        check_time_bound(&scenes, &options, force, "take fewer records or levels")?;
        let rows = parallel_rows(py, &points, &mut options, |&p, o| study.row(p, o))?;
        let typed: Vec<FragilityRow> = pythonize_rows(py, &rows)?;
        let out = PyDict::new(py);
        out.set_item("rows", rows)?;
        out.set_item("fits", json_to_py(py, &fit_curves(&typed))?)?;
        Ok(out.into_any())
    })
}

/// The rows back from their Python form (the fits are computed from the rows the
/// caller gets, so that both come from one run).
fn pythonize_rows(py: Python<'_>, rows: &Bound<'_, PyAny>) -> PyResult<Vec<FragilityRow>> {
    let text: String = py
        .import("json")?
        .call_method1("dumps", (rows,))?
        .extract()?;
    serde_json::from_str(&text).map_err(value_error)
}

pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(blocks_fragility, m)?)?;
    Ok(())
}
