//! `rollstack rotation`: convert one rotation between every representation.

use crate::angles::{parse_angle, parse_finite};
use crate::output::print_json;
use anyhow::{bail, Context, Result};
use clap::Args;
use rotations::{
    rotation_from_matrix, rotation_from_quaternion, AxisAngle, EulerSet, Matrix3, Rotation3,
    Vector3,
};
use serde::Serialize;
use std::collections::BTreeMap;

/// Arguments of `rollstack rotation`.
#[derive(Debug, Args)]
pub struct RotationArgs {
    /// Representation of the input: `axis-angle`, `quaternion`, `matrix` or `euler:SET`
    /// (SET one of 3-1-3, 3-2-3, 1-2-1, 1-3-1, 2-1-2, 2-3-2, 3-2-1, 3-1-2, 1-2-3, 1-3-2,
    /// 2-1-3, 2-3-1).
    #[arg(long)]
    pub from: String,
    /// Comma-separated values: axis-angle `x,y,z,angle` (axis on E1, E2, E3, need not be
    /// unit; angle in rad, `90deg` or `3pi/2`); quaternion `q0,q1,q2,q3` (scalar first,
    /// normalised); matrix: nine entries row by row, entry (i,j) = Eᵢ·R Eⱼ (within 1e-4 of
    /// a rotation; projected onto the nearest one); euler: three angles a1,a2,a3.
    #[arg(long, allow_hyphen_values = true)]
    pub values: String,
    /// Print one JSON object on stdout (otherwise a readable summary).
    #[arg(long)]
    pub json: bool,
}

/// How far a `--from matrix` input may be from orthogonal (Frobenius norm of RᵀR − I).
const MATRIX_TOLERANCE: f64 = 1e-4;

/// The input representation named by `--from`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Representation {
    /// `x,y,z,angle`.
    AxisAngle,
    /// `q0,q1,q2,q3`.
    Quaternion,
    /// Nine entries row by row.
    Matrix,
    /// Three angles of an Euler set.
    Euler(EulerSet),
}

impl Representation {
    /// Parses the `--from` value.
    ///
    /// # Errors
    /// An unknown representation or Euler set.
    pub fn parse(text: &str) -> Result<Self> {
        Ok(match text {
            "axis-angle" => Self::AxisAngle,
            "quaternion" => Self::Quaternion,
            "matrix" => Self::Matrix,
            other => match other.strip_prefix("euler:") {
                Some(set) => Self::Euler(EulerSet::from_name(set)?),
                None => bail!(
                    "unknown representation '{text}' (expected axis-angle, quaternion, matrix or euler:SET)"
                ),
            },
        })
    }

    fn expected_values(self) -> usize {
        match self {
            Self::AxisAngle | Self::Quaternion => 4,
            Self::Matrix => 9,
            Self::Euler(_) => 3,
        }
    }
}

/// The JSON of `rollstack rotation` (DESIGN.md, CLI contract).
#[derive(Debug, Serialize)]
pub struct RotationReport {
    /// Rows of R: entry [i][j] = Eᵢ · R Eⱼ.
    pub matrix: [[f64; 3]; 3],
    /// Canonical unit quaternion [q0, q1, q2, q3], q0 ≥ 0.
    pub quaternion: [f64; 4],
    /// Canonical unit axis (E3 for the identity).
    pub axis: [f64; 3],
    /// Canonical angle in [0, π], radians.
    pub angle: f64,
    /// The angles of all twelve Euler sets, keyed by set name.
    pub euler: BTreeMap<String, [f64; 3]>,
    /// Sets for which the rotation is at a singular value of the second angle (the first
    /// angle was set to 0 there).
    pub euler_singular: Vec<String>,
}

/// Parses the values of `--values` for a representation into a rotation.
///
/// # Errors
/// Wrong number of values, non-finite values, or an input that is not a rotation.
pub fn parse_rotation(repr: Representation, values: &str) -> Result<Rotation3<f64>> {
    let parts: Vec<&str> = values.split(',').map(str::trim).collect();
    let n = repr.expected_values();
    if parts.len() != n {
        bail!(
            "--values needs {n} comma-separated values for this representation, got {}",
            parts.len()
        );
    }
    let v = parts
        .iter()
        .enumerate()
        .map(|(i, text)| match repr {
            Representation::Euler(_) => parse_angle(text),
            Representation::AxisAngle if i == 3 => parse_angle(text),
            _ => parse_finite(text),
        })
        .collect::<Result<Vec<f64>, String>>()
        .map_err(anyhow::Error::msg)?;
    let rotation = match repr {
        Representation::AxisAngle => {
            AxisAngle::new(v[3], Vector3::new(v[0], v[1], v[2]))?.to_rotation()
        }
        Representation::Quaternion => rotation_from_quaternion([v[0], v[1], v[2], v[3]])?.1,
        Representation::Matrix => {
            rotation_from_matrix(&Matrix3::from_row_slice(&v), MATRIX_TOLERANCE)
                .context("--values")?
        }
        Representation::Euler(set) => set.rotation([v[0], v[1], v[2]]),
    };
    Ok(rotation)
}

/// Every representation of one rotation.
#[must_use]
pub fn report(rotation: &Rotation3<f64>) -> RotationReport {
    let m = rotation.matrix();
    let aa = AxisAngle::from_rotation(rotation);
    let q = rotations::quaternion_from_matrix(m);
    let mut euler = BTreeMap::new();
    let mut euler_singular = Vec::new();
    for set in EulerSet::ALL {
        let angles = set.angles(rotation);
        if set.is_singular(angles, 1e-12) {
            euler_singular.push(set.to_string());
        }
        euler.insert(set.to_string(), angles);
    }
    RotationReport {
        matrix: [0, 1, 2].map(|i| [m[(i, 0)], m[(i, 1)], m[(i, 2)]]),
        quaternion: [q.scalar(), q.vector()[0], q.vector()[1], q.vector()[2]],
        axis: [aa.axis.x, aa.axis.y, aa.axis.z],
        angle: aa.angle,
        euler,
        euler_singular,
    }
}

/// Runs `rollstack rotation`.
///
/// # Errors
/// Bad input (see [`parse_rotation`]).
pub fn run(args: &RotationArgs) -> Result<()> {
    let repr = Representation::parse(&args.from)?;
    let rotation = parse_rotation(repr, &args.values)?;
    let rep = report(&rotation);
    if args.json {
        return print_json(&rep);
    }
    println!("matrix (row i: Eᵢ · R Eⱼ):");
    for row in rep.matrix {
        println!("  [{:>12.9} {:>12.9} {:>12.9}]", row[0], row[1], row[2]);
    }
    let [q0, q1, q2, q3] = rep.quaternion;
    println!("quaternion [q0, q1, q2, q3] = [{q0:.9}, {q1:.9}, {q2:.9}, {q3:.9}]");
    println!(
        "angle = {:.9} rad ({:.6}°), axis = [{:.9}, {:.9}, {:.9}]",
        rep.angle,
        rep.angle.to_degrees(),
        rep.axis[0],
        rep.axis[1],
        rep.axis[2]
    );
    println!("Euler angles (rad):");
    for (set, a) in &rep.euler {
        let flag = if rep.euler_singular.contains(set) {
            "  (singular: a1 set to 0)"
        } else {
            ""
        };
        println!(
            "  {set}: [{:>12.9}, {:>12.9}, {:>12.9}]{flag}",
            a[0], a[1], a[2]
        );
    }
    Ok(())
}
