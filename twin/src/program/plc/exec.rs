//! Executes compiled routines: expressions with the controller's
//! arithmetic, statements, timers, counters and one-shots, and the motion
//! instructions through the program's binding.
//!
//! # Arithmetic
//! * SINT, INT, USINT, UINT and DINT compute in 32 bits; UDINT, LINT and
//!   ULINT in 64. A result that does not fit wraps (two's complement) and
//!   records a minor fault (type 4, code 4): 2147483647 + 1 = −2147483648.
//! * Integer ÷ integer truncates toward zero (7/2 = 3, −7/2 = −3); `MOD`
//!   takes the dividend's sign (−7 MOD 2 = −1).
//! * Division or `MOD` by zero records the minor fault (type 4, code 4).
//!   The twin then writes, for integers, the largest value of the type
//!   with the dividend's sign (0 for 0/0) as the quotient and 0 as the
//!   remainder; for reals, the IEEE result of `/` (±∞, NaN for 0/0) and 0
//!   for `MOD`.
//! * An operation with a REAL operand computes in REAL (LREAL with an LREAL
//!   or LINT operand): integer operands are converted first (rounded to
//!   single precision), and each result is rounded to REAL; a real result
//!   that is not finite from finite operands records the minor fault.
//!   Comparisons convert the same way.
//! * `**` computes in REAL (LREAL when an operand is LREAL or LINT).
//! * `SQRT` takes the square root of the absolute value, as the
//!   controller's SQRT does; `TRUNC` gives a DINT.

use super::ir::{
    ArrayAt, AxisMember, Builtin, CExpr, CKind, CStmt, CoordMember, Func, GsvAttribute, Instance, MotionArg, MotionCall,
    MotionMember, Place, SKind,
};
use super::memory::Memory;
use super::types::{DataType, Structure, Ty, Value};
use crate::st::ast::BinaryOp;
use planner::instruction::MotionInstructionBits;
use planner::task::MotionTask;

/// Slots of statements a scan may execute: the watchdog counts each
/// executed statement (and each loop test) as [`NOMINAL_STATEMENT_US`].
pub const NOMINAL_STATEMENT_US: f64 = 1.0;

/// The deepest `JSR` nesting before the controller's stack overflows.
pub const MAX_JSR_DEPTH: usize = 32;

/// A fault the program raised while executing.
#[derive(Debug, Clone, PartialEq)]
pub struct Raised {
    /// Fault type (4 program, 6 task).
    pub fault_type: u8,
    /// Fault code.
    pub code: u8,
    /// What happened.
    pub message: String,
    /// The routine (index in its program).
    pub routine: usize,
    /// The line of the statement.
    pub line: u32,
}

/// How a block ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Flow {
    /// Normally.
    Next,
    /// By `EXIT`.
    Exit,
    /// By `RET`.
    Return,
}

/// What the binding is asked to run.
pub enum Invocation<'i> {
    /// A Logix instruction with its operand values in call order.
    Logix(&'i MotionCall, Vec<crate::st::Expr>),
    /// A function block: the instance and its named input values.
    Block(&'i str, Vec<(String, crate::st::Expr)>),
}

/// Runs motion instructions and function blocks with their operand values
/// (the program's binding); `Err` carries the refusal and the call
/// position of the operand at fault.
pub type MotionRunner<'r> =
    dyn FnMut(Invocation<'_>, &Memory, &mut MotionTask) -> Result<(), (Option<usize>, String)> + 'r;

/// One scan's state.
pub struct Exec<'e> {
    /// Tag memory.
    pub mem: &'e mut Memory,
    /// The planner.
    pub task: &'e mut MotionTask,
    /// The scan's time, µs since the start.
    pub now_us: i64,
    /// `S:FS`.
    pub first_scan: bool,
    /// The program's compiled routines (main first).
    pub routines: &'e [Vec<CStmt>],
    /// Runs motion instructions.
    pub motion: &'e mut MotionRunner<'e>,
    /// Minor faults recorded in this scan.
    pub minor: Vec<Raised>,
    /// Minor faults recorded since the start (the `MinorFaults` counter).
    pub minor_total: i64,
    /// Instruction refusals at run time, with their messages.
    pub refusals: Vec<String>,
    /// Statements executed.
    pub steps: u64,
    /// The watchdog, in statements.
    pub budget: u64,
    routine: usize,
    line: u32,
    depth: usize,
    params: Vec<Value>,
    returns: Vec<Value>,
    /// A fault raised while evaluating: the statement stops at its next
    /// check, before any further side effect.
    fault: Option<Box<Raised>>,
}

/// Faults are boxed: the happy path carries a `Value`-sized result.
type R<T> = Result<T, Box<Raised>>;

impl<'e> Exec<'e> {
    /// A scan of one program.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        mem: &'e mut Memory,
        task: &'e mut MotionTask,
        now_us: i64,
        first_scan: bool,
        routines: &'e [Vec<CStmt>],
        motion: &'e mut MotionRunner<'e>,
        minor_total: i64,
        budget: u64,
    ) -> Self {
        Exec {
            mem,
            task,
            now_us,
            first_scan,
            routines,
            motion,
            minor: Vec::new(),
            minor_total,
            refusals: Vec::new(),
            steps: 0,
            budget,
            routine: 0,
            line: 0,
            depth: 0,
            params: Vec::new(),
            returns: Vec::new(),
            fault: None,
        }
    }

    /// Records the first fault of the statement.
    fn fail(&mut self, r: Box<Raised>) {
        if self.fault.is_none() {
            self.fault = Some(r);
        }
    }

    /// The fault an evaluation raised, if any.
    fn check(&mut self) -> R<()> {
        match self.fault.take() {
            Some(f) => Err(f),
            None => Ok(()),
        }
    }

    fn raise(&self, fault_type: u8, code: u8, message: String) -> Box<Raised> {
        Box::new(Raised {
            fault_type,
            code,
            message,
            routine: self.routine,
            line: self.line,
        })
    }

    fn overflow(&mut self, what: &str) {
        let r = self.raise(4, 4, format!("arithmetic overflow: {what}"));
        self.minor.push(*r);
        self.minor_total += 1;
    }

    fn tick(&mut self) -> R<()> {
        self.check()?;
        self.steps += 1;
        if self.steps > self.budget {
            return Err(self.raise(
                6,
                1,
                format!(
                    "task watchdog expired: the scan ran past {} statements ({} µs nominal)",
                    self.budget,
                    self.budget as f64 * NOMINAL_STATEMENT_US
                ),
            ));
        }
        Ok(())
    }

    /// Runs the program's main routine.
    ///
    /// # Errors
    /// The major fault that stopped it.
    pub fn run_main(&mut self) -> R<()> {
        self.routine = 0;
        self.block(&self.routines[0]).map(|_| ())
    }

    fn block(&mut self, stmts: &[CStmt]) -> R<Flow> {
        for s in stmts {
            self.line = s.line;
            self.tick()?;
            let flow = self.stmt(s)?;
            if flow != Flow::Next {
                return Ok(flow);
            }
        }
        Ok(Flow::Next)
    }

    fn stmt(&mut self, s: &CStmt) -> R<Flow> {
        match &s.kind {
            SKind::Assign { target, ty, value, .. } => {
                let v = self.eval(value);
                self.check()?;
                self.store(target, *ty, v);
                self.check()?;
            }
            SKind::If(branches, otherwise) => {
                for (c, body) in branches {
                    let taken = self.eval(c).truthy();
                    self.check()?;
                    if taken {
                        return self.block(body);
                    }
                }
                return self.block(otherwise);
            }
            SKind::Case(sel, arms, otherwise) => {
                let x = self.eval(sel).as_i64();
                self.check()?;
                for (labels, body) in arms {
                    if labels.iter().any(|l| l.matches(x)) {
                        return self.block(body);
                    }
                }
                return self.block(otherwise);
            }
            SKind::For {
                counter,
                ty,
                from,
                to,
                by,
                body,
            } => return self.for_loop(counter, *ty, from, to, by, body),
            SKind::While(c, body) => loop {
                self.tick()?;
                let more = self.eval(c).truthy();
                self.check()?;
                if !more {
                    break;
                }
                match self.block(body)? {
                    Flow::Exit => break,
                    Flow::Return => return Ok(Flow::Return),
                    Flow::Next => {}
                }
            },
            SKind::Repeat(body, until) => loop {
                self.tick()?;
                match self.block(body)? {
                    Flow::Exit => break,
                    Flow::Return => return Ok(Flow::Return),
                    Flow::Next => {}
                }
                let done = self.eval(until).truthy();
                self.check()?;
                if done {
                    break;
                }
            },
            SKind::Exit => return Ok(Flow::Exit),
            SKind::Builtin(b, inst) => {
                let base = self.instance_base(inst);
                self.check()?;
                self.builtin(*b, base);
            }
            SKind::Jsr {
                routine,
                inputs,
                returns,
            } => self.jsr(*routine, inputs, returns)?,
            SKind::Sbr(targets) => {
                let params = std::mem::take(&mut self.params);
                for ((place, ty), v) in targets.iter().zip(params) {
                    self.store(place, *ty, v);
                    self.check()?;
                }
            }
            SKind::Ret(values) => {
                self.returns = values.iter().map(|v| self.eval(v)).collect();
                self.check()?;
                return Ok(Flow::Return);
            }
            SKind::Cop(src, dst, len) => {
                let n = self.eval(len).as_i64();
                self.check()?;
                let (s, d) = (self.array_range(src, n)?, self.array_range(dst, n)?);
                let values: Vec<Value> = self.mem.slots[s..s + n as usize].to_vec();
                self.mem.slots[d..d + n as usize].copy_from_slice(&values);
            }
            SKind::Fll(value, dst, len) => {
                let n = self.eval(len).as_i64();
                self.check()?;
                let d = self.array_range(dst, n)?;
                let v = self.eval(value);
                self.check()?;
                let (stored, bad) = dst.ty.store(v);
                if bad {
                    self.overflow("FLL source does not fit the destination");
                }
                self.mem.slots[d..d + n as usize].fill(stored);
            }
            SKind::Size(len, place, ty) => {
                self.store(place, *ty, Value::Int(*len as i64));
                self.check()?;
            }
            SKind::Gsv(axis, attribute, place, ty) => {
                let config = self.task.axis_config(*axis);
                let v = match attribute {
                    GsvAttribute::Member(m) => self.axis_member(*axis, *m),
                    GsvAttribute::MaximumSpeed => Value::Real(config.max_velocity),
                    GsvAttribute::MaximumAcceleration => Value::Real(config.max_acceleration),
                    GsvAttribute::MaximumDeceleration => Value::Real(config.max_deceleration),
                    // Axes are always enabled in the twin: Running.
                    GsvAttribute::CipAxisState => Value::Int(4),
                };
                self.store(place, *ty, v);
                self.check()?;
            }
            SKind::Motion(call) => self.motion_call(call)?,
            SKind::Block(call) => {
                let mut inputs = Vec::with_capacity(call.inputs.len());
                for (name, arg) in &call.inputs {
                    inputs.push((name.clone(), self.operand(arg, None)));
                }
                self.check()?;
                if let Err((_, message)) = (self.motion)(Invocation::Block(&call.instance, inputs), self.mem, self.task)
                {
                    self.refusals.push(format!("{} (line {}): {message}", call.instance, self.line));
                }
            }
        }
        Ok(Flow::Next)
    }

    fn for_loop(&mut self, counter: &Place, ty: DataType, from: &CExpr, to: &CExpr, by: &CExpr, body: &[CStmt]) -> R<Flow> {
        let start = self.eval(from);
        self.check()?;
        self.store(counter, ty, start);
        loop {
            self.tick()?;
            let i = self.load(counter).as_i64();
            let end = self.eval(to).as_i64();
            let step = self.eval(by).as_i64();
            self.check()?;
            if (step >= 0 && i > end) || (step < 0 && i < end) {
                return Ok(Flow::Next);
            }
            match self.block(body)? {
                Flow::Exit => return Ok(Flow::Next),
                Flow::Return => return Ok(Flow::Return),
                Flow::Next => {}
            }
            let i = self.load(counter).as_i64();
            self.store(counter, ty, Value::Int(i.wrapping_add(step)));
        }
    }

    fn jsr(&mut self, routine: usize, inputs: &[CExpr], returns: &[(Place, DataType)]) -> R<()> {
        if self.depth >= MAX_JSR_DEPTH {
            return Err(self.raise(4, 84, format!("stack overflow: JSR nested deeper than {MAX_JSR_DEPTH}")));
        }
        self.params = inputs.iter().map(|e| self.eval(e)).collect();
        self.check()?;
        self.returns.clear();
        let (caller, line) = (self.routine, self.line);
        self.depth += 1;
        self.routine = routine;
        let flow = self.block(&self.routines[routine]);
        self.depth -= 1;
        self.routine = caller;
        self.line = line;
        flow?;
        let values = std::mem::take(&mut self.returns);
        for ((place, ty), v) in returns.iter().zip(values) {
            self.store(place, *ty, v);
            self.check()?;
        }
        Ok(())
    }

    fn array_range(&mut self, a: &ArrayAt, n: i64) -> R<usize> {
        let start = self.eval(&a.start).as_i64();
        self.check()?;
        if start < 0 || n < 0 || start + n > a.len as i64 {
            return Err(self.raise(
                4,
                20,
                format!("array subscript out of range: {}[{start}] + {n} elements (the array has {})", a.name, a.len),
            ));
        }
        Ok(a.base + start as usize)
    }

    fn instance_base(&mut self, inst: &Instance) -> usize {
        match &inst.index {
            None => inst.base,
            Some((index, len)) => {
                let i = self.eval(index).as_i64();
                if i < 0 || i >= *len as i64 {
                    let f = self.subscript_fault(&inst.name, i, *len);
                    self.fail(f);
                    return inst.base;
                }
                inst.base + i as usize * inst.structure.size()
            }
        }
    }

    fn subscript_fault(&self, name: &str, i: i64, len: usize) -> Box<Raised> {
        self.raise(
            4,
            20,
            format!("array subscript out of range: {name}[{i}] (valid 0..={})", len.saturating_sub(1)),
        )
    }

    /// The slot a place reads or writes (`None` for the planner's places,
    /// or when its subscript is out of range, which records the fault).
    fn slot(&mut self, place: &Place) -> Option<usize> {
        match place {
            Place::Slot(i) => Some(*i),
            Place::Element {
                base,
                len,
                stride,
                offset,
                index,
                name,
            } => {
                let i = self.leaf(index).as_i64();
                if i < 0 || i >= *len as i64 {
                    let f = self.subscript_fault(name, i, *len);
                    self.fail(f);
                    return None;
                }
                Some(base + i as usize * stride + offset)
            }
            _ => None,
        }
    }

    fn bit_number(&mut self, bit: &CExpr, width: u32) -> Option<u32> {
        let b = self.leaf(bit).as_i64();
        if b < 0 || b >= i64::from(width) {
            let f = self.raise(4, 20, format!("bit {b} is outside a {width}-bit integer"));
            self.fail(f);
            return None;
        }
        Some(b as u32)
    }

    /// Reads a place (0 after a subscript fault, which is recorded).
    pub fn load(&mut self, place: &Place) -> Value {
        if let Place::Slot(i) = place {
            return self.mem.slots[*i];
        }
        if let Place::Element { .. } = place {
            return self.slot(place).map_or(Value::Int(0), |i| self.mem.slots[i]);
        }
        match place {
            Place::Bit { inner, width, bit, .. } => {
                let v = self.load(inner).as_i64();
                let b = self.bit_number(bit, *width).unwrap_or(0);
                Value::Bool(v >> b & 1 == 1)
            }
            Place::Motion(h, member) => {
                let bits = self.task.motion_bits(*h);
                match member {
                    MotionMember::Bit(name) => Value::Bool(bits.bit(name).unwrap_or(false)),
                    MotionMember::Err => Value::Int(i64::from(bits.err)),
                    MotionMember::Exerr => Value::Int(i64::from(bits.exerr)),
                    MotionMember::Segment => Value::Int(i64::from(bits.segment)),
                }
            }
            Place::Axis(h, m) => self.axis_member(*h, *m),
            Place::Coord(h, m) => Value::Bool(match m {
                CoordMember::Status(name) => self
                    .task
                    .coord_status(*h)
                    .bits()
                    .into_iter()
                    .find(|(n, _)| n == name)
                    .is_some_and(|(_, b)| b),
                CoordMember::TransformSource => self.task.transform_source_status(*h),
                CoordMember::TransformTarget => self.task.transform_target_status(*h),
            }),
            Place::Fb(h, m) => {
                let o = self.task.outputs(*h);
                match m {
                    super::ir::FbMember::Bit(name) => Value::Bool(o.bits().into_iter().any(|(n, b)| n == *name && b)),
                    super::ir::FbMember::ErrorId => Value::Int(i64::from(o.error_id)),
                }
            }
            Place::FirstScan => Value::Bool(self.first_scan),
            Place::MinorInScan => Value::Bool(!self.minor.is_empty()),
            Place::MinorFaults => Value::Int(self.minor_total.min(i64::from(i32::MAX))),
            Place::Slot(_) | Place::Element { .. } => unreachable!("slots read above"),
        }
    }

    fn axis_member(&self, h: planner::task::AxisHandle, m: AxisMember) -> Value {
        let s = self.task.axis_state(h);
        let real = |x: f64| Value::Real(f64::from(x as f32));
        match m {
            AxisMember::ActualPosition => real(s.actual_position),
            AxisMember::CommandPosition => real(s.command_position),
            AxisMember::ActualVelocity => real(s.actual_velocity),
            AxisMember::CommandVelocity => real(s.command_velocity),
            AxisMember::CommandAcceleration => real(s.command_acceleration),
            AxisMember::CoordinatedMotionStatus => Value::Bool(self.task.coordinated_motion_status(h)),
            AxisMember::PositionCamStatus => Value::Bool(self.task.slave_cam_status(h).position_cam),
            AxisMember::PositionCamLockStatus => Value::Bool(self.task.slave_cam_status(h).lock),
            AxisMember::PositionCamPendingStatus => Value::Bool(self.task.slave_cam_status(h).pending),
            AxisMember::TransformStateStatus => Value::Bool(self.task.transform_state_status(h)),
            AxisMember::ControlledByTransformStatus => Value::Bool(self.task.controlled_by_transform_status(h)),
        }
    }

    /// Writes a place, converting to its type; nothing after a fault of the
    /// statement (a subscript out of range is recorded).
    pub fn store(&mut self, place: &Place, ty: DataType, v: Value) {
        if self.fault.is_some() {
            return;
        }
        // The common case, a DINT value into a DINT, needs no conversion.
        let (stored, bad) = match (ty, v) {
            (DataType::Dint, Value::Int(x)) if i32::try_from(x).is_ok() => (v, false),
            _ => ty.store(v),
        };
        if bad {
            self.overflow(&format!("the value does not fit {}", ty.name()));
        }
        if let Place::Slot(i) = place {
            self.mem.slots[*i] = stored;
            return;
        }
        if let Place::Element { .. } = place {
            if let Some(i) = self.slot(place) {
                self.mem.slots[i] = stored;
            }
            return;
        }
        match place {
            Place::Bit { inner, width, bit, ty } => {
                let Some(b) = self.bit_number(bit, *width) else { return };
                let old = self.load(inner).as_i64();
                let new = if stored.truthy() { old | 1 << b } else { old & !(1 << b) };
                let (value, _) = ty.store(Value::Int(ty.wrap(i128::from(new))));
                self.store(inner, *ty, value);
            }
            Place::Motion(h, MotionMember::Bit(name)) => {
                let mut bits = self.task.motion_bits(*h);
                set_bit(&mut bits, name, stored.truthy());
                self.task.set_motion_bits(*h, bits);
            }
            _ => unreachable!("the compiler refuses writes to read-only places"),
        }
    }

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
                if *math == Ty::Bool {
                    let y = self.leaf(b);
                    return Value::Bool(match op {
                        BinaryOp::And => x.truthy() && y.truthy(),
                        BinaryOp::Or => x.truthy() || y.truthy(),
                        BinaryOp::Xor => x.truthy() != y.truthy(),
                        _ => unreachable!("BOOL math is logic only"),
                    });
                }
                let y = self.leaf(b);
                self.binary(*op, x, y, *math)
            }
            CKind::Func(f, a) => {
                let v = self.eval(a);
                self.function(*f, v, a.ty, e.ty)
            }
        }
    }

    fn dint_result(&mut self, r: i64, what: &str) -> Value {
        if i32::try_from(r).is_ok() {
            Value::Int(r)
        } else {
            self.int_result(i128::from(r), Ty::Dint, what)
        }
    }

    /// [`Exec::eval`] with the leaves read in place.
    #[inline]
    fn leaf(&mut self, e: &CExpr) -> Value {
        match &e.kind {
            CKind::Const(v) => *v,
            CKind::Slot(i) => self.mem.slots[*i],
            _ => self.eval(e),
        }
    }

    fn int_result(&mut self, r: i128, ty: Ty, what: &str) -> Value {
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

    fn real_result(&mut self, r: f64, ty: Ty, finite_in: bool) -> Value {
        let r = if ty == Ty::Real { f64::from(r as f32) } else { r };
        if finite_in && !r.is_finite() {
            self.overflow(&format!("the {} result is not finite", ty.name()));
        }
        Value::Real(r)
    }

    fn binary(&mut self, op: BinaryOp, x: Value, y: Value, math: Ty) -> Value {
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
            let max = if math == Ty::Dint { i128::from(i32::MAX) } else { i128::from(i64::MAX) };
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
                    Value::Int(if math == Ty::Dint { i64::from(r as i32) } else { r as i64 })
                }
                B::Lt => Value::Bool(a < b),
                B::Le => Value::Bool(a <= b),
                B::Gt => Value::Bool(a > b),
                B::Ge => Value::Bool(a >= b),
                B::Eq => Value::Bool(a == b),
                B::Ne => Value::Bool(a != b),
                B::Pow => unreachable!("** computes in REAL"),
            };
        }
        // Operands are converted to the math type first (a DINT becomes a
        // REAL, rounded, before a REAL operation).
        let to_math = |v: Value| if math == Ty::Real { f64::from(v.as_f64() as f32) } else { v.as_f64() };
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
            B::Lt => Value::Bool(a < b),
            B::Le => Value::Bool(a <= b),
            B::Gt => Value::Bool(a > b),
            B::Ge => Value::Bool(a >= b),
            B::Eq => Value::Bool(a == b),
            B::Ne => Value::Bool(a != b),
            B::And | B::Or | B::Xor => unreachable!("the compiler refuses bitwise REAL"),
        }
    }

    fn function(&mut self, f: Func, v: Value, arg: Ty, result: Ty) -> Value {
        if f == Func::Abs && arg.is_integer() {
            return self.int_result(i128::from(v.as_i64()).abs(), arg, "ABS");
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
            Func::Trunc => {
                let t = x.trunc();
                return if t.is_finite() {
                    self.int_result(t as i128, Ty::Dint, "TRUNC")
                } else {
                    self.overflow("TRUNC of a value that is not finite");
                    Value::Int(0)
                };
            }
        };
        self.real_result(y, result, x.is_finite())
    }

    fn get(&self, base: usize, s: Structure, member: &str) -> Value {
        self.mem.slots[base + s.offset(member)]
    }

    fn set(&mut self, base: usize, s: Structure, member: &str, v: Value) {
        self.mem.slots[base + s.offset(member)] = v;
    }

    fn flag(&self, base: usize, s: Structure, member: &str) -> bool {
        self.get(base, s, member).truthy()
    }

    fn builtin(&mut self, b: Builtin, base: usize) {
        use Structure as S;
        match b {
            Builtin::Tonr | Builtin::Tofr | Builtin::Rtor => self.timer(b, base),
            Builtin::Ctud => self.counter(base),
            Builtin::Osri | Builtin::Osfi => {
                let enabled = self.flag(base, S::OneShot, "EnableIn");
                self.set(base, S::OneShot, "EnableOut", Value::Bool(enabled));
                if !enabled {
                    return;
                }
                let input = self.flag(base, S::OneShot, "InputBit");
                let last = if self.first_scan {
                    b == Builtin::Osri
                } else {
                    self.flag(base, S::OneShot, "InputBitLast")
                };
                let out = if b == Builtin::Osri { input && !last } else { !input && last };
                self.set(base, S::OneShot, "OutputBit", Value::Bool(out));
                self.set(base, S::OneShot, "InputBitLast", Value::Bool(input));
            }
            Builtin::RTrig | Builtin::FTrig => {
                let clk = self.flag(base, S::Trig, "CLK");
                let m = self.flag(base, S::Trig, "M");
                let q = if b == Builtin::RTrig { clk && !m } else { !clk && m };
                self.set(base, S::Trig, "Q", Value::Bool(q));
                self.set(base, S::Trig, "M", Value::Bool(clk));
            }
            Builtin::Ton | Builtin::Tof => self.iec_timer(b == Builtin::Ton, base),
        }
    }

    /// Whole milliseconds since the timer's last execution while timing;
    /// the remainder carries to the next execution.
    fn elapsed_ms(&mut self, base: usize, starting: bool) -> i64 {
        let s = Structure::Timer;
        let last = self.get(base, s, "LastScan_us").as_i64();
        if starting {
            self.set(base, s, "LastScan_us", Value::Int(self.now_us));
            return 0;
        }
        let ms = (self.now_us - last).max(0) / 1000;
        self.set(base, s, "LastScan_us", Value::Int(last + ms * 1000));
        ms
    }

    fn timer(&mut self, b: Builtin, base: usize) {
        let s = Structure::Timer;
        let enabled = self.flag(base, s, "EnableIn");
        self.set(base, s, "EnableOut", Value::Bool(enabled));
        if !enabled {
            return;
        }
        let pre = self.get(base, s, "PRE").as_i64();
        let mut acc = self.get(base, s, "ACC").as_i64();
        let was_en = self.flag(base, s, "EN");
        let mut dn = self.flag(base, s, "DN");
        let enable = self.flag(base, s, "TimerEnable");
        if pre < 0 {
            self.set(base, s, "PresetInv", Value::Bool(true));
            self.set(base, s, "InstructFault", Value::Bool(true));
            self.set(base, s, "Status", Value::Int(1));
            self.set(base, s, "TT", Value::Bool(false));
            self.set(base, s, "DN", Value::Bool(false));
            self.set(base, s, "EN", Value::Bool(enable));
            return;
        }
        self.set(base, s, "PresetInv", Value::Bool(false));
        self.set(base, s, "InstructFault", Value::Bool(false));
        self.set(base, s, "Status", Value::Int(0));
        if self.flag(base, s, "Reset") {
            for m in ["ACC", "EN", "TT", "DN"] {
                self.set(base, s, m, if m == "ACC" { Value::Int(0) } else { Value::Bool(false) });
            }
            return;
        }
        let timing = match b {
            Builtin::Tofr => !enable && dn,
            _ => enable && !dn,
        };
        let starting = match b {
            Builtin::Tofr => was_en || !self.flag(base, s, "TT"),
            _ => !was_en || !self.flag(base, s, "TT"),
        };
        if timing {
            acc = (acc + self.elapsed_ms(base, starting)).min(pre);
        }
        match b {
            Builtin::Tonr => {
                if !enable {
                    acc = 0;
                }
                dn = enable && acc >= pre;
            }
            Builtin::Rtor => dn = dn || acc >= pre,
            _ => {
                if enable {
                    acc = 0;
                    dn = true;
                } else if acc >= pre {
                    dn = false;
                }
            }
        }
        let tt = match b {
            Builtin::Tofr => !enable && dn,
            _ => enable && !dn,
        };
        self.set(base, s, "ACC", Value::Int(acc));
        self.set(base, s, "EN", Value::Bool(enable));
        self.set(base, s, "DN", Value::Bool(dn));
        self.set(base, s, "TT", Value::Bool(tt));
    }

    fn iec_timer(&mut self, on: bool, base: usize) {
        let s = Structure::IecTimer;
        let input = self.flag(base, s, "IN");
        let pt = self.get(base, s, "PT").as_i64().max(0);
        let running = self.flag(base, s, "Running");
        let timing = if on { input } else { !input };
        if timing && !running {
            self.set(base, s, "Start_us", Value::Int(self.now_us));
        }
        self.set(base, s, "Running", Value::Bool(timing));
        let et = if timing {
            ((self.now_us - self.get(base, s, "Start_us").as_i64()) / 1000).min(pt)
        } else {
            0
        };
        let done = timing && et >= pt;
        self.set(base, s, "ET", Value::Int(et));
        self.set(base, s, "Q", Value::Bool(if on { done } else { input || !done }));
    }

    fn counter(&mut self, base: usize) {
        let s = Structure::Counter;
        let enabled = self.flag(base, s, "EnableIn");
        self.set(base, s, "EnableOut", Value::Bool(enabled));
        if !enabled {
            return;
        }
        let up = self.flag(base, s, "CUEnable");
        let down = self.flag(base, s, "CDEnable");
        if self.first_scan {
            self.set(base, s, "CU", Value::Bool(true));
            self.set(base, s, "CD", Value::Bool(true));
        }
        let mut acc = self.get(base, s, "ACC").as_i64();
        if self.flag(base, s, "Reset") {
            acc = 0;
            self.set(base, s, "OV", Value::Bool(false));
            self.set(base, s, "UN", Value::Bool(false));
        } else {
            if up && !self.flag(base, s, "CU") {
                if acc == i64::from(i32::MAX) {
                    self.set(base, s, "OV", Value::Bool(true));
                }
                acc = i64::from((acc as i32).wrapping_add(1));
            }
            if down && !self.flag(base, s, "CD") {
                if acc == i64::from(i32::MIN) {
                    self.set(base, s, "UN", Value::Bool(true));
                }
                acc = i64::from((acc as i32).wrapping_sub(1));
            }
        }
        self.set(base, s, "CU", Value::Bool(up));
        self.set(base, s, "CD", Value::Bool(down));
        self.set(base, s, "ACC", Value::Int(acc));
        let pre = self.get(base, s, "PRE").as_i64();
        self.set(base, s, "DN", Value::Bool(acc >= pre));
    }

    /// An operand as the binding reads it (`kind`: the operand's catalogue
    /// kind, which decides integer or number; `None` keeps the value's own).
    fn operand(&mut self, arg: &MotionArg, kind: Option<planner::catalogue::Kind>) -> crate::st::Expr {
        match arg {
            MotionArg::Name(n) => crate::st::Expr::Ident(n.clone()),
            MotionArg::Element(n, index) => {
                let i = self.eval(index).as_i64();
                crate::st::Expr::Index(Box::new(crate::st::Expr::Ident(n.clone())), i)
            }
            MotionArg::Value(e) => {
                let v = self.eval(e);
                match (kind, v) {
                    (Some(k), _) => super::compile::operand_expr(k, v),
                    (None, Value::Bool(b)) => crate::st::Expr::Bool(b),
                    (None, Value::Int(i)) => crate::st::Expr::Integer(i),
                    (None, Value::Real(x)) => crate::st::Expr::Number(x),
                }
            }
        }
    }

    fn motion_call(&mut self, call: &MotionCall) -> R<()> {
        let mut exprs = Vec::with_capacity(call.args.len());
        for (spec, arg) in call.instruction.operands.iter().zip(&call.args) {
            exprs.push(self.operand(arg, Some(spec.kind)));
        }
        self.check()?;
        if let Err((operand, message)) = (self.motion)(Invocation::Logix(call, exprs), self.mem, self.task) {
            // An operand value the instruction cannot take: ERR 13 with the
            // operand's faceplate index, as the controller reports it.
            if let Some(control) = call.control {
                let exerr = operand
                    .and_then(|i| call.instruction.operands.get(i))
                    .map_or(0, |o| o.faceplate.max(0));
                let mut bits = MotionInstructionBits {
                    en: true,
                    ..MotionInstructionBits::default()
                };
                bits.set_error(13, exerr, 0);
                self.task.set_motion_bits(control, bits);
            }
            self.refusals.push(format!("{} (line {}): {message}", call.instruction.mnemonic, self.line));
        }
        Ok(())
    }
}

/// Sets a `MOTION_INSTRUCTION` bit by its name.
fn set_bit(bits: &mut MotionInstructionBits, name: &str, v: bool) {
    match name {
        "EN" => bits.en = v,
        "DN" => bits.dn = v,
        "ER" => bits.er = v,
        "IP" => bits.ip = v,
        "AC" => bits.ac = v,
        "PC" => bits.pc = v,
        "ACCEL" => bits.accel = v,
        _ => bits.decel = v,
    }
}
