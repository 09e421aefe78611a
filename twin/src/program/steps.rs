//! `[[program]]` steps: when each fires (its trigger) and the call it
//! executes, compiled by the one compiler in the controller's scope. The
//! rules are in the [`super`] module doc.

use super::bindings::Env;
use super::compile::{self, Compiler};
use super::exec::{self, Scratch};
use super::ir::{CExpr, MotionCall};
use super::memory::Memory;
use crate::scene::{Dialect, Scene, Trigger};
use planner::task::MotionTask;

/// A compiled step and its firing state.
#[derive(Debug, Clone)]
pub struct CompiledStep {
    trigger: CompiledTrigger,
    /// The call it executes.
    pub call: MotionCall,
    /// Its index in the scene's `[[program]]`.
    pub index: usize,
    fire_at_s: Option<f64>,
    fired: bool,
}

/// When a step fires.
#[derive(Debug, Clone)]
pub enum CompiledTrigger {
    /// At a time, s.
    At(f64),
    /// `delay_s` after its condition is first TRUE (once armed).
    When {
        /// The condition.
        condition: CExpr,
        /// Delay, s.
        delay_s: f64,
    },
}

/// Compiles every step of the scene: its call, then its `when`, in order
/// (a `when` may read the outputs of the instances earlier calls bound).
///
/// # Errors
/// The first error, pointing into the step's string.
pub fn compile(scene: &Scene, mem: &Memory, env: &mut Env<'_, '_>) -> Result<Vec<CompiledStep>, compile::Error> {
    let mut steps = Vec::with_capacity(scene.program.len());
    for (index, step) in scene.program.iter().enumerate() {
        let field = |f: &str| format!("program[{index}].{f}");
        let warned = env.bindings.warnings.len();
        let mut compiler = Compiler::new(mem, None, &[], Dialect::Logix, env, false);
        let call = compiler
            .instruction_call(&step.call)
            .map_err(|d| Box::new((*d).in_field(field("call"))))?;
        let trigger = match &step.trigger {
            Trigger::At { time_s } => CompiledTrigger::At(*time_s),
            Trigger::When { condition, delay_s } => CompiledTrigger::When {
                condition: compiler
                    .condition(condition)
                    .map_err(|d| Box::new((*d).in_field(field("when"))))?,
                delay_s: *delay_s,
            },
        };
        for w in &mut env.bindings.warnings[warned..] {
            w.field = Some(field("call"));
        }
        steps.push(CompiledStep {
            trigger,
            call,
            index,
            fire_at_s: None,
            fired: false,
        });
    }
    Ok(steps)
}

/// Fires the steps due now (module doc of [`super`]): every trigger is
/// read first, then the due steps execute their calls in list order. A
/// refusal of an operand's value (ERR 13) is kept in `refusals`.
pub fn fire(
    steps: &mut [CompiledStep],
    mem: &mut Memory,
    scratch: &mut Scratch,
    task: &mut MotionTask,
    refusals: &mut Vec<String>,
) {
    let eps = 1e-9 * task.dt_s();
    let now_s = task.time_s();
    let mut due = Vec::new();
    for i in 0..steps.len() {
        let armed = i == 0 || steps[i - 1].fired;
        let step = &mut steps[i];
        if step.fired {
            continue;
        }
        match &step.trigger {
            CompiledTrigger::At(t) => step.fire_at_s = Some(*t),
            CompiledTrigger::When { condition, delay_s } => {
                if armed && step.fire_at_s.is_none() && exec::evaluate(mem, task, scratch, condition).truthy() {
                    step.fire_at_s = Some(now_s + delay_s);
                }
            }
        }
        if let Some(t) = step.fire_at_s
            && t <= now_s + eps
        {
            step.fired = true;
            due.push(i);
        }
    }
    for i in due {
        let step = &steps[i];
        if let Err(fault) = exec::call(mem, task, scratch, &step.call)
            && fault.err() == 13
        {
            refusals.push(format!(
                "{} (program[{}]): {}: {fault}",
                step.call.instruction.mnemonic,
                step.index,
                planner::catalogue::err_text(fault.err(), fault.exerr())
            ));
        }
    }
}
