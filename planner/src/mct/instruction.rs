//! The MCT instruction: `MCT(Source System, Target System, Motion Control,
//! Orientation, Translation)`.
//!
//! * [`TransformSystem`] — what MCT reads from a coordinate system tag: its
//!   motion group, axes, transform dimension and (target) geometry.
//! * [`TransformTable`] — the controller's active transforms: it owns each
//!   running [`Transform`] and answers the status bits
//!   `TransformSourceStatus`, `TransformTargetStatus` (coordinate systems),
//!   `TransformStateStatus`, `ControlledByTransformStatus` (axes).
//! * [`Transform`] — one running transform, the coarse-update executor's
//!   interface: [`Transform::follow_source`] turns this update's source
//!   (Cartesian) command into joint commands, [`Transform::follow_joints`]
//!   turns joint positions into source positions, [`Transform::stop_step`]
//!   brings the joints to a controlled stop after a fault.
//! * [`Mct`] — the instruction's `MOTION_INSTRUCTION` tag and scan logic.
//!
//! # What the spec says, and how it is implemented
//! * Transitional: a false → true rung starts (or restarts) the transform,
//!   sets `.EN`, and on success `.DN` and `.IP`; the transform keeps running
//!   after `.DN` and while the rung is false. Prescan clears `.EN .DN .ER
//!   .IP`; a false rung clears `.EN` once `.DN` or `.ER` is set.
//! * At start the source positions become the forward kinematics of the
//!   target's current joint positions (through orientation and translation);
//!   afterwards moving either side moves the other.
//! * An MCS (or shutdown, or fault action) cancels the transform:
//!   [`Mct::cancel`] clears `.IP` and the status bits.
//! * Executing again while active re-reads orientation, translation and
//!   geometry; the source positions jump to the forward kinematics of the
//!   joints under the new values (the joints do not move).
//! * The arm solution the joints are in at start is kept for every Cartesian
//!   move; a move of the joints themselves re-reads it (only joint moves can
//!   flip it).
//! * Errors at execution: ERR 61 with EXERR 1–17 ([`MctError::exerr`]), ERR 13
//!   (operand out of range, EXERR = operand number counted from 0) for a
//!   non-finite Orientation (3) or Translation (4) element, ERR 67 when the
//!   joints' current position has no valid transform position.
//!
//! # Choices where the spec is silent
//! * **Check order**: operands (ERR 13); EXERR 1, 2, 3, 4, 16, 17, the
//!   geometry (4, 12, 15), 5, 6, 7, 8, 9, 13, 14, 10, 11; then the start
//!   position (ERR 67).
//! * **EXERR 7** ("an axis in one source system and/or target system"): an
//!   axis may be a source axis of one transform and a target axis of another
//!   (a chain of transforms), but not a source axis twice or a target axis
//!   twice. **EXERR 9** concerns the transformed axes; the SCARA geometries'
//!   third axis is shared by design (EXERR 16 requires it).
//! * **EXERR 11**: the table holds [`MAX_ACTIVE_TRANSFORMS`] transforms.
//! * **Orientation and translation of a transform of dimension < 3**: only
//!   what keeps the transformed plane (line) is accepted — for dimension 2
//!   the rotation about X3 and the X1, X2 translation, for dimension 1 the X1
//!   translation. Anything else would be lost and is refused with ERR 13
//!   (EXERR 3 for Orientation, 4 for Translation).
//! * **Runtime errors**: a source command with no valid joint position, a
//!   joint beyond its limit, or a joint that would have to move faster than
//!   its axis' maximum speed (close to a singularity) ends the transform with
//!   `.ER`, ERR 67 (`.DN` stays, `.IP` clears): [`Mct::fault`]. The joints
//!   are then stopped in joint space, each at its axis' maximum
//!   deceleration, from the last valid command ([`Transform::stop_step`]), so
//!   no command ever exceeds an axis' maximum speed.
//! * **Soft travel limits** ([`JointAxis::limits`]): a joint position beyond
//!   them is ERR 67 at execution and a fault while running. A running
//!   transform also faults (ERR 67, [`TransformFault::StoppingBeyondLimit`])
//!   as soon as a joint could no longer stop inside its limits at its axis'
//!   maximum deceleration, so the controlled stop that follows never commands
//!   a joint beyond a limit: the joint comes to rest short of it.
//! * Joint command velocities are the position increment of the update
//!   divided by the update period, so positions and velocities agree.
//! * **Joint accelerations are not limited** while the transform follows the
//!   source (as in Logix, which leaves it to the program to keep the robot
//!   away from singularities): close to — but outside the margin of — a
//!   singularity, a joint's speed may change abruptly from one update to the
//!   next (never beyond its axis' maximum speed). Only the speed is guarded
//!   (a fault above it), and
//!   the controlled stop after a fault decelerates at the axis' maximum.
//! * **A faulted transform** is no longer active as soon as `.IP` clears:
//!   `TransformSourceStatus`, `TransformTargetStatus` and
//!   `TransformStateStatus` go off with it, although the executor keeps it
//!   in the table while [`Transform::stop_step`] brings its joints to rest.
//!   An MCT on one of its axes meanwhile is EXERR 10 (the controlled stop is
//!   a motion process on that axis).
//! * Re-execution of a control structure whose transform runs replaces that
//!   transform (the table keeps one transform per control structure, the
//!   spec's "use a motion control tag only once"): with the same two systems
//!   it is the restart above; with other systems the old link ends and the
//!   new one starts, checked against every *other* transform (EXERR 5–9).
//!   Like a start, it needs no motion process on the new systems' axes
//!   (EXERR 10). A re-execution that fails leaves the running transform as
//!   it was (`.ER` set, `.IP` still set).

use super::{ArmSolution, Geometry, GeometryKind, GeometryParams, JointKind, Placement, Vec3};
use crate::instruction::MotionInstructionBits;

mod axes;
mod error;
mod transform;

pub use axes::{AxisId, JointAxis, SystemId};
pub use error::{MctError, TransformFault};
use transform::Driven;
pub use transform::{AxesCommand, Transform};

/// How many transforms may be active at once (EXERR 11 beyond).
pub const MAX_ACTIVE_TRANSFORMS: usize = 8;

/// A transform in a [`TransformTable`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct TransformId(u32);

/// What MCT reads from a coordinate system tag.
#[derive(Debug, Clone, PartialEq)]
pub struct TransformSystem {
    /// The system.
    pub id: SystemId,
    /// Whether it is assigned to the motion group (EXERR 1 if not).
    pub in_motion_group: bool,
    /// Its axes, X1 (J1) first.
    pub axes: Vec<AxisId>,
    /// Transform dimension: how many of its axes the transform uses.
    pub transform_dimension: usize,
    /// Coordinate system type / geometry (used for the target).
    pub geometry: GeometryKind,
    /// Geometry and Offsets tabs (used for the target).
    pub params: GeometryParams,
}

/// The state of an axis that MCT checks at execution.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct AxisCondition {
    /// The axis is shut down (EXERR 13).
    pub shutdown: bool,
    /// The axis is inhibited (EXERR 14).
    pub inhibited: bool,
    /// A motion process (jog, move, gear, a coordinated move, …) controls the
    /// axis (EXERR 10).
    pub motion_process: bool,
}

/// The active transforms of a controller.
#[derive(Debug, Clone, Default)]
pub struct TransformTable {
    slots: Vec<Option<Transform>>,
}

impl TransformTable {
    /// An empty table.
    pub fn new() -> Self {
        Self::default()
    }

    /// A running transform.
    pub fn get(&self, id: TransformId) -> Option<&Transform> {
        self.slots.get(id.0 as usize).and_then(Option::as_ref)
    }

    /// A running transform, mutable (for the executor's updates).
    pub fn get_mut(&mut self, id: TransformId) -> Option<&mut Transform> {
        self.slots.get_mut(id.0 as usize).and_then(Option::as_mut)
    }

    fn active(&self) -> impl Iterator<Item = (TransformId, &Transform)> {
        self.slots
            .iter()
            .enumerate()
            .filter_map(|(i, t)| t.as_ref().map(|t| (TransformId(i as u32), t)))
    }

    /// The transforms that are active: in the table and not stopping after a
    /// fault.
    fn running(&self) -> impl Iterator<Item = (TransformId, &Transform)> {
        self.active().filter(|(_, t)| !t.stopping)
    }

    /// Number of transforms in the table (active, or stopping after a fault).
    pub fn len(&self) -> usize {
        self.active().count()
    }

    /// Whether no transform is active.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// `TransformSourceStatus` of a coordinate system.
    pub fn transform_source_status(&self, system: SystemId) -> bool {
        self.running().any(|(_, t)| t.source == system)
    }

    /// `TransformTargetStatus` of a coordinate system.
    pub fn transform_target_status(&self, system: SystemId) -> bool {
        self.running().any(|(_, t)| t.target == system)
    }

    /// `TransformStateStatus` of an axis: part of an active transform.
    pub fn transform_state_status(&self, axis: AxisId) -> bool {
        self.running()
            .any(|(_, t)| t.source_axes.contains(&axis) || t.target_axes.contains(&axis))
    }

    /// `ControlledByTransformStatus` of an axis: moved by a transform in the
    /// last update (a joint while the source moved, or a source axis while
    /// the joints moved).
    pub fn controlled_by_transform_status(&self, axis: AxisId) -> bool {
        self.running().any(|(_, t)| match t.driven {
            Driven::Target => t.target_axes.contains(&axis),
            Driven::Source => t.source_axes.contains(&axis),
            Driven::None => false,
        })
    }

    /// Removes a transform (MCS, shutdown, fault). Unknown ids are ignored.
    pub fn cancel(&mut self, id: TransformId) {
        if let Some(slot) = self.slots.get_mut(id.0 as usize) {
            *slot = None;
        }
    }

    /// Checks an MCT execution and starts (or, with `restart`, restarts) the
    /// transform: the source positions it returns are the forward kinematics
    /// of `joints` (target axis positions, axis units).
    ///
    /// # Errors
    /// [`MctError`] — see the module doc for the check order.
    pub fn execute(
        &mut self,
        request: &MctRequest<'_>,
        restart: Option<TransformId>,
    ) -> Result<(TransformId, Vec3), MctError> {
        let restart = restart.filter(|id| self.get(*id).is_some());
        let (geometry, placement) = self.check(request, restart)?;
        let mut t = build(request, geometry, placement);
        t.check_limits(request.joints)?;
        let position = t.source_of(request.joints)?;
        t.solution = geometry.solution(t.to_kinematic(request.joints))?;
        t.source_command.positions = position;
        let id = match restart {
            Some(id) => {
                self.slots[id.0 as usize] = Some(t);
                id
            }
            None => match self.slots.iter().position(Option::is_none) {
                Some(i) => {
                    self.slots[i] = Some(t);
                    TransformId(i as u32)
                }
                None => {
                    self.slots.push(Some(t));
                    TransformId(self.slots.len() as u32 - 1)
                }
            },
        };
        Ok((id, position))
    }

    fn check(&self, r: &MctRequest<'_>, restart: Option<TransformId>) -> Result<(Geometry, Placement), MctError> {
        let (geometry, placement) = check_systems(r)?;
        let (source, target) = (r.source, r.target);
        let (sd, td) = (source.transform_dimension, target.transform_dimension);
        let others = || self.running().filter(|(id, _)| Some(*id) != restart).map(|(_, t)| t);
        // Axes a faulted transform is still stopping: in motion (EXERR 10).
        let stopping = |axis: &AxisId| {
            self.active()
                .any(|(_, t)| t.stopping && (t.source_axes.contains(axis) || t.target_axes.contains(axis)))
        };
        if others().any(|t| t.source == source.id) {
            return Err(MctError::SourceInUse { system: source.id });
        }
        if others().any(|t| t.target == target.id) {
            return Err(MctError::TargetInUse { system: target.id });
        }
        let mut source_axes = source.axes[..sd].to_vec();
        if geometry.shares_third_axis() {
            source_axes.push(source.axes[2]);
        }
        let target_axes = &target.axes[..td];
        for &axis in &source_axes {
            if others().any(|t| t.source_axes.contains(&axis)) {
                return Err(MctError::AxisInUse { axis });
            }
        }
        for &axis in target_axes {
            if others().any(|t| t.target_axes.contains(&axis)) {
                return Err(MctError::AxisInUse { axis });
            }
        }
        // A path target → … → source through active transforms closes a loop.
        let mut at = target.id;
        for _ in 0..=self.slots.len() {
            if at == source.id {
                return Err(MctError::CircularChain);
            }
            match others().find(|t| t.source == at) {
                Some(t) => at = t.target,
                None => break,
            }
        }
        if let Some(&axis) = source.axes[..sd].iter().find(|a| target_axes.contains(a)) {
            return Err(MctError::SharedAxis { axis });
        }
        let all: Vec<AxisId> = source_axes.iter().chain(target_axes).copied().collect();
        for &axis in &all {
            if (r.condition)(axis).shutdown {
                return Err(MctError::AxisShutdown { axis });
            }
        }
        for &axis in &all {
            if (r.condition)(axis).inhibited {
                return Err(MctError::AxisInhibited { axis });
            }
        }
        for &axis in &all {
            if (r.condition)(axis).motion_process || stopping(&axis) {
                return Err(MctError::MotionInProcess { axis });
            }
        }
        if restart.is_none() && self.len() >= MAX_ACTIVE_TRANSFORMS {
            return Err(MctError::NoResources {
                capacity: MAX_ACTIVE_TRANSFORMS,
            });
        }
        if r.joint_axes.len() < td {
            return Err(MctError::TargetDimension {
                dimension: td,
                axes: r.joint_axes.len(),
            });
        }
        Ok((geometry, placement))
    }
}

/// A transform of `request`'s systems at its joints, not yet placed in a
/// table.
fn build(request: &MctRequest<'_>, geometry: Geometry, placement: Placement) -> Transform {
    let (source, target) = (request.source, request.target);
    let dim = geometry.dimension();
    let mut source_axes = source.axes[..dim].to_vec();
    let target_axes = target.axes[..dim].to_vec();
    if geometry.shares_third_axis() {
        source_axes.push(source.axes[2]);
    }
    let kinds = geometry.joint_kinds();
    let scale = [0, 1, 2].map(|i| {
        if kinds[i] == JointKind::Revolute {
            180.0 / std::f64::consts::PI
        } else {
            1.0
        }
    });
    let joint_axes = request.joint_axes.iter().take(dim).copied().collect();
    Transform {
        source: source.id,
        target: target.id,
        source_axes,
        target_axes,
        geometry,
        placement,
        solution: ArmSolution::default(),
        joint_axes,
        scale,
        joints: AxesCommand {
            positions: request.joints,
            velocities: [0.0; 3],
        },
        source_command: AxesCommand::default(),
        driven: Driven::None,
        stopping: false,
    }
}

/// MCTP's Transform Direction: which way to convert, and for an inverse
/// which arm solution.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TransformDirection {
    /// Joint positions (target system) to the Cartesian position (source).
    Forward,
    /// The Cartesian position to joint positions, on the arm solution the
    /// target's joints stand in now.
    Inverse,
    /// The Cartesian position to joint positions, left arm (a serial arm's
    /// elbow angle negative; other geometries as [`TransformDirection::Inverse`]).
    InverseLeftArm,
    /// The Cartesian position to joint positions, right arm (elbow angle
    /// positive).
    InverseRightArm,
}

/// MCTP: the position `reference` converted between `request`'s systems as
/// MCT would convert it (its geometry, Orientation and Translation, arm
/// solutions), without a transform running or anything moving. Forward
/// gives the source's coordinates of joint positions (axis units);
/// inverse the joint positions (axis units, revolute joints from −180° to
/// 180°, as the geometry solves them) of source coordinates. A system's
/// axes may be in motion or in another transform: nothing is driven. Soft
/// travel limits are not checked (MCT checks them when it moves).
///
/// # Errors
/// MCT's refusals of the systems, orientation and translation (ERR 61
/// with its EXERR, ERR 13); ERR 67 for a position the geometry cannot
/// convert.
pub fn calculate(request: &MctRequest<'_>, direction: TransformDirection, reference: Vec3) -> Result<Vec3, MctError> {
    let (geometry, placement) = check_systems(request)?;
    let mut t = build(request, geometry, placement);
    t.joint_axes.clear();
    match direction {
        TransformDirection::Forward => Ok(t.source_of(reference)?),
        _ => {
            let now = geometry.solution(t.to_kinematic(request.joints));
            // Left and right are a serial arm's elbow (bit 0); a Delta's
            // knees and a Cartesian robot have no arms to choose.
            let serial = matches!(
                request.target.geometry,
                GeometryKind::ArticulatedIndependent
                    | GeometryKind::ArticulatedDependent
                    | GeometryKind::ScaraIndependent
            );
            t.solution = match direction {
                TransformDirection::InverseLeftArm if serial => now.unwrap_or_default().with(0, true),
                TransformDirection::InverseRightArm if serial => now.unwrap_or_default().with(0, false),
                _ => now?,
            };
            Ok(t.joints_principal(reference)?)
        }
    }
}

/// The checks of a transform's two systems, orientation and translation
/// that do not depend on what else runs (MCT's and MCTP's): the geometry
/// and placement they give.
fn check_systems(r: &MctRequest<'_>) -> Result<(Geometry, Placement), MctError> {
    let (source, target) = (r.source, r.target);
    let placement = Placement::new(r.orientation_deg, r.translation)?;
    for system in [source, target] {
        if !system.in_motion_group {
            return Err(MctError::NotInMotionGroup { system: system.id });
        }
    }
    if source.id == target.id {
        return Err(MctError::SameSystem { system: source.id });
    }
    let (sd, td) = (source.transform_dimension, target.transform_dimension);
    if !(1..=3).contains(&sd) || sd > source.axes.len() {
        return Err(MctError::SourceDimension {
            dimension: sd,
            axes: source.axes.len(),
        });
    }
    if !(1..=3).contains(&td) || td > target.axes.len() {
        return Err(MctError::TargetDimension {
            dimension: td,
            axes: target.axes.len(),
        });
    }
    if matches!(
        target.geometry,
        GeometryKind::ScaraIndependent | GeometryKind::ScaraDelta
    ) && (sd != 2 || source.axes.get(2).is_none() || source.axes.get(2) != target.axes.get(2))
    {
        return Err(MctError::ScaraAxes { source_dimension: sd });
    }
    if sd != td {
        return Err(MctError::DimensionMismatch {
            source_dimension: sd,
            target_dimension: td,
        });
    }
    let geometry = Geometry::new(target.geometry, &target.params, td)?;
    check_in_plane(r.orientation_deg, r.translation, td)?;
    Ok((geometry, placement))
}

fn check_in_plane(orientation_deg: Vec3, translation: Vec3, dimension: usize) -> Result<(), MctError> {
    let out = |operand, index: usize, value: f64| MctError::OutOfPlane {
        operand,
        index: index as u8,
        value,
        dimension,
    };
    let keep_rotation: &[usize] = match dimension {
        1 => &[],
        2 => &[2],
        _ => &[0, 1, 2],
    };
    for (i, &v) in orientation_deg.iter().enumerate() {
        if v != 0.0 && !keep_rotation.contains(&i) {
            return Err(out(3, i, v));
        }
    }
    for (i, &v) in translation.iter().enumerate().skip(dimension) {
        if v != 0.0 {
            return Err(out(4, i, v));
        }
    }
    Ok(())
}

/// The operands and context of one MCT execution.
pub struct MctRequest<'a> {
    /// Source System.
    pub source: &'a TransformSystem,
    /// Target System.
    pub target: &'a TransformSystem,
    /// Orientation, degrees about X1, X2, X3.
    pub orientation_deg: Vec3,
    /// Translation, coordinate units.
    pub translation: Vec3,
    /// The target's joint axes' limits, J1 first (at least its transform
    /// dimension).
    pub joint_axes: &'a [JointAxis],
    /// The target's current joint positions, axis units.
    pub joints: Vec3,
    /// Shutdown / inhibit / motion state of an axis.
    pub condition: &'a dyn Fn(AxisId) -> AxisCondition,
}

/// The MCT instruction's `MOTION_INSTRUCTION` tag and scan state.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Mct {
    bits: MotionInstructionBits,
    previous_rung: bool,
    transform: Option<TransformId>,
}

impl Mct {
    /// A tag at its initial state.
    pub fn new() -> Self {
        Self::default()
    }

    /// The `MOTION_INSTRUCTION` bits.
    pub fn bits(&self) -> MotionInstructionBits {
        self.bits
    }

    /// The transform this instruction started, while `.IP`.
    pub fn transform(&self) -> Option<TransformId> {
        self.transform.filter(|_| self.bits.ip)
    }

    /// Prescan: `.EN .DN .ER .IP` cleared.
    pub fn prescan(&mut self) {
        self.bits.en = false;
        self.bits.dn = false;
        self.bits.er = false;
        self.bits.ip = false;
        self.previous_rung = false;
    }

    /// One scan with rung-condition-in `rung`. On a false → true transition the
    /// instruction executes: on success `.DN` and `.IP` are set and the new
    /// source positions are returned (the executor sets the source axes'
    /// command positions to them); on failure `.ER` with ERR/EXERR.
    pub fn scan(&mut self, rung: bool, table: &mut TransformTable, request: &MctRequest<'_>) -> Option<Vec3> {
        if !rung {
            self.rung_false();
            return None;
        }
        if self.previous_rung {
            return None;
        }
        self.execute(table, request).ok()
    }

    /// A scan with the rung false: `.EN` clears once `.DN` or `.ER` is set.
    pub fn rung_false(&mut self) {
        self.previous_rung = false;
        if self.bits.dn || self.bits.er {
            self.bits.en = false;
        }
    }

    /// A scan of a rung that has just become true (a one-shot rung):
    /// executes the instruction whatever the previous rung state was. See
    /// [`Mct::scan`].
    ///
    /// # Errors
    /// The refusal, also in the bits (ERR 61 with its EXERR, ERR 13, ERR 67).
    pub fn execute(&mut self, table: &mut TransformTable, request: &MctRequest<'_>) -> Result<Vec3, MctError> {
        self.previous_rung = true;
        self.bits.en = true;
        self.bits.dn = false;
        self.bits.er = false;
        self.bits.err = 0;
        self.bits.exerr = 0;
        match table.execute(request, self.transform()) {
            Ok((id, position)) => {
                self.transform = Some(id);
                self.bits.dn = true;
                self.bits.ip = true;
                Ok(position)
            }
            Err(e) => {
                self.bits.set_error(e.err(), e.exerr(), 0);
                Err(e)
            }
        }
    }

    /// MCS (or shutdown, or a fault action): cancels the transform, clears
    /// `.IP`.
    pub fn cancel(&mut self, table: &mut TransformTable) {
        if let Some(id) = self.transform.take() {
            table.cancel(id);
        }
        self.bits.ip = false;
    }

    /// MCS (or shutdown, or a fault action) ends the transform while the
    /// executor still has to bring its joints to rest: clears `.IP` and
    /// returns the transform, which stays in the table (no longer active, see
    /// [`Transform::stop_step`]) until the executor removes it with
    /// [`TransformTable::cancel`]. `None` when none was running.
    pub fn stop(&mut self) -> Option<TransformId> {
        self.bits.ip = false;
        self.transform.take()
    }

    /// A runtime fault ended the transform: `.IP` cleared, `.ER` set with
    /// ERR 67 (`.DN` stays). The transform stays in the table until the
    /// executor's controlled stop has brought the joints to rest and it calls
    /// [`TransformTable::cancel`].
    pub fn fault(&mut self, fault: &TransformFault) {
        self.bits.ip = false;
        self.bits.set_error(fault.err(), 0, 0);
    }
}

#[cfg(test)]
mod tests;
