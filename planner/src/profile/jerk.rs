//! Jerk units of the Logix motion instructions (MCCM spec, "Jerk Units").
//!
//! A jerk operand is entered in one of these units:
//! * `0` units/s³ — taken as is;
//! * `1` % of Maximum — a percentage of the configured maximum accel or decel
//!   jerk;
//! * `2` % of Time — the share of the ramp time spent changing acceleration.
//!   The spec converts it with the instruction's speed `v` and accel (or decel)
//!   rate `a`:
//!
//!   `j [units/s³] = a² / v · (200 / j[% of time] − 1)` and back
//!   `j [% of time] = 200 / (1 + j[units/s³] · v / a²)`.
//!
//!   100 % of time gives a pure S (no constant-acceleration phase, `j = a²/v`);
//!   lower values give steeper jerk. The spec's formulas are only meaningful
//!   for 0 < % ≤ 100 (above 100 the ramp could not reach `a` at all), so those
//!   are the accepted values. 0 % of time would mean an infinite jerk: we
//!   reject it and let the caller choose a trapezoidal profile instead.
//!
//! The master-driven units (4 units per master unit³, 6 % of time master
//! driven) belong to master-driven coordinated motion and are not accepted by
//! these time-based conversions.

use crate::dynamics::positive;
use thiserror::Error;

/// The unit of a jerk operand.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum JerkUnits {
    /// `0` — position units per second³.
    UnitsPerSec3,
    /// `1` — percent of the configured maximum jerk.
    PercentOfMaximum,
    /// `2` — percent of the ramp time spent in jerk phases.
    PercentOfTime,
}

impl JerkUnits {
    /// The unit for a Logix operand value (0, 1, 2), or `None`.
    pub fn from_code(code: i64) -> Option<Self> {
        match code {
            0 => Some(Self::UnitsPerSec3),
            1 => Some(Self::PercentOfMaximum),
            2 => Some(Self::PercentOfTime),
            _ => None,
        }
    }
}

/// Why a jerk value cannot be converted.
#[derive(Debug, Clone, Copy, PartialEq, Error)]
#[non_exhaustive]
pub enum JerkUnitsError {
    /// The jerk value is out of range for its unit.
    #[error("jerk {value} is out of range for {units:?} (allowed: {allowed})")]
    OutOfRange {
        /// The unit the value was given in.
        units: JerkUnits,
        /// The value.
        value: f64,
        /// The accepted range, in words.
        allowed: &'static str,
    },
    /// A rate the conversion needs (speed, accel, maximum jerk) is not finite and > 0.
    #[error("{which} must be finite and > 0 to convert a jerk, got {value}")]
    BadReference {
        /// Which rate.
        which: &'static str,
        /// Its value.
        value: f64,
    },
}

fn reference(which: &'static str, value: f64) -> Result<f64, JerkUnitsError> {
    positive(value).ok_or(JerkUnitsError::BadReference { which, value })
}

/// The accel rate and speed a % of Time jerk is relative to.
fn rates(accel: f64, speed: f64) -> Result<(f64, f64), JerkUnitsError> {
    Ok((reference("accel", accel)?, reference("speed", speed)?))
}

/// A jerk in units/s³: finite and > 0.
fn in_units_per_sec3(value: f64) -> Result<f64, JerkUnitsError> {
    positive(value).ok_or(JerkUnitsError::OutOfRange {
        units: JerkUnits::UnitsPerSec3,
        value,
        allowed: "finite and > 0",
    })
}

/// A jerk in percent (`units`: of Maximum or of Time): 0 < % ≤ 100.
fn in_percent(units: JerkUnits, value: f64) -> Result<f64, JerkUnitsError> {
    if value > 0.0 && value <= 100.0 {
        Ok(value)
    } else {
        Err(JerkUnitsError::OutOfRange {
            units,
            value,
            allowed: "0 < % ≤ 100",
        })
    }
}

/// `j [units/s³] = a² / v · (200 / percent − 1)` for `0 < percent ≤ 100`.
///
/// # Errors
/// [`JerkUnitsError::OutOfRange`] for a percentage outside (0, 100],
/// [`JerkUnitsError::BadReference`] for a non-positive rate.
pub fn jerk_from_percent_of_time(percent: f64, accel: f64, speed: f64) -> Result<f64, JerkUnitsError> {
    let percent = in_percent(JerkUnits::PercentOfTime, percent)?;
    let (a, v) = rates(accel, speed)?;
    Ok(a * a / v * (200.0 / percent - 1.0))
}

/// `j [% of time] = 200 / (1 + j · v / a²)` for a jerk `j > 0` in units/s³.
///
/// # Errors
/// [`JerkUnitsError::OutOfRange`] for a jerk that is not finite and > 0,
/// [`JerkUnitsError::BadReference`] for a non-positive rate.
pub fn jerk_to_percent_of_time(jerk: f64, accel: f64, speed: f64) -> Result<f64, JerkUnitsError> {
    let jerk = in_units_per_sec3(jerk)?;
    let (a, v) = rates(accel, speed)?;
    Ok(200.0 / (1.0 + jerk * v / (a * a)))
}

/// Converts a jerk operand to units/s³.
///
/// `max_jerk` is the configured maximum (for % of Maximum); `accel` and
/// `speed` are the instruction's rate and speed (for % of Time; pass the decel
/// rate for a decel jerk).
///
/// # Errors
/// [`JerkUnitsError`] when the value is out of range for its unit
/// (units/s³: finite and > 0; % of Maximum: 0 < % ≤ 100; % of Time: 0 < % ≤ 100)
/// or a needed reference rate is not finite and > 0.
pub fn jerk_to_units_per_sec3(
    value: f64,
    units: JerkUnits,
    max_jerk: f64,
    accel: f64,
    speed: f64,
) -> Result<f64, JerkUnitsError> {
    match units {
        JerkUnits::UnitsPerSec3 => in_units_per_sec3(value),
        JerkUnits::PercentOfMaximum => Ok(reference("maximum jerk", max_jerk)? * in_percent(units, value)? / 100.0),
        JerkUnits::PercentOfTime => jerk_from_percent_of_time(value, accel, speed),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The spec's forward formula, value for value.
    #[test]
    fn percent_of_time_to_units_matches_spec_formula() {
        // a = 100, v = 50: a²/v = 200.
        assert_eq!(jerk_from_percent_of_time(100.0, 100.0, 50.0), Ok(200.0));
        assert_eq!(jerk_from_percent_of_time(50.0, 100.0, 50.0), Ok(600.0));
        assert_eq!(jerk_from_percent_of_time(20.0, 100.0, 50.0), Ok(1800.0));
    }

    #[test]
    fn units_to_percent_of_time_matches_spec_formula() {
        assert_eq!(jerk_to_percent_of_time(200.0, 100.0, 50.0), Ok(100.0));
        assert_eq!(jerk_to_percent_of_time(600.0, 100.0, 50.0), Ok(50.0));
        assert_eq!(jerk_to_percent_of_time(1800.0, 100.0, 50.0), Ok(20.0));
    }

    /// A ramp with the converted jerk really spends `percent` of its time in
    /// jerk phases: 2·(a/j) / (v/a + a/j).
    #[test]
    fn percent_of_time_is_the_jerk_share_of_the_ramp() {
        for &(p, a, v) in &[
            (100.0, 10.0, 5.0),
            (40.0, 3.0, 7.0),
            (1.0, 1000.0, 0.1),
            (73.5, 0.2, 0.01),
        ] {
            let j = jerk_from_percent_of_time(p, a, v).unwrap();
            let jerk_time = 2.0 * a / j;
            let ramp_time = v / a + a / j;
            assert!((jerk_time / ramp_time * 100.0 - p).abs() < 1e-9 * p, "{p} {a} {v}");
        }
    }

    #[test]
    fn conversions_round_trip_both_ways() {
        let mut x = 0.123_f64;
        for _ in 0..1000 {
            x = (x * 9301.0 + 49297.0) % 233280.0 / 233280.0; // tiny LCG, deterministic
            let p = 0.5 + 99.5 * x;
            let (a, v) = (0.1 + 50.0 * x, 0.05 + 20.0 * (1.0 - x));
            let j = jerk_from_percent_of_time(p, a, v).unwrap();
            let back = jerk_to_percent_of_time(j, a, v).unwrap();
            assert!((back - p).abs() <= 1e-12 * p);
            let j2 = jerk_from_percent_of_time(back, a, v).unwrap();
            assert!((j2 - j).abs() <= 1e-12 * j);
        }
    }

    #[test]
    fn percent_of_maximum_scales_the_configured_jerk() {
        assert_eq!(
            jerk_to_units_per_sec3(25.0, JerkUnits::PercentOfMaximum, 400.0, 1.0, 1.0),
            Ok(100.0)
        );
        assert_eq!(
            jerk_to_units_per_sec3(7.5, JerkUnits::UnitsPerSec3, 400.0, 1.0, 1.0),
            Ok(7.5)
        );
        assert_eq!(
            jerk_to_units_per_sec3(100.0, JerkUnits::PercentOfTime, 0.0, 100.0, 50.0),
            Ok(200.0)
        );
    }

    #[test]
    fn bad_values_are_errors_never_nan() {
        for bad in [0.0, -1.0, 100.5, f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            assert!(jerk_from_percent_of_time(bad, 1.0, 1.0).is_err(), "{bad}");
            assert!(
                jerk_to_units_per_sec3(bad, JerkUnits::PercentOfMaximum, 1.0, 1.0, 1.0).is_err(),
                "{bad}"
            );
        }
        for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            assert!(jerk_to_percent_of_time(bad, 1.0, 1.0).is_err());
            assert!(jerk_from_percent_of_time(50.0, bad, 1.0).is_err());
            assert!(jerk_from_percent_of_time(50.0, 1.0, bad).is_err());
            assert!(jerk_to_units_per_sec3(bad, JerkUnits::UnitsPerSec3, 1.0, 1.0, 1.0).is_err());
            assert!(jerk_to_units_per_sec3(50.0, JerkUnits::PercentOfMaximum, bad, 1.0, 1.0).is_err());
        }
        assert_eq!(JerkUnits::from_code(2), Some(JerkUnits::PercentOfTime));
        assert_eq!(JerkUnits::from_code(4), None);
    }
}
