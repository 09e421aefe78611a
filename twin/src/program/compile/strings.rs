//! String operands: the string instructions' calls (1756-RM003, ASCII
//! string and ASCII conversion instructions) and string comparisons.

use super::{Compiler, Result, err, show};
use crate::program::ir::{CExpr, CKind, SKind, StrArgs, StrAt, StrOp};
use crate::program::layout::Elem;
use crate::program::types::{DataType, Ty};
use crate::st::ast::{Arg, BinaryOp, Call, Expr, ExprKind, Ref};

impl Compiler<'_, '_, '_> {
    /// `CONCAT`, `MID`, `FIND`, `INSERT`, `DELETE`, `UPPER`, `LOWER`,
    /// `DTOS`, `STOD`, `RTOS`, `STOR`, with RM003's operand order.
    pub(super) fn string_instruction(&mut self, call: &Call, op: StrOp, upper: &str) -> Result<SKind> {
        let a = &call.args;
        let args = match op {
            StrOp::Concat => {
                self.argc(call, upper, 3)?;
                StrArgs::Join(
                    self.string_arg(&a[0], upper, "Source A")?,
                    self.string_arg(&a[1], upper, "Source B")?,
                    None,
                    self.string_dest(&a[2], upper)?,
                )
            }
            StrOp::Insert => {
                self.argc(call, upper, 4)?;
                StrArgs::Join(
                    self.string_arg(&a[0], upper, "Source A")?,
                    self.string_arg(&a[1], upper, "Source B")?,
                    Some(self.integer_arg(&a[2])?),
                    self.string_dest(&a[3], upper)?,
                )
            }
            StrOp::Mid | StrOp::Delete => {
                self.argc(call, upper, 4)?;
                StrArgs::Cut(
                    self.string_arg(&a[0], upper, "Source")?,
                    self.integer_arg(&a[1])?,
                    self.integer_arg(&a[2])?,
                    self.string_dest(&a[3], upper)?,
                )
            }
            StrOp::Find => {
                self.argc(call, upper, 4)?;
                let source = self.string_arg(&a[0], upper, "Source")?;
                let search = self.string_arg(&a[1], upper, "Search")?;
                let start = self.integer_arg(&a[2])?;
                let (place, ty) = self.number_dest(&a[3], upper, "Result")?;
                StrArgs::Find(source, search, start, place, ty)
            }
            StrOp::Upper | StrOp::Lower => {
                self.argc(call, upper, 2)?;
                StrArgs::Case(
                    self.string_arg(&a[0], upper, "Source")?,
                    self.string_dest(&a[1], upper)?,
                )
            }
            StrOp::Dtos | StrOp::Rtos => {
                self.argc(call, upper, 2)?;
                let value = self.value_arg(&a[0])?;
                let want_integer = op == StrOp::Dtos;
                if value.ty == Ty::Bool || want_integer && !value.ty.is_integer() {
                    let want = if want_integer { "SINT, INT or DINT" } else { "REAL" };
                    return err(
                        self,
                        a[0].span,
                        format!("{upper} Source: expected {want}, got {}", value.ty.name()),
                    );
                }
                StrArgs::FromNumber(value, self.string_dest(&a[1], upper)?)
            }
            StrOp::Stod | StrOp::Stor => {
                self.argc(call, upper, 2)?;
                let source = self.string_arg(&a[0], upper, "Source")?;
                let (place, ty) = self.number_dest(&a[1], upper, "Dest")?;
                let fits = if op == StrOp::Stod {
                    ty.is_integer()
                } else {
                    matches!(ty, DataType::Real | DataType::Lreal)
                };
                if !fits {
                    let want = if op == StrOp::Stod {
                        "an integer (SINT, INT, DINT …)"
                    } else {
                        "a REAL"
                    };
                    return err(
                        self,
                        a[1].span,
                        format!(
                            "{upper} Dest: expected {want}, got {} '{}'",
                            ty.name(),
                            a[1].text.trim()
                        ),
                    );
                }
                StrArgs::ToNumber(source, place, ty)
            }
        };
        Ok(SKind::Str(op, Box::new(args)))
    }

    /// A numeric tag an instruction writes.
    fn number_dest(&mut self, arg: &Arg, upper: &str, what: &str) -> Result<(crate::program::ir::Place, DataType)> {
        let (place, ty) = self.target_arg(arg)?;
        if ty == DataType::Bool {
            return err(
                self,
                arg.span,
                format!("{upper} {what}: expected a number, got BOOL '{}'", arg.text.trim()),
            );
        }
        Ok((place, ty))
    }

    fn string_arg(&mut self, arg: &Arg, upper: &str, what: &str) -> Result<StrAt> {
        match &arg.expr {
            Some(Expr {
                kind: ExprKind::Ref(r), ..
            }) => self.string_at(r, &format!("{upper} {what}")),
            _ => err(
                self,
                arg.span,
                format!("{upper} {what}: expected a string tag, got '{}'", arg.text.trim()),
            ),
        }
    }

    fn string_dest(&mut self, arg: &Arg, upper: &str) -> Result<StrAt> {
        if let Some(Expr {
            kind: ExprKind::Ref(r), ..
        }) = &arg.expr
        {
            self.refuse_constant(r)?;
        }
        self.string_arg(arg, upper, "Dest")
    }

    /// A string tag, element or member: where its `LEN` is and its `DATA`
    /// length.
    pub(super) fn string_at(&mut self, r: &Ref, what: &str) -> Result<StrAt> {
        let r = match self.qualified(r) {
            Some(q) => q,
            None => r.clone(),
        };
        let t = self.tag(&r)?;
        let info = self.mem.tags[t].clone();
        if info.elem().is_none() {
            return err(
                self,
                r.span,
                format!(
                    "{what}: '{}' is a {} tag, expected a string type",
                    show(&r),
                    info.type_name
                ),
            );
        }
        let mut path = r.path.iter();
        let at = self.locate(&r, &info, &mut path)?;
        let string = match at.elem {
            Elem::User(id) if path.as_slice().is_empty() && at.array.is_none() => self.mem.layouts.get(id).string,
            _ => None,
        };
        let Some(capacity) = string else {
            return err(
                self,
                r.span,
                format!(
                    "{what}: '{}' is not a string (STRING or a data type with string_length)",
                    show(&r)
                ),
            );
        };
        Ok(StrAt {
            base: info.base + at.slot,
            terms: at.terms.into_boxed_slice(),
            capacity,
            name: show(&r),
        })
    }

    /// A `[trace] tags` reference that names a whole string: its operand
    /// (`None` when it is not a string).
    pub fn traced_string(&mut self, e: &Expr) -> Option<Result<StrAt>> {
        let ExprKind::Ref(r) = &e.kind else { return None };
        if !self.is_string(r) {
            return None;
        }
        Some(self.string_at(r, "a traced string"))
    }

    /// `A = B` and the other comparisons of two strings, `None` when `e`
    /// is not one.
    pub(super) fn string_comparison(&mut self, first: &Expr, rest: &[(BinaryOp, Expr)]) -> Result<Option<CExpr>> {
        let [(op, second)] = rest else { return Ok(None) };
        let comparison = matches!(
            op,
            BinaryOp::Eq | BinaryOp::Ne | BinaryOp::Lt | BinaryOp::Le | BinaryOp::Gt | BinaryOp::Ge
        );
        let (ExprKind::Ref(a), ExprKind::Ref(b)) = (&first.kind, &second.kind) else {
            return Ok(None);
        };
        if !comparison || !(self.is_string(a) || self.is_string(b)) {
            return Ok(None);
        }
        let what = format!("'{}' compares", op.symbol());
        let x = self.string_at(a, &what)?;
        let y = self.string_at(b, &what)?;
        Ok(Some(CExpr {
            kind: CKind::StrCmp(*op, Box::new((x, y))),
            ty: Ty::Bool,
        }))
    }

    /// Whether a reference names a whole string (a cheap look: a tag of a
    /// data type whose path ends on a string type).
    fn is_string(&mut self, r: &Ref) -> bool {
        let r = self.qualified(r).unwrap_or_else(|| r.clone());
        let Some(t) = self.resolve(&r.name) else { return false };
        let info = self.mem.tags[t].clone();
        if !matches!(info.kind, crate::program::memory::Kind::User(_)) {
            return false;
        }
        let mut path = r.path.iter();
        match self.locate(&r, &info, &mut path) {
            Ok(at) => {
                path.as_slice().is_empty()
                    && at.array.is_none()
                    && matches!(at.elem, Elem::User(id) if self.mem.layouts.get(id).string.is_some())
            }
            Err(_) => false,
        }
    }
}
