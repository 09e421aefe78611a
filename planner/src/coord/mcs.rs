//! MCS, Motion Coordinated Stop: its operands and their verification.

use super::operands::{CoordFault, CoordMoveError, out_of_range};
use super::system::CoordinateSystem;
use crate::instruction::Refusal;
use crate::profile::{JerkUnits, jerk_to_units_per_sec3};

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
                        Refusal::Instruction(CoordFault::MaxDecelZero { exerr: -1 })
                    } else {
                        out_of_range(4)
                    });
                }
                d
            }
            _ => return Err(out_of_range(3)),
        };
        if decel == 0.0 {
            return Err(Refusal::Instruction(CoordFault::MaxDecelZero { exerr: -1 }));
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
