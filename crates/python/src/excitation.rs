//! `rollstack.blocks` excitation builders: a recorded accelerogram read, corrected and
//! integrated as a scene's base would play it, and acceleration pulses, as numpy arrays
//! of t, a, v, d (`blockstack::base`).

use crate::{guard, value_error};
use blockstack::base::{load_record, Baseline, Pulse, PulseShape, RecordOptions};
use numpy::ndarray::Array1;
use numpy::IntoPyArray;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::Path;

/// The dict {t, a, v, d} of numpy arrays.
fn arrays<'py>(py: Python<'py>, columns: [Vec<f64>; 4]) -> PyResult<Bound<'py, PyDict>> {
    let out = PyDict::new(py);
    for (name, column) in ["t", "a", "v", "d"].into_iter().zip(columns) {
        out.set_item(name, Array1::from_vec(column).into_pyarray(py))?;
    }
    Ok(out)
}

/// A record file (`.AT2` or CSV) as a scene's `record` motion plays it: read, corrected
/// (`baseline`), scaled to `scale_to_pga` then by `scale`, each unit of the file's
/// times `unit`; its samples' t, a, v, d.
#[pyfunction]
#[pyo3(signature = (path, dt = None, scale = 1.0, scale_to_pga = None, baseline = "end-at-rest", unit = 1.0))]
fn blocks_read_record<'py>(
    py: Python<'py>,
    path: &str,
    dt: Option<f64>,
    scale: f64,
    scale_to_pga: Option<f64>,
    baseline: &str,
    unit: f64,
) -> PyResult<Bound<'py, PyDict>> {
    guard(|| {
        let options = RecordOptions {
            dt,
            unit: input::finite("unit", unit).map_err(value_error)?,
            scale,
            scale_to_pga,
            baseline: Baseline::from_name(baseline).map_err(value_error)?,
        };
        let record = load_record(Path::new(path), &options).map_err(value_error)?;
        arrays(py, record.samples().map(<[f64]>::to_vec))
    })
}

/// A pulse's a, v, d (from rest at `start`) at the times `t`.
#[pyfunction]
#[pyo3(signature = (shape, amplitude, period, t, start = 0.0))]
fn blocks_pulse<'py>(
    py: Python<'py>,
    shape: &str,
    amplitude: f64,
    period: f64,
    t: Vec<f64>,
    start: f64,
) -> PyResult<Bound<'py, PyDict>> {
    guard(|| {
        let shape = PulseShape::from_name(shape).map_err(value_error)?;
        let pulse = Pulse::new(shape, amplitude, period, start).map_err(value_error)?;
        let at: Vec<_> = t.iter().map(|&s| pulse.at(s)).collect();
        let a = at.iter().map(|k| k.acceleration).collect();
        let v = at.iter().map(|k| k.velocity).collect();
        let d = at.iter().map(|k| k.displacement).collect();
        arrays(py, [t, a, v, d])
    })
}

pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(blocks_read_record, m)?)?;
    m.add_function(wrap_pyfunction!(blocks_pulse, m)?)?;
    Ok(())
}
