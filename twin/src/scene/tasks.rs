//! `[[tasks]]`: periodic, continuous and event tasks, their programs in
//! scan order, each program's tags (and its parameters' connections) and
//! routines (Structured Text files, parsed here so that
//! a syntax error names the routine file, line and column at load).

use super::model::{
    CONTINUOUS_PRIORITY, Connection, ControllerSettings, DEFAULT_WATCHDOG_MS, Dialect, EventTrigger, ProgramDef,
    RoutineDef, Tag, Task, TaskKind, Usage,
};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

use toml::Spanned;

use super::context::{Ctx, NameKind, Names, Parsed};
use super::error::{Problem, SceneError};
use super::model::{Axis, BaseType};
use super::raw::{RawController, RawProgram, RawRoutine, RawTask};
use crate::source::{Diagnostic, Source};
use crate::st::parse::{parse_ladder, parse_routine};

/// Parses every routine an export holds, on every core the machine
/// lends, largest first (a large project has hundreds of routines, and
/// parsing them is a good part of its load time). The tasks take each
/// result when they name its routine ([`Ctx::routine`]), so the error
/// reported is the first in the order the scene reads its routines.
pub(super) fn parse_embedded(
    expanded: &super::import::Expanded,
    files: &crate::source::Files,
) -> HashMap<PathBuf, Parsed> {
    let mut jobs: Vec<(&PathBuf, Source<'_>)> = expanded
        .routines
        .iter()
        .map(|(path, v)| {
            let source = Source::embedded(&v.text, files, expanded.l5x_file, std::sync::Arc::clone(&v.map));
            (path, source)
        })
        .collect();
    jobs.sort_by_key(|(path, source)| (std::cmp::Reverse(source.text.len()), *path));
    let threads = std::thread::available_parallelism()
        .map_or(1, std::num::NonZeroUsize::get)
        .min(jobs.len());
    let next = AtomicUsize::new(0);
    let work = || {
        let mut done = Vec::new();
        loop {
            let k = next.fetch_add(1, Ordering::Relaxed);
            let Some((path, source)) = jobs.get(k) else {
                return done;
            };
            done.push(((*path).clone(), parse_any(path, source)));
        }
    };
    // This thread works too: one core, or one routine, spawns no helper.
    std::thread::scope(|scope| {
        let helpers: Vec<_> = (1..threads).map(|_| scope.spawn(work)).collect();
        let mut all: HashMap<PathBuf, Parsed> = work().into_iter().collect();
        for h in helpers {
            // A parser panic is a bug: let it surface as one.
            all.extend(h.join().unwrap_or_else(|e| std::panic::resume_unwind(e)));
        }
        all
    })
}

/// Parses a routine file: ladder when its extension is `.rll`, else
/// Structured Text.
pub(super) fn parse_any(path: &Path, source: &Source<'_>) -> Parsed {
    if is_ladder(path) {
        parse_ladder(source)
    } else {
        parse_routine(source)
    }
}

/// Whether a routine file is ladder (`*.rll`).
pub(crate) fn is_ladder(path: &Path) -> bool {
    path.extension().is_some_and(|e| e.eq_ignore_ascii_case("rll"))
}

impl Ctx<'_> {
    /// `[controller]`.
    pub(super) fn controller_settings(
        &self,
        raw: Option<&RawController>,
        (axes, controller, base): (&[Axis], &Names, &Path),
        tasks: &[Task],
    ) -> Result<ControllerSettings, SceneError> {
        let mut settings = ControllerSettings::default();
        let Some(raw) = raw else {
            return Ok(settings);
        };
        if let Some(r) = raw.report_overflow_faults {
            settings.report_overflow_faults = r;
        }
        if let Some(s) = &raw.statement_us {
            settings.statement_us =
                self.in_range(s, "controller.statement_us", super::model::MIN_STATEMENT_US, 1000.0)?;
        }
        if let Some(t) = &raw.start_time {
            settings.start_time_us = utc_micros(t.get_ref()).map_err(|why| {
                let problem = Problem::BadDateTime {
                    text: t.get_ref().clone(),
                    why,
                };
                self.invalid(t, "controller.start_time", problem)
            })?;
        }
        if let Some(p) = &raw.fault_handler {
            let field = "controller.fault_handler";
            let mut taken = controller.clone();
            for q in tasks.iter().flat_map(|t| &t.programs) {
                taken.insert(q.name.to_lowercase(), (q.location.line, NameKind::Axis));
            }
            self.unique(&mut taken, &p.name, &format!("{field}.name"), NameKind::Axis)?;
            settings.fault_handler = Some(self.program_def(p, axes, controller, base, field)?);
        }
        Ok(settings)
    }

    pub(super) fn tasks(
        &self,
        raw: &[RawTask],
        axes: &[Axis],
        (controller, controller_tags): (&Names, &[Tag]),
        base: &Path,
    ) -> Result<Vec<Task>, SceneError> {
        if let Some(t) = raw.get(super::model::MAX_TASKS) {
            let why = format!(
                "a controller has at most {} tasks (1756-RM084: ControlLogix)",
                super::model::MAX_TASKS
            );
            let field = format!("tasks[{}].name", super::model::MAX_TASKS);
            return Err(self.invalid(&t.name, field, Problem::Rule { why }));
        }
        let mut task_names: Names = Names::new();
        let mut program_names: Names = Names::new();
        let mut tasks = Vec::with_capacity(raw.len());
        for (i, t) in raw.iter().enumerate() {
            let f = |field: &str| format!("tasks[{i}].{field}");
            if let Some(p) = t.programs.get(super::model::MAX_PROGRAMS_PER_TASK) {
                let why = format!(
                    "a task schedules at most {} programs (1756-RM084)",
                    super::model::MAX_PROGRAMS_PER_TASK
                );
                let field = f(&format!("programs[{}].name", super::model::MAX_PROGRAMS_PER_TASK));
                return Err(self.invalid(&p.name, field, Problem::Rule { why }));
            }
            let name = self.identifier(&t.name, &f("name"))?;
            self.unique(&mut task_names, &t.name, &f("name"), NameKind::Axis)?;
            let (kind, priority) = self.task_kind(t, i, &tasks, axes)?;
            let watchdog_ms = match &t.watchdog_ms {
                Some(w) => self.in_range(w, &f("watchdog_ms"), 0.1, 2_000_000.0)?,
                None => DEFAULT_WATCHDOG_MS,
            };
            let mut programs = Vec::with_capacity(t.programs.len());
            for (j, p) in t.programs.iter().enumerate() {
                let prefix = format!("tasks[{i}].programs[{j}]");
                // `Program.Tag` names a program's tag from outside it: a
                // program may not share its name with an axis or a tag.
                self.unique_beside(controller, &p.name, &format!("{prefix}.name"))?;
                self.unique(&mut program_names, &p.name, &format!("{prefix}.name"), NameKind::Axis)?;
                programs.push(self.program_def(p, axes, controller, base, &prefix)?);
            }
            tasks.push(Task {
                name,
                kind,
                priority,
                watchdog_ms,
                inhibit: t.inhibit.unwrap_or(false),
                programs,
                location: self.loc(&t.name),
            });
        }
        self.connections(raw, &tasks, controller_tags)?;
        Ok(tasks)
    }

    /// Every parameter's connection names a controller tag or another
    /// program's Input, Output or Public parameter, of the parameter's
    /// type (1756-PM021).
    fn connections(&self, raw: &[RawTask], tasks: &[Task], controller_tags: &[Tag]) -> Result<(), SceneError> {
        let programs: Vec<&ProgramDef> = tasks.iter().flat_map(|t| &t.programs).collect();
        for (i, (rt, t)) in raw.iter().zip(tasks).enumerate() {
            for (j, (rp, p)) in rt.programs.iter().zip(&t.programs).enumerate() {
                for (k, (rtag, tag)) in rp.tags.iter().zip(&p.tags).enumerate() {
                    let (Some(c), Some(at)) = (&tag.connection, &rtag.connection) else {
                        continue;
                    };
                    let bad = |why: String| {
                        let field = format!("tasks[{i}].programs[{j}].tags[{k}].connection");
                        let problem = Problem::BadConnection {
                            text: at.get_ref().trim().to_owned(),
                            why,
                        };
                        self.invalid(at, field, problem)
                    };
                    let target = match c {
                        Connection::Controller(name) => controller_tags
                            .iter()
                            .find(|x| x.name.eq_ignore_ascii_case(name))
                            .ok_or_else(|| bad(format!("no controller tag '{name}'")))?,
                        Connection::Parameter { program, param } => {
                            if program.eq_ignore_ascii_case(&p.name) {
                                return Err(bad("a parameter connects to a tag outside its own program".to_owned()));
                            }
                            let other = programs
                                .iter()
                                .find(|q| q.name.eq_ignore_ascii_case(program))
                                .ok_or_else(|| bad(format!("no program '{program}'")))?;
                            let target = other
                                .tags
                                .iter()
                                .find(|x| x.name.eq_ignore_ascii_case(param))
                                .ok_or_else(|| bad(format!("program '{}' has no tag '{param}'", other.name)))?;
                            if !target.usage.reachable() {
                                return Err(bad(format!(
                                    "{}.{} is {} {}: only Input, Output and Public parameters are reachable from another program",
                                    other.name,
                                    target.name,
                                    if target.usage == Usage::InOut { "an" } else { "a" },
                                    if target.usage == Usage::InOut {
                                        "InOut parameter"
                                    } else {
                                        "local tag"
                                    }
                                )));
                            }
                            target
                        }
                    };
                    if target.ty != tag.ty {
                        return Err(bad(format!(
                            "{} is {}, the parameter {} is {}",
                            c.stored_name(),
                            target.ty,
                            tag.name,
                            tag.ty
                        )));
                    }
                }
            }
        }
        Ok(())
    }

    /// A task's type and what it needs: a periodic task its period and
    /// priority, an event task its trigger and priority, a continuous task
    /// neither (at most one, below every other task).
    fn task_kind(&self, t: &RawTask, i: usize, before: &[Task], axes: &[Axis]) -> Result<(TaskKind, u8), SceneError> {
        let f = |field: &str| format!("tasks[{i}].{field}");
        const TYPES: [(&str, &str); 3] = [
            ("periodic", "periodic"),
            ("continuous", "continuous"),
            ("event", "event"),
        ];
        let kind: &'static str = match &t.kind {
            None => "periodic",
            Some(k) => self.word(k, &f("type"), "task type", &TYPES)?,
        };
        let not_here = |at: std::ops::Range<usize>, field: &'static str| {
            self.invalid_at(at, f(field), Problem::TaskFieldNotApplicable { field, kind })
        };
        let required = |field: &'static str, hint: &'static str| {
            self.invalid(&t.name, f(field), Problem::TaskFieldRequired { field, kind, hint })
        };
        if kind != "periodic"
            && let Some(p) = &t.period_ms
        {
            return Err(not_here(p.span(), "period_ms"));
        }
        if kind != "event" {
            if let Some(x) = &t.trigger {
                return Err(not_here(x.span(), "trigger"));
            }
            if let Some(x) = &t.axis {
                return Err(not_here(x.span(), "axis"));
            }
            if let Some(x) = &t.timeout_ms {
                return Err(not_here(x.span(), "timeout_ms"));
            }
        }
        let priority = match (&t.priority, kind) {
            (Some(p), "continuous") => return Err(not_here(p.span(), "priority")),
            (None, "continuous") => CONTINUOUS_PRIORITY,
            (Some(p), _) => self.int_in_range(p, &f("priority"), 1, 15)? as u8,
            (None, _) => return Err(required("priority", " (1, the highest, to 15)")),
        };
        let kind = match kind {
            "periodic" => match &t.period_ms {
                Some(p) => TaskKind::Periodic {
                    period_ms: self.in_range(p, &f("period_ms"), 0.1, 2_000_000.0)?,
                },
                None => {
                    return Err(required(
                        "period_ms",
                        " (a task with no period is type = \"continuous\")",
                    ));
                }
            },
            "continuous" => {
                if let Some(first) = before.iter().find(|x| x.kind == TaskKind::Continuous) {
                    let problem = Problem::SecondContinuousTask {
                        first: first.name.clone(),
                    };
                    return Err(self.invalid(t.kind.as_ref().unwrap_or(&t.name), f("type"), problem));
                }
                TaskKind::Continuous
            }
            _ => {
                let Some(trigger) = &t.trigger else {
                    return Err(required(
                        "trigger",
                        " (\"event_instruction\", \"motion_group_execution\", \"axis_registration_1\", \"axis_registration_2\" or \"axis_watch\")",
                    ));
                };
                // The axis triggers: a registration input (1, 2) or the
                // watch (0).
                let axis_event = match trigger.get_ref().to_ascii_lowercase().as_str() {
                    "axis_registration_1" => Some(1),
                    "axis_registration_2" => Some(2),
                    "axis_watch" => Some(0),
                    _ => None,
                };
                let trig = match (axis_event, &t.axis) {
                    (Some(input), Some(axis)) => {
                        let axis = axes
                            .iter()
                            .position(|a| a.name.eq_ignore_ascii_case(axis.get_ref().trim()))
                            .ok_or_else(|| {
                                let problem = Problem::UnknownAxis {
                                    name: axis.get_ref().clone(),
                                    nearest: None,
                                };
                                self.invalid(axis, f("axis"), problem)
                            })?;
                        match input {
                            0 => EventTrigger::AxisWatch { axis },
                            _ => EventTrigger::AxisRegistration { axis, input },
                        }
                    }
                    (Some(_), None) => {
                        let why = "an axis trigger names its axis: axis = \"…\"".to_owned();
                        return Err(self.invalid(trigger, f("axis"), Problem::Rule { why }));
                    }
                    (None, Some(axis)) => {
                        let why = "'axis' applies to the axis_registration_1, _2 and axis_watch triggers".to_owned();
                        return Err(self.invalid(axis, f("axis"), Problem::Rule { why }));
                    }
                    (None, None) => {
                        const WORDS: [(&str, EventTrigger); 5] = [
                            ("event_instruction", EventTrigger::EventInstruction),
                            ("motion_group_execution", EventTrigger::MotionGroupExecution),
                            ("axis_registration_1", EventTrigger::EventInstruction),
                            ("axis_registration_2", EventTrigger::EventInstruction),
                            ("axis_watch", EventTrigger::EventInstruction),
                        ];
                        self.word(trigger, &f("trigger"), "event trigger", &WORDS)?
                    }
                };
                let timeout_ms = match &t.timeout_ms {
                    Some(x) => Some(self.in_range(x, &f("timeout_ms"), 0.1, 2_000_000.0)?),
                    None => None,
                };
                TaskKind::Event {
                    trigger: trig,
                    timeout_ms,
                }
            }
        };
        Ok((kind, priority))
    }

    fn program_def(
        &self,
        p: &RawProgram,
        axes: &[Axis],
        controller: &Names,
        base: &Path,
        prefix: &str,
    ) -> Result<ProgramDef, SceneError> {
        let name = self.identifier(&p.name, &format!("{prefix}.name"))?;
        // Program tags live in their own namespace: they may reuse a
        // controller tag's name (and shadow it) but not an axis'.
        let mut names: Names = controller
            .iter()
            .filter(|(_, (_, kind))| matches!(kind, NameKind::Axis))
            .map(|(k, v)| (k.clone(), *v))
            .collect();
        let tags = self.tags(&p.tags, axes, &mut names, &format!("{prefix}.tags"))?;
        let aliases = self.aliases(&p.aliases, &mut names, &format!("{prefix}.aliases"))?;
        for (k, t) in p.tags.iter().enumerate() {
            if tags[k].ty.base == BaseType::CoordinateSystem {
                let problem = Problem::ControllerScopeOnly {
                    ty: tags[k].ty.base.name(),
                };
                return Err(self.invalid(&t.ty, format!("{prefix}.tags[{k}].type"), problem));
            }
        }
        let main = self.routine(&p.main, base, &format!("{prefix}.main"))?;
        let mut routines: Vec<RoutineDef> = Vec::with_capacity(p.routines.len());
        for (k, r) in p.routines.iter().enumerate() {
            let field = format!("{prefix}.routines[{k}]");
            let def = self.routine(r, base, &field)?;
            if def.name.eq_ignore_ascii_case(&main.name)
                || routines.iter().any(|x| x.name.eq_ignore_ascii_case(&def.name))
            {
                let problem = Problem::DuplicateRoutine { name: def.name };
                return Err(self.invalid(r, field, problem));
            }
            routines.push(def);
        }
        let fault_routine = match &p.fault_routine {
            None => None,
            Some(name) => match routines
                .iter()
                .position(|r| r.name.eq_ignore_ascii_case(name.get_ref()))
            {
                Some(k) => Some(k),
                None => {
                    let problem = Problem::UnknownFaultRoutine {
                        name: name.get_ref().clone(),
                        routines: routines.iter().map(|r| r.name.as_str()).collect::<Vec<_>>().join(", "),
                    };
                    return Err(self.invalid(name, format!("{prefix}.fault_routine"), problem));
                }
            },
        };
        Ok(ProgramDef {
            name,
            tags,
            aliases,
            main,
            routines,
            fault_routine,
            disabled: p.disabled.unwrap_or(false),
            location: self.loc(&p.name),
        })
    }

    fn routine(&self, raw: &Spanned<RawRoutine>, base: &Path, field: &str) -> Result<RoutineDef, SceneError> {
        let (file, dialect) = match raw.get_ref() {
            RawRoutine::Path(p) => (p, None),
            RawRoutine::Table { file, dialect } => (file, dialect.as_deref()),
        };
        let dialect = match dialect.map(str::to_ascii_lowercase).as_deref() {
            None | Some("logix") => Dialect::Logix,
            Some("iec") => Dialect::Iec,
            Some(other) => {
                let problem = Problem::UnknownDialect { name: other.to_owned() };
                return Err(self.invalid(raw, format!("{field}.dialect"), problem));
            }
        };
        let path = base.join(file);
        if let Some(v) = self
            .expanded
            .as_ref()
            .and_then(|e| e.routines.get(Path::new(file)).map(|v| (e.l5x_file, v)))
        {
            let (l5x, v) = v;
            let parsed = self.parsed.borrow_mut().remove(Path::new(file));
            let parsed = parsed.unwrap_or_else(|| {
                let files = self.files.borrow();
                parse_any(
                    Path::new(file),
                    &Source::embedded(&v.text, &files, l5x, std::sync::Arc::clone(&v.map)),
                )
            });
            let routine = parsed.map_err(|d| {
                // Name the routine and its line as Studio numbers them.
                let line = d
                    .labels
                    .first()
                    .and_then(|l| v.map.iter().position(|&b| b as usize >= l.range.start))
                    .map_or(0, |i| v.text[..i.min(v.text.len())].matches('\n').count());
                let at = if is_ladder(Path::new(file)) {
                    format!("{} rung {line}", v.name)
                } else {
                    format!("{} Line Number=\"{line}\"", v.name)
                };
                SceneError::Syntax(Box::new((*d).in_field(at)))
            })?;
            let name = Path::new(file)
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_default();
            return Ok(RoutineDef {
                name,
                path,
                dialect,
                routine,
            });
        }
        let name = path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        let valid = name.chars().next().is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
            && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_');
        if !valid {
            return Err(self.invalid(raw, field, Problem::InvalidName { name }));
        }
        if !path.is_file() {
            return Err(self.invalid(raw, field, Problem::MissingFile { path }));
        }
        let text = crate::source::read_text_bounded(&path, crate::source::InputKind::Routine).map_err(|e| {
            let d = Diagnostic::error(format!("{}: cannot read the routine: {e}", path.display()));
            SceneError::Syntax(Box::new(d))
        })?;
        let id = self.files.borrow_mut().add(path.clone(), text);
        let files = self.files.borrow();
        let routine = parse_any(&path, &Source::file(&files, id)).map_err(SceneError::Syntax)?;
        Ok(RoutineDef {
            name,
            path,
            dialect,
            routine,
        })
    }
}

/// `YYYY-MM-DDTHH:MM:SS[.ffffff]Z` (RFC 3339 in UTC) as µs since
/// 1970-01-01T00:00:00Z; years 1970 to 9999.
pub(super) fn utc_micros(text: &str) -> Result<i64, &'static str> {
    let b = text.as_bytes();
    if b.len() < 20 || b[4] != b'-' || b[7] != b'-' || !matches!(b[10], b'T' | b't') || b[13] != b':' || b[16] != b':' {
        return Err("expected YYYY-MM-DDTHH:MM:SSZ");
    }
    if !matches!(b[b.len() - 1], b'Z' | b'z') {
        return Err("the time must be UTC, ending in Z");
    }
    let num = |r: std::ops::Range<usize>| -> Result<i64, &'static str> {
        let s = text.get(r).ok_or("expected digits")?;
        if s.bytes().all(|c| c.is_ascii_digit()) {
            s.parse().map_err(|_| "expected digits")
        } else {
            Err("expected digits")
        }
    };
    let (year, month, day) = (num(0..4)?, num(5..7)?, num(8..10)?);
    let (hour, minute, second) = (num(11..13)?, num(14..16)?, num(17..19)?);
    let fraction = &text[19..text.len() - 1];
    let micros = match fraction.strip_prefix('.') {
        None if fraction.is_empty() => 0,
        Some(f) if (1..=6).contains(&f.len()) && f.bytes().all(|c| c.is_ascii_digit()) => {
            f.parse::<i64>().map_err(|_| "expected digits")? * 10_i64.pow(6 - f.len() as u32)
        }
        _ => return Err("at most six digits of a second after '.'"),
    };
    if !(1970..=9999).contains(&year) {
        return Err("the year is 1970 to 9999");
    }
    let leap = (year % 4 == 0 && year % 100 != 0) || year % 400 == 0;
    let days_in = [31, if leap { 29 } else { 28 }, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31];
    if !(1..=12).contains(&month) || day < 1 || day > days_in[month as usize - 1] {
        return Err("no such date");
    }
    if hour > 23 || minute > 59 || second > 59 {
        return Err("no such time of day");
    }
    // Days since 1970-01-01 (the civil-from-days inverse, proleptic
    // Gregorian).
    let (y, m) = if month <= 2 {
        (year - 1, month + 9)
    } else {
        (year, month - 3)
    };
    let era = y.div_euclid(400);
    let yoe = y - era * 400;
    let doy = (153 * m + 2) / 5 + day - 1;
    let doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
    let days = era * 146_097 + doe - 719_468;
    Ok(((days * 24 + hour) * 60 + minute) * 60_000_000 + second * 1_000_000 + micros)
}

#[cfg(test)]
mod tests {
    use super::utc_micros;

    #[test]
    fn utc_dates_count_microseconds_since_1970() {
        assert_eq!(utc_micros("1970-01-01T00:00:00Z"), Ok(0));
        assert_eq!(utc_micros("2000-01-01T00:00:00Z"), Ok(946_684_800_000_000));
        assert_eq!(utc_micros("2024-02-29T12:34:56.5Z"), Ok(1_709_210_096_500_000));
        assert_eq!(utc_micros("2026-11-27T08:00:00.000001Z"), Ok(1_795_766_400_000_001));
        assert!(utc_micros("2023-02-29T00:00:00Z").is_err());
        assert!(utc_micros("2026-11-27T08:00:00+01:00").is_err());
        assert!(utc_micros("2026-11-27 08:00").is_err());
        assert!(utc_micros("2026-13-01T00:00:00Z").is_err());
    }
}
