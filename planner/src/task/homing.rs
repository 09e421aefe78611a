//! The homing process of an axis, which MAH starts. The rules, and
//! what the twin does not simulate, are in [`crate::homing`].

use super::MotionTask;
use crate::homing::HomeMode;
use crate::servo::StateError;
use crate::task::engine::Finish;
use crate::task::engine::Need;
use crate::task::handles::{AxisHandle, InstructionHandle};

impl MotionTask {
    /// MAH (Motion Axis Home) on `axis` with its configured homing
    /// ([`crate::axis::AxisConfig::homing`]): `.DN` when accepted, `.PC`
    /// and `AxisHomedStatus` when the axis is homed — at once from rest,
    /// after the cancelled motion has come to rest otherwise (`.IP` and
    /// `HomingStatus` meanwhile).
    ///
    /// # Errors
    /// Active homing: ERR 53 (inhibited), 8 (feedback-only), 7 (shut down),
    /// 16 (already homing), 5 (servo off). Passive: ERR 53, 16.
    pub(crate) fn mah(&mut self, axis: AxisHandle, control: InstructionHandle) -> Result<(), StateError> {
        self.begin_state(control);
        let homing = self.axes[axis.0 as usize].config.homing;
        let need = match homing.mode {
            HomeMode::Active => Need::Motion,
            HomeMode::Passive => Need::Any,
        };
        let mut r = self.check_state(axis, need);
        if r.is_ok() && self.axes[axis.0 as usize].servo.homing.is_some() {
            r = Err(StateError::Homing);
        }
        if r.is_err() {
            return self.state_result(control, r);
        }
        self.motion_bits_mut(control).dn = true;
        if homing.mode == HomeMode::Active && self.cancel_motion_for_homing(axis) {
            self.axes[axis.0 as usize].servo.homing = Some(control);
            self.motion_bits_mut(control).ip = true;
            return Ok(());
        }
        self.home(axis, control);
        Ok(())
    }

    /// Cancels every motion process on `axis` for an active homing (module
    /// doc of [`crate::homing`]); returns whether the axis is still moving.
    fn cancel_motion_for_homing(&mut self, axis: AxisHandle) -> bool {
        let a = &mut self.axes[axis.0 as usize];
        let buffered = a.buffered.take().map(|(fb, _)| fb);
        let running = a.job.as_ref().and_then(|j| j.fb);
        self.ramp_to_rest(axis);
        for fb in running.into_iter().chain(buffered) {
            self.finish(fb, Finish::Aborted);
        }
        self.stop_cam_and_jog(axis);
        self.stop_superimposed(axis);
        self.mct_cancel_on_axis(axis);
        self.stop_systems_with_axis(axis);
        !self.at_rest(axis)
    }

    /// Whether `axis` stands still with no stop, superimposed or
    /// coordinated motion moving it.
    pub(super) fn at_rest(&self, axis: AxisHandle) -> bool {
        let a = &self.axes[axis.0 as usize];
        a.command.velocity == 0.0
            && !self.is_stopping(axis)
            && self.superimposed_moving(axis).is_none()
            && !self.coordinated_motion_status(axis)
    }

    /// The immediate sequence: the axis position becomes `HomePosition`.
    fn home(&mut self, axis: AxisHandle, control: InstructionHandle) {
        let a = &self.axes[axis.0 as usize];
        let delta = a.config.homing.position - a.actual;
        self.redefine_position(axis, delta);
        let a = &mut self.axes[axis.0 as usize];
        a.servo.homing = None;
        a.servo.homed = true;
        let b = self.motion_bits_mut(control);
        b.ip = false;
        b.pc = true;
    }

    /// A disable ends a homing in process: `.IP` off, no `.PC`.
    pub(super) fn end_homing(&mut self, axis: AxisHandle) {
        if let Some(control) = self.axes[axis.0 as usize].servo.homing.take() {
            self.motion_bits_mut(control).ip = false;
        }
    }

    /// Step of an update: a homing axis that has come to rest is homed.
    pub(super) fn advance_homing(&mut self) {
        for i in 0..self.axes.len() {
            let axis = AxisHandle(i as u32);
            if let Some(control) = self.axes[i].servo.homing
                && self.at_rest(axis)
            {
                self.home(axis, control);
            }
        }
    }
}
