//! Places: reading and writing tag memory, bits, and the members the
//! planner keeps.

use super::Exec;
use super::members::planner_value;
use crate::program::ir::{CExpr, MotionMember, Place};
use crate::program::types::{DataType, Value};
use planner::instruction::MotionInstructionBits;

impl Exec<'_> {
    /// The slot a place reads or writes (`None` for the planner's places,
    /// or when its subscript is out of range, which records the fault).
    pub(super) fn slot(&mut self, place: &Place) -> Option<usize> {
        match place {
            Place::Slot(i) => Some(*i),
            Place::Element { len, index, name, .. } => {
                let i = self.leaf(index).as_i64();
                let slot = place.element_slot(i);
                if slot.is_none() {
                    let f = self.subscript_fault(name, i, *len);
                    self.fail(f);
                }
                slot
            }
            Place::Path { base, terms } => match self.term_offset(terms, |t| t.slots) {
                Ok(offset) => Some(base + offset),
                Err(f) => {
                    self.fail(f);
                    None
                }
            },
            _ => None,
        }
    }

    /// The element of a `MOTION_INSTRUCTION` array the subscript names
    /// (`None` when it lies outside, which records the fault).
    pub(super) fn control_at(
        &mut self,
        handles: &[planner::task::InstructionHandle],
        index: &CExpr,
        name: &str,
    ) -> Option<planner::task::InstructionHandle> {
        let i = self.leaf(index).as_i64();
        match usize::try_from(i).ok().and_then(|k| handles.get(k)) {
            Some(h) => Some(*h),
            None => {
                let f = self.subscript_fault(name, i, handles.len());
                self.fail(f);
                None
            }
        }
    }

    pub(super) fn bit_number(&mut self, bit: &CExpr, width: u32) -> Option<u32> {
        let b = self.leaf(bit).as_i64();
        if b < 0 || b >= i64::from(width) {
            let f = self.raise(4, 20, format!("bit {b} is outside a {width}-bit integer"));
            self.fail(f);
            return None;
        }
        Some(b as u32)
    }

    /// Reads a place (0 after a subscript fault, which is recorded).
    pub fn load(&mut self, place: &Place) -> Value {
        if let Place::Slot(i) = place {
            return self.mem.slots[*i];
        }
        if let Place::Element { .. } | Place::Path { .. } = place {
            return self.slot(place).map_or(Value::Int(0), |i| self.mem.slots[i]);
        }
        match place {
            Place::Bit { inner, width, bit, .. } => {
                let v = self.load(inner).as_i64();
                let b = self.bit_number(bit, *width).unwrap_or(0);
                Value::Bool(v >> b & 1 == 1)
            }
            Place::Motion(..) | Place::Axis(..) | Place::Coord(..) | Place::Group(..) | Place::Fb(..) => {
                planner_value(place, self.task).unwrap_or(Value::Int(0))
            }
            Place::MotionAt(handles, index, member, name) => match self.control_at(handles, index, name) {
                Some(h) => planner_value(&Place::Motion(h, *member), self.task).unwrap_or(Value::Int(0)),
                None => Value::Int(0),
            },
            Place::FirstScan => Value::Bool(self.first_scan),
            Place::MinorInScan => Value::Bool(!self.minor.is_empty()),
            Place::MathFlag(bit) => Value::Bool(self.math_flags & bit != 0),
            Place::MinorFaults => Value::Int(self.minor_total.min(i64::from(i32::MAX))),
            Place::Column { index, ty } => {
                let x = self.columns.get(*index).copied().unwrap_or(0.0);
                match ty {
                    DataType::Bool => Value::Bool(x != 0.0),
                    DataType::Real | DataType::Lreal => Value::Real(x),
                    _ => Value::Int(x as i64),
                }
            }
            Place::Slot(_) | Place::Element { .. } | Place::Path { .. } => unreachable!("slots read above"),
        }
    }

    /// Writes a place, converting to its type; nothing after a fault of the
    /// statement (a subscript out of range is recorded).
    pub fn store(&mut self, place: &Place, ty: DataType, v: Value) {
        if self.fault.is_some() {
            return;
        }
        // The common case, a DINT value into a DINT, needs no conversion.
        let (stored, bad) = match (ty, v) {
            (DataType::Dint, Value::Int(x)) if i32::try_from(x).is_ok() => (v, false),
            _ => ty.store(v),
        };
        if bad {
            self.overflow(&format!("the value does not fit {}", ty.name()));
        }
        if let Place::Slot(i) = place {
            self.mem.slots[*i] = stored;
            return;
        }
        if let Place::Element { .. } | Place::Path { .. } = place {
            if let Some(i) = self.slot(place) {
                self.mem.slots[i] = stored;
            }
            return;
        }
        match place {
            Place::Bit { inner, width, bit, ty } => {
                let Some(b) = self.bit_number(bit, *width) else { return };
                let old = self.load(inner).as_i64();
                let new = if stored.truthy() { old | 1 << b } else { old & !(1 << b) };
                let (value, _) = ty.store(Value::Int(ty.wrap(i128::from(new))));
                self.store(inner, *ty, value);
            }
            Place::Motion(h, MotionMember::Bit(name)) => {
                let mut bits = self.task.motion_bits(*h);
                set_bit(&mut bits, name, stored.truthy());
                self.task.set_motion_bits(*h, bits);
            }
            Place::MotionAt(handles, index, MotionMember::Bit(bit), name) => {
                if let Some(h) = self.control_at(handles, index, name) {
                    let mut bits = self.task.motion_bits(h);
                    set_bit(&mut bits, bit, stored.truthy());
                    self.task.set_motion_bits(h, bits);
                }
            }
            _ => unreachable!("the compiler refuses writes to read-only places"),
        }
    }
}

/// Sets a `MOTION_INSTRUCTION` bit by its name.
fn set_bit(bits: &mut MotionInstructionBits, name: &str, v: bool) {
    match name {
        "EN" => bits.en = v,
        "DN" => bits.dn = v,
        "ER" => bits.er = v,
        "IP" => bits.ip = v,
        "AC" => bits.ac = v,
        "PC" => bits.pc = v,
        "ACCEL" => bits.accel = v,
        _ => bits.decel = v,
    }
}
