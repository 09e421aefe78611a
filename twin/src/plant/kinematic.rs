//! The kinematic plant (`plant = "kinematic"` in the scene, or `twin run
//! --plant kinematic`): for program tests that need the machine's geometry
//! but not its dynamics. It is what a Logix user knows as a CIP axis in
//! the test mode *Controller Loop Back*, and how a virtual axis behaves:
//! the feedback is the command.
//!
//! * Every driven joint is at its drive's setpoint at the end of each
//!   physics step, so an axis' actual position is its command position at
//!   every coarse update (to the rounding of the unit conversion): no
//!   following error, no settling, no torque.
//! * A drive that is off (servo off, a fault that disabled it) leaves its
//!   joint where it is, brake or not: there is no gravity to make it fall.
//!   Joints without a drive stay at their initial positions.
//! * A parallel robot's virtual joints follow the MCT kinematics, as in
//!   the physics plant.
//! * Link poses are the URDF's forward kinematics; the live collision
//!   checks, the pre-flight sweep, frames, trails and the recording use
//!   them as they use the physics' poses. Nothing is solved: contacts do
//!   not push the robot (the collision checks still report them).
//!
//! What differs from the physics plant, so from a machine: moves complete
//! as soon as their setpoints do (`Done`/`.PC` of a move that waits for
//! the actual position comes at its last setpoint), an Excessive Position
//! Error cannot happen, and a servo-off axis never moves (MSO's ERR 22,
//! Axis In Motion, does not arise).

use nalgebra::Isometry3;

use super::convert::isometry_to_arrays;
use super::physics::{JointDrive, PhysicsError, driven_joints, initial_positions};
use super::urdf::RobotModel;

/// One drive of the kinematic plant.
#[derive(Debug, Clone, Copy)]
struct Drive {
    /// Its URDF joint.
    joint: usize,
    /// Where its joint is at the end of the next step.
    setpoint: f64,
    /// Off: the joint stays where it is.
    free: bool,
    braked: bool,
}

/// A URDF robot whose driven joints are at their setpoints: the
/// kinematic counterpart of [`super::physics::RobotSim`], addressed the
/// same way (drive `i` is the `i`-th of the drives it was built with).
#[derive(Debug, Clone)]
pub struct KinematicSim {
    /// Per URDF joint, its position (rad or m).
    q: Vec<f64>,
    drives: Vec<Drive>,
    step_s: f64,
    steps: u64,
    /// Per link, its world pose after the last step.
    world_from_link: Vec<Isometry3<f64>>,
}

impl KinematicSim {
    /// The robot at `initial_joint_positions` (rad or m; unnamed joints at
    /// 0), each drive's setpoint at its joint's initial position.
    ///
    /// # Errors
    /// As [`super::physics::RobotSim::new`] for the joints and drives
    /// (unknown or fixed joint, a joint driven twice, invalid gains, a
    /// non-finite initial position), and [`PhysicsError::InvalidOption`]
    /// for a step that is not positive and finite.
    pub fn new(
        model: &RobotModel,
        drives: &[JointDrive],
        initial_joint_positions: &[(String, f64)],
        step_s: f64,
    ) -> Result<KinematicSim, PhysicsError> {
        if !(step_s.is_finite() && step_s > 0.0) {
            return Err(PhysicsError::InvalidOption { option: "step_s" });
        }
        let q = initial_positions(model, initial_joint_positions)?;
        let driven = driven_joints(model, drives)?;
        let mut slots = vec![
            Drive {
                joint: 0,
                setpoint: 0.0,
                free: false,
                braked: false,
            };
            drives.len()
        ];
        for (joint, drive) in driven.iter().enumerate() {
            if let Some(d) = *drive {
                slots[d].joint = joint;
                slots[d].setpoint = q[joint];
            }
        }
        let world_from_link = model.world_from_link(&q);
        Ok(KinematicSim {
            q,
            drives: slots,
            step_s,
            steps: 0,
            world_from_link,
        })
    }

    /// Sets where drive `drive_index`'s joint is at the end of the next
    /// [`KinematicSim::step`] (rad or m).
    ///
    /// # Panics
    /// If `drive_index` is not a drive's.
    pub fn set_setpoint(&mut self, drive_index: usize, position: f64) {
        self.drives[drive_index].setpoint = position;
    }

    /// Turns drive `drive_index` off (`free`: its joint stays where it is)
    /// or on again.
    ///
    /// # Panics
    /// If `drive_index` is not a drive's.
    pub fn set_drive_free(&mut self, drive_index: usize, free: bool) {
        self.drives[drive_index].free = free;
    }

    /// Engages or releases drive `drive_index`'s holding brake: engaged,
    /// its joint stays where it is.
    ///
    /// # Panics
    /// If `drive_index` is not a drive's.
    pub fn set_drive_braked(&mut self, drive_index: usize, braked: bool) {
        self.drives[drive_index].braked = braked;
    }

    /// `steps` steps at once: every drive that is on puts its joint at its
    /// setpoint; the link poses follow (forward kinematics, once).
    pub fn step(&mut self, model: &RobotModel, steps: u64) {
        for d in &self.drives {
            if !d.free && !d.braked {
                self.q[d.joint] = d.setpoint;
            }
        }
        self.world_from_link = model.world_from_link(&self.q);
        self.steps += steps;
    }

    /// Simulated time since construction, s.
    pub fn time_s(&self) -> f64 {
        self.steps as f64 * self.step_s
    }

    /// Position of drive `drive_index`'s joint, rad or m.
    ///
    /// # Panics
    /// If `drive_index` is not a drive's.
    pub fn joint_position(&self, drive_index: usize) -> f64 {
        self.q[self.drives[drive_index].joint]
    }

    /// Every link's world pose (translation m, quaternion xyzw), in model
    /// link order.
    pub fn world_from_link(&self) -> Vec<([f64; 3], [f64; 4])> {
        self.world_from_link.iter().map(isometry_to_arrays).collect()
    }

    /// Same as [`KinematicSim::world_from_link`], as isometries.
    pub fn world_from_link_isometries(&self) -> Vec<Isometry3<f64>> {
        self.world_from_link.clone()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plant::physics::JointDrive;
    use std::path::Path;

    fn scara() -> RobotModel {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/robots/scara/scara.urdf");
        RobotModel::load(&path).expect("scara")
    }

    #[test]
    fn driven_joints_are_at_their_setpoints_and_off_drives_stay() {
        let model = scara();
        let drives = [
            JointDrive::critically_damped("j1", 30.0),
            JointDrive::critically_damped("j3", 60.0),
        ];
        let mut sim = KinematicSim::new(&model, &drives, &[("j1".into(), 0.5)], 0.001).expect("sim");
        assert_eq!(sim.joint_position(0), 0.5);
        sim.set_setpoint(0, 0.7);
        sim.set_setpoint(1, -0.1);
        sim.set_drive_free(1, true);
        sim.step(&model, 1);
        assert_eq!((sim.joint_position(0), sim.joint_position(1)), (0.7, 0.0));
        sim.set_drive_free(1, false);
        sim.set_drive_braked(0, true);
        sim.set_setpoint(0, 0.9);
        sim.step(&model, 1);
        assert_eq!((sim.joint_position(0), sim.joint_position(1)), (0.7, -0.1));
        assert!((sim.time_s() - 0.002).abs() < 1e-15);
        // The poses are the URDF's forward kinematics of the joints.
        let j1 = model.joint_by_name("j1").expect("j1");
        let j3 = model.joint_by_name("j3").expect("j3");
        let mut q = vec![0.0; model.joints.len()];
        q[j1.0] = 0.7;
        q[j3.0] = -0.1;
        assert_eq!(sim.world_from_link_isometries(), model.world_from_link(&q));
    }

    #[test]
    fn a_joint_driven_twice_or_a_bad_step_is_refused() {
        let model = scara();
        let twice = [
            JointDrive::critically_damped("j1", 30.0),
            JointDrive::critically_damped("j1", 30.0),
        ];
        assert!(matches!(
            KinematicSim::new(&model, &twice, &[], 0.001),
            Err(PhysicsError::DuplicateDrive { .. })
        ));
        assert!(matches!(
            KinematicSim::new(&model, &[], &[], 0.0),
            Err(PhysicsError::InvalidOption { .. })
        ));
    }
}
