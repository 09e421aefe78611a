//! MATC (Motion Axis Time Cam): an axis follows a cam profile whose master
//! is time — the slave position as a function of the time since the cam
//! started — in Time Driven mode.
//!
//! # Operands (call order = faceplate index = ERR 13's EXERR)
//! `MATC(Axis, MotionControl, Direction, CamProfile, DistanceScaling,
//! TimeScaling, ExecutionMode, ExecutionSchedule, LockPosition,
//! LockDirection, InstructionMode)`, the operand table of the current
//! manual; older releases end at Execution Schedule (eight operands), a
//! call of eight is refused as a wrong operand count.
//! * Direction `same` (0), `opposite` (1), `reverse` (2: the opposite of
//!   the time cam running, else opposite), `unchanged` (3: that of the
//!   time cam running, else same).
//! * Cam Profile: a `CAM_PROFILE` MCCP calculated (its master values in
//!   seconds); ERR 30 while it is being calculated, 32 before.
//! * Distance Scaling multiplies the slave values, Time Scaling the master
//!   (time) values: a cam of 1 s with Time Scaling 2 takes 2 s. Distance
//!   Scaling may be any finite number; Time Scaling above 0. A cam whose
//!   peak speed (|Distance Scaling| × the profile's steepest slope / Time
//!   Scaling) would exceed the axis' maximum speed tenfold is refused with
//!   ERR 13 on Distance Scaling, as MAPC refuses one.
//! * Execution Mode `once` (0): the cam ends at the profile's last master
//!   value (`.PC`); `continuous` (1): it repeats, each cycle from where
//!   the last left the axis. Execution Schedule `immediate` (0), `pending`
//!   (1): after the time cam running ends (with none running, at once).
//! * Lock Position / Lock Direction: only Lock Direction `none` (0) is
//!   simulated (ERR 13 on Lock Direction otherwise). Instruction Mode
//!   `time driven` (0); `master driven` (1) needs MDAC, which the twin does
//!   not simulate: refused by name when the program loads.
//!
//! # Behaviour
//! The slave position is its position at the start plus Distance Scaling
//! × (profile(t / Time Scaling) − profile(first master value)), signed by
//! the direction; velocity and acceleration from the profile's slope and
//! curvature. A time cam is the one thing driving the axis, as a position
//! cam is: an immediate MATC ends a jog, a move, gearing or a position cam
//! on the axis, and a MAPC, a jog or a move ends the time cam. An
//! immediate MATC on an axis that is already time camming is ERR 23
//! (Illegal Dynamic Change). `.DN` when it executes, `.IP` while it runs
//! (pending too), `.PC` when a once cam ends. MAS with Stop Type All or
//! Time Cam ends it and ramps the axis to rest. `TimeCamStatus` while one
//! runs, `TimeCamPendingStatus` while one waits.

use super::entry::{Instruction, no_load, one_shot};
use crate::catalogue::words::{LOCK_DIRECTION, MAPC_DIRECTION, motion_control, op, w};
use crate::catalogue::{CallStyle, Format, Kind, Word};
use crate::instruction::{Fault, LogixFault, Refusal, fault};
use crate::profile::Sample;
use crate::task::engine::{Need, Takes, TimeCamRun};
use crate::task::{Args, AxisHandle, CamProfileHandle, InstructionHandle, MotionTask};
use thiserror::Error;

const EXECUTION_MODE: &[Word] = &[w("once", 0), w("continuous", 1)];
const EXECUTION_SCHEDULE: &[Word] = &[w("immediate", 0), w("pending", 1)];
const INSTRUCTION_MODE: &[Word] = &[w("timedriven", 0), w("masterdriven", 1)];

/// Motion Axis Time Cam.
pub const MATC: Instruction = Instruction {
    mnemonic: "MATC",
    title: "Motion Axis Time Cam",
    summary: "time cam: the axis follows a cam profile over time (distance and time scaling, once or continuous, immediate or pending)",
    reference: "Logix motion reference (MOTION-RM002, Motion Move Instructions)",
    style: CallStyle::Positional,
    operands: &[
        op("Axis", "AXIS", Format::Tag, Kind::Axis, 0),
        motion_control(1),
        op(
            "Direction",
            "UINT32",
            Format::Immediate,
            Kind::Enumeration(MAPC_DIRECTION),
            2,
        ),
        op("Cam Profile", "CAM_PROFILE", Format::Array, Kind::CamProfile, 3),
        op("Distance Scaling", "REAL", Format::ImmediateOrTag, Kind::Number, 4),
        op("Time Scaling", "REAL", Format::ImmediateOrTag, Kind::Number, 5),
        op(
            "Execution Mode",
            "UINT32",
            Format::Immediate,
            Kind::Enumeration(EXECUTION_MODE),
            6,
        ),
        op(
            "Execution Schedule",
            "UINT32",
            Format::Immediate,
            Kind::Enumeration(EXECUTION_SCHEDULE),
            7,
        ),
        op("Lock Position", "REAL", Format::ImmediateOrTag, Kind::Number, 8),
        op(
            "Lock Direction",
            "UINT32",
            Format::Immediate,
            Kind::Enumeration(LOCK_DIRECTION),
            9,
        ),
        op(
            "Instruction Mode",
            "UINT32",
            Format::Immediate,
            Kind::Enumeration(INSTRUCTION_MODE),
            10,
        ),
    ],
    execute,
    check,
    load: no_load,
};

/// MATC's own refusals.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Error)]
pub enum MatcFault {
    /// ERR 23: an immediate MATC on an axis already time camming.
    #[error("illegal dynamic change (ERR 23): the axis is already time camming; use Execution Schedule pending")]
    IllegalDynamicChange,
    /// ERR 30 or 32: the profile is not calculated.
    #[error("the cam profile is {} (ERR {})", if *.0 == 30 { "being calculated" } else { "not calculated" }, .0)]
    Profile(i32),
    /// Master Driven mode.
    #[error("Instruction Mode master driven needs MDAC, which the twin does not simulate")]
    MasterDriven,
}

impl LogixFault for MatcFault {
    fn err(&self) -> i32 {
        match self {
            Self::IllegalDynamicChange => 23,
            Self::Profile(e) => *e,
            Self::MasterDriven => 13,
        }
    }
    fn exerr(&self) -> i32 {
        match self {
            Self::MasterDriven => 10,
            _ => 0,
        }
    }
}

/// Why MATC fails.
pub type MatcError = Refusal<MatcFault>;

/// MATC's numeric operands.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MatcOperands {
    /// Direction code.
    pub direction: i64,
    /// Distance Scaling.
    pub distance_scaling: f64,
    /// Time Scaling.
    pub time_scaling: f64,
    /// Execution Mode, Execution Schedule, Lock Direction, Instruction Mode.
    pub codes: (i64, i64, i64, i64),
}

impl MatcOperands {
    /// The operands of a call, by catalogue position.
    #[must_use]
    pub fn bind(args: &Args<'_>) -> Self {
        Self {
            direction: args.integer(2),
            distance_scaling: args.number(4),
            time_scaling: args.number(5),
            codes: (args.integer(6), args.integer(7), args.integer(9), args.integer(10)),
        }
    }
}

/// A validated MATC: (direction code, continuous, pending).
///
/// # Errors
/// ERR 13 naming the operand; master driven mode by name.
pub fn validate(o: &MatcOperands) -> Result<(i64, bool, bool), MatcError> {
    let bad = |k: i32, v: f64| Refusal::operand(k, v);
    if !(0..=3).contains(&o.direction) {
        return Err(bad(2, o.direction as f64));
    }
    if !o.distance_scaling.is_finite() {
        return Err(bad(4, o.distance_scaling));
    }
    if !(o.time_scaling.is_finite() && o.time_scaling > 0.0) {
        return Err(bad(5, o.time_scaling));
    }
    let continuous = match o.codes.0 {
        0 => false,
        1 => true,
        m => return Err(bad(6, m as f64)),
    };
    let pending = match o.codes.1 {
        0 => false,
        1 => true,
        s => return Err(bad(7, s as f64)),
    };
    if o.codes.2 != 0 {
        return Err(bad(9, o.codes.2 as f64));
    }
    match o.codes.3 {
        0 => {}
        1 => return Err(Refusal::Instruction(MatcFault::MasterDriven)),
        m => return Err(bad(10, m as f64)),
    }
    Ok((o.direction, continuous, pending))
}

fn execute(task: &mut MotionTask, args: &Args<'_>) -> Result<(), Fault> {
    let control = args.control(1);
    let o = MatcOperands::bind(args);
    one_shot(task, control, |task| {
        task.matc(args.axis(0), control, args.cam_profile(3), &o)
    })
}

fn check(_: &MotionTask, args: &Args<'_>) -> Result<(), Fault> {
    validate(&MatcOperands::bind(args)).map(drop).map_err(fault)
}

impl MotionTask {
    /// MATC on `axis` (module doc).
    ///
    /// # Errors
    /// ERR 13 with EXERR = the operand, ERR 23, 30, 32, the axis-state
    /// errors.
    pub(crate) fn matc(
        &mut self,
        axis: AxisHandle,
        control: InstructionHandle,
        handle: CamProfileHandle,
        o: &MatcOperands,
    ) -> Result<(), MatcError> {
        self.instruction(control, |task| {
            let (direction, continuous, pending) = validate(o)?;
            task.check_state(axis, Need::Motion)?;
            let running = task
                .cam
                .axes
                .get(axis.0 as usize)
                .and_then(|c| c.time_cam.as_ref())
                .map(|r| r.sign);
            if running.is_some() && !pending {
                return Err(Refusal::Instruction(MatcFault::IllegalDynamicChange));
            }
            let sign = match (direction, running) {
                (0, _) => 1.0,
                (1, _) => -1.0,
                (2, Some(s)) => -s,
                (2, None) => -1.0,
                (_, Some(s)) => s,
                (_, None) => 1.0,
            };
            let profile = task.cam.profiles[handle.0 as usize]
                .1
                .acquire()
                .map_err(|s| Refusal::Instruction(MatcFault::Profile(if s == 1 { 30 } else { 32 })))?;
            let peak = o.distance_scaling.abs() * profile.peak_slope() / o.time_scaling;
            let allowed = crate::mapc::MAX_CAM_SPEED_RATIO * task.axes[axis.0 as usize].config.max_velocity;
            if !peak.is_finite() || peak > allowed {
                task.cam.profiles[handle.0 as usize].1.release();
                return Err(Refusal::operand(4, o.distance_scaling));
            }
            let run = TimeCamRun {
                control,
                handle,
                profile,
                sign,
                distance_scaling: o.distance_scaling,
                time_scaling: o.time_scaling,
                continuous,
                t_s: 0.0,
                origin: task.axes[axis.0 as usize].command.position,
            };
            if running.is_some() {
                if let Some(old) = task.cam_axis(axis).time_cam_pending.replace(run) {
                    task.end_time_cam_run(&old, false);
                }
            } else {
                task.take_axis(axis, Takes::ALL);
                task.cam_axis(axis).time_cam = Some(run);
            }
            let b = task.motion_bits_mut(control);
            b.dn = true;
            b.ip = true;
            Ok(())
        })
    }

    /// A time cam that ends: its MATC leaves `.IP` (`.PC` when it
    /// completed), its profile is released.
    pub(crate) fn end_time_cam_run(&mut self, run: &TimeCamRun, complete: bool) {
        let b = self.motion_bits_mut(run.control);
        b.ip = false;
        b.pc = complete;
        self.cam.profiles[run.handle.0 as usize].1.release();
    }

    /// Ends the time cams on `axis` (running and pending), the axis keeps
    /// its command state.
    pub(crate) fn end_time_cams(&mut self, axis: AxisHandle) -> bool {
        let Some(c) = self.cam.axes.get_mut(axis.0 as usize) else {
            return false;
        };
        let (running, pending) = (c.time_cam.take(), c.time_cam_pending.take());
        let any = running.is_some() || pending.is_some();
        for run in running.iter().chain(pending.iter()) {
            self.end_time_cam_run(run, false);
        }
        any
    }

    /// `TimeCamStatus` and `TimeCamPendingStatus` of `axis`.
    pub fn time_cam_status(&self, axis: AxisHandle) -> (bool, bool) {
        self.cam
            .axes
            .get(axis.0 as usize)
            .map_or((false, false), |c| (c.time_cam.is_some(), c.time_cam_pending.is_some()))
    }

    /// Advances every time cam one coarse update.
    pub(crate) fn advance_time_cams(&mut self) {
        let dt = self.dt_s;
        for i in 0..self.cam.axes.len().min(self.axes.len()) {
            let axis = AxisHandle(i as u32);
            let Some(mut run) = self.cam.axes[i].time_cam.take() else {
                continue;
            };
            run.t_s += dt;
            let (x0, xn) = run.profile.master_range();
            let span_s = (xn - x0) * run.time_scaling;
            let mut complete = false;
            if run.t_s >= span_s {
                if run.continuous {
                    // The next cycle starts where this one left the axis.
                    let (s0, sn) = run.profile.slave_range();
                    while run.t_s >= span_s && span_s > 0.0 {
                        run.t_s -= span_s;
                        run.origin += run.sign * run.distance_scaling * (sn - s0);
                    }
                } else {
                    run.t_s = span_s;
                    complete = true;
                }
            }
            let k = run.sign * run.distance_scaling;
            let p = run.profile.eval(x0 + run.t_s / run.time_scaling);
            let start = run.profile.eval(x0).slave;
            let sample = Sample {
                position: run.origin + k * (p.slave - start),
                velocity: if complete { 0.0 } else { k * p.slope / run.time_scaling },
                acceleration: if complete {
                    0.0
                } else {
                    k * p.curvature / (run.time_scaling * run.time_scaling)
                },
                jerk: 0.0,
            };
            self.set_command(axis, sample);
            if complete {
                self.end_time_cam_run(&run, true);
                if let Some(mut next) = self.cam.axes[i].time_cam_pending.take() {
                    next.origin = sample.position;
                    next.t_s = 0.0;
                    self.cam.axes[i].time_cam = Some(next);
                }
            } else {
                self.cam.axes[i].time_cam = Some(run);
            }
        }
    }
}

#[cfg(test)]
mod tests;
