//! Coordinated motion through the task: instruction bits, status bits,
//! blending per termination type, the queue, merge, MCS, master-driven
//! moves, single-axis interplay and seeded random arcs end to end.

use super::*;
use crate::axis::{AxisConfig, AxisKind};
use crate::coord::{CoordMoveInputs, CoordinateSystemConfig, LockDirection, McsInputs, primary_of};
use crate::dynamics::MoveDynamics;
use crate::mccm::MccmInputs;
use crate::modulo::{McBufferMode, McDirection, MoveModuloInputs};
use crate::task::engine::{ERR_IDLE_MASTER_SLAVE_MOVING, Lock};
use crate::task::handles::FbHandle;
use crate::vector::norm;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

const DT: f64 = 0.004;

fn gantry(primary: usize, extra: usize) -> (MotionTask, CoordHandle, Vec<AxisHandle>) {
    let mut task = MotionTask::new(DT).unwrap();
    let names = ["X", "Y", "Z", "A", "B"];
    let axes: Vec<AxisHandle> = (0..primary + extra)
        .map(|i| task.add_axis(AxisConfig::new(names[i], AxisKind::Linear), 0.0).unwrap())
        .collect();
    let cs = task
        .add_coordinate_system(
            CoordinateSystemConfig {
                axis_count: primary + extra,
                primary_axes: primary,
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
    (task, cs, axes)
}

/// Speed and rates per master unit (units 4), a master-driven move.
fn per_master_unit(speed: f64, rate: f64) -> MoveDynamics {
    MoveDynamics {
        speed,
        speed_units: 4,
        accel_rate: rate,
        accel_units: 4,
        decel_rate: rate,
        decel_units: 4,
        ..CoordMoveInputs::default().dynamics
    }
}

fn line(position: &[f64], termination_type: i64) -> CoordMoveInputs {
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

fn fire(task: &mut MotionTask, h: CoordInstructionHandle, call: CoordCall) {
    task.set_coord_instruction(h, true, call);
}

fn positions(task: &MotionTask, axes: &[AxisHandle]) -> Vec<f64> {
    axes.iter().map(|a| task.axis_state(*a).command_position).collect()
}

fn speed(task: &MotionTask, axes: &[AxisHandle], primary: usize) -> f64 {
    axes[..primary]
        .iter()
        .map(|a| task.axis_state(*a).command_velocity.powi(2))
        .sum::<f64>()
        .sqrt()
}

fn run_until(task: &mut MotionTask, max: usize, mut done: impl FnMut(&MotionTask) -> bool) -> usize {
    for k in 0..max {
        task.update();
        if done(task) {
            return k + 1;
        }
    }
    panic!("not done after {max} updates");
}

#[test]
fn a_full_circle_sets_and_clears_every_bit_in_order() {
    let (mut task, cs, axes) = gantry(2, 0);
    let call = CoordCall::Mccm(MccmInputs {
        common: line(&[0.0, 0.0], 1),
        circle_type: 3,
        via_center_radius: vec![0.0, 2.0],
        direction: 1,
    });
    let mc = task.add_coord_instruction("MC1", cs, call.clone());
    fire(&mut task, mc, call);
    task.update();
    let b = task.coord_bits(mc);
    assert!(b.en && b.dn && b.ip && b.ac && !b.pc && !b.er && b.accel && !b.decel);
    let st = task.coord_status(cs);
    assert!(st.motion && st.move_ && st.accel && !st.decel && !st.move_pending);
    assert!(axes.iter().all(|a| task.coordinated_motion_status(*a)));
    let (mut saw_decel, mut saw_cruise) = (false, false);
    let mut max_radius_error: f64 = 0.0;
    let n = run_until(&mut task, 10_000, |t| {
        let b = t.coord_bits(mc);
        saw_decel |= b.decel && t.coord_status(cs).decel;
        saw_cruise |= b.ip && !b.accel && !b.decel;
        b.pc
    });
    assert!(saw_decel && saw_cruise && n > 100);
    let b = task.coord_bits(mc);
    assert!(b.pc && !b.ip && !b.ac && !b.accel && !b.decel && b.dn && b.en);
    let st = task.coord_status(cs);
    assert!(!st.motion && !st.move_ && !st.accel && !st.decel && st.command_pos_tolerance);
    assert!(!task.coordinated_motion_status(axes[0]));
    assert_eq!(
        positions(&task, &axes),
        vec![0.0, 0.0],
        "a full circle ends at its start"
    );
    // Rung false clears .EN (DN is set).
    task.set_coord_rung(mc, false);
    task.update();
    assert!(!task.coord_bits(mc).en && task.coord_bits(mc).pc);
    // Every update of a second circle stays on it.
    let mut task2 = gantry(2, 0).0;
    let mc2 = task2.add_coord_instruction("MC2", cs, CoordCall::Mcs(McsInputs::default()));
    let circle = CoordCall::Mccm(MccmInputs {
        common: line(&[0.0, 0.0], 1),
        circle_type: 3,
        via_center_radius: vec![0.0, 2.0],
        direction: 2,
    });
    fire(&mut task2, mc2, circle);
    run_until(&mut task2, 10_000, |t| {
        let p = positions(t, &axes);
        max_radius_error = max_radius_error.max(((p[0]).hypot(p[1] - 2.0) - 2.0).abs());
        t.coord_bits(mc2).pc
    });
    assert!(max_radius_error < 1e-9, "{max_radius_error}");
}

/// Runs line (0,0)→(10,0) with `tt`, then (10,0)→(10,10) queued behind it.
/// Returns the path speeds per update, the distance to go and the speed of
/// the first move at its blend point (if it blended), and the final position.
fn two_lines(tt: i64, command_tolerance: f64) -> (Vec<f64>, Option<(f64, f64)>, Vec<f64>) {
    let (mut task, cs, axes) = gantry(2, 0);
    let mut first_inputs = line(&[10.0, 0.0], tt);
    first_inputs.command_tolerance = command_tolerance;
    let first = CoordCall::Mclm(first_inputs);
    let second = CoordCall::Mclm(line(&[10.0, 10.0], 1));
    let a = task.add_coord_instruction("A", cs, first.clone());
    let b = task.add_coord_instruction("B", cs, second.clone());
    fire(&mut task, a, first);
    fire(&mut task, b, second);
    task.update();
    assert!(task.coord_status(cs).move_pending && task.coord_status(cs).move_pending_queue_full);
    assert!(task.coord_bits(b).dn && task.coord_bits(b).ip && !task.coord_bits(b).ac);
    let mut speeds = vec![speed(&task, &axes, 2)];
    let mut blend_to_go = None;
    let mut saw_transition = false;
    run_until(&mut task, 20_000, |t| {
        speeds.push(speed(t, &axes, 2));
        let sys = &t.coord.systems[cs.0 as usize];
        if sys.components.len() == 2 {
            // AccelStatus and DecelStatus clear while a blend is in process.
            assert!(!t.coord_status(cs).accel && !t.coord_status(cs).decel);
        }
        if sys.components.len() == 2 && blend_to_go.is_none() {
            let c = &sys.components[0];
            let at = c.blend_at.unwrap();
            let there = c.profile.sample(at);
            blend_to_go = Some((c.mv.path().length() - there.position, there.velocity));
            // The first move's .PC at the blend point, its .IP until it ends.
            let ba = t.coord_bits(a);
            assert!(ba.pc && ba.ip && !ba.ac);
            assert!(t.coord_bits(b).ac && !t.coord_status(cs).move_pending);
        }
        saw_transition |= t.coord_status(cs).move_transition;
        t.coord_bits(b).pc
    });
    assert!(task.coord_bits(a).pc && !task.coord_bits(a).ip);
    assert_eq!(
        saw_transition,
        blend_to_go.is_some(),
        "MoveTransitionStatus while blending a corner"
    );
    (speeds, blend_to_go, positions(&task, &axes))
}

fn stops_between(speeds: &[f64]) -> bool {
    let first = speeds.iter().position(|v| *v > 1e-9).unwrap();
    let last = speeds.iter().rposition(|v| *v > 1e-9).unwrap();
    speeds[first..=last].iter().any(|v| *v <= 1e-9)
}

#[test]
fn termination_0_and_1_stop_at_the_junction() {
    for tt in [0, 1] {
        let (speeds, blend, end) = two_lines(tt, 0.0);
        assert!(blend.is_none());
        assert!(stops_between(&speeds), "tt {tt}");
        assert_eq!(end, vec![10.0, 10.0]);
    }
}

#[test]
fn termination_3_blends_from_the_deceleration_point() {
    let (speeds, blend, end) = two_lines(3, 0.0);
    // Decel distance at 10 units/s and 50 units/s²: v²/2d = 1.
    assert!((blend.unwrap().0 - 1.0).abs() < 1e-9, "{blend:?}");
    assert!(!stops_between(&speeds));
    assert_eq!(end, vec![10.0, 10.0]);
    // Never faster than programmed: the corner's speed is the vector sum.
    assert!(speeds.iter().all(|v| *v <= 10.0 * (1.0 + 1e-9)));
}

#[test]
fn termination_2_blends_at_the_systems_command_tolerance() {
    // System tolerance 0.5 < decel distance 1: the blend starts 0.5 before the end.
    let (speeds, blend, end) = two_lines(2, 7.0);
    assert!((blend.unwrap().0 - 0.5).abs() < 1e-9, "{blend:?}");
    assert!(!stops_between(&speeds));
    assert_eq!(end, vec![10.0, 10.0]);
}

#[test]
fn termination_6_blends_at_the_operands_command_tolerance() {
    let (speeds, blend, _) = two_lines(6, 0.25);
    assert!((blend.unwrap().0 - 0.25).abs() < 1e-9, "{blend:?}");
    assert!(blend.unwrap().1 > 0.0);
    assert!(!stops_between(&speeds));
    // A tolerance longer than the deceleration distance defers to the decel point.
    let (_, blend, _) = two_lines(6, 3.0);
    assert!((blend.unwrap().0 - 1.0).abs() < 1e-9, "{blend:?}");
    // Zero tolerance blends at the end point, where the first move is at rest.
    let (mut task, cs, _) = gantry(2, 0);
    let call = CoordCall::Mclm(CoordMoveInputs {
        command_tolerance: 0.0,
        ..line(&[10.0, 0.0], 6)
    });
    let h = task.add_coord_instruction("A", cs, call.clone());
    fire(&mut task, h, call);
    task.update();
    let c = &task.coord.systems[cs.0 as usize].components[0];
    assert_eq!(c.blend_at, Some(c.profile.duration_s()));
    assert_eq!(c.profile.sample(c.profile.duration_s()).velocity, 0.0);
}

#[test]
fn line_arc_line_blends_with_termination_2_and_ends_exactly() {
    let (mut task, cs, axes) = gantry(2, 0);
    let calls = [
        CoordCall::Mclm(line(&[10.0, 0.0], 2)),
        CoordCall::Mccm(MccmInputs {
            common: line(&[15.0, 5.0], 2),
            circle_type: 2,
            via_center_radius: vec![5.0],
            direction: 1,
        }),
        CoordCall::Mclm(line(&[15.0, 15.0], 1)),
    ];
    let hs: Vec<_> = calls
        .iter()
        .enumerate()
        .map(|(i, c)| task.add_coord_instruction(format!("M{i}"), cs, c.clone()))
        .collect();
    for (h, c) in hs.iter().zip(&calls) {
        fire(&mut task, *h, c.clone());
    }
    task.update();
    // The third is held: only .EN until the queue has room.
    let b3 = task.coord_bits(hs[2]);
    assert!(b3.en && !b3.dn && !b3.ip && !b3.er);
    let mut speeds = Vec::new();
    run_until(&mut task, 20_000, |t| {
        speeds.push(speed(t, &axes, 2));
        t.coord_bits(hs[2]).pc
    });
    assert!(!stops_between(&speeds));
    assert!(hs.iter().all(|h| task.coord_bits(*h).pc && task.coord_bits(*h).dn));
    assert_eq!(positions(&task, &axes), vec![15.0, 15.0]);
    assert!(!task.coord_status(cs).motion);
}

#[test]
fn termination_0_waits_for_the_actual_position() {
    let (mut task, cs, axes) = gantry(2, 0);
    let call = CoordCall::Mclm(line(&[1.0, 0.0], 0));
    let h = task.add_coord_instruction("M", cs, call.clone());
    fire(&mut task, h, call);
    for _ in 0..2000 {
        task.feed_actual_position(axes[0], 0.5);
        task.feed_actual_position(axes[1], 0.0);
        task.update();
    }
    assert!(!task.coord_bits(h).pc && task.coord_bits(h).ip);
    assert!(!task.coord_status(cs).actual_pos_tolerance);
    task.feed_actual_position(axes[0], 0.995);
    task.update();
    assert!(task.coord_bits(h).pc && task.coord_status(cs).actual_pos_tolerance);
}

#[test]
fn merge_replaces_the_motion_and_cancels_the_pending_move() {
    let (mut task, cs, axes) = gantry(2, 0);
    let a_call = CoordCall::Mclm(line(&[100.0, 0.0], 1));
    let b_call = CoordCall::Mclm(line(&[100.0, 100.0], 1));
    let mut merge_inputs = line(&[0.0, 50.0], 1);
    merge_inputs.merge = 1;
    merge_inputs.merge_speed = 1;
    merge_inputs.dynamics.speed = 30.0;
    let m_call = CoordCall::Mclm(merge_inputs);
    let a = task.add_coord_instruction("A", cs, a_call.clone());
    let b = task.add_coord_instruction("B", cs, b_call.clone());
    let m = task.add_coord_instruction("M", cs, m_call.clone());
    fire(&mut task, a, a_call);
    fire(&mut task, b, b_call);
    for _ in 0..500 {
        task.update();
    }
    let v_before = speed(&task, &axes, 2);
    assert!((v_before - 10.0).abs() < 1e-9);
    fire(&mut task, m, m_call);
    task.update();
    let (ba, bb, bm) = (task.coord_bits(a), task.coord_bits(b), task.coord_bits(m));
    assert!(!ba.ip && !ba.ac && !ba.pc, "superseded: {ba:?}");
    assert!(!bb.ip && !bb.ac && !bb.pc && bb.dn, "cancelled: {bb:?}");
    assert!(bm.ip && bm.ac && bm.dn);
    assert!(!task.coord_status(cs).move_pending);
    // Merge speed current: the new move runs at the speed the system had.
    let v = task.coord_active_move(cs).unwrap().limits().unwrap().velocity();
    assert!((v - v_before).abs() < 1e-9, "{v}");
    let mut speeds = Vec::new();
    run_until(&mut task, 20_000, |t| {
        speeds.push(speed(t, &axes, 2));
        t.coord_bits(m).pc
    });
    assert!(!stops_between(&speeds));
    assert_eq!(positions(&task, &axes), vec![0.0, 50.0]);
    assert!(!task.coord_bits(b).pc, "a cancelled move never completes");
}

#[test]
fn mcs_stops_along_the_path_and_cancels_the_queue() {
    let (mut task, cs, axes) = gantry(2, 0);
    let a_call = CoordCall::Mclm(line(&[30.0, 40.0], 2));
    let b_call = CoordCall::Mclm(line(&[0.0, 0.0], 1));
    let s_call = CoordCall::Mcs(McsInputs {
        stop_type: 1,
        change_decel: 1,
        decel_rate: 20.0,
        decel_units: 0,
        ..McsInputs::default()
    });
    let a = task.add_coord_instruction("A", cs, a_call.clone());
    let b = task.add_coord_instruction("B", cs, b_call.clone());
    let s = task.add_coord_instruction("S", cs, s_call.clone());
    fire(&mut task, a, a_call);
    fire(&mut task, b, b_call);
    for _ in 0..400 {
        task.update();
    }
    let at_stop = positions(&task, &axes);
    fire(&mut task, s, s_call);
    task.update();
    assert!(task.coord_status(cs).stopping && !task.coord_status(cs).move_pending);
    assert!(task.coord_bits(s).ip && task.coord_bits(s).dn && !task.coord_bits(s).pc);
    assert!(!task.coord_bits(a).ip && !task.coord_bits(a).ac && !task.coord_bits(b).ip);
    let n = run_until(&mut task, 10_000, |t| t.coord_bits(s).pc);
    let end = positions(&task, &axes);
    // 10 units/s braked at 20 units/s²: 2.5 units further along the line (3:4:5).
    let travelled = (end[0] - at_stop[0]).hypot(end[1] - at_stop[1]);
    assert!((travelled - 2.5).abs() < 0.05, "{travelled}");
    assert!((end[1] / end[0] - 4.0 / 3.0).abs() < 1e-9, "on the line");
    assert!(n as f64 * DT < 0.6);
    assert!(!task.coord_status(cs).stopping && !task.coord_status(cs).motion);
    assert!(!task.coord_bits(s).ip && !task.coord_bits(a).pc && !task.coord_bits(b).pc);
    // An MCS on a system at rest completes at once.
    task.set_coord_rung(s, false);
    task.update();
    task.set_coord_rung(s, true);
    task.update();
    assert!(task.coord_bits(s).pc && task.coord_bits(s).dn);
}

#[test]
fn errors_set_er_with_err_and_exerr() {
    let (mut task, cs, _) = gantry(3, 0);
    let call = CoordCall::Mccm(MccmInputs {
        common: line(&[1.0, 1.0, 0.0], 1),
        circle_type: 2,
        via_center_radius: vec![1.0],
        direction: 0,
    });
    let h = task.add_coord_instruction("M", cs, call.clone());
    fire(&mut task, h, call);
    task.update();
    let b = task.coord_bits(h);
    assert!(b.er && !b.dn && !b.ip && b.en && (b.err, b.exerr) == (25, 0));
    assert!(!task.coord_status(cs).motion);
    let bad = CoordCall::Mclm(CoordMoveInputs {
        dynamics: MoveDynamics {
            speed: -1.0,
            ..line(&[1.0, 1.0, 0.0], 1).dynamics
        },
        ..line(&[1.0, 1.0, 0.0], 1)
    });
    task.set_coord_instruction(h, false, bad.clone());
    task.update();
    assert!(!task.coord_bits(h).en);
    fire(&mut task, h, bad);
    task.update();
    let b = task.coord_bits(h);
    assert!(b.er && (b.err, b.exerr) == (13, 4));
}

#[test]
fn non_primary_axes_arrive_with_the_primary_axes() {
    let (mut task, cs, axes) = gantry(2, 1);
    let call = CoordCall::Mccm(MccmInputs {
        common: line(&[4.0, 0.0, 90.0], 1),
        circle_type: 1,
        via_center_radius: vec![2.0, 0.0],
        direction: 0,
    });
    let h = task.add_coord_instruction("M", cs, call.clone());
    fire(&mut task, h, call);
    let mut last_change = vec![0usize; 3];
    let mut prev = positions(&task, &axes);
    let mut k = 0;
    run_until(&mut task, 20_000, |t| {
        k += 1;
        let p = positions(t, &axes);
        for i in 0..3 {
            if p[i] != prev[i] {
                last_change[i] = k;
            }
        }
        prev = p;
        // The vector speed counts only X and Y.
        assert!(speed(t, &axes, 2) <= 10.0 * (1.0 + 1e-9));
        t.coord_bits(h).pc
    });
    assert_eq!(positions(&task, &axes), vec![4.0, 0.0, 90.0]);
    assert!(last_change.iter().all(|k| *k == last_change[0]), "{last_change:?}");
}

/// Seeded random arcs through the task: every axis finishes (has its last
/// non-zero command velocity) in the same coarse update, and the vector speed
/// never exceeds the programmed speed.
#[test]
fn random_arcs_through_the_task_finish_together_within_speed() {
    let mut rng = ChaCha8Rng::seed_from_u64(0x7461_736b);
    for case in 0..200 {
        let (mut task, cs, axes) = gantry(3, 0);
        let center: [f64; 3] = [rng.random_range(-5.0..5.0), rng.random_range(-5.0..5.0), 0.0];
        let radius = (center[0] * center[0] + center[1] * center[1]).sqrt();
        if radius < 0.1 {
            continue;
        }
        let theta = rng.random_range(0.3..6.0_f64);
        let start_angle = (-center[1]).atan2(-center[0]);
        let end = [
            center[0] + radius * (start_angle + theta).cos(),
            center[1] + radius * (start_angle + theta).sin(),
            rng.random_range(-1.0..1.0) * 0.0,
        ];
        let programmed = rng.random_range(1.0..20.0);
        let mut common = line(&end, 1);
        common.dynamics.speed = programmed;
        common.dynamics.profile = rng.random_range(0..2);
        let direction = if theta <= std::f64::consts::PI { 0 } else { 1 };
        let call = CoordCall::Mccm(MccmInputs {
            common,
            circle_type: 1,
            via_center_radius: center.to_vec(),
            direction: direction + 2 * i64::from(rng.random_bool(0.2)),
        });
        let h = task.add_coord_instruction("M", cs, call.clone());
        fire(&mut task, h, call);
        let mut last_change = [0usize; 3];
        let mut k = 0;
        run_until(&mut task, 100_000, |t| {
            k += 1;
            let p = positions(t, &axes);
            for i in 0..3 {
                if t.axis_state(axes[i]).command_velocity != 0.0 {
                    last_change[i] = k;
                }
            }
            assert!(speed(t, &axes, 3) <= programmed * (1.0 + 1e-9), "case {case}");
            let q = [p[0] - center[0], p[1] - center[1], p[2]];
            assert!(((q[0] * q[0] + q[1] * q[1]).sqrt() - radius).abs() < 1e-9);
            t.coord_bits(h).pc
        });
        let moved: Vec<usize> = last_change.iter().copied().filter(|k| *k > 0).collect();
        assert!(moved.windows(2).all(|w| w[0] == w[1]), "case {case}: {last_change:?}");
    }
}

#[test]
fn calculated_data_is_the_time_to_the_event_point() {
    let (mut task, cs, axes) = gantry(2, 0);
    let mut inputs = line(&[20.0, 0.0], 1);
    inputs.event_distance = vec![5.0, 0.0];
    let call = CoordCall::Mclm(inputs);
    let h = task.add_coord_instruction("M", cs, call.clone());
    fire(&mut task, h, call);
    task.update();
    let cd = task.coord_calculated_data(h).to_vec();
    // 20 units, 10 units/s, 50 units/s²: accel 0.2 s (1 unit), cruise to 15 at 1.6 s.
    assert!((cd[0] - 1.6).abs() < 1e-9 && (cd[1] - 2.2).abs() < 1e-9, "{cd:?}");
    let n = run_until(&mut task, 10_000, |t| positions(t, &axes)[0] >= 15.0 - 1e-9);
    assert!((n as f64 * DT - cd[0]).abs() <= DT);
}

fn master_setup(
    lock_direction: i64,
    lock_position: f64,
) -> (
    MotionTask,
    CoordHandle,
    Vec<AxisHandle>,
    AxisHandle,
    FbHandle,
    CoordInstructionHandle,
) {
    let (mut task, cs, axes) = gantry(2, 0);
    let master = task
        .add_axis(
            AxisConfig {
                modulo_period: Some(1000.0),
                max_velocity: 1000.0,
                max_acceleration: 10_000.0,
                max_deceleration: 10_000.0,
                ..AxisConfig::new("Master", AxisKind::Rotary)
            },
            0.0,
        )
        .unwrap();
    task.set_coordinate_system_master(cs, Some(master));
    let fb = task.add_move_modulo("MoveMaster", master);
    let inputs = CoordMoveInputs {
        position: vec![10.0, 0.0],
        termination_type: 1,
        lock_direction,
        lock_position,
        dynamics: per_master_unit(0.1, 0.01),
        ..Default::default()
    };
    let h = task.add_coord_instruction("M", cs, CoordCall::Mclm(inputs.clone()));
    fire(&mut task, h, CoordCall::Mclm(inputs));
    (task, cs, axes, master, fb, h)
}

fn move_master(task: &mut MotionTask, fb: FbHandle, to: f64) {
    task.set_move_modulo_inputs(
        fb,
        MoveModuloInputs {
            execute: false,
            ..Default::default()
        },
    );
    task.update();
    task.set_move_modulo_inputs(
        fb,
        MoveModuloInputs {
            execute: true,
            position: to,
            velocity: 500.0,
            direction: McDirection::Positive,
            buffer_mode: McBufferMode::Aborting,
            ..Default::default()
        },
    );
    run_until(task, 10_000, |t| t.outputs(fb).done);
}

#[test]
fn master_driven_move_advances_with_the_master_not_with_time() {
    let (mut task, cs, axes, _master, fb, h) = master_setup(0, 0.0);
    for _ in 0..500 {
        task.update();
    }
    assert!(
        task.coord_bits(h).ip && positions(&task, &axes)[0] == 0.0,
        "master at rest"
    );
    assert!(
        !task.coord_status(cs).coord_motion_lock,
        "never set for lock direction none"
    );
    move_master(&mut task, fb, 50.0);
    // Path position = the path profile sampled at master distance 50.
    let mv = task.coord_active_move(cs).unwrap().clone();
    let expected = mv.rest_profile().sample(50.0).position;
    assert!((positions(&task, &axes)[0] - expected).abs() < 1e-9);
    move_master(&mut task, fb, 500.0);
    assert!(task.coord_bits(h).pc);
    assert_eq!(positions(&task, &axes), vec![10.0, 0.0]);
}

#[test]
fn position_forward_lock_waits_for_the_master_to_cross() {
    let (mut task, cs, axes, _master, fb, h) = master_setup(3, 100.0);
    move_master(&mut task, fb, 90.0);
    assert_eq!(positions(&task, &axes)[0], 0.0);
    assert!(!task.coord_status(cs).coord_motion_lock && task.coord_bits(h).ip);
    move_master(&mut task, fb, 150.0);
    assert!(task.coord_status(cs).coord_motion_lock);
    let mv = task.coord_active_move(cs).unwrap().clone();
    let expected = mv.rest_profile().sample(50.0).position;
    assert!((positions(&task, &axes)[0] - expected).abs() < 1e-9);
}

#[test]
fn lock_directions_follow_the_spec() {
    // Immediate forward: locked at once; a reversing master is not followed.
    let mut l = Lock::new(LockDirection::ImmediateForwardOnly, 0.0, 10.0);
    assert!(l.locked);
    assert_eq!(l.advance(10.0, 15.0), 5.0);
    assert_eq!(l.advance(15.0, 12.0), 0.0);
    assert!(!l.locked);
    assert_eq!(l.advance(12.0, 14.0), 0.0, "not past where it reversed");
    assert_eq!(l.advance(14.0, 17.0), 2.0);
    assert!(l.locked, "set again when it resumes");
    // Immediate reverse mirrors it.
    let mut l = Lock::new(LockDirection::ImmediateReverseOnly, 0.0, 10.0);
    assert_eq!(l.advance(10.0, 7.0), 3.0);
    assert_eq!(l.advance(7.0, 9.0), 0.0);
    assert!(!l.locked);
    // Position reverse: waits for the master to cross the lock position downwards.
    let mut l = Lock::new(LockDirection::PositionReverse, 5.0, 10.0);
    assert!(!l.locked);
    assert_eq!(l.advance(10.0, 6.0), 0.0);
    assert_eq!(l.advance(6.0, 4.0), 1.0);
    assert!(l.locked);
    // Position forward ignores a crossing in reverse.
    let mut l = Lock::new(LockDirection::PositionForward, 5.0, 10.0);
    assert_eq!(l.advance(10.0, 4.0), 0.0);
    assert_eq!(l.advance(4.0, 7.0), 2.0);
    // None follows both ways and never locks.
    let mut l = Lock::new(LockDirection::None, 0.0, 0.0);
    assert_eq!(l.advance(0.0, 3.0), 3.0);
    assert_eq!(l.advance(3.0, 1.0), -2.0);
    assert!(!l.locked);
}

#[test]
fn coordinated_and_single_axis_motion_abort_each_other() {
    // X has a modulo period so MC_MoveModulo can run on it.
    let mut task = MotionTask::new(DT).unwrap();
    let x = task
        .add_axis(
            AxisConfig {
                modulo_period: Some(360.0),
                max_velocity: 100.0,
                ..AxisConfig::new("X", AxisKind::Linear)
            },
            0.0,
        )
        .unwrap();
    let y = task.add_axis(AxisConfig::new("Y", AxisKind::Linear), 0.0).unwrap();
    let cs = crate::task::tests::two_axis_system(&mut task, "CS", x, y);
    let fb = task.add_move_modulo("MoveX", x);
    task.set_move_modulo_inputs(
        fb,
        MoveModuloInputs {
            execute: true,
            position: 300.0,
            velocity: 10.0,
            ..Default::default()
        },
    );
    task.update();
    assert!(task.outputs(fb).active);
    // A coordinated move takes X: MC_MoveModulo is aborted.
    let call = CoordCall::Mclm(line(&[50.0, 50.0], 1));
    let h = task.add_coord_instruction("M", cs, call.clone());
    fire(&mut task, h, call);
    task.update();
    assert!(task.outputs(fb).command_aborted && task.coord_bits(h).ac);
    for _ in 0..200 {
        task.update();
    }
    // A new MC_MoveModulo takes X back: the coordinated move loses .IP/.AC and
    // Y comes to rest along the path.
    task.set_move_modulo_inputs(fb, MoveModuloInputs::default());
    task.update();
    task.set_move_modulo_inputs(
        fb,
        MoveModuloInputs {
            execute: true,
            position: 100.0,
            velocity: 10.0,
            ..Default::default()
        },
    );
    task.update();
    let b = task.coord_bits(h);
    assert!(!b.ip && !b.ac && !b.pc && task.outputs(fb).active);
    run_until(&mut task, 10_000, |t| !t.coord_status(cs).motion);
    assert!(task.axis_state(y).command_velocity == 0.0);
    assert!(!task.coordinated_motion_status(y));
    run_until(&mut task, 10_000, |t| t.outputs(fb).done);
}

#[test]
fn one_shot_execution_sets_bits_at_once_and_clears_en_after_its_update() {
    let (mut task, cs, axes) = gantry(2, 0);
    let mc = task.add_instruction("MC1");
    let _ = task.execute_coordinated(cs, mc, CoordCall::Mclm(line(&[1.0, 0.0], 1)));
    let b = task.motion_bits(mc);
    assert!(b.en && b.dn && b.ip && b.ac, "set by the scan itself: {b:?}");
    // The update of the executing scan still shows .EN; the next scan's
    // rung is false and clears it (.DN is set).
    task.update();
    assert!(task.motion_bits(mc).en);
    task.update();
    let b = task.motion_bits(mc);
    assert!(!b.en && b.dn && b.ip);
    let h = task.coord_instruction_of(mc).unwrap();
    assert_eq!(task.coord_control(h), mc);
    assert_eq!(task.coord_instruction_name(h), "MC1");
    run_until(&mut task, 10_000, |t| t.motion_bits(mc).pc);
    // The same tag executes again: DN/PC reset by the new scan, then set again.
    let _ = task.execute_coordinated(cs, mc, CoordCall::Mclm(line(&[1.0, 1.0], 1)));
    let b = task.motion_bits(mc);
    assert!(b.en && b.dn && !b.pc && b.ip);
    run_until(&mut task, 10_000, |t| t.motion_bits(mc).pc);
    assert_eq!(positions(&task, &axes), vec![1.0, 1.0]);
    // A held move keeps .EN until it is queued.
    let (a, b2, c) = (
        task.add_instruction("A"),
        task.add_instruction("B"),
        task.add_instruction("C"),
    );
    let _ = task.execute_coordinated(cs, a, CoordCall::Mclm(line(&[5.0, 1.0], 1)));
    let _ = task.execute_coordinated(cs, b2, CoordCall::Mclm(line(&[5.0, 5.0], 1)));
    let _ = task.execute_coordinated(cs, c, CoordCall::Mclm(line(&[1.0, 1.0], 1)));
    task.update();
    let bc = task.motion_bits(c);
    assert!(bc.en && !bc.dn && !bc.ip);
    // Queued at last: the rung is already false, so the same scan clears .EN.
    run_until(&mut task, 10_000, |t| t.motion_bits(c).dn);
    assert!(!task.motion_bits(c).en && task.motion_bits(c).ip);
    run_until(&mut task, 10_000, |t| t.motion_bits(c).pc);
    assert_eq!(positions(&task, &axes), vec![1.0, 1.0]);
}

#[test]
fn a_second_system_on_shared_axes_needs_merge_all_motion() {
    let (mut task, xy, axes) = gantry(2, 1);
    let xyz = task
        .add_coordinate_system(
            CoordinateSystemConfig {
                axis_count: 3,
                primary_axes: 3,
                max_speed: 100.0,
                max_accel: 1000.0,
                max_decel: 1000.0,
                ..CoordinateSystemConfig::new("XYZ")
            },
            &axes,
        )
        .unwrap();
    let a = task.add_instruction("A");
    let _ = task.execute_coordinated(xy, a, CoordCall::Mclm(line(&[50.0, 0.0, 0.0], 1)));
    for _ in 0..100 {
        task.update();
    }
    let here = positions(&task, &axes);
    let b = task.add_instruction("B");
    // Merge disabled (0) and coordinated motion (1) are refused: ERR 13, EXERR Merge.
    for merge in [0, 1] {
        let call = CoordCall::Mccm(MccmInputs {
            common: CoordMoveInputs {
                merge,
                move_type: 1,
                ..line(&[10.0, 10.0, 0.0], 1)
            },
            circle_type: 3,
            via_center_radius: vec![0.0, 10.0, 0.0],
            direction: 0,
        });
        let _ = task.execute_coordinated(xyz, b, call);
        let bb = task.motion_bits(b);
        assert!(bb.er && (bb.err, bb.exerr) == (13, 15), "{bb:?}");
        assert!(task.motion_bits(a).ip);
    }
    let call = CoordCall::Mclm(CoordMoveInputs {
        merge: 2,
        ..line(&[0.0, 0.0, 0.0], 1)
    });
    let _ = task.execute_coordinated(xyz, b, call);
    let (ba, bb) = (task.motion_bits(a), task.motion_bits(b));
    assert!(!ba.ip && !ba.ac && !ba.pc, "{ba:?}");
    assert!(bb.dn && bb.ip && bb.ac && !task.coord_status(xy).motion);
    assert_eq!(task.coord_active_move(xyz).unwrap().path().start(), here.as_slice());
    run_until(&mut task, 10_000, |t| t.motion_bits(b).pc);
    assert_eq!(positions(&task, &axes), vec![0.0, 0.0, 0.0]);
}

/// The same calls give bit-identical setpoints (no clock, no hash order).
#[test]
fn reruns_are_bit_identical() {
    let run = || {
        let (mut task, cs, axes) = gantry(3, 0);
        let calls = [
            CoordCall::Mclm(line(&[10.0, 0.0, 5.0], 3)),
            CoordCall::Mccm(MccmInputs {
                common: CoordMoveInputs {
                    dynamics: MoveDynamics {
                        profile: 1,
                        ..line(&[20.0, 10.0, 0.0], 2).dynamics
                    },
                    ..line(&[20.0, 10.0, 0.0], 2)
                },
                circle_type: 0,
                via_center_radius: vec![18.0, 3.0, 3.0],
                direction: 0,
            }),
            CoordCall::Mclm(line(&[0.0, 0.0, 0.0], 0)),
        ];
        let hs: Vec<_> = calls.iter().map(|_| task.add_instruction("M")).collect();
        let mut out = Vec::new();
        for k in 0..3000 {
            if let Some(i) = [0, 1, 2].into_iter().find(|i| k == 10 * i) {
                let _ = task.execute_coordinated(cs, hs[i], calls[i].clone());
            }
            task.update();
            out.extend(axes.iter().map(|a| task.axis_state(*a).command_position.to_bits()));
        }
        assert!(task.motion_bits(hs[2]).pc);
        out
    };
    assert_eq!(run(), run());
}

#[test]
fn mcs_stop_all_also_stops_single_axis_motion() {
    let mut task = MotionTask::new(DT).unwrap();
    let x = task
        .add_axis(
            AxisConfig {
                modulo_period: Some(360.0),
                max_velocity: 100.0,
                ..AxisConfig::new("X", AxisKind::Linear)
            },
            0.0,
        )
        .unwrap();
    let y = task.add_axis(AxisConfig::new("Y", AxisKind::Linear), 0.0).unwrap();
    let cs = task
        .add_coordinate_system(
            CoordinateSystemConfig {
                axis_count: 2,
                primary_axes: 2,
                ..CoordinateSystemConfig::new("CS")
            },
            &[x, y],
        )
        .unwrap();
    let fb = task.add_move_modulo("MoveX", x);
    task.set_move_modulo_inputs(
        fb,
        MoveModuloInputs {
            execute: true,
            position: 300.0,
            velocity: 50.0,
            ..Default::default()
        },
    );
    for _ in 0..100 {
        task.update();
    }
    assert!(task.outputs(fb).active && task.axis_state(x).command_velocity > 0.0);
    let stop = task.add_instruction("S");
    let coordinated_only = McsInputs {
        stop_type: 1,
        ..McsInputs::default()
    };
    let _ = task.execute_coordinated(cs, stop, CoordCall::Mcs(coordinated_only));
    task.update();
    assert!(
        task.motion_bits(stop).pc && task.outputs(fb).active,
        "type 1 leaves MC_MoveModulo alone"
    );
    let _ = task.execute_coordinated(cs, stop, CoordCall::Mcs(McsInputs::default()));
    task.update();
    assert!(task.outputs(fb).command_aborted);
    run_until(&mut task, 10_000, |t| t.axis_state(x).command_velocity == 0.0);
    assert!(task.axis_state(x).command_position < 300.0);
}

#[test]
fn merge_during_a_blend_brings_both_moves_to_rest_and_ends_exactly() {
    let (mut task, cs, axes) = gantry(2, 0);
    let a = task.add_instruction("A");
    let b = task.add_instruction("B");
    let m = task.add_instruction("M");
    let _ = task.execute_coordinated(cs, a, CoordCall::Mclm(line(&[10.0, 0.0], 3)));
    let _ = task.execute_coordinated(cs, b, CoordCall::Mclm(line(&[10.0, 10.0], 1)));
    run_until(&mut task, 10_000, |t| {
        t.coord.systems[cs.0 as usize].components.len() == 2
    });
    let merge = CoordMoveInputs {
        merge: 1,
        ..line(&[-5.0, 3.0], 1)
    };
    let _ = task.execute_coordinated(cs, m, CoordCall::Mclm(merge));
    assert!(task.motion_bits(m).ac && !task.motion_bits(b).ac && !task.motion_bits(b).ip);
    let mut speeds = Vec::new();
    run_until(&mut task, 10_000, |t| {
        speeds.push(speed(t, &axes, 2));
        t.motion_bits(m).pc
    });
    assert!(!stops_between(&speeds));
    assert_eq!(positions(&task, &axes), vec![-5.0, 3.0]);
    assert!(!task.motion_bits(b).pc);
}

#[test]
fn stop_all_axes_brings_coordinated_motion_to_rest_along_the_path() {
    let (mut task, cs, axes) = gantry(2, 0);
    let a = task.add_instruction("A");
    let b = task.add_instruction("B");
    let _ = task.execute_coordinated(cs, a, CoordCall::Mclm(line(&[30.0, 40.0], 1)));
    let _ = task.execute_coordinated(cs, b, CoordCall::Mclm(line(&[0.0, 0.0], 1)));
    for _ in 0..300 {
        task.update();
    }
    let report = task.stop_all_axes();
    assert_eq!(report.stopped_axes, axes);
    assert!(report.stopped_instructions.contains(&a) && report.stopped_instructions.contains(&b));
    assert!(!task.motion_bits(a).ip && !task.motion_bits(b).ip && !task.coord_status(cs).move_pending);
    run_until(&mut task, 10_000, |t| !t.coord_status(cs).motion);
    let end = positions(&task, &axes);
    assert!((end[1] / end[0] - 4.0 / 3.0).abs() < 1e-9, "on the line: {end:?}");
    assert!(!task.motion_bits(a).pc && !task.motion_bits(b).pc);
}

#[test]
fn a_jog_takes_its_axis_from_a_coordinated_move_and_a_move_merging_all_motion_takes_it_back() {
    let (mut task, cs, axes) = gantry(2, 0);
    let a = task.add_instruction("A");
    let _ = task.execute_coordinated(cs, a, CoordCall::Mclm(line(&[30.0, 40.0], 1)));
    for _ in 0..300 {
        task.update();
    }
    let jog = task.add_instruction("J");
    let operands = crate::task::instructions::maj::MajOperands {
        speed: 5.0,
        ..Default::default()
    };
    task.maj(axes[0], jog, &operands).unwrap();
    assert!(!task.motion_bits(a).ip && task.motion_bits(jog).ip);
    run_until(&mut task, 10_000, |t| !t.coord_status(cs).motion);
    // Y came to rest on the path; X jogs on at 5 units/s, written by the jog alone.
    assert_eq!(task.axis_state(axes[1]).command_velocity, 0.0);
    for _ in 0..200 {
        task.update();
    }
    assert!((task.axis_state(axes[0]).command_velocity - 5.0).abs() < 1e-9);
    // A new coordinated move with Merge Disabled leaves the jog running,
    // superimposed (MCCM document, Merge); one with Merge All Motion ends
    // it and drives both axes again.
    let _ = task.execute_coordinated(cs, a, CoordCall::Mclm(line(&[0.0, 0.0], 1)));
    assert!(task.motion_bits(jog).ip);
    let all_motion = CoordMoveInputs {
        merge: 2,
        ..line(&[0.0, 0.0], 1)
    };
    let _ = task.execute_coordinated(cs, a, CoordCall::Mclm(all_motion));
    assert!(!task.motion_bits(jog).ip);
    run_until(&mut task, 20_000, |t| t.motion_bits(a).pc);
    assert_eq!(positions(&task, &axes), vec![0.0, 0.0]);
}

/// 10,000 seeded random arcs of every circle type, move type and direction,
/// 2D and 3D, partial and full, through the task: every coarse update's
/// command point is on the circle (radius within 1e-9, in its plane), the
/// vector speed never exceeds the programmed speed, the tangential
/// acceleration (the change of the vector speed over a coarse update) stays
/// within the accel/decel rates and, for S-curves, the tangential jerk (its
/// second difference) within the jerks, the arc ends exactly at its end
/// point, and every axis has its last non-zero command velocity in the same
/// coarse update.
#[test]
fn random_arcs_of_every_circle_type_through_the_task() {
    use crate::coord::{CoordinateSystem, MoveContext};
    let mut rng = ChaCha8Rng::seed_from_u64(0x6172_6373);
    let mut per_type = [0usize; 4];
    for case in 0..10_000 {
        let mut r = crate::mccm::tests::random_arc(&mut rng);
        let config = CoordinateSystemConfig {
            axis_count: r.dim,
            primary_axes: r.dim,
            max_speed: 1000.0,
            max_accel: 1e5,
            max_decel: 1e5,
            ..CoordinateSystemConfig::new("CS")
        };
        // Speed and rates scaled to the arc, so each takes 0.1 .. 0.6 s.
        let system = CoordinateSystem::new(config.clone()).unwrap();
        let ctx = MoveContext {
            system: &system,
            axis_max_decel: &vec![1.0; r.dim],
            start: &r.start,
            has_master: false,
        };
        let length = crate::mccm::mccm(&r.inputs, &ctx).unwrap().path().length();
        let programmed = length / rng.random_range(0.1..0.6);
        r.inputs.common.dynamics.speed = programmed;
        r.inputs.common.dynamics.accel_rate = programmed * rng.random_range(2.0..20.0);
        r.inputs.common.dynamics.decel_rate = programmed * rng.random_range(2.0..20.0);
        let mut task = MotionTask::new(DT).unwrap();
        let axes: Vec<AxisHandle> = r
            .start
            .iter()
            .enumerate()
            .map(|(i, p)| {
                task.add_axis(AxisConfig::new(format!("A{i}"), AxisKind::Linear), *p)
                    .unwrap()
            })
            .collect();
        let cs = task.add_coordinate_system(config, &axes).unwrap();
        let mc = task.add_instruction("MC");
        per_type[r.inputs.circle_type as usize] += 1;
        let _ = task.execute_coordinated(cs, mc, CoordCall::Mccm(r.inputs.clone()));
        assert!(task.motion_bits(mc).dn, "case {case}: {:?}", task.motion_bits(mc));
        let arc = *task.coord_active_move(cs).unwrap().path().arc().unwrap();
        let end = task.coord_active_move(cs).unwrap().path().end().to_vec();
        let limits = *task.coord_active_move(cs).unwrap().limits().unwrap();
        let amax = limits.acceleration().max(limits.deceleration());
        let jmax = match limits.shape() {
            crate::profile::Shape::SCurve { accel_jerk, decel_jerk } => Some(accel_jerk.max(decel_jerk)),
            crate::profile::Shape::Trapezoidal => None,
        };
        let mut speeds = vec![0.0];
        let mut last_change = vec![0usize; r.dim];
        let mut k = 0;
        run_until(&mut task, 100_000, |t| {
            k += 1;
            let v = speed(t, &axes, r.dim);
            let n = speeds.len();
            let accel = (v - speeds[n - 1]) / DT;
            assert!(
                accel.abs() <= amax * (1.0 + 1e-6),
                "case {case}: accel {accel} > {amax}"
            );
            if let (Some(jmax), true) = (jmax, n >= 2) {
                let jerk = (v - 2.0 * speeds[n - 1] + speeds[n - 2]) / (DT * DT);
                assert!(jerk.abs() <= jmax * (1.0 + 1e-6), "case {case}: jerk {jerk} > {jmax}");
            }
            speeds.push(v);
            let p = positions(t, &axes);
            for i in 0..r.dim {
                if t.axis_state(axes[i]).command_velocity != 0.0 {
                    last_change[i] = k;
                }
            }
            let q = crate::vector::sub(primary_of(&p, r.dim), r.center);
            assert!((norm(q) - r.radius).abs() <= 1e-9, "case {case}: radius");
            assert!(crate::vector::dot(q, arc.normal()).abs() <= 1e-9, "case {case}: plane");
            assert!(
                speed(t, &axes, r.dim) <= programmed * (1.0 + 1e-9),
                "case {case}: speed"
            );
            t.motion_bits(mc).pc
        });
        assert_eq!(positions(&task, &axes), end, "case {case}: end point");
        let moved: Vec<usize> = last_change.iter().copied().filter(|k| *k > 0).collect();
        assert!(moved.windows(2).all(|w| w[0] == w[1]), "case {case}: {last_change:?}");
    }
    assert!(per_type.iter().all(|&n| n > 1000), "{per_type:?}");
}

#[test]
fn merge_speed_current_counts_single_axis_motion() {
    let (mut task, cs, axes) = gantry(2, 0);
    let jog = task.add_instruction("J");
    let operands = crate::task::instructions::maj::MajOperands {
        speed: 7.0,
        ..Default::default()
    };
    task.maj(axes[1], jog, &operands).unwrap();
    for _ in 0..200 {
        task.update();
    }
    assert!((task.axis_state(axes[1]).command_velocity - 7.0).abs() < 1e-9);
    let m = task.add_instruction("M");
    let merge = CoordMoveInputs {
        merge: 2,
        merge_speed: 1,
        ..line(&[20.0, 0.0], 1)
    };
    let _ = task.execute_coordinated(cs, m, CoordCall::Mclm(merge));
    assert!(!task.motion_bits(jog).ip, "all motion: the jog ends");
    let v = task.coord_active_move(cs).unwrap().limits().unwrap().velocity();
    assert!((v - 7.0).abs() < 1e-9, "{v}");
    run_until(&mut task, 20_000, |t| t.motion_bits(m).pc);
    assert_eq!(positions(&task, &axes)[0], 20.0);
}

/// Random sequences of MCLM, MCCM and MCS with arbitrary operands (codes out
/// of range, NaN, infinities, huge values), merges and queueing never panic
/// and never put a non-finite command on an axis.
#[test]
fn random_instruction_sequences_keep_the_commands_finite() {
    let mut rng = ChaCha8Rng::seed_from_u64(0x5e9);
    let specials = [f64::NAN, f64::INFINITY, 0.0, 1e-300, 1e300, -1e300];
    let pick = |rng: &mut ChaCha8Rng, lo: f64, hi: f64| {
        if rng.random_bool(0.1) {
            specials[rng.random_range(0..specials.len())]
        } else {
            rng.random_range(lo..hi)
        }
    };
    for _ in 0..150 {
        let (mut task, cs, axes) = gantry(2, 1);
        let tags: Vec<_> = (0..4).map(|i| task.add_instruction(format!("M{i}"))).collect();
        for k in 0..400 {
            if rng.random_bool(0.05) {
                let common = CoordMoveInputs {
                    move_type: rng.random_range(-1..3),
                    position: (0..3).map(|_| pick(&mut rng, -20.0, 20.0)).collect(),
                    termination_type: rng.random_range(-1..8),
                    merge: rng.random_range(0..3),
                    merge_speed: rng.random_range(0..2),
                    command_tolerance: pick(&mut rng, 0.0, 5.0),
                    event_distance: vec![pick(&mut rng, 0.0, 5.0)],
                    dynamics: MoveDynamics {
                        speed: pick(&mut rng, 0.0, 50.0),
                        accel_rate: pick(&mut rng, 1.0, 500.0),
                        decel_rate: pick(&mut rng, 1.0, 500.0),
                        profile: rng.random_range(0..2),
                        ..CoordMoveInputs::default().dynamics
                    },
                    ..Default::default()
                };
                let call = match rng.random_range(0..5) {
                    0 => CoordCall::Mcs(McsInputs {
                        stop_type: rng.random_range(0..3),
                        change_decel: rng.random_range(0..2),
                        decel_rate: pick(&mut rng, 1.0, 500.0),
                        decel_units: rng.random_range(0..2),
                        ..McsInputs::default()
                    }),
                    1 | 2 => CoordCall::Mclm(common),
                    _ => CoordCall::Mccm(MccmInputs {
                        common,
                        circle_type: rng.random_range(0..4),
                        via_center_radius: (0..2).map(|_| pick(&mut rng, -20.0, 20.0)).collect(),
                        direction: rng.random_range(0..4),
                    }),
                };
                let tag = tags[rng.random_range(0..tags.len())];
                let _ = task.execute_coordinated(cs, tag, call);
            }
            task.update();
            for a in &axes {
                let s = task.axis_state(*a);
                assert!(
                    s.command_position.is_finite() && s.command_velocity.is_finite(),
                    "update {k}: {s:?}"
                );
            }
        }
    }
}

#[test]
fn calculated_data_uses_the_current_speed_of_a_merge_at_current_speed() {
    let (mut task, cs, axes) = gantry(2, 0);
    let a = task.add_instruction("A");
    let _ = task.execute_coordinated(cs, a, CoordCall::Mclm(line(&[100.0, 0.0], 1)));
    for _ in 0..500 {
        task.update();
    }
    assert!((speed(&task, &axes, 2) - 10.0).abs() < 1e-9);
    // Merge at current speed (10, programmed 30): the old move comes to rest
    // at x = 20 (10²/(2·50) = 1 past x = 19); the new one runs 20 → 60 at 10.
    let m = task.add_instruction("M");
    let merge = CoordMoveInputs {
        merge: 1,
        merge_speed: 1,
        event_distance: vec![5.0],
        dynamics: MoveDynamics {
            speed: 30.0,
            ..line(&[60.0, 0.0], 1).dynamics
        },
        ..line(&[60.0, 0.0], 1)
    };
    let _ = task.execute_coordinated(cs, m, CoordCall::Mclm(merge));
    let h = task.coord_instruction_of(m).unwrap();
    // Accel 0.2 s (1 unit), then 34 units at 10 units/s to x = 55: 3.6 s
    // (at the programmed 30 it would be 0.6 s + 26/30 s).
    let cd = task.coord_calculated_data(h).to_vec();
    assert!((cd[0] - 3.6).abs() < 1e-9, "{cd:?}");
}

#[test]
fn a_master_driven_move_cannot_take_over_from_moving_time_driven_motion_while_the_master_stands_still() {
    let (mut task, cs, axes) = gantry(2, 0);
    let master = task.add_axis(AxisConfig::new("Master", AxisKind::Linear), 0.0).unwrap();
    task.set_coordinate_system_master(cs, Some(master));
    let master_driven = CoordMoveInputs {
        position: vec![10.0, 10.0],
        termination_type: 1,
        dynamics: per_master_unit(0.1, 0.01),
        ..Default::default()
    };
    // Queued behind a blending time-driven move: it fails when it would
    // start (at the blend point), keeps .DN, and the first move ends at rest.
    let a = task.add_instruction("A");
    let b = task.add_instruction("B");
    let _ = task.execute_coordinated(cs, a, CoordCall::Mclm(line(&[10.0, 0.0], 2)));
    let _ = task.execute_coordinated(cs, b, CoordCall::Mclm(master_driven.clone()));
    let bits = task.motion_bits(b);
    assert!(bits.dn && bits.ip && !bits.er, "{bits:?}");
    run_until(&mut task, 10_000, |t| t.motion_bits(b).er);
    assert!(speed(&task, &axes, 2) > 0.0);
    let bits = task.motion_bits(b);
    assert!(bits.dn && !bits.ip && !bits.ac, "{bits:?}");
    assert_eq!((bits.err, bits.exerr), (ERR_IDLE_MASTER_SLAVE_MOVING, 0));
    assert!(!task.coord_status(cs).move_pending);
    run_until(&mut task, 10_000, |t| t.motion_bits(a).pc);
    assert_eq!(positions(&task, &axes), vec![10.0, 0.0]);
    assert!(!task.coord_status(cs).motion);
    // Executed as a merge while the system moves: refused at once, no .DN,
    // the running move goes on.
    let c = task.add_instruction("C");
    let m = task.add_instruction("M");
    let _ = task.execute_coordinated(cs, c, CoordCall::Mclm(line(&[0.0, 0.0], 1)));
    for _ in 0..100 {
        task.update();
    }
    let _ = task.execute_coordinated(
        cs,
        m,
        CoordCall::Mclm(CoordMoveInputs {
            merge: 1,
            ..master_driven.clone()
        }),
    );
    let bits = task.motion_bits(m);
    assert!(bits.er && !bits.dn && !bits.ip, "{bits:?}");
    assert_eq!(bits.err, ERR_IDLE_MASTER_SLAVE_MOVING);
    assert!(task.motion_bits(c).ac);
    run_until(&mut task, 10_000, |t| t.motion_bits(c).pc);
    assert_eq!(positions(&task, &axes), vec![0.0, 0.0]);
    // Master and slave both at rest: the switch is allowed.
    let _ = task.execute_coordinated(cs, m, CoordCall::Mclm(master_driven));
    let bits = task.motion_bits(m);
    assert!(bits.dn && bits.ip && !bits.er, "{bits:?}");
}

#[test]
fn termination_4_and_5_follow_the_contour_through_the_end_point_without_stopping() {
    for (tt, profile) in [(4, 0), (5, 0), (4, 1), (5, 1)] {
        // Collinear lines: to x = 10 at 10 units/s, then to x = 20 at 5 units/s.
        let (mut task, cs, axes) = gantry(2, 0);
        let (a, b) = (task.add_instruction("A"), task.add_instruction("B"));
        let fast = CoordMoveInputs {
            dynamics: MoveDynamics {
                profile,
                ..line(&[10.0, 0.0], tt).dynamics
            },
            ..line(&[10.0, 0.0], tt)
        };
        let _ = task.execute_coordinated(cs, a, CoordCall::Mclm(fast));
        let slow = CoordMoveInputs {
            dynamics: MoveDynamics {
                speed: 5.0,
                profile,
                ..line(&[20.0, 0.0], 1).dynamics
            },
            ..line(&[20.0, 0.0], 1)
        };
        let _ = task.execute_coordinated(cs, b, CoordCall::Mclm(slow));
        let mut speeds = vec![0.0];
        let mut at_pc = None;
        run_until(&mut task, 20_000, |t| {
            let v = speed(t, &axes, 2);
            let dv = v - speeds[speeds.len() - 1];
            assert!(dv.abs() <= 50.0 * DT * (1.0 + 1e-9), "tt {tt}: accel {}", dv / DT);
            assert!(v <= 10.0 * (1.0 + 1e-9));
            speeds.push(v);
            if at_pc.is_none() && t.motion_bits(a).pc {
                at_pc = Some((positions(t, &axes), v, t.coord_status(cs).move_transition));
                assert!(t.motion_bits(b).ac && !t.motion_bits(a).ip, "tt {tt}");
            }
            t.motion_bits(b).pc
        });
        assert!(!stops_between(&speeds), "tt {tt}");
        // The first move completes at its end point, where the second starts
        // at the junction speed 5 (the lower of 10 and 5), on path.
        let (p, v, transition) = at_pc.unwrap();
        assert!(
            p[0] >= 10.0 && p[0] <= 10.0 + 5.0 * DT + 1e-9 && p[1] == 0.0,
            "tt {tt}: {p:?}"
        );
        assert!((v - 5.0).abs() < 1e-9, "tt {tt}: {v}");
        assert!(!transition);
        assert_eq!(positions(&task, &axes), vec![20.0, 0.0]);
    }
    // A tangent line–arc–line contour never stops and ends exactly.
    let (mut task, cs, axes) = gantry(2, 0);
    let calls = [
        CoordCall::Mclm(line(&[10.0, 0.0], 4)),
        CoordCall::Mccm(MccmInputs {
            common: line(&[15.0, 5.0], 4),
            circle_type: 1,
            via_center_radius: vec![10.0, 5.0],
            direction: 1,
        }),
        CoordCall::Mclm(line(&[15.0, 15.0], 1)),
    ];
    let hs: Vec<_> = (0..3).map(|i| task.add_instruction(format!("M{i}"))).collect();
    let mut speeds = Vec::new();
    let mut next = 0;
    for _ in 0..20_000 {
        // Each move is executed as soon as the queue has room.
        if next < 3 && !task.coord_status(cs).move_pending_queue_full {
            let _ = task.execute_coordinated(cs, hs[next], calls[next].clone());
            next += 1;
        }
        task.update();
        speeds.push(speed(&task, &axes, 2));
        if task.motion_bits(hs[2]).pc {
            break;
        }
    }
    assert!(task.motion_bits(hs[2]).pc);
    assert!(!stops_between(&speeds));
    assert_eq!(positions(&task, &axes), vec![15.0, 15.0]);
    // Without a pending move a type 4 move ends at rest at its end point.
    let (mut task, cs, axes) = gantry(2, 0);
    let h = task.add_instruction("A");
    let _ = task.execute_coordinated(cs, h, CoordCall::Mclm(line(&[3.0, 4.0], 4)));
    run_until(&mut task, 20_000, |t| t.motion_bits(h).pc);
    assert_eq!(positions(&task, &axes), vec![3.0, 4.0]);
    assert_eq!(speed(&task, &axes, 2), 0.0);
}

#[test]
fn a_merge_at_current_speed_recomputes_percent_of_time_jerks_for_that_speed() {
    let (mut task, cs, axes) = gantry(2, 0);
    let a = task.add_instruction("A");
    let _ = task.execute_coordinated(cs, a, CoordCall::Mclm(line(&[100.0, 0.0], 1)));
    for _ in 0..500 {
        task.update();
    }
    assert!((speed(&task, &axes, 2) - 10.0).abs() < 1e-9);
    let m = task.add_instruction("M");
    let merge = CoordMoveInputs {
        merge: 1,
        merge_speed: 1,
        dynamics: MoveDynamics {
            speed: 30.0,
            profile: 1,
            accel_jerk: 100.0,
            decel_jerk: 50.0,
            jerk_units: 2,
            ..line(&[60.0, 0.0], 1).dynamics
        },
        ..line(&[60.0, 0.0], 1)
    };
    let _ = task.execute_coordinated(cs, m, CoordCall::Mclm(merge));
    let limits = *task.coord_active_move(cs).unwrap().limits().unwrap();
    let crate::profile::Shape::SCurve { accel_jerk, decel_jerk } = limits.shape() else {
        panic!("an S-curve")
    };
    // j = a²/v · (200/% − 1) with the current speed 10 (not the programmed 30):
    // 50²/10 · 1 = 250 and 50²/10 · 3 = 750.
    assert!((limits.velocity() - 10.0).abs() < 1e-9);
    assert!(
        (accel_jerk - 250.0).abs() < 1e-9 && (decel_jerk - 750.0).abs() < 1e-9,
        "{limits:?}"
    );
}

#[test]
fn absolute_positions_of_a_rotary_axis_with_an_unwind_take_the_sign_as_direction() {
    let mut task = MotionTask::new(DT).unwrap();
    let x = task.add_axis(AxisConfig::new("X", AxisKind::Linear), 0.0).unwrap();
    let c = task
        .add_axis(
            AxisConfig {
                modulo_period: Some(360.0),
                ..AxisConfig::new("C", AxisKind::Rotary)
            },
            0.0,
        )
        .unwrap();
    let cs = task
        .add_coordinate_system(
            CoordinateSystemConfig {
                axis_count: 2,
                primary_axes: 1,
                max_speed: 1000.0,
                max_accel: 10_000.0,
                max_decel: 10_000.0,
                ..CoordinateSystemConfig::new("XC")
            },
            &[x, c],
        )
        .unwrap();
    let h = task.add_instruction("M");
    // (absolute C operand, unwrapped C after the move, direction of travel)
    for (target, expected, direction) in [
        (270.0, 270.0, 1.0),   // forward from 0
        (90.0, 450.0, 1.0),    // forward through the unwind, not back 180°
        (-0.0, 720.0, 1.0),    // −0 is 0: forward
        (-270.0, 630.0, -1.0), // negative: backward to 270
        (-360.0, 360.0, -1.0), // −unwind: backward to the unwind position
    ] {
        let _ = task.execute_coordinated(cs, h, CoordCall::Mclm(line(&[1.0, target], 1)));
        assert!(task.motion_bits(h).dn, "{target}: {:?}", task.motion_bits(h));
        run_until(&mut task, 20_000, |t| {
            let v = t.axis_state(c).command_velocity;
            assert!(v * direction >= 0.0, "{target}: C turns the wrong way ({v})");
            t.motion_bits(h).pc
        });
        let at = task.axis_state(c).command_position;
        assert!((at - expected).abs() < 1e-9, "{target}: C at {at}, expected {expected}");
        task.update();
    }
    // Beyond the unwind: ERR 13 on the Position operand (MCLM 3, MCCM 3).
    let _ = task.execute_coordinated(cs, h, CoordCall::Mclm(line(&[1.0, 400.0], 1)));
    let b = task.motion_bits(h);
    assert!(b.er && !b.dn && (b.err, b.exerr) == (13, 3), "{b:?}");
    // Incremental moves turn by the increment.
    task.update();
    let inc = CoordMoveInputs {
        move_type: 1,
        ..line(&[0.0, -100.0], 1)
    };
    let _ = task.execute_coordinated(cs, h, CoordCall::Mclm(inc));
    run_until(&mut task, 20_000, |t| t.motion_bits(h).pc);
    assert!((task.axis_state(c).command_position - 260.0).abs() < 1e-9);
}

#[test]
fn a_collinear_blend_never_sets_move_transition_status() {
    for tt in [2, 3, 6] {
        let (mut task, cs, axes) = gantry(2, 0);
        let (a, b) = (task.add_instruction("A"), task.add_instruction("B"));
        let first = CoordMoveInputs {
            command_tolerance: 0.5,
            ..line(&[10.0, 0.0], tt)
        };
        let _ = task.execute_coordinated(cs, a, CoordCall::Mclm(first));
        let _ = task.execute_coordinated(cs, b, CoordCall::Mclm(line(&[20.0, 0.0], 1)));
        let (mut blended, mut speeds) = (false, Vec::new());
        run_until(&mut task, 20_000, |t| {
            blended |= t.coord.systems[cs.0 as usize].components.len() == 2;
            assert!(!t.coord_status(cs).move_transition, "tt {tt}: on path");
            speeds.push(speed(t, &axes, 2));
            t.motion_bits(b).pc
        });
        assert!(blended && !stops_between(&speeds), "tt {tt}");
        // Collinear moves at the same speed blend into one cruise: never faster.
        assert!(speeds.iter().all(|v| *v <= 10.0 * (1.0 + 1e-9)), "tt {tt}");
        assert_eq!(positions(&task, &axes), vec![20.0, 0.0]);
    }
}

#[test]
fn a_blend_into_a_quickly_accelerating_move_is_deferred_so_the_speeds_never_add_up() {
    // First decelerates at 50 units/s² (0.2 s from 10), the second accelerates
    // at 500 (0.02 s to 10): started at the deceleration point, the collinear
    // speeds would add up to 19 units/s, and to 13.5 round a square corner.
    // Trapezoidal, then S-curves with different jerks (% of time) on each side.
    let cases = [
        ([20.0, 0.0], 3, 0, 100.0, 100.0),
        ([10.0, 10.0], 3, 0, 100.0, 100.0),
        ([20.0, 0.0], 2, 0, 100.0, 100.0),
        ([10.0, 10.0], 6, 0, 100.0, 100.0),
        ([20.0, 0.0], 3, 1, 10.0, 100.0),
        ([20.0, 0.0], 3, 1, 100.0, 10.0),
        ([10.0, 10.0], 2, 1, 30.0, 100.0),
    ];
    for (end, tt, profile, first_jerk, second_jerk) in cases {
        let (mut task, cs, axes) = gantry(2, 0);
        let (a, b) = (task.add_instruction("A"), task.add_instruction("B"));
        let first = CoordMoveInputs {
            command_tolerance: 0.9,
            dynamics: MoveDynamics {
                profile,
                accel_jerk: first_jerk,
                decel_jerk: first_jerk,
                jerk_units: 2,
                ..line(&[10.0, 0.0], tt).dynamics
            },
            ..line(&[10.0, 0.0], tt)
        };
        let _ = task.execute_coordinated(cs, a, CoordCall::Mclm(first));
        let quick = CoordMoveInputs {
            dynamics: MoveDynamics {
                accel_rate: 500.0,
                profile,
                accel_jerk: second_jerk,
                decel_jerk: second_jerk,
                jerk_units: 2,
                ..line(&end, 1).dynamics
            },
            ..line(&end, 1)
        };
        let _ = task.execute_coordinated(cs, b, CoordCall::Mclm(quick));
        let (mut blended, mut speeds) = (false, Vec::new());
        run_until(&mut task, 20_000, |t| {
            blended |= t.coord.systems[cs.0 as usize].components.len() == 2;
            speeds.push(speed(t, &axes, 2));
            t.motion_bits(b).pc
        });
        let fastest = speeds.iter().copied().fold(0.0, f64::max);
        assert!(fastest <= 10.0 * (1.0 + 1e-9), "{end:?} tt {tt}: {fastest}");
        assert!(blended && !stops_between(&speeds), "{end:?} tt {tt}");
        assert_eq!(positions(&task, &axes), end.to_vec());
    }
}

#[test]
fn a_move_executed_while_an_mcs_stops_clears_stopping_status_and_starts_where_the_stop_ends() {
    let (mut task, cs, axes) = gantry(2, 0);
    let (a, s, b) = (
        task.add_instruction("A"),
        task.add_instruction("S"),
        task.add_instruction("B"),
    );
    let _ = task.execute_coordinated(cs, a, CoordCall::Mclm(line(&[100.0, 0.0], 1)));
    for _ in 0..200 {
        task.update();
    }
    let _ = task.execute_coordinated(cs, s, CoordCall::Mcs(McsInputs::default()));
    task.update();
    assert!(task.coord_status(cs).stopping);
    // "The Stopping Status bit is cleared when the MCCM instruction executes."
    let _ = task.execute_coordinated(cs, b, CoordCall::Mclm(line(&[0.0, 10.0], 1)));
    assert!(!task.coord_status(cs).stopping && task.motion_bits(b).dn);
    let mut previous = positions(&task, &axes);
    run_until(&mut task, 20_000, |t| {
        let p = positions(t, &axes);
        // No jump: the new move starts where the stop brings the system to rest.
        assert!((p[0] - previous[0]).hypot(p[1] - previous[1]) <= 10.0 * DT * (1.0 + 1e-9));
        previous = p;
        t.motion_bits(b).pc
    });
    assert!(task.motion_bits(s).pc);
    assert_eq!(positions(&task, &axes), vec![0.0, 10.0]);
}

/// One MCLM executed on a one-shot rung: `.DN .IP` at once, `.PC` when the
/// line ends at its position.
#[test]
fn a_line_executes_on_a_one_shot_rung_and_ends_at_its_position() {
    let mut task = MotionTask::new(0.004).unwrap();
    let x = task.add_axis(AxisConfig::new("X", AxisKind::Linear), 0.0).unwrap();
    let y = task.add_axis(AxisConfig::new("Y", AxisKind::Linear), 0.0).unwrap();
    let config = CoordinateSystemConfig {
        axis_count: 2,
        primary_axes: 2,
        ..CoordinateSystemConfig::new("CS")
    };
    let cs = task.add_coordinate_system(config, &[x, y]).unwrap();
    let mc = task.add_instruction("MC1");
    let line = CoordMoveInputs {
        position: vec![0.3, 0.4],
        ..Default::default()
    };
    task.execute_coordinated(cs, mc, CoordCall::Mclm(line)).unwrap();
    assert!(task.motion_bits(mc).dn && task.motion_bits(mc).ip);
    while !task.motion_bits(mc).pc {
        task.update();
    }
    assert_eq!(task.axis_state(y).command_position, 0.4);
}
