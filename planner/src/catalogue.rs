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

mod instructions;

pub use instructions::*;

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
