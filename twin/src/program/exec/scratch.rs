//! Room for the operand values of an instruction call, kept between
//! calls so a scan allocates nothing.

use super::frame::Frame;
use planner::mccp::CamElement;

/// The most operands an instruction has (MCCM's 25), with room to spare.
pub(super) const MAX_OPERANDS: usize = 32;

/// Room for the arrays and CAM elements of an instruction call's operands,
/// and the frame stack of a scan (empty between scans, its allocation
/// kept).
#[derive(Debug, Default)]
pub struct Scratch {
    pub(super) numbers: Vec<f64>,
    pub(super) cams: Vec<CamElement>,
    pub(super) output_cams: Vec<planner::output_cam::OutputCamElement>,
    pub(super) compensations: Vec<planner::output_cam::OutputCompensation>,
    pub(super) frames: Vec<Frame<'static>>,
}
