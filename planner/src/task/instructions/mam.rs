//! MAM (Motion Axis Move): a single-axis move to a position, with a
//! trapezoidal or S-curve profile. The move runs as the axis' ramp in the
//! engine (`task/cam.rs`), superimposed on a cam, a gearing or coordinated
//! motion with Merge Disabled (`task/superimposed.rs`).
//!
//! # Operands (the manual's order, faceplate index = ERR 13's EXERR)
//! `MAM(Axis, MotionControl, MoveType, Position, Speed, SpeedUnits,
//! AccelRate, AccelUnits, DecelRate, DecelUnits, Profile, AccelJerk,
//! DecelJerk, JerkUnits, Merge, MergeSpeed, LockPosition, LockDirection,
//! EventDistance, CalculatedData)`.
//!
//! # Move types ([`MoveType`])
//! * 0 **Absolute**: to `Position`. On a modulo (rotary) axis the position
//!   is read trigonometrically within the axis' current revolution: the
//!   target is the start of that revolution plus `Position`, so the
//!   direction depends on where the axis is (less than the target: positive);
//!   a negative position turns back through 0 (−90 is 270 one revolution
//!   down); a position at or beyond the unwind turns more than one
//!   revolution.
//! * 1 **Incremental**: `Position` from the command position, either sign,
//!   any length.
//! * 2 **Rotary Shortest Path**: to `Position` (0 ≤ Position < unwind) the
//!   short way round, never more than half a revolution.
//! * 3 **Rotary Positive** / 4 **Rotary Negative**: to `Position` turning
//!   only forward / backward; a position at or beyond the unwind adds its
//!   whole revolutions (`Position` = 720 + 90 ends at 90 after two more
//!   turns); a negative position is refused (ERR 13).
//! * 5, 6 (master offset moves) are not simulated: ERR 13, EXERR 2.
//! * A `Position` past ±10⁹ units ([`crate::axis::MAX_POSITION`]) is
//!   refused with ERR 13 on Position, as is an incremental move whose
//!   target would pass it.
//!
//! Types 2–4 need a modulo axis: ERR 17 (Axis Mode Not Rotary) otherwise.
//!
//! # Rates
//! Speed in units/s (Speed Units 0) or % of the axis' `max_velocity` (1);
//! Accel/Decel Rate in units/s² (0) or % of the axis' maximum (1), both
//! above 0; Profile 0 trapezoidal, 1 S-curve with Accel/Decel Jerk in units/s³
//! (Jerk Units 0), % of the axis' `max_jerk` (1) or % of time (2, the MCCM
//! document's conversion with this move's speed and rates). Merge Speed 1
//! (Current) runs the move at the axis' speed when it executes.
//!
//! # Choices where the manual is silent or the twin is simpler
//! * `.PC` when the command reaches the target (the command, not the
//!   actual position: in-position is the axis' own status).
//! * Lock Position and Lock Direction: only Lock Direction 0 (None) is
//!   simulated; another value is refused with ERR 13 on Lock Direction.
//!   Event Distance and Calculated Data are accepted and not written.
//! * Merge: a MAM with Merge Enabled ends every motion on the axis (jog,
//!   move, cam, superimposed run, the coordinated motion of its systems)
//!   and starts from the axis' current state. With Merge Disabled, on an
//!   axis a cam or coordinated motion drives, the move is superimposed on
//!   that motion (`task/superimposed.rs`: its distance is its target minus
//!   the command when it executes); otherwise a second MAM replaces the
//!   one running (planned from the current command state: no stop in
//!   between), as Logix does. Superimposing a MAM on a jog is not
//!   simulated: it ends the jog as a merge does.

use super::entry::{Instruction, no_load, one_shot};
use crate::axis::AxisConfig;
use crate::catalogue::words::{
    INTEGER, JOG_ACCEL_UNITS, JOG_SPEED_UNITS, LOCK_DIRECTION, MAM_MERGE, MERGE_SPEED, NUMERIC, PROFILE,
    TIME_JERK_UNITS, motion_control, op,
};
use crate::catalogue::{CallStyle, Format, Kind};
use crate::dynamics::{MoveDynamics, time_rate};
use crate::instruction::{Fault, fault};
use crate::instruction::{LogixFault, Refusal};
use crate::profile::{Limits, Profile, State, jerk_from_percent_of_time};
use crate::task::engine::Need;
use crate::task::engine::{RampAim, RampPlan, Takes};
use crate::task::{Args, AxisHandle, InstructionHandle, MotionTask};
use thiserror::Error;

/// Motion Axis Move.
pub const MAM: Instruction = Instruction {
    mnemonic: "MAM",
    title: "Motion Axis Move",
    summary: "single-axis move: absolute, incremental, rotary shortest path / positive / negative, trapezoidal or S-curve with jerk units, merge and merge speed; a second MAM replaces the running one",
    reference: "Logix motion reference",
    style: CallStyle::Positional,
    operands: &[
        op("Axis", "AXIS", Format::Tag, Kind::Axis, 0),
        motion_control(1),
        op("Move Type", INTEGER, Format::ImmediateOrTag, Kind::Integer, 2),
        op("Position", NUMERIC, Format::ImmediateOrTag, Kind::Number, 3),
        op("Speed", NUMERIC, Format::ImmediateOrTag, Kind::Number, 4),
        op(
            "Speed Units",
            INTEGER,
            Format::Immediate,
            Kind::Enumeration(JOG_SPEED_UNITS),
            5,
        ),
        op("Accel Rate", NUMERIC, Format::ImmediateOrTag, Kind::Number, 6),
        op(
            "Accel Units",
            INTEGER,
            Format::Immediate,
            Kind::Enumeration(JOG_ACCEL_UNITS),
            7,
        ),
        op("Decel Rate", NUMERIC, Format::ImmediateOrTag, Kind::Number, 8),
        op(
            "Decel Units",
            INTEGER,
            Format::Immediate,
            Kind::Enumeration(JOG_ACCEL_UNITS),
            9,
        ),
        op("Profile", INTEGER, Format::Immediate, Kind::Enumeration(PROFILE), 10),
        op("Accel Jerk", NUMERIC, Format::ImmediateOrTag, Kind::Number, 11),
        op("Decel Jerk", NUMERIC, Format::ImmediateOrTag, Kind::Number, 12),
        op(
            "Jerk Units",
            INTEGER,
            Format::Immediate,
            Kind::Enumeration(TIME_JERK_UNITS),
            13,
        ),
        op("Merge", INTEGER, Format::Immediate, Kind::Enumeration(MAM_MERGE), 14),
        op(
            "Merge Speed",
            INTEGER,
            Format::Immediate,
            Kind::Enumeration(MERGE_SPEED),
            15,
        ),
        op("Lock Position", "REAL", Format::ImmediateOrTag, Kind::Number, 16),
        op(
            "Lock Direction",
            "UINT32",
            Format::ImmediateOrTag,
            Kind::Enumeration(LOCK_DIRECTION),
            17,
        ),
        op(
            "Event Distance",
            "REAL ARRAY or 0",
            Format::Array,
            Kind::OptionalArray,
            18,
        ),
        op(
            "Calculated Data",
            "REAL ARRAY or 0",
            Format::Array,
            Kind::OptionalArray,
            19,
        ),
    ],
    execute,
    check,
    load: no_load,
};

/// MAM's numeric operands.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MamOperands {
    /// Move Type code (0..=6).
    pub move_type: i64,
    /// Position or distance, axis units.
    pub position: f64,
    /// Speed, rates, profile and jerks (units: 0 or 1; jerk units 0, 1,
    /// 2).
    pub dynamics: MoveDynamics,
    /// 0 Disabled, 1 Enabled.
    pub merge: i64,
    /// 0 Programmed, 1 Current.
    pub merge_speed: i64,
    /// Lock Direction (0 None only).
    pub lock_direction: i64,
}

impl Default for MamOperands {
    fn default() -> Self {
        Self {
            move_type: 0,
            position: 0.0,
            dynamics: MoveDynamics {
                speed: 100.0,
                speed_units: 1,
                accel_rate: 100.0,
                accel_units: 1,
                decel_rate: 100.0,
                decel_units: 1,
                profile: 0,
                accel_jerk: 100.0,
                decel_jerk: 100.0,
                jerk_units: 2,
            },
            merge: 0,
            merge_speed: 0,
            lock_direction: 0,
        }
    }
}

/// How the Position operand is read.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MoveType {
    /// 0.
    Absolute,
    /// 1.
    Incremental,
    /// 2.
    RotaryShortestPath,
    /// 3.
    RotaryPositive,
    /// 4.
    RotaryNegative,
}

/// MAM's own refusal.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Error)]
#[non_exhaustive]
pub enum MamFault {
    /// ERR 17: a rotary move type on an axis without a modulo period.
    #[error("axis mode not rotary (ERR 17): move type {move_type} needs a modulo axis")]
    AxisModeNotRotary {
        /// The move type.
        move_type: i64,
    },
}

impl LogixFault for MamFault {
    fn err(&self) -> i32 {
        match self {
            Self::AxisModeNotRotary { .. } => 17,
        }
    }
}

/// Why an MAM is refused: ERR 13 with the operand, the axis' state, or
/// [`MamFault`].
pub type MamError = Refusal<MamFault>;

impl MamOperands {
    /// The operands of a call, by catalogue position (Lock Position, Event
    /// Distance and Calculated Data are not simulated: module doc).
    #[must_use]
    pub fn bind(args: &Args<'_>) -> Self {
        MamOperands {
            move_type: args.integer(2),
            position: args.number(3),
            dynamics: MoveDynamics {
                speed: args.number(4),
                speed_units: args.integer(5),
                accel_rate: args.number(6),
                accel_units: args.integer(7),
                decel_rate: args.number(8),
                decel_units: args.integer(9),
                profile: args.integer(10),
                accel_jerk: args.number(11),
                decel_jerk: args.number(12),
                jerk_units: args.integer(13),
            },
            merge: args.integer(14),
            merge_speed: args.integer(15),
            lock_direction: args.integer(17),
        }
    }
}

/// Faceplate indices (ERR 13's EXERR).
mod exerr {
    use super::MAM;

    pub(super) const MOVE_TYPE: i32 = MAM.exerr("Move Type");
    pub(super) const POSITION: i32 = MAM.exerr("Position");
    pub(super) const SPEED: i32 = MAM.exerr("Speed");
    pub(super) const SPEED_UNITS: i32 = MAM.exerr("Speed Units");
    pub(super) const ACCEL_RATE: i32 = MAM.exerr("Accel Rate");
    pub(super) const ACCEL_UNITS: i32 = MAM.exerr("Accel Units");
    pub(super) const DECEL_RATE: i32 = MAM.exerr("Decel Rate");
    pub(super) const DECEL_UNITS: i32 = MAM.exerr("Decel Units");
    pub(super) const PROFILE: i32 = MAM.exerr("Profile");
    pub(super) const ACCEL_JERK: i32 = MAM.exerr("Accel Jerk");
    pub(super) const DECEL_JERK: i32 = MAM.exerr("Decel Jerk");
    pub(super) const JERK_UNITS: i32 = MAM.exerr("Jerk Units");
    pub(super) const MERGE: i32 = MAM.exerr("Merge");
    pub(super) const MERGE_SPEED: i32 = MAM.exerr("Merge Speed");
    pub(super) const LOCK_DIRECTION: i32 = MAM.exerr("Lock Direction");
}

/// A validated MAM: where it goes (given the axis' state when it
/// executes), and with what limits.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Mam {
    /// How Position is read.
    pub move_type: MoveType,
    /// The Position operand.
    pub position: f64,
    /// Profile limits (velocity = the move's speed).
    pub limits: Limits,
    /// Merge Enabled.
    pub merge: bool,
}

fn bad(operand: i32, value: f64) -> MamError {
    Refusal::operand(operand, value)
}

fn code(operand: i32, value: i64, max: i64) -> Result<i64, MamError> {
    if (0..=max).contains(&value) {
        Ok(value)
    } else {
        Err(bad(operand, value as f64))
    }
}

/// A rate in units/s (units 0) or % of `max` (units 1), finite and > 0
/// (≥ 0 when `zero_ok`).
fn rate(operand: i32, value: f64, units_operand: i32, units: i64, max: f64, zero_ok: bool) -> Result<f64, MamError> {
    let v = time_rate(value, code(units_operand, units, 1)?, max).unwrap_or(f64::NAN);
    if v.is_finite() && (v > 0.0 || (zero_ok && v == 0.0)) {
        Ok(v)
    } else {
        Err(bad(operand, value))
    }
}

impl Mam {
    /// Validates MAM's operands against the axis; `current_speed` is
    /// |command velocity| when it executes (Merge Speed Current).
    ///
    /// # Errors
    /// [`MamError`] naming the first operand out of range, or ERR 17.
    pub fn new(o: &MamOperands, axis: &AxisConfig, current_speed: f64) -> Result<Self, MamError> {
        let move_type = match o.move_type {
            0 => MoveType::Absolute,
            1 => MoveType::Incremental,
            2 => MoveType::RotaryShortestPath,
            3 => MoveType::RotaryPositive,
            4 => MoveType::RotaryNegative,
            t => return Err(bad(exerr::MOVE_TYPE, t as f64)),
        };
        if !crate::axis::position_in_reach(o.position) {
            return Err(bad(exerr::POSITION, o.position));
        }
        let rotary = !matches!(move_type, MoveType::Absolute | MoveType::Incremental);
        match axis.modulo() {
            None if rotary => {
                return Err(Refusal::Instruction(MamFault::AxisModeNotRotary {
                    move_type: o.move_type,
                }));
            }
            Some(m) if move_type == MoveType::RotaryShortestPath && !(0.0..m.period()).contains(&o.position) => {
                return Err(bad(exerr::POSITION, o.position));
            }
            Some(_) if rotary && o.position < 0.0 => return Err(bad(exerr::POSITION, o.position)),
            _ => {}
        }
        let d = &o.dynamics;
        let merge = code(exerr::MERGE, o.merge, 1)? == 1;
        let current = code(exerr::MERGE_SPEED, o.merge_speed, 1)? == 1;
        if o.lock_direction != 0 {
            return Err(bad(exerr::LOCK_DIRECTION, o.lock_direction as f64));
        }
        let programmed = rate(
            exerr::SPEED,
            d.speed,
            exerr::SPEED_UNITS,
            d.speed_units,
            axis.max_velocity,
            false,
        )?;
        let speed = if current && current_speed > 0.0 {
            current_speed
        } else {
            programmed
        };
        let accel = rate(
            exerr::ACCEL_RATE,
            d.accel_rate,
            exerr::ACCEL_UNITS,
            d.accel_units,
            axis.max_acceleration,
            false,
        )?;
        let decel = rate(
            exerr::DECEL_RATE,
            d.decel_rate,
            exerr::DECEL_UNITS,
            d.decel_units,
            axis.max_deceleration,
            false,
        )?;
        let limits = match code(exerr::PROFILE, d.profile, 1)? {
            0 => Limits::trapezoidal(speed, accel, decel),
            _ => {
                let jerk = |operand: i32, value: f64, a: f64| -> Result<f64, MamError> {
                    let j = match code(exerr::JERK_UNITS, d.jerk_units, 2)? {
                        0 => value,
                        1 => value / 100.0 * axis.max_jerk,
                        _ => jerk_from_percent_of_time(value, a, speed).map_err(|_| bad(operand, value))?,
                    };
                    if j.is_finite() && j > 0.0 {
                        Ok(j)
                    } else {
                        Err(bad(operand, value))
                    }
                };
                let ja = jerk(exerr::ACCEL_JERK, d.accel_jerk, accel)?;
                let jd = jerk(exerr::DECEL_JERK, d.decel_jerk, decel)?;
                Limits::s_curve(speed, accel, decel, ja, jd)
            }
        }
        .map_err(|_| bad(exerr::SPEED, d.speed))?;
        Ok(Self {
            move_type,
            position: o.position,
            limits,
            merge,
        })
    }

    /// The absolute (unwound) target from the axis' command state.
    pub fn target(&self, start: State, axis: &AxisConfig) -> f64 {
        let p = start.position;
        let Some(m) = axis.modulo() else {
            return match self.move_type {
                MoveType::Incremental => p + self.position,
                _ => self.position,
            };
        };
        let period = m.period();
        let wrapped = m.wrap(p);
        let revolution_start = p - wrapped;
        match self.move_type {
            MoveType::Absolute => revolution_start + self.position,
            MoveType::Incremental => p + self.position,
            MoveType::RotaryShortestPath => {
                let mut d = self.position - wrapped;
                if d > period / 2.0 {
                    d -= period;
                } else if d < -period / 2.0 {
                    d += period;
                }
                p + d
            }
            MoveType::RotaryPositive | MoveType::RotaryNegative => {
                let turns = (self.position / period).floor();
                let within = self.position - turns * period;
                let forward = self.move_type == MoveType::RotaryPositive;
                let d = if forward {
                    (within - wrapped).rem_euclid(period)
                } else {
                    (wrapped - within).rem_euclid(period)
                };
                let d = d + turns * period;
                if forward { p + d } else { p - d }
            }
        }
    }
}

fn execute(task: &mut MotionTask, args: &Args<'_>) -> Result<(), Fault> {
    let control = args.control(1);
    one_shot(task, control, |task| {
        task.mam(args.axis(0), control, &MamOperands::bind(args))
    })
}

/// The operands' validation against the axis at rest.
fn check(task: &MotionTask, args: &Args<'_>) -> Result<(), Fault> {
    Mam::new(&MamOperands::bind(args), task.axis_config(args.axis(0)), 0.0)
        .map(|_| ())
        .map_err(fault)
}

impl MotionTask {
    /// MAM: moves `axis` as the operands say. `.DN` at once, `.IP` and
    /// `.AC` while it moves, `.PC` when the command reaches the target; a
    /// MAM that another replaces, or that a stop, a disable or another
    /// motion process ends, clears `.IP` without `.PC`.
    ///
    /// # Errors
    /// ERR 13 with EXERR = the operand, ERR 17 for a rotary move type on a
    /// non-modulo axis, the axis-state errors of [`crate::servo`] (ERR 9
    /// for a target further beyond an exceeded soft travel limit); the
    /// axis keeps what it was doing.
    pub(crate) fn mam(
        &mut self,
        axis: AxisHandle,
        control: InstructionHandle,
        operands: &MamOperands,
    ) -> Result<(), MamError> {
        let (mam, target) = self.instruction(control, |task| {
            let a = &task.axes[axis.0 as usize];
            let start = a.command.state();
            let m = Mam::new(operands, &a.config, start.velocity.abs())?;
            task.check_state(axis, Need::Motion)?;
            let target = m.target(start, &a.config);
            if !crate::axis::position_in_reach(target) {
                return Err(bad(exerr::POSITION, operands.position));
            }
            if target != start.position {
                task.check_overtravel(axis, target - start.position)?;
            }
            Ok::<_, MamError>((m, target))
        })?;
        let start = self.axes[axis.0 as usize].command.state();
        self.motion_bits_mut(control).dn = true;
        let base_driven = self.cam_drives(axis) || self.coordinated_motion_status(axis);
        if !mam.merge && base_driven {
            // Superimposed on the cam or the coordinated motion.
            self.superimpose_move(axis, control, target - start.position, &mam.limits);
            return Ok(());
        }
        // Every other single-axis motion on the axis ends (see the module
        // doc on merge); a MAM it replaces loses `.IP`.
        self.take_axis(
            axis,
            Takes {
                ramp: false,
                ..Takes::ALL
            },
        );
        let start = self.axes[axis.0 as usize].command.state();
        let profile = Profile::to_position(start, target, 0.0, &mam.limits);
        let plan = RampPlan {
            limits: mam.limits,
            aim: RampAim::Move { target },
        };
        self.start_move_ramp(axis, profile, plan, control);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::axis::AxisKind;

    fn table() -> AxisConfig {
        AxisConfig {
            modulo_period: Some(360.0),
            max_velocity: 360.0,
            max_acceleration: 3600.0,
            max_deceleration: 3600.0,
            max_jerk: 36_000.0,
            ..AxisConfig::new("T", AxisKind::Rotary)
        }
    }

    fn target(move_type: i64, position: f64, from: f64) -> f64 {
        let o = MamOperands {
            move_type,
            position,
            ..MamOperands::default()
        };
        let m = Mam::new(&o, &table(), 0.0).unwrap();
        m.target(State::at_rest(from), &table())
    }

    /// The manual's rotary examples (a 360° unwind).
    #[test]
    fn rotary_move_types_follow_the_manual_examples() {
        // Absolute to 225: the direction depends on where the axis is.
        assert_eq!(target(0, 225.0, 30.0), 225.0);
        assert_eq!(target(0, 225.0, 300.0), 225.0);
        assert_eq!(target(0, 225.0, 720.0 + 300.0), 720.0 + 225.0);
        // -90 is 270 through 0; 450 turns more than one revolution.
        assert_eq!(target(0, -90.0, 10.0), -90.0);
        assert_eq!(target(0, 450.0, 10.0), 450.0);
        // Shortest path 30 → 225 goes back through 0; 30 → 200 goes forward.
        assert_eq!(target(2, 225.0, 30.0), 30.0 - 165.0);
        assert_eq!(target(2, 200.0, 30.0), 200.0);
        // Positive 315 → 225 turns forward 270; negative 45 → 225 back 180.
        assert_eq!(target(3, 225.0, 315.0), 315.0 + 270.0);
        assert_eq!(target(4, 225.0, 45.0), 45.0 - 180.0);
        // Beyond the unwind: whole extra revolutions.
        assert_eq!(target(3, 720.0 + 90.0, 0.0), 810.0);
        assert_eq!(target(4, 360.0 + 270.0, 0.0), -90.0 - 360.0);
        // Incremental: any length, either sign.
        assert_eq!(target(1, -1000.0, 5.0), -995.0);
    }

    #[test]
    fn operands_out_of_range_name_their_faceplate_index() {
        let ok = MamOperands {
            position: 10.0,
            ..MamOperands::default()
        };
        let cases = [
            (MamOperands { move_type: 5, ..ok }, 2),
            (
                MamOperands {
                    position: f64::NAN,
                    ..ok
                },
                3,
            ),
            (
                MamOperands {
                    dynamics: MoveDynamics {
                        speed: 0.0,
                        ..ok.dynamics
                    },
                    ..ok
                },
                4,
            ),
            (
                MamOperands {
                    dynamics: MoveDynamics {
                        speed_units: 4,
                        ..ok.dynamics
                    },
                    ..ok
                },
                5,
            ),
            (
                MamOperands {
                    dynamics: MoveDynamics {
                        accel_rate: -1.0,
                        ..ok.dynamics
                    },
                    ..ok
                },
                6,
            ),
            (
                MamOperands {
                    dynamics: MoveDynamics {
                        decel_units: 2,
                        ..ok.dynamics
                    },
                    ..ok
                },
                9,
            ),
            (
                MamOperands {
                    dynamics: MoveDynamics {
                        profile: 2,
                        ..ok.dynamics
                    },
                    ..ok
                },
                10,
            ),
            (
                MamOperands {
                    dynamics: MoveDynamics {
                        profile: 1,
                        accel_jerk: 0.0,
                        ..ok.dynamics
                    },
                    ..ok
                },
                11,
            ),
            (
                MamOperands {
                    dynamics: MoveDynamics {
                        profile: 1,
                        jerk_units: 3,
                        ..ok.dynamics
                    },
                    ..ok
                },
                13,
            ),
            (MamOperands { merge: 2, ..ok }, 14),
            (MamOperands { merge_speed: -1, ..ok }, 15),
            (
                MamOperands {
                    lock_direction: 1,
                    ..ok
                },
                17,
            ),
            (
                MamOperands {
                    move_type: 2,
                    position: 360.0,
                    ..ok
                },
                3,
            ),
            (
                MamOperands {
                    move_type: 3,
                    position: -1.0,
                    ..ok
                },
                3,
            ),
        ];
        for (o, exerr) in cases {
            let e = Mam::new(&o, &table(), 0.0).unwrap_err();
            assert_eq!((e.err(), e.exerr()), (13, exerr), "{o:?}");
        }
        let linear = AxisConfig::new("X", AxisKind::Linear);
        let e = Mam::new(&MamOperands { move_type: 4, ..ok }, &linear, 0.0).unwrap_err();
        assert_eq!((e.err(), e.exerr()), (17, 0));
    }

    #[test]
    fn speed_units_and_merge_speed_current() {
        let o = MamOperands {
            dynamics: MoveDynamics {
                speed: 50.0,
                speed_units: 1,
                ..MamOperands::default().dynamics
            },
            ..MamOperands::default()
        };
        assert_eq!(Mam::new(&o, &table(), 0.0).unwrap().limits.velocity(), 180.0);
        let current = MamOperands { merge_speed: 1, ..o };
        assert_eq!(Mam::new(&current, &table(), 42.0).unwrap().limits.velocity(), 42.0);
        assert_eq!(Mam::new(&current, &table(), 0.0).unwrap().limits.velocity(), 180.0);
    }
}

#[cfg(test)]
mod executor_tests {
    use super::*;
    use crate::axis::{AxisConfig, AxisKind};
    use crate::dynamics::MoveDynamics;
    use crate::task::instructions::mas::MasOperands;

    const DT: f64 = 0.004;

    fn rig(modulo: bool) -> (MotionTask, AxisHandle) {
        rig_at(modulo, 0.0)
    }

    fn rig_at(modulo: bool, position: f64) -> (MotionTask, AxisHandle) {
        let mut task = MotionTask::new(DT).unwrap();
        let config = AxisConfig {
            modulo_period: modulo.then_some(360.0),
            max_velocity: 360.0,
            max_acceleration: 3600.0,
            max_deceleration: 3600.0,
            max_jerk: 36_000.0,
            ..AxisConfig::new("A", if modulo { AxisKind::Rotary } else { AxisKind::Linear })
        };
        let axis = task.add_axis(config, position).unwrap();
        (task, axis)
    }

    fn to(move_type: i64, position: f64, speed_pct: f64) -> MamOperands {
        MamOperands {
            move_type,
            position,
            dynamics: MoveDynamics {
                speed: speed_pct,
                ..MamOperands::default().dynamics
            },
            ..MamOperands::default()
        }
    }

    /// Runs until `.PC` or `.IP` falls; returns the command velocities.
    fn run(task: &mut MotionTask, axis: AxisHandle, mi: InstructionHandle) -> Vec<f64> {
        let mut v = Vec::new();
        for _ in 0..10_000 {
            task.update();
            v.push(task.axis_state(axis).command_velocity);
            if !task.motion_bits(mi).ip {
                break;
            }
        }
        v
    }

    #[test]
    fn an_absolute_move_ends_exactly_at_its_target_with_pc() {
        let (mut task, axis) = rig(false);
        let mi = task.add_instruction("Move");
        task.mam(axis, mi, &to(0, 100.0, 50.0)).unwrap();
        let b = task.motion_bits(mi);
        assert!(b.en && b.dn && b.ip && b.ac && !b.pc);
        assert!(task.axis_status(axis).moving);
        task.update();
        assert!(task.motion_bits(mi).accel);
        let v = run(&mut task, axis, mi);
        let b = task.motion_bits(mi);
        assert!(b.pc && !b.ip && !b.ac && !b.accel && !b.decel, "{b:?}");
        assert_eq!(task.axis_state(axis).command_position, 100.0);
        assert!(v.iter().all(|&x| x <= 180.0 + 1e-9), "50 % of 360");
        assert!(!task.axis_status(axis).moving);
    }

    #[test]
    fn a_second_mam_replaces_the_first_without_stopping() {
        let (mut task, axis) = rig(false);
        let (first, second) = (task.add_instruction("M1"), task.add_instruction("M2"));
        task.mam(axis, first, &to(0, 100.0, 50.0)).unwrap();
        for _ in 0..50 {
            task.update();
        }
        let v0 = task.axis_state(axis).command_velocity;
        assert!(v0 > 100.0);
        task.mam(axis, second, &to(1, 10.0, 50.0)).unwrap();
        let here = task.axis_state(axis).command_position;
        let b = task.motion_bits(first);
        assert!(!b.ip && !b.pc, "replaced: {b:?}");
        let v = run(&mut task, axis, second);
        assert!(task.motion_bits(second).pc);
        assert!(v[..v.len() - 1].iter().all(|&x| x != 0.0), "no stop on the way");
        assert!((task.axis_state(axis).command_position - (here + 10.0)).abs() < 1e-9);
    }

    #[test]
    fn mas_move_stops_a_mam_without_pc() {
        let (mut task, axis) = rig(false);
        let (mv, stop) = (task.add_instruction("Move"), task.add_instruction("Stop"));
        task.mam(axis, mv, &to(0, 500.0, 100.0)).unwrap();
        for _ in 0..30 {
            task.update();
        }
        let o = MasOperands {
            stop_type: 2,
            ..MasOperands::default()
        };
        task.mas(axis, stop, &o).unwrap();
        let b = task.motion_bits(mv);
        assert!(!b.ip && !b.pc);
        run(&mut task, axis, stop);
        assert!(task.motion_bits(stop).pc);
        assert!(task.axis_state(axis).command_position < 500.0);
    }

    #[test]
    fn an_s_curve_move_keeps_its_jerk_and_a_rotary_positive_move_never_turns_back() {
        let (mut task, axis) = rig_at(true, 315.0);
        let mi = task.add_instruction("Move");
        let o = MamOperands {
            dynamics: MoveDynamics {
                profile: 1,
                accel_jerk: 20_000.0,
                decel_jerk: 20_000.0,
                jerk_units: 0,
                ..to(3, 225.0, 100.0).dynamics
            },
            ..to(3, 225.0, 100.0)
        };
        task.mam(axis, mi, &o).unwrap();
        let mut peak_jerk: f64 = 0.0;
        for _ in 0..10_000 {
            task.update();
            let s = task.axis_state(axis);
            assert!(s.command_velocity >= 0.0, "forward only");
            peak_jerk = peak_jerk.max(s.command_jerk.abs());
            if task.motion_bits(mi).pc {
                break;
            }
        }
        assert!(peak_jerk <= 20_000.0 * (1.0 + 1e-9), "{peak_jerk}");
        let s = task.axis_state(axis);
        assert_eq!(s.modulo_command_position, Some(225.0));
        assert_eq!(s.command_position, 315.0 + 270.0, "315 → 225 forward is 270");
    }
}
