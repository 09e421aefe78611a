//! Building a [`RobotSim`](super::RobotSim)'s world from a [`RobotModel`]:
//! the options and drives checked, one rigid body per link that moves
//! (carrying the links fixed to it), the multibody joints between them,
//! and each link's mass and colliders.

use nalgebra::{Isometry3, UnitQuaternion, Vector3};
use rapier3d_f64::prelude::{
    ColliderBuilder, GenericJoint, GenericJointBuilder, Group, InteractionGroups, InteractionTestMode, JointAxesMask,
    JointAxis, MassProperties, MultibodyJointHandle, PhysicsWorld, RigidBodyBuilder, RigidBodyHandle,
};

use super::config::{DEFAULT_INERTIA_RADIUS_M, JointDrive, PhysicsError, PhysicsOptions, ROBOT_GROUP};
use crate::plant::convert::{matrix_to_rapier, pose_to_rapier, vector_to_rapier};
use crate::plant::urdf::{Geometry, Joint, JointKind, RobotModel};

/// The index of the movable joint called `name`.
pub(super) fn movable_joint(model: &RobotModel, name: &str) -> Result<usize, PhysicsError> {
    let index = model.joint_by_name(name).ok_or_else(|| PhysicsError::UnknownJoint {
        joint: name.to_string(),
    })?;
    if model.joint(index).kind.is_movable() {
        Ok(index.0)
    } else {
        Err(PhysicsError::FixedJoint {
            joint: name.to_string(),
        })
    }
}

/// Every joint's initial coordinate (0 where none is given).
pub(crate) fn initial_positions(model: &RobotModel, initial: &[(String, f64)]) -> Result<Vec<f64>, PhysicsError> {
    let mut q0 = vec![0.0; model.joints.len()];
    for (name, position) in initial {
        let j = movable_joint(model, name)?;
        if !position.is_finite() {
            return Err(PhysicsError::InvalidInitialPosition {
                joint: name.clone(),
                position: *position,
            });
        }
        q0[j] = *position;
    }
    Ok(q0)
}

/// Per joint, the index of the drive that drives it, after checking each
/// drive's gains and that no joint has two.
pub(crate) fn driven_joints(model: &RobotModel, drives: &[JointDrive]) -> Result<Vec<Option<usize>>, PhysicsError> {
    let mut driven = vec![None; model.joints.len()];
    for (d, drive) in drives.iter().enumerate() {
        let j = movable_joint(model, &drive.joint)?;
        let gains_ok = drive.stiffness.is_finite()
            && drive.stiffness >= 0.0
            && drive.damping.is_finite()
            && drive.damping >= 0.0
            && drive.max_force.is_none_or(|f| f > 0.0);
        if !gains_ok {
            return Err(PhysicsError::InvalidDrive {
                joint: drive.joint.clone(),
                stiffness: drive.stiffness,
                damping: drive.damping,
                max_force: drive.max_force,
            });
        }
        if driven[j].replace(d).is_some() {
            return Err(PhysicsError::DuplicateDrive {
                joint: drive.joint.clone(),
            });
        }
    }
    Ok(driven)
}

/// Where a link is simulated: a rigid body, and the link's pose on it when
/// the body is an ancestor's (`None`: the body is the link's own).
#[derive(Debug, Clone, Copy)]
pub(super) struct LinkFrame {
    pub(super) body: RigidBodyHandle,
    pub(super) body_from_link: Option<rapier3d_f64::math::Pose>,
}

/// Per link: the link whose body carries it and the link's pose in that
/// link's frame. A link below a fixed joint is carried by its parent's
/// carrier (a chain of fixed joints ends at the first link that moves, or
/// the root); every other link carries itself.
///
/// Merging the fixed links, as URDF simulators commonly do, keeps rigidly
/// attached tools, flanges and mounting plates out of the multibody: they
/// add no degree of freedom, but every link costs rapier its share of the
/// mass-matrix update each substep (`heavy_arm`: 8 links become 6).
pub(super) fn link_carriers(model: &RobotModel) -> Vec<(usize, Option<Isometry3<f64>>)> {
    let mut carrier: Vec<(usize, Option<Isometry3<f64>>)> = (0..model.links.len()).map(|l| (l, None)).collect();
    for &j in model.topological_joints() {
        let joint = model.joint(j);
        if joint.kind.is_movable() {
            continue;
        }
        let (host, host_from_parent) = carrier[joint.parent.0];
        let parent_from_child = joint.parent_from_joint * joint.joint_from_child(0.0);
        let host_from_child = host_from_parent.map_or(parent_from_child, |p| p * parent_from_child);
        carrier[joint.child.0] = (host, Some(host_from_child));
    }
    carrier
}

/// One rigid body per link that moves (the root fixed) at its initial
/// pose, carrying its own colliders and mass and those of the links fixed
/// to it ([`link_carriers`]); returns every link's frame in link order.
pub(super) fn insert_links(
    world: &mut PhysicsWorld,
    model: &RobotModel,
    q0: &[f64],
    options: &PhysicsOptions,
    posed: &[bool],
) -> Result<Vec<LinkFrame>, PhysicsError> {
    let world_from_link = model.world_from_link(q0);
    let groups = InteractionGroups::new(
        ROBOT_GROUP,
        Group::ALL.difference(ROBOT_GROUP),
        InteractionTestMode::And,
    );
    let carriers = link_carriers(model);
    // A carrier's mass: its own, plus its fixed links' in its frame.
    let mut mass: Vec<MassProperties> = model.links.iter().map(|link| mass_properties(link, options)).collect();
    for (l, &(host, host_from_link)) in carriers.iter().enumerate() {
        if let Some(offset) = host_from_link {
            let carried = mass[l].transform_by(&pose_to_rapier(&offset));
            mass[host] += carried;
        }
    }
    let mut bodies: Vec<Option<RigidBodyHandle>> = vec![None; model.links.len()];
    for (l, &(host, _)) in carriers.iter().enumerate() {
        if host != l {
            continue;
        }
        let builder = if l == model.root.0 {
            RigidBodyBuilder::fixed()
        } else if posed[l] {
            RigidBodyBuilder::kinematic_position_based()
        } else {
            RigidBodyBuilder::dynamic()
        };
        let body = builder
            .pose(pose_to_rapier(&world_from_link[l]))
            .additional_mass_properties(mass[l])
            .can_sleep(false)
            .build();
        bodies[l] = Some(world.bodies.insert(body));
    }
    let mut frames = Vec::with_capacity(model.links.len());
    for (link, &(host, host_from_link)) in model.links.iter().zip(&carriers) {
        let Some(handle) = bodies[host] else {
            unreachable!("every carrier has a body");
        };
        for collision in &link.collisions {
            let body_from_collision = host_from_link.map_or(collision.link_from_collision, |offset| {
                offset * collision.link_from_collision
            });
            let Some(collider) = collider_builder(&collision.geometry, &body_from_collision, &link.name)? else {
                continue;
            };
            world.colliders.insert_with_parent(
                collider.density(0.0).collision_groups(groups).build(),
                handle,
                &mut world.bodies,
            );
        }
        frames.push(LinkFrame {
            body: handle,
            body_from_link: host_from_link.map(|offset| pose_to_rapier(&offset)),
        });
    }
    Ok(frames)
}

/// The URDF tree as one multibody, joints inserted parent first; returns
/// each joint's handle by joint index.
pub(super) fn insert_joints(
    world: &mut PhysicsWorld,
    model: &RobotModel,
    links: &[LinkFrame],
    posed: &[bool],
) -> Result<Vec<Option<MultibodyJointHandle>>, PhysicsError> {
    let mut joint_handles = vec![None; model.joints.len()];
    for &index in model.topological_joints() {
        let joint = model.joint(index);
        if posed[joint.child.0] || links[joint.child.0].body_from_link.is_some() {
            continue;
        }
        let handle = world
            .multibody_joints
            .insert(
                links[joint.parent.0].body,
                links[joint.child.0].body,
                rapier_joint(joint, links[joint.parent.0].body_from_link),
                true,
            )
            .ok_or_else(|| PhysicsError::Multibody {
                joint: joint.name.clone(),
            })?;
        joint_handles[index.0] = Some(handle);
    }
    Ok(joint_handles)
}

/// Per link: whether it is posed (below a joint of `posed_joints`).
pub(super) fn posed_links(model: &RobotModel, posed_joints: &[String]) -> Result<Vec<bool>, PhysicsError> {
    let mut roots = vec![false; model.joints.len()];
    for name in posed_joints {
        roots[movable_joint(model, name)?] = true;
    }
    let mut posed = vec![false; model.links.len()];
    for &j in model.topological_joints() {
        let joint = model.joint(j);
        posed[joint.child.0] = roots[j.0] || posed[joint.parent.0];
    }
    Ok(posed)
}

pub(super) fn validate_options(options: &PhysicsOptions) -> Result<(), PhysicsError> {
    let bad = |option| Err(PhysicsError::InvalidOption { option });
    if !(options.step_s.is_finite() && options.step_s > 0.0) {
        return bad("step_s");
    }
    if !options.gravity_mps2.iter().all(|g| g.is_finite()) {
        return bad("gravity_mps2");
    }
    if !(options.default_link_mass_kg.is_finite() && options.default_link_mass_kg > 0.0) {
        return bad("default_link_mass_kg");
    }
    if options.substeps == 0 {
        return bad("substeps");
    }
    Ok(())
}

/// The rapier axis carrying a joint kind's one degree of freedom: the joint
/// frames are built so that it is always the local X axis.
pub(super) fn dof_axis(kind: JointKind) -> JointAxis {
    match kind {
        JointKind::Prismatic => JointAxis::LinX,
        _ => JointAxis::AngX,
    }
}

/// The multibody joint for a URDF joint, between its parent's body
/// (`body_from_parent`: the parent link's pose on it when the parent is
/// merged into an ancestor's body) and its child's. rapier moves
/// along/about the local X axis, so both joint frames are turned to put X
/// on the URDF axis: `parent_from_child(q) = parent_from_joint · R ·
/// motion_x(q) · R⁻¹ = parent_from_joint · motion_axis(q)` with
/// `R·x̂ = axis`.
pub(super) fn rapier_joint(joint: &Joint, body_from_parent: Option<rapier3d_f64::math::Pose>) -> GenericJoint {
    let x_to_axis = UnitQuaternion::rotation_between(&Vector3::x(), &joint.axis)
        .unwrap_or_else(|| UnitQuaternion::from_axis_angle(&Vector3::z_axis(), std::f64::consts::PI));
    let joint_from_dof = Isometry3::from_parts(nalgebra::Translation3::identity(), x_to_axis);
    let locked = match joint.kind {
        JointKind::Revolute | JointKind::Continuous => JointAxesMask::LOCKED_REVOLUTE_AXES,
        JointKind::Prismatic => JointAxesMask::LOCKED_PRISMATIC_AXES,
        JointKind::Fixed => JointAxesMask::LOCKED_FIXED_AXES,
    };
    let parent_from_dof = pose_to_rapier(&(joint.parent_from_joint * joint_from_dof));
    let mut data = GenericJointBuilder::new(locked)
        .local_frame1(body_from_parent.map_or(parent_from_dof, |offset| offset * parent_from_dof))
        .local_frame2(pose_to_rapier(&joint_from_dof))
        .build();
    if let Some(limits) = joint.limits
        && limits.lower < limits.upper
    {
        data.set_limits(dof_axis(joint.kind), [limits.lower, limits.upper]);
    }
    data
}

pub(super) fn mass_properties(link: &crate::plant::urdf::Link, options: &PhysicsOptions) -> MassProperties {
    match &link.inertial {
        Some(inertial) => {
            let rotation = inertial.link_from_inertial.rotation.to_rotation_matrix();
            let inertia_in_link = rotation.matrix() * inertial.inertia_kgm2 * rotation.matrix().transpose();
            MassProperties::with_inertia_matrix(
                vector_to_rapier(&inertial.link_from_inertial.translation.vector),
                inertial.mass_kg,
                matrix_to_rapier(&inertia_in_link),
            )
        }
        None => {
            let mass = options.default_link_mass_kg;
            let inertia = 0.4 * mass * DEFAULT_INERTIA_RADIUS_M * DEFAULT_INERTIA_RADIUS_M;
            MassProperties::new(
                vector_to_rapier(&Vector3::zeros()),
                mass,
                vector_to_rapier(&Vector3::repeat(inertia)),
            )
        }
    }
}

/// A massless collider for one `<collision>` shape, posed in the link frame;
/// `None` for shapes with no volume (zero size).
pub(super) fn collider_builder(
    geometry: &Geometry,
    link_from_collision: &Isometry3<f64>,
    link: &str,
) -> Result<Option<ColliderBuilder>, PhysicsError> {
    let mut link_from_shape = *link_from_collision;
    let builder = match geometry {
        Geometry::Box { size } => {
            if size.iter().any(|s| *s <= 0.0) {
                return Ok(None);
            }
            ColliderBuilder::cuboid(size[0] / 2.0, size[1] / 2.0, size[2] / 2.0)
        }
        Geometry::Cylinder { radius, length } => {
            if *radius <= 0.0 || *length <= 0.0 {
                return Ok(None);
            }
            // URDF cylinders run along Z, rapier's along Y: turn Y onto Z.
            link_from_shape *= UnitQuaternion::from_axis_angle(&Vector3::x_axis(), std::f64::consts::FRAC_PI_2);
            ColliderBuilder::cylinder(length / 2.0, *radius)
        }
        Geometry::Sphere { radius } => {
            if *radius <= 0.0 {
                return Ok(None);
            }
            ColliderBuilder::ball(*radius)
        }
        Geometry::Mesh { scale, mesh, .. } => {
            let points: Vec<_> = mesh
                .positions
                .iter()
                .map(|p| {
                    vector_to_rapier(&Vector3::new(
                        f64::from(p[0]) * scale[0],
                        f64::from(p[1]) * scale[1],
                        f64::from(p[2]) * scale[2],
                    ))
                })
                .collect();
            ColliderBuilder::convex_hull(&points)
                .ok_or_else(|| PhysicsError::DegenerateCollisionMesh { link: link.to_string() })?
        }
        // Geometry is non_exhaustive; future shapes get no collider until handled here.
        #[allow(unreachable_patterns)]
        _ => return Ok(None),
    };
    Ok(Some(builder.position(pose_to_rapier(&link_from_shape))))
}
