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
use std::fmt::Write as _;
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

/// What one system shows in the tour.
#[derive(Debug, Default)]
pub struct Section {
    /// Heading in the page.
    pub title: String,
    /// A few lines for the terminal summary and the page (headline numbers).
    pub summary: Vec<String>,
    /// HTML blocks (tables, images), in order. Paths are relative to the tour directory.
    pub blocks: Vec<Block>,
}

/// One piece of a section's page.
#[derive(Debug)]
pub enum Block {
    /// A paragraph of plain text.
    Text(String),
    /// A PNG written into the tour directory, with a caption.
    Image {
        /// File name relative to the tour directory.
        file: String,
        /// Caption under the image.
        caption: String,
    },
    /// A table with a header row.
    Table {
        /// Column names.
        header: Vec<String>,
        /// Cells, row by row.
        rows: Vec<Vec<String>>,
    },
    /// A link to a data file (CSV) in the tour directory.
    Data {
        /// File name relative to the tour directory.
        file: String,
        /// What it holds.
        description: String,
    },
}

impl Block {
    /// A table from its column names and rows of cells.
    #[must_use]
    pub fn table(header: &[&str], rows: Vec<Vec<String>>) -> Self {
        let header = header.iter().map(|s| (*s).to_owned()).collect();
        Self::Table { header, rows }
    }

    /// An image with its caption.
    #[must_use]
    pub fn image(file: impl Into<String>, caption: impl Into<String>) -> Self {
        Self::Image {
            file: file.into(),
            caption: caption.into(),
        }
    }

    /// A link to a data file with what it holds.
    #[must_use]
    pub fn data(file: impl Into<String>, description: impl Into<String>) -> Self {
        Self::Data {
            file: file.into(),
            description: description.into(),
        }
    }
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

fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

fn render_html(sections: &[(String, Section)], failures: &[String]) -> String {
    let mut h = String::from(
        "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>rollstack tour</title>\n\
         <style>body{font-family:sans-serif;max-width:1100px;margin:auto;padding:1em}\
         table{border-collapse:collapse}td,th{border:1px solid #bbb;padding:3px 8px;text-align:right}\
         img{max-width:100%;border:1px solid #ddd}figure{margin:1em 0}</style></head><body>\n\
         <h1>rollstack tour</h1>\n<p>Headline results of every system, computed with built-in \
         defaults by <code>rollstack tour</code>. Equation numbers refer to Honein (2024).</p>\n<ul>",
    );
    for (name, s) in sections {
        let _ = write!(h, "<li><a href=\"#{name}\">{}</a></li>", escape(&s.title));
    }
    h.push_str("</ul>\n");
    for f in failures {
        let _ = writeln!(h, "<p style=\"color:#b00\">Failed: {}</p>", escape(f));
    }
    for (name, s) in sections {
        let _ = writeln!(h, "<h2 id=\"{name}\">{}</h2>", escape(&s.title));
        if !s.summary.is_empty() {
            h.push_str("<ul>");
            for line in &s.summary {
                let _ = write!(h, "<li>{}</li>", escape(line));
            }
            h.push_str("</ul>\n");
        }
        for b in &s.blocks {
            render_block(&mut h, name, b);
        }
    }
    h.push_str("</body></html>\n");
    h
}

fn render_block(h: &mut String, dir: &str, block: &Block) {
    match block {
        Block::Text(t) => {
            let _ = writeln!(h, "<p>{}</p>", escape(t));
        }
        Block::Image { file, caption } => {
            let _ = writeln!(
                h,
                "<figure><img src=\"{dir}/{}\" alt=\"{}\"><figcaption>{}</figcaption></figure>",
                escape(file),
                escape(caption),
                escape(caption)
            );
        }
        Block::Table { header, rows } => {
            h.push_str("<table><tr>");
            for c in header {
                let _ = write!(h, "<th>{}</th>", escape(c));
            }
            h.push_str("</tr>");
            for r in rows {
                h.push_str("<tr>");
                for c in r {
                    let _ = write!(h, "<td>{}</td>", escape(c));
                }
                h.push_str("</tr>");
            }
            h.push_str("</table>\n");
        }
        Block::Data { file, description } => {
            let _ = writeln!(
                h,
                "<p>Data: <a href=\"{dir}/{}\">{}</a> ({})</p>",
                escape(file),
                escape(file),
                escape(description)
            );
        }
    }
}
