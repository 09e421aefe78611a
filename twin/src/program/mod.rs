//! The program: what the PLC side executes each coarse update.
//!
//! **In:** the scene's `[[program]]` steps (validated calls and triggers)
//! and the planner its axes were added to. **Out:** instruction calls into
//! the planner ([`planner::task::MotionTask`]), each at the update its
//! trigger makes it due.
//!
//! * [`bind`] reads a positional Logix call's operands through the
//!   instruction catalogue ([`planner::catalogue`]); one file per
//!   instruction family binds them to the planner: [`coord`] (MCLM, MCCM,
//!   MCS), [`mct`] (MCT), [`cam`] (MCCP, MAPC, MRP, MAJ, MAS), [`state`]
//!   (MSO, MSF, MASD, MASR, MAFR, MCSD, MCSR), [`modulo`] (the PLCopen
//!   block MC_MoveModulo, named inputs).
//! * [`steps`] holds the triggers: when each step fires.
//! * [`plc`] is the task engine: `[[tasks]]` of Structured Text programs
//!   scanned periodically, with live tags, timers and faults; its motion
//!   instructions are bound by the same family files, with operand values
//!   read when they execute.
//!
//! # Program steps
//! Each step fires once. A `when` step is armed once the step before it has
//! fired (the list is a sequence, like SFC transitions) and is due `after_s`
//! after the first update at which its bit is TRUE; an `at_s` step is due at
//! its time. A step fires at the first coarse update that starts at or after
//! it is due; due steps set their inputs in list order, just before the
//! planner update. A function-block call sets the inputs it
//! names; the others keep their last value, as PLC block inputs do.
//! A Logix call is one scan of a rung that has just become true (see
//! [`bind`]); `when` may name a control-structure bit (`MC1.PC`) as well as
//! a function-block output (`MoveTable.Done`).

pub mod bind;
pub mod cam;
pub mod coord;
pub mod mct;
pub mod modulo;
pub mod plc;
pub mod state;
pub mod steps;

use crate::scene::Scene;
use crate::st::{Args, Expr};
use bind::{Bind, BindError, LogixContext, LogixStep};
use planner::catalogue::{self, CallStyle, Family};
use planner::task::{FbHandle, InstructionHandle, MotionTask};
use std::path::PathBuf;
use steps::{CompiledStep, StepAction};
use thiserror::Error;

/// Why a program step cannot be bound.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum ProgramError {
    /// A program step cannot be carried out.
    #[error("{scene}:{line}:{column}: program[{index}].{field}: {message}")]
    Step {
        /// Scene file.
        scene: PathBuf,
        /// Line of the operand at fault, or of the `call`/`when` string.
        line: usize,
        /// Column of the operand at fault, or of the string.
        column: usize,
        /// Step index.
        index: usize,
        /// The step's field at fault (`call`, `when`).
        field: &'static str,
        /// What is wrong.
        message: String,
    },
    /// A `[trace] tags` entry that names nothing traceable.
    #[error("{scene}:{line}:{column}: trace.tags[{index}]: {message}")]
    TraceTag {
        /// Scene file.
        scene: PathBuf,
        /// Line of the entry.
        line: usize,
        /// Column of the entry.
        column: usize,
        /// Entry index.
        index: usize,
        /// What is wrong.
        message: String,
    },
    /// A routine of a task cannot be compiled.
    #[error(transparent)]
    Task(#[from] plc::TaskError),
}

/// A function-block instance of the program.
#[derive(Debug, Clone)]
pub struct FbBinding {
    /// Instance tag name.
    pub name: String,
    /// Planner handle.
    pub handle: FbHandle,
}

/// A `MOTION_INSTRUCTION` tag of the program (a Logix control structure).
#[derive(Debug, Clone)]
pub struct InstructionBinding {
    /// Tag name.
    pub name: String,
    /// Planner handle.
    pub handle: InstructionHandle,
}

/// The scene's program bound to the planner.
#[derive(Debug)]
pub struct Program {
    fbs: Vec<FbBinding>,
    instructions: Vec<InstructionBinding>,
    steps: Vec<CompiledStep>,
    plc: plc::Controller,
    traced: Vec<TracedTag>,
}

/// A `[trace] tags` entry bound to what it reads.
#[derive(Debug, Clone)]
pub struct TracedTag {
    /// The reference as written (the trace column's name).
    pub name: String,
    place: plc::ir::Place,
    ty: plc::types::DataType,
}

impl TracedTag {
    /// Whether the tag is a REAL (single precision), whose value the trace
    /// writes rounded to `f32`.
    pub fn single_precision(&self) -> bool {
        self.ty == plc::types::DataType::Real
    }
}

impl Program {
    /// Binds every program step: its call to the planner (creating
    /// instances, control structures and coordinate systems on first use)
    /// and its trigger.
    ///
    /// # Errors
    /// [`ProgramError::Step`] naming the step and what is wrong.
    pub fn bind(scene: &Scene, task: &mut MotionTask) -> Result<Program, ProgramError> {
        let mut instructions = Vec::new();
        let mut fbs = Vec::new();
        let plc = plc::Controller::new(scene, task, &mut instructions, &mut fbs)?;
        let mut program = Program {
            fbs,
            instructions,
            steps: Vec::new(),
            plc,
            traced: Vec::new(),
        };
        for (index, step) in scene.program.iter().enumerate() {
            let fail = |field: &'static str, e: BindError| {
                let at = e
                    .operand
                    .and_then(|i| step.operand_locations.get(i))
                    .unwrap_or(&step.location);
                ProgramError::Step {
                    scene: scene.path.clone(),
                    line: at.line,
                    column: at.column,
                    index,
                    field,
                    message: e.message,
                }
            };
            let action = program
                .bind_call(scene, task, &step.call)
                .map_err(|e| fail("call", e))?;
            let trigger = steps::trigger(&step.trigger, &program.fbs, &program.instructions)
                .map_err(|message| fail("when", BindError::from(message)))?;
            program.steps.push(CompiledStep::new(trigger, action));
        }
        for (index, (name, at)) in scene.trace_tags.iter().enumerate() {
            let (place, ty) = program
                .plc
                .trace_place(name, task, &mut program.instructions, &mut program.fbs)
                .map_err(|message| ProgramError::TraceTag {
                    scene: scene.path.clone(),
                    line: at.line,
                    column: at.column,
                    index,
                    message,
                })?;
            program.traced.push(TracedTag {
                name: name.clone(),
                place,
                ty,
            });
        }
        Ok(program)
    }

    fn bind_call(
        &mut self,
        scene: &Scene,
        task: &mut MotionTask,
        call: &crate::st::Call,
    ) -> Result<StepAction, BindError> {
        match &call.args {
            Args::Positional(operands) => {
                let operands: Vec<Expr> = operands.iter().map(|o| o.value.clone()).collect();
                let mut ctx = bind::LogixContext {
                    scene,
                    values: scene,
                    task,
                    instructions: &mut self.instructions,
                };
                Ok(StepAction::Logix(compile_logix(&call.name.value, &operands, &mut ctx)?))
            }
            Args::Named(_) => {
                let bound = modulo::bind(call, scene, task, &mut self.fbs)?;
                Ok(StepAction::MoveModulo {
                    fb: self.fbs[bound.fb].handle,
                    set: bound.set,
                })
            }
        }
    }

    /// One scan: fires the steps due at the planner's current time, in list
    /// order, then runs the task triggers due (their calls take effect at
    /// the next planner update).
    pub fn scan(&mut self, task: &mut MotionTask) {
        for i in steps::due(&mut self.steps, task, &self.fbs, &self.instructions) {
            self.steps[i].action.execute(task);
        }
        self.plc.scan(task, &mut self.instructions, &mut self.fbs);
    }

    /// The `[trace] tags` entries.
    pub fn traced_tags(&self) -> &[TracedTag] {
        &self.traced
    }

    /// A traced tag's value now.
    pub fn traced(&self, t: &TracedTag, task: &MotionTask) -> plc::types::Value {
        self.plc.peek(&t.place, task)
    }

    /// A traced tag's value now as the number the trace writes: BOOL 0/1,
    /// integers (exact up to 2^53), REAL rounded to single precision.
    pub fn traced_number(&self, t: &TracedTag, task: &MotionTask) -> f64 {
        match self.traced(t, task) {
            plc::types::Value::Bool(b) => f64::from(u8::from(b)),
            plc::types::Value::Int(i) => i as f64,
            plc::types::Value::Real(x) if t.single_precision() => f64::from(x as f32),
            plc::types::Value::Real(x) => x,
        }
    }

    /// The task engine: tag memory, faults, costs.
    pub fn controller(&self) -> &plc::Controller {
        &self.plc
    }

    /// The function-block instances, in the order the program first calls them.
    pub fn fbs(&self) -> &[FbBinding] {
        &self.fbs
    }

    /// The `MOTION_INSTRUCTION` tags the program executes with, in the order
    /// the program first uses them.
    pub fn instructions(&self) -> &[InstructionBinding] {
        &self.instructions
    }
}

/// Binds one positional call to the planner: the catalogue names its
/// family, and the family's file binds it.
///
/// # Errors
/// A message naming the operand at fault, or saying that the instruction is
/// not simulated.
pub fn compile_logix(name: &str, operands: &[Expr], ctx: &mut LogixContext<'_>) -> Result<LogixStep, BindError> {
    let Some(instruction) = catalogue::find(name).filter(|i| i.style == CallStyle::Positional) else {
        return Err(BindError::from(format!(
            "{} is a Logix motion instruction the twin does not simulate (it simulates: {})",
            name.to_ascii_uppercase(),
            catalogue::positional_mnemonics()
        )));
    };
    let mut bind = Bind::new(instruction, operands, ctx)?;
    let bound = match instruction.family {
        Family::Coordinated => coord::bind(&mut bind),
        Family::Transform => mct::bind(&mut bind),
        Family::Cam => cam::bind(&mut bind),
        Family::State => state::bind(&mut bind),
        Family::PlcOpen => Err(format!(
            "{} is a function block: call it on an instance with named inputs",
            instruction.mnemonic
        )),
    };
    bound.map_err(|message| BindError {
        operand: bind.last_operand(),
        message,
    })
}
