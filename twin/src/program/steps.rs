//! `[[program]]` steps at run time: when each fires (its trigger) and the
//! call it executes, as [`crate::program::compile::scene::steps`] compiled them. The
//! rules are in the [`super`] module doc.

use super::exec::{self, Scratch};
use super::ir::{CompiledStep, StepTrigger};
use super::memory::Memory;
use planner::task::MotionTask;

/// A step and its firing state.
#[derive(Debug, Clone)]
pub struct Step {
    /// What it is.
    pub compiled: CompiledStep,
    fire_at_s: Option<f64>,
    fired: bool,
}

impl Step {
    /// A step not fired yet.
    #[must_use]
    pub fn new(compiled: CompiledStep) -> Step {
        Step {
            compiled,
            fire_at_s: None,
            fired: false,
        }
    }
}

/// Fires the steps due now (module doc of [`super`]): every trigger is
/// read first, then the due steps execute their calls in list order. A
/// refusal of an operand's value (ERR 13) is kept in `refusals`.
pub fn fire(
    steps: &mut [Step],
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
        match &step.compiled.trigger {
            StepTrigger::At(t) => step.fire_at_s = Some(*t),
            StepTrigger::When { condition, delay_s } => {
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
        let step = &steps[i].compiled;
        if let Err(fault) = exec::call(mem, task, scratch, &step.call)
            && fault.err() == 13
        {
            refusals.push(format!(
                "{} (program[{}]): {}",
                step.call.instruction.mnemonic,
                step.index,
                exec::motion::refusal_text(&step.call, &fault)
            ));
        }
    }
}
