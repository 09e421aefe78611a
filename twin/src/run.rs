//! A scene running: program steps → planner → joint motors → physics →
//! actual positions back to the planner, one coarse update at a time.
//!
//! # Timing
//! Update `k` advances the planner to `t_k = k · coarse_update`; the physics
//! then runs the `coarse_update / physics_step` steps covering
//! `(t_{k-1}, t_k]`, each given the command position interpolated linearly
//! between the setpoints of `t_{k-1}` and `t_k` and the interpolated command
//! velocity as feed-forward. The joint positions at `t_k` are fed back as the
//! axes' actual positions, so `Done` (target position monitoring) sees them at
//! the next update, as a PLC sees its inputs at the start of its cycle.
//!
//! # Program steps
//! Each step fires once. A `when` step is armed once the step before it has
//! fired (the list is a sequence, like SFC transitions) and is due `after_s`
//! after the first update at which its bit is TRUE; an `at_s` step is due at
//! its time. A step fires at the first coarse update that starts at or after
//! it is due; due steps set their inputs in list order, just before the
//! planner update. A function-block call sets the inputs it
//! names; the others keep their last value, as PLC block inputs do.
//! A Logix call is one scan of a rung that has just become true (see
//! [`logix`]); `when` may name a control-structure bit (`MC1.PC`) as well as
//! a function-block output (`MoveTable.Done`).

use crate::frames::{Part, scene_parts};
use crate::physics::{JointDrive, PhysicsError, PhysicsOptions, RobotSim};
use crate::scene::{AxisKind, BaseType, FunctionBlock, Scene, TagValue, Trigger};
use crate::st::{Args, Call, Expr};
use crate::stl::StlError;
use crate::urdf::{RobotModel, UrdfError};
use planner::axis::{AxisConfig, AxisKind as PlannerAxisKind};
use planner::instruction::FbOutputs;
use planner::instruction::MotionInstructionBits;
use planner::modulo::{McBufferMode, McDirection, MoveModuloInputs};
use planner::task::{AxisHandle, FbHandle, InstructionHandle, MotionTask, TaskError};
use std::path::PathBuf;
use thiserror::Error;

pub mod cam;
mod collide;
pub mod coord;
pub use collide::Prediction;
pub mod limits;
pub mod logix;
pub mod mct;

/// Why a scene cannot run. Each variant names the scene file and the place.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum RunError {
    /// The robot's URDF (or a mesh it references) cannot be loaded.
    #[error("{scene}: robot.urdf: {source}")]
    Urdf {
        /// Scene file.
        scene: PathBuf,
        /// What failed (boxed: URDF errors are large).
        #[source]
        source: Box<UrdfError>,
    },
    /// An axis is mapped to a joint the URDF does not have (or cannot drive).
    #[error("{scene}:{line}:{column}: axes.joint: {message}")]
    Joint {
        /// Scene file.
        scene: PathBuf,
        /// Line of the field.
        line: usize,
        /// Column of the field.
        column: usize,
        /// What is wrong.
        message: String,
    },
    /// The physics world cannot be built.
    #[error("{scene}: robot: {source}")]
    Physics {
        /// Scene file.
        scene: PathBuf,
        /// What failed.
        #[source]
        source: PhysicsError,
    },
    /// The planner refuses an axis or the coarse update period.
    #[error("{scene}: {source}")]
    Planner {
        /// Scene file.
        scene: PathBuf,
        /// What failed.
        #[source]
        source: TaskError,
    },
    /// An obstacle's mesh file cannot be loaded.
    #[error("{scene}:{line}:{column}: obstacles.file: obstacle '{obstacle}': {source}")]
    ObstacleMesh {
        /// Scene file.
        scene: PathBuf,
        /// Line of the obstacle.
        line: usize,
        /// Column of the obstacle.
        column: usize,
        /// Obstacle name.
        obstacle: String,
        /// Why the STL file failed (names the file).
        #[source]
        source: StlError,
    },
    /// A transform's target robot (URDF) does not have the kinematics of its
    /// `geometry` table.
    #[error("{scene}:{line}:{column}: tags.geometry: {message}")]
    Kinematics {
        /// Scene file.
        scene: PathBuf,
        /// Line of the `geometry` table.
        line: usize,
        /// Column of the `geometry` table.
        column: usize,
        /// What disagrees, and by how much.
        message: String,
    },
    /// A coordinate system's `tool_link` is not a link of the URDF.
    #[error("{scene}:{line}:{column}: tags.coordinate_system.tool_link: {message}")]
    ToolLink {
        /// Scene file.
        scene: PathBuf,
        /// Line of the `coordinate_system` table.
        line: usize,
        /// Column of the table.
        column: usize,
        /// What is wrong.
        message: String,
    },
    /// The `[collision]` table names something the robot or scene lacks, or
    /// a collision shape cannot be built.
    #[error("{scene}:{line}:{column}: {source}")]
    Collision {
        /// Scene file.
        scene: PathBuf,
        /// Line of the field (or of the `[collision]` table).
        line: usize,
        /// Column of the field.
        column: usize,
        /// What is wrong.
        #[source]
        source: crate::collision::CollisionModelError,
    },
    /// A program step cannot be carried out.
    #[error("{scene}:{line}:{column}: program[{index}]: {message}")]
    Step {
        /// Scene file.
        scene: PathBuf,
        /// Line of the step.
        line: usize,
        /// Column of the step.
        column: usize,
        /// Step index.
        index: usize,
        /// What is wrong.
        message: String,
    },
}

/// One axis of the scene bound to the planner and a joint motor.
#[derive(Debug, Clone)]
pub struct AxisBinding {
    /// Axis tag name.
    pub name: String,
    /// Planner handle.
    pub handle: AxisHandle,
    /// Index of the joint drive in the physics world; `None` for a virtual
    /// axis.
    pub drive: Option<usize>,
    /// SI units (rad or m) per axis unit.
    pub si_per_unit: f64,
    /// In-position window, axis units.
    pub in_position_window: f64,
}

/// A function-block instance of the program.
#[derive(Debug, Clone)]
pub struct FbBinding {
    /// Instance tag name.
    pub name: String,
    /// Planner handle.
    pub handle: FbHandle,
}

/// A `MOTION_INSTRUCTION` tag of the program (a Logix control structure).
#[derive(Debug, Clone)]
pub struct InstructionBinding {
    /// Tag name.
    pub name: String,
    /// Planner handle.
    pub handle: InstructionHandle,
}

#[derive(Debug, Clone)]
enum StepAction {
    MoveModulo { fb: usize, set: Vec<Setting> },
    Logix(logix::LogixStep),
}

/// One MC_MoveModulo input with its value, as a call names it.
#[derive(Debug, Clone, Copy)]
enum Setting {
    Execute(bool),
    Position(f64),
    Velocity(f64),
    Acceleration(f64),
    Deceleration(f64),
    Jerk(f64),
    Direction(McDirection),
    BufferMode(McBufferMode),
}

impl Setting {
    fn apply(self, inputs: &mut MoveModuloInputs) {
        match self {
            Setting::Execute(b) => inputs.execute = b,
            Setting::Position(x) => inputs.position = x,
            Setting::Velocity(x) => inputs.velocity = x,
            Setting::Acceleration(x) => inputs.acceleration = x,
            Setting::Deceleration(x) => inputs.deceleration = x,
            Setting::Jerk(x) => inputs.jerk = x,
            Setting::Direction(d) => inputs.direction = d,
            Setting::BufferMode(m) => inputs.buffer_mode = m,
        }
    }
}

#[derive(Debug, Clone)]
struct CompiledStep {
    trigger: CompiledTrigger,
    action: StepAction,
    fire_at_s: Option<f64>,
    fired: bool,
}

#[derive(Debug, Clone)]
enum CompiledTrigger {
    At(f64),
    When {
        source: BitSource,
        output: String,
        delay_s: f64,
    },
}

/// Whose bit a `when` condition reads.
#[derive(Debug, Clone, Copy)]
enum BitSource {
    /// A function-block instance (index into `fbs`).
    Fb(usize),
    /// A control structure (index into `instructions`).
    Instruction(usize),
}

/// A loaded, bound scene, ready to step.
pub struct Twin {
    scene: Scene,
    model: RobotModel,
    parts: Vec<Part>,
    sim: RobotSim,
    task: MotionTask,
    axes: Vec<AxisBinding>,
    fbs: Vec<FbBinding>,
    instructions: Vec<InstructionBinding>,
    steps: Vec<CompiledStep>,
    substeps: usize,
    previous_command: Vec<(f64, f64)>,
    /// Axis of each instance in `fbs` (collision pre-flight).
    fb_axes: Vec<Option<AxisHandle>>,
    collision: Option<collide::CollideState>,
    /// Tool-centre trails of the coordinate systems (`run/coord.rs`).
    trails: Vec<coord::ToolTrail>,
    /// Parallel robots' virtual joints posed from MCT kinematics
    /// (`run/mct.rs`).
    rigs: Vec<mct::ParallelRig>,
    step_s: f64,
}

impl std::fmt::Debug for Twin {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Twin")
            .field("scene", &self.scene.path)
            .field("time_s", &self.time_s())
            .finish_non_exhaustive()
    }
}

/// The numeric value of an operand: a literal, a REAL/DINT tag, or an
/// element of an array tag.
fn number(expr: &Expr, scene: &Scene) -> Option<f64> {
    let numeric = |v: &TagValue| match v {
        TagValue::Real(x) => Some(*x),
        TagValue::Integer(i) => Some(*i as f64),
        _ => None,
    };
    let tag_value = |name: &str| scene.tag(name).and_then(|t| t.value.as_ref());
    match expr {
        Expr::Number(x) => Some(*x),
        Expr::Integer(i) => Some(*i as f64),
        Expr::Ident(name) => tag_value(name).and_then(numeric),
        Expr::Index(base, i) => match (base.as_ref(), usize::try_from(*i)) {
            (Expr::Ident(name), Ok(i)) => match tag_value(name) {
                Some(TagValue::Array(items)) => items.get(i).and_then(numeric),
                _ => None,
            },
            _ => None,
        },
        _ => None,
    }
}

impl Twin {
    /// Loads the URDF, builds the physics world and the planner, and binds
    /// every program step.
    ///
    /// # Errors
    /// [`RunError`] naming the scene file and the place that is wrong.
    pub fn new(scene: Scene) -> Result<Twin, RunError> {
        let path = scene.path.clone();
        let model = RobotModel::load(&scene.robot.urdf).map_err(|source| RunError::Urdf {
            scene: path.clone(),
            source: Box::new(source),
        })?;
        let parts = scene_parts(&model, &scene).map_err(|e| {
            let o = &scene.obstacles[e.obstacle];
            RunError::ObstacleMesh {
                scene: path.clone(),
                line: o.location.line,
                column: o.location.column,
                obstacle: o.name.clone(),
                source: e.source,
            }
        })?;
        let mut task = MotionTask::new(scene.coarse_update_ms / 1000.0).map_err(|source| RunError::Planner {
            scene: path.clone(),
            source,
        })?;
        let mut drives = Vec::new();
        let mut initial: Vec<(String, f64)> = scene
            .robot
            .initial_joints
            .iter()
            .map(|(k, v)| (k.clone(), *v))
            .collect();
        let mut axes = Vec::new();
        for axis in &scene.axes {
            let joint_error = |message: String| RunError::Joint {
                scene: path.clone(),
                line: axis.joint_location.line,
                column: axis.joint_location.column,
                message,
            };
            let config = limits::with_urdf_limits(axis_config(axis), axis, &model).map_err(joint_error)?;
            let handle = task
                .add_axis(config, axis.initial_position)
                .map_err(|source| RunError::Planner {
                    scene: path.clone(),
                    source,
                })?;
            let si = axis.units.si_per_unit();
            let Some(joint) = &axis.joint else {
                // A virtual axis: no joint, never fed (actual = command).
                axes.push(AxisBinding {
                    name: axis.name.clone(),
                    handle,
                    drive: None,
                    si_per_unit: si,
                    in_position_window: axis.in_position_window,
                });
                continue;
            };
            let Some(j) = model.joint_by_name(joint) else {
                let mut names: Vec<&str> = model
                    .joints
                    .iter()
                    .filter(|j| j.kind.is_movable())
                    .map(|j| j.name.as_str())
                    .collect();
                names.sort_unstable();
                return Err(joint_error(format!(
                    "axis '{}' is mapped to joint '{}', which {} does not have (movable joints: {})",
                    axis.name,
                    joint,
                    scene.robot.urdf.display(),
                    names.join(", ")
                )));
            };
            if !model.joint(j).kind.is_movable() {
                return Err(joint_error(format!(
                    "joint '{}' of axis '{}' is fixed and cannot be driven",
                    joint, axis.name
                )));
            }
            initial.retain(|(name, _)| name != joint);
            initial.push((joint.clone(), axis.initial_position * si));
            drives.push(JointDrive {
                joint: joint.clone(),
                stiffness: axis.motor.stiffness,
                damping: axis.motor.damping,
                max_force: None,
            });
            axes.push(AxisBinding {
                name: axis.name.clone(),
                handle,
                drive: Some(drives.len() - 1),
                si_per_unit: si,
                in_position_window: axis.in_position_window,
            });
        }
        mct::check_transforms(&scene, &model)?;
        let axis_drives: Vec<Option<usize>> = axes.iter().map(|a: &AxisBinding| a.drive).collect();
        let rigs = mct::parallel_rigs(&scene, &model, &axis_drives, &mut drives, &mut initial)?;
        initial.sort_by(|a, b| a.0.cmp(&b.0));
        let step_s = scene.physics_step_ms / 1000.0;
        let substeps = (scene.coarse_update_ms / scene.physics_step_ms).round().max(1.0) as usize;
        let options = PhysicsOptions {
            step_s,
            ..PhysicsOptions::default()
        };
        let sim = RobotSim::new(&model, &drives, &initial, options).map_err(|source| RunError::Physics {
            scene: path.clone(),
            source,
        })?;

        let mut fbs: Vec<FbBinding> = Vec::new();
        let mut instructions: Vec<InstructionBinding> = Vec::new();
        let mut fb_axis: Vec<Option<AxisHandle>> = Vec::new();
        let mut steps = Vec::new();
        for (index, step) in scene.program.iter().enumerate() {
            let fail = |message: String| RunError::Step {
                scene: path.clone(),
                line: step.location.line,
                column: step.location.column,
                index,
                message,
            };
            let action = match &step.call.args {
                Args::Positional(operands) => {
                    let operands: Vec<Expr> = operands.iter().map(|o| o.value.clone()).collect();
                    let mut ctx = logix::LogixContext {
                        scene: &scene,
                        task: &mut task,
                        axes: &axes,
                        instructions: &mut instructions,
                    };
                    StepAction::Logix(logix::compile(&step.call.name.value, &operands, &mut ctx).map_err(fail)?)
                }
                Args::Named(_) => {
                    compile_call(&step.call, &scene, &mut task, &mut fbs, &mut fb_axis, &axes).map_err(fail)?
                }
            };
            let trigger = match &step.trigger {
                Trigger::At { time_s } => CompiledTrigger::At(*time_s),
                Trigger::When { condition, delay_s } => {
                    let (tag, output) = match condition {
                        Expr::Member(base, output) => match base.as_ref() {
                            Expr::Ident(tag) => (tag.clone(), output.clone()),
                            _ => return Err(fail(format!("when = \"{condition}\": expected <instance>.<output>"))),
                        },
                        _ => {
                            return Err(fail(format!(
                                "when = \"{condition}\": expected <instance>.<output>, e.g. MoveTable.Done"
                            )));
                        }
                    };
                    let source = if let Some(fb) = fbs.iter().position(|f| f.name.eq_ignore_ascii_case(&tag)) {
                        if FbOutputs::default().bit(&output).is_none() {
                            return Err(fail(format!(
                                "when = \"{condition}\": '{output}' is not a function-block output (Done, Busy, Active, CommandAborted, Error)"
                            )));
                        }
                        BitSource::Fb(fb)
                    } else if let Some(i) = instructions.iter().position(|b| b.name.eq_ignore_ascii_case(&tag)) {
                        if MotionInstructionBits::default().bit(&output).is_none() {
                            return Err(fail(format!(
                                "when = \"{condition}\": '{output}' is not a control-structure bit (EN, DN, ER, IP, AC, PC, ACCEL, DECEL)"
                            )));
                        }
                        BitSource::Instruction(i)
                    } else {
                        return Err(fail(format!(
                            "when = \"{condition}\": '{tag}' is not an instance or control structure used by an earlier program step"
                        )));
                    };
                    CompiledTrigger::When {
                        source,
                        output,
                        delay_s: *delay_s,
                    }
                }
            };
            steps.push(CompiledStep {
                trigger,
                action,
                fire_at_s: None,
                fired: false,
            });
        }
        let collision = collide::CollideState::new(&model, &scene)
            .transpose()
            .map_err(|source| {
                let at = scene.collision.as_ref().map(|c| c.location).unwrap_or_default();
                let (line, column) = match &source {
                    crate::collision::CollisionModelError::UnknownToolLink { line, column, .. }
                    | crate::collision::CollisionModelError::UnknownPairBody { line, column, .. } => (*line, *column),
                    _ => (at.line, at.column),
                };
                RunError::Collision {
                    scene: path.clone(),
                    line,
                    column,
                    source,
                }
            })?;
        let previous_command = axes
            .iter()
            .map(|a| (task.axis_state(a.handle).command_position, 0.0))
            .collect();
        let mut twin = Twin {
            scene,
            model,
            parts,
            sim,
            task,
            axes,
            fbs,
            instructions,
            steps,
            substeps,
            previous_command,
            fb_axes: fb_axis,
            collision,
            trails: Vec::new(),
            rigs,
            step_s,
        };
        twin.trails = coord::tool_trails(&twin)?;
        twin.record_trails();
        Ok(twin)
    }

    /// The scene.
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// The robot model.
    pub fn model(&self) -> &RobotModel {
        &self.model
    }

    /// Every drawable piece: URDF visuals and obstacles, meshes loaded once.
    pub fn parts(&self) -> &[Part] {
        &self.parts
    }

    /// The planner.
    pub fn task(&self) -> &MotionTask {
        &self.task
    }

    /// The bound axes, in scene order.
    pub fn axes(&self) -> &[AxisBinding] {
        &self.axes
    }

    /// The function-block instances, in the order the program first calls them.
    pub fn fbs(&self) -> &[FbBinding] {
        &self.fbs
    }

    /// The `MOTION_INSTRUCTION` tags the program executes with, in the order
    /// the program first uses them.
    pub fn instructions(&self) -> &[InstructionBinding] {
        &self.instructions
    }

    /// Simulated time of the last update, seconds.
    pub fn time_s(&self) -> f64 {
        self.task.time_s()
    }

    /// Number of coarse updates in the scene's duration.
    pub fn total_updates(&self) -> u64 {
        (self.scene.duration_s / (self.scene.coarse_update_ms / 1000.0)).round() as u64
    }

    /// World poses of every URDF link (translation m, quaternion xyzw), in
    /// model link order.
    pub fn world_from_link(&self) -> Vec<([f64; 3], [f64; 4])> {
        self.sim.world_from_link()
    }

    /// One coarse update: fire due program steps, update the planner, run
    /// the physics steps, feed back the actual positions.
    pub fn step(&mut self) {
        let eps = 1e-9 * self.task.dt_s();
        let mut due = Vec::new();
        let now_s = self.task.time_s();
        for i in 0..self.steps.len() {
            let armed = i == 0 || self.steps[i - 1].fired;
            let step = &mut self.steps[i];
            if step.fired {
                continue;
            }
            match &step.trigger {
                CompiledTrigger::At(t) => step.fire_at_s = Some(*t),
                CompiledTrigger::When {
                    source,
                    output,
                    delay_s,
                } => {
                    let bit = match *source {
                        BitSource::Fb(fb) => self.task.outputs(self.fbs[fb].handle).bit(output),
                        BitSource::Instruction(i) => self.task.motion_bits(self.instructions[i].handle).bit(output),
                    };
                    if armed && step.fire_at_s.is_none() && bit.unwrap_or(false) {
                        step.fire_at_s = Some(now_s + delay_s);
                    }
                }
            }
            if let Some(t) = step.fire_at_s
                && t <= now_s + eps
            {
                due.push(i);
                step.fired = true;
            }
        }
        for i in due {
            match &self.steps[i].action {
                StepAction::MoveModulo { fb, set } => {
                    let handle = self.fbs[*fb].handle;
                    let mut inputs = self.task.move_modulo_inputs(handle);
                    for setting in set {
                        setting.apply(&mut inputs);
                    }
                    self.task.set_move_modulo_inputs(handle, inputs);
                }
                StepAction::Logix(step) => (step.run)(&mut self.task),
            }
        }
        self.task.update();
        self.collision_after_planner_update();
        self.collision_begin_update();

        let n = self.substeps;
        let now: Vec<(f64, f64)> = self
            .axes
            .iter()
            .map(|a| {
                let s = self.task.axis_state(a.handle);
                // MRP redefines positions, not the joint: back to the joint's frame.
                (
                    s.command_position - self.task.position_offset(a.handle),
                    s.command_velocity,
                )
            })
            .collect();
        for j in 0..n {
            let f = j as f64 / n as f64;
            let fm = (j as f64 + 0.5) / n as f64;
            let mut setpoints = Vec::with_capacity(self.axes.len());
            for (k, axis) in self.axes.iter().enumerate() {
                let Some(drive) = axis.drive else { continue };
                let (p0, v0) = self.previous_command[k];
                let (p1, v1) = now[k];
                let p = p0 + (p1 - p0) * f;
                let v = v0 + (v1 - v0) * fm;
                self.sim.set_setpoint(drive, p * axis.si_per_unit, v * axis.si_per_unit);
                setpoints.push((drive, p * axis.si_per_unit));
            }
            for rig in &mut self.rigs {
                let setpoint = |d: usize| setpoints.iter().find(|(x, _)| *x == d).map(|(_, p)| *p);
                rig.drive(&self.model, &mut self.sim, self.step_s, setpoint);
            }
            self.sim.step();
            self.collision_after_physics_step();
            if self.collision_abort() {
                break;
            }
        }
        self.previous_command = now;
        for axis in &self.axes {
            let Some(drive) = axis.drive else { continue };
            let actual = self.sim.joint_position(drive) / axis.si_per_unit;
            self.task.feed_actual_position(axis.handle, actual);
        }
        self.record_trails();
    }

    /// Trace column names: `time_s`, then per axis `<axis>.cmd_pos`,
    /// `.cmd_vel`, `.cmd_acc`, `.act_pos`, then per instance `<fb>.Done`,
    /// `.Busy`, `.Active`, `.CommandAborted`, `.Error`, `.ErrorID`, then per
    /// control structure `<tag>.EN`, `.DN`, `.ER`, `.IP`, `.AC`, `.PC`,
    /// `.ACCEL`, `.DECEL`, `.ERR`, `.EXERR`, `.SEGMENT`.
    pub fn trace_header(&self) -> Vec<String> {
        let mut h = vec!["time_s".to_string()];
        for a in &self.axes {
            for c in ["cmd_pos", "cmd_vel", "cmd_acc", "act_pos"] {
                h.push(format!("{}.{c}", a.name));
            }
        }
        for fb in &self.fbs {
            for (c, _) in FbOutputs::default().bits() {
                h.push(format!("{}.{c}", fb.name));
            }
            h.push(format!("{}.ErrorID", fb.name));
        }
        let zero = MotionInstructionBits::default();
        for ins in &self.instructions {
            for (c, _) in zero.bits() {
                h.push(format!("{}.{c}", ins.name));
            }
            for (c, _) in zero.codes() {
                h.push(format!("{}.{c}", ins.name));
            }
        }
        if self.collision_enabled() {
            h.push("collision.count".to_string());
            h.extend(self.collision_bodies().iter().map(|b| format!("{b}.clearance_m")));
        }
        h.extend(cam::trace_header(&self.task, &self.axes));
        self.coord_trace_header(&mut h);
        h.extend(mct::trace_header(&self.scene, &self.task, &self.axes));
        h
    }

    /// The trace row for the current update, matching [`Twin::trace_header`].
    /// Numbers use Rust's shortest round-trip formatting (deterministic).
    pub fn trace_row(&self) -> Vec<String> {
        let mut row = vec![format!("{}", self.time_s())];
        for a in &self.axes {
            let s = self.task.axis_state(a.handle);
            for x in [
                s.command_position,
                s.command_velocity,
                s.command_acceleration,
                s.actual_position,
            ] {
                row.push(format!("{x}"));
            }
        }
        for fb in &self.fbs {
            let o = self.task.outputs(fb.handle);
            for (_, b) in o.bits() {
                row.push(if b { "1" } else { "0" }.to_string());
            }
            row.push(o.error_id.to_string());
        }
        for ins in &self.instructions {
            let b = self.task.motion_bits(ins.handle);
            for (_, bit) in b.bits() {
                row.push(if bit { "1" } else { "0" }.to_string());
            }
            for (_, code) in b.codes() {
                row.push(code.to_string());
            }
        }
        if self.collision_enabled() {
            row.push(self.collision_events().len().to_string());
            row.extend(self.clearance_m().iter().map(|d| format!("{d}")));
        }
        row.extend(cam::trace_row(&self.task, &self.axes));
        self.coord_trace_row(&mut row);
        row.extend(mct::trace_row(&self.scene, &self.task, &self.axes));
        row
    }
}

/// The planner's configuration of a scene axis.
pub fn axis_config(axis: &crate::scene::Axis) -> AxisConfig {
    let kind = match axis.kind {
        AxisKind::Linear => PlannerAxisKind::Linear,
        AxisKind::Rotary => PlannerAxisKind::Rotary,
    };
    AxisConfig {
        modulo_period: axis.modulo_period,
        max_velocity: axis.max_velocity,
        max_acceleration: axis.max_acceleration,
        max_deceleration: axis.max_deceleration,
        max_jerk: axis.max_jerk,
        in_position_window: axis.in_position_window,
        target_position_monitoring: axis.target_position_monitoring,
        modulo_tolerance_window: axis.modulo_tolerance_window,
        soft_travel_limits: axis.soft_travel_limits,
        ..AxisConfig::new(axis.name.clone(), kind)
    }
}

/// Binds one call to its instance (created on its first call).
fn compile_call(
    call: &Call,
    scene: &Scene,
    task: &mut MotionTask,
    fbs: &mut Vec<FbBinding>,
    fb_axis: &mut Vec<Option<AxisHandle>>,
    axes: &[AxisBinding],
) -> Result<StepAction, String> {
    let name = &call.name.value;
    let tag = scene
        .tag(name)
        .ok_or_else(|| format!("'{name}' is not a declared tag"))?;
    let block = match tag.ty.base {
        BaseType::FunctionBlock(fb) => fb,
        _ => {
            return Err(format!(
                "'{name}' is a {} tag, not a function block",
                tag.ty.base.name()
            ));
        }
    };
    if block != FunctionBlock::MoveModulo {
        return Err(format!(
            "'{name}' is an {} instance; this version runs MC_MoveModulo (other instructions arrive with their own issues)",
            block.name()
        ));
    }
    let Args::Named(args) = &call.args else {
        return Err(format!(
            "'{name}' is a function block: call it with named inputs (Input := value)"
        ));
    };
    let mut axis = None;
    let mut set = Vec::new();
    for (input, value) in args {
        let input_name = input.value.to_ascii_lowercase();
        let v = &value.value;
        let num = |what: &str| {
            number(v, scene).ok_or_else(|| format!("{what} := {v}: expected a number or a REAL tag with a value"))
        };
        let entry = match input_name.as_str() {
            "axis" => {
                let Expr::Ident(a) = v else {
                    return Err(format!("Axis := {v}: expected an axis name"));
                };
                let binding = axes
                    .iter()
                    .find(|b| b.name.eq_ignore_ascii_case(a))
                    .ok_or_else(|| format!("Axis := {a}: no axis of that name in [[axes]]"))?;
                axis = Some(binding.handle);
                continue;
            }
            "execute" => match v {
                Expr::Bool(b) => Setting::Execute(*b),
                _ => return Err(format!("Execute := {v}: expected TRUE or FALSE")),
            },
            "position" => Setting::Position(num("Position")?),
            "velocity" => Setting::Velocity(num("Velocity")?),
            "acceleration" => Setting::Acceleration(num("Acceleration")?),
            "deceleration" => Setting::Deceleration(num("Deceleration")?),
            "jerk" => Setting::Jerk(num("Jerk")?),
            "direction" => {
                let d = match v {
                    Expr::Ident(w) => McDirection::from_name(w),
                    Expr::Integer(i) => McDirection::from_code(*i),
                    _ => None,
                };
                Setting::Direction(d.ok_or_else(|| format!("Direction := {v}: expected MC_Positive_Direction, MC_Shortest_Way, MC_Negative_Direction or MC_Current_Direction"))?)
            }
            "buffermode" => {
                let m = match v {
                    Expr::Ident(w) => McBufferMode::from_name(w),
                    Expr::Integer(i) => McBufferMode::from_code(*i),
                    _ => None,
                };
                Setting::BufferMode(m.ok_or_else(|| format!("BufferMode := {v}: expected MC_Aborting, MC_Buffered, MC_BlendingLow, MC_BlendingPrevious, MC_BlendingNext or MC_BlendingHigh"))?)
            }
            "options" => return Err("Options: ST_MoveOptions are not supported; leave the input open".to_string()),
            other => {
                return Err(format!(
                    "MC_MoveModulo has no input '{other}' (inputs: Axis, Execute, Position, Velocity, Acceleration, Deceleration, Jerk, Direction, BufferMode)"
                ));
            }
        };
        set.push(entry);
    }
    let index = match fbs.iter().position(|f| f.name.eq_ignore_ascii_case(name)) {
        Some(i) => {
            if let (Some(new), Some(old)) = (axis, fb_axis[i])
                && new != old
            {
                return Err(format!(
                    "'{name}' was called with another axis before; an instance drives one axis"
                ));
            }
            i
        }
        None => {
            let axis = axis.ok_or_else(|| format!("the first call of '{name}' must name its axis (Axis := ...)"))?;
            let handle = task.add_move_modulo(tag.name.clone(), axis);
            fbs.push(FbBinding {
                name: tag.name.clone(),
                handle,
            });
            fb_axis.push(Some(axis));
            fbs.len() - 1
        }
    };
    Ok(StepAction::MoveModulo { fb: index, set })
}
