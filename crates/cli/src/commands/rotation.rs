//! `rollstack rotation`: convert one rotation between every representation. The numbers
//! and their text come from [`rotations::rotation_report`]; this module reads the flags
//! (docs/cli.md).

use crate::output::print_json;
use anyhow::{bail, Context, Result};
use clap::Args;
use input::text::{parse_finite, parse_rotation_angle};
use rotations::{rotation_report, Representation, Rotation3, MATRIX_INPUT_TOLERANCE};

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

/// Reads the text of `--values` for a representation (angles may be written `90deg` or
/// `3pi/2`) and builds the rotation ([`Representation::rotation`]).
///
/// # Errors
/// Wrong number of values, non-finite values, or an input that is not a rotation.
pub fn parse_rotation(repr: Representation, values: &str) -> Result<Rotation3<f64>> {
    let parts: Vec<&str> = values.split(',').map(str::trim).collect();
    let n = repr.value_count();
    if parts.len() != n {
        bail!(
            "--values needs {n} comma-separated values for this representation, got {}",
            parts.len()
        );
    }
    let v = parts
        .iter()
        .enumerate()
        .map(|(i, text)| {
            if repr.is_angle(i) {
                parse_rotation_angle(text)
            } else {
                parse_finite(text)
            }
        })
        .collect::<Result<Vec<f64>, String>>()
        .map_err(anyhow::Error::msg)?;
    let rotation = repr.rotation(&v, MATRIX_INPUT_TOLERANCE);
    // A matrix that is not a rotation is a problem of the whole flag, not of one value.
    if repr == Representation::Matrix {
        rotation.context("--values")
    } else {
        Ok(rotation?)
    }
}

/// Runs `rollstack rotation`.
///
/// # Errors
/// Bad input (see [`parse_rotation`]).
pub fn run(args: &RotationArgs) -> Result<()> {
    let repr = Representation::from_name(&args.from)?;
    let rep = rotation_report(&parse_rotation(repr, &args.values)?);
    if args.json {
        return print_json(&rep);
    }
    println!("{rep}");
    Ok(())
}
