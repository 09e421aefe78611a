//! Superimposed single-axis motion: a MAM or MAJ that runs *on top of*
//! what drives the axis (a position cam, coordinated motion), as the MAPC
//! and MCCM documents require ("Electronic camming remains active through
//! any subsequent execution of jog, or move processes for the Slave axis";
//! MCCM's Merge Disabled and Coordinated Motion leave single-axis motion
//! running).
//!
//! Each axis has at most one superimposed run: a profile in *offset*
//! space (it starts at 0). The axis' command is the sum of its base (what
//! the drivers — cam, coordinated path, MCT — write) and the run's offset:
//! [`MotionTask::update`] takes the offset it added last time out of the
//! command before the drivers advance, and adds the new one after them.
//! Outside an update every command the task reports, and every command an
//! instruction starts from, is the sum.
//!
//! When a run starts:
//! * a MAM with Merge Disabled on an axis a cam or coordinated motion
//!   drives: the move's distance (its target from the command minus the
//!   command) in offset space, from the running offset's state (a second
//!   MAM replaces the first, as on an idle axis);
//! * a coordinated move (MCLM/MCCM with Merge Disabled or Coordinated
//!   Motion) that starts on an axis a MAJ jogs or a MAM moves: the jog or
//!   move goes on in offset space, its control structure keeps `.IP`, and
//!   the coordinated path starts from where the axis is, at rest.
//!
//! When it ends:
//! * a superimposed MAM completes (`.PC`) and its offset stays: the axis
//!   runs its base motion shifted by the distance;
//! * a start that takes the whole axis (MAM or MAJ with merge, MAPC,
//!   MC_MoveModulo, a coordinated move with Merge All Motion, a disable)
//!   keeps the offset in the command and ends the run (`.IP` off, no
//!   `.PC`);
//! * MAS (stop type all, jog or move) and MCS (stop type all) on the axis
//!   ramp the offset's velocity to 0 at the axis' maximum deceleration.
//!
//! Cams and MC_MoveModulo commands are never superimposed: a coordinated
//! move ends them on its axes (as before).

use super::MotionTask;
use crate::profile::{Limits, Profile, Sample, State};
use crate::task::engine::{SuperKind, SuperRun};
use crate::task::handles::{AxisHandle, InstructionHandle};

impl MotionTask {
    /// The superimposed offset in the axis' command after the last update
    /// (position, velocity, acceleration; `None` without a superimposed
    /// run): the trace's `sup_pos` and `sup_vel`.
    pub fn superimposed(&self, axis: AxisHandle) -> Option<Sample> {
        self.axes[axis.0 as usize].superimposed.as_ref().map(|r| r.applied)
    }

    /// Whether `axis` has a superimposed run that still moves (a jog or a
    /// move, not a held offset).
    pub(super) fn superimposed_moving(&self, axis: AxisHandle) -> Option<SuperKind> {
        let r = self.axes[axis.0 as usize].superimposed.as_ref()?;
        (r.kind != SuperKind::Hold).then_some(r.kind)
    }

    /// Starts (or replaces) a superimposed move of `distance` on `axis`
    /// with `limits`, from the offset's current state.
    pub(super) fn superimpose_move(
        &mut self,
        axis: AxisHandle,
        control: InstructionHandle,
        distance: f64,
        limits: &Limits,
    ) {
        let (from, previous) = match self.axes[axis.0 as usize].superimposed.take() {
            Some(r) => (r.applied, r.control.filter(|_| r.kind != SuperKind::Hold)),
            None => (Sample::default(), None),
        };
        if let Some(mi) = previous {
            self.motion_bits_mut(mi).end_motion();
        }
        let profile = Profile::to_position(from.state(), from.position + distance, 0.0, limits);
        self.axes[axis.0 as usize].superimposed = Some(SuperRun {
            profile,
            t_s: 0.0,
            control: Some(control),
            kind: SuperKind::Move,
            applied: from,
        });
        let b = self.motion_bits_mut(control);
        b.ip = true;
        b.ac = true;
    }

    /// A coordinated move takes `axis`: its jog or MAM ramp (`profile`, `t_s`
    /// into it, driven by `control`) goes on superimposed, and the base
    /// command is left at rest where the axis is.
    pub(super) fn superimpose_ramp(
        &mut self,
        axis: AxisHandle,
        profile: &Profile,
        t_s: f64,
        control: InstructionHandle,
        kind: SuperKind,
    ) {
        self.fold_superimposed(axis);
        let a = &mut self.axes[axis.0 as usize];
        let now = profile.sample(t_s);
        let mut offset_profile = profile.clone();
        offset_profile.shift_position(-now.position);
        let applied = Sample {
            position: 0.0,
            velocity: now.velocity,
            acceleration: now.acceleration,
            jerk: now.jerk,
        };
        // The command is the sum: base (at rest here) + offset (moving);
        // inside an update's advance it is the base alone.
        a.command = if self.superimposed_removed {
            Sample {
                position: now.position,
                ..Sample::default()
            }
        } else {
            Sample {
                position: now.position,
                ..applied
            }
        };
        a.superimposed = Some(SuperRun {
            profile: offset_profile,
            t_s,
            control: Some(control),
            kind,
            applied,
        });
    }

    /// Ends the superimposed run of `axis`, keeping its offset in the
    /// command (the base takes it over): its control structure loses `.IP`
    /// without `.PC`.
    pub(super) fn fold_superimposed(&mut self, axis: AxisHandle) {
        let Some(r) = self.axes[axis.0 as usize].superimposed.take() else {
            return;
        };
        if let (Some(mi), true) = (r.control, r.kind != SuperKind::Hold) {
            self.motion_bits_mut(mi).end_motion();
        }
        if self.superimposed_removed {
            // Inside an update's advance the command is the base alone.
            let a = &mut self.axes[axis.0 as usize];
            a.command.position += r.applied.position;
            a.command.velocity += r.applied.velocity;
            a.command.acceleration += r.applied.acceleration;
        }
    }

    /// MAS or MCS on `axis`: a superimposed jog or move ramps its offset's
    /// velocity to 0 at the axis' maximum deceleration (its control
    /// structure loses `.IP`). Returns whether one was running.
    pub(super) fn stop_superimposed(&mut self, axis: AxisHandle) -> bool {
        let decel = self.axes[axis.0 as usize].config.max_deceleration;
        let Some(r) = self.axes[axis.0 as usize].superimposed.as_mut() else {
            return false;
        };
        if r.kind == SuperKind::Hold {
            return false;
        }
        let state = State {
            acceleration: 0.0,
            ..r.applied.state()
        };
        let vmax = state.velocity.abs().max(f64::MIN_POSITIVE);
        r.profile = match Limits::trapezoidal(vmax, decel, decel) {
            Ok(l) => Profile::to_velocity(state, 0.0, &l),
            Err(_) => Profile::hold(state),
        };
        r.t_s = 0.0;
        r.kind = SuperKind::Hold;
        if let Some(mi) = r.control.take() {
            self.motion_bits_mut(mi).end_motion();
        }
        true
    }

    /// Start of an update's advance: every command loses the offset added
    /// last time (it is the base again).
    pub(super) fn remove_superimposed(&mut self) {
        self.superimposed_removed = true;
        for a in &mut self.axes {
            if let Some(r) = &a.superimposed {
                a.command.position -= r.applied.position;
                a.command.velocity -= r.applied.velocity;
                a.command.acceleration -= r.applied.acceleration;
            }
        }
    }

    /// End of an update's advance: every run advances and its offset is
    /// added to the command; a superimposed MAM that reached its end sets
    /// `.PC` and its offset is held from then on.
    pub(super) fn add_superimposed(&mut self) {
        self.superimposed_removed = false;
        let dt = self.dt_s;
        for i in 0..self.axes.len() {
            let Some(r) = self.axes[i].superimposed.as_mut() else {
                continue;
            };
            r.t_s += dt;
            let s = r.profile.sample(r.t_s);
            r.applied = s;
            let ended = r.t_s >= r.profile.duration_s() && r.kind != SuperKind::Jog;
            let (accel, decel) = r.profile.accel_decel_at(r.t_s);
            let (kind, control) = (r.kind, r.control);
            if ended {
                r.kind = SuperKind::Hold;
                r.control = None;
                r.applied.velocity = 0.0;
                r.applied.acceleration = 0.0;
            }
            let applied = r.applied;
            let a = &mut self.axes[i];
            a.command.position += applied.position;
            a.command.velocity += applied.velocity;
            a.command.acceleration += applied.acceleration;
            if !a.fed {
                a.actual = a.command.position;
            }
            if a.command.velocity != 0.0 {
                a.last_direction = a.command.velocity.signum();
            }
            if let (Some(mi), SuperKind::Move) = (control, kind) {
                self.motion_bits_mut(mi).follow_ramp(accel, decel, ended);
            }
        }
    }
}

#[cfg(test)]
mod tests;
