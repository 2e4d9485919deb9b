//! `rollstack tour --out DIR`: the main job.
//!
//! Runs the headline result of every system with built-in defaults, writes CSV and PNG
//! files into DIR, an `index.html` that shows them, and prints a short summary. Each
//! system contributes one [`Section`] from its own module; a section that fails is
//! reported in the page and the summary, the others still run, and the command then
//! exits non-zero.

mod blocks;
mod cylinder;
mod nsga;
mod rotations;
mod sphere;

use crate::output::{ensure_dir, write_atomic};
use anyhow::Result;
use clap::Args;
pub use figures::page::{render_html, Block, Section};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Arguments of `rollstack tour`.
#[derive(Debug, Args)]
pub struct TourArgs {
    /// Directory to write CSV, PNG and index.html into (created if missing).
    #[arg(long, default_value = "tour")]
    pub out: PathBuf,
    /// Run only these sections (comma-separated names, e.g. `rotations,sphere`).
    #[arg(long, value_delimiter = ',')]
    pub only: Vec<String>,
}

/// A function that produces one section, writing its files into the directory given.
pub type SectionFn = fn(&Path) -> Result<Section>;

/// The sections of the tour, in page order. Each system adds its entry here.
const SECTIONS: &[(&str, SectionFn)] = &[
    ("rotations", rotations::section),
    ("sphere", sphere::section),
    ("nsga", nsga::section),
    ("cylinder", cylinder::section),
    ("blocks", blocks::section),
];

/// Runs the tour.
///
/// # Errors
/// When the output directory cannot be written, or when any section failed (after
/// all sections ran and the page was written).
pub fn run(args: &TourArgs) -> Result<()> {
    let known: Vec<&str> = SECTIONS.iter().map(|(name, _)| *name).collect();
    if let Some(bad) = args.only.iter().find(|o| !known.contains(&o.as_str())) {
        anyhow::bail!(
            "unknown tour section '{bad}' (sections: {})",
            known.join(", ")
        );
    }
    ensure_dir(&args.out)?;
    let mut done = Vec::new();
    let mut failures = Vec::new();
    let selected = SECTIONS
        .iter()
        .filter(|(name, _)| args.only.is_empty() || args.only.iter().any(|o| o == name));
    for (name, make) in selected {
        let dir = args.out.join(name);
        ensure_dir(&dir)?;
        let start = Instant::now();
        let outcome = make(&dir);
        let seconds = start.elapsed().as_secs_f64();
        match outcome {
            Ok(section) => {
                println!("== {} ({seconds:.2} s)", section.title);
                for line in &section.summary {
                    println!("   {line}");
                }
                done.push(((*name).to_owned(), section));
            }
            Err(e) => {
                println!("== {name}: FAILED: {e:#}");
                failures.push(format!("{name}: {e:#}"));
            }
        }
    }
    let index = args.out.join("index.html");
    write_atomic(&index, render_html(&done, &failures).as_bytes())?;
    println!("wrote {}", index.display());
    anyhow::ensure!(
        failures.is_empty(),
        "{} tour section(s) failed",
        failures.len()
    );
    Ok(())
}
