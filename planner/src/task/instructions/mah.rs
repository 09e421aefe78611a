//! MAH (Motion Axis Home): homes an axis as its homing attributes say
//! ([`crate::homing`]: mode, sequence, position); the homing process runs
//! in the engine (`task/homing.rs`): active homing first brings the
//! motion in process to rest (`.IP`, `HomingStatus`), then redefines the
//! position; passive homing redefines it at once. `.PC` and
//! `AxisHomedStatus` when the axis is homed.

use crate::catalogue::words::op;
use crate::catalogue::{CallStyle, Format, Kind};
use crate::instruction::{Fault, fault};
use super::entry::{Instruction, no_check, no_load};
use crate::task::{Args, MotionTask};

/// Motion Axis Home (how it homes is the axis' configuration).
pub const MAH: Instruction = Instruction {
    mnemonic: "MAH",
    title: "Motion Axis Home",
    summary: "homes an axis as its `home_*` attributes say (active or passive, immediate sequence); sets `AxisHomedStatus`",
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
    let result = task.mah(args.axis(0), control).map_err(fault);
    task.rung_false_next_scan(control);
    result
}
