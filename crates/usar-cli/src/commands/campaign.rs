//! `usar campaign`: run, merge, report, export, list (slurm and status: [`super::slurm`]).

use super::print_json;
use crate::cli::{
    CampaignCommand, CampaignExportArgs, CampaignListArgs, CampaignMergeArgs, CampaignReportArgs,
    CampaignRunArgs, ReportFormat,
};
use crate::failure::{CmdResult, Failure, bad_input};
use crate::{progress, runners};
use serde_json::json;
use std::path::{Path, PathBuf};
use usar_campaign::design::{Summary, runner_named, summarize};
use usar_campaign::{CampaignError, Design, Shard, Store, export, report};

/// Campaign errors keep their kind: bad input exits 2, anything else 1.
pub(crate) fn fail(e: CampaignError) -> Failure {
    if e.is_input() {
        bad_input(e)
    } else {
        Failure::from(e)
    }
}

pub fn run(cmd: CampaignCommand) -> CmdResult {
    match cmd {
        CampaignCommand::Run(args) => run_campaign(args),
        CampaignCommand::Merge(args) => merge(args),
        CampaignCommand::Report(args) => report(args),
        CampaignCommand::Export(args) => export(args),
        CampaignCommand::List(args) => list(args),
        CampaignCommand::Slurm(args) => super::slurm::write(args),
        CampaignCommand::Status(args) => super::slurm::status(args),
    }
}

/// The design of a campaign file or preset, and its text.
pub(crate) fn load_design(
    preset: Option<&String>,
    file: Option<&PathBuf>,
) -> CmdResult<(Design, String)> {
    let (text, source) = match (preset, file) {
        (Some(name), _) => {
            let text = runners::PRESETS
                .iter()
                .find(|(n, _)| n == name)
                .map(|(_, t)| t.to_string())
                .ok_or_else(|| {
                    let names: Vec<&str> = runners::PRESETS.iter().map(|(n, _)| *n).collect();
                    bad_input(anyhow::anyhow!(
                        "--preset {name}: no such preset, expected one of {}",
                        names.join(", ")
                    ))
                })?;
            (text, format!("preset {name}"))
        }
        (None, Some(file)) => (
            std::fs::read_to_string(file)
                .map_err(|e| bad_input(anyhow::anyhow!("{}: cannot read: {e}", file.display())))?,
            file.display().to_string(),
        ),
        (None, None) => {
            return Err(bad_input(anyhow::anyhow!(
                "give a campaign FILE or --preset NAME"
            )));
        }
    };
    let runner = runner_named(&text, &source, runners::named).map_err(fail)?;
    let design = Design::parse(&text, &source, runner).map_err(fail)?;
    Ok((design, text))
}

fn run_campaign(args: CampaignRunArgs) -> CmdResult {
    let shard = Shard::parse(&args.shard).map_err(|e| bad_input(anyhow::anyhow!(e)))?;
    let (design, _) = load_design(args.preset.as_ref(), args.file.as_ref())?;
    let runner = runners::named(&design.campaign.runner).expect("checked by load_design");
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| Path::new("out/campaigns").join(&design.campaign.name));
    let mut store = Store::open_or_create(&out, &design).map_err(fail)?;
    let bar = progress::bar(0, "runs", args.json);
    let report = usar_campaign::run_design(
        &design,
        runner,
        &mut store,
        shard,
        args.jobs,
        |done, todo| {
            bar.set_length(todo);
            bar.set_position(done);
        },
    )
    .map_err(fail)?;
    bar.finish_and_clear();
    if args.json {
        print_json(&json!({
            "campaign": design.campaign.name,
            "design": design.hash,
            "out": out,
            "shard": args.shard,
            "report": report,
        }))
    } else {
        println!(
            "campaign {}: {} runs done, {} already there; {} of {} runs of the design in {}",
            design.campaign.name,
            report.done,
            report.skipped,
            report.stored,
            report.design_runs,
            Store::path_in(&out).display()
        );
        Ok(())
    }
}

fn merge(args: CampaignMergeArgs) -> CmdResult {
    let (inputs, runs) = usar_campaign::merge(&args.inputs, &args.out).map_err(fail)?;
    if args.json {
        print_json(&json!({ "inputs": inputs, "runs": runs, "out": Store::path_in(&args.out) }))
    } else {
        println!(
            "merged {inputs} result folders: {runs} runs in {}",
            Store::path_in(&args.out).display()
        );
        Ok(())
    }
}

/// Opens a result folder read-only with its campaign and runner.
fn open(
    dir: &Path,
) -> CmdResult<(
    Store,
    usar_campaign::CampaignFile,
    &'static dyn usar_campaign::Runner,
)> {
    let store = Store::open(&Store::path_in(dir)).map_err(fail)?;
    let campaign = store.campaign().map_err(fail)?;
    let runner = runners::named(&campaign.runner).ok_or_else(|| {
        bad_input(anyhow::anyhow!(
            "{}: results of runner `{}`, which this usar does not know",
            Store::path_in(dir).display(),
            campaign.runner
        ))
    })?;
    Ok((store, campaign, runner))
}

fn report(args: CampaignReportArgs) -> CmdResult {
    let (store, campaign, runner) = open(&args.dir)?;
    let runs = store.runs().map_err(fail)?;
    let format = match args.format {
        ReportFormat::Md => report::Format::Markdown,
        ReportFormat::Html => report::Format::Html,
    };
    let written = report::write_folder(&args.dir.join("report"), &campaign, &runs, runner, format)
        .map_err(fail)?;
    if args.json {
        // Through a JSON value, so every object's keys are sorted, as this output always had.
        print_json(&serde_json::to_value(&written)?)
    } else {
        print!("{}", written.report.to_markdown(&[]));
        println!(
            "written: {} and {} plots",
            written.file.display(),
            written.plots.len()
        );
        Ok(())
    }
}

fn export(args: CampaignExportArgs) -> CmdResult {
    let (store, _, _) = open(&args.dir)?;
    let runs = store.runs().map_err(fail)?;
    let header = export::write_csv(&runs, &args.csv).map_err(fail)?;
    if args.json {
        print_json(&json!({ "csv": args.csv, "rows": runs.len(), "columns": header }))
    } else {
        println!("{} runs → {}", runs.len(), args.csv.display());
        Ok(())
    }
}

fn list(args: CampaignListArgs) -> CmdResult {
    // Every preset is parsed against its runner, so a broken preset shows here.
    let presets: Vec<Summary> = runners::PRESETS
        .iter()
        .map(|(name, text)| summarize(name, &format!("preset {name}"), text, runners::named))
        .collect();
    let runners: Vec<_> = runners::all()
        .iter()
        .map(|r| json!({ "name": r.name(), "factors": r.factors(), "metrics": r.metrics() }))
        .collect();
    if args.json {
        return print_json(&json!({ "presets": presets, "runners": runners }));
    }
    println!("presets:");
    for p in &presets {
        match p {
            Summary::Broken { name, error } => println!("  {name:<14} BROKEN: {error}"),
            // The run count was never padded (it went through a JSON value); kept as it was.
            Summary::Ready {
                name,
                runs,
                description,
                ..
            } => println!("  {name:<14} {runs} runs  {description}"),
        }
    }
    for r in runners::all() {
        println!("runner {}:", r.name());
        for f in r.factors() {
            println!(
                "  factor {:<18} default {:<10} {}",
                f.name,
                f.default.to_string(),
                f.help
            );
        }
        for m in r.metrics() {
            println!("  metric {:<18} {}", m.name, m.help);
        }
    }
    Ok(())
}
