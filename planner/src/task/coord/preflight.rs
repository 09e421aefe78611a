//! Pre-flight hooks of coordinated motion: which MCLM/MCCM moves
//! started in the last update, so that the twin can sweep their paths
//! before the physics runs them, and the rejection of such a move.
//!
//! Choices (the spec has no pre-flight check, and Logix has no error code
//! for a rejected path):
//! * A move is reported when it **starts** (becomes a running component),
//!   as an MC_MoveModulo is swept when it becomes `Active`: at once when the
//!   system is idle or on a merge, at the blend point of the move before it
//!   (termination types 2, 3, 6), or when the move before it has ended. A
//!   queued (pending) move is not reported while it waits: where it starts
//!   from and when are known only then.
//! * A rejected move gets `.ER` with ERR [`ERR_PATH_COLLISION`] (200), EXERR
//!   0. 200 is outside the range of the Logix motion error codes (1 to
//!   about 100), so it cannot be mistaken for one of the spec's errors;
//!   `.DN`, `.IP`, `.AC`, `.PC`, `.ACCEL` and `.DECEL` are cleared (`.EN`
//!   clears with the rung, as after any error).
//! * Rejected in the update it started in, as the only motion of its
//!   system, with the system's axes at rest when it started: the move
//!   leaves no trace. The axes' command state (position, velocity,
//!   acceleration, jerk), direction memory and, when not fed back, actual
//!   position are restored bit for bit, the system's status goes idle, and
//!   nothing moves.
//! * Otherwise (a blend successor, a merge over motion that is braking, a
//!   later update, axes that were moving when it started) the move brakes to
//!   rest along its path with its own deceleration and jerk, like an MCS of
//!   that move alone; the motion before it continues. Its instruction no
//!   longer follows it.
//! * A move queued behind the rejected one (it would start at the rejected
//!   move's end point) is cancelled: it loses `.IP`/`.AC` without `.ER`, as
//!   after an MCS. A held move (queue full) is verified later from where the
//!   system then stands.
//! * A pending move can be rejected too: it leaves the queue.

use super::{add_displacement, rest_length};
use crate::profile::{Profile, State, stopping_distance};
use crate::task::MotionTask;
use crate::task::engine::{ERR_PATH_COLLISION, IdleState, Start, StartedCoordMove};
use crate::task::handles::{CoordHandle, CoordInstructionHandle};

impl MotionTask {
    /// The state a component starting now on `cs` would be undone to.
    pub(super) fn record_start(&self, cs: CoordHandle) -> Start {
        let sys = &self.coord.systems[cs.0 as usize];
        let idle = sys.components.is_empty().then(|| IdleState {
            commands: sys.axes.iter().map(|a| self.axes[a.0 as usize].command).collect(),
            last_direction: sys
                .axes
                .iter()
                .map(|a| self.axes[a.0 as usize].last_direction)
                .collect(),
            velocity: sys.velocity.clone(),
            acceleration: sys.acceleration.clone(),
        });
        Start {
            update: self.updates,
            idle,
        }
    }

    /// Hook for [`MotionTask::execute_coordinated`]: a move it started
    /// between two updates is first advanced by the next one.
    pub(super) fn started_before_update(&mut self, h: CoordInstructionHandle) {
        let updates = self.updates;
        for sys in &mut self.coord.systems {
            for c in &mut sys.components {
                if c.instr == Some(h) && c.start.update == updates {
                    c.start.update = updates + 1;
                }
            }
        }
    }

    /// The coordinated moves that started in the last [`MotionTask::update`]
    /// (a move executed between two updates counts as started in the
    /// second), in system order.
    pub fn coord_moves_started(&self) -> Vec<StartedCoordMove<'_>> {
        let mut v = Vec::new();
        for (i, sys) in self.coord.systems.iter().enumerate() {
            for c in &sys.components {
                if let Some(h) = c.instr
                    && c.start.update == self.updates
                {
                    v.push(StartedCoordMove {
                        instruction: h,
                        system: CoordHandle(i as u32),
                        mv: &c.mv,
                        profile: &c.profile,
                        progress: c.progress,
                    });
                }
            }
        }
        v
    }

    /// Rejects the coordinated move of `instr` (running or pending): `.ER`
    /// with ERR [`ERR_PATH_COLLISION`]; undone when rejected in the update it
    /// started in from rest, otherwise braked to rest along its path (see
    /// the module docs). Returns whether `instr` had a move to reject.
    ///
    /// # Examples
    /// ```
    /// use planner::axis::{AxisConfig, AxisKind};
    /// use planner::coord::{CoordMoveInputs, CoordinateSystemConfig};
    /// use planner::task::{CoordCall, ERR_PATH_COLLISION, MotionTask};
    /// let mut task = MotionTask::new(0.004).unwrap();
    /// let x = task.add_axis(AxisConfig::new("X", AxisKind::Linear), 0.0).unwrap();
    /// let y = task.add_axis(AxisConfig::new("Y", AxisKind::Linear), 0.0).unwrap();
    /// let config = CoordinateSystemConfig { axis_count: 2, primary_axes: 2, ..CoordinateSystemConfig::new("CS") };
    /// let cs = task.add_coordinate_system(config, &[x, y]).unwrap();
    /// let mc = task.add_coord_instruction("MC1", cs, CoordCall::Mclm(CoordMoveInputs::default()));
    /// let line = CoordMoveInputs { position: vec![0.3, 0.4], ..Default::default() };
    /// task.set_coord_instruction(mc, true, CoordCall::Mclm(line));
    /// task.update();
    /// let started = task.coord_moves_started();
    /// assert_eq!(started[0].instruction, mc);
    /// assert!(task.reject_coord_move(mc));
    /// let b = task.coord_bits(mc);
    /// assert!(b.er && !b.dn && !b.ip && b.err == ERR_PATH_COLLISION);
    /// task.update();
    /// assert_eq!(task.axis_state(y).command_position, 0.0);
    /// ```
    pub fn reject_coord_move(&mut self, instr: CoordInstructionHandle) -> bool {
        let cs = self.coord.instructions[instr.0 as usize].system;
        let updates = self.updates;
        let sys = &mut self.coord.systems[cs.0 as usize];
        let mut cancelled = Vec::new();
        if sys.pending.as_ref().is_some_and(|(h, _)| *h == instr) {
            sys.pending = None;
        } else {
            let Some(k) = sys.components.iter().position(|c| c.instr == Some(instr)) else {
                return false;
            };
            cancelled.extend(sys.pending.take().map(|(h, _)| h));
            let c = &sys.components[k];
            let undo = c.start.update >= updates
                && sys.components.len() == 1
                && c.start.idle.as_ref().is_some_and(IdleState::at_rest);
            if undo {
                let c = sys.components.pop().expect("k exists");
                let idle = c.start.idle.expect("checked");
                sys.base = c.mv.path().start().to_vec();
                sys.velocity = idle.velocity;
                sys.acceleration = idle.acceleration;
                sys.status.clear_motion();
                let (axes, taken) = (sys.axes.clone(), sys.taken.clone());
                for (i, axis) in axes.into_iter().enumerate() {
                    let a = &mut self.axes[axis.0 as usize];
                    if a.job.is_some() || taken.contains(&axis) {
                        continue;
                    }
                    a.command = idle.commands[i];
                    a.last_direction = idle.last_direction[i];
                    if !a.fed {
                        a.actual = idle.commands[i].position;
                    }
                }
                // The joints of a transform this system drives were moved
                // by its first step too: undo that step.
                self.mct_undo_update(cs);
            } else {
                let c = &mut sys.components[k];
                let now = c.s();
                let length = c.mv.path().length();
                match c.mv.limits().copied() {
                    Some(lim) => {
                        let state = now.state();
                        if state.position + stopping_distance(state, &lim) < length {
                            c.profile = Profile::to_velocity(state, 0.0, &lim);
                            c.progress = 0.0;
                        }
                    }
                    None => {
                        c.profile = Profile::hold(State::at_rest(now.position));
                        c.progress = 0.0;
                    }
                }
                c.stopping = true;
                c.blend_at = None;
                c.instr = None;
            }
        }
        // The next move starts where the remaining motion ends.
        let sys = &mut self.coord.systems[cs.0 as usize];
        let mut end = sys.base.clone();
        for c in &sys.components {
            let s = if c.stopping {
                rest_length(c, None)
            } else {
                c.mv.path().length()
            };
            add_displacement(&mut end, c, s);
        }
        sys.queue_end = end;
        self.refresh_queue_status(cs);
        for h in cancelled {
            self.cbits(h).end_motion();
        }
        let b = self.cbits(instr);
        b.set_error(ERR_PATH_COLLISION, 0, 0);
        b.dn = false;
        b.pc = false;
        b.end_motion();
        true
    }
}

#[cfg(test)]
mod tests;
