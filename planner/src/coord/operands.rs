//! The operands MCLM and MCCM share, their faceplate indices (from the
//! instruction catalogue) and the ERR/EXERR a move reports.

use super::system::CoordinateSystem;
use crate::catalogue::words::{
    ACCEL_UNITS, INTEGER, JERK_UNITS, LOCK_DIRECTION, MERGE, MERGE_SPEED, NUMERIC, PROFILE, SPEED_UNITS,
    motion_control, op,
};
use crate::catalogue::{self, Format, Kind, Operand};
use crate::dynamics::MoveDynamics;
use crate::instruction::{LogixFault, Refusal};
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

/// MCCM's operands; MCLM's are these without Circle Type,
/// Via/Center/Radius and Direction, with their own faceplate indices.
pub const MCCM_OPERANDS: &[Operand] = &[
    op(
        "Coordinate System",
        "COORDINATE_SYSTEM",
        Format::Tag,
        Kind::CoordinateSystem,
        0,
    ),
    motion_control(1),
    op("Move Type", INTEGER, Format::ImmediateOrTag, Kind::Integer, 2),
    op("Position", "REAL array", Format::Array, Kind::Values, 3),
    op("Circle Type", INTEGER, Format::ImmediateOrTag, Kind::Integer, 4),
    op(
        "Via/Center/Radius",
        "REAL array or REAL",
        Format::Array,
        Kind::Values,
        5,
    ),
    op("Direction", INTEGER, Format::ImmediateOrTag, Kind::Integer, 6),
    op("Speed", NUMERIC, Format::ImmediateOrTag, Kind::Number, 7),
    op(
        "Speed Units",
        INTEGER,
        Format::Immediate,
        Kind::Enumeration(SPEED_UNITS),
        8,
    ),
    op("Accel Rate", NUMERIC, Format::ImmediateOrTag, Kind::Number, 9),
    op(
        "Accel Units",
        INTEGER,
        Format::Immediate,
        Kind::Enumeration(ACCEL_UNITS),
        10,
    ),
    op("Decel Rate", NUMERIC, Format::ImmediateOrTag, Kind::Number, 11),
    op(
        "Decel Units",
        INTEGER,
        Format::Immediate,
        Kind::Enumeration(ACCEL_UNITS),
        12,
    ),
    op("Profile", INTEGER, Format::Immediate, Kind::Enumeration(PROFILE), 13),
    op("Accel Jerk", NUMERIC, Format::ImmediateOrTag, Kind::Number, 17),
    op("Decel Jerk", NUMERIC, Format::ImmediateOrTag, Kind::Number, 18),
    op(
        "Jerk Units",
        INTEGER,
        Format::ImmediateOrTag,
        Kind::Enumeration(JERK_UNITS),
        19,
    ),
    op("Termination Type", INTEGER, Format::ImmediateOrTag, Kind::Integer, 14),
    op("Merge", INTEGER, Format::Immediate, Kind::Enumeration(MERGE), 15),
    op(
        "Merge Speed",
        INTEGER,
        Format::Immediate,
        Kind::Enumeration(MERGE_SPEED),
        16,
    ),
    op("Command Tolerance", "REAL", Format::ImmediateOrTag, Kind::Number, 20),
    op("Lock Position", "REAL", Format::ImmediateOrTag, Kind::Number, 21),
    op(
        "Lock Direction",
        "UINT32",
        Format::ImmediateOrTag,
        Kind::Enumeration(LOCK_DIRECTION),
        22,
    ),
    op(
        "Event Distance",
        "REAL ARRAY or 0",
        Format::Array,
        Kind::OptionalArray,
        23,
    ),
    op(
        "Calculated Data",
        "REAL ARRAY or 0",
        Format::Array,
        Kind::OptionalArray,
        24,
    ),
];

/// The MCCM operands MCLM lacks (their faceplate slots 4–6).
const CIRCLE_OPERANDS: usize = 3;

/// MCLM's operands: MCCM's without Circle Type, Via/Center/Radius and
/// Direction; the faceplate indices after them move down by three.
pub const MCLM_OPERANDS: [Operand; MCCM_OPERANDS.len() - CIRCLE_OPERANDS] = {
    let first_circle = 4;
    let mut out = [MCCM_OPERANDS[0]; MCCM_OPERANDS.len() - CIRCLE_OPERANDS];
    let (mut from, mut to) = (0, 0);
    while from < MCCM_OPERANDS.len() {
        let mut operand = MCCM_OPERANDS[from];
        from += 1;
        if operand.faceplate >= first_circle && operand.faceplate < first_circle + CIRCLE_OPERANDS as i32 {
            continue;
        }
        if operand.faceplate >= first_circle {
            operand.faceplate -= CIRCLE_OPERANDS as i32;
        }
        out[to] = operand;
        to += 1;
    }
    out
};

/// Faceplate operand indices of one instruction (EXERR of ERR 13), read
/// from its operand table.
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
    pub const MCCM: Self = Self::of(MCCM_OPERANDS);
    /// MCLM's faceplate order (no circle operands: those are −1).
    pub const MCLM: Self = Self::of(&MCLM_OPERANDS);

    /// The indices of a coordinated move instruction, read from its
    /// operand table.
    const fn of(operands: &[Operand]) -> Self {
        Self {
            coordinate_system: catalogue::faceplate(operands, "Coordinate System"),
            move_type: catalogue::faceplate(operands, "Move Type"),
            position: catalogue::faceplate(operands, "Position"),
            circle_type: none_is_minus_one(catalogue::faceplate_of(operands, "Circle Type")),
            via_center_radius: none_is_minus_one(catalogue::faceplate_of(operands, "Via/Center/Radius")),
            direction: none_is_minus_one(catalogue::faceplate_of(operands, "Direction")),
            speed: catalogue::faceplate(operands, "Speed"),
            speed_units: catalogue::faceplate(operands, "Speed Units"),
            accel_rate: catalogue::faceplate(operands, "Accel Rate"),
            accel_units: catalogue::faceplate(operands, "Accel Units"),
            decel_rate: catalogue::faceplate(operands, "Decel Rate"),
            decel_units: catalogue::faceplate(operands, "Decel Units"),
            profile: catalogue::faceplate(operands, "Profile"),
            termination_type: catalogue::faceplate(operands, "Termination Type"),
            merge: catalogue::faceplate(operands, "Merge"),
            merge_speed: catalogue::faceplate(operands, "Merge Speed"),
            accel_jerk: catalogue::faceplate(operands, "Accel Jerk"),
            decel_jerk: catalogue::faceplate(operands, "Decel Jerk"),
            jerk_units: catalogue::faceplate(operands, "Jerk Units"),
            command_tolerance: catalogue::faceplate(operands, "Command Tolerance"),
            lock_position: catalogue::faceplate(operands, "Lock Position"),
            lock_direction: catalogue::faceplate(operands, "Lock Direction"),
            event_distance: catalogue::faceplate(operands, "Event Distance"),
        }
    }
}

const fn none_is_minus_one(index: Option<i32>) -> i32 {
    match index {
        Some(index) => index,
        None => -1,
    }
}

/// The own refusals of the coordinated moves (MCLM, MCCM) and stop (MCS),
/// beyond the shared ERR 13 and axis-state ones ([`CoordMoveError`]).
#[derive(Debug, Clone, Copy, PartialEq, Error)]
#[non_exhaustive]
pub enum CoordFault {
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
    /// ERR 201: a master-driven move would take over from time-driven
    /// motion while the master stands still and the system moves
    /// ([`crate::task::ERR_IDLE_MASTER_SLAVE_MOVING`]).
    #[error("ERR 201 master-driven move while the master stands still and the system moves")]
    IdleMasterSlaveMoving,
}

impl LogixFault for CoordFault {
    fn err(&self) -> i32 {
        match self {
            Self::RadiusIn3d => 25,
            Self::Collinear => 44,
            Self::EndpointEqualsStartpoint => 45,
            Self::RadiusMismatch { .. } => 46,
            Self::RadiusTooSmall { .. } => 49,
            Self::MaxDecelZero { .. } => 54,
            Self::IdleMasterSlaveMoving => 201,
        }
    }

    fn exerr(&self) -> i32 {
        match self {
            Self::MaxDecelZero { exerr } => *exerr,
            _ => 0,
        }
    }
}

/// Why a coordinated move (MCLM, MCCM) or stop (MCS) cannot start: ERR 13
/// naming the operand (EXERR: its faceplate index), an axis' state (EXERR:
/// the axis' index in the system), or [`CoordFault`].
pub type CoordMoveError = Refusal<CoordFault>;

pub(crate) fn out_of_range(exerr: i32) -> CoordMoveError {
    Refusal::operand_index(exerr)
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
