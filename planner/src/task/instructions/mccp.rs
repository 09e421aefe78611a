//! MCCP (Motion Calculate Cam Profile): calculates a `CAM_PROFILE` from the
//! elements of a `CAM` array (linear and clamped-cubic segments); the
//! calculation and its refusals (ERR 26–31, 179, ERR 13 for a slope) are
//! [`crate::mccp`]'s, the profile tags the engine's (`task/cam.rs`).
//!
//! The Cam operand is a CAM array or an element of one (`Cam[2]`: the
//! elements from 2); an element outside the array is ERR 13 (EXERR: the
//! Cam operand). Length is a UINT (0 to 65535, else ERR 13).

use crate::catalogue::CallStyle;
use crate::instruction::{Fault, fault};
use super::entry::{Instruction, one_shot, no_load};
use crate::instruction::{NoFault, Refusal};
use crate::mccp::{CamProfile, MCCP_OPERANDS};
use crate::task::{Args, MotionTask};

/// Motion Calculate Cam Profile.
pub const MCCP: Instruction = Instruction {
    mnemonic: "MCCP",
    title: "Motion Calculate Cam Profile",
    summary: "calculates a `CAM_PROFILE` from a `CAM` array (linear and clamped-cubic segments)",
    reference: "`002_…` (MCCP)",
    style: CallStyle::Positional,
    operands: MCCP_OPERANDS,
    execute,
    check,
    load: no_load,
};

/// Length as the UINT it is.
fn length(args: &Args<'_>) -> Result<usize, Refusal<NoFault>> {
    let n = args.integer(2);
    u16::try_from(n)
        .map(usize::from)
        .map_err(|_| Refusal::operand(MCCP.operands[2].faceplate, n as f64))
}

fn execute(task: &mut MotionTask, args: &Args<'_>) -> Result<(), Fault> {
    let control = args.control(0);
    let (cam, start) = args.cam(1);
    if start >= cam.len() {
        let e = Refusal::<NoFault>::operand(MCCP.operands[1].faceplate, start as f64);
        return Err(task.refuse_call(control, e));
    }
    let length = length(args).map_err(|e| task.refuse_call(control, e))?;
    one_shot(task, control, |task| task.mccp_from(control, cam, start, length, args.number(3), args.number(4), args.cam_profile(5)))
}

/// The profile a CAM array with constant points gives (masters not
/// increasing, a segment type that is neither linear nor cubic, a length
/// beyond the array).
fn check(_: &MotionTask, args: &Args<'_>) -> Result<(), Fault> {
    let (cam, start) = args.cam(1);
    let length = length(args).map_err(fault)?;
    let elements = cam.get(start..).unwrap_or(&[]);
    CamProfile::calculate(elements, length, args.number(3), args.number(4))
        .map(drop)
        .map_err(fault)
}
