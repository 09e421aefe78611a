//! MGSP (Motion Group Strobe Position): latches every axis' StrobeActualPosition and StrobeCommandPosition at one instant (`task/group.rs`). `.DN` in the scan it
//! executes; no `.IP` or `.PC`.

use super::entry::{Instruction, one_shot};
use crate::catalogue::words::GROUP_AND_CONTROL;
use crate::instruction::{Fault, NoFault};
use crate::task::{Args, MotionTask};

/// Motion Group Strobe Position.
pub const MGSP: Instruction = Instruction::positional(
    "MGSP",
    "Motion Group Strobe Position",
    "latches every axis' StrobeActualPosition and StrobeCommandPosition at one instant",
    "Logix motion reference",
    GROUP_AND_CONTROL,
    execute,
);

fn execute(task: &mut MotionTask, args: &Args<'_>) -> Result<(), Fault> {
    let control = args.control(1);
    one_shot(task, control, |task| {
        task.group_strobe(control);
        Ok::<(), NoFault>(())
    })
}
