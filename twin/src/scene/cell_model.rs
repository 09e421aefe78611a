//! The validated cell: workpieces (`[[part_types]]`), where they appear
//! and leave (`[[sources]]`, `[[sinks]]`), what carries them
//! (`[[conveyors]]`) and what senses them (`[[sensors]]`), each wired to
//! the program through tag references ([`IoTag`]).

use super::shape::{Location, Shape};
use crate::st::ast::Expr;

/// The most parts alive at once; past it a source stops spawning and the
/// summary says so.
pub const MAX_LIVE_PARTS: usize = 10_000;

/// The cell: empty when the scene has none of its tables.
#[derive(Debug, Clone, PartialEq, Default)]
#[non_exhaustive]
pub struct Cell {
    /// `[[part_types]]`, in file order.
    pub part_types: Vec<PartType>,
    /// `[[sources]]`, in file order.
    pub sources: Vec<Source>,
    /// `[[sinks]]`, in file order.
    pub sinks: Vec<Sink>,
    /// `[[conveyors]]`, in file order.
    pub conveyors: Vec<Conveyor>,
    /// `[[sensors]]`, in file order.
    pub sensors: Vec<Sensor>,
    /// `[[cylinders]]`, in file order.
    pub cylinders: Vec<Cylinder>,
    /// `[[grippers]]`, in file order.
    pub grippers: Vec<Gripper>,
    /// The parts world's step, ms (`parts_step_ms`, default the coarse
    /// update): a multiple of `physics_step_ms` that divides
    /// `coarse_update_ms`.
    pub parts_step_ms: f64,
}

impl Cell {
    /// Whether the scene has no cell at all (no parts world is built).
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.part_types.is_empty()
            && self.conveyors.is_empty()
            && self.sensors.is_empty()
            && self.cylinders.is_empty()
            && self.grippers.is_empty()
    }
}

/// A tag reference a device writes (an input) or reads (an output):
/// a BOOL, a bit of an integer (`DI.3`), a member (`Cell.PartAtPick`), a
/// DINT or a REAL, written as in `[trace] tags`. The program resolves it
/// and checks its type.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct IoTag {
    /// The reference as written (trimmed).
    pub text: String,
    /// The parsed reference.
    pub expr: Expr,
    /// Its field path (`sensors[2].tag`).
    pub field: String,
    /// Where it is written.
    pub location: Location,
}

/// What an [`IoTag`] must be.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum IoKind {
    /// A BOOL or a bit of an integer.
    Bool,
    /// A DINT (a count, a bitmask, encoder counts).
    Dint,
    /// A REAL (an analog value, a speed in %).
    Real,
    /// Three REALs in a row: the first of them (`Pos[0]`).
    Real3,
}

impl IoKind {
    /// The words a message uses.
    #[must_use]
    pub fn describe(self) -> &'static str {
        match self {
            IoKind::Bool => "a BOOL or a bit of an integer (DI.3)",
            IoKind::Dint => "a DINT",
            IoKind::Real => "a REAL",
            IoKind::Real3 => "the first of three REALs (Pos[0] of a REAL[3])",
        }
    }
}

/// Whether the device writes the tag or reads it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum IoDirection {
    /// The device writes it at each input update (a sensor, a status).
    Input,
    /// The device reads it after each update's scans (a command).
    Output,
}

/// `[[part_types]]`: a workpiece.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct PartType {
    /// Name (unique among part types).
    pub name: String,
    /// Shape, in the part's frame (its origin the part's centre).
    pub shape: Shape,
    /// Mass, kg (> 0).
    pub mass_kg: f64,
    /// Coulomb friction coefficient (default 0.6).
    pub friction: f64,
    /// Restitution (default 0).
    pub restitution: f64,
    /// RGBA, each in 0..=1.
    pub color: [f64; 4],
    /// Material, for inductive proximity sensors (`materials`); default
    /// empty.
    pub material: String,
    /// The number a vision system reports for it (default its 1-based
    /// index).
    pub type_id: i32,
    /// Where its name is written.
    pub location: Location,
}

/// When a source spawns.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum SourceTrigger {
    /// Every `period_s` from `start_s`.
    Every {
        /// Period, s.
        period_s: f64,
        /// First spawn, s.
        start_s: f64,
    },
    /// At each rise of a BOOL output.
    On(IoTag),
    /// At the listed times, s (ascending).
    At(Vec<f64>),
}

/// Seeded randomness of a source: each spawn's time, position and yaw
/// move by a uniform amount in ±the value.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[non_exhaustive]
pub struct Jitter {
    /// ± time, s (`every_s` and `at_s` only).
    pub time_s: f64,
    /// ± position along world x, y, z, m.
    pub position_m: [f64; 3],
    /// ± yaw about world z, degrees.
    pub yaw_deg: f64,
    /// The seed (default 0): the same seed, the same parts.
    pub seed: u64,
}

/// `[[sources]]`: where parts appear.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct Source {
    /// Name.
    pub name: String,
    /// Index into [`Cell::part_types`].
    pub part_type: usize,
    /// Spawn position, m.
    pub position_m: [f64; 3],
    /// Spawn orientation, degrees.
    pub rpy_deg: [f64; 3],
    /// When it spawns.
    pub trigger: SourceTrigger,
    /// At most this many parts (`None`: no limit).
    pub count: Option<u32>,
    /// Seeded jitter.
    pub jitter: Jitter,
    /// Spawns (1-based, in this source's order) that do not happen: a
    /// missing part, for bad-case tests.
    pub skip: Vec<u32>,
    /// Where its name is written.
    pub location: Location,
}

/// What a sink counts its parts as.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum SinkOutcome {
    /// A good part out of the cell.
    Delivered,
    /// A part rejected on purpose.
    Rejected,
}

impl SinkOutcome {
    /// The word of the scene and the summary.
    #[must_use]
    pub fn word(self) -> &'static str {
        match self {
            SinkOutcome::Delivered => "delivered",
            SinkOutcome::Rejected => "rejected",
        }
    }
}

/// `[[sinks]]`: a box that removes the parts whose centre enters it.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct Sink {
    /// Name.
    pub name: String,
    /// Centre, m.
    pub position_m: [f64; 3],
    /// Orientation, degrees.
    pub rpy_deg: [f64; 3],
    /// Full size, m.
    pub size_m: [f64; 3],
    /// `as`: delivered (default) or rejected.
    pub outcome: SinkOutcome,
    /// Where its name is written.
    pub location: Location,
}

/// A fault injected into a device for a bad-case test.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum FaultKind {
    /// A sensor reads detected whatever it sees.
    StuckOn,
    /// A sensor reads clear whatever it sees.
    StuckOff,
    /// A conveyor's belt or a cylinder stands still whatever it is told.
    Stalled,
    /// A vacuum gripper has no vacuum: it picks nothing and drops what it
    /// holds.
    NoVacuum,
}

impl FaultKind {
    /// The word of the scene.
    #[must_use]
    pub fn word(self) -> &'static str {
        match self {
            FaultKind::StuckOn => "stuck_on",
            FaultKind::StuckOff => "stuck_off",
            FaultKind::Stalled => "stalled",
            FaultKind::NoVacuum => "no_vacuum",
        }
    }
}

/// `faults = [{ kind, from_s, to_s }]`: a fault active over `[from_s, to_s)`.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub struct DeviceFault {
    /// What fails.
    pub kind: FaultKind,
    /// From, s.
    pub from_s: f64,
    /// Until, s (default: the end of the run).
    pub to_s: f64,
}

impl DeviceFault {
    /// Whether a fault of `kind` is active at `t_s`.
    #[must_use]
    pub fn active(faults: &[DeviceFault], kind: FaultKind, t_s: f64) -> bool {
        faults.iter().any(|f| f.kind == kind && f.from_s <= t_s && t_s < f.to_s)
    }
}

/// A VFD-driven conveyor's I/O.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct Vfd {
    /// Output BOOL: run.
    pub run: IoTag,
    /// Output BOOL: run backwards.
    pub reverse: Option<IoTag>,
    /// Output REAL: speed, % of `max_speed_mps` (without it: 100 %).
    pub speed: Option<IoTag>,
    /// Belt speed at 100 %, m/s.
    pub max_speed_mps: f64,
    /// Ramp, m/s² (up and down).
    pub accel_mps2: f64,
    /// Input BOOL: the belt moves.
    pub running_tag: Option<IoTag>,
    /// Input DINT: belt travel in counts, wrapping at the DINT's range.
    pub encoder_tag: Option<IoTag>,
    /// Encoder counts per metre of belt.
    pub counts_per_m: f64,
}

/// What moves a conveyor's belt.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum ConveyorDrive {
    /// A linear axis: the belt moves at its actual velocity.
    Axis(usize),
    /// A variable-frequency drive told by outputs.
    Vfd(Box<Vfd>),
}

/// `[[conveyors]]`: a belt, a box whose top carries parts along its local +x.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct Conveyor {
    /// Name.
    pub name: String,
    /// Centre, m.
    pub position_m: [f64; 3],
    /// Orientation, degrees.
    pub rpy_deg: [f64; 3],
    /// Full size, m (x the belt's length).
    pub size_m: [f64; 3],
    /// The belt's friction (default 0.8).
    pub friction: f64,
    /// RGBA.
    pub color: [f64; 4],
    /// What moves it.
    pub drive: ConveyorDrive,
    /// Parts at rest on it ride it as kinematic bodies (`ride`, default
    /// true; `plant/material/ride.rs`).
    pub ride: bool,
    /// Injected faults (`stalled`).
    pub faults: Vec<DeviceFault>,
    /// Where its name is written.
    pub location: Location,
}

/// What a sensor detects (`detects`).
#[derive(Debug, Clone, PartialEq, Eq)]
#[non_exhaustive]
pub enum Detect {
    /// Every part.
    Parts,
    /// The parts of one type (index into [`Cell::part_types`]).
    PartType(usize),
    /// Every robot link with a collision shape.
    Robot,
    /// One URDF link (checked against the URDF when the plant is built).
    Link(String),
    /// One obstacle (index into the scene's obstacles).
    Obstacle(usize),
}

/// A sensor kind and its own fields.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum SensorKind {
    /// A through-beam from `from_m` to `to_m` (sensor frame); with
    /// `curtain`, `count` beams `pitch_m` apart along the sensor's z.
    Beam {
        /// Emitter, m.
        from_m: [f64; 3],
        /// Receiver, m.
        to_m: [f64; 3],
        /// Light curtain: (beams, pitch m).
        curtain: Option<(u32, f64)>,
    },
    /// A diffuse (reflective) eye: a ray along the sensor's +x.
    Diffuse {
        /// Range, m.
        range_m: f64,
        /// Linear scaling of the distance: two (distance m, value) points.
        scale: Option<[[f64; 2]; 2]>,
    },
    /// A proximity field (box, sphere or cylinder).
    Proximity {
        /// The field.
        field: Shape,
        /// Materials it sees (inductive); empty: every part.
        materials: Vec<String>,
    },
    /// An occupancy zone.
    Zone {
        /// The zone.
        field: Shape,
    },
    /// The smallest distance between two groups of bodies (`between`); the
    /// BOOL is set while it is below `below_m`.
    Clearance {
        /// The two groups.
        between: [Vec<Detect>; 2],
        /// The threshold, m.
        below_m: f64,
    },
    /// A camera: `latency_ms` after its `trigger` output rises, the part
    /// nearest its field's centre.
    Vision(Box<VisionSpec>),
}

impl SensorKind {
    /// The kind's word.
    #[must_use]
    pub fn word(&self) -> &'static str {
        match self {
            SensorKind::Beam { curtain: None, .. } => "beam",
            SensorKind::Beam { .. } => "light curtain",
            SensorKind::Diffuse { .. } => "diffuse",
            SensorKind::Proximity { materials, .. } if !materials.is_empty() => "inductive proximity",
            SensorKind::Proximity { .. } => "proximity",
            SensorKind::Zone { .. } => "zone",
            SensorKind::Clearance { .. } => "clearance",
            SensorKind::Vision(_) => "vision",
        }
    }
}

/// A vision sensor's own fields.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct VisionSpec {
    /// The field of view (a box, sphere or cylinder).
    pub field: Shape,
    /// The trigger output (BOOL).
    pub trigger: IoTag,
    /// From trigger to result, s.
    pub latency_s: f64,
    /// Where the position goes: the first of three REALs (`Pos[0]`).
    pub position_tag: Option<IoTag>,
    /// The part's angle about the frame's z, degrees (REAL).
    pub angle_tag: Option<IoTag>,
    /// The part type's `type_id` (DINT).
    pub type_tag: Option<IoTag>,
    /// The link whose frame the position is in (`None`: the world).
    pub frame: Option<(String, Location)>,
    /// Position in millimetres (else metres).
    pub millimetres: bool,
}

/// `[[sensors]]`.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct Sensor {
    /// Name.
    pub name: String,
    /// Kind and its fields.
    pub kind: SensorKind,
    /// The BOOL it writes: detected (after `invert` and the delays).
    pub tag: IoTag,
    /// A curtain's DINT bitmask, a diffuse eye's REAL distance.
    pub value_tag: Option<IoTag>,
    /// A zone's DINT count of bodies inside.
    pub count_tag: Option<IoTag>,
    /// The link it is mounted on (`None`: the world).
    pub link: Option<(String, Location)>,
    /// Pose on the link (or in the world), m.
    pub position_m: [f64; 3],
    /// Orientation, degrees.
    pub rpy_deg: [f64; 3],
    /// What it sees (default `["parts"]`).
    pub detects: Vec<Detect>,
    /// Dark-operate / normally closed: the tag is TRUE while nothing is seen.
    pub invert: bool,
    /// The output turns on this long after the target is seen, s.
    pub on_delay_s: f64,
    /// The output turns off this long after the target is gone, s.
    pub off_delay_s: f64,
    /// The input module's RPI, s (`None`: the coarse update).
    pub rpi_s: Option<f64>,
    /// Change of state: an edge updates the tag at once.
    pub cos: bool,
    /// Injected faults (`stuck_on`, `stuck_off`).
    pub faults: Vec<DeviceFault>,
    /// Wired to a registration input: (axis index, input 1 or 2).
    pub registration: Option<(usize, u8)>,
    /// Where its name is written.
    pub location: Location,
}

/// `[[cylinders]]`: a kinematic box (stopper, pusher, diverter) that moves
/// `stroke_m` along its local +x.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct Cylinder {
    /// Name.
    pub name: String,
    /// The box's centre when retracted, m.
    pub position_m: [f64; 3],
    /// Orientation, degrees.
    pub rpy_deg: [f64; 3],
    /// Full size, m.
    pub size_m: [f64; 3],
    /// Travel along the local +x, m.
    pub stroke_m: f64,
    /// Time to extend, s.
    pub extend_s: f64,
    /// Time to retract, s.
    pub retract_s: f64,
    /// Output BOOL: extend.
    pub extend: IoTag,
    /// Output BOOL: retract (double-acting); without it the cylinder is
    /// spring-returned.
    pub retract: Option<IoTag>,
    /// Input BOOL: at the extended end.
    pub extended_tag: Option<IoTag>,
    /// Input BOOL: at the retracted end.
    pub retracted_tag: Option<IoTag>,
    /// RGBA.
    pub color: [f64; 4],
    /// Injected faults (`stalled`).
    pub faults: Vec<DeviceFault>,
    /// Where its name is written.
    pub location: Location,
}

/// What a gripper is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum GripperKind {
    /// A vacuum cup: holds after `build_up_ms`.
    Vacuum,
    /// Fingers: hold after `close_ms`.
    Fingers,
}

impl GripperKind {
    /// The kind's word.
    #[must_use]
    pub fn word(self) -> &'static str {
        match self {
            GripperKind::Vacuum => "vacuum",
            GripperKind::Fingers => "fingers",
        }
    }
}

/// `[[grippers]]`.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct Gripper {
    /// Name.
    pub name: String,
    /// Vacuum or fingers.
    pub kind: GripperKind,
    /// The URDF link it is mounted on (checked when the plant is built).
    pub link: (String, Location),
    /// The TCP on the link, m.
    pub position_m: [f64; 3],
    /// The TCP's orientation, degrees (its z points out of the gripper).
    pub rpy_deg: [f64; 3],
    /// Output BOOL: grip.
    pub grip: IoTag,
    /// Output BOOL: release (blow-off, open).
    pub release: Option<IoTag>,
    /// Input BOOL: a part is held.
    pub holding_tag: Option<IoTag>,
    /// Time from `grip` to holding, s (`build_up_ms` or `close_ms`).
    pub engage_s: f64,
    /// A part within this distance of the TCP is picked, m.
    pub reach_m: f64,
    /// The most the grip holds (weight plus inertial force), N.
    pub max_force_n: f64,
    /// Injected faults (`no_vacuum`).
    pub faults: Vec<DeviceFault>,
    /// Where its name is written.
    pub location: Location,
}
