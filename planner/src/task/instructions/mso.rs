//! MSO (Motion Servo On): closes the servo loop of an axis at its current
//! position, `.DN` once it is closed. Its Axis is an `AXIS_CIP_DRIVE`: a
//! virtual axis, always servo-on, is refused when the program loads, as
//! the controller's verifier refuses it. The state rules and their ERR
//! codes are [`crate::servo`]'s.

use crate::catalogue::words::op;
use crate::catalogue::{CallStyle, Format, Kind};
use crate::instruction::{Fault, fault};
use super::entry::{Instruction, no_check, no_load};
use crate::task::{Args, MotionTask};

/// Motion Servo On.
pub const MSO: Instruction = Instruction {
    mnemonic: "MSO",
    title: "Motion Servo On",
    summary: "closes the servo loop of an axis (a drive: virtual axes are always on); `.DN` once it is closed",
    reference: "Logix motion reference",
    style: CallStyle::Positional,
    operands: &[
        op("Axis", "AXIS_CIP_DRIVE", Format::Tag, Kind::DriveAxis, 0),
        op("Motion Control", "MOTION_INSTRUCTION", Format::Tag, Kind::MotionControl, 1),
    ],
    execute,
    check: no_check,
    load: no_load,
};

fn execute(task: &mut MotionTask, args: &Args<'_>) -> Result<(), Fault> {
    let control = args.control(1);
    let result = task.mso(args.axis(0), control).map_err(fault);
    task.rung_false_next_scan(control);
    result
}
