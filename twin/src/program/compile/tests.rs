//! Compile errors of the fixture scene's steps: each points at the name or
//! operand that is wrong, in the scene file, under the step's field.

use crate::program::Program;
use crate::scene;
use crate::source::Diagnostic;
use planner::task::MotionTask;
use std::path::{Path, PathBuf};

fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures")
}

/// The fixture with `from` replaced by `to` (which must occur exactly once).
fn edited(from: &str, to: &str) -> String {
    let text = std::fs::read_to_string(fixtures().join("indexing_table.toml")).expect("fixture readable");
    assert_eq!(text.matches(from).count(), 1, "'{from}' must occur once in the fixture");
    text.replace(from, to)
}

/// The diagnostic binding the program of `text` gives.
fn error_of(text: &str) -> Diagnostic {
    let scene = scene::parse(&fixtures().join("case.toml"), text).expect("the scene loads");
    let mut task = MotionTask::new(scene.coarse_update_s()).expect("planner");
    for a in &scene.axes {
        task.add_axis(a.config.clone(), 0.0).expect("axis");
    }
    match Program::bind(&scene, &mut task) {
        Ok(_) => panic!("the program should not compile"),
        Err(d) => *d,
    }
}

/// Asserts `d` is at the first `needle` of `text`, about `field`, and its
/// first line says where.
fn assert_at(d: &Diagnostic, text: &str, needle: &str, field: &str) {
    let byte = text.find(needle).expect("needle present");
    let before = &text[..byte];
    let line = before.matches('\n').count() + 1;
    let column = before[before.rfind('\n').map_or(0, |i| i + 1)..].chars().count() + 1;
    let path = fixtures().join("case.toml");
    assert_eq!(d.location(), Some((path.as_path(), line, column)), "{d}");
    assert_eq!(d.field.as_deref(), Some(field), "{d}");
    assert!(
        d.to_string()
            .starts_with(&format!("{}:{line}:{column}: {field}: ", path.display())),
        "{d}"
    );
}

#[test]
fn an_unknown_tag_in_a_call_points_at_the_name_and_suggests_the_nearest() {
    let text = edited("Axis := Table, Execute := TRUE", "Axis := Tabel, Execute := TRUE");
    let d = error_of(&text);
    assert_at(&d, &text, "Tabel", "program[0].call");
    assert_eq!(d.message, "Axis 'Tabel' is not an axis of [[axes]]");
    assert_eq!(d.help, ["did you mean 'Table'?"]);
}

#[test]
fn unknown_instances_and_instructions() {
    let text = edited(
        "call = \"MoveTable(Axis := Table, Execute := FALSE);\"",
        "call = \"MoveTabel(Axis := Table);\"",
    );
    let d = error_of(&text);
    assert_at(&d, &text, "MoveTabel", "program[1].call");
    assert_eq!(d.message, "'MoveTabel' is not a controller tag or an axis");
    assert_eq!(d.help, ["did you mean 'MoveTable'?"]);

    let text = edited("MCCP(MC1", "MCCX(MC1");
    let d = error_of(&text);
    assert_at(&d, &text, "MCCX", "program[3].call");
    assert_eq!(d.message, "unknown instruction 'MCCX'");
    assert_eq!(d.help, ["did you mean 'MCCM'?"]);

    let text = edited("Table, Execute := FALSE", "Table, Execute := MC_Sideways");
    let d = error_of(&text);
    assert_at(&d, &text, "MC_Sideways", "program[1].call");
    assert_eq!(d.message, "Execute := MC_Sideways: 'MC_Sideways' is not a tag");
    assert_eq!(d.notes, ["Execute takes TRUE, FALSE or a BOOL tag"]);
}

#[test]
fn calling_a_data_tag_is_an_error() {
    let text = edited(
        "MoveTable(Axis := Table, Execute := FALSE)",
        "Count(Axis := Table, Execute := FALSE)",
    );
    let d = error_of(&text);
    assert_at(&d, &text, "Count(", "program[1].call");
    assert_eq!(
        d.message,
        "'Count' is a DINT tag, not a function-block instance, so it cannot be called with named inputs"
    );
}

#[test]
fn an_unknown_enumeration_word_and_a_constant_index_out_of_bounds() {
    let text = edited("s-curve", "z-curve");
    let d = error_of(&text);
    assert_at(&d, &text, "z-curve", "program[2].call");
    assert_eq!(d.message, "'z-curve' is not a word of Profile and not a tag");
    assert_eq!(d.help, ["did you mean 's-curve'?"]);
    let text = edited("Pos[0], 1", "Pos[2], 1");
    let d = error_of(&text);
    assert_at(&d, &text, "2], 1", "program[2].call");
    assert_eq!(d.message, "index 2 is outside 'Pos' (valid: 0 to 1)");
}

#[test]
fn enumeration_words_belong_to_their_operand() {
    // `%oftime` is a Jerk Units word only; in Accel Units it is unknown.
    let text = edited("50, %ofmaximum, 50", "50, %oftime, 50");
    let d = error_of(&text);
    assert_at(&d, &text, "%oftime, 50", "program[2].call");
    assert_eq!(d.message, "'%oftime' is not a word of Accel Units and not a tag");
    assert_eq!(d.notes.len(), 2);
    assert!(d.notes[0].starts_with("Accel Units takes "), "{:?}", d.notes);
    assert!(d.notes[0].contains("%ofmaximum (1)"), "{:?}", d.notes);
    assert_eq!(d.notes[1], "'%oftime' is a word of Jerk Units of MCCM");
}

#[test]
fn instructions_outside_the_catalogue_are_refused_at_load() {
    let text = edited("MCCP(MC1", "MDAC(MC1");
    let d = error_of(&text);
    assert_at(&d, &text, "MDAC", "program[3].call");
    assert!(
        d.message
            .starts_with("MDAC is a Logix motion instruction the twin does not simulate (it simulates: MCLM, MCCM,"),
        "{d}"
    );
    // Named inputs or not.
    let text = edited("MoveTable(Axis := Table, Execute := FALSE)", "MDO(Axis := Table)");
    let d = error_of(&text);
    assert_at(&d, &text, "MDO(", "program[1].call");
    assert!(
        d.message
            .starts_with("MDO is a Logix motion instruction the twin does not simulate"),
        "{d}"
    );
}

#[test]
fn operand_counts_inputs_and_call_styles_are_checked_at_load() {
    // One operand too many: the error points at it.
    let text = edited("0, 0, 0, 0, 0, 0, 0)\"", "0, 0, 0, 0, 0, 0, 0, s-curve)\"");
    let d = error_of(&text);
    assert_at(&d, &text, "s-curve)", "program[2].call");
    assert!(
        d.message
            .starts_with("MCCM takes 25 operands (Coordinate System, Motion Control,"),
        "{d}"
    );
    assert!(d.message.ends_with(", got 26"), "{d}");
    // One too few: the error points at the last and names what is missing.
    let text = edited(", 0, 0, 0, 0)\"", ", 0, 0)\"");
    let d = error_of(&text);
    assert!(d.message.ends_with(", got 23"), "{d}");
    assert_eq!(d.help, ["add Event Distance, Calculated Data"]);
    // An instance called positionally.
    let text = edited("MoveTable(Axis := Table, Execute := FALSE)", "MoveTable(Table, FALSE)");
    let d = error_of(&text);
    assert_at(&d, &text, "MoveTable(Table", "program[1].call");
    assert!(
        d.message
            .starts_with("'MoveTable' is a MC_MoveModulo tag, not an instruction"),
        "{d}"
    );
    // A Logix instruction with named inputs.
    let text = edited("MoveTable(Axis := Table, Execute := FALSE)", "MAJ(Axis := Table)");
    let d = error_of(&text);
    assert!(
        d.message
            .starts_with("MAJ is a Logix instruction: call it with its operands in order"),
        "{d}"
    );
    assert_eq!(
        d.help,
        [
            "MAJ(Axis, Motion Control, Direction, Speed, Speed Units, Accel Rate, Accel Units, Decel Rate, Decel Units, Profile)"
        ]
    );
    // An input the block does not have, named as written.
    let text = edited("Table, Execute := FALSE", "Table, Speed := 180.0");
    let d = error_of(&text);
    assert_at(&d, &text, "Speed :=", "program[1].call");
    assert!(
        d.message
            .starts_with("MC_MoveModulo has no input 'Speed' (inputs: Axis, Execute,"),
        "{d}"
    );
}

#[test]
fn an_unknown_tag_in_a_when_condition() {
    let text = edited("when = \"MoveTable.Done\"", "when = \"Moved.Done\"");
    let d = error_of(&text);
    assert_at(&d, &text, "Moved.Done", "program[1].when");
    assert_eq!(d.message, "'Moved' is not a controller tag or an axis");
}
