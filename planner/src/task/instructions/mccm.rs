//! MCCM (Motion Coordinated Circular Move): an arc or a full circle through
//! the axes of a coordinate system, 2D or 3D, by via point, center, radius
//! or incremental center. The circle's construction and verification are
//! [`crate::mccm`]'s; the shared operands, termination, merge and
//! master-driven rules are [`crate::coord`]'s; the engine (`task/coord.rs`)
//! queues, blends and runs the move, as for MCLM ([`super::mclm`]).

use super::mclm::{MoveIndex, ignore_start_dependent};
use crate::catalogue::CallStyle;
use crate::instruction::{Fault, fault};
use super::entry::{Instruction, no_load};
use crate::coord::{CoordMoveError, MCCM_OPERANDS, MoveType};
use crate::instruction::Refusal;
use crate::mccm::MccmInputs;
use crate::task::{Args, CoordCall, MotionTask};

/// Motion Coordinated Circular Move.
pub const MCCM: Instruction = Instruction {
    mnemonic: "MCCM",
    title: "Motion Coordinated Circular Move",
    summary: "coordinated circular move of a `COORDINATE_SYSTEM`: 2D and 3D arcs, every circle type, termination types 0–6 with blending, merge, master-driven mode",
    reference: "`000_…` (MCCM)",
    style: CallStyle::Positional,
    operands: MCCM_OPERANDS,
    execute,
    check,
    load: no_load,
};

const INDEX: MoveIndex = MoveIndex::of(&MCCM);
const CIRCLE_TYPE: usize = MCCM.index("Circle Type");
const VIA_CENTER_RADIUS: usize = MCCM.index("Via/Center/Radius");
const DIRECTION: usize = MCCM.index("Direction");

/// MCCM's operands of a call, by catalogue position.
///
/// # Errors
/// ERR 13 for an array element outside its array.
fn bind(args: &Args<'_>) -> Result<MccmInputs, CoordMoveError> {
    let common = INDEX.bind(&MCCM, args)?;
    let via = args
        .array(VIA_CENTER_RADIUS)
        .ok_or(Refusal::operand_index(MCCM.operands[VIA_CENTER_RADIUS].faceplate))?;
    Ok(MccmInputs {
        common,
        circle_type: args.integer(CIRCLE_TYPE),
        via_center_radius: via.to_vec(),
        direction: args.integer(DIRECTION),
    })
}

fn execute(task: &mut MotionTask, args: &Args<'_>) -> Result<(), Fault> {
    let (system, control) = (args.system(0), args.control(1));
    let call = bind(args).map_err(|e| task.refuse_call(control, e))?;
    task.execute_coordinated(system, control, CoordCall::Mccm(call))
        .map_err(fault)
}

/// The circle's validation from the system at rest: an incremental move
/// is checked whole (a radius that cannot reach its end point, collinear
/// points); an absolute one for what does not depend on where it starts
/// (a radius circle in a 3D system, operands out of range).
fn check(task: &MotionTask, args: &Args<'_>) -> Result<(), Fault> {
    let inputs = bind(args).map_err(fault)?;
    let incremental = inputs.common.move_type == MoveType::Incremental as i64;
    task.verify_at_rest(args.system(0), |ctx| crate::mccm::mccm(&inputs, ctx))
        .map(drop)
        .or_else(|e| ignore_start_dependent(e, incremental))
        .map_err(fault)
}
