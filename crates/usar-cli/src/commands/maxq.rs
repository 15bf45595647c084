//! `usar maxq`: paper 000's hierarchical reinforcement learning.

use super::print_json;
use crate::cli::{MaxqCommand, MaxqEvalArgs, MaxqTaxiArgs, MaxqTeleopArgs, MaxqTrainArgs};
use crate::failure::{CmdResult, InputContext, bad_input};
use crate::progress;
use serde::Serialize;
use std::path::Path;
use usar_maxq::taxi::{TaxiConfig, run_taxi};
use usar_rescue::analysis::EvalSummary;
use usar_rescue::evaluation::{EvalConfig, eval_scene, evaluate};
use usar_rescue::figures;
use usar_rescue::operator::OperatorProfile;
use usar_rescue::policy::{PolicyFile, TrainingInfo};
use usar_rescue::teleoperation::{StudySummary, study};
use usar_rescue::training::{TrainConfig, TrainReport, train};

pub fn run(cmd: MaxqCommand) -> CmdResult {
    match cmd {
        MaxqCommand::Taxi(args) => taxi(args),
        MaxqCommand::Train(args) => train_command(args),
        MaxqCommand::Eval(args) => eval_command(args),
        MaxqCommand::TeleopStudy(args) => teleop_command(args),
    }
}

/// `usar maxq train`: the policy file, the stored-value counts and the curves.
fn train_command(args: MaxqTrainArgs) -> CmdResult {
    let config = TrainConfig {
        seed: args.seed,
        trials: args.trials,
        flat: !args.no_flat,
        ..TrainConfig::default()
    };
    config
        .validate()
        .map_err(|e| bad_input(anyhow::anyhow!("--{e}")))?;
    let bar = progress::bar(u64::from(args.trials), "training", args.json);
    let (learner, report) = train(&config, |t| bar.set_position(u64::from(t)));
    bar.finish_and_clear();
    PolicyFile::new(
        learner,
        TrainingInfo {
            seed: args.seed,
            trials: args.trials,
        },
    )
    .save(&args.out)
    .input()?;
    if let Some(path) = &args.plot {
        figures::plot_training(&report, path).input()?;
    }
    let ratio = report.maxq_over_flat();
    if args.json {
        #[derive(Serialize)]
        struct Out<'a> {
            policy: &'a Path,
            maxq_q_values: usize,
            flat_q_values: usize,
            maxq_over_flat: f64,
            #[serde(flatten)]
            report: &'a TrainReport,
        }
        return print_json(&Out {
            policy: &args.out,
            maxq_q_values: report.maxq_q_values,
            flat_q_values: report.flat_q_values,
            maxq_over_flat: ratio,
            report: &report,
        });
    }
    println!(
        "{} trials: MAXQ stored {} values, flat Q {} ({:.2} %); policy written to {}",
        report.trials,
        report.maxq_q_values,
        report.flat_q_values,
        100.0 * ratio,
        args.out.display()
    );
    Ok(())
}

/// `usar maxq eval`.
fn eval_command(args: MaxqEvalArgs) -> CmdResult {
    if args.reps == 0 {
        return Err(bad_input(anyhow::anyhow!("--reps must be at least 1")));
    }
    let policy = PolicyFile::load(&args.policy).map_err(bad_input)?;
    let config = EvalConfig {
        seed: args.seed,
        scene_seed: args.scene_seed,
        repetitions: args.reps,
        max_steps: args.max_steps,
        ..EvalConfig::default()
    };
    let total = (config.scenes.len() * 3 * config.weights.len()) as u64 * u64::from(args.reps);
    let bar = progress::bar(total, "evaluating", args.json);
    let runs = evaluate(&policy.learner, &config, || bar.inc(1));
    bar.finish_and_clear();
    if let Some(path) = &args.record {
        let (file, recording) = crate::record_file::RecordFile::create(path)?;
        let mut recorder = usar_record::RescueRecorder::new(recording);
        let replayed =
            usar_rescue::evaluation::replay(&policy.learner, &config, args.record_run, |d| {
                recorder.observe(d)
            });
        // The replay is the evaluated run, step for step.
        match replayed {
            Some(r)
                if runs
                    .get(args.record_run)
                    .is_some_and(|e| e.steps == r.steps) =>
            {
                file.done(recorder.finish())?;
            }
            Some(_) => {
                file.abandon();
                return Err(anyhow::anyhow!(
                    "--record-run {}: the replay differs from the evaluated run",
                    args.record_run
                )
                .into());
            }
            None => {
                file.abandon();
                return Err(bad_input(anyhow::anyhow!(
                    "--record-run {}: expected a run index below {}",
                    args.record_run,
                    runs.len()
                )));
            }
        }
    }
    let out = EvalSummary::new(&args.policy, &runs, &config, args.runs);
    if let Some(path) = &args.plot {
        figures::plot_evaluation(&out.analysis, path).input()?;
    }
    if args.json {
        return print_json(&out);
    }
    for (name, s) in &out.analysis.scenes {
        println!(
            "scene {name}: steps {:.0} (sd {:.0}), coverage {:.3}, collisions {:.2}, victims {:.2}/{:.2}, hand-offs {:.2} stuck + {:.2} victim; full coverage {}/{} runs",
            s.steps.mean,
            s.steps.sd.unwrap_or(0.0),
            s.coverage.mean,
            s.collisions.mean,
            s.victims_found.mean,
            s.victims_reachable.mean,
            s.handoffs_stuck.mean,
            s.handoffs_victim.mean,
            s.full_coverage_runs,
            s.runs
        );
    }
    Ok(())
}

/// `usar maxq teleop-study`.
fn teleop_command(args: MaxqTeleopArgs) -> CmdResult {
    let learner = match &args.policy {
        Some(path) => PolicyFile::load(path).map_err(bad_input)?.learner,
        None => {
            let config = TrainConfig {
                seed: args.seed,
                trials: args.trials.max(1),
                flat: false,
                ..TrainConfig::default()
            };
            let bar = progress::bar(u64::from(config.trials), "training", args.json);
            let (learner, _) = train(&config, |t| bar.set_position(u64::from(t)));
            bar.finish_and_clear();
            learner
        }
    };
    let scene = eval_scene("A", args.seed)
        .ok_or_else(|| bad_input(anyhow::anyhow!("scene A could not be built")))?;
    let participants = OperatorProfile::participants(args.seed);
    let results = study(
        &learner,
        &scene,
        &participants,
        &usar_rescue::DomainConfig::default(),
        args.seed,
    );
    if let Some(path) = &args.plot {
        figures::plot_study(&results, path).input()?;
    }
    let out = StudySummary::new(results);
    if args.json {
        return print_json(&out);
    }
    for (label, side) in [
        ("semi-autonomous", &out.semi_autonomous),
        ("teleoperated", &out.teleoperated),
    ] {
        println!(
            "{label}: victims {:.1}, explored {:.1} %, collisions {:.1}, time {:.0} s",
            side.victims_found.mean,
            side.explored_percent.mean,
            side.collisions.mean,
            side.time_s.mean
        );
    }
    Ok(())
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
        figures::plot_taxi(&report, path).input()?;
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
