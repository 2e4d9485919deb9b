//! The `rollstack` binary: parses the command line and reports errors in one line.

use rollstack_cli::output::remove_own_temps;

fn main() -> std::process::ExitCode {
    exit_quietly_on_stdout_errors();
    let cli = rollstack_cli::examples::parse();
    match rollstack_cli::run(cli) {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(err) => {
            remove_own_temps();
            if err.chain().any(is_broken_pipe) {
                return std::process::ExitCode::from(BROKEN_PIPE_STATUS);
            }
            // One clear line: the error and its causes, joined.
            eprintln!("error: {err:#}");
            // Failed rows (files written): a status a job array tells from a failed run.
            std::process::ExitCode::from(if err.is::<shards::RowsFailed>() { 3 } else { 1 })
        }
    }
}

/// The status of a shell tool whose output pipe was closed: 128 + SIGPIPE.
const BROKEN_PIPE_STATUS: u8 = 141;

/// Whether `e` is a write to a closed pipe.
fn is_broken_pipe(e: &(dyn std::error::Error + 'static)) -> bool {
    e.downcast_ref::<std::io::Error>()
        .is_some_and(|e| e.kind() == std::io::ErrorKind::BrokenPipe)
}

/// `println!` panics when stdout cannot be written. A closed pipe (`rollstack ... --json
/// | head`) is not an error of ours: the process ends the way a shell tool does (exit
/// status 141) instead of printing a panic. Any other failure (`> /dev/full`: no space
/// left) is a one-line error with exit status 1, not a panic's backtrace and 101.
/// Resetting the SIGPIPE handler would need `unsafe`, which the workspace forbids.
fn exit_quietly_on_stdout_errors() {
    let default_hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        let message = info
            .payload()
            .downcast_ref::<String>()
            .map(String::as_str)
            .or_else(|| info.payload().downcast_ref::<&str>().copied())
            .unwrap_or("");
        if message.contains("Broken pipe") {
            remove_own_temps();
            std::process::exit(BROKEN_PIPE_STATUS.into());
        }
        if let Some(cause) = message.strip_prefix("failed printing to stdout: ") {
            remove_own_temps();
            eprintln!("error: cannot write to stdout: {cause}");
            std::process::exit(1);
        }
        default_hook(info);
    }));
}
