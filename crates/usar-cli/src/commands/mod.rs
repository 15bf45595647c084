//! One module per command; each turns parsed arguments into library calls and prints the result
//! (text, or JSON with `--json`).

mod bench;
mod btm;
mod campaign;
pub mod console;
mod demo;
mod explore;
mod logs;
mod maxq;
mod mission;
mod plan;
mod ros2;
mod scene;
mod segment;
mod slurm;
mod team;

use crate::cli::{Cli, Command};
use crate::failure::CmdResult;

pub fn run(cli: Cli) -> CmdResult {
    match cli.command {
        Command::Scene(cmd) => scene::run(cmd),
        Command::Plan(args) => plan::run(args),
        Command::Explore(args) => explore::run(args),
        Command::Team(cmd) => team::run(cmd),
        Command::Mission(cmd) => mission::run(cmd),
        Command::Demo(args) => demo::run(args),
        Command::Bench(args) => bench::run(args),
        Command::Campaign(cmd) => campaign::run(cmd),
        Command::Maxq(cmd) => maxq::run(cmd),
        Command::Btm(cmd) => btm::run(cmd),
        Command::Console(args) => console::run(args),
        Command::Log(cmd) => logs::import(cmd),
        Command::Map(cmd) => logs::map(cmd),
        Command::Ros2(cmd) => ros2::run(cmd),
    }
}

/// Prints a value as pretty JSON on stdout.
pub fn print_json(value: &impl serde::Serialize) -> CmdResult {
    println!("{}", serde_json::to_string_pretty(value)?);
    Ok(())
}
