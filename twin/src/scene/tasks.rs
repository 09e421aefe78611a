//! `[[tasks]]`: periodic tasks, their programs in scan order, each
//! program's tags and routines (Structured Text files, parsed here so that
//! a syntax error names the routine file, line and column at load).

use super::model::{DEFAULT_WATCHDOG_MS, Dialect, ProgramDef, RoutineDef, Task};
use std::path::Path;

use toml::Spanned;

use super::context::{Ctx, NameKind, Names};
use super::error::{Problem, SceneError};
use super::model::{Axis, BaseType};
use super::raw::{RawProgram, RawRoutine, RawTask};
use crate::source::{Diagnostic, Source};
use crate::st::parse::parse_routine;

impl Ctx<'_> {
    pub(super) fn tasks(
        &self,
        raw: &[RawTask],
        axes: &[Axis],
        controller: &Names,
        base: &Path,
    ) -> Result<Vec<Task>, SceneError> {
        let mut task_names: Names = Names::new();
        let mut program_names: Names = Names::new();
        let mut tasks = Vec::with_capacity(raw.len());
        for (i, t) in raw.iter().enumerate() {
            let f = |field: &str| format!("tasks[{i}].{field}");
            let name = self.identifier(&t.name, &f("name"))?;
            self.unique(&mut task_names, &t.name, &f("name"), NameKind::Axis)?;
            let period_ms = self.in_range(&t.period_ms, &f("period_ms"), 0.1, 2_000_000.0)?;
            let priority = self.int_in_range(&t.priority, &f("priority"), 1, 15)?;
            let watchdog_ms = match &t.watchdog_ms {
                Some(w) => self.in_range(w, &f("watchdog_ms"), 0.1, 2_000_000.0)?,
                None => DEFAULT_WATCHDOG_MS,
            };
            let mut programs = Vec::with_capacity(t.programs.len());
            for (j, p) in t.programs.iter().enumerate() {
                let prefix = format!("tasks[{i}].programs[{j}]");
                // `Program.Tag` names a program's tag from outside it: a
                // program may not share its name with an axis or a tag.
                let mut taken = controller.clone();
                self.unique(&mut taken, &p.name, &format!("{prefix}.name"), NameKind::Axis)?;
                self.unique(&mut program_names, &p.name, &format!("{prefix}.name"), NameKind::Axis)?;
                programs.push(self.program_def(p, axes, controller, base, &prefix)?);
            }
            tasks.push(Task {
                name,
                period_ms,
                priority: priority as u8,
                watchdog_ms,
                programs,
                location: self.loc(&t.name),
            });
        }
        Ok(tasks)
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
        Ok(ProgramDef {
            name,
            tags,
            main,
            routines,
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
        let text = std::fs::read_to_string(&path).map_err(|e| {
            let d = Diagnostic::error(format!("{}: cannot read the routine: {e}", path.display()));
            SceneError::Syntax(Box::new(d))
        })?;
        let id = self.files.borrow_mut().add(path.clone(), text);
        let files = self.files.borrow();
        let routine = parse_routine(&Source::file(&files, id)).map_err(SceneError::Syntax)?;
        Ok(RoutineDef {
            name,
            path,
            dialect,
            routine,
        })
    }
}
