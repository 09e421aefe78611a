//! The outputs of a run, read from the [`crate::run::Twin`] after each
//! coarse update.
//!
//! **In:** the twin's state (planner, program, plant). **Out:** the CSV
//! trace ([`trace`]), the JSON summary, PNG frames and the Rerun
//! recording ([`session`]: one type per output, written as the run goes),
//! with the renderer ([`render`], cargo feature `render`), the Rerun
//! logging layer and what a run logs there (`recording`, cargo feature
//! `rerun`) and the golden-image comparison of the snapshot tests
//! ([`snapshot`]).

#[cfg(feature = "rerun")]
pub mod recording;
#[cfg(feature = "render")]
pub mod render;
pub mod session;
#[cfg(feature = "render")]
pub mod snapshot;
pub(crate) mod status;
pub mod trace;

/// Tint of a link in collision, in frames and the Rerun highlight (red).
pub const COLLISION_TINT_RGBA: [f32; 4] = [1.0, 0.05, 0.05, 0.8];
