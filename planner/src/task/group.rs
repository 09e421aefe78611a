//! The motion group: one `MOTION_GROUP` per controller, every axis of the
//! task in it. MGS stops the group, MGSD shuts it down until MGSR, MGSP
//! latches every axis' positions (`task/instructions/mgs.rs` …); the
//! group's status words are read from here.
//!
//! # Stops (MGS)
//! Each axis stops by the Stop Mode asked, or, for *programmed*, by its own
//! `ProgrammedStopMode` ([`ProgrammedStopMode`]):
//! * **Fast Stop**: every motion process on the axis ends (jogs, moves,
//!   cams, gearing, coordinated motion and transforms) and the command
//!   ramps to rest at the axis' `MaximumDeceleration`; the servo stays on,
//!   ready for the next move.
//! * **Fast Disable**: the same ramp, then the drive is disabled (servo
//!   off: MSO again) in the update the axis comes to rest.
//! * **Hard Disable**: the drive is disabled at once.
//! * **Fast Shutdown**: the ramp, then the axis is shut down (MGSR or MASR
//!   to reset it).
//! * **Hard Shutdown**: the axis is shut down at once.
//!
//! A servo-off, faulted or shut-down axis is already still: a stop leaves
//! its state alone, except that a shutdown mode shuts it down, and it does
//! not hold back `.PC` (its joint may still coast on a physics plant).
//! Fast Disable and Fast Shutdown disable the drive when the command
//! ramp has brought the command to rest; a joint that lags its command
//! coasts from there. A virtual
//! axis has no drive to disable: Fast and Hard Disable ramp it to rest as
//! Fast Stop does (as MSF leaves a virtual axis on). An inhibited axis is
//! left alone. The MGS's `.IP` is set while the group stops and `.PC` in
//! the update every axis is at rest (no stop ramp, command velocity 0, no
//! disable still to come).
//!
//! Choices where the manual is silent: the axes of a coordinate system
//! ramp each on its own (not along the path), as the controller's
//! programmed stop does; a second MGS while one is in process takes over
//! (the first keeps `.IP` clear, without `.PC`).
//!
//! # Status words
//! * `GroupStatus`: bit 0 `InhibStatus` (the group is inhibited: never, the
//!   twin's group cannot be), bit 1 `GroupSynced` (always: the twin's
//!   group needs no time synchronisation), bit 2 `AxisInhibitStatus` (an
//!   axis of the group is inhibited).
//! * `MotionFault`: bits 0–1 are connection faults the twin has none of: 0.
//! * `ServoFault`: bit 0 `POtrvlFault` / bit 1 `NOtrvlFault` when an axis
//!   has its positive / negative soft travel limit fault, bit 2
//!   `PosErrorFault` when an axis has an Excessive Position Error.
//! * `GroupFault`: overlap, CST loss and task loading are not simulated: 0.
//! * `AxisFault`: the bits 0–2 (physical, module, configuration) of the
//!   axes' `AxisFault` words, or-ed.

use super::MotionTask;
use crate::axis::ProgrammedStopMode;
use crate::servo::{AxisFaults, AxisType};
use crate::task::engine::Power;
use crate::task::handles::{AxisHandle, InstructionHandle};

/// The group's status words ([module doc](self)).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct GroupStatus {
    /// `GroupStatus`.
    pub group_status: u32,
    /// `MotionFault`.
    pub motion_fault: u32,
    /// `ServoFault`.
    pub servo_fault: u32,
    /// `GroupFault`.
    pub group_fault: u32,
    /// `AxisFault`.
    pub axis_fault: u32,
}

impl GroupStatus {
    /// `GroupStatus` bit 0.
    pub const INHIB_STATUS: u32 = 1 << 0;
    /// `GroupStatus` bit 1.
    pub const GROUP_SYNCED: u32 = 1 << 1;
    /// `GroupStatus` bit 2.
    pub const AXIS_INHIBIT_STATUS: u32 = 1 << 2;
    /// `ServoFault` bit 0.
    pub const POS_OVERTRAVEL: u32 = 1 << 0;
    /// `ServoFault` bit 1.
    pub const NEG_OVERTRAVEL: u32 = 1 << 1;
    /// `ServoFault` bit 2.
    pub const POS_ERROR: u32 = 1 << 2;
}

/// What a group stop does to one axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GroupStop {
    /// Stop Mode *programmed*: each axis' own mode.
    Programmed,
    /// Every axis Fast Stop.
    FastStop,
    /// Every axis Fast Disable.
    FastDisable,
}

impl MotionTask {
    /// The group's status words.
    pub fn group_status(&self) -> GroupStatus {
        let mut s = GroupStatus {
            group_status: GroupStatus::GROUP_SYNCED,
            ..GroupStatus::default()
        };
        for a in &self.axes {
            if a.config.inhibited {
                s.group_status |= GroupStatus::AXIS_INHIBIT_STATUS;
            }
            let m = a.servo.motion_faults;
            if m.positive() {
                s.servo_fault |= GroupStatus::POS_OVERTRAVEL;
            }
            if m.negative() {
                s.servo_fault |= GroupStatus::NEG_OVERTRAVEL;
            }
            if a.servo.position_error_exceeded && a.servo.faults.0 & AxisFaults::MOTION != 0 {
                s.servo_fault |= GroupStatus::POS_ERROR;
            }
            s.axis_fault |= a.servo.faults.0 & (AxisFaults::PHYSICAL | AxisFaults::MODULE | AxisFaults::CONFIG);
        }
        s
    }

    /// `StrobeActualPosition` and `StrobeCommandPosition` of `axis`: what
    /// the last MGSP latched (0 before any).
    pub fn strobe_positions(&self, axis: AxisHandle) -> (f64, f64) {
        self.group.strobes.get(axis.0 as usize).copied().unwrap_or((0.0, 0.0))
    }

    /// MGS: stops every axis of the group (module doc); `.DN` at once,
    /// `.IP` until every axis is at rest, then `.PC`.
    pub(crate) fn group_stop(&mut self, control: InstructionHandle, stop: GroupStop) {
        self.begin(control);
        if let Some(previous) = self.group.stop.take() {
            self.motion_bits_mut(previous).ip = false;
        }
        self.group.disable_at_rest.clear();
        for i in 0..self.axes.len() {
            let axis = AxisHandle(i as u32);
            let config = &self.axes[i].config;
            if config.inhibited {
                continue;
            }
            let mode = match stop {
                GroupStop::Programmed => config.programmed_stop_mode,
                GroupStop::FastStop => ProgrammedStopMode::FastStop,
                GroupStop::FastDisable => ProgrammedStopMode::FastDisable,
            };
            self.stop_axis_by(axis, mode);
        }
        self.break_all_master_links();
        let b = self.motion_bits_mut(control);
        b.dn = true;
        b.ip = true;
        self.group.stop = Some(control);
    }

    fn stop_axis_by(&mut self, axis: AxisHandle, mode: ProgrammedStopMode) {
        let a = &self.axes[axis.0 as usize];
        let on = matches!(a.servo.power, Power::On | Power::Starting(..));
        let drive = a.config.axis_type == AxisType::Servo;
        use ProgrammedStopMode as M;
        match mode {
            M::HardShutdown => self.disable(axis, Power::Shutdown),
            M::FastShutdown if !on => self.disable(axis, Power::Shutdown),
            M::HardDisable if on && drive => self.disable(axis, Power::Off),
            _ if !on => {}
            M::FastStop | M::FastDisable | M::HardDisable | M::FastShutdown => {
                self.stop_planner(axis);
                let then = match mode {
                    M::FastDisable if drive => Some(Power::Off),
                    M::FastShutdown => Some(Power::Shutdown),
                    _ => None,
                };
                if let Some(to) = then {
                    self.group.disable_at_rest.push((axis, to));
                }
            }
        }
    }

    /// The last step of an update: axes a group stop disables once at rest
    /// are disabled, and the MGS in process completes when every axis is at
    /// rest.
    pub(super) fn advance_group(&mut self) {
        let pending = std::mem::take(&mut self.group.disable_at_rest);
        for (axis, to) in pending {
            if self.at_rest(axis) {
                self.disable(axis, to);
            } else {
                self.group.disable_at_rest.push((axis, to));
            }
        }
        let Some(control) = self.group.stop else {
            return;
        };
        // A servo-off, faulted or shut-down axis is still as far as the
        // planner goes (its joint may coast; no command moves it).
        let all = (0..self.axes.len()).all(|i| {
            let off = matches!(self.axes[i].servo.power, Power::Off | Power::Faulted | Power::Shutdown);
            off || self.at_rest(AxisHandle(i as u32))
        });
        if all && self.group.disable_at_rest.is_empty() {
            let b = self.motion_bits_mut(control);
            b.ip = false;
            b.pc = true;
            self.group.stop = None;
        }
    }

    /// MGSD: every axis of the group is shut down at once (its motion ends,
    /// its drive is disabled) until MGSR, or MASR per axis; `.DN` at once.
    /// A group stop in process ends with it.
    pub(crate) fn group_shutdown(&mut self, control: InstructionHandle) {
        self.begin(control);
        if let Some(previous) = self.group.stop.take() {
            self.motion_bits_mut(previous).ip = false;
        }
        self.group.disable_at_rest.clear();
        self.break_all_master_links();
        for i in 0..self.axes.len() {
            if !self.axes[i].config.inhibited {
                self.disable(AxisHandle(i as u32), Power::Shutdown);
            }
        }
        self.motion_bits_mut(control).dn = true;
    }

    /// MGSR: every shut-down axis of the group leaves Shutdown, as MASR
    /// does (servo off; a virtual axis on); `.DN` at once.
    pub(crate) fn group_shutdown_reset(&mut self, control: InstructionHandle) {
        self.begin(control);
        for i in 0..self.axes.len() {
            if !self.axes[i].config.inhibited {
                self.shutdown_reset(AxisHandle(i as u32));
            }
        }
        self.motion_bits_mut(control).dn = true;
    }

    /// MGSP: latches every axis' actual and command positions, as they
    /// stand when it executes (the last update's); `.DN` at once.
    pub(crate) fn group_strobe(&mut self, control: InstructionHandle) {
        self.begin(control);
        self.group.strobes = self.axes.iter().map(|a| (a.actual, a.command.position)).collect();
        self.motion_bits_mut(control).dn = true;
    }
}

#[cfg(test)]
mod tests;
