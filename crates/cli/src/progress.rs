//! Progress on stderr, shown only when stderr is a terminal (docs/architecture.md,
//! Conventions): a bar over the rows of a sweep, a bar over model time for one run, a
//! spinner for work of unknown length, and the one line a resumed sweep always prints.

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::path::Path;

/// A progress bar of `len` units with a message; hidden when stderr is not a terminal,
/// so scripts and CI logs stay clean.
#[must_use]
pub fn bar(len: u64, message: &str) -> ProgressBar {
    bar_when(len, message, true)
}

/// [`bar`], drawn only when `wanted` (not with `--json`).
#[must_use]
pub fn bar_when(len: u64, message: &str, wanted: bool) -> ProgressBar {
    styled(
        Some(len),
        message,
        "{msg:>12} [{elapsed_precise}] {wide_bar} {pos}/{len} (eta {eta})",
        wanted,
    )
}

/// A line showing that work of unknown length is alive: a spinner, the elapsed time and
/// `message` (set another with `set_message` as the work moves on); drawn when `wanted`
/// (not with `--json`) and stderr is a terminal.
#[must_use]
pub fn busy(message: &str, wanted: bool) -> ProgressBar {
    let pb = styled(None, message, "{spinner} [{elapsed_precise}] {msg}", wanted);
    if !pb.is_hidden() {
        pb.enable_steady_tick(std::time::Duration::from_millis(200));
    }
    pb
}

/// Units of the bar of one run: its model time in thousandths of `t_end`.
const RUN_UNITS: u64 = 1000;

/// The progress of one time-stepping run over model time [0, `t_end`], drawn on stderr
/// when `wanted` (not with `--json`) and stderr is a terminal.
#[derive(Debug)]
pub struct RunProgress {
    bar: ProgressBar,
    t_end: f64,
}

impl RunProgress {
    /// A bar named `message` for a run to `t_end`.
    #[must_use]
    pub fn new(message: &str, t_end: f64, wanted: bool) -> Self {
        let template = "{msg:>12} [{elapsed_precise}] {wide_bar} {percent:>3}% of t (eta {eta})";
        Self {
            bar: styled(Some(RUN_UNITS), message, template, wanted),
            t_end,
        }
    }

    /// The run has reached model time `t`.
    pub fn at(&self, t: f64) {
        let done = if self.t_end > 0.0 {
            t / self.t_end
        } else {
            1.0
        };
        #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
        self.bar
            .set_position((done.clamp(0.0, 1.0) * RUN_UNITS as f64) as u64);
    }

    /// The run is over: the bar is cleared, so that the summary follows on a clean line.
    pub fn finish(&self) {
        self.bar.finish_and_clear();
    }
}

/// Says on stderr, terminal or not, that a sweep into `dir` resumed: `reused` of its
/// `total` rows were read back from the row log, the others are computed now.
pub fn resumed(dir: &Path, reused: usize, total: usize) {
    eprintln!(
        "resumed the sweep in {}: {reused} of {total} rows reused from its row log, {} to compute",
        dir.display(),
        total - reused
    );
}

/// A bar of `len` units (None: unknown) drawn with `template` when `wanted` and stderr
/// is a terminal, hidden otherwise.
fn styled(len: Option<u64>, message: &str, template: &str, wanted: bool) -> ProgressBar {
    let pb = ProgressBar::with_draw_target(len, ProgressDrawTarget::hidden());
    if wanted && std::io::stderr().is_terminal() {
        pb.set_draw_target(ProgressDrawTarget::stderr());
        if let Ok(style) = ProgressStyle::with_template(template) {
            pb.set_style(style);
        }
    }
    pb.set_message(message.to_owned());
    pb
}
