//! Expressions: the controller's arithmetic (module doc of [`super`]).

use super::Exec;
use crate::program::ir::{CExpr, CKind, Func};
use crate::program::types::{Ty, Value, wide_integer};
use crate::st::ast::BinaryOp;

impl Exec<'_> {
    /// Evaluates an expression (a subscript fault is recorded for the
    /// statement to stop at).
    pub fn eval(&mut self, e: &CExpr) -> Value {
        match &e.kind {
            CKind::Const(v) => *v,
            CKind::Slot(i) => self.mem.slots[*i],
            CKind::Load(p) => self.load(p),
            CKind::Neg(a) => {
                let v = self.eval(a);
                match e.ty {
                    Ty::Ulint => self.int_result(-unsigned(v), e.ty, "negation"),
                    Ty::Dint | Ty::Lint => self.int_result(-i128::from(v.as_i64()), e.ty, "negation"),
                    Ty::Real => Value::Real(f64::from(-v.as_f64() as f32)),
                    _ => Value::Real(-v.as_f64()),
                }
            }
            CKind::Not(a) => {
                let v = self.eval(a);
                match e.ty {
                    Ty::Bool => Value::Bool(!v.truthy()),
                    Ty::Dint => Value::Int(i64::from(!(v.as_i64() as i32))),
                    _ => Value::Int(!v.as_i64()),
                }
            }
            CKind::Binary(op, a, b, math) => {
                let x = self.leaf(a);
                let y = self.leaf(b);
                if a.ty == Ty::Ulint || b.ty == Ty::Ulint {
                    return self.ulint_operation(*op, (x, a.ty), (y, b.ty), *math);
                }
                self.operation(*op, x, y, *math)
            }
            CKind::Chain(first, links) => {
                let mut x = self.leaf(first);
                let mut x_ty = first.ty;
                for l in links {
                    let y = self.leaf(&l.operand);
                    x = if x_ty == Ty::Ulint || l.operand.ty == Ty::Ulint {
                        self.ulint_operation(l.op, (x, x_ty), (y, l.operand.ty), l.math)
                    } else {
                        self.operation(l.op, x, y, l.math)
                    };
                    x_ty = if l.op.is_comparison() { Ty::Bool } else { l.math };
                }
                x
            }
            CKind::Func(f, a) => {
                let v = self.eval(a);
                self.function(*f, v, a.ty, e.ty)
            }
            CKind::StrCmp(op, pair) => self.compare_strings(*op, &pair.0, &pair.1),
            CKind::Subscripts(parts, name) => {
                let mut linear = 0i64;
                let mut values = [0i64; 3];
                for (k, (sub, dim)) in parts.iter().enumerate() {
                    let i = self.leaf(sub).as_i64();
                    values[k] = i;
                    if !(0..*dim as i64).contains(&i) {
                        let written: Vec<String> = values[..=k].iter().map(i64::to_string).collect();
                        let f = self.raise(
                            4,
                            20,
                            format!(
                                "array subscript out of range: {name}[{}{}] (dimension {k} is 0..={})",
                                written.join(","),
                                if k + 1 < parts.len() { ",…" } else { "" },
                                dim - 1
                            ),
                        );
                        self.fail(f);
                        return Value::Int(-1);
                    }
                    linear = linear * *dim as i64 + i;
                }
                Value::Int(linear)
            }
        }
    }

    /// `x op y` computed in `math` (logic when it is `Bool`).
    #[inline(always)]
    fn operation(&mut self, op: BinaryOp, x: Value, y: Value, math: Ty) -> Value {
        if math == Ty::Bool {
            return Value::Bool(match op {
                BinaryOp::And => x.truthy() && y.truthy(),
                BinaryOp::Or => x.truthy() || y.truthy(),
                BinaryOp::Xor => x.truthy() != y.truthy(),
                _ => unreachable!("BOOL math is logic only"),
            });
        }
        self.binary(op, x, y, math)
    }

    pub(super) fn dint_result(&mut self, r: i64, what: &str) -> Value {
        if i32::try_from(r).is_ok() {
            Value::Int(r)
        } else {
            self.int_result(i128::from(r), Ty::Dint, what)
        }
    }

    /// [`Exec::eval`] with the leaves read in place.
    #[inline]
    pub(super) fn leaf(&mut self, e: &CExpr) -> Value {
        match &e.kind {
            CKind::Const(v) => *v,
            CKind::Slot(i) => self.mem.slots[*i],
            _ => self.eval(e),
        }
    }

    pub(super) fn int_result(&mut self, r: i128, ty: Ty, what: &str) -> Value {
        if ty == Ty::Ulint {
            if !(0..=i128::from(u64::MAX)).contains(&r) {
                self.overflow(&format!("{what} gives {r}, outside ULINT"));
            }
            // Its low 64 bits (two's complement: -1 is 2⁶⁴ − 1).
            return Value::Int(r as u64 as i64);
        }
        let (lo, hi) = if ty == Ty::Dint {
            (i128::from(i32::MIN), i128::from(i32::MAX))
        } else {
            (i128::from(i64::MIN), i128::from(i64::MAX))
        };
        if (lo..=hi).contains(&r) {
            Value::Int(r as i64)
        } else {
            self.overflow(&format!("{what} gives {r}, outside {}", ty.name()));
            Value::Int(if ty == Ty::Dint { i64::from(r as i32) } else { r as i64 })
        }
    }

    pub(super) fn real_result(&mut self, r: f64, ty: Ty, finite_in: bool) -> Value {
        let r = if ty == Ty::Real { f64::from(r as f32) } else { r };
        if finite_in && !r.is_finite() {
            self.overflow(&format!("the {} result is not finite", ty.name()));
        }
        Value::Real(r)
    }

    pub(super) fn binary(&mut self, op: BinaryOp, x: Value, y: Value, math: Ty) -> Value {
        use BinaryOp as B;
        if math == Ty::Dint {
            // Two 32-bit operands: every result fits 64 bits.
            let (a, b) = (x.as_i64(), y.as_i64());
            match op {
                B::Add => return self.dint_result(a + b, "addition"),
                B::Sub => return self.dint_result(a - b, "subtraction"),
                B::Mul => return self.dint_result(a * b, "multiplication"),
                B::Lt => return Value::Bool(a < b),
                B::Le => return Value::Bool(a <= b),
                B::Gt => return Value::Bool(a > b),
                B::Ge => return Value::Bool(a >= b),
                B::Eq => return Value::Bool(a == b),
                B::Ne => return Value::Bool(a != b),
                B::Mod if b != 0 => return Value::Int(a % b),
                _ => {}
            }
        }
        if math.is_integer() {
            let (a, b) = (i128::from(x.as_i64()), i128::from(y.as_i64()));
            let max = if math == Ty::Dint {
                i128::from(i32::MAX)
            } else {
                i128::from(i64::MAX)
            };
            return match op {
                B::Add => self.int_result(a + b, math, "addition"),
                B::Sub => self.int_result(a - b, math, "subtraction"),
                B::Mul => self.int_result(a * b, math, "multiplication"),
                B::Div | B::Mod if b == 0 => {
                    self.overflow("division by zero");
                    Value::Int(if op == B::Mod { 0 } else { (a.signum() * max) as i64 })
                }
                B::Div => self.int_result(a / b, math, "division"),
                B::Mod => Value::Int((a % b) as i64),
                B::And | B::Or | B::Xor => {
                    let r = match op {
                        B::And => a & b,
                        B::Or => a | b,
                        _ => a ^ b,
                    };
                    Value::Int(if math == Ty::Dint {
                        i64::from(r as i32)
                    } else {
                        r as i64
                    })
                }
                B::Pow => unreachable!("** computes in REAL"),
                _ => compare(op, a, b),
            };
        }
        // Operands are converted to the math type first (a DINT becomes a
        // REAL, rounded, before a REAL operation).
        let to_math = |v: Value| {
            if math == Ty::Real {
                f64::from(v.as_f64() as f32)
            } else {
                v.as_f64()
            }
        };
        let (a, b) = (to_math(x), to_math(y));
        let finite = a.is_finite() && b.is_finite();
        match op {
            B::Add => self.real_result(a + b, math, finite),
            B::Sub => self.real_result(a - b, math, finite),
            B::Mul => self.real_result(a * b, math, finite),
            B::Div => self.real_result(a / b, math, finite),
            B::Pow => self.real_result(a.powf(b), math, finite),
            B::Mod if b == 0.0 => {
                self.overflow("MOD by zero");
                Value::Real(0.0)
            }
            B::Mod => self.real_result(a - (a / b).trunc() * b, math, finite),
            B::And | B::Or | B::Xor => unreachable!("the compiler refuses bitwise REAL"),
            _ => compare(op, a, b),
        }
    }

    pub(super) fn function(&mut self, f: Func, v: Value, arg: Ty, result: Ty) -> Value {
        if f == Func::Abs && arg == Ty::Ulint {
            return v;
        }
        // A ULINT argument as the unsigned number its bits are.
        let v = if arg == Ty::Ulint && result.is_real() {
            Value::Real(unsigned(v) as f64)
        } else {
            v
        };
        if f == Func::Abs && arg.is_integer() {
            return self.int_result(i128::from(v.as_i64()).abs(), arg, "ABS");
        }
        if let Func::Frd | Func::Tod = f {
            return self.bcd(f == Func::Tod, v.as_i64());
        }
        let x = if result == Ty::Real || arg == Ty::Real {
            f64::from(v.as_f64() as f32)
        } else {
            v.as_f64()
        };
        let y = match f {
            Func::Abs => x.abs(),
            Func::Sqrt => x.abs().sqrt(),
            Func::Sin => x.sin(),
            Func::Cos => x.cos(),
            Func::Tan => x.tan(),
            Func::Asin => x.asin(),
            Func::Acos => x.acos(),
            Func::Atan => x.atan(),
            Func::Ln => x.ln(),
            Func::Log => x.log10(),
            Func::Deg => x.to_degrees(),
            Func::Rad => x.to_radians(),
            Func::Frd | Func::Tod => unreachable!("integers, above"),
            Func::Trunc => {
                let t = x.trunc();
                return if t.is_finite() {
                    self.int_result(wide_integer(t), Ty::Dint, "TRUNC")
                } else {
                    self.overflow("TRUNC of a value that is not finite");
                    Value::Int(0)
                };
            }
        };
        self.real_result(y, result, x.is_finite())
    }
}

impl Exec<'_> {
    /// TOD (`to`: an integer to BCD) or FRD (BCD to an integer), on 32
    /// bits (1756-RM003): a value TOD cannot write in eight digits, or an
    /// FRD source with a digit above 9, overflows (minor fault 4/4, `S:V`)
    /// and gives 0.
    fn bcd(&mut self, to: bool, v: i64) -> Value {
        if to {
            if !(0..=99_999_999).contains(&v) {
                self.overflow(&format!("TOD of {v}: BCD holds 0 to 99,999,999"));
                return Value::Int(0);
            }
            let (mut x, mut out, mut shift) = (v, 0i64, 0);
            while x > 0 {
                out |= (x % 10) << shift;
                x /= 10;
                shift += 4;
            }
            return Value::Int(i64::from(out as u32 as i32));
        }
        let bits = v as u32;
        let mut out = 0i64;
        for k in (0..8).rev() {
            let digit = i64::from((bits >> (4 * k)) & 0xF);
            if digit > 9 {
                self.overflow(&format!("FRD of 16#{bits:08X}: not BCD"));
                return Value::Int(0);
            }
            out = out * 10 + digit;
        }
        Value::Int(out)
    }
}

impl Exec<'_> {
    /// `x op y` where an operand is ULINT (`(value, type)` each): in
    /// ULINT math each operand is widened by its own type (a ULINT's bits
    /// unsigned, a signed type's value), and a result outside 0 to
    /// 2⁶⁴ − 1 records the overflow and keeps its low 64 bits (0 − 1 is
    /// 18446744073709551615); in REAL or LREAL math a ULINT operand is the
    /// unsigned number its bits are.
    fn ulint_operation(&mut self, op: BinaryOp, (x, x_ty): (Value, Ty), (y, y_ty): (Value, Ty), math: Ty) -> Value {
        use BinaryOp as B;
        let wide = |v: Value, ty: Ty| {
            if ty == Ty::Ulint {
                unsigned(v)
            } else {
                i128::from(v.as_i64())
            }
        };
        if math.is_real() {
            let real = |v: Value, ty: Ty| {
                if ty == Ty::Ulint {
                    Value::Real(unsigned(v) as f64)
                } else {
                    v
                }
            };
            return self.binary(op, real(x, x_ty), real(y, y_ty), math);
        }
        if math != Ty::Ulint {
            return self.operation(op, x, y, math);
        }
        let (a, b) = (wide(x, x_ty), wide(y, y_ty));
        match op {
            B::Add => self.int_result(a + b, math, "addition"),
            B::Sub => self.int_result(a - b, math, "subtraction"),
            B::Mul => self.int_result(a * b, math, "multiplication"),
            B::Div | B::Mod if b == 0 => {
                self.overflow("division by zero");
                Value::Int(if op == B::Div && a != 0 { -1 } else { 0 })
            }
            B::Div => self.int_result(a / b, math, "division"),
            B::Mod => self.int_result(a % b, math, "MOD"),
            B::And => Value::Int((a & b) as u64 as i64),
            B::Or => Value::Int((a | b) as u64 as i64),
            B::Xor => Value::Int((a ^ b) as u64 as i64),
            B::Pow => unreachable!("** computes in REAL"),
            _ => compare(op, a, b),
        }
    }
}

/// A ULINT's bits as the unsigned number they are.
fn unsigned(v: Value) -> i128 {
    i128::from(v.as_i64() as u64)
}

/// A comparison operator applied to two operands of one math type.
fn compare<T: PartialOrd>(op: BinaryOp, a: T, b: T) -> Value {
    Value::Bool(match op {
        BinaryOp::Lt => a < b,
        BinaryOp::Le => a <= b,
        BinaryOp::Gt => a > b,
        BinaryOp::Ge => a >= b,
        BinaryOp::Eq => a == b,
        BinaryOp::Ne => a != b,
        _ => unreachable!("comparisons only"),
    })
}
