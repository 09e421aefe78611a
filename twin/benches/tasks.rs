//! Task engine speed: one scan of a 500-statement Structured Text routine
//! (assignments with arithmetic, IF, CASE, array elements), and the cost of
//! a scan itself (a one-statement routine).
//!
//! Run with `CARGO_PROFILE_DEV_OPT_LEVEL=3 cargo bench -p twin --profile dev
//! --bench tasks`: the dependencies keep the dev profile's `opt-level = 2`,
//! the workspace crates (the engine) are optimised like a release build.

#![allow(missing_docs)]

use criterion::{Criterion, criterion_group, criterion_main};
use std::fmt::Write as _;
use twin::program::plc::sandbox::Sandbox;

/// 500 statements executed a scan: 100 blocks of five.
fn routine() -> String {
    let mut s = String::new();
    for i in 0..100 {
        let _ = writeln!(
            s,
            "A := A + {i} * 3 - B MOD 7;\n\
             X := X * 0.5 + REAL_{k} / 4.0;\n\
             IF A > 1000 THEN A := A - 1000; ELSE B := B + 1; END_IF;\n\
             CASE B MOD 4 OF 0: C := C + 1; 1, 2: C := C - 1; ELSE C := 0; END_CASE;\n\
             Arr[{j}] := Arr[{j}] + A;",
            k = i % 4,
            j = i % 16
        );
    }
    s
}

fn bench(c: &mut Criterion) {
    let mut tags = vec![
        ("A", "DINT"),
        ("B", "DINT"),
        ("C", "DINT"),
        ("X", "REAL"),
        ("Arr", "DINT[16]"),
    ];
    tags.extend([
        ("REAL_0", "REAL"),
        ("REAL_1", "REAL"),
        ("REAL_2", "REAL"),
        ("REAL_3", "REAL"),
    ]);
    let mut sandbox = Sandbox::new(&tags, &routine()).expect("routine compiles");
    sandbox.scan();
    let statements = sandbox.controller().stats().statements;
    assert!(statements >= 500, "{statements} statements a scan");
    c.bench_function("st_scan_500_statements", |b| b.iter(|| sandbox.scan()));
    let mut empty = Sandbox::new(&[("A", "DINT")], "A := 1;").expect("routine compiles");
    c.bench_function("st_scan_1_statement", |b| b.iter(|| empty.scan()));
}

criterion_group!(benches, bench);
criterion_main!(benches);
