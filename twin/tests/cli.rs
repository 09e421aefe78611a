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

/// `scenes/indexing_table.toml` without its own expectations (the tables
/// from its `# What this run must show` comment on) and with `edits`
/// applied, written under `target/cli/<name>/` (the URDF path made
/// absolute).
fn edited(name: &str, edits: &[(&str, &str)]) -> PathBuf {
    let mut text = common::shipped_scene_text(&root().join("scenes/indexing_table.toml"));
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

/// The indexing table without its own expectations (a run cut short by
/// `--duration` would fail them), under `target/cli/<name>/`.
fn plain_scene(name: &str) -> PathBuf {
    edited(name, &[])
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
    let scene = plain_scene("plain_137");
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
#[cfg_attr(not(feature = "rerun"), ignore = "needs the `rerun` feature")]
fn an_output_that_cannot_be_written_exits_74_naming_the_flag() {
    let dir = fresh_dir("cli", "unwritable");
    // A file where a folder is needed.
    let blocker = dir.join("file");
    std::fs::write(&blocker, "").expect("write");
    let scene = plain_scene("plain_162");
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
    let scene = plain_scene("plain_195");
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
        .arg(plain_scene("plain_213"))
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
        .arg(plain_scene("plain_235"))
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
#[cfg_attr(not(feature = "rerun"), ignore = "needs the `rerun` feature")]
fn serve_refuses_a_busy_port_and_goes_on_serving_after_the_run() {
    use std::io::BufRead as _;

    let scene = plain_scene("plain_258");
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
    let mesh = root().join("scenes/robots/indexing_table/meshes/vblock_fixture.stl");
    let mesh_before = std::fs::read(&mesh).expect("mesh");
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
        // Through a folder that does not exist yet.
        (
            vec![
                "--trace".into(),
                dir.join("n").join("z").into(),
                "--summary".into(),
                dir.join("n").join("..").join("n").join("z").into(),
            ],
            "--summary",
        ),
        // A file a frame takes.
        (
            vec![
                "--frames".into(),
                dir.join("ff").into(),
                "--trace".into(),
                dir.join("ff").join("iso-00000.png").into(),
            ],
            "a frame of the --frames folder takes this name",
        ),
        (
            vec![
                "--frames".into(),
                dir.join("ff").into(),
                "--summary".into(),
                dir.join("ff").join("iso-t1.5.png").into(),
            ],
            "a frame of the --frames folder takes this name",
        ),
        // A mesh the URDF names.
        (vec!["--trace".into(), mesh.clone().into()], "the scene reads this file"),
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
    assert_eq!(std::fs::read(&mesh).expect("mesh"), mesh_before, "the mesh was written");
    assert!(!out_file.exists(), "nothing is written when outputs are refused");
    assert!(!dir.join("n").exists(), "nothing is written when outputs are refused");
}

/// With standard output closed (`twin run … | true`), printing the summary
/// panicked before `--summary` was written; the file is written and the run
/// ends normally.
#[test]
fn a_closed_standard_output_costs_no_file() {
    let dir = fresh_dir("cli", "closed_stdout");
    let scene = edited("closed_stdout_scene", &[]);
    let summary = dir.join("s.json");
    let mut child = twin()
        .arg("run")
        .arg(&scene)
        .arg("--no-render")
        .arg("--summary")
        .arg(&summary)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("run twin");
    drop(child.stdout.take());
    let out = child.wait_with_output().expect("wait");
    let err = stderr(&out);
    assert!(!err.contains("panicked"), "{err}");
    assert_eq!(out.status.code(), Some(0), "{err}");
    assert!(summary.exists(), "--summary was not written");
}

#[test]
#[cfg_attr(not(feature = "rerun"), ignore = "needs the `rerun` feature")]
fn a_failing_output_names_its_flag_and_keeps_the_others() {
    let dir = fresh_dir("cli", "failing_output");
    let scene = plain_scene("plain_357");
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
        .arg(plain_scene("plain_413"))
        .args(["--no-render", "--connect", &format!("0.0.0.0:{port}")])
        .output()
        .expect("run twin");
    let err = stderr(&out);
    assert!(err.contains("warning: --connect 0.0.0.0:"), "{err}");
    assert!(err.contains("not this machine"), "{err}");
    let out = twin()
        .arg("run")
        .arg(plain_scene("plain_422"))
        .args(["--no-render", "--connect", &format!("127.0.0.1:{port}")])
        .output()
        .expect("run twin");
    assert!(!stderr(&out).contains("warning"), "{}", stderr(&out));
}

#[test]
#[cfg_attr(not(feature = "render"), ignore = "needs the `render` feature")]
fn frames_left_by_an_earlier_longer_run_are_named() {
    let dir = fresh_dir("cli", "stale_frames");
    std::fs::write(dir.join("iso-00099.png"), b"an earlier run's frame").expect("write");
    std::fs::write(dir.join("notes.png"), b"not a frame of ours").expect("write");
    let out = twin()
        .arg("run")
        .arg(plain_scene("plain_436"))
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
#[cfg_attr(not(feature = "rerun"), ignore = "needs the `rerun` feature")]
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
        .arg(plain_scene("plain_470"))
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
        assert_eq!(cells.len(), 17, "{line}");
        assert_eq!(cells[0], scene);
        for c in &cells[1..6] {
            let x: f64 = c.parse().unwrap_or_else(|_| panic!("{c} in {line}"));
            assert!(x > 0.0 && x.is_finite(), "{line}");
        }
        assert_eq!(cells[6], "-", "no [collision] in {scene}");
        assert_eq!((cells[7], cells[8]), ("-", "-"), "no cell in {scene}");
        let shares: f64 = cells[9..]
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

/// `scenes/indexing_table.toml` with `extra` appended, written under
/// `target/cli/<name>/scene.toml`; returns the path and the line the
/// first appended line has.
fn with_appended(name: &str, extra: &str) -> (PathBuf, usize) {
    let path = edited(name, &[]);
    let mut text = std::fs::read_to_string(&path).expect("scene");
    if !text.ends_with('\n') {
        text.push('\n');
    }
    let first_line = text.lines().count() + 1;
    text.push_str(extra);
    std::fs::write(&path, text).expect("write scene");
    (path, first_line)
}

/// The summary JSON of `twin run SCENE --no-render` and its exit code.
fn run_summary(path: &std::path::Path, extra: &[&str]) -> (Option<i32>, serde_json::Value, String) {
    let summary = path.with_file_name("summary.json");
    let out = twin()
        .arg("run")
        .arg(path)
        .args(["--no-render", "--summary"])
        .arg(&summary)
        .args(extra)
        .output()
        .expect("run twin");
    let text = std::fs::read_to_string(&summary).unwrap_or_default();
    (
        out.status.code(),
        serde_json::from_str(&text).unwrap_or(serde_json::Value::Null),
        format!("{}{}", String::from_utf8_lossy(&out.stdout), stderr(&out)),
    )
}

/// An expectation's entry in a summary.
fn expectation<'a>(summary: &'a serde_json::Value, name: &str) -> &'a serde_json::Value {
    summary["expectations"]
        .as_array()
        .and_then(|a| a.iter().find(|e| e["name"] == name))
        .unwrap_or_else(|| panic!("no expectation {name} in {summary}"))
}

#[test]
fn a_failed_expectation_exits_6_and_names_time_values_and_worst() {
    let (path, _) = with_appended(
        "expect_broken",
        "[[expect]]\nname = \"broken\"\nalways = \"Table.ActualPosition < 10.0\"\n",
    );
    let (code, summary, out) = run_summary(&path, &[]);
    assert_eq!(code, Some(6), "{out}");
    let e = expectation(&summary, "broken");
    assert_eq!(e["passed"], false);
    assert_eq!(e["kind"], "always");
    let message = e["message"].as_str().unwrap_or_default();
    // The table leaves 10° during the first move (0 → 90° from t = 0).
    assert!(
        message.starts_with("expect 'broken' failed at ")
            && message.contains("Table.ActualPosition = ")
            && message.contains("(< 10.0)")
            && message.contains("false in ")
            && message.contains(", worst "),
        "{message}"
    );
    let t = e["time_s"].as_f64().expect("a failing time");
    assert!(t > 0.0 && t < 1.5, "{t}");
    assert!(out.contains("FAIL expect 'broken' failed at"), "{out}");
    assert!(out.contains("error: 1 of 1 expectations failed"), "{out}");
}

#[test]
fn each_kind_of_expectation_passes_and_fails_on_the_indexing_table() {
    // MoveA: 0 → 90° from t = 0, done before 1 s; the buffered last move
    // ends at 135°, two turns on (the trace and the axis members unwind).
    // MoveA.CommandAborted rises once, when MoveB re-targets.
    let (path, _) = with_appended(
        "expect_kinds",
        r#"[[expect]]
name = "never an error"
never = "MoveA.Error OR MoveB.Error"

[[expect]]
name = "first move done by 1.5 s"
eventually = "MoveA.Done AND ABS(Table.ActualPosition - 90.0) < 0.5"
by_s = 1.5

[[expect]]
name = "ends at 135"
at_end = "ABS(Table.act_pos - 855.0) < 0.5 AND MoveA.Done"

[[expect]]
name = "aborted after the first done"
sequence = ["MoveA.Done", "MoveB.Busy", "MoveA.CommandAborted"]
within_s = 9.0

[[expect]]
name = "following error while moving"
always = "ABS(Table.cmd_pos - Table.act_pos) < 5.0"
while = "MoveA.Busy OR MoveB.Busy"
from_s = 0.0
to_s = 9.0

[[expect]]
name = "never reaches 200 too early"
eventually = "Table.cmd_pos > 1000.0"

[[expect]]
name = "busy cycles"
cycle = "MoveA.Busy"
min_s = 0.5
max_s = 1.0
count = 2

[[expect]]
name = "reversed order"
sequence = ["MoveA.CommandAborted", "MoveA.Done"]

[[expect]]
name = "time is a column"
at_end = "time_s >= 8.999"
"#,
    );
    let (code, summary, out) = run_summary(&path, &[]);
    assert_eq!(code, Some(6), "{out}");
    for name in [
        "never an error",
        "first move done by 1.5 s",
        "ends at 135",
        "aborted after the first done",
        "following error while moving",
        "time is a column",
    ] {
        let e = expectation(&summary, name);
        assert_eq!(e["passed"], true, "{name}: {e}");
    }
    let never = expectation(&summary, "never reaches 200 too early");
    assert_eq!(never["passed"], false);
    let m = never["message"].as_str().unwrap_or_default();
    assert!(
        m.contains("was never TRUE from 0 s to 9 s") && m.contains("best "),
        "{m}"
    );
    let cycle = expectation(&summary, "busy cycles");
    assert_eq!(cycle["passed"], false, "{cycle}");
    assert!(
        cycle["message"]
            .as_str()
            .unwrap_or_default()
            .contains("outside [0.5 s, 1 s]"),
        "{cycle}"
    );
    let reversed = expectation(&summary, "reversed order");
    assert_eq!(reversed["passed"], false);
    assert!(
        reversed["message"]
            .as_str()
            .unwrap_or_default()
            .contains("rose before step 1"),
        "{reversed}"
    );
}

#[test]
fn bad_expectations_and_variants_name_file_line_column_and_field() {
    let cases: [(&str, &str, usize, &str); 14] = [
        (
            "unknown_name",
            "[[expect]]\nname = \"x\"\nalways = \"Tabel.ActualPosition > 0.0\"\n",
            3,
            "expect[0].always: 'Tabel' is not a controller tag or an axis",
        ),
        (
            "not_bool",
            "[[expect]]\nname = \"x\"\nalways = \"Table.act_pos\"\n",
            3,
            "expect[0].always: the condition is LREAL: compare it",
        ),
        (
            "c_equals",
            "[[expect]]\nname = \"x\"\nalways = \"MoveA.Done == TRUE\"\n",
            3,
            "expect[0].always: ",
        ),
        (
            "two_kinds",
            "[[expect]]\nname = \"x\"\nalways = \"MoveA.Done\"\nnever = \"MoveB.Done\"\n",
            4,
            "expect[0]: give exactly one of always, never, eventually, at_end, sequence, cycle (found always and never)",
        ),
        (
            "no_kind",
            "[[expect]]\nname = \"x\"\n",
            2,
            "expect[0]: give exactly one of",
        ),
        (
            "empty_sequence",
            "[[expect]]\nname = \"x\"\nsequence = []\n",
            3,
            "expect[0].sequence: a sequence needs at least one condition",
        ),
        (
            "by_past_end",
            "[[expect]]\nname = \"x\"\neventually = \"MoveA.Done\"\nby_s = 12.0\n",
            4,
            "expect[0].by_s: by_s = 12 is after the end of the run (duration_s = 9)",
        ),
        (
            "option_of_another_kind",
            "[[expect]]\nname = \"x\"\nat_end = \"MoveA.Done\"\nwithin_s = 1.0\n",
            4,
            "expect[0].within_s: 'within_s' does not apply to 'at_end'",
        ),
        (
            "window_order",
            "[[expect]]\nname = \"x\"\nalways = \"MoveA.Done\"\nfrom_s = 5.0\nto_s = 2.0\n",
            5,
            "expect[0].to_s: from_s = 5 is after to_s = 2",
        ),
        (
            "duplicate_name",
            "[[expect]]\nname = \"x\"\nat_end = \"MoveA.Done\"\n[[expect]]\nname = \"X\"\nat_end = \"MoveA.Done\"\n",
            5,
            "expect[1].name: duplicate name 'X'",
        ),
        (
            "unknown_variant_tag",
            "[[variants]]\nname = \"v\"\ntags = { Speed = 3.0 }\n",
            3,
            "variants[0].tags.Speed: unknown tag 'Speed'",
        ),
        (
            "variant_tag_type",
            "[[tags]]\nname = \"Speed\"\ntype = \"DINT\"\nvalue = 1\n[[variants]]\nname = \"v\"\ntags = { Speed = 2.5 }\n",
            7,
            "variants[0].tags.Speed: value does not fit type DINT",
        ),
        (
            "bad_exit_code",
            "[test]\nexit_code = 7\n",
            2,
            "test.exit_code: exit code 7 is not one a run ends with",
        ),
        (
            "count_zero",
            "[[expect]]\nname = \"x\"\ncycle = \"MoveA.Busy\"\ncount = 0\n",
            4,
            "expect[0].count: must be between 1 and",
        ),
    ];
    for (name, extra, line, needle) in cases {
        let (path, first) = with_appended(&format!("bad_expect_{name}"), extra);
        let out = twin().arg("check").arg(&path).output().expect("run twin");
        let err = stderr(&out);
        assert_eq!(out.status.code(), Some(65), "{name}: {err}");
        let head = err.lines().next().unwrap_or_default();
        let place = format!("{}:{}:", path.display(), first + line - 1);
        assert!(
            head.starts_with("error: ") && head.contains(&place),
            "{name}: expected {place} in {head}"
        );
        assert!(head.contains(needle), "{name}: expected {needle:?} in {head}");
    }
}

#[test]
fn a_tag_that_is_also_a_trace_column_is_refused_naming_both() {
    let (path, first) = with_appended(
        "expect_column_clash",
        "[[tags]]\nname = \"time_s\"\ntype = \"REAL\"\nvalue = 0.0\n[[expect]]\nname = \"x\"\nalways = \"time_s >= 0.0\"\n",
    );
    let out = twin().arg("check").arg(&path).output().expect("run twin");
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(65), "{err}");
    let head = err.lines().next().unwrap_or_default();
    assert!(
        head.contains(&format!(
            "{}:{}:11: expect[0].always: 'time_s' names both the tag 'time_s' and the trace column 'time_s'",
            path.display(),
            first + 6
        )),
        "{head}"
    );
}

#[test]
fn variants_change_tags_duration_and_expectations() {
    let (path, _) = with_appended(
        "expect_variants",
        r#"[[tags]]
name = "Limit"
type = "REAL"
value = 100.0

[[expect]]
name = "under the limit"
always = "Table.cmd_pos < Limit"

[[variants]]
name = "short high"
tags = { Limit = 1000.0 }
duration_s = 1.0

[[variants.expect]]
name = "moving"
eventually = "MoveA.Busy"
"#,
    );
    let (code, summary, out) = run_summary(&path, &[]);
    assert_eq!(code, Some(6), "{out}");
    assert_eq!(expectation(&summary, "under the limit")["passed"], false);
    let (code, summary, out) = run_summary(&path, &["--variant", "short high"]);
    assert_eq!(code, Some(0), "{out}");
    assert_eq!(summary["variant"], "short high");
    assert!((summary["simulated_s"].as_f64().unwrap_or_default() - 1.0).abs() < 1e-9);
    assert_eq!(expectation(&summary, "under the limit")["passed"], true);
    assert_eq!(expectation(&summary, "moving")["passed"], true);
    let out = twin()
        .arg("run")
        .arg(&path)
        .args(["--no-render", "--variant", "nope"])
        .output()
        .expect("run twin");
    assert_eq!(out.status.code(), Some(64), "{}", stderr(&out));
    assert!(stderr(&out).contains("the variants short high"), "{}", stderr(&out));
}

/// A folder of scenes for `twin test`: the indexing table with a variant,
/// with a broken expectation, one that does not load, and one that runs
/// far longer than the timeout.
fn suite(name: &str) -> PathBuf {
    let dir = fresh_dir("cli", name);
    let base = std::fs::read_to_string(edited(&format!("{name}_base"), &[])).expect("scene");
    let good = format!(
        "{base}\n[[expect]]\nname = \"first move\"\neventually = \"MoveA.Done\"\nby_s = 1.5\n\n[[variants]]\nname = \"short\"\nduration_s = 2.0\n"
    );
    let write = |file: &str, text: String| std::fs::write(dir.join(file), text).expect("write");
    write("a_good.toml", good.replace("duration_s = 9.0", "duration_s = 3.0"));
    write(
        "b_broken.toml",
        format!("{base}\n[[expect]]\nname = \"broken\"\nalways = \"Table.ActualPosition < 10.0\"\n")
            .replace("duration_s = 9.0", "duration_s = 2.0"),
    );
    write(
        "c_bad.toml",
        base.replace("max_velocity = 360.0", "max_velocity = -1.0"),
    );
    write(
        "d_hangs.toml",
        base.replace("duration_s = 9.0", "duration_s = 100000.0"),
    );
    dir
}

#[test]
fn twin_test_reports_failures_errors_and_timeouts_in_junit() {
    let dir = suite("suite");
    let junit = dir.join("out/junit.xml");
    let artifacts = dir.join("out/failures");
    let out = twin()
        .arg("test")
        .arg(&dir)
        .args(["-j", "2", "--timeout", "4", "--no-render", "--junit"])
        .arg(&junit)
        .arg("--artifacts")
        .arg(&artifacts)
        .output()
        .expect("run twin test");
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    assert_eq!(out.status.code(), Some(1), "{stdout}{}", stderr(&out));
    let last = stdout.lines().last().unwrap_or_default();
    assert!(last.starts_with("2 passed, 3 failed"), "{stdout}");
    for line in ["PASS ", "FAIL ", "ERROR "] {
        assert!(stdout.contains(line), "{line}: {stdout}");
    }
    assert!(stdout.contains("timed out: killed after 4 s"), "{stdout}");
    assert!(stdout.contains("max_velocity"), "the load error's message: {stdout}");

    let xml = std::fs::read_to_string(&junit).expect("junit written");
    let report = quick_junit::Report::deserialize_from_str(&xml).expect("quick-junit reads the report");
    assert_eq!(report.test_suites.len(), 4, "a suite per scene file");
    let cases: Vec<&quick_junit::TestCase> = report.test_suites.iter().flat_map(|s| &s.test_cases).collect();
    let find = |class: &str, name: &str| {
        cases
            .iter()
            .find(|c| c.classname.as_ref().is_some_and(|k| k.as_str().ends_with(class)) && c.name.as_str() == name)
            .unwrap_or_else(|| panic!("no test case {class} {name} in {xml}"))
    };
    let broken = find("b_broken.toml", "broken");
    match &broken.status {
        quick_junit::TestCaseStatus::NonSuccess { kind, message, ty, .. } => {
            assert_eq!(*kind, quick_junit::NonSuccessKind::Failure);
            assert_eq!(ty.as_ref().map(|t| t.as_str()), Some("expectation"));
            let m = message.as_ref().map(|m| m.as_str()).unwrap_or_default();
            assert!(m.contains("failed at") && m.contains("Table.ActualPosition = "), "{m}");
        }
        other => panic!("broken: {other:?}"),
    }
    assert!(matches!(
        find("a_good.toml", "first move").status,
        quick_junit::TestCaseStatus::Success { .. }
    ));
    assert!(matches!(
        find("a_good.toml[short]", "run").status,
        quick_junit::TestCaseStatus::Success { .. }
    ));
    for errored in ["c_bad.toml", "d_hangs.toml"] {
        match &find(errored, "run").status {
            quick_junit::TestCaseStatus::NonSuccess { kind, .. } => {
                assert_eq!(*kind, quick_junit::NonSuccessKind::Error, "{errored}");
            }
            other => panic!("{errored}: {other:?}"),
        }
    }
    // The failed run's artifacts: summary, trace and recording.
    let failed_dir = std::fs::read_dir(&artifacts)
        .expect("artifacts")
        .filter_map(Result::ok)
        .find(|e| e.file_name().to_string_lossy().contains("b_broken"))
        .expect("the broken run's folder")
        .path();
    let recording = cfg!(feature = "rerun").then_some("run.rrd");
    for file in ["summary.json", "trace.csv"].into_iter().chain(recording) {
        assert!(failed_dir.join(file).is_file(), "{file} in {}", failed_dir.display());
    }
    assert!(xml.contains("[[ATTACHMENT|"), "{xml}");
}

#[test]
#[cfg_attr(not(feature = "render"), ignore = "needs the `render` feature")]
fn a_failed_expectation_attaches_a_picture_of_every_camera() {
    let dir = fresh_dir("cli", "suite_picture");
    let base = std::fs::read_to_string(edited("suite_picture_base", &[])).expect("scene");
    std::fs::write(
        dir.join("broken.toml"),
        format!("{base}\n[[expect]]\nname = \"broken\"\nalways = \"Table.ActualPosition < 10.0\"\n")
            .replace("duration_s = 9.0", "duration_s = 1.0"),
    )
    .expect("write");
    let junit = dir.join("junit.xml");
    let artifacts = dir.join("failures");
    let out = twin()
        .arg("test")
        .arg(dir.join("broken.toml"))
        .arg("--junit")
        .arg(&junit)
        .arg("--artifacts")
        .arg(&artifacts)
        .output()
        .expect("run twin test");
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let xml = std::fs::read_to_string(&junit).expect("junit");
    let picture = xml
        .split("[[ATTACHMENT|")
        .skip(1)
        .filter_map(|s| s.split("]]").next())
        .find(|p| p.ends_with(".png"));
    // The summary, trace and recording sit beside the pictures.
    for file in ["summary.json", "trace.csv"] {
        assert!(xml.contains(&format!("{file}]]")), "{file} attached: {xml}");
    }
    let rerun_stderr = std::fs::read_dir(&artifacts)
        .expect("artifacts")
        .filter_map(Result::ok)
        .map(|e| std::fs::read_to_string(e.path().join("stderr.txt")).unwrap_or_default())
        .collect::<String>();
    match picture {
        Some(p) => {
            assert!(std::path::Path::new(p).is_file(), "{p}");
            assert!(p.contains("iso-t"), "named after the camera and the time: {p}");
        }
        None => {
            // Only a machine with no Vulkan adapter takes no picture, and
            // the re-run says so; CI has lavapipe.
            assert!(
                std::env::var_os("CI").is_none() && rerun_stderr.contains("no Vulkan adapter"),
                "no picture: {xml}\n{rerun_stderr}"
            );
            eprintln!("SKIPPED the picture check: no Vulkan adapter ({rerun_stderr})");
        }
    }
}

/// Outputs may share the `--frames` folder under names no frame takes:
/// `twin test --artifacts` writes the summary, trace and recording beside
/// the pictures.
#[test]
fn outputs_beside_the_frames_are_kept() {
    let dir = fresh_dir("cli", "beside_frames");
    let scene = plain_scene("beside_frames_scene");
    let frames = dir.join("f");
    let out = twin()
        .arg("run")
        .arg(&scene)
        .args(["--duration", "0.1", "--frames-at", "0.05"])
        .arg("--frames")
        .arg(&frames)
        .arg("--summary")
        .arg(frames.join("summary.json"))
        .arg("--trace")
        .arg(frames.join("trace.csv"))
        .output()
        .expect("run twin");
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    for file in ["summary.json", "trace.csv"] {
        let len = std::fs::metadata(frames.join(file)).map(|m| m.len()).unwrap_or(0);
        assert!(len > 0, "{file} written beside the frames");
    }
}

#[test]
fn shards_run_every_run_exactly_once() {
    let list = |shard: &str| -> Vec<String> {
        let out = twin()
            .args(["test", "--list", "--shard", shard])
            .arg(root().join("scenes"))
            .output()
            .expect("twin test --list");
        assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
        String::from_utf8_lossy(&out.stdout)
            .lines()
            .map(str::to_owned)
            .collect()
    };
    let all = list("1/1");
    assert!(all.len() >= 15, "{all:?}");
    let mut union: Vec<String> = ["1/3", "2/3", "3/3"].iter().flat_map(|s| list(s)).collect();
    union.sort();
    let mut expected = all.clone();
    expected.sort();
    assert_eq!(union, expected, "three shards together run every run exactly once");
    for bad in ["0/3", "4/3", "1/0", "auto"] {
        let out = twin()
            .args(["test", "--list", "--shard", bad])
            .arg(root().join("scenes"))
            .env_remove("CI_NODE_INDEX")
            .env_remove("JOB_COMPLETION_INDEX")
            .output()
            .expect("twin test");
        assert_eq!(out.status.code(), Some(64), "{bad}: {}", stderr(&out));
    }
    let out = twin()
        .args(["test", "--list", "--shard", "auto", "--shards", "3"])
        .arg(root().join("scenes"))
        .env_remove("CI_NODE_INDEX")
        .env("JOB_COMPLETION_INDEX", "1")
        .output()
        .expect("twin test");
    assert_eq!(
        String::from_utf8_lossy(&out.stdout)
            .lines()
            .map(str::to_owned)
            .collect::<Vec<_>>(),
        list("2/3")
    );
}

#[test]
fn an_unwritable_junit_exits_74_before_anything_runs() {
    let dir = fresh_dir("cli", "suite_unwritable");
    let out = twin()
        .args(["test", "--junit", "/proc/twin/junit.xml"])
        .arg(root().join("scenes/indexing_table.toml"))
        .output()
        .expect("twin test");
    assert_eq!(out.status.code(), Some(74), "{}", stderr(&out));
    assert!(String::from_utf8_lossy(&out.stdout).is_empty(), "nothing ran");
    let _ = dir;
}

#[test]
fn repeat_compares_the_traces_of_deterministic_runs() {
    let (path, _) = with_appended("suite_repeat", "");
    let text = std::fs::read_to_string(&path)
        .expect("scene")
        .replace("duration_s = 9.0", "duration_s = 0.5");
    std::fs::write(&path, text).expect("write");
    let durations = path.with_file_name("durations.json");
    std::fs::write(&durations, "{\"elsewhere.toml\": 3.5}").expect("write");
    let out = twin()
        .arg("test")
        .arg(&path)
        .args(["--repeat", "2", "--no-render", "--durations"])
        .arg(&durations)
        .output()
        .expect("twin test");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{stdout}{}", stderr(&out));
    assert!(
        stdout
            .lines()
            .last()
            .unwrap_or_default()
            .starts_with("1 passed, 0 failed"),
        "{stdout}"
    );
    // The durations file keeps the other entries and gains this run's.
    let read: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&durations).expect("durations")).expect("JSON");
    assert_eq!(read["elsewhere.toml"], 3.5);
    assert!(
        read[path.display().to_string()].as_f64().is_some_and(|s| s > 0.0),
        "{read}"
    );
}

#[test]
fn shipped_scenes_with_expected_faults_pass_and_their_junit_reads_back() {
    // fault_demo must end with a major fault (exit code 4) and servo_states
    // with instruction errors (2): their [test] exit codes say so.
    let dir = fresh_dir("cli", "suite_shipped");
    let junit = dir.join("junit.xml");
    let out = twin()
        .current_dir(root())
        .args([
            "test",
            "scenes/fault_demo.toml",
            "scenes/servo_states.toml",
            "scenes/collision_cell_near_miss.toml",
            "--no-render",
            "--junit",
        ])
        .arg(&junit)
        .output()
        .expect("twin test");
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    assert_eq!(out.status.code(), Some(0), "{stdout}{}", stderr(&out));
    assert!(
        stdout
            .lines()
            .last()
            .unwrap_or_default()
            .starts_with("3 passed, 0 failed, 1 skipped"),
        "{stdout}"
    );
    let xml = std::fs::read_to_string(&junit).expect("junit");
    let report = quick_junit::Report::deserialize_from_str(&xml).expect("quick-junit reads the report");
    let names: Vec<String> = report
        .test_suites
        .iter()
        .flat_map(|s| &s.test_cases)
        .map(|c| {
            format!(
                "{}::{}",
                c.classname.as_ref().map_or("", |k| k.as_str()),
                c.name.as_str()
            )
        })
        .collect();
    for expected in [
        "scenes/fault_demo.toml::run",
        "scenes/fault_demo.toml::the major fault ends the run early",
        "scenes/servo_states.toml::MCT is refused with ERR 61 EXERR 13",
        "scenes/collision_cell_near_miss.toml::the gripper keeps 19 mm",
        "scenes/collision_cell_near_miss.toml::snapshots",
    ] {
        assert!(names.iter().any(|n| n == expected), "{expected} in {names:?}");
    }
}

/// A one-line routine could cost minutes of wall time a simulated second;
/// `--max-wall` stops a run cleanly between two updates: exit 7, the
/// outputs written up to there, the summary saying where it stopped.
#[test]
fn max_wall_stops_the_run_with_exit_7_and_its_outputs() {
    let dir = fresh_dir("cli", "max_wall");
    let scene = plain_scene("max_wall_scene");
    let (trace, summary) = (dir.join("t.csv"), dir.join("s.json"));
    let out = twin()
        .arg("run")
        .arg(&scene)
        .args(["--no-render", "--max-wall", "0.000001", "--trace"])
        .arg(&trace)
        .arg("--summary")
        .arg(&summary)
        .output()
        .expect("run twin");
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(7), "{err}");
    assert!(
        err.contains("--max-wall") && err.contains("stopped the run at t = 0.004 s"),
        "{err}"
    );
    let rows = std::fs::read_to_string(&trace).expect("trace").lines().count();
    assert_eq!(rows, 3, "the header, t = 0 and the one update run");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&summary).expect("summary")).expect("json");
    assert_eq!(json["wall_limit"]["time_s"].as_f64(), Some(0.004), "{json}");
    // A limit the run does not reach changes nothing.
    let out = twin()
        .arg("run")
        .arg(&scene)
        .args(["--no-render", "--duration", "0.1", "--max-wall", "600"])
        .output()
        .expect("run twin");
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let out = twin()
        .arg("run")
        .arg(&scene)
        .args(["--max-wall", "0"])
        .output()
        .expect("run twin");
    assert_eq!(out.status.code(), Some(64), "{}", stderr(&out));
}

/// sysexits for the scene file itself: one that does not exist, or is not
/// a regular file, is EX_NOINPUT (66); `--stdout` with standard output a
/// terminal is a usage error (64). A file the scene names that is missing
/// stays invalid input (65, the README's error table).
#[test]
fn a_missing_scene_exits_66_and_stdout_on_a_terminal_exits_64() {
    let dir = fresh_dir("cli", "no_input");
    for args in [
        vec!["check".to_owned(), dir.join("nope.toml").display().to_string()],
        vec![
            "run".to_owned(),
            dir.join("nope.toml").display().to_string(),
            "--no-render".to_owned(),
        ],
        vec!["check".to_owned(), dir.display().to_string()],
    ] {
        let out = twin().args(&args).output().expect("run twin");
        assert_eq!(out.status.code(), Some(66), "{args:?}: {}", stderr(&out));
    }
    // Standard output a terminal: `script` gives the command a pty (a
    // build without recordings refuses --stdout first, also 64).
    if !cfg!(feature = "rerun") {
        return;
    }
    let scene = plain_scene("stdout_tty");
    let command = format!(
        "{} run {} --no-render --duration 0.01 --stdout",
        env!("CARGO_BIN_EXE_twin"),
        scene.display()
    );
    let out = std::process::Command::new("script")
        .args(["-qec", &command, "/dev/null"])
        .stdin(std::process::Stdio::null())
        .output()
        .expect("script (util-linux) gives the command a terminal");
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(64), "{text}");
    assert!(text.contains("standard output is a terminal"), "{text}");
}

/// The codes of the README's "What a run itself reports" table, in order.
fn readme_exit_codes() -> Vec<u8> {
    let readme = std::fs::read_to_string(root().join("README.md")).expect("README.md");
    let table = readme
        .split("| exit code | meaning |")
        .nth(1)
        .expect("the README's exit-code table");
    table
        .lines()
        .skip(2)
        .take_while(|l| l.starts_with('|'))
        .map(|l| {
            let code = l.trim_start_matches('|').split('|').next().unwrap_or_default().trim();
            code.parse().unwrap_or_else(|_| panic!("not an exit code: {l}"))
        })
        .collect()
}

/// The exit-code table holds row by row: every code the README lists is
/// in `twin --help` and a run that ends with it, and a code the twin
/// gives that the table lacks fails here.
#[test]
fn the_exit_code_table_holds_row_by_row() {
    let codes = readme_exit_codes();
    let help = String::from_utf8_lossy(&twin().arg("--help").output().expect("twin --help").stdout).into_owned();
    let listed = help.split("Exit codes:").nth(1).expect("--help lists the exit codes");
    let run = |args: &[&str], path: &std::path::Path| {
        let mut command = twin();
        command.arg(args[0]).arg(path).args(&args[1..]);
        command.output().expect("run twin")
    };
    for code in &codes {
        assert!(
            listed.contains(&format!("{code} ")),
            "--help's exit codes lack {code}: {listed}"
        );
        let dir = fresh_dir("cli", &format!("exit_{code}"));
        let out = match code {
            0 => run(
                &["run", "--no-render", "--duration", "0.1"],
                &plain_scene("exit_0_scene"),
            ),
            // MC_MoveModulo refuses a negative velocity (ErrorID).
            2 => run(
                &["run", "--no-render", "--duration", "0.2"],
                &edited(
                    "exit_2_scene",
                    &[(
                        "Position := 90.0, Velocity := 180.0",
                        "Position := 90.0, Velocity := -180.0",
                    )],
                ),
            ),
            3 => {
                let text = common::shipped_scene_text(&root().join("scenes/collision_cell.toml"))
                    .replace("reaction = \"report\"", "reaction = \"abort\"")
                    .replace(
                        "urdf = \"robots/",
                        &format!("urdf = \"{}/scenes/robots/", root().display()),
                    );
                let path = dir.join("abort.toml");
                std::fs::write(&path, text).expect("scene");
                run(&["run", "--no-render"], &path)
            }
            4 => run(&["run", "--no-render"], &root().join("scenes/fault_demo.toml")),
            5 => run(
                &["run", "--no-render"],
                &common::one_joint_arm(
                    "cli",
                    "exit_5_arm",
                    "",
                    "",
                    "system_inertia = 4000.0, torque_limit_positive = 1e7, torque_limit_negative = -1e7",
                ),
            ),
            6 => {
                let path = plain_scene("exit_6_scene");
                let text = std::fs::read_to_string(&path).expect("scene")
                    + "\n[[expect]]\nname = \"never\"\nalways = \"Table.cmd_pos > 1000\"\n";
                std::fs::write(&path, text).expect("scene");
                run(&["run", "--no-render", "--duration", "0.1"], &path)
            }
            7 => run(
                &["run", "--no-render", "--max-wall", "0.001"],
                &plain_scene("exit_7_scene"),
            ),
            64 => run(&["run", "--frmes", "out"], &plain_scene("exit_64_scene")),
            65 => run(
                &["check"],
                &edited("exit_65_scene", &[("max_velocity = 360.0", "max_velocity = \"fast\"")]),
            ),
            66 => run(&["check"], &dir.join("nope.toml")),
            // A folder for the trace where a file is.
            74 => {
                std::fs::write(dir.join("a_file"), "").expect("file");
                let trace = dir.join("a_file/trace.csv");
                twin()
                    .arg("run")
                    .arg(plain_scene("exit_74_scene"))
                    .args(["--no-render", "--duration", "0.1", "--trace"])
                    .arg(&trace)
                    .output()
                    .expect("run twin")
            }
            _ => panic!("the README lists exit code {code}, which this test has no case for"),
        };
        assert_eq!(
            out.status.code(),
            Some(i32::from(*code)),
            "exit {code}: {}",
            stderr(&out)
        );
    }
    for code in [0, 2, 3, 4, 5, 6, 7, 64, 65, 66, 74] {
        assert!(codes.contains(&code), "the README's table lacks exit code {code}");
    }
}

/// `-q` prints the summary only when the run fails; `-v` prints each
/// instruction event on stderr as it happens, with its time.
#[test]
fn quiet_and_verbose() {
    let scene = plain_scene("quiet");
    let out = twin()
        .arg("run")
        .arg(&scene)
        .args(["--no-render", "--duration", "0.5", "-q"])
        .output()
        .expect("run twin");
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(out.stdout.is_empty(), "{}", String::from_utf8_lossy(&out.stdout));
    let failing = std::fs::read_to_string(&scene).expect("scene")
        + "\n[[expect]]\nname = \"never\"\nalways = \"Table.cmd_pos > 1000\"\n";
    let failing_scene = fresh_dir("cli", "quiet_failing").join("scene.toml");
    std::fs::write(&failing_scene, failing).expect("scene");
    let out = twin()
        .arg("run")
        .arg(&failing_scene)
        .args(["--no-render", "--duration", "0.5", "--quiet"])
        .output()
        .expect("run twin");
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(6), "{}", stderr(&out));
    assert!(text.contains("scene indexing_table") && text.contains("FAIL"), "{text}");
    let out = twin()
        .arg("run")
        .arg(&scene)
        .args(["--no-render", "--duration", "1.0", "-v"])
        .output()
        .expect("run twin");
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(0), "{err}");
    let events: Vec<&str> = err.lines().filter(|l| l.starts_with("t = ")).collect();
    assert!(
        events.iter().any(|l| l.contains("MoveA: Busy")) && events.iter().any(|l| l.contains("MoveA: Done")),
        "{err}"
    );
    // In time order.
    let times: Vec<f64> = events
        .iter()
        .filter_map(|l| l.strip_prefix("t = ")?.split(' ').next()?.parse().ok())
        .collect();
    assert!(times.windows(2).all(|w| w[0] <= w[1]), "{times:?}");
    let out = twin()
        .arg("run")
        .arg(&scene)
        .args(["-q", "-v"])
        .output()
        .expect("run twin");
    assert_eq!(out.status.code(), Some(64), "{}", stderr(&out));
}
