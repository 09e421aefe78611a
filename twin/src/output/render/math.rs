//! Small column-major matrix helpers for the renderer (f32, like the GPU).
//!
//! Matrices are `[[f32; 4]; 4]` arrays of columns: `m[c][r]` is row `r` of
//! column `c`, the layout WGSL's `mat4x4<f32>` expects.

/// A column-major 4x4 matrix.
pub(crate) type Mat4 = [[f32; 4]; 4];

pub(crate) fn sub(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

pub(crate) fn dot(a: [f32; 3], b: [f32; 3]) -> f32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

pub(crate) fn cross(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

pub(crate) fn length(a: [f32; 3]) -> f32 {
    dot(a, a).sqrt()
}

/// `a / |a|`, or `None` when `a` is (nearly) zero or not finite.
pub(crate) fn normalize(a: [f32; 3]) -> Option<[f32; 3]> {
    let len = length(a);
    (len.is_finite() && len > 1e-12).then(|| a.map(|c| c / len))
}

pub(crate) fn mul(a: &Mat4, b: &Mat4) -> Mat4 {
    std::array::from_fn(|c| std::array::from_fn(|r| (0..4).map(|k| a[k][r] * b[c][k]).sum()))
}

pub(crate) fn transform_point(m: &Mat4, p: [f32; 3]) -> [f32; 4] {
    std::array::from_fn(|r| m[0][r] * p[0] + m[1][r] * p[1] + m[2][r] * p[2] + m[3][r])
}

/// Right-handed view matrix: the camera at `eye` looks along -Z_view towards
/// `target`, +Y_view is `up` projected onto the image plane. `None` when the
/// eye sits on the target or `up` is parallel to the viewing direction.
pub(crate) fn look_at(eye: [f32; 3], target: [f32; 3], up: [f32; 3]) -> Option<Mat4> {
    let f = normalize(sub(target, eye))?;
    let s = normalize(cross(f, normalize(up)?))?;
    let u = cross(s, f);
    Some([
        [s[0], u[0], -f[0], 0.0],
        [s[1], u[1], -f[1], 0.0],
        [s[2], u[2], -f[2], 0.0],
        [-dot(s, eye), -dot(u, eye), dot(f, eye), 1.0],
    ])
}

/// Perspective projection with reversed depth and an infinite far plane:
/// depth 1 at `near_m`, tending to 0 at infinity (best precision with a
/// floating-point depth buffer). Clip space is wgpu's (depth 0..1, +Y up).
pub(crate) fn perspective_reversed_infinite(fov_y_rad: f32, aspect: f32, near_m: f32) -> Mat4 {
    let f = 1.0 / (0.5 * fov_y_rad).tan();
    [
        [f / aspect, 0.0, 0.0, 0.0],
        [0.0, f, 0.0, 0.0],
        [0.0, 0.0, 0.0, -1.0],
        [0.0, 0.0, near_m, 0.0],
    ]
}

/// Normal matrix of an affine transform (columns, xyz used) scaled by a
/// positive factor, and the sign of the determinant (-1 when it mirrors).
/// It is the cofactor matrix (det * inverse transpose) with the sign of det
/// removed, so it stays defined for singular matrices.
pub(crate) fn normal_matrix(m: &Mat4) -> ([[f32; 3]; 3], f32) {
    let col = |c: usize| [m[c][0], m[c][1], m[c][2]];
    let cof = [cross(col(1), col(2)), cross(col(2), col(0)), cross(col(0), col(1))];
    let det = dot(col(0), cof[0]);
    let sign = if det < 0.0 { -1.0 } else { 1.0 };
    // Scale so the largest column has unit length: keeps tiny or huge
    // scales within f32 range before the shader renormalises.
    let largest = cof.iter().map(|c| length(*c)).fold(0.0_f32, f32::max);
    let scale = if largest > 0.0 && largest.is_finite() {
        sign / largest
    } else {
        sign
    };
    (cof.map(|c| c.map(|v| v * scale)), sign)
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
        let dist = length(sub([3.0, -2.0, 1.5], [0.0, 0.0, 0.5]));
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
