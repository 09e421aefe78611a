use super::*;
use crate::source::Files;

fn files(text: &str) -> (Files, crate::source::FileId) {
    let mut f = Files::default();
    let id = f.add("r.st", text);
    (f, id)
}

fn routine(text: &str) -> R<Routine> {
    let (f, id) = files(text);
    parse_routine(&Source::file(&f, id))
}

fn call(text: &str) -> R<Call> {
    let (f, id) = files(text);
    parse_call(&Source::file(&f, id))
}

fn expression(text: &str) -> R<Expr> {
    let (f, id) = files(text);
    parse_expression(&Source::file(&f, id))
}

/// The tree written back with full parentheses, to check grouping.
fn show(e: &Expr) -> String {
    match &e.kind {
        ExprKind::Int(i) => i.to_string(),
        ExprKind::Real(x) => format!("{x:?}"),
        ExprKind::Bool(b) => b.to_string(),
        ExprKind::Ref(r) => r.name.clone(),
        ExprKind::Unary(UnaryOp::Neg, a) => format!("(-{})", show(a)),
        ExprKind::Unary(UnaryOp::Not, a) => format!("(NOT {})", show(a)),
        ExprKind::Binary(first, rest) => rest.iter().fold(show(first), |left, (op, right)| {
            format!("({left} {} {})", op.symbol(), show(right))
        }),
        ExprKind::Function(f, _, args) => format!("{f}({})", args.iter().map(show).collect::<Vec<_>>().join(",")),
    }
}

fn grouped(text: &str) -> String {
    show(&expression(text).unwrap())
}

/// `line:column` and the message of an error.
fn error(e: &Diagnostic) -> (usize, usize, String) {
    let (_, line, column) = e.location().expect("a place");
    (line, column, e.message.clone())
}

#[test]
fn precedence_follows_the_logix_table() {
    assert_eq!(grouped("1 + 2 * 3"), "(1 + (2 * 3))");
    assert_eq!(grouped("-2 ** 2"), "(-(2 ** 2))");
    assert_eq!(grouped("2 ** 3 ** 2"), "((2 ** 3) ** 2)");
    assert_eq!(grouped("a OR b XOR c AND d"), "(a OR (b XOR (c AND d)))");
    assert_eq!(grouped("a = b & c <> d"), "((a = b) AND (c <> d))");
    assert_eq!(grouped("NOT a = b"), "((NOT a) = b)");
    assert_eq!(grouped("a < b = c > d"), "((a < b) = (c > d))");
    assert_eq!(grouped("7 MOD 2 * 3"), "((7 MOD 2) * 3)");
    assert_eq!(grouped("10 - 4 - 3"), "((10 - 4) - 3)");
    assert_eq!(grouped("ABS(-3) + SIN(x)"), "(ABS((-3)) + SIN(x))");
    assert_eq!(grouped("2 ** -1"), "(2 ** (-1))");
    assert_eq!(grouped("2 ** -1 ** 2"), "((2 ** (-1)) ** 2)");
}

#[test]
fn spans_cover_what_they_name() {
    let (f, id) = files("A.B[1] + ABS(x)");
    let e = parse_expression(&Source::file(&f, id)).unwrap();
    assert_eq!(e.span.range(), 0..15);
    let ExprKind::Binary(a, rest) = &e.kind else { panic!() };
    let [(_, b)] = rest.as_slice() else { panic!() };
    assert_eq!(a.span.range(), 0..6);
    assert_eq!(b.span.range(), 9..15);
    let ExprKind::Ref(r) = &a.kind else { panic!() };
    assert_eq!(r.name_span().range(), 0..1);
}

#[test]
fn statements_of_every_kind() {
    let r = routine(
        "x := 1; y [:=] 2;\n\
         IF a THEN b := 1; ELSIF c THEN b := 2; ELSE b := 3; END_IF;\n\
         CASE s OF 1: t := 1; 2, 3: t := 2; 4..6, -1: t := 3; ELSE t := 0; END_CASE;\n\
         FOR i := 0 TO 10 BY 2 DO IF i > 4 THEN EXIT; END_IF; END_FOR;\n\
         WHILE n < 3 DO n := n + 1; END_WHILE;\n\
         REPEAT n := n - 1; UNTIL n <= 0 END_REPEAT;\n\
         MCLM(CS, MC1, 0, Pos[0], 100, unitspersec, 50, %ofMaximum, 50, unitspersec²);\n\
         Arr[i + 1].3 := TRUE; D.[k] := FALSE; ;",
    )
    .unwrap();
    assert_eq!(r.body.len(), 11);
    let StmtKind::Case { arms, otherwise, .. } = &r.body[3].kind else {
        panic!("CASE")
    };
    assert_eq!(arms[2].0, vec![CaseLabel::Range(4, 6), CaseLabel::Value(-1)]);
    assert_eq!(otherwise.len(), 1);
    let StmtKind::Call(call) = &r.body[7].kind else {
        panic!("call")
    };
    assert_eq!(call.args.len(), 10);
    assert_eq!(call.args[7].text, "%ofMaximum");
    assert!(call.args[7].expr.is_none());
    assert_eq!(call.args[9].text, "unitspersec²");
    assert!(call.args[3].expr.is_some());
    let StmtKind::Assign { retentive, .. } = &r.body[1].kind else {
        panic!("assign")
    };
    assert!(!retentive);
}

#[test]
fn named_arguments_and_words_with_a_dash() {
    let r = routine("Move(Axis := Table, Execute := TRUE); MAJ(A, M, 0, 10, s-curve);").unwrap();
    let StmtKind::Call(c) = &r.body[0].kind else { panic!() };
    assert_eq!(c.args[0].name.as_ref().map(|(n, _)| n.as_str()), Some("Axis"));
    let StmtKind::Call(c) = &r.body[1].kind else { panic!() };
    assert_eq!(c.args[4].text, "s-curve");
}

#[test]
fn a_program_call_is_a_one_statement_routine() {
    let c = call("MCCM(myCS, myMC, 0, Pos[0], 1, Ctr[0], 0, 100, Unitspersec, 50, Unitspersec2, 50, Unitspersec2, Trapezoidal, 100.0, 100.0, %ofTime, 2, CoordinatedMotion, Programmed, 0, 0, None, 0, 0);").unwrap();
    assert_eq!(c.name, "MCCM");
    assert_eq!(c.name_span.range(), 0..4);
    assert_eq!(c.args.len(), 25);
    assert_eq!(c.args[16].text, "%ofTime");
    assert_eq!(call("MCT (a, b, c, d, e)").unwrap().args.len(), 5);
    assert_eq!(call("MSO()").unwrap().args.len(), 0);
    let named = call("MoveTable(Axis := Table, Execute := TRUE, Position := 90.0)").unwrap();
    assert_eq!(
        named.args[2].name.as_ref().map(|(n, s)| (n.as_str(), s.range())),
        Some(("Position", 42..50))
    );
    assert_eq!(named.args[0].span.range(), 18..23);
    let e = call("MAM(Axis1); extra").unwrap_err();
    assert_eq!(error(&e).1, 13);
    let e = call("x := 1;").unwrap_err();
    assert!(e.message.starts_with("expected an instruction call"), "{e}");
}

#[test]
fn arguments_do_not_mix_and_inputs_are_named_once() {
    let e = call("F(A := 1, 2)").unwrap_err();
    assert_eq!(
        error(&e),
        (
            1,
            11,
            "cannot mix positional operands and named inputs in one call".into()
        )
    );
    let e = call("F(1, A := 2)").unwrap_err();
    assert_eq!(error(&e).1, 6);
    let e = call("F(A := 1, a := 2)").unwrap_err();
    assert_eq!(error(&e), (1, 11, "input 'a' is given more than once".into()));
    assert_eq!(e.labels[1].range, 2..3, "the first one");
}

#[test]
fn errors_name_the_place_and_what_was_expected() {
    let e = routine("x := 1;\nIF a THEN\n  y := ;\nEND_IF;").unwrap_err();
    let (line, column, message) = error(&e);
    assert_eq!((line, column), (3, 8));
    assert!(message.starts_with("expected an operand"), "{message}");
    let e = routine("x := 1").unwrap_err();
    assert_eq!(e.message, "expected ';', found the end of the text");
    let e = routine("IF := 2;").unwrap_err();
    assert!(e.message.contains("expected"), "{}", e.message);
    let e = routine("CASE s OF x: END_CASE;").unwrap_err();
    assert!(e.message.contains("CASE label"), "{}", e.message);
    assert!(routine("MCLM(a, b").is_err());
    assert!(routine("f(a,,b);").is_err());
    let e = expression("a == b").unwrap_err();
    assert_eq!(e.message, "'==' is not Structured Text: it compares with '='");
}

#[test]
fn an_unclosed_block_is_reported_at_its_opening_keyword() {
    let e = routine("x := 1;\n  IF a THEN\n  y := 2;\nCASE s OF 1: z := 3; END_CASE;\n").unwrap_err();
    assert_eq!((error(&e).0, error(&e).1), (2, 3), "{e}");
    assert_eq!(
        e.message,
        "this IF is never closed: expected END_IF, found the end of the text"
    );
    assert_eq!(e.labels.len(), 1, "at the end of the text only the IF is pointed at");
    let e = routine("CASE s OF\n1: IF a THEN b := 1;\n2: b := 2;\nEND_CASE;").unwrap_err();
    assert_eq!((error(&e).0, error(&e).1), (2, 4));
    assert!(
        e.message
            .starts_with("this IF is never closed: expected END_IF, found '2'"),
        "{e}"
    );
    assert_eq!(e.labels.len(), 2, "the IF and what came instead of END_IF");
    let e = routine("FOR i := 1 TO 3 DO\n  x := i;\n").unwrap_err();
    assert_eq!((error(&e).0, error(&e).1), (1, 1));
    let e = routine("WHILE a DO x := 1; END_IF;").unwrap_err();
    assert!(e.message.starts_with("this WHILE is never closed"), "{e}");
    let e = routine("x := 1; END_IF;").unwrap_err();
    assert_eq!(e.message, "'END_IF' without an open IF");
    let e = routine("REPEAT x := 1; END_REPEAT;").unwrap_err();
    assert!(
        e.message.starts_with("this REPEAT is never closed: expected UNTIL"),
        "{e}"
    );
    routine("REPEAT x := 1; UNTIL x > 3 END_REPEAT;").unwrap();
}

#[test]
fn a_routine_nested_beyond_the_bound_is_refused_not_a_stack_overflow() {
    // `VT(VT(VT(…` a thousand deep overflowed a test thread's stack.
    let deep_calls = format!("X := {}1{};", "VT(".repeat(1000), ")".repeat(1000));
    let deep_parens = format!("X := {}1{};", "(".repeat(1000), ")".repeat(1000));
    let deep_not = format!("X := {}TRUE;", "NOT ".repeat(1000));
    let deep_ifs = format!("{}X := 1;{}", "IF TRUE THEN ".repeat(1000), " END_IF;".repeat(1000));
    for text in [deep_calls, deep_parens, deep_not, deep_ifs] {
        let outcome = std::thread::Builder::new()
            .stack_size(512 * 1024)
            .spawn(move || routine(&text).map(|_| ()).map_err(|e| e.message.clone()))
            .unwrap()
            .join()
            .unwrap();
        let e = outcome.unwrap_err();
        assert!(e.starts_with("nested deeper than 32 levels"), "{e}");
    }
    // Thirty levels of parentheses are fine.
    routine(&format!("X := {}1{};", "(".repeat(28), ")".repeat(28))).unwrap();
}

#[test]
fn operator_chains_of_any_length_parse_flat_on_a_small_stack() {
    // A sum of 33 terms was refused as nested too deeply; a chain is one
    // level however long (1756-RM003 sets no limit on an expression's terms).
    let chains = [
        format!("X := 1{};", " + 1".repeat(20_000)),
        format!("X := A{};", " - B * C / D".repeat(5_000)),
        format!("X := 2{};", " ** 1".repeat(5_000)),
        format!("X := A < B{};", " OR C AND D".repeat(5_000)),
    ];
    for text in chains {
        let outcome = std::thread::Builder::new()
            .stack_size(256 * 1024)
            .spawn(move || routine(&text).map(|r| r.body.len()).map_err(|e| e.message.clone()))
            .unwrap()
            .join()
            .unwrap();
        assert_eq!(outcome, Ok(1));
    }
    let e = expression("1 + 2 - 3 + 4 * 5 * 6").unwrap();
    let ExprKind::Binary(_, rest) = &e.kind else { panic!() };
    assert_eq!(rest.len(), 3, "one chain of + and -, its last term a chain of *");
}

#[test]
fn seeded_random_texts_never_panic_and_errors_point_inside() {
    use rand::{Rng, SeedableRng};
    let alphabet: Vec<char> = "MCAxis_(),:=;.[]#-+%e0123456789 \u{b2}\u{b3}\u{e9}TRUEfalseIFTHENEND_\n\"'@"
        .chars()
        .collect();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(61131);
    for _ in 0..2000 {
        let len = rng.random_range(0..40);
        let text: String = (0..len)
            .map(|_| alphabet[rng.random_range(0..alphabet.len())])
            .collect();
        for e in [call(&text).err(), routine(&text).err(), expression(&text).err()]
            .into_iter()
            .flatten()
        {
            let l = &e.labels[0];
            assert!(l.range.end <= text.len(), "{text:?}: {e}");
        }
    }
}
