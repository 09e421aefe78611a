//! Axis states, as a CIP axis has them, and the rules the state
//! instructions (MSO, MSF, MASD, MASR, MAFR, MCSD, MCSR) and every motion
//! instruction follow. The executor side is `task/servo.rs`.
//!
//! # Axis types
//! [`AxisType`]: a **servo** axis drives a motor (a scene axis with a joint);
//! a **virtual** axis (no joint) has no drive and moves without MSO, as a
//! Logix `AXIS_VIRTUAL`; a **feedback-only** axis (Logix Axis Configuration
//! *Feedback Only*) only reports a position: every instruction that would
//! enable or move it fails with ERR 8 (Axis Type Not Servo).
//!
//! # States ([`CipAxisState`], the `CIPAxisState` attribute)
//! | state | code | how it is entered | leaves by |
//! |---|---|---|---|
//! | Stopped (servo off) | 2 | MSF; MASR; MAFR after a fault that disabled the drive; the scene's `servo_on = false` | MSO |
//! | Starting | 3 | MSO from Stopped | after [`SERVO_ENABLE_UPDATES`] coarse updates (or the brake release delay): Running |
//! | Running | 4 | MSO completes; a virtual axis always | MSF, MASD, a fault that disables the drive |
//! | Faulted | 8 | a fault whose action disables the drive | MAFR (→ Stopped), MASD (→ Shutdown) |
//! | Shutdown | 10 | MASD / MCSD; a fault whose action is Shutdown | MASR / MCSR (→ Stopped; a virtual axis → Running) |
//! | Axis Inhibited | 11 | the scene's `inhibit_axis = true` | — (configuration) |
//!
//! A feedback-only axis reports Stopped (it has no drive to enable). The
//! other CIP codes (Initializing, Pre-Charge, Testing, Stopping, Aborting,
//! Start Inhibited, …) are connection and drive-power states this twin does
//! not model; [`CipAxisState`] names them so that a program comparing with
//! them compiles. While the servo is off (Stopped, Faulted, Shutdown) the
//! command position follows the actual position, so MSO enables the loop
//! where the axis is, without a jump.
//!
//! # What each instruction requires ([`StateError`])
//! Checked in this order, the first failing rule wins:
//! 1. an inhibited axis refuses every instruction but MAFR: ERR 53;
//! 2. a feedback-only axis refuses MSO, MSF and motion: ERR 8;
//! 3. a shut-down axis refuses MSO and motion: ERR 7;
//! 4. a homing axis refuses motion (MAH is the only homing process): ERR 16;
//! 5. motion (MAM, MAJ, MAPC, MCLM, MCCM, MCT, MC_MoveModulo) needs the
//!    servo on (Running): ERR 5 otherwise (Starting counts as off: wait for
//!    the MSO's `.DN`);
//! 6. MSO on an axis whose drive a fault disabled (Faulted): ERR 20 (Axis In
//!    Faulted State) — MAFR first; MSO on a servo-off axis that is still
//!    moving (falling, coasting: |actual velocity| above
//!    [`MOVING_FRACTION`] of its maximum speed): ERR 22 (Axis In Motion).
//!
//! MSO on an axis already on (Running or Starting) and MSF on an axis
//! already off are not errors: `.DN` at once, nothing changes. MAS, MRP,
//! MASD, MASR and MAFR execute in any state but Axis Inhibited (MAFR there
//! too). For a coordinate-system instruction the EXERR of ERR 5, 7, 8, 16
//! and 53 is the index of the axis in the coordinate system (the MCCM
//! document's rule); for a single-axis instruction it is 0.
//!
//! # Faults ([`AxisFaults`], the `AxisFault` word)
//! The word's bits are the CIP axis' fault categories; [`AxisFaults::MOTION`]
//! holds the planner-detected faults: Excessive Position Error and soft
//! overtravel ([`FaultAction`] decides what the axis does). MAFR clears the
//! word and leaves an axis that the fault had disabled servo-off (Stopped):
//! the program must MSO again. MAFR does not leave Shutdown (MASR does).
//!
//! # Soft overtravel ([`MotionFaults`], the `MotionFault` word)
//! As the Logix Motion Fault and Alarm Exceptions define it: with soft
//! travel limits (`AxisConfig::soft_travel_limits`, Soft Travel Limit
//! Checking on) the task compares the axis' **actual** position with them
//! every coarse update. Beyond `max` (strictly) is Soft Travel Limit -
//! Positive, below `min` Soft Travel Limit - Negative. On a controlled axis
//! the exception is generated only while the command moves the axis further
//! out (command velocity pointing away from the range): an axis standing
//! beyond a limit, or commanded back towards the range, raises nothing —
//! the manual's recovery path (MAFR, MSO, move back in). A feedback-only
//! axis raises it whenever it is outside. The exception sets its
//! [`MotionFaults`] bit and [`AxisFaults::MOTION`] (both latched until MAFR
//! or MASR) and takes the axis' `soft_overtravel_action` (default Stop
//! Planner: the command ramps to rest at the maximum deceleration, the
//! servo stays on, so the axis stops beyond the limit by its stopping
//! distance).
//!
//! While a soft overtravel bit is set, or the actual position is beyond a
//! limit (action other than Ignore), a motion instruction that would move
//! the axis further out fails with ERR 9 (Overtravel Condition,
//! [`StateError::Overtravel`]); moves back towards the range execute. What
//! "further out" means per instruction (choices where the manual does not
//! say): MAM — its target beyond the current command position on that
//! side; MAJ — its direction; MCLM and MCCM — the axis' end position beyond
//! its start (EXERR: the axis' index in the coordinate system); MAG and MAPC
//! — either side, since the master decides the direction. MRP to a
//! position outside the limits redefines the position and raises the
//! exception at once (the MAPC document's rule: "a software overtravel
//! fault is generated when the instruction is executed").

use thiserror::Error;

/// What kind of axis: whether it has a drive to enable and move.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum AxisType {
    /// A servo drive (`AXIS_CIP_DRIVE`, Axis Configuration Position Loop).
    #[default]
    Servo,
    /// A virtual axis (`AXIS_VIRTUAL`): no drive, always servo-on.
    Virtual,
    /// An axis that only reads a feedback device (Axis Configuration
    /// Feedback Only): it cannot be enabled or moved.
    FeedbackOnly,
}

/// Coarse updates from an MSO on a servo-off axis until the loop is closed
/// (state Running, the MSO's `.DN`): the drive's enable handshake.
pub const SERVO_ENABLE_UPDATES: u32 = 2;

/// A servo-off axis faster than this fraction of its maximum speed is
/// "in motion" for MSO (ERR 22).
pub const MOVING_FRACTION: f64 = 0.01;

/// The `CIPAxisState` attribute's values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[repr(i32)]
pub enum CipAxisState {
    /// 0: the drive initializes.
    Initializing = 0,
    /// 1: DC bus not up.
    PreCharge = 1,
    /// 2: servo off, ready for MSO.
    Stopped = 2,
    /// 3: MSO in process.
    Starting = 3,
    /// 4: servo on.
    Running = 4,
    /// 5: a test process.
    Testing = 5,
    /// 6: the drive ramps down before disabling.
    Stopping = 6,
    /// 7: an abort ramp.
    Aborting = 7,
    /// 8: a fault disabled the drive.
    Faulted = 8,
    /// 9: a start inhibit is active.
    StartInhibited = 9,
    /// 10: shut down (MASD).
    Shutdown = 10,
    /// 11: the axis is inhibited.
    AxisInhibited = 11,
    /// 12: not in a motion group.
    NotGrouped = 12,
    /// 13: no module.
    NoModule = 13,
    /// 14: configuring.
    Configuring = 14,
    /// 15: synchronizing.
    Synchronizing = 15,
}

impl CipAxisState {
    /// The attribute's numeric value.
    pub fn code(self) -> i32 {
        self as i32
    }

    /// The state's name as the manual writes it.
    pub fn name(self) -> &'static str {
        match self {
            Self::Initializing => "Initializing",
            Self::PreCharge => "Pre-Charge",
            Self::Stopped => "Stopped",
            Self::Starting => "Starting",
            Self::Running => "Running",
            Self::Testing => "Testing",
            Self::Stopping => "Stopping",
            Self::Aborting => "Aborting",
            Self::Faulted => "Faulted",
            Self::StartInhibited => "Start Inhibited",
            Self::Shutdown => "Shutdown",
            Self::AxisInhibited => "Axis Inhibited",
            Self::NotGrouped => "Not Grouped",
            Self::NoModule => "No Module",
            Self::Configuring => "Configuring",
            Self::Synchronizing => "Synchronizing",
        }
    }
}

/// What an axis does when a fault is detected (the axis' exception action
/// for that fault).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum FaultAction {
    /// Nothing: the fault is not even recorded.
    Ignore,
    /// The fault is recorded as an alarm in the fault word; nothing stops.
    Alarm,
    /// The fault is recorded; nothing stops (the program decides).
    FaultStatusOnly,
    /// The fault is recorded and the planner stops the axis' motion at its
    /// maximum deceleration; the servo stays on.
    StopPlanner,
    /// The fault is recorded, motion ends at once and the drive is disabled
    /// (state Faulted): MAFR, then MSO. The default.
    #[default]
    StopDrive,
    /// The fault is recorded and the axis shuts down (state Shutdown):
    /// MASR, then MSO.
    Shutdown,
}

impl FaultAction {
    /// Every action with its name in the scene (Logix's words, no spaces).
    pub const NAMES: [(&'static str, FaultAction); 6] = [
        ("Ignore", Self::Ignore),
        ("Alarm", Self::Alarm),
        ("FaultStatusOnly", Self::FaultStatusOnly),
        ("StopPlanner", Self::StopPlanner),
        ("StopDrive", Self::StopDrive),
        ("Shutdown", Self::Shutdown),
    ];

    /// The action's name (Logix's words, no spaces), as in [`Self::NAMES`].
    pub fn name(self) -> &'static str {
        Self::NAMES.iter().find(|(_, a)| *a == self).map_or("", |(n, _)| n)
    }
}

/// The `AxisFault` word: one bit per fault category.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct AxisFaults(pub u32);

impl AxisFaults {
    /// Bit 0: a physical axis fault (drive, motor, feedback).
    pub const PHYSICAL: u32 = 1 << 0;
    /// Bit 1: a module fault.
    pub const MODULE: u32 = 1 << 1;
    /// Bit 2: a configuration fault.
    pub const CONFIG: u32 = 1 << 2;
    /// Bit 3: a motion group fault.
    pub const GROUP: u32 = 1 << 3;
    /// Bit 4: a motion fault detected by the planner (Excessive Position
    /// Error).
    pub const MOTION: u32 = 1 << 4;

    /// Whether no fault is recorded.
    pub fn is_clear(self) -> bool {
        self.0 == 0
    }
}

/// The `MotionFault` word: the motion planner's exception conditions (Logix
/// Motion Fault and Alarm Exceptions).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct MotionFaults(pub u32);

impl MotionFaults {
    /// Bit 1: Soft Travel Limit - Positive (`SoftTravelLimitPositiveFault`).
    pub const SOFT_TRAVEL_POSITIVE: u32 = 1 << 1;
    /// Bit 2: Soft Travel Limit - Negative (`SoftTravelLimitNegativeFault`).
    pub const SOFT_TRAVEL_NEGATIVE: u32 = 1 << 2;

    /// Whether no exception is recorded.
    pub fn is_clear(self) -> bool {
        self.0 == 0
    }

    /// The exception bit of the soft travel limit `position` is beyond
    /// (strictly), if any: `SOFT_TRAVEL_POSITIVE` above `max`,
    /// `SOFT_TRAVEL_NEGATIVE` below `min`; `None` without limits.
    pub fn beyond(limits: Option<(f64, f64)>, position: f64) -> Option<u32> {
        match limits? {
            (_, max) if position > max => Some(Self::SOFT_TRAVEL_POSITIVE),
            (min, _) if position < min => Some(Self::SOFT_TRAVEL_NEGATIVE),
            _ => None,
        }
    }

    /// Whether Soft Travel Limit - Positive is recorded.
    pub fn positive(self) -> bool {
        self.0 & Self::SOFT_TRAVEL_POSITIVE != 0
    }

    /// Whether Soft Travel Limit - Negative is recorded.
    pub fn negative(self) -> bool {
        self.0 & Self::SOFT_TRAVEL_NEGATIVE != 0
    }
}

/// Why a state or motion instruction cannot execute in the axis' state.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Error)]
#[non_exhaustive]
pub enum StateError {
    /// ERR 5: the servo loop is off.
    #[error("servo off state (ERR 5): execute MSO first")]
    ServoOff,
    /// ERR 7: the axis is shut down.
    #[error("shutdown state (ERR 7): execute MASR first")]
    Shutdown,
    /// ERR 8: the axis' type cannot do the instruction.
    #[error("axis type not servo (ERR 8)")]
    AxisType,
    /// ERR 9: the move would take the axis further beyond a soft travel
    /// limit it has exceeded.
    #[error("overtravel condition (ERR 9): move the axis back inside its soft travel limits")]
    Overtravel,
    /// ERR 16: the axis is homing.
    #[error("homing in process (ERR 16)")]
    Homing,
    /// ERR 20: a fault disabled the drive.
    #[error("axis in faulted state (ERR 20): execute MAFR first")]
    Faulted,
    /// ERR 22: the axis is moving.
    #[error("axis in motion (ERR 22)")]
    InMotion,
    /// ERR 53: the axis is inhibited.
    #[error("axis inhibited (ERR 53)")]
    Inhibited,
}

impl StateError {
    /// The `ERR` code.
    pub fn err(self) -> i32 {
        match self {
            Self::ServoOff => 5,
            Self::Shutdown => 7,
            Self::AxisType => 8,
            Self::Overtravel => 9,
            Self::Homing => 16,
            Self::Faulted => 20,
            Self::InMotion => 22,
            Self::Inhibited => 53,
        }
    }
}

/// The axis-status and motion-status bits a program reads (`Axis.Member`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct AxisStatusBits {
    /// `ServoActionStatus`: the servo loop is closed.
    pub servo_action: bool,
    /// `DriveEnableStatus`: the drive's power structure is enabled.
    pub drive_enable: bool,
    /// `ShutdownStatus`.
    pub shutdown: bool,
    /// `InhibitStatus`.
    pub inhibit: bool,
    /// `AxisHomedStatus`: a homing sequence completed (or the scene says
    /// the axis starts homed).
    pub homed: bool,
    /// `HomingStatus`: MAH in process.
    pub homing: bool,
    /// `MoveStatus`: a single-axis move (MAM, MC_MoveModulo) runs.
    pub moving: bool,
    /// `JogStatus`: a jog (MAJ) runs.
    pub jogging: bool,
    /// `GearingStatus`: a gear (MAG) is engaged.
    pub gearing: bool,
    /// `StoppingStatus`: a stop (MAS, MCS, a fault's stop) ramps the axis.
    pub stopping: bool,
}
