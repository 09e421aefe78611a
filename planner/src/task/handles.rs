//! The handles a program holds: an axis, a function-block instance, a
//! control structure, a cam profile, a coordinate system and a coordinated
//! instruction of a [`MotionTask`](super::MotionTask).

/// Handle of an axis in a [`MotionTask`](super::MotionTask).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct AxisHandle(pub(super) u32);

/// Handle of a function-block instance in a [`MotionTask`](super::MotionTask).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct FbHandle(pub(super) u32);

/// Handle of a Logix control structure (a `MOTION_INSTRUCTION` tag) in a
/// [`MotionTask`](super::MotionTask). The instruction that executes with the tag writes its
/// bits; one tag may serve several executions over time, as on a controller.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct InstructionHandle(pub(super) u32);

/// Handle of a `CAM_PROFILE` tag.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct CamProfileHandle(pub(super) u32);

/// Handle of a coordinate system in a [`MotionTask`](super::MotionTask).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct CoordHandle(pub(super) u32);

/// Handle of a coordinated instruction (MCLM, MCCM, MCS) in a [`MotionTask`](super::MotionTask).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct CoordInstructionHandle(pub(super) u32);
