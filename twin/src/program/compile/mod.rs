//! The one compiler: a parsed routine, a `[[program]]` step's call or a
//! scene expression compiled against tag memory and the planner — every
//! name resolved, every expression typed, every instruction's operands
//! bound by its catalogue entry — so that errors name the file, line and
//! column at load, with the source line, a caret and a suggestion, and
//! the interpreter only evaluates what comes out.

use super::bindings::Env;
use super::ir::{CExpr, CKind, CStmt, Func, Link, Place, SKind};
use super::memory::Memory;
use super::types::{DataType, Ty, Value};
use crate::scene::Dialect;
use crate::source::{Diagnostic, Span, diag};
use crate::st::ast::{Access, BinaryOp, Expr, ExprKind, Ref, Stmt, StmtKind, UnaryOp};

/// A compile error: a diagnostic pointing into the file.
pub type Error = Box<Diagnostic>;

/// A compile result.
pub type Result<T> = std::result::Result<T, Error>;

pub mod aoi;
mod call;
pub mod ladder;
mod motion;
mod reference;
pub mod scene;
mod strings;

/// What a routine, a call or an expression is compiled against.
pub struct Compiler<'c, 'e, 's> {
    /// Tag memory (names and layout).
    pub mem: &'c Memory,
    /// The program the text belongs to (its tags shadow the controller's);
    /// `None` for the controller scope (a step, a trace tag, a `when`).
    pub program: Option<&'c str>,
    /// The program's routines, for `JSR`.
    pub routines: &'c [String],
    /// The text's dialect.
    pub dialect: Dialect,
    /// The planner binding (handles are created on first use).
    pub env: &'c mut Env<'e, 's>,
    /// Whether the text is a scanned routine (its instructions' rungs are
    /// the routine's) rather than a one-shot `[[program]]` step.
    pub scanned: bool,
    /// Trace columns the text may also name (an expectation's); empty
    /// for a program's texts.
    pub columns: &'c [super::ir::Column],
    /// Whether the text is a ladder routine.
    pub ladder: bool,
    /// Slots a ladder display operand sets at load (a timer's Preset …).
    pub init: Vec<(usize, Value, Span)>,
    /// The rungs of this routine `[trace] rungs` names, with the slot
    /// each one's condition-out is written to.
    pub traced_rungs: Vec<(u32, usize)>,
    /// The Add-On Instruction routines this compiler's call sites added,
    /// in order; the first is the program's routine [`Compiler::aoi_base`].
    pub aoi_routines: Vec<super::ir::AoiRoutine>,
    /// The program's routine index the next added routine takes, less
    /// those this compiler added.
    pub aoi_base: usize,
    /// The Add-On Instructions being expanded, outermost first.
    aoi_stack: Vec<String>,
    /// Loop nesting (for `EXIT`).
    loops: usize,
}

impl Compiler<'_, '_, '_> {
    /// An error at `span`: `message`, and `label` under the caret.
    pub(super) fn error(&self, span: Span, message: impl Into<String>, label: impl Into<String>) -> Error {
        Box::new(self.env.files.error(span, message, label))
    }
}

/// An error at `span` of the compiler's files.
pub(super) fn err<T>(c: &Compiler<'_, '_, '_>, span: Span, message: impl Into<String>) -> Result<T> {
    Err(c.error(span, message, ""))
}

/// Adds `did you mean 'X'?` for the known name nearest to `name`.
pub(super) fn suggest<'a>(d: Error, name: &str, known: impl IntoIterator<Item = &'a str>) -> Error {
    match diag::nearest(name, known) {
        Some(n) => Box::new(d.with_help(format!("did you mean '{n}'?"))),
        None => d,
    }
}

impl<'c, 'e, 's> Compiler<'c, 'e, 's> {
    /// A compiler for a routine of `program` (`None`: the controller
    /// scope), `scanned` when it is a routine a task scans.
    pub fn new(
        mem: &'c Memory,
        program: Option<&'c str>,
        routines: &'c [String],
        dialect: Dialect,
        env: &'c mut Env<'e, 's>,
        scanned: bool,
    ) -> Self {
        Compiler {
            mem,
            program,
            routines,
            dialect,
            env,
            scanned,
            columns: &[],
            ladder: false,
            init: Vec::new(),
            traced_rungs: Vec::new(),
            aoi_routines: Vec::new(),
            aoi_base: routines.len(),
            aoi_stack: Vec::new(),
            loops: 0,
        }
    }

    /// Compiles statements.
    ///
    /// # Errors
    /// The first compile [`Error`].
    pub fn block(&mut self, stmts: &[Stmt]) -> Result<Vec<CStmt>> {
        let mut out = Vec::with_capacity(stmts.len());
        for s in stmts.iter().filter(|s| s.kind != StmtKind::Empty) {
            out.push(self.stmt(s)?);
        }
        out.shrink_to_fit();
        Ok(out)
    }

    fn stmt(&mut self, s: &Stmt) -> Result<CStmt> {
        let kind = match &s.kind {
            StmtKind::Assign {
                target,
                value,
                retentive,
            } => {
                let (target, ty) = self.writable(target)?;
                let value = ulint_as_real(self.expr(value)?, ty);
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
                    return Err(self.error(
                        selector.span,
                        format!("CASE selector must be an integer, got {}", sel.ty.name()),
                        sel.ty.name(),
                    ));
                }
                let mut out = Vec::with_capacity(arms.len());
                for (labels, body) in arms {
                    out.push((labels.clone(), self.block(body)?));
                }
                SKind::Case(sel, out, self.block(otherwise)?)
            }
            StmtKind::For { .. } | StmtKind::While { .. } | StmtKind::Repeat { .. } => self.loop_stmt(&s.kind)?,
            StmtKind::Exit if self.loops == 0 => return err(self, s.span, "EXIT outside FOR, WHILE or REPEAT"),
            StmtKind::Exit => SKind::Exit,
            StmtKind::Call(call) => self.call(call)?,
            StmtKind::Empty => unreachable!("filtered"),
        };
        Ok(CStmt {
            kind,
            line: self.env.files.line(s.span) as u32,
        })
    }

    /// FOR, WHILE and REPEAT (EXIT is allowed inside them).
    fn loop_stmt(&mut self, kind: &StmtKind) -> Result<SKind> {
        Ok(match kind {
            StmtKind::For {
                counter,
                from,
                to,
                by,
                body,
            } => {
                let (place, ty) = self.writable(counter)?;
                if !ty.is_integer() {
                    return Err(self.error(
                        counter.span,
                        format!("FOR counter must be an integer tag, got {}", ty.name()),
                        ty.name(),
                    ));
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
            _ => unreachable!("loops only"),
        })
    }

    /// A condition: BOOL (or an integer, non-zero is TRUE).
    ///
    /// # Errors
    /// A REAL expression, pointed at.
    pub fn condition(&mut self, e: &Expr) -> Result<CExpr> {
        let c = self.expr(e)?;
        if c.ty == Ty::Bool || c.ty.is_integer() {
            Ok(c)
        } else {
            Err(Box::new(
                (*self.error(
                    e.span,
                    format!("a condition must be BOOL, got {}", c.ty.name()),
                    format!("this is {}", c.ty.name()),
                ))
                .with_help("compare it, e.g. X > 0.0"),
            ))
        }
    }

    fn integer(&mut self, e: &Expr) -> Result<CExpr> {
        let c = self.expr(e)?;
        if c.ty.is_integer() || c.ty == Ty::Bool {
            Ok(c)
        } else {
            Err(self.error(
                e.span,
                format!("expected an integer expression, got {}", c.ty.name()),
                c.ty.name(),
            ))
        }
    }

    /// Compiles an expression.
    ///
    /// # Errors
    /// A compile [`Error`] at the offending part.
    pub fn expr(&mut self, e: &Expr) -> Result<CExpr> {
        Ok(match &e.kind {
            ExprKind::Int(i) => match i64::try_from(*i) {
                Ok(v) if i32::try_from(v).is_ok() => constant(Value::Int(v), Ty::Dint),
                Ok(v) => constant(Value::Int(v), Ty::Lint),
                // Past LINT, a ULINT (its bits).
                Err(_) => match u64::try_from(*i) {
                    Ok(v) => constant(Value::Int(v as i64), Ty::Ulint),
                    Err(_) => return err(self, e.span, format!("integer literal {i} is out of range (64 bits)")),
                },
            },
            ExprKind::Real(x) => constant(Value::Real(f64::from(*x as f32)), Ty::Real),
            ExprKind::Bool(b) => constant(Value::Bool(*b), Ty::Bool),
            ExprKind::Ref(r) => {
                let (place, ty) = self.place(r)?;
                load(place, ty)
            }
            ExprKind::Unary(UnaryOp::Neg, a) => {
                let a = self.expr(a)?;
                if a.ty == Ty::Bool {
                    return err(self, e.span, "'-' needs a number, got BOOL");
                }
                let ty = a.ty;
                // A negative literal is a constant (an Immediate operand).
                match a.kind {
                    // (A DINT -(-2147483648), `-16#8000_0000`, overflows:
                    // left to the scan, which records it.)
                    CKind::Const(Value::Int(i))
                        if ty != Ty::Ulint && i != i64::MIN && (ty != Ty::Dint || i != i64::from(i32::MIN)) =>
                    {
                        constant(Value::Int(-i), ty)
                    }
                    CKind::Const(Value::Real(x)) => constant(Value::Real(-x), ty),
                    _ => CExpr {
                        kind: CKind::Neg(Box::new(a)),
                        ty,
                    },
                }
            }
            ExprKind::Unary(UnaryOp::Not, a) => {
                let a = self.expr(a)?;
                if a.ty.is_real() {
                    return err(
                        self,
                        e.span,
                        format!("NOT needs BOOL or an integer, got {}", a.ty.name()),
                    );
                }
                let ty = a.ty;
                CExpr {
                    kind: CKind::Not(Box::new(a)),
                    ty,
                }
            }
            ExprKind::Binary(first, rest) => match self.string_comparison(first, rest)? {
                Some(c) => c,
                None => self.chain(first, rest)?,
            },
            ExprKind::Function(name, name_span, args) => {
                let Some(f) = Func::parse(name) else {
                    let d = self.error(
                        *name_span,
                        format!("unknown function '{name}' (functions: {})", Func::NAMES.join(", ")),
                        "not a function",
                    );
                    return Err(suggest(d, name, Func::NAMES));
                };
                if args.len() != 1 {
                    return err(
                        self,
                        e.span,
                        format!("{} takes 1 argument, got {}", name.to_ascii_uppercase(), args.len()),
                    );
                }
                let a = self.expr(&args[0])?;
                if a.ty == Ty::Bool {
                    return err(
                        self,
                        args[0].span,
                        format!("{} needs a number, got BOOL", name.to_ascii_uppercase()),
                    );
                }
                if matches!(f, Func::Frd | Func::Tod) && !a.ty.is_integer() {
                    return err(
                        self,
                        args[0].span,
                        format!("{} converts an integer, got {}", name.to_ascii_uppercase(), a.ty.name()),
                    );
                }
                let ty = match f {
                    Func::Abs => a.ty,
                    Func::Trunc | Func::Frd | Func::Tod => Ty::Dint,
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

    /// An operator chain, left to right: each operation typed from the
    /// value so far and its operand, constants folded while the chain
    /// starts with them.
    fn chain(&mut self, first: &Expr, rest: &[(BinaryOp, Expr)]) -> Result<CExpr> {
        let mut acc = self.expr(first)?;
        let mut acc_span = first.span;
        let mut head: Option<CExpr> = None;
        let mut links: Vec<Link> = Vec::with_capacity(rest.len());
        for (op, b) in rest {
            let y = self.expr(b)?;
            let (math, result) = self.operation_types(*op, acc.ty, y.ty, acc_span, b.span)?;
            acc_span = acc_span.to(b.span);
            if head.is_none()
                && let (CKind::Const(p), CKind::Const(q), Ty::Dint) = (&acc.kind, &y.kind, math)
                && let Some(v) = fold_dint(*op, p.as_i64(), q.as_i64())
            {
                acc = constant(v, result);
                continue;
            }
            if head.is_none() {
                head = Some(std::mem::replace(&mut acc, constant(Value::Int(0), result)));
            }
            acc.ty = result;
            links.push(Link {
                op: *op,
                operand: y,
                math,
            });
        }
        let Some(first) = head else {
            return Ok(acc);
        };
        let kind = if links.len() == 1 {
            let Link { op, operand, math } = links.pop().expect("one link");
            CKind::Binary(op, Box::new(first), Box::new(operand), math)
        } else {
            CKind::Chain(Box::new(first), links.into_boxed_slice())
        };
        Ok(CExpr { kind, ty: acc.ty })
    }

    /// The type `x op y` computes in and the type of its result.
    fn operation_types(&mut self, op: BinaryOp, x: Ty, y: Ty, a: Span, b: Span) -> Result<(Ty, Ty)> {
        let span = a.to(b);
        let numeric = |t: Ty| if t == Ty::Bool { Ty::Dint } else { t };
        let arith = |x: Ty, y: Ty| {
            let (x, y) = (numeric(x), numeric(y));
            if x == Ty::Lreal || y == Ty::Lreal {
                Ty::Lreal
            } else if x == Ty::Real || y == Ty::Real {
                if matches!(x, Ty::Lint | Ty::Ulint) || matches!(y, Ty::Lint | Ty::Ulint) {
                    Ty::Lreal
                } else {
                    Ty::Real
                }
            } else if x == Ty::Ulint || y == Ty::Ulint {
                Ty::Ulint
            } else if x == Ty::Lint || y == Ty::Lint {
                Ty::Lint
            } else {
                Ty::Dint
            }
        };
        let (math, result) = match op {
            BinaryOp::Pow => {
                let m = if matches!(arith(x, y), Ty::Lreal | Ty::Lint | Ty::Ulint) {
                    Ty::Lreal
                } else {
                    Ty::Real
                };
                (m, m)
            }
            BinaryOp::Mul | BinaryOp::Div | BinaryOp::Mod | BinaryOp::Add | BinaryOp::Sub => {
                let m = arith(x, y);
                (m, m)
            }
            BinaryOp::Lt | BinaryOp::Le | BinaryOp::Gt | BinaryOp::Ge | BinaryOp::Eq | BinaryOp::Ne => {
                if (x == Ty::Bool) != (y == Ty::Bool) && !(matches!(op, BinaryOp::Eq | BinaryOp::Ne)) {
                    return err(self, span, format!("'{}' compares numbers, got BOOL", op.symbol()));
                }
                let m = if x == Ty::Bool && y == Ty::Bool {
                    Ty::Dint
                } else {
                    arith(x, y)
                };
                (m, Ty::Bool)
            }
            BinaryOp::And | BinaryOp::Or | BinaryOp::Xor => {
                if x.is_real() || y.is_real() {
                    let (real, ty) = if x.is_real() { (a, x) } else { (b, y) };
                    let d = self.error(
                        real,
                        format!("{} needs BOOL or integer operands, got {}", op.symbol(), ty.name()),
                        format!("this is {}", ty.name()),
                    );
                    return Err(Box::new(d.with_help(format!(
                        "{} works on bits: make it an integer first (TRUNC(x), or assign it to a DINT, which rounds)",
                        op.symbol()
                    ))));
                }
                if x == Ty::Bool && y == Ty::Bool {
                    (Ty::Bool, Ty::Bool)
                } else {
                    let m = arith(x, y);
                    (m, m)
                }
            }
        };
        Ok((math, result))
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

/// A read of `place`, of type `ty` (a slot read in place).
pub(super) fn load(place: Place, ty: crate::program::types::DataType) -> CExpr {
    let kind = match place {
        Place::Slot(i) => CKind::Slot(i),
        place => CKind::Load(Box::new(place)),
    };
    CExpr { kind, ty: ty.math() }
}

/// A ULINT value written to a REAL or LREAL: converted as the unsigned
/// number its bits are (`value + 0.0` in LREAL; storing reads a value's
/// integer as signed). Any other value as it is.
pub(super) fn ulint_as_real(value: CExpr, to: DataType) -> CExpr {
    if value.ty != Ty::Ulint || !matches!(to, DataType::Real | DataType::Lreal) {
        return value;
    }
    CExpr {
        kind: CKind::Binary(
            BinaryOp::Add,
            Box::new(value),
            Box::new(constant(Value::Real(0.0), Ty::Lreal)),
            Ty::Lreal,
        ),
        ty: Ty::Lreal,
    }
}

pub(super) fn constant(v: Value, ty: Ty) -> CExpr {
    CExpr {
        kind: CKind::Const(v),
        ty,
    }
}

/// A reference written back, for messages.
pub(super) fn show(r: &Ref) -> String {
    let mut s = r.name.clone();
    for a in &r.path {
        match a {
            Access::Member(m, _) => {
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

#[cfg(test)]
mod tests;
