//! Running coordinated motion each update: advancing the systems along
//! their paths, contour junctions, writing the axes, completing moves.

use crate::coord::{CoordMove, CoordMoveError, Driver, TerminationType, primary_of};
use crate::profile::{Limits, Profile, Sample, State, stopping_distance};
use crate::task::MotionTask;
use crate::task::engine::Component;
use crate::task::handles::{CoordHandle, CoordInstructionHandle};
use crate::vector::{cross, dot, norm, sub};

impl MotionTask {
    pub(super) fn refresh_queue_status(&mut self, cs: CoordHandle) {
        let sys = &mut self.coord.systems[cs.0 as usize];
        sys.status.move_pending = sys.pending.is_some();
        sys.status.move_pending_queue_full = sys.pending.is_some();
    }

    /// Step 2b of an update: advances every coordinate system by one coarse
    /// update and writes its axes' command positions.
    pub(in crate::task) fn advance_coordinate_systems(&mut self) {
        for i in 0..self.coord.systems.len() {
            self.advance_system(CoordHandle(i as u32));
        }
    }

    pub(super) fn advance_system(&mut self, cs: CoordHandle) {
        let dt = self.dt_s;
        let master_now = {
            let sys = &self.coord.systems[cs.0 as usize];
            sys.master.map(|m| {
                let a = &self.axes[m.0 as usize];
                if sys.master_actual {
                    a.actual
                } else {
                    a.command.position
                }
            })
        };
        let sys = &mut self.coord.systems[cs.0 as usize];
        let master_prev = sys.master_prev.or(master_now).unwrap_or(0.0);
        sys.master_prev = master_now;
        for c in &mut sys.components {
            let delta = match c.mv.driver() {
                Driver::Time => dt,
                Driver::Master => c.lock.advance(master_prev, master_now.unwrap_or(master_prev)),
            };
            let before = c.progress;
            c.progress = (c.progress + delta).max(0.0);
            c.last_delta = c.progress - before;
        }
        self.plan_contour_junction(cs);
        // Blends: the newest component hands over at its blend point.
        loop {
            let sys = &mut self.coord.systems[cs.0 as usize];
            let Some(lead) = sys.components.last_mut() else { break };
            let Some(at) = lead.blend_at else { break };
            if lead.successor_started || lead.progress < at {
                break;
            }
            let Some((_, pending)) = &sys.pending else { break };
            // Time matching: the pending move's acceleration ends no sooner
            // than the lead's motion, so the two never add up to more than
            // the faster programmed speed.
            let at = if pending.driver() == lead.mv.driver() {
                at.max(lead.profile.duration_s() - acceleration_time(pending))
            } else {
                at
            };
            if lead.progress < at {
                break;
            }
            let leftover = (lead.progress - at).min(lead.last_delta.max(0.0));
            let (next, mv) = sys.pending.take().expect("checked above");
            if self.fail_idle_master_switch(cs, next, &mv) {
                // The lead runs on to its end point, as if nothing was queued.
                self.refresh_queue_status(cs);
                break;
            }
            let sys = &mut self.coord.systems[cs.0 as usize];
            let lead = sys.components.last_mut().expect("checked above");
            lead.successor_started = true;
            let finished = lead.instr;
            let initial = if lead.contour {
                let end = lead.profile.final_state();
                State {
                    position: 0.0,
                    velocity: end.velocity,
                    acceleration: end.acceleration,
                }
            } else {
                State::at_rest(0.0)
            };
            sys.status.command_pos_tolerance = false;
            if let Some(h) = finished {
                let b = self.cbits(h);
                b.pc = true;
                b.ac = false;
                b.accel = false;
                b.decel = false;
            }
            self.start_component_from(cs, next, mv, leftover, initial);
            self.refresh_queue_status(cs);
        }
        self.write_axes(cs);
        self.complete_components(cs);
    }

    /// Follow contour (termination types 4 and 5): while a move of either
    /// type leads and a move of the same driver is pending, its remaining
    /// profile is replanned from its current state to reach its end point
    /// at the junction speed, the lower of the two programmed speeds,
    /// limited to what the pending move can still stop from within its own
    /// length; the pending move then starts at that speed when the lead
    /// reaches its end point. Without a pending move (or when it leaves the
    /// queue again) the lead ends at rest.
    pub(super) fn plan_contour_junction(&mut self, cs: CoordHandle) {
        let sys = &mut self.coord.systems[cs.0 as usize];
        let pending = sys.pending.as_ref().map(|(_, mv)| mv);
        let Some(lead) = sys.components.last_mut() else { return };
        let contour_type = matches!(
            lead.mv.termination(),
            TerminationType::FollowContourConstrained | TerminationType::FollowContourUnconstrained
        );
        if !contour_type
            || lead.successor_started
            || lead.stopping
            || lead.held
            || lead.progress >= lead.profile.duration_s()
        {
            return;
        }
        let Some(limits) = lead.mv.limits().copied() else {
            return;
        };
        let next = pending.filter(|mv| mv.driver() == lead.mv.driver() && mv.limits().is_some());
        let junction = match next {
            Some(mv) if !lead.contour => {
                let next_limits = *mv.limits().expect("filtered");
                let mut v = limits.velocity().min(next_limits.velocity());
                let fits = |v: f64| {
                    stopping_distance(
                        State {
                            position: 0.0,
                            velocity: v,
                            acceleration: 0.0,
                        },
                        &next_limits,
                    ) <= mv.path().length()
                };
                if !fits(v) {
                    let (mut lo, mut hi) = (0.0, v);
                    for _ in 0..60 {
                        let mid = 0.5 * (lo + hi);
                        if fits(mid) { lo = mid } else { hi = mid }
                    }
                    v = lo;
                }
                v
            }
            None if lead.contour => 0.0,
            _ => return,
        };
        let now = lead.profile.sample(lead.progress);
        let from = State {
            position: now.position,
            velocity: now.velocity,
            acceleration: now.acceleration,
        };
        lead.profile = Profile::to_position(from, lead.mv.path().length(), junction, &limits);
        lead.progress = 0.0;
        lead.contour = junction > 0.0;
        lead.blend_at = lead.contour.then(|| lead.profile.duration_s());
    }

    pub(super) fn write_axes(&mut self, cs: CoordHandle) {
        let dt = self.dt_s;
        let sys = &mut self.coord.systems[cs.0 as usize];
        if sys.components.is_empty() {
            sys.velocity.iter_mut().for_each(|v| *v = 0.0);
            sys.acceleration.iter_mut().for_each(|v| *v = 0.0);
            return;
        }
        let n = sys.axes.len();
        let mut position = sys.base.clone();
        let mut velocity = vec![0.0; n];
        let (mut p, mut d) = (vec![0.0; n], vec![0.0; n]);
        for c in &sys.components {
            let s = c.s();
            let speed = match c.mv.driver() {
                Driver::Time => s.velocity,
                Driver::Master => s.velocity * c.last_delta / dt,
            };
            c.mv.path().point(s.position, &mut p, &mut d);
            let start = c.mv.path().start();
            for i in 0..n {
                // (position − start) + p: exactly p at the end of a lone move.
                position[i] = (position[i] - start[i]) + p[i];
                velocity[i] += d[i] * speed;
            }
        }
        let mut acceleration = vec![0.0; n];
        let mut jerk = vec![0.0; n];
        for i in 0..n {
            acceleration[i] = (velocity[i] - sys.velocity[i]) / dt;
            jerk[i] = (acceleration[i] - sys.acceleration[i]) / dt;
        }
        sys.velocity = velocity.clone();
        sys.acceleration = acceleration.clone();
        let axes = sys.axes.clone();
        let taken = sys.taken.clone();
        for (i, axis) in axes.into_iter().enumerate() {
            let a = &mut self.axes[axis.0 as usize];
            if a.job.is_some() || taken.contains(&axis) {
                continue;
            }
            a.command = Sample {
                position: position[i],
                velocity: velocity[i],
                acceleration: acceleration[i],
                jerk: jerk[i],
            };
            if !a.fed {
                a.actual = position[i];
            }
            if velocity[i] != 0.0 {
                a.last_direction = velocity[i].signum();
            }
        }
    }

    pub(super) fn complete_components(&mut self, cs: CoordHandle) {
        let actual = {
            let sys = &self.coord.systems[cs.0 as usize];
            // The path's own part of each actual position: a superimposed
            // jog or move is not the path's to settle.
            sys.axes
                .iter()
                .map(|&a| self.axes[a.0 as usize].actual - self.superimposed(a).map_or(0.0, |s| s.position))
                .collect::<Vec<_>>()
        };
        let sys = &mut self.coord.systems[cs.0 as usize];
        let primary = sys.system.config().primary_axes;
        let actual_tolerance = sys.system.config().actual_tolerance;
        let mut finished_ip = Vec::new();
        let mut finished_pc = Vec::new();
        // Older components end when their own profile ends.
        let mut i = 0;
        while i + 1 < sys.components.len() {
            if sys.components[i].done() {
                let c = sys.components.remove(i);
                absorb(&mut sys.base, &c, i == 0);
                finished_ip.extend(c.instr);
            } else {
                i += 1;
            }
        }
        let mut start_pending = false;
        if let Some(lead) = sys.components.last()
            && lead.done()
        {
            let satisfied = lead.stopping
                || lead.mv.termination() != TerminationType::ActualTolerance
                || norm(sub(
                    primary_of(&actual, primary),
                    primary_of(lead.mv.path().end(), primary),
                )) <= actual_tolerance;
            if satisfied {
                if lead.mv.termination() == TerminationType::ActualTolerance && !lead.stopping {
                    sys.status.actual_pos_tolerance = true;
                }
                let c = sys.components.pop().expect("lead exists");
                let oldest = sys.components.is_empty();
                absorb(&mut sys.base, &c, oldest);
                if let Some(h) = c.instr {
                    finished_pc.push(h);
                }
                start_pending = sys.pending.is_some();
            }
        }
        // Status of what is still running.
        let lead = sys.components.last();
        let blending = sys.components.len() > 1;
        let (accel, decel) = lead.map_or((false, false), |c| c.profile.accel_decel_at(c.progress));
        sys.status.accel = !blending && accel;
        sys.status.decel = !blending && decel;
        if let Some(c) = lead
            && !c.stopping
            && c.mv.path().length() - c.s().position < c.mv.command_tolerance()
        {
            sys.status.command_pos_tolerance = true;
        }
        sys.status.move_transition = blending && !collinear_junction(&sys.components);
        sys.status.coord_motion_lock = lead.is_some_and(|c| c.mv.driver() == Driver::Master && c.lock.locked);
        let component_bits: Vec<(CoordInstructionHandle, bool, bool)> = sys
            .components
            .iter()
            .enumerate()
            .filter_map(|(k, c)| {
                let (a, d) = c.profile.accel_decel_at(c.progress);
                let is_lead = k + 1 == sys.components.len();
                c.instr.map(|h| (h, is_lead && a, is_lead && d))
            })
            .collect();
        let idle = sys.components.is_empty();
        if idle && !start_pending {
            sys.status.motion = false;
            sys.status.move_ = false;
            sys.status.move_transition = false;
            sys.status.coord_motion_lock = false;
        }
        let stop = if idle { sys.stop.take() } else { None };
        if stop.is_some() {
            sys.status.stopping = false;
        }
        for (h, a, d) in component_bits {
            let b = self.cbits(h);
            b.accel = a && b.ac;
            b.decel = d && b.ac;
        }
        for h in finished_ip {
            let b = self.cbits(h);
            b.ip = false;
            b.accel = false;
            b.decel = false;
        }
        for h in finished_pc.into_iter().chain(stop) {
            let b = self.cbits(h);
            b.pc = true;
            b.end_motion();
        }
        if start_pending {
            let sys = &mut self.coord.systems[cs.0 as usize];
            let (h, mv) = sys.pending.take().expect("checked above");
            if !self.fail_idle_master_switch(cs, h, &mv) {
                self.start_component(cs, h, mv, 0.0);
            }
            self.refresh_queue_status(cs);
        }
    }
}

/// Absolute `Position` elements of rotary axes with an unwind `U` (see the
/// module doc): `|p| > U` is ERR 13 with the Position operand's index; else
/// `p ≥ 0` (and −0) turns the axis forward and `p < 0` backward, by less
/// than one unwind, to `|p|` modulo `U`; the element becomes that unwrapped
/// target. Incremental moves, short arrays and non-finite values are left
/// to the operand checks.
pub(super) fn unwind_rotary_targets(
    unwinds: &[Option<f64>],
    start: &[f64],
    move_type: i64,
    position: &mut [f64],
    position_exerr: i32,
) -> Result<(), CoordMoveError> {
    if move_type != 0 || position.len() < unwinds.len() {
        return Ok(());
    }
    for (i, unwind) in unwinds.iter().enumerate() {
        let (Some(u), p) = (*unwind, position[i]) else { continue };
        if !p.is_finite() {
            continue;
        }
        if p.abs() > u {
            return Err(crate::coord::out_of_range(position_exerr));
        }
        let w = crate::axis::Modulo::new(u).map_or(0.0, |m| m.wrap(start[i]));
        let turn = |d: f64| if d >= u { 0.0 } else { d };
        let delta = if p >= 0.0 {
            turn((p - w).rem_euclid(u))
        } else {
            -turn((w + p).rem_euclid(u))
        };
        position[i] = start[i] + delta;
    }
    Ok(())
}

/// How long `mv` accelerates from rest to its peak path speed (time, or
/// master distance).
pub(super) fn acceleration_time(mv: &CoordMove) -> f64 {
    let Some(limits) = mv.limits() else { return 0.0 };
    let profile = mv.rest_profile();
    let peak = profile.sample(profile.deceleration_start_s()).velocity;
    Profile::to_velocity(State::at_rest(0.0), peak, limits).duration_s()
}

/// Where component `c` comes to rest along its path when it brakes now.
pub(super) fn rest_length(c: &Component, limits: Option<Limits>) -> f64 {
    let now = c.s();
    let length = c.mv.path().length();
    if c.stopping {
        return c.profile.final_state().position.clamp(0.0, length);
    }
    match limits.or(c.mv.limits().copied()) {
        Some(l) => (now.position + stopping_distance(now.state(), &l)).clamp(0.0, length),
        None => now.position,
    }
}

/// Adds a finished component's displacement to `base`. The oldest
/// component, ended at its end point, leaves `base` exactly there (where the
/// next component starts), so no rounding accumulates over a sequence.
pub(super) fn absorb(base: &mut [f64], c: &Component, oldest: bool) {
    let s = c.s().position;
    if oldest && !c.stopping && s >= c.mv.path().length() {
        base.copy_from_slice(c.mv.path().end());
    } else {
        add_displacement(base, c, s);
    }
}

pub(super) fn add_displacement(at: &mut [f64], c: &Component, s: f64) {
    let n = at.len();
    let (mut p, mut d) = (vec![0.0; n], vec![0.0; n]);
    c.mv.path().point(s, &mut p, &mut d);
    for i in 0..n {
        at[i] = (at[i] - c.mv.path().start()[i]) + p[i];
    }
}

/// Whether the newest two components meet on one straight line (the
/// machine stays on the path; `MoveTransitionStatus` is not set).
pub(super) fn collinear_junction(components: &[Component]) -> bool {
    let [.., a, b] = components else { return true };
    let ta = a.mv.path().tangent(a.mv.path().length());
    let tb = b.mv.path().tangent(0.0);
    a.mv.path().arc().is_none() && b.mv.path().arc().is_none() && norm(cross(ta, tb)) < 1e-9 && dot(ta, tb) > 0.0
}
