//! PLCopen / Beckhoff `MC_MoveModulo`: modulo positioning of a rotary axis,
//! every BufferMode, as [`crate::modulo`] describes it; the commands run in
//! the engine (`task.rs`), each instance's outputs (`Done`, `Busy`,
//! `Active`, `CommandAborted`, `Error`, `ErrorID`) as PLCopen defines them.
//!
//! A call on an instance sets the inputs it names; the others keep their
//! last value, as PLC block inputs do, and the block evaluates them at the
//! next coarse update (a rising `Execute` starts a command). The instance
//! drives the axis its first call names (`Axis`, bound when the program
//! loads). `Options` (ST_MoveOptions) is the instance's declaration, not an
//! input a call sets.

use crate::catalogue::words::{MC_BUFFER_MODE, MC_DIRECTION, op};
use crate::catalogue::{CallStyle, Format, Kind};
use crate::instruction::Fault;
use super::entry::{Instruction, no_check, no_load};
use crate::modulo::{McBufferMode, McDirection};
use crate::task::{Arg, Args, MotionTask};

/// PLCopen / Beckhoff `MC_MoveModulo`, called on an instance with named
/// inputs (`Options` is listed so that naming it gets a clear refusal).
pub const MC_MOVE_MODULO: Instruction = Instruction {
    mnemonic: "MC_MoveModulo",
    title: "Modulo positioning",
    summary: "modulo positioning of a rotary axis, all BufferModes (PLCopen function block, named inputs on an instance)",
    reference: "`003_…` (MC_MoveModulo)",
    style: CallStyle::Named,
    operands: &[
        op("Axis", "AXIS_REF", Format::Tag, Kind::Axis, -1),
        op("Execute", "BOOL", Format::Input, Kind::Bool, -1),
        op("Position", "LREAL", Format::Input, Kind::Number, -1),
        op("Velocity", "LREAL", Format::Input, Kind::Number, -1),
        op("Acceleration", "LREAL", Format::Input, Kind::Number, -1),
        op("Deceleration", "LREAL", Format::Input, Kind::Number, -1),
        op("Jerk", "LREAL", Format::Input, Kind::Number, -1),
        op("Direction", "MC_Direction", Format::Input, Kind::Enumeration(MC_DIRECTION), -1),
        op(
            "BufferMode",
            "MC_BufferMode",
            Format::Input,
            Kind::Enumeration(MC_BUFFER_MODE),
            -1,
        ),
        op("Options", "ST_MoveOptions", Format::Input, Kind::Number, -1),
    ],
    execute,
    check: no_check,
    load: no_load,
};

/// Sets the inputs the call names on its instance; nothing it could refuse
/// (the block reports in its outputs).
fn execute(task: &mut MotionTask, args: &Args<'_>) -> Result<(), Fault> {
    let Some(fb) = args.instance else {
        return Ok(());
    };
    let mut inputs = task.move_modulo_inputs(fb);
    for (i, arg) in args.values.iter().enumerate() {
        if *arg == Arg::Absent {
            continue;
        }
        match i {
            1 => inputs.execute = args.bool(1),
            2 => inputs.position = args.number(2),
            3 => inputs.velocity = args.number(3),
            4 => inputs.acceleration = args.number(4),
            5 => inputs.deceleration = args.number(5),
            6 => inputs.jerk = args.number(6),
            7 => inputs.direction = McDirection::from_code(args.integer(7)).unwrap_or(inputs.direction),
            8 => inputs.buffer_mode = McBufferMode::from_code(args.integer(8)).unwrap_or(inputs.buffer_mode),
            _ => {}
        }
    }
    task.set_move_modulo_inputs(fb, inputs);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every word of Direction and BufferMode is a code the block takes.
    #[test]
    fn the_inputs_words_are_the_blocks_codes() {
        for w in MC_DIRECTION {
            assert!(McDirection::from_code(w.code).is_some(), "{}", w.word);
        }
        for w in MC_BUFFER_MODE {
            assert!(McBufferMode::from_code(w.code).is_some(), "{}", w.word);
        }
        let code = |words: &[crate::catalogue::Word], word: &str| {
            words.iter().find(|w| w.word.eq_ignore_ascii_case(word)).map(|w| w.code)
        };
        assert_eq!(
            code(MC_DIRECTION, "mc_shortest_way").and_then(McDirection::from_code),
            Some(McDirection::ShortestWay)
        );
        assert_eq!(
            code(MC_BUFFER_MODE, "MC_BlendingHigh").and_then(McBufferMode::from_code),
            Some(McBufferMode::BlendingHigh)
        );
    }
}
