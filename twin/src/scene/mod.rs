//! Scene files: the TOML description of one twin run (robot, axes, cameras,
//! obstacles, tags and the timed program of instruction calls).
//!
//! [`load`] reads a file, deserializes it (unknown fields are errors),
//! parses every `call`, `when`, trace tag and routine with [`crate::st`]
//! (their names and operands are the program stage's to check), and checks
//! everything that does not need the URDF: numeric ranges, unique names,
//! that the URDF, mesh and routine files exist.
//! Checks against the URDF (joint names and types) are the integrator's;
//! [`Scene::invalid`] builds errors for them with the same file:line:column
//! shape.
//!
//! Every [`SceneError`] displays as one line
//! `FILE:LINE:COLUMN: FIELD: what is wrong`, with 1-based line and column
//! (in characters) pointing into the scene file, also inside `call` strings;
//! [`SceneError::diagnostic`] adds the line with a caret under the value.
//! The format is documented field by field in `scenes/README.md`.
//!
//! Choices the specs leave open:
//! * Names of axes and tags share one namespace and are compared
//!   case-insensitively, as Logix and IEC 61131-3 do.
//!
//! The stage is split the way the data goes through it: `raw` (serde,
//! with spans) → `context` (file:line:column errors and single-value
//! checks) → `validate`, `tags`, `program`, `geometry`, `collision` (one
//! part of the file each) → `model` (the validated [`Scene`]).

use std::path::Path;

mod context;
mod error;
mod model;
mod raw;
mod shape;

pub mod aoi;
mod cell;
mod cell_model;
mod collision;
mod data_types;
mod expect;
mod geometry;
pub mod import;
mod nesting;
mod program;
mod tags;
mod tasks;
mod validate;

pub use cell_model::{
    Cell, Conveyor, ConveyorDrive, Cylinder, Detect, DeviceFault, FaultKind, Gripper, GripperKind, IoDirection, IoKind,
    IoTag, Jitter, MAX_LIVE_PARTS, PartType, Sensor, SensorKind, Sink, SinkOutcome, Source, SourceTrigger, Vfd,
    VisionSpec,
};
pub use error::{Problem, SceneError};
pub use geometry::GEOMETRY_TYPES;
pub use model::{
    Alias, AllowedPair, AoiDef, AoiParam, AoiUsage, Axis, AxisKind, BaseType, CONTINUOUS_PRIORITY, CamPoint, Camera,
    CollisionSettings, Condition, Connection, ControllerSettings, CoordinateSystemSettings, DEFAULT_PHYSICS_SUBSTEPS,
    DEFAULT_START_TIME_US, DEFAULT_STATEMENT_US, DEFAULT_WATCHDOG_MS, DataTypeDef, Dialect, EventTrigger, ExpectKind,
    Expectation, FunctionBlock, GeometrySettings, L5xImport, Location, MAX_ARRAY_LEN, MAX_AXIS_ACCELERATION,
    MAX_AXIS_JERK, MAX_AXIS_SPEED, MAX_CAM_ARRAY_LEN, MAX_DRIVE_TORQUE, MAX_DURATION_S, MAX_FEEDFORWARD_PCT,
    MAX_IMAGE_PX, MAX_LENGTH_M, MAX_LOOP_BANDWIDTH_STEP, MAX_MESH_SCALE, MAX_PHYSICS_SUBSTEPS, MAX_PROGRAMS_PER_TASK,
    MAX_STRING_LENGTH, MAX_TASKS, MIN_PHYSICS_STEP_MS, MIN_STATEMENT_US, MemberDef, MeshApproximation, MotorGains,
    Obstacle, PlantMode, Preflight, ProgramDef, RUN_EXIT_CODES, Reaction, Robot, RoutineDef, STRING_LENGTH,
    STRING_TYPE, Scene, SegmentType, ServoGains, Shape, Snapshots, Step, Tag, TagType, TagValue, Task, TaskKind,
    TestSettings, Tool, TraceRung, TraceTag, Trigger, Units, Usage, UserType, Variant,
};

use crate::source::Files;
use context::Ctx;
use raw::RawScene;

impl Scene {
    /// Builds a [`SceneError::Invalid`] pointing into this scene's file, for
    /// checks done after loading (e.g. against the URDF).
    #[must_use]
    pub fn invalid(&self, at: Location, field: impl Into<String>, problem: Problem) -> SceneError {
        let file = self.files.get(crate::source::FileId::default());
        SceneError::Invalid {
            file: self.path.clone(),
            line: at.line,
            column: at.column,
            field: field.into(),
            problem: Box::new(problem),
            at: Some(Box::new((
                std::sync::Arc::clone(file),
                file.token_at(at.line, at.column),
            ))),
        }
    }

    /// The axis called `name` (case-insensitive).
    #[must_use]
    pub fn axis(&self, name: &str) -> Option<&Axis> {
        self.axes.iter().find(|a| a.name.eq_ignore_ascii_case(name))
    }

    /// The scene as its variant `name` runs it: the variant's initial tag
    /// values, duration, plant and expected exit code, and its
    /// expectations after the scene's. `None` when there is no such
    /// variant.
    #[must_use]
    pub fn with_variant(&self, name: &str) -> Option<Scene> {
        let v = self.variants.iter().find(|v| v.name == name)?;
        let mut scene = self.clone();
        for (tag, value) in &v.tags {
            let slot = match tag.split_once('.') {
                _ if scene.tags.iter().any(|t| t.name.eq_ignore_ascii_case(tag)) => {
                    scene.tags.iter_mut().find(|t| t.name.eq_ignore_ascii_case(tag))
                }
                Some((program, short)) => scene
                    .tasks
                    .iter_mut()
                    .flat_map(|t| &mut t.programs)
                    .find(|p| p.name.eq_ignore_ascii_case(program))
                    .and_then(|p| p.tags.iter_mut().find(|t| t.name.eq_ignore_ascii_case(short))),
                None => None,
            };
            // The load checked that each names a declared tag.
            if let Some(t) = slot {
                t.value = Some(value.clone());
            }
        }
        if let Some(d) = v.duration_s {
            scene.duration_s = d;
        }
        if let Some(p) = v.plant {
            scene.plant = p;
        }
        if let Some(c) = v.exit_code {
            scene.test.exit_code = c;
        }
        scene.expectations.extend(v.expectations.iter().cloned());
        scene.variant = Some(v.name.clone());
        Some(scene)
    }

    /// The tag called `name` (case-insensitive).
    #[must_use]
    pub fn tag(&self, name: &str) -> Option<&Tag> {
        self.tags.iter().find(|t| t.name.eq_ignore_ascii_case(name))
    }
}

/// Reads, parses and validates a scene file.
///
/// # Errors
/// [`SceneError::Read`] if the file cannot be read; otherwise the first
/// problem found, as [`SceneError::Toml`], [`SceneError::Syntax`] or
/// [`SceneError::Invalid`], naming the file, line, column and field.
pub fn load(path: &Path) -> Result<Scene, SceneError> {
    let bytes =
        crate::source::read_bounded(path, crate::source::InputKind::Scene).map_err(|source| SceneError::Read {
            path: path.to_owned(),
            source,
        })?;
    let text = std::str::from_utf8(&bytes).map_err(|e| {
        // The valid part is text: count its lines and the last one's characters.
        let valid = String::from_utf8_lossy(&bytes[..e.valid_up_to()]);
        let line_start = valid.rfind('\n').map_or(0, |i| i + 1);
        SceneError::NotUtf8 {
            path: path.to_owned(),
            line: valid.matches('\n').count() + 1,
            column: valid[line_start..].chars().count() + 1,
        }
    })?;
    parse(path, text)
}

/// Parses and validates scene text as if read from `path` (which names the
/// file in errors and anchors relative paths; the URDF and mesh files must
/// exist relative to it).
///
/// # Errors
/// As [`load`], without [`SceneError::Read`].
pub fn parse(path: &Path, text: &str) -> Result<Scene, SceneError> {
    parse_with_l5x(path, text, None)
}

/// As [`parse`], with the text of the Studio 5000 export the scene names
/// (`[controller] l5x`) given instead of read from its file.
///
/// # Errors
/// As [`parse`].
pub fn parse_with_l5x(path: &Path, text: &str, l5x: Option<&str>) -> Result<Scene, SceneError> {
    let mut files = Files::default();
    let scene_file = files.add(path, text);
    if let Some(at) = nesting::too_deep(text) {
        let file = files.get(scene_file);
        let d = crate::source::Diagnostic::error(format!(
            "tables and arrays nested deeper than {} levels (brackets, braces and the dots of keys)",
            nesting::MAX_TOML_NESTING
        ))
        .with_label(crate::source::Label::new(
            file,
            at..at + 1,
            "this one opens the next level",
        ))
        .with_help("a bracket or brace is probably not closed");
        return Err(SceneError::Syntax(Box::new(d)));
    }
    let mut expanded = import::expand(path, text, &mut files, l5x).map_err(SceneError::Syntax)?;
    // The expanded text once, shared by the loader and `twin import`.
    let expanded_text: Option<std::sync::Arc<str>> = expanded.as_mut().map(|e| std::mem::take(&mut e.text).into());
    let l5x = expanded
        .as_ref()
        .zip(expanded_text.as_ref())
        .map(|(e, text)| L5xImport {
            path: e.l5x_path.clone(),
            report: e.report.iter().map(|r| (r.line, r.text.clone())).collect(),
            skipped: e.skipped.clone(),
            expanded: std::sync::Arc::clone(text),
            routines: {
                let mut r: Vec<(std::path::PathBuf, std::sync::Arc<str>)> = e
                    .routines
                    .iter()
                    .chain(e.aois.iter().map(|(p, v)| (p, v)))
                    .map(|(p, v)| (p.clone(), std::sync::Arc::clone(&v.text)))
                    .collect();
                r.sort();
                r
            },
        });
    let text = expanded_text.as_deref().unwrap_or(text);
    let parsed = expanded
        .as_ref()
        .map(|e| tasks::parse_embedded(e, &files))
        .unwrap_or_default();
    let ctx = Ctx {
        file: path.to_owned(),
        text,
        files: std::cell::RefCell::new(files),
        scene_file,
        data_types: std::cell::RefCell::new(vec![model::DataTypeDef::string()]),
        expanded,
        l5x,
        parsed: std::cell::RefCell::new(parsed),
    };
    let raw: RawScene = toml::from_str(text).map_err(|e| ctx.toml_error(&e))?;
    ctx.validate(raw, path)
}

#[cfg(test)]
mod tests;
