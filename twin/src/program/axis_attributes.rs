//! The `AXIS` attributes a program reads with `GSV` and sets with `SSV`
//! (MOTION-RM003, *CIP Axis Attributes*): the axis members a routine also
//! reads by name (`Table.ActualPosition`, GSV only), and the configuration
//! the twin models, each with the access the attribute tables give it.
//! [`AXIS_ATTRIBUTES`] is the one catalogue: the compiler looks names up in
//! it and the scene README's table is written from it.
//!
//! Where a change takes effect, as on the controller:
//! * the planner's attributes (dynamics, position error tolerance, soft
//!   travel limits, homing) at once: instructions started afterwards plan
//!   with the new limits (motion already planned keeps its profile), the
//!   tolerance and limits are checked from the next coarse update, the
//!   homing attributes are read by the next MAH;
//! * the drive's attributes (loop gains, torque limits, inertia) are sent
//!   to the drive, which uses them from the coarse update after the scan
//!   that set them.
//!
//! A value the attribute does not take (a negative speed, a torque limit
//! of the wrong sign, a soft travel limit on an axis without them) is
//! refused when the SSV runs: the attribute keeps its value and the
//! summary lists the refusal under `tasks.refused`.

use super::types::DataType;
use crate::scene::ServoGains;
use planner::axis::AxisLimit;

/// A drive attribute (the plant's servo loops, `[[axes]] drive`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DriveAttr {
    /// `PositionLoopBandwidth`, Hz.
    PositionLoopBandwidth,
    /// `PositionIntegratorBandwidth`, Hz.
    PositionIntegratorBandwidth,
    /// `VelocityLoopBandwidth`, Hz.
    VelocityLoopBandwidth,
    /// `VelocityIntegratorBandwidth`, Hz.
    VelocityIntegratorBandwidth,
    /// `VelocityFeedforwardGain`, %.
    VelocityFeedforwardGain,
    /// `AccelerationFeedforwardGain`, %.
    AccelerationFeedforwardGain,
    /// `TorqueLimitPositive`, N·m or N.
    TorqueLimitPositive,
    /// `TorqueLimitNegative`, N·m or N.
    TorqueLimitNegative,
    /// `SystemInertia`, kg·m² or kg.
    SystemInertia,
}

impl DriveAttr {
    /// The attribute's value in `g` (an absent limit or inertia reads 0).
    #[must_use]
    pub fn get(self, g: &ServoGains) -> f64 {
        match self {
            DriveAttr::PositionLoopBandwidth => g.position_loop_bandwidth_hz,
            DriveAttr::PositionIntegratorBandwidth => g.position_integrator_bandwidth_hz,
            DriveAttr::VelocityLoopBandwidth => g.velocity_loop_bandwidth_hz,
            DriveAttr::VelocityIntegratorBandwidth => g.velocity_integrator_bandwidth_hz,
            DriveAttr::VelocityFeedforwardGain => g.velocity_feedforward_gain_pct,
            DriveAttr::AccelerationFeedforwardGain => g.acceleration_feedforward_gain_pct,
            DriveAttr::TorqueLimitPositive => g.torque_limit_positive.unwrap_or(0.0),
            DriveAttr::TorqueLimitNegative => g.torque_limit_negative.unwrap_or(0.0),
            DriveAttr::SystemInertia => g.system_inertia.unwrap_or(0.0),
        }
    }

    /// `g` with the attribute set to `v`, or why `v` is refused.
    ///
    /// # Errors
    /// A value outside the attribute's range, as a sentence.
    pub fn set(self, g: &ServoGains, v: f64) -> Result<ServoGains, String> {
        let mut out = *g;
        let need = |ok: bool, what: &str| {
            if ok && v.is_finite() {
                Ok(())
            } else {
                Err(format!("{v} is not {what}"))
            }
        };
        match self {
            DriveAttr::PositionLoopBandwidth => {
                need(v > 0.0, "a positive bandwidth")?;
                out.position_loop_bandwidth_hz = v;
            }
            DriveAttr::VelocityLoopBandwidth => {
                need(v > 0.0, "a positive bandwidth")?;
                out.velocity_loop_bandwidth_hz = v;
            }
            DriveAttr::PositionIntegratorBandwidth => {
                need(v >= 0.0, "a bandwidth of 0 or more")?;
                out.position_integrator_bandwidth_hz = v;
            }
            DriveAttr::VelocityIntegratorBandwidth => {
                need(v >= 0.0, "a bandwidth of 0 or more")?;
                out.velocity_integrator_bandwidth_hz = v;
            }
            DriveAttr::VelocityFeedforwardGain => {
                need(v >= 0.0, "a gain of 0 % or more")?;
                out.velocity_feedforward_gain_pct = v;
            }
            DriveAttr::AccelerationFeedforwardGain => {
                need(v >= 0.0, "a gain of 0 % or more")?;
                out.acceleration_feedforward_gain_pct = v;
            }
            DriveAttr::TorqueLimitPositive => {
                need(v >= 0.0, "a positive torque limit (0 or more)")?;
                out.torque_limit_positive = Some(v);
            }
            DriveAttr::TorqueLimitNegative => {
                need(v <= 0.0, "a negative torque limit (0 or less)")?;
                out.torque_limit_negative = Some(v);
            }
            DriveAttr::SystemInertia => {
                need(v > 0.0, "a positive inertia")?;
                out.system_inertia = Some(v);
            }
        }
        Ok(out)
    }
}

/// A fixed property of the axis' configuration (GSV only).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Fixed {
    /// `PositionScalingNumerator`: position units per motion unit.
    ScalingNumerator,
    /// `PositionScalingDenominator`: 1 motion unit.
    ScalingDenominator,
    /// `PositionUnwindNumerator`: a rotary modulo axis' period (0 without).
    UnwindNumerator,
    /// `PositionUnwindDenominator`: 1 cycle.
    UnwindDenominator,
    /// `HomeMode`: 0 passive, 1 active.
    HomeMode,
    /// `HomeDirection`: 0 to 3.
    HomeDirection,
    /// `HomeSequence`: 0 immediate.
    HomeSequence,
}

/// What an attribute is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AxisAttr {
    /// A planner configuration attribute.
    Config(AxisLimit),
    /// A fixed configuration property.
    Fixed(Fixed),
    /// A drive attribute.
    Drive(DriveAttr),
}

/// One row of the catalogue.
#[derive(Debug, Clone, Copy)]
pub struct AxisAttribute {
    /// The name as GSV and SSV write it.
    pub name: &'static str,
    /// What it is.
    pub attr: AxisAttr,
    /// Its type as RM003 gives it.
    pub ty: DataType,
    /// Its unit.
    pub unit: &'static str,
    /// Whether SSV sets it (RM003's access `Set/SSV`; GSV reads them all).
    pub settable: bool,
    /// What it holds, for the README.
    pub doc: &'static str,
}

const fn row(
    name: &'static str,
    attr: AxisAttr,
    ty: DataType,
    unit: &'static str,
    settable: bool,
    doc: &'static str,
) -> AxisAttribute {
    AxisAttribute {
        name,
        attr,
        ty,
        unit,
        settable,
        doc,
    }
}

use AxisAttr::{Config, Drive, Fixed as F};
use DataType::{Real, Usint};

/// Every `AXIS` configuration attribute the twin models (one row a line).
#[rustfmt::skip]
pub const AXIS_ATTRIBUTES: [AxisAttribute; 28] = [
    row("MaximumSpeed", Config(AxisLimit::Velocity), Real, "units/s", true, "`max_velocity`: the speed `% of maximum` refers to, and the limit of the moves and stops the planner makes itself; a speed an instruction asks for in units/s (MAJ, MAM, MCD) is run as asked, as on the controller"),
    row("MaximumAcceleration", Config(AxisLimit::Acceleration), Real, "units/s²", true, "`max_acceleration`"),
    row("MaximumDeceleration", Config(AxisLimit::Deceleration), Real, "units/s²", true, "`max_deceleration`"),
    row("MaximumAccelerationJerk", Config(AxisLimit::Jerk), Real, "units/s³", true, "`max_jerk` (0: none); the planner has one jerk limit, so this and MaximumDecelerationJerk read and set the same value"),
    row("MaximumDecelerationJerk", Config(AxisLimit::Jerk), Real, "units/s³", true, "`max_jerk`, as MaximumAccelerationJerk"),
    row("PositionErrorTolerance", Config(AxisLimit::PositionErrorTolerance), Real, "units", true, "`position_error_tolerance` (0: not checked)"),
    row("SoftTravelLimitPositive", Config(AxisLimit::SoftTravelLimitPositive), Real, "units", true, "the upper soft travel limit (0 without limits; SSV only on an axis that has them)"),
    row("SoftTravelLimitNegative", Config(AxisLimit::SoftTravelLimitNegative), Real, "units", true, "the lower soft travel limit, as above"),
    row("HomePosition", Config(AxisLimit::HomePosition), Real, "units", true, "`home_position`, read by the next MAH"),
    row("HomeOffset", Config(AxisLimit::HomeOffset), Real, "units", true, "`home_offset`"),
    row("HomeSpeed", Config(AxisLimit::HomeSpeed), Real, "units/s", true, "`home_speed`"),
    row("HomeReturnSpeed", Config(AxisLimit::HomeReturnSpeed), Real, "units/s", true, "`home_return_speed`"),
    row("HomeMode", F(Fixed::HomeMode), Usint, "", false, "0 passive, 1 active"),
    row("HomeDirection", F(Fixed::HomeDirection), Usint, "", false, "0 unidirectional forward, 1 bidirectional forward, 2 unidirectional reverse, 3 bidirectional reverse"),
    row("HomeSequence", F(Fixed::HomeSequence), Usint, "", false, "0 immediate (the sequence the twin models)"),
    row("PositionScalingNumerator", F(Fixed::ScalingNumerator), Real, "units", false, "position units per PositionScalingDenominator: 360 or 2π a revolution (`deg`, `rad`), 1000 or 1 a metre (`mm`, `m`)"),
    row("PositionScalingDenominator", F(Fixed::ScalingDenominator), Real, "rev or m", false, "1: one revolution of a rotary joint, one metre of a linear one"),
    row("PositionUnwindNumerator", F(Fixed::UnwindNumerator), Real, "units", false, "a modulo axis' `modulo_period` (0 for a linear axis)"),
    row("PositionUnwindDenominator", F(Fixed::UnwindDenominator), Real, "cycles", false, "1"),
    row("PositionLoopBandwidth", Drive(DriveAttr::PositionLoopBandwidth), Real, "Hz", true, "the servo drive's position loop (> 0)"),
    row("PositionIntegratorBandwidth", Drive(DriveAttr::PositionIntegratorBandwidth), Real, "Hz", true, "0: no position integrator"),
    row("VelocityLoopBandwidth", Drive(DriveAttr::VelocityLoopBandwidth), Real, "Hz", true, "the velocity loop (> 0)"),
    row("VelocityIntegratorBandwidth", Drive(DriveAttr::VelocityIntegratorBandwidth), Real, "Hz", true, "0: no velocity integrator"),
    row("VelocityFeedforwardGain", Drive(DriveAttr::VelocityFeedforwardGain), Real, "%", true, "velocity feedforward (≥ 0)"),
    row("AccelerationFeedforwardGain", Drive(DriveAttr::AccelerationFeedforwardGain), Real, "%", true, "acceleration feedforward (≥ 0)"),
    row("TorqueLimitPositive", Drive(DriveAttr::TorqueLimitPositive), Real, "N·m or N", true, "≥ 0 (0 read: no limit configured); the twin's drive limits in joint units, not % rated"),
    row("TorqueLimitNegative", Drive(DriveAttr::TorqueLimitNegative), Real, "N·m or N", true, "≤ 0, as above"),
    row("SystemInertia", Drive(DriveAttr::SystemInertia), Real, "kg·m² or kg", true, "> 0 (0 read: the joint's own inertia at the initial pose)"),
];

/// The attribute called `name` (case-insensitive).
#[must_use]
pub fn find(name: &str) -> Option<&'static AxisAttribute> {
    AXIS_ATTRIBUTES.iter().find(|a| a.name.eq_ignore_ascii_case(name))
}

/// The table of the catalogue as `scenes/README.md` writes it.
#[must_use]
pub fn markdown_table() -> String {
    let mut out =
        String::from("| attribute | type | unit | access | what it holds |\n| --- | --- | --- | --- | --- |\n");
    for a in &AXIS_ATTRIBUTES {
        out.push_str(&format!(
            "| `{}` | {} | {} | {} | {} |\n",
            a.name,
            a.ty.name(),
            a.unit,
            if a.settable { "GSV, SSV" } else { "GSV" },
            a.doc
        ));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_scene_readme_lists_every_axis_attribute_as_the_catalogue_has_it() {
        assert_eq!(
            crate::program::scene_readme_block("axis-attributes"),
            markdown_table(),
            "scenes/README.md's AXIS attribute table is out of date"
        );
    }

    #[test]
    fn names_are_unique_and_drive_values_round_trip() {
        let names: std::collections::HashSet<String> =
            AXIS_ATTRIBUTES.iter().map(|a| a.name.to_ascii_lowercase()).collect();
        assert_eq!(names.len(), AXIS_ATTRIBUTES.len());
        let g = ServoGains::default();
        for a in &AXIS_ATTRIBUTES {
            if let AxisAttr::Drive(d) = a.attr {
                let v = if d == DriveAttr::TorqueLimitNegative { -3.0 } else { 3.0 };
                let set = d.set(&g, v).expect("a valid value");
                assert_eq!(d.get(&set), v, "{}", a.name);
                assert!(d.set(&g, f64::NAN).is_err(), "{}", a.name);
            }
        }
        assert!(DriveAttr::TorqueLimitNegative.set(&g, 1.0).is_err());
        assert!(DriveAttr::PositionLoopBandwidth.set(&g, 0.0).is_err());
    }
}
