//! The motion twin: scene files, URDF robots simulated in rapier, headless
//! rendering, Rerun recordings and traces, driven by the `planner` crate.
//!
//! The stages follow the data, and each imports only the ones before it:
//!
//! * [`source`] — the files a user wrote, spans into them, and the one
//!   diagnostic type every stage reports a user's input with;
//! * [`st`] — the Structured Text front-end (routines, step calls, scene
//!   expressions);
//! * [`scene`] — a scene file loaded and validated into a [`scene::Scene`];
//! * [`program`] — the scene's program bound to the planner, scanned each
//!   coarse update;
//! * [`plant`] — the robot (URDF → rapier), the axes bound to its joints,
//!   collision checks;
//! * [`run`] — [`run::Twin`], which puts program, planner and plant in order;
//! * [`output`] — trace, summary, frames and recording, read from the twin.
//!
//! `ARCHITECTURE.md` at the repository root draws the whole picture.

pub mod l5x;
pub mod output;
pub mod plant;
pub mod program;
pub mod run;
pub mod scene;
pub mod source;
pub mod st;
