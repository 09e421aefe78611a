//! Motion Axis Jog (MAJ) and Motion Axis Stop (MAS), minimal: a velocity jog
//! to drive cam masters, and the stop that ends jogs, moves and position
//! cams.
//!
//! The Logix pair was chosen over PLCopen MC_MoveVelocity/MC_Stop because
//! the cam instructions it drives (MCCP, MAPC, MRP) are Logix instructions
//! with MOTION_INSTRUCTION tags; one convention for the whole scene.
//!
//! # MAJ operands implemented
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
//! # MAS operands implemented
//! `MAS(Axis, MotionControl, StopType, ChangeDecel, DecelRate, DecelUnits)`:
//! Stop Type 0 All, 1 Jog, 2 Move, 8 Position Cam (the other Logix numbers —
//! gear, home, tune, test, time cam, master offset move, direct control —
//! name processes this planner does not have; they are accepted and stop
//! nothing). Change Decel 0 uses the axis' `max_deceleration`, 1 uses
//! DecelRate (DecelUnits 0 units/s², 1 percent of the maximum). The axis
//! ramps from its current velocity to rest; `.IP` while it does, `.PC` when
//! it is at rest.

use crate::axis::AxisConfig;
use crate::profile::{Limits, LimitsError};

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

/// MAS's numeric operands.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct MasOperands {
    /// Stop Type (0 All, 1 Jog, 2 Move, 8 Position Cam, …).
    pub stop_type: i32,
    /// 0 axis maximum deceleration, 1 DecelRate.
    pub change_decel: i32,
    /// Deceleration when Change Decel is 1.
    pub decel_rate: f64,
    /// 0 units per sec², 1 % of maximum.
    pub decel_units: i32,
}

/// Why MAJ or MAS fails (ERR 13 with the operand, or the axis' state).
pub type JogError = crate::instruction::OperandError;

/// Faceplate indices (ERR 13's EXERR), read from the catalogue.
mod exerr {
    use crate::catalogue::{MAJ, MAS};

    pub(super) const DIRECTION: i32 = MAJ.exerr("Direction");
    pub(super) const SPEED: i32 = MAJ.exerr("Speed");
    pub(super) const SPEED_UNITS: i32 = MAJ.exerr("Speed Units");
    pub(super) const ACCEL_RATE: i32 = MAJ.exerr("Accel Rate");
    pub(super) const ACCEL_UNITS: i32 = MAJ.exerr("Accel Units");
    pub(super) const DECEL_RATE: i32 = MAJ.exerr("Decel Rate");
    pub(super) const DECEL_UNITS: i32 = MAJ.exerr("Decel Units");
    pub(super) const PROFILE: i32 = MAJ.exerr("Profile");
    pub(super) const STOP_TYPE: i32 = MAS.exerr("Stop Type");
    pub(super) const CHANGE_DECEL: i32 = MAS.exerr("Change Decel");
    pub(super) const STOP_DECEL_RATE: i32 = MAS.exerr("Decel Rate");
    pub(super) const STOP_DECEL_UNITS: i32 = MAS.exerr("Decel Units");
}

/// A validated jog: signed velocity and the limits to reach it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Jog {
    /// Signed target velocity, units/s.
    pub velocity: f64,
    /// Ramp limits.
    pub limits: Limits,
}

fn rate(operand: i32, value: f64, units: i32, units_operand: i32, max: f64) -> Result<f64, JogError> {
    let v = match units {
        0 => value,
        1 => value / 100.0 * max,
        _ => {
            return Err(JogError::ParameterOutOfRange {
                operand: units_operand,
                value: f64::from(units),
            });
        }
    };
    if v.is_finite() && v >= 0.0 {
        Ok(v)
    } else {
        Err(JogError::ParameterOutOfRange { operand, value })
    }
}

fn positive(operand: i32, v: f64, value: f64) -> Result<f64, JogError> {
    if v > 0.0 {
        Ok(v)
    } else {
        Err(JogError::ParameterOutOfRange { operand, value })
    }
}

impl Jog {
    /// Validates MAJ's operands against the axis.
    ///
    /// # Errors
    /// [`JogError::ParameterOutOfRange`] naming the operand.
    pub fn new(o: &MajOperands, axis: &AxisConfig) -> Result<Self, JogError> {
        let sign = match o.direction {
            0 => 1.0,
            1 => -1.0,
            d => {
                return Err(JogError::ParameterOutOfRange {
                    operand: exerr::DIRECTION,
                    value: f64::from(d),
                });
            }
        };
        let speed = rate(
            exerr::SPEED,
            o.speed,
            o.speed_units,
            exerr::SPEED_UNITS,
            axis.max_velocity,
        )?;
        let accel = positive(
            exerr::ACCEL_RATE,
            rate(
                exerr::ACCEL_RATE,
                o.accel_rate,
                o.accel_units,
                exerr::ACCEL_UNITS,
                axis.max_acceleration,
            )?,
            o.accel_rate,
        )?;
        let decel = positive(
            exerr::DECEL_RATE,
            rate(
                exerr::DECEL_RATE,
                o.decel_rate,
                o.decel_units,
                exerr::DECEL_UNITS,
                axis.max_deceleration,
            )?,
            o.decel_rate,
        )?;
        let vmax = speed.max(axis.max_velocity);
        let limits = match o.profile {
            0 => Limits::trapezoidal(vmax, accel, decel),
            1 if axis.max_jerk > 0.0 => Limits::s_curve(vmax, accel, decel, axis.max_jerk, axis.max_jerk),
            p => {
                return Err(JogError::ParameterOutOfRange {
                    operand: exerr::PROFILE,
                    value: f64::from(p),
                });
            }
        }
        .map_err(|_: LimitsError| JogError::ParameterOutOfRange {
            operand: exerr::SPEED,
            value: o.speed,
        })?;
        Ok(Self {
            velocity: sign * speed,
            limits,
        })
    }
}

/// Which processes an MAS stops.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct StopScope {
    /// Jogs.
    pub jog: bool,
    /// Moves (MC_MoveModulo commands).
    pub moves: bool,
    /// Position cams.
    pub position_cam: bool,
    /// Gearing (MAG).
    pub gear: bool,
}

/// A validated MAS.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stop {
    /// What it stops.
    pub scope: StopScope,
    /// Deceleration, units/s².
    pub deceleration: f64,
}

impl Stop {
    /// Validates MAS's operands against the axis.
    ///
    /// # Errors
    /// [`JogError::ParameterOutOfRange`] naming the operand.
    pub fn new(o: &MasOperands, axis: &AxisConfig) -> Result<Self, JogError> {
        let bad = |operand: i32, value: f64| JogError::ParameterOutOfRange { operand, value };
        let scope = match o.stop_type {
            0 => StopScope {
                jog: true,
                moves: true,
                position_cam: true,
                gear: true,
            },
            1 => StopScope {
                jog: true,
                moves: false,
                position_cam: false,
                gear: false,
            },
            2 => StopScope {
                jog: false,
                moves: true,
                position_cam: false,
                gear: false,
            },
            3 => StopScope {
                jog: false,
                moves: false,
                position_cam: false,
                gear: true,
            },
            8 => StopScope {
                jog: false,
                moves: false,
                position_cam: true,
                gear: false,
            },
            4..=10 => StopScope {
                jog: false,
                moves: false,
                position_cam: false,
                gear: false,
            },
            t => return Err(bad(exerr::STOP_TYPE, f64::from(t))),
        };
        let deceleration = match o.change_decel {
            0 => axis.max_deceleration,
            1 => positive(
                exerr::STOP_DECEL_RATE,
                rate(
                    exerr::STOP_DECEL_RATE,
                    o.decel_rate,
                    o.decel_units,
                    exerr::STOP_DECEL_UNITS,
                    axis.max_deceleration,
                )?,
                o.decel_rate,
            )?,
            c => return Err(bad(exerr::CHANGE_DECEL, f64::from(c))),
        };
        Ok(Self { scope, deceleration })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::axis::AxisKind;

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

        let s = Stop::new(&MasOperands::default(), &axis).unwrap();
        assert_eq!(s.deceleration, 500.0);
        assert!(s.scope.jog && s.scope.moves && s.scope.position_cam);
        let s = Stop::new(
            &MasOperands {
                stop_type: 8,
                change_decel: 1,
                decel_rate: 20.0,
                decel_units: 1,
            },
            &axis,
        )
        .unwrap();
        assert_eq!(s.deceleration, 100.0);
        assert!(!s.scope.jog && s.scope.position_cam);
        let e = |o: MasOperands| Stop::new(&o, &axis).unwrap_err().exerr();
        assert_eq!(
            e(MasOperands {
                stop_type: 11,
                ..Default::default()
            }),
            2
        );
        assert_eq!(
            e(MasOperands {
                change_decel: 1,
                decel_rate: 0.0,
                ..Default::default()
            }),
            4
        );
    }
}
