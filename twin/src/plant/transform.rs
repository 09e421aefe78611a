//! The plant side of coordinate transforms (MCT): the load-time check that
//! each transform's target robot (its URDF chain) has the kinematics of the
//! target system's `geometry` table, and the parallel robots' virtual
//! joints, posed from the MCT kinematics every physics step.
//!
//! * `check_transforms` runs [`crate::plant::kinematics_check::check`] for
//!   every target system an MCT call names — in the scene's `[[program]]`
//!   steps or in its tasks' routines — and refuses the scene on a mismatch,
//!   naming the `geometry` table's line and the distance. A geometry the
//!   planner refuses (a zero link length, …) is not checked here: the MCT
//!   reports it at run time with its ERR/EXERR, as on the controller.
//! * MCT takes revolute joint axes in degrees (as Logix), so a target axis
//!   on a revolute URDF joint must have `units = "deg"`; the geometry's
//!   lengths are in the source system's coordinate units.

use super::dynamics::Dynamics;
use super::error::PlantError;
use super::kinematics_check::{ChainMapping, check, pose_parallel};
use super::physics::JointDrive;
use super::urdf::RobotModel;
use crate::scene::{Scene, TagValue};
use crate::st::ast::ExprKind;
use planner::mct::{Geometry, JointKind};
use planner::task::instructions::{self, mct::MCT};
use std::f64::consts::{PI, TAU};

/// Every target system with a `geometry` table that an MCT call of the
/// program names, once (the first call's source with it): `(source tag,
/// target tag)`. A program may call MCT on the same systems again (after
/// the link ended); it is still one transform of one robot. The calls are
/// the steps', then the routines' of the tasks, each looked up in the
/// instruction catalogue.
fn transforms(scene: &Scene) -> Vec<(&crate::scene::Tag, &crate::scene::Tag)> {
    let routines = scene
        .tasks
        .iter()
        .flat_map(|t| &t.programs)
        .flat_map(|p| std::iter::once(&p.main).chain(&p.routines))
        .flat_map(|r| r.routine.calls());
    let calls = scene.program.iter().map(|s| &s.call).chain(routines);
    let (source, target) = (MCT.index("Source System"), MCT.index("Target System"));
    let mut found: Vec<(&crate::scene::Tag, &crate::scene::Tag)> = Vec::new();
    for call in calls {
        if instructions::find(&call.name) != Some(&MCT) || call.args.len() != MCT.operands.len() {
            continue;
        }
        let tag = |k: usize| match call.args[k].expr.as_ref().map(|e| &e.kind) {
            Some(ExprKind::Ref(r)) if r.path.is_empty() => scene.tag(&r.name),
            _ => None,
        };
        if let (Some(source), Some(target)) = (tag(source), tag(target))
            && target.geometry.is_some()
            && !found.iter().any(|(_, t)| t.name == target.name)
        {
            found.push((source, target));
        }
    }
    found
}

/// A transform's target robot as the kinematics check sees it.
struct Chain {
    geometry: Geometry,
    mapping: ChainMapping,
    metres_per_unit: f64,
    /// The target's joint axes, J1 first: (scene axis index, SI per unit).
    axes: Vec<(usize, f64)>,
}

fn chain(scene: &Scene, source: &crate::scene::Tag, target: &crate::scene::Tag) -> Result<Option<Chain>, PlantError> {
    let Some(settings) = &target.geometry else {
        return Ok(None);
    };
    let fail = |message: String| PlantError::Kinematics {
        scene: scene.path.clone(),
        line: settings.location.line,
        column: settings.location.column,
        message: format!("coordinate system '{}': {message}", target.name),
    };
    let Ok(geometry) = Geometry::new(settings.kind, &settings.params, settings.transform_dimension) else {
        return Ok(None);
    };
    let members = |tag: &crate::scene::Tag| match &tag.value {
        Some(TagValue::Axes(m)) => m.clone(),
        _ => Vec::new(),
    };
    let axis_index = |name: &String| scene.axes.iter().position(|a| a.name.eq_ignore_ascii_case(name));
    let metres_per_unit = members(source)
        .first()
        .and_then(axis_index)
        .map_or(1.0, |i| scene.axes[i].units.si_per_unit());
    let needed = geometry.dimension() + usize::from(geometry.shares_third_axis());
    let kinds = geometry.joint_kinds();
    let mut joints = Vec::new();
    let mut axes = Vec::new();
    for (i, member) in members(target).iter().take(needed).enumerate() {
        let index = axis_index(member).ok_or_else(|| fail(format!("member '{member}' is not an axis")))?;
        let axis = &scene.axes[index];
        let si = axis.units.si_per_unit();
        if kinds[i] == JointKind::Revolute && (si - 1f64.to_radians()).abs() > 1e-15 {
            return Err(fail(format!(
                "J{} axis '{member}' is on a revolute joint: MCT needs its units in deg",
                i + 1
            )));
        }
        let Some(joint) = &axis.joint else {
            return Err(fail(format!(
                "J{} axis '{member}' is virtual: a transform's target axes drive joints",
                i + 1
            )));
        };
        joints.push(joint.clone());
        axes.push((index, si));
    }
    let (Some(base_link), Some(tool_link)) = (&settings.base_link, &settings.tool_link) else {
        return Err(fail(
            "a transform's target geometry needs base_link and tool_link to be checked against the URDF".into(),
        ));
    };
    Ok(Some(Chain {
        geometry,
        mapping: ChainMapping {
            joints,
            base_link: base_link.clone(),
            tool_link: tool_link.clone(),
            platform_joints: settings.platform_joints.clone(),
            forearm_joints: settings.forearm_joints.clone(),
            forearm_tip_links: settings.forearm_tip_links.clone(),
            ball_links: settings.ball_links.clone(),
        },
        metres_per_unit,
        axes,
    }))
}

/// Checks every transform of the program: the target system's URDF chain
/// against its MCT geometry.
///
/// # Errors
/// [`PlantError::Kinematics`] naming the `geometry` table's line, with the
/// mismatch (what, by how much, at which joint configuration), a mapping
/// error, or a revolute joint axis not in degrees.
pub(crate) fn check_transforms(scene: &Scene, model: &RobotModel) -> Result<(), PlantError> {
    for (source, target) in transforms(scene) {
        let Some(c) = chain(scene, source, target)? else {
            continue;
        };
        let location = target.geometry.as_ref().map(|g| g.location).unwrap_or(target.location);
        check(model, &c.geometry, &c.mapping, c.metres_per_unit).map_err(|e| PlantError::Kinematics {
            scene: scene.path.clone(),
            line: location.line,
            column: location.column,
            message: format!("coordinate system '{}': {e}", target.name),
        })?;
    }
    Ok(())
}

/// Position gain (1/s²) and velocity gain (1/s) of the motors that hold a
/// parallel robot's virtual joints on their kinematic pose: critically
/// damped at 60 Hz.
const VIRTUAL_GAINS: (f64, f64) = (142_122.3, 754.0);

/// A parallel robot's virtual joints (platform, forearms), which a URDF
/// tree cannot close: each physics step they are driven to the pose the MCT
/// forward kinematics gives for the upper-arm joints' setpoints
/// ([`crate::plant::kinematics_check::pose_parallel`]); poses from the setpoints
/// rather than the simulated arms, so the virtual joints add no feedback
/// loop to the arms' motors.
#[derive(Clone)]
pub(crate) struct ParallelRig {
    /// Scene axis index of each target axis, J1 first.
    arm_axes: Vec<usize>,
    geometry: Geometry,
    mapping: ChainMapping,
    metres_per_unit: f64,
    /// Drive index of each target axis, J1 first.
    arm_drives: Vec<usize>,
    /// (URDF joint index, drive index) of each virtual joint.
    virtual_drives: Vec<(usize, usize)>,
    previous: Vec<f64>,
}

/// Adds a drive (and its initial position) for every virtual joint of each
/// parallel robot of the program; `axis_drives[i]` is scene axis `i`'s
/// drive.
///
/// # Errors
/// [`PlantError::Kinematics`] (at the `geometry` table) when a virtual joint
/// is not in the URDF, is already driven (by an axis or another system's
/// geometry) or the initial joints have no position.
pub(crate) fn parallel_rigs(
    scene: &Scene,
    model: &RobotModel,
    axis_drives: &[Option<usize>],
    drives: &mut Vec<JointDrive>,
    initial: &mut Vec<(String, f64)>,
) -> Result<Vec<ParallelRig>, PlantError> {
    let mut rigs = Vec::new();
    // (virtual joint, the coordinate system whose geometry drives it)
    let mut virtual_owners: Vec<(String, String)> = Vec::new();
    for (source, target) in transforms(scene) {
        let Some(c) = chain(scene, source, target)? else {
            continue;
        };
        if c.geometry.parallel_forearm_length().is_none() {
            continue;
        }
        let location = target.geometry.as_ref().map(|g| g.location).unwrap_or(target.location);
        let fail = |message: String| PlantError::Kinematics {
            scene: scene.path.clone(),
            line: location.line,
            column: location.column,
            message: format!("coordinate system '{}': {message}", target.name),
        };
        let start: Vec<f64> = c
            .axes
            .iter()
            .map(|&(i, si)| scene.axes[i].initial_position * si)
            .collect();
        let pose = pose_parallel(model, &c.geometry, &c.mapping, &start, c.metres_per_unit)
            .map_err(|e| fail(format!("initial joints: {e}")))?;
        let names = c
            .mapping
            .platform_joints
            .iter()
            .chain(c.mapping.forearm_joints.iter().flatten());
        let mut virtual_drives = Vec::new();
        for name in names {
            let joint = model
                .joint_by_name(name)
                .ok_or_else(|| fail(format!("virtual joint '{name}' is not in the URDF")))?;
            if let Some(by) = drives.iter().position(|d| &d.joint == name) {
                let owner = match axis_drives.iter().position(|&d| d == Some(by)) {
                    Some(i) => format!("axis '{}'", scene.axes[i].name),
                    None => virtual_owners
                        .iter()
                        .find(|(joint, _)| joint == name)
                        .map_or_else(String::new, |(_, system)| format!("coordinate system '{system}'")),
                };
                return Err(fail(format!("virtual joint '{name}' is already driven by {owner}")));
            }
            virtual_owners.push((name.clone(), target.name.clone()));
            drives.push(JointDrive {
                joint: name.clone(),
                stiffness: VIRTUAL_GAINS.0,
                damping: VIRTUAL_GAINS.1,
                max_force: None,
                servo: None,
            });
            initial.retain(|(n, _)| n != name);
            initial.push((name.clone(), pose[joint.0]));
            virtual_drives.push((joint.0, drives.len() - 1));
        }
        let arm_drives = c
            .axes
            .iter()
            .map(|&(i, _)| axis_drives[i].ok_or_else(|| fail("a target axis has no joint".into())))
            .collect::<Result<_, _>>()?;
        rigs.push(ParallelRig {
            arm_axes: c.axes.iter().map(|&(i, _)| i).collect(),
            previous: virtual_drives.iter().map(|&(j, _)| pose[j]).collect(),
            geometry: c.geometry,
            mapping: c.mapping,
            metres_per_unit: c.metres_per_unit,
            arm_drives,
            virtual_drives,
        });
    }
    Ok(rigs)
}

impl ParallelRig {
    /// Sets the virtual joints' setpoints from the arm joints' setpoints
    /// (`setpoint(drive)`, URDF units; velocity: the change since the last
    /// call over `step_s`). Joints with no valid pose keep their setpoints.
    pub(crate) fn drive(
        &mut self,
        model: &RobotModel,
        sim: &mut Dynamics,
        step_s: f64,
        setpoint: impl Fn(usize) -> Option<f64>,
    ) {
        let Some(arms) = self
            .arm_drives
            .iter()
            .map(|&d| setpoint(d))
            .collect::<Option<Vec<f64>>>()
        else {
            return;
        };
        let Some(pose) = self.virtual_pose(model, &arms, &self.previous) else {
            return;
        };
        for (k, &(_, drive)) in self.virtual_drives.iter().enumerate() {
            let q = pose[k];
            sim.set_setpoint(drive, q, (q - self.previous[k]) / step_s);
            self.previous[k] = q;
        }
    }

    /// Scene axis index of each target axis, J1 first.
    pub(crate) fn arm_axes(&self) -> &[usize] {
        &self.arm_axes
    }

    /// URDF joint index of each virtual joint.
    pub(crate) fn virtual_joints(&self) -> Vec<usize> {
        self.virtual_drives.iter().map(|&(j, _)| j).collect()
    }

    /// The virtual joints' last setpoints (in [`Self::virtual_joints`] order).
    pub(crate) fn previous(&self) -> &[f64] {
        &self.previous
    }

    /// The virtual joints' positions (in [`Self::virtual_joints`] order)
    /// for arm joints at `arms` (URDF units, J1 first), continuous with
    /// `near`; `None` where the arms have no pose.
    pub(crate) fn virtual_pose(&self, model: &RobotModel, arms: &[f64], near: &[f64]) -> Option<Vec<f64>> {
        let mut pose = pose_parallel(model, &self.geometry, &self.mapping, arms, self.metres_per_unit).ok()?;
        // A forearm direction has two (yaw, pitch) pairs, (y, p) and
        // (y + π, π − p): keep the one continuous with `near`, unwrapped,
        // so no virtual joint ever jumps.
        let wrap = |a: f64| a - TAU * (a / TAU).round();
        let platform = self.mapping.platform_joints.len();
        for k in (platform..self.virtual_drives.len()).step_by(2) {
            let (yaw, pitch) = (self.virtual_drives[k].0, self.virtual_drives[k + 1].0);
            let (last_yaw, last_pitch) = (near[k], near[k + 1]);
            let distance = |y: f64, p: f64| wrap(y - last_yaw).abs() + wrap(p - last_pitch).abs();
            let (y, p) = (pose[yaw], pose[pitch]);
            let (y, p) = if distance(y + PI, PI - p) < distance(y, p) {
                (y + PI, PI - p)
            } else {
                (y, p)
            };
            pose[yaw] = last_yaw + wrap(y - last_yaw);
            pose[pitch] = last_pitch + wrap(p - last_pitch);
        }
        Some(self.virtual_drives.iter().map(|&(j, _)| pose[j]).collect())
    }
}
