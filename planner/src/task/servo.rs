//! Axis states in the motion task: MSO, MSF, MASD, MASR, MAFR, MCSD and
//! MCSR, the state check every motion instruction makes, and the planner's
//! fault detection (Excessive Position Error). The rules are in
//! [`crate::servo`].
//!
//! Each instruction executes inside its call (one scan of its rung): `.EN`
//! set, then `.DN` or `.ER` at once — except MSO from servo-off, whose
//! `.DN` comes when the loop is closed [`SERVO_ENABLE_UPDATES`] coarse
//! updates later (or after the axis' `servo_enable_delay_s`, the holding
//! brake's release time, when that is longer).
//!
//! Disabling an axis (MSF, MASD, MCSD, a fault with action Stop Drive or
//! Shutdown) ends every motion process on it at once, without a ramp —
//! the drive no longer follows a command: MC_MoveModulo commands get
//! `CommandAborted`; jogs, stop ramps and cams end (`.IP` off, no `.PC`);
//! coordinated motion of the systems holding the axis is cancelled (`.IP`
//! off); MCT transforms on the axis are cancelled. While the servo is off
//! the command follows the fed actual position.

use super::MotionTask;
use crate::instruction::{MotionInstructionBits, NoFault, Refusal};
use crate::profile::{Limits, Profile, Sample};
use crate::servo::{
    AxisFaults, AxisStatusBits, AxisType, CipAxisState, FaultAction, MOVING_FRACTION, MotionFaults,
    SERVO_ENABLE_UPDATES, StateError,
};
use crate::task::engine::SuperKind;
use crate::task::engine::{Need, Power};
use crate::task::handles::{AxisHandle, CoordHandle, InstructionHandle};

impl MotionTask {
    /// The axis' `CIPAxisState`.
    pub fn cip_axis_state(&self, axis: AxisHandle) -> CipAxisState {
        let a = &self.axes[axis.0 as usize];
        if a.config.inhibited {
            return CipAxisState::AxisInhibited;
        }
        match a.servo.power {
            Power::Off => CipAxisState::Stopped,
            Power::Starting(..) => CipAxisState::Starting,
            Power::On => CipAxisState::Running,
            Power::Faulted => CipAxisState::Faulted,
            Power::Shutdown => CipAxisState::Shutdown,
        }
    }

    /// Whether the axis' servo loop is closed (it follows its command).
    pub fn is_servo_on(&self, axis: AxisHandle) -> bool {
        let a = &self.axes[axis.0 as usize];
        !a.config.inhibited && a.servo.power == Power::On
    }

    /// Whether the axis' drive holds a position (on, or enabling).
    pub fn is_drive_enabled(&self, axis: AxisHandle) -> bool {
        let a = &self.axes[axis.0 as usize];
        !a.config.inhibited && matches!(a.servo.power, Power::On | Power::Starting(..))
    }

    /// The `AxisFault` word.
    pub fn axis_faults(&self, axis: AxisHandle) -> AxisFaults {
        self.axes[axis.0 as usize].servo.faults
    }

    /// The `MotionFault` word (soft overtravel, [`crate::servo`]).
    pub fn motion_faults(&self, axis: AxisHandle) -> MotionFaults {
        self.axes[axis.0 as usize].servo.motion_faults
    }

    /// Whether a motion of `axis` in `direction` (its sign: + positive, −
    /// negative, 0 either way) would go further beyond a soft travel limit
    /// the axis has exceeded: ERR 9 ([`crate::servo`]).
    pub(super) fn check_overtravel(&self, axis: AxisHandle, direction: f64) -> Result<(), StateError> {
        let a = &self.axes[axis.0 as usize];
        if a.config.soft_travel_limits.is_none() || a.config.soft_overtravel_action == FaultAction::Ignore {
            return Ok(());
        }
        // Recorded, or beyond a limit now.
        let out = MotionFaults(
            a.servo.motion_faults.0 | MotionFaults::beyond(a.config.soft_travel_limits, a.actual).unwrap_or(0),
        );
        if (out.positive() && direction >= 0.0) || (out.negative() && direction <= 0.0) {
            return Err(StateError::Overtravel);
        }
        Ok(())
    }

    /// Whether the axis' position error (command − actual) exceeded its
    /// `position_error_tolerance` in the last update.
    pub fn position_error_exceeded(&self, axis: AxisHandle) -> bool {
        self.axes[axis.0 as usize].servo.position_error_exceeded
    }

    /// The axis-status and motion-status bits after the last update.
    pub fn axis_status(&self, axis: AxisHandle) -> AxisStatusBits {
        let a = &self.axes[axis.0 as usize];
        let real_drive = a.config.axis_type == AxisType::Servo;
        let moving = a.job.as_ref().is_some_and(|j| !j.generation_done && !j.stopping) || a.buffered.is_some();
        let (jogging, ramp_stopping, mam) = self.jog_and_stop_status(axis);
        let sup = self.superimposed_moving(axis);
        let moving = moving || mam || sup == Some(SuperKind::Move);
        let jogging = jogging || sup == Some(SuperKind::Jog);
        AxisStatusBits {
            servo_action: self.is_servo_on(axis),
            drive_enable: real_drive && self.is_drive_enabled(axis),
            shutdown: a.servo.power == Power::Shutdown,
            inhibit: a.config.inhibited,
            homed: a.servo.homed,
            homing: a.servo.homing.is_some(),
            moving,
            jogging,
            gearing: a.gear.is_some(),
            stopping: ramp_stopping || a.job.as_ref().is_some_and(|j| j.stopping),
        }
    }

    /// Whether `axis` may do what `need` asks in its state.
    pub(super) fn check_state(&self, axis: AxisHandle, need: Need) -> Result<(), StateError> {
        let a = &self.axes[axis.0 as usize];
        if a.config.inhibited {
            return Err(StateError::Inhibited);
        }
        let feedback_only = a.config.axis_type == AxisType::FeedbackOnly;
        match need {
            Need::Any => Ok(()),
            Need::Disable if feedback_only => Err(StateError::AxisType),
            Need::Disable => Ok(()),
            Need::Enable | Need::Motion if feedback_only => Err(StateError::AxisType),
            Need::Enable | Need::Motion if a.servo.power == Power::Shutdown => Err(StateError::Shutdown),
            Need::Motion if a.servo.homing.is_some() => Err(StateError::Homing),
            Need::Motion if a.servo.power != Power::On => Err(StateError::ServoOff),
            Need::Motion => Ok(()),
            Need::Enable => match a.servo.power {
                Power::Faulted => Err(StateError::Faulted),
                Power::Off if a.actual_velocity.abs() > MOVING_FRACTION * a.config.max_velocity => {
                    Err(StateError::InMotion)
                }
                _ => Ok(()),
            },
        }
    }

    /// The first axis of coordinate system `cs` (by its index in the
    /// system) that cannot start motion, with the reason: ERR and EXERR of
    /// a coordinated instruction.
    pub(super) fn check_system_state(&self, cs: CoordHandle) -> Result<(), (StateError, i32)> {
        for (i, &axis) in self.coord_axes(cs).iter().enumerate() {
            self.check_state(axis, Need::Motion).map_err(|e| (e, i as i32))?;
        }
        Ok(())
    }

    /// Starts an execution of a state instruction: `.EN` set, the other
    /// bits and codes cleared.
    pub(super) fn begin_state(&mut self, control: InstructionHandle) {
        *self.motion_bits_mut(control) = MotionInstructionBits {
            en: true,
            ..MotionInstructionBits::default()
        };
    }

    pub(super) fn state_result(
        &mut self,
        control: InstructionHandle,
        r: Result<(), StateError>,
    ) -> Result<(), StateError> {
        let b = self.motion_bits_mut(control);
        match r {
            Ok(()) => b.dn = true,
            Err(e) => b.set_error(e.err(), 0, 0),
        }
        r
    }

    /// MSO (Motion Servo On): closes the servo loop of `axis` at its
    /// current position; `.DN` once it is closed.
    ///
    /// # Errors
    /// ERR 8 (feedback-only), 7 (shut down), 20 (faulted), 22 (servo off and
    /// moving), 53 (inhibited).
    pub(crate) fn mso(&mut self, axis: AxisHandle, control: InstructionHandle) -> Result<(), StateError> {
        self.begin_state(control);
        if let Err(e) = self.check_state(axis, Need::Enable) {
            return self.state_result(control, Err(e));
        }
        let dt_s = self.dt_s;
        let a = &mut self.axes[axis.0 as usize];
        if a.servo.power != Power::Off {
            // Already on or enabling: nothing changes.
            return self.state_result(control, Ok(()));
        }
        let delay_updates = (a.config.servo_enable_delay_s / dt_s).ceil() as u32;
        a.servo.power = Power::Starting(Some(control), SERVO_ENABLE_UPDATES.max(delay_updates));
        a.command = Sample {
            position: a.actual,
            ..Sample::default()
        };
        Ok(())
    }

    /// MSF (Motion Servo Off): opens the servo loop of `axis` and disables
    /// its drive; every motion process on it ends at once.
    ///
    /// # Errors
    /// ERR 8 (feedback-only), 53 (inhibited).
    pub(crate) fn msf(&mut self, axis: AxisHandle, control: InstructionHandle) -> Result<(), StateError> {
        self.begin_state(control);
        let r = self.check_state(axis, Need::Disable);
        if r.is_ok() {
            let a = &mut self.axes[axis.0 as usize];
            if matches!(a.servo.power, Power::On | Power::Starting(..)) && a.config.axis_type == AxisType::Servo {
                self.disable(axis, Power::Off);
            }
        }
        self.state_result(control, r)
    }

    /// MASD (Motion Axis Shutdown): ends every motion process on `axis`,
    /// disables its drive and puts it in the Shutdown state.
    ///
    /// # Errors
    /// ERR 53 (inhibited).
    pub(crate) fn masd(&mut self, axis: AxisHandle, control: InstructionHandle) -> Result<(), StateError> {
        self.begin_state(control);
        let r = self.check_state(axis, Need::Any);
        if r.is_ok() {
            self.break_master_links_of_axis(axis);
            self.disable(axis, Power::Shutdown);
        }
        self.state_result(control, r)
    }

    /// MASR (Motion Axis Shutdown Reset): a shut-down axis leaves Shutdown
    /// servo-off (Stopped); a virtual one is on again. The fault word is
    /// cleared too. On an axis not shut down it does nothing.
    ///
    /// # Errors
    /// ERR 53 (inhibited).
    pub(crate) fn masr(&mut self, axis: AxisHandle, control: InstructionHandle) -> Result<(), StateError> {
        self.begin_state(control);
        let r = self.check_state(axis, Need::Any);
        if r.is_ok() {
            self.shutdown_reset(axis);
        }
        self.state_result(control, r)
    }

    /// MAFR (Motion Axis Fault Reset): clears the `AxisFault` word; an axis
    /// a fault had disabled is servo-off (Stopped) — MSO to enable it. A
    /// shut-down axis stays shut down.
    ///
    /// # Errors
    /// ERR 53 (inhibited).
    pub(crate) fn mafr(&mut self, axis: AxisHandle, control: InstructionHandle) -> Result<(), StateError> {
        self.begin_state(control);
        let r = self.check_state(axis, Need::Any);
        if r.is_ok() {
            let a = &mut self.axes[axis.0 as usize];
            a.servo.faults = AxisFaults::default();
            a.servo.motion_faults = MotionFaults::default();
            a.servo.position_error_exceeded = false;
            if a.servo.power == Power::Faulted {
                a.servo.power = if a.config.axis_type == AxisType::Virtual {
                    Power::On
                } else {
                    Power::Off
                };
            }
        }
        self.state_result(control, r)
    }

    /// MCSD (Motion Coordinated Shutdown): MASD on every axis of `system`.
    /// Its coordinated motion is cancelled with them.
    ///
    /// # Errors
    /// ERR 53 with EXERR = the index of the first inhibited axis; no axis
    /// is shut down then.
    pub(crate) fn mcsd(&mut self, system: CoordHandle, control: InstructionHandle) -> Result<(), Refusal<NoFault>> {
        self.begin_state(control);
        let axes = self.coord_axes(system).to_vec();
        if let Some(r) = self.first_inhibited(&axes, control) {
            return r;
        }
        self.break_master_link(system);
        for axis in axes {
            self.disable(axis, Power::Shutdown);
        }
        self.motion_bits_mut(control).dn = true;
        Ok(())
    }

    /// MCSR (Motion Coordinated Shutdown Reset): MASR on every axis of
    /// `system`.
    ///
    /// # Errors
    /// ERR 53 with EXERR = the index of the first inhibited axis.
    pub(crate) fn mcsr(&mut self, system: CoordHandle, control: InstructionHandle) -> Result<(), Refusal<NoFault>> {
        self.begin_state(control);
        let axes = self.coord_axes(system).to_vec();
        if let Some(r) = self.first_inhibited(&axes, control) {
            return r;
        }
        for axis in axes {
            self.shutdown_reset(axis);
        }
        self.motion_bits_mut(control).dn = true;
        Ok(())
    }

    fn first_inhibited(
        &mut self,
        axes: &[AxisHandle],
        control: InstructionHandle,
    ) -> Option<Result<(), Refusal<NoFault>>> {
        let i = axes.iter().position(|a| self.axes[a.0 as usize].config.inhibited)?;
        let e = StateError::Inhibited;
        self.motion_bits_mut(control).set_error(e.err(), i as i32, 0);
        Some(Err(Refusal::State {
            state: e,
            exerr: i as i32,
        }))
    }

    pub(super) fn shutdown_reset(&mut self, axis: AxisHandle) {
        let a = &mut self.axes[axis.0 as usize];
        if a.servo.power == Power::Shutdown {
            a.servo.faults = AxisFaults::default();
            a.servo.motion_faults = MotionFaults::default();
            a.servo.position_error_exceeded = false;
            a.servo.power = if a.config.axis_type == AxisType::Virtual {
                Power::On
            } else {
                Power::Off
            };
        }
    }

    /// Disables `axis` into `to` (Off, Faulted, Shutdown): every motion
    /// process on it ends now, and a pending MSO fails.
    pub(super) fn disable(&mut self, axis: AxisHandle, to: Power) {
        if let Power::Starting(Some(control), _) = self.axes[axis.0 as usize].servo.power {
            let b = self.motion_bits_mut(control);
            let e = if to == Power::Shutdown {
                StateError::Shutdown
            } else {
                StateError::ServoOff
            };
            b.set_error(e.err(), 0, 0);
        }
        self.end_all_motion(axis);
        self.end_homing(axis);
        let a = &mut self.axes[axis.0 as usize];
        a.servo.power = to;
        a.command = Sample {
            position: a.actual,
            ..Sample::default()
        };
    }

    /// Ends every motion process on `axis` at once (no ramp).
    pub(super) fn end_all_motion(&mut self, axis: AxisHandle) {
        self.fold_superimposed(axis);
        self.release_cam_and_jog(axis);
        self.abort_modulo_commands(axis);
        self.cancel_systems_with_axis(axis);
        self.mct_cancel_on_axis(axis);
    }

    /// Step 3b of an update: enabling axes count down (MSO `.DN` when the
    /// loop closes), servo-off axes' commands follow their actual
    /// positions, and the position error of servo-on axes is checked.
    pub(super) fn advance_servo_states(&mut self) {
        for i in 0..self.axes.len() {
            let axis = AxisHandle(i as u32);
            let a = &mut self.axes[i];
            match a.servo.power {
                Power::Starting(control, left) => {
                    if left > 1 {
                        a.servo.power = Power::Starting(control, left - 1);
                    } else {
                        a.servo.power = Power::On;
                        if let Some(control) = control {
                            self.motion_bits_mut(control).dn = true;
                            self.rung_false_next_scan(control);
                        }
                    }
                }
                Power::On => {
                    self.check_position_error(axis);
                    self.check_soft_overtravel(axis);
                }
                Power::Off | Power::Faulted | Power::Shutdown => {
                    if a.fed {
                        a.command = Sample {
                            position: a.actual,
                            velocity: a.actual_velocity,
                            ..Sample::default()
                        };
                    }
                    if a.config.axis_type == AxisType::FeedbackOnly {
                        self.check_soft_overtravel(axis);
                    }
                }
            }
        }
    }

    /// Excessive Position Error: |command − actual| above the axis'
    /// `position_error_tolerance` records [`AxisFaults::MOTION`] and takes
    /// the axis' `position_error_action`.
    fn check_position_error(&mut self, axis: AxisHandle) {
        let a = &mut self.axes[axis.0 as usize];
        let Some(tolerance) = a.config.position_error_tolerance else {
            return;
        };
        let exceeded = a.fed && (a.command.position - a.actual).abs() > tolerance;
        let rising = exceeded && !a.servo.position_error_exceeded;
        a.servo.position_error_exceeded = exceeded;
        if !rising {
            return;
        }
        let action = a.config.position_error_action;
        if action != FaultAction::Ignore {
            a.servo.faults.0 |= AxisFaults::MOTION;
        }
        self.take_action(axis, action);
    }

    /// Soft overtravel ([`crate::servo`]): the actual position beyond a
    /// soft travel limit while the command moves further out (a
    /// feedback-only axis: whenever it is outside) raises the side's
    /// exception once and takes the axis' `soft_overtravel_action`.
    fn check_soft_overtravel(&mut self, axis: AxisHandle) {
        let a = &self.axes[axis.0 as usize];
        let Some(bit) = MotionFaults::beyond(a.config.soft_travel_limits, a.actual) else {
            return;
        };
        let v = a.command.velocity;
        let outward = if bit == MotionFaults::SOFT_TRAVEL_POSITIVE {
            v > 0.0
        } else {
            v < 0.0
        };
        if outward || a.config.axis_type == AxisType::FeedbackOnly {
            self.raise_soft_overtravel(axis, bit);
        }
    }

    /// Records the soft overtravel exception `bit` (unless already
    /// recorded) and takes the axis' `soft_overtravel_action`.
    pub(super) fn raise_soft_overtravel(&mut self, axis: AxisHandle, bit: u32) {
        let a = &mut self.axes[axis.0 as usize];
        let action = a.config.soft_overtravel_action;
        if action == FaultAction::Ignore || a.servo.motion_faults.0 & bit != 0 {
            return;
        }
        a.servo.motion_faults.0 |= bit;
        a.servo.faults.0 |= AxisFaults::MOTION;
        self.take_action(axis, action);
    }

    /// What a recorded fault does to the axis.
    fn take_action(&mut self, axis: AxisHandle, action: FaultAction) {
        match action {
            FaultAction::Ignore | FaultAction::Alarm | FaultAction::FaultStatusOnly => {}
            FaultAction::StopPlanner => self.stop_planner(axis),
            FaultAction::StopDrive => self.disable(axis, Power::Faulted),
            FaultAction::Shutdown => self.disable(axis, Power::Shutdown),
        }
    }

    /// A fault's Stop Planner action: every motion process on the axis
    /// ends and the command ramps to rest at the axis' maximum deceleration
    /// (the servo stays on).
    pub(super) fn stop_planner(&mut self, axis: AxisHandle) {
        let state = self.axes[axis.0 as usize].command.state();
        self.end_all_motion(axis);
        let cfg = &self.axes[axis.0 as usize].config;
        let vmax = cfg.max_velocity.max(state.velocity.abs());
        let profile = match Limits::trapezoidal(vmax, cfg.max_deceleration, cfg.max_deceleration) {
            Ok(limits) => Profile::to_velocity(state, 0.0, &limits),
            Err(_) => Profile::hold(state),
        };
        self.start_stop_ramp(axis, profile);
    }
}

#[cfg(test)]
mod tests;
