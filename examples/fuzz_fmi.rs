//! The full FMI call-sequence fuzz run over every shipped scene, through the exported
//! `extern "C"` functions (the harness in `tests/fuzz_harness`; `cargo test` runs a slice):
//!
//! ```sh
//! cargo run --release --example fuzz_fmi -- --sequences 100000 [--seed S] [--threads 2]
//!     [--first K] [--hang-seconds 30] [--progress 1000] [--trace]
//! ```
//!
//! Prints progress and a summary (sequences, calls, statuses by kind, slowest sequence) and
//! exits with 1 on a fmi2Fatal, an invalid status or a hang. A crash ends the process; a panic
//! names its sequence, which `--first K --sequences 1` replays.

#[path = "../tests/fuzz_harness/mod.rs"]
mod fuzz;

use std::time::Duration;

fn parse_u64(s: &str) -> u64 {
    let r = match s.strip_prefix("0x") {
        Some(h) => u64::from_str_radix(h, 16),
        None => s.replace('_', "").parse(),
    };
    r.unwrap_or_else(|_| panic!("not a number: {s}"))
}

fn main() {
    let mut cfg = fuzz::Config {
        sequences: 100_000,
        threads: 2,
        progress_every: 1000,
        ..fuzz::Config::default()
    };
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mut i = 0;
    while i < args.len() {
        let value = args.get(i + 1).map(String::as_str).unwrap_or("");
        match args[i].as_str() {
            "--sequences" => cfg.sequences = parse_u64(value),
            "--seed" => cfg.seed = parse_u64(value),
            "--threads" => cfg.threads = parse_u64(value) as usize,
            "--first" => cfg.first = parse_u64(value),
            "--hang-seconds" => cfg.hang_limit = Duration::from_secs(parse_u64(value)),
            "--progress" => cfg.progress_every = parse_u64(value),
            "--trace" => {
                cfg.trace = true;
                i += 1;
                continue;
            }
            other => {
                eprintln!(
                    "unknown argument {other}; usage: fuzz_fmi [--sequences N] [--seed S] [--threads T] [--first K] [--hang-seconds H] [--progress P] [--trace]"
                );
                std::process::exit(2);
            }
        }
        i += 2;
    }
    let harness = fuzz::Harness::new();
    println!(
        "fuzz_fmi: {} sequences from {} with seed {:#x} on {} threads over {} scenes: {}",
        cfg.sequences,
        cfg.first,
        cfg.seed,
        cfg.threads,
        harness.fmus.len(),
        harness
            .fmus
            .iter()
            .map(|f| f.name.as_str())
            .collect::<Vec<_>>()
            .join(", ")
    );
    let summary = harness.run(&cfg);
    println!("{}", summary.report());
    if summary.passed() {
        println!(
            "PASSED: no crash, no fmi2Fatal, no invalid status, no hang, no damaged state accepted"
        );
    } else {
        println!("FAILED");
        std::process::exit(1);
    }
}
