//! The outputs of a run, read from the [`crate::run::Twin`] after each
//! coarse update.
//!
//! **In:** the twin's state (planner, program, plant). **Out:** the CSV
//! trace ([`trace`]), the JSON summary, PNG frames and the Rerun
//! recording ([`session`]: one type per output, written as the run goes),
//! with the renderer ([`render`]), the Rerun logging layer ([`recording`])
//! and the golden-image comparison of the snapshot tests ([`snapshot`]).

pub mod recording;
#[cfg(feature = "render")]
pub mod render;
pub mod session;
#[cfg(feature = "render")]
pub mod snapshot;
pub mod trace;
