//! Coordinate systems (Logix `COORDINATE_SYSTEM`) and what every coordinated
//! move shares: the operands of MCLM and MCCM, their validation into a
//! [`CoordMove`], the path geometry (line or arc), and the status bits.
//!
//! # Coordinate system
//! [`CoordinateSystemConfig`] holds 1 to 3 *primary* Cartesian axes (the
//! first `primary_axes` of the system's axes; only they take part in the
//! vector speed and in arcs) and any number of further non-primary axes, the
//! vector's maximum speed, acceleration, deceleration, accel jerk and decel
//! jerk, and the command and actual tolerances. [`CoordinateSystem::new`]
//! validates it. A maximum deceleration of 0 is accepted, as Logix accepts it
//! in the properties dialog: a move on such a system fails with error 54,
//! EXERR −1 (the spec's rule).
//!
//! # Operands shared by MCLM and MCCM
//! Speed, accel and decel in units per second (0), % of maximum (1) or units
//! per master unit (4); profile trapezoidal (0) or S-curve (1); jerk in
//! units/s³ (0), % of maximum (1), % of time (2), units per master unit³ (4)
//! or % of time master driven (6), converted with the spec's formulas
//! ([`crate::profile::jerk_from_percent_of_time`]); termination types 0–6;
//! merge disabled / coordinated motion / all motion; merge speed programmed /
//! current; command tolerance (termination 6); lock position and direction
//! (master-driven moves); event distances (their calculated data is filled in
//! when the move is verified).
//!
//! # Choices where the spec is silent or contradicts itself
//! * **Operand indices** for ERR 13's EXERR are the faceplate order counted
//!   from 0. The MCCM table gives 0 coordinate system, 2 move type,
//!   3 position, 4 circle type, 5 via/center/radius, 6 direction, 7 speed,
//!   9 accel, 11 decel, 14 termination type (the faceplate without the jerk
//!   operands); the operands the table does not list continue that order:
//!   8 speed units, 10 accel units, 12 decel units, 13 profile, 15 merge,
//!   16 merge speed, 17 accel jerk, 18 decel jerk, 19 jerk units,
//!   20 command tolerance, 21 lock position, 22 lock direction, 23 event
//!   distance. MCLM has no circle operands, so its indices are the same list
//!   without 4–6 ([`OperandIndex::MCLM`]).
//! * **Termination type** range: the spec's table says "greater than 3" is an
//!   error, but its own enumeration lists 0–6; 0–6 are accepted. Types 4 and
//!   5 (follow contour) pass through the end point into a pending move
//!   without stopping (see `task/coord.rs`); without one they end like
//!   type 1.
//! * **Circle type** range: the table says "greater than 4"; the enumeration
//!   has 0–3, so 4 is an error too.
//! * **Speed 0** is legal (only < 0 is an error): the move is verified and
//!   stays in process at its start point until it is stopped or merged.
//! * **Accel or decel in % of maximum** of a system maximum of 0 gives a rate
//!   of 0, which is ERR 13 with the rate's index (a rate must be > 0).
//! * **Jerk** is checked only for S-curve moves (the spec: the values are used
//!   only then); a jerk ≤ 0, a % > 100 or a mode that does not match the
//!   speed units (time vs master) is ERR 13 with the jerk operand's index.
//! * **Master-driven**: speed, accel and decel units must all be per master
//!   unit (4) or all per second; a mix is ERR 13 with the index of the first
//!   operand that differs from the speed units. A master-driven move on a
//!   system without a master axis is ERR 13 with EXERR 8 (speed units).
//! * **Non-primary axes** move linearly with the path fraction (s / L), so they
//!   arrive with the primary axes; they do not count in the vector speed. A
//!   line that moves only non-primary axes uses their Euclidean distance as
//!   its path length.
//! * **Point tolerance**: two points are the same when they are closer than
//!   1e-9 · (1 + |start| + |end|) coordinate units; three points are collinear
//!   when the sine of their angle is below 1e-9.
//! * **Event distance** < 0 or not finite is ERR 13, EXERR 23 (MCCM) / 20
//!   (MCLM); a distance longer than the move gives 0 (the start).

use crate::profile::{
    JerkUnits, Limits, LimitsError, Profile, State, jerk_from_percent_of_time, jerk_to_units_per_sec3,
};
use thiserror::Error;

/// Three-component vector helpers (primary axes, zero-padded).
pub(crate) type V3 = [f64; 3];

pub(crate) fn sub(a: V3, b: V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
pub(crate) fn add(a: V3, b: V3) -> V3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
pub(crate) fn scale(a: V3, k: f64) -> V3 {
    [a[0] * k, a[1] * k, a[2] * k]
}
pub(crate) fn dot(a: V3, b: V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
pub(crate) fn cross(a: V3, b: V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
pub(crate) fn norm(a: V3) -> f64 {
    dot(a, a).sqrt()
}

/// Whether two points are the same within the documented point tolerance.
pub(crate) fn same_point(a: V3, b: V3) -> bool {
    norm(sub(a, b)) <= 1e-9 * (1.0 + norm(a) + norm(b))
}

/// Configuration of a coordinate system (the `COORDINATE_SYSTEM` properties).
#[derive(Debug, Clone, PartialEq)]
pub struct CoordinateSystemConfig {
    /// Tag name.
    pub name: String,
    /// Number of axes in the system, primary first (default 3).
    pub axis_count: usize,
    /// Number of primary axes, 1 to 3 (default 3).
    pub primary_axes: usize,
    /// Maximum vector speed, units/s (default 1).
    pub max_speed: f64,
    /// Maximum vector acceleration, units/s² (default 10).
    pub max_accel: f64,
    /// Maximum vector deceleration, units/s² (default 10; 0 is accepted and
    /// makes every move fail with error 54).
    pub max_decel: f64,
    /// Maximum accel jerk, units/s³, for jerk in % of maximum (default 100).
    pub max_accel_jerk: f64,
    /// Maximum decel jerk, units/s³, for jerk in % of maximum (default 100).
    pub max_decel_jerk: f64,
    /// Command tolerance, units (default 0.1): where termination type 2
    /// starts its blend, and the `CommandPosToleranceStatus` distance.
    pub command_tolerance: f64,
    /// Actual tolerance, units (default 0.01): termination type 0 completes
    /// when the actual position is this close to the end point.
    pub actual_tolerance: f64,
}

impl CoordinateSystemConfig {
    /// A configuration with the documented defaults.
    pub fn new(name: impl Into<String>) -> Self {
        Self {
            name: name.into(),
            axis_count: 3,
            primary_axes: 3,
            max_speed: 1.0,
            max_accel: 10.0,
            max_decel: 10.0,
            max_accel_jerk: 100.0,
            max_decel_jerk: 100.0,
            command_tolerance: 0.1,
            actual_tolerance: 0.01,
        }
    }
}

/// A coordinate system configuration field out of range.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum CoordConfigError {
    /// `primary_axes` must be 1..=3 and at most `axis_count`.
    #[error("coordinate system {name}: primary_axes {primary} must be 1..=3 and <= axis_count {count}")]
    PrimaryAxes {
        /// System name.
        name: String,
        /// Primary axes given.
        primary: usize,
        /// Axis count given.
        count: usize,
    },
    /// A field must be finite and ≥ 0 (speed, accel: > 0).
    #[error("coordinate system {name}: {field} must be finite and {allowed}, got {value}")]
    Field {
        /// System name.
        name: String,
        /// Field name.
        field: &'static str,
        /// The accepted range.
        allowed: &'static str,
        /// The value given.
        value: f64,
    },
}

/// A validated coordinate system configuration.
#[derive(Debug, Clone, PartialEq)]
pub struct CoordinateSystem {
    config: CoordinateSystemConfig,
}

impl CoordinateSystem {
    /// Validates `config`.
    ///
    /// # Errors
    /// [`CoordConfigError`] naming the first field out of range.
    pub fn new(config: CoordinateSystemConfig) -> Result<Self, CoordConfigError> {
        let c = &config;
        if !(1..=3).contains(&c.primary_axes) || c.primary_axes > c.axis_count {
            return Err(CoordConfigError::PrimaryAxes {
                name: c.name.clone(),
                primary: c.primary_axes,
                count: c.axis_count,
            });
        }
        let check = |field, value: f64, strict: bool| {
            let ok = value.is_finite() && if strict { value > 0.0 } else { value >= 0.0 };
            if ok {
                Ok(())
            } else {
                Err(CoordConfigError::Field {
                    name: c.name.clone(),
                    field,
                    allowed: if strict { "> 0" } else { ">= 0" },
                    value,
                })
            }
        };
        check("max_speed", c.max_speed, true)?;
        check("max_accel", c.max_accel, true)?;
        check("max_decel", c.max_decel, false)?;
        check("max_accel_jerk", c.max_accel_jerk, false)?;
        check("max_decel_jerk", c.max_decel_jerk, false)?;
        check("command_tolerance", c.command_tolerance, false)?;
        check("actual_tolerance", c.actual_tolerance, false)?;
        Ok(Self { config })
    }

    /// The configuration.
    pub fn config(&self) -> &CoordinateSystemConfig {
        &self.config
    }
}

/// Coordinate system and coordinated motion status bits (the
/// `COORDINATE_SYSTEM` tag's status members).
///
/// Set/clear rules (spec, "MCCM Changes to Status Bits"), as the
/// [`crate::task::MotionTask`] applies them:
/// * `motion` — a coordinated move is active on the system.
/// * `accel` / `decel` — the vector accelerates / decelerates; both clear
///   while a blend is in process and when motion concludes.
/// * `actual_pos_tolerance` — termination type 0 only: interpolation is
///   complete and the actual distance to the end point is within the actual
///   tolerance; stays set after completion; reset when a new move starts.
/// * `command_pos_tolerance` — the command distance to the end point is below
///   the command tolerance (the operand's for type 6); reset when a new move
///   starts, and for types 2, 3, 6 when the blend starts.
/// * `stopping` — an MCS is stopping the system; cleared when the stop
///   completes or an MCLM/MCCM executes.
/// * `move_` — a move began axis motion; cleared at the `.PC` of the last
///   move or by a stop.
/// * `move_transition` — a blend (types 2, 3, 6) is in process and the
///   machine is off the programmed path (not set for collinear blends);
///   cleared when the blend completes or by a stop.
/// * `move_pending`, `move_pending_queue_full` — a move waits in the queue
///   (one place, so both are always equal, as the spec says).
/// * `coord_motion_lock` — a master-driven move follows its master (see
///   [`LockDirection`]); never set for lock direction none.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct CoordStatus {
    /// `MotionStatus`.
    pub motion: bool,
    /// `AccelStatus`.
    pub accel: bool,
    /// `DecelStatus`.
    pub decel: bool,
    /// `ActualPosToleranceStatus`.
    pub actual_pos_tolerance: bool,
    /// `CommandPosToleranceStatus`.
    pub command_pos_tolerance: bool,
    /// `StoppingStatus`.
    pub stopping: bool,
    /// `MoveStatus`.
    pub move_: bool,
    /// `MoveTransitionStatus`.
    pub move_transition: bool,
    /// `MovePendingStatus`.
    pub move_pending: bool,
    /// `MovePendingQueueFullStatus`.
    pub move_pending_queue_full: bool,
    /// `CoordMotionLockStatus`.
    pub coord_motion_lock: bool,
}

impl CoordStatus {
    /// The bits with their Logix member names, in a fixed order (for traces).
    pub fn bits(&self) -> [(&'static str, bool); 11] {
        [
            ("MotionStatus", self.motion),
            ("AccelStatus", self.accel),
            ("DecelStatus", self.decel),
            ("ActualPosToleranceStatus", self.actual_pos_tolerance),
            ("CommandPosToleranceStatus", self.command_pos_tolerance),
            ("StoppingStatus", self.stopping),
            ("MoveStatus", self.move_),
            ("MoveTransitionStatus", self.move_transition),
            ("MovePendingStatus", self.move_pending),
            ("MovePendingQueueFullStatus", self.move_pending_queue_full),
            ("CoordMotionLockStatus", self.coord_motion_lock),
        ]
    }

    /// Clears the bits of motion in process (`MotionStatus`, `AccelStatus`,
    /// `DecelStatus`, `StoppingStatus`, `MoveStatus`, `MoveTransitionStatus`,
    /// `CoordMotionLockStatus`): the system is at rest. The tolerance and
    /// queue bits are left to their own rules.
    pub(crate) fn clear_motion(&mut self) {
        self.motion = false;
        self.accel = false;
        self.decel = false;
        self.stopping = false;
        self.move_ = false;
        self.move_transition = false;
        self.coord_motion_lock = false;
    }

    /// A bit by its Logix member name (case-insensitive).
    pub fn bit(&self, name: &str) -> Option<bool> {
        self.bits()
            .into_iter()
            .find(|(n, _)| n.eq_ignore_ascii_case(name))
            .map(|(_, b)| b)
    }
}

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
    fn from_code(code: i64) -> Option<Self> {
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
    /// Speed (≥ 0).
    pub speed: f64,
    /// Speed Units (0 units/s, 1 % of maximum, 4 units per master unit).
    pub speed_units: i64,
    /// Accel Rate (> 0).
    pub accel_rate: f64,
    /// Accel Units (0, 1, 4).
    pub accel_units: i64,
    /// Decel Rate (> 0).
    pub decel_rate: f64,
    /// Decel Units (0, 1, 4).
    pub decel_units: i64,
    /// Profile (0 trapezoidal, 1 S-curve).
    pub profile: i64,
    /// Accel Jerk.
    pub accel_jerk: f64,
    /// Decel Jerk.
    pub decel_jerk: f64,
    /// Jerk Units (0, 1, 2, 4, 6).
    pub jerk_units: i64,
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

/// Faceplate operand indices of one instruction (EXERR of ERR 13).
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
    pub const MCCM: Self = Self {
        coordinate_system: 0,
        move_type: 2,
        position: 3,
        circle_type: 4,
        via_center_radius: 5,
        direction: 6,
        speed: 7,
        speed_units: 8,
        accel_rate: 9,
        accel_units: 10,
        decel_rate: 11,
        decel_units: 12,
        profile: 13,
        termination_type: 14,
        merge: 15,
        merge_speed: 16,
        accel_jerk: 17,
        decel_jerk: 18,
        jerk_units: 19,
        command_tolerance: 20,
        lock_position: 21,
        lock_direction: 22,
        event_distance: 23,
    };
    /// MCLM's faceplate order (MCCM's without the three circle operands).
    pub const MCLM: Self = Self {
        coordinate_system: 0,
        move_type: 2,
        position: 3,
        circle_type: -1,
        via_center_radius: -1,
        direction: -1,
        speed: 4,
        speed_units: 5,
        accel_rate: 6,
        accel_units: 7,
        decel_rate: 8,
        decel_units: 9,
        profile: 10,
        termination_type: 11,
        merge: 12,
        merge_speed: 13,
        accel_jerk: 14,
        decel_jerk: 15,
        jerk_units: 16,
        command_tolerance: 17,
        lock_position: 18,
        lock_direction: 19,
        event_distance: 20,
    };
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

/// A path: the line or arc through the primary axes, with non-primary axes
/// moving linearly with the path fraction.
#[derive(Debug, Clone, PartialEq)]
pub struct PathGeometry {
    start: Vec<f64>,
    end: Vec<f64>,
    primary: usize,
    length: f64,
    shape: Shape,
}

#[derive(Debug, Clone, PartialEq)]
enum Shape {
    Line { direction: V3 },
    Arc(crate::mccm::Arc),
}

impl PathGeometry {
    pub(crate) fn line(start: Vec<f64>, end: Vec<f64>, primary: usize) -> Self {
        let p0 = primary_of(&start, primary);
        let p1 = primary_of(&end, primary);
        let mut length = norm(sub(p1, p0));
        let direction = if length > 0.0 {
            scale(sub(p1, p0), 1.0 / length)
        } else {
            [0.0; 3]
        };
        if length == 0.0 {
            // Only non-primary axes move: their distance is the path length.
            length = start[primary..]
                .iter()
                .zip(&end[primary..])
                .map(|(a, b)| (b - a) * (b - a))
                .sum::<f64>()
                .sqrt();
        }
        Self {
            start,
            end,
            primary,
            length,
            shape: Shape::Line { direction },
        }
    }

    pub(crate) fn circular(start: Vec<f64>, end: Vec<f64>, primary: usize, arc: crate::mccm::Arc) -> Self {
        Self {
            length: arc.length(),
            start,
            end,
            primary,
            shape: Shape::Arc(arc),
        }
    }

    /// Path length in coordinate units.
    pub fn length(&self) -> f64 {
        self.length
    }
    /// Start point (all axes).
    pub fn start(&self) -> &[f64] {
        &self.start
    }
    /// End point (all axes); exactly the programmed end point.
    pub fn end(&self) -> &[f64] {
        &self.end
    }
    /// The arc, for an arc path.
    pub fn arc(&self) -> Option<&crate::mccm::Arc> {
        match &self.shape {
            Shape::Arc(a) => Some(a),
            Shape::Line { .. } => None,
        }
    }

    /// Position and derivative d(position)/ds of every axis at path length
    /// `s` (clamped to [0, length]); exactly the end point at the end.
    pub fn point(&self, s: f64, position: &mut [f64], per_s: &mut [f64]) {
        let n = self.start.len();
        let s = s.clamp(0.0, self.length);
        if s >= self.length {
            position[..n].copy_from_slice(&self.end);
        }
        let frac = if self.length > 0.0 { s / self.length } else { 1.0 };
        let inv = if self.length > 0.0 { 1.0 / self.length } else { 0.0 };
        let (p, d) = match &self.shape {
            Shape::Line { direction } => {
                let p0 = primary_of(&self.start, self.primary);
                (add(p0, scale(*direction, s)), *direction)
            }
            Shape::Arc(arc) => arc.point_at_length(s),
        };
        let primary_zero = matches!(self.shape, Shape::Line { direction } if direction == [0.0; 3]);
        for i in 0..n {
            let (pi, di) = if i < self.primary && !primary_zero {
                (p[i], d[i])
            } else {
                let delta = self.end[i] - self.start[i];
                (self.start[i] + delta * frac, delta * inv)
            };
            if s < self.length {
                position[i] = pi;
            }
            per_s[i] = di;
        }
    }

    /// Unit tangent of the primary axes at path length `s`.
    pub fn tangent(&self, s: f64) -> V3 {
        let n = self.start.len();
        let mut p = vec![0.0; n];
        let mut d = vec![0.0; n];
        self.point(s, &mut p, &mut d);
        let t = primary_of(&d, self.primary);
        let l = norm(t);
        if l > 0.0 { scale(t, 1.0 / l) } else { t }
    }
}

pub(crate) fn primary_of(v: &[f64], primary: usize) -> V3 {
    let mut p = [0.0; 3];
    p[..primary].copy_from_slice(&v[..primary]);
    p
}

/// A verified coordinated move: its path, dynamics and termination.
#[derive(Debug, Clone, PartialEq)]
pub struct CoordMove {
    pub(crate) path: PathGeometry,
    pub(crate) driver: Driver,
    /// `None` for a move at speed 0 (it never advances).
    pub(crate) limits: Option<Limits>,
    pub(crate) termination: TerminationType,
    pub(crate) command_tolerance: f64,
    pub(crate) merge: Merge,
    pub(crate) merge_speed: MergeSpeed,
    pub(crate) lock_position: f64,
    pub(crate) lock_direction: LockDirection,
    /// The Event Distance operand (validated finite and ≥ 0).
    pub(crate) event_distance: Vec<f64>,
    /// Accel and decel jerk in % of time (S-curve with jerk units 2 or 6):
    /// the jerks follow the speed when a merge at current speed changes it.
    pub(crate) jerk_percent_of_time: Option<(f64, f64)>,
    pub(crate) calculated_data: Vec<f64>,
}

impl CoordMove {
    /// The path.
    pub fn path(&self) -> &PathGeometry {
        &self.path
    }
    /// Path limits (`None` for speed 0).
    pub fn limits(&self) -> Option<&Limits> {
        self.limits.as_ref()
    }
    /// Time or master driven.
    pub fn driver(&self) -> Driver {
        self.driver
    }
    /// The termination type.
    pub fn termination(&self) -> TerminationType {
        self.termination
    }
    /// Where a blend starts: the command tolerance of the system (type 2),
    /// of the operand (type 6), in units.
    pub fn command_tolerance(&self) -> f64 {
        self.command_tolerance
    }
    /// Merge.
    pub fn merge(&self) -> Merge {
        self.merge
    }
    /// Merge speed.
    pub fn merge_speed(&self) -> MergeSpeed {
        self.merge_speed
    }
    /// Lock direction and position.
    pub fn lock(&self) -> (LockDirection, f64) {
        (self.lock_direction, self.lock_position)
    }
    /// Calculated Data: for each event distance, the time (s) or master
    /// distance from the start of the move to the point that lies that far
    /// before its end, on the move's own profile from rest.
    pub fn calculated_data(&self) -> &[f64] {
        &self.calculated_data
    }

    /// The move's own path profile from rest (position = path length).
    pub fn rest_profile(&self) -> Profile {
        match &self.limits {
            Some(l) => Profile::to_position(State::at_rest(0.0), self.path.length, 0.0, l),
            None => Profile::hold(State::at_rest(0.0)),
        }
    }

    /// Same move with another maximum path speed (merge at current speed);
    /// its Calculated Data are those of the new speed.
    pub(crate) fn with_speed(&self, speed: f64) -> Self {
        let mut m = self.clone();
        let new = match (&self.limits, self.jerk_percent_of_time) {
            (Some(l), Some((pa, pd))) => {
                let aj = jerk_from_percent_of_time(pa, l.acceleration(), speed);
                let dj = jerk_from_percent_of_time(pd, l.deceleration(), speed);
                match (aj, dj) {
                    (Ok(aj), Ok(dj)) => Limits::s_curve(speed, l.acceleration(), l.deceleration(), aj, dj).ok(),
                    _ => None,
                }
            }
            (Some(l), None) => with_velocity(l, speed),
            (None, _) => None,
        };
        if let Some(new) = new {
            m.limits = Some(new);
            m.fill_calculated_data();
        }
        m
    }

    /// Calculated Data from the event distances on the move's rest profile.
    fn fill_calculated_data(&mut self) {
        let profile = self.rest_profile();
        let length = self.path.length;
        let moving = self.limits.is_some();
        self.calculated_data = self
            .event_distance
            .iter()
            .map(|d| {
                if moving {
                    progress_at_length(&profile, (length - d).max(0.0))
                } else {
                    0.0
                }
            })
            .collect();
    }
}

/// `l` with another maximum speed (same rates, jerks and shape).
pub(crate) fn with_velocity(l: &Limits, speed: f64) -> Option<Limits> {
    match l.shape() {
        crate::profile::Shape::Trapezoidal => Limits::trapezoidal(speed, l.acceleration(), l.deceleration()).ok(),
        crate::profile::Shape::SCurve { accel_jerk, decel_jerk } => {
            Limits::s_curve(speed, l.acceleration(), l.deceleration(), accel_jerk, decel_jerk).ok()
        }
    }
}

/// Progress (time or master distance) at which `profile` reaches path
/// length `s` (bisection; the profile never moves backwards).
pub(crate) fn progress_at_length(profile: &Profile, s: f64) -> f64 {
    let (mut lo, mut hi) = (0.0, profile.duration_s());
    if profile.sample(lo).position >= s {
        return 0.0;
    }
    if s >= profile.final_state().position {
        return hi;
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if profile.sample(mid).position >= s {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    hi
}

/// Resolves the operands shared by MCLM and MCCM, in faceplate order, and
/// returns the move's start and end points.
pub(crate) struct Resolved {
    pub start: Vec<f64>,
    pub end: Vec<f64>,
    pub move_type: MoveType,
}

pub(crate) fn resolve_move_type_and_position(
    inputs: &CoordMoveInputs,
    ctx: &MoveContext<'_>,
    idx: &OperandIndex,
) -> Result<Resolved, CoordMoveError> {
    let n = ctx.system.config().axis_count;
    let move_type = match inputs.move_type {
        0 => MoveType::Absolute,
        1 => MoveType::Incremental,
        _ => return Err(out_of_range(idx.move_type)),
    };
    if inputs.position.len() < n || inputs.position[..n].iter().any(|p| !p.is_finite()) {
        return Err(out_of_range(idx.position));
    }
    let start = ctx.start[..n].to_vec();
    let end = match move_type {
        MoveType::Absolute => inputs.position[..n].to_vec(),
        MoveType::Incremental => start.iter().zip(&inputs.position).map(|(s, p)| s + p).collect(),
    };
    Ok(Resolved { start, end, move_type })
}

/// Validates the dynamics, termination, merge, lock and event operands, then
/// builds the path with `path` (its own errors come after every ERR 13) and
/// the move. Call after the geometry operands were checked (the order of the
/// faceplate).
pub(crate) fn finish_move(
    inputs: &CoordMoveInputs,
    ctx: &MoveContext<'_>,
    idx: &OperandIndex,
    path: impl FnOnce() -> Result<PathGeometry, CoordMoveError>,
) -> Result<CoordMove, CoordMoveError> {
    let sys = ctx.system.config();
    let driver = match inputs.speed_units {
        0 | 1 => Driver::Time,
        4 => Driver::Master,
        _ => return Err(out_of_range(idx.speed_units)),
    };
    if !(inputs.speed.is_finite() && inputs.speed >= 0.0) {
        return Err(out_of_range(idx.speed));
    }
    let speed = if inputs.speed_units == 1 {
        inputs.speed / 100.0 * sys.max_speed
    } else {
        inputs.speed
    };
    let rate = |value: f64, units: i64, max: f64, value_idx: i32, units_idx: i32| {
        let unit_driver = match units {
            0 | 1 => Driver::Time,
            4 => Driver::Master,
            _ => return Err(out_of_range(units_idx)),
        };
        if unit_driver != driver {
            return Err(out_of_range(units_idx));
        }
        let r = if units == 1 { value / 100.0 * max } else { value };
        if r.is_finite() && r > 0.0 {
            Ok(r)
        } else {
            Err(out_of_range(value_idx))
        }
    };
    let accel = rate(
        inputs.accel_rate,
        inputs.accel_units,
        sys.max_accel,
        idx.accel_rate,
        idx.accel_units,
    )?;
    let decel = rate(
        inputs.decel_rate,
        inputs.decel_units,
        sys.max_decel,
        idx.decel_rate,
        idx.decel_units,
    )?;
    let s_curve = match inputs.profile {
        0 => false,
        1 => true,
        _ => return Err(out_of_range(idx.profile)),
    };
    let termination = TerminationType::from_code(inputs.termination_type).ok_or(out_of_range(idx.termination_type))?;
    let merge = match inputs.merge {
        0 => Merge::Disabled,
        1 => Merge::CoordinatedMotion,
        2 => Merge::AllMotion,
        _ => return Err(out_of_range(idx.merge)),
    };
    let merge_speed = match inputs.merge_speed {
        0 => MergeSpeed::Programmed,
        1 => MergeSpeed::Current,
        _ => return Err(out_of_range(idx.merge_speed)),
    };
    let command_tolerance = if termination == TerminationType::CommandToleranceProgrammed {
        if !(inputs.command_tolerance.is_finite() && inputs.command_tolerance >= 0.0) {
            return Err(out_of_range(idx.command_tolerance));
        }
        inputs.command_tolerance
    } else {
        sys.command_tolerance
    };
    let lock_direction = match inputs.lock_direction {
        0 => LockDirection::None,
        1 => LockDirection::ImmediateForwardOnly,
        2 => LockDirection::ImmediateReverseOnly,
        3 => LockDirection::PositionForward,
        4 => LockDirection::PositionReverse,
        _ => return Err(out_of_range(idx.lock_direction)),
    };
    if driver == Driver::Master && !inputs.lock_position.is_finite() {
        return Err(out_of_range(idx.lock_position));
    }
    if driver == Driver::Master && !ctx.has_master {
        return Err(out_of_range(idx.speed_units));
    }
    if inputs.event_distance.iter().any(|d| !(d.is_finite() && *d >= 0.0)) {
        return Err(out_of_range(idx.event_distance));
    }
    let limits = if speed > 0.0 {
        let limits = if s_curve {
            let units = match (inputs.jerk_units, driver) {
                (0, Driver::Time) | (4, Driver::Master) => JerkUnits::UnitsPerSec3,
                (1, _) => JerkUnits::PercentOfMaximum,
                (2, Driver::Time) | (6, Driver::Master) => JerkUnits::PercentOfTime,
                _ => return Err(out_of_range(idx.jerk_units)),
            };
            // % of time refers to the move's speed and its accel (decel) rate.
            let jerk = |value: f64, max: f64, rate: f64, exerr: i32| {
                jerk_to_units_per_sec3(value, units, max, rate, speed).map_err(|_| out_of_range(exerr))
            };
            let aj = jerk(inputs.accel_jerk, sys.max_accel_jerk, accel, idx.accel_jerk)?;
            let dj = jerk(inputs.decel_jerk, sys.max_decel_jerk, decel, idx.decel_jerk)?;
            Limits::s_curve(speed, accel, decel, aj, dj)
        } else {
            Limits::trapezoidal(speed, accel, decel)
        };
        // Every rate was checked > 0 above; a jerk error names its operand.
        Some(limits.map_err(|_: LimitsError| out_of_range(idx.speed))?)
    } else {
        None
    };
    // The geometry errors (25, 44, 45, 46, 49) after every ERR 13 check,
    // error 54 last: the system's, then each axis'.
    let path = path()?;
    if sys.max_decel == 0.0 {
        return Err(CoordMoveError::MaxDecelZero { exerr: -1 });
    }
    if let Some(i) = ctx.axis_max_decel.iter().position(|d| *d == 0.0) {
        return Err(CoordMoveError::MaxDecelZero { exerr: i as i32 });
    }
    let mut m = CoordMove {
        path,
        driver,
        limits,
        termination,
        command_tolerance,
        merge,
        merge_speed,
        lock_position: inputs.lock_position,
        lock_direction,
        event_distance: inputs.event_distance.clone(),
        jerk_percent_of_time: (s_curve
            && limits.is_some()
            && matches!((inputs.jerk_units, driver), (2, Driver::Time) | (6, Driver::Master)))
        .then_some((inputs.accel_jerk, inputs.decel_jerk)),
        calculated_data: Vec::new(),
    };
    m.fill_calculated_data();
    Ok(m)
}

/// MCS operands (Motion Coordinated Stop).
///
/// Stop Type 0 all (also stops single-axis motion on the system's axes),
/// 1 coordinated move (the coordinated motion only; 2 coordinated transform
/// is accepted and acts like 1, there is no transform here). Change Decel
/// 0 no (the system's maximum deceleration) / 1 yes (Decel Rate in Decel
/// Units, 0 units/s², 1 % of maximum). Change Decel Jerk 0/1 with Decel Jerk
/// in Jerk Units (0 units/s³, 1 % of maximum, 2 % of time); a trapezoidal
/// stop unless a jerk is changed. ERR 13 EXERR: 2 stop type, 3 change decel,
/// 4 decel rate, 5 decel units, 6 change decel jerk, 7 decel jerk,
/// 8 jerk units. ERR 54 EXERR −1 when the stop would use a system maximum
/// deceleration of 0.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct McsInputs {
    /// Stop Type (0 all, 1 coordinated move, 2 coordinated transform).
    pub stop_type: i64,
    /// Change Decel (0 no, 1 yes).
    pub change_decel: i64,
    /// Decel Rate.
    pub decel_rate: f64,
    /// Decel Units (0 units/s², 1 % of maximum).
    pub decel_units: i64,
    /// Change Decel Jerk (0 no, 1 yes).
    pub change_decel_jerk: i64,
    /// Decel Jerk.
    pub decel_jerk: f64,
    /// Jerk Units (0, 1, 2).
    pub jerk_units: i64,
}

impl Default for McsInputs {
    /// Stop all at the system's maximum deceleration.
    fn default() -> Self {
        Self {
            stop_type: 0,
            change_decel: 0,
            decel_rate: 100.0,
            decel_units: 1,
            change_decel_jerk: 0,
            decel_jerk: 100.0,
            jerk_units: 2,
        }
    }
}

/// A verified coordinated stop.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Mcs {
    /// Whether single-axis motion is stopped too (stop type all).
    pub stop_all: bool,
    /// Deceleration, units/s².
    pub decel: f64,
    /// Decel jerk, units/s³ (`None`: trapezoidal stop).
    pub decel_jerk: Option<f64>,
}

impl Mcs {
    /// Verifies MCS operands against `system`.
    ///
    /// # Errors
    /// ERR 13 with the operand index, ERR 54 (EXERR −1).
    pub fn new(inputs: &McsInputs, system: &CoordinateSystem) -> Result<Self, CoordMoveError> {
        let sys = system.config();
        let stop_all = match inputs.stop_type {
            0 => true,
            1 | 2 => false,
            _ => return Err(out_of_range(2)),
        };
        let decel = match inputs.change_decel {
            0 => sys.max_decel,
            1 => {
                let d = match inputs.decel_units {
                    0 => inputs.decel_rate,
                    1 => inputs.decel_rate / 100.0 * sys.max_decel,
                    _ => return Err(out_of_range(5)),
                };
                if !(d.is_finite() && d > 0.0) {
                    return Err(if sys.max_decel == 0.0 && inputs.decel_units == 1 {
                        CoordMoveError::MaxDecelZero { exerr: -1 }
                    } else {
                        out_of_range(4)
                    });
                }
                d
            }
            _ => return Err(out_of_range(3)),
        };
        if decel == 0.0 {
            return Err(CoordMoveError::MaxDecelZero { exerr: -1 });
        }
        let decel_jerk = match inputs.change_decel_jerk {
            0 => None,
            1 => {
                let units = JerkUnits::from_code(inputs.jerk_units).ok_or(out_of_range(8))?;
                Some(
                    jerk_to_units_per_sec3(inputs.decel_jerk, units, sys.max_decel_jerk, decel, sys.max_speed)
                        .map_err(|_| out_of_range(7))?,
                )
            }
            _ => return Err(out_of_range(6)),
        };
        Ok(Self {
            stop_all,
            decel,
            decel_jerk,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn system_validation_names_the_field() {
        let ok = CoordinateSystemConfig::new("CS");
        assert!(CoordinateSystem::new(ok.clone()).is_ok());
        for primary in [0, 4] {
            let c = CoordinateSystemConfig {
                primary_axes: primary,
                ..ok.clone()
            };
            assert!(matches!(
                CoordinateSystem::new(c),
                Err(CoordConfigError::PrimaryAxes { .. })
            ));
        }
        let c = CoordinateSystemConfig {
            axis_count: 2,
            ..ok.clone()
        };
        assert!(matches!(
            CoordinateSystem::new(c),
            Err(CoordConfigError::PrimaryAxes { .. })
        ));
        let c = CoordinateSystemConfig {
            max_speed: 0.0,
            ..ok.clone()
        };
        assert!(matches!(
            CoordinateSystem::new(c),
            Err(CoordConfigError::Field { field: "max_speed", .. })
        ));
        let c = CoordinateSystemConfig {
            command_tolerance: f64::NAN,
            ..ok.clone()
        };
        assert!(matches!(
            CoordinateSystem::new(c),
            Err(CoordConfigError::Field {
                field: "command_tolerance",
                ..
            })
        ));
        // A zero maximum deceleration is a configuration Logix accepts (error 54 at the move).
        let c = CoordinateSystemConfig { max_decel: 0.0, ..ok };
        assert!(CoordinateSystem::new(c).is_ok());
    }

    #[test]
    fn status_bits_by_name() {
        let s = CoordStatus {
            move_pending: true,
            ..Default::default()
        };
        assert_eq!(s.bit("MovePendingStatus"), Some(true));
        assert_eq!(s.bit("motionstatus"), Some(false));
        assert_eq!(s.bit("Nope"), None);
        assert_eq!(s.bits().len(), 11);
    }

    #[test]
    fn mcs_errors() {
        let sys = CoordinateSystem::new(CoordinateSystemConfig::new("CS")).unwrap();
        let e = |i: McsInputs| Mcs::new(&i, &sys).map(|_| ()).map_err(|e| (e.err(), e.exerr()));
        let d = McsInputs::default();
        assert_eq!(e(McsInputs { stop_type: 3, ..d }), Err((13, 2)));
        assert_eq!(e(McsInputs { change_decel: 2, ..d }), Err((13, 3)));
        assert_eq!(
            e(McsInputs {
                change_decel: 1,
                decel_rate: 0.0,
                ..d
            }),
            Err((13, 4))
        );
        assert_eq!(
            e(McsInputs {
                change_decel: 1,
                decel_units: 7,
                ..d
            }),
            Err((13, 5))
        );
        assert_eq!(
            e(McsInputs {
                change_decel_jerk: 9,
                ..d
            }),
            Err((13, 6))
        );
        assert_eq!(
            e(McsInputs {
                change_decel_jerk: 1,
                decel_jerk: -1.0,
                ..d
            }),
            Err((13, 7))
        );
        assert_eq!(
            e(McsInputs {
                change_decel_jerk: 1,
                jerk_units: 5,
                ..d
            }),
            Err((13, 8))
        );
        let zero = CoordinateSystem::new(CoordinateSystemConfig {
            max_decel: 0.0,
            ..CoordinateSystemConfig::new("Z")
        })
        .unwrap();
        assert_eq!(Mcs::new(&d, &zero).map_err(|e| (e.err(), e.exerr())), Err((54, -1)));
        let m = Mcs::new(
            &McsInputs {
                change_decel: 1,
                decel_rate: 50.0,
                decel_units: 1,
                ..d
            },
            &sys,
        )
        .unwrap();
        assert_eq!(m.decel, 5.0);
        assert!(m.stop_all);
    }
}
