//! PLC tasks end to end: the scenes that are Structured Text programs
//! (`scara_pallet`, `knife_cut`, `fault_demo`), and the controller's rules
//! that only show with a plant and a planner (latencies, scanned motion
//! instructions).

use std::path::{Path, PathBuf};
use std::process::Command;
use twin::program::types::Value;
use twin::run::Twin;

mod common;
use common::root;

fn out_dir(name: &str) -> PathBuf {
    common::fresh_dir("task-tests", name)
}

fn load(path: &Path) -> Twin {
    let scene = twin::scene::load(path).unwrap_or_else(|e| panic!("{e}"));
    Twin::new(scene).unwrap_or_else(|e| panic!("{e}"))
}

/// Runs the `twin` binary on a scene with a trace; returns the exit code,
/// stdout, and the trace's header and rows (as text).
fn run_bin(scene: &str, out_name: &str) -> (i32, String, Vec<String>, Vec<Vec<String>>) {
    let out = out_dir(out_name);
    let output = Command::new(env!("CARGO_BIN_EXE_twin"))
        .current_dir(root())
        .args(["run", scene, "--no-render", "--trace"])
        .arg(out.join("t.csv"))
        .arg("--summary")
        .arg(out.join("s.json"))
        .output()
        .expect("run twin");
    let text = std::fs::read_to_string(out.join("t.csv")).expect("trace");
    let mut lines = text.lines();
    let header: Vec<String> = lines.next().unwrap_or_default().split(',').map(str::to_owned).collect();
    let rows = lines.map(|l| l.split(',').map(str::to_owned).collect()).collect();
    let stdout = String::from_utf8_lossy(&output.stdout).into_owned() + &String::from_utf8_lossy(&output.stderr);
    (output.status.code().unwrap_or(-1), stdout, header, rows)
}

fn col(header: &[String], name: &str) -> usize {
    header
        .iter()
        .position(|h| h == name)
        .unwrap_or_else(|| panic!("no column {name}"))
}

fn num(s: &str) -> f64 {
    s.parse().unwrap_or_else(|_| panic!("not a number: {s}"))
}

#[test]
fn scara_pallet_places_twelve_parts_each_within_the_actual_tolerance_of_its_target() {
    let (code, stdout, h, rows) = run_bin("scenes/scara_pallet.toml", "scara_pallet");
    assert_eq!(code, 0, "{stdout}");
    let (state, k) = (col(&h, "Pallet.State"), col(&h, "Pallet.K"));
    let tool = [col(&h, "Cart.tool_x"), col(&h, "Cart.tool_y"), col(&h, "Cart.tool_z")];
    let target = [
        col(&h, "Pallet.Target[0]"),
        col(&h, "Pallet.Target[1]"),
        col(&h, "Pallet.Target[2]"),
    ];
    // The MCT robot frame (mct_base) is 0.55 m above the world origin.
    let base = [0.0, 0.0, 0.55];
    // The pallet as the routine computes it: corner (0.30, 0.15), pitch 0.05,
    // 3 rows of 4.
    let mut placed = Vec::new();
    for w in rows.windows(2) {
        // The release dwell (state 70) starts once the move down is complete.
        if w[1][state] == "70" && w[0][state] != "70" {
            let i = num(&w[1][k]) as usize;
            let want = [0.30 + (i / 4) as f64 * 0.05, 0.15 + (i % 4) as f64 * 0.05, -0.20];
            for a in 0..3 {
                let traced = num(&w[1][target[a]]);
                assert!(
                    (traced - want[a]).abs() < 1e-6,
                    "placement {i}: target {a} is {traced}, want {}",
                    want[a]
                );
                let err = (num(&w[1][tool[a]]) - base[a] - want[a]).abs();
                assert!(err <= 0.001, "placement {i}: tool off the target by {err} m along {a}");
            }
            placed.push(i);
        }
    }
    assert_eq!(placed, (0..12).collect::<Vec<_>>());
    let last = rows.last().expect("rows");
    assert_eq!(last[state], "100", "the pallet is full");
    assert_eq!(last[col(&h, "Pallet.Placed.ACC")], "12");
    assert!(stdout.contains("tasks: "), "{stdout}");
}

#[test]
fn knife_cut_switches_cams_at_the_end_of_the_running_cycle() {
    let (code, stdout, h, rows) = run_bin("scenes/knife_cut.toml", "knife_cut");
    assert_eq!(code, 0, "{stdout}");
    let (master, slave) = (col(&h, "Conveyor.cmd_pos"), col(&h, "Knife.cmd_pos"));
    let (switches, lock_at) = (col(&h, "Cutter.Switches"), col(&h, "Cutter.LockAt"));
    let pending = col(&h, "Knife.PositionCamPendingStatus");
    let last = rows.last().expect("rows");
    assert_eq!(last[switches], "2", "two cut-length changes");
    // Each switch: pending until the conveyor reaches LockAt, where the
    // knife has just completed a whole number of revolutions.
    let mut seen = Vec::new();
    for w in rows.windows(2) {
        if w[0][pending] == "1" && w[1][pending] == "0" {
            let at = num(&w[1][lock_at]);
            let m = num(&w[1][master]);
            assert!((m - at).abs() < 1.0, "replaced at master {m}, scheduled at {at}");
            let s = num(&w[1][slave]);
            let turns = s / 360.0;
            assert!(
                (turns - turns.round()).abs() < 0.01,
                "knife at {s} deg when the cam was replaced"
            );
            seen.push(at);
        }
    }
    assert_eq!(
        seen,
        vec![300.0, 700.0],
        "300 mm cycles end at 300; 200 mm cycles from 300 end at 700"
    );
    // After the second switch the knife turns once per 250 mm.
    let after: Vec<&Vec<String>> = rows.iter().filter(|r| num(&r[master]) >= 700.0).collect();
    let (m0, s0) = (num(&after[0][master]), num(&after[0][slave]));
    let end = after.last().expect("rows after 700");
    let rate = (num(&end[slave]) - s0) / (num(&end[master]) - m0);
    assert!((rate - 360.0 / 250.0).abs() < 0.05, "knife {rate} deg/mm");
}

#[test]
fn fault_demo_records_the_minor_fault_and_stops_on_the_major_with_exit_code_4() {
    let (code, stdout, h, rows) = run_bin("scenes/fault_demo.toml", "fault_demo");
    assert_eq!(code, 4, "{stdout}");
    assert!(
        stdout.contains("MAJOR FAULT type 4 code 20") && stdout.contains("Main.st:8"),
        "{stdout}"
    );
    assert!(
        stdout.contains("type 4 code 4") && stdout.contains("Main.st:13"),
        "{stdout}"
    );
    let last = rows.last().expect("rows");
    assert_eq!(
        last[col(&h, "Cell.Faults")],
        "1",
        "MinorFaults counts the division by zero"
    );
    assert_eq!(last[col(&h, "Cell.Average")], "2147483647", "the documented quotient");
    assert!(
        (num(&last[0]) - 1.084).abs() < 1e-9,
        "the run ends with the update of the fault"
    );
    let summary = std::fs::read_to_string(out_dir_path("fault_demo").join("s.json")).expect("summary");
    assert!(
        summary.contains("\"major_fault\"") && summary.contains("\"code\": 20"),
        "{summary}"
    );
    // 55 scans of the 20 ms Logger, the last one the fault's, none overlapping.
    assert!(
        summary.contains("\"name\": \"Logger\",\n        \"scans\": 55,\n        \"overlaps\": 0"),
        "{summary}"
    );
}

fn out_dir_path(name: &str) -> PathBuf {
    common::out_path("task-tests", name)
}

/// A scene in `target/task-tests/<name>/` on the indexing table fixture, with
/// `tags` and one task of `period_ms` whose main routine is `routine`.
fn scene(name: &str, tags: &str, routine: &str, period_ms: f64) -> PathBuf {
    let dir = out_dir(name);
    std::fs::write(dir.join("Main.st"), routine).expect("routine");
    let text = format!(
        "{}[[axes]]\nname = \"Slide\"\njoint = \"slide_joint\"\nkind = \"linear\"\nunits = \"mm\"\n\
         max_velocity = 500.0\nmax_acceleration = 5000.0\nmax_deceleration = 5000.0\nmax_jerk = 50000.0\n\
         in_position_window = 0.05\n\
         [[tags]]\nname = \"XY\"\ntype = \"COORDINATE_SYSTEM\"\nvalue = [\"Table\", \"Slide\"]\n\
         {tags}\n\
         [[tasks]]\nname = \"T\"\nperiod_ms = {period_ms:?}\npriority = 5\n\
         [[tasks.programs]]\nname = \"P\"\nmain = \"Main.st\"\n",
        common::indexing_table_head()
    );
    let path = dir.join("scene.toml");
    std::fs::write(&path, text).expect("scene");
    path
}

fn tag(name: &str, ty: &str) -> String {
    format!("[[tags]]\nname = \"{name}\"\ntype = \"{ty}\"\n")
}

fn value(twin: &Twin, name: &str) -> Value {
    let mem = twin.program().controller().memory();
    let t = mem.find(name).unwrap_or_else(|| panic!("no tag {name}"));
    mem.slots[mem.tags[t].base]
}

fn axis(twin: &Twin, name: &str) -> planner::task::AxisHandle {
    twin.plant()
        .axes()
        .iter()
        .find(|a| a.name == name)
        .expect("axis")
        .handle
}

fn control(twin: &Twin, name: &str) -> planner::task::InstructionHandle {
    twin.program()
        .instructions()
        .iter()
        .find(|b| b.name.eq_ignore_ascii_case(name))
        .expect("control structure")
        .handle
}

const MAJ: &str = "MAJ(Table, Jog, Forward, 90.0, UnitsPerSec, 900.0, UnitsPerSec2, 900.0, UnitsPerSec2, Trapezoidal);";

#[test]
fn a_10_ms_task_on_a_4_ms_update_runs_at_the_first_update_after_each_trigger() {
    let routine = format!("Scans := Scans + 1; IF Scans = 2 THEN {MAJ} END_IF; Seen := Table.ActualPosition;");
    let tags = format!(
        "{}{}{}",
        tag("Scans", "DINT"),
        tag("Seen", "REAL"),
        tag("Jog", "MOTION_INSTRUCTION")
    );
    let mut twin = load(&scene("latency", &tags, &routine, 10.0));
    let table = axis(&twin, "Table");
    let mut scans_at = Vec::new();
    let mut started_at = None;
    for _ in 0..10 {
        let before = twin.task().axis_state(table).actual_position;
        let t = twin.time_s();
        let scans = value(&twin, "Scans");
        twin.step();
        if value(&twin, "Scans") != scans {
            scans_at.push((t * 1000.0).round() as i64);
            // ActualPosition as the scan saw it: the last update's, at REAL precision.
            assert_eq!(value(&twin, "Seen"), Value::Real(f64::from(before as f32)));
        }
        if started_at.is_none() && twin.task().axis_state(table).command_velocity > 0.0 {
            started_at = Some((t * 1000.0).round() as i64);
        }
    }
    // Triggers at 0, 10, 20, 30 ms run at the updates starting at 0, 12, 20, 32 ms.
    assert_eq!(scans_at, vec![0, 12, 20, 32]);
    // The MAJ of the scan triggered at 10 ms takes effect in the update from 12 ms.
    assert_eq!(started_at, Some(12));
}

const MCLM: &str = "MCLM(XY, Move, 0, Target[0], 100.0, unitspersec, 1000, unitspersec2, 1000, unitspersec2, trapezoidal, 100, 100, %ofTime, 1, disabled, programmed, 0, 0, none, 0, 0);";

#[test]
fn an_mclm_in_a_branch_not_scanned_keeps_its_en_set() {
    let routine = format!("IF NOT Started THEN {MCLM} Started := TRUE; END_IF;");
    let tags = format!(
        "{}{}{}",
        tag("Started", "BOOL"),
        tag("Move", "MOTION_INSTRUCTION"),
        "[[tags]]\nname = \"Target\"\ntype = \"REAL[2]\"\nvalue = [30.0, 10.0]\n"
    );
    let mut twin = load(&scene("en_held", &tags, &routine, 4.0));
    let mv = control(&twin, "Move");
    for _ in 0..200 {
        twin.step();
    }
    let b = twin.task().motion_bits(mv);
    assert!(b.pc && b.dn, "the move completed: {b:?}");
    assert!(b.en, ".EN stays set: the statement is not scanned again");
}

#[test]
fn an_unguarded_mclm_executes_at_every_scan_and_queues_behind_itself() {
    // Written without a one-shot, the MCLM executes at every scan, each time
    // as a new execution with Merge Disabled: the second scan queues a
    // second move behind the running one (Move Pending); from the third on
    // the queue is full, so each execution is held: .DN stays clear while
    // the first move runs, and the instruction never reports its first
    // move's completion while the axis travels.
    let routine = MCLM.to_string();
    let tags = format!(
        "{}{}",
        tag("Move", "MOTION_INSTRUCTION"),
        "[[tags]]\nname = \"Target\"\ntype = \"REAL[2]\"\nvalue = [30.0, 10.0]\n"
    );
    let mut twin = load(&scene("unguarded", &tags, &routine, 4.0));
    let mv = control(&twin, "Move");
    let xy = twin.task().coord_handles().next().expect("XY");
    let table = axis(&twin, "Table");
    let mut travelling = 0;
    for update in 0..200 {
        twin.step();
        let b = twin.task().motion_bits(mv);
        let position = twin.task().axis_state(table).command_position;
        if update >= 2 && position < 29.9 {
            travelling += 1;
            assert!(b.en && !b.dn && !b.pc, "update {update}: held, {b:?}");
            assert!(
                twin.task().coord_status(xy).move_pending,
                "update {update}: a move queued"
            );
        }
    }
    assert!(travelling > 90, "{travelling} updates travelling");
    let end = twin.task().axis_state(table).command_position;
    assert!((end - 30.0).abs() < 1e-9, "it still reaches the target: {end}");
}

#[test]
fn a_motion_operand_computed_by_the_program_is_read_when_the_instruction_executes() {
    let routine =
        format!("Scans := Scans + 1;\nIF Scans = 3 THEN Target[0] := 10.0 * Scans; Target[1] := 5.0; {MCLM} END_IF;");
    let tags = format!(
        "{}{}{}",
        tag("Scans", "DINT"),
        tag("Move", "MOTION_INSTRUCTION"),
        tag("Target", "REAL[2]")
    );
    let mut twin = load(&scene("computed", &tags, &routine, 4.0));
    for _ in 0..300 {
        twin.step();
    }
    let table = twin.task().axis_state(axis(&twin, "Table"));
    assert!(
        (table.command_position - 30.0).abs() < 1e-9,
        "{}",
        table.command_position
    );
}

#[test]
fn motion_instruction_members_read_and_write_like_tags() {
    let routine = format!(
        "IF NOT Started THEN {MCLM} Started := TRUE; END_IF;\n\
         IF Move.PC AND NOT Seen THEN Seen := TRUE; Move.PC := FALSE; Err := Move.ERR; END_IF;"
    );
    let tags = format!(
        "{}{}{}{}{}",
        tag("Started", "BOOL"),
        tag("Seen", "BOOL"),
        tag("Err", "DINT"),
        tag("Move", "MOTION_INSTRUCTION"),
        "[[tags]]\nname = \"Target\"\ntype = \"REAL[2]\"\nvalue = [30.0, 10.0]\n"
    );
    let mut twin = load(&scene("members", &tags, &routine, 4.0));
    for _ in 0..200 {
        twin.step();
    }
    assert_eq!(value(&twin, "Seen"), Value::Bool(true));
    assert!(
        !twin.task().motion_bits(control(&twin, "Move")).pc,
        "the program cleared .PC"
    );
}

#[test]
fn writing_an_axis_member_is_refused_at_load_with_the_routine_line() {
    let path = scene(
        "readonly",
        &tag("X", "REAL"),
        "X := 1.0;\nTable.ActualPosition := X;",
        4.0,
    );
    let scene = twin::scene::load(&path).expect("parses");
    let e = Twin::new(scene).expect_err("refused").to_string();
    assert!(e.contains("Main.st:2:1") && e.contains("read-only"), "{e}");
}

#[test]
fn twin_check_reports_a_routine_syntax_error_with_file_line_and_column() {
    let path = scene(
        "syntax",
        &tag("X", "REAL"),
        "X := 1.0;\nIF X > 0 THEN\n  X := ;\nEND_IF;",
        4.0,
    );
    let output = Command::new(env!("CARGO_BIN_EXE_twin"))
        .args(["check"])
        .arg(&path)
        .output()
        .expect("run twin");
    let stderr = String::from_utf8_lossy(&output.stderr);
    // Invalid input: exit code 65 (README, "Errors and exit codes").
    assert_eq!(output.status.code(), Some(65));
    assert!(stderr.contains("Main.st:3:8: expected an operand"), "{stderr}");
}

/// Issue 39, 16: an instance's output read in one of its own call's
/// inputs (`Execute := NOT Move.Busy`) was refused with "'Move' is never
/// called"; the instance is now made before its inputs are compiled.
/// The table scene with `routine` as an IEC main routine and the table a
/// modulo axis, run for 300 updates (1.2 s).
fn iec_table_run(name: &str, tags: &str, routine: &str) -> twin::run::Twin {
    let path = scene(name, tags, routine, 4.0);
    let text = std::fs::read_to_string(&path).expect("scene");
    let text = text
        .replace("main = \"Main.st\"", "main = { file = \"Main.st\", dialect = \"iec\" }")
        .replacen("kind = \"rotary\"", "kind = \"rotary\"\nmodulo_period = 360.0", 1);
    std::fs::write(&path, text).expect("scene");
    let mut twin = load(&path);
    for _ in 0..300 {
        twin.step();
    }
    twin
}

#[test]
fn an_iec_call_may_read_its_own_instances_outputs() {
    let routine = "Move(Axis := Table, Execute := NOT Move.Busy AND NOT Move.Done, Position := 90.0, Velocity := 180.0,\n\
                        Acceleration := 1800.0, Deceleration := 1800.0, Jerk := 18000.0,\n\
                        Direction := MC_Positive_Direction, BufferMode := MC_Aborting);\n\
                   IF Move.Done THEN Finished := TRUE; END_IF;";
    let tags = format!("{}{}", tag("Finished", "BOOL"), tag("Move", "MC_MoveModulo"));
    let twin = iec_table_run("iec_fb_self_read", &tags, routine);
    assert_eq!(value(&twin, "Finished"), Value::Bool(true));
}

#[test]
fn an_iec_routine_calls_mc_move_modulo_on_its_instance_and_reads_its_outputs() {
    let routine = "Trig.CLK := TRUE; R_TRIG(Trig); IF Trig.Q THEN Go := TRUE; END_IF;\n\
                   Move(Axis := Table, Execute := Go, Position := 90.0, Velocity := 180.0, Acceleration := 1800.0,\n\
                        Deceleration := 1800.0, Jerk := 18000.0, Direction := MC_Positive_Direction, BufferMode := MC_Aborting);\n\
                   IF Move.Done THEN Finished := TRUE; Go := FALSE; END_IF;";
    let tags = format!(
        "{}{}{}{}",
        tag("Trig", "R_TRIG"),
        tag("Go", "BOOL"),
        tag("Finished", "BOOL"),
        tag("Move", "MC_MoveModulo")
    );
    let twin = iec_table_run("iec_fb", &tags, routine);
    assert_eq!(value(&twin, "Finished"), Value::Bool(true));
    let table = twin.task().axis_state(axis(&twin, "Table"));
    assert!(
        (table.command_position - 90.0).abs() < 1e-9,
        "{}",
        table.command_position
    );

    // The same routine in the Logix dialect is refused, naming the dialect.
    let logix = scene("iec_fb_in_logix", &tags, routine, 4.0);
    let e = Twin::new(twin::scene::load(&logix).expect("parses"))
        .expect_err("refused")
        .to_string();
    assert!(e.contains("IEC"), "{e}");
}

#[test]
fn mrp_mas_and_mcs_run_from_a_routine() {
    // Scan 1 redefines Table's position to 100 (MRP, no motion); scan 2
    // jogs it; scan 50 stops the jog (MAS). Scan 2 also starts an MCLM of
    // XY that scan 20 stops (MCS).
    let routine = format!(
        "N := N + 1;\n\
         IF N = 1 THEN MRP(Table, Redefine, absolute, command, 100.0); END_IF;\n\
         IF N = 2 THEN {MAJ} MCLM(XY, Move, 1, Target[0], 10.0, unitspersec, 1000, unitspersec2, 1000, unitspersec2, trapezoidal, 100, 100, %ofTime, 1, disabled, programmed, 0, 0, none, 0, 0); END_IF;\n\
         IF N = 20 THEN MCS(XY, Halt, coordinatedmove, yes, 500.0, unitspersec², no, 100.0, %ofTime); END_IF;\n\
         IF N = 50 THEN MAS(Table, Stop, jog, yes, 900.0, unitspersec²); END_IF;"
    );
    let tags = format!(
        "{}{}{}{}{}{}{}",
        tag("N", "DINT"),
        tag("Redefine", "MOTION_INSTRUCTION"),
        tag("Jog", "MOTION_INSTRUCTION"),
        tag("Stop", "MOTION_INSTRUCTION"),
        tag("Move", "MOTION_INSTRUCTION"),
        tag("Halt", "MOTION_INSTRUCTION"),
        "[[tags]]\nname = \"Target\"\ntype = \"REAL[2]\"\nvalue = [0.0, 50.0]\n"
    );
    let mut twin = load(&scene("mrp_mas_mcs", &tags, &routine, 4.0));
    let (table, slide) = (axis(&twin, "Table"), axis(&twin, "Slide"));
    twin.step();
    assert_eq!(twin.task().axis_state(table).command_position, 100.0, "MRP redefined");
    for _ in 0..300 {
        twin.step();
    }
    for name in ["Redefine", "Jog", "Stop", "Move", "Halt"] {
        let b = twin.task().motion_bits(control(&twin, name));
        assert!(!b.er, "{name}: {b:?}");
    }
    assert!(twin.task().motion_bits(control(&twin, "Stop")).pc, "MAS complete");
    assert_eq!(twin.task().axis_state(table).command_velocity, 0.0, "the jog stopped");
    let s = twin.task().axis_state(slide).command_position;
    assert!(s > 0.0 && s < 50.0, "MCS halted the move part way: Slide at {s}");
}

#[test]
fn ssv_sets_an_axis_limit_that_later_instructions_plan_with() {
    // MaximumSpeed 90 deg/s, then a jog at 100 % of maximum; an SSV of 0 is
    // refused and the limit kept.
    let routine = "N := N + 1;\n\
                   IF N = 1 THEN SSV(AXIS, Table, MaximumSpeed, 90.0); SSV(AXIS, Table, MaximumAcceleration, 0.0); END_IF;\n\
                   GSV(AXIS, Table, MaximumSpeed, Speed);\n\
                   IF N = 2 THEN MAJ(Table, Jog, Forward, 100.0, %ofMaximum, 900.0, UnitsPerSec2, 900.0, UnitsPerSec2, Trapezoidal); END_IF;";
    let tags = format!(
        "{}{}{}",
        tag("N", "DINT"),
        tag("Speed", "REAL"),
        tag("Jog", "MOTION_INSTRUCTION")
    );
    let out = out_dir_path("ssv");
    let path = scene("ssv", &tags, routine, 4.0);
    let mut twin = load(&path);
    for _ in 0..100 {
        twin.step();
    }
    assert_eq!(value(&twin, "Speed"), Value::Real(90.0));
    let table = twin.task().axis_state(axis(&twin, "Table"));
    assert!(
        (table.command_velocity - 90.0).abs() < 1e-9,
        "{}",
        table.command_velocity
    );
    assert_eq!(
        twin.task().axis_config(axis(&twin, "Table")).max_acceleration,
        3600.0,
        "0 refused"
    );
    let refused = twin.program().controller().refusals();
    assert!(
        refused.len() == 1 && refused[0].contains("max_acceleration"),
        "{refused:?} ({})",
        out.display()
    );
}

#[test]
fn aliases_stand_for_members_elements_bits_and_other_aliases_in_their_scope() {
    let tags = format!(
        "{}{}{}[[data_types]]\nname = \"R\"\nmembers = [{{ name = \"N\", type = \"DINT\" }}]\n\
         [[aliases]]\nname = \"Count\"\nalias_for = \"Rec.N\"\n\
         [[aliases]]\nname = \"Third\"\nalias_for = \"Arr[2]\"\n\
         [[aliases]]\nname = \"Bit5\"\nalias_for = \"Word.5\"\n\
         [[aliases]]\nname = \"Again\"\nalias_for = \"Count\"\n",
        tag("Rec", "R"),
        tag("Arr", "REAL[4]"),
        tag("Word", "DINT"),
    );
    let routine = "Count := Count + 1; Again := Again + 10; Third := 7.5; Bit5 := TRUE; Mine := Third + 1.0;";
    let path = scene("aliases", &tags, routine, 10.0);
    // The program's own alias Third shadows the controller's.
    let mut text = std::fs::read_to_string(&path).unwrap();
    text.push_str(
        "[[tasks.programs.tags]]\nname = \"Own\"\ntype = \"REAL\"\n\
         [[tasks.programs.tags]]\nname = \"Out\"\ntype = \"REAL\"\n\
         [[tasks.programs.aliases]]\nname = \"Third\"\nalias_for = \"Own\"\n\
         [[tasks.programs.aliases]]\nname = \"Mine\"\nalias_for = \"Out\"\n\
         [trace]\ntags = [\"Third\", \"Count\"]\n",
    );
    std::fs::write(&path, text).unwrap();
    let mut twin = load(&path);
    twin.step();
    let mem = twin.program().controller().memory();
    let slot = |name: &str, k: usize| mem.slots[mem.tags[mem.find(name).expect(name)].base + k];
    assert_eq!(slot("Rec", 0), Value::Int(11));
    assert_eq!(slot("Word", 0), Value::Int(32));
    assert_eq!(slot("Arr", 2), Value::Real(0.0));
    assert_eq!(slot("P.Own", 0), Value::Real(7.5));
    assert_eq!(slot("P.Out", 0), Value::Real(8.5));
}

#[test]
fn an_alias_naming_nothing_or_itself_is_refused_at_its_alias_for() {
    for (name, aliases, words) in [
        (
            "alias_dangling",
            "[[aliases]]\nname = \"A\"\nalias_for = \"Nope.X\"\n",
            "'Nope' is not",
        ),
        (
            "alias_circle",
            "[[aliases]]\nname = \"A\"\nalias_for = \"B\"\n[[aliases]]\nname = \"B\"\nalias_for = \"A.1\"\n",
            "stands for itself",
        ),
        (
            "alias_not_a_ref",
            "[[aliases]]\nname = \"A\"\nalias_for = \"1 + 2\"\n",
            "an alias stands for a tag",
        ),
    ] {
        let path = scene(name, aliases, "", 10.0);
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_twin"))
            .arg("check")
            .arg(&path)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(65), "{name}: {stderr}");
        let text = std::fs::read_to_string(&path).unwrap();
        let line = text[..text.find("alias_for").unwrap()].matches('\n').count() + 1;
        let first = stderr.lines().next().unwrap_or_default();
        assert!(first.contains(&format!("scene.toml:{line}:")), "{name}: {first}");
        assert!(first.contains(words), "{name}: {first}");
    }
}
