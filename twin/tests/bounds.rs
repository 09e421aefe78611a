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

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

/// [`common::one_joint_arm`] under `target/bounds/<name>`.
fn arm(name: &str, collision: &str, axis: &str, drive: &str) -> PathBuf {
    common::one_joint_arm("bounds", name, collision, axis, drive)
}

/// Loads `scene` and builds the twin: the load error's text, if any.
fn build(scene: &Path) -> Result<twin::run::Twin, String> {
    let s = twin::scene::load(scene).map_err(|e| e.to_string())?;
    twin::run::Twin::new(s).map_err(|e| twin::source::diag::with_causes(&e))
}

/// The error of what must fail; `what` says what was wrongly accepted.
fn refused<T, E: ToString>(r: Result<T, E>, what: &str) -> String {
    match r {
        Ok(_) => panic!("{what}"),
        Err(e) => e.to_string(),
    }
}

fn twin_cmd() -> Command {
    Command::new(env!("CARGO_BIN_EXE_twin"))
}

/// `twin check /dev/zero` read the stream until memory ran out: only
/// regular files are read, each up to its kind's bound (README budget
/// table; the bound itself and one byte more: `source::read`'s unit
/// tests).
#[test]
fn a_stream_without_end_is_refused_and_a_mesh_past_its_bound_too() {
    let out = twin_cmd().args(["check", "/dev/zero"]).output().expect("twin check");
    let err = String::from_utf8_lossy(&out.stderr);
    assert_ne!(out.status.code(), Some(0), "{err}");
    assert!(err.contains("/dev/zero") && err.contains("not a regular file"), "{err}");
    // A mesh one byte past its bound (a sparse file: no disk is used).
    let dir = common::fresh_dir("bounds", "endless_mesh");
    std::fs::File::create(dir.join("part.stl"))
        .and_then(|f| f.set_len(twin::source::InputKind::Mesh.max_bytes() + 1))
        .expect("sparse mesh");
    let scene = arm("endless_mesh_arm", "", "", "");
    let urdf = scene.with_file_name("arm.urdf");
    let text = std::fs::read_to_string(&urdf).expect("urdf").replace(
        "</link>\n  <joint",
        &format!(
            "<visual><geometry><mesh filename=\"{}\"/></geometry></visual></link>\n  <joint",
            dir.join("part.stl").display()
        ),
    );
    std::fs::write(&urdf, text).expect("urdf");
    let e = refused(build(&scene), "an endless mesh loads");
    assert!(e.contains("longer than 64 MiB"), "{e}");
}

/// `position_loop_bandwidth_hz = 1e6` gave 2e14 N·m and joints 200° off
/// with exit 0: a loop too fast for its substep is refused at its field;
/// the bound itself loads.
#[test]
fn drive_bandwidths_too_fast_for_the_substep_are_refused_at_load() {
    // physics_step_ms = 1 with 2 substeps: 0.5 ms.
    let max_hz = twin::scene::MAX_LOOP_BANDWIDTH_STEP / (std::f64::consts::TAU * 0.5e-3);
    let scene = arm("fast_loop", "", "", "position_loop_bandwidth_hz = 1e6");
    let e = refused(build(&scene), "a 1 MHz loop loads");
    assert!(
        e.contains("arm.toml:") && e.contains("axes[0].drive.position_loop_bandwidth_hz") && e.contains("unstable"),
        "{e}"
    );
    let at = arm(
        "loop_at_bound",
        "",
        "",
        &format!("velocity_loop_bandwidth_hz = {max_hz}"),
    );
    assert!(build(&at).is_ok(), "at the bound");
    let past = arm(
        "loop_past_bound",
        "",
        "",
        &format!("velocity_loop_bandwidth_hz = {}", max_hz * 1.001),
    );
    assert!(build(&past).is_err(), "past the bound");
    // A default bandwidth on a step too long for it names physics_step_ms.
    let long = std::fs::read_to_string(&scene)
        .expect("scene")
        .replace("position_loop_bandwidth_hz = 1e6", "")
        .replace("physics_step_ms = 1.0", "physics_step_ms = 4.0\nphysics_substeps = 1");
    std::fs::write(&scene, long).expect("scene");
    let e = refused(build(&scene), "80 Hz at 4 ms loads");
    assert!(e.contains("physics_step_ms") && e.contains("80 Hz"), "{e}");
}

/// Finite divergence ran to exit 0; a gain set that passes the load checks
/// but makes the joint run away (a `system_inertia` 10⁴ times the arm's)
/// stops the run as a physics fault within 50 ms, naming the link.
#[test]
fn a_runaway_joint_stops_the_run_as_a_physics_fault() {
    let runaway = "system_inertia = 4000.0, torque_limit_positive = 1e7, torque_limit_negative = -1e7";
    let scene = arm("runaway", "", "", runaway);
    let mut twin = build(&scene).unwrap_or_else(|e| panic!("{e}"));
    while !twin.stopped() && twin.time_s() < 0.5 {
        twin.step();
    }
    let fault = twin.plant().physics_fault().cloned().expect("a physics fault");
    assert!(fault.time_s <= 0.05, "stopped at {} s: {fault}", fault.time_s);
    assert!(fault.what.contains("link forearm"), "{fault}");
    // The right inertia holds the arm: no fault.
    let scene = arm(
        "held",
        "",
        "",
        "system_inertia = 0.41, torque_limit_positive = 1e7, torque_limit_negative = -1e7",
    );
    let mut twin = build(&scene).unwrap_or_else(|e| panic!("{e}"));
    while !twin.stopped() && twin.time_s() < 0.5 {
        twin.step();
    }
    assert!(twin.plant().physics_fault().is_none());
    // The CLI's exit code.
    let scene = arm("runaway_cli", "", "", runaway);
    let out = twin_cmd()
        .arg("run")
        .arg(&scene)
        .arg("--no-render")
        .output()
        .expect("twin run");
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(5), "{err}");
    assert!(err.contains("ran away") && err.contains("forearm"), "{err}");
}

/// `initial_position = -1e308` made a 180° move vanish below the float's
/// resolution; positions are bounded at ±10⁹ units at load and at run
/// time (ERR 13 on the operand).
#[test]
fn positions_beyond_reason_are_refused_at_load_and_at_run_time() {
    let far = arm("far", "", "initial_position = -1e308", "");
    let e = refused(build(&far), "-1e308 loads");
    assert!(
        e.contains("axes[0].initial_position") && e.contains("1000000000"),
        "{e}"
    );
    let limits = arm("far_limits", "", "soft_travel_limits = [-2e9, 10.0]", "");
    assert!(build(&limits).is_err(), "soft travel limits past the bound");
    // On a virtual axis (no joint range) the bound itself loads.
    let mut s = Sandbox::with_axes(
        &["X"],
        &[("M", "MOTION_INSTRUCTION"), ("P", "REAL"), ("E", "DINT"), ("Ex", "DINT")],
        "MAM(X, M, 0, P, 10, unitspersec, 100, unitspersec2, 100, unitspersec2, trapezoidal, 100, 100, %ofTime, disabled, programmed, 0, none, 0, 0);\n\
         E := M.ERR; Ex := M.EXERR;",
    )
    .unwrap_or_else(|e| panic!("{e}"));
    s.set("P", twin::program::types::Value::Real(2e9));
    s.scan();
    assert_eq!(s.value("E"), Some(twin::program::types::Value::Int(13)), "MAM to 2e9");
    assert_eq!(s.value("Ex"), Some(twin::program::types::Value::Int(3)), "on Position");
    // The REAL just past the bound (1,000,000,064) is refused too; the
    // bound itself starts the move.
    s.set("P", twin::program::types::Value::Real(1_000_000_064.0));
    s.scan();
    assert_eq!(
        s.value("E"),
        Some(twin::program::types::Value::Int(13)),
        "MAM to 1e9 + 64"
    );
    s.set("P", twin::program::types::Value::Real(1e9));
    s.scan();
    s.scan();
    assert_eq!(s.value("E"), Some(twin::program::types::Value::Int(0)), "MAM to 1e9");
}

/// A 284-byte STL tetrahedron 10³⁰ m across as a collision shape passed
/// `twin check` and hung the continuous collision check: a collision mesh
/// is bounded like the URDF's primitives (10⁴ m from its frame).
#[test]
fn an_astronomical_collision_mesh_is_refused_at_load() {
    for (name, size_m, ok) in [
        ("tetra_huge", 1e30f32, false),
        ("tetra_bound", 1e4, true),
        ("tetra_past", 1.001e4, false),
    ] {
        let scene = collision_mesh_arm(name, &common::tetrahedron(size_m), "");
        loads_or_names(&scene, ok, &["forearm", "reaches"]);
        // Without `[collision]` too: the physics and the parts world build
        // shapes from the URDF's collision meshes as well.
        let text = std::fs::read_to_string(&scene).expect("scene");
        let cut = text.find("[collision]").expect("a collision table");
        std::fs::write(&scene, &text[..cut]).expect("scene");
        loads_or_names(&scene, ok, &["forearm", "reaches"]);
    }
    // An obstacle's mesh, scaled past the bound.
    let scene = collision_mesh_arm("obstacle_huge", &common::tetrahedron(1.0), "");
    let obstacle = format!(
        "[[obstacles]]\nname = \"slab\"\nshape = \"mesh\"\nfile = {:?}\nscale = [2e4, 1.0, 1.0]\nposition = [2.0, 0.0, 0.0]\n",
        scene.with_file_name("part.stl")
    );
    let text = std::fs::read_to_string(&scene)
        .expect("scene")
        .replace("[collision]", &(obstacle + "[collision]"));
    std::fs::write(&scene, text).expect("scene");
    loads_or_names(&scene, false, &["slab", "reaches"]);
}

/// VHACD ran without bound (20,000 triangles: more than two minutes): a
/// mesh for `meshes = "convex_decomposition"` is bounded in triangles.
#[test]
fn convex_decomposition_is_bounded_in_triangles() {
    let max = twin::plant::collision::MAX_DECOMPOSITION_TRIANGLES;
    for (name, n, ok) in [("soup_bound", max, true), ("soup_past", max + 1, false)] {
        // A soup of small tetrahedra' faces along a line: concave as a whole.
        let mut triangles = Vec::new();
        let mut k = 0usize;
        while triangles.len() < n {
            let x = k as f32 * 0.01;
            for t in common::tetrahedron(0.008) {
                if triangles.len() < n {
                    triangles.push(t.map(|c| [c[0] + x, c[1], c[2]]));
                }
            }
            k += 1;
        }
        let scene = collision_mesh_arm(name, &triangles, "meshes = \"convex_decomposition\"\n");
        loads_or_names(&scene, ok, &["triangles", "convex_hull"]);
        // The scene's meshes together: as many of it as the total allows,
        // and one more (six of 1,000 took 34 s).
        let total = twin::plant::collision::MAX_DECOMPOSITION_TRIANGLES_TOTAL;
        if ok {
            for (copies, fits) in [(total / n, true), (total / n + 1, false)] {
                let urdf = scene.with_file_name("arm.urdf");
                let text = std::fs::read_to_string(&urdf).expect("urdf");
                let one = "<collision><geometry><mesh filename=\"part.stl\"/></geometry></collision>";
                let many = text.replacen(one, &one.repeat(copies), 1);
                std::fs::write(&urdf, &many).expect("urdf");
                loads_or_names(&scene, fits, &["together", "convex_hull"]);
                std::fs::write(&urdf, text).expect("urdf");
            }
        }
    }
}

/// The arm with `triangles` as the forearm's collision mesh and a
/// `[collision]` table with `settings`.
fn collision_mesh_arm(name: &str, triangles: &[[[f32; 3]; 3]], settings: &str) -> PathBuf {
    let scene = arm(
        name,
        "<collision><geometry><mesh filename=\"part.stl\"/></geometry></collision>",
        "",
        "",
    );
    std::fs::write(scene.with_file_name("part.stl"), common::binary_stl(triangles)).expect("stl");
    let text = std::fs::read_to_string(&scene).expect("scene") + "[collision]\nreaction = \"stop\"\n" + settings;
    std::fs::write(&scene, text).expect("scene");
    scene
}

/// `scene` builds when `ok`, else its error holds every one of `needles`.
fn loads_or_names(scene: &Path, ok: bool, needles: &[&str]) {
    match build(scene) {
        Ok(_) => assert!(ok, "{} loads", scene.display()),
        Err(e) => {
            assert!(!ok, "{}: {e}", scene.display());
            assert!(needles.iter().all(|n| e.contains(n)), "{e}");
        }
    }
}

/// A COLLADA index past its arrays was refused (exit 65) but mesh-loader's
/// panic text reached stderr first.
#[test]
fn a_collada_index_past_its_arrays_is_refused_without_panic_text() {
    let scene = arm(
        "dae_index",
        "<visual><geometry><mesh filename=\"part.dae\"/></geometry></visual>",
        "",
        "",
    );
    let dae = r##"<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit meter="1"/><up_axis>Z_UP</up_axis></asset>
  <library_geometries>
    <geometry id="g" name="g"><mesh>
      <source id="g-pos"><float_array id="g-pos-a" count="9">0 0 0 1 0 0 0 1 0</float_array>
        <technique_common><accessor source="#g-pos-a" count="3" stride="3">
          <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
        </accessor></technique_common></source>
      <vertices id="g-v"><input semantic="POSITION" source="#g-pos"/></vertices>
      <triangles count="1"><input semantic="VERTEX" source="#g-v" offset="0"/><p>0 1 999</p></triangles>
    </mesh></geometry>
  </library_geometries>
  <library_visual_scenes><visual_scene id="s"><node id="n"><instance_geometry url="#g"/></node></visual_scene></library_visual_scenes>
  <scene><instance_visual_scene url="#s"/></scene>
</COLLADA>
"##;
    std::fs::write(scene.with_file_name("part.dae"), dae).expect("dae");
    let out = twin_cmd().arg("check").arg(&scene).output().expect("twin check");
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(65), "{err}");
    assert!(err.contains("part.dae"), "{err}");
    assert!(!err.contains("panicked"), "{err}");
}

/// A 10,000-link chain took 4.8 GB to build (rapier's multibody keeps a
/// Jacobian of every link over every joint): a robot has at most
/// `MAX_LINKS` links, checked before anything is built.
#[test]
fn a_chain_of_links_past_the_bound_is_refused_before_it_is_built() {
    let max = twin::plant::urdf::checks::MAX_LINKS;
    // `links` links.
    let chain = |links: usize| common::chain_urdf(links - 1);
    let path = Path::new("chain.urdf");
    assert!(
        twin::plant::urdf::RobotModel::from_urdf_str(&chain(max), path).is_ok(),
        "at the bound"
    );
    let e = refused(
        twin::plant::urdf::RobotModel::from_urdf_str(&chain(max + 1), path),
        "one link past the bound loads",
    );
    let m = e.to_string();
    assert!(
        m.starts_with(&format!("chain.urdf:{}: link l{max}:", max * 2 + 1)),
        "{m}"
    );
    assert!(m.contains("257 links, more than the 256"), "{m}");
    let e = refused(
        twin::plant::urdf::RobotModel::from_urdf_str(&chain(10_000), path),
        "10,000 links load",
    );
    assert!(e.to_string().contains("10000 links"), "{e}");
}

/// A scene of `tasks` periodic tasks of `programs` programs each (one
/// statement a program), on the fixture table; loaded.
fn tasks_scene(name: &str, tasks: usize, programs: usize, statement_us: f64) -> Result<twin::scene::Scene, String> {
    let dir = common::fresh_dir("bounds", name);
    std::fs::write(dir.join("Main.st"), "N := N + 1;\n").expect("routine");
    let urdf = common::root().join("twin/tests/fixtures/robots/indexing_table.urdf");
    let mut s = format!(
        "name = \"tasks\"\nduration_s = 0.1\ncoarse_update_ms = 4.0\nphysics_step_ms = 1.0\n\
         [robot]\nurdf = {urdf:?}\n[controller]\nstatement_us = {statement_us}\n\
         [[tags]]\nname = \"N\"\ntype = \"DINT\"\n"
    );
    for t in 0..tasks {
        s.push_str(&format!("[[tasks]]\nname = \"T{t}\"\nperiod_ms = 4.0\npriority = 5\n"));
        for p in 0..programs {
            s.push_str(&format!(
                "[[tasks.programs]]\nname = \"P{t}_{p}\"\nmain = \"Main.st\"\n"
            ));
        }
    }
    let path = dir.join("tasks.toml");
    std::fs::write(&path, s).expect("scene");
    twin::scene::load(&path).map_err(|e| e.to_string())
}

/// The tasks, the programs a task schedules and the statements a run may
/// execute per simulated second (1 s / `statement_us`) are bounded: each
/// at its bound loads, one past it is refused naming its field.
#[test]
fn tasks_programs_and_statement_time_are_bounded() {
    use twin::scene::{MAX_PROGRAMS_PER_TASK, MAX_TASKS, MIN_STATEMENT_US};
    assert!(tasks_scene("tasks_at_bound", MAX_TASKS, 1, 1.0).is_ok());
    let e = refused(tasks_scene("tasks_past_bound", MAX_TASKS + 1, 1, 1.0), "33 tasks load");
    assert!(e.contains("tasks[32].name") && e.contains("at most 32 tasks"), "{e}");
    assert!(tasks_scene("programs_at_bound", 1, MAX_PROGRAMS_PER_TASK, 1.0).is_ok());
    let e = refused(
        tasks_scene("programs_past_bound", 1, MAX_PROGRAMS_PER_TASK + 1, 1.0),
        "1,001 programs load",
    );
    assert!(
        e.contains("tasks[0].programs[1000].name") && e.contains("at most 1000 programs"),
        "{e}"
    );
    assert!(tasks_scene("statement_at_bound", 1, 1, MIN_STATEMENT_US).is_ok());
    let e = refused(
        tasks_scene("statement_past_bound", 1, 1, MIN_STATEMENT_US * 0.99),
        "a 9.9 ns statement loads",
    );
    assert!(e.contains("controller.statement_us"), "{e}");
}

/// ULINT values above 2⁶³ − 1 could not be written (the literal was out of
/// range) and ULINT math was LINT's: `0 - 1` wrapped with no minor fault.
/// ULINT now computes unsigned.
#[test]
fn ulint_holds_values_past_2_63_and_its_underflow_is_a_minor_fault() {
    use twin::program::types::Value;
    let tags = [
        ("U", "ULINT"),
        ("Z", "ULINT"),
        ("D", "ULINT"),
        ("Big", "BOOL"),
        ("Wrapped", "BOOL"),
        ("R", "LREAL"),
    ];
    let routine = "U := 18446744073709551615; Big := U > 9223372036854775807; D := U / 2; R := U;\n\
                   Z := 0; Z := Z - 1; Wrapped := Z = U;";
    let mut s = Sandbox::new(&tags, routine).unwrap_or_else(|e| panic!("{e}"));
    s.scan();
    assert_eq!(s.value("U"), Some(Value::Int(-1)), "2^64 - 1 in its 64 bits");
    assert_eq!(s.value("Big"), Some(Value::Bool(true)));
    assert_eq!(s.value("D"), Some(Value::Int(i64::MAX)), "(2^64 - 1) / 2 = 2^63 - 1");
    assert_eq!(s.value("R"), Some(Value::Real(18446744073709551615.0)));
    assert_eq!(s.value("Wrapped"), Some(Value::Bool(true)), "0 - 1 wraps to 2^64 - 1");
    let minors = s.controller().minor_faults();
    assert_eq!(minors.len(), 1, "{minors:?}");
    assert_eq!((minors[0].fault_type, minors[0].code), (4, 4));
    assert!(
        Sandbox::new(&tags, "U := 18446744073709551616;").is_err(),
        "2^64 is past ULINT"
    );
    // Between ULINT and the signed types: the low bits, and the fault
    // when the value does not fit (a ULINT of 5 fits a DINT).
    let tags = [("U", "ULINT"), ("L", "LINT"), ("I", "DINT")];
    for (routine, faults) in [
        ("U := 18446744073709551615; I := U;", 1),
        ("U := 9223372036854775808; L := U;", 1),
        ("L := -5; U := L;", 1),
        ("U := 5; I := U; L := -0; U := L;", 0),
    ] {
        let mut s = Sandbox::new(&tags, routine).unwrap_or_else(|e| panic!("{e}"));
        s.scan();
        assert_eq!(s.controller().minor_faults().len(), faults, "{routine}");
    }
}

/// A ULINT above 2⁶³ − 1 was written to the trace as a negative number.
#[test]
fn the_trace_writes_a_ulint_unsigned() {
    let dir = common::fresh_dir("bounds", "ulint_trace");
    std::fs::write(dir.join("Main.st"), "U := 18446744073709551615;\n").expect("routine");
    let urdf = common::root().join("twin/tests/fixtures/robots/indexing_table.urdf");
    let scene = dir.join("ulint.toml");
    std::fs::write(
        &scene,
        format!(
            "name = \"ulint\"\nduration_s = 0.008\ncoarse_update_ms = 4.0\nphysics_step_ms = 1.0\n\
             [robot]\nurdf = {urdf:?}\n[[tags]]\nname = \"U\"\ntype = \"ULINT\"\n\
             [[tasks]]\nname = \"T\"\nperiod_ms = 4.0\npriority = 5\n\
             [[tasks.programs]]\nname = \"P\"\nmain = \"Main.st\"\n[trace]\ntags = [\"U\"]\n"
        ),
    )
    .expect("scene");
    let trace = dir.join("t.csv");
    let out = twin_cmd()
        .arg("run")
        .arg(&scene)
        .args(["--no-render", "--trace"])
        .arg(&trace)
        .output()
        .expect("twin run");
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    let text = std::fs::read_to_string(&trace).expect("trace");
    let last = text.lines().last().expect("a row");
    assert!(last.ends_with(",18446744073709551615"), "{last}");
}

/// A 21.6 MB routine took 2.65 GB: a routine file is read up to its
/// bound (4 MiB) and refused past it, naming the file.
#[test]
fn a_routine_past_its_size_bound_is_refused_naming_its_file() {
    let scene = tasks_scene("big_routine", 1, 1, 1.0)
        .map(|s| s.path)
        .expect("the scene loads");
    let routine = scene.with_file_name("Main.st");
    std::fs::File::create(&routine)
        .and_then(|f| f.set_len(twin::source::InputKind::Routine.max_bytes() + 1))
        .expect("sparse routine");
    let e = refused(twin::scene::load(&scene), "a 4 MiB + 1 routine loads");
    assert!(e.contains("Main.st") && e.contains("longer than 4 MiB"), "{e}");
}

/// 20,000 unclosed `coordinate_system = { [` lines (a fuzz mutant) made
/// the TOML parser's recovery overflow the stack: exit 134. The nesting is
/// checked before parsing, at the bracket that opens level 65.
#[test]
fn a_scene_of_unclosed_inline_tables_is_refused_not_a_stack_overflow() {
    let dir = common::fresh_dir("bounds", "unclosed_tables");
    let scene = dir.join("deep.toml");
    let text = format!(
        "name = \"deep\"\n{}",
        "coordinate_system = { [\"X\", \"Y\"]\n".repeat(20_000)
    );
    std::fs::write(&scene, text).expect("scene");
    let out = twin_cmd().arg("check").arg(&scene).output().expect("twin check");
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(65), "{err}");
    assert!(
        err.contains("deep.toml:65:23: tables and arrays nested deeper than 64 levels"),
        "{err}"
    );
    // A tag's value of 24 tables under keys of 60 dots (1,464 levels):
    // the same stack overflow, deserializing the value.
    let key = "a.".repeat(60);
    let value = format!("{}1{}", format!("{{{key}b = ").repeat(24), "}".repeat(24));
    std::fs::write(
        &scene,
        format!("name = \"deep\"\n[[tags]]\nname = \"Z\"\ntype = \"DINT\"\nvalue = {value}\n"),
    )
    .expect("scene");
    let out = twin_cmd().arg("check").arg(&scene).output().expect("twin check");
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(65), "{err}");
    assert!(err.contains("nested deeper than 64 levels"), "{err}");
}

/// A jog at 10³⁰⁷ units/s on an axis whose limits were 10³⁰⁸ reached
/// infinity with exit 0; feed-forward gains of 10³⁰⁰ % held a joint at its
/// URDF limit with 10²⁹⁹ N·m and exit 0. Axis limits, feed-forward gains
/// and torque limits are bounded: each at its bound loads, past it not.
#[test]
fn axis_limits_feedforward_gains_and_torque_limits_are_bounded() {
    use twin::scene::{MAX_AXIS_SPEED, MAX_DRIVE_TORQUE, MAX_FEEDFORWARD_PCT};
    let cases = [
        (
            "speed",
            format!("max_velocity = {MAX_AXIS_SPEED:e}"),
            String::new(),
            true,
        ),
        (
            "speed_past",
            format!("max_velocity = {:e}", MAX_AXIS_SPEED * 1.001),
            String::new(),
            false,
        ),
        (
            "ff",
            String::new(),
            format!("acceleration_feedforward_gain_pct = {MAX_FEEDFORWARD_PCT}"),
            true,
        ),
        (
            "ff_past",
            String::new(),
            "acceleration_feedforward_gain_pct = 1e300".to_owned(),
            false,
        ),
        (
            "torque",
            String::new(),
            format!("torque_limit_positive = {MAX_DRIVE_TORQUE:e}, torque_limit_negative = -{MAX_DRIVE_TORQUE:e}"),
            true,
        ),
        (
            "torque_past",
            String::new(),
            format!("torque_limit_negative = -{:e}", MAX_DRIVE_TORQUE * 1.001),
            false,
        ),
    ];
    for (name, axis, drive, ok) in cases {
        let scene = arm(&format!("limits_{name}"), "", "", &drive);
        if !axis.is_empty() {
            let text = std::fs::read_to_string(&scene)
                .expect("scene")
                .replace("max_velocity = 180.0", &axis);
            std::fs::write(&scene, text).expect("scene");
        }
        let field = if axis.is_empty() {
            "axes[0].drive."
        } else {
            "axes[0].max_velocity"
        };
        loads_or_names(&scene, ok, &[field]);
    }
}

/// Runs `twin` with `args` under a 2 GB address-space limit (`ulimit -v`),
/// killed after 20 s of wall time: its exit code, or `None` if it was
/// killed or died on a signal.
fn twin_in_2_gb(args: &[&std::ffi::OsStr]) -> (Option<i32>, String) {
    let mut cmd = Command::new("bash");
    cmd.arg("-c")
        .arg("ulimit -v 2000000 && exec \"$0\" \"$@\"")
        .arg(env!("CARGO_BIN_EXE_twin"))
        .args(args)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped());
    let mut child = cmd.spawn().expect("bash");
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(20);
    loop {
        if let Some(status) = child.try_wait().expect("wait") {
            let mut err = String::new();
            if let Some(mut e) = child.stderr.take() {
                let _ = std::io::Read::read_to_string(&mut e, &mut err);
            }
            return (status.code(), err);
        }
        if std::time::Instant::now() > deadline {
            let _ = child.kill();
            let _ = child.wait();
            return (None, "killed after 20 s".to_owned());
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
}

/// The acceptance run of issue 39: one generated input of each budget's
/// surface through `twin run`, under `ulimit -v 2000000`, ends with a
/// clean exit code (0, 2–5 or 65) within 20 s: nothing aborts or hangs.
#[test]
fn every_budget_surface_ends_cleanly_in_2_gb_and_20_s() {
    let os = |s: &Path| s.as_os_str().to_owned();
    let mut cases: Vec<(&str, std::ffi::OsString)> = Vec::new();
    // A runaway drive (exit 5).
    cases.push((
        "runaway",
        os(&arm(
            "gb_runaway",
            "",
            "",
            "system_inertia = 4000.0, torque_limit_positive = 1e7, torque_limit_negative = -1e7",
        )),
    ));
    // A collision mesh of 1e30 m.
    cases.push((
        "mesh",
        os(&collision_mesh_arm("gb_mesh", &common::tetrahedron(1e30), "")),
    ));
    // An inertia of 1e20 on the forearm.
    let heavy = arm("gb_inertia", "", "", "");
    let urdf = heavy.with_file_name("arm.urdf");
    let text = std::fs::read_to_string(&urdf).expect("urdf").replace(
        "ixx=\"0.01\" iyy=\"0.05\" izz=\"0.05\"",
        "ixx=\"1e20\" iyy=\"1e20\" izz=\"1e20\"",
    );
    std::fs::write(&urdf, text).expect("urdf");
    cases.push(("inertia", os(&heavy)));
    // A chain of 3,000 links.
    let chain = arm("gb_chain", "", "", "");
    let mut links = String::from(
        "<robot name=\"arm\">\n<link name=\"base\"/>\n<link name=\"forearm\"/>\n<joint name=\"j1\" type=\"revolute\"><parent link=\"base\"/><child link=\"forearm\"/><axis xyz=\"0 1 0\"/><limit lower=\"-3\" upper=\"3\" effort=\"200\" velocity=\"5\"/></joint>\n",
    );
    for i in 0..3000 {
        let parent = if i == 0 {
            "forearm".to_owned()
        } else {
            format!("c{}", i - 1)
        };
        links.push_str(&format!("<link name=\"c{i}\"/><joint name=\"cj{i}\" type=\"fixed\"><parent link=\"{parent}\"/><child link=\"c{i}\"/></joint>\n"));
    }
    std::fs::write(chain.with_file_name("arm.urdf"), links + "</robot>\n").expect("urdf");
    cases.push(("chain", os(&chain)));
    // Forty timer arrays of a million, and FLL of i64::MAX elements.
    for (name, tag_type, routine) in [
        ("gb_tags", "FBD_TIMER[1000000]", "N := N + 1;"),
        ("gb_fll", "DINT[4]", "FLL(0, T0[1], 9223372036854775807);"),
    ] {
        let dir = common::fresh_dir("bounds", name);
        std::fs::write(dir.join("Main.st"), routine).expect("routine");
        let urdf = common::root().join("twin/tests/fixtures/robots/indexing_table.urdf");
        let count = if name == "gb_tags" { 40 } else { 1 };
        let mut s = format!(
            "name = \"x\"\nduration_s = 0.2\ncoarse_update_ms = 4.0\nphysics_step_ms = 1.0\n[robot]\nurdf = {urdf:?}\n[[tags]]\nname = \"N\"\ntype = \"DINT\"\n"
        );
        for i in 0..count {
            s.push_str(&format!("[[tags]]\nname = \"T{i}\"\ntype = \"{tag_type}\"\n"));
        }
        s.push_str("[[tasks]]\nname = \"Main\"\nperiod_ms = 4.0\npriority = 5\n[[tasks.programs]]\nname = \"P\"\nmain = \"Main.st\"\n");
        std::fs::write(dir.join("x.toml"), s).expect("scene");
        cases.push((if name == "gb_tags" { "tags" } else { "fll" }, os(&dir.join("x.toml"))));
    }
    for (what, scene) in &cases {
        let (code, err) = twin_in_2_gb(&[std::ffi::OsStr::new("run"), scene, std::ffi::OsStr::new("--no-render")]);
        assert!(matches!(code, Some(0 | 2..=5 | 65)), "{what}: exit {code:?}: {err}");
    }
    // A device as the scene file is no input at all (sysexits' 66).
    let (code, err) = twin_in_2_gb(&[std::ffi::OsStr::new("check"), std::ffi::OsStr::new("/dev/zero")]);
    assert_eq!(code, Some(66), "/dev/zero: {err}");
}
