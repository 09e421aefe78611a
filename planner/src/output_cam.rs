//! Output cams (MAOC): the `OUTPUT_CAM` and `OUTPUT_COMPENSATION`
//! elements, their checks (ERR 36, ERR 37 with the element in `SEGMENT`)
//! and the evaluation of the outputs at a cam position. A leaf: the
//! instruction (`task/instructions/maoc.rs`) arms a cam on an axis and the
//! task (`task/output_cam.rs`) evaluates it each coarse update.
//!
//! # An element
//! `OutputBit` (0–31) is the bit of the Output word it drives. It latches
//! (turns the bit on) on the rising edge of its latch condition and
//! unlatches when its unlatch condition holds; a bit is on while any of
//! its elements is latched.
//! * `LatchType`: 0 Inactive (never latches), 1 Position (the cam position
//!   inside the compensated Left…Right), 2 Enable (the enable bit active),
//!   3 Position and Enable. A code outside 0–3 is Inactive (the manual's
//!   rule).
//! * `UnlatchType`: 0 Inactive (stays latched while the cam runs), 1
//!   Position (the cam position outside Left…Right), 2 Duration (`Duration`
//!   seconds after it latched), 3 Enable (the enable bit inactive), 4
//!   Position and Enable (either), 5 Duration and Enable (either). A code
//!   outside 0–5 is Inactive.
//! * `EnableType`: 0 Input (a bit of the Input word), 1 Inverted Input, 2
//!   Output (a bit of the Output word), 3 Inverted Output; `EnableBit`
//!   0–31.
//! * Left and Right are clamped to the cam's start and end.
//!
//! ERR 36 (Illegal Output Cam), `SEGMENT` = the element: an `OutputBit`
//! outside 0–31; Left not below Right on an element with a position latch
//! or unlatch; a Duration not above 0 with a duration unlatch; an
//! `EnableType` outside 0–3 or an `EnableBit` outside 0–31 on an element
//! with an enable latch or unlatch. The manual leaves such elements out
//! and flags the error; the twin refuses the MAOC (it arms nothing), so a
//! program never runs a cam with elements silently missing.
//!
//! # Compensation
//! `OUTPUT_COMPENSATION[b]` compensates output bit `b` (an array shorter
//! than 32 leaves the bits past its end uncompensated): the latch edge
//! moves by `Offset` plus the cam speed × `LatchDelay` and the unlatch edge
//! by `Offset` plus speed × `UnlatchDelay`, towards where the cam comes
//! from, so a device that responds `LatchDelay` late switches at Left.
//! `Mode`: 0 Normal, 1 Inverted (the bit is on while no element is
//! latched), 2 Pulsed (while latched the bit is on for `DutyCycle` % of
//! each `CycleTime`, from the latch), 3 Inverted and Pulsed. ERR 37
//! (Illegal Output Compensation), `SEGMENT` = the bit: a delay or offset
//! that is not a finite number, a negative delay, a Mode outside 0–3, or a
//! pulsed mode with `CycleTime` not above 0 or `DutyCycle` outside 0–100.

use thiserror::Error;

/// One `OUTPUT_CAM` element.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct OutputCamElement {
    /// `OutputBit`.
    pub output_bit: i64,
    /// `LatchType`.
    pub latch_type: i64,
    /// `UnlatchType`.
    pub unlatch_type: i64,
    /// `Left`, cam units.
    pub left: f64,
    /// `Right`, cam units.
    pub right: f64,
    /// `Duration`, s.
    pub duration: f64,
    /// `EnableType`.
    pub enable_type: i64,
    /// `EnableBit`.
    pub enable_bit: i64,
}

/// One `OUTPUT_COMPENSATION` element.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct OutputCompensation {
    /// `Offset`, cam units.
    pub offset: f64,
    /// `LatchDelay`, s.
    pub latch_delay: f64,
    /// `UnlatchDelay`, s.
    pub unlatch_delay: f64,
    /// `Mode`.
    pub mode: i64,
    /// `CycleTime`, s.
    pub cycle_time: f64,
    /// `DutyCycle`, %.
    pub duty_cycle: f64,
}

/// Why an output cam is refused.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Error)]
pub enum OutputCamFault {
    /// ERR 36.
    #[error("illegal output cam element {element} (ERR 36): {why}")]
    IllegalOutputCam {
        /// The element (`SEGMENT`).
        element: usize,
        /// What is wrong.
        why: &'static str,
    },
    /// ERR 37.
    #[error("illegal output compensation of output bit {bit} (ERR 37): {why}")]
    IllegalCompensation {
        /// The output bit, the compensation array's element (`SEGMENT`).
        bit: usize,
        /// What is wrong.
        why: &'static str,
    },
}

impl crate::instruction::LogixFault for OutputCamFault {
    fn err(&self) -> i32 {
        match self {
            Self::IllegalOutputCam { .. } => 36,
            Self::IllegalCompensation { .. } => 37,
        }
    }
    fn segment(&self) -> i32 {
        match self {
            Self::IllegalOutputCam { element, .. } => *element as i32,
            Self::IllegalCompensation { bit, .. } => *bit as i32,
        }
    }
}

/// A latch or unlatch condition.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Condition {
    Inactive,
    Position,
    Duration,
    Enable,
    PositionAndEnable,
    DurationAndEnable,
}

/// A checked element.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Element {
    bit: u32,
    latch: Condition,
    unlatch: Condition,
    left: f64,
    right: f64,
    duration_s: f64,
    /// (the Output word, inverted, bit)
    enable: (bool, bool, u32),
}

/// A checked compensation.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Compensation {
    offset: f64,
    latch_delay_s: f64,
    unlatch_delay_s: f64,
    inverted: bool,
    /// (cycle time, on time) for a pulsed output.
    pulsed: Option<(f64, f64)>,
}

/// A cam's checked elements and compensations.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct OutputCam {
    elements: Vec<Element>,
    compensation: [Compensation; 32],
}

impl OutputCam {
    /// Checks `elements` and `compensation` for a cam from `start` to
    /// `end` (Left and Right are clamped to it).
    ///
    /// # Errors
    /// ERR 36 or ERR 37 with the element (module doc).
    pub fn new(
        elements: &[OutputCamElement],
        compensation: &[OutputCompensation],
        (start, end): (f64, f64),
    ) -> Result<Self, OutputCamFault> {
        let bad = |element: usize, why| OutputCamFault::IllegalOutputCam { element, why };
        let mut out = Vec::with_capacity(elements.len());
        for (i, e) in elements.iter().enumerate() {
            let bit = u32::try_from(e.output_bit)
                .ok()
                .filter(|b| *b < 32)
                .ok_or(bad(i, "OutputBit is not 0–31"))?;
            let latch = match e.latch_type {
                1 => Condition::Position,
                2 => Condition::Enable,
                3 => Condition::PositionAndEnable,
                _ => Condition::Inactive,
            };
            let unlatch = match e.unlatch_type {
                1 => Condition::Position,
                2 => Condition::Duration,
                3 => Condition::Enable,
                4 => Condition::PositionAndEnable,
                5 => Condition::DurationAndEnable,
                _ => Condition::Inactive,
            };
            let uses = |c: &[Condition]| c.contains(&latch) || c.contains(&unlatch);
            let positional = uses(&[Condition::Position, Condition::PositionAndEnable]);
            if positional && !(e.left.is_finite() && e.right.is_finite() && e.left < e.right) {
                return Err(bad(i, "Left is not below Right"));
            }
            let timed = matches!(unlatch, Condition::Duration | Condition::DurationAndEnable);
            if timed && !(e.duration.is_finite() && e.duration > 0.0) {
                return Err(bad(i, "Duration is not above 0"));
            }
            let enabled = uses(&[
                Condition::Enable,
                Condition::PositionAndEnable,
                Condition::DurationAndEnable,
            ]);
            let enable_bit = u32::try_from(e.enable_bit).ok().filter(|b| *b < 32);
            let enable = match (e.enable_type, enable_bit) {
                (0..=3, Some(b)) => (e.enable_type >= 2, e.enable_type % 2 == 1, b),
                _ if enabled => return Err(bad(i, "EnableType is not 0–3 or EnableBit not 0–31")),
                _ => (false, false, 0),
            };
            out.push(Element {
                bit,
                latch,
                unlatch,
                left: e.left.max(start),
                right: e.right.min(end),
                duration_s: e.duration,
                enable,
            });
        }
        let mut comp = [Compensation::default(); 32];
        for (bit, c) in compensation.iter().enumerate().take(32) {
            let bad = |why| OutputCamFault::IllegalCompensation { bit, why };
            let delays = [c.latch_delay, c.unlatch_delay];
            if !c.offset.is_finite() || delays.iter().any(|d| !(d.is_finite() && *d >= 0.0)) {
                return Err(bad(
                    "Offset, LatchDelay or UnlatchDelay is not a finite number (delays ≥ 0)",
                ));
            }
            let pulsed = match c.mode {
                0 | 1 => None,
                2 | 3 => {
                    if !(c.cycle_time.is_finite() && c.cycle_time > 0.0) {
                        return Err(bad("CycleTime is not above 0"));
                    }
                    if !(0.0..=100.0).contains(&c.duty_cycle) {
                        return Err(bad("DutyCycle is not 0–100"));
                    }
                    Some((c.cycle_time, c.cycle_time * c.duty_cycle / 100.0))
                }
                _ => return Err(bad("Mode is not 0–3")),
            };
            comp[bit] = Compensation {
                offset: c.offset,
                latch_delay_s: c.latch_delay,
                unlatch_delay_s: c.unlatch_delay,
                inverted: c.mode == 1 || c.mode == 3,
                pulsed,
            };
        }
        Ok(Self {
            elements: out,
            compensation: comp,
        })
    }

    /// The bits the cam drives.
    #[must_use]
    pub fn mask(&self) -> u32 {
        self.elements.iter().fold(0, |m, e| m | 1 << e.bit)
    }

    /// The compensated latch and unlatch edges of `element` for a cam
    /// moving at `speed` (cam units/s): (latch at Left, unlatch at Right),
    /// each moved towards where the cam comes from.
    fn edges(&self, e: &Element, speed: f64) -> (f64, f64) {
        let c = &self.compensation[e.bit as usize];
        if speed >= 0.0 {
            (
                e.left - c.offset - speed * c.latch_delay_s,
                e.right - c.offset - speed * c.unlatch_delay_s,
            )
        } else {
            // Moving back, the cam enters at Right and leaves at Left.
            (
                e.left - c.offset - speed * c.unlatch_delay_s,
                e.right - c.offset - speed * c.latch_delay_s,
            )
        }
    }

    /// The number of elements.
    #[must_use]
    pub fn len(&self) -> usize {
        self.elements.len()
    }

    /// Whether the cam has no elements.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.elements.is_empty()
    }
}

/// An element's latch state.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Latch {
    on: bool,
    since_s: f64,
    latch_before: bool,
}

/// A switch of an output bit inside a coarse update (a scheduled output
/// switches there).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Switch {
    /// When, s.
    pub time_s: f64,
    /// The output bit.
    pub bit: u32,
    /// On or off.
    pub on: bool,
}

/// One evaluation of a cam: the cam position and speed, the Input and
/// Output words, the time, and where the last evaluation left the cam.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Step {
    /// Cam position at the last evaluation and now.
    pub from: f64,
    /// Cam position now.
    pub to: f64,
    /// Cam speed, cam units/s.
    pub speed: f64,
    /// Time of the last evaluation and now, s.
    pub t0_s: f64,
    /// Time now, s.
    pub t1_s: f64,
    /// The Input word.
    pub input: u32,
    /// The Output word as it stands.
    pub output: u32,
}

impl OutputCam {
    /// Evaluates the cam at `step.to`: updates the latches, returns the
    /// driven bits' values (within [`OutputCam::mask`]) and pushes each
    /// bit's switches: at the interpolated times of its position and
    /// duration edges (enable edges at `t1_s`), inverted for an inverted
    /// bit; a pulsed bit switches at update boundaries, when its value
    /// changes from `step.output`'s.
    pub fn evaluate(&self, latches: &mut Vec<Latch>, step: &Step, switches: &mut Vec<Switch>) -> u32 {
        latches.resize(self.elements.len(), Latch::default());
        // How many elements hold each bit latched, before this update.
        let mut held = [0u32; 32];
        for (e, l) in self.elements.iter().zip(latches.iter()) {
            held[e.bit as usize] += u32::from(l.on);
        }
        // The elements' latch (true) and unlatch edges, by time.
        let mut edges: Vec<Switch> = Vec::new();
        for (e, l) in self.elements.iter().zip(latches.iter_mut()) {
            let (lo, hi) = self.edges(e, step.speed);
            let inside = lo <= step.to && step.to <= hi;
            let (output, inverted, bit) = e.enable;
            let word = if output { step.output } else { step.input };
            let enable = (word >> bit & 1 == 1) != inverted;
            let latch_now = match e.latch {
                Condition::Position => inside,
                Condition::Enable => enable,
                Condition::PositionAndEnable => inside && enable,
                _ => false,
            };
            if !l.on && latch_now && !l.latch_before {
                l.on = true;
                // A position latch at the crossing of its edge inside the
                // update; an enable latch now.
                let edge = if step.to >= step.from { lo } else { hi };
                l.since_s = match e.latch {
                    Condition::Position | Condition::PositionAndEnable => crossing_time(step, edge),
                    _ => step.t1_s,
                };
                edges.push(Switch {
                    time_s: l.since_s,
                    bit: e.bit,
                    on: true,
                });
            }
            l.latch_before = latch_now;
            if l.on {
                let expired = step.t1_s - l.since_s >= e.duration_s;
                let off = match e.unlatch {
                    Condition::Position => !inside,
                    Condition::Duration => expired,
                    Condition::Enable => !enable,
                    Condition::PositionAndEnable => !inside || !enable,
                    Condition::DurationAndEnable => expired || !enable,
                    Condition::Inactive => false,
                };
                if off {
                    l.on = false;
                    let edge = if step.to >= step.from { hi } else { lo };
                    let time_s = match e.unlatch {
                        Condition::Position => crossing_time(step, edge),
                        Condition::PositionAndEnable if !inside => crossing_time(step, edge),
                        Condition::Duration => l.since_s + e.duration_s,
                        Condition::DurationAndEnable if expired => l.since_s + e.duration_s,
                        _ => step.t1_s,
                    };
                    edges.push(Switch {
                        time_s,
                        bit: e.bit,
                        on: false,
                    });
                }
            }
        }
        // A bit switches where the first of its elements latches and the
        // last unlatches.
        edges.sort_by(|a, b| a.time_s.total_cmp(&b.time_s));
        for edge in edges {
            let b = edge.bit as usize;
            let c = &self.compensation[b];
            let was = held[b] > 0;
            held[b] = if edge.on {
                held[b] + 1
            } else {
                held[b].saturating_sub(1)
            };
            if c.pulsed.is_none() && was != (held[b] > 0) {
                switches.push(Switch {
                    on: edge.on != c.inverted,
                    ..edge
                });
            }
        }
        let bits = self.bits_at(latches, step.t1_s);
        for (bit, c) in self.compensation.iter().enumerate() {
            let now = bits >> bit & 1 == 1;
            if c.pulsed.is_some() && self.mask() >> bit & 1 == 1 && now != (step.output >> bit & 1 == 1) {
                switches.push(Switch {
                    time_s: step.t1_s,
                    bit: bit as u32,
                    on: now,
                });
            }
        }
        bits
    }

    /// The driven bits' values with the latches as they are, at `t_s`
    /// (pulsed outputs by their cycle, inverted ones inverted).
    fn bits_at(&self, latches: &[Latch], t_s: f64) -> u32 {
        let mut latched = [None::<f64>; 32];
        for (e, l) in self.elements.iter().zip(latches) {
            if l.on {
                let since = latched[e.bit as usize].map_or(l.since_s, |s: f64| s.min(l.since_s));
                latched[e.bit as usize] = Some(since);
            }
        }
        let (mut bits, mask) = (0, self.mask());
        for (bit, (since, c)) in latched.iter().zip(&self.compensation).enumerate() {
            if mask >> bit & 1 == 0 {
                continue;
            }
            let mut on = match (*since, c.pulsed) {
                (Some(since), Some((cycle, on_time))) => (t_s - since).rem_euclid(cycle) < on_time,
                (Some(_), None) => true,
                (None, _) => false,
            };
            if c.inverted {
                on = !on;
            }
            if on {
                bits |= 1 << bit;
            }
        }
        bits
    }
}

/// When the cam position crossed `edge` inside the step (its end when it
/// did not move).
fn crossing_time(step: &Step, edge: f64) -> f64 {
    let moved = step.to - step.from;
    if moved == 0.0 {
        return step.t1_s;
    }
    let f = ((edge - step.from) / moved).clamp(0.0, 1.0);
    step.t0_s + f * (step.t1_s - step.t0_s)
}

#[cfg(test)]
mod tests;
