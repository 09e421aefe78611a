//! Motion planner of the motion twin: pure motion math and PLC motion
//! instruction semantics. No physics, GPU, files, clocks or CLI: time is passed
//! in by the caller, one coarse update at a time.
//!
//! * [`profile`] — trapezoidal and S-curve profiles, jerk units.
//! * [`axis`] — axis configuration (linear, rotary, modulo) and axis state.
//! * [`instruction`] — status shared by all instructions: the Logix
//!   MOTION_INSTRUCTION bits and the PLCopen function-block outputs.
//! * [`modulo`] — MC_MoveModulo.
//! * [`mccp`] — Motion Calculate Cam Profile: CAM arrays → cam profiles.
//! * [`mapc`] — Motion Axis Position Cam: position camming of a slave axis.
//! * [`mrp`] — Motion Redefine Position.
//! * [`jog`] — Motion Axis Jog / Motion Axis Stop (drives cam masters).
//! * [`mam`] — Motion Axis Move: single-axis moves (absolute, incremental,
//!   rotary move types).
//! * [`coord`] — coordinate systems, coordinated-move operands and status;
//!   [`mclm`] linear and [`mccm`] circular coordinated moves; MCS in `coord`.
//! * [`mct`] — MCT coordinated transforms and robot geometries.
//! * [`mag`] — MAG electronic gearing.
//! * [`mah`] — homing attributes and MAH.
//! * [`servo`] — axis types and states (MSO, MSF, MASD, MASR, MAFR, MCSD,
//!   MCSR) and the state every motion instruction needs.
//! * [`task`] — the coarse-update executor that owns axes and commands.

pub mod axis;
pub mod catalogue;
pub mod coord;
pub mod dynamics;
pub mod instruction;
pub mod jog;
pub mod mag;
pub mod mah;
pub mod mam;
pub mod mapc;
pub mod mccm;
pub mod mccp;
pub mod mclm;
pub mod mct;
pub mod modulo;
pub mod mrp;
pub mod profile;
pub mod servo;
pub mod task;
mod vector;
