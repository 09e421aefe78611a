//! Tokens of Structured Text: routines, `[[program]]` calls and scene
//! expressions all lex the same way.
//!
//! Comments (`// …`, `(* … *)`, `/* … */`) and white space are skipped.
//! Identifiers are ASCII letters, digits and `_`, not starting with a digit;
//! the Logix status flags `S:FS`, `S:N`, `S:Z`, `S:V`, `S:C`, `S:MINOR` lex
//! as one identifier, and so do `\Program` (a program parameter's
//! `\Program.Param`) and a module's I/O tag (`Local:1:I`, `Drive1:O`:
//! a name, an optional `:slot`, then `:I`, `:O`, `:C` or `:S`). Numbers: `123`, `1_000`, `16#FF`, `8#17`, `2#1010`,
//! `1.5`, `1.0e-3`, `2E6`; `1..5` is `1`, `..`, `5` (a CASE range). A
//! character that is none of these (`%`, `²`) becomes [`Tok::Other`]: it is
//! an error everywhere except inside an enumeration word of an instruction
//! operand (`%ofTime`, `unitspersec²`, `s-curve`), which the parser keeps
//! as written for the compiler to match against the operand's words.
//!
//! Positions are byte offsets into the text ([`Token::start`]); the
//! [`crate::source::Source`] maps them into their file.

use std::borrow::Cow;
use std::fmt;

/// A token's kind and value.
#[derive(Debug, Clone, PartialEq)]
pub enum Tok<'a> {
    /// An identifier or keyword, as written (the text's own bytes, but for
    /// a status flag, written `S:FS` whatever its case).
    Ident(Cow<'a, str>),
    /// An integer literal (any base), before any type is applied.
    Int(i128),
    /// A real literal.
    Real(f64),
    /// Punctuation or an operator: `:=` `(` `)` `[` `]` `,` `;` `.` `..` `:`
    /// `+` `-` `*` `**` `/` `=` `<>` `<` `<=` `>` `>=` `&` and the C
    /// comparisons `==` `!=` (read so that they can be refused with a hint).
    Sym(&'static str),
    /// Any other character.
    Other(char),
    /// The end of the text.
    Eof,
}

impl fmt::Display for Tok<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Tok::Ident(s) => write!(f, "'{s}'"),
            Tok::Int(i) => write!(f, "'{i}'"),
            Tok::Real(x) => write!(f, "'{x:?}'"),
            Tok::Sym(s) => write!(f, "'{s}'"),
            Tok::Other(c) => write!(f, "'{c}'"),
            Tok::Eof => f.write_str("the end of the text"),
        }
    }
}

/// A token and its bytes in the text.
#[derive(Debug, Clone, PartialEq)]
pub struct Token<'a> {
    /// What it is.
    pub tok: Tok<'a>,
    /// Its first byte.
    pub start: usize,
    /// One past its last byte.
    pub end: usize,
}

/// A lexical error: an unterminated comment or a malformed number.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LexError {
    /// Its first byte.
    pub start: usize,
    /// One past its last byte.
    pub end: usize,
    /// What is wrong.
    pub message: String,
}

const SYMBOLS: [&str; 24] = [
    ":=", "..", "**", "<>", "<=", ">=", "==", "!=", "(", ")", "[", "]", ",", ";", ".", ":", "+", "-", "*", "/", "=",
    "<", ">", "&",
];

const STATUS_FLAGS: [&str; 6] = ["FS", "N", "Z", "V", "C", "MINOR"];

/// Splits a text into tokens; the last one is [`Tok::Eof`].
///
/// # Errors
/// [`LexError`] for an unterminated block comment or a malformed number.
pub fn lex(text: &str) -> Result<Vec<Token<'_>>, LexError> {
    let mut lexer = Lexer { text, at: 0 };
    // About a token for every four characters of Structured Text.
    let mut out = Vec::with_capacity(text.len() / 4 + 1);
    loop {
        lexer.skip_space_and_comments()?;
        let start = lexer.at;
        let Some(c) = lexer.peek(0) else {
            out.push(Token {
                tok: Tok::Eof,
                start,
                end: start,
            });
            return Ok(out);
        };
        let rest = &text[start..];
        let tok = if c.is_ascii_digit() {
            lexer.number()?
        } else if c.is_ascii_alphabetic() || c == '_' {
            lexer.word()
        } else if c == '\\' && lexer.peek(1).is_some_and(|d| d.is_ascii_alphabetic() || d == '_') {
            // `\Program.Param`: another program's parameter (1756-PM021).
            lexer.at += 1;
            match lexer.word() {
                Tok::Ident(Cow::Borrowed(_)) => Tok::Ident(Cow::Borrowed(&text[start..lexer.at])),
                Tok::Ident(w) => Tok::Ident(Cow::Owned(format!("\\{w}"))),
                other => other,
            }
        } else if let Some(sym) = SYMBOLS.iter().find(|s| rest.starts_with(**s)) {
            lexer.at += sym.len();
            Tok::Sym(sym)
        } else {
            lexer.at += c.len_utf8();
            Tok::Other(c)
        };
        out.push(Token {
            tok,
            start,
            end: lexer.at,
        });
    }
}

struct Lexer<'a> {
    text: &'a str,
    at: usize,
}

impl<'a> Lexer<'a> {
    fn peek(&self, ahead: usize) -> Option<char> {
        self.text[self.at..].chars().nth(ahead)
    }

    fn bump(&mut self) {
        if let Some(c) = self.peek(0) {
            self.at += c.len_utf8();
        }
    }

    fn skip_space_and_comments(&mut self) -> Result<(), LexError> {
        loop {
            let rest = &self.text[self.at..];
            if rest.starts_with(char::is_whitespace) {
                self.bump();
            } else if rest.starts_with("//") {
                self.at += rest.find('\n').unwrap_or(rest.len());
            } else if rest.starts_with("(*") {
                self.block_comment("*)")?;
            } else if rest.starts_with("/*") {
                self.block_comment("*/")?;
            } else {
                return Ok(());
            }
        }
    }

    fn block_comment(&mut self, close: &str) -> Result<(), LexError> {
        let start = self.at;
        match self.text[start + 2..].find(close) {
            Some(i) => {
                self.at = start + 2 + i + close.len();
                Ok(())
            }
            None => Err(LexError {
                start,
                end: start + 2,
                message: format!("comment not closed: expected '{close}'"),
            }),
        }
    }

    fn word(&mut self) -> Tok<'a> {
        let start = self.at;
        while self.peek(0).is_some_and(|c| c.is_ascii_alphanumeric() || c == '_') {
            self.at += 1;
        }
        let word = &self.text[start..self.at];
        if word.eq_ignore_ascii_case("S") && self.peek(0) == Some(':') {
            let rest: String = self.text[self.at + 1..]
                .chars()
                .take_while(char::is_ascii_alphabetic)
                .collect();
            if let Some(flag) = STATUS_FLAGS.iter().find(|f| f.eq_ignore_ascii_case(&rest)) {
                self.at += 1 + rest.len();
                return Tok::Ident(Cow::Owned(format!("S:{flag}")));
            }
        }
        if let Some(len) = module_tag_tail(&self.text[self.at..]) {
            self.at += len;
        }
        Tok::Ident(Cow::Borrowed(&self.text[start..self.at]))
    }

    /// Digits of `radix` and the `_` between them, without the `_`.
    fn digits(&mut self, radix: u32) -> Cow<'a, str> {
        let start = self.at;
        let mut underscore = false;
        while let Some(c) = self.text[self.at..].chars().next() {
            if c == '_' {
                underscore = true;
            } else if !c.is_digit(radix) {
                break;
            }
            self.at += 1;
        }
        let written = &self.text[start..self.at];
        if underscore {
            Cow::Owned(written.replace('_', ""))
        } else {
            Cow::Borrowed(written)
        }
    }

    fn number(&mut self) -> Result<Tok<'a>, LexError> {
        let start = self.at;
        let whole = self.digits(10);
        if self.peek(0) == Some('#') {
            let radix = match &*whole {
                "2" => 2,
                "8" => 8,
                "16" => 16,
                _ => return Err(self.bad(start, format!("'{whole}#': the base of a literal is 2, 8 or 16"))),
            };
            self.at += 1;
            let digits = self.digits(radix);
            if digits.is_empty() || self.peek(0).is_some_and(|c| c.is_ascii_alphanumeric()) {
                return Err(self.bad(start, format!("'{whole}#…': expected base-{radix} digits")));
            }
            return i128::from_str_radix(&digits, radix)
                .map(|v| Tok::Int(bit_pattern(v)))
                .map_err(|_| self.bad(start, format!("'{whole}#{digits}' is too large")));
        }
        let mut real = false;
        if self.peek(0) == Some('.') && self.peek(1).is_some_and(|c| c.is_ascii_digit()) {
            self.at += 1;
            self.digits(10);
            real = true;
        }
        if matches!(self.peek(0), Some('e' | 'E')) {
            let signed = matches!(self.peek(1), Some('+' | '-'));
            let digit_at = if signed { 2 } else { 1 };
            if self.peek(digit_at).is_some_and(|c| c.is_ascii_digit()) {
                self.at += digit_at;
                self.digits(10);
                real = true;
            }
        }
        // The literal as read: its digits without `_`, the exponent's `e`
        // lower-case.
        let written = &self.text[start..self.at];
        let text: Cow<'_, str> = if written.contains(['_', 'E']) {
            Cow::Owned(written.replace('_', "").replace('E', "e"))
        } else {
            Cow::Borrowed(written)
        };
        if self.peek(0).is_some_and(|c| c.is_ascii_alphabetic() || c == '_') {
            return Err(self.bad(start, format!("'{text}' is followed by a letter: expected a number")));
        }
        if real {
            match text.parse::<f64>() {
                // Past LREAL's range the literal would be infinity.
                Ok(x) if x.is_infinite() => Err(self.bad(start, format!("'{text}' is too large for an LREAL"))),
                Ok(x) => Ok(Tok::Real(x)),
                Err(_) => Err(self.bad(start, format!("'{text}' is not a number"))),
            }
        } else {
            text.parse::<i128>()
                .map(Tok::Int)
                .map_err(|_| self.bad(start, format!("'{text}' is too large")))
        }
    }

    fn bad(&self, start: usize, message: String) -> LexError {
        LexError {
            start,
            end: self.at.max(start + 1),
            message,
        }
    }
}

/// A based literal (`16#…`, `8#…`, `2#…`) is a bit pattern: one of 32
/// bits is the DINT with those bits (`16#FFFF_FFFF` is −1), one of 64 the
/// LINT, as the controller stores it; no overflow is recorded.
fn bit_pattern(v: i128) -> i128 {
    if (i128::from(i32::MAX) + 1..=i128::from(u32::MAX)).contains(&v) {
        i128::from(v as u32 as i32)
    } else if (i128::from(i64::MAX) + 1..=i128::from(u64::MAX)).contains(&v) {
        i128::from(v as u64 as i64)
    } else {
        v
    }
}

/// Whether `name` is a module I/O tag's name (`Local:1:I`, `Drive1:O`):
/// an identifier and the tail [`module_tag_tail`] reads.
#[must_use]
pub fn is_module_tag_name(name: &str) -> bool {
    let head = name.find(':').unwrap_or(name.len());
    let ident = &name[..head];
    ident
        .chars()
        .next()
        .is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
        && ident.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
        && module_tag_tail(&name[head..]) == Some(name.len() - head)
}

/// The length of a module I/O tag's tail right after its first name:
/// `:1:I` of `Local:1:I`, `:I` of `Drive1:I` — optional `:slot` digits,
/// then `:I`, `:O`, `:C` or `:S`, not followed by a name character. `None`
/// for anything else (`:=`, a CASE label's `:`).
fn module_tag_tail(rest: &str) -> Option<usize> {
    let b = rest.as_bytes();
    let mut at = 0;
    if b.first() != Some(&b':') {
        return None;
    }
    // `:slot`, digits.
    let digits = b[1..].iter().take_while(|c| c.is_ascii_digit()).count();
    if digits > 0 && b.get(1 + digits) == Some(&b':') {
        at = 1 + digits;
    }
    let kind = *b.get(at + 1)?;
    let after = b.get(at + 2);
    let word_char = |c: &u8| c.is_ascii_alphanumeric() || *c == b'_';
    (matches!(kind.to_ascii_uppercase(), b'I' | b'O' | b'C' | b'S') && !after.is_some_and(word_char)).then_some(at + 2)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn toks(text: &str) -> Vec<Tok<'_>> {
        lex(text).unwrap().into_iter().map(|t| t.tok).collect()
    }

    #[test]
    fn literals_in_every_base_and_reals_with_exponents() {
        assert_eq!(
            toks("16#FF 8#17 2#1010 1_000 1.5 1.0e-3 2E6"),
            vec![
                Tok::Int(255),
                Tok::Int(15),
                Tok::Int(10),
                Tok::Int(1000),
                Tok::Real(1.5),
                Tok::Real(1.0e-3),
                Tok::Real(2e6),
                Tok::Eof
            ]
        );
    }

    #[test]
    fn based_literals_are_bit_patterns_of_32_or_64_bits() {
        assert_eq!(
            toks("16#FFFF_FFFF 16#8000_0000 16#7FFF_FFFF 16#1_0000_0000 16#FFFF_FFFF_FFFF_FFFF 2#1 4294967295"),
            [
                Tok::Int(-1),
                Tok::Int(i128::from(i32::MIN)),
                Tok::Int(i128::from(i32::MAX)),
                Tok::Int(1 << 32),
                Tok::Int(-1),
                Tok::Int(1),
                // A decimal literal is its value.
                Tok::Int(4_294_967_295),
                Tok::Eof
            ]
        );
    }

    #[test]
    fn a_module_io_tag_lexes_as_one_name_and_a_case_label_does_not() {
        assert_eq!(
            toks("Local:1:I.Data.3 Drive1:O x:=1"),
            vec![
                Tok::Ident("Local:1:I".into()),
                Tok::Sym("."),
                Tok::Ident("Data".into()),
                Tok::Sym("."),
                Tok::Int(3),
                Tok::Ident("Drive1:O".into()),
                Tok::Ident("x".into()),
                Tok::Sym(":="),
                Tok::Int(1),
                Tok::Eof
            ]
        );
        // `Red:Inc` is a name, a colon and a name: the tail must end there.
        assert_eq!(toks("Red:Inc")[0], Tok::Ident("Red".into()));
        assert_eq!(toks("A:1:Input")[0], Tok::Ident("A".into()));
    }

    #[test]
    fn a_program_parameter_reference_lexes_its_backslash_into_the_name() {
        assert_eq!(
            toks("\\Cell.Speed"),
            [
                Tok::Ident("\\Cell".into()),
                Tok::Sym("."),
                Tok::Ident("Speed".into()),
                Tok::Eof
            ]
        );
        assert_eq!(toks("\\ 1"), [Tok::Other('\\'), Tok::Int(1), Tok::Eof]);
    }

    #[test]
    fn ranges_bits_and_status_flags() {
        assert_eq!(
            toks("1..5 X.5 s:fs"),
            vec![
                Tok::Int(1),
                Tok::Sym(".."),
                Tok::Int(5),
                Tok::Ident("X".into()),
                Tok::Sym("."),
                Tok::Int(5),
                Tok::Ident("S:FS".into()),
                Tok::Eof
            ]
        );
    }

    #[test]
    fn comments_of_three_kinds_and_byte_positions() {
        let t = lex("a // x\n(* y\n *) b² /* z */ c").unwrap();
        let at: Vec<_> = t.iter().map(|t| (t.tok.clone(), t.start)).collect();
        assert_eq!(at[0], (Tok::Ident("a".into()), 0));
        assert_eq!(at[1], (Tok::Ident("b".into()), 16));
        assert_eq!(at[2], (Tok::Other('²'), 17));
        assert_eq!(at[3], (Tok::Ident("c".into()), 28));
        assert!(lex("(* open").is_err());
        assert!(lex("/* open").is_err());
    }

    #[test]
    fn malformed_numbers_and_other_characters() {
        assert!(lex("3#12").is_err());
        assert!(lex("16#").is_err());
        assert!(lex("12abc").is_err());
        assert_eq!(toks("%ofTime")[0], Tok::Other('%'));
        assert_eq!(toks("unitspersec²")[1], Tok::Other('²'));
        assert_eq!(toks("a == b")[1], Tok::Sym("=="));
    }
}
