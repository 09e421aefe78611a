//! MAR (Motion Arm Registration): arms registration event checking on one
//! of an axis' two registration inputs.
//!
//! `MAR(Axis, MotionControl, TriggerCondition, WindowedRegistration,
//! MinimumPosition, MaximumPosition, InputNumber)` (MOTION-RM002, Motion
//! Event Instructions):
//! * Trigger Condition 0 `positive_edge`, 1 `negative_edge`: which
//!   transition of the input is the event.
//! * Windowed Registration 0 `disabled`, 1 `enabled`: with it, an event
//!   whose position lies outside [Minimum, Maximum] is ignored and the
//!   input stays armed (the reference: "automatically rearmed"). On a
//!   linear axis Minimum must be below Maximum for an event to occur; on a
//!   rotary (modulo) axis both lie within the unwind and Minimum > Maximum
//!   is a window across the unwind (Minimum … unwind, 0 … Maximum).
//! * Input Number 1 or 2. Another number is ERR 12 (servo message failure)
//!   with EXERR 3 (invalid value: "Registration input provided is out of
//!   range"), as the reference's extended error table gives it.
//! * `.DN` once armed (in the scan it executes), `.IP` from then until the
//!   event, a newer MAR on the same input or an MDR, `.PC` at the event.
//!   Arming clears `RegEventNStatus` and sets `RegEventNArmedStatus`. At the
//!   event the axis' actual position at the input's transition goes to
//!   `RegistrationNPosition` (a modulo axis': unwound), `RegEventNStatus`
//!   is set and `RegEventNArmedStatus` cleared.
//! * ERR 13 with EXERR 2 to 5 for Trigger Condition, Windowed Registration
//!   or a window bound that is not a finite number.
//!
//! Where the transition comes from is the twin's: a registration sensor of
//! the cell ([`MotionTask::registration_edge`] with the position at the
//! edge, interpolated inside the physics step). Choices the reference
//! leaves open: MAR arms in any axis state (registration watches the
//! feedback, not the drive); a virtual axis can be armed and fires when a
//! sensor is wired to it.

use super::entry::{Instruction, no_load, one_shot};
use crate::catalogue::words::{MAR_TRIGGER, MAR_WINDOW, motion_control, op};
use crate::catalogue::{CallStyle, Format, Kind};
use crate::instruction::{Fault, LogixFault, Refusal, fault};
use crate::registration::{Arm, RegistrationInput, in_window};
use crate::task::{Args, AxisHandle, InstructionHandle, MotionTask};

/// Motion Arm Registration.
pub const MAR: Instruction = Instruction {
    mnemonic: "MAR",
    title: "Motion Arm Registration",
    summary: "arms a registration input: the axis' position at its next edge is latched",
    reference: "Logix motion reference (MOTION-RM002, Motion Event Instructions)",
    style: CallStyle::Positional,
    operands: &[
        op("Axis", "AXIS", Format::Tag, Kind::Axis, 0),
        motion_control(1),
        op(
            "Trigger Condition",
            "BOOLEAN",
            Format::Immediate,
            Kind::Enumeration(MAR_TRIGGER),
            2,
        ),
        op(
            "Windowed Registration",
            "BOOLEAN",
            Format::Immediate,
            Kind::Enumeration(MAR_WINDOW),
            3,
        ),
        op("Minimum Position", "REAL", Format::ImmediateOrTag, Kind::Number, 4),
        op("Maximum Position", "REAL", Format::ImmediateOrTag, Kind::Number, 5),
        op("Input Number", "UINT32", Format::Immediate, Kind::Number, 6),
    ],
    execute,
    check,
    load: no_load,
};

/// MAR's own refusal: an input number other than 1 or 2.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
#[error("registration input {input} is out of range: an axis has inputs 1 and 2 (ERR 12 EXERR 3)")]
pub struct BadInput {
    /// The number given.
    pub input: f64,
}

impl LogixFault for BadInput {
    fn err(&self) -> i32 {
        12
    }
    fn exerr(&self) -> i32 {
        3
    }
}

/// Why MAR (or MDR) fails.
pub type MarError = Refusal<BadInput>;

/// A registration input number, checked: 0 for input 1, 1 for input 2.
///
/// # Errors
/// ERR 12 EXERR 3 for another number.
pub fn input_index(input: f64) -> Result<usize, MarError> {
    if input == 1.0 {
        Ok(0)
    } else if input == 2.0 {
        Ok(1)
    } else {
        Err(Refusal::Instruction(BadInput { input }))
    }
}

/// A validated MAR.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Mar {
    /// The edge and the window.
    pub arm: Arm,
    /// 0 for input 1, 1 for input 2.
    pub input: usize,
}

impl Mar {
    /// Validates the operands.
    ///
    /// # Errors
    /// ERR 13 with EXERR 2 to 5, ERR 12 EXERR 3 (module doc).
    pub fn new(trigger: i32, windowed: i32, min: f64, max: f64, input: f64) -> Result<Mar, MarError> {
        let falling = match trigger {
            0 => false,
            1 => true,
            t => return Err(Refusal::operand(MAR.exerr("Trigger Condition"), f64::from(t))),
        };
        let windowed = match windowed {
            0 => false,
            1 => true,
            w => return Err(Refusal::operand(MAR.exerr("Windowed Registration"), f64::from(w))),
        };
        if !min.is_finite() {
            return Err(Refusal::operand(MAR.exerr("Minimum Position"), min));
        }
        if !max.is_finite() {
            return Err(Refusal::operand(MAR.exerr("Maximum Position"), max));
        }
        Ok(Mar {
            arm: Arm {
                falling,
                window: windowed.then_some((min, max)),
            },
            input: input_index(input)?,
        })
    }

    /// The operands of a call, validated.
    ///
    /// # Errors
    /// As [`Mar::new`].
    pub fn bind(args: &Args<'_>) -> Result<Mar, MarError> {
        Mar::new(
            args.code(2),
            args.code(3),
            args.number(4),
            args.number(5),
            args.number(6),
        )
    }
}

fn execute(task: &mut MotionTask, args: &Args<'_>) -> Result<(), Fault> {
    let control = args.control(1);
    one_shot(task, control, |task| task.mar(args.axis(0), control, args))
}

fn check(_: &MotionTask, args: &Args<'_>) -> Result<(), Fault> {
    Mar::bind(args).map(|_| ()).map_err(fault)
}

impl MotionTask {
    /// MAR on `axis` (module doc).
    ///
    /// # Errors
    /// As [`Mar::new`]; a refused MAR leaves the input as it was.
    pub(crate) fn mar(
        &mut self,
        axis: AxisHandle,
        control: InstructionHandle,
        args: &Args<'_>,
    ) -> Result<(), MarError> {
        self.instruction(control, |task| {
            let mar = Mar::bind(args)?;
            let earlier = task.axes[axis.0 as usize].registration[mar.input].armed;
            if let Some((_, c)) = earlier
                && c != control
            {
                task.motion_bits_mut(c).ip = false;
            }
            let input = &mut task.axes[axis.0 as usize].registration[mar.input];
            input.armed = Some((mar.arm, control));
            input.event = false;
            let bits = task.motion_bits_mut(control);
            bits.dn = true;
            bits.ip = true;
            Ok(())
        })
    }

    /// MDR: disarms input `input` (0 or 1) of `axis`; the MAR that armed it
    /// is no longer in process.
    pub(crate) fn disarm_registration(&mut self, axis: AxisHandle, input: usize) {
        if let Some((_, c)) = self.axes[axis.0 as usize].registration[input].armed.take() {
            self.motion_bits_mut(c).ip = false;
        }
    }

    /// A transition of registration input `input` (1 or 2) of `axis`:
    /// rising or falling, with the axis' actual position at that instant
    /// (axis units, in the frame [`MotionTask::axis_state`] reports). An
    /// armed input whose trigger it matches latches it (inside the window,
    /// if any; outside, it stays armed). Other transitions, and inputs
    /// other than 1 and 2, do nothing.
    pub fn registration_edge(&mut self, axis: AxisHandle, input: u8, rising: bool, position: f64) {
        let Some(k) = (input as usize).checked_sub(1).filter(|k| *k < 2) else {
            return;
        };
        let rotary = self.axes[axis.0 as usize].config.modulo().is_some();
        let shown = match self.axes[axis.0 as usize].config.modulo() {
            Some(m) => m.wrap(position),
            None => position,
        };
        let r = &mut self.axes[axis.0 as usize].registration[k];
        let Some((arm, control)) = r.armed else { return };
        if arm.falling == rising || !position.is_finite() {
            return;
        }
        if arm.window.is_some_and(|w| !in_window(w, shown, rotary)) {
            return;
        }
        r.armed = None;
        r.event = true;
        r.position = shown;
        r.events += 1;
        let bits = self.motion_bits_mut(control);
        bits.ip = false;
        bits.pc = true;
    }

    /// Registration input `input` (1 or 2) of `axis`; `None` for another
    /// number.
    #[must_use]
    pub fn registration(&self, axis: AxisHandle, input: u8) -> Option<&RegistrationInput<InstructionHandle>> {
        let k = (input as usize).checked_sub(1).filter(|k| *k < 2)?;
        Some(&self.axes[axis.0 as usize].registration[k])
    }
}

#[cfg(test)]
#[allow(clippy::unwrap_used)] // a failed unwrap is a failed test
mod tests {
    use super::*;
    use crate::axis::{AxisConfig, AxisKind};
    use crate::task::Arg;

    fn armed(
        task: &mut MotionTask,
        x: AxisHandle,
        mc: InstructionHandle,
        ops: (i64, i64, f64, f64, f64),
    ) -> Result<(), Fault> {
        let args = [
            Arg::Axis(x),
            Arg::Control(mc),
            Arg::Integer(ops.0),
            Arg::Integer(ops.1),
            Arg::Number(ops.2),
            Arg::Number(ops.3),
            Arg::Number(ops.4),
        ];
        MAR.execute(task, &Args::new(&args))
    }

    #[test]
    fn an_armed_input_latches_its_edge_once_and_reports_it() {
        let mut task = MotionTask::new(0.004).unwrap();
        let x = task.add_axis(AxisConfig::new("X", AxisKind::Linear), 0.0).unwrap();
        let mc = task.add_instruction("R");
        armed(&mut task, x, mc, (0, 0, 0.0, 0.0, 1.0)).unwrap();
        let b = task.motion_bits(mc);
        assert!(b.dn && b.ip && !b.pc);
        assert!(task.registration(x, 1).unwrap().armed());
        // A falling edge is not the event; the rising one is.
        task.registration_edge(x, 1, false, 10.0);
        assert!(task.registration(x, 1).unwrap().armed());
        task.registration_edge(x, 1, true, 12.5);
        let r = *task.registration(x, 1).unwrap();
        assert!(r.event && !r.armed());
        assert_eq!(r.position, 12.5);
        let b = task.motion_bits(mc);
        assert!(b.pc && !b.ip);
        // Not armed: later edges change nothing.
        task.registration_edge(x, 1, true, 20.0);
        assert_eq!(task.registration(x, 1).unwrap().position, 12.5);
        assert_eq!(task.registration(x, 1).unwrap().events, 1);
    }

    #[test]
    fn a_window_rearms_outside_it_and_spans_the_unwind_on_a_rotary_axis() {
        let mut task = MotionTask::new(0.004).unwrap();
        let x = task.add_axis(AxisConfig::new("X", AxisKind::Linear), 0.0).unwrap();
        let mc = task.add_instruction("R");
        armed(&mut task, x, mc, (1, 1, 100.0, 200.0, 2.0)).unwrap();
        task.registration_edge(x, 2, false, 50.0);
        assert!(task.registration(x, 2).unwrap().armed(), "outside: rearmed");
        task.registration_edge(x, 2, false, 150.0);
        assert_eq!(task.registration(x, 2).unwrap().position, 150.0);

        let mut rotary = AxisConfig::new("R", AxisKind::Rotary);
        rotary.modulo_period = Some(360.0);
        let r = task.add_axis(rotary, 0.0).unwrap();
        let mc2 = task.add_instruction("R2");
        armed(&mut task, r, mc2, (0, 1, 350.0, 10.0, 1.0)).unwrap();
        task.registration_edge(r, 1, true, 720.0 + 180.0);
        assert!(task.registration(r, 1).unwrap().armed(), "180 is outside 350 … 10");
        task.registration_edge(r, 1, true, 720.0 + 5.0);
        assert_eq!(task.registration(r, 1).unwrap().position, 5.0, "unwound");
    }

    #[test]
    fn operands_are_checked_and_a_newer_mar_supersedes_the_armed_one() {
        let mut task = MotionTask::new(0.004).unwrap();
        let x = task.add_axis(AxisConfig::new("X", AxisKind::Linear), 0.0).unwrap();
        let (a, b) = (task.add_instruction("A"), task.add_instruction("B"));
        let e = armed(&mut task, x, a, (2, 0, 0.0, 0.0, 1.0)).unwrap_err();
        assert_eq!((e.err(), e.exerr()), (13, 2));
        let e = armed(&mut task, x, a, (0, 1, f64::NAN, 0.0, 1.0)).unwrap_err();
        assert_eq!((e.err(), e.exerr()), (13, 4));
        let e = armed(&mut task, x, a, (0, 0, 0.0, 0.0, 3.0)).unwrap_err();
        assert_eq!((e.err(), e.exerr()), (12, 3));
        armed(&mut task, x, a, (0, 0, 0.0, 0.0, 1.0)).unwrap();
        armed(&mut task, x, b, (0, 0, 0.0, 0.0, 1.0)).unwrap();
        assert!(!task.motion_bits(a).ip, "superseded");
        assert!(task.motion_bits(b).ip);
    }
}
