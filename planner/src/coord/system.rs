//! A coordinate system: its configuration (the `COORDINATE_SYSTEM`
//! properties), its axes and its status bits.

use crate::vector::{V3, norm, sub};
use thiserror::Error;

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
///   [`super::LockDirection`]); never set for lock direction none.
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
