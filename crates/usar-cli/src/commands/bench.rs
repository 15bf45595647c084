//! `usar bench`: the speed of the hot loops ([`usar_bench::run`]), as a table or JSON.

use super::print_json;
use crate::cli::BenchArgs;
use crate::failure::{CmdResult, bad_input};
use crate::progress;

pub fn run(args: BenchArgs) -> CmdResult {
    if args.scaling {
        return scaling(&args);
    }
    if args.laser_reference {
        return laser_reference(&args);
    }
    if args.recording {
        let reps = if args.quick { 1 } else { 3 };
        let bar = progress::bar(2 * reps as u64, "runs", args.json);
        let r = usar_bench::recording::recording_overhead(reps, || bar.inc(1))?;
        bar.finish_and_clear();
        if args.json {
            return print_json(&r);
        }
        println!(
            "the demo's mission, median of {}: {:.2} s alone, {:.2} s recorded ({} messages, {:.1} MB): {:+.1} % (limit +20 %)",
            r.runs_each,
            r.plain_s,
            r.recorded_s,
            r.messages,
            r.bytes as f64 / 1e6,
            100.0 * r.overhead
        );
        return Ok(());
    }
    let bar = progress::bar(usar_bench::STAGES, "benchmarking", args.json);
    let report = usar_bench::run_observed(args.quick, || bar.inc(1))?;
    bar.finish_and_clear();
    if args.json {
        print_json(&report)
    } else {
        println!("{report}");
        Ok(())
    }
}

fn scaling(args: &BenchArgs) -> CmdResult {
    use usar_bench::scaling::{PIPELINES, ScalingReport, ScalingRow, scaling};
    if !(args.scaling_seconds.is_finite() && (1.0..=3600.0).contains(&args.scaling_seconds))
        || args.sizes.iter().any(|&n| !(1..=4096).contains(&n))
    {
        return Err(bad_input(anyhow::anyhow!(
            "--scaling-seconds: 1 to 3600; --sizes: 1 to 4096 robots each"
        )));
    }
    if let Some(name) = &args.pipeline {
        // One cell (or a column) in this process.
        let pipeline = PIPELINES.iter().find(|p| **p == name).ok_or_else(|| {
            bad_input(anyhow::anyhow!(
                "--pipeline {name}: expected {}",
                PIPELINES.join(" or ")
            ))
        })?;
        let report = scaling(&args.sizes, &[pipeline], args.scaling_seconds, |_| {})?;
        return print_json(&report);
    }
    // Each cell in a process of its own: its peak memory is its own.
    let bar = progress::bar(
        (args.sizes.len() * PIPELINES.len()) as u64,
        "scaling",
        args.json,
    );
    let mut rows: Vec<ScalingRow> = Vec::new();
    let mut floor = String::new();
    for &n in &args.sizes {
        for pipeline in PIPELINES {
            let out = std::process::Command::new(std::env::current_exe()?)
                .args(["bench", "--scaling", "--json", "--pipeline", pipeline])
                .arg(format!("--sizes={n}"))
                .arg(format!("--scaling-seconds={}", args.scaling_seconds))
                .stderr(std::process::Stdio::inherit())
                .output()?;
            if !out.status.success() {
                return Err(
                    anyhow::anyhow!("the scaling run of {n} robots ({pipeline}) failed").into(),
                );
            }
            let cell: ScalingReport = serde_json::from_slice(&out.stdout)?;
            floor = cell.floor;
            rows.extend(cell.rows);
            bar.inc(1);
        }
    }
    bar.finish_and_clear();
    let report = ScalingReport { floor, rows };
    if args.json {
        return print_json(&report);
    }
    println!(
        "{}, {} simulated s per run, one core, each run in a process of its own",
        report.floor, args.scaling_seconds
    );
    println!("pipeline      robots  real-time factor  robot-s/s   peak RSS");
    for r in &report.rows {
        println!(
            "{:<13} {:>6}  {:>16.1}  {:>9.0}  {}",
            r.pipeline,
            r.robots,
            r.realtime_factor,
            r.robot_s_per_s,
            r.peak_rss_mib.map_or("-".into(), |m| format!("{m:.0} MiB"))
        );
    }
    Ok(())
}

fn laser_reference(args: &BenchArgs) -> CmdResult {
    let python = args.python.clone().unwrap_or_else(|| {
        std::env::var_os("USAR_PYTHON").map_or_else(|| "python3".into(), Into::into)
    });
    let (scans, reps) = if args.quick { (2_000, 3) } else { (10_000, 5) };
    let bar = progress::bar(1, "laser, reference", args.json);
    let c = usar_bench::laser_reference::compare(&python, scans, reps)?;
    bar.finish_and_clear();
    if args.json {
        return print_json(&c);
    }
    println!(
        "360-beam 20 m scans with their occupancy update, {} a repetition, median of {}",
        c.scans, c.reps
    );
    println!(
        "usar                          {:>9.0} scans/s",
        c.usar_scans_per_s
    );
    println!(
        "raycast2D + OpenCV (Python)   {:>9.0} scans/s",
        c.reference_scans_per_s
    );
    println!("usar / reference              {:>9.2}x", c.ratio);
    Ok(())
}
