//! MCSV (Motion Calculate Slave Values): the slave value, the slope and
//! the slope's derivative of a calculated cam profile at a master value.
//!
//! `MCSV(MotionControl, CamProfile, MasterValue, SlaveValue, SlopeValue,
//! SlopeDerivative)`: Cam Profile a `CAM_PROFILE` MCCP calculated (ERR 30
//! while it is being calculated, 32 before); Master Value inside the
//! profile's master range, else ERR 13 on Master Value (the manual is
//! silent on a value outside it: the profile has no slave value there).
//! Slave Value, Slope Value and Slope Derivative are REAL tags it writes
//! in the scan it executes (slave units, per master unit, per master
//! unit²), `.DN` then; they keep their values on an error.

use super::entry::{Instruction, no_check, no_load, one_shot};
use crate::catalogue::words::{motion_control, op};
use crate::catalogue::{CallStyle, Format, Kind};
use crate::instruction::{Fault, LogixFault, Refusal};
use crate::task::{Args, CamProfileHandle, InstructionHandle, MotionTask};
use thiserror::Error;

/// Motion Calculate Slave Values.
pub const MCSV: Instruction = Instruction {
    mnemonic: "MCSV",
    title: "Motion Calculate Slave Values",
    summary: "a calculated cam profile's slave value, slope and slope derivative at a master value",
    reference: "Logix motion reference (MOTION-RM002, Motion Move Instructions)",
    style: CallStyle::Positional,
    operands: &[
        motion_control(0),
        op("Cam Profile", "CAM_PROFILE", Format::Array, Kind::CamProfile, 1),
        op("Master Value", "REAL", Format::ImmediateOrTag, Kind::Number, 2),
        op("Slave Value", "REAL", Format::Tag, Kind::OutputReal, 3),
        op("Slope Value", "REAL", Format::Tag, Kind::OutputReal, 4),
        op("Slope Derivative", "REAL", Format::Tag, Kind::OutputReal, 5),
    ],
    execute,
    check: no_check,
    load: no_load,
};

/// MCSV's refusal of a profile not calculated.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Error)]
#[error("the cam profile is {what} (ERR {code})", code = .0, what = if *.0 == 30 { "being calculated" } else { "not calculated" })]
pub struct NotCalculated(pub i32);

impl LogixFault for NotCalculated {
    fn err(&self) -> i32 {
        self.0
    }
}

fn execute(task: &mut MotionTask, args: &Args<'_>) -> Result<(), Fault> {
    let control = args.control(0);
    let (profile, master) = (args.cam_profile(1), args.number(2));
    one_shot(task, control, |task| task.mcsv(control, profile, master).map(drop))
}

impl MotionTask {
    /// MCSV (module doc): the three values, also left for the caller's
    /// tags ([`MotionTask::take_output`]).
    ///
    /// # Errors
    /// ERR 30, 32, or 13 on Master Value.
    pub(crate) fn mcsv(
        &mut self,
        control: InstructionHandle,
        profile: CamProfileHandle,
        master: f64,
    ) -> Result<[f64; 3], Refusal<NotCalculated>> {
        self.instruction(control, |task| {
            let tag = &task.cam.profiles[profile.0 as usize].1;
            let p = match (tag.profile(), tag.status()) {
                (Some(p), s) if s >= 2 => p.clone(),
                (_, s) => return Err(Refusal::Instruction(NotCalculated(if s == 1 { 30 } else { 32 }))),
            };
            let (x0, xn) = p.master_range();
            if !(x0..=xn).contains(&master) {
                return Err(Refusal::operand(MCSV.exerr("Master Value"), master));
            }
            let point = p.eval(master);
            let values = [point.slave, point.slope, point.curvature];
            task.output = Some(values);
            task.motion_bits_mut(control).dn = true;
            Ok(values)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mccp::CamElement;

    #[test]
    fn values_of_a_linear_and_a_cubic_profile_and_the_refusals() {
        let mut task = MotionTask::new(0.004).unwrap();
        let profile = task.add_cam_profile("P", 3);
        let mc = task.add_instruction("Mcsv");
        let e = task.mcsv(mc, profile, 0.5).unwrap_err();
        assert_eq!(e.err(), 32);
        let cam = [
            CamElement {
                master: 0.0,
                slave: 0.0,
                segment_type: 0,
            },
            CamElement {
                master: 2.0,
                slave: 4.0,
                segment_type: 1,
            },
            CamElement {
                master: 4.0,
                slave: 4.0,
                segment_type: 0,
            },
        ];
        let calc = task.add_instruction("Calc");
        task.mccp_from(calc, &cam, 0, 3, 0.0, 0.0, profile).unwrap();
        let [slave, slope, slope2] = task.mcsv(mc, profile, 1.0).unwrap();
        assert!((slave - 2.0).abs() < 1e-12 && (slope - 2.0).abs() < 1e-12 && slope2.abs() < 1e-12);
        assert!(task.motion_bits(mc).dn);
        assert_eq!(task.take_output(), Some([slave, slope, slope2]));
        // The cubic segment against the profile's own evaluation.
        let p = task.cam_profile(profile).profile().unwrap().clone();
        let at = p.eval(3.1);
        assert_eq!(task.mcsv(mc, profile, 3.1).unwrap(), [at.slave, at.slope, at.curvature]);
        let e = task.mcsv(mc, profile, 4.5).unwrap_err();
        assert_eq!((e.err(), e.exerr()), (13, 2));
    }
}
