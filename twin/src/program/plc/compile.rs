//! Compiles a parsed routine against tag memory and the planner: every
//! name resolved, every expression typed, every instruction's operands
//! checked, so that errors name the routine file, line and column at load.

use super::ir::{
    AXIS_MEMBERS, ArrayAt, BlockCall, Builtin, CExpr, CKind, CStmt, CoordMember, FbMember, Func, GSV_ATTRIBUTES,
    GsvAttribute, Instance, MotionArg, MotionCall, MotionMember, Place, SKind,
};
use super::memory::{Kind, Memory};
use super::types::{DataType, Structure, Ty, Value};
use crate::program::bind::{LogixContext, axis_named};
use crate::program::{FbBinding, coord, compile_logix};
use crate::scene::{BaseType, Dialect};
use crate::st::ast::{Access, Arg, BinaryOp, Call, Expr, ExprKind, Ref, Stmt, StmtKind, UnaryOp};
use crate::st::lex::Pos;
use planner::catalogue::{self, CallStyle, Kind as OperandKind};
use planner::instruction::MotionInstructionBits;

/// A compile error: where, and what is wrong.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CompileError {
    /// Where.
    pub pos: Pos,
    /// What.
    pub message: String,
}

type Result<T> = std::result::Result<T, CompileError>;

fn err<T>(pos: Pos, message: impl Into<String>) -> Result<T> {
    Err(CompileError {
        pos,
        message: message.into(),
    })
}

/// What a routine is compiled against.
pub struct Compiler<'c, 'a> {
    /// Tag memory (names and layout).
    pub mem: &'c Memory,
    /// The program the routine belongs to (its tags shadow the
    /// controller's).
    pub program: &'c str,
    /// The program's routines, for `JSR`.
    pub routines: &'c [String],
    /// The routine's dialect.
    pub dialect: Dialect,
    /// The planner binding (handles are created on first use).
    pub ctx: &'c mut LogixContext<'a>,
    /// The program's function-block instances (created on their first call).
    pub fbs: &'c mut Vec<FbBinding>,
    /// Loop nesting (for `EXIT`).
    loops: usize,
}

const BIT_NAMES: [&str; 8] = ["EN", "DN", "ER", "IP", "AC", "PC", "ACCEL", "DECEL"];

impl<'c, 'a> Compiler<'c, 'a> {
    /// A compiler for one routine.
    pub fn new(
        mem: &'c Memory,
        program: &'c str,
        routines: &'c [String],
        dialect: Dialect,
        ctx: &'c mut LogixContext<'a>,
        fbs: &'c mut Vec<FbBinding>,
    ) -> Self {
        Compiler {
            mem,
            program,
            routines,
            dialect,
            ctx,
            fbs,
            loops: 0,
        }
    }

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
    fn block_call(&mut self, call: &Call) -> Result<SKind> {
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
            return err(call.pos, format!("'{}' is not a tag of this program or a controller tag", call.name));
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
                Some(spec) if spec.code_of(text).is_some() => {
                    (MotionArg::Name(text.to_owned()), crate::st::Expr::Ident(text.to_owned()))
                }
                Some(spec) if spec.name == "Axis" => {
                    (MotionArg::Name(text.to_owned()), crate::st::Expr::Ident(text.to_owned()))
                }
                _ => {
                    let v = self.value_arg(arg)?;
                    let p = match (v.kind.clone(), spec.map(|s| s.kind)) {
                        (CKind::Const(c), _) => match c {
                            Value::Bool(b) => crate::st::Expr::Bool(b),
                            Value::Int(i) => crate::st::Expr::Integer(i),
                            Value::Real(x) => crate::st::Expr::Number(x),
                        },
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
        crate::program::modulo::bind(&named_call(&info.name, probe), self.ctx.scene, self.ctx.task, self.fbs)
            .map_err(|e| CompileError {
                pos: e.operand.and_then(|i| call.args.get(i)).map_or(call.pos, |a| a.pos),
                message: e.message,
            })?;
        Ok(SKind::Block(BlockCall {
            instance: info.name,
            inputs,
        }))
    }

    /// Compiles statements.
    ///
    /// # Errors
    /// The first [`CompileError`].
    pub fn block(&mut self, stmts: &[Stmt]) -> Result<Vec<CStmt>> {
        stmts.iter().filter(|s| s.kind != StmtKind::Empty).map(|s| self.stmt(s)).collect()
    }

    fn stmt(&mut self, s: &Stmt) -> Result<CStmt> {
        let kind = match &s.kind {
            StmtKind::Assign {
                target,
                value,
                retentive,
            } => {
                let (target, ty) = self.writable(target)?;
                let value = self.expr(value)?;
                SKind::Assign {
                    target,
                    ty,
                    value,
                    retentive: *retentive,
                }
            }
            StmtKind::If { branches, otherwise } => {
                let mut out = Vec::with_capacity(branches.len());
                for (c, body) in branches {
                    out.push((self.condition(c)?, self.block(body)?));
                }
                SKind::If(out, self.block(otherwise)?)
            }
            StmtKind::Case {
                selector,
                arms,
                otherwise,
            } => {
                let sel = self.expr(selector)?;
                if !sel.ty.is_integer() {
                    return err(selector.pos, format!("CASE selector must be an integer, got {}", sel.ty.name()));
                }
                let mut out = Vec::with_capacity(arms.len());
                for (labels, body) in arms {
                    out.push((labels.clone(), self.block(body)?));
                }
                SKind::Case(sel, out, self.block(otherwise)?)
            }
            StmtKind::For {
                counter,
                from,
                to,
                by,
                body,
            } => {
                let (place, ty) = self.writable(counter)?;
                if !ty.is_integer() {
                    return err(counter.pos, format!("FOR counter must be an integer tag, got {}", ty.name()));
                }
                let from = self.integer(from)?;
                let to = self.integer(to)?;
                let by = match by {
                    Some(b) => self.integer(b)?,
                    None => constant(Value::Int(1), Ty::Dint),
                };
                self.loops += 1;
                let body = self.block(body);
                self.loops -= 1;
                SKind::For {
                    counter: place,
                    ty,
                    from,
                    to,
                    by,
                    body: body?,
                }
            }
            StmtKind::While { condition, body } => {
                let c = self.condition(condition)?;
                self.loops += 1;
                let body = self.block(body);
                self.loops -= 1;
                SKind::While(c, body?)
            }
            StmtKind::Repeat { body, until } => {
                self.loops += 1;
                let b = self.block(body);
                self.loops -= 1;
                SKind::Repeat(b?, self.condition(until)?)
            }
            StmtKind::Exit if self.loops == 0 => return err(s.pos, "EXIT outside FOR, WHILE or REPEAT"),
            StmtKind::Exit => SKind::Exit,
            StmtKind::Call(call) => self.call(call)?,
            StmtKind::Empty => unreachable!("filtered"),
        };
        Ok(CStmt {
            kind,
            line: s.pos.line,
        })
    }

    fn condition(&mut self, e: &Expr) -> Result<CExpr> {
        let c = self.expr(e)?;
        if c.ty == Ty::Bool || c.ty.is_integer() {
            Ok(c)
        } else {
            err(e.pos, format!("a condition must be BOOL, got {}", c.ty.name()))
        }
    }

    fn integer(&mut self, e: &Expr) -> Result<CExpr> {
        let c = self.expr(e)?;
        if c.ty.is_integer() || c.ty == Ty::Bool {
            Ok(c)
        } else {
            err(e.pos, format!("expected an integer expression, got {}", c.ty.name()))
        }
    }

    /// Compiles an expression.
    ///
    /// # Errors
    /// A [`CompileError`] at the offending part.
    pub fn expr(&mut self, e: &Expr) -> Result<CExpr> {
        Ok(match &e.kind {
            ExprKind::Int(i) => match i64::try_from(*i) {
                Ok(v) if i32::try_from(v).is_ok() => constant(Value::Int(v), Ty::Dint),
                Ok(v) => constant(Value::Int(v), Ty::Lint),
                Err(_) => return err(e.pos, format!("integer literal {i} is out of range (64 bits)")),
            },
            ExprKind::Real(x) => constant(Value::Real(f64::from(*x as f32)), Ty::Real),
            ExprKind::Bool(b) => constant(Value::Bool(*b), Ty::Bool),
            ExprKind::Ref(r) => {
                let (place, ty) = self.place(r)?;
                let kind = match place {
                    Place::Slot(i) => CKind::Slot(i),
                    place => CKind::Load(Box::new(place)),
                };
                CExpr { kind, ty: ty.math() }
            }
            ExprKind::Unary(UnaryOp::Neg, a) => {
                let a = self.expr(a)?;
                if a.ty == Ty::Bool {
                    return err(e.pos, "'-' needs a number, got BOOL");
                }
                let ty = a.ty;
                CExpr {
                    kind: CKind::Neg(Box::new(a)),
                    ty,
                }
            }
            ExprKind::Unary(UnaryOp::Not, a) => {
                let a = self.expr(a)?;
                if a.ty.is_real() {
                    return err(e.pos, format!("NOT needs BOOL or an integer, got {}", a.ty.name()));
                }
                let ty = a.ty;
                CExpr {
                    kind: CKind::Not(Box::new(a)),
                    ty,
                }
            }
            ExprKind::Binary(op, a, b) => self.binary(*op, a, b, e.pos)?,
            ExprKind::Function(name, args) => {
                let Some(f) = Func::parse(name) else {
                    return err(
                        e.pos,
                        format!(
                            "unknown function '{name}' (functions: ABS, SQRT, SIN, COS, TAN, ASIN, ACOS, ATAN, LN, LOG, DEG, RAD, TRUNC)"
                        ),
                    );
                };
                if args.len() != 1 {
                    return err(e.pos, format!("{} takes 1 argument, got {}", name.to_ascii_uppercase(), args.len()));
                }
                let a = self.expr(&args[0])?;
                if a.ty == Ty::Bool {
                    return err(args[0].pos, format!("{} needs a number, got BOOL", name.to_ascii_uppercase()));
                }
                let ty = match f {
                    Func::Abs => a.ty,
                    Func::Trunc => Ty::Dint,
                    _ if a.ty == Ty::Lreal => Ty::Lreal,
                    _ => Ty::Real,
                };
                CExpr {
                    kind: CKind::Func(f, Box::new(a)),
                    ty,
                }
            }
        })
    }

    fn binary(&mut self, op: BinaryOp, a: &Expr, b: &Expr, pos: Pos) -> Result<CExpr> {
        let x = self.expr(a)?;
        let y = self.expr(b)?;
        let numeric = |t: Ty| if t == Ty::Bool { Ty::Dint } else { t };
        let arith = |x: Ty, y: Ty| {
            let (x, y) = (numeric(x), numeric(y));
            if x == Ty::Lreal || y == Ty::Lreal {
                Ty::Lreal
            } else if x == Ty::Real || y == Ty::Real {
                if x == Ty::Lint || y == Ty::Lint { Ty::Lreal } else { Ty::Real }
            } else if x == Ty::Lint || y == Ty::Lint {
                Ty::Lint
            } else {
                Ty::Dint
            }
        };
        let (math, result) = match op {
            BinaryOp::Pow => {
                let m = if arith(x.ty, y.ty) == Ty::Lreal || arith(x.ty, y.ty) == Ty::Lint {
                    Ty::Lreal
                } else {
                    Ty::Real
                };
                (m, m)
            }
            BinaryOp::Mul | BinaryOp::Div | BinaryOp::Mod | BinaryOp::Add | BinaryOp::Sub => {
                let m = arith(x.ty, y.ty);
                (m, m)
            }
            BinaryOp::Lt | BinaryOp::Le | BinaryOp::Gt | BinaryOp::Ge | BinaryOp::Eq | BinaryOp::Ne => {
                if (x.ty == Ty::Bool) != (y.ty == Ty::Bool) && !(matches!(op, BinaryOp::Eq | BinaryOp::Ne)) {
                    return err(pos, format!("'{}' compares numbers, got BOOL", op.symbol()));
                }
                let m = if x.ty == Ty::Bool && y.ty == Ty::Bool { Ty::Dint } else { arith(x.ty, y.ty) };
                (m, Ty::Bool)
            }
            BinaryOp::And | BinaryOp::Or | BinaryOp::Xor => {
                if x.ty.is_real() || y.ty.is_real() {
                    return err(pos, format!("{} needs BOOL or integer operands, got REAL", op.symbol()));
                }
                if x.ty == Ty::Bool && y.ty == Ty::Bool {
                    (Ty::Bool, Ty::Bool)
                } else {
                    let m = arith(x.ty, y.ty);
                    (m, m)
                }
            }
        };
        if let (CKind::Const(a), CKind::Const(b), Ty::Dint) = (&x.kind, &y.kind, math)
            && let Some(v) = fold_dint(op, a.as_i64(), b.as_i64())
        {
            return Ok(constant(v, result));
        }
        Ok(CExpr {
            kind: CKind::Binary(op, Box::new(x), Box::new(y), math),
            ty: result,
        })
    }

    fn tag(&self, r: &Ref) -> Result<usize> {
        self.mem.resolve(Some(self.program), &r.name).ok_or_else(|| CompileError {
            pos: r.pos,
            message: format!("'{}' is not a tag of this program, a controller tag or an axis", r.name),
        })
    }

    /// A place that may be written, with its type.
    fn writable(&mut self, r: &Ref) -> Result<(Place, DataType)> {
        let (place, ty) = self.place(r)?;
        match place {
            Place::Axis(..) | Place::Coord(..) | Place::Fb(..) | Place::FirstScan | Place::MinorInScan | Place::MinorFaults => err(
                r.pos,
                format!("'{}' is read-only (axis and coordinate-system members, S:FS, S:MINOR and MinorFaults are the controller's)", show(r)),
            ),
            Place::Motion(_, MotionMember::Bit(_)) => Ok((place, ty)),
            Place::Motion(..) => err(r.pos, format!("'{}' is read-only: the instruction writes its codes", show(r))),
            _ => Ok((place, ty)),
        }
    }

    /// Compiles a reference (for the trace).
    ///
    /// # Errors
    /// A [`CompileError`] when it names nothing readable.
    pub fn reference(&mut self, r: &Ref) -> Result<(Place, DataType)> {
        self.place(r)
    }

    /// `Program.Tag` written from outside the program: the qualified tag.
    fn qualified(&self, r: &Ref) -> Option<Ref> {
        if self.mem.resolve(Some(self.program), &r.name).is_some() {
            return None;
        }
        let Some(Access::Member(m)) = r.path.first() else {
            return None;
        };
        let name = format!("{}.{m}", r.name);
        self.mem.find(&name)?;
        Some(Ref {
            name,
            path: r.path[1..].to_vec(),
            pos: r.pos,
        })
    }

    /// Resolves a reference.
    fn place(&mut self, r: &Ref) -> Result<(Place, DataType)> {
        if let Some(q) = self.qualified(r) {
            return self.place(&q);
        }
        if r.path.is_empty() {
            match r.name.to_ascii_uppercase().as_str() {
                "S:FS" => return Ok((Place::FirstScan, DataType::Bool)),
                "S:MINOR" => return Ok((Place::MinorInScan, DataType::Bool)),
                n if n.starts_with("S:") => {
                    return err(r.pos, format!("status flag {} is not modelled (S:FS and S:MINOR are)", r.name));
                }
                "MINORFAULTS" if self.mem.resolve(Some(self.program), &r.name).is_none() => {
                    return Ok((Place::MinorFaults, DataType::Dint));
                }
                _ => {}
            }
        }
        let t = self.tag(r)?;
        let info = self.mem.tags[t].clone();
        let mut path = r.path.iter().peekable();
        let (mut place, mut ty) = match info.kind {
            Kind::Scalar(_) | Kind::Structure(Structure::Cam) if info.len.is_some() && path.peek().is_none() => {
                return err(r.pos, format!("'{}' is an array: name an element, e.g. {}[0]", r.name, r.name));
            }
            Kind::Scalar(ty) => {
                let place = match (info.len, path.peek()) {
                    (Some(len), Some(Access::Index(sub))) => {
                        path.next();
                        Place::Element {
                            base: info.base,
                            len,
                            stride: 1,
                            offset: 0,
                            index: self.subscript(sub, r)?,
                            name: info.name.clone(),
                        }
                    }
                    (Some(_), _) => return err(r.pos, format!("'{}' is an array: name an element", r.name)),
                    (None, _) => Place::Slot(info.base),
                };
                (place, ty)
            }
            Kind::Structure(s) => {
                let (index, len) = match (info.len, path.peek()) {
                    (Some(len), Some(Access::Index(sub))) => {
                        path.next();
                        (Some(self.subscript(sub, r)?), len)
                    }
                    (Some(_), _) => return err(r.pos, format!("'{}' is an array: name an element", r.name)),
                    (None, _) => (None, 1),
                };
                let Some(Access::Member(m)) = path.next() else {
                    return err(
                        r.pos,
                        format!("'{}' is a {}: name a member ({})", r.name, s.name(), s.visible_members()),
                    );
                };
                let Some((offset, mty)) = s.member(m) else {
                    return err(
                        r.pos,
                        format!("{} has no member '{m}' (members: {})", s.name(), s.visible_members()),
                    );
                };
                let place = match index {
                    Some(index) => Place::Element {
                        base: info.base,
                        len,
                        stride: s.size(),
                        offset,
                        index,
                        name: info.name.clone(),
                    },
                    None => Place::Slot(info.base + offset),
                };
                (place, mty)
            }
            Kind::Axis => {
                let Some(Access::Member(m)) = path.next() else {
                    return err(r.pos, format!("'{}' is an axis: name a member, e.g. {}.ActualPosition", r.name, r.name));
                };
                let Some((_, member, ty)) = AXIS_MEMBERS.iter().find(|(n, ..)| n.eq_ignore_ascii_case(m)) else {
                    let names: Vec<&str> = AXIS_MEMBERS.iter().map(|a| a.0).collect();
                    return err(r.pos, format!("axis member '{m}' is not modelled (members: {})", names.join(", ")));
                };
                let axis = axis_named(self.ctx.task, &info.name).ok_or_else(|| CompileError {
                    pos: r.pos,
                    message: format!("axis '{}' is not in the planner", info.name),
                })?;
                (Place::Axis(axis, *member), *ty)
            }
            Kind::Planner(BaseType::MotionInstruction) => {
                let Some(Access::Member(m)) = path.next() else {
                    return err(r.pos, format!("'{}' is a MOTION_INSTRUCTION: name a member, e.g. {}.PC", r.name, r.name));
                };
                let handle = self
                    .ctx
                    .instruction("Motion Control", &crate::st::Expr::Ident(info.name.clone()))
                    .map_err(|message| CompileError { pos: r.pos, message })?;
                let upper = m.to_ascii_uppercase();
                let (member, ty) = if let Some(b) = BIT_NAMES.iter().find(|b| **b == upper) {
                    (MotionMember::Bit(b), DataType::Bool)
                } else {
                    match upper.as_str() {
                        "ERR" => (MotionMember::Err, DataType::Int),
                        "EXERR" => (MotionMember::Exerr, DataType::Sint),
                        "SEGMENT" => (MotionMember::Segment, DataType::Dint),
                        _ => {
                            return err(
                                r.pos,
                                format!(
                                    "MOTION_INSTRUCTION has no member '{m}' (members: {}, ERR, EXERR, SEGMENT)",
                                    BIT_NAMES.join(", ")
                                ),
                            );
                        }
                    }
                };
                debug_assert!(MotionInstructionBits::default().bits().len() == BIT_NAMES.len());
                (Place::Motion(handle, member), ty)
            }
            Kind::Planner(BaseType::CoordinateSystem) => {
                let Some(Access::Member(m)) = path.next() else {
                    return err(r.pos, format!("'{}' is a COORDINATE_SYSTEM: name a status bit", r.name));
                };
                let handle = coord::coordinate_system(self.ctx, "Coordinate System", &crate::st::Expr::Ident(info.name.clone()))
                    .map_err(|message| CompileError { pos: r.pos, message })?;
                let status = planner::coord::CoordStatus::default();
                let member = if let Some((n, _)) = status.bits().into_iter().find(|(n, _)| n.eq_ignore_ascii_case(m)) {
                    CoordMember::Status(n)
                } else if m.eq_ignore_ascii_case("TransformSourceStatus") {
                    CoordMember::TransformSource
                } else if m.eq_ignore_ascii_case("TransformTargetStatus") {
                    CoordMember::TransformTarget
                } else {
                    let names: Vec<&str> = status.bits().into_iter().map(|b| b.0).collect();
                    return err(
                        r.pos,
                        format!(
                            "COORDINATE_SYSTEM has no member '{m}' (members: {}, TransformSourceStatus, TransformTargetStatus)",
                            names.join(", ")
                        ),
                    );
                };
                (Place::Coord(handle, member), DataType::Bool)
            }
            Kind::Planner(BaseType::FunctionBlock(_)) => {
                let Some(Access::Member(m)) = path.next() else {
                    return err(r.pos, format!("'{}' is a function block: name an output, e.g. {}.Done", r.name, r.name));
                };
                let Some(fb) = self.fbs.iter().find(|f| f.name.eq_ignore_ascii_case(&info.name)) else {
                    return err(
                        r.pos,
                        format!("'{}' is never called in an IEC routine or a program step: it has no outputs to read", r.name),
                    );
                };
                let outputs = planner::instruction::FbOutputs::default();
                let member = if m.eq_ignore_ascii_case("ErrorID") {
                    (FbMember::ErrorId, DataType::Udint)
                } else if let Some((n, _)) = outputs.bits().into_iter().find(|(n, _)| n.eq_ignore_ascii_case(m)) {
                    (FbMember::Bit(n), DataType::Bool)
                } else {
                    let names: Vec<&str> = outputs.bits().into_iter().map(|b| b.0).collect();
                    return err(r.pos, format!("function block outputs are {}, ErrorID; not '{m}'", names.join(", ")));
                };
                (Place::Fb(fb.handle, member.0), member.1)
            }
            Kind::Planner(base) => {
                return err(r.pos, format!("'{}' is a {} tag: a program does not read it in an expression", r.name, base.name()));
            }
        };
        // A bit of an integer: `.5` or `.[i]`.
        if let Some(access) = path.next() {
            let bit = match access {
                Access::Bit(b) => constant(Value::Int(i64::from(*b)), Ty::Dint),
                Access::BitExpr(e) => self.integer(e)?,
                _ => return err(r.pos, format!("'{}': nothing follows a {} value but a bit number", show(r), ty.name())),
            };
            if !ty.is_integer() {
                return err(r.pos, format!("'{}': bit access needs an integer, this is {}", show(r), ty.name()));
            }
            if let CKind::Const(Value::Int(b)) = bit.kind
                && (b < 0 || b >= i64::from(ty.bits()))
            {
                return err(r.pos, format!("'{}': bit {b} is outside a {} ({} bits)", show(r), ty.name(), ty.bits()));
            }
            place = Place::Bit {
                inner: Box::new(place),
                width: ty.bits(),
                bit,
                ty,
            };
            ty = DataType::Bool;
        }
        if path.next().is_some() {
            return err(r.pos, format!("'{}': too many parts", show(r)));
        }
        Ok((place, ty))
    }

    fn subscript(&mut self, sub: &[Expr], r: &Ref) -> Result<CExpr> {
        if sub.len() != 1 {
            return err(r.pos, format!("'{}' has one dimension, got {} subscripts", r.name, sub.len()));
        }
        self.integer(&sub[0])
    }

    fn instance(&mut self, arg: &Arg, want: &[Structure], what: &str) -> Result<Instance> {
        let bad = || CompileError {
            pos: arg.pos,
            message: format!(
                "{what} takes a {} tag, got '{}'",
                want.iter().map(|s| s.name()).collect::<Vec<_>>().join(" or "),
                arg.text
            ),
        };
        let Some(Expr {
            kind: ExprKind::Ref(r), ..
        }) = &arg.expr
        else {
            return Err(bad());
        };
        let t = self.tag(r)?;
        let info = self.mem.tags[t].clone();
        let Kind::Structure(s) = info.kind else { return Err(bad()) };
        if !want.contains(&s) {
            return Err(bad());
        }
        let index = match (info.len, r.path.as_slice()) {
            (None, []) => None,
            (Some(len), [Access::Index(sub)]) => Some((self.subscript(sub, r)?, len)),
            _ => return Err(bad()),
        };
        Ok(Instance {
            base: info.base,
            structure: s,
            index,
            name: info.name,
        })
    }

    fn array_at(&mut self, arg: &Arg, what: &str) -> Result<ArrayAt> {
        let bad = || CompileError {
            pos: arg.pos,
            message: format!("{what}: expected an array element such as Tag[0], got '{}'", arg.text),
        };
        let Some(Expr {
            kind: ExprKind::Ref(r), ..
        }) = &arg.expr
        else {
            return Err(bad());
        };
        let t = self.tag(r)?;
        let info = self.mem.tags[t].clone();
        let (Kind::Scalar(ty), Some(len)) = (info.kind, info.len) else {
            return Err(bad());
        };
        let start = match r.path.as_slice() {
            [Access::Index(sub)] => self.subscript(sub, r)?,
            [] => constant(Value::Int(0), Ty::Dint),
            _ => return Err(bad()),
        };
        Ok(ArrayAt {
            base: info.base,
            len,
            start,
            ty,
            name: info.name,
        })
    }

    fn value_arg(&mut self, arg: &Arg) -> Result<CExpr> {
        match &arg.expr {
            Some(e) => self.expr(e),
            None => err(arg.pos, format!("'{}' is not an expression", arg.text)),
        }
    }

    fn target_arg(&mut self, arg: &Arg) -> Result<(Place, DataType)> {
        match &arg.expr {
            Some(Expr {
                kind: ExprKind::Ref(r), ..
            }) => self.writable(r),
            _ => err(arg.pos, format!("expected a tag to write, got '{}'", arg.text)),
        }
    }

    fn call(&mut self, call: &Call) -> Result<SKind> {
        let upper = call.name.to_ascii_uppercase();
        let argc = |n: usize| -> Result<()> {
            if call.args.len() == n {
                Ok(())
            } else {
                err(call.pos, format!("{upper} takes {n} operand(s), got {}", call.args.len()))
            }
        };
        if call.args.iter().any(|a| a.name.is_some()) {
            return self.block_call(call);
        }
        let iec = self.dialect == Dialect::Iec;
        let builtin = match upper.as_str() {
            "TONR" => Some((Builtin::Tonr, Structure::Timer)),
            "TOFR" => Some((Builtin::Tofr, Structure::Timer)),
            "RTOR" => Some((Builtin::Rtor, Structure::Timer)),
            "CTUD" => Some((Builtin::Ctud, Structure::Counter)),
            "OSRI" => Some((Builtin::Osri, Structure::OneShot)),
            "OSFI" => Some((Builtin::Osfi, Structure::OneShot)),
            "R_TRIG" | "F_TRIG" | "TON" | "TOF" if !iec => {
                return err(
                    call.pos,
                    format!("{upper} is an IEC 61131-3 block Studio 5000 does not have: use the IEC dialect for this routine ({{ file = \"…\", dialect = \"iec\" }}), or the Logix instructions OSRI/OSFI/TONR/TOFR"),
                );
            }
            "R_TRIG" => Some((Builtin::RTrig, Structure::Trig)),
            "F_TRIG" => Some((Builtin::FTrig, Structure::Trig)),
            "TON" => Some((Builtin::Ton, Structure::IecTimer)),
            "TOF" => Some((Builtin::Tof, Structure::IecTimer)),
            _ => None,
        };
        if let Some((b, s)) = builtin {
            argc(1)?;
            return Ok(SKind::Builtin(b, self.instance(&call.args[0], &[s], &upper)?));
        }
        match upper.as_str() {
            "JSR" => return self.jsr(call),
            "SBR" => {
                let targets = call.args.iter().map(|a| self.target_arg(a)).collect::<Result<Vec<_>>>()?;
                return Ok(SKind::Sbr(targets));
            }
            "RET" => {
                let values = call.args.iter().map(|a| self.value_arg(a)).collect::<Result<Vec<_>>>()?;
                return Ok(SKind::Ret(values));
            }
            "COP" | "CPS" => {
                argc(3)?;
                let src = self.array_at(&call.args[0], "Source")?;
                let dst = self.array_at(&call.args[1], "Dest")?;
                if src.ty != dst.ty {
                    return err(
                        call.args[1].pos,
                        format!(
                            "{upper} between {} and {}: the twin copies elements of one type (copy across types element by element in a FOR loop)",
                            src.ty.name(),
                            dst.ty.name()
                        ),
                    );
                }
                let len = self.integer_arg(&call.args[2])?;
                return Ok(SKind::Cop(src, dst, len));
            }
            "FLL" => {
                argc(3)?;
                let value = self.value_arg(&call.args[0])?;
                let dst = self.array_at(&call.args[1], "Dest")?;
                let len = self.integer_arg(&call.args[2])?;
                return Ok(SKind::Fll(value, dst, len));
            }
            "SIZE" => {
                argc(3)?;
                let Some(Expr {
                    kind: ExprKind::Ref(r), ..
                }) = &call.args[0].expr
                else {
                    return err(call.args[0].pos, "SIZE: expected an array tag");
                };
                let t = self.tag(r)?;
                let Some(len) = self.mem.tags[t].len else {
                    return err(call.args[0].pos, format!("SIZE: '{}' is not an array", r.name));
                };
                if call.args[1].text.trim() != "0" {
                    return err(call.args[1].pos, "SIZE: arrays here have one dimension: Dimension To Vary is 0");
                }
                let (place, ty) = self.target_arg(&call.args[2])?;
                return Ok(SKind::Size(len, place, ty));
            }
            "GSV" => return self.gsv(call),
            "SSV" => {
                return err(
                    call.pos,
                    "SSV: no axis attribute is settable in the twin yet (GSV reads them)",
                );
            }
            _ => {}
        }
        self.motion(call)
    }

    fn integer_arg(&mut self, arg: &Arg) -> Result<CExpr> {
        match &arg.expr {
            Some(e) => self.integer(e),
            None => err(arg.pos, format!("expected an integer, got '{}'", arg.text)),
        }
    }

    fn jsr(&mut self, call: &Call) -> Result<SKind> {
        let Some(first) = call.args.first() else {
            return err(call.pos, "JSR takes a routine name");
        };
        let name = first.text.trim();
        let Some(routine) = self.routines.iter().position(|r| r.eq_ignore_ascii_case(name)) else {
            return err(
                first.pos,
                format!("JSR: no routine '{name}' in this program (routines: {})", self.routines.join(", ")),
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
            return err(call.pos, format!("JSR: Input Count is {count}, {} inputs given", rest.len() - 1));
        }
        let inputs = rest[1..=count].iter().map(|a| self.value_arg(a)).collect::<Result<Vec<_>>>()?;
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

    fn gsv(&mut self, call: &Call) -> Result<SKind> {
        if call.args.len() != 4 {
            return err(call.pos, format!("GSV takes 4 operands (Class, Instance, Attribute, Dest), got {}", call.args.len()));
        }
        if !call.args[0].text.trim().eq_ignore_ascii_case("AXIS") {
            return err(call.args[0].pos, "GSV: the twin models the AXIS class only");
        }
        let name = call.args[1].text.trim();
        let axis = axis_named(self.ctx.task, name).ok_or_else(|| CompileError {
            pos: call.args[1].pos,
            message: format!("GSV: '{name}' is not an axis"),
        })?;
        let attr_name = call.args[2].text.trim();
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
            let names: Vec<&str> = AXIS_MEMBERS.iter().map(|a| a.0).chain(GSV_ATTRIBUTES.iter().map(|a| a.0)).collect();
            return err(call.args[2].pos, format!("GSV: AXIS attribute '{attr_name}' is not modelled (attributes: {})", names.join(", ")));
        };
        let (place, ty) = self.target_arg(&call.args[3])?;
        Ok(SKind::Gsv(axis, attribute, place, ty))
    }

    /// A motion instruction: operands resolved by the catalogue, then bound
    /// once now (handles created, operands checked) with placeholder values
    /// for what is computed at run time.
    fn motion(&mut self, call: &Call) -> Result<SKind> {
        let Some(instruction) = catalogue::find(&call.name) else {
            if catalogue::NOT_SIMULATED.iter().any(|m| m.eq_ignore_ascii_case(&call.name)) {
                return err(
                    call.pos,
                    format!(
                        "{} is a Logix motion instruction the twin does not simulate (it simulates: {})",
                        call.name.to_ascii_uppercase(),
                        catalogue::positional_mnemonics()
                    ),
                );
            }
            return err(call.pos, format!("unknown instruction '{}'", call.name));
        };
        if instruction.style != CallStyle::Positional {
            return err(
                call.pos,
                format!("{} is a function block: the twin runs it from [[program]] steps only", instruction.mnemonic),
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
        let mut args = Vec::with_capacity(call.args.len());
        let mut probe = Vec::with_capacity(call.args.len());
        for (spec, arg) in instruction.operands.iter().zip(&call.args) {
            let text = arg.text.trim();
            if spec.code_of(text).is_some() {
                args.push(MotionArg::Name(text.to_owned()));
                probe.push(crate::st::Expr::Ident(text.to_owned()));
                continue;
            }
            let Some(expr) = &arg.expr else {
                return err(
                    arg.pos,
                    format!("{} '{text}': not an operand (its words: {})", spec.name, spec.word_list()),
                );
            };
            if let ExprKind::Ref(r) = &expr.kind
                && let Some(t) = self.mem.resolve(Some(self.program), &r.name)
            {
                let info = self.mem.tags[t].clone();
                let named = matches!(info.kind, Kind::Axis | Kind::Planner(_))
                    || info.len.is_some() && r.path.is_empty();
                if named && r.path.is_empty() {
                    args.push(MotionArg::Name(info.name.clone()));
                    probe.push(crate::st::Expr::Ident(info.name.clone()));
                    continue;
                }
                if let (Some(_), [Access::Index(sub)]) = (info.len, r.path.as_slice()) {
                    let index = self.subscript(sub, r)?;
                    let at = match index.kind {
                        CKind::Const(v) => v.as_i64(),
                        _ => 0,
                    };
                    probe.push(crate::st::Expr::Index(Box::new(crate::st::Expr::Ident(info.name.clone())), at));
                    args.push(MotionArg::Element(info.name.clone(), index));
                    continue;
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
                    format!("{} '{text}': the operand's format is Immediate: write a constant or one of {}", spec.name, spec.word_list()),
                );
            }
            probe.push(operand_expr(spec.kind, constant_value.unwrap_or(Value::Int(0))));
            args.push(MotionArg::Value(value));
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

/// A DINT operation on two constants, computed once at compile time when
/// it cannot fault (no overflow, no division by zero); `None` leaves it to
/// the scan, which records the fault where the program runs it.
fn fold_dint(op: BinaryOp, a: i64, b: i64) -> Option<Value> {
    let fits = |r: i64| i32::try_from(r).is_ok().then_some(Value::Int(r));
    match op {
        BinaryOp::Add => fits(a + b),
        BinaryOp::Sub => fits(a - b),
        BinaryOp::Mul => fits(a * b),
        BinaryOp::Div if b != 0 => fits(a / b),
        BinaryOp::Mod if b != 0 => Some(Value::Int(a % b)),
        BinaryOp::Lt => Some(Value::Bool(a < b)),
        BinaryOp::Le => Some(Value::Bool(a <= b)),
        BinaryOp::Gt => Some(Value::Bool(a > b)),
        BinaryOp::Ge => Some(Value::Bool(a >= b)),
        BinaryOp::Eq => Some(Value::Bool(a == b)),
        BinaryOp::Ne => Some(Value::Bool(a != b)),
        _ => None,
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

fn constant(v: Value, ty: Ty) -> CExpr {
    CExpr {
        kind: CKind::Const(v),
        ty,
    }
}

/// A reference written back, for messages.
fn show(r: &Ref) -> String {
    let mut s = r.name.clone();
    for a in &r.path {
        match a {
            Access::Member(m) => {
                s.push('.');
                s.push_str(m);
            }
            Access::Bit(b) => s.push_str(&format!(".{b}")),
            Access::BitExpr(_) => s.push_str(".[…]"),
            Access::Index(_) => s.push_str("[…]"),
        }
    }
    s
}
