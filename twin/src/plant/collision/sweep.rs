//! The pre-flight sweep: a planned path checked pose by pose, each step
//! as long as the distances at its start allow, for the first contact
//! (the parent module's doc states the bound).

use serde::Serialize;

use super::CollisionModel;
use crate::plant::urdf::RobotModel;

impl CollisionModel {
    /// Sweeps `path` (see the module docs for the bound): the first sample
    /// where a checked pair touches, if any.
    pub fn sweep(&self, model: &RobotModel, path: &dyn PathSampler, resolution_m: f64) -> SweepReport {
        let pair_rate = self.pair_rates(&path.joint_rate_bounds());
        let max_rate = pair_rate.iter().copied().fold(0.0, f64::max);
        let length = path.length();
        let min_step = if max_rate > 0.0 {
            resolution_m / max_rate
        } else {
            f64::INFINITY
        };
        // Bounded work: at most MAX_SWEEP_SAMPLES poses at the nominal
        // steps; a path that would need more at this resolution is stepped
        // more coarsely.
        let min_step = min_step.max(length / MAX_SWEEP_SAMPLES as f64);
        let tolerance = (SWEEP_TOLERANCE * length).max(f64::MIN_POSITIVE);
        let mut sweep = Sweep {
            world: self,
            model,
            path,
            rates: &pair_rate,
            tolerance,
            samples: 0,
            exact: true,
        };
        let hit = sweep.first_hit(length, min_step);
        let step_bound = if sweep.exact { tolerance } else { min_step };
        let mut report = SweepReport {
            collision: None,
            samples: sweep.samples,
            step_bound: step_bound.min(length.max(0.0)),
            length,
        };
        if let Some(at) = hit {
            let poses = model.world_from_link(&path.joint_positions(at));
            let check = self.check(&poses);
            let deepest = check
                .contacts
                .iter()
                .max_by(|x, y| x.at.depth_m.total_cmp(&y.at.depth_m));
            report.collision = deepest.map(|c| PredictedCollision {
                parameter: at,
                time_s: path.time_s(at),
                a: self.name(c.a).to_string(),
                b: self.name(c.b).to_string(),
                depth_m: c.at.depth_m,
                bound: report.step_bound,
            });
        }
        report
    }

    /// Per body, the bound of its points' speed along the path parameter
    /// relative to what it is checked against, given the joints' rate
    /// bounds: its own for obstacles, the sum of both bodies' for a self
    /// pair.
    fn pair_rates(&self, joint_rates: &[f64]) -> Vec<f64> {
        let lipschitz: Vec<f64> = self
            .reach
            .iter()
            .map(|r| r.iter().zip(joint_rates).map(|(r, q)| r * q.abs()).sum())
            .collect();
        let mut pair_rate = lipschitz.clone();
        for &(a, b) in &self.self_pairs {
            let both = lipschitz[a] + lipschitz[b];
            pair_rate[a] = pair_rate[a].max(both);
            pair_rate[b] = pair_rate[b].max(both);
        }
        pair_rate
    }
}

/// Whether some checked pair touches (a distance at or below zero).
fn touching(d: &[f64]) -> bool {
    d.iter().any(|x| *x <= 0.0)
}

/// One sweep's state: the path, the bodies' rate bounds, the work done.
struct Sweep<'a> {
    world: &'a CollisionModel,
    model: &'a RobotModel,
    path: &'a dyn PathSampler,
    /// Per body, the bound of its points' speed along the parameter.
    rates: &'a [f64],
    /// Intervals shorter than this are not split further (parameter units).
    tolerance: f64,
    samples: usize,
    /// Every interval was settled to the tolerance (not cut short by the
    /// sample budget).
    exact: bool,
}

impl Sweep<'_> {
    /// Steps along the path from its start, each step as long as the
    /// distances allow (at least `min_step`), and returns the first
    /// parameter where a pair touches, if any.
    fn first_hit(&mut self, length: f64, min_step: f64) -> Option<f64> {
        let mut s = 0.0;
        let mut d = self.distances(s);
        if touching(&d) {
            return Some(s);
        }
        while s < length {
            let safe = d
                .iter()
                .zip(self.rates)
                .filter(|(_, r)| **r > 0.0)
                .map(|(d, r)| d / r)
                .fold(f64::INFINITY, f64::min);
            let step = safe.max(min_step);
            // The budget's last pose is the path's end (rounding in the
            // steps above may leave a sliver).
            let next = if step.is_finite() && self.samples < MAX_SWEEP_SAMPLES {
                (s + step).min(length)
            } else {
                length
            };
            let d_next = self.distances(next);
            // A step longer than the distances allow could pass over a
            // contact: the first one in between, if any.
            let hit = if next - s > safe {
                self.first_contact((s, &d), (next, &d_next))
            } else {
                touching(&d_next).then_some(next)
            };
            if hit.is_some() {
                return hit;
            }
            (s, d) = (next, d_next);
        }
        None
    }

    /// Per body, the smallest distance at parameter `s`.
    fn distances(&mut self, s: f64) -> Vec<f64> {
        self.samples += 1;
        let poses = self.model.world_from_link(&self.path.joint_positions(s));
        self.world.distances(&poses)
    }

    /// The first parameter in `(a, b]` where a pair touches, to within the
    /// tolerance and never before the contact, given the distances at both
    /// ends: an interval whose ends' distances rule out a contact in
    /// between (each body's distance changes at most at its rate) is clear;
    /// another is halved, the earlier half first.
    fn first_contact(&mut self, (a, da): (f64, &[f64]), (b, db): (f64, &[f64])) -> Option<f64> {
        let clear = da
            .iter()
            .zip(db)
            .zip(self.rates)
            .all(|((x, y), r)| x + y > r * (b - a) || (*r == 0.0 && *x > 0.0 && *y > 0.0));
        if clear {
            return None;
        }
        if b - a <= self.tolerance || self.samples >= MAX_SWEEP_SAMPLES + MAX_REFINE_SAMPLES {
            if b - a > self.tolerance {
                self.exact = false;
            }
            return touching(db).then_some(b);
        }
        let mid = a + 0.5 * (b - a);
        if !(mid > a && mid < b) {
            // No parameter in between (the ends are neighbours in f64).
            return touching(db).then_some(b);
        }
        let dm = self.distances(mid);
        if let Some(first) = self.first_contact((a, da), (mid, &dm)) {
            return Some(first);
        }
        if touching(&dm) {
            return Some(mid);
        }
        self.first_contact((mid, &dm), (b, db))
    }
}

/// A planned path in joint space, by a path parameter `s` in `[0, length]`.
///
/// An MC_MoveModulo move samples its axis profile, an MCLM/MCCM move its
/// path by path length (`plant/collide.rs`). The sweep's bound holds only if
/// [`PathSampler::joint_rate_bounds`] are true upper bounds.
pub trait PathSampler {
    /// End of the parameter range (the start is 0).
    fn length(&self) -> f64;
    /// Joint positions (rad or m, per URDF joint in model order) at `s`.
    fn joint_positions(&self, s: f64) -> Vec<f64>;
    /// Per URDF joint, an upper bound of `|dq_j/ds|` over the path.
    fn joint_rate_bounds(&self) -> Vec<f64>;
    /// Time from the move's start at which the plan reaches `s`, s.
    fn time_s(&self, s: f64) -> f64;
}

/// A collision the sweep predicts.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PredictedCollision {
    /// Path parameter of the first colliding sample.
    pub parameter: f64,
    /// Time from the move's start at that sample, s.
    pub time_s: f64,
    /// First body.
    pub a: String,
    /// Second body.
    pub b: String,
    /// Penetration depth at the sample, m.
    pub depth_m: f64,
    /// The sweep's bound (parameter units; see the module doc): the first
    /// contact of the planned path lies in `[parameter - bound, parameter]`.
    pub bound: f64,
}

/// The most poses one pre-flight sweep steps through (bounded work,
/// whatever the path's length): a path that needs more at
/// `sweep_resolution_m` is stepped with steps of `length /
/// MAX_SWEEP_SAMPLES`.
pub const MAX_SWEEP_SAMPLES: usize = 100_000;

/// The most further poses a sweep checks to settle the steps between its
/// samples; beyond them the sweep's bound is its step again.
pub const MAX_REFINE_SAMPLES: usize = 100_000;

/// The sweep locates the first contact to this fraction of the path's
/// length (parameter units), never before it.
pub const SWEEP_TOLERANCE: f64 = 1e-6;

/// What a sweep did.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SweepReport {
    /// The first predicted collision, if any.
    pub collision: Option<PredictedCollision>,
    /// Poses checked.
    pub samples: usize,
    /// The bound `h` in parameter units (see the module docs).
    pub step_bound: f64,
    /// The path's parameter length.
    pub length: f64,
}
