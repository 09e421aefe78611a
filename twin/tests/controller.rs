//! The controller around the routines: task types and preemption
//! (1756-PM005), fault routines and JSR parameters (1756-PM014,
//! 1756-RM003), the system objects read with GSV and set with SSV
//! (1756-RM003), and the small semantics of literals, operator chains and
//! overflow reporting. Each test builds a scene, binds its program to a
//! planner without a plant and runs coarse updates of 4 ms.

use std::path::{Path, PathBuf};
use twin::program::Program;
use twin::program::types::Value;

mod common;

/// A scene in `target/controller-tests/<name>/`: the indexing table's
/// axes, then `body` (tags, tasks, `[controller]`), with `routines`
/// written beside it as `<name>.st`.
fn scene(name: &str, body: &str, routines: &[(&str, &str)]) -> PathBuf {
    let dir = common::fresh_dir("controller-tests", name);
    for (file, text) in routines {
        std::fs::write(dir.join(format!("{file}.st")), text).expect("routine");
    }
    let text = format!("{}{body}", common::indexing_table_head());
    let path = dir.join("scene.toml");
    std::fs::write(&path, text).expect("scene");
    path
}

/// A program bound to a planner with the scene's axes, run update by
/// update (no plant: the axes are at their command positions).
struct Bench {
    program: Program,
    task: planner::task::MotionTask,
}

impl Bench {
    fn load(path: &Path) -> Bench {
        Bench::try_load(path).unwrap_or_else(|e| panic!("{e}"))
    }

    fn try_load(path: &Path) -> Result<Bench, String> {
        let scene = twin::scene::load(path).map_err(|e| e.to_string())?;
        let mut task = planner::task::MotionTask::new(scene.coarse_update_s()).map_err(|e| e.to_string())?;
        for a in &scene.axes {
            task.add_axis(a.config.clone(), 0.0).map_err(|e| e.to_string())?;
        }
        let program = Program::bind(&scene, &mut task).map_err(|e| e.to_string())?;
        Ok(Bench { program, task })
    }

    fn updates(&mut self, n: usize) -> &mut Self {
        for _ in 0..n {
            self.program.scan(&mut self.task);
            self.task.update();
        }
        self
    }

    fn int(&self, name: &str) -> i64 {
        self.value(name).as_i64()
    }

    fn value(&self, name: &str) -> Value {
        let mem = self.program.controller().memory();
        let (base, index) = match name.split_once('[') {
            Some((b, i)) => (b, i.trim_end_matches(']').parse::<usize>().expect("index")),
            None => (name, 0),
        };
        let t = mem.find(base).unwrap_or_else(|| panic!("no tag {base}"));
        mem.slots[mem.tags[t].base + index]
    }

    fn minor(&self, fault_type: u8, code: u8) -> usize {
        let c = self.program.controller();
        c.minor_faults()
            .iter()
            .filter(|f| f.fault_type == fault_type && f.code == code)
            .count()
    }
}

fn tag(name: &str, ty: &str) -> String {
    format!("[[tags]]\nname = \"{name}\"\ntype = \"{ty}\"\n")
}

fn tags(list: &[(&str, &str)]) -> String {
    list.iter().map(|(n, t)| tag(n, t)).collect()
}

fn task(name: &str, head: &str, program: &str, main: &str, extra: &str) -> String {
    format!(
        "[[tasks]]\nname = \"{name}\"\n{head}\n[[tasks.programs]]\nname = \"{program}\"\nmain = \"{main}.st\"\n{extra}\n"
    )
}

/// 1756-PM005, "Manage Tasks" (priorities, overlap): a 2 ms priority-3
/// task beside a 50 ms priority-10 task whose scan takes 60 ms nominal.
/// The fast task interrupts the slow scan at the statement where each
/// trigger falls and sees its intermediate values; the slow task runs 10
/// scans in 1 s, and its 10 other triggers find it running: ignored,
/// counted in `OverlapCount`, minor fault 6/2 each.
#[test]
fn a_fast_task_preempts_a_long_slow_scan_whose_overlapping_triggers_are_ignored() {
    let fast = "FastScans := FastScans + 1;\n\
                IF Phase = 1 THEN SawOne := SawOne + 1; END_IF;\n\
                IF Phase = 2 THEN SawTwo := SawTwo + 1; END_IF;\n";
    // 1 + 29,999 + 1 + 29,998 + 4 statements and loop tests: 60,003 µs.
    let slow = "Phase := 1;\nFOR I := 1 TO 29997 DO END_FOR;\nPhase := 2;\nFOR J := 1 TO 29996 DO END_FOR;\n\
                Phase := 0;\nSlowScans := SlowScans + 1;\nGSV(TASK, THIS, OverlapCount, Overlaps);\n\
                GSV(TASK, THIS, LastScanTime, LastScan);\nGSV(TASK, Fast, OverlapCount, FastOverlaps);\n";
    let body = tags(&[
        ("FastScans", "DINT"),
        ("SawOne", "DINT"),
        ("SawTwo", "DINT"),
        ("Phase", "DINT"),
        ("I", "DINT"),
        ("J", "DINT"),
        ("SlowScans", "DINT"),
        ("Overlaps", "DINT"),
        ("LastScan", "DINT"),
        ("FastOverlaps", "DINT"),
    ]) + &task("Fast", "period_ms = 2.0\npriority = 3", "F", "Fast", "")
        + &task("Slow", "period_ms = 50.0\npriority = 10", "S", "Slow", "");
    let path = scene("preemption", &body, &[("Fast", fast), ("Slow", slow)]);
    let mut b = Bench::load(&path);
    b.updates(250);
    assert_eq!(b.int("SlowScans"), 10, "scans started at 0, 100, …, 900 ms");
    assert_eq!(
        b.int("Overlaps"),
        10,
        "the 10th scan reads it at 960 ms, after the trigger at 950 ms"
    );
    assert_eq!(b.minor(6, 2), 10, "the triggers at 50, 150, …, 950 ms");
    assert!(
        b.int("SawOne") >= 140 && b.int("SawTwo") >= 140,
        "{} {}",
        b.int("SawOne"),
        b.int("SawTwo")
    );
    // Each fast scan is 4 statements here and there: 4 µs; about 30 of them
    // interrupt a slow scan.
    let last = b.int("LastScan");
    assert!((60_050..60_250).contains(&last), "LastScanTime {last} µs");
    assert_eq!(b.int("FastOverlaps"), 0);
    // Triggers at 0, 2, …, 996 ms: the one at 998 ms waits for the update
    // at 1000 ms.
    assert_eq!(b.int("FastScans"), 499);
}

/// 1756-PM005, "Continuous task": no period, below every other task,
/// scanned again as soon as a scan ends. With a 10 ms task of 1,000
/// statements and a continuous task of 100, the continuous task gets the
/// rest: 9 ms of every 10.
#[test]
fn a_continuous_task_runs_in_the_time_the_others_leave() {
    let periodic = "FOR I := 1 TO 998 DO END_FOR;\nN := N + 1;\n";
    let continuous = "FOR J := 1 TO 98 DO END_FOR;\nC := C + 1;\nGSV(TASK, THIS, Priority, Prio);\n";
    let body = tags(&[
        ("I", "DINT"),
        ("J", "DINT"),
        ("N", "DINT"),
        ("C", "DINT"),
        ("Prio", "DINT"),
    ]) + &task("Main", "type = \"continuous\"", "Cont", "Cont", "")
        + &task("Timed", "period_ms = 10.0\npriority = 8", "Per", "Per", "");
    let path = scene("continuous", &body, &[("Per", periodic), ("Cont", continuous)]);
    let mut b = Bench::load(&path);
    b.updates(250);
    // 1,001 µs every 10 ms for the periodic task (100 scans), the other
    // 899.9 ms for 102-µs continuous scans: 8,822 of them, the 8,823rd
    // under way.
    assert_eq!(b.int("N"), 100);
    assert_eq!(b.int("C"), 8_822);
    assert_eq!(b.int("Prio"), 0, "a continuous task has no priority");

    // A continuous task whose routine executes nothing still lets the
    // clock move on (a statement's time a scan), and the run ends.
    let body = tags(&[("N", "DINT")]) + &task("Main", "type = \"continuous\"", "Cont", "Cont", "");
    let path = scene("continuous-empty", &body, &[("Cont", "(* nothing *)\n")]);
    let mut b = Bench::load(&path);
    b.updates(3);
    assert_eq!(
        b.program.controller().stats().scans,
        12_000,
        "4,000 empty scans an update"
    );
}

/// 1756-PM005, "Event task": triggered by an EVENT instruction (a higher
/// priority one runs at once, before the statement after the EVENT), by
/// each motion group execution, and by its timeout when no trigger comes
/// (`Status` bit 1).
#[test]
fn event_tasks_run_on_event_on_motion_group_execution_and_on_timeout() {
    let main = "Stage := 1;\nEVENT(Urgent);\nStage := 2;\nM := M + 1;\n";
    let urgent = "SeenStage := Stage;\nE := E + 1;\nGSV(TASK, THIS, Status, UrgentStatus);\n";
    let motion = "G := G + 1;\n";
    let idle = "T := T + 1;\nGSV(TASK, THIS, Status, IdleStatus);\n";
    let body = tags(&[
        ("Stage", "DINT"),
        ("SeenStage", "DINT"),
        ("M", "DINT"),
        ("E", "DINT"),
        ("G", "DINT"),
        ("T", "DINT"),
        ("UrgentStatus", "DINT"),
        ("IdleStatus", "DINT"),
    ]) + &task("Main", "period_ms = 20.0\npriority = 10", "P", "Main", "")
        + &task(
            "Urgent",
            "type = \"event\"\ntrigger = \"event_instruction\"\npriority = 2",
            "U",
            "Urgent",
            "",
        )
        + &task(
            "Motion",
            "type = \"event\"\ntrigger = \"motion_group_execution\"\npriority = 1",
            "MG",
            "Motion",
            "",
        )
        + &task(
            "Idle",
            "type = \"event\"\ntrigger = \"event_instruction\"\npriority = 12\ntimeout_ms = 30.0",
            "Id",
            "Idle",
            "",
        );
    let path = scene(
        "events",
        &body,
        &[("Main", main), ("Urgent", urgent), ("Motion", motion), ("Idle", idle)],
    );
    let mut b = Bench::load(&path);
    b.updates(50);
    assert_eq!(b.int("M"), 10, "the 20 ms task over 200 ms");
    assert_eq!(b.int("E"), 10, "one EVENT a scan");
    assert_eq!(
        b.int("SeenStage"),
        1,
        "the event task ran between the EVENT and the next statement"
    );
    assert_eq!(b.int("UrgentStatus") & 1, 1, "Status bit 0: an EVENT triggered it");
    assert_eq!(b.int("G"), 50, "once a coarse update");
    // No EVENT(Idle): its 30 ms timeout triggers it at 30, 60, …, 180 ms.
    assert_eq!(b.int("T"), 6);
    assert_eq!(b.int("IdleStatus") & 2, 2, "Status bit 1: the timeout triggered it");
}

/// 1756-PM005: tasks of equal priority share the controller in 1 ms
/// slices: two 4.5 ms scans triggered together start 1 ms apart and end
/// about 0.5 ms apart, after 9 ms; without slices the first would end
/// at 4.5 ms.
#[test]
fn equal_priorities_alternate_every_millisecond() {
    let routine = |me: &str| {
        format!(
            "FOR I{me} := 1 TO 1499 DO X{me} := X{me} + 1; Y{me} := X{me}; END_FOR;\n\
             GSV(TASK, THIS, StartTime, Start{me}[0]);\nGSV(WALLCLOCKTIME, , CurrentValue, End{me}[0]);\n"
        )
    };
    let mut declared = Vec::new();
    for me in ["A", "B"] {
        for (n, t) in [
            ("I", "DINT"),
            ("X", "DINT"),
            ("Y", "DINT"),
            ("Start", "DINT[2]"),
            ("End", "DINT[2]"),
        ] {
            declared.push((format!("{n}{me}"), t));
        }
    }
    let list: Vec<(&str, &str)> = declared.iter().map(|(n, t)| (n.as_str(), *t)).collect();
    let body = tags(&list)
        + "[controller]\nstart_time = \"1970-01-01T00:00:00Z\"\n"
        + &task("A", "period_ms = 20.0\npriority = 6", "PA", "A", "")
        + &task("B", "period_ms = 20.0\npriority = 6", "PB", "B", "");
    let (a, b_text) = (routine("A"), routine("B"));
    let path = scene("equal-priority", &body, &[("A", a.as_str()), ("B", b_text.as_str())]);
    let mut b = Bench::load(&path);
    b.updates(5);
    // 1 + 1,500 tests + 1,499 × 2 statements + 1: 4,500 µs each.
    assert_eq!((b.int("StartA[0]"), b.int("StartB[0]")), (0, 1000));
    let (end_a, end_b) = (b.int("EndA[0]"), b.int("EndB[0]"));
    assert!((8_400..=8_600).contains(&end_a), "A ended at {end_a} µs");
    assert!((8_900..=9_100).contains(&end_b), "B ended at {end_b} µs");
}

/// 1756-PM005, "Inhibit a task" and program `DisableFlag`: an inhibited
/// task is not scanned; a disabled program is skipped; SSV sets both.
#[test]
fn inhibited_tasks_and_disabled_programs_are_not_scanned() {
    let main =
        "N := N + 1;\nIF N = 5 THEN SSV(TASK, Other, InhibitTask, 1); SSV(PROGRAM, Second, DisableFlag, 1); END_IF;\n";
    let body = tags(&[
        ("N", "DINT"),
        ("O", "DINT"),
        ("Never", "DINT"),
        ("S", "DINT"),
        ("D", "DINT"),
    ]) + &task("Main", "period_ms = 4.0\npriority = 5", "P", "Main", "")
        + &task("Other", "period_ms = 4.0\npriority = 6", "First", "Other", "")
        + "[[tasks.programs]]\nname = \"Second\"\nmain = \"Second.st\"\n"
        + "[[tasks.programs]]\nname = \"Off\"\nmain = \"Off.st\"\ndisabled = true\n"
        + &task(
            "Asleep",
            "period_ms = 4.0\npriority = 7\ninhibit = true",
            "Sleeper",
            "Asleep",
            "",
        );
    let path = scene(
        "inhibit",
        &body,
        &[
            ("Main", main),
            ("Other", "O := O + 1;\n"),
            ("Second", "S := S + 1;\n"),
            ("Off", "D := D + 1;\n"),
            ("Asleep", "Never := 1;\n"),
        ],
    );
    let mut b = Bench::load(&path);
    b.updates(10);
    assert_eq!(b.int("N"), 10);
    // The 5th scan of Main inhibits Other after Other's 5th trigger (it
    // still runs, its program Second already disabled), then no more.
    assert_eq!((b.int("O"), b.int("S")), (5, 4));
    assert_eq!((b.int("D"), b.int("Never")), (0, 0));
}

/// 1756-PM005 (*Inhibit a task*, program *Disable*) and 1756-RM003 (GSV/SSV
/// PROGRAM `DisableFlag`): a program disabled by a higher-priority task
/// while its scan is stopped at a coarse update: the rest of that scan is
/// skipped, and the task's next program starts from its beginning.
#[test]
fn a_program_disabled_while_its_scan_is_stopped_skips_the_rest_of_it() {
    let long = "First := First + 1;\nFOR I := 1 TO 9999 DO END_FOR;\nLongDone := LongDone + 1;\n";
    let next = "IF J = 0 THEN Second := Second + 1; END_IF;\n";
    let switch = "T := T + 1;\nIF T = 2 THEN SSV(PROGRAM, Long, DisableFlag, 1); END_IF;\n";
    let body = tags(&[
        ("First", "DINT"),
        ("I", "DINT"),
        ("J", "DINT"),
        ("LongDone", "DINT"),
        ("Second", "DINT"),
        ("T", "DINT"),
    ]) + &task("Slow", "period_ms = 100.0\npriority = 10", "Long", "Long", "")
        + "[[tasks.programs]]\nname = \"Next\"\nmain = \"Next.st\"\n"
        + &task("Fast", "period_ms = 4.0\npriority = 2", "Switch", "Switch", "");
    let path = scene(
        "disable-while-stopped",
        &body,
        &[("Long", long), ("Next", next), ("Switch", switch)],
    );
    let mut b = Bench::load(&path);
    b.updates(10);
    // The long scan (20 ms) stopped at 4 ms; at 4 ms the fast task disabled
    // it: it never finishes, and Next runs its own routine from the start.
    assert_eq!((b.int("First"), b.int("LongDone"), b.int("Second")), (1, 0, 1));
    assert!(b.program.controller().major_fault().is_none());
}

/// 1756-PM005, "Watchdog": from the start of a scan to its end,
/// higher-priority tasks included.
#[test]
fn the_watchdog_counts_the_time_higher_priority_tasks_take() {
    let slow = "FOR I := 1 TO 1999 DO END_FOR;\nDone := Done + 1;\n";
    let fast = "FOR J := 1 TO 599 DO END_FOR;\n";
    let body = tags(&[("I", "DINT"), ("J", "DINT"), ("Done", "DINT")])
        + &task(
            "Slow",
            "period_ms = 20.0\npriority = 10\nwatchdog_ms = 3.0",
            "S",
            "Slow",
            "",
        )
        + &task("Fast", "period_ms = 1.0\npriority = 2", "F", "Fast", "");
    let path = scene("watchdog", &body, &[("Slow", slow), ("Fast", fast)]);
    let mut b = Bench::load(&path);
    b.updates(2);
    // 2,001 µs of its own, and 600 µs of every millisecond taken by the
    // fast task: past 3 ms before it ends.
    let f = b.program.controller().major_fault().expect("watchdog").clone();
    assert_eq!((f.fault_type, f.code, f.task.as_str()), (6, 1, "Slow"));
    assert_eq!(b.int("Done"), 0);
}

/// 1756-PM014, "Create a fault routine for a program": an instruction
/// fault in the program runs its fault routine; clearing Type and Code in
/// `MajorFaultRecord` skips the faulted statement and resumes with the
/// next; a fault left uncleared stops the controller.
#[test]
fn a_fault_routine_clears_an_out_of_range_subscript_and_the_scan_goes_on() {
    let main = "I := I + 1;\nArr[I] := 7;\nAfter := After + 1;\n";
    let handler = "GSV(PROGRAM, THIS, MajorFaultRecord, Rec[0]);\nFaultType := Rec[2] MOD 65536;\n\
                   FaultCode := Rec[2] / 65536;\nI := 0;\nRec[2] := 0;\nSSV(PROGRAM, THIS, MajorFaultRecord, Rec[0]);\n\
                   Handled := Handled + 1;\n";
    let body = tags(&[
        ("I", "DINT"),
        ("Arr", "DINT[3]"),
        ("After", "DINT"),
        ("Rec", "DINT[11]"),
        ("FaultType", "DINT"),
        ("FaultCode", "DINT"),
        ("Handled", "DINT"),
        ("Majors", "DINT"),
    ]) + &task(
        "T",
        "period_ms = 4.0\npriority = 5",
        "P",
        "Main",
        "routines = [\"Recover.st\"]\nfault_routine = \"Recover\"",
    );
    let path = scene("fault-routine", &body, &[("Main", main), ("Recover", handler)]);
    let mut b = Bench::load(&path);
    b.updates(8);
    assert!(b.program.controller().major_fault().is_none());
    // I: 1, 2, 3 (fault, reset to 0), 1, 2, 3 (fault), 1, 2.
    assert_eq!(b.int("Handled"), 2);
    assert_eq!((b.int("FaultType"), b.int("FaultCode")), (4, 20));
    assert_eq!(
        b.int("After"),
        8,
        "the statement after the faulted one ran in every scan"
    );
    assert_eq!(b.int("Arr[1]"), 7);

    // A fault routine that does not clear the record: the fault stands.
    let keep = "Handled := Handled + 1;\n";
    let path = scene("fault-routine-keeps", &body, &[("Main", main), ("Recover", keep)]);
    let mut b = Bench::load(&path);
    b.updates(8);
    let f = b.program.controller().major_fault().expect("uncleared").clone();
    assert_eq!((f.fault_type, f.code, f.line), (4, 20, 2));
    assert_eq!((b.int("Handled"), b.int("After")), (1, 2));
}

/// 1756-RM003, JSR: fewer input parameters than the SBR takes, or a RET
/// with fewer return parameters than the JSR has, is major fault 4/31;
/// extra ones are not received.
#[test]
fn jsr_parameter_counts_that_fall_short_are_major_fault_4_31() {
    let cases = [
        ("JSR(Sub, 1, 5);", "SBR(A, B);\nRET();", Some((4, 31, 1))),
        ("JSR(Sub, 1, 5, R1, R2);", "SBR(A);\nRET(A * 2);", Some((4, 31, 2))),
        ("JSR(Sub, 0, R1);", "A := 3;", Some((4, 31, 1))),
        ("JSR(Sub, 3, 5, 6, 7, R1);", "SBR(A, B);\nRET(A + B, 99);", None),
    ];
    for (k, (call, sub, fault)) in cases.into_iter().enumerate() {
        let body = tags(&[("A", "DINT"), ("B", "DINT"), ("R1", "DINT"), ("R2", "DINT")])
            + &task(
                "T",
                "period_ms = 4.0\npriority = 5",
                "P",
                "Main",
                "routines = [\"Sub.st\"]",
            );
        let path = scene(&format!("jsr-{k}"), &body, &[("Main", call), ("Sub", sub)]);
        let mut b = Bench::load(&path);
        b.updates(1);
        let got = b
            .program
            .controller()
            .major_fault()
            .map(|f| (f.fault_type, f.code, f.line));
        assert_eq!(got, fault, "{call} into {sub}");
        if fault.is_none() {
            assert_eq!(b.int("R1"), 11, "extra inputs and returns are not received");
        }
    }
}

/// 1756-RM003, GSV/SSV objects: TASK, PROGRAM, WALLCLOCKTIME, FAULTLOG,
/// MOTIONGROUP.
#[test]
fn system_objects_read_the_controller_and_settable_attributes_take_effect() {
    let main = "FOR I := 1 TO 98 DO END_FOR;\n\
                GSV(TASK, THIS, LastScanTime, Scan);\nGSV(TASK, THIS, Rate, Rate);\nGSV(TASK, THIS, Watchdog, Dog);\n\
                GSV(TASK, THIS, Priority, Prio);\nGSV(TASK, Other, Instance, Inst);\n\
                GSV(PROGRAM, THIS, LastScanTime, PScan);\n\
                GSV(WALLCLOCKTIME, , DateTime, Date[0]);\nGSV(WALLCLOCKTIME, , CurrentValue, Now[0]);\n\
                GSV(MOTIONGROUP, , CoarseUpdatePeriod, Coarse);\n\
                D := 2147483647 + 1;\nGSV(FAULTLOG, , MinorEvents, Minors);\nGSV(FAULTLOG, , MinorFaultBits, MinorBits);\n\
                GSV(TASK, THIS, MaxScanTime, Max);\nIF Max > 0 THEN SSV(TASK, THIS, MaxScanTime, 0); END_IF;\n\
                GSV(TASK, THIS, MaxScanTime, Max2);\n";
    let body = tags(&[
        ("I", "DINT"),
        ("Scan", "DINT"),
        ("Rate", "DINT"),
        ("Dog", "DINT"),
        ("Prio", "INT"),
        ("Inst", "DINT"),
        ("PScan", "DINT"),
        ("Date", "DINT[7]"),
        ("Now", "DINT[2]"),
        ("Coarse", "DINT"),
        ("D", "DINT"),
        ("Minors", "INT"),
        ("MinorBits", "DINT"),
        ("Max", "DINT"),
        ("Max2", "DINT"),
    ]) + "[controller]\nstart_time = \"2026-11-27T08:00:00Z\"\n"
        + &task(
            "T",
            "period_ms = 10.0\npriority = 7\nwatchdog_ms = 50.0",
            "P",
            "Main",
            "",
        )
        + &task("Other", "period_ms = 10.0\npriority = 8", "Second", "Other", "");
    let path = scene("gsv", &body, &[("Main", main), ("Other", ";")]);
    let mut b = Bench::load(&path);
    // Triggers at 0 and 10 ms (the update at 12 ms runs the second).
    b.updates(4);
    // The first scan: the FOR (1 + 99 tests), 15 statements, no SSV.
    assert_eq!(b.int("Scan"), 115);
    assert_eq!(
        (b.int("Rate"), b.int("Dog"), b.int("Prio"), b.int("Inst")),
        (10_000, 50_000, 7, 2)
    );
    assert_eq!(b.int("Coarse"), 4000);
    assert_eq!(b.int("PScan"), 115);
    let date: Vec<i64> = (0..7).map(|k| b.int(&format!("Date[{k}]"))).collect();
    // The second scan starts at 10 ms: its 107th statement reads the date.
    assert_eq!(date, [2026, 11, 27, 8, 0, 0, 10_107]);
    let now = (b.int("Now[1]") << 32) | (b.int("Now[0]") & 0xFFFF_FFFF);
    assert_eq!(now, 1_795_766_400_000_000 + 10_108);
    assert_eq!(b.int("Minors"), 2, "an overflow each scan");
    assert_eq!(b.int("MinorBits"), 1 << 4);
    assert_eq!((b.int("Max"), b.int("Max2")), (115, 0), "SSV resets it");
}

/// `[controller] report_overflow_faults = false` records no minor fault
/// 4/4 on overflow (Controller Properties, Advanced); a hex literal keeps
/// its bit pattern (`16#FFFF_FFFF` is −1 in a DINT, no fault); operator
/// chains of any length compute; S:N, S:Z, S:V and S:C read FALSE in
/// Structured Text (1756-RM003, math status flags: ladder only).
#[test]
fn literals_chains_and_overflow_reporting() {
    let sum = (1..=40).map(|k| k.to_string()).collect::<Vec<_>>().join(" + ");
    let main = format!(
        "D := 16#FFFF_FFFF;\nE := 16#8000_0000;\nSum := {sum};\nW := 2147483647;\nW := W + 1;\nFlags := S:N OR S:Z OR S:V OR S:C;\n"
    );
    let body = tags(&[
        ("D", "DINT"),
        ("E", "DINT"),
        ("Sum", "DINT"),
        ("W", "DINT"),
        ("Flags", "BOOL"),
    ]) + &task("T", "period_ms = 4.0\npriority = 5", "P", "Main", "");
    let path = scene("literals", &body, &[("Main", &main)]);
    let mut b = Bench::load(&path);
    b.updates(1);
    assert_eq!((b.int("D"), b.int("E"), b.int("Sum")), (-1, -2_147_483_648, 820));
    assert_eq!(b.int("W"), -2_147_483_648);
    assert_eq!(b.value("Flags"), Value::Bool(false));
    assert_eq!(b.minor(4, 4), 1, "only W + 1 overflows");
    let warned: Vec<String> = b.program.warnings().iter().map(|w| w.message.clone()).collect();
    assert_eq!(warned.len(), 4, "{warned:?}");
    assert!(warned[0].starts_with("S:N is a math status flag"), "{warned:?}");

    let quiet = body.replace("[[tasks]]", "[controller]\nreport_overflow_faults = false\n\n[[tasks]]");
    let path = scene("literals-quiet", &quiet, &[("Main", &main)]);
    let mut b = Bench::load(&path);
    b.updates(1);
    assert_eq!(b.int("W"), -2_147_483_648);
    assert_eq!(b.minor(4, 4), 0);
}

/// Bad input (the load errors of 1756-PM005 task settings, 1756-PM021
/// parameters, 1756-PM001 data types and 1756-RM003 operands): each a
/// one-line message naming the file, line, column and field (scene) or the
/// routine's line and column.
#[test]
fn bad_controller_input_is_refused_with_its_place() {
    let t = |head: &str| task("T", head, "P", "Main", "");
    let rows: Vec<(String, &str, &str)> = vec![
        (
            t("priority = 5"),
            "A := 1;",
            "tasks[0].period_ms: periodic tasks need 'period_ms'",
        ),
        (
            t("type = \"continuous\"") + &task("U", "type = \"continuous\"", "Q", "Main", ""),
            "A := 1;",
            "tasks[1].type: a controller has at most one continuous task (the first is 'T')",
        ),
        (
            t("type = \"event\"\npriority = 4"),
            "A := 1;",
            "tasks[0].trigger: event tasks need 'trigger'",
        ),
        (
            t("type = \"continuous\"\nperiod_ms = 10.0"),
            "A := 1;",
            "tasks[0].period_ms: 'period_ms' does not apply to continuous tasks",
        ),
        (
            t("type = \"continuous\"\npriority = 3"),
            "A := 1;",
            "tasks[0].priority: 'priority' does not apply to continuous tasks",
        ),
        (
            t("type = \"event\"\ntrigger = \"io\"\npriority = 3"),
            "A := 1;",
            "tasks[0].trigger: unknown event trigger 'io'",
        ),
        (
            t("type = \"cyclic\"\npriority = 3"),
            "A := 1;",
            "tasks[0].type: unknown task type 'cyclic'",
        ),
        (
            t("period_ms = 4.0\npriority = 5\ntrigger = \"event_instruction\""),
            "A := 1;",
            "tasks[0].trigger: 'trigger' does not apply to periodic tasks",
        ),
        (
            task(
                "T",
                "period_ms = 4.0\npriority = 5",
                "P",
                "Main",
                "fault_routine = \"Nope\"",
            ),
            "A := 1;",
            "fault_routine: no routine 'Nope' in this program",
        ),
        (
            "[controller]\nstart_time = \"2026-02-30T00:00:00Z\"\n".to_owned() + &t("period_ms = 4.0\npriority = 5"),
            "A := 1;",
            "controller.start_time: '2026-02-30T00:00:00Z' is not a UTC date and time",
        ),
        (
            t("period_ms = 4.0\npriority = 5"),
            "GSV(TASK, THIS, Speed, A);",
            "Main.st:1:17: GSV: TASK attribute 'Speed' is not modelled",
        ),
        (
            t("period_ms = 4.0\npriority = 5"),
            "SSV(TASK, THIS, Rate, A);",
            "Main.st:1:17: SSV: TASK.Rate is read-only",
        ),
        (
            t("period_ms = 4.0\npriority = 5"),
            "GSV(MODULE, X, Mode, A);",
            "Main.st:1:5: GSV: class 'MODULE' is not modelled",
        ),
        (
            t("period_ms = 4.0\npriority = 5"),
            "GSV(TASK, Nope, Rate, A);",
            "Main.st:1:11: GSV: no task 'Nope'",
        ),
        (
            t("period_ms = 4.0\npriority = 5"),
            "GSV(PROGRAM, THIS, MajorFaultRecord, Short[0]);",
            "Main.st:1:38: GSV: PROGRAM.MajorFaultRecord takes 11 DINTs; Short has 4 from element 0",
        ),
        (
            t("period_ms = 4.0\npriority = 5"),
            "EVENT(T);",
            "Main.st:1:7: EVENT: task 'T' is not an event task",
        ),
        (
            t("period_ms = 4.0\npriority = 5"),
            "SSV(WALLCLOCKTIME, , CurrentValue, Short[0]);",
            "Main.st:1:22: SSV: WALLCLOCKTIME.CurrentValue is read-only",
        ),
        (
            "[[tags]]\nname = \"U\"\ntype = \"DINT\"\nusage = \"input\"\n".to_owned()
                + &t("period_ms = 4.0\npriority = 5"),
            "A := 1;",
            "tags[2].usage: usage applies to program tags",
        ),
        (
            t("period_ms = 4.0\npriority = 5")
                + "[[tasks.programs.tags]]\nname = \"X\"\ntype = \"DINT\"\nusage = \"inout\"\n",
            "A := 1;",
            "tasks[0].programs[0].tags[0].connection: an InOut parameter needs a connection",
        ),
        (
            t("period_ms = 4.0\npriority = 5")
                + "[[tasks.programs.tags]]\nname = \"X\"\ntype = \"REAL\"\nusage = \"input\"\nconnection = \"A\"\n",
            "A := 1;",
            "tasks[0].programs[0].tags[0].connection: connection 'A': A is DINT, the parameter X is REAL",
        ),
        (
            "[[tags]]\nname = \"K\"\ntype = \"DINT[3]\"\nconstant = true\ndescription = \"recipe\"\nexternal_access = \"read_only\"\n".to_owned()
                + &t("period_ms = 4.0\npriority = 5"),
            "A := K[1];\nK[2] := A;",
            "Main.st:2:1: 'K[…]' is a constant tag (constant = true): a routine does not write it",
        ),
        (
            "[[tags]]\nname = \"K\"\ntype = \"DINT[3]\"\nconstant = true\n".to_owned() + &t("period_ms = 4.0\npriority = 5"),
            "COP(Short[0], K[0], 3);",
            "Main.st:1:15: 'K[…]' is a constant tag",
        ),
        (
            "[[tags]]\nname = \"M\"\ntype = \"MOTION_INSTRUCTION\"\nconstant = true\n".to_owned()
                + &t("period_ms = 4.0\npriority = 5"),
            "A := 1;",
            "tags[2].constant: MOTION_INSTRUCTION tags cannot be constant",
        ),
        (
            "[[tags]]\nname = \"M\"\ntype = \"DINT\"\nexternal_access = \"hidden\"\n".to_owned()
                + &t("period_ms = 4.0\npriority = 5"),
            "A := 1;",
            "tags[2].external_access: unknown external access 'hidden'",
        ),
    ];
    let array = |ty: &str, value: &str| {
        format!("[[tags]]\nname = \"M\"\ntype = \"{ty}\"\n{value}\n") + &t("period_ms = 4.0\npriority = 5")
    };
    let rows: Vec<(String, &str, &str)> = rows
        .into_iter()
        .chain([
            (
                array("REAL[0,3]", ""),
                "A := 1;",
                "tags[2].type: array length in 'REAL[0,3]' must be a whole number",
            ),
            (
                array("REAL[2,2,2,2]", ""),
                "A := 1;",
                "tags[2].type: 'REAL[2,2,2,2]' has 4 dimensions: Logix arrays have one to three",
            ),
            (
                array("DINT[2,3]", "value = [[1, 2, 3], [4, 5]]"),
                "A := 1;",
                "tags[2].value: value does not fit type DINT[2,3]",
            ),
            (
                array("DINT[2,3]", ""),
                "A := M[1];",
                "Main.st:1:6: 'M' has 2 dimensions, got 1 subscript",
            ),
            (
                array(
                    "CAM[2,3]",
                    "value = [[{ master = 0.0, slave = 0.0 }], [{ master = 0.0, slave = 0.0 }], [{ master = 0.0, slave = 0.0 }]]",
                ),
                "A := 1;",
                "tags[2].value: value does not fit type CAM[2,3]: expected an array of at most N rows",
            ),
        ])
        .chain(data_type_rows(&t("period_ms = 4.0\npriority = 5")))
        .collect();
    for (k, (body, routine, want)) in rows.iter().enumerate() {
        let body = tags(&[("A", "DINT"), ("Short", "DINT[4]")]) + body;
        let path = scene(&format!("bad-{k}"), &body, &[("Main", routine)]);
        let e = Bench::try_load(&path)
            .err()
            .unwrap_or_else(|| panic!("row {k} loads: {want}"));
        assert!(e.contains(want), "row {k}: {e}");
        let first = e.lines().next().unwrap_or_default();
        assert!(
            first.contains("scene.toml:") || first.contains("Main.st:"),
            "row {k} names no place: {e}"
        );
    }
}

/// Bad data types, string values and string or structure operands: each
/// refused at load with its place.
fn data_type_rows(t: &str) -> Vec<(String, &'static str, &'static str)> {
    let types = |text: &str| format!("{text}\n{t}");
    let udt = "[[data_types]]\nname = \"Pt\"\nmembers = [{ name = \"X\", type = \"REAL\" }, { name = \"Tag\", type = \"STRING\" }]\n\
               [[tags]]\nname = \"Pnt\"\ntype = \"Pt\"\n[[tags]]\nname = \"Txt\"\ntype = \"STRING\"\n";
    vec![
        (
            types(
                "[[data_types]]\nname = \"A\"\nmembers = [{ name = \"B\", type = \"B\" }]\n[[data_types]]\nname = \"B\"\nmembers = [{ name = \"A\", type = \"A\", dimension = 2 }]",
            ),
            "A := 1;",
            "data_types[1].members[0].type: data type A → B → A contains itself",
        ),
        (
            types("[[data_types]]\nname = \"A\"\nmembers = [{ name = \"B\", type = \"Widget\" }]"),
            "A := 1;",
            "data_types[0].members[0].type: unknown tag type 'Widget'",
        ),
        (
            types("[[data_types]]\nname = \"A\"\nmembers = [{ name = \"M\", type = \"COORDINATE_SYSTEM\" }]"),
            "A := 1;",
            "data_types[0].members[0].type: a data type's member is a number, BOOL, a string type, another data type, an instruction's structure (FBD_TIMER …) or a MOTION_INSTRUCTION, not COORDINATE_SYSTEM",
        ),
        (
            types("[[data_types]]\nname = \"A\"\nmembers = [{ name = \"M\", type = \"REAL[2,2]\" }]"),
            "A := 1;",
            "data_types[0].members[0].type: 'REAL[2,2]': a member array has one dimension",
        ),
        (
            types("[[data_types]]\nname = \"Dint\"\nmembers = [{ name = \"M\", type = \"REAL\" }]"),
            "A := 1;",
            "data_types[0].name: 'Dint' is a predefined data type",
        ),
        (
            types("[[data_types]]\nname = \"S\"\nstring_length = 10\nmembers = [{ name = \"M\", type = \"REAL\" }]"),
            "A := 1;",
            "data_types[0].string_length: a data type has members (a structure) or string_length (a string type): this one has both",
        ),
        (
            types(
                "[[data_types]]\nname = \"S\"\nstring_length = 4\n[[tags]]\nname = \"M\"\ntype = \"S\"\nvalue = \"hello\"",
            ),
            "A := 1;",
            "tags[2].value: 'hello' does not fit S: it has 5 characters, DATA holds 4",
        ),
        (
            types(&format!(
                "{udt}[[tags]]\nname = \"Q\"\ntype = \"Pt\"\nvalue = {{ Y = 1.0 }}"
            )),
            "A := 1;",
            "tags[4].value: Pt has no member 'Y' (members: X, Tag)",
        ),
        (
            types(&format!(
                "{udt}[[tags]]\nname = \"Q\"\ntype = \"Pt\"\nvalue = {{ Tag = 5 }}"
            )),
            "A := 1;",
            "tags[4].value.Tag: value does not fit type STRING: expected a string of ASCII characters",
        ),
        (
            types(udt),
            "A := Pnt.Y;",
            "Main.st:1:10: Pt has no member 'Y' (members: X, Tag)",
        ),
        (
            types(udt),
            "A := Pnt;",
            "Main.st:1:6: 'Pnt' is a Pt: name a member, or copy it whole with COP",
        ),
        (
            types(udt),
            "CONCAT(Txt, Pnt, Txt);",
            "Main.st:1:13: CONCAT Source B: 'Pnt' is not a string",
        ),
        (
            types(udt),
            "COP(Pnt.Tag.LEN.0, A, 1);",
            "Main.st:1:5: COP Source: a bit is not an operand of a copy",
        ),
        (
            types(udt),
            "IF Txt = A THEN A := 1; END_IF;",
            "Main.st:1:10: '=' compares: 'A' is not a string",
        ),
        (
            types(udt),
            "STOR(Txt, A);",
            "Main.st:1:11: STOR Dest: expected a REAL, got DINT 'A'",
        ),
    ]
}

/// 1756-RM003 (arrays) and 1756-PM005: arrays of one to three dimensions,
/// row-major, a scene value flat or nested; each subscript checked against
/// its own dimension (major fault 4/20); SIZE of any dimension; arrays of
/// MOTION_INSTRUCTION with constant and computed subscripts.
#[test]
fn arrays_of_two_and_three_dimensions_and_of_control_structures() {
    let main = "Sum := 0;\nFOR I := 0 TO 5 DO FOR J := 0 TO 2 DO Sum := Sum + Grid[I, J]; END_FOR; END_FOR;\n\
                Cube[1, 2, 3] := 7;\nFlat := Cube[1, 2, 3];\nSIZE(Grid, 0, Rows);\nSIZE(Grid, 1, Cols);\n\
                IF S:FS THEN MAM(Table, Mvs[1], 1, 10, 100, UnitsPerSec, 1000, UnitsPerSec2, 1000, UnitsPerSec2, trapezoidal, 100, 100, %ofTime, disabled, programmed, 0, none, 0, 0); END_IF;\n\
                K := 2;\nIF Mvs[1].PC AND NOT Mvs[K].EN THEN\n  MAM(Table, Mvs[K], 1, 5, 100, UnitsPerSec, 1000, UnitsPerSec2, 1000, UnitsPerSec2, trapezoidal, 100, 100, %ofTime, disabled, programmed, 0, none, 0, 0);\nEND_IF;\n\
                Both := Mvs[1].PC AND Mvs[K].PC;\nPos := Table.CommandPosition;\n";
    let grid: Vec<String> = (0..6)
        .map(|i| format!("[{}, {}, {}]", i * 3, i * 3 + 1, i * 3 + 2))
        .collect();
    let body = tags(&[
        ("I", "DINT"),
        ("J", "DINT"),
        ("K", "DINT"),
        ("Sum", "DINT"),
        ("Flat", "DINT"),
        ("Cube", "DINT[2,3,4]"),
        ("Rows", "DINT"),
        ("Cols", "DINT"),
        ("Both", "BOOL"),
        ("Pos", "REAL"),
        ("Mvs", "MOTION_INSTRUCTION[3]"),
    ]) + &format!(
        "[[tags]]\nname = \"Grid\"\ntype = \"DINT[6,3]\"\nvalue = [{}]\n",
        grid.join(", ")
    ) + &task("T", "period_ms = 4.0\npriority = 5", "P", "Main", "");
    let path = scene("arrays", &body, &[("Main", main)]);
    let mut b = Bench::load(&path);
    b.updates(100);
    assert_eq!(b.int("Sum"), (0..18).sum::<i64>());
    // [1, 2, 3] of [2, 3, 4]: 1·12 + 2·4 + 3 = 23.
    assert_eq!((b.int("Cube[23]"), b.int("Flat")), (7, 7));
    assert_eq!((b.int("Rows"), b.int("Cols")), (6, 3));
    assert_eq!(b.value("Both"), Value::Bool(true), "both moves completed");
    assert_eq!(b.value("Pos"), Value::Real(15.0), "10 then 5 degrees");
    let names: Vec<&str> = b.program.instructions().iter().map(|i| i.name.as_str()).collect();
    assert_eq!(
        names,
        ["Mvs[1]", "Mvs[0]", "Mvs[2]"],
        "each element is a control structure"
    );

    // A subscript outside its own dimension faults even when the element
    // index would lie inside the array: Grid[0, 5] is element 5.
    let path = scene("arrays-fault", &body, &[("Main", "J := 5;\nSum := Grid[0, J];\n")]);
    let mut b = Bench::load(&path);
    b.updates(1);
    let f = b.program.controller().major_fault().expect("4/20").clone();
    assert_eq!((f.fault_type, f.code, f.line), (4, 20, 2));
    assert!(
        f.message.contains("Grid[0,5]") && f.message.contains("dimension 1 is 0..=2"),
        "{}",
        f.message
    );
    let path = scene(
        "arrays-control-fault",
        &body,
        &[("Main", "K := 3;\nBoth := Mvs[K].DN;\n")],
    );
    let mut b = Bench::load(&path);
    b.updates(1);
    let f = b.program.controller().major_fault().expect("4/20").clone();
    assert_eq!((f.fault_type, f.code, f.line), (4, 20, 2));
}

/// 1756-PM014, "Create a routine for the Controller Fault Handler": a
/// major fault no program fault routine cleared (here a watchdog, which no
/// fault routine handles) runs the handler's program; when it clears its
/// `MajorFaultRecord` the faulted scan ends there and the task runs again
/// at its next trigger (PM014 does not say where execution resumes after
/// the handler; the twin ends the faulted scan). A handler that does not
/// clear it leaves the controller faulted.
#[test]
fn the_controller_fault_handler_clears_a_watchdog_and_the_task_runs_again() {
    let main = "N := N + 1;\nIF N = 2 THEN WHILE TRUE DO ; END_WHILE; END_IF;\nAfter := After + 1;\n";
    let handler = "GSV(PROGRAM, THIS, MajorFaultRecord, Rec[0]);\nSeen := Rec[2];\nIF Rec[2] = 6 + 65536 THEN Rec[2] := 0; SSV(PROGRAM, THIS, MajorFaultRecord, Rec[0]); END_IF;\nHandled := Handled + 1;\n";
    let body = |clear: bool| {
        tags(&[
            ("N", "DINT"),
            ("After", "DINT"),
            ("Rec", "DINT[11]"),
            ("Seen", "DINT"),
            ("Handled", "DINT"),
        ]) + &task(
            "T",
            "period_ms = 10.0\npriority = 5\nwatchdog_ms = 5.0",
            "P",
            "Main",
            "",
        ) + &format!(
            "[controller.fault_handler]\nname = \"Handler\"\nmain = \"{}.st\"\n",
            if clear { "Handler" } else { "Keep" }
        )
    };
    let path = scene(
        "fault-handler",
        &body(true),
        &[
            ("Main", main),
            ("Handler", handler),
            ("Keep", "Handled := Handled + 1;\n"),
        ],
    );
    let mut b = Bench::load(&path);
    b.updates(10);
    assert!(b.program.controller().major_fault().is_none());
    assert_eq!((b.int("Seen"), b.int("Handled")), (6 + 65536, 1));
    // Scans at 0, 10 (watchdog, cleared, ended), 20, 30: N counts 4, After 3.
    assert_eq!((b.int("N"), b.int("After")), (4, 3));
    let cleared = b.program.controller().cleared_faults();
    assert_eq!(cleared.len(), 1);
    assert_eq!(
        (cleared[0].fault_type, cleared[0].code, cleared[0].cleared),
        (6, 1, true)
    );

    let path = scene(
        "fault-handler-keeps",
        &body(false),
        &[
            ("Main", main),
            ("Handler", handler),
            ("Keep", "Handled := Handled + 1;\n"),
        ],
    );
    let mut b = Bench::load(&path);
    b.updates(10);
    let f = b.program.controller().major_fault().expect("not cleared").clone();
    assert_eq!((f.fault_type, f.code), (6, 1));
    assert_eq!((b.int("Handled"), b.int("N")), (1, 2));
}

/// 1756-PM021, program parameters: an Input takes its connection's value
/// when its program's scan starts, an Output writes its connection when
/// the scan ends, an InOut stands for its connection, and other programs
/// reach Input, Output and Public parameters as `\Program.Param` only.
#[test]
fn program_parameters_copy_alias_and_are_the_only_way_between_programs() {
    let a = "Out := Out + 1;\nSeen := In;\nRef := Ref + 1.0;\nPub := Pub + 10;\n";
    let b = "Got := Cmd;\nFromA := \\A.Pub;\n\\A.Seen := 0;\n";
    let param = |name: &str, ty: &str, usage: &str, connection: &str| {
        let c = if connection.is_empty() {
            String::new()
        } else {
            format!("connection = '{connection}'\n")
        };
        format!("[[tasks.programs.tags]]\nname = \"{name}\"\ntype = \"{ty}\"\nusage = \"{usage}\"\n{c}")
    };
    let body = format!(
        "{}{}{}{}{}{}{}{}{}",
        "[[tags]]\nname = \"Speed\"\ntype = \"REAL\"\nvalue = 50.0\n",
        task("TA", "period_ms = 10.0\npriority = 5", "A", "A", ""),
        param("In", "REAL", "input", "Speed"),
        param("Out", "DINT", "output", "\\B.Cmd"),
        param("Ref", "REAL", "inout", "Speed"),
        param("Pub", "DINT", "public", ""),
        param("Seen", "REAL", "output", ""),
        task("TB", "period_ms = 10.0\npriority = 6", "B", "B", ""),
        param("Cmd", "DINT", "input", "")
            + "[[tasks.programs.tags]]\nname = \"Got\"\ntype = \"DINT\"\n[[tasks.programs.tags]]\nname = \"FromA\"\ntype = \"DINT\"\n",
    );
    let path = scene("parameters", &body, &[("A", a), ("B", b)]);
    let mut b_ = Bench::load(&path);
    b_.updates(9);
    // Scans at 0, 10, 20, 30 ms: A before B each time.
    assert_eq!(b_.int("B.Got"), 4, "A's Output reached B's Input when A's scan ended");
    assert_eq!(b_.value("Speed"), Value::Real(54.0), "the InOut wrote its connection");
    // In took Speed at each scan's start, before Ref added to it.
    assert_eq!(b_.value("A.Seen"), Value::Real(0.0), "B wrote A's Output parameter");
    assert_eq!(b_.int("B.FromA"), 40);

    for (k, (routine, want)) in [
        (
            "Got := A.Pub;",
            "'A.Pub' is a tag of program A: a program reads another program's Input, Output and Public parameters only",
        ),
        ("Got := \\A.Ref;", "'\\A.Ref' is an InOut parameter"),
        ("Got := \\A.Nope;", "'\\A.Nope' is not a tag of a program A"),
    ]
    .into_iter()
    .enumerate()
    {
        let path = scene(&format!("parameters-bad-{k}"), &body, &[("A", a), ("B", routine)]);
        let e = Bench::try_load(&path)
            .err()
            .unwrap_or_else(|| panic!("{routine} loads"));
        assert!(e.contains("B.st:1:") && e.contains(want), "{routine}: {e}");
    }
}

/// A data type with nested types, member arrays and BOOLs
/// (`[[data_types]]`), shared by the data type tests.
const CELL_TYPES: &str = r#"
[[data_types]]
name = "Station"
members = [
  { name = "Busy", type = "BOOL" },
  { name = "Done", type = "BOOL" },
  { name = "Count", type = "DINT" },
  { name = "Pos", type = "REAL", dimension = 3 },
  { name = "Label", type = "STRING" },
]

[[data_types]]
name = "Cell"
description = "the whole cell"
members = [
  { name = "Mode", type = "SINT" },
  { name = "Stations", type = "Station", dimension = 2 },
  { name = "Total", type = "LINT" },
]
"#;

/// 1756-PM001, *Create a user-defined data type*: a UDT of UDTs with
/// member arrays, BOOLs and a STRING; scene values by member; reads and
/// writes through computed subscripts at every level, and a subscript out
/// of its member array is major fault 4/20 (1756-PM014) naming the member.
#[test]
fn data_types_nest_and_take_computed_subscripts_at_every_level() {
    let main = "I := 1; J := 2;\n\
                Line.Stations[I].Pos[J] := 2.5;\n\
                Line.Stations[I].Count := Line.Stations[I].Count + 1;\n\
                Line.Stations[0].Busy := TRUE;\n\
                Line.Total := Line.Total + Line.Stations[1].Count;\n\
                Got := Line.Stations[I].Pos[J];\n\
                First := Line.Stations[0].Count;\n\
                Len := Line.Stations[0].Label.LEN;\n\
                Ch := Line.Stations[0].Label.DATA[1];\n\
                Mode := Cells[1].Mode;\n\
                Bit := Cells[1].Stations[1].Count.2;\n";
    let body = format!(
        "{CELL_TYPES}{}[[tags]]\nname = \"Line\"\ntype = \"Cell\"\nvalue = {{ Mode = 3, Stations = [{{ Count = 10, Label = \"AB\" }}, {{ Pos = [1.0, 2.0, 3.0] }}] }}\n\
         [[tags]]\nname = \"Cells\"\ntype = \"Cell[2]\"\nvalue = [{{ Mode = 1 }}, {{ Mode = 2, Stations = [{{}}, {{ Count = 4 }}] }}]\n{}",
        tags(&[
            ("I", "DINT"),
            ("J", "DINT"),
            ("Got", "REAL"),
            ("First", "DINT"),
            ("Len", "DINT"),
            ("Ch", "SINT"),
            ("Mode", "DINT"),
            ("Bit", "BOOL"),
        ]),
        task("T", "period_ms = 4.0\npriority = 5", "P", "Main", "")
    );
    let path = scene("udt", &body, &[("Main", main)]);
    let mut b = Bench::load(&path);
    b.updates(3);
    assert_eq!(b.value("Got"), Value::Real(2.5));
    assert_eq!((b.int("First"), b.int("Len"), b.int("Ch")), (10, 2, i64::from(b'B')));
    assert_eq!((b.int("Mode"), b.value("Bit")), (2, Value::Bool(true)));
    // The subscript out of its member array faults naming the member.
    let path = scene(
        "udt-fault",
        &body,
        &[("Main", "J := 3;\nGot := Line.Stations[0].Pos[J];\n")],
    );
    let mut b = Bench::load(&path);
    b.updates(1);
    let f = b.program.controller().major_fault().expect("4/20").clone();
    assert_eq!((f.fault_type, f.code, f.line), (4, 20, 2));
    assert!(f.message.contains("Line.Stations.Pos[3]"), "{}", f.message);
}

/// 1756-RM003, COP/CPS: Length counts Dest elements, and the bytes copied
/// are Length × a Dest element's size, read from the Source's bytes as
/// the controller lays them out (a REAL's bits into a DINT, a DINT into
/// four SINTs, a whole structure, one element of an array of them).
#[test]
fn cop_copies_bytes_through_the_logix_layout() {
    let main = "One := 1.0;\nCOP(One, Bits, 1);\n\
                Word := 16#04030201;\nCOP(Word, Bytes[0], 4);\n\
                COP(Line, Copy, 1);\n\
                COP(Line.Stations[1], Cells[1].Stations[0], 1);\n\
                A := Copy.Stations[0].Count; B := Cells[1].Stations[0].Pos[2];\n\
                C := Copy.Mode; D := Copy.Stations[0].Label.LEN;\n\
                E := Bytes[0] + Bytes[1] * 10 + Bytes[3] * 100;\n\
                COP(Word, Mid[1], 2);\nF := Mid[0] + Mid[1] * 10 + Mid[2] * 100 + Mid[3] * 1000;\n";
    let body = format!(
        "{CELL_TYPES}{}[[tags]]\nname = \"Line\"\ntype = \"Cell\"\nvalue = {{ Mode = 3, Stations = [{{ Count = 10, Label = \"AB\" }}, {{ Pos = [1.0, 2.0, 3.0] }}] }}\n{}",
        tags(&[
            ("One", "REAL"),
            ("Bits", "DINT"),
            ("Word", "DINT"),
            ("Bytes", "SINT[4]"),
            ("Copy", "Cell"),
            ("Cells", "Cell[2]"),
            ("A", "DINT"),
            ("B", "REAL"),
            ("C", "DINT"),
            ("D", "DINT"),
            ("E", "DINT"),
            ("Mid", "SINT[4]"),
            ("F", "DINT"),
        ]),
        task("T", "period_ms = 4.0\npriority = 5", "P", "Main", "")
    );
    let path = scene("cop-bytes", &body, &[("Main", main)]);
    let mut b = Bench::load(&path);
    b.updates(1);
    assert_eq!(b.int("Bits"), 0x3F80_0000, "a REAL's bits");
    assert_eq!(b.int("E"), 1 + 20 + 400, "little-endian bytes");
    assert_eq!(b.int("F"), 10 + 200, "two bytes into the middle of an array");
    assert_eq!((b.int("A"), b.int("C"), b.int("D")), (10, 3, 2));
    assert_eq!(b.value("B"), Value::Real(3.0));
    // Past the end of the destination: major fault 4/20.
    let path = scene("cop-past-end", &body, &[("Main", "COP(Line, Cells[1], 2);\n")]);
    let mut b = Bench::load(&path);
    b.updates(1);
    let f = b.program.controller().major_fault().expect("4/20").clone();
    assert_eq!((f.fault_type, f.code), (4, 20), "{}", f.message);
}

/// 1756-RM003, ASCII string and conversion instructions on `STRING` and
/// a user string type of 5 characters: results, comparison, and the
/// faults (4/51 a result too long, 4/52 a number's text too long, 4/53 a
/// value beyond its type, 4/56 a Start outside the source).
#[test]
fn string_instructions_convert_cut_join_compare_and_fault() {
    let main = "CONCAT(Hello, World, Msg);\n\
                MID(Msg, 3, 2, Part);\n\
                FIND(Msg, World, 1, Where);\n\
                INSERT(Hello, Dash, 3, Ins);\n\
                DELETE(Msg, 2, 1, Del);\n\
                UPPER(Msg, Up);\nLOWER(Up, Low);\n\
                N := -1234;\nDTOS(N, Num);\nSTOD(Num, Back);\n\
                X := 2.5;\nRTOS(X, Real);\nSTOR(Real, Y);\n\
                Same := Low = Msg;\nLess := Hello < World;\nMore := Msg > Hello;\n\
                Len := Msg.LEN;\n";
    let body = format!(
        "[[data_types]]\nname = \"Short\"\nstring_length = 5\n\
         [[tags]]\nname = \"Hello\"\ntype = \"STRING\"\nvalue = \"hello\"\n\
         [[tags]]\nname = \"World\"\ntype = \"Short\"\nvalue = \"world\"\n\
         [[tags]]\nname = \"Dash\"\ntype = \"Short\"\nvalue = \"--\"\n{}{}",
        tags(&[
            ("Msg", "STRING"),
            ("Part", "Short"),
            ("Ins", "STRING"),
            ("Del", "STRING"),
            ("Up", "STRING"),
            ("Low", "STRING"),
            ("Num", "STRING"),
            ("Real", "STRING"),
            ("N", "DINT"),
            ("Back", "DINT"),
            ("Where", "DINT"),
            ("X", "REAL"),
            ("Y", "REAL"),
            ("Same", "BOOL"),
            ("Less", "BOOL"),
            ("More", "BOOL"),
            ("Len", "DINT"),
        ]),
        task("T", "period_ms = 4.0\npriority = 5", "P", "Main", "")
    );
    let path = scene("strings", &body, &[("Main", main)]);
    let mut b = Bench::load(&path);
    b.updates(1);
    let text = |b: &Bench, name: &str| {
        let mem = b.program.controller().memory();
        let t = mem.find(name).expect("tag");
        let base = mem.tags[t].base;
        let len = mem.slots[base].as_i64() as usize;
        (0..len)
            .map(|k| mem.slots[base + 1 + k].as_i64() as u8 as char)
            .collect::<String>()
    };
    assert_eq!(text(&b, "Msg"), "helloworld");
    assert_eq!(text(&b, "Part"), "ell");
    assert_eq!(text(&b, "Ins"), "he--llo");
    assert_eq!(text(&b, "Del"), "lloworld");
    assert_eq!(
        (text(&b, "Up"), text(&b, "Low")),
        ("HELLOWORLD".into(), "helloworld".into())
    );
    assert_eq!((text(&b, "Num"), b.int("Back")), ("-1234".into(), -1234));
    assert_eq!((text(&b, "Real"), b.value("Y")), ("2.500000".into(), Value::Real(2.5)));
    assert_eq!((b.int("Where"), b.int("Len")), (6, 10));
    assert_eq!(
        (b.value("Same"), b.value("Less"), b.value("More")),
        (Value::Bool(true), Value::Bool(true), Value::Bool(true))
    );
    for (name, routine, code) in [
        ("concat-long", "CONCAT(Hello, World, Part);\n", 51),
        ("dtos-long", "N := 123456;\nDTOS(N, Part);\n", 52),
        ("stod-range", "STOD(Big, S);\n", 53),
        ("mid-start", "MID(Hello, 2, 82, Part);\n", 56),
        ("len-bad", "Msg.LEN := 83;\nUPPER(Msg, Up);\n", 51),
    ] {
        let extra =
            "[[tags]]\nname = \"Big\"\ntype = \"STRING\"\nvalue = \"300\"\n[[tags]]\nname = \"S\"\ntype = \"SINT\"\n";
        let path = scene(
            &format!("strings-{name}"),
            &format!("{body}{extra}"),
            &[("Main", routine)],
        );
        let mut b = Bench::load(&path);
        b.updates(1);
        let f = b
            .program
            .controller()
            .major_fault()
            .unwrap_or_else(|| panic!("{name}: no fault"))
            .clone();
        assert_eq!((f.fault_type, f.code), (4, code), "{name}: {}", f.message);
    }
}

/// MOTION-RM003, CIP axis attributes: GSV reads the configuration the
/// twin models, SSV sets what the Access column allows, a planner
/// attribute takes effect at once (a MAM started afterwards runs at the new
/// MaximumSpeed), a value the attribute does not take is refused and kept.
#[test]
fn axis_attributes_read_and_set_as_rm003_allows() {
    let main = "IF S:FS THEN\n\
                  GSV(AXIS, Table, MaximumSpeed, Speed0);\n\
                  SSV(AXIS, Table, MaximumSpeed, 90.0);\n\
                  SSV(AXIS, Table, HomePosition, 12.5);\n\
                  SSV(AXIS, Table, PositionErrorTolerance, 3.0);\n\
                  SSV(AXIS, Table, SoftTravelLimitPositive, 10.0);\n\
                  SSV(AXIS, Table, MaximumAcceleration, -1.0);\n\
                  MAM(Table, Mv, 0, 90, 100, %ofMaximum, 100, %ofMaximum, 100, %ofMaximum, trapezoidal, 100, 100, %ofTime, disabled, programmed, 0, none, 0, 0);\n\
                END_IF;\n\
                GSV(AXIS, Table, MaximumSpeed, Speed1);\n\
                GSV(AXIS, Table, HomePosition, Home);\n\
                GSV(AXIS, Table, PositionErrorTolerance, Tol);\n\
                GSV(AXIS, Table, MaximumAcceleration, Acc);\n\
                GSV(AXIS, Table, PositionScalingNumerator, Scale);\n\
                GSV(AXIS, Table, HomeMode, Mode);\n\
                GSV(AXIS, Table, CommandVelocity, Vel);\n\
                IF Vel > Peak THEN Peak := Vel; END_IF;\n";
    let body = tags(&[
        ("Speed0", "REAL"),
        ("Speed1", "REAL"),
        ("Home", "REAL"),
        ("Tol", "REAL"),
        ("Acc", "REAL"),
        ("Scale", "REAL"),
        ("Mode", "DINT"),
        ("Vel", "REAL"),
        ("Peak", "REAL"),
        ("Mv", "MOTION_INSTRUCTION"),
    ]) + &task("T", "period_ms = 4.0\npriority = 5", "P", "Main", "");
    let path = scene("axis-attributes", &body, &[("Main", main)]);
    let mut b = Bench::load(&path);
    b.updates(400);
    assert_eq!(
        (b.value("Speed0"), b.value("Speed1")),
        (Value::Real(720.0), Value::Real(90.0))
    );
    assert_eq!((b.value("Home"), b.value("Tol")), (Value::Real(12.5), Value::Real(3.0)));
    assert_eq!(
        b.value("Acc"),
        Value::Real(3600.0),
        "a negative acceleration is refused and the value kept"
    );
    assert_eq!((b.value("Scale"), b.int("Mode")), (Value::Real(360.0), 1));
    assert!(
        b.value("Peak").as_f64() <= 90.0 + 1e-9,
        "the move ran at the new maximum"
    );
    assert!(b.value("Peak").as_f64() > 80.0, "{:?}", b.value("Peak"));
    let refused = b.program.controller().refusals().join("\n");
    assert!(refused.contains("no soft travel limits"), "{refused}");
    assert!(refused.contains("max_acceleration"), "{refused}");

    let bad = |name: &str, routine: &str| {
        let path = scene(name, &body, &[("Main", routine)]);
        Bench::try_load(&path).err().unwrap_or_else(|| panic!("{name} loads"))
    };
    let e = bad("axis-ssv-read-only", "SSV(AXIS, Table, HomeMode, 0);\n");
    assert!(e.contains("'HomeMode' is read-only"), "{e}");
    let e = bad("axis-ssv-status", "SSV(AXIS, Table, ActualPosition, 0.0);\n");
    assert!(e.contains("GSV reads it, SSV does not set it"), "{e}");
    let e = bad("axis-gsv-drive", "GSV(AXIS, Table, PositionLoopBandwidth, Tol);\n");
    assert!(e.contains("has no servo drive"), "{e}");
    let e = bad("axis-gsv-unknown", "GSV(AXIS, Table, MaximumSped, Tol);\n");
    assert!(e.contains("AXIS attribute 'MaximumSped' is not modelled"), "{e}");
}

/// MOTION-RM003: SSV of a drive attribute reaches the plant's servo drive
/// from the next coarse update; a torque limit set to 1 N·m holds the
/// drive's torque under it from then on.
#[test]
fn drive_attributes_set_by_ssv_reach_the_plant() {
    let head = common::indexing_table_head().replace(
        "motor = { stiffness = 35530.6, damping = 377.0 }",
        "drive = { position_loop_bandwidth_hz = 20.0 }",
    );
    let dir = common::fresh_dir("controller-tests", "drive-attributes");
    std::fs::write(
        dir.join("Main.st"),
        "GSV(AXIS, Table, PositionLoopBandwidth, Bw);\n\
         IF S:FS THEN\n  SSV(AXIS, Table, TorqueLimitPositive, 1.0);\n  SSV(AXIS, Table, TorqueLimitNegative, -1.0);\n  SSV(AXIS, Table, VelocityLoopBandwidth, 0.0);\n\
           MAM(Table, Mv, 0, 90, 100, %ofMaximum, 100, %ofMaximum, 100, %ofMaximum, trapezoidal, 100, 100, %ofTime, disabled, programmed, 0, none, 0, 0);\nEND_IF;\n\
         GSV(AXIS, Table, TorqueLimitPositive, Limit);\n",
    )
    .expect("routine");
    let text = format!(
        "{head}{}{}",
        tags(&[("Bw", "REAL"), ("Limit", "REAL"), ("Mv", "MOTION_INSTRUCTION")]),
        task("T", "period_ms = 4.0\npriority = 5", "P", "Main", "")
    );
    let path = dir.join("scene.toml");
    std::fs::write(&path, text).expect("scene");
    let scene = twin::scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
    let mut twin = twin::run::Twin::new(scene).unwrap_or_else(|e| panic!("{e}"));
    for _ in 0..100 {
        twin.step();
    }
    let mem = twin.program().controller().memory();
    let read = |name: &str| mem.slots[mem.tags[mem.find(name).expect("tag")].base];
    assert_eq!((read("Bw"), read("Limit")), (Value::Real(20.0), Value::Real(1.0)));
    let refused = twin.program().controller().refusals().join("\n");
    assert!(refused.contains("not a positive bandwidth"), "{refused}");
    let peak = twin.plant().drive_peak_torque(0).expect("a servo drive");
    assert!(peak <= 1.0 + 1e-9, "the new torque limit holds: peak {peak} N·m");
    assert!(peak > 0.5, "the drive pushes against it: peak {peak} N·m");
}

/// An instruction's structure as a member of a data type (a station's
/// delay timer, 1756-PM001 user-defined types): TONR runs on
/// `Stations[I].Delay`, its members read and written by path, EnableIn
/// TRUE from the start; an `FBD_TIMER[2,2]` array takes two subscripts.
#[test]
fn timers_live_inside_data_types_and_two_dimensional_arrays() {
    let main = "FOR I := 0 TO 1 DO\n\
                  Line[I].Delay.PRE := 20 * (I + 1);\n\
                  Line[I].Delay.TimerEnable := TRUE;\n\
                  TONR(Line[I].Delay);\n\
                  Line[I].Ready := Line[I].Delay.DN;\n\
                END_FOR;\n\
                Grid[1, 1].PRE := 8; Grid[1, 1].TimerEnable := TRUE;\n\
                TONR(Grid[1, 1]);\n\
                A := Line[0].Delay.ACC; B := Line[1].Delay.ACC; G := Grid[1, 1].ACC;\n\
                R0 := Line[0].Ready; R1 := Line[1].Ready; En := Line[1].Delay.EnableIn;\n";
    let body = format!(
        "[[data_types]]\nname = \"Stn\"\nmembers = [{{ name = \"Ready\", type = \"BOOL\" }}, {{ name = \"Delay\", type = \"FBD_TIMER\" }}]\n{}{}",
        tags(&[
            ("Line", "Stn[2]"),
            ("Grid", "FBD_TIMER[2,2]"),
            ("I", "DINT"),
            ("A", "DINT"),
            ("B", "DINT"),
            ("G", "DINT"),
            ("R0", "BOOL"),
            ("R1", "BOOL"),
            ("En", "BOOL"),
        ]),
        task("T", "period_ms = 4.0\npriority = 5", "P", "Main", "")
    );
    let path = scene("udt-timer", &body, &[("Main", main)]);
    let mut b = Bench::load(&path);
    b.updates(8);
    // Eight scans 4 ms apart: 28 ms since the first.
    assert_eq!((b.int("A"), b.int("B"), b.int("G")), (20, 28, 8));
    assert_eq!((b.value("R0"), b.value("R1")), (Value::Bool(true), Value::Bool(false)));
    assert_eq!(b.value("En"), Value::Bool(true));
    let path = scene(
        "udt-timer-value",
        &body.replace("type = \"Stn[2]\"", "type = \"Stn[2]\"\nvalue = [{ Delay = 1 }, {}]"),
        &[("Main", main)],
    );
    let e = Bench::try_load(&path).err().expect("a value for a timer member");
    assert!(e.contains("FBD_TIMER tags take no initial value"), "{e}");
}

/// 1756-RM003, FLL and SIZE on data types: FLL into a member array
/// converts the Source to the element type, FLL of 0 clears a whole
/// structure (its bytes), SIZE gives a member array's length.
#[test]
fn fll_fills_members_and_clears_structures_and_size_measures_member_arrays() {
    let main = "FLL(2.5, Line.Stations[1].Pos[0], 3);\n\
                FLL(7, Cells[0].Stations[0].Pos[1], 2);\n\
                A := Cells[0].Stations[0].Pos[2];\n\
                B := Line.Stations[1].Pos[2];\n\
                FLL(0, Copy, 1);\n\
                C := Copy.Mode + Copy.Stations[0].Count + Copy.Stations[0].Label.LEN;\n\
                SIZE(Line.Stations, 0, N);\nSIZE(Line.Stations[0].Pos, 0, M);\n";
    let value = "{ Mode = 3, Stations = [{ Count = 10, Label = \"AB\" }, {}] }";
    let body = format!(
        "{CELL_TYPES}[[tags]]\nname = \"Line\"\ntype = \"Cell\"\n[[tags]]\nname = \"Copy\"\ntype = \"Cell\"\nvalue = {value}\n{}{}",
        tags(&[
            ("Cells", "Cell[2]"),
            ("A", "REAL"),
            ("B", "REAL"),
            ("C", "DINT"),
            ("N", "DINT"),
            ("M", "DINT"),
        ]),
        task("T", "period_ms = 4.0\npriority = 5", "P", "Main", "")
    );
    let path = scene("fll-bytes", &body, &[("Main", main)]);
    let mut b = Bench::load(&path);
    b.updates(1);
    assert_eq!((b.value("A"), b.value("B")), (Value::Real(7.0), Value::Real(2.5)));
    assert_eq!((b.int("C"), b.int("N"), b.int("M")), (0, 2, 3));
    let path = scene("fll-past-end", &body, &[("Main", "FLL(0, Cells[1], 2);\n")]);
    let mut b = Bench::load(&path);
    b.updates(1);
    let f = b.program.controller().major_fault().expect("4/20").clone();
    assert_eq!((f.fault_type, f.code), (4, 20), "{}", f.message);
}

/// A `MOTION_INSTRUCTION` member of a data type (1756-PM001, user-defined
/// data types; MOTION-RM002, MAM's Motion Control operand): MAM takes
/// `Cmd[I].Move` with a computed subscript, its bits read by path, each
/// element a control structure of its own named by its path.
#[test]
fn motion_instructions_live_inside_data_types() {
    let main = "IF S:FS THEN\n  I := 1;\n  MAM(Table, Cmd[I].Move, 1, Cmd[I].Target, 100, %ofMaximum, 100, %ofMaximum, 100, %ofMaximum, trapezoidal, 100, 100, %ofTime, disabled, programmed, 0, none, 0, 0);\nEND_IF;\n\
                Done := Cmd[I].Move.PC;\nOther := Cmd[0].Move.EN;\nPos := Table.CommandPosition;\n";
    let body = format!(
        "[[data_types]]\nname = \"AxisCmd\"\nmembers = [{{ name = \"Move\", type = \"MOTION_INSTRUCTION\" }}, {{ name = \"Target\", type = \"REAL\" }}]\n\
         [[tags]]\nname = \"Cmd\"\ntype = \"AxisCmd[2]\"\nvalue = [{{ Target = 10.0 }}, {{ Target = 45.0 }}]\n{}{}",
        tags(&[("I", "DINT"), ("Done", "BOOL"), ("Other", "BOOL"), ("Pos", "REAL")]),
        task("T", "period_ms = 4.0\npriority = 5", "P", "Main", "")
    );
    let path = scene("udt-motion", &body, &[("Main", main)]);
    let mut b = Bench::load(&path);
    b.updates(200);
    assert_eq!(
        (b.value("Done"), b.value("Other")),
        (Value::Bool(true), Value::Bool(false))
    );
    assert_eq!(b.value("Pos"), Value::Real(45.0));
    let names: Vec<&str> = b.program.instructions().iter().map(|i| i.name.as_str()).collect();
    assert_eq!(names, ["Cmd[0].Move", "Cmd[1].Move"]);
    let path = scene(
        "udt-motion-fault",
        &body,
        &[("Main", "I := 2;\nDone := Cmd[I].Move.PC;\n")],
    );
    let mut b = Bench::load(&path);
    b.updates(1);
    let f = b.program.controller().major_fault().expect("4/20").clone();
    assert_eq!((f.fault_type, f.code, f.line), (4, 20, 2), "{}", f.message);
}

/// Arrays of two dimensions of CAM and CAM_PROFILE (1756-RM003 arrays,
/// MOTION-RM002 MCCP): a CAM[2,4]'s second row is a cam of its own
/// (`Cams[1,0]`), calculated into the second row of a CAM_PROFILE[2,4]
/// (`Profiles[1,0]`), which the computed-subscript MCCP call fills as
/// well.
#[test]
fn cams_and_cam_profiles_of_two_dimensions_take_a_row_each() {
    let main = "IF S:FS THEN\n  MCCP(Calc, Cams[1,0], 3, 0.0, 0.0, Profiles[1,0]);\n  R := 0;\n  MCCP(Calc0, Cams[R,0], 2, 0.0, 0.0, Profiles[0,0]);\nEND_IF;\n\
                Done := Calc.DN AND Calc0.DN;\nErr := Calc.ERR + Calc0.ERR;\nM := Cams[1,2].Master;\n";
    let body = format!(
        "[[tags]]\nname = \"Cams\"\ntype = \"CAM[2,4]\"\nvalue = [[{{ master = 0.0, slave = 0.0 }}, {{ master = 1.0, slave = 2.0 }}], \
         [{{ master = 0.0, slave = 0.0 }}, {{ master = 5.0, slave = 1.0 }}, {{ master = 10.0, slave = 4.0 }}]]\n{}{}",
        tags(&[
            ("Profiles", "CAM_PROFILE[2,4]"),
            ("Calc", "MOTION_INSTRUCTION"),
            ("Calc0", "MOTION_INSTRUCTION"),
            ("R", "DINT"),
            ("Done", "BOOL"),
            ("Err", "DINT"),
            ("M", "REAL"),
        ]),
        task("T", "period_ms = 4.0\npriority = 5", "P", "Main", "")
    );
    let path = scene("cam-rows", &body, &[("Main", main)]);
    let mut b = Bench::load(&path);
    b.updates(5);
    assert_eq!((b.value("Done"), b.int("Err")), (Value::Bool(true), 0));
    assert_eq!(b.value("M"), Value::Real(10.0));
    let path = scene(
        "cam-rows-bad",
        &body,
        &[("Main", "MCCP(Calc, Cams[1,0], 3, 0.0, 0.0, Profiles[R,0]);\n")],
    );
    let e = Bench::try_load(&path).err().expect("a computed profile row");
    assert!(e.contains("a CAM_PROFILE row is named by constant subscripts"), "{e}");
}
