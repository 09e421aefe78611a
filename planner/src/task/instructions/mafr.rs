//! MAFR (Motion Axis Fault Reset): clears the axis' `AxisFault` word; an
//! axis a fault had disabled is servo-off (MSO to enable it). The state
//! rules and their ERR codes are [`crate::servo`]'s.

use crate::catalogue::words::AXIS_AND_CONTROL;
use crate::instruction::Fault;
use super::entry::{Instruction, one_shot};
use crate::task::{Args, MotionTask};

/// Motion Axis Fault Reset.
pub const MAFR: Instruction = Instruction::positional(
    "MAFR",
    "Motion Axis Fault Reset",
    "clears an axis' faults; an axis a fault disabled is servo-off",
    "Logix motion reference",
    AXIS_AND_CONTROL,
    execute,
);

fn execute(task: &mut MotionTask, args: &Args<'_>) -> Result<(), Fault> {
    let control = args.control(1);
    one_shot(task, control, |task| task.mafr(args.axis(0), control))
}
