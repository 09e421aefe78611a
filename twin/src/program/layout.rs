//! Data types (`[[data_types]]`, `STRING` and the user string types) laid
//! out twice: in tag memory, one slot a scalar value, and in the bytes a
//! Logix controller keeps, which `COP` and `CPS` copy.
//!
//! # The byte layout (Logix Designer's, as its data type editor shows it)
//! * Members follow in declaration order, each aligned to its own size:
//!   SINT/USINT 1 byte, INT/UINT 2, DINT/UDINT/REAL 4, LINT/ULINT/LREAL 8;
//!   a structure member to its structure's alignment.
//! * Consecutive BOOL members share a hidden SINT, eight to a byte, bit 0
//!   first; any other member ends the run.
//! * A BOOL array takes whole 32-bit words, aligned to 4 (`BOOL[40]` is 8
//!   bytes), bit `i` in word `i / 32`.
//! * A structure is aligned to 4 bytes, or 8 with a 64-bit member inside,
//!   and its size is rounded up to that alignment.
//! * A string type is `LEN` DINT then `DATA` SINT[n]: `STRING` is 4 + 82
//!   bytes, rounded to 88.
//! * A `MOTION_INSTRUCTION` member is the planner's (a control structure
//!   per concrete member, `Axes[2].Move`): it takes no slot and, in the
//!   twin's layout, no byte, so COP does not copy it.

use super::types::{DataType, Structure, Value};
use crate::scene::{BaseType, DataTypeDef, MemberDef, TagType};

/// The element type of a member, or of a tag of a data type.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Elem {
    /// A scalar.
    Scalar(DataType),
    /// A data type, by its index in [`Layouts`].
    User(u16),
    /// A `MOTION_INSTRUCTION`: the planner keeps it (one control structure
    /// per concrete member, named by its path); no slots, no bytes.
    Control,
}

/// One member of a data type.
#[derive(Debug, Clone, PartialEq)]
pub struct Member {
    /// The name as declared.
    pub name: String,
    /// Its element type.
    pub elem: Elem,
    /// `Some(n)` for an array of `n`.
    pub len: Option<usize>,
    /// Slot offset inside the structure.
    pub slot: usize,
    /// Byte offset inside the structure.
    pub byte: usize,
    /// The bit of a BOOL packed in a hidden SINT (0 otherwise).
    pub bit: u8,
}

/// One data type's layout.
#[derive(Debug, Clone, PartialEq)]
pub struct Layout {
    /// The type's name.
    pub name: String,
    /// Its members (`LEN` and `DATA` for a string type).
    pub members: Vec<Member>,
    /// Slots one element takes.
    pub slots: usize,
    /// Bytes one element takes.
    pub bytes: usize,
    /// Its alignment, bytes (4 or 8).
    pub align: usize,
    /// A string type's `DATA` length.
    pub string: Option<usize>,
    /// An instruction's structure (`FBD_TIMER` …) as a data type's member:
    /// its members are the structure's, in its order, the hidden ones
    /// included (a program names the visible ones only).
    pub builtin: Option<Structure>,
}

impl Layout {
    /// A member by name, case-insensitively.
    #[must_use]
    pub fn member(&self, name: &str) -> Option<&Member> {
        self.members.iter().find(|m| m.name.eq_ignore_ascii_case(name))
    }

    /// The member names, for messages.
    #[must_use]
    pub fn member_names(&self) -> String {
        self.members
            .iter()
            .map(|m| m.name.as_str())
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// Every data type's layout, indexed as [`crate::scene::Scene::data_types`].
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Layouts(Vec<Layout>);

fn round_up(x: usize, to: usize) -> usize {
    x.div_ceil(to) * to
}

/// Bytes a scalar takes (BOOL: 1, as a tag of its own).
#[must_use]
pub fn scalar_bytes(t: DataType) -> usize {
    (t.bits() as usize / 8).max(1)
}

impl Layouts {
    /// The layouts of a scene's data types (checked acyclic at load),
    /// then one for each instruction structure a member may be
    /// ([`Structure::ALL`], at [`builtin_index`]).
    #[must_use]
    pub fn of(types: &[DataTypeDef]) -> Layouts {
        let mut all: Vec<DataTypeDef> = types.to_vec();
        all.extend(Structure::ALL.iter().map(|s| structure_def(*s)));
        let mut done: Vec<Option<Layout>> = vec![None; all.len()];
        for k in 0..all.len() {
            lay_out(k, &all, types.len(), &mut done);
        }
        for (k, s) in Structure::ALL.iter().enumerate() {
            if let Some(l) = done[types.len() + k].as_mut() {
                l.builtin = Some(*s);
            }
        }
        Layouts(done.into_iter().map(|l| l.expect("every type laid out")).collect())
    }

    /// The layout of data type `id`.
    #[must_use]
    pub fn get(&self, id: u16) -> &Layout {
        &self.0[usize::from(id)]
    }

    /// Slots one element takes.
    #[must_use]
    pub fn slots(&self, e: Elem) -> usize {
        match e {
            Elem::Scalar(_) => 1,
            Elem::User(id) => self.get(id).slots,
            Elem::Control => 0,
        }
    }

    /// Bytes one element takes (a BOOL 1).
    #[must_use]
    pub fn bytes(&self, e: Elem) -> usize {
        match e {
            Elem::Scalar(t) => scalar_bytes(t),
            Elem::User(id) => self.get(id).bytes,
            Elem::Control => 0,
        }
    }

    /// The bytes of `count` elements of `e` whose slots start at `slot`,
    /// appended to `out` (an array of BOOL packs 32 to a word).
    pub fn encode(&self, e: Elem, count: usize, slots: &[Value], slot: usize, out: &mut Vec<u8>) {
        match e {
            Elem::Control => {}
            Elem::Scalar(DataType::Bool) if count > 1 => {
                let start = out.len();
                out.resize(start + count.div_ceil(32) * 4, 0);
                for i in 0..count {
                    if slots[slot + i].truthy() {
                        out[start + i / 8] |= 1 << (i % 8);
                    }
                }
            }
            Elem::Scalar(t) => {
                for i in 0..count {
                    push_scalar(t, slots[slot + i], out);
                }
            }
            Elem::User(id) => {
                let l = self.get(id);
                for i in 0..count {
                    let start = out.len();
                    let base = slot + i * l.slots;
                    for m in &l.members {
                        let at = start + m.byte;
                        if out.len() < at {
                            out.resize(at, 0);
                        }
                        match (m.elem, m.len) {
                            (Elem::Scalar(DataType::Bool), None) => {
                                if out.len() <= at {
                                    out.push(0);
                                }
                                if slots[base + m.slot].truthy() {
                                    out[at] |= 1 << m.bit;
                                }
                            }
                            (elem, len) => self.encode(elem, len.unwrap_or(1), slots, base + m.slot, out),
                        }
                    }
                    out.resize(start + l.bytes, 0);
                }
            }
        }
    }

    /// Writes `count` elements of `e` into the slots from `slot`, from the
    /// bytes `bytes` starting at `at` (the inverse of [`Layouts::encode`]).
    pub fn decode(&self, e: Elem, count: usize, bytes: &[u8], at: usize, slots: &mut [Value], slot: usize) {
        match e {
            Elem::Control => {}
            Elem::Scalar(DataType::Bool) if count > 1 => {
                for i in 0..count {
                    slots[slot + i] = Value::Bool(bytes[at + i / 8] >> (i % 8) & 1 == 1);
                }
            }
            Elem::Scalar(t) => {
                let size = scalar_bytes(t);
                for i in 0..count {
                    slots[slot + i] = read_scalar(t, &bytes[at + i * size..at + (i + 1) * size]);
                }
            }
            Elem::User(id) => {
                let l = self.get(id);
                for i in 0..count {
                    let start = at + i * l.bytes;
                    let base = slot + i * l.slots;
                    for m in &l.members {
                        match (m.elem, m.len) {
                            (Elem::Scalar(DataType::Bool), None) => {
                                slots[base + m.slot] = Value::Bool(bytes[start + m.byte] >> m.bit & 1 == 1);
                            }
                            (elem, len) => {
                                self.decode(elem, len.unwrap_or(1), bytes, start + m.byte, slots, base + m.slot);
                            }
                        }
                    }
                }
            }
        }
    }
}

/// The scalar type of a scene base type, if it is one.
#[must_use]
pub fn scalar(base: BaseType) -> Option<DataType> {
    Some(match base {
        BaseType::Bool => DataType::Bool,
        BaseType::Sint => DataType::Sint,
        BaseType::Int => DataType::Int,
        BaseType::Dint => DataType::Dint,
        BaseType::Lint => DataType::Lint,
        BaseType::Usint => DataType::Usint,
        BaseType::Uint => DataType::Uint,
        BaseType::Udint => DataType::Udint,
        BaseType::Ulint => DataType::Ulint,
        BaseType::Real => DataType::Real,
        BaseType::Lreal => DataType::Lreal,
        _ => return None,
    })
}

/// The structure kept in slots for a scene base type, if it is one.
#[must_use]
pub fn structure(base: BaseType) -> Option<Structure> {
    Some(match base {
        BaseType::FbdTimer => Structure::Timer,
        BaseType::FbdCounter => Structure::Counter,
        BaseType::FbdOneshot => Structure::OneShot,
        BaseType::Cam => Structure::Cam,
        BaseType::RTrig | BaseType::FTrig => Structure::Trig,
        BaseType::Ton | BaseType::Tof => Structure::IecTimer,
        BaseType::Timer => Structure::LadderTimer,
        BaseType::Counter => Structure::LadderCounter,
        BaseType::Control => Structure::Control,
        BaseType::OutputCam => Structure::OutputCam,
        BaseType::OutputCompensation => Structure::OutputCompensation,
        _ => return None,
    })
}

/// The element type of a scene base type kept in slots as a member: a
/// scalar, a data type, or an instruction structure (whose layout follows
/// the scene's `user_types` data types).
#[must_use]
pub fn elem_of(base: BaseType, user_types: usize) -> Option<Elem> {
    match base {
        BaseType::User(u) => Some(Elem::User(u.index)),
        BaseType::MotionInstruction => Some(Elem::Control),
        b => scalar(b)
            .map(Elem::Scalar)
            .or_else(|| structure(b).map(|s| Elem::User(builtin_index(s, user_types)))),
    }
}

/// Where an instruction structure's layout is, after `user_types` data
/// types.
#[must_use]
pub fn builtin_index(s: Structure, user_types: usize) -> u16 {
    let k = Structure::ALL.iter().position(|x| *x == s).unwrap_or(0);
    (user_types + k) as u16
}

/// An instruction structure as a data type of its members (each scalar).
fn structure_def(s: Structure) -> DataTypeDef {
    let mut d = DataTypeDef::string();
    d.name = s.name().to_owned();
    d.string_length = None;
    d.members = s
        .members()
        .iter()
        .map(|(name, t, _)| MemberDef {
            name: (*name).to_owned(),
            ty: TagType::new(base_of(*t), None),
            description: String::new(),
            location: crate::scene::Location::default(),
        })
        .collect();
    d
}

/// The scene base type of a scalar type.
fn base_of(t: DataType) -> BaseType {
    match t {
        DataType::Bool => BaseType::Bool,
        DataType::Sint => BaseType::Sint,
        DataType::Int => BaseType::Int,
        DataType::Dint => BaseType::Dint,
        DataType::Lint => BaseType::Lint,
        DataType::Usint => BaseType::Usint,
        DataType::Uint => BaseType::Uint,
        DataType::Udint => BaseType::Udint,
        DataType::Ulint => BaseType::Ulint,
        DataType::Real => BaseType::Real,
        DataType::Lreal => BaseType::Lreal,
    }
}

fn lay_out(k: usize, types: &[DataTypeDef], user_types: usize, done: &mut Vec<Option<Layout>>) {
    if done[k].is_some() {
        return;
    }
    let def = &types[k];
    if let Some(n) = def.string_length {
        done[k] = Some(Layout {
            name: def.name.clone(),
            members: vec![
                Member {
                    name: "LEN".to_owned(),
                    elem: Elem::Scalar(DataType::Dint),
                    len: None,
                    slot: 0,
                    byte: 0,
                    bit: 0,
                },
                Member {
                    name: "DATA".to_owned(),
                    elem: Elem::Scalar(DataType::Sint),
                    len: Some(n),
                    slot: 1,
                    byte: 4,
                    bit: 0,
                },
            ],
            slots: n + 1,
            bytes: round_up(4 + n, 4),
            align: 4,
            string: Some(n),
            builtin: None,
        });
        return;
    }
    for m in &def.members {
        if let Some(Elem::User(id)) = elem_of(m.ty.base, user_types) {
            lay_out(usize::from(id), types, user_types, done);
        }
    }
    let (mut byte, mut slot, mut align) = (0usize, 0usize, 4usize);
    // The hidden SINT the last BOOL went into, and the next free bit.
    let mut host: Option<(usize, u8)> = None;
    let mut members = Vec::with_capacity(def.members.len());
    for m in &def.members {
        let elem = elem_of(m.ty.base, user_types).expect("members are kept in slots (checked at load)");
        let n = m.ty.array_len.unwrap_or(1);
        let (at, bit) = match (elem, m.ty.array_len) {
            (Elem::Scalar(DataType::Bool), None) => match host {
                Some((b, bit)) if bit < 8 => {
                    host = Some((b, bit + 1));
                    (b, bit)
                }
                _ => {
                    host = Some((byte, 1));
                    byte += 1;
                    (byte - 1, 0)
                }
            },
            (Elem::Scalar(DataType::Bool), Some(_)) => {
                host = None;
                let at = round_up(byte, 4);
                byte = at + n.div_ceil(32) * 4;
                (at, 0)
            }
            (Elem::Scalar(t), _) => {
                host = None;
                let size = scalar_bytes(t);
                align = align.max(size);
                let at = round_up(byte, size);
                byte = at + size * n;
                (at, 0)
            }
            (Elem::Control, _) => {
                // A structure on the controller: it ends a run of BOOLs.
                host = None;
                (byte, 0)
            }
            (Elem::User(id), _) => {
                host = None;
                let inner = done[usize::from(id)].as_ref().expect("laid out above");
                align = align.max(inner.align);
                let at = round_up(byte, inner.align);
                byte = at + inner.bytes * n;
                (at, 0)
            }
        };
        let slots_each = match elem {
            Elem::Scalar(_) => 1,
            Elem::User(id) => done[usize::from(id)].as_ref().map_or(0, |l| l.slots),
            Elem::Control => 0,
        };
        members.push(Member {
            name: m.name.clone(),
            elem,
            len: m.ty.array_len,
            slot,
            byte: at,
            bit,
        });
        slot += slots_each * n;
    }
    done[k] = Some(Layout {
        name: def.name.clone(),
        members,
        slots: slot,
        bytes: round_up(byte.max(1), align),
        align,
        string: None,
        builtin: None,
    });
}

fn push_scalar(t: DataType, v: Value, out: &mut Vec<u8>) {
    match t {
        DataType::Bool => out.push(u8::from(v.truthy())),
        DataType::Real => out.extend_from_slice(&(v.as_f64() as f32).to_le_bytes()),
        DataType::Lreal => out.extend_from_slice(&v.as_f64().to_le_bytes()),
        _ => {
            let bytes = v.as_i64().to_le_bytes();
            out.extend_from_slice(&bytes[..scalar_bytes(t)]);
        }
    }
}

fn read_scalar(t: DataType, b: &[u8]) -> Value {
    let mut word = [0u8; 8];
    word[..b.len()].copy_from_slice(b);
    let raw = i64::from_le_bytes(word);
    match t {
        DataType::Bool => Value::Bool(b[0] & 1 == 1),
        DataType::Real => Value::Real(f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]]))),
        DataType::Lreal => Value::Real(f64::from_le_bytes(word)),
        _ => Value::Int(t.wrap(i128::from(raw))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::UserType;

    fn member(name: &str, base: BaseType, len: Option<usize>) -> MemberDef {
        MemberDef {
            name: name.to_owned(),
            ty: TagType::new(base, len),
            description: String::new(),
            location: crate::scene::Location::default(),
        }
    }

    fn udt(name: &str, members: Vec<MemberDef>) -> DataTypeDef {
        let mut d = DataTypeDef::string();
        d.name = name.to_owned();
        d.string_length = None;
        d.members = members;
        d
    }

    fn user(index: u16) -> BaseType {
        BaseType::User(UserType { index, name: "T" })
    }

    /// Sizes and offsets as Logix Designer's data type editor gives them.
    #[test]
    fn members_align_to_their_size_and_bools_pack() {
        let types = vec![
            DataTypeDef::string(),
            // SINT, DINT: the DINT at 4, 8 bytes.
            udt(
                "A",
                vec![member("s", BaseType::Sint, None), member("d", BaseType::Dint, None)],
            ),
            // Nine BOOLs: two hidden SINTs, then an INT at 2; 4 bytes.
            udt(
                "B",
                (0..9)
                    .map(|i| member(&format!("b{i}"), BaseType::Bool, None))
                    .chain([member("i", BaseType::Int, None)])
                    .collect(),
            ),
            // BOOL, LREAL: 8-byte alignment, 16 bytes.
            udt(
                "C",
                vec![member("b", BaseType::Bool, None), member("x", BaseType::Lreal, None)],
            ),
            // BOOL[40] after a SINT: words from 4, 12 bytes.
            udt(
                "D",
                vec![member("s", BaseType::Sint, None), member("f", BaseType::Bool, Some(40))],
            ),
            // SINT then a nested C (8-aligned) and a STRING.
            udt(
                "E",
                vec![
                    member("s", BaseType::Sint, None),
                    member("c", user(3), None),
                    member("t", user(0), None),
                ],
            ),
        ];
        let l = Layouts::of(&types);
        assert_eq!((l.get(0).bytes, l.get(0).slots), (88, 83));
        let a = l.get(1);
        assert_eq!((a.members[1].byte, a.bytes), (4, 8));
        let b = l.get(2);
        assert_eq!((b.members[7].byte, b.members[7].bit), (0, 7));
        assert_eq!((b.members[8].byte, b.members[8].bit), (1, 0));
        assert_eq!((b.members[9].byte, b.bytes), (2, 4));
        let c = l.get(3);
        assert_eq!((c.members[1].byte, c.bytes, c.align), (8, 16, 8));
        let d = l.get(4);
        assert_eq!((d.members[1].byte, d.bytes, d.slots), (4, 12, 41));
        let e = l.get(5);
        assert_eq!((e.members[1].byte, e.members[2].byte, e.bytes), (8, 24, 112));
        assert_eq!((e.members[1].slot, e.members[2].slot, e.slots), (1, 3, 86));
    }

    #[test]
    fn a_motion_instruction_member_takes_no_slot_and_ends_a_run_of_bools() {
        let types = vec![
            DataTypeDef::string(),
            udt(
                "A",
                vec![
                    member("a", BaseType::Bool, None),
                    member("mv", BaseType::MotionInstruction, None),
                    member("b", BaseType::Bool, None),
                ],
            ),
        ];
        let l = Layouts::of(&types);
        let a = l.get(1);
        assert_eq!(a.members[1].elem, Elem::Control);
        assert_eq!(
            (a.members[2].byte, a.members[2].bit),
            (1, 0),
            "b starts a new hidden SINT"
        );
        assert_eq!((a.slots, a.bytes), (2, 4));
    }

    #[test]
    fn bytes_round_trip() {
        let types = vec![
            DataTypeDef::string(),
            udt(
                "A",
                vec![
                    member("b", BaseType::Bool, None),
                    member("c", BaseType::Bool, None),
                    member("i", BaseType::Int, None),
                    member("x", BaseType::Real, None),
                    member("f", BaseType::Bool, Some(33)),
                    member("u", BaseType::Usint, Some(3)),
                    member("l", BaseType::Lint, None),
                ],
            ),
        ];
        let l = Layouts::of(&types);
        let a = l.get(1);
        let mut slots: Vec<Value> = Vec::new();
        slots.extend([Value::Bool(false), Value::Bool(true), Value::Int(-2), Value::Real(1.5)]);
        slots.extend((0..33).map(|i| Value::Bool(i % 3 == 0)));
        slots.extend([Value::Int(200), Value::Int(0), Value::Int(7), Value::Int(-5)]);
        assert_eq!(slots.len(), a.slots);
        let mut bytes = Vec::new();
        l.encode(Elem::User(1), 1, &slots, 0, &mut bytes);
        assert_eq!(bytes.len(), a.bytes);
        assert_eq!(bytes[0], 0b10, "c is bit 1 of the hidden SINT");
        assert_eq!(&bytes[2..4], &(-2i16).to_le_bytes());
        let mut back = vec![Value::Int(0); slots.len()];
        l.decode(Elem::User(1), 1, &bytes, 0, &mut back, 0);
        assert_eq!(back, slots);
    }
}
