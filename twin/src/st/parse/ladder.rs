//! Ladder rungs in the neutral text of an L5X export, parsed by the same
//! lexer and parser as Structured Text (one token and span type): a
//! routine file `*.rll` holds one rung a line; blank lines and lines
//! starting with `#` are skipped.
//!
//! ```text
//! rung     = element* ";"
//! element  = instruction | branch
//! branch   = "[" leg ("," leg)* "]"          (nested to MAX_BRANCH_NESTING)
//! leg      = element*                        (an empty leg is a wire)
//! instruction = NAME "(" operand ("," operand)* ")" | NAME "(" ")"
//! ```
//!
//! Instructions in series may be separated by spaces or nothing
//! (`XIC(A)OTE(B);`). An operand is a tag, member, bit, literal, an
//! expression (CPT's and CMP's), `?` (a display value the instruction
//! does not read), or an enumeration word as Studio displays it (`Units
//! per sec`), kept as its text without spaces.

use super::{MAX_BRANCH_NESTING, Parser, R};
use crate::source::Diagnostic;
use crate::st::ast::{Element, Rung};
use crate::st::lex::Tok;

impl Parser<'_> {
    /// One rung: its elements, then `;` as the line's last token.
    pub(super) fn rung(&mut self, number: u32) -> R<Rung> {
        let first = self.at;
        let elements = self.elements(0)?;
        if !self.is_sym(";") {
            return Err(match self.tok(0) {
                Tok::Eof => self.error(
                    self.span_at(self.end.saturating_sub(1)),
                    "the rung does not end with ';'",
                    "end the rung here with ';'",
                ),
                Tok::Sym(",") => self.error(self.span(0), "',' outside a branch", "a branch leg starts after '['"),
                Tok::Sym("]") => self.error(self.span(0), "']' without its '['", "no branch is open here"),
                _ => self.unexpected("an instruction, '[' or ';'"),
            });
        }
        self.bump();
        if !self.at_end() {
            return Err(self.error(
                self.span(0),
                format!("text after the rung's ';': {}", self.tok(0)),
                "one rung a line",
            ));
        }
        Ok(Rung {
            number,
            elements,
            span: self.span_from(first),
        })
    }

    /// Elements in series up to `;`, `,`, `]` or the end of the line.
    fn elements(&mut self, depth: usize) -> R<Vec<Element>> {
        let mut out = Vec::new();
        loop {
            match self.tok(0).clone() {
                Tok::Sym("[") => out.push(self.branch(depth)?),
                Tok::Ident(name) if matches!(self.tok(1), Tok::Sym("(")) => {
                    let span = self.span(0);
                    self.bump();
                    out.push(Element::Instruction(self.call(name.into_owned(), span)?));
                }
                Tok::Ident(name) => {
                    return Err(self.error(
                        self.span(0),
                        format!("expected '(' after the instruction {name}, found {}", self.tok(1)),
                        "an instruction takes its operands in parentheses",
                    ));
                }
                Tok::Sym(";" | "," | "]") | Tok::Eof => return Ok(out),
                _ => return Err(self.unexpected("an instruction, '[' or ';'")),
            }
        }
    }

    /// `[leg ,leg …]`.
    fn branch(&mut self, depth: usize) -> R<Element> {
        let open = self.at;
        if depth >= MAX_BRANCH_NESTING {
            return Err(self.error(
                self.span(0),
                format!("branches nested deeper than {MAX_BRANCH_NESTING} levels"),
                "too deep here",
            ));
        }
        self.bump();
        let mut legs = vec![self.elements(depth + 1)?];
        while self.is_sym(",") {
            self.bump();
            legs.push(self.elements(depth + 1)?);
        }
        if !self.is_sym("]") {
            let found = self.tok(0);
            return Err(Box::new(
                Diagnostic::error(format!("this branch is never closed: expected ']', found {found}"))
                    .with_label(self.source.label(self.span_at(open), "'[' opened here"))
                    .with_label(self.source.label(self.span(0), "expected ']' before this")),
            ));
        }
        self.bump();
        Ok(Element::Branch(legs, self.span_from(open)))
    }
}
