//! The parser of Structured Text routines (recursive descent), with the
//! Logix operator precedence, highest first:
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
//! are case-insensitive; keywords cannot name tags.
//!
//! The lexer and parser are written here rather than taken from a parser
//! library: the dialect's one irregular corner, enumeration words such as
//! `s-curve` or `%ofTime` that are only words where an instruction operand
//! takes them, is decided by the operand, after parsing (each call
//! argument keeps its text), which a grammar-driven library would have to
//! special-case as well, and the whole fits in two short files.

use super::ast::{Access, Arg, BinaryOp, Call, CaseLabel, Expr, ExprKind, Ref, Routine, Stmt, StmtKind, UnaryOp};
use super::lex::{LexError, Pos, Tok, Token, lex};
use std::fmt;

/// A syntax error: where and what was expected.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub struct SyntaxError {
    /// Where.
    pub pos: Pos,
    /// What is wrong (`expected …, found …`).
    pub message: String,
}

impl fmt::Display for SyntaxError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

impl From<LexError> for SyntaxError {
    fn from(e: LexError) -> Self {
        SyntaxError {
            pos: e.pos,
            message: e.message,
        }
    }
}

/// Words that cannot name a tag.
pub const KEYWORDS: [&str; 22] = [
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
];

const MORE_KEYWORDS: [&str; 4] = ["XOR", "NOT", "TRUE", "FALSE"];

fn is_keyword(word: &str) -> bool {
    KEYWORDS
        .iter()
        .chain(MORE_KEYWORDS.iter())
        .any(|k| k.eq_ignore_ascii_case(word))
}

/// Parses a routine.
///
/// # Errors
/// The first [`SyntaxError`].
pub fn parse_routine(text: &str) -> Result<Routine, SyntaxError> {
    let mut p = Parser::new(text)?;
    let body = p.statements(&[])?;
    if !p.at_end() {
        return Err(p.unexpected("a statement"));
    }
    Ok(Routine { body })
}

/// Parses one expression (for `[trace] tags` and tests).
///
/// # Errors
/// The first [`SyntaxError`], also when text follows the expression.
pub fn parse_expression(text: &str) -> Result<Expr, SyntaxError> {
    let mut p = Parser::new(text)?;
    let e = p.expr()?;
    if !p.at_end() {
        return Err(p.unexpected("an operator or the end of the expression"));
    }
    Ok(e)
}

/// The deepest nesting a routine may have: statements inside statements,
/// parentheses, calls, unary operators and operator chains together. The
/// parser and the compiler recurse per level, so without a bound a
/// mutated or generated routine (`VT(VT(VT(…` a thousand times) would
/// overflow the stack; no hand-written routine comes near it.
pub const MAX_NESTING: usize = 32;

struct Parser {
    tokens: Vec<Token>,
    chars: Vec<char>,
    at: usize,
    /// Tokens from here on read as the end (a call argument being parsed).
    end: usize,
    /// Nesting levels entered now ([`MAX_NESTING`]).
    depth: usize,
}

const EOF: Tok = Tok::Eof;

impl Parser {
    fn new(text: &str) -> Result<Parser, SyntaxError> {
        let tokens = lex(text)?;
        let end = tokens.len() - 1;
        Ok(Parser {
            tokens,
            chars: text.chars().collect(),
            at: 0,
            end,
            depth: 0,
        })
    }

    /// Enters one nesting level (`extra` more for an operator chain).
    fn enter(&mut self, extra: usize) -> Result<(), SyntaxError> {
        if self.depth + extra >= MAX_NESTING {
            return Err(SyntaxError {
                pos: self.pos(),
                message: format!(
                    "nested deeper than {MAX_NESTING} levels (statements, parentheses, calls and operators together)"
                ),
            });
        }
        self.depth += 1;
        Ok(())
    }

    fn tok(&self, ahead: usize) -> &Tok {
        let i = self.at + ahead;
        if i >= self.end { &EOF } else { &self.tokens[i].tok }
    }

    fn pos(&self) -> Pos {
        self.tokens[self.at.min(self.end)].pos
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

    fn unexpected(&self, expected: &str) -> SyntaxError {
        SyntaxError {
            pos: self.pos(),
            message: format!("expected {expected}, found {}", self.tok(0)),
        }
    }

    fn sym(&mut self, s: &str) -> Result<(), SyntaxError> {
        if self.is_sym(s) {
            self.bump();
            Ok(())
        } else {
            Err(self.unexpected(&format!("'{s}'")))
        }
    }

    fn word(&mut self, w: &str) -> Result<(), SyntaxError> {
        if self.is_word(w) {
            self.bump();
            Ok(())
        } else {
            Err(self.unexpected(&format!("'{w}'")))
        }
    }

    /// Statements up to (not including) one of the `until` keywords, a
    /// CASE label, or the end.
    fn statements(&mut self, until: &[&str]) -> Result<Vec<Stmt>, SyntaxError> {
        let mut out = Vec::new();
        loop {
            if self.at_end() || until.iter().any(|w| self.is_word(w)) {
                return Ok(out);
            }
            if until.contains(&"END_CASE") && self.at_case_label() {
                return Ok(out);
            }
            out.push(self.statement()?);
        }
    }

    fn statement(&mut self) -> Result<Stmt, SyntaxError> {
        self.enter(0)?;
        let statement = self.statement_inner();
        self.depth -= 1;
        statement
    }

    fn statement_inner(&mut self) -> Result<Stmt, SyntaxError> {
        let pos = self.pos();
        let kind = match self.tok(0).clone() {
            Tok::Sym(";") => {
                self.bump();
                return Ok(Stmt {
                    kind: StmtKind::Empty,
                    pos,
                });
            }
            Tok::Ident(w) => match w.to_ascii_uppercase().as_str() {
                "IF" => self.if_statement()?,
                "CASE" => self.case_statement()?,
                "FOR" => self.for_statement()?,
                "WHILE" => {
                    self.bump();
                    let condition = self.expr()?;
                    self.word("DO")?;
                    let body = self.statements(&["END_WHILE"])?;
                    self.word("END_WHILE")?;
                    StmtKind::While { condition, body }
                }
                "REPEAT" => {
                    self.bump();
                    let body = self.statements(&["UNTIL"])?;
                    self.word("UNTIL")?;
                    let until = self.expr()?;
                    self.word("END_REPEAT")?;
                    StmtKind::Repeat { body, until }
                }
                "EXIT" => {
                    self.bump();
                    StmtKind::Exit
                }
                _ if is_keyword(&w) => return Err(self.unexpected("a statement")),
                _ if matches!(self.tok(1), Tok::Sym("(")) => {
                    self.bump();
                    StmtKind::Call(self.call(w, pos)?)
                }
                _ => self.assignment()?,
            },
            _ => return Err(self.unexpected("a statement")),
        };
        self.sym(";")?;
        Ok(Stmt { kind, pos })
    }

    fn assignment(&mut self) -> Result<StmtKind, SyntaxError> {
        let target = self.reference()?;
        let retentive = if self.is_sym("[") {
            self.bump();
            self.sym(":=")?;
            self.sym("]")?;
            false
        } else if self.is_sym(":=") {
            self.bump();
            true
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

    fn if_statement(&mut self) -> Result<StmtKind, SyntaxError> {
        self.bump();
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
        self.word("END_IF")?;
        Ok(StmtKind::If { branches, otherwise })
    }

    fn at_case_label(&self) -> bool {
        matches!(
            (self.tok(0), self.tok(1)),
            (Tok::Int(_), _) | (Tok::Sym("-"), Tok::Int(_))
        )
    }

    fn case_value(&mut self) -> Result<i64, SyntaxError> {
        let negative = self.is_sym("-");
        if negative {
            self.bump();
        }
        let Tok::Int(v) = *self.tok(0) else {
            return Err(self.unexpected("an integer CASE label"));
        };
        let v = if negative { -v } else { v };
        let v = i64::try_from(v).map_err(|_| SyntaxError {
            pos: self.pos(),
            message: format!("CASE label {v} is out of range"),
        })?;
        self.bump();
        Ok(v)
    }

    fn case_statement(&mut self) -> Result<StmtKind, SyntaxError> {
        self.bump();
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
        if !self.is_word("END_CASE") {
            return Err(self.unexpected("a CASE label, ELSE or END_CASE"));
        }
        self.bump();
        Ok(StmtKind::Case {
            selector,
            arms,
            otherwise,
        })
    }

    fn for_statement(&mut self) -> Result<StmtKind, SyntaxError> {
        self.bump();
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
        self.word("END_FOR")?;
        Ok(StmtKind::For {
            counter,
            from,
            to,
            by,
            body,
        })
    }

    /// `NAME(` has been read up to the name; reads the arguments and `)`.
    fn call(&mut self, name: String, pos: Pos) -> Result<Call, SyntaxError> {
        self.sym("(")?;
        let mut args = Vec::new();
        if self.is_sym(")") {
            self.bump();
            return Ok(Call { name, pos, args });
        }
        loop {
            let arg_name = match (self.tok(0), self.tok(1)) {
                (Tok::Ident(n), Tok::Sym(":=")) => {
                    let n = n.clone();
                    self.at += 2;
                    Some(n)
                }
                _ => None,
            };
            args.push(self.argument(arg_name)?);
            if self.is_sym(",") {
                self.bump();
            } else {
                self.sym(")")?;
                return Ok(Call { name, pos, args });
            }
        }
    }

    /// One argument: the tokens up to a `,` or `)` outside brackets.
    fn argument(&mut self, name: Option<String>) -> Result<Arg, SyntaxError> {
        let start = self.at;
        let mut depth = 0usize;
        let mut stop = start;
        loop {
            let t = if stop >= self.end { &EOF } else { &self.tokens[stop].tok };
            match t {
                Tok::Eof => {
                    self.at = stop;
                    return Err(self.unexpected("')'"));
                }
                Tok::Sym("(" | "[") => depth += 1,
                Tok::Sym(")" | "]") if depth > 0 => depth -= 1,
                Tok::Sym(")" | ",") if depth == 0 => break,
                Tok::Sym(";") => {
                    self.at = stop;
                    return Err(self.unexpected("')'"));
                }
                _ => {}
            }
            stop += 1;
        }
        if stop == start {
            return Err(self.unexpected("an operand"));
        }
        let pos = self.tokens[start].pos;
        let text: String = self.chars[self.tokens[start].start..self.tokens[stop - 1].end]
            .iter()
            .collect();
        let outer_end = self.end;
        self.end = stop;
        let expr = match self.expr() {
            Ok(e) if self.at == stop => Some(e),
            _ => None,
        };
        self.end = outer_end;
        self.at = stop;
        Ok(Arg { name, text, expr, pos })
    }

    fn reference(&mut self) -> Result<Ref, SyntaxError> {
        let pos = self.pos();
        let name = match self.tok(0) {
            Tok::Ident(w) if !is_keyword(w) => w.clone(),
            _ => return Err(self.unexpected("a tag name")),
        };
        self.bump();
        let mut path = Vec::new();
        loop {
            if self.is_sym(".") {
                self.bump();
                match self.tok(0).clone() {
                    Tok::Ident(m) => {
                        self.bump();
                        path.push(Access::Member(m));
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
                return Ok(Ref { name, path, pos });
            }
        }
    }

    /// An expression (the lowest level, `OR`).
    fn expr(&mut self) -> Result<Expr, SyntaxError> {
        self.enter(0)?;
        let e = self.binary(0);
        self.depth -= 1;
        e
    }

    fn level_op(&self, level: usize) -> Option<BinaryOp> {
        let word = |w: &str| self.is_word(w);
        let sym = |s: &str| self.is_sym(s);
        match level {
            0 if word("OR") => Some(BinaryOp::Or),
            1 if word("XOR") => Some(BinaryOp::Xor),
            2 if word("AND") || sym("&") => Some(BinaryOp::And),
            3 if sym("=") => Some(BinaryOp::Eq),
            3 if sym("<>") => Some(BinaryOp::Ne),
            4 if sym("<") => Some(BinaryOp::Lt),
            4 if sym("<=") => Some(BinaryOp::Le),
            4 if sym(">") => Some(BinaryOp::Gt),
            4 if sym(">=") => Some(BinaryOp::Ge),
            5 if sym("+") => Some(BinaryOp::Add),
            5 if sym("-") => Some(BinaryOp::Sub),
            6 if sym("*") => Some(BinaryOp::Mul),
            6 if sym("/") => Some(BinaryOp::Div),
            6 if word("MOD") => Some(BinaryOp::Mod),
            _ => None,
        }
    }

    fn binary(&mut self, level: usize) -> Result<Expr, SyntaxError> {
        if level == 7 {
            return self.unary();
        }
        let mut left = self.binary(level + 1)?;
        let mut chain = 0;
        while let Some(op) = self.level_op(level) {
            // Each operator of a chain nests the tree one level deeper.
            chain += 1;
            self.enter(chain)?;
            self.depth -= 1;
            self.bump();
            let right = self.binary(level + 1)?;
            let pos = left.pos;
            left = Expr {
                kind: ExprKind::Binary(op, Box::new(left), Box::new(right)),
                pos,
            };
        }
        Ok(left)
    }

    fn unary(&mut self) -> Result<Expr, SyntaxError> {
        let pos = self.pos();
        let op = if self.is_sym("-") {
            UnaryOp::Neg
        } else if self.is_word("NOT") {
            UnaryOp::Not
        } else {
            return self.power();
        };
        self.bump();
        self.enter(0)?;
        let operand = self.unary();
        self.depth -= 1;
        Ok(Expr {
            kind: ExprKind::Unary(op, Box::new(operand?)),
            pos,
        })
    }

    fn power(&mut self) -> Result<Expr, SyntaxError> {
        let mut left = self.primary()?;
        let mut chain = 0;
        while self.is_sym("**") {
            chain += 1;
            self.enter(chain)?;
            self.depth -= 1;
            self.bump();
            // A signed primary: `2 ** -1 ** 2` is `(2 ** -1) ** 2`.
            let right = if self.is_sym("-") {
                let pos = self.pos();
                self.bump();
                let operand = self.primary()?;
                Expr {
                    kind: ExprKind::Unary(UnaryOp::Neg, Box::new(operand)),
                    pos,
                }
            } else {
                self.primary()?
            };
            let pos = left.pos;
            left = Expr {
                kind: ExprKind::Binary(BinaryOp::Pow, Box::new(left), Box::new(right)),
                pos,
            };
        }
        Ok(left)
    }

    fn primary(&mut self) -> Result<Expr, SyntaxError> {
        let pos = self.pos();
        let kind = match self.tok(0).clone() {
            Tok::Int(i) => {
                self.bump();
                ExprKind::Int(i)
            }
            Tok::Real(x) => {
                self.bump();
                ExprKind::Real(x)
            }
            Tok::Sym("(") => {
                self.bump();
                let e = self.expr()?;
                self.sym(")")?;
                return Ok(Expr { kind: e.kind, pos });
            }
            Tok::Ident(w) if w.eq_ignore_ascii_case("TRUE") || w.eq_ignore_ascii_case("FALSE") => {
                self.bump();
                ExprKind::Bool(w.eq_ignore_ascii_case("TRUE"))
            }
            Tok::Ident(w) if !is_keyword(&w) && matches!(self.tok(1), Tok::Sym("(")) => {
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
                ExprKind::Function(w, args)
            }
            Tok::Ident(w) if !is_keyword(&w) => ExprKind::Ref(self.reference()?),
            _ => return Err(self.unexpected("an operand (number, TRUE/FALSE, tag or '(')")),
        };
        Ok(Expr { kind, pos })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The tree written back with full parentheses, to check grouping.
    fn show(e: &Expr) -> String {
        match &e.kind {
            ExprKind::Int(i) => i.to_string(),
            ExprKind::Real(x) => format!("{x:?}"),
            ExprKind::Bool(b) => b.to_string(),
            ExprKind::Ref(r) => r.name.clone(),
            ExprKind::Unary(UnaryOp::Neg, a) => format!("(-{})", show(a)),
            ExprKind::Unary(UnaryOp::Not, a) => format!("(NOT {})", show(a)),
            ExprKind::Binary(op, a, b) => format!("({} {} {})", show(a), op.symbol(), show(b)),
            ExprKind::Function(f, args) => format!("{f}({})", args.iter().map(show).collect::<Vec<_>>().join(",")),
        }
    }

    fn grouped(text: &str) -> String {
        show(&parse_expression(text).unwrap())
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
    fn statements_of_every_kind() {
        let r = parse_routine(
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
        let r = parse_routine("Move(Axis := Table, Execute := TRUE); MAJ(A, M, 0, 10, s-curve);").unwrap();
        let StmtKind::Call(c) = &r.body[0].kind else { panic!() };
        assert_eq!(c.args[0].name.as_deref(), Some("Axis"));
        let StmtKind::Call(c) = &r.body[1].kind else { panic!() };
        assert_eq!(c.args[4].text, "s-curve");
    }

    #[test]
    fn errors_name_the_place_and_what_was_expected() {
        let e = parse_routine("x := 1;\nIF a THEN\n  y := ;\nEND_IF;").unwrap_err();
        assert_eq!((e.pos.line, e.pos.column), (3, 8));
        assert!(e.message.starts_with("expected an operand"), "{}", e.message);
        let e = parse_routine("x := 1").unwrap_err();
        assert_eq!(e.message, "expected ';', found end of routine");
        let e = parse_routine("IF := 2;").unwrap_err();
        assert!(e.message.contains("expected"), "{}", e.message);
        let e = parse_routine("CASE s OF x: END_CASE;").unwrap_err();
        assert!(e.message.contains("CASE label"), "{}", e.message);
        assert!(parse_routine("MCLM(a, b").is_err());
        assert!(parse_routine("f(a,,b);").is_err());
    }

    #[test]
    fn a_routine_nested_beyond_the_bound_is_refused_not_a_stack_overflow() {
        // `VT(VT(VT(…` a thousand deep overflowed a test thread's stack.
        let deep_calls = format!("X := {}1{};", "VT(".repeat(1000), ")".repeat(1000));
        let deep_parens = format!("X := {}1{};", "(".repeat(1000), ")".repeat(1000));
        let deep_not = format!("X := {}TRUE;", "NOT ".repeat(1000));
        let long_chain = format!("X := 1{};", " + 1".repeat(1000));
        let deep_ifs = format!("{}X := 1;{}", "IF TRUE THEN ".repeat(1000), " END_IF;".repeat(1000));
        for text in [deep_calls, deep_parens, deep_not, long_chain, deep_ifs] {
            let outcome = std::thread::Builder::new()
                .stack_size(512 * 1024)
                .spawn(move || parse_routine(&text).map(|_| ()))
                .unwrap()
                .join()
                .unwrap();
            let e = outcome.unwrap_err();
            assert!(e.message.starts_with("nested deeper than 32 levels"), "{}", e.message);
        }
        // Thirty levels of parentheses are fine.
        parse_routine(&format!("X := {}1{};", "(".repeat(28), ")".repeat(28))).unwrap();
    }
}
