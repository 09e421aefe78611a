//! A running transform: its geometry and placement, the joints it commands,
//! and its forward/inverse steps each update.

use super::super::{ArmSolution, Geometry, JointKind, Placement, PositionError, Vec3};
use super::axes::{AxisId, JointAxis, SystemId};
use super::error::TransformFault;

/// Positions and velocities of the transformed axes of one side, in axis
/// units (and units/s); elements beyond the dimension are 0.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct AxesCommand {
    /// Command positions.
    pub positions: Vec3,
    /// Command velocities.
    pub velocities: Vec3,
}

/// Which side moved the other in the last update.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Driven {
    None,
    Target,
    Source,
}

/// A running transform.
#[derive(Debug, Clone, PartialEq)]
pub struct Transform {
    pub(super) source: SystemId,
    pub(super) target: SystemId,
    pub(super) source_axes: Vec<AxisId>,
    pub(super) target_axes: Vec<AxisId>,
    pub(super) geometry: Geometry,
    pub(super) placement: Placement,
    pub(super) solution: ArmSolution,
    pub(super) joint_axes: Vec<JointAxis>,
    /// Axis units per kinematic unit (180/π for revolute joints).
    pub(super) scale: Vec3,
    pub(super) joints: AxesCommand,
    pub(super) source_command: AxesCommand,
    pub(super) driven: Driven,
    /// A fault ended the transform and [`Transform::stop_step`] is bringing
    /// the joints to rest: no longer active (status bits off), but its axes
    /// are still in motion.
    pub(super) stopping: bool,
}

impl Transform {
    /// The geometry.
    pub fn geometry(&self) -> &Geometry {
        &self.geometry
    }

    /// Orientation and translation.
    pub fn placement(&self) -> &Placement {
        &self.placement
    }

    /// The arm solution kept for Cartesian moves.
    pub fn solution(&self) -> ArmSolution {
        self.solution
    }

    /// The source system.
    pub fn source(&self) -> SystemId {
        self.source
    }

    /// The target system.
    pub fn target(&self) -> SystemId {
        self.target
    }

    /// The source system's transformed axes (X1 first; the SCARA geometries'
    /// shared third axis last).
    pub fn source_axes(&self) -> &[AxisId] {
        &self.source_axes
    }

    /// The target system's transformed axes (J1 first).
    pub fn target_axes(&self) -> &[AxisId] {
        &self.target_axes
    }

    /// The last joint command (axis units).
    pub fn joint_command(&self) -> AxesCommand {
        self.joints
    }

    /// The last source command (coordinate units).
    pub fn source_command(&self) -> AxesCommand {
        self.source_command
    }

    pub(super) fn dimension(&self) -> usize {
        self.geometry.dimension()
    }

    /// Joint axis units → kinematic units.
    pub(super) fn to_kinematic(&self, joints: Vec3) -> Vec3 {
        [0, 1, 2].map(|i| joints[i] / self.scale[i])
    }

    /// The source position of joint positions (axis units).
    ///
    /// # Errors
    /// [`PositionError`] from the forward kinematics.
    pub fn source_of(&self, joints: Vec3) -> Result<Vec3, PositionError> {
        let x = self.geometry.forward(self.to_kinematic(joints))?;
        let mut s = self.placement.source_from_target(x);
        self.trim(&mut s);
        if self.geometry.shares_third_axis() {
            s[2] = joints[2];
        }
        Ok(s)
    }

    /// Zeroes the elements beyond the dimension (rounding of the rotation).
    pub(super) fn trim(&self, v: &mut Vec3) {
        for e in v.iter_mut().skip(self.dimension()) {
            *e = 0.0;
        }
    }

    /// The joint positions (axis units) for source position `source` on the
    /// kept arm solution, revolute joints unwrapped to the turn nearest the
    /// last command, limits checked.
    ///
    /// # Errors
    /// [`PositionError`]: out of reach, singular, other assembly, or beyond a
    /// joint limit.
    pub fn joints_of(&self, source: Vec3) -> Result<Vec3, PositionError> {
        self.joints_near(source, self.joints.positions)
    }

    /// [`Transform::joints_of`] with revolute joints unwrapped to the turn
    /// nearest `near` (axis units) instead of the last command: follows a
    /// planned path point by point (the pre-flight sweep).
    ///
    /// # Errors
    /// [`PositionError`]: out of reach, singular, other assembly, or beyond a
    /// joint limit.
    pub fn joints_near(&self, source: Vec3, near: Vec3) -> Result<Vec3, PositionError> {
        let mut target = self.placement.target_from_source(source);
        self.trim(&mut target);
        if self.geometry.shares_third_axis() {
            target[2] = source[2];
        }
        let q = self.geometry.inverse(target, self.solution)?;
        let kinds = self.geometry.joint_kinds();
        let mut joints = [0.0; 3];
        for i in 0..3 {
            let j = q[i] * self.scale[i];
            joints[i] = if kinds[i] == JointKind::Revolute {
                let prev = near[i];
                j + 360.0 * ((prev - j) / 360.0).round()
            } else {
                j
            };
        }
        self.check_limits(joints)?;
        Ok(joints)
    }

    /// The joint positions (axis units) for source position `source` on
    /// the kept arm solution, revolute joints as the geometry gives them
    /// (−180° to 180°), limits not checked (MCTP).
    ///
    /// # Errors
    /// [`PositionError`]: out of reach, singular, other assembly.
    pub(super) fn joints_principal(&self, source: Vec3) -> Result<Vec3, PositionError> {
        let mut target = self.placement.target_from_source(source);
        self.trim(&mut target);
        if self.geometry.shares_third_axis() {
            target[2] = source[2];
        }
        let q = self.geometry.inverse(target, self.solution)?;
        Ok([0, 1, 2].map(|i| q[i] * self.scale[i]))
    }

    pub(super) fn check_limits(&self, joints: Vec3) -> Result<(), PositionError> {
        for (i, axis) in self.joint_axes.iter().enumerate() {
            if let Some((min, max)) = axis.limits
                && !(min..=max).contains(&joints[i])
            {
                return Err(PositionError::BeyondJointLimit {
                    joint: i as u8,
                    position: joints[i],
                    min,
                    max,
                });
            }
        }
        Ok(())
    }

    /// One coarse update driven by the source: the joint commands that put
    /// the tool at `source` (coordinate units) `dt_s` after the last command.
    ///
    /// Velocities are `(new − last) / dt_s`. Nothing is changed on error.
    ///
    /// # Errors
    /// [`TransformFault::Position`] when `source` has no valid joint position
    /// (including a joint beyond its soft travel limits);
    /// [`TransformFault::JointSpeed`] when a joint would move faster than its
    /// axis' maximum speed; [`TransformFault::StoppingBeyondLimit`] when a
    /// joint's controlled stop ([`Transform::stop_step`]) from its new command
    /// would end beyond a soft travel limit. The executor then calls [`Transform::stop_step`]
    /// each update until it reports the joints at rest, and stops the source.
    pub fn follow_source(&mut self, source: Vec3, dt_s: f64) -> Result<AxesCommand, TransformFault> {
        let joints = self.joints_of(source)?;
        let mut velocities = [0.0; 3];
        for (i, axis) in self.joint_axes.iter().enumerate() {
            let v = (joints[i] - self.joints.positions[i]) / dt_s;
            if v.is_nan() || v.abs() > axis.max_speed {
                return Err(TransformFault::JointSpeed {
                    joint: i as u8,
                    required: v.abs(),
                    max: axis.max_speed,
                });
            }
            velocities[i] = v;
            if let Some((min, max)) = axis.limits {
                let d = stop_travel(v, axis.max_deceleration * dt_s, dt_s);
                let stop_position = joints[i] + d.copysign(v);
                if !(min..=max).contains(&stop_position) {
                    return Err(TransformFault::StoppingBeyondLimit {
                        joint: i as u8,
                        position: joints[i],
                        stop_position,
                        min,
                        max,
                    });
                }
            }
        }
        let mut s = source;
        self.trim(&mut s);
        self.source_command = AxesCommand {
            velocities: [0, 1, 2].map(|i| (s[i] - self.source_command.positions[i]) / dt_s),
            positions: s,
        };
        self.joints = AxesCommand {
            positions: joints,
            velocities,
        };
        self.driven = if velocities.iter().any(|&v| v != 0.0) {
            Driven::Target
        } else {
            Driven::None
        };
        Ok(self.joints)
    }

    /// One coarse update driven by the joints (a joint move while the
    /// transform is active): the source command for joint positions `joints`
    /// (axis units). The arm solution is re-read from the joints, so a joint
    /// move may flip it.
    ///
    /// # Errors
    /// [`TransformFault::Position`] when the joints have no valid transform
    /// position (a Delta whose forearms cannot meet, a joint beyond a limit).
    pub fn follow_joints(&mut self, joints: Vec3, dt_s: f64) -> Result<AxesCommand, TransformFault> {
        self.check_limits(joints)?;
        let source = self.source_of(joints)?;
        self.solution = self.geometry.solution(self.to_kinematic(joints))?;
        let velocities = [0, 1, 2].map(|i| (source[i] - self.source_command.positions[i]) / dt_s);
        self.joints = AxesCommand {
            velocities: [0, 1, 2].map(|i| (joints[i] - self.joints.positions[i]) / dt_s),
            positions: joints,
        };
        self.source_command = AxesCommand {
            positions: source,
            velocities,
        };
        self.driven = if velocities.iter().any(|&v| v != 0.0) {
            Driven::Source
        } else {
            Driven::None
        };
        Ok(self.source_command)
    }

    /// One coarse update in which neither side moved: the transform holds,
    /// both sides at rest, nothing driven.
    pub fn hold(&mut self) {
        self.joints.velocities = [0.0; 3];
        self.source_command.velocities = [0.0; 3];
        self.driven = Driven::None;
    }

    /// One coarse update of the controlled stop after a fault: each joint
    /// slows from its last command velocity at its axis' maximum
    /// deceleration. Returns the joint commands and whether every joint is at
    /// rest. Speeds only fall, so none exceeds the axis maximum; every
    /// command [`Transform::follow_source`] accepted can stop inside the soft
    /// travel limits, so none is passed (a position is also clamped to its
    /// limits, which absorbs rounding of the last ulp).
    pub fn stop_step(&mut self, dt_s: f64) -> (AxesCommand, bool) {
        let mut at_rest = true;
        for (i, axis) in self.joint_axes.iter().enumerate() {
            let v0 = self.joints.velocities[i];
            let dv = axis.max_deceleration * dt_s;
            let mut v1 = if v0.abs() <= dv { 0.0 } else { v0 - dv * v0.signum() };
            let mut p = self.joints.positions[i] + 0.5 * (v0 + v1) * dt_s;
            if let Some((min, max)) = axis.limits
                && !(min..=max).contains(&p)
            {
                p = p.clamp(min, max);
                v1 = 0.0;
            }
            self.joints.positions[i] = p;
            self.joints.velocities[i] = v1;
            at_rest &= v1 == 0.0;
        }
        self.driven = Driven::None;
        self.stopping = true;
        (self.joints, at_rest)
    }
}

/// The distance [`Transform::stop_step`] travels from speed `v` with speed
/// steps `dv` per update of `dt_s`: `n` full steps down to the remainder `r`,
/// then one update from `r` to rest, each update at its mean speed.
pub(super) fn stop_travel(v: f64, dv: f64, dt_s: f64) -> f64 {
    let v = v.abs();
    if v <= dv {
        return 0.5 * v * dt_s;
    }
    let mut n = (v / dv).floor();
    let mut r = v - n * dv;
    if r <= 0.0 {
        // v is a whole number of steps: the last full step ends at rest.
        n -= 1.0;
        r = dv;
    }
    (n * v - 0.5 * dv * n * n + 0.5 * r) * dt_s
}
