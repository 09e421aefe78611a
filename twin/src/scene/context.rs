//! The validation context: the scene file's text, and the helpers that turn a
//! span into a file:line:column error and check a single value.

use std::cell::RefCell;
use std::collections::HashMap;
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use toml::Spanned;

use super::error::{Problem, SceneError};
use super::model::Location;
use super::raw::{Numbers, ShapeKind};
use crate::source::{Diagnostic, FileId, Files, Source, toml_string_map};

pub(super) struct Ctx<'a> {
    pub(super) file: PathBuf,
    pub(super) text: &'a str,
    /// The scene's files: the scene itself ([`Ctx::scene_file`]) and the
    /// routines read so far.
    pub(super) files: RefCell<Files>,
    /// The scene file's id in `files`.
    pub(super) scene_file: FileId,
    /// The data types known so far: `STRING`, then `[[data_types]]`
    /// (names first, members once checked).
    pub(super) data_types: RefCell<Vec<super::model::DataTypeDef>>,
    /// A scene that names an L5X: `text` is the expanded scene, and this
    /// maps its bytes back to the scene file and the export.
    pub(super) expanded: Option<super::import::Expanded>,
    /// What the scene took from its export.
    pub(super) l5x: Option<super::model::L5xImport>,
    /// The export's routines, parsed on every core before the tasks are
    /// read, by their path in the expanded scene; each is taken when read.
    pub(super) parsed: RefCell<HashMap<PathBuf, Parsed>>,
}

/// A routine parsed ahead of the tasks that name it, or its syntax error.
pub(super) type Parsed = Result<crate::st::ast::Routine, Box<Diagnostic>>;

/// A name's first declaration: (lower-case name) -> (line, what it is).
pub(super) type Names = HashMap<String, (usize, NameKind)>;

#[derive(Clone, Copy)]
pub(super) enum NameKind {
    Axis,
    Tag,
}

/// The longest name that output files are named after, in characters.
const MAX_FILE_NAME_PART: usize = 100;

impl Ctx<'_> {
    pub(super) fn location(&self, byte: usize) -> Location {
        let (file, range) = self.mapped(byte..byte);
        let (line, column) = self.files.borrow().get(file).line_column(range.start);
        Location { line, column }
    }

    pub(super) fn loc<T>(&self, s: &Spanned<T>) -> Location {
        self.location(s.span().start)
    }

    pub(super) fn invalid<T>(&self, at: &Spanned<T>, field: impl Into<String>, problem: Problem) -> SceneError {
        self.invalid_at(at.span(), field, problem)
    }

    pub(super) fn invalid_at(&self, span: Range<usize>, field: impl Into<String>, problem: Problem) -> SceneError {
        let Location { line, column } = self.location(span.start);
        let (file, range) = self.mapped(span.clone());
        let field = match self.expanded.as_ref().and_then(|e| e.map.map(span).2) {
            Some(item) => item.to_owned(),
            None => field.into(),
        };
        let source = Arc::clone(self.files.borrow().get(file));
        SceneError::Invalid {
            file: source.path.clone(),
            line,
            column,
            field,
            problem: Box::new(problem),
            at: Some(Box::new((source, range))),
        }
    }

    /// The file and bytes that expanded-scene bytes `span` stand for (the
    /// scene file's own when the scene names no export).
    pub(super) fn mapped(&self, span: Range<usize>) -> (FileId, Range<usize>) {
        match &self.expanded {
            Some(e) => {
                let (file, range, _) = e.map.map(span);
                (file, range)
            }
            None => (self.scene_file, span),
        }
    }

    pub(super) fn toml_error(&self, e: &toml::de::Error) -> SceneError {
        let start = e.span().map_or(0, |s| s.start);
        // Table and key from the text as parsed (the expanded scene's).
        let (text_line, text_column) = {
            let before = &self.text[..start.min(self.text.len())];
            let line_start = before.rfind('\n').map_or(0, |i| i + 1);
            (
                before.matches('\n').count() + 1,
                before[line_start..].chars().count() + 1,
            )
        };
        let Location { line, column } = self.location(start);
        let table = e.span().and_then(|_| self.table_at(text_line));
        // A value of the wrong type: name its field and say it plainly.
        let plain = plain_type_message(e.message());
        let key = plain
            .as_ref()
            .and(e.span())
            .and_then(|_| self.key_at(text_line, text_column));
        let field = key.map(|key| match &table {
            Some(table) => format!("{table}.{key}"),
            None => key,
        });
        let message = match (&field, plain) {
            (Some(_), Some(plain)) => plain,
            _ => e.message().to_owned(),
        };
        let (file, at) = match e.span() {
            Some(s) => {
                let (id, range) = self.mapped(s);
                let source = Arc::clone(self.files.borrow().get(id));
                (source.path.clone(), Some(Box::new((source, range))))
            }
            None => (self.file.clone(), None),
        };
        SceneError::Toml {
            file,
            line,
            column,
            table,
            field,
            message,
            at,
        }
    }

    /// The key (`max_velocity`, `position.x`, `initial[2]`) whose value
    /// starts at `line`:`column`, when the line says it plainly: `key =
    /// value`, a key of an inline table, an element of a one-line array
    /// (no strings before the value, whose brackets could mislead).
    fn key_at(&self, line: usize, column: usize) -> Option<String> {
        let text = self.text.lines().nth(line.checked_sub(1)?)?;
        let before: String = text.chars().take(column.checked_sub(1)?).collect();
        if before.contains(['"', '\'', '#']) {
            return None;
        }
        // Open inline tables and arrays before the value: each with the
        // key it belongs to, and for an array the commas seen in it.
        let mut open: Vec<(char, String, usize)> = Vec::new();
        let (mut token, mut key) = (String::new(), None::<String>);
        for c in before.chars() {
            match c {
                '=' => key = Some(std::mem::take(&mut token).trim().to_owned()),
                '{' | '[' => {
                    open.push((c, key.take().unwrap_or_default(), 0));
                    token.clear();
                }
                '}' | ']' => {
                    open.pop();
                    token.clear();
                }
                ',' => {
                    if let Some((_, _, commas)) = open.last_mut() {
                        *commas += 1;
                    }
                    token.clear();
                    key = None;
                }
                _ => token.push(c),
            }
        }
        let is_key = |k: &str| {
            !k.is_empty()
                && k.chars()
                    .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-' || c == '.')
        };
        let mut path = Vec::new();
        for (bracket, name, commas) in &open {
            if !is_key(name) {
                return None;
            }
            path.push(if *bracket == '[' {
                format!("{name}[{commas}]")
            } else {
                name.clone()
            });
        }
        match key {
            // `key = ` right before the value.
            Some(k) if token.trim().is_empty() && is_key(&k) => path.push(k),
            // An array element.
            None if token.trim().is_empty() && open.last().is_some_and(|(b, _, _)| *b == '[') => {}
            _ => return None,
        }
        Some(path.join("."))
    }

    /// The table (`axes[1]`, `robot`) whose body contains `line`, from the
    /// nearest header above it.
    pub(super) fn table_at(&self, line: usize) -> Option<String> {
        let mut current = None;
        let mut counts: HashMap<String, usize> = HashMap::new();
        for text in self.text.lines().take(line) {
            let t = text.trim();
            let t = t.split_once('#').map_or(t, |(head, _)| head).trim();
            if let Some(name) = t.strip_prefix("[[").and_then(|r| r.strip_suffix("]]")) {
                let name = name.trim().to_owned();
                let n = counts.entry(name.clone()).or_default();
                current = Some(format!("{name}[{n}]"));
                *n += 1;
            } else if let Some(name) = t.strip_prefix('[').and_then(|r| r.strip_suffix(']')) {
                let name = name.trim();
                if !name.is_empty() && name.chars().all(|c| c.is_alphanumeric() || "_-.\"' ".contains(c)) {
                    current = Some(name.to_owned());
                }
            }
        }
        current
    }

    /// Parses a string value of the scene with `parse` as a source that
    /// sits inside the scene file: errors point into the string, with the
    /// field named.
    pub(super) fn parse_in<T>(
        &self,
        s: &Spanned<String>,
        field: &str,
        parse: impl FnOnce(&Source<'_>) -> Result<T, Box<Diagnostic>>,
    ) -> Result<T, SceneError> {
        let mut map = toml_string_map(self.text, s.span(), s.get_ref());
        let mut file = self.scene_file;
        if let Some(e) = &self.expanded {
            file = e.map.map(s.span()).0;
            map = map
                .iter()
                .map(|&b| e.map.map(b as usize..b as usize).1.start as u32)
                .collect();
        }
        let files = self.files.borrow();
        let source = Source::embedded(s.get_ref(), &files, file, map);
        parse(&source).map_err(|d| SceneError::Syntax(Box::new((*d).in_field(field))))
    }

    pub(super) fn finite(&self, v: &Spanned<f64>, field: &str) -> Result<f64, SceneError> {
        let value = *v.get_ref();
        if value.is_finite() {
            Ok(value)
        } else {
            Err(self.invalid(v, field, Problem::NotFinite { value }))
        }
    }

    /// One of a field's `words` (case-insensitive), as its value; another
    /// word is [`Problem::UnknownWord`], listing them.
    pub(super) fn word<T: Copy>(
        &self,
        raw: &Spanned<String>,
        field: &str,
        what: &'static str,
        words: &[(&'static str, T)],
    ) -> Result<T, SceneError> {
        let word = raw.get_ref().to_ascii_lowercase();
        if let Some((_, v)) = words.iter().find(|(w, _)| *w == word) {
            return Ok(*v);
        }
        let quoted: Vec<String> = words.iter().map(|(w, _)| format!("\"{w}\"")).collect();
        let expected = match quoted.split_last() {
            Some((last, [])) => last.clone(),
            Some((last, rest)) => format!("{} or {last}", rest.join(", ")),
            None => String::new(),
        };
        Err(self.invalid(raw, field, Problem::UnknownWord { what, word, expected }))
    }

    /// A finite value within `min..=max`.
    pub(super) fn in_range(&self, v: &Spanned<f64>, field: &str, min: f64, max: f64) -> Result<f64, SceneError> {
        let value = self.finite(v, field)?;
        if (min..=max).contains(&value) {
            Ok(value)
        } else {
            Err(self.out_of_range(v, field, value, min, max))
        }
    }

    /// An integer within `min..=max`.
    pub(super) fn int_in_range(&self, v: &Spanned<i64>, field: &str, min: i64, max: i64) -> Result<i64, SceneError> {
        let value = *v.get_ref();
        if (min..=max).contains(&value) {
            Ok(value)
        } else {
            Err(self.out_of_range(v, field, value as f64, min as f64, max as f64))
        }
    }

    fn out_of_range<T>(&self, v: &Spanned<T>, field: &str, value: f64, min: f64, max: f64) -> SceneError {
        let problem = Problem::OutOfRange {
            value,
            min,
            max,
            exclusive: false,
        };
        self.invalid(v, field, problem)
    }

    pub(super) fn positive(&self, v: &Spanned<f64>, field: &str) -> Result<f64, SceneError> {
        let value = self.finite(v, field)?;
        if value > 0.0 {
            Ok(value)
        } else {
            Err(self.invalid(v, field, Problem::NotPositive { value }))
        }
    }

    pub(super) fn non_negative(&self, v: &Spanned<f64>, field: &str) -> Result<f64, SceneError> {
        let value = self.finite(v, field)?;
        if value >= 0.0 {
            Ok(value)
        } else {
            Err(self.invalid(v, field, Problem::Negative { value }))
        }
    }

    pub(super) fn finite_array<const N: usize>(
        &self,
        v: &Spanned<Numbers<N>>,
        field: &str,
    ) -> Result<[f64; N], SceneError> {
        let values = v.get_ref().0;
        match values.iter().find(|x| !x.is_finite()) {
            Some(&value) => Err(self.invalid(v, field, Problem::NotFinite { value })),
            None => Ok(values),
        }
    }

    /// Three finite values, each > 0.
    /// An optional [`Ctx::positive`] field: `default` when absent.
    pub(super) fn positive_or(&self, v: &Option<Spanned<f64>>, field: &str, default: f64) -> Result<f64, SceneError> {
        v.as_ref().map_or(Ok(default), |v| self.positive(v, field))
    }

    /// An optional [`Ctx::non_negative`] field: `default` when absent.
    pub(super) fn non_negative_or(
        &self,
        v: &Option<Spanned<f64>>,
        field: &str,
        default: f64,
    ) -> Result<f64, SceneError> {
        v.as_ref().map_or(Ok(default), |v| self.non_negative(v, field))
    }

    pub(super) fn positive_array(&self, v: &Spanned<Numbers<3>>, field: &str) -> Result<[f64; 3], SceneError> {
        let values = self.finite_array(v, field)?;
        match values.iter().find(|x| **x <= 0.0) {
            Some(&value) => Err(self.invalid(v, field, Problem::NotPositive { value })),
            None => Ok(values),
        }
    }

    /// Every value within `(0, max]`.
    pub(super) fn bounded_array(&self, v: &Spanned<Numbers<3>>, field: &str, max: f64) -> Result<[f64; 3], SceneError> {
        let values = self.positive_array(v, field)?;
        self.at_most(v, field, &values, max)?;
        Ok(values)
    }

    /// A value within `(0, max]`.
    pub(super) fn bounded(&self, v: &Spanned<f64>, field: &str, max: f64) -> Result<f64, SceneError> {
        let value = self.positive(v, field)?;
        if value > max {
            let problem = Problem::OutOfRange {
                value,
                min: 0.0,
                max,
                exclusive: false,
            };
            return Err(self.invalid(v, field, problem));
        }
        Ok(value)
    }

    /// Every value's magnitude at most `max`.
    pub(super) fn at_most<T>(&self, v: &Spanned<T>, field: &str, values: &[f64], max: f64) -> Result<(), SceneError> {
        match values.iter().find(|x| x.abs() > max) {
            Some(&value) => {
                let problem = Problem::OutOfRange {
                    value,
                    min: -max,
                    max,
                    exclusive: false,
                };
                Err(self.invalid(v, field, problem))
            }
            None => Ok(()),
        }
    }

    /// A shape is missing a field its kind needs.
    pub(super) fn missing_shape_field<T>(
        &self,
        shape_at: &Spanned<T>,
        field: String,
        shape: &'static str,
        missing: &'static str,
    ) -> SceneError {
        let problem = Problem::MissingShapeField { shape, field: missing };
        self.invalid(shape_at, field, problem)
    }

    pub(super) fn nonempty_name(&self, v: &Spanned<String>, field: &str) -> Result<String, SceneError> {
        if v.get_ref().trim().is_empty() {
            Err(self.invalid(v, field, Problem::Empty))
        } else {
            Ok(v.get_ref().clone())
        }
    }

    /// A name that output files are named after (the scene, a camera):
    /// one path component that stays inside the output folder.
    pub(super) fn file_name_part(&self, v: &Spanned<String>, field: &str) -> Result<String, SceneError> {
        let name = self.nonempty_name(v, field)?;
        let why = if name.contains(['/', '\\']) {
            Some("it holds a path separator ('/' or '\\')")
        } else if name.starts_with('.') {
            Some("it starts with '.'")
        } else if name.chars().any(char::is_control) {
            Some("it holds a control character")
        } else if name.chars().count() > MAX_FILE_NAME_PART {
            Some("it is longer than 100 characters")
        } else {
            None
        };
        match why {
            Some(why) => Err(self.invalid(v, field, Problem::NotAFileName { name, why })),
            None => Ok(name),
        }
    }

    pub(super) fn existing_file(&self, v: &Spanned<String>, field: &str, base: &Path) -> Result<PathBuf, SceneError> {
        let path = base.join(v.get_ref());
        if v.get_ref().is_empty() || !path.is_file() {
            return Err(self.invalid(v, field, Problem::MissingFile { path }));
        }
        Ok(path)
    }

    /// Registers a name, failing on a duplicate (case-insensitive).
    pub(super) fn unique<V>(
        &self,
        seen: &mut HashMap<String, (usize, V)>,
        name: &Spanned<String>,
        field: &str,
        value: V,
    ) -> Result<(), SceneError> {
        let key = name.get_ref().to_lowercase();
        if let Some((first_line, _)) = seen.get(&key) {
            let problem = Problem::DuplicateName {
                name: name.get_ref().clone(),
                first_line: *first_line,
            };
            return Err(self.invalid(name, field, problem));
        }
        seen.insert(key, (self.loc(name).line, value));
        Ok(())
    }

    /// [`Ctx::unique`] against names declared elsewhere, without adding
    /// `name` to them.
    pub(super) fn unique_beside<V>(
        &self,
        others: &HashMap<String, (usize, V)>,
        name: &Spanned<String>,
        field: &str,
    ) -> Result<(), SceneError> {
        match others.get(&name.get_ref().to_lowercase()) {
            Some((first_line, _)) => {
                let problem = Problem::DuplicateName {
                    name: name.get_ref().clone(),
                    first_line: *first_line,
                };
                Err(self.invalid(name, field, problem))
            }
            None => Ok(()),
        }
    }

    pub(super) fn identifier(&self, name: &Spanned<String>, field: &str) -> Result<String, SceneError> {
        let n = name.get_ref();
        let mut chars = n.chars();
        let valid = chars.next().is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
            && chars.all(|c| c.is_ascii_alphanumeric() || c == '_');
        if valid {
            Ok(n.clone())
        } else {
            Err(self.invalid(name, field, Problem::InvalidName { name: n.clone() }))
        }
    }
}

/// serde's "invalid type: string \"fast\", expected f64" as a user reads
/// it: `expected a number, found "fast"`; `None` for other messages.
pub(super) fn plain_type_message(message: &str) -> Option<String> {
    let rest = message.trim().strip_prefix("invalid type: ")?;
    let (found, expected) = rest.rsplit_once(", expected ")?;
    let found = found.replace('`', "");
    let found = if let Some(s) = found.strip_prefix("string ") {
        s.to_owned()
    } else if let Some(v) = ["integer ", "floating point ", "boolean ", "character "]
        .iter()
        .find_map(|p| found.strip_prefix(p))
    {
        v.to_owned()
    } else {
        match found.as_str() {
            "sequence" => "an array".to_owned(),
            "map" => "a table".to_owned(),
            other => other.to_owned(),
        }
    };
    let expected = match expected.trim() {
        "f64" | "f32" | "a float" => "a number",
        "u8" | "u16" | "u32" | "u64" | "usize" | "i8" | "i16" | "i32" | "i64" | "isize" | "an integer" => "an integer",
        "a boolean" | "bool" => "true or false",
        "a sequence" => "an array",
        "a map" | "struct" => "a table",
        other => other,
    };
    Some(format!("expected {expected}, found {found}"))
}

/// The shape fields of an obstacle or the tool, as written.
#[derive(Clone, Copy)]
pub(super) struct ShapeFields<'a> {
    pub(super) kind: &'a Spanned<ShapeKind>,
    pub(super) size: &'a Option<Spanned<Numbers<3>>>,
    pub(super) radius: &'a Option<Spanned<f64>>,
    pub(super) length: &'a Option<Spanned<f64>>,
    pub(super) file: &'a Option<Spanned<String>>,
    pub(super) scale: &'a Option<Spanned<Numbers<3>>>,
}
