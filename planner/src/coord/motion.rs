//! A verified coordinated move ([`CoordMove`]): the profile along its path,
//! and the verification steps MCLM and MCCM share.

use super::operands::{
    CoordFault, CoordMoveError, CoordMoveInputs, Driver, LockDirection, Merge, MergeSpeed, MoveContext, MoveType,
    OperandIndex, TerminationType, out_of_range,
};
use super::path::PathGeometry;
use crate::instruction::Refusal;
use crate::profile::{
    JerkUnits, Limits, LimitsError, Profile, State, jerk_from_percent_of_time, jerk_to_units_per_sec3,
};

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
            Some(l) => Profile::to_position(State::at_rest(0.0), self.path.length(), 0.0, l),
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
        let length = self.path.length();
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
    let d = &inputs.dynamics;
    let driver = match d.speed_units {
        0 | 1 => Driver::Time,
        4 => Driver::Master,
        _ => return Err(out_of_range(idx.speed_units)),
    };
    if !(d.speed.is_finite() && d.speed >= 0.0) {
        return Err(out_of_range(idx.speed));
    }
    let speed = if d.speed_units == 1 {
        d.speed / 100.0 * sys.max_speed
    } else {
        d.speed
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
        d.accel_rate,
        d.accel_units,
        sys.max_accel,
        idx.accel_rate,
        idx.accel_units,
    )?;
    let decel = rate(
        d.decel_rate,
        d.decel_units,
        sys.max_decel,
        idx.decel_rate,
        idx.decel_units,
    )?;
    let s_curve = match d.profile {
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
            let units = match (d.jerk_units, driver) {
                (0, Driver::Time) | (4, Driver::Master) => JerkUnits::UnitsPerSec3,
                (1, _) => JerkUnits::PercentOfMaximum,
                (2, Driver::Time) | (6, Driver::Master) => JerkUnits::PercentOfTime,
                _ => return Err(out_of_range(idx.jerk_units)),
            };
            // % of time refers to the move's speed and its accel (decel) rate.
            let jerk = |value: f64, max: f64, rate: f64, exerr: i32| {
                jerk_to_units_per_sec3(value, units, max, rate, speed).map_err(|_| out_of_range(exerr))
            };
            let aj = jerk(d.accel_jerk, sys.max_accel_jerk, accel, idx.accel_jerk)?;
            let dj = jerk(d.decel_jerk, sys.max_decel_jerk, decel, idx.decel_jerk)?;
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
        return Err(Refusal::Instruction(CoordFault::MaxDecelZero { exerr: -1 }));
    }
    if let Some(i) = ctx.axis_max_decel.iter().position(|d| *d == 0.0) {
        return Err(Refusal::Instruction(CoordFault::MaxDecelZero { exerr: i as i32 }));
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
            && matches!((d.jerk_units, driver), (2, Driver::Time) | (6, Driver::Master)))
        .then_some((d.accel_jerk, d.decel_jerk)),
        calculated_data: Vec::new(),
    };
    m.fill_calculated_data();
    Ok(m)
}
