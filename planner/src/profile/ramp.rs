//! Velocity ramps: the time-optimal change from (v, a) to (v_target, 0).
//!
//! Trapezoidal: one constant-acceleration phase. S-curve: up to three
//! constant-jerk phases (acceleration towards a peak, hold at the peak, back to
//! zero); the peak is the limit, or lower when the velocity change is small.

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
    phases: [Phase; 3],
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
    pub(super) fn new(v: f64, a: f64, vt: f64, limits: &Limits) -> Self {
        let (a_max, jerk) = ramp_limits(v, vt, limits);
        let mut ramp = Self {
            phases: [Phase::default(); 3],
            count: 0,
            distance: 0.0,
        };
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
            let j = if v * a >= 0.0 { accel_jerk } else { decel_jerk };
            v + a * a.abs() / (2.0 * j)
        }
    }
}
