//! MDR (Motion Disarm Registration): disarms one of an axis' registration
//! inputs.
//!
//! `MDR(Axis, MotionControl, InputNumber)` (MOTION-RM002): the input no
//! longer looks for an event (`RegEventNArmedStatus` cleared) and the MAR
//! that armed it is no longer in process (its `.IP` cleared). `.DN` in the
//! scan it executes; disarming an input that is not armed is no error.
//! Input Number 1 or 2; another number is ERR 12 EXERR 3, as for MAR.

use super::entry::{Instruction, no_load, one_shot};
use super::mar::{MarError, input_index};
use crate::catalogue::words::{motion_control, op};
use crate::catalogue::{CallStyle, Format, Kind};
use crate::instruction::{Fault, fault};
use crate::task::{Args, AxisHandle, InstructionHandle, MotionTask};

/// Motion Disarm Registration.
pub const MDR: Instruction = Instruction {
    mnemonic: "MDR",
    title: "Motion Disarm Registration",
    summary: "disarms a registration input armed by MAR",
    reference: "Logix motion reference (MOTION-RM002, Motion Event Instructions)",
    style: CallStyle::Positional,
    operands: &[
        op("Axis", "AXIS", Format::Tag, Kind::Axis, 0),
        motion_control(1),
        op("Input Number", "UINT32", Format::Immediate, Kind::Number, 2),
    ],
    execute,
    check,
    load: no_load,
};

fn execute(task: &mut MotionTask, args: &Args<'_>) -> Result<(), Fault> {
    let control = args.control(1);
    one_shot(task, control, |task| task.mdr(args.axis(0), control, args.number(2)))
}

fn check(_: &MotionTask, args: &Args<'_>) -> Result<(), Fault> {
    input_index(args.number(2)).map(|_| ()).map_err(fault)
}

impl MotionTask {
    /// MDR on `axis`.
    ///
    /// # Errors
    /// ERR 12 EXERR 3 for an input other than 1 and 2.
    pub(crate) fn mdr(&mut self, axis: AxisHandle, control: InstructionHandle, input: f64) -> Result<(), MarError> {
        self.instruction(control, |task| {
            let k = input_index(input)?;
            task.disarm_registration(axis, k);
            task.motion_bits_mut(control).dn = true;
            Ok(())
        })
    }
}

#[cfg(test)]
#[allow(clippy::unwrap_used)] // a failed unwrap is a failed test
mod tests {
    use super::*;
    use crate::axis::{AxisConfig, AxisKind};
    use crate::task::Arg;
    use crate::task::instructions::mar::MAR;

    #[test]
    fn mdr_disarms_the_input_and_ends_the_mar() {
        let mut task = MotionTask::new(0.004).unwrap();
        let x = task.add_axis(AxisConfig::new("X", AxisKind::Linear), 0.0).unwrap();
        let (arm, disarm) = (task.add_instruction("A"), task.add_instruction("D"));
        let args = [
            Arg::Axis(x),
            Arg::Control(arm),
            Arg::Integer(0),
            Arg::Integer(0),
            Arg::Number(0.0),
            Arg::Number(0.0),
            Arg::Number(1.0),
        ];
        MAR.execute(&mut task, &Args::new(&args)).unwrap();
        let d = [Arg::Axis(x), Arg::Control(disarm), Arg::Number(1.0)];
        MDR.execute(&mut task, &Args::new(&d)).unwrap();
        assert!(task.motion_bits(disarm).dn);
        assert!(!task.motion_bits(arm).ip);
        assert!(!task.registration(x, 1).unwrap().armed());
        task.registration_edge(x, 1, true, 5.0);
        assert!(!task.registration(x, 1).unwrap().event, "disarmed: no event");
        let bad = [Arg::Axis(x), Arg::Control(disarm), Arg::Number(0.0)];
        let e = MDR.execute(&mut task, &Args::new(&bad)).unwrap_err();
        assert_eq!((e.err(), e.exerr()), (12, 3));
    }
}
