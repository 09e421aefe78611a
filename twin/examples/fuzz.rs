//! A longer fuzz campaign than `cargo test` runs (the cases are those of
//! `twin/tests/fuzz_cases`):
//!
//! ```text
//! cargo run -p twin --example fuzz -- --cases 10000000 [--from 0] [--threads 2] [--outcomes FILE]
//! ```
//!
//! Prints progress every million cases and every failure (case number,
//! target, what happened), then the distinct outcomes (accepted, or a
//! clean error with its numbers and paths left out) per target; exits 1
//! if any case failed. The dev build the
//! tests use runs about 5,000 cases a second on two cores; `--release`
//! is faster but builds every dependency again. `--example fuzz_show N`
//! prints case N's mutant.

#[allow(dead_code)] // the fuzz cases use a part
#[path = "../tests/common/mod.rs"]
mod common;
#[path = "../tests/fuzz_cases/mod.rs"]
mod fuzz_cases;

use fuzz_cases::{Corpus, run_cases_counted, silence_panics};
use std::collections::HashMap;
use std::path::Path;
use std::process::ExitCode;
use std::time::Instant;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let flag = |name: &str, default: u64| -> u64 {
        args.iter()
            .position(|a| a == name)
            .and_then(|i| args.get(i + 1))
            .and_then(|v| v.parse().ok())
            .unwrap_or(default)
    };
    let (from, cases, threads) = (
        flag("--from", 0),
        flag("--cases", 1_000_000),
        flag("--threads", 2).max(1),
    );
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let corpus = Corpus::load(&root);
    let _printing = silence_panics();
    let started = Instant::now();
    let mut failed = 0usize;
    let mut outcomes: HashMap<String, u64> = HashMap::new();
    let block = 1_000_000u64;
    let mut next = from;
    while next < from + cases {
        let end = (next + block).min(from + cases);
        let per = (end - next).div_ceil(threads);
        let failures: Vec<_> = std::thread::scope(|s| {
            let handles: Vec<_> = (0..threads)
                .map(|t| {
                    let (a, b) = ((next + t * per).min(end), (next + (t + 1) * per).min(end));
                    let (corpus, root) = (&corpus, &root);
                    s.spawn(move || run_cases_counted(corpus, root, a..b))
                })
                .collect();
            let mut failures = Vec::new();
            for h in handles {
                let (f, o) = h.join().expect("a fuzz worker");
                failures.extend(f);
                for (k, n) in o {
                    *outcomes.entry(k).or_insert(0) += n;
                }
            }
            failures
        });
        for f in &failures {
            println!("FAIL case {} ({}): {}", f.case, f.target, f.what);
        }
        failed += failures.len();
        next = end;
        println!(
            "{} cases, {failed} failed, {:.0} s",
            next - from,
            started.elapsed().as_secs_f64()
        );
    }
    // Per target: cases, accepted, distinct clean errors.
    let mut targets: Vec<(String, (u64, u64, u64))> = Vec::new();
    for (key, n) in &outcomes {
        let (target, what) = key.split_once(": ").unwrap_or((key, ""));
        let row = match targets.iter_mut().position(|(t, _)| t == target) {
            Some(i) => &mut targets[i].1,
            None => {
                targets.push((target.to_owned(), (0, 0, 0)));
                &mut targets.last_mut().expect("pushed").1
            }
        };
        row.0 += n;
        if what == "accepted" {
            row.1 += n;
        } else {
            row.2 += 1;
        }
    }
    targets.sort();
    println!("{} distinct outcomes", outcomes.len());
    // `--outcomes FILE`: every outcome with its count, a line each
    // (`count<TAB>outcome`), to merge the figures of campaigns run apart.
    if let Some(path) = args
        .iter()
        .position(|a| a == "--outcomes")
        .and_then(|i| args.get(i + 1))
    {
        let mut lines: Vec<String> = outcomes.iter().map(|(k, n)| format!("{n}\t{k}")).collect();
        lines.sort();
        if let Err(e) = std::fs::write(path, lines.join("\n") + "\n") {
            eprintln!("--outcomes {path}: {e}");
        }
    }
    for (target, (cases, accepted, errors)) in &targets {
        println!("  {target}: {cases} cases, {accepted} accepted, {errors} distinct clean errors");
    }
    if failed == 0 {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    }
}
