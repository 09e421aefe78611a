//! MAFR (Motion Axis Fault Reset): clears the axis' `AxisFault` word; an
//! axis a fault had disabled is servo-off (MSO to enable it). The state
//! rules and their ERR codes are [`crate::servo`]'s.

use crate::catalogue::words::op;
use crate::catalogue::{CallStyle, Format, Kind};
use crate::instruction::{Fault, fault};
use super::entry::{Instruction, no_check, no_load};
use crate::task::{Args, MotionTask};

/// Motion Axis Fault Reset.
pub const MAFR: Instruction = Instruction {
    mnemonic: "MAFR",
    title: "Motion Axis Fault Reset",
    summary: "clears an axis' faults; an axis a fault disabled is servo-off",
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
    let result = task.mafr(args.axis(0), control).map_err(fault);
    task.rung_false_next_scan(control);
    result
}
