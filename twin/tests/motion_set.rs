//! The rest of the everyday motion set in routines, in the sandbox (no
//! physics): MCD's bits and its change of a running move, its Format
//! errors at load and its ERR 13 at run time.

use twin::program::sandbox::Sandbox;
use twin::program::types::Value;

fn real(s: &Sandbox, name: &str) -> f64 {
    match s.value(name) {
        Some(Value::Real(x)) => x,
        other => panic!("{name}: {other:?}"),
    }
}

fn int(s: &Sandbox, name: &str) -> i64 {
    match s.value(name) {
        Some(Value::Int(x)) => x,
        Some(Value::Bool(b)) => i64::from(b),
        other => panic!("{name}: {other:?}"),
    }
}

fn flag(s: &Sandbox, name: &str) -> bool {
    int(s, name) != 0
}

const MCD_TAGS: &[(&str, &str)] = &[
    ("Mam1", "MOTION_INSTRUCTION"),
    ("Mcd1", "MOTION_INSTRUCTION"),
    ("Slow", "BOOL"),
    ("NewSpeed", "REAL"),
    ("V", "REAL"),
    ("Dn", "BOOL"),
    ("Er", "BOOL"),
    ("Ip", "BOOL"),
    ("MamIp", "BOOL"),
    ("Err", "DINT"),
    ("Exerr", "DINT"),
];

/// A move of 100 mm at 0.5 mm/s (the sandbox axis: 1 mm/s, 10 mm/s²) that
/// `Slow` changes to `NewSpeed` with MCD.
const MCD_ROUTINE: &str = "
IF NOT Mam1.EN THEN
    MAM(X, Mam1, 0, 100, 0.5, UnitsPerSec, 10, UnitsPerSec2, 10, UnitsPerSec2, trapezoidal, 100, 100, %ofTime, disabled, programmed, 0, none, 0, 0);
END_IF;
IF Slow AND NOT Mcd1.EN THEN
    MCD(X, Mcd1, move, yes, NewSpeed, no, 0, yes, 2.5, no, 0, no, 0, UnitsPerSec, UnitsPerSec2, UnitsPerSec2, UnitsPerSec3);
END_IF;
V := X.CommandVelocity;
Dn := Mcd1.DN; Er := Mcd1.ER; Ip := Mcd1.IP; MamIp := Mam1.IP;
Err := Mcd1.ERR; Exerr := Mcd1.EXERR;
";

#[test]
fn mcd_lowers_a_running_move_in_the_scan_it_executes() {
    let mut s = Sandbox::with_axes(&["X"], MCD_TAGS, MCD_ROUTINE).unwrap_or_else(|e| panic!("{e}"));
    for _ in 0..50 {
        s.scan();
    }
    assert!((real(&s, "V") - 0.5).abs() < 1e-6, "{}", real(&s, "V"));
    s.set("NewSpeed", Value::Real(0.2));
    s.set("Slow", Value::Bool(true));
    s.scan();
    assert!(flag(&s, "Dn"), ".DN in the scan it executes");
    assert!(!flag(&s, "Er") && !flag(&s, "Ip"));
    assert!(flag(&s, "MamIp"), "the move goes on");
    // Down from 0.5 to 0.2 at the new decel 2.5 mm/s²: 0.12 s, 30 updates,
    // 0.01 mm/s an update.
    let mut last = 0.5;
    for _ in 0..40 {
        let v = real(&s, "V");
        assert!(last - v <= 0.01 + 1e-6 && v <= last + 1e-9, "{last} → {v}");
        last = v;
        s.scan();
    }
    assert!((real(&s, "V") - 0.2).abs() < 1e-6);
}

#[test]
fn mcd_out_of_range_at_run_time_is_err_13_with_the_operands_faceplate_index() {
    let mut s = Sandbox::with_axes(&["X"], MCD_TAGS, MCD_ROUTINE).unwrap_or_else(|e| panic!("{e}"));
    for _ in 0..20 {
        s.scan();
    }
    s.set("NewSpeed", Value::Real(-1.0));
    s.set("Slow", Value::Bool(true));
    s.scan();
    assert!(flag(&s, "Er") && !flag(&s, "Dn"));
    assert_eq!((int(&s, "Err"), int(&s, "Exerr")), (13, 4));
    assert!((real(&s, "V") - 0.5).abs() < 1e-6, "the move keeps its speed");
}

#[test]
fn mcd_immediate_operands_out_of_range_are_refused_at_load() {
    for (call, operand) in [
        (
            "MCD(X, Mcd1, 2, Yes, 1.0, No, 0, No, 0, No, 0, No, 0, 0, 0, 0, 0);",
            "Motion Type",
        ),
        (
            "MCD(X, Mcd1, Jog, Maybe, 1.0, No, 0, No, 0, No, 0, No, 0, 0, 0, 0, 0);",
            "Change Speed",
        ),
        (
            "MCD(X, Mcd1, Jog, Yes, 1.0, No, 0, No, 0, No, 0, No, 0, 0, 0, 0, 7);",
            "Jerk Units",
        ),
        (
            "MCD(X, Mcd1, Jog, Yes, 1.0, No, 0, No, 0, No, 0, No, 0, 0, 3, 0, 0);",
            "Accel Units",
        ),
    ] {
        let e = match Sandbox::with_axes(&["X"], MCD_TAGS, call) {
            Ok(_) => panic!("{call} loads"),
            Err(e) => e,
        };
        assert!(e.contains(operand), "{call}: {e}");
    }
    // The online help's 16-operand syntax line is not the operand table's.
    let e = match Sandbox::with_axes(
        &["X"],
        MCD_TAGS,
        "MCD(X, Mcd1, Jog, Yes, 1.0, No, 0, No, 0, No, No, 0, 0, 0, 0, 0);",
    ) {
        Ok(_) => panic!("16 operands load"),
        Err(e) => e,
    };
    assert!(e.contains("17"), "{e}");
}
