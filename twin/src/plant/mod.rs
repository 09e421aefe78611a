//! The plant: the simulated machine the program drives.
//!
//! **In:** the scene (robot URDF, axes, obstacles, `[collision]`) when it is
//! built; every coarse update, the planner's command positions and
//! velocities. **Out:** the joints' actual positions, fed back to the
//! planner as the axes' actual positions; link poses, contacts, clearances,
//! predicted collisions and tool trails for the outputs.
//!
//! * [`axes`] binds the scene's axes to the planner and to the joints: the
//!   one place where axis units, MRP offsets and joint SI meet; [`limits`]
//!   gives them the URDF's soft travel limits.
//! * [`urdf`] (with [`stl`], [`dae`], [`mesh`]) loads the robot, [`physics`]
//!   builds the rapier multibody with a joint motor per drive
//!   ([`convert`]: nalgebra ↔ rapier) — or, with `plant = "kinematic"`,
//!   [`kinematic`] puts the joints at their setpoints instead (the plant's
//!   update does not care which: `dynamics.rs`) — [`transform`] checks an MCT target
//!   robot against its geometry ([`kinematics_check`]) and poses the
//!   virtual joints of parallel robots.
//! * [`collision`] is the parry collision model; [`collide`] runs its live
//!   checks after every physics step and the pre-flight sweep of every move
//!   that starts.
//! * [`visuals`] are the drawable pieces (URDF visuals and obstacles),
//!   [`trails`] the tool-centre trails.
//!
//! # Timing
//! Update `k` advances the planner to `t_k = k · coarse_update`; the physics
//! then runs the `coarse_update / physics_step` steps covering
//! `(t_{k-1}, t_k]`, each given the command position interpolated linearly
//! between the setpoints of `t_{k-1}` and `t_k` and the interpolated command
//! velocity as feed-forward. The joint positions at `t_k` are fed back as the
//! axes' actual positions, so `Done` (target position monitoring) sees them at
//! the next update, as a PLC sees its inputs at the start of its cycle.

pub mod axes;
pub mod collide;
pub mod collision;
pub mod convert;
pub mod dae;
mod dynamics;
mod error;
pub mod kinematic;
pub mod kinematics_check;
pub mod limits;
pub mod material;
pub mod mesh;
pub mod physics;
pub mod sensors;
pub mod servo_drive;
pub mod stl;
pub mod trails;
pub mod transform;
pub mod urdf;
pub mod visuals;
pub mod xml;

use axes::{AxisBinding, BoundAxes};
use collision::CollisionModelError;
use dynamics::Dynamics;
pub use error::PlantError;
use physics::{PhysicsError, PhysicsOptions, RobotSim};
use planner::task::MotionTask;
use trails::ToolTrail;
use transform::ParallelRig;
use urdf::RobotModel;
use visuals::{Visual, scene_visuals};

/// The simulated machine: robot model, physics, axes bound to joints,
/// collision checks and tool trails.
pub struct Plant {
    model: RobotModel,
    visuals: Vec<Visual>,
    sim: Dynamics,
    axes: Vec<AxisBinding>,
    /// Parallel robots' virtual joints posed from MCT kinematics.
    rigs: Vec<ParallelRig>,
    /// Per URDF joint, its initial position (0 where the scene gives none).
    rest_joints: Vec<f64>,
    substeps: usize,
    /// The coarse update period, s.
    update_s: f64,
    step_s: f64,
    /// Per axis, the last update's drive command (joint frame, axis units).
    previous_command: Vec<(f64, f64)>,
    collision: Option<collide::state::CollideState>,
    trails: Vec<ToolTrail>,
    /// Every link's world pose at the end of the last update (or at rest).
    world_from_link: Vec<([f64; 3], [f64; 4])>,
    /// Per axis, the joint position (SI) its engaged holding brake holds.
    brakes: Vec<Option<f64>>,
    /// Set when the physics state stopped being finite; the plant then
    /// stands still.
    physics_fault: Option<PhysicsFault>,
    /// What the physics simulation was built from (physics plant only), so
    /// that `twin bench` can build a bare one.
    physics_inputs: Option<PhysicsInputs>,
    /// `twin bench`: every physics step's drive commands, and the plant's
    /// wall time by stage.
    bench: Option<(Vec<Vec<physics::DriveCommand>>, PlantTimes)>,
    /// The cell's parts world and sensors (`None` without a cell).
    cell: Option<Cell>,
}

/// The cell: the parts world, its sensors, and the parts step.
struct Cell {
    material: material::Material,
    sensors: Vec<sensors::SensorSim>,
    /// Physics steps a parts step.
    physics_per_parts_step: usize,
    /// Physics steps since the last parts step.
    since_parts_step: usize,
    /// The links' poses at the start of the parts step.
    links_at_start: Vec<nalgebra::Isometry3<f64>>,
    /// Per axis, its position at the end of the last parts step (axis
    /// units), for the registration latches inside the next one.
    axis_positions: Vec<f64>,
    /// Per axis, its command position at the start of this update.
    commands_at_start: Vec<f64>,
}

/// What a physics simulation is built from: drives, initial joint
/// positions, options.
type PhysicsInputs = (Vec<physics::JointDrive>, Vec<(String, f64)>, PhysicsOptions);

/// The plant's wall time by stage (`twin bench`).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PlantTimes {
    /// Setting the drives and stepping the physics (or the kinematic
    /// plant), s.
    pub physics_s: f64,
    /// The live collision checks after each step, s.
    pub collision_s: f64,
    /// The parts world's steps (spawns, belts, parts, sinks), s.
    pub parts_s: f64,
    /// The sensors' checks, s.
    pub sensors_s: f64,
}

/// A run's physics, recorded to be replayed on a bare simulation: the same
/// robot, drives, step and substeps, each step given the drive commands the
/// twin gave it — rapier's work without the twin's (`twin bench`).
#[derive(Debug, Clone, Copy)]
pub struct PhysicsReplay<'a> {
    inputs: &'a PhysicsInputs,
    steps: &'a [Vec<physics::DriveCommand>],
    steps_per_update: usize,
}

impl PhysicsReplay<'_> {
    /// Physics steps recorded.
    pub fn steps(&self) -> usize {
        self.steps.len()
    }

    /// Builds a bare simulation of `model` and replays the steps on it; the
    /// wall time of the steps (the build not included), s.
    ///
    /// # Errors
    /// [`PhysicsError`] as [`RobotSim::new`] (it built once already).
    pub fn run(&self, model: &RobotModel) -> Result<f64, PhysicsError> {
        let (drives, initial, options) = self.inputs;
        let mut sim = RobotSim::new(model, drives, initial, options.clone())?;
        let started = std::time::Instant::now();
        for (k, commands) in self.steps.iter().enumerate() {
            if k % self.steps_per_update == 0 {
                sim.refresh_servo_inertias(model);
            }
            for (d, c) in commands.iter().enumerate() {
                sim.set_drive_command(d, *c);
            }
            sim.step();
        }
        Ok(started.elapsed().as_secs_f64())
    }
}

/// How fast a joint may move before the physics counts it as run away:
/// this many times its axis' maximum speed (`max_velocity`, as a program
/// may have changed it), and never less than [`RUNAWAY_FLOOR_RAD_PER_S`]
/// or [`RUNAWAY_FLOOR_M_PER_S`]. The planner never commands more than the
/// maximum speed, and a joint the drive lets go falls far slower: only a
/// solver fed gains or masses it cannot integrate gets there.
pub const RUNAWAY_SPEED_FACTOR: f64 = 100.0;

/// The least runaway speed of a rotary joint, rad/s (about 9,500 rpm).
pub const RUNAWAY_FLOOR_RAD_PER_S: f64 = 1000.0;

/// The least runaway speed of a linear joint, m/s.
pub const RUNAWAY_FLOOR_M_PER_S: f64 = 100.0;

/// How far from the world's origin a link may be before the physics
/// counts it as run away, m: a thousand times the largest length a scene
/// or URDF may give ([`crate::scene::MAX_LENGTH_M`]), so that a long
/// prismatic joint at its travel never reaches it.
pub const RUNAWAY_REACH_M: f64 = 1e7;

/// The physics state became NaN or infinite, or diverged while finite (a
/// joint faster than [`RUNAWAY_SPEED_FACTOR`] × its axis' maximum speed,
/// a link farther than [`RUNAWAY_REACH_M`] from the world's origin): a
/// model or gains the solver cannot integrate. The run stops
/// at that update: the state is never fed back as actual positions.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct PhysicsFault {
    /// Simulated time of the update that produced it, s.
    pub time_s: f64,
    /// What diverged: the first link or joint found, and how.
    pub what: String,
}

impl std::fmt::Display for PhysicsFault {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "the physics state diverged at t = {:.3} s: {}",
            self.time_s, self.what
        )
    }
}

impl Plant {
    /// Loads the URDF, adds the scene's axes to the planner, checks the
    /// transforms' target robots and builds the physics world.
    ///
    /// # Errors
    /// [`PlantError`] naming the scene file and the place that is wrong.
    pub fn new(scene: &crate::scene::Scene, task: &mut MotionTask) -> Result<Plant, PlantError> {
        let path = scene.path.clone();
        let model = RobotModel::load(&scene.robot.urdf).map_err(|source| PlantError::Urdf {
            scene: path.clone(),
            source: Box::new(source),
        })?;
        let visuals = scene_visuals(&model, scene).map_err(|e| {
            let o = &scene.obstacles[e.obstacle];
            PlantError::ObstacleMesh {
                scene: path.clone(),
                index: e.obstacle,
                line: o.location.line,
                column: o.location.column,
                obstacle: o.name.clone(),
                source: e.source,
            }
        })?;
        let mut initial: Vec<(String, f64)> = scene.robot.initial_joints.clone().into_iter().collect();
        let rest_joints = rest_joints(&model, &initial);
        let BoundAxes { axes, mut drives } = axes::bind_axes(scene, &model, task, &mut initial)?;
        transform::check_transforms(scene, &model)?;
        let axis_drives: Vec<Option<usize>> = axes.iter().map(|a| a.drive).collect();
        let rigs = transform::parallel_rigs(scene, &model, &axis_drives, &mut drives, &mut initial)?;
        initial.sort_by(|a, b| a.0.cmp(&b.0));
        let step_s = scene.physics_step_s();
        // A parallel robot's virtual joints follow the arms' kinematics:
        // posed, not simulated (see `PhysicsOptions::posed_joints`).
        let posed_joints = rigs
            .iter()
            .flat_map(|r| r.virtual_joints())
            .map(|j| model.joints[j].name.clone())
            .collect();
        let options = PhysicsOptions {
            step_s,
            substeps: scene.physics_substeps,
            posed_joints,
            ..PhysicsOptions::default()
        };
        let physics_inputs = (scene.plant == crate::scene::PlantMode::Physics)
            .then(|| (drives.clone(), initial.clone(), options.clone()));
        let sim = match scene.plant {
            crate::scene::PlantMode::Physics => {
                RobotSim::new(&model, &drives, &initial, options).map(Dynamics::Physics)
            }
            crate::scene::PlantMode::Kinematic => {
                kinematic::KinematicSim::new(&model, &drives, &initial, step_s).map(Dynamics::Kinematic)
            }
        }
        .map_err(|source| PlantError::Physics {
            scene: path.clone(),
            source,
        })?;
        let collision = collide::state::CollideState::new(&model, scene)
            .transpose()
            .map_err(|source| collision_error(scene, source))?;
        let previous_command = axes
            .iter()
            .map(|a| (task.axis_state(a.handle).command_position, 0.0))
            .collect();
        let world_from_link = sim.world_from_link();
        let cell = build_cell(scene, &model, &sim, &axes, task)?;
        Ok(Plant {
            cell,
            brakes: vec![None; axes.len()],
            substeps: (scene.coarse_update_ms / scene.physics_step_ms).round().max(1.0) as usize,
            update_s: scene.coarse_update_s(),
            model,
            visuals,
            sim,
            axes,
            rigs,
            rest_joints,
            step_s,
            previous_command,
            collision,
            trails: Vec::new(),
            world_from_link,
            physics_fault: None,
            physics_inputs,
            bench: None,
        })
    }

    /// Binds the tool trails of the coordinate systems the program uses
    /// (once the program is bound) and records their first points.
    ///
    /// # Errors
    /// [`PlantError::ToolLink`] when a `tool_link` is not a URDF link.
    pub fn bind_tool_trails(&mut self, scene: &crate::scene::Scene, task: &MotionTask) -> Result<(), PlantError> {
        self.trails = trails::tool_trails(scene, &self.model, task)?;
        self.record_trails();
        Ok(())
    }

    /// The physics steps of one coarse update: the drives follow the
    /// planner's new setpoints, the live collision checks run after every
    /// step, and the joints' positions are fed back as actual positions.
    pub fn advance(&mut self, task: &mut MotionTask) {
        if self.physics_fault.is_some() {
            return;
        }
        self.collision_begin_update();
        let now: Vec<(f64, f64)> = self.axes.iter().map(|a| a.drive_command(task)).collect();
        self.set_drive_modes(task);
        self.sim.refresh_servo_inertias(&self.model);
        let n = self.substeps;
        let started = self.bench.is_some().then(std::time::Instant::now);
        let mut collision_s = 0.0;
        self.set_axis_belts(task);
        if self.sim.is_kinematic() && self.collision.is_none() && self.cell.is_none() {
            // Nothing looks between the updates: the joints go to the
            // command at once.
            self.set_setpoints(&now, 1.0, 1.0);
            self.sim.step(&self.model, n);
        } else {
            // Physics: the setpoint at the start of each step, the velocity
            // at its middle. Kinematic: where the joint is at the step's
            // end, so the last step ends on the command exactly.
            let ahead = if self.sim.is_kinematic() { 1.0 } else { 0.0 };
            for j in 0..n {
                let f = (j as f64 + ahead) / n as f64;
                self.set_setpoints(&now, f, (j as f64 + 0.5) / n as f64);
                if let (Some((steps, _)), Dynamics::Physics(sim)) = (self.bench.as_mut(), &self.sim) {
                    steps.push((0..sim.drive_count()).map(|d| sim.drive_command(d)).collect());
                }
                self.sim.step(&self.model, 1);
                let checked = started.map(|_| std::time::Instant::now());
                self.collision_after_physics_step(task);
                if let Some(t) = checked {
                    collision_s += t.elapsed().as_secs_f64();
                }
                self.cell_after_physics_step(task, (j + 1) as f64 / n as f64);
                if self.collision_abort() {
                    break;
                }
            }
        }
        if let (Some(t), Some((_, times))) = (started, self.bench.as_mut()) {
            times.physics_s += t.elapsed().as_secs_f64() - collision_s;
            times.collision_s += collision_s;
        }
        self.previous_command = now;
        if let Some(cell) = self.cell.as_mut() {
            cell.commands_at_start = self
                .axes
                .iter()
                .map(|a| task.axis_state(a.handle).command_position)
                .collect();
        }
        let world_from_link = self.sim.world_from_link();
        if let Some(what) = self
            .non_finite(&world_from_link)
            .or_else(|| self.runaway(task, &world_from_link))
        {
            self.physics_fault = Some(PhysicsFault {
                time_s: task.time_s(),
                what,
            });
            return;
        }
        for axis in &self.axes {
            let Some(drive) = axis.drive else { continue };
            let position = axis.axis_position(task, self.sim.joint_position(drive));
            task.feed_actual_position(axis.handle, position);
        }
        self.world_from_link = world_from_link;
        self.record_trails();
    }

    /// The belts that follow an axis take its actual velocity (m/s).
    fn set_axis_belts(&mut self, task: &MotionTask) {
        let Some(cell) = self.cell.as_mut() else { return };
        for c in cell.material.conveyors_mut() {
            if let Some(a) = c.axis() {
                let axis = &self.axes[a];
                c.set_axis_speed(axis.to_si(task.axis_state(axis.handle).actual_velocity));
            }
        }
    }

    /// After a physics step: a parts step when one is due (the parts world
    /// and the sensors over it, with the links' poses at its start and end).
    fn cell_after_physics_step(&mut self, task: &mut MotionTask, fraction: f64) {
        let Some(cell) = self.cell.as_mut() else { return };
        cell.since_parts_step += 1;
        if cell.since_parts_step < cell.physics_per_parts_step {
            return;
        }
        // Each axis' position now, for the registration latches (a scene
        // without a registration sensor needs none): a driven axis' joint,
        // a virtual axis' command interpolated inside the update.
        let wired = cell.sensors.iter().any(|s| s.registration.is_some());
        let positions: Vec<f64> = if wired {
            self.axes
                .iter()
                .zip(&cell.commands_at_start)
                .map(|(a, start)| match a.drive {
                    Some(d) => a.axis_position(task, self.sim.joint_position(d)),
                    None => start + (task.axis_state(a.handle).command_position - start) * fraction,
                })
                .collect()
        } else {
            Vec::new()
        };
        cell.since_parts_step = 0;
        let t1 = self.sim.time_s();
        let t0 = t1 - cell.material.step_s();
        let links = self.sim.world_from_link_isometries();
        let timed = self.bench.is_some().then(std::time::Instant::now);
        cell.material.step(t1, &cell.links_at_start, &links);
        let parts_done = timed.map(|t| (t, std::time::Instant::now()));
        sensors::step(
            &mut cell.sensors,
            &cell.material,
            (t0, t1),
            &cell.links_at_start,
            &links,
        );
        let sensors_done = timed.map(|_| std::time::Instant::now());
        // Registration: each edge of a wired sensor latches the axis'
        // position at its instant, interpolated inside the parts step.
        for s in &cell.sensors {
            let Some((axis, input)) = s.registration else { continue };
            for &(t, rising) in s.step_edges() {
                let f = ((t - t0) / (t1 - t0)).clamp(0.0, 1.0);
                let p = cell.axis_positions[axis] + (positions[axis] - cell.axis_positions[axis]) * f;
                task.registration_edge(self.axes[axis].handle, input, rising, p);
            }
        }
        if wired {
            cell.axis_positions = positions;
        }
        cell.material.finish_step();
        cell.links_at_start = links;
        if cell.material.take_payload_changed() {
            self.sim.set_payloads(&cell.material.payloads());
        }
        if let (Some((t, p)), Some(s), Some((_, times))) = (parts_done, sensors_done, self.bench.as_mut()) {
            times.parts_s += (p - t).as_secs_f64() + s.elapsed().as_secs_f64();
            times.sensors_s += (s - p).as_secs_f64();
        }
    }

    /// The parts world, if the scene has a cell.
    pub fn material(&self) -> Option<&material::Material> {
        self.cell.as_ref().map(|c| &c.material)
    }

    /// The parts world, to set its devices' commands.
    pub fn material_mut(&mut self) -> Option<&mut material::Material> {
        self.cell.as_mut().map(|c| &mut c.material)
    }

    /// A vision sensor's trigger output after the scans at `t`
    /// ([`sensors::SensorSim::vision_trigger`]): the camera sees the cell
    /// as the last update left it.
    pub fn vision_trigger(&mut self, sensor: usize, on: bool, t: f64) {
        let Some(cell) = self.cell.as_mut() else { return };
        if !cell.sensors[sensor].vision_rises(on) {
            return;
        }
        let links = self.sim.world_from_link_isometries();
        cell.sensors[sensor].vision_capture(t, &cell.material, &links);
    }

    /// The sensors, in scene order.
    pub fn sensors(&self) -> &[sensors::SensorSim] {
        self.cell.as_ref().map_or(&[], |c| c.sensors.as_slice())
    }

    /// The sensors, to read their tags.
    pub fn sensors_mut(&mut self) -> &mut [sensors::SensorSim] {
        self.cell.as_mut().map_or(&mut [], |c| c.sensors.as_mut_slice())
    }

    /// Each drive's mode for this update from its axis' state: an enabled
    /// drive follows the command; a disabled one is free, or held by its
    /// holding brake where the joint was when the drive went off.
    fn set_drive_modes(&mut self, task: &MotionTask) {
        for (k, axis) in self.axes.iter().enumerate() {
            let Some(drive) = axis.drive else { continue };
            let enabled = task.is_drive_enabled(axis.handle);
            if enabled {
                self.brakes[k] = None;
            } else if axis.holding_brake && self.brakes[k].is_none() {
                self.brakes[k] = Some(self.sim.joint_position(drive));
            }
            self.sim.set_drive_free(drive, !enabled && !axis.holding_brake);
            self.sim.set_drive_braked(drive, self.brakes[k].is_some());
        }
    }

    /// Drive setpoints at fraction `f` of the update (velocity at `fm`),
    /// interpolated from the previous update's commands to `now`; a braked
    /// joint's setpoint is its brake position.
    fn set_setpoints(&mut self, now: &[(f64, f64)], f: f64, fm: f64) {
        // The joints' position setpoints, for the parallel rigs (none: no list).
        let rigs = !self.rigs.is_empty();
        let mut setpoints = Vec::new();
        for (k, axis) in self.axes.iter().enumerate() {
            let Some(drive) = axis.drive else { continue };
            if let Some(held) = self.brakes[k] {
                self.sim.set_setpoint(drive, held, 0.0);
                if rigs {
                    setpoints.push((drive, held));
                }
                continue;
            }
            let (p0, v0) = self.previous_command[k];
            let (p1, v1) = now[k];
            let p = p0 + (p1 - p0) * f;
            let v = v0 + (v1 - v0) * fm;
            self.sim.set_setpoint(drive, axis.to_si(p), axis.to_si(v));
            self.sim
                .set_setpoint_acceleration(drive, axis.to_si((v1 - v0) / self.update_s));
            if rigs {
                setpoints.push((drive, axis.to_si(p)));
            }
        }
        for rig in &mut self.rigs {
            let setpoint = |d: usize| setpoints.iter().find(|(x, _)| *x == d).map(|(_, p)| *p);
            rig.drive(&self.model, &mut self.sim, self.step_s, setpoint);
        }
    }

    /// The first link pose or drive position that is not finite, named.
    fn non_finite(&self, world_from_link: &[([f64; 3], [f64; 4])]) -> Option<String> {
        let finite = |(t, q): &([f64; 3], [f64; 4])| t.iter().chain(q).all(|v| v.is_finite());
        if let Some(k) = world_from_link.iter().position(|p| !finite(p)) {
            return Some(format!("link {}'s pose is not finite", self.model.links[k].name));
        }
        self.axes.iter().find_map(|axis| {
            let drive = axis.drive?;
            (!self.sim.joint_position(drive).is_finite())
                .then(|| format!("axis {}'s joint position is not finite", axis.name))
        })
    }

    /// The first link past the scene's reach or joint past its runaway
    /// speed ([`RUNAWAY_SPEED_FACTOR`]), named with the link it moves.
    fn runaway(&self, task: &MotionTask, world_from_link: &[([f64; 3], [f64; 4])]) -> Option<String> {
        let max_m = RUNAWAY_REACH_M;
        if let Some(k) = world_from_link
            .iter()
            .position(|(t, _)| t.iter().map(|x| x * x).sum::<f64>() > max_m * max_m)
        {
            let [x, y, z] = world_from_link[k].0;
            return Some(format!(
                "link {} left the scene: at ({x:.3e}, {y:.3e}, {z:.3e}) m, farther than {max_m:e} m from the origin",
                self.model.links[k].name
            ));
        }
        self.axes.iter().find_map(|axis| {
            let (drive, joint) = (axis.drive?, axis.joint?);
            let speed = self.sim.joint_velocity(drive)?.abs();
            let joint = &self.model.joints[joint];
            let (floor, unit) = if matches!(joint.kind, urdf::JointKind::Prismatic) {
                (RUNAWAY_FLOOR_M_PER_S, "m/s")
            } else {
                (RUNAWAY_FLOOR_RAD_PER_S, "rad/s")
            };
            let limit = (RUNAWAY_SPEED_FACTOR * axis.to_si(task.axis_config(axis.handle).max_velocity)).max(floor);
            (speed > limit).then(|| {
                format!(
                    "link {} ran away: joint {} of axis {} at {speed:.4e} {unit}, past {limit:.4e} {unit} \
                     ({RUNAWAY_SPEED_FACTOR} × the axis' maximum speed, at least {floor} {unit})",
                    self.model.links[joint.child.0].name, joint.name, axis.name
                )
            })
        })
    }

    /// Set once the physics state stopped being finite (the run stops).
    pub fn physics_fault(&self) -> Option<&PhysicsFault> {
        self.physics_fault.as_ref()
    }

    fn record_trails(&mut self) {
        if self.trails.is_empty() {
            return;
        }
        trails::record(&mut self.trails, &self.world_from_link);
    }

    /// Sets axis `axis_index`'s servo drive gains and limits (a program's
    /// SSV of a drive attribute), used from the next physics step; no
    /// effect on an axis without a servo drive.
    pub fn set_servo_gains(&mut self, axis_index: usize, gains: crate::scene::ServoGains) {
        if let Some(d) = self.axes[axis_index].drive {
            self.sim.set_servo_gains(d, gains);
        }
    }

    /// Axis `axis_index`'s servo drive torque in the last physics substep
    /// (N·m or N, 0 while the drive is off); `None` for an axis without a
    /// servo drive (virtual, or a spring `motor`).
    pub fn drive_torque(&self, axis_index: usize) -> Option<f64> {
        self.axes[axis_index].drive.and_then(|d| self.sim.drive_torque(d))
    }

    /// Axis `axis_index`'s largest |servo drive torque| over the run so far
    /// (every substep); `None` as for [`Plant::drive_torque`].
    pub fn drive_peak_torque(&self, axis_index: usize) -> Option<f64> {
        self.axes[axis_index].drive.and_then(|d| self.sim.drive_peak_torque(d))
    }

    /// The robot model.
    pub fn model(&self) -> &RobotModel {
        &self.model
    }

    /// Every drawable piece: URDF visuals and obstacles, meshes loaded once.
    pub fn visuals(&self) -> &[Visual] {
        &self.visuals
    }

    /// The bound axes, in scene order.
    pub fn axes(&self) -> &[AxisBinding] {
        &self.axes
    }

    /// World poses of every URDF link (translation m, quaternion xyzw), in
    /// model link order, at the end of the last update.
    pub fn world_from_link(&self) -> &[([f64; 3], [f64; 4])] {
        &self.world_from_link
    }

    /// `twin bench`: from now on, record every physics step's drive
    /// commands (for [`Plant::physics_replay`]) and time the plant's
    /// stages ([`Plant::times`]).
    pub fn record_for_bench(&mut self) {
        self.bench = Some((Vec::new(), PlantTimes::default()));
    }

    /// The plant's wall time by stage since [`Plant::record_for_bench`].
    pub fn times(&self) -> Option<PlantTimes> {
        self.bench.as_ref().map(|(_, t)| *t)
    }

    /// The physics steps recorded since [`Plant::record_for_bench`], to be
    /// replayed on a bare simulation; `None` for the kinematic plant or
    /// when nothing was recorded.
    pub fn physics_replay(&self) -> Option<PhysicsReplay<'_>> {
        let (steps, _) = self.bench.as_ref()?;
        Some(PhysicsReplay {
            inputs: self.physics_inputs.as_ref()?,
            steps,
            steps_per_update: self.substeps,
        })
    }

    /// The tool-centre trails of the coordinate systems that name a
    /// `tool_link`, in the order the program first uses the systems.
    pub fn tool_trails(&self) -> &[ToolTrail] {
        &self.trails
    }
}

/// The cell of a scene that has one: its parts world and sensors.
fn build_cell(
    scene: &crate::scene::Scene,
    model: &RobotModel,
    sim: &Dynamics,
    axes: &[AxisBinding],
    task: &MotionTask,
) -> Result<Option<Cell>, PlantError> {
    if scene.cell.is_empty() {
        return Ok(None);
    }
    let links = sim.world_from_link_isometries();
    let material = material::Material::new(scene, model, &links).map_err(|e| {
        let (at, field) = match &e {
            material::MaterialError::UnknownLink { gripper, .. } => (
                scene.cell.grippers[*gripper].link.1,
                format!("grippers[{gripper}].link"),
            ),
            material::MaterialError::SpawnsInside { source_index, .. } => (
                scene.cell.sources[*source_index].location,
                format!("sources[{source_index}].position"),
            ),
            _ => (crate::scene::Location { line: 1, column: 1 }, "part_types".to_owned()),
        };
        PlantError::Cell {
            scene: scene.path.clone(),
            line: at.line,
            column: at.column,
            field,
            message: e.to_string(),
        }
    })?;
    let sensors = sensors::build(scene, model).map_err(|(index, field, message)| {
        let at = scene.cell.sensors[index].location;
        PlantError::Cell {
            scene: scene.path.clone(),
            line: at.line,
            column: at.column,
            field,
            message,
        }
    })?;
    Ok(Some(Cell {
        material,
        sensors,
        physics_per_parts_step: (scene.cell.parts_step_ms / scene.physics_step_ms).round().max(1.0) as usize,
        since_parts_step: 0,
        links_at_start: links,
        axis_positions: axes
            .iter()
            .map(|a| match a.drive {
                Some(d) => a.axis_position(task, sim.joint_position(d)),
                None => task.axis_state(a.handle).command_position,
            })
            .collect(),
        commands_at_start: axes
            .iter()
            .map(|a| task.axis_state(a.handle).command_position)
            .collect(),
    }))
}

/// Per URDF joint, the scene's initial position (0 where it gives none).
fn rest_joints(model: &RobotModel, initial: &[(String, f64)]) -> Vec<f64> {
    let mut q = vec![0.0; model.joints.len()];
    for (name, value) in initial {
        if let Some(j) = model.joint_by_name(name) {
            q[j.0] = *value;
        }
    }
    q
}

/// A collision-model error placed at its field, or at the `[collision]` table.
fn collision_error(scene: &crate::scene::Scene, source: CollisionModelError) -> PlantError {
    let at = scene.collision.as_ref().map(|c| c.location).unwrap_or_default();
    let (line, column) = match &source {
        CollisionModelError::UnknownToolLink { line, column, .. }
        | CollisionModelError::UnknownPairBody { line, column, .. } => (*line, *column),
        _ => (at.line, at.column),
    };
    PlantError::Collision {
        scene: scene.path.clone(),
        line,
        column,
        source,
    }
}

#[cfg(test)]
#[allow(clippy::unwrap_used)] // a failed unwrap is a failed test
mod tests {
    use super::*;

    #[test]
    fn a_non_finite_physics_state_stops_the_plant_instead_of_being_fed_back() {
        // A NaN inertial origin used to make the tool NaN from the first
        // update while every axis reported act_pos == cmd_pos; here the
        // state is poisoned by hand, as a model the solver cannot
        // integrate would.
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/indexing_table.toml");
        let scene = crate::scene::load(&path).unwrap();
        let mut task = MotionTask::new(scene.coarse_update_s()).unwrap();
        let mut plant = Plant::new(&scene, &mut task).unwrap();
        let axis = plant.axes[0].handle;
        task.update();
        plant.advance(&mut task);
        assert!(plant.physics_fault().is_none());
        let last_actual = task.axis_state(axis).actual_position;
        let last_poses = plant.world_from_link().to_vec();

        let Dynamics::Physics(sim) = &mut plant.sim else {
            panic!("a physics plant");
        };
        sim.set_gravity_for_test([f64::NAN; 3]);
        task.update();
        plant.advance(&mut task);
        let fault = plant.physics_fault().cloned().expect("a physics fault");
        assert!(fault.what.contains("link") || fault.what.contains("axis"), "{fault}");
        assert!(
            fault.to_string().starts_with("the physics state diverged at t = "),
            "{fault}"
        );
        assert_eq!(
            task.axis_state(axis).actual_position,
            last_actual,
            "nothing non-finite is fed back"
        );
        assert_eq!(
            plant.world_from_link(),
            last_poses.as_slice(),
            "the last finite poses stay"
        );
        // The plant stands still from then on.
        task.update();
        plant.advance(&mut task);
        assert_eq!(plant.physics_fault(), Some(&fault));
    }
}
