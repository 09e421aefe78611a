//! The scene's axes bound to the planner and to the robot's joints: the one
//! place where axis units, MRP position offsets and joint SI units meet.
//!
//! An axis position in the planner is in axis units (`deg`, `mm`, …) and
//! includes the offset an MRP redefined; the joint it drives is in rad or m
//! and knows nothing of MRP. [`AxisJoint::joint_position`] (and
//! [`AxisBinding::drive_command`]) and [`AxisBinding::axis_position`]
//! convert between the two, both ways here: the planner takes and gives
//! only axis positions, and nothing else in the twin applies an MRP offset.
//! The unit factor itself is [`crate::scene::Units::si_per_unit`].

use super::error::PlantError;
use super::limits;
use super::physics::JointDrive;
use super::servo_drive::ServoGains;
use super::urdf::RobotModel;
use crate::scene::{Axis, Scene};
use planner::task::{AxisHandle, MotionTask};

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
    /// URDF joint index of the driven joint; `None` for a virtual axis.
    pub joint: Option<usize>,
    /// SI units (rad or m) per axis unit.
    pub si_per_unit: f64,
    /// In-position window, axis units.
    pub in_position_window: f64,
    /// The joint has a holding brake (see [`crate::scene::Axis::holding_brake`]).
    pub holding_brake: bool,
}

/// How an axis position becomes its joint's position right now.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxisJoint {
    /// URDF joint index.
    pub joint: usize,
    /// SI units per axis unit.
    pub si_per_unit: f64,
    /// The MRP position offset of the axis, axis units.
    pub offset: f64,
}

impl AxisJoint {
    /// The joint position (rad or m) of an axis position (axis units).
    pub fn joint_position(&self, axis_position: f64) -> f64 {
        (axis_position - self.offset) * self.si_per_unit
    }
}

impl AxisBinding {
    /// The joint mapping of a driven axis now (`None` for a virtual axis).
    pub fn axis_joint(&self, task: &MotionTask) -> Option<AxisJoint> {
        Some(AxisJoint {
            joint: self.joint?,
            si_per_unit: self.si_per_unit,
            offset: task.position_offset(self.handle),
        })
    }

    /// The command position and velocity in the joint's frame (MRP offset
    /// removed), axis units: what the drive interpolates between updates.
    pub fn drive_command(&self, task: &MotionTask) -> (f64, f64) {
        let s = task.axis_state(self.handle);
        (
            s.command_position - task.position_offset(self.handle),
            s.command_velocity,
        )
    }

    /// An axis-unit quantity in the joint's frame as SI (rad, m, rad/s …).
    pub fn to_si(&self, x: f64) -> f64 {
        x * self.si_per_unit
    }

    /// The axis position (axis units, MRP redefinitions included) of a
    /// joint position (rad or m): what the planner is fed.
    pub fn axis_position(&self, task: &MotionTask, joint_position: f64) -> f64 {
        joint_position / self.si_per_unit + task.position_offset(self.handle)
    }
}

/// The scene's axes added to the planner, with the joint drives they need
/// and the joints' initial positions (`initial`, URDF units).
pub(crate) struct BoundAxes {
    pub axes: Vec<AxisBinding>,
    pub drives: Vec<JointDrive>,
}

/// Adds every scene axis to the planner and binds it to its joint.
///
/// # Errors
/// [`PlantError::Joint`] naming the axis' `joint` field when the joint is
/// missing or fixed or the initial position is outside its limits;
/// [`PlantError::Planner`] when the planner refuses the axis.
pub(crate) fn bind_axes(
    scene: &Scene,
    model: &RobotModel,
    task: &mut MotionTask,
    initial: &mut Vec<(String, f64)>,
) -> Result<BoundAxes, PlantError> {
    let mut bound = BoundAxes {
        axes: Vec::new(),
        drives: Vec::new(),
    };
    for (index, axis) in scene.axes.iter().enumerate() {
        let joint_error = |message: String| PlantError::Joint {
            scene: scene.path.clone(),
            index,
            line: axis.joint_location.line,
            column: axis.joint_location.column,
            message,
        };
        let config = limits::with_urdf_limits(axis, model).map_err(joint_error)?;
        let handle = task
            .add_axis(config, axis.initial_position)
            .map_err(|source| PlantError::Planner {
                scene: scene.path.clone(),
                source,
            })?;
        let mut binding = AxisBinding {
            name: axis.name.clone(),
            handle,
            drive: None,
            joint: None,
            si_per_unit: axis.units.si_per_unit(),
            in_position_window: axis.config.in_position_window,
            holding_brake: axis.holding_brake,
        };
        // A virtual axis has no joint and is never fed (actual = command).
        if let Some(joint) = &axis.joint {
            let index = driven_joint(scene, model, axis, joint).map_err(joint_error)?;
            initial.retain(|(name, _)| name != joint);
            initial.push((joint.clone(), binding.to_si(axis.initial_position)));
            bound.drives.push(match axis.servo {
                Some(gains) => JointDrive::servo(joint, with_effort_limits(gains, model, index)),
                None => JointDrive {
                    joint: joint.clone(),
                    stiffness: axis.motor.stiffness,
                    damping: axis.motor.damping,
                    max_force: None,
                    servo: None,
                },
            });
            binding.drive = Some(bound.drives.len() - 1);
            binding.joint = Some(index);
        }
        bound.axes.push(binding);
    }
    Ok(bound)
}

/// A servo drive's torque limits where the scene leaves them out: the URDF
/// joint's `effort` (±), none when that is 0 or absent.
fn with_effort_limits(gains: ServoGains, model: &RobotModel, joint: usize) -> ServoGains {
    let effort = model.joints[joint]
        .limits
        .map(|l| l.effort)
        .filter(|e| e.is_finite() && *e > 0.0);
    ServoGains {
        torque_limit_positive: gains.torque_limit_positive.or(effort),
        torque_limit_negative: gains.torque_limit_negative.or(effort.map(|e| -e)),
        ..gains
    }
}

/// The URDF joint index an axis drives.
fn driven_joint(scene: &Scene, model: &RobotModel, axis: &Axis, joint: &str) -> Result<usize, String> {
    let Some(j) = model.joint_by_name(joint) else {
        let mut names: Vec<&str> = model
            .joints
            .iter()
            .filter(|j| j.kind.is_movable())
            .map(|j| j.name.as_str())
            .collect();
        names.sort_unstable();
        return Err(format!(
            "axis '{}' is mapped to joint '{}', which {} does not have (movable joints: {})",
            axis.name,
            joint,
            scene.robot.urdf.display(),
            names.join(", ")
        ));
    };
    if !model.joint(j).kind.is_movable() {
        return Err(format!(
            "joint '{}' of axis '{}' is fixed and cannot be driven",
            joint, axis.name
        ));
    }
    Ok(j.0)
}
