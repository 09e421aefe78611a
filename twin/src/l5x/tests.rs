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

#[test]
fn thousands_of_unclosed_elements_are_refused_before_the_parser_recurses() {
    // 50,000 nested start tags (a comment, a CDATA and a quoted '>' on
    // the way are not tags) on a thread with a small stack: refused at
    // the 65th, without recursion.
    let deep = "<A x=\"a>b\"><!-- <B> --><![CDATA[<C>]]>".repeat(50_000);
    let text = controller(&deep);
    let e = std::thread::Builder::new()
        .stack_size(256 * 1024)
        .spawn(move || read(&text).unwrap_err())
        .unwrap()
        .join()
        .unwrap();
    assert_eq!(e.message, format!("elements nested deeper than {MAX_XML_DEPTH}"));
    // Closed elements, however many, are not deep.
    let wide = controller(&"<A><B/></A>".repeat(10_000));
    assert!(read(&wide).is_ok());
}

#[test]
fn an_rll_routine_is_a_rung_a_line_mapped_into_its_cdata() {
    let text = controller(
        "<Programs><Program Name=\"P\" MainRoutineName=\"Main\"><Routines><Routine Name=\"Main\" Type=\"RLL\"><RLLContent>\r\n<Rung Number=\"0\" Type=\"N\">\r\n<Text>\r\n<![CDATA[XIC(A)OTE(B);]]>\r\n</Text>\r\n</Rung>\r\n<Rung Number=\"1\" Type=\"N\">\r\n<Comment>\r\n<![CDATA[two\r\nlines]]>\r\n</Comment>\r\n<Text>\r\n<![CDATA[XIC(B)\r\nOTE(C);]]>\r\n</Text>\r\n</Rung>\r\n</RLLContent></Routine></Routines></Program></Programs>",
    );
    let p = read(&text).unwrap();
    let (rll, map) = p.programs[0].routines[0].text.clone().unwrap();
    assert_eq!(&*rll, "XIC(A)OTE(B);\nXIC(B)  OTE(C);");
    assert_eq!(map.len(), rll.len() + 1);
    let c = rll.find("OTE(C)").unwrap();
    assert_eq!(&text[map[c] as usize..map[c] as usize + 6], "OTE(C)");
}
