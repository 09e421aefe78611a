//! The validated scene: what the program, plant and output stages read.
//! Every value here has passed [`super::load`]'s checks.

use crate::st::ast::Routine;
use planner::mct::{GeometryKind, GeometryParams};
use std::collections::BTreeMap;
use std::fmt;
use std::path::PathBuf;

use serde::Deserialize;

use crate::source::Files;
use crate::st::ast::{Call, Expr};
use planner::axis::AxisConfig;
use planner::coord::CoordinateSystemConfig;

pub use super::shape::{Location, Shape};

/// A validated scene.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct Scene {
    /// Scene name (default: the file stem).
    pub name: String,
    /// The scene file as given to [`super::load`].
    pub path: PathBuf,
    /// Simulated run time, seconds (> 0, at most [`MAX_DURATION_S`]).
    pub duration_s: f64,
    /// Planner coarse update period, milliseconds (1..=32).
    pub coarse_update_ms: f64,
    /// Physics step, milliseconds (at least [`MIN_PHYSICS_STEP_MS`]);
    /// divides `coarse_update_ms` exactly.
    pub physics_step_ms: f64,
    /// The robot model.
    pub robot: Robot,
    /// Axes, in file order.
    pub axes: Vec<Axis>,
    /// Cameras, in file order.
    pub cameras: Vec<Camera>,
    /// Static obstacles, in file order.
    pub obstacles: Vec<Obstacle>,
    /// Data types: `STRING` first, then `[[data_types]]` in file order
    /// ([`BaseType::User`] indexes them).
    pub data_types: Vec<DataTypeDef>,
    /// Declared tags, in file order.
    pub tags: Vec<Tag>,
    /// Program steps, in file order.
    pub program: Vec<Step>,
    /// Tasks of Structured Text programs (`[[tasks]]`).
    pub tasks: Vec<Task>,
    /// `[controller]`.
    pub controller: ControllerSettings,
    /// `[trace] tags`: tag references traced as extra columns.
    pub trace_tags: Vec<TraceTag>,
    /// `[trace] rungs`: ladder rungs traced.
    pub trace_rungs: Vec<TraceRung>,
    /// `add_on_instructions`: the Add-On Instructions the program may
    /// call (their instances' data types are in `data_types`).
    pub add_on_instructions: Vec<AoiDef>,
    /// The files the scene's texts come from: the scene file, then its
    /// routines; every parsed node's span points into one of them.
    pub files: Files,
    /// Controller-scoped aliases (`[[aliases]]`).
    pub aliases: Vec<Alias>,
    /// The Studio 5000 export the scene names (`[controller] l5x`), as
    /// expanded into the scene.
    pub l5x: Option<L5xImport>,
    /// Golden-image frames, if any.
    pub snapshots: Option<Snapshots>,
    /// Collision checking (`[collision]`); off when the table is absent.
    pub collision: Option<CollisionSettings>,
    /// How the plant moves the joints (`plant`; `twin run --plant`
    /// overrides it).
    pub plant: PlantMode,
    /// rapier steps per physics step (`physics_substeps`, 1 to
    /// [`MAX_PHYSICS_SUBSTEPS`], default [`DEFAULT_PHYSICS_SUBSTEPS`]).
    pub physics_substeps: usize,
    /// `[[expect]]`, in file order (a variant's own follow the scene's).
    pub expectations: Vec<Expectation>,
    /// `[test]`: what `twin test` expects of the run as a whole.
    pub test: TestSettings,
    /// `[[variants]]`, in file order ([`Scene::with_variant`] applies one).
    pub variants: Vec<Variant>,
    /// The variant applied, if any.
    pub variant: Option<String>,
    /// Parts, sources, sinks, conveyors and sensors (empty without them).
    pub cell: super::cell_model::Cell,
}

/// `[[expect]]`: a named condition on the run, checked on every trace row.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct Expectation {
    /// Its name (unique in the scene and its variant).
    pub name: String,
    /// What is expected.
    pub kind: ExpectKind,
    /// The entry's field path (`expect[3]`, `variants[0].expect[1]`).
    pub field: String,
    /// Where its `name` is written.
    pub location: Location,
}

/// A BOOL expression of an expectation, parsed, with its text.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct Condition {
    /// The expression as written (trimmed).
    pub text: String,
    /// The parsed expression (the run compiles it in controller scope).
    pub expr: Expr,
    /// Its field path (`expect[3].always`, `expect[0].sequence[2]`).
    pub field: String,
}

/// The kinds of [`Expectation`] (README, "Expectations").
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum ExpectKind {
    /// `always` (or, with `never`, its negation) holds at every row in
    /// [`from_s`, `to_s`] where `guard` (`while`) is TRUE.
    Always {
        /// The condition.
        condition: Condition,
        /// `never`: the condition must stay FALSE instead.
        never: bool,
        /// Start of the window, s (default 0).
        from_s: f64,
        /// End of the window, s (default: the end of the run).
        to_s: Option<f64>,
        /// `while`: rows where it is FALSE are not checked.
        guard: Option<Condition>,
    },
    /// `eventually`: TRUE at some row in [`after_s`, `by_s`].
    Eventually {
        /// The condition.
        condition: Condition,
        /// Start of the window, s (default 0).
        after_s: f64,
        /// End of the window, s (default: the end of the run).
        by_s: Option<f64>,
    },
    /// `at_end`: TRUE at the last row.
    AtEnd {
        /// The condition.
        condition: Condition,
    },
    /// `sequence`: each condition rises (FALSE → TRUE, or TRUE at t = 0),
    /// its first rise not before the previous one's, all within
    /// `within_s` of the first.
    Sequence {
        /// The conditions, in order (at least one).
        steps: Vec<Condition>,
        /// The most time from the first rise to the last, s.
        within_s: Option<f64>,
    },
    /// `cycle`: the time between consecutive rises lies in [`min_s`,
    /// `max_s`], and there are at least `count` such cycles.
    Cycle {
        /// The condition.
        condition: Condition,
        /// Shortest cycle, s (default 0).
        min_s: f64,
        /// Longest cycle, s (default: no limit).
        max_s: Option<f64>,
        /// Fewest cycles (default 1).
        count: u32,
    },
}

impl ExpectKind {
    /// The kind's name as the scene writes it.
    #[must_use]
    pub fn name(&self) -> &'static str {
        match self {
            ExpectKind::Always { never: false, .. } => "always",
            ExpectKind::Always { never: true, .. } => "never",
            ExpectKind::Eventually { .. } => "eventually",
            ExpectKind::AtEnd { .. } => "at_end",
            ExpectKind::Sequence { .. } => "sequence",
            ExpectKind::Cycle { .. } => "cycle",
        }
    }

    /// Every condition of the expectation, the guard included.
    pub fn conditions(&self) -> impl Iterator<Item = &Condition> {
        let (first, rest): (Option<&Condition>, &[Condition]) = match self {
            ExpectKind::Always { condition, .. }
            | ExpectKind::Eventually { condition, .. }
            | ExpectKind::AtEnd { condition }
            | ExpectKind::Cycle { condition, .. } => (Some(condition), &[]),
            ExpectKind::Sequence { steps, .. } => (None, steps.as_slice()),
        };
        let guard = match self {
            ExpectKind::Always { guard, .. } => guard.as_ref(),
            _ => None,
        };
        first.into_iter().chain(rest).chain(guard)
    }
}

/// `[test]`: what `twin test` expects of the run as a whole.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[non_exhaustive]
pub struct TestSettings {
    /// The exit code the run should end with without its expectations: 0
    /// (default), 2 an instruction error, 3 a collision abort, 4 a major
    /// fault, 5 a physics fault.
    pub exit_code: u8,
    /// Wall-clock limit of the run under `twin test`, s (`None`: its
    /// `--timeout`).
    pub timeout_s: Option<f64>,
}

/// The exit codes a run ends with, before its expectations (README,
/// "Errors and exit codes"): what `[test] exit_code` may expect.
pub const RUN_EXIT_CODES: [u8; 5] = [0, 2, 3, 4, 5];

/// `[[variants]]`: the scene with other initial values, duration, plant,
/// expected exit code and more expectations.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct Variant {
    /// Its name (unique in the scene): the run is `SCENE[NAME]`.
    pub name: String,
    /// Initial values: the tag (controller `Name` or `Program.Name`) and
    /// its value, checked against the tag's type.
    pub tags: Vec<(String, TagValue)>,
    /// Its `duration_s`, if it changes the scene's.
    pub duration_s: Option<f64>,
    /// Its `plant`, if it changes the scene's.
    pub plant: Option<PlantMode>,
    /// Its `exit_code`, if it changes the scene's `[test]` one.
    pub exit_code: Option<u8>,
    /// Expectations added to the scene's.
    pub expectations: Vec<Expectation>,
}

/// rapier steps per physics step when the scene does not say: the fewest
/// that keep every shipped scene's instruction outcomes and its largest
/// following error within 1 % of four substeps (README, *Benchmarks*).
pub const DEFAULT_PHYSICS_SUBSTEPS: usize = 2;

/// The most rapier steps per physics step a scene may ask for.
pub const MAX_PHYSICS_SUBSTEPS: usize = 16;

/// How the plant moves the joints (`plant = "physics" | "kinematic"`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum PlantMode {
    /// Rigid-body dynamics: drives, gravity, contacts (the default).
    #[default]
    Physics,
    /// The joints are at their setpoints, as a CIP axis in Controller Loop
    /// Back test mode (`plant/kinematic.rs`).
    Kinematic,
}

impl PlantMode {
    /// Every mode with its name in the scene and on the command line.
    pub const NAMES: [(&'static str, PlantMode); 2] = [("physics", Self::Physics), ("kinematic", Self::Kinematic)];

    /// The mode's name in the scene and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Self::Physics => "physics",
            Self::Kinematic => "kinematic",
        }
    }
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

impl AxisKind {
    /// The planner's axis kind.
    #[must_use]
    pub fn planner_kind(self) -> planner::axis::AxisKind {
        match self {
            AxisKind::Linear => planner::axis::AxisKind::Linear,
            AxisKind::Rotary => planner::axis::AxisKind::Rotary,
        }
    }
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
    pub(super) fn default_stiffness() -> f64 {
        1.0e4
    }
    pub(super) fn default_damping() -> f64 {
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
    /// Axis position units.
    pub units: Units,
    /// The axis as the planner takes it (its name and kind as above):
    /// modulo period, maximum rates (axis units, > 0), in-position window,
    /// target position monitoring (default true), modulo tolerance window
    /// (default 0), soft travel limits (default none here; the plant then
    /// takes the joint's URDF `<limit>` unless checking is off) and the
    /// soft overtravel action (default Stop Planner).
    pub config: AxisConfig,
    /// Logix `SoftTravelLimitChecking` (`soft_travel_limit_checking`,
    /// default true): off, the axis has no soft travel limits, not even its
    /// URDF joint's.
    pub soft_travel_limit_checking: bool,
    /// Initial position, axis units (default: 0, or from `robot.initial_joints`).
    pub initial_position: f64,
    /// Gains of the spring drive (`motor`); the joint's drive when `servo`
    /// is `None`.
    pub motor: MotorGains,
    /// The servo drive (`drive`; the default of an axis with a joint):
    /// `None` when the scene gives `motor` or the axis has no joint.
    pub servo: Option<ServoGains>,
    /// Whether the joint has a holding brake that holds it while the servo
    /// is off (default false: a servo-off joint is free and falls under
    /// gravity).
    pub holding_brake: bool,
    /// Where the `[[axes]]` entry's `name` is written.
    pub location: Location,
}

/// A servo drive's gains and limits (`[[axes]] drive`; the loops are the
/// plant's, `plant/servo_drive.rs`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ServoGains {
    /// `PositionLoopBandwidth`, Hz.
    pub position_loop_bandwidth_hz: f64,
    /// `PositionIntegratorBandwidth`, Hz (0: no integrator).
    pub position_integrator_bandwidth_hz: f64,
    /// `VelocityLoopBandwidth`, Hz.
    pub velocity_loop_bandwidth_hz: f64,
    /// `VelocityIntegratorBandwidth`, Hz (0: no integrator).
    pub velocity_integrator_bandwidth_hz: f64,
    /// `VelocityFeedforwardGain`, %.
    pub velocity_feedforward_gain_pct: f64,
    /// `AccelerationFeedforwardGain`, %.
    pub acceleration_feedforward_gain_pct: f64,
    /// `TorqueLimitPositive`, N·m or N (`None`: no limit).
    pub torque_limit_positive: Option<f64>,
    /// `TorqueLimitNegative`, N·m or N, ≤ 0 (`None`: no limit).
    pub torque_limit_negative: Option<f64>,
    /// `SystemInertia`, kg·m² or kg (`None`: the joint's inertia at the
    /// initial pose).
    pub system_inertia: Option<f64>,
}

impl Default for ServoGains {
    fn default() -> Self {
        Self {
            position_loop_bandwidth_hz: 20.0,
            position_integrator_bandwidth_hz: 0.0,
            velocity_loop_bandwidth_hz: 80.0,
            velocity_integrator_bandwidth_hz: 15.0,
            velocity_feedforward_gain_pct: 100.0,
            acceleration_feedforward_gain_pct: 100.0,
            torque_limit_positive: None,
            torque_limit_negative: None,
            system_inertia: None,
        }
    }
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
    /// Draw the beams and rays of the sensors, coloured by state
    /// (`show_sensors`, default false).
    pub show_sensors: bool,
    /// Where the entry's `name` is written.
    pub location: Location,
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
    /// `LINT` (64-bit).
    Lint,
    /// `USINT` (unsigned 8-bit).
    Usint,
    /// `UINT` (unsigned 16-bit).
    Uint,
    /// `ULINT` (unsigned 64-bit).
    Ulint,
    /// `FBD_TIMER` (TONR, TOFR, RTOR in Structured Text).
    FbdTimer,
    /// `FBD_COUNTER` (CTUD).
    FbdCounter,
    /// `FBD_ONESHOT` (OSRI, OSFI).
    FbdOneshot,
    /// `R_TRIG` (IEC dialect only).
    RTrig,
    /// `F_TRIG` (IEC dialect only).
    FTrig,
    /// `TON` (IEC dialect only; `PT`, `ET` in ms).
    Ton,
    /// `TOF` (IEC dialect only; `PT`, `ET` in ms).
    Tof,
    /// `TIMER` (ladder TON, TOF, RTO; `PRE`, `ACC` in ms).
    Timer,
    /// `COUNTER` (ladder CTU, CTD).
    Counter,
    /// `CONTROL` (ladder shift, FIFO and LIFO instructions).
    Control,
    /// `REAL`.
    Real,
    /// `LREAL`.
    Lreal,
    /// `MOTION_INSTRUCTION` (Logix control structure: .EN, .DN, .ER, .IP, .PC ...).
    MotionInstruction,
    /// `COORDINATE_SYSTEM`; its value lists the member axes.
    CoordinateSystem,
    /// `MOTION_GROUP`: the controller's one motion group, every axis in it
    /// (MGS, MGSD, MGSR, MGSP; its status words).
    MotionGroup,
    /// `CAM` (one cam point: master, slave, segment type).
    Cam,
    /// `CAM_PROFILE` (filled by MCCP).
    CamProfile,
    /// `OUTPUT_CAM` (one output cam element, MAOC).
    OutputCam,
    /// `OUTPUT_COMPENSATION` (one output bit's compensation, MAOC).
    OutputCompensation,
    /// A PLCopen function-block instance.
    FunctionBlock(FunctionBlock),
    /// A `[[data_types]]` structure, or a string type (`STRING` and the
    /// user string types).
    User(UserType),
}

/// A data type of the scene's [`Scene::data_types`]: its index there and
/// its name.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct UserType {
    /// Index in [`Scene::data_types`] (`STRING` is 0).
    pub index: u16,
    /// The name as declared.
    pub name: &'static str,
}

/// The predefined `STRING` type's index in [`Scene::data_types`].
pub const STRING_TYPE: UserType = UserType {
    index: 0,
    name: "STRING",
};

/// The characters a `STRING` holds (`DATA` is `SINT[82]`).
pub const STRING_LENGTH: usize = 82;

/// The longest user string type, characters.
pub const MAX_STRING_LENGTH: usize = 65_535;

/// `name` with a `'static` lifetime, so that [`BaseType`] stays `Copy`
/// with a data type's name in it. Each distinct name is kept once for the
/// life of the process (a scene declares a handful).
pub(crate) fn intern(name: &str) -> &'static str {
    use std::collections::BTreeSet;
    use std::sync::{Mutex, PoisonError};
    static NAMES: Mutex<BTreeSet<&'static str>> = Mutex::new(BTreeSet::new());
    let mut names = NAMES.lock().unwrap_or_else(PoisonError::into_inner);
    if let Some(known) = names.get(name) {
        return known;
    }
    let kept: &'static str = Box::leak(name.to_owned().into_boxed_str());
    names.insert(kept);
    kept
}

/// `[[data_types]]`: a user-defined structure (UDT), or a string type
/// (`string_length`). `STRING` itself is [`Scene::data_types`]`[0]`.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct DataTypeDef {
    /// The type's name.
    pub name: String,
    /// `description`.
    pub description: String,
    /// The members, in declaration order (none for a string type).
    pub members: Vec<MemberDef>,
    /// A string type's `DATA` length in characters (`LEN` DINT, `DATA`
    /// SINT[n]).
    pub string_length: Option<usize>,
    /// Where the entry's `name` is written (line 0 for `STRING`).
    pub location: Location,
}

impl DataTypeDef {
    /// The predefined `STRING`.
    #[must_use]
    pub fn string() -> DataTypeDef {
        DataTypeDef {
            name: "STRING".to_owned(),
            description: "the predefined string type: LEN DINT, DATA SINT[82]".to_owned(),
            members: Vec::new(),
            string_length: Some(STRING_LENGTH),
            location: Location { line: 0, column: 0 },
        }
    }
}

/// One member of a [`DataTypeDef`].
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct MemberDef {
    /// The member's name.
    pub name: String,
    /// Its type: a scalar, a string type or another data type; one
    /// dimension at most (`dimension`).
    pub ty: TagType,
    /// `description`.
    pub description: String,
    /// Where the member's `name` is written.
    pub location: Location,
}

impl BaseType {
    const NAMED: [(&'static str, BaseType); 28] = [
        ("BOOL", BaseType::Bool),
        ("SINT", BaseType::Sint),
        ("INT", BaseType::Int),
        ("DINT", BaseType::Dint),
        ("LINT", BaseType::Lint),
        ("USINT", BaseType::Usint),
        ("UINT", BaseType::Uint),
        ("UDINT", BaseType::Udint),
        ("ULINT", BaseType::Ulint),
        ("FBD_TIMER", BaseType::FbdTimer),
        ("FBD_COUNTER", BaseType::FbdCounter),
        ("FBD_ONESHOT", BaseType::FbdOneshot),
        ("R_TRIG", BaseType::RTrig),
        ("F_TRIG", BaseType::FTrig),
        ("TON", BaseType::Ton),
        ("TOF", BaseType::Tof),
        ("TIMER", BaseType::Timer),
        ("COUNTER", BaseType::Counter),
        ("CONTROL", BaseType::Control),
        ("REAL", BaseType::Real),
        ("LREAL", BaseType::Lreal),
        ("MOTION_INSTRUCTION", BaseType::MotionInstruction),
        ("COORDINATE_SYSTEM", BaseType::CoordinateSystem),
        ("MOTION_GROUP", BaseType::MotionGroup),
        ("CAM", BaseType::Cam),
        ("CAM_PROFILE", BaseType::CamProfile),
        ("OUTPUT_CAM", BaseType::OutputCam),
        ("OUTPUT_COMPENSATION", BaseType::OutputCompensation),
    ];

    /// An instruction's structure the twin lays out itself (`FBD_TIMER`,
    /// `FBD_COUNTER`, `FBD_ONESHOT`, `R_TRIG`, `F_TRIG`, `TON`, `TOF`),
    /// which keeps its state in tag memory and takes no initial value.
    #[must_use]
    pub fn is_instruction_structure(self) -> bool {
        matches!(
            self,
            BaseType::FbdTimer
                | BaseType::FbdCounter
                | BaseType::FbdOneshot
                | BaseType::RTrig
                | BaseType::FTrig
                | BaseType::Ton
                | BaseType::Tof
                | BaseType::Timer
                | BaseType::Counter
                | BaseType::Control
                | BaseType::OutputCam
                | BaseType::OutputCompensation
        )
    }

    /// The type name as written in a scene.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            BaseType::FunctionBlock(fb) => return fb.name(),
            BaseType::User(u) => return u.name,
            _ => {}
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
            .chain(["STRING"])
            .collect()
    }

    /// Whether its values live in tag memory (numbers, BOOL, CAM points),
    /// not in the planner (control structures, coordinate systems, cam
    /// profiles, function blocks) or in an instruction's structure.
    #[must_use]
    pub fn in_tag_memory(self) -> bool {
        self.is_atomic() || matches!(self, BaseType::Cam | BaseType::User(_))
    }

    /// BOOL or a number (what an Add-On Instruction's Input or Output
    /// parameter may be).
    #[must_use]
    pub fn is_atomic(self) -> bool {
        matches!(
            self,
            BaseType::Bool
                | BaseType::Sint
                | BaseType::Int
                | BaseType::Dint
                | BaseType::Lint
                | BaseType::Usint
                | BaseType::Uint
                | BaseType::Udint
                | BaseType::Ulint
                | BaseType::Real
                | BaseType::Lreal
        )
    }

    pub(super) fn integer_range(self) -> Option<(i64, i64)> {
        match self {
            BaseType::Sint => Some((i8::MIN.into(), i8::MAX.into())),
            BaseType::Int => Some((i16::MIN.into(), i16::MAX.into())),
            BaseType::Dint => Some((i32::MIN.into(), i32::MAX.into())),
            BaseType::Udint => Some((0, u32::MAX.into())),
            BaseType::Lint | BaseType::Ulint => Some((i64::MIN, i64::MAX)),
            BaseType::Usint => Some((0, u8::MAX.into())),
            BaseType::Uint => Some((0, u16::MAX.into())),
            _ => None,
        }
    }
}

/// An alias tag (`[[aliases]]`): a name that stands for another tag, a
/// member, an element or a bit of one (Logix `TagType="Alias"`).
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct Alias {
    /// Its name.
    pub name: String,
    /// What it stands for, parsed (`Recipe.Count`, `Flags.3`, `Pos[2]`).
    pub target: crate::st::ast::Ref,
    /// `description`.
    pub description: String,
    /// Where its `name` is written.
    pub location: Location,
}

/// What a scene took from its Studio 5000 export.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct L5xImport {
    /// The export, relative to the working folder as the scene names it.
    pub path: PathBuf,
    /// What it holds that the twin does not simulate: (L5X line, what).
    pub report: Vec<(usize, String)>,
    /// What `[controller] not_simulated` skipped.
    pub skipped: Vec<String>,
    /// The standalone scene it expands to (`twin import`).
    pub expanded: std::sync::Arc<str>,
    /// The routine files of the standalone scene: path relative to the
    /// scene's folder, text.
    pub routines: Vec<(PathBuf, std::sync::Arc<str>)>,
}

impl Scene {
    /// Every program: each task's, in order, then the controller fault
    /// handler's.
    pub fn programs(&self) -> impl Iterator<Item = &ProgramDef> {
        self.tasks
            .iter()
            .flat_map(|t| &t.programs)
            .chain(self.controller.fault_handler.as_ref())
    }

    /// The coarse update period, s (the scene writes ms).
    #[must_use]
    pub fn coarse_update_s(&self) -> f64 {
        self.coarse_update_ms / 1000.0
    }

    /// The physics step, s (the scene writes ms).
    #[must_use]
    pub fn physics_step_s(&self) -> f64 {
        self.physics_step_ms / 1000.0
    }

    /// Every file the scene reads: the scene itself, the URDF, every
    /// routine, every obstacle mesh (the URDF's own meshes are the
    /// plant's). Outputs must not be written over any of them.
    pub fn input_files(&self) -> Vec<PathBuf> {
        let mut files = vec![self.path.clone(), self.robot.urdf.clone()];
        for task in &self.tasks {
            for program in &task.programs {
                files.push(program.main.path.clone());
                files.extend(program.routines.iter().map(|r| r.path.clone()));
            }
        }
        for o in &self.obstacles {
            if let Shape::Mesh { path, .. } = &o.shape {
                files.push(path.clone());
            }
        }
        files
    }
}

/// The largest length a scene or URDF may give (a size, a radius, a
/// position's coordinate), m: a cell is metres across, and parry's contact
/// queries fail on shapes of astronomical size.
pub const MAX_LENGTH_M: f64 = 1e4;

/// The largest `max_velocity` of an axis, units/s: at it a move reaches
/// the position bound (`planner::axis::MAX_POSITION`, 10⁹ units) in a
/// second; a jog at 10³⁰⁷ units/s reached infinity.
pub const MAX_AXIS_SPEED: f64 = 1e9;

/// The largest `max_acceleration` and `max_deceleration`, units/s².
pub const MAX_AXIS_ACCELERATION: f64 = 1e12;

/// The largest `max_jerk`, units/s³.
pub const MAX_AXIS_JERK: f64 = 1e15;

/// The largest velocity and acceleration feed-forward gain of a servo
/// drive, % (the command fed forward twice over; 10³⁰⁰ % drove a joint
/// into its limit with 10²⁹⁹ N·m and exit 0).
pub const MAX_FEEDFORWARD_PCT: f64 = 200.0;

/// The largest magnitude of a servo drive's torque limits, N·m (N for a
/// linear joint): more than any motor in a cell gives.
pub const MAX_DRIVE_TORQUE: f64 = 1e7;

/// The most 2π × a servo loop's bandwidth × the physics substep may be.
/// The drive closes its loops explicitly once a substep, and such a
/// proportional loop diverges past 2 (each substep overshoots the error
/// it corrects); 1.5 leaves room for the cascade of position and velocity
/// loops. The default 80 Hz velocity loop is 0.50 at a 1 ms substep and
/// 1.01 at 2 ms (a 2 ms physics step with one substep, which runs within
/// 1 % of the default's following error).
pub const MAX_LOOP_BANDWIDTH_STEP: f64 = 1.5;

/// The largest mesh scale factor.
pub const MAX_MESH_SCALE: f64 = 1e6;

/// The widest or tallest camera image, pixels: the texture size every
/// wgpu adapter supports (8192).
pub const MAX_IMAGE_PX: u32 = 8192;

/// The longest run a scene (or `--duration`) may ask for: 10⁶ s of
/// simulated time (11.6 days), so that a run's length is always bounded.
pub const MAX_DURATION_S: f64 = 1e6;

/// The shortest physics step: 10 µs, at most 3,200 physics steps per
/// coarse update (32 ms), so an update always ends.
pub const MIN_PHYSICS_STEP_MS: f64 = 0.01;

/// The most elements a `CAM` or `CAM_PROFILE` array may have: MCCP's
/// `Length` operand is a UINT, so no longer cam can be calculated.
pub const MAX_CAM_ARRAY_LEN: usize = 65_535;

/// The most elements any other array tag may have. Logix limits arrays by
/// controller memory; here a million elements (tens of MB) is the bound,
/// checked before anything is allocated.
pub const MAX_ARRAY_LEN: usize = 1_000_000;

impl BaseType {
    /// The most elements an array of this type may have
    /// ([`MAX_CAM_ARRAY_LEN`] or [`MAX_ARRAY_LEN`]).
    pub fn max_array_len(self) -> usize {
        match self {
            BaseType::Cam | BaseType::CamProfile => MAX_CAM_ARRAY_LEN,
            _ => MAX_ARRAY_LEN,
        }
    }
}

/// A tag's type: an element type, optionally an array of one to three
/// dimensions, `TYPE[N]`, `TYPE[N,M]`, `TYPE[N,M,K]` (row-major: the last
/// subscript varies fastest).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct TagType {
    /// Element type.
    pub base: BaseType,
    /// `Some(N)` for arrays of N (> 0) elements in all.
    pub array_len: Option<usize>,
    /// The dimensions, first to last; 0 past the last one (all 0 for a
    /// scalar).
    pub dims: [usize; 3],
}

impl TagType {
    /// A scalar, or a one-dimensional array of `len` elements.
    #[must_use]
    pub fn new(base: BaseType, len: Option<usize>) -> TagType {
        TagType {
            base,
            array_len: len,
            dims: [len.unwrap_or(0), 0, 0],
        }
    }

    /// The dimensions that are there.
    #[must_use]
    pub fn dimensions(&self) -> &[usize] {
        let n = self.dims.iter().take_while(|d| **d > 0).count();
        &self.dims[..n]
    }
}

impl fmt::Display for TagType {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.dimensions() {
            [] => f.write_str(self.base.name()),
            dims => {
                let dims: Vec<String> = dims.iter().map(usize::to_string).collect();
                write!(f, "{}[{}]", self.base.name(), dims.join(","))
            }
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
    pub(super) fn default_segment() -> SegmentType {
        SegmentType::Cubic
    }

    /// A point a `CAM` tag's value leaves out: the controller's initial
    /// one (master 0, slave 0, linear).
    #[must_use]
    pub fn initial() -> CamPoint {
        CamPoint {
            master: 0.0,
            slave: 0.0,
            segment_type: SegmentType::Linear,
        }
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
    /// A string type's characters (ASCII, at most its length).
    Text(String),
    /// A data type's members by index in [`DataTypeDef::members`]
    /// (`None`: zero).
    Struct(Vec<Option<TagValue>>),
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
    /// `MC_MoveModulo` instances: the `Options` input their declaration
    /// sets (`ST_MoveOptions`; all off when the table is absent).
    pub move_options: planner::modulo::MoveOptions,
    /// A program tag's `usage` (1756-PM021): local, or a program
    /// parameter.
    pub usage: Usage,
    /// A parameter's `connection`, if it has one.
    pub connection: Option<Connection>,
    /// `constant = true`: no routine writes it (a write is refused at
    /// load).
    pub constant: bool,
    /// `description`: the tag's description, as Studio 5000 shows it.
    pub description: String,
    /// `external_access`: what HMIs and other controllers may do with it.
    pub external_access: ExternalAccess,
    /// `scheduled_output`: a DINT Output word on a scheduled output
    /// module (1756-OB16IS), tied to an axis' output cam: its bits switch
    /// at the interpolated times inside the coarse update.
    pub scheduled_output: Option<ScheduledOutput>,
    /// Where the entry's `name` is written.
    pub location: Location,
}

/// A tag's External Access (1756-PM004): recorded; the twin has no HMI or
/// other controller reading its tags.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ExternalAccess {
    /// `"read_write"` (the default).
    #[default]
    ReadWrite,
    /// `"read_only"`.
    ReadOnly,
    /// `"none"`.
    None,
}

impl ExternalAccess {
    /// Every value by its scene word.
    pub const WORDS: [(&'static str, ExternalAccess); 3] = [
        ("read_write", ExternalAccess::ReadWrite),
        ("read_only", ExternalAccess::ReadOnly),
        ("none", ExternalAccess::None),
    ];
}

/// What a program tag is to other programs (1756-PM021, *Program
/// Parameters*).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Usage {
    /// A local tag (the default): its program's only.
    #[default]
    Local,
    /// An Input parameter: takes its connection's value when its
    /// program's scan starts; other programs read it as `\Program.Tag`.
    Input,
    /// An Output parameter: writes its value to its connection when its
    /// program's scan ends; other programs read it as `\Program.Tag`.
    Output,
    /// An InOut parameter: an alias of its connection (required); not
    /// reachable from other programs.
    InOut,
    /// A Public parameter: other programs read and write it as
    /// `\Program.Tag`.
    Public,
}

impl Usage {
    /// Every usage by its scene word.
    pub const WORDS: [(&'static str, Usage); 5] = [
        ("local", Usage::Local),
        ("input", Usage::Input),
        ("output", Usage::Output),
        ("inout", Usage::InOut),
        ("public", Usage::Public),
    ];

    /// Its scene word.
    #[must_use]
    pub fn word(self) -> &'static str {
        Usage::WORDS
            .iter()
            .find(|(_, u)| *u == self)
            .map_or("local", |(w, _)| w)
    }

    /// Whether another program may name it as `\Program.Tag`.
    #[must_use]
    pub fn reachable(self) -> bool {
        matches!(self, Usage::Input | Usage::Output | Usage::Public)
    }
}

/// A parameter's connection: a controller tag, or another program's
/// parameter (`\Program.Param`).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Connection {
    /// A controller tag, by name.
    Controller(String),
    /// Another program's parameter.
    Parameter {
        /// The program.
        program: String,
        /// The parameter.
        param: String,
    },
}

impl Connection {
    /// The tag it names as tag memory stores it (`Tag`, `Program.Param`).
    #[must_use]
    pub fn stored_name(&self) -> String {
        match self {
            Connection::Controller(t) => t.clone(),
            Connection::Parameter { program, param } => format!("{program}.{param}"),
        }
    }
}

/// The `coordinate_system` table of a `COORDINATE_SYSTEM` tag (its
/// properties dialog): rates in the member axes' units.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct CoordinateSystemSettings {
    /// The system's properties as the planner takes them: named after the
    /// tag, one axis per member, primary axes the first `primary_axes`
    /// members (default: the member count, at most 3), the rates and
    /// tolerances in the members' units with the planner's defaults.
    pub system: CoordinateSystemConfig,
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
        /// The condition, e.g. `MoveTable.Done` (the program compiles it).
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
    /// The parsed call (the program compiles it).
    pub call: Call,
    /// Where the `call` string is written.
    pub location: Location,
}

/// How a call passes a parameter.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AoiUsage {
    /// Copied into the instance before the logic runs.
    Input,
    /// Copied out of the instance after it.
    Output,
    /// Passed by reference.
    InOut,
}

/// A parameter (not `EnableIn`/`EnableOut`).
#[derive(Debug, Clone, PartialEq)]
pub struct AoiParam {
    /// Its name.
    pub name: String,
    /// Its `DataType` as written (`DINT`, `TIMER`, `AXIS_CIP_DRIVE` …).
    pub data_type: String,
    /// Its type, when it is one a tag may have (`None`: an axis type).
    pub ty: Option<TagType>,
    /// Input, Output or InOut.
    pub usage: AoiUsage,
    /// A call passes it.
    pub required: bool,
    /// An InOut the instruction may not write.
    pub constant: bool,
    /// Where its `Name` is.
    pub span: crate::source::Span,
}

/// An Add-On Instruction the program may call.
#[derive(Debug, Clone, PartialEq)]
pub struct AoiDef {
    /// Its name (the call's, and its instances' data type's).
    pub name: String,
    /// The data type of its instances.
    pub data_type: UserType,
    /// Its parameters in definition order, `EnableIn`/`EnableOut` left out.
    pub parameters: Vec<AoiParam>,
    /// Its local tags' names (members of the instance).
    pub locals: Vec<String>,
    /// Member default values (parameters' and local tags' `DefaultData`)
    /// of scalars: member, value.
    pub defaults: Vec<(String, f64)>,
    /// `Logic`.
    pub logic: RoutineDef,
    /// `Prescan`, when `ExecutePrescan`.
    pub prescan: Option<RoutineDef>,
    /// `EnableInFalse`, when `ExecuteEnableInFalse`.
    pub enable_in_false: Option<RoutineDef>,
    /// Where its `Name` is.
    pub span: crate::source::Span,
    /// The `add_on_instructions` entry it came from.
    pub location: Location,
}

impl AoiDef {
    /// The parameters a call passes after the instance, in order.
    pub fn required(&self) -> impl Iterator<Item = &AoiParam> {
        self.parameters.iter().filter(|p| p.required)
    }

    /// A parameter by name (case-insensitive).
    #[must_use]
    pub fn parameter(&self, name: &str) -> Option<&AoiParam> {
        self.parameters.iter().find(|p| p.name.eq_ignore_ascii_case(name))
    }
}

/// A `[trace] rungs` entry: a ladder rung whose condition-out is traced
/// as an extra column.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct TraceRung {
    /// The reference as written, `Program/Routine:N` (the column's name).
    pub text: String,
    /// The program.
    pub program: String,
    /// The routine (its name: the file stem).
    pub routine: String,
    /// The rung's number (from 0).
    pub rung: u32,
}

/// A `[trace] tags` entry: a reference traced as an extra column.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct TraceTag {
    /// The reference as written (the column's name).
    pub text: String,
    /// The parsed reference (the program compiles it).
    pub expr: Expr,
}

/// `[snapshots]`: frames compared with golden images.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct Snapshots {
    /// Frame indices, sorted, distinct.
    pub frames: Vec<u32>,
}

/// What the twin does when a live check finds a contact.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize)]
#[serde(rename_all = "lowercase")]
#[non_exhaustive]
pub enum Reaction {
    /// Record the event and keep going (default).
    #[default]
    Report,
    /// Coordinated stop of every axis with its configured deceleration;
    /// the instances in process get `CommandAborted`.
    Stop,
    /// End the run after the physics step of the contact; the `twin`
    /// binary exits with code 3.
    Abort,
}

/// How a mesh collision shape is approximated.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize)]
#[serde(rename_all = "snake_case")]
#[non_exhaustive]
pub enum MeshApproximation {
    /// One convex hull per mesh (default): fast, conservative (never misses
    /// a contact the mesh has, may report one in a concavity).
    #[default]
    ConvexHull,
    /// A convex decomposition (parry's VHACD with default parameters): follows
    /// concave meshes, slower to build and to query.
    ConvexDecomposition,
}

/// What the pre-flight sweep does with a predicted collision.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize)]
#[serde(rename_all = "lowercase")]
#[non_exhaustive]
pub enum Preflight {
    /// No sweep.
    Off,
    /// Sweep every started move and report a predicted collision (default).
    #[default]
    Report,
    /// As `report`, and reject the move before the physics runs any of it:
    /// an MC_MoveModulo instance gets `Error` with ErrorID 16#422C, an
    /// MCLM/MCCM `.ER` with ERR 200; axes at rest do not move at all
    /// (`plant/collide.rs`).
    Reject,
}

/// A tool or payload shape carried by a link.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct Tool {
    /// Body name in events and trace columns (default: `tool`).
    pub name: String,
    /// The URDF link carrying it.
    pub link: String,
    /// Where `link` is written.
    pub link_location: Location,
    /// The geometry.
    pub shape: Shape,
    /// Position in the link frame, metres (default: zeros).
    pub position_m: [f64; 3],
    /// Roll, pitch, yaw in the link frame, degrees (default: zeros).
    pub rpy_deg: [f64; 3],
}

/// Two bodies allowed to touch (never reported).
#[derive(Debug, Clone, PartialEq)]
pub struct AllowedPair {
    /// First body (link or obstacle or tool name).
    pub a: String,
    /// Second body.
    pub b: String,
    /// Where the pair is written.
    pub location: Location,
}

/// `[collision]`: collision checking is on when the table is present.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct CollisionSettings {
    /// Reaction to a live contact (default: report).
    pub reaction: Reaction,
    /// Mesh approximation for URDF and obstacle meshes (default: convex hull).
    pub meshes: MeshApproximation,
    /// Check robot bodies against each other, except adjacent links and
    /// allowed pairs (default: true).
    pub self_collision: bool,
    /// Pairs never reported.
    pub allowed_pairs: Vec<AllowedPair>,
    /// Pre-flight sweep of started moves (default: report).
    pub preflight: Preflight,
    /// Sweep resolution: the largest distance any point of the robot moves
    /// between two samples once it is near an obstacle, metres (default 0.001).
    pub sweep_resolution_m: f64,
    /// Optional tool/payload shape.
    pub tool: Option<Tool>,
    /// Where the `[collision]` table is written.
    pub location: Location,
}

impl Default for CollisionSettings {
    /// The settings of an empty `[collision]` table.
    fn default() -> Self {
        CollisionSettings {
            reaction: Reaction::default(),
            meshes: MeshApproximation::default(),
            self_collision: true,
            allowed_pairs: Vec::new(),
            preflight: Preflight::default(),
            sweep_resolution_m: 0.001,
            tool: None,
            location: Location::default(),
        }
    }
}

/// A `COORDINATE_SYSTEM` tag's `geometry` table.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct GeometrySettings {
    /// `type`: the geometry.
    pub kind: GeometryKind,
    /// `transform_dimension` (default: 2 for the SCARA, Delta 2D and SCARA
    /// Delta geometries, 3 for Delta 3D, else the number of members, at
    /// most 3).
    pub transform_dimension: usize,
    /// `link_lengths` (L1, L2), `base_offsets`, `end_effector_offsets`
    /// (coordinate units) and `zero_angles_deg` (default: 0).
    pub params: GeometryParams,
    /// `base_link`: the URDF link whose frame is the MCT robot frame
    /// (required for a transform's target; default: none).
    pub base_link: Option<String>,
    /// `tool_link`: the URDF link whose origin is the tool point (required
    /// for a transform's target; default: none).
    pub tool_link: Option<String>,
    /// `platform_joints` (parallel geometries; default: none).
    pub platform_joints: Vec<String>,
    /// `forearm_joints`: `[yaw, pitch]` per arm (parallel geometries;
    /// default: none).
    pub forearm_joints: Vec<[String; 2]>,
    /// `forearm_tip_links` (parallel geometries; default: none).
    pub forearm_tip_links: Vec<String>,
    /// `ball_links` (parallel geometries; default: none).
    pub ball_links: Vec<String>,
    /// Where the table is written.
    pub location: Location,
}

/// The watchdog of a task that does not set `watchdog_ms`, as on the
/// controller.
pub const DEFAULT_WATCHDOG_MS: f64 = 500.0;

/// Which Structured Text a routine is written in.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Dialect {
    /// Studio 5000 Logix ST (the default): what verifies on a controller.
    #[default]
    Logix,
    /// IEC 61131-3 / TwinCAT additions: `R_TRIG`, `F_TRIG`, `TON`, `TOF`
    /// and PLCopen function blocks called with named inputs.
    Iec,
}

/// A task: what starts its scans, its priority and watchdog, its
/// programs (1756-PM005).
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct Task {
    /// Task name.
    pub name: String,
    /// What starts a scan.
    pub kind: TaskKind,
    /// Priority, 1 (highest) to 15; a continuous task has none and runs
    /// below every other ([`CONTINUOUS_PRIORITY`]).
    pub priority: u8,
    /// Watchdog, ms (default 500).
    pub watchdog_ms: f64,
    /// `inhibit`: the task is not scanned (its triggers are ignored).
    pub inhibit: bool,
    /// Programs in scan order.
    pub programs: Vec<ProgramDef>,
    /// Where the task's `name` is written.
    pub location: Location,
}

/// The priority a continuous task runs at: below every periodic and
/// event task (1 ..= 15).
pub const CONTINUOUS_PRIORITY: u8 = 16;

/// What starts a task's scans.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum TaskKind {
    /// `type = "periodic"` (the default with `period_ms`): every period.
    Periodic {
        /// Period, ms (0.1 to 2,000,000).
        period_ms: f64,
    },
    /// `type = "continuous"`: scanned again as soon as a scan ends, in the
    /// time the other tasks leave.
    Continuous,
    /// `type = "event"`: by its trigger, or by its timeout.
    Event {
        /// What triggers it.
        trigger: EventTrigger,
        /// `timeout_ms`: a scan when no trigger came within it.
        timeout_ms: Option<f64>,
    },
}

/// `[[tags]] scheduled_output`: the axis and output cam execution target
/// a scheduled output module is tied to, and the response time of the
/// device it switches (a glue valve).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScheduledOutput {
    /// The axis (index into the scene's axes).
    pub axis: usize,
    /// The output cam execution target.
    pub execution_target: u32,
    /// How long after a switch the device acts, s (`response_ms`).
    pub response_s: f64,
}

/// An event task's trigger.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EventTrigger {
    /// `"event_instruction"`: an `EVENT(Task)` a routine executes.
    EventInstruction,
    /// `"motion_group_execution"`: every coarse update, after the motion
    /// planner.
    MotionGroupExecution,
    /// `"axis_registration_1"` / `"axis_registration_2"` with `axis`: each
    /// registration event of that input of that axis.
    AxisRegistration {
        /// The axis (index into the scene's axes).
        axis: usize,
        /// The input, 1 or 2.
        input: u8,
    },
    /// `"axis_watch"` with `axis`: each watch event of that axis (MAW).
    AxisWatch {
        /// The axis (index into the scene's axes).
        axis: usize,
    },
}

impl EventTrigger {
    /// Every trigger by its scene word.
    pub const WORDS: [(&'static str, EventTrigger); 2] = [
        ("event_instruction", EventTrigger::EventInstruction),
        ("motion_group_execution", EventTrigger::MotionGroupExecution),
    ];
}

/// `[controller]`: the controller's own properties.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct ControllerSettings {
    /// `report_overflow_faults` (Controller Properties, Advanced: "Report
    /// Overflow Faults"): an arithmetic overflow records minor fault 4/4.
    pub report_overflow_faults: bool,
    /// `statement_us`: the nominal time of one executed statement (and one
    /// loop test), µs.
    pub statement_us: f64,
    /// `start_time`: the wall clock when the run starts, µs since
    /// 1970-01-01T00:00:00Z (`WALLCLOCKTIME`).
    pub start_time_us: i64,
    /// `[controller.fault_handler]`: the program of the Controller Fault
    /// Handler, scanned when a major fault no program's fault routine
    /// cleared would stop the controller.
    pub fault_handler: Option<ProgramDef>,
}

/// The nominal time of one statement unless `[controller] statement_us`
/// says otherwise, µs.
pub const DEFAULT_STATEMENT_US: f64 = 1.0;

/// The most `[[tasks]]` a controller has (1756-RM084: ControlLogix 32).
pub const MAX_TASKS: usize = 32;

/// The most programs one task schedules (1756-RM084: 1,000).
pub const MAX_PROGRAMS_PER_TASK: usize = 1000;

/// The least `[controller] statement_us`, µs. The controller's one clock
/// advances by a statement's time for each statement it executes, and it
/// never runs ahead of simulated time, so a run executes at most
/// 1 s / `statement_us` statements per simulated second: 10⁶ at the
/// default, 10⁸ at this bound, which the interpreter (10–25 ns a
/// statement) runs in one to three seconds of wall time.
pub const MIN_STATEMENT_US: f64 = 0.01;

/// The wall clock at the start of a run unless `[controller] start_time`
/// says otherwise: 2000-01-01T00:00:00Z, µs since 1970.
pub const DEFAULT_START_TIME_US: i64 = 946_684_800_000_000;

impl Default for ControllerSettings {
    fn default() -> Self {
        ControllerSettings {
            report_overflow_faults: true,
            statement_us: DEFAULT_STATEMENT_US,
            start_time_us: DEFAULT_START_TIME_US,
            fault_handler: None,
        }
    }
}

/// A program of a task.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct ProgramDef {
    /// Program name.
    pub name: String,
    /// Program-scoped tags (they shadow controller tags of the same name).
    pub tags: Vec<Tag>,
    /// Program-scoped aliases (`[[tasks.programs.aliases]]`).
    pub aliases: Vec<Alias>,
    /// The main routine: the one the task scans.
    pub main: RoutineDef,
    /// Further routines, called with `JSR`.
    pub routines: Vec<RoutineDef>,
    /// `fault_routine`: the routine (an index into `routines`) that runs
    /// when an instruction in the program raises a major fault.
    pub fault_routine: Option<usize>,
    /// `disabled`: the program is not scanned (`DisableFlag`).
    pub disabled: bool,
    /// Where the program's `name` is written.
    pub location: Location,
}

/// A routine file, parsed.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct RoutineDef {
    /// Routine name: the file stem.
    pub name: String,
    /// The file, relative to the scene's folder resolved.
    pub path: PathBuf,
    /// Its dialect.
    pub dialect: Dialect,
    /// The parsed routine.
    pub routine: Routine,
}
