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
pub use figures::page::{render_html, Block, PageHeader, Section};
use std::path::{Path, PathBuf};
use std::time::{Instant, SystemTime};

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
            Ok(mut section) => {
                link_every_file(&dir, &mut section)?;
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
    let header = PageHeader {
        version: env!("CARGO_PKG_VERSION").to_owned(),
        commit: Some(env!("ROLLSTACK_COMMIT").to_owned()).filter(|c| !c.is_empty()),
        date: utc_date(SystemTime::now()),
        command: std::iter::once("rollstack".to_owned())
            .chain(std::env::args().skip(1))
            .collect::<Vec<_>>()
            .join(" "),
    };
    write_atomic(&index, render_html(&header, &done, &failures).as_bytes())?;
    println!("wrote {}", index.display());
    anyhow::ensure!(
        failures.is_empty(),
        "{} tour section(s) failed",
        failures.len()
    );
    Ok(())
}

/// Adds a link to every file in `dir` (and below) that the section's blocks do not show,
/// so that the page accounts for everything the tour wrote.
fn link_every_file(dir: &Path, section: &mut Section) -> Result<()> {
    let mut files = Vec::new();
    list_files(dir, dir, &mut files)?;
    files.sort();
    let linked: Vec<String> = section
        .linked_files()
        .iter()
        .map(|f| (*f).to_owned())
        .collect();
    for file in files.into_iter().filter(|f| !linked.contains(f)) {
        let what = match file.rsplit('.').next() {
            Some("csv") => "data",
            Some("png") => "figure",
            Some("gif") => "animation",
            Some("json") => "the run's record: command, inputs, version, timings",
            _ => "file",
        };
        section.blocks.push(Block::data(file, what));
    }
    Ok(())
}

/// The files below `dir`, as paths relative to `root` with `/` separators.
fn list_files(root: &Path, dir: &Path, out: &mut Vec<String>) -> Result<()> {
    for entry in std::fs::read_dir(dir)? {
        let path = entry?.path();
        if path.is_dir() {
            list_files(root, &path, out)?;
        } else if let Ok(rel) = path.strip_prefix(root) {
            let name = rel.to_string_lossy().replace('\\', "/");
            if !name
                .rsplit('/')
                .next()
                .is_some_and(|n| n.starts_with(".tmp-"))
            {
                out.push(name);
            }
        }
    }
    Ok(())
}

/// The UTC calendar date of `t` as `YYYY-MM-DD` (the proleptic Gregorian calendar, from
/// the day count since 1970-01-01).
fn utc_date(t: SystemTime) -> String {
    let secs = t
        .duration_since(SystemTime::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs());
    let days = i64::try_from(secs / 86_400).unwrap_or(0);
    // Shift the epoch to 0000-03-01 so that leap days fall at the end of a year.
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    format!("{year:04}-{month:02}-{day:02}")
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    #[test]
    fn dates_from_the_day_count() {
        let at = |secs: u64| utc_date(SystemTime::UNIX_EPOCH + Duration::from_secs(secs));
        assert_eq!(at(0), "1970-01-01");
        assert_eq!(at(951_782_400), "2000-02-29");
        assert_eq!(at(1_795_564_800 + 86_399), "2026-11-25");
    }
}
