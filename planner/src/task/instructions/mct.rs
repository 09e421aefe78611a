//! MCT (Motion Coordinated Transform): a Cartesian coordinate system drives
//! a robot's joint system (Cartesian gantry or H-bot, articulated, SCARA,
//! Delta 3D/2D, SCARA Delta), in both directions, with the Orientation and
//! Translation of the Cartesian frame. The transform's rules and refusals
//! (ERR 61 with its EXERR, ERR 13, ERR 67) are [`crate::mct`]'s; the
//! engine (`task/mct.rs`) moves the side that did not move each coarse
//! update. Each system's geometry is the one its tag declares when the
//! program loads (the twin gives it to the task with the system).
//!
//! Orientation and Translation are `REAL[3]`: three elements from the one
//! the operand names; fewer is ERR 13 with the operand's faceplate index.

use super::entry::{Instruction, no_check, no_load};
use crate::catalogue::words::{motion_control, op};
use crate::catalogue::{CallStyle, Format, Kind};
use crate::instruction::{Fault, fault};
use crate::instruction::{NoFault, Refusal};
use crate::task::{Args, MotionTask};

/// Motion Coordinated Transform.
pub const MCT: Instruction = Instruction {
    mnemonic: "MCT",
    title: "Motion Coordinated Transform",
    summary: "coordinate transform: a Cartesian system drives a robot's joint system (Cartesian gantry/H-bot, articulated, SCARA, Delta 3D/2D, SCARA Delta), bidirectional, with orientation and translation",
    reference: "`001_…` (MCT)",
    style: CallStyle::Positional,
    operands: &[
        op(
            "Source System",
            "COORDINATE_SYSTEM",
            Format::Tag,
            Kind::CoordinateSystem,
            0,
        ),
        op(
            "Target System",
            "COORDINATE_SYSTEM",
            Format::Tag,
            Kind::CoordinateSystem,
            1,
        ),
        motion_control(2),
        op("Orientation", "REAL[3]", Format::Array, Kind::Vector3, 3),
        op("Translation", "REAL[3]", Format::Array, Kind::Vector3, 4),
    ],
    execute,
    check: no_check,
    load: no_load,
};

/// Three REALs from the element operand `i` of `instruction` names; ERR
/// 13 with its faceplate index when fewer remain.
pub(super) fn vector3(instruction: &Instruction, args: &Args<'_>, i: usize) -> Result<[f64; 3], Refusal<NoFault>> {
    match args.array(i) {
        Some([x, y, z, ..]) => Ok([*x, *y, *z]),
        _ => Err(Refusal::operand_index(instruction.operands[i].faceplate)),
    }
}

fn execute(task: &mut MotionTask, args: &Args<'_>) -> Result<(), Fault> {
    let control = args.control(2);
    let vectors = vector3(&MCT, args, 3).and_then(|o| Ok((o, vector3(&MCT, args, 4)?)));
    let (orientation, translation) = vectors.map_err(|e| task.refuse_call(control, e))?;
    task.execute_mct(control, args.system(0), args.system(1), orientation, translation)
        .map_err(fault)
}
