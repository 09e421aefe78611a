//! The vocabulary of the instructions' catalogue entries: the helpers that
//! write an operand and a word, the data-type texts, and the enumeration
//! words of the operands (the same word may have different codes in
//! different operands). An instruction whose operand has words no other
//! has may keep them in its own module.

use super::{Format, Kind, Operand, Word};

/// An operand: its name, data type text, Format, kind and faceplate index.
pub const fn op(name: &'static str, data_type: &'static str, format: Format, kind: Kind, faceplate: i32) -> Operand {
    Operand {
        name,
        data_type,
        format,
        kind,
        faceplate,
    }
}

/// The `Motion Control` operand (a `MOTION_INSTRUCTION` tag) at faceplate
/// index `faceplate`: every Logix motion instruction has one.
pub const fn motion_control(faceplate: i32) -> Operand {
    op(
        "Motion Control",
        "MOTION_INSTRUCTION",
        Format::Tag,
        Kind::MotionControl,
        faceplate,
    )
}

/// The operands of an axis-state instruction (MAFR, MAH, MASD, MASR): the
/// axis and its control structure.
pub const AXIS_AND_CONTROL: &[Operand] = &[op("Axis", "AXIS", Format::Tag, Kind::Axis, 0), motion_control(1)];

/// The operands of a drive's servo instruction (MSO, MSF): an axis with a
/// drive and its control structure.
pub const DRIVE_AXIS_AND_CONTROL: &[Operand] = &[
    op("Axis", "AXIS_CIP_DRIVE", Format::Tag, Kind::DriveAxis, 0),
    motion_control(1),
];

/// The operands of a coordinate system's state instruction (MCSD, MCSR).
pub const SYSTEM_AND_CONTROL: &[Operand] = &[
    op(
        "Coordinate System",
        "COORDINATE_SYSTEM",
        Format::Tag,
        Kind::CoordinateSystem,
        0,
    ),
    motion_control(1),
];

/// The operands of a motion group instruction (MGSD, MGSR, MGSP): the
/// group and the control structure.
pub const GROUP_AND_CONTROL: &[Operand] = &[
    op("Group", "MOTION_GROUP", Format::Tag, Kind::Group, 0),
    motion_control(1),
];

/// An enumeration word and its code.
pub const fn w(word: &'static str, code: i64) -> Word {
    Word { word, code }
}

/// The data type text of an integer operand.
pub const INTEGER: &str = "SINT, INT, or DINT";
/// The data type text of a number operand.
pub const NUMERIC: &str = "SINT, INT, DINT, or REAL";

/// Speed Units of the coordinated moves and MAM: time- or master-driven.
pub const SPEED_UNITS: &[Word] = &[w("unitspersec", 0), w("%ofmaximum", 1), w("unitspermasterunit", 4)];
/// Accel and Decel Units of the coordinated moves.
pub const ACCEL_UNITS: &[Word] = &[
    w("unitspersec²", 0),
    w("unitspersec2", 0),
    w("%ofmaximum", 1),
    w("unitspermasterunit²", 4),
    w("unitspermasterunit2", 4),
];
/// Jerk Units of the coordinated moves.
pub const JERK_UNITS: &[Word] = &[
    w("unitspersec³", 0),
    w("unitspersec3", 0),
    w("%ofmaximum", 1),
    w("%oftime", 2),
    w("unitspermasterunit³", 4),
    w("unitspermasterunit3", 4),
    w("%oftimemasterdriven", 6),
];
/// Profile: trapezoidal or S-curve.
pub const PROFILE: &[Word] = &[w("trapezoidal", 0), w("s-curve", 1)];
/// Merge of the coordinated moves.
pub const MERGE: &[Word] = &[w("disabled", 0), w("coordinatedmotion", 1), w("allmotion", 2)];
/// Merge Speed.
pub const MERGE_SPEED: &[Word] = &[w("programmed", 0), w("current", 1)];
/// Lock Direction.
pub const LOCK_DIRECTION: &[Word] = &[
    w("none", 0),
    w("immediateforwardonly", 1),
    w("immediatereverseonly", 2),
    w("positionforward", 3),
    w("positionreverse", 4),
];
/// MCS's Stop Type.
pub const MCS_STOP_TYPE: &[Word] = &[w("all", 0), w("coordinatedmove", 1), w("coordinatedtransform", 2)];
/// MAR's Trigger Condition.
pub const MAR_TRIGGER: &[Word] = &[w("positive_edge", 0), w("negative_edge", 1)];
/// MAR's Windowed Registration.
pub const MAR_WINDOW: &[Word] = &[w("disabled", 0), w("enabled", 1)];
/// No / Yes (Change Decel, Change Decel Jerk).
pub const NO_YES: &[Word] = &[w("no", 0), w("yes", 1)];
/// Decel Units of a time-driven stop.
pub const TIME_DECEL_UNITS: &[Word] = &[w("unitspersec²", 0), w("unitspersec2", 0), w("%ofmaximum", 1)];
/// Jerk Units of a time-driven move or stop.
pub const TIME_JERK_UNITS: &[Word] = &[
    w("unitspersec³", 0),
    w("unitspersec3", 0),
    w("%ofmaximum", 1),
    w("%oftime", 2),
];
/// Direction of a cam or a gearing (MAPC, MAG).
pub const MAPC_DIRECTION: &[Word] = &[w("same", 0), w("opposite", 1), w("reverse", 2), w("unchanged", 3)];
/// MAPC's Execution Mode.
pub const EXECUTION_MODE: &[Word] = &[w("once", 0), w("continuous", 1), w("persistent", 2)];
/// MAPC's Execution Schedule.
pub const EXECUTION_SCHEDULE: &[Word] = &[
    w("immediate", 0),
    w("pending", 1),
    w("forwardonly", 2),
    w("reverseonly", 3),
    w("bidirectional", 4),
];
/// MAPC's Cam Type.
pub const CAM_TYPE: &[Word] = &[w("newcam", 0), w("replaceandrestart", 1), w("replaceandcontinue", 2)];
/// Actual or command position (Master Reference, Position Select).
pub const ACTUAL_COMMAND: &[Word] = &[w("actual", 0), w("command", 1)];
/// MAPC's Master Direction.
pub const MASTER_DIRECTION: &[Word] = &[w("bidirectional", 0), w("forwardonly", 1), w("reverseonly", 2)];
/// MRP's Type.
pub const MRP_TYPE: &[Word] = &[w("absolute", 0), w("relative", 1)];
/// MAJ's Direction.
pub const JOG_DIRECTION: &[Word] = &[w("forward", 0), w("reverse", 1)];
/// Speed Units of a single-axis move or jog (time-driven).
pub const JOG_SPEED_UNITS: &[Word] = &[w("unitspersec", 0), w("%ofmaximum", 1)];
/// Accel and Decel Units of a single-axis move, jog or stop.
pub const JOG_ACCEL_UNITS: &[Word] = &[w("unitspersec²", 0), w("unitspersec2", 0), w("%ofmaximum", 1)];
/// MAM's Merge.
pub const MAM_MERGE: &[Word] = &[w("disabled", 0), w("enabled", 1)];
/// MAS's Stop Type.
pub const MAS_STOP_TYPE: &[Word] = &[
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
/// MGS's Stop Mode.
pub const MGS_STOP_MODE: &[Word] = &[w("programmed", 0), w("faststop", 1), w("fastdisable", 2)];
/// MC_MoveModulo's Direction (PLCopen MC_Direction).
pub const MC_DIRECTION: &[Word] = &[
    w("MC_Positive_Direction", 1),
    w("MC_Shortest_Way", 2),
    w("MC_Negative_Direction", 3),
    w("MC_Current_Direction", 4),
];
/// MC_MoveModulo's BufferMode (PLCopen MC_BufferMode).
pub const MC_BUFFER_MODE: &[Word] = &[
    w("MC_Aborting", 0),
    w("MC_Buffered", 1),
    w("MC_BlendingLow", 2),
    w("MC_BlendingPrevious", 3),
    w("MC_BlendingNext", 4),
    w("MC_BlendingHigh", 5),
];
