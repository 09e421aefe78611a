//! MAW (Motion Arm Watch): arms an axis' watch event, which occurs when
//! the axis' actual position crosses the watch position in the direction
//! asked.
//!
//! `MAW(Axis, MotionControl, TriggerCondition, Position)`:
//! * Trigger Condition `forward` (0): the actual position rises through
//!   Position; `reverse` (1): it falls through it. An Immediate operand.
//! * Position, axis units: ERR 13 EXERR 3 when it is not a finite number.
//! * `.DN` once armed (in the scan it executes), `.IP` from then until the
//!   event, a newer MAW on the axis or an MDW, `.PC` at the event. Arming
//!   sets `WatchEventArmedStatus`, clears `WatchEventStatus` and sets
//!   `WatchPosition` to Position. At the event `WatchEventStatus` is set
//!   and `WatchEventArmedStatus` cleared; an event task triggered by
//!   `axis_watch` on the axis runs at the start of the next coarse update.
//!
//! The crossing is looked for once a coarse update, between the actual
//! position of the update before and this one's; where it lies inside the
//! update is interpolated, and the event's time is kept
//! ([`crate::watch::Watch::event_time_s`]). Choices the reference leaves
//! open: `WatchPosition` is the armed set-point (the reference's "current
//! set-point position of an armed watch event"); on a modulo axis the
//! event is the first crossing of any position a whole number of unwinds
//! from Position; MAW arms in any axis state (it watches the feedback),
//! and a position the axis already stands on is not crossed until it
//! leaves and comes back.

use super::entry::{Instruction, no_load, one_shot};
use crate::catalogue::words::{motion_control, op, w};
use crate::catalogue::{CallStyle, Format, Kind, Word};
use crate::instruction::{Fault, NoFault, Refusal, fault};
use crate::task::{Args, AxisHandle, InstructionHandle, MotionTask};

/// MAW's Trigger Condition.
const TRIGGER: &[Word] = &[w("forward", 0), w("reverse", 1)];

/// Motion Arm Watch.
pub const MAW: Instruction = Instruction {
    mnemonic: "MAW",
    title: "Motion Arm Watch",
    summary: "arms a watch event: set when the axis' actual position crosses a position, forward or reverse",
    reference: "Logix motion reference (MOTION-RM002, Motion Event Instructions)",
    style: CallStyle::Positional,
    operands: &[
        op("Axis", "AXIS", Format::Tag, Kind::Axis, 0),
        motion_control(1),
        op(
            "Trigger Condition",
            "BOOLEAN",
            Format::Immediate,
            Kind::Enumeration(TRIGGER),
            2,
        ),
        op("Position", "REAL", Format::ImmediateOrTag, Kind::Number, 3),
    ],
    execute,
    check,
    load: no_load,
};

/// Why MAW fails: ERR 13 with the operand.
pub type MawError = Refusal<NoFault>;

/// A validated MAW: the direction (forward: `true`) and the position.
///
/// # Errors
/// ERR 13 EXERR 2 for a trigger other than 0 and 1, EXERR 3 for a position
/// that is not a finite number.
pub fn validate(trigger: i64, position: f64) -> Result<(bool, f64), MawError> {
    let forward = match trigger {
        0 => true,
        1 => false,
        t => return Err(Refusal::operand(MAW.exerr("Trigger Condition"), t as f64)),
    };
    if !position.is_finite() {
        return Err(Refusal::operand(MAW.exerr("Position"), position));
    }
    Ok((forward, position))
}

fn execute(task: &mut MotionTask, args: &Args<'_>) -> Result<(), Fault> {
    let control = args.control(1);
    one_shot(task, control, |task| {
        task.maw(args.axis(0), control, args.integer(2), args.number(3))
    })
}

fn check(_: &MotionTask, args: &Args<'_>) -> Result<(), Fault> {
    validate(args.integer(2), args.number(3)).map(|_| ()).map_err(fault)
}

impl MotionTask {
    /// MAW on `axis` (module doc).
    ///
    /// # Errors
    /// ERR 13 with EXERR 2 or 3; the watch stays as it was.
    pub(crate) fn maw(
        &mut self,
        axis: AxisHandle,
        control: InstructionHandle,
        trigger: i64,
        position: f64,
    ) -> Result<(), MawError> {
        self.instruction(control, |task| {
            let (forward, position) = validate(trigger, position)?;
            task.disarm_watch(axis);
            let a = &mut task.axes[axis.0 as usize];
            let watch = &mut a.watch;
            watch.armed = Some((forward, control));
            watch.position = position;
            watch.event = false;
            watch.last_actual = a.actual;
            let b = task.motion_bits_mut(control);
            b.dn = true;
            b.ip = true;
            Ok(())
        })
    }

    /// Disarms the watch of `axis`: the MAW that armed it leaves `.IP`.
    pub(crate) fn disarm_watch(&mut self, axis: AxisHandle) {
        if let Some((_, control)) = self.axes[axis.0 as usize].watch.armed.take() {
            self.motion_bits_mut(control).ip = false;
        }
    }

    /// Looks for each armed watch's crossing between the actual position of
    /// the last update and this one's (the last step of an update).
    pub(crate) fn advance_watches(&mut self) {
        let dt_s = self.dt_s;
        let now_s = self.time_s();
        for i in 0..self.axes.len() {
            let a = &mut self.axes[i];
            let (from, to) = (a.watch.last_actual, a.actual);
            a.watch.last_actual = to;
            let Some((forward, control)) = a.watch.armed else {
                continue;
            };
            let period = a.config.modulo().map(|m| m.period());
            let Some(f) = crate::watch::crossing(from, to, a.watch.position, forward, period) else {
                continue;
            };
            a.watch.armed = None;
            a.watch.event = true;
            a.watch.events += 1;
            a.watch.event_time_s = now_s - dt_s * (1.0 - f);
            let b = self.motion_bits_mut(control);
            b.ip = false;
            b.pc = true;
        }
    }

    /// The watch event of `axis`.
    #[must_use]
    pub fn watch(&self, axis: AxisHandle) -> &crate::watch::Watch<InstructionHandle> {
        &self.axes[axis.0 as usize].watch
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::axis::{AxisConfig, AxisKind};
    use crate::instruction::LogixFault;
    use crate::task::instructions::maj::MajOperands;

    #[test]
    fn a_forward_watch_fires_once_at_the_interpolated_crossing() {
        let mut task = MotionTask::new(0.004).unwrap();
        let config = AxisConfig {
            max_velocity: 100.0,
            max_acceleration: 1e6,
            max_deceleration: 1e6,
            ..AxisConfig::new("X", AxisKind::Linear)
        };
        let x = task.add_axis(config, 0.0).unwrap();
        let watch = task.add_instruction("Watch");
        task.maw(x, watch, 1, 0.5).unwrap();
        task.maw(x, watch, 0, 1.0).unwrap();
        assert!(task.watch(x).armed() && !task.watch(x).event && task.watch(x).position == 1.0);
        let jog = task.add_instruction("Jog");
        let o = MajOperands {
            speed: 100.0,
            speed_units: 0,
            accel_rate: 1e6,
            accel_units: 0,
            decel_rate: 1e6,
            decel_units: 0,
            ..MajOperands::default()
        };
        task.maj(x, jog, &o).unwrap();
        // 100 units/s from the first update: 0.4 an update (the first one
        // accelerates within the update: 0.4 less a sliver).
        let mut fired_at = None;
        for k in 1..=10 {
            task.update();
            if task.watch(x).event && fired_at.is_none() {
                fired_at = Some(k);
            }
        }
        assert_eq!(fired_at, Some(3), "1.0 is crossed in the third update");
        let w = task.watch(x);
        assert!(!w.armed() && w.events == 1);
        assert!(task.motion_bits(watch).pc && !task.motion_bits(watch).ip);
        // Crossed at 1.0 between ~0.8 and ~1.2: about 0.010 s.
        assert!((w.event_time_s - 0.010).abs() < 2e-4, "{}", w.event_time_s);
        // A reverse watch behind it does not fire while the axis goes on.
        let mdw = task.add_instruction("Watch2");
        task.maw(x, mdw, 1, 0.5).unwrap();
        for _ in 0..10 {
            task.update();
        }
        assert!(task.watch(x).armed() && task.watch(x).events == 1);
        task.disarm_watch(x);
        assert!(!task.watch(x).armed() && !task.motion_bits(mdw).ip);
    }

    #[test]
    fn operands_out_of_range() {
        assert_eq!(validate(2, 0.0).unwrap_err().exerr(), 2);
        assert_eq!(validate(0, f64::INFINITY).unwrap_err().exerr(), 3);
        assert_eq!(validate(1, -3.0).unwrap(), (false, -3.0));
    }
}
