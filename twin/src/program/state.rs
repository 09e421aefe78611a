//! Axis and coordinate-system state calls bound to the planner: `MSO`,
//! `MSF`, `MASD`, `MASR`, `MAFR`, `MAH` `(Axis, Motion Control)` and `MCSD`,
//! `MCSR` `(Coordinate System, Motion Control)`. The state rules and their
//! error codes are the planner's ([`planner::servo`]).
//!
//! MSO and MSF take no virtual axis (their Axis operand is an
//! `AXIS_CIP_DRIVE`, as in the Logix manual): naming one is refused when
//! the program is loaded, as the controller's verifier refuses it.

use super::bind::{Bind, LogixStep};
use planner::servo::{AxisType, StateError};
use planner::task::{AxisHandle, InstructionHandle, MotionTask};

/// Binds a state call.
///
/// # Errors
/// A message naming the operand at fault.
pub fn bind(b: &mut Bind<'_, '_>) -> Result<LogixStep, String> {
    let mnemonic = b.instruction.mnemonic;
    if matches!(mnemonic, "MCSD" | "MCSR") {
        let system = b.coordinate_system("Coordinate System")?;
        let control = b.motion_control()?;
        let shutdown = mnemonic == "MCSD";
        return Ok(LogixStep::one_shot(mnemonic, control, move |task| {
            let _ = if shutdown {
                task.mcsd(system, control)
            } else {
                task.mcsr(system, control)
            };
        }));
    }
    let axis = b.axis("Axis")?;
    let config = b.ctx.task.axis_config(axis);
    if matches!(mnemonic, "MSO" | "MSF") && config.axis_type == AxisType::Virtual {
        return Err(format!(
            "Axis {}: {mnemonic} takes an AXIS_CIP_DRIVE; '{}' is a virtual axis (no joint), which is always servo-on",
            config.name, config.name
        ));
    }
    let control = b.motion_control()?;
    type Execute = fn(&mut MotionTask, AxisHandle, InstructionHandle) -> Result<(), StateError>;
    let execute: Execute = match mnemonic {
        "MSO" => MotionTask::mso,
        "MSF" => MotionTask::msf,
        "MASD" => MotionTask::masd,
        "MASR" => MotionTask::masr,
        "MAH" => MotionTask::mah,
        _ => MotionTask::mafr,
    };
    Ok(LogixStep::one_shot(mnemonic, control, move |task| {
        let _ = execute(task, axis, control);
    }))
}
