//! Validation of `[[data_types]]` (user-defined structures and string
//! types) and of the values of tags of those types.
//!
//! Names are read first, so that a member may name a data type declared
//! further down; a data type that contains itself, directly or through
//! others, is refused naming the chain. A member is a number, a BOOL, a
//! string type or another data type, with one dimension at most
//! (`dimension = N`), as in Logix Designer's data type editor; an
//! instruction's structure (`FBD_TIMER`, `FBD_COUNTER`, `FBD_ONESHOT`, the
//! IEC blocks) is a member too, and so is a `MOTION_INSTRUCTION` (the
//! planner keeps one control structure per concrete member). The other
//! tags the planner keeps (`COORDINATE_SYSTEM`, `CAM_PROFILE`, PLCopen
//! blocks) are declared as tags of their own, not as members.

use std::collections::HashMap;

use toml::Spanned;

use super::context::Ctx;
use super::error::{Problem, SceneError};
use super::model::{
    BaseType, DataTypeDef, MAX_ARRAY_LEN, MAX_STRING_LENGTH, MemberDef, TagType, TagValue, UserType, intern,
};
use super::raw::RawDataType;
use super::tags::scalar_value;

/// Whether a member may have this type: a scalar, a string type, a data
/// type, or an instruction's structure (`FBD_TIMER` …); not a cam point.
pub(super) fn member_type_allowed(base: BaseType) -> bool {
    (base.in_tag_memory() || base.is_instruction_structure() || base == BaseType::MotionInstruction)
        && base != BaseType::Cam
}

impl Ctx<'_> {
    /// `[[data_types]]`, after the predefined `STRING`.
    pub(super) fn data_types(&self, raw: &[RawDataType]) -> Result<Vec<DataTypeDef>, SceneError> {
        let mut seen: HashMap<String, (usize, ())> = HashMap::new();
        for (i, d) in raw.iter().enumerate() {
            let field = format!("data_types[{i}].name");
            let name = self.identifier(&d.name, &field)?;
            if BaseType::parse(&name).is_some() || name.eq_ignore_ascii_case("STRING") {
                return Err(self.invalid(&d.name, field, Problem::PredefinedTypeName { name }));
            }
            if self.data_types.borrow().len() > usize::from(u16::MAX) {
                let problem = Problem::OutOfRange {
                    value: (i + 1) as f64,
                    min: 1.0,
                    max: f64::from(u16::MAX) - 1.0,
                    exclusive: false,
                };
                return Err(self.invalid(&d.name, field, problem));
            }
            self.unique(&mut seen, &d.name, &field, ())?;
            let string_length = match &d.string_length {
                Some(n) => Some(self.int_in_range(
                    n,
                    &format!("data_types[{i}].string_length"),
                    1,
                    MAX_STRING_LENGTH as i64,
                )? as usize),
                None => None,
            };
            self.data_types.borrow_mut().push(DataTypeDef {
                name,
                description: d.description.clone().unwrap_or_default(),
                members: Vec::new(),
                string_length,
                location: self.loc(&d.name),
            });
        }
        for (i, d) in raw.iter().enumerate() {
            let members = self.members(d, i)?;
            self.data_types.borrow_mut()[i + 1].members = members;
        }
        self.refuse_cycles(raw)?;
        for (i, d) in raw.iter().enumerate() {
            let leaves = self.leaves(BaseType::User(self.user_type(i + 1)));
            if leaves > MAX_ARRAY_LEN {
                let problem = Problem::ArrayTooLong {
                    type_name: d.name.get_ref().clone(),
                    max: MAX_ARRAY_LEN,
                    why: "the twin's limit for the values one tag holds, members of members included",
                };
                return Err(self.invalid(&d.name, format!("data_types[{i}].members"), problem));
            }
        }
        Ok(self.data_types.borrow().clone())
    }

    fn members(&self, d: &RawDataType, i: usize) -> Result<Vec<MemberDef>, SceneError> {
        let field = |j: usize, f: &str| format!("data_types[{i}].members[{j}].{f}");
        let raw_members = d.members.as_ref().map_or(&[][..], |m| m.get_ref().as_slice());
        match (&d.string_length, raw_members.is_empty()) {
            (Some(n), false) => {
                let problem = Problem::DataTypeShape {
                    what: "this one has both",
                };
                return Err(self.invalid(n, format!("data_types[{i}].string_length"), problem));
            }
            (None, true) => {
                let problem = Problem::DataTypeShape {
                    what: "this one has neither",
                };
                return Err(self.invalid(&d.name, format!("data_types[{i}].members"), problem));
            }
            _ => {}
        }
        let mut seen: HashMap<String, (usize, ())> = HashMap::new();
        let mut out = Vec::with_capacity(raw_members.len());
        for (j, m) in raw_members.iter().enumerate() {
            let name = self.identifier(&m.name, &field(j, "name"))?;
            self.unique(&mut seen, &m.name, &field(j, "name"), ())?;
            let mut ty = self.tag_type(&m.ty, &field(j, "type"))?;
            if !member_type_allowed(ty.base) {
                let problem = Problem::MemberTypeNotAllowed { base: ty.base.name() };
                return Err(self.invalid(&m.ty, field(j, "type"), problem));
            }
            if ty.dims[1] > 0 {
                let problem = Problem::MemberDimensions {
                    type_name: m.ty.get_ref().clone(),
                };
                return Err(self.invalid(&m.ty, field(j, "type"), problem));
            }
            if let Some(n) = &m.dimension {
                if ty.array_len.is_some() {
                    let problem = Problem::MemberDimensions {
                        type_name: format!("{} with dimension = {}", m.ty.get_ref(), n.get_ref()),
                    };
                    return Err(self.invalid(n, field(j, "dimension"), problem));
                }
                let len = self.int_in_range(n, &field(j, "dimension"), 1, MAX_ARRAY_LEN as i64)? as usize;
                ty = TagType::new(ty.base, Some(len));
            }
            out.push(MemberDef {
                name,
                ty,
                description: m.description.clone().unwrap_or_default(),
                location: self.loc(&m.name),
            });
        }
        Ok(out)
    }

    /// The data type at `index` of [`Ctx::data_types`], as a base type.
    fn user_type(&self, index: usize) -> UserType {
        UserType {
            index: index as u16,
            name: intern(&self.data_types.borrow()[index].name),
        }
    }

    /// A data type by name, case-insensitively.
    pub(super) fn find_data_type(&self, name: &str) -> Option<BaseType> {
        let index = self
            .data_types
            .borrow()
            .iter()
            .position(|d| d.name.eq_ignore_ascii_case(name))?;
        Some(BaseType::User(self.user_type(index)))
    }

    /// A data type that contains itself is refused at the member that
    /// closes the chain.
    fn refuse_cycles(&self, raw: &[RawDataType]) -> Result<(), SceneError> {
        // 0 unvisited, 1 on the path, 2 done.
        let types = self.data_types.borrow().clone();
        let mut state = vec![0u8; types.len()];
        let mut path: Vec<usize> = Vec::new();
        fn visit(
            at: usize,
            types: &[DataTypeDef],
            state: &mut [u8],
            path: &mut Vec<usize>,
        ) -> Option<(usize, usize, Vec<usize>)> {
            state[at] = 1;
            path.push(at);
            for (j, m) in types[at].members.iter().enumerate() {
                let BaseType::User(u) = m.ty.base else { continue };
                let next = usize::from(u.index);
                match state[next] {
                    1 => {
                        let from = path.iter().position(|p| *p == next).unwrap_or(0);
                        let mut cycle = path[from..].to_vec();
                        cycle.push(next);
                        return Some((at, j, cycle));
                    }
                    0 => {
                        if let Some(found) = visit(next, types, state, path) {
                            return Some(found);
                        }
                    }
                    _ => {}
                }
            }
            path.pop();
            state[at] = 2;
            None
        }
        for start in 1..types.len() {
            if state[start] != 0 {
                continue;
            }
            if let Some((at, j, cycle)) = visit(start, &types, &mut state, &mut path) {
                let names: Vec<&str> = cycle.iter().map(|k| types[*k].name.as_str()).collect();
                let member = raw[at - 1].members.as_ref().map(|m| &m.get_ref()[j].ty);
                let field = format!("data_types[{}].members[{j}].type", at - 1);
                let problem = Problem::RecursiveDataType {
                    cycle: names.join(" → "),
                };
                return Err(match member {
                    Some(ty) => self.invalid(ty, field, problem),
                    None => self.invalid(&raw[at - 1].name, field, problem),
                });
            }
        }
        Ok(())
    }

    /// The values one element of `base` holds (a scalar 1; a string type
    /// its length and LEN; a data type its members', recursively), capped
    /// past [`MAX_ARRAY_LEN`].
    pub(super) fn leaves(&self, base: BaseType) -> usize {
        if base.is_instruction_structure() {
            // The largest instruction structure's slots (FBD_TIMER's 13),
            // rounded up: a bound, not a layout.
            return 16;
        }
        let BaseType::User(u) = base else { return 1 };
        let types = self.data_types.borrow();
        let def = &types[usize::from(u.index)];
        if let Some(n) = def.string_length {
            return n + 1;
        }
        let members: Vec<TagType> = def.members.iter().map(|m| m.ty).collect();
        drop(types);
        members
            .iter()
            .map(|t| self.leaves(t.base).saturating_mul(t.array_len.unwrap_or(1)))
            .fold(0usize, |a, b| a.saturating_add(b).min(MAX_ARRAY_LEN + 1))
    }

    /// The initial value of one element of data type `u`: a string for a
    /// string type, else a table of member values (members left out are
    /// zero). Errors point at the tag's `value`, the field naming the
    /// member (`tags[2].value.Station[1].Count`).
    pub(super) fn user_value(
        &self,
        at: &Spanned<toml::Value>,
        value: &toml::Value,
        u: UserType,
        field: &str,
    ) -> Result<TagValue, SceneError> {
        let def = self.data_types.borrow()[usize::from(u.index)].clone();
        let ty = TagType::new(BaseType::User(u), None);
        let mismatch = |expected| self.invalid(at, field, Problem::ValueMismatch { ty, expected });
        if let Some(n) = def.string_length {
            let toml::Value::String(text) = value else {
                return Err(mismatch("a string of ASCII characters"));
            };
            let bad = |why: String| {
                let shown: String = text.chars().take(40).collect();
                let problem = Problem::BadString {
                    ty: u.name,
                    text: if shown.len() < text.len() {
                        format!("{shown}…")
                    } else {
                        shown
                    },
                    why,
                };
                self.invalid(at, field, problem)
            };
            if !text.is_ascii() {
                return Err(bad("a string type holds ASCII characters (one SINT each)".to_owned()));
            }
            if text.len() > n {
                return Err(bad(format!("it has {} characters, DATA holds {n}", text.len())));
            }
            return Ok(TagValue::Text(text.clone()));
        }
        let toml::Value::Table(table) = value else {
            return Err(mismatch("a table of member values, { Member = value, … }"));
        };
        let mut out: Vec<Option<TagValue>> = vec![None; def.members.len()];
        for (key, v) in table {
            let Some(k) = def.members.iter().position(|m| m.name.eq_ignore_ascii_case(key)) else {
                let problem = Problem::UnknownMember {
                    ty: u.name,
                    member: key.clone(),
                    members: def
                        .members
                        .iter()
                        .map(|m| m.name.as_str())
                        .collect::<Vec<_>>()
                        .join(", "),
                };
                return Err(self.invalid(at, field, problem));
            };
            let m = &def.members[k];
            let f = format!("{field}.{}", m.name);
            out[k] = Some(self.element_values(at, v, m.ty, &f)?);
        }
        Ok(TagValue::Struct(out))
    }

    /// A member's value: one element, or exactly N of them.
    fn element_values(
        &self,
        at: &Spanned<toml::Value>,
        v: &toml::Value,
        ty: TagType,
        field: &str,
    ) -> Result<TagValue, SceneError> {
        let one = |v: &toml::Value, f: &str| match ty.base {
            BaseType::User(inner) => self.user_value(at, v, inner, f),
            base if base.is_instruction_structure() || base == BaseType::MotionInstruction => Err(self.invalid(
                at,
                f,
                Problem::ValueNotAllowed {
                    ty: TagType::new(base, None),
                },
            )),
            base => scalar_value(base, v).ok_or_else(|| {
                self.invalid(
                    at,
                    f,
                    Problem::ValueMismatch {
                        ty: TagType::new(base, None),
                        expected: "a value of the member's type",
                    },
                )
            }),
        };
        match ty.array_len {
            None => one(v, field),
            Some(len) => match v {
                toml::Value::Array(items) if items.len() == len => items
                    .iter()
                    .enumerate()
                    .map(|(k, item)| one(item, &format!("{field}[{k}]")))
                    .collect::<Result<Vec<_>, _>>()
                    .map(TagValue::Array),
                _ => Err(self.invalid(
                    at,
                    field,
                    Problem::ValueMismatch {
                        ty,
                        expected: "an array of exactly N elements of the element type",
                    },
                )),
            },
        }
    }
}
