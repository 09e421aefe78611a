//! References: a tag, an element, a member or a bit resolved to the place
//! it reads or writes, and the structure and array operands of
//! instructions.

use super::{Compiler, Error, Result, constant, err, show, suggest};
use crate::program::ir::{
    AXIS_MEMBERS, ArrayAt, CExpr, CKind, CoordMember, DataAt, FbMember, Instance, MotionMember, Place, Term,
};
use crate::program::layout::Elem;
use crate::program::memory::{Kind, TagInfo};
use crate::program::types::{DataType, Structure, Ty, Value};
use crate::scene::BaseType;
use crate::source::Span;
use crate::st::ast::{Access, Arg, Expr, ExprKind, Ref};
use planner::instruction::MotionInstructionBits;

/// The `MOTION_INSTRUCTION` bits a program names.
const BIT_NAMES: [&str; 8] = ["EN", "DN", "ER", "IP", "AC", "PC", "ACCEL", "DECEL"];

/// How many aliases in a row a name may go through (an alias of an alias).
const MAX_ALIAS_CHAIN: usize = 16;

impl Compiler<'_, '_, '_> {
    /// `r` with the aliases it names replaced by what they stand for
    /// (`Placed.0` → `Recipe.Count.0` when `Placed` is an alias for
    /// `Recipe.Count`), scoped as tags are.
    pub fn dealias(&self, r: &mut Ref) {
        for _ in 0..MAX_ALIAS_CHAIN {
            let Some(target) = self.mem.alias(self.program, &r.name) else {
                return;
            };
            let mut path = target.path.clone();
            path.append(&mut r.path);
            r.name.clone_from(&target.name);
            r.path = path;
        }
    }

    /// `e` with its aliases replaced (see [`Compiler::dealias`]); borrowed
    /// when the scene has none.
    pub fn dealias_expr<'x>(&self, e: &'x Expr) -> std::borrow::Cow<'x, Expr> {
        if self.mem.aliases.is_empty() {
            return std::borrow::Cow::Borrowed(e);
        }
        let mut e = e.clone();
        e.refs_mut(&mut |r| self.dealias(r));
        std::borrow::Cow::Owned(e)
    }

    /// The tag a name resolves to in this scope.
    pub(super) fn resolve(&self, name: &str) -> Option<usize> {
        self.mem.resolve(self.program, name)
    }

    pub(super) fn tag(&self, r: &Ref) -> Result<usize> {
        self.resolve(&r.name).ok_or_else(|| match r.path.first() {
            Some(Access::Member(m, span)) if self.is_program(&r.name) => self.unknown_program_tag(&r.name, m, *span),
            _ => self.unknown_name(&r.name, r.name_span()),
        })
    }

    /// Whether `name` is a program with tags (`Program.Tag` in memory).
    fn is_program(&self, name: &str) -> bool {
        self.mem.tags.iter().any(|t| program_member(&t.name, name).is_some())
    }

    /// `Program.X` where the program has no tag `X`, with its nearest tag.
    fn unknown_program_tag(&self, program: &str, member: &str, span: Span) -> Error {
        let d = self.error(
            span,
            format!("program '{program}' has no tag '{member}'"),
            "not a tag of the program",
        );
        let own: Vec<&str> = self
            .mem
            .tags
            .iter()
            .filter_map(|t| program_member(&t.name, program))
            .collect();
        suggest(d, member, own)
    }

    /// `'X' is not a tag …`, with the nearest name this scope knows.
    pub(super) fn unknown_name(&self, name: &str, span: Span) -> Error {
        let scope = match self.program {
            Some(_) => "a tag of this program, a controller tag or an axis",
            None => "a controller tag or an axis",
        };
        let d = self.error(span, format!("'{name}' is not {scope}"), "unknown name");
        suggest(d, name, self.visible_names())
    }

    /// The names visible in this scope: the program's own tags (short),
    /// the controller's tags and axes, other programs' as `Program.Tag`,
    /// and the trace columns the compiler has.
    fn visible_names(&self) -> Vec<&str> {
        let own = self.program.map(|p| format!("{p}."));
        self.mem
            .tags
            .iter()
            .map(|t| match &own {
                Some(prefix) if t.name.len() > prefix.len() && t.name[..prefix.len()].eq_ignore_ascii_case(prefix) => {
                    &t.name[prefix.len()..]
                }
                _ => t.name.as_str(),
            })
            .chain(self.columns.iter().map(|c| c.name.as_str()))
            .collect()
    }

    /// A write to a `constant = true` tag, refused.
    pub(super) fn refuse_constant(&self, r: &Ref) -> Result<()> {
        let t = match r.name.strip_prefix('\\') {
            Some(program) => match r.path.first() {
                Some(Access::Member(m, _)) => self.mem.find(&format!("{program}.{m}")),
                _ => None,
            },
            None => self
                .resolve(&r.name)
                .or_else(|| self.qualified(r).and_then(|q| self.mem.find(&q.name))),
        };
        match t {
            Some(t) if self.mem.tags[t].constant => Err(self.error(
                r.span,
                format!(
                    "'{}' is a constant tag (constant = true): a routine does not write it",
                    show(r)
                ),
                "constant",
            )),
            _ => Ok(()),
        }
    }

    /// A place that may be written, with its type.
    pub(super) fn writable(&mut self, r: &Ref) -> Result<(Place, DataType)> {
        self.refuse_constant(r)?;
        let (place, ty) = self.place(r)?;
        match place {
            Place::Axis(..)
            | Place::Coord(..)
            | Place::Group(..)
            | Place::Fb(..)
            | Place::FirstScan
            | Place::MinorInScan
            | Place::MathFlag(_)
            | Place::MinorFaults
            | Place::Column { .. } => err(
                self,
                r.span,
                format!(
                    "'{}' is read-only (axis and coordinate-system members, the S: status flags and MinorFaults are the controller's)",
                    show(r)
                ),
            ),
            Place::Motion(_, MotionMember::Bit(_)) | Place::MotionAt(_, _, MotionMember::Bit(_), _) => Ok((place, ty)),
            Place::Motion(..) | Place::MotionAt(..) => err(
                self,
                r.span,
                format!("'{}' is read-only: the instruction writes its codes", show(r)),
            ),
            _ => Ok((place, ty)),
        }
    }

    /// A reference the trace reads (`State`, `Pos[0]`, `MC1.PC`,
    /// `Prog.Count`, `Axis.ActualPosition`), subscripts constant.
    ///
    /// # Errors
    /// A diagnostic when it is not a reference, or names nothing readable.
    pub fn traced(&mut self, e: &Expr) -> Result<(Place, DataType)> {
        match &e.kind {
            ExprKind::Ref(r) => self.place(r),
            _ => err(
                self,
                e.span,
                "not a tag reference: a trace column reads a tag, an element, a member or a bit",
            ),
        }
    }

    /// `Program.Tag` written from outside the program: the qualified tag.
    pub(super) fn qualified(&self, r: &Ref) -> Option<Ref> {
        if self.resolve(&r.name).is_some() {
            return None;
        }
        let Some(Access::Member(m, _)) = r.path.first() else {
            return None;
        };
        let name = format!("{}.{m}", r.name);
        self.mem.find(&name)?;
        Some(Ref {
            name,
            path: r.path[1..].to_vec(),
            span: r.span,
        })
    }

    /// Resolves a reference: a tag's place or, where the compiler has
    /// trace columns, a column of that name (a tag's member where it is
    /// one, `MC1.PC`). A column that is not a tag's (`collision.count`)
    /// named through a tag of the same name is refused, naming both.
    pub(super) fn place(&mut self, r: &Ref) -> Result<(Place, DataType)> {
        if self.columns.is_empty() {
            return self.tag_place(r);
        }
        let column =
            column_name(r).and_then(|name| self.columns.iter().position(|c| c.name.eq_ignore_ascii_case(&name)));
        match column {
            Some(i) if !self.columns[i].of_tag && (self.resolve(&r.name).is_some() || self.qualified(r).is_some()) => {
                err(
                    self,
                    r.span,
                    format!(
                        "'{}' names both the tag '{}' and the trace column '{}': rename the tag",
                        show(r),
                        r.name,
                        self.columns[i].name
                    ),
                )
            }
            Some(index) => match self.tag_place(r) {
                Ok(found) => Ok(found),
                Err(_) => {
                    let ty = self.columns[index].ty;
                    Ok((Place::Column { index, ty }, ty))
                }
            },
            None => self.tag_place(r),
        }
    }

    /// `\Program.Param`: another program's Input, Output or Public
    /// parameter (1756-PM021); its InOut parameters and local tags are not
    /// reachable.
    fn parameter_place(&mut self, r: &Ref, program: &str) -> Result<(Place, DataType)> {
        let Some(Access::Member(param, span)) = r.path.first() else {
            return err(
                self,
                r.span,
                format!("'{}': name a parameter, \\{program}.Param", r.name),
            );
        };
        let stored = format!("{program}.{param}");
        let Some(t) = self.mem.find_declared(&stored) else {
            return err(
                self,
                r.span,
                format!("'\\{stored}' is not a tag of a program {program}"),
            );
        };
        let usage = self.mem.tags[t].usage;
        if !usage.reachable() {
            return Err(self.error(
                *span,
                format!(
                    "'\\{stored}' is {}: only Input, Output and Public parameters are reachable from another program",
                    if usage == crate::scene::Usage::InOut {
                        "an InOut parameter"
                    } else {
                        "a local tag"
                    }
                ),
                "not reachable from here",
            ));
        }
        self.tag_place(&Ref {
            name: stored,
            path: r.path[1..].to_vec(),
            span: r.span,
        })
    }

    /// Resolves a reference to a tag's place.
    fn tag_place(&mut self, r: &Ref) -> Result<(Place, DataType)> {
        if let Some(program) = r.name.strip_prefix('\\') {
            return self.parameter_place(r, program);
        }
        let found = self.resolve(&r.name);
        if found.is_none()
            && let Some(q) = self.qualified(r)
        {
            if self.scanned
                && let Some(own) = self.program
                && let Some((other, _)) = q.name.split_once('.')
                && !other.eq_ignore_ascii_case(own)
            {
                let d = self.error(
                    r.span,
                    format!(
                        "'{}' is a tag of program {other}: a program reads another program's Input, Output and Public parameters only, as \\{}",
                        show(r),
                        show(r)
                    ),
                    "another program's tag",
                );
                return Err(Box::new(d.with_help(format!(
                    "make it a parameter of {other} (usage = \"output\" or \"public\") and write \\{}, or connect an Input parameter of this program to it",
                    show(r)
                ))));
            }
            return self.tag_place(&q);
        }
        let t = match found {
            Some(t) => t,
            None => {
                if let Some(flag) = self.status_flag(r)? {
                    return Ok(flag);
                }
                self.tag(r)?
            }
        };
        let mem = self.mem;
        let info = &mem.tags[t];
        let mut path = r.path.iter();
        let member = |path: &mut std::slice::Iter<'_, Access>, hint: &str| match path.next() {
            Some(Access::Member(m, span)) => Ok((m.clone(), *span)),
            _ => err(self, r.span, format!("'{}' is {hint}", r.name)),
        };
        let (place, ty) = match info.kind {
            Kind::Scalar(_) | Kind::Structure(_) | Kind::User(_) => self.memory_place(r, info, &mut path)?,
            Kind::Axis => {
                let m = member(
                    &mut path,
                    &format!("an axis: name a member, e.g. {}.ActualPosition", r.name),
                )?;
                self.axis_place(&info.name, &m)?
            }
            Kind::Planner(BaseType::MotionInstruction) => {
                let element = match (info.len, path.as_slice().first()) {
                    (None, _) => None,
                    (Some(_), Some(Access::Index(sub))) => {
                        path.next();
                        Some(self.control_element(r, info, sub)?)
                    }
                    (Some(_), _) => {
                        return err(
                            self,
                            r.span,
                            format!("'{}' is an array: name an element, e.g. {}[0].PC", r.name, r.name),
                        );
                    }
                };
                let m = match path.next() {
                    Some(Access::Member(m, span)) => (m.clone(), *span),
                    _ => {
                        return err(
                            self,
                            r.span,
                            format!(
                                "'{}' is a MOTION_INSTRUCTION: name a member, e.g. {}.PC",
                                show(r),
                                show(r)
                            ),
                        );
                    }
                };
                let (member, ty) = self.motion_member(&m)?;
                match element {
                    None => (Place::Motion(self.env.control(&info.name), member), ty),
                    Some(ControlRef::One(h)) => (Place::Motion(h, member), ty),
                    Some(ControlRef::At(handles, index)) => {
                        (Place::MotionAt(handles, Box::new(index), member, info.name.clone()), ty)
                    }
                }
            }
            Kind::Planner(BaseType::CoordinateSystem) => {
                let m = member(&mut path, "a COORDINATE_SYSTEM: name a status bit")?;
                self.coord_place(r, &info.name, &m)?
            }
            Kind::Planner(BaseType::MotionGroup) => {
                let (m, span) = member(&mut path, "a MOTION_GROUP: name a member, e.g. Group.GroupStatus")?;
                match crate::program::ir::GROUP_MEMBERS
                    .iter()
                    .find(|(n, _)| n.eq_ignore_ascii_case(&m))
                {
                    Some((_, member @ crate::program::ir::GroupMember::StatusBit(_))) => {
                        (Place::Group(*member), DataType::Bool)
                    }
                    Some((_, member)) => (Place::Group(*member), DataType::Dint),
                    None => {
                        let names = crate::program::ir::GROUP_MEMBERS.iter().map(|(n, _)| *n);
                        let list: Vec<&str> = names.clone().collect();
                        let d = self.error(
                            span,
                            format!("MOTION_GROUP has no member '{m}' (members: {})", list.join(", ")),
                            "no such member",
                        );
                        return Err(suggest(d, &m, names));
                    }
                }
            }
            Kind::Planner(BaseType::FunctionBlock(_)) => {
                let m = member(
                    &mut path,
                    &format!("a function block: name an output, e.g. {}.Done", r.name),
                )?;
                self.fb_place(r, &info.name, &m)?
            }
            Kind::Planner(base) => {
                return err(
                    self,
                    r.span,
                    format!(
                        "'{}' is a {} tag: a program does not read it in an expression",
                        r.name,
                        base.name()
                    ),
                );
            }
        };
        let (place, ty) = match path.next() {
            Some(access) => self.bit_of(r, place, ty, access)?,
            None => (place, ty),
        };
        if path.next().is_some() {
            return err(self, r.span, format!("'{}': too many parts", show(r)));
        }
        Ok((place, ty))
    }

    /// `S:FS`, `S:MINOR` and the `MinorFaults` counter.
    ///
    /// The math status flags `S:N`, `S:Z`, `S:V`, `S:C` are set by ladder
    /// instructions only on a 5580 (1756-RM003, "Math Status Flags"):
    /// Structured Text never sets them, so here they read FALSE, and a
    /// routine reading one gets a warning.
    fn status_flag(&mut self, r: &Ref) -> Result<Option<(Place, DataType)>> {
        if !r.path.is_empty() {
            return Ok(None);
        }
        Ok(match r.name.to_ascii_uppercase().as_str() {
            "S:FS" => Some((Place::FirstScan, DataType::Bool)),
            "S:MINOR" => Some((Place::MinorInScan, DataType::Bool)),
            "S:N" | "S:Z" | "S:V" | "S:C" => {
                let flag = match r.name.to_ascii_uppercase().as_str() {
                    "S:N" => crate::program::ir::MATH_N,
                    "S:Z" => crate::program::ir::MATH_Z,
                    "S:V" => crate::program::ir::MATH_V,
                    _ => crate::program::ir::MATH_C,
                };
                if !self.ladder {
                    let d = crate::source::Diagnostic::warning(format!(
                        "{} is a math status flag: on a 5580 only ladder instructions set it, Structured Text never does",
                        r.name.to_ascii_uppercase()
                    ))
                    .with_label(self.env.files.label(r.span, "not set by Structured Text"))
                    .with_help("test the value itself (X < 0 for S:N, X = 0 for S:Z); overflow is counted in MinorFaults and S:MINOR");
                    self.env.bindings.warnings.push(d);
                }
                Some((Place::MathFlag(flag), DataType::Bool))
            }
            n if n.starts_with("S:") => {
                return err(
                    self,
                    r.span,
                    format!(
                        "status flag {} is not modelled (S:FS, S:MINOR, S:N, S:Z, S:V and S:C are)",
                        r.name
                    ),
                );
            }
            "MINORFAULTS" if self.resolve(&r.name).is_none() => Some((Place::MinorFaults, DataType::Dint)),
            _ => None,
        })
    }

    /// A scalar, an element, or a member of a structure (or of an element
    /// of an array of them) in tag memory.
    fn memory_place(
        &mut self,
        r: &Ref,
        info: &TagInfo,
        path: &mut std::slice::Iter<'_, Access>,
    ) -> Result<(Place, DataType)> {
        let Kind::Structure(s) = info.kind else {
            return self.data_place(r, info, path);
        };
        let index = match (info.len, path.as_slice().first()) {
            (Some(len), Some(Access::Index(sub))) => {
                path.next();
                Some((self.checked_subscript(sub, r, info)?, len))
            }
            (Some(_), _) => {
                return err(
                    self,
                    r.span,
                    format!("'{}' is an array: name an element, e.g. {}[0]", r.name, r.name),
                );
            }
            (None, _) => None,
        };
        let Some(Access::Member(m, span)) = path.next() else {
            return err(
                self,
                r.span,
                format!(
                    "'{}' is a {}: name a member ({})",
                    r.name,
                    s.name(),
                    s.visible_members()
                ),
            );
        };
        let (offset, ty) = self.structure_member(s, m, *span)?;
        let place = match index {
            Some((index, len)) => Place::Element {
                base: info.base,
                len,
                stride: s.size(),
                offset,
                index,
                name: info.name.clone(),
            },
            None => Place::Slot(info.base + offset),
        };
        Ok((place, ty))
    }

    /// A member a program may name of an instruction's structure: its slot
    /// offset and type.
    fn structure_member(&self, s: Structure, m: &str, span: Span) -> Result<(usize, DataType)> {
        s.member(m).ok_or_else(|| {
            let d = self.error(
                span,
                format!("{} has no member '{m}' (members: {})", s.name(), s.visible_members()),
                "no such member",
            );
            let names = s.visible_members();
            suggest(d, m, names.split(", "))
        })
    }

    /// A scalar tag, an element of a scalar array, or a scalar member of a
    /// data type (`Cell.Station[I].Pos[J]`), down to a scalar.
    fn data_place(
        &mut self,
        r: &Ref,
        info: &TagInfo,
        path: &mut std::slice::Iter<'_, Access>,
    ) -> Result<(Place, DataType)> {
        let at = self.locate(r, info, path)?;
        // The reference as far as it went, for messages (`Cell.Pos`).
        let shown = || show_upto(r, path);
        if at.array.is_some() {
            let shown = shown();
            return err(
                self,
                r.span,
                format!("'{shown}' is an array: name an element, e.g. {shown}[0]"),
            );
        }
        let ty = match at.elem {
            Elem::Scalar(ty) => ty,
            Elem::Control => {
                let shown = shown();
                let Some(Access::Member(m, span)) = path.next() else {
                    return err(
                        self,
                        r.span,
                        format!("'{shown}' is a MOTION_INSTRUCTION: name a member, e.g. {shown}.PC"),
                    );
                };
                let (member, ty) = self.motion_member(&(m.clone(), *span))?;
                let place = match self.control_in_structure(info, at, r.span)? {
                    ControlRef::One(h) => Place::Motion(h, member),
                    ControlRef::At(handles, index) => Place::MotionAt(handles, Box::new(index), member, shown),
                };
                return Ok((place, ty));
            }
            Elem::User(id) if self.mem.layouts.get(id).builtin.is_some() => {
                let s = self.mem.layouts.get(id).builtin.expect("a structure");
                let shown = shown();
                return err(
                    self,
                    r.span,
                    format!("'{shown}' is a {}: name a member ({})", s.name(), s.visible_members()),
                );
            }
            Elem::User(id) => {
                let l = self.mem.layouts.get(id);
                let how = if l.string.is_some() {
                    "name a member (LEN, DATA[i]) or pass it to a string instruction"
                } else {
                    "name a member, or copy it whole with COP"
                };
                let shown = shown();
                return err(
                    self,
                    r.span,
                    format!("'{shown}' is a {}: {how} (members: {})", l.name, l.member_names()),
                );
            }
        };
        let place = match (at.terms.len(), at.tag_term) {
            (0, _) => Place::Slot(info.base + at.slot),
            (1, true) => {
                let t = at.terms.into_iter().next().expect("one term");
                Place::Element {
                    base: info.base,
                    len: t.len,
                    stride: t.slots,
                    offset: at.slot,
                    index: t.index,
                    name: t.name,
                }
            }
            _ => Place::Path {
                base: info.base + at.slot,
                terms: at.terms.into_boxed_slice(),
            },
        };
        Ok((place, ty))
    }

    /// Walks a reference through a tag kept as scalars or a data type:
    /// the tag's own subscripts, then members and their subscripts, as far
    /// as the path goes (the rest, a bit number, is the caller's).
    pub(super) fn locate(
        &mut self,
        r: &Ref,
        info: &TagInfo,
        path: &mut std::slice::Iter<'_, Access>,
    ) -> Result<Located> {
        let mem = self.mem;
        let Some(elem) = info.elem() else {
            return err(
                self,
                r.span,
                format!("'{}' is a {} tag, not data in tag memory", r.name, info.type_name),
            );
        };
        let mut at = Located {
            slot: 0,
            byte: 0,
            terms: Vec::new(),
            elem,
            array: None,
            tag_term: false,
            parts: Vec::new(),
        };
        if let Some(len) = info.len {
            let Some(Access::Index(sub)) = path.as_slice().first() else {
                at.array = Some(len);
                at.parts.push(NamePart::Tag);
                return Ok(at);
            };
            path.next();
            let index = self.checked_subscript(sub, r, info)?;
            let bytes = mem.layouts.bytes(elem);
            let constant = constant_of(&index);
            at.tag_term = self.push_term(&mut at, index, len, info.stride, bytes, &info.name);
            at.parts.push(match (at.tag_term, constant) {
                (false, Some(k)) => NamePart::TagConstant(k as usize),
                _ => NamePart::TagElement,
            });
        } else {
            at.parts.push(NamePart::Tag);
        }
        // The path as far as it has gone (`Cell.Station`), written once a
        // member is named.
        let mut shown = String::new();
        while let (Elem::User(id), Some(Access::Member(m, span))) = (at.elem, path.as_slice().first()) {
            path.next();
            if shown.is_empty() {
                shown.push_str(&info.name);
            }
            let layout = mem.layouts.get(id);
            if let Some(s) = layout.builtin {
                // An instruction's structure: its visible members only.
                let (offset, ty) = self.structure_member(s, m, *span)?;
                at.slot += offset;
                at.byte += layout.members[offset].byte;
                at.elem = Elem::Scalar(ty);
                break;
            }
            let Some(member) = layout.member(m) else {
                let d = self.error(
                    *span,
                    format!(
                        "{} has no member '{m}' (members: {})",
                        layout.name,
                        layout.member_names()
                    ),
                    "no such member",
                );
                return Err(suggest(d, m, layout.members.iter().map(|m| m.name.as_str())));
            };
            at.slot += member.slot;
            at.byte += member.byte;
            at.elem = member.elem;
            shown = format!("{shown}.{}", member.name);
            at.parts.push(NamePart::Text(format!(".{}", member.name)));
            let Some(len) = member.len else { continue };
            let Some(Access::Index(sub)) = path.as_slice().first() else {
                at.array = Some(len);
                break;
            };
            path.next();
            if sub.len() != 1 {
                return err(
                    self,
                    r.span,
                    format!("'{shown}' has 1 dimension, got {} subscripts", sub.len()),
                );
            }
            let index = self.integer(&sub[0])?;
            if !self.scanned && !matches!(index.kind, CKind::Const(v) if (0..len as i64).contains(&v.as_i64())) {
                return Err(self.error(
                    sub[0].span,
                    format!(
                        "a step's or a scene's subscript is a constant inside the array (valid: 0 to {})",
                        len - 1
                    ),
                    format!("'{shown}' has {len} elements"),
                ));
            }
            let (slots, bytes) = (mem.layouts.slots(at.elem), mem.layouts.bytes(at.elem));
            let constant = constant_of(&index);
            let added = self.push_term(&mut at, index, len, slots, bytes, &shown);
            at.parts.push(match (added, constant) {
                (false, Some(k)) => NamePart::Constant(k),
                _ => NamePart::Index,
            });
        }
        Ok(at)
    }

    /// The control structure a path through data types ends on (a
    /// `MOTION_INSTRUCTION` member, `Axes[I].Move`): its handle when every
    /// subscript is a constant, else every element's handle, in the
    /// row-major order of the computed subscripts, and the element index
    /// the scan computes (each subscript checked: major fault 4/20). Each
    /// is named by its full path (`Axes[2].Move`) in the trace.
    pub(super) fn control_in_structure(&mut self, info: &TagInfo, at: Located, span: Span) -> Result<ControlRef> {
        let Located { terms, parts, .. } = at;
        let render = |values: &[usize]| {
            let mut name = String::new();
            let mut k = 0;
            for p in &parts {
                match p {
                    NamePart::Tag => name.push_str(&info.name),
                    NamePart::TagConstant(k) => name.push_str(&element_name(info, *k)),
                    NamePart::Text(t) => name.push_str(t),
                    NamePart::Constant(k) => name.push_str(&format!("[{k}]")),
                    NamePart::TagElement => {
                        name.push_str(&element_name(info, values[k]));
                        k += 1;
                    }
                    NamePart::Index => {
                        name.push_str(&format!("[{}]", values[k]));
                        k += 1;
                    }
                }
            }
            name
        };
        if terms.is_empty() {
            return Ok(ControlRef::One(self.env.control(&render(&[]))));
        }
        let count = terms.iter().try_fold(1usize, |n, t| n.checked_mul(t.len));
        let Some(count) = count.filter(|n| *n <= MAX_CONTROL_ELEMENTS) else {
            return err(
                self,
                span,
                format!(
                    "'{}' reaches more than {MAX_CONTROL_ELEMENTS} control structures through computed subscripts: use constant subscripts for some",
                    render(&vec![0; terms.len()])
                ),
            );
        };
        let mut handles = Vec::with_capacity(count);
        let mut values = vec![0usize; terms.len()];
        for _ in 0..count {
            handles.push(self.env.control(&render(&values)));
            for d in (0..terms.len()).rev() {
                values[d] += 1;
                if values[d] < terms[d].len {
                    break;
                }
                values[d] = 0;
            }
        }
        let name = render(&vec![0; terms.len()]);
        let index = if terms.len() == 1 {
            terms.into_iter().next().expect("one term").index
        } else {
            let parts: Vec<(CExpr, usize)> = terms.into_iter().map(|t| (t.index, t.len)).collect();
            CExpr {
                kind: CKind::Subscripts(parts.into_boxed_slice(), name.clone()),
                ty: Ty::Dint,
            }
        };
        Ok(ControlRef::At(handles.into_boxed_slice(), index))
    }

    /// Folds a constant subscript inside the array into the offsets, else
    /// adds a computed one; whether it added one.
    fn push_term(&self, at: &mut Located, index: CExpr, len: usize, slots: usize, bytes: usize, name: &str) -> bool {
        if let CKind::Const(v) = index.kind
            && (0..len as i64).contains(&v.as_i64())
        {
            at.slot += v.as_i64() as usize * slots;
            at.byte += v.as_i64() as usize * bytes;
            return false;
        }
        at.terms.push(Term {
            index,
            len,
            slots,
            bytes,
            name: name.to_owned(),
        });
        true
    }

    fn axis_place(&mut self, axis: &str, (m, span): &(String, Span)) -> Result<(Place, DataType)> {
        let Some((_, member, ty)) = AXIS_MEMBERS.iter().find(|(n, ..)| n.eq_ignore_ascii_case(m)) else {
            let names: Vec<&str> = AXIS_MEMBERS.iter().map(|a| a.0).collect();
            let d = self.error(
                *span,
                format!("axis member '{m}' is not modelled (members: {})", names.join(", ")),
                "not an axis member",
            );
            return Err(suggest(d, m, names));
        };
        let Some(handle) = self.env.axis(axis) else {
            return err(self, *span, format!("axis '{axis}' is not in the planner"));
        };
        Ok((Place::Axis(handle, *member), *ty))
    }

    /// A `MOTION_INSTRUCTION` member by its name.
    fn motion_member(&self, (m, span): &(String, Span)) -> Result<(MotionMember, DataType)> {
        let upper = m.to_ascii_uppercase();
        debug_assert!(MotionInstructionBits::default().bits().len() == BIT_NAMES.len());
        Ok(match (BIT_NAMES.iter().find(|b| **b == upper), upper.as_str()) {
            (Some(b), _) => (MotionMember::Bit(b), DataType::Bool),
            (None, "ERR") => (MotionMember::Err, DataType::Int),
            (None, "EXERR") => (MotionMember::Exerr, DataType::Sint),
            (None, "SEGMENT") => (MotionMember::Segment, DataType::Dint),
            (None, _) => {
                let members = BIT_NAMES.join(", ");
                let d = self.error(
                    *span,
                    format!("MOTION_INSTRUCTION has no member '{m}' (members: {members}, ERR, EXERR, SEGMENT)"),
                    "no such member",
                );
                let known = BIT_NAMES.iter().copied().chain(["ERR", "EXERR", "SEGMENT"]);
                return Err(suggest(d, m, known));
            }
        })
    }

    /// The element of a `MOTION_INSTRUCTION` array that subscripts `sub`
    /// name: its handle for constant subscripts inside the array, else
    /// every element's handle and the element index the scan computes
    /// (and checks: major fault 4/20). Each element is a control structure
    /// of its own, named `Tag[i]` (`Tag[i,j]`) in the trace.
    pub(super) fn control_element(&mut self, r: &Ref, info: &TagInfo, sub: &[Expr]) -> Result<ControlRef> {
        let index = self.checked_subscript(sub, r, info)?;
        let len = info.len.unwrap_or(0);
        if let CKind::Const(v) = index.kind
            && (0..len as i64).contains(&v.as_i64())
        {
            let name = element_name(info, v.as_i64() as usize);
            return Ok(ControlRef::One(self.env.control(&name)));
        }
        let handles: Vec<_> = (0..len).map(|k| self.env.control(&element_name(info, k))).collect();
        Ok(ControlRef::At(handles.into_boxed_slice(), index))
    }

    fn coord_place(&mut self, r: &Ref, tag: &str, (m, span): &(String, Span)) -> Result<(Place, DataType)> {
        let handle = self.system(tag, r.name_span())?;
        let status = planner::coord::CoordStatus::default();
        let member = if let Some((n, _)) = status.bits().into_iter().find(|(n, _)| n.eq_ignore_ascii_case(m)) {
            CoordMember::Status(n)
        } else if m.eq_ignore_ascii_case("TransformSourceStatus") {
            CoordMember::TransformSource
        } else if m.eq_ignore_ascii_case("TransformTargetStatus") {
            CoordMember::TransformTarget
        } else {
            let names: Vec<&str> = status.bits().into_iter().map(|b| b.0).collect();
            let d = self.error(
                *span,
                format!(
                    "COORDINATE_SYSTEM has no member '{m}' (members: {}, TransformSourceStatus, TransformTargetStatus)",
                    names.join(", ")
                ),
                "no such member",
            );
            let known = names
                .into_iter()
                .chain(["TransformSourceStatus", "TransformTargetStatus"]);
            return Err(suggest(d, m, known));
        };
        Ok((Place::Coord(handle, member), DataType::Bool))
    }

    fn fb_place(&mut self, r: &Ref, tag: &str, (m, span): &(String, Span)) -> Result<(Place, DataType)> {
        let Some(fb) = self.env.bindings.fbs.iter().find(|f| f.name.eq_ignore_ascii_case(tag)) else {
            return err(
                self,
                r.span,
                format!(
                    "'{}' is never called in an IEC routine or a program step: it has no outputs to read",
                    r.name
                ),
            );
        };
        let outputs = planner::instruction::FbOutputs::default();
        if m.eq_ignore_ascii_case("ErrorID") {
            return Ok((Place::Fb(fb.handle, FbMember::ErrorId), DataType::Udint));
        }
        match outputs.bits().into_iter().find(|(n, _)| n.eq_ignore_ascii_case(m)) {
            Some((n, _)) => Ok((Place::Fb(fb.handle, FbMember::Bit(n)), DataType::Bool)),
            None => {
                let names: Vec<&str> = outputs.bits().into_iter().map(|b| b.0).collect();
                let d = self.error(
                    *span,
                    format!("function block outputs are {}, ErrorID; not '{m}'", names.join(", ")),
                    "no such output",
                );
                Err(suggest(d, m, names.into_iter().chain(["ErrorID"])))
            }
        }
    }

    /// A bit of an integer place: `.5` or `.[i]`.
    fn bit_of(&mut self, r: &Ref, place: Place, ty: DataType, access: &Access) -> Result<(Place, DataType)> {
        let bit = match access {
            Access::Bit(b) => constant(Value::Int(i64::from(*b)), Ty::Dint),
            Access::BitExpr(e) => self.integer(e)?,
            _ => {
                return err(
                    self,
                    r.span,
                    format!("'{}': nothing follows a {} value but a bit number", show(r), ty.name()),
                );
            }
        };
        if !ty.is_integer() {
            return err(
                self,
                r.span,
                format!("'{}': bit access needs an integer, this is {}", show(r), ty.name()),
            );
        }
        if let CKind::Const(Value::Int(b)) = bit.kind
            && (b < 0 || b >= i64::from(ty.bits()))
        {
            return err(
                self,
                r.span,
                format!("'{}': bit {b} is outside a {} ({} bits)", show(r), ty.name(), ty.bits()),
            );
        }
        let place = Place::Bit {
            inner: Box::new(place),
            width: ty.bits(),
            bit,
            ty,
        };
        Ok((place, DataType::Bool))
    }

    /// The element an array's subscripts name, as its index in the array
    /// (row-major: `[i, j, k]` is `i·d1·d2 + j·d2 + k`). One subscript per
    /// dimension; with several, each is checked against its own dimension
    /// when the scan evaluates it (major fault 4/20).
    pub(super) fn subscript(&mut self, sub: &[Expr], r: &Ref, info: &TagInfo) -> Result<CExpr> {
        let dims = info.dimensions();
        if sub.len() != dims.len().max(1) {
            return err(
                self,
                r.span,
                format!(
                    "'{}' has {} dimension{}, got {} subscript{}",
                    r.name,
                    dims.len(),
                    if dims.len() == 1 { "" } else { "s" },
                    sub.len(),
                    if sub.len() == 1 { "" } else { "s" }
                ),
            );
        }
        if dims.len() <= 1 {
            return self.integer(&sub[0]);
        }
        let mut parts = Vec::with_capacity(dims.len());
        for (e, &d) in sub.iter().zip(dims) {
            parts.push((self.integer(e)?, d));
        }
        let constant_in_range = parts.iter().all(|(e, d)| match e.kind {
            CKind::Const(v) => (0..*d as i64).contains(&v.as_i64()),
            _ => false,
        });
        if constant_in_range {
            let linear = parts.iter().fold(0i64, |acc, (e, d)| match e.kind {
                CKind::Const(v) => acc * *d as i64 + v.as_i64(),
                _ => acc,
            });
            return Ok(constant(Value::Int(linear), Ty::Dint));
        }
        Ok(CExpr {
            kind: CKind::Subscripts(parts.into_boxed_slice(), info.name.clone()),
            ty: Ty::Dint,
        })
    }

    /// A subscript of an array: a constant one must lie inside it when the
    /// text is a `[[program]]` step's or a scene's expression (nothing
    /// there can fault at run time).
    pub(super) fn checked_subscript(&mut self, sub: &[Expr], r: &Ref, info: &TagInfo) -> Result<CExpr> {
        let index = self.subscript(sub, r, info)?;
        let len = info.len.unwrap_or(0);
        if !self.scanned {
            let shown = || {
                if sub.len() == 1 {
                    format!("0 to {}", len.saturating_sub(1))
                } else {
                    let dims: Vec<String> = info.dimensions().iter().map(|d| format!("0..{}", d - 1)).collect();
                    format!("[{}]", dims.join(", "))
                }
            };
            match index.kind {
                CKind::Const(v) if (0..len as i64).contains(&v.as_i64()) => {}
                CKind::Const(v) => {
                    return Err(self.error(
                        sub[0].span,
                        format!("index {} is outside '{}' (valid: {})", v.as_i64(), r.name, shown()),
                        format!("'{}' has {len} elements", r.name),
                    ));
                }
                CKind::Subscripts(..) if sub.iter().all(|e| matches!(e.kind, ExprKind::Int(_))) => {
                    return Err(self.error(
                        sub[0].span,
                        format!("a subscript is outside '{}' (valid: {})", r.name, shown()),
                        format!("'{}' is {}", r.name, dims_text(info)),
                    ));
                }
                _ => {
                    return Err(self.error(
                        sub[0].span,
                        "a step's or a scene's subscript is a constant",
                        "not a constant",
                    ));
                }
            }
        }
        Ok(index)
    }

    /// The reference an operand is and the tag it names, if it is one.
    fn tag_arg<'r>(&self, arg: &'r Arg) -> Option<(&'r Ref, TagInfo)> {
        let Some(Expr {
            kind: ExprKind::Ref(r), ..
        }) = &arg.expr
        else {
            return None;
        };
        let t = self.resolve(&r.name)?;
        Some((r, self.mem.tags[t].clone()))
    }

    pub(super) fn instance(&mut self, arg: &Arg, want: &[Structure], what: &str) -> Result<Instance> {
        let message = format!(
            "{what} takes a {} tag, got '{}'",
            want.iter().map(|s| s.name()).collect::<Vec<_>>().join(" or "),
            arg.text
        );
        let bad = |c: &Self| c.error(arg.span, message.clone(), "");
        let Some((r, info)) = self.tag_arg(arg) else {
            return Err(bad(self));
        };
        if let Kind::User(_) = info.kind {
            // A member of a data type (`Station[I].Delay`).
            let mut path = r.path.iter();
            let at = self.locate(r, &info, &mut path)?;
            let s = match at.elem {
                Elem::User(id) if path.as_slice().is_empty() && at.array.is_none() => self.mem.layouts.get(id).builtin,
                _ => None,
            };
            let Some(s) = s.filter(|s| want.contains(s)) else {
                return Err(bad(self));
            };
            return Ok(Instance {
                base: info.base + at.slot,
                structure: s,
                index: None,
                terms: at.terms.into_boxed_slice(),
                name: show(r),
            });
        }
        let Kind::Structure(s) = info.kind else {
            return Err(bad(self));
        };
        if !want.contains(&s) {
            return Err(bad(self));
        }
        let index = match (info.len, r.path.as_slice()) {
            (None, []) => None,
            (Some(len), [Access::Index(sub)]) => Some((self.subscript(sub, r, &info)?, len)),
            _ => return Err(bad(self)),
        };
        Ok(Instance {
            base: info.base,
            structure: s,
            index,
            terms: Box::new([]),
            name: info.name,
        })
    }

    /// A `COP`/`CPS` operand: any tag, element or member in tag memory
    /// but BOOL (1756-RM003: SINT to LREAL, string types, structures).
    pub(super) fn data_at(&mut self, arg: &Arg, upper: &str, what: &str) -> Result<DataAt> {
        let bad = |c: &Self, why: &str| {
            c.error(
                arg.span,
                format!("{upper} {what}: {why}, got '{}'", arg.text.trim()),
                "",
            )
        };
        let Some((r, info)) = self.tag_arg(arg) else {
            return Err(bad(self, "expected a tag, an element or a member"));
        };
        if what == "Dest" {
            self.refuse_constant(r)?;
        }
        let Some(tag_elem) = info.elem() else {
            return Err(bad(
                self,
                "expected a number, a string type or a structure in tag memory",
            ));
        };
        let mut path = r.path.iter();
        let at = self.locate(r, &info, &mut path)?;
        if path.next().is_some() {
            return Err(bad(self, "a bit is not an operand of a copy"));
        }
        if at.elem == Elem::Control {
            return Err(bad(self, "a MOTION_INSTRUCTION is the planner's, not data to copy"));
        }
        if at.elem == Elem::Scalar(DataType::Bool) || tag_elem == Elem::Scalar(DataType::Bool) {
            return Err(bad(
                self,
                "BOOL is not a copy operand (SINT to LREAL, string types and structures are)",
            ));
        }
        let layouts = &self.mem.layouts;
        let tag_len = info.len.unwrap_or(1);
        Ok(DataAt {
            tag_base: info.base,
            tag_bytes: tag_len * layouts.bytes(tag_elem),
            tag_elem,
            tag_len,
            byte: at.byte,
            terms: at.terms.into_boxed_slice(),
            elem: at.elem,
            name: info.name,
        })
    }

    pub(super) fn array_at(&mut self, arg: &Arg, what: &str) -> Result<ArrayAt> {
        let message = format!("{what}: expected an array element such as Tag[0], got '{}'", arg.text);
        let bad = |c: &Self| c.error(arg.span, message.clone(), "");
        let Some((r, info)) = self.tag_arg(arg) else {
            return Err(bad(self));
        };
        if what == "Dest" {
            self.refuse_constant(r)?;
        }
        let (Kind::Scalar(ty), Some(len)) = (info.kind, info.len) else {
            return Err(bad(self));
        };
        let start = match r.path.as_slice() {
            [Access::Index(sub)] => self.subscript(sub, r, &info)?,
            [] => constant(Value::Int(0), Ty::Dint),
            _ => return Err(bad(self)),
        };
        Ok(ArrayAt {
            base: info.base,
            len,
            start,
            ty,
            name: info.name,
        })
    }
}

/// A reference walked through tag memory ([`Compiler::locate`]).
pub(super) struct Located {
    /// Slot offset from the tag's first slot (constant part).
    pub slot: usize,
    /// Byte offset inside the tag (constant part).
    pub byte: usize,
    /// The computed subscripts.
    pub terms: Vec<Term>,
    /// The element type reached.
    pub elem: Elem,
    /// `Some(n)`: the path ends on an array of `n` without a subscript.
    pub array: Option<usize>,
    /// Whether the first computed subscript is the tag's own.
    pub tag_term: bool,
    /// The path as written, constant subscripts in it, to name a control
    /// structure a path ends on.
    pub parts: Vec<NamePart>,
}

/// A piece of a path's name ([`Located::parts`]).
#[derive(Debug, Clone)]
pub(super) enum NamePart {
    /// The tag's name (`Axes`).
    Tag,
    /// The tag's element a constant subscript names (`Axes[2]`, `Grid[1,0]`).
    TagConstant(usize),
    /// Text as it is (`.Move`).
    Text(String),
    /// A member array's element a constant subscript names (`[0]`).
    Constant(i64),
    /// The tag's element a computed subscript names (`Axes[i]`, `Grid[i,j]`).
    TagElement,
    /// A member array's element a computed subscript names (`[k]`).
    Index,
}

/// The most control structures one reference reaches through computed
/// subscripts (each is bound in the planner when the program loads).
const MAX_CONTROL_ELEMENTS: usize = 10_000;

/// The value of a constant subscript.
fn constant_of(e: &CExpr) -> Option<i64> {
    match e.kind {
        CKind::Const(v) => Some(v.as_i64()),
        _ => None,
    }
}

/// The reference as written up to what `rest` leaves (`Cell.Pos`).
fn show_upto(r: &Ref, rest: &std::slice::Iter<'_, Access>) -> String {
    let used = r.path.len() - rest.as_slice().len();
    show(&Ref {
        name: r.name.clone(),
        path: r.path[..used].to_vec(),
        span: r.span,
    })
}

/// A control structure the compiler bound: one, or one of an array's
/// elements chosen when the scan runs.
pub(super) enum ControlRef {
    /// The handle.
    One(planner::task::InstructionHandle),
    /// Every element's handle and the element index.
    At(Box<[planner::task::InstructionHandle]>, CExpr),
}

/// The name of element `k` (row-major) of an array tag: `Tag[k]`, or
/// `Tag[i,j]` for two dimensions.
pub(super) fn element_name(info: &TagInfo, k: usize) -> String {
    let dims = info.dimensions();
    let mut rest = k;
    let mut subs = vec![0usize; dims.len().max(1)];
    for (slot, d) in subs.iter_mut().zip(dims).rev() {
        *slot = rest % d;
        rest /= d;
    }
    if dims.len() <= 1 {
        subs[0] = k;
    }
    let subs: Vec<String> = subs.iter().map(usize::to_string).collect();
    format!("{}[{}]", info.name, subs.join(","))
}

/// An array's dimensions as written: `DINT[6,3]`.
fn dims_text(info: &TagInfo) -> String {
    let dims: Vec<String> = info.dimensions().iter().map(usize::to_string).collect();
    format!("[{}]", dims.join(","))
}

/// A reference as a trace column's name (`J1.act_pos`): its name and
/// members joined by dots; `None` with a subscript or a bit.
fn column_name(r: &Ref) -> Option<String> {
    r.path.iter().all(|a| matches!(a, Access::Member(..))).then(|| show(r))
}

/// The tag name in `Program.Tag` when `stored` is a tag of `program`
/// (names compare case-insensitively, as Logix names do).
fn program_member<'a>(stored: &'a str, program: &str) -> Option<&'a str> {
    let rest = stored.get(program.len()..)?.strip_prefix('.')?;
    (stored.get(..program.len())?.eq_ignore_ascii_case(program) && !rest.is_empty()).then_some(rest)
}
