//! The fuzz suite: seeded mutants of every file the twin reads (see
//! `fuzz_cases`), [`DEFAULT_CASES`] of them (`FUZZ_CASES=n` for another
//! count), on two threads. No case may panic, abort, take longer than its
//! bound or fail without naming its file. `cargo run --example fuzz --
//! --cases N` runs longer campaigns.

#[allow(dead_code)] // other suites use the other helpers
mod common;
mod fuzz_cases;

use common::root;
use fuzz_cases::{Corpus, run_cases, silence_panics};

/// Cases run by `cargo test`.
const DEFAULT_CASES: u64 = 100_000;

#[test]
fn no_mutated_input_panics_hangs_or_fails_without_naming_its_file() {
    let cases = std::env::var("FUZZ_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(DEFAULT_CASES);
    let root = root();
    let corpus = Corpus::load(&root);
    let hook = silence_panics();
    let half = cases / 2;
    let failures: Vec<_> = std::thread::scope(|s| {
        let (corpus, root) = (&corpus, &root);
        let a = s.spawn(move || run_cases(corpus, root, 0..half));
        let b = s.spawn(move || run_cases(corpus, root, half..cases));
        [a, b]
            .into_iter()
            .flat_map(|h| h.join().expect("a fuzz worker"))
            .collect()
    });
    std::panic::set_hook(hook);
    assert!(
        failures.is_empty(),
        "{} of {cases} cases failed (rerun one with `cargo run --example fuzz -- --from N --cases 1`):\n{:#?}",
        failures.len(),
        &failures[..failures.len().min(10)]
    );
}

#[test]
fn the_ladder_sample_the_mutants_start_from_compiles_and_scans() {
    let mut s = twin::program::sandbox::Sandbox::ladder(&["Conv"], fuzz_cases::LADDER_TAGS, fuzz_cases::LADDER_SAMPLE)
        .unwrap_or_else(|e| panic!("{e}"));
    for _ in 0..5 {
        s.scan();
    }
    assert!(
        s.controller().major_fault().is_none(),
        "{:?}",
        s.controller().major_fault()
    );
}

#[test]
fn the_aoi_scene_the_mutants_start_from_loads() {
    let root = root();
    let corpus = Corpus::load(&root);
    let (path, text) = fuzz_cases::aoi_scene(&corpus, &root, None).unwrap();
    let scene = twin::scene::parse(&path, &text).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(scene.add_on_instructions.len(), 3);
}
