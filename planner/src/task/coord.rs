//! Coordinated motion in the executor: coordinate systems, MCLM / MCCM / MCS
//! instructions with their `MOTION_INSTRUCTION` bits, the one-place queue,
//! blending, merging, master-driven moves and the status bits.
//!
//! # How a system moves
//! Every started move is a *component*: its path geometry and a 1-D
//! [`Profile`] of the path length from rest to rest, advanced by time (or by
//! master distance). The command position of the system's axes is
//! `base + Σ (P_i(s_i) − P_i(0))` over the running components, where `base`
//! is the start of the oldest one (it absorbs each finished component). One
//! component is a plain move; two overlap during a blend or a merge: the
//! first finishes its own deceleration while the second accelerates from
//! the end point of the first, so the corner is rounded, the path speed
//! never drops to zero at the junction, and each component still ends
//! exactly at its programmed point.
//!
//! * **Termination types 2, 3, 6** with a pending move: the pending move
//!   starts when the active one reaches its *blend point*: type 3 its
//!   deceleration point; types 2 and 6 the point where the command distance
//!   to go equals the command tolerance (the system's, or the operand's for
//!   6) — deferred to the deceleration point when the tolerance is longer
//!   than the deceleration distance (the spec allows a deferral "for time
//!   matching"; starting earlier would overlap the cruise of the first move
//!   with the acceleration of the second and exceed the programmed speed on
//!   collinear moves). A tolerance of 0 blends at the end point, at rest.
//!   The blend is also deferred "for time matching": the pending move
//!   starts no sooner than its acceleration time before the active move's
//!   end, so its acceleration never ends before the active move's
//!   deceleration does and the two speeds never add up to more than the
//!   faster programmed speed (a quickly accelerating second move would
//!   otherwise overshoot on collinear moves).
//!   The active move's `.PC` is set at the blend point (its `.AC` clears,
//!   the new move's `.AC` sets); its `.IP` clears when it reaches its end.
//! * **Types 4, 5** (follow contour) with a pending move of the same
//!   driver: the move passes exactly through its end point without
//!   stopping, at the junction speed: the lower of the two programmed
//!   speeds, limited to what the pending move can stop from within its
//!   length (see `plan_contour_junction`); the pending move starts there at
//!   that speed. The path is not rounded, so the corner should be tangent
//!   (as the spec's follow-contour types assume); a corner that is not
//!   changes the axes' velocities in one coarse update. Type 5
//!   (unconstrained) is planned like type 4: the move never runs faster
//!   than its own programmed speed to meet a faster next move. `.PC` sets
//!   at the end point, `MoveTransitionStatus` stays clear (on path).
//! * **Types 0, 1**, types 4, 5 without a pending move (of the same
//!   driver), or no pending move: the move runs to its end point at rest;
//!   `.PC` and `.IP` when interpolation is complete, for
//!   type 0 only once the actual position (primary axes) is within the
//!   actual tolerance. A pending move starts then.
//! * **Queue**: one pending move. A further MCLM/MCCM with Merge disabled is
//!   *held* (its `.EN` stays set, nothing else) and is verified and queued
//!   as soon as the place is free: the choice a Logix program expects, which
//!   conditions its moves on `MovePendingQueueFullStatus`.
//! * **Merge** coordinated motion / all motion: running components are
//!   brought to rest along their paths with their own decelerations
//!   (superimposed, like a blend), the pending move is cancelled, and the new
//!   move starts at once from the point where the old motion comes to rest,
//!   with its programmed speed or, for merge speed *current*, the vector
//!   speed of all motion on the system's primary axes at that instant (from
//!   the axes' command velocities: coordinated motion, moves, jogs, cams;
//!   the programmed speed when they stand still; Calculated Data are
//!   computed with the speed the move runs at). Superseded instructions lose `.IP` and `.AC`.
//! * **Systems sharing axes**: a move on a system while another system that
//!   shares an axis with it moves (or has a move queued) is refused with
//!   ERR 13, EXERR = the Merge operand, unless its Merge is *all motion*
//!   (the spec: "an error is flagged if a second instruction is initiated …
//!   in another coordinate system containing any axes in common"). Merge
//!   all motion ends the other system's motion where its command stands
//!   (its instructions lose `.IP`/`.AC`); the two systems' motions are not
//!   blended, so the new move starts with the command velocity of its own
//!   (rest) profile.
//! * **Single-axis motion** (MC_MoveModulo, MAPC cams, MAJ jogs, MAS
//!   stops) and coordinated motion never superimpose here: a coordinated
//!   move that starts aborts the single-axis commands on its axes and ends
//!   their cams and jogs (whatever the merge type; the spec's superimposed
//!   motion for merge disabled is not modelled; the move starts from rest
//!   on its own profile), and a single-axis command that takes an axis of a
//!   moving system (or an axis reset) brings that system to rest along its
//!   path (its instructions lose `.IP`/`.AC`, the pending move is
//!   cancelled) while the single-axis command alone writes that axis.
//! * [`MotionTask::stop_all_axes`] (the twin's collision stop) brings every
//!   moving system to rest along its path with the system's maximum
//!   deceleration.
//! * **MCS** brings every component to rest along its path with the stop's
//!   deceleration (a component already braking to its end closer than that
//!   keeps its own profile), cancels the pending move and sets
//!   `StoppingStatus`; its `.IP` clears and `.PC` sets when the system is
//!   at rest. Stop type *all* also brings the single-axis commands on the
//!   system's axes to rest (they report `CommandAborted`).
//! * **Master driven** (speed units per master unit): the path advances by
//!   the master axis' command position instead of time (see
//!   [`LockDirection`] for when it follows). The master is linked with
//!   [`MotionTask::set_coordinate_system_master`] (the MDCC of a Logix
//!   program).
//! * The twin's pre-flight sweep sees each move when it starts
//!   ([`MotionTask::coord_moves_started`]) and may reject it
//!   ([`MotionTask::reject_coord_move`], `.ER` with ERR
//!   [`ERR_PATH_COLLISION`]; see `task/coord/preflight.rs`).
//! * Axis command acceleration and jerk of coordinated axes are the finite
//!   differences of the command velocity over the coarse update.
//! * `CommandPosToleranceStatus`: the spec says both "remains set after the
//!   instruction completes, reset when a new instruction is started" and,
//!   for types 0, 1, 4, 5, "cleared when the first move is complete"; the
//!   first rule is kept (it is cleared when the next move starts), and for
//!   types 2, 3, 6 it is cleared when the blend starts.
//!
//! * **Time driven → master driven** with the master at rest: the spec's
//!   run-time error ("you cannot switch from Time Driven Mode to Master
//!   Driven Mode if the master speed is zero unless the slave speed is zero
//!   too"; Rockwell names it MDSC_IDLE_MASTER_AND_SLAVE_MOVING). A
//!   master-driven move that would take over from time-driven motion (or
//!   from single-axis motion) while the system's primary axes move and the
//!   master's command velocity is 0 is not started: `.ER` with ERR
//!   [`ERR_IDLE_MASTER_SLAVE_MOVING`] (the spec gives no number; this one is
//!   the project's, next to [`ERR_PATH_COLLISION`]), EXERR 0. Executed
//!   directly or as a merge, it has no `.DN` and the running motion goes on;
//!   when it comes out of the queue at a blend point it keeps its `.DN`
//!   (the spec: "set with the Done bit when a queued instruction encounters
//!   a runtime error"), leaves the queue, and the running move ends at its
//!   end point.
//!
//! * **Rotary axes with an unwind** (`AxisKind::Rotary` with a modulo
//!   period `U`) in an absolute MCLM/MCCM: the spec's rule — the sign of
//!   the Position element selects the direction (0 and −0 forward; −U
//!   reaches the unwind position backward), the axis turns by less than one
//!   unwind to `|p|` modulo `U`, and `|p| > U` is an error (ERR 13, EXERR =
//!   the Position operand; the spec gives no number). Incremental moves
//!   turn by the increment. The via/center operands of an arc are not
//!   unwound (a rotary primary axis in an arc uses its unwrapped position).
//!
//! # Not modelled
//! * MCCD (change dynamics), MCSD/MCSR and MDCC as instructions; the
//!   master of master-driven moves is set with
//!   [`MotionTask::set_coordinate_system_master`].

use super::{AxisHandle, Finish, InstructionHandle, MotionTask};
use crate::axis::AxisKind;
use crate::coord::{
    CoordConfigError, CoordMove, CoordMoveError, CoordMoveInputs, CoordStatus, CoordinateSystem,
    CoordinateSystemConfig, Driver, LockDirection, Mcs, McsInputs, Merge, MergeSpeed, MoveContext, TerminationType,
    norm, primary_of, progress_at_length,
};
use crate::coord::{OperandIndex, with_velocity};
use crate::instruction::MotionInstructionBits;
use crate::mccm::{MccmInputs, mccm};
use crate::mclm::mclm;
use crate::profile::{Limits, Profile, Sample, State, stopping_distance};
use thiserror::Error;

/// ERR of a master-driven coordinated move that would take over from
/// time-driven motion while the master stands still and the system moves
/// (Rockwell's MDSC_IDLE_MASTER_AND_SLAVE_MOVING; EXERR 0).
pub const ERR_IDLE_MASTER_SLAVE_MOVING: i32 = 201;

/// Handle of a coordinate system in a [`MotionTask`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct CoordHandle(u32);

/// Handle of a coordinated instruction (MCLM, MCCM, MCS) in a [`MotionTask`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct CoordInstructionHandle(u32);

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
    systems: Vec<SystemSlot>,
    instructions: Vec<InstrSlot>,
}

#[derive(Debug, Clone)]
struct SystemSlot {
    system: CoordinateSystem,
    axes: Vec<AxisHandle>,
    master: Option<AxisHandle>,
    master_prev: Option<f64>,
    status: CoordStatus,
    base: Vec<f64>,
    components: Vec<Component>,
    pending: Option<(CoordInstructionHandle, CoordMove)>,
    stop: Option<CoordInstructionHandle>,
    queue_end: Vec<f64>,
    velocity: Vec<f64>,
    acceleration: Vec<f64>,
    /// Axes another command took while the system brakes (not written).
    taken: Vec<AxisHandle>,
}

#[derive(Debug, Clone)]
struct Component {
    instr: Option<CoordInstructionHandle>,
    mv: CoordMove,
    profile: Profile,
    progress: f64,
    last_delta: f64,
    blend_at: Option<f64>,
    successor_started: bool,
    /// Follow contour (types 4, 5): the profile was replanned to reach the
    /// end point at the junction speed of the pending move.
    contour: bool,
    stopping: bool,
    lock: Lock,
    /// When and from what it started (`task/coord/preflight.rs`).
    start: preflight::Start,
}

impl Component {
    fn done(&self) -> bool {
        if self.progress < self.profile.duration_s() {
            return false;
        }
        let l = self.mv.path().length();
        self.stopping || self.profile.final_state().position >= l - 1e-12 * (1.0 + l)
    }

    fn s(&self) -> Sample {
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
struct Lock {
    direction: LockDirection,
    position: f64,
    engaged: bool,
    mark: f64,
    locked: bool,
}

impl Lock {
    fn new(direction: LockDirection, position: f64, master_now: f64) -> Self {
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
    fn advance(&mut self, prev: f64, now: f64) -> f64 {
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
struct InstrSlot {
    control: InstructionHandle,
    system: CoordHandle,
    call: CoordCall,
    rung: bool,
    previous_rung: bool,
    held: bool,
    calculated_data: Vec<f64>,
}

impl MotionTask {
    /// Adds a coordinate system over `axes` (primary axes first, as many as
    /// `config.axis_count`).
    ///
    /// # Errors
    /// [`CoordSetupError`] for an invalid configuration or axis list.
    pub fn add_coordinate_system(
        &mut self,
        config: CoordinateSystemConfig,
        axes: &[AxisHandle],
    ) -> Result<CoordHandle, CoordSetupError> {
        let mut unique = axes.to_vec();
        unique.sort();
        unique.dedup();
        if axes.len() != config.axis_count || unique.len() != axes.len() {
            return Err(CoordSetupError::Axes {
                name: config.name.clone(),
                given: axes.len(),
                expected: config.axis_count,
            });
        }
        let system = CoordinateSystem::new(config)?;
        let here: Vec<f64> = axes.iter().map(|a| self.axes[a.0 as usize].command.position).collect();
        let n = axes.len();
        self.coord.systems.push(SystemSlot {
            system,
            axes: axes.to_vec(),
            master: None,
            master_prev: None,
            status: CoordStatus::default(),
            base: here.clone(),
            components: Vec::new(),
            pending: None,
            stop: None,
            queue_end: here,
            velocity: vec![0.0; n],
            acceleration: vec![0.0; n],
            taken: Vec::new(),
        });
        Ok(CoordHandle(self.coord.systems.len() as u32 - 1))
    }

    /// Links (or unlinks) the master axis whose command position drives the
    /// system's master-driven moves (the role of MDCC).
    pub fn set_coordinate_system_master(&mut self, system: CoordHandle, master: Option<AxisHandle>) {
        let slot = &mut self.coord.systems[system.0 as usize];
        slot.master = master;
        slot.master_prev = master.map(|m| self.axes[m.0 as usize].command.position);
    }

    /// The master axis of a system's master-driven moves, if linked.
    pub fn coordinate_system_master(&self, system: CoordHandle) -> Option<AxisHandle> {
        self.coord.systems[system.0 as usize].master
    }

    /// The status bits of a coordinate system after the last update.
    pub fn coord_status(&self, system: CoordHandle) -> CoordStatus {
        self.coord.systems[system.0 as usize].status
    }

    /// A coordinate system's configuration.
    pub fn coord_config(&self, system: CoordHandle) -> &CoordinateSystemConfig {
        self.coord.systems[system.0 as usize].system.config()
    }

    /// The axes of a coordinate system, primary first.
    pub fn coord_axes(&self, system: CoordHandle) -> &[AxisHandle] {
        &self.coord.systems[system.0 as usize].axes
    }

    /// Every coordinate system, in the order added.
    pub fn coord_handles(&self) -> impl Iterator<Item = CoordHandle> + use<> {
        (0..self.coord.systems.len() as u32).map(CoordHandle)
    }

    /// The arc or line currently leading the system's motion, if any (for
    /// traces and tests): the move of the newest running component.
    pub fn coord_active_move(&self, system: CoordHandle) -> Option<&CoordMove> {
        self.coord.systems[system.0 as usize].components.last().map(|c| &c.mv)
    }

    /// The axis bit `CoordinatedMotionStatus`: a coordinated move drives the
    /// axis.
    pub fn coordinated_motion_status(&self, axis: AxisHandle) -> bool {
        self.coord
            .systems
            .iter()
            .any(|s| !s.components.is_empty() && s.axes.contains(&axis))
    }

    /// Adds a coordinated instruction (its `MOTION_INSTRUCTION` tag is
    /// `name`) on `system`, with its rung false.
    pub fn add_coord_instruction(
        &mut self,
        name: impl Into<String>,
        system: CoordHandle,
        call: CoordCall,
    ) -> CoordInstructionHandle {
        let control = self.add_instruction(name);
        self.bind_coord_instruction(control, system, call)
    }

    fn bind_coord_instruction(
        &mut self,
        control: InstructionHandle,
        system: CoordHandle,
        call: CoordCall,
    ) -> CoordInstructionHandle {
        self.coord.instructions.push(InstrSlot {
            control,
            system,
            call,
            rung: false,
            previous_rung: false,
            held: false,
            calculated_data: Vec::new(),
        });
        CoordInstructionHandle(self.coord.instructions.len() as u32 - 1)
    }

    /// Executes MCLM, MCCM or MCS with the control structure `control` on
    /// `system` now: one scan of a rung that has just become true (the
    /// twin's one-shot rung). `.EN` and `.DN`/`.ER` are set at once; the rung
    /// is false from the next update on, which clears `.EN` once `.DN` or
    /// `.ER` is set (a held move keeps `.EN` until it is queued). One control
    /// structure serves one instruction at a time, as on a controller: a
    /// new call with the same tag replaces the operands it executes with.
    ///
    /// # Examples
    /// ```
    /// use planner::axis::{AxisConfig, AxisKind};
    /// use planner::coord::{CoordMoveInputs, CoordinateSystemConfig};
    /// use planner::task::{CoordCall, MotionTask};
    /// let mut task = MotionTask::new(0.004).unwrap();
    /// let x = task.add_axis(AxisConfig::new("X", AxisKind::Linear), 0.0).unwrap();
    /// let y = task.add_axis(AxisConfig::new("Y", AxisKind::Linear), 0.0).unwrap();
    /// let config = CoordinateSystemConfig { axis_count: 2, primary_axes: 2, ..CoordinateSystemConfig::new("CS") };
    /// let cs = task.add_coordinate_system(config, &[x, y]).unwrap();
    /// let mc = task.add_instruction("MC1");
    /// let line = CoordMoveInputs { position: vec![0.3, 0.4], ..Default::default() };
    /// task.execute_coordinated(cs, mc, CoordCall::Mclm(line));
    /// assert!(task.motion_bits(mc).dn && task.motion_bits(mc).ip);
    /// while !task.motion_bits(mc).pc {
    ///     task.update();
    /// }
    /// assert_eq!(task.axis_state(y).command_position, 0.4);
    /// ```
    pub fn execute_coordinated(&mut self, system: CoordHandle, control: InstructionHandle, call: CoordCall) {
        let existing = self
            .coord
            .instructions
            .iter()
            .position(|s| s.control == control)
            .map(|i| CoordInstructionHandle(i as u32));
        let h = match existing {
            Some(h) => {
                let slot = &mut self.coord.instructions[h.0 as usize];
                slot.system = system;
                slot.call = call;
                h
            }
            None => self.bind_coord_instruction(control, system, call),
        };
        let slot = &mut self.coord.instructions[h.0 as usize];
        slot.previous_rung = false;
        slot.rung = true;
        self.scan_coord_instruction(h);
        self.coord.instructions[h.0 as usize].rung = false;
        self.started_before_update(h);
    }

    /// The coordinated instruction bound to a control structure, if any.
    pub fn coord_instruction_of(&self, control: InstructionHandle) -> Option<CoordInstructionHandle> {
        self.coord
            .instructions
            .iter()
            .position(|s| s.control == control)
            .map(|i| CoordInstructionHandle(i as u32))
    }

    /// The control structure (`MOTION_INSTRUCTION` tag) of a coordinated
    /// instruction.
    pub fn coord_control(&self, instr: CoordInstructionHandle) -> InstructionHandle {
        self.coord.instructions[instr.0 as usize].control
    }

    fn cbits(&mut self, h: CoordInstructionHandle) -> &mut MotionInstructionBits {
        let control = self.coord.instructions[h.0 as usize].control;
        self.motion_bits_mut(control)
    }

    /// Sets an instruction's rung condition and operands; evaluated at the
    /// next update (a false → true transition executes it).
    pub fn set_coord_instruction(&mut self, instr: CoordInstructionHandle, rung: bool, call: CoordCall) {
        let slot = &mut self.coord.instructions[instr.0 as usize];
        slot.rung = rung;
        slot.call = call;
    }

    /// Sets only an instruction's rung condition.
    pub fn set_coord_rung(&mut self, instr: CoordInstructionHandle, rung: bool) {
        self.coord.instructions[instr.0 as usize].rung = rung;
    }

    /// An instruction's `MOTION_INSTRUCTION` bits after the last update.
    pub fn coord_bits(&self, instr: CoordInstructionHandle) -> MotionInstructionBits {
        self.instructions[self.coord.instructions[instr.0 as usize].control.0 as usize].bits
    }

    /// An instruction's Calculated Data (filled when it is verified).
    pub fn coord_calculated_data(&self, instr: CoordInstructionHandle) -> &[f64] {
        &self.coord.instructions[instr.0 as usize].calculated_data
    }

    /// An instruction's tag name.
    pub fn coord_instruction_name(&self, instr: CoordInstructionHandle) -> &str {
        self.instruction_name(self.coord.instructions[instr.0 as usize].control)
    }

    /// Every coordinated instruction, in the order added.
    pub fn coord_instruction_handles(&self) -> impl Iterator<Item = CoordInstructionHandle> + use<> {
        (0..self.coord.instructions.len() as u32).map(CoordInstructionHandle)
    }

    /// Step 1b of an update: rung transitions of the coordinated
    /// instructions (held ones retry first).
    pub(super) fn evaluate_coord_instructions(&mut self) {
        for i in 0..self.coord.instructions.len() {
            let h = CoordInstructionHandle(i as u32);
            if self.coord.instructions[i].held {
                self.execute_coord(h);
            }
        }
        for i in 0..self.coord.instructions.len() {
            self.scan_coord_instruction(CoordInstructionHandle(i as u32));
        }
    }

    /// One scan of an instruction's rung: a false rung clears `.EN` once
    /// `.DN` or `.ER` is set; a rising rung resets `.DN`, `.ER`, `.PC` and
    /// the error codes, sets `.EN`, and executes.
    fn scan_coord_instruction(&mut self, h: CoordInstructionHandle) {
        let slot = &mut self.coord.instructions[h.0 as usize];
        let rising = slot.rung && !slot.previous_rung;
        let rung = slot.rung;
        slot.previous_rung = slot.rung;
        let bits = self.cbits(h);
        if !rung && (bits.dn || bits.er) {
            bits.en = false;
        }
        if rising {
            *bits = MotionInstructionBits {
                en: true,
                ip: bits.ip,
                ac: bits.ac,
                accel: bits.accel,
                decel: bits.decel,
                ..MotionInstructionBits::default()
            };
            self.execute_coord(h);
        }
    }

    fn execute_coord(&mut self, h: CoordInstructionHandle) {
        let slot = &self.coord.instructions[h.0 as usize];
        let cs = slot.system;
        match slot.call.clone() {
            CoordCall::Mcs(inputs) => {
                self.coord.instructions[h.0 as usize].held = false;
                self.execute_mcs(h, cs, &inputs);
            }
            CoordCall::Mclm(mut inputs) => {
                let merge = (inputs.merge, OperandIndex::MCLM.merge);
                self.execute_move(h, cs, merge, |ctx, unwinds| {
                    let c = &mut inputs;
                    unwind_rotary_targets(
                        unwinds,
                        ctx.start,
                        c.move_type,
                        &mut c.position,
                        OperandIndex::MCLM.position,
                    )?;
                    mclm(&inputs, ctx)
                });
            }
            CoordCall::Mccm(mut inputs) => {
                let merge = (inputs.common.merge, OperandIndex::MCCM.merge);
                self.execute_move(h, cs, merge, |ctx, unwinds| {
                    let c = &mut inputs.common;
                    unwind_rotary_targets(
                        unwinds,
                        ctx.start,
                        c.move_type,
                        &mut c.position,
                        OperandIndex::MCCM.position,
                    )?;
                    mccm(&inputs, ctx)
                });
            }
        }
    }

    fn execute_move(
        &mut self,
        h: CoordInstructionHandle,
        cs: CoordHandle,
        (merge_code, merge_exerr): (i64, i32),
        verify: impl FnOnce(&MoveContext<'_>, &[Option<f64>]) -> Result<CoordMove, CoordMoveError>,
    ) {
        let sys = &self.coord.systems[cs.0 as usize];
        let busy = !sys.components.is_empty() || sys.pending.is_some();
        let merging = busy && (merge_code == 1 || merge_code == 2);
        if busy && !merging && sys.pending.is_some() {
            self.coord.instructions[h.0 as usize].held = true;
            return;
        }
        self.coord.instructions[h.0 as usize].held = false;
        let start = if merging {
            self.rest_point(cs)
        } else if busy {
            sys.queue_end.clone()
        } else {
            self.axis_positions(cs)
        };
        let decels: Vec<f64> = sys
            .axes
            .iter()
            .map(|a| self.axes[a.0 as usize].config.max_deceleration)
            .collect();
        let ctx = MoveContext {
            system: &sys.system,
            axis_max_decel: &decels,
            start: &start,
            has_master: sys.master.is_some(),
        };
        // The unwind of each rotary axis with a modulo period.
        let unwinds: Vec<Option<f64>> = sys
            .axes
            .iter()
            .map(|a| {
                let config = &self.axes[a.0 as usize].config;
                (config.kind == AxisKind::Rotary)
                    .then(|| config.modulo().map(|m| m.period()))
                    .flatten()
            })
            .collect();
        let result = verify(&ctx, &unwinds);
        let mv = match result {
            Ok(mv) => mv,
            Err(e) => {
                self.cbits(h).set_error(e.err(), e.exerr(), 0);
                return;
            }
        };
        // Another system moving axes of this one: merge all motion ends its
        // motion; otherwise the move is refused.
        let others = self.busy_systems_sharing_axes(cs);
        if !others.is_empty() {
            if mv.merge() != Merge::AllMotion {
                self.cbits(h).set_error(13, merge_exerr, 0);
                return;
            }
            for other in others {
                self.cancel_system(other);
            }
        }
        if (merging || !busy) && self.idle_master_with_moving_slave(cs, &mv) {
            self.cbits(h).set_error(ERR_IDLE_MASTER_SLAVE_MOVING, 0, 0);
            return;
        }
        self.cbits(h).dn = true;
        // Merge speed current: the speed of all motion on the axes now.
        let speed_now = self.vector_speed(cs);
        let mv = if mv.merge() != Merge::Disabled && mv.merge_speed() == MergeSpeed::Current && speed_now > 0.0 {
            mv.with_speed(speed_now)
        } else {
            mv
        };
        // Calculated Data with the speed the move runs at.
        self.coord.instructions[h.0 as usize].calculated_data = mv.calculated_data().to_vec();
        let sys = &mut self.coord.systems[cs.0 as usize];
        sys.status.stopping = false;
        if merging {
            self.bring_to_rest(cs, None);
            if mv.merge() == Merge::AllMotion {
                self.abort_single_axis_motion(cs);
            }
            self.start_component(cs, h, mv, 0.0);
        } else if busy {
            sys.queue_end = mv.path().end().to_vec();
            sys.pending = Some((h, mv));
            self.cbits(h).ip = true;
        } else {
            self.start_component(cs, h, mv, 0.0);
        }
        self.refresh_queue_status(cs);
    }

    fn execute_mcs(&mut self, h: CoordInstructionHandle, cs: CoordHandle, inputs: &McsInputs) {
        let sys = &self.coord.systems[cs.0 as usize];
        let stop = match Mcs::new(inputs, &sys.system) {
            Ok(s) => s,
            Err(e) => {
                self.cbits(h).set_error(e.err(), e.exerr(), 0);
                return;
            }
        };
        self.cbits(h).dn = true;
        self.mct_on_mcs(cs, inputs.stop_type);
        if stop.stop_all {
            self.stop_single_axis_motion(cs);
        }
        let sys = &mut self.coord.systems[cs.0 as usize];
        if sys.components.is_empty() && sys.pending.is_none() {
            self.cbits(h).pc = true;
            return;
        }
        let limits = match stop.decel_jerk {
            Some(j) => Limits::s_curve(f64::MAX / 4.0, stop.decel, stop.decel, j, j),
            None => Limits::trapezoidal(f64::MAX / 4.0, stop.decel, stop.decel),
        }
        .ok();
        self.bring_to_rest(cs, limits);
        let sys = &mut self.coord.systems[cs.0 as usize];
        sys.status.stopping = true;
        sys.status.move_ = false;
        sys.status.move_transition = false;
        sys.stop = Some(h);
        self.cbits(h).ip = true;
        self.refresh_queue_status(cs);
    }

    /// The other coordinate systems that move (or have a move queued on)
    /// an axis of `cs`.
    fn busy_systems_sharing_axes(&self, cs: CoordHandle) -> Vec<CoordHandle> {
        let mine = &self.coord.systems[cs.0 as usize].axes;
        (0..self.coord.systems.len())
            .filter(|&j| j != cs.0 as usize)
            .filter(|&j| {
                let s = &self.coord.systems[j];
                (!s.components.is_empty() || s.pending.is_some()) && s.axes.iter().any(|a| mine.contains(a))
            })
            .map(|j| CoordHandle(j as u32))
            .collect()
    }

    /// Ends a system's motion where its command stands now (merge all
    /// motion from another system): its instructions lose `.IP`/`.AC`, its
    /// queue is cleared, and its axes keep their command positions.
    fn cancel_system(&mut self, cs: CoordHandle) {
        let here = self.axis_positions(cs);
        let sys = &mut self.coord.systems[cs.0 as usize];
        let mut cleared: Vec<CoordInstructionHandle> = sys.components.drain(..).filter_map(|c| c.instr).collect();
        cleared.extend(sys.pending.take().map(|(h, _)| h));
        cleared.extend(sys.stop.take());
        sys.base = here.clone();
        sys.queue_end = here;
        sys.velocity.iter_mut().for_each(|v| *v = 0.0);
        sys.acceleration.iter_mut().for_each(|v| *v = 0.0);
        sys.status.clear_motion();
        self.refresh_queue_status(cs);
        for h in cleared {
            let b = self.cbits(h);
            b.ip = false;
            b.ac = false;
            b.accel = false;
            b.decel = false;
        }
    }

    /// Where the system's axes stand now (the command positions).
    fn axis_positions(&self, cs: CoordHandle) -> Vec<f64> {
        self.coord.systems[cs.0 as usize]
            .axes
            .iter()
            .map(|a| self.axes[a.0 as usize].command.position)
            .collect()
    }

    /// The primary-axis vector speed of the system now: the vector sum of
    /// all motion on its primary axes (coordinated, jogs, moves, cams), from
    /// the axes' command velocities.
    fn vector_speed(&self, cs: CoordHandle) -> f64 {
        let sys = &self.coord.systems[cs.0 as usize];
        let v: Vec<f64> = sys
            .axes
            .iter()
            .map(|a| self.axes[a.0 as usize].command.velocity)
            .collect();
        norm(primary_of(&v, sys.system.config().primary_axes))
    }

    /// Where the running motion comes to rest if every component brakes now
    /// with its own deceleration.
    fn rest_point(&self, cs: CoordHandle) -> Vec<f64> {
        let sys = &self.coord.systems[cs.0 as usize];
        let mut at = sys.base.clone();
        for c in &sys.components {
            let s_rest = rest_length(c, None);
            add_displacement(&mut at, c, s_rest);
        }
        at
    }

    /// Replaces every component's profile by one that brings it to rest
    /// along its path (with `limits`, or the move's own), cancels the pending
    /// move, and clears the instructions' `.IP`/`.AC`.
    fn bring_to_rest(&mut self, cs: CoordHandle, limits: Option<Limits>) {
        let sys = &mut self.coord.systems[cs.0 as usize];
        let mut cleared = Vec::new();
        for c in &mut sys.components {
            let now = c.s();
            let length = c.mv.path().length();
            let own = c.mv.limits().copied();
            let lim = match (limits, own) {
                (Some(l), Some(o)) => with_velocity(&l, o.velocity().max(now.velocity.abs())),
                (None, Some(o)) => Some(o),
                (_, None) => None,
            };
            if let Some(lim) = lim {
                let state = now.state();
                if state.position + stopping_distance(state, &lim) < length {
                    c.profile = Profile::to_velocity(state, 0.0, &lim);
                    c.progress = 0.0;
                }
            } else {
                c.profile = Profile::hold(State::at_rest(now.position));
                c.progress = 0.0;
            }
            c.stopping = true;
            c.blend_at = None;
            cleared.extend(c.instr.take());
        }
        if let Some((h, _)) = sys.pending.take() {
            cleared.push(h);
        }
        for h in cleared {
            let b = self.cbits(h);
            b.ip = false;
            b.ac = false;
            b.accel = false;
            b.decel = false;
        }
        let sys = &mut self.coord.systems[cs.0 as usize];
        sys.queue_end = {
            let mut at = sys.base.clone();
            for c in &sys.components {
                add_displacement(&mut at, c, rest_length(c, None));
            }
            at
        };
    }

    /// Whether master-driven `mv` would take over from time-driven (or
    /// single-axis) motion while the master stands still and the system's
    /// primary axes move: the spec's run-time error.
    fn idle_master_with_moving_slave(&self, cs: CoordHandle, mv: &CoordMove) -> bool {
        let sys = &self.coord.systems[cs.0 as usize];
        if mv.driver() != Driver::Master {
            return false;
        }
        let from_time_driven =
            sys.components.is_empty() || sys.components.iter().any(|c| c.mv.driver() == Driver::Time);
        let master_idle = sys
            .master
            .is_none_or(|m| self.axes[m.0 as usize].command.velocity == 0.0);
        from_time_driven && master_idle && self.vector_speed(cs) > 0.0
    }

    /// Fails a move that comes out of the queue with
    /// [`ERR_IDLE_MASTER_SLAVE_MOVING`] when it would start now (it keeps
    /// `.DN`, loses `.IP`); the queue then ends where the running move ends.
    fn fail_idle_master_switch(&mut self, cs: CoordHandle, h: CoordInstructionHandle, mv: &CoordMove) -> bool {
        if !self.idle_master_with_moving_slave(cs, mv) {
            return false;
        }
        let b = self.cbits(h);
        b.set_error(ERR_IDLE_MASTER_SLAVE_MOVING, 0, 0);
        b.ip = false;
        let sys = &mut self.coord.systems[cs.0 as usize];
        if let Some(c) = sys.components.last() {
            sys.queue_end = c.mv.path().end().to_vec();
        }
        true
    }

    fn start_component(&mut self, cs: CoordHandle, h: CoordInstructionHandle, mv: CoordMove, leftover: f64) {
        self.start_component_from(cs, h, mv, leftover, State::at_rest(0.0));
    }

    /// Starts a component whose path profile begins in `initial` (at rest,
    /// or at the junction speed of a follow-contour predecessor).
    fn start_component_from(
        &mut self,
        cs: CoordHandle,
        h: CoordInstructionHandle,
        mv: CoordMove,
        leftover: f64,
        initial: State,
    ) {
        let start = self.record_start(cs);
        self.abort_single_axis_motion(cs);
        let master_now = {
            let sys = &self.coord.systems[cs.0 as usize];
            sys.master
                .map(|m| self.axes[m.0 as usize].command.position)
                .unwrap_or(0.0)
        };
        let sys = &mut self.coord.systems[cs.0 as usize];
        if sys.components.is_empty() {
            sys.base = mv.path().start().to_vec();
        }
        let profile = match mv.limits() {
            Some(l) if initial.velocity > 0.0 => Profile::to_position(initial, mv.path().length(), 0.0, l),
            _ => mv.rest_profile(),
        };
        let blend_at = if mv.termination().blends() && mv.limits().is_some() {
            let decel_point = profile.deceleration_start_s();
            Some(match mv.termination() {
                TerminationType::NoDecel => decel_point,
                _ => progress_at_length(&profile, mv.path().length() - mv.command_tolerance()).max(decel_point),
            })
        } else {
            None
        };
        let (direction, position) = mv.lock();
        let lock = Lock::new(direction, position, master_now);
        sys.queue_end = mv.path().end().to_vec();
        sys.status.motion = true;
        sys.status.move_ = true;
        sys.status.stopping = false;
        sys.status.actual_pos_tolerance = false;
        sys.status.command_pos_tolerance = false;
        sys.status.coord_motion_lock = mv.driver() == Driver::Master && lock.locked;
        let progress = if mv.driver() == Driver::Time { leftover } else { 0.0 };
        sys.components.push(Component {
            instr: Some(h),
            mv,
            profile,
            progress,
            last_delta: progress,
            blend_at,
            successor_started: false,
            contour: false,
            stopping: false,
            lock,
            start,
        });
        let b = self.cbits(h);
        b.ip = true;
        b.ac = true;
    }

    /// Aborts the MC_MoveModulo commands (running and buffered), cams, jogs
    /// and stop ramps on the system's axes: a coordinated move takes them.
    fn abort_single_axis_motion(&mut self, cs: CoordHandle) {
        let axes = self.coord.systems[cs.0 as usize].axes.clone();
        self.coord.systems[cs.0 as usize].taken.clear();
        for axis in axes {
            self.release_cam_and_jog(axis);
            let a = &mut self.axes[axis.0 as usize];
            let job = a.job.take().and_then(|j| j.fb);
            let buffered = a.buffered.take().map(|(fb, _)| fb);
            for fb in job.into_iter().chain(buffered) {
                self.finish(fb, Finish::Aborted);
            }
        }
    }

    /// MCS stop type all: single-axis commands on the system's axes brake to
    /// rest with their own deceleration and report `CommandAborted`.
    fn stop_single_axis_motion(&mut self, cs: CoordHandle) {
        let axes = self.coord.systems[cs.0 as usize].axes.clone();
        for axis in axes {
            let a = &mut self.axes[axis.0 as usize];
            let buffered = a.buffered.take().map(|(fb, _)| fb);
            let mut aborted: Vec<_> = buffered.into_iter().collect();
            if let Some(job) = a.job.as_mut()
                && !job.generation_done
            {
                let state = job.profile.sample(job.t_s).state();
                job.profile = Profile::to_velocity(state, 0.0, job.command.limits());
                job.t_s = 0.0;
                job.target = job.profile.final_state().position;
                aborted.extend(job.fb.take());
            }
            for fb in aborted {
                self.finish(fb, Finish::Aborted);
            }
        }
    }

    /// Hook for single-axis starts (MC_MoveModulo, MAPC, MAJ, MAS, an axis
    /// reset): the coordinated motion of the axis' systems comes to rest
    /// along its path, and the system no longer writes `axis`.
    pub(super) fn release_axis_from_coordinated_motion(&mut self, axis: AxisHandle) {
        for i in 0..self.coord.systems.len() {
            let sys = &self.coord.systems[i];
            if sys.axes.contains(&axis) && (!sys.components.is_empty() || sys.pending.is_some()) {
                self.coord.systems[i].taken.push(axis);
                self.bring_to_rest(CoordHandle(i as u32), None);
                let st = &mut self.coord.systems[i].status;
                st.move_ = false;
                st.move_transition = false;
                self.refresh_queue_status(CoordHandle(i as u32));
            }
        }
    }

    /// Hook for an MCT fault: `cs`'s coordinated motion comes to rest along
    /// its path with its moves' own deceleration, every axis kept on the
    /// path (nothing is taken from the system).
    pub(super) fn bring_system_to_rest(&mut self, cs: CoordHandle) {
        let sys = &self.coord.systems[cs.0 as usize];
        if sys.components.is_empty() && sys.pending.is_none() {
            return;
        }
        self.bring_to_rest(cs, None);
        let st = &mut self.coord.systems[cs.0 as usize].status;
        st.move_ = false;
        st.move_transition = false;
        self.refresh_queue_status(cs);
    }

    /// Hook for [`MotionTask::stop_all_axes`]: every moving system comes to
    /// rest along its path with the system's maximum deceleration (its
    /// moves' own where that is 0); its MCS, if one is stopping it, no longer
    /// completes. Returns the axes of the systems that were moving.
    pub(super) fn stop_coordinated_motion(&mut self) -> Vec<AxisHandle> {
        let mut stopped = Vec::new();
        for i in 0..self.coord.systems.len() {
            let sys = &mut self.coord.systems[i];
            if sys.components.is_empty() && sys.pending.is_none() {
                continue;
            }
            sys.stop = None;
            let decel = sys.system.config().max_decel;
            let limits = Limits::trapezoidal(f64::MAX / 4.0, decel, decel).ok();
            stopped.extend(sys.axes.iter().copied());
            let cs = CoordHandle(i as u32);
            self.bring_to_rest(cs, limits);
            let st = &mut self.coord.systems[i].status;
            st.move_ = false;
            st.move_transition = false;
            self.refresh_queue_status(cs);
        }
        stopped
    }

    fn refresh_queue_status(&mut self, cs: CoordHandle) {
        let sys = &mut self.coord.systems[cs.0 as usize];
        sys.status.move_pending = sys.pending.is_some();
        sys.status.move_pending_queue_full = sys.pending.is_some();
    }

    /// Step 2b of an update: advances every coordinate system by one coarse
    /// update and writes its axes' command positions.
    pub(super) fn advance_coordinate_systems(&mut self) {
        for i in 0..self.coord.systems.len() {
            self.advance_system(CoordHandle(i as u32));
        }
    }

    fn advance_system(&mut self, cs: CoordHandle) {
        let dt = self.dt_s;
        let master_now = {
            let sys = &self.coord.systems[cs.0 as usize];
            sys.master.map(|m| self.axes[m.0 as usize].command.position)
        };
        let sys = &mut self.coord.systems[cs.0 as usize];
        let master_prev = sys.master_prev.or(master_now).unwrap_or(0.0);
        sys.master_prev = master_now;
        for c in &mut sys.components {
            let delta = match c.mv.driver() {
                Driver::Time => dt,
                Driver::Master => c.lock.advance(master_prev, master_now.unwrap_or(master_prev)),
            };
            let before = c.progress;
            c.progress = (c.progress + delta).max(0.0);
            c.last_delta = c.progress - before;
        }
        self.plan_contour_junction(cs);
        // Blends: the newest component hands over at its blend point.
        loop {
            let sys = &mut self.coord.systems[cs.0 as usize];
            let Some(lead) = sys.components.last_mut() else { break };
            let Some(at) = lead.blend_at else { break };
            if lead.successor_started || lead.progress < at {
                break;
            }
            let Some((_, pending)) = &sys.pending else { break };
            // Time matching: the pending move's acceleration ends no sooner
            // than the lead's motion, so the two never add up to more than
            // the faster programmed speed.
            let at = if pending.driver() == lead.mv.driver() {
                at.max(lead.profile.duration_s() - acceleration_time(pending))
            } else {
                at
            };
            if lead.progress < at {
                break;
            }
            let leftover = (lead.progress - at).min(lead.last_delta.max(0.0));
            let (next, mv) = sys.pending.take().expect("checked above");
            if self.fail_idle_master_switch(cs, next, &mv) {
                // The lead runs on to its end point, as if nothing was queued.
                self.refresh_queue_status(cs);
                break;
            }
            let sys = &mut self.coord.systems[cs.0 as usize];
            let lead = sys.components.last_mut().expect("checked above");
            lead.successor_started = true;
            let finished = lead.instr;
            let initial = if lead.contour {
                let end = lead.profile.final_state();
                State {
                    position: 0.0,
                    velocity: end.velocity,
                    acceleration: end.acceleration,
                }
            } else {
                State::at_rest(0.0)
            };
            sys.status.command_pos_tolerance = false;
            if let Some(h) = finished {
                let b = self.cbits(h);
                b.pc = true;
                b.ac = false;
                b.accel = false;
                b.decel = false;
            }
            self.start_component_from(cs, next, mv, leftover, initial);
            self.refresh_queue_status(cs);
        }
        self.write_axes(cs);
        self.complete_components(cs);
    }

    /// Follow contour (termination types 4 and 5): while a move of either
    /// type leads and a move of the same driver is pending, its remaining
    /// profile is replanned from its current state to reach its end point
    /// at the junction speed, the lower of the two programmed speeds,
    /// limited to what the pending move can still stop from within its own
    /// length; the pending move then starts at that speed when the lead
    /// reaches its end point. Without a pending move (or when it leaves the
    /// queue again) the lead ends at rest.
    fn plan_contour_junction(&mut self, cs: CoordHandle) {
        let sys = &mut self.coord.systems[cs.0 as usize];
        let pending = sys.pending.as_ref().map(|(_, mv)| mv);
        let Some(lead) = sys.components.last_mut() else { return };
        let contour_type = matches!(
            lead.mv.termination(),
            TerminationType::FollowContourConstrained | TerminationType::FollowContourUnconstrained
        );
        if !contour_type || lead.successor_started || lead.stopping || lead.progress >= lead.profile.duration_s() {
            return;
        }
        let Some(limits) = lead.mv.limits().copied() else {
            return;
        };
        let next = pending.filter(|mv| mv.driver() == lead.mv.driver() && mv.limits().is_some());
        let junction = match next {
            Some(mv) if !lead.contour => {
                let next_limits = *mv.limits().expect("filtered");
                let mut v = limits.velocity().min(next_limits.velocity());
                let fits = |v: f64| {
                    stopping_distance(
                        State {
                            position: 0.0,
                            velocity: v,
                            acceleration: 0.0,
                        },
                        &next_limits,
                    ) <= mv.path().length()
                };
                if !fits(v) {
                    let (mut lo, mut hi) = (0.0, v);
                    for _ in 0..60 {
                        let mid = 0.5 * (lo + hi);
                        if fits(mid) { lo = mid } else { hi = mid }
                    }
                    v = lo;
                }
                v
            }
            None if lead.contour => 0.0,
            _ => return,
        };
        let now = lead.profile.sample(lead.progress);
        let from = State {
            position: now.position,
            velocity: now.velocity,
            acceleration: now.acceleration,
        };
        lead.profile = Profile::to_position(from, lead.mv.path().length(), junction, &limits);
        lead.progress = 0.0;
        lead.contour = junction > 0.0;
        lead.blend_at = lead.contour.then(|| lead.profile.duration_s());
    }

    fn write_axes(&mut self, cs: CoordHandle) {
        let dt = self.dt_s;
        let sys = &mut self.coord.systems[cs.0 as usize];
        if sys.components.is_empty() {
            sys.velocity.iter_mut().for_each(|v| *v = 0.0);
            sys.acceleration.iter_mut().for_each(|v| *v = 0.0);
            return;
        }
        let n = sys.axes.len();
        let mut position = sys.base.clone();
        let mut velocity = vec![0.0; n];
        let (mut p, mut d) = (vec![0.0; n], vec![0.0; n]);
        for c in &sys.components {
            let s = c.s();
            let speed = match c.mv.driver() {
                Driver::Time => s.velocity,
                Driver::Master => s.velocity * c.last_delta / dt,
            };
            c.mv.path().point(s.position, &mut p, &mut d);
            let start = c.mv.path().start();
            for i in 0..n {
                // (position − start) + p: exactly p at the end of a lone move.
                position[i] = (position[i] - start[i]) + p[i];
                velocity[i] += d[i] * speed;
            }
        }
        let mut acceleration = vec![0.0; n];
        let mut jerk = vec![0.0; n];
        for i in 0..n {
            acceleration[i] = (velocity[i] - sys.velocity[i]) / dt;
            jerk[i] = (acceleration[i] - sys.acceleration[i]) / dt;
        }
        sys.velocity = velocity.clone();
        sys.acceleration = acceleration.clone();
        let axes = sys.axes.clone();
        let taken = sys.taken.clone();
        for (i, axis) in axes.into_iter().enumerate() {
            let a = &mut self.axes[axis.0 as usize];
            if a.job.is_some() || taken.contains(&axis) {
                continue;
            }
            a.command = Sample {
                position: position[i],
                velocity: velocity[i],
                acceleration: acceleration[i],
                jerk: jerk[i],
            };
            if !a.fed {
                a.actual = position[i];
            }
            if velocity[i] != 0.0 {
                a.last_direction = velocity[i].signum();
            }
        }
    }

    fn complete_components(&mut self, cs: CoordHandle) {
        let actual = {
            let sys = &self.coord.systems[cs.0 as usize];
            sys.axes
                .iter()
                .map(|a| self.axes[a.0 as usize].actual)
                .collect::<Vec<_>>()
        };
        let sys = &mut self.coord.systems[cs.0 as usize];
        let primary = sys.system.config().primary_axes;
        let actual_tolerance = sys.system.config().actual_tolerance;
        let mut finished_ip = Vec::new();
        let mut finished_pc = Vec::new();
        // Older components end when their own profile ends.
        let mut i = 0;
        while i + 1 < sys.components.len() {
            if sys.components[i].done() {
                let c = sys.components.remove(i);
                absorb(&mut sys.base, &c, i == 0);
                finished_ip.extend(c.instr);
            } else {
                i += 1;
            }
        }
        let mut start_pending = false;
        if let Some(lead) = sys.components.last()
            && lead.done()
        {
            let satisfied = lead.stopping
                || lead.mv.termination() != TerminationType::ActualTolerance
                || norm(crate::coord::sub(
                    primary_of(&actual, primary),
                    primary_of(lead.mv.path().end(), primary),
                )) <= actual_tolerance;
            if satisfied {
                if lead.mv.termination() == TerminationType::ActualTolerance && !lead.stopping {
                    sys.status.actual_pos_tolerance = true;
                }
                let c = sys.components.pop().expect("lead exists");
                let oldest = sys.components.is_empty();
                absorb(&mut sys.base, &c, oldest);
                if let Some(h) = c.instr {
                    finished_pc.push(h);
                }
                start_pending = sys.pending.is_some();
            }
        }
        // Status of what is still running.
        let lead = sys.components.last();
        let blending = sys.components.len() > 1;
        let (accel, decel) = lead.map_or((false, false), |c| c.profile.accel_decel_at(c.progress));
        sys.status.accel = !blending && accel;
        sys.status.decel = !blending && decel;
        if let Some(c) = lead
            && !c.stopping
            && c.mv.path().length() - c.s().position < c.mv.command_tolerance()
        {
            sys.status.command_pos_tolerance = true;
        }
        sys.status.move_transition = blending && !collinear_junction(&sys.components);
        sys.status.coord_motion_lock = lead.is_some_and(|c| c.mv.driver() == Driver::Master && c.lock.locked);
        let component_bits: Vec<(CoordInstructionHandle, bool, bool)> = sys
            .components
            .iter()
            .enumerate()
            .filter_map(|(k, c)| {
                let (a, d) = c.profile.accel_decel_at(c.progress);
                let is_lead = k + 1 == sys.components.len();
                c.instr.map(|h| (h, is_lead && a, is_lead && d))
            })
            .collect();
        let idle = sys.components.is_empty();
        if idle && !start_pending {
            sys.status.motion = false;
            sys.status.move_ = false;
            sys.status.move_transition = false;
            sys.status.coord_motion_lock = false;
        }
        let stop = if idle { sys.stop.take() } else { None };
        if stop.is_some() {
            sys.status.stopping = false;
        }
        for (h, a, d) in component_bits {
            let b = self.cbits(h);
            b.accel = a && b.ac;
            b.decel = d && b.ac;
        }
        for h in finished_ip {
            let b = self.cbits(h);
            b.ip = false;
            b.accel = false;
            b.decel = false;
        }
        for h in finished_pc.into_iter().chain(stop) {
            let b = self.cbits(h);
            b.pc = true;
            b.ip = false;
            b.ac = false;
            b.accel = false;
            b.decel = false;
        }
        if start_pending {
            let sys = &mut self.coord.systems[cs.0 as usize];
            let (h, mv) = sys.pending.take().expect("checked above");
            if !self.fail_idle_master_switch(cs, h, &mv) {
                self.start_component(cs, h, mv, 0.0);
            }
            self.refresh_queue_status(cs);
        }
    }
}

/// Absolute `Position` elements of rotary axes with an unwind `U` (see the
/// module doc): `|p| > U` is ERR 13 with the Position operand's index; else
/// `p ≥ 0` (and −0) turns the axis forward and `p < 0` backward, by less
/// than one unwind, to `|p|` modulo `U`; the element becomes that unwrapped
/// target. Incremental moves, short arrays and non-finite values are left
/// to the operand checks.
fn unwind_rotary_targets(
    unwinds: &[Option<f64>],
    start: &[f64],
    move_type: i64,
    position: &mut [f64],
    position_exerr: i32,
) -> Result<(), CoordMoveError> {
    if move_type != 0 || position.len() < unwinds.len() {
        return Ok(());
    }
    for (i, unwind) in unwinds.iter().enumerate() {
        let (Some(u), p) = (*unwind, position[i]) else { continue };
        if !p.is_finite() {
            continue;
        }
        if p.abs() > u {
            return Err(crate::coord::out_of_range(position_exerr));
        }
        let w = crate::axis::Modulo::new(u).map_or(0.0, |m| m.wrap(start[i]));
        let turn = |d: f64| if d >= u { 0.0 } else { d };
        let delta = if p >= 0.0 {
            turn((p - w).rem_euclid(u))
        } else {
            -turn((w + p).rem_euclid(u))
        };
        position[i] = start[i] + delta;
    }
    Ok(())
}

/// How long `mv` accelerates from rest to its peak path speed (time, or
/// master distance).
fn acceleration_time(mv: &CoordMove) -> f64 {
    let Some(limits) = mv.limits() else { return 0.0 };
    let profile = mv.rest_profile();
    let peak = profile.sample(profile.deceleration_start_s()).velocity;
    Profile::to_velocity(State::at_rest(0.0), peak, limits).duration_s()
}

/// Where component `c` comes to rest along its path when it brakes now.
fn rest_length(c: &Component, limits: Option<Limits>) -> f64 {
    let now = c.s();
    let length = c.mv.path().length();
    if c.stopping {
        return c.profile.final_state().position.clamp(0.0, length);
    }
    match limits.or(c.mv.limits().copied()) {
        Some(l) => (now.position + stopping_distance(now.state(), &l)).clamp(0.0, length),
        None => now.position,
    }
}

/// Adds a finished component's displacement to `base`. The oldest
/// component, ended at its end point, leaves `base` exactly there (where the
/// next component starts), so no rounding accumulates over a sequence.
fn absorb(base: &mut [f64], c: &Component, oldest: bool) {
    let s = c.s().position;
    if oldest && !c.stopping && s >= c.mv.path().length() {
        base.copy_from_slice(c.mv.path().end());
    } else {
        add_displacement(base, c, s);
    }
}

fn add_displacement(at: &mut [f64], c: &Component, s: f64) {
    let n = at.len();
    let (mut p, mut d) = (vec![0.0; n], vec![0.0; n]);
    c.mv.path().point(s, &mut p, &mut d);
    for i in 0..n {
        at[i] = (at[i] - c.mv.path().start()[i]) + p[i];
    }
}

/// Whether the newest two components meet on one straight line (the
/// machine stays on the path; `MoveTransitionStatus` is not set).
fn collinear_junction(components: &[Component]) -> bool {
    let [.., a, b] = components else { return true };
    let ta = a.mv.path().tangent(a.mv.path().length());
    let tb = b.mv.path().tangent(0.0);
    a.mv.path().arc().is_none()
        && b.mv.path().arc().is_none()
        && norm(crate::coord::cross(ta, tb)) < 1e-9
        && crate::coord::dot(ta, tb) > 0.0
}

mod preflight;
pub use preflight::{ERR_PATH_COLLISION, StartedCoordMove};

#[cfg(test)]
mod tests;
