//! Executor behaviour: PLCopen output rules for every BufferMode transition,
//! MC_MoveModulo through the task, and seeded random invariants.

use super::*;
use crate::axis::AxisKind;
use crate::modulo::{ErrorId, McDirection};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

const DT: f64 = 0.004;

/// A coordinate system `name` of the two linear axes `x`, `y` (100
/// units/s, 1000 units/s²), for the task's tests.
pub(crate) fn two_axis_system(task: &mut MotionTask, name: &str, x: AxisHandle, y: AxisHandle) -> CoordHandle {
    task.add_coordinate_system(
        crate::coord::CoordinateSystemConfig {
            axis_count: 2,
            primary_axes: 2,
            max_speed: 100.0,
            max_accel: 1000.0,
            max_decel: 1000.0,
            ..crate::coord::CoordinateSystemConfig::new(name)
        },
        &[x, y],
    )
    .unwrap()
}

fn table_axis(jerk: f64) -> AxisConfig {
    AxisConfig {
        modulo_period: Some(360.0),
        max_velocity: 720.0,
        max_acceleration: 3600.0,
        max_deceleration: 3600.0,
        max_jerk: jerk,
        in_position_window: 0.1,
        ..AxisConfig::new("Table", AxisKind::Rotary)
    }
}

fn setup(start: f64) -> (MotionTask, AxisHandle, FbHandle, FbHandle) {
    let mut task = MotionTask::new(DT).unwrap();
    let axis = task.add_axis(table_axis(36000.0), start).unwrap();
    let a = task.add_move_modulo("MoveA", axis);
    let b = task.add_move_modulo("MoveB", axis);
    (task, axis, a, b)
}

fn go(position: f64, velocity: f64, direction: McDirection, buffer_mode: McBufferMode) -> MoveModuloInputs {
    MoveModuloInputs {
        execute: true,
        position,
        velocity,
        direction,
        buffer_mode,
        ..Default::default()
    }
}

/// `Execute := FALSE`, other inputs unchanged.
fn release(task: &mut MotionTask, fb: FbHandle) {
    let inputs = MoveModuloInputs {
        execute: false,
        ..task.move_modulo_inputs(fb)
    };
    task.set_move_modulo_inputs(fb, inputs);
}

fn run_until(task: &mut MotionTask, max_updates: usize, mut stop: impl FnMut(&MotionTask) -> bool) -> usize {
    for n in 0..max_updates {
        task.update();
        if stop(task) {
            return n + 1;
        }
    }
    panic!("condition not reached in {max_updates} updates");
}

/// When Busy falls, exactly one of Done / CommandAborted / Error is set, and
/// Active implies Busy.
fn assert_plcopen_consistent(o: FbOutputs) {
    let finals = [o.done, o.command_aborted, o.error].iter().filter(|&&b| b).count();
    if o.busy {
        assert_eq!(finals, 0, "{o:?}");
    } else {
        assert!(finals <= 1, "{o:?}");
        assert!(!o.active, "{o:?}");
    }
}

#[test]
fn simple_move_busy_active_then_done_and_outputs_follow_execute() {
    let (mut task, axis, a, _) = setup(0.0);
    task.set_move_modulo_inputs(a, go(90.0, 180.0, McDirection::Positive, McBufferMode::Aborting));
    task.update();
    let o = task.outputs(a);
    assert!(o.busy && o.active && !o.done, "{o:?}");
    run_until(&mut task, 2000, |t| t.outputs(a).done);
    let o = task.outputs(a);
    assert!(!o.busy && !o.active && !o.command_aborted && !o.error);
    assert!((task.axis_state(axis).command_position - 90.0).abs() < 1e-9);
    // Done stays while Execute stays TRUE ...
    for _ in 0..10 {
        task.update();
        assert!(task.outputs(a).done);
    }
    // ... and clears with its falling edge.
    release(&mut task, a);
    task.update();
    assert_eq!(task.outputs(a), FbOutputs::default());
}

#[test]
fn done_shows_for_one_cycle_when_execute_fell_while_busy() {
    let (mut task, _, a, _) = setup(0.0);
    task.set_move_modulo_inputs(a, go(10.0, 180.0, McDirection::Positive, McBufferMode::Aborting));
    task.update();
    release(&mut task, a);
    run_until(&mut task, 2000, |t| t.outputs(a).done);
    task.update();
    assert_eq!(task.outputs(a), FbOutputs::default());
}

#[test]
fn spec_special_cases_through_the_task() {
    // At exactly 90 asked 90: no motion, Done at once.
    let (mut task, axis, a, _) = setup(90.0);
    task.set_move_modulo_inputs(a, go(90.0, 180.0, McDirection::Positive, McBufferMode::Aborting));
    task.update();
    assert!(task.outputs(a).done);
    assert_eq!(task.axis_state(axis).command_position, 90.0);
    // 450 in the positive direction: exactly one rotation.
    release(&mut task, a);
    task.update();
    task.set_move_modulo_inputs(a, go(450.0, 720.0, McDirection::Positive, McBufferMode::Aborting));
    let mut max_pos = f64::MIN;
    run_until(&mut task, 5000, |t| {
        max_pos = max_pos.max(t.axis_state(axis).command_position);
        t.outputs(a).done
    });
    assert_eq!(task.axis_state(axis).command_position, 450.0);
    assert!(max_pos <= 450.0 + 1e-9);
    // After a reset a little over 90: a complete rotation; a little under: minimal.
    for (actual, expected_move) in [(450.0001, 359.9999), (449.9999, 0.0001)] {
        release(&mut task, a);
        task.update();
        task.feed_actual_position(axis, actual);
        task.reset_axis(axis);
        assert_eq!(task.command_state(axis).position, actual);
        task.set_move_modulo_inputs(a, go(90.0, 720.0, McDirection::Positive, McBufferMode::Aborting));
        task.update();
        let target = task
            .active_target(axis)
            .unwrap_or(task.axis_state(axis).command_position);
        assert!(
            (target - actual - expected_move).abs() < 1e-9,
            "from {actual}: target {target}"
        );
        task.feed_actual_position(axis, target);
        run_until(&mut task, 5000, |t| t.outputs(a).done);
    }
}

#[test]
fn aborting_by_a_second_block_sets_command_aborted_and_never_reverses() {
    let (mut task, axis, a, b) = setup(0.0);
    task.set_move_modulo_inputs(a, go(270.0, 360.0, McDirection::Positive, McBufferMode::Aborting));
    run_until(&mut task, 200, |t| t.axis_state(axis).command_velocity > 300.0);
    // Ask B for 45 in the negative direction while moving positive.
    task.set_move_modulo_inputs(b, go(45.0, 180.0, McDirection::Negative, McBufferMode::Aborting));
    task.update();
    let (oa, ob) = (task.outputs(a), task.outputs(b));
    assert!(oa.command_aborted && !oa.busy && !oa.active, "{oa:?}");
    assert!(ob.busy && ob.active, "{ob:?}");
    run_until(&mut task, 5000, |t| {
        assert!(t.axis_state(axis).command_velocity >= 0.0, "reversed");
        t.outputs(b).done
    });
    let wrapped = task.axis_state(axis).modulo_command_position.unwrap();
    assert!((wrapped - 45.0).abs() < 1e-9, "{wrapped}");
}

#[test]
fn buffered_block_becomes_active_only_when_the_first_is_done() {
    let (mut task, axis, a, b) = setup(0.0);
    task.set_move_modulo_inputs(a, go(90.0, 360.0, McDirection::Positive, McBufferMode::Aborting));
    task.update();
    task.set_move_modulo_inputs(
        b,
        go(360.0 + 180.0, 360.0, McDirection::Positive, McBufferMode::Buffered),
    );
    task.update();
    let ob = task.outputs(b);
    assert!(ob.busy && !ob.active, "buffered, not active: {ob:?}");
    assert!(task.outputs(a).active);
    run_until(&mut task, 5000, |t| {
        let (oa, ob) = (t.outputs(a), t.outputs(b));
        assert_plcopen_consistent(oa);
        assert_plcopen_consistent(ob);
        if !oa.done {
            assert!(!ob.active);
        }
        oa.done
    });
    let ob = task.outputs(b);
    assert!(ob.busy && ob.active, "starts the update A is done: {ob:?}");
    // From standstill the extra turn counts: 90 -> 180 + 360.
    assert!((task.active_target(axis).unwrap() - 540.0).abs() < 1e-9);
    run_until(&mut task, 5000, |t| t.outputs(b).done);
    assert_eq!(task.axis_state(axis).command_position, 540.0);
}

#[test]
fn every_blending_mode_hands_over_at_its_junction_velocity() {
    use McBufferMode::*;
    // A at 200 deg/s, B at 400 deg/s.
    for (mode, expected) in [
        (BlendingLow, 200.0),
        (BlendingPrevious, 200.0),
        (BlendingNext, 400.0),
        (BlendingHigh, 400.0),
    ] {
        let (mut task, axis, a, b) = setup(0.0);
        task.set_move_modulo_inputs(a, go(180.0, 200.0, McDirection::Positive, Aborting));
        task.update();
        task.set_move_modulo_inputs(b, go(90.0, 400.0, McDirection::Positive, mode));
        task.update();
        assert!(task.outputs(b).busy && !task.outputs(b).active);
        // Run to the hand-over: the update where A is done and B active.
        let mut previous_velocity = 0.0;
        run_until(&mut task, 5000, |t| {
            let s = t.axis_state(axis);
            assert!(s.command_velocity >= 0.0, "{mode:?} reversed");
            if t.outputs(a).done {
                return true;
            }
            previous_velocity = s.command_velocity;
            false
        });
        let ob = task.outputs(b);
        assert!(ob.active && ob.busy, "{mode:?}: {ob:?}");
        // Velocity just before the hand-over is within one update of the junction.
        let j = task
            .axis_config(axis)
            .max_acceleration
            .max(task.axis_config(axis).max_deceleration)
            * DT;
        assert!(
            (previous_velocity - expected).abs() <= j + 1e-9,
            "{mode:?}: {previous_velocity} vs {expected}"
        );
        // B continues the same way to 90 + 360 (never back to 90).
        run_until(&mut task, 5000, |t| {
            assert!(t.axis_state(axis).command_velocity >= 0.0);
            t.outputs(b).done
        });
        assert!(
            (task.axis_state(axis).command_position - 450.0).abs() < 1e-9,
            "{mode:?}"
        );
    }
}

#[test]
fn buffer_full_and_busy_retrigger_are_errors() {
    let (mut task, axis, a, b) = setup(0.0);
    let c = task.add_move_modulo("MoveC", axis);
    task.set_move_modulo_inputs(a, go(90.0, 180.0, McDirection::Positive, McBufferMode::Aborting));
    task.update();
    task.set_move_modulo_inputs(b, go(180.0, 180.0, McDirection::Positive, McBufferMode::Buffered));
    task.set_move_modulo_inputs(c, go(270.0, 180.0, McDirection::Positive, McBufferMode::Buffered));
    task.update();
    let oc = task.outputs(c);
    assert!(oc.error && oc.error_id == ErrorId::BUFFER_FULL.0 && !oc.busy, "{oc:?}");
    // Re-trigger A while it is busy.
    release(&mut task, a);
    task.update();
    task.set_move_modulo_inputs(a, go(45.0, 180.0, McDirection::Positive, McBufferMode::Aborting));
    task.update();
    let oa = task.outputs(a);
    assert!(oa.error && oa.error_id == ErrorId::BUSY.0, "{oa:?}");
    // The motion under way still reaches 90, then B runs.
    run_until(&mut task, 5000, |t| t.outputs(b).done);
    assert!((task.axis_state(axis).command_position - 180.0).abs() < 1e-9);
}

#[test]
fn bad_operands_set_error_and_error_id_without_motion() {
    let (mut task, axis, a, _) = setup(10.0);
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY, -5.0, 0.0] {
        task.set_move_modulo_inputs(
            a,
            MoveModuloInputs {
                velocity: bad,
                ..go(90.0, 1.0, McDirection::Positive, McBufferMode::Aborting)
            },
        );
        task.update();
        let o = task.outputs(a);
        assert!(o.error && !o.busy && o.error_id == ErrorId::VELOCITY.0, "{bad}: {o:?}");
        release(&mut task, a);
        task.update();
        assert_eq!(task.outputs(a), FbOutputs::default());
        let s = task.axis_state(axis);
        assert_eq!((s.command_position, s.command_velocity), (10.0, 0.0));
    }
    assert!(MotionTask::new(0.0).is_err());
    assert!(MotionTask::new(f64::NAN).is_err());
    let mut t = MotionTask::new(DT).unwrap();
    assert!(t.add_axis(table_axis(0.0), f64::NAN).is_err());
    assert!(
        t.add_axis(
            AxisConfig {
                max_velocity: -1.0,
                ..table_axis(0.0)
            },
            0.0
        )
        .is_err()
    );
}

#[test]
fn done_waits_for_the_actual_position_when_monitoring() {
    let (mut task, axis, a, _) = setup(0.0);
    task.set_move_modulo_inputs(a, go(30.0, 360.0, McDirection::Positive, McBufferMode::Aborting));
    task.feed_actual_position(axis, 0.0);
    run_until(&mut task, 2000, |t| !t.axis_state(axis).has_job);
    assert!(!task.outputs(a).done, "actual still at 0");
    task.feed_actual_position(axis, 29.95);
    task.update();
    assert!(task.outputs(a).done, "inside the 0.1 window");

    let mut task = MotionTask::new(DT).unwrap();
    let axis = task
        .add_axis(
            AxisConfig {
                target_position_monitoring: false,
                ..table_axis(0.0)
            },
            0.0,
        )
        .unwrap();
    let a = task.add_move_modulo("M", axis);
    task.feed_actual_position(axis, -100.0);
    task.set_move_modulo_inputs(a, go(30.0, 360.0, McDirection::Positive, McBufferMode::Aborting));
    run_until(&mut task, 2000, |t| !t.axis_state(axis).has_job);
    assert!(task.outputs(a).done, "no monitoring: Done when generation ends");
}

#[test]
fn same_calls_give_bit_identical_setpoints() {
    let script = |task: &mut MotionTask, a: FbHandle, b: FbHandle| {
        let mut out = Vec::new();
        for n in 0..1500 {
            if n == 0 {
                task.set_move_modulo_inputs(a, go(700.0, 500.0, McDirection::Positive, McBufferMode::Aborting));
            }
            if n == 100 {
                task.set_move_modulo_inputs(b, go(10.0, 300.0, McDirection::ShortestWay, McBufferMode::BlendingHigh));
            }
            task.update();
            let s = task.axis_state(AxisHandle(0));
            out.push((
                s.command_position.to_bits(),
                s.command_velocity.to_bits(),
                s.command_acceleration.to_bits(),
            ));
        }
        out
    };
    let (mut t1, _, a1, b1) = setup(3.0);
    let (mut t2, _, a2, b2) = setup(3.0);
    assert_eq!(script(&mut t1, a1, b1), script(&mut t2, a2, b2));
}

/// Seeded random: a move is aborted mid-motion by a second one with a random
/// target, direction and buffer mode; the axis never reverses after the
/// second starts while moving, and ends exactly on the modulo target.
#[test]
fn random_retargets_never_reverse_and_end_on_the_modulo_target() {
    let mut rng = ChaCha8Rng::seed_from_u64(0x5EED_0010);
    let dirs = [
        McDirection::Positive,
        McDirection::Negative,
        McDirection::ShortestWay,
        McDirection::CurrentDirection,
    ];
    let modes = [
        McBufferMode::Aborting,
        McBufferMode::BlendingLow,
        McBufferMode::BlendingPrevious,
        McBufferMode::BlendingNext,
        McBufferMode::BlendingHigh,
    ];
    for case in 0..10_000 {
        let jerk = if case % 2 == 0 { 0.0 } else { 36000.0 };
        let mut task = MotionTask::new(0.008).unwrap();
        let start = rng.random_range(-1000.0..1000.0);
        let axis = task.add_axis(table_axis(jerk), start).unwrap();
        let a = task.add_move_modulo("A", axis);
        let b = task.add_move_modulo("B", axis);
        let first = go(
            rng.random_range(0.0..1080.0),
            rng.random_range(100.0..720.0),
            dirs[rng.random_range(0..4)],
            McBufferMode::Aborting,
        );
        task.set_move_modulo_inputs(a, first);
        let wait = rng.random_range(1..60);
        for _ in 0..wait {
            task.update();
        }
        let mode = modes[rng.random_range(0..modes.len())];
        let second = go(
            rng.random_range(0.0..1080.0),
            rng.random_range(100.0..720.0),
            dirs[rng.random_range(0..4)],
            mode,
        );
        task.set_move_modulo_inputs(b, second);
        // The direction B must keep: the velocity its profile starts from
        // (none if the axis stood still then; a move from rest is monotone).
        let mut sign: Option<f64> = None;
        let ctx = format!("case {case} from {start}: {first:?} then after {wait} {second:?}");
        for _ in 0..20_000 {
            task.update();
            let s = task.axis_state(axis);
            assert!(
                s.command_position.is_finite() && s.command_velocity.is_finite(),
                "{ctx}"
            );
            let b_started = task.outputs(b).active || task.outputs(b).done;
            if b_started && sign.is_none() {
                let v0 = task.active_profile(axis).map_or(0.0, |(p, _)| p.start_state().velocity);
                sign = Some(if v0 == 0.0 { 0.0 } else { v0.signum() });
            }
            if let Some(sign) = sign.as_mut() {
                if *sign != 0.0 {
                    assert!(s.command_velocity * *sign >= 0.0, "{ctx}: reversed");
                } else if s.command_velocity != 0.0 {
                    *sign = s.command_velocity.signum();
                }
            }
            if task.outputs(b).done {
                break;
            }
        }
        assert!(task.outputs(b).done, "{ctx}: never done");
        let goal = second.position % 360.0;
        let wrapped = task.axis_state(axis).modulo_command_position.unwrap();
        let err = (wrapped - goal).abs().min(360.0 - (wrapped - goal).abs());
        assert!(err <= 1e-9, "{ctx}: ended at {wrapped}, asked {goal}");
    }
}

/// MC_MoveModulo while the axis stops (a MAS ramp): refused with
/// AXIS_STOPPING, the stop goes on; once the axis stands still it runs.
#[test]
fn move_modulo_is_refused_while_the_axis_stops_and_accepted_after() {
    let (mut task, axis, a, _) = setup(0.0);
    let jog = task.add_instruction("Jog");
    let ops = crate::task::instructions::maj::MajOperands {
        speed: 360.0,
        speed_units: 0,
        ..Default::default()
    };
    task.maj(axis, jog, &ops).unwrap();
    run_until(&mut task, 1000, |t| t.axis_state(axis).command_velocity >= 359.0);
    let stop = task.add_instruction("Stop");
    task.mas(
        axis,
        stop,
        &crate::task::instructions::mas::MasOperands {
            stop_type: 0,
            change_decel: 1,
            decel_rate: 100.0,
            decel_units: 0,
        },
    )
    .unwrap();
    task.update();
    assert!(task.stop_in_progress(axis));
    task.set_move_modulo_inputs(a, go(90.0, 100.0, McDirection::Positive, McBufferMode::Aborting));
    task.update();
    let o = task.outputs(a);
    assert!(o.error && o.error_id == ErrorId::AXIS_STOPPING.0 && !o.busy, "{o:?}");
    assert!(task.axis_status(axis).stopping, "the stop goes on");
    let v = task.axis_state(axis).command_velocity;
    task.update();
    assert!(task.axis_state(axis).command_velocity < v);
    run_until(&mut task, 10_000, |t| !t.stop_in_progress(axis));
    release(&mut task, a);
    task.update();
    task.set_move_modulo_inputs(a, go(90.0, 100.0, McDirection::Positive, McBufferMode::Aborting));
    run_until(&mut task, 10_000, |t| t.outputs(a).done);
    assert!((task.axis_state(axis).command_position.rem_euclid(360.0) - 90.0).abs() < 1e-9);
}

/// On a coupled (geared) slave: refused without the axis option; with it,
/// `MC_Buffered` is refused and `MC_Aborting` decouples the axis and runs.
#[test]
fn move_modulo_on_a_coupled_slave_needs_the_axis_option_and_aborting() {
    let gear = |allowed: bool| {
        let mut task = MotionTask::new(DT).unwrap();
        let master = task.add_axis(table_axis(36000.0), 0.0).unwrap();
        let slave_config = AxisConfig {
            allow_motion_on_coupled_slave: allowed,
            ..table_axis(36000.0)
        };
        let slave = task.add_axis(slave_config, 0.0).unwrap();
        let mag = task.add_instruction("Gear");
        let ops = crate::task::instructions::mag::MagOperands {
            ratio: 1.0,
            clutch: 1,
            ..Default::default()
        };
        task.mag(slave, master, mag, &ops).unwrap();
        let fb = task.add_move_modulo("Move", slave);
        task.update();
        assert!(task.axis_status(slave).gearing);
        (task, slave, fb)
    };
    let (mut task, slave, fb) = gear(false);
    task.set_move_modulo_inputs(fb, go(90.0, 100.0, McDirection::Positive, McBufferMode::Aborting));
    task.update();
    assert_eq!(task.outputs(fb).error_id, ErrorId::COUPLED_SLAVE.0);
    assert!(task.axis_status(slave).gearing, "still coupled");

    let (mut task, slave, fb) = gear(true);
    task.set_move_modulo_inputs(fb, go(90.0, 100.0, McDirection::Positive, McBufferMode::Buffered));
    task.update();
    assert_eq!(task.outputs(fb).error_id, ErrorId::COUPLED_BUFFER_MODE.0);
    assert!(task.axis_status(slave).gearing);
    release(&mut task, fb);
    task.update();
    task.set_move_modulo_inputs(fb, go(90.0, 100.0, McDirection::Positive, McBufferMode::Aborting));
    task.update();
    assert!(task.outputs(fb).active && !task.axis_status(slave).gearing, "decoupled");
    run_until(&mut task, 10_000, |t| t.outputs(fb).done);
}

/// Done: with target position monitoring off and position range monitoring
/// on, Done waits for the actual position inside the position range window;
/// `Options.IgnorePositionMonitoring` sets it when setpoint generation ends;
/// `Options.EnableBlendingPosition` is refused.
#[test]
fn move_modulo_done_follows_the_monitoring_and_the_options() {
    let config = AxisConfig {
        target_position_monitoring: false,
        position_range_monitoring: true,
        position_range_window: 2.0,
        ..table_axis(36000.0)
    };
    let mut task = MotionTask::new(DT).unwrap();
    let axis = task.add_axis(config, 0.0).unwrap();
    let fb = task.add_move_modulo("Move", axis);
    task.feed_actual_position(axis, 0.0);
    task.set_move_modulo_inputs(fb, go(90.0, 100.0, McDirection::Positive, McBufferMode::Aborting));
    // The actual position lags 3 units: setpoints end, no Done.
    let mut ended = false;
    for _ in 0..10_000 {
        task.update();
        let cmd = task.axis_state(axis).command_position;
        task.feed_actual_position(axis, cmd - 3.0);
        if task.axis_state(axis).command_velocity == 0.0 && cmd == 90.0 {
            ended = true;
            break;
        }
    }
    assert!(ended);
    for _ in 0..10 {
        task.update();
    }
    assert!(!task.outputs(fb).done && task.outputs(fb).busy);
    task.feed_actual_position(axis, 88.5);
    task.update();
    assert!(task.outputs(fb).done, "inside the 2-unit range window");

    // IgnorePositionMonitoring: Done though the axis lags.
    release(&mut task, fb);
    task.update();
    let mut inputs = go(180.0, 100.0, McDirection::Positive, McBufferMode::Aborting);
    inputs.options.ignore_position_monitoring = true;
    task.set_move_modulo_inputs(fb, inputs);
    for _ in 0..10_000 {
        task.update();
        let cmd = task.axis_state(axis).command_position;
        task.feed_actual_position(axis, cmd - 30.0);
        if task.outputs(fb).done {
            break;
        }
    }
    assert!(task.outputs(fb).done);
    assert_eq!(task.axis_state(axis).command_position, 180.0);

    release(&mut task, fb);
    task.update();
    let mut inputs = go(10.0, 100.0, McDirection::Positive, McBufferMode::Aborting);
    inputs.options.enable_blending_position = true;
    task.set_move_modulo_inputs(fb, inputs);
    task.update();
    assert_eq!(task.outputs(fb).error_id, ErrorId::BLENDING_POSITION.0);
}

/// `profile_overshoot` on a MAM that re-targets the axis 10° ahead while
/// it moves at 720°/s (its stopping distance is about 72°): the new profile
/// passes the target and comes back; the flag holds exactly while the axis
/// is past the target, not for the whole ramp.
#[test]
fn a_target_behind_the_stopping_point_is_an_overshoot_while_past_it() {
    let (mut task, axis, _, _) = setup(0.0);
    let mam = task.add_instruction("Move");
    let far = crate::task::instructions::mam::MamOperands {
        position: 3000.0,
        ..Default::default()
    };
    task.mam(axis, mam, &far).unwrap();
    run_until(&mut task, 1000, |t| t.axis_state(axis).command_velocity >= 720.0 - 1e-9);
    assert!(!task.profile_overshoot(axis));
    let target = task.axis_state(axis).command_position + 10.0;
    let near = crate::task::instructions::mam::MamOperands {
        position: target,
        ..far
    };
    task.mam(axis, mam, &near).unwrap();
    let (mut flagged, mut back) = (0, false);
    for _ in 0..2000 {
        task.update();
        let p = task.axis_state(axis).command_position;
        let on = task.profile_overshoot(axis);
        assert_eq!(on, !back && p > target + 1e-9, "at {p}, target {target}");
        flagged += usize::from(on);
        back |= flagged > 0 && p <= target;
        if task.motion_bits(mam).pc {
            break;
        }
    }
    assert!(flagged > 10 && back);
    assert!((task.axis_state(axis).command_position - target).abs() < 1e-9);
}
