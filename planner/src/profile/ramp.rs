//! Velocity ramps: the time-optimal change from (v, a) to (v_target, 0).
//!
//! Trapezoidal: one constant-acceleration phase. S-curve: up to three
//! constant-jerk phases (acceleration towards a peak, hold at the peak, back to
//! zero); the peak is the limit, or lower when the velocity change is small.
//!
//! Which limits a phase uses follows what the phase does to the speed, as the
//! Logix accel and decel jerks are defined: while the speed rises the
//! acceleration limit and accel jerk apply, while it falls the deceleration
//! limit and decel jerk. A ramp that starts with the speed still rising but
//! must end slower (a stop issued while the axis accelerates) first brings
//! the acceleration to zero with the accel jerk — the speed peaks at
//! [`coast_velocity`], the least it can with that jerk — and only then
//! decelerates; likewise a ramp that starts decelerating but must end faster
//! first ends the deceleration with the decel jerk. So a stop never carries
//! the speed past the limit where the start state lets it stay within.

use super::kinematics::{Limits, Shape};

/// One piece of a ramp. `set_acceleration` is `Some(a)` for trapezoidal
/// phases, whose acceleration is a step, and `None` for jerk phases.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(super) struct Phase {
    pub duration_s: f64,
    pub jerk: f64,
    pub set_acceleration: Option<f64>,
}

/// A planned velocity change: its phases (a profile integrates them; the
/// planner's searches use the closed-form [`Course::reach`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Ramp {
    phases: [Phase; 5],
    count: usize,
    /// The speed and acceleration it starts from.
    start: (f64, f64),
}

/// Signed distance of one constant-jerk phase of `t_s` from (`v`, `a`).
#[inline]
pub(super) fn phase_distance(v: f64, a: f64, jerk: f64, t_s: f64) -> f64 {
    t_s * (v + t_s * (a * 0.5 + t_s * jerk * (1.0 / 6.0)))
}

/// The speed at which ending the acceleration `a` with `jerk` arrives.
fn coast(v: f64, a: f64, jerk: f64) -> f64 {
    v + a * a.abs() / (2.0 * jerk)
}

/// The acceleration and jerk limits a ramp from `v` to `vt` uses: raising the
/// speed uses the acceleration limits, lowering it the deceleration limits,
/// reversing the smaller of both.
pub(super) fn ramp_limits(v: f64, vt: f64, limits: &Limits) -> (f64, Option<f64>) {
    let (accel_jerk, decel_jerk) = match limits.shape {
        Shape::Trapezoidal => (None, None),
        Shape::SCurve { accel_jerk, decel_jerk } => (Some(accel_jerk), Some(decel_jerk)),
    };
    if v * vt < 0.0 {
        let jerk = accel_jerk.zip(decel_jerk).map(|(a, d)| a.min(d));
        (limits.acceleration.min(limits.deceleration), jerk)
    } else if vt.abs() >= v.abs() {
        (limits.acceleration, accel_jerk)
    } else {
        (limits.deceleration, decel_jerk)
    }
}

/// The part of a ramp that changes the speed in one go: from (`v`, `a`) to
/// the target with one acceleration limit and jerk (`None`: a trapezoid,
/// whose acceleration is a step).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Tail {
    pub v: f64,
    pub a: f64,
    pub a_max: f64,
    pub jerk: Option<f64>,
}

/// How a ramp from (v, a) reaches its target: at most two lead phases (the
/// fall to zero speed of a reversal that must end its acceleration on the
/// far side, then ending or easing the acceleration), then a [`Tail`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Course {
    /// A reversal's fall to zero speed with the decel jerk (see
    /// [`Course::through_zero`]).
    pub fall: Option<Phase>,
    pub lead: Option<Phase>,
    pub tail: Tail,
    /// Set when the lead eases a deceleration into a reversal just enough
    /// for the tail to end its acceleration at the target: the easing then
    /// depends on the target.
    pub eased: Option<Easing>,
}

/// The limits of an easing that ends where the target is (see
/// [`Course::eased`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Easing {
    /// 1/(2·j_both) − 1/(2·decel jerk): how the far side's reach grows with
    /// the acceleration left after the easing, squared.
    gain: f64,
    decel_jerk: f64,
    j_both: f64,
    /// The sign of the start acceleration (the frame the easing is in).
    sign: f64,
}

impl Course {
    pub(super) fn new(v: f64, a: f64, vt: f64, limits: &Limits) -> Self {
        let simple = |v: f64, a: f64, a_max: f64, jerk: Option<f64>| Course {
            fall: None,
            lead: None,
            tail: Tail { v, a, a_max, jerk },
            eased: None,
        };
        if let Shape::SCurve { accel_jerk, decel_jerk } = limits.shape
            && a != 0.0
        {
            // The acceleration must pass through zero before the speed turns
            // the other way: end it with the jerk of the current sense. A
            // ramp through zero speed while the speed falls uses the smaller
            // limits of both senses, which hold on either side.
            let rising = v * a >= 0.0;
            let j_now = if rising { accel_jerk } else { decel_jerk };
            let v_free = coast(v, a, j_now);
            // Through zero speed: asked for, or forced by an acceleration
            // that cannot end before the speed reaches zero.
            let reverses = v * vt < 0.0 || v_free * v < 0.0;
            if !reverses && (vt - v_free) * a > 0.0 {
                // The acceleration keeps its sign: one sense throughout.
                return if rising {
                    simple(v, a, limits.acceleration, Some(accel_jerk))
                } else {
                    simple(v, a, limits.deceleration, Some(decel_jerk))
                };
            }
            if (!reverses || rising) && v_free * v >= 0.0 {
                // End the acceleration, then change the speed from zero
                // acceleration with the limits of the new sense.
                let (a_max, jerk) = ramp_limits(v_free, vt, limits);
                return Course {
                    fall: None,
                    lead: Some(Phase {
                        duration_s: a.abs() / j_now,
                        jerk: -j_now.copysign(a),
                        set_acceleration: None,
                    }),
                    tail: Tail {
                        v: v_free,
                        a: 0.0,
                        a_max,
                        jerk: Some(jerk.unwrap_or(j_now)),
                    },
                    eased: None,
                };
            }
            let a_both = limits.acceleration.min(limits.deceleration);
            let j_both = accel_jerk.min(decel_jerk);
            if reverses && !rising {
                // Decelerating towards a reversal: past zero speed the
                // smaller limits hold, so while the speed still falls ease
                // the acceleration with the decel jerk to what the far side
                // can end without passing `vt`: (in the frame where a > 0)
                // v1 + a_c²/(2·j_both) ≤ vt with v1 = v + (a² − a_c²)/(2·jd).
                let s = a.signum();
                let (v_s, a_s, vt_s) = (s * v, s * a, s * vt);
                let v_free_d = v_s + a_s * a_s / (2.0 * decel_jerk);
                let gain = 1.0 / (2.0 * j_both) - 1.0 / (2.0 * decel_jerk);
                let mut a_c = a_s.min(a_both);
                let mut eased = None;
                if vt_s > v_s && gain > 0.0 {
                    let reach = ((vt_s - v_free_d).max(0.0) / gain).sqrt();
                    if reach < a_c {
                        a_c = reach;
                        eased = Some(Easing {
                            gain,
                            decel_jerk,
                            j_both,
                            sign: s,
                        });
                    }
                }
                let duration_s = (a_s - a_c) / decel_jerk;
                let jerk = -decel_jerk.copysign(a);
                let v1 = v + duration_s * (a + jerk * duration_s / 2.0);
                // Only while the speed still falls: an easing that would
                // reach zero speed first is left to the smaller limits.
                if a_c < a_s && v1 * v > 0.0 {
                    let course = Course {
                        fall: None,
                        lead: Some(Phase {
                            duration_s,
                            jerk,
                            set_acceleration: None,
                        }),
                        tail: Tail {
                            v: v1,
                            a: s * a_c,
                            a_max: a_both,
                            jerk: Some(j_both),
                        },
                        eased,
                    };
                    return Self::through_zero(v, a, vt, limits)
                        .filter(|_| course.tail.passes(limits))
                        .unwrap_or(course);
                }
            }
            if reverses {
                let course = simple(v, a, a_both, Some(j_both));
                if !rising && course.tail.passes(limits) {
                    return Self::through_zero(v, a, vt, limits).unwrap_or(course);
                }
                return course;
            }
        }
        let (a_max, jerk) = ramp_limits(v, vt, limits);
        simple(v, a, a_max, jerk)
    }

    /// A reversal whose speed still falls, planned by the jerk of each
    /// phase: the decel jerk eases the acceleration until the speed is
    /// zero, then the course of a start at rest with the acceleration left
    /// (accel jerk while the speed rises, decel jerk if it must fall again).
    /// The speed past zero then peaks at a_z²/(2·accel jerk), the least
    /// any plan reaches, where ending the acceleration with the smaller jerk
    /// of both senses peaks higher. `None` when the acceleration ends before
    /// zero speed.
    fn through_zero(v: f64, a: f64, vt: f64, limits: &Limits) -> Option<Course> {
        let Shape::SCurve { decel_jerk, .. } = limits.shape else {
            return None;
        };
        let (v_s, a_s) = (v * a.signum(), a.abs());
        let a_zero_sq = a_s * a_s + 2.0 * decel_jerk * v_s;
        if v_s >= 0.0 || a_zero_sq <= 0.0 {
            return None;
        }
        let a_zero = a_zero_sq.sqrt();
        let fall = Phase {
            duration_s: (a_s - a_zero) / decel_jerk,
            jerk: -decel_jerk.copysign(a),
            set_acceleration: None,
        };
        let rest = Course::new(0.0, a_zero.copysign(a), vt, limits);
        Some(Course {
            fall: Some(fall),
            ..rest
        })
    }

    /// Distance of the lead phases from (v, a), where the ramp starts.
    pub(super) fn lead_distance(&self, v: f64, a: f64) -> f64 {
        let (mut distance, mut v, mut a) = (0.0, v, a);
        if let Some(p) = self.fall {
            distance += phase_distance(v, a, p.jerk, p.duration_s);
            // The fall ends at zero speed (the rest of the course starts
            // there).
            v = 0.0;
            a += p.jerk * p.duration_s;
        }
        distance + self.lead.map_or(0.0, |p| phase_distance(v, a, p.jerk, p.duration_s))
    }

    /// Signed distance of the ramp from (v, a) to `vt` (the target this
    /// course was planned for), and its first and second derivatives with
    /// respect to `vt` (the second NaN where an easing makes it unknown).
    pub(super) fn reach(&self, v: f64, a: f64, vt: f64) -> [f64; 3] {
        let Some(Easing {
            gain,
            decel_jerk: jd,
            j_both: jb,
            sign,
        }) = self.eased
        else {
            let [tail, slope, curvature] = self.tail.reach(vt);
            return [self.lead_distance(v, a) + tail, slope, curvature];
        };
        let end = self.tail.end_acceleration(jb);
        let distance = self.lead_distance(v, a) + phase_distance(self.tail.v, self.tail.a, end.jerk, end.duration_s);
        // In the frame of the start acceleration: the easing ends at a_c
        // with speed v1, one phase at −jb ends a_c. With a_c² = (vt − v_free
        // under the decel jerk)/gain, d(distance)/d(a_c) is
        // −v1/jd + v1/jb − a_c²/(jd·jb) + a_c²/jb², and d(a_c)/d(vt) is
        // 1/(2·gain·a_c).
        let (v1, a_c) = (sign * self.tail.v, sign * self.tail.a);
        let per_a_c = -v1 / jd + v1 / jb - a_c * a_c / (jd * jb) + a_c * a_c / (jb * jb);
        [distance, per_a_c / (2.0 * gain * a_c), f64::NAN]
    }
}

/// Signed distance of the ramp from (v, a) to `vt`, in closed form (what
/// [`Ramp::new`]'s phases integrate to, without building them).
pub(super) fn ramp_distance(v: f64, a: f64, vt: f64, limits: &Limits) -> f64 {
    Course::new(v, a, vt, limits).reach(v, a, vt)[0]
}

impl Tail {
    /// Whether ending this tail's acceleration carries its speed past the
    /// velocity limit.
    fn passes(&self, limits: &Limits) -> bool {
        let Some(j) = self.jerk else {
            return false;
        };
        coast(self.v, self.a, j).abs() > limits.velocity
    }

    /// Signed distance of this tail to `vt`, and its first and second
    /// derivatives with respect to `vt`, in closed form (the phases
    /// [`Ramp::new`] builds).
    pub(super) fn reach(&self, vt: f64) -> [f64; 3] {
        let Tail { v, a_max, jerk, .. } = *self;
        let Some(j) = jerk else {
            // One phase at ±a_max: (vt² − v²) / (2·acc).
            let acc = a_max.copysign(vt - v);
            return if vt == v {
                [0.0, 0.0, 0.0]
            } else {
                [(vt * vt - v * v) / (2.0 * acc), vt / acc, 1.0 / acc]
            };
        };
        self.frame(j, vt).reach(vt)
    }

    /// The frame of the targets on `vt`'s side of the coast velocity.
    pub(super) fn frame(&self, j: f64, vt: f64) -> TailFrame {
        let inv_j = 1.0 / j;
        let v_free = self.v + 0.5 * self.a * self.a.abs() * inv_j;
        let s = if vt >= v_free { 1.0 } else { -1.0 };
        TailFrame::new(self, j, inv_j, s, v_free)
    }
}

/// An S-curve tail seen from one side of its coast velocity (the speed at
/// which ending the start acceleration arrives), in the frame where the
/// speed rises there: what its phases to every target on that side share,
/// computed once — a root search evaluates many targets.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct TailFrame {
    s: f64,
    /// Start speed and acceleration, in the frame.
    v: f64,
    a: f64,
    /// The coast speed, in the frame (no target on this side is below it).
    v_free: f64,
    j: f64,
    inv_j: f64,
    a_max: f64,
    /// The phases up to the hold when the acceleration limit is held:
    /// inverse peak, t1, j1, v1, t3.
    held: (f64, f64, f64, f64, f64),
}

impl TailFrame {
    fn new(tail: &Tail, j: f64, inv_j: f64, s: f64, v_free: f64) -> Self {
        let (v, a, a_max) = (s * tail.v, s * tail.a, tail.a_max);
        let mut frame = Self {
            s,
            v,
            a,
            v_free: s * v_free,
            j,
            inv_j,
            a_max,
            held: (0.0, 0.0, 0.0, 0.0, 0.0),
        };
        frame.held = frame.up_to_hold(a_max);
        frame
    }

    /// Inverse peak, t1, j1, v1, t3 for an acceleration peaking at `peak`.
    fn up_to_hold(&self, peak: f64) -> (f64, f64, f64, f64, f64) {
        let (v, a, j) = (self.v, self.a, self.j);
        let t1 = (peak - a).abs() * self.inv_j;
        let j1 = if peak >= a { j } else { -j };
        (1.0 / peak, t1, j1, v + t1 * (a + j1 * t1 / 2.0), peak * self.inv_j)
    }

    /// The phases to `vt`: one computation for the built ramps and the
    /// closed-form distances, so the two agree to the last bits.
    fn phases(&self, vt: f64) -> TailPhases {
        let vt = self.s * vt;
        // The acceleration peaks at its limit (held for t2), or lower, at
        // √(j·(vt − v) + a²/2). Measured from the coast speed the square
        // has no cancelling terms — j·(vt − v_free) + a² (a > 0) or
        // j·(vt − v_free) (a ≤ 0) — so a target at the coast speed ends
        // the acceleration exactly instead of adding phases as long as the
        // square root of a rounding residue.
        let (a, a_max) = (self.a, self.a_max);
        let from_coast = self.j * (vt - self.v_free).max(0.0);
        let rise = if a > 0.0 { from_coast + a * a } else { from_coast };
        let held = a > a_max || rise >= a_max * a_max;
        let peak = if held { a_max } else { rise.sqrt() };
        let (inv_peak, t1, j1, v1, t3) = if held { self.held } else { self.up_to_hold(peak) };
        // A hold only at the limit: below it the hold is zero, and the
        // formula's rounding (a difference of nearly equal speeds over a
        // small peak) must not add one.
        let t2 = if held && peak > 0.0 {
            ((vt - v1 - 0.5 * peak * t3) * inv_peak).max(0.0)
        } else {
            0.0
        };
        TailPhases {
            held,
            peak,
            inv_peak,
            t1,
            j1,
            v1,
            t2,
            t3,
        }
    }

    /// Signed distance to `vt`, and its first and second derivatives.
    pub(super) fn reach(&self, vt: f64) -> [f64; 3] {
        let ph = self.phases(vt);
        let (peak, inv_peak, t1, v1, t2, t3) = (ph.peak, ph.inv_peak, ph.t1, ph.v1, ph.t2, ph.t3);
        let (s, v, a, j, inv_j, j1) = (self.s, self.v, self.a, self.j, self.inv_j, ph.j1);
        let d1 = phase_distance(v, a, j1, t1);
        let v2 = v1 + peak * t2;
        let d2 = phase_distance(v1, peak, 0.0, t2);
        let d3 = phase_distance(v2, peak, -j, t3);
        // d/dvt: a longer hold at the peak (limited), or a higher peak
        // (not): both give v2/peak + t3. Its own derivative: 1/peak while
        // the peak is held; else, with v2 = v + (peak² − a²)/(2j) and
        // d(peak)/d(vt) = j/(2·peak), (3/(2j) − (v − a²/(2j))/peak²)·j/(2·peak).
        let curvature = if ph.held {
            inv_peak
        } else {
            (1.5 * inv_j - (v - 0.5 * a * a * inv_j) * inv_peak * inv_peak) * 0.5 * j * inv_peak
        };
        [s * (d1 + d2 + d3), v2 * inv_peak + t3, s * curvature]
    }
}

/// An S-curve tail's three phases to a target speed, in its
/// [`TailFrame`]: jerk `j1` for `t1` to the peak acceleration, a hold at
/// the peak for `t2`, jerk −j for `t3` to zero.
struct TailPhases {
    /// Whether the peak is the acceleration limit.
    held: bool,
    peak: f64,
    inv_peak: f64,
    t1: f64,
    j1: f64,
    /// Speed after the first phase, in the frame.
    v1: f64,
    t2: f64,
    t3: f64,
}

impl Tail {
    /// The phase that brings the acceleration to zero with jerk `j`: the
    /// whole tail where the target is the speed that reaches (an easing's
    /// tail). Built as such rather than as three phases to the target, whose
    /// square root amplifies rounding there.
    fn end_acceleration(&self, j: f64) -> Phase {
        Phase {
            duration_s: self.a.abs() / j,
            jerk: -j.copysign(self.a),
            set_acceleration: None,
        }
    }
}

/// A ramp from (`vp`, 0) down to `vf` (0 ≤ `vf` ≤ `vp`) with one
/// acceleration limit and jerk, as a function of `vp`: its distance and
/// that distance's first and second derivatives, in closed form. Starting
/// and ending at zero acceleration, the speed falls symmetrically, so the
/// distance is the mean speed times the duration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Settle {
    vf: f64,
    a_max: f64,
    inv_a: f64,
    /// The jerk's inverse, and the speed change from which the
    /// acceleration limit is held (a²/j); `None` for a trapezoid.
    jerk: Option<(f64, f64)>,
}

impl Settle {
    pub(super) fn new(vf: f64, a_max: f64, jerk: Option<f64>) -> Self {
        Self {
            vf,
            a_max,
            inv_a: 1.0 / a_max,
            jerk: jerk.map(|j| (1.0 / j, a_max * a_max / j)),
        }
    }

    /// The distance from `vp` and its first two derivatives.
    pub(super) fn reach(&self, vp: f64) -> [f64; 3] {
        let dv = vp - self.vf;
        // The duration and its first two derivatives with respect to vp.
        let (t, dt, ddt) = match self.jerk {
            None => (dv * self.inv_a, self.inv_a, 0.0),
            Some((inv_j, held_from)) if dv >= held_from => (dv * self.inv_a + self.a_max * inv_j, self.inv_a, 0.0),
            Some((inv_j, _)) => {
                // t = 2·r with r = √(dv/j): dt = 1/(j·r), ddt = −dt/(2·dv).
                let r = (dv * inv_j).sqrt();
                let inv_r = 1.0 / r;
                let dt = inv_j * inv_r;
                (2.0 * r, dt, -0.5 * dt * inv_j * inv_r * inv_r)
            }
        };
        let mean = 0.5 * (vp + self.vf);
        [mean * t, 0.5 * t + mean * dt, dt + mean * ddt]
    }
}

impl Ramp {
    fn empty(v: f64, a: f64) -> Self {
        Self {
            phases: [Phase::default(); 5],
            count: 0,
            start: (v, a),
        }
    }

    pub(super) fn new(v: f64, a: f64, vt: f64, limits: &Limits) -> Self {
        let course = Course::new(v, a, vt, limits);
        let mut ramp = Self::empty(v, a);
        if let Some(fall) = course.fall {
            ramp.push(fall);
        }
        if let Some(lead) = course.lead {
            ramp.push(lead);
        }
        let tail = course.tail;
        if let Some(easing) = course.eased {
            ramp.push(tail.end_acceleration(easing.j_both));
            return ramp;
        }
        match tail.jerk {
            None => {
                let (vt0, a_max) = (tail.v, tail.a_max);
                let dv = vt - vt0;
                if dv != 0.0 {
                    ramp.push(Phase {
                        duration_s: dv.abs() / a_max,
                        jerk: 0.0,
                        set_acceleration: Some(a_max.copysign(dv)),
                    });
                }
            }
            Some(j) => ramp.s_curve(&tail, vt, j),
        }
        ramp
    }

    /// One constant-jerk phase from (v, a): `duration_s` at jerk `jerk`.
    pub(super) fn jerk_phase(v: f64, a: f64, jerk: f64, duration_s: f64) -> Self {
        let mut ramp = Self::empty(v, a);
        ramp.push(Phase {
            duration_s,
            jerk,
            set_acceleration: None,
        });
        ramp
    }

    fn s_curve(&mut self, tail: &Tail, vt: f64, j: f64) {
        let frame = tail.frame(j, vt);
        let s = frame.s;
        let TailPhases { t1, j1, t2, t3, .. } = frame.phases(vt);
        self.push(Phase {
            duration_s: t1,
            jerk: s * j1,
            set_acceleration: None,
        });
        self.push(Phase {
            duration_s: t2,
            jerk: 0.0,
            set_acceleration: None,
        });
        self.push(Phase {
            duration_s: t3,
            jerk: -s * j,
            set_acceleration: None,
        });
    }

    fn push(&mut self, phase: Phase) {
        if phase.duration_s > 0.0 && phase.duration_s.is_finite() {
            self.phases[self.count] = phase;
            self.count += 1;
        }
    }

    /// Signed distance travelled during the ramp, integrated through its
    /// phases (the tests' check on the closed forms).
    #[cfg(test)]
    pub(super) fn distance(&self) -> f64 {
        let (mut p, (mut v, mut a)) = (0.0, self.start);
        for ph in self.phases() {
            if let Some(acc) = ph.set_acceleration {
                a = acc;
            }
            let t = ph.duration_s;
            let j = ph.jerk;
            p += phase_distance(v, a, j, t);
            v += t * (a + t * j / 2.0);
            a += t * j;
            if ph.set_acceleration.is_some() {
                a = 0.0;
            }
        }
        p
    }

    /// The phases in time order.
    pub(super) fn phases(&self) -> impl Iterator<Item = Phase> + '_ {
        self.phases[..self.count].iter().copied()
    }
}

/// Velocity reached from (v, a) by bringing the acceleration to zero as fast
/// as the limits allow (v itself for trapezoidal profiles).
pub(super) fn coast_velocity(v: f64, a: f64, limits: &Limits) -> f64 {
    match limits.shape {
        Shape::Trapezoidal => v,
        Shape::SCurve { accel_jerk, decel_jerk } => {
            // The speed rises while v·a ≥ 0 (accel jerk), falls otherwise.
            coast(v, a, if v * a >= 0.0 { accel_jerk } else { decel_jerk })
        }
    }
}
