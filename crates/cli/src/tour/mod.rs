//! `rollstack tour --out DIR`: the main job.
//!
//! Runs the headline results of every system as the `rollstack` commands that reproduce
//! them ([`sections()`], from `tour.toml`), each writing into its own directory below DIR, and
//! writes an `index.html` that shows every command, what it printed and every file it
//! wrote. A command that fails is reported in the page and the summary, the others still
//! run, and the tour then exits non-zero.

mod sections;

use crate::output::{ensure_dir, write_atomic};
use anyhow::{Context, Result};
use clap::Args;
pub use figures::page::{render_html, Block, PageHeader, Section};
pub use sections::{sections, SectionPlan, Step, TOUR_TOML};
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

/// Runs the tour.
///
/// # Errors
/// When this is not the `rollstack` executable, when the output directory cannot be
/// written, or when any command failed (after all ran and the page was written).
pub fn run(args: &TourArgs) -> Result<()> {
    let plans = sections()?;
    let known: Vec<&str> = plans.iter().map(|s| s.name.as_str()).collect();
    if let Some(bad) = args.only.iter().find(|o| !known.contains(&o.as_str())) {
        anyhow::bail!(
            "unknown tour section '{bad}' (sections: {})",
            known.join(", ")
        );
    }
    let exe = rollstack_executable()?;
    ensure_dir(&args.out)?;
    let mut done = Vec::new();
    let mut failures = Vec::new();
    let selected = plans
        .iter()
        .filter(|s| args.only.is_empty() || args.only.contains(&s.name));
    for plan in selected {
        let dir = args.out.join(&plan.name);
        ensure_dir(&dir)?;
        println!("== {}", plan.title);
        let section = run_section(&exe, plan, &dir, &mut failures)?;
        done.push((plan.name.clone(), section));
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
        "{} tour command(s) failed",
        failures.len()
    );
    Ok(())
}

/// The running program, which the tour calls for each step: the tour is the commands
/// a user would type, run the same way.
fn rollstack_executable() -> Result<PathBuf> {
    let exe = std::env::current_exe().context("cannot locate the running executable")?;
    let is_rollstack = exe
        .file_stem()
        .is_some_and(|s| s.to_string_lossy().starts_with("rollstack"));
    anyhow::ensure!(
        is_rollstack,
        "the tour runs rollstack's commands and must be started as `rollstack tour`"
    );
    Ok(exe)
}

/// Runs the steps of one section into `dir`: the page shows each step's text, its
/// command and output, and every file it wrote. A failed step is recorded in `failures`
/// and on the page; the later steps still run.
fn run_section(
    exe: &Path,
    plan: &SectionPlan,
    dir: &Path,
    failures: &mut Vec<String>,
) -> Result<Section> {
    let mut blocks = Vec::new();
    for step in &plan.steps {
        if !step.text.is_empty() {
            blocks.push(Block::Text(step.text.clone()));
        }
        let start = Instant::now();
        let (line, output, ok) = run_step(exe, step, dir)?;
        println!("$ {line}   ({:.1} s)", start.elapsed().as_secs_f64());
        for l in output.lines() {
            println!("   {l}");
        }
        if !ok {
            failures.push(format!("{}: `{line}` failed", plan.name));
        }
        blocks.push(Block::Command { line, output });
        if !step.out.is_empty() {
            link_files(dir, &step.out, &mut blocks)?;
        }
    }
    Ok(Section {
        title: plan.title.clone(),
        blocks,
    })
}

/// Runs one step: its command line as shown, what it printed (stdout, then stderr), and
/// whether it succeeded.
fn run_step(exe: &Path, step: &Step, dir: &Path) -> Result<(String, String, bool)> {
    let mut argv: Vec<String> = step.args.split_whitespace().map(str::to_owned).collect();
    if !step.out.is_empty() {
        argv.push("--out".into());
        argv.push(dir.join(&step.out).to_string_lossy().into_owned());
    }
    let line = format!("rollstack {}", argv.join(" "));
    let out = std::process::Command::new(exe)
        .args(&argv)
        .output()
        .with_context(|| format!("cannot run `{line}`"))?;
    let mut text = String::from_utf8_lossy(&out.stdout).into_owned();
    text.push_str(&String::from_utf8_lossy(&out.stderr));
    Ok((line, text, out.status.success()))
}

/// Adds every file the step wrote into `dir/sub` to the page: pictures shown, data linked.
fn link_files(dir: &Path, sub: &str, blocks: &mut Vec<Block>) -> Result<()> {
    let mut files = Vec::new();
    let root = dir.join(sub);
    if root.is_dir() {
        list_files(&root, &root, &mut files)?;
    }
    files.sort();
    for file in files {
        let path = format!("{sub}/{file}");
        blocks.push(match file.rsplit('.').next() {
            Some("png" | "gif") => Block::image(path, file),
            Some("csv") => Block::data(path, "data"),
            Some("json") => {
                Block::data(path, "the run's record: command, inputs, version, timings")
            }
            _ => Block::data(path, "file"),
        });
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
