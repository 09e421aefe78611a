//! Task engine speed: one scan of a 500-statement Structured Text routine
//! (assignments with arithmetic, IF, CASE, array elements), the cost of
//! a scan itself (a one-statement routine), and the cost of executing
//! motion instructions: a scan that executes eight (two each of MAM, MAJ,
//! MAS and MRP on four virtual axes) against the same scan with the
//! instructions' IF false. The difference divided by eight is the cost of
//! one executed motion instruction (the README's benchmark table). And one
//! scan of a 1,000-rung ladder routine of five instructions a rung.
//!
//! Run with `CARGO_PROFILE_DEV_OPT_LEVEL=3 cargo bench -p twin --profile dev
//! --bench tasks`: the dependencies keep the dev profile's `opt-level = 2`,
//! the workspace crates (the engine) are optimised like a release build.

#![allow(missing_docs)]

use criterion::{Criterion, criterion_group, criterion_main};
use std::fmt::Write as _;
use twin::program::sandbox::Sandbox;
use twin::program::types::Value;

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

/// Eight motion instructions, executed while `Go` is TRUE; none is
/// refused (the sandbox's axes have no maximum jerk, so both jogs are
/// trapezoidal: an S-curve MAJ there is ERR 13 on its Profile).
const MOTION: &str = "
IF Go THEN
  Target := Target + 0.5;
  MAM(A1, Mam1, 0, Target, 100.0, unitspersec, 1000.0, unitspersec2, 1000.0, unitspersec2, trapezoidal, 100.0, 100.0, %oftime, disabled, programmed, 0, none, 0, 0);
  MAM(A2, Mam2, 1, 0.25, 100.0, unitspersec, 1000.0, unitspersec2, 1000.0, unitspersec2, s-curve, 100.0, 100.0, %oftime, disabled, programmed, 0, none, 0, 0);
  MAJ(A3, Jog1, forward, Speed, unitspersec, 500.0, unitspersec2, 500.0, unitspersec2, trapezoidal);
  MAJ(A4, Jog2, reverse, 20.0, unitspersec, 500.0, unitspersec2, 500.0, unitspersec2, trapezoidal);
  MAS(A3, Stop1, jog, no, 100.0, unitspersec2);
  MAS(A4, Stop2, all, yes, 200.0, unitspersec2);
  MRP(A1, Mrp1, relative, command, 0.0);
  MRP(A2, Mrp2, absolute, actual, Offset);
END_IF;
";

fn motion(c: &mut Criterion) {
    let tags: Vec<(&str, &str)> = ["Mam1", "Mam2", "Jog1", "Jog2", "Stop1", "Stop2", "Mrp1", "Mrp2"]
        .iter()
        .map(|n| (*n, "MOTION_INSTRUCTION"))
        .chain([
            ("Go", "BOOL"),
            ("Target", "REAL"),
            ("Speed", "REAL"),
            ("Offset", "REAL"),
        ])
        .collect();
    let axes = ["A1", "A2", "A3", "A4"];
    let mut on = Sandbox::with_axes(&axes, &tags, MOTION).expect("routine compiles");
    on.set("Go", Value::Bool(true));
    on.set("Speed", Value::Real(10.0));
    on.scan();
    let before = on.controller().stats().statements;
    on.scan();
    assert_eq!(
        on.controller().stats().statements - before,
        10,
        "the IF, the assignment and 8 motion statements"
    );
    assert!(
        on.controller().refusals().is_empty(),
        "{:?}",
        on.controller().refusals()
    );
    c.bench_function("st_scan_8_motion_instructions", |b| b.iter(|| on.scan()));
    let mut off = Sandbox::with_axes(&axes, &tags, MOTION).expect("routine compiles");
    off.set("Go", Value::Bool(true));
    off.set("Speed", Value::Real(10.0));
    off.scan();
    off.set("Go", Value::Bool(false));
    c.bench_function("st_scan_8_motion_instructions_not_executed", |b| b.iter(|| off.scan()));
}

/// 1,000 rungs of five instructions each (bit, compare, math, move,
/// output, a branch every third rung), every instruction executed or
/// passed over as its rung condition says.
fn rungs() -> String {
    let mut s = String::new();
    for i in 0..1000 {
        let (j, k) = (i % 16, i % 50);
        let _ = match i % 3 {
            0 => writeln!(s, "XIC(Run) XIO(Fault) GRT(Count,{k}) ADD(Count,1,Count) OTE(Out[{j}]);"),
            1 => writeln!(s, "XIC(Out[{j}]) LES(X,100.0) MUL(X,1.001,X) MOV(X,Y) OTL(Flag);"),
            _ => writeln!(s, "[XIC(Flag) ,XIC(Run) ]EQU(Count,{k}) CPT(Z,Z + 1) OTU(Flag);"),
        };
    }
    let _ = writeln!(s, "GRT(Count,100000) CLR(Count);");
    s
}

fn ladder(c: &mut Criterion) {
    let tags = [
        ("Run", "BOOL"),
        ("Fault", "BOOL"),
        ("Flag", "BOOL"),
        ("Count", "DINT"),
        ("Z", "DINT"),
        ("X", "REAL"),
        ("Y", "REAL"),
        ("Out", "BOOL[16]"),
    ];
    let mut sandbox = Sandbox::ladder(&[], &tags, &rungs()).expect("rungs compile");
    // 5,002 instructions at the nominal 1 µs outlast the 4 ms task.
    sandbox.set_statement_us(0.5);
    sandbox.set("Run", Value::Bool(true));
    sandbox.set("X", Value::Real(1.0));
    sandbox.scan();
    let instructions = sandbox.controller().stats().statements;
    assert!(instructions >= 5000, "{instructions} instructions a scan");
    c.bench_function("ladder_scan_1000_rungs", |b| b.iter(|| sandbox.scan()));
}

criterion_group!(benches, bench, motion, ladder);
criterion_main!(benches);
