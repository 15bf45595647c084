//! `usar campaign slurm` and `usar campaign status`: a campaign as a SLURM job array
//! ([`usar_campaign::slurm`]).

use super::campaign::{fail, load_design};
use super::print_json;
use crate::cli::{CampaignSlurmArgs, CampaignStatusArgs};
use crate::failure::{CmdResult, bad_input};
use serde_json::json;
use std::process::Command;
use usar_campaign::slurm::{ShardState, SlurmJob, status as read_status};

pub fn write(args: CampaignSlurmArgs) -> CmdResult {
    let (design, text) = load_design(args.preset.as_ref(), args.file.as_ref())?;
    let out = std::path::absolute(&args.out)
        .map_err(|e| bad_input(anyhow::anyhow!("--out {}: {e}", args.out.display())))?;
    let job = SlurmJob {
        campaign_text: text,
        out,
        tasks: args.tasks,
        partition: args.partition,
        time: args.time,
        cpus_per_task: args.cpus_per_task,
        usar: std::env::current_exe()?,
    };
    job.check().map_err(fail)?;
    std::fs::create_dir_all(&job.out)
        .map_err(|e| bad_input(anyhow::anyhow!("--out {}: {e}", job.out.display())))?;
    let scripts = job.write(&design).map_err(fail)?;
    let submitted = if args.submit {
        let output = Command::new("sh")
            .arg(&scripts.submit)
            .output()
            .map_err(|e| {
                bad_input(anyhow::anyhow!(
                    "{}: cannot run: {e}",
                    scripts.submit.display()
                ))
            })?;
        if !output.status.success() {
            return Err(bad_input(anyhow::anyhow!(
                "sbatch refused the job: {}",
                String::from_utf8_lossy(&output.stderr).trim()
            )));
        }
        Some(String::from_utf8_lossy(&output.stdout).trim().to_string())
    } else {
        None
    };
    if args.json {
        return print_json(&json!({
            "campaign": design.campaign.name,
            "design": design.hash,
            "design_runs": design.len(),
            "tasks": job.tasks,
            "scripts": scripts,
            "submitted": submitted,
        }));
    }
    println!(
        "campaign {} ({} runs) in {} tasks: {}",
        design.campaign.name,
        design.len(),
        job.tasks,
        scripts.submit.display()
    );
    match submitted {
        Some(ids) => println!("submitted: {ids}"),
        None => println!("submit with: sh {}", scripts.submit.display()),
    }
    Ok(())
}

pub fn status(args: CampaignStatusArgs) -> CmdResult {
    let s = read_status(&args.dir).map_err(fail)?;
    if args.json {
        return print_json(&s);
    }
    let count = |f: fn(&ShardState) -> bool| s.shards.iter().filter(|x| f(x)).count();
    println!(
        "campaign {} ({} runs) in {} shards: {} done, {} running, {} partial, {} missing; merged: {}",
        s.job.campaign,
        s.job.design_runs,
        s.job.tasks,
        count(|x| *x == ShardState::Done),
        count(|x| matches!(x, ShardState::Running { .. })),
        count(|x| matches!(x, ShardState::Partial { .. })),
        count(|x| *x == ShardState::Missing),
        if s.merged { "yes" } else { "no" }
    );
    for (k, shard) in s.shards.iter().enumerate() {
        match shard {
            ShardState::Done => {}
            ShardState::Running { finished, runs } => {
                println!("  shard {}: running, {finished} of {runs} runs", k + 1)
            }
            ShardState::Partial { finished, runs } => {
                println!("  shard {}: stopped at {finished} of {runs} runs", k + 1)
            }
            ShardState::Missing => println!("  shard {}: not started", k + 1),
        }
    }
    Ok(())
}
