//! The program's I/O points: the tags the cell's devices write (inputs)
//! and read (outputs), resolved once to tag memory.
//!
//! A device names its tag as `[trace] tags` does: a BOOL (`PartAtPick`),
//! a bit of an integer (`DI.3`, as a 1756-IB16 gives
//! `Local:1:I.Data.3`), an element or member with constant subscripts
//! (`Cell.Eyes[2]`, `Line.Infeed.Run`), or a DINT or REAL for a value.
//! The binding refuses, each as a diagnostic at the reference with its
//! field: a name that is not a tag, a computed subscript, a type the device
//! cannot use, two devices writing the same bit (or one writing a whole
//! integer another writes a bit of), and a tag that is both an input and
//! an output (the input update would overwrite the program's output every
//! update). Several devices may read one output.
//!
//! Inputs are written straight into tag memory by `run.rs` before the
//! scans of an update (a routine may write an input tag too, as on a
//! controller, and the next input update overwrites it); outputs are read
//! after them.

use super::ir::Place;
use super::memory::Memory;
use super::types::{DataType, Value};
use crate::scene::{IoDirection, IoKind};

/// One I/O point: a slot of tag memory, or a bit of an integer slot.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct IoPoint {
    slot: usize,
    /// The bit number, for a bit of an integer.
    bit: Option<u32>,
    /// The slot's type.
    ty: DataType,
}

impl IoPoint {
    /// Whether the point's type is what `kind` needs.
    pub(super) fn fits(&self, kind: IoKind) -> bool {
        match kind {
            IoKind::Bool => self.bit.is_some() || self.ty == DataType::Bool,
            IoKind::Dint => self.bit.is_none() && self.ty == DataType::Dint,
            IoKind::Real | IoKind::Real3 => self.bit.is_none() && self.ty == DataType::Real,
        }
    }

    /// The point `k` slots after this one (the elements after `Pos[0]`).
    #[must_use]
    pub fn next(&self, k: usize, mem: &Memory) -> Option<IoPoint> {
        let slot = self.slot + k;
        (self.bit.is_none() && slot < mem.types.len()).then(|| IoPoint {
            slot,
            bit: None,
            ty: mem.types[slot],
        })
    }

    /// The point's type in words (`a bit`, `DINT`).
    pub(super) fn describe(&self) -> String {
        if self.bit.is_some() {
            "a bit".to_owned()
        } else {
            self.ty.name().to_owned()
        }
    }

    /// Writes an input: a BOOL or bit from `value`'s truth, a DINT wrapped
    /// to 32 bits, a REAL at single precision.
    pub(super) fn write(&self, mem: &mut Memory, value: Value) {
        match self.bit {
            Some(b) => {
                let old = mem.slots[self.slot].as_i64();
                let new = if value.truthy() { old | 1 << b } else { old & !(1 << b) };
                mem.slots[self.slot] = Value::Int(self.ty.wrap(i128::from(new)));
            }
            None => {
                let v = match (self.ty, value) {
                    (DataType::Dint, Value::Int(x)) => Value::Int(self.ty.wrap(i128::from(x))),
                    _ => value,
                };
                mem.slots[self.slot] = self.ty.store(v).0;
            }
        }
    }

    /// Reads an output.
    pub(super) fn read(&self, mem: &Memory) -> Value {
        let v = mem.slots[self.slot];
        match self.bit {
            Some(b) => Value::Bool(v.as_i64() >> b & 1 == 1),
            None => v,
        }
    }

    /// Whether two points write the same memory: the same slot and bit, or
    /// a whole slot and a bit of it.
    fn overlaps(&self, other: &IoPoint) -> bool {
        self.slot == other.slot && (self.bit.is_none() || other.bit.is_none() || self.bit == other.bit)
    }
}

/// The I/O points bound so far, with what each is, for `twin check`'s I/O
/// list and the overlap check.
#[derive(Debug, Clone, Default)]
pub struct IoMap {
    points: Vec<(IoPoint, IoEntry)>,
}

/// What an I/O point is, as `twin check` lists it.
#[derive(Debug, Clone, PartialEq)]
pub struct IoEntry {
    /// The tag as written.
    pub tag: String,
    /// Input or output.
    pub direction: IoDirection,
    /// The device's name.
    pub device: String,
    /// What the device does with it (`beam`, `run`, `encoder`, …).
    pub role: String,
    /// The field it is written in.
    pub field: String,
}

impl IoMap {
    /// Adds a point. Refused, with the message saying which: an input
    /// that overlaps an input bound before (one input, one device), and an
    /// input and an output that overlap (the input update would overwrite
    /// what the program writes for the output every update).
    pub(super) fn add(&mut self, point: IoPoint, entry: IoEntry, text: &str) -> Result<(), String> {
        let clash = self.points.iter().find(|(p, e)| {
            p.overlaps(&point) && (e.direction == IoDirection::Input || entry.direction == IoDirection::Input)
        });
        if let Some((_, other)) = clash {
            return Err(if other.direction == entry.direction {
                format!(
                    "'{text}' is written by {} '{}' already ({}: '{}'): one input, one device",
                    other.role, other.device, other.field, other.tag
                )
            } else {
                format!(
                    "'{text}' is an {} already ({} of '{}'): a tag is an input or an output, not both \
                     (each input update would overwrite the program's output)",
                    direction_word(other.direction),
                    other.field,
                    other.device
                )
            });
        }
        self.points.push((point, entry));
        Ok(())
    }

    /// The input device entry that writes `point` (or a bit of it).
    #[must_use]
    pub fn input_at(&self, point: IoPoint) -> Option<&IoEntry> {
        self.points
            .iter()
            .find(|(p, e)| e.direction == IoDirection::Input && p.overlaps(&point))
            .map(|(_, e)| e)
    }

    /// Every point bound, in binding order.
    pub fn entries(&self) -> impl Iterator<Item = &IoEntry> {
        self.points.iter().map(|(_, e)| e)
    }
}

fn direction_word(d: IoDirection) -> &'static str {
    match d {
        IoDirection::Input => "input",
        IoDirection::Output => "output",
    }
}

/// Resolves a place the compiler gave for a device's tag to a point; `None`
/// when it is not plain tag memory with constant subscripts.
pub(super) fn point_of(place: &Place, mem: &Memory) -> Option<IoPoint> {
    let constant = |e: &super::ir::CExpr| match e.kind {
        super::ir::CKind::Const(v) => Some(v.as_i64()),
        _ => None,
    };
    let slot = |p: &Place| -> Option<usize> {
        match p {
            Place::Slot(i) => Some(*i),
            Place::Element { index, .. } => p.element_slot(constant(index)?),
            Place::Path { base, terms } => {
                let mut slot = *base;
                for t in terms.iter() {
                    let i = constant(&t.index)?;
                    if !(0..t.len as i64).contains(&i) {
                        return None;
                    }
                    slot += i as usize * t.slots;
                }
                Some(slot)
            }
            _ => None,
        }
    };
    match place {
        Place::Bit { inner, width, bit, .. } => {
            let s = slot(inner)?;
            let b = constant(bit)?;
            (0..i64::from(*width)).contains(&b).then(|| IoPoint {
                slot: s,
                bit: Some(b as u32),
                ty: mem.types[s],
            })
        }
        p => {
            let s = slot(p)?;
            Some(IoPoint {
                slot: s,
                bit: None,
                ty: mem.types[s],
            })
        }
    }
}
