//! The Logix data types the task engine stores, how they convert on
//! assignment, and the layout of the structures it keeps in tag memory.
//!
//! # Conversions (on assignment, never by a function)
//! * REAL/LREAL → integer rounds half to even (−2.5 → −2, 1.5 → 2); a value
//!   outside the target's range (or not finite) writes the rounded value
//!   wrapped to the target's width (0 when not finite) and records a minor
//!   fault (type 4, code 4).
//! * integer → narrower integer keeps the low bits (SINT/INT are truncated
//!   on store); a value that changes records the same minor fault.
//! * anything → BOOL: non-zero is TRUE. BOOL → number: 0 or 1.
//! * → REAL rounds to single precision; a finite value too large for REAL
//!   becomes ±∞ with a minor fault.

/// A scalar data type.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum DataType {
    /// `BOOL`.
    Bool,
    /// `SINT` (8-bit).
    Sint,
    /// `INT` (16-bit).
    Int,
    /// `DINT` (32-bit).
    Dint,
    /// `LINT` (64-bit).
    Lint,
    /// `USINT`.
    Usint,
    /// `UINT`.
    Uint,
    /// `UDINT`.
    Udint,
    /// `ULINT` (its 64 bits in an `i64`; computed unsigned, [`Ty::Ulint`]).
    Ulint,
    /// `REAL` (IEEE single).
    Real,
    /// `LREAL` (IEEE double).
    Lreal,
}

impl DataType {
    /// The type's name.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            DataType::Bool => "BOOL",
            DataType::Sint => "SINT",
            DataType::Int => "INT",
            DataType::Dint => "DINT",
            DataType::Lint => "LINT",
            DataType::Usint => "USINT",
            DataType::Uint => "UINT",
            DataType::Udint => "UDINT",
            DataType::Ulint => "ULINT",
            DataType::Real => "REAL",
            DataType::Lreal => "LREAL",
        }
    }

    /// Whether it is an integer type.
    #[must_use]
    pub fn is_integer(self) -> bool {
        !matches!(self, DataType::Bool | DataType::Real | DataType::Lreal)
    }

    /// The width in bits (BOOL: 1).
    #[must_use]
    pub fn bits(self) -> u32 {
        match self {
            DataType::Bool => 1,
            DataType::Sint | DataType::Usint => 8,
            DataType::Int | DataType::Uint => 16,
            DataType::Dint | DataType::Udint | DataType::Real => 32,
            DataType::Lint | DataType::Ulint | DataType::Lreal => 64,
        }
    }

    /// The type an operand of this type is computed in.
    #[must_use]
    pub fn math(self) -> Ty {
        match self {
            DataType::Bool => Ty::Bool,
            DataType::Sint | DataType::Int | DataType::Dint | DataType::Usint | DataType::Uint => Ty::Dint,
            DataType::Lint | DataType::Udint => Ty::Lint,
            DataType::Ulint => Ty::Ulint,
            DataType::Real => Ty::Real,
            DataType::Lreal => Ty::Lreal,
        }
    }

    /// Stores `v` as this type: the stored value and whether a minor
    /// overflow fault is due.
    #[must_use]
    pub fn store(self, v: Value) -> (Value, bool) {
        match self {
            DataType::Bool => (Value::Bool(v.truthy()), false),
            DataType::Real => {
                let x = v.as_f64();
                let y = f64::from(x as f32);
                (Value::Real(y), x.is_finite() && !y.is_finite())
            }
            DataType::Lreal => (Value::Real(v.as_f64()), false),
            _ => {
                let (wide, bad) = match v {
                    Value::Bool(b) => (i128::from(b), false),
                    Value::Int(i) => (i128::from(i), false),
                    // A negative real has no ULINT (an integer value's
                    // sign cannot be told from a ULINT's bits).
                    Value::Real(x) if x.is_finite() => (round_half_even(x), self == DataType::Ulint && x <= -0.5),
                    Value::Real(_) => (0, true),
                };
                let stored = self.wrap(wide);
                (
                    Value::Int(stored),
                    bad || i128::from(stored) != wide && !self.same_bits(wide, stored),
                )
            }
        }
    }

    /// ULINT keeps 64 bits in an `i64`: a value that only differs by the
    /// sign reading is not an overflow.
    fn same_bits(self, wide: i128, stored: i64) -> bool {
        self == DataType::Ulint && (0..=i128::from(u64::MAX)).contains(&wide) && wide as u64 == stored as u64
    }

    /// `x` wrapped to the type's width (two's complement; unsigned types
    /// keep their low bits as a non-negative value, ULINT as its bits).
    #[must_use]
    pub fn wrap(self, x: i128) -> i64 {
        match self {
            DataType::Sint => i64::from(x as i8),
            DataType::Int => i64::from(x as i16),
            DataType::Dint => i64::from(x as i32),
            DataType::Usint => i64::from(x as u8),
            DataType::Uint => i64::from(x as u16),
            DataType::Udint => i64::from(x as u32),
            DataType::Lint | DataType::Ulint => x as i64,
            DataType::Bool => i64::from(x != 0),
            DataType::Real | DataType::Lreal => x as i64,
        }
    }
}

/// The type an expression is computed in: SINT, INT, USINT, UINT and DINT
/// are promoted to DINT; UDINT and LINT computed as LINT; ULINT unsigned.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Ty {
    /// BOOL.
    Bool,
    /// 32-bit integer math.
    Dint,
    /// 64-bit integer math.
    Lint,
    /// Unsigned 64-bit integer math (an operand of ULINT: its bits read
    /// unsigned; of a signed type: its value), results 0 to 2⁶⁴ − 1.
    Ulint,
    /// Single-precision math.
    Real,
    /// Double-precision math.
    Lreal,
}

impl Ty {
    /// Whether it is one of the integer kinds.
    #[must_use]
    pub fn is_integer(self) -> bool {
        matches!(self, Ty::Dint | Ty::Lint | Ty::Ulint)
    }

    /// Whether it is one of the real kinds.
    #[must_use]
    pub fn is_real(self) -> bool {
        matches!(self, Ty::Real | Ty::Lreal)
    }

    /// The name used in messages.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Ty::Bool => "BOOL",
            Ty::Dint => "DINT",
            Ty::Lint => "LINT",
            Ty::Ulint => "ULINT",
            Ty::Real => "REAL",
            Ty::Lreal => "LREAL",
        }
    }

    /// The storage type of a value computed in this type.
    #[must_use]
    pub fn data_type(self) -> DataType {
        match self {
            Ty::Bool => DataType::Bool,
            Ty::Dint => DataType::Dint,
            Ty::Lint => DataType::Lint,
            Ty::Ulint => DataType::Ulint,
            Ty::Real => DataType::Real,
            Ty::Lreal => DataType::Lreal,
        }
    }
}

/// A value in tag memory or under evaluation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Value {
    /// BOOL.
    Bool(bool),
    /// Any integer type (its bits; the slot's type says how to read them).
    Int(i64),
    /// REAL (held at single precision) or LREAL.
    Real(f64),
}

impl Value {
    /// Non-zero.
    #[must_use]
    pub fn truthy(self) -> bool {
        match self {
            Value::Bool(b) => b,
            Value::Int(i) => i != 0,
            Value::Real(x) => x != 0.0,
        }
    }

    /// As a double.
    #[must_use]
    pub fn as_f64(self) -> f64 {
        match self {
            Value::Bool(b) => f64::from(u8::from(b)),
            Value::Int(i) => i as f64,
            Value::Real(x) => x,
        }
    }

    /// As an integer (reals rounded half to even, saturating).
    #[must_use]
    pub fn as_i64(self) -> i64 {
        match self {
            Value::Bool(b) => i64::from(b),
            Value::Int(i) => i,
            Value::Real(x) if x.is_finite() => {
                round_half_even(x).clamp(i128::from(i64::MIN), i128::from(i64::MAX)) as i64
            }
            Value::Real(_) => 0,
        }
    }
}

/// Rounds a finite value to the nearest integer, ties to even (the Logix
/// REAL → integer conversion). Beyond ±2^100 the result keeps only what a
/// wrap to 64 bits or fewer keeps: a value with the same low 64 bits,
/// itself beyond every integer type's range (so the overflow shows).
#[must_use]
pub fn round_half_even(x: f64) -> i128 {
    wide_integer(x.round_ties_even())
}

/// An integral float as an integer; beyond ±2^100, see [`round_half_even`].
#[must_use]
pub fn wide_integer(r: f64) -> i128 {
    const TWO_64: f64 = 18_446_744_073_709_551_616.0;
    if r.abs() < 2f64.powi(100) {
        r as i128
    } else {
        // Exact: a float this large is a multiple of 2^48, and the
        // remainder of a division by a power of two is exact.
        (r.rem_euclid(TWO_64) as u128 as i128) + (1i128 << 100)
    }
}

/// A structure the engine keeps in tag memory: its members in slot order.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Structure {
    /// `FBD_TIMER` (TONR, TOFR, RTOR).
    Timer,
    /// `FBD_COUNTER` (CTUD).
    Counter,
    /// `FBD_ONESHOT` (OSRI, OSFI).
    OneShot,
    /// `CAM` (one cam point).
    Cam,
    /// `R_TRIG` / `F_TRIG` (IEC dialect).
    Trig,
    /// `TON` / `TOF` (IEC dialect; `PT` and `ET` in ms).
    IecTimer,
    /// `TIMER` (ladder TON, TOF, RTO; `PRE` and `ACC` in ms).
    LadderTimer,
    /// `COUNTER` (ladder CTU, CTD).
    LadderCounter,
    /// `CONTROL` (ladder BSL, BSR, FFL, FFU, LFL, LFU).
    Control,
    /// `OUTPUT_CAM` (MAOC).
    OutputCam,
    /// `OUTPUT_COMPENSATION` (MAOC).
    OutputCompensation,
}

/// The members of each structure: name, type, and whether a program may
/// name it (hidden ones hold the instruction's own history).
const TIMER: [(&str, DataType, bool); 13] = [
    ("EnableIn", DataType::Bool, true),
    ("TimerEnable", DataType::Bool, true),
    ("PRE", DataType::Dint, true),
    ("Reset", DataType::Bool, true),
    ("EnableOut", DataType::Bool, true),
    ("ACC", DataType::Dint, true),
    ("EN", DataType::Bool, true),
    ("TT", DataType::Bool, true),
    ("DN", DataType::Bool, true),
    ("Status", DataType::Dint, true),
    ("InstructFault", DataType::Bool, true),
    ("PresetInv", DataType::Bool, true),
    ("LastScan_us", DataType::Lint, false),
];

const COUNTER: [(&str, DataType, bool); 12] = [
    ("EnableIn", DataType::Bool, true),
    ("CUEnable", DataType::Bool, true),
    ("CDEnable", DataType::Bool, true),
    ("PRE", DataType::Dint, true),
    ("Reset", DataType::Bool, true),
    ("EnableOut", DataType::Bool, true),
    ("ACC", DataType::Dint, true),
    ("CU", DataType::Bool, true),
    ("CD", DataType::Bool, true),
    ("DN", DataType::Bool, true),
    ("OV", DataType::Bool, true),
    ("UN", DataType::Bool, true),
];

const ONESHOT: [(&str, DataType, bool); 5] = [
    ("EnableIn", DataType::Bool, true),
    ("InputBit", DataType::Bool, true),
    ("EnableOut", DataType::Bool, true),
    ("OutputBit", DataType::Bool, true),
    ("InputBitLast", DataType::Bool, false),
];

const CAM: [(&str, DataType, bool); 3] = [
    ("Master", DataType::Real, true),
    ("Slave", DataType::Real, true),
    ("SegmentType", DataType::Dint, true),
];

const TRIG: [(&str, DataType, bool); 3] = [
    ("CLK", DataType::Bool, true),
    ("Q", DataType::Bool, true),
    ("M", DataType::Bool, false),
];

const IEC_TIMER: [(&str, DataType, bool); 6] = [
    ("IN", DataType::Bool, true),
    ("PT", DataType::Dint, true),
    ("Q", DataType::Bool, true),
    ("ET", DataType::Dint, true),
    ("Running", DataType::Bool, false),
    ("Start_us", DataType::Lint, false),
];

/// `TIMER`: the bits, `PRE`, `ACC`, and when the timer last measured.
/// The slot offsets are [`LT_EN`] ….
const LADDER_TIMER: [(&str, DataType, bool); 6] = [
    ("EN", DataType::Bool, true),
    ("TT", DataType::Bool, true),
    ("DN", DataType::Bool, true),
    ("PRE", DataType::Dint, true),
    ("ACC", DataType::Dint, true),
    ("LastScan_us", DataType::Lint, false),
];

/// `TIMER.EN`'s slot offset.
pub const LT_EN: usize = 0;
/// `TIMER.TT`'s.
pub const LT_TT: usize = 1;
/// `TIMER.DN`'s.
pub const LT_DN: usize = 2;
/// `TIMER.PRE`'s.
pub const LT_PRE: usize = 3;
/// `TIMER.ACC`'s.
pub const LT_ACC: usize = 4;
/// When the timer last measured, µs (hidden).
pub const LT_LAST: usize = 5;

/// `COUNTER`; the slot offsets are [`LC_CU`] ….
const LADDER_COUNTER: [(&str, DataType, bool); 7] = [
    ("CU", DataType::Bool, true),
    ("CD", DataType::Bool, true),
    ("DN", DataType::Bool, true),
    ("OV", DataType::Bool, true),
    ("UN", DataType::Bool, true),
    ("PRE", DataType::Dint, true),
    ("ACC", DataType::Dint, true),
];

/// `COUNTER.CU`'s slot offset.
pub const LC_CU: usize = 0;
/// `COUNTER.CD`'s.
pub const LC_CD: usize = 1;
/// `COUNTER.DN`'s.
pub const LC_DN: usize = 2;
/// `COUNTER.OV`'s.
pub const LC_OV: usize = 3;
/// `COUNTER.UN`'s.
pub const LC_UN: usize = 4;
/// `COUNTER.PRE`'s.
pub const LC_PRE: usize = 5;
/// `COUNTER.ACC`'s.
pub const LC_ACC: usize = 6;

/// `CONTROL`; the slot offsets are [`CT_EN`] ….
const CONTROL: [(&str, DataType, bool); 10] = [
    ("EN", DataType::Bool, true),
    ("EU", DataType::Bool, true),
    ("DN", DataType::Bool, true),
    ("EM", DataType::Bool, true),
    ("ER", DataType::Bool, true),
    ("UL", DataType::Bool, true),
    ("IN", DataType::Bool, true),
    ("FD", DataType::Bool, true),
    ("LEN", DataType::Dint, true),
    ("POS", DataType::Dint, true),
];

/// `OUTPUT_CAM`, in [`planner::output_cam::OutputCamElement`]'s order.
const OUTPUT_CAM: [(&str, DataType, bool); 8] = [
    ("OutputBit", DataType::Dint, true),
    ("LatchType", DataType::Dint, true),
    ("UnlatchType", DataType::Dint, true),
    ("Left", DataType::Real, true),
    ("Right", DataType::Real, true),
    ("Duration", DataType::Real, true),
    ("EnableType", DataType::Dint, true),
    ("EnableBit", DataType::Dint, true),
];

/// `OUTPUT_COMPENSATION`, in [`planner::output_cam::OutputCompensation`]'s
/// order.
const OUTPUT_COMPENSATION: [(&str, DataType, bool); 6] = [
    ("Offset", DataType::Real, true),
    ("LatchDelay", DataType::Real, true),
    ("UnlatchDelay", DataType::Real, true),
    ("Mode", DataType::Dint, true),
    ("CycleTime", DataType::Real, true),
    ("DutyCycle", DataType::Real, true),
];

/// `CONTROL.EN`'s slot offset.
pub const CT_EN: usize = 0;
/// `CONTROL.EU`'s.
pub const CT_EU: usize = 1;
/// `CONTROL.DN`'s.
pub const CT_DN: usize = 2;
/// `CONTROL.EM`'s.
pub const CT_EM: usize = 3;
/// `CONTROL.ER`'s.
pub const CT_ER: usize = 4;
/// `CONTROL.UL`'s.
pub const CT_UL: usize = 5;
/// `CONTROL.LEN`'s.
pub const CT_LEN: usize = 8;
/// `CONTROL.POS`'s.
pub const CT_POS: usize = 9;

impl Structure {
    /// Every structure kept in slots.
    pub const ALL: [Structure; 11] = [
        Structure::Timer,
        Structure::Counter,
        Structure::OneShot,
        Structure::Cam,
        Structure::Trig,
        Structure::IecTimer,
        Structure::LadderTimer,
        Structure::LadderCounter,
        Structure::Control,
        Structure::OutputCam,
        Structure::OutputCompensation,
    ];

    /// The type name.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Structure::Timer => "FBD_TIMER",
            Structure::Counter => "FBD_COUNTER",
            Structure::OneShot => "FBD_ONESHOT",
            Structure::Cam => "CAM",
            Structure::Trig => "R_TRIG/F_TRIG",
            Structure::IecTimer => "TON/TOF",
            Structure::LadderTimer => "TIMER",
            Structure::LadderCounter => "COUNTER",
            Structure::Control => "CONTROL",
            Structure::OutputCam => "OUTPUT_CAM",
            Structure::OutputCompensation => "OUTPUT_COMPENSATION",
        }
    }

    /// The members in slot order.
    #[must_use]
    pub fn members(self) -> &'static [(&'static str, DataType, bool)] {
        match self {
            Structure::Timer => &TIMER,
            Structure::Counter => &COUNTER,
            Structure::OneShot => &ONESHOT,
            Structure::Cam => &CAM,
            Structure::Trig => &TRIG,
            Structure::IecTimer => &IEC_TIMER,
            Structure::LadderTimer => &LADDER_TIMER,
            Structure::LadderCounter => &LADDER_COUNTER,
            Structure::Control => &CONTROL,
            Structure::OutputCam => &OUTPUT_CAM,
            Structure::OutputCompensation => &OUTPUT_COMPENSATION,
        }
    }

    /// Slots one structure takes.
    #[must_use]
    pub fn size(self) -> usize {
        self.members().len()
    }

    /// The slot offset and type of a member a program may name
    /// (case-insensitive).
    #[must_use]
    pub fn member(self, name: &str) -> Option<(usize, DataType)> {
        self.members()
            .iter()
            .position(|(n, _, visible)| *visible && n.eq_ignore_ascii_case(name))
            .map(|i| (i, self.members()[i].1))
    }

    /// The slot offset of a member by its exact catalogue name, hidden ones
    /// included (for the instructions that keep their history there).
    ///
    /// # Panics
    /// When the structure has no such member (a programming error caught
    /// by the unit tests).
    #[must_use]
    pub fn offset(self, name: &str) -> usize {
        self.members()
            .iter()
            .position(|(n, _, _)| *n == name)
            .unwrap_or_else(|| panic!("{} has no member {name}", self.name()))
    }

    /// The names a program may use, for messages.
    #[must_use]
    pub fn visible_members(self) -> String {
        self.members()
            .iter()
            .filter(|m| m.2)
            .map(|m| m.0)
            .collect::<Vec<_>>()
            .join(", ")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn real_to_integer_rounds_half_to_even() {
        for (x, want) in [
            (-2.5, -2),
            (-1.5, -2),
            (1.5, 2),
            (2.5, 2),
            (0.49, 0),
            (-0.5, 0),
            (3.5, 4),
        ] {
            assert_eq!(DataType::Dint.store(Value::Real(x)), (Value::Int(want), false), "{x}");
        }
    }

    #[test]
    fn narrowing_keeps_the_low_bits_and_flags_the_overflow() {
        assert_eq!(
            DataType::Int.store(Value::Int(40_000)),
            (Value::Int(40_000 - 65_536), true)
        );
        assert_eq!(DataType::Sint.store(Value::Int(-128)), (Value::Int(-128), false));
        assert_eq!(DataType::Sint.store(Value::Int(128)), (Value::Int(-128), true));
        assert_eq!(DataType::Usint.store(Value::Int(-1)), (Value::Int(255), true));
        assert_eq!(
            DataType::Dint.store(Value::Real(3e9)),
            (Value::Int(3_000_000_000 - 4_294_967_296), true)
        );
        assert_eq!(DataType::Dint.store(Value::Real(f64::NAN)), (Value::Int(0), true));
        assert_eq!(DataType::Ulint.store(Value::Int(-1)), (Value::Int(-1), false));
    }

    #[test]
    fn huge_reals_wrap_by_their_low_bits() {
        // 3.4e38 as a REAL is 0xFFFFFF × 2^104: its low 64 bits are zero.
        let x = f64::from(3.4e38f32);
        assert_eq!(DataType::Dint.store(Value::Real(x)), (Value::Int(0), true));
        assert_eq!(DataType::Lint.store(Value::Real(-x)), (Value::Int(0), true));
        // 2^70 + 2^60 keeps 2^60 in its low 64 bits.
        let y = 2f64.powi(70) + 2f64.powi(60);
        assert_eq!(DataType::Lint.store(Value::Real(y)), (Value::Int(1 << 60), true));
    }

    #[test]
    fn reals_are_single_precision() {
        let (v, fault) = DataType::Real.store(Value::Real(0.1));
        assert_eq!(v, Value::Real(f64::from(0.1f32)));
        assert!(!fault);
        assert!(DataType::Real.store(Value::Real(1e39)).1);
        assert_eq!(DataType::Bool.store(Value::Int(2)), (Value::Bool(true), false));
    }

    #[test]
    fn every_structure_names_its_history_members() {
        for s in Structure::ALL {
            assert!(s.size() > 0);
            assert_eq!(s.member("nonsense"), None);
        }
        assert_eq!(Structure::Timer.offset("LastScan_us"), 12);
        assert_eq!(Structure::Timer.member("LastScan_us"), None, "hidden");
        assert_eq!(Structure::Timer.member("acc"), Some((5, DataType::Dint)));
    }
}
