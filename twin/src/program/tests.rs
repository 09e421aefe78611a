//! The language suite: each row a routine with known results, run by the
//! task engine against tag memory and a planner without a plant.

use super::types::Value;
use super::*;
use crate::scene;
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};

static RUN: AtomicUsize = AtomicUsize::new(0);

/// A scene with `tags` (TOML `[[tags]]` entries), one task of period
/// `period_ms` and one program whose main routine is `routine`.
pub(crate) fn scene_with(tags: &str, routine: &str, period_ms: f64) -> Result<Scene, String> {
    scene_of(tags, &[("Main", routine)], "", period_ms)
}

/// As [`scene_with`], with more routines (the first is the main one, each
/// written to `<name>.st`) and `program` appended to the program's table
/// (its `[[tasks.programs.tags]]`, say).
pub(crate) fn scene_of(tags: &str, routines: &[(&str, &str)], program: &str, period_ms: f64) -> Result<Scene, String> {
    let dir = std::env::temp_dir().join(format!(
        "twin-plc-{}-{}",
        std::process::id(),
        RUN.fetch_add(1, Ordering::Relaxed)
    ));
    std::fs::create_dir_all(&dir).map_err(|e| e.to_string())?;
    for (name, text) in routines {
        std::fs::write(dir.join(format!("{name}.st")), text).map_err(|e| e.to_string())?;
    }
    let called: Vec<String> = routines[1..].iter().map(|(n, _)| format!("\"{n}.st\"")).collect();
    let urdf = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/robots/indexing_table.urdf");
    let text = format!(
        "duration_s = 1.0\ncoarse_update_ms = 4.0\nphysics_step_ms = 1.0\n\
         [robot]\nurdf = {urdf:?}\n\
         [[axes]]\nname = \"Table\"\njoint = \"platter_joint\"\nkind = \"rotary\"\nunits = \"deg\"\n\
         max_velocity = 720.0\nmax_acceleration = 3600.0\nmax_deceleration = 3600.0\nmax_jerk = 36000.0\n\
         in_position_window = 0.1\n\
         {tags}\n\
         [[tasks]]\nname = \"T\"\nperiod_ms = {period_ms:?}\npriority = 5\n\
         [[tasks.programs]]\nname = \"P\"\nmain = \"{main}.st\"\nroutines = [{called}]\n{program}",
        main = routines[0].0,
        called = called.join(", "),
    );
    let path = dir.join("scene.toml");
    std::fs::write(&path, &text).map_err(|e| e.to_string())?;
    scene::parse(&path, &text).map_err(|e| e.to_string())
}

/// The task engine of `scene`, bound to a planner with its axes.
pub(crate) fn bound(scene: &Scene) -> Result<(Controller, MotionTask), String> {
    let mut task = MotionTask::new(scene.coarse_update_s()).map_err(|e| e.to_string())?;
    for a in &scene.axes {
        task.add_axis(a.config.clone(), 0.0).map_err(|e| e.to_string())?;
    }
    let program = Program::bind(scene, &mut task).map_err(|e| e.to_string())?;
    Ok((program.plc, task))
}

pub(crate) struct Run {
    pub(crate) plc: Controller,
    pub(crate) task: MotionTask,
}

impl Run {
    pub(crate) fn new(tags: &str, routine: &str) -> Result<Run, String> {
        let scene = scene_with(tags, routine, 4.0)?;
        let (plc, task) = bound(&scene)?;
        Ok(Run { plc, task })
    }

    /// Runs `n` scans, one per coarse update.
    pub(crate) fn scans(&mut self, n: usize) -> &mut Self {
        for _ in 0..n {
            self.plc.scan(&mut self.task);
            self.task.update();
        }
        self
    }

    pub(crate) fn get(&self, name: &str) -> Value {
        let mem = self.plc.memory();
        let t = mem.resolve(Some("P"), name).unwrap_or_else(|| panic!("no tag {name}"));
        mem.slots[mem.tags[t].base]
    }

    pub(crate) fn elem(&self, name: &str, i: usize) -> Value {
        let mem = self.plc.memory();
        let t = mem.resolve(Some("P"), name).unwrap_or_else(|| panic!("no tag {name}"));
        mem.slots[mem.tags[t].base + i]
    }

    pub(crate) fn member(&self, name: &str, member: &str) -> Value {
        let mem = self.plc.memory();
        let t = mem.resolve(Some("P"), name).unwrap_or_else(|| panic!("no tag {name}"));
        let memory::Kind::Structure(s) = mem.tags[t].kind else {
            panic!("{name} is no structure")
        };
        mem.slots[mem.tags[t].base + s.offset(member)]
    }
}

fn tag(name: &str, ty: &str) -> String {
    format!("[[tags]]\nname = \"{name}\"\ntype = \"{ty}\"\n")
}

fn int(v: Value) -> i64 {
    match v {
        Value::Int(i) => i,
        other => panic!("not an integer: {other:?}"),
    }
}

/// One scan of `routine` with DINT tags `A`..`F`, REAL tags `X`, `Y` and a
/// BOOL `B`.
fn one_scan(routine: &str) -> Run {
    let tags: String = ["A", "B2", "C", "D", "E", "F"]
        .iter()
        .map(|n| tag(n, "DINT"))
        .chain([tag("X", "REAL"), tag("Y", "REAL"), tag("B", "BOOL"), tag("L", "LREAL")])
        .collect();
    let mut run = Run::new(&tags, routine).unwrap_or_else(|e| panic!("{routine}: {e}"));
    run.scans(1);
    run
}

#[test]
fn integer_arithmetic_wraps_truncates_and_faults() {
    let rows: [(&str, i64, i64); 12] = [
        ("A := 2147483647; A := A + 1;", -2_147_483_648, 1),
        ("A := 7 / 2;", 3, 0),
        ("A := -7 / 2;", -3, 0),
        ("A := -7 MOD 2;", -1, 0),
        ("A := 7 MOD -2;", 1, 0),
        ("C := 0; A := 5 / C;", 2_147_483_647, 1),
        ("C := 0; A := -5 / C;", -2_147_483_647, 1),
        ("C := 0; A := 5 MOD C;", 0, 1),
        ("A := -2147483647 - 2;", 2_147_483_647, 1),
        ("A := ABS(-2147483647 - 1);", -2_147_483_648, 1),
        ("A := 16#7FFF_FFFF;", 2_147_483_647, 0),
        ("A := 2#1010 + 8#17;", 25, 0),
    ];
    for (routine, want, faults) in rows {
        let run = one_scan(routine);
        assert_eq!(int(run.get("A")), want, "{routine}");
        assert_eq!(run.plc.minor_fault_count(), faults, "{routine}");
        for f in run.plc.minor_faults() {
            assert_eq!((f.fault_type, f.code, f.major), (4, 4, false), "{routine}: {f}");
            assert!(f.message.starts_with("arithmetic overflow: "), "{routine}: {f}");
            assert_eq!(f.line, 1, "{routine}: {f}");
        }
    }
}

#[test]
fn real_to_integer_rounds_half_to_even_on_assignment() {
    for (x, want) in [
        ("-2.5", -2),
        ("-1.5", -2),
        ("1.5", 2),
        ("2.5", 2),
        ("0.5", 0),
        ("3.7", 4),
    ] {
        let run = one_scan(&format!("X := {x}; A := X;"));
        assert_eq!(int(run.get("A")), want, "{x}");
    }
    let run = one_scan("X := 3.0E9; A := X;");
    assert_eq!(run.plc.minor_fault_count(), 1, "REAL past DINT");
}

#[test]
fn precedence_of_the_logix_table() {
    let rows: [(&str, i64); 10] = [
        ("A := 2 + 3 * 4;", 14),
        ("A := (2 + 3) * 4;", 20),
        ("A := 10 - 4 - 3;", 3),
        ("A := -2 ** 2;", -4),
        ("A := 2 ** 3 ** 2;", 64),
        ("A := 7 MOD 4 * 2;", 6),
        ("B := 1 < 2 = 3 < 4; A := B;", 1),
        ("B := NOT 1 = 2; A := B;", 0),
        ("B := TRUE OR FALSE AND FALSE; A := B;", 1),
        ("B := TRUE XOR TRUE OR TRUE; A := B;", 1),
    ];
    for (routine, want) in rows {
        let run = one_scan(routine);
        assert_eq!(run.get("A").as_i64(), want, "{routine}");
    }
}

#[test]
fn reals_compute_in_single_precision_and_lreal_in_double() {
    let run = one_scan("X := 0.1; Y := X + 0.2; L := 0.1; L := L + 0.2;");
    assert_eq!(run.get("Y"), Value::Real(f64::from(0.1f32 + 0.2f32)));
    assert_eq!(run.get("L"), Value::Real(f64::from(0.1f32) + f64::from(0.2f32)));
    let run = one_scan("X := SQRT(-16.0); Y := TRUNC(-2.7); A := TRUNC(2.7);");
    assert_eq!(run.get("X"), Value::Real(4.0));
    assert_eq!(run.get("Y"), Value::Real(-2.0));
    assert_eq!(int(run.get("A")), 2);
    let run = one_scan("X := DEG(3.14159265); Y := RAD(180.0);");
    assert!((run.get("X").as_f64() - 180.0).abs() < 1e-3);
    assert!((run.get("Y").as_f64() - std::f64::consts::PI).abs() < 1e-6);
    let run = one_scan("X := 1.0 / 0.0;");
    assert_eq!(run.plc.minor_fault_count(), 1);
}

#[test]
fn control_flow_case_ranges_loops_and_exit() {
    let rows: [(&str, i64); 9] = [
        (
            "C := 5; CASE C OF 1: A := 1; 2, 3: A := 2; 4..6: A := 3; ELSE A := 4; END_CASE;",
            3,
        ),
        (
            "C := 3; CASE C OF 1: A := 1; 2, 3: A := 2; 4..6: A := 3; ELSE A := 4; END_CASE;",
            2,
        ),
        ("C := 9; CASE C OF 1: A := 1; 4..6: A := 3; ELSE A := 4; END_CASE;", 4),
        ("C := -2; CASE C OF -3..-1: A := 7; END_CASE;", 7),
        ("A := 0; FOR C := 1 TO 10 DO A := A + C; END_FOR;", 55),
        ("A := 0; FOR C := 10 TO 1 BY -3 DO A := A + C; END_FOR;", 22),
        (
            "A := 0; FOR C := 1 TO 100 DO IF C > 4 THEN EXIT; END_IF; A := A + 1; END_FOR;",
            4,
        ),
        ("A := 0; WHILE A < 7 DO A := A + 2; END_WHILE;", 8),
        ("A := 10; REPEAT A := A - 3; UNTIL A < 0 END_REPEAT;", -2),
    ];
    for (routine, want) in rows {
        assert_eq!(int(one_scan(routine).get("A")), want, "{routine}");
    }
    let run = one_scan("IF FALSE THEN A := 1; ELSIF TRUE THEN A := 2; ELSE A := 3; END_IF;");
    assert_eq!(int(run.get("A")), 2);
}

#[test]
fn bit_access_by_number_and_by_expression() {
    let run = one_scan("A := 0; A.5 := TRUE; C := 3; A.[C] := 1; B := A.5; D := A;");
    assert_eq!(int(run.get("D")), 40);
    assert_eq!(run.get("B"), Value::Bool(true));
    let run = one_scan("A := -1; A.31 := FALSE; D := A;");
    assert_eq!(int(run.get("D")), i64::from(i32::MAX));
}

#[test]
fn non_retentive_assignment_is_cleared_at_prescan_only() {
    let tags = format!("{}{}", tag("N", "DINT"), tag("K", "DINT"));
    let routine = "IF S:FS THEN K := N; END_IF; N [:=] N + 1;";
    let mut run = Run::new(
        &tags.replace("type = \"DINT\"\n", "type = \"DINT\"\nvalue = 40\n"),
        routine,
    )
    .unwrap();
    run.scans(3);
    assert_eq!(int(run.get("K")), 0, "prescan cleared N before the first scan");
    assert_eq!(int(run.get("N")), 3);
}

#[test]
fn tonr_accumulates_only_while_executed() {
    let tags = format!("{}{}", tag("T1", "FBD_TIMER"), tag("Run", "BOOL"));
    let routine = "T1.PRE := 100; T1.TimerEnable := TRUE; IF Run THEN TONR(T1); END_IF; Run := TRUE;";
    let mut run = Run::new(&tags, routine).unwrap();
    // First execution at the 2nd scan (4 ms): starts timing.
    run.scans(2);
    assert_eq!(int(run.member("T1", "ACC")), 0);
    assert_eq!(run.member("T1", "TT"), Value::Bool(true));
    run.scans(10);
    assert_eq!(int(run.member("T1", "ACC")), 40);
    run.scans(20);
    assert_eq!(int(run.member("T1", "ACC")), 100, "held at PRE");
    assert_eq!(run.member("T1", "DN"), Value::Bool(true));
    assert_eq!(run.member("T1", "TT"), Value::Bool(false));
}

#[test]
fn tofr_and_rtor_histories() {
    let tags = format!(
        "{}{}{}",
        tag("T1", "FBD_TIMER"),
        tag("T2", "FBD_TIMER"),
        tag("On", "BOOL")
    );
    let routine = "T1.PRE := 20; T1.TimerEnable := On; TOFR(T1);\n\
                   T2.PRE := 20; T2.TimerEnable := On; RTOR(T2);";
    let mut run = Run::new(
        &tags.replace(
            "name = \"On\"\ntype = \"BOOL\"\n",
            "name = \"On\"\ntype = \"BOOL\"\nvalue = true\n",
        ),
        routine,
    )
    .unwrap();
    run.scans(3);
    assert_eq!(run.member("T1", "DN"), Value::Bool(true), "TOFR on at once");
    assert_eq!(int(run.member("T2", "ACC")), 8);
    let on = run.plc.memory().tags[run.plc.memory().find("On").unwrap()].base;
    run.plc.memory_mut().slots[on] = Value::Bool(false);
    run.scans(3);
    assert_eq!(run.member("T1", "DN"), Value::Bool(true), "TOFR times the off delay");
    assert_eq!(int(run.member("T2", "ACC")), 8, "RTOR keeps ACC");
    run.scans(5);
    assert_eq!(run.member("T1", "DN"), Value::Bool(false));
    assert_eq!(int(run.member("T1", "ACC")), 20);
}

#[test]
fn ctud_counts_edges_and_osri_pulses_once() {
    let tags = format!(
        "{}{}{}{}",
        tag("C1", "FBD_COUNTER"),
        tag("O1", "FBD_ONESHOT"),
        tag("N", "DINT"),
        tag("Pulses", "DINT")
    );
    let routine = "N := N + 1;\n\
                   C1.PRE := 2; C1.CUEnable := (N MOD 2) = 0; C1.CDEnable := N = 7; CTUD(C1);\n\
                   O1.InputBit := N >= 3; OSRI(O1); IF O1.OutputBit THEN Pulses := Pulses + 1; END_IF;";
    let mut run = Run::new(&tags, routine).unwrap();
    run.scans(8);
    // Rising CUEnable at N = 2, 4, 6, 8; CDEnable rises at N = 7.
    assert_eq!(int(run.member("C1", "ACC")), 3);
    assert_eq!(run.member("C1", "DN"), Value::Bool(true));
    assert_eq!(int(run.get("Pulses")), 1, "one pulse");
}

#[test]
fn osri_gives_no_pulse_on_the_first_scan_when_the_input_is_already_true() {
    let tags = format!("{}{}", tag("O1", "FBD_ONESHOT"), tag("Pulses", "DINT"));
    let mut run = Run::new(
        &tags,
        "O1.InputBit := TRUE; OSRI(O1); IF O1.OutputBit THEN Pulses := Pulses + 1; END_IF;",
    )
    .unwrap();
    run.scans(3);
    assert_eq!(int(run.get("Pulses")), 0);
}

#[test]
fn jsr_passes_parameters_and_returns_values() {
    let tags = format!("{}{}{}", tag("A", "DINT"), tag("C", "DINT"), tag("D", "DINT"));
    let routines = [
        ("Main", "JSR(Twice, 1, 21, A);"),
        ("Twice", "SBR(C); D := C * 2; RET(D);"),
    ];
    let scene = scene_of(&tags, &routines, "", 4.0).unwrap();
    let (mut plc, mut task) = bound(&scene).unwrap();
    plc.scan(&mut task);
    let a = plc.memory().find("A").unwrap();
    assert_eq!(plc.memory().slots[plc.memory().tags[a].base], Value::Int(42));
}

#[test]
fn cop_fll_and_size() {
    let tags = format!("{}{}{}", tag("Src", "DINT[4]"), tag("Dst", "DINT[4]"), tag("A", "DINT"));
    let run = {
        let mut r = Run::new(
            &tags,
            "FLL(7, Src[0], 4); Src[1] := 1; COP(Src[1], Dst[0], 3); SIZE(Dst, 0, A);",
        )
        .unwrap();
        r.scans(1);
        r
    };
    assert_eq!(
        (0..4).map(|i| int(run.elem("Dst", i))).collect::<Vec<_>>(),
        vec![1, 7, 7, 0]
    );
    assert_eq!(int(run.get("A")), 4);
}

#[test]
fn program_tags_shadow_controller_tags() {
    let program_tag = "[[tasks.programs.tags]]\nname = \"A\"\ntype = \"DINT\"\n";
    let scene = scene_of(&tag("A", "DINT"), &[("Main", "A := 5;")], program_tag, 4.0).unwrap();
    let (mut plc, mut task) = bound(&scene).unwrap();
    plc.scan(&mut task);
    let read = |n: &str| plc.memory().slots[plc.memory().tags[plc.memory().find(n).unwrap()].base];
    assert_eq!(read("P.A"), Value::Int(5));
    assert_eq!(read("A"), Value::Int(0));
}

#[test]
fn major_faults_stop_the_controller_with_type_code_and_line() {
    let tags = format!("{}{}", tag("Arr", "DINT[3]"), tag("I", "DINT"));
    let mut run = Run::new(&tags, "I := I + 1;\nArr[I] := 1;").unwrap();
    run.scans(5);
    let f = run.plc.major_fault().expect("faulted");
    assert_eq!((f.fault_type, f.code, f.line, f.major), (4, 20, 2, true));
    assert!(f.message.contains("Arr[3]"), "{}", f.message);
    assert_eq!(int(run.get("I")), 3, "no scan after the fault");

    // The endless scan stops at every coarse update (4 ms) and resumes at
    // the next; the 500 ms watchdog expires in the 126th update.
    let mut run = Run::new(&tag("I", "DINT"), "WHILE TRUE DO I := I + 1; END_WHILE;").unwrap();
    run.scans(125);
    assert!(run.plc.major_fault().is_none(), "{:?}", run.plc.major_fault());
    run.scans(1);
    let f = run.plc.major_fault().expect("watchdog");
    assert_eq!((f.fault_type, f.code), (6, 1));
    assert!(f.message.starts_with("task watchdog expired"), "{}", f.message);
    // Statements and loop tests at 1 µs: the WHILE, then 2 µs a pass; the
    // test that would start pass 250,000 is past 500 ms.
    assert_eq!(int(run.get("I")), 249_999);

    let mut run = Run::new(&tag("A", "DINT"), "A := A + 1; A.[A + 40] := TRUE;").unwrap();
    run.scans(1);
    assert_eq!(run.plc.major_fault().map(|f| (f.fault_type, f.code)), Some((4, 20)));
}

#[test]
fn a_routine_calling_itself_overflows_the_stack() {
    let routines = [("Main", "JSR(Deeper);"), ("Deeper", "N := N + 1;\nJSR(Deeper);")];
    let scene = scene_of(&tag("N", "DINT"), &routines, "", 4.0).unwrap();
    let (mut plc, mut task) = bound(&scene).unwrap();
    plc.scan(&mut task);
    let f = plc.major_fault().expect("stack overflow");
    assert_eq!((f.fault_type, f.code, f.line), (4, 84, 2));
    assert!(
        f.routine.ends_with("Deeper.st") && f.message.starts_with("stack overflow"),
        "{f}"
    );
    let n = plc.memory().find("N").unwrap();
    assert_eq!(
        plc.memory().slots[plc.memory().tags[n].base],
        Value::Int(exec::MAX_JSR_DEPTH as i64)
    );
}

#[test]
fn a_scan_longer_than_the_period_is_an_overlap() {
    // 5,002 statements and tests: 5 ms on a 4 ms task. The trigger at 4 ms
    // finds the scan running and is ignored; the one at 8 ms starts the next.
    let mut run = Run::new(&tag("I", "DINT"), "FOR I := 1 TO 5000 DO END_FOR;").unwrap();
    run.scans(3);
    let f = &run.plc.minor_faults()[0];
    assert_eq!((f.fault_type, f.code), (6, 2));
    assert!(f.message.starts_with("task overlap"), "{}", f.message);
    assert_eq!(run.plc.minor_faults().len(), 1);
    assert_eq!(run.plc.stats().scans, 1, "the second scan is still running");
    assert!(run.plc.major_fault().is_none());
}

#[test]
fn compile_errors_name_the_line_column_and_what_was_expected() {
    let rows: [(&str, &str); 10] = [
        ("A := Nope;", "'Nope' is not a tag"),
        ("A := X AND B;", "needs BOOL or integer operands"),
        ("Table.ActualPosition := 1.0;", "read-only"),
        ("X := Table.Torque;", "not modelled"),
        ("A := Arr;", "is an array"),
        ("EXIT;", "EXIT outside"),
        ("TON(T1);", "IEC dialect"),
        ("MDO(Table, M);", "does not simulate"),
        ("A := FOO(1);", "unknown function"),
        ("A.40 := TRUE;", "outside a DINT"),
    ];
    let tags = format!(
        "{}{}{}{}",
        tag("A", "DINT"),
        tag("X", "REAL"),
        tag("B", "BOOL"),
        tag("Arr", "DINT[2]")
    );
    for (routine, want) in rows {
        let e = Run::new(&tags, routine)
            .err()
            .unwrap_or_else(|| panic!("{routine} compiles"));
        assert!(e.contains(want), "{routine}: {e}");
        assert!(e.contains("Main.st:1:"), "{routine}: {e}");
    }
    let e = scene_with(&tags, "A := 1;\nIF A THEN\n  A := ;\nEND_IF;", 4.0).unwrap_err();
    assert!(e.contains("Main.st:3:8: expected an operand"), "{e}");
}

#[test]
fn iec_ton_tof_and_triggers_in_the_iec_dialect() {
    let tags = format!(
        "{}{}{}{}{}",
        tag("T1", "TON"),
        tag("T2", "TOF"),
        tag("R1", "R_TRIG"),
        tag("F1", "F_TRIG"),
        tag("N", "DINT")
    );
    let routine = "N := N + 1;\n\
                   T1.IN := TRUE; T1.PT := 20; TON(T1);\n\
                   T2.IN := N < 3; T2.PT := 20; TOF(T2);\n\
                   R1.CLK := N >= 2; R_TRIG(R1);\n\
                   F1.CLK := N < 4; F_TRIG(F1);";
    let scene = scene_with(&tags, routine, 4.0).unwrap();
    let text = std::fs::read_to_string(&scene.path)
        .unwrap()
        .replace("main = \"Main.st\"", "main = { file = \"Main.st\", dialect = \"iec\" }");
    let scene = scene::parse(&scene.path, &text).unwrap();
    let (mut plc, mut task) = bound(&scene).unwrap();
    let member = |plc: &Controller, t: &str, m: &str| {
        let info = &plc.memory().tags[plc.memory().find(t).unwrap()];
        let memory::Kind::Structure(s) = info.kind else {
            panic!()
        };
        plc.memory().slots[info.base + s.offset(m)]
    };
    let mut q = Vec::new();
    for _ in 0..10 {
        plc.scan(&mut task);
        task.update();
        q.push((
            member(&plc, "T1", "Q").truthy(),
            member(&plc, "T2", "Q").truthy(),
            member(&plc, "R1", "Q").truthy(),
            member(&plc, "F1", "Q").truthy(),
        ));
    }
    // Scans at 0, 4, …, 36 ms: TON's Q from ET = 20 ms (the 6th scan);
    // TOF's Q from the 1st scan until 20 ms after IN fell at the 3rd (8 ms):
    // off from 28 ms (the 8th); R_TRIG pulses at the 2nd, F_TRIG at the 4th.
    let ton: Vec<bool> = q.iter().map(|x| x.0).collect();
    let tof: Vec<bool> = q.iter().map(|x| x.1).collect();
    let rising: Vec<bool> = q.iter().map(|x| x.2).collect();
    let falling: Vec<bool> = q.iter().map(|x| x.3).collect();
    assert_eq!(ton, [false, false, false, false, false, true, true, true, true, true]);
    assert_eq!(tof, [true, true, true, true, true, true, true, false, false, false]);
    assert_eq!(
        rising,
        [false, true, false, false, false, false, false, false, false, false]
    );
    assert_eq!(
        falling,
        [false, false, false, true, false, false, false, false, false, false]
    );
    assert_eq!(member(&plc, "T1", "ET"), Value::Int(20));
}
