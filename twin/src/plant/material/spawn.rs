//! A source's schedule: when its next part is due, where, with its seeded
//! jitter.

use nalgebra::{Isometry3, Translation3, UnitQuaternion};
use rapier3d_f64::math::Pose;

use crate::plant::convert::pose_to_rapier;
use crate::scene::{Source, SourceTrigger};

/// SplitMix64: a small, seeded, portable generator (the same parts on
/// every machine and build).
#[derive(Debug, Clone)]
struct SplitMix(u64);

impl SplitMix {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [−1, 1).
    fn symmetric(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }
}

/// A source's progress.
#[derive(Debug, Clone)]
pub(super) struct SourceState {
    rng: SplitMix,
    /// Spawns done (skipped ones included).
    done: u32,
    /// The next spawn's time, s (`None`: none is scheduled).
    next_s: Option<f64>,
    /// Rises of the `on` output not yet served.
    requested: u32,
    trigger_was: bool,
    stopped: bool,
}

impl SourceState {
    pub(super) fn new(s: &Source, index: usize) -> SourceState {
        let seed = s.jitter.seed ^ (index as u64).wrapping_mul(0xA076_1D64_78BD_642F);
        let mut state = SourceState {
            rng: SplitMix(seed),
            done: 0,
            next_s: None,
            requested: 0,
            trigger_was: false,
            stopped: false,
        };
        state.next_s = state.scheduled(s);
        state
    }

    /// The time of spawn number `done + 1` of a timed source, jittered.
    fn scheduled(&mut self, s: &Source) -> Option<f64> {
        if s.count.is_some_and(|n| self.done >= n) {
            return None;
        }
        let nominal = match &s.trigger {
            SourceTrigger::Every { period_s, start_s } => start_s + f64::from(self.done) * period_s,
            SourceTrigger::At(times) => *times.get(self.done as usize)?,
            SourceTrigger::On(_) => return None,
        };
        let jitter = s.jitter.time_s * self.rng.symmetric();
        Some((nominal + jitter).max(0.0))
    }

    pub(super) fn set_trigger(&mut self, on: bool) {
        if on && !self.trigger_was {
            self.requested += 1;
        }
        self.trigger_was = on;
    }

    pub(super) fn stop(&mut self) {
        self.stopped = true;
    }

    /// The pose and number (1-based) of a spawn due at `t`, if any; it
    /// stays due until [`SourceState::spawned`].
    pub(super) fn due(&mut self, s: &Source, t: f64) -> Option<(Pose, u32)> {
        if self.stopped || s.count.is_some_and(|n| self.done >= n) {
            return None;
        }
        let due = match s.trigger {
            SourceTrigger::On(_) => self.requested > 0,
            _ => self.next_s.is_some_and(|at| at <= t + 1e-12),
        };
        if !due {
            return None;
        }
        // The jitter of this spawn's place, drawn for every try alike:
        // a spawn that waits keeps its draw (the generator is advanced
        // once it happens).
        let mut rng = self.rng.clone();
        let j = &s.jitter;
        let dx = [0, 1, 2].map(|k| j.position_m[k] * rng.symmetric());
        let yaw = j.yaw_deg.to_radians() * rng.symmetric();
        let [r, p, y] = s.rpy_deg.map(f64::to_radians);
        let pose = Isometry3::from_parts(
            Translation3::new(
                s.position_m[0] + dx[0],
                s.position_m[1] + dx[1],
                s.position_m[2] + dx[2],
            ),
            UnitQuaternion::from_euler_angles(0.0, 0.0, yaw) * UnitQuaternion::from_euler_angles(r, p, y),
        );
        Some((pose_to_rapier(&pose), self.done + 1))
    }

    /// The spawn [`SourceState::due`] gave happened (or was skipped).
    pub(super) fn spawned(&mut self, s: &Source) {
        // Advance the generator past this spawn's place draws.
        for _ in 0..4 {
            self.rng.next_u64();
        }
        self.done += 1;
        self.requested = self.requested.saturating_sub(1);
        self.next_s = self.scheduled(s);
    }
}
