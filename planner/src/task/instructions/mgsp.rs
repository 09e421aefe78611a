//! MGSP (Motion Group Strobe Position): latches every axis'
//! StrobeActualPosition and StrobeCommandPosition at one instant
//! (`task/group.rs`). `.DN` in the scan it executes; no
//! `.IP` or `.PC`.

use super::entry::Instruction;
use super::mgs::group_call;
use crate::catalogue::words::GROUP_AND_CONTROL;
use crate::instruction::Fault;
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
    group_call(task, args, MotionTask::group_strobe)
}
