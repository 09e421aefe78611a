//! The operands MCLM and MCCM share, their faceplate indices (from the
//! instruction catalogue) and the ERR/EXERR a move reports.

use super::CoordinateSystem;
use crate::catalogue;
use crate::dynamics::MoveDynamics;
use thiserror::Error;

/// Move Type: 0 absolute, 1 incremental.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MoveType {
    /// `0`.
    Absolute,
    /// `1`.
    Incremental,
}

/// Termination Type 0–6.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TerminationType {
    /// `0` — complete when interpolation is done and the actual position is
    /// within the actual tolerance.
    ActualTolerance,
    /// `1` — complete when interpolation is done.
    NoSettle,
    /// `2` — blend into the pending move from the system's command tolerance.
    CommandTolerance,
    /// `3` — blend into the pending move from the deceleration point.
    NoDecel,
    /// `4` — follow contour, velocity constrained: through the end point
    /// without stopping, at the lower of the two programmed speeds, into a
    /// pending move (at rest without one).
    FollowContourConstrained,
    /// `5` — follow contour, velocity unconstrained (planned like 4).
    FollowContourUnconstrained,
    /// `6` — like 2 with the instruction's own command tolerance.
    CommandToleranceProgrammed,
}

impl TerminationType {
    pub(crate) fn from_code(code: i64) -> Option<Self> {
        Some(match code {
            0 => Self::ActualTolerance,
            1 => Self::NoSettle,
            2 => Self::CommandTolerance,
            3 => Self::NoDecel,
            4 => Self::FollowContourConstrained,
            5 => Self::FollowContourUnconstrained,
            6 => Self::CommandToleranceProgrammed,
            _ => return None,
        })
    }

    /// Whether the move blends into a pending move (types 2, 3, 6).
    pub fn blends(self) -> bool {
        matches!(
            self,
            Self::CommandTolerance | Self::NoDecel | Self::CommandToleranceProgrammed
        )
    }
}

/// Merge: 0 disabled, 1 coordinated motion, 2 all motion.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Merge {
    /// `0` — queue behind the running move.
    Disabled,
    /// `1` — replace the coordinated motion of the system.
    CoordinatedMotion,
    /// `2` — replace the coordinated motion and single-axis motion.
    AllMotion,
}

/// Merge Speed: 0 programmed, 1 current.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MergeSpeed {
    /// `0`.
    Programmed,
    /// `1`.
    Current,
}

/// Lock Direction of a master-driven move.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LockDirection {
    /// `0` — follow the master in both directions at once; never "locked".
    None,
    /// `1` — follow at once, only while the master moves forward.
    ImmediateForwardOnly,
    /// `2` — follow at once, only while the master moves in reverse.
    ImmediateReverseOnly,
    /// `3` — start following when the master crosses the lock position
    /// forward, then forward only.
    PositionForward,
    /// `4` — start following when the master crosses the lock position in
    /// reverse, then reverse only.
    PositionReverse,
}

/// What drives a move's path: time, or a master axis' position.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Driver {
    /// Time driven: rates in units/s, units/s², units/s³.
    Time,
    /// Master driven: rates per master unit.
    Master,
}

/// The operand values shared by MCLM and MCCM, as the program passes them
/// (enumerations as their numeric codes, arrays as slices).
#[derive(Debug, Clone, PartialEq)]
pub struct CoordMoveInputs {
    /// Move Type (0 absolute, 1 incremental).
    pub move_type: i64,
    /// Position array, one element per axis of the system.
    pub position: Vec<f64>,
    /// Speed, rates, profile and jerks.
    pub dynamics: MoveDynamics,
    /// Termination Type (0–6).
    pub termination_type: i64,
    /// Merge (0, 1, 2).
    pub merge: i64,
    /// Merge Speed (0, 1).
    pub merge_speed: i64,
    /// Command Tolerance (termination type 6), units ≥ 0.
    pub command_tolerance: f64,
    /// Lock Position (master units).
    pub lock_position: f64,
    /// Lock Direction (0–4).
    pub lock_direction: i64,
    /// Event Distances, measured from the end of the move.
    pub event_distance: Vec<f64>,
}

impl Default for CoordMoveInputs {
    /// Absolute, empty position, speed 1 units/s, accel/decel 10 units/s²,
    /// trapezoidal, jerk 100 % of time, termination 0, merge disabled.
    fn default() -> Self {
        Self {
            move_type: 0,
            position: Vec::new(),
            dynamics: MoveDynamics {
                speed: 1.0,
                speed_units: 0,
                accel_rate: 10.0,
                accel_units: 0,
                decel_rate: 10.0,
                decel_units: 0,
                profile: 0,
                accel_jerk: 100.0,
                decel_jerk: 100.0,
                jerk_units: 2,
            },
            termination_type: 0,
            merge: 0,
            merge_speed: 0,
            command_tolerance: 0.0,
            lock_position: 0.0,
            lock_direction: 0,
            event_distance: Vec::new(),
        }
    }
}

/// Faceplate operand indices of one instruction (EXERR of ERR 13), read
/// from [`crate::catalogue`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct OperandIndex {
    /// Coordinate System.
    pub coordinate_system: i32,
    /// Move Type.
    pub move_type: i32,
    /// Position.
    pub position: i32,
    /// Circle Type (MCCM only; −1 for MCLM).
    pub circle_type: i32,
    /// Via/Center/Radius (MCCM only).
    pub via_center_radius: i32,
    /// Direction (MCCM only).
    pub direction: i32,
    /// Speed.
    pub speed: i32,
    /// Speed Units.
    pub speed_units: i32,
    /// Accel Rate.
    pub accel_rate: i32,
    /// Accel Units.
    pub accel_units: i32,
    /// Decel Rate.
    pub decel_rate: i32,
    /// Decel Units.
    pub decel_units: i32,
    /// Profile.
    pub profile: i32,
    /// Termination Type.
    pub termination_type: i32,
    /// Merge.
    pub merge: i32,
    /// Merge Speed.
    pub merge_speed: i32,
    /// Accel Jerk.
    pub accel_jerk: i32,
    /// Decel Jerk.
    pub decel_jerk: i32,
    /// Jerk Units.
    pub jerk_units: i32,
    /// Command Tolerance.
    pub command_tolerance: i32,
    /// Lock Position.
    pub lock_position: i32,
    /// Lock Direction.
    pub lock_direction: i32,
    /// Event Distance.
    pub event_distance: i32,
}

impl OperandIndex {
    /// MCCM's faceplate order.
    pub const MCCM: Self = Self::of(&catalogue::MCCM);
    /// MCLM's faceplate order (no circle operands: those are −1).
    pub const MCLM: Self = Self::of(&catalogue::MCLM);

    /// The indices of a coordinated move instruction, read from its
    /// catalogue entry.
    const fn of(i: &catalogue::Instruction) -> Self {
        Self {
            coordinate_system: i.exerr("Coordinate System"),
            move_type: i.exerr("Move Type"),
            position: i.exerr("Position"),
            circle_type: none_is_minus_one(i.faceplate_of("Circle Type")),
            via_center_radius: none_is_minus_one(i.faceplate_of("Via/Center/Radius")),
            direction: none_is_minus_one(i.faceplate_of("Direction")),
            speed: i.exerr("Speed"),
            speed_units: i.exerr("Speed Units"),
            accel_rate: i.exerr("Accel Rate"),
            accel_units: i.exerr("Accel Units"),
            decel_rate: i.exerr("Decel Rate"),
            decel_units: i.exerr("Decel Units"),
            profile: i.exerr("Profile"),
            termination_type: i.exerr("Termination Type"),
            merge: i.exerr("Merge"),
            merge_speed: i.exerr("Merge Speed"),
            accel_jerk: i.exerr("Accel Jerk"),
            decel_jerk: i.exerr("Decel Jerk"),
            jerk_units: i.exerr("Jerk Units"),
            command_tolerance: i.exerr("Command Tolerance"),
            lock_position: i.exerr("Lock Position"),
            lock_direction: i.exerr("Lock Direction"),
            event_distance: i.exerr("Event Distance"),
        }
    }
}

const fn none_is_minus_one(index: Option<i32>) -> i32 {
    match index {
        Some(index) => index,
        None => -1,
    }
}

/// Why a coordinated move (MCLM, MCCM) or stop (MCS) cannot start: the
/// controller's ERR/EXERR, as numbers.
#[derive(Debug, Clone, Copy, PartialEq, Error)]
#[non_exhaustive]
pub enum CoordMoveError {
    /// ERR 13, Parameter Out Of Range; EXERR = the operand's faceplate index.
    #[error("ERR 13 parameter out of range: operand {exerr}")]
    ParameterOutOfRange {
        /// The operand index.
        exerr: i32,
    },
    /// ERR 25, Illegal Instruction: a radius circle in a 3D system.
    #[error("ERR 25 illegal instruction: radius circles are 2D only")]
    RadiusIn3d,
    /// ERR 44, Collinearity: the points do not define a plane.
    #[error("ERR 44 collinearity: the circle's points are collinear")]
    Collinear,
    /// ERR 45, Endpoint = Startpoint where that is illegal.
    #[error("ERR 45 the end point equals the start point")]
    EndpointEqualsStartpoint,
    /// ERR 46, start/end radius mismatch: |R1 − R2| > 0.15 · R1.
    #[error("ERR 46 start radius {r_start} and end radius {r_end} differ by more than 15 %")]
    RadiusMismatch {
        /// Start radius R1.
        r_start: f64,
        /// End radius R2.
        r_end: f64,
    },
    /// ERR 49, radius too small (< 0.001) or too short to span the points.
    #[error("ERR 49 radius {radius} too small or too short to span the points")]
    RadiusTooSmall {
        /// The radius.
        radius: f64,
    },
    /// ERR 54, Maximum Deceleration Value Is Zero; EXERR = the axis index in
    /// the system, or −1 for the coordinate system itself.
    #[error("ERR 54 maximum deceleration is zero (EXERR {exerr})")]
    MaxDecelZero {
        /// Axis index, or −1.
        exerr: i32,
    },
}

impl CoordMoveError {
    /// The `ERR` code.
    pub fn err(&self) -> i32 {
        match self {
            Self::ParameterOutOfRange { .. } => 13,
            Self::RadiusIn3d => 25,
            Self::Collinear => 44,
            Self::EndpointEqualsStartpoint => 45,
            Self::RadiusMismatch { .. } => 46,
            Self::RadiusTooSmall { .. } => 49,
            Self::MaxDecelZero { .. } => 54,
        }
    }

    /// The `EXERR` code (0 where the error has none).
    pub fn exerr(&self) -> i32 {
        match self {
            Self::ParameterOutOfRange { exerr } | Self::MaxDecelZero { exerr } => *exerr,
            _ => 0,
        }
    }
}

pub(crate) fn out_of_range(exerr: i32) -> CoordMoveError {
    CoordMoveError::ParameterOutOfRange { exerr }
}

/// What a move is verified against: the system, its axes' maximum
/// decelerations, the position the move starts from, and whether a master
/// axis is linked.
#[derive(Debug, Clone, Copy)]
pub struct MoveContext<'a> {
    /// The coordinate system.
    pub system: &'a CoordinateSystem,
    /// Maximum deceleration of each axis of the system, in system order.
    pub axis_max_decel: &'a [f64],
    /// Where the move starts (the previous move's end point, or the command
    /// position when the system is idle), one value per axis.
    pub start: &'a [f64],
    /// Whether the system has a master axis (master-driven moves need one).
    pub has_master: bool,
}
