//! MCD (Motion Change Dynamics): changes the speed, acceleration,
//! deceleration and jerks of the jog (MAJ) or the move (MAM) an axis runs,
//! on the fly.
//!
//! # Operands (the operand table's order, faceplate index = ERR 13's EXERR)
//! `MCD(Axis, MotionControl, MotionType, ChangeSpeed, Speed, ChangeAccel,
//! AccelRate, ChangeDecel, DecelRate, ChangeAccelJerk, AccelJerk,
//! ChangeDecelJerk, DecelJerk, SpeedUnits, AccelUnits, DecelUnits,
//! JerkUnits)`. The online help's Structured Text syntax line lists 16
//! operands in another order (Change Decel and Decel Rate after Change
//! Decel Jerk, and no Decel Jerk): the twin follows the operand table,
//! which has all 17, and a call of 16 is refused as a wrong operand count.
//!
//! * Motion Type `jog` (0) changes the running MAJ, `move` (1) the running
//!   MAM.
//! * Each Change operand (`no` 0 / `yes` 1) says whether its value applies;
//!   a value whose Change is `no` is neither read nor checked.
//! * Speed in units/s or % of the axis' maximum speed; Accel and Decel Rate
//!   in units/s² or % of the axis' maximum acceleration / deceleration;
//!   the jerks in units/s³, % of the axis' maximum jerk, or % of time (the
//!   MAM conversion, with the speed and rates the motion has after the
//!   change).
//!
//! # Behaviour
//! The ramp is planned again from the axis' command state when MCD
//! executes (position, velocity and acceleration carry over: no step),
//! with the new limits and the same aim — the jog's direction at its (new)
//! speed, the move's target at rest. A speed lowered below the present one
//! is reached with the deceleration limits, as Logix decelerates to a
//! lowered speed. `.DN` is set in the scan it executes ("the instruction
//! execution completes in a single scan, and the DN bit is set
//! immediately"); MCD uses no `.IP` or `.PC`. The MAJ's or MAM's own bits
//! go on as before: the move still sets its `.PC` at the target.
//!
//! # Choices where the manual is silent
//! * With no jog (no move) of the Motion Type running on the axis, MCD
//!   changes nothing and still sets `.DN`: there is nothing in process for
//!   it to change, and the manual lists no error for it. A stop ramp (MAS)
//!   is not a jog: MCD leaves it alone.
//! * MCD changes the ramp an axis runs by itself; a MAM superimposed on a
//!   cam or coordinated motion (`task/superimposed.rs`) keeps its dynamics.
//! * A jerk change on a trapezoidal jog or move is checked and has no
//!   effect (a trapezoid has no jerk). A jerk given in % of time is turned
//!   into units/s³ when MCD executes, from the speed and rates the motion
//!   then has.
//! * Speed 0 is a valid jog speed (the axis ramps to rest and the jog stays
//!   in process, as MAJ allows); a move needs a speed above 0.

use super::entry::{Instruction, no_load, one_shot};
use crate::axis::AxisConfig;
use crate::catalogue::words::{
    JOG_ACCEL_UNITS, JOG_SPEED_UNITS, NO_YES, NUMERIC, TIME_JERK_UNITS, motion_control, op, w,
};
use crate::catalogue::{CallStyle, Format, Kind, Word};
use crate::dynamics::time_rate;
use crate::instruction::{Fault, NoFault, Refusal, fault};
use crate::profile::{Limits, Profile, Shape, jerk_from_percent_of_time};
use crate::task::engine::{RampAim, RampPlan};
use crate::task::{Args, AxisHandle, InstructionHandle, MotionTask};

/// MCD's Motion Type.
const MOTION_TYPE: &[Word] = &[w("jog", 0), w("move", 1)];

/// Motion Change Dynamics.
pub const MCD: Instruction = Instruction {
    mnemonic: "MCD",
    title: "Motion Change Dynamics",
    summary: "changes the speed, accel, decel and jerks of a running jog or move on the fly, from the axis' state (no step)",
    reference: "Logix motion reference",
    style: CallStyle::Positional,
    operands: &[
        op("Axis", "AXIS", Format::Tag, Kind::Axis, 0),
        motion_control(1),
        op(
            "Motion Type",
            "UDINT",
            Format::Immediate,
            Kind::Enumeration(MOTION_TYPE),
            2,
        ),
        op(
            "Change Speed",
            "BOOLEAN",
            Format::Immediate,
            Kind::Enumeration(NO_YES),
            3,
        ),
        op("Speed", NUMERIC, Format::ImmediateOrTag, Kind::Number, 4),
        op(
            "Change Accel",
            "BOOLEAN",
            Format::Immediate,
            Kind::Enumeration(NO_YES),
            5,
        ),
        op("Accel Rate", NUMERIC, Format::ImmediateOrTag, Kind::Number, 6),
        op(
            "Change Decel",
            "BOOLEAN",
            Format::Immediate,
            Kind::Enumeration(NO_YES),
            7,
        ),
        op("Decel Rate", NUMERIC, Format::ImmediateOrTag, Kind::Number, 8),
        op(
            "Change Accel Jerk",
            "BOOLEAN",
            Format::Immediate,
            Kind::Enumeration(NO_YES),
            9,
        ),
        op("Accel Jerk", NUMERIC, Format::ImmediateOrTag, Kind::Number, 10),
        op(
            "Change Decel Jerk",
            "BOOLEAN",
            Format::Immediate,
            Kind::Enumeration(NO_YES),
            11,
        ),
        op("Decel Jerk", NUMERIC, Format::ImmediateOrTag, Kind::Number, 12),
        op(
            "Speed Units",
            "DINT",
            Format::Immediate,
            Kind::Enumeration(JOG_SPEED_UNITS),
            13,
        ),
        op(
            "Accel Units",
            "DINT",
            Format::Immediate,
            Kind::Enumeration(JOG_ACCEL_UNITS),
            14,
        ),
        op(
            "Decel Units",
            "DINT",
            Format::Immediate,
            Kind::Enumeration(JOG_ACCEL_UNITS),
            15,
        ),
        op(
            "Jerk Units",
            "DINT",
            Format::Immediate,
            Kind::Enumeration(TIME_JERK_UNITS),
            16,
        ),
    ],
    execute,
    check,
    load: no_load,
};

/// Why MCD fails: ERR 13 with the operand.
pub type McdError = Refusal<NoFault>;

/// One value of MCD with its Change flag.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Change {
    /// The Change operand's code (0 no, 1 yes).
    pub flag: i64,
    /// The value.
    pub value: f64,
}

impl Change {
    /// A value that is not changed.
    pub const NONE: Change = Change { flag: 0, value: 0.0 };

    /// A value that is changed to `value`.
    #[must_use]
    pub fn to(value: f64) -> Change {
        Change { flag: 1, value }
    }
}

/// MCD's operands after the axis and the control structure.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct McdOperands {
    /// 0 jog, 1 move.
    pub motion_type: i64,
    /// Speed and its Change.
    pub speed: Change,
    /// Accel Rate and its Change.
    pub accel: Change,
    /// Decel Rate and its Change.
    pub decel: Change,
    /// Accel Jerk and its Change.
    pub accel_jerk: Change,
    /// Decel Jerk and its Change.
    pub decel_jerk: Change,
    /// 0 units per sec, 1 % of maximum.
    pub speed_units: i64,
    /// 0 units per sec², 1 % of maximum.
    pub accel_units: i64,
    /// 0 units per sec², 1 % of maximum.
    pub decel_units: i64,
    /// 0 units per sec³, 1 % of maximum, 2 % of time.
    pub jerk_units: i64,
}

impl Default for McdOperands {
    fn default() -> Self {
        Self {
            motion_type: 1,
            speed: Change::NONE,
            accel: Change::NONE,
            decel: Change::NONE,
            accel_jerk: Change::NONE,
            decel_jerk: Change::NONE,
            speed_units: 0,
            accel_units: 0,
            decel_units: 0,
            jerk_units: 0,
        }
    }
}

impl McdOperands {
    /// The operands of a call, by catalogue position.
    #[must_use]
    pub fn bind(args: &Args<'_>) -> Self {
        let change = |flag: usize| Change {
            flag: args.integer(flag),
            value: args.number(flag + 1),
        };
        Self {
            motion_type: args.integer(2),
            speed: change(3),
            accel: change(5),
            decel: change(7),
            accel_jerk: change(9),
            decel_jerk: change(11),
            speed_units: args.integer(13),
            accel_units: args.integer(14),
            decel_units: args.integer(15),
            jerk_units: args.integer(16),
        }
    }
}

/// Faceplate indices (ERR 13's EXERR).
mod exerr {
    use super::MCD;

    pub(super) const MOTION_TYPE: i32 = MCD.exerr("Motion Type");
    pub(super) const CHANGE_SPEED: i32 = MCD.exerr("Change Speed");
    pub(super) const SPEED: i32 = MCD.exerr("Speed");
    pub(super) const CHANGE_ACCEL: i32 = MCD.exerr("Change Accel");
    pub(super) const ACCEL_RATE: i32 = MCD.exerr("Accel Rate");
    pub(super) const CHANGE_DECEL: i32 = MCD.exerr("Change Decel");
    pub(super) const DECEL_RATE: i32 = MCD.exerr("Decel Rate");
    pub(super) const CHANGE_ACCEL_JERK: i32 = MCD.exerr("Change Accel Jerk");
    pub(super) const ACCEL_JERK: i32 = MCD.exerr("Accel Jerk");
    pub(super) const CHANGE_DECEL_JERK: i32 = MCD.exerr("Change Decel Jerk");
    pub(super) const DECEL_JERK: i32 = MCD.exerr("Decel Jerk");
    pub(super) const SPEED_UNITS: i32 = MCD.exerr("Speed Units");
    pub(super) const ACCEL_UNITS: i32 = MCD.exerr("Accel Units");
    pub(super) const DECEL_UNITS: i32 = MCD.exerr("Decel Units");
    pub(super) const JERK_UNITS: i32 = MCD.exerr("Jerk Units");
}

/// Which motion MCD changes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MotionType {
    /// 0: the running MAJ.
    Jog,
    /// 1: the running MAM.
    Move,
}

/// A validated MCD: the motion it changes and the new values, converted
/// to axis units (s, units/s, units/s², units/s³); `None` where a value is
/// not changed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Mcd {
    /// The motion it changes.
    pub motion_type: MotionType,
    /// New speed.
    pub speed: Option<f64>,
    /// New acceleration limit.
    pub accel: Option<f64>,
    /// New deceleration limit.
    pub decel: Option<f64>,
    /// New accel jerk, with the value still in % of time (converted by
    /// [`Mcd::limits`], which knows the speed and rate).
    pub accel_jerk: Option<Jerk>,
    /// New decel jerk, as [`Mcd::accel_jerk`].
    pub decel_jerk: Option<Jerk>,
}

/// A jerk operand: in units/s³, or in % of time (a function of the speed
/// and rate the motion will have).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Jerk {
    /// units/s³.
    Absolute(f64),
    /// % of time, with its faceplate index for a refusal.
    PercentOfTime(f64, i32),
}

fn bad(operand: i32, value: f64) -> McdError {
    Refusal::operand(operand, value)
}

/// Whether a Change operand says yes.
pub(super) fn changed(flag: i64, operand: i32) -> Result<bool, McdError> {
    match flag {
        0 => Ok(false),
        1 => Ok(true),
        f => Err(bad(operand, f as f64)),
    }
}

/// A changed rate in units/s (units 0) or % of `max` (units 1): finite,
/// above 0 (or 0 where `zero_ok`). `operands` are the faceplate indices
/// of the Change, the value and the units.
pub(super) fn rate(
    change: Change,
    (flag, operand, units_operand): (i32, i32, i32),
    units: i64,
    max: f64,
    zero_ok: bool,
) -> Result<Option<f64>, McdError> {
    if !changed(change.flag, flag)? {
        return Ok(None);
    }
    let v = time_rate(change.value, units, max).ok_or(bad(units_operand, units as f64))?;
    if v.is_finite() && (v > 0.0 || (zero_ok && v == 0.0)) {
        Ok(Some(v))
    } else {
        Err(bad(operand, change.value))
    }
}

/// A changed jerk in units/s³ (units 0), % of `max` (1) or % of time (2,
/// kept as a percentage for the speed and rate after the change); the
/// faceplate indices of the Change, the jerk and the Jerk Units.
pub(super) fn jerk_change(
    change: Change,
    (flag, operand, units_operand): (i32, i32, i32),
    units: i64,
    max: f64,
) -> Result<Option<Jerk>, McdError> {
    if !changed(change.flag, flag)? {
        return Ok(None);
    }
    let value = change.value;
    let j = match units {
        0 => value,
        1 => value / 100.0 * max,
        2 if value.is_finite() && value > 0.0 && value <= 100.0 => {
            return Ok(Some(Jerk::PercentOfTime(value, operand)));
        }
        2 => return Err(bad(operand, value)),
        u => return Err(bad(units_operand, u as f64)),
    };
    if j.is_finite() && j > 0.0 {
        Ok(Some(Jerk::Absolute(j)))
    } else {
        Err(bad(operand, value))
    }
}

impl Mcd {
    /// Validates MCD's operands against the axis.
    ///
    /// # Errors
    /// ERR 13 naming the first operand out of range.
    pub fn new(o: &McdOperands, axis: &AxisConfig) -> Result<Self, McdError> {
        use exerr::*;
        let motion_type = match o.motion_type {
            0 => MotionType::Jog,
            1 => MotionType::Move,
            t => return Err(bad(MOTION_TYPE, t as f64)),
        };
        let jog = motion_type == MotionType::Jog;
        let speed = rate(
            o.speed,
            (CHANGE_SPEED, SPEED, SPEED_UNITS),
            o.speed_units,
            axis.max_velocity,
            jog,
        )?;
        let accel = rate(
            o.accel,
            (CHANGE_ACCEL, ACCEL_RATE, ACCEL_UNITS),
            o.accel_units,
            axis.max_acceleration,
            false,
        )?;
        let decel = rate(
            o.decel,
            (CHANGE_DECEL, DECEL_RATE, DECEL_UNITS),
            o.decel_units,
            axis.max_deceleration,
            false,
        )?;
        let jerk = |change: Change, flag: i32, operand: i32| {
            jerk_change(change, (flag, operand, JERK_UNITS), o.jerk_units, axis.max_jerk)
        };
        Ok(Self {
            motion_type,
            speed,
            accel,
            decel,
            accel_jerk: jerk(o.accel_jerk, CHANGE_ACCEL_JERK, ACCEL_JERK)?,
            decel_jerk: jerk(o.decel_jerk, CHANGE_DECEL_JERK, DECEL_JERK)?,
        })
    }

    /// The limits and aim of a ramp planned with `plan`, after the change.
    /// A jog's limit speed stays at least the axis maximum (as MAJ plans
    /// it); a move's is its speed.
    ///
    /// # Errors
    /// ERR 13 on a jerk in % of time that the new speed or rate cannot
    /// convert (a jog at speed 0).
    pub(crate) fn apply(&self, plan: &RampPlan, axis: &AxisConfig) -> Result<RampPlan, McdError> {
        let old = plan.limits;
        let (aim, velocity) = match plan.aim {
            RampAim::Jog { sign, speed } => {
                let speed = self.speed.unwrap_or(speed);
                (RampAim::Jog { sign, speed }, speed.max(axis.max_velocity))
            }
            aim @ RampAim::Move { .. } => (aim, self.speed.unwrap_or(old.velocity())),
        };
        let speed = match aim {
            RampAim::Jog { speed, .. } => speed,
            RampAim::Move { .. } => velocity,
        };
        let accel = self.accel.unwrap_or(old.acceleration());
        let decel = self.decel.unwrap_or(old.deceleration());
        let limits = match old.shape() {
            Shape::Trapezoidal => Limits::trapezoidal(velocity, accel, decel),
            Shape::SCurve { accel_jerk, decel_jerk } => {
                let convert = |jerk: Option<Jerk>, old: f64, rate: f64| match jerk {
                    None => Ok(old),
                    Some(Jerk::Absolute(j)) => Ok(j),
                    Some(Jerk::PercentOfTime(p, operand)) => {
                        jerk_from_percent_of_time(p, rate, speed).map_err(|_| bad(operand, p))
                    }
                };
                let ja = convert(self.accel_jerk, accel_jerk, accel)?;
                let jd = convert(self.decel_jerk, decel_jerk, decel)?;
                Limits::s_curve(velocity, accel, decel, ja, jd)
            }
        }
        .map_err(|_| bad(exerr::SPEED, speed))?;
        Ok(RampPlan { limits, aim })
    }
}

fn execute(task: &mut MotionTask, args: &Args<'_>) -> Result<(), Fault> {
    let control = args.control(1);
    one_shot(task, control, |task| {
        task.mcd(args.axis(0), control, &McdOperands::bind(args))
    })
}

fn check(task: &MotionTask, args: &Args<'_>) -> Result<(), Fault> {
    Mcd::new(&McdOperands::bind(args), task.axis_config(args.axis(0)))
        .map(|_| ())
        .map_err(fault)
}

impl MotionTask {
    /// MCD: changes the dynamics of the jog or move `axis` runs (module
    /// doc). `.DN` at once.
    ///
    /// # Errors
    /// ERR 13 with EXERR = the operand; the motion keeps its dynamics.
    pub(crate) fn mcd(
        &mut self,
        axis: AxisHandle,
        control: InstructionHandle,
        operands: &McdOperands,
    ) -> Result<(), McdError> {
        self.instruction(control, |task| {
            let config = task.axis_config(axis).clone();
            let mcd = Mcd::new(operands, &config)?;
            let state = task.axes[axis.0 as usize].command.state();
            let ramp = task.cam.axes.get_mut(axis.0 as usize).and_then(|c| c.ramp.as_mut());
            if let Some(r) = ramp {
                let runs = match mcd.motion_type {
                    MotionType::Jog => r.jog.is_some(),
                    MotionType::Move => r.mv.is_some(),
                };
                if let (true, Some(plan)) = (runs, r.plan) {
                    let plan = mcd.apply(&plan, &config)?;
                    r.profile = match plan.aim {
                        RampAim::Jog { sign, speed } => Profile::to_velocity(state, sign * speed, &plan.limits),
                        RampAim::Move { target } => Profile::to_position(state, target, 0.0, &plan.limits),
                    };
                    r.t_s = 0.0;
                    r.plan = Some(plan);
                }
            }
            task.motion_bits_mut(control).dn = true;
            Ok(())
        })
    }
}

#[cfg(test)]
mod tests;
