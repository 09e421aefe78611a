//! Scene files: the TOML description of one twin run (robot, axes, cameras,
//! obstacles, tags and the timed program of instruction calls).
//!
//! [`load`] reads a file, deserializes it (unknown fields are errors),
//! parses every `call` and `when` with [`crate::st`], and checks everything
//! that does not need the URDF: numeric ranges, unique names, that every
//! tag a call refers to is declared, that the URDF and mesh files exist.
//! Checks against the URDF (joint names and types) are the integrator's;
//! [`Scene::invalid`] builds errors for them with the same file:line:column
//! shape.
//!
//! Every [`SceneError`] displays as one line
//! `FILE:LINE:COLUMN: FIELD: what is wrong`, with 1-based line and column
//! (in characters) pointing into the scene file, also inside `call` strings.
//! The format is documented field by field in `scenes/README.md`.
//!
//! Choices the specs leave open:
//! * Names of axes and tags share one namespace and are compared
//!   case-insensitively, as Logix and IEC 61131-3 do.
//! * A positional call's name must be a Logix motion instruction
//!   ([`crate::st::LOGIX_INSTRUCTIONS`]); its bare-word operands must be a
//!   declared tag/axis or a known enumeration word
//!   ([`crate::st::LOGIX_ENUMERATIONS`]).
//! * A named call's name must be a tag of a function-block type; its
//!   bare-word inputs must be a tag/axis or a PLCopen enumeration value.

use std::collections::{BTreeMap, HashMap};
use std::fmt;
use std::ops::Range;
use std::path::{Path, PathBuf};

use serde::Deserialize;
use toml::Spanned;

mod geometry;
pub use geometry::{GEOMETRY_TYPES, GeometrySettings};

use crate::st::{self, Args, Call, Expr, ParseError};

mod collision;
pub use collision::{AllowedPair, CollisionSettings, MeshApproximation, Preflight, Reaction, Tool};

// ------------------------------------------------------------------ public model

/// A 1-based line and column (in characters) in the scene file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct Location {
    /// 1-based line.
    pub line: usize,
    /// 1-based column, counted in characters.
    pub column: usize,
}

/// A validated scene.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct Scene {
    /// Scene name (default: the file stem).
    pub name: String,
    /// The scene file as given to [`load`].
    pub path: PathBuf,
    /// Simulated run time, seconds (> 0).
    pub duration_s: f64,
    /// Planner coarse update period, milliseconds (1..=32).
    pub coarse_update_ms: f64,
    /// Physics step, milliseconds; divides `coarse_update_ms` exactly.
    pub physics_step_ms: f64,
    /// The robot model.
    pub robot: Robot,
    /// Axes, in file order.
    pub axes: Vec<Axis>,
    /// Cameras, in file order.
    pub cameras: Vec<Camera>,
    /// Static obstacles, in file order.
    pub obstacles: Vec<Obstacle>,
    /// Declared tags, in file order.
    pub tags: Vec<Tag>,
    /// Program steps, in file order.
    pub program: Vec<Step>,
    /// Golden-image frames, if any.
    pub snapshots: Option<Snapshots>,
    /// Collision checking (`[collision]`); off when the table is absent.
    pub collision: Option<CollisionSettings>,
}

/// `[robot]`.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct Robot {
    /// The URDF file, resolved relative to the scene file's folder.
    pub urdf: PathBuf,
    /// Where `robot.urdf` is written.
    pub urdf_location: Location,
    /// Initial joint positions, joint name -> SI position (rad or m).
    pub initial_joints: BTreeMap<String, f64>,
    /// Where each `initial_joints` entry's value is written.
    pub initial_joint_locations: BTreeMap<String, Location>,
}

/// Whether an axis turns or slides.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Deserialize)]
#[serde(rename_all = "lowercase")]
#[non_exhaustive]
pub enum AxisKind {
    /// A prismatic joint; units `m` or `mm`.
    Linear,
    /// A revolute or continuous joint; units `deg` or `rad`.
    Rotary,
}

impl fmt::Display for AxisKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            AxisKind::Linear => "linear",
            AxisKind::Rotary => "rotary",
        })
    }
}

/// Axis position units (the program's "axis units").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Deserialize)]
#[serde(rename_all = "lowercase")]
#[non_exhaustive]
pub enum Units {
    /// Degrees (rotary).
    Deg,
    /// Radians (rotary).
    Rad,
    /// Metres (linear).
    M,
    /// Millimetres (linear).
    Mm,
}

impl Units {
    /// SI units (rad or m) per axis unit.
    #[must_use]
    pub fn si_per_unit(self) -> f64 {
        match self {
            Units::Deg => std::f64::consts::PI / 180.0,
            Units::Rad | Units::M => 1.0,
            Units::Mm => 1.0e-3,
        }
    }

    /// Whether these units fit an axis of `kind`.
    #[must_use]
    pub fn fits(self, kind: AxisKind) -> bool {
        matches!(
            (self, kind),
            (Units::Deg | Units::Rad, AxisKind::Rotary) | (Units::M | Units::Mm, AxisKind::Linear)
        )
    }
}

impl fmt::Display for Units {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Units::Deg => "deg",
            Units::Rad => "rad",
            Units::M => "m",
            Units::Mm => "mm",
        })
    }
}

/// Position-motor gains of the joint an axis drives (rapier's
/// `motor_position(target, stiffness, damping)`).
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MotorGains {
    /// Stiffness, N·m/rad (rotary) or N/m (linear) (default: 1.0e4).
    #[serde(default = "MotorGains::default_stiffness")]
    pub stiffness: f64,
    /// Damping, N·m·s/rad (rotary) or N·s/m (linear) (default: 2.0e2).
    #[serde(default = "MotorGains::default_damping")]
    pub damping: f64,
}

impl MotorGains {
    fn default_stiffness() -> f64 {
        1.0e4
    }
    fn default_damping() -> f64 {
        2.0e2
    }
}

impl Default for MotorGains {
    fn default() -> Self {
        Self {
            stiffness: Self::default_stiffness(),
            damping: Self::default_damping(),
        }
    }
}

/// `[[axes]]`: one axis of the motion program, driving one URDF joint, or a
/// virtual axis (no `joint`) whose actual position is its command position.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct Axis {
    /// Axis tag name used in the program.
    pub name: String,
    /// The URDF joint it drives; `None` for a virtual axis (the Logix
    /// virtual axes of a Cartesian coordinate system under MCT).
    pub joint: Option<String>,
    /// Where `joint` is written (the axis' `name` for a virtual axis).
    pub joint_location: Location,
    /// Linear or rotary.
    pub kind: AxisKind,
    /// Modulo period in axis units, for modulo axes.
    pub modulo_period: Option<f64>,
    /// Axis position units.
    pub units: Units,
    /// Axis units / s (> 0).
    pub max_velocity: f64,
    /// Axis units / s² (> 0).
    pub max_acceleration: f64,
    /// Axis units / s² (> 0).
    pub max_deceleration: f64,
    /// Axis units / s³ (> 0).
    pub max_jerk: f64,
    /// Axis units (> 0).
    pub in_position_window: f64,
    /// PLCopen "Target Position Monitoring" (default: true).
    pub target_position_monitoring: bool,
    /// Axis units (≥ 0, default: 0).
    pub modulo_tolerance_window: f64,
    /// Initial position, axis units (default: 0, or from `robot.initial_joints`).
    pub initial_position: f64,
    /// Soft travel limits `(min, max)`, axis units (default: none here; the
    /// run then takes the joint's URDF `<limit>` — see `run::limits`).
    pub soft_travel_limits: Option<(f64, f64)>,
    /// Joint motor gains.
    pub motor: MotorGains,
    /// Where the `[[axes]]` entry's `name` is written.
    pub location: Location,
}

/// `[[cameras]]`: a pinhole camera in the world frame (Z up).
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct Camera {
    /// Camera name (used in snapshot file names).
    pub name: String,
    /// Eye position in the world, metres.
    pub position_m: [f64; 3],
    /// Look-at point in the world, metres.
    pub target_m: [f64; 3],
    /// Vertical field of view, degrees (0 < fov < 180).
    pub fov_deg: f64,
    /// Image width, pixels (> 0).
    pub width: u32,
    /// Image height, pixels (> 0).
    pub height: u32,
    /// Frames per simulated second (> 0).
    pub fps: f64,
    /// Where the entry's `name` is written.
    pub location: Location,
}

/// The geometry of an obstacle, metres.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum Shape {
    /// Axis-aligned box (in the obstacle frame) with full edge lengths.
    Box {
        /// Full size along x, y, z, metres.
        size_m: [f64; 3],
    },
    /// Cylinder along the obstacle frame's z axis.
    Cylinder {
        /// Radius, metres.
        radius_m: f64,
        /// Full length, metres.
        length_m: f64,
    },
    /// Sphere.
    Sphere {
        /// Radius, metres.
        radius_m: f64,
    },
    /// A mesh file (resolved relative to the scene file), scaled per axis.
    Mesh {
        /// The mesh file.
        path: PathBuf,
        /// Scale factors along x, y, z.
        scale: [f64; 3],
    },
}

/// `[[obstacles]]`: a fixed body in the world.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct Obstacle {
    /// Obstacle name.
    pub name: String,
    /// Geometry.
    pub shape: Shape,
    /// Position of the obstacle frame in the world, metres.
    pub position_m: [f64; 3],
    /// Roll, pitch, yaw of the obstacle frame, degrees (default: zeros).
    pub rpy_deg: [f64; 3],
    /// RGBA colour, each in 0..=1 (default: [0.6, 0.6, 0.6, 1.0]).
    pub color: [f64; 4],
    /// Where the entry's `name` is written.
    pub location: Location,
}

/// PLCopen (Tc2_MC2) function blocks a tag can be an instance of.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum FunctionBlock {
    /// `MC_Power`.
    Power,
    /// `MC_Reset`.
    Reset,
    /// `MC_Home`.
    Home,
    /// `MC_Stop`.
    Stop,
    /// `MC_Halt`.
    Halt,
    /// `MC_MoveAbsolute`.
    MoveAbsolute,
    /// `MC_MoveRelative`.
    MoveRelative,
    /// `MC_MoveAdditive`.
    MoveAdditive,
    /// `MC_MoveModulo`.
    MoveModulo,
    /// `MC_MoveVelocity`.
    MoveVelocity,
}

impl FunctionBlock {
    /// All function blocks.
    pub const ALL: [FunctionBlock; 10] = [
        FunctionBlock::Power,
        FunctionBlock::Reset,
        FunctionBlock::Home,
        FunctionBlock::Stop,
        FunctionBlock::Halt,
        FunctionBlock::MoveAbsolute,
        FunctionBlock::MoveRelative,
        FunctionBlock::MoveAdditive,
        FunctionBlock::MoveModulo,
        FunctionBlock::MoveVelocity,
    ];

    /// The block's name as written in a scene (`MC_MoveModulo`).
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            FunctionBlock::Power => "MC_Power",
            FunctionBlock::Reset => "MC_Reset",
            FunctionBlock::Home => "MC_Home",
            FunctionBlock::Stop => "MC_Stop",
            FunctionBlock::Halt => "MC_Halt",
            FunctionBlock::MoveAbsolute => "MC_MoveAbsolute",
            FunctionBlock::MoveRelative => "MC_MoveRelative",
            FunctionBlock::MoveAdditive => "MC_MoveAdditive",
            FunctionBlock::MoveModulo => "MC_MoveModulo",
            FunctionBlock::MoveVelocity => "MC_MoveVelocity",
        }
    }
}

/// The element type of a tag.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum BaseType {
    /// `BOOL`.
    Bool,
    /// `SINT` (8-bit).
    Sint,
    /// `INT` (16-bit).
    Int,
    /// `DINT` (32-bit).
    Dint,
    /// `UDINT` (unsigned 32-bit).
    Udint,
    /// `REAL`.
    Real,
    /// `LREAL`.
    Lreal,
    /// `MOTION_INSTRUCTION` (Logix control structure: .EN, .DN, .ER, .IP, .PC ...).
    MotionInstruction,
    /// `COORDINATE_SYSTEM`; its value lists the member axes.
    CoordinateSystem,
    /// `CAM` (one cam point: master, slave, segment type).
    Cam,
    /// `CAM_PROFILE` (filled by MCCP).
    CamProfile,
    /// A PLCopen function-block instance.
    FunctionBlock(FunctionBlock),
}

impl BaseType {
    const NAMED: [(&'static str, BaseType); 11] = [
        ("BOOL", BaseType::Bool),
        ("SINT", BaseType::Sint),
        ("INT", BaseType::Int),
        ("DINT", BaseType::Dint),
        ("UDINT", BaseType::Udint),
        ("REAL", BaseType::Real),
        ("LREAL", BaseType::Lreal),
        ("MOTION_INSTRUCTION", BaseType::MotionInstruction),
        ("COORDINATE_SYSTEM", BaseType::CoordinateSystem),
        ("CAM", BaseType::Cam),
        ("CAM_PROFILE", BaseType::CamProfile),
    ];

    /// The type name as written in a scene.
    #[must_use]
    pub fn name(self) -> &'static str {
        if let BaseType::FunctionBlock(fb) = self {
            return fb.name();
        }
        Self::NAMED.iter().find(|(_, t)| *t == self).map_or("?", |(n, _)| n)
    }

    /// Parses a type name, case-insensitively.
    #[must_use]
    pub fn parse(name: &str) -> Option<BaseType> {
        Self::NAMED
            .iter()
            .find(|(n, _)| n.eq_ignore_ascii_case(name))
            .map(|(_, t)| *t)
            .or_else(|| {
                FunctionBlock::ALL
                    .into_iter()
                    .find(|fb| fb.name().eq_ignore_ascii_case(name))
                    .map(BaseType::FunctionBlock)
            })
    }

    /// Every accepted type name, for error messages and docs.
    #[must_use]
    pub fn all_names() -> Vec<&'static str> {
        Self::NAMED
            .iter()
            .map(|(n, _)| *n)
            .chain(FunctionBlock::ALL.iter().map(|fb| fb.name()))
            .collect()
    }

    fn integer_range(self) -> Option<(i64, i64)> {
        match self {
            BaseType::Sint => Some((i8::MIN.into(), i8::MAX.into())),
            BaseType::Int => Some((i16::MIN.into(), i16::MAX.into())),
            BaseType::Dint => Some((i32::MIN.into(), i32::MAX.into())),
            BaseType::Udint => Some((0, u32::MAX.into())),
            _ => None,
        }
    }
}

/// A tag's type: an element type, optionally an array `TYPE[N]`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct TagType {
    /// Element type.
    pub base: BaseType,
    /// `Some(N)` for arrays of N (> 0) elements.
    pub array_len: Option<usize>,
}

impl fmt::Display for TagType {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.array_len {
            Some(n) => write!(f, "{}[{n}]", self.base.name()),
            None => f.write_str(self.base.name()),
        }
    }
}

/// Cam segment interpolation (Logix `CAM.SegmentType`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Deserialize)]
#[serde(rename_all = "lowercase")]
#[non_exhaustive]
pub enum SegmentType {
    /// 0 = linear.
    Linear,
    /// 1 = cubic.
    Cubic,
}

/// One cam point (Logix `CAM` element).
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CamPoint {
    /// Master position, master axis units.
    pub master: f64,
    /// Slave position, slave axis units.
    pub slave: f64,
    /// Interpolation of the segment that starts here (default: cubic).
    #[serde(default = "CamPoint::default_segment")]
    pub segment_type: SegmentType,
}

impl CamPoint {
    fn default_segment() -> SegmentType {
        SegmentType::Cubic
    }
}

/// A tag's initial value, already checked against its type.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum TagValue {
    /// `BOOL`.
    Bool(bool),
    /// `SINT`, `INT`, `DINT`, `UDINT` (within the type's range).
    Integer(i64),
    /// `REAL`, `LREAL`.
    Real(f64),
    /// Arrays of the above, exactly N elements.
    Array(Vec<TagValue>),
    /// `CAM[N]`: up to N points with strictly increasing master positions.
    CamPoints(Vec<CamPoint>),
    /// `COORDINATE_SYSTEM`: the member axis names (1 to 6, declared, distinct).
    Axes(Vec<String>),
}

/// `[[tags]]`: a tag the program refers to.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct Tag {
    /// Tag name.
    pub name: String,
    /// Tag type.
    pub ty: TagType,
    /// Initial value (required for `COORDINATE_SYSTEM`; not allowed for
    /// `MOTION_INSTRUCTION`, `CAM_PROFILE` and function blocks).
    pub value: Option<TagValue>,
    /// `COORDINATE_SYSTEM` tags: the system's dynamics, tolerances and tool
    /// link (`None` for other tags; the defaults when the table is absent).
    pub coordinate_system: Option<CoordinateSystemSettings>,
    /// `COORDINATE_SYSTEM` tags: the MCT geometry of a robot's joint system
    /// and its URDF mapping (`None` when the `geometry` table is absent).
    pub geometry: Option<GeometrySettings>,
    /// Where the entry's `name` is written.
    pub location: Location,
}

/// The `coordinate_system` table of a `COORDINATE_SYSTEM` tag (its
/// properties dialog): rates in the member axes' units.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct CoordinateSystemSettings {
    /// Primary (Cartesian) axes: the first `primary_axes` members (default:
    /// the member count, at most 3).
    pub primary_axes: usize,
    /// Maximum vector speed, units/s (default 1).
    pub max_speed: f64,
    /// Maximum vector acceleration, units/s² (default 10).
    pub max_accel: f64,
    /// Maximum vector deceleration, units/s² (default 10; 0 makes moves
    /// fail with error 54, as on the controller).
    pub max_decel: f64,
    /// Maximum accel jerk, units/s³ (default 100).
    pub max_accel_jerk: f64,
    /// Maximum decel jerk, units/s³ (default 100).
    pub max_decel_jerk: f64,
    /// Command tolerance, units (default 0.1).
    pub command_tolerance: f64,
    /// Actual tolerance, units (default 0.01).
    pub actual_tolerance: f64,
    /// URDF link whose origin is the tool centre: its path is drawn as a
    /// trail and its world position traced (default: none).
    pub tool_link: Option<String>,
    /// Axis whose command position drives the system's master-driven moves
    /// (the role of an MDCC; default: none).
    pub master_axis: Option<String>,
    /// Where the table is written (or the tag's name when absent).
    pub location: Location,
}

/// What fires a program step.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum Trigger {
    /// At a simulated time.
    At {
        /// Seconds since the start (0 ≤ time ≤ duration).
        time_s: f64,
    },
    /// On the rising edge of a BOOL tag or bit, plus a delay.
    When {
        /// The reference, e.g. `MoveTable.Done`.
        condition: Expr,
        /// Delay after the edge, seconds (≥ 0, default: 0).
        delay_s: f64,
    },
}

/// `[[program]]`: one instruction call and when it fires.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct Step {
    /// When the call fires.
    pub trigger: Trigger,
    /// The parsed call.
    pub call: Call,
    /// The call as written.
    pub call_text: String,
    /// Where the `call` string is written.
    pub location: Location,
}

/// `[snapshots]`: frames compared with golden images.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct Snapshots {
    /// Frame indices, sorted, distinct.
    pub frames: Vec<u32>,
}

// ------------------------------------------------------------------ errors

/// What is wrong with a field's value.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum Problem {
    /// NaN or infinite.
    #[error("must be a finite number, got {value}")]
    NotFinite {
        /// The value.
        value: f64,
    },
    /// Zero or negative where a positive value is needed.
    #[error("must be greater than 0, got {value}")]
    NotPositive {
        /// The value.
        value: f64,
    },
    /// Negative where zero or more is needed.
    #[error("must not be negative, got {value}")]
    Negative {
        /// The value.
        value: f64,
    },
    /// Outside an inclusive (or, when `exclusive`, open) range.
    #[error("must be between {min} and {max}{}, got {value}", if *exclusive { " (exclusive)" } else { "" })]
    OutOfRange {
        /// The value.
        value: f64,
        /// Lower bound.
        min: f64,
        /// Upper bound.
        max: f64,
        /// Whether the bounds themselves are excluded.
        exclusive: bool,
    },
    /// The physics step does not divide the coarse update period.
    #[error("physics_step_ms = {physics_step_ms} does not divide coarse_update_ms = {coarse_update_ms} exactly")]
    StepNotDivisor {
        /// The physics step, ms.
        physics_step_ms: f64,
        /// The coarse update period, ms.
        coarse_update_ms: f64,
    },
    /// A name used twice.
    #[error("duplicate name '{name}' (first declared on line {first_line})")]
    DuplicateName {
        /// The name.
        name: String,
        /// Line of the first declaration.
        first_line: usize,
    },
    /// An empty name.
    #[error("must not be empty")]
    Empty,
    /// Not an ST identifier.
    #[error("'{name}' is not a valid tag name (letters, digits and '_', not starting with a digit)")]
    InvalidName {
        /// The name.
        name: String,
    },
    /// A tag reference that names no tag or axis.
    #[error("unknown tag '{name}': not declared in [[tags]] or [[axes]]")]
    UnknownTag {
        /// The name.
        name: String,
    },
    /// A bare word that is neither a tag/axis nor an enumeration word.
    #[error("unknown tag or enumeration word '{name}'")]
    UnknownOperand {
        /// The word.
        name: String,
    },
    /// A positional call to something that is not a Logix motion instruction.
    #[error(
        "unknown instruction '{name}' (positional calls are Logix motion instructions; function-block instances take named inputs)"
    )]
    UnknownInstruction {
        /// The name.
        name: String,
    },
    /// A named call on something that is not a function-block instance.
    #[error("'{name}' is {kind}, not a function-block instance, so it cannot be called with named inputs")]
    NotCallable {
        /// The name.
        name: String,
        /// What it is (`a REAL tag`, `an axis`).
        kind: String,
    },
    /// An index outside an array tag.
    #[error("index {index} is outside '{name}' (valid: 0..{len})")]
    IndexOutOfBounds {
        /// The array tag.
        name: String,
        /// The index used.
        index: i64,
        /// The array length.
        len: usize,
    },
    /// A referenced file that does not exist.
    #[error("file '{}' does not exist", path.display())]
    MissingFile {
        /// The resolved path.
        path: PathBuf,
    },
    /// A program step with both `at_s` and `when`.
    #[error("has both 'at_s' and 'when'; give exactly one")]
    BothTriggers,
    /// A program step with neither `at_s` nor `when`.
    #[error("has neither 'at_s' nor 'when'; give exactly one")]
    NoTrigger,
    /// `after_s` on a step that is not triggered by `when`.
    #[error("'after_s' applies only to steps triggered by 'when'")]
    AfterWithoutWhen,
    /// `at_s` past the end of the run.
    #[error("at_s = {at_s} is after the end of the run (duration_s = {duration_s})")]
    AfterEnd {
        /// The step time, s.
        at_s: f64,
        /// The run duration, s.
        duration_s: f64,
    },
    /// A tag type not in the known list.
    #[error("unknown tag type '{type_name}', expected one of {}, optionally as an array TYPE[N]", BaseType::all_names().join(", "))]
    UnknownTagType {
        /// The type as written.
        type_name: String,
    },
    /// `TYPE[0]` or a malformed array length.
    #[error("array length in '{type_name}' must be a whole number of at least 1")]
    BadArrayLength {
        /// The type as written.
        type_name: String,
    },
    /// An array of a type that cannot be an array here.
    #[error("{base} cannot be declared as an array")]
    ArrayNotAllowed {
        /// The element type name.
        base: &'static str,
    },
    /// An initial value that does not fit the tag type.
    #[error("value does not fit type {ty}: expected {expected}")]
    ValueMismatch {
        /// The tag type.
        ty: TagType,
        /// What would fit.
        expected: &'static str,
    },
    /// An initial value on a type that takes none.
    #[error("{ty} tags take no initial value")]
    ValueNotAllowed {
        /// The tag type.
        ty: TagType,
    },
    /// A type that needs an initial value.
    #[error("{ty} tags need a value ({expected})")]
    ValueRequired {
        /// The tag type.
        ty: TagType,
        /// What to give.
        expected: &'static str,
    },
    /// A `coordinate_system` or `geometry` table on a tag that is not a
    /// coordinate system.
    #[error("only COORDINATE_SYSTEM tags take coordinate_system and geometry tables")]
    CoordinateSystemOnly,
    /// An unknown MCT geometry type.
    #[error("unknown geometry '{name}', expected one of {expected}")]
    UnknownGeometry {
        /// The name given.
        name: String,
        /// The accepted names.
        expected: String,
    },
    /// A coordinate system naming an undeclared axis.
    #[error("unknown axis '{name}'")]
    UnknownAxis {
        /// The name.
        name: String,
    },
    /// Axis units that do not fit its kind.
    #[error("units '{units}' do not fit a {kind} axis (rotary: deg or rad; linear: m or mm)")]
    UnitsMismatch {
        /// The units.
        units: Units,
        /// The axis kind.
        kind: AxisKind,
    },
    /// `initial_position` disagrees with `robot.initial_joints`.
    #[error(
        "initial_position = {initial_position} {units} disagrees with robot.initial_joints.{joint} = {joint_position_si} (SI)"
    )]
    InitialPositionMismatch {
        /// The axis' initial position, axis units.
        initial_position: f64,
        /// The axis units.
        units: Units,
        /// The joint.
        joint: String,
        /// The joint's initial position, rad or m.
        joint_position_si: f64,
    },
    /// `soft_travel_limits` not ordered `[min, max]` with min < max.
    #[error("soft_travel_limits = [{min}, {max}] must have min < max")]
    SoftTravelLimitsOrder {
        /// The first element.
        min: f64,
        /// The second element.
        max: f64,
    },
    /// `soft_travel_limits` on a modulo axis.
    #[error("soft_travel_limits are not allowed on a modulo axis (modulo_period = {period})")]
    SoftTravelLimitsOnModulo {
        /// The modulo period.
        period: f64,
    },
    /// The initial position outside the soft travel limits.
    #[error("initial position {position} is outside soft_travel_limits = [{min}, {max}]")]
    OutsideSoftTravelLimits {
        /// The initial position, axis units.
        position: f64,
        /// Lower limit.
        min: f64,
        /// Upper limit.
        max: f64,
    },
    /// Two axes driving one joint.
    #[error("joint '{joint}' is already driven by axis '{other_axis}'")]
    SharedJoint {
        /// The joint.
        joint: String,
        /// The first axis driving it.
        other_axis: String,
    },
    /// A shape without one of its parameters.
    #[error("shape '{shape}' needs field '{field}'")]
    MissingShapeField {
        /// The shape kind.
        shape: &'static str,
        /// The missing field.
        field: &'static str,
    },
    /// A parameter of another shape.
    #[error("field '{field}' does not apply to shape '{shape}'")]
    ExtraShapeField {
        /// The shape kind.
        shape: &'static str,
        /// The extra field.
        field: &'static str,
    },
    /// A camera looking at its own position.
    #[error("camera target must differ from its position")]
    DegenerateCamera,
    /// Cam points whose master positions do not increase.
    #[error("cam master positions must increase strictly (point {index})")]
    CamNotIncreasing {
        /// Index of the first offending point.
        index: usize,
    },
    /// Snapshots without any camera.
    #[error("snapshots need at least one [[cameras]] entry")]
    NoCamera,
    /// A snapshot frame listed twice.
    #[error("frame {frame} is listed twice")]
    DuplicateFrame {
        /// The frame.
        frame: u32,
    },
    /// A URDF joint that does not exist (for the integrator's checks).
    #[error("the URDF has no joint '{joint}'")]
    UnknownJoint {
        /// The joint.
        joint: String,
    },
}

/// An error loading a scene. `Display` is one line:
/// `FILE:LINE:COLUMN: FIELD: what is wrong`.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SceneError {
    /// The file could not be read.
    Read {
        /// The scene file.
        path: PathBuf,
        /// The I/O error.
        #[source]
        source: std::io::Error,
    },
    /// TOML syntax, an unknown or missing field, or a value of the wrong type.
    Toml {
        /// The scene file.
        file: PathBuf,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// The table the error is in (`axes[1]`, `robot`), if any.
        table: Option<String>,
        /// The TOML/serde message.
        message: String,
    },
    /// A `call` or `when` string that is not valid Structured Text.
    Syntax {
        /// The scene file.
        file: PathBuf,
        /// 1-based line.
        line: usize,
        /// 1-based column (of the offending character, inside the string).
        column: usize,
        /// The field, e.g. `program[3].call`.
        field: String,
        /// The parse error.
        #[source]
        source: ParseError,
    },
    /// A value that parses but is not allowed.
    Invalid {
        /// The scene file.
        file: PathBuf,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// The field, e.g. `axes[0].max_velocity`.
        field: String,
        /// What is wrong.
        problem: Problem,
    },
}

impl SceneError {
    /// The 1-based line and column, when the error has a place in the file.
    #[must_use]
    pub fn location(&self) -> Option<Location> {
        match self {
            SceneError::Read { .. } => None,
            SceneError::Toml { line, column, .. }
            | SceneError::Syntax { line, column, .. }
            | SceneError::Invalid { line, column, .. } => Some(Location {
                line: *line,
                column: *column,
            }),
        }
    }

    /// The field path, for syntax and validation errors.
    #[must_use]
    pub fn field(&self) -> Option<&str> {
        match self {
            SceneError::Syntax { field, .. } | SceneError::Invalid { field, .. } => Some(field),
            SceneError::Toml { table, .. } => table.as_deref(),
            SceneError::Read { .. } => None,
        }
    }

    /// The validation problem, for [`SceneError::Invalid`].
    #[must_use]
    pub fn problem(&self) -> Option<&Problem> {
        match self {
            SceneError::Invalid { problem, .. } => Some(problem),
            _ => None,
        }
    }
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SceneError::Read { path, source } => write!(f, "{}: cannot read the scene file: {source}", path.display()),
            SceneError::Toml {
                file,
                line,
                column,
                table,
                message,
            } => {
                write!(f, "{}:{line}:{column}: ", file.display())?;
                if let Some(table) = table {
                    write!(f, "in {table}: ")?;
                }
                // serde quotes names with backticks; keep the message on one line.
                f.write_str(&message.trim().replace('`', "'").replace('\n', " "))
            }
            SceneError::Syntax {
                file,
                line,
                column,
                field,
                source,
            } => {
                write!(f, "{}:{line}:{column}: {field}: {source}", file.display())
            }
            SceneError::Invalid {
                file,
                line,
                column,
                field,
                problem,
            } => {
                write!(f, "{}:{line}:{column}: {field}: {problem}", file.display())
            }
        }
    }
}

impl Scene {
    /// Builds a [`SceneError::Invalid`] pointing into this scene's file, for
    /// checks done after loading (e.g. against the URDF).
    #[must_use]
    pub fn invalid(&self, at: Location, field: impl Into<String>, problem: Problem) -> SceneError {
        SceneError::Invalid {
            file: self.path.clone(),
            line: at.line,
            column: at.column,
            field: field.into(),
            problem,
        }
    }

    /// The axis called `name` (case-insensitive).
    #[must_use]
    pub fn axis(&self, name: &str) -> Option<&Axis> {
        self.axes.iter().find(|a| a.name.eq_ignore_ascii_case(name))
    }

    /// The tag called `name` (case-insensitive).
    #[must_use]
    pub fn tag(&self, name: &str) -> Option<&Tag> {
        self.tags.iter().find(|t| t.name.eq_ignore_ascii_case(name))
    }
}

// ------------------------------------------------------------------ raw (serde) layer

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawScene {
    name: Option<Spanned<String>>,
    duration_s: Spanned<f64>,
    coarse_update_ms: Spanned<f64>,
    physics_step_ms: Spanned<f64>,
    robot: RawRobot,
    #[serde(default)]
    axes: Vec<RawAxis>,
    #[serde(default)]
    cameras: Vec<RawCamera>,
    #[serde(default)]
    obstacles: Vec<RawObstacle>,
    #[serde(default)]
    tags: Vec<RawTag>,
    #[serde(default)]
    program: Vec<RawStep>,
    snapshots: Option<RawSnapshots>,
    collision: Option<collision::RawCollision>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawRobot {
    urdf: Spanned<String>,
    #[serde(default)]
    initial_joints: BTreeMap<String, Spanned<f64>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawAxis {
    name: Spanned<String>,
    joint: Option<Spanned<String>>,
    kind: Spanned<AxisKind>,
    modulo_period: Option<Spanned<f64>>,
    units: Spanned<Units>,
    max_velocity: Spanned<f64>,
    max_acceleration: Spanned<f64>,
    max_deceleration: Spanned<f64>,
    max_jerk: Spanned<f64>,
    in_position_window: Spanned<f64>,
    target_position_monitoring: Option<bool>,
    modulo_tolerance_window: Option<Spanned<f64>>,
    initial_position: Option<Spanned<f64>>,
    soft_travel_limits: Option<Spanned<[f64; 2]>>,
    motor: Option<Spanned<MotorGains>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawCamera {
    name: Spanned<String>,
    position: Spanned<[f64; 3]>,
    target: Spanned<[f64; 3]>,
    fov_deg: Spanned<f64>,
    width: Spanned<u32>,
    height: Spanned<u32>,
    fps: Spanned<f64>,
}

#[derive(Deserialize, Clone, Copy, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
enum ShapeKind {
    Box,
    Cylinder,
    Sphere,
    Mesh,
}

impl ShapeKind {
    fn name(self) -> &'static str {
        match self {
            ShapeKind::Box => "box",
            ShapeKind::Cylinder => "cylinder",
            ShapeKind::Sphere => "sphere",
            ShapeKind::Mesh => "mesh",
        }
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawObstacle {
    name: Spanned<String>,
    shape: Spanned<ShapeKind>,
    size: Option<Spanned<[f64; 3]>>,
    radius: Option<Spanned<f64>>,
    length: Option<Spanned<f64>>,
    file: Option<Spanned<String>>,
    scale: Option<Spanned<[f64; 3]>>,
    position: Spanned<[f64; 3]>,
    rpy_deg: Option<Spanned<[f64; 3]>>,
    color: Option<Spanned<[f64; 4]>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawTag {
    name: Spanned<String>,
    #[serde(rename = "type")]
    ty: Spanned<String>,
    value: Option<Spanned<toml::Value>>,
    coordinate_system: Option<Spanned<RawCoordinateSystem>>,
    geometry: Option<Spanned<geometry::RawGeometry>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawCoordinateSystem {
    primary_axes: Option<Spanned<i64>>,
    max_speed: Option<Spanned<f64>>,
    max_accel: Option<Spanned<f64>>,
    max_decel: Option<Spanned<f64>>,
    max_accel_jerk: Option<Spanned<f64>>,
    max_decel_jerk: Option<Spanned<f64>>,
    command_tolerance: Option<Spanned<f64>>,
    actual_tolerance: Option<Spanned<f64>>,
    tool_link: Option<Spanned<String>>,
    master_axis: Option<Spanned<String>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawStep {
    at_s: Option<Spanned<f64>>,
    when: Option<Spanned<String>>,
    after_s: Option<Spanned<f64>>,
    call: Spanned<String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawSnapshots {
    frames: Spanned<Vec<Spanned<u32>>>,
}

// ------------------------------------------------------------------ loading

/// Reads, parses and validates a scene file.
///
/// # Errors
/// [`SceneError::Read`] if the file cannot be read; otherwise the first
/// problem found, as [`SceneError::Toml`], [`SceneError::Syntax`] or
/// [`SceneError::Invalid`], naming the file, line, column and field.
pub fn load(path: &Path) -> Result<Scene, SceneError> {
    let text = std::fs::read_to_string(path).map_err(|source| SceneError::Read {
        path: path.to_owned(),
        source,
    })?;
    parse(path, &text)
}

/// Parses and validates scene text as if read from `path` (which names the
/// file in errors and anchors relative paths; the URDF and mesh files must
/// exist relative to it).
///
/// # Errors
/// As [`load`], without [`SceneError::Read`].
pub fn parse(path: &Path, text: &str) -> Result<Scene, SceneError> {
    let ctx = Ctx {
        file: path.to_owned(),
        text,
    };
    let raw: RawScene = toml::from_str(text).map_err(|e| ctx.toml_error(&e))?;
    ctx.validate(raw, path)
}

struct Ctx<'a> {
    file: PathBuf,
    text: &'a str,
}

/// A name's first declaration: (lower-case name) -> (line, what it is).
type Names = HashMap<String, (usize, NameKind)>;

#[derive(Clone, Copy)]
enum NameKind {
    Axis,
    Tag(TagType),
}

impl Ctx<'_> {
    fn location(&self, byte: usize) -> Location {
        let byte = byte.min(self.text.len());
        let before = &self.text[..byte];
        let line_start = before.rfind('\n').map_or(0, |i| i + 1);
        Location {
            line: before.matches('\n').count() + 1,
            column: before[line_start..].chars().count() + 1,
        }
    }

    fn loc<T>(&self, s: &Spanned<T>) -> Location {
        self.location(s.span().start)
    }

    fn invalid<T>(&self, at: &Spanned<T>, field: impl Into<String>, problem: Problem) -> SceneError {
        self.invalid_at(at.span(), field, problem)
    }

    fn invalid_at(&self, span: Range<usize>, field: impl Into<String>, problem: Problem) -> SceneError {
        let Location { line, column } = self.location(span.start);
        SceneError::Invalid {
            file: self.file.clone(),
            line,
            column,
            field: field.into(),
            problem,
        }
    }

    fn toml_error(&self, e: &toml::de::Error) -> SceneError {
        let start = e.span().map_or(0, |s| s.start);
        let Location { line, column } = self.location(start);
        SceneError::Toml {
            file: self.file.clone(),
            line,
            column,
            table: e.span().and_then(|_| self.table_at(line)),
            message: e.message().to_owned(),
        }
    }

    /// The table (`axes[1]`, `robot`) whose body contains `line`, from the
    /// nearest header above it.
    fn table_at(&self, line: usize) -> Option<String> {
        let mut current = None;
        let mut counts: HashMap<String, usize> = HashMap::new();
        for text in self.text.lines().take(line) {
            let t = text.trim();
            let t = t.split_once('#').map_or(t, |(head, _)| head).trim();
            if let Some(name) = t.strip_prefix("[[").and_then(|r| r.strip_suffix("]]")) {
                let name = name.trim().to_owned();
                let n = counts.entry(name.clone()).or_default();
                current = Some(format!("{name}[{n}]"));
                *n += 1;
            } else if let Some(name) = t.strip_prefix('[').and_then(|r| r.strip_suffix(']')) {
                let name = name.trim();
                if !name.is_empty() && name.chars().all(|c| c.is_alphanumeric() || "_-.\"' ".contains(c)) {
                    current = Some(name.to_owned());
                }
            }
        }
        current
    }

    /// Maps a 1-based character column inside a string value to the file.
    fn string_location(&self, s: &Spanned<String>, column: usize) -> Location {
        let span = s.span();
        let raw = &self.text[span.clone()];
        let (open, close) = if raw.starts_with("\"\"\"") || raw.starts_with("'''") {
            (3, 3)
        } else {
            (1, 1)
        };
        let mut content_start = span.start + open.min(raw.len());
        if open == 3 {
            let rest = &self.text[content_start..];
            if rest.starts_with("\r\n") {
                content_start += 2;
            } else if rest.starts_with('\n') {
                content_start += 1;
            }
        }
        let content_end = span.end.saturating_sub(close).max(content_start);
        let raw_content = &self.text[content_start..content_end];
        // Without escapes the decoded value is the raw text; with them this is approximate.
        let index = column.saturating_sub(1);
        let byte = raw_content
            .char_indices()
            .nth(index)
            .map_or(raw_content.len(), |(b, _)| b);
        self.location(content_start + byte)
    }

    fn syntax(&self, s: &Spanned<String>, field: String, source: ParseError) -> SceneError {
        let Location { line, column } = self.string_location(s, source.column());
        SceneError::Syntax {
            file: self.file.clone(),
            line,
            column,
            field,
            source,
        }
    }

    fn finite(&self, v: &Spanned<f64>, field: &str) -> Result<f64, SceneError> {
        let value = *v.get_ref();
        if value.is_finite() {
            Ok(value)
        } else {
            Err(self.invalid(v, field, Problem::NotFinite { value }))
        }
    }

    fn positive(&self, v: &Spanned<f64>, field: &str) -> Result<f64, SceneError> {
        let value = self.finite(v, field)?;
        if value > 0.0 {
            Ok(value)
        } else {
            Err(self.invalid(v, field, Problem::NotPositive { value }))
        }
    }

    fn non_negative(&self, v: &Spanned<f64>, field: &str) -> Result<f64, SceneError> {
        let value = self.finite(v, field)?;
        if value >= 0.0 {
            Ok(value)
        } else {
            Err(self.invalid(v, field, Problem::Negative { value }))
        }
    }

    fn finite_array<const N: usize>(&self, v: &Spanned<[f64; N]>, field: &str) -> Result<[f64; N], SceneError> {
        match v.get_ref().iter().find(|x| !x.is_finite()) {
            Some(&value) => Err(self.invalid(v, field, Problem::NotFinite { value })),
            None => Ok(*v.get_ref()),
        }
    }

    fn nonempty_name(&self, v: &Spanned<String>, field: &str) -> Result<String, SceneError> {
        if v.get_ref().trim().is_empty() {
            Err(self.invalid(v, field, Problem::Empty))
        } else {
            Ok(v.get_ref().clone())
        }
    }

    fn existing_file(&self, v: &Spanned<String>, field: &str, base: &Path) -> Result<PathBuf, SceneError> {
        let path = base.join(v.get_ref());
        if v.get_ref().is_empty() || !path.is_file() {
            return Err(self.invalid(v, field, Problem::MissingFile { path }));
        }
        Ok(path)
    }

    /// Registers a name, failing on a duplicate (case-insensitive).
    fn unique<V>(
        &self,
        seen: &mut HashMap<String, (usize, V)>,
        name: &Spanned<String>,
        field: &str,
        value: V,
    ) -> Result<(), SceneError> {
        let key = name.get_ref().to_lowercase();
        if let Some((first_line, _)) = seen.get(&key) {
            let problem = Problem::DuplicateName {
                name: name.get_ref().clone(),
                first_line: *first_line,
            };
            return Err(self.invalid(name, field, problem));
        }
        seen.insert(key, (self.loc(name).line, value));
        Ok(())
    }

    fn identifier(&self, name: &Spanned<String>, field: &str) -> Result<String, SceneError> {
        let n = name.get_ref();
        let mut chars = n.chars();
        let valid = chars.next().is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
            && chars.all(|c| c.is_ascii_alphanumeric() || c == '_');
        if valid {
            Ok(n.clone())
        } else {
            Err(self.invalid(name, field, Problem::InvalidName { name: n.clone() }))
        }
    }

    fn validate(&self, raw: RawScene, path: &Path) -> Result<Scene, SceneError> {
        let base = path.parent().unwrap_or_else(|| Path::new(""));
        let name = match &raw.name {
            Some(n) => self.nonempty_name(n, "name")?,
            None => path
                .file_stem()
                .map_or_else(String::new, |s| s.to_string_lossy().into_owned()),
        };
        let duration_s = self.positive(&raw.duration_s, "duration_s")?;
        let coarse_update_ms = self.finite(&raw.coarse_update_ms, "coarse_update_ms")?;
        if !(1.0..=32.0).contains(&coarse_update_ms) {
            let problem = Problem::OutOfRange {
                value: coarse_update_ms,
                min: 1.0,
                max: 32.0,
                exclusive: false,
            };
            return Err(self.invalid(&raw.coarse_update_ms, "coarse_update_ms", problem));
        }
        let physics_step_ms = self.positive(&raw.physics_step_ms, "physics_step_ms")?;
        let ratio = coarse_update_ms / physics_step_ms;
        if (ratio - ratio.round()).abs() > 1e-9 || ratio.round() < 1.0 {
            let problem = Problem::StepNotDivisor {
                physics_step_ms,
                coarse_update_ms,
            };
            return Err(self.invalid(&raw.physics_step_ms, "physics_step_ms", problem));
        }

        let robot = self.robot(&raw.robot, base)?;
        let mut names: Names = HashMap::new();
        let axes = self.axes(&raw.axes, &robot, &mut names)?;
        let cameras = self.cameras(&raw.cameras)?;
        let obstacles = self.obstacles(&raw.obstacles, base)?;
        let tags = self.tags(&raw.tags, &axes, &mut names)?;
        let program = self.program(&raw.program, duration_s, &names)?;
        let snapshots = match &raw.snapshots {
            Some(s) => Some(self.snapshots(s, &cameras)?),
            None => None,
        };
        let collision = match &raw.collision {
            Some(c) => Some(self.collision(c, base)?),
            None => None,
        };
        Ok(Scene {
            collision,
            name,
            path: path.to_owned(),
            duration_s,
            coarse_update_ms,
            physics_step_ms,
            robot,
            axes,
            cameras,
            obstacles,
            tags,
            program,
            snapshots,
        })
    }

    fn robot(&self, raw: &RawRobot, base: &Path) -> Result<Robot, SceneError> {
        let urdf = self.existing_file(&raw.urdf, "robot.urdf", base)?;
        let mut initial_joints = BTreeMap::new();
        let mut initial_joint_locations = BTreeMap::new();
        for (joint, value) in &raw.initial_joints {
            let v = self.finite(value, &format!("robot.initial_joints.{joint}"))?;
            initial_joints.insert(joint.clone(), v);
            initial_joint_locations.insert(joint.clone(), self.loc(value));
        }
        Ok(Robot {
            urdf,
            urdf_location: self.loc(&raw.urdf),
            initial_joints,
            initial_joint_locations,
        })
    }

    fn axes(&self, raw: &[RawAxis], robot: &Robot, names: &mut Names) -> Result<Vec<Axis>, SceneError> {
        let mut joints: HashMap<String, (usize, String)> = HashMap::new();
        let mut axes = Vec::with_capacity(raw.len());
        for (i, a) in raw.iter().enumerate() {
            let f = |field: &str| format!("axes[{i}].{field}");
            let name = self.identifier(&a.name, &f("name"))?;
            self.unique(names, &a.name, &f("name"), NameKind::Axis)?;
            let joint = match &a.joint {
                Some(spanned) => {
                    let joint = self.nonempty_name(spanned, &f("joint"))?;
                    if let Some((_, other_axis)) = joints.get(&joint) {
                        let problem = Problem::SharedJoint {
                            joint: joint.clone(),
                            other_axis: other_axis.clone(),
                        };
                        return Err(self.invalid(spanned, f("joint"), problem));
                    }
                    joints.insert(joint.clone(), (i, name.clone()));
                    Some(joint)
                }
                None => None,
            };
            let kind = *a.kind.get_ref();
            let units = *a.units.get_ref();
            if !units.fits(kind) {
                return Err(self.invalid(&a.units, f("units"), Problem::UnitsMismatch { units, kind }));
            }
            let modulo_period = match &a.modulo_period {
                Some(p) => Some(self.positive(p, &f("modulo_period"))?),
                None => None,
            };
            let max_velocity = self.positive(&a.max_velocity, &f("max_velocity"))?;
            let max_acceleration = self.positive(&a.max_acceleration, &f("max_acceleration"))?;
            let max_deceleration = self.positive(&a.max_deceleration, &f("max_deceleration"))?;
            let max_jerk = self.positive(&a.max_jerk, &f("max_jerk"))?;
            let in_position_window = self.positive(&a.in_position_window, &f("in_position_window"))?;
            let modulo_tolerance_window = match &a.modulo_tolerance_window {
                Some(w) => self.non_negative(w, &f("modulo_tolerance_window"))?,
                None => 0.0,
            };
            let motor = match &a.motor {
                Some(m) => {
                    let gains = *m.get_ref();
                    for (value, field) in [(gains.stiffness, "stiffness"), (gains.damping, "damping")] {
                        let spanned = Spanned::new(m.span(), value);
                        self.non_negative(&spanned, &f(&format!("motor.{field}")))?;
                    }
                    gains
                }
                None => MotorGains::default(),
            };
            let joint_si = joint.as_ref().and_then(|j| robot.initial_joints.get(j)).copied();
            let initial_position = match (&a.initial_position, joint_si) {
                (Some(p), joint_si) => {
                    let value = self.finite(p, &f("initial_position"))?;
                    if let Some(si) = joint_si {
                        let as_si = value * units.si_per_unit();
                        if (as_si - si).abs() > 1e-9 * (1.0 + si.abs()) {
                            let problem = Problem::InitialPositionMismatch {
                                initial_position: value,
                                units,
                                joint: joint.clone().unwrap_or_default(),
                                joint_position_si: si,
                            };
                            return Err(self.invalid(p, f("initial_position"), problem));
                        }
                    }
                    value
                }
                (None, Some(si)) => si / units.si_per_unit(),
                (None, None) => 0.0,
            };
            let soft_travel_limits = match &a.soft_travel_limits {
                Some(l) => {
                    let [min, max] = self.finite_array(l, &f("soft_travel_limits"))?;
                    if min >= max {
                        return Err(self.invalid(
                            l,
                            f("soft_travel_limits"),
                            Problem::SoftTravelLimitsOrder { min, max },
                        ));
                    }
                    if let Some(period) = modulo_period {
                        return Err(self.invalid(
                            l,
                            f("soft_travel_limits"),
                            Problem::SoftTravelLimitsOnModulo { period },
                        ));
                    }
                    if !(min..=max).contains(&initial_position) {
                        let problem = Problem::OutsideSoftTravelLimits {
                            position: initial_position,
                            min,
                            max,
                        };
                        return Err(match &a.initial_position {
                            Some(p) => self.invalid(p, f("initial_position"), problem),
                            None => self.invalid(l, f("soft_travel_limits"), problem),
                        });
                    }
                    Some((min, max))
                }
                None => None,
            };
            axes.push(Axis {
                name,
                joint,
                joint_location: a.joint.as_ref().map_or_else(|| self.loc(&a.name), |j| self.loc(j)),
                kind,
                modulo_period,
                units,
                max_velocity,
                max_acceleration,
                max_deceleration,
                max_jerk,
                in_position_window,
                target_position_monitoring: a.target_position_monitoring.unwrap_or(true),
                modulo_tolerance_window,
                initial_position,
                soft_travel_limits,
                motor,
                location: self.loc(&a.name),
            });
        }
        Ok(axes)
    }

    fn cameras(&self, raw: &[RawCamera]) -> Result<Vec<Camera>, SceneError> {
        let mut seen: HashMap<String, (usize, ())> = HashMap::new();
        let mut cameras = Vec::with_capacity(raw.len());
        for (i, c) in raw.iter().enumerate() {
            let f = |field: &str| format!("cameras[{i}].{field}");
            let name = self.nonempty_name(&c.name, &f("name"))?;
            self.unique(&mut seen, &c.name, &f("name"), ())?;
            let position_m = self.finite_array(&c.position, &f("position"))?;
            let target_m = self.finite_array(&c.target, &f("target"))?;
            if position_m == target_m {
                return Err(self.invalid(&c.target, f("target"), Problem::DegenerateCamera));
            }
            let fov_deg = self.finite(&c.fov_deg, &f("fov_deg"))?;
            if !(fov_deg > 0.0 && fov_deg < 180.0) {
                let problem = Problem::OutOfRange {
                    value: fov_deg,
                    min: 0.0,
                    max: 180.0,
                    exclusive: true,
                };
                return Err(self.invalid(&c.fov_deg, f("fov_deg"), problem));
            }
            for (v, field) in [(&c.width, "width"), (&c.height, "height")] {
                if *v.get_ref() == 0 {
                    return Err(self.invalid(v, f(field), Problem::NotPositive { value: 0.0 }));
                }
            }
            let fps = self.positive(&c.fps, &f("fps"))?;
            cameras.push(Camera {
                name,
                position_m,
                target_m,
                fov_deg,
                width: *c.width.get_ref(),
                height: *c.height.get_ref(),
                fps,
                location: self.loc(&c.name),
            });
        }
        Ok(cameras)
    }

    fn obstacles(&self, raw: &[RawObstacle], base: &Path) -> Result<Vec<Obstacle>, SceneError> {
        let mut seen: HashMap<String, (usize, ())> = HashMap::new();
        let mut obstacles = Vec::with_capacity(raw.len());
        for (i, o) in raw.iter().enumerate() {
            let f = |field: &str| format!("obstacles[{i}].{field}");
            let name = self.nonempty_name(&o.name, &f("name"))?;
            self.unique(&mut seen, &o.name, &f("name"), ())?;
            let kind = *o.shape.get_ref();
            let shape_name = kind.name();
            let needs: &[&'static str] = match kind {
                ShapeKind::Box => &["size"],
                ShapeKind::Cylinder => &["radius", "length"],
                ShapeKind::Sphere => &["radius"],
                ShapeKind::Mesh => &["file", "scale"],
            };
            let given: [(&'static str, Option<Range<usize>>); 5] = [
                ("size", o.size.as_ref().map(Spanned::span)),
                ("radius", o.radius.as_ref().map(Spanned::span)),
                ("length", o.length.as_ref().map(Spanned::span)),
                ("file", o.file.as_ref().map(Spanned::span)),
                ("scale", o.scale.as_ref().map(Spanned::span)),
            ];
            for (field, span) in &given {
                if let Some(span) = span
                    && !needs.contains(field)
                {
                    let problem = Problem::ExtraShapeField {
                        shape: shape_name,
                        field,
                    };
                    return Err(self.invalid_at(span.clone(), f(field), problem));
                }
            }
            let missing = |field: &'static str| {
                self.invalid(
                    &o.shape,
                    f("shape"),
                    Problem::MissingShapeField {
                        shape: shape_name,
                        field,
                    },
                )
            };
            let positive_array = |v: &Spanned<[f64; 3]>, field: &str| -> Result<[f64; 3], SceneError> {
                let values = self.finite_array(v, field)?;
                match values.iter().find(|x| **x <= 0.0) {
                    Some(&value) => Err(self.invalid(v, field, Problem::NotPositive { value })),
                    None => Ok(values),
                }
            };
            let shape = match kind {
                ShapeKind::Box => {
                    let size = o.size.as_ref().ok_or_else(|| missing("size"))?;
                    Shape::Box {
                        size_m: positive_array(size, &f("size"))?,
                    }
                }
                ShapeKind::Cylinder => Shape::Cylinder {
                    radius_m: self.positive(o.radius.as_ref().ok_or_else(|| missing("radius"))?, &f("radius"))?,
                    length_m: self.positive(o.length.as_ref().ok_or_else(|| missing("length"))?, &f("length"))?,
                },
                ShapeKind::Sphere => Shape::Sphere {
                    radius_m: self.positive(o.radius.as_ref().ok_or_else(|| missing("radius"))?, &f("radius"))?,
                },
                ShapeKind::Mesh => {
                    let file = o.file.as_ref().ok_or_else(|| missing("file"))?;
                    let path = self.existing_file(file, &f("file"), base)?;
                    let scale = match &o.scale {
                        Some(s) => positive_array(s, &f("scale"))?,
                        None => [1.0; 3],
                    };
                    Shape::Mesh { path, scale }
                }
            };
            let position_m = self.finite_array(&o.position, &f("position"))?;
            let rpy_deg = match &o.rpy_deg {
                Some(r) => self.finite_array(r, &f("rpy_deg"))?,
                None => [0.0; 3],
            };
            let color = match &o.color {
                Some(c) => {
                    let rgba = self.finite_array(c, &f("color"))?;
                    if let Some(&value) = rgba.iter().find(|x| !(0.0..=1.0).contains(*x)) {
                        let problem = Problem::OutOfRange {
                            value,
                            min: 0.0,
                            max: 1.0,
                            exclusive: false,
                        };
                        return Err(self.invalid(c, f("color"), problem));
                    }
                    rgba
                }
                None => [0.6, 0.6, 0.6, 1.0],
            };
            obstacles.push(Obstacle {
                name,
                shape,
                position_m,
                rpy_deg,
                color,
                location: self.loc(&o.name),
            });
        }
        Ok(obstacles)
    }

    fn tag_type(&self, raw: &Spanned<String>, field: &str) -> Result<TagType, SceneError> {
        let written = raw.get_ref().trim();
        let (base_name, array_len) = match written.split_once('[') {
            Some((base, rest)) => {
                let bad = || {
                    self.invalid(
                        raw,
                        field,
                        Problem::BadArrayLength {
                            type_name: written.to_owned(),
                        },
                    )
                };
                let len_text = rest.strip_suffix(']').ok_or_else(bad)?.trim();
                let len: usize = len_text.parse().map_err(|_| bad())?;
                if len == 0 {
                    return Err(bad());
                }
                (base.trim(), Some(len))
            }
            None => (written, None),
        };
        let Some(base) = BaseType::parse(base_name) else {
            return Err(self.invalid(
                raw,
                field,
                Problem::UnknownTagType {
                    type_name: written.to_owned(),
                },
            ));
        };
        if array_len.is_some() && matches!(base, BaseType::CoordinateSystem | BaseType::FunctionBlock(_)) {
            return Err(self.invalid(raw, field, Problem::ArrayNotAllowed { base: base.name() }));
        }
        Ok(TagType { base, array_len })
    }

    fn tags(&self, raw: &[RawTag], axes: &[Axis], names: &mut Names) -> Result<Vec<Tag>, SceneError> {
        let mut tags = Vec::with_capacity(raw.len());
        for (i, t) in raw.iter().enumerate() {
            let f = |field: &str| format!("tags[{i}].{field}");
            let name = self.identifier(&t.name, &f("name"))?;
            let ty = self.tag_type(&t.ty, &f("type"))?;
            self.unique(names, &t.name, &f("name"), NameKind::Tag(ty))?;
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
            tags.push(Tag {
                name,
                ty,
                value,
                coordinate_system,
                geometry,
                location: self.loc(&t.name),
            });
        }
        Ok(tags)
    }

    fn coordinate_system(
        &self,
        raw: Option<&Spanned<RawCoordinateSystem>>,
        axes: &[Axis],
        members: usize,
        name: &Spanned<String>,
        field: &str,
    ) -> Result<CoordinateSystemSettings, SceneError> {
        let f = |x: &str| format!("{field}.{x}");
        let default_primary = members.min(3);
        let Some(raw) = raw else {
            return Ok(CoordinateSystemSettings {
                primary_axes: default_primary,
                max_speed: 1.0,
                max_accel: 10.0,
                max_decel: 10.0,
                max_accel_jerk: 100.0,
                max_decel_jerk: 100.0,
                command_tolerance: 0.1,
                actual_tolerance: 0.01,
                tool_link: None,
                master_axis: None,
                location: self.loc(name),
            });
        };
        let r = raw.get_ref();
        let primary_axes = match &r.primary_axes {
            Some(p) => {
                let max = default_primary as i64;
                let value = *p.get_ref();
                if !(1..=max).contains(&value) {
                    let problem = Problem::OutOfRange {
                        value: value as f64,
                        min: 1.0,
                        max: max as f64,
                        exclusive: false,
                    };
                    return Err(self.invalid(p, f("primary_axes"), problem));
                }
                value as usize
            }
            None => default_primary,
        };
        let pos = |v: &Option<Spanned<f64>>, name: &str, default: f64| match v {
            Some(v) => self.positive(v, &f(name)),
            None => Ok(default),
        };
        let non_neg = |v: &Option<Spanned<f64>>, name: &str, default: f64| match v {
            Some(v) => self.non_negative(v, &f(name)),
            None => Ok(default),
        };
        Ok(CoordinateSystemSettings {
            primary_axes,
            max_speed: pos(&r.max_speed, "max_speed", 1.0)?,
            max_accel: pos(&r.max_accel, "max_accel", 10.0)?,
            max_decel: non_neg(&r.max_decel, "max_decel", 10.0)?,
            max_accel_jerk: non_neg(&r.max_accel_jerk, "max_accel_jerk", 100.0)?,
            max_decel_jerk: non_neg(&r.max_decel_jerk, "max_decel_jerk", 100.0)?,
            command_tolerance: non_neg(&r.command_tolerance, "command_tolerance", 0.1)?,
            actual_tolerance: non_neg(&r.actual_tolerance, "actual_tolerance", 0.01)?,
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
                        };
                        return Err(self.invalid(m, f("master_axis"), problem));
                    }
                },
                None => None,
            },
            location: self.loc(raw),
        })
    }

    fn tag_value(
        &self,
        v: &Spanned<toml::Value>,
        ty: TagType,
        axes: &[Axis],
        field: &str,
    ) -> Result<TagValue, SceneError> {
        let mismatch = |expected| self.invalid(v, field, Problem::ValueMismatch { ty, expected });
        match (ty.base, ty.array_len) {
            (BaseType::MotionInstruction | BaseType::CamProfile | BaseType::FunctionBlock(_), _) => {
                Err(self.invalid(v, field, Problem::ValueNotAllowed { ty }))
            }
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
                        return Err(self.invalid(v, field, Problem::UnknownAxis { name: axis.clone() }));
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
                if items.len() > len.unwrap_or(1) || items.is_empty() {
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
                Ok(TagValue::CamPoints(points))
            }
            (base, Some(len)) => {
                let expected = "an array of exactly N elements of the element type";
                let toml::Value::Array(items) = v.get_ref() else {
                    return Err(mismatch(expected));
                };
                if items.len() != len {
                    return Err(mismatch(expected));
                }
                items
                    .iter()
                    .map(|item| scalar_value(base, item).ok_or_else(|| mismatch(expected)))
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

    fn program(&self, raw: &[RawStep], duration_s: f64, names: &Names) -> Result<Vec<Step>, SceneError> {
        let mut steps = Vec::with_capacity(raw.len());
        for (i, s) in raw.iter().enumerate() {
            let f = |field: &str| format!("program[{i}].{field}");
            let trigger = match (&s.at_s, &s.when) {
                (Some(_), Some(when)) => {
                    return Err(self.invalid(when, f("when"), Problem::BothTriggers));
                }
                (None, None) => {
                    return Err(self.invalid(&s.call, format!("program[{i}]"), Problem::NoTrigger));
                }
                (Some(at), None) => {
                    if let Some(after) = &s.after_s {
                        return Err(self.invalid(after, f("after_s"), Problem::AfterWithoutWhen));
                    }
                    let time_s = self.non_negative(at, &f("at_s"))?;
                    if time_s > duration_s {
                        return Err(self.invalid(
                            at,
                            f("at_s"),
                            Problem::AfterEnd {
                                at_s: time_s,
                                duration_s,
                            },
                        ));
                    }
                    Trigger::At { time_s }
                }
                (None, Some(when)) => {
                    let condition = st::parse_condition(when.get_ref()).map_err(|e| self.syntax(when, f("when"), e))?;
                    self.check_reference(when, &condition, &f("when"), names)?;
                    let delay_s = match &s.after_s {
                        Some(after) => self.non_negative(after, &f("after_s"))?,
                        None => 0.0,
                    };
                    Trigger::When {
                        condition: condition.value,
                        delay_s,
                    }
                }
            };
            let call = st::parse_call(s.call.get_ref()).map_err(|e| self.syntax(&s.call, f("call"), e))?;
            self.check_call(&s.call, &call, &f("call"), names)?;
            steps.push(Step {
                trigger,
                call,
                call_text: s.call.get_ref().clone(),
                location: self.loc(&s.call),
            });
        }
        Ok(steps)
    }

    /// Errors for a name inside a `call`/`when` string at `span` (characters).
    fn invalid_in(&self, text: &Spanned<String>, span: st::Span, field: &str, problem: Problem) -> SceneError {
        let Location { line, column } = self.string_location(text, span.column());
        SceneError::Invalid {
            file: self.file.clone(),
            line,
            column,
            field: field.to_owned(),
            problem,
        }
    }

    /// Checks that a reference's root names a tag or axis, and that a direct
    /// index into an array tag is in bounds.
    fn check_reference(
        &self,
        text: &Spanned<String>,
        expr: &st::Spanned<Expr>,
        field: &str,
        names: &Names,
    ) -> Result<(), SceneError> {
        let Some(root) = expr.value.root_ident() else {
            return Ok(());
        };
        let Some((_, kind)) = names.get(&root.to_lowercase()) else {
            return Err(self.invalid_in(text, expr.span, field, Problem::UnknownTag { name: root.to_owned() }));
        };
        if let (
            Expr::Index(base, index),
            NameKind::Tag(TagType {
                array_len: Some(len), ..
            }),
        ) = (&expr.value, kind)
            && matches!(**base, Expr::Ident(_))
            && usize::try_from(*index).map_or(true, |i| i >= *len)
        {
            let problem = Problem::IndexOutOfBounds {
                name: root.to_owned(),
                index: *index,
                len: *len,
            };
            return Err(self.invalid_in(text, expr.span, field, problem));
        }
        Ok(())
    }

    fn check_call(&self, text: &Spanned<String>, call: &Call, field: &str, names: &Names) -> Result<(), SceneError> {
        let name = &call.name;
        let operand = |expr: &st::Spanned<Expr>, enumerations: &[&str]| -> Result<(), SceneError> {
            if let Expr::Ident(word) = &expr.value
                && !names.contains_key(&word.to_lowercase())
            {
                if enumerations.iter().any(|e| e.eq_ignore_ascii_case(word)) {
                    return Ok(());
                }
                // In named calls only `MC_...` words are enumeration values; others are tags.
                let problem = if enumerations == st::PLCOPEN_ENUMERATIONS
                    && !word.get(..3).is_some_and(|p| p.eq_ignore_ascii_case("MC_"))
                {
                    Problem::UnknownTag { name: word.clone() }
                } else {
                    Problem::UnknownOperand { name: word.clone() }
                };
                return Err(self.invalid_in(text, expr.span, field, problem));
            }
            self.check_reference(text, expr, field, names)
        };
        match &call.args {
            Args::Named(inputs) => {
                match names.get(&name.value.to_lowercase()) {
                    Some((
                        _,
                        NameKind::Tag(TagType {
                            base: BaseType::FunctionBlock(_),
                            ..
                        }),
                    )) => {}
                    Some((_, other)) => {
                        let kind = match other {
                            NameKind::Axis => "an axis".to_owned(),
                            NameKind::Tag(ty) => format!("a {ty} tag"),
                        };
                        let problem = Problem::NotCallable {
                            name: name.value.clone(),
                            kind,
                        };
                        return Err(self.invalid_in(text, name.span, field, problem));
                    }
                    None => {
                        let problem = Problem::UnknownTag {
                            name: name.value.clone(),
                        };
                        return Err(self.invalid_in(text, name.span, field, problem));
                    }
                }
                for (_, value) in inputs {
                    operand(value, st::PLCOPEN_ENUMERATIONS)?;
                }
            }
            Args::Positional(operands) => {
                if !st::LOGIX_INSTRUCTIONS
                    .iter()
                    .any(|m| m.eq_ignore_ascii_case(&name.value))
                {
                    let problem = if names.contains_key(&name.value.to_lowercase()) {
                        Problem::NotCallable {
                            name: name.value.clone(),
                            kind: "called positionally".to_owned(),
                        }
                    } else {
                        Problem::UnknownInstruction {
                            name: name.value.clone(),
                        }
                    };
                    return Err(self.invalid_in(text, name.span, field, problem));
                }
                for value in operands {
                    operand(value, st::LOGIX_ENUMERATIONS)?;
                }
            }
        }
        Ok(())
    }

    fn snapshots(&self, raw: &RawSnapshots, cameras: &[Camera]) -> Result<Snapshots, SceneError> {
        if cameras.is_empty() {
            return Err(self.invalid(&raw.frames, "snapshots.frames", Problem::NoCamera));
        }
        let mut frames: Vec<u32> = Vec::with_capacity(raw.frames.get_ref().len());
        for frame in raw.frames.get_ref() {
            if frames.contains(frame.get_ref()) {
                let problem = Problem::DuplicateFrame {
                    frame: *frame.get_ref(),
                };
                return Err(self.invalid(frame, "snapshots.frames", problem));
            }
            frames.push(*frame.get_ref());
        }
        frames.sort_unstable();
        Ok(Snapshots { frames })
    }
}

/// A scalar initial value of `base`, if `value` fits it.
fn scalar_value(base: BaseType, value: &toml::Value) -> Option<TagValue> {
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::st::ParseError;
    use rand::{Rng, SeedableRng};

    fn fixtures() -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures")
    }

    fn fixture_text() -> String {
        std::fs::read_to_string(fixtures().join("indexing_table.toml")).expect("fixture readable")
    }

    /// The fixture with `from` replaced by `to` (which must occur exactly once).
    fn edited(from: &str, to: &str) -> String {
        let text = fixture_text();
        assert_eq!(text.matches(from).count(), 1, "'{from}' must occur once in the fixture");
        text.replace(from, to)
    }

    fn error_of(text: &str) -> SceneError {
        match parse(&fixtures().join("case.toml"), text) {
            Ok(_) => panic!("scene should not load"),
            Err(e) => e,
        }
    }

    /// 1-based line and column of the first occurrence of `needle`.
    fn find(text: &str, needle: &str) -> Location {
        let byte = text.find(needle).expect("needle present");
        let before = &text[..byte];
        let line_start = before.rfind('\n').map_or(0, |i| i + 1);
        Location {
            line: before.matches('\n').count() + 1,
            column: before[line_start..].chars().count() + 1,
        }
    }

    fn assert_place(e: &SceneError, at: Location, field: &str) {
        assert_eq!(e.location(), Some(at), "{e}");
        assert_eq!(e.field(), Some(field), "{e}");
        let line = e.to_string();
        assert!(line.starts_with(&format!(
            "{}:{}:{}: ",
            fixtures().join("case.toml").display(),
            at.line,
            at.column
        )));
        assert!(!line.contains('\n'), "{line}");
    }

    #[test]
    fn complete_fixture_loads() {
        let scene = load(&fixtures().join("indexing_table.toml")).expect("fixture loads");
        assert_eq!(scene.name, "indexing_table");
        assert_eq!(
            (scene.duration_s, scene.coarse_update_ms, scene.physics_step_ms),
            (8.0, 4.0, 1.0)
        );
        assert_eq!(scene.robot.urdf, fixtures().join("robots/indexing_table.urdf"));
        assert_eq!(scene.axes.len(), 2);
        let table = scene.axis("table").expect("case-insensitive lookup");
        assert_eq!(table.modulo_period, Some(360.0));
        assert_eq!(table.motor, MotorGains::default());
        let slide = scene.axis("Slide").expect("Slide");
        assert_eq!((slide.kind, slide.units), (AxisKind::Linear, Units::Mm));
        assert!(
            (slide.initial_position - 100.0).abs() < 1e-9,
            "0.1 m from initial_joints is 100 mm"
        );
        assert!(slide.target_position_monitoring);
        assert_eq!(slide.joint_location, find(&fixture_text(), "\"slide_joint\""));
        assert_eq!(scene.cameras[0].width, 640);
        assert!(matches!(
            scene.obstacles[1].shape,
            Shape::Cylinder {
                radius_m: 0.05,
                length_m: 0.8
            }
        ));
        assert!(matches!(
            &scene.obstacles[3].shape,
            Shape::Mesh {
                scale: [0.001, 0.001, 0.001],
                ..
            }
        ));
        assert_eq!(scene.obstacles[2].color, [0.6, 0.6, 0.6, 1.0]);
        assert_eq!(
            scene.tag("CS1").and_then(|t| t.value.clone()),
            Some(TagValue::Axes(vec!["Table".into(), "Slide".into()]))
        );
        assert_eq!(
            scene.tag("Pos").and_then(|t| t.value.clone()),
            Some(TagValue::Array(vec![TagValue::Real(90.0), TagValue::Real(100.0)]))
        );
        let Some(TagValue::CamPoints(cam)) = scene.tag("Cam_1").and_then(|t| t.value.clone()) else {
            panic!("cam points")
        };
        assert_eq!(cam[0].segment_type, SegmentType::Linear);
        assert_eq!(cam[1].segment_type, SegmentType::Cubic);
        assert_eq!(
            scene.tag("MoveTable").map(|t| t.ty.base),
            Some(BaseType::FunctionBlock(FunctionBlock::MoveModulo))
        );
        assert_eq!(scene.program.len(), 4);
        assert_eq!(scene.program[0].trigger, Trigger::At { time_s: 0.0 });
        assert_eq!(
            scene.program[1].trigger,
            Trigger::When {
                condition: Expr::Member(Box::new(Expr::Ident("MoveTable".into())), "Done".into()),
                delay_s: 0.5
            }
        );
        let Args::Positional(operands) = &scene.program[2].call.args else {
            panic!("positional MCCM")
        };
        assert_eq!(operands.len(), 25);
        assert_eq!(
            scene.snapshots.as_ref().map(|s| s.frames.clone()),
            Some(vec![0, 12, 30])
        );
    }

    #[test]
    fn name_defaults_to_file_stem() {
        let text = edited("name = \"indexing_table\"\n", "");
        let scene = parse(&fixtures().join("stem_name.toml"), &text).expect("loads");
        assert_eq!(scene.name, "stem_name");
    }

    #[test]
    fn unknown_field_names_table_line_and_column() {
        let text = edited("max_velocity = 720.0", "max_speed = 720.0");
        let e = error_of(&text);
        assert!(matches!(&e, SceneError::Toml { .. }), "{e}");
        assert_place(&e, find(&text, "max_speed"), "axes[0]");
        assert!(e.to_string().contains("'max_speed'"), "{e}");
    }

    #[test]
    fn wrong_type_points_at_the_value() {
        let text = edited("fps = 10.0", "fps = \"fast\"");
        let e = error_of(&text);
        assert!(matches!(&e, SceneError::Toml { .. }), "{e}");
        assert_place(&e, find(&text, "\"fast\""), "cameras[0]");
    }

    #[test]
    fn missing_required_field_is_an_error() {
        // (`joint` is optional: an axis without one is virtual.)
        let text = edited("kind = \"linear\"\n", "");
        assert!(matches!(error_of(&text), SceneError::Toml { .. }));
    }

    fn syntax_case(from: &str, to: &str, points_at: &str, field: &str) -> ParseError {
        let text = edited(from, to);
        let e = error_of(&text);
        assert_place(&e, find(&text, points_at), field);
        match e {
            SceneError::Syntax { source, .. } => source,
            other => panic!("expected a syntax error, got {other}"),
        }
    }

    #[test]
    fn missing_assign_maps_into_the_file() {
        let source = syntax_case("Position := 90.0", "Position 90.0", "90.0, Velocity", "program[0].call");
        assert!(matches!(source, ParseError::MissingAssign { ref input, .. } if input == "Position"));
    }

    #[test]
    fn unterminated_call_points_past_the_text() {
        let source = syntax_case(
            "Execute := FALSE);\"",
            "Execute := FALSE\"",
            "\"\n\n[[program]]\nat_s = 2.0",
            "program[1].call",
        );
        assert!(matches!(source, ParseError::Unterminated { .. }));
    }

    #[test]
    fn missing_comma_in_positional_call() {
        let source = syntax_case("MCCM(CS1, MC1,", "MCCM(CS1 MC1,", "MC1, 0, Pos", "program[2].call");
        assert!(matches!(
            source,
            ParseError::Unexpected {
                expected: st::Expected::CloseOrComma,
                ..
            }
        ));
    }

    #[test]
    fn bad_when_condition() {
        let source = syntax_case(
            "when = \"MC1.PC\"",
            "when = \"MC1.\"",
            "\"\ncall = \"MCCP",
            "program[3].when",
        );
        assert!(matches!(
            source,
            ParseError::Unexpected {
                expected: st::Expected::MemberName,
                ..
            }
        ));
    }

    #[test]
    fn mixed_arguments() {
        let source = syntax_case(
            "Axis := Table, Execute := FALSE",
            "Table, Execute := FALSE",
            "Execute := FALSE",
            "program[1].call",
        );
        assert!(matches!(source, ParseError::MixedArguments { .. }));
    }

    #[test]
    fn missing_urdf_names_path_and_field() {
        let text = edited("robots/indexing_table.urdf", "robots/nope.urdf");
        let e = error_of(&text);
        assert_place(&e, find(&text, "\"robots/nope.urdf\""), "robot.urdf");
        assert!(matches!(e.problem(), Some(Problem::MissingFile { path }) if path.ends_with("robots/nope.urdf")));
    }

    #[test]
    fn missing_mesh_file() {
        let text = edited("meshes/guard.obj", "meshes/none.obj");
        let e = error_of(&text);
        assert_place(&e, find(&text, "\"meshes/none.obj\""), "obstacles[3].file");
    }

    #[test]
    fn unknown_tag_in_a_call_points_at_the_name() {
        let text = edited("Axis := Table, Execute := TRUE", "Axis := Tabel, Execute := TRUE");
        let e = error_of(&text);
        assert_place(&e, find(&text, "Tabel"), "program[0].call");
        assert!(matches!(e.problem(), Some(Problem::UnknownTag { name }) if name == "Tabel"));
    }

    #[test]
    fn unknown_instance_and_instruction() {
        let text = edited(
            "call = \"MoveTable(Axis := Table, Execute := FALSE);\"",
            "call = \"MoveTabel(Axis := Table);\"",
        );
        let e = error_of(&text);
        assert_place(&e, find(&text, "MoveTabel"), "program[1].call");
        assert!(matches!(e.problem(), Some(Problem::UnknownTag { .. })));

        let text = edited("MCCP(MC1", "MCCX(MC1");
        let e = error_of(&text);
        assert_place(&e, find(&text, "MCCX"), "program[3].call");
        assert!(matches!(e.problem(), Some(Problem::UnknownInstruction { .. })));

        let text = edited("Table, Execute := FALSE", "Table, Execute := MC_Sideways");
        assert!(matches!(
            error_of(&text).problem(),
            Some(Problem::UnknownOperand { .. })
        ));
    }

    #[test]
    fn calling_a_data_tag_is_an_error() {
        let text = edited(
            "MoveTable(Axis := Table, Execute := FALSE)",
            "Count(Axis := Table, Execute := FALSE)",
        );
        assert!(matches!(error_of(&text).problem(), Some(Problem::NotCallable { .. })));
    }

    #[test]
    fn unknown_enumeration_word_and_bad_index() {
        let text = edited("s-curve", "z-curve");
        let e = error_of(&text);
        assert_place(&e, find(&text, "z-curve"), "program[2].call");
        let text = edited("Pos[0], 1", "Pos[2], 1");
        assert!(matches!(
            error_of(&text).problem(),
            Some(Problem::IndexOutOfBounds { index: 2, len: 2, .. })
        ));
    }

    #[test]
    fn unknown_tag_in_when() {
        let text = edited("when = \"MoveTable.Done\"", "when = \"Moved.Done\"");
        let e = error_of(&text);
        assert_place(&e, find(&text, "Moved.Done"), "program[1].when");
    }

    #[test]
    fn duplicate_axis_name() {
        let text = edited("name = \"Slide\"", "name = \"table\"");
        let e = error_of(&text);
        assert_place(&e, find(&text, "\"table\""), "axes[1].name");
        assert!(matches!(
            e.problem(),
            Some(Problem::DuplicateName { first_line: 12, .. })
        ));
    }

    #[test]
    fn tag_clashing_with_axis() {
        let text = edited("name = \"Count\"", "name = \"Slide\"");
        assert!(matches!(error_of(&text).problem(), Some(Problem::DuplicateName { .. })));
    }

    #[test]
    fn physics_step_must_divide_coarse_update() {
        let text = edited("physics_step_ms = 1.0", "physics_step_ms = 3.0");
        let e = error_of(&text);
        assert_place(&e, find(&text, "3.0"), "physics_step_ms");
        assert!(matches!(e.problem(), Some(Problem::StepNotDivisor { .. })));
        let text = edited("physics_step_ms = 1.0", "physics_step_ms = 0.5");
        assert!(parse(&fixtures().join("case.toml"), &text).is_ok());
        let text = edited("coarse_update_ms = 4.0", "coarse_update_ms = 40.0");
        assert!(matches!(error_of(&text).problem(), Some(Problem::OutOfRange { .. })));
    }

    #[test]
    fn both_triggers() {
        let text = edited("when = \"MoveTable.Done\"", "at_s = 1.0\nwhen = \"MoveTable.Done\"");
        let e = error_of(&text);
        assert_place(&e, find(&text, "\"MoveTable.Done\""), "program[1].when");
        assert!(matches!(e.problem(), Some(Problem::BothTriggers)));
    }

    #[test]
    fn neither_trigger() {
        let text = edited("at_s = 2.0\n", "");
        let e = error_of(&text);
        assert_place(&e, find(&text, "\"MCCM("), "program[2]");
        assert!(matches!(e.problem(), Some(Problem::NoTrigger)));
    }

    #[test]
    fn after_s_needs_when_and_at_s_within_duration() {
        let text = edited("at_s = 2.0\n", "at_s = 2.0\nafter_s = 1.0\n");
        assert!(matches!(error_of(&text).problem(), Some(Problem::AfterWithoutWhen)));
        let text = edited("at_s = 2.0\n", "at_s = 9.0\n");
        assert!(matches!(error_of(&text).problem(), Some(Problem::AfterEnd { .. })));
    }

    #[test]
    fn ranges_are_checked() {
        for (from, to, field) in [
            ("max_jerk = 36000.0", "max_jerk = -1.0", "axes[0].max_jerk"),
            ("max_velocity = 500.0", "max_velocity = nan", "axes[1].max_velocity"),
            ("fps = 10.0", "fps = 0.0", "cameras[0].fps"),
            ("width = 640", "width = 0", "cameras[0].width"),
            ("fov_deg = 45.0", "fov_deg = 180.0", "cameras[0].fov_deg"),
            ("duration_s = 8.0", "duration_s = 0.0", "duration_s"),
            ("radius = 0.1", "radius = -0.1", "obstacles[2].radius"),
            (
                "color = [0.8, 0.8, 0.2, 1.0]",
                "color = [0.8, 0.8, 0.2, 2.0]",
                "obstacles[0].color",
            ),
            ("units = \"mm\"", "units = \"deg\"", "axes[1].units"),
            (
                "initial_position = 0.0",
                "initial_position = 1.0",
                "axes[0].initial_position",
            ),
        ] {
            let e = error_of(&edited(from, to));
            assert!(matches!(e, SceneError::Invalid { .. }), "{to}: {e}");
            assert_eq!(e.field(), Some(field), "{to}: {e}");
        }
    }

    #[test]
    fn shapes_need_their_own_fields() {
        let e = error_of(&edited("radius = 0.05\n", ""));
        assert!(
            matches!(e.problem(), Some(Problem::MissingShapeField { field: "radius", .. })),
            "{e}"
        );
        let e = error_of(&edited("radius = 0.1\n", "radius = 0.1\nsize = [1.0, 1.0, 1.0]\n"));
        assert!(
            matches!(e.problem(), Some(Problem::ExtraShapeField { field: "size", .. })),
            "{e}"
        );
    }

    #[test]
    fn tag_types_and_values_are_checked() {
        let text = edited("type = \"DINT\"", "type = \"DWORD\"");
        let e = error_of(&text);
        assert_place(&e, find(&text, "\"DWORD\""), "tags[5].type");
        assert!(matches!(e.problem(), Some(Problem::UnknownTagType { type_name }) if type_name == "DWORD"));
        for (from, to) in [
            ("type = \"REAL[2]\"\nvalue = [90.0", "type = \"REAL[0]\"\nvalue = [90.0"),
            ("value = 3", "value = 3.5"),
            ("value = 3", "value = 4294967296"),
            ("value = true", "value = 1"),
            ("value = [90.0, 100]", "value = [90.0]"),
            ("value = [\"Table\", \"Slide\"]", "value = [\"Table\", \"Spindle\"]"),
            ("type = \"MC_MoveModulo\"", "type = \"MC_MoveModulo\"\nvalue = 1"),
            ("{ master = 90.0, slave = 10.0 }", "{ master = 0.0, slave = 10.0 }"),
        ] {
            let e = error_of(&edited(from, to));
            assert!(matches!(e, SceneError::Invalid { .. }), "{to}: {e}");
        }
    }

    #[test]
    fn snapshots_need_distinct_frames() {
        let e = error_of(&edited("frames = [0, 12, 30]", "frames = [0, 12, 12]"));
        assert!(matches!(e.problem(), Some(Problem::DuplicateFrame { frame: 12 })));
    }

    #[test]
    fn unreadable_file() {
        let e = load(&fixtures().join("does_not_exist.toml")).expect_err("no file");
        assert!(matches!(e, SceneError::Read { .. }));
        assert_eq!(e.location(), None);
    }

    #[test]
    fn escaped_call_string_still_reports_a_place() {
        let text = edited(
            "call = \"MoveTable(Axis := Table, Execute := FALSE);\"",
            "call = \"MoveTable(Axis := \\u0054able, Execute := FALSE\"",
        );
        let e = error_of(&text);
        assert!(matches!(e, SceneError::Syntax { .. }), "{e}");
        assert_eq!(e.location().map(|l| l.line), Some(find(&text, "\\u0054").line));
    }

    #[test]
    fn random_edits_never_panic() {
        let original = fixture_text();
        let alphabet: Vec<char> = "()[],.:=;\"'#\n -%²éabzTRUE0123456789{}".chars().collect();
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(0x5ce9e);
        for _ in 0..300 {
            let mut chars: Vec<char> = original.chars().collect();
            for _ in 0..rng.random_range(1..6) {
                let at = rng.random_range(0..chars.len());
                match rng.random_range(0..3) {
                    0 => {
                        chars.remove(at);
                    }
                    1 => chars.insert(at, alphabet[rng.random_range(0..alphabet.len())]),
                    _ => chars[at] = alphabet[rng.random_range(0..alphabet.len())],
                }
            }
            let text: String = chars.into_iter().collect();
            if let Err(e) = parse(&fixtures().join("case.toml"), &text) {
                let line = e.to_string();
                assert!(!line.is_empty() && !line.contains('\n'), "{line:?}");
            }
        }
    }

    #[test]
    fn soft_travel_limits_are_checked_at_the_field() {
        // Slide starts at robot.initial_joints.slide_joint = 0.1 m = 100 mm.
        let ok = edited(
            "in_position_window = 0.05\n",
            "in_position_window = 0.05\nsoft_travel_limits = [0.0, 300.0]\n",
        );
        let scene = parse(&fixtures().join("case.toml"), &ok).expect("limits around 100 mm");
        assert_eq!(scene.axes[1].soft_travel_limits, Some((0.0, 300.0)));
        assert_eq!(scene.axes[0].soft_travel_limits, None);
        for (limits, problem) in [
            ("[300.0, 0.0]", "order"),
            ("[0.0, 0.0]", "order"),
            ("[nan, 300.0]", "finite"),
            ("[0.0, 50.0]", "outside"),
        ] {
            let text = edited(
                "in_position_window = 0.05\n",
                &format!("in_position_window = 0.05\nsoft_travel_limits = {limits}\n"),
            );
            let e = error_of(&text);
            assert_place(&e, find(&text, limits), "axes[1].soft_travel_limits");
            let expected = match problem {
                "order" => matches!(e.problem(), Some(Problem::SoftTravelLimitsOrder { .. })),
                "finite" => matches!(e.problem(), Some(Problem::NotFinite { .. })),
                _ => matches!(
                    e.problem(),
                    Some(Problem::OutsideSoftTravelLimits { position, .. }) if (*position - 100.0).abs() < 1e-9
                ),
            };
            assert!(expected, "{limits}: {e}");
        }
        let modulo = edited(
            "modulo_tolerance_window = 0.0\n",
            "modulo_tolerance_window = 0.0\nsoft_travel_limits = [-90.0, 90.0]\n",
        );
        let e = error_of(&modulo);
        assert_place(&e, find(&modulo, "[-90.0, 90.0]"), "axes[0].soft_travel_limits");
        assert!(matches!(
            e.problem(),
            Some(Problem::SoftTravelLimitsOnModulo { period }) if *period == 360.0
        ));
    }
}
