//! The axis faults of a run as they rise: what the summary, the
//! recording's controller log and `twin run -v` report.

use crate::run::Twin;

/// An axis fault that rose in this update (see [`new_axis_faults`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RisenFault {
    /// The exception, as Logix names it.
    pub fault: &'static str,
    /// What it means.
    pub meaning: &'static str,
    /// The exception action the axis took (Logix's word).
    pub action: &'static str,
}

/// The axis faults that rose since `previous` (the axis' `MotionFault`
/// word and whether its position error exceeded the tolerance, as last
/// seen; updated): a soft travel limit, an Excessive Position Error whose
/// action is not `Ignore`. The summary and the recording's controller log
/// list them.
pub fn new_axis_faults(
    twin: &Twin,
    axis: &crate::plant::axes::AxisBinding,
    previous: &mut (u32, bool),
) -> Vec<RisenFault> {
    use planner::servo::{FaultAction, MotionFaults};
    let task = twin.task();
    let now = (
        task.motion_faults(axis.handle).0,
        task.position_error_exceeded(axis.handle),
    );
    let (motion_before, exceeded_before) = std::mem::replace(previous, now);
    let config = task.axis_config(axis.handle);
    let mut faults = Vec::new();
    for (bit, fault, meaning) in [
        (
            MotionFaults::SOFT_TRAVEL_POSITIVE,
            "Soft Travel Limit - Positive",
            "the position passed the positive soft travel limit",
        ),
        (
            MotionFaults::SOFT_TRAVEL_NEGATIVE,
            "Soft Travel Limit - Negative",
            "the position passed the negative soft travel limit",
        ),
    ] {
        if now.0 & bit != 0 && motion_before & bit == 0 {
            faults.push(RisenFault {
                fault,
                meaning,
                action: config.soft_overtravel_action.name(),
            });
        }
    }
    if now.1 && !exceeded_before && config.position_error_action != FaultAction::Ignore {
        faults.push(RisenFault {
            fault: "Excessive Position Error",
            meaning: "the following error exceeded the axis' position error tolerance",
            action: config.position_error_action.name(),
        });
    }
    faults
}
