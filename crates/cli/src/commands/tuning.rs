//! The hidden `--tuning NAME=VALUE` flag of the block and cylinder commands: one of
//! nsga's options set by name (`nsga::Options::set`), to measure what a constant or a
//! stage of the step's policy is worth with one binary
//! (`scripts/reference_workload.py BIN --variant NAME=VALUE`).

use anyhow::Result;
use clap::Args;

/// `--tuning NAME=VALUE`, repeatable.
#[derive(Debug, Clone, Default, Args)]
pub struct TuningArgs {
    /// Set one of nsga's options by its name, `NAME=VALUE` (repeatable): a measured
    /// constant (`tuning.stall_iterations=4`), a stage (`policy.max_halvings=0`,
    /// `newton.predict_start=false`) or any other option (`newton.max_iter=20`). For
    /// measuring (scripts/reference_workload.py); the names are those of
    /// `nsga::Options` and its groups.
    #[arg(long = "tuning", value_name = "NAME=VALUE", hide = true)]
    pub assignments: Vec<String>,
}

impl TuningArgs {
    /// Sets the options named on the command line in `options`.
    ///
    /// # Errors
    /// An assignment that names no option, or whose value does not fit it.
    pub fn apply(&self, options: &mut ::nsga::Options) -> Result<()> {
        for a in &self.assignments {
            options
                .set(a)
                .map_err(|e| anyhow::anyhow!("--tuning: {e}"))?;
        }
        Ok(())
    }
}
