//! An instruction's entry: its operands (the catalogue's vocabulary,
//! [`crate::catalogue`]) and the functions that execute, check and prepare
//! a call of it. Each instruction's module under `task/instructions/`
//! defines its entry; the registry ([`super::INSTRUCTIONS`]) lists them.

use crate::catalogue::{CallStyle, Operand, faceplate_of, str_eq};
use crate::instruction::{Fault, LogixFault, fault};
use crate::task::{Args, InstructionHandle, MotionTask};

/// Runs a call on the motion task with its operand values (see
/// [`Instruction::execute`]).
pub type Execute = fn(&mut MotionTask, &Args<'_>) -> Result<(), Fault>;

/// Validates a call whose operands are all known (see
/// [`Instruction::check`]).
pub type Check = fn(&MotionTask, &Args<'_>) -> Result<(), Fault>;

/// Prepares the motion task for a call at load (see [`Instruction::load`]).
pub type Load = fn(&mut MotionTask, &Args<'_>);

/// One instruction the product accepts: its operands, and what it does.
#[derive(Clone, Copy)]
pub struct Instruction {
    /// Mnemonic or block type (`MCCM`, `MC_MoveModulo`).
    pub mnemonic: &'static str,
    /// The manual's title.
    pub title: &'static str,
    /// What it does, in one line (the docs' table).
    pub summary: &'static str,
    /// Where its behaviour is specified: a document of `shared/spec/`
    /// (`000_…`) or the Logix manual whose rules it follows.
    pub reference: &'static str,
    /// How it is called.
    pub style: CallStyle,
    /// Operands in call order.
    pub operands: &'static [Operand],
    /// Executes a call: the operands' values in call order ([`Args`], for
    /// a named call only the inputs it names). The instruction writes its
    /// control structure (`.EN`, `.DN`, `.ER` with ERR and EXERR) or its
    /// block outputs, as on the controller, and returns the refusal too.
    pub execute: Execute,
    /// Runs the instruction's validation on a call whose operands are all
    /// known when the program loads (constants, and the tags the program
    /// names), against the task's configuration, without executing it:
    /// the refusal it would give, whatever the state it runs in.
    pub check: Check,
    /// What a call of it prepares in the motion task when the program
    /// loads (with its tag operands; numbers are not known yet).
    pub load: Load,
}

impl std::fmt::Debug for Instruction {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Instruction")
            .field("mnemonic", &self.mnemonic)
            .field("style", &self.style)
            .field("operands", &self.operands.len())
            .finish_non_exhaustive()
    }
}

impl PartialEq for Instruction {
    /// Instructions are the same when their mnemonics are.
    fn eq(&self, other: &Self) -> bool {
        self.mnemonic == other.mnemonic
    }
}

/// A [`Instruction::check`] that finds nothing to refuse.
pub fn no_check(_: &MotionTask, _: &Args<'_>) -> Result<(), Fault> {
    Ok(())
}

/// A [`Instruction::load`] that prepares nothing.
pub fn no_load(_: &mut MotionTask, _: &Args<'_>) {}

impl Instruction {
    /// A Logix instruction (operands by position) with nothing to check
    /// or prepare when the program loads: the axis- and system-state
    /// instructions, whose operands are tags.
    pub const fn positional(
        mnemonic: &'static str,
        title: &'static str,
        summary: &'static str,
        reference: &'static str,
        operands: &'static [Operand],
        execute: Execute,
    ) -> Instruction {
        Instruction {
            mnemonic,
            title,
            summary,
            reference,
            style: CallStyle::Positional,
            operands,
            execute,
            check: no_check,
            load: no_load,
        }
    }

    /// Executes a call with its operand values, in catalogue order: the
    /// one way a program runs an instruction. The instruction writes its
    /// control structure or block outputs, and says why it refused, if it
    /// did.
    ///
    /// # Errors
    /// The instruction's refusal ([`crate::instruction::LogixFault`]: ERR, EXERR, SEGMENT and
    /// the sentence), also written in its control structure.
    ///
    /// # Examples
    /// ```
    /// use planner::axis::{AxisConfig, AxisKind};
    /// use planner::task::instructions::mrp::MRP;
    /// use planner::task::{Arg, Args, MotionTask};
    /// let mut task = MotionTask::new(0.004).unwrap();
    /// let x = task.add_axis(AxisConfig::new("X", AxisKind::Linear), 0.0).unwrap();
    /// let mc = task.add_instruction("MC1");
    /// // MRP(X, MC1, relative, command, 5.0)
    /// let args = [Arg::Axis(x), Arg::Control(mc), Arg::Integer(1), Arg::Integer(1), Arg::Number(5.0)];
    /// MRP.execute(&mut task, &Args::new(&args)).unwrap();
    /// assert_eq!(task.axis_state(x).command_position, 5.0);
    /// // Type 7 is out of range: ERR 13 with the Type operand's faceplate index.
    /// let bad = [Arg::Axis(x), Arg::Control(mc), Arg::Integer(7), Arg::Integer(1), Arg::Number(5.0)];
    /// let e = MRP.execute(&mut task, &Args::new(&bad)).unwrap_err();
    /// assert_eq!((e.err(), e.exerr()), (13, 2));
    /// assert_eq!(e.meaning(), Some("parameter out of range"));
    /// assert!(task.motion_bits(mc).er);
    /// ```
    pub fn execute(&self, task: &mut MotionTask, args: &Args<'_>) -> Result<(), Fault> {
        (self.execute)(task, args)
    }

    /// Runs the validation on a call whose operands are all known when the
    /// program loads ([`Instruction::check`](#structfield.check)), without
    /// executing it.
    ///
    /// # Errors
    /// The refusal the call would get whenever it executes.
    pub fn check(&self, task: &MotionTask, args: &Args<'_>) -> Result<(), Fault> {
        (self.check)(task, args)
    }

    /// Prepares the task for a call when the program loads
    /// ([`Instruction::load`](#structfield.load)).
    pub fn prepare(&self, task: &mut MotionTask, args: &Args<'_>) {
        (self.load)(task, args);
    }

    /// The operand called `name` (case-insensitive) with its call position.
    pub fn operand(&self, name: &str) -> Option<(usize, &'static Operand)> {
        self.operands
            .iter()
            .enumerate()
            .find(|(_, o)| o.name.eq_ignore_ascii_case(name))
    }

    /// The faceplate index (ERR 13's EXERR) of the operand called `name`,
    /// exactly as the catalogue spells it. Evaluated at compile time where
    /// it is used in a constant; a name the instruction lacks fails the
    /// build there.
    pub const fn exerr(&self, name: &str) -> i32 {
        match self.faceplate_of(name) {
            Some(index) => index,
            None => panic!("the instruction has no operand of that name"),
        }
    }

    /// The call position of the operand called `name`, exactly as the
    /// catalogue spells it: the index its value has in [`Args`]. Evaluated
    /// at compile time where it is used in a constant; a name the
    /// instruction lacks fails the build there.
    pub const fn index(&self, name: &str) -> usize {
        let mut i = 0;
        while i < self.operands.len() {
            if str_eq(self.operands[i].name, name) {
                return i;
            }
            i += 1;
        }
        panic!("the instruction has no operand of that name")
    }

    /// The faceplate index of the operand called `name` (exact spelling),
    /// `None` when the instruction has no such operand.
    pub const fn faceplate_of(&self, name: &str) -> Option<i32> {
        faceplate_of(self.operands, name)
    }

    /// The operand whose faceplate index is `exerr` (the EXERR of its
    /// ERR 13), with its call position.
    pub fn operand_at_faceplate(&self, exerr: i32) -> Option<(usize, &'static Operand)> {
        self.operands
            .iter()
            .enumerate()
            .find(|(_, o)| o.faceplate == exerr && exerr >= 0)
    }

    /// `ERR 13 (parameter out of range) EXERR 15 (Decel Jerk)`: a refusal's
    /// codes with the ERR's meaning, and for ERR 13 the operand its EXERR
    /// names.
    pub fn refusal_codes(&self, err: i32, exerr: i32) -> String {
        let codes = crate::catalogue::err_text(err, exerr);
        match self.operand_at_faceplate(exerr) {
            Some((_, operand)) if err == 13 => format!("{codes} ({})", operand.name),
            _ => codes,
        }
    }

    /// The operand names in call order, comma separated.
    pub fn operand_names(&self) -> String {
        let names: Vec<&str> = self.operands.iter().map(|o| o.name).collect();
        names.join(", ")
    }
}

/// One execution of a Logix instruction on a one-shot rung: the
/// instruction's `run`, then its rung goes false from the next scan
/// (`MotionTask::rung_false_next_scan`); its refusal as a [`Fault`].
pub(crate) fn one_shot<E: LogixFault>(
    task: &mut MotionTask,
    control: InstructionHandle,
    run: impl FnOnce(&mut MotionTask) -> Result<(), E>,
) -> Result<(), Fault> {
    let result = run(task);
    task.rung_false_next_scan(control);
    result.map_err(fault)
}
