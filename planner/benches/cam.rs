//! Cam speed: MCCP calculation time for a 1,000-point cam (all cubic, and
//! mixed linear/cubic), and the position cam's cost per coarse update (a
//! master jogged by MAJ, one slave on a continuous 1,000-point cam, the whole
//! `MotionTask::update`, and the MAPC process alone).

#![allow(missing_docs)]

use criterion::{Criterion, criterion_group, criterion_main};
use planner::axis::{AxisConfig, AxisKind};
use planner::mapc::axis::{CamRequest, PositionCamAxis};
use planner::mapc::{Mapc, MapcOperands};
use planner::mccp::{CamElement, CamProfile};
use planner::task::instructions::{maj::MAJ, mapc::MAPC, mccp::MCCP};
use planner::task::{Arg, Args, MotionTask};
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
    // MCCP(MCCP_1, Cam[0], 1000, 1.0, 1.0, Knife_Profile)
    let mccp = [
        Arg::Control(mi),
        Arg::Cam(&points, 0),
        Arg::Integer(1000),
        Arg::Number(1.0),
        Arg::Number(1.0),
        Arg::CamProfile(profile),
    ];
    MCCP.execute(&mut task, &Args::new(&mccp)).expect("valid cam");
    // MAJ(Conveyor, MAJ_1, forward, 200, unitspersec, 100, %ofmaximum, 100, %ofmaximum, trapezoidal)
    let jog = task.add_instruction("MAJ_1");
    let maj = [
        Arg::Axis(master),
        Arg::Control(jog),
        Arg::Integer(0),
        Arg::Number(200.0),
        Arg::Integer(0),
        Arg::Number(100.0),
        Arg::Integer(1),
        Arg::Number(100.0),
        Arg::Integer(1),
        Arg::Integer(0),
    ];
    MAJ.execute(&mut task, &Args::new(&maj)).expect("valid jog");
    // MAPC(Knife, Conveyor, MAPC_1, same, Knife_Profile, 1, 1, continuous,
    // immediate, 0, 0, newcam, command, bidirectional)
    let pc = task.add_instruction("MAPC_1");
    let mapc = [
        Arg::Axis(slave),
        Arg::Axis(master),
        Arg::Control(pc),
        Arg::Integer(0),
        Arg::CamProfile(profile),
        Arg::Number(1.0),
        Arg::Number(1.0),
        Arg::Integer(1),
        Arg::Integer(0),
        Arg::Number(0.0),
        Arg::Number(0.0),
        Arg::Integer(0),
        Arg::Integer(1),
        Arg::Integer(0),
    ];
    MAPC.execute(&mut task, &Args::new(&mapc)).expect("valid cam");
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
