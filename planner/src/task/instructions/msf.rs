//! MSF (Motion Servo Off): opens the servo loop of an axis and disables its
//! drive; every motion process on it ends at once. Its Axis is an
//! `AXIS_CIP_DRIVE` (see [`super::mso`]). The state rules and their ERR
//! codes are [`crate::servo`]'s.

use crate::catalogue::words::op;
use crate::catalogue::{CallStyle, Format, Kind};
use crate::instruction::{Fault, fault};
use super::entry::{Instruction, no_check, no_load};
use crate::task::{Args, MotionTask};

/// Motion Servo Off.
pub const MSF: Instruction = Instruction {
    mnemonic: "MSF",
    title: "Motion Servo Off",
    summary: "opens the servo loop of an axis and disables its drive; its motion ends",
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
    let result = task.msf(args.axis(0), control).map_err(fault);
    task.rung_false_next_scan(control);
    result
}
