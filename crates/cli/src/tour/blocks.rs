//! Tour section: the block stack (Ch. 4, App. I): the Leaning Tower of Lire in its
//! harmonic maximum-overhang configuration (ERRATA 16) and Painlevé's paradoxes for one
//! block (Figure I.2, ERRATA 18). The simulations join when the nsga stepper is wired in.

use super::{Block, Section};
use crate::commands::blocks::{painleve_report, plot_stack, write_painleve_files};
use anyhow::Result;
use blockstack::scenarios::{lire, maximum_overhang, Perturbation};
use std::path::Path;

/// Builds the section.
///
/// # Errors
/// When a file cannot be written.
pub fn section(dir: &Path) -> Result<Section> {
    let mut summary = Vec::new();
    let mut blocks = Vec::new();

    let scene = lire(4, Perturbation::None)?;
    let q = scene.initial_coordinates();
    let contacts = scene.contacts(0.0, &q, &vec![0.0; q.len()]);
    summary.push(format!(
        "Lire tower, 4 blocks w = 1: maximum overhang {:.6} = 25/24 w (ERRATA 16; (4.3.1) as printed gives w/2); largest |gap| at rest {:.1e}",
        maximum_overhang(4, 1.0),
        contacts.normals.iter().flatten().take(8).map(|r| r.value.abs()).fold(0.0, f64::max)
    ));
    plot_stack(
        &dir.join("blocks_lire_overhang.png"),
        &scene,
        &q,
        0.0,
        "Figure 4.3: maximum overhang, offsets w/8, w/6, w/4, w/2",
    )?;
    blocks.push(Block::Image {
        file: "blocks_lire_overhang.png".into(),
        caption: "The four-block Leaning Tower of Lire on a fixed table (black) in the harmonic maximum-overhang configuration (ERRATA 16).".into(),
    });

    let report = painleve_report(0.5, 0.2)?;
    write_painleve_files(dir, 0.5, 3.0, 121, &report)?;
    summary.push(format!(
        "Painlevé (App. I, ERRATA 18): least μ_d = {:.6} (4/3) at ϑ = ±{:.3}°; w/h = 0.5: ϑ ∈ ({:.3}°, {:.3}°)",
        report.mu_min,
        report.theta_at_mu_min.abs().to_degrees(),
        report.theta_min.to_degrees(),
        report.theta_max.to_degrees()
    ));
    let lc = &report.line_contact.sliding_right[0];
    summary.push(format!(
        "line contact (I.2.10), w/h = 0.5, μ_d = 0.2, sliding right: n_R = {:.4}, n_L = {:.4}",
        lc.n_right, lc.n_left
    ));
    blocks.push(Block::Image {
        file: "painleve.png".into(),
        caption: "Figure I.2 for w/h = 0.5: (a) admissible angles (I.1.3); (b) where b ≤ 0 (paradox) per slip direction, faded outside the admissible range; i, ii: least μ_d = 4/3.".into(),
    });
    blocks.push(Block::Data {
        file: "painleve_b_grid.csv".into(),
        description: "b(ϑ, ±1, μ_d) on a 121 × 121 grid".into(),
    });
    Ok(Section {
        title: "Block stack (Ch. 4, App. I)".into(),
        summary,
        blocks,
    })
}
