//! MASR (Motion Axis Shutdown Reset): a shut-down axis leaves Shutdown
//! servo-off (a virtual one is on again), its fault word cleared. The state
//! rules and their ERR codes are [`crate::servo`]'s.

use crate::catalogue::words::AXIS_AND_CONTROL;
use crate::instruction::Fault;
use super::entry::{Instruction, one_shot};
use crate::task::{Args, MotionTask};

/// Motion Axis Shutdown Reset.
pub const MASR: Instruction = Instruction::positional(
    "MASR",
    "Motion Axis Shutdown Reset",
    "takes an axis out of Shutdown (servo off; a virtual axis on)",
    "Logix motion reference",
    AXIS_AND_CONTROL,
    execute,
);

fn execute(task: &mut MotionTask, args: &Args<'_>) -> Result<(), Fault> {
    let control = args.control(1);
    one_shot(task, control, |task| task.masr(args.axis(0), control))
}
