//! MCT in the executor: transforms between coordinate systems of the task.
//!
//! * [`MotionTask::set_transform_geometry`] gives a coordinate system its
//!   geometry (the Geometry/Offsets tabs) and transform dimension; a system
//!   without one is a Cartesian gantry with no offsets whose transform
//!   dimension is its number of primary axes.
//! * [`MotionTask::execute_mct`] executes MCT with a control structure (a
//!   one-shot rung, like [`MotionTask::execute_coordinated`]): `.EN` and
//!   `.DN`/`.ER` at once, `.IP` while the transform runs; the source axes'
//!   command positions jump to the forward kinematics of the joints.
//! * Each update, after the coordinate systems have moved
//!   ([`MotionTask::update`] step 4): if a source axis' command moved, the
//!   joints follow it ([`Transform::follow_source`]); otherwise, if a joint's
//!   command moved (a joint move, which may flip the arm solution), the
//!   source axes follow the joints. When both sides were moved in the same
//!   update the source wins and the joint commands are overwritten.
//! * A fault (ERR 67: out of reach, singular, a joint speed above its axis'
//!   maximum) ends the transform: `.ER`, `.IP` off; the source system's
//!   coordinated motion is brought to rest along its path, and the joints are
//!   stopped in joint space at their axes' maximum deceleration from their
//!   last valid command. The transform leaves the table when the joints are
//!   at rest; the source axes are no longer linked (a new MCT re-links them
//!   from the joints).
//! * MCS with stop type *all* (0) or *coordinated transform* (2) on the source
//!   or the target system cancels the transform (`.IP` off and the status
//!   bits with it); stop type *coordinated move* (1) leaves it running.
//!   Joints that were following the source are not frozen where they are:
//!   they stop in joint space at their axes' maximum deceleration, as after
//!   a fault, and the transform leaves the table when they are at rest (an
//!   MCT on their axes meanwhile is EXERR 10). Joints moving under their own
//!   commands (a joint move the source was following) go on.
//! * The task has one motion group, so EXERR 1 cannot arise here (it is
//!   tested on [`crate::mct::instruction`]). EXERR 13 is an axis of either
//!   system in the Shutdown state (MASD, MCSD, a fault's Shutdown action),
//!   EXERR 14 an inhibited one ([`crate::servo`]). EXERR 10 is any
//!   single-axis command or coordinated move on an axis of either system.
//! * Joint axes: maximum speed, deceleration and soft travel limits from
//!   their [`crate::axis::AxisConfig`]. A Cartesian command that would put a
//!   joint beyond its limit — or so close to it, that fast, that the joint
//!   could not stop before it — faults the transform with ERR 67 on the MCT
//!   control structure, exactly like a position out of reach: the source
//!   system's move is brought to rest along its path and the joints stop at
//!   their maximum deceleration, short of the limit. No joint command
//!   produced by a transform is ever beyond a soft travel limit.
//!
//! # Soft travel limits and the other commands (a choice)
//! Soft travel limits guard what a *transform* commands before it is
//! commanded: a joint position is a consequence of a Cartesian command
//! there, invisible to the program, so the executor keeps it inside. Every
//! other command names its axis positions directly and is checked as Logix
//! checks it, after the fact: the actual position crossing a limit while the
//! command moves out is a soft overtravel fault with the axis' exception
//! action, and a further move out fails with ERR 9 (see [`crate::servo`]).
//! While a transform runs, a joint move that ends beyond a limit ends the
//! link (ERR 67 on the MCT structure) but not the joint move itself; MRP
//! outside the limits raises the fault (see [`crate::mrp`]).

use super::MotionTask;
use crate::mct::instruction::{
    AxesCommand, AxisCondition, AxisId, JointAxis, Mct, MctError, MctRequest, SystemId, Transform, TransformFault,
    TransformId, TransformSystem,
};
use crate::mct::{GeometryKind, GeometryParams, Vec3};
use crate::profile::Sample;
use crate::servo::CipAxisState;
use crate::task::engine::{BeforeUpdate, MctSlot, TransformGeometry};
use crate::task::handles::{AxisHandle, CoordHandle, InstructionHandle};

fn axis_id(a: AxisHandle) -> AxisId {
    AxisId(a.0)
}

fn handle(a: AxisId) -> AxisHandle {
    AxisHandle(a.0)
}

impl MotionTask {
    /// Sets a coordinate system's geometry and transform dimension, used when
    /// it is the target of an MCT (and for its transform dimension as a
    /// source). Takes effect at the next MCT execution.
    pub fn set_transform_geometry(&mut self, system: CoordHandle, geometry: TransformGeometry) {
        let list = &mut self.mct.geometries;
        match list.iter_mut().find(|(s, _)| *s == system) {
            Some(slot) => slot.1 = geometry,
            None => list.push((system, geometry)),
        }
    }

    /// The transform table's id of a coordinate system: its index in the task.
    fn system_id(&self, system: CoordHandle) -> SystemId {
        SystemId(self.coord_handles().position(|h| h == system).unwrap_or(usize::MAX) as u32)
    }

    fn transform_system(&self, system: CoordHandle) -> TransformSystem {
        let geometry = self
            .mct
            .geometries
            .iter()
            .find(|(s, _)| *s == system)
            .map(|(_, g)| *g)
            .unwrap_or(TransformGeometry {
                kind: GeometryKind::CartesianGantry,
                params: GeometryParams::default(),
                transform_dimension: self.coord_config(system).primary_axes,
            });
        TransformSystem {
            id: self.system_id(system),
            in_motion_group: true,
            axes: self.coord_axes(system).iter().copied().map(axis_id).collect(),
            transform_dimension: geometry.transform_dimension,
            geometry: geometry.kind,
            params: geometry.params,
        }
    }

    /// Executes `MCT(source, target, control, orientation, translation)` now:
    /// one scan of a rung that has just become true. Executing again with the
    /// same control structure while its transform runs restarts it with the
    /// new orientation, translation and geometry.
    ///
    /// # Errors
    /// The refusal, also in the control structure (ERR 61 with its EXERR,
    /// ERR 13, ERR 67).
    pub(crate) fn execute_mct(
        &mut self,
        control: InstructionHandle,
        source: CoordHandle,
        target: CoordHandle,
        orientation_deg: Vec3,
        translation: Vec3,
    ) -> Result<(), MctError> {
        let index = match self.mct.instructions.iter().position(|s| s.control == control) {
            Some(i) => i,
            None => {
                self.mct.instructions.push(MctSlot {
                    control,
                    mct: Mct::new(),
                    source,
                    stopping: None,
                    release: false,
                    joint_motion: [(0.0, 0.0); 3],
                    before_update: None,
                });
                self.mct.instructions.len() - 1
            }
        };
        let source_system = self.transform_system(source);
        let target_system = self.transform_system(target);
        let (joint_axes, joints) = self.target_joints(target);
        let conditions: Vec<(AxisId, AxisCondition)> = source_system
            .axes
            .iter()
            .chain(&target_system.axes)
            .map(|&id| {
                let a = &self.axes[id.0 as usize];
                let single = a.job.as_ref().is_some_and(|j| !j.generation_done) || a.buffered.is_some();
                let coordinated = self.coordinated_motion_status(handle(id));
                (
                    id,
                    AxisCondition {
                        motion_process: single || coordinated,
                        shutdown: self.cip_axis_state(handle(id)) == CipAxisState::Shutdown,
                        inhibited: self.axes[id.0 as usize].config.inhibited,
                    },
                )
            })
            .collect();
        let condition = move |axis: AxisId| {
            conditions
                .iter()
                .find(|(id, _)| *id == axis)
                .map(|(_, c)| *c)
                .unwrap_or_default()
        };
        let request = MctRequest {
            source: &source_system,
            target: &target_system,
            orientation_deg,
            translation,
            joint_axes: &joint_axes,
            joints,
            condition: &condition,
        };
        let scanned = self.is_scanned(control);
        let slot = &mut self.mct.instructions[index];
        slot.source = source;
        slot.release = !scanned;
        slot.joint_motion = [(0.0, 0.0); 3];
        let started = slot.mct.execute(&mut self.mct.table, &request);
        let bits = slot.mct.bits();
        *self.motion_bits_mut(control) = bits;
        let position = started?;
        if let Some(id) = self.mct.instructions[index].mct.transform() {
            let axes: Vec<AxisId> = self
                .mct
                .table
                .get(id)
                .map(|t| t.source_axes().to_vec())
                .unwrap_or_default();
            for (i, axis) in axes.into_iter().enumerate() {
                let a = &mut self.axes[axis.0 as usize];
                a.command = Sample {
                    position: position[i],
                    ..Sample::default()
                };
                if !a.fed {
                    a.actual = position[i];
                }
            }
        }
        Ok(())
    }

    /// A target system's joint axes (limits) and their command positions.
    fn target_joints(&self, target: CoordHandle) -> (Vec<JointAxis>, Vec3) {
        let target_axes = self.coord_axes(target);
        let joint_axes = target_axes
            .iter()
            .map(|a| {
                let c = &self.axes[a.0 as usize].config;
                JointAxis {
                    max_speed: c.max_velocity,
                    max_deceleration: c.max_deceleration,
                    limits: c.soft_travel_limits,
                }
            })
            .collect();
        let mut joints = [0.0; 3];
        for (j, a) in joints.iter_mut().zip(target_axes) {
            *j = self.axes[a.0 as usize].command.position;
        }
        (joint_axes, joints)
    }

    /// MCTP: `reference` converted from one of the systems to the other
    /// ([`crate::mct::instruction::calculate`]), with the target's joints
    /// as they stand; `.DN` in the scan it executes. Nothing moves.
    ///
    /// # Errors
    /// MCT's refusals of the systems and placement, ERR 67 for a position
    /// the geometry cannot convert.
    pub(crate) fn mctp(
        &mut self,
        control: InstructionHandle,
        (source, target): (CoordHandle, CoordHandle),
        (orientation_deg, translation): (Vec3, Vec3),
        direction: crate::mct::instruction::TransformDirection,
        reference: Vec3,
    ) -> Result<Vec3, MctError> {
        self.instruction(control, |task| {
            let source_system = task.transform_system(source);
            let target_system = task.transform_system(target);
            let (joint_axes, joints) = task.target_joints(target);
            let idle = |_: AxisId| AxisCondition::default();
            let request = MctRequest {
                source: &source_system,
                target: &target_system,
                orientation_deg,
                translation,
                joint_axes: &joint_axes,
                joints,
                condition: &idle,
            };
            let position = crate::mct::instruction::calculate(&request, direction, reference)?;
            task.motion_bits_mut(control).dn = true;
            Ok(position)
        })
    }

    /// The transform an MCT control structure runs, while its `.IP` is set.
    pub fn mct_transform(&self, control: InstructionHandle) -> Option<&Transform> {
        let slot = self.mct.instructions.iter().find(|s| s.control == control)?;
        self.mct.table.get(slot.mct.transform()?)
    }

    /// The running transform (`.IP` set) whose source is `system`, if any.
    pub fn transform_of_source(&self, system: CoordHandle) -> Option<&Transform> {
        let id = self.system_id(system);
        self.mct
            .instructions
            .iter()
            .filter_map(|s| self.mct.table.get(s.mct.transform()?))
            .find(|t| t.source() == id)
    }

    /// A transform's source axes (X1 first; the SCARA geometries' shared
    /// third axis last) and target axes (J1 first) as task handles.
    pub fn transform_axes(&self, transform: &Transform) -> (Vec<AxisHandle>, Vec<AxisHandle>) {
        let handles = |axes: &[AxisId]| axes.iter().copied().map(handle).collect();
        (handles(transform.source_axes()), handles(transform.target_axes()))
    }

    /// The MCT control structures whose transform runs (`.IP`).
    pub(super) fn running_mct_controls(&self) -> Vec<InstructionHandle> {
        self.mct
            .instructions
            .iter()
            .filter(|s| s.mct.transform().is_some())
            .map(|s| s.control)
            .collect()
    }

    /// `TransformSourceStatus` of a coordinate system.
    pub fn transform_source_status(&self, system: CoordHandle) -> bool {
        self.mct.table.transform_source_status(self.system_id(system))
    }

    /// `TransformTargetStatus` of a coordinate system.
    pub fn transform_target_status(&self, system: CoordHandle) -> bool {
        self.mct.table.transform_target_status(self.system_id(system))
    }

    /// `TransformStateStatus` of an axis.
    pub fn transform_state_status(&self, axis: AxisHandle) -> bool {
        self.mct.table.transform_state_status(axis_id(axis))
    }

    /// `ControlledByTransformStatus` of an axis.
    pub fn controlled_by_transform_status(&self, axis: AxisHandle) -> bool {
        self.mct.table.controlled_by_transform_status(axis_id(axis))
    }

    /// Step 1 of an update for MCT: one-shot rungs go false.
    pub(super) fn evaluate_mct_instructions(&mut self) {
        for i in 0..self.mct.instructions.len() {
            let slot = &mut self.mct.instructions[i];
            if std::mem::take(&mut slot.release) {
                slot.mct.rung_false();
                let (control, bits) = (slot.control, slot.mct.bits());
                *self.motion_bits_mut(control) = bits;
            }
        }
    }

    /// Whether MCT slot `i` has an established transform that satisfies
    /// `involved` (asked as the slots are visited: cancelling one may end
    /// another's transform).
    fn mct_slot_involved(&self, i: usize, involved: impl Fn(&Transform) -> bool) -> bool {
        let t = self.mct.instructions[i].mct.transform();
        t.and_then(|t| self.mct.table.get(t)).is_some_and(involved)
    }

    /// Hook for MCS on `system` with `stop_type` (0 all, 1 coordinated move,
    /// 2 coordinated transform): types 0 and 2 cancel the transforms the
    /// system is the source or target of.
    pub(super) fn mct_on_mcs(&mut self, system: CoordHandle, stop_type: i64) {
        if stop_type == 1 {
            return;
        }
        let id = self.system_id(system);
        for i in 0..self.mct.instructions.len() {
            if !self.mct_slot_involved(i, |tr| tr.source() == id || tr.target() == id) {
                continue;
            }
            let slot = &mut self.mct.instructions[i];
            let Some(t) = slot.mct.transform() else { continue };
            // Joints that follow the source may be turning: they stop at
            // their axes' deceleration, as after a fault, not at once. Joints
            // that move under their own commands (the source follows them)
            // go on; only the link ends.
            let table = &self.mct.table;
            let joints_follow = table.get(t).is_some_and(|tr| {
                tr.target_axes()
                    .iter()
                    .any(|&a| table.controlled_by_transform_status(a))
            });
            if joints_follow {
                let id = slot.mct.stop();
                // Step 4 of this update takes the stop's first step.
                slot.stopping = id;
            } else {
                slot.mct.cancel(&mut self.mct.table);
            }
            let (control, bits) = (slot.control, slot.mct.bits());
            *self.motion_bits_mut(control) = bits;
        }
    }

    /// Cancels at once every transform with `axis` among its source or
    /// target axes (the axis' drive was disabled: MSF, a shutdown, a fault).
    pub(super) fn mct_cancel_on_axis(&mut self, axis: AxisHandle) {
        let id = axis_id(axis);
        for i in 0..self.mct.instructions.len() {
            if !self.mct_slot_involved(i, |tr| tr.source_axes().contains(&id) || tr.target_axes().contains(&id)) {
                continue;
            }
            let slot = &mut self.mct.instructions[i];
            slot.mct.cancel(&mut self.mct.table);
            slot.stopping = None;
            let (control, bits) = (slot.control, slot.mct.bits());
            *self.motion_bits_mut(control) = bits;
        }
    }

    /// Step 4 of an update: every transform follows the side that moved.
    pub(super) fn advance_transforms(&mut self) {
        let dt = self.dt_s;
        for i in 0..self.mct.instructions.len() {
            if let Some(id) = self.mct.instructions[i].stopping {
                if !self.stop_step(i, id) {
                    self.mct.instructions[i].stopping = None;
                }
                continue;
            }
            let Some(id) = self.mct.instructions[i].mct.transform() else {
                continue;
            };
            let Some(t) = self.mct.table.get(id) else { continue };
            let before = BeforeUpdate {
                transform: t.clone(),
                joint_motion: self.mct.instructions[i].joint_motion,
                axes: t
                    .target_axes()
                    .iter()
                    .map(|&a| {
                        let x = &self.axes[a.0 as usize];
                        (handle(a), x.command, x.actual, x.last_direction)
                    })
                    .collect(),
            };
            self.mct.instructions[i].before_update = Some(Box::new(before));
            let source_axes = t.source_axes().to_vec();
            let target_axes = t.target_axes().to_vec();
            let read = |axes: &[AxisId]| {
                let mut v = [0.0; 3];
                for (x, a) in v.iter_mut().zip(axes) {
                    *x = self.axes[a.0 as usize].command.position;
                }
                v
            };
            let source_now = read(&source_axes);
            let mut joints_now = read(&target_axes);
            if source_axes.len() > target_axes.len() {
                // The SCARA geometries' shared third axis is the third joint.
                joints_now[2] = source_now[2];
            }
            let source_moved = source_now != t.source_command().positions;
            let joints_moved = joints_now != t.joint_command().positions;
            let t = self.mct.table.get_mut(id).expect("checked above");
            if source_moved {
                match t.follow_source(source_now, dt) {
                    Ok(cmd) => self.write_joints(i, &target_axes, cmd),
                    Err(fault) => self.fault(i, id, &fault),
                }
            } else if joints_moved {
                match t.follow_joints(joints_now, dt) {
                    Ok(cmd) => {
                        for (k, axis) in source_axes.iter().enumerate().take(target_axes.len()) {
                            let a = &mut self.axes[axis.0 as usize];
                            a.command = Sample {
                                position: cmd.positions[k],
                                velocity: cmd.velocities[k],
                                ..Sample::default()
                            };
                            if !a.fed {
                                a.actual = cmd.positions[k];
                            }
                        }
                    }
                    Err(fault) => {
                        // The joints move under their own commands: only the
                        // link ends. The source axes, which only followed,
                        // hold where the link last put them (not the
                        // SCARA geometries' shared third axis: a joint).
                        for axis in source_axes.iter().take(target_axes.len()) {
                            let a = &mut self.axes[axis.0 as usize];
                            a.command = Sample {
                                position: a.command.position,
                                ..Sample::default()
                            };
                        }
                        let slot = &mut self.mct.instructions[i];
                        slot.mct.fault(&fault);
                        slot.mct.cancel(&mut self.mct.table);
                        let (control, bits) = (slot.control, slot.mct.bits());
                        *self.motion_bits_mut(control) = bits;
                    }
                }
            } else {
                t.hold();
            }
        }
    }

    /// Undoes this update's [`MotionTask::advance_transforms`] step of the
    /// running transforms whose source is `system`: the transform and its
    /// joint axes' commands are restored as they were before it (used when
    /// the source system's move is withdrawn in the update it started in,
    /// so its joints do not move either).
    pub(super) fn mct_undo_update(&mut self, system: CoordHandle) {
        let id = self.system_id(system);
        for i in 0..self.mct.instructions.len() {
            let slot = &mut self.mct.instructions[i];
            let Some(t) = slot.mct.transform() else { continue };
            let Some(before) = slot.before_update.take() else {
                continue;
            };
            let Some(transform) = self.mct.table.get_mut(t) else {
                continue;
            };
            if transform.source() != id {
                slot.before_update = Some(before);
                continue;
            }
            *transform = before.transform;
            slot.joint_motion = before.joint_motion;
            for (a, command, actual, last_direction) in before.axes {
                let x = &mut self.axes[a.0 as usize];
                x.command = command;
                x.actual = actual;
                x.last_direction = last_direction;
            }
        }
    }

    fn fault(&mut self, i: usize, id: TransformId, fault: &TransformFault) {
        let slot = &mut self.mct.instructions[i];
        slot.mct.fault(fault);
        slot.stopping = Some(id);
        let (control, bits, source) = (slot.control, slot.mct.bits(), slot.source);
        *self.motion_bits_mut(control) = bits;
        self.bring_system_to_rest(source);
        self.stop_joints(i, id);
    }

    /// Starts the controlled stop of transform `id`'s joints (instruction
    /// slot `i`): its first update now, the rest in
    /// [`MotionTask::advance_transforms`]; the transform leaves the table when
    /// the joints are at rest.
    fn stop_joints(&mut self, i: usize, id: TransformId) {
        self.mct.instructions[i].stopping = Some(id);
        self.stop_step(i, id);
    }

    /// One coarse update of the controlled stop of transform `id` (of
    /// instruction `i`): writes the joint commands and, once the joints are
    /// at rest, takes the transform out of the table. Returns false when the
    /// transform is no longer in the table.
    fn stop_step(&mut self, i: usize, id: TransformId) -> bool {
        let dt = self.dt_s;
        let Some(t) = self.mct.table.get_mut(id) else {
            return false;
        };
        let (cmd, at_rest) = t.stop_step(dt);
        let axes = t.target_axes().to_vec();
        self.write_joints(i, &axes, cmd);
        if at_rest {
            self.mct.table.cancel(id);
            self.mct.instructions[i].stopping = None;
        }
        true
    }

    fn write_joints(&mut self, i: usize, axes: &[AxisId], cmd: AxesCommand) {
        let dt = self.dt_s;
        for (k, axis) in axes.iter().enumerate() {
            let (v_prev, a_prev) = self.mct.instructions[i].joint_motion[k];
            let v = cmd.velocities[k];
            let acc = (v - v_prev) / dt;
            self.mct.instructions[i].joint_motion[k] = (v, acc);
            let a = &mut self.axes[axis.0 as usize];
            a.command = Sample {
                position: cmd.positions[k],
                velocity: v,
                acceleration: acc,
                jerk: (acc - a_prev) / dt,
            };
            if !a.fed {
                a.actual = cmd.positions[k];
            }
            if v != 0.0 {
                a.last_direction = v.signum();
            }
        }
    }
}

#[cfg(test)]
mod tests;
