//! MAM in the motion task: the move runs as the axis' ramp (with the jogs
//! and stop ramps of `task/cam.rs`), from the axis' command state when it
//! executes. The rules are in [`crate::mam`].

use super::servo::Need;
use super::{AxisHandle, InstructionHandle, MotionTask};
use crate::mam::{Mam, MamError, MamOperands};
use crate::profile::Profile;

impl MotionTask {
    /// MAM: moves `axis` as the operands say. `.DN` at once, `.IP` and
    /// `.AC` while it moves, `.PC` when the command reaches the target; a
    /// MAM that another replaces, or that a stop, a disable or another
    /// motion process ends, clears `.IP` without `.PC`.
    ///
    /// # Errors
    /// ERR 13 with EXERR = the operand, ERR 17 for a rotary move type on a
    /// non-modulo axis, the axis-state errors of [`crate::servo`] (ERR 9
    /// for a target further beyond an exceeded soft travel limit); the
    /// axis keeps what it was doing.
    pub fn mam(
        &mut self,
        axis: AxisHandle,
        control: InstructionHandle,
        operands: &MamOperands,
    ) -> Result<(), MamError> {
        self.begin(control);
        let a = &self.axes[axis.0 as usize];
        let start = a.command.state();
        let validated = Mam::new(operands, &a.config, start.velocity.abs()).and_then(|m| {
            self.check_state(axis, Need::Motion).map_err(MamError::State)?;
            let target = m.target(start, &a.config);
            if target != start.position {
                self.check_overtravel(axis, target - start.position)
                    .map_err(MamError::State)?;
            }
            Ok((m, target))
        });
        let (mam, target) = match validated {
            Ok(v) => v,
            Err(e) => {
                self.fail(control, e.err(), e.exerr(), 0);
                return Err(e);
            }
        };
        self.bits_mut(control).dn = true;
        let base_driven = self.cam_drives(axis) || self.coordinated_motion_status(axis);
        if !mam.merge && base_driven {
            // Superimposed on the cam or the coordinated motion.
            self.superimpose_move(axis, control, target - start.position, &mam.limits);
            return Ok(());
        }
        // Every other single-axis motion on the axis ends (see the module
        // doc of `crate::mam` on merge); a MAM it replaces loses `.IP`.
        self.fold_superimposed(axis);
        self.abort_move(axis);
        self.end_cams(axis);
        self.end_gear(axis);
        let start = self.axes[axis.0 as usize].command.state();
        let profile = Profile::to_position(start, target, 0.0, &mam.limits);
        self.start_move_ramp(axis, profile, control);
        Ok(())
    }

    fn bits_mut(&mut self, control: InstructionHandle) -> &mut crate::instruction::MotionInstructionBits {
        self.motion_bits_mut(control)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::axis::{AxisConfig, AxisKind};
    use crate::dynamics::MoveDynamics;
    use crate::jog::MasOperands;

    const DT: f64 = 0.004;

    fn rig(modulo: bool) -> (MotionTask, AxisHandle) {
        rig_at(modulo, 0.0)
    }

    fn rig_at(modulo: bool, position: f64) -> (MotionTask, AxisHandle) {
        let mut task = MotionTask::new(DT).unwrap();
        let config = AxisConfig {
            modulo_period: modulo.then_some(360.0),
            max_velocity: 360.0,
            max_acceleration: 3600.0,
            max_deceleration: 3600.0,
            max_jerk: 36_000.0,
            ..AxisConfig::new("A", if modulo { AxisKind::Rotary } else { AxisKind::Linear })
        };
        let axis = task.add_axis(config, position).unwrap();
        (task, axis)
    }

    fn to(move_type: i64, position: f64, speed_pct: f64) -> MamOperands {
        MamOperands {
            move_type,
            position,
            dynamics: MoveDynamics {
                speed: speed_pct,
                ..MamOperands::default().dynamics
            },
            ..MamOperands::default()
        }
    }

    /// Runs until `.PC` or `.IP` falls; returns the command velocities.
    fn run(task: &mut MotionTask, axis: AxisHandle, mi: InstructionHandle) -> Vec<f64> {
        let mut v = Vec::new();
        for _ in 0..10_000 {
            task.update();
            v.push(task.axis_state(axis).command_velocity);
            if !task.motion_bits(mi).ip {
                break;
            }
        }
        v
    }

    #[test]
    fn an_absolute_move_ends_exactly_at_its_target_with_pc() {
        let (mut task, axis) = rig(false);
        let mi = task.add_instruction("Move");
        task.mam(axis, mi, &to(0, 100.0, 50.0)).unwrap();
        let b = task.motion_bits(mi);
        assert!(b.en && b.dn && b.ip && b.ac && !b.pc);
        assert!(task.axis_status(axis).moving);
        task.update();
        assert!(task.motion_bits(mi).accel);
        let v = run(&mut task, axis, mi);
        let b = task.motion_bits(mi);
        assert!(b.pc && !b.ip && !b.ac && !b.accel && !b.decel, "{b:?}");
        assert_eq!(task.axis_state(axis).command_position, 100.0);
        assert!(v.iter().all(|&x| x <= 180.0 + 1e-9), "50 % of 360");
        assert!(!task.axis_status(axis).moving);
    }

    #[test]
    fn a_second_mam_replaces_the_first_without_stopping() {
        let (mut task, axis) = rig(false);
        let (first, second) = (task.add_instruction("M1"), task.add_instruction("M2"));
        task.mam(axis, first, &to(0, 100.0, 50.0)).unwrap();
        for _ in 0..50 {
            task.update();
        }
        let v0 = task.axis_state(axis).command_velocity;
        assert!(v0 > 100.0);
        task.mam(axis, second, &to(1, 10.0, 50.0)).unwrap();
        let here = task.axis_state(axis).command_position;
        let b = task.motion_bits(first);
        assert!(!b.ip && !b.pc, "replaced: {b:?}");
        let v = run(&mut task, axis, second);
        assert!(task.motion_bits(second).pc);
        assert!(v[..v.len() - 1].iter().all(|&x| x != 0.0), "no stop on the way");
        assert!((task.axis_state(axis).command_position - (here + 10.0)).abs() < 1e-9);
    }

    #[test]
    fn mas_move_stops_a_mam_without_pc() {
        let (mut task, axis) = rig(false);
        let (mv, stop) = (task.add_instruction("Move"), task.add_instruction("Stop"));
        task.mam(axis, mv, &to(0, 500.0, 100.0)).unwrap();
        for _ in 0..30 {
            task.update();
        }
        let o = MasOperands {
            stop_type: 2,
            ..MasOperands::default()
        };
        task.mas(axis, stop, &o).unwrap();
        let b = task.motion_bits(mv);
        assert!(!b.ip && !b.pc);
        run(&mut task, axis, stop);
        assert!(task.motion_bits(stop).pc);
        assert!(task.axis_state(axis).command_position < 500.0);
    }

    #[test]
    fn an_s_curve_move_keeps_its_jerk_and_a_rotary_positive_move_never_turns_back() {
        let (mut task, axis) = rig_at(true, 315.0);
        let mi = task.add_instruction("Move");
        let o = MamOperands {
            dynamics: MoveDynamics {
                profile: 1,
                accel_jerk: 20_000.0,
                decel_jerk: 20_000.0,
                jerk_units: 0,
                ..to(3, 225.0, 100.0).dynamics
            },
            ..to(3, 225.0, 100.0)
        };
        task.mam(axis, mi, &o).unwrap();
        let mut peak_jerk: f64 = 0.0;
        for _ in 0..10_000 {
            task.update();
            let s = task.axis_state(axis);
            assert!(s.command_velocity >= 0.0, "forward only");
            peak_jerk = peak_jerk.max(s.command_jerk.abs());
            if task.motion_bits(mi).pc {
                break;
            }
        }
        assert!(peak_jerk <= 20_000.0 * (1.0 + 1e-9), "{peak_jerk}");
        let s = task.axis_state(axis);
        assert_eq!(s.modulo_command_position, Some(225.0));
        assert_eq!(s.command_position, 315.0 + 270.0, "315 → 225 forward is 270");
    }
}
