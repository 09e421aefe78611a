//! Tag memory: every tag of the controller and of its programs laid out
//! in slots, with the name table the compiler resolves references with.
//!
//! Scalars take one slot, arrays one slot an element, structures
//! ([`Structure`]) one slot a member, data types ([`Layouts`]) one slot
//! a scalar member, members of members included. Tags the planner owns
//! (`MOTION_INSTRUCTION`, `COORDINATE_SYSTEM`, `CAM_PROFILE`, axes) take
//! no slots: their members are read from (and for `MOTION_INSTRUCTION`
//! written to) the planner. A program-scoped tag is stored under
//! `Program.Tag`; inside its program the short name finds it first.

use super::layout::{Elem, Layouts};
pub use super::layout::{scalar, structure};
use super::types::{DataType, Structure, Value};
use crate::scene::{BaseType, CamPoint, SegmentType, TagType, TagValue, Usage};
use std::collections::HashMap;

/// What a tag is, for the compiler.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// A scalar (or an array of them).
    Scalar(DataType),
    /// A structure in slots (or an array of them).
    Structure(Structure),
    /// A tag the planner keeps (motion control structure, coordinate
    /// system, cam profile, function-block instance).
    Planner(BaseType),
    /// An axis (`[[axes]]`).
    Axis,
    /// A data type (`[[data_types]]`, `STRING`, a user string type) in
    /// slots, by its index in [`Memory::layouts`] (or an array of them).
    User(u16),
}

/// One tag's place in memory.
#[derive(Debug, Clone)]
pub struct TagInfo {
    /// The name as declared (`Program.Tag` for a program tag).
    pub name: String,
    /// What it is.
    pub kind: Kind,
    /// First slot.
    pub base: usize,
    /// `Some(n)` for an array of `n` elements.
    pub len: Option<usize>,
    /// An array's dimensions, first to last (0 past the last; all 0 for
    /// a scalar): element `[i, j, k]` is `i·d1·d2 + j·d2 + k`.
    pub dims: [usize; 3],
    /// A program tag's usage (local or a parameter).
    pub usage: Usage,
    /// An InOut parameter: the tag it stands for (every name of it finds
    /// that tag).
    pub alias: Option<usize>,
    /// `constant = true`: no routine writes it.
    pub constant: bool,
    /// Slots one element takes.
    pub stride: usize,
    /// The element type's name (`REAL`, `STRING`, a data type's).
    pub type_name: &'static str,
}

impl TagInfo {
    /// The dimensions that are there (none for a scalar).
    #[must_use]
    pub fn dimensions(&self) -> &[usize] {
        let n = self.dims.iter().take_while(|d| **d > 0).count();
        &self.dims[..n]
    }

    /// Slots one element takes.
    #[must_use]
    pub fn stride(&self) -> usize {
        self.stride
    }

    /// The element type of a tag kept in slots as scalars or a data type.
    #[must_use]
    pub fn elem(&self) -> Option<Elem> {
        match self.kind {
            Kind::Scalar(t) => Some(Elem::Scalar(t)),
            Kind::User(id) => Some(Elem::User(id)),
            _ => None,
        }
    }
}

/// The controller's tag memory.
#[derive(Debug, Clone, Default)]
pub struct Memory {
    /// Values.
    pub slots: Vec<Value>,
    /// The type of each slot.
    pub types: Vec<DataType>,
    /// Tags, in declaration order.
    pub tags: Vec<TagInfo>,
    /// The data types' layouts (`STRING` first).
    pub layouts: Layouts,
    /// Alias tags: (lower-case `Program.Name` or `Name`) → what it stands
    /// for. They hold no memory: the compiler reads the target in their
    /// place.
    pub aliases: HashMap<String, crate::st::ast::Ref>,
    /// Lower-case name → tag, with foldhash's fixed-seed hasher: a compile
    /// looks names up several times a reference.
    by_name: HashMap<NameKey, usize, foldhash::fast::FixedState>,
    /// Lower-case tag name without its program → the controller's tag of
    /// that name and whether a program has one: a controller tag named in
    /// a routine is found with one lookup ([`Memory::resolve`]).
    by_short: HashMap<NameKey, Scoped, foldhash::fast::FixedState>,
}

/// The tags of one name: the controller's, and whether a program has one.
#[derive(Debug, Clone, Copy, Default)]
struct Scoped {
    controller: Option<usize>,
    in_programs: bool,
}

/// The most slots (values) all the tags of a scene may take together:
/// 2²⁴, about 300 MB. Each array is bounded by itself
/// ([`crate::scene::MAX_ARRAY_LEN`]); this bounds their sum, where a
/// structure element takes a slot per member (ten `FBD_TIMER[1000000]`
/// would take 130 million).
pub const MAX_TAG_SLOTS: usize = 1 << 24;

/// The first tag (controller tags, then each program's) with which the
/// scene's tags pass [`MAX_TAG_SLOTS`]: its name, where it is written and
/// the slots they would take up to it. Counted before any is allocated.
#[must_use]
pub fn over_budget(scene: &crate::scene::Scene) -> Option<(String, crate::scene::Location, usize)> {
    let layouts = Layouts::of(&scene.data_types);
    let mut total = 0usize;
    // The program's name beside each of its tags (none for controller
    // tags); the full name is written only for the tag that passes.
    let controller = scene.tags.iter().map(|t| (None, t));
    let programs = scene
        .programs()
        .flat_map(|p| p.tags.iter().map(move |t| (Some(p.name.as_str()), t)));
    for (program, t) in controller.chain(programs) {
        let stride = match (scalar(t.ty.base), structure(t.ty.base), t.ty.base) {
            (Some(_), ..) => 1,
            (_, Some(s), _) => s.size(),
            (.., BaseType::User(u)) => layouts.get(u.index).slots,
            _ => 0,
        };
        total = total.saturating_add(t.ty.array_len.unwrap_or(1).saturating_mul(stride));
        if total > MAX_TAG_SLOTS {
            let name = program.map_or_else(|| t.name.clone(), |p| format!("{p}.{}", t.name));
            return Some((name, t.location, total));
        }
    }
    None
}

impl Memory {
    /// The tag memory of a scene: its axes, its controller tags, then each
    /// program's tags under `Program.Tag`, with their initial values.
    #[must_use]
    pub fn of_scene(scene: &crate::scene::Scene) -> Memory {
        let mut mem = Memory {
            layouts: Layouts::of(&scene.data_types),
            ..Memory::default()
        };
        for a in &scene.axes {
            mem.add_axis(&a.name);
        }
        for t in &scene.tags {
            let k = mem.add(&t.name, t.ty, t.value.as_ref());
            mem.tags[k].constant = t.constant;
            if t.value.is_none() {
                mem.aoi_defaults(k, scene);
            }
        }
        for p in scene.programs() {
            for tag in &p.tags {
                let name = format!("{}.{}", p.name, tag.name);
                let t = mem.add(&name, tag.ty, tag.value.as_ref());
                mem.tags[t].usage = tag.usage;
                mem.tags[t].constant = tag.constant;
                if tag.value.is_none() {
                    mem.aoi_defaults(t, scene);
                }
            }
        }
        for a in &scene.aliases {
            mem.aliases.insert(a.name.to_lowercase(), a.target.clone());
        }
        for p in scene.programs() {
            for a in &p.aliases {
                mem.aliases
                    .insert(format!("{}.{}", p.name, a.name).to_lowercase(), a.target.clone());
            }
        }
        // InOut parameters stand for their connections (checked at load).
        for p in scene.programs() {
            for tag in p.tags.iter().filter(|t| t.usage == Usage::InOut) {
                let own = mem.find_declared(&format!("{}.{}", p.name, tag.name));
                let target = tag
                    .connection
                    .as_ref()
                    .and_then(|c| mem.find_declared(&c.stored_name()));
                if let (Some(own), Some(target)) = (own, target) {
                    mem.tags[own].alias = Some(target);
                }
            }
        }
        mem
    }

    /// An Add-On Instruction instance (or array of them) without a value
    /// of its own: its parameters' and local tags' default values.
    fn aoi_defaults(&mut self, k: usize, scene: &crate::scene::Scene) {
        if scene.add_on_instructions.is_empty() {
            return;
        }
        let Kind::User(id) = self.tags[k].kind else { return };
        let (base, stride) = (self.tags[k].base, self.tags[k].stride);
        for e in 0..self.tags[k].len.unwrap_or(1) {
            self.defaults_at(id, base + e * stride, scene);
        }
    }

    /// The defaults of the instance of data type `id` at slot `base`: its
    /// own when it is an Add-On Instruction's, and those of the instances
    /// among its members (an instruction's local tag of another's type).
    fn defaults_at(&mut self, id: u16, base: usize, scene: &crate::scene::Scene) {
        if let Some(aoi) = scene.add_on_instructions.iter().find(|a| a.data_type.index == id) {
            for (member, v) in &aoi.defaults {
                let Some(m) = self.layouts.get(id).member(member) else {
                    continue;
                };
                let at = base + m.slot;
                let value = if self.types[at] == DataType::Bool || self.types[at].is_integer() {
                    Value::Int(*v as i64)
                } else {
                    Value::Real(*v)
                };
                self.slots[at] = self.types[at].store(value).0;
            }
        }
        let nested: Vec<(u16, usize, usize)> = self
            .layouts
            .get(id)
            .members
            .iter()
            .filter_map(|m| match m.elem {
                crate::program::layout::Elem::User(inner) => Some((inner, m.slot, m.len.unwrap_or(1))),
                _ => None,
            })
            .collect();
        for (inner, slot, n) in nested {
            let size = self.layouts.slots(crate::program::layout::Elem::User(inner));
            for e in 0..n {
                self.defaults_at(inner, base + slot + e * size, scene);
            }
        }
    }

    /// Adds a tag with its initial value (zeros when it has none) and
    /// returns its index.
    pub fn add(&mut self, name: &str, ty: TagType, value: Option<&TagValue>) -> usize {
        let (base, len) = (ty.base, ty.array_len);
        let kind = match (scalar(base), structure(base), base) {
            (Some(t), ..) => Kind::Scalar(t),
            (_, Some(s), _) => Kind::Structure(s),
            (.., BaseType::User(u)) => Kind::User(u.index),
            _ => Kind::Planner(base),
        };
        let start = self.slots.len();
        let stride = match kind {
            Kind::Structure(s) => s.size(),
            Kind::Scalar(_) => 1,
            Kind::User(id) => self.layouts.get(id).slots,
            Kind::Planner(_) | Kind::Axis => 0,
        };
        let info = TagInfo {
            stride,
            type_name: base.name(),
            name: name.to_owned(),
            kind,
            base: start,
            len,
            dims: ty.dims,
            usage: Usage::Local,
            alias: None,
            constant: false,
        };
        let count = len.unwrap_or(1) * info.stride();
        match kind {
            Kind::Scalar(t) => {
                let zero = t.store(Value::Int(0)).0;
                self.slots.resize(start + count, zero);
                self.types.resize(start + count, t);
            }
            Kind::Structure(s) => {
                // EnableIn is TRUE in a new structure: the instruction runs
                // when it is executed.
                for _ in 0..len.unwrap_or(1) {
                    for (name, t, _) in s.members() {
                        self.slots.push(t.store(Value::Bool(*name == "EnableIn")).0);
                        self.types.push(*t);
                    }
                }
            }
            Kind::User(id) => {
                for _ in 0..len.unwrap_or(1) {
                    self.push_zeros(Elem::User(id));
                }
            }
            Kind::Planner(_) | Kind::Axis => {}
        }
        match (kind, value) {
            (Kind::User(id), Some(TagValue::Array(items))) => {
                let each = self.layouts.get(id).slots;
                for (i, v) in items.iter().enumerate() {
                    self.write_initial(Elem::User(id), start + i * each, v);
                }
            }
            (Kind::User(id), Some(v)) => self.write_initial(Elem::User(id), start, v),
            (Kind::Scalar(t), Some(TagValue::Array(items))) => {
                for (i, v) in items.iter().enumerate() {
                    self.slots[start + i] = t.store(initial(v)).0;
                }
            }
            (Kind::Scalar(t), Some(v)) => self.slots[start] = t.store(initial(v)).0,
            (Kind::Structure(Structure::Cam), Some(TagValue::CamPoints(points))) => {
                for (i, p) in points.iter().enumerate() {
                    let at = start + i * 3;
                    self.slots[at] = DataType::Real.store(Value::Real(p.master)).0;
                    self.slots[at + 1] = DataType::Real.store(Value::Real(p.slave)).0;
                    self.slots[at + 2] = Value::Int(segment_code(p.segment_type));
                }
            }
            _ => {}
        }
        self.tags.push(info);
        self.index(name);
        self.tags.len() - 1
    }

    /// Appends the zero slots of one element of `e`.
    fn push_zeros(&mut self, e: Elem) {
        match e {
            Elem::Control => {}
            Elem::Scalar(t) => {
                self.slots.push(t.store(Value::Int(0)).0);
                self.types.push(t);
            }
            Elem::User(id) => {
                let start = self.slots.len();
                let layout = self.layouts.get(id);
                let builtin = layout.builtin;
                let members: Vec<(Elem, usize)> = layout.members.iter().map(|m| (m.elem, m.len.unwrap_or(1))).collect();
                for (elem, n) in members {
                    for _ in 0..n {
                        self.push_zeros(elem);
                    }
                }
                // An instruction's structure starts with EnableIn TRUE, as a
                // tag of its own does.
                if let Some(s) = builtin
                    && s.members().iter().any(|m| m.0 == "EnableIn")
                {
                    self.slots[start + s.offset("EnableIn")] = Value::Bool(true);
                }
            }
        }
    }

    /// Writes a scene value (checked at load against the type) into the
    /// slots of one element of `e` starting at `slot`.
    fn write_initial(&mut self, e: Elem, slot: usize, v: &TagValue) {
        match (e, v) {
            (Elem::Scalar(t), v) => self.slots[slot] = t.store(initial(v)).0,
            (Elem::User(id), TagValue::Text(text)) => {
                let capacity = self.layouts.get(id).string.unwrap_or(0);
                let bytes = &text.as_bytes()[..text.len().min(capacity)];
                self.slots[slot] = Value::Int(bytes.len() as i64);
                for (k, b) in bytes.iter().enumerate() {
                    self.slots[slot + 1 + k] = Value::Int(i64::from(*b as i8));
                }
            }
            (Elem::User(id), TagValue::Struct(values)) => {
                let members: Vec<(Elem, usize, usize)> = self
                    .layouts
                    .get(id)
                    .members
                    .iter()
                    .map(|m| (m.elem, m.slot, self.layouts.slots(m.elem)))
                    .collect();
                for ((elem, at, each), v) in members.into_iter().zip(values) {
                    match v {
                        Some(TagValue::Array(items)) => {
                            for (i, item) in items.iter().enumerate() {
                                self.write_initial(elem, slot + at + i * each, item);
                            }
                        }
                        Some(v) => self.write_initial(elem, slot + at, v),
                        None => {}
                    }
                }
            }
            _ => {}
        }
    }

    /// Adds an axis name (no slots).
    pub fn add_axis(&mut self, name: &str) {
        self.tags.push(TagInfo {
            stride: 0,
            type_name: "AXIS",
            name: name.to_owned(),
            kind: Kind::Axis,
            base: self.slots.len(),
            len: None,
            dims: [0; 3],
            usage: Usage::Local,
            alias: None,
            constant: false,
        });
        self.index(name);
    }

    /// The tag called `name` (case-insensitive), as stored; an InOut
    /// parameter's name finds the tag it stands for.
    #[must_use]
    pub fn find(&self, name: &str) -> Option<usize> {
        let t = self.find_declared(name)?;
        Some(self.tags[t].alias.unwrap_or(t))
    }

    /// The tag declared as `name` (an InOut parameter itself).
    #[must_use]
    pub fn find_declared(&self, name: &str) -> Option<usize> {
        self.declared_in(None, name)
    }

    /// The tag declared as `program.name`, or `name` without a program
    /// (case-insensitive).
    fn declared_in(&self, program: Option<&str>, name: &str) -> Option<usize> {
        let key = match program {
            Some(p) => NameKey::of(&[p, ".", name]),
            None => NameKey::of(&[name]),
        };
        self.by_name.get(&key).copied()
    }

    /// Slots a tag takes.
    #[must_use]
    pub fn slot_count(&self, tag: usize) -> usize {
        let info = &self.tags[tag];
        info.len.unwrap_or(1) * info.stride()
    }

    /// The target of the alias `name` in this scope: the program's own
    /// alias, else (when the program has no tag of the name) the
    /// controller's.
    #[must_use]
    pub fn alias(&self, program: Option<&str>, name: &str) -> Option<&crate::st::ast::Ref> {
        if self.aliases.is_empty() {
            return None;
        }
        if let Some(p) = program {
            if let Some(r) = self.aliases.get(&format!("{p}.{name}").to_lowercase()) {
                return Some(r);
            }
            if self.find(&format!("{p}.{name}")).is_some() {
                return None;
            }
        }
        self.aliases.get(&name.to_lowercase())
    }

    /// The tag `name` as seen from `program`: its own tag first, then the
    /// controller's.
    #[must_use]
    pub fn resolve(&self, program: Option<&str>, name: &str) -> Option<usize> {
        let declared = if name.contains('.') {
            // `Program.Tag` written out.
            program
                .and_then(|p| self.declared_in(Some(p), name))
                .or_else(|| self.declared_in(None, name))?
        } else {
            let scoped = self.scoped(name)?;
            match program {
                Some(p) if scoped.in_programs => self.declared_in(Some(p), name).or(scoped.controller)?,
                _ => scoped.controller?,
            }
        };
        Some(self.tags[declared].alias.unwrap_or(declared))
    }

    /// The tags called `name` (no program part, case-insensitive).
    fn scoped(&self, name: &str) -> Option<Scoped> {
        self.by_short.get(&NameKey::of(&[name])).copied()
    }

    /// Enters the last tag added under `name` in the name tables (a name
    /// added again finds the later tag).
    fn index(&mut self, name: &str) {
        let t = self.tags.len() - 1;
        self.by_name.insert(NameKey::of(&[name]), t);
        match name.split_once('.') {
            Some((_, short)) => self.by_short.entry(NameKey::of(&[short])).or_default().in_programs = true,
            None => self.by_short.entry(NameKey::of(&[name])).or_default().controller = Some(t),
        }
    }

    /// A tag's current value in the scene's form (numeric arrays and cam
    /// points), for instruction operands read when they execute.
    #[must_use]
    pub fn value(&self, tag: usize) -> Option<TagValue> {
        let info = &self.tags[tag];
        let n = info.len.unwrap_or(1);
        let read = |slot: usize| match self.slots[slot] {
            Value::Bool(b) => TagValue::Bool(b),
            Value::Int(i) => TagValue::Integer(i),
            Value::Real(x) => TagValue::Real(x),
        };
        match info.kind {
            Kind::Scalar(_) if info.len.is_some() => {
                Some(TagValue::Array((0..n).map(|i| read(info.base + i)).collect()))
            }
            Kind::Scalar(_) => Some(read(info.base)),
            Kind::Structure(Structure::Cam) => Some(TagValue::CamPoints(
                (0..n)
                    .map(|i| {
                        let at = info.base + 3 * i;
                        CamPoint {
                            master: self.slots[at].as_f64(),
                            slave: self.slots[at + 1].as_f64(),
                            segment_type: segment(self.slots[at + 2].as_i64()),
                        }
                    })
                    .collect(),
            )),
            _ => None,
        }
    }
}

fn initial(v: &TagValue) -> Value {
    match v {
        TagValue::Bool(b) => Value::Bool(*b),
        TagValue::Integer(i) => Value::Int(*i),
        TagValue::Real(x) => Value::Real(*x),
        _ => Value::Int(0),
    }
}

/// A cam point's `SegmentType` code: 0 linear, 1 cubic.
fn segment_code(s: SegmentType) -> i64 {
    match s {
        SegmentType::Linear => 0,
        SegmentType::Cubic => 1,
    }
}

/// The segment type a program wrote: 0 is linear, any other value cubic
/// (the controller's MCCP reads the member the same way: zero or not).
fn segment(code: i64) -> SegmentType {
    if code == 0 {
        SegmentType::Linear
    } else {
        SegmentType::Cubic
    }
}

/// The key a tag name is stored under: its lower-case bytes, kept in the
/// table itself when they fit (most names), so that a lookup compares
/// them without following a pointer. The compiler looks names up a few
/// times for every reference it compiles.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
enum NameKey {
    /// Up to [`INLINE_NAME`] bytes, zero-padded (a name holds no NUL).
    Inline([u8; INLINE_NAME]),
    /// A longer name.
    Long(Box<[u8]>),
}

/// The longest name kept inline in a [`NameKey`].
const INLINE_NAME: usize = 32;

impl NameKey {
    /// The key of the name `parts` joined.
    fn of(parts: &[&str]) -> NameKey {
        let len: usize = parts.iter().map(|p| p.len()).sum();
        if len > INLINE_NAME {
            return NameKey::Long(parts.concat().to_ascii_lowercase().into_bytes().into_boxed_slice());
        }
        let mut bytes = [0u8; INLINE_NAME];
        let mut n = 0;
        for p in parts {
            bytes[n..n + p.len()].copy_from_slice(p.as_bytes());
            n += p.len();
        }
        bytes.make_ascii_lowercase();
        NameKey::Inline(bytes)
    }
}
