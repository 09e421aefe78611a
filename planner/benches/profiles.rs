//! Planner speed: S-curve planning time per profile, and per-axis
//! interpolation time per coarse update (sampling plus the MC_MoveModulo
//! executor's bookkeeping).

#![allow(missing_docs)]

#[path = "../tests/reference/cases.rs"]
#[allow(
    dead_code,
    reason = "the test checks the final velocity's sign; the bench only plans"
)]
mod cases;

use criterion::{Criterion, criterion_group, criterion_main};
use planner::axis::{AxisConfig, AxisKind};
use planner::modulo::{McBufferMode, McDirection, MoveModuloInputs};
use planner::profile::{Limits, Profile, State};
use planner::task::MotionTask;
use std::hint::black_box;

fn planning(c: &mut Criterion) {
    let limits = Limits::s_curve(720.0, 3600.0, 3000.0, 36000.0, 30000.0).expect("valid limits");
    c.bench_function("s_curve_plan_rest_to_rest", |b| {
        b.iter(|| Profile::to_position(black_box(State::at_rest(0.0)), black_box(123.4), 0.0, &limits))
    });
    let moving = State {
        position: 10.0,
        velocity: 300.0,
        acceleration: -500.0,
    };
    c.bench_function("s_curve_plan_moving_start_with_blend", |b| {
        b.iter(|| Profile::to_position(black_box(moving), black_box(400.0), black_box(200.0), &limits))
    });
    let trapezoid = Limits::trapezoidal(720.0, 3600.0, 3000.0).expect("valid limits");
    c.bench_function("trapezoid_plan_rest_to_rest", |b| {
        b.iter(|| Profile::to_position(black_box(State::at_rest(0.0)), black_box(123.4), 0.0, &trapezoid))
    });
    let profile = Profile::to_position(State::at_rest(0.0), 123.4, 0.0, &limits);
    let mut t = 0.0;
    c.bench_function("s_curve_sample", |b| {
        b.iter(|| {
            t = (t + 0.001) % profile.duration_s();
            profile.sample(black_box(t))
        })
    });
}

/// 10,000 seeded state-to-state cases (moving starts within the limits,
/// asymmetric jerks, targets near the stopping point or anywhere).
fn state_to_state_cases() -> Vec<(State, f64, f64, Limits)> {
    use rand::{Rng, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(14);
    (0..10_000)
        .map(|_| {
            let v = 10f64.powf(rng.random_range(-1.0..3.0));
            let a = v * 10f64.powf(rng.random_range(-1.0..1.5));
            let d = a * 10f64.powf(rng.random_range(-0.5..0.5));
            let ja = a * a / v * 10f64.powf(rng.random_range(-0.5..2.0));
            let jd = ja * 10f64.powf(rng.random_range(-0.7..0.7));
            let limits = Limits::s_curve(v, a, d, ja, jd).expect("valid limits");
            let start = State {
                position: 0.0,
                velocity: v * rng.random_range(-0.9..0.9),
                acceleration: a.min(d) * rng.random_range(-0.3..0.3),
            };
            let stop = planner::profile::stopping_distance(start, &limits);
            let target = if rng.random_bool(0.5) {
                stop * (1.0 + rng.random_range(-0.1..0.1))
            } else {
                v * v / a * rng.random_range(-5.0..5.0)
            };
            let vf = if rng.random_bool(0.25) {
                v * rng.random_range(0.0..1.0)
            } else {
                0.0
            };
            (start, target, vf, limits)
        })
        .collect()
}

fn state_to_state(c: &mut Criterion) {
    mean_and_worst(c, "s_curve_plan_state_to_state_10k_cases", &state_to_state_cases());
    // The same measurement on the cases Ruckig is timed on
    // (`tests/reference/ruckig_timing.py`): one accel limit and one jerk.
    mean_and_worst(c, "s_curve_plan_state_to_state_ruckig_table_10k", &ruckig_table_cases());
}

/// The first 10,000 cases of the Ruckig table that Ruckig solved (start,
/// target, final speed, limits): the cases `ruckig_timing.py` times Ruckig
/// on.
fn ruckig_table_cases() -> Vec<(State, f64, f64, Limits)> {
    let table = include_str!("../tests/reference/ruckig_state_to_state.txt");
    cases::rows(table)
        .take(10_000)
        .filter_map(|(case, solved)| {
            let limits = Limits::s_curve(case.v, case.a, case.a, case.j, case.j).expect("valid limits");
            solved.map(|s| (case.start, s.target, case.vf, limits))
        })
        .collect()
}

/// Mean (criterion times the whole set; divide by its size) and worst
/// (each case timed alone in each of 20 passes over the set, its best
/// time kept so that a preempted run does not count, then the slowest
/// case) planning time over `cases`.
fn mean_and_worst(c: &mut Criterion, name: &str, cases: &[(State, f64, f64, Limits)]) {
    c.bench_function(name, |b| {
        b.iter(|| {
            for (start, target, vf, limits) in cases {
                black_box(Profile::to_position(black_box(*start), *target, *vf, limits));
            }
        })
    });
    let mut best_ns = vec![u128::MAX; cases.len()];
    for _ in 0..20 {
        for ((start, target, vf, limits), best) in cases.iter().zip(&mut best_ns) {
            let t = std::time::Instant::now();
            black_box(Profile::to_position(black_box(*start), *target, *vf, limits));
            *best = (*best).min(t.elapsed().as_nanos());
        }
    }
    let worst_ns = best_ns.into_iter().max().unwrap_or(0);
    println!("{name}: {} cases, worst case {worst_ns} ns", cases.len());
}

fn coarse_update(c: &mut Criterion) {
    // 16 modulo axes, each running a long move: time per update / 16 is the
    // per-axis interpolation cost.
    let mut task = MotionTask::new(0.004).expect("valid period");
    for i in 0..16 {
        let config = AxisConfig {
            modulo_period: Some(360.0),
            max_velocity: 720.0,
            max_acceleration: 3600.0,
            max_deceleration: 3600.0,
            max_jerk: 36000.0,
            ..AxisConfig::new(format!("A{i}"), AxisKind::Rotary)
        };
        let axis = task.add_axis(config, 0.0).expect("valid axis");
        let fb = task.add_move_modulo(format!("M{i}"), axis);
        let inputs = MoveModuloInputs {
            execute: true,
            position: 1e12,
            velocity: 700.0,
            direction: McDirection::Positive,
            buffer_mode: McBufferMode::Aborting,
            ..Default::default()
        };
        task.set_move_modulo_inputs(fb, inputs);
    }
    c.bench_function("coarse_update_16_axes", |b| b.iter(|| task.update()));
}

criterion_group!(benches, planning, state_to_state, coarse_update);
criterion_main!(benches);
