//! State-to-state planning against a time-optimal reference, and the limits
//! every plan holds.
//!
//! * `ruckig_table`: 100,000 cases whose limits and start states come from a
//!   SplitMix64 stream that `reference/ruckig_state_to_state.py` repeats bit
//!   for bit, and whose targets lie near the stopping point, beyond it or
//!   anywhere; the table holds Ruckig 0.19.4's time-optimal duration for each.
//!   Every plan must match it within 1e-9 relative and hold the limits.
//! * `ruckig_asymmetric_accel_table`: 100,000 cases with different accel
//!   and decel limits (and one jerk, as Ruckig has) on moves that start at
//!   rest or moving forwards and never reverse, where Ruckig's limits by the
//!   sign of the acceleration are the planner's by whether the speed rises
//!   or falls; `reference/ruckig_asymmetric_accel.txt` holds Ruckig's
//!   durations, matched within 1e-9 relative.
//! * `asymmetric_jerk_table`: 100,000 cases whose accel and decel limits
//!   and jerks all differ, from rest or moving forwards with no
//!   acceleration or one up to the limit, to targets from just beyond the
//!   ramps through the lowest peak to far away — the moves whose
//!   time-optimal shape is known in closed form; `reference/asymmetric_jerk.txt` holds the optimum's
//!   duration found by 30-digit bisection, matched within 1e-9 relative.
//! * `asymmetric_random_starts`: 100,000 seeded cases with accel and decel
//!   limits and jerks that differ (up to 16×), start velocities and
//!   accelerations inside and beyond the limits and targets near the stopping
//!   point. No NaN, the target reached, and every limit held wherever the
//!   start state allows it: a phase that raises the speed within the accel
//!   limits, one that lowers it within the decel limits, the speed within
//!   the maximum (or, from a start that cannot keep it, no higher than
//!   ending the acceleration at once carries it: with the jerk of its sense,
//!   or the smaller jerk for an acceleration beyond its limit).

#[path = "reference/cases.rs"]
mod cases;

use cases::SplitMix64;
use planner::profile::{Limits, Profile, Sample, State};

/// The limits a phase must keep: accel limits while it raises the speed,
/// decel limits while it lowers it, the smaller of both where the velocity
/// changes sign inside it.
fn phase_limits(t0: f64, dur: f64, s: Sample, p: &Profile, l: &Limits) -> (f64, f64) {
    let (ja, jd) = match l.shape() {
        planner::profile::Shape::SCurve { accel_jerk, decel_jerk } => (accel_jerk, decel_jerk),
        planner::profile::Shape::Trapezoidal => (f64::INFINITY, f64::INFINITY),
    };
    let mid = p.sample(t0 + dur / 2.0);
    let end = p.sample(t0 + dur);
    let crosses = s.velocity * end.velocity < 0.0 && s.velocity.abs().min(end.velocity.abs()) > 1e-9 * l.velocity();
    if crosses {
        return (l.acceleration().min(l.deceleration()), ja.min(jd));
    }
    if mid.velocity * mid.acceleration >= 0.0 {
        (l.acceleration(), ja)
    } else {
        (l.deceleration(), jd)
    }
}

/// Checks every limit on every phase of `p`. Returns a description of the
/// first violation.
fn limits_held(p: &Profile, l: &Limits, v_cap: f64) -> Result<(), String> {
    let tol = 1e-9;
    let peak = p.peak_speed();
    if peak > v_cap * (1.0 + tol) {
        return Err(format!("peak speed {peak} > {v_cap}"));
    }
    for (t0, dur, s) in p.phases() {
        let (a_max, j_max) = phase_limits(t0, dur, s, p, l);
        let end = p.sample(t0 + dur);
        let a_peak = s.acceleration.abs().max(end.acceleration.abs());
        if a_peak > a_max * (1.0 + tol) && !(t0 == 0.0 && a_peak <= s.acceleration.abs()) {
            return Err(format!("|a| {a_peak} > {a_max} in the phase at {t0} s"));
        }
        // A crumb (a phase whose jerk moves the acceleration by less than a
        // millionth of its limit, left where a velocity lands 1e-15 off its
        // aim) has no jerk that matters.
        let crumb = dur * s.jerk.abs() < 1e-6 * a_max;
        if s.jerk.abs() > j_max * (1.0 + tol) && !crumb {
            return Err(format!("|j| {} > {j_max} in the phase at {t0} s", s.jerk));
        }
    }
    Ok(())
}

/// The profile's own end (integrated through its phases) lands on the target.
fn reaches_target(p: &Profile, target: f64, ctx: &str) {
    let d = p.duration_s();
    assert!(d.is_finite() && d >= 0.0, "{ctx}: duration {d}");
    let end = match p.phases().last() {
        Some((_, t, s)) => s.position + t * (s.velocity + t * (s.acceleration / 2.0 + t * s.jerk / 6.0)),
        None => p.start_state().position,
    };
    // Rounding grows with the farthest excursion (a profile that overshoots
    // and comes back cancels large terms).
    let start = p.start_state().position;
    let reach = p
        .phases()
        .map(|(_, _, s)| (s.position - start).abs())
        .fold((target - start).abs(), f64::max);
    let scale = 1e-9 * reach + 1e-13 * (1.0 + target.abs() + start.abs());
    assert!((end - target).abs() <= scale, "{ctx}: ends at {end}, target {target}");
    assert_eq!(p.final_state().position, target, "{ctx}");
}

/// Durations compared with a reference table: how many, the worst relative
/// difference, the cases where the reference is the slower one, and the
/// first failures.
#[derive(Default)]
struct Tally {
    compared: usize,
    worst: f64,
    slower_reference: Vec<usize>,
    failures: Vec<String>,
}

impl Tally {
    /// Checks case `i`'s plan: the target reached with speed `vf`, every
    /// limit held, the duration within 1e-9 of `reference`.
    fn check(&mut self, i: usize, p: &Profile, limits: &Limits, (target, vf): (f64, f64), reference: f64, ctx: &str) {
        reaches_target(p, target, ctx);
        assert_eq!(p.final_state().velocity, vf, "{ctx}");
        if let Err(e) = limits_held(p, limits, limits.velocity()) {
            panic!("{ctx}: {e}");
        }
        let rel = (p.duration_s() - reference).abs() / reference.max(1e-300);
        self.compared += 1;
        if rel > 1e-9 && p.duration_s() < reference {
            // A profile that holds every limit and reaches the target sooner
            // than the reference proves the reference was not time-optimal
            // (Ruckig 0.19.4 returns such profiles for a few fast starts
            // with high jerk); counted, and bounded by `finish`.
            self.slower_reference.push(i);
            return;
        }
        self.worst = self.worst.max(rel);
        if rel > 1e-9 && self.failures.len() < 20 {
            let d = p.duration_s();
            self.failures
                .push(format!("{ctx}: {d} s, reference {reference} s ({rel:.2e})"));
        }
    }

    /// At least `min_compared` cases compared, at most `max_slower` where
    /// the reference is slower, no failure.
    fn finish(self, table: &str, min_compared: usize, max_slower: usize) {
        let (compared, worst, slower) = (self.compared, self.worst, self.slower_reference.len());
        eprintln!(
            "{table}: {compared} compared, {slower} where the reference is slower, worst of the rest {worst:.1e}"
        );
        assert!(compared >= min_compared, "{compared} cases compared");
        assert!(
            slower <= max_slower,
            "{slower} cases where the reference is slower: {:?}",
            self.slower_reference
        );
        assert!(
            self.failures.is_empty(),
            "worst {worst:.2e}; {} …\n{}",
            self.failures.len(),
            self.failures.join("\n")
        );
    }
}

#[test]
fn ruckig_table() {
    let table = include_str!("reference/ruckig_state_to_state.txt");
    let mut tally = Tally::default();
    for (i, (case, solved)) in cases::rows(table).enumerate() {
        let Some(cases::Solved {
            target,
            sign,
            duration_s: duration,
        }) = solved
        else {
            continue;
        };
        let limits = Limits::s_curve(case.v, case.a, case.a, case.j, case.j).unwrap();
        let p = Profile::to_position(case.start, target, case.vf, &limits);
        let ctx = format!(
            "case {i}: v {} a {} j {} start {:?} target {target} vf {sign}{}",
            case.v, case.a, case.j, case.start, case.vf
        );
        if std::env::var("CASE").is_ok_and(|c| c == i.to_string()) {
            eprintln!("{ctx}");
            for ph in p.phases() {
                eprintln!("  {ph:?}");
            }
        }
        let expected_vf = match sign {
            "+" => case.vf,
            "-" => -case.vf,
            _ => 0.0,
        };
        tally.check(i, &p, &limits, (target, expected_vf), duration, &ctx);
    }
    tally.finish("Ruckig table", 99_000, 20);
}

/// One case of the asymmetric-acceleration table: the same draws, in the
/// same order, as `draw_asymmetric` in the generator.
fn draw_asymmetric(rng: &mut SplitMix64) -> (Limits, State, f64) {
    let v = rng.scale(-4, 10);
    let a = v * rng.scale(-3, 5);
    let d = a * rng.scale(-2, 2);
    let j = a * a / v * rng.scale(-2, 7);
    let p0 = (2.0 * rng.unit() - 1.0) * 100.0;
    let kind = rng.below(4);
    let v0 = if kind == 0 { 0.0 } else { v * rng.unit() };
    let a0 = if kind <= 1 { 0.0 } else { (a + d) * rng.unit() - d };
    let a0 = cases::keeping(v0, a0, j, 0.0..=v);
    let vf = if rng.below(4) == 0 { v * rng.unit() } else { 0.0 };
    // The generator's target recipe (k, u) is consumed here too; the
    // table stores the target.
    let _ = (rng.below(21), rng.unit());
    let limits = Limits::s_curve(v, a, d, j, j).unwrap();
    let start = State {
        position: p0,
        velocity: v0,
        acceleration: a0,
    };
    (limits, start, vf)
}

/// Different accel and decel limits (equal jerks: Ruckig has one) on moves
/// that never reverse, where Ruckig's sign-of-acceleration limits are the
/// planner's speed-rising/falling limits: durations within 1e-9.
#[test]
fn ruckig_asymmetric_accel_table() {
    let table = include_str!("reference/ruckig_asymmetric_accel.txt");
    let mut rng = SplitMix64(0x5EED_A014);
    let mut tally = Tally::default();
    for (i, line) in table.lines().filter(|l| !l.starts_with('#')).enumerate() {
        let (limits, start, vf) = draw_asymmetric(&mut rng);
        let (target, duration) = line.split_once(' ').unwrap();
        if duration == "x" {
            continue;
        }
        let target: f64 = target.parse().unwrap();
        let p = Profile::to_position(start, target, vf, &limits);
        let ctx = format!("case {i}: {limits:?} start {start:?} target {target} vf {vf}");
        tally.check(i, &p, &limits, (target, vf), duration.parse().unwrap(), &ctx);
    }
    tally.finish("asymmetric accel table", 99_000, 20);
}

/// Different accel and decel limits and jerks (up to 16× apart) on moves
/// whose time-optimal shape is known in closed form — a start at rest or
/// moving forwards, with no acceleration or one up to the limit that the
/// speed limit lets end, a target at least as far as the ramps through the
/// lowest peak — against
/// `reference/asymmetric_jerk.txt` (the optimum found by 30-digit bisection
/// in `asymmetric_jerk_reference.py`): durations within 1e-9 relative.
#[test]
fn asymmetric_jerk_table() {
    let table = include_str!("reference/asymmetric_jerk.txt");
    let mut rng = SplitMix64(0x5EED_1E14);
    let mut tally = Tally::default();
    for (i, line) in table.lines().filter(|l| !l.starts_with('#')).enumerate() {
        // The generator's draws, in its order.
        let v = rng.scale(-4, 10);
        let a = v * rng.scale(-3, 5);
        let d = a * rng.scale(-2, 2);
        let ja = a * a / v * rng.scale(-2, 7);
        let jd = ja * rng.scale(-4, 3);
        let p0 = (2.0 * rng.unit() - 1.0) * 100.0;
        let kind = rng.below(4);
        let v0 = if kind == 0 { 0.0 } else { v * rng.unit() };
        let mut a0 = if kind >= 2 { a * rng.unit() } else { 0.0 };
        while v0 + a0 * a0 / (2.0 * ja) > v {
            a0 *= 0.5;
        }
        let vf = if rng.below(4) == 0 { v * rng.unit() } else { 0.0 };
        let _ = (rng.below(31), rng.unit());
        let (target, duration) = line.split_once(' ').unwrap();
        let target: f64 = target.parse().unwrap();
        let limits = Limits::s_curve(v, a, d, ja, jd).unwrap();
        let start = State {
            position: p0,
            velocity: v0,
            acceleration: a0,
        };
        let p = Profile::to_position(start, target, vf, &limits);
        let ctx = format!("case {i}: {limits:?} start {start:?} target {target} vf {vf}");
        tally.check(i, &p, &limits, (target, vf), duration.parse().unwrap(), &ctx);
    }
    // The reference is exact here: no case may be faster than it.
    tally.finish("asymmetric jerk table", 100_000, 0);
}

/// Where an axis that ends its acceleration as fast as the limits allow
/// coasts to, using the jerk of each phase: the decel jerk while the speed
/// falls, the accel jerk while it rises — so one that passes zero speed
/// first eases with the decel jerk down to zero speed, then ends what is
/// left of its acceleration with the accel jerk.
fn coast(v: f64, a: f64, ja: f64, jd: f64) -> f64 {
    let j = if v * a >= 0.0 { ja } else { jd };
    let free = v + a * a.abs() / (2.0 * j);
    if free * v < 0.0 {
        // a² − a_zero² = 2·jd·|v| on the way to zero speed.
        let a_zero_sq = a * a - 2.0 * jd * v.abs();
        (a_zero_sq / (2.0 * ja)).copysign(a)
    } else {
        free
    }
}

#[test]
fn asymmetric_random_starts() {
    let mut rng = SplitMix64(0xA5E_0014);
    let mut held_cases = 0;
    for i in 0..100_000 {
        let v = rng.scale(-4, 10);
        let a = v * rng.scale(-3, 5);
        let d = a * rng.scale(-2, 2);
        let ja = a * a / v * rng.scale(-2, 7);
        let jd = ja * rng.scale(-4, 3);
        let limits = Limits::s_curve(v, a, d, ja, jd).unwrap();
        // Start states inside and beyond the limits (up to 2× each).
        let v0 = v * (4.0 * rng.unit() - 2.0) * if rng.below(4) == 0 { 0.0 } else { 1.0 };
        let a0 = a.max(d) * (4.0 * rng.unit() - 2.0) * if rng.below(4) == 0 { 0.0 } else { 1.0 };
        let start = State {
            position: (2.0 * rng.unit() - 1.0) * 100.0,
            velocity: v0,
            acceleration: a0,
        };
        let stop = planner::profile::stopping_distance(start, &limits);
        let span = v * v / a.min(d) + a / ja.min(jd) * v;
        let side = if rng.below(2) == 0 { 1.0 } else { -1.0 };
        let target = match rng.below(3) {
            0 => start.position + stop + side * span * (1.0 + rng.unit()) * 2f64.powi(-(rng.below(30) as i32)),
            1 => start.position + stop,
            _ => start.position + side * span * 8.0 * rng.unit(),
        };
        let vf = if rng.below(4) == 0 { v * rng.unit() } else { 0.0 };
        let ctx = format!("case {i}: v {v} a {a} d {d} ja {ja} jd {jd} start {start:?} target {target} vf {vf}");
        let p = Profile::to_position(start, target, vf, &limits);
        reaches_target(&p, target, &ctx);
        for (t0, dur, s) in p.phases() {
            let finite = [t0, dur, s.position, s.velocity, s.acceleration, s.jerk];
            assert!(finite.iter().all(|x| x.is_finite()), "{ctx}: phase {finite:?}");
        }
        let rising = v0 * a0 >= 0.0;
        let accel_ok = a0.abs() <= if rising { a } else { d };
        let coast_v = coast(v0, a0, ja, jd);
        // An acceleration that carries the axis through zero speed must
        // first come within the far side's limit, before the speed is zero.
        let a_both = a.min(d);
        let crossing_ok = coast_v * v0 >= 0.0 || v0.abs() >= (a0 * a0 - a_both * a_both) / (2.0 * jd);
        if v0.abs() <= v && accel_ok && crossing_ok && coast_v.abs() <= v {
            held_cases += 1;
            if let Err(e) = limits_held(&p, &limits, v) {
                panic!("{ctx}: {e}");
            }
        } else if accel_ok {
            // The speed never goes higher than the start forces it to.
            let least = v.max(v0.abs()).max(coast_v.abs());
            assert!(
                p.peak_speed() <= least * (1.0 + 1e-9),
                "{ctx}: peak {} > {least}",
                p.peak_speed()
            );
        } else {
            // An acceleration beyond its limit is ended with the smaller
            // jerk at worst.
            let slow = coast(v0, a0, ja.min(jd), ja.min(jd));
            let least = v.max(v0.abs()).max(coast_v.abs()).max(slow.abs());
            assert!(
                p.peak_speed() <= least * (1.0 + 1e-9),
                "{ctx}: peak {} > {least}",
                p.peak_speed()
            );
        }
    }
    assert!(held_cases > 30_000, "{held_cases}");
}

/// v 10, a = d 100, accel jerk 10,000, decel jerk 1,000, and a state
/// moving at `velocity` with `acceleration`.
fn decel_jerk_tenth(velocity: f64, acceleration: f64) -> (Limits, State) {
    let limits = Limits::s_curve(10.0, 100.0, 100.0, 10_000.0, 1_000.0).unwrap();
    let state = State {
        position: 0.0,
        velocity,
        acceleration,
    };
    (limits, state)
}

/// The example (limits above). A stop issued as the acceleration
/// starts to fall (v 9.5, a 100) peaks at the limit, not at 14.5 (where
/// ending the acceleration with the decel jerk would carry it).
#[test]
fn a_stop_while_accelerating_keeps_the_velocity_limit() {
    let (limits, start) = decel_jerk_tenth(9.5, 100.0);
    let stop = Profile::to_velocity(start, 0.0, &limits);
    assert!((stop.peak_speed() - 10.0).abs() < 1e-12, "{}", stop.peak_speed());
    limits_held(&stop, &limits, 10.0).unwrap();
    let halt = planner::profile::stopping_distance(start, &limits);
    let to_stop = Profile::to_position(start, halt, 0.0, &limits);
    assert!(to_stop.peak_speed() <= 10.0 + 1e-12);
    // From rest, the whole move: the accel ramp ends at exactly v_max.
    let full = Profile::to_position(State::at_rest(0.0), 100.0, 0.0, &limits);
    assert!((full.peak_speed() - 10.0).abs() < 1e-12);
}

/// The reversal: decelerating towards zero speed (v −98.9, a
/// +243.1) to a target just behind with a final speed the other way. Ending
/// the acceleration with the decel jerk (24.1) past zero speed peaks at 4.07
/// × v_max; with the accel jerk (112.7) once the speed rises it stays within.
#[test]
fn a_reversal_ends_its_acceleration_with_the_accel_jerk() {
    let limits = Limits::s_curve(276.2, 270.4, 872.5, 112.7, 24.1).unwrap();
    let start = State {
        position: 78.401,
        velocity: -98.9,
        acceleration: 243.1,
    };
    let p = Profile::to_position(start, 78.398, 104.8, &limits);
    reaches_target(&p, 78.398, "reversal");
    assert!(coast(start.velocity, start.acceleration, 112.7, 24.1) < 276.2);
    assert!(p.peak_speed() <= 276.2 * (1.0 + 1e-12), "peak {}", p.peak_speed());
    limits_held(&p, &limits, 276.2).unwrap();
}

/// `Profile::overshoot`: a plan that must pass its target (it lies behind
/// where the axis can stop) or its speed limit (the start cannot keep it)
/// says so, and `overshoot_at` is true exactly while it is past the target
/// or above the limit; a plan that keeps its limits never says so.
#[test]
fn overshoots_are_reported_while_they_last() {
    let (limits, moving) = decel_jerk_tenth(10.0, 0.0);
    let stop = planner::profile::stopping_distance(moving, &limits);
    let p = Profile::to_position(moving, 0.5 * stop, 0.0, &limits);
    assert!(p.overshoot());
    let past: Vec<bool> = (0..=1000)
        .map(|k| p.duration_s() * f64::from(k) / 1000.0)
        .map(|t| p.overshoot_at(t) == (p.sample(t).position > 0.5 * stop) || t >= p.duration_s())
        .collect();
    assert!(past.iter().all(|&ok| ok));
    // Not holdable: at 9.9 with a = 100, ending the acceleration with the
    // accel jerk carries it to 10.4.
    let (_, fast) = decel_jerk_tenth(9.9, 100.0);
    let p = Profile::to_velocity(fast, 0.0, &limits);
    assert!(p.overshoot() && p.overshoot_at(0.005) && !p.overshoot_at(p.duration_s() * 0.9));
    assert!((p.peak_speed() - 10.4).abs() < 1e-12, "the least the accel jerk allows");
    // Within the limits: no overshoot.
    let p = Profile::to_position(State::at_rest(0.0), 50.0, 0.0, &limits);
    assert!(!p.overshoot());
    let p = Profile::to_velocity(moving, 0.0, &limits);
    assert!(!p.overshoot());
}
