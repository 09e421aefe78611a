//! The peak speed of a position profile, and the softened brake: the
//! root finding behind [`Profile::to_position`] (the parent module's doc
//! describes the shapes).

use super::kinematics::{Limits, Shape, State};
use super::ramp::{Course, Ramp, Settle, TailFrame, phase_distance, ramp_distance, ramp_limits};

/// The time-optimal profile for an axis that is already decelerating
/// (`dir`-frame acceleration < 0) towards a target beyond its braking point
/// but short of where it would be after ending the deceleration: it
/// decelerates less hard first — the acceleration rises from `a0` to some
/// `a1 < 0` with the decel jerk — then brakes to `vf` with the full limits,
/// never touching zero acceleration in between (no creep). `a1` is the one
/// whose distance equals the target's; the distance grows with `a1`.
/// The two ramps, in the travel frame; `None` when the planner's other
/// shapes should handle the case.
pub(super) fn softened_brake(start: State, dir: f64, vf: f64, dist: f64, limits: &Limits) -> Option<(Ramp, Ramp)> {
    let Shape::SCurve { decel_jerk: j, .. } = limits.shape else {
        return None;
    };
    let (v0, a0) = (dir * start.velocity, dir * start.acceleration);
    let soften = |a1: f64| {
        let first = Ramp::jerk_phase(v0, a0, j, (a1 - a0) / j);
        let v1 = v0 + (a1 * a1 - a0 * a0) / (2.0 * j);
        let rest = Ramp::new(v1, a1, vf, limits);
        (first, rest)
    };
    let excess = |a1: f64| softened_excess(v0, a0, a1, vf, dist, limits);
    let at_start = excess(a0);
    let at_zero = excess(0.0);
    if at_start[0] > 0.0 || at_zero[0] < 0.0 {
        return None;
    }
    let tol = 1e-13 * dist.abs();
    let a1 = if at_zero[1].is_finite() {
        newton_at_most(a0, 0.0, at_start[0], at_zero, tol, excess)
    } else {
        largest_at_most(a0, 0.0, tol, |a1| excess(a1)[0])
    };
    Some(soften(a1))
}

/// The distance of [`softened_brake`]'s profile with the acceleration
/// eased to `a1` (in `[a0, 0]`), minus `dist`, and its derivative by `a1`
/// (the second derivative unknown: NaN). The brake after the easing starts
/// at `a1` and first deepens it with the decel jerk, so it is the ramp from
/// zero acceleration at the virtual speed v_v = v1 + a1²/(2j) (whose own
/// first phase would pass through (v1, a1)) less that virtual phase:
/// closed-form, like its derivative, 2·v_v/j + a1²/j² + 2·a1·S'(v_v)/j with
/// S the ramp from (v_v, 0) to `vf`. (The coast speed v1 − a1²/(2j) is the
/// same for every `a1`, so the brake deepens throughout when it does at
/// `a0`; with a start deceleration beyond the limit it does not, and the
/// distance comes from the general ramp.)
pub(super) fn softened_excess(v0: f64, a0: f64, a1: f64, vf: f64, dist: f64, limits: &Limits) -> [f64; 3] {
    let Shape::SCurve { decel_jerk: j, .. } = limits.shape else {
        return [f64::NAN; 3];
    };
    let lead = phase_distance(v0, a0, j, (a1 - a0) / j);
    let v1 = v0 + (a1 * a1 - a0 * a0) / (2.0 * j);
    if -a0 > limits.deceleration {
        return [lead + ramp_distance(v1, a1, vf, limits) - dist, f64::NAN, f64::NAN];
    }
    let v_virtual = v1 + a1 * a1 / (2.0 * j);
    let [settle, settle_slope, _] = Settle::new(vf, limits.deceleration, Some(j)).reach(v_virtual);
    let virtual_phase = (-a1 / j) * (v_virtual - a1 * a1 / (6.0 * j));
    let slope = 2.0 * v_virtual / j + a1 * a1 / (j * j) + 2.0 * a1 * settle_slope / j;
    [lead + settle - virtual_phase - dist, slope, f64::NAN]
}

/// The ramps of a position profile as a function of its peak speed `vp`:
/// from (v0, a0) to `vp`, then from `vp` at rest acceleration down to `vf`
/// (no second ramp when `vf` is `None`), for `vp` in a search range. The
/// distances and their slopes are closed-form, so Newton steps find the
/// peak whose ramps fit a distance in a few evaluations.
pub(super) struct PeakRamps<'a> {
    start: (f64, f64),
    /// The final speed and the limits of the ramp down to it.
    settle: Option<Settle>,
    range: (f64, f64),
    /// Where the first ramp's course is taken from: inside the range also
    /// at its ends (at an end it may be another: at the coast velocity a
    /// ramp only ends its acceleration), so the distance is one smooth
    /// function.
    inside: (f64, f64),
    /// The first ramp's course where it is the same throughout the range
    /// (it is unless an easing varies with the peak, or the range spans
    /// the coast velocity), with its lead's distance and its tail's frame.
    course: Option<(Course, f64, Option<TailFrame>)>,
    /// The first ramp's course and tail frame at the inside of the high
    /// end, kept from [`PeakRamps::excess_at_high`] for
    /// [`PeakRamps::fix_course`].
    high: Option<(Course, Option<TailFrame>)>,
    dist: f64,
    limits: &'a Limits,
}

impl<'a> PeakRamps<'a> {
    pub(super) fn new(start: (f64, f64), vf: Option<f64>, (lo, hi): (f64, f64), dist: f64, limits: &'a Limits) -> Self {
        let nudge = (hi - lo).max(0.0) * 2f64.powi(-20);
        let mid = 0.5 * (lo + hi);
        Self {
            start,
            settle: vf.map(|vf| {
                let (a_max, jerk) = ramp_limits(mid, vf, limits);
                Settle::new(vf, a_max, jerk)
            }),
            range: (lo, hi),
            inside: (lo + nudge, (hi - nudge).max(lo + nudge)),
            course: None,
            high: None,
            dist,
            limits,
        }
    }

    /// The first ramp's course at `vt`, and its tail's frame where the
    /// course has a tail and no easing.
    fn course_at(&self, vt: f64) -> (Course, Option<TailFrame>) {
        let (v0, a0) = self.start;
        let course = Course::new(v0, a0, vt, self.limits);
        let frame = course.tail.jerk.filter(|_| course.eased.is_none());
        (course, frame.map(|j| course.tail.frame(j, vt)))
    }

    /// The first ramp's distance to `vp` and its first and second
    /// derivatives, along a course and tail frame from
    /// [`PeakRamps::course_at`].
    fn first_ramp(&self, (course, frame): (Course, Option<TailFrame>), vp: f64) -> [f64; 3] {
        let (v0, a0) = self.start;
        match frame {
            Some(frame) => {
                let [tail, slope, curvature] = frame.reach(vp);
                [course.lead_distance(v0, a0) + tail, slope, curvature]
            }
            None => course.reach(v0, a0, vp),
        }
    }

    /// [`PeakRamps::excess`] at the range's high end, before any course is
    /// fixed: where the ramps fit there no search follows, and where they
    /// do not the course found there is kept for [`PeakRamps::fix_course`].
    pub(super) fn excess_at_high(&mut self) -> [f64; 3] {
        let hi = self.range.1;
        let high = self.course_at(self.inside.1);
        self.high = Some(high);
        self.with_settle(self.first_ramp(high, hi), hi)
    }

    /// Takes the first ramp's course once for the whole range where it is
    /// the same throughout (before a search's many evaluations).
    pub(super) fn fix_course(&mut self) {
        let (v0, a0) = self.start;
        let (high, high_frame) = self.high.take().unwrap_or_else(|| self.course_at(self.inside.1));
        let (low, low_frame) = self.course_at(self.inside.0);
        self.course = (low.eased.is_none() && low == high).then(|| {
            let frame = low_frame.filter(|frame| Some(*frame) == high_frame);
            (low, low.lead_distance(v0, a0), frame)
        });
    }

    /// The ramps' distance minus the distance to fit, and its first and
    /// second derivatives, at `vp`.
    pub(super) fn excess(&self, vp: f64) -> [f64; 3] {
        let first = match self.course {
            Some((course, lead, frame)) => {
                let [tail, slope, curvature] = match (frame, course.tail.jerk) {
                    (Some(frame), _) => frame.reach(vp),
                    // The side of the coast speed of the range's inside (see
                    // below).
                    (None, Some(j)) => course.tail.frame(j, vp.clamp(self.inside.0, self.inside.1)).reach(vp),
                    (None, None) => course.tail.reach(vp),
                };
                [lead + tail, slope, curvature]
            }
            None => {
                // The course, and the side of the coast speed the tail is
                // seen from, of the range's inside: at an end the distance
                // is the limit from inside (from the other side of the
                // coast speed it has a square-root kink).
                let inside = vp.clamp(self.inside.0, self.inside.1);
                self.first_ramp(self.course_at(inside), vp)
            }
        };
        self.with_settle(first, vp)
    }

    /// `first` (the first ramp's distance to `vp` and its derivatives) with
    /// the second ramp's added and the distance to fit taken off.
    fn with_settle(&self, first: [f64; 3], vp: f64) -> [f64; 3] {
        let second = self.settle.map_or([0.0; 3], |settle| settle.reach(vp));
        [
            first[0] + second[0] - self.dist,
            first[1] + second[1],
            first[2] + second[2],
        ]
    }

    /// The largest peak in the range whose ramps fit, to within `tol`
    /// (they fit at the range's low end).
    pub(super) fn solve(mut self, tol: f64) -> f64 {
        let (lo, hi) = self.range;
        if hi <= lo {
            return lo;
        }
        self.fix_course();
        newton_at_most(lo, hi, self.excess(lo)[0], self.excess(hi), tol, |vp| self.excess(vp))
    }
}

/// Largest `x` in `[lo, hi]` with `f(x) ≤ 0`, for `f` increasing, given
/// `f` and its first and second derivatives (and their values at the
/// ends): `hi` when `f(hi) ≤ 0`, `lo` when `f(lo) ≥ −tol`, else the first
/// point found with |f| ≤ `tol` (on either side of the root), or the
/// root to the resolution of `x`.
/// Far from the root a step assumes `f − f(lo)` grows like a power of
/// `x − lo` (a ramp's distance does, with exponent ½ to 2, so one such step
/// lands close from any distance); near it a step goes to the root of the
/// local quadratic (exact where both ramps hold their acceleration limit,
/// cubically convergent elsewhere; Newton where the curvature is unknown);
/// a step that leaves the bracket, and every step after the tenth, bisects.
pub(super) fn newton_at_most(
    lo: f64,
    hi: f64,
    f_lo: f64,
    [f_hi, df_hi, ddf_hi]: [f64; 3],
    tol: f64,
    f: impl Fn(f64) -> [f64; 3],
) -> f64 {
    if f_hi <= 0.0 {
        return hi;
    }
    if f_lo >= -tol {
        return lo;
    }
    let span = -f_lo;
    let (mut a, mut b) = (lo, hi);
    let (mut x, mut fx, mut dfx, mut ddfx) = (hi, f_hi, df_hi, ddf_hi);
    for step in 0..100 {
        if fx.abs() <= 2.0 * f64::EPSILON * x.abs() * dfx.abs() && dfx.is_finite() {
            // Converged to the resolution of x: keep the ramps inside the
            // distance if a few ulps below does, else f is at its rounding
            // and the cruise absorbs it.
            for _ in 0..4 {
                if fx <= 0.0 || x <= a {
                    break;
                }
                x = x.next_down();
                fx = f(x)[0];
            }
            return x.max(a);
        }
        let mut next = if step >= 10 {
            f64::NAN
        } else if fx.abs() > span {
            let rise = fx - f_lo;
            let power = dfx * (x - lo) / rise;
            lo + (x - lo) * (-(rise / span).ln() / power).exp()
        } else {
            // The root of f + f'·δ + f''·δ²/2 nearest x, in the form that
            // does not cancel: δ = −2f / (f' + √(f'² − 2·f·f'')); Newton
            // where there is none or the curvature is unknown (NaN).
            let discriminant = dfx * dfx - 2.0 * fx * ddfx;
            if discriminant >= 0.0 {
                x - 2.0 * fx / (dfx + discriminant.sqrt())
            } else {
                x - fx / dfx
            }
        };
        if !(next > a && next < b) {
            next = 0.5 * (a + b);
            if !(next > a && next < b) {
                break;
            }
        }
        x = next;
        [fx, dfx, ddfx] = f(x);
        if fx <= 0.0 {
            a = x;
            if fx >= -tol {
                return x;
            }
        } else {
            b = x;
            if fx <= tol {
                return x;
            }
        }
        // The bracket is down to a few ulps: f is at its rounding there.
        if b - a <= 8.0 * f64::EPSILON * b.abs() {
            return a;
        }
    }
    a
}

/// Largest `x` in `[lo, hi]` with `f(x) ≤ 0`, for `f` increasing and
/// `f(lo) ≤ 0`: `hi` when `f(hi) ≤ 0`, else a point on the root's low side
/// where `f` is within `tol` of 0 (or the root to the last bits). Regula
/// falsi with the Illinois modification, which converges superlinearly on
/// the smooth ramp distances, and a bisection step whenever an
/// interpolation does not halve the bracket.
pub(super) fn largest_at_most(lo: f64, hi: f64, tol: f64, f: impl Fn(f64) -> f64) -> f64 {
    if hi <= lo {
        return lo;
    }
    let mut f_hi = f(hi);
    if f_hi <= 0.0 {
        return hi;
    }
    let (mut lo, mut hi) = (lo, hi);
    let mut f_lo = f(lo).min(0.0);
    // Which end the last step moved (+1 low, −1 high), for Illinois; and
    // whether the next step bisects (the last one did not halve the bracket).
    let (mut side, mut bisect) = (0i8, false);
    for _ in 0..200 {
        let width = hi - lo;
        let mid = 0.5 * (lo + hi);
        let mut x = if bisect || f_hi <= f_lo {
            mid
        } else {
            lo - f_lo * width / (f_hi - f_lo)
        };
        if !(x > lo && x < hi) {
            x = mid;
            if x <= lo || x >= hi {
                break;
            }
        }
        let fx = f(x);
        if fx <= 0.0 {
            lo = x;
            f_lo = fx;
            if side == 1 && !bisect {
                f_hi *= 0.5;
            }
            side = 1;
            if fx >= -tol {
                break;
            }
        } else {
            hi = x;
            f_hi = fx;
            if side == -1 && !bisect {
                f_lo *= 0.5;
            }
            side = -1;
        }
        bisect = !bisect && hi - lo > 0.5 * width;
    }
    lo
}
