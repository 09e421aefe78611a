//! MAS (Motion Axis Stop), its first six operands: stops what its Stop
//! Type names on an axis — jogs, moves, position cams, gearing, time cams
//! — and ramps the axis to rest.
//!
//! `MAS(Axis, MotionControl, StopType, ChangeDecel, DecelRate, DecelUnits)`:
//! Stop Type 0 All, 1 Jog, 2 Move, 3 Gear, 7 Time Cam, 8 Position Cam (the
//! other Logix numbers — home, tune, test, master offset move, direct
//! control — name processes this planner does not have; they are accepted
//! and stop nothing). Change Decel 0 uses the axis' `max_deceleration`, 1 uses
//! DecelRate (DecelUnits 0 units/s², 1 percent of the maximum). The axis
//! ramps from its current velocity to rest; `.IP` while it does, `.PC` when
//! it is at rest (at once when nothing named was running). ERR 13 with
//! EXERR = faceplate operand number for an operand out of range.

use super::entry::{Instruction, no_load, one_shot};
use super::maj::rate;
use crate::axis::AxisConfig;
use crate::catalogue::words::{JOG_ACCEL_UNITS, MAS_STOP_TYPE, NO_YES, motion_control, op};
use crate::catalogue::{CallStyle, Format, Kind};
use crate::dynamics::positive;
use crate::instruction::{Fault, fault};
use crate::instruction::{NoFault, Refusal};
use crate::profile::{Limits, Profile, Sample, State};
use crate::task::engine::Need;
use crate::task::engine::SuperKind;
use crate::task::{Args, AxisHandle, InstructionHandle, MotionTask, RampRun};

/// Motion Axis Stop (its first six operands).
pub const MAS: Instruction = Instruction {
    mnemonic: "MAS",
    title: "Motion Axis Stop",
    summary: "stops what its Stop Type names on an axis (jogs, moves, position cams, gearing) with a ramp to rest",
    reference: "Logix motion reference",
    style: CallStyle::Positional,
    operands: &[
        op("Axis", "AXIS", Format::Tag, Kind::Axis, 0),
        motion_control(1),
        op(
            "Stop Type",
            "DINT",
            Format::Immediate,
            Kind::Enumeration(MAS_STOP_TYPE),
            2,
        ),
        op("Change Decel", "DINT", Format::Immediate, Kind::Enumeration(NO_YES), 3),
        op("Decel Rate", "REAL", Format::ImmediateOrTag, Kind::Number, 4),
        op(
            "Decel Units",
            "DINT",
            Format::Immediate,
            Kind::Enumeration(JOG_ACCEL_UNITS),
            5,
        ),
    ],
    execute,
    check,
    load: no_load,
};

/// Why MAS fails: ERR 13 with the operand, or the axis' state.
pub type MasError = Refusal<NoFault>;

/// MAS's numeric operands.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct MasOperands {
    /// Stop Type (0 All, 1 Jog, 2 Move, 3 Gear, 8 Position Cam, …).
    pub stop_type: i32,
    /// 0 axis maximum deceleration, 1 DecelRate.
    pub change_decel: i32,
    /// Deceleration when Change Decel is 1.
    pub decel_rate: f64,
    /// 0 units per sec², 1 % of maximum.
    pub decel_units: i32,
}

impl MasOperands {
    /// The operands of a call, by catalogue position.
    #[must_use]
    pub fn bind(args: &Args<'_>) -> Self {
        MasOperands {
            stop_type: args.code(2),
            change_decel: args.code(3),
            decel_rate: args.number(4),
            decel_units: args.code(5),
        }
    }
}

/// Faceplate indices (ERR 13's EXERR).
mod exerr {
    use super::MAS;

    pub(super) const STOP_TYPE: i32 = MAS.exerr("Stop Type");
    pub(super) const CHANGE_DECEL: i32 = MAS.exerr("Change Decel");
    pub(super) const DECEL_RATE: i32 = MAS.exerr("Decel Rate");
    pub(super) const DECEL_UNITS: i32 = MAS.exerr("Decel Units");
}

/// Which processes an MAS stops.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct StopScope {
    /// Jogs.
    pub jog: bool,
    /// Moves (MC_MoveModulo commands, MAMs).
    pub moves: bool,
    /// Position cams.
    pub position_cam: bool,
    /// Gearing (MAG).
    pub gear: bool,
    /// Time cams (MATC).
    pub time_cam: bool,
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
    /// ERR 13 naming the operand.
    pub fn new(o: &MasOperands, axis: &AxisConfig) -> Result<Self, MasError> {
        let scope = |jog, moves, position_cam, gear| StopScope {
            jog,
            moves,
            position_cam,
            gear,
            time_cam: false,
        };
        let scope = match o.stop_type {
            0 => StopScope {
                time_cam: true,
                ..scope(true, true, true, true)
            },
            1 => scope(true, false, false, false),
            2 => scope(false, true, false, false),
            3 => scope(false, false, false, true),
            7 => StopScope {
                time_cam: true,
                ..scope(false, false, false, false)
            },
            8 => scope(false, false, true, false),
            4..=10 => scope(false, false, false, false),
            t => return Err(Refusal::operand(exerr::STOP_TYPE, f64::from(t))),
        };
        let deceleration = match o.change_decel {
            0 => axis.max_deceleration,
            1 => rate(
                exerr::DECEL_RATE,
                o.decel_rate,
                o.decel_units,
                exerr::DECEL_UNITS,
                axis.max_deceleration,
            )
            .and_then(|d| positive(d).ok_or(Refusal::operand(exerr::DECEL_RATE, o.decel_rate)))?,
            c => return Err(Refusal::operand(exerr::CHANGE_DECEL, f64::from(c))),
        };
        Ok(Self { scope, deceleration })
    }
}

fn execute(task: &mut MotionTask, args: &Args<'_>) -> Result<(), Fault> {
    let control = args.control(1);
    one_shot(task, control, |task| {
        task.mas(args.axis(0), control, &MasOperands::bind(args))
    })
}

fn check(task: &MotionTask, args: &Args<'_>) -> Result<(), Fault> {
    Stop::new(&MasOperands::bind(args), task.axis_config(args.axis(0)))
        .map(|_| ())
        .map_err(fault)
}

impl MotionTask {
    /// MAS: stops what the Stop Type names on `axis` and ramps it to rest.
    ///
    /// # Errors
    /// ERR 13 with EXERR = the operand.
    pub(crate) fn mas(
        &mut self,
        axis: AxisHandle,
        motion_control: InstructionHandle,
        operands: &MasOperands,
    ) -> Result<(), MasError> {
        self.instruction(motion_control, |task| {
            let stop = Stop::new(operands, task.axis_config(axis))?;
            task.check_state(axis, Need::Any)?;
            task.stop_named(axis, motion_control, &stop)
        })
    }

    /// Ends what `stop` names on `axis` and starts its ramp to rest.
    fn stop_named(&mut self, axis: AxisHandle, motion_control: InstructionHandle, stop: &Stop) -> Result<(), MasError> {
        // A preloaded Pending cam (no cam active) is part of the position
        // cam process too: the stop resets its Pending Status.
        let cam_running = self.cam.axes.get(axis.0 as usize).is_some_and(|c| {
            let s = c.cam.status();
            s.position_cam || s.pending
        });
        let (jogging, _, mam) = self.jog_and_stop_status(axis);
        let moving = self.axes[axis.0 as usize].job.is_some() || mam;
        let mut stops = false;
        if stop.scope.position_cam && cam_running {
            self.end_cams(axis);
            stops = true;
        }
        if stop.scope.gear && self.end_gear(axis) {
            stops = true;
        }
        if stop.scope.time_cam && self.end_time_cams(axis) {
            stops = true;
        }
        if stop.scope.jog && stop.scope.moves && stop.scope.position_cam {
            // Stop Type All breaks a master link of the axis' systems.
            self.break_master_links_of_axis(axis);
        }
        if stop.scope.jog && jogging {
            self.end_ramp(axis);
            stops = true;
        }
        if stop.scope.moves && moving {
            self.abort_move(axis);
            if mam {
                self.end_ramp(axis);
            }
            stops = true;
        }
        let sup_named = match self.superimposed_moving(axis) {
            Some(SuperKind::Jog) => stop.scope.jog,
            Some(SuperKind::Move) => stop.scope.moves,
            _ => false,
        };
        if sup_named {
            self.stop_superimposed(axis);
        }
        self.motion_bits_mut(motion_control).dn = true;
        let state = self.axes[axis.0 as usize].command.state();
        if !stops || state.velocity == 0.0 {
            if stops {
                self.axes[axis.0 as usize].command = Sample {
                    position: state.position,
                    ..Sample::default()
                };
            }
            self.motion_bits_mut(motion_control).pc = true;
            return Ok(());
        }
        let vmax = self.axes[axis.0 as usize].config.max_velocity.max(state.velocity.abs());
        let limits = Limits::trapezoidal(vmax, stop.deceleration, stop.deceleration)
            .map_err(|_| Refusal::operand(exerr::DECEL_RATE, stop.deceleration))?;
        let state = State {
            acceleration: 0.0,
            ..state
        };
        self.end_ramp(axis);
        self.cam_axis(axis).ramp = Some(RampRun {
            stop: Some(motion_control),
            ..RampRun::new(Profile::to_velocity(state, 0.0, &limits))
        });
        self.motion_bits_mut(motion_control).ip = true;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::axis::AxisKind;
    use crate::instruction::LogixFault;

    #[test]
    fn stop_types_decelerations_and_operand_errors() {
        let axis = AxisConfig {
            max_velocity: 200.0,
            max_acceleration: 1000.0,
            max_deceleration: 500.0,
            ..AxisConfig::new("Conveyor", AxisKind::Linear)
        };
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
