//! A [`RobotModel`] simulated in rapier (f64) as a multibody with a fixed
//! root, driven by per-joint position + velocity motors.
//!
//! One rigid body per URDF link that moves, placed so that its body frame
//! *is* the link frame; the root link's body is fixed at the world origin.
//! A link on a fixed joint (a tool, flange or mounting plate; through a
//! chain of fixed joints) has no body of its own: its mass and colliders
//! ride on the body of the nearest ancestor that moves, and its pose is
//! that body's times the fixed offset. The dynamics are the same (the
//! lumped mass is exact for a rigid attachment; traces agree to rounding,
//! 1e-11 N·m on `heavy_arm`'s torques), and rapier's multibody has fewer
//! links to update each substep (`heavy_arm`: 6 of its 8 links). Masses and inertias come from each link's `<inertial>`;
//! colliders from its `<collision>` shapes (boxes, cylinders, spheres,
//! convex hulls of meshes) carry no mass. The robot's own links never
//! collide with each other (they share a collision group that filters
//! itself out); other bodies added later in the default groups still
//! collide with them.
//!
//! # Motor model
//! Drives use rapier's **acceleration-based** motor model: each step the
//! joint is pulled towards its setpoint like a spring-damper whose
//! `stiffness` (1/s²) and `damping` (1/s) act on acceleration, independent of
//! the link inertia behind the joint. A critically damped drive with natural
//! angular frequency ω has `stiffness = ω²`, `damping = 2ω`
//! ([`JointDrive::critically_damped`]); the gains of one drive therefore work
//! on any payload. The spring is integrated implicitly, so high gains stay
//! stable at coarse steps. `max_force` caps the motor's generalized force
//! (N·m or N); the cap is the only place the link inertia shows.
//!
//! For the indexing table (`scenes/robots/indexing_table`) a 30 Hz drive
//! with a 300 N·m cap tracks a 90° cycloidal index in 0.5 s within about
//! 1.1 mrad (20 Hz: 2.5 mrad, 50 Hz: 0.4 mrad) at the default 2 ms step and
//! settles on the target; the test at the bottom of this file checks it.
//!
//! Choices rapier and URDF leave open:
//! - Joints without a drive are passive (free under gravity, URDF limits
//!   still enforced for revolute and prismatic joints).
//! - A link without `<inertial>` gets [`PhysicsOptions::default_link_mass_kg`]
//!   with the inertia of a solid 5 cm-radius sphere.
//! - Bodies never sleep, so a joint at rest reacts to its next setpoint at once.

use nalgebra::{Isometry3, Vector3};
use rapier3d_f64::prelude::{JointAxis, MotorModel, MultibodyJointHandle, PhysicsWorld, RigidBodyHandle};

use crate::plant::convert::{isometry_to_arrays, pose_from_rapier, pose_to_rapier, vector_to_rapier};
use crate::plant::servo_drive::{ServoLoop, Setpoint, joint_inertia};
use crate::plant::urdf::RobotModel;

mod build;
mod config;

use build::{LinkFrame, dof_axis, insert_joints, insert_links, movable_joint, posed_links, validate_options};
pub(crate) use build::{driven_joints, initial_positions};
use config::DEFAULT_INERTIA_RADIUS_M;
pub use config::{JointDrive, PhysicsError, PhysicsOptions};

/// What a drive is told for one step ([`RobotSim::drive_command`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DriveCommand {
    /// Setpoint position at the start of the step, rad or m.
    pub position: f64,
    /// Setpoint velocity, rad/s or m/s.
    pub velocity: f64,
    /// Setpoint acceleration (a servo drive's feed-forward), rad/s² or m/s².
    pub acceleration: f64,
    /// The drive is off.
    pub free: bool,
    /// The holding brake is engaged.
    pub braked: bool,
}

/// The velocity (rad/s or m/s) a servo drive's motor asks for, far beyond
/// any joint's reach, so that its force limit (the loops' torque) binds.
const UNREACHABLE_SPEED: f64 = 1.0e6;

/// The force-based damping of that motor: large, so the limit binds even
/// when the joint moves fast.
const UNREACHABLE_DAMPING: f64 = 1.0e9;

/// What [`RobotSim`] keeps per drive.
#[derive(Debug, Clone)]
struct DriveSlot {
    /// The multibody joint; `None` for a posed joint (its position is the
    /// setpoint).
    handle: Option<MultibodyJointHandle>,
    axis: JointAxis,
    stiffness: f64,
    damping: f64,
    /// Setpoint position at the start of the current step (rad or m).
    position: f64,
    /// Setpoint velocity (rad/s or m/s).
    velocity: f64,
    /// The motor is off: no torque, the joint is free.
    free: bool,
    /// The spring drive's force limit (`f64::MAX` for none).
    max_force: f64,
    /// Setpoint acceleration (rad/s² or m/s²), for a servo drive's
    /// feed-forward.
    acceleration: f64,
    /// A servo drive: its loops, and the bodies and axis its torque acts on.
    servo: Option<ServoSlot>,
    /// A servo drive's holding brake holds the joint at `position`.
    braked: bool,
}

/// A servo drive's loops, whose torque the joint motor applies.
#[derive(Debug, Clone)]
struct ServoSlot {
    control: ServoLoop,
    /// The URDF joint it drives.
    joint: usize,
    /// No `SystemInertia` given: the loops scale by the inertia the joint
    /// moves in the current pose ([`RobotSim::refresh_servo_inertias`]).
    pose_inertia: bool,
}

/// A URDF robot in a rapier world, stepped at a fixed rate with joint motors.
///
/// Deterministic: two sims built alike and fed the same setpoints produce
/// bit-identical states (single-threaded rapier, no clocks).
pub struct RobotSim {
    world: PhysicsWorld,
    /// Where each model link is, in model link order: its rigid body, and
    /// for a link merged into an ancestor's body, its pose on that body.
    link_frames: Vec<LinkFrame>,
    /// The posed links' joints, parents first: (URDF joint index, the
    /// drive setting its position, if any).
    posed: Vec<(usize, Option<usize>)>,
    /// Per URDF joint: parent_from_joint and the joint itself, to pose
    /// links (copied from the model).
    joints: Vec<crate::plant::urdf::Joint>,
    drives: Vec<DriveSlot>,
    step_s: f64,
    substeps: usize,
    steps: u64,
    default_link_mass_kg: f64,
    /// Per body carrying a payload now or before: its mass properties
    /// without payload.
    unloaded: Vec<(RigidBodyHandle, rapier3d_f64::prelude::MassProperties)>,
}

impl std::fmt::Debug for RobotSim {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("RobotSim")
            .field("links", &self.link_frames.len())
            .field("drives", &self.drives)
            .field("step_s", &self.step_s)
            .field("steps", &self.steps)
            .finish_non_exhaustive()
    }
}

impl RobotSim {
    /// Builds the world: `model` as a fixed-root multibody at the world origin,
    /// `drives` as motors (drive `i` is addressed as index `i` afterwards),
    /// joints placed at `initial_joint_positions` (rad or m; unnamed joints
    /// at 0). Each drive's setpoint starts at its joint's initial position
    /// with zero velocity, so the robot holds still until told otherwise.
    ///
    /// # Errors
    /// [`PhysicsError::UnknownJoint`] or [`PhysicsError::FixedJoint`] for a
    /// bad joint name, [`PhysicsError::DuplicateDrive`],
    /// [`PhysicsError::InvalidDrive`], [`PhysicsError::InvalidOption`],
    /// [`PhysicsError::InvalidInitialPosition`],
    /// [`PhysicsError::DegenerateCollisionMesh`], [`PhysicsError::Multibody`].
    pub fn new(
        model: &RobotModel,
        drives: &[JointDrive],
        initial_joint_positions: &[(String, f64)],
        options: PhysicsOptions,
    ) -> Result<RobotSim, PhysicsError> {
        validate_options(&options)?;
        let q0 = initial_positions(model, initial_joint_positions)?;
        let driven = driven_joints(model, drives)?;

        let mut world = PhysicsWorld::new();
        world.gravity = vector_to_rapier(&Vector3::from(options.gravity_mps2));
        world.integration_parameters.dt = options.step_s / options.substeps as f64;
        world.integration_parameters.num_solver_iterations = 1;
        let posed_link = posed_links(model, &options.posed_joints)?;
        let link_frames = insert_links(&mut world, model, &q0, &options, &posed_link)?;
        let joint_handles = insert_joints(&mut world, model, &link_frames, &posed_link)?;

        let mut slots = Vec::with_capacity(drives.len());
        for drive in drives {
            let j = movable_joint(model, &drive.joint)?;
            let handle = joint_handles[j];
            if handle.is_none() && !posed_link[model.joints[j].child.0] {
                return Err(PhysicsError::Multibody {
                    joint: drive.joint.clone(),
                });
            }
            let joint = &model.joints[j];
            let servo = drive.servo.map(|gains| {
                let inertia = gains.system_inertia.unwrap_or_else(|| {
                    let poses = model.world_from_link(&q0);
                    joint_inertia(model, j, &poses, options.default_link_mass_kg, DEFAULT_INERTIA_RADIUS_M)
                });
                ServoSlot {
                    control: ServoLoop::new(gains, inertia.max(1e-9)),
                    joint: j,
                    pose_inertia: gains.system_inertia.is_none(),
                }
            });
            slots.push(DriveSlot {
                handle,
                axis: dof_axis(joint.kind),
                stiffness: drive.stiffness,
                damping: drive.damping,
                position: q0[j],
                velocity: 0.0,
                free: false,
                max_force: drive.max_force.unwrap_or(f64::MAX),
                acceleration: 0.0,
                servo,
                braked: false,
            });
        }

        let posed = model
            .topological_joints()
            .iter()
            .filter(|j| {
                let child = model.joints[j.0].child.0;
                posed_link[child] && link_frames[child].body_from_link.is_none()
            })
            .map(|j| (j.0, driven[j.0]))
            .collect();
        let mut sim = RobotSim {
            world,
            link_frames,
            posed,
            joints: model.joints.clone(),
            drives: slots,
            step_s: options.step_s,
            substeps: options.substeps,
            default_link_mass_kg: options.default_link_mass_kg,
            steps: 0,
            unloaded: Vec::new(),
        };
        sim.place_at_rest(model, drives, &driven, &joint_handles, &q0);
        Ok(sim)
    }

    /// Displaces every joint to its initial coordinate, sets each driven
    /// joint's motor to hold it, and places the links there.
    fn place_at_rest(
        &mut self,
        model: &RobotModel,
        drives: &[JointDrive],
        driven: &[Option<usize>],
        joint_handles: &[Option<MultibodyJointHandle>],
        q0: &[f64],
    ) {
        for (j, joint) in model.joints.iter().enumerate() {
            let Some(handle) = joint_handles[j] else {
                continue;
            };
            let axis = dof_axis(joint.kind);
            if let Some((multibody, link_id)) = self.world.multibody_joints.get_mut(handle)
                && let Some(link) = multibody.link_mut(link_id)
            {
                if joint.kind.is_movable() && q0[j] != 0.0 {
                    link.joint.apply_displacement(&[q0[j]]);
                }
                if let Some(d) = driven[j] {
                    let drive = &drives[d];
                    let data = &mut link.joint.data;
                    data.set_motor_model(axis, MotorModel::AccelerationBased);
                    data.set_motor(axis, q0[j], 0.0, drive.stiffness, drive.damping);
                    data.set_motor_max_force(axis, drive.max_force.unwrap_or(f64::MAX));
                }
            }
        }
        // Place every link at the initial coordinates (the whole tree is one multibody).
        if let Some(handle) = joint_handles.iter().flatten().next()
            && let Some((multibody, _)) = self.world.multibody_joints.get_mut(*handle)
        {
            multibody.forward_kinematics(&self.world.bodies, false);
            multibody.update_rigid_bodies(&mut self.world.bodies, false);
        }
    }

    /// Sets gravity (m/s²): lets a test poison the state with NaN, as a
    /// model the solver cannot integrate would.
    #[cfg(test)]
    pub(crate) fn set_gravity_for_test(&mut self, gravity_mps2: [f64; 3]) {
        self.world.gravity = vector_to_rapier(&Vector3::from(gravity_mps2));
    }

    /// Number of drives (the valid `drive_index` range is `0..drive_count()`).
    pub fn drive_count(&self) -> usize {
        self.drives.len()
    }

    /// Sets drive `drive_index`'s target for the next [`RobotSim::step`]:
    /// `position` (rad or m, unwrapped for continuous joints) is the
    /// trajectory sample at the *start* of the step ([`RobotSim::time_s`]),
    /// `velocity` (rad/s or m/s) the feed-forward velocity over the step —
    /// best the sample at `time_s() + step_s() / 2`, the one at `time_s()`
    /// is close. Within the step the motor target advances from `position`
    /// at `velocity`. The setpoint persists until the next call.
    ///
    /// # Panics
    /// If `drive_index >= drive_count()`.
    pub fn set_setpoint(&mut self, drive_index: usize, position: f64, velocity: f64) {
        let slot = &mut self.drives[drive_index];
        slot.position = position;
        slot.velocity = velocity;
        self.apply_motor_targets(0.0);
    }

    /// Everything drive `drive_index` is told for the next step (setpoint,
    /// feed-forward, off, braked): recorded by `twin bench` and replayed
    /// onto a bare simulation with [`RobotSim::set_drive_command`].
    ///
    /// # Panics
    /// If `drive_index >= drive_count()`.
    pub fn drive_command(&self, drive_index: usize) -> DriveCommand {
        let slot = &self.drives[drive_index];
        DriveCommand {
            position: slot.position,
            velocity: slot.velocity,
            acceleration: slot.acceleration,
            free: slot.free,
            braked: slot.braked,
        }
    }

    /// Tells drive `drive_index` everything at once (see
    /// [`RobotSim::drive_command`]).
    ///
    /// # Panics
    /// If `drive_index >= drive_count()`.
    pub fn set_drive_command(&mut self, drive_index: usize, command: DriveCommand) {
        let slot = &mut self.drives[drive_index];
        slot.position = command.position;
        slot.velocity = command.velocity;
        slot.acceleration = command.acceleration;
        slot.free = command.free;
        slot.braked = command.braked;
        self.apply_motor_targets(0.0);
    }

    /// Turns drive `drive_index`'s motor off (`free`: the joint moves only
    /// under gravity and contacts) or on again (following its setpoint).
    ///
    /// # Panics
    /// If `drive_index >= drive_count()`.
    pub fn set_drive_free(&mut self, drive_index: usize, free: bool) {
        self.drives[drive_index].free = free;
        self.apply_motor_targets(0.0);
    }

    /// Sets drive `drive_index`'s setpoint acceleration (rad/s² or m/s²),
    /// the feed-forward of a servo drive (a spring drive ignores it).
    ///
    /// # Panics
    /// If `drive_index >= drive_count()`.
    pub fn set_setpoint_acceleration(&mut self, drive_index: usize, acceleration: f64) {
        self.drives[drive_index].acceleration = acceleration;
    }

    /// Engages (`true`) or releases a servo drive's holding brake: engaged,
    /// the joint is held at its setpoint position by the brake and the
    /// loops are off. A spring drive holds its setpoint anyway.
    ///
    /// # Panics
    /// If `drive_index >= drive_count()`.
    pub fn set_drive_braked(&mut self, drive_index: usize, braked: bool) {
        self.drives[drive_index].braked = braked;
        self.apply_motor_targets(0.0);
    }

    /// Changes a servo drive's gains and limits, from the next substep on
    /// (a program's SSV of a drive attribute); a `SystemInertia` replaces
    /// the inertia of the pose. No effect on a spring drive.
    ///
    /// # Panics
    /// If `drive_index >= drive_count()`.
    pub fn set_servo_gains(&mut self, drive_index: usize, gains: crate::scene::ServoGains) {
        if let Some(servo) = self.drives[drive_index].servo.as_mut() {
            servo.control.set_gains(gains);
            if let Some(inertia) = gains.system_inertia {
                servo.control.set_inertia(inertia.max(1e-9));
                servo.pose_inertia = false;
            }
        }
    }

    /// The torque (N·m or N) a servo drive applied in the last substep
    /// (0 while it is off or braked); `None` for a spring drive.
    ///
    /// # Panics
    /// If `drive_index >= drive_count()`.
    pub fn drive_torque(&self, drive_index: usize) -> Option<f64> {
        self.drives[drive_index].servo.as_ref().map(|s| s.control.last_torque())
    }

    /// The largest |torque| (N·m or N) a servo drive applied in any
    /// substep so far; `None` for a spring drive.
    ///
    /// # Panics
    /// If `drive_index >= drive_count()`.
    pub fn drive_peak_torque(&self, drive_index: usize) -> Option<f64> {
        self.drives[drive_index].servo.as_ref().map(|s| s.control.peak_torque())
    }

    /// Sets each servo drive without a `SystemInertia` to the inertia its
    /// joint moves in the current pose (`model` is the one the simulation
    /// was built from): the loops keep their bandwidths as the arm folds
    /// and stretches, like a drive with a load observer.
    pub fn refresh_servo_inertias(&mut self, model: &RobotModel) {
        if !self
            .drives
            .iter()
            .any(|d| d.servo.as_ref().is_some_and(|s| s.pose_inertia))
        {
            return;
        }
        let poses = self.world_from_link_isometries();
        let mass = self.default_link_mass_kg;
        for slot in &mut self.drives {
            if let Some(servo) = slot.servo.as_mut().filter(|s| s.pose_inertia) {
                let inertia = joint_inertia(model, servo.joint, &poses, mass, DEFAULT_INERTIA_RADIUS_M);
                if inertia.is_finite() {
                    servo.control.set_inertia(inertia.max(1e-9));
                }
            }
        }
    }

    /// Closes every enabled servo drive's loops for one substep of `dt_s`
    /// that starts `elapsed_s` into the step, on the joint's measured
    /// position and velocity; a drive that is off or braked resets them.
    fn close_servo_loops(&mut self, elapsed_s: f64, dt_s: f64) {
        for i in 0..self.drives.len() {
            if self.drives[i].servo.is_none() {
                continue;
            }
            let (q, qd) = (self.joint_position(i), self.joint_velocity(i));
            let slot = &mut self.drives[i];
            let Some(servo) = slot.servo.as_mut() else { continue };
            if slot.free || slot.braked || !(q.is_finite() && qd.is_finite()) {
                servo.control.reset();
                continue;
            }
            let sp = Setpoint {
                position: slot.position + slot.velocity * elapsed_s,
                velocity: slot.velocity,
                acceleration: slot.acceleration,
            };
            servo.control.torque(sp, q, qd, dt_s);
        }
    }

    /// Places the posed links where they are `elapsed_s` into the step
    /// (their drives' setpoints advanced at their velocities; a posed joint
    /// without a drive at 0): as the next kinematic pose of their bodies,
    /// parents first, a simulated parent where it is now.
    fn pose_links(&mut self, elapsed_s: f64) {
        if self.posed.is_empty() {
            return;
        }
        let mut placed: Vec<(RigidBodyHandle, rapier3d_f64::math::Pose)> = Vec::with_capacity(self.posed.len());
        for &(j, drive) in &self.posed {
            let joint = &self.joints[j];
            let q = drive.map_or(0.0, |d| {
                let slot = &self.drives[d];
                slot.position + slot.velocity * elapsed_s
            });
            let frame = self.link_frames[joint.parent.0];
            let host = placed
                .iter()
                .find(|(body, _)| *body == frame.body)
                .map_or_else(|| *self.world.bodies[frame.body].position(), |(_, p)| *p);
            let parent = frame.body_from_link.map_or(host, |offset| host * offset);
            let pose = parent * pose_to_rapier(&(joint.parent_from_joint * joint.joint_from_child(q)));
            let child = self.link_frames[joint.child.0].body;
            placed.push((child, pose));
            self.world.bodies[child].set_next_kinematic_position(pose);
        }
    }

    /// Writes every drive's motor for `elapsed_s` into the step.
    ///
    /// * A spring drive: a spring to its setpoint moving at its velocity.
    /// * A servo drive that is enabled: its loops' torque, applied exactly
    ///   as a force-limited motor that asks for an unreachable velocity in
    ///   the torque's direction (the motor then always pushes with its full
    ///   limit, `|τ|`). rapier's multibody links take no user torques, and
    ///   the motor's impulse is the joint's own generalized force.
    /// * A servo drive that is braked: a stiff spring at the held position
    ///   whose torque is limited to the drive's (a brake slips beyond its
    ///   holding torque, which is sized like the motor's).
    /// * A free drive: no force at all (limit 0).
    fn apply_motor_targets(&mut self, elapsed_s: f64) {
        for slot in &self.drives {
            if let Some(handle) = slot.handle
                && let Some((multibody, link_id)) = self.world.multibody_joints.get_mut(handle)
                && let Some(link) = multibody.link_mut(link_id)
            {
                let data = &mut link.joint.data;
                let (model, target, speed, stiffness, damping, limit) = match (&slot.servo, slot.free, slot.braked) {
                    (_, true, _) => (MotorModel::AccelerationBased, slot.position, 0.0, 0.0, 0.0, 0.0),
                    (Some(servo), false, true) => (
                        MotorModel::AccelerationBased,
                        slot.position,
                        0.0,
                        slot.stiffness,
                        slot.damping,
                        servo.control.brake_torque(),
                    ),
                    (Some(servo), false, false) => {
                        let tau = servo.control.last_torque();
                        (
                            MotorModel::ForceBased,
                            0.0,
                            UNREACHABLE_SPEED.copysign(tau),
                            0.0,
                            UNREACHABLE_DAMPING,
                            tau.abs(),
                        )
                    }
                    (None, false, _) => (
                        MotorModel::AccelerationBased,
                        slot.position + slot.velocity * elapsed_s,
                        slot.velocity,
                        slot.stiffness,
                        slot.damping,
                        slot.max_force,
                    ),
                };
                data.set_motor_model(slot.axis, model);
                data.set_motor(slot.axis, target, speed, stiffness, damping);
                data.set_motor_max_force(slot.axis, limit);
            }
        }
    }

    /// Advances the world by one step of [`PhysicsOptions::step_s`]
    /// ([`PhysicsOptions::substeps`] rapier steps). A setpoint not renewed
    /// before the next step keeps moving at its velocity from where this
    /// step's target ended.
    pub fn step(&mut self) {
        let substep_s = self.step_s / self.substeps as f64;
        for k in 0..self.substeps {
            self.close_servo_loops(k as f64 * substep_s, substep_s);
            self.apply_motor_targets(k as f64 * substep_s);
            self.pose_links((k + 1) as f64 * substep_s);
            self.world.step();
        }
        for slot in &mut self.drives {
            slot.position += slot.velocity * self.step_s;
        }
        self.apply_motor_targets(0.0);
        self.steps += 1;
    }

    /// Sets the payloads the links carry: (link, mass properties in the
    /// link frame); a link left out carries none. A payload adds to its
    /// link's body (a link merged into an ancestor's body: to that body,
    /// at the link's offset), so the joints' motors carry it.
    pub fn set_payloads(&mut self, payloads: &[(usize, rapier3d_f64::prelude::MassProperties)]) {
        let mut total: Vec<(RigidBodyHandle, rapier3d_f64::prelude::MassProperties)> = Vec::new();
        for (link, mass) in payloads {
            let frame = &self.link_frames[*link];
            let on_body = frame.body_from_link.map_or(*mass, |offset| mass.transform_by(&offset));
            match total.iter_mut().find(|(b, _)| *b == frame.body) {
                Some((_, m)) => *m += on_body,
                None => total.push((frame.body, on_body)),
            }
        }
        for (body, _) in &total {
            if !self.unloaded.iter().any(|(b, _)| b == body) {
                let base = self.world.bodies[*body].mass_properties().local_mprops;
                self.unloaded.push((*body, base));
            }
        }
        for (body, base) in &self.unloaded {
            let extra = total.iter().find(|(b, _)| b == body).map(|(_, m)| *m);
            let props = extra.map_or(*base, |m| *base + m);
            self.world.bodies[*body].set_additional_mass_properties(props, true);
        }
    }

    /// Simulated time since construction, s (steps taken × `step_s`).
    pub fn time_s(&self) -> f64 {
        self.steps as f64 * self.step_s
    }

    /// The step length, s.
    pub fn step_s(&self) -> f64 {
        self.step_s
    }

    /// Actual position of drive `drive_index`'s joint, rad or m. Continuous
    /// joints are unwrapped: the angle keeps counting past ±π.
    ///
    /// # Panics
    /// If `drive_index >= drive_count()`.
    pub fn joint_position(&self, drive_index: usize) -> f64 {
        let slot = &self.drives[drive_index];
        let Some(handle) = slot.handle else {
            return slot.position;
        };
        self.world
            .multibody_joints
            .get(handle)
            .and_then(|(multibody, link_id)| multibody.link(link_id))
            .map_or(f64::NAN, |link| link.joint().coords()[slot.axis as usize])
    }

    /// Actual velocity of drive `drive_index`'s joint, rad/s or m/s.
    ///
    /// # Panics
    /// If `drive_index >= drive_count()`.
    pub fn joint_velocity(&self, drive_index: usize) -> f64 {
        let slot = &self.drives[drive_index];
        let Some(handle) = slot.handle else {
            return slot.velocity;
        };
        self.world
            .multibody_joints
            .get(handle)
            .and_then(|(multibody, link_id)| Some(multibody.joint_velocity(multibody.link(link_id)?)[0]))
            .unwrap_or(f64::NAN)
    }

    /// `world_from_link` of every link in [`RobotModel::links`] order:
    /// translation in metres and rotation as a unit quaternion `[x, y, z, w]`.
    pub fn world_from_link(&self) -> Vec<([f64; 3], [f64; 4])> {
        self.world_from_link_isometries()
            .iter()
            .map(isometry_to_arrays)
            .collect()
    }

    /// Same as [`RobotSim::world_from_link`], as nalgebra isometries.
    pub fn world_from_link_isometries(&self) -> Vec<Isometry3<f64>> {
        self.link_frames
            .iter()
            .map(|frame| {
                let body = *self.world.bodies[frame.body].position();
                pose_from_rapier(&frame.body_from_link.map_or(body, |offset| body * offset))
            })
            .collect()
    }
}

#[cfg(test)]
#[allow(clippy::unwrap_used)] // a failed unwrap is a failed test
mod tests {
    use super::*;
    use std::f64::consts::{FRAC_PI_2, PI};
    use std::path::Path;

    /// A pendulum-like single revolute joint about Y with an off-axis mass, so
    /// gravity loads it, plus a prismatic stage and a fixed tool, with joint
    /// origins that rotate and offset the frames.
    const ARM: &str = r#"<robot name="arm">
      <link name="base"><collision><geometry><box size="0.3 0.3 0.1"/></geometry></collision></link>
      <link name="upper">
        <inertial><origin xyz="0 0 0.25" rpy="0.1 0.2 0.3"/><mass value="2"/>
          <inertia ixx="0.045" ixy="0.001" ixz="0" iyy="0.04" iyz="0" izz="0.01"/></inertial>
        <collision><origin xyz="0 0 0.25"/><geometry><cylinder radius="0.04" length="0.5"/></geometry></collision>
      </link>
      <link name="slider">
        <inertial><mass value="0.5"/><inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.001"/></inertial>
        <collision><geometry><sphere radius="0.03"/></geometry></collision>
      </link>
      <link name="tool"/>
      <joint name="shoulder" type="revolute">
        <parent link="base"/><child link="upper"/>
        <origin xyz="0.05 0 0.1" rpy="0.3 0 0"/><axis xyz="0 1 0"/>
        <limit lower="-3" upper="3" effort="100" velocity="2"/>
      </joint>
      <joint name="slide" type="prismatic">
        <parent link="upper"/><child link="slider"/>
        <origin xyz="0 0 0.5" rpy="0 0 1.2"/><axis xyz="0.6 0 0.8"/>
        <limit lower="-0.5" upper="0.5" effort="100" velocity="0.5"/>
      </joint>
      <joint name="tool_mount" type="fixed">
        <parent link="slider"/><child link="tool"/><origin xyz="0.1 0 0" rpy="0 1.0 0"/>
      </joint>
    </robot>"#;

    fn arm() -> RobotModel {
        RobotModel::from_urdf_str(ARM, Path::new("arm.urdf")).unwrap()
    }

    fn drives(hz: f64) -> Vec<JointDrive> {
        vec![
            JointDrive::critically_damped("shoulder", hz),
            JointDrive::critically_damped("slide", hz),
        ]
    }

    fn hold(sim: &mut RobotSim, targets: &[f64], steps: usize) {
        for _ in 0..steps {
            for (d, &t) in targets.iter().enumerate() {
                sim.set_setpoint(d, t, 0.0);
            }
            sim.step();
        }
    }

    #[test]
    fn revolute_joint_settles_on_target() {
        let model = arm();
        let no_gravity = PhysicsOptions {
            gravity_mps2: [0.0; 3],
            ..PhysicsOptions::default()
        };
        let mut sim = RobotSim::new(&model, &drives(10.0), &[], no_gravity).unwrap();
        hold(&mut sim, &[0.8, 0.1], 1000);
        assert!(
            (sim.joint_position(0) - 0.8).abs() < 1e-4,
            "shoulder {}",
            sim.joint_position(0)
        );
        assert!(
            (sim.joint_position(1) - 0.1).abs() < 1e-4,
            "slide {}",
            sim.joint_position(1)
        );
        assert!(sim.joint_velocity(0).abs() < 1e-3);
        assert!((sim.time_s() - 2.0).abs() < 1e-9);

        // With gravity the proportional drive droops by about (gravity
        // angular acceleration) / stiffness: a few mrad at 10 Hz, less at 30 Hz.
        let mut sim = RobotSim::new(&model, &drives(10.0), &[], PhysicsOptions::default()).unwrap();
        hold(&mut sim, &[0.8, 0.1], 1000);
        let droop_10hz = (sim.joint_position(0) - 0.8).abs();
        let mut sim = RobotSim::new(&model, &drives(30.0), &[], PhysicsOptions::default()).unwrap();
        hold(&mut sim, &[0.8, 0.1], 1000);
        let droop_30hz = (sim.joint_position(0) - 0.8).abs();
        assert!(
            droop_10hz < 1e-2 && droop_30hz < droop_10hz / 5.0,
            "{droop_10hz} {droop_30hz}"
        );
    }

    #[test]
    fn trajectory_with_velocity_feed_forward_is_tracked() {
        let model = arm();
        let mut sim = RobotSim::new(&model, &drives(20.0), &[], PhysicsOptions::default()).unwrap();
        // θ(t) = A·(1 − cos ωt): starts at rest, peak acceleration A·ω² ≈ 24 rad/s²,
        // on top of up to ~20 rad/s² of gravity load.
        let (amplitude, omega) = (0.6, std::f64::consts::TAU);
        let theta = |t: f64| amplitude * (1.0 - (omega * t).cos());
        let mut max_error: f64 = 0.0;
        for _ in 0..1000 {
            let (t, t_mid) = (sim.time_s(), sim.time_s() + sim.step_s() / 2.0);
            sim.set_setpoint(0, theta(t), amplitude * omega * (omega * t_mid).sin());
            sim.set_setpoint(1, 0.0, 0.0);
            sim.step();
            max_error = max_error.max((sim.joint_position(0) - theta(sim.time_s())).abs());
        }
        assert!(max_error < 5e-3, "max tracking error {max_error} rad");
    }

    /// A posed joint's links are placed, not simulated: the slider sits
    /// exactly where the simulated shoulder and the slide's setpoint put
    /// it, and the multibody keeps only the shoulder's degree of freedom.
    #[test]
    fn posed_links_follow_their_parent_and_setpoint_outside_the_multibody() {
        let model = arm();
        let options = PhysicsOptions {
            posed_joints: vec!["slide".to_string()],
            ..PhysicsOptions::default()
        };
        let mut sim = RobotSim::new(&model, &drives(10.0), &[], options).unwrap();
        for k in 0..200 {
            let slide = 0.3 * (k as f64 / 200.0);
            sim.set_setpoint(0, 0.4, 0.0);
            sim.set_setpoint(1, slide, 0.0);
            sim.step();
        }
        assert_eq!(sim.joint_position(1), 0.3 * 199.0 / 200.0);
        let handle = sim.drives[0].handle.expect("the shoulder is simulated");
        let (multibody, _) = sim.world.multibody_joints.get(handle).expect("multibody");
        assert_eq!(multibody.ndofs(), 1);
        assert!(sim.drives[1].handle.is_none());
        // The slider and the tool below it: the URDF's kinematics of the
        // shoulder's simulated angle and the slide's setpoint.
        let shoulder = model.joint_by_name("shoulder").unwrap();
        let slide = model.joint_by_name("slide").unwrap();
        let mut q = vec![0.0; model.joints.len()];
        q[shoulder.0] = sim.joint_position(0);
        q[slide.0] = sim.joint_position(1);
        let expected = model.world_from_link(&q);
        let got = sim.world_from_link_isometries();
        for link in ["slider", "tool"] {
            let l = model.link_by_name(link).unwrap().0;
            let d = (got[l].translation.vector - expected[l].translation.vector).norm();
            // The parent's pose is the one at the start of the last substep.
            assert!(d < 1e-3, "{link}: {d} m");
        }
        assert!(matches!(
            RobotSim::new(
                &model,
                &[],
                &[],
                PhysicsOptions {
                    posed_joints: vec!["tool_mount".to_string()],
                    ..PhysicsOptions::default()
                }
            ),
            Err(PhysicsError::FixedJoint { .. })
        ));
    }

    #[test]
    fn initial_configuration_is_honoured() {
        let model = arm();
        let q0 = [("shoulder".to_string(), -0.7), ("slide".to_string(), 0.2)];
        let mut sim = RobotSim::new(&model, &drives(10.0), &q0, PhysicsOptions::default()).unwrap();
        assert_eq!(sim.joint_position(0), -0.7);
        assert_eq!(sim.joint_position(1), 0.2);
        // Setpoints start at the initial positions: the robot holds there.
        for _ in 0..200 {
            sim.step();
        }
        assert!((sim.joint_position(0) + 0.7).abs() < 5e-3, "{}", sim.joint_position(0));
        assert!((sim.joint_position(1) - 0.2).abs() < 5e-3, "{}", sim.joint_position(1));
    }

    #[test]
    fn unknown_and_fixed_joint_names_are_errors() {
        let model = arm();
        let err = RobotSim::new(
            &model,
            &[JointDrive::critically_damped("elbow", 5.0)],
            &[],
            PhysicsOptions::default(),
        )
        .unwrap_err();
        assert!(matches!(err, PhysicsError::UnknownJoint { joint } if joint == "elbow"));
        let err = RobotSim::new(&model, &[], &[("wrist".to_string(), 1.0)], PhysicsOptions::default()).unwrap_err();
        assert!(matches!(err, PhysicsError::UnknownJoint { joint } if joint == "wrist"));
        let err = RobotSim::new(
            &model,
            &[JointDrive::critically_damped("tool_mount", 5.0)],
            &[],
            PhysicsOptions::default(),
        )
        .unwrap_err();
        assert!(matches!(err, PhysicsError::FixedJoint { .. }));
        let twice = [
            JointDrive::critically_damped("slide", 5.0),
            JointDrive::critically_damped("slide", 6.0),
        ];
        assert!(matches!(
            RobotSim::new(&model, &twice, &[], PhysicsOptions::default()),
            Err(PhysicsError::DuplicateDrive { .. })
        ));
        let options = PhysicsOptions {
            step_s: 0.0,
            ..PhysicsOptions::default()
        };
        assert!(matches!(
            RobotSim::new(&model, &[], &[], options),
            Err(PhysicsError::InvalidOption { option: "step_s" })
        ));
    }

    #[test]
    fn model_forward_kinematics_matches_rapier_link_poses() {
        let model = arm();
        for (shoulder, slide) in [(0.0, 0.0), (0.9, -0.3), (-2.5, 0.45), (FRAC_PI_2, 0.1)] {
            let q0 = [("shoulder".to_string(), shoulder), ("slide".to_string(), slide)];
            let mut sim = RobotSim::new(&model, &drives(10.0), &q0, PhysicsOptions::default()).unwrap();
            // At construction and again after motion, at the actual joint positions.
            for round in 0..2 {
                let q = [sim.joint_position(0), sim.joint_position(1), 0.0];
                let expected = model.world_from_link(&q);
                let actual = sim.world_from_link_isometries();
                for (l, (e, a)) in expected.iter().zip(&actual).enumerate() {
                    let dist = (e.translation.vector - a.translation.vector).norm();
                    let angle = e.rotation.angle_to(&a.rotation);
                    assert!(
                        dist < 1e-6 && angle < 1e-6,
                        "q={q:?} round {round} link {l}: {dist} m, {angle} rad"
                    );
                }
                hold(&mut sim, &[shoulder + 0.3, slide * 0.5], 50);
            }
        }
    }

    #[test]
    fn identical_inputs_give_bit_identical_runs() {
        let model = arm();
        let run = || {
            let mut sim = RobotSim::new(
                &model,
                &drives(15.0),
                &[("shoulder".to_string(), 0.2)],
                PhysicsOptions::default(),
            )
            .unwrap();
            let mut trace = Vec::new();
            for k in 0..300 {
                let t = k as f64 * 0.002;
                sim.set_setpoint(0, 0.2 + (3.0 * t).sin(), 3.0 * (3.0 * t).cos());
                sim.set_setpoint(1, 0.3 * t, 0.3);
                sim.step();
                trace.push((sim.joint_position(0).to_bits(), sim.joint_position(1).to_bits()));
            }
            let poses: Vec<u64> = sim
                .world_from_link()
                .iter()
                .flat_map(|(t, q)| t.iter().chain(q).map(|x| x.to_bits()).collect::<Vec<_>>())
                .collect();
            (trace, poses)
        };
        assert_eq!(run(), run());
    }

    #[test]
    fn continuous_joint_is_unwrapped_past_pi() {
        let xml = r#"<robot name="spin"><link name="base"/>
          <link name="disc"><inertial><mass value="1"/>
            <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.02"/></inertial></link>
          <joint name="spin" type="continuous"><parent link="base"/><child link="disc"/><axis xyz="0 0 1"/></joint>
        </robot>"#;
        let model = RobotModel::from_urdf_str(xml, Path::new("spin.urdf")).unwrap();
        let q0 = [("spin".to_string(), 3.0)];
        let mut sim = RobotSim::new(
            &model,
            &[JointDrive::critically_damped("spin", 10.0)],
            &q0,
            PhysicsOptions::default(),
        )
        .unwrap();
        let mut previous = sim.joint_position(0);
        for k in 1..=1000 {
            let t = k as f64 * 0.002;
            sim.set_setpoint(0, 3.0 + PI * t, PI);
            sim.step();
            let now = sim.joint_position(0);
            assert!((now - previous).abs() < 0.05, "jump from {previous} to {now}");
            previous = now;
        }
        assert!((previous - (3.0 + 2.0 * PI)).abs() < 0.01, "{previous}");
    }

    /// Guards the merging of fixed links: a pendulum carrying a weight and
    /// a tip on a chain of fixed joints (turned, with anisotropic inertia)
    /// swings exactly as the same pendulum with those masses lumped into
    /// its own `<inertial>` by hand, and the merged links stand where the
    /// model's forward kinematics puts them.
    #[test]
    fn links_on_fixed_joints_swing_as_their_lumped_mass() {
        use nalgebra::{Matrix3, Rotation3};
        let inertial = |xyz: [f64; 3], m: f64, i: Matrix3<f64>| {
            format!(
                r#"<inertial><origin xyz="{} {} {}"/><mass value="{m}"/><inertia ixx="{}" ixy="{}" ixz="{}" iyy="{}" iyz="{}" izz="{}"/></inertial>"#,
                xyz[0],
                xyz[1],
                xyz[2],
                i[(0, 0)],
                i[(0, 1)],
                i[(0, 2)],
                i[(1, 1)],
                i[(1, 2)],
                i[(2, 2)]
            )
        };
        let pendulum = |arm: String, fixed: &str| {
            let xml = format!(
                r#"<robot name="p"><link name="base"/><link name="arm">{arm}</link>{fixed}
                <joint name="swing" type="continuous"><parent link="base"/><child link="arm"/><axis xyz="0 1 0"/></joint>
                </robot>"#
            );
            RobotModel::from_urdf_str(&xml, Path::new("p.urdf")).unwrap()
        };
        // The arm's own mass, the weight (0.5 m out, turned 0.7 rad about
        // z) and the tip (0.05 m further along the weight's x).
        let (m_arm, c_arm, i_arm) = (1.0, Vector3::new(0.25, 0.0, 0.0), Matrix3::from_diagonal_element(0.01));
        let (m_weight, i_weight) = (2.0, Matrix3::from_diagonal(&Vector3::new(0.02, 0.03, 0.04)));
        let (m_tip, c_tip_in_weight, i_tip) = (
            0.5,
            Vector3::new(0.1, 0.0, 0.0),
            Matrix3::from_diagonal(&Vector3::new(0.001, 0.002, 0.003)),
        );
        let turn = Rotation3::from_euler_angles(0.0, 0.0, 0.7);
        let weight_origin = Vector3::new(0.5, 0.0, 0.0);
        let tip_origin = weight_origin + turn * Vector3::new(0.05, 0.0, 0.0);
        let merged = pendulum(
            inertial(c_arm.into(), m_arm, i_arm),
            &format!(
                r#"<link name="weight">{}</link><link name="tip">{}</link>
                <joint name="mount" type="fixed"><parent link="arm"/><child link="weight"/><origin xyz="0.5 0 0" rpy="0 0 0.7"/></joint>
                <joint name="tip_mount" type="fixed"><parent link="weight"/><child link="tip"/><origin xyz="0.05 0 0"/></joint>"#,
                inertial([0.0; 3], m_weight, i_weight),
                inertial(c_tip_in_weight.into(), m_tip, i_tip),
            ),
        );
        // Lumped by hand: parallel axes about the common centre of mass.
        let parts = [
            (m_arm, c_arm, i_arm),
            (m_weight, weight_origin, turn * i_weight * turn.transpose()),
            (
                m_tip,
                tip_origin + turn * c_tip_in_weight,
                turn * i_tip * turn.transpose(),
            ),
        ];
        let mass: f64 = parts.iter().map(|p| p.0).sum();
        let com = parts.iter().map(|p| p.1 * p.0).sum::<Vector3<f64>>() / mass;
        let inertia = parts.iter().fold(Matrix3::zeros(), |acc, (m, c, i)| {
            let r = c - com;
            acc + i + (Matrix3::identity() * r.norm_squared() - r * r.transpose()) * *m
        });
        let lumped = pendulum(inertial(com.into(), mass, inertia), "");
        let swing = |model: &RobotModel| {
            let drive = [JointDrive::critically_damped("swing", 10.0)];
            let mut sim =
                RobotSim::new(model, &drive, &[("swing".to_string(), 0.3)], PhysicsOptions::default()).unwrap();
            sim.set_drive_free(0, true);
            let mut angles = Vec::new();
            for _ in 0..300 {
                sim.step();
                let q = sim.joint_position(0);
                angles.push(q);
                let expected = model.world_from_link(
                    &model
                        .joints
                        .iter()
                        .map(|j| if j.kind.is_movable() { q } else { 0.0 })
                        .collect::<Vec<_>>(),
                );
                for (e, a) in expected.iter().zip(sim.world_from_link_isometries()) {
                    assert!((e.translation.vector - a.translation.vector).norm() < 1e-9);
                    assert!(e.rotation.angle_to(&a.rotation) < 1e-9);
                }
            }
            angles
        };
        let (a, b) = (swing(&merged), swing(&lumped));
        assert!(
            (a[0] - 0.3).abs() > 1e-6 && (a[299] - 0.3).abs() > 0.05,
            "it swings: {} {}",
            a[0],
            a[299]
        );
        for (k, (x, y)) in a.iter().zip(&b).enumerate() {
            assert!((x - y).abs() < 1e-9, "step {k}: merged {x}, lumped {y}");
        }
    }

    #[test]
    fn undriven_pendulum_falls_under_gravity() {
        let model = arm();
        let mut sim = RobotSim::new(
            &model,
            &[JointDrive::critically_damped("slide", 10.0)],
            &[("shoulder".to_string(), 0.3)],
            PhysicsOptions::default(),
        )
        .unwrap();
        let before = sim.world_from_link()[1];
        for _ in 0..100 {
            sim.step();
        }
        let after = sim.world_from_link()[1];
        assert_ne!(before.1, after.1, "the free shoulder should swing");
    }

    fn indexing_table() -> RobotModel {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/robots/indexing_table/indexing_table.urdf");
        RobotModel::load(&path).unwrap()
    }

    /// Cycloidal 90° index in `duration_s`: zero velocity and acceleration at
    /// both ends, peak acceleration 2π·Θ/T².
    fn index_move(t: f64, duration_s: f64) -> (f64, f64) {
        let theta = FRAC_PI_2;
        let tau = (t / duration_s).clamp(0.0, 1.0);
        let angle = std::f64::consts::TAU * tau;
        (
            theta * (tau - angle.sin() / std::f64::consts::TAU),
            theta / duration_s * (1.0 - angle.cos()),
        )
    }

    fn index_tracking_error(drive: JointDrive) -> (f64, f64) {
        let model = indexing_table();
        let mut sim = RobotSim::new(&model, &[drive], &[], PhysicsOptions::default()).unwrap();
        let mut max_error: f64 = 0.0;
        for _ in 0..500 {
            let position = index_move(sim.time_s(), 0.5).0;
            let velocity = index_move(sim.time_s() + sim.step_s() / 2.0, 0.5).1;
            sim.set_setpoint(0, position, velocity);
            sim.step();
            max_error = max_error.max((sim.joint_position(0) - index_move(sim.time_s(), 0.5).0).abs());
        }
        (max_error, (sim.joint_position(0) - FRAC_PI_2).abs())
    }

    #[test]
    fn indexing_table_tracks_a_quarter_turn_in_half_a_second() {
        let drive = JointDrive {
            max_force: Some(300.0),
            ..JointDrive::critically_damped("platter_joint", 30.0)
        };
        let (max_error, final_error) = index_tracking_error(drive);
        assert!(max_error < 2e-3, "max tracking error {max_error} rad");
        assert!(final_error < 1e-4, "final error {final_error} rad");
        // The V-block (0°) ends where the clamp (90°) started.
        let model = indexing_table();
        let q0 = [("platter_joint".to_string(), FRAC_PI_2)];
        let sim = RobotSim::new(&model, &[], &q0, PhysicsOptions::default()).unwrap();
        let vblock = model.link_by_name("fixture_vblock").unwrap().0;
        let clamp = model.link_by_name("fixture_clamp").unwrap().0;
        let start = RobotSim::new(&model, &[], &[], PhysicsOptions::default()).unwrap();
        let (after, before) = (sim.world_from_link()[vblock].0, start.world_from_link()[clamp].0);
        assert!(
            after.iter().zip(before).all(|(a, b)| (a - b).abs() < 1e-9),
            "{after:?} {before:?}"
        );
    }
}
