//! MASR (Motion Axis Shutdown Reset): a shut-down axis leaves Shutdown
//! servo-off (a virtual one is on again), its fault word cleared. The state
//! rules and their ERR codes are [`crate::servo`]'s.

use crate::catalogue::words::op;
use crate::catalogue::{CallStyle, Format, Kind};
use crate::instruction::{Fault, fault};
use super::entry::{Instruction, no_check, no_load};
use crate::task::{Args, MotionTask};

/// Motion Axis Shutdown Reset.
pub const MASR: Instruction = Instruction {
    mnemonic: "MASR",
    title: "Motion Axis Shutdown Reset",
    summary: "takes an axis out of Shutdown (servo off; a virtual axis on)",
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
    let result = task.masr(args.axis(0), control).map_err(fault);
    task.rung_false_next_scan(control);
    result
}
