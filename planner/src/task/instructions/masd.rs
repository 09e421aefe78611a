//! MASD (Motion Axis Shutdown): ends every motion process on an axis,
//! disables its drive and puts it in the Shutdown state. The state rules
//! and their ERR codes are [`crate::servo`]'s.

use crate::catalogue::words::AXIS_AND_CONTROL;
use crate::instruction::Fault;
use super::entry::{Instruction, one_shot};
use crate::task::{Args, MotionTask};

/// Motion Axis Shutdown.
pub const MASD: Instruction = Instruction::positional(
    "MASD",
    "Motion Axis Shutdown",
    "ends the motion of an axis, disables its drive and shuts it down",
    "Logix motion reference",
    AXIS_AND_CONTROL,
    execute,
);

fn execute(task: &mut MotionTask, args: &Args<'_>) -> Result<(), Fault> {
    let control = args.control(1);
    one_shot(task, control, |task| task.masd(args.axis(0), control))
}
