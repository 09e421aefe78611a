//! Building the collision model: shapes from URDF geometry and the scene,
//! the robot's bodies, the checked pairs, and each body's reach for the
//! sweep's bound.

use super::bodies::{Body, CollisionModelError, RobotBody};
use crate::plant::convert::pose_to_rapier;
use crate::plant::stl::load_stl;
use crate::plant::urdf::{Geometry, JointKind, RobotModel};
use crate::scene::{CollisionSettings, MeshApproximation, Obstacle, Shape};
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use rapier3d_f64::math::{Pose, Vector};
use rapier3d_f64::parry::shape::SharedShape;

pub(super) fn vec3(v: Vector) -> [f64; 3] {
    [v.x, v.y, v.z]
}

pub(crate) fn shape_of(
    geometry: &Geometry,
    meshes: MeshApproximation,
    body: &str,
) -> Result<Option<(Isometry3<f64>, SharedShape)>, CollisionModelError> {
    let id = Isometry3::identity();
    Ok(match geometry {
        Geometry::Box { size } => (size.iter().all(|s| *s > 0.0))
            .then(|| (id, SharedShape::cuboid(size[0] / 2.0, size[1] / 2.0, size[2] / 2.0))),
        Geometry::Cylinder { radius, length } => (*radius > 0.0 && *length > 0.0).then(|| {
            // URDF cylinders run along Z, parry's along Y: turn Y onto Z.
            let turn = UnitQuaternion::from_axis_angle(&Vector3::x_axis(), std::f64::consts::FRAC_PI_2);
            (
                Isometry3::from_parts(Translation3::identity(), turn),
                SharedShape::cylinder(length / 2.0, *radius),
            )
        }),
        Geometry::Sphere { radius } => (*radius > 0.0).then(|| (id, SharedShape::ball(*radius))),
        Geometry::Mesh { scale, mesh, .. } => Some((id, mesh_shape(mesh, *scale, meshes, body)?)),
        #[allow(unreachable_patterns)]
        _ => None,
    })
}

/// The most triangles a mesh may have for parry's VHACD convex
/// decomposition (`meshes = "convex_decomposition"`), whose time grows
/// with them: a random soup of 250, 500, 1,000 and 2,000 triangles took
/// 1.8, 2.7, 4.5 and 8.4 s (dev build, 2026-11-28); 20,000 took minutes.
/// A mesh with more is refused, naming `convex_hull` as the way out.
pub const MAX_DECOMPOSITION_TRIANGLES: usize = 1_000;

/// The most triangles all the meshes of a scene may have together for
/// `meshes = "convex_decomposition"` (links, tool and obstacles): about
/// 15 s of decomposition in the dev build; the work is not shared between
/// meshes, so six meshes of 1,000 took 34 s.
pub const MAX_DECOMPOSITION_TRIANGLES_TOTAL: usize = 3_000;

/// Refuses a scene whose meshes to decompose have more triangles together
/// than [`MAX_DECOMPOSITION_TRIANGLES_TOTAL`], before any is decomposed.
pub(super) fn decomposition_budget(
    model: &RobotModel,
    obstacles: &[Obstacle],
    settings: &CollisionSettings,
) -> Result<(), CollisionModelError> {
    if settings.meshes != MeshApproximation::ConvexDecomposition {
        return Ok(());
    }
    let mut triangles: usize = model
        .links
        .iter()
        .flat_map(|l| &l.collisions)
        .map(|c| match &c.geometry {
            Geometry::Mesh { mesh, .. } => mesh.indices.len() / 3,
            _ => 0,
        })
        .sum();
    let scene_shapes = obstacles
        .iter()
        .map(|o| (&o.shape, o.name.as_str()))
        .chain(settings.tool.iter().map(|t| (&t.shape, t.name.as_str())));
    for (shape, name) in scene_shapes {
        if let Shape::Mesh { path, .. } = shape {
            let mesh = load_stl(path).map_err(|source| CollisionModelError::Mesh {
                body: name.to_string(),
                source,
            })?;
            triangles += mesh.indices.len() / 3;
        }
    }
    if triangles > MAX_DECOMPOSITION_TRIANGLES_TOTAL {
        return Err(CollisionModelError::DecompositionBudget {
            triangles,
            max: MAX_DECOMPOSITION_TRIANGLES_TOTAL,
        });
    }
    Ok(())
}

pub(super) fn mesh_shape(
    mesh: &crate::plant::mesh::TriMesh,
    scale: [f64; 3],
    meshes: MeshApproximation,
    body: &str,
) -> Result<SharedShape, CollisionModelError> {
    let points: Vec<Vector> = mesh
        .positions
        .iter()
        .map(|p| {
            Vector::new(
                f64::from(p[0]) * scale[0],
                f64::from(p[1]) * scale[1],
                f64::from(p[2]) * scale[2],
            )
        })
        .collect();
    let max_m = crate::scene::MAX_LENGTH_M;
    let extent_m = mesh.extent_m(scale);
    if extent_m > max_m {
        return Err(CollisionModelError::MeshTooLarge {
            body: body.to_string(),
            extent_m,
            max_m,
        });
    }
    let degenerate = || CollisionModelError::DegenerateMesh { body: body.to_string() };
    // A mesh without a 3-D hull has nothing to decompose either (and parry
    // refuses an empty decomposition).
    let hull = SharedShape::convex_hull(&points).ok_or_else(degenerate)?;
    match meshes {
        MeshApproximation::ConvexDecomposition if mesh.indices.len() >= 3 => {
            let triangles = mesh.indices.len() / 3;
            if triangles > MAX_DECOMPOSITION_TRIANGLES {
                return Err(CollisionModelError::DecompositionTooLarge {
                    body: body.to_string(),
                    triangles,
                    max: MAX_DECOMPOSITION_TRIANGLES,
                });
            }
            let triangles: Vec<[u32; 3]> = mesh.indices.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect();
            Ok(SharedShape::convex_decomposition(&points, &triangles))
        }
        _ => Ok(hull),
    }
}

pub(crate) fn scene_shape(shape: &Shape, body: &str) -> Result<Geometry, CollisionModelError> {
    Ok(match shape {
        Shape::Box { size_m } => Geometry::Box { size: *size_m },
        Shape::Cylinder { radius_m, length_m } => Geometry::Cylinder {
            radius: *radius_m,
            length: *length_m,
        },
        Shape::Sphere { radius_m } => Geometry::Sphere { radius: *radius_m },
        Shape::Mesh { path, scale } => Geometry::Mesh {
            path: path.clone(),
            scale: *scale,
            mesh: load_stl(path).map_err(|source| CollisionModelError::Mesh {
                body: body.to_string(),
                source,
            })?,
        },
        #[allow(unreachable_patterns)]
        _ => return Err(CollisionModelError::DegenerateMesh { body: body.to_string() }),
    })
}

/// The scene's obstacles as placed shapes, in scene order.
pub(super) fn obstacle_shapes(
    obstacles: &[Obstacle],
    settings: &CollisionSettings,
) -> Result<Vec<(Pose, SharedShape)>, CollisionModelError> {
    obstacles
        .iter()
        .map(|o| {
            let geometry = scene_shape(&o.shape, &o.name)?;
            let world_from_obstacle = pose_from_xyz_rpy_deg(o.position_m, o.rpy_deg);
            let (local, shape) = shape_of(&geometry, settings.meshes, &o.name)?
                .ok_or_else(|| CollisionModelError::DegenerateMesh { body: o.name.clone() })?;
            Ok((pose_to_rapier(&(world_from_obstacle * local)), shape))
        })
        .collect()
}

pub(crate) fn pose_from_xyz_rpy_deg(position_m: [f64; 3], rpy_deg: [f64; 3]) -> Isometry3<f64> {
    let [r, p, y] = rpy_deg.map(f64::to_radians);
    Isometry3::from_parts(
        Translation3::new(position_m[0], position_m[1], position_m[2]),
        UnitQuaternion::from_euler_angles(r, p, y),
    )
}

/// The robot's bodies: every link with collision shapes, in URDF order,
/// then the tool on its link.
pub(super) fn robot_bodies(
    model: &RobotModel,
    settings: &CollisionSettings,
) -> Result<Vec<RobotBody>, CollisionModelError> {
    let mut bodies = Vec::new();
    for (l, link) in model.links.iter().enumerate() {
        let mut shapes = Vec::new();
        for c in &link.collisions {
            if let Some((local, shape)) = shape_of(&c.geometry, settings.meshes, &link.name)? {
                shapes.push((pose_to_rapier(&(c.link_from_collision * local)), shape));
            }
        }
        if !shapes.is_empty() {
            bodies.push(RobotBody {
                name: link.name.clone(),
                link: l,
                shapes,
            });
        }
    }
    if let Some(tool) = &settings.tool {
        let link = model
            .link_by_name(&tool.link)
            .ok_or_else(|| CollisionModelError::UnknownToolLink {
                link: tool.link.clone(),
                line: tool.link_location.line,
                column: tool.link_location.column,
            })?;
        let geometry = scene_shape(&tool.shape, &tool.name)?;
        let link_from_tool = pose_from_xyz_rpy_deg(tool.position_m, tool.rpy_deg);
        if let Some((local, shape)) = shape_of(&geometry, settings.meshes, &tool.name)? {
            bodies.push(RobotBody {
                name: tool.name.clone(),
                link: link.0,
                shapes: vec![(pose_to_rapier(&(link_from_tool * local)), shape)],
            });
        }
    }
    Ok(bodies)
}

/// The scene's allowed pairs as sorted body pairs, found by name.
pub(super) fn allowed_pairs(
    bodies: &[RobotBody],
    obstacle_names: &[String],
    settings: &CollisionSettings,
) -> Result<Vec<[Body; 2]>, CollisionModelError> {
    let find = |name: &str| -> Option<Body> {
        bodies
            .iter()
            .position(|b| b.name == name)
            .map(Body::Robot)
            .or_else(|| obstacle_names.iter().position(|o| o == name).map(Body::Obstacle))
    };
    let mut allowed = Vec::new();
    for p in &settings.allowed_pairs {
        let mut pair = [Body::Robot(0); 2];
        for (slot, name) in pair.iter_mut().zip([&p.a, &p.b]) {
            *slot = find(name).ok_or_else(|| CollisionModelError::UnknownPairBody {
                name: name.clone(),
                line: p.location.line,
                column: p.location.column,
            })?;
        }
        pair.sort();
        allowed.push(pair);
    }
    Ok(allowed)
}

/// The robot body pairs checked against each other: not on the same or
/// adjacent rigid groups (the tool counts as its link) and not allowed.
pub(super) fn self_pairs(
    model: &RobotModel,
    bodies: &[RobotBody],
    is_allowed: impl Fn(Body, Body) -> bool,
) -> Vec<(usize, usize)> {
    let group = rigid_groups(model);
    let adjacent = |a: usize, b: usize| {
        let (ga, gb) = (group[a], group[b]);
        ga == gb
            || model.joints.iter().any(|j| {
                let (gp, gc) = (group[j.parent.0], group[j.child.0]);
                (gp, gc) == (ga, gb) || (gp, gc) == (gb, ga)
            })
    };
    let mut pairs = Vec::new();
    for a in 0..bodies.len() {
        for b in a + 1..bodies.len() {
            let (la, lb) = (bodies[a].link, bodies[b].link);
            if adjacent(la, lb) || is_allowed(Body::Robot(a), Body::Robot(b)) {
                continue;
            }
            pairs.push((a, b));
        }
    }
    pairs
}

/// Per URDF link, the index of its *rigid group*: the lowest link index
/// among the links joined to it through fixed joints only (a link with no
/// fixed joint is a group of its own). Links of one group never move
/// relative to each other.
pub(super) fn rigid_groups(model: &RobotModel) -> Vec<usize> {
    let mut group: Vec<usize> = (0..model.links.len()).collect();
    fn root(group: &mut [usize], mut l: usize) -> usize {
        while group[l] != l {
            group[l] = group[group[l]];
            l = group[l];
        }
        l
    }
    for j in &model.joints {
        if j.kind == JointKind::Fixed {
            let (a, b) = (root(&mut group, j.parent.0), root(&mut group, j.child.0));
            let (lo, hi) = (a.min(b), a.max(b));
            group[hi] = lo;
        }
    }
    (0..group.len()).map(|l| root(&mut group, l)).collect()
}

/// Upper bound of the distance from each joint's origin to any point of
/// `body` in any configuration (0 for joints not above the body; 1 for
/// prismatic joints, whose motion moves every point by exactly |Δq|).
pub(super) fn reach_of(model: &RobotModel, body: &RobotBody) -> Vec<f64> {
    let radius = body
        .shapes
        .iter()
        .map(|(p, s)| {
            let sphere = s.compute_local_bounding_sphere();
            (*p * sphere.center).length() + sphere.radius
        })
        .fold(0.0, f64::max);
    let mut reach = vec![0.0; model.joints.len()];
    // Walk up from the body's link: `below` bounds the distance from the
    // current joint's origin to the body's points.
    let mut below = radius;
    let mut link = body.link;
    while let Some(j) = model.links[link].parent_joint {
        let joint = &model.joints[j.0];
        reach[j.0] = match joint.kind {
            JointKind::Prismatic => 1.0,
            JointKind::Fixed => 0.0,
            _ => below,
        };
        let travel = match (joint.kind, joint.limits) {
            (JointKind::Prismatic, Some(l)) => l.lower.abs().max(l.upper.abs()),
            _ => 0.0,
        };
        below += joint.parent_from_joint.translation.vector.norm() + travel;
        link = joint.parent.0;
    }
    reach
}
