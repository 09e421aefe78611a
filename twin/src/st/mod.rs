//! Structured Text: the single instruction calls of a scene's
//! `[[program]]` steps (this module), and whole routines of the Logix ST
//! dialect for `[[tasks]]` ([`lex`] → [`parse`] → [`ast`]).
//!
//! # Calls
//!
//! Two call shapes are accepted, the two the specs use:
//!
//! * **Positional** (Rockwell Logix instructions): the operands in the
//!   order of the manual's faceplate, e.g.
//!   `MCCM(CS1, MC1, 0, Pos[0], 1, Ctr[0], 0, 100, unitspersec, 50, %ofmaximum, ...);`
//! * **Named** (PLCopen / Beckhoff function blocks called on an instance
//!   tag): `MoveTable(Axis := Table, Execute := TRUE, Position := 90.0);`
//!
//! Mixing the two in one call is an error. Only what such calls need is
//! parsed: integer and real literals (`1`, `-2.5`, `1.0e3`, `16#FF`,
//! `1_000`), `TRUE`/`FALSE` in any case, identifiers (tags and enumeration
//! words), member access (`MC1.PC`) and array elements (`Pos[1]`). There is
//! no arithmetic: a `-` directly before a digit is a sign, and a `-` between
//! a letter and a letter or digit is part of a word, so that enumeration
//! words such as `s-curve`, `%ofmaximum`, `unitspersec²` and `unitspersec2`
//! are single identifiers.
//!
//! Choices the manuals leave open:
//! * An empty call `Foo()` parses as [`Args::Positional`] with no operands.
//! * A space between the instruction name and `(` is allowed (`MCT (a, b)`,
//!   as printed in the MCT manual).
//! * Identifiers are kept as written; comparisons are the caller's choice
//!   (Logix and IEC 61131-3 names are case-insensitive).
//! * Columns in errors and [`Span`]s count characters, not bytes.
//!
//! # Examples
//!
//! ```
//! use twin::st::{parse_call, Args, Expr};
//!
//! let call = parse_call("MoveTable(Axis := Table, Position := 90.0);").unwrap();
//! assert_eq!(call.name.value, "MoveTable");
//! let Args::Named(inputs) = &call.args else { panic!("named call") };
//! assert_eq!(inputs[1].0.value, "Position");
//! assert_eq!(inputs[1].1.value, Expr::Number(90.0));
//! ```

use std::fmt;

pub mod ast;
pub mod lex;
pub mod parse;

/// A half-open range of character offsets (0-based) in the parsed text.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct Span {
    /// Offset of the first character.
    pub start: usize,
    /// Offset one past the last character.
    pub end: usize,
}

impl Span {
    /// The 1-based column of the first character.
    #[must_use]
    pub fn column(&self) -> usize {
        self.start + 1
    }
}

/// A value together with where it was written.
#[derive(Debug, Clone, PartialEq)]
pub struct Spanned<T> {
    /// The parsed value.
    pub value: T,
    /// Where it was written (character offsets).
    pub span: Span,
}

/// One instruction call.
#[derive(Debug, Clone, PartialEq)]
pub struct Call {
    /// The instruction mnemonic (positional calls, e.g. `MCCM`) or the
    /// function-block instance tag (named calls, e.g. `MoveTable`).
    pub name: Spanned<String>,
    /// The operands or inputs.
    pub args: Args,
}

/// The arguments of a call.
#[derive(Debug, Clone, PartialEq)]
pub enum Args {
    /// Operands in faceplate order (Logix instructions). Also used for an
    /// empty argument list.
    Positional(Vec<Spanned<Expr>>),
    /// `Input := value` pairs (PLCopen function blocks), in written order;
    /// input names are unique (case-insensitively).
    Named(Vec<(Spanned<String>, Spanned<Expr>)>),
}

/// An operand expression.
#[derive(Debug, Clone, PartialEq)]
pub enum Expr {
    /// A real literal (`-2.5`, `1.0e3`).
    Number(f64),
    /// An integer literal (`1`, `-7`, `16#FF`).
    Integer(i64),
    /// `TRUE` or `FALSE` (any case).
    Bool(bool),
    /// A tag name or an enumeration word (`Table`, `s-curve`, `%ofmaximum`).
    Ident(String),
    /// Member access: `MC1.PC`, `MoveTable.Done`.
    Member(Box<Expr>, String),
    /// Array element: `Pos[1]`.
    Index(Box<Expr>, i64),
}

impl Expr {
    /// The identifier a reference starts from: `Pos` for `Pos[1]`, `MC1`
    /// for `MC1.PC`, `Table` for `Table`; `None` for literals.
    #[must_use]
    pub fn root_ident(&self) -> Option<&str> {
        match self {
            Expr::Ident(name) => Some(name),
            Expr::Member(base, _) | Expr::Index(base, _) => base.root_ident(),
            Expr::Number(_) | Expr::Integer(_) | Expr::Bool(_) => None,
        }
    }

    /// The numeric value of an [`Expr::Number`] or [`Expr::Integer`].
    #[must_use]
    pub fn as_f64(&self) -> Option<f64> {
        match self {
            Expr::Number(x) => Some(*x),
            #[allow(clippy::cast_precision_loss)]
            Expr::Integer(i) => Some(*i as f64),
            _ => None,
        }
    }
}

impl fmt::Display for Expr {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Expr::Number(x) => write!(f, "{x:?}"),
            Expr::Integer(i) => write!(f, "{i}"),
            Expr::Bool(b) => f.write_str(if *b { "TRUE" } else { "FALSE" }),
            Expr::Ident(name) => f.write_str(name),
            Expr::Member(base, member) => write!(f, "{base}.{member}"),
            Expr::Index(base, index) => write!(f, "{base}[{index}]"),
        }
    }
}

/// What the parser was looking for when it failed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum Expected {
    /// The instruction name or instance tag at the start of a call.
    CallName,
    /// `(` after the call name.
    OpenParen,
    /// `)` or `,` after an argument.
    CloseOrComma,
    /// An operand: a literal or a tag reference.
    Operand,
    /// An input name of a named call.
    InputName,
    /// A member name after `.`.
    MemberName,
    /// An integer array index after `[`.
    ArrayIndex,
    /// `]` after an array index.
    CloseBracket,
    /// A tag reference (`Tag`, `Tag.Bit`, `Tag[1].Bit`).
    Reference,
    /// Nothing more (only an optional `;` may follow a call).
    End,
}

impl fmt::Display for Expected {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Expected::CallName => "an instruction name or instance tag",
            Expected::OpenParen => "'('",
            Expected::CloseOrComma => "')' or ','",
            Expected::Operand => "an operand (number, TRUE/FALSE or tag)",
            Expected::InputName => "an input name",
            Expected::MemberName => "a member name after '.'",
            Expected::ArrayIndex => "an integer array index",
            Expected::CloseBracket => "']'",
            Expected::Reference => "a tag reference such as 'Tag.Bit'",
            Expected::End => "end of text (only ';' may follow the call)",
        })
    }
}

/// A Structured Text syntax error. [`ParseError::column`] gives the 1-based
/// character column; the `Display` text leaves it out so that callers can
/// place it (the scene loader maps it into the scene file).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ParseError {
    /// A token other than the one expected.
    #[error("expected {expected}, found {found}")]
    Unexpected {
        /// 1-based character column of the offending token.
        column: usize,
        /// What would have been accepted.
        expected: Expected,
        /// The offending text (`end of text` at the end).
        found: String,
    },
    /// A named input without `:=`.
    #[error("expected ':=' after input name '{input}'")]
    MissingAssign {
        /// 1-based character column where `:=` was expected.
        column: usize,
        /// The input name.
        input: String,
    },
    /// The text ended inside the argument list.
    #[error("unterminated call: the '(' is never closed, expected {expected}")]
    Unterminated {
        /// 1-based column just past the end of the text.
        column: usize,
        /// 1-based column of the `(`.
        open_column: usize,
        /// What would have been accepted next.
        expected: Expected,
    },
    /// Positional operands and named inputs in one call.
    #[error("cannot mix positional operands and named inputs in one call")]
    MixedArguments {
        /// 1-based column of the first argument of the other kind.
        column: usize,
    },
    /// The same input given twice.
    #[error("input '{input}' is given more than once")]
    DuplicateInput {
        /// 1-based column of the second occurrence.
        column: usize,
        /// The input name.
        input: String,
    },
    /// A malformed or out-of-range numeric literal.
    #[error("invalid number '{text}'")]
    InvalidNumber {
        /// 1-based column of the literal.
        column: usize,
        /// The literal as written.
        text: String,
    },
    /// A character that starts no token.
    #[error("unexpected character '{ch}'")]
    UnexpectedChar {
        /// 1-based column of the character.
        column: usize,
        /// The character.
        ch: char,
    },
}

impl ParseError {
    /// The 1-based character column the error points at.
    #[must_use]
    pub fn column(&self) -> usize {
        match self {
            ParseError::Unexpected { column, .. }
            | ParseError::MissingAssign { column, .. }
            | ParseError::Unterminated { column, .. }
            | ParseError::MixedArguments { column }
            | ParseError::DuplicateInput { column, .. }
            | ParseError::InvalidNumber { column, .. }
            | ParseError::UnexpectedChar { column, .. } => *column,
        }
    }
}

/// Parses one instruction call, e.g. `MAM(Axis1, MC2, 0, 90.0, ...)` or
/// `MoveTable(Axis := Table, Execute := TRUE)`, with an optional trailing `;`.
///
/// # Errors
/// A [`ParseError`] with the column of the first problem.
pub fn parse_call(src: &str) -> Result<Call, ParseError> {
    let tokens = lex(src)?;
    let mut p = Parser {
        tokens,
        pos: 0,
        end: src.chars().count(),
    };
    let call = p.call()?;
    if p.peek_kind() == Some(&Tok::Semi) {
        p.pos += 1;
    }
    p.expect_end()?;
    Ok(call)
}

/// Parses a condition such as `MoveTable.Done`, `MC1.PC` or `Flags[2]`:
/// a reference to a BOOL tag or bit, whose rising edge triggers a step.
///
/// # Errors
/// A [`ParseError`] with the column of the first problem.
pub fn parse_condition(src: &str) -> Result<Spanned<Expr>, ParseError> {
    let tokens = lex(src)?;
    let mut p = Parser {
        tokens,
        pos: 0,
        end: src.chars().count(),
    };
    let reference = match p.peek_kind() {
        Some(Tok::Word(w)) if bool_word(w).is_none() => p.operand()?,
        _ => return Err(p.unexpected(Expected::Reference)),
    };
    p.expect_end()?;
    Ok(reference)
}

// ---------------------------------------------------------------- lexer

#[derive(Debug, Clone, PartialEq)]
enum Tok {
    Word(String),
    Int(i64),
    Real(f64),
    LParen,
    RParen,
    Comma,
    Assign,
    Dot,
    LBracket,
    RBracket,
    Semi,
    /// A lone `=` or `:` (a mistyped `:=`).
    BadAssign,
}

#[derive(Debug, Clone)]
struct Token {
    tok: Tok,
    span: Span,
    text: String,
}

fn is_word_start(c: char) -> bool {
    c.is_alphabetic() || c == '_' || c == '%'
}

fn is_word_continue(c: char) -> bool {
    c.is_alphanumeric() || c == '_' || c == '%' || c == '²' || c == '³'
}

fn lex(src: &str) -> Result<Vec<Token>, ParseError> {
    let chars: Vec<char> = src.chars().collect();
    let mut tokens = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        let start = i;
        let single = |tok: Tok| Token {
            tok,
            span: Span { start, end: start + 1 },
            text: c.to_string(),
        };
        match c {
            c if c.is_whitespace() => {
                i += 1;
                continue;
            }
            '(' => tokens.push(single(Tok::LParen)),
            ')' => tokens.push(single(Tok::RParen)),
            ',' => tokens.push(single(Tok::Comma)),
            '.' => tokens.push(single(Tok::Dot)),
            '[' => tokens.push(single(Tok::LBracket)),
            ']' => tokens.push(single(Tok::RBracket)),
            ';' => tokens.push(single(Tok::Semi)),
            ':' if chars.get(i + 1) == Some(&'=') => {
                tokens.push(Token {
                    tok: Tok::Assign,
                    span: Span { start, end: start + 2 },
                    text: ":=".into(),
                });
                i += 2;
                continue;
            }
            ':' | '=' => tokens.push(single(Tok::BadAssign)),
            c if c.is_ascii_digit()
                || ((c == '-' || c == '+') && chars.get(i + 1).is_some_and(char::is_ascii_digit)) =>
            {
                let (token, next) = lex_number(&chars, i)?;
                tokens.push(token);
                i = next;
                continue;
            }
            c if is_word_start(c) => {
                let mut j = i + 1;
                while j < chars.len() {
                    let d = chars[j];
                    let joins = d == '-'
                        && chars[j - 1].is_alphabetic()
                        && chars.get(j + 1).is_some_and(|n| n.is_alphanumeric());
                    if is_word_continue(d) || joins {
                        j += 1;
                    } else {
                        break;
                    }
                }
                let text: String = chars[i..j].iter().collect();
                tokens.push(Token {
                    tok: Tok::Word(text.clone()),
                    span: Span { start, end: j },
                    text,
                });
                i = j;
                continue;
            }
            c => {
                return Err(ParseError::UnexpectedChar {
                    column: start + 1,
                    ch: c,
                });
            }
        }
        i += 1;
    }
    Ok(tokens)
}

/// Lexes a numeric literal starting at `start` (which may be a sign).
fn lex_number(chars: &[char], start: usize) -> Result<(Token, usize), ParseError> {
    let mut j = start;
    if chars[j] == '-' || chars[j] == '+' {
        j += 1;
    }
    // Digits, letters, '_', '#', '.', and a sign directly after an exponent 'e'.
    while j < chars.len() {
        let d = chars[j];
        let exp_sign = (d == '-' || d == '+') && matches!(chars[j - 1], 'e' | 'E') && !chars[start..j].contains(&'#');
        let dot = d == '.' && chars.get(j + 1).is_some_and(char::is_ascii_digit);
        if d.is_ascii_alphanumeric() || d == '_' || d == '#' || dot || exp_sign {
            j += 1;
        } else {
            break;
        }
    }
    let text: String = chars[start..j].iter().collect();
    let invalid = || ParseError::InvalidNumber {
        column: start + 1,
        text: text.clone(),
    };
    let (negative, body) = match text.strip_prefix('-') {
        Some(rest) => (true, rest),
        None => (false, text.strip_prefix('+').unwrap_or(&text)),
    };
    if body.starts_with('_') || body.ends_with('_') || body.contains("__") {
        return Err(invalid());
    }
    let cleaned: String = body.chars().filter(|&c| c != '_').collect();
    let tok = if let Some((radix, digits)) = cleaned.split_once('#') {
        let radix: u32 = match radix {
            "2" => 2,
            "8" => 8,
            "16" => 16,
            _ => return Err(invalid()),
        };
        if digits.is_empty() {
            return Err(invalid());
        }
        let magnitude = i64::from_str_radix(digits, radix).map_err(|_| invalid())?;
        Tok::Int(if negative { -magnitude } else { magnitude })
    } else if cleaned.chars().all(|c| c.is_ascii_digit()) {
        let signed = if negative { format!("-{cleaned}") } else { cleaned };
        Tok::Int(signed.parse().map_err(|_| invalid())?)
    } else {
        let valid_shape = cleaned
            .chars()
            .all(|c| c.is_ascii_digit() || matches!(c, '.' | 'e' | 'E' | '-' | '+'));
        if !valid_shape {
            return Err(invalid());
        }
        let value: f64 = cleaned.parse().map_err(|_| invalid())?;
        if !value.is_finite() {
            return Err(invalid());
        }
        Tok::Real(if negative { -value } else { value })
    };
    Ok((
        Token {
            tok,
            span: Span { start, end: j },
            text,
        },
        j,
    ))
}

fn bool_word(word: &str) -> Option<bool> {
    if word.eq_ignore_ascii_case("TRUE") {
        Some(true)
    } else if word.eq_ignore_ascii_case("FALSE") {
        Some(false)
    } else {
        None
    }
}

// ---------------------------------------------------------------- parser

struct Parser {
    tokens: Vec<Token>,
    pos: usize,
    /// Character length of the source (column of "end of text" is end + 1).
    end: usize,
}

impl Parser {
    fn peek(&self) -> Option<&Token> {
        self.tokens.get(self.pos)
    }

    fn peek_kind(&self) -> Option<&Tok> {
        self.peek().map(|t| &t.tok)
    }

    fn column_here(&self) -> usize {
        self.peek().map_or(self.end + 1, |t| t.span.column())
    }

    fn unexpected(&self, expected: Expected) -> ParseError {
        ParseError::Unexpected {
            column: self.column_here(),
            expected,
            found: self
                .peek()
                .map_or_else(|| "end of text".to_owned(), |t| format!("'{}'", t.text)),
        }
    }

    fn expect_end(&self) -> Result<(), ParseError> {
        if self.peek().is_some() {
            Err(self.unexpected(Expected::End))
        } else {
            Ok(())
        }
    }

    fn call(&mut self) -> Result<Call, ParseError> {
        let name = match self.peek() {
            Some(Token {
                tok: Tok::Word(w),
                span,
                ..
            }) if bool_word(w).is_none() => Spanned {
                value: w.clone(),
                span: *span,
            },
            _ => return Err(self.unexpected(Expected::CallName)),
        };
        self.pos += 1;
        let open = match self.peek() {
            Some(Token {
                tok: Tok::LParen, span, ..
            }) => *span,
            _ => return Err(self.unexpected(Expected::OpenParen)),
        };
        self.pos += 1;
        let unterminated = |p: &Self, expected| ParseError::Unterminated {
            column: p.end + 1,
            open_column: open.column(),
            expected,
        };

        if self.peek_kind() == Some(&Tok::RParen) {
            self.pos += 1;
            return Ok(Call {
                name,
                args: Args::Positional(Vec::new()),
            });
        }
        let mut positional: Vec<Spanned<Expr>> = Vec::new();
        let mut named: Vec<(Spanned<String>, Spanned<Expr>)> = Vec::new();
        loop {
            let Some(token) = self.peek().cloned() else {
                return Err(unterminated(self, Expected::Operand));
            };
            let after = self.tokens.get(self.pos + 1).map(|t| (&t.tok, t.span.column()));
            let word = match &token.tok {
                Tok::Word(w) if bool_word(w).is_none() => Some(w.clone()),
                _ => None,
            };
            if let (Some(input), Some((Tok::BadAssign, column))) = (&word, after) {
                return Err(ParseError::MissingAssign {
                    column,
                    input: input.clone(),
                });
            }
            let is_named = word.is_some() && matches!(after, Some((Tok::Assign, _)));
            if is_named && !positional.is_empty() {
                return Err(ParseError::MixedArguments {
                    column: token.span.column(),
                });
            }
            if !is_named && !named.is_empty() {
                // After named inputs, a bare word is most likely an input whose ':=' is missing.
                return Err(match (word, after) {
                    (Some(input), None) => ParseError::MissingAssign {
                        column: self.end + 1,
                        input,
                    },
                    (Some(input), Some((tok, column))) if !matches!(tok, Tok::Dot | Tok::LBracket) => {
                        ParseError::MissingAssign { column, input }
                    }
                    _ => ParseError::MixedArguments {
                        column: token.span.column(),
                    },
                });
            }
            if let (true, Some(input)) = (is_named, word) {
                self.pos += 2; // name and ':='
                if named.iter().any(|(n, _)| n.value.eq_ignore_ascii_case(&input)) {
                    return Err(ParseError::DuplicateInput {
                        column: token.span.column(),
                        input,
                    });
                }
                if self.peek().is_none() {
                    return Err(unterminated(self, Expected::Operand));
                }
                let value = self.operand()?;
                named.push((
                    Spanned {
                        value: input,
                        span: token.span,
                    },
                    value,
                ));
            } else {
                let value = self.operand()?;
                positional.push(value);
            }
            match self.peek_kind() {
                Some(Tok::Comma) => self.pos += 1,
                Some(Tok::RParen) => {
                    self.pos += 1;
                    break;
                }
                None => return Err(unterminated(self, Expected::CloseOrComma)),
                Some(_) => return Err(self.unexpected(Expected::CloseOrComma)),
            }
        }
        let args = if named.is_empty() {
            Args::Positional(positional)
        } else {
            Args::Named(named)
        };
        Ok(Call { name, args })
    }

    /// A literal or a reference (`Tag`, `Tag.Member`, `Tag[1]`, chains of them).
    fn operand(&mut self) -> Result<Spanned<Expr>, ParseError> {
        let Some(token) = self.peek().cloned() else {
            return Err(self.unexpected(Expected::Operand));
        };
        let start = token.span.start;
        let mut end = token.span.end;
        let mut expr = match token.tok {
            Tok::Int(i) => {
                self.pos += 1;
                return Ok(Spanned {
                    value: Expr::Integer(i),
                    span: token.span,
                });
            }
            Tok::Real(x) => {
                self.pos += 1;
                return Ok(Spanned {
                    value: Expr::Number(x),
                    span: token.span,
                });
            }
            Tok::Word(w) => {
                self.pos += 1;
                if let Some(b) = bool_word(&w) {
                    return Ok(Spanned {
                        value: Expr::Bool(b),
                        span: token.span,
                    });
                }
                Expr::Ident(w)
            }
            _ => return Err(self.unexpected(Expected::Operand)),
        };
        loop {
            match self.peek_kind() {
                Some(Tok::Dot) => {
                    self.pos += 1;
                    match self.peek().cloned() {
                        Some(Token {
                            tok: Tok::Word(member),
                            span,
                            ..
                        }) => {
                            self.pos += 1;
                            end = span.end;
                            expr = Expr::Member(Box::new(expr), member);
                        }
                        _ => return Err(self.unexpected(Expected::MemberName)),
                    }
                }
                Some(Tok::LBracket) => {
                    self.pos += 1;
                    let index = match self.peek_kind() {
                        Some(Tok::Int(i)) => *i,
                        _ => return Err(self.unexpected(Expected::ArrayIndex)),
                    };
                    self.pos += 1;
                    match self.peek() {
                        Some(Token {
                            tok: Tok::RBracket,
                            span,
                            ..
                        }) => {
                            end = span.end;
                            self.pos += 1;
                        }
                        _ => return Err(self.unexpected(Expected::CloseBracket)),
                    }
                    expr = Expr::Index(Box::new(expr), index);
                }
                _ => break,
            }
        }
        Ok(Spanned {
            value: expr,
            span: Span { start, end },
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    fn ident(s: &str) -> Expr {
        Expr::Ident(s.to_owned())
    }

    fn positional(src: &str) -> Vec<Expr> {
        match parse_call(src).expect("parses").args {
            Args::Positional(v) => v.into_iter().map(|a| a.value).collect(),
            Args::Named(_) => panic!("expected positional"),
        }
    }

    #[test]
    fn mccm_example_from_the_manual() {
        let src = "MCCM(myMccmCoordinateSystem, myMccmMotionControl, myMccmMoveType, myMccmPosition[0], myMccmCircleType, myMccmRadius[0], myMccmDirection, myMccmSpeed, Unitspersec, myMccmAccelRate, Unitspersec2, myMccmDecelRate, Unitspersec2, Trapezoidal, 100.0, 100.0, %ofTime, myMccmTermType, CoordinatedMotion, Programmed, 0, 0, None, 0, 0);";
        let call = parse_call(src).expect("parses");
        assert_eq!(call.name.value, "MCCM");
        assert_eq!(call.name.span, Span { start: 0, end: 4 });
        let args = positional(src);
        assert_eq!(args.len(), 25);
        assert_eq!(args[3], Expr::Index(Box::new(ident("myMccmPosition")), 0));
        assert_eq!(args[10], ident("Unitspersec2"));
        assert_eq!(args[14], Expr::Number(100.0));
        assert_eq!(args[16], ident("%ofTime"));
        assert_eq!(args[24], Expr::Integer(0));
    }

    #[test]
    fn enumeration_words_are_single_identifiers() {
        let args = positional(
            "MCCM(CS1, MC1, 0, Pos, 1, Ctr, 0, 100, unitspersec, 50, %ofmaximum, 50, unitspersec\u{b2}, s-curve, 100, 100, unitspersec\u{b3}, 2, 0, 0, 0, 0, 0, 0, 0)",
        );
        assert_eq!(args.len(), 25);
        assert_eq!(args[10], ident("%ofmaximum"));
        assert_eq!(args[12], ident("unitspersec\u{b2}"));
        assert_eq!(args[13], ident("s-curve"));
        assert_eq!(args[16], ident("unitspersec\u{b3}"));
    }

    #[test]
    fn other_manual_examples() {
        assert_eq!(positional("MCCP(MCCP_1,Cam_1[0],30,1.0,1.0,Cam_pro1[0]);").len(), 6);
        assert_eq!(
            positional(
                "MCT (myMctSourceSystem, myMctTargetSystem, myMctMotionControl, myMctOrientation, myMctTranslation);"
            )
            .len(),
            5
        );
        let mapc = positional(
            "MAPC (Axis0, Axis1, MAPC_1, 1, Cam_prof1[0], 1.0, 1.0, Once, Immediate, Mlckpos, Clckpos, NewCam, Actual, ForwardOnly);",
        );
        assert_eq!(mapc.len(), 14);
        assert_eq!(mapc[7], ident("Once"));
        assert_eq!(positional("MAFR(Axis1, MC1)").len(), 2);
        assert_eq!(positional("MSO()"), Vec::<Expr>::new());
    }

    #[test]
    fn named_function_block_call() {
        let call = parse_call("MoveTable(Axis := Table, Execute := TRUE, Position := 90.0, Velocity := 180.0, Direction := MC_Positive_Direction, BufferMode := MC_Aborting)").expect("parses");
        let Args::Named(inputs) = call.args else {
            panic!("named")
        };
        let names: Vec<&str> = inputs.iter().map(|(n, _)| n.value.as_str()).collect();
        assert_eq!(
            names,
            ["Axis", "Execute", "Position", "Velocity", "Direction", "BufferMode"]
        );
        assert_eq!(inputs[1].1.value, Expr::Bool(true));
        assert_eq!(inputs[0].1.span, Span { start: 18, end: 23 });
        assert_eq!(inputs[4].1.value, ident("MC_Positive_Direction"));
    }

    #[test]
    fn literals() {
        let args = positional(
            "X(1, -2.5, 1.0e3, 2E-2, 16#FF, -16#10, 2#1010, 1_000, true, False, +3, MC1.PC, Pos[1].Bit, A.B.C)",
        );
        assert_eq!(
            args,
            [
                Expr::Integer(1),
                Expr::Number(-2.5),
                Expr::Number(1000.0),
                Expr::Number(0.02),
                Expr::Integer(255),
                Expr::Integer(-16),
                Expr::Integer(10),
                Expr::Integer(1000),
                Expr::Bool(true),
                Expr::Bool(false),
                Expr::Integer(3),
                Expr::Member(Box::new(ident("MC1")), "PC".into()),
                Expr::Member(Box::new(Expr::Index(Box::new(ident("Pos")), 1)), "Bit".into()),
                Expr::Member(Box::new(Expr::Member(Box::new(ident("A")), "B".into())), "C".into()),
            ]
        );
        assert_eq!(args[12].root_ident(), Some("Pos"));
        assert_eq!(args[4].as_f64(), Some(255.0));
    }

    #[test]
    fn conditions() {
        let c = parse_condition(" MoveTable.Done ").expect("parses");
        assert_eq!(c.value, Expr::Member(Box::new(ident("MoveTable")), "Done".into()));
        assert_eq!(c.span, Span { start: 1, end: 15 });
        assert!(parse_condition("Flags[2]").is_ok());
        assert!(matches!(
            parse_condition("TRUE"),
            Err(ParseError::Unexpected {
                column: 1,
                expected: Expected::Reference,
                ..
            })
        ));
        assert!(matches!(
            parse_condition("A.Done B"),
            Err(ParseError::Unexpected {
                column: 8,
                expected: Expected::End,
                ..
            })
        ));
        assert!(matches!(
            parse_condition(""),
            Err(ParseError::Unexpected { column: 1, .. })
        ));
    }

    #[test]
    fn errors_carry_columns_and_expectations() {
        let cases: [(&str, usize); 12] = [
            ("MoveTable(Axis := Table, Position 90.0)", 35),
            ("MoveTable(Axis := Table, Position = 90.0)", 35),
            ("MAM(Axis1, MC2", 15),
            ("MAM(Axis1 MC2)", 11),
            ("MAM(Axis1, , MC2)", 12),
            ("MAM Axis1", 5),
            ("(Axis1)", 1),
            ("MAM(Axis1, MC2.)", 16),
            ("MAM(Pos[x])", 9),
            ("MAM(1.2.3)", 5),
            ("MAM(Axis1); extra", 13),
            ("MAM(Axis1, Ax @ 1)", 15),
        ];
        for (src, column) in cases {
            let e = parse_call(src).expect_err(src);
            assert_eq!(e.column(), column, "{src}: {e}");
        }
        assert!(matches!(
            parse_call("MoveTable(Axis := Table, Position 90.0)"),
            Err(ParseError::MissingAssign { ref input, .. }) if input == "Position"
        ));
        assert!(matches!(
            parse_call("MAM(Axis1, MC2"),
            Err(ParseError::Unterminated {
                open_column: 4,
                expected: Expected::CloseOrComma,
                ..
            })
        ));
        assert!(matches!(
            parse_call("MAM(Axis1 MC2)"),
            Err(ParseError::Unexpected {
                expected: Expected::CloseOrComma,
                ..
            })
        ));
        assert!(matches!(
            parse_call("F(A := 1, 2)"),
            Err(ParseError::MixedArguments { column: 11 })
        ));
        assert!(matches!(
            parse_call("F(1, A := 2)"),
            Err(ParseError::MixedArguments { column: 6 })
        ));
        assert!(matches!(
            parse_call("F(A := 1, a := 2)"),
            Err(ParseError::DuplicateInput { column: 11, .. })
        ));
        assert!(matches!(
            parse_call("F(99999999999999999999)"),
            Err(ParseError::InvalidNumber { column: 3, .. })
        ));
        assert!(matches!(
            parse_call("F(A := )"),
            Err(ParseError::Unexpected {
                expected: Expected::Operand,
                ..
            })
        ));
    }

    #[test]
    fn columns_count_characters() {
        let e = parse_call("F(unitspersec\u{b2} \u{b2})").expect_err("stray");
        assert_eq!(e.column(), 16);
    }

    #[test]
    fn display_is_one_line_without_column() {
        let e = parse_call("MoveTable(Axis := Table, Position 90.0)").expect_err("bad");
        assert_eq!(e.to_string(), "expected ':=' after input name 'Position'");
        let e = parse_call("MAM(Axis1 MC2)").expect_err("bad");
        assert_eq!(e.to_string(), "expected ')' or ',', found 'MC2'");
    }

    fn assert_column_in_range(src: &str, e: &ParseError) {
        assert!(
            e.column() >= 1 && e.column() <= src.chars().count() + 1,
            "{src:?}: {e:?}"
        );
    }

    #[test]
    fn seeded_random_strings_never_panic() {
        let alphabet: Vec<char> = "MCAxis_(),:=;.[]#-+%e0123456789 \u{b2}\u{b3}\u{e9}TRUEfalse\t\"'@"
            .chars()
            .collect();
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(61131);
        for _ in 0..500 {
            let len = rng.random_range(0..40);
            let src: String = (0..len)
                .map(|_| alphabet[rng.random_range(0..alphabet.len())])
                .collect();
            if let Err(e) = parse_call(&src) {
                assert_column_in_range(&src, &e);
            }
            if let Err(e) = parse_condition(&src) {
                assert_column_in_range(&src, &e);
            }
        }
        // Mutations of a valid call exercise deeper paths.
        let valid: Vec<char> = "MoveTable(Axis := Table, Execute := TRUE, Position := -90.5e1, Pos[1].X := 16#FF);"
            .chars()
            .collect();
        for _ in 0..500 {
            let mut chars = valid.clone();
            for _ in 0..rng.random_range(1..4) {
                let at = rng.random_range(0..chars.len());
                chars[at] = alphabet[rng.random_range(0..alphabet.len())];
            }
            let src: String = chars.into_iter().collect();
            if let Err(e) = parse_call(&src) {
                assert_column_in_range(&src, &e);
            }
        }
    }
}
