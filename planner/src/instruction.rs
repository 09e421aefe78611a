//! Instruction status shared by every instruction.
//!
//! * [`MotionInstructionBits`] — the Logix `MOTION_INSTRUCTION` tag: control
//!   bits `.EN .DN .ER .PC .IP .AC .ACCEL .DECEL` and the `ERR`, `EXERR` and
//!   `SEGMENT` codes.
//! * [`FbOutputs`] — the PLCopen function-block outputs `Done`, `Busy`,
//!   `Active`, `CommandAborted`, `Error`, `ErrorID`.
//!
//! These are *status*: an instruction in process is not an error. Errors are
//! carried as numbers in the status (as on the controller). An instruction
//! that refuses to execute says why with a [`LogixFault`]: a [`Refusal`]
//! for the cases all instructions share (an operand out of range, an axis'
//! state) around the instruction's own small enum.

use crate::servo::StateError;
use thiserror::Error;

/// A refusal as the controller reports it in a `MOTION_INSTRUCTION`: the
/// `ERR` code, the `EXERR` and `SEGMENT` that qualify it, and (through
/// `Display`) the planner's sentence saying what was wrong. The meaning of
/// each `ERR` code is the catalogue's ([`crate::catalogue::err_meaning`]).
pub trait LogixFault: std::error::Error + Send + Sync + 'static {
    /// The `ERR` code.
    fn err(&self) -> i32;
    /// The `EXERR` code (0 where the error has none).
    fn exerr(&self) -> i32 {
        0
    }
    /// The `SEGMENT` (0 where the error has none).
    fn segment(&self) -> i32 {
        0
    }
    /// What the `ERR` code means, from the catalogue
    /// ([`crate::catalogue::ERRORS`]); the `Display` text is the
    /// instruction's own sentence about this call.
    fn meaning(&self) -> Option<&'static str> {
        crate::catalogue::err_meaning(self.err())
    }
}

/// A refusal of any instruction, as
/// [`crate::task::instructions::Instruction::execute`] returns it.
pub type Fault = Box<dyn LogixFault>;

/// A refusal as a [`Fault`].
pub fn fault<E: LogixFault>(e: E) -> Fault {
    Box::new(e)
}

/// Why an instruction refused to execute: the two cases every instruction
/// shares — an operand out of range (ERR 13) and the state of an axis it
/// names — and the instruction's own (`E`, a small enum of the
/// instruction's module; [`NoFault`] when it has none).
#[derive(Debug, Clone, Copy, PartialEq, Error)]
#[non_exhaustive]
pub enum Refusal<E> {
    /// ERR 13, Parameter Out Of Range: EXERR is the operand's faceplate
    /// index, counted from 0 (the catalogue's [`crate::catalogue::Operand`]
    /// `faceplate`).
    #[error("parameter out of range: operand {exerr}{} (ERR 13)", value.map_or(String::new(), |v| format!(" = {v}")))]
    Operand {
        /// The operand's faceplate index (EXERR).
        exerr: i32,
        /// The value it was given, where one number is at fault.
        value: Option<f64>,
    },
    /// The state of an axis refuses the instruction (ERR 5, 7, 8, 9, 16,
    /// 20, 22, 53). EXERR is 0, or for an instruction on a coordinate
    /// system the index of the axis in it.
    #[error("{state}")]
    State {
        /// What the state refuses.
        state: StateError,
        /// The axis' index in its coordinate system, or 0.
        exerr: i32,
    },
    /// The instruction's own refusal.
    #[error(transparent)]
    Instruction(E),
}

impl<E> Refusal<E> {
    /// ERR 13 for the operand with faceplate index `exerr`, given `value`.
    pub fn operand(exerr: i32, value: f64) -> Self {
        Self::Operand {
            exerr,
            value: Some(value),
        }
    }

    /// ERR 13 for the operand with faceplate index `exerr` as a whole (an
    /// array too short, a point the operands make impossible).
    pub fn operand_index(exerr: i32) -> Self {
        Self::Operand { exerr, value: None }
    }
}

impl<E> From<StateError> for Refusal<E> {
    fn from(state: StateError) -> Self {
        Self::State { state, exerr: 0 }
    }
}

impl<E: LogixFault> LogixFault for Refusal<E> {
    fn err(&self) -> i32 {
        match self {
            Self::Operand { .. } => 13,
            Self::State { state, .. } => state.err(),
            Self::Instruction(e) => e.err(),
        }
    }

    fn exerr(&self) -> i32 {
        match self {
            Self::Operand { exerr, .. } | Self::State { exerr, .. } => *exerr,
            Self::Instruction(e) => e.exerr(),
        }
    }

    fn segment(&self) -> i32 {
        match self {
            Self::Instruction(e) => e.segment(),
            _ => 0,
        }
    }
}

/// The own refusals of an instruction that has none beyond the shared
/// ones of [`Refusal`] (MAJ, MAS, MRP, MAG, the state instructions).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Error)]
pub enum NoFault {}

impl LogixFault for NoFault {
    fn err(&self) -> i32 {
        match *self {}
    }
}

impl LogixFault for StateError {
    fn err(&self) -> i32 {
        StateError::err(*self)
    }
}

/// A Logix `MOTION_INSTRUCTION` tag.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct MotionInstructionBits {
    /// `.EN` (bit 31): the rung is true / the instruction was enabled.
    pub en: bool,
    /// `.DN` (bit 29): the instruction was verified and started (or queued).
    pub dn: bool,
    /// `.ER` (bit 28): the instruction failed; see `err`/`exerr`.
    pub er: bool,
    /// `.PC` (bit 27): the process is complete.
    pub pc: bool,
    /// `.IP` (bit 26): the process is in progress.
    pub ip: bool,
    /// `.AC` (bit 23): the instruction controls the motion now.
    pub ac: bool,
    /// `.ACCEL` (bit 1): the move is raising its speed.
    pub accel: bool,
    /// `.DECEL` (bit 2): the move is lowering its speed.
    pub decel: bool,
    /// `ERR`: the error code (0 = none).
    pub err: i32,
    /// `EXERR`: the extended error code (the operand at fault, …).
    pub exerr: i32,
    /// `SEGMENT`: the offending segment or element, where the error has one.
    pub segment: i32,
}

impl MotionInstructionBits {
    /// The `FLAGS` DINT with each bit at its documented position.
    pub fn flags(&self) -> u32 {
        let bit = |b: bool, n: u32| u32::from(b) << n;
        bit(self.en, 31)
            | bit(self.dn, 29)
            | bit(self.er, 28)
            | bit(self.pc, 27)
            | bit(self.ip, 26)
            | bit(self.ac, 23)
            | bit(self.decel, 2)
            | bit(self.accel, 1)
    }

    /// Records a failure: sets `.ER` and the `ERR`, `EXERR` and `SEGMENT`
    /// codes (0 where the error has none). The other bits are left to the
    /// failing instruction's own rules.
    pub fn set_error(&mut self, err: i32, exerr: i32, segment: i32) {
        self.er = true;
        self.err = err;
        self.exerr = exerr;
        self.segment = segment;
    }

    /// The motion the instruction started is over (done, stopped or
    /// cancelled): `.IP`, `.AC`, `.ACCEL` and `.DECEL` clear; `.PC` and the
    /// error bits are left to the caller.
    pub fn end_motion(&mut self) {
        self.ip = false;
        self.ac = false;
        self.accel = false;
        self.decel = false;
    }

    /// Follows a move's ramp: `.ACCEL` / `.DECEL` while it speeds up or
    /// slows down; when it has `ended`, the motion is over and `.PC` set.
    pub fn follow_ramp(&mut self, accel: bool, decel: bool, ended: bool) {
        self.accel = accel && !ended;
        self.decel = decel && !ended;
        if ended {
            self.end_motion();
            self.pc = true;
        }
    }

    /// The control bits with their mnemonics, in the order `EN`, `DN`,
    /// `ER`, `IP`, `AC`, `PC`, `ACCEL`, `DECEL` (trace and log order).
    pub fn bits(&self) -> [(&'static str, bool); 8] {
        [
            ("EN", self.en),
            ("DN", self.dn),
            ("ER", self.er),
            ("IP", self.ip),
            ("AC", self.ac),
            ("PC", self.pc),
            ("ACCEL", self.accel),
            ("DECEL", self.decel),
        ]
    }

    /// The error codes with their names: `ERR`, `EXERR`, `SEGMENT`.
    pub fn codes(&self) -> [(&'static str, i32); 3] {
        [("ERR", self.err), ("EXERR", self.exerr), ("SEGMENT", self.segment)]
    }

    /// A bit by its mnemonic (`"EN"`, `"DN"`, `"ER"`, `"PC"`, `"IP"`, `"AC"`,
    /// `"ACCEL"`, `"DECEL"`, case-insensitive), for `MC1.PC`-style tag paths.
    pub fn bit(&self, mnemonic: &str) -> Option<bool> {
        Some(match mnemonic.to_ascii_uppercase().as_str() {
            "EN" => self.en,
            "DN" => self.dn,
            "ER" => self.er,
            "PC" => self.pc,
            "IP" => self.ip,
            "AC" => self.ac,
            "ACCEL" => self.accel,
            "DECEL" => self.decel,
            _ => return None,
        })
    }
}

/// PLCopen function-block outputs.
///
/// Rules kept by every block: when `busy` falls, exactly one of `done`,
/// `command_aborted`, `error` is set; `active` only while the block controls
/// the axis; the final outputs stay while `Execute` stays TRUE, are cleared
/// on its falling edge, and show for exactly one cycle if `Execute` was
/// already FALSE when the block finished.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct FbOutputs {
    /// `Done`: the command completed.
    pub done: bool,
    /// `Busy`: the command is being processed (queued or active).
    pub busy: bool,
    /// `Active`: the command controls the axis now.
    pub active: bool,
    /// `CommandAborted`: another command or a stop replaced this one.
    pub command_aborted: bool,
    /// `Error`: the command failed; see `error_id`.
    pub error: bool,
    /// `ErrorID`: the error number (0 = none).
    pub error_id: u32,
}

impl FbOutputs {
    /// The boolean outputs with their PLCopen names, in the order
    /// `Done`, `Busy`, `Active`, `CommandAborted`, `Error`.
    pub fn bits(&self) -> [(&'static str, bool); 5] {
        [
            ("Done", self.done),
            ("Busy", self.busy),
            ("Active", self.active),
            ("CommandAborted", self.command_aborted),
            ("Error", self.error),
        ]
    }

    /// An output by its PLCopen name (`"Done"`, `"Busy"`, `"Active"`,
    /// `"CommandAborted"`, `"Error"`, case-insensitive), for tag paths such
    /// as `MoveTable.Done`.
    pub fn bit(&self, name: &str) -> Option<bool> {
        Some(match name.to_ascii_lowercase().as_str() {
            "done" => self.done,
            "busy" => self.busy,
            "active" => self.active,
            "commandaborted" => self.command_aborted,
            "error" => self.error,
            _ => return None,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flags_put_each_bit_at_its_spec_position() {
        let one = |f: fn(&mut MotionInstructionBits)| {
            let mut b = MotionInstructionBits::default();
            f(&mut b);
            b.flags()
        };
        assert_eq!(one(|b| b.en = true), 1 << 31);
        assert_eq!(one(|b| b.dn = true), 1 << 29);
        assert_eq!(one(|b| b.er = true), 1 << 28);
        assert_eq!(one(|b| b.pc = true), 1 << 27);
        assert_eq!(one(|b| b.ip = true), 1 << 26);
        assert_eq!(one(|b| b.ac = true), 1 << 23);
        assert_eq!(one(|b| b.accel = true), 1 << 1);
        assert_eq!(one(|b| b.decel = true), 1 << 2);
    }

    #[test]
    fn bits_by_name() {
        let b = MotionInstructionBits {
            pc: true,
            ..Default::default()
        };
        assert_eq!(b.bit("PC"), Some(true));
        assert_eq!(b.bit("ip"), Some(false));
        assert_eq!(b.bit("XX"), None);
        for (name, value) in b.bits() {
            assert_eq!(b.bit(name), Some(value), "{name}");
        }
        assert_eq!(b.bits().iter().filter(|(_, v)| *v).count(), 1);
        let o = FbOutputs {
            done: true,
            ..Default::default()
        };
        assert_eq!(o.bit("Done"), Some(true));
        assert_eq!(o.bit("CommandAborted"), Some(false));
        assert_eq!(o.bit("ErrorID"), None);
    }
}
