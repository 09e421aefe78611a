//! The instruction catalogue: every Logix instruction and PLCopen function
//! block the product accepts, described once.
//!
//! Each [`Instruction`] lists its operands in the order a Structured Text
//! call writes them, and for each operand:
//! * its name, data type and **Format** column as the manual prints them
//!   ([`Format`] decides whether a bad value is refused when the program is
//!   loaded or reported by the instruction at run time with ERR 13);
//! * what it holds ([`Kind`]): a tag of a motion type, a number, an array,
//!   or an enumeration with its words and their codes *for this operand*
//!   (the same word has different codes in different operands; words are
//!   compared case-insensitively, [`Word`]);
//! * its faceplate index, counted from zero over the ladder faceplate
//!   including the axis / coordinate-system and motion-control slots: the
//!   EXERR of ERR 13 (Parameter Out Of Range). The faceplate order is not
//!   always the call order: MCCM's faceplate puts Termination Type, Merge
//!   and Merge Speed before the jerks (its document's EXERR table gives
//!   Termination Type 14).
//!
//! The Structured Text call checks, the binding of calls to the planner,
//! the instructions' ERR 13 EXERR numbers, error messages and the operand
//! lists in `scenes/README.md` all derive from this table.
//!
//! # Choices where the documents are silent
//! * MCS, MAJ and MAS are not among the specification documents; their
//!   operands, formats and words follow the Logix motion reference. MAJ and
//!   MAS take only their first ten / six operands (the jerk, merge and lock
//!   operands are not simulated), and MAJ's units per master unit are not
//!   simulated (its Speed Units words are those of a time-driven jog).
//! * MC_MoveModulo's inputs have no faceplate index (PLCopen blocks report
//!   `ErrorID`, not EXERR); their format is [`Format::Input`].
//!
//! # Examples
//! ```
//! use planner::catalogue::{self, Format};
//!
//! let mccm = catalogue::find("mccm").unwrap();
//! assert_eq!(mccm.operands.len(), 25);
//! assert_eq!(catalogue::MCCM.exerr("Termination Type"), 14);
//! let units = mccm.operand("Jerk Units").unwrap().1;
//! assert_eq!(units.format, Format::ImmediateOrTag);
//! assert_eq!(units.code_of("%ofTime"), Some(2));
//! ```

/// How an operand may be given, as the manual's Format column says.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// A tag of the operand's data type (an axis, a control structure).
    Tag,
    /// A constant. An enumeration value outside the operand's codes is
    /// refused when the program is loaded, as the controller's verifier
    /// refuses it.
    Immediate,
    /// A constant or a tag. A value out of range reaches the instruction,
    /// which fails at run time with ERR 13 and EXERR = the faceplate index.
    ImmediateOrTag,
    /// An array tag or an element of one (`Pos[0]`: the array from there).
    Array,
    /// An input of a PLCopen function block (`VAR_INPUT`), given by name;
    /// enumeration values are checked when the program is loaded.
    Input,
}

impl Format {
    /// The Format column's text.
    pub fn name(self) -> &'static str {
        match self {
            Self::Tag => "Tag",
            Self::Immediate => "Immediate",
            Self::ImmediateOrTag => "Immediate or Tag",
            Self::Array => "Array",
            Self::Input => "Input",
        }
    }
}

/// One enumeration word and its code in one operand.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Word {
    /// The word as Structured Text writes it (compared case-insensitively).
    pub word: &'static str,
    /// Its numeric code.
    pub code: i64,
}

/// What an operand holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// An axis tag.
    Axis,
    /// A `COORDINATE_SYSTEM` tag.
    CoordinateSystem,
    /// A `MOTION_INSTRUCTION` tag (the control structure).
    MotionControl,
    /// A `CAM` array tag or element.
    Cam,
    /// A `CAM_PROFILE` array tag (element `[0]` only).
    CamProfile,
    /// A number (REAL or integer).
    Number,
    /// A non-negative integer count (UINT).
    Count,
    /// An integer code the manual lists without words (Move Type …).
    Integer,
    /// A boolean (`TRUE` / `FALSE`).
    Bool,
    /// An enumeration: one of these words, or an integer code.
    Enumeration(&'static [Word]),
    /// A REAL array from the given element to its end (`Pos[0]`); for
    /// Via/Center/Radius also a single number (the radius).
    Values,
    /// Three REALs from an array element (`REAL[3]`).
    Vector3,
    /// `0` (none) or a REAL array tag.
    OptionalArray,
}

impl Kind {
    /// The enumeration words (empty for other kinds).
    pub fn words(self) -> &'static [Word] {
        match self {
            Self::Enumeration(words) => words,
            _ => &[],
        }
    }
}

/// One operand of an instruction.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Operand {
    /// The manual's name (`Speed Units`).
    pub name: &'static str,
    /// The data type column (`SINT, INT, or DINT`).
    pub data_type: &'static str,
    /// The Format column.
    pub format: Format,
    /// What it holds.
    pub kind: Kind,
    /// Index on the faceplate counted from zero: the EXERR of ERR 13
    /// (−1 where the instruction reports none).
    pub faceplate: i32,
}

impl Operand {
    /// The code of an enumeration word (case-insensitive), `None` when the
    /// operand has no such word.
    pub fn code_of(&self, word: &str) -> Option<i64> {
        self.kind
            .words()
            .iter()
            .find(|w| w.word.eq_ignore_ascii_case(word))
            .map(|w| w.code)
    }

    /// Whether `code` is one of the enumeration's codes.
    pub fn has_code(&self, code: i64) -> bool {
        self.kind.words().iter().any(|w| w.code == code)
    }

    /// The words with their codes, for messages and docs:
    /// `unitspersec (0), %ofmaximum (1)`.
    pub fn word_list(&self) -> String {
        let list: Vec<String> = self
            .kind
            .words()
            .iter()
            .map(|w| format!("{} ({})", w.word, w.code))
            .collect();
        list.join(", ")
    }
}

/// How a program calls an instruction.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CallStyle {
    /// A Logix instruction: operands by position, `MCLM(CS1, MC1, …)`.
    Positional,
    /// A PLCopen function block called on an instance tag with named
    /// inputs, `Move(Axis := Table, Execute := TRUE, …)`.
    Named,
}

/// The instruction families, each bound to the planner by one binding file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Family {
    /// Coordinated motion: MCLM, MCCM, MCS.
    Coordinated,
    /// Coordinate transforms: MCT.
    Transform,
    /// Cams and the single-axis calls: MCCP, MAPC, MRP, MAJ, MAS, MAM, MAG.
    Cam,
    /// PLCopen single-axis blocks: MC_MoveModulo.
    PlcOpen,
    /// Axis and coordinate-system states: MSO, MSF, MASD, MASR, MAFR,
    /// MCSD, MCSR, and homing (MAH).
    State,
}

/// One instruction the product accepts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Instruction {
    /// Mnemonic or block type (`MCCM`, `MC_MoveModulo`).
    pub mnemonic: &'static str,
    /// The manual's title.
    pub title: &'static str,
    /// How it is called.
    pub style: CallStyle,
    /// Its family.
    pub family: Family,
    /// Operands in call order.
    pub operands: &'static [Operand],
}

impl Instruction {
    /// The operand called `name` (case-insensitive) with its call position.
    pub fn operand(&self, name: &str) -> Option<(usize, &'static Operand)> {
        self.operands
            .iter()
            .enumerate()
            .find(|(_, o)| o.name.eq_ignore_ascii_case(name))
    }

    /// The faceplate index (ERR 13's EXERR) of the operand called `name`,
    /// exactly as the catalogue spells it. Evaluated at compile time where
    /// it is used in a constant; a name the instruction lacks fails the
    /// build there.
    pub const fn exerr(&self, name: &str) -> i32 {
        match self.faceplate_of(name) {
            Some(index) => index,
            None => panic!("the instruction has no operand of that name"),
        }
    }

    /// The faceplate index of the operand called `name` (exact spelling),
    /// `None` when the instruction has no such operand.
    pub const fn faceplate_of(&self, name: &str) -> Option<i32> {
        let mut i = 0;
        while i < self.operands.len() {
            if str_eq(self.operands[i].name, name) {
                return Some(self.operands[i].faceplate);
            }
            i += 1;
        }
        None
    }

    /// The operand names in call order, comma separated.
    pub fn operand_names(&self) -> String {
        let names: Vec<&str> = self.operands.iter().map(|o| o.name).collect();
        names.join(", ")
    }
}

const fn str_eq(a: &str, b: &str) -> bool {
    let (a, b) = (a.as_bytes(), b.as_bytes());
    if a.len() != b.len() {
        return false;
    }
    let mut i = 0;
    while i < a.len() {
        if a[i] != b[i] {
            return false;
        }
        i += 1;
    }
    true
}

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

/// The instruction called `name` (case-insensitive).
pub fn find(name: &str) -> Option<&'static Instruction> {
    INSTRUCTIONS
        .iter()
        .copied()
        .find(|i| i.mnemonic.eq_ignore_ascii_case(name))
}

/// The mnemonics of the positional instructions, comma separated (for
/// messages).
pub fn positional_mnemonics() -> String {
    let names: Vec<&str> = INSTRUCTIONS
        .iter()
        .filter(|i| i.style == CallStyle::Positional)
        .map(|i| i.mnemonic)
        .collect();
    names.join(", ")
}

/// Logix motion instructions a program may name that the product does not
/// simulate: a call of one is refused with a message saying so, rather
/// than as an unknown name.
pub const NOT_SIMULATED: &[&str] = &[
    // Motion state
    "MDO", "MDF", "MDS", // Motion move
    "MCD", "MCSV", "MATC", "MDAC", // Motion group
    "MGS", "MGSD", "MGSR", "MGSP", // Motion event
    "MAW", "MDW", "MAR", "MDR", "MAOC", "MDOC", // Motion configuration
    "MAAT", "MRAT", "MAHD", "MRHD", // Multi-axis coordinated motion
    "MCCD", "MCTP", "MCTO", "MCTPO", "MCPM", "MDCC",
];

/// The catalogue as Markdown: per instruction a heading and a table of its
/// operands (call position, name, data type, Format, faceplate index,
/// enumeration words with their codes). `scenes/README.md` holds exactly
/// this text between its `catalogue:begin` and `catalogue:end` markers.
pub fn markdown() -> String {
    let mut out = String::new();
    for ins in INSTRUCTIONS {
        let call = match ins.style {
            CallStyle::Positional => "positional",
            CallStyle::Named => "named inputs, on an instance tag",
        };
        out.push_str(&format!("#### `{}` — {} ({call})\n\n", ins.mnemonic, ins.title));
        out.push_str("| # | operand | data type | format | EXERR | words (code) |\n");
        out.push_str("| --- | --- | --- | --- | --- | --- |\n");
        for (i, o) in ins.operands.iter().enumerate() {
            let exerr = if o.faceplate < 0 {
                "—".to_string()
            } else {
                o.faceplate.to_string()
            };
            let words: Vec<String> = o
                .kind
                .words()
                .iter()
                .map(|w| format!("`{}` ({})", w.word, w.code))
                .collect();
            out.push_str(&format!(
                "| {i} | {} | {} | {} | {exerr} | {} |\n",
                o.name,
                o.data_type,
                o.format.name(),
                words.join(", ")
            ));
        }
        out.push('\n');
    }
    out
}

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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mccm_faceplate_indices_are_the_documents_exerr_table() {
        // The MCCM document's ERR 13 table, row by row.
        for (name, exerr) in [
            ("Coordinate System", 0),
            ("Move Type", 2),
            ("Position", 3),
            ("Circle Type", 4),
            ("Via/Center/Radius", 5),
            ("Direction", 6),
            ("Speed", 7),
            ("Accel Rate", 9),
            ("Decel Rate", 11),
            ("Termination Type", 14),
        ] {
            assert_eq!(MCCM.exerr(name), exerr, "{name}");
        }
        // MAPC EXERR 5 = Slave Scaling, MRP EXERR 4 = Position.
        assert_eq!(MAPC.exerr("Slave Scaling"), 5);
        assert_eq!(MRP.exerr("Position"), 4);
    }

    #[test]
    fn faceplate_indices_are_a_permutation_of_the_call_positions() {
        for ins in INSTRUCTIONS.iter().filter(|i| i.style == CallStyle::Positional) {
            let mut seen: Vec<i32> = ins.operands.iter().map(|o| o.faceplate).collect();
            seen.sort_unstable();
            let expected: Vec<i32> = (0..ins.operands.len() as i32).collect();
            assert_eq!(seen, expected, "{}", ins.mnemonic);
        }
    }

    #[test]
    fn mclm_is_mccm_without_the_circle_operands() {
        let circle = ["Circle Type", "Via/Center/Radius", "Direction"];
        let from_mccm: Vec<(&str, &str, Format, Kind)> = MCCM
            .operands
            .iter()
            .filter(|o| !circle.contains(&o.name))
            .map(|o| (o.name, o.data_type, o.format, o.kind))
            .collect();
        let mclm: Vec<(&str, &str, Format, Kind)> = MCLM
            .operands
            .iter()
            .map(|o| (o.name, o.data_type, o.format, o.kind))
            .collect();
        assert_eq!(mclm, from_mccm);
        // MCLM's faceplate: MCCM's without slots 4–6.
        for (name, exerr) in [
            ("Move Type", 2),
            ("Position", 3),
            ("Speed", 4),
            ("Profile", 10),
            ("Termination Type", 11),
            ("Accel Jerk", 14),
            ("Jerk Units", 16),
            ("Event Distance", 20),
            ("Calculated Data", 21),
        ] {
            assert_eq!(MCLM.exerr(name), exerr, "{name}");
        }
    }

    #[test]
    fn words_are_unique_per_operand_and_the_same_word_may_differ_between_operands() {
        for ins in INSTRUCTIONS {
            for o in ins.operands {
                let words = o.kind.words();
                for (i, a) in words.iter().enumerate() {
                    assert!(
                        !words[i + 1..].iter().any(|b| b.word.eq_ignore_ascii_case(a.word)),
                        "{} {}: {} twice",
                        ins.mnemonic,
                        o.name,
                        a.word
                    );
                }
            }
        }
        // `reverse` is MAPC Direction 2 but MAJ Direction 1; `%oftime` exists
        // only in Jerk Units.
        assert_eq!(MAPC.operand("Direction").unwrap().1.code_of("Reverse"), Some(2));
        assert_eq!(MAJ.operand("direction").unwrap().1.code_of("REVERSE"), Some(1));
        assert_eq!(MCCM.operand("Speed Units").unwrap().1.code_of("%oftime"), None);
        assert_eq!(MCCM.operand("Jerk Units").unwrap().1.code_of("%OfTime"), Some(2));
    }

    #[test]
    fn find_is_case_insensitive_and_knows_only_catalogued_instructions() {
        assert_eq!(find("mc_movemodulo").map(|i| i.mnemonic), Some("MC_MoveModulo"));
        assert_eq!(find("Mapc").map(|i| i.operands.len()), Some(14));
        assert_eq!(find("mso").map(|i| i.operands.len()), Some(2));
        assert!(find("MCD").is_none());
        for name in NOT_SIMULATED {
            assert!(find(name).is_none(), "{name} is both simulated and not");
        }
    }
}
