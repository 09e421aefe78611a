//! What moves the joints: the rapier multibody ([`RobotSim`]) or the
//! kinematic plant ([`KinematicSim`]), behind one set of calls so that the
//! plant's update, its collision checks and the parallel robots' virtual
//! joints do not care which.

use nalgebra::Isometry3;

use super::kinematic::KinematicSim;
use super::physics::RobotSim;
use super::urdf::RobotModel;

/// The plant's joints, simulated one of two ways (scene `plant`).
#[allow(clippy::large_enum_variant)]
pub(crate) enum Dynamics {
    /// Rigid-body dynamics.
    Physics(RobotSim),
    /// The joints at their setpoints.
    Kinematic(KinematicSim),
}

impl Dynamics {
    /// Whether this is the kinematic plant.
    pub(crate) fn is_kinematic(&self) -> bool {
        matches!(self, Self::Kinematic(_))
    }

    /// Drive `drive`'s setpoint: `position` at the start of the step and
    /// the feed-forward `velocity` (physics); where the joint is at the end
    /// of the step (kinematic, which ignores `velocity`). The plant gives
    /// each what it needs ([`super::Plant::advance`]).
    pub(crate) fn set_setpoint(&mut self, drive: usize, position: f64, velocity: f64) {
        match self {
            Self::Physics(sim) => sim.set_setpoint(drive, position, velocity),
            Self::Kinematic(sim) => sim.set_setpoint(drive, position),
        }
    }

    /// A servo drive's feed-forward acceleration (physics only).
    pub(crate) fn set_setpoint_acceleration(&mut self, drive: usize, acceleration: f64) {
        if let Self::Physics(sim) = self {
            sim.set_setpoint_acceleration(drive, acceleration);
        }
    }

    pub(crate) fn set_drive_free(&mut self, drive: usize, free: bool) {
        match self {
            Self::Physics(sim) => sim.set_drive_free(drive, free),
            Self::Kinematic(sim) => sim.set_drive_free(drive, free),
        }
    }

    pub(crate) fn set_drive_braked(&mut self, drive: usize, braked: bool) {
        match self {
            Self::Physics(sim) => sim.set_drive_braked(drive, braked),
            Self::Kinematic(sim) => sim.set_drive_braked(drive, braked),
        }
    }

    /// A servo drive's new gains and limits (physics only: the kinematic
    /// plant has no loops).
    pub(crate) fn set_servo_gains(&mut self, drive: usize, gains: crate::scene::ServoGains) {
        if let Self::Physics(sim) = self {
            sim.set_servo_gains(drive, gains);
        }
    }

    /// The servo drives' inertias for the current pose (physics only).
    pub(crate) fn refresh_servo_inertias(&mut self, model: &RobotModel) {
        if let Self::Physics(sim) = self {
            sim.refresh_servo_inertias(model);
        }
    }

    /// `steps` physics steps with the setpoints as they are.
    pub(crate) fn step(&mut self, model: &RobotModel, steps: usize) {
        match self {
            Self::Physics(sim) => {
                for _ in 0..steps {
                    sim.step();
                }
            }
            Self::Kinematic(sim) => sim.step(model, steps as u64),
        }
    }

    pub(crate) fn time_s(&self) -> f64 {
        match self {
            Self::Physics(sim) => sim.time_s(),
            Self::Kinematic(sim) => sim.time_s(),
        }
    }

    pub(crate) fn joint_position(&self, drive: usize) -> f64 {
        match self {
            Self::Physics(sim) => sim.joint_position(drive),
            Self::Kinematic(sim) => sim.joint_position(drive),
        }
    }

    /// A joint's actual velocity, rad/s or m/s; `None` in the kinematic
    /// plant (a joint there is where its command is).
    pub(crate) fn joint_velocity(&self, drive: usize) -> Option<f64> {
        match self {
            Self::Physics(sim) => Some(sim.joint_velocity(drive)),
            Self::Kinematic(_) => None,
        }
    }

    /// A servo drive's torque in the last substep; `None` for a spring
    /// drive and in the kinematic plant (nothing is solved).
    pub(crate) fn drive_torque(&self, drive: usize) -> Option<f64> {
        match self {
            Self::Physics(sim) => sim.drive_torque(drive),
            Self::Kinematic(_) => None,
        }
    }

    /// As [`Dynamics::drive_torque`], the largest so far.
    pub(crate) fn drive_peak_torque(&self, drive: usize) -> Option<f64> {
        match self {
            Self::Physics(sim) => sim.drive_peak_torque(drive),
            Self::Kinematic(_) => None,
        }
    }

    /// The held parts' mass properties on their links (physics plant; the
    /// kinematic plant has no dynamics to carry them).
    pub(crate) fn set_payloads(&mut self, payloads: &[(usize, rapier3d_f64::prelude::MassProperties)]) {
        if let Dynamics::Physics(sim) = self {
            sim.set_payloads(payloads);
        }
    }

    pub(crate) fn world_from_link(&self) -> Vec<([f64; 3], [f64; 4])> {
        match self {
            Self::Physics(sim) => sim.world_from_link(),
            Self::Kinematic(sim) => sim.world_from_link(),
        }
    }

    pub(crate) fn world_from_link_isometries(&self) -> Vec<Isometry3<f64>> {
        match self {
            Self::Physics(sim) => sim.world_from_link_isometries(),
            Self::Kinematic(sim) => sim.world_from_link_isometries(),
        }
    }
}
