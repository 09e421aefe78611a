//! MRP in the motion task: an axis' position frame redefined, with the
//! motion in process on it and its cam's slave offset.

use super::super::servo::Need;
use super::super::{AxisHandle, InstructionHandle, MotionTask};
use crate::mrp::{Mrp, MrpError};

impl MotionTask {
    /// MRP on `axis` (Type and Position Select as DINTs).
    ///
    /// # Errors
    /// ERR 13 with EXERR 2, 3 or 4; EXERR 4 also when the redefined position
    /// would lie outside the axis' soft travel limits (see [`crate::mrp`]).
    /// A failed MRP redefines nothing.
    pub fn mrp(
        &mut self,
        axis: AxisHandle,
        motion_control: InstructionHandle,
        kind: i32,
        select: i32,
        position: f64,
    ) -> Result<(), MrpError> {
        self.begin(motion_control);
        let mrp = match Mrp::new(kind, select, position).and_then(|m| {
            self.check_state(axis, Need::Any).map_err(MrpError::State)?;
            Ok(m)
        }) {
            Ok(m) => m,
            Err(e) => {
                self.fail(motion_control, e.err(), e.exerr(), 0);
                return Err(e);
            }
        };
        let a = &self.axes[axis.0 as usize];
        let delta = mrp.delta(a.command.position, a.actual);
        // Soft overtravel watches the actual position (`crate::servo`): a
        // redefinition outside the limits raises the exception at once.
        let overtravel = crate::servo::MotionFaults::beyond(a.config.soft_travel_limits, a.actual + delta);
        self.redefine_position(axis, delta);
        self.bits(motion_control).dn = true;
        if let Some(bit) = overtravel {
            self.raise_soft_overtravel(axis, bit);
        }
        Ok(())
    }

    /// Shifts `axis`' position frame by `delta`: command and actual
    /// positions, the motion in process on it and the cam's slave offset
    /// (MRP, MAH).
    pub(in crate::task) fn redefine_position(&mut self, axis: AxisHandle, delta: f64) {
        let a = &mut self.axes[axis.0 as usize];
        a.command.position += delta;
        a.actual += delta;
        if let Some(job) = a.job.as_mut() {
            job.profile.shift_position(delta);
            job.target += delta;
        }
        let c = self.cam_axis(axis);
        c.redefined += delta;
        if let Some(r) = c.ramp.as_mut() {
            r.profile.shift_position(delta);
        }
        c.cam.redefine_slave(delta);
    }
}
