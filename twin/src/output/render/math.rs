//! The renderer's matrix math, through glam (f32, like the GPU).
//!
//! Matrices cross module and GPU boundaries as `[[f32; 4]; 4]` arrays of
//! columns: `m[c][r]` is row `r` of column `c`, the layout WGSL's
//! `mat4x4<f32>` expects (and glam's `from_cols_array_2d`). What glam
//! leaves to the caller is decided here: a degenerate camera is `None`
//! instead of a NaN matrix, and the normal matrix stays defined for
//! singular transforms.

use glam::camera::rh::{proj::directx, view};
use glam::{Mat4 as Matrix, Vec3};

/// A column-major 4x4 matrix.
pub(crate) type Mat4 = [[f32; 4]; 4];

pub(crate) fn mul(a: &Mat4, b: &Mat4) -> Mat4 {
    (Matrix::from_cols_array_2d(a) * Matrix::from_cols_array_2d(b)).to_cols_array_2d()
}

pub(crate) fn transform_point(m: &Mat4, p: [f32; 3]) -> [f32; 4] {
    (Matrix::from_cols_array_2d(m) * Vec3::from(p).extend(1.0)).to_array()
}

/// Right-handed view matrix: the camera at `eye` looks along -Z_view towards
/// `target`, +Y_view is `up` projected onto the image plane. `None` when the
/// eye sits on the target or `up` is parallel to the viewing direction.
pub(crate) fn look_at(eye: [f32; 3], target: [f32; 3], up: [f32; 3]) -> Option<Mat4> {
    let eye = Vec3::from(eye);
    let forward = (Vec3::from(target) - eye).try_normalize()?;
    let up = Vec3::from(up).try_normalize()?;
    forward.cross(up).try_normalize()?;
    Some(view::look_to_mat4(eye, forward, up).to_cols_array_2d())
}

/// Perspective projection with reversed depth and an infinite far plane:
/// depth 1 at `near_m`, tending to 0 at infinity (best precision with a
/// floating-point depth buffer). Clip space is wgpu's (depth 0..1, +Y up).
pub(crate) fn perspective_reversed_infinite(fov_y_rad: f32, aspect: f32, near_m: f32) -> Mat4 {
    // WebGPU's clip space is DirectX's.
    directx::perspective_infinite_reverse(fov_y_rad, aspect, near_m).to_cols_array_2d()
}

/// Normal matrix of an affine transform (columns, xyz used) scaled by a
/// positive factor, and the sign of the determinant (-1 when it mirrors).
/// It is the cofactor matrix (det * inverse transpose) with the sign of det
/// removed, so it stays defined for singular matrices.
pub(crate) fn normal_matrix(m: &Mat4) -> ([[f32; 3]; 3], f32) {
    let m = Matrix::from_cols_array_2d(m);
    let (c0, c1, c2) = (m.x_axis.truncate(), m.y_axis.truncate(), m.z_axis.truncate());
    let cof = [c1.cross(c2), c2.cross(c0), c0.cross(c1)];
    let det = c0.dot(cof[0]);
    let sign = if det < 0.0 { -1.0 } else { 1.0 };
    // Scale so the largest column has unit length: keeps tiny or huge
    // scales within f32 range before the shader renormalises.
    let largest = cof.iter().map(|c| c.length()).fold(0.0_f32, f32::max);
    let scale = if largest > 0.0 && largest.is_finite() {
        sign / largest
    } else {
        sign
    };
    (cof.map(|c| (c * scale).to_array()), sign)
}

/// Linear value of an sRGB-encoded channel (0..1).
pub(crate) fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn look_at_maps_target_onto_negative_view_z() {
        let view = look_at([3.0, -2.0, 1.5], [0.0, 0.0, 0.5], [0.0, 0.0, 1.0]).expect("valid camera");
        let t = transform_point(&view, [0.0, 0.0, 0.5]);
        let dist = Vec3::new(3.0, -2.0, 1.5).distance(Vec3::new(0.0, 0.0, 0.5));
        assert!(t[0].abs() < 1e-5 && t[1].abs() < 1e-5);
        assert!((t[2] + dist).abs() < 1e-5);
        // World up is up on screen: a point above the target has view y > 0.
        assert!(transform_point(&view, [0.0, 0.0, 1.0])[1] > 0.0);
    }

    #[test]
    fn degenerate_cameras_are_rejected() {
        assert!(look_at([1.0, 1.0, 1.0], [1.0, 1.0, 1.0], [0.0, 0.0, 1.0]).is_none());
        assert!(look_at([0.0, 0.0, 5.0], [0.0, 0.0, 0.0], [0.0, 0.0, 1.0]).is_none());
        assert!(look_at([1.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]).is_none());
    }

    #[test]
    fn reversed_depth_is_one_at_near_and_falls_with_distance() {
        let p = perspective_reversed_infinite(1.0, 1.5, 0.01);
        let near = transform_point(&p, [0.0, 0.0, -0.01]);
        let far = transform_point(&p, [0.0, 0.0, -100.0]);
        assert!((near[2] / near[3] - 1.0).abs() < 1e-6);
        assert!(far[2] / far[3] > 0.0 && far[2] / far[3] < 1e-3);
    }

    #[test]
    fn normal_matrix_handles_scale_and_mirror() {
        let m = [
            [2.0, 0.0, 0.0, 0.0],
            [0.0, -1.0, 0.0, 0.0],
            [0.0, 0.0, 4.0, 0.0],
            [1.0, 2.0, 3.0, 1.0],
        ];
        let (n, sign) = normal_matrix(&m);
        assert_eq!(sign, -1.0);
        // Inverse transpose of diag(2, -1, 4) is diag(0.5, -1, 0.25).
        assert!(n[0][0] > 0.0 && n[1][1] < 0.0 && n[2][2] > 0.0);
        assert!((n[0][0] / n[2][2] - 2.0).abs() < 1e-6);
        let (z, _) = normal_matrix(&[[0.0; 4]; 4]);
        assert!(z.iter().flatten().all(|v| *v == 0.0));
    }

    #[test]
    fn srgb_round_trips_through_eight_bits() {
        for v in 0..=255_u8 {
            let lin = srgb_to_linear(f32::from(v) / 255.0);
            let back = if lin <= 0.003_130_8 {
                lin * 12.92
            } else {
                1.055 * lin.powf(1.0 / 2.4) - 0.055
            };
            assert_eq!((back * 255.0).round() as u8, v);
        }
    }
}
