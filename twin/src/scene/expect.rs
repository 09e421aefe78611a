//! Validation of `[[expect]]`, `[test]` and `[[variants]]`: each
//! expectation has exactly one kind and only that kind's options, its
//! times inside the run, and its conditions parsed with the Structured
//! Text front-end (the run compiles them against the tags, axes and trace
//! columns, so a wrong name is reported at load with its place in the
//! string); a variant sets declared tags with values of their types.

use std::collections::HashMap;

use toml::Spanned;

use super::context::Ctx;
use super::error::{Problem, SceneError};
use super::model::{
    Axis, Condition, ExpectKind, Expectation, PlantMode, RUN_EXIT_CODES, Tag, Task, TestSettings, Variant,
};
use super::raw::{PlantWord, RawExpect, RawTest, RawVariant};
use crate::st::parse::parse_expression;

/// The options each kind takes, and the list as a message writes it.
const TAKES: [(&str, &[&str], &str); 6] = [
    ("always", &["from_s", "to_s", "while"], "from_s, to_s, while"),
    ("never", &["from_s", "to_s", "while"], "from_s, to_s, while"),
    ("eventually", &["after_s", "by_s"], "after_s, by_s"),
    ("at_end", &[], "no options"),
    ("sequence", &["within_s"], "within_s"),
    ("cycle", &["min_s", "max_s", "count"], "min_s, max_s, count"),
];

/// What a variant's checks need of the scene around it.
pub(super) struct VariantScope<'a> {
    pub(super) tags: &'a [Tag],
    pub(super) tasks: &'a [Task],
    pub(super) axes: &'a [Axis],
    pub(super) duration_s: f64,
    pub(super) expectations: &'a [Expectation],
}

impl Ctx<'_> {
    /// `[[expect]]` entries under `prefix` (`expect`, `variants[0].expect`),
    /// their names unique among `taken` and each other, their times inside
    /// a run of `duration_s` (of `variant`, when it is a variant's).
    pub(super) fn expectations(
        &self,
        raw: &[RawExpect],
        prefix: &str,
        duration_s: f64,
        variant: Option<&str>,
        taken: &[Expectation],
    ) -> Result<Vec<Expectation>, SceneError> {
        let mut seen: HashMap<String, (usize, ())> = taken
            .iter()
            .map(|e| (e.name.to_lowercase(), (e.location.line, ())))
            .collect();
        let mut out = Vec::with_capacity(raw.len());
        for (i, e) in raw.iter().enumerate() {
            let field = format!("{prefix}[{i}]");
            let name = self.nonempty_name(&e.name, &format!("{field}.name"))?;
            self.unique(&mut seen, &e.name, &format!("{field}.name"), ())?;
            let kind = self.expect_kind(e, &field, duration_s, variant)?;
            out.push(Expectation {
                name,
                kind,
                field,
                location: self.loc(&e.name),
            });
        }
        Ok(out)
    }

    fn condition(&self, s: &Spanned<String>, field: String) -> Result<Condition, SceneError> {
        let expr = self.parse_in(s, &field, parse_expression)?;
        Ok(Condition {
            text: s.get_ref().trim().to_owned(),
            expr,
            field,
        })
    }

    fn expect_kind(
        &self,
        e: &RawExpect,
        field: &str,
        duration_s: f64,
        variant: Option<&str>,
    ) -> Result<ExpectKind, SceneError> {
        let kinds: Vec<(&'static str, Option<std::ops::Range<usize>>)> = vec![
            ("always", e.always.as_ref().map(Spanned::span)),
            ("never", e.never.as_ref().map(Spanned::span)),
            ("eventually", e.eventually.as_ref().map(Spanned::span)),
            ("at_end", e.at_end.as_ref().map(Spanned::span)),
            ("sequence", e.sequence.as_ref().map(Spanned::span)),
            ("cycle", e.cycle.as_ref().map(Spanned::span)),
        ];
        let given: Vec<_> = kinds.iter().filter_map(|(k, s)| s.clone().map(|s| (*k, s))).collect();
        let kind = match given.as_slice() {
            [(kind, _)] => *kind,
            [] => {
                return Err(self.invalid(&e.name, field.to_owned(), Problem::ExpectKinds { found: Vec::new() }));
            }
            [_, (_, second), ..] => {
                let found = given.iter().map(|(k, _)| *k).collect();
                return Err(self.invalid_at(second.clone(), field.to_owned(), Problem::ExpectKinds { found }));
            }
        };
        let (_, takes, takes_text) = TAKES.iter().find(|(k, ..)| *k == kind).copied().unwrap_or(TAKES[3]);
        let options: [(&'static str, Option<std::ops::Range<usize>>); 9] = [
            ("from_s", e.from_s.as_ref().map(Spanned::span)),
            ("to_s", e.to_s.as_ref().map(Spanned::span)),
            ("while", e.guard.as_ref().map(Spanned::span)),
            ("after_s", e.after_s.as_ref().map(Spanned::span)),
            ("by_s", e.by_s.as_ref().map(Spanned::span)),
            ("within_s", e.within_s.as_ref().map(Spanned::span)),
            ("min_s", e.min_s.as_ref().map(Spanned::span)),
            ("max_s", e.max_s.as_ref().map(Spanned::span)),
            ("count", e.count.as_ref().map(Spanned::span)),
        ];
        for (option, span) in options {
            if let Some(span) = span
                && !takes.contains(&option)
            {
                let problem = Problem::ExpectOption {
                    option,
                    kind,
                    takes: takes_text,
                };
                return Err(self.invalid_at(span, format!("{field}.{option}"), problem));
            }
        }
        let f = |o: &str| format!("{field}.{o}");
        // A time inside the run: not negative, not past its end.
        let time = |v: &Option<Spanned<f64>>, option: &'static str| -> Result<Option<f64>, SceneError> {
            let Some(v) = v else { return Ok(None) };
            let value = self.non_negative(v, &f(option))?;
            if value > duration_s + 1e-9 {
                let problem = Problem::PastEnd {
                    option,
                    value,
                    duration_s,
                    variant: variant.map(str::to_owned),
                };
                return Err(self.invalid(v, f(option), problem));
            }
            Ok(Some(value))
        };
        let ordered =
            |low: (&'static str, Option<f64>), high: (&'static str, Option<f64>, &Option<Spanned<f64>>)| match (
                low.1, high.1, high.2,
            ) {
                (Some(low_s), Some(high_s), Some(at)) if low_s > high_s => Err(self.invalid(
                    at,
                    f(high.0),
                    Problem::WindowOrder {
                        low: low.0,
                        low_s,
                        high: high.0,
                        high_s,
                    },
                )),
                _ => Ok(()),
            };
        let one = |s: &Option<Spanned<String>>| {
            let s = s.as_ref().expect("the kind given");
            self.condition(s, f(kind))
        };
        Ok(match kind {
            "always" | "never" => {
                let (from_s, to_s) = (time(&e.from_s, "from_s")?, time(&e.to_s, "to_s")?);
                ordered(("from_s", from_s), ("to_s", to_s, &e.to_s))?;
                ExpectKind::Always {
                    condition: one(if kind == "always" { &e.always } else { &e.never })?,
                    never: kind == "never",
                    from_s: from_s.unwrap_or(0.0),
                    to_s,
                    guard: match &e.guard {
                        Some(g) => Some(self.condition(g, f("while"))?),
                        None => None,
                    },
                }
            }
            "eventually" => {
                let (after_s, by_s) = (time(&e.after_s, "after_s")?, time(&e.by_s, "by_s")?);
                ordered(("after_s", after_s), ("by_s", by_s, &e.by_s))?;
                ExpectKind::Eventually {
                    condition: one(&e.eventually)?,
                    after_s: after_s.unwrap_or(0.0),
                    by_s,
                }
            }
            "at_end" => ExpectKind::AtEnd {
                condition: one(&e.at_end)?,
            },
            "sequence" => {
                let list = e.sequence.as_ref().expect("the kind given");
                if list.get_ref().is_empty() {
                    return Err(self.invalid(list, f("sequence"), Problem::EmptySequence));
                }
                let steps = list
                    .get_ref()
                    .iter()
                    .enumerate()
                    .map(|(k, s)| self.condition(s, format!("{field}.sequence[{k}]")))
                    .collect::<Result<_, _>>()?;
                ExpectKind::Sequence {
                    steps,
                    within_s: match &e.within_s {
                        Some(w) => Some(self.positive(w, &f("within_s"))?),
                        None => None,
                    },
                }
            }
            _ => {
                let min_s = match &e.min_s {
                    Some(v) => Some(self.non_negative(v, &f("min_s"))?),
                    None => None,
                };
                let max_s = match &e.max_s {
                    Some(v) => Some(self.positive(v, &f("max_s"))?),
                    None => None,
                };
                ordered(("min_s", min_s), ("max_s", max_s, &e.max_s))?;
                let count = match &e.count {
                    Some(c) => self.int_in_range(c, &f("count"), 1, 1_000_000)? as u32,
                    None => 1,
                };
                ExpectKind::Cycle {
                    condition: one(&e.cycle)?,
                    min_s: min_s.unwrap_or(0.0),
                    max_s,
                    count,
                }
            }
        })
    }

    /// `[test]`.
    pub(super) fn test_settings(&self, raw: Option<&RawTest>) -> Result<TestSettings, SceneError> {
        let Some(raw) = raw else {
            return Ok(TestSettings::default());
        };
        Ok(TestSettings {
            exit_code: match &raw.exit_code {
                Some(c) => self.run_exit_code(c, "test.exit_code")?,
                None => 0,
            },
            timeout_s: match &raw.timeout_s {
                Some(t) => Some(self.positive(t, "test.timeout_s")?),
                None => None,
            },
        })
    }

    fn run_exit_code(&self, c: &Spanned<i64>, field: &str) -> Result<u8, SceneError> {
        let code = *c.get_ref();
        match u8::try_from(code) {
            Ok(code) if RUN_EXIT_CODES.contains(&code) => Ok(code),
            _ => Err(self.invalid(c, field, Problem::NotRunExitCode { code })),
        }
    }

    /// `[[variants]]`: names unique, tags declared and values of their
    /// types, durations and expectations checked as the scene's are.
    pub(super) fn variants(&self, raw: &[RawVariant], scope: &VariantScope<'_>) -> Result<Vec<Variant>, SceneError> {
        let mut seen = HashMap::new();
        let mut out = Vec::with_capacity(raw.len());
        for (i, v) in raw.iter().enumerate() {
            let field = format!("variants[{i}]");
            let name = self.nonempty_name(&v.name, &format!("{field}.name"))?;
            self.unique(&mut seen, &v.name, &format!("{field}.name"), ())?;
            let mut tags = Vec::with_capacity(v.tags.len());
            // `Program.Tag = 1` unquoted is a table `Program` in TOML: its
            // entries are that program's tags.
            let mut entries: Vec<(String, Spanned<toml::Value>)> = Vec::with_capacity(v.tags.len());
            for (key, value) in &v.tags {
                match value.get_ref() {
                    toml::Value::Table(inner) if variant_tag(scope, key).is_none() => {
                        for (sub, x) in inner {
                            entries.push((format!("{key}.{sub}"), Spanned::new(value.span(), x.clone())));
                        }
                    }
                    _ => entries.push((key.clone(), value.clone())),
                }
            }
            for (tag_name, value) in &entries {
                let tag_field = format!("{field}.tags.{tag_name}");
                let Some(tag) = variant_tag(scope, tag_name) else {
                    let names = scope
                        .tags
                        .iter()
                        .map(|t| t.name.clone())
                        .chain(
                            scope
                                .tasks
                                .iter()
                                .flat_map(|t| &t.programs)
                                .flat_map(|p| p.tags.iter().map(move |t| format!("{}.{}", p.name, t.name))),
                        )
                        .collect::<Vec<_>>();
                    let nearest =
                        crate::source::diag::nearest(tag_name, names.iter().map(String::as_str)).map(str::to_owned);
                    let problem = Problem::UnknownVariantTag {
                        name: tag_name.clone(),
                        nearest,
                    };
                    return Err(self.invalid(value, tag_field, problem));
                };
                let checked = self.tag_value(value, tag.ty, scope.axes, &tag_field)?;
                tags.push((tag_name.clone(), checked));
            }
            let duration_s = match &v.duration_s {
                Some(d) => Some(self.in_range(d, &format!("{field}.duration_s"), 1e-9, super::MAX_DURATION_S)?),
                None => None,
            };
            let run_s = duration_s.unwrap_or(scope.duration_s);
            if duration_s.is_some() {
                // The scene's own expectations run in this variant too.
                for e in scope.expectations {
                    self.check_inside(e, run_s, &name)?;
                }
            }
            let expectations = self.expectations(
                &v.expect,
                &format!("{field}.expect"),
                run_s,
                Some(&name),
                scope.expectations,
            )?;
            out.push(Variant {
                name,
                tags,
                duration_s,
                plant: v.plant.as_ref().map(|p| match p.get_ref() {
                    PlantWord::Physics => PlantMode::Physics,
                    PlantWord::Kinematic => PlantMode::Kinematic,
                }),
                exit_code: match &v.exit_code {
                    Some(c) => Some(self.run_exit_code(c, &format!("{field}.exit_code"))?),
                    None => None,
                },
                expectations,
            });
        }
        Ok(out)
    }

    /// A scene expectation's times inside a variant's shorter run.
    fn check_inside(&self, e: &Expectation, duration_s: f64, variant: &str) -> Result<(), SceneError> {
        let times: Vec<(&'static str, f64)> = match &e.kind {
            ExpectKind::Always { from_s, to_s, .. } => {
                let mut t = vec![("from_s", *from_s)];
                t.extend(to_s.map(|x| ("to_s", x)));
                t
            }
            ExpectKind::Eventually { after_s, by_s, .. } => {
                let mut t = vec![("after_s", *after_s)];
                t.extend(by_s.map(|x| ("by_s", x)));
                t
            }
            _ => Vec::new(),
        };
        for (option, value) in times {
            if value > duration_s + 1e-9 {
                let file = self.files.borrow();
                let source = file.get(self.scene_file);
                let span = source.token_at(e.location.line, e.location.column);
                drop(file);
                let problem = Problem::PastEnd {
                    option,
                    value,
                    duration_s,
                    variant: Some(variant.to_owned()),
                };
                return Err(self.invalid_at(span, format!("{}.{option}", e.field), problem));
            }
        }
        Ok(())
    }
}

/// The tag a variant names: a controller tag, or `Program.Tag`.
fn variant_tag<'a>(scope: &VariantScope<'a>, name: &str) -> Option<&'a Tag> {
    if let Some(t) = scope.tags.iter().find(|t| t.name.eq_ignore_ascii_case(name)) {
        return Some(t);
    }
    let (program, tag) = name.split_once('.')?;
    scope
        .tasks
        .iter()
        .flat_map(|t| &t.programs)
        .find(|p| p.name.eq_ignore_ascii_case(program))?
        .tags
        .iter()
        .find(|t| t.name.eq_ignore_ascii_case(tag))
}
