//! The motion twin: scene files, URDF robots simulated in rapier, headless
//! rendering, Rerun recordings and traces, driven by the `planner` crate.

pub mod mesh;
pub mod recording;
