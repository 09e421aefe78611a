//! MC_MoveModulo (Beckhoff Tc2_MC2 / PLCopen): positioning to a modulo
//! position of an axis.
//!
//! # What the spec says, and how it is implemented
//! * `Execute` — the command starts on a rising edge (evaluated by the
//!   [`crate::task::MotionTask`] each coarse update).
//! * `Position` — modulo target, ≥ 0. From standstill (and when a buffered
//!   command starts from standstill) a position ≥ one period adds full turns:
//!   `Position = turns · period + modulo target`.
//! * `Velocity` > 0; `Acceleration`, `Deceleration`, `Jerk` ≥ 0, where 0 means
//!   the axis default (`max_acceleration`, `max_deceleration`, `max_jerk`).
//!   The profile is an S-curve when the resulting jerk is > 0, trapezoidal
//!   when it is 0 (an axis configured without jerk limit).
//! * `Direction` — positive, negative, shortest way, current direction.
//! * Started **during a motion**, the direction of travel is never reversed:
//!   the target is reached in the current direction on the shortest path that
//!   still lets the axis brake in time (whole periods are added until the
//!   braking distance fits), and extra turns in `Position` are ignored.
//! * **Special cases**: at exactly 90° asked 90° → no motion (`Done` at once);
//!   450° in the positive direction → exactly one rotation; after an axis
//!   reset ([`crate::task::MotionTask::reset_axis`], which adopts the actual
//!   position as set position) a position a little under 90° gives a minimal
//!   positive move, a little over gives a complete rotation — unless the
//!   axis' **modulo tolerance window** covers the difference, in which case
//!   the target is reached the shortest way (against the direction asked if
//!   need be) and only the explicit extra turns are added (the TwinCAT
//!   "modulo tolerance window"; default 0, i.e. the spec's plain behaviour).
//! * `BufferMode` — see [`McBufferMode`]; the junction velocities of the
//!   blending modes are PLCopen's (lower / first / second / higher of the two
//!   commands' velocities).
//! * Outputs follow the PLCopen rules documented on
//!   [`crate::instruction::FbOutputs`]. `Done` when setpoint generation has
//!   ended and — with target position monitoring — the actual position is in
//!   the in-position window; with position range monitoring only
//!   ([`crate::axis::AxisConfig::position_range_monitoring`]) in the
//!   position range window; at once with neither, or with
//!   `Options.IgnorePositionMonitoring`.
//! * **Coupled slaves**: on an axis a cam or a gearing drives, the command
//!   is refused ([`ErrorId::COUPLED_SLAVE`]) unless the axis allows motion
//!   commands on coupled slaves
//!   ([`crate::axis::AxisConfig::allow_motion_on_coupled_slave`]); then it
//!   decouples the axis (ends the cam or gear) and runs, and — "the only
//!   available BufferMode is Aborting" — any other mode is refused
//!   ([`ErrorId::COUPLED_BUFFER_MODE`]).
//! * **Stops**: "a standard stop may have been triggered just before": a
//!   command issued while the axis stops (a MAS ramp, a fault's, a
//!   collision's or a coordinated stop) is refused with
//!   [`ErrorId::AXIS_STOPPING`] and the stop goes on, as PLCopen's Stopping
//!   state refuses motion; once the axis stands still it is accepted. (The
//!   twin runs no MC_Stop block, whose `Execute` would extend that state.)
//! * **Options** ([`MoveOptions`], `ST_MoveOptions`):
//!   `IgnorePositionMonitoring` is honoured (above);
//!   `EnableStopPositionMonitoring` concerns stop commands only and has no
//!   effect here; `EnableBlendingPosition` is not simulated and a command
//!   with it set is refused ([`ErrorId::BLENDING_POSITION`]).
//!
//! # Choices where the spec is silent
//! * **Shortest way** from standstill adds the extra turns in the direction of
//!   the shortest way (positive when the axis is already at the target); a
//!   tie (exactly half a period) goes positive.
//! * **Current direction** from standstill uses the direction of the axis'
//!   last motion (positive for an axis that never moved).
//! * **During a motion** the `Direction` input is not checked against the
//!   direction of travel: the spec says the direction cannot be reversed, so
//!   the current direction wins, whatever was asked.
//! * **Blending** ends the running command at its own target with the
//!   junction velocity (lower when its remaining distance is too short to
//!   reach it); its `Done` is set at the hand-over, since an axis passing
//!   through a target at speed is never "in position".
//! * **Buffered** commands start when the running one is `Done` (after the
//!   in-position check). One command can wait per axis; a second one gets
//!   [`ErrorId::BUFFER_FULL`].
//! * **Re-triggering** an instance that is still busy: the spec says this is
//!   not possible; the new edge is refused with [`ErrorId::BUSY`], and the
//!   motion already under way continues (it belongs to the axis now) without
//!   reporting to the instance any more.
//! * The axis must have a modulo period ([`crate::axis::AxisConfig::modulo_period`]),
//!   else [`ErrorId::NOT_MODULO`]. `Velocity` above the axis' `max_velocity`
//!   is refused ([`ErrorId::VELOCITY`]), as TwinCAT does; acceleration,
//!   deceleration and jerk are taken as given.
//!
//! # ErrorID
//! Numbers in TwinCAT's NC range; 0x4221 has TwinCAT's meaning ("requested
//! set velocity is not allowed"), the others are this product's, listed on
//! [`ErrorId`].

use crate::axis::{AxisConfig, Modulo};
use crate::profile::{Limits, State, stopping_distance};
use thiserror::Error;

/// PLCopen `MC_Direction` (Tc2_MC2 values).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum McDirection {
    /// `MC_Positive_Direction` (1).
    #[default]
    Positive,
    /// `MC_Shortest_Way` (2).
    ShortestWay,
    /// `MC_Negative_Direction` (3).
    Negative,
    /// `MC_Current_Direction` (4).
    CurrentDirection,
}

impl McDirection {
    /// The enumeration for its numeric value, or `None`.
    pub fn from_code(code: i64) -> Option<Self> {
        Some(match code {
            1 => Self::Positive,
            2 => Self::ShortestWay,
            3 => Self::Negative,
            4 => Self::CurrentDirection,
            _ => return None,
        })
    }
}

/// PLCopen `MC_BufferMode`: what happens when the axis is already executing
/// another command.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum McBufferMode {
    /// `MC_Aborting` (0): start now, aborting the running command.
    #[default]
    Aborting,
    /// `MC_Buffered` (1): start when the running command is done (at rest).
    Buffered,
    /// `MC_BlendingLow` (2): blend at the lower of both velocities.
    BlendingLow,
    /// `MC_BlendingPrevious` (3): blend at the running command's velocity.
    BlendingPrevious,
    /// `MC_BlendingNext` (4): blend at this command's velocity.
    BlendingNext,
    /// `MC_BlendingHigh` (5): blend at the higher of both velocities.
    BlendingHigh,
}

impl McBufferMode {
    /// The enumeration for its numeric value, or `None`.
    pub fn from_code(code: i64) -> Option<Self> {
        Some(match code {
            0 => Self::Aborting,
            1 => Self::Buffered,
            2 => Self::BlendingLow,
            3 => Self::BlendingPrevious,
            4 => Self::BlendingNext,
            5 => Self::BlendingHigh,
            _ => return None,
        })
    }

    /// The junction velocity (magnitude) between a running command of
    /// velocity `previous` and a new one of velocity `next`, or `None` for
    /// the non-blending modes.
    pub fn junction_velocity(self, previous: f64, next: f64) -> Option<f64> {
        match self {
            Self::Aborting | Self::Buffered => None,
            Self::BlendingLow => Some(previous.min(next)),
            Self::BlendingPrevious => Some(previous),
            Self::BlendingNext => Some(next),
            Self::BlendingHigh => Some(previous.max(next)),
        }
    }
}

/// The block's inputs (`VAR_INPUT`), as the program sets them.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct MoveModuloInputs {
    /// `Execute`: a rising edge starts the command.
    pub execute: bool,
    /// `Position`: modulo target (≥ 0), axis units; ≥ one period adds turns.
    pub position: f64,
    /// `Velocity`: maximum travel velocity (> 0), units/s.
    pub velocity: f64,
    /// `Acceleration` (≥ 0, 0 = axis default), units/s².
    pub acceleration: f64,
    /// `Deceleration` (≥ 0, 0 = axis default), units/s².
    pub deceleration: f64,
    /// `Jerk` (≥ 0, 0 = axis default), units/s³.
    pub jerk: f64,
    /// `Direction`.
    pub direction: McDirection,
    /// `BufferMode`.
    pub buffer_mode: McBufferMode,
    /// `Options` (`ST_MoveOptions`).
    pub options: MoveOptions,
}

/// `ST_MoveOptions` (Tc2_MC2): optional settings of a travel command; all
/// off by default ("the input can normally remain open").
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct MoveOptions {
    /// `EnableBlendingPosition`: hand over at `BlendingPosition` instead
    /// of the running command's target. Not simulated: a command with it
    /// set is refused ([`ErrorId::BLENDING_POSITION`]).
    pub enable_blending_position: bool,
    /// `BlendingPosition`, axis units (used only with the flag above).
    pub blending_position: f64,
    /// `IgnorePositionMonitoring`: `Done` as soon as setpoint generation
    /// ends, whatever the axis' target-position or position-range
    /// monitoring.
    pub ignore_position_monitoring: bool,
    /// `EnableStopPositionMonitoring`: concerns MC_Stop and MC_Halt only
    /// (they define no target); no effect on MC_MoveModulo.
    pub enable_stop_position_monitoring: bool,
}

/// An MC_MoveModulo `ErrorID`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct ErrorId(pub u32);

impl ErrorId {
    /// 0x4221: `Velocity` not finite and > 0, or above the axis maximum.
    pub const VELOCITY: Self = Self(0x4221);
    /// 0x4222: `Position` negative or not finite.
    pub const POSITION: Self = Self(0x4222);
    /// 0x4223: `Acceleration` negative or not finite.
    pub const ACCELERATION: Self = Self(0x4223);
    /// 0x4224: `Deceleration` negative or not finite.
    pub const DECELERATION: Self = Self(0x4224);
    /// 0x4225: `Jerk` negative or not finite.
    pub const JERK: Self = Self(0x4225);
    /// 0x4226: `Direction` is not an `MC_Direction` value.
    pub const DIRECTION: Self = Self(0x4226);
    /// 0x4227: `BufferMode` is not an `MC_BufferMode` value.
    pub const BUFFER_MODE: Self = Self(0x4227);
    /// 0x4228: the axis has no modulo period.
    pub const NOT_MODULO: Self = Self(0x4228);
    /// 0x4229: a command is already waiting in the axis' buffer.
    pub const BUFFER_FULL: Self = Self(0x4229);
    /// 0x422A: the instance was triggered again while busy.
    pub const BUSY: Self = Self(0x422A);
    /// 0x422B: the axis' own limits are unusable (a zero default rate).
    pub const AXIS_LIMITS: Self = Self(0x422B);
    /// 0x422C: the twin's pre-flight sweep predicts a collision on the
    /// planned path and the scene rejects such moves (rejected in the
    /// update it became Active, as the twin does, the move is undone and an
    /// axis at rest does not move; see `MotionTask::reject_move`).
    pub const PATH_COLLISION: Self = Self(0x422C);
    /// 0x422D: the axis is not ready for motion: servo off, shut down,
    /// faulted, inhibited or feedback-only (see [`crate::servo`]).
    pub const AXIS_NOT_READY: Self = Self(0x422D);
    /// 0x422E: the axis is stopping (a MAS, a fault's or a collision's stop
    /// ramp): motion commands are refused until it stands still, and the
    /// stop goes on.
    pub const AXIS_STOPPING: Self = Self(0x422E);
    /// 0x422F: the axis is a coupled slave (cam or gear) and its
    /// configuration does not allow motion commands on coupled slaves.
    pub const COUPLED_SLAVE: Self = Self(0x422F);
    /// 0x4230: on a coupled slave only `MC_Aborting` is available.
    pub const COUPLED_BUFFER_MODE: Self = Self(0x4230);
    /// 0x4231: `Options.EnableBlendingPosition` is not simulated.
    pub const BLENDING_POSITION: Self = Self(0x4231);

    /// What the number means, in words (for logs and summaries).
    pub fn meaning(self) -> &'static str {
        match self {
            Self::VELOCITY => "Velocity not allowed (must be > 0 and <= the axis maximum)",
            Self::POSITION => "Position not allowed (must be finite and >= 0)",
            Self::ACCELERATION => "Acceleration not allowed (must be finite and >= 0)",
            Self::DECELERATION => "Deceleration not allowed (must be finite and >= 0)",
            Self::JERK => "Jerk not allowed (must be finite and >= 0)",
            Self::DIRECTION => "Direction is not an MC_Direction value",
            Self::BUFFER_MODE => "BufferMode is not an MC_BufferMode value",
            Self::NOT_MODULO => "the axis has no modulo period",
            Self::BUFFER_FULL => "a command is already buffered on the axis",
            Self::BUSY => "the block was triggered again while busy",
            Self::AXIS_LIMITS => "the axis limits cannot form a profile",
            Self::PATH_COLLISION => "the planned path collides (pre-flight sweep); the move was rejected",
            Self::AXIS_NOT_READY => {
                "the axis is not ready for motion (servo off, shut down, faulted, inhibited or feedback-only)"
            }
            Self::AXIS_STOPPING => "the axis is stopping; motion commands are refused until it stands still",
            Self::COUPLED_SLAVE => "the axis is a coupled slave and motion commands on coupled slaves are not allowed",
            Self::COUPLED_BUFFER_MODE => "on a coupled slave only MC_Aborting is available",
            Self::BLENDING_POSITION => "Options.EnableBlendingPosition is not simulated",
            _ => "unknown error",
        }
    }
}

/// Why an MC_MoveModulo command is refused.
#[derive(Debug, Clone, Copy, PartialEq, Error)]
#[non_exhaustive]
pub enum MoveModuloError {
    /// See [`ErrorId::VELOCITY`].
    #[error("Velocity {velocity} must be finite, > 0 and <= the axis maximum {max}")]
    Velocity {
        /// The operand.
        velocity: f64,
        /// The axis maximum.
        max: f64,
    },
    /// See [`ErrorId::POSITION`].
    #[error("Position {position} must be finite and >= 0")]
    Position {
        /// The operand.
        position: f64,
    },
    /// See [`ErrorId::ACCELERATION`], [`ErrorId::DECELERATION`], [`ErrorId::JERK`].
    #[error("{operand} {value} must be finite and >= 0 (0 = axis default)")]
    Rate {
        /// `"Acceleration"`, `"Deceleration"` or `"Jerk"`.
        operand: &'static str,
        /// The operand.
        value: f64,
    },
    /// See [`ErrorId::DIRECTION`].
    #[error("Direction {code} is not an MC_Direction value (1..=4)")]
    Direction {
        /// The numeric value given.
        code: i64,
    },
    /// See [`ErrorId::BUFFER_MODE`].
    #[error("BufferMode {code} is not an MC_BufferMode value (0..=5)")]
    BufferMode {
        /// The numeric value given.
        code: i64,
    },
    /// See [`ErrorId::NOT_MODULO`].
    #[error("axis has no modulo period")]
    NotModulo,
    /// See [`ErrorId::BUFFER_FULL`].
    #[error("a command is already buffered on the axis")]
    BufferFull,
    /// See [`ErrorId::BUSY`].
    #[error("the instance is busy; it cannot be triggered with new parameters while active")]
    Busy,
    /// See [`ErrorId::AXIS_LIMITS`].
    #[error("the axis limits cannot form a profile")]
    AxisLimits,
    /// See [`ErrorId::PATH_COLLISION`].
    #[error("the pre-flight sweep predicts a collision on the planned path")]
    PathCollision,
    /// See [`ErrorId::AXIS_NOT_READY`].
    #[error("axis not ready: {0}")]
    AxisNotReady(crate::servo::StateError),
    /// See [`ErrorId::AXIS_STOPPING`].
    #[error("the axis is stopping; motion commands are refused until it stands still")]
    AxisStopping,
    /// See [`ErrorId::COUPLED_SLAVE`].
    #[error("the axis is a coupled slave (cam or gear) and does not allow motion commands")]
    CoupledSlave,
    /// See [`ErrorId::COUPLED_BUFFER_MODE`].
    #[error("BufferMode {mode:?} on a coupled slave: only MC_Aborting is available")]
    CoupledBufferMode {
        /// The mode asked.
        mode: McBufferMode,
    },
    /// See [`ErrorId::BLENDING_POSITION`].
    #[error("Options.EnableBlendingPosition is not simulated (the hand-over is the running command's target)")]
    BlendingPosition,
}

impl MoveModuloError {
    /// The `ErrorID` output for this error.
    pub fn error_id(&self) -> ErrorId {
        match self {
            Self::Velocity { .. } => ErrorId::VELOCITY,
            Self::Position { .. } => ErrorId::POSITION,
            Self::Rate {
                operand: "Acceleration",
                ..
            } => ErrorId::ACCELERATION,
            Self::Rate {
                operand: "Deceleration",
                ..
            } => ErrorId::DECELERATION,
            Self::Rate { .. } => ErrorId::JERK,
            Self::Direction { .. } => ErrorId::DIRECTION,
            Self::BufferMode { .. } => ErrorId::BUFFER_MODE,
            Self::NotModulo => ErrorId::NOT_MODULO,
            Self::BufferFull => ErrorId::BUFFER_FULL,
            Self::Busy => ErrorId::BUSY,
            Self::AxisLimits => ErrorId::AXIS_LIMITS,
            Self::PathCollision => ErrorId::PATH_COLLISION,
            Self::AxisNotReady(_) => ErrorId::AXIS_NOT_READY,
            Self::AxisStopping => ErrorId::AXIS_STOPPING,
            Self::CoupledSlave => ErrorId::COUPLED_SLAVE,
            Self::CoupledBufferMode { .. } => ErrorId::COUPLED_BUFFER_MODE,
            Self::BlendingPosition => ErrorId::BLENDING_POSITION,
        }
    }
}

/// A validated MC_MoveModulo command: it cannot exist with bad operands.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MoveModulo {
    position: f64,
    velocity: f64,
    limits: Limits,
    direction: McDirection,
    buffer_mode: McBufferMode,
    modulo: Modulo,
    tolerance_window: f64,
    ignore_position_monitoring: bool,
}

fn rate(operand: &'static str, value: f64, default: f64) -> Result<f64, MoveModuloError> {
    if !(value.is_finite() && value >= 0.0) {
        return Err(MoveModuloError::Rate { operand, value });
    }
    Ok(if value == 0.0 { default } else { value })
}

impl MoveModulo {
    /// Validates the inputs against the axis configuration.
    ///
    /// # Errors
    /// [`MoveModuloError`] for the first operand out of range (checked in
    /// the order Position, Velocity, Acceleration, Deceleration, Jerk), an
    /// axis without modulo period, or `Options.EnableBlendingPosition`.
    pub fn new(inputs: &MoveModuloInputs, axis: &AxisConfig) -> Result<Self, MoveModuloError> {
        if !(crate::axis::position_in_reach(inputs.position) && inputs.position >= 0.0) {
            return Err(MoveModuloError::Position {
                position: inputs.position,
            });
        }
        let v = inputs.velocity;
        if !(v.is_finite() && v > 0.0 && v <= axis.max_velocity) {
            return Err(MoveModuloError::Velocity {
                velocity: v,
                max: axis.max_velocity,
            });
        }
        let acc = rate("Acceleration", inputs.acceleration, axis.max_acceleration)?;
        let dec = rate("Deceleration", inputs.deceleration, axis.max_deceleration)?;
        let jerk = rate("Jerk", inputs.jerk, axis.max_jerk)?;
        let modulo = axis.modulo().ok_or(MoveModuloError::NotModulo)?;
        let limits = if jerk > 0.0 {
            Limits::s_curve(v, acc, dec, jerk, jerk)
        } else {
            Limits::trapezoidal(v, acc, dec)
        };
        let limits = limits.map_err(|_| MoveModuloError::AxisLimits)?;
        if inputs.options.enable_blending_position {
            return Err(MoveModuloError::BlendingPosition);
        }
        Ok(Self {
            position: inputs.position,
            velocity: v,
            limits,
            direction: inputs.direction,
            buffer_mode: inputs.buffer_mode,
            modulo,
            tolerance_window: axis.modulo_tolerance_window,
            ignore_position_monitoring: inputs.options.ignore_position_monitoring,
        })
    }

    /// Whether `Done` ignores the axis' position monitoring
    /// (`Options.IgnorePositionMonitoring`).
    pub fn ignores_position_monitoring(&self) -> bool {
        self.ignore_position_monitoring
    }

    /// The command's velocity (units/s).
    pub fn velocity(&self) -> f64 {
        self.velocity
    }

    /// The command's profile limits.
    pub fn limits(&self) -> &Limits {
        &self.limits
    }

    /// The buffer mode.
    pub fn buffer_mode(&self) -> McBufferMode {
        self.buffer_mode
    }

    /// The absolute (unwrapped) target for the command starting at `start`.
    ///
    /// `last_direction` (+1 or −1) is the direction of the axis' last motion,
    /// used by [`McDirection::CurrentDirection`] from standstill. The axis is
    /// "moving" when its command velocity is not zero.
    pub fn absolute_target(&self, start: State, last_direction: f64) -> f64 {
        let period = self.modulo.period();
        let here = self.modulo.wrap(start.position);
        let turns = (self.position / period).floor();
        let goal = self.modulo.wrap(self.position - turns * period);
        let ahead = |dir: f64| {
            if dir > 0.0 {
                self.modulo.wrap(goal - here)
            } else {
                self.modulo.wrap(here - goal)
            }
        };

        if start.velocity != 0.0 {
            // Never reverse; shortest path that still allows braking.
            let dir = start.velocity.signum();
            let brake = stopping_distance(start, &self.limits).abs();
            let mut delta = ahead(dir);
            while delta < brake {
                delta += period;
            }
            return start.position + dir * delta;
        }

        let mut shortest = ahead(1.0);
        if shortest > period / 2.0 {
            shortest -= period;
        }
        let extra = turns * period;
        let last = if last_direction < 0.0 { -1.0 } else { 1.0 };
        let delta = if shortest.abs() <= self.tolerance_window {
            let dir = match self.direction {
                McDirection::Positive => 1.0,
                McDirection::Negative => -1.0,
                McDirection::ShortestWay => {
                    if shortest < 0.0 {
                        -1.0
                    } else {
                        1.0
                    }
                }
                McDirection::CurrentDirection => last,
            };
            shortest + dir * extra
        } else {
            match self.direction {
                McDirection::Positive => ahead(1.0) + extra,
                McDirection::Negative => -(ahead(-1.0) + extra),
                McDirection::ShortestWay => shortest + shortest.signum() * extra,
                McDirection::CurrentDirection => last * (ahead(last) + extra),
            }
        };
        start.position + delta
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::axis::AxisKind;

    fn axis(tolerance: f64) -> AxisConfig {
        AxisConfig {
            modulo_period: Some(360.0),
            max_velocity: 720.0,
            max_acceleration: 3600.0,
            max_deceleration: 3600.0,
            max_jerk: 36000.0,
            modulo_tolerance_window: tolerance,
            ..AxisConfig::new("Table", AxisKind::Rotary)
        }
    }

    fn cmd(position: f64, direction: McDirection) -> MoveModulo {
        let inputs = MoveModuloInputs {
            execute: true,
            position,
            velocity: 180.0,
            direction,
            ..Default::default()
        };
        MoveModulo::new(&inputs, &axis(0.0)).unwrap()
    }

    fn target_from(start_deg: f64, position: f64, direction: McDirection) -> f64 {
        cmd(position, direction).absolute_target(State::at_rest(start_deg), 1.0) - start_deg
    }

    /// "If the axis is located at an exact set position, such as 90 degrees,
    /// and if positioning to 90 degrees is required, no movement is carried out."
    #[test]
    fn spec_at_exactly_90_asked_90_does_not_move() {
        for dir in [
            McDirection::Positive,
            McDirection::Negative,
            McDirection::ShortestWay,
            McDirection::CurrentDirection,
        ] {
            assert_eq!(target_from(90.0, 90.0, dir), 0.0, "{dir:?}");
        }
    }

    /// "If required to turn 450 degrees in a positive direction, it will
    /// perform just one rotation."
    #[test]
    fn spec_450_positive_from_90_is_exactly_one_rotation() {
        assert_eq!(target_from(90.0, 450.0, McDirection::Positive), 360.0);
        assert_eq!(target_from(90.0 + 720.0, 450.0, McDirection::Positive), 360.0);
    }

    /// "The axis will then no longer be exactly at 90 degrees, but will be a
    /// little under or over. These cases will give rise either to a minimum
    /// positioning to 90 degrees, or on the other hand a complete rotation."
    #[test]
    fn spec_after_reset_a_little_under_is_minimal_a_little_over_is_a_full_turn() {
        let under = target_from(89.9999, 90.0, McDirection::Positive);
        assert!((under - 0.0001).abs() < 1e-9, "{under}");
        let over = target_from(90.0001, 90.0, McDirection::Positive);
        assert!((over - 359.9999).abs() < 1e-9, "{over}");
        // With a tolerance window covering the difference: the shortest way.
        let c = MoveModulo::new(
            &MoveModuloInputs {
                position: 90.0,
                velocity: 180.0,
                ..Default::default()
            },
            &axis(0.01),
        )
        .unwrap();
        let t = c.absolute_target(State::at_rest(90.0001), 1.0);
        assert!((t - 90.0).abs() < 1e-9, "{t}");
        let c = MoveModulo::new(
            &MoveModuloInputs {
                position: 450.0,
                velocity: 180.0,
                ..Default::default()
            },
            &axis(0.01),
        )
        .unwrap();
        let t = c.absolute_target(State::at_rest(90.0001), 1.0);
        assert!((t - 450.0).abs() < 1e-9, "one explicit turn from the window: {t}");
    }

    #[test]
    fn each_direction_from_several_starts() {
        use McDirection::*;
        // (start, position, direction, expected distance)
        let table = [
            (0.0, 90.0, Positive, 90.0),
            (0.0, 90.0, Negative, -270.0),
            (0.0, 90.0, ShortestWay, 90.0),
            (0.0, 270.0, ShortestWay, -90.0),
            (0.0, 180.0, ShortestWay, 180.0),
            (350.0, 10.0, Positive, 20.0),
            (350.0, 10.0, Negative, -340.0),
            (350.0, 10.0, ShortestWay, 20.0),
            (10.0, 350.0, ShortestWay, -20.0),
            (-30.0, 0.0, Positive, 30.0),
            (725.0, 0.0, Negative, -5.0),
            (90.0, 90.0, Positive, 0.0),
            (90.0, 90.0, Negative, 0.0),
            (90.0, 360.0 + 90.0, Negative, -360.0),
            (90.0, 720.0 + 90.0, ShortestWay, 720.0),
            (0.0, 360.0, Positive, 360.0),
            (0.0, 360.0 + 270.0, Negative, -450.0),
            (0.0, 2.0 * 360.0 + 270.0, ShortestWay, -810.0),
            (100.0, 200.0, CurrentDirection, 100.0),
            // Start exactly on the target, one period away (unwrapped).
            (450.0, 90.0, Positive, 0.0),
            (-270.0, 90.0, Negative, 0.0),
            (450.0, 90.0, ShortestWay, 0.0),
            (-270.0, 450.0, Positive, 360.0),
            (450.0, 450.0, CurrentDirection, 360.0),
            // Start one period away from a different target.
            (360.0, 90.0, Negative, -270.0),
            (-360.0, 90.0, ShortestWay, 90.0),
        ];
        for (start, position, dir, want) in table {
            let got = target_from(start, position, dir);
            assert!(
                (got - want).abs() < 1e-9,
                "{start} -> {position} {dir:?}: got {got}, want {want}"
            );
        }
        // Current direction after a negative motion.
        let c = cmd(200.0, CurrentDirection);
        assert!((c.absolute_target(State::at_rest(100.0), -1.0) - (100.0 - 260.0)).abs() < 1e-9);
    }

    #[test]
    fn while_moving_keeps_the_direction_and_ignores_turns() {
        let c = cmd(720.0 + 90.0, McDirection::Negative);
        // Moving positive at 180°/s, far enough to brake before 90.
        let start = State {
            position: 0.0,
            velocity: 180.0,
            acceleration: 0.0,
        };
        let t = c.absolute_target(start, 1.0);
        assert!((t - 90.0).abs() < 1e-9, "{t}");
        // Too close to brake: one more period.
        let start = State {
            position: 89.0,
            velocity: 180.0,
            acceleration: 0.0,
        };
        let t = c.absolute_target(start, 1.0);
        assert!((t - 450.0).abs() < 1e-9, "{t}");
        // Moving negative.
        let start = State {
            position: 200.0,
            velocity: -180.0,
            acceleration: 0.0,
        };
        let t = c.absolute_target(start, 1.0);
        assert!((t - 90.0).abs() < 1e-9, "{t}");
    }

    #[test]
    fn junction_velocities() {
        use McBufferMode::*;
        assert_eq!(BlendingLow.junction_velocity(2.0, 5.0), Some(2.0));
        assert_eq!(BlendingPrevious.junction_velocity(2.0, 5.0), Some(2.0));
        assert_eq!(BlendingNext.junction_velocity(2.0, 5.0), Some(5.0));
        assert_eq!(BlendingHigh.junction_velocity(2.0, 5.0), Some(5.0));
        assert_eq!(Buffered.junction_velocity(2.0, 5.0), None);
        assert_eq!(Aborting.junction_velocity(2.0, 5.0), None);
    }

    /// Every operand fed NaN, ±inf, negative and zero gives its ErrorID.
    #[test]
    fn bad_operands_give_their_error_id() {
        let good = MoveModuloInputs {
            execute: true,
            position: 10.0,
            velocity: 10.0,
            ..Default::default()
        };
        let a = axis(0.0);
        assert!(MoveModulo::new(&good, &a).is_ok());
        let id = |i: MoveModuloInputs| MoveModulo::new(&i, &a).map(|_| ()).map_err(|e| e.error_id());
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY, -1.0] {
            assert_eq!(
                id(MoveModuloInputs { position: bad, ..good }),
                Err(ErrorId::POSITION),
                "{bad}"
            );
            assert_eq!(
                id(MoveModuloInputs { velocity: bad, ..good }),
                Err(ErrorId::VELOCITY),
                "{bad}"
            );
            assert_eq!(
                id(MoveModuloInputs {
                    acceleration: bad,
                    ..good
                }),
                Err(ErrorId::ACCELERATION),
                "{bad}"
            );
            assert_eq!(
                id(MoveModuloInputs {
                    deceleration: bad,
                    ..good
                }),
                Err(ErrorId::DECELERATION),
                "{bad}"
            );
            assert_eq!(id(MoveModuloInputs { jerk: bad, ..good }), Err(ErrorId::JERK), "{bad}");
        }
        // Zero: legal for Position and the rates (axis default), not Velocity.
        assert_eq!(id(MoveModuloInputs { position: 0.0, ..good }), Ok(()));
        assert_eq!(id(MoveModuloInputs { velocity: 0.0, ..good }), Err(ErrorId::VELOCITY));
        assert_eq!(
            id(MoveModuloInputs {
                acceleration: 0.0,
                deceleration: 0.0,
                jerk: 0.0,
                ..good
            }),
            Ok(())
        );
        assert_eq!(
            id(MoveModuloInputs {
                velocity: 721.0,
                ..good
            }),
            Err(ErrorId::VELOCITY)
        );
        let linear = AxisConfig::new("X", AxisKind::Linear);
        assert_eq!(
            MoveModulo::new(&MoveModuloInputs { velocity: 0.5, ..good }, &linear)
                .map(|_| ())
                .map_err(|e| e.error_id()),
            Err(ErrorId::NOT_MODULO)
        );
        assert_eq!(McDirection::from_code(0), None);
        assert_eq!(McDirection::from_code(4), Some(McDirection::CurrentDirection));
        assert_eq!(McBufferMode::from_code(6), None);
        assert_eq!(MoveModuloError::Direction { code: 9 }.error_id(), ErrorId::DIRECTION);
        assert_eq!(MoveModuloError::BufferMode { code: 9 }.error_id(), ErrorId::BUFFER_MODE);
    }
}
