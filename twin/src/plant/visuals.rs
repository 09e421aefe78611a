//! Scene geometry for rendering: URDF visuals and obstacles as triangle
//! meshes with their poses, built once; the link poses change per frame.

use crate::plant::mesh::TriMesh;
use crate::plant::stl::{StlError, load_stl};
use crate::plant::urdf::{Geometry, RobotModel};
use crate::scene::{Scene, Shape};
use nalgebra::{Isometry3, Matrix4, Quaternion, Translation3, UnitQuaternion};

/// Default colour of a URDF visual without material (light grey).
pub const DEFAULT_VISUAL_RGBA: [f32; 4] = [0.7, 0.7, 0.72, 1.0];

/// Tessellation of cylinders and spheres.
const SEGMENTS: u32 = 48;

/// One drawable piece: a mesh, what it hangs on, its fixed offset, colour.
#[derive(Debug, Clone)]
pub struct Visual {
    /// The triangles (already scaled for URDF mesh scale).
    pub mesh: TriMesh,
    /// The link it belongs to (`None`: fixed in the world).
    pub link: Option<usize>,
    /// Pose of the mesh in the link frame (or the world for obstacles).
    pub parent_from_mesh: Isometry3<f64>,
    /// sRGB colour and alpha.
    pub color_rgba: [f32; 4],
    /// Name for logs (link, obstacle or conveyor name).
    pub name: String,
    /// What a world-fixed piece is, for its recording path
    /// (`obstacles`, `conveyors`; links: empty).
    pub group: &'static str,
}

fn geometry_mesh(geometry: &Geometry) -> TriMesh {
    match geometry {
        Geometry::Box { size } => TriMesh::cuboid([size[0] as f32, size[1] as f32, size[2] as f32]),
        Geometry::Cylinder { radius, length } => TriMesh::cylinder(*radius as f32, *length as f32, SEGMENTS),
        Geometry::Sphere { radius } => TriMesh::sphere(*radius as f32, SEGMENTS / 2, SEGMENTS),
        Geometry::Mesh { scale, mesh, .. } => scaled(mesh, *scale),
    }
}

/// An obstacle's mesh file cannot be loaded.
#[derive(Debug, thiserror::Error)]
#[error("obstacle {obstacle}: {source}")]
pub struct ObstacleMeshError {
    /// Index of the obstacle in the scene's `[[obstacles]]`.
    pub obstacle: usize,
    /// Why the STL file failed (it names the file).
    #[source]
    pub source: StlError,
}

/// `mesh` scaled per axis (URDF mesh `scale`, obstacle `scale`).
fn scaled(mesh: &TriMesh, scale: [f64; 3]) -> TriMesh {
    let [x, y, z] = scale.map(|v| v as f32);
    mesh.transformed(&[
        [x, 0.0, 0.0, 0.0],
        [0.0, y, 0.0, 0.0],
        [0.0, 0.0, z, 0.0],
        [0.0, 0.0, 0.0, 1.0],
    ])
}

/// Every visual of the robot and every obstacle of the scene.
///
/// Obstacle meshes are loaded with the STL loader (the only mesh format
/// the twin reads); a mesh that fails to load is an error, never dropped.
///
/// # Errors
/// [`ObstacleMeshError`] when an obstacle's mesh cannot be loaded.
pub fn scene_visuals(model: &RobotModel, scene: &Scene) -> Result<Vec<Visual>, ObstacleMeshError> {
    let mut visuals = Vec::new();
    for (i, link) in model.links.iter().enumerate() {
        for visual in &link.visuals {
            visuals.push(Visual {
                mesh: geometry_mesh(&visual.geometry),
                link: Some(i),
                parent_from_mesh: visual.link_from_visual,
                color_rgba: visual.color_rgba.unwrap_or(DEFAULT_VISUAL_RGBA),
                name: link.name.clone(),
                group: "",
            });
        }
    }
    for (index, o) in scene.obstacles.iter().enumerate() {
        let mesh = shape_mesh(&o.shape).map_err(|source| ObstacleMeshError {
            obstacle: index,
            source,
        })?;
        visuals.push(Visual {
            mesh,
            link: None,
            parent_from_mesh: placed(o.position_m, o.rpy_deg),
            color_rgba: o.color.map(|c| c as f32),
            name: o.name.clone(),
            group: "obstacles",
        });
    }
    for c in &scene.cell.conveyors {
        visuals.push(Visual {
            mesh: shape_mesh(&Shape::Box { size_m: c.size_m }).unwrap_or_default(),
            link: None,
            parent_from_mesh: placed(c.position_m, c.rpy_deg),
            color_rgba: c.color.map(|x| x as f32),
            name: c.name.clone(),
            group: "conveyors",
        });
    }
    Ok(visuals)
}

/// A pose from a position (m) and roll, pitch, yaw (degrees).
fn placed(position_m: [f64; 3], rpy_deg: [f64; 3]) -> Isometry3<f64> {
    let [r, p, y] = rpy_deg.map(f64::to_radians);
    Isometry3::from_parts(
        Translation3::new(position_m[0], position_m[1], position_m[2]),
        UnitQuaternion::from_euler_angles(r, p, y),
    )
}

/// A scene shape's triangles (an STL file's, loaded and scaled).
///
/// # Errors
/// [`StlError`] when a mesh file cannot be loaded.
pub fn shape_mesh(shape: &Shape) -> Result<TriMesh, StlError> {
    Ok(match shape {
        Shape::Box { size_m } => TriMesh::cuboid([size_m[0] as f32, size_m[1] as f32, size_m[2] as f32]),
        Shape::Cylinder { radius_m, length_m } => TriMesh::cylinder(*radius_m as f32, *length_m as f32, SEGMENTS),
        Shape::Sphere { radius_m } => TriMesh::sphere(*radius_m as f32, SEGMENTS / 2, SEGMENTS),
        Shape::Mesh { path, scale } => scaled(&load_stl(path)?, *scale),
    })
}

/// `world_from_mesh` of a visual, given the link poses (translation, xyzw quaternion).
pub fn world_from_visual(visual: &Visual, links: &[([f64; 3], [f64; 4])]) -> Isometry3<f64> {
    match visual.link.and_then(|i| links.get(i)) {
        Some((t, q)) => {
            let world_from_link = Isometry3::from_parts(
                Translation3::new(t[0], t[1], t[2]),
                UnitQuaternion::from_quaternion(Quaternion::new(q[3], q[0], q[1], q[2])),
            );
            world_from_link * visual.parent_from_mesh
        }
        None => visual.parent_from_mesh,
    }
}

/// Column-major 4×4 matrix of an isometry, as the renderer takes it.
pub fn column_major(iso: &Isometry3<f64>) -> [[f32; 4]; 4] {
    let m: Matrix4<f64> = iso.to_homogeneous();
    let mut out = [[0.0f32; 4]; 4];
    for (c, col) in out.iter_mut().enumerate() {
        for (r, v) in col.iter_mut().enumerate() {
            *v = m[(r, c)] as f32;
        }
    }
    out
}
