//! The motion engine: [`MotionTask`], what it holds — per axis, per
//! function-block instance, per control structure, per coordinate system,
//! cam and transform — and the order of the processes in one coarse
//! update ([`MotionTask::update`]); with the reports and calls its methods
//! take and return. Each process's behaviour is an `impl MotionTask` in
//! its own file of `task/` (or, for an instruction's own process such as
//! MAG's gearing, in the instruction's unit), called from here by method;
//! nothing here names those files.

use super::handles::{AxisHandle, CamProfileHandle, CoordHandle, CoordInstructionHandle, FbHandle, InstructionHandle};
use crate::axis::AxisConfig;
use crate::coord::{
    CoordConfigError, CoordMove, CoordMoveError, CoordMoveInputs, CoordStatus, CoordinateSystem, LockDirection,
    McsInputs,
};
use crate::instruction::{FbOutputs, MotionInstructionBits};
use crate::mapc::axis::PositionCamAxis;
use crate::mapc::{MapcOperands, MasterReference};
use crate::mccm::MccmInputs;
use crate::mccp::CamProfileTag;
use crate::mct::instruction::{Mct, Transform, TransformId, TransformTable};
use crate::mct::{GeometryKind, GeometryParams};
use crate::modulo::{MoveModulo, MoveModuloError, MoveModuloInputs};
use crate::profile::{Limits, Profile, Sample};
use crate::servo::{AxisFaults, AxisType, MotionFaults};
use thiserror::Error;

/// A motion task: axes, instances, and the coarse update.
#[derive(Debug, Clone)]
pub struct MotionTask {
    pub(super) dt_s: f64,
    pub(super) updates: u64,
    pub(super) axes: Vec<AxisSlot>,
    pub(super) fbs: Vec<FbSlot>,
    pub(super) instructions: Vec<InstructionSlot>,
    /// Coordinate systems and coordinated instructions (`task/coord.rs`).
    pub(super) coord: CoordState,
    pub(super) cam: CamState,
    /// MCT transforms (`task/mct.rs`).
    pub(super) mct: MctState,
    /// Between [`MotionTask::remove_superimposed`](MotionTask::remove_superimposed) and
    /// [`MotionTask::add_superimposed`](MotionTask::add_superimposed): commands are bases.
    pub(super) superimposed_removed: bool,
    /// The motion group (`task/group.rs`).
    pub(super) group: GroupState,
    /// What the last instruction executed wrote to its output operand
    /// (MCTP's Transform Position), until the caller takes it.
    pub(super) output: Option<[f64; 3]>,
}

impl MotionTask {
    /// Runs one coarse update.
    pub fn update(&mut self) {
        self.updates += 1;
        for i in 0..self.fbs.len() {
            self.evaluate_inputs(FbHandle(i as u32));
        }
        self.evaluate_coord_instructions();
        self.evaluate_mct_instructions();
        self.remove_superimposed();
        for i in 0..self.axes.len() {
            self.advance_axis(AxisHandle(i as u32));
        }
        self.advance_coordinate_systems();
        self.advance_master_links();
        self.advance_cams_and_jogs();
        self.advance_time_cams();
        self.advance_gears();
        self.advance_transforms();
        self.add_superimposed();
        self.advance_homing();
        self.advance_servo_states();
        self.advance_group();
        self.advance_watches();
        self.advance_output_cams();
    }
}

/// The motion group's state kept by the task (`task/group.rs`).
#[derive(Debug, Clone, Default)]
pub(super) struct GroupState {
    /// The MGS whose stop is in process.
    pub(super) stop: Option<InstructionHandle>,
    /// Axes a Fast Disable or Fast Shutdown disables once at rest.
    pub(super) disable_at_rest: Vec<(AxisHandle, Power)>,
    /// Per axis: (`StrobeActualPosition`, `StrobeCommandPosition`) of the
    /// last MGSP.
    pub(super) strobes: Vec<(f64, f64)>,
}

// The task itself: axes, function-block instances, control structures.

#[derive(Debug, Clone)]
pub(super) struct Job {
    pub(super) fb: Option<FbHandle>,
    pub(super) command: MoveModulo,
    pub(super) profile: Profile,
    pub(super) t_s: f64,
    pub(super) target: f64,
    pub(super) generation_done: bool,
    /// A stop ramp (see `task/stop.rs`): never blended into.
    pub(super) stopping: bool,
    /// Where a command started from rest or an abort (not a blend
    /// hand-over) came from, for [`MotionTask::reject_move`](super::MotionTask::reject_move).
    pub(super) origin: Option<Origin>,
}

#[derive(Debug, Clone)]
pub(super) struct AxisSlot {
    pub(super) config: AxisConfig,
    pub(super) command: Sample,
    pub(super) actual: f64,
    /// Change of the fed position over the last update, units/s.
    pub(super) actual_velocity: f64,
    pub(super) fed: bool,
    pub(super) last_direction: f64,
    pub(super) job: Option<Job>,
    pub(super) buffered: Option<(FbHandle, MoveModulo)>,
    /// Servo state, faults (`task/servo.rs`).
    pub(super) servo: ServoSlot,
    /// A MAM or MAJ running on top of the axis' base motion
    /// (`task/superimposed.rs`).
    pub(super) superimposed: Option<SuperRun>,
    /// MAG gearing of the axis to a master (`task/instructions/mag.rs`).
    pub(super) gear: Option<GearRun>,
    /// Registration inputs 1 and 2 (`task/instructions/mar.rs`).
    pub(super) registration: [crate::registration::RegistrationInput<InstructionHandle>; 2],
    /// The watch event (`task/instructions/maw.rs`).
    pub(super) watch: crate::watch::Watch<InstructionHandle>,
    /// Output cams by execution target (`task/output_cam.rs`).
    pub(super) output_cams: Vec<OutputCamTarget>,
}

/// One execution target of an axis' output cams.
#[derive(Debug, Clone, Default)]
pub(super) struct OutputCamTarget {
    pub(super) active: Option<OutputCamRun>,
    pub(super) pending: Option<OutputCamRun>,
    /// The Input word as the program last gave it.
    pub(super) input: u32,
    /// The bits the cam drives and their values; `release` once the cam
    /// has ended and its bits have been turned off.
    pub(super) mask: u32,
    pub(super) bits: u32,
    pub(super) release: bool,
    /// The Output and Input words' references (the caller's).
    pub(super) words: (usize, usize),
    /// The switches of the last update.
    pub(super) switches: Vec<crate::output_cam::Switch>,
}

/// An output cam MAOC armed (or made pending).
#[derive(Debug, Clone)]
pub(super) struct OutputCamRun {
    pub(super) control: InstructionHandle,
    pub(super) cam: crate::output_cam::OutputCam,
    /// The bits the cam drives.
    pub(super) mask_hint: u32,
    pub(super) latches: Vec<crate::output_cam::Latch>,
    pub(super) range: (f64, f64),
    pub(super) mode: CamMode,
    pub(super) schedule: CamSchedule,
    pub(super) axis_arm: f64,
    pub(super) cam_arm: f64,
    pub(super) actual: bool,
    /// Armed: the cam position follows the axis.
    pub(super) armed: bool,
    /// The axis position and the cam position of the last evaluation.
    pub(super) last_axis: f64,
    pub(super) last_cam: f64,
    pub(super) words: (usize, usize),
}

/// An output cam's Execution Mode.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum CamMode {
    Once,
    Continuous,
    Persistent,
}

/// An output cam's Execution Schedule.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum CamSchedule {
    Immediate,
    Pending,
    ForwardOnly,
    ReverseOnly,
    BiDirectional,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Phase {
    Idle,
    Buffered,
    Active,
    Finished { at_update: u64 },
}

#[derive(Debug, Clone)]
pub(super) struct FbSlot {
    pub(super) name: String,
    pub(super) axis: AxisHandle,
    pub(super) inputs: MoveModuloInputs,
    pub(super) previous_execute: bool,
    pub(super) outputs: FbOutputs,
    pub(super) phase: Phase,
}

#[derive(Debug, Clone)]
pub(super) struct InstructionSlot {
    pub(super) name: String,
    pub(super) bits: MotionInstructionBits,
    /// Executed by a scanned language (Structured Text): its rung does not
    /// fall by itself after an execution.
    pub(super) scanned: bool,
}

#[derive(Debug, Clone, Copy)]
pub(super) enum Finish {
    Done,
    Aborted,
    Error(MoveModuloError),
}

// Cams, ramps and their limits (`task/cam.rs`).

/// Whether an axis' last command exceeded its configured limits.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct LimitFlags {
    /// |command velocity| > `max_velocity`.
    pub velocity: bool,
    /// |command acceleration| > max(`max_acceleration`, `max_deceleration`).
    pub acceleration: bool,
}

pub(super) type Tag = (InstructionHandle, CamProfileHandle);

pub(super) type MasterKey = (AxisHandle, MasterReference);

/// The axis' ramp: a jog, a MAM move or a stop ramp along a profile.
#[derive(Debug, Clone)]
pub(crate) struct RampRun {
    pub(crate) profile: Profile,
    pub(crate) t_s: f64,
    /// The MAJ driving it (`None` for a stop ramp or a move).
    pub(crate) jog: Option<InstructionHandle>,
    /// The MAM moving the axis along it (`None` for a jog or a stop ramp).
    pub(crate) mv: Option<InstructionHandle>,
    /// The MAS stopping it, if any.
    pub(crate) stop: Option<InstructionHandle>,
    /// What a jog or a move was planned for, which MCD re-plans (`None` for
    /// a stop ramp).
    pub(crate) plan: Option<RampPlan>,
}

/// The limits and aim of a jog's or a move's ramp.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct RampPlan {
    pub(crate) limits: Limits,
    pub(crate) aim: RampAim,
}

/// Where a ramp goes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum RampAim {
    /// A jog: its direction (±1) and speed.
    Jog { sign: f64, speed: f64 },
    /// A move: its absolute target, reached at rest.
    Move { target: f64 },
}

impl RampRun {
    /// A ramp along `profile` from its start, owned by no instruction.
    pub(crate) fn new(profile: Profile) -> Self {
        Self {
            profile,
            t_s: 0.0,
            jog: None,
            mv: None,
            stop: None,
            plan: None,
        }
    }
}

#[derive(Debug, Clone, Default)]
pub(crate) struct CamAxis {
    pub(crate) cam: PositionCamAxis<Tag, MasterKey>,
    pub(crate) ramp: Option<RampRun>,
    /// The time cam (MATC) driving the axis, and the one pending behind it
    /// (`task/instructions/matc.rs`).
    pub(crate) time_cam: Option<TimeCamRun>,
    pub(crate) time_cam_pending: Option<TimeCamRun>,
    pub(super) cam_drove: bool,
    pub(super) redefined: f64,
    pub(super) limits: LimitFlags,
    pub(super) declared_slave: bool,
}

/// A time cam (MATC): the profile's master is time.
#[derive(Debug, Clone)]
pub(crate) struct TimeCamRun {
    pub(crate) control: InstructionHandle,
    pub(crate) handle: CamProfileHandle,
    pub(crate) profile: std::sync::Arc<crate::mccp::CamProfile>,
    /// +1 same, −1 opposite.
    pub(crate) sign: f64,
    pub(crate) distance_scaling: f64,
    pub(crate) time_scaling: f64,
    pub(crate) continuous: bool,
    /// Time since it started, s.
    pub(crate) t_s: f64,
    /// The slave position at its start (and at each cycle's start).
    pub(crate) origin: f64,
}

/// The task's cam-instruction state (profiles, tags, per-axis processes).
#[derive(Debug, Clone, Default)]
pub(super) struct CamState {
    pub(super) profiles: Vec<(String, CamProfileTag)>,
    pub(crate) axes: Vec<CamAxis>,
    /// One-shot rungs: (tag, update count when its scan ran).
    pub(super) rung_false: Vec<(InstructionHandle, u64)>,
}

/// What a MAPC call names besides its numeric operands.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MapcCall {
    /// Slave axis.
    pub slave: AxisHandle,
    /// Master axis.
    pub master: AxisHandle,
    /// Motion Control tag.
    pub motion_control: InstructionHandle,
    /// Cam Profile tag.
    pub cam_profile: CamProfileHandle,
    /// The numeric operands.
    pub operands: MapcOperands,
}

// Coordinate systems and coordinated moves (`task/coord.rs`).

/// ERR of a master-driven coordinated move that would take over from
/// time-driven motion while the master stands still and the system moves
/// (Rockwell's MDSC_IDLE_MASTER_AND_SLAVE_MOVING; EXERR 0).
pub const ERR_IDLE_MASTER_SLAVE_MOVING: i32 = 201;

/// A coordinated instruction call with its operands.
#[derive(Debug, Clone, PartialEq)]
pub enum CoordCall {
    /// MCLM.
    Mclm(CoordMoveInputs),
    /// MCCM.
    Mccm(MccmInputs),
    /// MCS.
    Mcs(McsInputs),
}

/// Why a coordinate system cannot be added.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum CoordSetupError {
    /// The configuration is invalid.
    #[error(transparent)]
    Config(#[from] CoordConfigError),
    /// The number of axes given differs from the configuration's `axis_count`,
    /// or an axis appears twice.
    #[error("coordinate system {name}: {given} axes given for axis_count {expected}, each once")]
    Axes {
        /// System name.
        name: String,
        /// Axes given.
        given: usize,
        /// `axis_count`.
        expected: usize,
    },
}

#[derive(Debug, Clone, Default)]
pub(super) struct CoordState {
    pub(super) systems: Vec<SystemSlot>,
    pub(super) instructions: Vec<InstrSlot>,
    /// The refusal of the execution in progress (its call returns it).
    pub(super) refused: Option<CoordMoveError>,
}

#[derive(Debug, Clone)]
pub(super) struct SystemSlot {
    pub(super) system: CoordinateSystem,
    pub(super) axes: Vec<AxisHandle>,
    pub(super) master: Option<AxisHandle>,
    pub(super) master_prev: Option<f64>,
    /// The master's actual position drives the system (MDCC Master
    /// Reference actual), else its command position.
    pub(super) master_actual: bool,
    /// The MDCC that linked the master, while the link holds.
    pub(super) mdcc: Option<InstructionHandle>,
    /// An MDCC to another master made while master-driven motion runs:
    /// (master, actual reference, its MDCC), linked when that motion ends.
    pub(super) pending_master: Option<(AxisHandle, bool, InstructionHandle)>,
    pub(super) status: CoordStatus,
    pub(super) base: Vec<f64>,
    pub(super) components: Vec<Component>,
    pub(super) pending: Option<(CoordInstructionHandle, CoordMove)>,
    pub(super) stop: Option<CoordInstructionHandle>,
    pub(super) queue_end: Vec<f64>,
    pub(super) velocity: Vec<f64>,
    pub(super) acceleration: Vec<f64>,
    /// Axes another command took while the system brakes (not written).
    pub(super) taken: Vec<AxisHandle>,
}

#[derive(Debug, Clone)]
pub(super) struct Component {
    pub(super) instr: Option<CoordInstructionHandle>,
    pub(super) mv: CoordMove,
    pub(super) profile: Profile,
    pub(super) progress: f64,
    pub(super) last_delta: f64,
    pub(super) blend_at: Option<f64>,
    pub(super) successor_started: bool,
    /// Follow contour (types 4, 5): the profile was replanned to reach the
    /// end point at the junction speed of the pending move.
    pub(super) contour: bool,
    pub(super) stopping: bool,
    /// An MCCD of speed 0 holds it where it came to rest on its path
    /// (a feed hold), until an MCCD gives it a speed again.
    pub(super) held: bool,
    pub(super) lock: Lock,
    /// When and from what it started (`task/coord/preflight.rs`).
    pub(super) start: Start,
}

impl Component {
    pub(super) fn done(&self) -> bool {
        if self.progress < self.profile.duration_s() {
            return false;
        }
        let l = self.mv.path().length();
        self.stopping || self.profile.final_state().position >= l - 1e-12 * (1.0 + l)
    }

    pub(super) fn s(&self) -> Sample {
        let mut s = self.profile.sample(self.progress);
        s.position = s.position.clamp(0.0, self.mv.path().length());
        if self.progress >= self.profile.duration_s() {
            // Past its end: a follow-contour move that ended at its junction
            // speed hands that speed to its successor.
            s.velocity = 0.0;
            s.acceleration = 0.0;
            s.jerk = 0.0;
        }
        s
    }
}

#[derive(Debug, Clone, Copy)]
pub(super) struct Lock {
    pub(super) direction: LockDirection,
    pub(super) position: f64,
    pub(super) engaged: bool,
    pub(super) mark: f64,
    pub(super) locked: bool,
}

impl Lock {
    pub(super) fn new(direction: LockDirection, position: f64, master_now: f64) -> Self {
        use LockDirection as L;
        Self {
            direction,
            position,
            engaged: matches!(direction, L::None | L::ImmediateForwardOnly | L::ImmediateReverseOnly),
            mark: master_now,
            locked: matches!(direction, L::ImmediateForwardOnly | L::ImmediateReverseOnly),
        }
    }

    /// Path progress (master distance) gained while the master moves from
    /// `prev` to `now`.
    pub(super) fn advance(&mut self, prev: f64, now: f64) -> f64 {
        use LockDirection as L;
        let forward = match self.direction {
            L::None => return now - prev,
            L::ImmediateForwardOnly | L::PositionForward => true,
            L::ImmediateReverseOnly | L::PositionReverse => false,
        };
        let sign = if forward { 1.0 } else { -1.0 };
        if !self.engaged {
            let crossed = sign * (prev - self.position) < 0.0 && sign * (now - self.position) >= 0.0;
            if !crossed {
                return 0.0;
            }
            self.engaged = true;
            self.mark = self.position;
        }
        let gain = sign * (now - self.mark);
        if gain > 0.0 {
            self.mark = now;
            self.locked = true;
            gain
        } else {
            if sign * (now - prev) < 0.0 {
                self.locked = false;
            }
            0.0
        }
    }
}

#[derive(Debug, Clone)]
pub(super) struct InstrSlot {
    pub(super) control: InstructionHandle,
    pub(super) system: CoordHandle,
    pub(super) call: CoordCall,
    pub(super) rung: bool,
    pub(super) previous_rung: bool,
    /// Set by a one-shot execution (a program step, not a scanned rung): the
    /// update count it executed at; the rung goes false two updates later,
    /// so `.EN` shows for the update of the scan that executed it.
    pub(super) one_shot_at: Option<u64>,
    pub(super) held: bool,
    pub(super) calculated_data: Vec<f64>,
}

// Starting a coordinated move (`task/coord/preflight.rs`).

/// ERR of a coordinated move rejected by the pre-flight sweep (EXERR 0).
pub const ERR_PATH_COLLISION: i32 = 200;

/// When a component started, and the state to restore if it is undone.
#[derive(Debug, Clone)]
pub(super) struct Start {
    /// The update that first advances it: the current one when it starts
    /// inside [`MotionTask::update`](super::MotionTask::update), the next one when it starts in
    /// [`MotionTask::execute_coordinated`](super::MotionTask::execute_coordinated) between updates.
    pub(super) update: u64,
    /// The system was idle: its axes' commands and direction memories, and
    /// the system's velocity and acceleration memories, before the start.
    pub(super) idle: Option<IdleState>,
}

/// A coordinated move that started in the last update
/// ([`MotionTask::coord_moves_started`](super::MotionTask::coord_moves_started)).
#[derive(Debug, Clone, Copy)]
pub struct StartedCoordMove<'a> {
    /// The MCLM/MCCM instruction.
    pub instruction: CoordInstructionHandle,
    /// Its coordinate system.
    pub system: CoordHandle,
    /// The verified move: path (from its programmed start point, in
    /// coordinate units of the system's axes), dynamics, driver.
    pub mv: &'a CoordMove,
    /// Its path profile (position = path length from the start), by time
    /// (s) or, for master-driven moves, by master distance.
    pub profile: &'a Profile,
    /// How far into `profile` the last update took it (s or master units;
    /// 0 when it starts at the next update).
    pub progress: f64,
}

#[derive(Debug, Clone)]
pub(super) struct IdleState {
    pub(super) commands: Vec<Sample>,
    pub(super) last_direction: Vec<f64>,
    pub(super) velocity: Vec<f64>,
    pub(super) acceleration: Vec<f64>,
}
impl IdleState {
    /// Every axis' command velocity is 0. The acceleration of the last
    /// sample is not looked at: a move that ended in this update leaves
    /// the rounding of its profile's last jerk phase there (its velocity is
    /// exactly 0), and a move started from there starts from rest.
    pub(super) fn at_rest(&self) -> bool {
        self.commands.iter().all(|c| c.velocity == 0.0)
    }
}

// Transforms (`task/mct.rs`).

/// The transform-related configuration of a coordinate system.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TransformGeometry {
    /// Coordinate system type / geometry (default: Cartesian gantry).
    pub kind: GeometryKind,
    /// Link lengths, offsets, zero angles (default: all 0).
    pub params: GeometryParams,
    /// Transform dimension (default: the number of primary axes).
    pub transform_dimension: usize,
}

#[derive(Debug, Clone, Default)]
pub(super) struct MctState {
    pub(super) table: TransformTable,
    pub(super) geometries: Vec<(CoordHandle, TransformGeometry)>,
    pub(super) instructions: Vec<MctSlot>,
}

#[derive(Debug, Clone)]
pub(super) struct MctSlot {
    pub(super) control: InstructionHandle,
    pub(super) mct: Mct,
    pub(super) source: CoordHandle,
    /// A transform that faulted and whose joints are still stopping.
    pub(super) stopping: Option<TransformId>,
    /// The rung goes false at the next update (one-shot).
    pub(super) release: bool,
    /// Last joint velocities and accelerations written (for finite
    /// differences).
    pub(super) joint_motion: [(f64, f64); 3],
    /// The transform and its joint axes' commands as they were before this
    /// update's [`MotionTask::advance_transforms`](super::MotionTask::advance_transforms) step (see
    /// [`MotionTask::mct_undo_update`](super::MotionTask::mct_undo_update)).
    pub(super) before_update: Option<Box<BeforeUpdate>>,
}

#[derive(Debug, Clone)]
pub(super) struct BeforeUpdate {
    pub(super) transform: Transform,
    pub(super) joint_motion: [(f64, f64); 3],
    /// Per target axis: command, actual, last direction.
    pub(super) axes: Vec<(AxisHandle, Sample, f64, f64)>,
}

// Servo states (`task/servo.rs`).

/// Whether the drive of an axis is enabled.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Power {
    /// Servo off (Stopped).
    Off,
    /// MSO in process: the control structure and the updates left.
    Starting(Option<InstructionHandle>, u32),
    /// Servo on (Running).
    On,
    /// A fault disabled the drive.
    Faulted,
    /// Shut down.
    Shutdown,
}

/// The state of one axis.
#[derive(Debug, Clone)]
pub(super) struct ServoSlot {
    pub(super) power: Power,
    pub(super) faults: AxisFaults,
    /// The soft overtravel exceptions recorded (latched until MAFR/MASR).
    pub(super) motion_faults: MotionFaults,
    /// The axis' position error exceeded its tolerance in the last update.
    pub(super) position_error_exceeded: bool,
    /// An active MAH waiting for the axis to come to rest (`task/homing.rs`).
    pub(super) homing: Option<InstructionHandle>,
    /// `AxisHomedStatus`: an MAH completed.
    pub(super) homed: bool,
}

impl ServoSlot {
    pub(super) fn new(config: &AxisConfig) -> Self {
        let power = match config.axis_type {
            AxisType::Virtual => Power::On,
            AxisType::FeedbackOnly => Power::Off,
            AxisType::Servo if config.start_servo_on => Power::On,
            AxisType::Servo => Power::Off,
        };
        Self {
            power,
            faults: AxisFaults::default(),
            motion_faults: MotionFaults::default(),
            position_error_exceeded: false,
            homing: None,
            homed: false,
        }
    }
}

/// What an instruction asks of an axis' state.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Need {
    /// A motion process: the servo on.
    Motion,
    /// MSO.
    Enable,
    /// MSF.
    Disable,
    /// MAS, MRP, MASD, MASR: any state but inhibited.
    Any,
}

// Superimposed motion (`task/superimposed.rs`).

/// What a superimposed run does.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum SuperKind {
    /// A MAJ's velocity ramp.
    Jog,
    /// A MAM's move; `.PC` at its end.
    Move,
    /// Its own end: a ramp to rest, or the offset held after a move.
    Hold,
}

/// One axis' superimposed run.
#[derive(Debug, Clone)]
pub(super) struct SuperRun {
    pub(super) profile: Profile,
    pub(super) t_s: f64,
    pub(super) control: Option<InstructionHandle>,
    pub(super) kind: SuperKind,
    /// The offset added to the command by the last update.
    pub(super) applied: Sample,
}

// Gearing (MAG, `task/instructions/mag.rs`).

/// The gearing of one slave axis.
#[derive(Debug, Clone)]
pub(crate) struct GearRun {
    pub(crate) control: InstructionHandle,
    pub(crate) master: AxisHandle,
    pub(crate) reference: MasterReference,
    /// Signed slave units per master unit.
    pub(crate) ratio: f64,
    /// The master position at the last update (redefinitions taken out).
    pub(crate) last_master: f64,
    /// The clutch acceleration while slipping; `None` once locked.
    pub(crate) clutch: Option<f64>,
    /// The slave's gearing velocity, units/s.
    pub(crate) velocity: f64,
}

// Stops (`task/stop.rs`).

/// The axis state a command started from (not for blend hand-overs).
#[derive(Debug, Clone, Copy)]
pub(super) struct Origin {
    /// [`MotionTask::updates`](super::MotionTask::updates) of the update the command started in.
    pub(super) update: u64,
    /// The axis' command before the command started.
    pub(super) command: Sample,
    /// The axis' direction memory before the command started.
    pub(super) last_direction: f64,
}

/// What [`MotionTask::stop_all_axes`](super::MotionTask::stop_all_axes) did.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct StopReport {
    /// Axes that were moving (or had a command) and now ramp to rest.
    pub stopped_axes: Vec<AxisHandle>,
    /// Instances that got `CommandAborted`, in axis order (running, then buffered).
    pub aborted: Vec<FbHandle>,
    /// Logix control structures that were in process (`.IP`), in the order added.
    pub stopped_instructions: Vec<InstructionHandle>,
}

// Handing an axis over (`task/cam.rs`).

/// The processes on an axis a new single-axis motion ends
/// ([`MotionTask::take_axis`](super::MotionTask::take_axis)), besides the
/// moves and coordinated motion every one aborts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Takes {
    /// Its position cams.
    pub cams: bool,
    /// Its gearing.
    pub gear: bool,
    /// Its jog or move ramp.
    pub ramp: bool,
}

impl Takes {
    /// Every process.
    pub(crate) const ALL: Takes = Takes {
        cams: true,
        gear: true,
        ramp: true,
    };
}
