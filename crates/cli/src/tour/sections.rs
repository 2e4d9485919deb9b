//! What the tour runs: `crates/cli/tour.toml`, compiled into the binary. For each system,
//! the `rollstack` commands that reproduce its headline results, each with what it shows
//! and the thesis's numbers to compare with.

use anyhow::{Context, Result};
use serde::Deserialize;

/// The tour's content as written.
pub const TOUR_TOML: &str = include_str!("../../tour.toml");

/// One step of a tour section: a `rollstack` command line, run as a user would run it.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Step {
    /// The arguments after `rollstack`, separated by spaces (none contains a space).
    pub args: String,
    /// The directory, below the section's, that the command writes into (`--out`); empty
    /// for a command that only prints.
    #[serde(default)]
    pub out: String,
    /// What the step shows and the thesis's numbers to compare with (may be empty).
    #[serde(default)]
    pub text: String,
    /// Whether docs/cli.md shows this very command's output as a transcript, run by its
    /// test (`crates/cli/tests/cli_doc.rs`): only then may `text` quote what the run
    /// prints (which ω fail, how many motions), since that quote is then checked.
    #[serde(default)]
    pub checked: bool,
}

/// One section of the tour: a system and the commands that show it.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SectionPlan {
    /// The section's directory and its name for `--only`.
    pub name: String,
    /// Its heading.
    pub title: String,
    /// Its commands, in page order.
    #[serde(rename = "step")]
    pub steps: Vec<Step>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Tour {
    section: Vec<SectionPlan>,
}

/// The sections of the tour, in page order.
///
/// # Errors
/// When `tour.toml` does not read (a test keeps it readable).
pub fn sections() -> Result<Vec<SectionPlan>> {
    Ok(toml::from_str::<Tour>(TOUR_TOML)
        .context("the tour's content (tour.toml)")?
        .section)
}
