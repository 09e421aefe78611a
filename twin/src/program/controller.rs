//! The task engine: the scene's `[[tasks]]` scanned against the planner,
//! the way a Logix controller runs periodic tasks of Structured Text
//! programs.
//!
//! **In:** the scene's tasks (parsed routines), its tags and axes, the
//! planner. **Out:** live tag values, motion instructions executed into the
//! planner, faults.
//!
//! # Timing
//! Task *k*-th trigger is at `k × period_ms` from the start (the first at
//! 0). The twin runs the program stage once per coarse update, at the
//! update's start time `t`: every trigger in `(t − coarse_update, t]` runs
//! then, in time order (higher priority, the lower number, first at equal
//! times; then in file order). Tasks are not phase-locked to the coarse
//! update, as on the controller, so:
//! * a motion instruction a scan executes takes effect at the next coarse
//!   update (the one starting at `t`), whatever the scan's own time;
//! * `ActualPosition` (and every axis member) is the value of the last
//!   coarse update: up to one coarse update old, as the controller's;
//! * a task faster than the coarse update runs several scans back to back
//!   at one update, each seeing the same axis values;
//! * timers use the scan's own trigger time.
//!
//! A scan's nominal duration is its executed statements (and loop tests)
//! × [`super::exec::NOMINAL_STATEMENT_US`]. Past `watchdog_ms` the watchdog
//! expires (major fault type 6, code 1); past `period_ms` the next trigger
//! finds the task still running (minor fault type 6, code 2, overlap).
//!
//! # Prescan and first scan
//! Before the first scan every routine of every program is prescanned:
//! non-retentive assignments (`[:=]`) clear their target; motion
//! instructions clear `.EN .DN .ER .IP`; `TONR`/`TOFR` clear `EN TT DN ACC`,
//! `RTOR` clears `EN TT` and keeps `ACC`; `R_TRIG`/`F_TRIG` clear `M`,
//! `TON`/`TOF` stop timing. Each program's first scan after that runs with
//! `S:FS` set, and an instruction executed in it takes its stored input as
//! set (`OSRI`: a TRUE input on the first scan gives no pulse; `OSFI`: a
//! FALSE one none either; `CTUD`: an enable already TRUE does not count).
//!
//! # Faults
//! | kind | type | code | when |
//! |---|---|---|---|
//! | major | 4 | 20 | array subscript or bit number out of range |
//! | major | 4 | 84 | `JSR` nested deeper than [`super::exec::MAX_JSR_DEPTH`] |
//! | major | 6 | 1 | task watchdog expired |
//! | minor | 4 | 4 | arithmetic overflow, division by zero, a value that does not fit its tag |
//! | minor | 6 | 2 | periodic task overlap |
//!
//! A major fault stops every task (the controller is faulted); the run
//! stops at the end of that update. Minor faults are recorded and counted
//! (`MinorFaults`, `S:MINOR`) and the run goes on.

use super::exec::{Exec, NOMINAL_STATEMENT_US, Raised, Scratch};
use super::ir::{Builtin, CStmt, CompiledProgram, Place, SKind};
use super::memory::Memory;
use super::types::{Structure, Value};
use crate::scene::Scene;
use planner::instruction::MotionInstructionBits;
use planner::task::MotionTask;
use std::path::PathBuf;
use std::time::{Duration, Instant};

/// A fault the controller recorded (also as the summary writes it).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Fault {
    /// Major (the controller stopped) or minor.
    pub major: bool,
    /// Fault type.
    pub fault_type: u8,
    /// Fault code.
    pub code: u8,
    /// What happened.
    pub message: String,
    /// Task.
    pub task: String,
    /// Program.
    pub program: String,
    /// Routine file.
    pub routine: PathBuf,
    /// Line in the routine.
    pub line: u32,
    /// Scan time, s.
    pub time_s: f64,
}

impl std::fmt::Display for Fault {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} fault (type {}, code {}) at t = {:.3} s in task {}, program {}, {}:{}: {}",
            if self.major { "major" } else { "minor" },
            self.fault_type,
            self.code,
            self.time_s,
            self.task,
            self.program,
            self.routine.display(),
            self.line,
            self.message
        )
    }
}

struct ProgramRun {
    name: String,
    routine_paths: Vec<PathBuf>,
    routines: Vec<Vec<CStmt>>,
    first_scan: bool,
}

impl ProgramRun {
    fn new(p: CompiledProgram) -> ProgramRun {
        ProgramRun {
            name: p.name,
            routine_paths: p.routine_paths,
            routines: p.routines,
            first_scan: true,
        }
    }
}

struct TaskRun {
    name: String,
    period_us: i64,
    priority: u8,
    budget: u64,
    next_us: i64,
    programs: Vec<ProgramRun>,
}

/// What the tasks cost and did, for the summary.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TaskStats {
    /// Scans run (programs × triggers).
    pub scans: u64,
    /// Statements executed.
    pub statements: u64,
    /// Wall time spent scanning.
    pub wall: Duration,
}

/// The scene's tasks, compiled, with tag memory and the fault log.
pub struct Controller {
    mem: Memory,
    scratch: Scratch,
    tasks: Vec<TaskRun>,
    prescanned: bool,
    major: Option<Fault>,
    minor: Vec<Fault>,
    minor_total: i64,
    refusals: Vec<String>,
    stats: TaskStats,
}

impl std::fmt::Debug for Controller {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Controller")
            .field("tasks", &self.tasks.iter().map(|t| &t.name).collect::<Vec<_>>())
            .field("major", &self.major)
            .field("minor_total", &self.minor_total)
            .finish_non_exhaustive()
    }
}

/// The most minor faults kept with their text (all are counted).
pub const MINOR_FAULTS_KEPT: usize = 1000;

impl Controller {
    /// The task engine over tag memory, with each task's programs as
    /// [`crate::program::compile::scene::program`] compiled them (`programs[t]`:
    /// the scene's task `t`'s, in order).
    #[must_use]
    pub fn new(scene: &Scene, mem: Memory, programs: Vec<Vec<CompiledProgram>>) -> Controller {
        let tasks = scene
            .tasks
            .iter()
            .zip(programs)
            .map(|(t, programs)| TaskRun {
                name: t.name.clone(),
                period_us: (t.period_ms * 1000.0).round().max(1.0) as i64,
                priority: t.priority,
                budget: (t.watchdog_ms * 1000.0 / NOMINAL_STATEMENT_US) as u64,
                next_us: 0,
                programs: programs.into_iter().map(ProgramRun::new).collect(),
            })
            .collect();
        Controller {
            mem,
            scratch: Scratch::default(),
            tasks,
            prescanned: false,
            major: None,
            minor: Vec::new(),
            minor_total: 0,
            refusals: Vec::new(),
            stats: TaskStats::default(),
        }
    }

    /// Whether the scene has any task.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.tasks.is_empty()
    }

    /// Runs every trigger due at the planner's current time (module doc,
    /// "Timing"). Nothing runs once a major fault stopped the controller.
    pub fn scan(&mut self, task: &mut MotionTask) {
        if self.major.is_some() || self.tasks.is_empty() {
            return;
        }
        let wall = Instant::now();
        if !self.prescanned {
            self.prescan(task);
            self.prescanned = true;
        }
        let now_us = (task.time_s() * 1e6).round() as i64;
        let mut due: Vec<(i64, u8, usize)> = Vec::new();
        for (i, t) in self.tasks.iter_mut().enumerate() {
            while t.next_us <= now_us {
                due.push((t.next_us, t.priority, i));
                t.next_us += t.period_us;
            }
        }
        due.sort_unstable();
        for (at_us, _, i) in due {
            self.run_task(i, at_us, task);
            if self.major.is_some() {
                break;
            }
        }
        self.stats.wall += wall.elapsed();
    }

    fn run_task(&mut self, i: usize, at_us: i64, task: &mut MotionTask) {
        let mut statements = 0u64;
        for p in 0..self.tasks[i].programs.len() {
            let t = &mut self.tasks[i];
            let budget = t.budget.saturating_sub(statements);
            let program = &mut t.programs[p];
            let first = std::mem::replace(&mut program.first_scan, false);
            let mut exec = Exec::new(
                &mut self.mem,
                task,
                at_us,
                first,
                &program.routines,
                &mut self.scratch,
                self.minor_total,
                budget,
            );
            let result = exec.run_main();
            statements += exec.steps;
            let minor = std::mem::take(&mut exec.minor);
            self.minor_total = exec.minor_total;
            let refusals = std::mem::take(&mut exec.refusals);
            self.stats.scans += 1;
            self.stats.statements += exec.steps;
            if !self.record(i, p, at_us, minor, refusals, result) {
                return;
            }
        }
        self.check_overlap(i, at_us, statements);
    }

    /// Records a program scan's faults and refusals; `false` when a major
    /// fault stopped the controller.
    fn record(
        &mut self,
        i: usize,
        p: usize,
        at_us: i64,
        minor: Vec<Raised>,
        refusals: Vec<String>,
        result: Result<(), Box<Raised>>,
    ) -> bool {
        self.refusals.extend(refusals);
        if minor.is_empty() && result.is_ok() {
            return true;
        }
        let (task_name, program_name) = (self.tasks[i].name.clone(), self.tasks[i].programs[p].name.clone());
        let paths = self.tasks[i].programs[p].routine_paths.clone();
        let fault = |r: Raised, major: bool| Fault {
            major,
            fault_type: r.fault_type,
            code: r.code,
            message: r.message,
            task: task_name.clone(),
            program: program_name.clone(),
            routine: paths[r.routine].clone(),
            line: r.line,
            time_s: at_us as f64 / 1e6,
        };
        for r in minor {
            self.keep_minor(fault(r, false));
        }
        match result {
            Ok(()) => true,
            Err(r) => {
                self.major = Some(fault(*r, true));
                false
            }
        }
    }

    /// A minor fault 6/2 when the task's scan ran longer than its period.
    fn check_overlap(&mut self, i: usize, at_us: i64, statements: u64) {
        let t = &self.tasks[i];
        let nominal_us = statements as f64 * NOMINAL_STATEMENT_US;
        if nominal_us > t.period_us as f64 {
            let program = t.programs.first().map(|p| (p.name.clone(), p.routine_paths[0].clone()));
            let (program, routine) = program.unwrap_or_default();
            let overlap = Fault {
                major: false,
                fault_type: 6,
                code: 2,
                message: format!(
                    "periodic task overlap: the scan took {nominal_us:.0} µs (nominal), longer than its period of {} µs",
                    t.period_us
                ),
                task: t.name.clone(),
                program,
                routine,
                line: 0,
                time_s: at_us as f64 / 1e6,
            };
            self.minor_total += 1;
            self.keep_minor(overlap);
        }
    }

    fn keep_minor(&mut self, f: Fault) {
        if self.minor.len() < MINOR_FAULTS_KEPT {
            self.minor.push(f);
        }
    }

    fn prescan(&mut self, task: &mut MotionTask) {
        for t in &self.tasks {
            for p in &t.programs {
                for body in &p.routines {
                    prescan_block(body, &mut self.mem, task);
                }
            }
        }
    }

    /// The major fault that stopped the controller, if any.
    #[must_use]
    pub fn major_fault(&self) -> Option<&Fault> {
        self.major.as_ref()
    }

    /// The minor faults recorded (the first [`MINOR_FAULTS_KEPT`]).
    #[must_use]
    pub fn minor_faults(&self) -> &[Fault] {
        &self.minor
    }

    /// How many minor faults were recorded.
    #[must_use]
    pub fn minor_fault_count(&self) -> i64 {
        self.minor_total
    }

    /// Instructions that refused an operand's value at run time (ERR 13,
    /// also in their control structure) and SSVs that refused a value.
    #[must_use]
    pub fn refusals(&self) -> &[String] {
        &self.refusals
    }

    /// What the tasks cost.
    #[must_use]
    pub fn stats(&self) -> &TaskStats {
        &self.stats
    }

    /// Tag memory.
    #[must_use]
    pub fn memory(&self) -> &Memory {
        &self.mem
    }

    /// Tag memory, to write a tag as a test or a sandbox does.
    pub fn memory_mut(&mut self) -> &mut Memory {
        &mut self.mem
    }

    /// Tag memory, the operand scratch and the refusals, to fire the
    /// `[[program]]` steps.
    pub(super) fn step_context(&mut self) -> (&mut Memory, &mut Scratch, &mut Vec<String>) {
        (&mut self.mem, &mut self.scratch, &mut self.refusals)
    }

    /// Reads a traced place (a slot, an element with a constant subscript,
    /// a bit of one, or a planner member) without side effects.
    #[must_use]
    pub fn peek(&self, place: &Place, task: &MotionTask) -> Value {
        peek(place, &self.mem, task)
    }
}

pub(super) fn peek(place: &Place, mem: &Memory, task: &MotionTask) -> Value {
    let constant = |e: &super::ir::CExpr| match e.kind {
        super::ir::CKind::Const(v) => v.as_i64(),
        _ => 0,
    };
    match place {
        Place::Slot(i) => mem.slots[*i],
        Place::Element { index, .. } => place
            .element_slot(constant(index))
            .map_or(Value::Int(0), |i| mem.slots[i]),
        Place::Bit { inner, bit, .. } => Value::Bool(peek(inner, mem, task).as_i64() >> constant(bit) & 1 == 1),
        Place::Motion(..) | Place::Axis(..) | Place::Coord(..) | Place::Fb(..) => {
            super::exec::members::planner_value(place, task).unwrap_or(Value::Int(0))
        }
        Place::FirstScan | Place::MinorInScan => Value::Bool(false),
        Place::MinorFaults => Value::Int(0),
        Place::Column { .. } => Value::Int(0),
    }
}

/// The prescan of one block (module doc): every branch, no condition
/// evaluated. A subscript that cannot be evaluated without a scan leaves
/// its target as it is.
fn prescan_block(body: &[CStmt], mem: &mut Memory, task: &mut MotionTask) {
    for s in body {
        match &s.kind {
            SKind::Assign {
                target,
                ty,
                retentive: false,
                ..
            } => {
                if let Place::Slot(i) = target {
                    mem.slots[*i] = ty.store(Value::Int(0)).0;
                } else if let Place::Element {
                    base,
                    len,
                    stride,
                    offset,
                    index,
                    ..
                } = target
                    && let super::ir::CKind::Const(v) = index.kind
                    && (0..*len as i64).contains(&v.as_i64())
                {
                    mem.slots[base + v.as_i64() as usize * stride + offset] = ty.store(Value::Int(0)).0;
                }
            }
            SKind::If(branches, otherwise) => {
                for (_, b) in branches {
                    prescan_block(b, mem, task);
                }
                prescan_block(otherwise, mem, task);
            }
            SKind::Case(_, arms, otherwise) => {
                for (_, b) in arms {
                    prescan_block(b, mem, task);
                }
                prescan_block(otherwise, mem, task);
            }
            SKind::For { body, .. } | SKind::While(_, body) | SKind::Repeat(body, _) => prescan_block(body, mem, task),
            SKind::Builtin(b, inst) => {
                let n = inst.index.as_ref().map_or(1, |(_, len)| *len);
                for k in 0..n {
                    let base = inst.base + k * inst.structure.size();
                    prescan_builtin(*b, base, mem);
                }
            }
            SKind::Motion(call) => {
                if let Some(control) = call.control {
                    let bits = task.motion_bits(control);
                    task.set_motion_bits(
                        control,
                        MotionInstructionBits {
                            en: false,
                            dn: false,
                            er: false,
                            ip: false,
                            ..bits
                        },
                    );
                }
            }
            _ => {}
        }
    }
}

fn prescan_builtin(b: Builtin, base: usize, mem: &mut Memory) {
    let mut set = |s: Structure, member: &str, v: Value| mem.slots[base + s.offset(member)] = v;
    let off = Value::Bool(false);
    match b {
        Builtin::Osri | Builtin::Osfi | Builtin::Ctud => {}
        Builtin::Tonr | Builtin::Tofr | Builtin::Rtor => {
            for m in ["EN", "TT", "DN"] {
                if !(b == Builtin::Rtor && m == "DN") {
                    set(Structure::Timer, m, off);
                }
            }
            if b != Builtin::Rtor {
                set(Structure::Timer, "ACC", Value::Int(0));
            }
        }
        Builtin::RTrig | Builtin::FTrig => set(Structure::Trig, "M", off),
        Builtin::Ton | Builtin::Tof => set(Structure::IecTimer, "Running", off),
    }
}
