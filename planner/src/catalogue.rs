//! The instruction catalogue's vocabulary: how each instruction the
//! product accepts is described, once.
//!
//! Each instruction's entry ([`crate::task::instructions::Instruction`])
//! lists its operands in the order a Structured Text
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
//! An entry also carries what the instruction does (it executes a call on
//! the motion task with its operand values, bound by catalogue position,
//! and checks a call whose operands are all known when the program loads).
//! Each entry lives in its instruction's module under `task/instructions/`,
//! and the registry there ([`crate::task::instructions::INSTRUCTIONS`])
//! lists them all: the Structured Text compiler, the binding of operands,
//! the EXERR numbers, error messages and the operand lists in
//! `scenes/README.md` ([`crate::task::instructions::markdown`]) all derive
//! from the entries. [`errors`] gives the meaning of every ERR code.
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
//! use planner::catalogue::Format;
//! use planner::task::instructions;
//!
//! let mccm = instructions::find("mccm").unwrap();
//! assert_eq!(mccm.operands.len(), 25);
//! assert_eq!(mccm.exerr("Termination Type"), 14);
//! let units = mccm.operand("Jerk Units").unwrap().1;
//! assert_eq!(units.format, Format::ImmediateOrTag);
//! assert_eq!(units.code_of("%ofTime"), Some(2));
//! ```

pub mod errors;
pub mod words;

pub use errors::{ERRORS, ErrorCode, err_meaning, err_text};

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
    /// An axis with a drive (`AXIS_CIP_DRIVE`): a virtual axis, always
    /// servo-on, is refused when the program loads, as the controller's
    /// verifier refuses it (MSO, MSF).
    DriveAxis,
    /// A `COORDINATE_SYSTEM` tag.
    CoordinateSystem,
    /// The `MOTION_GROUP` tag (one per controller: every axis is in it).
    Group,
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
    /// Three REALs from an array element (`REAL[3]`) that the instruction
    /// writes ([`crate::task::MotionTask::take_output`]).
    OutputVector3,
    /// `0` (none) or a REAL array tag.
    OptionalArray,
    /// A REAL tag the instruction writes when it executes (MCSV's Slave
    /// Value, Slope, Slope Derivative), passed as the caller's reference:
    /// the n-th such operand takes the n-th value of
    /// [`crate::task::MotionTask::take_output`].
    OutputReal,
    /// A DINT tag the instruction keeps writing (MAOC's Output), passed as
    /// the caller's reference ([`crate::task::Arg::Reference`]).
    OutputWord,
    /// A DINT tag the instruction keeps reading (MAOC's Input), passed as
    /// the caller's reference.
    InputWord,
    /// An `OUTPUT_CAM` array from the element named.
    OutputCams,
    /// An `OUTPUT_COMPENSATION` array from the element named.
    Compensations,
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

/// The faceplate index of the operand called `name` (exact spelling) in an
/// operand table, for the modules that share one instruction's operands
/// with its validation; a name the table lacks fails the build where it is
/// evaluated in a constant.
pub const fn faceplate(operands: &[Operand], name: &str) -> i32 {
    match faceplate_of(operands, name) {
        Some(index) => index,
        None => panic!("no operand of that name"),
    }
}

/// The faceplate index of the operand called `name` (exact spelling) in an
/// operand table, `None` when it has no such operand.
pub const fn faceplate_of(operands: &[Operand], name: &str) -> Option<i32> {
    let mut i = 0;
    while i < operands.len() {
        if str_eq(operands[i].name, name) {
            return Some(operands[i].faceplate);
        }
        i += 1;
    }
    None
}

pub(crate) const fn str_eq(a: &str, b: &str) -> bool {
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
