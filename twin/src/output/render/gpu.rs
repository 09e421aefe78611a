//! GPU-side resources (meshes, targets, growable buffers, pipelines) and
//! the bytes uploaded to them each frame.

use super::camera::{Camera, CameraFrame};
use super::error::{MeshProblem, ReadbackStage, RenderError};
use super::math;
use crate::plant::mesh::TriMesh;

/// Colour format of the render target; sRGB so blending happens in linear light.
pub(super) const COLOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
pub(super) const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// Bytes per mesh vertex: position and normal, three f32 each.
pub(super) const VERTEX_BYTES: u64 = 24;
/// Bytes per instance: world_from_mesh (4 vec4), normal matrix (3 vec4), colour.
pub(super) const INSTANCE_BYTES: u64 = 128;
/// Bytes per line segment: start and end (3 f32 each) and colour (4 f32).
pub(super) const SEGMENT_BYTES: u64 = 40;
/// Bytes of the `Globals` uniform block in `scene.wgsl`.
pub(super) const GLOBALS_BYTES: u64 = 128;
/// Width of trail lines (pixels).
pub const LINE_WIDTH_PX: f32 = 2.0;
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

/// A mesh as stored by the renderer.
#[derive(Debug)]
pub(super) enum GpuMesh {
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
pub(super) struct Target {
    pub(super) width_px: u32,
    pub(super) height_px: u32,
    /// Multisampled colour attachment; `None` without MSAA.
    pub(super) msaa_view: Option<wgpu::TextureView>,
    /// Single-sampled colour texture that is copied back.
    pub(super) resolved: wgpu::Texture,
    pub(super) resolved_view: wgpu::TextureView,
    pub(super) depth_view: wgpu::TextureView,
    pub(super) readback: wgpu::Buffer,
    pub(super) padded_bytes_per_row: u32,
}

/// A vertex buffer that grows (by doubling) and is reused between frames.
#[derive(Debug)]
pub(super) struct GrowBuffer {
    pub(super) buffer: wgpu::Buffer,
    pub(super) capacity: u64,
    pub(super) label: &'static str,
}

impl GrowBuffer {
    pub(super) fn new(device: &wgpu::Device, label: &'static str, capacity: u64) -> GrowBuffer {
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

    pub(super) fn write(&mut self, device: &wgpu::Device, queue: &wgpu::Queue, bytes: &[u8]) {
        let needed = bytes.len() as u64;
        if needed > self.capacity {
            *self = GrowBuffer::new(device, self.label, needed.next_power_of_two());
        }
        if !bytes.is_empty() {
            queue.write_buffer(&self.buffer, 0, bytes);
        }
    }
}

/// Copies the mapped, row-padded readback buffer into an image.
pub(super) fn read_image(
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
pub(super) fn validate_mesh(mesh: &TriMesh, max_buffer_bytes: u64) -> Result<(), MeshProblem> {
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
pub(super) fn line_bytes(lines: &[LineStrip]) -> Result<Vec<u8>, RenderError> {
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
pub(super) fn globals_bytes(camera: &Camera, frame: &CameraFrame) -> Vec<u8> {
    let eye = camera.eye_in_world;
    let distance = glam::Vec3::from(camera.target_in_world).distance(glam::Vec3::from(eye));
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

pub(super) fn push_f32s(bytes: &mut Vec<u8>, values: &[f32]) {
    for v in values {
        bytes.extend_from_slice(&v.to_le_bytes());
    }
}

/// Shared settings of the three pipelines.
pub(super) struct PipelineBuilder<'a> {
    pub(super) device: &'a wgpu::Device,
    pub(super) layout: &'a wgpu::PipelineLayout,
    pub(super) module: &'a wgpu::ShaderModule,
    pub(super) sample_count: u32,
}

impl PipelineBuilder<'_> {
    /// A pipeline using `vs_<name>` / `fs_<name>`, alpha blending and reversed depth.
    pub(super) fn build(
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
