//! MCTP (Motion Calculate Transform Position): converts a position between
//! a Cartesian coordinate system and a robot's joint system as MCT would
//! transform it (its geometries, Orientation and Translation, arm
//! solutions), without a transform running and without motion
//! ([`crate::mct::instruction::calculate`]).
//!
//! `MCTP(SourceSystem, TargetSystem, MotionControl, Orientation,
//! Translation, TransformDirection, ReferencePosition, TransformPosition)`:
//! * Transform Direction `forward` (0): Reference Position holds joint
//!   positions of the target system (axis units), Transform Position gets
//!   the source system's coordinates; `inverse` (1): Reference Position
//!   holds source coordinates, Transform Position gets joint positions on
//!   the arm solution the target's joints stand in now; `inverse left arm`
//!   (2) and `inverse right arm` (3) choose a serial arm's elbow (SCARA,
//!   articulated; the other geometries have none to choose: as `inverse`).
//!   The manual lists the words without their codes; the codes follow
//!   their order. The "above" / "below" choices some releases offer are
//!   not simulated (refused at load).
//! * Orientation, Translation, Reference Position and Transform Position
//!   are `REAL[3]` from the element named; fewer than three is ERR 13 with
//!   the operand's faceplate index. Transform Position is written in the
//!   scan MCTP executes (REAL precision) and left as it was on an error.
//! * `.DN` in the scan it executes; `.ER` with MCT's ERR and EXERR (ERR 61
//!   for the systems, ERR 13 for orientation and translation, ERR 67 for a
//!   position out of reach or at a singularity).
//!
//! Choices where the manual is silent: the systems' axes may be moving
//! or in a running transform (nothing is driven); soft travel limits are
//! not checked (MCT checks them when it moves).

use super::entry::{Instruction, no_check, no_load, one_shot};
use super::mct::vector3;
use crate::catalogue::words::{motion_control, op, w};
use crate::catalogue::{CallStyle, Format, Kind, Word};
use crate::instruction::{Fault, Refusal};
use crate::mct::instruction::TransformDirection;
use crate::task::{Args, MotionTask};

/// MCTP's Transform Direction.
const DIRECTION: &[Word] = &[
    w("forward", 0),
    w("inverse", 1),
    w("inverseleftarm", 2),
    w("inverserightarm", 3),
];

/// Motion Calculate Transform Position.
pub const MCTP: Instruction = Instruction {
    mnemonic: "MCTP",
    title: "Motion Calculate Transform Position",
    summary: "converts a position between a Cartesian system and a joint system as MCT would (forward, inverse, left / right arm), without motion",
    reference: "Logix motion reference (MOTION-RM002, Multi-Axis Coordinated Motion)",
    style: CallStyle::Positional,
    operands: &[
        op(
            "Source System",
            "COORDINATE_SYSTEM",
            Format::Tag,
            Kind::CoordinateSystem,
            0,
        ),
        op(
            "Target System",
            "COORDINATE_SYSTEM",
            Format::Tag,
            Kind::CoordinateSystem,
            1,
        ),
        motion_control(2),
        op("Orientation", "REAL[3]", Format::Array, Kind::Vector3, 3),
        op("Translation", "REAL[3]", Format::Array, Kind::Vector3, 4),
        op(
            "Transform Direction",
            "DINT",
            Format::Immediate,
            Kind::Enumeration(DIRECTION),
            5,
        ),
        op("Reference Position", "REAL[3]", Format::Array, Kind::Vector3, 6),
        op("Transform Position", "REAL[3]", Format::Array, Kind::OutputVector3, 7),
    ],
    execute,
    check: no_check,
    load: no_load,
};

fn execute(task: &mut MotionTask, args: &Args<'_>) -> Result<(), Fault> {
    let control = args.control(2);
    let operands = (|| {
        let direction = match args.integer(5) {
            0 => TransformDirection::Forward,
            1 => TransformDirection::Inverse,
            2 => TransformDirection::InverseLeftArm,
            3 => TransformDirection::InverseRightArm,
            d => return Err(Refusal::operand(MCTP.exerr("Transform Direction"), d as f64)),
        };
        // Transform Position needs three elements to be written.
        vector3(&MCTP, args, 7)?;
        Ok((
            vector3(&MCTP, args, 3)?,
            vector3(&MCTP, args, 4)?,
            direction,
            vector3(&MCTP, args, 6)?,
        ))
    })();
    let (orientation, translation, direction, reference) = match operands {
        Ok(o) => o,
        Err(e) => return one_shot(task, control, |task| task.instruction(control, |_| Err::<(), _>(e))),
    };
    one_shot(task, control, |task| {
        let position = task.mctp(
            control,
            (args.system(0), args.system(1)),
            (orientation, translation),
            direction,
            reference,
        )?;
        task.output = Some(position);
        Ok::<(), crate::mct::instruction::MctError>(())
    })
}
