//! The pinhole camera and the view/projection it gives the shader.

use glam::Vec3;

use super::error::{CameraProblem, RenderError};
use super::math::{self, Mat4};

/// Distance from the eye to the near clipping plane (metres).
pub const NEAR_PLANE_M: f32 = 0.01;

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
pub(super) struct CameraFrame {
    pub(super) clip_from_world: Mat4,
    pub(super) to_light_in_world: [f32; 3],
}

impl Camera {
    /// Validates the camera and derives its matrices and light direction.
    pub(super) fn frame(&self) -> Result<CameraFrame, RenderError> {
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
        let forward = (Vec3::from(target) - Vec3::from(eye))
            .try_normalize()
            .ok_or(RenderError::Camera {
                problem: CameraProblem::EyeOnTarget,
            })?;
        let up = Vec3::from(self.up_in_world)
            .try_normalize()
            .ok_or(RenderError::Camera {
                problem: CameraProblem::UpAlongView,
            })?;
        let view = math::look_at(eye, target, up.to_array()).ok_or(RenderError::Camera {
            problem: CameraProblem::UpAlongView,
        })?;
        let aspect = width_px as f32 / height_px as f32;
        let proj = math::perspective_reversed_infinite(self.fov_y_deg.to_radians(), aspect, NEAR_PLANE_M);
        let right = forward.cross(up).try_normalize().ok_or(RenderError::Camera {
            problem: CameraProblem::UpAlongView,
        })?;
        // Above, behind and to the left of the camera.
        let to_light_in_world = (up - 0.6 * forward - 0.5 * right)
            .try_normalize()
            .unwrap_or(up)
            .to_array();
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
