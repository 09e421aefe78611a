//! Collision checking in the run loop (issue #7): live checks after every
//! physics step, the scene's reaction, and the pre-flight sweep of every
//! MC_MoveModulo that becomes `Active`.
//!
//! * Live checks run on the simulated link poses after each physics step;
//!   events are stamped with that step's time. A `stop` reaction asks the
//!   planner for a coordinated stop ([`planner::task::MotionTask::stop_all_axes`])
//!   at the step of the contact; the ramp starts at the next coarse update,
//!   the rest of the current update's physics steps keep their setpoints
//!   (a PLC sees the stop at the start of its next cycle). `abort` ends the
//!   run after that physics step ([`Twin::collision_abort`]).
//! * Obstacles are not bodies of the physics world: links pass through
//!   them (the twin reports contacts, it does not push back), so the depth
//!   keeps growing while the plan goes on.
//! * The sweep runs when an instance becomes `Active`, after the planner
//!   update and before the physics steps of that update. Its path parameter
//!   is the distance the axis travels from the move's start, in axis units;
//!   undriven joints keep their initial positions and the other axes their
//!   command positions (a single-axis move). With `preflight = "reject"` a
//!   predicted collision rejects the move ([`planner::task::MotionTask::reject_move`]).

use super::Twin;
use crate::collision::{
    Body, CheckResult, CollisionEvent, CollisionModel, CollisionModelError, Contact, Monitor, PathSampler,
    PredictedCollision,
};
use crate::scene::{CollisionSettings, Preflight, Reaction};
use planner::modulo::MoveModuloError;
use planner::profile::Profile;
use serde::Serialize;

/// A pre-flight sweep that predicted a collision.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Prediction {
    /// The instance whose move was swept.
    pub instance: String,
    /// Time the move started (the update it became Active), s.
    pub started_s: f64,
    /// What the sweep found; for MC_MoveModulo `parameter` is in axis units travelled.
    pub collision: PredictedCollision,
    /// Simulated time at which the plan reaches the collision, s
    /// (`started_s + collision.time_s`).
    pub predicted_at_s: f64,
    /// Whether the move was rejected.
    pub rejected: bool,
}

pub(super) struct CollideState {
    settings: CollisionSettings,
    model: CollisionModel,
    monitor: Monitor,
    last: CheckResult,
    clearance_in_update: Vec<f64>,
    min_clearance: Vec<f64>,
    previous_active: Vec<bool>,
    predictions: Vec<Prediction>,
    abort: bool,
}

impl CollideState {
    pub(super) fn new(
        twin_model: &crate::urdf::RobotModel,
        scene: &crate::scene::Scene,
    ) -> Option<Result<Self, CollisionModelError>> {
        let settings = scene.collision.clone()?;
        Some(
            CollisionModel::new(twin_model, &scene.obstacles, &settings).map(|model| {
                let n = model.body_names().len();
                CollideState {
                    settings,
                    model,
                    monitor: Monitor::default(),
                    last: CheckResult {
                        contacts: Vec::new(),
                        clearance_m: vec![f64::INFINITY; n],
                    },
                    clearance_in_update: vec![f64::INFINITY; n],
                    min_clearance: vec![f64::INFINITY; n],
                    previous_active: Vec::new(),
                    predictions: Vec::new(),
                    abort: false,
                }
            }),
        )
    }
}

/// An MC_MoveModulo profile as a path: `s` = axis units travelled.
struct AxisMovePath {
    profile: Profile,
    start: f64,
    direction: f64,
    joint: usize,
    si_per_unit: f64,
    base: Vec<f64>,
}

impl AxisMovePath {
    fn time_of(&self, s: f64) -> f64 {
        let (mut lo, mut hi) = (0.0, self.profile.duration_s());
        for _ in 0..60 {
            let mid = 0.5 * (lo + hi);
            if (self.profile.sample(mid).position - self.start) * self.direction < s {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        hi
    }
}

impl PathSampler for AxisMovePath {
    fn length(&self) -> f64 {
        (self.profile.final_state().position - self.start).abs()
    }
    fn joint_positions(&self, s: f64) -> Vec<f64> {
        let mut q = self.base.clone();
        q[self.joint] = (self.start + self.direction * s) * self.si_per_unit;
        q
    }
    fn joint_rate_bounds(&self) -> Vec<f64> {
        let mut r = vec![0.0; self.base.len()];
        r[self.joint] = self.si_per_unit.abs();
        r
    }
    fn time_s(&self, s: f64) -> f64 {
        self.time_of(s)
    }
}

impl Twin {
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
    pub(super) fn collision_after_physics_step(&mut self) {
        let Some(c) = self.collision.as_mut() else { return };
        let poses = self.sim.world_from_link_isometries();
        let result = c.model.check(&poses);
        let t = self.sim.time_s();
        let started = c.monitor.observe(&c.model, t, &result);
        for (i, d) in result.clearance_m.iter().enumerate() {
            c.clearance_in_update[i] = c.clearance_in_update[i].min(*d);
            c.min_clearance[i] = c.min_clearance[i].min(*d);
        }
        c.last = result;
        if !started.is_empty() {
            match c.settings.reaction {
                Reaction::Stop => {
                    self.task.stop_all_axes();
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
    /// MC_MoveModulo uses it when an instance becomes `Active`; coordinated
    /// moves (MCCM, MCLM) call it with their own [`PathSampler`] when they start.
    pub fn preflight_path(&mut self, instance: &str, path: &dyn PathSampler) -> Option<&Prediction> {
        let c = self.collision.as_mut()?;
        if c.settings.preflight == Preflight::Off {
            return None;
        }
        let collision = c
            .model
            .sweep(&self.model, path, c.settings.sweep_resolution_m)
            .collision?;
        // The move's profile starts at the previous update's time.
        let started_s = self.task.time_s() - self.task.dt_s();
        c.predictions.push(Prediction {
            instance: instance.to_string(),
            started_s,
            predicted_at_s: started_s + collision.time_s,
            collision,
            rejected: c.settings.preflight == Preflight::Reject,
        });
        c.predictions.last()
    }

    /// Joint positions (per URDF joint) of the command now: axes at their
    /// command positions, undriven joints at their initial positions.
    fn command_joints(&self) -> Vec<f64> {
        let mut q = vec![0.0; self.model.joints.len()];
        for (name, value) in &self.scene.robot.initial_joints {
            if let Some(j) = self.model.joint_by_name(name) {
                q[j.0] = *value;
            }
        }
        for (a, axis) in self.axes.iter().zip(&self.scene.axes) {
            if let Some(j) = axis.joint.as_deref().and_then(|name| self.model.joint_by_name(name)) {
                q[j.0] = self.task.axis_state(a.handle).command_position * a.si_per_unit;
            }
        }
        q
    }

    /// Pre-flight sweep of every MC_MoveModulo instance that became Active
    /// in this update.
    pub(super) fn collision_after_planner_update(&mut self) {
        let Some(c) = self.collision.as_mut() else { return };
        c.previous_active.resize(self.fbs.len(), false);
        let mut started = Vec::new();
        for (i, fb) in self.fbs.iter().enumerate() {
            let active = self.task.outputs(fb.handle).active;
            if active && !c.previous_active[i] {
                started.push(i);
            }
            c.previous_active[i] = active;
        }
        for i in started {
            let Some(path) = self.move_modulo_path(i) else {
                continue;
            };
            let (name, handle) = (self.fbs[i].name.clone(), self.fbs[i].handle);
            if self.preflight_path(&name, &path).is_some_and(|p| p.rejected) {
                self.task.reject_move(handle, MoveModuloError::PathCollision);
                if let Some(c) = self.collision.as_mut() {
                    c.previous_active[i] = false;
                }
            }
        }
    }

    /// The planned path of the move instance `fb` (index into `fbs`) runs.
    fn move_modulo_path(&self, fb: usize) -> Option<AxisMovePath> {
        let axis_handle = self.fb_axes.get(fb).copied().flatten()?;
        let binding = self.axes.iter().find(|a| a.handle == axis_handle)?;
        let (profile, _) = self.task.active_profile(axis_handle)?;
        let joint = self
            .scene
            .axes
            .iter()
            .find(|a| a.name == binding.name)
            .and_then(|a| a.joint.as_deref())
            .and_then(|name| self.model.joint_by_name(name))?;
        let start = profile.start_state().position;
        let end = profile.final_state().position;
        Some(AxisMovePath {
            profile: profile.clone(),
            start,
            direction: if end >= start { 1.0 } else { -1.0 },
            joint: joint.0,
            si_per_unit: binding.si_per_unit,
            base: self.command_joints(),
        })
    }
}
