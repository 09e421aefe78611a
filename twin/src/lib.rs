//! The motion twin: scene files, URDF robots simulated in rapier, headless
//! rendering, Rerun recordings and traces, driven by the `planner` crate.

pub mod collision;
pub mod convert;
pub mod dae;
pub mod frames;
pub mod kinematics_check;
pub mod mesh;
pub mod physics;
pub mod recording;
#[cfg(feature = "render")]
pub mod render;
pub mod run;
pub mod scene;
pub mod session;
#[cfg(feature = "render")]
pub mod snapshot;
pub mod st;
pub mod stl;
pub mod urdf;
