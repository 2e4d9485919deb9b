//! The `rollstack` binary: parses the command line and reports errors in one line.

fn main() -> std::process::ExitCode {
    exit_quietly_on_broken_pipe();
    let cli = rollstack_cli::examples::parse();
    match rollstack_cli::run(cli) {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(err) => {
            // One clear line: the error and its causes, joined.
            eprintln!("error: {err:#}");
            // Failed rows (files written): a status a job array tells from a failed run.
            std::process::ExitCode::from(if err.is::<shards::RowsFailed>() { 3 } else { 1 })
        }
    }
}

/// `rollstack ... --json | head` closes stdout early; Rust then panics inside `println!`.
/// A closed pipe is not an error of ours, so end the process the way a shell tool does
/// (exit status 141 = 128 + SIGPIPE) instead of printing a panic. Resetting the SIGPIPE
/// handler would need `unsafe`, which the workspace forbids.
fn exit_quietly_on_broken_pipe() {
    let default_hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        let message = info
            .payload()
            .downcast_ref::<String>()
            .map(String::as_str)
            .or_else(|| info.payload().downcast_ref::<&str>().copied())
            .unwrap_or("");
        if message.contains("Broken pipe") {
            std::process::exit(141);
        }
        default_hook(info);
    }));
}
