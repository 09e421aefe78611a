//! Motion Axis Move (MAM): a single-axis move to a position, with a
//! trapezoidal or S-curve profile. The executor side is `task/mam.rs`.
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

use crate::axis::AxisConfig;
use crate::dynamics::MoveDynamics;
use crate::profile::{Limits, State, jerk_from_percent_of_time};
use thiserror::Error;

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

/// Why an MAM is refused.
#[derive(Debug, Clone, Copy, PartialEq, Error)]
#[non_exhaustive]
pub enum MamError {
    /// ERR 13: an operand out of range (EXERR = its faceplate index).
    #[error("parameter out of range: operand {operand} = {value} (ERR 13)")]
    ParameterOutOfRange {
        /// Faceplate index.
        operand: i32,
        /// Its value.
        value: f64,
    },
    /// ERR 17: a rotary move type on an axis without a modulo period.
    #[error("axis mode not rotary (ERR 17): move type {move_type} needs a modulo axis")]
    AxisModeNotRotary {
        /// The move type.
        move_type: i64,
    },
    /// The axis' state refuses the move (ERR 5, 7, 8, 53 …; EXERR 0).
    #[error("{0}")]
    State(crate::servo::StateError),
}

impl MamError {
    /// The `ERR` code.
    pub fn err(&self) -> i32 {
        match self {
            Self::ParameterOutOfRange { .. } => 13,
            Self::AxisModeNotRotary { .. } => 17,
            Self::State(e) => e.err(),
        }
    }

    /// The `EXERR` code.
    pub fn exerr(&self) -> i32 {
        match self {
            Self::ParameterOutOfRange { operand, .. } => *operand,
            _ => 0,
        }
    }
}

/// Faceplate indices, read from the catalogue.
mod exerr {
    use crate::catalogue::MAM;

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
    MamError::ParameterOutOfRange { operand, value }
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
    let v = match code(units_operand, units, 1)? {
        0 => value,
        _ => value / 100.0 * max,
    };
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
        if !o.position.is_finite() {
            return Err(bad(exerr::POSITION, o.position));
        }
        let rotary = !matches!(move_type, MoveType::Absolute | MoveType::Incremental);
        match axis.modulo() {
            None if rotary => return Err(MamError::AxisModeNotRotary { move_type: o.move_type }),
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
