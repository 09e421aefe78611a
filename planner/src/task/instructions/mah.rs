//! MAH (Motion Axis Home): homes an axis as its homing attributes say
//! ([`crate::homing`]: mode, sequence, position); the homing process runs
//! in the engine (`task/homing.rs`): active homing first brings the
//! motion in process to rest (`.IP`, `HomingStatus`), then redefines the
//! position; passive homing redefines it at once. `.PC` and
//! `AxisHomedStatus` when the axis is homed.

use crate::catalogue::words::AXIS_AND_CONTROL;
use crate::instruction::Fault;
use super::entry::{Instruction, one_shot};
use crate::task::{Args, MotionTask};

/// Motion Axis Home (how it homes is the axis' configuration).
pub const MAH: Instruction = Instruction::positional(
    "MAH",
    "Motion Axis Home",
    "homes an axis as its `home_*` attributes say (active or passive, immediate sequence); sets `AxisHomedStatus`",
    "Logix motion reference",
    AXIS_AND_CONTROL,
    execute,
);

fn execute(task: &mut MotionTask, args: &Args<'_>) -> Result<(), Fault> {
    let control = args.control(1);
    one_shot(task, control, |task| task.mah(args.axis(0), control))
}
