//! Planner speed: S-curve planning time per profile, and per-axis
//! interpolation time per coarse update (sampling plus the MC_MoveModulo
//! executor's bookkeeping).

#![allow(missing_docs)]

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

criterion_group!(benches, planning, coarse_update);
criterion_main!(benches);
