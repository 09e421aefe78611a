//! Stops the task commands from outside the program: a coordinated stop of
//! every axis (the twin's reaction to a collision, like MCS/MAS "all" or
//! PLCopen MC_Stop on every axis), and the rejection of a move that has just
//! started (the twin's pre-flight sweep).
//!
//! Choices the specs leave open:
//! * The stop ramp of an axis uses the axis' configured `max_deceleration`
//!   and `max_jerk` (an S-curve ramp to zero velocity from the command state
//!   of the last update, [`Profile::to_velocity`]); the ramp starts at the
//!   next [`MotionTask::update`], as a PLC sees a stop request at the start
//!   of its cycle.
//! * The instance running on the axis and one waiting in its buffer get
//!   `CommandAborted` (PLCopen: "the axis was stopped"); a stop of an axis at
//!   rest aborts nothing. The stop ramp belongs to no instance.
//! * A stop is not latched: a command started after it (an `Aborting` one
//!   at once, a buffered one when the ramp has ended and the axis is in
//!   position) runs normally, as after an MC_Stop whose `Execute` has fallen.
//!   A buffered or blending command never blends into a stop ramp.
//! * A rejected move ([`MotionTask::reject_move`]) sets the instance's
//!   `Error` with the given error. Rejected in the update it started in
//!   (the twin's pre-flight sweep runs right after that update, before the
//!   physics has applied any of it), the move leaves no trace: the axis'
//!   command state (position, velocity, acceleration, jerk), its direction
//!   memory and, when not fed back, its actual position are restored to
//!   the state the move started from; an axis that was at rest then stays
//!   exactly there (no stop ramp), one that was moving (the move aborted a
//!   running command) ramps to rest from that state. A move rejected in a
//!   later update, or one that took over in a blend hand-over, stops along
//!   the stop ramp from where its last update left it.
//!
//! * Logix control structures (`MOTION_INSTRUCTION` tags) in process
//!   (`.IP` set) get `.IP`, `.AC`, `.ACCEL` and `.DECEL` cleared without `.PC`,
//!   as when an MAS/MCS stops the motion they started (Logix sets no `.ER` on
//!   the stopped instruction); they are listed in [`StopReport`].
//!   Instructions that keep motion state of their own (MCCM, MCLM, …) stop it
//!   in this same function when they arrive.
//! * A running MCT transform is not cancelled and its control structure
//!   keeps `.IP`: its source system's coordinated motion comes to rest
//!   along its path, and the target joints follow it through the
//!   transform (like an MCS of type *coordinated move* on the source), so
//!   the tool stops on its programmed Cartesian path rather than the joints
//!   ramping each on its own.

use super::MotionTask;
use crate::modulo::MoveModuloError;
use crate::profile::{Limits, Profile};
use crate::task::engine::StopReport;
use crate::task::engine::{Finish, Job};
use crate::task::handles::{AxisHandle, FbHandle, InstructionHandle};

impl MotionTask {
    /// Coordinated stop of every axis with its configured deceleration and
    /// jerk; the running and buffered instances get `CommandAborted`.
    ///
    /// # Examples
    /// ```
    /// use planner::axis::{AxisConfig, AxisKind};
    /// use planner::modulo::MoveModuloInputs;
    /// use planner::task::MotionTask;
    /// let mut task = MotionTask::new(0.004).unwrap();
    /// let config = AxisConfig {
    ///     modulo_period: Some(360.0),
    ///     max_velocity: 180.0,
    ///     max_acceleration: 900.0,
    ///     max_deceleration: 900.0,
    ///     max_jerk: 9000.0,
    ///     ..AxisConfig::new("T", AxisKind::Rotary)
    /// };
    /// let axis = task.add_axis(config, 0.0).unwrap();
    /// let fb = task.add_move_modulo("Move", axis);
    /// task.set_move_modulo_inputs(fb, MoveModuloInputs { execute: true, position: 90.0, velocity: 90.0, ..Default::default() });
    /// for _ in 0..50 { task.update(); }
    /// let report = task.stop_all_axes();
    /// assert_eq!(report.aborted, vec![fb]);
    /// assert!(task.outputs(fb).command_aborted);
    /// ```
    pub fn stop_all_axes(&mut self) -> StopReport {
        let mut report = StopReport::default();
        for i in 0..self.axes.len() {
            let axis = AxisHandle(i as u32);
            let a = &mut self.axes[i];
            let buffered = a.buffered.take().map(|(fb, _)| fb);
            let running = a.job.as_ref().and_then(|j| j.fb);
            if self.ramp_to_rest(axis) {
                report.stopped_axes.push(axis);
            }
            for fb in running.into_iter().chain(buffered) {
                self.finish(fb, Finish::Aborted);
                report.aborted.push(fb);
            }
        }
        let transforms = self.running_mct_controls();
        for (i, slot) in self.instructions.iter_mut().enumerate() {
            let b = &mut slot.bits;
            if b.ip && !transforms.contains(&InstructionHandle(i as u32)) {
                b.ip = false;
                b.ac = false;
                b.accel = false;
                b.decel = false;
                report.stopped_instructions.push(InstructionHandle(i as u32));
            }
        }
        // Position cams and jogs (task/cam.rs) ramp to rest the same way.
        for i in 0..self.axes.len() {
            let axis = AxisHandle(i as u32);
            if self.stop_cam_and_jog(axis) && !report.stopped_axes.contains(&axis) {
                report.stopped_axes.push(axis);
            }
        }
        // Coordinated motion (task/coord.rs) comes to rest along its paths.
        for axis in self.stop_coordinated_motion() {
            if !report.stopped_axes.contains(&axis) {
                report.stopped_axes.push(axis);
            }
        }
        report
    }

    /// Rejects the move `fb` runs or waits with: the instance gets `Error`
    /// with `error`'s ErrorID. A move rejected in the update it started in
    /// is undone (the axis' command goes back to the state it started from
    /// and, from rest, stays there); otherwise its axis ramps to rest (see
    /// the module docs). Returns whether `fb` had a command (running or
    /// buffered) to reject.
    pub fn reject_move(&mut self, fb: FbHandle, error: MoveModuloError) -> bool {
        let updates = self.updates;
        let mut found = false;
        for i in 0..self.axes.len() {
            let a = &mut self.axes[i];
            if a.buffered.as_ref().is_some_and(|(b, _)| *b == fb) {
                a.buffered = None;
                found = true;
            }
            let Some(job) = a.job.as_ref().filter(|j| j.fb == Some(fb)) else {
                continue;
            };
            found = true;
            if let Some(o) = job.origin.filter(|o| o.update == updates) {
                a.command = o.command;
                a.last_direction = o.last_direction;
                if !a.fed {
                    a.actual = o.command.position;
                }
                if o.command.velocity == 0.0 && o.command.acceleration == 0.0 {
                    a.job = None;
                    continue;
                }
            }
            self.ramp_to_rest(AxisHandle(i as u32));
        }
        if found {
            self.finish(fb, Finish::Error(error));
        }
        found
    }

    /// Whether `axis` is ramping down after [`MotionTask::stop_all_axes`] or
    /// [`MotionTask::reject_move`].
    pub fn is_stopping(&self, axis: AxisHandle) -> bool {
        self.axes[axis.0 as usize]
            .job
            .as_ref()
            .is_some_and(|j| j.stopping && !j.generation_done)
            || self.is_ramping_to_rest(axis)
    }

    /// Whether any stop ramps `axis` now: a MAS (or a fault's) stop ramp,
    /// a stop of its single-axis command, or a coordinated stop of a system
    /// it belongs to. Motion commands (MC_MoveModulo) are refused meanwhile.
    pub fn stop_in_progress(&self, axis: AxisHandle) -> bool {
        self.is_stopping(axis) || self.coordinated_stop_with(axis)
    }

    /// Replaces the axis' command by a stop ramp from its command state.
    /// Returns false when the axis has no command (nothing to stop).
    pub(super) fn ramp_to_rest(&mut self, axis: AxisHandle) -> bool {
        let a = &mut self.axes[axis.0 as usize];
        let Some(job) = a.job.take() else {
            return false;
        };
        let c = &a.config;
        let limits = Limits::s_curve(
            c.max_velocity,
            c.max_acceleration,
            c.max_deceleration,
            c.max_jerk,
            c.max_jerk,
        )
        .or_else(|_| Limits::trapezoidal(c.max_velocity, c.max_acceleration, c.max_deceleration));
        let start = a.command.state();
        let profile = match limits {
            Ok(limits) => Profile::to_velocity(start, 0.0, &limits),
            // Validated configs always give limits; hold still otherwise.
            Err(_) => Profile::hold(start),
        };
        let target = profile.final_state().position;
        a.job = Some(Job {
            fb: None,
            command: job.command,
            profile,
            t_s: 0.0,
            target,
            generation_done: false,
            stopping: true,
            origin: None,
        });
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::axis::{AxisConfig, AxisKind};
    use crate::modulo::{ErrorId, McBufferMode, MoveModuloInputs};

    const DT: f64 = 0.004;
    const DECEL: f64 = 1800.0;

    fn setup() -> (MotionTask, AxisHandle, FbHandle, FbHandle) {
        let mut task = MotionTask::new(DT).unwrap();
        let config = AxisConfig {
            modulo_period: Some(360.0),
            max_velocity: 360.0,
            max_acceleration: 3600.0,
            max_deceleration: DECEL,
            max_jerk: 36000.0,
            in_position_window: 0.1,
            ..AxisConfig::new("Arm", AxisKind::Rotary)
        };
        let axis = task.add_axis(config, 0.0).unwrap();
        let a = task.add_move_modulo("MoveA", axis);
        let b = task.add_move_modulo("MoveB", axis);
        (task, axis, a, b)
    }

    fn go(position: f64, buffer_mode: McBufferMode) -> MoveModuloInputs {
        MoveModuloInputs {
            execute: true,
            position,
            velocity: 300.0,
            buffer_mode,
            ..Default::default()
        }
    }

    #[test]
    fn stop_aborts_running_and_buffered_and_ramps_within_the_deceleration() {
        let (mut task, axis, a, b) = setup();
        task.set_move_modulo_inputs(a, go(270.0, McBufferMode::Aborting));
        for _ in 0..60 {
            task.update();
        }
        task.set_move_modulo_inputs(b, go(10.0, McBufferMode::Buffered));
        task.update();
        assert!(task.outputs(b).busy && !task.outputs(b).active);
        let v0 = task.axis_state(axis).command_velocity;
        assert!(v0 > 100.0, "moving: {v0}");
        let report = task.stop_all_axes();
        assert_eq!(report.aborted, vec![a, b]);
        assert_eq!(report.stopped_axes, vec![axis]);
        for fb in [a, b] {
            let o = task.outputs(fb);
            assert!(
                o.command_aborted && !o.busy && !o.active && !o.done && !o.error,
                "{o:?}"
            );
        }
        assert!(task.is_stopping(axis));
        let mut previous = task.axis_state(axis);
        let mut updates = 0;
        while task.axis_state(axis).command_velocity != 0.0 || updates == 0 {
            task.update();
            updates += 1;
            let s = task.axis_state(axis);
            assert!(s.command_acceleration.abs() <= DECEL * (1.0 + 1e-9), "{s:?}");
            assert!(s.command_velocity >= 0.0 && s.command_velocity <= previous.command_velocity + 1e-9);
            assert!(
                (s.command_velocity - previous.command_velocity).abs() <= DECEL * DT * (1.0 + 1e-9),
                "finite differences stay within the deceleration"
            );
            previous = s;
            assert!(updates < 1000, "comes to rest");
        }
        // The aborted outputs stay while Execute stays TRUE.
        assert!(task.outputs(a).command_aborted);
        // A new move after the stop runs normally.
        task.set_move_modulo_inputs(
            a,
            MoveModuloInputs {
                execute: false,
                ..go(0.0, McBufferMode::Aborting)
            },
        );
        task.update();
        task.set_move_modulo_inputs(a, go(0.0, McBufferMode::Aborting));
        task.update();
        assert!(task.outputs(a).active);
    }

    #[test]
    fn stop_clears_in_process_logix_bits_without_pc() {
        let (mut task, _, _, _) = setup();
        let mc1 = task.add_instruction("MC1");
        let mc2 = task.add_instruction("MC2");
        *task.motion_bits_mut(mc1) = crate::instruction::MotionInstructionBits {
            en: true,
            dn: true,
            ip: true,
            ac: true,
            accel: true,
            ..Default::default()
        };
        *task.motion_bits_mut(mc2) = crate::instruction::MotionInstructionBits {
            en: true,
            dn: true,
            pc: true,
            ..Default::default()
        };
        let report = task.stop_all_axes();
        assert_eq!(report.stopped_instructions, vec![mc1]);
        let b = task.motion_bits(mc1);
        assert!(b.en && b.dn && !b.ip && !b.ac && !b.accel && !b.pc && !b.er, "{b:?}");
        assert!(task.motion_bits(mc2).pc, "a finished instruction keeps its bits");
    }

    #[test]
    fn stop_at_rest_aborts_nothing() {
        let (mut task, axis, _, _) = setup();
        task.update();
        let report = task.stop_all_axes();
        assert!(report.aborted.is_empty() && report.stopped_axes.is_empty());
        task.update();
        assert_eq!(task.axis_state(axis).command_position, 0.0);
    }

    fn state_bits(task: &MotionTask, axis: AxisHandle) -> [u64; 4] {
        let s = task.axis_state(axis);
        [
            s.command_position,
            s.command_velocity,
            s.command_acceleration,
            s.actual_position,
        ]
        .map(f64::to_bits)
    }

    #[test]
    fn a_move_rejected_in_its_first_update_leaves_the_axis_exactly_where_it_was() {
        let (mut task, axis, a, _) = setup();
        task.update();
        let before = state_bits(&task, axis);
        task.set_move_modulo_inputs(a, go(90.0, McBufferMode::Aborting));
        task.update();
        assert!(task.outputs(a).active);
        assert_ne!(state_bits(&task, axis), before, "the first setpoint was written");
        assert!(task.reject_move(a, MoveModuloError::PathCollision));
        assert_eq!(state_bits(&task, axis), before, "undone at once");
        let o = task.outputs(a);
        assert!(
            o.error && !o.busy && !o.active && !o.command_aborted && !o.done,
            "{o:?}"
        );
        assert_eq!(o.error_id, ErrorId::PATH_COLLISION.0);
        assert!(!task.is_stopping(axis), "no stop ramp");
        for _ in 0..100 {
            task.update();
            assert_eq!(state_bits(&task, axis), before);
        }
        assert!(task.outputs(a).error, "Error stays while Execute stays TRUE");
        assert!(
            !task.reject_move(a, MoveModuloError::PathCollision),
            "nothing left to reject"
        );
    }

    #[test]
    fn a_move_rejected_later_ramps_to_rest_from_where_it_is() {
        let (mut task, axis, a, _) = setup();
        task.set_move_modulo_inputs(a, go(90.0, McBufferMode::Aborting));
        for _ in 0..20 {
            task.update();
        }
        let p0 = task.axis_state(axis).command_position;
        assert!(task.reject_move(a, MoveModuloError::PathCollision));
        assert!(task.outputs(a).error && task.is_stopping(axis));
        for _ in 0..200 {
            task.update();
        }
        let s = task.axis_state(axis);
        assert_eq!(s.command_velocity, 0.0);
        assert!(s.command_position > p0 && s.command_position < 90.0, "{s:?}");
    }

    #[test]
    fn a_move_aborting_a_moving_one_rejected_in_its_first_update_ramps_from_the_old_state() {
        let (mut task, axis, a, b) = setup();
        task.set_move_modulo_inputs(a, go(270.0, McBufferMode::Aborting));
        for _ in 0..100 {
            task.update();
        }
        let moving = task.axis_state(axis);
        assert!(
            moving.command_velocity > 100.0 && moving.command_acceleration == 0.0,
            "cruising: {moving:?}"
        );
        task.set_move_modulo_inputs(b, go(10.0, McBufferMode::Aborting));
        task.update();
        assert!(task.outputs(a).command_aborted && task.outputs(b).active);
        assert!(task.reject_move(b, MoveModuloError::PathCollision));
        let s = task.axis_state(axis);
        assert_eq!(
            (s.command_position, s.command_velocity),
            (moving.command_position, moving.command_velocity),
            "back to the state B started from"
        );
        assert!(task.is_stopping(axis));
        let mut v = s.command_velocity;
        for _ in 0..300 {
            task.update();
            let now = task.axis_state(axis).command_velocity;
            assert!(now >= 0.0 && now <= v + 1e-9 && (v - now) / DT <= DECEL * (1.0 + 1e-9));
            v = now;
        }
        assert_eq!(v, 0.0);
    }
}
