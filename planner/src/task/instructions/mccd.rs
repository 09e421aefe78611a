//! MCCD (Motion Coordinated Change Dynamics): changes the speed,
//! acceleration, deceleration and jerks of a coordinate system's
//! coordinated move (MCLM, MCCM) on the fly, and with Scope *active and
//! pending motion* those of the move queued behind it.
//!
//! # Operands (call order = faceplate index = ERR 13's EXERR)
//! `MCCD(CoordinateSystem, MotionControl, MotionType, ChangeSpeed, Speed,
//! SpeedUnits, ChangeAccel, AccelRate, AccelUnits, ChangeDecel, DecelRate,
//! DecelUnits, ChangeAccelJerk, AccelJerk, ChangeDecelJerk, DecelJerk,
//! JerkUnits, Scope)`: Motion Type `coordinated move` (0); each Change
//! `no` (0) / `yes` (1); Speed in units/s or % of the system's maximum
//! speed, the rates in units/s² or % of its maximum accel / decel, the
//! jerks in units/s³, % of its maximum jerks or % of time (with the speed
//! and rates after the change); Scope `active motion` (0) or `active and
//! pending motion` (1). A value whose Change is `no` is neither read nor
//! checked.
//!
//! # Behaviour
//! The active move's path profile is planned again from where it stands
//! on its path (length, path speed and acceleration carry over: no step)
//! to its end point with the new limits, ending at the speed it was
//! planned to end at (a follow-contour junction speed, or rest). Its blend
//! point is found again on the new profile, as when it started. A speed
//! lowered below the present one is reached with the deceleration limits.
//! With Scope *active and pending*, the pending move takes the same
//! changes and starts with them. `.DN` in the scan it executes; MCCD has
//! no `.IP` or `.PC`; the moves keep their bits.
//!
//! # Choices where the manual is silent
//! * The active move is the newest one the system runs; while it blends
//!   out of the one before, that one finishes as planned.
//! * With no coordinated move in process, MCCD changes nothing and still
//!   sets `.DN` (with Scope *active and pending*, a queued move is
//!   changed all the same).
//! * Units per master unit are not offered (a time-driven change): MCCD on
//!   a master-driven move is ERR 13 on Speed Units, the mode change the
//!   manual refuses at run time. A move programmed at speed 0 (it never
//!   advances) keeps speed 0 unless MCCD changes its speed.
//! * Speed 0 is a feed hold: the active move decelerates with its
//!   deceleration limits to rest on its path and stays there, `.IP` and
//!   its bits as they were, no blend to the pending move meanwhile; an
//!   MCCD that changes the speed again resumes it to its end point (one
//!   that changes only rates keeps it held). A hold leaves the pending move
//!   as it is (a queued move at speed 0 would never advance).

use super::entry::{Instruction, no_load, one_shot};
use super::mcd::{Change, Jerk, jerk_change, rate};
use crate::catalogue::words::{ACCEL_UNITS, JERK_UNITS, NO_YES, NUMERIC, SPEED_UNITS, motion_control, op, w};
use crate::catalogue::{CallStyle, Format, Kind, Word};
use crate::coord::{CoordMove, CoordinateSystemConfig, Driver, progress_at_length, with_velocity};
use crate::instruction::{Fault, NoFault, Refusal, fault};
use crate::profile::{Limits, Profile, Shape, State, jerk_from_percent_of_time};
use crate::task::{Args, CoordHandle, InstructionHandle, MotionTask};

/// MCCD's Motion Type.
const MOTION_TYPE: &[Word] = &[w("coordinatedmove", 0)];
/// MCCD's Scope.
const SCOPE: &[Word] = &[w("activemotion", 0), w("activeandpendingmotion", 1)];

/// Motion Coordinated Change Dynamics.
pub const MCCD: Instruction = Instruction {
    mnemonic: "MCCD",
    title: "Motion Coordinated Change Dynamics",
    summary: "changes the speed, accel, decel and jerks of a coordinate system's active move (and with scope, its pending one) on the fly",
    reference: "Logix motion reference (MOTION-RM002, Multi-Axis Coordinated Motion)",
    style: CallStyle::Positional,
    operands: &[
        op(
            "Coordinate System",
            "COORDINATE_SYSTEM",
            Format::Tag,
            Kind::CoordinateSystem,
            0,
        ),
        motion_control(1),
        op(
            "Motion Type",
            "DINT",
            Format::Immediate,
            Kind::Enumeration(MOTION_TYPE),
            2,
        ),
        op("Change Speed", "DINT", Format::Immediate, Kind::Enumeration(NO_YES), 3),
        op("Speed", NUMERIC, Format::ImmediateOrTag, Kind::Number, 4),
        op(
            "Speed Units",
            "DINT",
            Format::Immediate,
            Kind::Enumeration(SPEED_UNITS),
            5,
        ),
        op("Change Accel", "DINT", Format::Immediate, Kind::Enumeration(NO_YES), 6),
        op("Accel Rate", NUMERIC, Format::ImmediateOrTag, Kind::Number, 7),
        op(
            "Accel Units",
            "DINT",
            Format::Immediate,
            Kind::Enumeration(ACCEL_UNITS),
            8,
        ),
        op("Change Decel", "DINT", Format::Immediate, Kind::Enumeration(NO_YES), 9),
        op("Decel Rate", NUMERIC, Format::ImmediateOrTag, Kind::Number, 10),
        op(
            "Decel Units",
            "DINT",
            Format::Immediate,
            Kind::Enumeration(ACCEL_UNITS),
            11,
        ),
        op(
            "Change Accel Jerk",
            "DINT",
            Format::Immediate,
            Kind::Enumeration(NO_YES),
            12,
        ),
        op("Accel Jerk", NUMERIC, Format::ImmediateOrTag, Kind::Number, 13),
        op(
            "Change Decel Jerk",
            "DINT",
            Format::Immediate,
            Kind::Enumeration(NO_YES),
            14,
        ),
        op("Decel Jerk", NUMERIC, Format::ImmediateOrTag, Kind::Number, 15),
        op(
            "Jerk Units",
            "DINT",
            Format::Immediate,
            Kind::Enumeration(JERK_UNITS),
            16,
        ),
        op("Scope", "DINT", Format::Immediate, Kind::Enumeration(SCOPE), 17),
    ],
    execute,
    check,
    load: no_load,
};

/// Why MCCD fails: ERR 13 with the operand.
pub type MccdError = Refusal<NoFault>;

/// MCCD's operands after the system and the control structure.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MccdOperands {
    /// 0 coordinated move.
    pub motion_type: i64,
    /// Speed and its Change.
    pub speed: Change,
    /// 0 units per sec, 1 % of maximum.
    pub speed_units: i64,
    /// Accel Rate and its Change.
    pub accel: Change,
    /// 0 units per sec², 1 % of maximum.
    pub accel_units: i64,
    /// Decel Rate and its Change.
    pub decel: Change,
    /// 0 units per sec², 1 % of maximum.
    pub decel_units: i64,
    /// Accel Jerk and its Change.
    pub accel_jerk: Change,
    /// Decel Jerk and its Change.
    pub decel_jerk: Change,
    /// 0 units per sec³, 1 % of maximum, 2 % of time.
    pub jerk_units: i64,
    /// 0 active motion, 1 active and pending motion.
    pub scope: i64,
}

impl Default for MccdOperands {
    fn default() -> Self {
        Self {
            motion_type: 0,
            speed: Change::NONE,
            speed_units: 0,
            accel: Change::NONE,
            accel_units: 0,
            decel: Change::NONE,
            decel_units: 0,
            accel_jerk: Change::NONE,
            decel_jerk: Change::NONE,
            jerk_units: 0,
            scope: 0,
        }
    }
}

impl MccdOperands {
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
            speed_units: args.integer(5),
            accel: change(6),
            accel_units: args.integer(8),
            decel: change(9),
            decel_units: args.integer(11),
            accel_jerk: change(12),
            decel_jerk: change(14),
            jerk_units: args.integer(16),
            scope: args.integer(17),
        }
    }
}

/// Faceplate indices (ERR 13's EXERR).
mod exerr {
    use super::MCCD;

    pub(super) const MOTION_TYPE: i32 = MCCD.exerr("Motion Type");
    pub(super) const CHANGE_SPEED: i32 = MCCD.exerr("Change Speed");
    pub(super) const SPEED: i32 = MCCD.exerr("Speed");
    pub(super) const SPEED_UNITS: i32 = MCCD.exerr("Speed Units");
    pub(super) const CHANGE_ACCEL: i32 = MCCD.exerr("Change Accel");
    pub(super) const ACCEL_RATE: i32 = MCCD.exerr("Accel Rate");
    pub(super) const ACCEL_UNITS: i32 = MCCD.exerr("Accel Units");
    pub(super) const CHANGE_DECEL: i32 = MCCD.exerr("Change Decel");
    pub(super) const DECEL_RATE: i32 = MCCD.exerr("Decel Rate");
    pub(super) const DECEL_UNITS: i32 = MCCD.exerr("Decel Units");
    pub(super) const CHANGE_ACCEL_JERK: i32 = MCCD.exerr("Change Accel Jerk");
    pub(super) const ACCEL_JERK: i32 = MCCD.exerr("Accel Jerk");
    pub(super) const CHANGE_DECEL_JERK: i32 = MCCD.exerr("Change Decel Jerk");
    pub(super) const DECEL_JERK: i32 = MCCD.exerr("Decel Jerk");
    pub(super) const JERK_UNITS: i32 = MCCD.exerr("Jerk Units");
    pub(super) const SCOPE: i32 = MCCD.exerr("Scope");
}

fn bad(operand: i32, value: f64) -> MccdError {
    Refusal::operand(operand, value)
}

/// A validated MCCD, its values in coordinate units (`None`: unchanged).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Mccd {
    speed: Option<f64>,
    accel: Option<f64>,
    decel: Option<f64>,
    accel_jerk: Option<Jerk>,
    decel_jerk: Option<Jerk>,
    /// Scope active and pending.
    pub pending_too: bool,
}

impl Mccd {
    /// Validates the operands against the system's configuration.
    ///
    /// # Errors
    /// ERR 13 naming the first operand out of range.
    pub fn new(o: &MccdOperands, sys: &CoordinateSystemConfig) -> Result<Self, MccdError> {
        use exerr::*;
        if o.motion_type != 0 {
            return Err(bad(MOTION_TYPE, o.motion_type as f64));
        }
        let speed = rate(
            o.speed,
            (CHANGE_SPEED, SPEED, SPEED_UNITS),
            o.speed_units,
            sys.max_speed,
            true,
        )?;
        let accel = rate(
            o.accel,
            (CHANGE_ACCEL, ACCEL_RATE, ACCEL_UNITS),
            o.accel_units,
            sys.max_accel,
            false,
        )?;
        let decel = rate(
            o.decel,
            (CHANGE_DECEL, DECEL_RATE, DECEL_UNITS),
            o.decel_units,
            sys.max_decel,
            false,
        )?;
        let jerk = |c: Change, flag: i32, operand: i32, max: f64| {
            jerk_change(c, (flag, operand, JERK_UNITS), o.jerk_units, max)
        };
        let accel_jerk = jerk(o.accel_jerk, CHANGE_ACCEL_JERK, ACCEL_JERK, sys.max_accel_jerk)?;
        let decel_jerk = jerk(o.decel_jerk, CHANGE_DECEL_JERK, DECEL_JERK, sys.max_decel_jerk)?;
        let pending_too = match o.scope {
            0 => false,
            1 => true,
            s => return Err(bad(SCOPE, s as f64)),
        };
        Ok(Self {
            speed,
            accel,
            decel,
            accel_jerk,
            decel_jerk,
            pending_too,
        })
    }

    /// `mv` with the changes (its Calculated Data as it started).
    ///
    /// # Errors
    /// ERR 13 on Speed Units for a master-driven move; on a jerk in % of
    /// time the new rates cannot convert.
    fn apply(&self, mv: &CoordMove) -> Result<CoordMove, MccdError> {
        if mv.driver() == Driver::Master {
            return Err(bad(exerr::SPEED_UNITS, 0.0));
        }
        let mut m = mv.clone();
        let Some(old) = mv.limits().copied() else {
            // A move at speed 0 gets rates only with a speed.
            return Ok(m);
        };
        // A hold keeps the move's speed for when it resumes.
        let speed = self.speed.filter(|s| *s > 0.0).unwrap_or(old.velocity());
        let accel = self.accel.unwrap_or(old.acceleration());
        let decel = self.decel.unwrap_or(old.deceleration());
        let limits = match old.shape() {
            Shape::Trapezoidal => Limits::trapezoidal(speed, accel, decel),
            Shape::SCurve { accel_jerk, decel_jerk } => {
                // A jerk set in % of time follows the speed and rates.
                let (pa, pd) = match mv.jerk_percent_of_time {
                    Some((pa, pd)) => (Some(pa), Some(pd)),
                    None => (None, None),
                };
                let convert = |change: Option<Jerk>, percent: Option<f64>, old: f64, rate: f64, operand: i32| {
                    let percent = match change {
                        Some(Jerk::Absolute(j)) => return Ok((j, None)),
                        Some(Jerk::PercentOfTime(p, _)) => Some(p),
                        None => percent,
                    };
                    match percent {
                        Some(p) => jerk_from_percent_of_time(p, rate, speed)
                            .map(|j| (j, Some(p)))
                            .map_err(|_| bad(operand, p)),
                        None => Ok((old, None)),
                    }
                };
                let (ja, pa) = convert(self.accel_jerk, pa, accel_jerk, accel, exerr::ACCEL_JERK)?;
                let (jd, pd) = convert(self.decel_jerk, pd, decel_jerk, decel, exerr::DECEL_JERK)?;
                m.jerk_percent_of_time = pa.zip(pd);
                Limits::s_curve(speed, accel, decel, ja, jd)
            }
        }
        .map_err(|_| bad(exerr::SPEED, speed))?;
        m.limits = Some(limits);
        Ok(m)
    }
}

fn execute(task: &mut MotionTask, args: &Args<'_>) -> Result<(), Fault> {
    let control = args.control(1);
    one_shot(task, control, |task| {
        task.mccd(args.system(0), control, &MccdOperands::bind(args))
    })
}

fn check(task: &MotionTask, args: &Args<'_>) -> Result<(), Fault> {
    Mccd::new(&MccdOperands::bind(args), task.coord_config(args.system(0)))
        .map(drop)
        .map_err(fault)
}

impl MotionTask {
    /// MCCD on `system` (module doc); `.DN` at once.
    ///
    /// # Errors
    /// ERR 13 with EXERR = the operand; nothing changes.
    pub(crate) fn mccd(
        &mut self,
        system: CoordHandle,
        control: InstructionHandle,
        o: &MccdOperands,
    ) -> Result<(), MccdError> {
        self.instruction(control, |task| {
            let mccd = Mccd::new(o, task.coord_config(system))?;
            let sys = &mut task.coord.systems[system.0 as usize];
            // Verify both before changing either.
            let active = sys.components.iter().rposition(|c| !c.stopping);
            let new_active = match active {
                Some(k) => Some(mccd.apply(&sys.components[k].mv)?),
                None => None,
            };
            let new_pending = match (&sys.pending, mccd.pending_too) {
                (Some((_, mv)), true) => Some(mccd.apply(mv)?),
                _ => None,
            };
            let hold = mccd.speed == Some(0.0);
            if let (Some(k), Some(mv)) = (active, new_active) {
                let c = &mut sys.components[k];
                let now = c.profile.sample(c.progress);
                let from = State {
                    position: now.position,
                    velocity: now.velocity,
                    acceleration: now.acceleration,
                };
                let length = mv.path().length();
                if let Some(limits) = mv.limits() {
                    c.held = hold || (c.held && mccd.speed.is_none());
                    if c.held {
                        // To rest on the path, with the move's limits at
                        // least as fast as it goes now.
                        let brake =
                            with_velocity(limits, limits.velocity().max(from.velocity.abs())).unwrap_or(*limits);
                        c.profile = Profile::to_velocity(from, 0.0, &brake);
                        c.blend_at = None;
                    } else {
                        let end_speed = c.profile.final_state().velocity.min(limits.velocity());
                        c.profile = Profile::to_position(from, length, end_speed, limits);
                        if !c.successor_started {
                            c.blend_at = if c.contour {
                                Some(c.profile.duration_s())
                            } else if mv.termination().blends() {
                                let decel_point = c.profile.deceleration_start_s();
                                Some(match mv.termination() {
                                    crate::coord::TerminationType::NoDecel => decel_point,
                                    _ => {
                                        progress_at_length(&c.profile, length - mv.command_tolerance()).max(decel_point)
                                    }
                                })
                            } else {
                                None
                            };
                        }
                    }
                    c.progress = 0.0;
                    c.last_delta = 0.0;
                }
                c.mv = mv;
            }
            if let (Some((_, pending)), Some(mv)) = (sys.pending.as_mut(), new_pending.filter(|_| !hold)) {
                *pending = mv;
            }
            task.motion_bits_mut(control).dn = true;
            Ok(())
        })
    }
}

#[cfg(test)]
mod tests;
