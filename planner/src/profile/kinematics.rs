//! The kinematic vocabulary of a profile: the state of one dimension, a
//! sample of a profile, and the validated limits with their shape.

use crate::dynamics;
use thiserror::Error;

/// Kinematic state of one dimension at an instant (units, units/s, units/s²).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct State {
    /// Position in the dimension's units.
    pub position: f64,
    /// Velocity in units/s.
    pub velocity: f64,
    /// Acceleration in units/s².
    pub acceleration: f64,
}

impl State {
    /// A state at rest at `position`.
    pub fn at_rest(position: f64) -> Self {
        Self {
            position,
            velocity: 0.0,
            acceleration: 0.0,
        }
    }
}

/// A profile sampled at one instant: [`State`] plus the jerk (units/s³).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Sample {
    /// Position in units.
    pub position: f64,
    /// Velocity in units/s.
    pub velocity: f64,
    /// Acceleration in units/s².
    pub acceleration: f64,
    /// Jerk in units/s³ (0 for trapezoidal profiles).
    pub jerk: f64,
}

impl Sample {
    /// The kinematic state (drops the jerk).
    pub fn state(&self) -> State {
        State {
            position: self.position,
            velocity: self.velocity,
            acceleration: self.acceleration,
        }
    }
}

/// Velocity-profile shape.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Shape {
    /// Constant-acceleration ramps; acceleration changes in steps.
    Trapezoidal,
    /// Jerk-limited ramps (units/s³, both > 0 and finite).
    SCurve {
        /// Jerk while the speed rises.
        accel_jerk: f64,
        /// Jerk while the speed falls.
        decel_jerk: f64,
    },
}

/// Validated dynamic limits of one profile. All values are magnitudes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Limits {
    pub(super) velocity: f64,
    pub(super) acceleration: f64,
    pub(super) deceleration: f64,
    pub(super) shape: Shape,
}

/// Why a set of [`Limits`] cannot be built.
#[derive(Debug, Clone, Copy, PartialEq, Error)]
#[non_exhaustive]
pub enum LimitsError {
    /// A limit is zero, negative, NaN or infinite.
    #[error("{which} must be finite and > 0, got {value}")]
    NotPositive {
        /// Which limit (`"velocity"`, `"acceleration"`, …).
        which: &'static str,
        /// The offending value.
        value: f64,
    },
}

fn positive(which: &'static str, value: f64) -> Result<f64, LimitsError> {
    dynamics::positive(value).ok_or(LimitsError::NotPositive { which, value })
}

impl Limits {
    /// Limits for a trapezoidal profile.
    ///
    /// # Errors
    /// [`LimitsError::NotPositive`] when a value is not finite and > 0.
    pub fn trapezoidal(velocity: f64, acceleration: f64, deceleration: f64) -> Result<Self, LimitsError> {
        Ok(Self {
            velocity: positive("velocity", velocity)?,
            acceleration: positive("acceleration", acceleration)?,
            deceleration: positive("deceleration", deceleration)?,
            shape: Shape::Trapezoidal,
        })
    }

    /// Limits for an S-curve profile.
    ///
    /// # Errors
    /// [`LimitsError::NotPositive`] when a value is not finite and > 0.
    pub fn s_curve(
        velocity: f64,
        acceleration: f64,
        deceleration: f64,
        accel_jerk: f64,
        decel_jerk: f64,
    ) -> Result<Self, LimitsError> {
        let mut limits = Self::trapezoidal(velocity, acceleration, deceleration)?;
        limits.shape = Shape::SCurve {
            accel_jerk: positive("accel jerk", accel_jerk)?,
            decel_jerk: positive("decel jerk", decel_jerk)?,
        };
        Ok(limits)
    }

    /// Maximum speed (units/s).
    pub fn velocity(&self) -> f64 {
        self.velocity
    }
    /// Maximum acceleration (units/s²), used while the speed rises.
    pub fn acceleration(&self) -> f64 {
        self.acceleration
    }
    /// Maximum deceleration (units/s²), used while the speed falls.
    pub fn deceleration(&self) -> f64 {
        self.deceleration
    }
    /// The profile shape with its jerks.
    pub fn shape(&self) -> Shape {
        self.shape
    }
}
