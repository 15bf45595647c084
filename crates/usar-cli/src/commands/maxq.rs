//! `usar maxq`: paper 000's hierarchical reinforcement learning.

use super::print_json;
use crate::cli::{MaxqCommand, MaxqTaxiArgs};
use crate::failure::{CmdResult, InputContext, bad_input};
use usar_maxq::taxi::{TaxiConfig, run_taxi};
use usar_plot::{LineChart, Series};

pub fn run(cmd: MaxqCommand) -> CmdResult {
    match cmd {
        MaxqCommand::Taxi(args) => taxi(args),
    }
}

fn taxi(args: MaxqTaxiArgs) -> CmdResult {
    if args.episodes == 0 || args.eval_starts == 0 {
        return Err(bad_input(anyhow::anyhow!(
            "--episodes and --eval-starts must be at least 1"
        )));
    }
    let config = TaxiConfig {
        seed: args.seed,
        episodes: args.episodes,
        eval_starts: args.eval_starts,
        ..TaxiConfig::default()
    };
    let report = run_taxi(&config);
    if let Some(path) = &args.plot {
        let curve = |pick: fn(&(u64, f64, f64)) -> f64| {
            report.curve.iter().map(|p| (p.0 as f64, pick(p))).collect()
        };
        LineChart {
            title: format!("Taxi: greedy return (optimal {:.2})", report.optimal_return),
            x_label: "episodes".into(),
            y_label: format!("mean return over {} starts", config.eval_starts),
            series: vec![
                Series::line("MAXQ-Q", curve(|p| p.1)),
                Series::line("flat Q", curve(|p| p.2)),
            ],
            y_range: Some((report.optimal_return - 20.0, report.optimal_return + 2.0)),
        }
        .save(path)
        .input()?;
    }
    if args.json {
        return print_json(&report);
    }
    let at = |e: Option<u64>| e.map_or("never".to_string(), |e| format!("after {e} episodes"));
    println!(
        "optimal return {:.3}; MAXQ-Q {:.3} (within 0.5 {}, {} values stored); flat Q {:.3} (within 0.5 {}, {} values)",
        report.optimal_return,
        report.maxq_return,
        at(report.maxq_episodes_to_optimal),
        report.maxq_stored_values,
        report.flat_return,
        at(report.flat_episodes_to_optimal),
        report.flat_stored_values
    );
    Ok(())
}
