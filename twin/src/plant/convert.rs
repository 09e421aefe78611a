//! Every conversion between nalgebra, URDF and rapier's glam-based math types.
//!
//! rapier 0.36 speaks `glamx` (glam `DVec3`, `DQuat`, `DPose3` in its f64
//! build); the robot model and the `planner` speak nalgebra; URDF files speak
//! `xyz` + `rpy`. Keeping the conversions here, component by component, means
//! a version bump of either side breaks exactly one file.
//!
//! URDF, nalgebra and rapier all use the same right-handed Z-up frames and
//! metres here: nothing in this module changes axes or units.

use nalgebra::{Isometry3, Matrix3, Quaternion, Translation3, UnitQuaternion, Vector3};
use rapier3d_f64::math::{Matrix, Pose, Rotation, Vector};

/// `parent_from_child` of a URDF `<origin xyz=".." rpy=".."/>`: translation in
/// metres, then fixed-axis roll about X, pitch about Y, yaw about Z (radians),
/// i.e. `R = Rz(yaw) · Ry(pitch) · Rx(roll)` as the URDF spec defines.
pub fn isometry_from_urdf_pose(pose: &urdf_rs::Pose) -> Isometry3<f64> {
    let [x, y, z] = pose.xyz.0;
    let [roll, pitch, yaw] = pose.rpy.0;
    Isometry3::from_parts(
        Translation3::new(x, y, z),
        UnitQuaternion::from_euler_angles(roll, pitch, yaw),
    )
}

/// nalgebra vector → rapier vector (same frame, same units).
pub fn vector_to_rapier(v: &Vector3<f64>) -> Vector {
    Vector::new(v.x, v.y, v.z)
}

/// rapier vector → nalgebra vector (same frame, same units).
pub fn vector_from_rapier(v: Vector) -> Vector3<f64> {
    Vector3::new(v.x, v.y, v.z)
}

/// nalgebra unit quaternion → rapier rotation.
pub fn rotation_to_rapier(q: &UnitQuaternion<f64>) -> Rotation {
    Rotation::from_xyzw(q.i, q.j, q.k, q.w)
}

/// rapier rotation → nalgebra unit quaternion (renormalised).
pub fn rotation_from_rapier(q: Rotation) -> UnitQuaternion<f64> {
    UnitQuaternion::from_quaternion(Quaternion::new(q.w, q.x, q.y, q.z))
}

/// nalgebra isometry → rapier pose (`a_from_b` stays `a_from_b`).
pub fn pose_to_rapier(iso: &Isometry3<f64>) -> Pose {
    Pose::from_parts(
        vector_to_rapier(&iso.translation.vector),
        rotation_to_rapier(&iso.rotation),
    )
}

/// rapier pose → nalgebra isometry (`a_from_b` stays `a_from_b`).
pub fn pose_from_rapier(pose: &Pose) -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::from(vector_from_rapier(pose.translation)),
        rotation_from_rapier(pose.rotation),
    )
}

/// nalgebra 3×3 matrix → rapier matrix (e.g. an inertia tensor in kg·m²).
pub fn matrix_to_rapier(m: &Matrix3<f64>) -> Matrix {
    Matrix::from_cols(
        vector_to_rapier(&m.column(0).into_owned()),
        vector_to_rapier(&m.column(1).into_owned()),
        vector_to_rapier(&m.column(2).into_owned()),
    )
}

/// Plain arrays (translation m, quaternion `[x, y, z, w]`) as an isometry:
/// the inverse of [`isometry_to_arrays`].
pub fn isometry_from_arrays((t, q): &([f64; 3], [f64; 4])) -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::new(t[0], t[1], t[2]),
        UnitQuaternion::from_quaternion(Quaternion::new(q[3], q[0], q[1], q[2])),
    )
}

/// An isometry as plain arrays: translation in metres and the rotation as a
/// unit quaternion `[x, y, z, w]`, the layout Rerun and most renderers take.
pub fn isometry_to_arrays(iso: &Isometry3<f64>) -> ([f64; 3], [f64; 4]) {
    let t = iso.translation.vector;
    let q = iso.rotation;
    ([t.x, t.y, t.z], [q.i, q.j, q.k, q.w])
}

#[cfg(test)]
#[allow(clippy::unwrap_used)] // a failed unwrap is a failed test
mod tests {
    use super::*;

    fn sample() -> Isometry3<f64> {
        Isometry3::from_parts(
            Translation3::new(0.1, -0.2, 0.3),
            UnitQuaternion::from_euler_angles(0.3, -0.7, 2.1),
        )
    }

    #[test]
    fn pose_round_trip_is_exact_enough() {
        let iso = sample();
        let back = pose_from_rapier(&pose_to_rapier(&iso));
        assert!((back.translation.vector - iso.translation.vector).norm() < 1e-15);
        assert!(back.rotation.angle_to(&iso.rotation) < 1e-12);
    }

    #[test]
    fn rapier_and_nalgebra_compose_and_transform_alike() {
        let a = sample();
        let b = Isometry3::from_parts(
            Translation3::new(-1.0, 0.5, 2.0),
            UnitQuaternion::from_euler_angles(-1.0, 0.2, 0.4),
        );
        let p = Vector3::new(0.3, 0.4, -0.5);
        let na = (a * b).transform_vector(&p) + (a * b).translation.vector;
        let rp = (pose_to_rapier(&a) * pose_to_rapier(&b)).transform_point(vector_to_rapier(&p));
        assert!((vector_from_rapier(rp) - na).norm() < 1e-12);
    }

    #[test]
    fn urdf_rpy_is_fixed_axis_xyz() {
        let pose = urdf_rs::Pose {
            xyz: urdf_rs::Vec3([1.0, 2.0, 3.0]),
            rpy: urdf_rs::Vec3([0.0, 0.0, std::f64::consts::FRAC_PI_2]),
        };
        let iso = isometry_from_urdf_pose(&pose);
        // Yaw of +90°: the child's X axis points along the parent's Y axis.
        let x_in_parent = iso.rotation * Vector3::x();
        assert!((x_in_parent - Vector3::y()).norm() < 1e-12);
        assert_eq!(isometry_to_arrays(&iso).0, [1.0, 2.0, 3.0]);
    }

    #[test]
    fn matrix_columns_survive() {
        let m = Matrix3::new(1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0);
        let r = matrix_to_rapier(&m);
        assert_eq!(r.col(0).to_array(), [1.0, 4.0, 7.0]);
        assert_eq!(r.col(2).to_array(), [3.0, 6.0, 9.0]);
    }
}
