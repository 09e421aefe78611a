//! Triangle meshes shared by the URDF loader, the renderer and the Rerun logger.
//!
//! Coordinates are in metres, in the frame of whatever owns the mesh (a URDF
//! link's visual origin, an obstacle). URDF is Z-up; so is every mesh here.

/// An indexed triangle mesh with per-vertex normals (counter-clockwise front faces).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TriMesh {
    /// Vertex positions in metres.
    pub positions: Vec<[f32; 3]>,
    /// Unit vertex normals, one per position.
    pub normals: Vec<[f32; 3]>,
    /// Triangle list, three indices per triangle.
    pub indices: Vec<u32>,
}
