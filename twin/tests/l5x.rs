//! Scenes that name a Studio 5000 export (`[controller] l5x`): the example
//! runs with the program's counts, `twin import` is deterministic and its
//! scene runs byte for byte as the L5X scene does, and malformed exports
//! and bindings get one line at their place.

#[allow(dead_code)] // other suites use the other helpers
mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

use common::{fresh_dir, root};

fn twin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_twin"))
}

fn example() -> (PathBuf, String, String) {
    let dir = root().join("scenes/l5x");
    let scene = std::fs::read_to_string(dir.join("scara_pick.toml")).expect("example scene");
    let export = std::fs::read_to_string(dir.join("scara_pick.L5X")).expect("example export");
    (dir, scene, export)
}

/// The example's scene and export, each with one replacement, written to
/// a folder of their own (the URDF named by its absolute path).
fn variant(name: &str, scene_edit: (&str, &str), l5x_edit: (&str, &str)) -> PathBuf {
    let (_, scene, export) = example();
    let urdf = root().join("scenes/robots/scara/scara.urdf");
    let out = fresh_dir("l5x", name);
    assert!(scene.contains(scene_edit.0), "{:?} not in the scene", scene_edit.0);
    assert!(export.contains(l5x_edit.0), "{:?} not in the export", l5x_edit.0);
    let scene = scene
        .replace(
            "\"../robots/scara/scara.urdf\"",
            &format!("{:?}", urdf.display().to_string()),
        )
        .replacen(scene_edit.0, scene_edit.1, 1);
    let export = export.replacen(l5x_edit.0, l5x_edit.1, 1);
    std::fs::write(out.join("scara_pick.toml"), scene).unwrap();
    std::fs::write(out.join("scara_pick.L5X"), export).unwrap();
    out.join("scara_pick.toml")
}

/// `twin check` of a variant: exit code 65 and the first stderr line.
fn refused(scene: &Path) -> String {
    let out = twin().arg("check").arg(scene).output().expect("twin runs");
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(out.status.code(), Some(65), "{stderr}");
    let first = stderr.lines().next().unwrap_or_default();
    first.strip_prefix("error: ").unwrap_or(first).to_owned()
}

/// The 1-based line of the example export holding the first `needle`
/// after `after`.
fn export_line(after: &str, needle: &str) -> usize {
    let (_, _, export) = example();
    let from = export.find(after).expect("anchor");
    let at = from + export[from..].find(needle).expect("needle");
    export[..at].matches('\n').count() + 1
}

/// 1-based line and column of the first `needle` in `text`.
fn place(text: &str, needle: &str) -> (usize, usize) {
    let at = text
        .find(needle)
        .unwrap_or_else(|| panic!("{needle:?} not in the file"));
    let before = &text[..at];
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    (
        before.matches('\n').count() + 1,
        before[line_start..].chars().count() + 1,
    )
}

/// Asserts a refusal at `needle`'s place in `file` (of the variant's
/// folder), with `words` in the message.
fn refused_at(scene: &Path, file: &str, needle: &str, words: &str) {
    let line = refused(scene);
    let path = scene.with_file_name(file);
    let text = std::fs::read_to_string(&path).unwrap();
    let (l, c) = place(&text, needle);
    let prefix = format!("{}:{l}:{c}: ", path.display());
    assert!(line.starts_with(&prefix), "expected {prefix}…, got {line}");
    assert!(line.contains(words), "expected {words:?} in {line}");
}

#[test]
fn the_example_checks_with_its_report_and_runs_to_the_programs_counts() {
    let scene = root().join("scenes/l5x/scara_pick.toml");
    let out = twin().arg("check").arg(&scene).output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(stdout.contains("L5X "), "{stdout}");
    let decel_jerk = export_line("<Tag Name=\"J1\"", "MaximumDecelerationJerk=");
    assert!(
        stdout.contains(&format!(
            "scara_pick.L5X:{decel_jerk}: axis J1: MaximumDecelerationJerk is not simulated"
        )),
        "{stdout}"
    );

    let dir = fresh_dir("l5x", "example_run");
    let summary = dir.join("summary.json");
    let out = twin()
        .args(["run", "--no-render", "--summary"])
        .arg(&summary)
        .arg(&scene)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    let json: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&summary).unwrap()).unwrap();
    let outcome = |name: &str| {
        json["instructions"]
            .as_array()
            .unwrap()
            .iter()
            .find(|i| i["name"] == name)
            .unwrap_or_else(|| panic!("{name} in {json}"))
            .clone()
    };
    // Two cycles: five linear moves each, one arc each, no errors
    // (`completed` counts `.PC` rises, `done` `.DN` rises).
    assert_eq!(outcome("PickPlace.Move")["completed"], 10, "{json}");
    assert_eq!(outcome("PickPlace.Arc")["completed"], 2, "{json}");
    assert_eq!(outcome("PickPlace.Move")["errors"], 0, "{json}");
    assert_eq!(json["expectations"].as_array().map(Vec::len), Some(3));
    assert!(
        json["expectations"]
            .as_array()
            .unwrap()
            .iter()
            .all(|e| e["passed"] == true),
        "{json}"
    );
    assert!(
        json["l5x"]["not_simulated"].as_array().is_some_and(|a| !a.is_empty()),
        "{json}"
    );
}

#[test]
fn import_is_deterministic_and_its_scene_traces_byte_for_byte_as_the_l5x_scene() {
    let scene = root().join("scenes/l5x/scara_pick.toml");
    let dir = fresh_dir("l5x", "import");
    let (a, b) = (dir.join("a/scene.toml"), dir.join("b/scene.toml"));
    for out in [&a, &b] {
        let o = twin().arg("import").arg(&scene).arg("-o").arg(out).output().unwrap();
        assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    }
    let read = |p: &Path| std::fs::read(p).unwrap();
    assert_eq!(read(&a), read(&b));
    for r in ["PickPlace/Main.st", "PickPlace/ArcVia.st", "Stats/Count.st"] {
        assert_eq!(
            read(&a.with_file_name("routines").join(r)),
            read(&b.with_file_name("routines").join(r)),
            "{r}"
        );
    }
    let text = String::from_utf8(read(&a)).unwrap();
    let j1 = export_line("<Tag Name=\"J1\"", "Name=\"J1\"");
    assert!(
        text.contains(&format!("# scara_pick.L5X:{j1}\n[[axes]]\nname = \"J1\"")),
        "{text}"
    );
    // Both scenes traced.
    let trace = |scene: &Path, name: &str| {
        let t = dir.join(name);
        let o = twin()
            .args(["run", "--no-render", "--trace"])
            .arg(&t)
            .arg(scene)
            .output()
            .unwrap();
        assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
        read(&t)
    };
    assert_eq!(trace(&scene, "l5x.csv"), trace(&a, "imported.csv"));
    // A scene naming no export is a usage error.
    let o = twin()
        .arg("import")
        .arg(&a)
        .arg("-o")
        .arg(dir.join("c.toml"))
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(64), "{}", String::from_utf8_lossy(&o.stderr));
}

#[test]
fn malformed_xml_is_refused_where_the_parser_stopped() {
    let scene = variant("bad_xml", ("", ""), ("<Tag Name=\"Zero\"", "<Tag Name=\"Zero\" <"));
    let line = refused(&scene);
    let (l, _) = place(
        &std::fs::read_to_string(scene.with_file_name("scara_pick.L5X")).unwrap(),
        "<Tag Name=\"Zero\"",
    );
    assert!(line.contains(&format!("scara_pick.L5X:{l}:")), "{line}");
    assert!(line.contains("malformed XML"), "{line}");
}

#[test]
fn a_tag_without_a_data_type_is_refused_at_the_tag() {
    let scene = variant(
        "no_data_type",
        ("", ""),
        (
            "<Tag Name=\"Pick\" TagType=\"Base\" DataType=\"REAL\"",
            "<Tag Name=\"Pick\" TagType=\"Base\"",
        ),
    );
    refused_at(
        &scene,
        "scara_pick.L5X",
        "<Tag Name=\"Pick\"",
        "has no DataType attribute",
    );
}

#[test]
fn a_zero_dimension_is_refused_at_dimensions() {
    let scene = variant(
        "zero_dimension",
        ("", ""),
        (
            "Name=\"Pick\" TagType=\"Base\" DataType=\"REAL\" Dimensions=\"3\"",
            "Name=\"Pick\" TagType=\"Base\" DataType=\"REAL\" Dimensions=\"0\"",
        ),
    );
    refused_at(
        &scene,
        "scara_pick.L5X",
        "0\" Radix=\"Float\" Constant=\"false\"",
        "Pick Dimensions: Dimensions=\"0\"",
    );
}

#[test]
fn an_unknown_system_type_is_refused_listing_the_known_ones() {
    let scene = variant(
        "system_type",
        ("", ""),
        ("SystemType=\"SCARA Independent\"", "SystemType=\"Hexapod\""),
    );
    refused_at(
        &scene,
        "scara_pick.L5X",
        "Hexapod",
        "Joints SystemType: Joints's SystemType \"Hexapod\" is not one the twin simulates: Cartesian, Articulated Dependent",
    );
}

#[test]
fn a_two_to_one_ratio_is_refused() {
    let scene = variant(
        "ratio",
        ("", ""),
        (
            "ConversionRatioNumerator=\"1.0 1.0 1.0\"",
            "ConversionRatioNumerator=\"2.0 1.0 1.0\"",
        ),
    );
    refused_at(
        &scene,
        "scara_pick.L5X",
        "2.0 1.0 1.0",
        "conversion ratio 2.0:1.0: the twin simulates 1:1 ratios only",
    );
}

#[test]
fn an_st_error_is_refused_at_its_character_in_the_cdata_with_its_line_number() {
    let scene = variant(
        "st_error",
        ("", ""),
        ("Slot := Recipe.Count MOD 2;", "Slot := Recipe.Count MOD ;"),
    );
    let line = refused(&scene);
    let path = scene.with_file_name("scara_pick.L5X");
    let export = std::fs::read_to_string(&path).unwrap();
    let (l, c) = place(&export, "MOD ;");
    // The routine line is the Line element's Number.
    let at = export.find("MOD ;").unwrap();
    let open = export[..at].rfind("<Line Number=\"").unwrap() + "<Line Number=\"".len();
    let number = &export[open..open + export[open..].find('"').unwrap()];
    let expected = format!(
        "{}:{l}:{}: PickPlace/Main Line Number=\"{number}\": ",
        path.display(),
        c + 4
    );
    assert!(line.starts_with(&expected), "expected {expected}…, got {line}");
}

#[test]
fn a_dangling_alias_is_refused_at_alias_for() {
    let scene = variant(
        "alias",
        ("", ""),
        ("AliasFor=\"Recipe.Count\"", "AliasFor=\"Recipe.Cuont\""),
    );
    refused_at(
        &scene,
        "scara_pick.L5X",
        "Recipe.Cuont",
        "names member Cuont, which PickRecipe does not have",
    );
    let scene = variant(
        "alias_tag",
        ("", ""),
        ("AliasFor=\"Recipe.Count\"", "AliasFor=\"Recipes.Count\""),
    );
    refused_at(&scene, "scara_pick.L5X", "Recipes.Count", "names no tag of the export");
}

#[test]
fn a_program_export_is_refused_asking_for_the_controller() {
    let scene = variant(
        "program_export",
        ("", ""),
        ("TargetType=\"Controller\"", "TargetType=\"Program\""),
    );
    refused_at(
        &scene,
        "scara_pick.L5X",
        "Program\" ContainsContext",
        "export the controller",
    );
}

#[test]
fn a_joint_the_urdf_lacks_is_refused_at_the_binding() {
    let scene = variant("missing_joint", ("joint = \"j2\"", "joint = \"j9\""), ("", ""));
    refused_at(&scene, "scara_pick.toml", "\"j9\"", "j9");
}

#[test]
fn a_limit_the_export_holds_is_refused_in_the_scene_naming_both_places() {
    let scene = variant(
        "max_velocity",
        (
            "name = \"J1\"\njoint = \"j1\"",
            "name = \"J1\"\njoint = \"j1\"\nmax_velocity = 100.0",
        ),
        ("", ""),
    );
    let export = std::fs::read_to_string(scene.with_file_name("scara_pick.L5X")).unwrap();
    let j1 = export.find("<Tag Name=\"J1\"").unwrap();
    let speed_line = export[..j1 + export[j1..].find("MaximumSpeed=").unwrap()]
        .matches('\n')
        .count()
        + 1;
    refused_at(
        &scene,
        "scara_pick.toml",
        "max_velocity",
        &format!("axes[0].max_velocity: J1's MaximumSpeed comes from scara_pick.L5X:{speed_line}; change it there"),
    );
}

#[test]
fn scene_tasks_and_unknown_bindings_are_refused() {
    let scene = variant(
        "scene_tasks",
        ("[[cameras]]", "[[tasks]]\nname = \"T\"\n\n[[cameras]]"),
        ("", ""),
    );
    refused_at(
        &scene,
        "scara_pick.toml",
        "tasks]]",
        "the export's Tasks are the program",
    );
    let scene = variant("unknown_axis", ("name = \"Z\"", "name = \"W\""), ("", ""));
    refused_at(&scene, "scara_pick.toml", "\"W\"", "no axis 'W' in scara_pick.L5X");
    let scene = variant(
        "bad_value",
        (
            "l5x = \"scara_pick.L5X\"",
            "l5x = \"scara_pick.L5X\"\nvalues = { Nope = 1 }",
        ),
        ("", ""),
    );
    refused_at(&scene, "scara_pick.toml", "1 }", "no tag 'nope'");
}

#[test]
fn a_main_routine_the_twin_does_not_run_is_refused_unless_not_simulated_names_it() {
    let l5x = (
        "<Routine Name=\"Count\" Type=\"ST\">",
        "<Routine Name=\"Count\" Type=\"FBD\">",
    );
    let scene = variant("fbd_main", ("", ""), l5x);
    refused_at(
        &scene,
        "scara_pick.L5X",
        "FBD\">",
        "name \"Stats/Count\" in [controller] not_simulated",
    );
    let scene = variant(
        "fbd_skipped",
        (
            "l5x = \"scara_pick.L5X\"",
            "l5x = \"scara_pick.L5X\"\nnot_simulated = [\"Stats/Count\"]",
        ),
        l5x,
    );
    // The skipped program's tag goes with it.
    let text = std::fs::read_to_string(&scene)
        .unwrap()
        .replace(", \"Stats.Scans\"", "");
    std::fs::write(&scene, text).unwrap();
    let out = twin().arg("check").arg(&scene).output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(stdout.contains("skipped (not_simulated): Stats/Count"), "{stdout}");
}

#[test]
fn a_cip_axis_starts_servo_off_and_its_values_come_from_the_scene_when_given() {
    // `values` over the exported ones: one cycle instead of two.
    let scene = variant(
        "values",
        (
            "l5x = \"scara_pick.L5X\"",
            "l5x = \"scara_pick.L5X\"\nvalues = { Recipe = { Target = 1, DwellMs = 150 } }",
        ),
        ("", ""),
    );
    let text = std::fs::read_to_string(&scene)
        .unwrap()
        .replace("Recipe.Count = 2", "Recipe.Count = 1");
    std::fs::write(&scene, text).unwrap();
    let out = twin()
        .args(["run", "--no-render", "--plant", "kinematic"])
        .arg(&scene)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{stdout}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(stdout.contains("PickPlace.Arc: done 1,"), "{stdout}");
}

#[test]
fn module_io_tags_are_controller_tags_and_a_sensor_on_one_takes_its_rpi() {
    let sensor = "[[sensors]]\nname = \"Guard\"\nkind = \"beam\"\ntag = \"Local:1:I.Data.1\"\nfrom = [0.9, -0.1, 0.1]\nto = [0.9, 0.1, 0.1]\n\n[trace]";
    let scene = variant("module_io", ("[trace]", sensor), ("", ""));
    let out = twin().arg("check").arg(&scene).output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(stdout.contains("Local:1:I: AB_1756_DI_I_0"), "{stdout}");
    assert!(stdout.contains("Local:1:I.Data.1"), "{stdout}");
    let imported = scene.with_file_name("imported.toml");
    let o = twin()
        .arg("import")
        .arg(&scene)
        .arg("-o")
        .arg(&imported)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    let text = std::fs::read_to_string(&imported).unwrap();
    // The connection's RPI (20000 µs) after the sensor's header.
    assert!(text.contains("[[sensors]]\nrpi_ms = 20.0\nname = \"Guard\""), "{text}");
    assert!(
        text.contains("[[aliases]]\nname = \"GuardOpen\"\nalias_for = \"Local:1:I.Data.0\""),
        "{text}"
    );
    // A module alias to a module the export lacks.
    let scene = variant(
        "module_alias",
        ("", ""),
        ("AliasFor=\"Local:1:I.Data.0\"", "AliasFor=\"Local:7:I.Data.0\""),
    );
    refused_at(
        &scene,
        "scara_pick.L5X",
        "Local:7:I.Data.0",
        "names no I/O tag of the export's modules",
    );
}

#[test]
fn a_binding_the_urdf_disagrees_with_is_refused_at_the_binding() {
    let scene = variant(
        "geometry_link",
        (
            "geometry = { base_link = \"mct_base\", tool_link = \"tool\" }",
            "geometry = { base_link = \"mct_base\", tool_link = \"nolink\" }",
        ),
        ("", ""),
    );
    refused_at(
        &scene,
        "scara_pick.toml",
        "geometry = { base_link",
        "URDF has no link 'nolink'",
    );
}

#[test]
fn a_drive_or_coordinate_system_setting_the_export_holds_is_refused_in_the_binding() {
    let scene = variant(
        "drive_tuning",
        (
            "motor = { stiffness = 35530.6, damping = 377.0 }",
            "drive = { position_loop_bandwidth_hz = 50.0 }",
        ),
        ("", ""),
    );
    refused_at(
        &scene,
        "scara_pick.toml",
        "position_loop_bandwidth_hz",
        "axes[0].drive.position_loop_bandwidth_hz: J1's PositionLoopBandwidth comes from scara_pick.L5X:",
    );
    let scene = variant(
        "cs_speed",
        (
            "coordinate_system = { tool_link = \"tool\" }",
            "coordinate_system = { tool_link = \"tool\", max_speed = 2.0 }",
        ),
        ("", ""),
    );
    refused_at(
        &scene,
        "scara_pick.toml",
        "max_speed",
        "tags[0].coordinate_system.max_speed: Cart's MaximumSpeed comes from scara_pick.L5X:",
    );
}

#[test]
fn a_coordinate_system_bound_twice_is_refused() {
    let scene = variant(
        "cs_twice",
        (
            "[[tags]]\nname = \"Joints\"",
            "[[tags]]\nname = \"Cart\"\n\n[[tags]]\nname = \"Joints\"",
        ),
        ("", ""),
    );
    let text = std::fs::read_to_string(&scene).unwrap();
    let second = text
        .match_indices("name = \"Cart\"")
        .nth(1)
        .expect("two Cart bindings")
        .0;
    let line = text[..second].matches('\n').count() + 1;
    let first = refused(&scene);
    assert!(
        first.contains(&format!(
            "scara_pick.toml:{line}:8: tags[1].name: coordinate system 'Cart' is bound twice"
        )),
        "{first}"
    );
}

/// The Stats program's Count routine as ladder: `rungs` are (Type, text).
fn ladder_count(name: &str, rungs: &[(&str, &str)]) -> PathBuf {
    let body: String = rungs
        .iter()
        .enumerate()
        .map(|(k, (ty, text))| {
            format!("<Rung Number=\"{k}\" Type=\"{ty}\">\r\n<Text>\r\n<![CDATA[{text}]]>\r\n</Text>\r\n</Rung>\r\n")
        })
        .collect();
    let st = "<Routine Name=\"Count\" Type=\"ST\">\r\n<STContent>\r\n<Line Number=\"0\">\r\n<![CDATA[// Stats: counts its own scans, in the time the motion task leaves.]]>\r\n</Line>\r\n<Line Number=\"1\">\r\n<![CDATA[Scans := Scans + 1;]]>\r\n</Line>\r\n</STContent>";
    let rll = format!("<Routine Name=\"Count\" Type=\"RLL\">\r\n<RLLContent>\r\n{body}</RLLContent>");
    variant(name, ("", ""), (st, &rll))
}

#[test]
fn an_rll_routine_runs_from_the_export_and_imports_as_an_rll_file() {
    let scene = ladder_count(
        "rll_count",
        &[("N", "ADD(Scans,1,Scans);"), ("N", "GRT(Scans,5)OTE(Big);")],
    );
    // `Big` is not a tag of the export: the error names the rung's CDATA.
    refused_at(
        &scene,
        "scara_pick.L5X",
        "Big)",
        "Stats/Count rung 1: 'Big' is not a tag of this program",
    );
    let scene = ladder_count(
        "rll_count",
        &[("N", "ADD(Scans,1,Scans);"), ("N", "GRT(Scans,5)NOP();")],
    );
    let out = twin().arg("check").arg(&scene).output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(!stdout.contains("RLL routines are not simulated"), "{stdout}");
    let imported = scene.with_file_name("imported/scene.toml");
    let o = twin()
        .arg("import")
        .arg(&scene)
        .arg("-o")
        .arg(&imported)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let rll = std::fs::read_to_string(imported.with_file_name("routines/Stats/Count.rll")).expect("Count.rll");
    assert_eq!(rll, "ADD(Scans,1,Scans);\nGRT(Scans,5)NOP();");
    let run = twin().arg("check").arg(&imported).output().unwrap();
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
}

#[test]
fn a_malformed_rung_names_its_l5x_position_and_rung_and_a_pending_edit_is_refused() {
    let scene = ladder_count(
        "rll_bad",
        &[("N", "ADD(Scans,1,Scans);"), ("N", "XIC(Scans.0)[OTE(Scans.1);")],
    );
    let line = refused(&scene);
    assert!(
        line.contains("this branch is never closed") && line.contains("Stats/Count rung 1"),
        "{line}"
    );
    let text = std::fs::read_to_string(scene.with_file_name("scara_pick.L5X")).unwrap();
    let (l, c) = place(&text, "[OTE(Scans.1)");
    assert!(line.contains(&format!("scara_pick.L5X:{l}:{c}:")), "{line}");
    let scene = ladder_count(
        "rll_edit",
        &[("N", "ADD(Scans,1,Scans);"), ("rR", "NOP();"), ("I", "NOP();")],
    );
    refused_at(
        &scene,
        "scara_pick.L5X",
        "rR\"",
        "Stats/Count rung 1 has an online edit pending (Type=\"rR\"): accept or cancel the edits",
    );
}

/// The SCARA project with its routines in ladder (`scara_pick_ladder`)
/// traces as its Structured Text twin in every column but two kinds:
/// `.EN`, which a FALSE rung clears once `.DN` is set while a Structured
/// Text statement leaves it set; and `Stats.Scans`, the continuous task's
/// scans in the time the motion task leaves, which counts the routines'
/// cost (every rung is scanned at every scan, a CASE runs one state's
/// statements; the two scenes set `statement_us` apart).
#[test]
fn the_ladder_scara_traces_as_its_st_twin_but_for_en_and_the_idle_count() {
    let dir = fresh_dir("l5x", "ladder_twin");
    let trace = |scene: &str| {
        let t = dir.join(format!("{scene}.csv"));
        let o = twin()
            .args(["run", "--no-render", "--trace"])
            .arg(&t)
            .arg(root().join(format!("scenes/l5x/{scene}.toml")))
            .output()
            .unwrap();
        assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
        let text = std::fs::read_to_string(&t).unwrap();
        let rows: Vec<Vec<String>> = text
            .lines()
            .map(|l| l.split(',').map(str::to_owned).collect())
            .collect();
        rows
    };
    let (st, ladder) = (trace("scara_pick"), trace("scara_pick_ladder"));
    // The ladder trace has the ST trace's columns, then its traced rung.
    assert_eq!(&ladder[0][..st[0].len()], &st[0][..]);
    assert_eq!(&ladder[0][st[0].len()..], ["PickPlace/Main:17"]);
    assert_eq!(st.len(), ladder.len());
    let header = &st[0];
    let col = |name: &str| {
        header
            .iter()
            .position(|h| h == name)
            .unwrap_or_else(|| panic!("{name}"))
    };
    for (k, name) in header.iter().enumerate() {
        if name.ends_with(".EN") || name == "Stats.Scans" {
            continue;
        }
        for (a, b) in st[1..].iter().zip(&ladder[1..]) {
            assert_eq!(a[k], b[k], "{name} at t = {} s", a[0]);
        }
    }
    // The traced rung is TRUE in the scans that count a part (Placed
    // rises there).
    let (rung, placed) = (st[0].len(), col("Placed"));
    let rises: Vec<&str> = ladder[1..]
        .windows(2)
        .filter(|w| w[0][placed] != w[1][placed])
        .map(|w| w[1][rung].as_str())
        .collect();
    assert_eq!(rises, ["1", "1"], "two parts, each counted by rung 17");
    // Where .EN differs: MSO executed at the first scan; the next scan its
    // rung is FALSE (State moved on) and .DN is set, so ladder clears .EN.
    let en = col("PickPlace.Servo[0].EN");
    let last = |rows: &[Vec<String>]| rows.last().unwrap()[en].clone();
    assert_eq!(last(&st), "1", "ST: MSO's .EN stays set");
    assert_eq!(last(&ladder), "0", "ladder: the FALSE rung cleared it");
    let placed = col("Recipe.Done");
    assert_eq!(ladder.last().unwrap()[placed], "1");
}

/// The project's Add-On Instruction: Stats counts its scans through one
/// (an InOut DINT), the export's instance tag of the instruction's type.
fn with_aoi(name: &str, call: &str) -> PathBuf {
    let aoi = "<AddOnInstructionDefinitions>\r\n<AddOnInstructionDefinition Name=\"Tally\" Revision=\"1.0\" ExecutePrescan=\"false\" ExecutePostscan=\"false\" ExecuteEnableInFalse=\"false\">\r\n<Parameters>\r\n<Parameter Name=\"EnableIn\" TagType=\"Base\" DataType=\"BOOL\" Usage=\"Input\" Required=\"false\" Visible=\"false\"/>\r\n<Parameter Name=\"EnableOut\" TagType=\"Base\" DataType=\"BOOL\" Usage=\"Output\" Required=\"false\" Visible=\"false\"/>\r\n<Parameter Name=\"Count\" TagType=\"Base\" DataType=\"DINT\" Usage=\"InOut\" Required=\"true\" Visible=\"true\" Constant=\"false\"/>\r\n</Parameters>\r\n<Routines>\r\n<Routine Name=\"Logic\" Type=\"RLL\">\r\n<RLLContent>\r\n<Rung Number=\"0\" Type=\"N\">\r\n<Text>\r\n<![CDATA[ADD(Count,1,Count);]]>\r\n</Text>\r\n</Rung>\r\n</RLLContent>\r\n</Routine>\r\n</Routines>\r\n</AddOnInstructionDefinition>\r\n</AddOnInstructionDefinitions>\r\n";
    let scene = variant(name, ("", ""), ("<AddOnInstructionDefinitions/>\r\n", aoi));
    let l5x = scene.with_file_name("scara_pick.L5X");
    let text = std::fs::read_to_string(&l5x).unwrap();
    let tag = "<Tag Name=\"T1\" TagType=\"Base\" DataType=\"Tally\" ExternalAccess=\"Read/Write\"/>\r\n";
    let text = text
        .replacen(
            "<Program Name=\"Stats\" TestEdits=\"false\" MainRoutineName=\"Count\" Disabled=\"false\" UseAsFolder=\"false\">\r\n<Tags>\r\n",
            &format!("<Program Name=\"Stats\" TestEdits=\"false\" MainRoutineName=\"Count\" Disabled=\"false\" UseAsFolder=\"false\">\r\n<Tags>\r\n{tag}"),
            1,
        )
        .replacen("Scans := Scans + 1;", call, 1);
    std::fs::write(&l5x, text).unwrap();
    scene
}

#[test]
fn a_projects_add_on_instructions_run_and_import_as_exports_of_their_own() {
    let scene = with_aoi("aoi_project", "Tally(T1, Scans);");
    let out = twin().arg("check").arg(&scene).output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(
        !stdout.contains("Add-On Instruction Tally"),
        "no longer reported: {stdout}"
    );
    assert!(stdout.contains("1 Add-On Instruction call(s): Tally ×1"), "{stdout}");
    let imported = scene.with_file_name("imported/scene.toml");
    let o = twin()
        .arg("import")
        .arg(&scene)
        .arg("-o")
        .arg(&imported)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let said = String::from_utf8_lossy(&o.stdout);
    assert!(
        said.contains("with 3 routines under") && said.contains("and 1 Add-On Instruction exports under"),
        "{said}"
    );
    let aoi = std::fs::read_to_string(imported.with_file_name("aoi/Tally.L5X")).expect("aoi/Tally.L5X");
    assert!(aoi.contains("TargetType=\"AddOnInstructionDefinition\""), "{aoi}");
    assert!(
        aoi.contains("<AddOnInstructionDefinition Use=\"Target\" Name=\"Tally\""),
        "{aoi}"
    );
    let text = std::fs::read_to_string(&imported).unwrap();
    assert!(text.contains("add_on_instructions = [\"aoi/Tally.L5X\"]"), "{text}");
    // The two scenes run alike: Stats counts through the instruction.
    let trace = |scene: &Path, name: &str| {
        let t = scene.with_file_name(name);
        let o = twin()
            .args(["run", "--no-render", "--trace"])
            .arg(&t)
            .arg(scene)
            .output()
            .unwrap();
        assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
        std::fs::read(&t).unwrap()
    };
    let (a, b) = (trace(&scene, "a.csv"), trace(&imported, "b.csv"));
    assert_eq!(a, b);
    let text = String::from_utf8(a).unwrap();
    let header: Vec<&str> = text.lines().next().unwrap().split(',').collect();
    let k = header.iter().position(|h| *h == "Stats.Scans").unwrap();
    let last: f64 = text.lines().last().unwrap().split(',').nth(k).unwrap().parse().unwrap();
    assert!(last > 1000.0, "{last}");
    // An error inside the instruction names the project's line.
    let scene = with_aoi("aoi_missing", "Tally(T1);");
    let line = refused(&scene);
    assert!(
        line.contains("Tally is missing its required parameter(s) Count"),
        "{line}"
    );
}
