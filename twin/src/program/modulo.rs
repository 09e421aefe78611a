//! MC_MoveModulo calls bound to the planner: a named call on an instance
//! tag, `Move(Axis := Table, Execute := TRUE, Position := 90.0, …)`.
//!
//! A call sets the inputs it names; the others keep their last value, as
//! PLC block inputs do. The instance is created on its first call, which
//! must name its axis; an instance drives one axis. Inputs and their
//! enumeration words come from [`planner::catalogue::MC_MOVE_MODULO`].
//! `Options` (ST_MoveOptions) is set where the instance is declared — its
//! `[[tags]]` entry's `options = { IgnorePositionMonitoring = true }`, as an
//! IEC declaration initialises a block's input — and a call naming it is
//! refused with a message saying so.

use super::FbBinding;
use super::bind::{BindError, axis_named, number};
use crate::scene::{BaseType, FunctionBlock, Scene};
use crate::st::{Args, Call, Expr};
use planner::catalogue::{Kind, MC_MOVE_MODULO, Operand};
use planner::modulo::{McBufferMode, McDirection, MoveModuloInputs};
use planner::task::{AxisHandle, MotionTask};

/// One MC_MoveModulo input with its value, as a call names it.
#[derive(Debug, Clone, Copy)]
pub enum Setting {
    /// `Execute`.
    Execute(bool),
    /// `Position`, axis units.
    Position(f64),
    /// `Velocity`, axis units/s.
    Velocity(f64),
    /// `Acceleration`, axis units/s².
    Acceleration(f64),
    /// `Deceleration`, axis units/s².
    Deceleration(f64),
    /// `Jerk`, axis units/s³.
    Jerk(f64),
    /// `Direction`.
    Direction(McDirection),
    /// `BufferMode`.
    BufferMode(McBufferMode),
}

impl Setting {
    /// Sets this input in `inputs`.
    pub fn apply(self, inputs: &mut MoveModuloInputs) {
        match self {
            Setting::Execute(b) => inputs.execute = b,
            Setting::Position(x) => inputs.position = x,
            Setting::Velocity(x) => inputs.velocity = x,
            Setting::Acceleration(x) => inputs.acceleration = x,
            Setting::Deceleration(x) => inputs.deceleration = x,
            Setting::Jerk(x) => inputs.jerk = x,
            Setting::Direction(d) => inputs.direction = d,
            Setting::BufferMode(m) => inputs.buffer_mode = m,
        }
    }
}

/// A bound call: the instance (index into the program's instances) and
/// the inputs it sets.
pub(super) struct BoundCall {
    pub fb: usize,
    pub set: Vec<Setting>,
}

/// Binds one named call to its instance (created on its first call).
///
/// # Errors
/// A message naming the input at fault.
pub(super) fn bind(
    call: &Call,
    scene: &Scene,
    task: &mut MotionTask,
    fbs: &mut Vec<FbBinding>,
) -> Result<BoundCall, BindError> {
    let name = &call.name.value;
    let tag = scene
        .tag(name)
        .ok_or_else(|| format!("'{name}' is not a declared tag"))?;
    let block = match tag.ty.base {
        BaseType::FunctionBlock(fb) => fb,
        _ => {
            return Err(format!("'{name}' is a {} tag, not a function block", tag.ty.base.name()).into());
        }
    };
    if block != FunctionBlock::MoveModulo {
        let message = format!(
            "'{name}' is an {} instance; the twin runs the function block MC_MoveModulo",
            block.name()
        );
        return Err(message.into());
    }
    let Args::Named(args) = &call.args else {
        return Err(format!("'{name}' is a function block: call it with named inputs (Input := value)").into());
    };
    let mut axis = None;
    let mut set = Vec::new();
    for (i, (input, value)) in args.iter().enumerate() {
        let at = |message: String| BindError {
            operand: Some(i),
            message,
        };
        let Some((_, spec)) = MC_MOVE_MODULO.operand(&input.value) else {
            return Err(at(format!(
                "MC_MoveModulo has no input '{}' (inputs: {})",
                input.value,
                MC_MOVE_MODULO.operand_names()
            )));
        };
        match setting(spec, &value.value, scene, task).map_err(at)? {
            Input::Axis(a) => axis = Some(a),
            Input::Set(s) => set.push(s),
        }
    }
    let index = instance(name, &tag.name, axis, task, fbs)?;
    let handle = fbs[index].handle;
    let inputs = MoveModuloInputs {
        options: tag.move_options,
        ..task.move_modulo_inputs(handle)
    };
    task.set_move_modulo_inputs(handle, inputs);
    Ok(BoundCall { fb: index, set })
}

enum Input {
    Axis(AxisHandle),
    Set(Setting),
}

/// The value one input is given.
fn setting(spec: &Operand, v: &Expr, scene: &Scene, task: &MotionTask) -> Result<Input, String> {
    let what = spec.name;
    let num = || number(v, scene).ok_or_else(|| format!("{what} := {v}: expected a number or a REAL tag with a value"));
    let word = || {
        let code = match v {
            Expr::Ident(w) => spec.code_of(w),
            Expr::Integer(i) => Some(*i).filter(|i| spec.has_code(*i)),
            _ => None,
        };
        code.ok_or_else(|| format!("{what} := {v}: expected one of {}", spec.word_list()))
    };
    Ok(Input::Set(match (what, spec.kind) {
        ("Axis", _) => {
            let Expr::Ident(a) = v else {
                return Err(format!("Axis := {v}: expected an axis name"));
            };
            let handle = axis_named(task, a).ok_or_else(|| format!("Axis := {a}: no axis of that name in [[axes]]"))?;
            return Ok(Input::Axis(handle));
        }
        ("Options", _) => {
            return Err(
                "Options: set the instance's ST_MoveOptions where it is declared, e.g. options = { IgnorePositionMonitoring = true } in its [[tags]] entry; a call cannot change them"
                    .to_string(),
            );
        }
        ("Execute", _) => match v {
            Expr::Bool(b) => Setting::Execute(*b),
            _ => return Err(format!("Execute := {v}: expected TRUE or FALSE")),
        },
        ("Position", _) => Setting::Position(num()?),
        ("Velocity", _) => Setting::Velocity(num()?),
        ("Acceleration", _) => Setting::Acceleration(num()?),
        ("Deceleration", _) => Setting::Deceleration(num()?),
        ("Jerk", _) => Setting::Jerk(num()?),
        ("Direction", Kind::Enumeration(_)) => Setting::Direction(
            McDirection::from_code(word()?).ok_or_else(|| format!("Direction := {v}: not simulated"))?,
        ),
        _ => Setting::BufferMode(
            McBufferMode::from_code(word()?).ok_or_else(|| format!("BufferMode := {v}: not simulated"))?,
        ),
    }))
}

/// The index of instance `name`, created on its first call.
fn instance(
    name: &str,
    declared: &str,
    axis: Option<AxisHandle>,
    task: &mut MotionTask,
    fbs: &mut Vec<FbBinding>,
) -> Result<usize, String> {
    if let Some(i) = fbs.iter().position(|f| f.name.eq_ignore_ascii_case(name)) {
        if axis.is_some_and(|new| new != task.fb_axis(fbs[i].handle)) {
            return Err(format!(
                "'{name}' was called with another axis before; an instance drives one axis"
            ));
        }
        return Ok(i);
    }
    let axis = axis.ok_or_else(|| format!("the first call of '{name}' must name its axis (Axis := ...)"))?;
    let handle = task.add_move_modulo(declared.to_string(), axis);
    fbs.push(FbBinding {
        name: declared.to_string(),
        handle,
    });
    Ok(fbs.len() - 1)
}
