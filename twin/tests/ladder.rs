//! Ladder routines in the engine's sandbox: each instruction's action on
//! a TRUE rung, a FALSE rung and at prescan, and its status bits and math
//! flags, against the Execution tables of the Logix 5000 General
//! Instructions Reference (1756-RM003); rung grammar and its errors; a
//! motion instruction's transition rule (MOTION-RM002). The sandbox scans
//! one 4 ms periodic task per call.

use twin::program::Program;
use twin::program::sandbox::Sandbox;
use twin::program::types::Value;

mod common;

fn ladder(tags: &[(&str, &str)], rungs: &str) -> Sandbox {
    Sandbox::ladder(&[], tags, rungs).unwrap_or_else(|e| panic!("{e}"))
}

fn b(s: &Sandbox, name: &str) -> bool {
    s.value(name).unwrap_or_else(|| panic!("no {name}")).truthy()
}

fn i(s: &Sandbox, name: &str) -> i64 {
    s.value(name).unwrap_or_else(|| panic!("no {name}")).as_i64()
}

fn f(s: &Sandbox, name: &str) -> f64 {
    s.value(name).unwrap_or_else(|| panic!("no {name}")).as_f64()
}

fn set(s: &mut Sandbox, name: &str, on: bool) {
    s.set(name, Value::Bool(on));
}

fn error(tags: &[(&str, &str)], rungs: &str) -> String {
    match Sandbox::ladder(&[], tags, rungs) {
        Ok(_) => panic!("{rungs:?} was accepted"),
        Err(e) => e,
    }
}

const BITS: &[(&str, &str)] = &[
    ("A", "BOOL"),
    ("B", "BOOL"),
    ("C", "BOOL"),
    ("Q", "BOOL"),
    ("R", "BOOL"),
    ("S", "BOOL"),
    ("W", "DINT"),
];

#[test]
fn series_and_branches_are_and_and_or_with_outputs_anywhere_in_a_leg() {
    // Q = A AND (B OR C); R is written in the middle of the first leg,
    // with the condition there (A AND B); S after the branch is Q.
    let rungs = "XIC(A)[XIC(B) OTE(R) ,XIC(C) ]OTE(Q) OTE(S);\n";
    let mut s = ladder(BITS, rungs);
    for bits in 0..8u8 {
        let (a, bb, c) = (bits & 1 == 1, bits & 2 == 2, bits & 4 == 4);
        set(&mut s, "A", a);
        set(&mut s, "B", bb);
        set(&mut s, "C", c);
        s.scan();
        assert_eq!(b(&s, "Q"), a && (bb || c), "A {a} B {bb} C {c}");
        assert_eq!(b(&s, "S"), a && (bb || c));
        assert_eq!(b(&s, "R"), a && bb);
    }
}

#[test]
fn nested_branches_and_empty_legs() {
    // An empty leg is a wire: [XIC(A) ,] is always TRUE.
    let mut s = ladder(
        BITS,
        "[XIC(A) ,]OTE(Q);\n[[XIC(A) ,XIC(B) ]XIC(C) ,XIO(A) XIO(B) ]OTE(R);\n",
    );
    for bits in 0..8u8 {
        let (a, bb, c) = (bits & 1 == 1, bits & 2 == 2, bits & 4 == 4);
        set(&mut s, "A", a);
        set(&mut s, "B", bb);
        set(&mut s, "C", c);
        s.scan();
        assert!(b(&s, "Q"));
        // [[A ,B ]C ,/A /B ]: (A OR B) AND C, OR neither A nor B.
        let want = if a || bb { c } else { true };
        assert_eq!(b(&s, "R"), want, "{a} {bb} {c}");
    }
}

#[test]
fn latch_unlatch_and_bits_of_integers() {
    let mut s = ladder(
        BITS,
        "XIC(A) OTL(W.3);\nXIC(B) OTU(W.3);\nXIC(W.3) OTE(Q);\nXIO(W.3) OTE(W.0);\n",
    );
    s.scan();
    assert_eq!(i(&s, "W"), 1);
    set(&mut s, "A", true);
    s.scan();
    assert_eq!(i(&s, "W"), 8, "OTL set bit 3, OTE cleared bit 0");
    assert!(b(&s, "Q"));
    set(&mut s, "A", false);
    s.scan();
    assert_eq!(i(&s, "W"), 8, "a latch holds on a FALSE rung");
    set(&mut s, "B", true);
    s.scan();
    assert_eq!(i(&s, "W"), 1);
}

#[test]
fn one_shots_pulse_once_per_transition_and_prescan_arms_them() {
    let rungs = "XIC(A) ONS(S) OTE(Q);\nXIC(A) OSR(B,R);\nXIC(A) OSF(C,W.0);\n";
    let mut s = ladder(BITS, rungs);
    // A TRUE on the first scan: the prescan set ONS's and OSR's storage
    // bits, so neither fires.
    set(&mut s, "A", true);
    s.scan();
    assert!(!b(&s, "Q") && !b(&s, "R"));
    set(&mut s, "A", false);
    s.scan();
    assert!(!b(&s, "S"), "a FALSE rung clears ONS's storage bit");
    assert_eq!(i(&s, "W"), 1, "OSF pulses when its rung goes FALSE");
    s.scan();
    assert_eq!(i(&s, "W"), 0, "for one scan");
    set(&mut s, "A", true);
    s.scan();
    assert!(b(&s, "Q") && b(&s, "R"), "one scan on the rise");
    s.scan();
    assert!(!b(&s, "Q") && !b(&s, "R"), "then off while TRUE");
}

#[test]
fn ton_tof_rto_time_in_milliseconds_and_res_clears() {
    let tags = &[
        ("A", "BOOL"),
        ("Z", "BOOL"),
        ("T1", "TIMER"),
        ("T2", "TIMER"),
        ("T3", "TIMER"),
    ];
    let rungs = "XIC(A) TON(T1,20,0);\nXIC(A) TOF(T2,20,0);\nXIC(A) RTO(T3,30,?);\nXIC(Z) RES(T3);\n";
    let mut s = ladder(tags, rungs);
    assert_eq!(i(&s, "T1.PRE"), 20, "the rung's Preset is PRE at load");
    s.scan();
    assert!(!b(&s, "T1.EN") && !b(&s, "T2.DN"));
    set(&mut s, "A", true);
    s.scan(); // starts timing
    assert!(b(&s, "T1.EN") && b(&s, "T1.TT") && !b(&s, "T1.DN"));
    assert!(b(&s, "T2.EN") && b(&s, "T2.DN") && !b(&s, "T2.TT"));
    for _ in 0..4 {
        s.scan();
    }
    assert_eq!(i(&s, "T1.ACC"), 16);
    s.scan();
    assert!(b(&s, "T1.DN") && !b(&s, "T1.TT"));
    assert_eq!(i(&s, "T1.ACC"), 20, "ACC stops at PRE");
    assert_eq!(i(&s, "T3.ACC"), 20);
    set(&mut s, "A", false);
    s.scan();
    assert!(!b(&s, "T1.EN") && !b(&s, "T1.DN"));
    assert_eq!(i(&s, "T1.ACC"), 0, "TON resets on a FALSE rung");
    assert_eq!(i(&s, "T3.ACC"), 20, "RTO keeps ACC");
    assert!(!b(&s, "T3.EN") && !b(&s, "T3.TT"));
    assert!(
        b(&s, "T2.TT") && b(&s, "T2.DN") && !b(&s, "T2.EN"),
        "TOF times on a FALSE rung"
    );
    for _ in 0..5 {
        s.scan();
    }
    assert!(!b(&s, "T2.DN") && !b(&s, "T2.TT"));
    assert_eq!(i(&s, "T2.ACC"), 20);
    set(&mut s, "A", true);
    for _ in 0..4 {
        s.scan();
    }
    assert!(b(&s, "T3.DN"), "RTO resumed from 20 and reached 30");
    set(&mut s, "Z", true);
    s.scan();
    assert_eq!(i(&s, "T3.ACC"), 0);
    assert!(!b(&s, "T3.DN"));
}

#[test]
fn a_negative_preset_is_major_fault_4_34() {
    let mut s = ladder(&[("A", "BOOL"), ("T1", "TIMER")], "TON(T1,-5,0);\n");
    set(&mut s, "A", true);
    s.scan();
    let f = s.controller().major_fault().expect("a major fault");
    assert_eq!((f.fault_type, f.code), (4, 34), "{f}");
    assert!(f.routine.ends_with("Main.rll") && f.line == 1, "{f}");
}

#[test]
fn counters_count_transitions_and_flag_overflow() {
    let tags = &[("A", "BOOL"), ("B", "BOOL"), ("Z", "BOOL"), ("C1", "COUNTER")];
    let mut s = ladder(tags, "XIC(A) CTU(C1,3,0);\nXIC(B) CTD(C1,?,?);\nXIC(Z) RES(C1);\n");
    // The prescan set CU and CD: a rung TRUE at the first scan counts
    // nothing; these start FALSE.
    s.scan();
    for _ in 0..3 {
        set(&mut s, "A", true);
        s.scan();
        s.scan();
        set(&mut s, "A", false);
        s.scan();
    }
    assert_eq!(i(&s, "C1.ACC"), 3);
    assert!(b(&s, "C1.DN"));
    set(&mut s, "B", true);
    s.scan();
    assert_eq!(i(&s, "C1.ACC"), 2);
    assert!(!b(&s, "C1.DN"));
    set(&mut s, "Z", true);
    s.scan();
    assert_eq!(i(&s, "C1.ACC"), 0);
    // Down past the smallest DINT: UN.
    let mut s = ladder(tags, "XIC(B) CTD(C1,0,-2147483648);\n");
    s.scan();
    set(&mut s, "B", true);
    s.scan();
    assert!(b(&s, "C1.UN"));
    assert_eq!(i(&s, "C1.ACC"), 2147483647);
}

#[test]
fn comparisons_lim_both_ways_meq_and_cmp_expressions() {
    let tags = &[("X", "DINT"), ("Y", "REAL"), ("Q", "BOOL[8]")];
    let rungs = "EQU(X,5) OTE(Q[0]);\nGRT(Y,X) OTE(Q[1]);\nLIM(0,X,10) OTE(Q[2]);\nLIM(10,X,0) OTE(Q[3]);\nMEQ(X,16#F,16#5) OTE(Q[4]);\nCMP(X*2 + 1 >= 11 AND Y <> 0.0) OTE(Q[5]);\nNEQ(X,5)LEQ(X,7)OTE(Q[6]);\nCMP(SQR(X*X+0) = ABS(-X)) OTE(Q[7]);\n";
    let mut s = ladder(tags, rungs);
    let q = |s: &Sandbox| (0..8).map(|k| b(s, &format!("Q[{k}]"))).collect::<Vec<_>>();
    s.set("X", Value::Int(5));
    s.set("Y", Value::Real(5.5));
    s.scan();
    assert_eq!(q(&s), [true, true, true, false, true, true, false, true]);
    s.set("X", Value::Int(21));
    s.scan();
    // LIM(10, X, 0): outside the open range 0 < X < 10.
    assert_eq!(q(&s), [false, false, false, true, true, true, false, true]);
}

#[test]
fn math_sets_the_status_flags_as_rm003_tabulates() {
    let tags = &[
        ("A", "DINT"),
        ("D", "DINT"),
        ("N", "BOOL"),
        ("Z", "BOOL"),
        ("V", "BOOL"),
        ("C", "BOOL"),
        ("R", "REAL"),
        ("K", "SINT"),
    ];
    let flags = "XIC(S:N) OTE(N);\nXIC(S:Z) OTE(Z);\nXIC(S:V) OTE(V);\nXIC(S:C) OTE(C);\n";
    let run = |rung: &str, a: i64| {
        let mut s = ladder(tags, &format!("{rung}\n{flags}"));
        s.set("A", Value::Int(a));
        s.scan();
        let out = [b(&s, "N"), b(&s, "Z"), b(&s, "V"), b(&s, "C")];
        (s, out)
    };
    // ADD: 2147483647 + 1 overflows (V, negative) with no unsigned carry.
    let (s, fl) = run("ADD(A,1,D);", 2_147_483_647);
    assert_eq!(i(&s, "D"), -2_147_483_648);
    assert_eq!(fl, [true, false, true, false]);
    // -1 + 1 = 0 carries out of bit 31 (unsigned 0xFFFFFFFF + 1).
    let (_, fl) = run("ADD(A,1,D);", -1);
    assert_eq!(fl, [false, true, false, true]);
    // SUB borrows when A < B as unsigned numbers.
    let (s, fl) = run("SUB(A,5,D);", 3);
    assert_eq!(i(&s, "D"), -2);
    assert_eq!(fl, [true, false, false, true]);
    // A result that does not fit its SINT destination: V.
    let (s, fl) = run("MUL(A,100,K);", 3);
    assert_eq!(i(&s, "K"), 44);
    assert!(fl[2]);
    // REAL math: no carry.
    let (s, fl) = run("DIV(A,4.0,R);", -6);
    assert_eq!(f(&s, "R"), -1.5);
    assert_eq!(fl, [true, false, false, false]);
    // CPT with the ladder function names.
    let (s, _) = run("CPT(R,SQR(A) + ATN(0.0) + TRN(2.7) * 2 ** 2);", 16);
    assert_eq!(f(&s, "R"), 12.0);
    // BCD: TOD of 1234 is 16#1234, FRD reads it back.
    let (s, _) = run("CPT(D,TOD(A));", 1234);
    assert_eq!(i(&s, "D"), 0x1234);
    let (s, _) = run("CPT(D,FRD(A));", 0x9876);
    assert_eq!(i(&s, "D"), 9876);
    let (s, fl) = run("CPT(D,FRD(A));", 0x1A);
    assert_eq!((i(&s, "D"), fl[2]), (0, true), "not BCD: overflow");
    // A FALSE rung computes nothing and leaves the flags.
    let (s, fl) = run("XIC(N) ADD(A,1,D);", 0);
    assert_eq!(i(&s, "D"), 0);
    assert_eq!(fl, [false; 4]);
}

#[test]
fn moves_and_logic() {
    let tags = &[("A", "DINT"), ("D", "DINT[8]"), ("I", "INT"), ("J", "INT")];
    let rungs = "MOV(A,D[0]);\nMVM(16#0000_FFFF,16#0000_00F0,D[1]);\nCLR(D[2]);\nAND(A,16#F0,D[3]);\nOR(A,1,D[4]);\nXOR(A,A,D[5]);\nNOT(A,D[6]);\nSWPB(16#1234_5678,REVERSE,D[7]);\nSWPB(16#1234,HIGH/LOW,J);\n";
    let mut s = ladder(tags, rungs);
    s.set("A", Value::Int(0x1234));
    s.scan();
    let d = |k: usize| i(&s, &format!("D[{k}]"));
    assert_eq!(d(0), 0x1234);
    assert_eq!(d(1), 0xF0);
    assert_eq!(d(2), 0);
    assert_eq!(d(3), 0x30);
    assert_eq!(d(4), 0x1235);
    assert_eq!(d(5), 0);
    assert_eq!(d(6), !0x1234);
    assert_eq!(d(7), 0x7856_3412);
    assert_eq!(i(&s, "J"), 0x3412);
    let mut s = ladder(&[("A", "DINT"), ("D", "DINT")], "BTD(A,4,D,8,4);\n");
    s.set("A", Value::Int(0xA0));
    s.set("D", Value::Int(0xFFFF));
    s.scan();
    assert_eq!(i(&s, "D"), 0xFAFF);
}

#[test]
fn bit_shifts_and_fifo_lifo_move_on_the_rung_transition() {
    let tags = &[
        ("A", "BOOL"),
        ("In", "BOOL"),
        ("Bits", "DINT[2]"),
        ("R1", "CONTROL"),
        ("Part", "DINT"),
        ("Fifo", "DINT[4]"),
        ("F1", "CONTROL"),
        ("Out", "DINT"),
        ("U", "BOOL"),
    ];
    let rungs = "XIC(A) BSL(Bits[0],R1,In,40);\nXIC(A) FFL(Part,Fifo[0],F1,3,0);\nXIC(U) FFU(Fifo[0],Out,F1,3,0);\n";
    let mut s = ladder(tags, rungs);
    assert_eq!(i(&s, "R1.LEN"), 40);
    // The prescan set FFL's .EN: a rung TRUE at the first scan loads
    // nothing; this one starts FALSE.
    s.scan();
    for k in 0..3 {
        set(&mut s, "In", k != 1);
        s.set("Part", Value::Int(10 + k));
        set(&mut s, "A", true);
        s.scan();
        s.scan(); // still TRUE: no second shift or load
        set(&mut s, "A", false);
        s.scan();
    }
    assert_eq!(i(&s, "Bits[0]"), 0b101, "bit 0 is the last shifted in");
    assert_eq!(i(&s, "F1.POS"), 3);
    assert!(b(&s, "F1.DN"));
    set(&mut s, "A", true);
    s.set("Part", Value::Int(99));
    s.scan();
    assert_eq!(i(&s, "F1.POS"), 3, "a full FIFO loads nothing");
    set(&mut s, "U", true);
    s.scan();
    assert_eq!(i(&s, "Out"), 10, "first in, first out");
    assert_eq!(i(&s, "F1.POS"), 2);
    assert_eq!((i(&s, "Fifo[0]"), i(&s, "Fifo[1]"), i(&s, "Fifo[2]")), (11, 12, 0));
    // 40 bits: bit 39 (word 1 bit 7) shifts out into UL after 40 shifts.
    let mut s = ladder(tags, "XIC(A) BSL(Bits[0],R1,In,40);\n");
    set(&mut s, "In", true);
    for _ in 0..40 {
        set(&mut s, "A", true);
        s.scan();
        set(&mut s, "A", false);
        s.scan();
    }
    assert_eq!(i(&s, "Bits[1]"), 0xFF);
    assert!(!b(&s, "R1.UL"));
    set(&mut s, "A", true);
    s.scan();
    assert!(b(&s, "R1.UL"));
    // LIFO: last in, first out.
    let rungs = "XIC(A) LFL(Part,Fifo[0],F1,4,0);\nXIC(U) LFU(Fifo[0],Out,F1,4,0);\n";
    let mut s = ladder(tags, rungs);
    for k in 0..2 {
        s.set("Part", Value::Int(k + 1));
        set(&mut s, "A", true);
        s.scan();
        set(&mut s, "A", false);
        s.scan();
    }
    set(&mut s, "U", true);
    s.scan();
    assert_eq!(i(&s, "Out"), 2);
}

#[test]
fn jumps_mcr_zones_afi_and_tnd() {
    let tags = &[("A", "BOOL"), ("Q", "BOOL[6]"), ("N", "DINT")];
    let rungs = "\
XIC(A) JMP(Skip);
OTE(Q[0]);
LBL(Skip) OTE(Q[1]);
XIC(A) MCR();
OTE(Q[2]);
MCR();
AFI() OTE(Q[3]);
XIO(A) TND();
OTE(Q[4]);
";
    let mut s = ladder(tags, rungs);
    s.scan();
    let q = |s: &Sandbox| (0..5).map(|k| b(s, &format!("Q[{k}]"))).collect::<Vec<_>>();
    assert_eq!(
        q(&s),
        [true, true, false, false, false],
        "A FALSE: no jump, the MCR zone runs FALSE, TND ends the routine"
    );
    set(&mut s, "A", true);
    s.scan();
    assert_eq!(
        q(&s),
        [true, true, true, false, true],
        "A TRUE: the jump skips rung 1 (Q[0] keeps its value); the zone runs; no TND"
    );
    // A backward jump loops (the watchdog bounds it).
    let mut s = ladder(&[("N", "DINT")], "LBL(Top) ADD(N,1,N);\nLES(N,10) JMP(Top);\n");
    s.scan();
    assert_eq!(i(&s, "N"), 10);
}

#[test]
fn malformed_rungs_are_one_line_errors_at_their_position() {
    let cases: &[(&str, &str)] = &[
        ("XIC(A) OTE(Q)\n", "Main.rll:1:13: the rung does not end with ';'"),
        ("XIC(A) [OTE(Q) ,OTE(R);\n", "Main.rll:1:8: this branch is never closed"),
        ("XIC(A) OTE(Q) ];\n", "Main.rll:1:15: ']' without its '['"),
        ("XIC(A) OTE(Q); OTE(R);\n", "Main.rll:1:16: text after the rung's ';'"),
        ("XIC(A) ,OTE(Q);\n", "',' outside a branch"),
        (
            "OTE(Q);\nXIC A OTE(Q);\n",
            "Main.rll:2:1: expected '(' after the instruction XIC",
        ),
        ("FOO(A);\n", "unknown ladder instruction 'FOO'"),
        (
            "MSG(A);\n",
            "MSG is a Logix instruction the twin does not simulate in ladder",
        ),
        ("XIC(A,Q);\n", "XIC takes 1 operand(s), got 2"),
        ("TON(A,?,?);\n", "TON takes a TIMER tag, got 'A'"),
        ("XIC(W);\n", "expected a BOOL or a bit"),
        ("JMP(Nowhere);\n", "no LBL Nowhere in this routine"),
        ("OTE(Q);\nXIC(A) LBL(X);\n", "LBL must be the rung's first instruction"),
        (
            "MOV(W+1,W);\n",
            "MOV's operand 'W+1' is an expression: a ladder operand is a tag or a number",
        ),
    ];
    for (rungs, want) in cases {
        let e = error(BITS, rungs);
        assert!(e.contains(want), "{rungs:?}: {e}");
    }
    // An expression nested too deep is reported as such, not echoed.
    let deep = format!("CPT(W,{}1{});\n", "(".repeat(40), ")".repeat(40));
    let e = error(BITS, &deep);
    assert!(e.contains("nested deeper than 32 levels"), "{e}");
    // Two display operands of one member that disagree.
    let e = Sandbox::ladder(&[], &[("T", "TIMER")], "TON(T,500,0);\nTOF(T,800,?);\n")
        .err()
        .expect("refused");
    assert!(
        e.contains("Main.rll:2:7: this display operand sets 800 where Main.rll:1:7 sets 500"),
        "{e}"
    );
}

#[test]
fn comments_and_blank_lines_are_skipped_and_rungs_number_from_zero() {
    let mut s = ladder(
        BITS,
        "# a comment\n\nXIC(A) OTE(Q);\n   # indented comment\nXIO(A) OTE(R);\n",
    );
    s.scan();
    assert!(!b(&s, "Q") && b(&s, "R"));
}

#[test]
fn motion_in_ladder_executes_on_the_transition_and_st_at_every_scan() {
    let tags = &[
        ("Go", "BOOL"),
        ("Mso1", "MOTION_INSTRUCTION"),
        ("Mam1", "MOTION_INSTRUCTION"),
        ("Ok", "BOOL"),
        ("En", "BOOL"),
        ("Dn", "BOOL"),
        ("Ip", "BOOL"),
    ];
    let rungs = "MSO(X,Mso1);\nXIC(Go) MAM(X,Mam1,0,100,50,Units per sec,1000,Units per sec2,1000,Units per sec2,Trapezoidal,100,100,% of Time,Disabled,0,0,None,0,0);\nXIC(Mso1.DN) OTE(Ok);\nXIC(Mam1.EN) OTE(En);\nXIC(Mam1.DN) OTE(Dn);\nXIC(Mam1.IP) OTE(Ip);\n";
    let mut s = Sandbox::ladder(&["X"], tags, rungs).unwrap_or_else(|e| panic!("{e}"));
    s.scan();
    assert!(b(&s, "Ok"));
    set(&mut s, "Go", true);
    s.scan();
    assert!(b(&s, "En") && b(&s, "Dn") && b(&s, "Ip"));
    // The rung stays TRUE: .EN stays set and the move is not restarted.
    for _ in 0..3 {
        s.scan();
        assert!(b(&s, "En") && b(&s, "Ip"));
    }
    set(&mut s, "Go", false);
    s.scan();
    assert!(!b(&s, "En"), "a FALSE rung clears .EN once .DN is set");
    assert!(b(&s, "Ip"), "the move goes on");
}

/// A scene of the indexing table with one 4 ms task whose program's
/// routines are the files `routines` (name with its extension, text).
fn scene_program(name: &str, tags: &[(&str, &str)], routines: &[(&str, &str)], extra: &str) -> Program {
    let dir = common::fresh_dir("ladder-tests", name);
    for (file, text) in routines {
        std::fs::write(dir.join(file), text).expect("routine");
    }
    let tags: String = tags
        .iter()
        .map(|(n, t)| format!("[[tags]]\nname = \"{n}\"\ntype = \"{t}\"\n"))
        .collect();
    let others: Vec<String> = routines[1..].iter().map(|(f, _)| format!("\"{f}\"")).collect();
    let text = format!(
        "{}{tags}[[tasks]]\nname = \"T\"\nperiod_ms = 4.0\npriority = 5\n[[tasks.programs]]\nname = \"P\"\nmain = \"{}\"\nroutines = [{}]\n{extra}\n",
        common::indexing_table_head(),
        routines[0].0,
        others.join(", ")
    );
    let path = dir.join("scene.toml");
    std::fs::write(&path, text).expect("scene");
    let scene = twin::scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
    let mut task = planner::task::MotionTask::new(scene.coarse_update_s()).unwrap();
    for a in &scene.axes {
        task.add_axis(a.config.clone(), 0.0).unwrap();
    }
    let mut program = Program::bind(&scene, &mut task).unwrap_or_else(|e| panic!("{e}"));
    for _ in 0..2 {
        program.scan(&mut task);
        task.update();
    }
    program
}

fn tag_value(p: &Program, name: &str) -> i64 {
    let mem = p.controller().memory();
    let t = mem.find(name).unwrap_or_else(|| panic!("no tag {name}"));
    mem.slots[mem.tags[t].base].as_i64()
}

#[test]
fn jsr_between_ladder_and_st_passes_parameters_and_keeps_the_callers_rung() {
    let main = "\
JSR(Inc,1,In,Out);
XIC(A)[JSR(Deep,0) ,XIC(B) ]OTE(Q);
XIO(A) JSR(Calc,1,Out,Twice);
";
    let inc = "SBR(X);\nADD(X,1,Y);\nRET(Y);\n";
    // Deep's own rungs leave their condition FALSE; the caller's rung
    // resumes with its own.
    let deep = "XIO(A) OTE(Seen);\nAFI() OTE(Never);\n";
    let calc = "SBR(V);\nRET(V * 2);\n";
    let tags = &[
        ("In", "DINT"),
        ("Out", "DINT"),
        ("Twice", "DINT"),
        ("X", "DINT"),
        ("Y", "DINT"),
        ("V", "DINT"),
        ("A", "BOOL"),
        ("B", "BOOL"),
        ("Q", "BOOL"),
        ("Seen", "BOOL"),
        ("Never", "BOOL"),
    ];
    let routines = [
        ("Main.rll", main),
        ("Inc.rll", inc),
        ("Deep.rll", deep),
        ("Calc.st", calc),
    ];
    let p = scene_program("jsr", tags, &routines, "");
    assert_eq!(tag_value(&p, "Out"), 1);
    assert_eq!(tag_value(&p, "Twice"), 2, "ST called from ladder");
    assert_eq!(tag_value(&p, "Q"), 0, "A FALSE: no JSR, Q FALSE");
    // A TRUE: the rung calls Deep and goes on TRUE after it.
    let extra = "[[tags]]\nname = \"One\"\ntype = \"BOOL\"\nvalue = true\n";
    let main = main
        .replace("XIC(A)[", "XIC(One)[")
        .replace("XIO(A) JSR", "XIO(One) JSR");
    let routines = [
        ("Main.rll", main.as_str()),
        ("Inc.rll", inc),
        ("Deep.rll", deep),
        ("Calc.st", calc),
    ];
    let p = scene_program("jsr_true", tags, &routines, extra);
    assert_eq!(tag_value(&p, "Q"), 1, "the caller's rung condition survives the call");
    assert_eq!(tag_value(&p, "Seen"), 1);
    assert_eq!(tag_value(&p, "Never"), 0);
}

#[test]
fn a_fault_in_a_rung_runs_the_fault_routine_and_the_rung_goes_on() {
    let main = "XIC(Go) MOV(9,Idx) MOV(1,Arr[Idx]) OTE(After);\n";
    // The fault routine clears the major fault record: the scan resumes
    // after the faulted instruction, on the same rung.
    let fault = "GSV(PROGRAM, THIS, MajorFaultRecord, Record[0]);\nRecord[2] := 0;\nSSV(PROGRAM, THIS, MajorFaultRecord, Record[0]);\nHandled := Handled + 1;\n";
    let tags = &[
        ("Go", "BOOL"),
        ("Idx", "DINT"),
        ("Arr", "DINT[4]"),
        ("After", "BOOL"),
        ("Record", "DINT[11]"),
        ("Handled", "DINT"),
    ];
    let extra = "fault_routine = \"Fault\"\n[[tags]]\nname = \"Go2\"\ntype = \"BOOL\"\nvalue = true\n";
    let main = main.replace("XIC(Go)", "XIC(Go2)");
    let p = scene_program(
        "fault",
        tags,
        &[("Main.rll", main.as_str()), ("Fault.st", fault)],
        extra,
    );
    assert!(
        p.controller().major_fault().is_none(),
        "{:?}",
        p.controller().major_fault()
    );
    assert_eq!(tag_value(&p, "Handled"), 2, "once a scan");
    assert_eq!(tag_value(&p, "After"), 1, "the rung went on TRUE after the faulted MOV");
}

#[test]
fn a_traced_rung_is_a_trace_column_of_its_condition_out() {
    let dir = common::fresh_dir("ladder-tests", "trace_rungs");
    std::fs::write(dir.join("Main.rll"), "XIC(T1.DN) OTE(Q);\nTON(T1,20,0);\n").unwrap();
    let text = format!(
        "{}[[tags]]\nname = \"T1\"\ntype = \"TIMER\"\n[[tags]]\nname = \"Q\"\ntype = \"BOOL\"\n\
         [[tasks]]\nname = \"T\"\nperiod_ms = 4.0\npriority = 5\n[[tasks.programs]]\nname = \"P\"\nmain = \"Main.rll\"\n\
         [trace]\nrungs = [\"P/Main:0\"]\n",
        common::indexing_table_head().replace("duration_s = 2.0", "duration_s = 0.1")
    );
    let scene = dir.join("scene.toml");
    std::fs::write(&scene, &text).unwrap();
    let trace = dir.join("trace.csv");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_twin"))
        .args(["run", "--no-render", "--trace"])
        .arg(&trace)
        .arg(&scene)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let csv = std::fs::read_to_string(&trace).unwrap();
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    let col = header.iter().position(|h| *h == "P/Main:0").expect("the rung's column");
    let col_t = header.iter().position(|h| *h == "time_s").expect("time_s");
    let rows: Vec<(f64, f64)> = csv
        .lines()
        .skip(1)
        .map(|l| {
            let cells: Vec<&str> = l.split(',').collect();
            (cells[col_t].parse().unwrap(), cells[col].parse().unwrap())
        })
        .collect();
    // TRUE from the scan after T1 is done (20 ms of timing from the first scan).
    let first_on = rows.iter().find(|(_, v)| *v == 1.0).expect("the rung turns TRUE").0;
    assert!((0.02..=0.03).contains(&first_on), "{first_on}");
    assert!(rows.iter().filter(|(t, _)| *t < 0.02).all(|(_, v)| *v == 0.0));
    // A rung that is not there.
    std::fs::write(&scene, text.replace("P/Main:0", "P/Main:7")).unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_twin"))
        .arg("check")
        .arg(&scene)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("trace.rungs[0]: 'P/Main:7' names no rung: P/Main has 2 rungs (0 to 1)"),
        "{err}"
    );
}

/// One instruction's row: its rung (`XIC(En)` before it makes the rung
/// condition), the tags, the values before the prescan, and what must
/// hold after the prescan, then after scans with `En` FALSE, TRUE, TRUE,
/// FALSE ("A=1 T.ACC=4"; empty: not checked). 4 ms a scan.
struct Row {
    rung: &'static str,
    tags: &'static [(&'static str, &'static str)],
    init: &'static str,
    phases: [&'static str; 5],
}

fn assign(s: &mut Sandbox, spec: &str) {
    for item in spec.split_whitespace() {
        let (name, v) = item.split_once('=').expect("name=value");
        let value = if v.contains('.') {
            Value::Real(v.parse().unwrap())
        } else {
            Value::Int(v.parse().unwrap())
        };
        s.set(name, value);
    }
}

fn check(s: &Sandbox, rung: &str, phase: &str, spec: &str) {
    for item in spec.split_whitespace() {
        let (name, v) = item.split_once('=').expect("name=value");
        let got = s.value(name).unwrap_or_else(|| panic!("{rung}: no {name}"));
        let want: f64 = v.parse().unwrap();
        assert!(
            (got.as_f64() - want).abs() < 1e-9,
            "{rung}, {phase}: {name} = {got:?}, want {v}"
        );
    }
}

const TMR: &[(&str, &str)] = &[("En", "BOOL"), ("T", "TIMER"), ("Q", "BOOL")];
const CNT: &[(&str, &str)] = &[("En", "BOOL"), ("C", "COUNTER"), ("Q", "BOOL")];
const BIT: &[(&str, &str)] = &[
    ("En", "BOOL"),
    ("Q", "BOOL"),
    ("S", "BOOL"),
    ("O", "BOOL"),
    ("B", "BOOL"),
];
const NUM: &[(&str, &str)] = &[
    ("En", "BOOL"),
    ("Q", "BOOL"),
    ("A", "DINT"),
    ("D", "DINT"),
    ("R", "REAL"),
    ("N", "BOOL"),
    ("Z", "BOOL"),
    ("V", "BOOL"),
];
const ARR: &[(&str, &str)] = &[
    ("En", "BOOL"),
    ("B", "BOOL"),
    ("A", "DINT"),
    ("D", "DINT"),
    ("Arr", "DINT[4]"),
    ("Ctl", "CONTROL"),
];

/// 1756-RM003's Execution rows, instruction by instruction.
const ROWS: &[Row] = &[
    // Bit: input instructions pass the condition AND the bit.
    Row {
        rung: "XIC(En) XIC(B) OTE(Q);",
        tags: BIT,
        init: "B=1",
        phases: ["Q=0", "Q=0", "Q=1", "Q=1", "Q=0"],
    },
    Row {
        rung: "XIC(En) XIO(B) OTE(Q);",
        tags: BIT,
        init: "B=1",
        phases: ["", "Q=0", "Q=0", "Q=0", "Q=0"],
    },
    Row {
        rung: "XIC(En) OTE(Q);",
        tags: BIT,
        init: "Q=1",
        phases: ["Q=0", "Q=0", "Q=1", "Q=1", "Q=0"],
    },
    Row {
        rung: "XIC(En) OTL(Q);",
        tags: BIT,
        init: "Q=0",
        phases: ["Q=0", "Q=0", "Q=1", "Q=1", "Q=1"],
    },
    Row {
        rung: "XIC(En) OTU(Q);",
        tags: BIT,
        init: "Q=1",
        phases: ["Q=1", "Q=1", "Q=0", "Q=0", "Q=0"],
    },
    Row {
        rung: "XIC(En) ONS(S) OTE(Q);",
        tags: BIT,
        init: "",
        phases: ["S=1", "S=0 Q=0", "S=1 Q=1", "S=1 Q=0", "S=0 Q=0"],
    },
    Row {
        rung: "XIC(En) OSR(S,O) OTE(Q);",
        tags: BIT,
        init: "O=1",
        phases: ["S=1 O=0", "S=0 O=0 Q=0", "S=1 O=1 Q=1", "O=0 Q=1", "S=0 O=0"],
    },
    Row {
        rung: "XIC(En) OSF(S,O) OTE(Q);",
        tags: BIT,
        init: "S=1 O=1",
        phases: ["S=0 O=0", "O=0 Q=0", "S=1 O=0 Q=1", "S=1 O=0", "S=0 O=1 Q=0"],
    },
    // Timers: 4 ms a scan; PRE 8.
    Row {
        rung: "XIC(En) TON(T,8,0) XIC(T.DN) OTE(Q);",
        tags: TMR,
        init: "T.ACC=3 T.EN=1",
        phases: [
            "T.EN=0 T.TT=0 T.DN=0 T.ACC=0 T.PRE=8",
            "T.EN=0 T.ACC=0",
            "T.EN=1 T.TT=1 T.ACC=0 Q=0",
            "T.TT=1 T.ACC=4",
            "T.EN=0 T.TT=0 T.DN=0 T.ACC=0",
        ],
    },
    Row {
        rung: "XIC(En) TOF(T,8,0);",
        tags: TMR,
        init: "",
        phases: [
            "T.EN=0 T.DN=0 T.ACC=8",
            "T.EN=0 T.TT=0 T.DN=0",
            "T.EN=1 T.DN=1 T.TT=0 T.ACC=0",
            "T.EN=1 T.DN=1",
            "T.EN=0 T.TT=1 T.DN=1 T.ACC=0",
        ],
    },
    // RTO keeps ACC through the prescan and a FALSE rung.
    Row {
        rung: "XIC(En) RTO(T,8,0);",
        tags: TMR,
        init: "T.ACC=5 T.DN=1 T.EN=1 T.TT=1",
        phases: [
            "T.EN=0 T.TT=0 T.DN=0 T.ACC=5",
            "T.ACC=5",
            "T.EN=1 T.TT=1 T.ACC=5",
            "T.ACC=8 T.DN=1 T.TT=0",
            "T.EN=0 T.TT=0 T.ACC=8 T.DN=1",
        ],
    },
    Row {
        rung: "XIC(En) RES(T);",
        tags: TMR,
        init: "T.ACC=5 T.DN=1",
        phases: ["T.ACC=5 T.DN=1", "T.ACC=5", "T.ACC=0 T.DN=0", "", ""],
    },
    // Counters: the prescan sets CU/CD, so a TRUE first scan counts nothing.
    Row {
        rung: "XIC(En) CTU(C,2,0);",
        tags: CNT,
        init: "",
        phases: [
            "C.CU=1 C.PRE=2",
            "C.CU=0 C.ACC=0",
            "C.CU=1 C.ACC=1 C.DN=0",
            "C.ACC=1",
            "C.CU=0 C.ACC=1",
        ],
    },
    Row {
        rung: "XIC(En) CTD(C,-1,0);",
        tags: CNT,
        init: "",
        phases: [
            "C.CD=1",
            "C.CD=0 C.ACC=0 C.DN=1",
            "C.CD=1 C.ACC=-1 C.DN=1",
            "C.ACC=-1",
            "C.CD=0",
        ],
    },
    // Compare: the rung goes on with the test.
    Row {
        rung: "XIC(En) EQU(A,3) OTE(Q);",
        tags: NUM,
        init: "A=3",
        phases: ["", "Q=0", "Q=1", "Q=1", "Q=0"],
    },
    Row {
        rung: "XIC(En) NEQ(A,3) OTE(Q);",
        tags: NUM,
        init: "A=3",
        phases: ["", "Q=0", "Q=0", "Q=0", "Q=0"],
    },
    Row {
        rung: "XIC(En) LES(A,4) OTE(Q);",
        tags: NUM,
        init: "A=3",
        phases: ["", "", "Q=1", "", "Q=0"],
    },
    Row {
        rung: "XIC(En) LEQ(A,3) OTE(Q);",
        tags: NUM,
        init: "A=3",
        phases: ["", "", "Q=1", "", "Q=0"],
    },
    Row {
        rung: "XIC(En) GRT(A,3) OTE(Q);",
        tags: NUM,
        init: "A=3",
        phases: ["", "", "Q=0", "", ""],
    },
    Row {
        rung: "XIC(En) GEQ(A,3.0) OTE(Q);",
        tags: NUM,
        init: "A=3",
        phases: ["", "", "Q=1", "", "Q=0"],
    },
    Row {
        rung: "XIC(En) LIM(1,A,5) OTE(Q);",
        tags: NUM,
        init: "A=3",
        phases: ["", "", "Q=1", "", "Q=0"],
    },
    Row {
        rung: "XIC(En) LIM(5,A,1) OTE(Q);",
        tags: NUM,
        init: "A=3",
        phases: ["", "", "Q=0", "", ""],
    },
    Row {
        rung: "XIC(En) MEQ(A,16#F,16#13) OTE(Q);",
        tags: NUM,
        init: "A=3",
        phases: ["", "", "Q=1", "", "Q=0"],
    },
    Row {
        rung: "XIC(En) CMP(A * 2 > 5) OTE(Q);",
        tags: NUM,
        init: "A=3",
        phases: ["", "", "Q=1", "", "Q=0"],
    },
    // Math: Dest on a TRUE rung, with the flags; nothing on a FALSE one.
    Row {
        rung: "XIC(En) ADD(A,D,D) XIC(S:Z) OTE(Z);",
        tags: NUM,
        init: "A=3",
        phases: ["D=0", "D=0", "D=3 Z=0", "D=6", "D=6"],
    },
    Row {
        rung: "XIC(En) SUB(D,A,D) XIC(S:N) OTE(N);",
        tags: NUM,
        init: "A=3",
        phases: ["", "D=0", "D=-3 N=1", "D=-6 N=1", "D=-6"],
    },
    Row {
        rung: "XIC(En) MUL(A,1000000000,D) XIC(S:V) OTE(V);",
        tags: NUM,
        init: "A=3",
        phases: ["", "D=0 V=0", "V=1", "", ""],
    },
    Row {
        rung: "XIC(En) DIV(A,2,D);",
        tags: NUM,
        init: "A=7",
        phases: ["", "D=0", "D=3", "", ""],
    },
    Row {
        rung: "XIC(En) DIV(A,2.0,D);",
        tags: NUM,
        init: "A=7",
        phases: ["", "", "D=4", "", ""],
    },
    Row {
        rung: "XIC(En) MOD(A,4,D);",
        tags: NUM,
        init: "A=7",
        phases: ["", "", "D=3", "", ""],
    },
    Row {
        rung: "XIC(En) NEG(A,D);",
        tags: NUM,
        init: "A=7",
        phases: ["", "", "D=-7", "", ""],
    },
    Row {
        rung: "XIC(En) ABS(A,D);",
        tags: NUM,
        init: "A=-7",
        phases: ["", "", "D=7", "", ""],
    },
    Row {
        rung: "XIC(En) SQR(A,R);",
        tags: NUM,
        init: "A=16",
        phases: ["", "R=0.0", "R=4.0", "", ""],
    },
    Row {
        rung: "XIC(En) CPT(R,A ** 2 / 4.0);",
        tags: NUM,
        init: "A=3",
        phases: ["", "", "R=2.25", "", ""],
    },
    // The math functions as instructions, and XPY.
    Row {
        rung: "XIC(En) XPY(A,2,D);",
        tags: NUM,
        init: "A=3",
        phases: ["", "D=0", "D=9", "", ""],
    },
    Row {
        rung: "XIC(En) TRN(R,D);",
        tags: NUM,
        init: "R=2.7",
        phases: ["", "", "D=2", "", ""],
    },
    Row {
        rung: "XIC(En) TOD(A,D);",
        tags: NUM,
        init: "A=12",
        phases: ["", "", "D=18", "", ""],
    },
    Row {
        rung: "XIC(En) FRD(A,D);",
        tags: NUM,
        init: "A=18",
        phases: ["", "", "D=12", "", ""],
    },
    Row {
        rung: "XIC(En) COS(R,R);",
        tags: NUM,
        init: "R=0.0",
        phases: ["", "R=0.0", "R=1.0", "", ""],
    },
    // Move and logic.
    Row {
        rung: "XIC(En) MOV(A,D);",
        tags: NUM,
        init: "A=9",
        phases: ["", "D=0", "D=9", "", ""],
    },
    Row {
        rung: "XIC(En) MVM(A,16#F0,D);",
        tags: NUM,
        init: "A=255 D=1",
        phases: ["", "D=1", "D=241", "", ""],
    },
    Row {
        rung: "XIC(En) CLR(D);",
        tags: NUM,
        init: "D=9",
        phases: ["", "D=9", "D=0", "", ""],
    },
    Row {
        rung: "XIC(En) AND(A,6,D);",
        tags: NUM,
        init: "A=3",
        phases: ["", "", "D=2", "", ""],
    },
    Row {
        rung: "XIC(En) OR(A,4,D);",
        tags: NUM,
        init: "A=3",
        phases: ["", "", "D=7", "", ""],
    },
    Row {
        rung: "XIC(En) XOR(A,1,D);",
        tags: NUM,
        init: "A=3",
        phases: ["", "", "D=2", "", ""],
    },
    Row {
        rung: "XIC(En) NOT(A,D);",
        tags: NUM,
        init: "A=3",
        phases: ["", "", "D=-4", "", ""],
    },
    Row {
        rung: "XIC(En) SWPB(A,WORD,D);",
        tags: NUM,
        init: "A=1",
        phases: ["", "", "D=65536", "", ""],
    },
    Row {
        rung: "XIC(En) BTD(A,0,D,2,2);",
        tags: NUM,
        init: "A=3",
        phases: ["", "", "D=12", "", ""],
    },
    // Shift, FIFO and LIFO act on the rise.
    Row {
        rung: "XIC(En) BSL(Arr[0],Ctl,B,3);",
        tags: ARR,
        init: "B=1 Ctl.EN=1",
        phases: [
            "Ctl.EN=0 Ctl.LEN=3",
            "Ctl.EN=0 Ctl.DN=0",
            "Arr[0]=1 Ctl.EN=1 Ctl.DN=1",
            "Arr[0]=1",
            "Ctl.EN=0 Ctl.DN=0",
        ],
    },
    Row {
        rung: "XIC(En) BSR(Arr[0],Ctl,B,3);",
        tags: ARR,
        init: "B=1",
        phases: ["", "", "Arr[0]=4", "Arr[0]=4", ""],
    },
    Row {
        rung: "XIC(En) FFL(A,Arr[0],Ctl,4,0);",
        tags: ARR,
        init: "A=5",
        phases: [
            "Ctl.EN=1",
            "Ctl.EN=0 Ctl.POS=0 Ctl.EM=1",
            "Arr[0]=5 Ctl.POS=1 Ctl.EM=0",
            "Ctl.POS=1",
            "Ctl.EN=0",
        ],
    },
    Row {
        rung: "XIC(En) FFU(Arr[0],D,Ctl,4,2);",
        tags: ARR,
        init: "Arr[0]=7 Arr[1]=8",
        phases: [
            "Ctl.EU=1 Ctl.POS=2",
            "Ctl.EU=0",
            "D=7 Arr[0]=8 Arr[1]=0 Ctl.POS=1",
            "Ctl.POS=1",
            "Ctl.EU=0",
        ],
    },
    Row {
        rung: "XIC(En) LFL(A,Arr[0],Ctl,4,1);",
        tags: ARR,
        init: "A=5",
        phases: ["Ctl.EN=1", "", "Arr[1]=5 Ctl.POS=2", "Ctl.POS=2", ""],
    },
    Row {
        rung: "XIC(En) LFU(Arr[0],D,Ctl,4,2);",
        tags: ARR,
        init: "Arr[0]=7 Arr[1]=8",
        phases: ["Ctl.EU=1", "", "D=8 Arr[1]=0 Ctl.POS=1", "", ""],
    },
    // Program control.
    Row {
        rung: "XIC(En) AFI() OTE(Q);",
        tags: BIT,
        init: "",
        phases: ["", "Q=0", "Q=0", "Q=0", "Q=0"],
    },
    Row {
        rung: "XIC(En) NOP() OTE(Q);",
        tags: BIT,
        init: "",
        phases: ["", "Q=0", "Q=1", "Q=1", "Q=0"],
    },
];

#[test]
fn every_instruction_on_a_true_rung_a_false_rung_and_at_prescan() {
    let phase_names = ["prescan", "FALSE scan", "TRUE scan", "second TRUE scan", "FALSE again"];
    for row in ROWS {
        let mut s =
            Sandbox::ladder(&[], row.tags, &format!("{}\n", row.rung)).unwrap_or_else(|e| panic!("{}: {e}", row.rung));
        assign(&mut s, row.init);
        s.prescan();
        check(&s, row.rung, phase_names[0], row.phases[0]);
        for (k, en) in [false, true, true, false].into_iter().enumerate() {
            s.set("En", Value::Bool(en));
            s.scan();
            check(&s, row.rung, phase_names[k + 1], row.phases[k + 1]);
        }
        assert!(
            s.controller().major_fault().is_none(),
            "{}: {:?}",
            row.rung,
            s.controller().major_fault()
        );
    }
}

#[test]
fn twin_check_names_a_rung_that_writes_an_input_tag() {
    let dir = common::fresh_dir("ladder-tests", "input_write");
    std::fs::write(dir.join("Main.rll"), "XIC(Go) OTE(DI.2);\nXIC(Go) MOV(0,DI);\n").unwrap();
    let text = format!(
        "{}[[tags]]\nname = \"DI\"\ntype = \"DINT\"\n[[tags]]\nname = \"Go\"\ntype = \"BOOL\"\n\
         [[sensors]]\nname = \"PE\"\nkind = \"beam\"\ntag = \"DI.2\"\nfrom = [0.0, -0.2, 0.6]\nto = [0.0, 0.2, 0.6]\n\
         [[tasks]]\nname = \"T\"\nperiod_ms = 4.0\npriority = 5\n[[tasks.programs]]\nname = \"P\"\nmain = \"Main.rll\"\n",
        common::indexing_table_head()
    );
    let scene = dir.join("scene.toml");
    std::fs::write(&scene, text).unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_twin"))
        .arg("check")
        .arg(&scene)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(stdout.contains("Main.rll:1:13 writes the input tag DI.2"), "{stdout}");
    assert!(stdout.contains("Main.rll:2:15 writes the input tag DI.2"), "{stdout}");
}

#[test]
fn the_string_instructions_run_on_a_true_rung() {
    let tags = &[("En", "BOOL"), ("A", "DINT"), ("S1", "STRING"), ("S3", "STRING")];
    let mut s = ladder(tags, "XIC(En) DTOS(A,S1) CONCAT(S1,S1,S3);\n");
    s.set("A", Value::Int(427));
    s.scan();
    assert_eq!(i(&s, "S3.LEN"), 0, "a FALSE rung: nothing");
    s.set("En", Value::Bool(true));
    s.scan();
    assert_eq!(i(&s, "S1.LEN"), 3);
    assert_eq!(i(&s, "S3.LEN"), 6);
}
