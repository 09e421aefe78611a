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

mod camera;
mod error;
mod gpu;
mod math;

pub use camera::{Camera, NEAR_PLANE_M};
pub use error::{CameraProblem, MeshProblem, ReadbackStage, RenderError};
use gpu::{
    COLOR_FORMAT, DEPTH_FORMAT, GLOBALS_BYTES, GpuMesh, GrowBuffer, INSTANCE_BYTES, PipelineBuilder, SEGMENT_BYTES,
    Target, VERTEX_BYTES, globals_bytes, line_bytes, push_f32s, read_image, validate_mesh,
};
pub use gpu::{LINE_WIDTH_PX, LineStrip};

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, mpsc};

use crate::plant::mesh::TriMesh;

/// The line a caller prints when [`Renderer::new`] finds no Vulkan adapter.
pub const NO_ADAPTER_HINT: &str = "no Vulkan adapter found: frames are not rendered \
     (install Mesa's software driver: apt-get install mesa-vulkan-drivers)";

/// The background colour of every image (sRGB, 8 bits per channel).
pub const BACKGROUND_RGBA8: [u8; 4] = [206, 211, 217, 255];

/// Samples per pixel when the adapter supports multisampling.
const MSAA_SAMPLES: u32 = 4;

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

#[cfg(test)]
mod tests;
