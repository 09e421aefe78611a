//! Known values and seeded random invariants of the profile planner.

use super::peak::softened_excess;
use super::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

const CASES: usize = 10_000;

fn random_limits(rng: &mut ChaCha8Rng, s_curve: bool) -> Limits {
    let v = 10f64.powf(rng.random_range(-1.5..3.0));
    let a = v * 10f64.powf(rng.random_range(-1.0..1.5));
    let d = a * 10f64.powf(rng.random_range(-0.7..0.7));
    if s_curve {
        let ja = a * a / v * 10f64.powf(rng.random_range(-0.5..2.0));
        let jd = ja * 10f64.powf(rng.random_range(-0.7..0.7));
        Limits::s_curve(v, a, d, ja, jd).unwrap()
    } else {
        Limits::trapezoidal(v, a, d).unwrap()
    }
}

fn jerks(l: &Limits) -> Option<(f64, f64)> {
    match l.shape() {
        Shape::Trapezoidal => None,
        Shape::SCurve { accel_jerk, decel_jerk } => Some((accel_jerk, decel_jerk)),
    }
}

/// Analytic time-optimal rest-to-rest duration, from the closed-form ramp
/// formulas (an independent computation from the planner's integrated ramps).
fn analytic_rest_to_rest_s(distance: f64, l: &Limits) -> f64 {
    let (a, d, v_max) = (l.acceleration(), l.deceleration(), l.velocity());
    let ramp_time = |vp: f64, acc: f64, jerk: Option<f64>| match jerk {
        None => vp / acc,
        Some(j) if vp >= acc * acc / j => vp / acc + acc / j,
        Some(j) => 2.0 * (vp / j).sqrt(),
    };
    let (ja, jd) = match jerks(l) {
        Some((ja, jd)) => (Some(ja), Some(jd)),
        None => (None, None),
    };
    let both = |vp: f64| (ramp_time(vp, a, ja), ramp_time(vp, d, jd));
    // Each ramp covers vp·T/2 (its velocity curve is point-symmetric).
    let dist = |vp: f64| {
        let (ta, td) = both(vp);
        vp * (ta + td) / 2.0
    };
    if dist(v_max) <= distance {
        let (ta, td) = both(v_max);
        return ta + td + (distance - dist(v_max)) / v_max;
    }
    let vp = match (ja, jd) {
        (None, None) => (2.0 * distance * a * d / (a + d)).sqrt(),
        (Some(ja), Some(jd)) => {
            let (ba, bd) = (a * a / ja, d * d / jd);
            // Closed forms in the regimes where both ramps are alike.
            let qa = 0.5 * (1.0 / a + 1.0 / d);
            let qb = 0.5 * (a / ja + d / jd);
            let both_limited = (-qb + (qb * qb + 4.0 * qa * distance).sqrt()) / (2.0 * qa);
            let neither = (distance / (1.0 / ja.sqrt() + 1.0 / jd.sqrt())).powf(2.0 / 3.0);
            if both_limited >= ba.max(bd) {
                both_limited
            } else if neither <= ba.min(bd) {
                neither
            } else {
                // Mixed regime: D is an explicit increasing polynomial in √vp;
                // bisect it.
                let (mut lo, mut hi) = (ba.min(bd), ba.max(bd));
                for _ in 0..200 {
                    let mid = 0.5 * (lo + hi);
                    if dist(mid) <= distance { lo = mid } else { hi = mid }
                }
                0.5 * (lo + hi)
            }
        }
        _ => unreachable!(),
    };
    let (ta, td) = both(vp);
    ta + td
}

/// Samples densely and at every segment boundary.
fn samples(p: &Profile) -> Vec<(f64, Sample)> {
    let mut out = Vec::new();
    for seg in &p.segments {
        for k in 0..=8 {
            let t = seg.t0_s + seg.duration_s * f64::from(k) / 8.0;
            out.push((t, seg.at(seg.duration_s * f64::from(k) / 8.0)));
        }
    }
    out
}

/// Every sample within the limits: speed, accel while the speed rises, decel
/// while it falls, jerk.
fn assert_within_limits(p: &Profile, l: &Limits, ctx: &str) {
    let eps = 1e-9;
    let (ja, jd) = jerks(l).unwrap_or((0.0, 0.0));
    for (t, s) in samples(p) {
        assert!(
            s.position.is_finite() && s.velocity.is_finite() && s.acceleration.is_finite(),
            "{ctx}: NaN at {t}"
        );
        assert!(
            s.velocity.abs() <= l.velocity() * (1.0 + eps),
            "{ctx}: |v| {} > {} at {t}",
            s.velocity,
            l.velocity()
        );
        let limit = if s.velocity * s.acceleration > 0.0 {
            l.acceleration()
        } else {
            l.deceleration()
        };
        assert!(
            s.acceleration.abs() <= limit * (1.0 + eps) || s.velocity.abs() < 1e-12,
            "{ctx}: |a| {} > {limit} at {t} (v {})",
            s.acceleration,
            s.velocity
        );
        assert!(s.jerk.abs() <= ja.max(jd) * (1.0 + eps), "{ctx}: |j| {} at {t}", s.jerk);
    }
}

/// The last segment ends on the final state (the snapped final state hides
/// nothing).
fn assert_continuous_end(p: &Profile, ctx: &str) {
    let f = p.final_state();
    if let Some(seg) = p.segments.last() {
        let end = seg.at(seg.duration_s);
        let scale = 1.0 + f.position.abs() + (f.position - p.start_state().position).abs();
        assert!(
            (end.position - f.position).abs() <= 1e-9 * scale,
            "{ctx}: end {} vs {}",
            end.position,
            f.position
        );
        assert!(
            (end.velocity - f.velocity).abs() <= 1e-9 * (1.0 + f.velocity.abs()),
            "{ctx}: end v {} vs {}",
            end.velocity,
            f.velocity
        );
    }
    let s = p.sample(p.duration_s());
    assert_eq!(s.position, f.position, "{ctx}");
}

#[test]
fn rest_to_rest_known_trapezoid() {
    // 10 units at v 2, a 1, d 1: ramps 2 s each (2 units each), 6 units cruise = 3 s.
    let l = Limits::trapezoidal(2.0, 1.0, 1.0).unwrap();
    let p = Profile::to_position(State::at_rest(0.0), 10.0, 0.0, &l);
    assert!((p.duration_s() - 7.0).abs() < 1e-12);
    assert_eq!(p.sample(1.0).velocity, 1.0);
    assert_eq!(p.sample(1.0).acceleration, 1.0);
    assert!((p.sample(3.5).position - 5.0).abs() < 1e-12);
    assert_eq!(p.sample(7.0).position, 10.0);
    // Triangle: 1 unit → vp = 1, 2 s.
    let p = Profile::to_position(State::at_rest(5.0), 4.0, 0.0, &l);
    assert!((p.duration_s() - 2.0).abs() < 1e-12);
    assert!((p.sample(1.0).velocity + 1.0).abs() < 1e-12);
}

#[test]
fn rest_to_rest_known_s_curve_has_seven_phases() {
    // v 1, a 1, j 10: each ramp = 1/1 + 1/10 = 1.1 s, covers 0.55; 10 units.
    let l = Limits::s_curve(1.0, 1.0, 1.0, 10.0, 10.0).unwrap();
    let p = Profile::to_position(State::at_rest(0.0), 10.0, 0.0, &l);
    assert_eq!(p.segments.len(), 7);
    assert!((p.duration_s() - (2.2 + (10.0 - 1.1))).abs() < 1e-12);
    let jerk_pattern: Vec<f64> = p
        .segments
        .iter()
        .map(|s| s.jerk.signum() * s.jerk.abs().min(1.0))
        .collect();
    assert_eq!(jerk_pattern, vec![1.0, 0.0, -1.0, 0.0, -1.0, 0.0, 1.0]);
    assert_eq!(p.sample(p.duration_s()).position, 10.0);
}

#[test]
fn zero_distance_from_rest_is_an_empty_profile() {
    let l = Limits::s_curve(1.0, 1.0, 1.0, 10.0, 10.0).unwrap();
    let p = Profile::to_position(State::at_rest(3.0), 3.0, 0.0, &l);
    assert_eq!(p.duration_s(), 0.0);
    assert_eq!(p.sample(0.5).position, 3.0);
}

#[test]
fn random_rest_to_rest_is_time_optimal_and_within_limits() {
    let mut rng = ChaCha8Rng::seed_from_u64(0x5EED_0001);
    for case in 0..CASES {
        let s_curve = case % 2 == 0;
        let l = random_limits(&mut rng, s_curve);
        let p0 = rng.random_range(-1e3..1e3);
        let dist = 10f64.powf(rng.random_range(-4.0..3.5)) * if rng.random_bool(0.5) { 1.0 } else { -1.0 };
        let p = Profile::to_position(State::at_rest(p0), p0 + dist, 0.0, &l);
        let ctx = format!("case {case}: {l:?} from {p0} by {dist}");
        let t = analytic_rest_to_rest_s(dist.abs(), &l);
        assert!(
            (p.duration_s() - t).abs() <= 1e-9 * t,
            "{ctx}: duration {} vs analytic {t}",
            p.duration_s()
        );
        assert!((p.sample(p.duration_s()).position - (p0 + dist)).abs() <= 1e-9, "{ctx}");
        assert_within_limits(&p, &l, &ctx);
        assert_continuous_end(&p, &ctx);
    }
}

fn random_start(rng: &mut ChaCha8Rng, l: &Limits) -> State {
    // An acceleration the limits can hold, and a velocity from which the
    // acceleration can be brought to zero without exceeding v_max.
    let a_lim = match l.shape() {
        // Coasting the acceleration to zero must leave room under v_max.
        Shape::SCurve { accel_jerk, decel_jerk } => l
            .acceleration()
            .min(l.deceleration())
            .min((l.velocity() * accel_jerk.min(decel_jerk)).sqrt()),
        Shape::Trapezoidal => 0.0,
    };
    let a = if a_lim > 0.0 {
        rng.random_range(-a_lim..a_lim)
    } else {
        0.0
    };
    let coast = match l.shape() {
        Shape::SCurve { accel_jerk, decel_jerk } => a * a / (2.0 * accel_jerk.min(decel_jerk)),
        Shape::Trapezoidal => 0.0,
    };
    let v_room = (l.velocity() - coast).max(0.0);
    State {
        position: rng.random_range(-100.0..100.0),
        velocity: rng.random_range(-v_room..=v_room),
        acceleration: a,
    }
}

#[test]
fn random_moving_starts_reach_target_within_limits() {
    let mut rng = ChaCha8Rng::seed_from_u64(0x5EED_0002);
    for case in 0..CASES {
        let l = random_limits(&mut rng, case % 3 != 0);
        let start = random_start(&mut rng, &l);
        let target = start.position + rng.random_range(-1.0..1.0) * 10f64.powf(rng.random_range(-3.0..3.0));
        let p = Profile::to_position(start, target, 0.0, &l);
        let ctx = format!("case {case}: {l:?} {start:?} -> {target}");
        assert_eq!(p.sample(0.0).position, start.position, "{ctx}");
        let end = p.sample(p.duration_s());
        assert!((end.position - target).abs() <= 1e-9, "{ctx}");
        assert_eq!((end.velocity, end.acceleration), (0.0, 0.0), "{ctx}");
        assert_within_limits(&p, &l, &ctx);
        assert_continuous_end(&p, &ctx);
        // Continuous velocity (and acceleration for S-curves) at every joint.
        for w in p.segments.windows(2) {
            let e = w[0].at(w[0].duration_s);
            let tol = 1e-9 * (1.0 + l.velocity());
            assert!((e.velocity - w[1].start.velocity).abs() <= tol, "{ctx}");
            if jerks(&l).is_some() {
                assert!(
                    (e.acceleration - w[1].start.acceleration).abs() <= 1e-9 * (1.0 + l.acceleration()),
                    "{ctx}"
                );
            }
        }
    }
}

#[test]
fn random_blends_end_at_the_asked_speed_when_reachable() {
    let mut rng = ChaCha8Rng::seed_from_u64(0x5EED_0003);
    for case in 0..CASES {
        let l = random_limits(&mut rng, case % 2 == 0);
        let start = State::at_rest(0.0);
        let vf = rng.random_range(0.0..l.velocity());
        let target = 10f64.powf(rng.random_range(-3.0..3.0));
        let p = Profile::to_position(start, target, vf, &l);
        let ctx = format!("case {case}: {l:?} -> {target} at {vf}");
        let f = p.final_state();
        assert_eq!(f.position, target, "{ctx}");
        assert!(
            f.velocity <= vf * (1.0 + 1e-12) && f.velocity >= 0.0,
            "{ctx}: {}",
            f.velocity
        );
        // Reachable when a straight acceleration ramp to vf fits.
        let ramp = ramp::Ramp::new(0.0, 0.0, vf, &l);
        if ramp.distance() <= target * (1.0 - 1e-9) {
            assert!(
                (f.velocity - vf).abs() <= 1e-9 * (1.0 + vf),
                "{ctx}: reached {}",
                f.velocity
            );
        }
        assert_within_limits(&p, &l, &ctx);
        assert_continuous_end(&p, &ctx);
        // After the end the position keeps moving at the final speed.
        let later = p.sample(p.duration_s() + 0.5);
        assert!((later.position - (target + 0.5 * f.velocity)).abs() <= 1e-9 * (1.0 + target));
    }
}

#[test]
fn overshooting_start_brakes_and_comes_back() {
    let l = Limits::s_curve(10.0, 5.0, 5.0, 50.0, 50.0).unwrap();
    let start = State {
        position: 0.0,
        velocity: 10.0,
        acceleration: 0.0,
    };
    let p = Profile::to_position(start, 1.0, 0.0, &l);
    let min_v = samples(&p)
        .iter()
        .map(|(_, s)| s.velocity)
        .fold(f64::INFINITY, f64::min);
    assert!(min_v < 0.0, "must reverse");
    assert!((p.sample(p.duration_s()).position - 1.0).abs() < 1e-12);
    assert_within_limits(&p, &l, "overshoot");
    assert_continuous_end(&p, "overshoot");
}

#[test]
fn velocity_ramp_stops_and_jogs() {
    let l = Limits::s_curve(10.0, 5.0, 4.0, 50.0, 40.0).unwrap();
    let start = State {
        position: 1.0,
        velocity: 8.0,
        acceleration: 1.0,
    };
    let stop = Profile::to_velocity(start, 0.0, &l);
    let d = stopping_distance(start, &l);
    assert!((stop.final_state().position - (1.0 + d)).abs() < 1e-12);
    assert_eq!(stop.final_state().velocity, 0.0);
    let jog = Profile::to_velocity(State::at_rest(0.0), -25.0, &l);
    assert_eq!(jog.final_state().velocity, -10.0, "clamped to the limit");
    let s = jog.sample(jog.duration_s() + 2.0);
    assert!((s.velocity + 10.0).abs() < 1e-12);
}

#[test]
fn bad_limits_and_targets_never_give_nan() {
    for bad in [0.0, -1.0, f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        assert!(Limits::trapezoidal(bad, 1.0, 1.0).is_err());
        assert!(Limits::trapezoidal(1.0, bad, 1.0).is_err());
        assert!(Limits::trapezoidal(1.0, 1.0, bad).is_err());
        assert!(Limits::s_curve(1.0, 1.0, 1.0, bad, 1.0).is_err());
        assert!(Limits::s_curve(1.0, 1.0, 1.0, 1.0, bad).is_err());
    }
    let l = Limits::s_curve(1.0, 1.0, 1.0, 10.0, 10.0).unwrap();
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        let p = Profile::to_position(State::at_rest(2.0), bad, 0.0, &l);
        assert_eq!(p.sample(1.0).position, 2.0);
        let p = Profile::to_position(State::at_rest(2.0), 3.0, bad, &l);
        assert!(p.sample(0.7).position.is_finite());
        let p = Profile::to_velocity(State::at_rest(2.0), bad, &l);
        assert!(p.sample(0.7).position.is_finite());
        let s = State {
            velocity: bad,
            acceleration: bad,
            position: 0.0,
        };
        assert!(Profile::to_position(s, 1.0, 0.0, &l).sample(0.3).position.is_finite());
    }
    assert!(
        Profile::to_position(State::at_rest(0.0), 1.0, 0.0, &l)
            .sample(f64::NAN)
            .position
            .is_finite()
    );
}

#[test]
fn replanning_mid_motion_is_seamless() {
    let l = Limits::s_curve(5.0, 10.0, 8.0, 100.0, 80.0).unwrap();
    let first = Profile::to_position(State::at_rest(0.0), 20.0, 0.0, &l);
    let mid = first.sample(0.7).state();
    let second = Profile::to_position(mid, 3.0, 0.0, &l);
    let s0 = second.sample(0.0);
    assert_eq!(
        (s0.position, s0.velocity, s0.acceleration),
        (mid.position, mid.velocity, mid.acceleration)
    );
    assert!((second.sample(second.duration_s()).position - 3.0).abs() < 1e-12);
    assert_within_limits(&second, &l, "replan");
}

#[test]
fn identical_inputs_give_bit_identical_profiles() {
    let l = Limits::s_curve(3.3, 7.1, 5.9, 91.0, 47.0).unwrap();
    let start = State {
        position: 1.25,
        velocity: -0.7,
        acceleration: 2.0,
    };
    let a = Profile::to_position(start, 17.0, 0.4, &l);
    let b = Profile::to_position(start, 17.0, 0.4, &l);
    for k in 0..1000 {
        let t = f64::from(k) * 0.01;
        assert_eq!(a.sample(t).position.to_bits(), b.sample(t).position.to_bits());
    }
}

/// The closed-form distances the peak search uses equal the built ramps'
/// integrated distances, and their slopes the ramps' difference quotients.
#[test]
fn closed_form_ramp_distances_match_the_built_ramps() {
    let mut rng = ChaCha8Rng::seed_from_u64(77);
    for case in 0..CASES {
        let l = random_limits(&mut rng, case % 4 != 0);
        let (v_max, a_max) = (l.velocity(), l.acceleration().max(l.deceleration()));
        let v = v_max * rng.random_range(-1.2..1.2);
        let a = if jerks(&l).is_some() {
            a_max * rng.random_range(-1.2..1.2)
        } else {
            0.0
        };
        let vt = v_max * rng.random_range(-1.0..1.0);
        let ctx = format!("case {case}: {l:?} from v {v} a {a} to {vt}");
        let course = ramp::Course::new(v, a, vt, &l);
        let [closed, slope, curvature] = course.reach(v, a, vt);
        let built = ramp::Ramp::new(v, a, vt, &l).distance();
        let scale = v_max * v_max / a_max + v.abs() * v_max / a_max + built.abs();
        // Near the coast velocity the distance is steep in vt (the slope
        // grows without bound): allow the rounding of vt times the slope.
        let steepest = slope.abs().max(course.tail.reach(vt)[1].abs());
        let conditioning = 1e-14 * steepest * (vt.abs() + v_max);
        assert!(
            (closed - built).abs() <= 1e-12 * scale + conditioning,
            "{ctx}: {closed} vs {built}"
        );
        // The slope against a central difference, where the course keeps
        // its shape (an easing varies with vt, smoothly).
        let tail = course.tail;
        let tail_free = tail.v + tail.a * tail.a.abs() / (2.0 * jerks(&l).map_or(f64::INFINITY, |j| j.0.min(j.1)));
        // An easing ends the tail's acceleration right at vt, where the
        // tail's distance has a square-root kink that amplifies rounding:
        // a wider step there.
        let h = if course.eased.is_some() {
            1e-4 * v_max
        } else {
            1e-6 * (vt - tail_free).abs().min(v_max)
        };
        let shape = |x: f64| {
            let c = ramp::Course::new(v, a, x, &l);
            (c.lead.is_some(), c.tail.a_max, c.tail.jerk, c.eased.is_some())
        };
        if h > 0.0 && shape(vt - h) == shape(vt) && shape(vt + h) == shape(vt) {
            let quotient = (ramp::ramp_distance(v, a, vt + h, &l) - ramp::ramp_distance(v, a, vt - h, &l)) / (2.0 * h);
            assert!(
                (quotient - slope).abs() <= 1e-4 * (slope.abs() + v_max / a_max),
                "{ctx}: slope {slope} vs {quotient}"
            );
            if course.eased.is_none() {
                let reach = |x: f64| course.tail.reach(x);
                let second = (reach(vt + h)[1] - reach(vt - h)[1]) / (2.0 * h);
                assert!(
                    (second - curvature).abs() <= 1e-4 * (curvature.abs() + 1.0 / a_max),
                    "{ctx}: curvature {curvature} vs {second}"
                );
            }
        }
        // The settling ramp from (vp, 0) down to vt's magnitude.
        let (vp, vf) = (v.abs().max(vt.abs()), v.abs().min(vt.abs()));
        let (a_lim, jerk) = ramp::ramp_limits(vp, vf, &l);
        let settle = ramp::Settle::new(vf, a_lim, jerk);
        let [d2, s2, c2] = settle.reach(vp);
        let built2 = ramp::Ramp::new(vp, 0.0, vf, &l).distance();
        assert!((d2 - built2).abs() <= 1e-12 * scale, "{ctx}: settle {d2} vs {built2}");
        let h = 1e-6 * (vp - vf);
        if h > 0.0 {
            let q2 = (settle.reach(vp + h)[0] - settle.reach(vp - h)[0]) / (2.0 * h);
            assert!(
                (q2 - s2).abs() <= 1e-5 * (s2.abs() + v_max / a_max),
                "{ctx}: settle slope {s2} vs {q2}"
            );
            let c = (settle.reach(vp + h)[1] - settle.reach(vp - h)[1]) / (2.0 * h);
            assert!(
                (c - c2).abs() <= 1e-4 * (c2.abs() + 1.0 / a_max),
                "{ctx}: settle curvature {c2} vs {c}"
            );
        }
    }
}

/// The softened brake's closed-form distance (a ramp from a virtual start
/// less its virtual phase) equals the easing phase plus the general ramp,
/// and its slope the difference quotient.
#[test]
fn softened_brake_distance_matches_the_general_ramp() {
    let mut rng = ChaCha8Rng::seed_from_u64(78);
    let mut checked = 0;
    for case in 0..CASES {
        let l = random_limits(&mut rng, true);
        let Some((_, jd)) = jerks(&l) else { continue };
        let d = l.deceleration();
        let v0 = l.velocity() * rng.random_range(0.1..1.0);
        let a0 = -d * rng.random_range(0.0..1.0);
        let a1 = a0 * rng.random_range(0.0..1.0);
        // The shape's precondition: the coast speed stays above vf.
        let coast = v0 - a0 * a0 / (2.0 * jd);
        if coast <= 0.0 {
            continue;
        }
        let vf = coast * rng.random_range(0.0..1.0);
        let ctx = format!("case {case}: {l:?} v0 {v0} a0 {a0} a1 {a1} vf {vf}");
        let [excess, slope, _] = softened_excess(v0, a0, a1, vf, 0.0, &l);
        let t = (a1 - a0) / jd;
        let v1 = v0 + (a1 * a1 - a0 * a0) / (2.0 * jd);
        let general = t * (v0 + t * (a0 / 2.0 + t * jd / 6.0)) + ramp::Ramp::new(v1, a1, vf, &l).distance();
        let scale = v0 * v0 / d + v0 * d / jd;
        assert!(
            (excess - general).abs() <= 1e-11 * scale,
            "{ctx}: {excess} vs {general}"
        );
        let h = 1e-6 * d;
        if a1 - h >= a0 && a1 + h <= 0.0 {
            let quotient = (softened_excess(v0, a0, a1 + h, vf, 0.0, &l)[0]
                - softened_excess(v0, a0, a1 - h, vf, 0.0, &l)[0])
                / (2.0 * h);
            assert!(
                (quotient - slope).abs() <= 1e-4 * (slope.abs() + v0 / jd),
                "{ctx}: slope {slope} vs {quotient}"
            );
            checked += 1;
        }
    }
    assert!(checked > CASES / 4, "only {checked} slopes checked");
}
