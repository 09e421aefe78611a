//! MAJ (Motion Axis Jog), minimal: a velocity jog, chiefly to drive cam
//! masters (a master must move for a slave to follow).
//!
//! The Logix pair MAJ/MAS was chosen over PLCopen MC_MoveVelocity/MC_Stop
//! because the cam instructions it drives (MCCP, MAPC, MRP) are Logix
//! instructions with MOTION_INSTRUCTION tags; one convention for the whole
//! scene.
//!
//! `MAJ(Axis, MotionControl, Direction, Speed, SpeedUnits, AccelRate,
//! AccelUnits, DecelRate, DecelUnits, Profile)`: Direction 0 forward /
//! 1 reverse; Speed, AccelRate, DecelRate in units per sec (Units 0) or
//! percent of the axis maximum (Units 1); Profile 0 trapezoidal, 1 S-curve
//! (jerk = the axis' `max_jerk`, which must then be > 0). The later operands
//! (jerks, Merge, Merge Speed, lock position) are not modelled: a jog always
//! merges (replaces a running jog or move at once, from the current state).
//! ERR 13 with EXERR = faceplate operand number for an operand out of range.
//! Speed may exceed the axis' `max_velocity` only as asked in units per sec
//! (as Logix, the configured maximum does not clamp an explicit jog speed);
//! 0 is a valid speed (the axis ramps to rest and the jog stays in process).
//!
//! The jog runs as the axis' ramp in the engine (`task/cam.rs`), which a
//! MAS, a move or a cam ends; `.DN` and `.IP` at once.

use super::entry::{Instruction, no_load, one_shot};
use crate::axis::AxisConfig;
use crate::catalogue::words::{JOG_ACCEL_UNITS, JOG_DIRECTION, JOG_SPEED_UNITS, PROFILE, motion_control, op};
use crate::catalogue::{CallStyle, Format, Kind};
use crate::dynamics::{positive, time_rate};
use crate::instruction::{Fault, fault};
use crate::instruction::{NoFault, Refusal};
use crate::profile::{Limits, Profile};
use crate::task::engine::Need;
use crate::task::engine::{RampAim, RampPlan, Takes};
use crate::task::{Args, AxisHandle, InstructionHandle, MotionTask, RampRun};

/// Motion Axis Jog (its first ten operands).
pub const MAJ: Instruction = Instruction {
    mnemonic: "MAJ",
    title: "Motion Axis Jog",
    summary: "velocity jog, chiefly to drive cam masters (a master must move for a slave to follow)",
    reference: "Logix motion reference",
    style: CallStyle::Positional,
    operands: &[
        op("Axis", "AXIS", Format::Tag, Kind::Axis, 0),
        motion_control(1),
        op(
            "Direction",
            "DINT",
            Format::Immediate,
            Kind::Enumeration(JOG_DIRECTION),
            2,
        ),
        op("Speed", "REAL", Format::ImmediateOrTag, Kind::Number, 3),
        op(
            "Speed Units",
            "DINT",
            Format::Immediate,
            Kind::Enumeration(JOG_SPEED_UNITS),
            4,
        ),
        op("Accel Rate", "REAL", Format::ImmediateOrTag, Kind::Number, 5),
        op(
            "Accel Units",
            "DINT",
            Format::Immediate,
            Kind::Enumeration(JOG_ACCEL_UNITS),
            6,
        ),
        op("Decel Rate", "REAL", Format::ImmediateOrTag, Kind::Number, 7),
        op(
            "Decel Units",
            "DINT",
            Format::Immediate,
            Kind::Enumeration(JOG_ACCEL_UNITS),
            8,
        ),
        op("Profile", "DINT", Format::Immediate, Kind::Enumeration(PROFILE), 9),
    ],
    execute,
    check,
    load: no_load,
};

/// Why MAJ fails: ERR 13 with the operand, or the axis' state.
pub type MajError = Refusal<NoFault>;

/// MAJ's numeric operands.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MajOperands {
    /// 0 forward, 1 reverse.
    pub direction: i32,
    /// Speed magnitude.
    pub speed: f64,
    /// 0 units per sec, 1 % of maximum.
    pub speed_units: i32,
    /// Acceleration.
    pub accel_rate: f64,
    /// 0 units per sec², 1 % of maximum.
    pub accel_units: i32,
    /// Deceleration.
    pub decel_rate: f64,
    /// 0 units per sec², 1 % of maximum.
    pub decel_units: i32,
    /// 0 trapezoidal, 1 S-curve.
    pub profile: i32,
}

impl Default for MajOperands {
    fn default() -> Self {
        Self {
            direction: 0,
            speed: 0.0,
            speed_units: 0,
            accel_rate: 100.0,
            accel_units: 1,
            decel_rate: 100.0,
            decel_units: 1,
            profile: 0,
        }
    }
}

impl MajOperands {
    /// The operands of a call, by catalogue position.
    #[must_use]
    pub fn bind(args: &Args<'_>) -> Self {
        MajOperands {
            direction: args.code(2),
            speed: args.number(3),
            speed_units: args.code(4),
            accel_rate: args.number(5),
            accel_units: args.code(6),
            decel_rate: args.number(7),
            decel_units: args.code(8),
            profile: args.code(9),
        }
    }
}

/// Faceplate indices (ERR 13's EXERR).
mod exerr {
    use super::MAJ;

    pub(super) const DIRECTION: i32 = MAJ.exerr("Direction");
    pub(super) const SPEED: i32 = MAJ.exerr("Speed");
    pub(super) const SPEED_UNITS: i32 = MAJ.exerr("Speed Units");
    pub(super) const ACCEL_RATE: i32 = MAJ.exerr("Accel Rate");
    pub(super) const ACCEL_UNITS: i32 = MAJ.exerr("Accel Units");
    pub(super) const DECEL_RATE: i32 = MAJ.exerr("Decel Rate");
    pub(super) const DECEL_UNITS: i32 = MAJ.exerr("Decel Units");
    pub(super) const PROFILE: i32 = MAJ.exerr("Profile");
}

/// A validated jog: signed velocity and the limits to reach it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Jog {
    /// Signed target velocity, units/s.
    pub velocity: f64,
    /// Ramp limits.
    pub limits: Limits,
}

/// A rate in units/s (units 0) or % of `max` (units 1), finite and ≥ 0.
pub(super) fn rate(operand: i32, value: f64, units: i32, units_operand: i32, max: f64) -> Result<f64, MajError> {
    let v = time_rate(value, i64::from(units), max).ok_or(Refusal::operand(units_operand, f64::from(units)))?;
    if v.is_finite() && v >= 0.0 {
        Ok(v)
    } else {
        Err(Refusal::operand(operand, value))
    }
}

impl Jog {
    /// Validates MAJ's operands against the axis.
    ///
    /// # Errors
    /// ERR 13 naming the operand.
    pub fn new(o: &MajOperands, axis: &AxisConfig) -> Result<Self, MajError> {
        let sign = match o.direction {
            0 => 1.0,
            1 => -1.0,
            d => return Err(Refusal::operand(exerr::DIRECTION, f64::from(d))),
        };
        let speed = rate(
            exerr::SPEED,
            o.speed,
            o.speed_units,
            exerr::SPEED_UNITS,
            axis.max_velocity,
        )?;
        let accel = rate(
            exerr::ACCEL_RATE,
            o.accel_rate,
            o.accel_units,
            exerr::ACCEL_UNITS,
            axis.max_acceleration,
        )
        .and_then(|a| positive(a).ok_or(Refusal::operand(exerr::ACCEL_RATE, o.accel_rate)))?;
        let decel = rate(
            exerr::DECEL_RATE,
            o.decel_rate,
            o.decel_units,
            exerr::DECEL_UNITS,
            axis.max_deceleration,
        )
        .and_then(|d| positive(d).ok_or(Refusal::operand(exerr::DECEL_RATE, o.decel_rate)))?;
        let vmax = speed.max(axis.max_velocity);
        let limits = match o.profile {
            0 => Limits::trapezoidal(vmax, accel, decel),
            1 if axis.max_jerk > 0.0 => Limits::s_curve(vmax, accel, decel, axis.max_jerk, axis.max_jerk),
            p => return Err(Refusal::operand(exerr::PROFILE, f64::from(p))),
        }
        .map_err(|_| Refusal::operand(exerr::SPEED, o.speed))?;
        Ok(Self {
            velocity: sign * speed,
            limits,
        })
    }
}

fn execute(task: &mut MotionTask, args: &Args<'_>) -> Result<(), Fault> {
    let control = args.control(1);
    one_shot(task, control, |task| {
        task.maj(args.axis(0), control, &MajOperands::bind(args))
    })
}

fn check(task: &MotionTask, args: &Args<'_>) -> Result<(), Fault> {
    Jog::new(&MajOperands::bind(args), task.axis_config(args.axis(0)))
        .map(|_| ())
        .map_err(fault)
}

impl MotionTask {
    /// MAJ: jogs `axis` at the operands' speed, from its current state.
    ///
    /// # Errors
    /// ERR 13 with EXERR = the operand; the axis-state errors of
    /// [`crate::servo`] (ERR 9 for a jog further beyond an exceeded soft
    /// travel limit).
    pub(crate) fn maj(
        &mut self,
        axis: AxisHandle,
        motion_control: InstructionHandle,
        operands: &MajOperands,
    ) -> Result<(), MajError> {
        self.instruction(motion_control, |task| {
            let jog = Jog::new(operands, task.axis_config(axis))?;
            task.check_state(axis, Need::Motion)?;
            if jog.velocity != 0.0 {
                task.check_overtravel(axis, jog.velocity)?;
            }
            task.take_axis(axis, Takes::ALL);
            let state = task.axes[axis.0 as usize].command.state();
            task.cam_axis(axis).ramp = Some(RampRun {
                jog: Some(motion_control),
                plan: Some(RampPlan {
                    limits: jog.limits,
                    aim: RampAim::Jog {
                        sign: if operands.direction == 1 { -1.0 } else { 1.0 },
                        speed: jog.velocity.abs(),
                    },
                }),
                ..RampRun::new(Profile::to_velocity(state, jog.velocity, &jog.limits))
            });
            let b = task.motion_bits_mut(motion_control);
            b.dn = true;
            b.ip = true;
            Ok(())
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::axis::AxisKind;
    use crate::instruction::LogixFault;

    #[test]
    fn units_directions_and_operand_errors() {
        let axis = AxisConfig {
            max_velocity: 200.0,
            max_acceleration: 1000.0,
            max_deceleration: 500.0,
            ..AxisConfig::new("Conveyor", AxisKind::Linear)
        };
        let j = Jog::new(
            &MajOperands {
                direction: 1,
                speed: 50.0,
                speed_units: 1,
                ..Default::default()
            },
            &axis,
        )
        .unwrap();
        assert_eq!(j.velocity, -100.0);
        assert_eq!(j.limits.acceleration(), 1000.0);
        assert_eq!(j.limits.deceleration(), 500.0);
        let e = |o: MajOperands| Jog::new(&o, &axis).unwrap_err().exerr();
        let base = MajOperands {
            speed: 10.0,
            ..Default::default()
        };
        assert_eq!(e(MajOperands { direction: 2, ..base }), 2);
        assert_eq!(e(MajOperands { speed: -1.0, ..base }), 3);
        assert_eq!(e(MajOperands { speed_units: 5, ..base }), 4);
        assert_eq!(
            e(MajOperands {
                accel_rate: 0.0,
                ..base
            }),
            5
        );
        assert_eq!(
            e(MajOperands {
                decel_rate: f64::NAN,
                ..base
            }),
            7
        );
        assert_eq!(e(MajOperands { profile: 1, ..base }), 9);
    }
}
