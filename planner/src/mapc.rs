//! Motion Axis Position Cam (MAPC): a slave axis follows a master axis
//! through a calculated cam profile.
//!
//! [`Mapc::new`] validates the operands; [`PositionCamAxis`] is the position
//! cam process of one slave axis (its active cam, the cam waiting to start,
//! and the slave's Position Cam Status / Lock Status / Pending Status). The
//! [`crate::task::MotionTask`] owns one per axis and drives it each coarse
//! update; this module knows no axes, only master positions handed in.
//!
//! # Position law
//! With master position `m` (Actual or Command per Master Reference, plus the
//! slave's master offset), the cam coordinate is
//! `u = u_ref + (c − c_ref) / MasterScaling`, where `c` is the *clutch* master
//! position (below) and `(c_ref, u_ref)` the point where the cam locked
//! (`u_ref` = Cam Lock Position at the Master Lock Position, or at the
//! master's position for Immediate). The slave command is
//! `slave_start + sign · SlaveScaling · (F(u) − F(u_start))`: the cam's
//! contribution is *added to* the slave position it locked at (spec: "added
//! to the command position"), so locking never makes the slave jump — the
//! spec's Cam Lock Position table (slave' = slave − slave(Cam Lock)).
//! `F` is the profile, clamped to its master range in Once and Persistent
//! modes, and unwound in Continuous mode (`F(u + P) = F(u) + (y_end − y_start)`
//! with `P` the master range).
//!
//! # Operands
//! * **Direction** Same (+), Opposite (−), Reverse (flips the axis' current
//!   or previous camming direction; Opposite the first time), Unchanged
//!   (keeps it; Same the first time). The memory is per slave axis and is
//!   updated when an MAPC executes.
//! * **Slave/Master Scaling** multiply the profile's slave/master values.
//! * **Execution Mode** Once: ends when `u` leaves the master range (the
//!   slave stays at the end value), `.PC` set, Position Cam Status reset.
//!   Continuous: repeats indefinitely. Persistent: the slave holds at the end
//!   value while `u` is outside the range (Lock Status reset) and follows
//!   again when the master comes back; it never completes.
//! * **Execution Schedule** Immediate: locks now, Master Lock Position
//!   ignored. Forward only / Reverse only / Bidirectional: locks when the
//!   master crosses the Master Lock Position in that direction (reaching it
//!   counts). Pending: starts when the active cam ends (Once: crossing its
//!   boundary; Continuous: at the end of the current cycle; Persistent: when
//!   the master leaves the range), at that exact boundary point, at its own
//!   Cam Lock Position, using the active cam's master and master reference
//!   (the Master Axis, Master Lock Position and Master Reference operands are
//!   ignored). A Pending cam executed with no cam active is preloaded: no
//!   motion until a non-pending MAPC starts a cam, which it then follows.
//! * **Master Lock Position** on a modulo (rotary) master is independent of
//!   the turns count: any `MasterLock + k · period` is a lock position.
//!   It is compared with master position + the slave's
//!   master offset ([`PositionCamAxis::shift_master_offset`], a master offset
//!   move): with offset X the slave locks at master `MasterLock − X`. Every
//!   non-pending MAPC resets the master offset to 0.
//! * **Cam Lock Position** must lie in the profile's master range (else ERR 13,
//!   EXERR 10).
//! * **Cam Type** New: supersedes the active cam (and a scheduled replacement;
//!   a Pending cam stays). Replace and Restart: the replacement starts at its
//!   Cam Lock Position from the slave's position at the replacement point
//!   (velocity may jump: the spec makes that the user's concern). Replace and
//!   Continue: the replacement continues from the active cam's coordinate `u`
//!   at the replacement point and from the active cam's lock reference, so
//!   the slave moves to the replacement profile's position there (the spec's
//!   "sudden change"); Cam Lock Position ignored. A replacement cancels a
//!   Pending cam when it executes (its `.IP` is reset). With a schedule other
//!   than Immediate it waits (Pending Status set) until the master crosses its
//!   Master Lock Position, then replaces. A replacement executed while no cam
//!   is active acts as a New cam.
//! * **Master Direction** (slip clutch) Forward only: the clutch position `c`
//!   follows the master only forward (`c = max(c, m)`); while the master is
//!   behind `c` the slave holds (Lock Status reset) and picks up again when the
//!   master gets back to where it reversed. Reverse only mirrors this.
//!   Bidirectional: `c = m`. A replacement that takes over from a slipping cam
//!   with the same restricted direction inherits its clutch, so it too picks
//!   up where the master reversed (the spec's "Replace and Continue with
//!   Active Cam Unlocked" figure: `.AC` at the Master Lock Position, the slave
//!   held where it was until the master is back at the reversal point, then
//!   driven by the replacement).
//!
//! # Status bits
//! * Position Cam Status: a cam is active (waiting for its lock or running)
//!   or a scheduled replacement waits. A Pending cam alone (preloaded) does not
//!   set it.
//! * Position Cam Lock Status: the active cam drives the slave: running, not
//!   slipping, and (Once/Persistent) `u` inside the master range.
//! * Position Cam Pending Status: a Pending cam or a scheduled replacement
//!   waits.
//!
//! # Errors
//! ERR 13 (Parameter Out of Range) with EXERR = the operand's faceplate number
//! ([`operand`]); ERR 32 (Cam Profile Not Calculated) for a profile with
//! Status 0 and ERR 30 (Cam Profile Being Calculated) for Status 1 — the
//! spec's "0, 1: not calculated yet". The spec's `.SEGMENT` errors 28/29/179
//! on a cam profile cannot arise here: a [`CamProfile`] is validated when it
//! is built (MCCP, or [`CamProfile::from_elements`] for a profile written
//! element by element, which reports them with SEGMENT).
//! One case of 179 remains at run time (a choice): a running cam whose slave
//! position is no longer a finite number (Slave/Master Scaling and master
//! travel so extreme that `f64` overflows) ends, the slave holds its last
//! position, and the MAPC gets `.ER` with ERR 179 (SEGMENT 0).
//!
//! # Choices where the spec is silent
//! * A replacement waiting for its lock when the active Once cam completes
//!   stays armed and starts (as a new cam, from the slave's position) when
//!   the master crosses its lock position.
//! * A second Pending cam supersedes the first; a Pending cam supersedes a
//!   waiting scheduled replacement.
//! * MAPC with the slave as its own master is ERR 13, EXERR 1.

use crate::mccp::CamProfile;
use std::sync::Arc;
use thiserror::Error;

/// Direction operand.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum CamDirection {
    /// 0: slave values in the master's sense.
    #[default]
    Same,
    /// 1: slave values in the opposite sense.
    Opposite,
    /// 2: the current or previous direction reversed (Opposite the first time).
    Reverse,
    /// 3: the current or previous direction kept (Same the first time).
    Unchanged,
}

/// Execution Mode operand.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ExecutionMode {
    /// 0: until the cam boundary is crossed.
    #[default]
    Once,
    /// 1: repeated indefinitely.
    Continuous,
    /// 2: follows whenever the master is inside the range.
    Persistent,
}

/// Execution Schedule operand.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ExecutionSchedule {
    /// 0: lock now.
    #[default]
    Immediate,
    /// 1: start when the active cam ends.
    Pending,
    /// 2: lock when the master crosses the lock position forward.
    ForwardOnly,
    /// 3: lock when the master crosses the lock position in reverse.
    ReverseOnly,
    /// 4: lock when the master crosses the lock position either way.
    Bidirectional,
}

/// Cam Type operand.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum CamType {
    /// 0: a new cam.
    #[default]
    NewCam,
    /// 1: replace the active cam, starting at the Cam Lock Position.
    ReplaceAndRestart,
    /// 2: replace the active cam, continuing at its current point.
    ReplaceAndContinue,
}

/// Master Reference operand.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum MasterReference {
    /// 0: the master's actual (measured) position.
    #[default]
    Actual,
    /// 1: the master's command position.
    Command,
}

/// Master Direction operand (the slip clutch).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum MasterDirection {
    /// 0: the slave follows the master both ways.
    #[default]
    Bidirectional,
    /// 1: the slave follows only forward master motion.
    ForwardOnly,
    /// 2: the slave follows only reverse master motion.
    ReverseOnly,
}

/// MAPC's numeric operands as the call gives them (Slave, Master, Motion
/// Control and Cam Profile are the task's handles).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MapcOperands {
    /// Direction, 0..=3 (default 0 Same).
    pub direction: i32,
    /// Slave Scaling (default 1).
    pub slave_scaling: f64,
    /// Master Scaling (default 1).
    pub master_scaling: f64,
    /// Execution Mode, 0..=2 (default 0 Once).
    pub execution_mode: i32,
    /// Execution Schedule, 0..=4 (default 0 Immediate).
    pub execution_schedule: i32,
    /// Master Lock Position, master units (default 0).
    pub master_lock_position: f64,
    /// Cam Lock Position, cam master units (default 0).
    pub cam_lock_position: f64,
    /// Cam Type, 0..=2 (default 0 New Cam).
    pub cam_type: i32,
    /// Master Reference, 0 Actual or 1 Command (default 0).
    pub master_reference: i32,
    /// Master Direction, 0..=2 (default 0 Bidirectional).
    pub master_direction: i32,
}

impl Default for MapcOperands {
    fn default() -> Self {
        Self {
            direction: 0,
            slave_scaling: 1.0,
            master_scaling: 1.0,
            execution_mode: 0,
            execution_schedule: 0,
            master_lock_position: 0.0,
            cam_lock_position: 0.0,
            cam_type: 0,
            master_reference: 0,
            master_direction: 0,
        }
    }
}

/// Faceplate operand numbers (EXERR of ERR 13).
pub mod operand {
    /// Slave Axis.
    pub const SLAVE: i32 = 0;
    /// Master Axis.
    pub const MASTER: i32 = 1;
    /// Direction.
    pub const DIRECTION: i32 = 3;
    /// Cam Profile.
    pub const CAM_PROFILE: i32 = 4;
    /// Slave Scaling.
    pub const SLAVE_SCALING: i32 = 5;
    /// Master Scaling.
    pub const MASTER_SCALING: i32 = 6;
    /// Execution Mode.
    pub const EXECUTION_MODE: i32 = 7;
    /// Execution Schedule.
    pub const EXECUTION_SCHEDULE: i32 = 8;
    /// Master Lock Position.
    pub const MASTER_LOCK_POSITION: i32 = 9;
    /// Cam Lock Position.
    pub const CAM_LOCK_POSITION: i32 = 10;
    /// Cam Type.
    pub const CAM_TYPE: i32 = 11;
    /// Master Reference.
    pub const MASTER_REFERENCE: i32 = 12;
    /// Master Direction.
    pub const MASTER_DIRECTION: i32 = 13;
}

/// Why an MAPC failed.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum MapcError {
    /// ERR 13: an operand out of range (EXERR = its faceplate number).
    #[error("parameter out of range: operand {operand} = {value} (ERR 13)")]
    ParameterOutOfRange {
        /// Operand number (EXERR), see [`operand`].
        operand: i32,
        /// Its value.
        value: f64,
    },
    /// ERR 30: the profile's Status is 1.
    #[error("cam profile is being calculated (Status 1) (ERR 30)")]
    CamProfileBeingCalculated,
    /// ERR 32: the profile's Status is 0.
    #[error("cam profile not calculated (Status 0) (ERR 32)")]
    CamProfileNotCalculated,
}

impl MapcError {
    /// The `ERR` code.
    pub fn err(&self) -> i32 {
        match self {
            Self::ParameterOutOfRange { .. } => 13,
            Self::CamProfileBeingCalculated => 30,
            Self::CamProfileNotCalculated => 32,
        }
    }

    /// The `EXERR` code.
    pub fn exerr(&self) -> i32 {
        match self {
            Self::ParameterOutOfRange { operand, .. } => *operand,
            _ => 0,
        }
    }

    /// The error for a profile whose Status makes it unusable (0 or 1).
    pub fn from_status(status: u32) -> Self {
        if status == 1 {
            Self::CamProfileBeingCalculated
        } else {
            Self::CamProfileNotCalculated
        }
    }
}

/// Validated MAPC operands.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Mapc {
    /// Direction.
    pub direction: CamDirection,
    /// Slave Scaling (finite).
    pub slave_scaling: f64,
    /// Master Scaling (finite, non-zero).
    pub master_scaling: f64,
    /// Execution Mode.
    pub execution_mode: ExecutionMode,
    /// Execution Schedule.
    pub execution_schedule: ExecutionSchedule,
    /// Master Lock Position (finite).
    pub master_lock_position: f64,
    /// Cam Lock Position (finite).
    pub cam_lock_position: f64,
    /// Cam Type.
    pub cam_type: CamType,
    /// Master Reference.
    pub master_reference: MasterReference,
    /// Master Direction.
    pub master_direction: MasterDirection,
}

impl Mapc {
    /// Validates the operands.
    ///
    /// # Errors
    /// [`MapcError::ParameterOutOfRange`] naming the first bad operand.
    pub fn new(o: &MapcOperands) -> Result<Self, MapcError> {
        let bad = |operand: i32, value: f64| MapcError::ParameterOutOfRange { operand, value };
        let pick = |operand: i32, v: i32, n: i32| {
            if (0..n).contains(&v) {
                Ok(v)
            } else {
                Err(bad(operand, f64::from(v)))
            }
        };
        let direction = match pick(operand::DIRECTION, o.direction, 4)? {
            0 => CamDirection::Same,
            1 => CamDirection::Opposite,
            2 => CamDirection::Reverse,
            _ => CamDirection::Unchanged,
        };
        if !o.slave_scaling.is_finite() {
            return Err(bad(operand::SLAVE_SCALING, o.slave_scaling));
        }
        if !(o.master_scaling.is_finite() && o.master_scaling != 0.0) {
            return Err(bad(operand::MASTER_SCALING, o.master_scaling));
        }
        let execution_mode = match pick(operand::EXECUTION_MODE, o.execution_mode, 3)? {
            0 => ExecutionMode::Once,
            1 => ExecutionMode::Continuous,
            _ => ExecutionMode::Persistent,
        };
        let execution_schedule = match pick(operand::EXECUTION_SCHEDULE, o.execution_schedule, 5)? {
            0 => ExecutionSchedule::Immediate,
            1 => ExecutionSchedule::Pending,
            2 => ExecutionSchedule::ForwardOnly,
            3 => ExecutionSchedule::ReverseOnly,
            _ => ExecutionSchedule::Bidirectional,
        };
        if !o.master_lock_position.is_finite() {
            return Err(bad(operand::MASTER_LOCK_POSITION, o.master_lock_position));
        }
        if !o.cam_lock_position.is_finite() {
            return Err(bad(operand::CAM_LOCK_POSITION, o.cam_lock_position));
        }
        let cam_type = match pick(operand::CAM_TYPE, o.cam_type, 3)? {
            0 => CamType::NewCam,
            1 => CamType::ReplaceAndRestart,
            _ => CamType::ReplaceAndContinue,
        };
        let master_reference = match pick(operand::MASTER_REFERENCE, o.master_reference, 2)? {
            0 => MasterReference::Actual,
            _ => MasterReference::Command,
        };
        let master_direction = match pick(operand::MASTER_DIRECTION, o.master_direction, 3)? {
            0 => MasterDirection::Bidirectional,
            1 => MasterDirection::ForwardOnly,
            _ => MasterDirection::ReverseOnly,
        };
        Ok(Self {
            direction,
            slave_scaling: o.slave_scaling,
            master_scaling: o.master_scaling,
            execution_mode,
            execution_schedule,
            master_lock_position: o.master_lock_position,
            cam_lock_position: o.cam_lock_position,
            cam_type,
            master_reference,
            master_direction,
        })
    }
}

/// The slave axis' position cam status bits.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct SlaveCamStatus {
    /// Position Cam Status.
    pub position_cam: bool,
    /// Position Cam Lock Status.
    pub lock: bool,
    /// Position Cam Pending Status.
    pub pending: bool,
}

/// What happened to an MAPC instruction (identified by its tag `T`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CamEvent<T> {
    /// The cam began interpolating the slave (`.AC` set).
    Active(T),
    /// The cam ended: `.IP` and `.AC` reset, its profile released; `.PC` set
    /// when `complete` (a Once cam that crossed its boundary).
    Ended {
        /// The instruction.
        tag: T,
        /// Whether it completed (Once mode) rather than being superseded,
        /// cancelled or stopped.
        complete: bool,
    },
    /// The cam's slave position overflowed (not a finite number): the cam
    /// ended (an [`CamEvent::Ended`] comes before this) and the instruction
    /// gets `.ER` with ERR 179 (Invalid Cam Profile Element: "overflow or not
    /// a number").
    Overflow(T),
}

/// An MAPC to start on a [`PositionCamAxis`].
#[derive(Debug, Clone)]
pub struct CamRequest<T, K> {
    /// The instruction (returned in events).
    pub tag: T,
    /// The master and its reference (the key handed to the master lookup).
    pub master: K,
    /// The validated operands.
    pub mapc: Mapc,
    /// The profile (already counted in its Status by the caller).
    pub profile: Arc<CamProfile>,
    /// The master's modulo period, if it is a modulo (rotary) axis: its
    /// Master Lock Position is then independent of the turns count.
    pub master_period: Option<f64>,
}

#[derive(Debug, Clone)]
struct Cam<T, K> {
    tag: T,
    master: K,
    profile: Arc<CamProfile>,
    sign: f64,
    mapc: Mapc,
    master_period: Option<f64>,
}

#[derive(Debug, Clone, Copy)]
struct Run {
    clutch: f64,
    c_ref: f64,
    u_ref: f64,
    u_start: f64,
    slave_start: f64,
    f_start: f64,
    u: f64,
    slipping: bool,
    /// A Replace and Continue cam that took over from a slipping cam shows
    /// this slave position until the master picks up.
    hold: Option<f64>,
}

#[derive(Debug, Clone, Copy)]
enum Phase {
    /// Waiting for the master to cross the lock position.
    Armed {
        prev: f64,
    },
    Running(Run),
}

#[derive(Debug, Clone)]
struct Active<T, K> {
    cam: Cam<T, K>,
    phase: Phase,
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum WaitKind {
    Pending,
    Replacement { prev: f64 },
}

#[derive(Debug, Clone)]
struct Waiting<T, K> {
    cam: Cam<T, K>,
    kind: WaitKind,
}

/// The position cam process of one slave axis.
#[derive(Debug, Clone)]
pub struct PositionCamAxis<T, K> {
    direction_memory: Option<f64>,
    master_offset: f64,
    active: Option<Active<T, K>>,
    waiting: Option<Waiting<T, K>>,
}

impl<T, K> Default for PositionCamAxis<T, K> {
    fn default() -> Self {
        Self {
            direction_memory: None,
            master_offset: 0.0,
            active: None,
            waiting: None,
        }
    }
}

/// `F(u)`: the profile in the cam's execution mode.
fn cam_value(profile: &CamProfile, mode: ExecutionMode, u: f64) -> f64 {
    match mode {
        ExecutionMode::Continuous => {
            let (x0, xn) = profile.master_range();
            let (y0, yn) = profile.slave_range();
            let period = xn - x0;
            let k = ((u - x0) / period).floor();
            let w = (u - k * period).clamp(x0, xn);
            profile.eval(w).slave + k * (yn - y0)
        }
        _ => profile.eval(u).slave,
    }
}

fn cycle(profile: &CamProfile, u: f64) -> f64 {
    let (x0, xn) = profile.master_range();
    ((u - x0) / (xn - x0)).floor()
}

impl<T: Copy + PartialEq, K: Copy + PartialEq> Cam<T, K> {
    fn value(&self, u: f64) -> f64 {
        cam_value(&self.profile, self.mapc.execution_mode, u)
    }

    fn slave_at(&self, run: &Run, u: f64) -> f64 {
        run.slave_start + self.sign * self.mapc.slave_scaling * (self.value(u) - run.f_start)
    }

    /// A fresh run locked at clutch position `c0` at cam coordinate `u0`.
    fn lock_at(&self, c0: f64, u0: f64, slave: f64) -> Run {
        Run {
            clutch: c0,
            c_ref: c0,
            u_ref: u0,
            u_start: u0,
            slave_start: slave,
            f_start: self.value(u0),
            u: u0,
            slipping: false,
            hold: None,
        }
    }

    /// The clutch and coordinate for master position `m`, without changing
    /// the run.
    fn follow(&self, run: &Run, m: f64) -> (f64, f64, bool) {
        let (c, slipping) = match self.mapc.master_direction {
            MasterDirection::Bidirectional => (m, false),
            MasterDirection::ForwardOnly if m >= run.clutch => (m, false),
            MasterDirection::ReverseOnly if m <= run.clutch => (m, false),
            _ => (run.clutch, true),
        };
        (c, run.u_ref + (c - run.c_ref) / self.mapc.master_scaling, slipping)
    }
}

/// Where the master, moving from `prev` to `now`, crossed (or reached) the
/// lock position in the schedule's direction; on a modulo master any
/// position `lock + k · period` counts.
fn crossing(schedule: ExecutionSchedule, lock: f64, period: Option<f64>, prev: f64, now: f64) -> Option<f64> {
    let (forward_ok, reverse_ok) = match schedule {
        ExecutionSchedule::ForwardOnly => (true, false),
        ExecutionSchedule::ReverseOnly => (false, true),
        ExecutionSchedule::Bidirectional => (true, true),
        ExecutionSchedule::Immediate | ExecutionSchedule::Pending => (false, false),
    };
    if now > prev && forward_ok {
        let at = period.map_or(lock, |p| lock + ((prev - lock) / p).ceil() * p);
        (prev <= at && at <= now).then_some(at)
    } else if now < prev && reverse_ok {
        let at = period.map_or(lock, |p| lock + ((prev - lock) / p).floor() * p);
        (now <= at && at <= prev).then_some(at)
    } else {
        None
    }
}

impl<T: Copy + PartialEq, K: Copy + PartialEq> PositionCamAxis<T, K> {
    /// The slave's status bits.
    pub fn status(&self) -> SlaveCamStatus {
        let replacement = matches!(
            self.waiting,
            Some(Waiting {
                kind: WaitKind::Replacement { .. },
                ..
            })
        );
        let lock = match &self.active {
            Some(Active {
                cam,
                phase: Phase::Running(run),
            }) => {
                let (x0, xn) = cam.profile.master_range();
                !run.slipping && (cam.mapc.execution_mode == ExecutionMode::Continuous || (x0..=xn).contains(&run.u))
            }
            _ => false,
        };
        SlaveCamStatus {
            position_cam: self.active.is_some() || replacement,
            lock,
            pending: self.waiting.is_some(),
        }
    }

    /// Whether a cam owns the slave now (active, running or waiting for its
    /// lock, or a replacement waiting): nothing else may command it.
    pub fn drives(&self) -> bool {
        let s = self.status();
        s.position_cam
    }

    /// The master offset (master offset moves), master units.
    pub fn master_offset(&self) -> f64 {
        self.master_offset
    }

    /// A master offset move: shifts the master position the cam sees by
    /// `delta` (the cam profile moves by −`delta` along the master).
    pub fn shift_master_offset(&mut self, delta: f64) {
        if delta.is_finite() {
            self.master_offset += delta;
        }
    }

    /// The slave's position was redefined by `delta` (MRP): the running cam
    /// continues from the shifted position.
    pub fn redefine_slave(&mut self, delta: f64) {
        if let Some(Active {
            phase: Phase::Running(run),
            ..
        }) = &mut self.active
        {
            run.slave_start += delta;
            if let Some(h) = run.hold.as_mut() {
                *h += delta;
            }
        }
    }

    /// The cam coordinate `u` of the running cam (unscaled cam master units).
    pub fn cam_coordinate(&self) -> Option<f64> {
        match &self.active {
            Some(Active {
                phase: Phase::Running(run),
                ..
            }) => Some(run.u),
            _ => None,
        }
    }

    /// The direction sign (+1 Same, −1 Opposite) the next cam would use for
    /// `direction`, and the memory after it.
    fn resolve(&mut self, direction: CamDirection) -> f64 {
        let previous = self.direction_memory.unwrap_or(1.0);
        let sign = match direction {
            CamDirection::Same => 1.0,
            CamDirection::Opposite => -1.0,
            CamDirection::Reverse => -previous,
            CamDirection::Unchanged => previous,
        };
        self.direction_memory = Some(sign);
        sign
    }

    /// Executes an MAPC. `slave` is the slave's command position now, and
    /// `master(key)` a master's position now (without the master offset).
    /// Returns the events of other cams it superseded and its own `Active`
    /// when it locks at once.
    ///
    /// # Errors
    /// ERR 13 (EXERR 10) when the Cam Lock Position is outside the profile's
    /// master range (not checked for Replace and Continue, which ignores it).
    pub fn start(
        &mut self,
        req: CamRequest<T, K>,
        slave: f64,
        master: impl Fn(K) -> f64,
    ) -> Result<Vec<CamEvent<T>>, MapcError> {
        let m = req.mapc;
        let (x0, xn) = req.profile.master_range();
        let lock_ignored =
            m.cam_type == CamType::ReplaceAndContinue && m.execution_schedule != ExecutionSchedule::Pending;
        if !lock_ignored && !(x0..=xn).contains(&m.cam_lock_position) {
            return Err(MapcError::ParameterOutOfRange {
                operand: operand::CAM_LOCK_POSITION,
                value: m.cam_lock_position,
            });
        }
        let sign = self.resolve(m.direction);
        let cam = Cam {
            tag: req.tag,
            master: req.master,
            profile: req.profile,
            sign,
            mapc: m,
            master_period: req.master_period.filter(|p| p.is_finite() && *p > 0.0),
        };
        let mut events = Vec::new();
        if m.execution_schedule == ExecutionSchedule::Pending {
            if let Some(w) = self.waiting.take() {
                events.push(CamEvent::Ended {
                    tag: w.cam.tag,
                    complete: false,
                });
            }
            self.waiting = Some(Waiting {
                cam,
                kind: WaitKind::Pending,
            });
            return Ok(events);
        }
        self.master_offset = 0.0;
        let now = master(cam.master) + self.master_offset;
        let replace = m.cam_type != CamType::NewCam && self.active.is_some();
        if replace {
            // A replacement cancels whatever waits.
            if let Some(w) = self.waiting.take() {
                events.push(CamEvent::Ended {
                    tag: w.cam.tag,
                    complete: false,
                });
            }
            if m.execution_schedule == ExecutionSchedule::Immediate {
                self.replace(cam, now, slave, &master, &mut events);
            } else {
                self.waiting = Some(Waiting {
                    cam,
                    kind: WaitKind::Replacement { prev: now },
                });
            }
            return Ok(events);
        }
        // A new cam: supersedes the active cam and a waiting replacement.
        if let Some(a) = self.active.take() {
            events.push(CamEvent::Ended {
                tag: a.cam.tag,
                complete: false,
            });
        }
        if matches!(
            self.waiting,
            Some(Waiting {
                kind: WaitKind::Replacement { .. },
                ..
            })
        ) && let Some(w) = self.waiting.take()
        {
            events.push(CamEvent::Ended {
                tag: w.cam.tag,
                complete: false,
            });
        }
        if m.execution_schedule == ExecutionSchedule::Immediate {
            let run = cam.lock_at(now, m.cam_lock_position, slave);
            events.push(CamEvent::Active(cam.tag));
            self.active = Some(Active {
                cam,
                phase: Phase::Running(run),
            });
        } else {
            self.active = Some(Active {
                cam,
                phase: Phase::Armed { prev: now },
            });
        }
        Ok(events)
    }

    /// Replaces the active cam by `cam` at master position `at` (master
    /// offset included) of the replacement's master.
    fn replace(
        &mut self,
        cam: Cam<T, K>,
        at: f64,
        slave_now: f64,
        master: &impl Fn(K) -> f64,
        events: &mut Vec<CamEvent<T>>,
    ) {
        let old = self.active.take();
        let mut run = None;
        if let Some(Active {
            cam: old_cam,
            phase: Phase::Running(old_run),
        }) = &old
        {
            let m_old = if old_cam.master == cam.master {
                at
            } else {
                master(old_cam.master) + self.master_offset
            };
            let (c_old, u_old, slipping) = old_cam.follow(old_run, m_old);
            let inherit = slipping
                && old_cam.mapc.master_direction == cam.mapc.master_direction
                && cam.mapc.master_direction != MasterDirection::Bidirectional;
            let c0 = if inherit { c_old } else { at };
            let slave_at = old_cam.slave_at(old_run, u_old);
            run = Some(match cam.mapc.cam_type {
                CamType::ReplaceAndContinue => Run {
                    clutch: c0,
                    c_ref: c0,
                    u_ref: u_old,
                    u_start: old_run.u_start,
                    slave_start: old_run.slave_start,
                    f_start: cam.value(old_run.u_start),
                    u: u_old,
                    slipping: false,
                    hold: inherit.then_some(slave_at),
                },
                _ => cam.lock_at(c0, cam.mapc.cam_lock_position, slave_at),
            });
        }
        if let Some(a) = old {
            events.push(CamEvent::Ended {
                tag: a.cam.tag,
                complete: false,
            });
        }
        let run = run.unwrap_or_else(|| cam.lock_at(at, cam.mapc.cam_lock_position, slave_now));
        events.push(CamEvent::Active(cam.tag));
        self.active = Some(Active {
            cam,
            phase: Phase::Running(run),
        });
    }

    /// Stops the position cam process (MAS/MCS with Stop Type All or Position
    /// Cam, or a shutdown): every cam ends, not complete.
    pub fn stop(&mut self) -> Vec<CamEvent<T>> {
        let mut events = Vec::new();
        if let Some(a) = self.active.take() {
            events.push(CamEvent::Ended {
                tag: a.cam.tag,
                complete: false,
            });
        }
        if let Some(w) = self.waiting.take() {
            events.push(CamEvent::Ended {
                tag: w.cam.tag,
                complete: false,
            });
        }
        events
    }

    /// One coarse update: `slave` is the slave's command position before it,
    /// `master(key)` the masters' positions now. Returns the slave's new
    /// command position (`None` when no cam commands it) and the events.
    ///
    /// A slave position that is not a finite number (extreme scalings or
    /// master travel overflowing `f64`) ends the active cam with
    /// [`CamEvent::Overflow`]; the slave holds where it was.
    pub fn update(&mut self, slave: f64, master: impl Fn(K) -> f64) -> (Option<f64>, Vec<CamEvent<T>>) {
        let (position, mut events) = self.advance(slave, master);
        if position.is_some_and(|p| !p.is_finite()) {
            if let Some(a) = self.active.take() {
                events.push(CamEvent::Ended {
                    tag: a.cam.tag,
                    complete: false,
                });
                events.push(CamEvent::Overflow(a.cam.tag));
            } else if let Some(CamEvent::Ended { tag, complete }) =
                events.iter_mut().rev().find(|e| matches!(e, CamEvent::Ended { .. }))
            {
                // A Once cam that ended at its boundary with an overflowing
                // end position: it did not complete.
                *complete = false;
                let tag = *tag;
                events.push(CamEvent::Overflow(tag));
            }
            return (Some(slave), events);
        }
        (position, events)
    }

    fn advance(&mut self, slave: f64, master: impl Fn(K) -> f64) -> (Option<f64>, Vec<CamEvent<T>>) {
        let mut events = Vec::new();
        let offset = self.master_offset;
        let mpos = |k: K| master(k) + offset;
        // A scheduled replacement whose master crossed its lock position.
        if let Some(Waiting {
            cam,
            kind: WaitKind::Replacement { prev },
        }) = &mut self.waiting
        {
            let now = mpos(cam.master);
            let lock = cam.mapc.master_lock_position;
            let crossed = crossing(cam.mapc.execution_schedule, lock, cam.master_period, *prev, now);
            *prev = now;
            if let Some(at) = crossed
                && let Some(w) = self.waiting.take()
            {
                self.replace(w.cam, at, slave, &mpos, &mut events);
            }
        }
        let Some(active) = &mut self.active else {
            return (None, events);
        };
        let cam = &active.cam;
        let m = mpos(cam.master);
        let mut run = match active.phase {
            Phase::Armed { prev } => {
                let lock = cam.mapc.master_lock_position;
                let Some(at) = crossing(cam.mapc.execution_schedule, lock, cam.master_period, prev, m) else {
                    active.phase = Phase::Armed { prev: m };
                    return (Some(slave), events);
                };
                events.push(CamEvent::Active(cam.tag));
                cam.lock_at(at, cam.mapc.cam_lock_position, slave)
            }
            Phase::Running(run) => run,
        };
        let (c, u, slipping) = cam.follow(&run, m);
        let (x0, xn) = cam.profile.master_range();
        let pending = matches!(
            self.waiting,
            Some(Waiting {
                kind: WaitKind::Pending,
                ..
            })
        );
        // Where the cam ends this update, if it does: the boundary crossed.
        let boundary = match cam.mapc.execution_mode {
            ExecutionMode::Once => (!(x0..=xn).contains(&u)).then(|| u.clamp(x0, xn)),
            ExecutionMode::Persistent if pending => (!(x0..=xn).contains(&u)).then(|| u.clamp(x0, xn)),
            ExecutionMode::Continuous if pending => {
                // The end of the cycle `u` was in: its end going forward,
                // its start going back (however far the master went).
                let (k0, k1) = (cycle(&cam.profile, run.u), cycle(&cam.profile, u));
                (k1 != k0).then_some(x0 + (xn - x0) * if k1 > k0 { k0 + 1.0 } else { k0 })
            }
            _ => None,
        };
        let Some(ub) = boundary else {
            run.clutch = c;
            run.u = u;
            run.slipping = slipping;
            let s = match run.hold {
                Some(h) if slipping => h,
                _ => {
                    run.hold = None;
                    cam.slave_at(&run, u)
                }
            };
            active.phase = Phase::Running(run);
            return (Some(s), events);
        };
        // The cam ends at `ub`; a Pending cam takes over there.
        let slave_end = cam.slave_at(&run, ub);
        let c_end = run.c_ref + (ub - run.u_ref) * cam.mapc.master_scaling;
        let complete = cam.mapc.execution_mode == ExecutionMode::Once;
        let old_master = cam.master;
        let Some(a) = self.active.take() else {
            return (Some(slave_end), events);
        };
        events.push(CamEvent::Ended {
            tag: a.cam.tag,
            complete,
        });
        if pending && let Some(w) = self.waiting.take() {
            let mut next = w.cam;
            next.master = old_master;
            let mut run = next.lock_at(c_end, next.mapc.cam_lock_position, slave_end);
            let (c, u, slipping) = next.follow(&run, m);
            run.clutch = c;
            run.u = u;
            run.slipping = slipping;
            let s = next.slave_at(&run, u);
            events.push(CamEvent::Active(next.tag));
            self.active = Some(Active {
                cam: next,
                phase: Phase::Running(run),
            });
            return (Some(s), events);
        }
        (Some(slave_end), events)
    }
}

#[cfg(test)]
mod tests;
