//! Program steps: when each fires (its trigger) and what it does (its
//! action). The rules are in the [`super`] module doc.

use super::bind::LogixStep;
use super::modulo::Setting;
use super::{FbBinding, InstructionBinding};
use crate::scene::Trigger;
use crate::st::Expr;
use planner::instruction::{FbOutputs, MotionInstructionBits};
use planner::task::{FbHandle, MotionTask};

/// What a step does when it fires.
#[derive(Debug, Clone)]
pub enum StepAction {
    /// Sets MC_MoveModulo inputs of an instance.
    MoveModulo {
        /// The instance.
        fb: FbHandle,
        /// The inputs the call names.
        set: Vec<Setting>,
    },
    /// One scan of a Logix call's rung.
    Logix(LogixStep),
}

impl StepAction {
    /// Carries the action out on the planner.
    pub fn execute(&self, task: &mut MotionTask) {
        match self {
            StepAction::MoveModulo { fb, set } => {
                let mut inputs = task.move_modulo_inputs(*fb);
                for setting in set {
                    setting.apply(&mut inputs);
                }
                task.set_move_modulo_inputs(*fb, inputs);
            }
            StepAction::Logix(step) => (step.run)(&mut *task),
        }
    }
}

/// A bound step and its firing state.
#[derive(Debug, Clone)]
pub struct CompiledStep {
    trigger: CompiledTrigger,
    /// What it does.
    pub action: StepAction,
    fire_at_s: Option<f64>,
    fired: bool,
}

impl CompiledStep {
    /// A step that has not fired yet.
    pub fn new(trigger: CompiledTrigger, action: StepAction) -> Self {
        CompiledStep {
            trigger,
            action,
            fire_at_s: None,
            fired: false,
        }
    }
}

/// When a step fires.
#[derive(Debug, Clone)]
pub enum CompiledTrigger {
    /// At a time, s.
    At(f64),
    /// `delay_s` after a bit is first TRUE (once armed).
    When {
        /// Whose bit.
        source: BitSource,
        /// The bit's name (`Done`, `PC`, …).
        output: String,
        /// Delay, s.
        delay_s: f64,
    },
}

/// Whose bit a `when` condition reads.
#[derive(Debug, Clone, Copy)]
pub enum BitSource {
    /// A function-block instance (index into the program's instances).
    Fb(usize),
    /// A control structure (index into the program's control structures).
    Instruction(usize),
}

/// Binds a step's trigger to the instances and control structures bound
/// so far.
///
/// # Errors
/// A message when the condition names no such bit.
pub fn trigger(
    trigger: &Trigger,
    fbs: &[FbBinding],
    instructions: &[InstructionBinding],
) -> Result<CompiledTrigger, String> {
    let (condition, delay_s) = match trigger {
        Trigger::At { time_s } => return Ok(CompiledTrigger::At(*time_s)),
        Trigger::When { condition, delay_s } => (condition, *delay_s),
    };
    let (tag, output) = match condition {
        Expr::Member(base, output) => match base.as_ref() {
            Expr::Ident(tag) => (tag.clone(), output.clone()),
            _ => return Err(format!("when = \"{condition}\": expected <instance>.<output>")),
        },
        _ => {
            return Err(format!(
                "when = \"{condition}\": expected <instance>.<output>, e.g. MoveTable.Done"
            ));
        }
    };
    let source = if let Some(fb) = fbs.iter().position(|f| f.name.eq_ignore_ascii_case(&tag)) {
        if FbOutputs::default().bit(&output).is_none() {
            return Err(format!(
                "when = \"{condition}\": '{output}' is not a function-block output (Done, Busy, Active, CommandAborted, Error)"
            ));
        }
        BitSource::Fb(fb)
    } else if let Some(i) = instructions.iter().position(|b| b.name.eq_ignore_ascii_case(&tag)) {
        if MotionInstructionBits::default().bit(&output).is_none() {
            return Err(format!(
                "when = \"{condition}\": '{output}' is not a control-structure bit (EN, DN, ER, IP, AC, PC, ACCEL, DECEL)"
            ));
        }
        BitSource::Instruction(i)
    } else {
        return Err(format!(
            "when = \"{condition}\": '{tag}' is not an instance or control structure used by an earlier program step"
        ));
    };
    Ok(CompiledTrigger::When {
        source,
        output,
        delay_s,
    })
}

/// Marks the steps due now as fired and returns them, in list order.
pub fn due(
    steps: &mut [CompiledStep],
    task: &MotionTask,
    fbs: &[FbBinding],
    instructions: &[InstructionBinding],
) -> Vec<usize> {
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
            CompiledTrigger::When {
                source,
                output,
                delay_s,
            } => {
                let bit = match *source {
                    BitSource::Fb(fb) => task.outputs(fbs[fb].handle).bit(output),
                    BitSource::Instruction(i) => task.motion_bits(instructions[i].handle).bit(output),
                };
                if armed && step.fire_at_s.is_none() && bit.unwrap_or(false) {
                    step.fire_at_s = Some(now_s + delay_s);
                }
            }
        }
        if let Some(t) = step.fire_at_s
            && t <= now_s + eps
        {
            due.push(i);
            step.fired = true;
        }
    }
    due
}
