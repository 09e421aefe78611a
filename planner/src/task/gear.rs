//! MAG in the motion task: electronic gearing of a slave to a master. The
//! rules are in [`crate::mag`].
//!
//! Each coarse update, after jogs, moves and cams have advanced, a geared
//! slave's command moves by `ratio × Δmaster` (the master's actual or
//! command position, its MRP redefinitions taken out, as for a cam); while
//! the clutch is slipping, by the clutch velocity instead, which ramps to
//! `ratio × master velocity` at the clutch acceleration and then locks.

use super::{AxisHandle, InstructionHandle, MotionTask};
use crate::mag::{Mag, MagError, MagOperands};
use crate::mapc::MasterReference;
use crate::profile::Sample;

/// The gearing of one slave axis.
#[derive(Debug, Clone)]
pub(super) struct GearRun {
    control: InstructionHandle,
    master: AxisHandle,
    reference: MasterReference,
    /// Signed slave units per master unit.
    ratio: f64,
    /// The master position at the last update (redefinitions taken out).
    last_master: f64,
    /// The clutch acceleration while slipping; `None` once locked.
    clutch: Option<f64>,
    /// The slave's gearing velocity, units/s.
    velocity: f64,
}

impl MotionTask {
    /// MAG: gears `slave` to `master` at the operands' ratio (module doc of
    /// [`crate::mag`]). A MAG on a slave already geared supersedes the
    /// running one (its `.IP` clears); the clutch then starts from the
    /// gearing velocity it had.
    ///
    /// # Errors
    /// ERR 13 (EXERR = the operand), or the slave's state error (5, 7, 8,
    /// 16, 53).
    pub fn mag(
        &mut self,
        slave: AxisHandle,
        master: AxisHandle,
        control: InstructionHandle,
        operands: &MagOperands,
    ) -> Result<(), MagError> {
        self.begin(control);
        let validated = Mag::new(operands, &self.axes[slave.0 as usize].config).and_then(|m| {
            if slave == master {
                return Err(MagError::ParameterOutOfRange {
                    operand: crate::catalogue::MAG.exerr("Master Axis"),
                    value: f64::from(master.0),
                });
            }
            self.check_state(slave, super::servo::Need::Motion)?;
            // The master decides the direction: either side counts.
            self.check_overtravel(slave, 0.0)?;
            Ok(m)
        });
        let mag = match validated {
            Ok(m) => m,
            Err(e) => {
                self.fail(control, e.err(), e.exerr(), 0);
                return Err(e);
            }
        };
        let previous = self.axes[slave.0 as usize].gear.take();
        let current_sign = previous.as_ref().map(|g| g.ratio.signum());
        let velocity = match &previous {
            Some(g) => {
                self.bits(g.control).ip = false;
                g.velocity
            }
            None => {
                let a = &self.axes[slave.0 as usize];
                let sup = self.superimposed(slave).map_or(0.0, |s| s.velocity);
                a.command.velocity - sup
            }
        };
        // The gearing takes the slave from a move or a cam; a jog or MAM
        // running on it goes on superimposed.
        self.abort_move(slave);
        self.end_cams(slave);
        self.superimpose_running_ramp(slave);
        let key = (master, mag.master_reference);
        self.axes[slave.0 as usize].gear = Some(GearRun {
            control,
            master,
            reference: mag.master_reference,
            ratio: mag.effective_ratio(current_sign),
            last_master: self.cam_master_position(key),
            clutch: mag.clutch_accel,
            velocity,
        });
        let b = self.bits(control);
        b.dn = true;
        b.ip = true;
        Ok(())
    }

    /// Whether `axis` is geared (`GearingStatus`), and locked to its master
    /// (`GearingLockStatus`: not while the clutch slips).
    pub fn gearing_status(&self, axis: AxisHandle) -> (bool, bool) {
        match &self.axes[axis.0 as usize].gear {
            Some(g) => (true, g.clutch.is_none()),
            None => (false, false),
        }
    }

    /// Ends the gearing of `axis` (`.IP` clears; the command keeps its
    /// state for whatever takes the axis next).
    pub(super) fn end_gear(&mut self, axis: AxisHandle) -> bool {
        match self.axes[axis.0 as usize].gear.take() {
            Some(g) => {
                self.bits(g.control).ip = false;
                true
            }
            None => false,
        }
    }

    /// Step of an update: every geared slave follows its master.
    pub(super) fn advance_gears(&mut self) {
        let dt = self.dt_s;
        for i in 0..self.axes.len() {
            let Some(mut g) = self.axes[i].gear.take() else {
                continue;
            };
            let m = self.cam_master_position((g.master, g.reference));
            let dm = m - g.last_master;
            g.last_master = m;
            let geared_velocity = g.ratio * dm / dt;
            let dp = match g.clutch {
                None => g.ratio * dm,
                Some(accel) => {
                    let step = accel * dt;
                    let dv = geared_velocity - g.velocity;
                    if dv.abs() <= step {
                        g.clutch = None;
                        g.ratio * dm
                    } else {
                        g.velocity += step.copysign(dv);
                        g.velocity * dt
                    }
                }
            };
            let old = self.axes[i].command;
            let v = dp / dt;
            if g.clutch.is_none() {
                g.velocity = v;
            }
            self.axes[i].gear = Some(g);
            self.set_command(
                AxisHandle(i as u32),
                Sample {
                    position: old.position + dp,
                    velocity: v,
                    acceleration: (v - old.velocity) / dt,
                    jerk: 0.0,
                },
            );
        }
    }
}

#[cfg(test)]
mod tests;
