//! How an instruction's status reads as text: the summary's final outputs
//! and first errors, and the recording's instruction log.

use planner::instruction::{FbOutputs, MotionInstructionBits};
use std::fmt::Write as _;

/// A function block's outputs: the bits that are set, then `ErrorID 16#…
/// (meaning)` when Error is set; `idle` when nothing is.
pub(crate) fn describe(o: FbOutputs) -> String {
    let mut s = String::new();
    for (name, bit) in o.bits() {
        if bit {
            let _ = write!(s, "{name} ");
        }
    }
    if o.error {
        let _ = write!(
            s,
            "ErrorID 16#{:04X} ({})",
            o.error_id,
            planner::modulo::ErrorId(o.error_id).meaning()
        );
    }
    if s.is_empty() {
        "idle".to_string()
    } else {
        s.trim_end().to_string()
    }
}

/// A control structure's bits that are set (`.DN .PC`), then its error
/// codes when `.ER` is set; `idle` when nothing is.
pub(crate) fn describe_bits(b: MotionInstructionBits) -> String {
    let mut s = String::new();
    for (name, bit) in b.bits() {
        if bit {
            let _ = write!(s, ".{name} ");
        }
    }
    if b.er {
        let _ = write!(s, "{}", error_codes(b));
    }
    if s.is_empty() {
        "idle".to_string()
    } else {
        s.trim_end().to_string()
    }
}

/// `ERR e EXERR x`, and `SEGMENT s` for a path segment.
pub(crate) fn error_codes(b: MotionInstructionBits) -> String {
    let mut s = format!("ERR {} EXERR {}", b.err, b.exerr);
    if b.segment != 0 {
        let _ = write!(s, " SEGMENT {}", b.segment);
    }
    s
}
