//! Headless renderer: draws meshes, tool-centre trails and a ground grid into
//! an offscreen image with wgpu on Vulkan (a GPU, or Mesa's software
//! rasteriser lavapipe where there is none).
//!
//! # Conventions
//! - **World frame**: right-handed, Z up, metres — the URDF convention, so
//!   meshes and link poses go in unchanged. The ground is the z = 0 plane.
//! - **Camera**: sits at [`Camera::eye_in_world`] and looks towards
//!   [`Camera::target_in_world`]; [`Camera::up_in_world`] (default +Z) points
//!   up on screen, so it must not be parallel to the viewing direction (use
//!   +Y as up for a camera straight above its target). Vertical field of view
//!   in degrees; the near plane is [`NEAR_PLANE_M`] and there is no far plane
//!   (reversed, infinite depth).
//! - **Transforms**: [`DrawItem::world_from_mesh`] is a column-major 4x4
//!   matrix (`m[column][row]`, translation in `m[3]`), may scale and mirror.
//! - **Colours**: sRGB-encoded RGBA in 0..1, as in CSS or image editors;
//!   lighting happens in linear light and the image comes back sRGB-encoded.
//! - **Image**: row 0 is the top of the picture; pixel (0, 0) is top-left.
//!
//! # Lighting
//! A key directional light from above and over the camera's left shoulder
//! ([`Camera::key_light_dir_in_world`]), a hemisphere ambient term (surfaces
//! facing up get more than those facing down) and a faint Blinn-Phong
//! highlight. The light follows the camera, so every view shows its top faces
//! bright, its left faces lit and its right faces in shade. No shadows.
//! Ground grid: thin lines every 0.1 m, heavier every 1 m, the world X axis
//! in red and Y in green, fading out with distance from the eye.
//!
//! # Determinism
//! Nothing depends on time, thread scheduling or hash-map order: the same
//! inputs give byte-identical images on the same machine and driver. Items are
//! drawn in the order given. Different drivers or GPUs may differ by rounding
//! (see the snapshot tolerance in [`crate::output::snapshot`]).
//!
//! # No adapter
//! [`Renderer::new`] returns [`RenderError::NoAdapter`] when the machine has
//! no Vulkan adapter (no GPU driver and no lavapipe). Callers print
//! [`NO_ADAPTER_HINT`] once and carry on without frames.
//!
//! # Cost
//! Pipelines, the uniform buffer, instance and line buffers, the render
//! targets and the readback buffer are kept between frames (targets are
//! rebuilt only when the image size changes). Each frame uploads one uniform
//! block, one instance array and one line-vertex array, and draws.

mod math;

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, mpsc};

use crate::plant::mesh::TriMesh;
use math::Mat4;

/// The line a caller prints when [`Renderer::new`] finds no Vulkan adapter.
pub const NO_ADAPTER_HINT: &str = "no Vulkan adapter found: frames are not rendered \
     (install Mesa's software driver: apt-get install mesa-vulkan-drivers)";

/// Distance from the eye to the near clipping plane (metres).
pub const NEAR_PLANE_M: f32 = 0.01;

/// The background colour of every image (sRGB, 8 bits per channel).
pub const BACKGROUND_RGBA8: [u8; 4] = [206, 211, 217, 255];

/// Samples per pixel when the adapter supports multisampling.
const MSAA_SAMPLES: u32 = 4;
/// Colour format of the render target; sRGB so blending happens in linear light.
const COLOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// Bytes per mesh vertex: position and normal, three f32 each.
const VERTEX_BYTES: u64 = 24;
/// Bytes per instance: world_from_mesh (4 vec4), normal matrix (3 vec4), colour.
const INSTANCE_BYTES: u64 = 128;
/// Bytes per line segment: start and end (3 f32 each) and colour (4 f32).
const SEGMENT_BYTES: u64 = 40;
/// Bytes of the `Globals` uniform block in `scene.wgsl`.
const GLOBALS_BYTES: u64 = 128;
/// Width of trail lines (pixels).
pub const LINE_WIDTH_PX: f32 = 2.0;

/// A pinhole camera looking from `eye_in_world` towards `target_in_world`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    /// Camera position in the world frame (m). (default: (3, -3, 2))
    pub eye_in_world: [f32; 3],
    /// Point the camera looks at, in the world frame (m); it lands in the
    /// image centre. (default: (0, 0, 0.5))
    pub target_in_world: [f32; 3],
    /// Direction that points up on screen, in the world frame; need not be
    /// unit length nor perpendicular to the view. (default: +Z)
    pub up_in_world: [f32; 3],
    /// Vertical field of view (degrees, in (0, 180)). (default: 45)
    pub fov_y_deg: f32,
    /// Image width (pixels). (default: 640)
    pub width_px: u32,
    /// Image height (pixels). (default: 480)
    pub height_px: u32,
}

impl Default for Camera {
    fn default() -> Camera {
        Camera {
            eye_in_world: [3.0, -3.0, 2.0],
            target_in_world: [0.0, 0.0, 0.5],
            up_in_world: [0.0, 0.0, 1.0],
            fov_y_deg: 45.0,
            width_px: 640,
            height_px: 480,
        }
    }
}

/// What a camera's derived matrices and light are.
#[derive(Debug, Clone, Copy)]
struct CameraFrame {
    clip_from_world: Mat4,
    to_light_in_world: [f32; 3],
}

impl Camera {
    /// Validates the camera and derives its matrices and light direction.
    fn frame(&self) -> Result<CameraFrame, RenderError> {
        let (width_px, height_px) = (self.width_px, self.height_px);
        if width_px == 0 || height_px == 0 {
            return Err(RenderError::EmptyImage { width_px, height_px });
        }
        if !(self.fov_y_deg > 0.0 && self.fov_y_deg < 180.0) {
            return Err(RenderError::FieldOfView {
                fov_y_deg: self.fov_y_deg,
            });
        }
        let all = [self.eye_in_world, self.target_in_world, self.up_in_world];
        if !all.iter().flatten().all(|v| v.is_finite()) {
            return Err(RenderError::Camera {
                problem: CameraProblem::NonFinite,
            });
        }
        let (eye, target) = (self.eye_in_world, self.target_in_world);
        let forward = math::normalize(math::sub(target, eye)).ok_or(RenderError::Camera {
            problem: CameraProblem::EyeOnTarget,
        })?;
        let up = math::normalize(self.up_in_world).ok_or(RenderError::Camera {
            problem: CameraProblem::UpAlongView,
        })?;
        let view = math::look_at(eye, target, up).ok_or(RenderError::Camera {
            problem: CameraProblem::UpAlongView,
        })?;
        let aspect = width_px as f32 / height_px as f32;
        let proj = math::perspective_reversed_infinite(self.fov_y_deg.to_radians(), aspect, NEAR_PLANE_M);
        let right = math::normalize(math::cross(forward, up)).ok_or(RenderError::Camera {
            problem: CameraProblem::UpAlongView,
        })?;
        // Above, behind and to the left of the camera.
        let mix: [f32; 3] = std::array::from_fn(|k| 1.0 * up[k] - 0.6 * forward[k] - 0.5 * right[k]);
        let to_light_in_world = math::normalize(mix).unwrap_or(up);
        Ok(CameraFrame {
            clip_from_world: math::mul(&proj, &view),
            to_light_in_world,
        })
    }

    /// The matrix from world coordinates to wgpu clip space (column-major,
    /// reversed depth: 1 at the near plane, 0 at infinity).
    ///
    /// # Errors
    /// [`RenderError::EmptyImage`], [`RenderError::FieldOfView`] or
    /// [`RenderError::Camera`] when the camera cannot form an image.
    pub fn clip_from_world(&self) -> Result<[[f32; 4]; 4], RenderError> {
        Ok(self.frame()?.clip_from_world)
    }

    /// Where `point_in_world` lands in the image, in pixels from the top-left
    /// corner (x right, y down; pixel centres at .5). `None` when the point
    /// is behind the near plane or the camera is invalid. Points outside the
    /// field of view give coordinates outside the image.
    #[must_use]
    pub fn project_to_pixel(&self, point_in_world: [f32; 3]) -> Option<[f32; 2]> {
        let clip = math::transform_point(&self.frame().ok()?.clip_from_world, point_in_world);
        if clip[3] < NEAR_PLANE_M {
            return None;
        }
        let (x, y) = (clip[0] / clip[3], clip[1] / clip[3]);
        Some([
            (x + 1.0) * 0.5 * self.width_px as f32,
            (1.0 - y) * 0.5 * self.height_px as f32,
        ])
    }

    /// Unit vector from a surface towards the key light (world frame): above,
    /// behind and left of the camera. `None` for an invalid camera.
    #[must_use]
    pub fn key_light_dir_in_world(&self) -> Option<[f32; 3]> {
        Some(self.frame().ok()?.to_light_in_world)
    }
}

/// Handle to a mesh uploaded with [`Renderer::upload_mesh`]; only meaningful
/// for the renderer that issued it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct MeshId(u32);

impl MeshId {
    /// The handle's index in its renderer (upload order, from 0).
    #[must_use]
    pub fn index(self) -> u32 {
        self.0
    }
}

/// One mesh placed in the world.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DrawItem {
    /// The mesh to draw.
    pub mesh: MeshId,
    /// Pose (and optional scale or mirror) of the mesh in the world frame:
    /// column-major 4x4 affine matrix, translation in metres in column 3.
    pub world_from_mesh: [[f32; 4]; 4],
    /// Surface colour, sRGB RGBA in 0..1. Alpha below 1 blends with what was
    /// drawn before (draw translucent items last); the item still hides what
    /// is drawn after it and behind it.
    pub color_rgba: [f32; 4],
    /// Optional highlight (e.g. red for a colliding link), sRGB RGBA: its RGB
    /// replaces the colour's in proportion to its alpha (1 = fully tinted).
    pub tint_rgba: Option<[f32; 4]>,
}

/// A polyline in the world (e.g. a tool-centre trail), drawn
/// [`LINE_WIDTH_PX`] wide and hidden behind surfaces. Fewer than two points
/// draw nothing; segments reaching behind the near plane are dropped.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct LineStrip {
    /// Consecutive points in the world frame (m).
    pub points_in_world: Vec<[f32; 3]>,
    /// Line colour, sRGB RGBA in 0..1 (alpha blends).
    pub color_rgba: [f32; 4],
}

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
    /// No Vulkan adapter exists (no GPU driver and no lavapipe); see [`NO_ADAPTER_HINT`].
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

/// A mesh as stored by the renderer.
#[derive(Debug)]
enum GpuMesh {
    Ready {
        vertices: wgpu::Buffer,
        indices: wgpu::Buffer,
        index_count: u32,
    },
    Empty,
    Invalid(MeshProblem),
}

/// Render targets and readback buffer for one image size.
#[derive(Debug)]
struct Target {
    width_px: u32,
    height_px: u32,
    /// Multisampled colour attachment; `None` without MSAA.
    msaa_view: Option<wgpu::TextureView>,
    /// Single-sampled colour texture that is copied back.
    resolved: wgpu::Texture,
    resolved_view: wgpu::TextureView,
    depth_view: wgpu::TextureView,
    readback: wgpu::Buffer,
    padded_bytes_per_row: u32,
}

/// A vertex buffer that grows (by doubling) and is reused between frames.
#[derive(Debug)]
struct GrowBuffer {
    buffer: wgpu::Buffer,
    capacity: u64,
    label: &'static str,
}

impl GrowBuffer {
    fn new(device: &wgpu::Device, label: &'static str, capacity: u64) -> GrowBuffer {
        let buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: capacity,
            usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        GrowBuffer {
            buffer,
            capacity,
            label,
        }
    }

    fn write(&mut self, device: &wgpu::Device, queue: &wgpu::Queue, bytes: &[u8]) {
        let needed = bytes.len() as u64;
        if needed > self.capacity {
            *self = GrowBuffer::new(device, self.label, needed.next_power_of_two());
        }
        if !bytes.is_empty() {
            queue.write_buffer(&self.buffer, 0, bytes);
        }
    }
}

/// Offscreen renderer with cached pipelines and buffers. See the module docs
/// for conventions.
#[derive(Debug)]
pub struct Renderer {
    device: wgpu::Device,
    queue: wgpu::Queue,
    adapter_info: wgpu::AdapterInfo,
    max_side_px: u32,
    max_buffer_bytes: u64,
    sample_count: u32,
    mesh_pipeline: wgpu::RenderPipeline,
    grid_pipeline: wgpu::RenderPipeline,
    line_pipeline: wgpu::RenderPipeline,
    globals: wgpu::Buffer,
    bind_group: wgpu::BindGroup,
    instances: GrowBuffer,
    line_vertices: GrowBuffer,
    meshes: Vec<GpuMesh>,
    target: Option<Target>,
    lost: Arc<AtomicBool>,
    uncaptured: Arc<Mutex<Option<wgpu::Error>>>,
}

impl Renderer {
    /// Opens the first suitable Vulkan adapter (a GPU if present, else
    /// lavapipe) and builds the pipelines.
    ///
    /// # Errors
    /// [`RenderError::NoAdapter`] when no Vulkan adapter exists — print
    /// [`NO_ADAPTER_HINT`] and continue without frames;
    /// [`RenderError::RequestDevice`] when the adapter refuses a device.
    pub fn new() -> Result<Renderer, RenderError> {
        let instance = wgpu::Instance::new(wgpu::InstanceDescriptor {
            backends: wgpu::Backends::VULKAN,
            flags: wgpu::InstanceFlags::from_build_config().with_env(),
            ..wgpu::InstanceDescriptor::new_without_display_handle()
        });
        let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::HighPerformance,
            force_fallback_adapter: false,
            compatible_surface: None,
            apply_limit_buckets: false,
        }))
        .map_err(|_| RenderError::NoAdapter)?;
        let limits = adapter.limits();
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("twin renderer"),
            required_features: wgpu::Features::empty(),
            required_limits: limits.clone(),
            ..wgpu::DeviceDescriptor::default()
        }))
        .map_err(|source| RenderError::RequestDevice { source })?;

        let lost = Arc::new(AtomicBool::new(false));
        let lost_flag = Arc::clone(&lost);
        device.set_device_lost_callback(move |_reason, _message| lost_flag.store(true, Ordering::SeqCst));
        // wgpu panics on errors nobody captures; keep the first one for the
        // next `render` call to return instead.
        let uncaptured: Arc<Mutex<Option<wgpu::Error>>> = Arc::new(Mutex::new(None));
        let sink = Arc::clone(&uncaptured);
        device.on_uncaptured_error(Arc::new(move |error| {
            let mut slot = sink.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
            slot.get_or_insert(error);
        }));

        let supports = |format| {
            adapter
                .get_texture_format_features(format)
                .flags
                .sample_count_supported(MSAA_SAMPLES)
        };
        let sample_count = if supports(COLOR_FORMAT) && supports(DEPTH_FORMAT) {
            MSAA_SAMPLES
        } else {
            1
        };

        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("scene.wgsl"),
            source: wgpu::ShaderSource::Wgsl(include_str!("render/scene.wgsl").into()),
        });
        let bind_group_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("globals"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: wgpu::BufferSize::new(GLOBALS_BYTES),
                },
                count: None,
            }],
        });
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("scene"),
            bind_group_layouts: &[Some(&bind_group_layout)],
            immediate_size: 0,
        });
        let globals = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("globals"),
            size: GLOBALS_BYTES,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("globals"),
            layout: &bind_group_layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: globals.as_entire_binding(),
            }],
        });

        let mesh_attributes = wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3];
        let instance_attributes = wgpu::vertex_attr_array![
            2 => Float32x4, 3 => Float32x4, 4 => Float32x4, 5 => Float32x4,
            6 => Float32x4, 7 => Float32x4, 8 => Float32x4, 9 => Float32x4
        ];
        let segment_attributes = wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x4];
        let builder = PipelineBuilder {
            device: &device,
            layout: &layout,
            module: &module,
            sample_count,
        };
        let mesh_pipeline = builder.build(
            "mesh",
            &[
                Some(wgpu::VertexBufferLayout {
                    array_stride: VERTEX_BYTES,
                    step_mode: wgpu::VertexStepMode::Vertex,
                    attributes: &mesh_attributes,
                }),
                Some(wgpu::VertexBufferLayout {
                    array_stride: INSTANCE_BYTES,
                    step_mode: wgpu::VertexStepMode::Instance,
                    attributes: &instance_attributes,
                }),
            ],
            wgpu::PrimitiveTopology::TriangleList,
            true,
        );
        let grid_pipeline = builder.build("grid", &[], wgpu::PrimitiveTopology::TriangleList, false);
        let line_pipeline = builder.build(
            "line",
            &[Some(wgpu::VertexBufferLayout {
                array_stride: SEGMENT_BYTES,
                step_mode: wgpu::VertexStepMode::Instance,
                attributes: &segment_attributes,
            })],
            wgpu::PrimitiveTopology::TriangleList,
            false,
        );
        let instances = GrowBuffer::new(&device, "instances", 64 * INSTANCE_BYTES);
        let line_vertices = GrowBuffer::new(&device, "line segments", 1024 * SEGMENT_BYTES);

        Ok(Renderer {
            adapter_info: adapter.get_info(),
            max_side_px: limits.max_texture_dimension_2d,
            max_buffer_bytes: limits.max_buffer_size,
            sample_count,
            device,
            queue,
            mesh_pipeline,
            grid_pipeline,
            line_pipeline,
            globals,
            bind_group,
            instances,
            line_vertices,
            meshes: Vec::new(),
            target: None,
            lost,
            uncaptured,
        })
    }

    /// The adapter in use (name, driver, device type), for logs.
    #[must_use]
    pub fn adapter_info(&self) -> &wgpu::AdapterInfo {
        &self.adapter_info
    }

    /// Samples per pixel: 4 when the adapter supports 4x MSAA, else 1.
    #[must_use]
    pub fn sample_count(&self) -> u32 {
        self.sample_count
    }

    /// Copies a mesh (in its own frame, metres) to the GPU and returns its
    /// handle. Never fails here: a malformed mesh (normals missing, indices
    /// out of range, NaN) gets a handle too, and drawing it makes
    /// [`Renderer::render`] return [`RenderError::InvalidMesh`] naming the
    /// problem. A mesh without triangles draws nothing.
    pub fn upload_mesh(&mut self, mesh: &TriMesh) -> MeshId {
        let id = MeshId(u32::try_from(self.meshes.len()).unwrap_or(u32::MAX));
        let stored = match validate_mesh(mesh, self.max_buffer_bytes) {
            Err(problem) => GpuMesh::Invalid(problem),
            Ok(()) if mesh.indices.is_empty() => GpuMesh::Empty,
            Ok(()) => {
                let mut vertex_bytes = Vec::with_capacity(mesh.positions.len() * VERTEX_BYTES as usize);
                for (p, n) in mesh.positions.iter().zip(&mesh.normals) {
                    push_f32s(&mut vertex_bytes, p);
                    push_f32s(&mut vertex_bytes, n);
                }
                let index_bytes: Vec<u8> = mesh.indices.iter().flat_map(|i| i.to_le_bytes()).collect();
                let buffer = |label, bytes: &[u8], usage| {
                    let buffer = self.device.create_buffer(&wgpu::BufferDescriptor {
                        label: Some(label),
                        size: bytes.len() as u64,
                        usage: usage | wgpu::BufferUsages::COPY_DST,
                        mapped_at_creation: false,
                    });
                    self.queue.write_buffer(&buffer, 0, bytes);
                    buffer
                };
                GpuMesh::Ready {
                    vertices: buffer("mesh vertices", &vertex_bytes, wgpu::BufferUsages::VERTEX),
                    indices: buffer("mesh indices", &index_bytes, wgpu::BufferUsages::INDEX),
                    // Validation bounds the index count by the buffer size limit.
                    index_count: u32::try_from(mesh.indices.len()).unwrap_or(u32::MAX),
                }
            }
        };
        self.meshes.push(stored);
        id
    }

    /// Renders one frame: `items` in order (depth-tested), the ground grid,
    /// then `lines`, seen through `camera`, and reads it back as an sRGB
    /// image of `camera.width_px` x `camera.height_px`.
    ///
    /// # Errors
    /// Invalid input: [`RenderError::EmptyImage`], [`RenderError::ImageTooLarge`],
    /// [`RenderError::FieldOfView`], [`RenderError::Camera`],
    /// [`RenderError::UnknownMesh`], [`RenderError::InvalidMesh`],
    /// [`RenderError::NonFiniteItem`], [`RenderError::NonFiniteLine`].
    /// GPU trouble: [`RenderError::DeviceLost`], [`RenderError::Gpu`],
    /// [`RenderError::Readback`].
    pub fn render(
        &mut self,
        camera: &Camera,
        items: &[DrawItem],
        lines: &[LineStrip],
    ) -> Result<image::RgbaImage, RenderError> {
        self.check_health()?;
        let frame = camera.frame()?;
        let (width_px, height_px) = (camera.width_px, camera.height_px);
        let too_large = || RenderError::ImageTooLarge {
            width_px,
            height_px,
            max_side_px: self.max_side_px,
            max_bytes: self.max_buffer_bytes,
        };
        if width_px > self.max_side_px || height_px > self.max_side_px {
            return Err(too_large());
        }
        // Rows padded to wgpu's copy alignment (256 bytes), checked so that
        // an adapter with absurd limits cannot make this overflow.
        let padded_bytes_per_row = width_px
            .checked_mul(4)
            .and_then(|row| row.checked_next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT))
            .ok_or_else(too_large)?;
        let readback_bytes = u64::from(padded_bytes_per_row) * u64::from(height_px);
        if readback_bytes > self.max_buffer_bytes {
            return Err(too_large());
        }
        let instance_bytes = self.instance_bytes(items)?;
        let line_bytes = line_bytes(lines)?;
        let globals_bytes = globals_bytes(camera, &frame);

        let scopes = [
            self.device.push_error_scope(wgpu::ErrorFilter::OutOfMemory),
            self.device.push_error_scope(wgpu::ErrorFilter::Validation),
            self.device.push_error_scope(wgpu::ErrorFilter::Internal),
        ];
        self.ensure_target(width_px, height_px, padded_bytes_per_row, readback_bytes);
        self.queue.write_buffer(&self.globals, 0, &globals_bytes);
        self.instances.write(&self.device, &self.queue, &instance_bytes);
        self.line_vertices.write(&self.device, &self.queue, &line_bytes);
        let outcome = self.draw_and_read(items, line_bytes.len() as u64 / SEGMENT_BYTES);
        // Pop innermost first; report the first error any scope caught.
        let mut gpu_error = None;
        for scope in scopes.into_iter().rev() {
            if let Some(error) = pollster::block_on(scope.pop()) {
                gpu_error.get_or_insert(error);
            }
        }
        if self.lost.load(Ordering::SeqCst) {
            return Err(RenderError::DeviceLost);
        }
        match gpu_error {
            Some(source) => Err(RenderError::Gpu { source }),
            None => outcome,
        }
    }

    /// Records and submits the frame, waits for it and reads the image back.
    fn draw_and_read(&self, items: &[DrawItem], segment_count: u64) -> Result<image::RgbaImage, RenderError> {
        let target = self.target.as_ref().ok_or(RenderError::Readback {
            stage: ReadbackStage::NotCompleted,
        })?;
        let (width_px, height_px) = (target.width_px, target.height_px);
        let mut encoder = self
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("frame") });
        self.encode_pass(&mut encoder, target, items, segment_count);
        encoder.copy_texture_to_buffer(
            wgpu::TexelCopyTextureInfo {
                texture: &target.resolved,
                mip_level: 0,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            wgpu::TexelCopyBufferInfo {
                buffer: &target.readback,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(target.padded_bytes_per_row),
                    rows_per_image: Some(height_px),
                },
            },
            wgpu::Extent3d {
                width: width_px,
                height: height_px,
                depth_or_array_layers: 1,
            },
        );
        let submission = self.queue.submit([encoder.finish()]);
        let (sender, receiver) = mpsc::channel();
        target.readback.map_async(wgpu::MapMode::Read, .., move |result| {
            // The receiver lives until after the wait below; a failed send
            // only means the frame was abandoned, which needs no report.
            let _ = sender.send(result);
        });
        self.device
            .poll(wgpu::PollType::Wait {
                submission_index: Some(submission),
                timeout: None,
            })
            .map_err(|_| RenderError::Readback {
                stage: ReadbackStage::Wait,
            })?;
        match receiver.try_recv() {
            Err(_) => Err(RenderError::Readback {
                stage: ReadbackStage::NotCompleted,
            }),
            Ok(Err(_)) => Err(RenderError::Readback {
                stage: ReadbackStage::Map,
            }),
            Ok(Ok(())) => {
                let image = read_image(&target.readback, width_px, height_px, target.padded_bytes_per_row);
                target.readback.unmap();
                image
            }
        }
    }

    /// Returns a pending device-lost or uncaptured GPU error, once.
    fn check_health(&self) -> Result<(), RenderError> {
        if self.lost.load(Ordering::SeqCst) {
            return Err(RenderError::DeviceLost);
        }
        let mut slot = self
            .uncaptured
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        match slot.take() {
            Some(source) => Err(RenderError::Gpu { source }),
            None => Ok(()),
        }
    }

    /// Validates the items and packs their per-instance data.
    fn instance_bytes(&self, items: &[DrawItem]) -> Result<Vec<u8>, RenderError> {
        let mut bytes = Vec::with_capacity(items.len() * INSTANCE_BYTES as usize);
        for (item, draw) in items.iter().enumerate() {
            let mesh = draw.mesh.0;
            match self.meshes.get(mesh as usize) {
                None => return Err(RenderError::UnknownMesh { item, mesh }),
                Some(GpuMesh::Invalid(problem)) => {
                    return Err(RenderError::InvalidMesh {
                        item,
                        mesh,
                        problem: *problem,
                    });
                }
                Some(GpuMesh::Ready { .. } | GpuMesh::Empty) => {}
            }
            let tint = draw.tint_rgba.unwrap_or([0.0; 4]);
            let finite = draw
                .world_from_mesh
                .iter()
                .flatten()
                .chain(&draw.color_rgba)
                .chain(&tint);
            if !finite.into_iter().all(|v| v.is_finite()) {
                return Err(RenderError::NonFiniteItem { item });
            }
            let (normal, sign) = math::normal_matrix(&draw.world_from_mesh);
            for column in &draw.world_from_mesh {
                push_f32s(&mut bytes, column);
            }
            for (k, column) in normal.iter().enumerate() {
                push_f32s(&mut bytes, column);
                push_f32s(&mut bytes, &[if k == 0 { sign } else { 0.0 }]);
            }
            let amount = tint[3].clamp(0.0, 1.0);
            let rgb: [f32; 3] = std::array::from_fn(|k| {
                let c = draw.color_rgba[k].clamp(0.0, 1.0);
                math::srgb_to_linear(c + (tint[k].clamp(0.0, 1.0) - c) * amount)
            });
            push_f32s(&mut bytes, &rgb);
            push_f32s(&mut bytes, &[draw.color_rgba[3].clamp(0.0, 1.0)]);
        }
        Ok(bytes)
    }

    /// (Re)creates render targets and the readback buffer when the size changes.
    fn ensure_target(&mut self, width_px: u32, height_px: u32, padded_bytes_per_row: u32, readback_bytes: u64) {
        if self
            .target
            .as_ref()
            .is_some_and(|t| t.width_px == width_px && t.height_px == height_px)
        {
            return;
        }
        let size = wgpu::Extent3d {
            width: width_px,
            height: height_px,
            depth_or_array_layers: 1,
        };
        let texture = |label, format, samples, usage| {
            self.device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size,
                mip_level_count: 1,
                sample_count: samples,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage,
                view_formats: &[],
            })
        };
        let view = |t: &wgpu::Texture| t.create_view(&wgpu::TextureViewDescriptor::default());
        let attachment = wgpu::TextureUsages::RENDER_ATTACHMENT;
        let msaa_view =
            (self.sample_count > 1).then(|| view(&texture("msaa colour", COLOR_FORMAT, self.sample_count, attachment)));
        let resolved = texture("colour", COLOR_FORMAT, 1, attachment | wgpu::TextureUsages::COPY_SRC);
        let depth_view = view(&texture("depth", DEPTH_FORMAT, self.sample_count, attachment));
        let readback = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("readback"),
            size: readback_bytes,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        self.target = Some(Target {
            width_px,
            height_px,
            msaa_view,
            resolved_view: view(&resolved),
            resolved,
            depth_view,
            readback,
            padded_bytes_per_row,
        });
    }

    /// Records the single render pass: meshes, grid, lines.
    fn encode_pass(&self, encoder: &mut wgpu::CommandEncoder, target: &Target, items: &[DrawItem], segment_count: u64) {
        let background = BACKGROUND_RGBA8.map(|c| f64::from(math::srgb_to_linear(f32::from(c) / 255.0)));
        let (view, resolve_target) = match &target.msaa_view {
            Some(msaa) => (msaa, Some(&target.resolved_view)),
            None => (&target.resolved_view, None),
        };
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("scene"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view,
                depth_slice: None,
                resolve_target,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color {
                        r: background[0],
                        g: background[1],
                        b: background[2],
                        a: 1.0,
                    }),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &target.depth_view,
                // Reversed depth: 0 is infinitely far.
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(0.0),
                    store: wgpu::StoreOp::Discard,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_bind_group(0, &self.bind_group, &[]);
        if !items.is_empty() {
            pass.set_pipeline(&self.mesh_pipeline);
            pass.set_vertex_buffer(1, self.instances.buffer.slice(..));
            for (index, item) in (0_u32..).zip(items) {
                if let Some(GpuMesh::Ready {
                    vertices,
                    indices,
                    index_count,
                }) = self.meshes.get(item.mesh.0 as usize)
                {
                    pass.set_vertex_buffer(0, vertices.slice(..));
                    pass.set_index_buffer(indices.slice(..), wgpu::IndexFormat::Uint32);
                    pass.draw_indexed(0..*index_count, 0, index..index + 1);
                }
            }
        }
        pass.set_pipeline(&self.grid_pipeline);
        pass.draw(0..6, 0..1);
        if segment_count > 0 {
            pass.set_pipeline(&self.line_pipeline);
            pass.set_vertex_buffer(0, self.line_vertices.buffer.slice(..));
            pass.draw(0..6, 0..u32::try_from(segment_count).unwrap_or(u32::MAX));
        }
    }
}

/// Copies the mapped, row-padded readback buffer into an image.
fn read_image(
    buffer: &wgpu::Buffer,
    width_px: u32,
    height_px: u32,
    padded_bytes_per_row: u32,
) -> Result<image::RgbaImage, RenderError> {
    let copy_failed = RenderError::Readback {
        stage: ReadbackStage::Copy,
    };
    let view = buffer.get_mapped_range(..).map_err(|_| RenderError::Readback {
        stage: ReadbackStage::Copy,
    })?;
    let row_bytes = width_px as usize * 4;
    let mut pixels = Vec::with_capacity(row_bytes * height_px as usize);
    for row in view.chunks(padded_bytes_per_row as usize).take(height_px as usize) {
        pixels.extend_from_slice(row.get(..row_bytes).ok_or(RenderError::Readback {
            stage: ReadbackStage::Copy,
        })?);
    }
    drop(view);
    image::RgbaImage::from_raw(width_px, height_px, pixels).ok_or(copy_failed)
}

/// Checks that a mesh can be uploaded and drawn safely.
fn validate_mesh(mesh: &TriMesh, max_buffer_bytes: u64) -> Result<(), MeshProblem> {
    let vertices = mesh.positions.len();
    if mesh.normals.len() != vertices {
        return Err(MeshProblem::NormalCount {
            positions: vertices,
            normals: mesh.normals.len(),
        });
    }
    if !mesh.indices.len().is_multiple_of(3) {
        return Err(MeshProblem::PartialTriangle {
            indices: mesh.indices.len(),
        });
    }
    let bytes = (vertices as u64 * VERTEX_BYTES).max(mesh.indices.len() as u64 * 4);
    if bytes > max_buffer_bytes {
        return Err(MeshProblem::TooLarge {
            bytes,
            max_bytes: max_buffer_bytes,
        });
    }
    if let Some(vertex) =
        (0..vertices).find(|&v| !mesh.positions[v].iter().chain(&mesh.normals[v]).all(|c| c.is_finite()))
    {
        return Err(MeshProblem::NonFinite { vertex });
    }
    if let Some((position, &index)) = mesh.indices.iter().enumerate().find(|(_, i)| **i as usize >= vertices) {
        return Err(MeshProblem::IndexOutOfRange {
            triangle: position / 3,
            index,
            vertices,
        });
    }
    Ok(())
}

/// Validates the strips and packs their segments (start, end, linear colour).
fn line_bytes(lines: &[LineStrip]) -> Result<Vec<u8>, RenderError> {
    let mut bytes = Vec::new();
    for (strip, line) in lines.iter().enumerate() {
        if let Some(point) = line
            .points_in_world
            .iter()
            .position(|p| !p.iter().all(|c| c.is_finite()))
        {
            return Err(RenderError::NonFiniteLine { strip, point });
        }
        if !line.color_rgba.iter().all(|c| c.is_finite()) {
            return Err(RenderError::NonFiniteLine {
                strip,
                point: line.points_in_world.len(),
            });
        }
        let c = line.color_rgba.map(|v| v.clamp(0.0, 1.0));
        let color = [
            math::srgb_to_linear(c[0]),
            math::srgb_to_linear(c[1]),
            math::srgb_to_linear(c[2]),
            c[3],
        ];
        for pair in line.points_in_world.windows(2) {
            push_f32s(&mut bytes, &pair[0]);
            push_f32s(&mut bytes, &pair[1]);
            push_f32s(&mut bytes, &color);
        }
    }
    Ok(bytes)
}

/// Packs the `Globals` uniform block of `scene.wgsl`.
fn globals_bytes(camera: &Camera, frame: &CameraFrame) -> Vec<u8> {
    let eye = camera.eye_in_world;
    let distance = math::length(math::sub(camera.target_in_world, eye));
    // The grid fades out between these distances from the eye (m), scaled
    // with the viewing distance so close-ups and overviews both look right.
    let fade_start = (1.5 * distance).max(2.0);
    let fade_end = (4.0 * distance).max(6.0);
    let mut bytes = Vec::with_capacity(GLOBALS_BYTES as usize);
    for column in &frame.clip_from_world {
        push_f32s(&mut bytes, column);
    }
    push_f32s(&mut bytes, &[eye[0], eye[1], eye[2], 1.0]);
    let l = frame.to_light_in_world;
    push_f32s(&mut bytes, &[l[0], l[1], l[2], 0.0]);
    push_f32s(&mut bytes, &[fade_start, fade_end, eye[0], eye[1]]);
    let size_px = [camera.width_px as f32, camera.height_px as f32];
    push_f32s(&mut bytes, &[size_px[0], size_px[1], LINE_WIDTH_PX, 0.0]);
    bytes
}

fn push_f32s(bytes: &mut Vec<u8>, values: &[f32]) {
    for v in values {
        bytes.extend_from_slice(&v.to_le_bytes());
    }
}

/// Shared settings of the three pipelines.
struct PipelineBuilder<'a> {
    device: &'a wgpu::Device,
    layout: &'a wgpu::PipelineLayout,
    module: &'a wgpu::ShaderModule,
    sample_count: u32,
}

impl PipelineBuilder<'_> {
    /// A pipeline using `vs_<name>` / `fs_<name>`, alpha blending and reversed depth.
    fn build(
        &self,
        name: &str,
        buffers: &[Option<wgpu::VertexBufferLayout<'_>>],
        topology: wgpu::PrimitiveTopology,
        depth_write: bool,
    ) -> wgpu::RenderPipeline {
        let vs = format!("vs_{name}");
        let fs = format!("fs_{name}");
        self.device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some(name),
            layout: Some(self.layout),
            vertex: wgpu::VertexState {
                module: self.module,
                entry_point: Some(&vs),
                compilation_options: wgpu::PipelineCompilationOptions::default(),
                buffers,
            },
            primitive: wgpu::PrimitiveState {
                topology,
                front_face: wgpu::FrontFace::Ccw,
                // No culling: mirrored transforms and open meshes stay visible;
                // the shader lights whichever side faces the camera.
                cull_mode: None,
                ..wgpu::PrimitiveState::default()
            },
            depth_stencil: Some(wgpu::DepthStencilState {
                format: DEPTH_FORMAT,
                depth_write_enabled: Some(depth_write),
                depth_compare: Some(wgpu::CompareFunction::GreaterEqual),
                stencil: wgpu::StencilState::default(),
                bias: wgpu::DepthBiasState::default(),
            }),
            multisample: wgpu::MultisampleState {
                count: self.sample_count,
                mask: !0,
                alpha_to_coverage_enabled: false,
            },
            fragment: Some(wgpu::FragmentState {
                module: self.module,
                entry_point: Some(&fs),
                compilation_options: wgpu::PipelineCompilationOptions::default(),
                targets: &[Some(wgpu::ColorTargetState {
                    format: COLOR_FORMAT,
                    blend: Some(wgpu::BlendState::ALPHA_BLENDING),
                    write_mask: wgpu::ColorWrites::ALL,
                })],
            }),
            multiview_mask: None,
            cache: None,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A renderer, or `None` (with a skip line) when this machine has no
    /// Vulkan adapter. In CI or with `TWIN_REQUIRE_GPU=1` a missing adapter fails.
    fn renderer_or_skip(test: &str) -> Option<Renderer> {
        match Renderer::new() {
            Ok(renderer) => Some(renderer),
            Err(RenderError::NoAdapter) => {
                let required =
                    std::env::var_os("CI").is_some() || std::env::var("TWIN_REQUIRE_GPU").is_ok_and(|v| v == "1");
                assert!(
                    !required,
                    "{test}: {NO_ADAPTER_HINT} (CI or TWIN_REQUIRE_GPU=1 requires one)"
                );
                eprintln!("SKIPPED {test}: {NO_ADAPTER_HINT}");
                None
            }
            Err(other) => panic!("{test}: renderer failed to start: {other}"),
        }
    }

    fn translation(x: f32, y: f32, z: f32) -> [[f32; 4]; 4] {
        [
            [1.0, 0.0, 0.0, 0.0],
            [0.0, 1.0, 0.0, 0.0],
            [0.0, 0.0, 1.0, 0.0],
            [x, y, z, 1.0],
        ]
    }

    const BOX_CENTRE: [f32; 3] = [0.0, 0.0, 0.3];
    const BOX_HALF: f32 = 0.2;
    const CYLINDER_CENTRE: [f32; 3] = [0.75, 0.45, 0.25];
    const SPHERE_CENTRE: [f32; 3] = [-0.65, -0.6, 0.3];
    const RED: [f32; 4] = [0.85, 0.18, 0.12, 1.0];
    const BLUE: [f32; 4] = [0.15, 0.35, 0.85, 1.0];
    const GREEN: [f32; 4] = [0.2, 0.75, 0.25, 1.0];
    const MAGENTA: [f32; 4] = [0.9, 0.1, 0.9, 1.0];

    struct Scene {
        camera: Camera,
        items: Vec<DrawItem>,
        lines: Vec<LineStrip>,
        /// A small magenta sphere right behind the box as seen from the camera.
        hidden_centre: [f32; 3],
        hidden: DrawItem,
    }

    fn scene(renderer: &mut Renderer) -> Scene {
        let camera = Camera {
            eye_in_world: [3.0, -3.0, 1.6],
            target_in_world: [0.0, 0.0, 0.3],
            width_px: 320,
            height_px: 240,
            ..Camera::default()
        };
        let cuboid = renderer.upload_mesh(&TriMesh::cuboid([2.0 * BOX_HALF; 3]));
        let cylinder = renderer.upload_mesh(&TriMesh::cylinder(0.15, 0.5, 48));
        let sphere = renderer.upload_mesh(&TriMesh::sphere(0.2, 24, 48));
        let small = renderer.upload_mesh(&TriMesh::sphere(0.06, 12, 24));
        let item = |mesh, [x, y, z]: [f32; 3], color_rgba| DrawItem {
            mesh,
            world_from_mesh: translation(x, y, z),
            color_rgba,
            tint_rgba: None,
        };
        let eye = camera.eye_in_world;
        let away = math::normalize(math::sub(BOX_CENTRE, eye)).expect("eye is not on the box");
        let hidden_centre: [f32; 3] = std::array::from_fn(|k| BOX_CENTRE[k] + 0.45 * away[k]);
        let trail = LineStrip {
            points_in_world: (0..=40)
                .map(|i| {
                    let a = i as f32 / 40.0 * std::f32::consts::PI;
                    [0.9 * a.cos(), -0.9 * a.sin(), 0.05]
                })
                .collect(),
            color_rgba: MAGENTA,
        };
        Scene {
            camera,
            items: vec![
                item(cuboid, BOX_CENTRE, RED),
                item(cylinder, CYLINDER_CENTRE, BLUE),
                item(sphere, SPHERE_CENTRE, GREEN),
            ],
            lines: vec![trail],
            hidden_centre,
            hidden: item(small, hidden_centre, MAGENTA),
        }
    }

    fn pixel_at(img: &image::RgbaImage, camera: &Camera, point: [f32; 3]) -> [u8; 4] {
        let [x, y] = camera.project_to_pixel(point).expect("point in front of the camera");
        assert!(
            x >= 0.0 && y >= 0.0 && x < img.width() as f32 && y < img.height() as f32,
            "{point:?} off screen"
        );
        img.get_pixel(x as u32, y as u32).0
    }

    fn luma(p: [u8; 4]) -> f32 {
        0.2126 * f32::from(p[0]) + 0.7152 * f32::from(p[1]) + 0.0722 * f32::from(p[2])
    }

    fn dominant(p: [u8; 4], channel: usize) -> bool {
        (0..3)
            .filter(|&k| k != channel)
            .all(|k| i32::from(p[channel]) > i32::from(p[k]) + 40)
    }

    fn save(img: &image::RgbaImage, name: &str) {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../target/render-test");
        std::fs::create_dir_all(&dir).expect("create target/render-test");
        img.save_with_format(dir.join(name), image::ImageFormat::Png)
            .expect("save png");
    }

    use std::path::Path;

    #[test]
    fn scene_shows_shapes_grid_lighting_and_background() {
        let Some(mut renderer) = renderer_or_skip("scene_shows_shapes_grid_lighting_and_background") else {
            return;
        };
        let s = scene(&mut renderer);
        let img = renderer.render(&s.camera, &s.items, &s.lines).expect("render");
        save(&img, "scene.png");
        assert_eq!(img.dimensions(), (320, 240));

        // Background in the top corners (above the horizon).
        for x in [0, img.width() - 1] {
            let p = img.get_pixel(x, 0).0;
            for k in 0..4 {
                assert!(p[k].abs_diff(BACKGROUND_RGBA8[k]) <= 1, "corner {x}: {p:?}");
            }
        }
        // Each object's colour at its projected centre.
        assert!(dominant(pixel_at(&img, &s.camera, BOX_CENTRE), 0), "box is red");
        assert!(
            dominant(pixel_at(&img, &s.camera, CYLINDER_CENTRE), 2),
            "cylinder is blue"
        );
        assert!(dominant(pixel_at(&img, &s.camera, SPHERE_CENTRE), 1), "sphere is green");

        // Faces turned towards the key light are brighter than those turned away.
        let light = s.camera.key_light_dir_in_world().expect("valid camera");
        let mut faces: Vec<(f32, f32)> = [[0.0, 0.0, 1.0], [0.0, -1.0, 0.0], [1.0, 0.0, 0.0]]
            .iter()
            .map(|n: &[f32; 3]| {
                let face_centre: [f32; 3] = std::array::from_fn(|k| BOX_CENTRE[k] + 0.9 * BOX_HALF * n[k]);
                (math::dot(*n, light), luma(pixel_at(&img, &s.camera, face_centre)))
            })
            .collect();
        faces.sort_by(|a, b| a.0.total_cmp(&b.0));
        assert!(
            faces[0].0 < faces[2].0 - 0.3,
            "test needs faces lit differently: {faces:?}"
        );
        assert!(
            faces[0].1 + 20.0 < faces[1].1 && faces[1].1 + 10.0 < faces[2].1,
            "brightness follows the light: {faces:?}"
        );

        // The ground grid: the red X axis and green Y axis on z = 0, and grey
        // lines darkening the ground near the camera.
        let near = |point: [f32; 3], test: &dyn Fn([u8; 4]) -> bool| {
            let [x, y] = s.camera.project_to_pixel(point).expect("in front");
            (-2..=2).any(|dy: i32| {
                (-2..=2).any(|dx: i32| {
                    let (px, py) = (x as i32 + dx, y as i32 + dy);
                    px >= 0 && py >= 0 && test(img.get_pixel(px as u32, py as u32).0)
                })
            })
        };
        assert!(
            near([1.6, 0.0, 0.0], &|p| i32::from(p[0]) > i32::from(p[1]) + 30),
            "X axis is red"
        );
        assert!(
            near([0.0, -1.6, 0.0], &|p| i32::from(p[1]) > i32::from(p[0]) + 15),
            "Y axis is green"
        );
        assert!(
            near([1.0, -1.0, 0.0], &|p| luma(p) < luma(BACKGROUND_RGBA8) - 30.0),
            "major lines darken"
        );
        assert!(
            near([1.3, -1.3, 0.0], &|p| luma(p) < luma(BACKGROUND_RGBA8) - 12.0),
            "minor lines darken"
        );
        // The trail (magenta, at z = 0.05 in front of the box).
        assert!(
            near([0.0, -0.9, 0.05], &|p| i32::from(p[0]) > i32::from(p[1]) + 40
                && i32::from(p[2]) > i32::from(p[1]) + 40),
            "trail drawn"
        );
    }

    #[test]
    fn renders_are_byte_identical_and_survive_size_changes() {
        let Some(mut renderer) = renderer_or_skip("renders_are_byte_identical_and_survive_size_changes") else {
            return;
        };
        let s = scene(&mut renderer);
        let first = renderer.render(&s.camera, &s.items, &s.lines).expect("render");
        let second = renderer.render(&s.camera, &s.items, &s.lines).expect("render");
        assert!(first == second, "two renders differ");
        let small = Camera {
            width_px: 97,
            height_px: 61,
            ..s.camera
        };
        let odd = renderer.render(&small, &s.items, &s.lines).expect("odd size");
        assert_eq!(odd.dimensions(), (97, 61));
        assert!(
            dominant(pixel_at(&odd, &small, BOX_CENTRE), 0),
            "box is red at any size"
        );
        let third = renderer.render(&s.camera, &s.items, &s.lines).expect("render");
        assert!(first == third, "render after a size change differs");
        // A second renderer on the same machine gives the same bytes.
        let mut other = Renderer::new().expect("second renderer");
        let s2 = scene(&mut other);
        assert!(other.render(&s2.camera, &s2.items, &s2.lines).expect("render") == first);
    }

    #[test]
    fn depth_test_hides_objects_behind_others_in_any_draw_order() {
        let Some(mut renderer) = renderer_or_skip("depth_test_hides_objects_behind_others_in_any_draw_order") else {
            return;
        };
        let s = scene(&mut renderer);
        let box_item = s.items[0];
        let alone = renderer.render(&s.camera, &[s.hidden], &[]).expect("render");
        assert!(
            dominant(pixel_at(&alone, &s.camera, s.hidden_centre), 0) || {
                let p = pixel_at(&alone, &s.camera, s.hidden_centre);
                p[0] > p[1] + 40 && p[2] > p[1] + 40
            },
            "the small sphere is visible on its own"
        );
        for order in [[box_item, s.hidden], [s.hidden, box_item]] {
            let img = renderer.render(&s.camera, &order, &[]).expect("render");
            let p = pixel_at(&img, &s.camera, s.hidden_centre);
            assert!(dominant(p, 0) && p[2] < 100, "box hides the sphere: {p:?}");
        }
    }

    #[test]
    fn tint_and_mirrored_transforms_render_sensibly() {
        let Some(mut renderer) = renderer_or_skip("tint_and_mirrored_transforms_render_sensibly") else {
            return;
        };
        let s = scene(&mut renderer);
        let mut tinted = s.items[1];
        tinted.tint_rgba = Some([1.0, 0.0, 0.0, 1.0]);
        let img = renderer.render(&s.camera, &[tinted], &[]).expect("render");
        assert!(
            dominant(pixel_at(&img, &s.camera, CYLINDER_CENTRE), 0),
            "fully tinted cylinder is red"
        );

        // Mirroring the box in Y must not darken its lit faces.
        let plain = renderer.render(&s.camera, &s.items[..1], &[]).expect("render");
        let mut mirrored = s.items[0];
        mirrored.world_from_mesh[1][1] = -1.0;
        let flipped = renderer.render(&s.camera, &[mirrored], &[]).expect("render");
        let top: [f32; 3] = [BOX_CENTRE[0], BOX_CENTRE[1], BOX_CENTRE[2] + 0.9 * BOX_HALF];
        let (a, b) = (pixel_at(&plain, &s.camera, top), pixel_at(&flipped, &s.camera, top));
        assert!((luma(a) - luma(b)).abs() < 3.0, "mirrored top {b:?} vs {a:?}");
    }

    #[test]
    fn bad_input_is_an_error_not_a_panic() {
        let Some(mut renderer) = renderer_or_skip("bad_input_is_an_error_not_a_panic") else {
            return;
        };
        let s = scene(&mut renderer);
        let zero = Camera {
            width_px: 0,
            ..s.camera
        };
        assert!(matches!(
            renderer.render(&zero, &s.items, &[]),
            Err(RenderError::EmptyImage { width_px: 0, .. })
        ));
        let huge = Camera {
            width_px: u32::MAX / 2,
            ..s.camera
        };
        assert!(matches!(
            renderer.render(&huge, &s.items, &[]),
            Err(RenderError::ImageTooLarge { .. })
        ));
        let blind = Camera {
            fov_y_deg: 0.0,
            ..s.camera
        };
        assert!(matches!(
            renderer.render(&blind, &[], &[]),
            Err(RenderError::FieldOfView { .. })
        ));
        let on_target = Camera {
            eye_in_world: s.camera.target_in_world,
            ..s.camera
        };
        assert!(matches!(
            renderer.render(&on_target, &[], &[]),
            Err(RenderError::Camera {
                problem: CameraProblem::EyeOnTarget
            })
        ));
        let top_down = Camera {
            eye_in_world: [0.0, 0.0, 5.0],
            target_in_world: [0.0, 0.0, 0.0],
            ..s.camera
        };
        assert!(matches!(
            renderer.render(&top_down, &[], &[]),
            Err(RenderError::Camera {
                problem: CameraProblem::UpAlongView
            })
        ));

        let mut broken = TriMesh::cuboid([1.0; 3]);
        broken.indices.push(999);
        broken.indices.extend_from_slice(&[0, 1]);
        let bad = renderer.upload_mesh(&broken);
        let mut bad_item = s.items[0];
        bad_item.mesh = bad;
        assert!(matches!(
            renderer.render(&s.camera, &[s.items[1], bad_item], &[]),
            Err(RenderError::InvalidMesh {
                item: 1,
                problem: MeshProblem::IndexOutOfRange { index: 999, .. },
                ..
            })
        ));
        let mut unknown = s.items[0];
        unknown.mesh = MeshId(9999);
        assert!(matches!(
            renderer.render(&s.camera, &[unknown], &[]),
            Err(RenderError::UnknownMesh { item: 0, mesh: 9999 })
        ));
        let mut nan = s.items[0];
        nan.world_from_mesh[3][0] = f32::NAN;
        assert!(matches!(
            renderer.render(&s.camera, &[nan], &[]),
            Err(RenderError::NonFiniteItem { item: 0 })
        ));
        let bad_line = LineStrip {
            points_in_world: vec![[0.0; 3], [f32::INFINITY, 0.0, 0.0]],
            color_rgba: MAGENTA,
        };
        assert!(matches!(
            renderer.render(&s.camera, &[], &[bad_line]),
            Err(RenderError::NonFiniteLine { strip: 0, point: 1 })
        ));

        // A strip reaching behind the camera renders (that segment is dropped).
        let behind: [f32; 3] = std::array::from_fn(|k| 2.0 * s.camera.eye_in_world[k] - s.camera.target_in_world[k]);
        let through_eye = LineStrip {
            points_in_world: vec![[0.0; 3], [0.5, 0.0, 0.0], behind],
            color_rgba: MAGENTA,
        };
        renderer
            .render(&s.camera, &[], &[through_eye])
            .expect("strip through the eye");

        // Empty meshes and short strips draw nothing, and the renderer still works.
        let empty = renderer.upload_mesh(&TriMesh::default());
        let mut empty_item = s.items[0];
        empty_item.mesh = empty;
        let short = LineStrip {
            points_in_world: vec![[0.0; 3]],
            color_rgba: MAGENTA,
        };
        let img = renderer
            .render(&s.camera, &[empty_item], &[short])
            .expect("render after errors");
        assert_eq!(img.get_pixel(0, 0).0, BACKGROUND_RGBA8);
    }

    #[test]
    fn frame_time_640x480() {
        let Some(mut renderer) = renderer_or_skip("frame_time_640x480") else {
            return;
        };
        let s = scene(&mut renderer);
        let camera = Camera {
            width_px: 640,
            height_px: 480,
            ..s.camera
        };
        save(
            &renderer.render(&camera, &s.items, &s.lines).expect("warm-up"),
            "scene-640x480.png",
        );
        let frames = 10;
        let start = std::time::Instant::now();
        for _ in 0..frames {
            renderer.render(&camera, &s.items, &s.lines).expect("render");
        }
        let per_frame = start.elapsed() / frames;
        eprintln!(
            "640x480 frame on {} ({:?}, {}x MSAA): {per_frame:?}",
            renderer.adapter_info().name,
            renderer.adapter_info().device_type,
            renderer.sample_count()
        );
    }
}
