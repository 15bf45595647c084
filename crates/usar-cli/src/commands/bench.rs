//! `usar bench`: the speed of the hot loops ([`usar_bench::run`]), as a table or JSON.

use super::print_json;
use crate::cli::BenchArgs;
use crate::failure::CmdResult;
use crate::progress;

pub fn run(args: BenchArgs) -> CmdResult {
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
