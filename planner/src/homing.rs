//! Homing: the homing attributes of an axis and what MAH (Motion Axis
//! Home, `task/instructions/mah.rs`) does with them; the homing process
//! runs in `task/homing.rs`.
//!
//! As in Logix, `MAH(Axis, MotionControl)` has no operands beyond the axis:
//! how it homes is the axis' configuration ([`Homing`], the scene's
//! `home_*` fields), under the `AXIS_CIP_DRIVE` attribute names
//! `HomeMode`, `HomeSequence`, `HomePosition`, `HomeOffset`,
//! `HomeDirection`, `HomeSpeed`, `HomeReturnSpeed`.
//!
//! # Modes and sequences
//! * **Active** ([`HomeMode::Active`], the default) needs the servo on: on a servo-off axis MAH fails with ERR 5, on
//!   a shut-down one with ERR 7, on a feedback-only one with ERR 8 (active
//!   homing needs a drive). All other motion in process on the axis is
//!   cancelled first, as the Logix manual says: single-axis motion (moves,
//!   jogs, cams, gearing, superimposed motion) ramps to rest with the
//!   axis' maximum deceleration, and the coordinated motion of the systems
//!   holding the axis comes to rest along its path at the system's maximum
//!   deceleration, as in a collision stop (transforms on the axis are
//!   cancelled). While the axis comes to
//!   rest the homing is in process (`.IP`, `HomingStatus`): motion
//!   instructions on the axis fail with ERR 16 (Homing In Process), and so
//!   does a second MAH. At rest, the **immediate** sequence redefines the
//!   axis position to `HomePosition` (command and actual together, the
//!   following error kept, as an MRP of the actual position); `.PC` and
//!   `AxisHomedStatus` are set. On an axis already at rest all of this
//!   happens in the MAH's own scan: `.DN`, `.PC` at once.
//! * **Passive** ([`HomeMode::Passive`]; the scene's default for a
//!   feedback-only axis) commands no motion and works in any servo state; the immediate
//!   sequence redefines the position at once (`.DN`, `.PC`,
//!   `AxisHomedStatus`), without cancelling motion in process.
//!
//! # Not simulated
//! The twin has no home limit switch, encoder marker or torque sensing, so
//! the sequences that wait for one (Switch, Marker, Switch-Marker, Torque
//! Level, …) are not offered: [`HomeSequence`] has the **immediate**
//! sequence only, and the scene refuses the others by name. `HomeOffset`,
//! `HomeDirection`, `HomeSpeed` and `HomeReturnSpeed` are kept and checked
//! but, as in Logix, the immediate sequence does not use them (they shape
//! the search and return moves of the switch and marker sequences).
//! `AxisHomedStatus` stays set until the end of the run (an MRP does not
//! set it, and does not clear it).

/// Logix `HomeMode`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum HomeMode {
    /// 0: the homing event comes from outside; no motion is commanded.
    Passive,
    /// 1: the controller moves the axis to home it (servo on).
    #[default]
    Active,
}

/// Logix `HomeSequence`: only the immediate sequence (module doc).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum HomeSequence {
    /// 0: home where the axis is, without a search move.
    #[default]
    Immediate,
}

/// Logix `HomeDirection` (used by the search sequences only).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum HomeDirection {
    /// Unidirectional forward.
    #[default]
    UnidirectionalForward,
    /// Bidirectional forward.
    BidirectionalForward,
    /// Unidirectional reverse.
    UnidirectionalReverse,
    /// Bidirectional reverse.
    BidirectionalReverse,
}

/// An axis' homing attributes (axis units).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Homing {
    /// `HomeMode`.
    pub mode: HomeMode,
    /// `HomeSequence`.
    pub sequence: HomeSequence,
    /// `HomePosition`: the axis position once homed.
    pub position: f64,
    /// `HomeOffset` (search sequences only).
    pub offset: f64,
    /// `HomeDirection` (search sequences only).
    pub direction: HomeDirection,
    /// `HomeSpeed`, units/s (search sequences only; 0: the axis' maximum
    /// speed / 10).
    pub speed: f64,
    /// `HomeReturnSpeed`, units/s (search sequences only; 0: as `speed`).
    pub return_speed: f64,
}
