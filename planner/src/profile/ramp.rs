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

use super::{Limits, Shape};

/// One piece of a ramp. `set_acceleration` is `Some(a)` for trapezoidal
/// phases, whose acceleration is a step, and `None` for jerk phases.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(super) struct Phase {
    pub duration_s: f64,
    pub jerk: f64,
    pub set_acceleration: Option<f64>,
}

/// A planned velocity change.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Ramp {
    phases: [Phase; 4],
    count: usize,
    distance: f64,
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

impl Ramp {
    fn empty() -> Self {
        Self {
            phases: [Phase::default(); 4],
            count: 0,
            distance: 0.0,
        }
    }

    pub(super) fn new(v: f64, a: f64, vt: f64, limits: &Limits) -> Self {
        let mut ramp = Self::empty();
        if let Shape::SCurve { accel_jerk, decel_jerk } = limits.shape
            && a != 0.0
        {
            // The acceleration must pass through zero before the speed turns
            // the other way: end it with the jerk of the current sense. A
            // ramp through zero speed while the speed falls uses the smaller
            // limits of both senses, which hold on either side.
            let rising = v * a >= 0.0;
            let j_now = if rising { accel_jerk } else { decel_jerk };
            let v_free = v + a * a.abs() / (2.0 * j_now);
            // Through zero speed: asked for, or forced by an acceleration
            // that cannot end before the speed reaches zero.
            let reverses = v * vt < 0.0 || v_free * v < 0.0;
            if !reverses && (vt - v_free) * a > 0.0 {
                // The acceleration keeps its sign: one sense throughout.
                let (a_max, j) = if rising {
                    (limits.acceleration, accel_jerk)
                } else {
                    (limits.deceleration, decel_jerk)
                };
                ramp.s_curve(v, a, vt, a_max, j);
                ramp.distance = ramp.integrate(v, a);
                return ramp;
            }
            if (!reverses || rising) && v_free * v >= 0.0 {
                // End the acceleration, then change the speed from zero
                // acceleration with the limits of the new sense.
                ramp.push(Phase {
                    duration_s: a.abs() / j_now,
                    jerk: -j_now.copysign(a),
                    set_acceleration: None,
                });
                if vt != v_free {
                    let (a_max, jerk) = ramp_limits(v_free, vt, limits);
                    ramp.s_curve(v_free, 0.0, vt, a_max, jerk.unwrap_or(j_now));
                }
                ramp.distance = ramp.integrate(v, a);
                return ramp;
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
                if vt_s > v_s && gain > 0.0 {
                    a_c = a_c.min(((vt_s - v_free_d).max(0.0) / gain).sqrt());
                }
                let duration_s = (a_s - a_c) / decel_jerk;
                let jerk = -decel_jerk.copysign(a);
                let v1 = v + duration_s * (a + jerk * duration_s / 2.0);
                // Only while the speed still falls: an easing that would
                // reach zero speed first is left to the smaller limits.
                if a_c < a_s && v1 * v > 0.0 {
                    ramp.push(Phase {
                        duration_s,
                        jerk,
                        set_acceleration: None,
                    });
                    ramp.s_curve(v1, s * a_c, vt, a_both, j_both);
                    ramp.distance = ramp.integrate(v, a);
                    return ramp;
                }
            }
            if reverses {
                ramp.s_curve(v, a, vt, a_both, j_both);
                ramp.distance = ramp.integrate(v, a);
                return ramp;
            }
        }
        let (a_max, jerk) = ramp_limits(v, vt, limits);
        match jerk {
            None => {
                let dv = vt - v;
                if dv != 0.0 {
                    let acc = a_max.copysign(dv);
                    ramp.push(Phase {
                        duration_s: dv.abs() / a_max,
                        jerk: 0.0,
                        set_acceleration: Some(acc),
                    });
                }
            }
            Some(j) => ramp.s_curve(v, a, vt, a_max, j),
        }
        ramp.distance = ramp.integrate(v, a);
        ramp
    }

    /// One constant-jerk phase from (v, a): `duration_s` at jerk `jerk`.
    pub(super) fn jerk_phase(v: f64, a: f64, jerk: f64, duration_s: f64) -> Self {
        let mut ramp = Self::empty();
        ramp.push(Phase {
            duration_s,
            jerk,
            set_acceleration: None,
        });
        ramp.distance = ramp.integrate(v, a);
        ramp
    }

    fn s_curve(&mut self, v: f64, a: f64, vt: f64, a_max: f64, j: f64) {
        // Velocity reached by ramping the acceleration straight to zero.
        let v_free = v + a * a.abs() / (2.0 * j);
        let dv_total = vt - v_free;
        if dv_total == 0.0 {
            if a != 0.0 {
                self.push(Phase {
                    duration_s: a.abs() / j,
                    jerk: -j.copysign(a),
                    set_acceleration: None,
                });
            }
            return;
        }
        // Work in the frame where the velocity must rise.
        let s = dv_total.signum();
        let (v, a, vt) = (s * v, s * a, s * vt);
        let unclipped = (j * (vt - v) + 0.5 * a * a).max(0.0).sqrt();
        let peak = if a > a_max { a_max } else { unclipped.min(a_max) };
        let t1 = (peak - a).abs() / j;
        let dv1 = 0.5 * (a + peak) * t1;
        let t3 = peak / j;
        let dv3 = 0.5 * peak * t3;
        let t2 = if peak > 0.0 {
            ((vt - v - dv1 - dv3) / peak).max(0.0)
        } else {
            0.0
        };
        let j1 = if peak >= a { j } else { -j };
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

    fn integrate(&self, v0: f64, a0: f64) -> f64 {
        let (mut p, mut v, mut a) = (0.0, v0, a0);
        for ph in self.phases() {
            if let Some(acc) = ph.set_acceleration {
                a = acc;
            }
            let t = ph.duration_s;
            let j = ph.jerk;
            p += t * (v + t * (a / 2.0 + t * j / 6.0));
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

    /// Signed distance travelled during the ramp.
    pub(super) fn distance(&self) -> f64 {
        self.distance
    }
}

/// Velocity reached from (v, a) by bringing the acceleration to zero as fast
/// as the limits allow (v itself for trapezoidal profiles).
pub(super) fn coast_velocity(v: f64, a: f64, limits: &Limits) -> f64 {
    match limits.shape {
        Shape::Trapezoidal => v,
        Shape::SCurve { accel_jerk, decel_jerk } => {
            // The speed rises while v·a ≥ 0 (accel jerk), falls otherwise.
            let j = if v * a >= 0.0 { accel_jerk } else { decel_jerk };
            v + a * a.abs() / (2.0 * j)
        }
    }
}
