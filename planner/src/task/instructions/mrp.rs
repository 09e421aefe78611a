//! MRP (Motion Redefine Position): gives an axis a new position without
//! moving it.
//!
//! `MRP(Axis, MotionControl, Type, PositionSelect, Position)`:
//! * Type 0 **absolute**: the selected position becomes `Position`;
//!   1 **relative**: `Position` is added to it.
//! * Position Select 0 **actual**, 1 **command**: the position the new value
//!   is applied to. The other one is shifted by the same amount, so the
//!   following error (command − actual) is preserved and no motion results.
//! * Usable while moving: the motion task shifts the running move, jog or
//!   cam with the axis, so the motion in progress continues undisturbed;
//!   cams mastered to the axis see no master motion from it. A relative
//!   redefinition is exact at any speed. An absolute one takes the position
//!   of the coarse update in which it executes (the spec's "position error
//!   equal to the motion of the axis during the time it takes to execute"
//!   is at most one coarse update of travel).
//! * ERR 13 with EXERR 2 (Type), 3 (Position Select) or 4 (Position not
//!   finite, or past ±10⁹ units: [`crate::axis::MAX_POSITION`]).
//! * **Soft travel limits** (`AxisConfig::soft_travel_limits`, the spec's
//!   Max Positive / Max Negative Travel): a redefined *actual* position
//!   (the one soft overtravel checking watches; absolute or relative, either
//!   Position Select) outside them is redefined all the same (`.DN`) and
//!   raises the soft overtravel fault at once, as the spec says ("a
//!   software overtravel fault is generated when the instruction is
//!   executed"); the axis then takes its `soft_overtravel_action` (see
//!   [`crate::servo`]). The bounds themselves are inside.
//!
//! Choice: the redefinition completes inside the call (`.DN` at once; the
//! spec allows several coarse updates).

use super::entry::{Instruction, no_load, one_shot};
use crate::catalogue::words::{ACTUAL_COMMAND, MRP_TYPE, motion_control, op};
use crate::catalogue::{CallStyle, Format, Kind};
use crate::instruction::{Fault, fault};
use crate::instruction::{NoFault, Refusal};
use crate::task::engine::Need;
use crate::task::{Args, AxisHandle, InstructionHandle, MotionTask};

/// Motion Redefine Position.
pub const MRP: Instruction = Instruction {
    mnemonic: "MRP",
    title: "Motion Redefine Position",
    summary: "redefines an axis position, no motion",
    reference: "`004_…` (MAPC, with MRP)",
    style: CallStyle::Positional,
    operands: &[
        op("Axis", "AXIS", Format::Tag, Kind::Axis, 0),
        motion_control(1),
        op("Type", "BOOLEAN", Format::Immediate, Kind::Enumeration(MRP_TYPE), 2),
        op(
            "Position Select",
            "BOOLEAN",
            Format::Immediate,
            Kind::Enumeration(ACTUAL_COMMAND),
            3,
        ),
        op("Position", "REAL", Format::ImmediateOrTag, Kind::Number, 4),
    ],
    execute,
    check,
    load: no_load,
};

/// Why MRP fails: ERR 13 with the operand, or the axis' state.
pub type MrpError = Refusal<NoFault>;

/// Absolute or relative.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RedefineType {
    /// 0: the position becomes the value.
    Absolute,
    /// 1: the value is added to the position.
    Relative,
}

/// Actual or command position.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PositionSelect {
    /// 0: the actual position.
    Actual,
    /// 1: the command position.
    Command,
}

/// A validated MRP.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Mrp {
    /// Absolute or relative.
    pub kind: RedefineType,
    /// Which position the value applies to.
    pub select: PositionSelect,
    /// The value, axis units.
    pub position: f64,
}

impl Mrp {
    /// Validates the operands (Type, Position Select as DINTs).
    ///
    /// # Errors
    /// ERR 13 naming the operand.
    pub fn new(kind: i32, select: i32, position: f64) -> Result<Self, MrpError> {
        let kind = match kind {
            0 => RedefineType::Absolute,
            1 => RedefineType::Relative,
            k => return Err(Refusal::operand(MRP.exerr("Type"), f64::from(k))),
        };
        let select = match select {
            0 => PositionSelect::Actual,
            1 => PositionSelect::Command,
            s => return Err(Refusal::operand(MRP.exerr("Position Select"), f64::from(s))),
        };
        if !crate::axis::position_in_reach(position) {
            return Err(Refusal::operand(MRP.exerr("Position"), position));
        }
        Ok(Self { kind, select, position })
    }

    /// The operands of a call, validated.
    ///
    /// # Errors
    /// As [`Mrp::new`].
    pub fn bind(args: &Args<'_>) -> Result<Self, MrpError> {
        Mrp::new(args.code(2), args.code(3), args.number(4))
    }

    /// The shift to apply to both command and actual position, given them.
    pub fn delta(&self, command: f64, actual: f64) -> f64 {
        let current = match self.select {
            PositionSelect::Actual => actual,
            PositionSelect::Command => command,
        };
        match self.kind {
            RedefineType::Absolute => self.position - current,
            RedefineType::Relative => self.position,
        }
    }
}

fn execute(task: &mut MotionTask, args: &Args<'_>) -> Result<(), Fault> {
    let control = args.control(1);
    one_shot(task, control, |task| {
        task.mrp(args.axis(0), control, args.code(2), args.code(3), args.number(4))
    })
}

fn check(_: &MotionTask, args: &Args<'_>) -> Result<(), Fault> {
    Mrp::bind(args).map(|_| ()).map_err(fault)
}

impl MotionTask {
    /// MRP on `axis` (Type and Position Select as DINTs).
    ///
    /// # Errors
    /// ERR 13 with EXERR 2, 3 or 4; EXERR 4 also when the redefined position
    /// would lie outside the axis' soft travel limits (module doc). A
    /// failed MRP redefines nothing.
    pub(crate) fn mrp(
        &mut self,
        axis: AxisHandle,
        motion_control: InstructionHandle,
        kind: i32,
        select: i32,
        position: f64,
    ) -> Result<(), MrpError> {
        self.instruction(motion_control, |task| {
            let mrp = Mrp::new(kind, select, position)?;
            task.check_state(axis, Need::Any)?;
            let a = &task.axes[axis.0 as usize];
            let delta = mrp.delta(a.command.position, a.actual);
            // Soft overtravel watches the actual position (`crate::servo`): a
            // redefinition outside the limits raises the exception at once.
            let overtravel = crate::servo::MotionFaults::beyond(a.config.soft_travel_limits, a.actual + delta);
            task.redefine_position(axis, delta);
            task.motion_bits_mut(motion_control).dn = true;
            if let Some(bit) = overtravel {
                task.raise_soft_overtravel(axis, bit);
            }
            Ok(())
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::instruction::LogixFault;

    #[test]
    fn delta_preserves_following_error_and_operands_are_checked() {
        // Command 10, actual 9.5 (following error 0.5).
        let abs_actual = Mrp::new(0, 0, 100.0).unwrap().delta(10.0, 9.5);
        assert_eq!((10.0 + abs_actual, 9.5 + abs_actual), (100.5, 100.0));
        let abs_command = Mrp::new(0, 1, 100.0).unwrap().delta(10.0, 9.5);
        assert_eq!((10.0 + abs_command, 9.5 + abs_command), (100.0, 99.5));
        assert_eq!(Mrp::new(1, 0, -3.0).unwrap().delta(10.0, 9.5), -3.0);
        assert_eq!(Mrp::new(2, 0, 0.0).unwrap_err().exerr(), 2);
        assert_eq!(Mrp::new(0, 2, 0.0).unwrap_err().exerr(), 3);
        assert_eq!(Mrp::new(0, 0, f64::NAN).unwrap_err().exerr(), 4);
    }
}
