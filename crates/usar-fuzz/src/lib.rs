//! `usar-fuzz`: a fuzz harness for every loader of usar that runs on the stable toolchain.
//!
//! Each [`loaders::Loader`] (map images, ROS YAML, MovingAI maps and scenarios, scene JSON,
//! robot / mission / campaign TOML, policy JSON, BTM SQLite / JSON / `.btmb`) is fed mutations
//! of real files ([`mutate`]) and random bytes for a bounded time. A **finding** is an input
//! that made the loader panic, hold more than [`MAX_PEAK_BYTES`] at once (measured by
//! [`meter::MeteredAllocator`]), or take longer than [`MAX_INPUT_SECONDS`]. Findings are saved
//! under `target/fuzz-findings/` to become named regression tests (`tests/regressions.rs`).
//!
//! ```no_run
//! // In a binary or test with the metered allocator installed:
//! let report = usar_fuzz::fuzz(usar_fuzz::loaders::loader("ros-yaml").unwrap(), 2.0, 1);
//! assert!(report.findings.is_empty(), "{report:?}");
//! ```
//!
//! In CI each loader runs for `USAR_FUZZ_SECONDS` (default 15) seconds; set it higher to
//! fuzz as long as you like: `USAR_FUZZ_SECONDS=600 cargo test -p usar-fuzz --release`.

pub mod loaders;
pub mod meter;
pub mod mutate;

use rand::SeedableRng;
use rand_pcg::Pcg64Mcg;
use std::cell::Cell;
use std::panic::AssertUnwindSafe;
use std::path::PathBuf;
use std::time::{Duration, Instant};

/// An input holding more than this much memory at once is a finding (the bound the issue
/// asks of every command: 500 MB).
pub const MAX_PEAK_BYTES: usize = 500_000_000;
/// An input taking longer than this is a finding (inputs are at most 4 MB).
pub const MAX_INPUT_SECONDS: f64 = 5.0;

/// What made an input a finding.
#[derive(Clone, Debug, PartialEq)]
pub enum Problem {
    Panic(String),
    Memory { peak_bytes: usize },
    Slow { seconds: f64 },
}

/// An input that broke a loader, and where it was saved.
#[derive(Clone, Debug)]
pub struct Finding {
    pub loader: &'static str,
    pub problem: Problem,
    pub input_len: usize,
    pub saved: Option<PathBuf>,
}

/// What one fuzzing session did.
#[derive(Clone, Debug)]
pub struct FuzzReport {
    pub loader: &'static str,
    /// Inputs tried.
    pub inputs: u64,
    /// Inputs the loader accepted (the rest were refused with an error).
    pub accepted: u64,
    pub findings: Vec<Finding>,
}

thread_local! {
    static FUZZING: Cell<bool> = const { Cell::new(false) };
}

/// A panic hook that stays quiet for panics the harness catches on its own thread and prints
/// all others as the default hook does.
fn install_quiet_hook() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        let default = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if !FUZZING.with(Cell::get) {
                default(info);
            }
        }));
    });
}

/// Feeds `loader` mutated inputs for `seconds`, from the PRNG seed `seed` (the inputs are a
/// function of the seed; how many are tried depends on the machine's speed).
pub fn fuzz(loader: &'static loaders::Loader, seconds: f64, seed: u64) -> FuzzReport {
    install_quiet_hook();
    let seeds = (loader.seeds)();
    let mut rng = Pcg64Mcg::seed_from_u64(seed);
    let mut report = FuzzReport {
        loader: loader.name,
        inputs: 0,
        accepted: 0,
        findings: Vec::new(),
    };
    let deadline = Instant::now() + Duration::from_secs_f64(seconds);
    // The seeds themselves first: each must load.
    let mut queue: Vec<Vec<u8>> = seeds.clone();
    while Instant::now() < deadline || !queue.is_empty() {
        let input = queue
            .pop()
            .unwrap_or_else(|| mutate::next_input(&seeds, &mut rng));
        report.inputs += 1;
        let (outcome, problem) = check(loader, &input);
        if outcome == Some(true) {
            report.accepted += 1;
        }
        if let Some(problem) = problem {
            let saved = save(loader.name, &input);
            report.findings.push(Finding {
                loader: loader.name,
                problem,
                input_len: input.len(),
                saved,
            });
            if report.findings.len() >= 20 {
                break;
            }
        }
    }
    report
}

/// Runs one input: whether it was accepted (None: it panicked) and the problem, if any.
pub fn check(loader: &loaders::Loader, input: &[u8]) -> (Option<bool>, Option<Problem>) {
    let start = meter::current();
    meter::reset_peak();
    let t = Instant::now();
    FUZZING.with(|f| f.set(true));
    let result = std::panic::catch_unwind(AssertUnwindSafe(|| (loader.load)(input)));
    FUZZING.with(|f| f.set(false));
    let seconds = t.elapsed().as_secs_f64();
    let peak_bytes = meter::peak_since(start);
    match result {
        Err(payload) => {
            let message = payload
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| payload.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_else(|| "a panic".to_string());
            (None, Some(Problem::Panic(message)))
        }
        Ok(r) if peak_bytes > MAX_PEAK_BYTES => {
            (Some(r.is_ok()), Some(Problem::Memory { peak_bytes }))
        }
        Ok(r) if seconds > MAX_INPUT_SECONDS => (Some(r.is_ok()), Some(Problem::Slow { seconds })),
        Ok(r) => (Some(r.is_ok()), None),
    }
}

/// Saves a finding's input as `target/fuzz-findings/LOADER-HASH.bin`.
fn save(loader: &str, input: &[u8]) -> Option<PathBuf> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../target/fuzz-findings");
    std::fs::create_dir_all(&dir).ok()?;
    // FNV-1a: a stable name for the same input.
    let hash = input.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x100_0000_01b3)
    });
    let path = dir.join(format!("{loader}-{hash:016x}.bin"));
    std::fs::write(&path, input).ok()?;
    Some(path)
}

/// The README's examples, compiled and run as doctests.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;
