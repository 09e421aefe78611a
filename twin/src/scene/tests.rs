use super::*;
use crate::source::Diagnostic;
use crate::st::ast::{Access, ExprKind};
use rand::{Rng, SeedableRng};
use std::path::PathBuf;

fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures")
}

fn fixture_text() -> String {
    std::fs::read_to_string(fixtures().join("indexing_table.toml")).expect("fixture readable")
}

/// The fixture with `from` replaced by `to` (which must occur exactly once).
fn edited(from: &str, to: &str) -> String {
    let text = fixture_text();
    assert_eq!(text.matches(from).count(), 1, "'{from}' must occur once in the fixture");
    text.replace(from, to)
}

fn error_of(text: &str) -> SceneError {
    match parse(&fixtures().join("case.toml"), text) {
        Ok(_) => panic!("scene should not load"),
        Err(e) => e,
    }
}

/// 1-based line and column of the first occurrence of `needle`.
fn find(text: &str, needle: &str) -> Location {
    let byte = text.find(needle).expect("needle present");
    let before = &text[..byte];
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    Location {
        line: before.matches('\n').count() + 1,
        column: before[line_start..].chars().count() + 1,
    }
}

fn assert_place(e: &SceneError, at: Location, field: &str) {
    assert_eq!(e.location(), Some(at), "{e}");
    assert_eq!(e.field(), Some(field), "{e}");
    let line = e.to_string();
    assert!(line.starts_with(&format!(
        "{}:{}:{}: ",
        fixtures().join("case.toml").display(),
        at.line,
        at.column
    )));
    assert!(!line.contains('\n'), "{line}");
}

#[test]
fn complete_fixture_loads() {
    let scene = load(&fixtures().join("indexing_table.toml")).expect("fixture loads");
    assert_eq!(scene.name, "indexing_table");
    assert_eq!(
        (scene.duration_s, scene.coarse_update_ms, scene.physics_step_ms),
        (8.0, 4.0, 1.0)
    );
    assert_eq!(scene.robot.urdf, fixtures().join("robots/indexing_table.urdf"));
    assert_eq!(scene.axes.len(), 2);
    let table = scene.axis("table").expect("case-insensitive lookup");
    assert_eq!(table.config.modulo_period, Some(360.0));
    assert_eq!(table.motor, MotorGains::default());
    let slide = scene.axis("Slide").expect("Slide");
    assert_eq!((slide.kind, slide.units), (AxisKind::Linear, Units::Mm));
    assert!(
        (slide.initial_position - 100.0).abs() < 1e-9,
        "0.1 m from initial_joints is 100 mm"
    );
    assert!(slide.config.target_position_monitoring);
    assert_eq!(slide.joint_location, find(&fixture_text(), "\"slide_joint\""));
    assert_eq!(scene.cameras[0].width, 640);
    assert!(matches!(
        scene.obstacles[1].shape,
        Shape::Cylinder {
            radius_m: 0.05,
            length_m: 0.8
        }
    ));
    assert!(matches!(
        &scene.obstacles[3].shape,
        Shape::Mesh {
            scale: [0.001, 0.001, 0.001],
            ..
        }
    ));
    assert_eq!(scene.obstacles[2].color, [0.6, 0.6, 0.6, 1.0]);
    assert_eq!(
        scene.tag("CS1").and_then(|t| t.value.clone()),
        Some(TagValue::Axes(vec!["Table".into(), "Slide".into()]))
    );
    assert_eq!(
        scene.tag("Pos").and_then(|t| t.value.clone()),
        Some(TagValue::Array(vec![TagValue::Real(90.0), TagValue::Real(100.0)]))
    );
    let Some(TagValue::CamPoints(cam)) = scene.tag("Cam_1").and_then(|t| t.value.clone()) else {
        panic!("cam points")
    };
    assert_eq!(cam[0].segment_type, SegmentType::Linear);
    assert_eq!(cam[1].segment_type, SegmentType::Cubic);
    assert_eq!(
        scene.tag("MoveTable").map(|t| t.ty.base),
        Some(BaseType::FunctionBlock(FunctionBlock::MoveModulo))
    );
    assert_eq!(scene.program.len(), 4);
    assert_eq!(scene.program[0].trigger, Trigger::At { time_s: 0.0 });
    let Trigger::When { condition, delay_s } = &scene.program[1].trigger else {
        panic!("a when step")
    };
    assert_eq!(*delay_s, 0.5);
    assert!(
        matches!(&condition.kind, ExprKind::Ref(r) if r.name == "MoveTable"
            && matches!(&r.path[..], [Access::Member(m, _)] if m == "Done")),
        "{condition:?}"
    );
    let call = &scene.program[2].call;
    assert_eq!(call.name, "MCCM");
    assert_eq!(call.args.len(), 25);
    assert!(call.args.iter().all(|a| a.name.is_none()), "positional");
    assert_eq!(
        scene.snapshots.as_ref().map(|s| s.frames.clone()),
        Some(vec![0, 12, 30])
    );
}

#[test]
fn name_defaults_to_file_stem() {
    let text = edited("name = \"indexing_table\"\n", "");
    let scene = parse(&fixtures().join("stem_name.toml"), &text).expect("loads");
    assert_eq!(scene.name, "stem_name");
}

#[test]
fn unknown_field_names_table_line_and_column() {
    let text = edited("max_velocity = 720.0", "max_speed = 720.0");
    let e = error_of(&text);
    assert!(matches!(&e, SceneError::Toml { .. }), "{e}");
    assert_place(&e, find(&text, "max_speed"), "axes[0]");
    assert!(e.to_string().contains("'max_speed'"), "{e}");
}

#[test]
fn wrong_type_points_at_the_value() {
    let text = edited("fps = 10.0", "fps = \"fast\"");
    let e = error_of(&text);
    assert!(matches!(&e, SceneError::Toml { .. }), "{e}");
    assert_place(&e, find(&text, "\"fast\""), "cameras[0].fps");
    assert!(
        e.to_string()
            .ends_with("cameras[0].fps: expected a number, found \"fast\""),
        "{e}"
    );
}

#[test]
fn plain_type_messages_name_what_was_expected_and_found() {
    use super::context::plain_type_message as plain;
    for (serde, user) in [
        (
            "invalid type: string \"fast\", expected f64",
            "expected a number, found \"fast\"",
        ),
        (
            "invalid type: integer `1`, expected a boolean",
            "expected true or false, found 1",
        ),
        (
            "invalid type: floating point `1.5`, expected u32",
            "expected an integer, found 1.5",
        ),
        (
            "invalid type: sequence, expected a string",
            "expected a string, found an array",
        ),
        ("invalid type: map, expected f64", "expected a number, found a table"),
    ] {
        assert_eq!(plain(serde).as_deref(), Some(user), "{serde}");
    }
    assert_eq!(plain("unknown field `x`"), None);
}

#[test]
fn missing_required_field_is_an_error() {
    // (`joint` is optional: an axis without one is virtual.)
    let text = edited("kind = \"linear\"\n", "");
    assert!(matches!(error_of(&text), SceneError::Toml { .. }));
}

fn syntax_case(from: &str, to: &str, points_at: &str, field: &str) -> Diagnostic {
    let text = edited(from, to);
    let e = error_of(&text);
    assert_place(&e, find(&text, points_at), field);
    match e {
        SceneError::Syntax(d) => *d,
        other => panic!("expected a syntax error, got {other}"),
    }
}

#[test]
fn missing_assign_maps_into_the_file() {
    let d = syntax_case("Position := 90.0", "Position 90.0", "90.0, Velocity", "program[0].call");
    assert_eq!(d.message, "expected ':=' after input 'Position', found '90.0'");
}

#[test]
fn unterminated_call_points_past_the_text() {
    let d = syntax_case(
        "Execute := FALSE);\"",
        "Execute := FALSE\"",
        "\"\n\n[[program]]\nat_s = 2.0",
        "program[1].call",
    );
    assert!(d.message.contains("the call's '(' is never closed"), "{d}");
    assert_eq!(d.labels.len(), 2, "the end and the '('");
}

#[test]
fn missing_comma_in_positional_call() {
    let d = syntax_case("MCCM(CS1, MC1,", "MCCM(CS1 MC1,", "MC1, 0, Pos", "program[2].call");
    assert_eq!(d.message, "expected ')' or ',', found 'MC1'");
}

#[test]
fn bad_when_condition() {
    let d = syntax_case(
        "when = \"MC1.PC\"",
        "when = \"MC1.\"",
        "\"\ncall = \"MCCP",
        "program[3].when",
    );
    assert!(d.message.starts_with("expected a member name"), "{d}");
}

#[test]
fn mixed_arguments() {
    let d = syntax_case(
        "Axis := Table, Execute := FALSE",
        "Table, Execute := FALSE",
        "Execute := FALSE",
        "program[1].call",
    );
    assert_eq!(d.message, "cannot mix positional operands and named inputs in one call");
}

#[test]
fn missing_urdf_names_path_and_field() {
    let text = edited("robots/indexing_table.urdf", "robots/nope.urdf");
    let e = error_of(&text);
    assert_place(&e, find(&text, "\"robots/nope.urdf\""), "robot.urdf");
    assert!(matches!(e.problem(), Some(Problem::MissingFile { path }) if path.ends_with("robots/nope.urdf")));
}

#[test]
fn missing_mesh_file() {
    let text = edited("meshes/guard.obj", "meshes/none.obj");
    let e = error_of(&text);
    assert_place(&e, find(&text, "\"meshes/none.obj\""), "obstacles[3].file");
}

#[test]
fn fixed_length_arrays_take_exactly_their_length() {
    for (from, to, at) in [
        (
            "size = [0.1, 0.6, 0.4]",
            "size = [0.1, 0.6, 0.4, 9.0]",
            "[0.1, 0.6, 0.4, 9.0]",
        ),
        ("size = [0.1, 0.6, 0.4]", "size = [0.1, 0.6]", "[0.1, 0.6]"),
        (
            "position = [0.6, 0.0, 0.2]",
            "position = [0.6, 0.0, 0.2, \"x\"]",
            "\"x\"]",
        ),
        (
            "position = [1.2, -1.2, 1.0]",
            "position = [1.2, -1.2, 1.0, 0.0]",
            "[1.2, -1.2, 1.0, 0.0]",
        ),
    ] {
        let text = edited(from, to);
        let e = error_of(&text);
        let place = find(&text, at);
        match &e {
            SceneError::Toml { line, column, .. } => assert_eq!((*line, *column), (place.line, place.column), "{e}"),
            other => panic!("{other}"),
        }
        let message = e.to_string();
        assert!(
            message.contains("an array of 3 numbers") || message.contains("expected a number, found \"x\""),
            "{message}"
        );
    }
    // Integers are numbers too.
    parse(
        &fixtures().join("case.toml"),
        &edited("size = [0.1, 0.6, 0.4]", "size = [1, 2, 3]"),
    )
    .expect("integers");
}

#[test]
fn duplicate_axis_name() {
    let text = edited("name = \"Slide\"", "name = \"table\"");
    let e = error_of(&text);
    assert_place(&e, find(&text, "\"table\""), "axes[1].name");
    assert!(matches!(
        e.problem(),
        Some(Problem::DuplicateName { first_line: 12, .. })
    ));
}

#[test]
fn tag_clashing_with_axis() {
    let text = edited("name = \"Count\"", "name = \"Slide\"");
    assert!(matches!(error_of(&text).problem(), Some(Problem::DuplicateName { .. })));
}

#[test]
fn physics_step_must_divide_coarse_update() {
    let text = edited("physics_step_ms = 1.0", "physics_step_ms = 3.0");
    let e = error_of(&text);
    assert_place(&e, find(&text, "3.0"), "physics_step_ms");
    assert!(matches!(e.problem(), Some(Problem::StepNotDivisor { .. })));
    let text = edited("physics_step_ms = 1.0", "physics_step_ms = 0.5");
    assert!(parse(&fixtures().join("case.toml"), &text).is_ok());
    let text = edited("coarse_update_ms = 4.0", "coarse_update_ms = 40.0");
    assert!(matches!(error_of(&text).problem(), Some(Problem::OutOfRange { .. })));
}

#[test]
fn both_triggers() {
    let text = edited("when = \"MoveTable.Done\"", "at_s = 1.0\nwhen = \"MoveTable.Done\"");
    let e = error_of(&text);
    assert_place(&e, find(&text, "\"MoveTable.Done\""), "program[1].when");
    assert!(matches!(e.problem(), Some(Problem::BothTriggers)));
}

#[test]
fn neither_trigger() {
    let text = edited("at_s = 2.0\n", "");
    let e = error_of(&text);
    assert_place(&e, find(&text, "\"MCCM("), "program[2]");
    assert!(matches!(e.problem(), Some(Problem::NoTrigger)));
}

#[test]
fn after_s_needs_when_and_at_s_within_duration() {
    let text = edited("at_s = 2.0\n", "at_s = 2.0\nafter_s = 1.0\n");
    assert!(matches!(error_of(&text).problem(), Some(Problem::AfterWithoutWhen)));
    let text = edited("at_s = 2.0\n", "at_s = 9.0\n");
    assert!(matches!(error_of(&text).problem(), Some(Problem::AfterEnd { .. })));
}

#[test]
fn ranges_are_checked() {
    for (from, to, field) in [
        ("max_jerk = 36000.0", "max_jerk = -1.0", "axes[0].max_jerk"),
        ("max_velocity = 500.0", "max_velocity = nan", "axes[1].max_velocity"),
        ("fps = 10.0", "fps = 0.0", "cameras[0].fps"),
        ("fps = 10.0", "fps = 1000.0", "cameras[0].fps"),
        ("width = 640", "width = 0", "cameras[0].width"),
        ("fov_deg = 45.0", "fov_deg = 180.0", "cameras[0].fov_deg"),
        ("duration_s = 8.0", "duration_s = 0.0", "duration_s"),
        ("radius = 0.1", "radius = -0.1", "obstacles[2].radius"),
        (
            "color = [0.8, 0.8, 0.2, 1.0]",
            "color = [0.8, 0.8, 0.2, 2.0]",
            "obstacles[0].color",
        ),
        ("units = \"mm\"", "units = \"deg\"", "axes[1].units"),
        (
            "initial_position = 0.0",
            "initial_position = 1.0",
            "axes[0].initial_position",
        ),
    ] {
        let e = error_of(&edited(from, to));
        assert!(matches!(e, SceneError::Invalid { .. }), "{to}: {e}");
        assert_eq!(e.field(), Some(field), "{to}: {e}");
    }
}

#[test]
fn shapes_need_their_own_fields() {
    let e = error_of(&edited("radius = 0.05\n", ""));
    assert!(
        matches!(e.problem(), Some(Problem::MissingShapeField { field: "radius", .. })),
        "{e}"
    );
    let e = error_of(&edited("radius = 0.1\n", "radius = 0.1\nsize = [1.0, 1.0, 1.0]\n"));
    assert!(
        matches!(e.problem(), Some(Problem::ExtraShapeField { field: "size", .. })),
        "{e}"
    );
}

#[test]
fn tag_types_and_values_are_checked() {
    let text = edited("type = \"DINT\"", "type = \"DWORD\"");
    let e = error_of(&text);
    assert_place(&e, find(&text, "\"DWORD\""), "tags[5].type");
    assert!(matches!(e.problem(), Some(Problem::UnknownTagType { type_name }) if type_name == "DWORD"));
    for (from, to) in [
        ("type = \"REAL[2]\"\nvalue = [90.0", "type = \"REAL[0]\"\nvalue = [90.0"),
        ("value = 3", "value = 3.5"),
        ("value = 3", "value = 4294967296"),
        ("value = true", "value = 1"),
        ("value = [90.0, 100]", "value = [90.0]"),
        ("value = [\"Table\", \"Slide\"]", "value = [\"Table\", \"Spindle\"]"),
        ("type = \"MC_MoveModulo\"", "type = \"MC_MoveModulo\"\nvalue = 1"),
        ("{ master = 90.0, slave = 10.0 }", "{ master = 0.0, slave = 10.0 }"),
    ] {
        let e = error_of(&edited(from, to));
        assert!(matches!(e, SceneError::Invalid { .. }), "{to}: {e}");
    }
}

#[test]
fn snapshots_need_distinct_frames() {
    let e = error_of(&edited("frames = [0, 12, 30]", "frames = [0, 12, 12]"));
    assert!(matches!(e.problem(), Some(Problem::DuplicateFrame { frame: 12 })));
}

#[test]
fn unreadable_file() {
    let e = load(&fixtures().join("does_not_exist.toml")).expect_err("no file");
    assert!(matches!(e, SceneError::Read { .. }));
    assert_eq!(e.location(), None);
}

#[test]
fn escaped_call_string_still_reports_a_place() {
    let text = edited(
        "call = \"MoveTable(Axis := Table, Execute := FALSE);\"",
        "call = \"MoveTable(Axis := \\u0054able, Execute := FALSE\"",
    );
    let e = error_of(&text);
    assert!(matches!(e, SceneError::Syntax(_)), "{e}");
    assert_eq!(e.location().map(|l| l.line), Some(find(&text, "\\u0054").line));
}

#[test]
fn random_edits_never_panic() {
    let original = fixture_text();
    let alphabet: Vec<char> = "()[],.:=;\"'#\n -%²éabzTRUE0123456789{}".chars().collect();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(0x5ce9e);
    for _ in 0..300 {
        let mut chars: Vec<char> = original.chars().collect();
        for _ in 0..rng.random_range(1..6) {
            let at = rng.random_range(0..chars.len());
            match rng.random_range(0..3) {
                0 => {
                    chars.remove(at);
                }
                1 => chars.insert(at, alphabet[rng.random_range(0..alphabet.len())]),
                _ => chars[at] = alphabet[rng.random_range(0..alphabet.len())],
            }
        }
        let text: String = chars.into_iter().collect();
        if let Err(e) = parse(&fixtures().join("case.toml"), &text) {
            let line = e.to_string();
            assert!(!line.is_empty() && !line.contains('\n'), "{line:?}");
        }
    }
}

#[test]
fn soft_travel_limits_are_checked_at_the_field() {
    // Slide starts at robot.initial_joints.slide_joint = 0.1 m = 100 mm.
    let ok = edited(
        "in_position_window = 0.05\n",
        "in_position_window = 0.05\nsoft_travel_limits = [0.0, 300.0]\n",
    );
    let scene = parse(&fixtures().join("case.toml"), &ok).expect("limits around 100 mm");
    assert_eq!(scene.axes[1].config.soft_travel_limits, Some((0.0, 300.0)));
    assert_eq!(scene.axes[0].config.soft_travel_limits, None);
    for (limits, problem) in [
        ("[300.0, 0.0]", "order"),
        ("[0.0, 0.0]", "order"),
        ("[nan, 300.0]", "finite"),
        ("[0.0, 50.0]", "outside"),
    ] {
        let text = edited(
            "in_position_window = 0.05\n",
            &format!("in_position_window = 0.05\nsoft_travel_limits = {limits}\n"),
        );
        let e = error_of(&text);
        assert_place(&e, find(&text, limits), "axes[1].soft_travel_limits");
        let expected = match problem {
            "order" => matches!(e.problem(), Some(Problem::SoftTravelLimitsOrder { .. })),
            "finite" => matches!(e.problem(), Some(Problem::NotFinite { .. })),
            _ => matches!(
                e.problem(),
                Some(Problem::OutsideSoftTravelLimits { position, .. }) if (*position - 100.0).abs() < 1e-9
            ),
        };
        assert!(expected, "{limits}: {e}");
    }
    let modulo = edited(
        "modulo_tolerance_window = 0.0\n",
        "modulo_tolerance_window = 0.0\nsoft_travel_limits = [-90.0, 90.0]\n",
    );
    let e = error_of(&modulo);
    assert_place(&e, find(&modulo, "[-90.0, 90.0]"), "axes[0].soft_travel_limits");
    assert!(matches!(
        e.problem(),
        Some(Problem::SoftTravelLimitsOnModulo { period }) if *period == 360.0
    ));
}

#[test]
fn soft_overtravel_action_and_checking_are_read_and_a_conflict_is_refused_at_the_field() {
    use planner::servo::FaultAction;
    let scene = parse(&fixtures().join("case.toml"), &fixture_text()).expect("case");
    assert_eq!(scene.axes[1].config.soft_overtravel_action, FaultAction::StopPlanner);
    assert!(scene.axes[1].soft_travel_limit_checking);
    let ok = edited(
        "in_position_window = 0.05\n",
        "in_position_window = 0.05\nsoft_overtravel_action = \"stop_drive\"\nsoft_travel_limit_checking = false\n",
    );
    let scene = parse(&fixtures().join("case.toml"), &ok).expect("action and checking");
    assert_eq!(scene.axes[1].config.soft_overtravel_action, FaultAction::StopDrive);
    assert!(!scene.axes[1].soft_travel_limit_checking);
    let conflict = edited(
        "in_position_window = 0.05\n",
        "in_position_window = 0.05\nsoft_travel_limits = [0.0, 300.0]\nsoft_travel_limit_checking = false\n",
    );
    let e = error_of(&conflict);
    let mut at = find(&conflict, "soft_travel_limit_checking = false");
    at.column += "soft_travel_limit_checking = ".len();
    assert_place(&e, at, "axes[1].soft_travel_limit_checking");
    assert!(matches!(e.problem(), Some(Problem::SoftTravelLimitsUnchecked)), "{e}");
    let word = edited(
        "in_position_window = 0.05\n",
        "in_position_window = 0.05\nsoft_overtravel_action = \"halt\"\n",
    );
    let e = error_of(&word);
    assert_eq!(e.location(), Some(find(&word, "\"halt\"")), "{e}");
    assert!(
        e.to_string().contains("'halt'") && e.to_string().contains("'stop_planner'"),
        "{e}"
    );
}

#[test]
fn the_plant_mode_is_read_and_an_unknown_one_is_refused_at_its_place() {
    use crate::scene::PlantMode;
    let scene = parse(&fixtures().join("case.toml"), &fixture_text()).expect("case");
    assert_eq!(scene.plant, PlantMode::Physics);
    let kinematic = format!("plant = \"kinematic\"\n{}", fixture_text());
    let scene = parse(&fixtures().join("case.toml"), &kinematic).expect("kinematic");
    assert_eq!(scene.plant, PlantMode::Kinematic);
    let bad = format!("plant = \"rigid\"\n{}", fixture_text());
    let e = error_of(&bad);
    assert_eq!(e.location(), Some(find(&bad, "\"rigid\"")), "{e}");
    assert!(e.to_string().contains("'kinematic'"), "{e}");
}

#[test]
fn physics_substeps_default_to_two_and_are_bounded_at_the_field() {
    use crate::scene::{DEFAULT_PHYSICS_SUBSTEPS, MAX_PHYSICS_SUBSTEPS};
    let scene = parse(&fixtures().join("case.toml"), &fixture_text()).expect("case");
    assert_eq!((scene.physics_substeps, DEFAULT_PHYSICS_SUBSTEPS), (2, 2));
    let four = format!("physics_substeps = 4\n{}", fixture_text());
    assert_eq!(
        parse(&fixtures().join("case.toml"), &four)
            .expect("four")
            .physics_substeps,
        4
    );
    for bad in ["0", "17", "-1"] {
        let text = format!("physics_substeps = {bad}\n{}", fixture_text());
        let e = error_of(&text);
        assert_place(&e, find(&text, bad), "physics_substeps");
        assert!(e.to_string().contains(&MAX_PHYSICS_SUBSTEPS.to_string()), "{e}");
    }
}

#[test]
fn homing_fields_are_checked_at_the_field() {
    use planner::homing::HomeMode;
    let ok = edited(
        "in_position_window = 0.05\n",
        "in_position_window = 0.05\nhome_mode = \"passive\"\nhome_position = 25.0\nhome_speed = 10.0\n",
    );
    let scene = parse(&fixtures().join("case.toml"), &ok).expect("homing fields");
    let homing = scene.axes[1].config.homing;
    assert_eq!(
        (homing.mode, homing.position, homing.speed),
        (HomeMode::Passive, 25.0, 10.0)
    );
    assert_eq!(scene.axes[0].config.homing.mode, HomeMode::Active, "the default");

    let text = edited(
        "in_position_window = 0.05\n",
        "in_position_window = 0.05\nhome_sequence = \"switch_marker\"\n",
    );
    let e = error_of(&text);
    assert_place(&e, find(&text, "\"switch_marker\""), "axes[1].home_sequence");
    assert!(e.to_string().contains("not simulated"), "{e}");

    let text = edited(
        "in_position_window = 0.05\n",
        "in_position_window = 0.05\naxis_configuration = \"feedback_only\"\nhome_mode = \"active\"\n",
    );
    let e = error_of(&text);
    assert_place(&e, find(&text, "\"active\""), "axes[1].home_mode");

    let text = edited(
        "in_position_window = 0.05\n",
        "in_position_window = 0.05\nhome_return_speed = -1.0\n",
    );
    assert_place(&error_of(&text), find(&text, "-1.0"), "axes[1].home_return_speed");
}

#[test]
fn drive_fields_are_checked_at_the_field() {
    // Slide has a joint and no motor: a servo drive, with the defaults
    // where `drive` leaves a gain out.
    let ok = edited(
        "in_position_window = 0.05\n",
        "in_position_window = 0.05\ndrive = { velocity_loop_bandwidth_hz = 60.0, torque_limit_positive = 80.0, torque_limit_negative = -70.0 }\n",
    );
    let scene = parse(&fixtures().join("case.toml"), &ok).expect("drive fields");
    let gains = scene.axes[1].servo.expect("a servo drive");
    assert_eq!(gains.velocity_loop_bandwidth_hz, 60.0);
    assert_eq!(
        (gains.torque_limit_positive, gains.torque_limit_negative),
        (Some(80.0), Some(-70.0))
    );
    assert_eq!(
        gains.position_loop_bandwidth_hz,
        ServoGains::default().position_loop_bandwidth_hz
    );
    assert_eq!(scene.axes[0].servo, None, "the platter keeps its spring motor");

    for (drive, field) in [
        ("{ torque_limit_negative = 5.0 }", "torque_limit_negative"),
        ("{ velocity_loop_bandwidth_hz = 0.0 }", "velocity_loop_bandwidth_hz"),
        (
            "{ velocity_integrator_bandwidth_hz = -1.0 }",
            "velocity_integrator_bandwidth_hz",
        ),
        ("{ system_inertia = nan }", "system_inertia"),
    ] {
        let text = edited(
            "in_position_window = 0.05\n",
            &format!("in_position_window = 0.05\ndrive = {drive}\n"),
        );
        let e = error_of(&text);
        assert_eq!(e.field(), Some(format!("axes[1].drive.{field}").as_str()), "{e}");
        assert!(!e.to_string().contains('\n'));
    }
    let text = edited(
        "in_position_window = 0.05\n",
        "in_position_window = 0.05\nmotor = { stiffness = 1.0 }\ndrive = {}\n",
    );
    let e = error_of(&text);
    assert!(e.to_string().contains("not both"), "{e}");
}

#[test]
fn move_options_are_checked_on_the_instance() {
    let with = |options: &str| {
        edited(
            "type = \"MC_MoveModulo\"",
            &format!("type = \"MC_MoveModulo\"\noptions = {options}"),
        )
    };
    let scene = parse(
        &fixtures().join("case.toml"),
        &with("{ IgnorePositionMonitoring = true }"),
    )
    .unwrap();
    let tag = scene.tag("MoveTable").unwrap();
    assert!(tag.move_options.ignore_position_monitoring && !tag.move_options.enable_blending_position);
    let e = error_of(&with("{ EnableBlendingPosition = true }"));
    assert_eq!(e.field(), Some("tags[0].options.EnableBlendingPosition"), "{e}");
    assert!(matches!(e.problem(), Some(Problem::OptionNotSimulated { .. })));
    let e = error_of(&with("{ IgnorePositionMonitoring = 1 }"));
    assert!(e.to_string().contains("case.toml:"), "{e}");
    let e = error_of(&with("{ Blending = true }"));
    assert!(e.to_string().contains("Blending"), "{e}");
    let e = error_of(&edited(
        "type = \"DINT\"",
        "type = \"DINT\"\noptions = { IgnorePositionMonitoring = true }",
    ));
    assert!(matches!(e.problem(), Some(Problem::MoveOptionsOnly)), "{e}");
}

#[test]
fn huge_array_tags_are_refused_before_anything_is_allocated() {
    // CAM[4294967296] used to abort allocating 103 GB; DINT[100000000]
    // took 39 s and 7 GB. Both are refused at the type, at once.
    let fixture = fixture_text();
    let first = fixture.find("type = \"REAL[2]\"").expect("a REAL[2] tag");
    for (ty, max) in [
        ("CAM[4294967296]", 65_535),
        ("CAM_PROFILE[65536]", 65_535),
        ("DINT[100000000]", 1_000_000),
        ("REAL[18446744073709551615]", 1_000_000),
    ] {
        let text = format!(
            "{}type = \"{ty}\"{}",
            &fixture[..first],
            &fixture[first + "type = \"REAL[2]\"".len()..]
        );
        let started = std::time::Instant::now();
        let e = error_of(&text);
        assert!(
            started.elapsed() < std::time::Duration::from_secs(5),
            "{ty}: slow refusal"
        );
        let line = e.to_string();
        assert!(line.contains(&format!("'{ty}' has more than {max} elements")), "{line}");
        assert_eq!(e.location(), Some(find(&text, &format!("\"{ty}\""))), "{line}");
    }
    // The limits themselves are allowed.
    let at_limit = format!(
        "{}type = \"CAM[65535]\"{}",
        &fixture[..first],
        &fixture[first + "type = \"REAL[2]\"".len()..]
    );
    if let Err(e) = parse(&fixtures().join("case.toml"), &at_limit) {
        assert!(!e.to_string().contains("elements ("), "{e}");
    }
}

#[test]
fn a_physics_step_too_short_to_finish_an_update_is_refused() {
    // 4e-12 ms divides the update exactly and used to hang the run.
    for step in ["4e-12", "0.001"] {
        let text = edited("physics_step_ms = 1.0", &format!("physics_step_ms = {step}"));
        let e = error_of(&text);
        assert_place(&e, find(&text, step), "physics_step_ms");
        assert!(e.to_string().contains("must be between 0.01 and"), "{e}");
    }
}

#[test]
fn a_run_longer_than_the_documented_bound_is_refused() {
    let text = edited("duration_s = 8.0", "duration_s = 1e300");
    let e = error_of(&text);
    assert_place(&e, find(&text, "1e300"), "duration_s");
}

#[test]
fn names_that_output_files_are_named_after_stay_inside_their_folder() {
    // A camera named `../../x` or `/abs/path` made `--frames DIR` write
    // outside DIR; the scene's name names snapshots and recordings.
    for (from, bad, field, why) in [
        ("name = \"iso\"", "../../x", "cameras[0].name", "path separator"),
        ("name = \"iso\"", "/abs/path", "cameras[0].name", "path separator"),
        ("name = \"iso\"", "a\\\\b", "cameras[0].name", "path separator"),
        ("name = \"iso\"", "..", "cameras[0].name", "starts with '.'"),
        ("name = \"iso\"", ".hidden", "cameras[0].name", "starts with '.'"),
        ("name = \"iso\"", "tab\\there", "cameras[0].name", "control character"),
        ("name = \"indexing_table\"", "../escape", "name", "path separator"),
    ] {
        let written = format!("name = \"{bad}\"");
        let text = edited(from, &written);
        let e = error_of(&text);
        assert_place(&e, find(&text, &format!("\"{bad}\"")), field);
        assert!(e.to_string().contains(why), "{e}");
    }
    // Spaces and dots inside are fine.
    let text = edited("name = \"iso\"", "name = \"iso view 2.5\"");
    parse(&fixtures().join("case.toml"), &text).expect("a plain name loads");
}

#[test]
fn a_camera_image_beyond_the_texture_limit_is_refused() {
    let text = edited("width = 640", "width = 1000000");
    let e = error_of(&text);
    assert_place(&e, find(&text, "1000000"), "cameras[0].width");
}

#[test]
fn an_obstacle_of_astronomical_size_is_refused() {
    // A box of 1e300 m panicked in parry's EPA during the run.
    let text = edited("size = [0.1, 0.6, 0.4]", "size = [0.1, 0.6, 1e300]");
    let e = error_of(&text);
    assert!(e.to_string().contains("size: must be between -10000 and 10000"), "{e}");
    assert_eq!(e.location(), Some(find(&text, "[0.1, 0.6, 1e300]")), "{e}");
}

#[test]
fn a_scene_that_is_not_utf8_names_the_line_and_column() {
    let dir = std::env::temp_dir().join(format!("twin-scene-utf8-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    let path = dir.join("bad.toml");
    std::fs::write(&path, b"name = \"x\"\nduration_s = 1.0 # caf\xe9\n").expect("write");
    let e = load(&path).expect_err("not UTF-8");
    assert_eq!(e.location(), Some(Location { line: 2, column: 23 }), "{e}");
    assert!(
        e.to_string()
            .ends_with("bad.toml:2:23: not UTF-8 text (a scene is a TOML text file)"),
        "{e}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_modulo_tolerance_window_of_half_the_period_names_its_field() {
    // It used to surface from the planner with no place in the scene.
    let text = edited("modulo_tolerance_window = 0.0", "modulo_tolerance_window = 180.0");
    let e = error_of(&text);
    assert_place(&e, find(&text, "180.0"), "axes[0].modulo_tolerance_window");
}

#[test]
fn a_camera_looking_straight_down_names_its_target() {
    // It used to fail only when frames were rendered, with no place.
    let text = edited("position = [1.2, -1.2, 1.0]", "position = [0.0, 0.0, 3.0]");
    let e = error_of(&text);
    assert_place(&e, find(&text, "[0.0, 0.0, 0.2]"), "cameras[0].target");
    assert!(e.to_string().contains("straight up or down"), "{e}");
}

#[test]
fn a_variant_sets_a_program_tag_written_either_way() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/scara_pallet.toml");
    let shipped = std::fs::read_to_string(&path).expect("scene");
    for key in ["Pallet.Pitch", "\"Pallet.Pitch\""] {
        let text = format!("{shipped}\n[[variants]]\nname = \"wide\"\ntags = {{ {key} = 0.125 }}\n");
        let scene = parse(&path, &text).expect("scene loads");
        let pitch = |s: &Scene| {
            s.tasks
                .iter()
                .flat_map(|t| &t.programs)
                .flat_map(|p| &p.tags)
                .find(|t| t.name == "Pitch")
                .and_then(|t| t.value.clone())
        };
        assert_ne!(pitch(&scene), Some(TagValue::Real(0.125)), "{key}");
        let wide = scene.with_variant("wide").expect("the variant");
        assert_eq!(pitch(&wide), Some(TagValue::Real(0.125)), "{key}");
        assert_eq!(wide.variant.as_deref(), Some("wide"));
        assert!(scene.with_variant("narrow").is_none());
    }
    let text = format!("{shipped}\n[[variants]]\nname = \"x\"\ntags = {{ Pallet.Pich = 0.125 }}\n");
    let e = parse(&path, &text).expect_err("unknown tag");
    assert!(
        e.to_string()
            .contains("variants[0].tags.Pallet.Pich: unknown tag 'Pallet.Pich'"),
        "{e}"
    );
    assert!(
        e.diagnostic().render(false).contains("did you mean 'Pallet.Pitch'?"),
        "{}",
        e.diagnostic().render(false)
    );
}
