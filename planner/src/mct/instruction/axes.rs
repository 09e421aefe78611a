//! The coordinate systems and axes a transform works on, as the executor
//! knows them, and the limits of a target axis.

/// A coordinate system, as known to the executor.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct SystemId(pub u32);

/// An axis, as known to the executor.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct AxisId(pub u32);

/// Limits of a target (joint) axis, in axis units (degrees for a revolute
/// joint, coordinate units for a prismatic one).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointAxis {
    /// Maximum speed, units/s: no joint command is faster.
    pub max_speed: f64,
    /// Deceleration of the controlled stop after a fault, units/s².
    pub max_deceleration: f64,
    /// Soft travel limits `(min, max)` (default: none).
    pub limits: Option<(f64, f64)>,
}
