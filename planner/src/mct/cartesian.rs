//! Cartesian geometries: gantry and H-bot.
//!
//! * **Gantry**: joint *i* moves Cartesian axis *i*:
//!   `Xᵢ = Jᵢ + Xᵢb + Xᵢe` for the transformed axes (dimension 1–3).
//! * **H-bot**: two motors J1, J2 drive one belt; with the belt travel of
//!   each motor in coordinate units, `X1 = (J1 + J2)/2 + X1b + X1e`,
//!   `X2 = (J1 − J2)/2 + X2b + X2e`, and (dimension 3) the third axis like a
//!   gantry axis, `X3 = J3 + X3b + X3e`. Inverse: `J1 = u + v`, `J2 = u − v`
//!   with `u`, `v` the offset-free X1, X2.
//!
//! Link lengths and zero angles are not used. Both have one arm solution and
//! no singularity. Untransformed elements (beyond the dimension) are 0.

use super::Vec3;

/// Cartesian gantry (validated by [`super::Geometry::new`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gantry {
    pub(crate) dimension: usize,
    /// Base plus end-effector offset per axis.
    pub(crate) offset: Vec3,
}

impl Gantry {
    pub(crate) fn forward(&self, q: Vec3) -> Vec3 {
        let mut x = [0.0; 3];
        for i in 0..self.dimension {
            x[i] = q[i] + self.offset[i];
        }
        x
    }

    pub(crate) fn inverse(&self, x: Vec3) -> Vec3 {
        let mut q = [0.0; 3];
        for i in 0..self.dimension {
            q[i] = x[i] - self.offset[i];
        }
        q
    }
}

/// Cartesian H-bot (validated by [`super::Geometry::new`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HBot {
    pub(crate) dimension: usize,
    pub(crate) offset: Vec3,
}

impl HBot {
    pub(crate) fn forward(&self, q: Vec3) -> Vec3 {
        let z = if self.dimension == 3 {
            q[2] + self.offset[2]
        } else {
            0.0
        };
        [
            0.5 * (q[0] + q[1]) + self.offset[0],
            0.5 * (q[0] - q[1]) + self.offset[1],
            z,
        ]
    }

    pub(crate) fn inverse(&self, x: Vec3) -> Vec3 {
        let u = x[0] - self.offset[0];
        let v = x[1] - self.offset[1];
        let z = if self.dimension == 3 {
            x[2] - self.offset[2]
        } else {
            0.0
        };
        [u + v, u - v, z]
    }
}

#[cfg(test)]
mod tests {
    use super::super::{ArmSolution, Geometry, GeometryKind, GeometryParams};

    #[test]
    fn hbot_known_values() {
        let params = GeometryParams {
            base_offsets: [1.0, 2.0, 3.0],
            end_effector_offsets: [0.5, 0.25, -1.0],
            ..Default::default()
        };
        let g = Geometry::new(GeometryKind::CartesianHBot, &params, 3).unwrap();
        // Both motors forward by 1: pure X1; opposite: pure X2.
        assert_eq!(g.forward([1.0, 1.0, 0.0]).unwrap(), [2.5, 2.25, 2.0]);
        assert_eq!(g.forward([1.0, -1.0, 4.0]).unwrap(), [1.5, 3.25, 6.0]);
        assert_eq!(
            g.inverse([1.5, 3.25, 6.0], ArmSolution::default()).unwrap(),
            [1.0, -1.0, 4.0]
        );
    }

    #[test]
    fn gantry_known_values_and_unused_axes_stay_zero() {
        let params = GeometryParams {
            base_offsets: [1.0, 2.0, 3.0],
            end_effector_offsets: [0.5, 0.5, 0.5],
            ..Default::default()
        };
        let g = Geometry::new(GeometryKind::CartesianGantry, &params, 2).unwrap();
        assert_eq!(g.forward([1.0, 1.0, 9.0]).unwrap(), [2.5, 3.5, 0.0]);
        assert_eq!(
            g.inverse([2.5, 3.5, 9.0], ArmSolution::default()).unwrap(),
            [1.0, 1.0, 0.0]
        );
    }
}
