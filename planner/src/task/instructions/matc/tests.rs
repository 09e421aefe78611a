//! MATC through the task: a once cam over time with distance and time
//! scaling, continuous cycles, the pending cam, ERR 23, what ends a time
//! cam, and the operands' refusals.

use super::*;
use crate::axis::{AxisConfig, AxisKind};
use crate::mccp::CamElement;
use crate::task::instructions::maj::MajOperands;

const DT: f64 = 0.004;

/// An axis and a profile calculated from a linear cam: 0 → 0, 1 s → 10.
fn setup() -> (MotionTask, AxisHandle, CamProfileHandle) {
    let mut task = MotionTask::new(DT).unwrap();
    let config = AxisConfig {
        max_velocity: 100.0,
        max_acceleration: 1e5,
        max_deceleration: 1e5,
        ..AxisConfig::new("S", AxisKind::Linear)
    };
    let s = task.add_axis(config, 5.0).unwrap();
    let profile = task.add_cam_profile("P", 2);
    let cam = [
        CamElement {
            master: 0.0,
            slave: 0.0,
            segment_type: 0,
        },
        CamElement {
            master: 1.0,
            slave: 10.0,
            segment_type: 0,
        },
    ];
    let mccp = task.add_instruction("Calc");
    task.mccp_from(mccp, &cam, 0, 2, 0.0, 0.0, profile).unwrap();
    (task, s, profile)
}

fn operands(distance_scaling: f64, time_scaling: f64, continuous: bool, pending: bool) -> MatcOperands {
    MatcOperands {
        direction: 0,
        distance_scaling,
        time_scaling,
        codes: (i64::from(continuous), i64::from(pending), 0, 0),
    }
}

fn pos(task: &MotionTask, s: AxisHandle) -> f64 {
    task.axis_state(s).command_position
}

#[test]
fn a_once_time_cam_scales_distance_and_time_and_completes() {
    let (mut task, s, profile) = setup();
    let mc = task.add_instruction("Cam");
    task.matc(s, mc, profile, &operands(3.0, 2.0, false, false)).unwrap();
    assert_eq!(task.time_cam_status(s), (true, false));
    assert!(task.motion_bits(mc).dn && task.motion_bits(mc).ip);
    // 30 units over 2 s: 15 units/s.
    for k in 1..=600 {
        task.update();
        let t = (k as f64 * DT).min(2.0);
        assert!(
            (pos(&task, s) - (5.0 + 15.0 * t)).abs() < 1e-9,
            "{k}: {}",
            pos(&task, s)
        );
    }
    assert!((pos(&task, s) - 35.0).abs() < 1e-9);
    assert!(task.motion_bits(mc).pc && !task.motion_bits(mc).ip);
    assert_eq!(task.time_cam_status(s), (false, false));
}

#[test]
fn continuous_cycles_a_pending_cam_and_err_23() {
    let (mut task, s, profile) = setup();
    let first = task.add_instruction("First");
    task.matc(s, first, profile, &operands(1.0, 0.5, true, false)).unwrap();
    // Continuous: 10 units every 0.5 s.
    for _ in 0..250 {
        task.update();
    }
    assert!((pos(&task, s) - 25.0).abs() < 1e-9, "{}", pos(&task, s));
    // Immediate on an axis time camming: ERR 23.
    let second = task.add_instruction("Second");
    let e = task
        .matc(s, second, profile, &operands(1.0, 1.0, false, false))
        .unwrap_err();
    assert_eq!(e.err(), 23);
    // Pending waits behind the running cam (continuous: until it ends).
    task.matc(s, second, profile, &operands(-1.0, 1.0, false, true))
        .unwrap();
    assert_eq!(task.time_cam_status(s), (true, true));
    // A jog takes the axis: both time cams end without .PC.
    let jog = task.add_instruction("Jog");
    task.maj(
        s,
        jog,
        &MajOperands {
            speed: 1.0,
            speed_units: 0,
            ..MajOperands::default()
        },
    )
    .unwrap();
    assert_eq!(task.time_cam_status(s), (false, false));
    assert!(!task.motion_bits(first).ip && !task.motion_bits(first).pc);
    assert!(!task.motion_bits(second).ip);
}

#[test]
fn refusals() {
    let (mut task, s, profile) = setup();
    let mc = task.add_instruction("Cam");
    let e = |task: &mut MotionTask, o: MatcOperands| {
        let e = task.matc(s, mc, profile, &o).unwrap_err();
        (e.err(), e.exerr())
    };
    let ok = operands(1.0, 1.0, false, false);
    assert_eq!(e(&mut task, MatcOperands { direction: 4, ..ok }), (13, 2));
    assert_eq!(
        e(
            &mut task,
            MatcOperands {
                distance_scaling: f64::NAN,
                ..ok
            }
        ),
        (13, 4)
    );
    assert_eq!(
        e(
            &mut task,
            MatcOperands {
                time_scaling: 0.0,
                ..ok
            }
        ),
        (13, 5)
    );
    assert_eq!(
        e(
            &mut task,
            MatcOperands {
                codes: (2, 0, 0, 0),
                ..ok
            }
        ),
        (13, 6)
    );
    assert_eq!(
        e(
            &mut task,
            MatcOperands {
                codes: (0, 0, 3, 0),
                ..ok
            }
        ),
        (13, 9)
    );
    assert_eq!(
        e(
            &mut task,
            MatcOperands {
                codes: (0, 0, 0, 1),
                ..ok
            }
        ),
        (13, 10)
    );
    // Too fast for the axis: 10 units/s × 20,000 is above 1000 × its
    // maximum speed of 100.
    assert_eq!(
        e(
            &mut task,
            MatcOperands {
                distance_scaling: 20_000.0,
                ..ok
            }
        ),
        (13, 4)
    );
    // A profile not calculated: ERR 32.
    let other = task.add_cam_profile("Q", 2);
    let err = task.matc(s, mc, other, &ok).unwrap_err();
    assert_eq!(err.err(), 32);
}
