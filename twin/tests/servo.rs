//! Axis states end to end: the `servo_states` scene (MSO, MSF with a holding
//! brake, MASD, MAFR, MASR, the refusals with their ERR and EXERR), and
//! variants of shipped scenes that make an axis feedback-only (ERR 8) or
//! inhibited (ERR 53, MCT EXERR 14).

use std::path::{Path, PathBuf};
use std::process::Command;

mod common;
use common::root;

/// Runs the `twin` binary on `scene` with a trace; returns the exit code,
/// its output, and the trace's header and rows.
fn run(scene: &Path, out_name: &str) -> (i32, String, Vec<String>, Vec<Vec<String>>) {
    let out = common::fresh_dir("servo-tests", out_name);
    let output = Command::new(env!("CARGO_BIN_EXE_twin"))
        .current_dir(root())
        .arg("run")
        .arg(scene)
        .args(["--no-render", "--trace"])
        .arg(out.join("t.csv"))
        .arg("--summary")
        .arg(out.join("s.json"))
        .output()
        .expect("run twin");
    let log = String::from_utf8_lossy(&output.stdout).into_owned() + &String::from_utf8_lossy(&output.stderr);
    let text = std::fs::read_to_string(out.join("t.csv")).unwrap_or_else(|e| panic!("no trace ({e}): {log}"));
    let mut lines = text.lines();
    let header = lines.next().unwrap_or_default().split(',').map(str::to_owned).collect();
    let rows = lines.map(|l| l.split(',').map(str::to_owned).collect()).collect();
    (output.status.code().unwrap_or(-1), log, header, rows)
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

/// A shipped scene with `edits` applied, written under `target/` with its
/// relative paths made absolute.
fn variant(scene: &str, name: &str, edits: &[(&str, &str)]) -> PathBuf {
    let scenes = root().join("scenes");
    let mut text = common::shipped_scene_text(&scenes.join(scene));
    for (from, to) in edits {
        assert!(text.contains(from), "{scene} has no '{from}'");
        text = text.replacen(from, to, 1);
    }
    let base = scenes.display().to_string();
    let text = text
        .replace("\"robots/", &format!("\"{base}/robots/"))
        .replace("\"routines/", &format!("\"{base}/routines/"));
    let dir = common::fresh_dir("servo-tests", &format!("{name}-scene"));
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(&path, text).expect("write variant");
    path
}

#[test]
fn servo_states_refuses_with_the_documented_codes_and_the_brake_holds_the_arm() {
    let (code, log, h, rows) = run(&root().join("scenes/servo_states.toml"), "servo_states");
    // Exit 2: instructions reported errors, on purpose.
    assert_eq!(code, 2, "{log}");
    let last = rows.last().expect("rows");
    assert_eq!(last[col(&h, "Main.State")], "50", "the program ran to its end");
    // The closing MAM put J1 at -30 exactly, and .PC says so.
    assert_eq!(num(&last[col(&h, "J1.cmd_pos")]), -30.0);
    assert_eq!(last[col(&h, "MoveJ1.PC")], "1");
    let refused: Vec<&str> = (0..4)
        .map(|i| last[col(&h, &format!("Main.Refused[{i}]"))].as_str())
        .collect();
    // MCLM with J2 servo-off: ERR 5, EXERR 1; MCT with J3 shut down: ERR 61,
    // EXERR 13; MCLM with J3 shut down: ERR 7, EXERR 2; MSO on the
    // shut-down J3 after MAFR: ERR 7.
    assert_eq!(refused, ["501", "6113", "702", "700"]);
    assert_eq!(last[col(&h, "Main.N")], "4");

    // MSO on J2 (brake release 100 ms) at the first scan (t = 0): .DN at
    // the 25th coarse update.
    let t = col(&h, "time_s");
    let on2 = col(&h, "Main.On2.DN");
    let first_dn = rows
        .iter()
        .find(|r| r[on2] == "1")
        .map(|r| num(&r[t]))
        .expect("MSO J2 done");
    assert!((first_dn - 0.1).abs() < 1e-9, "J2 enabled at {first_dn}");

    // J2 servo-off from the MSF (state 20) to the MSO (state 30): the brake
    // holds it, and its command follows its actual position.
    let state = col(&h, "Main.State");
    let (cmd, act) = (col(&h, "J2.cmd_pos"), col(&h, "J2.act_pos"));
    let braked: Vec<&Vec<String>> = rows.iter().filter(|r| r[state] == "21").collect();
    assert!(braked.len() > 100, "{}", braked.len());
    let held = num(&braked[0][act]);
    for r in &braked[1..] {
        assert!(
            (num(&r[act]) - held).abs() < 0.2,
            "J2 moved to {} under its brake",
            r[act]
        );
        assert!((num(&r[cmd]) - num(&r[act])).abs() < 0.2);
    }
}

#[test]
fn a_feedback_only_axis_refuses_mso_with_err_8() {
    let scene = variant(
        "servo_states.toml",
        "feedback_only",
        &[(
            "initial_position = 0.0\nmotor = { stiffness = 35530.6, damping = 377.0 }\nservo_on_at_start = false",
            "initial_position = 0.0\nmotor = { stiffness = 35530.6, damping = 377.0 }\nservo_on_at_start = false\naxis_configuration = \"feedback_only\"",
        )],
    );
    let (code, log, h, rows) = run(&scene, "feedback_only");
    assert_eq!(code, 2, "{log}");
    let last = rows.last().expect("rows");
    assert_eq!(
        (
            last[col(&h, "Main.On1.ER")].as_str(),
            last[col(&h, "Main.On1.ERR")].as_str()
        ),
        ("1", "8")
    );
    assert_eq!(last[col(&h, "Main.State")], "10", "the program waits for J1");
    // Not driven: J1 (vertical, no load) stays where it was.
    assert!(num(&last[col(&h, "J1.cmd_pos")]).abs() < 1e-6);
}

#[test]
fn an_inhibited_axis_refuses_with_err_53_and_mct_names_it_with_exerr_14() {
    let scene = variant(
        "servo_states.toml",
        "inhibited",
        &[(
            "brake_release_delay_ms = 100.0\n\n[[cameras]]",
            "brake_release_delay_ms = 100.0\ninhibit_axis = true\n\n[[cameras]]",
        )],
    );
    let (code, log, h, rows) = run(&scene, "inhibited");
    assert_eq!(code, 2, "{log}");
    let last = rows.last().expect("rows");
    assert_eq!(last[col(&h, "Main.On3.ERR")], "53", "MSO on the inhibited J3");

    // scara_pallet's first scan starts MCT(Cart, Joints): with J2 inhibited
    // it is refused with EXERR 14 and the pallet is never started.
    let scene = variant(
        "scara_pallet.toml",
        "pallet_inhibited",
        &[("joint = \"j2\"", "joint = \"j2\"\ninhibit_axis = true")],
    );
    let (code, log, h, rows) = run(&scene, "pallet_inhibited");
    assert_eq!(code, 2, "{log}");
    let last = rows.last().expect("rows");
    assert_eq!(
        (
            last[col(&h, "Pallet.Xform.ER")].as_str(),
            last[col(&h, "Pallet.Xform.EXERR")].as_str()
        ),
        ("1", "14")
    );
    assert_eq!(last[col(&h, "Pallet.State")], "5");
}

/// `rotary_knife` with a MAM on the knife (the cam slave) at 1 s: with
/// Merge Disabled it is superimposed on the cam, which goes on; with Merge
/// Enabled it ends the cam.
fn knife_with_mam(merge: &str) -> (Vec<String>, Vec<Vec<String>>) {
    let step = format!(
        "[[program]]\nat_s = 1.0\ncall = \"MAM(Knife, Trim, 1, 10.0, 200.0, UnitsPerSec, 2000.0, UnitsPerSec2, 2000.0, UnitsPerSec2, Trapezoidal, 0, 0, UnitsPerSec3, {merge}, Programmed, 0, None, 0, 0)\"\n\n[[program]]\nat_s = 1.5"
    );
    let tag = "[[tags]]\nname = \"Trim\"\ntype = \"MOTION_INSTRUCTION\"\n\n[[tags]]\nname = \"Stop\"";
    let scene = variant(
        "rotary_knife.toml",
        &format!("knife_mam_{merge}"),
        &[("[[program]]\nat_s = 1.5", &step), ("[[tags]]\nname = \"Stop\"", tag)],
    );
    let (code, log, h, rows) = run(&scene, &format!("knife_mam_{merge}"));
    assert_eq!(code, 0, "{log}");
    (h, rows)
}

#[test]
fn a_mam_on_the_knife_rides_on_its_cam_or_ends_it() {
    let original = root().join("scenes/rotary_knife.toml");
    let (code, log, h0, base) = run(&original, "knife_base");
    assert_eq!(code, 0, "{log}");
    let knife0 = col(&h0, "Knife.cmd_pos");

    let (h, rows) = knife_with_mam("Disabled");
    let (t, knife, sup) = (col(&h, "time_s"), col(&h, "Knife.cmd_pos"), col(&h, "Knife.sup_pos"));
    let (cam, pc) = (col(&h, "Knife.PositionCamStatus"), col(&h, "Trim.PC"));
    let mut checked = 0;
    for (r, r0) in rows.iter().zip(&base) {
        let time = num(&r[t]);
        // From the MAM's end to the cam replacement at 1.5 s: exactly 10°
        // past the cam, the cam still active.
        if r[pc] == "1" && time < 1.5 {
            let diff = num(&r[knife]) - num(&r0[knife0]);
            assert!((diff - 10.0).abs() < 1e-9, "t {time}: {diff}");
            assert_eq!(num(&r[sup]), 10.0);
            assert_eq!(r[cam], "1");
            checked += 1;
        }
    }
    assert!(checked > 50, "{checked} rows");

    let (h, rows) = knife_with_mam("Enabled");
    let (t, cam, pc) = (
        col(&h, "time_s"),
        col(&h, "Knife.PositionCamStatus"),
        col(&h, "Trim.PC"),
    );
    let after: Vec<&Vec<String>> = rows.iter().filter(|r| (1.01..1.5).contains(&num(&r[t]))).collect();
    assert!(after.iter().all(|r| r[cam] == "0"), "the merge ended the cam");
    assert!(after.iter().any(|r| r[pc] == "1"));
}

/// Rising edges of a 0/1 column.
fn rises(rows: &[Vec<String>], c: usize) -> usize {
    rows.windows(2).filter(|w| w[0][c] == "0" && w[1][c] == "1").count()
}

#[test]
fn the_heavy_arm_completes_every_move_holds_still_and_keeps_within_its_torque_limits() {
    let (code, log, h, rows) = run(&root().join("scenes/heavy_arm.toml"), "heavy_arm");
    assert_eq!(code, 0, "{log}");
    let last = rows.last().expect("rows");
    assert_eq!(last[col(&h, "Main.State")], "90", "the program ran to its end: {log}");
    assert_eq!(last[col(&h, "Main.Cycles")], "2");
    // Every MCLM ends on the actual position (termination type 0): Pose1,
    // Pose2, Pose1, Pose2, home.
    assert_eq!(rises(&rows, col(&h, "Move.PC")), 5);
    for wrist in ["Wrist4", "Wrist5", "Wrist6"] {
        assert_eq!(last[col(&h, &format!("Main.{wrist}.PC"))], "1", "{wrist}");
    }
    // The overload faulted J2 (Excessive Position Error: the AxisFault word's
    // motion bit), MAFR left it servo-off, and MSO brought it back.
    assert_eq!(last[col(&h, "Main.Faults")], "16");
    let state2 = col(&h, "J2.CIPAxisState");
    let faulted = rows.iter().position(|r| r[state2] == "8").expect("J2 faulted");
    let stopped = faulted + rows[faulted..].iter().position(|r| r[state2] == "2").expect("MAFR");
    assert!(rows[stopped..].iter().any(|r| r[state2] == "4"), "MSO again");
    // The summary lists it, once, with its action.
    let faults: Vec<&str> = log.lines().filter(|l| l.contains("Excessive Position Error")).collect();
    assert_eq!(faults.len(), 1, "{log}");
    assert!(
        faults[0].starts_with("  axis J2: ") && faults[0].ends_with("action StopDrive"),
        "{log}"
    );

    // The drives' torques stay within the URDF joints' efforts.
    let effort = [250.0, 450.0, 200.0, 50.0, 50.0, 25.0];
    for (k, limit) in effort.iter().enumerate() {
        let c = col(&h, &format!("J{}.torque", k + 1));
        let peak = rows.iter().map(|r| num(&r[c]).abs()).fold(0.0, f64::max);
        assert!(peak <= limit + 1e-9, "J{}: {peak} N·m", k + 1);
    }

    // Standstill: after each move (command velocity back to 0) that is
    // followed by 0.5 s of rest with the servo on, the position error is
    // below a tenth of the 0.1 deg in-position window.
    let t = col(&h, "time_s");
    let mut checked = 0;
    for k in 1..=6 {
        let (v, p, a, s) = (
            col(&h, &format!("J{k}.cmd_vel")),
            col(&h, &format!("J{k}.cmd_pos")),
            col(&h, &format!("J{k}.act_pos")),
            col(&h, &format!("J{k}.CIPAxisState")),
        );
        for i in 1..rows.len() {
            if num(&rows[i - 1][v]) == 0.0 || num(&rows[i][v]) != 0.0 {
                continue;
            }
            let until = num(&rows[i][t]) + 0.5;
            let Some(j) = rows[i..].iter().position(|r| num(&r[t]) >= until - 1e-9) else {
                continue;
            };
            let rest = &rows[i..=i + j];
            if rest.iter().any(|r| num(&r[v]) != 0.0 || r[s] != "4") {
                continue;
            }
            let error = (num(&rest[j][p]) - num(&rest[j][a])).abs();
            assert!(error < 0.01, "J{k} {error} deg after the stop at {}", rows[i][t]);
            checked += 1;
        }
    }
    assert!(checked >= 6, "{checked} standstills checked");
}

#[test]
fn motion_during_an_active_mah_is_refused_with_err_16() {
    let dir = common::fresh_dir("servo-tests", "homing-routine");
    let routine = dir.join("Main.st");
    std::fs::write(
        &routine,
        "CASE State OF\n\
           0: MSO(J1, On1); State := 10;\n\
           10: IF On1.DN THEN\n\
                 MAM(J1, Wrist4, 1, 90, 50, %ofMaximum, 50, %ofMaximum, 50, %ofMaximum, trapezoidal, 100, 100, %ofTime, disabled, programmed, 0, none, 0, 0);\n\
                 State := 20;\n\
               END_IF;\n\
           20: MAH(J1, Home1);\n\
               Retries := J1.HomingStatus;\n\
               MAM(J1, Wrist5, 1, 10, 50, %ofMaximum, 50, %ofMaximum, 50, %ofMaximum, trapezoidal, 100, 100, %ofTime, disabled, programmed, 0, none, 0, 0);\n\
               IF Wrist5.ER THEN Faults := Wrist5.ERR; END_IF;\n\
               State := 30;\n\
           30: IF Home1.PC AND J1.AxisHomedStatus THEN State := 40; END_IF;\n\
           40: ;\n\
         END_CASE;\n",
    )
    .expect("routine");
    let main = format!("main = \"{}\"", routine.display());
    let scene = variant(
        "heavy_arm.toml",
        "homing",
        &[
            ("main = \"routines/heavy_arm/Main.st\"", &main),
            (
                "position_error_tolerance = 1.0\n",
                "position_error_tolerance = 1.0\nhome_position = 5.0\n",
            ),
        ],
    );
    let (code, log, h, rows) = run(&scene, "homing");
    assert_eq!(code, 2, "{log}");
    let last = rows.last().expect("rows");
    assert_eq!(last[col(&h, "Main.State")], "40", "{log}");
    assert_eq!(last[col(&h, "Main.Retries")], "1", "HomingStatus while the jog stops");
    assert_eq!(last[col(&h, "Main.Faults")], "16", "MAM while homing: ERR 16");
    // Homed at rest: J1 reads 5 where it stopped.
    let p = num(&last[col(&h, "J1.cmd_pos")]);
    assert!((p - 5.0).abs() < 0.01, "{p}");
}

#[test]
fn a_geared_wrist_follows_its_master_at_the_ratio_until_mas_gear() {
    let dir = common::fresh_dir("servo-tests", "gear-routine");
    let routine = dir.join("Main.st");
    std::fs::write(
        &routine,
        "CASE State OF\n\
           0: MSO(J4, On4); MSO(J6, On6); State := 10;\n\
           10: IF On4.DN AND On6.DN THEN\n\
                 MAG(J6, J4, Wrist6, same, 2.0, 1, 1, command, real, enabled, 100, %ofmaximum);\n\
                 MAM(J4, Wrist4, 1, 45, 50, %ofMaximum, 50, %ofMaximum, 50, %ofMaximum, trapezoidal, 100, 100, %ofTime, disabled, programmed, 0, none, 0, 0);\n\
                 State := 20;\n\
               END_IF;\n\
           20: IF Wrist4.PC THEN\n\
                 Faults := J6.GearingStatus + 2 * J6.GearingLockStatus;\n\
                 MAS(J6, Reset2, gear, no, 0, unitspersec2);\n\
                 MAM(J4, Wrist4, 1, -45, 50, %ofMaximum, 50, %ofMaximum, 50, %ofMaximum, trapezoidal, 100, 100, %ofTime, disabled, programmed, 0, none, 0, 0);\n\
                 State := 30;\n\
               END_IF;\n\
           30: IF Wrist4.PC THEN State := 40; END_IF;\n\
           40: ;\n\
         END_CASE;\n",
    )
    .expect("routine");
    let main = format!("main = \"{}\"", routine.display());
    let scene = variant(
        "heavy_arm.toml",
        "gear",
        &[("main = \"routines/heavy_arm/Main.st\"", &main)],
    );
    let (code, log, h, rows) = run(&scene, "gear");
    assert_eq!(code, 0, "{log}");
    let last = rows.last().expect("rows");
    assert_eq!(last[col(&h, "Main.State")], "40", "{log}");
    assert_eq!(last[col(&h, "Main.Faults")], "3", "geared and locked");
    assert_eq!(last[col(&h, "Main.Wrist6.IP")], "0", "MAS Gear ended it");
    // Geared, J6 moved twice J4's 45 degrees; after MAS Gear it stayed
    // while J4 went back.
    let (j4, j6) = (col(&h, "J4.cmd_pos"), col(&h, "J6.cmd_pos"));
    let state = col(&h, "Main.State");
    let at_stop = rows.iter().rev().find(|r| r[state] == "20").expect("state 20");
    assert!((num(&at_stop[j6]) - 90.0).abs() < 1e-6, "{}", at_stop[j6]);
    assert!((num(&at_stop[j4]) - 45.0).abs() < 1e-6, "{}", at_stop[j4]);
    assert!((num(&last[j6]) - 90.0).abs() < 1e-6);
    assert!(num(&last[j4]).abs() < 1e-6);
}

/// Guards against a SCARA quill driven past its URDF limit going on with no
/// error: the URDF `<limit>` is the axis' soft travel limits, the actual
/// position at the stop raises Soft Travel Limit - Negative (Stop Planner:
/// the MAM ends, the axis ramps to rest), a further move down fails with
/// ERR 9 and a move back up completes; MAFR clears the fault.
#[test]
fn a_scara_quill_driven_past_its_urdf_limit_faults_and_a_further_move_down_fails_with_err_9() {
    let robots = root().join("scenes/robots").display().to_string();
    let mam = |tag: &str, to: f64| {
        format!(
            "MAM(Z, {tag}, 0, {to}, 0.5, unitspersec, 5, unitspersec2, 5, unitspersec2, trapezoidal, 100, 100, %ofTime, disabled, programmed, 0, none, 0, 0)"
        )
    };
    let mut text = format!(
        r#"name = "quill_overtravel"
duration_s = 2.4
coarse_update_ms = 4.0
physics_step_ms = 1.0

[robot]
urdf = "{robots}/scara/scara.urdf"

[[axes]]
name = "Z"
joint = "j3"
kind = "linear"
units = "m"
max_velocity = 1.0
max_acceleration = 10.0
max_deceleration = 10.0
max_jerk = 100000.0
in_position_window = 0.0005
motor = {{ stiffness = 142122.3, damping = 754.0 }}
"#
    );
    for tag in ["Down", "Further", "Back", "Reset"] {
        text += &format!("\n[[tags]]\nname = \"{tag}\"\ntype = \"MOTION_INSTRUCTION\"\n");
    }
    for (at, call) in [
        (0.1, mam("Down", -0.4)),
        (1.2, mam("Further", -0.35)),
        (1.4, mam("Back", -0.1)),
        (2.2, "MAFR(Z, Reset)".to_string()),
    ] {
        text += &format!("\n[[program]]\nat_s = {at}\ncall = \"{call}\"\n");
    }
    text += "\n[trace]\ntags = [\"Z.SoftTravelLimitNegativeFault\", \"Z.SoftTravelLimitNegative\", \"Z.SoftTravelLimitChecking\"]\n";
    let dir = common::fresh_dir("servo-tests", "quill-overtravel-scene");
    let scene = dir.join("quill.toml");
    std::fs::write(&scene, text).expect("write scene");
    let (code, log, header, rows) = run(&scene, "quill-overtravel");
    assert_eq!(code, 2, "the refused move is an instruction error: {log}");
    let (t, act, fault) = (
        col(&header, "time_s"),
        col(&header, "Z.act_pos"),
        col(&header, "Z.MotionFault"),
    );
    let at = |time: f64| {
        rows.iter()
            .find(|r| (num(&r[t]) - time).abs() < 1e-9)
            .unwrap_or_else(|| panic!("no row at {time}"))
    };
    // The quill reaches its stop (-0.3 m) at about 0.76 s.
    let first = rows.iter().position(|r| r[fault] != "0").expect("the fault rises");
    let t_fault = num(&rows[first][t]);
    assert!((0.7..0.8).contains(&t_fault), "{t_fault}");
    assert_eq!(rows[first][fault], "4", "Soft Travel Limit - Negative");
    // What a program reads: the URDF's lower limit, checking on, the bit.
    let member = |m: &str| rows[first][col(&header, &format!("Z.{m}"))].clone();
    assert_eq!(member("SoftTravelLimitNegative"), "-0.3");
    assert_eq!(member("SoftTravelLimitChecking"), "1");
    assert_eq!(member("SoftTravelLimitNegativeFault"), "1");
    assert_eq!(rows[first - 1][col(&header, "Z.SoftTravelLimitNegativeFault")], "0");
    assert!(num(&rows[first][act]) < -0.3 && num(&rows[first][act]) > -0.3 - 1e-6);
    let down = |name: &str, bit: &str| at(1.3)[col(&header, &format!("{name}.{bit}"))].clone();
    assert_eq!(
        (down("Down", "IP"), down("Down", "PC")),
        ("0".into(), "0".into()),
        "the MAM is stopped"
    );
    assert_eq!(
        (down("Further", "ER"), down("Further", "ERR")),
        ("1".into(), "9".into())
    );
    let back = at(2.1);
    assert_eq!(back[col(&header, "Back.PC")], "1");
    assert!((num(&back[act]) + 0.1).abs() < 1e-3);
    assert_eq!(back[fault], "4", "latched until MAFR");
    assert_eq!(at(2.3)[fault], "0");
    assert!(log.contains("axis Z: Soft Travel Limit - Negative at 0.7"), "{log}");
}
