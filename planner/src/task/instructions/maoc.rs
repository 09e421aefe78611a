//! MAOC (Motion Arm Output Cam): arms an output cam on an axis' execution
//! target: bits of the Output word switched by the cam position, from an
//! `OUTPUT_CAM` array, compensated per bit by an `OUTPUT_COMPENSATION`
//! array. The elements and their checks are [`crate::output_cam`]'s; the
//! arming, the modes and the words are the task's (`task/output_cam.rs`).
//!
//! # Operands (call order = faceplate index = ERR 13's EXERR)
//! `MAOC(Axis, ExecutionTarget, MotionControl, Output, Input, OutputCam,
//! CamStartPosition, CamEndPosition, OutputCompensation, ExecutionMode,
//! ExecutionSchedule, AxisArmPosition, CamArmPosition, Reference)`:
//! * Execution Target: 0 … the axis' `OutputCamExecutionTargets` − 1,
//!   else ERR 35 (Illegal Execution Target).
//! * Output and Input: DINT tags. The cam writes the Output word's bits
//!   its elements name each coarse update; enable bits of type Input read
//!   the Input word.
//! * Output Cam, Output Compensation: arrays from the element named. The
//!   cam uses every element from there to the end of the array (a spare
//!   element is an Inactive one: `LatchType` 0); Output Compensation is
//!   indexed by output bit from there.
//! * Cam Start / End Position: the cam's range, Start below End (ERR 13 on
//!   Cam End Position otherwise, on Cam Start for a number that is not
//!   finite).
//! * Execution Mode `once` (0), `continuous` (1), `persistent` (2);
//!   Execution Schedule `immediate` (0), `pending` (1), `forward only`
//!   (2), `reverse only` (3), `bi-directional` (4); Reference `actual`
//!   (0) or `command` (1) position. Immediate operands.
//! * Axis Arm Position (any finite number) and Cam Arm Position (inside
//!   the range): where the cam is armed, and the cam position there.
//!
//! # Bits
//! `.DN` when MAOC has been initiated (the scan it executes); `.IP` from
//! then until the cam ends (a *once* cam leaving its range), a newer MAOC
//! on the target replaces it (unless pending), or MDOC disarms it; `.PC`
//! when a *once* cam leaves its range. `.SEGMENT` is the element of ERR 36
//! or the output bit of ERR 37. MAOC arms in any axis state (it watches a
//! position); an Output word in use by another target's cam is the
//! program's to keep apart, as on the controller.

use super::entry::{Instruction, no_load, one_shot};
use crate::catalogue::words::{ACTUAL_COMMAND, EXECUTION_MODE, EXECUTION_SCHEDULE, motion_control, op};
use crate::catalogue::{CallStyle, Format, Kind};
use crate::instruction::{Fault, LogixFault, Refusal};
use crate::output_cam::{OutputCam, OutputCamElement, OutputCamFault, OutputCompensation};
use crate::task::engine::{CamMode, CamSchedule, OutputCamRun};
use crate::task::{Args, AxisHandle, InstructionHandle, MotionTask};
use thiserror::Error;

/// Motion Arm Output Cam.
pub const MAOC: Instruction = Instruction {
    mnemonic: "MAOC",
    title: "Motion Arm Output Cam",
    summary: "arms an output cam: Output bits switched at cam positions, with latch and unlatch by position, duration or enable, compensation for device delays, once / continuous / persistent",
    reference: "Logix motion reference (MOTION-RM002, Motion Event Instructions)",
    style: CallStyle::Positional,
    operands: &[
        op("Axis", "AXIS", Format::Tag, Kind::Axis, 0),
        op("Execution Target", "UINT32", Format::Immediate, Kind::Count, 1),
        motion_control(2),
        op("Output", "DINT", Format::Tag, Kind::OutputWord, 3),
        op("Input", "DINT", Format::Tag, Kind::InputWord, 4),
        op("Output Cam", "OUTPUT_CAM", Format::Array, Kind::OutputCams, 5),
        op("Cam Start Position", "REAL", Format::ImmediateOrTag, Kind::Number, 6),
        op("Cam End Position", "REAL", Format::ImmediateOrTag, Kind::Number, 7),
        op(
            "Output Compensation",
            "OUTPUT_COMPENSATION",
            Format::Array,
            Kind::Compensations,
            8,
        ),
        op(
            "Execution Mode",
            "UINT32",
            Format::Immediate,
            Kind::Enumeration(EXECUTION_MODE),
            9,
        ),
        op(
            "Execution Schedule",
            "UINT32",
            Format::Immediate,
            Kind::Enumeration(EXECUTION_SCHEDULE),
            10,
        ),
        op("Axis Arm Position", "REAL", Format::ImmediateOrTag, Kind::Number, 11),
        op("Cam Arm Position", "REAL", Format::ImmediateOrTag, Kind::Number, 12),
        op(
            "Reference",
            "UINT32",
            Format::Immediate,
            Kind::Enumeration(ACTUAL_COMMAND),
            13,
        ),
    ],
    execute,
    check: super::entry::no_check,
    load: no_load,
};

/// MAOC's own refusals.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Error)]
pub enum MaocFault {
    /// ERR 35.
    #[error("illegal execution target {target}: the axis has {targets} (ERR 35)")]
    ExecutionTarget {
        /// The target asked for.
        target: i64,
        /// The axis' `OutputCamExecutionTargets`.
        targets: u32,
    },
    /// ERR 36 or 37.
    #[error("{0}")]
    Cam(OutputCamFault),
}

impl LogixFault for MaocFault {
    fn err(&self) -> i32 {
        match self {
            Self::ExecutionTarget { .. } => 35,
            Self::Cam(c) => c.err(),
        }
    }
    fn segment(&self) -> i32 {
        match self {
            Self::ExecutionTarget { .. } => 0,
            Self::Cam(c) => c.segment(),
        }
    }
}

/// Why MAOC (or MDOC) fails.
pub type MaocError = Refusal<MaocFault>;

/// MAOC's operands after the axis and the control structure.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MaocOperands<'a> {
    /// Execution Target.
    pub target: i64,
    /// The caller's references to the Output and Input tags.
    pub words: (usize, usize),
    /// Output Cam elements (`None`: the element named is outside its
    /// array).
    pub cams: Option<&'a [OutputCamElement]>,
    /// Output Compensation elements.
    pub compensation: Option<&'a [OutputCompensation]>,
    /// Cam Start and End Position.
    pub range: (f64, f64),
    /// Execution Mode, Execution Schedule, Reference codes.
    pub codes: (i64, i64, i64),
    /// Axis Arm and Cam Arm Position.
    pub arm: (f64, f64),
}

impl<'a> MaocOperands<'a> {
    /// The operands of a call, by catalogue position.
    #[must_use]
    pub fn bind(args: &Args<'a>) -> Self {
        Self {
            target: args.integer(1),
            words: (args.reference(3), args.reference(4)),
            cams: args.output_cams(5),
            compensation: args.compensations(8),
            range: (args.number(6), args.number(7)),
            codes: (args.integer(9), args.integer(10), args.integer(13)),
            arm: (args.number(11), args.number(12)),
        }
    }
}

/// Checks the operand range of an execution target.
///
/// # Errors
/// ERR 35 for a target the axis does not have.
pub fn target_index(target: i64, targets: u32) -> Result<usize, MaocError> {
    usize::try_from(target)
        .ok()
        .filter(|t| (*t as u64) < u64::from(targets))
        .ok_or(Refusal::Instruction(MaocFault::ExecutionTarget { target, targets }))
}

fn bad(exerr: i32, value: f64) -> MaocError {
    Refusal::operand(exerr, value)
}

fn execute(task: &mut MotionTask, args: &Args<'_>) -> Result<(), Fault> {
    let control = args.control(2);
    let operands = MaocOperands::bind(args);
    one_shot(task, control, |task| task.maoc(args.axis(0), control, &operands))
}

impl MotionTask {
    /// MAOC on `axis` (module doc).
    ///
    /// # Errors
    /// ERR 13 with EXERR = the operand, ERR 35, 36, 37; the target keeps
    /// what it ran.
    pub(crate) fn maoc(
        &mut self,
        axis: AxisHandle,
        control: InstructionHandle,
        o: &MaocOperands<'_>,
    ) -> Result<(), MaocError> {
        self.instruction(control, |task| {
            let targets = task.axes[axis.0 as usize].config.output_cam_execution_targets;
            let target = target_index(o.target, targets)?;
            let cams = o.cams.filter(|c| !c.is_empty()).ok_or(Refusal::operand_index(5))?;
            let compensation = o.compensation.ok_or(Refusal::operand_index(8))?;
            let (start, end) = o.range;
            if !start.is_finite() {
                return Err(bad(6, start));
            }
            if !(end.is_finite() && end > start) {
                return Err(bad(7, end));
            }
            let mode = match o.codes.0 {
                0 => CamMode::Once,
                1 => CamMode::Continuous,
                2 => CamMode::Persistent,
                m => return Err(bad(9, m as f64)),
            };
            let schedule = match o.codes.1 {
                0 => CamSchedule::Immediate,
                1 => CamSchedule::Pending,
                2 => CamSchedule::ForwardOnly,
                3 => CamSchedule::ReverseOnly,
                4 => CamSchedule::BiDirectional,
                s => return Err(bad(10, s as f64)),
            };
            let actual = match o.codes.2 {
                0 => true,
                1 => false,
                r => return Err(bad(13, r as f64)),
            };
            let (axis_arm, cam_arm) = o.arm;
            if !axis_arm.is_finite() {
                return Err(bad(11, axis_arm));
            }
            if !(start..=end).contains(&cam_arm) && schedule != CamSchedule::Immediate {
                return Err(bad(12, cam_arm));
            }
            let cam = OutputCam::new(cams, compensation, (start, end))
                .map_err(|e| Refusal::Instruction(MaocFault::Cam(e)))?;
            let a = &task.axes[axis.0 as usize];
            let here = if actual { a.actual } else { a.command.position };
            let immediate = matches!(schedule, CamSchedule::Immediate);
            let t = task.output_cam_target(axis, target);
            let pending = schedule == CamSchedule::Pending && t.active.is_some();
            let run = OutputCamRun {
                control,
                latches: Vec::new(),
                mask_hint: cam.mask(),
                cam,
                range: (start, end),
                mode,
                schedule,
                axis_arm: if immediate || schedule == CamSchedule::Pending {
                    0.0
                } else {
                    axis_arm
                },
                cam_arm: if immediate || schedule == CamSchedule::Pending {
                    0.0
                } else {
                    cam_arm
                },
                actual,
                armed: false,
                last_axis: here,
                last_cam: 0.0,
                words: o.words,
            };
            if pending {
                if let Some(old) = t.pending.replace(OutputCamRun {
                    axis_arm: 0.0,
                    cam_arm,
                    ..run
                }) {
                    task.motion_bits_mut(old.control).ip = false;
                }
            } else {
                task.disarm_output_cam(axis, target, false);
                let t = task.output_cam_target(axis, target);
                // The bits the cam that ran drove go off this update.
                let old_mask = if t.release { t.mask } else { 0 };
                t.mask = run.mask_hint | old_mask;
                t.bits = 0;
                t.release = false;
                t.words = run.words;
                t.active = Some(run);
            }
            let b = task.motion_bits_mut(control);
            b.dn = true;
            b.ip = true;
            Ok(())
        })
    }
}

#[cfg(test)]
mod tests;
