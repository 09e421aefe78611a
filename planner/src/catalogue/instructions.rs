//! The catalogue's entries: every instruction's operands in faceplate
//! order, with their data types, formats and enumeration words, and the
//! list of them all (the parent module's doc says how they are used). An
//! instruction the twin learns is added here alone.

use super::{CallStyle, Family, Format, Instruction, Kind, Operand, Word};

/// Every instruction the product accepts, in the order the docs list them.
pub const INSTRUCTIONS: &[&Instruction] = &[
    &MCLM,
    &MCCM,
    &MCS,
    &MCT,
    &MCCP,
    &MAPC,
    &MRP,
    &MAJ,
    &MAS,
    &MAM,
    &MAG,
    &MSO,
    &MSF,
    &MASD,
    &MASR,
    &MAFR,
    &MAH,
    &MCSD,
    &MCSR,
    &MC_MOVE_MODULO,
];

const fn op(name: &'static str, data_type: &'static str, format: Format, kind: Kind, faceplate: i32) -> Operand {
    Operand {
        name,
        data_type,
        format,
        kind,
        faceplate,
    }
}

const fn w(word: &'static str, code: i64) -> Word {
    Word { word, code }
}

const INTEGER: &str = "SINT, INT, or DINT";
const NUMERIC: &str = "SINT, INT, DINT, or REAL";

use Format::{Array, Immediate, ImmediateOrTag, Input, Tag};

// ---------------------------------------------------------------- words

const SPEED_UNITS: &[Word] = &[w("unitspersec", 0), w("%ofmaximum", 1), w("unitspermasterunit", 4)];
const ACCEL_UNITS: &[Word] = &[
    w("unitspersec²", 0),
    w("unitspersec2", 0),
    w("%ofmaximum", 1),
    w("unitspermasterunit²", 4),
    w("unitspermasterunit2", 4),
];
const JERK_UNITS: &[Word] = &[
    w("unitspersec³", 0),
    w("unitspersec3", 0),
    w("%ofmaximum", 1),
    w("%oftime", 2),
    w("unitspermasterunit³", 4),
    w("unitspermasterunit3", 4),
    w("%oftimemasterdriven", 6),
];
const PROFILE: &[Word] = &[w("trapezoidal", 0), w("s-curve", 1)];
const MERGE: &[Word] = &[w("disabled", 0), w("coordinatedmotion", 1), w("allmotion", 2)];
const MERGE_SPEED: &[Word] = &[w("programmed", 0), w("current", 1)];
const LOCK_DIRECTION: &[Word] = &[
    w("none", 0),
    w("immediateforwardonly", 1),
    w("immediatereverseonly", 2),
    w("positionforward", 3),
    w("positionreverse", 4),
];
const MCS_STOP_TYPE: &[Word] = &[w("all", 0), w("coordinatedmove", 1), w("coordinatedtransform", 2)];
const NO_YES: &[Word] = &[w("no", 0), w("yes", 1)];
const TIME_DECEL_UNITS: &[Word] = &[w("unitspersec²", 0), w("unitspersec2", 0), w("%ofmaximum", 1)];
const TIME_JERK_UNITS: &[Word] = &[
    w("unitspersec³", 0),
    w("unitspersec3", 0),
    w("%ofmaximum", 1),
    w("%oftime", 2),
];
const MAPC_DIRECTION: &[Word] = &[w("same", 0), w("opposite", 1), w("reverse", 2), w("unchanged", 3)];
const EXECUTION_MODE: &[Word] = &[w("once", 0), w("continuous", 1), w("persistent", 2)];
const EXECUTION_SCHEDULE: &[Word] = &[
    w("immediate", 0),
    w("pending", 1),
    w("forwardonly", 2),
    w("reverseonly", 3),
    w("bidirectional", 4),
];
const CAM_TYPE: &[Word] = &[w("newcam", 0), w("replaceandrestart", 1), w("replaceandcontinue", 2)];
const ACTUAL_COMMAND: &[Word] = &[w("actual", 0), w("command", 1)];
const MASTER_DIRECTION: &[Word] = &[w("bidirectional", 0), w("forwardonly", 1), w("reverseonly", 2)];
const MRP_TYPE: &[Word] = &[w("absolute", 0), w("relative", 1)];
const JOG_DIRECTION: &[Word] = &[w("forward", 0), w("reverse", 1)];
const JOG_SPEED_UNITS: &[Word] = &[w("unitspersec", 0), w("%ofmaximum", 1)];
const JOG_ACCEL_UNITS: &[Word] = &[w("unitspersec²", 0), w("unitspersec2", 0), w("%ofmaximum", 1)];
const RATIO_FORMAT: &[Word] = &[w("real", 0), w("fraction_slave_master_counts", 1)];
const CLUTCH: &[Word] = &[w("enabled", 0), w("disabled", 1)];
const MAM_MERGE: &[Word] = &[w("disabled", 0), w("enabled", 1)];
const MAS_STOP_TYPE: &[Word] = &[
    w("all", 0),
    w("jog", 1),
    w("move", 2),
    w("gear", 3),
    w("home", 4),
    w("tune", 5),
    w("test", 6),
    w("timecam", 7),
    w("positioncam", 8),
    w("masteroffsetmove", 9),
    w("directcontrol", 10),
];
const MC_DIRECTION: &[Word] = &[
    w("MC_Positive_Direction", 1),
    w("MC_Shortest_Way", 2),
    w("MC_Negative_Direction", 3),
    w("MC_Current_Direction", 4),
];
const MC_BUFFER_MODE: &[Word] = &[
    w("MC_Aborting", 0),
    w("MC_Buffered", 1),
    w("MC_BlendingLow", 2),
    w("MC_BlendingPrevious", 3),
    w("MC_BlendingNext", 4),
    w("MC_BlendingHigh", 5),
];

// ---------------------------------------------------------- instructions

/// MCCM's operands; MCLM's are these without Circle Type,
/// Via/Center/Radius and Direction, with their own faceplate indices.
const MCCM_OPERANDS: &[Operand] = &[
    op("Coordinate System", "COORDINATE_SYSTEM", Tag, Kind::CoordinateSystem, 0),
    op("Motion Control", "MOTION_INSTRUCTION", Tag, Kind::MotionControl, 1),
    op("Move Type", INTEGER, ImmediateOrTag, Kind::Integer, 2),
    op("Position", "REAL array", Array, Kind::Values, 3),
    op("Circle Type", INTEGER, ImmediateOrTag, Kind::Integer, 4),
    op("Via/Center/Radius", "REAL array or REAL", Array, Kind::Values, 5),
    op("Direction", INTEGER, ImmediateOrTag, Kind::Integer, 6),
    op("Speed", NUMERIC, ImmediateOrTag, Kind::Number, 7),
    op("Speed Units", INTEGER, Immediate, Kind::Enumeration(SPEED_UNITS), 8),
    op("Accel Rate", NUMERIC, ImmediateOrTag, Kind::Number, 9),
    op("Accel Units", INTEGER, Immediate, Kind::Enumeration(ACCEL_UNITS), 10),
    op("Decel Rate", NUMERIC, ImmediateOrTag, Kind::Number, 11),
    op("Decel Units", INTEGER, Immediate, Kind::Enumeration(ACCEL_UNITS), 12),
    op("Profile", INTEGER, Immediate, Kind::Enumeration(PROFILE), 13),
    op("Accel Jerk", NUMERIC, ImmediateOrTag, Kind::Number, 17),
    op("Decel Jerk", NUMERIC, ImmediateOrTag, Kind::Number, 18),
    op("Jerk Units", INTEGER, ImmediateOrTag, Kind::Enumeration(JERK_UNITS), 19),
    op("Termination Type", INTEGER, ImmediateOrTag, Kind::Integer, 14),
    op("Merge", INTEGER, Immediate, Kind::Enumeration(MERGE), 15),
    op("Merge Speed", INTEGER, Immediate, Kind::Enumeration(MERGE_SPEED), 16),
    op("Command Tolerance", "REAL", ImmediateOrTag, Kind::Number, 20),
    op("Lock Position", "REAL", ImmediateOrTag, Kind::Number, 21),
    op(
        "Lock Direction",
        "UINT32",
        ImmediateOrTag,
        Kind::Enumeration(LOCK_DIRECTION),
        22,
    ),
    op("Event Distance", "REAL ARRAY or 0", Array, Kind::OptionalArray, 23),
    op("Calculated Data", "REAL ARRAY or 0", Array, Kind::OptionalArray, 24),
];

/// Motion Coordinated Circular Move.
pub const MCCM: Instruction = Instruction {
    mnemonic: "MCCM",
    title: "Motion Coordinated Circular Move",
    style: CallStyle::Positional,
    family: Family::Coordinated,
    operands: MCCM_OPERANDS,
};

/// The MCCM operands MCLM lacks (their faceplate slots 4–6).
const CIRCLE_OPERANDS: usize = 3;

/// MCLM's operands: MCCM's without Circle Type, Via/Center/Radius and
/// Direction; the faceplate indices after them move down by three.
const MCLM_OPERANDS: [Operand; MCCM_OPERANDS.len() - CIRCLE_OPERANDS] = {
    let first_circle = 4;
    let mut out = [MCCM_OPERANDS[0]; MCCM_OPERANDS.len() - CIRCLE_OPERANDS];
    let (mut from, mut to) = (0, 0);
    while from < MCCM_OPERANDS.len() {
        let mut operand = MCCM_OPERANDS[from];
        from += 1;
        if operand.faceplate >= first_circle && operand.faceplate < first_circle + CIRCLE_OPERANDS as i32 {
            continue;
        }
        if operand.faceplate >= first_circle {
            operand.faceplate -= CIRCLE_OPERANDS as i32;
        }
        out[to] = operand;
        to += 1;
    }
    out
};

/// Motion Coordinated Linear Move.
pub const MCLM: Instruction = Instruction {
    mnemonic: "MCLM",
    title: "Motion Coordinated Linear Move",
    style: CallStyle::Positional,
    family: Family::Coordinated,
    operands: &MCLM_OPERANDS,
};

/// Motion Coordinated Stop.
pub const MCS: Instruction = Instruction {
    mnemonic: "MCS",
    title: "Motion Coordinated Stop",
    style: CallStyle::Positional,
    family: Family::Coordinated,
    operands: &[
        op("Coordinate System", "COORDINATE_SYSTEM", Tag, Kind::CoordinateSystem, 0),
        op("Motion Control", "MOTION_INSTRUCTION", Tag, Kind::MotionControl, 1),
        op("Stop Type", "DINT", Immediate, Kind::Enumeration(MCS_STOP_TYPE), 2),
        op("Change Decel", "DINT", Immediate, Kind::Enumeration(NO_YES), 3),
        op("Decel Rate", "REAL", ImmediateOrTag, Kind::Number, 4),
        op("Decel Units", "DINT", Immediate, Kind::Enumeration(TIME_DECEL_UNITS), 5),
        op("Change Decel Jerk", "DINT", Immediate, Kind::Enumeration(NO_YES), 6),
        op("Decel Jerk", "REAL", ImmediateOrTag, Kind::Number, 7),
        op("Jerk Units", "DINT", Immediate, Kind::Enumeration(TIME_JERK_UNITS), 8),
    ],
};

/// Motion Coordinated Transform.
pub const MCT: Instruction = Instruction {
    mnemonic: "MCT",
    title: "Motion Coordinated Transform",
    style: CallStyle::Positional,
    family: Family::Transform,
    operands: &[
        op("Source System", "COORDINATE_SYSTEM", Tag, Kind::CoordinateSystem, 0),
        op("Target System", "COORDINATE_SYSTEM", Tag, Kind::CoordinateSystem, 1),
        op("Motion Control", "MOTION_INSTRUCTION", Tag, Kind::MotionControl, 2),
        op("Orientation", "REAL[3]", Array, Kind::Vector3, 3),
        op("Translation", "REAL[3]", Array, Kind::Vector3, 4),
    ],
};

/// Motion Calculate Cam Profile.
pub const MCCP: Instruction = Instruction {
    mnemonic: "MCCP",
    title: "Motion Calculate Cam Profile",
    style: CallStyle::Positional,
    family: Family::Cam,
    operands: &[
        op("Motion Control", "MOTION_INSTRUCTION", Tag, Kind::MotionControl, 0),
        op("Cam", "CAM", Array, Kind::Cam, 1),
        op("Length", "UINT", ImmediateOrTag, Kind::Count, 2),
        op("Start Slope", "REAL", ImmediateOrTag, Kind::Number, 3),
        op("End Slope", "REAL", ImmediateOrTag, Kind::Number, 4),
        op("Cam Profile", "CAM_PROFILE", Array, Kind::CamProfile, 5),
    ],
};

/// Motion Axis Position Cam.
pub const MAPC: Instruction = Instruction {
    mnemonic: "MAPC",
    title: "Motion Axis Position Cam",
    style: CallStyle::Positional,
    family: Family::Cam,
    operands: &[
        op("Slave Axis", "AXIS", Tag, Kind::Axis, 0),
        op("Master Axis", "AXIS", Tag, Kind::Axis, 1),
        op("Motion Control", "MOTION_INSTRUCTION", Tag, Kind::MotionControl, 2),
        op("Direction", "DINT", Immediate, Kind::Enumeration(MAPC_DIRECTION), 3),
        op("Cam Profile", "CAM_PROFILE", Array, Kind::CamProfile, 4),
        op("Slave Scaling", "REAL", ImmediateOrTag, Kind::Number, 5),
        op("Master Scaling", "REAL", ImmediateOrTag, Kind::Number, 6),
        op(
            "Execution Mode",
            "DINT",
            Immediate,
            Kind::Enumeration(EXECUTION_MODE),
            7,
        ),
        op(
            "Execution Schedule",
            "DINT",
            Immediate,
            Kind::Enumeration(EXECUTION_SCHEDULE),
            8,
        ),
        op("Master Lock Position", "REAL", ImmediateOrTag, Kind::Number, 9),
        op("Cam Lock Position", "REAL", ImmediateOrTag, Kind::Number, 10),
        op("Cam Type", "DINT", Immediate, Kind::Enumeration(CAM_TYPE), 11),
        op(
            "Master Reference",
            "DINT",
            Immediate,
            Kind::Enumeration(ACTUAL_COMMAND),
            12,
        ),
        op(
            "Master Direction",
            "DINT",
            Immediate,
            Kind::Enumeration(MASTER_DIRECTION),
            13,
        ),
    ],
};

/// Motion Redefine Position.
pub const MRP: Instruction = Instruction {
    mnemonic: "MRP",
    title: "Motion Redefine Position",
    style: CallStyle::Positional,
    family: Family::Cam,
    operands: &[
        op("Axis", "AXIS", Tag, Kind::Axis, 0),
        op("Motion Control", "MOTION_INSTRUCTION", Tag, Kind::MotionControl, 1),
        op("Type", "BOOLEAN", Immediate, Kind::Enumeration(MRP_TYPE), 2),
        op(
            "Position Select",
            "BOOLEAN",
            Immediate,
            Kind::Enumeration(ACTUAL_COMMAND),
            3,
        ),
        op("Position", "REAL", ImmediateOrTag, Kind::Number, 4),
    ],
};

/// Motion Axis Jog (its first ten operands).
pub const MAJ: Instruction = Instruction {
    mnemonic: "MAJ",
    title: "Motion Axis Jog",
    style: CallStyle::Positional,
    family: Family::Cam,
    operands: &[
        op("Axis", "AXIS", Tag, Kind::Axis, 0),
        op("Motion Control", "MOTION_INSTRUCTION", Tag, Kind::MotionControl, 1),
        op("Direction", "DINT", Immediate, Kind::Enumeration(JOG_DIRECTION), 2),
        op("Speed", "REAL", ImmediateOrTag, Kind::Number, 3),
        op("Speed Units", "DINT", Immediate, Kind::Enumeration(JOG_SPEED_UNITS), 4),
        op("Accel Rate", "REAL", ImmediateOrTag, Kind::Number, 5),
        op("Accel Units", "DINT", Immediate, Kind::Enumeration(JOG_ACCEL_UNITS), 6),
        op("Decel Rate", "REAL", ImmediateOrTag, Kind::Number, 7),
        op("Decel Units", "DINT", Immediate, Kind::Enumeration(JOG_ACCEL_UNITS), 8),
        op("Profile", "DINT", Immediate, Kind::Enumeration(PROFILE), 9),
    ],
};

/// Motion Axis Gear.
pub const MAG: Instruction = Instruction {
    mnemonic: "MAG",
    title: "Motion Axis Gear",
    style: CallStyle::Positional,
    family: Family::Cam,
    operands: &[
        op("Slave Axis", "AXIS", Tag, Kind::Axis, 0),
        op("Master Axis", "AXIS", Tag, Kind::Axis, 1),
        op("Motion Control", "MOTION_INSTRUCTION", Tag, Kind::MotionControl, 2),
        op("Direction", "DINT", Immediate, Kind::Enumeration(MAPC_DIRECTION), 3),
        op("Ratio", "REAL", ImmediateOrTag, Kind::Number, 4),
        op("Slave Counts", "DINT", ImmediateOrTag, Kind::Integer, 5),
        op("Master Counts", "DINT", ImmediateOrTag, Kind::Integer, 6),
        op(
            "Master Reference",
            "DINT",
            Immediate,
            Kind::Enumeration(ACTUAL_COMMAND),
            7,
        ),
        op("Ratio Format", "DINT", Immediate, Kind::Enumeration(RATIO_FORMAT), 8),
        op("Clutch", "DINT", Immediate, Kind::Enumeration(CLUTCH), 9),
        op("Accel Rate", "REAL", ImmediateOrTag, Kind::Number, 10),
        op("Accel Units", "DINT", Immediate, Kind::Enumeration(JOG_ACCEL_UNITS), 11),
    ],
};

/// Motion Axis Move.
pub const MAM: Instruction = Instruction {
    mnemonic: "MAM",
    title: "Motion Axis Move",
    style: CallStyle::Positional,
    family: Family::Cam,
    operands: &[
        op("Axis", "AXIS", Tag, Kind::Axis, 0),
        op("Motion Control", "MOTION_INSTRUCTION", Tag, Kind::MotionControl, 1),
        op("Move Type", INTEGER, ImmediateOrTag, Kind::Integer, 2),
        op("Position", NUMERIC, ImmediateOrTag, Kind::Number, 3),
        op("Speed", NUMERIC, ImmediateOrTag, Kind::Number, 4),
        op("Speed Units", INTEGER, Immediate, Kind::Enumeration(JOG_SPEED_UNITS), 5),
        op("Accel Rate", NUMERIC, ImmediateOrTag, Kind::Number, 6),
        op("Accel Units", INTEGER, Immediate, Kind::Enumeration(JOG_ACCEL_UNITS), 7),
        op("Decel Rate", NUMERIC, ImmediateOrTag, Kind::Number, 8),
        op("Decel Units", INTEGER, Immediate, Kind::Enumeration(JOG_ACCEL_UNITS), 9),
        op("Profile", INTEGER, Immediate, Kind::Enumeration(PROFILE), 10),
        op("Accel Jerk", NUMERIC, ImmediateOrTag, Kind::Number, 11),
        op("Decel Jerk", NUMERIC, ImmediateOrTag, Kind::Number, 12),
        op("Jerk Units", INTEGER, Immediate, Kind::Enumeration(TIME_JERK_UNITS), 13),
        op("Merge", INTEGER, Immediate, Kind::Enumeration(MAM_MERGE), 14),
        op("Merge Speed", INTEGER, Immediate, Kind::Enumeration(MERGE_SPEED), 15),
        op("Lock Position", "REAL", ImmediateOrTag, Kind::Number, 16),
        op(
            "Lock Direction",
            "UINT32",
            ImmediateOrTag,
            Kind::Enumeration(LOCK_DIRECTION),
            17,
        ),
        op("Event Distance", "REAL ARRAY or 0", Array, Kind::OptionalArray, 18),
        op("Calculated Data", "REAL ARRAY or 0", Array, Kind::OptionalArray, 19),
    ],
};

/// Motion Axis Stop (its first six operands).
pub const MAS: Instruction = Instruction {
    mnemonic: "MAS",
    title: "Motion Axis Stop",
    style: CallStyle::Positional,
    family: Family::Cam,
    operands: &[
        op("Axis", "AXIS", Tag, Kind::Axis, 0),
        op("Motion Control", "MOTION_INSTRUCTION", Tag, Kind::MotionControl, 1),
        op("Stop Type", "DINT", Immediate, Kind::Enumeration(MAS_STOP_TYPE), 2),
        op("Change Decel", "DINT", Immediate, Kind::Enumeration(NO_YES), 3),
        op("Decel Rate", "REAL", ImmediateOrTag, Kind::Number, 4),
        op("Decel Units", "DINT", Immediate, Kind::Enumeration(JOG_ACCEL_UNITS), 5),
    ],
};

/// MSO's and MSF's operands: the drive instructions take no AXIS_VIRTUAL.
const DRIVE_STATE_OPERANDS: [Operand; 2] = [
    op("Axis", "AXIS_CIP_DRIVE", Tag, Kind::Axis, 0),
    op("Motion Control", "MOTION_INSTRUCTION", Tag, Kind::MotionControl, 1),
];

/// MASD's, MASR's and MAFR's operands.
const AXIS_STATE_OPERANDS: [Operand; 2] = [
    op("Axis", "AXIS", Tag, Kind::Axis, 0),
    op("Motion Control", "MOTION_INSTRUCTION", Tag, Kind::MotionControl, 1),
];

/// MCSD's and MCSR's operands.
const SYSTEM_STATE_OPERANDS: [Operand; 2] = [
    op("Coordinate System", "COORDINATE_SYSTEM", Tag, Kind::CoordinateSystem, 0),
    op("Motion Control", "MOTION_INSTRUCTION", Tag, Kind::MotionControl, 1),
];

/// A state instruction.
const fn state(mnemonic: &'static str, title: &'static str, operands: &'static [Operand]) -> Instruction {
    Instruction {
        mnemonic,
        title,
        style: CallStyle::Positional,
        family: Family::State,
        operands,
    }
}

/// Motion Servo On.
pub const MSO: Instruction = state("MSO", "Motion Servo On", &DRIVE_STATE_OPERANDS);
/// Motion Servo Off.
pub const MSF: Instruction = state("MSF", "Motion Servo Off", &DRIVE_STATE_OPERANDS);
/// Motion Axis Shutdown.
pub const MASD: Instruction = state("MASD", "Motion Axis Shutdown", &AXIS_STATE_OPERANDS);
/// Motion Axis Shutdown Reset.
pub const MASR: Instruction = state("MASR", "Motion Axis Shutdown Reset", &AXIS_STATE_OPERANDS);
/// Motion Axis Fault Reset.
pub const MAFR: Instruction = state("MAFR", "Motion Axis Fault Reset", &AXIS_STATE_OPERANDS);
/// Motion Axis Home (how it homes is the axis' configuration:
/// [`crate::mah`]).
pub const MAH: Instruction = state("MAH", "Motion Axis Home", &AXIS_STATE_OPERANDS);
/// Motion Coordinated Shutdown.
pub const MCSD: Instruction = state("MCSD", "Motion Coordinated Shutdown", &SYSTEM_STATE_OPERANDS);
/// Motion Coordinated Shutdown Reset.
pub const MCSR: Instruction = state("MCSR", "Motion Coordinated Shutdown Reset", &SYSTEM_STATE_OPERANDS);

/// PLCopen / Beckhoff `MC_MoveModulo`, called on an instance with named
/// inputs (`Options` is listed so that naming it gets a clear refusal).
pub const MC_MOVE_MODULO: Instruction = Instruction {
    mnemonic: "MC_MoveModulo",
    title: "Modulo positioning",
    style: CallStyle::Named,
    family: Family::PlcOpen,
    operands: &[
        op("Axis", "AXIS_REF", Tag, Kind::Axis, -1),
        op("Execute", "BOOL", Input, Kind::Bool, -1),
        op("Position", "LREAL", Input, Kind::Number, -1),
        op("Velocity", "LREAL", Input, Kind::Number, -1),
        op("Acceleration", "LREAL", Input, Kind::Number, -1),
        op("Deceleration", "LREAL", Input, Kind::Number, -1),
        op("Jerk", "LREAL", Input, Kind::Number, -1),
        op("Direction", "MC_Direction", Input, Kind::Enumeration(MC_DIRECTION), -1),
        op(
            "BufferMode",
            "MC_BufferMode",
            Input,
            Kind::Enumeration(MC_BUFFER_MODE),
            -1,
        ),
        op("Options", "ST_MoveOptions", Input, Kind::Number, -1),
    ],
};
