//! Diagnostics: the one error type for what a user wrote — a scene, a
//! routine, a call, a URDF — rendered as rustc and cargo render theirs.
//!
//! ```text
//! error: scenes/cell.toml:57:20: program[3].call: unknown instruction 'MCLN'
//!   --> scenes/cell.toml:57:20
//!    |
//! 57 | call = "MCLN(XYZ, L1, 0, Pos[0], 100, unitspersec)"
//!    |         ^^^^ not an instruction the twin knows
//!    |
//!    = help: did you mean 'MCLM'?
//! ```
//!
//! The first line is the error as one line (`FILE:LINE:COLUMN: FIELD:
//! message`, what [`Diagnostic`]'s `Display` gives and scripts grep); then
//! the place, the source line with a caret under the span and its label,
//! other places the error involves, and `help:` and `note:` lines.
//! Rendering uses codespan-reporting (chosen for its rustc-style layout
//! with `-->`, `|` and `= help:` in ASCII, and for being in the lock file
//! already, through wgpu's shader compiler, with only unicode-width under
//! it); colour is plain ANSI, off when stderr is not a terminal or
//! `NO_COLOR` is set.

use super::file::SourceFile;
use codespan_reporting::diagnostic::{Diagnostic as Report, Label as ReportLabel, LabelStyle, Severity as Level};
use codespan_reporting::files::SimpleFiles;
use codespan_reporting::term::{self, Chars, Config, GeneralWriteResult, WriteStyle};
use std::fmt;
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// How bad it is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Severity {
    /// The input cannot be used.
    Error,
    /// The input runs, but not as its author probably meant.
    Warning,
}

/// A place in a file, with what to say there.
#[derive(Debug, Clone, PartialEq)]
pub struct Label {
    /// The file.
    pub file: Arc<SourceFile>,
    /// Its bytes the label underlines.
    pub range: Range<usize>,
    /// What to say there (may be empty).
    pub message: String,
}

impl Label {
    /// A label on `range` of `file`.
    #[must_use]
    pub fn new(file: &Arc<SourceFile>, range: Range<usize>, message: impl Into<String>) -> Self {
        let len = file.text.len();
        let start = range.start.min(len);
        Label {
            file: Arc::clone(file),
            range: start..range.end.clamp(start, len),
            message: message.into(),
        }
    }
}

/// An error or warning about something a user wrote. See the module doc.
#[derive(Debug, Clone, PartialEq)]
pub struct Diagnostic {
    /// Error or warning.
    pub severity: Severity,
    /// The scene field it is about (`program[3].call`), if any.
    pub field: Option<String>,
    /// What is wrong, in one line.
    pub message: String,
    /// The places: the first is where the error is.
    pub labels: Vec<Label>,
    /// Where it is when no text can be shown (a file that cannot be read,
    /// a place known only by line and column): file, line, column.
    pub place: Option<(PathBuf, usize, usize)>,
    /// `help:` lines: what to write instead.
    pub help: Vec<String>,
    /// `note:` lines: why.
    pub notes: Vec<String>,
}

impl Diagnostic {
    /// An error saying `message`.
    #[must_use]
    pub fn error(message: impl Into<String>) -> Self {
        Diagnostic {
            severity: Severity::Error,
            field: None,
            message: message.into(),
            labels: Vec::new(),
            place: None,
            help: Vec::new(),
            notes: Vec::new(),
        }
    }

    /// A warning saying `message`.
    #[must_use]
    pub fn warning(message: impl Into<String>) -> Self {
        Diagnostic {
            severity: Severity::Warning,
            ..Diagnostic::error(message)
        }
    }

    /// The scene field it is about.
    #[must_use]
    pub fn in_field(mut self, field: impl Into<String>) -> Self {
        self.field = Some(field.into());
        self
    }

    /// Adds a place (the first is where the error is).
    #[must_use]
    pub fn with_label(mut self, label: Label) -> Self {
        self.labels.push(label);
        self
    }

    /// Where it is, by line and column, when no text can be shown.
    #[must_use]
    pub fn at_place(mut self, path: impl Into<PathBuf>, line: usize, column: usize) -> Self {
        self.place = Some((path.into(), line, column));
        self
    }

    /// When it knows only a file, line and column (a check after
    /// loading), labels the token there, the file's text read from disk,
    /// so the rendering shows the line; unchanged when the file cannot be
    /// read.
    #[must_use]
    pub fn labelled_from_file(mut self) -> Self {
        if !self.labels.is_empty() {
            return self;
        }
        let Some((path, line, column)) = self.place.clone() else {
            return self;
        };
        let Ok(text) = super::read::read_text_bounded(&path, super::read::InputKind::L5x) else {
            return self;
        };
        let file = Arc::new(SourceFile::new(path, text));
        let range = file.token_at(line, column);
        if file.line_column(range.start) != (line, column) {
            return self;
        }
        self.place = None;
        self.labels.push(Label::new(&file, range, ""));
        self
    }

    /// Adds a `help:` line.
    #[must_use]
    pub fn with_help(mut self, help: impl Into<String>) -> Self {
        self.help.push(help.into());
        self
    }

    /// Adds a `note:` line.
    #[must_use]
    pub fn with_note(mut self, note: impl Into<String>) -> Self {
        self.notes.push(note.into());
        self
    }

    /// The file, line and column (1-based, characters) it is at.
    #[must_use]
    pub fn location(&self) -> Option<(&Path, usize, usize)> {
        if let Some(l) = self.labels.first() {
            let (line, column) = l.file.line_column(l.range.start);
            return Some((&l.file.path, line, column));
        }
        self.place.as_ref().map(|(p, l, c)| (p.as_path(), *l, *c))
    }

    /// The whole diagnostic as the terminal shows it: the first line, then
    /// the source lines with their carets and the `help:` lines. `color`
    /// adds ANSI colours.
    #[must_use]
    pub fn render(&self, color: bool) -> String {
        let level = match self.severity {
            Severity::Error => Level::Error,
            Severity::Warning => Level::Warning,
        };
        let mut files = SimpleFiles::new();
        let mut ids: Vec<(*const SourceFile, usize)> = Vec::new();
        let mut labels = Vec::with_capacity(self.labels.len());
        for (i, l) in self.labels.iter().enumerate() {
            let key = Arc::as_ptr(&l.file);
            let id = match ids.iter().find(|(k, _)| *k == key) {
                Some((_, id)) => *id,
                None => {
                    let id = files.add(l.file.path.display().to_string(), l.file.text.clone());
                    ids.push((key, id));
                    id
                }
            };
            let style = if i == 0 {
                LabelStyle::Primary
            } else {
                LabelStyle::Secondary
            };
            labels.push(ReportLabel::new(style, id, l.range.clone()).with_message(&l.message));
        }
        let notes = self
            .help
            .iter()
            .map(|h| format!("help: {h}"))
            .chain(self.notes.iter().map(|n| format!("note: {n}")))
            .collect();
        let report = Report::new(level)
            .with_message(self.to_string())
            .with_labels(labels)
            .with_notes(notes);
        let config = Config {
            chars: Chars::ascii(),
            ..Config::default()
        };
        let mut out = Vec::new();
        let written = if color {
            term::emit_to_write_style(&mut Ansi(&mut out), &config, &files, &report)
        } else {
            term::emit_to_io_write(&mut out, &config, &files, &report)
        };
        match written {
            Ok(()) => String::from_utf8_lossy(&out).into_owned(),
            // The files are the labels' own: rendering cannot miss one.
            Err(_) => format!("{}: {self}\n", self.severity_word()),
        }
    }

    fn severity_word(&self) -> &'static str {
        match self.severity {
            Severity::Error => "error",
            Severity::Warning => "warning",
        }
    }
}

impl fmt::Display for Diagnostic {
    /// The first line: `FILE:LINE:COLUMN: FIELD: message`, the parts it
    /// has.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some((path, line, column)) = self.location() {
            write!(f, "{}:{line}:{column}: ", path.display())?;
        }
        if let Some(field) = &self.field {
            write!(f, "{field}: ")?;
        }
        f.write_str(&self.message)
    }
}

impl std::error::Error for Diagnostic {}

/// An error and its causes on one line, `: ` between them, each cause
/// left out whose text the line already holds (a wrapper that repeats its
/// source's message).
#[must_use]
pub fn with_causes(error: &(dyn std::error::Error + 'static)) -> String {
    let mut text = error.to_string();
    let mut cause = error.source();
    while let Some(c) = cause {
        let part = c.to_string();
        if !text.contains(&part) {
            text.push_str(": ");
            text.push_str(&part);
        }
        cause = c.source();
    }
    text
}

/// Whether diagnostics on stderr should be coloured: a terminal, and no
/// `NO_COLOR` (<https://no-color.org>).
#[must_use]
pub fn stderr_wants_color() -> bool {
    use std::io::IsTerminal as _;
    std::env::var_os("NO_COLOR").is_none_or(|v| v.is_empty()) && std::io::stderr().is_terminal()
}

/// The known name nearest to `name` (case-insensitive), when it is near
/// enough to be a typing slip: at most a third of the name's letters
/// differ (one for short names).
#[must_use]
pub fn nearest<'a>(name: &str, known: impl IntoIterator<Item = &'a str>) -> Option<&'a str> {
    let lower = name.to_lowercase();
    let allowed = (lower.chars().count() / 3).max(1);
    known
        .into_iter()
        .map(|k| (strsim::damerau_levenshtein(&lower, &k.to_lowercase()), k))
        .filter(|(d, k)| *d <= allowed && *d > 0 || (*d == 0 && *k != name))
        // At equal distance, a name the slip is the start of (`L` → `L1`).
        .min_by_key(|(d, k)| (*d, !k.to_lowercase().starts_with(&lower)))
        .map(|(_, k)| k)
}

/// ANSI colours on a byte buffer, the styles rustc uses.
struct Ansi<'a>(&'a mut Vec<u8>);

impl std::io::Write for Ansi<'_> {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.0.extend_from_slice(buf);
        Ok(buf.len())
    }

    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

impl Ansi<'_> {
    fn code(&mut self, code: &str) -> GeneralWriteResult {
        self.0.extend_from_slice(code.as_bytes());
        Ok(())
    }
}

impl WriteStyle for Ansi<'_> {
    fn set_header(&mut self, severity: Level) -> GeneralWriteResult {
        self.code(match severity {
            Level::Bug | Level::Error => "\x1b[1;31m",
            Level::Warning => "\x1b[1;33m",
            Level::Note => "\x1b[1;32m",
            Level::Help => "\x1b[1;36m",
        })
    }

    fn set_header_message(&mut self) -> GeneralWriteResult {
        self.code("\x1b[1m")
    }

    fn set_line_number(&mut self) -> GeneralWriteResult {
        self.code("\x1b[1;34m")
    }

    fn set_note_bullet(&mut self) -> GeneralWriteResult {
        self.code("\x1b[1;34m")
    }

    fn set_source_border(&mut self) -> GeneralWriteResult {
        self.code("\x1b[1;34m")
    }

    fn set_label(&mut self, severity: Level, label_style: LabelStyle) -> GeneralWriteResult {
        match (label_style, severity) {
            (LabelStyle::Secondary, _) => self.code("\x1b[1;34m"),
            (_, Level::Warning) => self.code("\x1b[1;33m"),
            _ => self.code("\x1b[1;31m"),
        }
    }

    fn reset(&mut self) -> GeneralWriteResult {
        self.code("\x1b[0m")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn file(text: &str) -> Arc<SourceFile> {
        Arc::new(SourceFile::new("scene.toml", text))
    }

    #[test]
    fn the_first_line_is_the_one_line_error_and_the_caret_sits_under_the_span() {
        let f = file("[robot]\ncall = \"MCLN(CS1)\"\n");
        let d = Diagnostic::error("unknown instruction 'MCLN'")
            .in_field("program[0].call")
            .with_label(Label::new(&f, 16..20, "not an instruction the twin knows"))
            .with_help("did you mean 'MCLM'?");
        assert_eq!(
            d.to_string(),
            "scene.toml:2:9: program[0].call: unknown instruction 'MCLN'"
        );
        let text = d.render(false);
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(
            lines[0],
            "error: scene.toml:2:9: program[0].call: unknown instruction 'MCLN'"
        );
        assert_eq!(lines[1], "  --> scene.toml:2:9");
        assert_eq!(lines[3], "2 | call = \"MCLN(CS1)\"");
        assert_eq!(lines[4], "  |         ^^^^ not an instruction the twin knows");
        assert_eq!(lines[6], "  = help: did you mean 'MCLM'?");
        assert!(d.render(true).contains("\x1b[1;31m"), "coloured");
    }

    #[test]
    fn a_place_without_text_still_names_file_line_and_column() {
        let d = Diagnostic::error("cannot read").at_place("r.st", 0, 0);
        assert_eq!(d.to_string(), "r.st:0:0: cannot read");
        assert_eq!(d.render(false).lines().next(), Some("error: r.st:0:0: cannot read"));
    }

    #[test]
    fn the_nearest_name_is_a_typing_slip_away() {
        let known = ["MCLM", "MCCM", "MAM", "MAJ"];
        assert_eq!(nearest("MCLN", known), Some("MCLM"));
        assert_eq!(nearest("mccm", known), Some("MCCM"));
        assert_eq!(nearest("XYZW", known), None);
        assert_eq!(nearest("Tabel", ["Table", "Cam"]), Some("Table"));
        assert_eq!(nearest("L", ["X", "L1"]), Some("L1"), "a name it starts");
    }
}
