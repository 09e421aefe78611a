//! Seeded random Structured Text programs of arithmetic and control flow,
//! each compiled into a [`Sandbox`] and scanned once; every tag's final
//! value and the minor-fault count are compared with a reference
//! evaluator written here, independently of the engine, from the language
//! rules (operator precedence, the arithmetic and conversion rules, the
//! statement semantics).
//!
//! Program `n` (0 ≤ n < [`PROGRAMS`]) is generated from
//! `ChaCha8Rng::seed_from_u64(SEED_BASE + n)`. A generated program whose
//! reference run would execute more than [`BUDGET`] statements (and loop
//! tests) is drawn again from the same generator, so every index yields a
//! program. `ST_RANDOM_ONLY=n` runs program `n` alone and prints it;
//! `ST_RANDOM_PROGRAMS=k` runs programs `0..k`.
//!
//! A program is 3 to 15 statements (a few more with loop counters), at
//! most three compound statements deep; every loop ends within a few
//! passes (FOR bounds are small or the program is drawn again; WHILE and
//! REPEAT carry a pass counter `U`/`V`/`W` in their condition). On a
//! disagreement the test prints the first failing programs in full, then
//! each of the first few reduced greedily (statements removed, operands
//! simplified) to a small program with the same disagreement.
//!
//! Choices the rules leave open, taken here: a real converted to an
//! integer whose rounded value is outside the target's range wraps that
//! value exactly (so ±3.4e38, a multiple of 2^104, wraps to 0); `AND`/`OR`
//! evaluate both operands; `a ** -b ** c` is `(a ** -b) ** c` (the right
//! operand of `**` is a signed primary, and `**` groups left to right);
//! `-2147483648` is unary minus on the LINT literal 2147483648; `SQRT`,
//! `SIN`, `COS`, `TAN`, `ATAN` take a DINT or REAL argument, convert it
//! to REAL, compute in double precision and round to REAL, without a
//! fault.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::cmp::Ordering;
use std::time::Instant;
use twin::program::{sandbox::Sandbox, types::Value};

/// The seed of program `n` is `SEED_BASE + n`.
const SEED_BASE: u64 = 0x5747_0000_0000;
/// Programs run by default.
const PROGRAMS: u64 = 60_000;
/// Statements plus loop tests a reference run may execute (the engine's
/// period of 4 ms is 4000 nominal statements, its watchdog 500,000).
const BUDGET: u32 = 1_500;
/// Failing programs printed in full (`ST_RANDOM_SHOW=k` to change).
const SHOWN: usize = 2;
/// Failing programs reduced (to a smaller program with the same
/// disagreement) and printed, the distinct reductions once each
/// (`ST_RANDOM_REDUCE=k` to change).
const REDUCED: usize = 16;

// ---------------------------------------------------------------- tags

/// A tag's declared type.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Tt {
    Dint,
    Lint,
    Real,
    Bool,
}

impl Tt {
    fn name(self) -> &'static str {
        match self {
            Tt::Dint => "DINT",
            Tt::Lint => "LINT",
            Tt::Real => "REAL",
            Tt::Bool => "BOOL",
        }
    }
}

/// The scalar tags; `Arr` (DINT[8]) is apart.
const TAGS: [(&str, Tt); 18] = [
    ("A", Tt::Dint),
    ("B", Tt::Dint),
    ("C", Tt::Dint),
    ("D", Tt::Dint),
    ("E", Tt::Dint),
    ("F", Tt::Dint),
    ("X", Tt::Real),
    ("Y", Tt::Real),
    ("Z", Tt::Real),
    ("P", Tt::Bool),
    ("Q", Tt::Bool),
    ("L", Tt::Lint),
    // FOR counters, by FOR nesting.
    ("I", Tt::Dint),
    ("J", Tt::Dint),
    ("K", Tt::Dint),
    // WHILE / REPEAT pass counters, by nesting.
    ("U", Tt::Dint),
    ("V", Tt::Dint),
    ("W", Tt::Dint),
];
const DINTS: [usize; 6] = [0, 1, 2, 3, 4, 5];
const REALS: [usize; 3] = [6, 7, 8];
const BOOLS: [usize; 2] = [9, 10];
const LINT: usize = 11;
const FOR_COUNTERS: [usize; 3] = [12, 13, 14];
const GUARDS: [usize; 3] = [15, 16, 17];
const READ_ONLY: [usize; 6] = [12, 13, 14, 15, 16, 17];
const ARR_LEN: usize = 8;

// ---------------------------------------------------------------- syntax

#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Op {
    Pow,
    Mul,
    Div,
    Mod,
    Add,
    Sub,
    Lt,
    Le,
    Gt,
    Ge,
    Eq,
    Ne,
    And,
    Xor,
    Or,
}

impl Op {
    /// Precedence level, 1 the tightest (primaries), as in the rules.
    fn level(self) -> u8 {
        match self {
            Op::Pow => 2,
            Op::Mul | Op::Div | Op::Mod => 4,
            Op::Add | Op::Sub => 5,
            Op::Lt | Op::Le | Op::Gt | Op::Ge => 6,
            Op::Eq | Op::Ne => 7,
            Op::And => 8,
            Op::Xor => 9,
            Op::Or => 10,
        }
    }

    fn text(self) -> &'static str {
        match self {
            Op::Pow => "**",
            Op::Mul => "*",
            Op::Div => "/",
            Op::Mod => "MOD",
            Op::Add => "+",
            Op::Sub => "-",
            Op::Lt => "<",
            Op::Le => "<=",
            Op::Gt => ">",
            Op::Ge => ">=",
            Op::Eq => "=",
            Op::Ne => "<>",
            Op::And => "AND",
            Op::Xor => "XOR",
            Op::Or => "OR",
        }
    }
}

#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Func {
    Abs,
    Sqrt,
    Trunc,
    Sin,
    Cos,
    Tan,
    Atan,
}

impl Func {
    fn name(self) -> &'static str {
        match self {
            Func::Abs => "ABS",
            Func::Sqrt => "SQRT",
            Func::Trunc => "TRUNC",
            Func::Sin => "SIN",
            Func::Cos => "COS",
            Func::Tan => "TAN",
            Func::Atan => "ATAN",
        }
    }
}

/// An expression as generated; literals keep the text they are written
/// with.
#[derive(Clone, Debug)]
enum Ex {
    /// A non-negative integer literal.
    Int(i64, String),
    /// A real literal: its value rounded to REAL, and its text.
    Real(f32, String),
    Bool(bool),
    Tag(usize),
    /// `Arr[subscript]`.
    Arr(Box<Ex>),
    Neg(Box<Ex>),
    Not(Box<Ex>),
    /// Redundant parentheses.
    Paren(Box<Ex>),
    Call(Func, Box<Ex>),
    Bin(Op, Box<Ex>, Box<Ex>),
}

#[derive(Clone, Debug)]
enum Target {
    Tag(usize),
    Arr(Ex),
}

#[derive(Clone, Copy, Debug)]
enum Label {
    One(i64),
    Range(i64, i64),
}

#[derive(Clone, Debug)]
enum St {
    Assign(Target, Ex),
    If(Vec<(Ex, Vec<St>)>, Option<Vec<St>>),
    Case(Ex, Vec<(Vec<Label>, Vec<St>)>, Option<Vec<St>>),
    For {
        counter: usize,
        from: Ex,
        to: Ex,
        by: Option<Ex>,
        body: Vec<St>,
    },
    While(Ex, Vec<St>),
    Repeat(Vec<St>, Ex),
    Exit,
}

// ---------------------------------------------------------------- static types

/// The type an expression is computed in.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Ty {
    Bool,
    Dint,
    Lint,
    Real,
    Lreal,
}

impl Ty {
    fn is_real(self) -> bool {
        matches!(self, Ty::Real | Ty::Lreal)
    }
}

fn tag_ty(t: Tt) -> Ty {
    match t {
        Tt::Dint => Ty::Dint,
        Tt::Lint => Ty::Lint,
        Tt::Real => Ty::Real,
        Tt::Bool => Ty::Bool,
    }
}

/// The math type of `+ - * / MOD` and of comparisons of numbers.
fn arith_ty(a: Ty, b: Ty) -> Ty {
    let n = |t| if t == Ty::Bool { Ty::Dint } else { t };
    let (a, b) = (n(a), n(b));
    if a.is_real() || b.is_real() {
        if [a, b].iter().any(|t| matches!(t, Ty::Lreal | Ty::Lint)) {
            Ty::Lreal
        } else {
            Ty::Real
        }
    } else if a == Ty::Lint || b == Ty::Lint {
        Ty::Lint
    } else {
        Ty::Dint
    }
}

fn bin_ty(op: Op, a: Ty, b: Ty) -> Ty {
    match op {
        Op::Pow => {
            if [a, b].iter().any(|t| matches!(t, Ty::Lreal | Ty::Lint)) {
                Ty::Lreal
            } else {
                Ty::Real
            }
        }
        Op::Mul | Op::Div | Op::Mod | Op::Add | Op::Sub => arith_ty(a, b),
        Op::Lt | Op::Le | Op::Gt | Op::Ge | Op::Eq | Op::Ne => Ty::Bool,
        Op::And | Op::Xor | Op::Or => {
            if a == Ty::Bool && b == Ty::Bool {
                Ty::Bool
            } else if a == Ty::Lint || b == Ty::Lint {
                Ty::Lint
            } else {
                Ty::Dint
            }
        }
    }
}

fn ty(e: &Ex) -> Ty {
    match e {
        Ex::Int(v, _) => {
            if i32::try_from(*v).is_ok() {
                Ty::Dint
            } else {
                Ty::Lint
            }
        }
        Ex::Real(..) => Ty::Real,
        Ex::Bool(_) => Ty::Bool,
        Ex::Tag(i) => tag_ty(TAGS[*i].1),
        Ex::Arr(_) => Ty::Dint,
        Ex::Neg(x) | Ex::Not(x) | Ex::Paren(x) => ty(x),
        Ex::Call(f, x) => match f {
            Func::Abs => ty(x),
            Func::Trunc => Ty::Dint,
            _ => Ty::Real,
        },
        Ex::Bin(op, l, r) => bin_ty(*op, ty(l), ty(r)),
    }
}

// ---------------------------------------------------------------- generator

struct Gen<'r> {
    rng: &'r mut ChaCha8Rng,
    /// FOR counters whose every value in the current body is 0..=7.
    safe: Vec<usize>,
    /// Enclosing FOR loops.
    fors: usize,
    /// Enclosing WHILE/REPEAT loops.
    whiles: usize,
    /// Enclosing loops of any kind.
    loops: usize,
    /// Statements still to generate (the program's size).
    left: usize,
}

impl Gen<'_> {
    fn p(&mut self, prob: f64) -> bool {
        self.rng.random_bool(prob)
    }

    fn pick<T: Copy>(&mut self, xs: &[T]) -> T {
        xs[self.rng.random_range(0..xs.len())]
    }

    fn pct(&mut self) -> u32 {
        self.rng.random_range(0..100)
    }

    // ---- literals

    fn int_text(&mut self, v: i64) -> String {
        match self.rng.random_range(0..20) {
            0..=13 => v.to_string(),
            14..=15 => {
                // 1_000_000
                let digits = v.to_string();
                let mut out = String::new();
                for (k, ch) in digits.chars().enumerate() {
                    if k > 0 && (digits.len() - k).is_multiple_of(3) {
                        out.push('_');
                    }
                    out.push(ch);
                }
                out
            }
            16..=17 => {
                if self.p(0.5) {
                    format!("16#{v:X}")
                } else {
                    format!("16#{v:x}")
                }
            }
            18 if v < 4096 => format!("8#{v:o}"),
            19 if v < 1024 => format!("2#{v:b}"),
            _ => v.to_string(),
        }
    }

    fn lit(&mut self, v: i64) -> Ex {
        let text = self.int_text(v);
        // A based literal is a bit pattern: 16#8000_0000 is the DINT
        // -2147483648 (a 32-bit pattern), no overflow.
        let v = if text.contains('#') && (i64::from(i32::MAX) + 1..=i64::from(u32::MAX)).contains(&v) {
            i64::from(v as u32 as i32)
        } else {
            v
        };
        Ex::Int(v, text)
    }

    fn small_lit(&mut self, max: i64) -> Ex {
        let v = self.rng.random_range(0..=max);
        Ex::Int(v, v.to_string())
    }

    fn int_lit(&mut self) -> Ex {
        let v: i64 = match self.pct() {
            0..=59 => self.rng.random_range(0..=12),
            60..=74 => self.rng.random_range(0..=1000),
            75..=82 => self.rng.random_range(2_147_483_600..=2_147_483_700),
            83..=88 => self.pick(&[
                2_147_483_647,
                2_147_483_648,
                4_294_967_295,
                65_535,
                16_777_217,
                16_777_216,
            ]),
            89..=95 => self.rng.random_range(0..=100_000_000),
            _ => self.pick(&[
                3_000_000_000,
                1 << 40,
                i64::MAX,
                (1 << 53) + 1,
                1 << 62,
                4_611_686_018_427_387_905,
            ]),
        };
        self.lit(v)
    }

    fn digits(&mut self, n: usize) -> String {
        (0..n)
            .map(|_| char::from(b'0' + self.rng.random_range(0..10u8)))
            .collect()
    }

    fn real_lit(&mut self) -> Ex {
        let e = if self.p(0.5) { 'e' } else { 'E' };
        let text = match self.pct() {
            0..=44 => {
                let n = self.rng.random_range(1..=3);
                format!("{}.{}", self.rng.random_range(0..=100), self.digits(n))
            }
            45..=56 => format!("{}.5", self.rng.random_range(0..=5)),
            57..=71 => {
                let n = self.rng.random_range(1..=2);
                format!(
                    "{}.{}{e}{}",
                    self.rng.random_range(1..=9),
                    self.digits(n),
                    self.rng.random_range(-3..=3)
                )
            }
            72..=79 => format!("{}{e}{}", self.rng.random_range(1..=9), self.rng.random_range(0..=6)),
            80..=92 => {
                let exp = if self.p(0.6) {
                    self.rng.random_range(8..=12)
                } else {
                    self.rng.random_range(18..=38)
                };
                format!("{}.{}{e}{exp}", self.rng.random_range(1..=9), self.digits(1))
            }
            _ => self
                .pick(&[
                    "3.4e38",
                    "1.0e38",
                    "16777217.0",
                    "0.1",
                    "1.0e-40",
                    "0.0",
                    "2147483647.0",
                    "2.5",
                    "1.0e3",
                ])
                .to_owned(),
        };
        let v = text.parse::<f64>().expect("real literal") as f32;
        Ex::Real(v, text)
    }

    // ---- leaves

    fn arr(&mut self, d: u32) -> Ex {
        let sub = if !self.safe.is_empty() && self.p(0.5) {
            Ex::Tag(self.pick(&self.safe.clone()))
        } else if d > 0 && self.p(0.25) {
            // ABS(e MOD 8) is within 0..=7 whatever the DINT e.
            let e = self.dint(d - 1);
            Ex::Call(
                Func::Abs,
                Box::new(Ex::Bin(Op::Mod, Box::new(e), Box::new(self.lit(8)))),
            )
        } else {
            let v = self.rng.random_range(0..ARR_LEN as i64);
            self.lit(v)
        };
        Ex::Arr(Box::new(sub))
    }

    fn int_leaf(&mut self, d: u32) -> Ex {
        match self.pct() {
            0..=34 => Ex::Tag(self.pick(&DINTS)),
            35..=40 => Ex::Tag(self.pick(&READ_ONLY)),
            41..=47 => Ex::Tag(LINT),
            48..=59 => self.arr(d),
            _ => self.int_lit(),
        }
    }

    fn real_leaf(&mut self) -> Ex {
        if self.p(0.55) {
            Ex::Tag(self.pick(&REALS))
        } else {
            self.real_lit()
        }
    }

    fn bool_leaf(&mut self) -> Ex {
        if self.p(0.2) {
            Ex::Bool(self.p(0.5))
        } else {
            Ex::Tag(self.pick(&BOOLS))
        }
    }

    // ---- expressions

    fn arith_op(&mut self) -> Op {
        self.pick(&[Op::Add, Op::Add, Op::Sub, Op::Sub, Op::Mul, Op::Mul, Op::Div, Op::Mod])
    }

    /// A DINT or LINT expression.
    fn int(&mut self, d: u32) -> Ex {
        if d == 0 || self.p(0.3) {
            return self.int_leaf(d);
        }
        let d = d - 1;
        match self.pct() {
            0..=44 => {
                let op = self.arith_op();
                let (l, r) = (self.int_or_bool(d), self.int_or_bool(d));
                Ex::Bin(op, Box::new(l), Box::new(r))
            }
            45..=53 => Ex::Neg(Box::new(self.int(d))),
            54..=61 => Ex::Call(Func::Abs, Box::new(self.int(d))),
            62..=71 => Ex::Call(Func::Trunc, Box::new(self.real(d))),
            72..=84 => {
                let op = self.pick(&[Op::And, Op::Or, Op::Xor]);
                let (mut l, mut r) = (self.int_or_bool(d), self.int(d));
                if self.p(0.5) {
                    std::mem::swap(&mut l, &mut r);
                }
                Ex::Bin(op, Box::new(l), Box::new(r))
            }
            85..=91 => Ex::Not(Box::new(self.int(d))),
            _ => Ex::Paren(Box::new(self.int(d))),
        }
    }

    fn int_or_bool(&mut self, d: u32) -> Ex {
        if self.p(0.07) { self.boolean(d) } else { self.int(d) }
    }

    /// A DINT expression.
    fn dint(&mut self, d: u32) -> Ex {
        for _ in 0..10 {
            let e = self.int(d);
            if ty(&e) == Ty::Dint {
                return e;
            }
        }
        self.small_lit(9)
    }

    /// A REAL or LREAL expression.
    fn real(&mut self, d: u32) -> Ex {
        if d == 0 || self.p(0.3) {
            return self.real_leaf();
        }
        let d = d - 1;
        match self.pct() {
            0..=44 => {
                let op = self.arith_op();
                let (mut l, mut r) = (self.real(d), self.num(d));
                if self.p(0.5) {
                    std::mem::swap(&mut l, &mut r);
                }
                Ex::Bin(op, Box::new(l), Box::new(r))
            }
            45..=56 => {
                let l = self.num(d);
                let r = match self.pct() {
                    0..=39 => self.small_lit(4),
                    40..=59 => Ex::Neg(Box::new(self.small_lit(3))),
                    60..=69 => Ex::Neg(Box::new(self.real_leaf())),
                    _ => self.num(d),
                };
                Ex::Bin(Op::Pow, Box::new(l), Box::new(r))
            }
            57..=66 => Ex::Neg(Box::new(self.real(d))),
            67..=73 => Ex::Call(Func::Abs, Box::new(self.real(d))),
            74..=81 => Ex::Call(Func::Sqrt, Box::new(self.fn_arg(d))),
            82..=91 => {
                let f = self.pick(&[Func::Sin, Func::Cos, Func::Tan, Func::Atan]);
                Ex::Call(f, Box::new(self.fn_arg(d)))
            }
            _ => Ex::Paren(Box::new(self.real(d))),
        }
    }

    /// A DINT or REAL argument (for SQRT and the trigonometric functions).
    fn fn_arg(&mut self, d: u32) -> Ex {
        for _ in 0..10 {
            let e = self.num(d);
            if matches!(ty(&e), Ty::Dint | Ty::Real) {
                return e;
            }
        }
        self.real_leaf()
    }

    /// Any number.
    fn num(&mut self, d: u32) -> Ex {
        if self.p(0.5) { self.int(d) } else { self.real(d) }
    }

    /// A BOOL expression.
    fn boolean(&mut self, d: u32) -> Ex {
        if d == 0 || self.p(0.25) {
            return self.bool_leaf();
        }
        let d = d - 1;
        let (op, l, r) = match self.pct() {
            0..=39 => {
                let op = self.pick(&[Op::Lt, Op::Le, Op::Gt, Op::Ge, Op::Eq, Op::Ne]);
                (op, self.num(d), self.num(d))
            }
            40..=45 => (self.pick(&[Op::Eq, Op::Ne]), self.boolean(d), self.boolean(d)),
            46..=48 => {
                let op = self.pick(&[Op::Eq, Op::Ne]);
                let (mut l, mut r) = (self.boolean(d), self.num(d));
                if self.p(0.5) {
                    std::mem::swap(&mut l, &mut r);
                }
                (op, l, r)
            }
            49..=59 => return Ex::Not(Box::new(self.boolean(d))),
            60..=91 => (self.pick(&[Op::And, Op::Or, Op::Xor]), self.boolean(d), self.boolean(d)),
            _ => return Ex::Paren(Box::new(self.boolean(d))),
        };
        Ex::Bin(op, Box::new(l), Box::new(r))
    }

    /// An IF/WHILE/UNTIL condition: BOOL mostly, an integer sometimes.
    fn cond(&mut self, d: u32) -> Ex {
        if self.p(0.15) { self.int(d) } else { self.boolean(d) }
    }

    // ---- statements

    fn assign(&mut self) -> St {
        let d = self.rng.random_range(1..=3);
        let (target, tt) = match self.pct() {
            0..=34 => (Target::Tag(self.pick(&DINTS)), Tt::Dint),
            35..=54 => (Target::Tag(self.pick(&REALS)), Tt::Real),
            55..=66 => (Target::Tag(self.pick(&BOOLS)), Tt::Bool),
            67..=73 => (Target::Tag(LINT), Tt::Lint),
            _ => (Target::Arr(self.arr(1).unbox_arr()), Tt::Dint),
        };
        let value = match tt {
            Tt::Bool if self.p(0.8) => self.boolean(d),
            Tt::Dint if self.p(0.55) => self.int(d),
            _ if self.p(0.05) => self.boolean(d),
            _ => self.num(d),
        };
        St::Assign(target, value)
    }

    /// `lo..=hi` statements, fewer when the program's size is reached (but
    /// at least one).
    fn block(&mut self, depth: u32, lo: usize, hi: usize) -> Vec<St> {
        let n = self.rng.random_range(lo..=hi);
        let mut out = Vec::new();
        while out.is_empty() || (out.len() < n && self.left > 0) {
            out.extend(self.stmt(depth));
        }
        out
    }

    /// A number of arms or branches: `1..=hi`, fewer when the program's
    /// size is nearly reached.
    fn arms(&mut self, hi: usize) -> usize {
        self.rng.random_range(1..=hi).min(self.left.max(1))
    }

    /// One statement (two for a loop with its pass counter's reset).
    fn stmt(&mut self, depth: u32) -> Vec<St> {
        self.left = self.left.saturating_sub(1);
        let compound = depth < 3 && self.left > 0;
        let roll = self.pct();
        if self.loops > 0 && roll < 4 {
            return vec![St::Exit];
        }
        if !compound || roll < 55 {
            return vec![self.assign()];
        }
        match roll {
            55..=70 => {
                let n = self.arms(3);
                let branches = (0..n).map(|_| (self.cond(2), self.block(depth + 1, 1, 3))).collect();
                let otherwise = (self.left > 0 && self.p(0.5)).then(|| self.block(depth + 1, 1, 3));
                vec![St::If(branches, otherwise)]
            }
            71..=80 => {
                let sel = if self.p(0.6) {
                    let e = self.dint(1);
                    let m = self.rng.random_range(3..=9);
                    Ex::Bin(Op::Mod, Box::new(e), Box::new(self.lit(m)))
                } else {
                    self.dint(2)
                };
                let n = self.arms(4);
                let arms = (0..n)
                    .map(|_| {
                        let k = self.rng.random_range(1..=3);
                        let labels = (0..k)
                            .map(|_| {
                                let a = self.rng.random_range(-4..=8);
                                if self.p(0.3) {
                                    Label::Range(a, a + self.rng.random_range(0..=4))
                                } else {
                                    Label::One(a)
                                }
                            })
                            .collect();
                        (labels, self.block(depth + 1, 1, 3))
                    })
                    .collect();
                let otherwise = (self.left > 0 && self.p(0.5)).then(|| self.block(depth + 1, 1, 2));
                vec![St::Case(sel, arms, otherwise)]
            }
            81..=90 if self.fors < FOR_COUNTERS.len() => {
                let counter = FOR_COUNTERS[self.fors];
                let safe = self.p(0.5);
                let (from, to, by) = if safe {
                    let a = self.rng.random_range(0..ARR_LEN as i64);
                    let b = self.rng.random_range(0..ARR_LEN as i64);
                    let s = self.pick(&[1, 1, 2, 3, -1, -1, -2]);
                    (self.lit(a), self.lit(b), s)
                } else {
                    let from = if self.p(0.6) {
                        let v = self.rng.random_range(-3..=5);
                        self.signed(v)
                    } else {
                        self.dint(1)
                    };
                    let to = match self.pct() {
                        0..=39 => {
                            let v = self.rng.random_range(-3..=12);
                            self.signed(v)
                        }
                        40..=69 => Ex::Bin(Op::Mod, Box::new(self.dint(1)), Box::new(self.lit(9))),
                        _ => self.dint(1),
                    };
                    (from, to, self.pick(&[1, 1, 1, 2, 3, -1, -2]))
                };
                let by = if by == 1 && self.p(0.5) {
                    None
                } else {
                    Some(self.signed(by))
                };
                self.fors += 1;
                self.loops += 1;
                if safe {
                    self.safe.push(counter);
                }
                let body = self.block(depth + 1, 1, 3);
                if safe {
                    self.safe.pop();
                }
                self.fors -= 1;
                self.loops -= 1;
                vec![St::For {
                    counter,
                    from,
                    to,
                    by,
                    body,
                }]
            }
            _ if self.whiles < GUARDS.len() => {
                let guard = GUARDS[self.whiles];
                self.left = self.left.saturating_sub(2);
                let n = self.rng.random_range(0..=4);
                self.whiles += 1;
                self.loops += 1;
                let mut body = self.block(depth + 1, 1, 3);
                self.whiles -= 1;
                self.loops -= 1;
                let g = || Box::new(Ex::Tag(guard));
                body.push(St::Assign(
                    Target::Tag(guard),
                    Ex::Bin(Op::Add, g(), Box::new(self.lit(1))),
                ));
                let c = self.cond(2);
                let reset = St::Assign(Target::Tag(guard), self.lit(0));
                let n = Box::new(self.lit(n));
                let swap = self.p(0.5);
                let join = |op, a: Box<Ex>, b: Box<Ex>| if swap { Ex::Bin(op, b, a) } else { Ex::Bin(op, a, b) };
                let lp = if self.p(0.6) {
                    St::While(join(Op::And, Box::new(Ex::Bin(Op::Lt, g(), n)), Box::new(c)), body)
                } else {
                    St::Repeat(body, join(Op::Or, Box::new(Ex::Bin(Op::Ge, g(), n)), Box::new(c)))
                };
                vec![reset, lp]
            }
            _ => vec![self.assign()],
        }
    }

    /// `v` as a literal, negated when negative.
    fn signed(&mut self, v: i64) -> Ex {
        let lit = self.lit(v.abs());
        if v < 0 { Ex::Neg(Box::new(lit)) } else { lit }
    }

    fn program(&mut self) -> Vec<St> {
        let mut out = Vec::new();
        // Some starting values, so that the first expressions have
        // something to work on.
        self.left = self.rng.random_range(3..=15);
        for _ in 0..self.rng.random_range(0..=3) {
            self.left -= 1;
            out.push(self.assign());
        }
        while self.left > 0 {
            out.extend(self.stmt(0));
        }
        out
    }
}

impl Ex {
    fn unbox_arr(self) -> Ex {
        match self {
            Ex::Arr(s) => *s,
            other => other,
        }
    }
}

// ---------------------------------------------------------------- printer

/// Prints a program; with a generator, keywords and names in random case
/// and `AND` sometimes as `&`.
struct Printer<'r> {
    rng: Option<&'r mut ChaCha8Rng>,
    out: String,
}

fn print(prog: &[St], rng: Option<&mut ChaCha8Rng>) -> String {
    let mut p = Printer {
        rng,
        out: String::new(),
    };
    p.block(prog, 0);
    p.out
}

fn level(e: &Ex) -> u8 {
    match e {
        Ex::Bin(op, ..) => op.level(),
        Ex::Neg(_) | Ex::Not(_) => 3,
        _ => 1,
    }
}

impl Printer<'_> {
    /// A keyword or name in a random case.
    fn word(&mut self, w: &str) -> String {
        let Some(rng) = self.rng.as_mut() else {
            return w.to_owned();
        };
        match rng.random_range(0..10) {
            0..=5 => w.to_owned(),
            6..=7 => w.to_lowercase(),
            _ => {
                let mut c = w.chars();
                c.next()
                    .map(|f| f.to_uppercase().collect::<String>() + &c.as_str().to_lowercase())
                    .unwrap_or_default()
            }
        }
    }

    fn push(&mut self, s: &str) {
        self.out.push_str(s);
    }

    fn kw(&mut self, w: &str) {
        let w = self.word(w);
        self.push(&w);
    }

    fn sub(&mut self, e: &Ex, bare: bool) {
        if bare {
            self.expr(e);
        } else {
            self.push("(");
            self.expr(e);
            self.push(")");
        }
    }

    fn expr(&mut self, e: &Ex) {
        match e {
            Ex::Int(_, t) | Ex::Real(_, t) => self.push(t),
            Ex::Bool(b) => self.kw(if *b { "TRUE" } else { "FALSE" }),
            Ex::Tag(i) => self.kw(TAGS[*i].0),
            Ex::Arr(s) => {
                self.kw("Arr");
                self.push("[");
                self.expr(s);
                self.push("]");
            }
            Ex::Neg(x) => {
                self.push("-");
                self.sub(x, level(x) <= 2);
            }
            Ex::Not(x) => {
                self.kw("NOT");
                self.push(" ");
                self.sub(x, level(x) <= 2);
            }
            Ex::Paren(x) => self.sub(x, false),
            Ex::Call(f, x) => {
                self.kw(f.name());
                self.push("(");
                self.expr(x);
                self.push(")");
            }
            Ex::Bin(op, l, r) => {
                let lv = op.level();
                if *op == Op::Pow {
                    self.sub(l, level(l) <= 2);
                    self.push(" ** ");
                    match &**r {
                        Ex::Neg(x) if level(x) == 1 => {
                            self.push("-");
                            self.expr(x);
                        }
                        r => self.sub(r, level(r) == 1),
                    }
                } else {
                    self.sub(l, level(l) <= lv);
                    self.push(" ");
                    if *op == Op::And && self.rng.as_mut().is_some_and(|r| r.random_bool(0.25)) {
                        self.push("&");
                    } else {
                        self.kw(op.text());
                    }
                    self.push(" ");
                    self.sub(r, level(r) < lv);
                }
            }
        }
    }

    fn indent(&mut self, n: usize) {
        for _ in 0..n {
            self.push("    ");
        }
    }

    fn label(v: i64) -> String {
        v.to_string()
    }

    fn block(&mut self, b: &[St], ind: usize) {
        for s in b {
            if let Some(rng) = self.rng.as_mut() {
                let comment = match rng.random_range(0..40) {
                    0 => "// a comment := 1;\n",
                    1 => "(* a comment; END_IF *)\n",
                    2 => "/* a comment ** */\n",
                    _ => "",
                };
                if !comment.is_empty() {
                    self.indent(ind);
                    self.push(comment);
                }
            }
            self.stmt(s, ind);
        }
    }

    fn stmt(&mut self, s: &St, ind: usize) {
        self.indent(ind);
        match s {
            St::Assign(t, e) => {
                match t {
                    Target::Tag(i) => self.kw(TAGS[*i].0),
                    Target::Arr(sub) => {
                        self.kw("Arr");
                        self.push("[");
                        self.expr(sub);
                        self.push("]");
                    }
                }
                self.push(" := ");
                self.expr(e);
                self.push(";\n");
            }
            St::If(branches, otherwise) => {
                for (k, (c, b)) in branches.iter().enumerate() {
                    if k > 0 {
                        self.indent(ind);
                    }
                    self.kw(if k == 0 { "IF" } else { "ELSIF" });
                    self.push(" ");
                    self.expr(c);
                    self.push(" ");
                    self.kw("THEN");
                    self.push("\n");
                    self.block(b, ind + 1);
                }
                if let Some(b) = otherwise {
                    self.indent(ind);
                    self.kw("ELSE");
                    self.push("\n");
                    self.block(b, ind + 1);
                }
                self.indent(ind);
                self.kw("END_IF");
                self.push(";\n");
            }
            St::Case(sel, arms, otherwise) => {
                self.kw("CASE");
                self.push(" ");
                self.expr(sel);
                self.push(" ");
                self.kw("OF");
                self.push("\n");
                for (labels, b) in arms {
                    self.indent(ind + 1);
                    let text: Vec<String> = labels
                        .iter()
                        .map(|l| match l {
                            Label::One(v) => Self::label(*v),
                            Label::Range(a, b) => format!("{}..{}", Self::label(*a), Self::label(*b)),
                        })
                        .collect();
                    self.push(&text.join(", "));
                    self.push(":\n");
                    self.block(b, ind + 2);
                }
                if let Some(b) = otherwise {
                    self.indent(ind + 1);
                    self.kw("ELSE");
                    self.push("\n");
                    self.block(b, ind + 2);
                }
                self.indent(ind);
                self.kw("END_CASE");
                self.push(";\n");
            }
            St::For {
                counter,
                from,
                to,
                by,
                body,
            } => {
                self.kw("FOR");
                self.push(" ");
                self.kw(TAGS[*counter].0);
                self.push(" := ");
                self.expr(from);
                self.push(" ");
                self.kw("TO");
                self.push(" ");
                self.expr(to);
                if let Some(by) = by {
                    self.push(" ");
                    self.kw("BY");
                    self.push(" ");
                    self.expr(by);
                }
                self.push(" ");
                self.kw("DO");
                self.push("\n");
                self.block(body, ind + 1);
                self.indent(ind);
                self.kw("END_FOR");
                self.push(";\n");
            }
            St::While(c, body) => {
                self.kw("WHILE");
                self.push(" ");
                self.expr(c);
                self.push(" ");
                self.kw("DO");
                self.push("\n");
                self.block(body, ind + 1);
                self.indent(ind);
                self.kw("END_WHILE");
                self.push(";\n");
            }
            St::Repeat(body, c) => {
                self.kw("REPEAT");
                self.push("\n");
                self.block(body, ind + 1);
                self.indent(ind);
                self.kw("UNTIL");
                self.push(" ");
                self.expr(c);
                self.push("\n");
                self.indent(ind);
                self.kw("END_REPEAT");
                self.push(";\n");
            }
            St::Exit => {
                self.kw("EXIT");
                self.push(";\n");
            }
        }
    }
}

// ---------------------------------------------------------------- reference

/// A value under evaluation, typed.
#[derive(Clone, Copy, Debug)]
enum V {
    B(bool),
    D(i32),
    L(i64),
    R(f32),
    /// LREAL.
    X(f64),
}

fn vty(v: V) -> Ty {
    match v {
        V::B(_) => Ty::Bool,
        V::D(_) => Ty::Dint,
        V::L(_) => Ty::Lint,
        V::R(_) => Ty::Real,
        V::X(_) => Ty::Lreal,
    }
}

/// The value converted to REAL (single precision), as REAL math does.
fn f32v(v: V) -> f32 {
    match v {
        V::B(b) => f32::from(u8::from(b)),
        V::D(i) => i as f32,
        V::L(i) => i as f32,
        V::R(r) => r,
        V::X(x) => x as f32,
    }
}

/// The value converted to LREAL.
fn f64v(v: V) -> f64 {
    match v {
        V::B(b) => f64::from(u8::from(b)),
        V::D(i) => f64::from(i),
        V::L(i) => i as f64,
        V::R(r) => f64::from(r),
        V::X(x) => x,
    }
}

fn i64v(v: V) -> i64 {
    match v {
        V::B(b) => i64::from(b),
        V::D(i) => i64::from(i),
        V::L(i) => i,
        V::R(_) | V::X(_) => unreachable!("integer expected, got {v:?}"),
    }
}

fn truthy(v: V) -> bool {
    match v {
        V::B(b) => b,
        V::D(i) => i != 0,
        V::L(i) => i != 0,
        V::R(r) => r != 0.0,
        V::X(x) => x != 0.0,
    }
}

/// An integral finite `x` exactly as an i128, or `None` when its
/// magnitude is ≥ 2^120 (then a multiple of 2^68: its low 64 bits are 0).
fn integral(x: f64) -> Option<i128> {
    (x.abs() < 2f64.powi(120)).then_some(x as i128)
}

/// Why a generated program is not used.
#[derive(Debug)]
struct Discard;

enum Flow {
    Next,
    Exit,
}

struct Ref {
    tags: Vec<V>,
    arr: [i32; ARR_LEN],
    faults: i64,
    steps: u32,
}

impl Ref {
    fn new() -> Ref {
        Ref {
            tags: TAGS
                .iter()
                .map(|(_, t)| match t {
                    Tt::Dint => V::D(0),
                    Tt::Lint => V::L(0),
                    Tt::Real => V::R(0.0),
                    Tt::Bool => V::B(false),
                })
                .collect(),
            arr: [0; ARR_LEN],
            faults: 0,
            steps: 0,
        }
    }

    fn fault(&mut self) {
        self.faults += 1;
    }

    fn tick(&mut self) -> Result<(), Discard> {
        self.steps += 1;
        if self.steps > BUDGET { Err(Discard) } else { Ok(()) }
    }

    // ---- expressions

    fn eval(&mut self, e: &Ex) -> Result<V, Discard> {
        Ok(match e {
            Ex::Int(v, _) => match i32::try_from(*v) {
                Ok(i) => V::D(i),
                Err(_) => V::L(*v),
            },
            Ex::Real(v, _) => V::R(*v),
            Ex::Bool(b) => V::B(*b),
            Ex::Tag(i) => self.tags[*i],
            Ex::Arr(s) => {
                let k = self.index(s)?;
                V::D(self.arr[k])
            }
            Ex::Paren(x) => self.eval(x)?,
            Ex::Neg(x) => match self.eval(x)? {
                V::D(i) => V::D(i.checked_neg().unwrap_or_else(|| {
                    self.fault();
                    i.wrapping_neg()
                })),
                V::L(i) => V::L(i.checked_neg().unwrap_or_else(|| {
                    self.fault();
                    i.wrapping_neg()
                })),
                V::R(r) => V::R(-r),
                V::X(x) => V::X(-x),
                v @ V::B(_) => unreachable!("- on {v:?}"),
            },
            Ex::Not(x) => match self.eval(x)? {
                V::B(b) => V::B(!b),
                V::D(i) => V::D(!i),
                V::L(i) => V::L(!i),
                v => unreachable!("NOT on {v:?}"),
            },
            Ex::Call(f, x) => {
                let v = self.eval(x)?;
                self.call(*f, v)
            }
            Ex::Bin(op, l, r) => {
                let a = self.eval(l)?;
                let b = self.eval(r)?;
                self.bin(*op, a, b)
            }
        })
    }

    fn index(&mut self, s: &Ex) -> Result<usize, Discard> {
        let k = i64v(self.eval(s)?);
        usize::try_from(k).ok().filter(|k| *k < ARR_LEN).ok_or(Discard)
    }

    fn call(&mut self, f: Func, v: V) -> V {
        match f {
            Func::Abs => match v {
                V::D(i) => V::D(i.checked_abs().unwrap_or_else(|| {
                    self.fault();
                    i.wrapping_abs()
                })),
                V::L(i) => V::L(i.checked_abs().unwrap_or_else(|| {
                    self.fault();
                    i.wrapping_abs()
                })),
                V::R(r) => V::R(r.abs()),
                V::X(x) => V::X(x.abs()),
                V::B(_) => unreachable!("ABS of BOOL"),
            },
            Func::Trunc => {
                let x = f64v(v);
                if !x.is_finite() {
                    self.fault();
                    return V::D(0);
                }
                match integral(x.trunc()) {
                    Some(t) => {
                        let d = t as i32;
                        if i128::from(d) != t {
                            self.fault();
                        }
                        V::D(d)
                    }
                    None => {
                        self.fault();
                        V::D(0)
                    }
                }
            }
            Func::Sqrt | Func::Sin | Func::Cos | Func::Tan | Func::Atan => {
                let x = f64::from(f32v(v));
                let r = match f {
                    Func::Sqrt => x.abs().sqrt(),
                    Func::Sin => x.sin(),
                    Func::Cos => x.cos(),
                    Func::Tan => x.tan(),
                    _ => x.atan(),
                };
                V::R(r as f32)
            }
        }
    }

    /// `x op y` in real math; `None` for MOD by zero.
    fn real_op(op: Op, x: f64, y: f64) -> Option<f64> {
        Some(match op {
            Op::Add => x + y,
            Op::Sub => x - y,
            Op::Mul => x * y,
            Op::Div => x / y,
            Op::Mod => {
                if y == 0.0 {
                    return None;
                }
                x - (x / y).trunc() * y
            }
            _ => unreachable!(),
        })
    }

    fn int_op(&mut self, op: Op, x: i128, y: i128, max: i128) -> i128 {
        match op {
            Op::Add => x + y,
            Op::Sub => x - y,
            Op::Mul => x * y,
            Op::Div => {
                if y == 0 {
                    self.fault();
                    x.signum() * max
                } else {
                    x / y
                }
            }
            Op::Mod => {
                if y == 0 {
                    self.fault();
                    0
                } else {
                    x % y
                }
            }
            _ => unreachable!(),
        }
    }

    fn bin(&mut self, op: Op, a: V, b: V) -> V {
        let (ta, tb) = (vty(a), vty(b));
        match op {
            Op::Pow => {
                if bin_ty(op, ta, tb) == Ty::Lreal {
                    let (x, y) = (f64v(a), f64v(b));
                    let r = x.powf(y);
                    if !r.is_finite() && x.is_finite() && y.is_finite() {
                        self.fault();
                    }
                    V::X(r)
                } else {
                    let (x, y) = (f64::from(f32v(a)), f64::from(f32v(b)));
                    let r = x.powf(y) as f32;
                    if !r.is_finite() && x.is_finite() && y.is_finite() {
                        self.fault();
                    }
                    V::R(r)
                }
            }
            Op::Add | Op::Sub | Op::Mul | Op::Div | Op::Mod => match arith_ty(ta, tb) {
                Ty::Real => {
                    let (x, y) = (f64::from(f32v(a)), f64::from(f32v(b)));
                    match Self::real_op(op, x, y) {
                        None => {
                            self.fault();
                            V::R(0.0)
                        }
                        Some(r) => {
                            let r = r as f32;
                            if !r.is_finite() && x.is_finite() && y.is_finite() {
                                self.fault();
                            }
                            V::R(r)
                        }
                    }
                }
                Ty::Lreal => {
                    let (x, y) = (f64v(a), f64v(b));
                    match Self::real_op(op, x, y) {
                        None => {
                            self.fault();
                            V::X(0.0)
                        }
                        Some(r) => {
                            if !r.is_finite() && x.is_finite() && y.is_finite() {
                                self.fault();
                            }
                            V::X(r)
                        }
                    }
                }
                Ty::Dint => {
                    let r = self.int_op(op, i64v(a).into(), i64v(b).into(), i32::MAX.into());
                    let w = r as i32;
                    if i128::from(w) != r {
                        self.fault();
                    }
                    V::D(w)
                }
                Ty::Lint => {
                    let r = self.int_op(op, i64v(a).into(), i64v(b).into(), i64::MAX.into());
                    let w = r as i64;
                    if i128::from(w) != r {
                        self.fault();
                    }
                    V::L(w)
                }
                Ty::Bool => unreachable!(),
            },
            Op::Lt | Op::Le | Op::Gt | Op::Ge | Op::Eq | Op::Ne => {
                let ord = if ta == Ty::Bool && tb == Ty::Bool {
                    i64v(a).partial_cmp(&i64v(b))
                } else {
                    match arith_ty(ta, tb) {
                        Ty::Real => f32v(a).partial_cmp(&f32v(b)),
                        Ty::Lreal => f64v(a).partial_cmp(&f64v(b)),
                        _ => i64v(a).partial_cmp(&i64v(b)),
                    }
                };
                V::B(match op {
                    Op::Lt => ord == Some(Ordering::Less),
                    Op::Le => matches!(ord, Some(Ordering::Less | Ordering::Equal)),
                    Op::Gt => ord == Some(Ordering::Greater),
                    Op::Ge => matches!(ord, Some(Ordering::Greater | Ordering::Equal)),
                    Op::Eq => ord == Some(Ordering::Equal),
                    _ => ord != Some(Ordering::Equal),
                })
            }
            Op::And | Op::Xor | Op::Or => {
                if let (V::B(x), V::B(y)) = (a, b) {
                    return V::B(match op {
                        Op::And => x && y,
                        Op::Xor => x != y,
                        _ => x || y,
                    });
                }
                let (x, y) = (i64v(a), i64v(b));
                let r = match op {
                    Op::And => x & y,
                    Op::Xor => x ^ y,
                    _ => x | y,
                };
                if ta == Ty::Lint || tb == Ty::Lint {
                    V::L(r)
                } else {
                    V::D(r as i32)
                }
            }
        }
    }

    // ---- assignment

    /// `v` converted to an integer of `bits` (32 or 64) bits.
    fn int_of(&mut self, v: V, bits: u32) -> i64 {
        let (wide, bad) = match v {
            V::B(b) => (i128::from(b), false),
            V::D(i) => (i128::from(i), false),
            V::L(i) => (i128::from(i), false),
            V::R(_) | V::X(_) => {
                let x = f64v(v);
                if x.is_finite() {
                    match integral(x.round_ties_even()) {
                        Some(r) => (r, false),
                        None => (0, true),
                    }
                } else {
                    (0, true)
                }
            }
        };
        let w = if bits == 32 {
            i64::from(wide as i32)
        } else {
            wide as i64
        };
        if bad || i128::from(w) != wide {
            self.fault();
        }
        w
    }

    fn store(&mut self, t: Tt, v: V) -> V {
        match t {
            Tt::Bool => V::B(truthy(v)),
            Tt::Real => V::R(match v {
                V::X(x) => {
                    let r = x as f32;
                    if x.is_finite() && !r.is_finite() {
                        self.fault();
                    }
                    r
                }
                _ => f32v(v),
            }),
            Tt::Dint => V::D(self.int_of(v, 32) as i32),
            Tt::Lint => V::L(self.int_of(v, 64)),
        }
    }

    // ---- statements

    fn block(&mut self, b: &[St]) -> Result<Flow, Discard> {
        for s in b {
            if let Flow::Exit = self.stmt(s)? {
                return Ok(Flow::Exit);
            }
        }
        Ok(Flow::Next)
    }

    fn stmt(&mut self, s: &St) -> Result<Flow, Discard> {
        self.tick()?;
        match s {
            St::Assign(t, e) => {
                let v = self.eval(e)?;
                match t {
                    Target::Tag(i) => {
                        let stored = self.store(TAGS[*i].1, v);
                        self.tags[*i] = stored;
                    }
                    Target::Arr(sub) => {
                        let k = self.index(sub)?;
                        let V::D(d) = self.store(Tt::Dint, v) else {
                            unreachable!()
                        };
                        self.arr[k] = d;
                    }
                }
            }
            St::If(branches, otherwise) => {
                for (c, b) in branches {
                    if truthy(self.eval(c)?) {
                        return self.block(b);
                    }
                }
                if let Some(b) = otherwise {
                    return self.block(b);
                }
            }
            St::Case(sel, arms, otherwise) => {
                let v = i64v(self.eval(sel)?);
                for (labels, b) in arms {
                    let hit = labels.iter().any(|l| match *l {
                        Label::One(x) => v == x,
                        Label::Range(lo, hi) => (lo..=hi).contains(&v),
                    });
                    if hit {
                        return self.block(b);
                    }
                }
                if let Some(b) = otherwise {
                    return self.block(b);
                }
            }
            St::For {
                counter,
                from,
                to,
                by,
                body,
            } => {
                let v = self.eval(from)?;
                self.tags[*counter] = self.store(Tt::Dint, v);
                loop {
                    self.tick()?;
                    let end = i64v(self.eval(to)?);
                    let step = match by {
                        Some(b) => self.eval(b)?,
                        None => V::D(1),
                    };
                    let s = i64v(step);
                    let i = i64v(self.tags[*counter]);
                    if (s > 0 && i > end) || (s < 0 && i < end) {
                        break;
                    }
                    if let Flow::Exit = self.block(body)? {
                        break;
                    }
                    let next = self.bin(Op::Add, self.tags[*counter], step);
                    self.tags[*counter] = self.store(Tt::Dint, next);
                }
            }
            St::While(c, body) => loop {
                self.tick()?;
                if !truthy(self.eval(c)?) {
                    break;
                }
                if let Flow::Exit = self.block(body)? {
                    break;
                }
            },
            St::Repeat(body, c) => loop {
                if let Flow::Exit = self.block(body)? {
                    break;
                }
                self.tick()?;
                if truthy(self.eval(c)?) {
                    break;
                }
            },
            St::Exit => return Ok(Flow::Exit),
        }
        Ok(Flow::Next)
    }
}

// ---------------------------------------------------------------- comparison

fn expected(v: V) -> Value {
    match v {
        V::B(b) => Value::Bool(b),
        V::D(i) => Value::Int(i64::from(i)),
        V::L(i) => Value::Int(i),
        V::R(r) => Value::Real(f64::from(r)),
        V::X(x) => Value::Real(x),
    }
}

fn same(a: Value, b: Value) -> bool {
    match (a, b) {
        (Value::Real(x), Value::Real(y)) => (x.is_nan() && y.is_nan()) || x.to_bits() == y.to_bits(),
        _ => a == b,
    }
}

/// Generates program `n`: the program, its text, the reference's final
/// state and how many programs were drawn again.
fn generate(n: u64) -> (Vec<St>, String, Ref, u32) {
    let mut rng = ChaCha8Rng::seed_from_u64(SEED_BASE + n);
    let mut discarded = 0;
    loop {
        let prog = Gen {
            rng: &mut rng,
            safe: Vec::new(),
            fors: 0,
            whiles: 0,
            loops: 0,
            left: 0,
        }
        .program();
        let mut r = Ref::new();
        if r.block(&prog).is_err() {
            discarded += 1;
            continue;
        }
        let text = print(&prog, Some(&mut rng));
        return (prog, text, r, discarded);
    }
}

/// A disagreement: what differs (tag names, `minor faults`, `major fault`,
/// `compile`) and the report.
struct Failure {
    what: Vec<String>,
    report: String,
}

/// Runs program `n`; `Err` describes every difference.
fn check(n: u64, text: &str, r: &Ref) -> Result<(), Failure> {
    let head = format!("program #{n} (seed {:#x} = SEED_BASE + {n})", SEED_BASE + n);
    let mut decl: Vec<(&str, &str)> = TAGS.iter().map(|(name, t)| (*name, t.name())).collect();
    decl.push(("Arr", "DINT[8]"));
    let mut s = Sandbox::new(&decl, text).map_err(|e| Failure {
        what: vec!["compile".into()],
        report: format!("{head}: does not compile: {e}\n--- routine ---\n{text}"),
    })?;
    s.scan();
    let (mut what, mut diffs) = (Vec::new(), Vec::new());
    if let Some(f) = s.controller().major_fault() {
        what.push("major fault".to_owned());
        diffs.push(format!("major fault: {f}"));
    }
    let mut cmp = |name: String, exp: Value| match s.value(&name) {
        Some(act) if same(act, exp) => {}
        act => {
            diffs.push(format!("tag {name}: expected {exp:?}, actual {act:?}"));
            what.push(name);
        }
    };
    for (i, (name, _)) in TAGS.iter().enumerate() {
        cmp((*name).to_owned(), expected(r.tags[i]));
    }
    for (k, v) in r.arr.iter().enumerate() {
        cmp(format!("Arr[{k}]"), Value::Int(i64::from(*v)));
    }
    let minors = s.controller().minor_fault_count();
    if minors != r.faults {
        what.push("minor faults".to_owned());
        diffs.push(format!("minor faults: expected {}, actual {minors}", r.faults));
    }
    if diffs.is_empty() {
        Ok(())
    } else {
        Err(Failure {
            what,
            report: format!("{head}:\n  {}\n--- routine ---\n{text}", diffs.join("\n  ")),
        })
    }
}

// ---------------------------------------------------------------- reduction

/// Statements in a program, nested ones included.
fn size(b: &[St]) -> usize {
    b.iter()
        .map(|s| 1 + inner_blocks(s).iter().map(|b| size(b)).sum::<usize>())
        .sum()
}

/// Whether every `EXIT` is inside a loop.
fn exits_ok(b: &[St], in_loop: bool) -> bool {
    b.iter().all(|s| match s {
        St::Exit => in_loop,
        St::Assign(..) => true,
        St::If(..) | St::Case(..) => inner_blocks(s).iter().all(|b| exits_ok(b, in_loop)),
        St::For { body, .. } | St::While(_, body) | St::Repeat(body, _) => exits_ok(body, true),
    })
}

fn inner_blocks(s: &St) -> Vec<&[St]> {
    match s {
        St::If(br, o) => br.iter().map(|(_, b)| b.as_slice()).chain(o.as_deref()).collect(),
        St::Case(_, arms, o) => arms.iter().map(|(_, b)| b.as_slice()).chain(o.as_deref()).collect(),
        St::For { body, .. } | St::While(_, body) | St::Repeat(body, _) => vec![body],
        St::Assign(..) | St::Exit => Vec::new(),
    }
}

/// Smaller programs: a statement removed, a compound statement replaced
/// by one of its blocks, a statement made smaller.
fn block_cands(b: &[St]) -> Vec<Vec<St>> {
    let mut out = Vec::new();
    if b.len() > 1 {
        for i in 0..b.len() {
            let mut c = b.to_vec();
            c.remove(i);
            out.push(c);
        }
    }
    for (i, s) in b.iter().enumerate() {
        for inner in inner_blocks(s) {
            let mut c = b[..i].to_vec();
            c.extend_from_slice(inner);
            c.extend_from_slice(&b[i + 1..]);
            out.push(c);
        }
    }
    for (i, s) in b.iter().enumerate() {
        for s in stmt_cands(s) {
            let mut c = b.to_vec();
            c[i] = s;
            out.push(c);
        }
    }
    out
}

fn stmt_cands(s: &St) -> Vec<St> {
    let mut out = Vec::new();
    match s {
        St::Assign(t, e) => {
            out.extend(expr_cands(e).into_iter().map(|c| St::Assign(t.clone(), c)));
            if let Target::Arr(sub) = t {
                out.extend(
                    expr_cands(sub)
                        .into_iter()
                        .map(|c| St::Assign(Target::Arr(c), e.clone())),
                );
            }
        }
        St::If(br, o) => {
            if br.len() > 1 {
                for i in 0..br.len() {
                    let mut c = br.clone();
                    c.remove(i);
                    out.push(St::If(c, o.clone()));
                }
            }
            if o.is_some() {
                out.push(St::If(br.clone(), None));
            }
            for i in 0..br.len() {
                for c in expr_cands(&br[i].0) {
                    let mut x = br.clone();
                    x[i].0 = c;
                    out.push(St::If(x, o.clone()));
                }
                for c in block_cands(&br[i].1) {
                    let mut x = br.clone();
                    x[i].1 = c;
                    out.push(St::If(x, o.clone()));
                }
            }
            if let Some(ob) = o {
                out.extend(block_cands(ob).into_iter().map(|c| St::If(br.clone(), Some(c))));
            }
        }
        St::Case(sel, arms, o) => {
            if arms.len() > 1 {
                for i in 0..arms.len() {
                    let mut c = arms.clone();
                    c.remove(i);
                    out.push(St::Case(sel.clone(), c, o.clone()));
                }
            }
            if o.is_some() {
                out.push(St::Case(sel.clone(), arms.clone(), None));
            }
            out.extend(
                expr_cands(sel)
                    .into_iter()
                    .map(|c| St::Case(c, arms.clone(), o.clone())),
            );
            for i in 0..arms.len() {
                for j in 0..arms[i].0.len() {
                    let mut x = arms.clone();
                    if let Label::Range(lo, _) = x[i].0[j] {
                        x[i].0[j] = Label::One(lo);
                        out.push(St::Case(sel.clone(), x.clone(), o.clone()));
                    }
                    if x[i].0.len() > 1 {
                        x[i].0.remove(j);
                        out.push(St::Case(sel.clone(), x, o.clone()));
                    }
                }
                for c in block_cands(&arms[i].1) {
                    let mut x = arms.clone();
                    x[i].1 = c;
                    out.push(St::Case(sel.clone(), x, o.clone()));
                }
            }
            if let Some(ob) = o {
                out.extend(
                    block_cands(ob)
                        .into_iter()
                        .map(|c| St::Case(sel.clone(), arms.clone(), Some(c))),
                );
            }
        }
        St::For {
            counter,
            from,
            to,
            by,
            body,
        } => {
            let make = |from: &Ex, to: &Ex, by: &Option<Ex>, body: &Vec<St>| St::For {
                counter: *counter,
                from: from.clone(),
                to: to.clone(),
                by: by.clone(),
                body: body.clone(),
            };
            if by.is_some() {
                out.push(make(from, to, &None, body));
            }
            out.extend(expr_cands(from).iter().map(|c| make(c, to, by, body)));
            out.extend(expr_cands(to).iter().map(|c| make(from, c, by, body)));
            out.extend(block_cands(body).iter().map(|c| make(from, to, by, c)));
        }
        St::While(c, body) => {
            out.extend(expr_cands(c).into_iter().map(|x| St::While(x, body.clone())));
            out.extend(block_cands(body).into_iter().map(|b| St::While(c.clone(), b)));
        }
        St::Repeat(body, c) => {
            out.extend(expr_cands(c).into_iter().map(|x| St::Repeat(body.clone(), x)));
            out.extend(block_cands(body).into_iter().map(|b| St::Repeat(b, c.clone())));
        }
        St::Exit => {}
    }
    out
}

/// Smaller expressions of the same type (so that every rule on operand
/// types still holds): an operand, a plain literal, a smaller operand.
fn expr_cands(e: &Ex) -> Vec<Ex> {
    let t = ty(e);
    let mut out: Vec<Ex> = Vec::new();
    let children: Vec<&Ex> = match e {
        Ex::Arr(x) | Ex::Neg(x) | Ex::Not(x) | Ex::Paren(x) | Ex::Call(_, x) => vec![x],
        Ex::Bin(_, l, r) => vec![l, r],
        _ => Vec::new(),
    };
    out.extend(children.iter().filter(|c| ty(c) == t).map(|c| (*c).clone()));
    match (t, e) {
        (_, Ex::Int(v, text)) if *text != v.to_string() => out.push(Ex::Int(*v, v.to_string())),
        (_, Ex::Int(..) | Ex::Real(..) | Ex::Bool(_)) => {}
        (Ty::Dint, _) => {
            out.push(Ex::Int(0, "0".into()));
            out.push(Ex::Int(1, "1".into()));
        }
        (Ty::Real, _) => out.push(Ex::Real(1.0, "1.0".into())),
        (Ty::Bool, _) => {
            out.push(Ex::Bool(false));
            out.push(Ex::Bool(true));
        }
        _ => {}
    }
    let re = |x: Ex| Box::new(x);
    match e {
        Ex::Arr(x) => out.extend(expr_cands(x).into_iter().map(|c| Ex::Arr(re(c)))),
        Ex::Neg(x) => out.extend(expr_cands(x).into_iter().map(|c| Ex::Neg(re(c)))),
        Ex::Not(x) => out.extend(expr_cands(x).into_iter().map(|c| Ex::Not(re(c)))),
        Ex::Paren(x) => out.extend(expr_cands(x).into_iter().map(|c| Ex::Paren(re(c)))),
        Ex::Call(f, x) => out.extend(expr_cands(x).into_iter().map(|c| Ex::Call(*f, re(c)))),
        Ex::Bin(op, l, r) => {
            out.extend(expr_cands(l).into_iter().map(|c| Ex::Bin(*op, re(c), r.clone())));
            out.extend(expr_cands(r).into_iter().map(|c| Ex::Bin(*op, l.clone(), re(c))));
        }
        _ => {}
    }
    out
}

/// Reduces failing program `n` greedily while it still disagrees with the
/// reference in some of the things that `what` lists, and in nothing else
/// (so as not to drift to another disagreement); the report of the
/// smallest.
fn shrink(n: u64, prog: &[St], what: &[String]) -> Option<String> {
    let fails = |p: &[St]| -> Option<String> {
        if !exits_ok(p, false) {
            return None;
        }
        let mut r = Ref::new();
        r.block(p).ok()?;
        match check(n, &print(p, None), &r) {
            Err(f) if f.what.iter().all(|w| what.contains(w)) => Some(f.report),
            _ => None,
        }
    };
    let mut best = prog.to_vec();
    let mut report = fails(&best)?;
    let mut tries = 0;
    'reduce: while tries < 20_000 {
        for c in block_cands(&best) {
            tries += 1;
            if let Some(m) = fails(&c) {
                best = c;
                report = m;
                continue 'reduce;
            }
        }
        break;
    }
    Some(report)
}

fn env_u64(name: &str) -> Option<u64> {
    std::env::var(name)
        .ok()
        .map(|v| v.parse().unwrap_or_else(|_| panic!("{name}={v}: not a number")))
}

#[test]
fn random_programs_agree_with_the_reference_evaluator() {
    let start = Instant::now();
    let programs: Vec<u64> = match env_u64("ST_RANDOM_ONLY") {
        Some(n) => vec![n],
        None => (0..env_u64("ST_RANDOM_PROGRAMS").unwrap_or(PROGRAMS)).collect(),
    };
    let single = programs.len() == 1;
    let show = env_u64("ST_RANDOM_SHOW").map_or(SHOWN, |k| k as usize);
    let reduce = env_u64("ST_RANDOM_REDUCE").map_or(REDUCED, |k| k as usize);
    let (mut failed, mut discarded, mut faults, mut statements, mut written) = (0, 0, 0, 0, 0);
    let (mut shown, mut reduced) = (Vec::new(), Vec::<String>::new());
    let routine = |report: &str| report.split_once("--- routine ---").map(|(_, r)| r.to_owned());
    for &n in &programs {
        let (prog, text, r, d) = generate(n);
        discarded += d;
        faults += r.faults;
        statements += u64::from(r.steps);
        written += size(&prog);
        if single {
            println!("{text}");
        }
        if let Err(f) = check(n, &text, &r) {
            failed += 1;
            if failed <= reduce
                && let Some(m) = shrink(n, &prog, &f.what)
                && !reduced.iter().any(|r| routine(r) == routine(&m))
            {
                reduced.push(m);
            }
            if shown.len() < show {
                shown.push(f.report);
            }
        }
    }
    println!(
        "{} programs of {written} statements ({discarded} over budget and drawn again), {statements} statements \
         and loop tests executed, {faults} minor faults expected, {failed} failing, {:.1} s",
        programs.len(),
        start.elapsed().as_secs_f64()
    );
    assert!(
        failed == 0,
        "{failed} of {} programs disagree with the reference.\n\n\
         ======== the first {} failing programs ========\n\n{}\n\n\
         ======== the first {} failing programs reduced (keywords in upper case), {} distinct ========\n\n{}",
        programs.len(),
        shown.len(),
        shown.join("\n\n"),
        failed.min(reduce),
        reduced.len(),
        reduced.join("\n\n")
    );
}
