//! From what a sensor sees to what the program reads: injected faults,
//! `invert`, the on- and off-delays, then the input module.
//!
//! ```text
//! detected ──▶ fault ──▶ invert ──▶ on/off delay ──▶ output ──▶ input module ──▶ tag
//!  (edges inside      stuck_on/off     (dark-operate)   (the sensor's      (every RPI, or at
//!   each parts step)                                     own timers)        once with COS)
//! ```
//!
//! * **Edges** come with their time inside the parts step (the continuous
//!   detection of `super::field`), so a pulse shorter than a step is an
//!   edge pair like any other.
//! * **Delays**: the output turns on `on_delay` after the sensed state
//!   turns on and stays on; it turns off `off_delay` after it turns off and
//!   stays off. A sensed change back before the delay ran out cancels it.
//! * **Input module**: the tag takes the output's value at each input
//!   update, at `n · rpi` s of simulated time (n = 0, 1, …), asynchronous
//!   to the scans; with COS an output edge updates it at once. The program
//!   sees the tag at its next scan (module `run.rs`: the scans of an
//!   update run at its start). So an edge at `t` reaches the tag at the
//!   first input update at or after `t` (at `t` itself with COS), and the
//!   program at the first scan at or after that.
//! * **Missed pulses**: an output pulse (a rise and the fall after it)
//!   with no input update in `[rise, fall)` and no COS never reaches the
//!   tag: it is counted in `missed_pulses`, a design fault no anchor
//!   reports.

use crate::scene::{DeviceFault, FaultKind};

/// A sensor's signal chain and its statistics.
#[derive(Debug, Clone)]
pub struct Signal {
    invert: bool,
    on_delay_s: f64,
    off_delay_s: f64,
    rpi_s: f64,
    cos: bool,
    faults: Vec<DeviceFault>,
    /// What the sensor detects now (before faults and invert).
    detected: bool,
    /// The output now.
    output: bool,
    /// An output change waiting for its delay: (when, to what).
    pending: Option<(f64, bool)>,
    /// Output changes not yet taken by the input module, in time order.
    changes: Vec<(f64, bool)>,
    /// The output's value before `changes`.
    base: bool,
    /// The tag's value (what the input module delivered last).
    tag: bool,
    /// Time up to which the input module has run, s.
    module_s: f64,
    /// The last rise of the output, s.
    rose_s: Option<f64>,
    /// Statistics.
    stats: SignalStats,
    /// Every output change (time, new value), up to [`MAX_LOGGED_EDGES`].
    log: Vec<(f64, bool)>,
    /// Where the last fed step's changes start in `changes`.
    step_from: usize,
}

/// The most output changes a sensor keeps for the recording and tests.
pub const MAX_LOGGED_EDGES: usize = 100_000;

/// What a sensor's output did over the run.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize)]
pub struct SignalStats {
    /// Rising edges of the output.
    pub edges: u64,
    /// Time the output was on, s.
    pub on_s: f64,
    /// Output pulses no input update saw (module doc).
    pub missed_pulses: u64,
}

impl Signal {
    /// A signal at rest: nothing detected at t = 0 (the output is TRUE
    /// from the start for an inverted sensor).
    #[must_use]
    pub fn new(invert: bool, delays_s: (f64, f64), rpi_s: f64, cos: bool, faults: Vec<DeviceFault>) -> Signal {
        let mut s = Signal {
            invert,
            on_delay_s: delays_s.0,
            off_delay_s: delays_s.1,
            rpi_s,
            cos,
            faults,
            detected: false,
            output: false,
            pending: None,
            changes: Vec::new(),
            base: false,
            tag: false,
            module_s: 0.0,
            rose_s: None,
            stats: SignalStats::default(),
            log: Vec::new(),
            step_from: 0,
        };
        let sensed = s.sensed(0.0);
        s.output = sensed;
        s.base = sensed;
        s.tag = sensed;
        if sensed {
            s.rose_s = Some(0.0);
        }
        s
    }

    /// The sensed state at `t`: the detection through the faults active
    /// then, inverted for a dark-operate sensor.
    fn sensed(&self, t: f64) -> bool {
        let level = if DeviceFault::active(&self.faults, FaultKind::StuckOn, t) {
            true
        } else if DeviceFault::active(&self.faults, FaultKind::StuckOff, t) {
            false
        } else {
            self.detected
        };
        level != self.invert
    }

    /// Feeds one parts step `(t0, t1]`: the detection's changes inside it
    /// (time-ordered, each the new detected state), then runs the delays to
    /// `t1`.
    pub fn feed(&mut self, t0: f64, t1: f64, detections: &[(f64, bool)]) {
        self.step_from = self.changes.len();
        // The fault windows' ends are changes of the sensed state too.
        let mut events: Vec<(f64, Option<bool>)> = detections.iter().map(|&(t, d)| (t, Some(d))).collect();
        for f in &self.faults {
            for t in [f.from_s, f.to_s] {
                if t > t0 && t <= t1 {
                    events.push((t, None));
                }
            }
        }
        events.sort_by(|a, b| a.0.total_cmp(&b.0));
        for (t, detected) in events {
            self.run_pending(t);
            if let Some(d) = detected {
                self.detected = d;
            }
            self.sensed_now(t);
        }
        self.run_pending(t1);
    }

    /// The sensed state may have changed at `t`: start or cancel a delay.
    fn sensed_now(&mut self, t: f64) {
        let sensed = self.sensed(t);
        if sensed == self.output {
            self.pending = None;
            return;
        }
        if self.pending.is_some_and(|(_, to)| to == sensed) {
            return;
        }
        let delay = if sensed { self.on_delay_s } else { self.off_delay_s };
        if delay <= 0.0 {
            self.pending = None;
            self.set_output(t, sensed);
        } else {
            self.pending = Some((t + delay, sensed));
        }
    }

    fn run_pending(&mut self, t: f64) {
        if let Some((at, to)) = self.pending
            && at <= t
        {
            self.pending = None;
            self.set_output(at, to);
        }
    }

    fn set_output(&mut self, t: f64, on: bool) {
        if on == self.output {
            return;
        }
        self.output = on;
        self.changes.push((t, on));
        if self.log.len() < MAX_LOGGED_EDGES {
            self.log.push((t, on));
        }
        if on {
            self.stats.edges += 1;
            self.rose_s = Some(t);
        } else if let Some(rose) = self.rose_s.take() {
            self.stats.on_s += t - rose;
            if !self.cos && !self.update_between(rose, t) {
                self.stats.missed_pulses += 1;
            }
        }
    }

    /// Whether an input update falls in `[a, b)`.
    fn update_between(&self, a: f64, b: f64) -> bool {
        let first = (a / self.rpi_s - 1e-9).ceil();
        first * self.rpi_s < b - 1e-12
    }

    /// The tag's value for a scan at `t`: the output at the last input
    /// update at or before `t` (with COS: the output at `t`).
    pub fn tag_at(&mut self, t: f64) -> bool {
        if self.cos {
            self.tag = self.output_at(t);
        } else {
            let last = (t / self.rpi_s + 1e-9).floor() * self.rpi_s;
            if last >= self.module_s - 1e-12 {
                self.tag = self.output_at(last);
            }
        }
        self.module_s = t;
        let keep_from = self.changes.partition_point(|(at, _)| *at <= t);
        if let Some(&(_, v)) = self.changes[..keep_from].last() {
            self.base = v;
        }
        self.changes.drain(..keep_from);
        self.step_from = self.changes.len();
        self.tag
    }

    /// The output at `t` (no later than the last fed step).
    fn output_at(&self, t: f64) -> bool {
        let k = self.changes.partition_point(|(at, _)| *at <= t);
        if k == 0 { self.base } else { self.changes[k - 1].1 }
    }

    /// Whether an input update falls in `(t0, t1]`.
    #[must_use]
    pub fn updated_in(&self, t0: f64, t1: f64) -> bool {
        self.cos || (t1 / self.rpi_s + 1e-9).floor() * self.rpi_s > t0 + 1e-12
    }

    /// The output's changes in the last fed step (time s, new value).
    #[must_use]
    pub fn step_changes(&self) -> &[(f64, bool)] {
        &self.changes[self.step_from.min(self.changes.len())..]
    }

    /// The output's changes so far (time s, new value), the first
    /// [`MAX_LOGGED_EDGES`].
    #[must_use]
    pub fn log(&self) -> &[(f64, bool)] {
        &self.log
    }

    /// The output now (after the last fed step).
    #[must_use]
    pub fn output(&self) -> bool {
        self.output
    }

    /// The statistics so far; `on_s` counts an output still on up to `t`.
    #[must_use]
    pub fn stats(&self, t: f64) -> SignalStats {
        let mut s = self.stats;
        if let Some(rose) = self.rose_s {
            s.on_s += (t - rose).max(0.0);
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn plain(rpi_s: f64, cos: bool) -> Signal {
        Signal::new(false, (0.0, 0.0), rpi_s, cos, Vec::new())
    }

    #[test]
    fn a_pulse_between_two_updates_is_missed_without_cos_and_seen_with_it() {
        // A 2 ms pulse at 13..15 ms under a 10 ms RPI: no update at 10 or
        // 20 ms sees it.
        let mut s = plain(0.010, false);
        s.feed(0.010, 0.020, &[(0.013, true), (0.015, false)]);
        assert!(!s.tag_at(0.020));
        assert_eq!(s.stats(0.020).missed_pulses, 1);
        assert_eq!(s.stats(0.020).edges, 1);
        assert!((s.stats(0.020).on_s - 0.002).abs() < 1e-12);

        let mut c = plain(0.010, true);
        c.feed(0.010, 0.020, &[(0.013, true), (0.015, false)]);
        assert_eq!(c.stats(0.020).missed_pulses, 0);
    }

    #[test]
    fn the_tag_takes_the_output_at_the_last_input_update() {
        // RPI 10 ms, scans every 4 ms: an edge at 11 ms reaches the tag at
        // the 20 ms update, and the scans see it from 20 ms on.
        let mut s = plain(0.010, false);
        s.feed(0.008, 0.012, &[(0.011, true)]);
        assert!(!s.tag_at(0.012));
        s.feed(0.012, 0.016, &[]);
        assert!(!s.tag_at(0.016));
        s.feed(0.016, 0.020, &[]);
        assert!(s.tag_at(0.020));
        // With COS, at once.
        let mut c = plain(0.010, true);
        c.feed(0.008, 0.012, &[(0.011, true)]);
        assert!(c.tag_at(0.012));
    }

    #[test]
    fn delays_filter_short_changes_and_invert_starts_on() {
        let mut s = Signal::new(false, (0.005, 0.003), 0.001, false, Vec::new());
        // On for 4 ms < 5 ms on-delay: the output never turns on.
        s.feed(0.0, 0.010, &[(0.002, true), (0.006, false)]);
        assert!(!s.output());
        // On for good at 20 ms: on at 25 ms; off at 40 ms: off at 43 ms.
        s.feed(0.010, 0.030, &[(0.020, true)]);
        assert!(s.output());
        assert_eq!(s.changes.last(), Some(&(0.025, true)));
        s.feed(0.030, 0.050, &[(0.040, false)]);
        assert!(!s.output());
        assert!((s.changes.last().map(|c| c.0).unwrap_or(0.0) - 0.043).abs() < 1e-12);

        let inverted = Signal::new(true, (0.0, 0.0), 0.01, false, Vec::new());
        assert!(inverted.output(), "dark-operate: TRUE while nothing is seen");
    }

    #[test]
    fn stuck_faults_override_the_detection_for_their_window() {
        let faults = vec![
            DeviceFault {
                kind: FaultKind::StuckOn,
                from_s: 0.1,
                to_s: 0.2,
            },
            DeviceFault {
                kind: FaultKind::StuckOff,
                from_s: 0.3,
                to_s: f64::INFINITY,
            },
        ];
        let mut s = Signal::new(false, (0.0, 0.0), 0.01, false, faults);
        s.feed(0.0, 0.15, &[]);
        assert!(s.output(), "stuck on from 0.1 s");
        s.feed(0.15, 0.25, &[]);
        assert!(!s.output(), "released at 0.2 s");
        s.feed(0.25, 0.28, &[(0.26, true)]);
        assert!(s.output());
        s.feed(0.28, 0.35, &[]);
        assert!(!s.output(), "stuck off from 0.3 s although a part is there");
    }
}
