//! The compiled form of a routine, a step's call or a scene expression:
//! names resolved to slots and planner handles, every expression typed,
//! every instruction call bound to its catalogue entry with its operands
//! as values or expressions, so that a scan does no lookups — the
//! interpreter only evaluates what the compiler produced.

use super::system::Attribute;
use super::types::{DataType, Structure, Ty, Value};
use crate::st::ast::{BinaryOp, CaseLabel};
use planner::task::instructions::Instruction;
use planner::task::{Arg, AxisHandle, CoordHandle, FbHandle, InstructionHandle};

/// A typed expression.
#[derive(Debug, Clone)]
pub struct CExpr {
    /// What it computes.
    pub kind: CKind,
    /// The type it computes in.
    pub ty: Ty,
}

/// The expression kinds.
#[derive(Debug, Clone)]
pub enum CKind {
    /// A constant.
    Const(Value),
    /// A read of one slot of tag memory (the common case of [`CKind::Load`]).
    Slot(usize),
    /// A read.
    Load(Box<Place>),
    /// `-x`.
    Neg(Box<CExpr>),
    /// `NOT x`.
    Not(Box<CExpr>),
    /// `a op b`, both operands computed in `math`.
    Binary(BinaryOp, Box<CExpr>, Box<CExpr>, Ty),
    /// `a op b op c …` (two operations or more), applied left to right:
    /// the source's operator chain kept flat, so that a sum of a thousand
    /// terms is one loop, not a thousand nested calls.
    Chain(Box<CExpr>, Box<[Link]>),
    /// A function of one argument.
    Func(Func, Box<CExpr>),
    /// The element index of several subscripts, each with its dimension
    /// (row-major), checked one by one; the array's name for the fault.
    Subscripts(Box<[(CExpr, usize)]>, String),
    /// A comparison of two strings (BOOL).
    StrCmp(BinaryOp, Box<(StrAt, StrAt)>),
}

/// One operation of a [`CKind::Chain`]: the value so far `op` the operand,
/// both computed in `math`.
#[derive(Debug, Clone)]
pub struct Link {
    /// The operator.
    pub op: BinaryOp,
    /// The right operand.
    pub operand: CExpr,
    /// The type both sides are computed in (`Bool` for logic).
    pub math: Ty,
}

/// The functions of the dialect.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Func {
    /// `ABS`.
    Abs,
    /// `SQRT` (of the absolute value, as the controller does).
    Sqrt,
    /// `SIN`.
    Sin,
    /// `COS`.
    Cos,
    /// `TAN`.
    Tan,
    /// `ASIN`.
    Asin,
    /// `ACOS`.
    Acos,
    /// `ATAN`.
    Atan,
    /// `LN`.
    Ln,
    /// `LOG` (base 10).
    Log,
    /// `DEG`.
    Deg,
    /// `RAD`.
    Rad,
    /// `TRUNC`.
    Trunc,
    /// `FRD`: a BCD value (eight digits in 32 bits) to an integer.
    Frd,
    /// `TOD`: an integer 0 to 99,999,999 to BCD.
    Tod,
}

impl Func {
    /// Every function's name, for messages.
    pub const NAMES: [&'static str; 15] = [
        "ABS", "SQRT", "SIN", "COS", "TAN", "ASIN", "ACOS", "ATAN", "LN", "LOG", "DEG", "RAD", "TRUNC", "FRD", "TOD",
    ];

    /// The function called `name` (case-insensitive).
    #[must_use]
    pub fn parse(name: &str) -> Option<Func> {
        Some(match name.to_ascii_uppercase().as_str() {
            "ABS" => Func::Abs,
            "SQRT" | "SQR" => Func::Sqrt,
            "SIN" => Func::Sin,
            "COS" => Func::Cos,
            "TAN" => Func::Tan,
            "ASIN" => Func::Asin,
            "ACOS" => Func::Acos,
            "ATAN" => Func::Atan,
            "LN" => Func::Ln,
            "LOG" => Func::Log,
            "DEG" => Func::Deg,
            "RAD" => Func::Rad,
            "TRUNC" => Func::Trunc,
            "FRD" => Func::Frd,
            "TOD" => Func::Tod,
            _ => return None,
        })
    }
}

/// Something a program reads or writes.
#[derive(Debug, Clone)]
pub enum Place {
    /// A slot of tag memory.
    Slot(usize),
    /// An element (or an element's member) of an array tag: `base +
    /// index × stride + offset`, the index checked against `len`.
    Element {
        /// First slot of the array.
        base: usize,
        /// Elements.
        len: usize,
        /// Slots an element.
        stride: usize,
        /// Slot offset of the member inside the element.
        offset: usize,
        /// The subscript.
        index: CExpr,
        /// The tag name, for the fault message.
        name: String,
    },
    /// A place inside a structure reached through computed subscripts
    /// (`Cell.Station[I].Pos[J]`): `base + Σ index × slots`, each index
    /// checked against its own length.
    Path {
        /// The slot with every constant offset folded in.
        base: usize,
        /// The computed subscripts, outermost first.
        terms: Box<[Term]>,
    },
    /// A bit of an integer place.
    Bit {
        /// The integer.
        inner: Box<Place>,
        /// Its width in bits (the bit number must be below it).
        width: u32,
        /// The bit number.
        bit: CExpr,
        /// The integer's type.
        ty: DataType,
    },
    /// A member of a `MOTION_INSTRUCTION` tag (bits writable, codes not).
    Motion(InstructionHandle, MotionMember),
    /// A member of the element of a `MOTION_INSTRUCTION` array a computed
    /// subscript names: every element's handle, the element index, the
    /// array's name for the fault.
    MotionAt(Box<[InstructionHandle]>, Box<CExpr>, MotionMember, String),
    /// An axis member (read-only).
    Axis(AxisHandle, AxisMember),
    /// A coordinate-system status bit (read-only).
    Coord(CoordHandle, CoordMember),
    /// A member of the motion group (read-only).
    Group(GroupMember),
    /// An output of a PLCopen function-block instance (read-only).
    Fb(FbHandle, FbMember),
    /// `S:FS`.
    FirstScan,
    /// `S:MINOR` (a minor fault was recorded in this scan).
    MinorInScan,
    /// `S:N`, `S:Z`, `S:V`, `S:C` (one of [`MATH_N`] …): set by ladder
    /// instructions only, read anywhere in the scan.
    MathFlag(u8),
    /// The `MinorFaults` counter.
    MinorFaults,
    /// A trace column an expectation reads (`J1.act_pos`), by its index
    /// in the values the caller passes ([`crate::output::trace::Values`]).
    Column {
        /// The column's index.
        index: usize,
        /// How its number reads: BOOL 0/1, an integer, a real.
        ty: DataType,
    },
}

/// `S:N`: the last math result was negative.
pub const MATH_N: u8 = 1;
/// `S:Z`: it was zero.
pub const MATH_Z: u8 = 2;
/// `S:V`: it overflowed (or did not fit its destination).
pub const MATH_V: u8 = 4;
/// `S:C`: an integer ADD or SUB carried (borrowed).
pub const MATH_C: u8 = 8;

/// A computed subscript on a path through structures.
#[derive(Debug, Clone)]
pub struct Term {
    /// The element index.
    pub index: CExpr,
    /// Elements (the index must be below it: major fault 4/20).
    pub len: usize,
    /// Slots an element takes.
    pub slots: usize,
    /// Bytes an element takes (for `COP`/`CPS`).
    pub bytes: usize,
    /// The array's name as written, for the fault message.
    pub name: String,
}

/// Where a `COP`/`CPS` operand starts: in which tag, at which slot and
/// byte of it (constant part, then the computed subscripts), and what
/// element type is there.
#[derive(Debug, Clone)]
pub struct DataAt {
    /// The tag's first slot.
    pub tag_base: usize,
    /// Bytes the whole tag takes.
    pub tag_bytes: usize,
    /// The tag's element type and element count.
    pub tag_elem: crate::program::layout::Elem,
    /// Its element count.
    pub tag_len: usize,
    /// Constant byte offset of the operand inside the tag.
    pub byte: usize,
    /// Computed subscripts (their `bytes` give the offset).
    pub terms: Box<[Term]>,
    /// The element type at the operand (Length counts Dest's elements).
    pub elem: crate::program::layout::Elem,
    /// The tag's name, for messages.
    pub name: String,
}

/// A name an expression may read besides the program's: a trace column.
#[derive(Debug, Clone, PartialEq)]
pub struct Column {
    /// The column's name (`J1.act_pos`, `collision.count`).
    pub name: String,
    /// Its type.
    pub ty: DataType,
    /// Whether the part before its last dot names the tag (axis,
    /// coordinate system, instruction, block, traced tag) the column
    /// belongs to (`J1.cmd_pos`, `MC1.PC`), rather than something that is
    /// not a tag (`time_s`, `collision.count`, `tool.clearance_m`): a tag
    /// of that name then means something else.
    pub of_tag: bool,
}

impl Place {
    /// The slot of element `index` of an [`Place::Element`], `None` when
    /// the index is out of range or the place is not an element.
    #[must_use]
    pub fn element_slot(&self, index: i64) -> Option<usize> {
        match self {
            Place::Element {
                base,
                len,
                stride,
                offset,
                ..
            } if (0..*len as i64).contains(&index) => Some(base + index as usize * stride + offset),
            _ => None,
        }
    }
}

/// The members of a `MOTION_INSTRUCTION`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MotionMember {
    /// A status bit by its name (`EN`, `DN`, `ER`, `IP`, `AC`, `PC`, …).
    Bit(&'static str),
    /// `ERR`.
    Err,
    /// `EXERR`.
    Exerr,
    /// `SEGMENT`.
    Segment,
}

/// The outputs of a PLCopen function block.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FbMember {
    /// A BOOL output by name (`Done`, `Busy`, `Active`, `CommandAborted`,
    /// `Error`).
    Bit(&'static str),
    /// `ErrorID`.
    ErrorId,
}

/// The axis members a program reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AxisMember {
    /// `ActualPosition` (one coarse update old).
    ActualPosition,
    /// `CommandPosition`.
    CommandPosition,
    /// `ActualVelocity`.
    ActualVelocity,
    /// `CommandVelocity`.
    CommandVelocity,
    /// `CommandAcceleration`.
    CommandAcceleration,
    /// `CoordinatedMotionStatus`.
    CoordinatedMotionStatus,
    /// `PositionCamStatus`.
    PositionCamStatus,
    /// `PositionCamLockStatus`.
    PositionCamLockStatus,
    /// `PositionCamPendingStatus`.
    PositionCamPendingStatus,
    /// `TransformStateStatus`.
    TransformStateStatus,
    /// `ControlledByTransformStatus`.
    ControlledByTransformStatus,
    /// `CIPAxisState`: the axis state ([`planner::servo::CipAxisState`]).
    CipAxisState,
    /// `AxisFault`: the fault word ([`planner::servo::AxisFaults`]).
    AxisFault,
    /// `ServoActionStatus`: the servo loop is closed.
    ServoActionStatus,
    /// `DriveEnableStatus`: the drive is enabled.
    DriveEnableStatus,
    /// `ShutdownStatus`: the axis is shut down.
    ShutdownStatus,
    /// `InhibitStatus`: the axis is inhibited.
    InhibitStatus,
    /// `AxisHomedStatus`: a homing sequence completed.
    AxisHomedStatus,
    /// `HomingStatus`: a homing sequence runs.
    HomingStatus,
    /// `MoveStatus`: a single-axis move runs.
    MoveStatus,
    /// `JogStatus`: a jog runs.
    JogStatus,
    /// `GearingStatus`: gearing is engaged.
    GearingStatus,
    /// `GearingLockStatus`: the slave is locked to its master (not while
    /// the MAG's clutch slips).
    GearingLockStatus,
    /// `StoppingStatus`: a stop ramps the axis.
    StoppingStatus,
    /// `MotionFault`: the soft overtravel word
    /// ([`planner::servo::MotionFaults`]).
    MotionFault,
    /// `SoftTravelLimitPositiveFault`: bit 1 of `MotionFault`.
    SoftTravelLimitPositiveFault,
    /// `SoftTravelLimitNegativeFault`: bit 2 of `MotionFault`.
    SoftTravelLimitNegativeFault,
    /// `SoftTravelLimitChecking`: the axis has soft travel limits.
    SoftTravelLimitChecking,
    /// `SoftTravelLimitPositive`, axis units (0 without limits).
    SoftTravelLimitPositive,
    /// `SoftTravelLimitNegative`, axis units (0 without limits).
    SoftTravelLimitNegative,
    /// `RegistrationNPosition`: the actual position latched by input N's
    /// last registration event (MAR).
    RegistrationPosition(u8),
    /// `RegEventNStatus`: input N's registration event occurred.
    RegEventStatus(u8),
    /// `RegEventNArmedStatus`: input N is armed.
    RegEventArmedStatus(u8),
    /// `TimeCamStatus`: a time cam (MATC) drives the axis.
    TimeCamStatus,
    /// `TimeCamPendingStatus`: a time cam waits to.
    TimeCamPendingStatus,
    /// `WatchEventArmedStatus`: a MAW armed the watch.
    WatchEventArmedStatus,
    /// `WatchEventStatus`: the watch event occurred.
    WatchEventStatus,
    /// `WatchPosition`: the watch's set-point.
    WatchPosition,
    /// `StrobeActualPosition`: the actual position the last MGSP latched.
    StrobeActualPosition,
    /// `StrobeCommandPosition`: the command position the last MGSP
    /// latched.
    StrobeCommandPosition,
}

/// Every axis member, with its name and type, for parsing and docs.
pub const AXIS_MEMBERS: [(&str, AxisMember, DataType); 43] = [
    ("ActualPosition", AxisMember::ActualPosition, DataType::Real),
    ("CommandPosition", AxisMember::CommandPosition, DataType::Real),
    ("ActualVelocity", AxisMember::ActualVelocity, DataType::Real),
    ("CommandVelocity", AxisMember::CommandVelocity, DataType::Real),
    ("CommandAcceleration", AxisMember::CommandAcceleration, DataType::Real),
    (
        "CoordinatedMotionStatus",
        AxisMember::CoordinatedMotionStatus,
        DataType::Bool,
    ),
    ("PositionCamStatus", AxisMember::PositionCamStatus, DataType::Bool),
    (
        "PositionCamLockStatus",
        AxisMember::PositionCamLockStatus,
        DataType::Bool,
    ),
    (
        "PositionCamPendingStatus",
        AxisMember::PositionCamPendingStatus,
        DataType::Bool,
    ),
    ("TransformStateStatus", AxisMember::TransformStateStatus, DataType::Bool),
    (
        "ControlledByTransformStatus",
        AxisMember::ControlledByTransformStatus,
        DataType::Bool,
    ),
    ("CIPAxisState", AxisMember::CipAxisState, DataType::Dint),
    ("AxisFault", AxisMember::AxisFault, DataType::Dint),
    ("ServoActionStatus", AxisMember::ServoActionStatus, DataType::Bool),
    ("DriveEnableStatus", AxisMember::DriveEnableStatus, DataType::Bool),
    ("ShutdownStatus", AxisMember::ShutdownStatus, DataType::Bool),
    ("InhibitStatus", AxisMember::InhibitStatus, DataType::Bool),
    ("AxisHomedStatus", AxisMember::AxisHomedStatus, DataType::Bool),
    ("HomingStatus", AxisMember::HomingStatus, DataType::Bool),
    ("MoveStatus", AxisMember::MoveStatus, DataType::Bool),
    ("JogStatus", AxisMember::JogStatus, DataType::Bool),
    ("GearingStatus", AxisMember::GearingStatus, DataType::Bool),
    ("GearingLockStatus", AxisMember::GearingLockStatus, DataType::Bool),
    ("StoppingStatus", AxisMember::StoppingStatus, DataType::Bool),
    ("TimeCamStatus", AxisMember::TimeCamStatus, DataType::Bool),
    ("TimeCamPendingStatus", AxisMember::TimeCamPendingStatus, DataType::Bool),
    (
        "WatchEventArmedStatus",
        AxisMember::WatchEventArmedStatus,
        DataType::Bool,
    ),
    ("WatchEventStatus", AxisMember::WatchEventStatus, DataType::Bool),
    ("WatchPosition", AxisMember::WatchPosition, DataType::Real),
    ("StrobeActualPosition", AxisMember::StrobeActualPosition, DataType::Real),
    (
        "StrobeCommandPosition",
        AxisMember::StrobeCommandPosition,
        DataType::Real,
    ),
    ("MotionFault", AxisMember::MotionFault, DataType::Dint),
    (
        "SoftTravelLimitPositiveFault",
        AxisMember::SoftTravelLimitPositiveFault,
        DataType::Bool,
    ),
    (
        "SoftTravelLimitNegativeFault",
        AxisMember::SoftTravelLimitNegativeFault,
        DataType::Bool,
    ),
    (
        "SoftTravelLimitChecking",
        AxisMember::SoftTravelLimitChecking,
        DataType::Bool,
    ),
    (
        "SoftTravelLimitPositive",
        AxisMember::SoftTravelLimitPositive,
        DataType::Real,
    ),
    (
        "SoftTravelLimitNegative",
        AxisMember::SoftTravelLimitNegative,
        DataType::Real,
    ),
    (
        "Registration1Position",
        AxisMember::RegistrationPosition(1),
        DataType::Real,
    ),
    (
        "Registration2Position",
        AxisMember::RegistrationPosition(2),
        DataType::Real,
    ),
    ("RegEvent1Status", AxisMember::RegEventStatus(1), DataType::Bool),
    ("RegEvent2Status", AxisMember::RegEventStatus(2), DataType::Bool),
    (
        "RegEvent1ArmedStatus",
        AxisMember::RegEventArmedStatus(1),
        DataType::Bool,
    ),
    (
        "RegEvent2ArmedStatus",
        AxisMember::RegEventArmedStatus(2),
        DataType::Bool,
    ),
];

/// The motion group's members a program reads
/// ([`planner::task::group`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GroupMember {
    /// A status word (`GroupStatus`, `MotionFault`, `ServoFault`,
    /// `GroupFault`, `AxisFault`), DINT.
    Word(GroupWord),
    /// A BOOL member for a bit of `GroupStatus` (`InhibStatus` 0,
    /// `GroupSynced` 1, `AxisInhibitStatus` 2).
    StatusBit(u32),
}

/// The motion group's status words.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GroupWord {
    /// `GroupStatus`.
    GroupStatus,
    /// `MotionFault`.
    MotionFault,
    /// `ServoFault`.
    ServoFault,
    /// `GroupFault`.
    GroupFault,
    /// `AxisFault`.
    AxisFault,
}

/// Every member of a `MOTION_GROUP` a program reads, with its name.
pub const GROUP_MEMBERS: [(&str, GroupMember); 8] = [
    ("GroupStatus", GroupMember::Word(GroupWord::GroupStatus)),
    ("InhibStatus", GroupMember::StatusBit(0)),
    ("GroupSynced", GroupMember::StatusBit(1)),
    ("AxisInhibitStatus", GroupMember::StatusBit(2)),
    ("MotionFault", GroupMember::Word(GroupWord::MotionFault)),
    ("ServoFault", GroupMember::Word(GroupWord::ServoFault)),
    ("GroupFault", GroupMember::Word(GroupWord::GroupFault)),
    ("AxisFault", GroupMember::Word(GroupWord::AxisFault)),
];

/// Coordinate-system status bits.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CoordMember {
    /// A bit of the planner's coordinate-system status by name.
    Status(&'static str),
    /// `TransformSourceStatus`.
    TransformSource,
    /// `TransformTargetStatus`.
    TransformTarget,
}

/// A structure instance: a tag, or an element of an array of them.
#[derive(Debug, Clone)]
pub struct Instance {
    /// First slot of the tag.
    pub base: usize,
    /// The structure.
    pub structure: Structure,
    /// `(subscript, length)` for an element of an array.
    pub index: Option<(CExpr, usize)>,
    /// The computed subscripts of a member of a data type (`Station[I].Delay`).
    pub terms: Box<[Term]>,
    /// The tag name, for fault messages.
    pub name: String,
}

/// The general (not motion) instructions a routine calls: timers,
/// counters, one-shots, routine calls, array and system-value
/// instructions. [`General::find`] is the one lookup of their names.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum General {
    /// A timer, counter, one-shot or edge instruction on its structure.
    Builtin(Builtin),
    /// `JSR`.
    Jsr,
    /// `SBR`.
    Sbr,
    /// `RET`.
    Ret,
    /// `COP`.
    Cop,
    /// `CPS`.
    Cps,
    /// `FLL`.
    Fll,
    /// `SIZE`.
    Size,
    /// `GSV`.
    Gsv,
    /// `SSV`.
    Ssv,
    /// `EVENT`.
    Event,
    /// A string instruction (1756-RM003, ASCII string and conversion
    /// instructions).
    Str(StrOp),
}

/// The string instructions.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StrOp {
    /// `CONCAT(SourceA, SourceB, Dest)`.
    Concat,
    /// `MID(Source, Qty, Start, Dest)`.
    Mid,
    /// `FIND(Source, Search, Start, Result)`.
    Find,
    /// `INSERT(SourceA, SourceB, Start, Dest)`.
    Insert,
    /// `DELETE(Source, Qty, Start, Dest)`.
    Delete,
    /// `UPPER(Source, Dest)`.
    Upper,
    /// `LOWER(Source, Dest)`.
    Lower,
    /// `DTOS(Source, Dest)`.
    Dtos,
    /// `STOD(Source, Dest)`.
    Stod,
    /// `RTOS(Source, Dest)`.
    Rtos,
    /// `STOR(Source, Dest)`.
    Stor,
}

/// A string operand: where its `LEN` is (constant part, then the computed
/// subscripts) and how many characters its `DATA` holds.
#[derive(Debug, Clone)]
pub struct StrAt {
    /// The slot of `LEN`, constant offsets folded in (`DATA[i]` follows at
    /// `+ 1 + i`).
    pub base: usize,
    /// Computed subscripts on the way.
    pub terms: Box<[Term]>,
    /// `DATA`'s length.
    pub capacity: usize,
    /// The operand as written, for messages.
    pub name: String,
}

/// The operands of a string instruction.
#[derive(Debug, Clone)]
pub enum StrArgs {
    /// `CONCAT(A, B, Dest)`; `INSERT(A, B, Start, Dest)` with its Start.
    Join(StrAt, StrAt, Option<CExpr>, StrAt),
    /// `MID` and `DELETE`: Source, Qty, Start, Dest.
    Cut(StrAt, CExpr, CExpr, StrAt),
    /// `FIND(Source, Search, Start, Result)`.
    Find(StrAt, StrAt, CExpr, Place, DataType),
    /// `UPPER`, `LOWER`: Source, Dest.
    Case(StrAt, StrAt),
    /// `DTOS`, `RTOS`: a number into a string.
    FromNumber(CExpr, StrAt),
    /// `STOD`, `STOR`: a string into a number.
    ToNumber(StrAt, Place, DataType),
}

/// Every general instruction by its name.
pub const GENERAL: [(&str, General); 31] = [
    ("TONR", General::Builtin(Builtin::Tonr)),
    ("TOFR", General::Builtin(Builtin::Tofr)),
    ("RTOR", General::Builtin(Builtin::Rtor)),
    ("CTUD", General::Builtin(Builtin::Ctud)),
    ("OSRI", General::Builtin(Builtin::Osri)),
    ("OSFI", General::Builtin(Builtin::Osfi)),
    ("R_TRIG", General::Builtin(Builtin::RTrig)),
    ("F_TRIG", General::Builtin(Builtin::FTrig)),
    ("TON", General::Builtin(Builtin::Ton)),
    ("TOF", General::Builtin(Builtin::Tof)),
    ("JSR", General::Jsr),
    ("SBR", General::Sbr),
    ("RET", General::Ret),
    ("COP", General::Cop),
    ("CPS", General::Cps),
    ("FLL", General::Fll),
    ("SIZE", General::Size),
    ("GSV", General::Gsv),
    ("SSV", General::Ssv),
    ("EVENT", General::Event),
    ("CONCAT", General::Str(StrOp::Concat)),
    ("MID", General::Str(StrOp::Mid)),
    ("FIND", General::Str(StrOp::Find)),
    ("INSERT", General::Str(StrOp::Insert)),
    ("DELETE", General::Str(StrOp::Delete)),
    ("UPPER", General::Str(StrOp::Upper)),
    ("LOWER", General::Str(StrOp::Lower)),
    ("DTOS", General::Str(StrOp::Dtos)),
    ("STOD", General::Str(StrOp::Stod)),
    ("RTOS", General::Str(StrOp::Rtos)),
    ("STOR", General::Str(StrOp::Stor)),
];

impl General {
    /// The general instruction called `name` (case-insensitive).
    #[must_use]
    pub fn find(name: &str) -> Option<General> {
        GENERAL
            .iter()
            .find(|(n, _)| n.eq_ignore_ascii_case(name))
            .map(|(_, g)| *g)
    }

    /// Its name.
    #[must_use]
    pub fn name(self) -> &'static str {
        GENERAL.iter().find(|(_, g)| *g == self).map_or("?", |(n, _)| n)
    }
}

/// The timer and edge instructions.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Builtin {
    /// `TONR`.
    Tonr,
    /// `TOFR`.
    Tofr,
    /// `RTOR`.
    Rtor,
    /// `CTUD`.
    Ctud,
    /// `OSRI`.
    Osri,
    /// `OSFI`.
    Osfi,
    /// `R_TRIG` (IEC).
    RTrig,
    /// `F_TRIG` (IEC).
    FTrig,
    /// `TON` (IEC).
    Ton,
    /// `TOF` (IEC).
    Tof,
}

impl Builtin {
    /// The structure it works on.
    #[must_use]
    pub fn structure(self) -> Structure {
        match self {
            Builtin::Tonr | Builtin::Tofr | Builtin::Rtor => Structure::Timer,
            Builtin::Ctud => Structure::Counter,
            Builtin::Osri | Builtin::Osfi => Structure::OneShot,
            Builtin::RTrig | Builtin::FTrig => Structure::Trig,
            Builtin::Ton | Builtin::Tof => Structure::IecTimer,
        }
    }

    /// Whether it is an IEC 61131-3 block Studio 5000 does not have.
    #[must_use]
    pub fn iec_only(self) -> bool {
        matches!(self, Builtin::RTrig | Builtin::FTrig | Builtin::Ton | Builtin::Tof)
    }
}

/// An array operand: a tag and its first element.
#[derive(Debug, Clone)]
pub struct ArrayAt {
    /// First slot of the tag.
    pub base: usize,
    /// Elements.
    pub len: usize,
    /// Start element.
    pub start: CExpr,
    /// Element type.
    pub ty: DataType,
    /// The tag name, for fault messages.
    pub name: String,
}

/// One operand of an instruction call, in catalogue order: what the call
/// gives the instruction when it executes.
#[derive(Debug, Clone)]
pub enum Operand {
    /// Known when the program loads: a handle (axis, coordinate system,
    /// control structure, cam profile), an enumeration word's code, a
    /// constant, `0` for an optional array, or an input a named call
    /// leaves out ([`Arg::Absent`]).
    Fixed(Arg<'static>),
    /// A number computed when the instruction executes.
    Number(CExpr),
    /// An integer (an integer operand, a code, a count), computed when the
    /// instruction executes; a REAL rounds half to even, as on assignment.
    Integer(CExpr),
    /// A BOOL computed when the instruction executes.
    Bool(CExpr),
    /// The elements of a numeric array from a subscript to the array's end.
    Array(ArrayAt),
    /// One number where an array is expected (a radius): a one-element array.
    Scalar(CExpr),
    /// A CAM array and the element it starts at.
    Cam(ArrayAt),
    /// An array of an instruction structure (`OUTPUT_CAM`,
    /// `OUTPUT_COMPENSATION`) and the element it starts at.
    Structures(ArrayAt, crate::program::types::Structure),
    /// Numbers known at load: a `[[program]]` step's array operand, read
    /// from the scene's tag values.
    Values(Vec<f64>),
    /// CAM elements known at load (a step's Cam operand), the whole array
    /// and the element the operand starts at.
    CamPoints(Vec<planner::mccp::CamElement>, usize),
    /// The element of a `MOTION_INSTRUCTION` array a computed subscript
    /// names: every element's handle, the element index, the array's name.
    ControlAt(Box<[InstructionHandle]>, CExpr, String),
}

/// An instruction call: its catalogue entry and its operands.
#[derive(Debug, Clone)]
pub struct MotionCall {
    /// The catalogue entry.
    pub instruction: &'static Instruction,
    /// The operands, one per catalogue operand.
    pub operands: Vec<Operand>,
    /// Its control structure, if it has one.
    pub control: Option<InstructionHandle>,
    /// The function-block instance a named call runs on.
    pub instance: Option<FbHandle>,
}

/// A compiled statement.
#[derive(Debug, Clone)]
pub struct CStmt {
    /// What it does.
    pub kind: SKind,
    /// Its line in the routine.
    pub line: u32,
}

/// The statement kinds.
#[derive(Debug, Clone)]
pub enum SKind {
    /// `target := value` (`retentive` false for `[:=]`).
    Assign {
        /// The target.
        target: Place,
        /// The target's type.
        ty: DataType,
        /// The value.
        value: CExpr,
        /// `false` for `[:=]`: cleared at prescan.
        retentive: bool,
    },
    /// IF.
    If(Vec<(CExpr, Vec<CStmt>)>, Vec<CStmt>),
    /// CASE.
    Case(CExpr, Vec<(Vec<CaseLabel>, Vec<CStmt>)>, Vec<CStmt>),
    /// FOR.
    For {
        /// The counter.
        counter: Place,
        /// Its type.
        ty: DataType,
        /// From.
        from: CExpr,
        /// To.
        to: CExpr,
        /// By.
        by: CExpr,
        /// Body.
        body: Vec<CStmt>,
    },
    /// WHILE.
    While(CExpr, Vec<CStmt>),
    /// REPEAT … UNTIL.
    Repeat(Vec<CStmt>, CExpr),
    /// EXIT.
    Exit,
    /// A timer, counter or edge instruction on its structure.
    Builtin(Builtin, Instance),
    /// `JSR(routine, n, inputs…, returns…)`.
    Jsr {
        /// Routine index in the program.
        routine: usize,
        /// Input values.
        inputs: Vec<CExpr>,
        /// Where the returned values go, with their types.
        returns: Vec<(Place, DataType)>,
    },
    /// `SBR(params…)`: the inputs of the JSR that called this routine.
    Sbr(Vec<(Place, DataType)>),
    /// `RET(values…)`: leaves the routine, handing the values back.
    Ret(Vec<CExpr>),
    /// `COP`/`CPS`: copies `len` elements.
    Cop(ArrayAt, ArrayAt, CExpr),
    /// A string instruction.
    Str(StrOp, Box<StrArgs>),
    /// `COP`/`CPS` across types or of structures: copies Length × the
    /// destination element's bytes, through the controller's byte layout.
    CopBytes(Box<DataAt>, Box<DataAt>, CExpr),
    /// `FLL`: fills `len` elements with a value.
    Fll(CExpr, ArrayAt, CExpr),
    /// `FLL` into a structure, a member array or across types: the
    /// Source's bytes (as its type stores them) repeated over Length × the
    /// destination element's bytes.
    FllBytes(CExpr, Box<DataAt>, CExpr),
    /// `SIZE(array, 0, dest)`.
    Size(usize, Place, DataType),
    /// `GSV(AXIS, axis, attribute, dest)`.
    Gsv(AxisHandle, GsvAttribute, Place, DataType),
    /// `SSV(AXIS, axis, attribute, source)`.
    Ssv(AxisHandle, SsvAttribute, CExpr),
    /// `GSV` of a system object (TASK, PROGRAM, WALLCLOCKTIME, FAULTLOG,
    /// MOTIONGROUP) into a tag.
    SysGet(&'static Attribute, Object, SysData),
    /// `SSV` of a system object from a tag or value.
    SysSet(&'static Attribute, Object, SysData),
    /// `EVENT(Task)`: triggers an event task (its index).
    Event(usize),
    /// A motion instruction, or a PLCopen function block called on its
    /// instance with named inputs (IEC dialect; the inputs it names are set
    /// at every execution).
    Motion(MotionCall),
    /// A ladder instruction, on the rung condition.
    Ladder(Box<Ladder>),
}

/// A ladder instruction compiled: what it does with the rung condition
/// (`crate::program::exec`'s ladder module holds the rules, 1756-RM003).
#[derive(Debug, Clone)]
pub enum Ladder {
    /// A rung starts (its number): the condition is TRUE, FALSE inside a
    /// disabled MCR zone.
    Start(u32),
    /// A rung ends: its condition-out is traced into this slot.
    End(Option<usize>),
    /// `[`: the condition is kept for every leg.
    Open,
    /// `,`: the next leg starts from the branch's condition.
    Leg,
    /// `]`: the condition is the OR of the legs'.
    Close,
    /// An input instruction: the condition AND this BOOL (XIC, XIO, EQU …
    /// CMP, MEQ).
    Examine(CExpr),
    /// `LIM(Low, Test, High)`.
    Lim(CExpr, CExpr, CExpr),
    /// `AFI`: the condition is FALSE.
    Afi,
    /// `OTE`, `OTL`, `OTU`.
    Output(OutputKind, Place),
    /// `ONS(Storage)`.
    Ons(Place),
    /// `OSR(Storage, Output)` (`rising`) or `OSF`.
    Edge {
        /// OSR.
        rising: bool,
        /// The storage bit.
        storage: Place,
        /// The output bit.
        output: Place,
    },
    /// TON, TOF, RTO on a `TIMER`.
    Timer(TimerKind, Instance),
    /// CTU (`up`) or CTD on a `COUNTER`.
    Counter(bool, Instance),
    /// `RES` of a TIMER, COUNTER or CONTROL.
    Res(Instance),
    /// A math, move or logic instruction: when the rung is TRUE, `target
    /// := value`, setting the math flags `flags` names (`carry`: the ADD or
    /// SUB whose carry `S:C` is).
    Compute {
        /// The destination.
        target: Place,
        /// Its type.
        ty: DataType,
        /// The result.
        value: CExpr,
        /// The flags it sets ([`MATH_N`] …).
        flags: u8,
        /// An integer ADD (`Some(true)`) or SUB: the operands, for `S:C`.
        carry: Option<(bool, CExpr, CExpr)>,
    },
    /// `SWPB(Source, Order Mode, Dest)`.
    Swpb(CExpr, SwapOrder, Place, DataType),
    /// `BTD(Source, Source Bit, Dest, Dest Bit, Length)`.
    Btd {
        /// The source.
        source: CExpr,
        /// Its first bit.
        source_bit: CExpr,
        /// The destination.
        dest: Place,
        /// Its type.
        ty: DataType,
        /// Its first bit.
        dest_bit: CExpr,
        /// Bits moved.
        length: CExpr,
    },
    /// An instruction the Structured Text engine executes (JSR, COP, FLL,
    /// GSV …), when the rung is TRUE.
    OnTrue(SKind),
    /// A motion instruction: executed on the rung's false-to-true
    /// transition (its `.EN` clear), `.EN` cleared on a false rung once
    /// `.DN` or `.ER` is set (MOTION-RM002).
    Motion(MotionCall),
    /// `JMP(Label)`: to the statement of the rung the label starts.
    Jmp(usize),
    /// `TND`: the routine ends here.
    Tnd,
    /// `MCR`: opens a zone (enabled by the condition) or closes the open one.
    Mcr,
    /// `BSL`/`BSR` (`left`) on a `CONTROL`.
    Shift {
        /// BSL.
        left: bool,
        /// The DINT array (its first word).
        array: ArrayAt,
        /// The control.
        control: Instance,
        /// The bit shifted in.
        source: CExpr,
    },
    /// `FFL`/`LFL` (load) and `FFU`/`LFU` (unload) on a `CONTROL`.
    Stack {
        /// What it does.
        kind: StackKind,
        /// The FIFO/LIFO array (its first element).
        array: ArrayAt,
        /// The control.
        control: Instance,
        /// The value loaded (FFL, LFL), or where the unloaded one goes.
        value: StackValue,
    },
}

/// The output instructions.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OutputKind {
    /// `OTE`: the bit is the condition.
    Energize,
    /// `OTL`: set on a TRUE rung.
    Latch,
    /// `OTU`: cleared on a TRUE rung.
    Unlatch,
}

/// The ladder timers.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TimerKind {
    /// `TON`.
    On,
    /// `TOF`.
    Off,
    /// `RTO`.
    Retentive,
}

/// SWPB's order modes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SwapOrder {
    /// `REVERSE`: the bytes in reverse order.
    Reverse,
    /// `WORD`: the two words swapped.
    Word,
    /// `HIGH/LOW`: the bytes of each word swapped.
    HighLow,
}

/// FIFO and LIFO instructions.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StackKind {
    /// `FFL`.
    FifoLoad,
    /// `FFU`.
    FifoUnload,
    /// `LFL`.
    LifoLoad,
    /// `LFU`.
    LifoUnload,
}

/// What a FIFO/LIFO instruction moves.
#[derive(Debug, Clone)]
pub enum StackValue {
    /// The Source loaded.
    Load(CExpr),
    /// Where the unloaded element goes.
    Unload(Place, DataType),
}

/// The object a system `GSV`/`SSV` names.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Object {
    /// `THIS`: the scanning task or program.
    This,
    /// A task's or program's index.
    Index(usize),
    /// The class' one object.
    Single,
}

/// Where a system attribute's value goes to or comes from.
#[derive(Debug, Clone)]
pub enum SysData {
    /// One value into a tag (GSV).
    Target(Place, DataType),
    /// One value from an expression (SSV).
    Value(CExpr),
    /// Several DINTs from an array element on (both).
    Words(ArrayAt),
}

/// What `GSV` of an `AXIS` attribute reads
/// ([`crate::program::axis_attributes`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum GsvAttribute {
    /// A member also readable as `Axis.Member`.
    Member(AxisMember),
    /// A planner configuration attribute.
    Config(planner::axis::AxisLimit),
    /// A fixed property, known at load.
    Const(Value),
    /// A drive attribute of the axis at this index of the scene's axes.
    Drive(usize, crate::program::axis_attributes::DriveAttr),
}

/// What `SSV` of an `AXIS` attribute sets.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SsvAttribute {
    /// A planner configuration attribute.
    Config(planner::axis::AxisLimit),
    /// A drive attribute of the axis at this index of the scene's axes.
    Drive(usize, crate::program::axis_attributes::DriveAttr),
}

/// A program's routines, compiled (main first), with the files they came
/// from.
#[derive(Debug, Clone)]
pub struct CompiledProgram {
    /// The program's name.
    pub name: String,
    /// Each routine's file.
    pub routine_paths: Vec<std::path::PathBuf>,
    /// Each routine's statements.
    pub routines: Vec<Vec<CStmt>>,
    /// Slots the ladder routines' display operands set at load (a
    /// timer's `PRE` written in its rung).
    pub init: Vec<(usize, Value, crate::source::Span)>,
    /// The first routine an Add-On Instruction call site added (the
    /// routines from here on are instructions'); `routines.len()` when
    /// none.
    pub aoi_from: usize,
    /// The instructions' Prescan routines (their indices), run at
    /// prescan.
    pub aoi_prescan: Vec<usize>,
}

/// A routine an Add-On Instruction call site adds to its program.
#[derive(Debug, Clone)]
pub struct AoiRoutine {
    /// The file its statements' lines are in (the instruction's export).
    pub path: std::path::PathBuf,
    /// Its statements.
    pub body: Vec<CStmt>,
    /// Whether it is an instruction's Prescan routine, run at prescan.
    pub prescan: bool,
}

/// A `[[program]]` step, compiled: when it fires and the call it executes.
#[derive(Debug, Clone)]
pub struct CompiledStep {
    /// When it fires.
    pub trigger: StepTrigger,
    /// The call it executes.
    pub call: MotionCall,
    /// Its index in the scene's `[[program]]`.
    pub index: usize,
}

/// When a step fires.
#[derive(Debug, Clone)]
pub enum StepTrigger {
    /// At a time, s.
    At(f64),
    /// `delay_s` after its condition is first TRUE (once armed).
    When {
        /// The condition.
        condition: CExpr,
        /// Delay, s.
        delay_s: f64,
    },
}
