//! Calls of the instruction catalogue: a Logix motion instruction with its
//! operands in faceplate order, or a PLCopen function block on its
//! instance with named inputs. The call's name is looked up once
//! ([`planner::task::instructions::find`]); each operand is bound by the
//! kind its catalogue entry gives ([`Kind`]):
//!
//! * axes, coordinate systems, control structures and cam profiles become
//!   planner handles now (created on first use);
//! * an enumeration operand takes one of *its* words (case-insensitive) or
//!   an integer: with the **Immediate** format the integer must be one of
//!   the operand's codes and a tag is refused (the controller's verifier
//!   refuses both); with **Immediate or Tag** any integer is passed on and
//!   the instruction reports a value out of range with ERR 13;
//! * a constant must fit the operand's data type (a DINT, Length's UINT);
//! * numbers, integers and arrays are expressions a scan evaluates; a
//!   `[[program]]` step is one scan of a one-shot rung with the scene's
//!   tag values, read when the scene loads (numbers at double precision,
//!   as the scene writes them), so its operands are constants, tags and
//!   array elements with constant subscripts.
//!
//! A call whose operands are all known at load is checked against the
//! instruction's validation ([`planner::task::instructions::Instruction::check`]):
//! what the instruction would refuse whenever it runs is a warning.

use super::reference::ControlRef;
use super::{Compiler, Error, Result, err, suggest};
use crate::program::ir::{ArrayAt, CExpr, CKind, MotionCall, Operand, SKind};
use crate::program::memory::{Kind as TagKind, TagInfo};
use crate::program::types::{DataType, Structure, Ty, Value};
use crate::scene::{BaseType, SegmentType, TagValue};
use crate::source::Diagnostic;
use crate::st::ast::{Access, Arg as ArgText, Call, Expr, ExprKind, Ref};
use planner::catalogue::{CallStyle, Format, Kind, Operand as Spec};
use planner::mccp::CamElement;
use planner::task::instructions;
use planner::task::instructions::Instruction;
use planner::task::{Arg, Args, CoordHandle};

impl Compiler<'_, '_, '_> {
    /// A motion instruction or function-block call statement.
    pub(super) fn motion(&mut self, call: &Call) -> Result<SKind> {
        Ok(SKind::Motion(self.instruction_call(call)?))
    }

    /// Compiles a call of the catalogue: its entry, its operands bound.
    ///
    /// # Errors
    /// An unknown or misused instruction, an operand count or an operand
    /// its kind refuses, pointed at.
    pub fn instruction_call(&mut self, call: &Call) -> Result<MotionCall> {
        if call.args.iter().any(|a| a.name.is_some()) {
            return self.block_call(call);
        }
        let instruction = self.positional_instruction(call)?;
        let count = instruction.operands.len();
        if call.args.len() != count {
            return Err(self.operand_count(instruction, call));
        }
        let mut operands = Vec::with_capacity(count);
        for (spec, arg) in instruction.operands.iter().zip(&call.args) {
            operands.push(self.operand(instruction, spec, arg)?);
        }
        let control = operands.iter().find_map(|o| match o {
            Operand::Fixed(Arg::Control(h)) => Some(*h),
            _ => None,
        });
        if self.scanned {
            for o in &operands {
                match o {
                    Operand::Fixed(Arg::Control(h)) => self.env.task.set_scanned(*h),
                    Operand::ControlAt(handles, ..) => handles.iter().for_each(|h| self.env.task.set_scanned(*h)),
                    _ => {}
                }
            }
        }
        let compiled = MotionCall {
            instruction,
            operands,
            control,
            instance: None,
        };
        self.prepare(&compiled, call)?;
        Ok(compiled)
    }

    /// The catalogue entry a positional call names.
    fn positional_instruction(&self, call: &Call) -> Result<&'static Instruction> {
        let name = &call.name;
        if let Some(i) = instructions::find(name) {
            if i.style == CallStyle::Positional {
                return Ok(i);
            }
            return Err(Box::new(
                (*self.error(
                    call.name_span,
                    format!(
                        "{} is a function block: call it on its instance with named inputs",
                        i.mnemonic
                    ),
                    "a function block",
                ))
                .with_help(format!(
                    "declare a {} tag and call it: MyMove(Axis := Table, Execute := TRUE, …)",
                    i.mnemonic
                )),
            ));
        }
        if let Some(d) = self.not_simulated(call) {
            return Err(d);
        }
        if let Some(t) = self.resolve(name) {
            let info = &self.mem.tags[t];
            return Err(Box::new(
                (*self.error(
                    call.name_span,
                    format!(
                        "'{name}' is {}, not an instruction; a function-block instance takes named inputs (Input := value)",
                        describe(info)
                    ),
                    "not an instruction",
                ))
                .with_help(format!("{name}(Input := value, …)")),
            ));
        }
        Err(self.unknown_instruction(call))
    }

    /// A Logix motion instruction the twin does not simulate, refused.
    fn not_simulated(&self, call: &Call) -> Option<Error> {
        let name = &call.name;
        instructions::NOT_SIMULATED
            .iter()
            .any(|m| m.eq_ignore_ascii_case(name))
            .then(|| {
                self.error(
                    call.name_span,
                    format!(
                        "{} is a Logix motion instruction the twin does not simulate (it simulates: {})",
                        name.to_ascii_uppercase(),
                        instructions::positional_mnemonics()
                    ),
                    "not simulated",
                )
            })
    }

    /// `MCLM takes 22 operands (…), got 21`, at the first extra operand or
    /// at the call's end, with the operands missing.
    fn operand_count(&self, instruction: &Instruction, call: &Call) -> Error {
        let count = instruction.operands.len();
        let got = call.args.len();
        let message = format!(
            "{} takes {count} operands ({}), got {got}",
            instruction.mnemonic,
            instruction.operand_names()
        );
        if got > count {
            return self.error(call.args[count].span, message, "one operand too many from here");
        }
        let missing: Vec<&str> = instruction.operands[got..].iter().map(|o| o.name).collect();
        let at = call.args.last().map_or(call.span, |a| a.span);
        let d = self.error(
            at,
            message,
            format!(
                "{} missing after this",
                if missing.len() == 1 { "an operand" } else { "operands" }
            ),
        );
        Box::new(d.with_help(format!("add {}", missing.join(", "))))
    }

    /// What `spec` takes, from the call's argument.
    fn operand(&mut self, instruction: &Instruction, spec: &'static Spec, arg: &ArgText) -> Result<Operand> {
        let text = arg.text.trim();
        if let Some(code) = spec.code_of(text) {
            return Ok(Operand::Fixed(Arg::Integer(code)));
        }
        match spec.kind {
            Kind::Axis | Kind::DriveAxis => self
                .axis_operand(instruction, spec, arg)
                .map(|h| Operand::Fixed(Arg::Axis(h))),
            Kind::CoordinateSystem => {
                let name = self.bare_name(spec, arg, "a COORDINATE_SYSTEM tag")?;
                Ok(Operand::Fixed(Arg::System(self.system(name, arg.span)?)))
            }
            Kind::Group => {
                let name = self.bare_name(spec, arg, "the MOTION_GROUP tag")?;
                let Some(t) = self.resolve(name) else {
                    return Err(self.unknown_name(name, arg.span));
                };
                let info = &self.mem.tags[t];
                if info.kind != TagKind::Planner(BaseType::MotionGroup) {
                    return err(
                        self,
                        arg.span,
                        format!(
                            "{} '{name}' is {}, expected the MOTION_GROUP tag",
                            spec.name,
                            describe(info)
                        ),
                    );
                }
                Ok(Operand::Fixed(Arg::Group))
            }
            Kind::OutputWord | Kind::InputWord => self.word_operand(spec, arg),
            Kind::OutputReal => self.output_real_operand(spec, arg),
            Kind::OutputCams => self.structures_operand(spec, arg, Structure::OutputCam),
            Kind::Compensations => self.structures_operand(spec, arg, Structure::OutputCompensation),
            Kind::MotionControl => self.control_operand(spec, arg),
            Kind::CamProfile => self.cam_profile_operand(spec, arg),
            Kind::Cam => self.cam_operand(spec, arg),
            Kind::Number => self.number_operand(spec, arg),
            Kind::Count | Kind::Integer => self.integer_operand(spec, arg),
            Kind::Enumeration(_) => self
                .code_operand(spec, arg)
                .map_err(|d| word_elsewhere(instruction, spec, arg, d)),
            Kind::Bool => self.bool_operand(spec, arg),
            Kind::Values | Kind::Vector3 | Kind::OutputVector3 | Kind::OptionalArray => self.array_operand(spec, arg),
        }
    }

    /// A DINT tag an instruction keeps writing or reading (MAOC's Output
    /// and Input): the tag's slot is the instruction's reference to it.
    fn word_operand(&mut self, spec: &Spec, arg: &ArgText) -> Result<Operand> {
        let name = self.bare_name(spec, arg, "a DINT tag")?;
        let Some(t) = self.resolve(name) else {
            return Err(self.unknown_name(name, arg.span));
        };
        let info = &self.mem.tags[t];
        if info.kind != TagKind::Scalar(DataType::Dint) || info.len.is_some() {
            return err(
                self,
                arg.span,
                format!("{} '{name}' is {}, expected a DINT tag", spec.name, describe(info)),
            );
        }
        if spec.kind == Kind::OutputWord && info.constant {
            return err(
                self,
                arg.span,
                format!("{} '{name}' is a constant: the instruction writes it", spec.name),
            );
        }
        Ok(Operand::Fixed(Arg::Reference(info.base)))
    }

    /// A REAL tag an instruction writes (MCSV's values): its slot is the
    /// instruction's reference to it. Only a routine's call writes one.
    fn output_real_operand(&mut self, spec: &Spec, arg: &ArgText) -> Result<Operand> {
        let name = self.bare_name(spec, arg, "a REAL tag")?;
        let Some(t) = self.resolve(name) else {
            return Err(self.unknown_name(name, arg.span));
        };
        let info = &self.mem.tags[t];
        if info.kind != TagKind::Scalar(DataType::Real) || info.len.is_some() {
            return err(
                self,
                arg.span,
                format!("{} '{name}' is {}, expected a REAL tag", spec.name, describe(info)),
            );
        }
        if info.constant {
            return err(
                self,
                arg.span,
                format!("{} '{name}' is a constant: the instruction writes it", spec.name),
            );
        }
        if !self.scanned {
            return err(
                self,
                arg.span,
                format!("{} is written by the instruction: call it from a routine", spec.name),
            );
        }
        Ok(Operand::Fixed(Arg::Reference(info.base)))
    }

    /// An array of an instruction structure from the element named
    /// (`Cams`, `Cams[2]`), read from tag memory when the call executes:
    /// MAOC's Output Cam and Output Compensation. Only a routine's call
    /// takes one (a step has no such values).
    fn structures_operand(&mut self, spec: &Spec, arg: &ArgText, structure: Structure) -> Result<Operand> {
        let bad = |c: &Self| {
            c.error(
                arg.span,
                format!(
                    "{} '{}': expected an {} array or an element of one",
                    spec.name,
                    arg.text.trim(),
                    structure.name()
                ),
                "not such an array",
            )
        };
        let Some(Expr {
            kind: ExprKind::Ref(r), ..
        }) = &arg.expr
        else {
            return Err(bad(self));
        };
        let Some(t) = self.resolve(&r.name) else {
            return Err(self.unknown_name(&r.name, r.name_span()));
        };
        let info = self.mem.tags[t].clone();
        if info.kind != TagKind::Structure(structure) || info.len.is_none() {
            return Err(bad(self));
        }
        if !self.scanned {
            return err(
                self,
                arg.span,
                format!(
                    "{} takes {} values a routine sets: call it from a routine",
                    spec.name,
                    structure.name()
                ),
            );
        }
        let len = info.len.unwrap_or(1);
        let start = match r.path.as_slice() {
            [] => super::constant(Value::Int(0), Ty::Dint),
            [Access::Index(sub)] => self.checked_subscript(sub, r, &info)?,
            _ => return Err(bad(self)),
        };
        Ok(Operand::Structures(
            ArrayAt {
                base: info.base,
                len,
                start,
                ty: DataType::Dint,
                name: info.name,
            },
            structure,
        ))
    }

    /// A Motion Control operand: a `MOTION_INSTRUCTION` tag, or an element
    /// of an array of them (`Mvs[1]`, `Mvs[I]`).
    fn control_operand(&mut self, spec: &Spec, arg: &ArgText) -> Result<Operand> {
        if let Some(Expr {
            kind: ExprKind::Ref(r), ..
        }) = &arg.expr
            && let [Access::Index(sub)] = r.path.as_slice()
            && let Some(t) = self.resolve(&r.name)
            && self.mem.tags[t].kind == TagKind::Planner(BaseType::MotionInstruction)
            && self.mem.tags[t].len.is_some()
        {
            let info = self.mem.tags[t].clone();
            return Ok(match self.control_element(r, &info, sub)? {
                ControlRef::One(h) => Operand::Fixed(Arg::Control(h)),
                ControlRef::At(handles, index) => Operand::ControlAt(handles, index, info.name.clone()),
            });
        }
        if let Some(Expr {
            kind: ExprKind::Ref(r), ..
        }) = &arg.expr
            && !r.path.is_empty()
            && let Some(t) = self.resolve(&r.name)
            && matches!(self.mem.tags[t].kind, TagKind::User(_))
        {
            // A member of a data type (`Axes[I].Move`).
            let info = self.mem.tags[t].clone();
            let mut path = r.path.iter();
            let at = self.locate(r, &info, &mut path)?;
            if at.elem != crate::program::layout::Elem::Control || at.array.is_some() || !path.as_slice().is_empty() {
                return err(
                    self,
                    arg.span,
                    format!("{} '{}': expected a MOTION_INSTRUCTION", spec.name, arg.text.trim()),
                );
            }
            return Ok(match self.control_in_structure(&info, at, r.span)? {
                ControlRef::One(h) => Operand::Fixed(Arg::Control(h)),
                ControlRef::At(handles, index) => Operand::ControlAt(handles, index, super::show(r)),
            });
        }
        let name = self.bare_name(spec, arg, "a MOTION_INSTRUCTION tag")?;
        let info = self.planner_tag(spec, arg, name, BaseType::MotionInstruction)?;
        Ok(Operand::Fixed(Arg::Control(self.env.control(&info.name))))
    }

    /// The name an operand that takes a tag writes bare.
    fn bare_name<'a>(&self, spec: &Spec, arg: &'a ArgText, expected: &str) -> Result<&'a str> {
        match &arg.expr {
            Some(Expr {
                kind: ExprKind::Ref(r), ..
            }) if r.path.is_empty() => Ok(&r.name),
            _ => Err(self.error(
                arg.span,
                format!("{} '{}': expected {expected}", spec.name, arg.text),
                format!("{} takes {expected}", spec.name),
            )),
        }
    }

    /// An axis operand: an axis of `[[axes]]`; for an `AXIS_CIP_DRIVE`
    /// operand (MSO, MSF) not a virtual one, always servo-on.
    fn axis_operand(&self, instruction: &Instruction, spec: &Spec, arg: &ArgText) -> Result<planner::task::AxisHandle> {
        let name = self.bare_name(spec, arg, "an axis")?;
        let Some(axis) = self.env.axis(name) else {
            let what = match self.resolve(name) {
                Some(t) => format!("'{name}' is {}, not an axis", describe(&self.mem.tags[t])),
                None => format!("'{name}' is not an axis of [[axes]]"),
            };
            let d = self.error(arg.span, format!("{} {what}", spec.name), "not an axis");
            let axes: Vec<String> = self.env.scene.axes.iter().map(|a| a.name.clone()).collect();
            return Err(suggest(d, name, axes.iter().map(String::as_str)));
        };
        let config = self.env.task.axis_config(axis);
        if spec.kind == Kind::DriveAxis && config.axis_type == planner::servo::AxisType::Virtual {
            return err(
                self,
                arg.span,
                format!(
                    "{} {}: {} takes an AXIS_CIP_DRIVE; '{}' is a virtual axis (no joint), which is always servo-on",
                    spec.name, config.name, instruction.mnemonic, config.name
                ),
            );
        }
        Ok(axis)
    }

    /// The tag an operand names, a planner tag of type `base`.
    fn planner_tag(&self, spec: &Spec, arg: &ArgText, name: &str, base: BaseType) -> Result<TagInfo> {
        let Some(t) = self.resolve(name) else {
            return Err(self.unknown_name(name, arg.span));
        };
        let info = self.mem.tags[t].clone();
        if info.kind != TagKind::Planner(base) || info.len.is_some() && base != BaseType::CamProfile {
            return err(
                self,
                arg.span,
                format!("{} {name} is {}, expected {}", spec.name, describe(&info), base.name()),
            );
        }
        Ok(info)
    }

    /// The coordinate system of the controller tag `name`, created on its
    /// first use.
    pub(super) fn system(&mut self, name: &str, span: crate::source::Span) -> Result<CoordHandle> {
        let Some(t) = self.resolve(name) else {
            return Err(self.unknown_name(name, span));
        };
        let info = &self.mem.tags[t];
        let decl = match (info.kind, self.env.decls.get(&info.name)) {
            (TagKind::Planner(BaseType::CoordinateSystem), Some(decl)) => decl,
            _ => {
                return err(
                    self,
                    span,
                    format!("'{name}' is {}, expected a COORDINATE_SYSTEM tag", describe(info)),
                );
            }
        };
        self.env
            .coordinate_system(decl)
            .map_err(|message| self.error(span, format!("coordinate system '{name}': {message}"), ""))
    }

    /// `Profile` or `Profile[0]` of a `CAM_PROFILE` tag.
    fn cam_profile_operand(&mut self, spec: &Spec, arg: &ArgText) -> Result<Operand> {
        let Some(Expr {
            kind: ExprKind::Ref(r), ..
        }) = &arg.expr
        else {
            return err(
                self,
                arg.span,
                format!("{} '{}': expected a CAM_PROFILE tag", spec.name, arg.text),
            );
        };
        let info = self.planner_tag(spec, arg, &r.name, BaseType::CamProfile)?;
        let dims = info.dimensions().to_vec();
        let len = info.len.unwrap_or(1);
        // A one-dimensional array (or a bare tag) is one profile; an array
        // of two or three dimensions is one profile per row, named by the
        // row's first element (`Profiles[1,0]`), the last dimension long.
        let (name, len) = match (r.path.as_slice(), dims.len()) {
            ([], 0 | 1) => (info.name.clone(), len),
            ([Access::Index(sub)], 1)
                if matches!(
                    sub.as_slice(),
                    [Expr {
                        kind: ExprKind::Int(0),
                        ..
                    }]
                ) =>
            {
                (info.name.clone(), len)
            }
            ([Access::Index(sub)], n) if n > 1 && sub.len() == n => {
                let constants: Option<Vec<usize>> = sub
                    .iter()
                    .zip(&dims)
                    .map(|(e, d)| match e.kind {
                        ExprKind::Int(i) if (0..*d as i128).contains(&i) => Some(i as usize),
                        _ => None,
                    })
                    .collect();
                match constants {
                    Some(c) if c.last() == Some(&0) => {
                        let linear = c.iter().zip(&dims).fold(0usize, |acc, (i, d)| acc * d + i);
                        (super::reference::element_name(&info, linear), dims[n - 1])
                    }
                    _ => {
                        return err(
                            self,
                            arg.span,
                            format!(
                                "{} {}: a CAM_PROFILE row is named by constant subscripts inside the array, the last one 0 (e.g. {}[{}0])",
                                spec.name,
                                arg.text,
                                r.name,
                                "0,".repeat(n - 1)
                            ),
                        );
                    }
                }
            }
            ([Access::Index(_)], _) => {
                return err(
                    self,
                    arg.span,
                    format!(
                        "{} {}: only element [0] of a CAM_PROFILE array is allowed",
                        spec.name, arg.text
                    ),
                );
            }
            _ => {
                return err(
                    self,
                    arg.span,
                    format!("{} '{}': expected a CAM_PROFILE tag", spec.name, arg.text),
                );
            }
        };
        Ok(Operand::Fixed(Arg::CamProfile(self.env.cam_profile(&name, len))))
    }

    /// A reference to a whole array tag or one of its elements: the tag
    /// and the subscript (`None` for the whole array).
    fn array_reference<'a>(&self, arg: &'a ArgText) -> Option<(&'a Ref, TagInfo, Option<&'a Expr>)> {
        let Some(Expr {
            kind: ExprKind::Ref(r), ..
        }) = &arg.expr
        else {
            return None;
        };
        let info = self.mem.tags[self.resolve(&r.name)?].clone();
        info.len?;
        match r.path.as_slice() {
            [] => Some((r, info, None)),
            [Access::Index(sub)] if sub.len() == 1 => Some((r, info, Some(&sub[0]))),
            _ => None,
        }
    }

    /// A `CAM` array or an element of one: its first point (any number
    /// of subscripts, row-major for an array of two or three dimensions).
    fn cam_operand(&mut self, spec: &Spec, arg: &ArgText) -> Result<Operand> {
        let bad = |c: &Self| {
            c.error(
                arg.span,
                format!(
                    "{} '{}': expected a CAM array or an element of one, e.g. Cam[0]",
                    spec.name, arg.text
                ),
                "not a CAM array",
            )
        };
        let Some(Expr {
            kind: ExprKind::Ref(r), ..
        }) = &arg.expr
        else {
            return Err(bad(self));
        };
        let Some(t) = self.resolve(&r.name) else {
            return Err(bad(self));
        };
        let info = self.mem.tags[t].clone();
        if info.kind != TagKind::Structure(Structure::Cam) || info.len.is_none() {
            return Err(bad(self));
        }
        let len = info.len.unwrap_or(1);
        let start = match r.path.as_slice() {
            [] => super::constant(Value::Int(0), Ty::Dint),
            [Access::Index(sub)] => self.checked_subscript(sub, r, &info)?,
            _ => return Err(bad(self)),
        };
        if !self.scanned {
            // A step's subscripts are constants inside the array (checked
            // above).
            let start = match start.kind {
                CKind::Const(v) => v.as_i64() as usize,
                _ => 0,
            };
            return Ok(Operand::CamPoints(self.scene_cam(&info.name, len), start));
        }
        Ok(Operand::Cam(ArrayAt {
            base: info.base,
            len,
            start,
            ty: DataType::Real,
            name: info.name,
        }))
    }

    /// A constant subscript inside an array of `len` (a step's).
    fn constant_index(&mut self, e: &Expr, r: &Ref, len: usize) -> Result<usize> {
        let index = self.integer(e)?;
        match index.kind {
            CKind::Const(v) if (0..len as i64).contains(&v.as_i64()) => Ok(v.as_i64() as usize),
            CKind::Const(v) => Err(self.error(
                e.span,
                format!(
                    "index {} is outside '{}' (valid: 0 to {})",
                    v.as_i64(),
                    r.name,
                    len.saturating_sub(1)
                ),
                format!("'{}' has {len} elements", r.name),
            )),
            _ => err(self, e.span, "a step's subscript is a constant"),
        }
    }

    /// A CAM tag's points as the scene gives them; the elements it does not
    /// list hold the controller's initial values (master 0, slave 0,
    /// linear), as in a `CAM[N]` tag on the controller.
    fn scene_cam(&self, name: &str, len: usize) -> Vec<CamElement> {
        let mut out: Vec<CamElement> = match self.env.decls.get(name).and_then(|t| t.value.as_ref()) {
            Some(TagValue::CamPoints(points)) => points
                .iter()
                .map(|p| CamElement {
                    master: p.master,
                    slave: p.slave,
                    segment_type: i32::from(p.segment_type != SegmentType::Linear),
                })
                .collect(),
            _ => Vec::new(),
        };
        out.resize(len.max(out.len()), CamElement::default());
        out
    }

    /// A number: an expression a scan evaluates; in a step, a constant or
    /// a tag's value from the scene.
    fn number_operand(&mut self, spec: &Spec, arg: &ArgText) -> Result<Operand> {
        let e = self.operand_expr(spec, arg)?;
        if !self.scanned {
            return self.step_number(spec, arg, e).map(|x| Operand::Fixed(Arg::Number(x)));
        }
        let c = self.numeric(spec, arg, e)?;
        Ok(match c.kind {
            CKind::Const(v) => Operand::Fixed(Arg::Number(v.as_f64())),
            _ if spec.format == Format::Immediate => return Err(self.not_constant(spec, arg)),
            _ => Operand::Number(c),
        })
    }

    /// An Immediate operand given a tag or an expression: the controller's
    /// verifier refuses it.
    fn not_constant(&self, spec: &Spec, arg: &ArgText) -> Error {
        self.error(
            arg.span,
            format!(
                "{} '{}': the operand's format is Immediate: write a constant",
                spec.name,
                arg.text.trim()
            ),
            "not a constant",
        )
    }

    /// An integer operand without words (Move Type, Length, a count).
    fn integer_operand(&mut self, spec: &'static Spec, arg: &ArgText) -> Result<Operand> {
        let e = self.operand_expr(spec, arg)?;
        if !self.scanned {
            let x = self.step_number(spec, arg, e)?;
            if x.fract() != 0.0 || x.abs() >= 1e15 {
                return err(
                    self,
                    arg.span,
                    format!("{} {}: expected an integer, got {x}", spec.name, arg.text),
                );
            }
            return self.fitting(spec, arg, x as i64);
        }
        let c = self.numeric(spec, arg, e)?;
        match c.kind {
            CKind::Const(v) => self.fitting(spec, arg, v.as_i64()),
            _ if spec.format == Format::Immediate => Err(self.not_constant(spec, arg)),
            _ => Ok(Operand::Integer(c)),
        }
    }

    /// A constant integer that fits the operand's data type.
    fn fitting(&self, spec: &Spec, arg: &ArgText, n: i64) -> Result<Operand> {
        let range = match (spec.kind, spec.data_type) {
            (Kind::Count, _) => Some((0, i64::from(u16::MAX), "a UINT (0..=65535)")),
            (_, "DINT") => Some((i64::from(i32::MIN), i64::from(i32::MAX), "a DINT")),
            _ => None,
        };
        match range {
            Some((lo, hi, what)) if !(lo..=hi).contains(&n) => err(
                self,
                arg.span,
                format!("{} {}: expected {what}, got {n}", spec.name, arg.text),
            ),
            _ => Ok(Operand::Fixed(Arg::Integer(n))),
        }
    }

    /// An enumeration operand: one of its words, or an integer (module
    /// doc). A function block's input in a routine may be any integer
    /// expression, as an IEC input is a variable.
    fn code_operand(&mut self, spec: &'static Spec, arg: &ArgText) -> Result<Operand> {
        let text = arg.text.trim();
        let word_like = text.chars().all(|c| c.is_alphanumeric() || "_%²³-".contains(c))
            && !text.starts_with(|c: char| c.is_ascii_digit() || c == '-');
        let names_tag =
            matches!(&arg.expr, Some(Expr { kind: ExprKind::Ref(r), .. }) if self.resolve(&r.name).is_some());
        if word_like && !names_tag {
            return Err(self.unknown_word(spec, arg));
        }
        let constant_only = spec.format == Format::Immediate || spec.format == Format::Input && !self.scanned;
        if constant_only && names_tag {
            return Err(Box::new(
                (*self.error(
                    arg.span,
                    format!(
                        "{} {text}: the operand's format is {} (a constant), not a tag",
                        spec.name,
                        spec.format.name()
                    ),
                    "a tag",
                ))
                .with_help(format!("write one of {}", spec.word_list())),
            ));
        }
        let e = self.operand_expr(spec, arg)?;
        let value = if self.scanned {
            let c = self.numeric(spec, arg, e)?;
            match c.kind {
                CKind::Const(v) => v.as_i64(),
                _ if constant_only => {
                    return Err(Box::new(
                        (*self.error(
                            arg.span,
                            format!(
                                "{} '{text}': the operand's format is {}: write a constant or one of {}",
                                spec.name,
                                spec.format.name(),
                                spec.word_list()
                            ),
                            "not a constant",
                        ))
                        .with_help(format!("its words: {}", spec.word_list())),
                    ));
                }
                _ => return Ok(Operand::Integer(c)),
            }
        } else {
            let x = self.step_number(spec, arg, e)?;
            if x.fract() != 0.0 || x.abs() >= 1e15 {
                return Err(self.unknown_word(spec, arg));
            }
            x as i64
        };
        if matches!(spec.format, Format::Immediate | Format::Input) && !spec.has_code(value) {
            return Err(Box::new(
                (*self.error(
                    arg.span,
                    format!("{} {text}: expected one of {}", spec.name, spec.word_list()),
                    format!("not a code of {}", spec.name),
                ))
                .with_help(format!("its words: {}", spec.word_list())),
            ));
        }
        Ok(Operand::Fixed(Arg::Integer(value)))
    }

    /// `'mmpersec' is not a word of Speed Units`, listing the operand's
    /// words and the nearest one.
    fn unknown_word(&self, spec: &Spec, arg: &ArgText) -> Error {
        let text = arg.text.trim();
        let d = self.error(
            arg.span,
            format!("'{text}' is not a word of {} and not a tag", spec.name),
            format!("not a word of {}", spec.name),
        );
        let d = suggest(d, text, spec.kind.words().iter().map(|w| w.word));
        Box::new(d.with_note(format!("{} takes {}", spec.name, spec.word_list())))
    }

    /// A BOOL input (`Execute`).
    fn bool_operand(&mut self, spec: &Spec, arg: &ArgText) -> Result<Operand> {
        let e = self.operand_expr(spec, arg)?;
        if let ExprKind::Ref(r) = &e.kind
            && r.path.is_empty()
            && self.resolve(&r.name).is_none()
        {
            let d = self.error(
                arg.span,
                format!("{} := {}: '{}' is not a tag", spec.name, arg.text, r.name),
                "not TRUE, FALSE or a BOOL tag",
            );
            let d = suggest(d, &r.name, ["TRUE", "FALSE"]);
            return Err(Box::new(
                d.with_note(format!("{} takes TRUE, FALSE or a BOOL tag", spec.name)),
            ));
        }
        let c = self.expr(e)?;
        if c.ty != Ty::Bool {
            return err(
                self,
                arg.span,
                format!("{} := {}: expected TRUE or FALSE", spec.name, arg.text),
            );
        }
        Ok(match c.kind {
            CKind::Const(v) => Operand::Fixed(Arg::Bool(v.truthy())),
            _ if !self.scanned => {
                return err(
                    self,
                    arg.span,
                    format!("{} := {}: expected TRUE or FALSE", spec.name, arg.text),
                );
            }
            _ => Operand::Bool(c),
        })
    }

    /// An array from an element (`Pos[0]` or `Pos`), `0` for an optional
    /// one, or one number for Via/Center/Radius.
    fn array_operand(&mut self, spec: &Spec, arg: &ArgText) -> Result<Operand> {
        let zero = matches!(arg.expr.as_ref().map(|e| &e.kind), Some(ExprKind::Int(0)))
            || matches!(arg.expr.as_ref().map(|e| &e.kind), Some(ExprKind::Real(x)) if *x == 0.0);
        if spec.kind == Kind::OptionalArray && zero {
            return Ok(Operand::Fixed(Arg::None));
        }
        if let Some((r, info, index)) = self.array_reference(arg)
            && let TagKind::Scalar(ty) = info.kind
            && ty != DataType::Bool
        {
            let len = info.len.unwrap_or(0);
            if !self.scanned && spec.kind == Kind::OutputVector3 {
                return err(
                    self,
                    arg.span,
                    format!(
                        "{} {}: the instruction writes it, which only a routine's call can have it do",
                        spec.name, arg.text
                    ),
                );
            }
            if !self.scanned {
                let start = match index {
                    Some(e) => self.constant_index(e, r, len)?,
                    None => 0,
                };
                let values = self.scene_numbers(&info.name, spec, arg)?;
                let count = if spec.kind == Kind::Vector3 { 3 } else { len - start };
                if start + count > values.len() {
                    return err(
                        self,
                        arg.span,
                        format!(
                            "{} {}: needs {count} elements from [{start}], '{}' has {len}",
                            spec.name, arg.text, r.name
                        ),
                    );
                }
                return Ok(Operand::Values(values[start..].to_vec()));
            }
            let start = match index {
                Some(e) => self.integer(e)?,
                None => super::constant(Value::Int(0), Ty::Dint),
            };
            return Ok(Operand::Array(ArrayAt {
                base: info.base,
                len,
                start,
                ty,
                name: info.name,
            }));
        }
        // A name that is no tag at all: say so, with the nearest.
        if let Some(Expr {
            kind: ExprKind::Ref(r), ..
        }) = &arg.expr
            && self.resolve(&r.name).is_none()
        {
            return Err(self.unknown_name(&r.name, r.name_span()));
        }
        let expected = match spec.kind {
            Kind::OptionalArray => "0 or a REAL array tag",
            Kind::Vector3 | Kind::OutputVector3 => "a REAL array element, three from there (REAL[3])",
            _ => "a REAL array tag or element, e.g. Pos[0]",
        };
        if spec.kind == Kind::Values
            && let Some(e) = &arg.expr
        {
            let numeric = self.resolve_number_like(e);
            if numeric {
                if !self.scanned {
                    let x = self.step_number(spec, arg, e)?;
                    return Ok(Operand::Values(vec![x]));
                }
                let c = self.numeric(spec, arg, e)?;
                return Ok(Operand::Scalar(c));
            }
        }
        err(
            self,
            arg.span,
            format!("{} {}: expected {expected}", spec.name, arg.text),
        )
    }

    /// Whether an expression is a number rather than an array reference.
    fn resolve_number_like(&self, e: &Expr) -> bool {
        match &e.kind {
            ExprKind::Ref(r) => self
                .resolve(&r.name)
                .is_some_and(|t| matches!(self.mem.tags[t].kind, TagKind::Scalar(_)) && self.mem.tags[t].len.is_none()),
            _ => true,
        }
    }

    /// A numeric array tag's values as the scene gives them.
    fn scene_numbers(&self, name: &str, spec: &Spec, arg: &ArgText) -> Result<Vec<f64>> {
        match self.env.decls.get(name).and_then(|t| t.value.as_ref()) {
            Some(TagValue::Array(items)) => items
                .iter()
                .map(|v| match v {
                    TagValue::Real(x) => Ok(*x),
                    TagValue::Integer(i) => Ok(*i as f64),
                    _ => err(
                        self,
                        arg.span,
                        format!("{} {}: '{name}' holds non-numeric elements", spec.name, arg.text),
                    ),
                })
                .collect(),
            _ => err(
                self,
                arg.span,
                format!(
                    "{} {}: '{name}' is not a REAL/DINT array tag with a value",
                    spec.name, arg.text
                ),
            ),
        }
    }

    /// The operand's expression.
    fn operand_expr<'a>(&self, spec: &Spec, arg: &'a ArgText) -> Result<&'a Expr> {
        arg.expr.as_ref().ok_or_else(|| {
            // Structured Text has no string operands here.
            let quoted = arg.text.starts_with(['\'', '"']);
            let d = if quoted {
                self.error(
                    arg.span,
                    format!(
                        "{}: a string is no operand of a motion instruction, found {}",
                        spec.name, arg.text
                    ),
                    "a string",
                )
            } else {
                self.error(
                    arg.span,
                    format!("{} '{}': not an operand", spec.name, arg.text),
                    "not an expression",
                )
            };
            match spec.kind.words() {
                [] => d,
                _ => Box::new(d.with_note(format!("{} takes {}", spec.name, spec.word_list()))),
            }
        })
    }

    /// A numeric expression.
    fn numeric(&mut self, spec: &Spec, arg: &ArgText, e: &Expr) -> Result<CExpr> {
        let c = self.expr(e)?;
        if c.ty == Ty::Bool {
            return err(
                self,
                arg.span,
                format!("{} {}: expected a number, got BOOL", spec.name, arg.text),
            );
        }
        Ok(c)
    }

    /// A step's number: a literal (double precision, as written), a minus
    /// sign before one, or a scalar tag's or an element's value from the
    /// scene.
    fn step_number(&mut self, spec: &Spec, arg: &ArgText, e: &Expr) -> Result<f64> {
        let refused = |c: &Self| {
            c.error(
                arg.span,
                format!(
                    "{} {}: expected a number or a REAL/DINT tag with a value (a step reads the scene's values)",
                    spec.name, arg.text
                ),
                "not a number",
            )
        };
        match &e.kind {
            ExprKind::Int(i) => Ok(*i as f64),
            ExprKind::Real(x) => Ok(*x),
            ExprKind::Unary(crate::st::ast::UnaryOp::Neg, a) => self.step_number(spec, arg, a).map(|x| -x),
            ExprKind::Ref(r) => {
                let Some(t) = self.resolve(&r.name) else {
                    return Err(self.unknown_name(&r.name, r.name_span()));
                };
                let info = self.mem.tags[t].clone();
                let value = self.env.decls.get(&info.name).and_then(|d| d.value.clone());
                let numeric = |v: &TagValue| match v {
                    TagValue::Real(x) => Some(*x),
                    TagValue::Integer(i) => Some(*i as f64),
                    _ => None,
                };
                let x = match (r.path.as_slice(), &value) {
                    ([], Some(v)) => numeric(v),
                    ([Access::Index(sub)], Some(TagValue::Array(items))) if sub.len() == 1 => {
                        let i = self.constant_index(&sub[0], r, info.len.unwrap_or(0))?;
                        items.get(i).and_then(numeric)
                    }
                    _ => None,
                };
                x.ok_or_else(|| refused(self))
            }
            _ => Err(refused(self)),
        }
    }

    /// A PLCopen function block called on its instance with named inputs.
    fn block_call(&mut self, call: &Call) -> Result<MotionCall> {
        let name = &call.name;
        let Some(t) = self.resolve(name) else {
            if let Some(i) = instructions::find(name).filter(|i| i.style == CallStyle::Positional) {
                return Err(Box::new(
                    (*self.error(
                        call.name_span,
                        format!(
                            "{} is a Logix instruction: call it with its operands in order, {}(...), not with named inputs",
                            i.mnemonic, i.mnemonic
                        ),
                        "a Logix instruction",
                    ))
                    .with_help(format!("{}({})", i.mnemonic, i.operand_names())),
                ));
            }
            if let Some(d) = self.not_simulated(call) {
                return Err(d);
            }
            return Err(self.unknown_name(name, call.name_span));
        };
        let info = self.mem.tags[t].clone();
        let TagKind::Planner(BaseType::FunctionBlock(block)) = info.kind else {
            return err(
                self,
                call.name_span,
                format!(
                    "'{name}' is {}, not a function-block instance, so it cannot be called with named inputs",
                    describe(&info)
                ),
            );
        };
        let Some(instruction) = instructions::find(block.name()).filter(|i| i.style == CallStyle::Named) else {
            return err(
                self,
                call.name_span,
                format!(
                    "'{name}' is an {} instance; the twin runs the function block MC_MoveModulo",
                    block.name()
                ),
            );
        };
        if self.scanned && self.dialect != crate::scene::Dialect::Iec {
            return err(
                self,
                call.name_span,
                format!(
                    "{name} is called with named inputs, as a PLCopen function block: write it in a routine of the IEC dialect ({{ file = \"…\", dialect = \"iec\" }}) or in a [[program]] step"
                ),
            );
        }
        let mut operands: Vec<Operand> = instruction
            .operands
            .iter()
            .map(|_| Operand::Fixed(Arg::Absent))
            .collect();
        // The instance first, with the axis its call names: another input
        // may read its outputs (`Execute := NOT MM.Busy`).
        let axis_arg = call
            .args
            .iter()
            .position(|a| a.name.as_ref().is_some_and(|(n, _)| n.eq_ignore_ascii_case("Axis")));
        let mut axis = None;
        if let (Some(k), Some((i, spec))) = (axis_arg, instruction.operand("Axis")) {
            let op = self.operand(instruction, spec, &call.args[k])?;
            if let Operand::Fixed(Arg::Axis(h)) = op {
                axis = Some(h);
            }
            operands[i] = op;
        }
        let instance = self
            .env
            .instance(&info.name, axis)
            .map_err(|message| self.error(call.name_span, message, ""))?;
        for (k, arg) in call.args.iter().enumerate() {
            if Some(k) == axis_arg {
                continue;
            }
            let Some((input, span)) = &arg.name else {
                return err(
                    self,
                    arg.span,
                    "a function-block call names every input (Input := value)",
                );
            };
            let Some((i, spec)) = instruction.operand(input) else {
                let d = self.error(
                    *span,
                    format!(
                        "{} has no input '{input}' (inputs: {})",
                        instruction.mnemonic,
                        instruction.operand_names()
                    ),
                    "no such input",
                );
                return Err(suggest(d, input, instruction.operands.iter().map(|o| o.name)));
            };
            if spec.name == "Options" {
                return err(
                    self,
                    *span,
                    "Options: set the instance's ST_MoveOptions where it is declared, e.g. options = { IgnorePositionMonitoring = true } in its [[tags]] entry; a call cannot change them",
                );
            }
            operands[i] = self.operand(instruction, spec, arg)?;
        }
        let compiled = MotionCall {
            instruction,
            operands,
            control: None,
            instance: Some(instance),
        };
        self.prepare(&compiled, call)?;
        Ok(compiled)
    }

    /// Notes the call, prepares the task for it, and checks it when its
    /// operands are all known: a refusal is a warning (the call fails
    /// whenever it runs), or an error where the operand it names is
    /// Immediate (the controller's verifier refuses the routine: MATC's
    /// master driven mode).
    ///
    /// # Errors
    /// The refusal of an Immediate operand.
    fn prepare(&mut self, compiled: &MotionCall, call: &Call) -> Result<()> {
        let instruction = compiled.instruction;
        self.env.note_call(instruction);
        let mut known = true;
        let values: Vec<Arg<'_>> = compiled
            .operands
            .iter()
            .map(|o| match o {
                Operand::Fixed(a) => *a,
                Operand::Values(v) => Arg::Array(v),
                Operand::CamPoints(points, start) => Arg::Cam(points, *start),
                _ => {
                    known = false;
                    Arg::Absent
                }
            })
            .collect();
        let args = Args {
            values: &values,
            instance: compiled.instance,
        };
        instruction.prepare(self.env.task, &args);
        if !known || instruction.style == CallStyle::Named {
            return Ok(());
        }
        if let Err(fault) = instruction.check(self.env.task, &args) {
            if let Some((i, o)) = instruction
                .operand_at_faceplate(fault.exerr())
                .filter(|(_, o)| fault.err() == 13 && o.format == Format::Immediate)
            {
                let span = call.args.get(i).map_or(call.name_span, |a| a.span);
                return err(self, span, format!("{} {}: {fault}", instruction.mnemonic, o.name));
            }
            let d = Diagnostic::warning(format!(
                "{} refuses this call whenever it runs: {}",
                instruction.mnemonic,
                instruction.refusal_codes(fault.err(), fault.exerr())
            ));
            // ERR 13 names its operand: point there.
            let operand = (fault.err() == 13)
                .then(|| instruction.operand_at_faceplate(fault.exerr()))
                .flatten()
                .and_then(|(i, o)| call.args.get(i).map(|a| (a.span, o.name)));
            let d = match operand {
                Some((span, name)) => d.with_label(self.env.files.label(span, format!("{name} out of range"))),
                None => d.with_label(self.env.files.label(call.name_span, "its operands are constants")),
            };
            self.env
                .bindings
                .warnings
                .push(d.with_note(format!("the instruction says: {fault}")));
        }
        Ok(())
    }
}

/// What a tag is, for messages: `an axis`, `a REAL[2] tag`.
fn describe(info: &TagInfo) -> String {
    let ty = match info.kind {
        TagKind::Axis => return "an axis".to_owned(),
        TagKind::Scalar(t) => t.name().to_owned(),
        TagKind::Structure(s) => s.name().to_owned(),
        TagKind::Planner(b) => b.name().to_owned(),
        TagKind::User(_) => info.type_name.to_owned(),
    };
    match info.len {
        Some(n) => format!("a {ty}[{n}] tag"),
        None => format!("a {ty} tag"),
    }
}

/// A word refused for one operand that is a word of another operand of the
/// same instruction (`%ofTime` in Accel Units: a Jerk Units word) says so.
fn word_elsewhere(instruction: &Instruction, spec: &Spec, arg: &ArgText, d: Error) -> Error {
    let text = arg.text.trim();
    if !d.message.starts_with(&format!("'{text}' is not a word of ")) {
        return d;
    }
    let owners: Vec<&str> = instruction
        .operands
        .iter()
        .filter(|o| o.name != spec.name && o.code_of(text).is_some())
        .map(|o| o.name)
        .collect();
    if owners.is_empty() {
        return d;
    }
    Box::new((*d).with_note(format!(
        "'{text}' is a word of {} of {}",
        owners.join(" and "),
        instruction.mnemonic
    )))
}
