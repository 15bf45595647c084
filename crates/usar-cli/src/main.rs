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
    let args = cli::Cli::parse();
    match commands::run(args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(failure) => {
            eprintln!("usar: {:#}", failure.error);
            ExitCode::from(failure.exit_code())
        }
    }
}
