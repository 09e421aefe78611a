//! MDCC through the task: the link, a master-driven line following the
//! master's command or actual position, `.AC`, what breaks the link, and
//! the refusals.

use super::*;
use crate::axis::{AxisConfig, AxisKind};
use crate::coord::{CoordMoveInputs, CoordinateSystemConfig, McsInputs};
use crate::dynamics::MoveDynamics;
use crate::instruction::LogixFault;
use crate::task::CoordCall;

const DT: f64 = 0.004;

/// Master M (not in the system) and a gantry X, Y.
fn setup() -> (MotionTask, CoordHandle, AxisHandle, Vec<AxisHandle>) {
    let mut task = MotionTask::new(DT).unwrap();
    let config = |n: &str| AxisConfig {
        max_velocity: 1000.0,
        max_acceleration: 1e6,
        max_deceleration: 1e6,
        ..AxisConfig::new(n, AxisKind::Linear)
    };
    let m = task.add_axis(config("M"), 0.0).unwrap();
    let axes: Vec<AxisHandle> = ["X", "Y"]
        .iter()
        .map(|n| task.add_axis(config(n), 0.0).unwrap())
        .collect();
    let cs = task
        .add_coordinate_system(
            CoordinateSystemConfig {
                axis_count: 2,
                primary_axes: 2,
                max_speed: 100.0,
                max_accel: 1000.0,
                max_decel: 1000.0,
                command_tolerance: 0.5,
                actual_tolerance: 0.01,
                ..CoordinateSystemConfig::new("CS")
            },
            &axes,
        )
        .unwrap();
    (task, cs, m, axes)
}

/// A master-driven line to (10, 0): 1 unit per master unit, rates 1000
/// per master unit².
fn line() -> CoordCall {
    CoordCall::Mclm(CoordMoveInputs {
        position: vec![10.0, 0.0],
        termination_type: 1,
        dynamics: MoveDynamics {
            speed: 1.0,
            speed_units: 4,
            accel_rate: 1000.0,
            accel_units: 4,
            decel_rate: 1000.0,
            decel_units: 4,
            ..CoordMoveInputs::default().dynamics
        },
        ..Default::default()
    })
}

#[test]
fn a_master_driven_line_follows_the_linked_master_and_mcs_all_breaks_the_link() {
    let (mut task, cs, m, axes) = setup();
    let link = task.add_instruction("Link");
    task.mdcc(cs, m, link, 1, 100.0).unwrap();
    assert!(task.motion_bits(link).dn && task.motion_bits(link).ip && !task.motion_bits(link).ac);
    assert_eq!(task.coordinate_system_master(cs), Some(m));
    let mv = task.add_coord_instruction("Mv", cs, line());
    task.set_coord_instruction(mv, true, line());
    task.update();
    assert!(task.motion_bits(link).ac, ".AC while the master-driven move is active");
    // Move the master by hand (its command): the line follows it.
    let mut master = 0.0;
    for _ in 0..5 {
        master += 1.0;
        task.axes[m.0 as usize].command.position = master;
        task.update();
    }
    let x = task.axis_state(axes[0]).command_position;
    assert!(x > 3.0 && x <= 5.0 + 1e-9, "{x}");
    // MCS All on the system breaks the link.
    let stop = task.add_coord_instruction(
        "Stop",
        cs,
        CoordCall::Mcs(McsInputs {
            stop_type: 0,
            ..Default::default()
        }),
    );
    task.set_coord_instruction(
        stop,
        true,
        CoordCall::Mcs(McsInputs {
            stop_type: 0,
            ..Default::default()
        }),
    );
    task.update();
    let b = task.motion_bits(link);
    assert!(!b.ip && !b.ac);
    assert_eq!(task.coordinate_system_master(cs), None);
}

#[test]
fn the_actual_reference_follows_the_fed_position_and_refusals() {
    let (mut task, cs, m, axes) = setup();
    let link = task.add_instruction("Link");
    // The master as one of the system's own axes: ERR 13 on Master Axis.
    let e = task.mdcc(cs, axes[0], link, 0, 0.0).unwrap_err();
    assert_eq!((e.err(), e.exerr()), (13, 1));
    let e = task.mdcc(cs, m, link, 0, -1.0).unwrap_err();
    assert_eq!((e.err(), e.exerr()), (13, 4));
    task.mdcc(cs, m, link, 0, 0.0).unwrap();
    let mv = task.add_coord_instruction("Mv", cs, line());
    task.set_coord_instruction(mv, true, line());
    task.update();
    // The actual position moves, the command does not: the line follows
    // the actual.
    for k in 1..=4 {
        task.feed_actual_position(m, f64::from(k));
        task.update();
    }
    assert_eq!(task.axis_state(m).command_position, 0.0);
    assert!(task.axis_state(axes[0]).command_position > 2.0);
    // MASD on a slave axis breaks the link too.
    let down = task.add_instruction("Down");
    task.masd(axes[1], down).unwrap();
    assert!(!task.motion_bits(link).ip);
}

#[test]
fn a_reassignment_while_master_driven_motion_runs_is_pending_until_it_ends() {
    let (mut task, cs, m, axes) = setup();
    let other = task.add_axis(AxisConfig::new("M2", AxisKind::Linear), 0.0).unwrap();
    let first = task.add_instruction("First");
    task.mdcc(cs, m, first, 1, 0.0).unwrap();
    let mv = task.add_coord_instruction("Mv", cs, line());
    task.set_coord_instruction(mv, true, line());
    task.update();
    let second = task.add_instruction("Second");
    task.mdcc(cs, other, second, 1, 0.0).unwrap();
    assert!(task.motion_bits(second).dn && task.motion_bits(second).ip);
    assert_eq!(
        task.coordinate_system_master(cs),
        Some(m),
        "pending: the move follows M"
    );
    let mut master = 0.0;
    while !task.coord_bits(mv).pc {
        master += 1.0;
        task.axes[m.0 as usize].command.position = master;
        task.update();
        assert!(master < 100.0);
    }
    assert!((task.axis_state(axes[0]).command_position - 10.0).abs() < 1e-9);
    task.update();
    assert_eq!(task.coordinate_system_master(cs), Some(other));
    assert!(!task.motion_bits(first).ip && task.motion_bits(second).ip);
}
