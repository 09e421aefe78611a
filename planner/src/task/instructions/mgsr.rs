//! MGSR (Motion Group Shutdown Reset): takes every shut-down axis of the
//! motion group out of Shutdown, as MASR does (`task/group.rs`). `.DN` in the scan it executes; no
//! `.IP` or `.PC`.

use super::entry::Instruction;
use super::mgs::group_call;
use crate::catalogue::words::GROUP_AND_CONTROL;
use crate::instruction::Fault;
use crate::task::{Args, MotionTask};

/// Motion Group Shutdown Reset.
pub const MGSR: Instruction = Instruction::positional(
    "MGSR",
    "Motion Group Shutdown Reset",
    "takes every shut-down axis of the motion group out of Shutdown, as MASR does",
    "Logix motion reference",
    GROUP_AND_CONTROL,
    execute,
);

fn execute(task: &mut MotionTask, args: &Args<'_>) -> Result<(), Fault> {
    group_call(task, args, MotionTask::group_shutdown_reset)
}
