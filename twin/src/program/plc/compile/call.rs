//! Instruction calls: timers and the like, routine calls, data
//! instructions, GSV, function blocks, and the motion instructions bound
//! through the catalogue.

use super::{CompileError, Compiler, Result, err};
use crate::program::bind::axis_named;
use crate::program::compile_logix;
use crate::program::plc::ir::{
    AXIS_MEMBERS, BlockCall, Builtin, CExpr, CKind, GSV_ATTRIBUTES, GsvAttribute, MotionArg, MotionCall, Place, SKind,
    SSV_ATTRIBUTES,
};
use crate::program::plc::memory::Kind;
use crate::program::plc::types::{DataType, Structure, Ty, Value};
use crate::scene::{BaseType, Dialect};
use crate::st::ast::{Access, Arg, Call, Expr, ExprKind, Stmt, StmtKind};
use crate::st::lex::Pos;
use planner::catalogue::{self, CallStyle, Kind as OperandKind};

impl Compiler<'_, '_> {
    /// Binds the function-block calls of `stmts` (creating their instances),
    /// so that a reference to an instance's output compiles wherever it
    /// stands.
    ///
    /// # Errors
    /// The first [`CompileError`] of a call.
    pub fn bind_blocks(&mut self, stmts: &[Stmt]) -> Result<()> {
        for s in stmts {
            match &s.kind {
                StmtKind::Call(call) if call.args.iter().any(|a| a.name.is_some()) => {
                    self.block_call(call)?;
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

    /// A PLCopen function block called on its instance with named inputs.
    pub(super) fn block_call(&mut self, call: &Call) -> Result<SKind> {
        if self.dialect != Dialect::Iec {
            return err(
                call.pos,
                format!(
                    "{} is called with named inputs, as a PLCopen function block: write it in a routine of the IEC dialect ({{ file = \"…\", dialect = \"iec\" }}) or in a [[program]] step",
                    call.name
                ),
            );
        }
        let Some(t) = self.mem.resolve(Some(self.program), &call.name) else {
            return err(
                call.pos,
                format!("'{}' is not a tag of this program or a controller tag", call.name),
            );
        };
        let info = self.mem.tags[t].clone();
        if !matches!(info.kind, Kind::Planner(BaseType::FunctionBlock(_))) {
            return err(call.pos, format!("'{}' is not a function-block instance", call.name));
        }
        let block = &catalogue::MC_MOVE_MODULO;
        let mut inputs = Vec::with_capacity(call.args.len());
        let mut probe = Vec::with_capacity(call.args.len());
        for arg in &call.args {
            let Some(input) = &arg.name else {
                return err(arg.pos, "a function-block call names every input (Input := value)");
            };
            let text = arg.text.trim();
            let spec = block.operand(input).map(|(_, spec)| spec);
            let (value, p) = match spec {
                Some(spec) if spec.code_of(text).is_some() => (
                    MotionArg::Name(text.to_owned()),
                    crate::st::Expr::Ident(text.to_owned()),
                ),
                Some(spec) if spec.name == "Axis" => (
                    MotionArg::Name(text.to_owned()),
                    crate::st::Expr::Ident(text.to_owned()),
                ),
                _ => {
                    let v = self.value_arg(arg)?;
                    let p = match (v.kind.clone(), spec.map(|s| s.kind)) {
                        (CKind::Const(c), _) => value_expr(c),
                        (_, Some(OperandKind::Enumeration(words))) => {
                            crate::st::Expr::Integer(words.first().map_or(0, |w| w.code))
                        }
                        _ if v.ty == Ty::Bool => crate::st::Expr::Bool(false),
                        _ => crate::st::Expr::Number(0.0),
                    };
                    (MotionArg::Value(v), p)
                }
            };
            inputs.push((input.clone(), value));
            probe.push((input.clone(), p));
        }
        crate::program::modulo::bind(&named_call(&info.name, probe), self.ctx.scene, self.ctx.task, self.fbs).map_err(
            |e| CompileError {
                pos: e.operand.and_then(|i| call.args.get(i)).map_or(call.pos, |a| a.pos),
                message: e.message,
            },
        )?;
        Ok(SKind::Block(BlockCall {
            instance: info.name,
            inputs,
        }))
    }

    pub(super) fn value_arg(&mut self, arg: &Arg) -> Result<CExpr> {
        match &arg.expr {
            Some(e) => self.expr(e),
            None => err(arg.pos, format!("'{}' is not an expression", arg.text)),
        }
    }

    pub(super) fn target_arg(&mut self, arg: &Arg) -> Result<(Place, DataType)> {
        match &arg.expr {
            Some(Expr {
                kind: ExprKind::Ref(r), ..
            }) => self.writable(r),
            _ => err(arg.pos, format!("expected a tag to write, got '{}'", arg.text)),
        }
    }

    pub(super) fn call(&mut self, call: &Call) -> Result<SKind> {
        if call.args.iter().any(|a| a.name.is_some()) {
            return self.block_call(call);
        }
        let upper = call.name.to_ascii_uppercase();
        if let Some((b, s)) = self.builtin_of(&upper, call.pos)? {
            argc(call, &upper, 1)?;
            return Ok(SKind::Builtin(b, self.instance(&call.args[0], &[s], &upper)?));
        }
        match upper.as_str() {
            "JSR" => self.jsr(call),
            "SBR" => {
                let targets = call
                    .args
                    .iter()
                    .map(|a| self.target_arg(a))
                    .collect::<Result<Vec<_>>>()?;
                Ok(SKind::Sbr(targets))
            }
            "RET" => {
                let values = call
                    .args
                    .iter()
                    .map(|a| self.value_arg(a))
                    .collect::<Result<Vec<_>>>()?;
                Ok(SKind::Ret(values))
            }
            "COP" | "CPS" | "FLL" | "SIZE" => self.data_instruction(call, &upper),
            "GSV" | "SSV" => self.system_value(call, &upper),
            _ => self.motion(call),
        }
    }

    /// The timer, counter and edge instructions, by name; the IEC blocks
    /// only in the IEC dialect.
    fn builtin_of(&self, upper: &str, pos: Pos) -> Result<Option<(Builtin, Structure)>> {
        let iec = self.dialect == Dialect::Iec;
        Ok(Some(match upper {
            "TONR" => (Builtin::Tonr, Structure::Timer),
            "TOFR" => (Builtin::Tofr, Structure::Timer),
            "RTOR" => (Builtin::Rtor, Structure::Timer),
            "CTUD" => (Builtin::Ctud, Structure::Counter),
            "OSRI" => (Builtin::Osri, Structure::OneShot),
            "OSFI" => (Builtin::Osfi, Structure::OneShot),
            "R_TRIG" | "F_TRIG" | "TON" | "TOF" if !iec => {
                return err(
                    pos,
                    format!(
                        "{upper} is an IEC 61131-3 block Studio 5000 does not have: use the IEC dialect for this routine ({{ file = \"…\", dialect = \"iec\" }}), or the Logix instructions OSRI/OSFI/TONR/TOFR"
                    ),
                );
            }
            "R_TRIG" => (Builtin::RTrig, Structure::Trig),
            "F_TRIG" => (Builtin::FTrig, Structure::Trig),
            "TON" => (Builtin::Ton, Structure::IecTimer),
            "TOF" => (Builtin::Tof, Structure::IecTimer),
            _ => return Ok(None),
        }))
    }

    /// `COP`, `CPS`, `FLL`, `SIZE`.
    fn data_instruction(&mut self, call: &Call, upper: &str) -> Result<SKind> {
        argc(call, upper, 3)?;
        let a = &call.args;
        match upper {
            "FLL" => {
                let value = self.value_arg(&a[0])?;
                let dst = self.array_at(&a[1], "Dest")?;
                Ok(SKind::Fll(value, dst, self.integer_arg(&a[2])?))
            }
            "SIZE" => {
                let Some(Expr {
                    kind: ExprKind::Ref(r), ..
                }) = &a[0].expr
                else {
                    return err(a[0].pos, "SIZE: expected an array tag");
                };
                let t = self.tag(r)?;
                let Some(len) = self.mem.tags[t].len else {
                    return err(a[0].pos, format!("SIZE: '{}' is not an array", r.name));
                };
                if a[1].text.trim() != "0" {
                    return err(a[1].pos, "SIZE: arrays here have one dimension: Dimension To Vary is 0");
                }
                let (place, ty) = self.target_arg(&a[2])?;
                Ok(SKind::Size(len, place, ty))
            }
            _ => {
                let src = self.array_at(&a[0], "Source")?;
                let dst = self.array_at(&a[1], "Dest")?;
                if src.ty != dst.ty {
                    return err(
                        a[1].pos,
                        format!(
                            "{upper} between {} and {}: the twin copies elements of one type (copy across types element by element in a FOR loop)",
                            src.ty.name(),
                            dst.ty.name()
                        ),
                    );
                }
                Ok(SKind::Cop(src, dst, self.integer_arg(&a[2])?))
            }
        }
    }

    pub(super) fn integer_arg(&mut self, arg: &Arg) -> Result<CExpr> {
        match &arg.expr {
            Some(e) => self.integer(e),
            None => err(arg.pos, format!("expected an integer, got '{}'", arg.text)),
        }
    }

    pub(super) fn jsr(&mut self, call: &Call) -> Result<SKind> {
        let Some(first) = call.args.first() else {
            return err(call.pos, "JSR takes a routine name");
        };
        let name = first.text.trim();
        let Some(routine) = self.routines.iter().position(|r| r.eq_ignore_ascii_case(name)) else {
            return err(
                first.pos,
                format!(
                    "JSR: no routine '{name}' in this program (routines: {})",
                    self.routines.join(", ")
                ),
            );
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
            _ => return err(rest[0].pos, "JSR: Input Count must be a constant number"),
        };
        if rest.len() < 1 + count {
            return err(
                call.pos,
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
                call.pos,
                format!(
                    "{upper} takes 4 operands (Class, Instance, Attribute, {operands}), got {}",
                    call.args.len()
                ),
            );
        }
        if !call.args[0].text.trim().eq_ignore_ascii_case("AXIS") {
            return err(
                call.args[0].pos,
                format!("{upper}: the twin models the AXIS class only"),
            );
        }
        let name = call.args[1].text.trim();
        let axis = axis_named(self.ctx.task, name).ok_or_else(|| CompileError {
            pos: call.args[1].pos,
            message: format!("{upper}: '{name}' is not an axis"),
        })?;
        let attr_name = call.args[2].text.trim();
        if upper == "SSV" {
            let Some((_, limit)) = SSV_ATTRIBUTES.iter().find(|(n, _)| n.eq_ignore_ascii_case(attr_name)) else {
                let names: Vec<&str> = SSV_ATTRIBUTES.iter().map(|a| a.0).collect();
                return err(
                    call.args[2].pos,
                    format!(
                        "SSV: AXIS attribute '{attr_name}' cannot be set (settable: {})",
                        names.join(", ")
                    ),
                );
            };
            let value = self.value_arg(&call.args[3])?;
            if value.ty == Ty::Bool {
                return err(call.args[3].pos, "SSV: the Source is a number, not a BOOL");
            }
            return Ok(SKind::Ssv(axis, *limit, value));
        }
        let attribute = AXIS_MEMBERS
            .iter()
            .find(|(n, ..)| n.eq_ignore_ascii_case(attr_name))
            .map(|(_, m, _)| GsvAttribute::Member(*m))
            .or_else(|| {
                GSV_ATTRIBUTES
                    .iter()
                    .find(|(n, _)| n.eq_ignore_ascii_case(attr_name))
                    .map(|(_, a)| *a)
            });
        let Some(attribute) = attribute else {
            let names: Vec<&str> = AXIS_MEMBERS
                .iter()
                .map(|a| a.0)
                .chain(GSV_ATTRIBUTES.iter().map(|a| a.0))
                .collect();
            return err(
                call.args[2].pos,
                format!(
                    "GSV: AXIS attribute '{attr_name}' is not modelled (attributes: {})",
                    names.join(", ")
                ),
            );
        };
        let (place, ty) = self.target_arg(&call.args[3])?;
        Ok(SKind::Gsv(axis, attribute, place, ty))
    }

    /// A motion instruction: operands resolved by the catalogue, then bound
    /// once now (handles created, operands checked) with placeholder values
    /// for what is computed at run time.
    pub(super) fn motion(&mut self, call: &Call) -> Result<SKind> {
        let instruction = motion_instruction(call)?;
        let mut args = Vec::with_capacity(call.args.len());
        let mut probe = Vec::with_capacity(call.args.len());
        for (spec, arg) in instruction.operands.iter().zip(&call.args) {
            let (a, p) = self.motion_operand(spec, arg)?;
            args.push(a);
            probe.push(p);
        }
        let step = compile_logix(instruction.mnemonic, &probe, self.ctx).map_err(|e| CompileError {
            pos: e.operand.and_then(|i| call.args.get(i)).map_or(call.pos, |a| a.pos),
            message: e.message,
        })?;
        if let Some(control) = step.control {
            self.ctx.task.set_scanned(control);
        }
        Ok(SKind::Motion(MotionCall {
            instruction,
            args,
            control: step.control,
        }))
    }

    /// One operand of a motion instruction, and the value it is bound with
    /// at load (the constant, or a placeholder for what the program
    /// computes).
    fn motion_operand(&mut self, spec: &catalogue::Operand, arg: &Arg) -> Result<(MotionArg, crate::st::Expr)> {
        let text = arg.text.trim();
        if spec.code_of(text).is_some() {
            return Ok((
                MotionArg::Name(text.to_owned()),
                crate::st::Expr::Ident(text.to_owned()),
            ));
        }
        let Some(expr) = &arg.expr else {
            return err(
                arg.pos,
                format!(
                    "{} '{text}': not an operand (its words: {})",
                    spec.name,
                    spec.word_list()
                ),
            );
        };
        if let ExprKind::Ref(r) = &expr.kind
            && let Some(t) = self.mem.resolve(Some(self.program), &r.name)
        {
            let info = self.mem.tags[t].clone();
            let ident = || crate::st::Expr::Ident(info.name.clone());
            let named = matches!(info.kind, Kind::Axis | Kind::Planner(_)) || info.len.is_some();
            if named && r.path.is_empty() {
                return Ok((MotionArg::Name(info.name.clone()), ident()));
            }
            if let (Some(_), [Access::Index(sub)]) = (info.len, r.path.as_slice()) {
                let index = self.subscript(sub, r)?;
                let at = match index.kind {
                    CKind::Const(v) => v.as_i64(),
                    _ => 0,
                };
                let probe = crate::st::Expr::Index(Box::new(ident()), at);
                return Ok((MotionArg::Element(info.name.clone(), index), probe));
            }
        }
        let value = self.expr(expr)?;
        let constant_value = match value.kind {
            CKind::Const(v) => Some(v),
            _ => None,
        };
        if matches!(spec.format, catalogue::Format::Immediate) && constant_value.is_none() {
            return err(
                arg.pos,
                format!(
                    "{} '{text}': the operand's format is Immediate: write a constant or one of {}",
                    spec.name,
                    spec.word_list()
                ),
            );
        }
        let probe = operand_expr(spec.kind, constant_value.unwrap_or(Value::Int(0)));
        Ok((MotionArg::Value(value), probe))
    }
}

/// The catalogue entry of a positional call, with its operand count checked.
fn motion_instruction(call: &Call) -> Result<&'static catalogue::Instruction> {
    let Some(instruction) = catalogue::find(&call.name) else {
        if catalogue::NOT_SIMULATED
            .iter()
            .any(|m| m.eq_ignore_ascii_case(&call.name))
        {
            let name = call.name.to_ascii_uppercase();
            let simulated = catalogue::positional_mnemonics();
            return err(
                call.pos,
                format!("{name} is a Logix motion instruction the twin does not simulate (it simulates: {simulated})"),
            );
        }
        return err(call.pos, format!("unknown instruction '{}'", call.name));
    };
    if instruction.style != CallStyle::Positional {
        return err(
            call.pos,
            format!(
                "{} is a function block: call it on its instance with named inputs",
                instruction.mnemonic
            ),
        );
    }
    if call.args.len() != instruction.operands.len() {
        return err(
            call.pos,
            format!(
                "{} takes {} operands ({}), got {}",
                instruction.mnemonic,
                instruction.operands.len(),
                instruction.operand_names(),
                call.args.len()
            ),
        );
    }
    Ok(instruction)
}

/// Checks a call's operand count.
fn argc(call: &Call, upper: &str, n: usize) -> Result<()> {
    if call.args.len() == n {
        Ok(())
    } else {
        err(
            call.pos,
            format!("{upper} takes {n} operand(s), got {}", call.args.len()),
        )
    }
}

/// A named call in the form the `[[program]]` binding reads.
#[must_use]
pub fn named_call(instance: &str, inputs: Vec<(String, crate::st::Expr)>) -> crate::st::Call {
    use crate::st::{Args, Span, Spanned};
    fn spanned<T>(value: T) -> Spanned<T> {
        Spanned {
            value,
            span: Span::default(),
        }
    }
    crate::st::Call {
        name: spanned(instance.to_owned()),
        args: Args::Named(inputs.into_iter().map(|(n, e)| (spanned(n), spanned(e))).collect()),
    }
}

/// A value as the binding reads an operand that keeps its own type.
#[must_use]
pub fn value_expr(v: Value) -> crate::st::Expr {
    match v {
        Value::Bool(b) => crate::st::Expr::Bool(b),
        Value::Int(i) => crate::st::Expr::Integer(i),
        Value::Real(x) => crate::st::Expr::Number(x),
    }
}

/// The call operand a value becomes for the binding: integers for the
/// integer kinds (REAL rounded half to even, as on assignment), numbers
/// otherwise.
#[must_use]
pub fn operand_expr(kind: OperandKind, v: Value) -> crate::st::Expr {
    match kind {
        OperandKind::Count | OperandKind::Integer | OperandKind::Enumeration(_) => crate::st::Expr::Integer(v.as_i64()),
        OperandKind::Bool => crate::st::Expr::Bool(v.truthy()),
        _ => match v {
            Value::Bool(b) => crate::st::Expr::Integer(i64::from(b)),
            Value::Int(i) => crate::st::Expr::Integer(i),
            Value::Real(x) => crate::st::Expr::Number(x),
        },
    }
}
