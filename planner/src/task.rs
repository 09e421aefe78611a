//! The coarse-update executor: a motion task that owns axes and instruction
//! instances and advances them one coarse update (`dt`) at a time.
//!
//! Each [`MotionTask::update`]:
//! 1. evaluates every instance's inputs in the order the instances were
//!    added (rising edges of `Execute` start, buffer or abort commands;
//!    falling edges clear finished outputs);
//! 2. advances every axis' active command by `dt` and samples its profile
//!    (the command setpoint); a blended command hands over to the buffered
//!    one inside the update, at the exact hand-over time;
//! 3. takes the actual position — the last one fed with
//!    [`MotionTask::feed_actual_position`], or the new command position for an
//!    axis never fed (an ideal drive) — and updates `Done` (target position
//!    monitoring), starting a buffered command when its predecessor is done;
//! 4. (MCT, `task/mct.rs`) after the coordinate systems have moved, every
//!    active transform moves the side that did not move;
//!
//! Around steps 2–4 the superimposed offsets (`task/superimposed.rs`) are
//! taken out of the commands and added back.
//!
//! 5. (axis states, `task/servo.rs`) an MSO in process counts down, the
//!    command of a servo-off axis follows its actual position, and the
//!    position error of a servo-on axis is checked against its tolerance.
//!
//! Nothing here reads a clock: time advances only through `update`, so the
//! same calls give bit-identical setpoints.

use crate::axis::{AxisConfig, AxisConfigError, AxisLimit, AxisState};
use crate::instruction::{FbOutputs, MotionInstructionBits};
use crate::modulo::{McBufferMode, MoveModulo, MoveModuloError, MoveModuloInputs};
use crate::profile::{Profile, Sample, State};
use engine::{
    AxisSlot, CamState, CoordState, FbSlot, Finish, InstructionSlot, Job, MctState, Need, Origin, Phase, ServoSlot,
};
use thiserror::Error;

pub mod args;
pub mod instructions;

mod engine;
mod handles;

mod cam;
mod coord;
pub mod group;
mod homing;
mod mct;
pub mod output_cam;
mod servo;
mod stop;
mod superimposed;

pub use args::{Arg, Args};
pub(crate) use engine::RampRun;
pub use engine::{
    CoordCall, CoordSetupError, ERR_IDLE_MASTER_SLAVE_MOVING, ERR_PATH_COLLISION, LimitFlags, MapcCall, MotionTask,
    StartedCoordMove, StopReport, TransformGeometry,
};
pub use handles::{AxisHandle, CamProfileHandle, CoordHandle, CoordInstructionHandle, FbHandle, InstructionHandle};

/// Why a task, axis or instance cannot be set up.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum TaskError {
    /// The coarse update period must be finite and in (0, 1] s.
    #[error("coarse update period {dt_s} s must be finite and in (0, 1] s")]
    Period {
        /// The period given.
        dt_s: f64,
    },
    /// An axis configuration is invalid.
    #[error("axis '{name}': {source}")]
    Axis {
        /// Axis name.
        name: String,
        /// What is wrong.
        #[source]
        source: AxisConfigError,
    },
}

impl MotionTask {
    /// A task with coarse update period `dt_s` seconds.
    ///
    /// # Errors
    /// [`TaskError::Period`] unless 0 < `dt_s` ≤ 1.
    pub fn new(dt_s: f64) -> Result<Self, TaskError> {
        if !(dt_s.is_finite() && dt_s > 0.0 && dt_s <= 1.0) {
            return Err(TaskError::Period { dt_s });
        }
        Ok(Self {
            dt_s,
            updates: 0,
            axes: Vec::new(),
            fbs: Vec::new(),
            instructions: Vec::new(),
            coord: CoordState::default(),
            cam: CamState::default(),
            mct: MctState::default(),
            superimposed_removed: false,
            group: Default::default(),
            output: None,
        })
    }

    /// The coarse update period in seconds.
    pub fn dt_s(&self) -> f64 {
        self.dt_s
    }

    /// Time of the last update: `updates × dt` seconds (exact multiple, no
    /// accumulated rounding).
    pub fn time_s(&self) -> f64 {
        self.updates as f64 * self.dt_s
    }

    /// Number of updates run so far.
    pub fn updates(&self) -> u64 {
        self.updates
    }

    /// Adds an axis at rest at `initial_position` (axis units).
    ///
    /// # Errors
    /// [`TaskError::Axis`] when the configuration or the position is invalid
    /// (not finite or past [`crate::axis::MAX_POSITION`], or outside the
    /// axis' soft travel limits).
    pub fn add_axis(&mut self, config: AxisConfig, initial_position: f64) -> Result<AxisHandle, TaskError> {
        let err = |source| TaskError::Axis {
            name: config.name.clone(),
            source,
        };
        config.validate().map_err(err)?;
        if !crate::axis::position_in_reach(initial_position) {
            return Err(err(AxisConfigError::InitialPosition {
                value: initial_position,
            }));
        }
        config.check_soft_travel_limits(initial_position).map_err(err)?;
        self.axes.push(AxisSlot {
            servo: ServoSlot::new(&config),
            superimposed: None,
            gear: None,
            config,
            command: Sample {
                position: initial_position,
                ..Sample::default()
            },
            actual: initial_position,
            actual_velocity: 0.0,
            fed: false,
            last_direction: 1.0,
            job: None,
            buffered: None,
            registration: Default::default(),
            watch: Default::default(),
            output_cams: Vec::new(),
        });
        Ok(AxisHandle(self.axes.len() as u32 - 1))
    }

    /// Adds an MC_MoveModulo instance named `name` acting on `axis`.
    pub fn add_move_modulo(&mut self, name: impl Into<String>, axis: AxisHandle) -> FbHandle {
        self.fbs.push(FbSlot {
            name: name.into(),
            axis,
            inputs: MoveModuloInputs::default(),
            previous_execute: false,
            outputs: FbOutputs::default(),
            phase: Phase::Idle,
        });
        FbHandle(self.fbs.len() as u32 - 1)
    }

    /// The axis an MC_MoveModulo instance acts on.
    pub fn fb_axis(&self, fb: FbHandle) -> AxisHandle {
        self.fbs[fb.0 as usize].axis
    }

    /// Sets an instance's inputs (a call of the block); they are evaluated at
    /// the next [`MotionTask::update`] and stay until set again.
    pub fn set_move_modulo_inputs(&mut self, fb: FbHandle, inputs: MoveModuloInputs) {
        self.fbs[fb.0 as usize].inputs = inputs;
    }

    /// An instance's current inputs.
    pub fn move_modulo_inputs(&self, fb: FbHandle) -> MoveModuloInputs {
        self.fbs[fb.0 as usize].inputs
    }

    /// An instance's outputs after the last update.
    pub fn outputs(&self, fb: FbHandle) -> FbOutputs {
        self.fbs[fb.0 as usize].outputs
    }

    /// An instance's name.
    pub fn fb_name(&self, fb: FbHandle) -> &str {
        &self.fbs[fb.0 as usize].name
    }

    /// Every instance, in the order added.
    pub fn fb_handles(&self) -> impl Iterator<Item = FbHandle> + use<> {
        (0..self.fbs.len() as u32).map(FbHandle)
    }

    /// Adds a Logix control structure (`MOTION_INSTRUCTION` tag) named
    /// `name`, all bits clear.
    pub fn add_instruction(&mut self, name: impl Into<String>) -> InstructionHandle {
        self.instructions.push(InstructionSlot {
            name: name.into(),
            bits: MotionInstructionBits::default(),
            scanned: false,
        });
        InstructionHandle(self.instructions.len() as u32 - 1)
    }

    /// A control structure's bits and error codes after the last update (or
    /// after the last instruction call, which sets `.EN`, `.DN`/`.ER` at once,
    /// as a scan of the rung does).
    pub fn motion_bits(&self, instruction: InstructionHandle) -> MotionInstructionBits {
        self.instructions[instruction.0 as usize].bits
    }

    /// The bits of a control structure, for the instruction that executes
    /// with it.
    #[allow(
        dead_code,
        reason = "written by the Logix instructions that execute with a control structure"
    )]
    /// Writes a control structure's bits and codes, as a program that
    /// writes `MC1.EN := 0;` does (the instruction reads them at its next
    /// execution or update).
    pub fn set_motion_bits(&mut self, instruction: InstructionHandle, bits: MotionInstructionBits) {
        self.instructions[instruction.0 as usize].bits = bits;
    }

    /// Marks a control structure as executed by a scanned language
    /// (Structured Text): each execution is a scan of a rung that goes
    /// false then true, and the rung does not fall by itself afterwards, so
    /// `.EN` stays set until the instruction executes again (a statement in
    /// a branch that is not taken is not scanned at all). Without this
    /// mark an execution is a one-shot rung, false from the next update on.
    pub fn set_scanned(&mut self, instruction: InstructionHandle) {
        self.instructions[instruction.0 as usize].scanned = true;
    }

    /// Whether [`MotionTask::set_scanned`] marked the control structure.
    pub fn is_scanned(&self, instruction: InstructionHandle) -> bool {
        self.instructions[instruction.0 as usize].scanned
    }

    pub(crate) fn motion_bits_mut(&mut self, instruction: InstructionHandle) -> &mut MotionInstructionBits {
        &mut self.instructions[instruction.0 as usize].bits
    }

    /// A control structure's tag name.
    pub fn instruction_name(&self, instruction: InstructionHandle) -> &str {
        &self.instructions[instruction.0 as usize].name
    }

    /// Every control structure, in the order added.
    pub fn instruction_handles(&self) -> impl Iterator<Item = InstructionHandle> + use<> {
        (0..self.instructions.len() as u32).map(InstructionHandle)
    }

    /// Every axis, in the order added.
    pub fn axis_handles(&self) -> impl Iterator<Item = AxisHandle> + use<> {
        (0..self.axes.len() as u32).map(AxisHandle)
    }

    /// An axis' configuration.
    pub fn axis_config(&self, axis: AxisHandle) -> &AxisConfig {
        &self.axes[axis.0 as usize].config
    }

    /// Sets one of an axis' configuration attributes, as a program's SSV
    /// does. The dynamic limits take effect for instructions started
    /// afterwards (and `% of maximum` rates refer to them); motion already
    /// planned keeps its profile. The position error tolerance and the soft
    /// travel limits are checked against from the next update on; the
    /// homing attributes are read by the next MAH.
    ///
    /// # Errors
    /// [`AxisConfigError`] when the value breaks the configuration's rules
    /// ([`AxisConfig::with_limit`]); the axis keeps its value.
    pub fn set_axis_limit(&mut self, axis: AxisHandle, limit: AxisLimit, value: f64) -> Result<(), AxisConfigError> {
        let config = self.axes[axis.0 as usize].config.with_limit(limit, value)?;
        self.axes[axis.0 as usize].config = config;
        Ok(())
    }

    /// Whether the single-axis profile running on `axis` (an MC_MoveModulo,
    /// a MAM, a jog, a stop ramp) is overshooting now: above its speed limit
    /// because its start state could not keep it, or past its target, to
    /// which it comes back ([`crate::profile::Profile::overshoot_at`]). The
    /// trace's `<axis>.overshoot`.
    pub fn profile_overshoot(&self, axis: AxisHandle) -> bool {
        let job = self.axes[axis.0 as usize]
            .job
            .as_ref()
            .is_some_and(|j| !j.generation_done && j.profile.overshoot_at(j.t_s));
        job || self.ramp_overshoots(axis)
    }

    /// What the instruction just executed wrote to its output operand (a
    /// `Kind::OutputVector3`: MCTP's Transform Position), taken once; the
    /// caller stores it in the operand's tag.
    pub fn take_output(&mut self) -> Option<[f64; 3]> {
        self.output.take()
    }

    /// An axis' state after the last update.
    pub fn axis_state(&self, axis: AxisHandle) -> AxisState {
        let a = &self.axes[axis.0 as usize];
        AxisState {
            command_position: a.command.position,
            command_velocity: a.command.velocity,
            command_acceleration: a.command.acceleration,
            command_jerk: a.command.jerk,
            actual_position: a.actual,
            actual_velocity: if a.fed { a.actual_velocity } else { a.command.velocity },
            modulo_command_position: a.config.modulo().map(|m| m.wrap(a.command.position)),
            has_job: a.job.as_ref().is_some_and(|j| !j.generation_done),
        }
    }

    /// Feeds the measured position of an axis (axis units, unwrapped, in
    /// the axis' positions: the MRP redefinitions made so far included, the
    /// frame [`MotionTask::axis_state`] reports in; a device that reports in
    /// its own frame is `position_offset` away, see
    /// [`MotionTask::position_offset`]); used from the next update on. An
    /// axis never fed follows its command.
    pub fn feed_actual_position(&mut self, axis: AxisHandle, position: f64) {
        let dt_s = self.dt_s;
        let a = &mut self.axes[axis.0 as usize];
        if position.is_finite() {
            a.actual_velocity = if a.fed { (position - a.actual) / dt_s } else { 0.0 };
            a.actual = position;
            a.fed = true;
        }
    }

    /// Axis reset (MC_Reset): the actual position becomes the set position,
    /// motion stops at once, and the running and buffered commands are
    /// aborted (`CommandAborted`).
    pub fn reset_axis(&mut self, axis: AxisHandle) {
        self.fold_superimposed(axis);
        self.release_cam_and_jog(axis);
        self.release_axis_from_coordinated_motion(axis);
        let a = &mut self.axes[axis.0 as usize];
        a.command = Sample {
            position: a.actual,
            ..Sample::default()
        };
        let job_fb = a.job.take().and_then(|j| j.fb);
        let buffered_fb = a.buffered.take().map(|(fb, _)| fb);
        for fb in job_fb.into_iter().chain(buffered_fb) {
            self.finish(fb, Finish::Aborted);
        }
    }

    fn evaluate_inputs(&mut self, fb: FbHandle) {
        let updates = self.updates;
        let slot = &mut self.fbs[fb.0 as usize];
        let execute = slot.inputs.execute;
        let rising = execute && !slot.previous_execute;
        slot.previous_execute = execute;
        if let Phase::Finished { at_update } = slot.phase
            && !execute
            && at_update < updates
        {
            slot.outputs = FbOutputs::default();
            slot.phase = Phase::Idle;
        }
        if !rising {
            return;
        }
        if matches!(slot.phase, Phase::Active | Phase::Buffered) {
            // Not possible while busy: refuse, and detach the running command.
            self.detach(fb);
            self.finish(fb, Finish::Error(MoveModuloError::Busy));
            return;
        }
        let slot = &mut self.fbs[fb.0 as usize];
        slot.outputs = FbOutputs::default();
        let axis = slot.axis;
        let inputs = slot.inputs;
        let command = match MoveModulo::new(&inputs, &self.axes[axis.0 as usize].config) {
            Ok(c) => c,
            Err(e) => return self.finish(fb, Finish::Error(e)),
        };
        if let Err(e) = self.check_state(axis, Need::Motion) {
            return self.finish(fb, Finish::Error(MoveModuloError::AxisNotReady(e)));
        }
        if self.stop_in_progress(axis) {
            return self.finish(fb, Finish::Error(MoveModuloError::AxisStopping));
        }
        if self.cam_drives(axis) {
            if !self.axes[axis.0 as usize].config.allow_motion_on_coupled_slave {
                return self.finish(fb, Finish::Error(MoveModuloError::CoupledSlave));
            }
            let mode = command.buffer_mode();
            if mode != McBufferMode::Aborting {
                return self.finish(fb, Finish::Error(MoveModuloError::CoupledBufferMode { mode }));
            }
        }
        let a = &mut self.axes[axis.0 as usize];
        let idle = a.job.is_none();
        match command.buffer_mode() {
            McBufferMode::Aborting => self.start(axis, fb, command, None),
            _ if idle => self.start(axis, fb, command, None),
            mode => {
                if a.buffered.is_some() {
                    return self.finish(fb, Finish::Error(MoveModuloError::BufferFull));
                }
                a.buffered = Some((fb, command));
                let blend = a
                    .job
                    .as_ref()
                    .and_then(|j| mode.junction_velocity(j.command.velocity(), command.velocity()));
                if let (Some(vj), Some(job)) = (blend, a.job.as_mut())
                    && !job.generation_done
                    && !job.stopping
                {
                    // End the running command at its target with the junction speed.
                    let now = job.profile.sample(job.t_s).state();
                    job.profile = Profile::to_position(now, job.target, vj, job.command.limits());
                    job.t_s = 0.0;
                }
                let slot = &mut self.fbs[fb.0 as usize];
                slot.phase = Phase::Buffered;
                slot.outputs.busy = true;
            }
        }
    }

    /// Starts `command` on `axis` now, `elapsed_s` into its profile (a blend
    /// hand-over inside an update), aborting whatever runs there.
    fn start(&mut self, axis: AxisHandle, fb: FbHandle, command: MoveModulo, elapsed_s: Option<f64>) {
        self.fold_superimposed(axis);
        self.release_cam_and_jog(axis);
        self.release_axis_from_coordinated_motion(axis);
        let a = &mut self.axes[axis.0 as usize];
        // A blend hand-over replaces a command that has just finished (Done);
        // any other start aborts what runs or waits on the axis.
        let replaced = [a.job.take().and_then(|j| j.fb), a.buffered.take().map(|(b, _)| b)];
        let aborted: Vec<FbHandle> = match elapsed_s {
            Some(_) => Vec::new(),
            None => replaced.into_iter().flatten().filter(|&b| b != fb).collect(),
        };
        let origin = elapsed_s.is_none().then_some(Origin {
            update: self.updates,
            command: a.command,
            last_direction: a.last_direction,
        });
        let state = a.command.state();
        let target = command.absolute_target(state, a.last_direction);
        let profile = Profile::to_position(state, target, 0.0, command.limits());
        a.job = Some(Job {
            fb: Some(fb),
            command,
            profile,
            t_s: elapsed_s.unwrap_or(0.0),
            target,
            generation_done: false,
            stopping: false,
            origin,
        });
        for other in aborted {
            self.finish(other, Finish::Aborted);
        }
        let slot = &mut self.fbs[fb.0 as usize];
        slot.phase = Phase::Active;
        slot.outputs = FbOutputs {
            busy: true,
            active: true,
            ..FbOutputs::default()
        };
    }

    fn advance_axis(&mut self, axis: AxisHandle) {
        let dt = self.dt_s;
        let a = &mut self.axes[axis.0 as usize];
        if let Some(job) = a.job.as_mut()
            && !job.generation_done
        {
            job.t_s += dt;
            if job.t_s >= job.profile.duration_s() {
                let leftover = job.t_s - job.profile.duration_s();
                let end = job.profile.final_state();
                job.generation_done = true;
                job.t_s = job.profile.duration_s();
                if end.velocity != 0.0 {
                    // Blend hand-over: the buffered command takes over moving.
                    let finished = job.fb;
                    a.command = Sample {
                        position: end.position,
                        velocity: end.velocity,
                        acceleration: 0.0,
                        jerk: 0.0,
                    };
                    if let Some((next_fb, next)) = a.buffered.take() {
                        if let Some(fb) = finished {
                            self.finish(fb, Finish::Done);
                        }
                        self.start(axis, next_fb, next, Some(leftover));
                        let a = &mut self.axes[axis.0 as usize];
                        if let Some(job) = a.job.as_mut() {
                            a.command = job.profile.sample(job.t_s);
                        }
                        return self.settle(axis);
                    }
                }
            }
        }
        let a = &mut self.axes[axis.0 as usize];
        if let Some(job) = a.job.as_ref() {
            a.command = job.profile.sample(job.t_s);
        }
        self.settle(axis);
    }

    /// Actual position, direction memory, `Done`, and buffered starts.
    fn settle(&mut self, axis: AxisHandle) {
        let a = &mut self.axes[axis.0 as usize];
        if !a.fed {
            a.actual = a.command.position;
        }
        if a.command.velocity != 0.0 {
            a.last_direction = a.command.velocity.signum();
        }
        let Some(job) = a.job.as_ref() else { return };
        if !job.generation_done {
            return;
        }
        // MC_MoveModulo's Done rule (spec): target position monitoring
        // waits for the in-position window, position range monitoring (with
        // target monitoring off) for the position range window; neither, or
        // Options.IgnorePositionMonitoring, sets Done when setpoint
        // generation ends.
        let error = (a.actual - job.target).abs();
        let c = &a.config;
        let in_position = if job.command.ignores_position_monitoring() {
            true
        } else if c.target_position_monitoring {
            error <= c.in_position_window
        } else if c.position_range_monitoring {
            error <= c.position_range_window
        } else {
            true
        };
        if !in_position {
            return;
        }
        let fb = job.fb;
        a.job = None;
        let next = a.buffered.take();
        if let Some(fb) = fb {
            self.finish(fb, Finish::Done);
        }
        if let Some((next_fb, next)) = next {
            self.start(axis, next_fb, next, None);
        }
    }

    /// Detaches `fb` from the command it drives, which keeps running.
    fn detach(&mut self, fb: FbHandle) {
        for a in &mut self.axes {
            if let Some(job) = a.job.as_mut()
                && job.fb == Some(fb)
            {
                job.fb = None;
            }
            if a.buffered.as_ref().is_some_and(|(b, _)| *b == fb) {
                a.buffered = None;
            }
        }
    }

    fn finish(&mut self, fb: FbHandle, how: Finish) {
        let updates = self.updates;
        let slot = &mut self.fbs[fb.0 as usize];
        slot.phase = Phase::Finished { at_update: updates };
        slot.outputs = match how {
            Finish::Done => FbOutputs {
                done: true,
                ..FbOutputs::default()
            },
            Finish::Aborted => FbOutputs {
                command_aborted: true,
                ..FbOutputs::default()
            },
            Finish::Error(e) => FbOutputs {
                error: true,
                error_id: e.error_id().0,
                ..FbOutputs::default()
            },
        };
    }

    /// The absolute target of the command running on `axis`, if any.
    pub fn active_target(&self, axis: AxisHandle) -> Option<f64> {
        self.axes[axis.0 as usize].job.as_ref().map(|j| j.target)
    }

    /// The profile of the command running on `axis`, if any, and the time
    /// into it (for inspection and tests).
    pub fn active_profile(&self, axis: AxisHandle) -> Option<(&Profile, f64)> {
        self.axes[axis.0 as usize].job.as_ref().map(|j| (&j.profile, j.t_s))
    }

    /// The state an axis would start a new command from (its command state).
    pub fn command_state(&self, axis: AxisHandle) -> State {
        self.axes[axis.0 as usize].command.state()
    }
}

#[cfg(test)]
mod tests;
