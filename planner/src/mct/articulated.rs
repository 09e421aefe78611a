//! Articulated robots: independent (2D and 3D) and dependent.
//!
//! Kinematic angles are `θᵢ = Jᵢ + Zᵢ` (radians).
//!
//! # Three dimensions (J1 waist, J2 shoulder, J3 elbow)
//! * J1 turns the arm about X3; at θ1 = 0 the arm plane is the X1–X3 plane,
//!   positive θ1 turns it from X1 towards X2.
//! * In the arm plane, with `r` the radial (horizontal) and `h` the vertical
//!   coordinate: θ2 is the angle of L1 (J2 → J3) above the horizontal; for
//!   the **independent** robot θ3 is the angle of L2 (J3 → tool) relative to
//!   L1, for the **dependent** robot (parallelogram drive) θ3 is the angle of
//!   L2 above the horizontal. All zero: both links horizontal along +X1.
//! * Base offsets: J2 sits X1b out along the arm direction, X2b sideways
//!   (towards +X2 at θ1 = 0) and X3b up from the base origin. End-effector
//!   offsets: the tool sits X1e further along the arm direction, X2e sideways
//!   and X3e up from the end of L2 (the wrist is assumed to keep its
//!   orientation, as in Logix for these geometries).
//!
//! ```text
//! r = X1b + L1 cos θ2 + L2 cos(θ2 + θ3') + X1e      θ3' = θ3 (independent)
//! h = X3b + L1 sin θ2 + L2 sin(θ2 + θ3') + X3e      θ3' = θ3 − θ2 (dependent)
//! t = X2b + X2e
//! X1 = r cos θ1 − t sin θ1,  X2 = r sin θ1 + t cos θ1,  X3 = h
//! ```
//!
//! Arm solutions: bit 0 (left arm) = negative relative elbow angle θ3';
//! bit 1 (back) = the radial distance `r` is negative (the arm reaches over
//! the waist axis). The waist singularity (the tool on the circle
//! `X1² + X2² = t²`, where front and back meet) is refused when the radial
//! distance is under `SINGULARITY_MARGIN_RAD · (L1 + L2)`.
//!
//! # Two dimensions (J1 shoulder, J2 elbow)
//! The arm moves in the X1–X2 plane, X2 taking the vertical role ("X3b and
//! X3e are X2b and X2e"): `X1 = X1b + L1 cos θ1 + L2 cos(θ1 + θ2') + X1e`,
//! `X2 = X2b + L1 sin θ1 + L2 sin(θ1 + θ2') + X2e`, `θ2'` relative as above.

use super::{ArmSolution, PositionError, SINGULARITY_MARGIN_RAD, Vec3, planar_forward, planar_inverse, wrap_pi};

/// An articulated robot (validated by [`super::Geometry::new`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Articulated {
    pub(crate) dependent: bool,
    pub(crate) dimension: usize,
    pub(crate) l1: f64,
    pub(crate) l2: f64,
    pub(crate) base: Vec3,
    pub(crate) effector: Vec3,
    pub(crate) zero_rad: Vec3,
}

impl Articulated {
    /// Shoulder and relative elbow angle from the two arm joints.
    fn link_angles(&self, shoulder_q: f64, elbow_q: f64, shoulder_z: f64, elbow_z: f64) -> (f64, f64) {
        let a1 = shoulder_q + shoulder_z;
        let e = elbow_q + elbow_z;
        (a1, if self.dependent { e - a1 } else { e })
    }

    /// Joint positions from shoulder and relative elbow angles.
    fn joints(&self, a1: f64, a2: f64, shoulder_z: f64, elbow_z: f64) -> (f64, f64) {
        let e = if self.dependent { a1 + a2 } else { a2 };
        (wrap_pi(a1 - shoulder_z), wrap_pi(e - elbow_z))
    }

    pub(crate) fn forward(&self, q: Vec3) -> Vec3 {
        let (b, e, z) = (self.base, self.effector, self.zero_rad);
        if self.dimension == 2 {
            let (a1, a2) = self.link_angles(q[0], q[1], z[0], z[1]);
            let (px, py) = planar_forward(self.l1, self.l2, a1, a2);
            return [b[0] + px + e[0], b[1] + py + e[1], 0.0];
        }
        let (a1, a2) = self.link_angles(q[1], q[2], z[1], z[2]);
        let (pr, ph) = planar_forward(self.l1, self.l2, a1, a2);
        let r = b[0] + pr + e[0];
        let t = b[1] + e[1];
        let (s, c) = (q[0] + z[0]).sin_cos();
        [r * c - t * s, r * s + t * c, b[2] + ph + e[2]]
    }

    pub(crate) fn inverse(&self, x: Vec3, solution: ArmSolution) -> Result<Vec3, PositionError> {
        let (b, e, z) = (self.base, self.effector, self.zero_rad);
        let left = solution.flipped(0);
        if self.dimension == 2 {
            let (a1, a2) = planar_inverse(self.l1, self.l2, x[0] - b[0] - e[0], x[1] - b[1] - e[1], left, 0)?;
            let (q1, q2) = self.joints(a1, a2, z[0], z[1]);
            return Ok([q1, q2, 0.0]);
        }
        let t = b[1] + e[1];
        let rho2 = x[0] * x[0] + x[1] * x[1] - t * t;
        if rho2 < 0.0 {
            return Err(PositionError::OutOfReach {
                chain: 0,
                excess: t.abs() - x[0].hypot(x[1]),
            });
        }
        let rho = rho2.sqrt();
        let margin = SINGULARITY_MARGIN_RAD * (self.l1 + self.l2);
        if rho < margin {
            return Err(PositionError::Singularity {
                chain: 1,
                angle_rad: rho / (self.l1 + self.l2),
                margin_rad: SINGULARITY_MARGIN_RAD,
            });
        }
        let r = if solution.flipped(1) { -rho } else { rho };
        let waist = x[1].atan2(x[0]) - t.atan2(r);
        let (a1, a2) = planar_inverse(self.l1, self.l2, r - b[0] - e[0], x[2] - b[2] - e[2], left, 0)?;
        let (q2, q3) = self.joints(a1, a2, z[1], z[2]);
        Ok([wrap_pi(waist - z[0]), q2, q3])
    }

    pub(crate) fn solution(&self, q: Vec3) -> ArmSolution {
        let (b, e, z) = (self.base, self.effector, self.zero_rad);
        if self.dimension == 2 {
            let (_, a2) = self.link_angles(q[0], q[1], z[0], z[1]);
            return ArmSolution::default().with(0, wrap_pi(a2) < 0.0);
        }
        let (a1, a2) = self.link_angles(q[1], q[2], z[1], z[2]);
        let (pr, _) = planar_forward(self.l1, self.l2, a1, a2);
        ArmSolution::default()
            .with(0, wrap_pi(a2) < 0.0)
            .with(1, b[0] + pr + e[0] < 0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::super::{ArmSolution, Geometry, GeometryKind, GeometryParams, PositionError};

    fn params() -> GeometryParams {
        GeometryParams {
            link_lengths: [1.0, 0.5, 0.0],
            ..Default::default()
        }
    }

    #[test]
    fn independent_3d_known_values() {
        let g = Geometry::new(GeometryKind::ArticulatedIndependent, &params(), 3).unwrap();
        // All zero: stretched along +X1.
        let x = g.forward([0.0; 3]).unwrap();
        assert_eq!(x, [1.5, 0.0, 0.0]);
        // Waist 90°, shoulder up 90°, elbow 90°: L1 up, L2 back along −(arm dir) = −X2.
        let h = std::f64::consts::FRAC_PI_2;
        let x = g.forward([h, h, h]).unwrap();
        assert!(
            (x[0] - 0.0).abs() < 1e-15 && (x[1] + 0.5).abs() < 1e-15 && (x[2] - 1.0).abs() < 1e-15,
            "{x:?}"
        );
    }

    #[test]
    fn dependent_elbow_is_measured_from_the_horizontal() {
        let ind = Geometry::new(GeometryKind::ArticulatedIndependent, &params(), 3).unwrap();
        let dep = Geometry::new(GeometryKind::ArticulatedDependent, &params(), 3).unwrap();
        let q = [0.3, 0.7, -0.2];
        let a = ind.forward(q).unwrap();
        let b = dep.forward([0.3, 0.7, 0.7 - 0.2]).unwrap();
        for i in 0..3 {
            assert!((a[i] - b[i]).abs() < 1e-15);
        }
    }

    #[test]
    fn stretched_and_folded_and_beyond_reach_are_refused() {
        let g = Geometry::new(GeometryKind::ArticulatedIndependent, &params(), 2).unwrap();
        assert!(matches!(
            g.inverse([1.5, 0.0, 0.0], ArmSolution::RIGHT_ARM),
            Err(PositionError::Singularity { .. })
        ));
        assert!(matches!(
            g.inverse([0.5, 0.0, 0.0], ArmSolution::RIGHT_ARM),
            Err(PositionError::Singularity { .. })
        ));
        match g.inverse([1.75, 0.0, 0.0], ArmSolution::RIGHT_ARM) {
            Err(PositionError::OutOfReach { excess, .. }) => assert!((excess - 0.25).abs() < 1e-15),
            other => panic!("{other:?}"),
        }
        match g.inverse([0.25, 0.0, 0.0], ArmSolution::LEFT_ARM) {
            Err(PositionError::OutOfReach { excess, .. }) => assert!((excess - 0.25).abs() < 1e-15),
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn waist_axis_is_a_singularity() {
        let g = Geometry::new(GeometryKind::ArticulatedIndependent, &params(), 3).unwrap();
        assert!(matches!(
            g.inverse([0.0, 0.0, 1.0], ArmSolution::RIGHT_ARM),
            Err(PositionError::Singularity { chain: 1, .. })
        ));
    }
}
