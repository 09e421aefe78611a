//! Executes compiled routines: expressions with the controller's
//! arithmetic, statements, timers, counters and one-shots, and instruction
//! calls: their operands evaluated and handed to the instruction
//! ([`planner::task::instructions::Instruction::execute`], `motion.rs`). It only evaluates what the
//! compiler produced: no name is looked up and nothing is parsed here.
//!
//! # Scans that stop and resume
//! Statements run from a stack of frames (a block and its next statement,
//! a loop between passes, a JSR's return, a fault routine), not by
//! recursion, so a scan can stop before any statement when the clock
//! reaches the scheduler's stop time ([`Exec::run`] gives a [`Paused`]:
//! each frame as indices into the compiled routines) and resume there
//! ([`Exec::resume`]). An instruction fault (type 4) in a program with a
//! fault routine runs that routine on top of the frames; when it clears
//! the program's `MajorFaultRecord` (Type and Code 0) the scan goes on with
//! the statement after the faulted one (1756-PM014, *Recover from a major
//! fault*), else the fault stops the scan, as does any fault raised inside
//! the fault routine.
//!
//! # Arithmetic
//! * SINT, INT, USINT, UINT and DINT compute in 32 bits; UDINT and LINT
//!   in 64. A result that does not fit wraps (two's complement) and
//!   records a minor fault (type 4, code 4): 2147483647 + 1 = −2147483648.
//! * An operation with a ULINT operand (and no real one) computes unsigned
//!   in 64 bits, a signed operand taken at its value: results outside
//!   0 to 2⁶⁴ − 1 keep their low 64 bits and record the minor fault
//!   (0 − 1 = 18446744073709551615). A literal past LINT is a ULINT. A
//!   ULINT assigned to a signed integer that cannot hold it, or a negative
//!   integer assigned to a ULINT, keeps the low bits and records the
//!   minor fault; a ULINT in a REAL or LREAL operation or assignment is
//!   its unsigned value.
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
    ArrayAt, CExpr, CStmt, DataAt, GsvAttribute, Instance, Ladder, MotionCall, Object, Place, SKind, SsvAttribute,
    SysData, Term,
};
use super::layout::Elem;
use super::memory::Memory;
use super::system::{Attribute, Class, System};
use super::types::{DataType, Ty, Value};
use planner::instruction::Fault;
use planner::task::MotionTask;

mod arith;
mod builtins;
mod frame;
mod ladder;
pub(super) mod members;
pub(super) mod motion;
mod places;
mod power;
mod scratch;
mod strings;

use frame::{Frame, recycle};
pub use scratch::Scratch;

/// Executes a `[[program]]` step's call: its operands are constants and
/// references the compiler checked, read from tag memory now.
///
/// # Errors
/// The instruction's refusal.
pub fn call(mem: &mut Memory, task: &mut MotionTask, scratch: &mut Scratch, call: &MotionCall) -> Result<(), Fault> {
    let mut exec = Exec::outside(mem, task, scratch);
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
    Exec::outside(mem, task, scratch).eval(e)
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
    let mut exec = Exec::outside(mem, task, scratch);
    exec.columns = columns;
    exec.eval(e)
}

/// The nominal time of one executed statement (and one loop test) unless
/// `[controller] statement_us` says otherwise, µs.
pub const NOMINAL_STATEMENT_US: f64 = crate::scene::DEFAULT_STATEMENT_US;

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

/// A [`Frame`] without its references: which statement and block, to
/// find them again in the same compiled routines.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Saved {
    Block {
        pc: usize,
        sub: u32,
    },
    Loop {
        started: bool,
    },
    Call {
        caller: usize,
        line: u32,
        power: power::Power,
    },
    FaultRoutine {
        caller: usize,
        line: u32,
        power: power::Power,
    },
}

/// A program's scan stopped between two statements, to resume where it
/// stopped.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Paused {
    frames: Vec<Saved>,
    routine: usize,
    line: u32,
    depth: usize,
    params: Vec<Value>,
    returns: Vec<Value>,
    fault: Option<Box<Raised>>,
    power: power::Power,
    math_flags: u8,
}

/// How far a scan got.
#[derive(Debug, Clone, PartialEq)]
pub enum Progress {
    /// The program's scan ended.
    Done,
    /// It stopped at its stop time, between two statements.
    Paused(Paused),
}

/// The statement of a block of statement `s` (IF and CASE: each branch,
/// then ELSE; a loop: its body).
fn sub_block(s: &CStmt, sub: u32) -> &[CStmt] {
    let sub = sub as usize;
    match &s.kind {
        SKind::If(branches, otherwise) => branches.get(sub).map_or(otherwise.as_slice(), |(_, b)| b.as_slice()),
        SKind::Case(_, arms, otherwise) => arms.get(sub).map_or(otherwise.as_slice(), |(_, b)| b.as_slice()),
        SKind::For { body, .. } | SKind::While(_, body) | SKind::Repeat(body, _) => body,
        _ => &[],
    }
}

/// One scan's state.
pub struct Exec<'e> {
    /// Tag memory.
    pub mem: &'e mut Memory,
    /// The planner.
    pub task: &'e mut MotionTask,
    /// The scan's time (its trigger's), µs since the start: what timers
    /// measure with.
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
    /// The controller's clock, ns: each statement and loop test advances
    /// it by `statement_ns`.
    pub clock_ns: i64,
    /// Where the scan stops (before the next statement) to let the
    /// scheduler run something else.
    pub stop_ns: i64,
    /// The nominal time of one statement, ns.
    pub statement_ns: i64,
    /// The watchdog expires when the clock passes this.
    pub watchdog_ns: i64,
    /// The watchdog's time, for its message.
    pub watchdog_us: f64,
    /// Whether an overflow records minor fault 4/4
    /// (`report_overflow_faults`).
    pub report_overflow: bool,
    /// The program's fault routine, if it has one.
    pub fault_routine: Option<usize>,
    /// The system objects, with the scan's task and program (their
    /// indices); `None` outside a scan.
    pub system: Option<(&'e mut System, usize, usize)>,
    /// Event tasks an `EVENT` triggered (their indices), for the
    /// scheduler.
    pub events: Vec<usize>,
    /// Major faults the fault routine cleared in this run.
    pub cleared: Vec<Raised>,
    frames: Vec<Frame<'e>>,
    routine: usize,
    line: u32,
    depth: usize,
    params: Vec<Value>,
    returns: Vec<Value>,
    /// The fault the fault routine is running for.
    handling: Option<Box<Raised>>,
    /// The fault routine left its fault standing: it stops the scan.
    uncleared: bool,
    /// A fault raised while evaluating: the statement stops at its next
    /// check, before any further side effect.
    fault: Option<Box<Raised>>,
    /// The trace columns an expectation reads ([`Place::Column`]); empty
    /// in a scan.
    pub columns: &'e [f64],
    /// The math status flags ([`crate::program::ir::MATH_N`] …) the last
    /// ladder instruction that sets them left.
    pub math_flags: u8,
    /// The rung condition and branches of the ladder rung executing.
    power: power::Power,
    /// Whether an arithmetic overflow happened since it was last cleared
    /// (a ladder instruction's `S:V`).
    overflowed: bool,
    /// A ladder `JMP` taken: the statement the routine goes on at.
    jump: Option<usize>,
    /// The first of the program's routines an Add-On Instruction call
    /// site added: a fault the fault routine clears inside one cancels the
    /// rest of the instruction.
    pub aoi_from: usize,
}

impl Drop for Exec<'_> {
    /// Gives the frame stack's allocation back to the scratch.
    fn drop(&mut self) {
        if self.frames.capacity() > 0 {
            self.scratch.frames = recycle(std::mem::take(&mut self.frames));
        }
    }
}

/// Faults are boxed: the happy path carries a `Value`-sized result.
type R<T> = Result<T, Box<Raised>>;

impl<'e> Exec<'e> {
    /// An executor outside any scan: a step's call, an expression.
    pub fn outside(mem: &'e mut Memory, task: &'e mut MotionTask, scratch: &'e mut Scratch) -> Self {
        let now_us = (task.time_s() * 1e6).round() as i64;
        Exec::new(mem, task, now_us, false, &[], scratch, 0)
    }

    /// A scan of one program, starting at its main routine (or where
    /// [`Exec::resume`] puts it), its clock at 0 until the caller sets it.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        mem: &'e mut Memory,
        task: &'e mut MotionTask,
        now_us: i64,
        first_scan: bool,
        routines: &'e [Vec<CStmt>],
        scratch: &'e mut Scratch,
        minor_total: i64,
    ) -> Self {
        let statement_ns = (NOMINAL_STATEMENT_US * 1000.0) as i64;
        let frames = if scratch.frames.capacity() == 0 {
            Vec::new()
        } else {
            recycle(std::mem::take(&mut scratch.frames))
        };
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
            clock_ns: 0,
            stop_ns: i64::MAX,
            statement_ns,
            watchdog_ns: i64::MAX,
            watchdog_us: f64::INFINITY,
            report_overflow: true,
            fault_routine: None,
            system: None,
            events: Vec::new(),
            cleared: Vec::new(),
            frames,
            routine: 0,
            line: 0,
            depth: 0,
            params: Vec::new(),
            returns: Vec::new(),
            handling: None,
            uncleared: false,
            fault: None,
            columns: &[],
            math_flags: 0,
            power: power::Power::default(),
            overflowed: false,
            jump: None,
            aoi_from: usize::MAX,
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
        self.overflowed = true;
        if !self.report_overflow {
            return;
        }
        let r = self.raise(4, 4, format!("arithmetic overflow: {what}"));
        self.minor.push(*r);
        self.minor_total += 1;
        let clock_ns = self.clock_ns;
        if let Some((sys, _, program)) = self.system.as_mut() {
            sys.minor_events += 1;
            sys.minor_fault_bits |= 1 << 4;
            sys.programs[*program].minor_record = sys.record(clock_ns, 4, 4);
        }
    }

    /// A ULINT written to a signed integer that cannot hold its value, or
    /// a negative integer written to a ULINT, records the overflow minor
    /// fault (the store keeps the low bits, as for any integer that does
    /// not fit): storing alone reads an integer's bits the same either way.
    #[cold]
    fn check_sign_change(&mut self, from: Ty, to: DataType, v: Value) {
        let Value::Int(bits) = v else { return };
        let lost = match (from, to) {
            (Ty::Ulint, DataType::Ulint) => false,
            (Ty::Ulint, to) if to.math().is_integer() => {
                let wide = i128::from(bits as u64);
                i128::from(to.wrap(wide)) != wide
            }
            (Ty::Dint | Ty::Lint, DataType::Ulint) => bits < 0,
            _ => false,
        };
        if lost {
            self.overflow(&format!("the value does not fit {}", to.name()));
        }
    }

    /// One statement (or loop test) executed: the clock advances and the
    /// watchdog is checked.
    #[inline(always)]
    fn tick(&mut self) -> R<()> {
        self.check()?;
        self.steps += 1;
        self.clock_ns += self.statement_ns;
        if self.clock_ns > self.watchdog_ns {
            return Err(self.watchdog());
        }
        Ok(())
    }

    #[cold]
    #[inline(never)]
    fn watchdog(&self) -> Box<Raised> {
        self.raise(
            6,
            1,
            format!(
                "task watchdog expired: the scan ran longer than {} µs (statements at {} µs nominal, higher-priority tasks and coarse updates included)",
                self.watchdog_us,
                self.statement_ns as f64 / 1000.0
            ),
        )
    }

    /// Runs the program's main routine from its start, to its end.
    ///
    /// # Errors
    /// The major fault that stopped it.
    pub fn run_main(&mut self) -> R<()> {
        self.start();
        match self.run()? {
            Progress::Done => Ok(()),
            Progress::Paused(_) => unreachable!("a scan with no stop time runs to its end"),
        }
    }

    /// Runs routine `k` from its start to its end (an Add-On
    /// Instruction's Prescan routine, at prescan).
    ///
    /// # Errors
    /// The fault that stopped it.
    pub fn run_routine(&mut self, k: usize) -> R<()> {
        self.frames.clear();
        self.routine = k;
        self.depth = 0;
        if let Some(body) = self.routines.get(k) {
            self.frames.push(Frame::Block {
                stmts: body,
                pc: 0,
                sub: k as u32,
            });
        }
        self.run().map(|_| ())
    }

    /// Puts the scan at the start of the main routine.
    pub fn start(&mut self) {
        self.frames.clear();
        self.routine = 0;
        self.depth = 0;
        if let Some(main) = self.routines.first() {
            self.frames.push(Frame::Block {
                stmts: main,
                pc: 0,
                sub: 0,
            });
        }
    }

    /// Puts the scan where `paused` stopped.
    pub fn resume(&mut self, paused: Paused) {
        self.frames.clear();
        let routines = self.routines;
        let mut frames: Vec<Frame<'e>> = Vec::with_capacity(paused.frames.len());
        for saved in &paused.frames {
            // The statement that holds the next frame: the one before the
            // enclosing block's `pc`.
            let holder = match frames.last() {
                Some(Frame::Block { stmts, pc, .. }) => pc.checked_sub(1).map(|i| &stmts[i]),
                Some(Frame::Loop { stmt, .. }) => Some(*stmt),
                _ => None,
            };
            let frame = match *saved {
                Saved::Block { pc, sub } => {
                    let stmts: &'e [CStmt] = match holder {
                        Some(s) if !matches!(frames.last(), Some(Frame::Call { .. } | Frame::FaultRoutine { .. })) => {
                            sub_block(s, sub)
                        }
                        _ => &routines[sub as usize],
                    };
                    Frame::Block { stmts, pc, sub }
                }
                Saved::Loop { started } => Frame::Loop {
                    stmt: holder.expect("a loop sits in a block"),
                    started,
                },
                Saved::Call { caller, line, power } => {
                    let returns: &'e [(Place, DataType)] = match holder.map(|s| &s.kind) {
                        Some(SKind::Jsr { returns, .. }) => returns,
                        Some(SKind::Ladder(l)) => match &**l {
                            super::ir::Ladder::OnTrue(SKind::Jsr { returns, .. }) => returns,
                            _ => &[],
                        },
                        _ => &[],
                    };
                    Frame::Call {
                        caller,
                        line,
                        returns,
                        power,
                    }
                }
                Saved::FaultRoutine { caller, line, power } => Frame::FaultRoutine { caller, line, power },
            };
            frames.push(frame);
        }
        self.frames = frames;
        self.routine = paused.routine;
        self.line = paused.line;
        self.depth = paused.depth;
        self.params = paused.params;
        self.returns = paused.returns;
        self.handling = paused.fault;
        self.power = paused.power;
        self.math_flags = paused.math_flags;
    }

    fn pause(&mut self) -> Paused {
        Paused {
            frames: self
                .frames
                .iter()
                .map(|f| match *f {
                    Frame::Block { pc, sub, .. } => Saved::Block { pc, sub },
                    Frame::Loop { started, .. } => Saved::Loop { started },
                    Frame::Call {
                        caller, line, power, ..
                    } => Saved::Call { caller, line, power },
                    Frame::FaultRoutine { caller, line, power } => Saved::FaultRoutine { caller, line, power },
                })
                .collect(),
            routine: self.routine,
            line: self.line,
            depth: self.depth,
            params: std::mem::take(&mut self.params),
            returns: std::mem::take(&mut self.returns),
            fault: self.handling.take(),
            power: self.power,
            math_flags: self.math_flags,
        }
    }

    /// Runs the scan until its end, or until the clock reaches `stop_ns`
    /// (it then stops before its next statement).
    ///
    /// # Errors
    /// The major fault that stopped it (an instruction fault the fault
    /// routine did not clear, a watchdog).
    pub fn run(&mut self) -> R<Progress> {
        loop {
            let depth = self.frames.len();
            let (stmts, at) = match self.frames.last() {
                None => return Ok(Progress::Done),
                Some(Frame::Block { stmts, pc, .. }) => (*stmts, *pc),
                Some(Frame::Loop { .. }) => {
                    if self.clock_ns >= self.stop_ns {
                        return Ok(Progress::Paused(self.pause()));
                    }
                    let Some(Frame::Loop { stmt, started }) = self.frames.last_mut() else {
                        unreachable!("a loop frame")
                    };
                    let (stmt, started): (&'e CStmt, bool) = (*stmt, std::mem::replace(started, true));
                    self.line = stmt.line;
                    if let Err(raised) = self.loop_pass(stmt, started) {
                        self.fault_raised(raised)?;
                    }
                    continue;
                }
                Some(Frame::Call { .. } | Frame::FaultRoutine { .. }) => {
                    unreachable!("a routine's block sits above its call")
                }
            };
            // The block's statements, its frame's `pc` written back only
            // when the loop leaves it; entering and leaving nested blocks
            // stays in this loop.
            let mut depth = depth;
            let (mut stmts, mut at) = (stmts, at);
            loop {
                let Some(s) = stmts.get(at) else {
                    self.frames.pop();
                    if let Some(&Frame::Block { stmts: outer, pc, .. }) = self.frames.last() {
                        (stmts, at, depth) = (outer, pc, depth - 1);
                        continue;
                    }
                    if let Err(raised) = self.block_ended() {
                        self.fault_raised(raised)?;
                    }
                    break;
                };
                if self.clock_ns >= self.stop_ns {
                    self.set_pc(depth, at);
                    return Ok(Progress::Paused(self.pause()));
                }
                at += 1;
                self.line = s.line;
                let result = self.tick().and_then(|()| self.stmt(s));
                let now = self.frames.len();
                if now == depth && result.is_ok() {
                    if let Some(to) = self.jump.take() {
                        at = to;
                    }
                    continue;
                }
                // It entered a block, a loop or a routine, or left this
                // block (EXIT, RET), or faulted.
                if now >= depth {
                    self.set_pc(depth, at);
                }
                if let Err(raised) = result {
                    self.fault_raised(raised)?;
                } else if now > depth
                    && let Some(&Frame::Block { stmts: inner, pc, .. }) = self.frames.last()
                {
                    (stmts, at, depth) = (inner, pc, now);
                    continue;
                }
                break;
            }
        }
    }

    /// Writes `pc` into the block frame at `depth - 1`.
    #[inline]
    fn set_pc(&mut self, depth: usize, at: usize) {
        if let Some(Frame::Block { pc, .. }) = self.frames.get_mut(depth - 1) {
            *pc = at;
        }
    }

    /// A statement raised `raised`: an instruction fault (type 4) runs the
    /// program's fault routine, once; anything else stops the scan.
    fn fault_raised(&mut self, raised: Box<Raised>) -> R<()> {
        let Some(fr) = self.fault_routine else {
            return Err(raised);
        };
        if raised.fault_type != 4 || self.handling.is_some() || std::mem::take(&mut self.uncleared) {
            return Err(raised);
        }
        self.fault = None;
        let clock_ns = self.clock_ns;
        if let Some((sys, _, program)) = self.system.as_mut() {
            sys.programs[*program].major_record = sys.record(clock_ns, raised.fault_type, raised.code);
        }
        let power = self.take_power();
        self.frames.push(Frame::FaultRoutine {
            caller: self.routine,
            line: self.line,
            power,
        });
        self.frames.push(Frame::Block {
            stmts: &self.routines[fr],
            pc: 0,
            sub: fr as u32,
        });
        self.handling = Some(raised);
        self.routine = fr;
        Ok(())
    }

    /// A block ran to its end: what holds it goes on.
    fn block_ended(&mut self) -> R<()> {
        match self.frames.last() {
            Some(Frame::Call { .. }) => self.return_from_call(None),
            Some(Frame::FaultRoutine { .. }) => self.fault_routine_ended(),
            _ => Ok(()),
        }
    }

    /// Leaves the routine of the innermost call (`values`: what its RET
    /// handed back; `None` when it ran to its end).
    fn return_from_call(&mut self, values: Option<Vec<Value>>) -> R<()> {
        let Some(Frame::Call {
            caller,
            line,
            returns,
            power,
        }) = self.frames.pop()
        else {
            unreachable!("returning from a call")
        };
        self.restore_power(power);
        self.depth -= 1;
        let called = self.routine;
        self.routine = caller;
        let values = values.unwrap_or_default();
        if values.len() < returns.len() {
            // 1756-RM003, JSR: a RET with fewer return parameters than the
            // JSR has is major fault 4/31 (more are ignored).
            let line = self.line;
            self.routine = called;
            let f = self.raise(
                4,
                31,
                format!(
                    "invalid JSR parameter: the JSR takes {} return value(s), the routine returned {}{}",
                    returns.len(),
                    values.len(),
                    if values.is_empty() {
                        " (it ended without a RET that returns them)"
                    } else {
                        ""
                    }
                ),
            );
            self.routine = caller;
            self.line = line;
            return Err(f);
        }
        self.line = line;
        for ((place, ty), v) in returns.iter().zip(values) {
            self.store(place, *ty, v);
            self.check()?;
        }
        Ok(())
    }

    /// The fault routine ran to its end (or its RET): the fault is
    /// cleared when it zeroed the program's major fault record's type and
    /// code; then the scan resumes after the faulted statement, else the
    /// fault stands.
    fn fault_routine_ended(&mut self) -> R<()> {
        let Some(Frame::FaultRoutine { caller, line, power }) = self.frames.pop() else {
            unreachable!("leaving the fault routine")
        };
        self.restore_power(power);
        self.routine = caller;
        self.line = line;
        let raised = self.handling.take().expect("a fault is being handled");
        if self.fault_cleared() {
            if let Some((sys, ..)) = self.system.as_mut() {
                sys.major_events += 1;
                sys.major_fault_bits |= 1 << raised.fault_type;
            }
            self.cleared.push(*raised);
            // Inside an Add-On Instruction the rest of it is cancelled:
            // the scan goes on after the call.
            while self.routine >= self.aoi_from && self.frames.iter().any(|f| matches!(f, Frame::Call { .. })) {
                self.leave_routine(None)?;
            }
            Ok(())
        } else {
            self.uncleared = true;
            Err(raised)
        }
    }

    /// Whether the fault routine cleared the fault: the program's
    /// `MajorFaultRecord` has Type and Code 0 (its word 2).
    fn fault_cleared(&self) -> bool {
        self.system
            .as_ref()
            .is_some_and(|(sys, _, program)| sys.programs[*program].major_record[2] == 0)
    }

    fn stmt(&mut self, s: &'e CStmt) -> R<()> {
        self.kind(&s.kind, s)
    }

    /// Executes `kind`, statement `s`'s (or the instruction a ladder
    /// statement holds).
    fn kind(&mut self, kind: &'e SKind, s: &'e CStmt) -> R<()> {
        match kind {
            SKind::Assign { target, ty, value, .. } => {
                let v = self.eval(value);
                self.check()?;
                if value.ty == Ty::Ulint || *ty == DataType::Ulint {
                    self.check_sign_change(value.ty, *ty, v);
                }
                self.store(target, *ty, v);
                self.check()?;
            }
            SKind::If(branches, otherwise) => {
                let mut sub = branches.len();
                for (k, (c, _)) in branches.iter().enumerate() {
                    let taken = self.eval(c).truthy();
                    self.check()?;
                    if taken {
                        sub = k;
                        break;
                    }
                }
                let stmts = branches.get(sub).map_or(otherwise.as_slice(), |(_, b)| b.as_slice());
                self.enter(stmts, sub);
            }
            SKind::Case(sel, arms, otherwise) => {
                let x = self.eval(sel).as_i64();
                self.check()?;
                let sub = arms
                    .iter()
                    .position(|(labels, _)| labels.iter().any(|l| l.matches(x)))
                    .unwrap_or(arms.len());
                let stmts = arms.get(sub).map_or(otherwise.as_slice(), |(_, b)| b.as_slice());
                self.enter(stmts, sub);
            }
            SKind::For { counter, ty, from, .. } => {
                let start = self.eval(from);
                self.check()?;
                self.store(counter, *ty, start);
                self.check()?;
                self.frames.push(Frame::Loop {
                    stmt: s,
                    started: false,
                });
            }
            SKind::While(..) | SKind::Repeat(..) => self.frames.push(Frame::Loop {
                stmt: s,
                started: false,
            }),
            SKind::Exit => {
                while let Some(f) = self.frames.pop() {
                    if matches!(f, Frame::Loop { .. }) {
                        break;
                    }
                }
            }
            SKind::Ret(values) => {
                let values: Vec<Value> = values.iter().map(|v| self.eval(v)).collect();
                self.check()?;
                self.leave_routine(Some(values))?;
            }
            SKind::Jsr {
                routine,
                inputs,
                returns,
            } => self.jsr(*routine, inputs, returns)?,
            SKind::Ladder(op) => match &**op {
                Ladder::OnTrue(inner) => {
                    if self.rung_condition() {
                        self.kind(inner, s)?;
                    }
                }
                Ladder::Jmp(to) => {
                    if self.rung_condition() {
                        self.jump = Some(*to);
                    }
                }
                Ladder::Tnd => {
                    if self.rung_condition() {
                        self.leave_routine(None)?;
                    }
                }
                other => self.ladder(other)?,
            },
            other => self.instruction(other)?,
        }
        Ok(())
    }

    /// Leaves the routine executing (RET, TND): every block and loop of
    /// it, then its call, handing back `values` (`None`: none).
    fn leave_routine(&mut self, values: Option<Vec<Value>>) -> R<()> {
        while matches!(self.frames.last(), Some(Frame::Block { .. } | Frame::Loop { .. })) {
            self.frames.pop();
        }
        match self.frames.last() {
            Some(Frame::Call { .. }) => self.return_from_call(values)?,
            Some(Frame::FaultRoutine { .. }) => self.fault_routine_ended()?,
            _ => {}
        }
        Ok(())
    }

    /// Enters a block of the statement being executed (empty blocks too:
    /// the loop leaves them at once).
    fn enter(&mut self, stmts: &'e [CStmt], sub: usize) {
        if !stmts.is_empty() {
            self.frames.push(Frame::Block {
                stmts,
                pc: 0,
                sub: sub as u32,
            });
        }
    }

    /// One pass of a loop: its test (counted as a statement) and its body,
    /// or its end.
    fn loop_pass(&mut self, stmt: &'e CStmt, started: bool) -> R<()> {
        let more = match &stmt.kind {
            SKind::For {
                counter, ty, to, by, ..
            } => {
                if started {
                    let step = self.eval(by).as_i64();
                    let i = self.load(counter).as_i64();
                    self.check()?;
                    self.store(counter, *ty, Value::Int(i.wrapping_add(step)));
                    self.check()?;
                }
                self.tick()?;
                let i = self.load(counter).as_i64();
                let end = self.eval(to).as_i64();
                let step = self.eval(by).as_i64();
                self.check()?;
                !((step >= 0 && i > end) || (step < 0 && i < end))
            }
            SKind::While(c, _) => {
                self.tick()?;
                let more = self.eval(c).truthy();
                self.check()?;
                more
            }
            SKind::Repeat(_, until) => {
                if started {
                    let done = self.eval(until).truthy();
                    self.check()?;
                    if done {
                        false
                    } else {
                        self.tick()?;
                        true
                    }
                } else {
                    self.tick()?;
                    true
                }
            }
            _ => unreachable!("only loops are Loop frames"),
        };
        if more {
            self.frames.push(Frame::Block {
                stmts: sub_block(stmt, 0),
                pc: 0,
                sub: 0,
            });
        } else {
            self.frames.pop();
        }
        Ok(())
    }

    /// The instructions that are not control flow.
    fn instruction(&mut self, kind: &SKind) -> R<()> {
        match kind {
            SKind::Builtin(b, inst) => {
                let base = self.instance_base(inst);
                self.check()?;
                self.builtin(*b, base);
            }
            SKind::Sbr(targets) => {
                let params = std::mem::take(&mut self.params);
                if self.depth > 0 && params.len() < targets.len() {
                    // 1756-RM003, JSR: fewer input parameters than the SBR
                    // takes is major fault 4/31 (extra ones are not
                    // received).
                    return Err(self.raise(
                        4,
                        31,
                        format!(
                            "invalid JSR parameter: the SBR takes {} input(s), the JSR passed {}",
                            targets.len(),
                            params.len()
                        ),
                    ));
                }
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
            SKind::Str(op, args) => self.string_instruction(*op, args)?,
            SKind::CopBytes(src, dst, len) => {
                let n = self.eval(len).as_i64();
                self.check()?;
                self.copy_bytes(src, dst, n)?;
            }
            SKind::FllBytes(value, dst, len) => {
                let n = self.eval(len).as_i64();
                self.check()?;
                let v = self.eval(value);
                self.check()?;
                // Into numbers the Source converts to their type first (as
                // FLL into an array does); into a structure its own bytes go.
                let source = match dst.elem {
                    Elem::Scalar(t) => t,
                    Elem::User(_) | Elem::Control => value.ty.data_type(),
                };
                let (stored, bad) = source.store(v);
                if bad {
                    self.overflow("FLL source does not fit the destination");
                }
                let mut pattern = Vec::with_capacity(8);
                self.mem
                    .layouts
                    .encode(Elem::Scalar(source), 1, &[stored], 0, &mut pattern);
                self.fill_bytes(dst, n, &pattern)?;
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
                let v = match attribute {
                    GsvAttribute::Member(m) => members::axis_value(self.task, *axis, *m),
                    GsvAttribute::Config(limit) => Value::Real(self.task.axis_config(*axis).limit(*limit)),
                    GsvAttribute::Const(v) => *v,
                    GsvAttribute::Drive(k, d) => {
                        let gains = self
                            .system
                            .as_ref()
                            .and_then(|(sys, ..)| sys.drives.get(*k).copied().flatten());
                        Value::Real(gains.map_or(0.0, |g| d.get(&g)))
                    }
                };
                self.store(place, *ty, v);
                self.check()?;
            }
            SKind::Ssv(axis, target, value) => {
                let v = self.eval(value).as_f64();
                self.check()?;
                let refused = match target {
                    SsvAttribute::Config(limit) => {
                        self.task.set_axis_limit(*axis, *limit, v).err().map(|e| e.to_string())
                    }
                    SsvAttribute::Drive(k, d) => match self.system.as_mut() {
                        Some((sys, ..)) => match sys.drives.get(*k).copied().flatten().map(|g| d.set(&g, v)) {
                            Some(Ok(g)) => {
                                sys.drives[*k] = Some(g);
                                if !sys.drive_changes.contains(k) {
                                    sys.drive_changes.push(*k);
                                }
                                None
                            }
                            Some(Err(why)) => Some(why),
                            None => Some("the axis has no servo drive".to_owned()),
                        },
                        None => Some("a drive attribute is set by a task's routine, not a program step".to_owned()),
                    },
                };
                if let Some(e) = refused {
                    let name = self.task.axis_config(*axis).name.clone();
                    self.refusals.push(format!("SSV {name} (line {}): {e}", self.line));
                }
            }
            SKind::SysGet(attribute, object, data) => self.system_get(attribute, *object, data)?,
            SKind::SysSet(attribute, object, data) => self.system_set(attribute, *object, data)?,
            SKind::Event(k) => {
                // The scheduler releases it now: the scan stops before its
                // next statement so that a higher-priority event task runs
                // at once.
                self.events.push(*k);
                self.stop_ns = self.clock_ns;
            }
            SKind::Motion(call) => self.motion_call(call)?,
            _ => unreachable!("control flow is executed by stmt"),
        }
        Ok(())
    }

    fn jsr(&mut self, routine: usize, inputs: &[CExpr], returns: &'e [(Place, DataType)]) -> R<()> {
        if self.depth >= MAX_JSR_DEPTH {
            return Err(self.raise(4, 84, format!("stack overflow: JSR nested deeper than {MAX_JSR_DEPTH}")));
        }
        self.params = inputs.iter().map(|e| self.eval(e)).collect();
        self.check()?;
        let power = self.take_power();
        self.frames.push(Frame::Call {
            caller: self.routine,
            line: self.line,
            returns,
            power,
        });
        self.depth += 1;
        self.routine = routine;
        self.frames.push(Frame::Block {
            stmts: &self.routines[routine],
            pc: 0,
            sub: routine as u32,
        });
        Ok(())
    }

    /// The index of a system object in its class.
    fn object(&self, class: Class, object: Object) -> usize {
        match (object, &self.system) {
            (Object::Index(k), _) => k,
            (Object::This, Some((_, task, program))) if class == Class::Task => *task,
            (Object::This, Some((_, _, program))) => *program,
            _ => 0,
        }
    }

    fn system_get(&mut self, attribute: &Attribute, object: Object, data: &SysData) -> R<()> {
        let k = self.object(attribute.class, object);
        let mut words = [0i64; 11];
        let clock_ns = self.clock_ns;
        let Some((sys, ..)) = self.system.as_ref() else {
            return Ok(());
        };
        sys.get(
            attribute.class,
            attribute.attr,
            k,
            clock_ns,
            &mut words[..attribute.words],
        );
        match data {
            SysData::Target(place, ty) => {
                self.store(place, *ty, Value::Int(words[0]));
                self.check()?;
            }
            SysData::Words(at) => {
                let d = self.array_range(at, attribute.words as i64)?;
                for (slot, w) in self.mem.slots[d..d + attribute.words].iter_mut().zip(words) {
                    *slot = Value::Int(w);
                }
            }
            SysData::Value(_) => unreachable!("GSV writes a tag"),
        }
        Ok(())
    }

    fn system_set(&mut self, attribute: &Attribute, object: Object, data: &SysData) -> R<()> {
        let k = self.object(attribute.class, object);
        let mut words = [0i64; 11];
        match data {
            SysData::Value(e) => {
                let v = self.eval(e);
                self.check()?;
                let (stored, bad) = if attribute.ty == "INT" {
                    DataType::Int.store(v)
                } else {
                    DataType::Dint.store(v)
                };
                if bad {
                    self.overflow(&format!("the value does not fit {}", attribute.ty));
                }
                words[0] = stored.as_i64();
            }
            SysData::Words(at) => {
                let s = self.array_range(at, attribute.words as i64)?;
                for (w, slot) in words.iter_mut().zip(&self.mem.slots[s..s + attribute.words]) {
                    *w = slot.as_i64();
                }
            }
            SysData::Target(..) => unreachable!("SSV reads a value"),
        }
        if let Some((sys, ..)) = self.system.as_mut() {
            sys.set(attribute.class, attribute.attr, k, &words[..attribute.words]);
        }
        Ok(())
    }

    fn array_range(&mut self, a: &ArrayAt, n: i64) -> R<usize> {
        let start = self.eval(&a.start).as_i64();
        self.check()?;
        if start < 0 || n < 0 || start.checked_add(n).is_none_or(|end| end > a.len as i64) {
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

    /// The offset computed subscripts add, `each` slots or bytes an
    /// element of each (every subscript checked: major fault 4/20).
    pub(super) fn term_offset(&mut self, terms: &[Term], each: fn(&Term) -> usize) -> R<usize> {
        let mut offset = 0;
        for t in terms {
            let i = self.leaf(&t.index).as_i64();
            self.check()?;
            if !(0..t.len as i64).contains(&i) {
                return Err(self.subscript_fault(&t.name, i, t.len));
            }
            offset += i as usize * each(t);
        }
        Ok(offset)
    }

    /// The byte offset of a copy operand inside its tag.
    fn data_offset(&mut self, d: &DataAt) -> R<usize> {
        Ok(d.byte + self.term_offset(&d.terms, |t| t.bytes)?)
    }

    /// `FLL` through the controller's bytes: `pattern` repeated over
    /// `n` destination elements (past the tag's end: major fault 4/20).
    fn fill_bytes(&mut self, dst: &DataAt, n: i64, pattern: &[u8]) -> R<()> {
        let to = self.data_offset(dst)?;
        let count = usize::try_from(n)
            .ok()
            .and_then(|n| n.checked_mul(self.mem.layouts.bytes(dst.elem)))
            .filter(|c| to.checked_add(*c).is_some_and(|end| end <= dst.tag_bytes));
        let Some(count) = count else {
            return Err(self.raise(
                4,
                20,
                format!(
                    "FLL past the end of {}: {n} element(s) of {} bytes from byte {to} ({} bytes)",
                    dst.name,
                    self.mem.layouts.bytes(dst.elem),
                    dst.tag_bytes
                ),
            ));
        };
        if count == 0 {
            return Ok(());
        }
        let (mut b, at, first) = window_bytes(self.mem, dst, to, count);
        for (k, byte) in b[at..at + count].iter_mut().enumerate() {
            *byte = pattern[k % pattern.len()];
        }
        store_window(self.mem, dst, first, &b);
        Ok(())
    }

    /// `COP`/`CPS` through the controller's bytes (1756-RM003): Length ×
    /// the destination element's bytes, from the source's bytes as the
    /// layout lays them out. A copy that would read or write past the end
    /// of its tag is major fault 4/20 (the twin has no memory beyond a tag).
    fn copy_bytes(&mut self, src: &DataAt, dst: &DataAt, n: i64) -> R<()> {
        let (from, to) = (self.data_offset(src)?, self.data_offset(dst)?);
        let count = usize::try_from(n)
            .ok()
            .and_then(|n| n.checked_mul(self.mem.layouts.bytes(dst.elem)));
        let fits =
            |at: usize, d: &DataAt| count.is_some_and(|c| at.checked_add(c).is_some_and(|end| end <= d.tag_bytes));
        if !fits(from, src) || !fits(to, dst) {
            return Err(self.raise(
                4,
                20,
                format!(
                    "COP/CPS past the end of a tag: {n} element(s) of {} bytes from byte {from} of {} ({} bytes) to byte {to} of {} ({} bytes)",
                    self.mem.layouts.bytes(dst.elem),
                    src.name,
                    src.tag_bytes,
                    dst.name,
                    dst.tag_bytes
                ),
            ));
        }
        let count = count.unwrap_or(0);
        if count == 0 {
            return Ok(());
        }
        let (a, from, _) = window_bytes(self.mem, src, from, count);
        let (mut b, to, first) = window_bytes(self.mem, dst, to, count);
        b[to..to + count].copy_from_slice(&a[from..from + count]);
        store_window(self.mem, dst, first, &b);
        Ok(())
    }

    fn instance_base(&mut self, inst: &Instance) -> usize {
        if !inst.terms.is_empty() {
            return match self.term_offset(&inst.terms, |t| t.slots) {
                Ok(offset) => inst.base + offset,
                Err(f) => {
                    self.fail(f);
                    inst.base
                }
            };
        }
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

/// The bytes of the elements of a copy operand's tag that bytes `at ..
/// at + count` (count > 0) fall in, only those being turned into bytes:
/// the bytes, where `at` lies in them, and the first element.
fn window_bytes(mem: &Memory, d: &DataAt, at: usize, count: usize) -> (Vec<u8>, usize, usize) {
    let each = mem.layouts.bytes(d.tag_elem).max(1);
    let first = at / each;
    let end = (at + count).div_ceil(each).min(d.tag_len);
    let n = end.saturating_sub(first).max(1);
    let mut bytes = Vec::with_capacity(n * each);
    let slot = d.tag_base + first * mem.layouts.slots(d.tag_elem);
    mem.layouts.encode(d.tag_elem, n, &mem.slots, slot, &mut bytes);
    (bytes, at - first * each, first)
}

/// Writes back the elements [`window_bytes`] read, from `first` on.
fn store_window(mem: &mut Memory, d: &DataAt, first: usize, bytes: &[u8]) {
    let n = bytes.len() / mem.layouts.bytes(d.tag_elem).max(1);
    let slot = d.tag_base + first * mem.layouts.slots(d.tag_elem);
    mem.layouts.decode(d.tag_elem, n, bytes, 0, &mut mem.slots, slot);
}
