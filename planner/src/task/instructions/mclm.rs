//! MCLM (Motion Coordinated Linear Move): a straight line through the axes
//! of a coordinate system. The operands' meaning, units, termination,
//! merge, master-driven and event rules are those of [`crate::coord`]; the
//! line is built and verified by [`crate::mclm`]; the move is queued,
//! blended and run by the engine (`task/coord.rs`), which verifies a move
//! that waits for a queue slot when it takes it. A one-shot rung (a
//! `[[program]]` step) stays true for the update after the call, as the
//! queue needs.
//!
//! Event Distance is kept for the move; Calculated Data is checked (`0` or
//! an array) and the calculated values stay in the planner
//! ([`MotionTask::coord_calculated_data`]).

use crate::catalogue::CallStyle;
use crate::instruction::{Fault, fault};
use super::entry::{Instruction, no_load};
use crate::coord::{CoordMoveError, CoordMoveInputs, MCLM_OPERANDS, MoveType};
use crate::dynamics::MoveDynamics;
use crate::instruction::{LogixFault, Refusal};
use crate::task::{Args, CoordCall, MotionTask};

/// Motion Coordinated Linear Move.
pub const MCLM: Instruction = Instruction {
    mnemonic: "MCLM",
    title: "Motion Coordinated Linear Move",
    summary: "coordinated linear move of a `COORDINATE_SYSTEM`, termination types 0–6 with blending, merge, master-driven mode",
    reference: "`000_…` (MCCM)",
    style: CallStyle::Positional,
    operands: &MCLM_OPERANDS,
    execute,
    check,
    load: no_load,
};

/// Where the operands MCLM and MCCM share sit in a call, by catalogue
/// position (the circle operands shift MCCM's).
#[derive(Debug, Clone, Copy)]
pub(super) struct MoveIndex {
    move_type: usize,
    position: usize,
    speed: usize,
    termination_type: usize,
    event_distance: usize,
    calculated_data: usize,
}

impl MoveIndex {
    /// The positions in `entry`'s call.
    pub(super) const fn of(entry: &Instruction) -> Self {
        MoveIndex {
            move_type: entry.index("Move Type"),
            position: entry.index("Position"),
            speed: entry.index("Speed"),
            termination_type: entry.index("Termination Type"),
            event_distance: entry.index("Event Distance"),
            calculated_data: entry.index("Calculated Data"),
        }
    }

    /// The shared operands of a call, in their call order: Speed to Jerk
    /// Units follow each other, and so do Termination Type to Lock
    /// Direction.
    ///
    /// # Errors
    /// ERR 13 for a Position, Event Distance or Calculated Data element
    /// outside its array.
    pub(super) fn bind(&self, entry: &Instruction, args: &Args<'_>) -> Result<CoordMoveInputs, CoordMoveError> {
        let array = |i: usize| args.optional_array(i).ok_or(Refusal::operand_index(entry.operands[i].faceplate));
        let position = array(self.position)?.to_vec();
        let s = self.speed;
        let dynamics = MoveDynamics {
            speed: args.number(s),
            speed_units: args.integer(s + 1),
            accel_rate: args.number(s + 2),
            accel_units: args.integer(s + 3),
            decel_rate: args.number(s + 4),
            decel_units: args.integer(s + 5),
            profile: args.integer(s + 6),
            accel_jerk: args.number(s + 7),
            decel_jerk: args.number(s + 8),
            jerk_units: args.integer(s + 9),
        };
        let t = self.termination_type;
        let inputs = CoordMoveInputs {
            move_type: args.integer(self.move_type),
            position,
            dynamics,
            termination_type: args.integer(t),
            merge: args.integer(t + 1),
            merge_speed: args.integer(t + 2),
            command_tolerance: args.number(t + 3),
            lock_position: args.number(t + 4),
            lock_direction: args.integer(t + 5),
            event_distance: array(self.event_distance)?.to_vec(),
        };
        array(self.calculated_data)?;
        Ok(inputs)
    }
}

const INDEX: MoveIndex = MoveIndex::of(&MCLM);

fn execute(task: &mut MotionTask, args: &Args<'_>) -> Result<(), Fault> {
    let (system, control) = (args.system(0), args.control(1));
    let call = INDEX.bind(&MCLM, args).map_err(|e| task.refuse_call(control, e))?;
    task.execute_coordinated(system, control, CoordCall::Mclm(call))
        .map_err(fault)
}

/// The line's validation from the system at rest: an incremental move is
/// checked whole; an absolute one (whose start the program decides) for
/// what does not depend on where it starts.
fn check(task: &MotionTask, args: &Args<'_>) -> Result<(), Fault> {
    let inputs = INDEX.bind(&MCLM, args).map_err(fault)?;
    let incremental = inputs.move_type == MoveType::Incremental as i64;
    task.verify_at_rest(args.system(0), |ctx| crate::mclm::mclm(&inputs, ctx))
        .map(drop)
        .or_else(|e| ignore_start_dependent(e, incremental))
        .map_err(fault)
}

/// `Ok` for a refusal that depends on the start point of an absolute move.
pub(super) fn ignore_start_dependent(e: CoordMoveError, incremental: bool) -> Result<(), CoordMoveError> {
    match e.err() {
        13 | 25 | 54 => Err(e),
        _ if incremental => Err(e),
        _ => Ok(()),
    }
}
