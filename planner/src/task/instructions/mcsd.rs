//! MCSD (Motion Coordinated Shutdown): MASD on every axis of a coordinate
//! system; its coordinated motion is cancelled with them. ERR 53 names the
//! first inhibited axis by its index in the system (EXERR).

use crate::catalogue::words::op;
use crate::catalogue::{CallStyle, Format, Kind};
use crate::instruction::{Fault, fault};
use super::entry::{Instruction, no_check, no_load};
use crate::task::{Args, MotionTask};

/// Motion Coordinated Shutdown.
pub const MCSD: Instruction = Instruction {
    mnemonic: "MCSD",
    title: "Motion Coordinated Shutdown",
    summary: "MASD on every axis of a coordinate system; its coordinated motion is cancelled",
    reference: "Logix motion reference",
    style: CallStyle::Positional,
    operands: &[
        op("Coordinate System", "COORDINATE_SYSTEM", Format::Tag, Kind::CoordinateSystem, 0),
        op("Motion Control", "MOTION_INSTRUCTION", Format::Tag, Kind::MotionControl, 1),
    ],
    execute,
    check: no_check,
    load: no_load,
};

fn execute(task: &mut MotionTask, args: &Args<'_>) -> Result<(), Fault> {
    let control = args.control(1);
    let result = task.mcsd(args.system(0), control).map_err(fault);
    task.rung_false_next_scan(control);
    result
}
