//! `rollstack rotation`: convert one rotation between every representation. The numbers
//! and their text come from [`rotations::rotation_report`]; this module reads the flags
//! (docs/cli.md).

use crate::output::{ensure_dir, print_json, write_csv, write_run_json};
use anyhow::{bail, Context, Result};
use clap::Args;
use figures::rotations::draw_basis;
use input::text::{parse_finite, parse_rotation_angle};
use rotations::report::euler_round_trip;
use rotations::{rotation_report, EulerSet, Representation, Rotation3, MATRIX_INPUT_TOLERANCE};
use std::path::{Path, PathBuf};

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
    /// Directory for the twelve Euler sets with their round-trip errors (euler_angles.csv),
    /// the rotated basis (rotated_basis.png) and run.json; without it, nothing is written.
    #[arg(long)]
    pub out: Option<PathBuf>,
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
    let rotation = parse_rotation(repr, &args.values)?;
    let rep = rotation_report(&rotation);
    if let Some(dir) = &args.out {
        write_files(dir, &rotation, args)?;
    }
    if args.json {
        return print_json(&rep);
    }
    println!("{rep}");
    Ok(())
}

/// The files of `rotation --out`: every Euler set's angles (rad) and round-trip error
/// (rad), the rotated basis, and run.json.
fn write_files(dir: &Path, rotation: &Rotation3<f64>, args: &RotationArgs) -> Result<()> {
    ensure_dir(dir)?;
    let rows = EulerSet::ALL.iter().map(|&set| {
        let trip = euler_round_trip(set, rotation);
        let [a1, a2, a3] = trip.angles;
        std::iter::once(set.to_string())
            .chain([a1, a2, a3, trip.error].iter().map(f64::to_string))
            .collect::<Vec<String>>()
    });
    let header = ["set", "a1_rad", "a2_rad", "a3_rad", "roundtrip_error_rad"];
    write_csv(&dir.join("euler_angles.csv"), &header, rows)?;
    draw_basis(&dir.join("rotated_basis.png"), rotation)?;
    let inputs = serde_json::json!({"from": args.from, "values": args.values});
    write_run_json(dir, "rotation", &inputs, &serde_json::json!({}))
}
