//! `rollstack.rotations`: conversions between the representations of §2.2 and App. A
//! (axis–angle (2.2.1)₁, quaternions (2.2.1)₂, matrices, the 12 Euler sets (A.1.2)),
//! batched over leading axes, and the report of one rotation, from `rotations`.

use crate::{guard, json_to_py, value_error};
use numpy::ndarray::{ArrayD, IxDyn};
use numpy::{IntoPyArray, PyArrayDyn, PyReadonlyArrayDyn};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use rotations::{
    quaternion_from_matrix, rotation_report, AxisAngle, EulerSet, Representation, Rotation3,
    Vector3, MATRIX_INPUT_TOLERANCE,
};

/// The rotation R(angle, axis) of (2.2.1)₁ (axis need not be unit), as the CLI reads
/// `--angle` and `--axis`.
pub(crate) fn target_rotation(angle: f64, axis: [f64; 3]) -> PyResult<Rotation3<f64>> {
    Ok(
        AxisAngle::new(angle, Vector3::new(axis[0], axis[1], axis[2]))
            .map_err(|e| value_error(format!("axis: {e}")))?
            .to_rotation(),
    )
}

fn representation(name: &str) -> PyResult<Representation> {
    Representation::from_name(name).map_err(value_error)
}

/// The values of `rotation` in `repr`: [x, y, z, θ] (canonical axis–angle),
/// [q0, q1, q2, q3] (q0 ≥ 0), nine matrix entries row by row, or three Euler angles.
fn values_of(rotation: &Rotation3<f64>, repr: Representation) -> Vec<f64> {
    match repr {
        Representation::AxisAngle => {
            let a = AxisAngle::from_rotation(rotation);
            vec![a.axis[0], a.axis[1], a.axis[2], a.angle]
        }
        Representation::Quaternion => {
            let q = quaternion_from_matrix(rotation.matrix());
            vec![q.w, q.i, q.j, q.k]
        }
        Representation::Matrix => {
            let m = rotation.matrix();
            (0..3)
                .flat_map(|i| (0..3).map(move |j| m[(i, j)]))
                .collect()
        }
        Representation::Euler(set) => set.angles(rotation).to_vec(),
    }
}

/// Converts an array whose last axis holds rotations in `from` (shape (..., 4), (..., 4),
/// (..., 3, 3) or (..., 3)) to `to`, row by row.
#[pyfunction]
fn rotations_convert<'py>(
    py: Python<'py>,
    values: PyReadonlyArrayDyn<'py, f64>,
    from: &str,
    to: &str,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    guard(|| {
        let (from, to) = (representation(from)?, representation(to)?);
        let a = values.as_array();
        let shape = a.shape().to_vec();
        let input_dims = if from == Representation::Matrix { 2 } else { 1 };
        let k_in = from.value_count();
        let ok = shape.len() >= input_dims
            && shape[shape.len() - input_dims..].iter().product::<usize>() == k_in
            && (input_dims == 1 || shape[shape.len() - 2..] == [3, 3]);
        if !ok {
            let want = if input_dims == 2 {
                "(..., 3, 3)".to_owned()
            } else {
                format!("(..., {k_in})")
            };
            return Err(PyValueError::new_err(format!(
                "values of shape {shape:?}: {from} needs the shape {want}"
            )));
        }
        let lead = &shape[..shape.len() - input_dims];
        let flat: Vec<f64> = a.iter().copied().collect();
        let mut out = Vec::with_capacity(flat.len() / k_in * to.value_count());
        for (row, v) in flat.chunks(k_in).enumerate() {
            let rotation = from
                .rotation(v, MATRIX_INPUT_TOLERANCE)
                .map_err(|e| value_error(format!("rotation {row}: {e}")))?;
            out.extend(values_of(&rotation, to));
        }
        let mut out_shape = lead.to_vec();
        if to == Representation::Matrix {
            out_shape.extend([3, 3]);
        } else {
            out_shape.push(to.value_count());
        }
        let array = ArrayD::from_shape_vec(IxDyn(&out_shape), out).map_err(value_error)?;
        Ok(array.into_pyarray(py))
    })
}

/// The report of one rotation in every representation (`rotations::rotation_report`),
/// as the CLI's `rotation --json`.
#[pyfunction]
fn rotations_report<'py>(
    py: Python<'py>,
    values: Vec<f64>,
    from: &str,
) -> PyResult<Bound<'py, PyAny>> {
    guard(|| {
        let repr = representation(from)?;
        let rotation = repr
            .rotation(&values, MATRIX_INPUT_TOLERANCE)
            .map_err(value_error)?;
        json_to_py(py, &rotation_report(&rotation))
    })
}

/// The names of the twelve Euler sets (`1-2-3`, …, `3-2-3`).
#[pyfunction]
fn rotations_euler_sets() -> Vec<String> {
    EulerSet::ALL.iter().map(ToString::to_string).collect()
}

pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(rotations_convert, m)?)?;
    m.add_function(wrap_pyfunction!(rotations_report, m)?)?;
    m.add_function(wrap_pyfunction!(rotations_euler_sets, m)?)?;
    Ok(())
}
