//! Motion Axis Position Cam (MAPC): a slave axis follows a master axis
//! through a calculated cam profile.
//!
//! [`Mapc::new`] validates the operands; [`axis::PositionCamAxis`] is the position
//! cam process of one slave axis (its active cam, the cam waiting to start,
//! and the slave's Position Cam Status / Lock Status / Pending Status). The
//! [`crate::task::MotionTask`] owns one per axis and drives it each coarse
//! update; this module knows no axes, only master positions handed in.
//!
//! # Position law
//! With master position `m` (Actual or Command per Master Reference, plus the
//! slave's master offset), the cam coordinate is
//! `u = u_ref + (c − c_ref) / MasterScaling`, where `c` is the *clutch* master
//! position (below) and `(c_ref, u_ref)` the point where the cam locked
//! (`u_ref` = Cam Lock Position at the Master Lock Position, or at the
//! master's position for Immediate). The slave command is
//! `slave_start + sign · SlaveScaling · (F(u) − F(u_start))`: the cam's
//! contribution is *added to* the slave position it locked at (spec: "added
//! to the command position"), so locking never makes the slave jump — the
//! spec's Cam Lock Position table (slave' = slave − slave(Cam Lock)).
//! `F` is the profile, clamped to its master range in Once and Persistent
//! modes, and unwound in Continuous mode (`F(u + P) = F(u) + (y_end − y_start)`
//! with `P` the master range).
//!
//! # Operands
//! * **Direction** Same (+), Opposite (−), Reverse (flips the axis' current
//!   or previous camming direction; Opposite the first time), Unchanged
//!   (keeps it; Same the first time). The memory is per slave axis and is
//!   updated when an MAPC executes.
//! * **Slave/Master Scaling** multiply the profile's slave/master values.
//! * **Execution Mode** Once: ends when `u` leaves the master range (the
//!   slave stays at the end value), `.PC` set, Position Cam Status reset.
//!   Continuous: repeats indefinitely. Persistent: the slave holds at the end
//!   value while `u` is outside the range (Lock Status reset) and follows
//!   again when the master comes back; it never completes.
//! * **Execution Schedule** Immediate: locks now, Master Lock Position
//!   ignored. Forward only / Reverse only / Bidirectional: locks when the
//!   master crosses the Master Lock Position in that direction (reaching it
//!   counts). Pending: starts when the active cam ends (Once: crossing its
//!   boundary; Continuous: at the end of the current cycle; Persistent: when
//!   the master leaves the range), at that exact boundary point, at its own
//!   Cam Lock Position, using the active cam's master and master reference
//!   (the Master Axis, Master Lock Position and Master Reference operands are
//!   ignored). A Pending cam executed with no cam active is preloaded: no
//!   motion until a non-pending MAPC starts a cam, which it then follows.
//! * **Master Lock Position** on a modulo (rotary) master is independent of
//!   the turns count: any `MasterLock + k · period` is a lock position.
//!   It is compared with master position + the slave's
//!   master offset ([`axis::PositionCamAxis::shift_master_offset`], a master offset
//!   move): with offset X the slave locks at master `MasterLock − X`. Every
//!   non-pending MAPC resets the master offset to 0.
//! * **Cam Lock Position** must lie in the profile's master range (else ERR 13,
//!   EXERR 10).
//! * **Cam Type** New: supersedes the active cam (and a scheduled replacement;
//!   a Pending cam stays). Replace and Restart: the replacement starts at its
//!   Cam Lock Position from the slave's position at the replacement point
//!   (velocity may jump: the spec makes that the user's concern). Replace and
//!   Continue: the replacement continues from the active cam's coordinate `u`
//!   at the replacement point and from the active cam's lock reference, so
//!   the slave moves to the replacement profile's position there (the spec's
//!   "sudden change"); Cam Lock Position ignored. A replacement cancels a
//!   Pending cam when it executes (its `.IP` is reset). With a schedule other
//!   than Immediate it waits (Pending Status set) until the master crosses its
//!   Master Lock Position, then replaces. A replacement executed while no cam
//!   is active acts as a New cam.
//! * **Master Direction** (slip clutch) Forward only: the clutch position `c`
//!   follows the master only forward (`c = max(c, m)`); while the master is
//!   behind `c` the slave holds (Lock Status reset) and picks up again when the
//!   master gets back to where it reversed. Reverse only mirrors this.
//!   Bidirectional: `c = m`. A replacement that takes over from a slipping cam
//!   with the same restricted direction inherits its clutch, so it too picks
//!   up where the master reversed (the spec's "Replace and Continue with
//!   Active Cam Unlocked" figure: `.AC` at the Master Lock Position, the slave
//!   held where it was until the master is back at the reversal point, then
//!   driven by the replacement).
//!
//! # Status bits
//! * Position Cam Status: a cam is active (waiting for its lock or running)
//!   or a scheduled replacement waits. A Pending cam alone (preloaded) does not
//!   set it.
//! * Position Cam Lock Status: the active cam drives the slave: running, not
//!   slipping, and (Once/Persistent) `u` inside the master range.
//! * Position Cam Pending Status: a Pending cam or a scheduled replacement
//!   waits.
//!
//! # Errors
//! ERR 13 (Parameter Out of Range) with EXERR = the operand's faceplate number
//! ([`operand`]); ERR 32 (Cam Profile Not Calculated) for a profile with
//! Status 0 and ERR 30 (Cam Profile Being Calculated) for Status 1 — the
//! spec's "0, 1: not calculated yet". The spec's `.SEGMENT` errors 28/29/179
//! on a cam profile cannot arise here: a [`crate::mccp::CamProfile`] is validated when it
//! is built (MCCP, or [`crate::mccp::CamProfile::from_elements`] for a profile written
//! element by element, which reports them with SEGMENT).
//! One case of 179 remains at run time (a choice): a running cam whose slave
//! position is no longer a finite number (Slave/Master Scaling and master
//! travel so extreme that `f64` overflows) ends, the slave holds its last
//! position, and the MAPC gets `.ER` with ERR 179 (SEGMENT 0).
//!
//! # Choices where the spec is silent
//! * A replacement waiting for its lock when the active Once cam completes
//!   stays armed and starts (as a new cam, from the slave's position) when
//!   the master crosses its lock position.
//! * A second Pending cam supersedes the first; a Pending cam supersedes a
//!   waiting scheduled replacement.
//! * MAPC with the slave as its own master is ERR 13, EXERR 1.
//! * **Speed rule**: no drive follows a cam that would command, at the
//!   master's maximum speed, a slave speed beyond all reason — a cam whose
//!   master points are 10⁻¹² apart commanded 1.2·10¹⁶ deg/s. The peak slave
//!   speed is the profile's steepest slope ([`crate::mccp::CamProfile::peak_slope`])
//!   × |Slave Scaling / Master Scaling| × the master axis' maximum speed
//!   ([`peak_slave_speed`]); MAPC refuses a cam whose peak slave speed is
//!   not finite or exceeds [`MAX_CAM_SPEED_RATIO`] × the slave axis'
//!   maximum speed, with ERR 13 (parameter out of range), EXERR = the Slave
//!   Scaling operand. The factor leaves room for masters whose maximum speed
//!   is set far above what they run at; the drive's own limits (position
//!   error, torque) act below it.

use crate::catalogue::words::{
    ACTUAL_COMMAND, CAM_TYPE, EXECUTION_MODE, EXECUTION_SCHEDULE, MAPC_DIRECTION, MASTER_DIRECTION, motion_control, op,
};
use crate::catalogue::{Format, Kind, Operand};
use thiserror::Error;

/// How far a cam's peak slave speed may exceed the slave axis' maximum
/// speed before MAPC refuses it (the speed rule in the module doc).
pub const MAX_CAM_SPEED_RATIO: f64 = 1000.0;

/// The peak slave speed of a cam (units/s): `peak_slope` (slave units per
/// master unit of the profile) × |Slave Scaling / Master Scaling| ×
/// `master_max_speed`. NaN or infinite when any of them is.
pub fn peak_slave_speed(peak_slope: f64, mapc: &Mapc, master_max_speed: f64) -> f64 {
    peak_slope * (mapc.slave_scaling / mapc.master_scaling).abs() * master_max_speed
}

pub mod axis;

/// Direction operand.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum CamDirection {
    /// 0: slave values in the master's sense.
    #[default]
    Same,
    /// 1: slave values in the opposite sense.
    Opposite,
    /// 2: the current or previous direction reversed (Opposite the first time).
    Reverse,
    /// 3: the current or previous direction kept (Same the first time).
    Unchanged,
}

/// Execution Mode operand.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ExecutionMode {
    /// 0: until the cam boundary is crossed.
    #[default]
    Once,
    /// 1: repeated indefinitely.
    Continuous,
    /// 2: follows whenever the master is inside the range.
    Persistent,
}

/// Execution Schedule operand.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ExecutionSchedule {
    /// 0: lock now.
    #[default]
    Immediate,
    /// 1: start when the active cam ends.
    Pending,
    /// 2: lock when the master crosses the lock position forward.
    ForwardOnly,
    /// 3: lock when the master crosses the lock position in reverse.
    ReverseOnly,
    /// 4: lock when the master crosses the lock position either way.
    Bidirectional,
}

/// Cam Type operand.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum CamType {
    /// 0: a new cam.
    #[default]
    NewCam,
    /// 1: replace the active cam, starting at the Cam Lock Position.
    ReplaceAndRestart,
    /// 2: replace the active cam, continuing at its current point.
    ReplaceAndContinue,
}

/// Master Reference operand.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum MasterReference {
    /// 0: the master's actual (measured) position.
    #[default]
    Actual,
    /// 1: the master's command position.
    Command,
}

/// Master Direction operand (the slip clutch).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum MasterDirection {
    /// 0: the slave follows the master both ways.
    #[default]
    Bidirectional,
    /// 1: the slave follows only forward master motion.
    ForwardOnly,
    /// 2: the slave follows only reverse master motion.
    ReverseOnly,
}

/// MAPC's numeric operands as the call gives them (Slave, Master, Motion
/// Control and Cam Profile are the task's handles).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MapcOperands {
    /// Direction, 0..=3 (default 0 Same).
    pub direction: i32,
    /// Slave Scaling (default 1).
    pub slave_scaling: f64,
    /// Master Scaling (default 1).
    pub master_scaling: f64,
    /// Execution Mode, 0..=2 (default 0 Once).
    pub execution_mode: i32,
    /// Execution Schedule, 0..=4 (default 0 Immediate).
    pub execution_schedule: i32,
    /// Master Lock Position, master units (default 0).
    pub master_lock_position: f64,
    /// Cam Lock Position, cam master units (default 0).
    pub cam_lock_position: f64,
    /// Cam Type, 0..=2 (default 0 New Cam).
    pub cam_type: i32,
    /// Master Reference, 0 Actual or 1 Command (default 0).
    pub master_reference: i32,
    /// Master Direction, 0..=2 (default 0 Bidirectional).
    pub master_direction: i32,
}

impl Default for MapcOperands {
    fn default() -> Self {
        Self {
            direction: 0,
            slave_scaling: 1.0,
            master_scaling: 1.0,
            execution_mode: 0,
            execution_schedule: 0,
            master_lock_position: 0.0,
            cam_lock_position: 0.0,
            cam_type: 0,
            master_reference: 0,
            master_direction: 0,
        }
    }
}

/// MAPC's operands (its catalogue entry is `task/instructions/mapc.rs`;
/// they are here beside the validation that names them).
pub const MAPC_OPERANDS: &[Operand] = &[
    op("Slave Axis", "AXIS", Format::Tag, Kind::Axis, 0),
    op("Master Axis", "AXIS", Format::Tag, Kind::Axis, 1),
    motion_control(2),
    op(
        "Direction",
        "DINT",
        Format::Immediate,
        Kind::Enumeration(MAPC_DIRECTION),
        3,
    ),
    op("Cam Profile", "CAM_PROFILE", Format::Array, Kind::CamProfile, 4),
    op("Slave Scaling", "REAL", Format::ImmediateOrTag, Kind::Number, 5),
    op("Master Scaling", "REAL", Format::ImmediateOrTag, Kind::Number, 6),
    op(
        "Execution Mode",
        "DINT",
        Format::Immediate,
        Kind::Enumeration(EXECUTION_MODE),
        7,
    ),
    op(
        "Execution Schedule",
        "DINT",
        Format::Immediate,
        Kind::Enumeration(EXECUTION_SCHEDULE),
        8,
    ),
    op("Master Lock Position", "REAL", Format::ImmediateOrTag, Kind::Number, 9),
    op("Cam Lock Position", "REAL", Format::ImmediateOrTag, Kind::Number, 10),
    op("Cam Type", "DINT", Format::Immediate, Kind::Enumeration(CAM_TYPE), 11),
    op(
        "Master Reference",
        "DINT",
        Format::Immediate,
        Kind::Enumeration(ACTUAL_COMMAND),
        12,
    ),
    op(
        "Master Direction",
        "DINT",
        Format::Immediate,
        Kind::Enumeration(MASTER_DIRECTION),
        13,
    ),
];

/// Faceplate operand numbers (EXERR of ERR 13), read from
/// [`MAPC_OPERANDS`].
pub mod operand {
    use super::MAPC_OPERANDS;
    use crate::catalogue::faceplate;

    /// Slave Axis.
    pub const SLAVE: i32 = faceplate(MAPC_OPERANDS, "Slave Axis");
    /// Master Axis.
    pub const MASTER: i32 = faceplate(MAPC_OPERANDS, "Master Axis");
    /// Direction.
    pub const DIRECTION: i32 = faceplate(MAPC_OPERANDS, "Direction");
    /// Cam Profile.
    pub const CAM_PROFILE: i32 = faceplate(MAPC_OPERANDS, "Cam Profile");
    /// Slave Scaling.
    pub const SLAVE_SCALING: i32 = faceplate(MAPC_OPERANDS, "Slave Scaling");
    /// Master Scaling.
    pub const MASTER_SCALING: i32 = faceplate(MAPC_OPERANDS, "Master Scaling");
    /// Execution Mode.
    pub const EXECUTION_MODE: i32 = faceplate(MAPC_OPERANDS, "Execution Mode");
    /// Execution Schedule.
    pub const EXECUTION_SCHEDULE: i32 = faceplate(MAPC_OPERANDS, "Execution Schedule");
    /// Master Lock Position.
    pub const MASTER_LOCK_POSITION: i32 = faceplate(MAPC_OPERANDS, "Master Lock Position");
    /// Cam Lock Position.
    pub const CAM_LOCK_POSITION: i32 = faceplate(MAPC_OPERANDS, "Cam Lock Position");
    /// Cam Type.
    pub const CAM_TYPE: i32 = faceplate(MAPC_OPERANDS, "Cam Type");
    /// Master Reference.
    pub const MASTER_REFERENCE: i32 = faceplate(MAPC_OPERANDS, "Master Reference");
    /// Master Direction.
    pub const MASTER_DIRECTION: i32 = faceplate(MAPC_OPERANDS, "Master Direction");
}

/// Why an MAPC failed.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum MapcError {
    /// ERR 13: an operand out of range (EXERR = its faceplate number).
    #[error("parameter out of range: operand {operand} = {value} (ERR 13)")]
    ParameterOutOfRange {
        /// Operand number (EXERR), see [`operand`].
        operand: i32,
        /// Its value.
        value: f64,
    },
    /// ERR 30: the profile's Status is 1.
    #[error("cam profile is being calculated (Status 1) (ERR 30)")]
    CamProfileBeingCalculated,
    /// ERR 32: the profile's Status is 0.
    #[error("cam profile not calculated (Status 0) (ERR 32)")]
    CamProfileNotCalculated,
    /// The axis' state refuses the instruction (ERR 5, 7, 8, 16, 53 …; EXERR 0).
    #[error("{0}")]
    State(crate::servo::StateError),
}

impl crate::instruction::LogixFault for MapcError {
    fn err(&self) -> i32 {
        MapcError::err(self)
    }

    fn exerr(&self) -> i32 {
        MapcError::exerr(self)
    }
}

impl MapcError {
    /// The `ERR` code.
    pub fn err(&self) -> i32 {
        match self {
            Self::ParameterOutOfRange { .. } => 13,
            Self::CamProfileBeingCalculated => 30,
            Self::CamProfileNotCalculated => 32,
            Self::State(e) => e.err(),
        }
    }

    /// The `EXERR` code.
    pub fn exerr(&self) -> i32 {
        match self {
            Self::ParameterOutOfRange { operand, .. } => *operand,
            _ => 0,
        }
    }

    /// The error for a profile whose Status makes it unusable (0 or 1).
    pub fn from_status(status: u32) -> Self {
        if status == 1 {
            Self::CamProfileBeingCalculated
        } else {
            Self::CamProfileNotCalculated
        }
    }
}

/// Validated MAPC operands.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Mapc {
    /// Direction.
    pub direction: CamDirection,
    /// Slave Scaling (finite).
    pub slave_scaling: f64,
    /// Master Scaling (finite, non-zero).
    pub master_scaling: f64,
    /// Execution Mode.
    pub execution_mode: ExecutionMode,
    /// Execution Schedule.
    pub execution_schedule: ExecutionSchedule,
    /// Master Lock Position (finite).
    pub master_lock_position: f64,
    /// Cam Lock Position (finite).
    pub cam_lock_position: f64,
    /// Cam Type.
    pub cam_type: CamType,
    /// Master Reference.
    pub master_reference: MasterReference,
    /// Master Direction.
    pub master_direction: MasterDirection,
}

impl Mapc {
    /// Validates the operands.
    ///
    /// # Errors
    /// [`MapcError::ParameterOutOfRange`] naming the first bad operand.
    pub fn new(o: &MapcOperands) -> Result<Self, MapcError> {
        let bad = |operand: i32, value: f64| MapcError::ParameterOutOfRange { operand, value };
        let pick = |operand: i32, v: i32, n: i32| {
            if (0..n).contains(&v) {
                Ok(v)
            } else {
                Err(bad(operand, f64::from(v)))
            }
        };
        let direction = match pick(operand::DIRECTION, o.direction, 4)? {
            0 => CamDirection::Same,
            1 => CamDirection::Opposite,
            2 => CamDirection::Reverse,
            _ => CamDirection::Unchanged,
        };
        if !o.slave_scaling.is_finite() {
            return Err(bad(operand::SLAVE_SCALING, o.slave_scaling));
        }
        if !(o.master_scaling.is_finite() && o.master_scaling != 0.0) {
            return Err(bad(operand::MASTER_SCALING, o.master_scaling));
        }
        let execution_mode = match pick(operand::EXECUTION_MODE, o.execution_mode, 3)? {
            0 => ExecutionMode::Once,
            1 => ExecutionMode::Continuous,
            _ => ExecutionMode::Persistent,
        };
        let execution_schedule = match pick(operand::EXECUTION_SCHEDULE, o.execution_schedule, 5)? {
            0 => ExecutionSchedule::Immediate,
            1 => ExecutionSchedule::Pending,
            2 => ExecutionSchedule::ForwardOnly,
            3 => ExecutionSchedule::ReverseOnly,
            _ => ExecutionSchedule::Bidirectional,
        };
        if !o.master_lock_position.is_finite() {
            return Err(bad(operand::MASTER_LOCK_POSITION, o.master_lock_position));
        }
        if !o.cam_lock_position.is_finite() {
            return Err(bad(operand::CAM_LOCK_POSITION, o.cam_lock_position));
        }
        let cam_type = match pick(operand::CAM_TYPE, o.cam_type, 3)? {
            0 => CamType::NewCam,
            1 => CamType::ReplaceAndRestart,
            _ => CamType::ReplaceAndContinue,
        };
        let master_reference = match pick(operand::MASTER_REFERENCE, o.master_reference, 2)? {
            0 => MasterReference::Actual,
            _ => MasterReference::Command,
        };
        let master_direction = match pick(operand::MASTER_DIRECTION, o.master_direction, 3)? {
            0 => MasterDirection::Bidirectional,
            1 => MasterDirection::ForwardOnly,
            _ => MasterDirection::ReverseOnly,
        };
        Ok(Self {
            direction,
            slave_scaling: o.slave_scaling,
            master_scaling: o.master_scaling,
            execution_mode,
            execution_schedule,
            master_lock_position: o.master_lock_position,
            cam_lock_position: o.cam_lock_position,
            cam_type,
            master_reference,
            master_direction,
        })
    }
}

#[cfg(test)]
mod tests;
