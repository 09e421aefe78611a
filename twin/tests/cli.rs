//! The `twin` command as a user meets it: every bad-input case of the
//! README's "Errors and exit codes" table names its file, place and field
//! and exits with its code; usage errors suggest the near miss; `--duration`
//! and `twin check`'s report.

mod common;

use common::{fresh_dir, root};
use std::path::PathBuf;
use std::process::{Command, Output};

fn twin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_twin"))
}

/// `scenes/indexing_table.toml` with `edits` applied, written under
/// `target/cli/<name>/` (the URDF path made absolute).
fn edited(name: &str, edits: &[(&str, &str)]) -> PathBuf {
    let mut text = std::fs::read_to_string(root().join("scenes/indexing_table.toml")).expect("scene");
    for (from, to) in edits {
        let edited = text.replacen(from, to, 1);
        assert_ne!(edited, text, "'{from}' is not in the scene");
        text = edited;
    }
    let robots = root().join("scenes/robots");
    let text = text.replace("urdf = \"robots/", &format!("urdf = \"{}/", robots.display()));
    let path = fresh_dir("cli", name).join("scene.toml");
    std::fs::write(&path, text).expect("write scene");
    path
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// Runs `twin check` on an edited scene; asserts exit code 65 and a first
/// line of stderr holding the file, `line:column` and `needle` (the
/// rendering with the source line follows it).
fn check_rejects(name: &str, edits: &[(&str, &str)], place: &str, needle: &str) {
    let path = edited(name, edits);
    let out = twin().arg("check").arg(&path).output().expect("run twin");
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(65), "{name}: {err}");
    let first = err.lines().next().unwrap_or_default();
    assert!(first.starts_with("error: "), "{name}: {err}");
    assert!(
        first.contains(&format!("{}:{place}: ", path.display())),
        "{name}: {err}"
    );
    assert!(first.contains(needle), "{name}: expected {needle:?} in {first}");
    assert!(
        err.lines().nth(1).is_some_and(|l| l.trim_start().starts_with("--> ")),
        "{name}: the source line follows: {err}"
    );
}

#[test]
fn a_value_of_the_wrong_type_names_its_field() {
    check_rejects(
        "wrong_type",
        &[("max_velocity = 360.0", "max_velocity = \"fast\"")],
        "27:16",
        "axes[0].max_velocity: expected a number, found \"fast\"",
    );
    check_rejects(
        "wrong_type_inline",
        &[("stiffness = 35530.6", "stiffness = \"stiff\"")],
        "36:23",
        "axes[0].motor.stiffness: expected a number, found \"stiff\"",
    );
    check_rejects(
        "wrong_type_array",
        &[("position = [1.5, -1.7, 1.6]", "position = [1.5, \"x\", 1.6]")],
        "40:18",
        "cameras[0].position[1]: expected a number, found \"x\"",
    );
    check_rejects(
        "wrong_type_bool",
        &[("target_position_monitoring = true", "target_position_monitoring = 1")],
        "32:30",
        "axes[0].target_position_monitoring: expected true or false, found 1",
    );
}

#[test]
fn unknown_fields_out_of_range_values_and_missing_files_name_their_field() {
    check_rejects(
        "unknown_field",
        &[("max_velocity = 360.0", "max_velocty = 360.0")],
        "27:1",
        "in axes[0]: unknown field 'max_velocty', expected one of",
    );
    check_rejects(
        "out_of_range",
        &[("max_velocity = 360.0", "max_velocity = -5.0")],
        "27:16",
        "axes[0].max_velocity: must be greater than 0, got -5",
    );
    check_rejects(
        "unknown_joint",
        &[("joint = \"platter_joint\"", "joint = \"platter_jnt\"")],
        "23:9",
        "axes[0].joint: axis 'Table' is mapped to joint 'platter_jnt'",
    );
    check_rejects(
        "bad_call",
        &[("Position := 90.0,", "Position := ,")],
        "64:59",
        "program[0].call: expected an operand",
    );
    check_rejects(
        "missing_urdf",
        &[("indexing_table/indexing_table.urdf", "nope.urdf")],
        "19:8",
        "robot.urdf: file '",
    );
}

#[test]
fn usage_errors_exit_64_and_suggest_the_near_miss() {
    let out = twin()
        .args(["run", "--frmes", "x", "scenes/indexing_table.toml"])
        .output()
        .expect("run twin");
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(64), "{err}");
    assert!(err.contains("--frames"), "a did-you-mean for --frames: {err}");
    let out = twin().arg("chek").output().expect("run twin");
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(64), "{err}");
    assert!(err.contains("check"), "a did-you-mean for check: {err}");
    let scene = root().join("scenes/indexing_table.toml");
    for bad in ["0", "-1", "abc", "inf", "NaN", "1e7"] {
        let out = twin()
            .arg("run")
            .arg(&scene)
            .args(["--no-render", &format!("--duration={bad}")])
            .output()
            .expect("run twin");
        let err = stderr(&out);
        assert_eq!(out.status.code(), Some(64), "--duration {bad}: {err}");
        assert!(err.contains("--duration"), "{err}");
    }
    // --help and --version succeed.
    for flag in ["--help", "--version"] {
        let out = twin().arg(flag).output().expect("run twin");
        assert_eq!(out.status.code(), Some(0), "{flag}");
    }
}

#[test]
fn an_output_that_cannot_be_written_exits_74_naming_the_flag() {
    let dir = fresh_dir("cli", "unwritable");
    // A file where a folder is needed.
    let blocker = dir.join("file");
    std::fs::write(&blocker, "").expect("write");
    let scene = root().join("scenes/indexing_table.toml");
    for flag in ["--trace", "--summary", "--save"] {
        let out = twin()
            .arg("run")
            .arg(&scene)
            .arg("--no-render")
            .arg(flag)
            .arg(blocker.join("out"))
            .output()
            .expect("run twin");
        let err = stderr(&out);
        assert_eq!(out.status.code(), Some(74), "{flag}: {err}");
        assert!(err.contains(flag), "{flag}: {err}");
    }
    // No viewer listening.
    let port = std::net::TcpListener::bind("127.0.0.1:0")
        .and_then(|l| l.local_addr())
        .expect("free port")
        .port();
    let out = twin()
        .arg("run")
        .arg(&scene)
        .args(["--no-render", "--connect", &format!("127.0.0.1:{port}")])
        .output()
        .expect("run twin");
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(74), "{err}");
    assert!(err.contains(&format!("127.0.0.1:{port}")), "{err}");
}

#[test]
fn duration_overrides_the_scenes_run_length() {
    let dir = fresh_dir("cli", "duration");
    let scene = root().join("scenes/indexing_table.toml");
    let out = twin()
        .arg("run")
        .arg(&scene)
        .args(["--no-render", "--duration", "0.1", "--trace"])
        .arg(dir.join("t.csv"))
        .output()
        .expect("run twin");
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let trace = std::fs::read_to_string(dir.join("t.csv")).expect("trace");
    let last = trace.lines().last().expect("rows");
    assert!(last.starts_with("0.1,"), "the last row is at 0.1 s: {last}");
}

#[test]
fn check_prints_what_the_scene_resolved_to() {
    let out = twin()
        .arg("check")
        .arg(root().join("scenes/indexing_table.toml"))
        .output()
        .expect("run twin");
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let text = String::from_utf8_lossy(&out.stdout);
    for needle in [
        ": ok (1 axes",
        "robot: ",
        "axes:\n  Table (rotary, deg): joint platter_joint",
        "1 deg = 0.017453292519943295 rad",
        "max velocity 360 deg/s",
        "cameras:\n  iso: ",
    ] {
        assert!(text.contains(needle), "{needle:?} in\n{text}");
    }
}

#[test]
fn rendering_without_a_runtime_dir_prints_no_mesa_noise() {
    let dir = fresh_dir("cli", "runtime_dir");
    let out = twin()
        .arg("run")
        .arg(root().join("scenes/indexing_table.toml"))
        .args(["--duration", "0.04", "--frames"])
        .arg(dir.join("frames"))
        .env_remove("XDG_RUNTIME_DIR")
        .output()
        .expect("run twin");
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(0), "{err}");
    assert!(!err.contains("XDG_RUNTIME_DIR"), "{err}");
}

/// A port nothing listens on now.
fn free_port() -> u16 {
    std::net::TcpListener::bind("127.0.0.1:0")
        .and_then(|l| l.local_addr())
        .expect("free port")
        .port()
}

#[test]
fn serve_refuses_a_busy_port_and_goes_on_serving_after_the_run() {
    use std::io::BufRead as _;

    let scene = root().join("scenes/indexing_table.toml");
    let busy = std::net::TcpListener::bind("127.0.0.1:0").expect("bind");
    let addr = busy.local_addr().expect("address").to_string();
    let out = twin()
        .arg("run")
        .arg(&scene)
        .args(["--no-render", "--serve", &addr])
        .output()
        .expect("run twin");
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(74), "{err}");
    assert!(err.contains(&format!("cannot serve a recording at {addr}")), "{err}");
    drop(busy);

    let port = free_port();
    let mut child = twin()
        .arg("run")
        .arg(&scene)
        .args(["--no-render", "--serve", &format!("127.0.0.1:{port}")])
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("start twin");
    let lines = std::io::BufReader::new(child.stderr.take().expect("stderr"));
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        for line in lines.lines().map_while(Result::ok) {
            if tx.send(line).is_err() {
                break;
            }
        }
    });
    let expected = format!("serving the recording at rerun+http://127.0.0.1:{port}/proxy");
    let mut seen = Vec::new();
    let served = loop {
        match rx.recv_timeout(std::time::Duration::from_secs(120)) {
            Ok(line) if line.contains(&expected) => break true,
            Ok(line) => seen.push(line),
            Err(_) => break false,
        }
    };
    let connected = std::net::TcpStream::connect(("127.0.0.1", port)).is_ok();
    let still_running = child.try_wait().expect("try_wait").is_none();
    child.kill().ok();
    child.wait().ok();
    assert!(served, "no {expected:?} in {seen:?}");
    assert!(connected, "nothing listens on port {port} after the run");
    assert!(still_running, "twin stopped serving after the run");
}

#[test]
fn two_outputs_on_one_path_or_an_output_on_an_input_are_refused() {
    let dir = fresh_dir("cli", "same_path");
    let scene = edited("same_path_scene", &[]);
    let before = std::fs::read(&scene).expect("scene");
    let out_file = dir.join("out");
    let cases: Vec<(Vec<std::ffi::OsString>, &str)> = vec![
        (
            vec![
                "--trace".into(),
                out_file.clone().into(),
                "--summary".into(),
                out_file.clone().into(),
            ],
            "--summary",
        ),
        (
            vec![
                "--trace".into(),
                out_file.clone().into(),
                "--save".into(),
                dir.join(".").join("out").into(),
            ],
            "--save",
        ),
        (
            vec!["--trace".into(), scene.clone().into()],
            "the scene reads this file",
        ),
    ];
    for (flags, needle) in cases {
        let out = twin()
            .arg("run")
            .arg(&scene)
            .arg("--no-render")
            .args(&flags)
            .output()
            .expect("run twin");
        let err = stderr(&out);
        assert_eq!(out.status.code(), Some(64), "{flags:?}: {err}");
        assert!(err.contains(needle), "{flags:?}: {err}");
    }
    assert_eq!(std::fs::read(&scene).expect("scene"), before, "the scene was written");
    assert!(!out_file.exists(), "nothing is written when outputs are refused");
}

#[test]
fn a_failing_output_names_its_flag_and_keeps_the_others() {
    let dir = fresh_dir("cli", "failing_output");
    let scene = root().join("scenes/indexing_table.toml");
    if std::path::Path::new("/dev/full").exists() {
        let summary = dir.join("summary.json");
        let out = twin()
            .arg("run")
            .arg(&scene)
            .args(["--no-render", "--trace", "/dev/full", "--summary"])
            .arg(&summary)
            .output()
            .expect("run twin");
        let err = stderr(&out);
        assert_eq!(out.status.code(), Some(74), "{err}");
        assert!(err.contains("--trace: cannot write /dev/full"), "{err}");
        assert!(summary.exists(), "the summary is still written: {err}");
    }
    // A recording that cannot start leaves an earlier trace at the path as
    // it was, and no temporary file behind.
    let trace = dir.join("trace.csv");
    std::fs::write(&trace, "earlier run\n").expect("write");
    let port = free_port();
    let out = twin()
        .arg("run")
        .arg(&scene)
        .args(["--no-render", "--trace"])
        .arg(&trace)
        .args(["--connect", &format!("127.0.0.1:{port}")])
        .output()
        .expect("run twin");
    assert_eq!(out.status.code(), Some(74), "{}", stderr(&out));
    assert_eq!(std::fs::read_to_string(&trace).expect("trace"), "earlier run\n");
    let temporary: Vec<_> = std::fs::read_dir(&dir)
        .expect("dir")
        .filter_map(Result::ok)
        .map(|e| e.file_name())
        .filter(|n| n.to_string_lossy().ends_with(".tmp"))
        .collect();
    assert!(temporary.is_empty(), "left behind: {temporary:?}");
    // A successful run replaces it.
    let out = twin()
        .arg("run")
        .arg(&scene)
        .args(["--no-render", "--trace"])
        .arg(&trace)
        .output()
        .expect("run twin");
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(std::fs::read_to_string(&trace).expect("trace").starts_with("time_s"));
}

#[test]
fn connect_to_another_machine_warns() {
    // 0.0.0.0 is not a loopback address (and reaches this machine, where
    // nothing listens on the port: the run then stops with 74).
    let port = free_port();
    let out = twin()
        .arg("run")
        .arg(root().join("scenes/indexing_table.toml"))
        .args(["--no-render", "--connect", &format!("0.0.0.0:{port}")])
        .output()
        .expect("run twin");
    let err = stderr(&out);
    assert!(err.contains("warning: --connect 0.0.0.0:"), "{err}");
    assert!(err.contains("not this machine"), "{err}");
    let out = twin()
        .arg("run")
        .arg(root().join("scenes/indexing_table.toml"))
        .args(["--no-render", "--connect", &format!("127.0.0.1:{port}")])
        .output()
        .expect("run twin");
    assert!(!stderr(&out).contains("warning"), "{}", stderr(&out));
}

#[test]
fn frames_left_by_an_earlier_longer_run_are_named() {
    let dir = fresh_dir("cli", "stale_frames");
    std::fs::write(dir.join("iso-00099.png"), b"an earlier run's frame").expect("write");
    std::fs::write(dir.join("notes.png"), b"not a frame of ours").expect("write");
    let out = twin()
        .arg("run")
        .arg(root().join("scenes/indexing_table.toml"))
        .args(["--duration", "0.5", "--frames"])
        .arg(&dir)
        .output()
        .expect("run twin");
    let err = stderr(&out);
    if err.contains("no Vulkan adapter") {
        return; // no frames here at all
    }
    assert!(out.status.success(), "{err}");
    assert!(
        err.contains("1 frames of an earlier, longer run remain (from iso-00099.png)"),
        "{err}"
    );
    assert!(dir.join("iso-00099.png").exists() && dir.join("iso-00000.png").exists());
}

#[test]
fn a_viewer_that_accepts_but_never_reads_costs_no_other_output() {
    // It used to block forever after the trace was written; the summary
    // was never written.
    let listener = std::net::TcpListener::bind("127.0.0.1:0").expect("bind");
    let addr = listener.local_addr().expect("address").to_string();
    std::thread::spawn(move || {
        let mut held = Vec::new();
        for stream in listener.incoming().map_while(Result::ok) {
            held.push(stream); // accepted, never read
        }
    });
    let dir = fresh_dir("cli", "silent_viewer");
    let (trace, summary, rrd) = (dir.join("t.csv"), dir.join("s.json"), dir.join("r.rrd"));
    let started = std::time::Instant::now();
    let out = twin()
        .arg("run")
        .arg(root().join("scenes/indexing_table.toml"))
        .args(["--no-render", "--connect", &addr, "--trace"])
        .arg(&trace)
        .arg("--summary")
        .arg(&summary)
        .arg("--save")
        .arg(&rrd)
        .output()
        .expect("run twin");
    let err = stderr(&out);
    assert!(started.elapsed() < std::time::Duration::from_secs(120), "{err}");
    assert_eq!(out.status.code(), Some(74), "{err}");
    assert!(err.contains("recording"), "{err}");
    assert!(trace.exists() && summary.exists(), "{err}");
    // The file recording is on its own thread: the stuck viewer costs it
    // nothing (it used to be lost with the viewer's stream).
    let saved = std::fs::read(&rrd).unwrap_or_else(|e| panic!("no {}: {e}; {err}", rrd.display()));
    assert!(
        saved.starts_with(b"RRF2") && saved.len() > 10_000,
        "{} bytes",
        saved.len()
    );
}

#[test]
fn plant_kinematic_runs_with_actual_equal_to_command_and_says_so() {
    let dir = fresh_dir("cli", "plant_kinematic");
    let (trace, summary) = (dir.join("t.csv"), dir.join("s.json"));
    let out = twin()
        .arg("run")
        .arg(root().join("scenes/scara_pick.toml"))
        .args(["--no-render", "--plant", "kinematic", "--trace"])
        .arg(&trace)
        .arg("--summary")
        .arg(&summary)
        .output()
        .expect("run twin");
    let text = String::from_utf8_lossy(&out.stdout).into_owned() + &stderr(&out);
    assert!(out.status.success(), "{text}");
    assert!(text.contains("plant: kinematic"), "{text}");
    assert!(
        std::fs::read_to_string(&summary)
            .expect("summary")
            .contains("\"plant\": \"kinematic\"")
    );
    let csv = std::fs::read_to_string(&trace).expect("trace");
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().expect("header").split(',').collect();
    assert_eq!(header.last(), Some(&"plant.kinematic"));
    let (cmd, act) = (
        header.iter().position(|h| *h == "Z.cmd_pos").expect("Z.cmd_pos"),
        header.iter().position(|h| *h == "Z.act_pos").expect("Z.act_pos"),
    );
    for line in lines {
        let row: Vec<f64> = line.split(',').map(|x| x.parse().expect("number")).collect();
        assert_eq!(row[cmd], row[act], "{line}");
        assert_eq!(row.last(), Some(&1.0));
    }
    let bad = twin()
        .arg("run")
        .arg(root().join("scenes/scara_pick.toml"))
        .args(["--no-render", "--plant", "rigid"])
        .output()
        .expect("run twin");
    assert_eq!(bad.status.code(), Some(64));
    assert!(
        stderr(&bad).contains("expected physics or kinematic"),
        "{}",
        stderr(&bad)
    );
}

#[test]
fn bench_prints_a_row_per_scene_with_the_bare_simulation_and_the_kinematic_plant() {
    let out = twin()
        .args(["bench", "--runs", "1", "--no-render"])
        .arg(root().join("scenes/fault_demo.toml"))
        .arg(root().join("scenes/knife_cut.toml"))
        .arg(root().join("scenes/collision_cell.toml"))
        .output()
        .expect("run twin");
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(out.status.success(), "{text}{}", stderr(&out));
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 5, "{text}");
    // The live collision checks' cost per physics step, with [collision].
    let cell: Vec<&str> = lines[4].trim_matches('|').split('|').map(str::trim).collect();
    assert_eq!(cell[0], "collision_cell");
    assert!(cell[6].parse::<f64>().is_ok_and(|us| us > 0.0), "{}", lines[4]);
    assert!(
        lines[0]
            .starts_with("| scene | physics xRT | steps/s | bare steps/s | twin/bare | kinematic xRT | collision µs |")
    );
    for (line, scene) in lines[2..4].iter().zip(["fault_demo", "knife_cut"]) {
        let cells: Vec<&str> = line.trim_matches('|').split('|').map(str::trim).collect();
        assert_eq!(cells.len(), 15, "{line}");
        assert_eq!(cells[0], scene);
        for c in &cells[1..6] {
            let x: f64 = c.parse().unwrap_or_else(|_| panic!("{c} in {line}"));
            assert!(x > 0.0 && x.is_finite(), "{line}");
        }
        assert_eq!(cells[6], "-", "no [collision] in {scene}");
        let shares: f64 = cells[7..]
            .iter()
            .map(|c| c.trim_end_matches(" %").parse::<f64>().expect("a share"))
            .sum();
        assert!((0.0..=101.0 + 8.0).contains(&shares), "{line}");
    }
    let empty = fresh_dir("cli", "bench_empty");
    let none = twin()
        .args(["bench", "--runs", "1", "--no-render"])
        .arg(&empty)
        .output()
        .expect("run twin");
    assert!(!none.status.success());
    assert!(stderr(&none).contains("no scene to measure"), "{}", stderr(&none));
}
