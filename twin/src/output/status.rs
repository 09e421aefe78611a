//! How an instruction's status reads as text: the summary's final outputs
//! and first errors, and the recording's instruction log and state lanes.

use planner::instruction::{FbOutputs, MotionInstructionBits};
use std::fmt::Write as _;

/// An instruction's outputs as the summary and the recording read them: a
/// PLCopen function block's ([`FbOutputs`]) or a Logix control
/// structure's ([`MotionInstructionBits`]).
pub(crate) trait Status: Copy + PartialEq {
    /// The bits, named, in their documented order.
    fn named_bits(&self) -> impl Iterator<Item = (&'static str, bool)>;
    /// Whether it reports an error (`Error`, `.ER`).
    fn failed(&self) -> bool;
    /// A set bit as text: `Done`, `.DN`.
    fn bit_text(name: &str) -> String;
    /// The error as text, when [`Status::failed`].
    fn error_text(&self) -> String;
    /// One word for the state it is in, the recording's state lane: the
    /// error (`ER 54`, `Error 16#4605`), else `IP` / `Busy`, `PC` / `Done`,
    /// `DN`, `EN`, `Aborted`; empty when idle (a gap in the lane).
    #[cfg(feature = "rerun")]
    fn lane(&self) -> String;
}

impl Status for FbOutputs {
    fn named_bits(&self) -> impl Iterator<Item = (&'static str, bool)> {
        self.bits().into_iter()
    }
    fn failed(&self) -> bool {
        self.error
    }
    fn bit_text(name: &str) -> String {
        name.to_owned()
    }
    fn error_text(&self) -> String {
        format!(
            "ErrorID 16#{:04X} ({})",
            self.error_id,
            planner::modulo::ErrorId(self.error_id).meaning()
        )
    }
    #[cfg(feature = "rerun")]
    fn lane(&self) -> String {
        let word = if self.error {
            return format!("Error 16#{:04X}", self.error_id);
        } else if self.active {
            "Active"
        } else if self.busy {
            "Busy"
        } else if self.done {
            "Done"
        } else if self.command_aborted {
            "Aborted"
        } else {
            ""
        };
        word.to_owned()
    }
}

impl Status for MotionInstructionBits {
    fn named_bits(&self) -> impl Iterator<Item = (&'static str, bool)> {
        self.bits().into_iter()
    }
    fn failed(&self) -> bool {
        self.er
    }
    fn bit_text(name: &str) -> String {
        format!(".{name}")
    }
    fn error_text(&self) -> String {
        error_codes(*self)
    }
    #[cfg(feature = "rerun")]
    fn lane(&self) -> String {
        let word = if self.er {
            return format!("ER {}", self.err);
        } else if self.ip {
            "IP"
        } else if self.pc {
            "PC"
        } else if self.dn {
            "DN"
        } else if self.en {
            "EN"
        } else {
            ""
        };
        word.to_owned()
    }
}

/// The bits that are set (`Done Busy`, `.DN .PC`), then the error when
/// there is one; `idle` when nothing is.
pub(crate) fn describe<S: Status>(status: S) -> String {
    let mut s = String::new();
    for (name, bit) in status.named_bits() {
        if bit {
            s.push_str(&S::bit_text(name));
            s.push(' ');
        }
    }
    if status.failed() {
        s.push_str(&status.error_text());
    }
    if s.is_empty() {
        "idle".to_string()
    } else {
        s.trim_end().to_string()
    }
}

/// `ERR e (its meaning) EXERR x`, and `SEGMENT s` for a path segment.
pub(crate) fn error_codes(b: MotionInstructionBits) -> String {
    let mut s = planner::catalogue::err_text(b.err, b.exerr);
    if b.segment != 0 {
        let _ = write!(s, " SEGMENT {}", b.segment);
    }
    s
}
