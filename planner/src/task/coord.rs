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
//! * **Single-axis motion**: a coordinated move with Merge Disabled or
//!   Coordinated Motion that starts on an axis a MAJ jogs or a MAM moves
//!   leaves that jog or move running, superimposed on the path (the
//!   spec's Merge section; `task/superimposed.rs`); Merge All Motion ends
//!   it (also when the system was idle). A coordinated move ends the
//!   MC_MoveModulo commands, cams and stop ramps on its axes whatever the
//!   merge (superimposing those is not modelled); the move starts from
//!   rest on its own profile. A single-axis command that takes an axis of
//!   a moving system (MC_MoveModulo, MAPC, MAJ, a MAM with Merge Enabled,
//!   an axis reset) brings that system to rest along its path (its
//!   instructions lose `.IP`/`.AC`, the pending move is cancelled) while
//!   the single-axis command alone writes that axis; a MAM with Merge
//!   Disabled runs superimposed instead.
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
//!   the master axis' command position (or, linked by an MDCC with Master
//!   Reference actual, its actual position) instead of time (see
//!   [`LockDirection`] for when it follows). The master is linked by MDCC
//!   (`task/instructions/mdcc.rs`) or with
//!   [`MotionTask::set_coordinate_system_master`].
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
//! MCCD changes a running move's dynamics (`task/instructions/mccd.rs`).

use super::MotionTask;
use crate::coord::{CoordMove, CoordMoveError, CoordStatus, CoordinateSystem, CoordinateSystemConfig, MoveContext};
use crate::instruction::MotionInstructionBits;
use crate::task::engine::{CoordCall, CoordSetupError, InstrSlot, SystemSlot};
use crate::task::handles::{AxisHandle, InstructionHandle};
use crate::task::handles::{CoordHandle, CoordInstructionHandle};

mod advance;
mod execute;

use advance::{add_displacement, rest_length};

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
            master_actual: false,
            mdcc: None,
            pending_master: None,
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
        slot.master_actual = false;
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

    /// Whether a coordinated stop (MCS, a fault's or a collision's) ramps a
    /// coordinate system that `axis` belongs to.
    pub(super) fn coordinated_stop_with(&self, axis: AxisHandle) -> bool {
        self.coord
            .systems
            .iter()
            .any(|s| s.axes.contains(&axis) && s.components.iter().any(|c| c.stopping))
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
            one_shot_at: None,
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
    /// # Errors
    /// The refusal when the instruction fails in this call (a move queued
    /// behind a full queue is verified when it is taken, later).
    pub(crate) fn execute_coordinated(
        &mut self,
        system: CoordHandle,
        control: InstructionHandle,
        call: CoordCall,
    ) -> Result<(), CoordMoveError> {
        self.coord.refused = None;
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
        // A scanned rung is the routine's to set; a one-shot stays true
        // through the next update and goes false after it.
        let one_shot_at = (!self.is_scanned(control)).then_some(self.updates);
        self.coord.instructions[h.0 as usize].one_shot_at = one_shot_at;
        self.started_before_update(h);
        self.coord.refused.take().map_or(Ok(()), Err)
    }

    /// Runs `verify` with the context of a move from `system` at rest at
    /// its origin (the checks of a call when the program loads).
    pub(crate) fn verify_at_rest<T>(&self, system: CoordHandle, verify: impl FnOnce(&MoveContext<'_>) -> T) -> T {
        let sys = &self.coord.systems[system.0 as usize];
        let decels: Vec<f64> = sys
            .axes
            .iter()
            .map(|a| self.axes[a.0 as usize].config.max_deceleration)
            .collect();
        let start = vec![0.0; sys.axes.len()];
        verify(&MoveContext {
            system: &sys.system,
            axis_max_decel: &decels,
            start: &start,
            has_master: sys.master.is_some(),
        })
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
}

mod preflight;

#[cfg(test)]
mod tests;
