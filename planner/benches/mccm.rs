//! MCCM speed: planning time per move (verification, arc geometry and the
//! S-curve path profile) and interpolation time per coarse update of a
//! 3-axis coordinate system running an arc through the motion task.

#![allow(missing_docs)]

use criterion::{Criterion, criterion_group, criterion_main};
use planner::axis::{AxisConfig, AxisKind};
use planner::coord::{CoordMoveInputs, CoordinateSystem, CoordinateSystemConfig, MoveContext};
use planner::dynamics::MoveDynamics;
use planner::mccm::{MccmInputs, mccm};
use planner::task::{CoordCall, MotionTask};
use std::hint::black_box;

fn config() -> CoordinateSystemConfig {
    CoordinateSystemConfig {
        axis_count: 3,
        primary_axes: 3,
        max_speed: 500.0,
        max_accel: 5000.0,
        max_decel: 5000.0,
        ..CoordinateSystemConfig::new("CS")
    }
}

fn arc_inputs() -> MccmInputs {
    MccmInputs {
        common: CoordMoveInputs {
            position: vec![0.0, 100.0, 20.0],
            dynamics: MoveDynamics {
                speed: 200.0,
                accel_rate: 2000.0,
                decel_rate: 2000.0,
                profile: 1,
                accel_jerk: 100.0,
                decel_jerk: 100.0,
                jerk_units: 2,
                ..CoordMoveInputs::default().dynamics
            },
            ..Default::default()
        },
        circle_type: 0,
        via_center_radius: vec![70.0, 70.0, 10.0],
        direction: 0,
    }
}

fn planning(c: &mut Criterion) {
    let system = CoordinateSystem::new(config()).expect("valid system");
    let inputs = arc_inputs();
    let ctx = MoveContext {
        system: &system,
        axis_max_decel: &[1.0; 3],
        start: &[100.0, 0.0, 0.0],
        has_master: false,
    };
    c.bench_function("mccm_plan_3d_via_s_curve", |b| {
        b.iter(|| mccm(black_box(&inputs), black_box(&ctx)))
    });
}

fn interpolation(c: &mut Criterion) {
    let mut task = MotionTask::new(0.001).expect("valid period");
    let axes: Vec<_> = ["X", "Y", "Z"]
        .iter()
        .map(|n| {
            task.add_axis(AxisConfig::new(*n, AxisKind::Linear), 0.0)
                .expect("valid axis")
        })
        .collect();
    let cs = task.add_coordinate_system(config(), &axes).expect("valid system");
    let mut full = arc_inputs();
    full.circle_type = 3;
    full.via_center_radius = vec![-50.0, 0.0, 0.0];
    full.common.position = vec![-50.0, 50.0, 0.0];
    full.direction = 2;
    let call = CoordCall::Mccm(full);
    let mc = task.add_coord_instruction("MC", cs, call.clone());
    c.bench_function("mccm_interpolate_per_coarse_update", |b| {
        b.iter(|| {
            if !task.coord_status(cs).motion {
                task.set_coord_rung(mc, false);
                task.update();
                task.set_coord_instruction(mc, true, call.clone());
            }
            task.update();
            black_box(task.axis_state(axes[0]).command_position)
        })
    });
}

criterion_group!(benches, planning, interpolation);
criterion_main!(benches);
