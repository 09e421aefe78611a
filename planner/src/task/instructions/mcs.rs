//! MCS (Motion Coordinated Stop): stops a coordinate system's motion along
//! its path and cancels its queue; Stop Type All also stops the
//! single-axis motion of its axes. The operands and their verification
//! are [`crate::coord::McsInputs`]'s; the engine (`task/coord.rs`) ramps
//! the path to rest.

use crate::catalogue::words::{motion_control, MCS_STOP_TYPE, NO_YES, TIME_DECEL_UNITS, TIME_JERK_UNITS, op};
use crate::catalogue::{CallStyle, Format, Kind};
use crate::instruction::{Fault, fault};
use super::entry::{Instruction, no_load};
use crate::coord::{Mcs, McsInputs};
use crate::task::{Args, CoordCall, MotionTask};

/// Motion Coordinated Stop.
pub const MCS: Instruction = Instruction {
    mnemonic: "MCS",
    title: "Motion Coordinated Stop",
    summary: "coordinated stop: stops a system and cancels its queue",
    reference: "`000_…` (MCCM)",
    style: CallStyle::Positional,
    operands: &[
        op("Coordinate System", "COORDINATE_SYSTEM", Format::Tag, Kind::CoordinateSystem, 0),
        motion_control(1),
        op("Stop Type", "DINT", Format::Immediate, Kind::Enumeration(MCS_STOP_TYPE), 2),
        op("Change Decel", "DINT", Format::Immediate, Kind::Enumeration(NO_YES), 3),
        op("Decel Rate", "REAL", Format::ImmediateOrTag, Kind::Number, 4),
        op("Decel Units", "DINT", Format::Immediate, Kind::Enumeration(TIME_DECEL_UNITS), 5),
        op("Change Decel Jerk", "DINT", Format::Immediate, Kind::Enumeration(NO_YES), 6),
        op("Decel Jerk", "REAL", Format::ImmediateOrTag, Kind::Number, 7),
        op("Jerk Units", "DINT", Format::Immediate, Kind::Enumeration(TIME_JERK_UNITS), 8),
    ],
    execute,
    check,
    load: no_load,
};

fn bind(args: &Args<'_>) -> McsInputs {
    McsInputs {
        stop_type: args.integer(2),
        change_decel: args.integer(3),
        decel_rate: args.number(4),
        decel_units: args.integer(5),
        change_decel_jerk: args.integer(6),
        decel_jerk: args.number(7),
        jerk_units: args.integer(8),
    }
}

fn execute(task: &mut MotionTask, args: &Args<'_>) -> Result<(), Fault> {
    task.execute_coordinated(args.system(0), args.control(1), CoordCall::Mcs(bind(args)))
        .map_err(fault)
}

fn check(task: &MotionTask, args: &Args<'_>) -> Result<(), Fault> {
    task.verify_at_rest(args.system(0), |ctx| Mcs::new(&bind(args), ctx.system))
        .map(drop)
        .map_err(fault)
}
