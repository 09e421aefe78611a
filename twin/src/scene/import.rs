//! A scene that names a Studio 5000 export (`[controller] l5x`): the
//! export's motion group, axes, coordinate systems, data types, tags,
//! tasks, programs and ST and ladder routines become the scene text they
//! stand for, and the scene keeps the robot, the cell and the bindings.
//!
//! The result is one TOML text, the *expanded scene*: generated top-level
//! keys, then the scene file with its bindings blanked out (spaces, its
//! line breaks kept), then the generated tables. It is what `twin import`
//! writes and what the loader validates, so an imported scene runs as the
//! L5X scene does. Every piece of it is a [`Segment`] of [`PosMap`]: copied
//! from the scene file (a position inside maps back byte for byte) or
//! generated from an L5X attribute (every position inside maps to that
//! attribute, and an error there names it: `J1 MaximumSpeed`). The ST
//! routines become files `routines/<Program>/<Routine>.st` of the expanded
//! scene, the RLL routines `<Routine>.rll` (a rung a line), each byte
//! mapped into its CDATA.
//!
//! What a binding may give is listed in [`AXIS_BINDING`], [`CS_BINDING`]
//! and [`GEOMETRY_BINDING`]; a field the export already holds is refused,
//! naming both places (`axes[0].max_velocity: J1's MaximumSpeed comes from
//! scara_pick.L5X:112; change it there`).
//!
//! Choices the issue and the manuals leave open, and what the twin does:
//! * an axis' kind (linear or rotary) follows its units (`deg`, `rad`:
//!   rotary; `m`, `mm`: linear);
//! * exception actions: the soft overtravel action is `MotionExceptionAction`
//!   entries 1 and 2 (the positive one when they differ, reported), the
//!   Excessive Position Error action `CIPAxisExceptionAction` entry 54
//!   (MOTION-RM003); `Disable` is `stop_drive`, `Unsupported` the default;
//! * a tag of a type the twin does not know (`MESSAGE` …) is reported and
//!   left out: a routine naming it is refused at load; a tag of an
//!   Add-On Instruction's type is its instance;
//! * an instruction structure's exported values (an `FBD_TIMER`'s preset
//!   …) are reported, not read: the twin's structures start cleared with
//!   `EnableIn` set, and the routine sets what it uses;
//! * an alias tag becomes an `[[aliases]]` entry of its scope;
//! * a module's input and output tags become controller tags of their
//!   names (`Local:1:I`) whose types are their Decorated structures, named
//!   with `_` for `:` (`AB_1756_DI_I_0`); a sensor naming an input tag
//!   takes the connection's RPI as its `rpi_ms` unless it gives one.

use std::collections::HashMap;
use std::fmt::Write as _;
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use toml::de::{DeTable, DeValue};

use super::model::BaseType;
use crate::l5x::{self, At, Project, Value};
use crate::source::{Diagnostic, FileId, Files};

/// Fields an `[[axes]]` binding may give.
pub const AXIS_BINDING: &[&str] = &[
    "name",
    "joint",
    "initial_position",
    "units",
    "motor",
    "drive",
    "holding_brake",
    "brake_release_delay_ms",
];
/// Fields of an axis binding's `drive`.
const DRIVE_BINDING: &[&str] = &["torque_limit_positive", "torque_limit_negative", "system_inertia"];
/// Fields a `[[tags]]` binding of a coordinate system may give.
const CS_TAG_BINDING: &[&str] = &["name", "coordinate_system", "geometry"];
/// Scene fields of a coordinate system tag and the L5X attributes that
/// hold them.
const CS_TAG_FIELDS: &[(&str, &str)] = &[("value", "Axes")];
/// Fields a coordinate system's `coordinate_system` binding may give.
pub const CS_BINDING: &[&str] = &["tool_link", "master_axis"];
/// Fields a coordinate system's `geometry` binding may give.
pub const GEOMETRY_BINDING: &[&str] = &[
    "base_link",
    "tool_link",
    "platform_joints",
    "forearm_joints",
    "forearm_tip_links",
    "ball_links",
];

/// Scene fields and the L5X attributes that hold them.
const AXIS_FIELDS: &[(&str, &str)] = &[
    ("kind", "PositionUnits"),
    ("modulo_period", "PositionUnwind"),
    ("max_velocity", "MaximumSpeed"),
    ("max_acceleration", "MaximumAcceleration"),
    ("max_deceleration", "MaximumDeceleration"),
    ("max_jerk", "MaximumAccelerationJerk"),
    ("in_position_window", "PositionLockTolerance"),
    ("soft_travel_limits", "SoftTravelLimitPositive"),
    ("soft_travel_limit_checking", "SoftTravelLimitChecking"),
    ("position_error_tolerance", "PositionErrorTolerance"),
    ("axis_configuration", "AxisConfiguration"),
    ("servo_on_at_start", "its download state (servo off)"),
    ("home_mode", "HomeMode"),
    ("home_sequence", "HomeSequence"),
    ("home_position", "HomePosition"),
    ("home_offset", "HomeOffset"),
    ("home_direction", "HomeDirection"),
    ("home_speed", "HomeSpeed"),
    ("home_return_speed", "HomeReturnSpeed"),
];

const DRIVE_FIELDS: &[(&str, &str)] = &[
    ("position_loop_bandwidth_hz", "PositionLoopBandwidth"),
    ("position_integrator_bandwidth_hz", "PositionIntegratorBandwidth"),
    ("velocity_loop_bandwidth_hz", "VelocityLoopBandwidth"),
    ("velocity_integrator_bandwidth_hz", "VelocityIntegratorBandwidth"),
    ("velocity_feedforward_gain_pct", "VelocityFeedforwardGain"),
    ("acceleration_feedforward_gain_pct", "AccelerationFeedforwardGain"),
];

const CS_FIELDS: &[(&str, &str)] = &[
    ("primary_axes", "CoordinationMode"),
    ("max_speed", "MaximumSpeed"),
    ("max_accel", "MaximumAcceleration"),
    ("max_decel", "MaximumDeceleration"),
    ("max_accel_jerk", "MaximumAccelerationJerk"),
    ("max_decel_jerk", "MaximumDecelerationJerk"),
    ("command_tolerance", "CommandPositionTolerance"),
    ("actual_tolerance", "ActualPositionTolerance"),
];

const GEOMETRY_FIELDS: &[(&str, &str)] = &[
    ("type", "SystemType"),
    ("transform_dimension", "TransformDimension"),
    ("link_lengths", "LinkLength1"),
    ("base_offsets", "BaseOffset1"),
    ("end_effector_offsets", "EndEffectorOffset1"),
    ("zero_angles_deg", "ZeroAngleOffset1"),
];

/// `SystemType` (with `TransformDimension` for a Delta) → `geometry.type`.
const SYSTEM_TYPES: &[(&str, &str)] = &[
    ("Cartesian", "cartesian_gantry"),
    ("Articulated Dependent", "articulated_dependent"),
    ("Articulated Independent", "articulated_independent"),
    ("SCARA Independent", "scara_independent"),
    ("Delta", "delta_3d"),
    ("SCARA Delta", "scara_delta"),
];

/// A line the expansion inserts into the scene's own text: the scene
/// offset, the text, the L5X bytes it comes from, the item.
type Insert = (usize, String, Range<usize>, String);

/// Where a piece of the expanded scene comes from.
#[derive(Debug, Clone)]
pub struct Segment {
    /// Its bytes in the expanded scene.
    pub expanded: Range<usize>,
    /// The file it comes from.
    pub file: FileId,
    /// Its bytes there.
    pub source: Range<usize>,
    /// Copied byte for byte (else every byte maps to `source`).
    pub verbatim: bool,
    /// The L5X item an error here is about (`J1 MaximumSpeed`).
    pub item: Option<String>,
}

/// The expanded scene's positions, back to the files.
#[derive(Debug, Clone, Default)]
pub struct PosMap {
    /// In order of `expanded`, without gaps.
    pub segments: Vec<Segment>,
}

impl PosMap {
    /// The segment holding expanded byte `at`.
    #[must_use]
    pub fn segment(&self, at: usize) -> Option<&Segment> {
        let i = self.segments.partition_point(|s| s.expanded.end <= at);
        self.segments.get(i).or_else(|| self.segments.last())
    }

    /// The file and byte range of expanded bytes `range`.
    #[must_use]
    pub fn map(&self, range: Range<usize>) -> (FileId, Range<usize>, Option<&str>) {
        let Some(s) = self.segment(range.start) else {
            return (FileId::default(), range, None);
        };
        if s.verbatim {
            let start = s.source.start + range.start.saturating_sub(s.expanded.start);
            let end = s.source.start + range.end.saturating_sub(s.expanded.start).min(s.source.len());
            (s.file, start..end.max(start), s.item.as_deref())
        } else {
            (s.file, s.source.clone(), s.item.as_deref())
        }
    }
}

/// A routine of the export, as a file of the expanded scene.
#[derive(Debug, Clone)]
pub struct VirtualRoutine {
    /// Its text.
    pub text: Arc<str>,
    /// The L5X byte of each text byte, and one past the end.
    pub map: Arc<[u32]>,
    /// `Program/Routine`, for messages.
    pub name: String,
}

/// A line of the fidelity report: what the export holds that the twin
/// does not simulate.
#[derive(Debug, Clone, PartialEq)]
pub struct ReportLine {
    /// 1-based line in the L5X.
    pub line: usize,
    /// What it is.
    pub text: String,
}

/// An expanded scene.
#[derive(Debug, Clone)]
pub struct Expanded {
    /// The scene text.
    pub text: String,
    /// Its positions back to the files.
    pub map: PosMap,
    /// The routine files it names, by path relative to the scene's folder.
    pub routines: HashMap<PathBuf, VirtualRoutine>,
    /// The Add-On Instruction exports it names (`aoi/<Name>.L5X`), each
    /// the project's definition copied byte for byte inside an export's
    /// envelope, mapped back into the project.
    pub aois: Vec<(PathBuf, VirtualRoutine)>,
    /// The export.
    pub l5x_path: PathBuf,
    /// The export's id in the files.
    pub l5x_file: FileId,
    /// What is not simulated.
    pub report: Vec<ReportLine>,
    /// What `not_simulated` skipped.
    pub skipped: Vec<String>,
}

type Fail = Box<Diagnostic>;

/// The scene text of `scene_text` with its export expanded, or `None`
/// when it names none. The export is read from its file, or is
/// `l5x_text` when given.
///
/// # Errors
/// The first problem, as a diagnostic at its place (scene or L5X).
pub fn expand(
    scene_path: &Path,
    scene_text: &str,
    files: &mut Files,
    l5x_text: Option<&str>,
) -> Result<Option<Expanded>, Fail> {
    // A scene TOML cannot parse: the loader reports it.
    let Ok(doc) = DeTable::parse(scene_text) else {
        return Ok(None);
    };
    let doc = doc.get_ref();
    let Some(controller) = table(doc, "controller") else {
        return Ok(None);
    };
    let Some(l5x) = controller.iter().find(|(k, _)| k.get_ref() == "l5x").map(|(_, v)| v) else {
        return Ok(None);
    };
    let DeValue::String(name) = l5x.get_ref() else {
        return Err(scene_error(
            files,
            l5x.span(),
            "controller.l5x",
            "expected the export's path, a string",
        ));
    };
    let base = scene_path.parent().unwrap_or_else(|| Path::new(""));
    let l5x_path = base.join(name.as_ref());
    let bytes = match l5x_text {
        Some(t) => Ok(t.as_bytes().to_vec()),
        None => crate::source::read_bounded(&l5x_path, crate::source::InputKind::L5x),
    }
    .map_err(|e| {
        scene_error(
            files,
            l5x.span(),
            "controller.l5x",
            format!("cannot read {}: {e}", l5x_path.display()),
        )
    })?;
    let text = match String::from_utf8(bytes) {
        Ok(t) => t,
        Err(e) => {
            return Err(scene_error(
                files,
                l5x.span(),
                "controller.l5x",
                format!(
                    "{}: not UTF-8 text (byte {})",
                    l5x_path.display(),
                    e.utf8_error().valid_up_to()
                ),
            ));
        }
    };
    let l5x_file = files.add(l5x_path.clone(), text);
    let l5x_text = Arc::clone(&files.get(l5x_file).text);
    let project = l5x::read(&l5x_text).map_err(|e| {
        Box::new(Diagnostic::error(e.message).with_label(files.label(crate::source::Span::new(l5x_file, e.span), "")))
    })?;
    let mut g = Gen {
        files,
        scene_text,
        l5x_file,
        l5x_name: l5x_path
            .file_name()
            .map_or_else(String::new, |n| n.to_string_lossy().into_owned()),
        out: String::new(),
        map: PosMap::default(),
        routines: HashMap::new(),
        aois: Vec::new(),
        report: Vec::new(),
        skipped: Vec::new(),
        blank: Vec::new(),
        project: &project,
        values: HashMap::new(),
        not_simulated: Vec::new(),
    };
    g.generate(doc, controller)?;
    let Gen {
        out,
        map,
        routines,
        aois,
        report,
        skipped,
        ..
    } = g;
    Ok(Some(Expanded {
        text: out,
        map,
        routines,
        aois,
        l5x_path,
        l5x_file,
        report,
        skipped,
    }))
}

/// An error at scene bytes `span`, about `field`.
fn scene_error(files: &Files, span: Range<usize>, field: &str, message: impl Into<String>) -> Fail {
    let label = files.label(crate::source::Span::new(FileId::default(), span), "");
    Box::new(Diagnostic::error(message).in_field(field).with_label(label))
}

fn table<'a, 'i>(t: &'a DeTable<'i>, key: &str) -> Option<&'a DeTable<'i>> {
    match get(t, key)?.get_ref() {
        DeValue::Table(t) => Some(t),
        _ => None,
    }
}

/// The bytes of `key` and of its value in `t`.
fn key_span(t: &DeTable<'_>, key: &str) -> Option<(Range<usize>, Range<usize>)> {
    t.iter()
        .find(|(k, _)| k.get_ref() == key)
        .map(|(k, v)| (k.span(), v.span()))
}

fn get<'a, 'i>(t: &'a DeTable<'i>, key: &str) -> Option<&'a toml::Spanned<DeValue<'i>>> {
    t.iter().find(|(k, _)| k.get_ref() == key).map(|(_, v)| v)
}

fn array_tables<'a, 'i>(t: &'a DeTable<'i>, key: &str) -> Vec<(Range<usize>, &'a DeTable<'i>)> {
    match get(t, key).map(toml::Spanned::get_ref) {
        Some(DeValue::Array(a)) => a
            .iter()
            .filter_map(|e| match e.get_ref() {
                DeValue::Table(t) => Some((e.span(), t)),
                _ => None,
            })
            .collect(),
        _ => Vec::new(),
    }
}

fn string<'a>(v: &'a toml::Spanned<DeValue<'_>>) -> Option<&'a str> {
    match v.get_ref() {
        DeValue::String(s) => Some(s.as_ref()),
        _ => None,
    }
}

struct Gen<'a> {
    files: &'a mut Files,
    scene_text: &'a str,
    l5x_file: FileId,
    l5x_name: String,
    out: String,
    map: PosMap,
    routines: HashMap<PathBuf, VirtualRoutine>,
    aois: Vec<(PathBuf, VirtualRoutine)>,
    report: Vec<ReportLine>,
    skipped: Vec<String>,
    /// Scene bytes blanked in the copy (bindings, `[controller]`).
    blank: Vec<Range<usize>>,
    project: &'a Project,
    /// `values`: lower-case tag name → the value's scene bytes.
    values: HashMap<String, (Range<usize>, bool)>,
    /// `not_simulated`: the items and whether each was used.
    not_simulated: Vec<(String, Range<usize>, bool)>,
}

impl<'a> Gen<'a> {
    fn line_of(&self, span: &Range<usize>) -> usize {
        self.files.get(self.l5x_file).line_column(span.start).0
    }

    fn place(&self, span: &Range<usize>) -> String {
        format!("{}:{}", self.l5x_name, self.line_of(span))
    }

    fn note(&mut self, span: &Range<usize>, text: impl Into<String>) {
        self.report.push(ReportLine {
            line: self.line_of(span),
            text: text.into(),
        });
    }

    fn l5x_err(&self, span: Range<usize>, item: &str, message: impl Into<String>) -> Fail {
        let label = self.files.label(crate::source::Span::new(self.l5x_file, span), "");
        Box::new(Diagnostic::error(message).in_field(item).with_label(label))
    }

    fn scene_err(&self, span: Range<usize>, field: &str, message: impl Into<String>) -> Fail {
        scene_error(self.files, span, field, message)
    }

    /// Appends `text` as one segment of the map.
    fn push(&mut self, text: &str, file: FileId, source: Range<usize>, verbatim: bool, item: Option<String>) {
        let start = self.out.len();
        self.out.push_str(text);
        self.map.segments.push(Segment {
            expanded: start..self.out.len(),
            file,
            source,
            verbatim,
            item,
        });
    }

    /// Appends generated `text` that stands for L5X bytes `span`.
    fn emit(&mut self, text: &str, span: &Range<usize>, item: Option<String>) {
        self.push(text, self.l5x_file, span.clone(), false, item);
    }

    /// Appends scene bytes `range` as they are.
    fn copy(&mut self, range: Range<usize>) {
        let scene_text = self.scene_text;
        self.push(&scene_text[range.clone()], FileId::default(), range, true, None);
    }

    /// `key = <scene bytes of value>` on a line of its own.
    fn copy_field(&mut self, key: &str, value: Range<usize>) {
        let at = value.start..value.start;
        self.gen_scene(&format!("{key} = "), &at);
        self.copy(value);
        self.gen_scene("\n", &at);
    }

    /// Appends generated `text` that stands for scene bytes `span`.
    fn gen_scene(&mut self, text: &str, span: &Range<usize>) {
        self.push(text, FileId::default(), span.clone(), false, None);
    }

    /// A table header, after a comment naming the L5X line it comes from.
    fn header(&mut self, header: &str, span: &Range<usize>, item: String) {
        let text = format!("\n# {}\n{header}\n", self.place(span));
        self.emit(&text, span, Some(item));
    }

    /// `key = { ` opening an inline table: standing for the scene's own
    /// `key` in `binding` when it has one, else for L5X bytes `at`.
    fn open_table(&mut self, key: &str, binding: Option<&DeTable<'_>>, at: &Range<usize>, item: String) {
        let text = format!("{key} = {{ ");
        match binding.and_then(|b| key_span(b, key)) {
            Some((k, _)) => self.gen_scene(&text, &k),
            None => self.emit(&text, at, Some(item)),
        }
    }

    /// A generated line `key = value` for L5X attribute `at`.
    fn line(&mut self, key: &str, value: &str, at: &Range<usize>, item: &str) {
        self.emit(&format!("{key} = {value}\n"), at, Some(item.to_owned()));
    }

    /// Refuses a key of the binding table `sub` that is not in `allowed`,
    /// naming the L5X attribute `fields` says holds it (`owner`'s).
    fn refuse_unlisted(
        &self,
        sub: &DeTable<'_>,
        (allowed, fields): (&[&str], &[(&str, &str)]),
        (owner, params): (&str, &l5x::Params),
        prefix: &str,
    ) -> Result<(), Fail> {
        for (k, _) in sub.iter() {
            let key = k.get_ref().to_string();
            if allowed.contains(&key.as_str()) {
                continue;
            }
            let attr = fields
                .iter()
                .find(|(f, _)| *f == key)
                .map_or("configuration", |(_, a)| a);
            let at = params.get(attr).map_or(params.element.clone(), |a| a.span.clone());
            return Err(self.refuse_field(&format!("{prefix}.{key}"), k.span(), owner, attr, &at));
        }
        Ok(())
    }

    fn refuse_field(&self, field: &str, key_span: Range<usize>, owner: &str, attr: &str, at: &Range<usize>) -> Fail {
        self.scene_err(
            key_span,
            field,
            format!("{owner}'s {attr} comes from {}; change it there", self.place(at)),
        )
    }

    fn generate(&mut self, doc: &DeTable<'_>, controller: &DeTable<'_>) -> Result<(), Fail> {
        let project = self.project;
        // What the scene may not give next to an export.
        for (key, attr) in [("tasks", "Tasks"), ("data_types", "DataTypes")] {
            if let Some(v) = get(doc, key) {
                let (span, _) = key_span(doc, key).unwrap_or((v.span(), v.span()));
                return Err(self.scene_err(
                    span,
                    key,
                    format!("the export's {attr} are the program: change them in {}", self.l5x_name),
                ));
            }
        }
        if let (Some((mg, params)), Some(v)) = (&project.motion_group, get(doc, "coarse_update_ms")) {
            let at = params
                .get("CoarseUpdatePeriod")
                .map_or(mg.span.clone(), |a| a.span.clone());
            let (k, _) = key_span(doc, "coarse_update_ms").unwrap_or((v.span(), v.span()));
            return Err(self.refuse_field("coarse_update_ms", k, &mg.value, "CoarseUpdatePeriod", &at));
        }
        self.read_controller(controller)?;
        // Blank the scene's [controller], [[axes]] and [[tags]].
        self.blank_table(doc, "controller");
        let axes_bindings: Vec<_> = array_tables(doc, "axes");
        let tag_bindings: Vec<_> = array_tables(doc, "tags");
        for (header, t) in axes_bindings.iter().chain(&tag_bindings) {
            self.blank_entries(header.clone(), t);
        }

        // Top-level keys: before the scene's first table. (The motion
        // group's period goes on its tag.)
        let loopback = !project.axes.is_empty()
            && project.axes.iter().all(|a| {
                a.params
                    .get("TestModeEnable")
                    .is_some_and(|v| v.value.eq_ignore_ascii_case("Enabled"))
                    && a.params
                        .get("TestModeConfiguration")
                        .is_some_and(|v| v.value.eq_ignore_ascii_case("Controller Loop Back"))
            });
        self.aoi_files(doc)?;
        if loopback && get(doc, "plant").is_none() {
            let at = project.axes[0]
                .params
                .get("TestModeEnable")
                .map(|a| a.span.clone())
                .unwrap_or_default();
            self.line("plant", "\"kinematic\"", &at, "TestModeConfiguration");
        }
        // The scene, its bindings blanked.
        let mut blank = std::mem::take(&mut self.blank);
        blank.sort_by_key(|r| r.start);
        let inserts = self.sensor_rpis(doc)?;
        let mut at = 0;
        for r in &blank {
            if r.start < at {
                continue;
            }
            self.copy_inserting(at..r.start, &inserts);
            let spaces: String = self.scene_text[r.clone()]
                .chars()
                .map(|c| if c == '\n' || c == '\r' { c } else { ' ' })
                .collect();
            self.gen_scene(&spaces, &(r.start..r.start));
            at = r.end;
        }
        self.copy_inserting(at..self.scene_text.len(), &inserts);
        self.gen_scene("\n\n", &(0..0));
        self.gen_scene(
            &format!(
                "# ---- from {} (controller {}) ----\n",
                self.l5x_name, project.controller
            ),
            &(0..0),
        );

        self.controller_table(controller)?;
        self.data_types()?;
        self.module_data_types();
        self.axes(&axes_bindings)?;
        self.tags(&tag_bindings)?;
        self.tasks()?;
        for (name, span, used) in &self.not_simulated {
            if !used {
                return Err(self.scene_err(
                    span.clone(),
                    "controller.not_simulated",
                    format!("'{name}' is nothing the export holds that the twin skips"),
                ));
            }
        }
        Ok(())
    }

    /// Scene bytes `range`, with the generated lines of `inserts` (scene
    /// offset, text, L5X bytes, item) at their offsets.
    fn copy_inserting(&mut self, range: Range<usize>, inserts: &[Insert]) {
        let mut at = range.start;
        for (offset, text, span, item) in inserts.iter().filter(|i| range.contains(&i.0)) {
            self.copy(at..*offset);
            self.emit(text, span, Some(item.clone()));
            at = *offset;
        }
        self.copy(at..range.end);
    }

    /// `rpi_ms = …` for each scene sensor whose `tag` is a module's input
    /// tag and that gives no `rpi_ms`: the connection's RPI, inserted after
    /// the sensor's header line.
    fn sensor_rpis(&self, doc: &DeTable<'_>) -> Result<Vec<Insert>, Fail> {
        let tags = self.module_tags();
        let mut out = Vec::new();
        for (header, t) in array_tables(doc, "sensors") {
            if get(t, "rpi_ms").is_some() || !self.scene_text[header.clone()].trim_start().starts_with("[[") {
                continue;
            }
            let Some(tag) = get(t, "tag").and_then(string) else {
                continue;
            };
            let base = tag.trim().split(['.', '[']).next().unwrap_or("");
            let Some((name, _, Some(rpi))) = tags.iter().find(|(n, _, _)| n.eq_ignore_ascii_case(base)) else {
                continue;
            };
            let item = format!("{name} RPI");
            let us = self.number(rpi, &item)?;
            let line_end = self.scene_text[header.end..]
                .find('\n')
                .map_or(self.scene_text.len(), |i| header.end + i + 1);
            out.push((
                line_end,
                format!("rpi_ms = {}\n", float(us / 1000.0)),
                rpi.span.clone(),
                item,
            ));
        }
        out.sort_by_key(|i| i.0);
        Ok(out)
    }

    /// Blanks a standard table: its header and every key = value in it.
    fn blank_table(&mut self, doc: &DeTable<'_>, key: &str) {
        if let Some(v) = get(doc, key)
            && let DeValue::Table(t) = v.get_ref()
        {
            self.blank_entries(v.span(), t);
        }
    }

    fn blank_entries(&mut self, header: Range<usize>, t: &DeTable<'_>) {
        if self.scene_text[header.clone()].trim_start().starts_with('[') {
            self.blank.push(header);
        }
        for (k, v) in t.iter() {
            let text = &self.scene_text[v.span()];
            if text.trim_start().starts_with('[') && !matches!(v.get_ref(), DeValue::Array(_)) {
                // A sub-table header `[axes.drive]`.
                self.blank.push(v.span());
                if let DeValue::Table(sub) = v.get_ref() {
                    for (k2, v2) in sub.iter() {
                        self.blank.push(k2.span().start..v2.span().end);
                    }
                }
            } else {
                self.blank.push(k.span().start..v.span().end);
            }
        }
    }

    fn read_controller(&mut self, controller: &DeTable<'_>) -> Result<(), Fail> {
        for (k, v) in controller.iter() {
            match k.get_ref().as_ref() {
                "values" => {
                    let DeValue::Table(t) = v.get_ref() else {
                        return Err(self.scene_err(
                            v.span(),
                            "controller.values",
                            "expected a table of tag values".to_owned(),
                        ));
                    };
                    for (tag, value) in t.iter() {
                        self.values
                            .insert(tag.get_ref().to_ascii_lowercase(), (value.span(), false));
                    }
                }
                "not_simulated" => {
                    let DeValue::Array(a) = v.get_ref() else {
                        return Err(self.scene_err(
                            v.span(),
                            "controller.not_simulated",
                            "expected an array of names".to_owned(),
                        ));
                    };
                    for e in a.iter() {
                        let Some(s) = string(e) else {
                            return Err(self.scene_err(
                                e.span(),
                                "controller.not_simulated",
                                "expected a name".to_owned(),
                            ));
                        };
                        self.not_simulated.push((s.to_owned(), e.span(), false));
                    }
                }
                "report_overflow_faults" => {
                    let at = self
                        .project
                        .report_minor_overflow
                        .as_ref()
                        .map(|a| a.span.clone())
                        .unwrap_or_default();
                    return Err(self.refuse_field(
                        "controller.report_overflow_faults",
                        k.span(),
                        &self.project.controller,
                        "ReportMinorOverflow",
                        &at,
                    ));
                }
                "fault_handler" => {
                    let at = self
                        .project
                        .major_fault_program
                        .as_ref()
                        .map(|a| a.span.clone())
                        .unwrap_or_default();
                    return Err(self.refuse_field(
                        "controller.fault_handler",
                        k.span(),
                        &self.project.controller,
                        "MajorFaultProgram",
                        &at,
                    ));
                }
                _ => {}
            }
        }
        Ok(())
    }

    fn skips(&mut self, item: &str) -> bool {
        match self
            .not_simulated
            .iter_mut()
            .find(|(n, _, _)| n.eq_ignore_ascii_case(item))
        {
            Some(e) => {
                e.2 = true;
                self.skipped.push(item.to_owned());
                true
            }
            None => false,
        }
    }

    fn number(&self, a: &At<String>, item: &str) -> Result<f64, Fail> {
        let t = a.value.trim();
        t.parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| self.l5x_err(a.span.clone(), item, format!("\"{}\" is not a finite number", a.value)))
    }

    fn controller_table(&mut self, controller: &DeTable<'_>) -> Result<(), Fail> {
        let project = self.project;
        self.gen_scene("\n[controller]\n", &(0..0));
        for (k, v) in controller.iter() {
            let key = k.get_ref().to_string();
            if !matches!(key.as_str(), "l5x" | "values" | "not_simulated") {
                self.copy_field(&key, v.span());
            }
        }
        if let Some(a) = &project.report_minor_overflow {
            let item = format!("{} ReportMinorOverflow", project.controller);
            let b = match a.value.to_ascii_lowercase().as_str() {
                "true" => "true",
                "false" => "false",
                _ => {
                    return Err(self.l5x_err(
                        a.span.clone(),
                        &item,
                        format!("ReportMinorOverflow=\"{}\": expected true or false", a.value),
                    ));
                }
            };
            self.line("report_overflow_faults", b, &a.span, &item);
        }
        if let Some(handler) = &project.major_fault_program {
            let Some(program) = project
                .programs
                .iter()
                .find(|p| p.name.value.eq_ignore_ascii_case(&handler.value))
            else {
                return Err(self.l5x_err(
                    handler.span.clone(),
                    "MajorFaultProgram",
                    format!(
                        "MajorFaultProgram=\"{}\": the export has no such program",
                        handler.value
                    ),
                ));
            };
            self.program(
                program,
                "controller.fault_handler",
                "[controller.fault_handler]",
                "[[controller.fault_handler.tags]]",
            )?;
        }
        Ok(())
    }

    fn data_types(&mut self) -> Result<(), Fail> {
        for t in &self.project.data_types {
            let item = format!("DataType {}", t.name.value);
            self.header("[[data_types]]", &t.name.span, item.clone());
            self.line("name", &quote(&t.name.value), &t.name.span, &item);
            if !t.description.is_empty() {
                self.line("description", &quote(&t.description), &t.name.span, &item);
            }
            if let Some(n) = t.string_length {
                self.line("string_length", &n.to_string(), &t.name.span, &item);
                continue;
            }
            self.emit("members = [\n", &t.name.span, Some(item.clone()));
            for m in t.members.iter().filter(|m| !m.hidden) {
                let mitem = format!("{}.{}", t.name.value, m.name.value);
                let ty = if m.data_type.value.eq_ignore_ascii_case("BIT") {
                    "BOOL".to_owned()
                } else {
                    m.data_type.value.clone()
                };
                let mut text = format!("  {{ name = {}, type = {}", quote(&m.name.value), quote(&ty));
                if m.dimension.value > 0 {
                    let _ = write!(text, ", dimension = {}", m.dimension.value);
                }
                if !m.description.is_empty() {
                    let _ = write!(text, ", description = {}", quote(&m.description));
                }
                text.push_str(" },\n");
                self.emit(&text, &m.data_type.span, Some(mitem));
            }
            self.emit("]\n", &t.name.span, Some(item));
        }
        Ok(())
    }

    fn axes(&mut self, bindings: &[(Range<usize>, &DeTable<'_>)]) -> Result<(), Fail> {
        let project = self.project;
        // Each binding names an export axis.
        let mut bound: Vec<Option<&DeTable<'_>>> = vec![None; project.axes.len()];
        for (i, (header, t)) in bindings.iter().enumerate() {
            let field = |k: &str| format!("axes[{i}].{k}");
            let Some(name_v) = get(t, "name") else {
                return Err(self.scene_err(
                    header.clone(),
                    &format!("axes[{i}]"),
                    "an axis binding names an axis of the export: name = \"…\"".to_owned(),
                ));
            };
            let name = string(name_v).unwrap_or_default();
            let Some(k) = project
                .axes
                .iter()
                .position(|a| a.name.value.eq_ignore_ascii_case(name))
            else {
                let names: Vec<&str> = project.axes.iter().map(|a| a.name.value.as_str()).collect();
                return Err(self.scene_err(
                    name_v.span(),
                    &field("name"),
                    format!("no axis '{name}' in {} (its axes: {})", self.l5x_name, names.join(", ")),
                ));
            };
            let axis = &project.axes[k];
            let owner = (axis.name.value.as_str(), &axis.params);
            self.refuse_unlisted(t, (AXIS_BINDING, AXIS_FIELDS), owner, &format!("axes[{i}]"))?;
            if let Some(DeValue::Table(d)) = get(t, "drive").map(toml::Spanned::get_ref) {
                self.refuse_unlisted(d, (DRIVE_BINDING, DRIVE_FIELDS), owner, &field("drive"))?;
            }
            if bound[k].is_some() {
                return Err(self.scene_err(name_v.span(), &field("name"), format!("axis '{name}' is bound twice")));
            }
            bound[k] = Some(*t);
        }
        for (axis, binding) in project.axes.iter().zip(bound) {
            self.axis(axis, binding)?;
        }
        Ok(())
    }

    fn axis(&mut self, axis: &l5x::AxisTag, binding: Option<&DeTable<'_>>) -> Result<(), Fail> {
        let name = &axis.name.value;
        let item = |attr: &str| format!("{name} {attr}");
        let cip = match axis.data_type.value.as_str() {
            "AXIS_CIP_DRIVE" => true,
            "AXIS_VIRTUAL" => false,
            other => {
                return Err(self.l5x_err(
                    axis.data_type.span.clone(),
                    &item("DataType"),
                    format!("{name} is an {other}: the twin simulates AXIS_CIP_DRIVE and AXIS_VIRTUAL axes (a 5580's)"),
                ));
            }
        };
        let p = &axis.params;
        let field = |b: &DeTable<'_>, key: &str| get(b, key).map(toml::Spanned::span);
        let joint = binding.and_then(|b| field(b, "joint"));
        self.header("[[axes]]", &axis.name.span, item("Name"));
        self.line("name", &quote(name), &axis.name.span, &item("Name"));
        if let Some(j) = &joint {
            self.copy_field("joint", j.clone());
        } else if cip {
            self.note(
                &axis.name.span,
                format!("axis {name}: a CIP axis with no joint in the scene runs virtual"),
            );
        }
        // Units and kind.
        let units_attr = p.get("PositionUnits");
        let scene_units = binding.and_then(|b| field(b, "units"));
        let word = units_attr.map(|u| unit_word(&u.value));
        let units = match (&scene_units, word) {
            (Some(u), _) => {
                let w = self.scene_text[u.clone()]
                    .trim_matches(['"', '\''])
                    .to_ascii_lowercase();
                self.copy_field("units", u.clone());
                w
            }
            (None, Some(Some(w))) => {
                let at = units_attr.map(|a| a.span.clone()).unwrap_or_default();
                self.line("units", &quote(w), &at, &item("PositionUnits"));
                w.to_owned()
            }
            (None, _) => {
                let (span, written) = units_attr.map_or((p.element.clone(), String::new()), |a| {
                    (a.span.clone(), a.value.clone())
                });
                return Err(self.l5x_err(
                    span,
                    &item("PositionUnits"),
                    format!(
                        "{name}'s PositionUnits \"{written}\" is none of deg, rad, mm, m: give the axis' units in the scene (`units = \"deg\"` on its [[axes]] binding)"
                    ),
                ));
            }
        };
        let kind = if matches!(units.as_str(), "deg" | "rad") {
            "rotary"
        } else {
            "linear"
        };
        let kind_at = units_attr.map(|a| a.span.clone()).unwrap_or(p.element.clone());
        self.line("kind", &quote(kind), &kind_at, &item("PositionUnits"));
        // Unwind.
        if cip {
            if p.get("TravelMode")
                .is_some_and(|t| t.value.eq_ignore_ascii_case("Cyclic"))
            {
                self.modulo_period(p, name, "PositionUnwindNumerator", "PositionUnwindDenominator")?;
            }
        } else if p
            .get("RotaryAxis")
            .is_some_and(|t| t.value.eq_ignore_ascii_case("Rotary"))
        {
            self.modulo_period(p, name, "PositionUnwind", "ConversionConstant")?;
        }
        for (key, attr) in [
            ("max_velocity", "MaximumSpeed"),
            ("max_acceleration", "MaximumAcceleration"),
            ("max_deceleration", "MaximumDeceleration"),
            ("max_jerk", "MaximumAccelerationJerk"),
            ("in_position_window", "PositionLockTolerance"),
        ] {
            let a = self.required(p, attr, name)?;
            let v = self.number(&a, &item(attr))?;
            self.line(key, &float(v), &a.span, &item(attr));
        }
        if let Some(a) = p.get("MaximumDecelerationJerk") {
            self.number(a, &item("MaximumDecelerationJerk"))?;
            self.note(
                &a.span,
                format!(
                    "axis {name}: MaximumDecelerationJerk is not simulated; both ramps use MaximumAccelerationJerk"
                ),
            );
        }
        match p.get("SoftTravelLimitChecking").map(|a| a.value.to_ascii_lowercase()) {
            Some(v) if v == "true" => {
                let pos = self.required(p, "SoftTravelLimitPositive", name)?;
                let neg = self.required(p, "SoftTravelLimitNegative", name)?;
                let (hi, lo) = (
                    self.number(&pos, &item("SoftTravelLimitPositive"))?,
                    self.number(&neg, &item("SoftTravelLimitNegative"))?,
                );
                self.line(
                    "soft_travel_limits",
                    &format!("[{}, {}]", float(lo), float(hi)),
                    &pos.span,
                    &item("SoftTravelLimitPositive"),
                );
            }
            _ => {
                let at = p
                    .get("SoftTravelLimitChecking")
                    .map_or(p.element.clone(), |a| a.span.clone());
                self.line(
                    "soft_travel_limit_checking",
                    "false",
                    &at,
                    &item("SoftTravelLimitChecking"),
                );
            }
        }
        if joint.is_some() {
            if let Some(a) = p.get("PositionErrorTolerance") {
                let v = self.number(a, &item("PositionErrorTolerance"))?;
                if v > 0.0 {
                    self.line(
                        "position_error_tolerance",
                        &float(v),
                        &a.span,
                        &item("PositionErrorTolerance"),
                    );
                }
            }
            if cip {
                self.line("servo_on_at_start", "false", &axis.name.span, &item("servo state"));
            }
            if let Some(a) = p.get("AxisConfiguration") {
                let w = match a.value.as_str() {
                    "Position Loop" => "position_loop",
                    "Feedback Only" => "feedback_only",
                    other => {
                        return Err(self.l5x_err(
                            a.span.clone(),
                            &item("AxisConfiguration"),
                            format!("{name}'s AxisConfiguration \"{other}\" is not simulated (Position Loop, Feedback Only are)"),
                        ));
                    }
                };
                self.line("axis_configuration", &quote(w), &a.span, &item("AxisConfiguration"));
            }
        }
        self.exception_actions(p, name, joint.is_some())?;
        self.home(p, name)?;
        // The drive: the export's loop tuning, the scene's torque limits.
        let motor = binding.and_then(|b| field(b, "motor"));
        if let Some(m) = motor {
            self.copy_field("motor", m);
        } else if joint.is_some() {
            let mut parts: Vec<(String, Option<Range<usize>>, Range<usize>)> = Vec::new();
            for (key, attr) in DRIVE_FIELDS {
                if let Some(a) = p.get(attr) {
                    let v = self.number(a, &item(attr))?;
                    if v > 0.0 {
                        parts.push((format!("{key} = {}", float(v)), None, a.span.clone()));
                    }
                }
            }
            if let Some(DeValue::Table(d)) = binding.and_then(|b| get(b, "drive")).map(toml::Spanned::get_ref) {
                for (k, v) in d.iter() {
                    parts.push((k.get_ref().to_string(), Some(v.span()), v.span()));
                }
            }
            if !parts.is_empty() {
                self.emit("drive = { ", &axis.params.element, Some(item("drive")));
                for (i, (text, scene, at)) in parts.into_iter().enumerate() {
                    if i > 0 {
                        self.emit(", ", &at, None);
                    }
                    match scene {
                        Some(v) => {
                            self.gen_scene(&format!("{text} = "), &(v.start..v.start));
                            self.copy(v);
                        }
                        None => {
                            let attr = text.split(" = ").next().unwrap_or("").to_owned();
                            let l5x_attr = DRIVE_FIELDS.iter().find(|(k, _)| *k == attr).map_or("", |(_, a)| a);
                            self.emit(&text, &at, Some(item(l5x_attr)));
                        }
                    }
                }
                self.emit(" }\n", &axis.params.element, Some(item("drive")));
            }
            for attr in ["TorqueLimitPositive", "TorqueLimitNegative"] {
                if let Some(a) = p.get(attr) {
                    self.note(&a.span, format!("axis {name}: {attr} is % of the motor's rated torque; the torque limit in N·m comes from the scene or the URDF"));
                }
            }
        }
        for key in ["initial_position", "holding_brake", "brake_release_delay_ms"] {
            if let Some(v) = binding.and_then(|b| field(b, key)) {
                self.copy_field(key, v);
            }
        }
        Ok(())
    }

    /// The soft overtravel action from `MotionExceptionAction` (entries 1
    /// and 2: Soft Travel Limit - Positive / Negative, MOTION-RM003 *Motion
    /// Fault and Alarm Exceptions*) and, on an axis with a joint, the
    /// Excessive Position Error action from `CIPAxisExceptionAction`
    /// (entry 54, *Standard Axis Exceptions*). `Unsupported` keeps the
    /// scene's default.
    fn exception_actions(&mut self, p: &l5x::Params, name: &str, joint: bool) -> Result<(), Fail> {
        let word = |w: &str| match w {
            "Ignore" => Some(Some("ignore")),
            "Alarm" => Some(Some("alarm")),
            "FaultStatusOnly" | "Fault Status Only" => Some(Some("fault_status_only")),
            "StopPlanner" | "Stop Planner" => Some(Some("stop_planner")),
            "Disable" | "StopDrive" | "Stop Drive" => Some(Some("stop_drive")),
            "Shutdown" => Some(Some("shutdown")),
            "Unsupported" => Some(None),
            _ => None,
        };
        let entries = |a: &At<String>| -> Vec<String> {
            // Studio writes each action as one word or as words in a
            // multi-word name; split on the known names.
            let mut out = Vec::new();
            let words: Vec<&str> = a.value.split_whitespace().collect();
            let mut i = 0;
            while i < words.len() {
                let two = words.get(i + 1).map(|w| format!("{} {w}", words[i]));
                let three = words.get(i + 2).map(|w| format!("{} {} {w}", words[i], words[i + 1]));
                if let Some(t) = three.filter(|t| word(t).is_some()) {
                    out.push(t);
                    i += 3;
                } else if let Some(t) = two.filter(|t| word(t).is_some()) {
                    out.push(t);
                    i += 2;
                } else {
                    out.push(words[i].to_owned());
                    i += 1;
                }
            }
            out
        };
        let mut action = |attr: &str, indexes: &[usize], key: &str| -> Result<(), Fail> {
            let Some(a) = p.get(attr) else { return Ok(()) };
            let list = entries(a);
            let mut chosen: Option<&'static str> = None;
            for &i in indexes {
                let Some(w) = list.get(i) else { continue };
                let Some(mapped) = word(w) else {
                    return Err(self.l5x_err(
                        a.span.clone(),
                        &format!("{name} {attr}"),
                        format!("{attr} entry {i} \"{w}\": expected Ignore, Alarm, Fault Status Only, Stop Planner, Disable, Shutdown or Unsupported"),
                    ));
                };
                match (chosen, mapped) {
                    (None, Some(m)) => chosen = Some(m),
                    (Some(c), Some(m)) if c != m => {
                        self.note(&a.span, format!("axis {name}: {attr} differs between the soft travel limits; the twin applies {c} to both"));
                    }
                    _ => {}
                }
            }
            if let Some(c) = chosen {
                self.line(key, &quote(c), &a.span, &format!("{name} {attr}"));
            }
            Ok(())
        };
        action("MotionExceptionAction", &[1, 2], "soft_overtravel_action")?;
        if joint {
            action("CIPAxisExceptionAction", &[54], "position_error_action")?;
        }
        Ok(())
    }

    /// `modulo_period = numerator / denominator`, two required attributes
    /// (a CIP axis' unwind ratio, a virtual axis' unwind over its
    /// conversion constant); a zero denominator is refused.
    fn modulo_period(&mut self, p: &l5x::Params, name: &str, numerator: &str, denominator: &str) -> Result<(), Fail> {
        let item = |attr: &str| format!("{name} {attr}");
        let num = self.required(p, numerator, name)?;
        let den = self.required(p, denominator, name)?;
        let (n, d) = (
            self.number(&num, &item(numerator))?,
            self.number(&den, &item(denominator))?,
        );
        if d == 0.0 {
            return Err(self.l5x_err(den.span, &item(denominator), format!("{denominator} is 0")));
        }
        self.line("modulo_period", &float(n / d), &num.span, &item(numerator));
        Ok(())
    }

    fn home(&mut self, p: &l5x::Params, name: &str) -> Result<(), Fail> {
        let item = |attr: &str| format!("{name} {attr}");
        // (scene field, L5X attribute, its words and the scene's).
        type Words = &'static [(&'static str, &'static str)];
        let words: [(&str, &str, Words); 4] = [
            ("home_mode", "HomeMode", &[("Active", "active"), ("Passive", "passive")]),
            (
                "home_sequence",
                "HomeSequence",
                &[
                    ("Immediate", "immediate"),
                    ("Home To Switch", "switch"),
                    ("Home To Marker", "marker"),
                    ("Home To Switch And Marker", "switch_marker"),
                    ("Home To Torque Level", "torque_level"),
                    ("Home To Torque Level And Marker", "torque_level_marker"),
                ],
            ),
            (
                "home_direction",
                "HomeDirection",
                &[
                    ("Uni-directional Forward", "unidirectional_forward"),
                    ("Bi-directional Forward", "bidirectional_forward"),
                    ("Uni-directional Reverse", "unidirectional_reverse"),
                    ("Bi-directional Reverse", "bidirectional_reverse"),
                ],
            ),
            (
                "programmed_stop_mode",
                "ProgrammedStopMode",
                &[
                    ("Fast Stop", "fast_stop"),
                    ("Fast Disable", "fast_disable"),
                    ("Hard Disable", "hard_disable"),
                    ("Fast Shutdown", "fast_shutdown"),
                    ("Hard Shutdown", "hard_shutdown"),
                ],
            ),
        ];
        for (key, attr, table) in words {
            if let Some(a) = p.get(attr) {
                let Some((_, w)) = table.iter().find(|(l, _)| l.eq_ignore_ascii_case(a.value.trim())) else {
                    let known: Vec<&str> = table.iter().map(|(l, _)| *l).collect();
                    return Err(self.l5x_err(
                        a.span.clone(),
                        &item(attr),
                        format!("{attr}=\"{}\": expected one of {}", a.value, known.join(", ")),
                    ));
                };
                self.line(key, &quote(w), &a.span, &item(attr));
            }
        }
        if let Some(a) = p.get("OutputCamExecutionTargets") {
            let v = self.number(a, &item("OutputCamExecutionTargets"))?;
            self.line(
                "output_cam_execution_targets",
                &format!("{}", v as i64),
                &a.span,
                &item("OutputCamExecutionTargets"),
            );
        }
        for (key, attr) in [
            ("home_position", "HomePosition"),
            ("home_offset", "HomeOffset"),
            ("home_speed", "HomeSpeed"),
            ("home_return_speed", "HomeReturnSpeed"),
        ] {
            if let Some(a) = p.get(attr) {
                let v = self.number(a, &item(attr))?;
                self.line(key, &float(v), &a.span, &item(attr));
            }
        }
        Ok(())
    }

    fn required(&self, p: &l5x::Params, attr: &str, owner: &str) -> Result<At<String>, Fail> {
        p.get(attr).cloned().ok_or_else(|| {
            self.l5x_err(
                p.element.clone(),
                &format!("{owner} {attr}"),
                format!("{owner} has no {attr} attribute"),
            )
        })
    }

    fn tags(&mut self, bindings: &[(Range<usize>, &DeTable<'_>)]) -> Result<(), Fail> {
        let project = self.project;
        let mut bound: Vec<Option<&DeTable<'_>>> = vec![None; project.coordinate_systems.len()];
        for (i, (header, t)) in bindings.iter().enumerate() {
            let field = |k: &str| format!("tags[{i}].{k}");
            let Some(name_v) = get(t, "name") else {
                return Err(self.scene_err(
                    header.clone(),
                    &format!("tags[{i}]"),
                    "a tag binding names a coordinate system of the export: name = \"…\"".to_owned(),
                ));
            };
            let name = string(name_v).unwrap_or_default();
            let Some(k) = project
                .coordinate_systems
                .iter()
                .position(|c| c.name.value.eq_ignore_ascii_case(name))
            else {
                let exported = project
                    .tags
                    .iter()
                    .chain(project.programs.iter().flat_map(|p| &p.tags))
                    .find(|t| t.name.value.eq_ignore_ascii_case(name));
                let message = match exported {
                    Some(tag) => format!(
                        "{name} comes from {}; give its initial value in [controller] values, change the rest there",
                        self.place(&tag.span)
                    ),
                    None => format!(
                        "no coordinate system '{name}' in {}: a scene next to an export binds only its coordinate systems; declare other tags in the project",
                        self.l5x_name
                    ),
                };
                return Err(self.scene_err(name_v.span(), &field("name"), message));
            };
            let cs = &project.coordinate_systems[k];
            let owner = (cs.name.value.as_str(), &cs.params);
            self.refuse_unlisted(t, (CS_TAG_BINDING, CS_TAG_FIELDS), owner, &format!("tags[{i}]"))?;
            for (key, allowed, fields) in [
                ("coordinate_system", CS_BINDING, CS_FIELDS),
                ("geometry", GEOMETRY_BINDING, GEOMETRY_FIELDS),
            ] {
                let Some(v) = get(t, key) else { continue };
                let DeValue::Table(sub) = v.get_ref() else {
                    return Err(self.scene_err(v.span(), &field(key), "expected a table"));
                };
                self.refuse_unlisted(sub, (allowed, fields), owner, &field(key))?;
            }
            if bound[k].is_some() {
                return Err(self.scene_err(
                    name_v.span(),
                    &field("name"),
                    format!("coordinate system '{name}' is bound twice"),
                ));
            }
            bound[k] = Some(t);
        }
        for (cs, binding) in project.coordinate_systems.iter().zip(bound) {
            self.coordinate_system(cs, binding)?;
        }
        if let Some((mg, params)) = &project.motion_group {
            let Some(period) = params.get("CoarseUpdatePeriod") else {
                return Err(self.l5x_err(
                    params.element.clone(),
                    &mg.value,
                    format!("motion group {} has no CoarseUpdatePeriod", mg.value),
                ));
            };
            let item = format!("{} Name", mg.value);
            self.header("[[tags]]", &mg.span, item.clone());
            self.line("name", &quote(&mg.value), &mg.span, &item);
            self.line("type", "\"MOTION_GROUP\"", &mg.span, &format!("{} DataType", mg.value));
            let item = format!("{} CoarseUpdatePeriod", mg.value);
            let us = self.number(period, &item)?;
            self.line("coarse_update_ms", &float(us / 1000.0), &period.span, &item);
        }
        self.module_io_tags();
        for tag in &project.tags {
            self.tag(tag, None, "[[tags]]")?;
        }
        self.aliases(&project.tags, None, "[[aliases]]")?;
        for (name, (span, used)) in &self.values {
            if !used {
                return Err(self.scene_err(
                    span.clone(),
                    &format!("controller.values.{name}"),
                    format!("no tag '{name}' in {} takes a value", self.l5x_name),
                ));
            }
        }
        Ok(())
    }

    fn coordinate_system(&mut self, cs: &l5x::CoordinateSystemTag, binding: Option<&DeTable<'_>>) -> Result<(), Fail> {
        let name = &cs.name.value;
        let p = &cs.params;
        let item = |attr: &str| format!("{name} {attr}");
        self.header("[[tags]]", &cs.name.span, item("Name"));
        self.line("name", &quote(name), &cs.name.span, &item("Name"));
        self.line("type", "\"COORDINATE_SYSTEM\"", &cs.name.span, &item("DataType"));
        let axes = self.required(p, "Axes", name)?;
        let members: Vec<&str> = axes
            .value
            .split_whitespace()
            .filter(|a| *a != "{none}" && !a.is_empty())
            .collect();
        if let Some(d) = p.get("Dimension") {
            let n = self.number(d, &item("Dimension"))?;
            if n != members.len() as f64 {
                return Err(self.l5x_err(
                    d.span.clone(),
                    &item("Dimension"),
                    format!("Dimension=\"{}\" but Axes names {} axes", d.value, members.len()),
                ));
            }
        }
        let list: Vec<String> = members.iter().map(|a| quote(a)).collect();
        self.line("value", &format!("[{}]", list.join(", ")), &axes.span, &item("Axes"));
        // Conversion ratios: 1:1 only.
        if let (Some(num), Some(den)) = (p.get("ConversionRatioNumerator"), p.get("ConversionRatioDenominator")) {
            for (n, d) in num.value.split_whitespace().zip(den.value.split_whitespace()) {
                if n.parse::<f64>().ok() != d.parse::<f64>().ok() || n.parse::<f64>().is_err() {
                    return Err(self.l5x_err(
                        num.span.clone(),
                        &item("ConversionRatioNumerator"),
                        format!("{name}'s conversion ratio {n}:{d}: the twin simulates 1:1 ratios only"),
                    ));
                }
            }
        }
        // coordinate_system = { … }. The table itself stands for the
        // scene's binding when there is one: the checks after loading (the
        // tool link against the URDF) are about what the scene gave.
        self.open_table(
            "coordinate_system",
            binding,
            &p.element,
            item("CoordinateSystemParameters"),
        );
        let mut first = true;
        if let Some(mode) = p.get("CoordinationMode") {
            let words: Vec<&str> = mode.value.split_whitespace().collect();
            let primaries = words.iter().take_while(|w| w.eq_ignore_ascii_case("Primary")).count();
            if primaries == 0 || words.iter().skip(primaries).any(|w| w.eq_ignore_ascii_case("Primary")) {
                return Err(self.l5x_err(
                    mode.span.clone(),
                    &item("CoordinationMode"),
                    format!("CoordinationMode=\"{}\": primary axes first, at least one", mode.value),
                ));
            }
            self.emit(
                &format!("primary_axes = {}", primaries.min(members.len()).min(3)),
                &mode.span,
                Some(item("CoordinationMode")),
            );
            first = false;
        }
        for (key, attr) in &CS_FIELDS[1..] {
            if let Some(a) = p.get(attr) {
                let v = self.number(a, &item(attr))?;
                if !first {
                    self.emit(", ", &a.span, None);
                }
                self.emit(&format!("{key} = {}", float(v)), &a.span, Some(item(attr)));
                first = false;
            }
        }
        if let Some(DeValue::Table(t)) = binding
            .and_then(|b| get(b, "coordinate_system"))
            .map(toml::Spanned::get_ref)
        {
            for (k, v) in t.iter() {
                if !first {
                    self.gen_scene(", ", &(v.span().start..v.span().start));
                }
                self.gen_scene(&format!("{} = ", k.get_ref()), &(v.span().start..v.span().start));
                self.copy(v.span());
                first = false;
            }
        }
        self.emit(" }\n", &p.element, Some(item("CoordinateSystemParameters")));
        // geometry = { … }.
        let system = self.required(p, "SystemType", name)?;
        let dim = match p.get("TransformDimension") {
            Some(a) => Some((self.number(a, &item("TransformDimension"))?, a.span.clone())),
            None => None,
        };
        let norm = |s: &str| {
            s.chars()
                .filter(|c| c.is_ascii_alphanumeric())
                .collect::<String>()
                .to_ascii_lowercase()
        };
        let Some(&(_, mut kind)) = SYSTEM_TYPES.iter().find(|(l, _)| norm(l) == norm(&system.value)) else {
            let known: Vec<&str> = SYSTEM_TYPES.iter().map(|(l, _)| *l).collect();
            return Err(self.l5x_err(
                system.span.clone(),
                &item("SystemType"),
                format!(
                    "{name}'s SystemType \"{}\" is not one the twin simulates: {}",
                    system.value,
                    known.join(", ")
                ),
            ));
        };
        if kind == "delta_3d" && dim.as_ref().is_some_and(|(d, _)| *d == 2.0) {
            kind = "delta_2d";
        }
        self.open_table("geometry", binding, &system.span, item("SystemType"));
        self.emit(
            &format!("type = {}", quote(kind)),
            &system.span,
            Some(item("SystemType")),
        );
        if let Some((d, span)) = &dim {
            self.emit(
                &format!(", transform_dimension = {d}"),
                span,
                Some(item("TransformDimension")),
            );
        }
        for (key, prefix, n) in [
            ("link_lengths", "LinkLength", 2),
            ("base_offsets", "BaseOffset", 3),
            ("end_effector_offsets", "EndEffectorOffset", 3),
            ("zero_angles_deg", "ZeroAngleOffset", 3),
        ] {
            let attrs: Vec<Option<&At<String>>> = (1..=n).map(|k| p.get(&format!("{prefix}{k}"))).collect();
            if attrs.iter().all(Option::is_none) {
                continue;
            }
            let mut values = Vec::new();
            for (k, a) in attrs.iter().enumerate() {
                values.push(match a {
                    Some(a) => float(self.number(a, &item(&format!("{prefix}{}", k + 1)))?),
                    None => "0.0".to_owned(),
                });
            }
            let at = attrs
                .iter()
                .flatten()
                .next()
                .map(|a| a.span.clone())
                .unwrap_or_default();
            self.emit(
                &format!(", {key} = [{}]", values.join(", ")),
                &at,
                Some(item(&format!("{prefix}1"))),
            );
        }
        if let Some(DeValue::Table(t)) = binding.and_then(|b| get(b, "geometry")).map(toml::Spanned::get_ref) {
            for (k, v) in t.iter() {
                self.gen_scene(&format!(", {} = ", k.get_ref()), &(v.span().start..v.span().start));
                self.copy(v.span());
            }
        }
        self.emit(" }\n", &system.span, Some(item("SystemType")));
        Ok(())
    }

    /// A tag as `[[tags]]`/`[[tasks.programs.tags]]`; `program` for the
    /// program's parameters. Types the twin does not know are reported.
    fn tag(&mut self, tag: &l5x::Tag, program: Option<&l5x::Program>, header: &str) -> Result<(), Fail> {
        let name = &tag.name.value;
        let full = program.map_or_else(|| name.clone(), |p| format!("{}.{name}", p.name.value));
        let item = |attr: &str| format!("{full} {attr}");
        if tag.alias_for.is_some() {
            // Aliases follow the scope's tags (`aliases`).
            return Ok(());
        }
        let Some(data_type) = &tag.data_type else { return Ok(()) };
        let ty = &data_type.value;
        let known = BaseType::parse(ty).is_some()
            || ty.eq_ignore_ascii_case("STRING")
            || self
                .project
                .data_types
                .iter()
                .any(|d| d.name.value.eq_ignore_ascii_case(ty))
            || self.project.aois.iter().any(|a| a.name.value.eq_ignore_ascii_case(ty));
        if !known {
            self.note(
                &data_type.span,
                format!("tag {full}: type {ty} is not simulated; a routine naming it is refused"),
            );
            return Ok(());
        }
        let mut type_text = ty.clone();
        if let Some(d) = &tag.dimensions {
            let dims: Vec<&str> = d.value.split_whitespace().collect();
            for x in &dims {
                match x.parse::<u64>() {
                    Ok(n) if n >= 1 && n <= super::model::MAX_ARRAY_LEN as u64 => {}
                    _ => {
                        return Err(self.l5x_err(
                            d.span.clone(),
                            &item("Dimensions"),
                            format!(
                                "Dimensions=\"{}\": each dimension is 1 to {}",
                                d.value,
                                super::model::MAX_ARRAY_LEN
                            ),
                        ));
                    }
                }
            }
            if dims.len() > 3 || dims.is_empty() {
                return Err(self.l5x_err(
                    d.span.clone(),
                    &item("Dimensions"),
                    format!("Dimensions=\"{}\": one to three dimensions", d.value),
                ));
            }
            let _ = write!(type_text, "[{}]", dims.join(","));
        }
        self.header(header, &tag.span, item("Name"));
        self.line("name", &quote(name), &tag.name.span, &item("Name"));
        self.line("type", &quote(&type_text), &data_type.span, &item("DataType"));
        let key = full.to_ascii_lowercase();
        if let Some((span, used)) = self.values.get_mut(&key) {
            *used = true;
            let span = span.clone();
            self.copy_field("value", span);
        } else if let Some(v) = &tag.value {
            // Decorated data names the members; L5K data does not.
            if is_instruction_structure(ty) && matches!(v.value, Value::Struct(_)) && has_settings(&v.value) {
                self.note(
                    &v.span,
                    format!("tag {full}: its exported {ty} values (presets, settings) are not read; the structure starts cleared, EnableIn set"),
                );
            }
            if let Some(text) = self.value_text(&v.value, ty) {
                self.line("value", &text, &v.span, &item("Data"));
            }
        }
        if tag.constant {
            self.line("constant", "true", &tag.span, &item("Constant"));
        }
        if let Some(a) = &tag.external_access {
            let w = match a.value.as_str() {
                "Read/Write" => "read_write",
                "Read Only" => "read_only",
                "None" => "none",
                other => {
                    return Err(self.l5x_err(
                        a.span.clone(),
                        &item("ExternalAccess"),
                        format!("ExternalAccess=\"{other}\": expected Read/Write, Read Only or None"),
                    ));
                }
            };
            self.line("external_access", &quote(w), &a.span, &item("ExternalAccess"));
        }
        if !tag.description.is_empty() {
            self.line("description", &quote(&tag.description), &tag.span, &item("Description"));
        }
        if let (Some(p), Some(u)) = (program, &tag.usage) {
            let w = match u.value.as_str() {
                "Input" => "input",
                "Output" => "output",
                "InOut" => "inout",
                "Public" => "public",
                "Local" => "local",
                other => {
                    return Err(self.l5x_err(
                        u.span.clone(),
                        &item("Usage"),
                        format!("Usage=\"{other}\": expected Input, Output, InOut or Public"),
                    ));
                }
            };
            self.line("usage", &quote(w), &u.span, &item("Usage"));
            let me = format!("\\{}.{name}", p.name.value);
            let other = self
                .project
                .programs
                .iter()
                .flat_map(|q| &q.connections)
                .find_map(|(a, b)| {
                    if a.value.eq_ignore_ascii_case(&me) {
                        Some(b)
                    } else if b.value.eq_ignore_ascii_case(&me) {
                        Some(a)
                    } else {
                        None
                    }
                });
            if let Some(c) = other {
                self.line("connection", &quote(&c.value), &c.span, &item("ParameterConnection"));
            }
        }
        Ok(())
    }

    /// Every module I/O tag: its name (`Local:1:I`), its structure and the
    /// connection's RPI.
    fn module_tags(&self) -> Vec<(String, &'a l5x::IoType, Option<&'a At<String>>)> {
        let mut out = Vec::new();
        let project: &'a Project = self.project;
        for m in &project.modules {
            let prefix = m.tag_prefix();
            for c in &m.connections {
                for (suffix, ty) in c.input.iter().chain(&c.output) {
                    out.push((format!("{prefix}:{suffix}"), ty, c.rpi_us.as_ref()));
                }
            }
        }
        out
    }

    /// The data types of the module tags, each once, nested ones first.
    fn module_data_types(&mut self) {
        let mut done: Vec<String> = Vec::new();
        for (_, ty, _) in self.module_tags() {
            self.module_type(ty, &mut done);
        }
    }

    fn module_type(&mut self, ty: &l5x::IoType, done: &mut Vec<String>) {
        let name = io_type_name(&ty.data_type.value);
        if done.iter().any(|d| d.eq_ignore_ascii_case(&name)) {
            return;
        }
        done.push(name.clone());
        for m in &ty.members {
            if let Some(n) = &m.nested {
                self.module_type(n, done);
            }
        }
        let item = format!("DataType {}", ty.data_type.value);
        self.header("[[data_types]]", &ty.data_type.span, item.clone());
        self.line("name", &quote(&name), &ty.data_type.span, &item);
        self.line(
            "description",
            &quote(&format!("the module-defined type {}", ty.data_type.value)),
            &ty.data_type.span,
            &item,
        );
        self.emit("members = [\n", &ty.data_type.span, Some(item.clone()));
        for m in &ty.members {
            let mty = match &m.nested {
                Some(n) => io_type_name(&n.data_type.value),
                None if m.data_type.eq_ignore_ascii_case("BIT") => "BOOL".to_owned(),
                None => m.data_type.clone(),
            };
            let mut text = format!("  {{ name = {}, type = {}", quote(&m.name), quote(&mty));
            if m.dimension > 0 {
                let _ = write!(text, ", dimension = {}", m.dimension);
            }
            text.push_str(" },\n");
            self.emit(
                &text,
                &ty.data_type.span,
                Some(format!("{} {}", ty.data_type.value, m.name)),
            );
        }
        self.emit("]\n", &ty.data_type.span, Some(item));
    }

    /// The module I/O tags as controller tags.
    fn module_io_tags(&mut self) {
        for (name, ty, _) in self.module_tags() {
            let item = format!("{name} DataType");
            self.header("[[tags]]", &ty.data_type.span, item.clone());
            self.line("name", &quote(&name), &ty.data_type.span, &item);
            self.line(
                "type",
                &quote(&io_type_name(&ty.data_type.value)),
                &ty.data_type.span,
                &item,
            );
        }
    }

    /// The alias tags among `tags` as `[[aliases]]` entries of `header`.
    fn aliases(&mut self, tags: &[l5x::Tag], program: Option<&l5x::Program>, header: &str) -> Result<(), Fail> {
        for tag in tags {
            let Some(alias) = &tag.alias_for else { continue };
            let name = &tag.name.value;
            let full = program.map_or_else(|| name.clone(), |p| format!("{}.{name}", p.name.value));
            self.alias_target(alias, program, &full)?;
            let item = |attr: &str| format!("{full} {attr}");
            self.header(header, &tag.span, item("Name"));
            self.line("name", &quote(name), &tag.name.span, &item("Name"));
            self.line("alias_for", &quote(alias.value.trim()), &alias.span, &item("AliasFor"));
            if !tag.description.is_empty() {
                self.line("description", &quote(&tag.description), &tag.span, &item("Description"));
            }
        }
        Ok(())
    }

    /// Refuses an alias whose target names nothing in the export: its
    /// base tag (in the program, else the controller; a module's tag by
    /// its module) and, for a structure, its first member.
    fn alias_target(&self, alias: &At<String>, program: Option<&l5x::Program>, full: &str) -> Result<(), Fail> {
        let target = alias.value.trim();
        let project = self.project;
        let dangling = |what: String| {
            self.l5x_err(
                alias.span.clone(),
                &format!("{full} AliasFor"),
                format!("alias {full}: AliasFor=\"{target}\" {what}"),
            )
        };
        if target.contains(':') {
            let base = target.split(['.', '[']).next().unwrap_or("");
            return if self.module_tags().iter().any(|(n, _, _)| n.eq_ignore_ascii_case(base)) {
                Ok(())
            } else {
                Err(dangling("names no I/O tag of the export's modules".to_owned()))
            };
        }
        let end = target.find(['.', '[']).unwrap_or(target.len());
        let base = &target[..end];
        let same = |n: &str| n.eq_ignore_ascii_case(base);
        let in_program = program.and_then(|p| p.tags.iter().find(|t| same(&t.name.value)));
        let tag = in_program.or_else(|| project.tags.iter().find(|t| same(&t.name.value)));
        let motion = project.axes.iter().any(|a| same(&a.name.value))
            || project.coordinate_systems.iter().any(|c| same(&c.name.value))
            || project.motion_group.as_ref().is_some_and(|(m, _)| same(&m.value));
        let Some(tag) = tag else {
            return if motion {
                Ok(())
            } else {
                Err(dangling("names no tag of the export".to_owned()))
            };
        };
        // The first member of a structure tag.
        let rest = target[end..]
            .trim_start_matches(|c| c != '.' && c != ']')
            .trim_start_matches(']');
        if let (Some(member), Some(ty)) = (rest.strip_prefix('.'), &tag.data_type) {
            let member = member.split(['.', '[']).next().unwrap_or("");
            if let Some(udt) = project
                .data_types
                .iter()
                .find(|d| d.name.value.eq_ignore_ascii_case(&ty.value))
            {
                let known = udt
                    .members
                    .iter()
                    .any(|m| !m.hidden && m.name.value.eq_ignore_ascii_case(member));
                if !known && member.parse::<u32>().is_err() {
                    return Err(dangling(format!(
                        "names member {member}, which {} does not have",
                        udt.name.value
                    )));
                }
            }
        }
        Ok(())
    }

    /// A value as TOML for type `ty`; `None` for the types the twin fills.
    fn value_text(&self, v: &Value, ty: &str) -> Option<String> {
        match BaseType::parse(ty) {
            Some(
                BaseType::MotionInstruction | BaseType::CoordinateSystem | BaseType::MotionGroup | BaseType::CamProfile,
            ) => return None,
            _ if is_instruction_structure(ty) => return None,
            Some(BaseType::Cam) => return Some(self.cam_text(v)),
            _ => {}
        }
        Some(self.toml_value(v, ty))
    }

    fn cam_text(&self, v: &Value) -> String {
        let point = |p: &Value| -> String {
            let Value::Struct(m) = p else {
                return "{ master = 0.0, slave = 0.0 }".to_owned();
            };
            let f = |n: &str| m.iter().find(|(k, _)| k.eq_ignore_ascii_case(n)).map(|(_, v)| v);
            let num = |v: Option<&Value>| match v {
                Some(Value::Float(x)) => float(*x),
                Some(Value::Int(i)) => float(*i as f64),
                _ => "0.0".to_owned(),
            };
            let seg = match f("SegmentType") {
                Some(Value::Int(0)) => "linear",
                _ => "cubic",
            };
            format!(
                "{{ master = {}, slave = {}, segment_type = \"{seg}\" }}",
                num(f("Master")),
                num(f("Slave"))
            )
        };
        match v {
            Value::Array(items) => {
                // Trailing all-zero points are the unused rest of the array.
                let mut pts: Vec<&Value> = items.iter().collect();
                while pts.len() > 1
                    && pts
                        .last()
                        .is_some_and(|p| point(p).starts_with("{ master = 0.0, slave = 0.0"))
                {
                    pts.pop();
                }
                format!("[{}]", pts.iter().map(|p| point(p)).collect::<Vec<_>>().join(", "))
            }
            other => format!("[{}]", point(other)),
        }
    }

    fn toml_value(&self, v: &Value, ty: &str) -> String {
        let real = ty.eq_ignore_ascii_case("REAL") || ty.eq_ignore_ascii_case("LREAL");
        match v {
            Value::Bool(b) => b.to_string(),
            Value::Int(i) if real => float(*i as f64),
            Value::Int(i) if ty.eq_ignore_ascii_case("BOOL") => (*i != 0).to_string(),
            Value::Int(i) => i.to_string(),
            Value::Float(f) => float(*f),
            Value::Str(s) => quote(s),
            Value::Array(items) => {
                let parts: Vec<String> = items.iter().map(|e| self.toml_value(e, ty)).collect();
                format!("[{}]", parts.join(", "))
            }
            Value::Struct(members) => {
                let udt = self
                    .project
                    .data_types
                    .iter()
                    .find(|d| d.name.value.eq_ignore_ascii_case(ty));
                let mut parts = Vec::new();
                for (name, value) in members {
                    let Some(m) = udt.and_then(|d| d.members.iter().find(|m| m.name.value.eq_ignore_ascii_case(name)))
                    else {
                        continue;
                    };
                    if m.hidden {
                        continue;
                    }
                    let mty = if m.data_type.value.eq_ignore_ascii_case("BIT") {
                        "BOOL"
                    } else {
                        m.data_type.value.as_str()
                    };
                    if let Some(text) = self.value_text(value, mty) {
                        parts.push(format!("{} = {text}", key(name)));
                    }
                }
                format!("{{ {} }}", parts.join(", "))
            }
        }
    }

    fn tasks(&mut self) -> Result<(), Fail> {
        let project = self.project;
        let mut scheduled: Vec<String> = Vec::new();
        for task in &project.tasks {
            let name = &task.name.value;
            let item = |attr: &str| format!("{name} {attr}");
            self.header("[[tasks]]", &task.name.span, item("Name"));
            self.line("name", &quote(name), &task.name.span, &item("Name"));
            match task.kind.value.as_str() {
                "CONTINUOUS" => self.line("type", "\"continuous\"", &task.kind.span, &item("Type")),
                "PERIODIC" => {
                    let rate = task.rate.clone().ok_or_else(|| {
                        self.l5x_err(
                            task.kind.span.clone(),
                            &item("Rate"),
                            format!("periodic task {name} has no Rate"),
                        )
                    })?;
                    self.line(
                        "period_ms",
                        &float(self.number(&rate, &item("Rate"))?),
                        &rate.span,
                        &item("Rate"),
                    );
                    self.priority(task)?;
                }
                "EVENT" => {
                    self.line("type", "\"event\"", &task.kind.span, &item("Type"));
                    self.priority(task)?;
                    let trigger = task.event_trigger.clone().ok_or_else(|| {
                        self.l5x_err(
                            task.kind.span.clone(),
                            &item("EventTrigger"),
                            format!("event task {name} has no EventInfo EventTrigger"),
                        )
                    })?;
                    let word = match trigger.value.as_str() {
                        "EVENT Instruction Only" => Some("event_instruction"),
                        "Motion Group Execution" => Some("motion_group_execution"),
                        "Axis Registration 1" => Some("axis_registration_1"),
                        "Axis Registration 2" => Some("axis_registration_2"),
                        "Axis Watch" => Some("axis_watch"),
                        _ => None,
                    };
                    match word {
                        Some(w) => self.line("trigger", &quote(w), &trigger.span, &item("EventTrigger")),
                        None => {
                            self.note(
                                &trigger.span,
                                format!(
                                    "task {name}: trigger \"{}\" is not simulated; only EVENT instructions trigger it",
                                    trigger.value
                                ),
                            );
                            self.line("trigger", "\"event_instruction\"", &trigger.span, &item("EventTrigger"));
                        }
                    }
                    if word.is_some_and(|w| w.starts_with("axis_")) {
                        let axis = task.event_tag.clone().ok_or_else(|| {
                            self.l5x_err(
                                trigger.span.clone(),
                                &item("EventTag"),
                                format!("event task {name} has no EventTag naming its axis"),
                            )
                        })?;
                        self.line("axis", &quote(&axis.value), &axis.span, &item("EventTag"));
                    }
                    if task.enable_timeout {
                        let rate = task.rate.clone().ok_or_else(|| {
                            self.l5x_err(
                                trigger.span.clone(),
                                &item("Rate"),
                                format!("event task {name} enables its timeout without a Rate"),
                            )
                        })?;
                        self.line(
                            "timeout_ms",
                            &float(self.number(&rate, &item("Rate"))?),
                            &rate.span,
                            &item("Rate"),
                        );
                    }
                }
                other => {
                    return Err(self.l5x_err(
                        task.kind.span.clone(),
                        &item("Type"),
                        format!("task Type=\"{other}\": expected CONTINUOUS, PERIODIC or EVENT"),
                    ));
                }
            }
            if let Some(w) = &task.watchdog {
                let v = self.number(w, &item("Watchdog"))?;
                self.line("watchdog_ms", &float(v), &w.span, &item("Watchdog"));
            }
            if task.inhibit {
                self.line("inhibit", "true", &task.name.span, &item("InhibitTask"));
            }
            for prog in &task.programs {
                let Some(program) = project
                    .programs
                    .iter()
                    .find(|p| p.name.value.eq_ignore_ascii_case(&prog.value))
                else {
                    return Err(self.l5x_err(
                        prog.span.clone(),
                        &item("ScheduledProgram"),
                        format!(
                            "task {name} schedules program {}, which the export does not hold",
                            prog.value
                        ),
                    ));
                };
                scheduled.push(program.name.value.to_ascii_lowercase());
                if program.use_as_folder {
                    continue;
                }
                self.program(
                    program,
                    "tasks.programs",
                    "[[tasks.programs]]",
                    "[[tasks.programs.tags]]",
                )?;
            }
        }
        let handler = project
            .major_fault_program
            .as_ref()
            .map(|h| h.value.to_ascii_lowercase());
        for p in &project.programs {
            let lower = p.name.value.to_ascii_lowercase();
            if !scheduled.contains(&lower) && handler.as_ref() != Some(&lower) && !p.use_as_folder {
                self.note(
                    &p.name.span,
                    format!("program {}: scheduled in no task, never scanned", p.name.value),
                );
            }
        }
        Ok(())
    }

    fn priority(&mut self, task: &l5x::Task) -> Result<(), Fail> {
        let item = format!("{} Priority", task.name.value);
        let p = task.priority.clone().ok_or_else(|| {
            self.l5x_err(
                task.kind.span.clone(),
                &item,
                format!("task {} has no Priority", task.name.value),
            )
        })?;
        let v = p.value.trim().parse::<i64>().map_err(|_| {
            self.l5x_err(
                p.span.clone(),
                &item,
                format!("Priority=\"{}\": expected a whole number", p.value),
            )
        })?;
        self.line("priority", &v.to_string(), &p.span, &item);
        Ok(())
    }

    fn program(&mut self, program: &l5x::Program, field: &str, header: &str, tags_header: &str) -> Result<(), Fail> {
        let name = &program.name.value;
        let item = |attr: &str| format!("{name} {attr}");
        let Some(main) = &program.main else {
            return Err(self.l5x_err(
                program.name.span.clone(),
                &item("MainRoutineName"),
                format!("program {name} has no main routine"),
            ));
        };
        let find = |r: &str| program.routines.iter().find(|x| x.name.value.eq_ignore_ascii_case(r));
        let Some(main_routine) = find(&main.value) else {
            return Err(self.l5x_err(
                main.span.clone(),
                &item("MainRoutineName"),
                format!("program {name}'s main routine {} is not in the export", main.value),
            ));
        };
        if !l5x::runs(&main_routine.kind.value) {
            let what = format!("{name}/{}", main_routine.name.value);
            if self.skips(&what) || self.skips(name) {
                self.note(
                    &main_routine.kind.span,
                    format!(
                        "program {name} skipped (not_simulated): its main routine is {}",
                        main_routine.kind.value
                    ),
                );
                return Ok(());
            }
            return Err(self.l5x_err(
                main_routine.kind.span.clone(),
                &item("MainRoutineName"),
                format!(
                    "program {name}'s main routine {} is {}, which the twin does not simulate; name \"{what}\" in [controller] not_simulated to run without it",
                    main_routine.name.value, main_routine.kind.value
                ),
            ));
        }
        let _ = field;
        self.header(header, &program.name.span, item("Name"));
        self.line("name", &quote(name), &program.name.span, &item("Name"));
        let path = |r: &l5x::Routine| {
            let ext = if r.kind.value == "RLL" { "rll" } else { "st" };
            format!("routines/{name}/{}.{ext}", r.name.value)
        };
        let main_path = path(main_routine);
        self.add_routine(program, main_routine, &main_path);
        self.line("main", &quote(&main_path), &main.span, &item("MainRoutineName"));
        let others: Vec<&l5x::Routine> = program
            .routines
            .iter()
            .filter(|r| l5x::runs(&r.kind.value) && !r.name.value.eq_ignore_ascii_case(&main_routine.name.value))
            .collect();
        if !others.is_empty() {
            let mut list = Vec::new();
            for r in &others {
                let p = path(r);
                self.add_routine(program, r, &p);
                list.push(quote(&p));
            }
            self.line(
                "routines",
                &format!("[{}]", list.join(", ")),
                &others[0].name.span,
                &item("Routines"),
            );
        }
        if let Some(f) = &program.fault {
            match find(&f.value) {
                Some(r) if l5x::runs(&r.kind.value) => self.line(
                    "fault_routine",
                    &quote(&r.name.value),
                    &f.span,
                    &item("FaultRoutineName"),
                ),
                Some(r) => {
                    let what = format!("{name}/{}", r.name.value);
                    if !self.skips(&what) {
                        return Err(self.l5x_err(f.span.clone(), &item("FaultRoutineName"), format!("program {name}'s fault routine {} is {}, which the twin does not simulate; name \"{what}\" in [controller] not_simulated to run without it", r.name.value, r.kind.value)));
                    }
                }
                None => {
                    return Err(self.l5x_err(
                        f.span.clone(),
                        &item("FaultRoutineName"),
                        format!("program {name}'s fault routine {} is not in the export", f.value),
                    ));
                }
            }
        }
        if program.disabled {
            self.line("disabled", "true", &program.name.span, &item("Disabled"));
        }
        for tag in &program.tags {
            self.tag(tag, Some(program), tags_header)?;
        }
        self.aliases(
            &program.tags,
            Some(program),
            &tags_header.replace("tags]]", "aliases]]"),
        )?;
        Ok(())
    }

    /// `add_on_instructions`: each of the project's definitions as an
    /// export of its own, `aoi/<Name>.L5X` (what `twin import` writes, and
    /// what Studio 5000 imports).
    fn aoi_files(&mut self, doc: &DeTable<'_>) -> Result<(), Fail> {
        let project = self.project;
        if project.aois.is_empty() {
            return Ok(());
        }
        if let Some(v) = get(doc, "add_on_instructions") {
            let (span, _) = key_span(doc, "add_on_instructions").unwrap_or((v.span(), v.span()));
            return Err(self.scene_err(
                span,
                "add_on_instructions",
                format!(
                    "the export's Add-On Instructions are the program's: change them in {}",
                    self.l5x_name
                ),
            ));
        }
        let text = Arc::clone(&self.files.get(self.l5x_file).text);
        let mut list = Vec::new();
        for a in &project.aois {
            let name = &a.name.value;
            let head = format!(
                "<?xml version=\"1.0\" encoding=\"UTF-8\" standalone=\"yes\"?>\r\n<RSLogix5000Content SchemaRevision=\"1.0\" TargetName=\"{name}\" TargetType=\"AddOnInstructionDefinition\" ContainsContext=\"true\">\r\n<Controller Use=\"Context\" Name=\"{}\">\r\n<AddOnInstructionDefinitions Use=\"Context\">\r\n",
                self.project.controller
            );
            let tail = "\r\n</AddOnInstructionDefinitions>\r\n</Controller>\r\n</RSLogix5000Content>\r\n";
            let body = &text[a.span.clone()];
            // Studio marks the exported definition Use="Target".
            let start_tag = &body[..body.find('>').unwrap_or(body.len())];
            let body = if start_tag.contains(" Use=") {
                body.to_owned()
            } else {
                body.replacen(
                    "<AddOnInstructionDefinition ",
                    "<AddOnInstructionDefinition Use=\"Target\" ",
                    1,
                )
            };
            let inserted = body.len() - (a.span.end - a.span.start);
            let mut map: Vec<u32> = Vec::with_capacity(head.len() + body.len() + tail.len() + 1);
            map.extend(std::iter::repeat_n(a.span.start as u32, head.len()));
            let open = "<AddOnInstructionDefinition ".len();
            map.extend((0..body.len()).map(|i| {
                let original = if i < open {
                    i
                } else if i < open + inserted {
                    open
                } else {
                    i - inserted
                };
                (a.span.start + original) as u32
            }));
            map.extend(std::iter::repeat_n(a.span.end as u32, tail.len() + 1));
            let path = format!("aoi/{name}.L5X");
            list.push(quote(&path));
            self.aois.push((
                PathBuf::from(path),
                VirtualRoutine {
                    text: format!("{head}{body}{tail}").into(),
                    map: map.into(),
                    name: name.clone(),
                },
            ));
        }
        let item = format!("{} Name", project.aois[0].name.value);
        self.line(
            "add_on_instructions",
            &format!("[{}]", list.join(", ")),
            &project.aois[0].name.span,
            &item,
        );
        Ok(())
    }

    fn add_routine(&mut self, program: &l5x::Program, r: &l5x::Routine, path: &str) {
        let Some((text, map)) = &r.text else { return };
        self.routines.insert(
            PathBuf::from(path),
            VirtualRoutine {
                text: Arc::clone(text),
                map: Arc::clone(map),
                name: format!("{}/{}", program.name.value, r.name.value),
            },
        );
    }
}

/// Whether `ty` is an instruction's structure the twin lays out itself.
fn is_instruction_structure(ty: &str) -> bool {
    BaseType::parse(ty).is_some_and(|b| b.is_instruction_structure() || matches!(b, BaseType::FunctionBlock(_)))
}

/// Whether an exported structure value sets anything but `EnableIn`.
fn has_settings(v: &Value) -> bool {
    match v {
        Value::Bool(b) => *b,
        Value::Int(i) => *i != 0,
        Value::Float(f) => *f != 0.0,
        Value::Str(s) => !s.is_empty(),
        Value::Array(items) => items.iter().any(has_settings),
        Value::Struct(members) => members
            .iter()
            .any(|(n, v)| !n.eq_ignore_ascii_case("EnableIn") && has_settings(v)),
    }
}

/// A module-defined type's name as a scene data type's: `:` becomes `_`
/// (`AB:1756_DI:I:0` → `AB_1756_DI_I_0`).
fn io_type_name(data_type: &str) -> String {
    data_type
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() || c == '_' { c } else { '_' })
        .collect()
}

/// A PositionUnits text as a scene unit word.
fn unit_word(units: &str) -> Option<&'static str> {
    match units.trim().to_ascii_lowercase().as_str() {
        "deg" | "degree" | "degrees" => Some("deg"),
        "rad" | "radian" | "radians" => Some("rad"),
        "mm" | "millimeter" | "millimeters" | "millimetre" | "millimetres" => Some("mm"),
        "m" | "meter" | "meters" | "metre" | "metres" => Some("m"),
        _ => None,
    }
}

/// A float as TOML writes it (always with a `.` or an exponent).
fn float(v: f64) -> String {
    if v.is_nan() {
        return "nan".to_owned();
    }
    if v.is_infinite() {
        return if v > 0.0 { "inf".to_owned() } else { "-inf".to_owned() };
    }
    let s = format!("{v:?}");
    if s.contains(['.', 'e', 'E']) {
        s
    } else {
        format!("{s}.0")
    }
}

/// A TOML basic string.
fn quote(s: &str) -> String {
    let mut out = String::with_capacity(s.len() + 2);
    out.push('"');
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\r' => out.push_str("\\r"),
            '\t' => out.push_str("\\t"),
            c if c.is_control() => {
                let _ = write!(out, "\\u{:04X}", c as u32);
            }
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

/// A TOML key: bare when it can be.
fn key(s: &str) -> String {
    if !s.is_empty() && s.chars().all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-') {
        s.to_owned()
    } else {
        quote(s)
    }
}
