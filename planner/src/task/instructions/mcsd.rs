//! MCSD (Motion Coordinated Shutdown): MASD on every axis of a coordinate
//! system; its coordinated motion is cancelled with them. ERR 53 names the
//! first inhibited axis by its index in the system (EXERR).

use crate::catalogue::words::SYSTEM_AND_CONTROL;
use crate::instruction::Fault;
use super::entry::{Instruction, one_shot};
use crate::task::{Args, MotionTask};

/// Motion Coordinated Shutdown.
pub const MCSD: Instruction = Instruction::positional(
    "MCSD",
    "Motion Coordinated Shutdown",
    "MASD on every axis of a coordinate system; its coordinated motion is cancelled",
    "Logix motion reference",
    SYSTEM_AND_CONTROL,
    execute,
);

fn execute(task: &mut MotionTask, args: &Args<'_>) -> Result<(), Fault> {
    let control = args.control(1);
    one_shot(task, control, |task| task.mcsd(args.system(0), control))
}
