//! `usar`: semi-autonomous robotic urban search and rescue — scenes, planners, exploration,
//! experiments. This binary only parses arguments and delegates to the library crates.

mod cli;
mod commands;
mod failure;
mod progress;
mod record_file;
mod runners;
mod scene_source;

use clap::Parser;
use std::process::ExitCode;

fn main() -> ExitCode {
    restore_sigpipe();
    let args = match cli::Cli::try_parse() {
        Ok(args) => args,
        Err(e) => return argument_error(e),
    };
    usar_world::limits::set_limits(args.limits.limits());
    match commands::run(args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(failure) => {
            eprintln!("usar: {:#}", failure.error);
            ExitCode::from(failure.exit_code())
        }
    }
}

/// Help and version go to stdout as clap prints them; a wrong argument is one line on stderr,
/// as every other bad input is, and exit code 2.
fn argument_error(e: clap::Error) -> ExitCode {
    use clap::error::ErrorKind;
    if matches!(
        e.kind(),
        ErrorKind::DisplayHelp
            | ErrorKind::DisplayVersion
            | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand
    ) {
        let _ = e.print();
        return ExitCode::from(if e.use_stderr() { 2 } else { 0 });
    }
    // clap's message, without its usage block, joined onto one line.
    let text = e.render().to_string();
    let message: Vec<&str> = text
        .lines()
        .map(str::trim)
        .take_while(|l| !l.starts_with("Usage:") && !l.starts_with("For more information"))
        .filter(|l| !l.is_empty())
        .collect();
    let message = message.join(" ");
    let message = message.strip_prefix("error: ").unwrap_or(&message);
    eprintln!("usar: {message} (see usar --help)");
    ExitCode::from(2)
}

/// Output into a closed pipe (`usar campaign list | head`) ends the program quietly, as it does
/// for other Unix tools, instead of a panic in `println!` (Rust ignores SIGPIPE by default).
#[cfg(unix)]
fn restore_sigpipe() {
    // SAFETY: called first thing in main, before any thread exists; SIG_DFL is a valid handler.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}

#[cfg(not(unix))]
fn restore_sigpipe() {}
