//! Why a frame cannot be rendered: camera, mesh and readback problems.

/// Why a camera cannot form an image.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum CameraProblem {
    /// Eye, target or up contains NaN or infinity.
    #[error("eye, target or up is not finite")]
    NonFinite,
    /// Eye and target coincide, so there is no viewing direction.
    #[error("eye and target coincide")]
    EyeOnTarget,
    /// The up vector is zero or parallel to the viewing direction.
    #[error("up is zero or parallel to the viewing direction")]
    UpAlongView,
}

/// Why an uploaded mesh cannot be drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum MeshProblem {
    /// `normals` and `positions` differ in length.
    #[error("{normals} normals for {positions} positions")]
    NormalCount {
        /// Number of positions.
        positions: usize,
        /// Number of normals.
        normals: usize,
    },
    /// The index count is not a multiple of three.
    #[error("{indices} indices do not form whole triangles")]
    PartialTriangle {
        /// Number of indices.
        indices: usize,
    },
    /// A triangle refers to a vertex that does not exist.
    #[error("triangle {triangle} uses vertex {index} of {vertices}")]
    IndexOutOfRange {
        /// Triangle number (index position / 3).
        triangle: usize,
        /// The offending vertex index.
        index: u32,
        /// Number of vertices.
        vertices: usize,
    },
    /// A position or normal contains NaN or infinity.
    #[error("vertex {vertex} is not finite")]
    NonFinite {
        /// Vertex number.
        vertex: usize,
    },
    /// The mesh needs a bigger GPU buffer than the adapter allows.
    #[error("mesh needs {bytes} bytes, the adapter allows {max_bytes}")]
    TooLarge {
        /// Bytes needed by the larger of the vertex and index buffers.
        bytes: u64,
        /// The adapter's maximum buffer size.
        max_bytes: u64,
    },
}

/// Where reading a frame back from the GPU failed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum ReadbackStage {
    /// Waiting for the GPU to finish failed (device lost or timed out).
    Wait,
    /// Mapping the readback buffer failed.
    Map,
    /// The buffer was not mapped after the wait returned.
    NotCompleted,
    /// The mapped bytes could not be read or did not fit the image.
    Copy,
}

/// Errors of the renderer.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum RenderError {
    /// No Vulkan adapter exists (no GPU driver and no lavapipe); see [`super::NO_ADAPTER_HINT`].
    #[error("no Vulkan adapter found")]
    NoAdapter,
    /// The adapter exists but refused to open a device.
    #[error("the Vulkan adapter could not open a device")]
    RequestDevice {
        /// wgpu's reason.
        #[source]
        source: wgpu::RequestDeviceError,
    },
    /// The camera's image has no pixels.
    #[error("image size {width_px}x{height_px} px is empty")]
    EmptyImage {
        /// Requested width (px).
        width_px: u32,
        /// Requested height (px).
        height_px: u32,
    },
    /// The camera's image exceeds the adapter's texture or buffer limits.
    #[error(
        "image size {width_px}x{height_px} px exceeds the adapter's limit of {max_side_px} px per side or {max_bytes} bytes"
    )]
    ImageTooLarge {
        /// Requested width (px).
        width_px: u32,
        /// Requested height (px).
        height_px: u32,
        /// Largest texture side the adapter allows (px).
        max_side_px: u32,
        /// Largest buffer the adapter allows (bytes).
        max_bytes: u64,
    },
    /// The field of view is not in (0, 180) degrees.
    #[error("field of view {fov_y_deg} deg is not in (0, 180)")]
    FieldOfView {
        /// The requested vertical field of view (degrees).
        fov_y_deg: f32,
    },
    /// The camera's eye, target and up do not define a view.
    #[error("camera cannot form an image")]
    Camera {
        /// What is wrong with it.
        #[source]
        problem: CameraProblem,
    },
    /// A draw item refers to a mesh this renderer did not upload.
    #[error("draw item {item} refers to unknown mesh {mesh}")]
    UnknownMesh {
        /// Position of the item in the `items` slice.
        item: usize,
        /// The mesh handle's index.
        mesh: u32,
    },
    /// A draw item refers to a mesh that failed validation at upload.
    #[error("draw item {item} uses invalid mesh {mesh}")]
    InvalidMesh {
        /// Position of the item in the `items` slice.
        item: usize,
        /// The mesh handle's index.
        mesh: u32,
        /// What is wrong with the mesh.
        #[source]
        problem: MeshProblem,
    },
    /// A draw item's transform or colour contains NaN or infinity.
    #[error("draw item {item} has a non-finite transform or colour")]
    NonFiniteItem {
        /// Position of the item in the `items` slice.
        item: usize,
    },
    /// A line strip's point or colour contains NaN or infinity.
    #[error("line strip {strip} has a non-finite point or colour (point {point})")]
    NonFiniteLine {
        /// Position of the strip in the `lines` slice.
        strip: usize,
        /// First offending point, or the point count when the colour is at fault.
        point: usize,
    },
    /// The GPU device was lost (driver reset or crash); create a new renderer.
    #[error("the GPU device was lost")]
    DeviceLost,
    /// wgpu reported a validation, out-of-memory or internal error.
    #[error("the GPU reported an error")]
    Gpu {
        /// wgpu's error.
        #[source]
        source: wgpu::Error,
    },
    /// Copying the finished frame back to memory failed.
    #[error("reading the frame back failed at stage {stage:?}")]
    Readback {
        /// Which step failed.
        stage: ReadbackStage,
    },
}
