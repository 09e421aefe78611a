//! MCT through the task: an MCCM circle in the Cartesian system drives the
//! SCARA joints on the circle, joint moves drive the Cartesian axes, MCS
//! cancels, a move out of reach faults and stops the joints within their
//! speed limits.

use super::*;
use crate::axis::{AxisConfig, AxisKind};
use crate::coord::{CoordMoveInputs, CoordinateSystemConfig, McsInputs};
use crate::dynamics::MoveDynamics;
use crate::mccm::MccmInputs;
use crate::mct::Geometry;
use crate::mct::Placement;
use crate::task::TaskError;
use crate::task::engine::CoordCall;

const DT: f64 = 0.004;

struct Robot {
    task: MotionTask,
    cart: CoordHandle,
    joints: CoordHandle,
    xyz: [AxisHandle; 3],
    j: [AxisHandle; 2],
    mct: InstructionHandle,
}

fn params() -> GeometryParams {
    GeometryParams {
        link_lengths: [0.4, 0.3, 0.0],
        base_offsets: [0.02, -0.01, 0.0],
        end_effector_offsets: [0.0, 0.0, 0.0],
        zero_angles_deg: [0.0, 0.0, 0.0],
    }
}

/// Cartesian X, Y, Z → SCARA J1, J2 with the shared Z, joints at `q_deg`.
fn scara(q_deg: [f64; 2]) -> Robot {
    scara_limited(q_deg, [None, None])
}

/// As [`scara`], with soft travel limits on J1, J2 (degrees).
fn scara_limited(q_deg: [f64; 2], limits: [Option<(f64, f64)>; 2]) -> Robot {
    let mut task = MotionTask::new(DT).unwrap();
    let lin = |n: &str| AxisConfig {
        max_velocity: 2.0,
        ..AxisConfig::new(n, AxisKind::Linear)
    };
    let rot = |n: &str, soft_travel_limits| AxisConfig {
        soft_travel_limits,
        max_velocity: 360.0,
        max_acceleration: 3600.0,
        max_deceleration: 3600.0,
        ..AxisConfig::new(n, AxisKind::Rotary)
    };
    let x = task.add_axis(lin("X"), 0.0).unwrap();
    let y = task.add_axis(lin("Y"), 0.0).unwrap();
    let z = task.add_axis(lin("Z"), 0.1).unwrap();
    let j1 = task.add_axis(rot("J1", limits[0]), q_deg[0]).unwrap();
    let j2 = task.add_axis(rot("J2", limits[1]), q_deg[1]).unwrap();
    let system = |name: &str, primary| CoordinateSystemConfig {
        axis_count: 3,
        primary_axes: primary,
        max_speed: 1000.0,
        max_accel: 10_000.0,
        max_decel: 10_000.0,
        ..CoordinateSystemConfig::new(name)
    };
    let cart = task.add_coordinate_system(system("Cart", 2), &[x, y, z]).unwrap();
    let joints = task.add_coordinate_system(system("Joints", 2), &[j1, j2, z]).unwrap();
    task.set_transform_geometry(
        joints,
        TransformGeometry {
            kind: GeometryKind::ScaraIndependent,
            params: params(),
            transform_dimension: 2,
        },
    );
    let mct = task.add_instruction("MCT1");
    Robot {
        task,
        cart,
        joints,
        xyz: [x, y, z],
        j: [j1, j2],
        mct,
    }
}

fn geometry() -> Geometry {
    Geometry::new(GeometryKind::ScaraIndependent, &params(), 2).unwrap()
}

fn pos(task: &MotionTask, a: AxisHandle) -> f64 {
    task.axis_state(a).command_position
}

/// The tool by forward kinematics of the joint command positions.
fn tool(r: &Robot) -> Vec3 {
    let q = [
        pos(&r.task, r.j[0]).to_radians(),
        pos(&r.task, r.j[1]).to_radians(),
        0.0,
    ];
    geometry().forward(q).unwrap()
}

#[test]
fn an_mccm_circle_under_mct_keeps_the_tool_on_the_circle() {
    let mut r = scara([20.0, 70.0]);
    let _ = r.task.execute_mct(r.mct, r.cart, r.joints, [0.0; 3], [0.0; 3]);
    let b = r.task.motion_bits(r.mct);
    assert!(b.en && b.dn && b.ip && !b.er, "{b:?}");
    assert!(r.task.transform_source_status(r.cart) && r.task.transform_target_status(r.joints));
    assert!(!r.task.transform_source_status(r.joints));
    for a in [r.xyz[0], r.xyz[1], r.xyz[2], r.j[0], r.j[1]] {
        assert!(r.task.transform_state_status(a));
    }
    // The source took the forward kinematics of the joints.
    let start = tool(&r);
    assert_eq!([pos(&r.task, r.xyz[0]), pos(&r.task, r.xyz[1])], [start[0], start[1]]);
    assert_eq!(pos(&r.task, r.xyz[2]), 0.1);
    // A full circle of radius 5 cm about a centre 5 cm to −X1.
    let centre = [start[0] - 0.05, start[1]];
    let call = CoordCall::Mccm(MccmInputs {
        common: CoordMoveInputs {
            position: vec![start[0], start[1], 0.1],
            termination_type: 1,
            dynamics: MoveDynamics {
                speed: 0.2,
                accel_rate: 2.0,
                decel_rate: 2.0,
                ..CoordMoveInputs::default().dynamics
            },
            ..Default::default()
        },
        circle_type: 3,
        via_center_radius: vec![-0.05, 0.0],
        direction: 3,
    });
    let mc = r.task.add_coord_instruction("MC1", r.cart, call.clone());
    r.task.set_coord_instruction(mc, true, call);
    let mut worst: f64 = 0.0;
    let mut controlled = false;
    let mut turned = 0.0_f64;
    for _ in 0..5000 {
        r.task.update();
        let t = tool(&r);
        let radius = (t[0] - centre[0]).hypot(t[1] - centre[1]);
        worst = worst.max((radius - 0.05).abs());
        // The joints follow the Cartesian command exactly.
        assert!((t[0] - pos(&r.task, r.xyz[0])).abs() < 1e-9 && (t[1] - pos(&r.task, r.xyz[1])).abs() < 1e-9);
        controlled |= r.task.controlled_by_transform_status(r.j[0]);
        turned = turned.max((t[1] - centre[1]).atan2(t[0] - centre[0]).abs());
        for j in r.j {
            assert!(r.task.axis_state(j).command_velocity.abs() <= 360.0);
        }
        if r.task.coord_bits(mc).pc {
            break;
        }
    }
    assert!(r.task.coord_bits(mc).pc, "the circle completes");
    assert!(worst < 1e-9, "tool off the circle by {worst}");
    assert!(controlled && turned > 3.0, "the joints moved round the circle");
    assert!(!r.task.controlled_by_transform_status(r.xyz[0]));
    // The transform keeps running after the move.
    assert!(r.task.motion_bits(r.mct).ip);
    r.task.update();
    assert!(!r.task.motion_bits(r.mct).en, "the one-shot rung went false");
    assert!(!r.task.controlled_by_transform_status(r.j[0]), "nothing moves");
}

/// After a Cartesian move under MCT has ended, the joints hold still with
/// zero command speed and acceleration (no stale speed of the last update).
#[test]
fn joints_at_rest_after_a_cartesian_move_have_zero_command_speed() {
    let mut r = scara([20.0, 70.0]);
    let _ = r.task.execute_mct(r.mct, r.cart, r.joints, [0.0; 3], [0.0; 3]);
    let start = tool(&r);
    let call = CoordCall::Mclm(CoordMoveInputs {
        position: vec![start[0] - 0.1, start[1] + 0.05, 0.1],
        termination_type: 1,
        dynamics: MoveDynamics {
            speed: 0.3,
            accel_rate: 3.0,
            decel_rate: 3.0,
            ..CoordMoveInputs::default().dynamics
        },
        ..Default::default()
    });
    let ml = r.task.add_coord_instruction("ML1", r.cart, call.clone());
    r.task.set_coord_instruction(ml, true, call);
    for _ in 0..2000 {
        r.task.update();
        if r.task.coord_bits(ml).pc {
            break;
        }
    }
    assert!(r.task.coord_bits(ml).pc);
    let at = r.j.map(|j| pos(&r.task, j));
    for _ in 0..3 {
        r.task.update();
    }
    for (k, j) in r.j.into_iter().enumerate() {
        let s = r.task.axis_state(j);
        assert_eq!(s.command_position, at[k]);
        assert_eq!(s.command_velocity, 0.0, "J{}: {s:?}", k + 1);
        assert_eq!(s.command_acceleration, 0.0, "J{}: {s:?}", k + 1);
    }
}

#[test]
fn a_joint_move_drives_the_cartesian_axes_and_mcs_cancels() {
    let mut r = scara([10.0, 60.0]);
    let _ = r
        .task
        .execute_mct(r.mct, r.cart, r.joints, [0.0, 0.0, 30.0], [0.1, 0.0, 0.0]);
    assert!(r.task.motion_bits(r.mct).ip);
    // MCLM in the joint system: J2 from 60° to 90°.
    let call = CoordCall::Mclm(CoordMoveInputs {
        position: vec![10.0, 90.0, 0.1],
        termination_type: 1,
        dynamics: MoveDynamics {
            speed: 90.0,
            accel_rate: 900.0,
            decel_rate: 900.0,
            ..CoordMoveInputs::default().dynamics
        },
        ..Default::default()
    });
    let ml = r.task.add_coord_instruction("ML1", r.joints, call.clone());
    r.task.set_coord_instruction(ml, true, call);
    let placement = Placement::new([0.0, 0.0, 30.0], [0.1, 0.0, 0.0]).unwrap();
    let mut controlled = false;
    for _ in 0..2000 {
        r.task.update();
        let expected = placement.source_from_target(tool(&r));
        assert!((pos(&r.task, r.xyz[0]) - expected[0]).abs() < 1e-12);
        assert!((pos(&r.task, r.xyz[1]) - expected[1]).abs() < 1e-12);
        controlled |= r.task.controlled_by_transform_status(r.xyz[0]);
        if r.task.coord_bits(ml).pc {
            break;
        }
    }
    assert!(r.task.coord_bits(ml).pc && controlled);
    assert_eq!(pos(&r.task, r.j[1]), 90.0);
    // MCS stop type "coordinated move" leaves the transform; "transform" cancels it.
    let stop = |t: i64| {
        CoordCall::Mcs(McsInputs {
            stop_type: t,
            ..McsInputs::default()
        })
    };
    let ms = r.task.add_coord_instruction("MS1", r.cart, stop(1));
    r.task.set_coord_instruction(ms, true, stop(1));
    r.task.update();
    assert!(r.task.coord_bits(ms).dn && r.task.motion_bits(r.mct).ip);
    r.task.set_coord_instruction(ms, false, stop(2));
    r.task.update();
    r.task.set_coord_instruction(ms, true, stop(2));
    r.task.update();
    let b = r.task.motion_bits(r.mct);
    assert!(!b.ip && b.dn && !b.er, "{b:?}");
    assert!(!r.task.transform_source_status(r.cart) && !r.task.transform_state_status(r.j[0]));
}

#[test]
fn a_move_out_of_reach_faults_and_stops_the_joints_within_their_limits() {
    let mut r = scara([0.0, 60.0]);
    let _ = r.task.execute_mct(r.mct, r.cart, r.joints, [0.0; 3], [0.0; 3]);
    let start = tool(&r);
    // Straight out along the arm's direction, to 1 m from the base: through
    // full stretch (0.7 m).
    let call = CoordCall::Mclm(CoordMoveInputs {
        position: vec![
            1.0 * start[0] / start[0].hypot(start[1]),
            1.0 * start[1] / start[0].hypot(start[1]),
            0.1,
        ],
        termination_type: 1,
        dynamics: MoveDynamics {
            speed: 0.5,
            accel_rate: 5.0,
            decel_rate: 5.0,
            ..CoordMoveInputs::default().dynamics
        },
        ..Default::default()
    });
    let ml = r.task.add_coord_instruction("ML1", r.cart, call.clone());
    r.task.set_coord_instruction(ml, true, call);
    let mut faulted_at = None;
    for k in 0..3000 {
        r.task.update();
        for j in r.j {
            let v = r.task.axis_state(j).command_velocity;
            assert!(v.is_finite() && v.abs() <= 360.0, "{k}: {v}");
        }
        if faulted_at.is_none() && r.task.motion_bits(r.mct).er {
            faulted_at = Some(k);
        }
        if faulted_at.is_some() && r.j.iter().all(|&j| r.task.axis_state(j).command_velocity == 0.0) {
            break;
        }
    }
    let b = r.task.motion_bits(r.mct);
    assert!(faulted_at.is_some() && b.er && b.err == 67 && !b.ip && b.dn, "{b:?}");
    // The joints came to rest and the transform left the table.
    assert!(!r.task.transform_state_status(r.j[0]));
    for j in r.j {
        assert_eq!(r.task.axis_state(j).command_velocity, 0.0);
    }
    // The source system's move was brought to rest.
    for _ in 0..500 {
        r.task.update();
    }
    assert!(!r.task.coordinated_motion_status(r.xyz[0]));
}

/// MCS (stop type all or coordinated transform) on the Cartesian system in
/// the middle of a move under MCT froze the joints at once: their command
/// speed fell from its full value to zero in one update.
#[test]
fn mcs_in_the_middle_of_a_cartesian_move_stops_the_joints_within_their_deceleration() {
    for (stop_type, system) in [(0, "Cart"), (2, "Cart"), (0, "Joints"), (2, "Joints")] {
        let mut r = scara([20.0, 70.0]);
        let _ = r.task.execute_mct(r.mct, r.cart, r.joints, [0.0; 3], [0.0; 3]);
        let start = tool(&r);
        let call = CoordCall::Mclm(CoordMoveInputs {
            position: vec![start[0] - 0.3, start[1] + 0.1, 0.1],
            termination_type: 1,
            dynamics: MoveDynamics {
                speed: 0.5,
                accel_rate: 5.0,
                decel_rate: 5.0,
                ..CoordMoveInputs::default().dynamics
            },
            ..Default::default()
        });
        let ml = r.task.add_coord_instruction("ML1", r.cart, call.clone());
        r.task.set_coord_instruction(ml, true, call);
        // Mid-move, the joints turning.
        for _ in 0..100 {
            r.task.update();
        }
        let speed = |r: &Robot| r.j.map(|j| r.task.axis_state(j).command_velocity);
        assert!(speed(&r).iter().any(|v| v.abs() > 5.0), "{:?}", speed(&r));
        let stop = CoordCall::Mcs(McsInputs {
            stop_type,
            ..McsInputs::default()
        });
        let cs = if system == "Cart" { r.cart } else { r.joints };
        let ms = r.task.add_coord_instruction("MS1", cs, stop.clone());
        r.task.set_coord_instruction(ms, true, stop);
        let dv = 3600.0 * DT * (1.0 + 1e-9);
        let mut last = speed(&r);
        let mut last_at = r.j.map(|j| pos(&r.task, j));
        for k in 0..1000 {
            r.task.update();
            let now = speed(&r);
            let at = r.j.map(|j| pos(&r.task, j));
            for i in 0..2 {
                // The positions move as the speeds say (not frozen under a
                // stale speed).
                let moved = at[i] - last_at[i];
                assert!(
                    (moved - 0.5 * (now[i] + last[i]) * DT).abs() < 1e-9,
                    "MCS {stop_type} on {system}, update {k}: J{} moved {moved} at {} -> {} deg/s",
                    i + 1,
                    last[i],
                    now[i]
                );
                assert!(
                    (now[i] - last[i]).abs() <= dv,
                    "MCS {stop_type} on {system}, update {k}: J{} {} -> {} deg/s",
                    i + 1,
                    last[i],
                    now[i]
                );
            }
            last = now;
            last_at = at;
        }
        let b = r.task.motion_bits(r.mct);
        assert!(!b.ip && !b.er, "{b:?}");
        assert_eq!(last, [0.0; 2], "MCS {stop_type} on {system}");
        assert!(!r.task.transform_source_status(r.cart) && !r.task.transform_state_status(r.j[0]));
    }
}

/// A joint move that left a joint's soft travel limit ended the link, but
/// the Cartesian axes kept the command speed of the link's last update.
#[test]
fn a_joint_move_beyond_a_limit_ends_the_link_and_leaves_the_cartesian_axes_at_rest() {
    let mut r = scara_limited([0.0, 60.0], [Some((-20.0, 25.0)), None]);
    let _ = r.task.execute_mct(r.mct, r.cart, r.joints, [0.0; 3], [0.0; 3]);
    let call = CoordCall::Mclm(CoordMoveInputs {
        position: vec![40.0, 60.0, 0.1],
        termination_type: 1,
        dynamics: MoveDynamics {
            speed: 90.0,
            accel_rate: 900.0,
            decel_rate: 900.0,
            ..CoordMoveInputs::default().dynamics
        },
        ..Default::default()
    });
    let ml = r.task.add_coord_instruction("ML1", r.joints, call.clone());
    r.task.set_coord_instruction(ml, true, call);
    let mut ended = None;
    for k in 0..2000 {
        r.task.update();
        if r.task.motion_bits(r.mct).er {
            ended = Some(k);
            break;
        }
        assert!(r.task.axis_state(r.xyz[0]).command_velocity != 0.0 || k == 0);
    }
    let b = r.task.motion_bits(r.mct);
    assert!(ended.is_some() && b.err == 67 && !b.ip, "{b:?}");
    let at = r.xyz.map(|a| pos(&r.task, a));
    for _ in 0..3 {
        r.task.update();
    }
    for (k, a) in r.xyz.into_iter().enumerate() {
        let s = r.task.axis_state(a);
        assert_eq!(s.command_position, at[k], "{a:?}");
        assert_eq!(s.command_velocity, 0.0, "{a:?}: {s:?}");
    }
    // The joint move itself goes on (the link ended, not the move).
    assert!(pos(&r.task, r.j[0]) > 25.0);
}

#[test]
fn mcs_on_the_source_during_a_joint_move_ends_the_link_and_the_joint_move_goes_on() {
    let mut r = scara([10.0, 60.0]);
    let _ = r.task.execute_mct(r.mct, r.cart, r.joints, [0.0; 3], [0.0; 3]);
    let call = CoordCall::Mclm(CoordMoveInputs {
        position: vec![10.0, 90.0, 0.1],
        termination_type: 1,
        dynamics: MoveDynamics {
            speed: 30.0,
            accel_rate: 300.0,
            decel_rate: 300.0,
            ..CoordMoveInputs::default().dynamics
        },
        ..Default::default()
    });
    let ml = r.task.add_coord_instruction("ML1", r.joints, call.clone());
    r.task.set_coord_instruction(ml, true, call);
    for _ in 0..50 {
        r.task.update();
    }
    assert!(r.task.controlled_by_transform_status(r.xyz[0]));
    let stop = CoordCall::Mcs(McsInputs {
        stop_type: 2,
        ..McsInputs::default()
    });
    let ms = r.task.add_coord_instruction("MS1", r.cart, stop.clone());
    r.task.set_coord_instruction(ms, true, stop);
    let mut last = pos(&r.task, r.j[1]);
    for k in 0..2000 {
        r.task.update();
        // J2 keeps its own move's profile: forward, at most 30°/s.
        let now = pos(&r.task, r.j[1]);
        assert!(
            now >= last && now - last <= 30.0 * DT * (1.0 + 1e-9),
            "{k}: J2 {last} -> {now}"
        );
        last = now;
        if r.task.coord_bits(ml).pc {
            break;
        }
    }
    let b = r.task.motion_bits(r.mct);
    assert!(!b.ip && !b.er, "{b:?}");
    assert!(r.task.coord_bits(ml).pc, "the joint move completes");
    assert_eq!(pos(&r.task, r.j[1]), 90.0);
}

/// A fault ended the transform (`.IP` off) but its status bits stayed on
/// for the whole controlled stop of the joints.
#[test]
fn the_transform_status_bits_go_off_with_ip_when_a_fault_stops_the_joints() {
    let mut r = scara([0.0, 60.0]);
    let _ = r.task.execute_mct(r.mct, r.cart, r.joints, [0.0; 3], [0.0; 3]);
    let start = tool(&r);
    let out = 1.0 / start[0].hypot(start[1]);
    let call = CoordCall::Mclm(CoordMoveInputs {
        position: vec![start[0] * out, start[1] * out, 0.1],
        termination_type: 1,
        dynamics: MoveDynamics {
            speed: 0.5,
            accel_rate: 5.0,
            decel_rate: 5.0,
            ..CoordMoveInputs::default().dynamics
        },
        ..Default::default()
    });
    let ml = r.task.add_coord_instruction("ML1", r.cart, call.clone());
    r.task.set_coord_instruction(ml, true, call);
    let mut stopping_updates = 0;
    for _ in 0..3000 {
        r.task.update();
        if !r.task.motion_bits(r.mct).er {
            assert!(r.task.transform_source_status(r.cart) && r.task.transform_target_status(r.joints));
            continue;
        }
        let moving = r.j.iter().any(|&j| r.task.axis_state(j).command_velocity != 0.0);
        assert!(!r.task.transform_source_status(r.cart), "source status after the fault");
        assert!(
            !r.task.transform_target_status(r.joints),
            "target status after the fault"
        );
        for a in [r.xyz[0], r.xyz[1], r.j[0], r.j[1]] {
            assert!(!r.task.transform_state_status(a), "{a:?}");
            assert!(!r.task.controlled_by_transform_status(a), "{a:?}");
        }
        if !moving {
            break;
        }
        stopping_updates += 1;
        // An MCT on the joints while they are still stopping: a motion
        // process controls them (EXERR 10).
        let again = r.task.add_instruction("MCT2");
        let _ = r.task.execute_mct(again, r.cart, r.joints, [0.0; 3], [0.0; 3]);
        let b = r.task.motion_bits(again);
        assert!(b.er && (b.err, b.exerr) == (61, 10), "{b:?}");
    }
    assert!(stopping_updates > 3, "the stop took {stopping_updates} updates");
    // At rest, a new MCT links the systems again.
    for _ in 0..500 {
        r.task.update();
    }
    let again = r.task.add_instruction("MCT3");
    let _ = r.task.execute_mct(again, r.cart, r.joints, [0.0; 3], [0.0; 3]);
    let b = r.task.motion_bits(again);
    assert!(b.ip && !b.er, "{b:?}");
    assert!(r.task.transform_source_status(r.cart));
}

#[test]
fn a_cartesian_move_across_a_joint_limit_faults_and_stops_the_joint_short_of_it() {
    let (min, max) = (-20.0, 25.0);
    let mut r = scara_limited([0.0, 60.0], [Some((min, max)), None]);
    let _ = r.task.execute_mct(r.mct, r.cart, r.joints, [0.0; 3], [0.0; 3]);
    assert!(r.task.motion_bits(r.mct).ip);
    // A straight line to where J1 would be at 70°: J1 turns through 25°.
    let end = geometry()
        .forward([70f64.to_radians(), 60f64.to_radians(), 0.0])
        .unwrap();
    let call = CoordCall::Mclm(CoordMoveInputs {
        position: vec![end[0], end[1], 0.1],
        termination_type: 1,
        dynamics: MoveDynamics {
            speed: 0.5,
            accel_rate: 5.0,
            decel_rate: 5.0,
            ..CoordMoveInputs::default().dynamics
        },
        ..Default::default()
    });
    let ml = r.task.add_coord_instruction("ML1", r.cart, call.clone());
    r.task.set_coord_instruction(ml, true, call);
    let mut faulted_at = None;
    let mut j1_max = f64::NEG_INFINITY;
    for k in 0..3000 {
        r.task.update();
        if faulted_at.is_none() && r.task.motion_bits(r.mct).er {
            faulted_at = Some(k);
        }
        let j1 = r.task.axis_state(r.j[0]);
        j1_max = j1_max.max(j1.command_position);
        assert!(
            (min..=max).contains(&j1.command_position),
            "{k}: J1 command {} beyond its limits",
            j1.command_position
        );
        for j in r.j {
            let s = r.task.axis_state(j);
            assert!(
                s.command_velocity.is_finite() && s.command_velocity.abs() <= 360.0,
                "{k}: {s:?}"
            );
            if faulted_at.is_some() {
                // The controlled stop decelerates within the axis maximum.
                assert!(s.command_acceleration.abs() <= 3600.0 * (1.0 + 1e-9), "{k}: {s:?}");
            }
        }
        if faulted_at.is_some() && r.j.iter().all(|&j| r.task.axis_state(j).command_velocity == 0.0) {
            break;
        }
    }
    let b = r.task.motion_bits(r.mct);
    assert!(faulted_at.is_some() && b.er && b.err == 67 && !b.ip && b.dn, "{b:?}");
    // The transform drove J1 most of the way to its limit before it faulted.
    assert!(j1_max > 20.0 && j1_max <= max, "{j1_max}");
    assert!(!r.task.transform_state_status(r.j[0]));
    for j in r.j {
        assert_eq!(r.task.axis_state(j).command_velocity, 0.0);
    }
    for _ in 0..500 {
        r.task.update();
    }
    assert!(!r.task.coordinated_motion_status(r.xyz[0]));
    // Every source axis came to rest with the system (none left behind).
    for a in r.xyz {
        assert_eq!(r.task.axis_state(a).command_velocity, 0.0, "{a:?}");
    }
    assert!(r.task.axis_state(r.j[0]).command_position <= max);
}

#[test]
fn an_axis_can_neither_start_nor_be_transformed_beyond_its_limit() {
    let mut task = MotionTask::new(DT).unwrap();
    let limited = AxisConfig {
        soft_travel_limits: Some((-10.0, 10.0)),
        ..AxisConfig::new("J", AxisKind::Rotary)
    };
    assert!(matches!(
        task.add_axis(limited.clone(), 11.0),
        Err(TaskError::Axis {
            source: crate::axis::AxisConfigError::OutsideSoftTravelLimits { .. },
            ..
        })
    ));
    assert!(task.add_axis(limited, 10.0).is_ok());
    // MRP beyond the limit redefines and raises the soft overtravel fault
    // (crate::mrp); MRP back inside, MAFR, and MCT links the joint as usual.
    let mut r = scara_limited([0.0, 60.0], [None, Some((-150.0, 150.0))]);
    let mrp = r.task.add_instruction("MRP1");
    r.task.mrp(r.j[1], mrp, 0, 1, 151.0).unwrap();
    assert_eq!(r.task.axis_state(r.j[1]).command_position, 151.0);
    assert!(r.task.motion_faults(r.j[1]).positive());
    let _ = r.task.execute_mct(r.mct, r.cart, r.joints, [0.0; 3], [0.0; 3]);
    // A transform refuses a joint beyond its limit (ERR 67).
    let b = r.task.motion_bits(r.mct);
    assert!(b.er && b.err == 67, "{b:?}");
    r.task.mrp(r.j[1], mrp, 0, 1, 60.0).unwrap();
    let reset = r.task.add_instruction("MAFR1");
    r.task.mafr(r.j[1], reset).unwrap();
    assert!(r.task.motion_faults(r.j[1]).is_clear());
    let _ = r.task.execute_mct(r.mct, r.cart, r.joints, [0.0; 3], [0.0; 3]);
    let b = r.task.motion_bits(r.mct);
    assert!(!b.er && b.ip, "{b:?}");
    assert!(r.task.transform_state_status(r.j[1]));
}

#[test]
fn mct_refuses_to_start_while_an_axis_moves_and_restarts_with_new_operands() {
    let mut r = scara([10.0, 60.0]);
    let call = CoordCall::Mclm(CoordMoveInputs {
        position: vec![0.3, 0.3, 0.1],
        termination_type: 1,
        dynamics: MoveDynamics {
            speed: 0.1,
            accel_rate: 1.0,
            decel_rate: 1.0,
            ..CoordMoveInputs::default().dynamics
        },
        ..Default::default()
    });
    let ml = r.task.add_coord_instruction("ML1", r.cart, call.clone());
    r.task.set_coord_instruction(ml, true, call);
    r.task.update();
    let _ = r.task.execute_mct(r.mct, r.cart, r.joints, [0.0; 3], [0.0; 3]);
    let b = r.task.motion_bits(r.mct);
    assert!(b.er && (b.err, b.exerr) == (61, 10), "{b:?}");
    let ms = r
        .task
        .add_coord_instruction("MS1", r.cart, CoordCall::Mcs(McsInputs::default()));
    r.task
        .set_coord_instruction(ms, true, CoordCall::Mcs(McsInputs::default()));
    for _ in 0..500 {
        r.task.update();
    }
    let _ = r.task.execute_mct(r.mct, r.cart, r.joints, [0.0; 3], [0.0; 3]);
    assert!(r.task.motion_bits(r.mct).ip);
    let first = [pos(&r.task, r.xyz[0]), pos(&r.task, r.xyz[1])];
    r.task.update();
    let _ = r
        .task
        .execute_mct(r.mct, r.cart, r.joints, [0.0, 0.0, 0.0], [0.5, 0.25, 0.0]);
    let b = r.task.motion_bits(r.mct);
    assert!(b.ip && b.dn && b.en, "{b:?}");
    let second = [pos(&r.task, r.xyz[0]), pos(&r.task, r.xyz[1])];
    assert!((second[0] - (first[0] - 0.5)).abs() < 1e-12 && (second[1] - (first[1] - 0.25)).abs() < 1e-12);
    assert!(r.task.mct_transform(r.mct).is_some());
}

#[test]
fn the_same_calls_give_bit_identical_joint_commands() {
    let run = || {
        let mut r = scara([20.0, 70.0]);
        let _ = r
            .task
            .execute_mct(r.mct, r.cart, r.joints, [0.0, 0.0, 15.0], [0.01, 0.02, 0.0]);
        let start = [pos(&r.task, r.xyz[0]), pos(&r.task, r.xyz[1])];
        let call = CoordCall::Mccm(MccmInputs {
            common: CoordMoveInputs {
                position: vec![start[0] - 0.03, start[1] + 0.03, 0.1],
                termination_type: 1,
                dynamics: MoveDynamics {
                    speed: 0.2,
                    accel_rate: 2.0,
                    decel_rate: 2.0,
                    ..CoordMoveInputs::default().dynamics
                },
                ..Default::default()
            },
            circle_type: 3,
            via_center_radius: vec![-0.03, 0.0],
            direction: 1,
        });
        let mc = r.task.add_coord_instruction("MC1", r.cart, call.clone());
        r.task.set_coord_instruction(mc, true, call);
        r.task.update();
        assert!(r.task.coord_bits(mc).ip && r.task.motion_bits(r.mct).ip);
        let mut bits = Vec::new();
        for _ in 0..400 {
            r.task.update();
            for a in [r.j[0], r.j[1], r.xyz[0], r.xyz[1]] {
                let s = r.task.axis_state(a);
                bits.push((s.command_position.to_bits(), s.command_velocity.to_bits()));
            }
        }
        bits
    };
    let (a, b) = (run(), run());
    assert_ne!(a[0].0, a[a.len() - 4].0, "J1 moved");
    assert_eq!(a, b);
}
