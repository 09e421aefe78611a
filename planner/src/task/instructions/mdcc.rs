//! MDCC (Motion Master Driven Coordinated Control): links a coordinate
//! system (the slave) to a master axis, so that its MCLM and MCCM in
//! master-driven units (speed per master unit) follow the master's
//! position instead of time.
//!
//! `MDCC(SlaveSystem, MasterAxis, MotionControl, MasterReference,
//! NominalMasterVelocity)`:
//! * Master Reference `actual` (0) or `command` (1): which position of
//!   the master drives the system.
//! * Nominal Master Velocity: master units/s, finite and ≥ 0. The manual
//!   uses it to relate time-based and master-based units; the twin records
//!   it (its master-driven jerks are per master unit already).
//! * A master that is one of the slave system's axes is ERR 13 on Master
//!   Axis.
//!
//! # Bits
//! `.DN` when the link is made (the scan it executes), `.IP` while it
//! holds, `.AC` while a master-driven MCLM or MCCM is active on the slave
//! system. MAS All on a slave axis, MCS All on the system, MGS, MASD on a
//! slave axis, MCSD on the system and MGSD break the link: `.IP` and `.AC`
//! clear, the system has no master until the next MDCC.
//!
//! # Reassignment
//! An MDCC to another master while master-driven motion runs on the
//! system is pending, as the manual describes: its `.IP` is set, the
//! running motion keeps following the old master, and the new link is
//! made when no master-driven move is active on the system any more (the
//! old MDCC then leaves `.IP`). With no such motion it links at once.
//! The scene's `coordinate_system.master_axis` is the same link made at
//! start with the command position, without a control structure.

use super::entry::{Instruction, no_check, no_load, one_shot};
use crate::catalogue::words::{ACTUAL_COMMAND, motion_control, op};
use crate::catalogue::{CallStyle, Format, Kind};
use crate::coord::Driver;
use crate::instruction::{Fault, NoFault, Refusal};
use crate::task::{Args, AxisHandle, CoordHandle, InstructionHandle, MotionTask};

/// Motion Master Driven Coordinated Control.
pub const MDCC: Instruction = Instruction {
    mnemonic: "MDCC",
    title: "Motion Master Driven Coordinated Control",
    summary: "links a coordinate system to a master axis: its master-driven MCLM/MCCM follow the master's actual or command position",
    reference: "Logix motion reference (MOTION-RM002, Multi-Axis Coordinated Motion)",
    style: CallStyle::Positional,
    operands: &[
        op(
            "Slave System",
            "COORDINATE_SYSTEM",
            Format::Tag,
            Kind::CoordinateSystem,
            0,
        ),
        op("Master Axis", "AXIS", Format::Tag, Kind::Axis, 1),
        motion_control(2),
        op(
            "Master Reference",
            "UINT32",
            Format::Immediate,
            Kind::Enumeration(ACTUAL_COMMAND),
            3,
        ),
        op(
            "Nominal Master Velocity",
            "REAL",
            Format::ImmediateOrTag,
            Kind::Number,
            4,
        ),
    ],
    execute,
    check: no_check,
    load: no_load,
};

fn execute(task: &mut MotionTask, args: &Args<'_>) -> Result<(), Fault> {
    let control = args.control(2);
    let (system, master) = (args.system(0), args.axis(1));
    let (reference, nominal) = (args.integer(3), args.number(4));
    one_shot(task, control, |task| {
        task.mdcc(system, master, control, reference, nominal)
    })
}

impl MotionTask {
    /// MDCC (module doc).
    ///
    /// # Errors
    /// ERR 13 on Master Axis, Master Reference or Nominal Master Velocity;
    /// the system keeps its link.
    pub(crate) fn mdcc(
        &mut self,
        system: CoordHandle,
        master: AxisHandle,
        control: InstructionHandle,
        reference: i64,
        nominal: f64,
    ) -> Result<(), Refusal<NoFault>> {
        self.instruction(control, |task| {
            if task.coord_axes(system).contains(&master) {
                return Err(Refusal::operand(1, f64::from(master.0)));
            }
            let actual = match reference {
                0 => true,
                1 => false,
                r => return Err(Refusal::operand(3, r as f64)),
            };
            if !(nominal.is_finite() && nominal >= 0.0) {
                return Err(Refusal::operand(4, nominal));
            }
            let sys = &mut task.coord.systems[system.0 as usize];
            let following = sys
                .components
                .iter()
                .any(|c| c.mv.driver() == Driver::Master && !c.stopping);
            if following && sys.master.is_some_and(|m| m != master) {
                if let Some((_, _, old)) = sys.pending_master.replace((master, actual, control)) {
                    task.motion_bits_mut(old).ip = false;
                }
            } else {
                task.link_master(system, master, actual, control);
            }
            let b = task.motion_bits_mut(control);
            b.dn = true;
            b.ip = true;
            Ok(())
        })
    }

    /// Links `system` to `master` for MDCC `control`, ending the link it
    /// had.
    fn link_master(&mut self, system: CoordHandle, master: AxisHandle, actual: bool, control: InstructionHandle) {
        self.break_master_link(system);
        self.set_coordinate_system_master(system, Some(master));
        let a = &self.axes[master.0 as usize];
        let now = if actual { a.actual } else { a.command.position };
        let sys = &mut self.coord.systems[system.0 as usize];
        sys.master_actual = actual;
        sys.master_prev = Some(now);
        sys.mdcc = Some(control);
    }

    /// Breaks the MDCC link of `system` (module doc): its MDCC leaves
    /// `.IP` and `.AC`, the system has no master; a pending reassignment
    /// is dropped too.
    pub(crate) fn break_master_link(&mut self, system: CoordHandle) {
        let sys = &mut self.coord.systems[system.0 as usize];
        if let Some((_, _, pending)) = sys.pending_master.take() {
            self.motion_bits_mut(pending).ip = false;
        }
        let sys = &mut self.coord.systems[system.0 as usize];
        let Some(control) = sys.mdcc.take() else {
            return;
        };
        sys.master = None;
        sys.master_prev = None;
        let b = self.motion_bits_mut(control);
        b.ip = false;
        b.ac = false;
    }

    /// Breaks the MDCC links of the systems `axis` belongs to.
    pub(crate) fn break_master_links_of_axis(&mut self, axis: AxisHandle) {
        for i in 0..self.coord.systems.len() {
            if self.coord.systems[i].axes.contains(&axis) {
                self.break_master_link(CoordHandle(i as u32));
            }
        }
    }

    /// Breaks every MDCC link (MGS, MGSD).
    pub(crate) fn break_all_master_links(&mut self) {
        for i in 0..self.coord.systems.len() {
            self.break_master_link(CoordHandle(i as u32));
        }
    }

    /// `.AC` of each MDCC: a master-driven move is active on its system
    /// (after the coordinate systems' update); a pending reassignment is
    /// linked once none is.
    pub(crate) fn advance_master_links(&mut self) {
        for i in 0..self.coord.systems.len() {
            let sys = &self.coord.systems[i];
            let active = sys
                .components
                .iter()
                .any(|c| c.mv.driver() == Driver::Master && !c.stopping);
            if !active && let Some((master, actual, control)) = sys.pending_master {
                self.coord.systems[i].pending_master = None;
                self.link_master(CoordHandle(i as u32), master, actual, control);
            }
            let Some(control) = self.coord.systems[i].mdcc else {
                continue;
            };
            self.motion_bits_mut(control).ac = active;
        }
    }
}

#[cfg(test)]
mod tests;
