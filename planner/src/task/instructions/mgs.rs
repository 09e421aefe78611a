//! MGS (Motion Group Stop): stops every axis of the motion group, each by
//! its `ProgrammedStopMode` (Stop Mode *programmed*) or all by Fast Stop or
//! Fast Disable. What each mode does, and when `.PC` sets, is the group's
//! (`task/group.rs`).
//!
//! `MGS(Group, MotionControl, StopMode)`: Stop Mode `programmed` (0),
//! `fast stop` (1), `fast disable` (2), an Immediate operand. The manual
//! prints the words, not their codes: the codes follow the words' order.

use super::entry::{Instruction, no_check, no_load, one_shot};
use crate::catalogue::words::{MGS_STOP_MODE, motion_control, op};
use crate::catalogue::{CallStyle, Format, Kind};
use crate::instruction::{Fault, NoFault, Refusal};
use crate::task::group::GroupStop;
use crate::task::{Args, InstructionHandle, MotionTask};

/// Motion Group Stop.
pub const MGS: Instruction = Instruction {
    mnemonic: "MGS",
    title: "Motion Group Stop",
    summary: "stops every axis of the motion group by its programmed stop mode, or by fast stop / fast disable; `.PC` when all are at rest",
    reference: "Logix motion reference",
    style: CallStyle::Positional,
    operands: &[
        op("Group", "MOTION_GROUP", Format::Tag, Kind::Group, 0),
        motion_control(1),
        op(
            "Stop Mode",
            "DINT",
            Format::Immediate,
            Kind::Enumeration(MGS_STOP_MODE),
            2,
        ),
    ],
    execute,
    check: no_check,
    load: no_load,
};

fn execute(task: &mut MotionTask, args: &Args<'_>) -> Result<(), Fault> {
    let control = args.control(1);
    one_shot(task, control, |task| {
        let stop = match args.integer(2) {
            0 => GroupStop::Programmed,
            1 => GroupStop::FastStop,
            2 => GroupStop::FastDisable,
            mode => {
                let e = Refusal::<NoFault>::operand(MGS.exerr("Stop Mode"), mode as f64);
                return task.instruction(control, |_| Err::<(), _>(e));
            }
        };
        task.group_stop(control, stop);
        Ok(())
    })
}

/// Runs a group instruction whose only operands are the group and its
/// control structure (MGSD, MGSR, MGSP): `run` on the control structure,
/// on a one-shot rung; these never refuse.
pub(super) fn group_call(
    task: &mut MotionTask,
    args: &Args<'_>,
    run: fn(&mut MotionTask, InstructionHandle),
) -> Result<(), Fault> {
    let control = args.control(1);
    one_shot(task, control, |task| {
        run(task, control);
        Ok::<(), NoFault>(())
    })
}
