//! MDW (Motion Disarm Watch): disarms an axis' watch event.
//!
//! `MDW(Axis, MotionControl)`: `WatchEventArmedStatus` is cleared and the
//! MAW that armed it is no longer in process (its `.IP` cleared, no
//! `.PC`); `WatchEventStatus` and `WatchPosition` keep their values.
//! `.DN` in the scan it executes; disarming a watch that is not armed is no
//! error.

use super::entry::{Instruction, one_shot};
use crate::catalogue::words::AXIS_AND_CONTROL;
use crate::instruction::{Fault, NoFault};
use crate::task::{Args, MotionTask};

/// Motion Disarm Watch.
pub const MDW: Instruction = Instruction::positional(
    "MDW",
    "Motion Disarm Watch",
    "disarms the watch event armed by MAW",
    "Logix motion reference (MOTION-RM002, Motion Event Instructions)",
    AXIS_AND_CONTROL,
    execute,
);

fn execute(task: &mut MotionTask, args: &Args<'_>) -> Result<(), Fault> {
    let control = args.control(1);
    one_shot(task, control, |task| {
        task.instruction(control, |task| {
            task.disarm_watch(args.axis(0));
            task.motion_bits_mut(control).dn = true;
            Ok::<(), NoFault>(())
        })
    })
}
