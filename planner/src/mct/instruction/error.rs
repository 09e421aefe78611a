//! Why an MCT fails (ERR/EXERR) and why a running transform faults.

use super::super::{GeometryError, PositionError, orientation::PlacementError};
use super::axes::{AxisId, SystemId};
use thiserror::Error;

/// An MCT execution error, with its Logix ERR/EXERR.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum MctError {
    /// EXERR 1: a system is not in the motion group.
    #[error("coordinate system {system:?} is not assigned to the motion group")]
    NotInMotionGroup {
        /// The system.
        system: SystemId,
    },
    /// EXERR 2: source and target are the same system.
    #[error("source and target are the same coordinate system {system:?}")]
    SameSystem {
        /// The system.
        system: SystemId,
    },
    /// EXERR 3: the source transform dimension is not 1–3 or exceeds its axes.
    #[error("source transform dimension {dimension} must be 1 to 3 and at most its {axes} axes")]
    SourceDimension {
        /// The dimension.
        dimension: usize,
        /// Number of axes.
        axes: usize,
    },
    /// EXERR 4: the target transform dimension is not 1–3 or exceeds its axes.
    #[error("target transform dimension {dimension} must be 1 to 3 and at most its {axes} axes")]
    TargetDimension {
        /// The dimension.
        dimension: usize,
        /// Number of axes.
        axes: usize,
    },
    /// EXERR 5: the source is already the source of an active transform.
    #[error("coordinate system {system:?} is already the source of an active transform")]
    SourceInUse {
        /// The system.
        system: SystemId,
    },
    /// EXERR 6: the target is already the target of an active transform.
    #[error("coordinate system {system:?} is already the target of an active transform")]
    TargetInUse {
        /// The system.
        system: SystemId,
    },
    /// EXERR 7: an axis is already used on the same side of another transform.
    #[error("axis {axis:?} is already used in another active transform")]
    AxisInUse {
        /// The axis.
        axis: AxisId,
    },
    /// EXERR 8: the transform would close a circular chain.
    #[error("the target leads back to the source through active transforms")]
    CircularChain,
    /// EXERR 9: an axis is in both the source and the target.
    #[error("axis {axis:?} is in both the source and the target system")]
    SharedAxis {
        /// The axis.
        axis: AxisId,
    },
    /// EXERR 10: a motion process controls a source or target axis.
    #[error("a motion process controls axis {axis:?}")]
    MotionInProcess {
        /// The axis.
        axis: AxisId,
    },
    /// EXERR 11: no room for another active transform.
    #[error("no resources for another transform ({capacity} active)")]
    NoResources {
        /// The table's capacity.
        capacity: usize,
    },
    /// EXERR 13: an axis is shut down.
    #[error("axis {axis:?} is in the shutdown state")]
    AxisShutdown {
        /// The axis.
        axis: AxisId,
    },
    /// EXERR 14: an axis is inhibited.
    #[error("axis {axis:?} is inhibited")]
    AxisInhibited {
        /// The axis.
        axis: AxisId,
    },
    /// EXERR 16: a SCARA geometry needs source dimension 2 and the same third
    /// axis in both systems.
    #[error(
        "SCARA geometry needs source transform dimension 2 (got {source_dimension}) and the same third axis in both systems"
    )]
    ScaraAxes {
        /// The source dimension.
        source_dimension: usize,
    },
    /// EXERR 17: the source and target transform dimensions differ.
    #[error("source transform dimension {source_dimension} differs from target transform dimension {target_dimension}")]
    DimensionMismatch {
        /// Source dimension.
        source_dimension: usize,
        /// Target dimension.
        target_dimension: usize,
    },
    /// EXERR 4, 12, 15 or 16 from the target's geometry.
    #[error("target geometry: {0}")]
    Geometry(#[from] GeometryError),
    /// ERR 13: a non-finite Orientation (EXERR 3) or Translation (EXERR 4)
    /// element.
    #[error("operand: {0}")]
    Operand(#[from] PlacementError),
    /// ERR 13: an Orientation (`operand` 3) or Translation (`operand` 4)
    /// element that a transform of this dimension cannot apply.
    #[error("operand {operand} element {index} = {value} cannot apply to a transform of dimension {dimension}")]
    OutOfPlane {
        /// 3 (Orientation) or 4 (Translation).
        operand: i32,
        /// Element index.
        index: u8,
        /// Its value.
        value: f64,
        /// The transform dimension.
        dimension: usize,
    },
    /// ERR 67: the joints' position has no valid transform position.
    #[error("invalid transform position: {0}")]
    Position(#[from] PositionError),
}

impl crate::instruction::LogixFault for MctError {
    fn err(&self) -> i32 {
        MctError::err(self)
    }

    fn exerr(&self) -> i32 {
        MctError::exerr(self)
    }
}

impl MctError {
    /// The Logix ERR code.
    pub fn err(&self) -> i32 {
        match self {
            Self::Operand(_) | Self::OutOfPlane { .. } => 13,
            Self::Position(e) => e.err(),
            _ => 61,
        }
    }

    /// The Logix EXERR code.
    pub fn exerr(&self) -> i32 {
        match self {
            Self::NotInMotionGroup { .. } => 1,
            Self::SameSystem { .. } => 2,
            Self::SourceDimension { .. } => 3,
            Self::TargetDimension { .. } => 4,
            Self::SourceInUse { .. } => 5,
            Self::TargetInUse { .. } => 6,
            Self::AxisInUse { .. } => 7,
            Self::CircularChain => 8,
            Self::SharedAxis { .. } => 9,
            Self::MotionInProcess { .. } => 10,
            Self::NoResources { .. } => 11,
            Self::AxisShutdown { .. } => 13,
            Self::AxisInhibited { .. } => 14,
            Self::ScaraAxes { .. } => 16,
            Self::DimensionMismatch { .. } => 17,
            Self::Geometry(e) => e.exerr(),
            Self::Operand(PlacementError::Orientation { .. }) => 3,
            Self::Operand(_) => 4,
            Self::OutOfPlane { operand, .. } => *operand,
            Self::Position(_) => 0,
        }
    }
}

/// Why a running transform stopped following (ERR 67); the executor brings
/// the joints to a controlled stop with [`super::Transform::stop_step`].
#[derive(Debug, Clone, Copy, PartialEq, Error)]
#[non_exhaustive]
pub enum TransformFault {
    /// The source position has no valid joint position.
    #[error("invalid transform position: {0}")]
    Position(#[from] PositionError),
    /// A joint's new command is within its soft travel limits, but stopping
    /// it from there at its axis' maximum deceleration would carry it past a
    /// limit: the transform faults one update earlier, from a command whose
    /// controlled stop stays inside.
    #[error(
        "joint {joint} at {position} could not stop before its soft travel limit [{min}, {max}] (it would stop at {stop_position})"
    )]
    StoppingBeyondLimit {
        /// The joint (0-based).
        joint: u8,
        /// The joint command the source command would need, axis units.
        position: f64,
        /// Where the controlled stop from that command would end.
        stop_position: f64,
        /// Lower limit.
        min: f64,
        /// Upper limit.
        max: f64,
    },
    /// A joint would have to move faster than its axis allows.
    #[error("joint {joint} would need {required} units/s, its axis allows {max}")]
    JointSpeed {
        /// The joint (0-based).
        joint: u8,
        /// The speed the source command would need.
        required: f64,
        /// The axis' maximum speed.
        max: f64,
    },
}

impl TransformFault {
    /// The Logix ERR code: 67.
    pub fn err(&self) -> i32 {
        super::super::ERR_INVALID_TRANSFORM_POSITION
    }
}
