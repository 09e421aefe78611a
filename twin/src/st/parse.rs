//! The parser of Structured Text (recursive descent): routines, the single
//! calls of `[[program]]` steps (a one-statement routine) and the
//! expressions a scene holds, with the Logix operator precedence, highest
//! first:
//!
//! | level | operators |
//! |---|---|
//! | 1 | `( )`, function calls |
//! | 2 | `**` (left to right; its right side may carry a sign) |
//! | 3 | unary `-`, `NOT` |
//! | 4 | `*` `/` `MOD` |
//! | 5 | `+` `-` |
//! | 6 | `<` `<=` `>` `>=` |
//! | 7 | `=` `<>` |
//! | 8 | `&` `AND` |
//! | 9 | `XOR` |
//! | 10 | `OR` |
//!
//! Operators of one level group left to right. Keywords and identifiers
//! are case-insensitive; keywords cannot name tags. `==` and `!=` are
//! refused with the Structured Text spelling (`=`, `<>`).
//!
//! A call's arguments are all positional (Logix instructions, in the
//! manual's faceplate order) or all named (`Input := value`, PLCopen
//! function blocks); an input named twice is refused. A space between a
//! call's name and `(` is allowed (`MCT (a, b)`, as the MCT manual prints
//! it). An `IF`, `CASE`, `FOR`, `WHILE` or `REPEAT` whose end keyword is
//! missing is reported at its opening keyword.
//!
//! The lexer and parser are written here rather than taken from a parser
//! library: the dialect's one irregular corner, enumeration words such as
//! `s-curve` or `%ofTime` that are only words where an instruction operand
//! takes them, is decided by the operand, after parsing (each call
//! argument keeps its text), which a grammar-driven library would have to
//! special-case as well, and the whole fits in two short files.

use super::ast::{Access, Arg, BinaryOp, Call, CaseLabel, Expr, ExprKind, Ref, Routine, Stmt, StmtKind, UnaryOp};
use super::lex::{Tok, Token, lex};
use crate::source::{Diagnostic, Source, Span};

/// Words that cannot name a tag.
pub const KEYWORDS: [&str; 26] = [
    "IF",
    "THEN",
    "ELSIF",
    "ELSE",
    "END_IF",
    "CASE",
    "OF",
    "END_CASE",
    "FOR",
    "TO",
    "BY",
    "DO",
    "END_FOR",
    "WHILE",
    "END_WHILE",
    "REPEAT",
    "UNTIL",
    "END_REPEAT",
    "EXIT",
    "MOD",
    "AND",
    "OR",
    "XOR",
    "NOT",
    "TRUE",
    "FALSE",
];

/// The keywords that end a block: a statement list stops at them.
const CLOSERS: [&str; 8] = [
    "ELSIF",
    "ELSE",
    "END_IF",
    "END_CASE",
    "END_FOR",
    "END_WHILE",
    "UNTIL",
    "END_REPEAT",
];

/// The keywords a statement starts with.
const STATEMENT_WORDS: [&str; 6] = ["IF", "CASE", "FOR", "WHILE", "REPEAT", "EXIT"];

fn is_keyword(word: &str) -> bool {
    KEYWORDS.iter().any(|k| k.eq_ignore_ascii_case(word))
}

/// The deepest nesting a routine may have: statements inside statements,
/// parentheses, calls and unary operators together. An operator chain
/// (`a + b - c + …`, any length) is one level: it is held flat. The
/// parser and the compiler recurse per level, so without a bound a
/// mutated or generated routine (`VT(VT(VT(…` a thousand times) would
/// overflow the stack; no hand-written routine comes near it.
pub const MAX_NESTING: usize = 32;

type R<T> = Result<T, Box<Diagnostic>>;

/// Parses a routine.
///
/// # Errors
/// The first syntax error, as a [`Diagnostic`] pointing into the file.
pub fn parse_routine(source: &Source<'_>) -> R<Routine> {
    let mut p = Parser::new(source)?;
    let body = p.statements(&[])?;
    if !p.at_end() {
        return Err(p.stray_closer());
    }
    Ok(Routine { body, rungs: None })
}

/// Parses one instruction call, as a `[[program]]` step writes it:
/// `MAM(Axis1, MC2, 0, 90.0, …)` or `MoveTable(Axis := Table, Execute :=
/// TRUE)`, with an optional trailing `;`.
///
/// # Errors
/// The first syntax error, or text that is not one call.
pub fn parse_call(source: &Source<'_>) -> R<Call> {
    let mut p = Parser::new(source)?;
    let span = p.span(0);
    let call = match (p.tok(0).clone(), p.tok(1)) {
        (Tok::Ident(name), Tok::Sym("(")) if !is_keyword(&name) => {
            p.bump();
            p.call(name.into_owned(), span)?
        }
        _ => return Err(p.unexpected("an instruction call such as MCLM(…) or an instance's Move(Input := …)")),
    };
    if p.is_sym(";") {
        p.bump();
    }
    if !p.at_end() {
        return Err(p.unexpected("the end of the call (only ';' may follow it)"));
    }
    Ok(call)
}

/// Parses one expression (a step's `when`, a traced tag, a scene's
/// expectation).
///
/// # Errors
/// The first syntax error, also when text follows the expression.
pub fn parse_expression(source: &Source<'_>) -> R<Expr> {
    let mut p = Parser::new(source)?;
    let e = p.expr()?;
    if !p.at_end() {
        return Err(p.unexpected("an operator or the end of the expression"));
    }
    Ok(e)
}

/// The deepest branch nesting a rung may have (Studio allows far fewer on
/// screen; the bound keeps a generated rung from exhausting the stack).
pub const MAX_BRANCH_NESTING: usize = 16;

/// Parses a ladder routine: one rung a line, blank lines and `#` lines
/// skipped (the grammar: the `ladder` module).
///
/// # Errors
/// The first syntax error, as a [`Diagnostic`] pointing into the file.
pub fn parse_ladder(source: &Source<'_>) -> R<Routine> {
    let text = source.text;
    let mut tokens: Vec<Token<'_>> = Vec::with_capacity(text.len() / 4 + 1);
    let mut lines: Vec<(usize, usize)> = Vec::new();
    let mut at = 0;
    for line in text.split_inclusive('\n') {
        let start = at;
        at += line.len();
        let body = line.trim();
        if body.is_empty() || body.starts_with('#') {
            continue;
        }
        let lexed = lex(line).map_err(|e| {
            let span = source.span(start + e.start, start + e.end);
            Box::new(Diagnostic::error(e.message).with_label(source.label(span, "")))
        })?;
        let first = tokens.len();
        tokens.extend(lexed.into_iter().filter(|t| t.tok != Tok::Eof).map(|mut t| {
            t.start += start;
            t.end += start;
            t
        }));
        if tokens.len() > first {
            lines.push((first, tokens.len()));
            // The line's end: what an error at the end of the rung points at.
            let eol = start + line.trim_end().len();
            tokens.push(Token {
                tok: Tok::Eof,
                start: eol,
                end: eol,
            });
        }
    }
    tokens.push(Token {
        tok: Tok::Eof,
        start: text.len(),
        end: text.len(),
    });
    let mut p = Parser::from_tokens(source, tokens, true);
    let mut rungs = Vec::with_capacity(lines.len());
    for (number, (first, last)) in lines.into_iter().enumerate() {
        p.at = first;
        p.end = last;
        rungs.push(p.rung(number as u32)?);
    }
    Ok(Routine {
        body: Vec::new(),
        rungs: Some(rungs),
    })
}

struct Parser<'s> {
    source: &'s Source<'s>,
    tokens: Vec<Token<'s>>,
    at: usize,
    /// Tokens from here on read as the end (a call argument being parsed).
    end: usize,
    /// Nesting levels entered now ([`MAX_NESTING`]).
    depth: usize,
    /// Open constructs: the keyword and where it is.
    open: Vec<(&'static str, Span)>,
    /// A rung's operands: an operand that is not an expression (`?`, an
    /// enumeration written with spaces, `Units per sec`) is kept as text.
    ladder: bool,
}

const EOF: Tok<'static> = Tok::Eof;

impl<'s> Parser<'s> {
    fn new(source: &'s Source<'s>) -> R<Parser<'s>> {
        let tokens = lex(source.text).map_err(|e| {
            let span = source.span(e.start, e.end);
            Box::new(Diagnostic::error(e.message).with_label(source.label(span, "")))
        })?;
        Ok(Parser::from_tokens(source, tokens, false))
    }

    /// A parser at the first of `tokens` (the last is the end).
    fn from_tokens(source: &'s Source<'s>, tokens: Vec<Token<'s>>, ladder: bool) -> Parser<'s> {
        let end = tokens.len() - 1;
        Parser {
            source,
            tokens,
            at: 0,
            end,
            depth: 0,
            open: Vec::new(),
            ladder,
        }
    }

    fn error(&self, span: Span, message: impl Into<String>, label: impl Into<String>) -> Box<Diagnostic> {
        Box::new(Diagnostic::error(message).with_label(self.source.label(span, label)))
    }

    /// Enters one nesting level.
    fn enter(&mut self) -> R<()> {
        if self.depth >= MAX_NESTING {
            return Err(self.error(
                self.span(0),
                format!(
                    "nested deeper than {MAX_NESTING} levels (statements, parentheses, calls and unary operators together)"
                ),
                "too deep here",
            ));
        }
        self.depth += 1;
        Ok(())
    }

    fn tok(&self, ahead: usize) -> &Tok<'s> {
        let i = self.at + ahead;
        if i >= self.end { &EOF } else { &self.tokens[i].tok }
    }

    /// The span of the token `ahead` of the current one (the end of the
    /// text past the last).
    fn span(&self, ahead: usize) -> Span {
        let t = &self.tokens[(self.at + ahead).min(self.end)];
        self.source.span(t.start, t.end)
    }

    /// The span from token `from` to the token before the current one.
    fn span_from(&self, from: usize) -> Span {
        let first = &self.tokens[from.min(self.end)];
        let last = &self.tokens[self.at.saturating_sub(1).max(from).min(self.end)];
        self.source.span(first.start, last.end.max(first.start))
    }

    fn at_end(&self) -> bool {
        self.at >= self.end
    }

    fn bump(&mut self) {
        if self.at < self.end {
            self.at += 1;
        }
    }

    fn is_sym(&self, s: &str) -> bool {
        matches!(self.tok(0), Tok::Sym(x) if *x == s)
    }

    fn is_word(&self, w: &str) -> bool {
        matches!(self.tok(0), Tok::Ident(x) if x.eq_ignore_ascii_case(w))
    }

    fn is_closer(&self) -> bool {
        CLOSERS.iter().any(|w| self.is_word(w))
    }

    fn unexpected(&self, expected: &str) -> Box<Diagnostic> {
        self.error(
            self.span(0),
            format!("expected {expected}, found {}", self.tok(0)),
            format!("expected {expected}"),
        )
    }

    fn sym(&mut self, s: &str) -> R<()> {
        if self.is_sym(s) {
            self.bump();
            Ok(())
        } else {
            Err(self.unexpected(&format!("'{s}'")))
        }
    }

    fn word(&mut self, w: &str) -> R<()> {
        if self.is_word(w) {
            self.bump();
            Ok(())
        } else {
            Err(self.unexpected(&format!("'{w}'")))
        }
    }

    /// A closing keyword with nothing open to close: `END_IF` without `IF`.
    fn stray_closer(&self) -> Box<Diagnostic> {
        if let Tok::Ident(w) = self.tok(0) {
            let opener = match w.to_ascii_uppercase().as_str() {
                "ELSIF" | "ELSE" | "END_IF" => "IF",
                "END_CASE" => "CASE",
                "END_FOR" => "FOR",
                "END_WHILE" => "WHILE",
                "UNTIL" | "END_REPEAT" => "REPEAT",
                _ => return self.unexpected("a statement"),
            };
            return self.error(
                self.span(0),
                format!("'{w}' without an open {opener}"),
                format!("no {opener} is open here"),
            );
        }
        self.unexpected("a statement")
    }

    /// Opens a construct at the current keyword.
    fn open(&mut self, keyword: &'static str) {
        let span = self.span(0);
        self.open.push((keyword, span));
        self.bump();
    }

    /// Closes the innermost construct with `closer` (then `;` follows in
    /// the statement), or reports it unclosed at its opening keyword.
    fn close(&mut self, closer: &str) -> R<()> {
        let (keyword, opened) = self.open.pop().unwrap_or(("", self.span(0)));
        if self.is_word(closer) {
            self.bump();
            return Ok(());
        }
        let found = self.tok(0).to_string();
        let d = Diagnostic::error(format!(
            "this {keyword} is never closed: expected {closer}, found {found}"
        ))
        .with_label(self.source.label(opened, format!("{keyword} opened here")));
        // At the end of the text there is nothing more to point at.
        Err(Box::new(if matches!(self.tok(0), Tok::Eof) {
            d.with_help(format!("end the {keyword} with {closer};"))
        } else {
            d.with_label(
                self.source
                    .label(self.span(0), format!("expected {closer} before this")),
            )
            .with_help(format!("end the {keyword} with {closer}; before {found}"))
        }))
    }

    /// Statements up to (not including) one of the `until` keywords, a
    /// closing keyword, a CASE label inside a CASE, or the end.
    fn statements(&mut self, until: &[&str]) -> R<Vec<Stmt>> {
        let mut out = Vec::new();
        loop {
            let done = self.at_end() || until.iter().any(|w| self.is_word(w)) || self.is_closer()
                // A CASE label ends the statements of the arm before it, also
                // those of an IF inside the arm.
                || (self.at_case_label() && self.open.iter().any(|(k, _)| *k == "CASE"));
            if done {
                out.shrink_to_fit();
                return Ok(out);
            }
            out.push(self.statement()?);
        }
    }

    fn statement(&mut self) -> R<Stmt> {
        self.enter()?;
        let statement = self.statement_inner();
        self.depth -= 1;
        statement
    }

    fn statement_inner(&mut self) -> R<Stmt> {
        let span = self.span(0);
        let word = match self.tok(0) {
            Tok::Sym(";") => {
                self.bump();
                return Ok(Stmt {
                    kind: StmtKind::Empty,
                    span,
                });
            }
            Tok::Ident(w) => STATEMENT_WORDS.iter().find(|k| k.eq_ignore_ascii_case(w)).copied(),
            _ => return Err(self.unexpected("a statement")),
        };
        let kind = match word {
            Some(word) => match word {
                "IF" => self.if_statement()?,
                "CASE" => self.case_statement()?,
                "FOR" => self.for_statement()?,
                "WHILE" => {
                    self.open("WHILE");
                    let condition = self.expr()?;
                    self.word("DO")?;
                    let body = self.statements(&["END_WHILE"])?;
                    self.close("END_WHILE")?;
                    StmtKind::While { condition, body }
                }
                "REPEAT" => {
                    self.open("REPEAT");
                    let body = self.statements(&["UNTIL"])?;
                    if !self.is_word("UNTIL") {
                        self.close("UNTIL")?;
                    }
                    self.bump();
                    let until = self.expr()?;
                    self.close("END_REPEAT")?;
                    StmtKind::Repeat { body, until }
                }
                "EXIT" => {
                    self.bump();
                    StmtKind::Exit
                }
                _ => return Err(self.unexpected("a statement")),
            },
            None => match self.tok(0) {
                Tok::Ident(w) if is_keyword(w) => return Err(self.unexpected("a statement")),
                Tok::Ident(w) if matches!(self.tok(1), Tok::Sym("(")) => {
                    let name = w.to_string();
                    self.bump();
                    StmtKind::Call(self.call(name, span)?)
                }
                _ => self.assignment()?,
            },
        };
        self.sym(";")?;
        Ok(Stmt { kind, span })
    }

    fn assignment(&mut self) -> R<StmtKind> {
        let target = self.reference()?;
        let retentive = if self.is_sym("[") {
            self.bump();
            self.sym(":=")?;
            self.sym("]")?;
            false
        } else if self.is_sym(":=") {
            self.bump();
            true
        } else if self.is_sym("=") {
            return Err(self.equals_assignment());
        } else {
            return Err(self.unexpected("':=' or '[:=]'"));
        };
        let value = self.expr()?;
        Ok(StmtKind::Assign {
            target,
            value,
            retentive,
        })
    }

    fn if_statement(&mut self) -> R<StmtKind> {
        self.open("IF");
        let mut branches = Vec::new();
        loop {
            let condition = self.expr()?;
            self.word("THEN")?;
            let body = self.statements(&["ELSIF", "ELSE", "END_IF"])?;
            branches.push((condition, body));
            if self.is_word("ELSIF") {
                self.bump();
            } else {
                break;
            }
        }
        let otherwise = if self.is_word("ELSE") {
            self.bump();
            self.statements(&["END_IF"])?
        } else {
            Vec::new()
        };
        self.close("END_IF")?;
        Ok(StmtKind::If { branches, otherwise })
    }

    fn at_case_label(&self) -> bool {
        matches!(
            (self.tok(0), self.tok(1)),
            (Tok::Int(_), _) | (Tok::Sym("-"), Tok::Int(_))
        )
    }

    fn case_value(&mut self) -> R<i64> {
        let start = self.at;
        let negative = self.is_sym("-");
        if negative {
            self.bump();
        }
        let Tok::Int(v) = *self.tok(0) else {
            return Err(self.unexpected("an integer CASE label"));
        };
        let v = if negative { -v } else { v };
        self.bump();
        i64::try_from(v).map_err(|_| {
            self.error(
                self.span_from(start),
                format!("CASE label {v} is out of range"),
                "beyond 64 bits",
            )
        })
    }

    fn case_statement(&mut self) -> R<StmtKind> {
        self.open("CASE");
        let selector = self.expr()?;
        self.word("OF")?;
        let mut arms = Vec::new();
        while self.at_case_label() {
            let mut labels = Vec::new();
            loop {
                let a = self.case_value()?;
                if self.is_sym("..") {
                    self.bump();
                    labels.push(CaseLabel::Range(a, self.case_value()?));
                } else {
                    labels.push(CaseLabel::Value(a));
                }
                if self.is_sym(",") {
                    self.bump();
                } else {
                    break;
                }
            }
            self.sym(":")?;
            let body = self.statements(&["ELSE", "END_CASE"])?;
            arms.push((labels, body));
        }
        let otherwise = if self.is_word("ELSE") {
            self.bump();
            self.statements(&["END_CASE"])?
        } else {
            Vec::new()
        };
        if !self.is_word("END_CASE") && !self.at_end() && !self.is_closer() {
            return Err(self.unexpected("a CASE label, ELSE or END_CASE"));
        }
        self.close("END_CASE")?;
        Ok(StmtKind::Case {
            selector,
            arms,
            otherwise,
        })
    }

    fn for_statement(&mut self) -> R<StmtKind> {
        self.open("FOR");
        let counter = self.reference()?;
        self.sym(":=")?;
        let from = self.expr()?;
        self.word("TO")?;
        let to = self.expr()?;
        let by = if self.is_word("BY") {
            self.bump();
            Some(self.expr()?)
        } else {
            None
        };
        self.word("DO")?;
        let body = self.statements(&["END_FOR"])?;
        self.close("END_FOR")?;
        Ok(StmtKind::For {
            counter: Box::new(counter),
            from: Box::new(from),
            to: Box::new(to),
            by: by.map(Box::new),
            body,
        })
    }

    /// `NAME` (at `name_span`) has been read; reads `(`, the arguments and
    /// `)`.
    fn call(&mut self, name: String, name_span: Span) -> R<Call> {
        let open = self.at;
        self.sym("(")?;
        let mut args: Vec<Arg> = Vec::new();
        // `()`, or arguments separated by commas up to `)` (after a comma
        // an argument must follow).
        while !self.is_sym(")") || !args.is_empty() {
            let arg_name = match (self.tok(0), self.tok(1)) {
                (Tok::Ident(n), Tok::Sym(":=")) => {
                    let n = n.to_string();
                    let span = self.span(0);
                    self.at += 2;
                    Some((n, span))
                }
                // `Input value` among named inputs: the `:=` is missing.
                (Tok::Ident(_), next)
                    if args.first().is_some_and(|a| a.name.is_some())
                        && !matches!(next, Tok::Sym("," | ")" | ";" | "." | "[") | Tok::Eof) =>
                {
                    return Err(self.missing_assign());
                }
                _ => None,
            };
            // GSV/SSV of a class with one object leave the instance empty:
            // `GSV(WALLCLOCKTIME, , DateTime, Now[0])`.
            let empty_instance = args.len() == 1
                && arg_name.is_none()
                && self.is_sym(",")
                && (name.eq_ignore_ascii_case("GSV") || name.eq_ignore_ascii_case("SSV"));
            if empty_instance {
                let at = self.tokens[self.at].start;
                args.push(Arg {
                    name: None,
                    text: String::new(),
                    expr: None,
                    span: self.source.span(at, at),
                });
                self.bump();
                continue;
            }
            let arg = self.argument(arg_name, open)?;
            self.check_argument(&args, &arg)?;
            args.push(arg);
            if self.is_sym(",") {
                self.bump();
            } else if self.is_sym(")") {
                break;
            } else {
                return Err(self.unexpected("')' or ','"));
            }
        }
        self.bump();
        Ok(Call {
            name,
            name_span,
            args,
            span: name_span.to(self.span_from(open)),
        })
    }

    /// Positional and named arguments do not mix; an input is named once.
    fn check_argument(&self, before: &[Arg], arg: &Arg) -> R<()> {
        let Some(first) = before.first() else {
            return Ok(());
        };
        match (&first.name, &arg.name) {
            (Some(_), None) => Err(Box::new(
                Diagnostic::error("cannot mix positional operands and named inputs in one call")
                    .with_label(self.source.label(arg.span, "an operand without its input's name"))
                    .with_help("name every input of a function block: Input := value"),
            )),
            (None, Some((_, span))) => Err(Box::new(
                Diagnostic::error("cannot mix positional operands and named inputs in one call")
                    .with_label(self.source.label(*span, "a named input after positional operands"))
                    .with_help("a Logix instruction takes its operands in order, without names"),
            )),
            (Some(_), Some((input, span))) => match before
                .iter()
                .filter_map(|a| a.name.as_ref())
                .find(|(n, _)| n.eq_ignore_ascii_case(input))
            {
                Some((_, first)) => Err(Box::new(
                    Diagnostic::error(format!("input '{input}' is given more than once"))
                        .with_label(self.source.label(*span, "given again here"))
                        .with_label(self.source.label(*first, "first given here")),
                )),
                None => Ok(()),
            },
            (None, None) => Ok(()),
        }
    }

    // The errors of a call, built outside the functions that recurse (a
    // debug build gives every local of a function a slot in its frame).

    /// `f(a, b` without its `)`.
    #[cold]
    #[inline(never)]
    fn unclosed_call(&self, open: usize) -> Box<Diagnostic> {
        let found = self.tok(0).to_string();
        Box::new(
            Diagnostic::error(format!(
                "expected ')' or ',', found {found}: the call's '(' is never closed"
            ))
            .with_label(self.source.label(self.span(0), "expected ')' here"))
            .with_label(self.source.label(self.span_at(open), "'(' opened here")),
        )
    }

    /// Two operands side by side (`f(a b)`).
    #[cold]
    #[inline(never)]
    fn missing_comma(&self) -> Box<Diagnostic> {
        let found = self.tok(0).to_string();
        let label = if self.is_sym(";") {
            "write ',' here"
        } else {
            "expected ',' before this"
        };
        Box::new(
            Diagnostic::error(format!("expected ')' or ',', found {found}"))
                .with_label(self.source.label(self.span(0), label))
                .with_help("separate the operands with commas"),
        )
    }

    /// `X = 1;`: an assignment written with the comparison.
    #[cold]
    #[inline(never)]
    fn equals_assignment(&self) -> Box<Diagnostic> {
        Box::new(
            Diagnostic::error("expected ':=' or '[:=]', found '=': '=' compares")
                .with_label(self.source.label(self.span(0), "write ':='"))
                .with_help("assign with ':='"),
        )
    }

    /// `Input value` among named inputs: the `:=` is missing.
    #[cold]
    #[inline(never)]
    fn missing_assign(&self) -> Box<Diagnostic> {
        let (input, found) = (self.tok(0).to_string(), self.tok(1).to_string());
        let input = input.trim_matches('\'');
        Box::new(
            Diagnostic::error(format!("expected ':=' after input '{input}', found {found}"))
                .with_label(self.source.label(self.span(1), "expected ':=' before this"))
                .with_help(format!("name the input and its value: {input} := value")),
        )
    }

    /// One argument: the tokens up to a `,` or `)` outside brackets.
    fn argument(&mut self, name: Option<(String, Span)>, open: usize) -> R<Arg> {
        let start = self.at;
        let mut depth = 0usize;
        let mut stop = start;
        loop {
            let t = if stop >= self.end { &EOF } else { &self.tokens[stop].tok };
            match t {
                Tok::Eof | Tok::Sym(";") => {
                    self.at = stop;
                    // `f(a; b)`: a `;` where a `,` belongs, the `(` closed later.
                    let closed_later = self.tokens[stop..self.end.min(self.tokens.len())]
                        .iter()
                        .any(|t| t.tok == Tok::Sym(")"));
                    if matches!(t, Tok::Sym(";")) && closed_later {
                        return Err(self.missing_comma());
                    }
                    return Err(self.unclosed_call(open));
                }
                Tok::Sym("(" | "[") => depth += 1,
                Tok::Sym(")" | "]") if depth > 0 => depth -= 1,
                Tok::Sym(")" | ",") if depth == 0 => break,
                _ => {}
            }
            stop += 1;
        }
        if stop == start {
            return Err(self.unexpected("an operand"));
        }
        let (first, last) = (&self.tokens[start], &self.tokens[stop - 1]);
        let text = self.source.text[first.start..last.end].to_owned();
        let span = self.source.span(first.start, last.end);
        let outer_end = self.end;
        self.end = stop;
        let expr = match self.expr() {
            Ok(e) if self.at == stop => Some(e),
            // Two operands side by side: a comma is missing between them.
            Ok(_) if !self.ladder && matches!(self.tok(0), Tok::Ident(_) | Tok::Int(_) | Tok::Real(_)) => {
                return Err(self.missing_comma());
            }
            // A rung's operand that is no enumeration word and no `?` is
            // an expression: its error (nesting too deep, say) stands.
            Err(e) if self.ladder && !text.chars().all(|c| c.is_ascii_alphanumeric() || " _%/-.?".contains(c)) => {
                self.end = outer_end;
                return Err(e);
            }
            _ => None,
        };
        self.end = outer_end;
        self.at = stop;
        // A rung writes an enumeration as Studio displays it (`Units per
        // sec`, `% of Time`): without its spaces it is the operand's word.
        let text = if self.ladder && expr.is_none() {
            text.split_whitespace().collect()
        } else {
            text
        };
        Ok(Arg { name, text, expr, span })
    }

    fn span_at(&self, token: usize) -> Span {
        let t = &self.tokens[token.min(self.tokens.len() - 1)];
        self.source.span(t.start, t.end)
    }

    fn reference(&mut self) -> R<Ref> {
        let start = self.at;
        let name = match self.tok(0) {
            Tok::Ident(w) if !is_keyword(w) => w.to_string(),
            _ => return Err(self.unexpected("a tag name")),
        };
        self.bump();
        let mut path = Vec::new();
        loop {
            if self.is_sym(".") {
                self.bump();
                match self.tok(0).clone() {
                    Tok::Ident(m) => {
                        let span = self.span(0);
                        self.bump();
                        path.push(Access::Member(m.into_owned(), span));
                    }
                    Tok::Int(b) => {
                        let bit = u32::try_from(b).map_err(|_| self.unexpected("a bit number"))?;
                        self.bump();
                        path.push(Access::Bit(bit));
                    }
                    Tok::Sym("[") => {
                        self.bump();
                        let e = self.expr()?;
                        self.sym("]")?;
                        path.push(Access::BitExpr(Box::new(e)));
                    }
                    _ => return Err(self.unexpected("a member name or bit number after '.'")),
                }
            } else if self.is_sym("[") && !matches!(self.tok(1), Tok::Sym(":=")) {
                self.bump();
                let mut subscripts = vec![self.expr()?];
                while self.is_sym(",") {
                    self.bump();
                    subscripts.push(self.expr()?);
                }
                self.sym("]")?;
                path.push(Access::Index(subscripts));
            } else {
                return Ok(Ref {
                    name,
                    path,
                    span: self.span_from(start),
                });
            }
        }
    }

    /// An expression (the lowest level, `OR`).
    fn expr(&mut self) -> R<Expr> {
        self.enter()?;
        let e = self.binary(0);
        self.depth -= 1;
        e
    }

    /// The binary operator at the current token and its precedence level
    /// (0 `OR` … 6 `*`, `/`, `MOD`: the Logix table), if one is there.
    fn binary_op(&self) -> R<Option<(BinaryOp, usize)>> {
        let word = |w: &str| self.is_word(w);
        let sym = |s: &str| self.is_sym(s);
        if sym("==") || sym("!=") {
            return Err(self.c_comparison());
        }
        Ok(Some(if word("OR") {
            (BinaryOp::Or, 0)
        } else if word("XOR") {
            (BinaryOp::Xor, 1)
        } else if word("AND") || sym("&") {
            (BinaryOp::And, 2)
        } else if sym("=") {
            (BinaryOp::Eq, 3)
        } else if sym("<>") {
            (BinaryOp::Ne, 3)
        } else if sym("<") {
            (BinaryOp::Lt, 4)
        } else if sym("<=") {
            (BinaryOp::Le, 4)
        } else if sym(">") {
            (BinaryOp::Gt, 4)
        } else if sym(">=") {
            (BinaryOp::Ge, 4)
        } else if sym("+") {
            (BinaryOp::Add, 5)
        } else if sym("-") {
            (BinaryOp::Sub, 5)
        } else if sym("*") {
            (BinaryOp::Mul, 6)
        } else if sym("/") {
            (BinaryOp::Div, 6)
        } else if word("MOD") {
            (BinaryOp::Mod, 6)
        } else {
            return Ok(None);
        }))
    }

    /// `==` or `!=`, which C writes and Structured Text does not.
    #[cold]
    #[inline(never)]
    fn c_comparison(&self) -> Box<Diagnostic> {
        let (c, st) = if self.is_sym("==") { ("==", "=") } else { ("!=", "<>") };
        Box::new(
            Diagnostic::error(format!("'{c}' is not Structured Text: it compares with '{st}'"))
                .with_label(self.source.label(self.span(0), format!("write '{st}'")))
                .with_help(format!("replace '{c}' with '{st}'")),
        )
    }

    /// The operators of level `min` and above, left-associative
    /// (precedence climbing: one frame a level of the table). The
    /// operators of one level that follow each other form one chain
    /// ([`ExprKind::Binary`]), so a sum of any number of terms nests one
    /// level, not one per term.
    fn binary(&mut self, min: usize) -> R<Expr> {
        let mut left = self.unary()?;
        let mut chain: Option<usize> = None;
        while let Some((op, level)) = self.binary_op()? {
            if level < min {
                break;
            }
            self.bump();
            let right = self.binary(level + 1)?;
            let span = left.span.to(right.span);
            left = match (chain == Some(level), left.kind) {
                (true, ExprKind::Binary(first, mut rest)) => {
                    rest.push((op, right));
                    Expr {
                        kind: ExprKind::Binary(first, rest),
                        span,
                    }
                }
                (_, kind) => Expr {
                    kind: ExprKind::Binary(Box::new(Expr { kind, span: left.span }), vec![(op, right)]),
                    span,
                },
            };
            chain = Some(level);
        }
        // A routine holds hundreds of thousands of chains: none keeps room
        // it will not use.
        if let ExprKind::Binary(_, rest) = &mut left.kind {
            rest.shrink_to_fit();
        }
        Ok(left)
    }

    fn unary(&mut self) -> R<Expr> {
        let span = self.span(0);
        let op = if self.is_sym("-") {
            UnaryOp::Neg
        } else if self.is_word("NOT") {
            UnaryOp::Not
        } else {
            return self.power();
        };
        self.bump();
        self.enter()?;
        let operand = self.unary();
        self.depth -= 1;
        let operand = operand?;
        Ok(Expr {
            span: span.to(operand.span),
            kind: ExprKind::Unary(op, Box::new(operand)),
        })
    }

    fn power(&mut self) -> R<Expr> {
        let left = self.primary()?;
        let mut rest = Vec::new();
        while self.is_sym("**") {
            self.bump();
            // A signed primary: `2 ** -1 ** 2` is `(2 ** -1) ** 2`.
            let right = if self.is_sym("-") {
                let span = self.span(0);
                self.bump();
                let operand = self.primary()?;
                Expr {
                    span: span.to(operand.span),
                    kind: ExprKind::Unary(UnaryOp::Neg, Box::new(operand)),
                }
            } else {
                self.primary()?
            };
            rest.push((BinaryOp::Pow, right));
        }
        Ok(match rest.last() {
            None => left,
            Some((_, last)) => Expr {
                span: left.span.to(last.span),
                kind: ExprKind::Binary(Box::new(left), rest),
            },
        })
    }

    fn primary(&mut self) -> R<Expr> {
        let start = self.at;
        let kind = match self.tok(0) {
            Tok::Int(i) => {
                let i = *i;
                self.bump();
                ExprKind::Int(i)
            }
            Tok::Real(x) => {
                let x = *x;
                self.bump();
                ExprKind::Real(x)
            }
            Tok::Sym("(") => {
                self.bump();
                let e = self.expr()?;
                self.sym(")")?;
                return Ok(Expr {
                    kind: e.kind,
                    span: self.span_from(start),
                });
            }
            Tok::Ident(w) if w.eq_ignore_ascii_case("TRUE") || w.eq_ignore_ascii_case("FALSE") => {
                let value = w.eq_ignore_ascii_case("TRUE");
                self.bump();
                ExprKind::Bool(value)
            }
            Tok::Ident(w) if !is_keyword(w) && matches!(self.tok(1), Tok::Sym("(")) => {
                let w = w.to_string();
                let name_span = self.span(0);
                self.at += 2;
                let mut args = Vec::new();
                if !self.is_sym(")") {
                    args.push(self.expr()?);
                    while self.is_sym(",") {
                        self.bump();
                        args.push(self.expr()?);
                    }
                }
                self.sym(")")?;
                ExprKind::Function(w, name_span, args)
            }
            Tok::Ident(w) if !is_keyword(w) => ExprKind::Ref(self.reference()?),
            _ => return Err(self.unexpected("an operand (number, TRUE/FALSE, tag or '(')")),
        };
        Ok(Expr {
            kind,
            span: self.span_from(start),
        })
    }
}

mod ladder;

#[cfg(test)]
mod tests;
