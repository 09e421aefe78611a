//! Instruction calls: the general instructions (timers, counters,
//! one-shots, routine calls, array and system-value instructions, looked
//! up in [`General`]), and the dispatch of every other call to the motion
//! instructions of the catalogue (`motion.rs`).

use super::{Compiler, Result, err, show, suggest};
use crate::program::axis_attributes::{self, AXIS_ATTRIBUTES, AxisAttr, Fixed};
use crate::program::ir::{
    AXIS_MEMBERS, CExpr, CKind, GENERAL, General, GsvAttribute, Object, Place, SKind, SsvAttribute, SysData,
};
use crate::program::system::{self, Class};
use crate::program::types::{DataType, Ty, Value};
use crate::scene::Dialect;
use crate::scene::{EventTrigger, TaskKind};
use crate::st::ast::{Arg, Call, Expr, ExprKind, Stmt, StmtKind};
use planner::task::instructions::{self, INSTRUCTIONS};

impl Compiler<'_, '_, '_> {
    /// Binds the function-block calls of `stmts` (creating their instances),
    /// so that a reference to an instance's output compiles wherever it
    /// stands.
    ///
    /// # Errors
    /// The first error of a call.
    pub fn bind_blocks(&mut self, stmts: &[Stmt]) -> Result<()> {
        for s in stmts {
            match &s.kind {
                StmtKind::Call(call) if call.args.iter().any(|a| a.name.is_some()) => {
                    self.call(call)?;
                }
                StmtKind::If { branches, otherwise } => {
                    for (_, b) in branches {
                        self.bind_blocks(b)?;
                    }
                    self.bind_blocks(otherwise)?;
                }
                StmtKind::Case { arms, otherwise, .. } => {
                    for (_, b) in arms {
                        self.bind_blocks(b)?;
                    }
                    self.bind_blocks(otherwise)?;
                }
                StmtKind::For { body, .. } | StmtKind::While { body, .. } | StmtKind::Repeat { body, .. } => {
                    self.bind_blocks(body)?;
                }
                _ => {}
            }
        }
        Ok(())
    }

    pub(super) fn value_arg(&mut self, arg: &Arg) -> Result<CExpr> {
        match &arg.expr {
            Some(e) => self.expr(e),
            None => Err(self.error(
                arg.span,
                format!("'{}' is not an expression", arg.text),
                "not an expression",
            )),
        }
    }

    pub(super) fn target_arg(&mut self, arg: &Arg) -> Result<(Place, DataType)> {
        match &arg.expr {
            Some(Expr {
                kind: ExprKind::Ref(r), ..
            }) => self.writable(r),
            _ => Err(self.error(
                arg.span,
                format!("expected a tag to write, got '{}'", arg.text),
                "not a tag",
            )),
        }
    }

    /// A call statement: a general instruction, or a motion instruction or
    /// function block of the catalogue.
    pub(super) fn call(&mut self, call: &Call) -> Result<SKind> {
        let Some(general) = General::find(&call.name) else {
            if let Some(aoi) = self.find_aoi(&call.name) {
                // The call site's statements, as one block.
                let line = self.env.files.line(call.span) as u32;
                let body = self
                    .aoi_call(aoi, call, false)?
                    .into_iter()
                    .map(|kind| crate::program::ir::CStmt { kind, line })
                    .collect();
                let always = super::constant(Value::Bool(true), Ty::Bool);
                return Ok(SKind::If(vec![(always, body)], Vec::new()));
            }
            return self.motion(call);
        };
        let upper = general.name();
        match general {
            General::Builtin(b) => {
                if b.iec_only() && self.dialect != Dialect::Iec {
                    return err(
                        self,
                        call.name_span,
                        format!(
                            "{upper} is an IEC 61131-3 block Studio 5000 does not have: use the IEC dialect for this routine ({{ file = \"…\", dialect = \"iec\" }}), or the Logix instructions OSRI/OSFI/TONR/TOFR"
                        ),
                    );
                }
                self.argc(call, upper, 1)?;
                Ok(SKind::Builtin(
                    b,
                    self.instance(&call.args[0], &[b.structure()], upper)?,
                ))
            }
            General::Jsr => self.jsr(call),
            General::Sbr => {
                let targets = call
                    .args
                    .iter()
                    .map(|a| self.target_arg(a))
                    .collect::<Result<Vec<_>>>()?;
                Ok(SKind::Sbr(targets))
            }
            General::Ret => {
                let values = call
                    .args
                    .iter()
                    .map(|a| self.value_arg(a))
                    .collect::<Result<Vec<_>>>()?;
                Ok(SKind::Ret(values))
            }
            General::Cop | General::Cps | General::Fll | General::Size => self.data_instruction(call, general),
            General::Gsv | General::Ssv => self.system_value(call, upper),
            General::Event => self.event(call),
            General::Str(op) => self.string_instruction(call, op, upper),
        }
    }

    /// `COP`, `CPS`, `FLL`, `SIZE`.
    fn data_instruction(&mut self, call: &Call, general: General) -> Result<SKind> {
        let upper = general.name();
        self.argc(call, upper, 3)?;
        let a = &call.args;
        match general {
            General::Fll => {
                let value = self.value_arg(&a[0])?;
                if value.ty == Ty::Bool {
                    return err(
                        self,
                        a[0].span,
                        "FLL: the Source is a number (SINT to LREAL), not a BOOL",
                    );
                }
                let dst = match self.array_at(&a[1], "Dest") {
                    Ok(dst) => dst,
                    Err(_) => {
                        let dst = self.data_at(&a[1], upper, "Dest")?;
                        return Ok(SKind::FllBytes(value, Box::new(dst), self.integer_arg(&a[2])?));
                    }
                };
                Ok(SKind::Fll(value, dst, self.integer_arg(&a[2])?))
            }
            General::Size => {
                let Some(Expr {
                    kind: ExprKind::Ref(r), ..
                }) = &a[0].expr
                else {
                    return err(self, a[0].span, "SIZE: expected an array tag");
                };
                let t = self.tag(r)?;
                let info = self.mem.tags[t].clone();
                let dims = if r.path.is_empty() {
                    info.dimensions().to_vec()
                } else {
                    // A member array (`SIZE(Line.Pos, 0, N)`).
                    let mut path = r.path.iter();
                    match self.locate(r, &info, &mut path)? {
                        at if path.as_slice().is_empty() => at.array.into_iter().collect(),
                        _ => Vec::new(),
                    }
                };
                if dims.is_empty() {
                    return err(self, a[0].span, format!("SIZE: '{}' is not an array", show(r)));
                }
                let dim = match &a[1].expr {
                    Some(Expr {
                        kind: ExprKind::Int(d), ..
                    }) if (0..dims.len() as i128).contains(d) => *d as usize,
                    _ => {
                        return err(
                            self,
                            a[1].span,
                            format!(
                                "SIZE: Dimension To Vary is a constant from 0 to {} ('{}' has {} dimension{})",
                                dims.len() - 1,
                                r.name,
                                dims.len(),
                                if dims.len() == 1 { "" } else { "s" }
                            ),
                        );
                    }
                };
                let (place, ty) = self.target_arg(&a[2])?;
                Ok(SKind::Size(dims[dim], place, ty))
            }
            _ => {
                // Two arrays of one scalar type copy element by element;
                // anything else goes through the controller's bytes.
                if let (Ok(src), Ok(dst)) = (self.array_at(&a[0], "Source"), self.array_at(&a[1], "Dest"))
                    && src.ty == dst.ty
                {
                    return Ok(SKind::Cop(src, dst, self.integer_arg(&a[2])?));
                }
                let src = self.data_at(&a[0], upper, "Source")?;
                let dst = self.data_at(&a[1], upper, "Dest")?;
                Ok(SKind::CopBytes(Box::new(src), Box::new(dst), self.integer_arg(&a[2])?))
            }
        }
    }

    pub(super) fn integer_arg(&mut self, arg: &Arg) -> Result<CExpr> {
        match &arg.expr {
            Some(e) => self.integer(e),
            None => err(self, arg.span, format!("expected an integer, got '{}'", arg.text)),
        }
    }

    pub(super) fn jsr(&mut self, call: &Call) -> Result<SKind> {
        let Some(first) = call.args.first() else {
            return err(self, call.span, "JSR takes a routine name");
        };
        let name = first.text.trim();
        let Some(routine) = self.routines.iter().position(|r| r.eq_ignore_ascii_case(name)) else {
            let d = self.error(
                first.span,
                format!(
                    "JSR: no routine '{name}' in this program (routines: {})",
                    self.routines.join(", ")
                ),
                "no such routine",
            );
            return Err(suggest(d, name, self.routines.iter().map(String::as_str)));
        };
        let rest = &call.args[1..];
        if rest.is_empty() {
            return Ok(SKind::Jsr {
                routine,
                inputs: Vec::new(),
                returns: Vec::new(),
            });
        }
        let count = match rest[0].expr.as_ref().map(|e| &e.kind) {
            Some(ExprKind::Int(n)) if (0..=i128::from(u8::MAX)).contains(n) => *n as usize,
            _ => return err(self, rest[0].span, "JSR: Input Count must be a constant number"),
        };
        if rest.len() < 1 + count {
            return err(
                self,
                call.span,
                format!("JSR: Input Count is {count}, {} inputs given", rest.len() - 1),
            );
        }
        let inputs = rest[1..=count]
            .iter()
            .map(|a| self.value_arg(a))
            .collect::<Result<Vec<_>>>()?;
        let returns = rest[1 + count..]
            .iter()
            .map(|a| self.target_arg(a))
            .collect::<Result<Vec<_>>>()?;
        Ok(SKind::Jsr {
            routine,
            inputs,
            returns,
        })
    }

    /// `GSV`/`SSV` of the `AXIS` class.
    fn system_value(&mut self, call: &Call, upper: &str) -> Result<SKind> {
        let operands = if upper == "GSV" { "Dest" } else { "Source" };
        if call.args.len() != 4 {
            return err(
                self,
                call.span,
                format!(
                    "{upper} takes 4 operands (Class, Instance, Attribute, {operands}), got {}",
                    call.args.len()
                ),
            );
        }
        let class_name = call.args[0].text.trim();
        if !class_name.eq_ignore_ascii_case("AXIS") {
            let Some(class) = Class::find(class_name) else {
                let names: Vec<&str> = std::iter::once("AXIS")
                    .chain(Class::NAMES.iter().map(|c| c.0))
                    .collect();
                let d = self.error(
                    call.args[0].span,
                    format!(
                        "{upper}: class '{class_name}' is not modelled (classes: {})",
                        names.join(", ")
                    ),
                    "not modelled",
                );
                return Err(suggest(d, class_name, names));
            };
            return self.system_object(call, upper, class);
        }
        let name = call.args[1].text.trim();
        let Some(axis) = self.env.axis(name) else {
            return Err(self.error(
                call.args[1].span,
                format!("{upper}: '{name}' is not an axis"),
                "not an axis",
            ));
        };
        let attr_name = call.args[2].text.trim();
        let member = AXIS_MEMBERS.iter().find(|(n, ..)| n.eq_ignore_ascii_case(attr_name));
        let found = axis_attributes::find(attr_name);
        let Some(row) = found else {
            if let (Some((_, m, _)), "GSV") = (member, upper) {
                let (place, ty) = self.target_arg(&call.args[3])?;
                return Ok(SKind::Gsv(axis, GsvAttribute::Member(*m), place, ty));
            }
            let names: Vec<&str> = AXIS_ATTRIBUTES
                .iter()
                .filter(|a| upper == "GSV" || a.settable)
                .map(|a| a.name)
                .chain(AXIS_MEMBERS.iter().map(|a| a.0).filter(|_| upper == "GSV"))
                .collect();
            let why = if member.is_some() {
                "is a status the controller keeps: GSV reads it, SSV does not set it"
            } else {
                "is not modelled"
            };
            let d = self.error(
                call.args[2].span,
                format!("{upper}: AXIS attribute '{attr_name}' {why} (see scenes/README.md, AXIS attributes)"),
                if member.is_some() { "read-only" } else { "not modelled" },
            );
            return Err(suggest(d, attr_name, names));
        };
        let index = self
            .env
            .scene
            .axes
            .iter()
            .position(|a| a.name.eq_ignore_ascii_case(name));
        if let AxisAttr::Drive(_) = row.attr
            && index.and_then(|k| self.env.scene.axes[k].servo).is_none()
        {
            return err(
                self,
                call.args[1].span,
                format!(
                    "{upper}: {} is a servo drive attribute, and axis '{name}' has no servo drive (it is virtual, or its joint has a spring motor)",
                    row.name
                ),
            );
        }
        let k = index.unwrap_or(0);
        if upper == "SSV" {
            if !row.settable {
                return err(
                    self,
                    call.args[2].span,
                    format!(
                        "SSV: AXIS attribute '{}' is read-only (MOTION-RM003 access: GSV); it comes from the scene's [[axes]] entry",
                        row.name
                    ),
                );
            }
            let value = self.value_arg(&call.args[3])?;
            if value.ty == Ty::Bool {
                return err(self, call.args[3].span, "SSV: the Source is a number, not a BOOL");
            }
            let target = match row.attr {
                AxisAttr::Config(limit) => SsvAttribute::Config(limit),
                AxisAttr::Drive(d) => SsvAttribute::Drive(k, d),
                AxisAttr::Fixed(_) => unreachable!("fixed attributes are not settable"),
            };
            return Ok(SKind::Ssv(axis, target, value));
        }
        let attribute = match row.attr {
            AxisAttr::Config(limit) => GsvAttribute::Config(limit),
            AxisAttr::Drive(d) => GsvAttribute::Drive(k, d),
            AxisAttr::Fixed(f) => GsvAttribute::Const(self.fixed_axis_value(k, f)),
        };
        let (place, ty) = self.target_arg(&call.args[3])?;
        Ok(SKind::Gsv(axis, attribute, place, ty))
    }

    /// A fixed `AXIS` attribute of the scene's axis `k`.
    fn fixed_axis_value(&self, k: usize, f: Fixed) -> Value {
        let Some(a) = self.env.scene.axes.get(k) else {
            return Value::Int(0);
        };
        let c = &a.config;
        match f {
            Fixed::ScalingNumerator => {
                let per_si = 1.0 / a.units.si_per_unit();
                Value::Real(match a.kind {
                    crate::scene::AxisKind::Rotary => std::f64::consts::TAU * per_si,
                    crate::scene::AxisKind::Linear => per_si,
                })
            }
            Fixed::ScalingDenominator | Fixed::UnwindDenominator => Value::Real(1.0),
            Fixed::UnwindNumerator => Value::Real(c.modulo_period.unwrap_or(0.0)),
            Fixed::HomeMode => Value::Int(match c.homing.mode {
                planner::homing::HomeMode::Passive => 0,
                planner::homing::HomeMode::Active => 1,
            }),
            Fixed::HomeDirection => Value::Int(match c.homing.direction {
                planner::homing::HomeDirection::UnidirectionalForward => 0,
                planner::homing::HomeDirection::BidirectionalForward => 1,
                planner::homing::HomeDirection::UnidirectionalReverse => 2,
                planner::homing::HomeDirection::BidirectionalReverse => 3,
            }),
            Fixed::HomeSequence => Value::Int(0),
        }
    }

    /// `GSV`/`SSV` of a system object (module doc of
    /// [`crate::program::system`]): the class, the instance (`THIS`, a task
    /// or program name; anything for a class of one object), the attribute
    /// and its access, and the tag: a scalar for one value, an array
    /// element of a DINT array for several.
    fn system_object(&mut self, call: &Call, upper: &str, class: Class) -> Result<SKind> {
        let a = &call.args;
        let instance_name = a[1].text.trim();
        let object = if !class.has_instances() {
            Object::Single
        } else if instance_name.eq_ignore_ascii_case("THIS") {
            Object::This
        } else {
            let names: Vec<String> = match class {
                Class::Task => self.env.scene.tasks.iter().map(|t| t.name.clone()).collect(),
                _ => self.env.scene.programs().map(|p| p.name.clone()).collect(),
            };
            match names.iter().position(|n| n.eq_ignore_ascii_case(instance_name)) {
                Some(k) => Object::Index(k),
                None => {
                    let d = self.error(
                        a[1].span,
                        format!(
                            "{upper}: no {} '{instance_name}' (THIS{}{})",
                            class.name().to_ascii_lowercase(),
                            if names.is_empty() { "" } else { ", " },
                            names.join(", ")
                        ),
                        "no such object",
                    );
                    return Err(suggest(d, instance_name, names.iter().map(String::as_str)));
                }
            }
        };
        if object == Object::This && !self.scanned {
            return err(
                self,
                a[1].span,
                format!("{upper}: THIS names the task or program of a routine"),
            );
        }
        let attr_name = a[2].text.trim();
        let Some(attribute) = system::find(class, attr_name) else {
            let names = system::names(class);
            let d = self.error(
                a[2].span,
                format!(
                    "{upper}: {} attribute '{attr_name}' is not modelled (attributes: {})",
                    class.name(),
                    names.join(", ")
                ),
                "not modelled",
            );
            return Err(suggest(d, attr_name, names));
        };
        if upper == "SSV" && attribute.access == system::Access::Get {
            return err(
                self,
                a[2].span,
                format!(
                    "SSV: {}.{} is read-only (GSV only, 1756-RM003)",
                    class.name(),
                    attribute.name
                ),
            );
        }
        let data = if attribute.words > 1 {
            let at = self.array_at(&a[3], if upper == "GSV" { "Dest" } else { "Source" })?;
            if at.ty != DataType::Dint {
                return err(
                    self,
                    a[3].span,
                    format!(
                        "{upper}: {}.{} is {}: give an element of a DINT array",
                        class.name(),
                        attribute.name,
                        attribute.ty
                    ),
                );
            }
            if let CKind::Const(v) = at.start.kind
                && v.as_i64() + attribute.words as i64 > at.len as i64
            {
                return err(
                    self,
                    a[3].span,
                    format!(
                        "{upper}: {}.{} takes {} DINTs; {} has {} from element {}",
                        class.name(),
                        attribute.name,
                        attribute.words,
                        at.name,
                        at.len as i64 - v.as_i64(),
                        v.as_i64()
                    ),
                );
            }
            SysData::Words(at)
        } else if upper == "GSV" {
            let (place, ty) = self.target_arg(&a[3])?;
            SysData::Target(place, ty)
        } else {
            SysData::Value(self.value_arg(&a[3])?)
        };
        Ok(if upper == "GSV" {
            SKind::SysGet(attribute, object, data)
        } else {
            SKind::SysSet(attribute, object, data)
        })
    }

    /// `EVENT(Task)`: the task must be an event task triggered by the
    /// EVENT instruction.
    fn event(&mut self, call: &Call) -> Result<SKind> {
        self.argc(call, "EVENT", 1)?;
        let name = call.args[0].text.trim();
        let tasks = &self.env.scene.tasks;
        let Some(k) = tasks.iter().position(|t| t.name.eq_ignore_ascii_case(name)) else {
            let names: Vec<&str> = tasks.iter().map(|t| t.name.as_str()).collect();
            let d = self.error(call.args[0].span, format!("EVENT: no task '{name}'"), "no such task");
            return Err(suggest(d, name, names));
        };
        if !matches!(
            tasks[k].kind,
            TaskKind::Event {
                trigger: EventTrigger::EventInstruction,
                ..
            }
        ) {
            return err(
                self,
                call.args[0].span,
                format!(
                    "EVENT: task '{}' is not an event task triggered by the EVENT instruction (type = \"event\", trigger = \"event_instruction\")",
                    tasks[k].name
                ),
            );
        }
        Ok(SKind::Event(k))
    }

    /// Checks a call's operand count.
    pub(super) fn argc(&self, call: &Call, upper: &str, n: usize) -> Result<()> {
        if call.args.len() == n {
            Ok(())
        } else {
            err(
                self,
                call.span,
                format!("{upper} takes {n} operand(s), got {}", call.args.len()),
            )
        }
    }

    /// `unknown instruction 'X'`, with the nearest name of every
    /// instruction and block the twin knows.
    pub(super) fn unknown_instruction(&self, call: &Call) -> super::Error {
        let d = self.error(
            call.name_span,
            format!("unknown instruction '{}'", call.name),
            "not an instruction the twin knows",
        );
        let known = INSTRUCTIONS
            .iter()
            .map(|i| i.mnemonic)
            .chain(GENERAL.iter().map(|(n, _)| *n))
            .chain(instructions::NOT_SIMULATED.iter().copied());
        suggest(d, &call.name, known)
    }
}
