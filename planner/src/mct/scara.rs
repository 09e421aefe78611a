//! SCARA independent: a two-link arm turning about vertical axes, plus the
//! vertical third axis shared by the source and target systems.
//!
//! Kinematic angles `θᵢ = Jᵢ + Zᵢ`. J1 turns L1 (J1 → J2) about X3, from +X1
//! towards +X2; J2 turns L2 (J2 → tool) relative to L1. The third axis is the
//! same axis in both coordinate systems (EXERR 16), so the transform passes
//! it through unchanged: `X3 = J3`.
//!
//! ```text
//! X1 = X1b + L1 cos θ1 + L2 cos(θ1 + θ2) + X1e
//! X2 = X2b + L1 sin θ1 + L2 sin(θ1 + θ2) + X2e
//! X3 = J3
//! ```
//!
//! X3b, X3e and Z3 are not used (the third axis is not transformed). Seen from
//! above, θ2 > 0 puts the elbow to the right of the line from J1 to the tool:
//! the **right arm** (solution bit 0 clear); θ2 < 0 is the **left arm**.

use super::{ArmSolution, PositionError, Vec3, planar_forward, planar_inverse, wrap_pi};

/// SCARA independent (validated by [`super::Geometry::new`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScaraIndependent {
    pub(crate) l1: f64,
    pub(crate) l2: f64,
    pub(crate) base: Vec3,
    pub(crate) effector: Vec3,
    pub(crate) zero_rad: Vec3,
}

impl ScaraIndependent {
    pub(crate) fn forward(&self, q: Vec3) -> Vec3 {
        let (px, py) = planar_forward(self.l1, self.l2, q[0] + self.zero_rad[0], q[1] + self.zero_rad[1]);
        [
            self.base[0] + px + self.effector[0],
            self.base[1] + py + self.effector[1],
            q[2],
        ]
    }

    pub(crate) fn inverse(&self, x: Vec3, solution: ArmSolution) -> Result<Vec3, PositionError> {
        let (a1, a2) = planar_inverse(
            self.l1,
            self.l2,
            x[0] - self.base[0] - self.effector[0],
            x[1] - self.base[1] - self.effector[1],
            solution.flipped(0),
            0,
        )?;
        Ok([wrap_pi(a1 - self.zero_rad[0]), wrap_pi(a2 - self.zero_rad[1]), x[2]])
    }

    pub(crate) fn solution(&self, q: Vec3) -> ArmSolution {
        ArmSolution::default().with(0, wrap_pi(q[1] + self.zero_rad[1]) < 0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::super::{ArmSolution, Geometry, GeometryKind, GeometryParams};

    #[test]
    fn scara_known_values_with_offsets_and_zero_angles() {
        let params = GeometryParams {
            link_lengths: [0.4, 0.3, 0.0],
            base_offsets: [0.1, -0.2, 5.0],
            end_effector_offsets: [0.01, 0.02, 7.0],
            zero_angles_deg: [90.0, -90.0, 33.0],
        };
        let g = Geometry::new(GeometryKind::ScaraIndependent, &params, 2).unwrap();
        // θ1 = 90° (L1 along +X2), θ2 = −90° relative (L2 along +X1): left arm.
        let x = g.forward([0.0, 0.0, 0.25]).unwrap();
        let expected = [0.1 + 0.3 + 0.01, -0.2 + 0.4 + 0.02, 0.25];
        for i in 0..3 {
            assert!((x[i] - expected[i]).abs() < 1e-15, "{x:?}");
        }
        assert_eq!(g.solution([0.0, 0.0, 0.25]).unwrap(), ArmSolution::LEFT_ARM);
        let q = g.inverse(x, ArmSolution::LEFT_ARM).unwrap();
        assert!(
            q.iter().zip([0.0, 0.0, 0.25]).all(|(a, b)| (a - b).abs() < 1e-12),
            "{q:?}"
        );
        // The right arm reaches the same point with the mirrored elbow.
        let r = g.inverse(x, ArmSolution::RIGHT_ARM).unwrap();
        assert_eq!(g.solution(r).unwrap(), ArmSolution::RIGHT_ARM);
        let back = g.forward(r).unwrap();
        assert!(back.iter().zip(x).all(|(a, b)| (a - b).abs() < 1e-12));
    }
}
