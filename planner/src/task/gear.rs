//! Gearing in the motion task: a slave axis geared to a master, as MAG
//! (`task/instructions/mag.rs`) starts it.
//!
//! Each coarse update, after jogs, moves and cams have advanced, a geared
//! slave's command moves by `ratio × Δmaster` (the master's actual or
//! command position, its MRP redefinitions taken out, as for a cam); while
//! the clutch is slipping, by the clutch velocity instead, which ramps to
//! `ratio × master velocity` at the clutch acceleration and then locks.

use super::MotionTask;
use crate::profile::Sample;
use crate::task::handles::AxisHandle;

impl MotionTask {
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
                self.motion_bits_mut(g.control).ip = false;
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
