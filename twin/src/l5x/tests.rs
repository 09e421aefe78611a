use super::{MAX_XML_DEPTH, read};

fn controller(body: &str) -> String {
    format!(
        "\u{feff}<?xml version=\"1.0\"?>\r\n<RSLogix5000Content TargetType=\"Controller\">\r\n<Controller Name=\"C\">\r\n{body}\r\n</Controller>\r\n</RSLogix5000Content>\r\n"
    )
}

#[test]
fn an_st_routine_keeps_the_file_byte_of_every_character() {
    let text = controller(
        "<Programs><Program Name=\"P\" MainRoutineName=\"Main\"><Routines><Routine Name=\"Main\" Type=\"ST\"><STContent>\r\n<Line Number=\"0\">\r\n<![CDATA[A := 1;]]>\r\n</Line>\r\n<Line Number=\"2\">\r\n<![CDATA[B := A;]]>\r\n</Line>\r\n</STContent></Routine></Routines></Program></Programs>",
    );
    let p = read(&text).unwrap();
    let (st, map) = p.programs[0].routines[0].text.clone().unwrap();
    // A skipped Line Number is an empty line: text line i is Line Number i.
    assert_eq!(&*st, "A := 1;\n\nB := A;");
    assert_eq!(map.len(), st.len() + 1);
    let b = st.find('B').unwrap();
    assert_eq!(&text[map[b] as usize..map[b] as usize + 7], "B := A;");
    assert_eq!(&text[map[0] as usize..map[0] as usize + 7], "A := 1;");
}

#[test]
fn only_a_controller_export_is_read() {
    let e =
        read("<RSLogix5000Content TargetType=\"Routine\"><Controller Name=\"C\"/></RSLogix5000Content>").unwrap_err();
    assert!(e.message.contains("export the controller"), "{}", e.message);
    let e = read("<Project/>").unwrap_err();
    assert!(e.message.contains("not a Studio 5000 export"), "{}", e.message);
    let e = read("<RSLogix5000Content TargetType=\"Controller\"><Controller").unwrap_err();
    assert!(e.message.starts_with("malformed XML"), "{}", e.message);
}

#[test]
fn nesting_past_the_bound_is_refused_at_the_element() {
    let deep = "<X>".repeat(MAX_XML_DEPTH + 5) + &"</X>".repeat(MAX_XML_DEPTH + 5);
    let text = controller(&deep);
    let e = read(&text).unwrap_err();
    assert!(e.message.contains("nested"), "{}", e.message);
    assert_eq!(&text[e.span.start..e.span.start + 3], "<X>");
}

#[test]
fn the_motion_group_is_one_and_unknown_elements_are_skipped() {
    let mg = |n: &str| {
        format!(
            "<Tag Name=\"{n}\" DataType=\"MOTION_GROUP\"><Data Format=\"MotionGroup\"><MotionGroupParameters CoarseUpdatePeriod=\"4000\"/></Data></Tag>"
        )
    };
    let text = controller(&format!("<Mystery/><Tags>{}</Tags>", mg("MG")));
    let p = read(&text).unwrap();
    assert_eq!(
        p.motion_group.unwrap().1.get("CoarseUpdatePeriod").unwrap().value,
        "4000"
    );
    let text = controller(&format!("<Tags>{}{}</Tags>", mg("MG"), mg("MG2")));
    assert!(read(&text).unwrap_err().message.contains("a second motion group, MG2"));
}
