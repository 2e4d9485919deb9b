//! Tour section: the rotation tools on one rotation, the holonomy (2.4.10) of the thesis.
//! The numbers come from [`rotations::report`].

use super::{Block, Section};
use crate::output::write_csv;
use anyhow::Result;
use figures::rotations::draw_basis;
use holonomy::studies::examples::printed_holonomy_2_4_10;
use rotations::report::euler_round_trip;
use rotations::{AxisAngle, EulerSet, Vector3};
use std::path::Path;

/// Builds the section: a table of four Euler decompositions, all twelve as CSV, and a
/// picture of the rotated basis.
///
/// # Errors
/// When a file cannot be written.
pub fn section(dir: &Path) -> Result<Section> {
    // ψ = 62.7042°, s = −0.389418 A1 − 0.921061 A3: the holonomy printed in (2.4.10).
    let r = printed_holonomy_2_4_10()?;
    let mut rows = Vec::new();
    let mut worst: f64 = 0.0;
    for set in EulerSet::ALL {
        let trip = euler_round_trip(set, &r);
        worst = worst.max(trip.error);
        let [a1, a2, a3] = trip.angles.map(f64::to_degrees);
        rows.push(vec![
            set.to_string(),
            format!("{a1:.6}"),
            format!("{a2:.6}"),
            format!("{a3:.6}"),
            format!("{:.1e}", trip.error),
        ]);
    }
    let header = ["set", "a1_deg", "a2_deg", "a3_deg", "roundtrip_error_rad"];
    write_csv(&dir.join("euler_angles.csv"), &header, &rows)?;
    draw_basis(&dir.join("rotated_basis.png"), &r)?;

    // A rotation about E3 sits at the singular value a2 = 0 of the 3-1-3 set.
    let about_e3 = AxisAngle::new(0.9, Vector3::z())?.to_rotation();
    let singular = euler_round_trip(EulerSet::from_name("3-1-3")?, &about_e3);

    let aa = AxisAngle::from_rotation(&r);
    Ok(Section {
        title: "Rotations: one rotation in every representation".into(),
        summary: vec![
            format!(
                "R(ψ = {:.4}°, s = [{:.6}, {:.6}, {:.6}]) from (2.4.10): 12 Euler sets, worst round-trip error {worst:.1e} rad",
                aa.angle.to_degrees(),
                aa.axis.x,
                aa.axis.y,
                aa.axis.z
            ),
            format!(
                "singular 3-1-3 case (0.9 rad about E3): angles [{:.3}, {:.3}, {:.3}], error {:.1e} rad",
                singular.angles[0], singular.angles[1], singular.angles[2], singular.error
            ),
        ],
        blocks: vec![
            Block::Text(
                "The holonomy (2.4.10) of the rolling sphere, decomposed into the four Euler sets \
                 used for path planning in §2.5 (angles in degrees). Every set reproduces the \
                 rotation to round-off; the error is the angle of R_targetᵀ R(a1, a2, a3)."
                    .into(),
            ),
            Block::Table {
                header: header.iter().map(|s| (*s).to_owned()).collect(),
                rows: rows
                    .iter()
                    .filter(|r| ["3-1-3", "3-2-3", "3-2-1", "3-1-2"].contains(&r[0].as_str()))
                    .cloned()
                    .collect(),
            },
            Block::Data { file: "euler_angles.csv".into(), description: "all twelve Euler sets".into() },
            Block::Image {
                file: "rotated_basis.png".into(),
                caption: "The fixed basis E1, E2, E3 (grey) and the rotated basis eᵢ = R Eᵢ (colour), with the axis of rotation (black)".into(),
            },
        ],
    })
}
