//! Starting coordinated instructions: the rung scan, verification of
//! MCLM/MCCM/MCS against the system, queueing, merging and stopping.

use super::advance::{add_displacement, rest_length, unwind_rotary_targets};
use crate::axis::AxisKind;
use crate::coord::{
    CoordFault, CoordMove, CoordMoveError, Driver, Mcs, McsInputs, Merge, MergeSpeed, MoveContext, OperandIndex,
    TerminationType, primary_of, progress_at_length, with_velocity,
};
use crate::instruction::MotionInstructionBits;
use crate::instruction::{LogixFault, Refusal};
use crate::mccm::mccm;
use crate::mclm::mclm;
use crate::profile::{Limits, Profile, State, stopping_distance};
use crate::task::MotionTask;
use crate::task::engine::Finish;
use crate::task::engine::{Component, CoordCall, ERR_IDLE_MASTER_SLAVE_MOVING, Lock};
use crate::task::handles::AxisHandle;
use crate::task::handles::{CoordHandle, CoordInstructionHandle};
use crate::vector::norm;

impl MotionTask {
    /// Step 1b of an update: rung transitions of the coordinated
    /// instructions (held ones retry first).
    pub(in crate::task) fn evaluate_coord_instructions(&mut self) {
        let updates = self.updates;
        for slot in &mut self.coord.instructions {
            if slot.one_shot_at.is_some_and(|at| updates >= at + 2) {
                slot.rung = false;
                slot.one_shot_at = None;
            }
        }
        for i in 0..self.coord.instructions.len() {
            let h = CoordInstructionHandle(i as u32);
            if self.coord.instructions[i].held {
                self.execute_coord(h);
            }
        }
        for i in 0..self.coord.instructions.len() {
            self.scan_coord_instruction(CoordInstructionHandle(i as u32));
        }
    }

    /// One scan of an instruction's rung: a false rung clears `.EN` once
    /// `.DN` or `.ER` is set; a rising rung resets `.DN`, `.ER`, `.PC` and
    /// the error codes, sets `.EN`, and executes.
    pub(super) fn scan_coord_instruction(&mut self, h: CoordInstructionHandle) {
        let slot = &mut self.coord.instructions[h.0 as usize];
        let rising = slot.rung && !slot.previous_rung;
        let rung = slot.rung;
        slot.previous_rung = slot.rung;
        let bits = self.cbits(h);
        if !rung && (bits.dn || bits.er) {
            bits.en = false;
        }
        if rising {
            *bits = MotionInstructionBits {
                en: true,
                ip: bits.ip,
                ac: bits.ac,
                accel: bits.accel,
                decel: bits.decel,
                ..MotionInstructionBits::default()
            };
            self.execute_coord(h);
        }
    }

    pub(super) fn execute_coord(&mut self, h: CoordInstructionHandle) {
        let slot = &self.coord.instructions[h.0 as usize];
        let cs = slot.system;
        match slot.call.clone() {
            CoordCall::Mcs(inputs) => {
                self.coord.instructions[h.0 as usize].held = false;
                self.execute_mcs(h, cs, &inputs);
            }
            CoordCall::Mclm(mut inputs) => {
                let merge = (inputs.merge, OperandIndex::MCLM.merge);
                self.execute_move(h, cs, merge, |ctx, unwinds| {
                    let c = &mut inputs;
                    unwind_rotary_targets(
                        unwinds,
                        ctx.start,
                        c.move_type,
                        &mut c.position,
                        OperandIndex::MCLM.position,
                    )?;
                    mclm(&inputs, ctx)
                });
            }
            CoordCall::Mccm(mut inputs) => {
                let merge = (inputs.common.merge, OperandIndex::MCCM.merge);
                self.execute_move(h, cs, merge, |ctx, unwinds| {
                    let c = &mut inputs.common;
                    unwind_rotary_targets(
                        unwinds,
                        ctx.start,
                        c.move_type,
                        &mut c.position,
                        OperandIndex::MCCM.position,
                    )?;
                    mccm(&inputs, ctx)
                });
            }
        }
    }

    pub(super) fn execute_move(
        &mut self,
        h: CoordInstructionHandle,
        cs: CoordHandle,
        (merge_code, merge_exerr): (i64, i32),
        verify: impl FnOnce(&MoveContext<'_>, &[Option<f64>]) -> Result<CoordMove, CoordMoveError>,
    ) {
        let sys = &self.coord.systems[cs.0 as usize];
        let busy = !sys.components.is_empty() || sys.pending.is_some();
        let merging = busy && (merge_code == 1 || merge_code == 2);
        if busy && !merging && sys.pending.is_some() {
            self.coord.instructions[h.0 as usize].held = true;
            return;
        }
        self.coord.instructions[h.0 as usize].held = false;
        if let Err((state, exerr)) = self.check_system_state(cs) {
            return self.refuse(h, Refusal::State { state, exerr });
        }
        let sys = &self.coord.systems[cs.0 as usize];
        let start = if merging {
            self.rest_point(cs)
        } else if busy {
            sys.queue_end.clone()
        } else {
            self.axis_positions(cs)
        };
        let decels: Vec<f64> = sys
            .axes
            .iter()
            .map(|a| self.axes[a.0 as usize].config.max_deceleration)
            .collect();
        let ctx = MoveContext {
            system: &sys.system,
            axis_max_decel: &decels,
            start: &start,
            has_master: sys.master.is_some(),
        };
        // The unwind of each rotary axis with a modulo period.
        let unwinds: Vec<Option<f64>> = sys
            .axes
            .iter()
            .map(|a| {
                let config = &self.axes[a.0 as usize].config;
                (config.kind == AxisKind::Rotary)
                    .then(|| config.modulo().map(|m| m.period()))
                    .flatten()
            })
            .collect();
        let result = verify(&ctx, &unwinds);
        let mv = match result {
            Ok(mv) => mv,
            Err(e) => return self.refuse(h, e),
        };
        // An axis that would end further beyond a soft travel limit it has
        // exceeded: ERR 9, EXERR its index ([`crate::servo`]).
        let axes = &self.coord.systems[cs.0 as usize].axes;
        let out = axes
            .iter()
            .zip(mv.path().end().iter().zip(&start))
            .position(|(&a, (end, from))| {
                let distance = end - from;
                distance != 0.0 && self.check_overtravel(a, distance).is_err()
            });
        if let Some(i) = out {
            let state = crate::servo::StateError::Overtravel;
            return self.refuse(h, Refusal::State { state, exerr: i as i32 });
        }
        // Another system moving axes of this one: merge all motion ends its
        // motion; otherwise the move is refused.
        let others = self.busy_systems_sharing_axes(cs);
        if !others.is_empty() {
            if mv.merge() != Merge::AllMotion {
                return self.refuse(h, Refusal::operand_index(merge_exerr));
            }
            for other in others {
                self.cancel_system(other);
            }
        }
        if (merging || !busy) && self.idle_master_with_moving_slave(cs, &mv) {
            return self.refuse(h, Refusal::Instruction(CoordFault::IdleMasterSlaveMoving));
        }
        self.cbits(h).dn = true;
        // Merge speed current: the speed of all motion on the axes now.
        let speed_now = self.vector_speed(cs);
        let mv = if mv.merge() != Merge::Disabled && mv.merge_speed() == MergeSpeed::Current && speed_now > 0.0 {
            mv.with_speed(speed_now)
        } else {
            mv
        };
        // Calculated Data with the speed the move runs at.
        self.coord.instructions[h.0 as usize].calculated_data = mv.calculated_data().to_vec();
        let sys = &mut self.coord.systems[cs.0 as usize];
        sys.status.stopping = false;
        if merging {
            self.bring_to_rest(cs, None);
            if mv.merge() == Merge::AllMotion {
                self.abort_single_axis_motion(cs);
            }
            self.start_component(cs, h, mv, 0.0);
        } else if busy {
            sys.queue_end = mv.path().end().to_vec();
            sys.pending = Some((h, mv));
            self.cbits(h).ip = true;
        } else {
            if mv.merge() == Merge::AllMotion {
                self.abort_single_axis_motion(cs);
            }
            self.start_component(cs, h, mv, 0.0);
        }
        self.refresh_queue_status(cs);
    }

    /// Refuses the instruction's execution: `.ER` with the refusal's ERR
    /// and EXERR, which [`MotionTask::execute_coordinated`] returns when it
    /// happens in its call.
    fn refuse(&mut self, h: CoordInstructionHandle, refusal: CoordMoveError) {
        self.cbits(h).set_error(refusal.err(), refusal.exerr(), 0);
        self.coord.refused = Some(refusal);
    }

    pub(super) fn execute_mcs(&mut self, h: CoordInstructionHandle, cs: CoordHandle, inputs: &McsInputs) {
        let sys = &self.coord.systems[cs.0 as usize];
        let stop = match Mcs::new(inputs, &sys.system) {
            Ok(s) => s,
            Err(e) => return self.refuse(h, e),
        };
        self.cbits(h).dn = true;
        self.mct_on_mcs(cs, inputs.stop_type);
        if stop.stop_all {
            self.stop_single_axis_motion(cs);
            self.break_master_link(cs);
        }
        let sys = &mut self.coord.systems[cs.0 as usize];
        if sys.components.is_empty() && sys.pending.is_none() {
            self.cbits(h).pc = true;
            return;
        }
        let limits = match stop.decel_jerk {
            Some(j) => Limits::s_curve(f64::MAX / 4.0, stop.decel, stop.decel, j, j),
            None => Limits::trapezoidal(f64::MAX / 4.0, stop.decel, stop.decel),
        }
        .ok();
        self.bring_to_rest(cs, limits);
        let sys = &mut self.coord.systems[cs.0 as usize];
        sys.status.stopping = true;
        sys.status.move_ = false;
        sys.status.move_transition = false;
        sys.stop = Some(h);
        self.cbits(h).ip = true;
        self.refresh_queue_status(cs);
    }

    /// The other coordinate systems that move (or have a move queued on)
    /// an axis of `cs`.
    pub(super) fn busy_systems_sharing_axes(&self, cs: CoordHandle) -> Vec<CoordHandle> {
        let mine = &self.coord.systems[cs.0 as usize].axes;
        (0..self.coord.systems.len())
            .filter(|&j| j != cs.0 as usize)
            .filter(|&j| {
                let s = &self.coord.systems[j];
                (!s.components.is_empty() || s.pending.is_some()) && s.axes.iter().any(|a| mine.contains(a))
            })
            .map(|j| CoordHandle(j as u32))
            .collect()
    }

    /// Cancels at once the coordinated motion (moves, queue, stop) of every
    /// system that holds `axis` (its drive was disabled). The system's other
    /// axes, whose drives still follow their commands, ramp to rest each at
    /// its own deceleration from where the path left them (as a Stop
    /// Planner would), rather than keeping the path's last velocity.
    pub(in crate::task) fn cancel_systems_with_axis(&mut self, axis: AxisHandle) {
        for i in 0..self.coord.systems.len() {
            let sys = &self.coord.systems[i];
            let busy = !sys.components.is_empty() || sys.pending.is_some() || sys.stop.is_some();
            if busy && sys.axes.contains(&axis) {
                let others: Vec<AxisHandle> = sys.axes.iter().copied().filter(|&a| a != axis).collect();
                self.cancel_system(CoordHandle(i as u32));
                for other in others {
                    let c = self.axes[other.0 as usize].command;
                    if c.velocity != 0.0 || c.acceleration != 0.0 {
                        let profile = self.rest_profile(other);
                        self.start_stop_ramp(other, profile);
                    }
                }
            }
        }
    }

    /// Ends a system's motion where its command stands now (merge all
    /// motion from another system): its instructions lose `.IP`/`.AC`, its
    /// queue is cleared, and its axes keep their command positions.
    pub(super) fn cancel_system(&mut self, cs: CoordHandle) {
        let here = self.axis_positions(cs);
        let sys = &mut self.coord.systems[cs.0 as usize];
        let mut cleared: Vec<CoordInstructionHandle> = sys.components.drain(..).filter_map(|c| c.instr).collect();
        cleared.extend(sys.pending.take().map(|(h, _)| h));
        cleared.extend(sys.stop.take());
        sys.base = here.clone();
        sys.queue_end = here;
        sys.velocity.iter_mut().for_each(|v| *v = 0.0);
        sys.acceleration.iter_mut().for_each(|v| *v = 0.0);
        sys.status.clear_motion();
        self.refresh_queue_status(cs);
        for h in cleared {
            self.cbits(h).end_motion();
        }
    }

    /// Where the system's axes stand now (the command positions).
    pub(super) fn axis_positions(&self, cs: CoordHandle) -> Vec<f64> {
        self.coord.systems[cs.0 as usize]
            .axes
            .iter()
            .map(|a| self.axes[a.0 as usize].command.position)
            .collect()
    }

    /// The primary-axis vector speed of the system now: the vector sum of
    /// all motion on its primary axes (coordinated, jogs, moves, cams), from
    /// the axes' command velocities.
    pub(super) fn vector_speed(&self, cs: CoordHandle) -> f64 {
        let sys = &self.coord.systems[cs.0 as usize];
        let v: Vec<f64> = sys
            .axes
            .iter()
            .map(|a| self.axes[a.0 as usize].command.velocity)
            .collect();
        norm(primary_of(&v, sys.system.config().primary_axes))
    }

    /// Where the running motion comes to rest if every component brakes now
    /// with its own deceleration.
    pub(super) fn rest_point(&self, cs: CoordHandle) -> Vec<f64> {
        let sys = &self.coord.systems[cs.0 as usize];
        let mut at = sys.base.clone();
        for c in &sys.components {
            let s_rest = rest_length(c, None);
            add_displacement(&mut at, c, s_rest);
        }
        at
    }

    /// Replaces every component's profile by one that brings it to rest
    /// along its path (with `limits`, or the move's own), cancels the pending
    /// move, and clears the instructions' `.IP`/`.AC`.
    pub(super) fn bring_to_rest(&mut self, cs: CoordHandle, limits: Option<Limits>) {
        let sys = &mut self.coord.systems[cs.0 as usize];
        let mut cleared = Vec::new();
        for c in &mut sys.components {
            let now = c.s();
            let length = c.mv.path().length();
            let own = c.mv.limits().copied();
            let lim = match (limits, own) {
                (Some(l), Some(o)) => with_velocity(&l, o.velocity().max(now.velocity.abs())),
                (None, Some(o)) => Some(o),
                (_, None) => None,
            };
            if let Some(lim) = lim {
                let state = now.state();
                if state.position + stopping_distance(state, &lim) < length {
                    c.profile = Profile::to_velocity(state, 0.0, &lim);
                    c.progress = 0.0;
                }
            } else {
                c.profile = Profile::hold(State::at_rest(now.position));
                c.progress = 0.0;
            }
            c.stopping = true;
            c.blend_at = None;
            cleared.extend(c.instr.take());
        }
        if let Some((h, _)) = sys.pending.take() {
            cleared.push(h);
        }
        for h in cleared {
            self.cbits(h).end_motion();
        }
        let sys = &mut self.coord.systems[cs.0 as usize];
        sys.queue_end = {
            let mut at = sys.base.clone();
            for c in &sys.components {
                add_displacement(&mut at, c, rest_length(c, None));
            }
            at
        };
    }

    /// Whether master-driven `mv` would take over from time-driven (or
    /// single-axis) motion while the master stands still and the system's
    /// primary axes move: the spec's run-time error.
    pub(super) fn idle_master_with_moving_slave(&self, cs: CoordHandle, mv: &CoordMove) -> bool {
        let sys = &self.coord.systems[cs.0 as usize];
        if mv.driver() != Driver::Master {
            return false;
        }
        let from_time_driven =
            sys.components.is_empty() || sys.components.iter().any(|c| c.mv.driver() == Driver::Time);
        let master_idle = sys.master.is_none_or(|m| {
            let a = &self.axes[m.0 as usize];
            (if sys.master_actual {
                a.actual_velocity
            } else {
                a.command.velocity
            }) == 0.0
        });
        from_time_driven && master_idle && self.vector_speed(cs) > 0.0
    }

    /// Fails a move that comes out of the queue with
    /// [`ERR_IDLE_MASTER_SLAVE_MOVING`] when it would start now (it keeps
    /// `.DN`, loses `.IP`); the queue then ends where the running move ends.
    pub(super) fn fail_idle_master_switch(
        &mut self,
        cs: CoordHandle,
        h: CoordInstructionHandle,
        mv: &CoordMove,
    ) -> bool {
        if !self.idle_master_with_moving_slave(cs, mv) {
            return false;
        }
        let b = self.cbits(h);
        b.set_error(ERR_IDLE_MASTER_SLAVE_MOVING, 0, 0);
        b.ip = false;
        let sys = &mut self.coord.systems[cs.0 as usize];
        if let Some(c) = sys.components.last() {
            sys.queue_end = c.mv.path().end().to_vec();
        }
        true
    }

    pub(super) fn start_component(&mut self, cs: CoordHandle, h: CoordInstructionHandle, mv: CoordMove, leftover: f64) {
        self.start_component_from(cs, h, mv, leftover, State::at_rest(0.0));
    }

    /// Starts a component whose path profile begins in `initial` (at rest,
    /// or at the junction speed of a follow-contour predecessor).
    pub(super) fn start_component_from(
        &mut self,
        cs: CoordHandle,
        h: CoordInstructionHandle,
        mv: CoordMove,
        leftover: f64,
        initial: State,
    ) {
        let start = self.record_start(cs);
        self.take_axes_for_coordinated_motion(cs);
        let master_now = {
            let sys = &self.coord.systems[cs.0 as usize];
            sys.master
                .map(|m| self.axes[m.0 as usize].command.position)
                .unwrap_or(0.0)
        };
        let sys = &mut self.coord.systems[cs.0 as usize];
        if sys.components.is_empty() {
            sys.base = mv.path().start().to_vec();
        }
        let profile = match mv.limits() {
            Some(l) if initial.velocity > 0.0 => Profile::to_position(initial, mv.path().length(), 0.0, l),
            _ => mv.rest_profile(),
        };
        let blend_at = if mv.termination().blends() && mv.limits().is_some() {
            let decel_point = profile.deceleration_start_s();
            Some(match mv.termination() {
                TerminationType::NoDecel => decel_point,
                _ => progress_at_length(&profile, mv.path().length() - mv.command_tolerance()).max(decel_point),
            })
        } else {
            None
        };
        let (direction, position) = mv.lock();
        let lock = Lock::new(direction, position, master_now);
        sys.queue_end = mv.path().end().to_vec();
        sys.status.motion = true;
        sys.status.move_ = true;
        sys.status.stopping = false;
        sys.status.actual_pos_tolerance = false;
        sys.status.command_pos_tolerance = false;
        sys.status.coord_motion_lock = mv.driver() == Driver::Master && lock.locked;
        let progress = if mv.driver() == Driver::Time { leftover } else { 0.0 };
        sys.components.push(Component {
            instr: Some(h),
            mv,
            profile,
            progress,
            last_delta: progress,
            blend_at,
            successor_started: false,
            contour: false,
            stopping: false,
            held: false,
            lock,
            start,
        });
        let b = self.cbits(h);
        b.ip = true;
        b.ac = true;
    }

    /// Merge All Motion: aborts every single-axis process on the system's
    /// axes — MC_MoveModulo commands (running and buffered), cams, jogs,
    /// moves, stop ramps and superimposed runs.
    pub(super) fn abort_single_axis_motion(&mut self, cs: CoordHandle) {
        let axes = self.coord.systems[cs.0 as usize].axes.clone();
        self.coord.systems[cs.0 as usize].taken.clear();
        for axis in axes {
            self.fold_superimposed(axis);
            self.release_cam_and_jog(axis);
            self.abort_modulo_commands(axis);
        }
    }

    /// A coordinated move takes the system's axes: MC_MoveModulo commands,
    /// cams and stop ramps end; a jog or MAM goes on superimposed.
    pub(super) fn take_axes_for_coordinated_motion(&mut self, cs: CoordHandle) {
        let axes = self.coord.systems[cs.0 as usize].axes.clone();
        self.coord.systems[cs.0 as usize].taken.clear();
        for axis in axes {
            self.superimpose_or_release(axis);
            self.abort_modulo_commands(axis);
        }
    }

    /// MCS stop type all: single-axis commands on the system's axes brake to
    /// rest with their own deceleration and report `CommandAborted`.
    pub(super) fn stop_single_axis_motion(&mut self, cs: CoordHandle) {
        let axes = self.coord.systems[cs.0 as usize].axes.clone();
        for axis in axes {
            self.stop_superimposed(axis);
            let a = &mut self.axes[axis.0 as usize];
            let buffered = a.buffered.take().map(|(fb, _)| fb);
            let mut aborted: Vec<_> = buffered.into_iter().collect();
            if let Some(job) = a.job.as_mut()
                && !job.generation_done
            {
                let state = job.profile.sample(job.t_s).state();
                job.profile = Profile::to_velocity(state, 0.0, job.command.limits());
                job.t_s = 0.0;
                job.target = job.profile.final_state().position;
                aborted.extend(job.fb.take());
            }
            for fb in aborted {
                self.finish(fb, Finish::Aborted);
            }
        }
    }

    /// Hook for single-axis starts (MC_MoveModulo, MAPC, MAJ, MAS, an axis
    /// reset): the coordinated motion of the axis' systems comes to rest
    /// along its path, and the system no longer writes `axis`.
    pub(in crate::task) fn release_axis_from_coordinated_motion(&mut self, axis: AxisHandle) {
        for i in 0..self.coord.systems.len() {
            let sys = &self.coord.systems[i];
            if sys.axes.contains(&axis) && (!sys.components.is_empty() || sys.pending.is_some()) {
                self.coord.systems[i].taken.push(axis);
                self.bring_to_rest(CoordHandle(i as u32), None);
                let st = &mut self.coord.systems[i].status;
                st.move_ = false;
                st.move_transition = false;
                self.refresh_queue_status(CoordHandle(i as u32));
            }
        }
    }

    /// Hook for an MCT fault: `cs`'s coordinated motion comes to rest along
    /// its path with its moves' own deceleration, every axis kept on the
    /// path (nothing is taken from the system).
    pub(in crate::task) fn bring_system_to_rest(&mut self, cs: CoordHandle) {
        let sys = &self.coord.systems[cs.0 as usize];
        if sys.components.is_empty() && sys.pending.is_none() {
            return;
        }
        self.bring_to_rest(cs, None);
        let st = &mut self.coord.systems[cs.0 as usize].status;
        st.move_ = false;
        st.move_transition = false;
        self.refresh_queue_status(cs);
    }

    /// Hook for [`MotionTask::stop_all_axes`]: every moving system comes to
    /// rest along its path with the system's maximum deceleration (its
    /// moves' own where that is 0); its MCS, if one is stopping it, no longer
    /// completes. Returns the axes of the systems that were moving.
    pub(in crate::task) fn stop_coordinated_motion(&mut self) -> Vec<AxisHandle> {
        let mut stopped = Vec::new();
        for i in 0..self.coord.systems.len() {
            stopped.extend(self.stop_system_along_path(CoordHandle(i as u32)));
        }
        stopped
    }

    /// Every moving system that holds `axis` comes to rest along its path
    /// as in [`MotionTask::stop_all_axes`] (an active MAH's cancel).
    pub(in crate::task) fn stop_systems_with_axis(&mut self, axis: AxisHandle) {
        for i in 0..self.coord.systems.len() {
            if self.coord.systems[i].axes.contains(&axis) {
                self.stop_system_along_path(CoordHandle(i as u32));
            }
        }
    }

    /// Brings system `cs`, if it moves, to rest along its path with its
    /// maximum deceleration; returns its axes then (none if it was idle).
    fn stop_system_along_path(&mut self, cs: CoordHandle) -> Vec<AxisHandle> {
        let sys = &mut self.coord.systems[cs.0 as usize];
        if sys.components.is_empty() && sys.pending.is_none() {
            return Vec::new();
        }
        sys.stop = None;
        let decel = sys.system.config().max_decel;
        let limits = Limits::trapezoidal(f64::MAX / 4.0, decel, decel).ok();
        let axes = sys.axes.clone();
        self.bring_to_rest(cs, limits);
        let st = &mut self.coord.systems[cs.0 as usize].status;
        st.move_ = false;
        st.move_transition = false;
        self.refresh_queue_status(cs);
        axes
    }
}
