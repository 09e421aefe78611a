//! The single-axis processes of the motion task: position cams (MAPC, with
//! the profiles MCCP calculates), the axis' ramp (a MAJ jog, a MAM move, a
//! MAS stop ramp) and position redefinitions (MRP, MAH). The instructions
//! themselves are under `task/instructions/`.
//!
//! Each instruction executes inside its call (the rung's false-to-true
//! transition, as in one scan): MCCP calculates, MAPC starts or schedules,
//! MRP redefines, MAJ/MAS start their ramps. Motion happens in
//! [`MotionTask::update`]: after the MC_MoveModulo commands have advanced,
//! jogs and stop ramps advance (axis order), then position cams (axis order;
//! a slave mastered to another cam's slave sees its master's new position
//! when the master was added first).
//!
//! # One driver per axis
//! An axis is driven by one thing at a time: an MC_MoveModulo command, a jog
//! (or MAS stop ramp), or a position cam (active, waiting for its lock, or a
//! scheduled replacement). Starting one ends the others on that axis:
//! * a MoveModulo start ends the cam process (every cam's `.IP` reset, not
//!   complete) and the jog (its `.IP` reset);
//! * MAJ aborts the MoveModulo command (`CommandAborted`) and ends the cams,
//!   then ramps from the axis' current state (a running jog is merged:
//!   re-planned to the new speed);
//! * MAPC (non-pending) aborts the MoveModulo command and the jog; the cam
//!   starts from the slave's current command position. A MAM with Merge
//!   Disabled on a cam slave runs superimposed on the cam
//!   (`task/superimposed.rs`); a MAJ (which has no Merge operand here)
//!   ends the cam.
//! * MAS stops what its Stop Type names and ramps the axis to rest from its
//!   current velocity with the stop deceleration.
//! * [`MotionTask::reset_axis`] ends cams and jogs as well.
//!
//! # Trace helpers
//! [`MotionTask::slave_cam_status`] gives the slave's Position Cam Status,
//! Lock Status and Pending Status; [`MotionTask::limits_exceeded`] says
//! whether the last update's command velocity or acceleration exceeded the
//! axis' configured maxima (camming ignores them, as the spec warns; the flag
//! makes it visible). Cam velocities and accelerations are finite differences
//! of the command positions over the coarse update.
//!
//! # MRP and masters
//! MRP shifts an axis' command and actual positions by the same amount and
//! moves its running command, jog or cam with it. Cams see their masters'
//! positions *without* MRP shifts (the redefinitions are summed per axis and
//! taken out), so redefining a master's position never moves its slaves; a
//! Master Lock Position is taken in the master's positions of the moment the
//! MAPC executes. Every position the task takes and gives, fed actual
//! positions included, is in the axis' redefined positions; a device keeps
//! its own frame, [`MotionTask::position_offset`] away, and the caller
//! converts between the two.

use super::MotionTask;
use crate::instruction::{LogixFault, MotionInstructionBits};
use crate::mapc::axis::{CamEvent, CamRequest, SlaveCamStatus};
use crate::mapc::{Mapc, MapcError, MasterReference};
use crate::mccp::{CamElement, CamProfile, CamProfileTag, MccpError};
use crate::profile::{Limits, Profile, Sample};
use crate::task::engine::Finish;
use crate::task::engine::Need;
use crate::task::engine::SuperKind;
use crate::task::engine::Takes;
use crate::task::engine::{CamAxis, LimitFlags, MapcCall, MasterKey, RampAim, RampPlan, RampRun, Tag};
use crate::task::handles::CamProfileHandle;
use crate::task::handles::{AxisHandle, InstructionHandle};
use std::sync::Arc;

impl MotionTask {
    pub(crate) fn cam_axis(&mut self, axis: AxisHandle) -> &mut CamAxis {
        let i = axis.0 as usize;
        if self.cam.axes.len() <= i {
            self.cam.axes.resize_with(i + 1, CamAxis::default);
        }
        &mut self.cam.axes[i]
    }

    /// Adds a `CAM_PROFILE` tag of `capacity` elements (Status 0).
    pub fn add_cam_profile(&mut self, name: impl Into<String>, capacity: usize) -> CamProfileHandle {
        self.cam.profiles.push((name.into(), CamProfileTag::new(capacity)));
        CamProfileHandle(self.cam.profiles.len() as u32 - 1)
    }

    /// A `CAM_PROFILE` tag.
    pub fn cam_profile(&self, h: CamProfileHandle) -> &CamProfileTag {
        &self.cam.profiles[h.0 as usize].1
    }

    /// A `CAM_PROFILE` tag's name.
    pub fn cam_profile_name(&self, h: CamProfileHandle) -> &str {
        &self.cam.profiles[h.0 as usize].0
    }

    /// Writes a profile's Status (a program writing `Profile[0].Status`).
    #[cfg(test)]
    pub(crate) fn set_cam_profile_status(&mut self, h: CamProfileHandle, status: u32) {
        self.cam.profiles[h.0 as usize].1.set_status(status);
    }

    /// The `CAM_PROFILE` tag named `name` (case-insensitive), if added.
    pub fn find_cam_profile(&self, name: &str) -> Option<CamProfileHandle> {
        self.cam
            .profiles
            .iter()
            .position(|(n, _)| n.eq_ignore_ascii_case(name))
            .map(|i| CamProfileHandle(i as u32))
    }

    /// Declares `axis` a position cam slave (for traces that list the slave
    /// status only for such axes).
    pub(crate) fn declare_cam_slave(&mut self, axis: AxisHandle) {
        self.cam_axis(axis).declared_slave = true;
    }

    /// Whether `axis` was declared a cam slave (MAPC on it, at load).
    pub fn is_cam_slave(&self, axis: AxisHandle) -> bool {
        self.cam.axes.get(axis.0 as usize).is_some_and(|c| c.declared_slave)
    }

    /// A one-shot rung: the instruction just executed with `h` in this scan;
    /// its rung is false from the second coarse update on (so `.EN` shows
    /// in the update that executed it), which clears `.EN` there, or at the
    /// first update after that which finds `.DN` or `.ER` set (see
    /// [`MotionTask::rung_false`]). A new execution replaces a pending one.
    pub(crate) fn rung_false_next_scan(&mut self, h: InstructionHandle) {
        if self.is_scanned(h) {
            return;
        }
        let now = self.updates;
        self.cam.rung_false.retain(|&(x, _)| x != h);
        self.cam.rung_false.push((h, now));
    }

    /// The rung went false: `.EN` is cleared if `.DN` or `.ER` is set.
    pub(crate) fn rung_false(&mut self, h: InstructionHandle) {
        let b = self.motion_bits_mut(h);
        if b.dn || b.er {
            b.en = false;
        }
    }

    /// Starts an execution: `.EN` set, `.DN .ER .PC .IP .AC` and the codes
    /// cleared.
    pub(super) fn begin(&mut self, h: InstructionHandle) {
        *self.motion_bits_mut(h) = MotionInstructionBits {
            en: true,
            ..MotionInstructionBits::default()
        };
    }

    pub(super) fn fail(&mut self, h: InstructionHandle, err: i32, exerr: i32, segment: i32) {
        self.motion_bits_mut(h).set_error(err, exerr, segment);
    }

    /// Refuses a call before it executes (an operand its values cannot
    /// give, such as an element outside its array): `.EN`, and `.ER` with
    /// the refusal's ERR and EXERR, as [`MotionTask::instruction`] would.
    pub(crate) fn refuse_call<E: LogixFault>(&mut self, h: InstructionHandle, e: E) -> crate::instruction::Fault {
        self.begin(h);
        self.fail(h, e.err(), e.exerr(), e.segment());
        Box::new(e)
    }

    /// Executes an instruction with the control structure `h`: `.EN` set
    /// and everything else cleared, then `run`; its refusal sets `.ER` with
    /// the refusal's ERR, EXERR and SEGMENT. The protocol every instruction
    /// follows (begin, validate, check the axes' state, act).
    pub(crate) fn instruction<T, E: LogixFault>(
        &mut self,
        h: InstructionHandle,
        run: impl FnOnce(&mut Self) -> Result<T, E>,
    ) -> Result<T, E> {
        self.begin(h);
        run(self).inspect_err(|e| self.fail(h, e.err(), e.exerr(), e.segment()))
    }

    /// Shifts `axis`' position frame by `delta`: command and actual
    /// positions, the motion in process on it and the cam's slave offset
    /// (MRP, MAH).
    pub(crate) fn redefine_position(&mut self, axis: AxisHandle, delta: f64) {
        let a = &mut self.axes[axis.0 as usize];
        a.command.position += delta;
        a.actual += delta;
        if let Some(job) = a.job.as_mut() {
            job.profile.shift_position(delta);
            job.target += delta;
        }
        a.watch.last_actual += delta;
        let c = self.cam_axis(axis);
        c.redefined += delta;
        if let Some(r) = c.ramp.as_mut() {
            r.profile.shift_position(delta);
            if let Some(RampPlan {
                aim: RampAim::Move { target },
                ..
            }) = r.plan.as_mut()
            {
                *target += delta;
            }
        }
        c.cam.redefine_slave(delta);
    }

    /// MCCP: calculates `profile` from the first `length` elements of `cam`.
    /// Returns the error also written into the tag.
    #[cfg(test)]
    pub(crate) fn mccp(
        &mut self,
        motion_control: InstructionHandle,
        cam: &[CamElement],
        length: usize,
        start_slope: f64,
        end_slope: f64,
        profile: CamProfileHandle,
    ) -> Result<(), MccpError> {
        self.mccp_from(motion_control, cam, 0, length, start_slope, end_slope, profile)
    }

    /// MCCP with the Cam operand an element of a CAM array, `Cam[start]`:
    /// calculates from `length` elements of `cam_array` starting at `start`.
    /// ERR 26's EXERR is the size of the whole array (the spec: "the number
    /// of cams in the Cam Tag provided"), not the count from `start`.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn mccp_from(
        &mut self,
        motion_control: InstructionHandle,
        cam_array: &[CamElement],
        start: usize,
        length: usize,
        start_slope: f64,
        end_slope: f64,
        profile: CamProfileHandle,
    ) -> Result<(), MccpError> {
        self.begin(motion_control);
        let cam = cam_array.get(start..).unwrap_or(&[]);
        let r = self.cam.profiles[profile.0 as usize]
            .1
            .calculate(cam, length, start_slope, end_slope)
            .map_err(|e| match e {
                MccpError::IllegalCamLength { length, .. } => MccpError::IllegalCamLength {
                    length,
                    elements: cam_array.len(),
                },
                e => e,
            });
        match &r {
            Ok(()) => self.motion_bits_mut(motion_control).dn = true,
            Err(e) => e.write_to(self.motion_bits_mut(motion_control)),
        }
        r
    }

    /// The master position a cam sees (without MRP shifts).
    pub(super) fn cam_master_position(&self, key: MasterKey) -> f64 {
        let (axis, reference) = key;
        let a = &self.axes[axis.0 as usize];
        let p = match reference {
            MasterReference::Actual => a.actual,
            MasterReference::Command => a.command.position,
        };
        p - self.cam.axes.get(axis.0 as usize).map_or(0.0, |c| c.redefined)
    }

    /// MAPC: starts, schedules or preloads a position cam on `call.slave`.
    ///
    /// # Errors
    /// ERR 13 (operand, EXERR = number), 30 (profile Status 1), 32 (Status 0).
    pub(crate) fn mapc(&mut self, call: MapcCall) -> Result<(), MapcError> {
        let mi = call.motion_control;
        self.begin(mi);
        let r = self.mapc_inner(call);
        match &r {
            Ok(()) => {
                let b = self.motion_bits_mut(mi);
                b.dn = true;
                b.ip = true;
            }
            Err(e) => self.fail(mi, e.err(), e.exerr(), 0),
        }
        r
    }

    fn mapc_inner(&mut self, call: MapcCall) -> Result<(), MapcError> {
        let mut mapc = Mapc::new(&call.operands)?;
        self.check_state(call.slave, Need::Motion).map_err(MapcError::State)?;
        // The master decides the direction: either side counts.
        self.check_overtravel(call.slave, 0.0).map_err(MapcError::State)?;
        if call.slave == call.master {
            return Err(MapcError::ParameterOutOfRange {
                operand: crate::mapc::operand::MASTER,
                value: f64::from(call.master.0),
            });
        }
        // Lock positions are compared with MRP-free master positions.
        mapc.master_lock_position -= self.cam.axes.get(call.master.0 as usize).map_or(0.0, |c| c.redefined);
        let tag = &mut self.cam.profiles[call.cam_profile.0 as usize].1;
        let profile: Arc<CamProfile> = tag.acquire().map_err(MapcError::from_status)?;
        // The speed rule (module doc of `crate::mapc`).
        let peak_mps = crate::mapc::peak_slave_speed(
            profile.peak_slope(),
            &mapc,
            self.axes[call.master.0 as usize].config.max_velocity,
        );
        let allowed = crate::mapc::MAX_CAM_SPEED_RATIO * self.axes[call.slave.0 as usize].config.max_velocity;
        if !peak_mps.is_finite() || peak_mps > allowed {
            self.cam.profiles[call.cam_profile.0 as usize].1.release();
            return Err(MapcError::ParameterOutOfRange {
                operand: crate::mapc::operand::SLAVE_SCALING,
                value: mapc.slave_scaling,
            });
        }
        let key = (call.master, mapc.master_reference);
        let slave = self.axes[call.slave.0 as usize].command.position;
        let req = CamRequest {
            tag: (call.motion_control, call.cam_profile),
            master: key,
            mapc,
            profile,
            master_period: self.axes[call.master.0 as usize].config.modulo_period,
        };
        let mut engine = std::mem::take(&mut self.cam_axis(call.slave).cam);
        let r = engine.start(req, slave, |k| self.cam_master_position(k));
        self.cam_axis(call.slave).cam = engine;
        let events = match r {
            Ok(ev) => ev,
            Err(e) => {
                self.cam.profiles[call.cam_profile.0 as usize].1.release();
                return Err(e);
            }
        };
        if mapc.execution_schedule != crate::mapc::ExecutionSchedule::Pending {
            // A cam takes the axis from a move, a gearing, a jog and a time
            // cam; the position cams queued on it are its own.
            self.end_time_cams(call.slave);
            self.take_axis(
                call.slave,
                Takes {
                    cams: false,
                    gear: true,
                    ramp: true,
                },
            );
        }
        self.apply_cam_events(&events);
        Ok(())
    }

    fn apply_cam_events(&mut self, events: &[CamEvent<Tag>]) {
        for ev in events {
            match *ev {
                CamEvent::Active((mi, _)) => self.motion_bits_mut(mi).ac = true,
                CamEvent::Overflow((mi, _)) => self.fail(mi, 179, 0, 0),
                CamEvent::Ended {
                    tag: (mi, profile),
                    complete,
                } => {
                    let b = self.motion_bits_mut(mi);
                    b.ip = false;
                    b.ac = false;
                    b.pc = complete;
                    self.cam.profiles[profile.0 as usize].1.release();
                }
            }
        }
    }

    /// A new single-axis motion takes `axis`: a jog or MAM superimposed
    /// on it folds into the command, its MC_MoveModulo commands and its
    /// coordinated motion abort, and the processes it `takes` end.
    pub(crate) fn take_axis(&mut self, axis: AxisHandle, takes: Takes) {
        self.fold_superimposed(axis);
        self.abort_move(axis);
        if takes.cams {
            self.end_cams(axis);
        }
        if takes.gear {
            self.end_gear(axis);
        }
        if takes.ramp {
            self.end_ramp(axis);
        }
    }

    pub(super) fn abort_move(&mut self, axis: AxisHandle) {
        // Coordinated motion on the axis comes to rest too (task/coord.rs).
        self.release_axis_from_coordinated_motion(axis);
        self.abort_modulo_commands(axis);
    }

    /// Aborts the MC_MoveModulo command running on `axis` and the one
    /// buffered behind it (`CommandAborted`).
    pub(super) fn abort_modulo_commands(&mut self, axis: AxisHandle) {
        let a = &mut self.axes[axis.0 as usize];
        let job_fb = a.job.take().and_then(|j| j.fb);
        let buffered_fb = a.buffered.take().map(|(fb, _)| fb);
        for fb in job_fb.into_iter().chain(buffered_fb) {
            self.finish(fb, Finish::Aborted);
        }
    }

    pub(crate) fn end_ramp(&mut self, axis: AxisHandle) {
        if let Some(r) = self.cam_axis(axis).ramp.take() {
            for mi in r.jog.into_iter().chain(r.stop) {
                self.motion_bits_mut(mi).ip = false;
            }
            if let Some(mi) = r.mv {
                self.motion_bits_mut(mi).end_motion();
            }
        }
    }

    pub(super) fn end_cams(&mut self, axis: AxisHandle) {
        self.end_time_cams(axis);
        let c = self.cam_axis(axis);
        c.cam_drove = false;
        let events = c.cam.stop();
        self.apply_cam_events(&events);
    }

    /// Hook for MoveModulo starts and axis resets: cams and jogs on `axis`
    /// end.
    pub(super) fn release_cam_and_jog(&mut self, axis: AxisHandle) {
        self.end_gear(axis);
        if (axis.0 as usize) < self.cam.axes.len() {
            self.end_cams(axis);
            self.end_ramp(axis);
            let c = self.cam_axis(axis);
            c.limits = LimitFlags::default();
        }
    }

    /// The slave's Position Cam Status, Lock Status and Pending Status.
    pub fn slave_cam_status(&self, axis: AxisHandle) -> SlaveCamStatus {
        self.cam
            .axes
            .get(axis.0 as usize)
            .map(|c| c.cam.status())
            .unwrap_or_default()
    }

    /// Whether a running jog, MAM or stop ramp on `axis` is overshooting
    /// ([`crate::profile::Profile::overshoot_at`]).
    pub(super) fn ramp_overshoots(&self, axis: AxisHandle) -> bool {
        self.cam
            .axes
            .get(axis.0 as usize)
            .and_then(|c| c.ramp.as_ref())
            .is_some_and(|r| r.profile.overshoot_at(r.t_s))
    }

    /// Whether the last update's command exceeded the axis' limits.
    pub fn limits_exceeded(&self, axis: AxisHandle) -> LimitFlags {
        self.cam.axes.get(axis.0 as usize).map(|c| c.limits).unwrap_or_default()
    }

    /// The sum of MRP redefinitions on `axis`: the axis' positions are the
    /// device's (joint's) positions plus this.
    pub fn position_offset(&self, axis: AxisHandle) -> f64 {
        self.cam.axes.get(axis.0 as usize).map_or(0.0, |c| c.redefined)
    }

    /// A master offset move on the slave `axis`: its cams see their master
    /// `delta` further (the profile shifts by −`delta` along the master).
    #[cfg(test)]
    pub(crate) fn shift_master_offset(&mut self, axis: AxisHandle, delta: f64) {
        self.cam_axis(axis).cam.shift_master_offset(delta);
    }

    /// The cam coordinate of the running cam on `axis` (cam master units).
    pub fn cam_coordinate(&self, axis: AxisHandle) -> Option<f64> {
        self.cam.axes.get(axis.0 as usize).and_then(|c| c.cam.cam_coordinate())
    }

    /// Hook for [`MotionTask::stop_all_axes`]: ends the cams and the jog on
    /// `axis` and ramps it to rest from its command state with its configured
    /// deceleration and jerk (as the MoveModulo commands there); a gearing
    /// on it ends the same way. Returns whether the axis had a cam, jog or
    /// gearing to stop.
    pub(super) fn stop_cam_and_jog(&mut self, axis: AxisHandle) -> bool {
        let geared = self.end_gear(axis);
        let (drives, ramp, pending) = self.cam.axes.get(axis.0 as usize).map_or((false, false, false), |c| {
            (c.cam.drives(), c.ramp.is_some(), c.cam.status().pending)
        });
        if !(geared || drives || ramp) {
            // A preloaded Pending cam moves nothing but ends as well.
            if pending {
                self.end_cams(axis);
            }
            return false;
        }
        self.end_cams(axis);
        let profile = self.rest_profile(axis);
        self.start_stop_ramp(axis, profile);
        true
    }

    /// A ramp of `axis` from its command state to rest with its configured
    /// deceleration and jerk (S-curve; trapezoidal without a jerk).
    pub(super) fn rest_profile(&self, axis: AxisHandle) -> Profile {
        let a = &self.axes[axis.0 as usize];
        let start = a.command.state();
        let cfg = &a.config;
        let vmax = cfg.max_velocity.max(start.velocity.abs());
        let limits = Limits::s_curve(
            vmax,
            cfg.max_acceleration,
            cfg.max_deceleration,
            cfg.max_jerk,
            cfg.max_jerk,
        )
        .or_else(|_| Limits::trapezoidal(vmax, cfg.max_acceleration, cfg.max_deceleration));
        match limits {
            Ok(limits) => Profile::to_velocity(start, 0.0, &limits),
            Err(_) => Profile::hold(start),
        }
    }

    /// Starts a stop ramp along `profile` on `axis` (no control structure):
    /// a fault's Stop Planner action.
    pub(super) fn start_stop_ramp(&mut self, axis: AxisHandle, profile: Profile) {
        self.end_ramp(axis);
        self.cam_axis(axis).ramp = Some(RampRun::new(profile));
    }

    /// Whether `axis` jogs (MAJ), runs a stop ramp, and moves (MAM).
    pub(super) fn jog_and_stop_status(&self, axis: AxisHandle) -> (bool, bool, bool) {
        match self.cam.axes.get(axis.0 as usize).and_then(|c| c.ramp.as_ref()) {
            Some(r) => (r.jog.is_some(), r.jog.is_none() && r.mv.is_none(), r.mv.is_some()),
            None => (false, false, false),
        }
    }

    /// Whether a position cam or a gearing drives `axis` now.
    pub(super) fn cam_drives(&self, axis: AxisHandle) -> bool {
        self.cam.axes.get(axis.0 as usize).is_some_and(|c| c.cam.drives()) || self.axes[axis.0 as usize].gear.is_some()
    }

    /// A gearing or a coordinated move takes `axis`: a jog or MAM ramp on
    /// it goes on superimposed (`task/superimposed.rs`); a stop ramp ends
    /// (its MAS loses `.IP`).
    pub(super) fn superimpose_running_ramp(&mut self, axis: AxisHandle) {
        let ramp = self.cam.axes.get_mut(axis.0 as usize).and_then(|c| c.ramp.take());
        if let Some(r) = ramp {
            match (r.jog, r.mv) {
                (Some(j), _) => self.superimpose_ramp(axis, &r.profile, r.t_s, j, SuperKind::Jog),
                (None, Some(m)) => self.superimpose_ramp(axis, &r.profile, r.t_s, m, SuperKind::Move),
                (None, None) => {
                    if let Some(mi) = r.stop {
                        self.motion_bits_mut(mi).ip = false;
                    }
                }
            }
        }
    }

    /// A coordinated move takes `axis`: a jog or MAM ramp on it goes on
    /// superimposed (`task/superimposed.rs`); stop ramps, cams and gearing
    /// end.
    pub(super) fn superimpose_or_release(&mut self, axis: AxisHandle) {
        self.superimpose_running_ramp(axis);
        self.release_cam_and_jog(axis);
    }

    /// Starts a MAM's move along `profile` on `axis` (whatever ramp ran
    /// there ends): `.IP` and `.AC` until the command reaches the end.
    pub(super) fn start_move_ramp(
        &mut self,
        axis: AxisHandle,
        profile: Profile,
        plan: RampPlan,
        control: InstructionHandle,
    ) {
        self.end_ramp(axis);
        self.cam_axis(axis).ramp = Some(RampRun {
            mv: Some(control),
            plan: Some(plan),
            ..RampRun::new(profile)
        });
        let b = self.motion_bits_mut(control);
        b.ip = true;
        b.ac = true;
    }

    /// Whether `axis` runs a stop ramp (MAS or a stop of all axes).
    pub(super) fn is_ramping_to_rest(&self, axis: AxisHandle) -> bool {
        self.cam
            .axes
            .get(axis.0 as usize)
            .is_some_and(|c| c.ramp.as_ref().is_some_and(|r| r.jog.is_none() && r.mv.is_none()))
    }

    /// Advances jogs, stop ramps and position cams by one coarse update
    /// (called by [`MotionTask::update`] after the MoveModulo commands).
    pub(super) fn advance_cams_and_jogs(&mut self) {
        let dt = self.dt_s;
        let updates = self.updates;
        // A false rung clears `.EN` once `.DN` or `.ER` is set: until then
        // it stays pending.
        let pending = std::mem::take(&mut self.cam.rung_false);
        for (h, at) in pending {
            if updates < at + 2 {
                self.cam.rung_false.push((h, at));
                continue;
            }
            self.rung_false(h);
            if self.motion_bits(h).en {
                self.cam.rung_false.push((h, at));
            }
        }
        for i in 0..self.cam.axes.len().min(self.axes.len()) {
            let axis = AxisHandle(i as u32);
            let Some(r) = self.cam.axes[i].ramp.as_mut() else {
                continue;
            };
            r.t_s += dt;
            let sample = r.profile.sample(r.t_s);
            let ended = r.jog.is_none() && r.t_s >= r.profile.duration_s();
            let (stop_mi, move_mi) = (r.stop, r.mv);
            let (accel, decel) = r.profile.accel_decel_at(r.t_s);
            self.set_command(axis, sample);
            if let Some(mi) = move_mi {
                self.motion_bits_mut(mi).follow_ramp(accel, decel, ended);
            }
            let stopped = ended;
            if stopped {
                self.cam.axes[i].ramp = None;
                self.axes[i].command.velocity = 0.0;
                if let Some(mi) = stop_mi {
                    let b = self.motion_bits_mut(mi);
                    b.ip = false;
                    b.pc = true;
                }
            }
        }
        for i in 0..self.cam.axes.len().min(self.axes.len()) {
            let axis = AxisHandle(i as u32);
            if !self.cam.axes[i].cam.drives() && !self.cam.axes[i].cam_drove {
                continue;
            }
            let old = self.axes[i].command;
            let mut engine = std::mem::take(&mut self.cam.axes[i].cam);
            let (position, events) = engine.update(old.position, |k| self.cam_master_position(k));
            self.cam.axes[i].cam = engine;
            self.apply_cam_events(&events);
            self.cam.axes[i].cam_drove = position.is_some();
            match position {
                Some(p) => {
                    let v = (p - old.position) / dt;
                    let acc = (v - old.velocity) / dt;
                    self.set_command(
                        axis,
                        Sample {
                            position: p,
                            velocity: v,
                            acceleration: acc,
                            jerk: 0.0,
                        },
                    );
                }
                None => self.set_command(
                    axis,
                    Sample {
                        position: old.position,
                        ..Sample::default()
                    },
                ),
            }
        }
    }

    pub(super) fn set_command(&mut self, axis: AxisHandle, sample: Sample) {
        let a = &mut self.axes[axis.0 as usize];
        a.command = sample;
        if !a.fed {
            a.actual = sample.position;
        }
        if sample.velocity != 0.0 {
            a.last_direction = sample.velocity.signum();
        }
        let flags = LimitFlags {
            velocity: sample.velocity.abs() > a.config.max_velocity * (1.0 + 1e-9),
            acceleration: sample.acceleration.abs()
                > a.config.max_acceleration.max(a.config.max_deceleration) * (1.0 + 1e-9),
        };
        self.cam_axis(axis).limits = flags;
    }
}

#[cfg(test)]
mod tests;
