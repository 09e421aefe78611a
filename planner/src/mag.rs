//! MAG (Motion Axis Gear): electronic gearing of a slave axis to a master
//! axis at a ratio. The executor side is `task/gear.rs`.
//!
//! `MAG(SlaveAxis, MasterAxis, MotionControl, Direction, Ratio, SlaveCounts,
//! MasterCounts, MasterReference, RatioFormat, Clutch, AccelRate,
//! AccelUnits)`, as in the Logix motion reference:
//!
//! * **Ratio**: with Ratio Format 0 (*Real*) the slave moves `Ratio` slave
//!   units per master unit; the value is sign sensitive and its magnitude
//!   must lie in 0.00001 ..= 9.99999 (the manual's range), else ERR 13 with
//!   EXERR = the Ratio operand. With Ratio Format 1 (*Fraction*) the ratio
//!   is `SlaveCounts / MasterCounts` (both non-zero integers, else ERR 13
//!   naming the operand). The twin has no encoders: a count is one position
//!   unit of its axis (Logix uses feedback counts, bypassing the conversion
//!   constant; a fraction still gives an exact rational ratio).
//! * **Direction**: 0 *Same* (the ratio as given), 1 *Opposite* (negated),
//!   2 *Reverse* (the opposite of the direction the slave is geared in now;
//!   *Opposite* when it is not geared), 3 *Unchanged* (the current
//!   direction with the new ratio; *Same* when not geared).
//! * **Master Reference**: 0 the master's actual position, 1 its command.
//! * **Clutch**: 0 *enabled*: the slave's gearing velocity ramps from the
//!   slave's current velocity to the geared velocity at `AccelRate`
//!   (trapezoidal), then locks (`GearingLockStatus`); the position offset
//!   built up while clutching is kept, as on a car's clutch. 1 *disabled*:
//!   locked at once (an abrupt start if the master moves, as the manual
//!   warns). `AccelRate` in units/s² (AccelUnits 0) or % of the slave's
//!   maximum acceleration (1); it must be > 0 with the clutch enabled.
//! * The configured velocity and acceleration limits do not apply to
//!   gearing (the manual says so).
//!
//! Bits: `.DN` when gearing is initiated, `.IP` until it is superseded by
//! another MAG on the slave, stopped (MAS *All* or *Gear*), ended by a MAM
//! that merges or a MAJ, by a move, coordinated motion or a position cam
//! taking the slave, or by a disable (MSF, shutdown, a fault). A MAM with
//! Merge Disabled runs superimposed on the gearing, as on a cam. The slave
//! needs the servo on (ERR 5/7/8/16/53 as every move); the master may be in
//! any state. A slave that is its own master is refused with ERR 13 naming
//! the Master Axis operand.

use crate::axis::AxisConfig;
use crate::catalogue::MAG;
use crate::mapc::MasterReference;

/// MAG's numeric operands (enumerations as their codes).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MagOperands {
    /// 0 Same, 1 Opposite, 2 Reverse, 3 Unchanged.
    pub direction: i32,
    /// Real ratio (Ratio Format 0).
    pub ratio: f64,
    /// Slave counts (Ratio Format 1).
    pub slave_counts: i32,
    /// Master counts (Ratio Format 1).
    pub master_counts: i32,
    /// 0 actual, 1 command.
    pub master_reference: i32,
    /// 0 real, 1 fraction.
    pub ratio_format: i32,
    /// 0 enabled, 1 disabled.
    pub clutch: i32,
    /// Clutch acceleration.
    pub accel_rate: f64,
    /// 0 units/s², 1 % of maximum.
    pub accel_units: i32,
}

impl Default for MagOperands {
    fn default() -> Self {
        Self {
            direction: 0,
            ratio: 1.0,
            slave_counts: 1,
            master_counts: 1,
            master_reference: 0,
            ratio_format: 0,
            clutch: 1,
            accel_rate: 100.0,
            accel_units: 1,
        }
    }
}

/// Why MAG fails (ERR 13 with the operand, or the slave's state).
pub type MagError = crate::instruction::OperandError;

/// MAG's Direction.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GearDirection {
    /// 0.
    Same,
    /// 1.
    Opposite,
    /// 2.
    Reverse,
    /// 3.
    Unchanged,
}

/// A validated MAG.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Mag {
    /// Direction.
    pub direction: GearDirection,
    /// Slave units per master unit, as given (sign included).
    pub ratio: f64,
    /// Which master position drives the slave.
    pub master_reference: MasterReference,
    /// Clutch acceleration, units/s² (`None`: clutch disabled).
    pub clutch_accel: Option<f64>,
}

/// The smallest and largest |Ratio| of the real format.
pub const RATIO_RANGE: (f64, f64) = (0.00001, 9.99999);

impl Mag {
    /// Validates the operands against the slave's configuration.
    ///
    /// # Errors
    /// [`MagError::ParameterOutOfRange`] naming the first operand at fault.
    pub fn new(o: &MagOperands, slave: &AxisConfig) -> Result<Self, MagError> {
        let bad = |name: &str, value: f64| MagError::ParameterOutOfRange {
            operand: MAG.exerr(name),
            value,
        };
        let direction = match o.direction {
            0 => GearDirection::Same,
            1 => GearDirection::Opposite,
            2 => GearDirection::Reverse,
            3 => GearDirection::Unchanged,
            d => return Err(bad("Direction", f64::from(d))),
        };
        let ratio = match o.ratio_format {
            0 => {
                let m = o.ratio.abs();
                if !(o.ratio.is_finite() && (RATIO_RANGE.0..=RATIO_RANGE.1).contains(&m)) {
                    return Err(bad("Ratio", o.ratio));
                }
                o.ratio
            }
            1 => {
                if o.slave_counts == 0 {
                    return Err(bad("Slave Counts", 0.0));
                }
                if o.master_counts == 0 {
                    return Err(bad("Master Counts", 0.0));
                }
                f64::from(o.slave_counts) / f64::from(o.master_counts)
            }
            f => return Err(bad("Ratio Format", f64::from(f))),
        };
        let master_reference = match o.master_reference {
            0 => MasterReference::Actual,
            1 => MasterReference::Command,
            r => return Err(bad("Master Reference", f64::from(r))),
        };
        let clutch_accel = match o.clutch {
            0 => {
                let a = match o.accel_units {
                    0 => o.accel_rate,
                    1 => o.accel_rate / 100.0 * slave.max_acceleration,
                    u => return Err(bad("Accel Units", f64::from(u))),
                };
                if !(a.is_finite() && a > 0.0) {
                    return Err(bad("Accel Rate", o.accel_rate));
                }
                Some(a)
            }
            1 => None,
            c => return Err(bad("Clutch", f64::from(c))),
        };
        Ok(Self {
            direction,
            ratio,
            master_reference,
            clutch_accel,
        })
    }

    /// The signed ratio the slave follows, given the sign of the gearing
    /// running now (`None`: not geared).
    pub fn effective_ratio(&self, current_sign: Option<f64>) -> f64 {
        let sign = match self.direction {
            GearDirection::Same => 1.0,
            GearDirection::Opposite => -1.0,
            GearDirection::Reverse => -current_sign.unwrap_or(1.0),
            GearDirection::Unchanged => current_sign.unwrap_or(1.0),
        };
        sign * self.ratio
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::axis::AxisKind;

    fn slave() -> AxisConfig {
        AxisConfig {
            max_acceleration: 400.0,
            ..AxisConfig::new("S", AxisKind::Rotary)
        }
    }

    #[test]
    fn each_operand_out_of_range_is_named_by_its_faceplate_number() {
        let ok = MagOperands::default();
        for (o, name) in [
            (MagOperands { direction: 4, ..ok }, "Direction"),
            (MagOperands { ratio: 10.0, ..ok }, "Ratio"),
            (MagOperands { ratio: 0.0, ..ok }, "Ratio"),
            (MagOperands { ratio: f64::NAN, ..ok }, "Ratio"),
            (
                MagOperands {
                    ratio_format: 1,
                    slave_counts: 0,
                    ..ok
                },
                "Slave Counts",
            ),
            (
                MagOperands {
                    ratio_format: 1,
                    master_counts: 0,
                    ..ok
                },
                "Master Counts",
            ),
            (MagOperands { ratio_format: 2, ..ok }, "Ratio Format"),
            (
                MagOperands {
                    master_reference: 2,
                    ..ok
                },
                "Master Reference",
            ),
            (MagOperands { clutch: 2, ..ok }, "Clutch"),
            (
                MagOperands {
                    clutch: 0,
                    accel_rate: 0.0,
                    ..ok
                },
                "Accel Rate",
            ),
            (
                MagOperands {
                    clutch: 0,
                    accel_units: 3,
                    ..ok
                },
                "Accel Units",
            ),
        ] {
            let e = Mag::new(&o, &slave()).unwrap_err();
            assert_eq!((e.err(), e.exerr()), (13, MAG.exerr(name)), "{name}");
        }
    }

    #[test]
    fn ratio_formats_directions_and_clutch_units() {
        let o = MagOperands {
            ratio: -2.5,
            ..MagOperands::default()
        };
        let m = Mag::new(&o, &slave()).unwrap();
        assert_eq!(m.effective_ratio(None), -2.5, "the ratio is sign sensitive");
        let fraction = MagOperands {
            ratio_format: 1,
            slave_counts: 1,
            master_counts: 3,
            direction: 1,
            clutch: 0,
            accel_rate: 50.0,
            accel_units: 1,
            ..MagOperands::default()
        };
        let m = Mag::new(&fraction, &slave()).unwrap();
        assert_eq!(m.effective_ratio(None), -1.0 / 3.0);
        assert_eq!(m.clutch_accel, Some(200.0));
        let reverse = Mag {
            direction: GearDirection::Reverse,
            ..m
        };
        assert_eq!(reverse.effective_ratio(Some(-1.0)), 1.0 / 3.0);
        assert_eq!(reverse.effective_ratio(None), -1.0 / 3.0);
        let unchanged = Mag {
            direction: GearDirection::Unchanged,
            ..m
        };
        assert_eq!(unchanged.effective_ratio(Some(-1.0)), -1.0 / 3.0);
    }
}
