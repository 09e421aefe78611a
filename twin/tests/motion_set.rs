//! The rest of the everyday motion set in routines, in the sandbox (no
//! physics): MCD's bits and its change of a running move, its Format
//! errors at load and its ERR 13 at run time.

mod common;

use twin::program::Program;
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

const GROUP_TAGS: &[(&str, &str)] = &[
    ("G", "MOTION_GROUP"),
    ("Jog1", "MOTION_INSTRUCTION"),
    ("Mam1", "MOTION_INSTRUCTION"),
    ("Mgs1", "MOTION_INSTRUCTION"),
    ("Mgsd1", "MOTION_INSTRUCTION"),
    ("Mgsr1", "MOTION_INSTRUCTION"),
    ("Mgsp1", "MOTION_INSTRUCTION"),
    ("Stop", "BOOL"),
    ("Move", "BOOL"),
    ("Down", "BOOL"),
    ("Reset", "BOOL"),
    ("Strobe", "BOOL"),
    ("V", "REAL"),
    ("P", "REAL"),
    ("Latched", "REAL"),
    ("LatchedActual", "REAL"),
    ("Bits", "DINT"),
    ("Synced", "BOOL"),
    ("ServoOn", "BOOL"),
    ("Shut", "BOOL"),
    ("MgsPc", "BOOL"),
    ("MgsIp", "BOOL"),
    ("MgsDn", "BOOL"),
    ("MamIp", "BOOL"),
    ("MamErr", "DINT"),
    ("MgspDn", "BOOL"),
];

/// X jogs at its maximum speed (1 mm/s); `Stop` runs MGS with `mode`,
/// `Move` a MAM, `Down` MGSD, `Reset` MGSR, `Strobe` MGSP.
fn group_routine(mode: &str) -> String {
    format!(
        "
IF NOT Jog1.EN THEN MAJ(X, Jog1, 0, 100, %ofMaximum, 100, %ofMaximum, 100, %ofMaximum, trapezoidal); END_IF;
P := X.CommandPosition;
IF Stop AND NOT Mgs1.EN THEN MGS(G, Mgs1, {mode}); END_IF;
IF Move AND NOT Mam1.EN THEN
    MAM(X, Mam1, 1, 0.5, 0.5, UnitsPerSec, 10, UnitsPerSec2, 10, UnitsPerSec2, trapezoidal, 100, 100, %ofTime, disabled, programmed, 0, none, 0, 0);
END_IF;
IF Down AND NOT Mgsd1.EN THEN MGSD(G, Mgsd1); END_IF;
IF Reset AND NOT Mgsr1.EN THEN MGSR(G, Mgsr1); END_IF;
IF Strobe AND NOT Mgsp1.EN THEN MGSP(G, Mgsp1); END_IF;
V := X.CommandVelocity;
Latched := X.StrobeCommandPosition; LatchedActual := X.StrobeActualPosition;
Bits := G.GroupStatus; Synced := G.GroupSynced;
ServoOn := X.ServoActionStatus; Shut := X.ShutdownStatus;
MgsPc := Mgs1.PC; MgsIp := Mgs1.IP; MgsDn := Mgs1.DN;
MamIp := Mam1.IP; MamErr := Mam1.ERR; MgspDn := Mgsp1.DN;
"
    )
}

fn group_sandbox(mode: &str) -> Sandbox {
    Sandbox::with_axes(&["X"], GROUP_TAGS, &group_routine(mode)).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn mgs_fast_stop_brings_every_axis_to_rest_at_its_maximum_deceleration_and_a_move_follows() {
    let mut s = group_sandbox("faststop");
    for _ in 0..40 {
        s.scan();
    }
    assert!((real(&s, "V") - 1.0).abs() < 1e-6);
    assert!(
        flag(&s, "Synced") && int(&s, "Bits") == 2,
        "GroupSynced, nothing inhibited"
    );
    s.set("Stop", Value::Bool(true));
    s.scan();
    assert!(flag(&s, "MgsDn") && flag(&s, "MgsIp") && !flag(&s, "MgsPc"));
    // The sandbox axis' maximum deceleration is 10 mm/s²: 0.04 mm/s an
    // update, at rest after 25 updates (V is read in each scan, before its
    // update: the MGS scan reads 1 mm/s, then 25 scans ramp it).
    let mut last = real(&s, "V");
    let mut updates = 1;
    while real(&s, "V") > 0.0 {
        s.scan();
        let v = real(&s, "V");
        assert!((last - v - 0.04).abs() < 1e-6 || v == 0.0, "{last} → {v}");
        last = v;
        updates += 1;
        assert!(updates < 40);
    }
    assert_eq!(updates, 26);
    s.scan();
    assert!(
        flag(&s, "MgsPc") && !flag(&s, "MgsIp"),
        ".PC once every axis is at rest"
    );
    assert!(flag(&s, "ServoOn"), "Fast Stop leaves the servo on");
    s.set("Move", Value::Bool(true));
    s.scan();
    s.scan();
    assert!(flag(&s, "MamIp") && real(&s, "V") > 0.0, "a following MAM runs");
}

#[test]
fn mgs_fast_disable_leaves_the_drive_off() {
    let mut s = group_sandbox("fastdisable");
    for _ in 0..40 {
        s.scan();
    }
    s.set("Stop", Value::Bool(true));
    for _ in 0..24 {
        s.scan();
        assert!(flag(&s, "ServoOn"), "on while it ramps");
    }
    for _ in 0..3 {
        s.scan();
    }
    assert!(flag(&s, "MgsPc") && !flag(&s, "ServoOn"), "off once at rest");
    s.set("Move", Value::Bool(true));
    s.scan();
    assert_eq!(int(&s, "MamErr"), 5, "servo off state: MSO again");
}

#[test]
fn mgsd_shuts_the_group_down_until_mgsr() {
    let mut s = group_sandbox("programmed");
    for _ in 0..10 {
        s.scan();
    }
    s.set("Down", Value::Bool(true));
    s.scan();
    assert!(flag(&s, "Shut") && real(&s, "V") == 0.0);
    for _ in 0..10 {
        s.scan();
        assert!(flag(&s, "Shut"), "stays shut down");
    }
    s.set("Move", Value::Bool(true));
    s.scan();
    assert_eq!(int(&s, "MamErr"), 7, "shutdown state");
    s.set("Reset", Value::Bool(true));
    s.scan();
    assert!(!flag(&s, "Shut"));
}

#[test]
fn mgsp_latches_the_positions_of_that_update() {
    let mut s = group_sandbox("programmed");
    for _ in 0..30 {
        s.scan();
    }
    let before = real(&s, "P");
    s.set("Strobe", Value::Bool(true));
    s.scan();
    assert!(flag(&s, "MgspDn"));
    // P is read in the scan before MGSP executes: the command position of
    // the last update, which MGSP latches.
    assert_eq!(real(&s, "Latched"), real(&s, "P"));
    assert!(real(&s, "P") > before);
    let latched = real(&s, "Latched");
    for _ in 0..5 {
        s.scan();
    }
    assert_eq!(real(&s, "Latched"), latched, "held until the next MGSP");
    assert_eq!(real(&s, "LatchedActual"), latched, "no plant: actual = command");
}

#[test]
fn group_operands_are_checked_at_load() {
    for (routine, needle) in [
        ("MGS(G, Mgs1, 5);", "Stop Mode"),
        ("MGS(X, Mgs1, programmed);", "MOTION_GROUP"),
        ("MGSD(Jog1, Mgsd1);", "MOTION_GROUP"),
        ("V := G.Speed;", "no member 'Speed'"),
        ("G.GroupStatus := 1;", "read"),
    ] {
        let e = match Sandbox::with_axes(&["X"], GROUP_TAGS, routine) {
            Ok(_) => panic!("{routine} loads"),
            Err(e) => e,
        };
        assert!(e.contains(needle), "{routine}: {e}");
    }
}

#[test]
fn maw_and_mdw_in_a_routine() {
    let tags = &[
        ("W", "MOTION_INSTRUCTION"),
        ("D", "MOTION_INSTRUCTION"),
        ("Arm", "BOOL"),
        ("Disarm", "BOOL"),
        ("Where", "REAL"),
        ("Armed", "BOOL"),
        ("Ip", "BOOL"),
        ("Dn", "BOOL"),
        ("Err", "DINT"),
        ("Exerr", "DINT"),
        ("Set", "REAL"),
    ];
    let routine = "
IF Arm AND NOT W.EN THEN MAW(X, W, reverse, Where); END_IF;
IF Disarm AND NOT D.EN THEN MDW(X, D); END_IF;
Armed := X.WatchEventArmedStatus; Set := X.WatchPosition;
Ip := W.IP; Dn := W.DN; Err := W.ERR; Exerr := W.EXERR;
";
    let mut s = Sandbox::with_axes(&["X"], tags, routine).unwrap_or_else(|e| panic!("{e}"));
    s.set("Where", Value::Real(-2.5));
    s.set("Arm", Value::Bool(true));
    s.scan();
    assert!(flag(&s, "Dn") && flag(&s, "Ip") && flag(&s, "Armed"));
    assert_eq!(real(&s, "Set"), -2.5);
    s.set("Disarm", Value::Bool(true));
    s.scan();
    assert!(!flag(&s, "Ip") && !flag(&s, "Armed"), "MDW disarms");
    // A position that is not a number: ERR 13 on Position (faceplate 3).
    let mut s = Sandbox::with_axes(&["X"], tags, routine).unwrap_or_else(|e| panic!("{e}"));
    s.set("Where", Value::Real(f64::INFINITY));
    s.set("Arm", Value::Bool(true));
    s.scan();
    assert_eq!((int(&s, "Err"), int(&s, "Exerr")), (13, 3));
    assert!(!flag(&s, "Armed"));
    // The trigger is Immediate: refused at load.
    let e = match Sandbox::with_axes(&["X"], tags, "MAW(X, W, sideways, 1.0);") {
        Ok(_) => panic!("loads"),
        Err(e) => e,
    };
    assert!(e.contains("Trigger Condition"), "{e}");
}

/// A scene of virtual axes: Cartesian X, Y, Z (m) and a SCARA J1, J2 (deg)
/// sharing Z, with `routine` in a 4 ms task; two scans run.
fn scara_program(name: &str, tags: &[(&str, &str)], routine: &str) -> Program {
    let (mut program, mut task) = scara_bind(name, tags, routine).unwrap_or_else(|e| panic!("{e}"));
    for _ in 0..2 {
        program.scan(&mut task);
        task.update();
    }
    program
}

/// The scene of [`scara_program`] loaded and bound, or the error.
fn scara_bind(
    name: &str,
    tags: &[(&str, &str)],
    routine: &str,
) -> Result<(Program, planner::task::MotionTask), String> {
    let dir = common::fresh_dir("motion-set", name);
    std::fs::write(dir.join("Main.st"), routine).expect("routine");
    let axis = |n: &str, kind: &str, units: &str| {
        format!(
            "[[axes]]\nname = \"{n}\"\nkind = \"{kind}\"\nunits = \"{units}\"\nmax_velocity = 360.0\n\
             max_acceleration = 3600.0\nmax_deceleration = 3600.0\nmax_jerk = 100000.0\nin_position_window = 0.001\n"
        )
    };
    let axes = axis("X", "linear", "m")
        + &axis("Y", "linear", "m")
        + &axis("Z", "linear", "m")
        + &axis("J1", "rotary", "deg")
        + &axis("J2", "rotary", "deg");
    let systems = "[[tags]]\nname = \"Cart\"\ntype = \"COORDINATE_SYSTEM\"\nvalue = [\"X\", \"Y\", \"Z\"]\n\
                   geometry = { type = \"cartesian_gantry\", transform_dimension = 2 }\n\
                   [[tags]]\nname = \"Joints\"\ntype = \"COORDINATE_SYSTEM\"\nvalue = [\"J1\", \"J2\", \"Z\"]\n\
                   coordinate_system = { primary_axes = 2 }\n\
                   geometry = { type = \"scara_independent\", link_lengths = [0.35, 0.25] }\n";
    let tags: String = tags
        .iter()
        .map(|(n, t)| format!("[[tags]]\nname = \"{n}\"\ntype = \"{t}\"\n"))
        .collect();
    let text = format!(
        "{}{axes}{systems}{tags}[[tasks]]\nname = \"T\"\nperiod_ms = 4.0\npriority = 5\n[[tasks.programs]]\nname = \"P\"\nmain = \"Main.st\"\n",
        common::indexing_table_head()
    );
    let path = dir.join("scene.toml");
    std::fs::write(&path, text).expect("scene");
    let scene = twin::scene::load(&path).map_err(|e| e.to_string())?;
    let mut task = planner::task::MotionTask::new(scene.coarse_update_s()).unwrap();
    for a in &scene.axes {
        task.add_axis(a.config.clone(), 0.0).unwrap();
    }
    let program = Program::bind(&scene, &mut task).map_err(|e| e.to_string())?;
    Ok((program, task))
}

fn element(p: &Program, name: &str, k: usize) -> f64 {
    let mem = p.controller().memory();
    let t = mem.find(name).unwrap_or_else(|| panic!("no tag {name}"));
    mem.slots[mem.tags[t].base + k].as_f64()
}

#[test]
fn mctp_converts_forward_and_back_without_motion_and_reports_err_67() {
    let tags = &[
        ("Orient", "REAL[3]"),
        ("Trans", "REAL[3]"),
        ("Ref", "REAL[3]"),
        ("Out", "REAL[3]"),
        ("Back", "REAL[3]"),
        ("Far", "REAL[6]"),
        ("Mc1", "MOTION_INSTRUCTION"),
        ("Mc2", "MOTION_INSTRUCTION"),
        ("Mc3", "MOTION_INSTRUCTION"),
        ("Mc4", "MOTION_INSTRUCTION"),
        ("Dn", "BOOL"),
        ("Err3", "DINT"),
        ("Err4", "DINT"),
        ("Exerr4", "DINT"),
        ("Done", "BOOL"),
    ];
    let routine = "
IF NOT Done THEN
    Ref[0] := 30.0; Ref[1] := 45.0; Far[0] := 2.0; Far[3] := -7.0; Far[4] := -7.0; Far[5] := -7.0;
    MCTP(Cart, Joints, Mc1, Orient[0], Trans[0], forward, Ref[0], Out[0]);
    MCTP(Cart, Joints, Mc2, Orient[0], Trans[0], inverserightarm, Out[0], Back[0]);
    MCTP(Cart, Joints, Mc3, Orient[0], Trans[0], inverse, Far[0], Far[3]);
    MCTP(Cart, Joints, Mc4, Orient[0], Trans[0], forward, Ref[0], Far[4]);
    Done := TRUE;
END_IF;
Dn := Mc1.DN AND Mc2.DN; Err3 := Mc3.ERR; Err4 := Mc4.ERR; Exerr4 := Mc4.EXERR;
";
    let p = scara_program("mctp", tags, routine);
    let (a, b) = (30f64.to_radians(), 75f64.to_radians());
    let x = 0.35 * a.cos() + 0.25 * b.cos();
    let y = 0.35 * a.sin() + 0.25 * b.sin();
    assert!((element(&p, "Out", 0) - x).abs() < 1e-6 && (element(&p, "Out", 1) - y).abs() < 1e-6);
    assert!((element(&p, "Back", 0) - 30.0).abs() < 1e-3 && (element(&p, "Back", 1) - 45.0).abs() < 1e-3);
    let mem = p.controller().memory();
    assert_eq!(mem.slots[mem.tags[mem.find("Dn").unwrap()].base].as_i64(), 1);
    assert_eq!(mem.slots[mem.tags[mem.find("Err3").unwrap()].base].as_i64(), 67);
    assert_eq!(element(&p, "Far", 3), -7.0, "left as it was on an error");
    // Two elements from Far[4]: ERR 13 on Transform Position (faceplate 7).
    assert_eq!((element(&p, "Err4", 0), element(&p, "Exerr4", 0)), (13.0, 7.0));
}

#[test]
fn mctp_operands_are_checked_at_load() {
    let tags = &[("V", "REAL[3]"), ("Mc1", "MOTION_INSTRUCTION")];
    for (routine, needle) in [
        (
            "MCTP(Cart, Joints, Mc1, V[0], V[0], inverseabove, V[0], V[0]);",
            "Transform Direction",
        ),
        (
            "MCTP(Cart, Joints, Mc1, V[0], V[0], forward, V[0], 5.0);",
            "Transform Position",
        ),
        (
            "MCTP(Cart, Mc1, Mc1, V[0], V[0], forward, V[0], V[0]);",
            "COORDINATE_SYSTEM",
        ),
    ] {
        match scara_bind("mctp-load", tags, routine) {
            Ok(_) => panic!("{routine} loads"),
            Err(e) => assert!(e.contains(needle), "{routine}: {e}"),
        }
    }
}

fn set_bool(p: &mut Program, name: &str, value: bool) {
    let mem = p.memory_mut();
    let t = mem.find(name).unwrap_or_else(|| panic!("no tag {name}"));
    let slot = mem.tags[t].base;
    mem.slots[slot] = Value::Bool(value);
}

#[test]
fn mccd_in_a_routine_changes_the_moving_systems_speed() {
    let tags = &[
        ("Target", "REAL[3]"),
        ("Mv", "MOTION_INSTRUCTION"),
        ("Ch", "MOTION_INSTRUCTION"),
        ("Slow", "BOOL"),
        ("V", "REAL"),
        ("Dn", "BOOL"),
        ("Err", "DINT"),
        ("Exerr", "DINT"),
        ("NewSpeed", "REAL"),
        ("SlowSeen", "BOOL"),
    ];
    let routine = "
IF NOT Mv.EN THEN
    Target[0] := 1.0;
    MCLM(Cart, Mv, 0, Target[0], 0.5, unitspersec, 5, unitspersec2, 5, unitspersec2, trapezoidal, 100, 100, %oftime, 0, disabled, programmed, 0, 0, none, 0, 0);
END_IF;
IF Slow AND NOT SlowSeen THEN
    MCCD(Cart, Ch, coordinatedmove, yes, NewSpeed, unitspersec, no, 0, unitspersec2, no, 0, unitspersec2, no, 0, no, 0, unitspersec3, activemotion);
END_IF;
SlowSeen := Slow;
V := X.CommandVelocity; Dn := Ch.DN; Err := Ch.ERR; Exerr := Ch.EXERR;
";
    let (mut p, mut task) = scara_bind("mccd", tags, routine).unwrap_or_else(|e| panic!("{e}"));
    let scan = |p: &mut Program, task: &mut planner::task::MotionTask| {
        p.scan(task);
        task.update();
    };
    for _ in 0..60 {
        scan(&mut p, &mut task);
    }
    let v = |p: &Program| element(p, "V", 0);
    assert!((v(&p) - 0.5).abs() < 1e-6, "{}", v(&p));
    {
        let mem = p.memory_mut();
        let t = mem.find("NewSpeed").unwrap();
        let slot = mem.tags[t].base;
        mem.slots[slot] = Value::Real(0.2);
    }
    set_bool(&mut p, "Slow", true);
    scan(&mut p, &mut task);
    assert_eq!(element(&p, "Dn", 0), 1.0);
    // Down to 0.2 at 5 m/s²: 0.06 s, 15 updates of 0.02.
    for _ in 0..20 {
        scan(&mut p, &mut task);
    }
    assert!((v(&p) - 0.2).abs() < 1e-6, "{}", v(&p));
    // A negative speed at run time: ERR 13 on Speed (faceplate 4).
    {
        let mem = p.memory_mut();
        let t = mem.find("NewSpeed").unwrap();
        let slot = mem.tags[t].base;
        mem.slots[slot] = Value::Real(-1.0);
    }
    set_bool(&mut p, "Slow", false);
    scan(&mut p, &mut task);
    set_bool(&mut p, "Slow", true);
    for _ in 0..4 {
        scan(&mut p, &mut task);
    }
    assert_eq!((element(&p, "Err", 0), element(&p, "Exerr", 0)), (13.0, 4.0));
    assert!((v(&p) - 0.2).abs() < 1e-6, "the move keeps its speed");
}

const MAOC_TAGS: &[(&str, &str)] = &[
    ("Cams", "OUTPUT_CAM[2]"),
    ("Comp", "OUTPUT_COMPENSATION[4]"),
    ("Out", "DINT"),
    ("In", "DINT"),
    ("Cam1", "MOTION_INSTRUCTION"),
    ("Off", "MOTION_INSTRUCTION"),
    ("J", "MOTION_INSTRUCTION"),
    ("Init", "BOOL"),
    ("Target", "DINT"),
    ("Disarm", "BOOL"),
    ("Bit", "BOOL"),
    ("Ip", "BOOL"),
    ("Err", "DINT"),
    ("Seg", "DINT"),
];

/// X jogs at 1 mm/s; a once cam on execution target `Target` turns Out.2
/// on from 0.2 to 0.4 mm (Out.5 is the program's own).
const MAOC_ROUTINE: &str = "
IF NOT Init THEN
    Cams[0].OutputBit := 2; Cams[0].LatchType := 1; Cams[0].UnlatchType := 1;
    Cams[0].Left := 0.2; Cams[0].Right := 0.4;
    Cams[1].OutputBit := 2; Cams[1].LatchType := 0;
    Out.5 := TRUE;
    MAJ(X, J, 0, 1.0, unitspersec, 1000, unitspersec2, 1000, unitspersec2, trapezoidal);
    MAOC(X, 0, Cam1, Out, In, Cams[0], 0.0, 10.0, Comp[0], once, immediate, 0.0, 0.0, command);
    Init := TRUE;
END_IF;
IF Disarm AND NOT Off.EN THEN MDOC(X, 0, Off, all); END_IF;
Bit := Out.2; Ip := Cam1.IP; Err := Cam1.ERR; Seg := Cam1.SEGMENT;
";

#[test]
fn maoc_switches_its_output_bit_and_leaves_the_others() {
    let mut s = Sandbox::with_axes(&["X"], MAOC_TAGS, MAOC_ROUTINE).unwrap_or_else(|e| panic!("{e}"));
    let mut on = Vec::new();
    for k in 0..300 {
        s.scan();
        if flag(&s, "Bit") {
            on.push(k);
        }
        assert_eq!(int(&s, "Out") >> 5 & 1, 1, "the program's bit stays");
    }
    // 4 µm an update: 0.2 mm after 50 updates, 0.4 mm after 100 (the Output
    // word reaches the tag at the next scan).
    assert!(
        (50..=52).contains(&on[0]) && (99..=102).contains(on.last().unwrap()),
        "{on:?}"
    );
    assert!(flag(&s, "Ip"), "still inside its range");
    // MDOC all: .IP clears, the bit stays off.
    s.set("Disarm", Value::Bool(true));
    s.scan();
    s.scan();
    assert!(!flag(&s, "Ip"));
}

#[test]
fn maoc_refusals_at_run_time_and_at_load() {
    // An illegal element: ERR 36 with the element in SEGMENT.
    let routine = MAOC_ROUTINE.replace("Cams[1].OutputBit := 2;", "Cams[1].OutputBit := 32;");
    let mut s = Sandbox::with_axes(&["X"], MAOC_TAGS, &routine).unwrap_or_else(|e| panic!("{e}"));
    s.scan();
    assert_eq!((int(&s, "Err"), int(&s, "Seg")), (36, 1));
    // An execution target the axis does not have: ERR 35.
    let routine = MAOC_ROUTINE.replace("MAOC(X, 0,", "MAOC(X, 4,");
    let mut s = Sandbox::with_axes(&["X"], MAOC_TAGS, &routine).unwrap_or_else(|e| panic!("{e}"));
    s.scan();
    assert_eq!(int(&s, "Err"), 35);
    for (from, to, needle) in [
        (
            "MAOC(X, 0,",
            "MAOC(X, Target,",
            "Execution Target 'Target': the operand's format is Immediate",
        ),
        ("Out, In, Cams[0]", "Init, In, Cams[0]", "expected a DINT tag"),
        ("Cams[0], 0.0", "Comp[0], 0.0", "OUTPUT_CAM array"),
        ("once, immediate", "twice, immediate", "Execution Mode"),
    ] {
        let routine = MAOC_ROUTINE.replace(from, to);
        match Sandbox::with_axes(&["X"], MAOC_TAGS, &routine) {
            Ok(_) => panic!("{to} loads"),
            Err(e) => assert!(e.contains(needle), "{to}: {e}"),
        }
    }
}

#[test]
fn matc_in_a_routine_time_cams_the_axis_and_refuses_master_driven_mode() {
    let tags = &[
        ("C", "CAM[2]"),
        ("P", "CAM_PROFILE[2]"),
        ("Calc", "MOTION_INSTRUCTION"),
        ("Tc", "MOTION_INSTRUCTION"),
        ("Init", "BOOL"),
        ("Status", "BOOL"),
        ("Pc", "BOOL"),
        ("Pos", "REAL"),
        ("Err", "DINT"),
    ];
    let routine = "
IF NOT Init THEN
    C[1].Master := 1.0; C[1].Slave := 0.5;
    MCCP(Calc, C[0], 2, 0.0, 0.0, P[0]);
    Init := TRUE;
END_IF;
IF Calc.DN AND NOT Tc.EN THEN
    MATC(X, Tc, same, P[0], 2.0, 0.5, once, immediate, 0.0, none, timedriven);
END_IF;
Status := X.TimeCamStatus; Pc := Tc.PC; Pos := X.CommandPosition; Err := Tc.ERR;
";
    let mut s = Sandbox::with_axes(&["X"], tags, routine).unwrap_or_else(|e| panic!("{e}"));
    s.scan();
    s.scan();
    assert!(flag(&s, "Status"), "time camming: {}", int(&s, "Err"));
    // 1 mm over 0.5 s (distance × 2, time × 0.5).
    for _ in 0..130 {
        s.scan();
    }
    assert!(flag(&s, "Pc") && !flag(&s, "Status"));
    assert!((real(&s, "Pos") - 1.0).abs() < 1e-6, "{}", real(&s, "Pos"));
    let master = routine.replace("timedriven);", "masterdriven);");
    match Sandbox::with_axes(&["X"], tags, &master) {
        Ok(_) => panic!("master driven loads"),
        Err(e) => assert!(e.contains("MDAC"), "{e}"),
    }
}

#[test]
fn mcsv_in_a_routine_writes_the_slave_value_and_its_slopes() {
    let tags = &[
        ("C", "CAM[2]"),
        ("P", "CAM_PROFILE[2]"),
        ("Calc", "MOTION_INSTRUCTION"),
        ("Mc", "MOTION_INSTRUCTION"),
        ("Init", "BOOL"),
        ("Master", "REAL"),
        ("Slave", "REAL"),
        ("Slope", "REAL"),
        ("Slope2", "REAL"),
        ("Err", "DINT"),
        ("Exerr", "DINT"),
    ];
    let routine = "
IF NOT Init THEN
    C[1].Master := 4.0; C[1].Slave := 2.0;
    MCCP(Calc, C[0], 2, 0.0, 0.0, P[0]);
    Init := TRUE;
END_IF;
IF Calc.DN THEN MCSV(Mc, P[0], Master, Slave, Slope, Slope2); END_IF;
Err := Mc.ERR; Exerr := Mc.EXERR;
";
    let mut s = Sandbox::with_axes(&[], tags, routine).unwrap_or_else(|e| panic!("{e}"));
    s.set("Master", Value::Real(3.0));
    for _ in 0..3 {
        s.scan();
    }
    assert_eq!(
        (real(&s, "Slave"), real(&s, "Slope"), real(&s, "Slope2")),
        (1.5, 0.5, 0.0)
    );
    // Outside the profile's master range: ERR 13 on Master Value, the
    // values as they were.
    s.set("Master", Value::Real(9.0));
    for _ in 0..3 {
        s.scan();
    }
    assert_eq!((int(&s, "Err"), int(&s, "Exerr")), (13, 2));
    assert_eq!(real(&s, "Slave"), 1.5);
    match Sandbox::with_axes(&[], tags, "MCSV(Mc, P[0], 1.0, Init, Slope, Slope2);") {
        Ok(_) => panic!("a BOOL output loads"),
        Err(e) => assert!(e.contains("expected a REAL tag"), "{e}"),
    }
}

#[test]
fn mdcc_in_a_routine_links_a_system_to_a_master() {
    let tags = &[
        ("Target", "REAL[3]"),
        ("Link", "MOTION_INSTRUCTION"),
        ("Mv", "MOTION_INSTRUCTION"),
        ("Jog", "MOTION_INSTRUCTION"),
        ("Init", "BOOL"),
        ("Ip", "BOOL"),
        ("Ac", "BOOL"),
        ("Err", "DINT"),
    ];
    let routine = "
IF NOT Init THEN
    Target[0] := 0.5;
    MDCC(Cart, J1, Link, command, 10.0);
    MCLM(Cart, Mv, 0, Target[0], 0.01, unitspermasterunit, 1.0, unitspermasterunit2, 1.0, unitspermasterunit2, trapezoidal, 100, 100, %oftime, 0, disabled, programmed, 0, 0, none, 0, 0);
    MAJ(J1, Jog, forward, 10.0, unitspersec, 100.0, unitspersec2, 100.0, unitspersec2, trapezoidal);
    Init := TRUE;
END_IF;
Ip := Link.IP; Ac := Link.AC; Err := Mv.ERR;
";
    let (mut p, mut task) = scara_bind("mdcc", tags, routine).unwrap_or_else(|e| panic!("{e}"));
    for _ in 0..50 {
        p.scan(&mut task);
        task.update();
    }
    assert_eq!(element(&p, "Err", 0), 0.0);
    assert_eq!((element(&p, "Ip", 0), element(&p, "Ac", 0)), (1.0, 1.0));
    // J1 jogs at 10°/s: 0.01 m per degree, the line moves with it (X is
    // the scene's second axis, after the indexing table's).
    let x = task.axis_state(task.axis_handles().nth(1).unwrap()).command_position;
    assert!(x > 0.0 && x < 0.5, "{x}");
}

/// Every Immediate enumeration operand of the instructions this set adds
/// refuses a code outside its words when the program loads, naming the
/// operand (the catalogue says which operands those are).
#[test]
fn every_immediate_operand_of_the_new_instructions_is_checked_at_load() {
    let tags = &[
        ("MC", "MOTION_INSTRUCTION"),
        ("G", "MOTION_GROUP"),
        ("V", "REAL[3]"),
        ("Cams", "OUTPUT_CAM[2]"),
        ("Comp", "OUTPUT_COMPENSATION[2]"),
        ("Out", "DINT"),
        ("In", "DINT"),
        ("Prof", "CAM_PROFILE[2]"),
    ];
    let calls = [
        "MCD(X, MC, move, yes, 1.0, no, 0, no, 0, no, 0, no, 0, unitspersec, unitspersec2, unitspersec2, unitspersec3)",
        "MCCD(Cart, MC, coordinatedmove, yes, 1.0, unitspersec, no, 0, unitspersec2, no, 0, unitspersec2, no, 0, no, 0, unitspersec3, activemotion)",
        "MGS(G, MC, programmed)",
        "MAW(X, MC, forward, 1.0)",
        "MAOC(X, 0, MC, Out, In, Cams[0], 0.0, 10.0, Comp[0], once, immediate, 0.0, 0.0, actual)",
        "MDOC(X, 0, MC, all)",
        "MATC(X, MC, same, Prof[0], 1.0, 1.0, once, immediate, 0.0, none, timedriven)",
        "MCTP(Cart, Joints, MC, V[0], V[0], forward, V[0], V[0])",
        "MDCC(Cart, J1, MC, command, 1.0)",
    ];
    let mut checked = 0;
    for call in calls {
        let (name, rest) = call.split_once('(').unwrap();
        let args: Vec<&str> = rest.trim_end_matches(')').split(", ").collect();
        scara_bind("immediate-ok", tags, &format!("{call};\n")).unwrap_or_else(|e| panic!("{call}: {e}"));
        let instruction = planner::task::instructions::find(name).unwrap();
        assert_eq!(instruction.operands.len(), args.len(), "{name}");
        for (i, o) in instruction.operands.iter().enumerate() {
            if o.format != planner::catalogue::Format::Immediate || o.kind.words().is_empty() {
                continue;
            }
            let mut bad = args.clone();
            bad[i] = "99";
            let text = format!("{name}({});\n", bad.join(", "));
            match scara_bind("immediate-bad", tags, &text) {
                Ok(_) => panic!("{text} loads"),
                Err(e) => assert!(e.contains(o.name), "{text}: {e}"),
            }
            checked += 1;
        }
    }
    assert!(checked >= 30, "{checked}");
}
