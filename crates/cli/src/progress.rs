//! Progress bars on stderr, shown only when stderr is a terminal (docs/architecture.md, Conventions).

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;

/// A progress bar of `len` units with a message; hidden when stderr is not a terminal,
/// so scripts and CI logs stay clean.
#[must_use]
pub fn bar(len: u64, message: &str) -> ProgressBar {
    let pb = ProgressBar::with_draw_target(Some(len), ProgressDrawTarget::hidden());
    if std::io::stderr().is_terminal() {
        pb.set_draw_target(ProgressDrawTarget::stderr());
        if let Ok(style) = ProgressStyle::with_template(
            "{msg:>12} [{elapsed_precise}] {wide_bar} {pos}/{len} (eta {eta})",
        ) {
            pb.set_style(style);
        }
    }
    pb.set_message(message.to_owned());
    pb
}
