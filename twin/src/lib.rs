//! The motion twin: scene files, URDF robots simulated in rapier, headless
//! rendering, Rerun recordings and traces, driven by the `planner` crate.

pub mod convert;
pub mod mesh;
pub mod physics;
#[cfg(feature = "render")]
pub mod render;
pub mod scene;
#[cfg(feature = "render")]
pub mod snapshot;
pub mod st;
pub mod stl;
pub mod urdf;
