//! Collision checking in the run loop: live checks after every
//! physics step, the scene's reaction, and the pre-flight sweep of every
//! move that starts (MC_MoveModulo, MCLM, MCCM).
//!
//! * Live checks run on the simulated link poses after each physics step;
//!   events are stamped with that step's time. A `stop` reaction asks the
//!   planner for a coordinated stop ([`planner::task::MotionTask::stop_all_axes`])
//!   at the step of the contact; the ramp starts at the next coarse update,
//!   the rest of the current update's physics steps keep their setpoints
//!   (a PLC sees the stop at the start of its next cycle). `abort` ends the
//!   run after that physics step ([`Plant::collision_abort`]).
//! * Obstacles are not bodies of the physics world: links pass through
//!   them (the twin reports contacts, it does not push back), so the depth
//!   keeps growing while the plan goes on.
//! * The sweep runs when a move *starts*, after the planner update and
//!   before the physics steps of that update: an MC_MoveModulo when its
//!   instance becomes `Active`, an MCLM/MCCM when it becomes a running
//!   move of its coordinate system ([`planner::task::MotionTask::coord_moves_started`]:
//!   at once from rest or on a merge, at the blend point of the move before
//!   it, or when that move has ended; a queued move is swept when it starts,
//!   not while it waits, so the sweep starts where the motion really is).
//!   Undriven joints keep their initial positions, axes outside the move
//!   their command positions.
//! * MC_MoveModulo path parameter: the distance the axis travels from the
//!   move's start, in axis units.
//! * MCLM/MCCM path parameter: the path length along the move from its
//!   programmed start point, in coordinate units (the planner's path
//!   length, [`planner::coord::PathGeometry::point`]). The system's axes map
//!   to their URDF joints in one function (`joints_from_coordinates`: axis
//!   units × SI per unit, less an MRP offset). Joint-rate bound per axis (proven, so the sweep's step
//!   bound holds): a line moves every axis linearly, `|Δ_i| / L`; an arc's
//!   primary axes move with `‖dP/ds‖ ≤ 1` (the planner's arc length per
//!   radian is `√(r_max² + (dr/dφ)²)`, at least the speed of any point), so
//!   `1`; non-primary axes `|Δ_i| / L`; times `1 + 1e-9` for rounding. A
//!   move that starts in a blend is swept along its own programmed path;
//!   the rounding of the corner by the blend (within the command tolerance
//!   of the corner) is not part of the sweep. Master-driven moves are not
//!   swept (their timing is the master's).
//! * A coordinate system that is the source of a running MCT has virtual
//!   axes: its path's coordinates go through the transform's inverse
//!   kinematics ([`planner::mct::instruction::Transform::joints_near`]: its
//!   orientation, translation, the arm solution it runs with, its joint
//!   limits) to the target system's joints; its other axes (the SCARA's
//!   shared Z) keep their own joints; a parallel robot's virtual platform
//!   and forearm joints are posed from the target joints as in the run.
//!   Revolute joints unwrap point to point from the transform's last
//!   command. The path is sampled on a grid of `TRANSFORM_GRID` (1024)
//!   equal steps; the joint-rate bound per joint is **estimated**, not
//!   proven: twice the largest finite difference between neighbouring
//!   grid points (and at least the direct axes' proven bound). It holds
//!   where the joints' rate varies by less than a factor of two within one
//!   grid step, which fails only close to a singularity (a stretched
//!   elbow); a seeded random test checks it on lines and arcs of the SCARA,
//!   articulated and Delta scenes. The sweep's bound (module
//!   [`super::collision`]) holds as far as this estimate does.
//! * A point of such a path that the transform cannot reach (out of
//!   reach, singular, beyond a joint's soft travel limit) is itself a
//!   finding: the sweep stops at the last reachable grid point before it,
//!   and when it found no collision there, records a [`Prediction`] with
//!   `out_of_reach` (why), the first unreachable path length (bisection to
//!   the rounding of the path length) and its time, `collision.a`/`b` the
//!   target and source systems, `collision.bound` the grid step (an
//!   unreachable stretch shorter than one step between two reachable grid
//!   points can be missed). It never rejects the move: the
//!   controller's own MCT faults it with ERR 67 and a controlled stop on
//!   its way there, which the twin runs as on the controller.
//! * With `preflight = "reject"` a predicted collision rejects the move
//!   before the physics has applied any of it: an MC_MoveModulo gets
//!   `Error` with ErrorID 16#422C ([`planner::task::MotionTask::reject_move`]),
//!   an MCLM/MCCM `.ER` with ERR 200, EXERR 0
//!   ([`planner::task::ERR_PATH_COLLISION`]; Logix has no code for this, 200
//!   is outside its range; [`planner::task::MotionTask::reject_coord_move`]).
//!   Rejected in the update it started in, a move from rest leaves its axes
//!   exactly where they were: its first setpoint is withdrawn (command state
//!   restored), no stop ramp, no motion at all. A move that started while
//!   its axes were moving (an abort, a blend, a merge) ramps to rest instead.
//!   (An axis whose command velocity is 0 is at rest, whatever the
//!   rounding of the previous move's last acceleration sample.) The
//!   joints a transform drives from the rejected system are restored with
//!   it: they do not move either.

use super::Plant;
use super::axes::AxisJoint;
use super::collision::monitor::CollisionEvent;
use super::collision::sweep::{PathSampler, PredictedCollision};
use super::collision::{Body, Contact};
use crate::scene::{Preflight, Reaction};
use planner::coord::Driver;
use planner::modulo::MoveModuloError;
use planner::task::{AxisHandle, CoordHandle, FbHandle, MotionTask};

mod paths;
pub(super) mod state;

use paths::{AxisMovePath, CoordMovePath, TransformMapping};
pub use state::Prediction;

impl Plant {
    /// Whether the scene checks collisions (it has a `[collision]` table).
    pub fn collision_enabled(&self) -> bool {
        self.collision.is_some()
    }

    /// Every collision event so far.
    pub fn collision_events(&self) -> &[CollisionEvent] {
        self.collision.as_ref().map_or(&[], |c| c.monitor.events())
    }

    /// Every predicted collision of the pre-flight sweep so far.
    pub fn predicted_collisions(&self) -> &[Prediction] {
        self.collision.as_ref().map_or(&[], |c| &c.predictions)
    }

    /// Robot collision body names (the `<body>.clearance_m` columns).
    pub fn collision_bodies(&self) -> Vec<String> {
        self.collision
            .as_ref()
            .map(|c| c.model.body_names().iter().map(|s| s.to_string()).collect())
            .unwrap_or_default()
    }

    /// Per collision body, the smallest clearance over the last update's physics steps, m.
    pub fn clearance_m(&self) -> Vec<f64> {
        self.collision
            .as_ref()
            .map(|c| c.clearance_in_update.clone())
            .unwrap_or_default()
    }

    /// Per collision body, the smallest clearance over the run so far, m.
    pub fn min_clearance_m(&self) -> Vec<f64> {
        self.collision
            .as_ref()
            .map(|c| c.min_clearance.clone())
            .unwrap_or_default()
    }

    /// Contacts of the last physics step.
    pub fn contacts(&self) -> &[Contact] {
        self.collision.as_ref().map_or(&[], |c| &c.last.contacts)
    }

    /// URDF link indices of the robot bodies in contact now (sorted).
    pub fn colliding_links(&self) -> Vec<usize> {
        let Some(c) = self.collision.as_ref() else {
            return Vec::new();
        };
        let links = c.model.body_links();
        let mut v: Vec<usize> = c
            .monitor
            .colliding()
            .into_iter()
            .filter_map(|b| match b {
                Body::Robot(i) => Some(links[i]),
                Body::Obstacle(_) => None,
            })
            .collect();
        v.sort_unstable();
        v.dedup();
        v
    }

    /// Whether an `abort` reaction ended the run.
    pub fn collision_abort(&self) -> bool {
        self.collision.as_ref().is_some_and(|c| c.abort)
    }

    pub(super) fn collision_begin_update(&mut self) {
        if let Some(c) = self.collision.as_mut() {
            c.clearance_in_update.fill(f64::INFINITY);
        }
    }

    /// Live check after one physics step.
    pub(super) fn collision_after_physics_step(&mut self, task: &mut MotionTask) {
        let Some(c) = self.collision.as_mut() else { return };
        let poses = self.sim.world_from_link_isometries();
        // The discrete check, and the continuous detection: what touched
        // during the step, and when.
        let (result, mut touches) = c.model.check_step(c.previous.as_deref().map(|p| (p, &c.last)), &poses);
        let t = self.sim.time_s();
        for (at, _) in &mut touches {
            *at = t - self.step_s * (1.0 - *at);
        }
        let started = c.monitor.observe_from(&c.model, t, &result, &touches);
        c.previous = Some(poses);
        for (i, d) in result.clearance_m.iter().enumerate() {
            c.clearance_in_update[i] = c.clearance_in_update[i].min(*d);
            c.min_clearance[i] = c.min_clearance[i].min(*d);
        }
        c.last = result;
        if !started.is_empty() {
            match c.settings.reaction {
                Reaction::Stop => {
                    task.stop_all_axes();
                }
                Reaction::Abort => c.abort = true,
                _ => {}
            }
        }
    }

    /// Sweeps a planned path that starts now (at the last planner update)
    /// against the collision model and records a predicted collision.
    /// Returns the prediction; when its `rejected` is set (scene
    /// `preflight = "reject"`), the caller must fail its instruction.
    /// `None` when the scene has no `[collision]`, the sweep is off, or the
    /// path is clear.
    ///
    /// The run loop sweeps every MC_MoveModulo and MCLM/MCCM move this way
    /// when it starts (with the move's own start time); a caller may sweep
    /// any other path with its own [`PathSampler`].
    pub fn preflight_path(&mut self, task: &MotionTask, instance: &str, path: &dyn PathSampler) -> Option<&Prediction> {
        // The move's profile starts at the previous update's time.
        let started_s = task.time_s() - task.dt_s();
        self.preflight_path_from(instance, path, started_s)
    }

    /// [`Plant::preflight_path`] for a move whose profile starts at `started_s`.
    fn preflight_path_from(&mut self, instance: &str, path: &dyn PathSampler, started_s: f64) -> Option<&Prediction> {
        let c = self.collision.as_mut()?;
        if c.settings.preflight == Preflight::Off {
            return None;
        }
        let collision = c
            .model
            .sweep(&self.model, path, c.settings.sweep_resolution_m)
            .collision?;
        c.predictions.push(Prediction {
            instance: instance.to_string(),
            started_s,
            predicted_at_s: started_s + collision.time_s,
            collision,
            rejected: c.settings.preflight == Preflight::Reject,
            out_of_reach: None,
        });
        c.predictions.last()
    }

    /// Joint positions (per URDF joint) of the command now: axes at their
    /// command positions, undriven joints at their initial positions.
    fn command_joints(&self, task: &MotionTask) -> Vec<f64> {
        let mut q = self.rest_joints.clone();
        for a in &self.axes {
            if let Some(j) = a.axis_joint(task) {
                q[j.joint] = j.joint_position(task.axis_state(a.handle).command_position);
            }
        }
        q
    }

    /// Pre-flight sweep of every MC_MoveModulo instance that became Active
    /// and every coordinated move that started in this update.
    pub fn after_planner_update(&mut self, task: &mut MotionTask) {
        self.preflight_move_modulo(task);
        self.preflight_coordinated(task);
    }

    fn preflight_move_modulo(&mut self, task: &mut MotionTask) {
        let Some(c) = self.collision.as_mut() else { return };
        let fbs: Vec<FbHandle> = task.fb_handles().collect();
        c.previous_active.resize(fbs.len(), false);
        let mut started = Vec::new();
        for (i, &fb) in fbs.iter().enumerate() {
            let active = task.outputs(fb).active;
            if active && !c.previous_active[i] {
                started.push(i);
            }
            c.previous_active[i] = active;
        }
        for i in started {
            let Some((path, elapsed_s)) = self.move_modulo_path(task, fbs[i]) else {
                continue;
            };
            let name = task.fb_name(fbs[i]).to_string();
            let started_s = task.time_s() - elapsed_s;
            if self
                .preflight_path_from(&name, &path, started_s)
                .is_some_and(|p| p.rejected)
            {
                task.reject_move(fbs[i], MoveModuloError::PathCollision);
                if let Some(c) = self.collision.as_mut() {
                    c.previous_active[i] = false;
                }
            }
        }
    }

    /// Sweeps every time-driven MCLM/MCCM that started in this update and
    /// rejects it when the scene says so.
    fn preflight_coordinated(&mut self, task: &mut MotionTask) {
        if self
            .collision
            .as_ref()
            .is_none_or(|c| c.settings.preflight == Preflight::Off)
        {
            return;
        }
        let base = self.command_joints(task);
        let now_s = task.time_s();
        let mut swept = Vec::new();
        for mv in task.coord_moves_started() {
            if mv.mv.driver() == Driver::Master {
                continue;
            }
            let primary = task.coord_config(mv.system).primary_axes;
            let path = CoordMovePath::new(
                mv.mv,
                mv.profile,
                primary,
                self.coord_axis_joints(task, mv.system),
                base.clone(),
                self.transform_mapping(task, mv.system),
            );
            let name = task.coord_instruction_name(mv.instruction).to_string();
            swept.push((
                mv.instruction,
                name,
                path,
                now_s - mv.progress,
                transform_systems(task, mv.system),
            ));
        }
        for (instruction, name, path, started_s, systems) in swept {
            match self.preflight_path_from(&name, &path, started_s) {
                Some(p) => {
                    if p.rejected {
                        task.reject_coord_move(instruction);
                    }
                }
                None => self.record_unreachable(name, &path, started_s, systems),
            }
        }
    }

    /// Records the first point of a transform path the MCT cannot reach.
    fn record_unreachable(
        &mut self,
        name: String,
        path: &CoordMovePath,
        started_s: f64,
        (target, source): (String, String),
    ) {
        let Some((s, why)) = path.transform.as_ref().and_then(|t| t.unreachable.as_ref()) else {
            return;
        };
        let Some(c) = self.collision.as_mut() else { return };
        let time_s = path.time_s(*s);
        c.predictions.push(Prediction {
            instance: name,
            started_s,
            predicted_at_s: started_s + time_s,
            collision: PredictedCollision {
                parameter: *s,
                time_s,
                a: target,
                b: source,
                depth_m: 0.0,
                bound: path.transform.as_ref().map_or(0.0, |t| t.step),
            },
            rejected: false,
            out_of_reach: Some(why.to_string()),
        });
    }

    /// The transform coordinate system `cs` is the running source of, as
    /// the sweep maps it (`None`: no transform).
    fn transform_mapping(&self, task: &MotionTask, cs: CoordHandle) -> Option<TransformMapping> {
        let transform = task.transform_of_source(cs)?;
        let system_axes = task.coord_axes(cs);
        let (source_axes, target_axes) = task.transform_axes(transform);
        let source_index = source_axes
            .iter()
            .map(|a| system_axes.iter().position(|h| h == a))
            .collect::<Option<Vec<usize>>>()?;
        let target: Vec<Option<AxisJoint>> = target_axes.iter().map(|a| self.axis_joint(task, *a)).collect();
        let arm_axes: Vec<usize> = target_axes
            .iter()
            .filter_map(|a| self.axes.iter().position(|b| b.handle == *a))
            .collect();
        let rig = self
            .rigs
            .iter()
            .find(|r| r.arm_axes() == arm_axes.as_slice())
            .map(|r| (r.clone(), self.model.clone()));
        Some(TransformMapping {
            transform: transform.clone(),
            source_index,
            target,
            rig,
        })
    }

    /// Where the axis `handle` drives the robot now (`None`: no joint).
    fn axis_joint(&self, task: &MotionTask, handle: AxisHandle) -> Option<AxisJoint> {
        self.axes.iter().find(|b| b.handle == handle)?.axis_joint(task)
    }

    /// The joint each axis of coordinate system `cs` drives, in system order.
    fn coord_axis_joints(&self, task: &MotionTask, cs: CoordHandle) -> Vec<Option<AxisJoint>> {
        task.coord_axes(cs).iter().map(|&h| self.axis_joint(task, h)).collect()
    }

    /// The planned path the move instance `fb` runs, and how far into its
    /// profile the last update took it, s.
    fn move_modulo_path(&self, task: &MotionTask, fb: FbHandle) -> Option<(AxisMovePath, f64)> {
        let axis = task.fb_axis(fb);
        let joint = self.axis_joint(task, axis)?;
        let (profile, elapsed_s) = task.active_profile(axis)?;
        let start = profile.start_state().position;
        let end = profile.final_state().position;
        let path = AxisMovePath {
            profile: profile.clone(),
            start,
            direction: if end >= start { 1.0 } else { -1.0 },
            axis: joint,
            base: self.command_joints(task),
        };
        Some((path, elapsed_s))
    }
}

/// The (target, source) system names of the transform `cs` is the source
/// of; empty names without one.
fn transform_systems(task: &MotionTask, cs: CoordHandle) -> (String, String) {
    task.transform_of_source(cs)
        .and_then(|t| {
            let name_of = |id: planner::mct::instruction::SystemId| {
                task.coord_handles()
                    .nth(id.0 as usize)
                    .map(|h| task.coord_config(h).name.clone())
            };
            Some((name_of(t.target())?, name_of(t.source())?))
        })
        .unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::run::Twin;
    use planner::coord::{CoordMove, CoordMoveInputs, CoordinateSystem, CoordinateSystemConfig, MoveContext};
    use planner::dynamics::MoveDynamics;
    use planner::mccm::{MccmInputs, mccm};
    use planner::mclm::mclm;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// An MCCM through `via` (circle type 0), `None` where the three
    /// points make no arc; an MCLM without `via`.
    fn line_or_arc(common: CoordMoveInputs, via: Option<Vec<f64>>, ctx: &MoveContext<'_>) -> Option<CoordMove> {
        match via {
            Some(via_center_radius) => {
                let inputs = MccmInputs {
                    common,
                    circle_type: 0,
                    via_center_radius,
                    direction: 0,
                };
                mccm(&inputs, ctx).ok()
            }
            None => Some(mclm(&common, ctx).unwrap()),
        }
    }

    /// Random lines and 3D arcs (three primary axes and one non-primary)
    /// mapped onto joints with random scales and offsets: the joint motion
    /// between two nearby path parameters never exceeds the rate bound, and
    /// the time of a parameter is nondecreasing up to the profile's end.
    #[test]
    fn coordinated_joint_rate_bounds_hold_on_random_lines_and_arcs() {
        let system = CoordinateSystem::new(CoordinateSystemConfig {
            axis_count: 4,
            primary_axes: 3,
            ..CoordinateSystemConfig::new("XYZA")
        })
        .unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let point = |rng: &mut ChaCha8Rng| (0..4).map(|_| rng.random_range(-200.0..200.0)).collect::<Vec<f64>>();
        let (mut arcs, mut lines) = (0, 0);
        // `base` has 6 joints; axis 2 has no joint.
        let joints = [Some(4), Some(0), None, Some(2)];
        for k in 0..400 {
            let start = point(&mut rng);
            let common = CoordMoveInputs {
                position: point(&mut rng),
                dynamics: MoveDynamics {
                    speed: 100.0,
                    accel_rate: 500.0,
                    decel_rate: 500.0,
                    ..CoordMoveInputs::default().dynamics
                },
                ..Default::default()
            };
            let ctx = MoveContext {
                system: &system,
                axis_max_decel: &[1000.0; 4],
                start: &start,
                has_master: false,
            };
            let via = (k % 2 == 0).then(|| point(&mut rng));
            let Some(mv) = line_or_arc(common, via, &ctx) else {
                continue;
            };
            if mv.path().arc().is_some() {
                arcs += 1;
            } else {
                lines += 1;
            }
            let profile = mv.rest_profile();
            let axes: Vec<Option<AxisJoint>> = joints
                .iter()
                .map(|j| {
                    j.map(|joint| AxisJoint {
                        joint,
                        si_per_unit: rng.random_range(-0.01..0.01),
                        offset: rng.random_range(-5.0..5.0),
                    })
                })
                .collect();
            let base: Vec<f64> = (0..6).map(|_| rng.random_range(-1.0..1.0)).collect();
            let path = CoordMovePath::new(&mv, &profile, 3, axes, base.clone(), None);
            let rates = path.joint_rate_bounds();
            let length = path.length();
            let mut previous_t = 0.0;
            for i in 0..=200 {
                let s1 = length * i as f64 / 200.0;
                let s2 = (s1 + rng.random_range(0.0..0.05) * length).min(length);
                let (q1, q2) = (path.joint_positions(s1), path.joint_positions(s2));
                for j in 0..6 {
                    let moved = (q2[j] - q1[j]).abs();
                    assert!(
                        moved <= rates[j] * (s2 - s1) + 1e-12,
                        "joint {j}: {moved} over {}",
                        s2 - s1
                    );
                    if ![4, 0, 2].contains(&j) {
                        assert_eq!(q1[j], base[j], "joint {j} is not driven");
                    }
                }
                let t = path.time_s(s1);
                assert!(t >= previous_t && t <= profile.duration_s(), "{t}");
                previous_t = t;
            }
        }
        assert!(arcs > 100 && lines > 100, "{arcs} {lines}");
    }

    /// A scene run until its transform runs: the twin and the source system.
    fn twin_with_transform(scene: &str, source: &str) -> (Twin, CoordHandle) {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../scenes")
            .join(scene);
        let mut twin = Twin::new(crate::scene::load(&path).unwrap()).unwrap();
        let cs = twin
            .task()
            .coord_handles()
            .find(|h| twin.task().coord_config(*h).name == source)
            .unwrap();
        while twin.task().transform_of_source(cs).is_none() {
            twin.step();
        }
        (twin, cs)
    }

    /// Seeded random lines and arcs of an MCT source system (SCARA,
    /// articulated arm, Delta with its virtual joints) from where the tool
    /// is, some leaving the workspace: between any two nearby path lengths
    /// up to the reachable end, every joint moves no more than its rate
    /// bound allows; where the path leaves the workspace the transform
    /// cannot reach the reported point, and can reach every grid point
    /// before it.
    #[test]
    fn transform_joint_rate_estimates_hold_on_random_mct_paths() {
        let mut rng = ChaCha8Rng::seed_from_u64(77);
        for (scene, source) in [
            ("scara_pick.toml", "Cart"),
            ("articulated_arc.toml", "Work"),
            ("delta_pick.toml", "Cart"),
        ] {
            let (twin, cs) = twin_with_transform(scene, source);
            let config = twin.task().coord_config(cs).clone();
            let n = config.axis_count;
            let system = CoordinateSystem::new(config.clone()).unwrap();
            let start: Vec<f64> = twin
                .task()
                .coord_axes(cs)
                .iter()
                .map(|h| twin.task().axis_state(*h).command_position)
                .collect();
            let (mut checked, mut unreachable) = (0, 0);
            for k in 0..24 {
                let mut point = || {
                    start
                        .iter()
                        .map(|x| x + rng.random_range(-0.3..0.3))
                        .collect::<Vec<f64>>()
                };
                let common = CoordMoveInputs {
                    position: point(),
                    dynamics: MoveDynamics {
                        speed: 0.5,
                        accel_rate: 2.0,
                        decel_rate: 2.0,
                        ..CoordMoveInputs::default().dynamics
                    },
                    ..Default::default()
                };
                let ctx = MoveContext {
                    system: &system,
                    axis_max_decel: &vec![1000.0; n],
                    start: &start,
                    has_master: false,
                };
                let via = (k % 2 == 0).then(&mut point);
                let Some(mv) = line_or_arc(common, via, &ctx) else {
                    continue;
                };
                let path = CoordMovePath::new(
                    &mv,
                    &mv.rest_profile(),
                    config.primary_axes,
                    twin.plant().coord_axis_joints(twin.task(), cs),
                    twin.plant().command_joints(twin.task()),
                    twin.plant().transform_mapping(twin.task(), cs),
                );
                let t = path.transform.as_ref().unwrap();
                // At its start (where the tool is) the path gives the
                // joints the transform commands now, and a parallel
                // robot's virtual joints where the run put them.
                assert_eq!(t.mapping.rig.is_some(), scene == "delta_pick.toml");
                let q0 = path.joint_positions(0.0);
                for a in t.mapping.target.iter().flatten() {
                    assert!(
                        (q0[a.joint] - path.base[a.joint]).abs() < 1e-9,
                        "{scene}: joint {}",
                        a.joint
                    );
                }
                if let Some((rig, _)) = &t.mapping.rig {
                    for (&j, v) in rig.virtual_joints().iter().zip(rig.previous()) {
                        assert!((q0[j] - v).abs() < 1e-6, "{scene}: virtual joint {j}: {} vs {v}", q0[j]);
                    }
                }
                let reach = path.length();
                assert!(reach <= mv.path().length() && reach >= 0.0);
                if let Some((s_u, _)) = &t.unreachable {
                    unreachable += 1;
                    assert!(reach <= *s_u);
                    let mut p = vec![0.0; n];
                    mv.path().point(*s_u, &mut p, &mut vec![0.0; n]);
                    let near = t.references.last().cloned().unwrap();
                    assert!(
                        t.mapping.joints(&path.axes, &p, &path.base, &near).is_err(),
                        "{scene}: {s_u} is reachable"
                    );
                }
                let rates = path.joint_rate_bounds();
                for _ in 0..300 {
                    let s1 = rng.random_range(0.0..=reach);
                    let s2 = (s1 + rng.random_range(0.0..4.0) * t.step).min(reach);
                    let (q1, q2) = (path.joint_positions(s1), path.joint_positions(s2));
                    for j in 0..q1.len() {
                        let moved = (q2[j] - q1[j]).abs();
                        assert!(
                            moved <= rates[j] * (s2 - s1) + 1e-12,
                            "{scene} joint {j}: {moved} over {} (bound {})",
                            s2 - s1,
                            rates[j]
                        );
                    }
                    checked += 1;
                }
            }
            assert!(checked >= 3000, "{scene}: {checked}");
            assert!(unreachable >= 1, "{scene}: {unreachable} paths leave the workspace");
        }
    }
}
