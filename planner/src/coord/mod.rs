//! Coordinate systems (Logix `COORDINATE_SYSTEM`) and what every coordinated
//! move shares: the operands of MCLM and MCCM, their validation into a
//! [`CoordMove`], the path geometry (line or arc), and the status bits.
//!
//! # Coordinate system
//! [`CoordinateSystemConfig`] holds 1 to 3 *primary* Cartesian axes (the
//! first `primary_axes` of the system's axes; only they take part in the
//! vector speed and in arcs) and any number of further non-primary axes, the
//! vector's maximum speed, acceleration, deceleration, accel jerk and decel
//! jerk, and the command and actual tolerances. [`CoordinateSystem::new`]
//! validates it. A maximum deceleration of 0 is accepted, as Logix accepts it
//! in the properties dialog: a move on such a system fails with error 54,
//! EXERR −1 (the spec's rule).
//!
//! # Operands shared by MCLM and MCCM
//! Speed, accel and decel in units per second (0), % of maximum (1) or units
//! per master unit (4); profile trapezoidal (0) or S-curve (1); jerk in
//! units/s³ (0), % of maximum (1), % of time (2), units per master unit³ (4)
//! or % of time master driven (6), converted with the spec's formulas
//! ([`crate::profile::jerk_from_percent_of_time`]); termination types 0–6;
//! merge disabled / coordinated motion / all motion; merge speed programmed /
//! current; command tolerance (termination 6); lock position and direction
//! (master-driven moves); event distances (their calculated data is filled in
//! when the move is verified).
//!
//! # Choices where the spec is silent or contradicts itself
//! * **Operand indices** for ERR 13's EXERR are the faceplate order counted
//!   from 0, read from [`crate::catalogue`] ([`OperandIndex`]): the MCCM
//!   table's 0 coordinate system … 14 termination type, and the operands
//!   the table does not list continuing that order; MCLM's are the same
//!   list without the three circle operands.
//! * **Termination type** range: the spec's table says "greater than 3" is an
//!   error, but its own enumeration lists 0–6; 0–6 are accepted. Types 4 and
//!   5 (follow contour) pass through the end point into a pending move
//!   without stopping (see `task/coord.rs`); without one they end like
//!   type 1.
//! * **Circle type** range: the table says "greater than 4"; the enumeration
//!   has 0–3, so 4 is an error too.
//! * **Speed 0** is legal (only < 0 is an error): the move is verified and
//!   stays in process at its start point until it is stopped or merged.
//! * **Accel or decel in % of maximum** of a system maximum of 0 gives a rate
//!   of 0, which is ERR 13 with the rate's index (a rate must be > 0).
//! * **Jerk** is checked only for S-curve moves (the spec: the values are used
//!   only then); a jerk ≤ 0, a % > 100 or a mode that does not match the
//!   speed units (time vs master) is ERR 13 with the jerk operand's index.
//! * **Master-driven**: speed, accel and decel units must all be per master
//!   unit (4) or all per second; a mix is ERR 13 with the index of the first
//!   operand that differs from the speed units. A master-driven move on a
//!   system without a master axis is ERR 13 with EXERR 8 (speed units).
//! * **Non-primary axes** move linearly with the path fraction (s / L), so they
//!   arrive with the primary axes; they do not count in the vector speed. A
//!   line that moves only non-primary axes uses their Euclidean distance as
//!   its path length.
//! * **Point tolerance**: two points are the same when they are closer than
//!   1e-9 · (1 + |start| + |end|) coordinate units; three points are collinear
//!   when the sine of their angle is below 1e-9.
//! * **Event distance** < 0 or not finite is ERR 13, EXERR 23 (MCCM) / 20
//!   (MCLM); a distance longer than the move gives 0 (the start).

mod mcs;
mod motion;
mod operands;
mod path;
mod system;

pub use mcs::{Mcs, McsInputs};
pub use motion::CoordMove;
pub(crate) use motion::{finish_move, progress_at_length, resolve_move_type_and_position, with_velocity};
pub(crate) use operands::out_of_range;
pub use operands::{
    CoordFault, CoordMoveError, CoordMoveInputs, Driver, LockDirection, MCCM_OPERANDS, MCLM_OPERANDS, Merge,
    MergeSpeed, MoveContext, MoveType, OperandIndex, TerminationType,
};
pub(crate) use path::primary_of;
pub use path::{Arc, PathGeometry};
pub(crate) use system::same_point;
pub use system::{CoordConfigError, CoordStatus, CoordinateSystem, CoordinateSystemConfig};

#[cfg(test)]
mod tests;
