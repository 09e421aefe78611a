//! MAPC (Motion Axis Position Cam): a slave axis follows a master axis
//! through a calculated cam profile — execution modes and schedules, cam
//! types, master reference and direction, the slip clutch. The operands'
//! validation and the cam math are [`crate::mapc`]'s; the cams run in the
//! engine (`task/cam.rs`), one driver per axis.
//!
//! A call declares its slave a cam slave when the program loads, so that
//! the trace and the recording carry its cam columns from the start.

use crate::catalogue::CallStyle;
use crate::instruction::{Fault, fault};
use super::entry::{Instruction, one_shot};
use crate::mapc::{MAPC_OPERANDS, Mapc, MapcOperands};
use crate::task::{Args, MapcCall, MotionTask};

/// Motion Axis Position Cam.
pub const MAPC: Instruction = Instruction {
    mnemonic: "MAPC",
    title: "Motion Axis Position Cam",
    summary: "position cam of a slave on a master (modes, schedules, cam types, slip clutch)",
    reference: "`004_…` (MAPC)",
    style: CallStyle::Positional,
    operands: MAPC_OPERANDS,
    execute,
    check,
    load,
};

fn operands(args: &Args<'_>) -> MapcOperands {
    MapcOperands {
        direction: args.code(3),
        slave_scaling: args.number(5),
        master_scaling: args.number(6),
        execution_mode: args.code(7),
        execution_schedule: args.code(8),
        master_lock_position: args.number(9),
        cam_lock_position: args.number(10),
        cam_type: args.code(11),
        master_reference: args.code(12),
        master_direction: args.code(13),
    }
}

fn execute(task: &mut MotionTask, args: &Args<'_>) -> Result<(), Fault> {
    let control = args.control(2);
    let call = MapcCall {
        slave: args.axis(0),
        master: args.axis(1),
        motion_control: control,
        cam_profile: args.cam_profile(4),
        operands: operands(args),
    };
    one_shot(task, control, |task| task.mapc(call))
}

fn check(_: &MotionTask, args: &Args<'_>) -> Result<(), Fault> {
    Mapc::new(&operands(args)).map(drop).map_err(fault)
}

fn load(task: &mut MotionTask, args: &Args<'_>) {
    task.declare_cam_slave(args.axis(0));
}
