//! The registry of instructions: every instruction the product accepts is
//! a module here — its catalogue entry (operands, formats, words,
//! faceplate indices), its typed operands bound from the call by catalogue
//! position, its validation, its refusals and its executor — and one line
//! of `instructions!` below, which declares the module and lists its
//! entry in [`INSTRUCTIONS`]. The program (the twin's compiler), the docs
//! (`scenes/README.md`, [`markdown`]) and the ERR 13 EXERR numbers read
//! the entries; nothing else names an instruction.
//!
//! Where an instruction's motion is a process of the motion engine that
//! other instructions stop or replace (a move ramp, a cam, gearing,
//! coordinated motion, a transform, the servo states), the executor starts
//! it through the engine (`task/*.rs`), which runs it each coarse update.

use crate::catalogue::CallStyle;

pub mod entry;
pub use entry::{Check, Execute, Instruction, Load, no_check, no_load};

/// Declares each instruction module and lists its entry, in the order the
/// docs show them.
macro_rules! instructions {
    ($($module:ident::$entry:ident),* $(,)?) => {
        $(pub mod $module;)*

        /// Every instruction the product accepts, in the order the docs
        /// list them.
        pub static INSTRUCTIONS: &[&Instruction] = &[$(&$module::$entry),*];

        /// Each instruction's unit (its module's name), as
        /// [`INSTRUCTIONS`] lists them.
        static UNITS: &[&str] = &[$(stringify!($module)),*];
    };
}

instructions! {
    mclm::MCLM,
    mccm::MCCM,
    mccd::MCCD,
    mcs::MCS,
    mct::MCT,
    mctp::MCTP,
    mccp::MCCP,
    mcsv::MCSV,
    mapc::MAPC,
    matc::MATC,
    mrp::MRP,
    mar::MAR,
    mdr::MDR,
    maw::MAW,
    mdw::MDW,
    maoc::MAOC,
    mdoc::MDOC,
    maj::MAJ,
    mas::MAS,
    mam::MAM,
    mcd::MCD,
    mag::MAG,
    mso::MSO,
    msf::MSF,
    masd::MASD,
    masr::MASR,
    mafr::MAFR,
    mah::MAH,
    mcsd::MCSD,
    mcsr::MCSR,
    mdcc::MDCC,
    mgs::MGS,
    mgsd::MGSD,
    mgsr::MGSR,
    mgsp::MGSP,
    mc_move_modulo::MC_MOVE_MODULO,
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
    "MDO", "MDF", "MDS",  // Motion move
    "MDAC", // Motion configuration
    "MAAT", "MRAT", "MAHD", "MRHD", // Multi-axis coordinated motion
    "MCTO", "MCTPO", "MCPM",
];

/// The file of `instruction`'s unit, from the planner's root
/// (`src/task/instructions/mag.rs`).
pub fn unit_file(instruction: &Instruction) -> String {
    let unit = INSTRUCTIONS
        .iter()
        .position(|i| *i == instruction)
        .map_or("?", |k| UNITS[k]);
    format!("src/task/instructions/{unit}.rs")
}

/// The instructions a program can call, as the Markdown table the
/// project's `README.md` holds between its `calls:begin` and `calls:end`
/// markers: call, what it does, its unit, its specification, whether a
/// routine may call it.
pub fn calls_markdown() -> String {
    let mut out = String::from("| call | what it does | unit (`planner/`) | specification | in routines |\n");
    out.push_str("| --- | --- | --- | --- | --- |\n");
    for ins in INSTRUCTIONS {
        let (call, routines) = match ins.style {
            CallStyle::Positional => (format!("`{}`", ins.mnemonic), "yes"),
            CallStyle::Named => (format!("`{}` (named inputs)", ins.mnemonic), "IEC dialect"),
        };
        out.push_str(&format!(
            "| {call} | {} | `{}` | {} | {routines} |\n",
            ins.summary,
            unit_file(ins),
            ins.reference
        ));
    }
    out
}

/// The catalogue of every instruction as Markdown: per instruction a
/// heading and a table of its operands (call position, name, data type, Format, faceplate index,
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
    use crate::catalogue::{Format, Kind};
    use maj::MAJ;
    use mapc::MAPC;
    use mccm::MCCM;
    use mclm::MCLM;
    use mrp::MRP;

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
        assert!(find("MDAC").is_none());
        for name in NOT_SIMULATED {
            assert!(find(name).is_none(), "{name} is both simulated and not");
        }
    }
}
