//! Cam speed: MCCP calculation time for a 1,000-point cam (all cubic, and
//! mixed linear/cubic), and the position cam's cost per coarse update (a
//! master jogged by MAJ, one slave on a continuous 1,000-point cam, the whole
//! `MotionTask::update`, and the MAPC process alone).

#![allow(missing_docs)]

use criterion::{Criterion, criterion_group, criterion_main};
use planner::axis::{AxisConfig, AxisKind};
use planner::jog::MajOperands;
use planner::mapc::{CamRequest, Mapc, MapcOperands, PositionCamAxis};
use planner::mccp::{CamElement, CamProfile};
use planner::task::{MapcCall, MotionTask};
use std::hint::black_box;
use std::sync::Arc;

fn cam(n: usize, mixed: bool) -> Vec<CamElement> {
    (0..n)
        .map(|i| {
            let x = i as f64 * 0.36;
            CamElement {
                master: x,
                slave: 50.0 * (x.to_radians() * 3.0).sin() + x,
                segment_type: if mixed && i % 7 == 3 { 0 } else { 1 },
            }
        })
        .collect()
}

fn mccp(c: &mut Criterion) {
    let all_cubic = cam(1000, false);
    c.bench_function("mccp_1000_points_all_cubic", |b| {
        b.iter(|| CamProfile::calculate(black_box(&all_cubic), 1000, 1.0, 1.0).expect("valid cam"))
    });
    let mixed = cam(1000, true);
    c.bench_function("mccp_1000_points_mixed", |b| {
        b.iter(|| CamProfile::calculate(black_box(&mixed), 1000, 1.0, 1.0).expect("valid cam"))
    });
}

fn mapc(c: &mut Criterion) {
    let points = cam(1000, false);
    let mut task = MotionTask::new(0.001).expect("valid period");
    let axis = |name: &str| AxisConfig {
        max_velocity: 1000.0,
        ..AxisConfig::new(name, AxisKind::Linear)
    };
    let master = task.add_axis(axis("Conveyor"), 0.0).expect("valid axis");
    let slave = task.add_axis(axis("Knife"), 0.0).expect("valid axis");
    let profile = task.add_cam_profile("Knife_Profile", 1000);
    let mi = task.add_instruction("MCCP_1");
    task.mccp(mi, &points, 1000, 1.0, 1.0, profile).expect("valid cam");
    let jog = task.add_instruction("MAJ_1");
    task.maj(
        master,
        jog,
        &MajOperands {
            speed: 200.0,
            ..Default::default()
        },
    )
    .expect("valid jog");
    let pc = task.add_instruction("MAPC_1");
    task.mapc(MapcCall {
        slave,
        master,
        motion_control: pc,
        cam_profile: profile,
        operands: MapcOperands {
            execution_mode: 1,
            master_reference: 1,
            ..MapcOperands::default()
        },
    })
    .expect("valid cam");
    c.bench_function("task_update_jogged_master_and_cam_slave", |b| b.iter(|| task.update()));

    let p = Arc::new(CamProfile::calculate(&points, 1000, 1.0, 1.0).expect("valid cam"));
    let mut cam: PositionCamAxis<u32, u8> = PositionCamAxis::default();
    let req = CamRequest {
        tag: 0,
        master: 0,
        mapc: Mapc::new(&MapcOperands {
            execution_mode: 1,
            ..MapcOperands::default()
        })
        .expect("valid operands"),
        profile: p,
        master_period: None,
    };
    cam.start(req, 0.0, |_| 0.0).expect("valid cam");
    let mut m = 0.0;
    let mut s = 0.0;
    c.bench_function("mapc_update_1000_point_continuous_cam", |b| {
        b.iter(|| {
            m += 0.2;
            s = cam.update(s, |_| black_box(m)).0.unwrap_or(s);
            s
        })
    });
}

criterion_group!(benches, mccp, mapc);
criterion_main!(benches);
