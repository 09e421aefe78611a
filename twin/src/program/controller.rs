//! The task engine: the scene's `[[tasks]]` scanned against the planner,
//! the way a Logix controller (a 5580) runs periodic, continuous and event
//! tasks of Structured Text and ladder programs (1756-PM005).
//!
//! **In:** the scene's tasks (parsed routines), its tags and axes, the
//! planner. **Out:** live tag values, motion instructions executed into the
//! planner, faults, the system objects' values (`super::system`).
//!
//! # Timing
//! The controller has one clock (ns); each executed statement and loop
//! test advances it by `[controller] statement_us`. The program stage of
//! the coarse update starting at `t` (Δ the coarse update period):
//! * releases the triggers up to `t` at their times: periodic triggers
//!   (`k × period_ms`), the motion group execution (at `t`), event
//!   timeouts, and `EVENT(Task)` at the statement that executes it. A
//!   trigger whose task is still running or waiting is an overlap: ignored,
//!   counted (`OverlapCount`, `Status` bit 2), minor fault 6/2;
//! * runs the highest-priority ready task; a trigger of a higher priority
//!   stops the running scan before its next statement (the interpreter
//!   keeps where it was, `exec::Paused`) and the scan resumes when the
//!   controller is free again; equal priorities alternate in
//!   [`TIME_SLICE_NS`] slices, the one waiting longest first; the
//!   continuous task runs when no other is ready, scan after scan;
//! * while a scan runs past `t`, the clock goes on, releasing the triggers
//!   it passes, up to `t + Δ`: there the coarse update interrupts whatever
//!   runs, which resumes in the next stage after the planner's update (an
//!   idle controller waits for the next stage instead).
//!
//! So a motion instruction takes effect at its stage's planner update;
//! axis members are the last update's; a scan spanning an update sees them
//! change there; a task faster than the coarse update runs its scans at
//! their trigger times within one stage; timers measure with the scan's
//! trigger time. With short scans (an idle controller between them) this
//! is the order of triggers in `(t − Δ, t]`, in time order, higher
//! priority first at equal times: every shipped scene's trace is what it
//! was before preemption existed.
//!
//! The watchdog (`watchdog_ms`, major fault 6/1) counts from a scan's start
//! to its end on this clock, preemptions and coarse updates included.
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
//! Ladder instructions take their prescan actions (1756-RM003: `OTE`
//! clears, `ONS` and `OSR` set their storage bit, `TON` resets, `CTU` sets
//! `CU` …; `scenes/README.md`, *Ladder routines*), and each Add-On
//! Instruction call whose instruction executes its Prescan routine runs it
//! once.
//!
//! # Faults (1756-PM014)
//! | kind | type | code | when |
//! |---|---|---|---|
//! | major | 4 | 20 | array subscript, bit number or copied range out of range |
//! | major | 4 | 31 | a JSR passes fewer inputs than the SBR takes, or gets fewer return values than it has |
//! | major | 4 | 84 | `JSR` nested deeper than [`super::exec::MAX_JSR_DEPTH`] |
//! | major | 6 | 1 | task watchdog expired |
//! | minor | 4 | 4 | arithmetic overflow, division by zero, a value that does not fit its tag (`report_overflow_faults`) |
//! | minor | 6 | 2 | task overlap |
//!
//! A major fault of type 4 in a program with a fault routine runs it; if it
//! clears the program's `MajorFaultRecord` the scan goes on after the
//! faulted statement (`exec`). A major fault nothing cleared stops every
//! task (the controller is faulted); the run stops at the end of that
//! update. Minor faults are recorded and counted (`MinorFaults`, `S:MINOR`,
//! FAULTLOG) and the run goes on.

use super::exec::{Exec, Paused, Progress, Raised, Scratch};
use super::ir::{Builtin, CStmt, CompiledProgram, Place, SKind};
use super::memory::Memory;
use super::system::{ProgramStatus, STATUS_EVENT, STATUS_OVERLAP, STATUS_TIMEOUT, System, TaskStatus};
use super::types::{Structure, Value};
use crate::scene::{EventTrigger, Scene, TaskKind};
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
    /// A major fault the program's fault routine cleared: the scan went on
    /// after the faulted statement.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub cleared: bool,
}

impl Fault {
    /// The record of `r`, raised in a routine of `routine_paths`, in a scan
    /// triggered at `at_us`.
    fn of(r: Raised, major: bool, task: &str, program: &str, routine_paths: &[PathBuf], at_us: i64) -> Fault {
        Fault {
            major,
            fault_type: r.fault_type,
            code: r.code,
            message: r.message,
            task: task.to_owned(),
            program: program.to_owned(),
            routine: routine_paths[r.routine].clone(),
            line: r.line,
            time_s: at_us as f64 / 1e6,
            cleared: false,
        }
    }
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
        )?;
        if self.cleared {
            f.write_str(" (cleared by the fault routine)")?;
        }
        Ok(())
    }
}

struct ProgramRun {
    name: String,
    routine_paths: Vec<PathBuf>,
    routines: Vec<Vec<CStmt>>,
    /// The first Add-On Instruction routine.
    aoi_from: usize,
    /// The instructions' Prescan routines.
    aoi_prescan: Vec<usize>,
    fault_routine: Option<usize>,
    first_scan: bool,
    /// Its index in [`System::programs`].
    index: usize,
    /// Input parameters: (its first slot, its connection's, slots), copied
    /// when the program's scan starts.
    inputs: Vec<(usize, usize, usize)>,
    /// Output parameters: (the connection's first slot, its own, slots),
    /// copied when the program's scan ends.
    outputs: Vec<(usize, usize, usize)>,
}

/// Makes a program's parameter copies (destination slot, source slot,
/// slots) in tag memory.
fn copy_parameters(mem: &mut Memory, copies: &[(usize, usize, usize)]) {
    for &(to, from, n) in copies {
        mem.slots.copy_within(from..from + n, to);
    }
}

/// The copies a program's Input and Output parameters make (1756-PM021):
/// (destination slot, source slot, slots) each.
fn parameter_copies(def: &crate::scene::ProgramDef, mem: &Memory) -> [Vec<(usize, usize, usize)>; 2] {
    let mut copies = [Vec::new(), Vec::new()];
    for tag in &def.tags {
        let (Some(c), Some(own)) = (
            &tag.connection,
            mem.find_declared(&format!("{}.{}", def.name, tag.name)),
        ) else {
            continue;
        };
        let Some(other) = mem.find(&c.stored_name()) else {
            continue;
        };
        let (a, b, n) = (mem.tags[own].base, mem.tags[other].base, mem.slot_count(own));
        match tag.usage {
            crate::scene::Usage::Input => copies[0].push((a, b, n)),
            crate::scene::Usage::Output => copies[1].push((b, a, n)),
            _ => {}
        }
    }
    copies
}

/// A scan started and not ended: running, preempted, or stopped at a
/// coarse update.
#[derive(Debug, Clone)]
struct ActiveScan {
    /// The trigger's time, µs (what timers measure with).
    trigger_us: i64,
    /// When it started, on the controller's clock, ns.
    start_ns: i64,
    /// The program it is in.
    program: usize,
    /// When that program's scan started, ns.
    program_start_ns: i64,
    /// Where that program stopped, if it did.
    paused: Option<Paused>,
    /// Statements executed.
    statements: u64,
}

struct TaskRun {
    name: String,
    kind: TaskKind,
    priority: u8,
    watchdog_ns: i64,
    watchdog_us: f64,
    /// A periodic task's period, an event task's timeout, ns.
    period_ns: Option<i64>,
    /// The next periodic trigger or timeout, ns.
    next_ns: i64,
    /// A trigger released and its scan not started: its time, µs, and
    /// the `Status` bits it sets.
    pending: Option<(i64, i64)>,
    active: Option<ActiveScan>,
    /// Where it stands among the tasks of its priority (lower first).
    queued: u64,
    programs: Vec<ProgramRun>,
    /// A registration-triggered event task: the events seen so far.
    registrations_seen: u64,
    /// A registration event happened since the last update: a trigger at
    /// the start of this one.
    registration_due: bool,
}

impl TaskRun {
    fn busy(&self) -> bool {
        self.pending.is_some() || self.active.is_some()
    }
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
    /// The Controller Fault Handler's program.
    fault_handler: Option<ProgramRun>,
    sys: System,
    prescanned: bool,
    major: Option<Fault>,
    minor: Vec<Fault>,
    cleared: Vec<Fault>,
    /// Every fault recorded, in order (minor ones while fewer than
    /// [`MINOR_FAULTS_KEPT`] are kept).
    log: Vec<Fault>,
    minor_total: i64,
    refusals: Vec<String>,
    /// Every refusal so far, and how many of `refusals` are counted.
    refusal_total: u64,
    refusals_counted: usize,
    stats: TaskStats,
    /// The controller's clock, ns.
    clock_ns: i64,
    /// The coarse update period, ns.
    update_ns: i64,
    statement_ns: i64,
    report_overflow: bool,
    /// Triggers due this update, in time order: (time ns, task, the
    /// `Status` bits they set).
    releases: Vec<(i64, usize, i64)>,
    queue_seq: u64,
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

/// Run-time refusals kept for the summary; [`Controller::refusal_count`]
/// counts them all.
pub const REFUSALS_KEPT: usize = 1000;

/// Equal-priority tasks alternate in slices of this much of the
/// controller's time, ns (1756-PM005: "tasks of equal priority ... each
/// run for 1 ms").
pub const TIME_SLICE_NS: i64 = 1_000_000;

impl Controller {
    /// The task engine over tag memory, with each task's programs as
    /// [`crate::program::compile::scene::program`] compiled them (`programs[t]`:
    /// the scene's task `t`'s, in order).
    #[must_use]
    pub fn new(
        scene: &Scene,
        mem: Memory,
        programs: Vec<Vec<CompiledProgram>>,
        fault_handler: Option<CompiledProgram>,
    ) -> Controller {
        let ns = |ms: f64| (ms * 1e6).round().max(1.0) as i64;
        let mut sys = System {
            start_time_us: scene.controller.start_time_us,
            coarse_update_us: (scene.coarse_update_ms * 1000.0).round() as i64,
            drives: scene.axes.iter().map(|a| a.servo).collect(),
            ..System::default()
        };
        let mut tasks = Vec::with_capacity(scene.tasks.len());
        for ((i, t), compiled) in scene.tasks.iter().enumerate().zip(programs) {
            let period_ns = match t.kind {
                TaskKind::Periodic { period_ms } => Some(ns(period_ms)),
                TaskKind::Event { timeout_ms, .. } => timeout_ms.map(ns),
                TaskKind::Continuous => None,
            };
            sys.tasks.push(TaskStatus {
                name: t.name.clone(),
                priority: if t.kind == TaskKind::Continuous {
                    0
                } else {
                    i64::from(t.priority)
                },
                rate_us: period_ns.map_or(0, |p| p / 1000),
                watchdog_us: (t.watchdog_ms * 1000.0).round() as i64,
                enable_timeout: matches!(
                    t.kind,
                    TaskKind::Event {
                        timeout_ms: Some(_),
                        ..
                    }
                ),
                inhibit: t.inhibit,
                ..TaskStatus::default()
            });
            let mut runs = Vec::with_capacity(compiled.len());
            for (def, p) in t.programs.iter().zip(compiled) {
                sys.programs.push(ProgramStatus {
                    name: p.name.clone(),
                    task: i,
                    disabled: def.disabled,
                    ..ProgramStatus::default()
                });
                let [inputs, outputs] = parameter_copies(def, &mem);
                runs.push(ProgramRun {
                    name: p.name,
                    routine_paths: p.routine_paths,
                    routines: p.routines,
                    aoi_from: p.aoi_from,
                    aoi_prescan: p.aoi_prescan,
                    // The fault routine is one of `routines`, after main.
                    fault_routine: def.fault_routine.map(|k| k + 1),
                    first_scan: true,
                    index: sys.programs.len() - 1,
                    inputs,
                    outputs,
                });
            }
            tasks.push(TaskRun {
                name: t.name.clone(),
                kind: t.kind,
                priority: t.priority,
                watchdog_ns: ns(t.watchdog_ms),
                watchdog_us: t.watchdog_ms * 1000.0,
                period_ns,
                next_ns: match t.kind {
                    TaskKind::Periodic { .. } => 0,
                    _ => period_ns.unwrap_or(i64::MAX),
                },
                pending: None,
                active: None,
                queued: 0,
                registrations_seen: 0,
                registration_due: false,
                programs: runs,
            });
        }
        let handler_copies = scene
            .controller
            .fault_handler
            .as_ref()
            .map(|def| parameter_copies(def, &mem));
        let fault_handler = fault_handler.map(|p| {
            let [inputs, outputs] = handler_copies.unwrap_or_default();
            sys.programs.push(ProgramStatus {
                name: p.name.clone(),
                task: usize::MAX,
                ..ProgramStatus::default()
            });
            ProgramRun {
                name: p.name,
                routine_paths: p.routine_paths,
                routines: p.routines,
                aoi_from: p.aoi_from,
                aoi_prescan: p.aoi_prescan,
                fault_routine: None,
                first_scan: true,
                index: sys.programs.len() - 1,
                inputs,
                outputs,
            }
        });
        Controller {
            mem,
            scratch: Scratch::default(),
            tasks,
            fault_handler,
            sys,
            prescanned: false,
            major: None,
            minor: Vec::new(),
            cleared: Vec::new(),
            log: Vec::new(),
            minor_total: 0,
            refusals: Vec::new(),
            refusal_total: 0,
            refusals_counted: 0,
            stats: TaskStats::default(),
            clock_ns: 0,
            update_ns: ns(scene.coarse_update_ms),
            statement_ns: ((scene.controller.statement_us * 1000.0).round() as i64).max(1),
            report_overflow: scene.controller.report_overflow_faults,
            releases: Vec::new(),
            queue_seq: 0,
        }
    }

    /// Whether the scene has any task.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.tasks.is_empty()
    }

    /// Runs the controller for the coarse update starting at the planner's
    /// current time `t` (module doc, "Timing"). Nothing runs once a major
    /// fault stopped the controller.
    pub fn scan(&mut self, task: &mut MotionTask) {
        if self.major.is_some() || self.tasks.is_empty() {
            return;
        }
        let wall = Instant::now();
        self.prescan_once(task);
        let now_ns = (task.time_s() * 1e6).round() as i64 * 1000;
        let horizon_ns = now_ns + self.update_ns;
        for t in &mut self.tasks {
            let events = match t.kind {
                TaskKind::Event {
                    trigger: EventTrigger::AxisRegistration { axis, input },
                    ..
                } => task
                    .axis_handles()
                    .nth(axis)
                    .and_then(|h| task.registration(h, input))
                    .map_or(0, |r| r.events),
                TaskKind::Event {
                    trigger: EventTrigger::AxisWatch { axis },
                    ..
                } => task.axis_handles().nth(axis).map_or(0, |h| task.watch(h).events),
                _ => continue,
            };
            t.registration_due = events > t.registrations_seen;
            t.registrations_seen = events;
        }
        self.collect_releases(now_ns, horizon_ns);
        let mut next = 0;
        loop {
            while let Some(&(at, i, status)) = self.releases.get(next)
                && at <= self.clock_ns
            {
                self.release(i, at, status);
                next += 1;
            }
            let Some(i) = self.pick() else {
                // Idle: until the next trigger up to `t`; a later one waits
                // for the next update.
                match self.releases.get(next) {
                    Some(&(at, ..)) if at <= now_ns => self.clock_ns = self.clock_ns.max(at),
                    _ => break,
                }
                continue;
            };
            if self.clock_ns >= horizon_ns {
                break;
            }
            // Run it until it ends, until a trigger that may preempt it,
            // until its slice ends, or until the coarse update.
            let priority = self.tasks[i].priority;
            let mut stop = horizon_ns;
            if let Some(&(at, ..)) = self.releases[next..]
                .iter()
                .find(|&&(_, j, _)| self.tasks[j].priority <= priority)
            {
                stop = stop.min(at);
            }
            let shared = self
                .tasks
                .iter()
                .enumerate()
                .any(|(j, t)| j != i && t.priority == priority && t.busy());
            let slice_end = if shared {
                self.clock_ns + TIME_SLICE_NS
            } else {
                i64::MAX
            };
            let ended = self.run_task(i, stop.min(slice_end), task);
            if self.major.is_some() {
                break;
            }
            if !ended && self.clock_ns >= slice_end {
                // Its slice ended: behind the others of its priority.
                self.queue_seq += 1;
                self.tasks[i].queued = self.queue_seq;
            }
        }
        self.stats.wall += wall.elapsed();
    }

    /// The triggers before `horizon`, in time order: periodic triggers,
    /// event timeouts, and the motion group's execution at `now`. Those
    /// the clock does not reach in this update are collected again in the
    /// next.
    fn collect_releases(&mut self, now_ns: i64, horizon_ns: i64) {
        self.releases.clear();
        for (i, t) in self.tasks.iter().enumerate() {
            match t.kind {
                TaskKind::Periodic { .. } => {
                    let period = t.period_ns.unwrap_or(i64::MAX);
                    let mut at = t.next_ns;
                    while at < horizon_ns {
                        self.releases.push((at, i, 0));
                        at = at.saturating_add(period);
                    }
                }
                TaskKind::Event { trigger, .. } => {
                    if t.next_ns < horizon_ns {
                        self.releases.push((t.next_ns, i, STATUS_TIMEOUT));
                    }
                    if trigger == EventTrigger::MotionGroupExecution || t.registration_due {
                        self.releases.push((now_ns, i, 0));
                    }
                }
                TaskKind::Continuous => {}
            }
        }
        // In time order; at equal times the higher priority, then the
        // scene's order.
        let tasks = &self.tasks;
        self.releases.sort_by_key(|&(at, i, _)| (at, tasks[i].priority, i));
    }

    /// A trigger of task `i` at `at_ns` (`status`: the `Status` bits it
    /// sets): the task is ready to scan, or, when its previous trigger has
    /// not finished (or not started), the trigger is an overlap: ignored,
    /// counted, minor fault 6/2. An event task's trigger restarts its
    /// timeout.
    fn release(&mut self, i: usize, at_ns: i64, status: i64) {
        let t = &mut self.tasks[i];
        match t.kind {
            TaskKind::Periodic { .. } => t.next_ns = at_ns.saturating_add(t.period_ns.unwrap_or(i64::MAX)),
            TaskKind::Event { .. } => {
                if status == STATUS_TIMEOUT && t.next_ns != at_ns {
                    // A trigger came first and restarted the timeout.
                    return;
                }
                t.next_ns = t.period_ns.map_or(i64::MAX, |timeout| at_ns + timeout);
            }
            TaskKind::Continuous => {}
        }
        if self.sys.tasks[i].inhibit {
            return;
        }
        if t.busy() {
            self.sys.tasks[i].overlap_count += 1;
            self.sys.tasks[i].status |= STATUS_OVERLAP;
            let (program, routine) = t
                .programs
                .first()
                .map(|p| (p.name.clone(), p.routine_paths[0].clone()))
                .unwrap_or_default();
            let overlap = Fault {
                major: false,
                fault_type: 6,
                code: 2,
                message: format!(
                    "task overlap: the trigger at {:.3} ms found the task's previous scan {}; it is ignored",
                    at_ns as f64 / 1e6,
                    if t.active.is_some() {
                        "still running"
                    } else {
                        "still waiting to run"
                    }
                ),
                task: t.name.clone(),
                program,
                routine,
                line: 0,
                time_s: at_ns as f64 / 1e9,
                cleared: false,
            };
            self.minor_total += 1;
            self.sys.minor_events += 1;
            self.sys.minor_fault_bits |= 1 << 6;
            self.keep_minor(overlap);
            return;
        }
        self.queue_seq += 1;
        t.queued = self.queue_seq;
        t.pending = Some((at_ns.div_euclid(1000), status));
    }

    /// The task to run now: the highest priority among those with a scan
    /// to run or resume (the longest waiting first at equal priority), else
    /// the continuous task.
    fn pick(&mut self) -> Option<usize> {
        let best = self
            .tasks
            .iter()
            .enumerate()
            .filter(|(_, t)| t.busy())
            .min_by_key(|(_, t)| (t.priority, t.queued))
            .map(|(i, _)| i);
        if best.is_some() {
            return best;
        }
        let i = self.tasks.iter().position(|t| t.kind == TaskKind::Continuous)?;
        if self.sys.tasks[i].inhibit {
            return None;
        }
        self.tasks[i].pending = Some((self.clock_ns.div_euclid(1000), 0));
        Some(i)
    }

    /// Runs task `i`'s scan (starting it if it is pending) until it ends or
    /// the clock reaches `stop_ns`; `true` when it ended.
    fn run_task(&mut self, i: usize, stop_ns: i64, task: &mut MotionTask) -> bool {
        if self.tasks[i].active.is_none() {
            let (trigger_us, status) = self.tasks[i].pending.take().expect("a task to start");
            let wall_us = self.sys.wall_clock_us(self.clock_ns);
            let st = &mut self.sys.tasks[i];
            if let Some(last) = st.last_start_ns {
                let interval = (self.clock_ns - last) / 1000;
                st.max_interval_us = st.max_interval_us.max(interval);
                st.min_interval_us = if st.scans == 1 {
                    interval
                } else {
                    st.min_interval_us.min(interval)
                };
            }
            st.last_start_ns = Some(self.clock_ns);
            st.start_time_us = wall_us;
            st.status = (st.status & STATUS_OVERLAP) | status;
            st.scans += 1;
            self.tasks[i].active = Some(ActiveScan {
                trigger_us,
                start_ns: self.clock_ns,
                program: 0,
                program_start_ns: self.clock_ns,
                paused: None,
                statements: 0,
            });
        }
        loop {
            let t = &mut self.tasks[i];
            let scan = t.active.as_mut().expect("an active scan");
            let p = scan.program;
            if p >= t.programs.len() {
                if t.kind == TaskKind::Continuous && self.clock_ns == scan.start_ns {
                    // A continuous scan that executed nothing (its programs
                    // empty or disabled) still takes a statement's time, so
                    // that the controller's clock moves on.
                    self.clock_ns += self.statement_ns;
                }
                let elapsed_us = (self.clock_ns - scan.start_ns) / 1000;
                t.active = None;
                self.sys.tasks[i].scan_ended(elapsed_us);
                return true;
            }
            let program = &mut t.programs[p];
            if self.sys.programs[program.index].disabled {
                // Disabled before its scan (or while it was stopped, by a
                // higher-priority SSV): the rest of it is skipped.
                scan.paused = None;
                scan.program += 1;
                scan.program_start_ns = self.clock_ns;
                continue;
            }
            let starting = scan.paused.is_none();
            let first = starting && std::mem::replace(&mut program.first_scan, false);
            if starting {
                copy_parameters(&mut self.mem, &program.inputs);
            }
            let mut exec = Exec::new(
                &mut self.mem,
                task,
                scan.trigger_us,
                first,
                &program.routines,
                &mut self.scratch,
                self.minor_total,
            );
            exec.clock_ns = self.clock_ns;
            exec.aoi_from = program.aoi_from;
            exec.stop_ns = stop_ns;
            exec.statement_ns = self.statement_ns;
            exec.watchdog_ns = scan.start_ns + t.watchdog_ns;
            exec.watchdog_us = t.watchdog_us;
            exec.report_overflow = self.report_overflow;
            exec.fault_routine = program.fault_routine;
            exec.system = Some((&mut self.sys, i, program.index));
            match scan.paused.take() {
                Some(paused) => exec.resume(paused),
                None => exec.start(),
            }
            let result = exec.run();
            self.clock_ns = exec.clock_ns;
            scan.statements += exec.steps;
            self.stats.statements += exec.steps;
            self.minor_total = exec.minor_total;
            // What the scan left besides its progress (usually nothing).
            let extra = !(exec.minor.is_empty()
                && exec.refusals.is_empty()
                && exec.events.is_empty()
                && exec.cleared.is_empty());
            let taken = extra.then(|| {
                (
                    std::mem::take(&mut exec.minor),
                    std::mem::take(&mut exec.cleared),
                    std::mem::take(&mut exec.refusals),
                    std::mem::take(&mut exec.events),
                )
            });
            drop(exec);
            let (ended, paused, fault) = match result {
                Ok(Progress::Done) => (true, None, None),
                Ok(Progress::Paused(paused)) => (false, Some(paused), None),
                Err(raised) => (true, None, Some(raised)),
            };
            if ended {
                copy_parameters(&mut self.mem, &program.outputs);
                self.stats.scans += 1;
                self.sys.programs[program.index].scan_ended((self.clock_ns - scan.program_start_ns) / 1000);
                scan.program += 1;
                scan.program_start_ns = self.clock_ns;
            }
            scan.paused = paused;
            let stopped = scan.paused.is_some();
            let trigger_us = scan.trigger_us;
            if taken.is_some() || fault.is_some() {
                let (minor, mut cleared, refusals, events) = taken.unwrap_or_default();
                let fault = match fault {
                    Some(raised) if self.fault_handler.is_some() => {
                        match self.run_fault_handler(i, &raised, trigger_us, task) {
                            Ok(()) => {
                                // Cleared: the faulted scan ends here; the task
                                // runs again at its next trigger.
                                cleared.push(*raised);
                                if let Some(scan) = self.tasks[i].active.take() {
                                    self.sys.tasks[i].scan_ended((self.clock_ns - scan.start_ns) / 1000);
                                }
                                let _ = self.record(i, p, trigger_us, (minor, cleared), refusals, Ok(()));
                                return true;
                            }
                            Err(Some(standing)) => Some(standing),
                            // The handler itself faulted: recorded, the
                            // controller stopped.
                            Err(None) => return true,
                        }
                    }
                    other => other,
                };
                let outcome = fault.map_or(Ok(()), Err);
                if !self.record(i, p, trigger_us, (minor, cleared), refusals, outcome) {
                    return true;
                }
                for e in &events {
                    self.release(*e, self.clock_ns, STATUS_EVENT);
                }
                if !events.is_empty() {
                    // An event task may preempt: the scheduler decides
                    // what runs next (this scan resumes where it is).
                    return false;
                }
            }
            if stopped {
                // Stopped at `stop_ns`, or after an EVENT: the scheduler
                // decides what runs next.
                return false;
            }
        }
    }

    /// Runs the Controller Fault Handler's program for the major fault
    /// `raised` of task `i` (its `MajorFaultRecord` holds it): to its end,
    /// with the faulted task's watchdog. `Ok` when it cleared the record's
    /// Type and Code; else `Some` fault that stands, or `None` when the
    /// handler itself faulted (recorded: the controller is stopped).
    fn run_fault_handler(
        &mut self,
        i: usize,
        raised: &Raised,
        trigger_us: i64,
        task: &mut MotionTask,
    ) -> Result<(), Option<Box<Raised>>> {
        let Some(handler) = self.fault_handler.as_mut() else {
            return Err(Some(Box::new(raised.clone())));
        };
        let index = handler.index;
        self.sys.programs[index].major_record = self.sys.record(self.clock_ns, raised.fault_type, raised.code);
        let first = std::mem::replace(&mut handler.first_scan, false);
        copy_parameters(&mut self.mem, &handler.inputs);
        let mut exec = Exec::new(
            &mut self.mem,
            task,
            trigger_us,
            first,
            &handler.routines,
            &mut self.scratch,
            self.minor_total,
        );
        exec.clock_ns = self.clock_ns;
        exec.aoi_from = handler.aoi_from;
        exec.statement_ns = self.statement_ns;
        exec.watchdog_ns = self.clock_ns + self.tasks[i].watchdog_ns;
        exec.watchdog_us = self.tasks[i].watchdog_us;
        exec.report_overflow = self.report_overflow;
        exec.system = Some((&mut self.sys, i, index));
        exec.start();
        let result = exec.run();
        self.clock_ns = exec.clock_ns;
        self.stats.statements += exec.steps;
        self.stats.scans += 1;
        self.minor_total = exec.minor_total;
        let minor = std::mem::take(&mut exec.minor);
        drop(exec);
        let handler = self.fault_handler.as_ref().expect("the handler ran");
        copy_parameters(&mut self.mem, &handler.outputs);
        let fault = |r: Raised, major: bool| {
            Fault::of(
                r,
                major,
                "(controller fault handler)",
                &handler.name,
                &handler.routine_paths,
                trigger_us,
            )
        };
        let minor: Vec<Fault> = minor.into_iter().map(|r| fault(r, false)).collect();
        let own = result.as_ref().err().map(|r| fault((**r).clone(), true));
        for f in minor {
            self.keep_minor(f);
        }
        match (result, own) {
            (Ok(_), _) if self.sys.programs[index].major_record[2] == 0 => {
                self.sys.major_events += 1;
                self.sys.major_fault_bits |= 1 << raised.fault_type;
                Ok(())
            }
            (Ok(_), _) => Err(Some(Box::new(raised.clone()))),
            (Err(r), Some(f)) => {
                self.sys.major_events += 1;
                self.sys.major_fault_bits |= 1 << r.fault_type;
                self.log.push(f.clone());
                self.major = Some(f);
                Err(None)
            }
            (Err(r), None) => Err(Some(r)),
        }
    }

    /// Records a program scan's faults and refusals; `false` when a major
    /// fault stopped the controller.
    fn record(
        &mut self,
        i: usize,
        p: usize,
        at_us: i64,
        (minor, cleared): (Vec<Raised>, Vec<Raised>),
        refusals: Vec<String>,
        result: Result<(), Box<Raised>>,
    ) -> bool {
        self.refusals.extend(refusals);
        self.cap_refusals();
        if minor.is_empty() && cleared.is_empty() && result.is_ok() {
            return true;
        }
        let (task_name, program_name) = (self.tasks[i].name.clone(), self.tasks[i].programs[p].name.clone());
        let paths = self.tasks[i].programs[p].routine_paths.clone();
        let index = self.tasks[i].programs[p].index;
        let fault = |r: Raised, major: bool| Fault::of(r, major, &task_name, &program_name, &paths, at_us);
        for r in minor {
            self.keep_minor(fault(r, false));
        }
        for r in cleared {
            let f = Fault {
                cleared: true,
                ..fault(r, true)
            };
            self.log.push(f.clone());
            self.cleared.push(f);
        }
        match result {
            Ok(()) => true,
            Err(r) => {
                self.sys.major_events += 1;
                self.sys.major_fault_bits |= 1 << r.fault_type;
                self.sys.programs[index].major_record = self.sys.record(self.clock_ns, r.fault_type, r.code);
                let f = fault(*r, true);
                self.log.push(f.clone());
                self.major = Some(f);
                false
            }
        }
    }

    fn keep_minor(&mut self, f: Fault) {
        if self.minor.len() < MINOR_FAULTS_KEPT {
            self.log.push(f.clone());
            self.minor.push(f);
        }
    }

    /// The prescan (module doc), unless it ran: the first scan runs it, a
    /// sandbox may run it alone to see what it leaves.
    pub fn prescan_once(&mut self, task: &mut MotionTask) {
        if !self.prescanned {
            self.prescan(task);
            self.prescanned = true;
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
        // Add-On Instructions that execute their Prescan routine: each
        // call site's, once (1756-PM010). A fault there is a minor one.
        let programs = self.tasks.iter().flat_map(|t| &t.programs).chain(&self.fault_handler);
        for p in programs {
            for &k in &p.aoi_prescan {
                let mut exec = Exec::new(&mut self.mem, task, 0, false, &p.routines, &mut self.scratch, 0);
                exec.aoi_from = p.aoi_from;
                exec.statement_ns = self.statement_ns;
                if let Err(r) = exec.run_routine(k) {
                    let f = Fault::of(*r, false, "(prescan)", &p.name, &p.routine_paths, 0);
                    self.log.push(f.clone());
                    self.minor.push(f);
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

    /// The major faults fault routines cleared, in order.
    #[must_use]
    pub fn cleared_faults(&self) -> &[Fault] {
        &self.cleared
    }

    /// Every fault recorded, in order: minor ones (the first
    /// [`MINOR_FAULTS_KEPT`]), the major ones fault routines cleared, the
    /// major fault that stopped the controller.
    #[must_use]
    pub fn fault_log(&self) -> &[Fault] {
        &self.log
    }

    /// How many minor faults were recorded.
    #[must_use]
    pub fn minor_fault_count(&self) -> i64 {
        self.minor_total
    }

    /// Instructions that refused an operand's value at run time (ERR 13,
    /// also in their control structure) and SSVs that refused a value: the
    /// first [`REFUSALS_KEPT`].
    #[must_use]
    pub fn refusals(&self) -> &[String] {
        &self.refusals
    }

    /// How many refusals there were in all.
    #[must_use]
    pub fn refusal_count(&self) -> u64 {
        self.refusal_total
    }

    /// Counts the refusals added since the last call and keeps the first
    /// [`REFUSALS_KEPT`] (a refusal every scan of a fast task would grow
    /// the list without bound).
    pub(super) fn cap_refusals(&mut self) {
        let added = self.refusals.len().saturating_sub(self.refusals_counted);
        self.refusal_total += added as u64;
        self.refusals.truncate(REFUSALS_KEPT);
        self.refusals_counted = self.refusals.len();
    }

    /// What the tasks cost.
    #[must_use]
    pub fn stats(&self) -> &TaskStats {
        &self.stats
    }

    /// The system objects: each task's and program's status (scans, scan
    /// times, overlaps), the fault log's counts.
    #[must_use]
    pub fn system(&self) -> &System {
        &self.sys
    }

    /// The drive attributes SSV changed since the last call, by axis
    /// index in the scene, for the plant to take.
    pub fn take_drive_changes(&mut self) -> Vec<(usize, crate::scene::ServoGains)> {
        let changed = std::mem::take(&mut self.sys.drive_changes);
        changed
            .into_iter()
            .filter_map(|k| self.sys.drives.get(k).copied().flatten().map(|g| (k, g)))
            .collect()
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

    /// Sets the nominal time of a statement (`[controller] statement_us`),
    /// as a sandbox does for a routine longer than its task's period.
    pub fn set_statement_us(&mut self, us: f64) {
        self.statement_ns = ((us * 1000.0).round() as i64).max(1);
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
        Place::Path { base, terms } => {
            let mut slot = *base;
            for t in terms {
                let i = constant(&t.index);
                if !(0..t.len as i64).contains(&i) {
                    return Value::Int(0);
                }
                slot += i as usize * t.slots;
            }
            mem.slots[slot]
        }
        Place::Bit { inner, bit, .. } => Value::Bool(peek(inner, mem, task).as_i64() >> constant(bit) & 1 == 1),
        Place::Motion(..) | Place::Axis(..) | Place::Coord(..) | Place::Group(..) | Place::Fb(..) => {
            super::exec::members::planner_value(place, task).unwrap_or(Value::Int(0))
        }
        Place::MotionAt(handles, index, member, _) => usize::try_from(constant(index))
            .ok()
            .and_then(|k| handles.get(k))
            .and_then(|h| super::exec::members::planner_value(&Place::Motion(*h, *member), task))
            .unwrap_or(Value::Int(0)),
        Place::FirstScan | Place::MinorInScan | Place::MathFlag(_) => Value::Bool(false),
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
            SKind::Ladder(l) => prescan_ladder(l, mem, task),
            SKind::Motion(call) => prescan_motion(call, task),
            _ => {}
        }
    }
}

/// The prescan of a motion instruction: `.EN .DN .ER .IP` cleared.
fn prescan_motion(call: &super::ir::MotionCall, task: &mut MotionTask) {
    {
        {
            {
                let elements = call.operands.iter().flat_map(|o| match o {
                    super::ir::Operand::ControlAt(handles, ..) => handles.iter().copied(),
                    _ => [].iter().copied(),
                });
                for control in call.control.into_iter().chain(elements) {
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
        }
    }
}

/// Writes `v` to a place the prescan can reach without evaluating
/// anything: a slot, an element or a bit with a constant subscript.
fn set_constant_place(place: &Place, ty: super::types::DataType, v: Value, mem: &mut Memory) {
    let constant = |e: &super::ir::CExpr| match e.kind {
        super::ir::CKind::Const(c) => Some(c.as_i64()),
        _ => None,
    };
    match place {
        Place::Slot(i) => mem.slots[*i] = ty.store(v).0,
        Place::Element { index, .. } => {
            if let Some(i) = constant(index).and_then(|k| place.element_slot(k)) {
                mem.slots[i] = ty.store(v).0;
            }
        }
        Place::Bit { inner, width, bit, .. } => {
            if let (Place::Slot(i), Some(b)) = (&**inner, constant(bit))
                && (0..i64::from(*width)).contains(&b)
            {
                let old = mem.slots[*i].as_i64();
                let new = if v.truthy() { old | 1 << b } else { old & !(1 << b) };
                mem.slots[*i] = mem.types[*i].store(Value::Int(new)).0;
            }
        }
        _ => {}
    }
}

/// The prescan of a ladder instruction (1756-RM003's "Prescan" rows).
fn prescan_ladder(l: &super::ir::Ladder, mem: &mut Memory, task: &mut MotionTask) {
    use super::ir::{Ladder, OutputKind, StackKind, TimerKind};
    use super::types::{CT_DN, CT_EN, CT_ER, CT_EU, DataType, LC_CD, LC_CU, LT_ACC, LT_DN, LT_EN, LT_PRE, LT_TT};
    let bit =
        |place: &Place, on: bool, mem: &mut Memory| set_constant_place(place, DataType::Bool, Value::Bool(on), mem);
    let each = |inst: &super::ir::Instance, mem: &mut Memory, f: &dyn Fn(&mut [Value], usize)| {
        if !inst.terms.is_empty() {
            return;
        }
        let n = inst.index.as_ref().map_or(1, |(_, len)| *len);
        for k in 0..n {
            f(&mut mem.slots, inst.base + k * inst.structure.size());
        }
    };
    match l {
        Ladder::Output(OutputKind::Energize, place) => bit(place, false, mem),
        Ladder::Ons(storage) => bit(storage, true, mem),
        Ladder::Edge {
            rising,
            storage,
            output,
        } => {
            bit(storage, *rising, mem);
            bit(output, false, mem);
        }
        Ladder::Timer(kind, inst) => each(inst, mem, &|s, b| {
            for k in [LT_EN, LT_TT, LT_DN] {
                s[b + k] = Value::Bool(false);
            }
            match kind {
                TimerKind::On => s[b + LT_ACC] = Value::Int(0),
                TimerKind::Off => s[b + LT_ACC] = s[b + LT_PRE],
                TimerKind::Retentive => {}
            }
        }),
        Ladder::Counter(up, inst) => each(inst, mem, &|s, b| {
            s[b + if *up { LC_CU } else { LC_CD }] = Value::Bool(true)
        }),
        Ladder::Shift { control, .. } => each(control, mem, &|s, b| {
            for k in [CT_EN, CT_DN, CT_ER] {
                s[b + k] = Value::Bool(false);
            }
        }),
        Ladder::Stack { kind, control, .. } => {
            let k = match kind {
                StackKind::FifoLoad | StackKind::LifoLoad => CT_EN,
                StackKind::FifoUnload | StackKind::LifoUnload => CT_EU,
            };
            each(control, mem, &|s, b| s[b + k] = Value::Bool(true));
        }
        Ladder::Motion(call) => prescan_motion(call, task),
        _ => {}
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
