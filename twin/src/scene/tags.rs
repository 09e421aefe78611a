//! Validation of tags: data types (Logix base types, arrays, cam points,
//! function blocks), initial values and coordinate-system settings.

use planner::coord::CoordinateSystemConfig;
use planner::modulo::MoveOptions;
use toml::Spanned;

use super::context::{Ctx, NameKind, Names};
use super::error::{Problem, SceneError};
use super::model::{
    Axis, BaseType, CamPoint, Connection, CoordinateSystemSettings, ExternalAccess, FunctionBlock, MAX_ARRAY_LEN, Tag,
    TagType, TagValue, Usage,
};
use super::raw::{RawCoordinateSystem, RawMoveOptions, RawTag};

impl Ctx<'_> {
    /// `[[aliases]]` of one scope: each name unique in the scope's
    /// `names`, each `alias_for` a reference (a tag, a member, an element
    /// or a bit; what it names is the program stage's to resolve).
    pub(super) fn aliases(
        &self,
        raw: &[super::raw::RawAlias],
        names: &mut super::context::Names,
        prefix: &str,
    ) -> Result<Vec<super::model::Alias>, SceneError> {
        let mut out = Vec::with_capacity(raw.len());
        for (i, a) in raw.iter().enumerate() {
            let field = |f: &str| format!("{prefix}[{i}].{f}");
            let name = self.identifier(&a.name, &field("name"))?;
            self.unique(names, &a.name, &field("name"), super::context::NameKind::Tag)?;
            let expr = self.parse_in(&a.alias_for, &field("alias_for"), crate::st::parse::parse_expression)?;
            let crate::st::ast::ExprKind::Ref(target) = expr.kind else {
                let why =
                    "an alias stands for a tag, a member, an element or a bit: alias_for = \"Tag.Member\"".to_owned();
                return Err(self.invalid(&a.alias_for, field("alias_for"), Problem::Rule { why }));
            };
            out.push(super::model::Alias {
                name,
                target,
                description: a.description.as_ref().map(|d| d.get_ref().clone()).unwrap_or_default(),
                location: self.loc(&a.name),
            });
        }
        Ok(out)
    }

    pub(super) fn tag_type(&self, raw: &Spanned<String>, field: &str) -> Result<TagType, SceneError> {
        let written = raw.get_ref().trim();
        let (base_name, dims) = match written.split_once('[') {
            Some((base, rest)) => {
                let bad = |problem: Problem| self.invalid(raw, field, problem);
                let bad_len = || {
                    bad(Problem::BadArrayLength {
                        type_name: written.to_owned(),
                    })
                };
                let list = rest.strip_suffix(']').ok_or_else(bad_len)?;
                let parts: Vec<&str> = list.split(',').map(str::trim).collect();
                if parts.len() > 3 {
                    return Err(bad(Problem::TooManyDimensions {
                        type_name: written.to_owned(),
                        count: parts.len(),
                    }));
                }
                let mut dims = [0usize; 3];
                for (k, part) in parts.iter().enumerate() {
                    let len: usize = part.parse().map_err(|_| bad_len())?;
                    if len == 0 {
                        return Err(bad_len());
                    }
                    dims[k] = len;
                }
                (base.trim(), dims)
            }
            None => (written, [0; 3]),
        };
        let array_len = (dims[0] > 0).then(|| {
            dims.iter()
                .filter(|d| **d > 0)
                .try_fold(1usize, |n, d| n.checked_mul(*d))
                .unwrap_or(usize::MAX)
        });
        let Some(base) = BaseType::parse(base_name).or_else(|| self.find_data_type(base_name)) else {
            return Err(self.invalid(
                raw,
                field,
                Problem::UnknownTagType {
                    type_name: written.to_owned(),
                },
            ));
        };
        if array_len.is_some()
            && matches!(
                base,
                BaseType::CoordinateSystem | BaseType::MotionGroup | BaseType::FunctionBlock(_)
            )
        {
            return Err(self.invalid(raw, field, Problem::ArrayNotAllowed { base: base.name() }));
        }
        if let Some(len) = array_len
            && len > base.max_array_len()
        {
            let why = if matches!(base, BaseType::Cam | BaseType::CamProfile) {
                "MCCP's Length is a UINT"
            } else {
                "the twin's limit for an array tag"
            };
            let problem = Problem::ArrayTooLong {
                type_name: written.to_owned(),
                max: base.max_array_len(),
                why,
            };
            return Err(self.invalid(raw, field, problem));
        }
        if let (BaseType::User(_), Some(len)) = (base, array_len)
            && len.saturating_mul(self.leaves(base)) > MAX_ARRAY_LEN
        {
            let problem = Problem::ArrayTooLong {
                type_name: written.to_owned(),
                max: MAX_ARRAY_LEN,
                why: "the twin's limit for the values one tag holds, elements × members",
            };
            return Err(self.invalid(raw, field, problem));
        }
        Ok(TagType { base, array_len, dims })
    }

    /// A tag's `usage`: program tags only (`prefix` names a program's
    /// tags); `local` unless given.
    fn usage(&self, t: &RawTag, prefix: &str, f: &dyn Fn(&str) -> String) -> Result<Usage, SceneError> {
        let Some(raw) = &t.usage else {
            if let Some(c) = &t.connection {
                return Err(self.invalid(c, f("connection"), Problem::ConnectionWithoutParameter));
            }
            return Ok(Usage::Local);
        };
        if prefix == "tags" {
            return Err(self.invalid(raw, f("usage"), Problem::UsageOnControllerTag));
        }
        let usage = self.word(raw, &f("usage"), "usage", &Usage::WORDS)?;
        match (usage, &t.connection) {
            (Usage::InOut, None) => Err(self.invalid(raw, f("connection"), Problem::InOutNeedsConnection)),
            (Usage::Local | Usage::Public, Some(c)) => {
                Err(self.invalid(c, f("connection"), Problem::ConnectionWithoutParameter))
            }
            _ => Ok(usage),
        }
    }

    /// A `connection`: `Tag` (a controller tag) or `\Program.Param`.
    fn connection(&self, raw: &Spanned<String>, field: &str) -> Result<Connection, SceneError> {
        let text = raw.get_ref().trim();
        let ident = |s: &str| {
            let mut chars = s.chars();
            chars.next().is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
                && chars.all(|c| c.is_ascii_alphanumeric() || c == '_')
        };
        let bad = || {
            self.invalid(
                raw,
                field,
                Problem::BadConnection {
                    text: text.to_owned(),
                    why: "write a controller tag (Tag) or another program's parameter (\\Program.Param)".to_owned(),
                },
            )
        };
        match text.strip_prefix('\\') {
            Some(rest) => match rest.split_once('.') {
                Some((program, param)) if ident(program) && ident(param) => Ok(Connection::Parameter {
                    program: program.to_owned(),
                    param: param.to_owned(),
                }),
                _ => Err(bad()),
            },
            None if ident(text) => Ok(Connection::Controller(text.to_owned())),
            None => Err(bad()),
        }
    }

    /// An MC_MoveModulo instance's `Options` (module doc of
    /// [`planner::modulo`]): `EnableBlendingPosition` is refused by name.
    fn move_options(&self, raw: &RawMoveOptions, field: &str) -> Result<MoveOptions, SceneError> {
        if let Some(flag) = &raw.enable_blending_position
            && *flag.get_ref()
        {
            let problem = Problem::OptionNotSimulated {
                member: "EnableBlendingPosition",
                why: "a blending MC_MoveModulo hands over at the running command's target",
            };
            return Err(self.invalid(flag, format!("{field}.EnableBlendingPosition"), problem));
        }
        let blending_position = match &raw.blending_position {
            Some(p) => self.finite(p, &format!("{field}.BlendingPosition"))?,
            None => 0.0,
        };
        Ok(MoveOptions {
            enable_blending_position: false,
            blending_position,
            ignore_position_monitoring: raw.ignore_position_monitoring.unwrap_or(false),
            enable_stop_position_monitoring: raw.enable_stop_position_monitoring.unwrap_or(false),
        })
    }

    /// The tags of `raw`, whose fields are named `{prefix}[i].field`.
    pub(super) fn tags(
        &self,
        raw: &[RawTag],
        axes: &[Axis],
        names: &mut Names,
        prefix: &str,
    ) -> Result<Vec<Tag>, SceneError> {
        let mut tags: Vec<Tag> = Vec::with_capacity(raw.len());
        for (i, t) in raw.iter().enumerate() {
            let f = |field: &str| format!("{prefix}[{i}].{field}");
            // A module's I/O tag (`Local:1:I`) is a name of its own kind.
            let name = if crate::st::lex::is_module_tag_name(t.name.get_ref()) {
                t.name.get_ref().clone()
            } else {
                self.identifier(&t.name, &f("name"))?
            };
            let ty = self.tag_type(&t.ty, &f("type"))?;
            if let Some(period) = &t.coarse_update_ms
                && ty.base != BaseType::MotionGroup
            {
                let why = "only a MOTION_GROUP tag has a coarse update period".to_owned();
                return Err(self.invalid(period, f("coarse_update_ms"), Problem::Rule { why }));
            }
            if ty.base == BaseType::MotionGroup {
                let first = tags.iter().find(|t| t.ty.base == BaseType::MotionGroup);
                let why = match first {
                    _ if prefix != "tags" => Some("not a program's".to_owned()),
                    Some(first) => Some(format!("'{}' is already it", first.name)),
                    None => None,
                };
                if let Some(why) = why {
                    return Err(self.invalid(&t.ty, f("type"), Problem::OneMotionGroup { why }));
                }
            }
            self.unique(names, &t.name, &f("name"), NameKind::Tag)?;
            let value = match &t.value {
                Some(v) => Some(self.tag_value(v, ty, axes, &f("value"))?),
                None if ty.base == BaseType::CoordinateSystem => {
                    let problem = Problem::ValueRequired {
                        ty,
                        expected: "value = [\"AxisName\", ...]",
                    };
                    return Err(self.invalid(&t.ty, f("value"), problem));
                }
                None => None,
            };
            let coordinate_system = match (&t.coordinate_system, &value) {
                (Some(raw), _) if ty.base != BaseType::CoordinateSystem => {
                    return Err(self.invalid(raw, f("coordinate_system"), Problem::CoordinateSystemOnly));
                }
                (raw, Some(TagValue::Axes(members))) => {
                    Some(self.coordinate_system(raw.as_ref(), axes, members.len(), &t.name, &f("coordinate_system"))?)
                }
                _ => None,
            };
            let geometry = match (&t.geometry, &value) {
                (Some(raw), _) if ty.base != BaseType::CoordinateSystem => {
                    return Err(self.invalid(raw, f("geometry"), Problem::CoordinateSystemOnly));
                }
                (Some(raw), Some(TagValue::Axes(members))) => {
                    Some(self.geometry(raw, members.len(), &f("geometry"))?)
                }
                _ => None,
            };
            let move_options = match &t.options {
                Some(raw) if ty.base != BaseType::FunctionBlock(FunctionBlock::MoveModulo) => {
                    return Err(self.invalid(raw, f("options"), Problem::MoveOptionsOnly));
                }
                Some(raw) => self.move_options(raw.get_ref(), &f("options"))?,
                None => MoveOptions::default(),
            };
            tags.push(Tag {
                name,
                ty,
                value,
                coordinate_system,
                geometry,
                move_options,
                usage: self.usage(t, prefix, &f)?,
                constant: match &t.constant {
                    Some(c) if *c.get_ref() && !ty.base.in_tag_memory() => {
                        let problem = Problem::ConstantNotAllowed { ty };
                        return Err(self.invalid(c, f("constant"), problem));
                    }
                    Some(c) => *c.get_ref(),
                    None => false,
                },
                description: t.description.clone().unwrap_or_default(),
                external_access: match &t.external_access {
                    None => ExternalAccess::ReadWrite,
                    Some(w) => self.word(w, &f("external_access"), "external access", &ExternalAccess::WORDS)?,
                },
                connection: match &t.connection {
                    Some(c) => Some(self.connection(c, &f("connection"))?),
                    None => None,
                },
                scheduled_output: match &t.scheduled_output {
                    Some(s) if prefix != "tags" || ty != TagType::new(BaseType::Dint, None) => {
                        let why = "a scheduled output is a controller DINT tag (the Output word)".to_owned();
                        return Err(self.invalid(s, f("scheduled_output"), Problem::Rule { why }));
                    }
                    Some(s) => {
                        let scheduled = self.scheduled_output(s.get_ref(), axes, &f("scheduled_output"))?;
                        let same = |o: &super::model::ScheduledOutput| {
                            (o.axis, o.execution_target) == (scheduled.axis, scheduled.execution_target)
                        };
                        if let Some(first) = tags.iter().find(|t| t.scheduled_output.as_ref().is_some_and(same)) {
                            let why = format!(
                                "'{}' is already the scheduled output of this axis' execution target {}",
                                first.name, scheduled.execution_target
                            );
                            return Err(self.invalid(s, f("scheduled_output"), Problem::Rule { why }));
                        }
                        Some(scheduled)
                    }
                    None => None,
                },
                location: self.loc(&t.name),
            });
        }
        Ok(tags)
    }

    /// A tag's `scheduled_output`: an axis of the scene, one of its output
    /// cam execution targets, and a response time of at most 1 s.
    fn scheduled_output(
        &self,
        raw: &super::raw::RawScheduledOutput,
        axes: &[Axis],
        field: &str,
    ) -> Result<super::model::ScheduledOutput, SceneError> {
        let f = |x: &str| format!("{field}.{x}");
        let axis = axes
            .iter()
            .position(|a| a.name.eq_ignore_ascii_case(raw.axis.get_ref().trim()))
            .ok_or_else(|| {
                let problem = Problem::UnknownAxis {
                    name: raw.axis.get_ref().clone(),
                    nearest: None,
                };
                self.invalid(&raw.axis, f("axis"), problem)
            })?;
        let targets = axes[axis].config.output_cam_execution_targets;
        let execution_target = match &raw.execution_target {
            Some(t) => match u32::try_from(*t.get_ref()).ok().filter(|k| *k < targets) {
                Some(k) => k,
                None => {
                    let why = format!(
                        "the axis has output cam execution targets 0 to {}",
                        targets.saturating_sub(1)
                    );
                    return Err(self.invalid(t, f("execution_target"), Problem::Rule { why }));
                }
            },
            None => 0,
        };
        let response_s = match &raw.response_ms {
            Some(r) => self.in_range(r, &f("response_ms"), 0.0, 1000.0)? / 1000.0,
            None => 0.0,
        };
        Ok(super::model::ScheduledOutput {
            axis,
            execution_target,
            response_s,
        })
    }

    pub(super) fn coordinate_system(
        &self,
        raw: Option<&Spanned<RawCoordinateSystem>>,
        axes: &[Axis],
        members: usize,
        name: &Spanned<String>,
        field: &str,
    ) -> Result<CoordinateSystemSettings, SceneError> {
        let f = |x: &str| format!("{field}.{x}");
        let default_primary = members.min(3);
        let defaults = CoordinateSystemConfig {
            axis_count: members,
            primary_axes: default_primary,
            ..CoordinateSystemConfig::new(name.get_ref().clone())
        };
        let Some(raw) = raw else {
            return Ok(CoordinateSystemSettings {
                system: defaults,
                tool_link: None,
                master_axis: None,
                location: self.loc(name),
            });
        };
        let r = raw.get_ref();
        let primary_axes = match &r.primary_axes {
            Some(p) => self.int_in_range(p, &f("primary_axes"), 1, default_primary as i64)? as usize,
            None => default_primary,
        };
        let pos = |v: &Option<Spanned<f64>>, name: &str, default: f64| self.positive_or(v, &f(name), default);
        let non_neg = |v: &Option<Spanned<f64>>, name: &str, default: f64| self.non_negative_or(v, &f(name), default);
        let system = CoordinateSystemConfig {
            primary_axes,
            max_speed: pos(&r.max_speed, "max_speed", defaults.max_speed)?,
            max_accel: pos(&r.max_accel, "max_accel", defaults.max_accel)?,
            max_decel: non_neg(&r.max_decel, "max_decel", defaults.max_decel)?,
            max_accel_jerk: non_neg(&r.max_accel_jerk, "max_accel_jerk", defaults.max_accel_jerk)?,
            max_decel_jerk: non_neg(&r.max_decel_jerk, "max_decel_jerk", defaults.max_decel_jerk)?,
            command_tolerance: non_neg(&r.command_tolerance, "command_tolerance", defaults.command_tolerance)?,
            actual_tolerance: non_neg(&r.actual_tolerance, "actual_tolerance", defaults.actual_tolerance)?,
            ..defaults
        };
        Ok(CoordinateSystemSettings {
            system,
            tool_link: match &r.tool_link {
                Some(l) => Some(self.nonempty_name(l, &f("tool_link"))?),
                None => None,
            },
            master_axis: match &r.master_axis {
                Some(m) => match axes.iter().find(|a| a.name.eq_ignore_ascii_case(m.get_ref())) {
                    Some(a) => Some(a.name.clone()),
                    None => {
                        let problem = Problem::UnknownAxis {
                            name: m.get_ref().clone(),
                            nearest: nearest_axis(m.get_ref(), axes),
                        };
                        return Err(self.invalid(m, f("master_axis"), problem));
                    }
                },
                None => None,
            },
            location: self.loc(raw),
        })
    }

    pub(super) fn tag_value(
        &self,
        v: &Spanned<toml::Value>,
        ty: TagType,
        axes: &[Axis],
        field: &str,
    ) -> Result<TagValue, SceneError> {
        let mismatch = |expected| self.invalid(v, field, Problem::ValueMismatch { ty, expected });
        match (ty.base, ty.array_len) {
            (
                BaseType::MotionInstruction
                | BaseType::MotionGroup
                | BaseType::CamProfile
                | BaseType::FunctionBlock(_)
                | BaseType::FbdTimer
                | BaseType::FbdCounter
                | BaseType::FbdOneshot
                | BaseType::RTrig
                | BaseType::FTrig
                | BaseType::Ton
                | BaseType::Tof
                | BaseType::Timer
                | BaseType::Counter
                | BaseType::Control,
                _,
            ) => Err(self.invalid(v, field, Problem::ValueNotAllowed { ty })),
            (BaseType::CoordinateSystem, _) => {
                let expected = "an array of 1 to 6 distinct axis names";
                let toml::Value::Array(items) = v.get_ref() else {
                    return Err(mismatch(expected));
                };
                if items.is_empty() || items.len() > 6 {
                    return Err(mismatch(expected));
                }
                let mut members: Vec<String> = Vec::new();
                for item in items {
                    let toml::Value::String(axis) = item else {
                        return Err(mismatch(expected));
                    };
                    let Some(found) = axes.iter().find(|a| a.name.eq_ignore_ascii_case(axis)) else {
                        let problem = Problem::UnknownAxis {
                            name: axis.clone(),
                            nearest: nearest_axis(axis, axes),
                        };
                        return Err(self.invalid(v, field, problem));
                    };
                    if members.iter().any(|m| m.eq_ignore_ascii_case(axis)) {
                        return Err(mismatch(expected));
                    }
                    members.push(found.name.clone());
                }
                Ok(TagValue::Axes(members))
            }
            (BaseType::Cam, len) => {
                let expected = "an array of { master = .., slave = .., segment_type = \"linear\" | \"cubic\" } tables";
                let toml::Value::Array(items) = v.get_ref() else {
                    return Err(mismatch(expected));
                };
                let dims = ty.dimensions();
                if dims.len() > 1 {
                    // One cam a row (the last dimension): an array of rows,
                    // each as a one-dimensional CAM's value; the points a row
                    // leaves out are the controller's initial ones.
                    let row_len = dims[dims.len() - 1];
                    let rows = len.unwrap_or(1) / row_len;
                    if items.is_empty() || items.len() > rows {
                        return Err(mismatch(
                            "an array of at most N rows (the leading dimensions), each an array of cam points",
                        ));
                    }
                    let mut points: Vec<CamPoint> = Vec::with_capacity(items.len() * row_len);
                    for (k, row) in items.iter().enumerate() {
                        let toml::Value::Array(row) = row else {
                            return Err(mismatch("an array of rows, each an array of cam points"));
                        };
                        let mut these = self.cam_points(v, row, row_len, &format!("{field}[{k}]"))?;
                        these.resize(row_len, CamPoint::initial());
                        points.extend(these);
                    }
                    return Ok(TagValue::CamPoints(points));
                }
                self.cam_points(v, items, len.unwrap_or(1), field)
                    .map(TagValue::CamPoints)
            }
            (BaseType::User(u), None) => self.user_value(v, v.get_ref(), u, field),
            (base, Some(len)) => {
                let expected = if ty.dimensions().len() > 1 || matches!(base, BaseType::User(_)) {
                    "an array of all the elements in row-major order (the last subscript fastest), flat or nested by dimension"
                } else {
                    "an array of exactly N elements of the element type"
                };
                let toml::Value::Array(items) = v.get_ref() else {
                    return Err(mismatch(expected));
                };
                let mut flat: Vec<&toml::Value> = Vec::with_capacity(len);
                if items.len() == len && items.iter().all(|i| !i.is_array()) {
                    flat.extend(items);
                } else if !flatten(items, ty.dimensions(), &mut flat) {
                    return Err(mismatch(expected));
                }
                flat.iter()
                    .enumerate()
                    .map(|(k, item)| match base {
                        BaseType::User(u) => self.user_value(v, item, u, &format!("{field}[{k}]")),
                        _ => scalar_value(base, item).ok_or_else(|| mismatch(expected)),
                    })
                    .collect::<Result<_, _>>()
                    .map(TagValue::Array)
            }
            (base, None) => {
                let expected = match base {
                    BaseType::Bool => "true or false",
                    BaseType::Real | BaseType::Lreal => "a finite number",
                    _ => "an integer within the type's range",
                };
                scalar_value(base, v.get_ref()).ok_or_else(|| mismatch(expected))
            }
        }
    }
}

impl Ctx<'_> {
    /// 1 to `max` cam points, masters strictly increasing.
    fn cam_points(
        &self,
        v: &Spanned<toml::Value>,
        items: &[toml::Value],
        max: usize,
        field: &str,
    ) -> Result<Vec<CamPoint>, SceneError> {
        let expected = "an array of { master = .., slave = .., segment_type = \"linear\" | \"cubic\" } tables";
        let ty = TagType::new(BaseType::Cam, Some(max));
        let mismatch = |expected| self.invalid(v, field, Problem::ValueMismatch { ty, expected });
        if items.len() > max || items.is_empty() {
            return Err(mismatch("between 1 and N cam points"));
        }
        let mut points: Vec<CamPoint> = Vec::with_capacity(items.len());
        for (index, item) in items.iter().enumerate() {
            let point: CamPoint = item.clone().try_into().map_err(|_| mismatch(expected))?;
            if !point.master.is_finite() || !point.slave.is_finite() {
                return Err(mismatch(expected));
            }
            if points.last().is_some_and(|p| p.master >= point.master) {
                return Err(self.invalid(v, field, Problem::CamNotIncreasing { index }));
            }
            points.push(point);
        }
        Ok(points)
    }
}

/// Nested arrays of exactly the shape `dims` (outermost first), their
/// scalars appended in row-major order; `false` for any other shape.
fn flatten<'v>(items: &'v [toml::Value], dims: &[usize], out: &mut Vec<&'v toml::Value>) -> bool {
    let Some((&n, inner)) = dims.split_first() else {
        return false;
    };
    if items.len() != n {
        return false;
    }
    for item in items {
        match (item, inner.is_empty()) {
            (toml::Value::Array(sub), false) => {
                if !flatten(sub, inner, out) {
                    return false;
                }
            }
            (toml::Value::Array(_), true) => return false,
            (scalar, true) => out.push(scalar),
            (_, false) => return false,
        }
    }
    true
}

/// A scalar initial value of `base`, if `value` fits it.
pub(super) fn scalar_value(base: BaseType, value: &toml::Value) -> Option<TagValue> {
    match (base, value) {
        (BaseType::Bool, toml::Value::Boolean(b)) => Some(TagValue::Bool(*b)),
        (BaseType::Real | BaseType::Lreal, toml::Value::Float(x)) if x.is_finite() => Some(TagValue::Real(*x)),
        #[allow(clippy::cast_precision_loss)]
        (BaseType::Real | BaseType::Lreal, toml::Value::Integer(i)) => Some(TagValue::Real(*i as f64)),
        (base, toml::Value::Integer(i)) => {
            let (min, max) = base.integer_range()?;
            (min..=max).contains(i).then_some(TagValue::Integer(*i))
        }
        _ => None,
    }
}

/// The declared axis nearest to `name`, for a `help:` line.
fn nearest_axis(name: &str, axes: &[Axis]) -> Option<String> {
    crate::source::diag::nearest(name, axes.iter().map(|a| a.name.as_str())).map(str::to_owned)
}
