//! MCT — Motion Coordinated Transform (Logix): robot geometries, the
//! orientation/translation of the source frame, and the transform that links a
//! Cartesian *source* coordinate system to a joint *target* coordinate system
//! in both directions.
//!
//! * [`orientation`] — the `Orientation` `REAL[3]` and `Translation` `REAL[3]`
//!   operands ([`Placement`]), reproducing the spec's rotation table.
//! * One module per geometry family, each with forward and inverse kinematics:
//!   [`cartesian`] (gantry, H-bot), [`articulated`] (independent 2D/3D,
//!   dependent), [`scara`] (SCARA independent), [`delta`] (Delta 3D, Delta 2D,
//!   SCARA Delta).
//! * [`Geometry`] — a validated geometry (the Geometry/Offsets tabs of the
//!   target coordinate system); an invalid one cannot be built
//!   ([`GeometryError`], EXERR 4, 12, 15, 16).
//! * [`instruction`] — the MCT instruction: operand and connection checks
//!   (ERR 61 with EXERR 1–17, ERR 13), the running [`instruction::Transform`]
//!   (source → joints and joints → source each coarse update, ERR 67), the
//!   control bits and the four transform status bits.
//!
//! # Units and frames
//! Inside this module lengths are in the source system's coordinate units
//! (the same units as link lengths and offsets; SI metres in the twin) and
//! revolute joint angles are in radians. The instruction converts at its
//! boundary: revolute joint axes are in degrees (as Logix requires for a
//! rotary joint axis), prismatic joint axes in coordinate units. Positions are
//! always `[f64; 3]` ([`Vec3`]); a transform of dimension 2 leaves the third
//! element alone (0, or the shared third axis of the SCARA geometries).
//!
//! # Choices where the spec is silent
//! The spec names the geometries and their parameters but gives no equations;
//! each geometry module documents its zero pose, sign conventions and which of
//! the Logix parameters (L1, L2, X1b…X3b, X1e…X3e, Z1…Z3) it uses (unused
//! ones are ignored, as the Logix dialog greys them out). Common to all:
//! * joint angle in the kinematic equations `θᵢ = qᵢ + Zᵢ` (axis position plus
//!   zero-angle offset);
//! * **arm solutions** ([`ArmSolution`]): every branch choice of the inverse
//!   kinematics (left/right arm, front/back reach, each Delta knee) is one bit;
//!   [`Geometry::solution`] reads the bits from a joint position, and the
//!   transform keeps the bits it read at start for every Cartesian move;
//! * **singularity margin** [`SINGULARITY_MARGIN_RAD`]: an inverse solution
//!   whose branch angle (elbow angle from fully stretched or folded back, a
//!   Delta knee angle from collinear) is within this margin is refused as
//!   [`PositionError::Singularity`] (ERR 67), because there the two arm
//!   solutions meet and the joint speed for a Cartesian speed grows without
//!   bound. The transform additionally never commands a joint speed above the
//!   axis maximum (see [`instruction`]).

pub mod articulated;
pub mod cartesian;
pub mod delta;
pub mod instruction;
pub mod orientation;
pub mod scara;

#[cfg(test)]
mod tests;

pub use orientation::Placement;

use std::f64::consts::PI;
use thiserror::Error;

/// A position or joint vector; the third element is unused (0) by
/// two-dimensional transforms.
pub type Vec3 = [f64; 3];

/// Branch angles closer than this to a singular value (0 or π) are refused by
/// the inverse kinematics: 1 mrad (0.057°).
pub const SINGULARITY_MARGIN_RAD: f64 = 1e-3;

/// Logix ERR code of a transform that cannot reach or hold a position.
pub const ERR_INVALID_TRANSFORM_POSITION: i32 = 67;

/// The branch choices of an inverse solution, one bit per choice.
///
/// * Serial arms (articulated, SCARA independent): bit 0 set = **left arm**
///   (the relative elbow angle is negative), clear = **right arm** (elbow angle
///   positive). Articulated 3D only: bit 1 set = **back** reach (the wrist lies
///   behind the waist axis, radial distance < 0).
/// * Delta 3D / Delta 2D / SCARA Delta: bit *i* set = arm *i*'s knee points
///   inward (the mirror solution); clear = the usual knee-outward pose.
/// * Cartesian geometries have a single solution (no bits).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct ArmSolution(u8);

impl ArmSolution {
    /// Right arm, front reach, every Delta knee outward.
    pub const RIGHT_ARM: Self = Self(0);
    /// Left arm (bit 0).
    pub const LEFT_ARM: Self = Self(1);

    /// The bits.
    pub fn bits(self) -> u8 {
        self.0
    }

    /// A solution from its bits.
    pub fn from_bits(bits: u8) -> Self {
        Self(bits)
    }

    /// Whether branch `chain` (0, 1, 2) takes its second solution.
    pub fn flipped(self, chain: usize) -> bool {
        self.0 & (1 << chain) != 0
    }

    /// This solution with branch `chain` set to `flipped`.
    #[must_use]
    pub fn with(self, chain: usize, flipped: bool) -> Self {
        if flipped {
            Self(self.0 | (1 << chain))
        } else {
            Self(self.0 & !(1 << chain))
        }
    }
}

/// Whether a joint turns (revolute, radians inside, degrees on the axis) or
/// slides (prismatic, coordinate units).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum JointKind {
    /// A rotary joint.
    Revolute,
    /// A linear joint, or the SCARA geometries' shared third axis.
    Prismatic,
}

/// Why the kinematics cannot give a position (Logix ERR 67, invalid transform
/// position).
#[derive(Debug, Clone, Copy, PartialEq, Error)]
#[non_exhaustive]
pub enum PositionError {
    /// The position cannot be reached by branch `chain`: `excess` coordinate
    /// units beyond the reachable region (beyond full stretch, inside the
    /// folded-back hole, or — for a Delta forward solution — forearms that
    /// cannot meet).
    #[error("position out of reach by {excess} coordinate units (chain {chain})")]
    OutOfReach {
        /// The arm / chain (0-based).
        chain: u8,
        /// How far outside the reachable region, coordinate units (≥ 0).
        excess: f64,
    },
    /// The position is within [`SINGULARITY_MARGIN_RAD`] of a fully stretched
    /// or folded-back arm (or a Delta knee collinear with its forearm), where
    /// the arm solutions meet.
    #[error(
        "position at a singularity: chain {chain} branch angle {angle_rad} rad is within {margin_rad} rad of 0 or pi"
    )]
    Singularity {
        /// The arm / chain (0-based).
        chain: u8,
        /// Branch angle from the singular pose, radians.
        angle_rad: f64,
        /// The margin.
        margin_rad: f64,
    },
    /// A parallel robot's inverse solution would hold the platform on the far
    /// side of its elbows (the mechanism's other assembly mode, which the
    /// robot's forward kinematics never gives); `depth` is how far past the
    /// elbows' plane, coordinate units.
    #[error("the platform would sit {depth} coordinate units above its elbows (other assembly mode)")]
    OtherAssembly {
        /// Distance past the elbows' plane (line for the planar robots).
        depth: f64,
    },
    /// A joint would leave its limits (axis units).
    #[error("joint {joint} position {position} beyond its limit [{min}, {max}]")]
    BeyondJointLimit {
        /// The joint (0-based).
        joint: u8,
        /// The position it would need.
        position: f64,
        /// Lower limit.
        min: f64,
        /// Upper limit.
        max: f64,
    },
    /// A position or joint value is not finite.
    #[error("position or joint value is not finite")]
    NotFinite,
}

impl PositionError {
    /// The Logix ERR code: 67.
    pub fn err(&self) -> i32 {
        ERR_INVALID_TRANSFORM_POSITION
    }
}

/// The coordinate system types and geometries MCT can drive.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum GeometryKind {
    /// Cartesian gantry: each joint is one Cartesian axis (dimension 1–3).
    CartesianGantry,
    /// Cartesian H-bot: two motors on one belt drive X1/X2 (dimension 2–3).
    CartesianHBot,
    /// Articulated independent: each joint angle is relative to the previous
    /// link (dimension 2 or 3).
    ArticulatedIndependent,
    /// Articulated dependent: the last joint's angle is measured from the
    /// horizontal (parallelogram drive) (dimension 2 or 3).
    ArticulatedDependent,
    /// SCARA independent: two-link arm in the X1–X2 plane plus the shared
    /// vertical third axis (source dimension 2).
    ScaraIndependent,
    /// Delta three-dimensional: three upper arms at 120°.
    Delta3d,
    /// Delta two-dimensional: two upper arms in the X1–X2 (vertical) plane.
    Delta2d,
    /// SCARA Delta: two upper arms in the horizontal X1–X2 plane plus the
    /// shared vertical third axis (source dimension 2).
    ScaraDelta,
}

/// The Geometry and Offsets tabs of a coordinate system, in coordinate units
/// (lengths) and degrees (zero angles) — the boundary form; see [`Geometry`].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct GeometryParams {
    /// Link lengths L1, L2 (L3 unused by these geometries) (default: 0, which
    /// is refused for every geometry with links — EXERR 12).
    pub link_lengths: Vec3,
    /// Base offsets X1b, X2b, X3b (default: 0).
    pub base_offsets: Vec3,
    /// End-effector offsets X1e, X2e, X3e (default: 0).
    pub end_effector_offsets: Vec3,
    /// Zero-angle orientations Z1, Z2, Z3, degrees (default: 0).
    pub zero_angles_deg: Vec3,
}

/// A geometry that cannot be built (Logix ERR 61 with the EXERR of
/// [`GeometryError::exerr`]).
#[derive(Debug, Clone, Copy, PartialEq, Error)]
#[non_exhaustive]
pub enum GeometryError {
    /// The transform dimension does not suit the geometry (EXERR 4; EXERR 16
    /// for the SCARA geometries, which need dimension 2).
    #[error("{kind:?} cannot have transform dimension {dimension}")]
    Dimension {
        /// The geometry.
        kind: GeometryKind,
        /// The dimension given.
        dimension: usize,
    },
    /// A link length used by the geometry is zero, negative or not finite
    /// (EXERR 12).
    #[error("link length L{link} = {value} must be finite and > 0")]
    LinkLength {
        /// 1-based link number.
        link: u8,
        /// Its value.
        value: f64,
    },
    /// Delta / SCARA Delta: X1b − X1e < 0 (EXERR 15).
    #[error("base offset X1b {base} minus end-effector offset X1e {effector} must not be negative")]
    DeltaOffsets {
        /// X1b.
        base: f64,
        /// X1e.
        effector: f64,
    },
    /// Delta 3D / Delta 2D: L1 + (X1b − X1e) > L2 (EXERR 15).
    #[error("L1 {l1} + (X1b - X1e) {offset} is greater than L2 {l2}")]
    DeltaReach {
        /// L1.
        l1: f64,
        /// X1b − X1e.
        offset: f64,
        /// L2.
        l2: f64,
    },
    /// An offset or zero angle is not finite (reported with EXERR 15, the
    /// "check the configured offsets" code, for every geometry).
    #[error("geometry parameter {field} must be finite, got {value}")]
    NotFinite {
        /// `"base_offsets"`, `"end_effector_offsets"` or `"zero_angles_deg"`.
        field: &'static str,
        /// Its value.
        value: f64,
    },
}

impl GeometryError {
    /// The Logix ERR code: 61 (connection conflict), as for every MCT
    /// configuration error.
    pub fn err(&self) -> i32 {
        61
    }

    /// The Logix EXERR code.
    pub fn exerr(&self) -> i32 {
        match self {
            Self::Dimension {
                kind: GeometryKind::ScaraIndependent | GeometryKind::ScaraDelta,
                ..
            } => 16,
            Self::Dimension { .. } => 4,
            Self::LinkLength { .. } => 12,
            Self::DeltaOffsets { .. } | Self::DeltaReach { .. } | Self::NotFinite { .. } => 15,
        }
    }
}

/// A validated robot geometry with its transform dimension.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Geometry {
    /// See [`cartesian::Gantry`].
    CartesianGantry(cartesian::Gantry),
    /// See [`cartesian::HBot`].
    CartesianHBot(cartesian::HBot),
    /// See [`articulated::Articulated`] (independent or dependent).
    Articulated(articulated::Articulated),
    /// See [`scara::ScaraIndependent`].
    ScaraIndependent(scara::ScaraIndependent),
    /// See [`delta::Delta3d`].
    Delta3d(delta::Delta3d),
    /// See [`delta::FiveBar`] (Delta 2D or SCARA Delta).
    FiveBar(delta::FiveBar),
}

impl Geometry {
    /// A geometry of `kind` with `params` and transform dimension `dimension`.
    ///
    /// # Examples
    /// A SCARA with 0.35 m and 0.25 m links: forward, then inverse on the arm
    /// solution the joints are in.
    /// ```
    /// use planner::mct::{Geometry, GeometryKind, GeometryParams};
    /// let params = GeometryParams { link_lengths: [0.35, 0.25, 0.0], ..Default::default() };
    /// let scara = Geometry::new(GeometryKind::ScaraIndependent, &params, 2).unwrap();
    /// let q = [0.3, 1.2, 0.1];
    /// let x = scara.forward(q).unwrap();
    /// let back = scara.inverse(x, scara.solution(q).unwrap()).unwrap();
    /// assert!(q.iter().zip(back).all(|(a, b)| (a - b).abs() < 1e-12));
    /// // A zero link length is Logix EXERR 12.
    /// let bad = GeometryParams { link_lengths: [0.35, 0.0, 0.0], ..params };
    /// assert_eq!(Geometry::new(GeometryKind::ScaraIndependent, &bad, 2).unwrap_err().exerr(), 12);
    /// ```
    ///
    /// # Errors
    /// [`GeometryError`]: a dimension the geometry cannot have (EXERR 4 / 16),
    /// a zero, negative or non-finite link length (EXERR 12), Delta offsets
    /// that break X1b − X1e ≥ 0 or L1 + (X1b − X1e) ≤ L2 (EXERR 15), or a
    /// non-finite offset or zero angle.
    pub fn new(kind: GeometryKind, params: &GeometryParams, dimension: usize) -> Result<Self, GeometryError> {
        let finite = |field: &'static str, v: &Vec3| match v.iter().find(|x| !x.is_finite()) {
            Some(&value) => Err(GeometryError::NotFinite { field, value }),
            None => Ok(()),
        };
        finite("base_offsets", &params.base_offsets)?;
        finite("end_effector_offsets", &params.end_effector_offsets)?;
        finite("zero_angles_deg", &params.zero_angles_deg)?;
        let dim_ok = match kind {
            GeometryKind::CartesianGantry => (1..=3).contains(&dimension),
            GeometryKind::CartesianHBot => (2..=3).contains(&dimension),
            GeometryKind::ArticulatedIndependent | GeometryKind::ArticulatedDependent => (2..=3).contains(&dimension),
            GeometryKind::ScaraIndependent | GeometryKind::Delta2d | GeometryKind::ScaraDelta => dimension == 2,
            GeometryKind::Delta3d => dimension == 3,
        };
        if !dim_ok {
            return Err(GeometryError::Dimension { kind, dimension });
        }
        let link = |i: usize| {
            let value = params.link_lengths[i];
            if value.is_finite() && value > 0.0 {
                Ok(value)
            } else {
                Err(GeometryError::LinkLength {
                    link: i as u8 + 1,
                    value,
                })
            }
        };
        let zero_rad = params.zero_angles_deg.map(f64::to_radians);
        let base = params.base_offsets;
        let effector = params.end_effector_offsets;
        Ok(match kind {
            GeometryKind::CartesianGantry => Self::CartesianGantry(cartesian::Gantry {
                dimension,
                offset: add(base, effector),
            }),
            GeometryKind::CartesianHBot => Self::CartesianHBot(cartesian::HBot {
                dimension,
                offset: add(base, effector),
            }),
            GeometryKind::ArticulatedIndependent | GeometryKind::ArticulatedDependent => {
                Self::Articulated(articulated::Articulated {
                    dependent: kind == GeometryKind::ArticulatedDependent,
                    dimension,
                    l1: link(0)?,
                    l2: link(1)?,
                    base,
                    effector,
                    zero_rad,
                })
            }
            GeometryKind::ScaraIndependent => Self::ScaraIndependent(scara::ScaraIndependent {
                l1: link(0)?,
                l2: link(1)?,
                base,
                effector,
                zero_rad,
            }),
            GeometryKind::Delta3d | GeometryKind::Delta2d | GeometryKind::ScaraDelta => {
                let l1 = link(0)?;
                let l2 = link(1)?;
                let offset = base[0] - effector[0];
                if offset < 0.0 {
                    return Err(GeometryError::DeltaOffsets {
                        base: base[0],
                        effector: effector[0],
                    });
                }
                if kind != GeometryKind::ScaraDelta && l1 + offset > l2 {
                    return Err(GeometryError::DeltaReach { l1, offset, l2 });
                }
                // Delta 3D's arms turn about X3; Delta 2D and SCARA Delta's about X2.
                let up = if kind == GeometryKind::Delta3d { 2 } else { 1 };
                let arms = delta::DeltaArms {
                    l1,
                    l2,
                    offset,
                    base_height: base[up],
                    effector_height: effector[up],
                    zero_rad,
                };
                match kind {
                    GeometryKind::Delta3d => Self::Delta3d(delta::Delta3d { arms }),
                    _ => Self::FiveBar(delta::FiveBar {
                        scara: kind == GeometryKind::ScaraDelta,
                        arms,
                    }),
                }
            }
        })
    }

    /// The geometry's kind.
    pub fn kind(&self) -> GeometryKind {
        match self {
            Self::CartesianGantry(_) => GeometryKind::CartesianGantry,
            Self::CartesianHBot(_) => GeometryKind::CartesianHBot,
            Self::Articulated(a) if a.dependent => GeometryKind::ArticulatedDependent,
            Self::Articulated(_) => GeometryKind::ArticulatedIndependent,
            Self::ScaraIndependent(_) => GeometryKind::ScaraIndependent,
            Self::Delta3d(_) => GeometryKind::Delta3d,
            Self::FiveBar(f) if f.scara => GeometryKind::ScaraDelta,
            Self::FiveBar(_) => GeometryKind::Delta2d,
        }
    }

    /// The transform dimension (number of transformed axes).
    pub fn dimension(&self) -> usize {
        match self {
            Self::CartesianGantry(g) => g.dimension,
            Self::CartesianHBot(g) => g.dimension,
            Self::Articulated(a) => a.dimension,
            Self::Delta3d(_) => 3,
            Self::ScaraIndependent(_) | Self::FiveBar(_) => 2,
        }
    }

    /// Whether the geometry passes its third axis through untransformed (the
    /// SCARA geometries: source and target share the third axis).
    pub fn shares_third_axis(&self) -> bool {
        matches!(
            self,
            Self::ScaraIndependent(_) | Self::FiveBar(delta::FiveBar { scara: true, .. })
        )
    }

    /// L2 of the parallel geometries (Delta 3D, Delta 2D, SCARA Delta): the
    /// forearm length that closes each chain, which a tree model (URDF)
    /// cannot express and a consistency check must measure; `None` for the
    /// serial and Cartesian geometries.
    pub fn parallel_forearm_length(&self) -> Option<f64> {
        match self {
            Self::Delta3d(d) => Some(d.arms.l2),
            Self::FiveBar(f) => Some(f.arms.l2),
            _ => None,
        }
    }

    /// Revolute or prismatic, per joint (unused joints are reported
    /// prismatic).
    pub fn joint_kinds(&self) -> [JointKind; 3] {
        use JointKind::{Prismatic as P, Revolute as R};
        match self {
            Self::CartesianGantry(_) | Self::CartesianHBot(_) => [P, P, P],
            Self::Articulated(a) if a.dimension == 2 => [R, R, P],
            Self::Articulated(_) | Self::Delta3d(_) => [R, R, R],
            Self::ScaraIndependent(_) => [R, R, P],
            Self::FiveBar(_) => [R, R, P],
        }
    }

    /// Forward kinematics: the tool position (coordinate units, robot frame)
    /// of joint positions `q` (radians / coordinate units).
    ///
    /// # Errors
    /// [`PositionError::NotFinite`] for a non-finite joint; a Delta whose
    /// forearms cannot meet gives [`PositionError::OutOfReach`].
    pub fn forward(&self, q: Vec3) -> Result<Vec3, PositionError> {
        if q.iter().any(|x| !x.is_finite()) {
            return Err(PositionError::NotFinite);
        }
        let x = match self {
            Self::CartesianGantry(g) => g.forward(q),
            Self::CartesianHBot(g) => g.forward(q),
            Self::Articulated(a) => a.forward(q),
            Self::ScaraIndependent(s) => s.forward(q),
            Self::Delta3d(d) => d.forward(q)?,
            Self::FiveBar(f) => f.forward(q)?,
        };
        finite(x)
    }

    /// Inverse kinematics: the joint positions (radians in (−π, π] /
    /// coordinate units) that put the tool at `x` on arm solution `solution`.
    ///
    /// # Errors
    /// [`PositionError::OutOfReach`], [`PositionError::Singularity`] (within
    /// [`SINGULARITY_MARGIN_RAD`] of a stretched or folded-back pose), or
    /// [`PositionError::NotFinite`].
    pub fn inverse(&self, x: Vec3, solution: ArmSolution) -> Result<Vec3, PositionError> {
        if x.iter().any(|v| !v.is_finite()) {
            return Err(PositionError::NotFinite);
        }
        let q = match self {
            Self::CartesianGantry(g) => g.inverse(x),
            Self::CartesianHBot(g) => g.inverse(x),
            Self::Articulated(a) => a.inverse(x, solution)?,
            Self::ScaraIndependent(s) => s.inverse(x, solution)?,
            Self::Delta3d(d) => d.inverse(x, solution)?,
            Self::FiveBar(f) => f.inverse(x, solution)?,
        };
        finite(q)
    }

    /// The arm solution the robot is in at joint positions `q`.
    ///
    /// # Errors
    /// As [`Geometry::forward`] (the Delta solutions need the platform
    /// position).
    pub fn solution(&self, q: Vec3) -> Result<ArmSolution, PositionError> {
        if q.iter().any(|x| !x.is_finite()) {
            return Err(PositionError::NotFinite);
        }
        Ok(match self {
            Self::CartesianGantry(_) | Self::CartesianHBot(_) => ArmSolution::default(),
            Self::Articulated(a) => a.solution(q),
            Self::ScaraIndependent(s) => s.solution(q),
            Self::Delta3d(d) => d.solution(q)?,
            Self::FiveBar(f) => f.solution(q)?,
        })
    }
}

fn finite(v: Vec3) -> Result<Vec3, PositionError> {
    if v.iter().all(|x| x.is_finite()) {
        Ok(v)
    } else {
        Err(PositionError::NotFinite)
    }
}

pub(crate) fn add(a: Vec3, b: Vec3) -> Vec3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

/// `a` wrapped into [−π, π].
pub(crate) fn wrap_pi(a: f64) -> f64 {
    a - 2.0 * PI * (a / (2.0 * PI)).round()
}

/// Two-link planar arm: the point of link angles `a1` (absolute) and `a2`
/// (relative to link 1).
pub(crate) fn planar_forward(l1: f64, l2: f64, a1: f64, a2: f64) -> (f64, f64) {
    let (s1, c1) = a1.sin_cos();
    let (s12, c12) = (a1 + a2).sin_cos();
    (l1 * c1 + l2 * c12, l1 * s1 + l2 * s12)
}

/// Two-link planar arm: link angles `(a1, a2)` reaching `(px, py)`, with the
/// relative elbow angle `a2` negative when `negative_elbow`.
///
/// The elbow cosine's complement is computed in factored form,
/// `1 − c² = ((l1+l2)² − d²)(d² − (l1−l2)²) / (2 l1 l2)²`, so the angle stays
/// accurate close to the stretched and folded poses.
pub(crate) fn planar_inverse(
    l1: f64,
    l2: f64,
    px: f64,
    py: f64,
    negative_elbow: bool,
    chain: u8,
) -> Result<(f64, f64), PositionError> {
    let d = px.hypot(py);
    let outer = (l1 + l2 - d) * (l1 + l2 + d);
    let inner = (d - (l1 - l2).abs()) * (d + (l1 - l2).abs());
    if outer < 0.0 {
        return Err(PositionError::OutOfReach {
            chain,
            excess: d - (l1 + l2),
        });
    }
    if inner < 0.0 {
        return Err(PositionError::OutOfReach {
            chain,
            excess: (l1 - l2).abs() - d,
        });
    }
    let c2 = (d * d - l1 * l1 - l2 * l2) / (2.0 * l1 * l2);
    let s2 = (outer * inner).sqrt() / (2.0 * l1 * l2);
    let a2_abs = s2.atan2(c2);
    check_branch(a2_abs, chain)?;
    let a2 = if negative_elbow { -a2_abs } else { a2_abs };
    let a1 = py.atan2(px) - (l2 * a2.sin()).atan2(l1 + l2 * a2.cos());
    Ok((wrap_pi(a1), a2))
}

/// Refuses a branch angle in [0, π] within the margin of 0 or π.
pub(crate) fn check_branch(angle_rad: f64, chain: u8) -> Result<(), PositionError> {
    if !(SINGULARITY_MARGIN_RAD..=PI - SINGULARITY_MARGIN_RAD).contains(&angle_rad) {
        Err(PositionError::Singularity {
            chain,
            angle_rad,
            margin_rad: SINGULARITY_MARGIN_RAD,
        })
    } else {
        Ok(())
    }
}
