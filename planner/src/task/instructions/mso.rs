//! MSO (Motion Servo On): closes the servo loop of an axis at its current
//! position, `.DN` once it is closed. Its Axis is an `AXIS_CIP_DRIVE`: a
//! virtual axis, always servo-on, is refused when the program loads, as
//! the controller's verifier refuses it. The state rules and their ERR
//! codes are [`crate::servo`]'s.

use crate::catalogue::words::DRIVE_AXIS_AND_CONTROL;
use crate::instruction::Fault;
use super::entry::{Instruction, one_shot};
use crate::task::{Args, MotionTask};

/// Motion Servo On.
pub const MSO: Instruction = Instruction::positional(
    "MSO",
    "Motion Servo On",
    "closes the servo loop of an axis (a drive: virtual axes are always on); `.DN` once it is closed",
    "Logix motion reference",
    DRIVE_AXIS_AND_CONTROL,
    execute,
);

fn execute(task: &mut MotionTask, args: &Args<'_>) -> Result<(), Fault> {
    let control = args.control(1);
    one_shot(task, control, |task| task.mso(args.axis(0), control))
}
