//! `add_on_instructions`: Add-On Instruction definitions (1756-PM010) read
//! from their exports (`TargetType="AddOnInstructionDefinition"`), or
//! from the project of a scene that names an L5X (its
//! `AddOnInstructionDefinitions`, as the virtual files `aoi/<Name>.L5X`).
//!
//! Each definition becomes the data type of its instances, named as the
//! instruction: `EnableIn` and `EnableOut` (BOOL), its Input and Output
//! parameters, then its local tags. InOut parameters take no room: a call
//! passes them by reference. Its routines `Logic`, `Prescan` (when
//! `ExecutePrescan`) and `EnableInFalse` (when `ExecuteEnableInFalse`) are
//! parsed here, ladder or Structured Text; `Postscan` runs only for SFC
//! actions, which the twin has none of, so it is never read.
//!
//! The program stage compiles each call (`compile::aoi`).

use std::path::Path;
use std::sync::Arc;

use toml::Spanned;

use super::context::Ctx;
use super::error::SceneError;
use super::model::{
    AoiDef, AoiParam, AoiUsage, BaseType, DataTypeDef, Location, MemberDef, RoutineDef, TagType, UserType, intern,
};
use crate::l5x::{self, AoiDefinition};
use crate::source::{Diagnostic, FileId, Source, Span};
use crate::st::parse::{parse_ladder, parse_routine};

/// An export read: its file, and how its bytes map into it.
struct Export {
    text: Arc<str>,
    file: FileId,
    map: Option<Arc<[u32]>>,
}

impl Export {
    fn span(&self, r: std::ops::Range<usize>) -> Span {
        let at = |i: usize| match &self.map {
            None => i as u32,
            Some(m) => m[i.min(m.len() - 1)],
        };
        Span {
            file: self.file,
            start: at(r.start),
            end: at(r.end).max(at(r.start)),
        }
    }

    /// A routine's byte map composed with the export's.
    fn routine_map(&self, map: &[u32]) -> Arc<[u32]> {
        match &self.map {
            None => map.into(),
            Some(m) => map.iter().map(|&b| m[(b as usize).min(m.len() - 1)]).collect(),
        }
    }
}

impl Ctx<'_> {
    fn aoi_error(&self, span: Span, message: impl Into<String>) -> SceneError {
        let files = self.files.borrow();
        SceneError::Syntax(Box::new(Diagnostic::error(message).with_label(files.label(span, ""))))
    }

    /// Reads `add_on_instructions` (module doc), registering each
    /// definition's data type after `[[data_types]]`.
    pub(super) fn add_on_instructions(&self, raw: &[Spanned<String>], base: &Path) -> Result<Vec<AoiDef>, SceneError> {
        // Every definition's name first (its data type, empty), so that a
        // parameter or local tag may be of any instruction's type.
        let mut found: Vec<(AoiDefinition, Arc<Export>, Location, usize)> = Vec::new();
        for (i, entry) in raw.iter().enumerate() {
            let field = format!("add_on_instructions[{i}]");
            let export = Arc::new(self.aoi_export(entry, base, &field)?);
            let defs =
                l5x::read_aoi_export(&export.text).map_err(|e| self.aoi_error(export.span(e.span), e.message))?;
            for d in defs {
                let same = found
                    .iter()
                    .find(|(o, ..)| o.name.value.eq_ignore_ascii_case(&d.name.value));
                if let Some((o, first, ..)) = same {
                    // An export carries the definitions its instruction
                    // uses: the same one twice is one; two that differ are
                    // an error.
                    if first.text[o.span.clone()] == export.text[d.span.clone()] {
                        continue;
                    }
                    let at = first.span(o.name.span.clone());
                    let (line, _) = self.files.borrow().line_column(at);
                    let file = self.files.borrow().path(at.file).display().to_string();
                    return Err(self.aoi_error(
                        export.span(d.name.span.clone()),
                        format!(
                            "Add-On Instruction {} is defined twice, differently (first at {file}:{line}): list one export of it",
                            d.name.value
                        ),
                    ));
                }
                let index = self.aoi_name(&d, &export)?;
                found.push((d, Arc::clone(&export), self.loc(entry), index));
            }
        }
        let mut out = Vec::with_capacity(found.len());
        for (d, export, location, index) in &found {
            out.push(self.aoi(d, export, *location, *index)?);
        }
        // No instruction contains itself through its local tags.
        for a in &out {
            let mut path = vec![a.name.clone()];
            if self.contains_itself(a.data_type.index, &mut path) {
                return Err(self.aoi_error(
                    a.span,
                    format!("Add-On Instruction {} contains itself: {}", a.name, path.join(" → ")),
                ));
            }
        }
        // Nor holds more values than a tag may.
        let mut memo = vec![None; self.data_types.borrow().len()];
        for a in &out {
            if self.values_in(a.data_type.index, &mut memo) > super::model::MAX_ARRAY_LEN {
                return Err(self.aoi_error(
                    a.span,
                    format!(
                        "Add-On Instruction {}: an instance would hold more than {} values, local tags of local tags included",
                        a.name,
                        super::model::MAX_ARRAY_LEN
                    ),
                ));
            }
        }
        Ok(out)
    }

    /// The values one instance of data type `id` holds (capped just past
    /// the bound), each type counted once (`memo`).
    fn values_in(&self, id: u16, memo: &mut [Option<usize>]) -> usize {
        if let Some(n) = memo[usize::from(id)] {
            return n;
        }
        let members: Vec<TagType> = self.data_types.borrow()[usize::from(id)]
            .members
            .iter()
            .map(|m| m.ty)
            .collect();
        let cap = super::model::MAX_ARRAY_LEN + 1;
        let n = members
            .iter()
            .map(|t| {
                let one = match t.base {
                    BaseType::User(u) if self.data_types.borrow()[usize::from(u.index)].string_length.is_none() => {
                        self.values_in(u.index, memo)
                    }
                    b => self.leaves(b),
                };
                one.saturating_mul(t.array_len.unwrap_or(1))
            })
            .fold(0usize, |a, b| a.saturating_add(b).min(cap));
        memo[usize::from(id)] = Some(n);
        n
    }

    /// Whether data type `start` holds itself through its members
    /// (`path` the chain when it does): a search that visits each type
    /// once and keeps its own stack, so that neither a wide nor a deep
    /// web of instructions costs more than its size.
    fn contains_itself(&self, start: u16, path: &mut Vec<String>) -> bool {
        let types = self.data_types.borrow();
        let mut done = vec![false; types.len()];
        done[usize::from(start)] = true;
        // Each frame: a type and its next member to look at.
        let mut stack: Vec<(u16, usize)> = vec![(start, 0)];
        while let Some(top) = stack.last_mut() {
            let (t, k) = *top;
            let members = &types[usize::from(t)].members;
            let Some(m) = members.get(k) else {
                stack.pop();
                if !stack.is_empty() {
                    path.pop();
                }
                continue;
            };
            top.1 += 1;
            let BaseType::User(u) = m.ty.base else { continue };
            if u.index == start {
                path.push(format!("{} ({})", m.name, u.name));
                return true;
            }
            if !std::mem::replace(&mut done[usize::from(u.index)], true) {
                path.push(format!("{} ({})", m.name, u.name));
                stack.push((u.index, 0));
            }
        }
        false
    }

    /// Checks a definition's name and registers its data type (members
    /// later): its index.
    fn aoi_name(&self, d: &AoiDefinition, export: &Export) -> Result<usize, SceneError> {
        let name = &d.name.value;
        let name_span = export.span(d.name.span.clone());
        let valid = name.chars().next().is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
            && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_');
        if !valid {
            return Err(self.aoi_error(name_span, format!("'{name}' is not an Add-On Instruction name")));
        }
        if BaseType::parse(name).is_some()
            || self.find_data_type(name).is_some()
            || planner::task::instructions::find(name).is_some()
        {
            return Err(self.aoi_error(
                name_span,
                format!("Add-On Instruction {name}: the name is taken by a data type or an instruction"),
            ));
        }
        let index = self.data_types.borrow().len();
        if index > usize::from(u16::MAX) {
            return Err(self.aoi_error(name_span, "too many data types and Add-On Instructions"));
        }
        self.data_types.borrow_mut().push(DataTypeDef {
            name: name.clone(),
            description: d.description.clone(),
            members: Vec::new(),
            string_length: None,
            location: Location::default(),
        });
        Ok(index)
    }

    fn aoi_export(&self, entry: &Spanned<String>, base: &Path, field: &str) -> Result<Export, SceneError> {
        let rel = Path::new(entry.get_ref());
        if let Some(e) = &self.expanded
            && let Some((_, v)) = e.aois.iter().find(|(p, _)| p == rel)
        {
            return Ok(Export {
                text: Arc::clone(&v.text),
                file: e.l5x_file,
                map: Some(Arc::clone(&v.map)),
            });
        }
        let path = base.join(rel);
        if !path.is_file() {
            return Err(self.invalid(entry, field, super::error::Problem::MissingFile { path: path.clone() }));
        }
        let text = crate::source::read_text_bounded(&path, crate::source::InputKind::Routine).map_err(|e| {
            SceneError::Syntax(Box::new(Diagnostic::error(format!(
                "{}: cannot read the Add-On Instruction export: {e}",
                path.display()
            ))))
        })?;
        let file = self.files.borrow_mut().add(path, text);
        let text = Arc::clone(&self.files.borrow().get(file).text);
        Ok(Export { text, file, map: None })
    }

    fn aoi(&self, d: &AoiDefinition, export: &Export, location: Location, index: usize) -> Result<AoiDef, SceneError> {
        let name = d.name.value.clone();
        let name_span = export.span(d.name.span.clone());
        let mut members = vec![
            member("EnableIn", TagType::new(BaseType::Bool, None)),
            member("EnableOut", TagType::new(BaseType::Bool, None)),
        ];
        let mut parameters = Vec::new();
        let mut defaults = Vec::new();
        for p in &d.parameters {
            let pname = p.name.value.clone();
            let span = export.span(p.name.span.clone());
            if pname.eq_ignore_ascii_case("EnableIn") || pname.eq_ignore_ascii_case("EnableOut") {
                continue;
            }
            let usage = match p.usage.value.as_str() {
                "Input" => AoiUsage::Input,
                "Output" => AoiUsage::Output,
                "InOut" => AoiUsage::InOut,
                other => {
                    return Err(self.aoi_error(
                        export.span(p.usage.span.clone()),
                        format!("{name}.{pname}: Usage=\"{other}\": expected Input, Output or InOut"),
                    ));
                }
            };
            let dims = p
                .dimensions
                .as_ref()
                .map(|d| d.value.trim().to_owned())
                .filter(|d| d != "0");
            let ty = self.aoi_type(
                &format!("{name}.{pname}"),
                &p.data_type.value,
                dims.as_deref(),
                &export.span(p.data_type.span.clone()),
            )?;
            if usage != AoiUsage::InOut {
                let atomic = ty.is_some_and(|t| t.array_len.is_none() && t.base.is_atomic());
                if !atomic {
                    return Err(self.aoi_error(
                        export.span(p.data_type.span.clone()),
                        format!(
                            "{name}.{pname}: an {} parameter is BOOL or a number; pass a {} as InOut",
                            p.usage.value, p.data_type.value
                        ),
                    ));
                }
                members.push(member(&pname, ty.expect("atomic")));
                if let Some(v) = p.default.as_ref().and_then(|v| scalar(&v.value)) {
                    defaults.push((pname.clone(), v));
                }
            }
            parameters.push(AoiParam {
                name: pname,
                data_type: p.data_type.value.clone(),
                ty,
                usage,
                required: p.required || usage == AoiUsage::InOut,
                constant: p.constant,
                span,
            });
        }
        let mut locals = Vec::new();
        for l in &d.local_tags {
            let dims = l
                .dimensions
                .as_ref()
                .map(|d| d.value.trim().to_owned())
                .filter(|d| d != "0");
            let span = export.span(l.data_type.span.clone());
            let owner = format!("{name}.{}", l.name.value);
            let ty = self.aoi_type(&owner, &l.data_type.value, dims.as_deref(), &span)?;
            let Some(ty) = ty.filter(|t| super::data_types::member_type_allowed(t.base)) else {
                return Err(self.aoi_error(
                    span,
                    format!(
                        "{name}.{}: a local tag of type {} (an axis, a coordinate system, a cam): pass it as an InOut parameter",
                        l.name.value, l.data_type.value
                    ),
                ));
            };
            members.push(member(&l.name.value, ty));
            if let Some(v) = l.default.as_ref().and_then(|v| scalar(&v.value)) {
                defaults.push((l.name.value.clone(), v));
            }
            locals.push(l.name.value.clone());
        }
        let mut seen: Vec<String> = Vec::new();
        for m in &members {
            let lower = m.name.to_ascii_lowercase();
            if seen.contains(&lower) {
                return Err(self.aoi_error(
                    name_span,
                    format!("{name}: two parameters or local tags named {}", m.name),
                ));
            }
            seen.push(lower);
        }
        {
            let mut types = self.data_types.borrow_mut();
            types[index].members = members;
            types[index].location = location;
        }
        let data_type = UserType {
            index: index as u16,
            name: intern(&name),
        };
        let routine = |which: &str| d.routines.iter().find(|r| r.name.value.eq_ignore_ascii_case(which));
        let Some(logic) = routine("Logic") else {
            return Err(self.aoi_error(name_span, format!("Add-On Instruction {name} has no Logic routine")));
        };
        let logic = self.aoi_routine(&name, logic, export)?;
        let optional = |flag: bool, which: &str| -> Result<Option<RoutineDef>, SceneError> {
            if !flag {
                return Ok(None);
            }
            match routine(which) {
                Some(r) => Ok(Some(self.aoi_routine(&name, r, export)?)),
                None => Err(self.aoi_error(
                    name_span,
                    format!("Add-On Instruction {name}: Execute{which}=\"true\" but it has no {which} routine"),
                )),
            }
        };
        Ok(AoiDef {
            prescan: optional(d.execute_prescan, "Prescan")?,
            enable_in_false: optional(d.execute_enable_in_false, "EnableInFalse")?,
            name,
            data_type,
            parameters,
            locals,
            defaults,
            logic,
            span: name_span,
            location,
        })
    }

    /// A parameter's or local tag's type: `None` for an axis (an InOut).
    fn aoi_type(
        &self,
        owner: &str,
        data_type: &str,
        dims: Option<&str>,
        span: &Span,
    ) -> Result<Option<TagType>, SceneError> {
        if data_type.starts_with("AXIS_") {
            return Ok(None);
        }
        let Some(base) = BaseType::parse(data_type).or_else(|| self.find_data_type(data_type)) else {
            return Err(self.aoi_error(*span, format!("{owner}: unknown data type {data_type}")));
        };
        let len = match dims {
            None => None,
            Some(d) => {
                let mut n = 1usize;
                for part in d.split_whitespace() {
                    let k: usize = part.parse().ok().filter(|k| *k > 0).ok_or_else(|| {
                        self.aoi_error(*span, format!("{owner}: Dimensions=\"{d}\": expected whole numbers"))
                    })?;
                    n = n.saturating_mul(k);
                }
                if n > super::model::MAX_ARRAY_LEN {
                    return Err(self.aoi_error(
                        *span,
                        format!(
                            "{owner}: Dimensions=\"{d}\": more than {} elements",
                            super::model::MAX_ARRAY_LEN
                        ),
                    ));
                }
                Some(n)
            }
        };
        Ok(Some(TagType::new(base, len)))
    }

    fn aoi_routine(&self, aoi: &str, r: &l5x::Routine, export: &Export) -> Result<RoutineDef, SceneError> {
        let Some((text, map)) = &r.text else {
            return Err(self.aoi_error(
                export.span(r.kind.span.clone()),
                format!(
                    "Add-On Instruction {aoi}'s {} routine is {}, which the twin does not simulate",
                    r.name.value, r.kind.value
                ),
            ));
        };
        let map = export.routine_map(map);
        let files = self.files.borrow();
        let source = Source::embedded(text, &files, export.file, map);
        let ladder = r.kind.value == "RLL";
        let parsed = if ladder {
            parse_ladder(&source)
        } else {
            parse_routine(&source)
        };
        let routine = parsed.map_err(|d| {
            let line = d
                .labels
                .first()
                .and_then(|l| source_line(text, &source, l.range.start))
                .unwrap_or(0);
            let at = if ladder {
                format!("{aoi}/{} rung {line}", r.name.value)
            } else {
                format!("{aoi}/{} Line Number=\"{line}\"", r.name.value)
            };
            SceneError::Syntax(Box::new((*d).in_field(at)))
        })?;
        Ok(RoutineDef {
            name: format!("{aoi}_{}", r.name.value),
            path: files.path(export.file).to_path_buf(),
            dialect: super::model::Dialect::Logix,
            routine,
        })
    }
}

/// The text line (from 0) of file byte `at` in an embedded text.
fn source_line(text: &str, source: &Source<'_>, at: usize) -> Option<usize> {
    let i = (0..=text.len()).find(|&i| source.span(i, i).start as usize >= at)?;
    Some(text[..i.min(text.len())].matches('\n').count())
}

fn member(name: &str, ty: TagType) -> MemberDef {
    MemberDef {
        name: name.to_owned(),
        ty,
        description: String::new(),
        location: Location::default(),
    }
}

fn scalar(v: &l5x::Value) -> Option<f64> {
    match v {
        l5x::Value::Bool(b) => Some(f64::from(u8::from(*b))),
        l5x::Value::Int(i) => Some(*i as f64),
        l5x::Value::Float(f) => Some(*f),
        _ => None,
    }
}
