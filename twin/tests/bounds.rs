//! Bounded work and memory for every input (issue 39): each defect's
//! reproducer, failing before its fix.

use twin::program::sandbox::Sandbox;

/// FLL and COP with a length of i64::MAX: `start + n` overflowed and the
/// range check passed (a panic); now the subscript fault, major fault 4/20.
#[test]
fn fll_and_cop_with_a_huge_length_fault_instead_of_panicking() {
    for routine in [
        "FLL(0, Arr[1], 9223372036854775807);",
        "COP(Arr[1], Arr[2], 9223372036854775807);",
    ] {
        let mut s = Sandbox::new(&[("Arr", "DINT[4]")], routine).unwrap_or_else(|e| panic!("{e}"));
        s.scan();
        let f = s
            .controller()
            .major_fault()
            .unwrap_or_else(|| panic!("{routine}: no fault"));
        assert_eq!((f.fault_type, f.code), (4, 20), "{routine}: {}", f.message);
    }
}

/// A refusal every scan kept a String each, without bound: the controller
/// keeps the first 1,000 and counts them all.
#[test]
fn run_time_refusals_are_kept_up_to_a_bound_and_counted() {
    let routine = "MAJ(X, J, 0, Speed, unitspersec, 10, unitspersec2, 10, unitspersec2, trapezoidal);";
    let mut s = Sandbox::with_axes(&["X"], &[("J", "MOTION_INSTRUCTION"), ("Speed", "REAL")], routine)
        .unwrap_or_else(|e| panic!("{e}"));
    s.set("Speed", twin::program::types::Value::Real(-1.0));
    for _ in 0..1500 {
        s.scan();
    }
    let c = s.controller();
    assert_eq!(c.refusals().len(), twin::program::controller::REFUSALS_KEPT);
    assert_eq!(c.refusal_count(), 1500);
}

/// `R := 1.0e999999999;` compiled to infinity with no error; a literal
/// past LREAL's range is refused as an integer one is.
#[test]
fn a_real_literal_past_lreal_is_refused() {
    let e = match Sandbox::new(&[("R", "REAL")], "R := 1.0e999999999;") {
        Ok(_) => panic!("an infinite literal compiles"),
        Err(e) => e,
    };
    assert!(e.contains("too large") && e.contains("Main.st:1:"), "{e}");
    assert!(Sandbox::new(&[("R", "REAL")], "R := 1.7e308;").is_ok());
}

/// Each array was bounded, not their sum: ten `FBD_TIMER[1000000]` took
/// 2.17 GB. The tags' total is checked before anything is allocated.
#[test]
fn tag_memory_is_bounded_in_sum_before_it_is_allocated() {
    let names: Vec<String> = (0..20).map(|i| format!("T{i}")).collect();
    let tags: Vec<(&str, &str)> = names.iter().map(|n| (n.as_str(), "FBD_TIMER[1000000]")).collect();
    let e = match Sandbox::new(&tags, "") {
        Ok(_) => panic!("20 million timers load"),
        Err(e) => e,
    };
    assert!(e.contains("tag T1:") && e.contains("budget for tag memory"), "{e}");
    // At the bound: 2^24 DINTs in 17 arrays of 986,895 (and one short).
    let per = twin::program::memory::MAX_TAG_SLOTS / 17;
    let last = twin::program::memory::MAX_TAG_SLOTS - 16 * per;
    let ty_full = format!("DINT[{per}]");
    let ty_last = format!("DINT[{last}]");
    let mut at_bound: Vec<(&str, &str)> = names[..16].iter().map(|n| (n.as_str(), ty_full.as_str())).collect();
    at_bound.push(("Last", ty_last.as_str()));
    assert!(Sandbox::new(&at_bound, "").is_ok(), "at the bound");
    let ty_over = format!("DINT[{}]", last + 1);
    at_bound.pop();
    at_bound.push(("Last", ty_over.as_str()));
    assert!(Sandbox::new(&at_bound, "").is_err(), "one past the bound");
}
