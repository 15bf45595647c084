//! `usar`: semi-autonomous robotic urban search and rescue — scenes, planners, exploration,
//! experiments. This binary only parses arguments and delegates to the library crates.

mod cli;
mod commands;
mod failure;
mod progress;
mod runners;
mod scene_source;
mod team_setup;

use clap::Parser;
use std::process::ExitCode;

fn main() -> ExitCode {
    restore_sigpipe();
    let args = cli::Cli::parse();
    usar_world::limits::set_limits(args.limits.limits());
    match commands::run(args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(failure) => {
            eprintln!("usar: {:#}", failure.error);
            ExitCode::from(failure.exit_code())
        }
    }
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
