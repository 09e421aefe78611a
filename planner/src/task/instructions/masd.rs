//! MASD (Motion Axis Shutdown): ends every motion process on an axis,
//! disables its drive and puts it in the Shutdown state. The state rules
//! and their ERR codes are [`crate::servo`]'s.

use crate::catalogue::words::op;
use crate::catalogue::{CallStyle, Format, Kind};
use crate::instruction::{Fault, fault};
use super::entry::{Instruction, no_check, no_load};
use crate::task::{Args, MotionTask};

/// Motion Axis Shutdown.
pub const MASD: Instruction = Instruction {
    mnemonic: "MASD",
    title: "Motion Axis Shutdown",
    summary: "ends the motion of an axis, disables its drive and shuts it down",
    reference: "Logix motion reference",
    style: CallStyle::Positional,
    operands: &[
        op("Axis", "AXIS", Format::Tag, Kind::Axis, 0),
        op("Motion Control", "MOTION_INSTRUCTION", Format::Tag, Kind::MotionControl, 1),
    ],
    execute,
    check: no_check,
    load: no_load,
};

fn execute(task: &mut MotionTask, args: &Args<'_>) -> Result<(), Fault> {
    let control = args.control(1);
    let result = task.masd(args.axis(0), control).map_err(fault);
    task.rung_false_next_scan(control);
    result
}
