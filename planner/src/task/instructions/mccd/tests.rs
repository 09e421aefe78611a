//! MCCD through the task: the active move slowed with no step, the pending
//! move changed with scope active and pending (and not without it), and
//! each operand's ERR 13.

use super::*;
use crate::axis::{AxisConfig, AxisKind};
use crate::coord::CoordMoveInputs;
use crate::dynamics::MoveDynamics;
use crate::instruction::LogixFault;
use crate::task::{AxisHandle, CoordCall, CoordInstructionHandle};

const DT: f64 = 0.004;

fn gantry() -> (MotionTask, CoordHandle, Vec<AxisHandle>) {
    let mut task = MotionTask::new(DT).unwrap();
    let axes: Vec<AxisHandle> = ["X", "Y"]
        .iter()
        .map(|n| {
            let config = AxisConfig {
                max_velocity: 1000.0,
                max_acceleration: 10_000.0,
                max_deceleration: 10_000.0,
                ..AxisConfig::new(*n, AxisKind::Linear)
            };
            task.add_axis(config, 0.0).unwrap()
        })
        .collect();
    let cs = task
        .add_coordinate_system(
            CoordinateSystemConfig {
                axis_count: 2,
                primary_axes: 2,
                max_speed: 100.0,
                max_accel: 1000.0,
                max_decel: 1000.0,
                max_accel_jerk: 10_000.0,
                max_decel_jerk: 10_000.0,
                command_tolerance: 0.5,
                actual_tolerance: 0.01,
                ..CoordinateSystemConfig::new("CS")
            },
            &axes,
        )
        .unwrap();
    (task, cs, axes)
}

/// An S-curve line to `position` at 20 units/s, 100 units/s², jerk 1000.
fn line(position: &[f64]) -> CoordCall {
    CoordCall::Mclm(CoordMoveInputs {
        position: position.to_vec(),
        termination_type: 1,
        dynamics: MoveDynamics {
            speed: 20.0,
            accel_rate: 100.0,
            decel_rate: 100.0,
            profile: 1,
            accel_jerk: 1000.0,
            decel_jerk: 1000.0,
            jerk_units: 0,
            ..CoordMoveInputs::default().dynamics
        },
        ..Default::default()
    })
}

fn start(task: &mut MotionTask, cs: CoordHandle, name: &str, to: &[f64]) -> CoordInstructionHandle {
    let call = line(to);
    let h = task.add_coord_instruction(name, cs, call.clone());
    task.set_coord_instruction(h, true, call);
    h
}

fn path_speed(task: &MotionTask, axes: &[AxisHandle]) -> f64 {
    axes.iter()
        .map(|a| task.axis_state(*a).command_velocity.powi(2))
        .sum::<f64>()
        .sqrt()
}

#[test]
fn mccd_speeds_the_active_move_up_with_no_step_and_scope_reaches_the_pending_one() {
    let (mut task, cs, axes) = gantry();
    let first = start(&mut task, cs, "M1", &[40.0, 0.0]);
    task.update();
    let second = start(&mut task, cs, "M2", &[40.0, 40.0]);
    for _ in 0..150 {
        task.update();
    }
    assert!((path_speed(&task, &axes) - 20.0).abs() < 1e-9);
    assert!(task.coord_status(cs).move_pending);
    let change = task.add_instruction("Change");
    let o = MccdOperands {
        speed: Change::to(50.0),
        speed_units: 1,
        decel_jerk: Change::to(200.0),
        scope: 1,
        ..MccdOperands::default()
    };
    task.mccd(cs, change, &o).unwrap();
    assert!(task.motion_bits(change).dn && !task.motion_bits(change).ip);
    // 50 % of the system's maximum speed (100): the move speeds up from
    // 20 with no step in the path speed.
    let mut last = path_speed(&task, &axes);
    let mut peak: f64 = 0.0;
    while !task.coord_bits(first).pc {
        task.update();
        let v = path_speed(&task, &axes);
        assert!((v - last).abs() <= 100.0 * DT + 1e-9, "{last} → {v}");
        peak = peak.max(v);
        last = v;
    }
    assert!((peak - 50.0).abs() < 1e-6 || peak < 50.0, "{peak}");
    assert!(peak > 20.0 + 1.0, "the active move ran faster: {peak}");
    // The pending move runs at the new speed too.
    let mut second_peak: f64 = 0.0;
    while !task.coord_bits(second).pc {
        task.update();
        second_peak = second_peak.max(path_speed(&task, &axes));
    }
    assert!((second_peak - 50.0).abs() < 1e-6, "{second_peak}");
}

#[test]
fn scope_active_leaves_the_pending_move_as_it_was() {
    let (mut task, cs, axes) = gantry();
    let first = start(&mut task, cs, "M1", &[40.0, 0.0]);
    task.update();
    let second = start(&mut task, cs, "M2", &[40.0, 40.0]);
    for _ in 0..150 {
        task.update();
    }
    let change = task.add_instruction("Change");
    let o = MccdOperands {
        speed: Change::to(10.0),
        ..MccdOperands::default()
    };
    task.mccd(cs, change, &o).unwrap();
    let mut first_tail: f64 = 0.0;
    let mut k = 0;
    let mut last = path_speed(&task, &axes);
    while !task.coord_bits(first).pc {
        task.update();
        let v = path_speed(&task, &axes);
        assert!((v - last).abs() <= 100.0 * DT + 1e-9, "no step: {last} → {v}");
        last = v;
        k += 1;
        if k > 60 {
            first_tail = first_tail.max(path_speed(&task, &axes));
        }
    }
    assert!(first_tail <= 10.0 + 1e-9, "the active move runs at 10: {first_tail}");
    let mut second_peak: f64 = 0.0;
    while !task.coord_bits(second).pc {
        task.update();
        second_peak = second_peak.max(path_speed(&task, &axes));
    }
    assert!(
        (second_peak - 20.0).abs() < 1e-6,
        "the pending move keeps 20: {second_peak}"
    );
    // Both end where they were programmed to.
    assert!((task.axis_state(axes[0]).command_position - 40.0).abs() < 1e-9);
    assert!((task.axis_state(axes[1]).command_position - 40.0).abs() < 1e-9);
}

#[test]
fn speed_0_holds_the_active_move_on_its_path_until_a_speed_resumes_it() {
    let (mut task, cs, axes) = gantry();
    let first = start(&mut task, cs, "M1", &[40.0, 0.0]);
    task.update();
    let second = start(&mut task, cs, "M2", &[40.0, 40.0]);
    for _ in 0..150 {
        task.update();
    }
    let change = task.add_instruction("Change");
    let hold = MccdOperands {
        speed: Change::to(0.0),
        ..MccdOperands::default()
    };
    task.mccd(cs, change, &hold).unwrap();
    let mut last = path_speed(&task, &axes);
    for _ in 0..300 {
        task.update();
        let v = path_speed(&task, &axes);
        assert!(last - v <= 100.0 * DT + 1e-9 && v <= last + 1e-9, "{last} → {v}");
        last = v;
    }
    let held_at = task.axis_state(axes[0]).command_position;
    assert_eq!(path_speed(&task, &axes), 0.0);
    assert!(held_at < 40.0, "held short of the end: {held_at}");
    assert!(
        task.coord_bits(first).ip && !task.coord_bits(first).pc,
        "still in process"
    );
    assert!(task.coord_status(cs).move_pending, "the pending move waits");
    // Changing a rate keeps it held; a speed resumes it to its end.
    let slower = MccdOperands {
        decel: Change::to(50.0),
        ..MccdOperands::default()
    };
    task.mccd(cs, change, &slower).unwrap();
    for _ in 0..50 {
        task.update();
    }
    assert_eq!(task.axis_state(axes[0]).command_position, held_at);
    let resume = MccdOperands {
        speed: Change::to(20.0),
        ..MccdOperands::default()
    };
    task.mccd(cs, change, &resume).unwrap();
    let mut k = 0;
    while !task.coord_bits(second).pc {
        task.update();
        k += 1;
        assert!(k < 5000);
    }
    assert!(task.coord_bits(first).pc);
    assert!((task.axis_state(axes[0]).command_position - 40.0).abs() < 1e-9);
    assert!((task.axis_state(axes[1]).command_position - 40.0).abs() < 1e-9);
}

#[test]
fn each_operand_out_of_range_names_its_faceplate_index() {
    let (task, cs, _) = gantry();
    let sys = task.coord_config(cs);
    let ok = MccdOperands::default();
    let exerr = |o: MccdOperands| Mccd::new(&o, sys).unwrap_err().exerr();
    let yes = Change::to;
    let flag = |f| Change { flag: f, value: 1.0 };
    assert_eq!(exerr(MccdOperands { motion_type: 1, ..ok }), 2);
    assert_eq!(exerr(MccdOperands { speed: flag(2), ..ok }), 3);
    assert_eq!(exerr(MccdOperands { speed: yes(-1.0), ..ok }), 4);
    assert_eq!(
        exerr(MccdOperands {
            speed: yes(1.0),
            speed_units: 4,
            ..ok
        }),
        5
    );
    assert_eq!(exerr(MccdOperands { accel: flag(-1), ..ok }), 6);
    assert_eq!(
        exerr(MccdOperands {
            accel: yes(f64::NAN),
            ..ok
        }),
        7
    );
    assert_eq!(
        exerr(MccdOperands {
            accel: yes(1.0),
            accel_units: 2,
            ..ok
        }),
        8
    );
    assert_eq!(exerr(MccdOperands { decel: flag(5), ..ok }), 9);
    assert_eq!(exerr(MccdOperands { decel: yes(-3.0), ..ok }), 10);
    assert_eq!(
        exerr(MccdOperands {
            decel: yes(1.0),
            decel_units: 7,
            ..ok
        }),
        11
    );
    assert_eq!(
        exerr(MccdOperands {
            accel_jerk: flag(3),
            ..ok
        }),
        12
    );
    assert_eq!(
        exerr(MccdOperands {
            accel_jerk: yes(0.0),
            ..ok
        }),
        13
    );
    assert_eq!(
        exerr(MccdOperands {
            decel_jerk: flag(4),
            ..ok
        }),
        14
    );
    assert_eq!(
        exerr(MccdOperands {
            decel_jerk: yes(101.0),
            jerk_units: 2,
            ..ok
        }),
        15
    );
    assert_eq!(
        exerr(MccdOperands {
            decel_jerk: yes(1.0),
            jerk_units: 4,
            ..ok
        }),
        16
    );
    assert_eq!(exerr(MccdOperands { scope: 2, ..ok }), 17);
    // Unchanged values are not checked; no motion: .DN, nothing changes.
    assert!(
        Mccd::new(
            &MccdOperands {
                speed: Change { flag: 0, value: -1.0 },
                ..ok
            },
            sys
        )
        .is_ok()
    );
    let (mut task, cs, _) = gantry();
    let change = task.add_instruction("Change");
    task.mccd(cs, change, &MccdOperands { speed: yes(5.0), ..ok }).unwrap();
    assert!(task.motion_bits(change).dn);
}
