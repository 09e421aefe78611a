//! A file the user wrote, and where a byte of it is.

use std::ops::Range;
use std::path::PathBuf;
use std::sync::{Arc, OnceLock};

/// A file the user wrote, as read. Two are equal when their paths and
/// texts are (whether either has made its line index does not count).
#[derive(Debug)]
pub struct SourceFile {
    /// Its path, as the user named it (messages print it).
    pub path: PathBuf,
    /// Its text.
    pub text: Arc<str>,
    /// The byte each line starts at, made on first use: a large file (an
    /// L5X export of tens of megabytes) answers [`SourceFile::line_column`]
    /// in a binary search, not a scan from its start.
    lines: OnceLock<Vec<usize>>,
}

impl PartialEq for SourceFile {
    fn eq(&self, other: &Self) -> bool {
        self.path == other.path && self.text == other.text
    }
}

impl Eq for SourceFile {}

impl SourceFile {
    /// A file and its text.
    #[must_use]
    pub fn new(path: impl Into<PathBuf>, text: impl Into<Arc<str>>) -> Self {
        SourceFile {
            path: path.into(),
            text: text.into(),
            lines: OnceLock::new(),
        }
    }

    /// The 1-based line and column (in characters) of byte `at`.
    #[must_use]
    pub fn line_column(&self, at: usize) -> (usize, usize) {
        let at = floor_char_boundary(&self.text, at.min(self.text.len()));
        let line = self.line(at);
        let line_start = self.lines()[line - 1];
        (line, self.text[line_start..at].chars().count() + 1)
    }

    /// The 1-based line of byte `at`.
    #[must_use]
    pub fn line(&self, at: usize) -> usize {
        self.lines().partition_point(|&start| start <= at)
    }

    /// The first byte of each line.
    fn lines(&self) -> &[usize] {
        self.lines.get_or_init(|| {
            std::iter::once(0)
                .chain(self.text.match_indices('\n').map(|(i, _)| i + 1))
                .collect()
        })
    }

    /// The bytes of the token that starts at 1-based `line` and `column`
    /// (characters): a quoted string, or the text up to white space, a
    /// comma or a closing bracket. For a place known only by line and
    /// column (a check after loading).
    #[must_use]
    pub fn token_at(&self, line: usize, column: usize) -> Range<usize> {
        let text = &*self.text;
        let line_start = text
            .split_inclusive('\n')
            .take(line.saturating_sub(1))
            .map(str::len)
            .sum::<usize>()
            .min(text.len());
        let rest = &text[line_start..];
        let start = line_start
            + rest
                .char_indices()
                .nth(column.saturating_sub(1))
                .map_or(rest.len(), |(i, _)| i);
        let token = &text[start..];
        let len = match token.chars().next() {
            Some(q @ ('"' | '\'')) => token[1..].find(q).map_or(token.len(), |i| i + 2),
            _ => token
                .find(|c: char| c.is_whitespace() || matches!(c, ',' | ']' | '}'))
                .unwrap_or(token.len()),
        };
        start..start + len.max(usize::from(!token.is_empty()))
    }
}

fn floor_char_boundary(text: &str, mut at: usize) -> usize {
    while !text.is_char_boundary(at) {
        at -= 1;
    }
    at
}
