//! Rejection of started coordinated moves (the twin's pre-flight sweep):
//! undone bit for bit in the update they start in, braked otherwise.

use super::*;
use crate::axis::{AxisConfig, AxisKind};
use crate::coord::{CoordMoveInputs, CoordinateSystemConfig};
use crate::dynamics::MoveDynamics;
use crate::mccm::MccmInputs;
use crate::task::engine::CoordCall;
use crate::task::handles::AxisHandle;

const DT: f64 = 0.004;

fn xy(start: [f64; 2]) -> (MotionTask, CoordHandle, Vec<AxisHandle>) {
    let mut task = MotionTask::new(DT).unwrap();
    let axes: Vec<AxisHandle> = ["X", "Y"]
        .iter()
        .zip(start)
        .map(|(n, p)| task.add_axis(AxisConfig::new(*n, AxisKind::Linear), p).unwrap())
        .collect();
    let config = CoordinateSystemConfig {
        axis_count: 2,
        primary_axes: 2,
        max_speed: 100.0,
        max_accel: 1000.0,
        max_decel: 1000.0,
        command_tolerance: 0.5,
        ..CoordinateSystemConfig::new("CS")
    };
    let cs = task.add_coordinate_system(config, &axes).unwrap();
    (task, cs, axes)
}

fn common(position: [f64; 2], termination_type: i64) -> CoordMoveInputs {
    CoordMoveInputs {
        position: position.to_vec(),
        termination_type,
        dynamics: MoveDynamics {
            speed: 10.0,
            accel_rate: 50.0,
            decel_rate: 50.0,
            ..CoordMoveInputs::default().dynamics
        },
        ..Default::default()
    }
}

/// An arc from `from` via `from + (1, 1)` to `from + (2, 0)`.
fn arc(from: [f64; 2], termination_type: i64) -> CoordCall {
    CoordCall::Mccm(MccmInputs {
        common: common([from[0] + 2.0, from[1]], termination_type),
        circle_type: 0,
        via_center_radius: vec![from[0] + 1.0, from[1] + 1.0],
        direction: 0,
    })
}

fn line(to: [f64; 2], termination_type: i64) -> CoordCall {
    CoordCall::Mclm(common(to, termination_type))
}

fn bits(task: &MotionTask, axes: &[AxisHandle]) -> Vec<u64> {
    axes.iter()
        .flat_map(|a| {
            let s = task.axis_state(*a);
            [
                s.command_position,
                s.command_velocity,
                s.command_acceleration,
                s.actual_position,
            ]
        })
        .map(f64::to_bits)
        .collect()
}

#[test]
fn an_arc_rejected_in_its_first_update_leaves_the_axes_bit_identical() {
    let start = [0.3, -0.7];
    let (mut task, cs, axes) = xy(start);
    task.update();
    let before = bits(&task, &axes);
    let mc = task.add_coord_instruction("MC1", cs, arc(start, 0));
    task.set_coord_instruction(mc, true, arc(start, 0));
    task.update();
    assert_ne!(bits(&task, &axes), before, "the arc's first setpoint is written");
    let started = task.coord_moves_started();
    assert_eq!(started.len(), 1);
    assert_eq!((started[0].instruction, started[0].system), (mc, cs));
    assert_eq!(started[0].progress, DT);
    assert!(started[0].mv.path().arc().is_some());
    assert!(task.reject_coord_move(mc));
    assert_eq!(bits(&task, &axes), before);
    let b = task.coord_bits(mc);
    assert!(b.en && b.er && !b.dn && !b.ip && !b.ac && !b.pc, "{b:?}");
    assert_eq!((b.err, b.exerr), (ERR_PATH_COLLISION, 0));
    let st = task.coord_status(cs);
    assert!(!st.motion && !st.move_ && !st.accel && !st.move_pending, "{st:?}");
    assert!(axes.iter().all(|a| !task.coordinated_motion_status(*a)));
    for _ in 0..300 {
        task.update();
        assert_eq!(bits(&task, &axes), before);
        assert!(task.coord_moves_started().is_empty());
    }
    // .EN clears with the rung; the error stays until the next execution.
    task.set_coord_rung(mc, false);
    task.update();
    let b = task.coord_bits(mc);
    assert!(!b.en && b.er, "{b:?}");
    assert!(!task.reject_coord_move(mc), "nothing left to reject");
    // The same arc runs normally afterwards, from where the axes stand.
    task.set_coord_instruction(mc, true, arc(start, 0));
    for _ in 0..2000 {
        task.update();
        if task.coord_bits(mc).pc {
            break;
        }
    }
    assert!(task.coord_bits(mc).pc && !task.coord_bits(mc).er);
    assert_eq!(task.axis_state(axes[0]).command_position, start[0] + 2.0);
    assert_eq!(task.axis_state(axes[1]).command_position, start[1]);
}

#[test]
fn a_move_queued_behind_a_rejected_one_is_cancelled_without_error() {
    let (mut task, cs, axes) = xy([0.0, 0.0]);
    let before = bits(&task, &axes);
    let first = task.add_instruction("MC1");
    let second = task.add_instruction("MC2");
    let _ = task.execute_coordinated(cs, first, line([1.0, 0.0], 0));
    let _ = task.execute_coordinated(cs, second, line([1.0, 1.0], 0));
    assert!(task.coord_status(cs).move_pending);
    let h = task.coord_instruction_of(first).unwrap();
    assert!(task.reject_coord_move(h));
    assert_eq!(bits(&task, &axes), before, "nothing written yet");
    let b = task.motion_bits(second);
    assert!(b.dn && !b.ip && !b.er, "{b:?}");
    assert!(!task.coord_status(cs).move_pending);
    for _ in 0..100 {
        task.update();
        assert_eq!(bits(&task, &axes), before);
    }
}

#[test]
fn a_rejected_pending_move_leaves_the_queue_and_the_running_one_ends_on_its_point() {
    let (mut task, cs, axes) = xy([0.0, 0.0]);
    let first = task.add_instruction("MC1");
    let second = task.add_instruction("MC2");
    let _ = task.execute_coordinated(cs, first, line([1.0, 0.0], 2));
    let _ = task.execute_coordinated(cs, second, line([1.0, 1.0], 2));
    task.update();
    let h2 = task.coord_instruction_of(second).unwrap();
    assert!(task.reject_coord_move(h2));
    assert!(!task.coord_status(cs).move_pending);
    let b = task.motion_bits(second);
    assert!(b.er && !b.dn && !b.ip && b.err == ERR_PATH_COLLISION, "{b:?}");
    for _ in 0..1000 {
        task.update();
    }
    assert!(task.motion_bits(first).pc);
    assert_eq!(task.axis_state(axes[0]).command_position, 1.0);
    assert_eq!(task.axis_state(axes[1]).command_position, 0.0);
    // The queue continues from the first move's end.
    let third = task.add_instruction("MC3");
    let _ = task.execute_coordinated(cs, third, line([1.0, 2.0], 0));
    for _ in 0..2000 {
        task.update();
    }
    assert!(task.motion_bits(third).pc);
    assert_eq!(task.axis_state(axes[1]).command_position, 2.0);
}

#[test]
fn a_rejected_blend_successor_brakes_along_its_path_and_the_first_move_completes() {
    let (mut task, cs, axes) = xy([0.0, 0.0]);
    let first = task.add_instruction("MC1");
    let second = task.add_instruction("MC2");
    let _ = task.execute_coordinated(cs, first, line([1.0, 0.0], 2));
    let _ = task.execute_coordinated(cs, second, arc([1.0, 0.0], 0));
    let h2 = task.coord_instruction_of(second).unwrap();
    let mut updates = 0;
    while task.coord_moves_started().iter().all(|m| m.instruction != h2) {
        task.update();
        updates += 1;
        assert!(updates < 2000, "the arc starts at the blend point");
    }
    assert!(task.motion_bits(first).pc, "the blend has started");
    assert!(task.reject_coord_move(h2));
    let b = task.motion_bits(second);
    assert!(b.er && !b.ip && !b.ac && !b.dn, "{b:?}");
    let mut previous = task.axis_state(axes[1]).command_position;
    for _ in 0..1000 {
        task.update();
        let y = task.axis_state(axes[1]).command_position;
        assert!(
            y.is_finite() && (y - previous).abs() <= 10.0 * DT * (1.0 + 1e-9),
            "continuous"
        );
        previous = y;
    }
    let st = task.coord_status(cs);
    assert!(!st.motion, "at rest: {st:?}");
    // The arc was braked early: it barely left the first move's end point.
    let x = task.axis_state(axes[0]).command_position;
    let y = task.axis_state(axes[1]).command_position;
    assert!((x - 1.0).abs() < 0.1 && y.abs() < 0.1, "({x}, {y})");
    assert!(axes.iter().all(|a| task.axis_state(*a).command_velocity == 0.0));
}

#[test]
fn a_move_rejected_after_its_first_update_brakes_within_its_deceleration() {
    let (mut task, cs, axes) = xy([0.0, 0.0]);
    let mc = task.add_instruction("MC1");
    let _ = task.execute_coordinated(cs, mc, line([0.0, 5.0], 0));
    for _ in 0..100 {
        task.update();
    }
    let h = task.coord_instruction_of(mc).unwrap();
    assert!(task.coord_moves_started().is_empty());
    let y0 = task.axis_state(axes[1]).command_position;
    assert!(y0 > 0.1);
    assert!(task.reject_coord_move(h));
    assert!(task.motion_bits(mc).er);
    let mut v_prev = task.axis_state(axes[1]).command_velocity;
    for _ in 0..1000 {
        task.update();
        let v = task.axis_state(axes[1]).command_velocity;
        assert!(v >= 0.0 && v <= v_prev + 1e-12);
        assert!((v_prev - v) / DT <= 50.0 * (1.0 + 1e-6), "{v_prev} -> {v}");
        v_prev = v;
    }
    let y = task.axis_state(axes[1]).command_position;
    assert!(y > y0 && y < 5.0, "braked along the path: {y}");
    assert_eq!(v_prev, 0.0);
}

#[test]
fn a_move_executed_between_updates_is_reported_and_undone_after_the_next_update() {
    let (mut task, cs, axes) = xy([0.0, 0.0]);
    task.update();
    let before = bits(&task, &axes);
    let mc = task.add_instruction("MC1");
    let _ = task.execute_coordinated(cs, mc, arc([0.0, 0.0], 0));
    assert!(task.coord_moves_started().is_empty(), "not advanced yet");
    task.update();
    let h = task.coord_instruction_of(mc).unwrap();
    let started = task.coord_moves_started();
    assert_eq!((started.len(), started[0].instruction, started[0].progress), (1, h, DT));
    task.update();
    assert!(task.coord_moves_started().is_empty(), "reported once");
    // Rejected after its second update it brakes; after its first it is undone.
    assert!(task.reject_coord_move(h));
    task.update();
    assert_ne!(bits(&task, &axes), before);
    let (mut fresh, cs2, axes2) = xy([0.0, 0.0]);
    fresh.update();
    let mc2 = fresh.add_instruction("MC1");
    let _ = fresh.execute_coordinated(cs2, mc2, arc([0.0, 0.0], 0));
    fresh.update();
    assert!(fresh.reject_coord_move(fresh.coord_instruction_of(mc2).unwrap()));
    for _ in 0..50 {
        fresh.update();
        assert_eq!(bits(&fresh, &axes2), before);
    }
}
