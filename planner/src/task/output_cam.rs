//! Output cams in the executor: each axis' execution targets, what MAOC
//! arms and MDOC disarms (`task/instructions/maoc.rs`, `mdoc.rs`), their
//! evaluation once a coarse update (the last step of an update), and the
//! Output and Input words the caller keeps in its tags.
//!
//! # The cam position
//! * Execution Schedule *immediate*: armed when MAOC executes; the cam
//!   position is the axis position (Axis Arm and Cam Arm Position are not
//!   used).
//! * *forward only*, *reverse only*, *bi-directional*: armed when the axis
//!   position passes Axis Arm Position in that direction; the cam position
//!   is then Cam Arm Position plus the axis' travel since.
//! * *pending*: waits for the cam running on the target to end (a *once*
//!   cam leaving its range), then is armed at the axis position where it
//!   left its range (interpolated inside the update), its cam position Cam
//!   Arm Position plus the travel since; with no cam running it arms at
//!   once, as *immediate*.
//!
//! # Execution Mode
//! * *once*: when the cam position leaves the range (past Cam End Position
//!   moving forward, before Cam Start Position moving back) the cam ends:
//!   its bits turn off, `.IP` clears, `.PC` sets, a pending cam takes over.
//! * *continuous*: the cam position wraps from the end of the range to its
//!   start (and back): it runs until MDOC or another MAOC.
//! * *persistent*: outside the range the cam's bits are off and its
//!   latches reset; it stays armed and works again when the cam position
//!   comes back.
//!
//! # Words
//! The Output word's bits the cam drives change in the update the cam
//! evaluates them; the caller writes them to the Output tag
//! ([`MotionTask::output_cam_words`]) and gives the Input tag's value
//! ([`MotionTask::set_output_cam_input`]). When a cam ends or is disarmed
//! its bits go off and the caller's tag is released. Each update's
//! switches at their interpolated times ([`MotionTask::output_cam_switches`])
//! are what a scheduled output module would switch at.

use super::MotionTask;
use crate::output_cam::{Step, Switch};
use crate::task::engine::{CamMode, CamSchedule, OutputCamTarget};
use crate::task::handles::AxisHandle;
use crate::watch::crossing;

/// The Output word of an execution target, for its caller.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct OutputCamWord {
    /// The caller's reference to the Output tag.
    pub output: usize,
    /// The caller's reference to the Input tag.
    pub input: usize,
    /// The axis and the execution target.
    pub axis: AxisHandle,
    /// The execution target.
    pub target: u32,
    /// The bits the cam drives.
    pub mask: u32,
    /// Their values.
    pub bits: u32,
}

impl MotionTask {
    /// The execution targets of `axis`, created as MAOC needs them.
    pub(super) fn output_cam_target(&mut self, axis: AxisHandle, target: usize) -> &mut OutputCamTarget {
        let cams = &mut self.axes[axis.0 as usize].output_cams;
        if cams.len() <= target {
            cams.resize_with(target + 1, OutputCamTarget::default);
        }
        &mut cams[target]
    }

    /// The Output words the output cams drive, for the caller to merge
    /// into its Output tags (`(tag & !mask) | bits`). A target whose cam
    /// ended gives its bits off once more, then no longer.
    pub fn output_cam_words(&mut self) -> Vec<OutputCamWord> {
        let mut out = Vec::new();
        for (i, a) in self.axes.iter_mut().enumerate() {
            for (k, t) in a.output_cams.iter_mut().enumerate() {
                if t.mask == 0 {
                    continue;
                }
                out.push(OutputCamWord {
                    output: t.words.0,
                    input: t.words.1,
                    axis: AxisHandle(i as u32),
                    target: k as u32,
                    mask: t.mask,
                    bits: t.bits,
                });
                if t.release {
                    t.mask = 0;
                    t.release = false;
                }
            }
        }
        out
    }

    /// The Input word of an execution target (the caller's Input tag).
    pub fn set_output_cam_input(&mut self, axis: AxisHandle, target: u32, input: u32) {
        if let Some(t) = self.axes[axis.0 as usize].output_cams.get_mut(target as usize) {
            t.input = input;
        }
    }

    /// The switches an execution target's cam made in the last update, at
    /// their interpolated times.
    pub fn output_cam_switches(&self, axis: AxisHandle, target: u32) -> &[Switch] {
        self.axes[axis.0 as usize]
            .output_cams
            .get(target as usize)
            .map_or(&[], |t| &t.switches)
    }

    /// Whether an output cam is armed on an execution target (its
    /// `.IP` MAOC runs), and whether one is pending.
    pub fn output_cam_status(&self, axis: AxisHandle, target: u32) -> (bool, bool) {
        self.axes[axis.0 as usize]
            .output_cams
            .get(target as usize)
            .map_or((false, false), |t| {
                (t.active.as_ref().is_some_and(|r| r.armed), t.pending.is_some())
            })
    }

    /// Ends the cam on a target (MDOC, a newer MAOC): its bits go off,
    /// its MAOC leaves `.IP` without `.PC`; a pending one too when `all`.
    pub(super) fn disarm_output_cam(&mut self, axis: AxisHandle, target: usize, pending_too: bool) {
        let Some(t) = self.axes[axis.0 as usize].output_cams.get_mut(target) else {
            return;
        };
        let mut ended = Vec::new();
        if let Some(run) = t.active.take() {
            ended.push(run.control);
            t.bits = 0;
            t.release = true;
        }
        if pending_too && let Some(run) = t.pending.take() {
            ended.push(run.control);
        }
        for control in ended {
            self.motion_bits_mut(control).ip = false;
        }
    }

    /// Evaluates every armed output cam (the last step of an update).
    pub(super) fn advance_output_cams(&mut self) {
        let (dt_s, now_s) = (self.dt_s, self.time_s());
        let mut completed = Vec::new();
        for i in 0..self.axes.len() {
            let a = &mut self.axes[i];
            let (actual, command) = (a.actual, a.command.position);
            for (k, t) in a.output_cams.iter_mut().enumerate() {
                t.switches.clear();
                let input = t.input;
                let output_bits = t.bits;
                let Some(run) = t.active.as_mut() else { continue };
                let p = if run.actual { actual } else { command };
                if !run.armed {
                    let forward = p >= run.last_axis;
                    let passes = |dir: bool| crossing(run.last_axis, p, run.axis_arm, dir, None).is_some();
                    let arms = match run.schedule {
                        CamSchedule::ForwardOnly => passes(true),
                        CamSchedule::ReverseOnly => passes(false),
                        CamSchedule::BiDirectional => passes(forward),
                        CamSchedule::Immediate | CamSchedule::Pending => true,
                    };
                    if !arms {
                        run.last_axis = p;
                        continue;
                    }
                    run.armed = true;
                    // The cam position where the axis was at the last
                    // evaluation (the arm position lies in between).
                    run.last_cam = run.cam_arm + (run.last_axis - run.axis_arm);
                }
                let (start, end) = run.range;
                let travel = p - run.last_axis;
                let mut to = run.last_cam + travel;
                if run.mode == CamMode::Continuous && end > start {
                    to = start + (to - start).rem_euclid(end - start);
                }
                let from = to - travel;
                let step = Step {
                    from,
                    to,
                    speed: travel / dt_s,
                    t0_s: now_s - dt_s,
                    t1_s: now_s,
                    input,
                    output: output_bits,
                };
                run.last_axis = p;
                run.last_cam = to;
                let inside = start <= to && to <= end;
                // The elements' own edges first (one that ends at the range's
                // end unlatches where the cam crosses it, inside the update).
                t.bits = run.cam.evaluate(&mut run.latches, &step, &mut t.switches);
                if !inside && run.mode != CamMode::Continuous {
                    // Outside the range: what is still on goes off now.
                    for l in &mut run.latches {
                        *l = Default::default();
                    }
                    for bit in 0..32 {
                        if t.bits >> bit & 1 == 1 {
                            t.switches.push(Switch {
                                time_s: now_s,
                                bit,
                                on: false,
                            });
                        }
                    }
                    t.bits = 0;
                    // Before the range (still coming) or past it.
                    let past = (to > end && travel >= 0.0) || (to < start && travel <= 0.0);
                    if run.mode == CamMode::Once && past {
                        // The axis position where the cam left its range.
                        let left_at = if to > end { p - (to - end) } else { p - (to - start) };
                        completed.push((i, k, left_at));
                    }
                }
            }
        }
        for (i, k, position) in completed {
            let t = &mut self.axes[i].output_cams[k];
            let Some(run) = t.active.take() else { continue };
            t.release = true;
            if let Some(mut next) = t.pending.take() {
                next.armed = true;
                next.axis_arm = position;
                next.last_axis = position;
                next.last_cam = next.cam_arm;
                t.mask |= next.mask_hint;
                t.words = next.words;
                t.release = false;
                t.active = Some(next);
            }
            let b = self.motion_bits_mut(run.control);
            b.ip = false;
            b.pc = true;
        }
    }
}
