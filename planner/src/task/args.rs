//! The operand values of one call, as the program hands them to an
//! instruction: by catalogue position ([`crate::task::instructions::Instruction`]'s
//! `operands`), each a value of the operand's [`crate::catalogue::Kind`].
//!
//! The program binds every operand by its kind, so an accessor of another
//! kind than the value is a bug of the binding, not of the user's program:
//! it panics naming the position. An instruction reads its operands with
//! these accessors and builds its typed operands from them; values it
//! cannot take (a position array too short, a count out of range) are its
//! own ERR 13, with the operand's faceplate index.

use crate::mccp::CamElement;
use crate::task::handles::{AxisHandle, CamProfileHandle, CoordHandle, FbHandle, InstructionHandle};

/// One operand's value.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Arg<'a> {
    /// An axis (`Kind::Axis`, `Kind::DriveAxis`).
    Axis(AxisHandle),
    /// A coordinate system.
    System(CoordHandle),
    /// The motion group (one per controller).
    Group,
    /// A tag the instruction keeps writing or reading, by the caller's
    /// reference (MAOC's Output and Input words).
    Reference(usize),
    /// `OUTPUT_CAM` elements from the one the operand names.
    OutputCams(&'a [crate::output_cam::OutputCamElement]),
    /// `OUTPUT_COMPENSATION` elements, whole array.
    Compensations(&'a [crate::output_cam::OutputCompensation]),
    /// A control structure (`MOTION_INSTRUCTION` tag).
    Control(InstructionHandle),
    /// A `CAM_PROFILE` tag.
    CamProfile(CamProfileHandle),
    /// A number (REAL or integer).
    Number(f64),
    /// An integer (integer operands, enumeration codes, counts).
    Integer(i64),
    /// `TRUE` / `FALSE`.
    Bool(bool),
    /// A REAL array from the element the operand names to the array's
    /// end (`Pos[2]`: elements 2, 3, …; empty past the end). `Kind::Values`
    /// may also be one number (a radius): then one element.
    Array(&'a [f64]),
    /// An element reference whose subscript is outside its array
    /// (negative, or past the end): the instruction refuses the operand
    /// (ERR 13).
    NoElement,
    /// A CAM array, whole, and the element the operand starts at.
    Cam(&'a [CamElement], usize),
    /// `0` for an optional array: none given.
    None,
    /// An input a named call does not give (it keeps its last value), or
    /// an operand not known at load.
    Absent,
}

/// The operand values of one call, in catalogue order.
#[derive(Debug, Clone, Copy)]
pub struct Args<'a> {
    /// The values, one per catalogue operand.
    pub values: &'a [Arg<'a>],
    /// The function-block instance a named call runs on.
    pub instance: Option<FbHandle>,
}

impl<'a> Args<'a> {
    /// The values of a positional call.
    #[must_use]
    pub fn new(values: &'a [Arg<'a>]) -> Self {
        Args { values, instance: None }
    }

    /// The value at `i`.
    #[must_use]
    pub fn get(&self, i: usize) -> Arg<'a> {
        self.values.get(i).copied().unwrap_or(Arg::Absent)
    }

    /// Whether every operand is known (none [`Arg::Absent`]).
    #[must_use]
    pub fn all_known(&self) -> bool {
        !self.values.contains(&Arg::Absent)
    }

    fn wrong(&self, i: usize, want: &str) -> ! {
        panic!("operand {i} is bound as {:?}, read as {want}", self.get(i))
    }

    /// The axis at `i`.
    #[must_use]
    pub fn axis(&self, i: usize) -> AxisHandle {
        match self.get(i) {
            Arg::Axis(h) => h,
            _ => self.wrong(i, "an axis"),
        }
    }

    /// The coordinate system at `i`.
    #[must_use]
    pub fn system(&self, i: usize) -> CoordHandle {
        match self.get(i) {
            Arg::System(h) => h,
            _ => self.wrong(i, "a coordinate system"),
        }
    }

    /// The control structure at `i`.
    #[must_use]
    pub fn control(&self, i: usize) -> InstructionHandle {
        match self.get(i) {
            Arg::Control(h) => h,
            _ => self.wrong(i, "a control structure"),
        }
    }

    /// The cam profile at `i`.
    #[must_use]
    pub fn cam_profile(&self, i: usize) -> CamProfileHandle {
        match self.get(i) {
            Arg::CamProfile(h) => h,
            _ => self.wrong(i, "a cam profile"),
        }
    }

    /// The number at `i` (an integer reads as its value).
    #[must_use]
    pub fn number(&self, i: usize) -> f64 {
        match self.get(i) {
            Arg::Number(x) => x,
            Arg::Integer(n) => n as f64,
            _ => self.wrong(i, "a number"),
        }
    }

    /// The integer at `i`.
    #[must_use]
    pub fn integer(&self, i: usize) -> i64 {
        match self.get(i) {
            Arg::Integer(n) => n,
            _ => self.wrong(i, "an integer"),
        }
    }

    /// The integer at `i` as a DINT code: a value beyond DINT saturates,
    /// still out of every code's range.
    #[must_use]
    pub fn code(&self, i: usize) -> i32 {
        self.integer(i).clamp(i64::from(i32::MIN), i64::from(i32::MAX)) as i32
    }

    /// The BOOL at `i`.
    #[must_use]
    pub fn bool(&self, i: usize) -> bool {
        match self.get(i) {
            Arg::Bool(b) => b,
            _ => self.wrong(i, "a BOOL"),
        }
    }

    /// The array at `i` from its element to the array's end (`Kind::Values`
    /// given one number: that number); `None` for an element outside its
    /// array ([`Arg::NoElement`]).
    #[must_use]
    pub fn array(&self, i: usize) -> Option<&'a [f64]> {
        match self.get(i) {
            Arg::Array(v) => Some(v),
            Arg::NoElement => None,
            _ => self.wrong(i, "an array"),
        }
    }

    /// The tag reference at `i` (MAOC's Output and Input words).
    #[must_use]
    pub fn reference(&self, i: usize) -> usize {
        match self.get(i) {
            Arg::Reference(r) => r,
            _ => self.wrong(i, "a tag reference"),
        }
    }

    /// The `OUTPUT_CAM` elements at `i`; `None` for an element outside its
    /// array.
    #[must_use]
    pub fn output_cams(&self, i: usize) -> Option<&'a [crate::output_cam::OutputCamElement]> {
        match self.get(i) {
            Arg::OutputCams(v) => Some(v),
            Arg::NoElement => None,
            _ => self.wrong(i, "OUTPUT_CAM elements"),
        }
    }

    /// The `OUTPUT_COMPENSATION` elements at `i`; `None` for an element
    /// outside its array.
    #[must_use]
    pub fn compensations(&self, i: usize) -> Option<&'a [crate::output_cam::OutputCompensation]> {
        match self.get(i) {
            Arg::Compensations(v) => Some(v),
            Arg::NoElement => None,
            _ => self.wrong(i, "OUTPUT_COMPENSATION elements"),
        }
    }

    /// The optional array at `i`: empty for `0`; `None` for an element
    /// outside its array.
    #[must_use]
    pub fn optional_array(&self, i: usize) -> Option<&'a [f64]> {
        match self.get(i) {
            Arg::None => Some(&[]),
            _ => self.array(i),
        }
    }

    /// The CAM array at `i`, whole, and the element the operand starts at.
    #[must_use]
    pub fn cam(&self, i: usize) -> (&'a [CamElement], usize) {
        match self.get(i) {
            Arg::Cam(points, start) => (points, start),
            _ => self.wrong(i, "a CAM array"),
        }
    }
}
