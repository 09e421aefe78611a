//! Checks of the cell's tables: `[[part_types]]`, `[[sources]]`,
//! `[[sinks]]`, `[[conveyors]]`, `[[sensors]]` and `parts_step_ms`. Tag
//! references are parsed here; the program resolves them and checks their
//! types when it binds.

use std::collections::HashMap;
use std::path::Path;

use toml::Spanned;

use super::cell_model::{
    Cell, Conveyor, ConveyorDrive, Cylinder, Detect, DeviceFault, FaultKind, Gripper, GripperKind, IoTag, Jitter,
    PartType, Sensor, SensorKind, Sink, SinkOutcome, Source, SourceTrigger, Vfd, VisionSpec,
};
use super::context::{Ctx, ShapeFields};
use super::error::{Problem, SceneError};
use super::model::{Axis, AxisKind, MAX_LENGTH_M, Obstacle, Shape, Units};
use super::raw::{
    Numbers, RawConveyor, RawCylinder, RawFault, RawGripper, RawPartType, RawScene, RawSensor, RawSink, RawSource,
    ShapeKind,
};
use crate::st::parse::parse_expression;

/// The most parts a source may be asked for, and the most `at_s` entries.
const MAX_SOURCE_COUNT: i64 = 1_000_000;

/// The most beams of a light curtain (its bitmask is a DINT).
const MAX_CURTAIN_BEAMS: i64 = 32;

/// The scene's timing, which the cell's rates must fit.
pub(super) struct CellTiming<'a> {
    pub(super) coarse_update_ms: f64,
    pub(super) physics_step_ms: f64,
    pub(super) duration_s: f64,
    pub(super) axes: &'a [Axis],
    pub(super) obstacles: &'a [Obstacle],
}

impl Ctx<'_> {
    pub(super) fn cell(&self, raw: &RawScene, base: &Path, timing: &CellTiming<'_>) -> Result<Cell, SceneError> {
        let parts_step_ms = match &raw.parts_step_ms {
            Some(v) => {
                let ms = self.positive(v, "parts_step_ms")?;
                let per_update = timing.coarse_update_ms / ms;
                let per_step = ms / timing.physics_step_ms;
                let whole = |x: f64| (x - x.round()).abs() < 1e-9 && x.round() >= 1.0;
                if !whole(per_update) || !whole(per_step) {
                    let why = format!(
                        "must be a multiple of physics_step_ms = {} that divides coarse_update_ms = {}",
                        timing.physics_step_ms, timing.coarse_update_ms
                    );
                    return Err(self.invalid(v, "parts_step_ms", Problem::Rule { why }));
                }
                ms
            }
            None => timing.coarse_update_ms,
        };
        let part_types = self.part_types(&raw.part_types, base)?;
        let sources = self.sources(&raw.sources, &part_types, timing.duration_s)?;
        let sinks = self.sinks(&raw.sinks)?;
        let conveyors = self.conveyors(&raw.conveyors, timing)?;
        let sensors = self.sensors(&raw.sensors, &part_types, timing)?;
        let cylinders = self.cylinders(&raw.cylinders)?;
        let grippers = self.grippers(&raw.grippers)?;
        Ok(Cell {
            part_types,
            sources,
            sinks,
            conveyors,
            sensors,
            cylinders,
            grippers,
            parts_step_ms,
        })
    }

    /// A device's tag reference, parsed as an expression.
    fn io_tag(&self, s: &Spanned<String>, field: &str) -> Result<IoTag, SceneError> {
        let expr = self.parse_in(s, field, parse_expression)?;
        Ok(IoTag {
            text: s.get_ref().trim().to_owned(),
            expr,
            field: field.to_owned(),
            location: self.loc(s),
        })
    }

    fn optional_io_tag(&self, s: &Option<Spanned<String>>, field: &str) -> Result<Option<IoTag>, SceneError> {
        s.as_ref().map(|s| self.io_tag(s, field)).transpose()
    }

    pub(super) fn color_or(
        &self,
        c: &Option<Spanned<Numbers<4>>>,
        field: &str,
        default: [f64; 4],
    ) -> Result<[f64; 4], SceneError> {
        let Some(c) = c else { return Ok(default) };
        let rgba = self.finite_array(c, field)?;
        if let Some(&value) = rgba.iter().find(|x| !(0.0..=1.0).contains(*x)) {
            let problem = Problem::OutOfRange {
                value,
                min: 0.0,
                max: 1.0,
                exclusive: false,
            };
            return Err(self.invalid(c, field, problem));
        }
        Ok(rgba)
    }

    fn position(&self, p: &Spanned<Numbers<3>>, field: &str) -> Result<[f64; 3], SceneError> {
        let v = self.finite_array(p, field)?;
        self.at_most(p, field, &v, MAX_LENGTH_M)?;
        Ok(v)
    }

    fn rpy(&self, r: &Option<Spanned<Numbers<3>>>, field: &str) -> Result<[f64; 3], SceneError> {
        r.as_ref().map_or(Ok([0.0; 3]), |r| self.finite_array(r, field))
    }

    fn part_types(&self, raw: &[RawPartType], base: &Path) -> Result<Vec<PartType>, SceneError> {
        let mut seen = HashMap::new();
        let mut out = Vec::with_capacity(raw.len());
        for (i, p) in raw.iter().enumerate() {
            let f = |field: &str| format!("part_types[{i}].{field}");
            let name = self.nonempty_name(&p.name, &f("name"))?;
            self.unique(&mut seen, &p.name, &f("name"), ())?;
            let fields = ShapeFields {
                kind: &p.shape,
                size: &p.size,
                radius: &p.radius,
                length: &p.length,
                file: &p.file,
                scale: &p.scale,
            };
            let shape = self.shape(&fields, base, &f)?;
            let mass_kg = self.positive(&p.mass_kg, &f("mass_kg"))?;
            let friction = match &p.friction {
                Some(v) => self.in_range(v, &f("friction"), 0.0, 10.0)?,
                None => 0.6,
            };
            let restitution = match &p.restitution {
                Some(v) => self.in_range(v, &f("restitution"), 0.0, 1.0)?,
                None => 0.0,
            };
            let type_id = match &p.type_id {
                Some(v) => self.int_in_range(v, &f("type_id"), i64::from(i32::MIN), i64::from(i32::MAX))? as i32,
                None => i32::try_from(i + 1).unwrap_or(i32::MAX),
            };
            out.push(PartType {
                name,
                shape,
                mass_kg,
                friction,
                restitution,
                color: self.color_or(&p.color, &f("color"), [0.85, 0.55, 0.2, 1.0])?,
                material: p
                    .material
                    .as_ref()
                    .map(|m| m.get_ref().trim().to_ascii_lowercase())
                    .unwrap_or_default(),
                type_id,
                location: self.loc(&p.name),
            });
        }
        Ok(out)
    }

    /// An index into `part_types` by name.
    fn part_type_index(
        &self,
        name: &Spanned<String>,
        field: &str,
        part_types: &[PartType],
    ) -> Result<usize, SceneError> {
        part_types
            .iter()
            .position(|p| p.name.eq_ignore_ascii_case(name.get_ref().trim()))
            .ok_or_else(|| {
                let names: Vec<String> = part_types.iter().map(|p| format!("'{}'", p.name)).collect();
                let expected = if names.is_empty() {
                    "a [[part_types]] name (the scene has none)".to_owned()
                } else {
                    names.join(", ")
                };
                let problem = Problem::UnknownWord {
                    what: "part type",
                    word: name.get_ref().clone(),
                    expected,
                };
                self.invalid(name, field, problem)
            })
    }

    fn sources(&self, raw: &[RawSource], part_types: &[PartType], duration_s: f64) -> Result<Vec<Source>, SceneError> {
        let mut seen = HashMap::new();
        let mut out = Vec::with_capacity(raw.len());
        for (i, s) in raw.iter().enumerate() {
            let f = |field: &str| format!("sources[{i}].{field}");
            let name = self.nonempty_name(&s.name, &f("name"))?;
            self.unique(&mut seen, &s.name, &f("name"), ())?;
            let part_type = self.part_type_index(&s.part_type, &f("part_type"), part_types)?;
            let given: Vec<&'static str> = [
                ("every_s", s.every_s.is_some()),
                ("on", s.on.is_some()),
                ("at_s", s.at_s.is_some()),
            ]
            .into_iter()
            .filter_map(|(w, g)| g.then_some(w))
            .collect();
            if given.len() != 1 {
                let why = if given.is_empty() {
                    "give one of every_s, on or at_s: when the source spawns".to_owned()
                } else {
                    format!("give one of every_s, on or at_s, not {}", given.join(" and "))
                };
                return Err(self.invalid(&s.name, f("name"), Problem::Rule { why }));
            }
            let trigger = if let Some(every) = &s.every_s {
                let start_s = match &s.start_s {
                    Some(v) => self.in_range(v, &f("start_s"), 0.0, duration_s)?,
                    None => 0.0,
                };
                SourceTrigger::Every {
                    period_s: self.positive(every, &f("every_s"))?,
                    start_s,
                }
            } else if let Some(on) = &s.on {
                if let Some(v) = &s.start_s {
                    let why = "start_s applies to every_s".to_owned();
                    return Err(self.invalid(v, f("start_s"), Problem::Rule { why }));
                }
                SourceTrigger::On(self.io_tag(on, &f("on"))?)
            } else {
                let at = s.at_s.as_ref().map(Spanned::get_ref).map_or(&[][..], Vec::as_slice);
                let mut times = Vec::with_capacity(at.len());
                for (k, t) in at.iter().enumerate() {
                    let value = self.in_range(t, &format!("sources[{i}].at_s[{k}]"), 0.0, duration_s)?;
                    if times.last().is_some_and(|last| value < *last) {
                        let why = "the times must not decrease".to_owned();
                        return Err(self.invalid(t, format!("sources[{i}].at_s[{k}]"), Problem::Rule { why }));
                    }
                    times.push(value);
                }
                SourceTrigger::At(times)
            };
            let count = match &s.count {
                Some(c) => Some(self.int_in_range(c, &f("count"), 1, MAX_SOURCE_COUNT)? as u32),
                None => None,
            };
            let jitter = match &s.jitter {
                Some(j) => {
                    let raw = j.get_ref();
                    let time_s = self.non_negative_or(&raw.time_s, &f("jitter.time_s"), 0.0)?;
                    if time_s > 0.0 && matches!(trigger, SourceTrigger::On(_)) {
                        let why = "a source spawning on a rise has no time to jitter".to_owned();
                        return Err(self.invalid(j, f("jitter.time_s"), Problem::Rule { why }));
                    }
                    let position_m = match &raw.position_m {
                        Some(p) => self.bounded_array_non_negative(p, &f("jitter.position_m"))?,
                        None => [0.0; 3],
                    };
                    Jitter {
                        time_s,
                        position_m,
                        yaw_deg: self.non_negative_or(&raw.yaw_deg, &f("jitter.yaw_deg"), 0.0)?,
                        seed: match &raw.seed {
                            Some(v) => self.int_in_range(v, &f("jitter.seed"), 0, i64::MAX)? as u64,
                            None => 0,
                        },
                    }
                }
                None => Jitter::default(),
            };
            let mut skip = Vec::new();
            for (k, n) in s
                .skip
                .as_ref()
                .map(Spanned::get_ref)
                .map_or(&[][..], Vec::as_slice)
                .iter()
                .enumerate()
            {
                skip.push(self.int_in_range(n, &format!("sources[{i}].skip[{k}]"), 1, MAX_SOURCE_COUNT)? as u32);
            }
            out.push(Source {
                name,
                part_type,
                position_m: self.position(&s.position, &f("position"))?,
                rpy_deg: self.rpy(&s.rpy_deg, &f("rpy_deg"))?,
                trigger,
                count,
                jitter,
                skip,
                location: self.loc(&s.name),
            });
        }
        Ok(out)
    }

    fn bounded_array_non_negative(&self, v: &Spanned<Numbers<3>>, field: &str) -> Result<[f64; 3], SceneError> {
        let values = self.finite_array(v, field)?;
        if let Some(&value) = values.iter().find(|x| **x < 0.0) {
            return Err(self.invalid(v, field, Problem::Negative { value }));
        }
        self.at_most(v, field, &values, MAX_LENGTH_M)?;
        Ok(values)
    }

    fn sinks(&self, raw: &[RawSink]) -> Result<Vec<Sink>, SceneError> {
        let mut seen = HashMap::new();
        let mut out = Vec::with_capacity(raw.len());
        for (i, s) in raw.iter().enumerate() {
            let f = |field: &str| format!("sinks[{i}].{field}");
            let name = self.nonempty_name(&s.name, &f("name"))?;
            self.unique(&mut seen, &s.name, &f("name"), ())?;
            let outcome = match &s.outcome {
                Some(w) => self.word(
                    w,
                    &f("as"),
                    "sink outcome",
                    &[
                        ("delivered", SinkOutcome::Delivered),
                        ("rejected", SinkOutcome::Rejected),
                    ],
                )?,
                None => SinkOutcome::Delivered,
            };
            out.push(Sink {
                name,
                position_m: self.position(&s.position, &f("position"))?,
                rpy_deg: self.rpy(&s.rpy_deg, &f("rpy_deg"))?,
                size_m: self.bounded_array(&s.size, &f("size"), MAX_LENGTH_M)?,
                outcome,
                location: self.loc(&s.name),
            });
        }
        Ok(out)
    }

    fn faults(
        &self,
        raw: &[RawFault],
        field: &str,
        kinds: &[(&'static str, FaultKind)],
    ) -> Result<Vec<DeviceFault>, SceneError> {
        let mut out = Vec::with_capacity(raw.len());
        for (k, r) in raw.iter().enumerate() {
            let f = |x: &str| format!("{field}[{k}].{x}");
            let kind = self.word(&r.kind, &f("kind"), "fault kind for this device", kinds)?;
            let from_s = self.non_negative(&r.from_s, &f("from_s"))?;
            let to_s = match &r.to_s {
                Some(v) => {
                    let to = self.finite(v, &f("to_s"))?;
                    if to <= from_s {
                        let problem = Problem::WindowOrder {
                            low: "from_s",
                            low_s: from_s,
                            high: "to_s",
                            high_s: to,
                        };
                        return Err(self.invalid(v, f("to_s"), problem));
                    }
                    to
                }
                None => f64::INFINITY,
            };
            out.push(DeviceFault { kind, from_s, to_s });
        }
        Ok(out)
    }

    fn conveyors(&self, raw: &[RawConveyor], timing: &CellTiming<'_>) -> Result<Vec<Conveyor>, SceneError> {
        let mut seen = HashMap::new();
        let mut out = Vec::with_capacity(raw.len());
        for (i, c) in raw.iter().enumerate() {
            let f = |field: &str| format!("conveyors[{i}].{field}");
            let name = self.nonempty_name(&c.name, &f("name"))?;
            self.unique(&mut seen, &c.name, &f("name"), ())?;
            let vfd_fields: [(&str, Option<std::ops::Range<usize>>); 8] = [
                ("run", c.run.as_ref().map(Spanned::span)),
                ("reverse", c.reverse.as_ref().map(Spanned::span)),
                ("speed", c.speed.as_ref().map(Spanned::span)),
                ("max_speed_mps", c.max_speed_mps.as_ref().map(Spanned::span)),
                ("accel_mps2", c.accel_mps2.as_ref().map(Spanned::span)),
                ("running_tag", c.running_tag.as_ref().map(Spanned::span)),
                ("encoder_tag", c.encoder_tag.as_ref().map(Spanned::span)),
                ("counts_per_m", c.counts_per_m.as_ref().map(Spanned::span)),
            ];
            let drive = match (&c.axis, &c.run) {
                (Some(axis), _) => {
                    if let Some((field, Some(span))) = vfd_fields.iter().find(|(_, s)| s.is_some()) {
                        let why = format!(
                            "'{field}' belongs to a VFD conveyor; this one follows the axis '{}'",
                            axis.get_ref()
                        );
                        return Err(self.invalid_at(span.clone(), f(field), Problem::Rule { why }));
                    }
                    let index = timing
                        .axes
                        .iter()
                        .position(|a| a.name.eq_ignore_ascii_case(axis.get_ref().trim()))
                        .ok_or_else(|| {
                            self.invalid(
                                axis,
                                f("axis"),
                                Problem::UnknownAxis {
                                    name: axis.get_ref().clone(),
                                    nearest: None,
                                },
                            )
                        })?;
                    let a = &timing.axes[index];
                    if a.kind != AxisKind::Linear || !matches!(a.units, Units::M | Units::Mm) {
                        let why = format!("a conveyor follows a linear axis (mm or m); '{}' is rotary", a.name);
                        return Err(self.invalid(axis, f("axis"), Problem::Rule { why }));
                    }
                    ConveyorDrive::Axis(index)
                }
                (None, Some(run)) => {
                    let encoder_tag = self.optional_io_tag(&c.encoder_tag, &f("encoder_tag"))?;
                    let counts_per_m = match (&c.counts_per_m, &encoder_tag) {
                        (Some(v), Some(_)) => self.positive(v, &f("counts_per_m"))?,
                        (Some(v), None) => {
                            let why = "counts_per_m scales encoder_tag: give both".to_owned();
                            return Err(self.invalid(v, f("counts_per_m"), Problem::Rule { why }));
                        }
                        (None, Some(_)) => {
                            let why = "an encoder_tag needs counts_per_m".to_owned();
                            return Err(self.invalid(&c.name, f("counts_per_m"), Problem::Rule { why }));
                        }
                        (None, None) => 1.0,
                    };
                    let max_speed_mps = match &c.max_speed_mps {
                        Some(v) => self.positive(v, &f("max_speed_mps"))?,
                        None => {
                            let why = "a VFD conveyor needs max_speed_mps (its belt speed at 100 %)".to_owned();
                            return Err(self.invalid(&c.name, f("max_speed_mps"), Problem::Rule { why }));
                        }
                    };
                    ConveyorDrive::Vfd(Box::new(Vfd {
                        run: self.io_tag(run, &f("run"))?,
                        reverse: self.optional_io_tag(&c.reverse, &f("reverse"))?,
                        speed: self.optional_io_tag(&c.speed, &f("speed"))?,
                        max_speed_mps,
                        accel_mps2: self.positive_or(&c.accel_mps2, &f("accel_mps2"), f64::INFINITY)?,
                        running_tag: self.optional_io_tag(&c.running_tag, &f("running_tag"))?,
                        encoder_tag,
                        counts_per_m,
                    }))
                }
                (None, None) => {
                    let why = "give 'axis' (the belt follows a linear axis) or 'run' (a VFD's run output)".to_owned();
                    return Err(self.invalid(&c.name, f("name"), Problem::Rule { why }));
                }
            };
            out.push(Conveyor {
                name,
                position_m: self.position(&c.position, &f("position"))?,
                rpy_deg: self.rpy(&c.rpy_deg, &f("rpy_deg"))?,
                size_m: self.bounded_array(&c.size, &f("size"), MAX_LENGTH_M)?,
                friction: match &c.friction {
                    Some(v) => self.in_range(v, &f("friction"), 0.0, 10.0)?,
                    None => 0.8,
                },
                color: self.color_or(&c.color, &f("color"), [0.2, 0.2, 0.22, 1.0])?,
                drive,
                ride: c.ride.as_ref().is_none_or(|v| *v.get_ref()),
                faults: self.faults(&c.faults, &f("faults"), &[("stalled", FaultKind::Stalled)])?,
                location: self.loc(&c.name),
            });
        }
        Ok(out)
    }

    fn sensors(
        &self,
        raw: &[RawSensor],
        part_types: &[PartType],
        timing: &CellTiming<'_>,
    ) -> Result<Vec<Sensor>, SceneError> {
        let mut seen = HashMap::new();
        let mut out = Vec::with_capacity(raw.len());
        for (i, s) in raw.iter().enumerate() {
            let f = |field: &str| format!("sensors[{i}].{field}");
            let name = self.nonempty_name(&s.name, &f("name"))?;
            self.unique(&mut seen, &s.name, &f("name"), ())?;
            let kind_word = self.word(
                &s.kind,
                &f("kind"),
                "sensor kind",
                &[
                    ("beam", 0u8),
                    ("diffuse", 1),
                    ("proximity", 2),
                    ("zone", 3),
                    ("clearance", 4),
                    ("vision", 5),
                ],
            )?;
            let kind_name = ["beam", "diffuse", "proximity", "zone", "clearance", "vision"][usize::from(kind_word)];
            // Which of the kind-specific fields each kind takes.
            let takes: &[&str] = match kind_word {
                0 => &["from", "to", "count", "pitch_m", "value_tag"],
                1 => &["range_m", "value_tag", "scale"],
                2 => &["shape", "size", "radius", "length", "materials"],
                3 => &["shape", "size", "radius", "length", "count_tag"],
                4 => &["between", "below_m", "value_tag"],
                _ => &[
                    "shape",
                    "size",
                    "radius",
                    "length",
                    "trigger",
                    "latency_ms",
                    "position_tag",
                    "angle_tag",
                    "type_tag",
                    "frame",
                    "units",
                ],
            };
            let specific: [(&str, Option<std::ops::Range<usize>>); 22] = [
                ("between", s.between.as_ref().map(Spanned::span)),
                ("below_m", s.below_m.as_ref().map(Spanned::span)),
                ("trigger", s.trigger.as_ref().map(Spanned::span)),
                ("latency_ms", s.latency_ms.as_ref().map(Spanned::span)),
                ("position_tag", s.position_tag.as_ref().map(Spanned::span)),
                ("angle_tag", s.angle_tag.as_ref().map(Spanned::span)),
                ("type_tag", s.type_tag.as_ref().map(Spanned::span)),
                ("frame", s.frame.as_ref().map(Spanned::span)),
                ("units", s.units.as_ref().map(Spanned::span)),
                ("from", s.from.as_ref().map(Spanned::span)),
                ("to", s.to.as_ref().map(Spanned::span)),
                ("count", s.count.as_ref().map(Spanned::span)),
                ("pitch_m", s.pitch_m.as_ref().map(Spanned::span)),
                ("value_tag", s.value_tag.as_ref().map(Spanned::span)),
                ("range_m", s.range_m.as_ref().map(Spanned::span)),
                ("scale", s.scale.as_ref().map(Spanned::span)),
                ("shape", s.shape.as_ref().map(Spanned::span)),
                ("size", s.size.as_ref().map(Spanned::span)),
                ("radius", s.radius.as_ref().map(Spanned::span)),
                ("length", s.length.as_ref().map(Spanned::span)),
                ("materials", s.materials.as_ref().map(Spanned::span)),
                ("count_tag", s.count_tag.as_ref().map(Spanned::span)),
            ];
            for (field, span) in &specific {
                if let Some(span) = span
                    && !takes.contains(field)
                {
                    let why = format!(
                        "'{field}' does not apply to a {kind_name} sensor (it takes {})",
                        takes.join(", ")
                    );
                    return Err(self.invalid_at(span.clone(), f(field), Problem::Rule { why }));
                }
            }
            let missing = |field: &str| {
                let why = format!("a {kind_name} sensor needs '{field}'");
                self.invalid(&s.kind, f(field), Problem::Rule { why })
            };
            let field_shape = |ctx: &Self| -> Result<Shape, SceneError> {
                let kind = s.shape.as_ref().ok_or_else(|| missing("shape"))?;
                if *kind.get_ref() == ShapeKind::Mesh {
                    let why = "a sensor's field is a box, a sphere or a cylinder".to_owned();
                    return Err(ctx.invalid(kind, f("shape"), Problem::Rule { why }));
                }
                let none_file = None;
                let none_scale = None;
                let fields = ShapeFields {
                    kind,
                    size: &s.size,
                    radius: &s.radius,
                    length: &s.length,
                    file: &none_file,
                    scale: &none_scale,
                };
                ctx.shape(&fields, Path::new(""), &f)
            };
            let kind = match kind_word {
                0 => {
                    let from_m = self.position(s.from.as_ref().ok_or_else(|| missing("from"))?, &f("from"))?;
                    let to_at = s.to.as_ref().ok_or_else(|| missing("to"))?;
                    let to_m = self.position(to_at, &f("to"))?;
                    let length = (0..3).map(|k| (to_m[k] - from_m[k]).powi(2)).sum::<f64>().sqrt();
                    if length < 1e-6 {
                        let why = "the beam's 'to' must differ from its 'from'".to_owned();
                        return Err(self.invalid(to_at, f("to"), Problem::Rule { why }));
                    }
                    let curtain = match (&s.count, &s.pitch_m) {
                        (Some(n), Some(p)) => {
                            let n = self.int_in_range(n, &f("count"), 1, MAX_CURTAIN_BEAMS)? as u32;
                            Some((n, self.positive(p, &f("pitch_m"))?))
                        }
                        (Some(n), None) => {
                            let why = "a light curtain's count needs pitch_m".to_owned();
                            return Err(self.invalid(n, f("pitch_m"), Problem::Rule { why }));
                        }
                        (None, Some(p)) => {
                            let why = "pitch_m spaces a light curtain's beams: give count too".to_owned();
                            return Err(self.invalid(p, f("count"), Problem::Rule { why }));
                        }
                        (None, None) => None,
                    };
                    if let (None, Some(v)) = (&curtain, &s.value_tag) {
                        let why = "a beam's value_tag is a light curtain's bitmask: give count and pitch_m".to_owned();
                        return Err(self.invalid(v, f("value_tag"), Problem::Rule { why }));
                    }
                    SensorKind::Beam { from_m, to_m, curtain }
                }
                1 => {
                    let range_m = self.bounded(
                        s.range_m.as_ref().ok_or_else(|| missing("range_m"))?,
                        &f("range_m"),
                        MAX_LENGTH_M,
                    )?;
                    let scale = match &s.scale {
                        Some(sc) => {
                            let [a, b] = sc.get_ref();
                            let pts = [a.0, b.0];
                            if let Some(&value) = pts.iter().flatten().find(|x| !x.is_finite()) {
                                return Err(self.invalid(sc, f("scale"), Problem::NotFinite { value }));
                            }
                            if pts[0][0] == pts[1][0] {
                                let why = "the two points of a scale need two distances".to_owned();
                                return Err(self.invalid(sc, f("scale"), Problem::Rule { why }));
                            }
                            Some(pts)
                        }
                        None => None,
                    };
                    SensorKind::Diffuse { range_m, scale }
                }
                2 => {
                    let materials = s
                        .materials
                        .as_ref()
                        .map(Spanned::get_ref)
                        .map_or(&[][..], Vec::as_slice)
                        .iter()
                        .map(|m| m.get_ref().trim().to_ascii_lowercase())
                        .collect();
                    SensorKind::Proximity {
                        field: field_shape(self)?,
                        materials,
                    }
                }
                3 => SensorKind::Zone {
                    field: field_shape(self)?,
                },
                4 => {
                    let between_at = s.between.as_ref().ok_or_else(|| missing("between"))?;
                    let mut groups: [Vec<Detect>; 2] = [Vec::new(), Vec::new()];
                    for (g, list) in between_at.get_ref().iter().enumerate() {
                        for (k, d) in list.iter().enumerate() {
                            groups[g].push(self.detect(
                                d,
                                &format!("sensors[{i}].between[{g}][{k}]"),
                                part_types,
                                timing.obstacles,
                            )?);
                        }
                        if groups[g].is_empty() {
                            return Err(self.invalid(between_at, format!("sensors[{i}].between[{g}]"), Problem::Empty));
                        }
                    }
                    if let Some(d) = &s.detects {
                        let why = "a clearance sensor's groups are its 'between'".to_owned();
                        return Err(self.invalid(d, f("detects"), Problem::Rule { why }));
                    }
                    SensorKind::Clearance {
                        between: groups,
                        below_m: self.positive(s.below_m.as_ref().ok_or_else(|| missing("below_m"))?, &f("below_m"))?,
                    }
                }
                _ => SensorKind::Vision(Box::new(VisionSpec {
                    field: field_shape(self)?,
                    trigger: self.io_tag(s.trigger.as_ref().ok_or_else(|| missing("trigger"))?, &f("trigger"))?,
                    latency_s: self.non_negative_or(&s.latency_ms, &f("latency_ms"), 50.0)? / 1000.0,
                    position_tag: self.optional_io_tag(&s.position_tag, &f("position_tag"))?,
                    angle_tag: self.optional_io_tag(&s.angle_tag, &f("angle_tag"))?,
                    type_tag: self.optional_io_tag(&s.type_tag, &f("type_tag"))?,
                    frame: s.frame.as_ref().map(|l| (l.get_ref().trim().to_owned(), self.loc(l))),
                    millimetres: match &s.units {
                        Some(u) => self.word(u, &f("units"), "units", &[("m", false), ("mm", true)])?,
                        None => false,
                    },
                })),
            };
            let detects = match &s.detects {
                Some(list) => {
                    let mut out = Vec::new();
                    for (k, d) in list.get_ref().iter().enumerate() {
                        out.push(self.detect(
                            d,
                            &format!("sensors[{i}].detects[{k}]"),
                            part_types,
                            timing.obstacles,
                        )?);
                    }
                    if out.is_empty() {
                        return Err(self.invalid(list, f("detects"), Problem::Empty));
                    }
                    out
                }
                None => vec![Detect::Parts],
            };
            let rpi_s = match &s.rpi_ms {
                Some(v) => Some(self.in_range(v, &f("rpi_ms"), 0.2, 750.0)? / 1000.0),
                None => None,
            };
            let registration = match &s.registration {
                Some(r) => {
                    if kind_word >= 3 {
                        let why = format!(
                            "a {kind_name} sensor has no registration output: wire a beam, diffuse or proximity sensor"
                        );
                        return Err(self.invalid(r, f("registration"), Problem::Rule { why }));
                    }
                    let raw = r.get_ref();
                    let axis = timing
                        .axes
                        .iter()
                        .position(|a| a.name.eq_ignore_ascii_case(raw.axis.get_ref().trim()))
                        .ok_or_else(|| {
                            let problem = Problem::UnknownAxis {
                                name: raw.axis.get_ref().clone(),
                                nearest: None,
                            };
                            self.invalid(&raw.axis, f("registration.axis"), problem)
                        })?;
                    let input = self.int_in_range(&raw.input, &f("registration.input"), 1, 2)? as u8;
                    if let Some(other) = out.iter().find(|o: &&Sensor| o.registration == Some((axis, input))) {
                        let why = format!(
                            "registration input {input} of '{}' is wired to sensor '{}' already",
                            timing.axes[axis].name, other.name
                        );
                        return Err(self.invalid(&raw.input, f("registration.input"), Problem::Rule { why }));
                    }
                    Some((axis, input))
                }
                None => None,
            };
            out.push(Sensor {
                name,
                kind,
                registration,
                tag: self.io_tag(&s.tag, &f("tag"))?,
                value_tag: self.optional_io_tag(&s.value_tag, &f("value_tag"))?,
                count_tag: self.optional_io_tag(&s.count_tag, &f("count_tag"))?,
                link: s.link.as_ref().map(|l| (l.get_ref().trim().to_owned(), self.loc(l))),
                position_m: match &s.position {
                    Some(p) => self.position(p, &f("position"))?,
                    None => [0.0; 3],
                },
                rpy_deg: self.rpy(&s.rpy_deg, &f("rpy_deg"))?,
                detects,
                invert: s.invert.as_ref().is_some_and(|v| *v.get_ref()),
                on_delay_s: self.non_negative_or(&s.on_delay_ms, &f("on_delay_ms"), 0.0)? / 1000.0,
                off_delay_s: self.non_negative_or(&s.off_delay_ms, &f("off_delay_ms"), 0.0)? / 1000.0,
                rpi_s,
                cos: s.cos.as_ref().is_some_and(|v| *v.get_ref()),
                faults: self.faults(
                    &s.faults,
                    &f("faults"),
                    &[("stuck_on", FaultKind::StuckOn), ("stuck_off", FaultKind::StuckOff)],
                )?,
                location: self.loc(&s.name),
            });
        }
        Ok(out)
    }

    /// One `detects` word: `parts`, `robot`, a part type, an obstacle, or a
    /// link (checked against the URDF when the plant is built).
    fn detect(
        &self,
        d: &Spanned<String>,
        field: &str,
        part_types: &[PartType],
        obstacles: &[Obstacle],
    ) -> Result<Detect, SceneError> {
        let word = d.get_ref().trim();
        if word.is_empty() {
            return Err(self.invalid(d, field, Problem::Empty));
        }
        if word.eq_ignore_ascii_case("parts") {
            return Ok(Detect::Parts);
        }
        if word.eq_ignore_ascii_case("robot") {
            return Ok(Detect::Robot);
        }
        if let Some(k) = part_types.iter().position(|p| p.name.eq_ignore_ascii_case(word)) {
            return Ok(Detect::PartType(k));
        }
        if let Some(k) = obstacles.iter().position(|o| o.name.eq_ignore_ascii_case(word)) {
            return Ok(Detect::Obstacle(k));
        }
        Ok(Detect::Link(word.to_owned()))
    }

    fn cylinders(&self, raw: &[RawCylinder]) -> Result<Vec<Cylinder>, SceneError> {
        let mut seen = HashMap::new();
        let mut out = Vec::with_capacity(raw.len());
        for (i, c) in raw.iter().enumerate() {
            let f = |field: &str| format!("cylinders[{i}].{field}");
            let name = self.nonempty_name(&c.name, &f("name"))?;
            self.unique(&mut seen, &c.name, &f("name"), ())?;
            let extend_s = self.positive(&c.extend_ms, &f("extend_ms"))? / 1000.0;
            out.push(Cylinder {
                name,
                position_m: self.position(&c.position, &f("position"))?,
                rpy_deg: self.rpy(&c.rpy_deg, &f("rpy_deg"))?,
                size_m: self.bounded_array(&c.size, &f("size"), MAX_LENGTH_M)?,
                stroke_m: self.bounded(&c.stroke_m, &f("stroke_m"), MAX_LENGTH_M)?,
                extend_s,
                retract_s: self.positive_or(&c.retract_ms, &f("retract_ms"), extend_s * 1000.0)? / 1000.0,
                extend: self.io_tag(&c.extend, &f("extend"))?,
                retract: self.optional_io_tag(&c.retract, &f("retract"))?,
                extended_tag: self.optional_io_tag(&c.extended_tag, &f("extended_tag"))?,
                retracted_tag: self.optional_io_tag(&c.retracted_tag, &f("retracted_tag"))?,
                color: self.color_or(&c.color, &f("color"), [0.75, 0.75, 0.8, 1.0])?,
                faults: self.faults(&c.faults, &f("faults"), &[("stalled", FaultKind::Stalled)])?,
                location: self.loc(&c.name),
            });
        }
        Ok(out)
    }

    fn grippers(&self, raw: &[RawGripper]) -> Result<Vec<Gripper>, SceneError> {
        let mut seen = HashMap::new();
        let mut out = Vec::with_capacity(raw.len());
        for (i, g) in raw.iter().enumerate() {
            let f = |field: &str| format!("grippers[{i}].{field}");
            let name = self.nonempty_name(&g.name, &f("name"))?;
            self.unique(&mut seen, &g.name, &f("name"), ())?;
            let kind = self.word(
                &g.kind,
                &f("kind"),
                "gripper kind",
                &[("vacuum", GripperKind::Vacuum), ("fingers", GripperKind::Fingers)],
            )?;
            let (own, other) = match kind {
                GripperKind::Vacuum => ((&g.build_up_ms, "build_up_ms"), (&g.close_ms, "close_ms")),
                GripperKind::Fingers => ((&g.close_ms, "close_ms"), (&g.build_up_ms, "build_up_ms")),
            };
            if let Some(v) = other.0 {
                let why = format!(
                    "'{}' applies to {} grippers; a {} gripper takes '{}'",
                    other.1,
                    if kind == GripperKind::Vacuum {
                        "fingers"
                    } else {
                        "vacuum"
                    },
                    kind.word(),
                    own.1
                );
                return Err(self.invalid(v, f(other.1), Problem::Rule { why }));
            }
            let faults: &[(&'static str, FaultKind)] = match kind {
                GripperKind::Vacuum => &[("no_vacuum", FaultKind::NoVacuum)],
                GripperKind::Fingers => &[],
            };
            out.push(Gripper {
                name,
                kind,
                link: (g.link.get_ref().trim().to_owned(), self.loc(&g.link)),
                position_m: match &g.position {
                    Some(p) => self.position(p, &f("position"))?,
                    None => [0.0; 3],
                },
                rpy_deg: self.rpy(&g.rpy_deg, &f("rpy_deg"))?,
                grip: self.io_tag(&g.grip, &f("grip"))?,
                release: self.optional_io_tag(&g.release, &f("release"))?,
                holding_tag: self.optional_io_tag(&g.holding_tag, &f("holding_tag"))?,
                engage_s: self.non_negative_or(own.0, &f(own.1), 50.0)? / 1000.0,
                reach_m: self.positive_or(&g.reach_m, &f("reach_m"), 0.005)?,
                max_force_n: self.positive_or(&g.max_force_n, &f("max_force_n"), f64::INFINITY)?,
                faults: self.faults(&g.faults, &f("faults"), faults)?,
                location: self.loc(&g.name),
            });
        }
        Ok(out)
    }
}
