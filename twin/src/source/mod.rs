//! The first stage: the files a user wrote ([`Files`]), and
//! the texts the front-end parses inside them ([`Source`]) — a whole file
//! (a routine), or a string that sits at an offset inside one (a scene's
//! `call`, `when` or trace tag, later a ladder rung or an L5X routine's
//! CDATA). Every [`Span`] is a byte range of a *file*, so a message can
//! show the file's line with a caret under the place, wherever the text
//! was parsed from. [`diag`] is the one error type every later stage
//! reports a user's input with.

pub mod diag;
mod file;
pub mod read;

pub use diag::{Diagnostic, Label, Severity};
pub use file::SourceFile;
pub use read::{InputKind, read_bounded, read_text_bounded};

use std::fmt;
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// A file's place in [`Files`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct FileId(u32);

/// The files of one scene: the scene file, its routines.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Files {
    files: Vec<Arc<SourceFile>>,
}

impl Files {
    /// Adds a file and returns its id.
    pub fn add(&mut self, path: impl Into<PathBuf>, text: impl Into<Arc<str>>) -> FileId {
        self.files.push(Arc::new(SourceFile::new(path, text)));
        FileId(self.files.len() as u32 - 1)
    }

    /// The file `id`.
    ///
    /// # Panics
    /// For an id of other [`Files`].
    #[must_use]
    pub fn get(&self, id: FileId) -> &Arc<SourceFile> {
        &self.files[id.0 as usize]
    }

    /// Every file, in the order they were added.
    pub fn iter(&self) -> impl Iterator<Item = &Arc<SourceFile>> {
        self.files.iter()
    }

    /// The file's path.
    #[must_use]
    pub fn path(&self, id: FileId) -> &Path {
        &self.get(id).path
    }

    /// The 1-based line and column (characters) a span starts at.
    #[must_use]
    pub fn line_column(&self, span: Span) -> (usize, usize) {
        self.get(span.file).line_column(span.start as usize)
    }

    /// The 1-based line a span starts at.
    #[must_use]
    pub fn line(&self, span: Span) -> usize {
        self.get(span.file).line(span.start as usize)
    }

    /// A label on `span`, saying `message` there.
    #[must_use]
    pub fn label(&self, span: Span, message: impl Into<String>) -> Label {
        Label::new(self.get(span.file), span.range(), message)
    }

    /// An error at `span`, its label saying `label`.
    #[must_use]
    pub fn error(&self, span: Span, message: impl Into<String>, label: impl Into<String>) -> Diagnostic {
        Diagnostic::error(message).with_label(self.label(span, label))
    }
}

/// A byte range of a file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct Span {
    /// The file.
    pub file: FileId,
    /// Its first byte.
    pub start: u32,
    /// One past its last byte.
    pub end: u32,
}

impl Span {
    /// Bytes `range` of `file`.
    #[must_use]
    pub fn new(file: FileId, range: Range<usize>) -> Span {
        Span {
            file,
            start: range.start as u32,
            end: range.end.max(range.start) as u32,
        }
    }

    /// From the start of `self` to the end of `other` (same file).
    #[must_use]
    pub fn to(self, other: Span) -> Span {
        Span {
            end: other.end.max(self.end),
            ..self
        }
    }

    /// The byte range.
    #[must_use]
    pub fn range(self) -> Range<usize> {
        self.start as usize..self.end as usize
    }
}

impl fmt::Display for Span {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}..{}", self.start, self.end)
    }
}

/// A text to parse and where its bytes sit in their file.
#[derive(Debug, Clone)]
pub struct Source<'a> {
    /// The text.
    pub text: &'a str,
    /// Its file's id.
    pub id: FileId,
    /// Its file.
    pub file: Arc<SourceFile>,
    /// The file byte of each text byte, and one past the end; `None`
    /// when the text is the file's own.
    map: Option<Arc<[u32]>>,
}

impl<'a> Source<'a> {
    /// The whole text of file `id` of `files`.
    #[must_use]
    pub fn file(files: &'a Files, id: FileId) -> Self {
        let file = files.get(id);
        Source {
            text: &file.text,
            id,
            file: Arc::clone(file),
            map: None,
        }
    }

    /// A text that sits inside file `id` of `files`: `map[i]` is the file
    /// byte of text byte `i` (`text.len() + 1` entries, see
    /// [`toml_string_map`]).
    #[must_use]
    pub fn embedded(text: &'a str, files: &Files, id: FileId, map: Arc<[u32]>) -> Self {
        debug_assert_eq!(map.len(), text.len() + 1);
        Source {
            text,
            id,
            file: Arc::clone(files.get(id)),
            map: Some(map),
        }
    }

    /// The file span of text bytes `start..end`.
    #[must_use]
    pub fn span(&self, start: usize, end: usize) -> Span {
        let at = |i: usize| match &self.map {
            None => i as u32,
            Some(map) => map[i.min(map.len() - 1)],
        };
        let (start, end) = (at(start), at(end));
        Span {
            file: self.id,
            start,
            end: end.max(start),
        }
    }

    /// A label on file span `span` (of this source's file).
    #[must_use]
    pub fn label(&self, span: Span, message: impl Into<String>) -> Label {
        Label::new(&self.file, span.range(), message)
    }
}

/// The file byte of each byte of a TOML string's value (and one past its
/// end), given the file's text, the string's span in it (quotes included)
/// and the decoded value: escapes (`\"`, `\n`, `\u00B2`, a line-ending
/// backslash) map to the bytes that wrote them. When the value cannot be
/// followed through the raw text, every byte maps to the string's start.
#[must_use]
pub fn toml_string_map(file_text: &str, span: Range<usize>, value: &str) -> Arc<[u32]> {
    decode_map(file_text, span.clone(), value).unwrap_or_else(|| vec![span.start as u32; value.len() + 1].into())
}

fn decode_map(file_text: &str, span: Range<usize>, value: &str) -> Option<Arc<[u32]>> {
    let raw = file_text.get(span.clone())?;
    let (quote, literal) = if raw.starts_with("\"\"\"") {
        (3, false)
    } else if raw.starts_with("'''") {
        (3, true)
    } else if raw.starts_with('"') {
        (1, false)
    } else if raw.starts_with('\'') {
        (1, true)
    } else {
        return None;
    };
    let mut at = span.start + quote;
    let end = span.end.checked_sub(quote)?;
    // A multi-line string drops the line break right after its opening.
    if quote == 3 {
        if file_text[at..].starts_with("\r\n") {
            at += 2;
        } else if file_text[at..].starts_with('\n') {
            at += 1;
        }
    }
    let mut map = Vec::with_capacity(value.len() + 1);
    let mut decoded = String::with_capacity(value.len());
    while at < end {
        let rest = &file_text[at..end];
        let c = rest.chars().next()?;
        if c == '\\' && !literal {
            let next = rest[1..].chars().next()?;
            let (ch, len) = match next {
                'b' => (Some('\u{8}'), 2),
                't' => (Some('\t'), 2),
                'n' => (Some('\n'), 2),
                'f' => (Some('\u{c}'), 2),
                'r' => (Some('\r'), 2),
                '"' => (Some('"'), 2),
                '\\' => (Some('\\'), 2),
                'e' => (Some('\u{1b}'), 2),
                'u' | 'U' => {
                    let n = if next == 'u' { 4 } else { 8 };
                    let hex = rest.get(2..2 + n)?;
                    (Some(char::from_u32(u32::from_str_radix(hex, 16).ok()?)?), 2 + n)
                }
                'x' => {
                    let hex = rest.get(2..4)?;
                    (Some(char::from_u32(u32::from_str_radix(hex, 16).ok()?)?), 4)
                }
                // A line-ending backslash: the break and the white space
                // after it are not part of the value.
                c if c.is_whitespace() => {
                    let skip = rest[1..]
                        .find(|c: char| !c.is_whitespace())
                        .map_or(rest.len(), |i| i + 1);
                    (None, skip)
                }
                _ => return None,
            };
            if let Some(ch) = ch {
                for _ in 0..ch.len_utf8() {
                    map.push(at as u32);
                }
                decoded.push(ch);
            }
            at += len;
        } else {
            for i in 0..c.len_utf8() {
                map.push((at + i) as u32);
            }
            decoded.push(c);
            at += c.len_utf8();
        }
    }
    map.push(at as u32);
    (decoded == value).then(|| map.into())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mapped(file: &str, value: &str) -> Vec<u32> {
        let start = file.find(['"', '\'']).expect("a string");
        let end = file.rfind(['"', '\'']).expect("a string") + 1;
        toml_string_map(file, start..end, value).to_vec()
    }

    #[test]
    fn plain_strings_map_byte_for_byte() {
        let file = "call = \"MAM(A)\"";
        assert_eq!(mapped(file, "MAM(A)"), vec![8, 9, 10, 11, 12, 13, 14]);
    }

    #[test]
    fn escapes_map_to_the_bytes_that_wrote_them() {
        // `\u00B2` writes the two bytes of '²'.
        let file = r#"call = "a\"b\u00B2c""#;
        let m = mapped(file, "a\"b²c");
        assert_eq!(m, vec![8, 9, 11, 12, 12, 18, 19]);
        let f = SourceFile::new("s.toml", file);
        assert_eq!(f.line_column(m[5] as usize), (1, 19));
    }

    #[test]
    fn a_value_that_does_not_decode_maps_to_the_start() {
        assert_eq!(mapped("x = \"ab\"", "zz"), vec![4, 4, 4]);
    }

    #[test]
    fn a_files_line_index_does_not_change_its_equality() {
        let a = SourceFile::new("s.toml", "x = 1\ny = 2\n");
        let b = SourceFile::new("s.toml", "x = 1\ny = 2\n");
        assert_eq!(a.line_column(8), (2, 3));
        assert_eq!(a, b);
        assert_ne!(a, SourceFile::new("t.toml", "x = 1\ny = 2\n"));
    }

    #[test]
    fn a_token_at_a_line_and_column() {
        let f = SourceFile::new("s.toml", "[robot]\njoint = \"platter_jnt\"\nx = [1.5, 2]\n");
        assert_eq!(&f.text[f.token_at(2, 9)], "\"platter_jnt\"");
        assert_eq!(&f.text[f.token_at(3, 6)], "1.5");
        assert_eq!(&f.text[f.token_at(3, 11)], "2");
    }

    #[test]
    fn lines_and_columns_count_characters() {
        let f = SourceFile::new("r.st", "a := 1;\nb² := 2;");
        assert_eq!(f.line_column(0), (1, 1));
        assert_eq!(f.line_column(8), (2, 1));
        assert_eq!(f.line_column(11), (2, 3));
        assert_eq!(f.line_column(99), (2, 9));
    }
}
