//! MSF (Motion Servo Off): opens the servo loop of an axis and disables its
//! drive; every motion process on it ends at once. Its Axis is an
//! `AXIS_CIP_DRIVE` (see [`super::mso`]). The state rules and their ERR
//! codes are [`crate::servo`]'s.

use crate::catalogue::words::DRIVE_AXIS_AND_CONTROL;
use crate::instruction::Fault;
use super::entry::{Instruction, one_shot};
use crate::task::{Args, MotionTask};

/// Motion Servo Off.
pub const MSF: Instruction = Instruction::positional(
    "MSF",
    "Motion Servo Off",
    "opens the servo loop of an axis and disables its drive; its motion ends",
    "Logix motion reference",
    DRIVE_AXIS_AND_CONTROL,
    execute,
);

fn execute(task: &mut MotionTask, args: &Args<'_>) -> Result<(), Fault> {
    let control = args.control(1);
    one_shot(task, control, |task| task.msf(args.axis(0), control))
}
