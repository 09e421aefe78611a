//! Parallel robots: Delta 3D, Delta 2D and SCARA Delta.
//!
//! Kinematic angles `θᵢ = Jᵢ + Zᵢ`. As in Logix, a joint is 0 when its upper
//! arm (L1) is horizontal pointing outward, and positive when the arm moves
//! down (towards the work space). Each forearm (L2, a parallelogram) joins
//! the end of its upper arm to the moving platform.
//!
//! # Delta 3D
//! * Upper arm *i* turns in the vertical plane at azimuth `φᵢ = 0°, 120°,
//!   240°` about X3 (arm 1 along +X1, then counter-clockwise seen from
//!   above). Its joint axis is X1b from the centre, at height X3b.
//! * The forearms reach the platform X1e from the platform centre; the tool
//!   sits X3e above the platform centre (give a negative X3e for a tool
//!   below the platform). X2b, X2e, L3 are not used.
//! * EXERR 15: X1b − X1e ≥ 0 and L1 + (X1b − X1e) ≤ L2.
//! * Forward kinematics intersects the three spheres of radius L2 around the
//!   elbows (shifted inward by X1e); of the two intersections the one below
//!   the elbows is the platform. Forearms that cannot meet, or three elbows
//!   on one line, give ERR 67.
//!
//! # Delta 2D and SCARA Delta (five-bar)
//! * Two upper arms: arm 1's joint at `X1 = +X1b` pointing to +X1 at zero,
//!   arm 2's at `X1 = −X1b` pointing to −X1 (mirror image); forearms reach the
//!   platform at ±X1e.
//! * **Delta 2D** moves in the vertical X1–X2 plane: the joint axes are at
//!   height X2b, the work space is below (−X2), the tool is X2e above the
//!   platform centre. The third element is 0.
//! * **SCARA Delta** moves in the horizontal X1–X2 plane: the joint axes are
//!   at X2 = X2b, the work space is in front (+X2), "down" meaning towards
//!   +X2; the tool is X2e from the platform centre along X2. The third axis
//!   is shared with the source system and passed through (`X3 = J3`); only
//!   X1b − X1e ≥ 0 is required (EXERR 15).
//! * Forward kinematics intersects the two circles of radius L2 and takes the
//!   intersection on the work-space side.
//!
//! # Assembly mode
//! Forward kinematics always gives the platform on the work-space side of
//! the (shifted) elbows. An inverse solution — typically one with a knee
//! flipped — that would hold the platform on the other side is refused with
//! [`PositionError::OtherAssembly`], and one within
//! `SINGULARITY_MARGIN_RAD · L2` of the elbows' plane (the forearms
//! coplanar: the parallel singularity, where the platform loses stiffness)
//! with [`PositionError::Singularity`] (chain 3). So every inverse solution
//! is one the forward kinematics gives back.
//!
//! # Arm solutions and singularities
//! For arm *i*, the inverse kinematics solves `u cos θ − w sin θ = K` with
//! `(u, w)` the platform point in the arm's plane; with `α = atan2(w, u)` and
//! `β = acos(K / √(u² + w²))`, the usual knee-outward pose is `θ = −α − β`
//! (solution bit *i* clear) and the mirror pose `θ = −α + β` (bit set). The
//! two meet when β is 0 or π (upper arm collinear with the forearm's
//! projection) — Logix's computed joint-limit condition; positions with β
//! within [`super::SINGULARITY_MARGIN_RAD`] of 0 or π are refused.

use super::{ArmSolution, PositionError, Vec3, check_branch, wrap_pi};
use crate::vector::{cross, dot, norm, scale, sub};
use std::f64::consts::PI;

/// Delta 3D (validated by [`super::Geometry::new`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Delta3d {
    /// Its arms (heights along X3).
    pub(crate) arms: DeltaArms,
}

/// The dimensions every delta robot has: arm lengths `L1` and `L2`, the
/// offset X1b − X1e, the base and effector heights along the axis the arms
/// turn in (X3 for Delta 3D, X2 for Delta 2D and SCARA Delta) and the
/// joints' zero angles.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DeltaArms {
    pub(crate) l1: f64,
    pub(crate) l2: f64,
    pub(crate) offset: f64,
    pub(crate) base_height: f64,
    pub(crate) effector_height: f64,
    pub(crate) zero_rad: Vec3,
}

const AZIMUTH_RAD: [f64; 3] = [0.0, 2.0 * PI / 3.0, 4.0 * PI / 3.0];

/// Solves `u cos θ − w sin θ = K` for one arm, with `v` the out-of-plane
/// coordinate (0 for the planar robots).
fn arm_angle(l1: f64, l2: f64, u: f64, v: f64, w: f64, flipped: bool, chain: u8) -> Result<f64, PositionError> {
    let rho = u.hypot(w);
    let nearest = (rho - l1).hypot(v);
    let farthest = (rho + l1).hypot(v);
    if nearest > l2 {
        return Err(PositionError::OutOfReach {
            chain,
            excess: nearest - l2,
        });
    }
    if farthest < l2 {
        return Err(PositionError::OutOfReach {
            chain,
            excess: l2 - farthest,
        });
    }
    let k = (u * u + v * v + w * w + l1 * l1 - l2 * l2) / (2.0 * l1);
    let ratio = (k / rho).clamp(-1.0, 1.0);
    let beta = ((1.0 - ratio) * (1.0 + ratio)).sqrt().atan2(ratio);
    check_branch(beta, chain)?;
    let alpha = w.atan2(u);
    Ok(if flipped { beta - alpha } else { -alpha - beta })
}

/// Refuses a platform `below` (signed, positive on the work-space side) the
/// elbows' plane that is on the wrong side or too close to it.
fn assembly(below: f64, l2: f64) -> Result<(), PositionError> {
    if !below.is_finite() || below.abs() < super::SINGULARITY_MARGIN_RAD * l2 {
        return Err(PositionError::Singularity {
            chain: 3,
            angle_rad: if below.is_finite() { below / l2 } else { 0.0 },
            margin_rad: super::SINGULARITY_MARGIN_RAD,
        });
    }
    if below < 0.0 {
        return Err(PositionError::OtherAssembly { depth: -below });
    }
    Ok(())
}

/// Whether angle `theta` of an arm whose platform point is `(u, w)` is the
/// mirror (flipped) solution.
fn arm_flipped(theta: f64, u: f64, w: f64) -> bool {
    wrap_pi(theta + w.atan2(u)) > 0.0
}

impl Delta3d {
    /// Elbow `i` shifted inward by X1e: the centre of forearm sphere `i`.
    fn centre(&self, i: usize, theta: f64) -> Vec3 {
        let (s, c) = theta.sin_cos();
        let radial = self.arms.offset + self.arms.l1 * c;
        let (sp, cp) = AZIMUTH_RAD[i].sin_cos();
        [radial * cp, radial * sp, self.arms.base_height - self.arms.l1 * s]
    }

    fn platform(&self, q: Vec3) -> Result<Vec3, PositionError> {
        let c = [0, 1, 2].map(|i| self.centre(i, q[i] + self.arms.zero_rad[i]));
        let d21 = sub(c[1], c[0]);
        let d31 = sub(c[2], c[0]);
        let d = norm(d21);
        if d < 1e-12 * self.arms.l2 {
            return Err(degenerate(1));
        }
        let ex = scale(d21, 1.0 / d);
        let i = dot(ex, d31);
        let ey_raw = sub(d31, scale(ex, i));
        let j = norm(ey_raw);
        if j < 1e-12 * self.arms.l2 {
            return Err(degenerate(2));
        }
        let ey = scale(ey_raw, 1.0 / j);
        let ez = cross(ex, ey);
        let x = d / 2.0;
        let y = (i * i + j * j - 2.0 * i * x) / (2.0 * j);
        let in_plane = x.hypot(y);
        if in_plane > self.arms.l2 {
            return Err(PositionError::OutOfReach {
                chain: 0,
                excess: in_plane - self.arms.l2,
            });
        }
        let z = ((self.arms.l2 - in_plane) * (self.arms.l2 + in_plane)).sqrt();
        let z = if ez[2] > 0.0 { -z } else { z };
        Ok([
            c[0][0] + x * ex[0] + y * ey[0] + z * ez[0],
            c[0][1] + x * ex[1] + y * ey[1] + z * ez[1],
            c[0][2] + x * ex[2] + y * ey[2] + z * ez[2],
        ])
    }

    /// Platform point in arm `i`'s plane: (u, v, w).
    fn arm_frame(&self, i: usize, p: Vec3) -> (f64, f64, f64) {
        let (sp, cp) = AZIMUTH_RAD[i].sin_cos();
        (
            p[0] * cp + p[1] * sp - self.arms.offset,
            -p[0] * sp + p[1] * cp,
            p[2] - self.arms.base_height,
        )
    }

    pub(crate) fn forward(&self, q: Vec3) -> Result<Vec3, PositionError> {
        let p = self.platform(q)?;
        Ok([p[0], p[1], p[2] + self.arms.effector_height])
    }

    pub(crate) fn inverse(&self, x: Vec3, solution: ArmSolution) -> Result<Vec3, PositionError> {
        let p = [x[0], x[1], x[2] - self.arms.effector_height];
        let mut q = [0.0; 3];
        for (i, qi) in q.iter_mut().enumerate() {
            let (u, v, w) = self.arm_frame(i, p);
            let theta = arm_angle(self.arms.l1, self.arms.l2, u, v, w, solution.flipped(i), i as u8)?;
            *qi = wrap_pi(theta - self.arms.zero_rad[i]);
        }
        let c = [0, 1, 2].map(|i| self.centre(i, q[i] + self.arms.zero_rad[i]));
        let n = cross(sub(c[1], c[0]), sub(c[2], c[0]));
        let len = norm(n);
        let down = if n[2] > 0.0 { -1.0 / len } else { 1.0 / len };
        assembly(dot(sub(p, c[0]), n) * down, self.arms.l2)?;
        Ok(q)
    }

    pub(crate) fn solution(&self, q: Vec3) -> Result<ArmSolution, PositionError> {
        let p = self.platform(q)?;
        let mut s = ArmSolution::default();
        for (i, (qi, zi)) in q.iter().zip(self.arms.zero_rad).enumerate() {
            let (u, _, w) = self.arm_frame(i, p);
            s = s.with(i, arm_flipped(qi + zi, u, w));
        }
        Ok(s)
    }
}

/// Delta 2D or SCARA Delta (validated by [`super::Geometry::new`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FiveBar {
    /// SCARA Delta (horizontal, work space +X2, shared third axis) rather
    /// than Delta 2D (vertical, work space −X2).
    pub(crate) scara: bool,
    /// Its arms (heights along X2).
    pub(crate) arms: DeltaArms,
}

impl FiveBar {
    /// +1 for Delta 2D (local w = X2), −1 for SCARA Delta (local w = −X2).
    fn sign(&self) -> f64 {
        if self.scara { -1.0 } else { 1.0 }
    }

    /// Arm `i`'s circle centre in the local (u, w) frame (w up, work space
    /// below).
    fn centre(&self, i: usize, theta: f64) -> (f64, f64) {
        let (s, c) = theta.sin_cos();
        let radial = self.arms.offset + self.arms.l1 * c;
        (if i == 0 { radial } else { -radial }, -self.arms.l1 * s)
    }

    fn platform(&self, q: Vec3) -> Result<(f64, f64), PositionError> {
        let (u1, w1) = self.centre(0, q[0] + self.arms.zero_rad[0]);
        let (u2, w2) = self.centre(1, q[1] + self.arms.zero_rad[1]);
        let (du, dw) = (u2 - u1, w2 - w1);
        let d = du.hypot(dw);
        if d < 1e-12 * self.arms.l2 {
            return Err(degenerate(1));
        }
        let half = d / 2.0;
        if half > self.arms.l2 {
            return Err(PositionError::OutOfReach {
                chain: 0,
                excess: half - self.arms.l2,
            });
        }
        let h = ((self.arms.l2 - half) * (self.arms.l2 + half)).sqrt();
        // Unit normal to the centre line, pointing down (w < 0) when it can.
        let (mut nu, mut nw) = (-dw / d, du / d);
        if nw > 0.0 {
            (nu, nw) = (-nu, -nw);
        }
        Ok((u1 + du / 2.0 + h * nu, w1 + dw / 2.0 + h * nw))
    }

    fn arm_frame(&self, i: usize, (u, w): (f64, f64)) -> (f64, f64) {
        (if i == 0 { u } else { -u } - self.arms.offset, w)
    }

    pub(crate) fn forward(&self, q: Vec3) -> Result<Vec3, PositionError> {
        let (u, w) = self.platform(q)?;
        let third = if self.scara { q[2] } else { 0.0 };
        Ok([
            u,
            self.arms.base_height + self.sign() * w + self.arms.effector_height,
            third,
        ])
    }

    pub(crate) fn inverse(&self, x: Vec3, solution: ArmSolution) -> Result<Vec3, PositionError> {
        let p = (
            x[0],
            self.sign() * (x[1] - self.arms.effector_height - self.arms.base_height),
        );
        let mut q = [0.0; 3];
        for (i, qi) in q.iter_mut().enumerate().take(2) {
            let (u, w) = self.arm_frame(i, p);
            let theta = arm_angle(self.arms.l1, self.arms.l2, u, 0.0, w, solution.flipped(i), i as u8)?;
            *qi = wrap_pi(theta - self.arms.zero_rad[i]);
        }
        let (u1, w1) = self.centre(0, q[0] + self.arms.zero_rad[0]);
        let (u2, w2) = self.centre(1, q[1] + self.arms.zero_rad[1]);
        let (du, dw) = (u2 - u1, w2 - w1);
        let len = du.hypot(dw);
        // Normal (−dw, du) turned to point down.
        let down = if du > 0.0 { -1.0 / len } else { 1.0 / len };
        assembly(((p.0 - u1) * -dw + (p.1 - w1) * du) * down, self.arms.l2)?;
        if self.scara {
            q[2] = x[2];
        }
        Ok(q)
    }

    pub(crate) fn solution(&self, q: Vec3) -> Result<ArmSolution, PositionError> {
        let p = self.platform(q)?;
        let mut s = ArmSolution::default();
        for (i, (qi, zi)) in q.iter().zip(self.arms.zero_rad).enumerate().take(2) {
            let (u, w) = self.arm_frame(i, p);
            s = s.with(i, arm_flipped(qi + zi, u, w));
        }
        Ok(s)
    }
}

/// A degenerate platform solution on `chain` (the arms' spheres do not
/// span a plane): a singularity at angle 0.
fn degenerate(chain: u8) -> PositionError {
    PositionError::Singularity {
        chain,
        angle_rad: 0.0,
        margin_rad: super::SINGULARITY_MARGIN_RAD,
    }
}

#[cfg(test)]
mod tests {
    use super::super::{ArmSolution, Geometry, GeometryKind, GeometryParams, PositionError};

    fn delta_params() -> GeometryParams {
        GeometryParams {
            link_lengths: [0.3, 0.8, 0.0],
            base_offsets: [0.2, 0.0, 0.0],
            end_effector_offsets: [0.05, 0.0, -0.1],
            ..Default::default()
        }
    }

    #[test]
    fn delta3d_equal_joints_put_the_platform_on_the_centre_line_below() {
        let g = Geometry::new(GeometryKind::Delta3d, &delta_params(), 3).unwrap();
        let t = 0.4_f64;
        let x = g.forward([t; 3]).unwrap();
        assert!(x[0].abs() < 1e-15 && x[1].abs() < 1e-15, "{x:?}");
        // Radial gap from the centre line: X1b − X1e + L1 cos θ; depth by Pythagoras.
        let radial = 0.15 + 0.3 * t.cos();
        let z = -0.3 * t.sin() - (0.8f64 * 0.8 - radial * radial).sqrt() - 0.1;
        assert!((x[2] - z).abs() < 1e-14, "{x:?} vs {z}");
        assert_eq!(g.solution([t; 3]).unwrap(), ArmSolution::RIGHT_ARM);
    }

    #[test]
    fn delta3d_forearms_that_cannot_meet_are_refused() {
        let g = Geometry::new(GeometryKind::Delta3d, &delta_params(), 3).unwrap();
        // Arm 1 folded inward past the centre, arms 2 and 3 horizontal: the
        // elbow triangle's circumradius (1.05) exceeds L2, the spheres do not meet.
        match g.forward([std::f64::consts::PI, 0.0, 0.0]) {
            Err(PositionError::OutOfReach { excess, .. }) => assert!((excess - 0.25).abs() < 1e-9, "{excess}"),
            other => panic!("{other:?}"),
        }
        // Far below the reach of every arm.
        assert!(matches!(
            g.inverse([0.0, 0.0, -3.0], ArmSolution::RIGHT_ARM),
            Err(PositionError::OutOfReach { .. })
        ));
    }

    #[test]
    fn five_bar_symmetric_pose_known_values() {
        let params = GeometryParams {
            link_lengths: [0.3, 0.8, 0.0],
            base_offsets: [0.2, 1.0, 0.0],
            end_effector_offsets: [0.05, 0.1, 0.0],
            ..Default::default()
        };
        let t = 0.4_f64;
        let radial = 0.15 + 0.3 * t.cos();
        let depth = 0.3 * t.sin() + (0.8f64 * 0.8 - radial * radial).sqrt();
        let d2 = Geometry::new(GeometryKind::Delta2d, &params, 2).unwrap();
        let x = d2.forward([t, t, 0.0]).unwrap();
        assert!(
            x[0].abs() < 1e-15 && (x[1] - (1.0 - depth + 0.1)).abs() < 1e-14,
            "{x:?}"
        );
        let sd = Geometry::new(GeometryKind::ScaraDelta, &params, 2).unwrap();
        let x = sd.forward([t, t, 0.7]).unwrap();
        assert!(
            x[0].abs() < 1e-15 && (x[1] - (1.0 + depth + 0.1)).abs() < 1e-14,
            "{x:?}"
        );
        assert_eq!(x[2], 0.7);
    }
}
