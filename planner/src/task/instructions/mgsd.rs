//! MGSD (Motion Group Shutdown): shuts every axis of the motion group down
//! (motion ends, drives off) until MGSR or MASR (`task/group.rs`). `.DN` in the scan it executes; no
//! `.IP` or `.PC`.

use super::entry::Instruction;
use super::mgs::group_call;
use crate::catalogue::words::GROUP_AND_CONTROL;
use crate::instruction::Fault;
use crate::task::{Args, MotionTask};

/// Motion Group Shutdown.
pub const MGSD: Instruction = Instruction::positional(
    "MGSD",
    "Motion Group Shutdown",
    "shuts every axis of the motion group down (motion ends, drives off) until MGSR or MASR",
    "Logix motion reference",
    GROUP_AND_CONTROL,
    execute,
);

fn execute(task: &mut MotionTask, args: &Args<'_>) -> Result<(), Fault> {
    group_call(task, args, MotionTask::group_shutdown)
}
