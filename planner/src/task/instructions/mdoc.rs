//! MDOC (Motion Disarm Output Cam): disarms an axis' output cams.
//!
//! `MDOC(Axis, ExecutionTarget, MotionControl, DisarmType)`: Disarm Type
//! `all` (0) ends the cams of every execution target of the axis (and the
//! pending ones), `specific` (1) those of Execution Target (ERR 35 for a
//! target the axis does not have). The bits the cams drove turn off; their
//! MAOCs leave `.IP` without `.PC`. `.DN` in the scan it executes;
//! disarming a target with no cam is no error.

use super::entry::{Instruction, no_check, no_load, one_shot};
use super::maoc::{MaocError, target_index};
use crate::catalogue::words::{motion_control, op, w};
use crate::catalogue::{CallStyle, Format, Kind, Word};
use crate::instruction::{Fault, Refusal};
use crate::task::{Args, MotionTask};

/// MDOC's Disarm Type.
const DISARM_TYPE: &[Word] = &[w("all", 0), w("specific", 1)];

/// Motion Disarm Output Cam.
pub const MDOC: Instruction = Instruction {
    mnemonic: "MDOC",
    title: "Motion Disarm Output Cam",
    summary: "disarms the output cams of an axis: all, or one execution target",
    reference: "Logix motion reference (MOTION-RM002, Motion Event Instructions)",
    style: CallStyle::Positional,
    operands: &[
        op("Axis", "AXIS", Format::Tag, Kind::Axis, 0),
        op("Execution Target", "UINT32", Format::Immediate, Kind::Count, 1),
        motion_control(2),
        op(
            "Disarm Type",
            "UINT32",
            Format::Immediate,
            Kind::Enumeration(DISARM_TYPE),
            3,
        ),
    ],
    execute,
    check: no_check,
    load: no_load,
};

fn execute(task: &mut MotionTask, args: &Args<'_>) -> Result<(), Fault> {
    let control = args.control(2);
    let axis = args.axis(0);
    let (target, disarm) = (args.integer(1), args.integer(3));
    one_shot(task, control, |task| {
        task.instruction(control, |task| -> Result<(), MaocError> {
            let targets = task.axes[axis.0 as usize].config.output_cam_execution_targets;
            match disarm {
                0 => {
                    for k in 0..task.axes[axis.0 as usize].output_cams.len() {
                        task.disarm_output_cam(axis, k, true);
                    }
                }
                1 => {
                    let k = target_index(target, targets)?;
                    task.disarm_output_cam(axis, k, true);
                }
                d => return Err(Refusal::operand(MDOC.exerr("Disarm Type"), d as f64)),
            }
            task.motion_bits_mut(control).dn = true;
            Ok(())
        })
    })
}
