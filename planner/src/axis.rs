//! Axes: configuration (linear, rotary, modulo), limits, and state.
//!
//! Positions are `f64` in the axis' position units (degrees for a rotary axis
//! configured in degrees, metres or millimetres for a linear one), exactly as
//! a PLC axis works in its configured units; the twin converts them to SI at
//! the joint. The command position is *unwrapped* (TwinCAT's absolute
//! "SetPos", continuous through full turns); a modulo axis also reports the
//! wrapped position through its [`Modulo`] period.

use crate::dynamics;
use crate::homing::Homing;
pub use crate::servo::AxisType;
use crate::servo::FaultAction;
use thiserror::Error;

/// Linear or rotary axis. Either may be modulo (TwinCAT makes no difference).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum AxisKind {
    /// A linear axis.
    #[default]
    Linear,
    /// A rotary axis.
    Rotary,
}

/// A modulo period (the unwind, e.g. 360 degrees): validated finite and > 0.
///
/// Wrapped positions are in `[0, period)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Modulo {
    period: f64,
}

impl Modulo {
    /// A modulo period.
    ///
    /// # Errors
    /// [`AxisConfigError::NotPositive`] when the period is not finite and > 0.
    pub fn new(period: f64) -> Result<Self, AxisConfigError> {
        positive("modulo_period", period).map(|period| Self { period })
    }

    /// The period in axis units.
    pub fn period(&self) -> f64 {
        self.period
    }

    /// `position` wrapped into `[0, period)`.
    pub fn wrap(&self, position: f64) -> f64 {
        let w = position - self.period * (position / self.period).floor();
        if w >= self.period || w < 0.0 { 0.0 } else { w }
    }
}

/// Configuration of one axis (the System Manager / axis properties page).
#[derive(Debug, Clone, PartialEq)]
pub struct AxisConfig {
    /// Axis tag name.
    pub name: String,
    /// Linear or rotary (default: linear).
    pub kind: AxisKind,
    /// Modulo period in axis units, e.g. 360 (default: none, not modulo).
    pub modulo_period: Option<f64>,
    /// Maximum speed, units/s (default 1). Instructions may not ask for more.
    pub max_velocity: f64,
    /// Default and maximum acceleration, units/s² (default 10); used when an
    /// instruction passes 0.
    pub max_acceleration: f64,
    /// Default deceleration, units/s² (default 10); used when an instruction
    /// passes 0.
    pub max_deceleration: f64,
    /// Default jerk, units/s³ (default 0 = no jerk limit: trapezoidal
    /// profiles); used when an instruction passes 0.
    pub max_jerk: f64,
    /// In-position window, ± units around the target (default 0.01).
    pub in_position_window: f64,
    /// Target position monitoring: `Done` waits for the actual position to be
    /// inside the in-position window (default true). Off: position range
    /// monitoring decides, or `Done` comes as soon as setpoint generation
    /// ends.
    pub target_position_monitoring: bool,
    /// Position range monitoring (TwinCAT "Position Range Monitoring"):
    /// with target position monitoring off, `Done` waits for the actual
    /// position to be inside the position range window (default false).
    pub position_range_monitoring: bool,
    /// Position range window, ± units around the target (default 5).
    pub position_range_window: f64,
    /// Motion commands are allowed on a coupled (cam or gear) slave
    /// (TwinCAT "Allow motion commands to slave axis"; default false): an
    /// MC_MoveModulo then decouples the axis and runs, with `MC_Aborting`
    /// only.
    pub allow_motion_on_coupled_slave: bool,
    /// Modulo tolerance window, ± units (default 0): a modulo move from
    /// standstill whose start is at most this far from its modulo target takes
    /// the shortest way to it, whatever the direction asked.
    pub modulo_tolerance_window: f64,
    /// Soft travel limits `(min, max)`, axis units (Logix
    /// `SoftTravelLimitNegative`, `SoftTravelLimitPositive` with soft
    /// overtravel checking on) (default: none). Finite, `min < max`, not on a
    /// modulo axis; the initial position must lie inside
    /// ([`crate::task::MotionTask::add_axis`]). The task watches the actual
    /// position against them (soft overtravel, [`crate::servo`]); what a
    /// transform commands never crosses them (see [`crate::task`] module
    /// `mct`).
    pub soft_travel_limits: Option<(f64, f64)>,
    /// What the axis does on a soft overtravel (the Motion Exception Action
    /// of Soft Travel Limit - Positive / Negative; default: Stop Planner).
    pub soft_overtravel_action: FaultAction,
    /// Servo, virtual or feedback-only (default: servo). See
    /// [`crate::servo`].
    pub axis_type: AxisType,
    /// Logix `InhibitAxis`: every instruction on the axis fails with ERR 53
    /// (default false).
    pub inhibited: bool,
    /// Whether a servo axis starts with its loop closed, as after an MSO
    /// (default true); off, the program enables it with MSO.
    pub start_servo_on: bool,
    /// Time an MSO waits for the drive (a holding brake's release delay),
    /// s (default 0: [`crate::servo::SERVO_ENABLE_UPDATES`] coarse updates).
    pub servo_enable_delay_s: f64,
    /// Logix `PositionErrorTolerance`, axis units (default: none, not
    /// checked): a larger |command − actual| on a servo-on axis is an
    /// Excessive Position Error.
    pub position_error_tolerance: Option<f64>,
    /// What the axis does on an Excessive Position Error (default: Stop
    /// Drive).
    pub position_error_action: FaultAction,
    /// How MAH homes the axis (default: active, immediate, home position
    /// 0). See [`crate::homing`].
    pub homing: Homing,
    /// Logix `ProgrammedStopMode`: how an MGS of Stop Mode *programmed*
    /// stops the axis (default: Fast Stop).
    pub programmed_stop_mode: ProgrammedStopMode,
    /// Logix `OutputCamExecutionTargets`: how many output cams (MAOC) the
    /// axis runs at once, each an Execution Target 0 … n − 1 (default 4,
    /// at most 8).
    pub output_cam_execution_targets: u32,
}

/// Logix `ProgrammedStopMode` (MOTION-RM003): how the group's programmed
/// stop (MGS *programmed*, a controller state change) stops an axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ProgrammedStopMode {
    /// Ramp to rest at the axis' maximum deceleration; the servo stays on.
    #[default]
    FastStop,
    /// Ramp to rest at the maximum deceleration, then disable the drive.
    FastDisable,
    /// Disable the drive at once (no ramp).
    HardDisable,
    /// Ramp to rest at the maximum deceleration, then shut the axis down.
    FastShutdown,
    /// Shut the axis down at once.
    HardShutdown,
}

impl ProgrammedStopMode {
    /// Every mode with its scene word, in the manual's order (its code).
    pub const ALL: [(&'static str, ProgrammedStopMode); 5] = [
        ("fast_stop", Self::FastStop),
        ("fast_disable", Self::FastDisable),
        ("hard_disable", Self::HardDisable),
        ("fast_shutdown", Self::FastShutdown),
        ("hard_shutdown", Self::HardShutdown),
    ];

    /// The mode of a scene word or an export's attribute value
    /// (`fast_stop`, `FastStop`, `Fast Stop`: case, spaces and
    /// underscores ignored).
    #[must_use]
    pub fn parse(text: &str) -> Option<Self> {
        let squash = |t: &str| {
            t.chars()
                .filter(|c| *c != '_' && *c != ' ')
                .collect::<String>()
                .to_ascii_lowercase()
        };
        let text = squash(text);
        Self::ALL.iter().find(|(w, _)| squash(w) == text).map(|(_, m)| *m)
    }
}

impl AxisConfig {
    /// A configuration with the documented defaults.
    pub fn new(name: impl Into<String>, kind: AxisKind) -> Self {
        Self {
            name: name.into(),
            kind,
            modulo_period: None,
            max_velocity: 1.0,
            max_acceleration: 10.0,
            max_deceleration: 10.0,
            max_jerk: 0.0,
            in_position_window: 0.01,
            target_position_monitoring: true,
            position_range_monitoring: false,
            position_range_window: 5.0,
            allow_motion_on_coupled_slave: false,
            modulo_tolerance_window: 0.0,
            soft_travel_limits: None,
            soft_overtravel_action: FaultAction::StopPlanner,
            axis_type: AxisType::Servo,
            inhibited: false,
            start_servo_on: true,
            servo_enable_delay_s: 0.0,
            position_error_tolerance: None,
            position_error_action: FaultAction::StopDrive,
            homing: Homing::default(),
            programmed_stop_mode: ProgrammedStopMode::FastStop,
            output_cam_execution_targets: 4,
        }
    }

    /// Checks every field.
    ///
    /// # Errors
    /// [`AxisConfigError`] naming the first field that is out of range.
    pub fn validate(&self) -> Result<(), AxisConfigError> {
        if let Some(p) = self.modulo_period {
            Modulo::new(p)?;
        }
        positive("max_velocity", self.max_velocity)?;
        positive("max_acceleration", self.max_acceleration)?;
        positive("max_deceleration", self.max_deceleration)?;
        non_negative("max_jerk", self.max_jerk)?;
        non_negative("in_position_window", self.in_position_window)?;
        non_negative("position_range_window", self.position_range_window)?;
        non_negative("modulo_tolerance_window", self.modulo_tolerance_window)?;
        non_negative("servo_enable_delay_s", self.servo_enable_delay_s)?;
        if let Some(t) = self.position_error_tolerance {
            positive("position_error_tolerance", t)?;
        }
        if let Some(p) = self.modulo_period
            && self.modulo_tolerance_window >= p / 2.0
        {
            return Err(AxisConfigError::ToleranceWindowTooWide {
                window: self.modulo_tolerance_window,
                period: p,
            });
        }
        finite("home_position", self.homing.position)?;
        finite("home_offset", self.homing.offset)?;
        non_negative("home_speed", self.homing.speed)?;
        non_negative("home_return_speed", self.homing.return_speed)?;
        if let Some((min, max)) = self.soft_travel_limits {
            if !(min.is_finite() && max.is_finite() && min < max) {
                return Err(AxisConfigError::SoftTravelLimits { min, max });
            }
            if let Some(period) = self.modulo_period {
                return Err(AxisConfigError::SoftTravelLimitsOnModulo { period });
            }
        }
        Ok(())
    }

    /// Checks that `position` (axis units) lies within the soft travel
    /// limits, bounds included (always true without limits).
    ///
    /// # Errors
    /// [`AxisConfigError::OutsideSoftTravelLimits`].
    pub fn check_soft_travel_limits(&self, position: f64) -> Result<(), AxisConfigError> {
        match self.soft_travel_limits {
            Some((min, max)) if !(min..=max).contains(&position) => {
                Err(AxisConfigError::OutsideSoftTravelLimits { position, min, max })
            }
            _ => Ok(()),
        }
    }

    /// The modulo period, if the axis is modulo.
    pub fn modulo(&self) -> Option<Modulo> {
        self.modulo_period.and_then(|p| Modulo::new(p).ok())
    }
}

/// An axis configuration field out of range.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum AxisConfigError {
    /// A field that must be finite and > 0 is not.
    #[error("axis field {field} must be finite and > 0, got {value}")]
    NotPositive {
        /// Field name.
        field: &'static str,
        /// Its value.
        value: f64,
    },
    /// A field that must be finite and ≥ 0 is not.
    #[error("axis field {field} must be finite and >= 0, got {value}")]
    Negative {
        /// Field name.
        field: &'static str,
        /// Its value.
        value: f64,
    },
    /// A field that must be finite is not.
    #[error("axis field {field} must be finite, got {value}")]
    NotFinite {
        /// Field name.
        field: &'static str,
        /// Its value.
        value: f64,
    },
    /// The modulo tolerance window must be under half the period.
    #[error("modulo_tolerance_window {window} must be less than half the modulo period {period}")]
    ToleranceWindowTooWide {
        /// The window.
        window: f64,
        /// The period.
        period: f64,
    },
    /// Soft travel limits that are not finite or not `min < max`.
    #[error("soft_travel_limits [{min}, {max}] must be finite with min < max")]
    SoftTravelLimits {
        /// Lower limit.
        min: f64,
        /// Upper limit.
        max: f64,
    },
    /// Soft travel limits on a modulo axis (its position wraps; Logix checks
    /// soft overtravel only on linear positioning).
    #[error("soft_travel_limits are not allowed on a modulo axis (period {period})")]
    SoftTravelLimitsOnModulo {
        /// The modulo period.
        period: f64,
    },
    /// A position (the initial position) outside the soft travel limits.
    #[error("position {position} is outside the soft travel limits [{min}, {max}]")]
    OutsideSoftTravelLimits {
        /// The position.
        position: f64,
        /// Lower limit.
        min: f64,
        /// Upper limit.
        max: f64,
    },
    /// A soft travel limit set on an axis configured without them.
    #[error("the axis has no soft travel limits to change (give soft_travel_limits in its configuration)")]
    NoSoftTravelLimits,
    /// The initial position is not finite or past [`MAX_POSITION`].
    #[error("axis initial position must be finite and at most 1e9 in magnitude, got {value}")]
    InitialPosition {
        /// Its value.
        value: f64,
    },
}

/// The largest magnitude an axis position may have, in axis units: an
/// initial or home position, a soft travel limit, an MAM, MRP or
/// MC_MoveModulo target. Past it a double resolves less than 10⁻⁷ of a
/// unit, and the increments of a move vanish below the float's resolution
/// (at 10³⁰⁸ a half turn moves nothing). Run-time targets past it are
/// refused with ERR 13 on their operand.
pub const MAX_POSITION: f64 = 1e9;

/// Whether `position` is finite and within [`MAX_POSITION`].
pub fn position_in_reach(position: f64) -> bool {
    position.is_finite() && position.abs() <= MAX_POSITION
}

fn positive(field: &'static str, value: f64) -> Result<f64, AxisConfigError> {
    dynamics::positive(value).ok_or(AxisConfigError::NotPositive { field, value })
}

fn finite(field: &'static str, value: f64) -> Result<f64, AxisConfigError> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(AxisConfigError::NotFinite { field, value })
    }
}

fn non_negative(field: &'static str, value: f64) -> Result<f64, AxisConfigError> {
    if value.is_finite() && value >= 0.0 {
        Ok(value)
    } else {
        Err(AxisConfigError::Negative { field, value })
    }
}

/// A configuration attribute of an axis a program may read and change at
/// run time (Logix SSV; [`crate::task::MotionTask::set_axis_limit`]), in
/// axis units.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AxisLimit {
    /// `max_velocity` (`MaximumSpeed`).
    Velocity,
    /// `max_acceleration` (`MaximumAcceleration`).
    Acceleration,
    /// `max_deceleration` (`MaximumDeceleration`).
    Deceleration,
    /// `max_jerk` (`MaximumAccelerationJerk` and `MaximumDecelerationJerk`:
    /// the planner has one jerk limit; 0 is none).
    Jerk,
    /// `position_error_tolerance` (`PositionErrorTolerance`; 0: not
    /// checked).
    PositionErrorTolerance,
    /// The upper soft travel limit (`SoftTravelLimitPositive`).
    SoftTravelLimitPositive,
    /// The lower soft travel limit (`SoftTravelLimitNegative`).
    SoftTravelLimitNegative,
    /// `homing.position` (`HomePosition`).
    HomePosition,
    /// `homing.offset` (`HomeOffset`).
    HomeOffset,
    /// `homing.speed` (`HomeSpeed`).
    HomeSpeed,
    /// `homing.return_speed` (`HomeReturnSpeed`).
    HomeReturnSpeed,
}

impl AxisConfig {
    /// The value of a settable attribute (a missing soft travel limit and
    /// an unchecked position error tolerance read 0).
    #[must_use]
    pub fn limit(&self, limit: AxisLimit) -> f64 {
        match limit {
            AxisLimit::Velocity => self.max_velocity,
            AxisLimit::Acceleration => self.max_acceleration,
            AxisLimit::Deceleration => self.max_deceleration,
            AxisLimit::Jerk => self.max_jerk,
            AxisLimit::PositionErrorTolerance => self.position_error_tolerance.unwrap_or(0.0),
            AxisLimit::SoftTravelLimitPositive => self.soft_travel_limits.map_or(0.0, |l| l.1),
            AxisLimit::SoftTravelLimitNegative => self.soft_travel_limits.map_or(0.0, |l| l.0),
            AxisLimit::HomePosition => self.homing.position,
            AxisLimit::HomeOffset => self.homing.offset,
            AxisLimit::HomeSpeed => self.homing.speed,
            AxisLimit::HomeReturnSpeed => self.homing.return_speed,
        }
    }

    /// This configuration with `limit` set to `value`, validated.
    ///
    /// # Errors
    /// The value breaks a rule of [`AxisConfig::validate`], or it sets a
    /// soft travel limit of an axis that has none.
    pub fn with_limit(&self, limit: AxisLimit, value: f64) -> Result<AxisConfig, AxisConfigError> {
        let mut c = self.clone();
        match limit {
            AxisLimit::Velocity => c.max_velocity = value,
            AxisLimit::Acceleration => c.max_acceleration = value,
            AxisLimit::Deceleration => c.max_deceleration = value,
            AxisLimit::Jerk => c.max_jerk = value,
            AxisLimit::PositionErrorTolerance => {
                c.position_error_tolerance = (value != 0.0).then_some(value);
            }
            AxisLimit::SoftTravelLimitPositive | AxisLimit::SoftTravelLimitNegative => {
                let Some((min, max)) = c.soft_travel_limits else {
                    return Err(AxisConfigError::NoSoftTravelLimits);
                };
                c.soft_travel_limits = Some(if limit == AxisLimit::SoftTravelLimitPositive {
                    (min, value)
                } else {
                    (value, max)
                });
            }
            AxisLimit::HomePosition => c.homing.position = value,
            AxisLimit::HomeOffset => c.homing.offset = value,
            AxisLimit::HomeSpeed => c.homing.speed = value,
            AxisLimit::HomeReturnSpeed => c.homing.return_speed = value,
        }
        c.validate()?;
        Ok(c)
    }
}

/// What an axis reports after a coarse update.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct AxisState {
    /// Command (set) position, unwrapped, axis units.
    pub command_position: f64,
    /// Command velocity, units/s.
    pub command_velocity: f64,
    /// Command acceleration, units/s².
    pub command_acceleration: f64,
    /// Command jerk, units/s³.
    pub command_jerk: f64,
    /// Actual position, unwrapped, axis units: fed back from outside, or the
    /// command position for an axis that is never fed (an ideal drive).
    pub actual_position: f64,
    /// Actual velocity, units/s: the change of the fed position over the
    /// last update (the command velocity for an axis never fed).
    pub actual_velocity: f64,
    /// Command position wrapped by the modulo period (modulo axes only).
    pub modulo_command_position: Option<f64>,
    /// Whether any motion command is generating setpoints on the axis.
    pub has_job: bool,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wrap_is_in_range_and_exact_at_multiples() {
        let m = Modulo::new(360.0).unwrap();
        assert_eq!(m.wrap(90.0), 90.0);
        assert_eq!(m.wrap(450.0), 90.0);
        assert_eq!(m.wrap(-90.0), 270.0);
        assert_eq!(m.wrap(720.0), 0.0);
        assert_eq!(m.wrap(-1e-17), 0.0);
        for k in -1000..1000 {
            let x = f64::from(k) * 7.3;
            let w = m.wrap(x);
            assert!((0.0..360.0).contains(&w));
        }
    }

    #[test]
    fn validation_names_the_field() {
        let mut c = AxisConfig::new("A", AxisKind::Rotary);
        assert_eq!(c.validate(), Ok(()));
        c.max_velocity = f64::NAN;
        assert!(matches!(
            c.validate(),
            Err(AxisConfigError::NotPositive {
                field: "max_velocity",
                ..
            })
        ));
        c.max_velocity = 1.0;
        c.max_jerk = -1.0;
        assert!(matches!(
            c.validate(),
            Err(AxisConfigError::Negative { field: "max_jerk", .. })
        ));
        c.max_jerk = 0.0;
        c.modulo_period = Some(0.0);
        assert!(matches!(
            c.validate(),
            Err(AxisConfigError::NotPositive {
                field: "modulo_period",
                ..
            })
        ));
        c.modulo_period = Some(360.0);
        c.modulo_tolerance_window = 180.0;
        assert!(matches!(
            c.validate(),
            Err(AxisConfigError::ToleranceWindowTooWide { .. })
        ));
    }

    #[test]
    fn soft_travel_limits_must_be_finite_ordered_and_not_modulo() {
        let mut c = AxisConfig::new("J1", AxisKind::Rotary);
        for bad in [(10.0, 10.0), (10.0, -10.0), (f64::NAN, 1.0), (-1.0, f64::INFINITY)] {
            c.soft_travel_limits = Some(bad);
            assert!(
                matches!(c.validate(), Err(AxisConfigError::SoftTravelLimits { .. })),
                "{bad:?}"
            );
        }
        c.soft_travel_limits = Some((-90.0, 90.0));
        assert_eq!(c.validate(), Ok(()));
        assert_eq!(c.check_soft_travel_limits(90.0), Ok(()));
        assert_eq!(c.check_soft_travel_limits(-90.0), Ok(()));
        assert_eq!(
            c.check_soft_travel_limits(90.5),
            Err(AxisConfigError::OutsideSoftTravelLimits {
                position: 90.5,
                min: -90.0,
                max: 90.0
            })
        );
        c.modulo_period = Some(360.0);
        assert_eq!(
            c.validate(),
            Err(AxisConfigError::SoftTravelLimitsOnModulo { period: 360.0 })
        );
        c.soft_travel_limits = None;
        assert_eq!(c.check_soft_travel_limits(1e9), Ok(()));
    }
}
