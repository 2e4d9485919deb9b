//! The `rollstack` binary: parses the command line and reports errors in one line.

use clap::Parser;

fn main() -> std::process::ExitCode {
    let cli = rollstack_cli::Cli::parse();
    match rollstack_cli::run(cli) {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(err) => {
            // One clear line: the error and its causes, joined.
            eprintln!("error: {err:#}");
            std::process::ExitCode::FAILURE
        }
    }
}
