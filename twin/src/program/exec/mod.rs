//! Executes compiled routines: expressions with the controller's
//! arithmetic, statements, timers, counters and one-shots, and instruction
//! calls: their operands evaluated and handed to the instruction
//! ([`planner::task::instructions::Instruction::execute`], `motion.rs`). It only evaluates what the
//! compiler produced: no name is looked up and nothing is parsed here.
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

use super::ir::{ArrayAt, CExpr, CStmt, GsvAttribute, Instance, MotionCall, Place, SKind};
use super::memory::Memory;
use super::types::{DataType, Value};
use planner::instruction::Fault;
use planner::task::MotionTask;

mod arith;
mod builtins;
pub(super) mod members;
pub(super) mod motion;
mod places;
mod scratch;

pub use scratch::Scratch;

/// Executes a `[[program]]` step's call: its operands are constants and
/// references the compiler checked, read from tag memory now.
///
/// # Errors
/// The instruction's refusal.
pub fn call(mem: &mut Memory, task: &mut MotionTask, scratch: &mut Scratch, call: &MotionCall) -> Result<(), Fault> {
    let now_us = (task.time_s() * 1e6).round() as i64;
    let mut exec = Exec::new(mem, task, now_us, false, &[], scratch, 0, u64::MAX);
    match exec.execute_call(call) {
        Ok(result) => result,
        // A step's operands are constants and references with constant
        // subscripts the compiler checked: nothing there can fault.
        Err(raised) => unreachable!("a step's operand faulted: {}", raised.message),
    }
}

/// The value of a compiled expression now, outside a scan (a step's
/// `when`, a scene's expression): it reads tag memory and the planner.
#[must_use]
pub fn evaluate(mem: &mut Memory, task: &mut MotionTask, scratch: &mut Scratch, e: &CExpr) -> Value {
    let now_us = (task.time_s() * 1e6).round() as i64;
    let mut exec = Exec::new(mem, task, now_us, false, &[], scratch, 0, u64::MAX);
    exec.eval(e)
}

/// The value of an expectation's compiled expression now: it reads tag
/// memory, the planner and `columns`, the trace row's values
/// ([`Place::Column`]). What it records (a minor fault) is dropped.
#[must_use]
pub fn evaluate_with_columns(
    mem: &mut Memory,
    task: &mut MotionTask,
    scratch: &mut Scratch,
    e: &CExpr,
    columns: &[f64],
) -> Value {
    let now_us = (task.time_s() * 1e6).round() as i64;
    let mut exec = Exec::new(mem, task, now_us, false, &[], scratch, 0, u64::MAX);
    exec.columns = columns;
    exec.eval(e)
}

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
    /// Room for the operand values of an instruction call.
    pub scratch: &'e mut Scratch,
    /// Minor faults recorded in this scan.
    pub minor: Vec<Raised>,
    /// Minor faults recorded since the start (the `MinorFaults` counter).
    pub minor_total: i64,
    /// Instruction refusals of an operand's value (ERR 13) and SSV
    /// refusals, with their messages.
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
    /// The trace columns an expectation reads ([`Place::Column`]); empty
    /// in a scan.
    pub columns: &'e [f64],
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
        scratch: &'e mut Scratch,
        minor_total: i64,
        budget: u64,
    ) -> Self {
        Exec {
            mem,
            task,
            now_us,
            first_scan,
            routines,
            scratch,
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
            columns: &[],
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
            SKind::Ret(values) => {
                self.returns = values.iter().map(|v| self.eval(v)).collect();
                self.check()?;
                return Ok(Flow::Return);
            }
            other => self.instruction(other)?,
        }
        Ok(Flow::Next)
    }

    /// The instructions that are not control flow.
    fn instruction(&mut self, kind: &SKind) -> R<()> {
        match kind {
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
                    GsvAttribute::Member(m) => members::axis_value(self.task, *axis, *m),
                    GsvAttribute::MaximumSpeed => Value::Real(config.max_velocity),
                    GsvAttribute::MaximumAcceleration => Value::Real(config.max_acceleration),
                    GsvAttribute::MaximumDeceleration => Value::Real(config.max_deceleration),
                };
                self.store(place, *ty, v);
                self.check()?;
            }
            SKind::Ssv(axis, limit, value) => {
                let v = self.eval(value).as_f64();
                self.check()?;
                if let Err(e) = self.task.set_axis_limit(*axis, *limit, v) {
                    let name = self.task.axis_config(*axis).name.clone();
                    self.refusals.push(format!("SSV {name} (line {}): {e}", self.line));
                }
            }
            SKind::Motion(call) => self.motion_call(call)?,
            _ => unreachable!("control flow is executed by stmt"),
        }
        Ok(())
    }

    fn for_loop(
        &mut self,
        counter: &Place,
        ty: DataType,
        from: &CExpr,
        to: &CExpr,
        by: &CExpr,
        body: &[CStmt],
    ) -> R<Flow> {
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
                format!(
                    "array subscript out of range: {}[{start}] + {n} elements (the array has {})",
                    a.name, a.len
                ),
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
            format!(
                "array subscript out of range: {name}[{i}] (valid 0..={})",
                len.saturating_sub(1)
            ),
        )
    }
}
