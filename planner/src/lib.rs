//! Motion planner of the motion twin: pure motion math and PLC motion
//! instruction semantics. No physics, GPU, files, clocks or CLI: time is passed
//! in by the caller, one coarse update at a time.
//!
//! * [`task::instructions`] — every instruction the product accepts, one
//!   module each: its catalogue entry, typed operands bound by catalogue
//!   position, validation, refusals and executor; the registry lists them.
//! * [`catalogue`] — how an instruction is described (operands, formats,
//!   enumeration words, faceplate indices) and what each ERR code means.
//! * [`instruction`] — the status every instruction writes: the Logix
//!   MOTION_INSTRUCTION bits and the PLCopen function-block outputs; the
//!   refusals ([`instruction::LogixFault`], [`instruction::Refusal`]).
//! * [`task`] — the coarse-update executor (the motion engine) that owns
//!   axes and commands; a call runs through its instruction's entry,
//!   [`task::instructions::Instruction::execute`].
//! * [`profile`] — trapezoidal and S-curve profiles, jerk units;
//!   [`dynamics`] — the rates and units moves share.
//! * [`axis`] — axis configuration (linear, rotary, modulo) and axis state.
//! * [`servo`] — axis types and states and the state every motion
//!   instruction needs; [`homing`] — the homing attributes MAH uses.
//! * [`modulo`] — MC_MoveModulo's commands.
//! * [`mccp`] — cam profiles from CAM arrays; [`mapc`] — position camming
//!   of a slave axis.
//! * [`coord`] — coordinate systems, coordinated-move operands and status;
//!   [`mclm`] lines and [`mccm`] circles.
//! * [`mct`] — coordinated transforms and robot geometries.
//! * [`registration`], [`watch`] — an axis' motion events (MAR, MAW).

pub mod axis;
pub mod catalogue;
pub mod coord;
pub mod dynamics;
pub mod homing;
pub mod instruction;
pub mod mapc;
pub mod mccm;
pub mod mccp;
pub mod mclm;
pub mod mct;
pub mod modulo;
pub mod output_cam;
pub mod profile;
pub mod registration;
pub mod servo;
pub mod task;
mod vector;
pub mod watch;
