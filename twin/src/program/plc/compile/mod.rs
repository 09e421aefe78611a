//! Compiles a parsed routine against tag memory and the planner: every
//! name resolved, every expression typed, every instruction's operands
//! checked, so that errors name the routine file, line and column at load.

use super::ir::{CExpr, CKind, CStmt, Func, Place, SKind};
use super::memory::Memory;
use super::types::{Ty, Value};
use crate::program::FbBinding;
use crate::program::bind::LogixContext;
use crate::scene::Dialect;
use crate::st::ast::{Access, BinaryOp, Expr, ExprKind, Ref, Stmt, StmtKind, UnaryOp};
use crate::st::lex::Pos;

/// A compile error: where, and what is wrong.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CompileError {
    /// Where.
    pub pos: Pos,
    /// What.
    pub message: String,
}

type Result<T> = std::result::Result<T, CompileError>;

mod call;
mod reference;

pub use call::{named_call, operand_expr, value_expr};

pub(super) fn err<T>(pos: Pos, message: impl Into<String>) -> Result<T> {
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

    /// Compiles statements.
    ///
    /// # Errors
    /// The first [`CompileError`].
    pub fn block(&mut self, stmts: &[Stmt]) -> Result<Vec<CStmt>> {
        stmts
            .iter()
            .filter(|s| s.kind != StmtKind::Empty)
            .map(|s| self.stmt(s))
            .collect()
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
                    return err(
                        selector.pos,
                        format!("CASE selector must be an integer, got {}", sel.ty.name()),
                    );
                }
                let mut out = Vec::with_capacity(arms.len());
                for (labels, body) in arms {
                    out.push((labels.clone(), self.block(body)?));
                }
                SKind::Case(sel, out, self.block(otherwise)?)
            }
            StmtKind::For { .. } | StmtKind::While { .. } | StmtKind::Repeat { .. } => self.loop_stmt(&s.kind)?,
            StmtKind::Exit if self.loops == 0 => return err(s.pos, "EXIT outside FOR, WHILE or REPEAT"),
            StmtKind::Exit => SKind::Exit,
            StmtKind::Call(call) => self.call(call)?,
            StmtKind::Empty => unreachable!("filtered"),
        };
        Ok(CStmt { kind, line: s.pos.line })
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
                    return err(
                        counter.pos,
                        format!("FOR counter must be an integer tag, got {}", ty.name()),
                    );
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
                    return err(
                        e.pos,
                        format!("{} takes 1 argument, got {}", name.to_ascii_uppercase(), args.len()),
                    );
                }
                let a = self.expr(&args[0])?;
                if a.ty == Ty::Bool {
                    return err(
                        args[0].pos,
                        format!("{} needs a number, got BOOL", name.to_ascii_uppercase()),
                    );
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
                if x == Ty::Lint || y == Ty::Lint {
                    Ty::Lreal
                } else {
                    Ty::Real
                }
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
                let m = if x.ty == Ty::Bool && y.ty == Ty::Bool {
                    Ty::Dint
                } else {
                    arith(x.ty, y.ty)
                };
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
