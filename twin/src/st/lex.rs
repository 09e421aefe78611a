//! Tokens of a Structured Text routine.
//!
//! Comments (`// …`, `(* … *)`, `/* … */`) and white space are skipped.
//! Identifiers are ASCII letters, digits and `_`, not starting with a digit;
//! the Logix status flags `S:FS`, `S:N`, `S:Z`, `S:V`, `S:C`, `S:MINOR` lex
//! as one identifier. Numbers: `123`, `1_000`, `16#FF`, `8#17`, `2#1010`,
//! `1.5`, `1.0e-3`, `2E6`; `1..5` is `1`, `..`, `5` (a CASE range). A
//! character that is none of these (`%`, `²`) becomes [`Tok::Other`]: it is
//! an error everywhere except inside an enumeration word of an instruction
//! operand (`%ofTime`, `unitspersec²`), which the parser reads as written.

use std::fmt;

/// Where a token or node starts: 1-based line and column (characters).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Hash)]
pub struct Pos {
    /// 1-based line.
    pub line: u32,
    /// 1-based column, in characters.
    pub column: u32,
}

impl fmt::Display for Pos {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}", self.line, self.column)
    }
}

/// A token's kind and value.
#[derive(Debug, Clone, PartialEq)]
pub enum Tok {
    /// An identifier or keyword, as written.
    Ident(String),
    /// An integer literal (any base), before any type is applied.
    Int(i128),
    /// A real literal.
    Real(f64),
    /// Punctuation or an operator: `:=` `(` `)` `[` `]` `,` `;` `.` `..` `:`
    /// `+` `-` `*` `**` `/` `=` `<>` `<` `<=` `>` `>=` `&`.
    Sym(&'static str),
    /// Any other character.
    Other(char),
    /// The end of the text.
    Eof,
}

impl fmt::Display for Tok {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Tok::Ident(s) => write!(f, "'{s}'"),
            Tok::Int(i) => write!(f, "'{i}'"),
            Tok::Real(x) => write!(f, "'{x:?}'"),
            Tok::Sym(s) => write!(f, "'{s}'"),
            Tok::Other(c) => write!(f, "'{c}'"),
            Tok::Eof => f.write_str("end of routine"),
        }
    }
}

/// A token with its place: character offsets into the text and its line
/// and column.
#[derive(Debug, Clone, PartialEq)]
pub struct Token {
    /// What it is.
    pub tok: Tok,
    /// Offset of its first character.
    pub start: usize,
    /// Offset one past its last character.
    pub end: usize,
    /// Line and column of its first character.
    pub pos: Pos,
}

/// A lexical error: an unterminated comment or a malformed number.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LexError {
    /// Where it starts.
    pub pos: Pos,
    /// What is wrong.
    pub message: String,
}

const SYMBOLS: [&str; 22] = [
    ":=", "..", "**", "<>", "<=", ">=", "(", ")", "[", "]", ",", ";", ".", ":", "+", "-", "*", "/", "=", "<", ">", "&",
];

const STATUS_FLAGS: [&str; 6] = ["FS", "N", "Z", "V", "C", "MINOR"];

/// Splits a routine into tokens; the last one is [`Tok::Eof`].
///
/// # Errors
/// [`LexError`] for an unterminated block comment or a malformed number.
pub fn lex(text: &str) -> Result<Vec<Token>, LexError> {
    let chars: Vec<char> = text.chars().collect();
    let mut lexer = Lexer {
        chars: &chars,
        at: 0,
        line: 1,
        column: 1,
    };
    let mut out = Vec::new();
    loop {
        lexer.skip_space_and_comments()?;
        let start = lexer.at;
        let pos = lexer.pos();
        let Some(&c) = chars.get(start) else {
            out.push(Token {
                tok: Tok::Eof,
                start,
                end: start,
                pos,
            });
            return Ok(out);
        };
        let tok = if c.is_ascii_digit() {
            lexer.number()?
        } else if c.is_ascii_alphabetic() || c == '_' {
            lexer.word()
        } else if let Some(sym) = SYMBOLS
            .iter()
            .find(|s| s.chars().enumerate().all(|(i, sc)| chars.get(start + i) == Some(&sc)))
        {
            lexer.advance(sym.chars().count());
            Tok::Sym(sym)
        } else {
            lexer.advance(1);
            Tok::Other(c)
        };
        out.push(Token {
            tok,
            start,
            end: lexer.at,
            pos,
        });
    }
}

struct Lexer<'a> {
    chars: &'a [char],
    at: usize,
    line: u32,
    column: u32,
}

impl Lexer<'_> {
    fn pos(&self) -> Pos {
        Pos {
            line: self.line,
            column: self.column,
        }
    }

    fn peek(&self, ahead: usize) -> Option<char> {
        self.chars.get(self.at + ahead).copied()
    }

    fn advance(&mut self, n: usize) {
        for _ in 0..n {
            if let Some(c) = self.peek(0) {
                if c == '\n' {
                    self.line += 1;
                    self.column = 1;
                } else {
                    self.column += 1;
                }
                self.at += 1;
            }
        }
    }

    fn skip_space_and_comments(&mut self) -> Result<(), LexError> {
        loop {
            match (self.peek(0), self.peek(1)) {
                (Some(c), _) if c.is_whitespace() => self.advance(1),
                (Some('/'), Some('/')) => {
                    while self.peek(0).is_some_and(|c| c != '\n') {
                        self.advance(1);
                    }
                }
                (Some('('), Some('*')) => self.block_comment("*)")?,
                (Some('/'), Some('*')) => self.block_comment("*/")?,
                _ => return Ok(()),
            }
        }
    }

    fn block_comment(&mut self, close: &str) -> Result<(), LexError> {
        let pos = self.pos();
        let close: Vec<char> = close.chars().collect();
        self.advance(2);
        loop {
            match (self.peek(0), self.peek(1)) {
                (Some(a), Some(b)) if a == close[0] && b == close[1] => {
                    self.advance(2);
                    return Ok(());
                }
                (Some(_), _) => self.advance(1),
                (None, _) => {
                    return Err(LexError {
                        pos,
                        message: format!("comment not closed: expected '{}'", close.iter().collect::<String>()),
                    });
                }
            }
        }
    }

    fn word(&mut self) -> Tok {
        let start = self.at;
        while self.peek(0).is_some_and(|c| c.is_ascii_alphanumeric() || c == '_') {
            self.advance(1);
        }
        let mut word: String = self.chars[start..self.at].iter().collect();
        if word.eq_ignore_ascii_case("S") && self.peek(0) == Some(':') {
            let rest: String = self.chars[self.at + 1..]
                .iter()
                .take_while(|c| c.is_ascii_alphabetic())
                .collect();
            if let Some(flag) = STATUS_FLAGS.iter().find(|f| f.eq_ignore_ascii_case(&rest)) {
                self.advance(1 + rest.len());
                word = format!("S:{flag}");
            }
        }
        Tok::Ident(word)
    }

    fn digits(&mut self, radix: u32) -> String {
        let mut out = String::new();
        while let Some(c) = self.peek(0) {
            if c == '_' {
                self.advance(1);
            } else if c.is_digit(radix) {
                out.push(c);
                self.advance(1);
            } else {
                break;
            }
        }
        out
    }

    fn number(&mut self) -> Result<Tok, LexError> {
        let pos = self.pos();
        let bad = |message: String| LexError { pos, message };
        let whole = self.digits(10);
        if self.peek(0) == Some('#') {
            let radix = match whole.as_str() {
                "2" => 2,
                "8" => 8,
                "16" => 16,
                _ => return Err(bad(format!("'{whole}#': the base of a literal is 2, 8 or 16"))),
            };
            self.advance(1);
            let digits = self.digits(radix);
            if digits.is_empty() || self.peek(0).is_some_and(|c| c.is_ascii_alphanumeric()) {
                return Err(bad(format!("'{whole}#…': expected base-{radix} digits")));
            }
            return i128::from_str_radix(&digits, radix)
                .map(Tok::Int)
                .map_err(|_| bad(format!("'{whole}#{digits}' is too large")));
        }
        let mut text = whole;
        let mut real = false;
        if self.peek(0) == Some('.') && self.peek(1).is_some_and(|c| c.is_ascii_digit()) {
            self.advance(1);
            text.push('.');
            text.push_str(&self.digits(10));
            real = true;
        }
        if matches!(self.peek(0), Some('e' | 'E')) {
            let signed = matches!(self.peek(1), Some('+' | '-'));
            let digit_at = if signed { 2 } else { 1 };
            if self.peek(digit_at).is_some_and(|c| c.is_ascii_digit()) {
                text.push('e');
                if signed {
                    text.push(self.peek(1).unwrap_or('+'));
                }
                self.advance(digit_at);
                text.push_str(&self.digits(10));
                real = true;
            }
        }
        if self.peek(0).is_some_and(|c| c.is_ascii_alphabetic() || c == '_') {
            return Err(bad(format!("'{text}' is followed by a letter: expected a number")));
        }
        if real {
            text.parse::<f64>()
                .map(Tok::Real)
                .map_err(|_| bad(format!("'{text}' is not a number")))
        } else {
            text.parse::<i128>()
                .map(Tok::Int)
                .map_err(|_| bad(format!("'{text}' is too large")))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn toks(text: &str) -> Vec<Tok> {
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
    fn comments_of_three_kinds_and_positions() {
        let t = lex("a // x\n(* y\n *) b /* z */ c").unwrap();
        let names: Vec<_> = t.iter().map(|t| (t.tok.clone(), t.pos.line, t.pos.column)).collect();
        assert_eq!(names[0], (Tok::Ident("a".into()), 1, 1));
        assert_eq!(names[1], (Tok::Ident("b".into()), 3, 5));
        assert_eq!(names[2], (Tok::Ident("c".into()), 3, 15));
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
    }
}
