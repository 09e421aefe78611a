//! The Logix motion error codes (`.ERR`) the instructions report, each
//! with its meaning, for the summary, the console and the recording
//! (`ERR 49 (circular: radius too small for the end point) EXERR 0`).
//!
//! The names follow the Logix motion reference's "Motion Error Codes
//! (.ERR)"; ERR 200 and 201 are the twin's own (the pre-flight path
//! collision and a master-driven move taking over while the master stands
//! still: `task/coord`), outside the Logix range of 1 to 199.

/// One error code and what it means.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ErrorCode {
    /// The `ERR` value.
    pub code: i32,
    /// What it means, in a few words.
    pub meaning: &'static str,
}

const fn e(code: i32, meaning: &'static str) -> ErrorCode {
    ErrorCode { code, meaning }
}

/// Every `ERR` an instruction of the twin can report, by code.
pub const ERRORS: &[ErrorCode] = &[
    e(5, "servo off state: the axis' servo loop is open"),
    e(7, "shutdown state: the axis is shut down"),
    e(8, "axis type not servo"),
    e(9, "overtravel condition: beyond a soft travel limit"),
    e(11, "axis not configured"),
    e(12, "servo message failure"),
    e(13, "parameter out of range"),
    e(16, "homing in process"),
    e(17, "axis mode not rotary"),
    e(20, "axis in faulted state"),
    e(22, "axis in motion"),
    e(25, "illegal instruction"),
    e(26, "illegal cam length"),
    e(27, "illegal cam profile length"),
    e(28, "illegal cam type"),
    e(29, "illegal cam order: master values not increasing"),
    e(30, "cam profile being calculated"),
    e(31, "cam profile being used"),
    e(32, "cam profile not calculated"),
    e(35, "illegal execution target"),
    e(36, "illegal output cam"),
    e(37, "illegal output compensation"),
    e(44, "circular: the points are collinear"),
    e(45, "circular: the end point is the start point"),
    e(46, "circular: start and end radius differ"),
    e(49, "circular: radius too small for the end point"),
    e(53, "axis inhibited"),
    e(54, "maximum deceleration is zero"),
    e(61, "transform connection conflict"),
    e(67, "invalid transform position"),
    e(179, "cam profile element not a finite number"),
    e(200, "path collision found by the pre-flight sweep"),
    e(201, "master idle while the slave moves"),
];

/// What `ERR` `code` means; `None` for a code no instruction reports.
pub fn err_meaning(code: i32) -> Option<&'static str> {
    ERRORS.iter().find(|e| e.code == code).map(|e| e.meaning)
}

/// `ERR 49 (circular: radius too small for the end point) EXERR 0`: the
/// codes with the error's meaning, as the summary, the console and the
/// recording print them (without one for a code the catalogue lacks).
pub fn err_text(err: i32, exerr: i32) -> String {
    match err_meaning(err) {
        Some(meaning) => format!("ERR {err} ({meaning}) EXERR {exerr}"),
        None => format!("ERR {err} EXERR {exerr}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn codes_are_sorted_and_unique() {
        assert!(ERRORS.windows(2).all(|w| w[0].code < w[1].code));
        assert_eq!(err_meaning(49), Some("circular: radius too small for the end point"));
        assert_eq!(err_meaning(0), None);
        assert_eq!(
            err_text(49, 0),
            "ERR 49 (circular: radius too small for the end point) EXERR 0"
        );
        assert_eq!(err_text(99, 3), "ERR 99 EXERR 3");
    }
}
