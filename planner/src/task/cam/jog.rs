//! MAJ and MAS in the motion task: the jog ramp from the axis' current
//! state, and the stop of what the Stop Type names with a ramp to rest.

use super::super::servo::Need;
use super::super::superimposed::SuperKind;
use super::super::{AxisHandle, InstructionHandle, MotionTask};
use super::RampRun;
use crate::jog::{Jog, JogError, MajOperands, MasOperands, Stop};
use crate::profile::{Limits, Profile, Sample, State};

impl MotionTask {
    /// MAJ: jogs `axis` at the operands' speed, from its current state.
    ///
    /// # Errors
    /// ERR 13 with EXERR = the operand; the axis-state errors of
    /// [`crate::servo`] (ERR 9 for a jog further beyond an exceeded soft
    /// travel limit).
    pub fn maj(
        &mut self,
        axis: AxisHandle,
        motion_control: InstructionHandle,
        operands: &MajOperands,
    ) -> Result<(), JogError> {
        let jog = Jog::new(operands, &self.axes[axis.0 as usize].config);
        let jog = self.begin_validated(motion_control, jog)?;
        self.state_allows(axis, motion_control, Need::Motion)?;
        if jog.velocity != 0.0
            && let Err(e) = self.check_overtravel(axis, jog.velocity)
        {
            self.fail(motion_control, e.err(), 0, 0);
            return Err(JogError::State(e));
        }
        self.fold_superimposed(axis);
        self.abort_move(axis);
        self.end_cams(axis);
        self.end_gear(axis);
        self.end_ramp(axis);
        let state = self.axes[axis.0 as usize].command.state();
        self.cam_axis(axis).ramp = Some(RampRun {
            jog: Some(motion_control),
            ..RampRun::new(Profile::to_velocity(state, jog.velocity, &jog.limits))
        });
        let b = self.bits(motion_control);
        b.dn = true;
        b.ip = true;
        Ok(())
    }

    /// MAS: stops what the Stop Type names on `axis` and ramps it to rest.
    ///
    /// # Errors
    /// ERR 13 with EXERR = the operand.
    pub fn mas(
        &mut self,
        axis: AxisHandle,
        motion_control: InstructionHandle,
        operands: &MasOperands,
    ) -> Result<(), JogError> {
        let stop = Stop::new(operands, &self.axes[axis.0 as usize].config);
        let stop = self.begin_validated(motion_control, stop)?;
        self.state_allows(axis, motion_control, Need::Any)?;
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
        self.bits(motion_control).dn = true;
        let state = self.axes[axis.0 as usize].command.state();
        if !stops || state.velocity == 0.0 {
            if stops {
                self.axes[axis.0 as usize].command = Sample {
                    position: state.position,
                    ..Sample::default()
                };
            }
            self.bits(motion_control).pc = true;
            return Ok(());
        }
        let vmax = self.axes[axis.0 as usize].config.max_velocity.max(state.velocity.abs());
        let limits = Limits::trapezoidal(vmax, stop.deceleration, stop.deceleration).map_err(|_| {
            JogError::ParameterOutOfRange {
                operand: crate::catalogue::MAS.exerr("Decel Rate"),
                value: stop.deceleration,
            }
        })?;
        let state = State {
            acceleration: 0.0,
            ..state
        };
        self.end_ramp(axis);
        self.cam_axis(axis).ramp = Some(RampRun {
            stop: Some(motion_control),
            ..RampRun::new(Profile::to_velocity(state, 0.0, &limits))
        });
        self.bits(motion_control).ip = true;
        Ok(())
    }
}
