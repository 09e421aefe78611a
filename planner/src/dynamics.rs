//! The operands that set how a move runs — speed, acceleration and
//! deceleration rates, profile and jerks, each with its units — as the
//! program passes them. MAM and MCLM/MCCM share them (their faceplates
//! list them in the same order, Speed to Jerk Units); what a code means
//! and which codes an instruction accepts is the instruction's
//! (`task/instructions/mam.rs`, [`crate::coord`]). The conversion of a
//! time-driven rate and the positive-and-finite test are here, once.

/// Speed, rates, profile and jerks of a move, enumerations as their
/// numeric codes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MoveDynamics {
    /// Speed (≥ 0).
    pub speed: f64,
    /// Speed Units (0 units/s, 1 % of maximum, 4 units per master unit).
    pub speed_units: i64,
    /// Accel Rate (> 0).
    pub accel_rate: f64,
    /// Accel Units (0 units/s², 1 % of maximum, 4 per master unit²).
    pub accel_units: i64,
    /// Decel Rate (> 0).
    pub decel_rate: f64,
    /// Decel Units (as Accel Units).
    pub decel_units: i64,
    /// Profile (0 trapezoidal, 1 S-curve).
    pub profile: i64,
    /// Accel Jerk (S-curve).
    pub accel_jerk: f64,
    /// Decel Jerk (S-curve).
    pub decel_jerk: f64,
    /// Jerk Units (0 units/s³, 1 % of maximum, 2 % of time, 4 per master
    /// unit³, 6 % of time master driven).
    pub jerk_units: i64,
}

/// A time-driven rate as units per second (per second², …): given in
/// those units (code 0), or in percent of the axis' maximum `max` (code
/// 1); `None` for any other units code.
#[must_use]
pub fn time_rate(value: f64, units: i64, max: f64) -> Option<f64> {
    match units {
        0 => Some(value),
        1 => Some(value / 100.0 * max),
        _ => None,
    }
}

/// `value` when it is finite and greater than zero.
#[must_use]
pub fn positive(value: f64) -> Option<f64> {
    (value.is_finite() && value > 0.0).then_some(value)
}
