//! Superimposed motion: a MAM on a cam slave, and a jog under coordinated
//! moves with each merge type.

use super::*;
use crate::axis::{AxisConfig, AxisKind};
use crate::coord::CoordMoveInputs;
use crate::dynamics::MoveDynamics;
use crate::mapc::MapcOperands;
use crate::mccp::CamElement;
use crate::task::engine::{CoordCall, MapcCall};
use crate::task::handles::CoordHandle;
use crate::task::instructions::maj::MajOperands;
use crate::task::instructions::mam::MamOperands;
use crate::task::instructions::mas::MasOperands;

const DT: f64 = 0.004;

fn axis(name: &str) -> AxisConfig {
    AxisConfig {
        max_velocity: 1000.0,
        max_acceleration: 10_000.0,
        max_deceleration: 10_000.0,
        max_jerk: 100_000.0,
        ..AxisConfig::new(name, AxisKind::Linear)
    }
}

/// A master jogging at 100 units/s and a slave on a once-cam of slope 0.5
/// over 1000 master units, locked from the start.
fn cam_rig() -> (MotionTask, AxisHandle, AxisHandle, InstructionHandle) {
    let mut task = MotionTask::new(DT).unwrap();
    let master = task.add_axis(axis("Master"), 0.0).unwrap();
    let slave = task.add_axis(axis("Slave"), 0.0).unwrap();
    let cam = [(0.0, 0.0), (1000.0, 500.0)].map(|(master, slave)| CamElement {
        master,
        slave,
        segment_type: 0,
    });
    let profile = task.add_cam_profile("P", 2);
    let calc = task.add_instruction("Calc");
    task.mccp(calc, &cam, 2, 0.0, 0.0, profile).unwrap();
    let jog = task.add_instruction("Jog");
    let o = MajOperands {
        speed: 100.0,
        speed_units: 0,
        accel_rate: 1000.0,
        accel_units: 0,
        decel_rate: 1000.0,
        decel_units: 0,
        ..MajOperands::default()
    };
    task.maj(master, jog, &o).unwrap();
    let mapc = task.add_instruction("Cam");
    task.mapc(MapcCall {
        slave,
        master,
        motion_control: mapc,
        cam_profile: profile,
        operands: MapcOperands {
            master_reference: 1,
            ..MapcOperands::default()
        },
    })
    .unwrap();
    assert!(task.motion_bits(mapc).ip);
    (task, master, slave, mapc)
}

fn incremental(distance: f64, merge: i64) -> MamOperands {
    MamOperands {
        move_type: 1,
        position: distance,
        merge,
        dynamics: MoveDynamics {
            speed: 50.0,
            speed_units: 0,
            accel_rate: 500.0,
            accel_units: 0,
            decel_rate: 500.0,
            decel_units: 0,
            ..MamOperands::default().dynamics
        },
        ..MamOperands::default()
    }
}

#[test]
fn a_mam_with_merge_disabled_on_a_cam_slave_ends_exactly_its_distance_past_the_cam() {
    let (mut with, _, slave, cam) = cam_rig();
    let (mut without, _, slave_b, _) = cam_rig();
    for _ in 0..500 {
        with.update();
        without.update();
    }
    let mv = with.add_instruction("Move");
    with.mam(slave, mv, &incremental(10.0, 0)).unwrap();
    assert!(with.motion_bits(mv).ip);
    let mut done_at = None;
    for k in 0..1000 {
        with.update();
        without.update();
        let diff = with.axis_state(slave).command_position - without.axis_state(slave_b).command_position;
        assert!((-1e-9..=10.0 + 1e-9).contains(&diff), "offset {diff}");
        if with.motion_bits(mv).pc && done_at.is_none() {
            done_at = Some(k);
        }
        if done_at.is_some() {
            assert!((diff - 10.0).abs() < 1e-9, "held offset {diff}");
        }
        let offset = with.superimposed(slave).map_or(f64::NAN, |s| s.position);
        assert!((offset - diff).abs() < 1e-9, "{offset} vs {diff}");
    }
    assert!(done_at.is_some(), "the MAM completed");
    assert!(with.slave_cam_status(slave).position_cam, "the cam goes on");
    assert!(with.motion_bits(cam).ip);
    // The cam itself is untouched: the slave still moves at half the master.
    let v = with.axis_state(slave).command_velocity;
    assert!((v - 50.0).abs() < 1e-6, "{v}");
}

#[test]
fn a_mam_with_merge_enabled_on_a_cam_slave_ends_the_cam() {
    let (mut task, _, slave, cam) = cam_rig();
    for _ in 0..500 {
        task.update();
    }
    let from = task.axis_state(slave).command_position;
    let mv = task.add_instruction("Move");
    task.mam(slave, mv, &incremental(10.0, 1)).unwrap();
    assert!(!task.motion_bits(cam).ip, "the merge ended the cam");
    assert!(!task.slave_cam_status(slave).position_cam);
    for _ in 0..2000 {
        task.update();
        if task.motion_bits(mv).pc {
            break;
        }
    }
    assert!(task.motion_bits(mv).pc);
    assert!((task.axis_state(slave).command_position - (from + 10.0)).abs() < 1e-9);
    assert!(task.superimposed(slave).is_none());
}

struct Gantry {
    task: MotionTask,
    cs: CoordHandle,
    x: AxisHandle,
    y: AxisHandle,
    jog: InstructionHandle,
}

/// X jogs at 5 units/s; a 2-axis system XY.
fn gantry() -> Gantry {
    let mut task = MotionTask::new(DT).unwrap();
    let x = task.add_axis(axis("X"), 0.0).unwrap();
    let y = task.add_axis(axis("Y"), 0.0).unwrap();
    let cs = crate::task::tests::two_axis_system(&mut task, "XY", x, y);
    let jog = task.add_instruction("Jog");
    let o = MajOperands {
        speed: 5.0,
        speed_units: 0,
        accel_rate: 100.0,
        accel_units: 0,
        decel_rate: 100.0,
        decel_units: 0,
        ..MajOperands::default()
    };
    task.maj(x, jog, &o).unwrap();
    for _ in 0..100 {
        task.update();
    }
    Gantry { task, cs, x, y, jog }
}

fn line(to: [f64; 2], merge: i64) -> CoordCall {
    CoordCall::Mclm(CoordMoveInputs {
        position: to.to_vec(),
        termination_type: 1,
        merge,
        dynamics: MoveDynamics {
            speed: 20.0,
            accel_rate: 200.0,
            decel_rate: 200.0,
            ..CoordMoveInputs::default().dynamics
        },
        ..Default::default()
    })
}

#[test]
fn a_jog_keeps_running_under_coordinated_moves_with_merge_disabled_and_coordinated_motion() {
    let mut g = gantry();
    let x0 = g.task.axis_state(g.x).command_position;
    let first = line([x0 + 10.0, 10.0], 0);
    let h1 = g.task.add_coord_instruction("L1", g.cs, first.clone());
    g.task.set_coord_instruction(h1, true, first);
    g.task.update();
    assert!(g.task.coord_bits(h1).ip, "{:?}", g.task.coord_bits(h1));
    assert!(g.task.motion_bits(g.jog).ip, "the jog goes on superimposed");
    assert!(g.task.axis_status(g.x).jogging);
    for _ in 0..100 {
        g.task.update();
    }
    // A second move merging coordinated motion: the jog still runs.
    let second = line([x0, 0.0], 1);
    let h2 = g.task.add_coord_instruction("L2", g.cs, second.clone());
    g.task.set_coord_instruction(h2, true, second);
    g.task.update();
    assert!(g.task.motion_bits(g.jog).ip);
    for _ in 0..2000 {
        g.task.update();
        if g.task.coord_bits(h2).pc {
            break;
        }
    }
    assert!(g.task.coord_bits(h2).pc);
    let offset = g.task.superimposed(g.x).expect("superimposed jog");
    assert!((offset.velocity - 5.0).abs() < 1e-9);
    // X is the path's end plus the jog's travel since the first move.
    let x = g.task.axis_state(g.x).command_position;
    assert!(
        (x - (x0 + offset.position)).abs() < 1e-9,
        "{x} vs {x0} + {}",
        offset.position
    );
    assert_eq!(g.task.axis_state(g.y).command_position, 0.0);
    // MAS jog ramps the superimposed jog to rest; the offset stays.
    let stop = g.task.add_instruction("Stop");
    let o = MasOperands {
        stop_type: 1,
        ..MasOperands::default()
    };
    g.task.mas(g.x, stop, &o).unwrap();
    assert!(!g.task.motion_bits(g.jog).ip);
    for _ in 0..100 {
        g.task.update();
    }
    let held = g.task.superimposed(g.x).expect("held offset");
    assert_eq!(held.velocity, 0.0);
    assert_eq!(g.task.axis_state(g.x).command_velocity, 0.0);
}

#[test]
fn merge_all_motion_stops_the_jog() {
    let mut g = gantry();
    let call = line([1.0, 1.0], 2);
    let h = g.task.add_coord_instruction("L", g.cs, call.clone());
    g.task.set_coord_instruction(h, true, call);
    g.task.update();
    assert!(g.task.coord_bits(h).ip);
    assert!(!g.task.motion_bits(g.jog).ip, "All Motion ends the jog");
    assert!(g.task.superimposed(g.x).is_none());
    for _ in 0..2000 {
        g.task.update();
        if g.task.coord_bits(h).pc {
            break;
        }
    }
    assert!(g.task.coord_bits(h).pc);
    assert_eq!(g.task.axis_state(g.x).command_position, 1.0);
}
