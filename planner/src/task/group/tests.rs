//! Group stops by each axis' programmed stop mode, and the status words.

use super::*;
use crate::axis::{AxisConfig, AxisKind};
use crate::servo::AxisType;
use crate::task::instructions::maj::MajOperands;

fn axis(task: &mut MotionTask, name: &str, mode: ProgrammedStopMode, axis_type: AxisType) -> AxisHandle {
    let config = AxisConfig {
        max_velocity: 100.0,
        max_acceleration: 1000.0,
        max_deceleration: 500.0,
        programmed_stop_mode: mode,
        axis_type,
        ..AxisConfig::new(name, AxisKind::Linear)
    };
    task.add_axis(config, 0.0).unwrap()
}

#[test]
fn mgs_programmed_follows_each_axis_programmed_stop_mode() {
    use ProgrammedStopMode as M;
    let mut task = MotionTask::new(0.004).unwrap();
    let modes = [
        (M::FastStop, AxisType::Servo),
        (M::FastDisable, AxisType::Servo),
        (M::HardDisable, AxisType::Servo),
        (M::FastShutdown, AxisType::Servo),
        (M::HardShutdown, AxisType::Servo),
        (M::FastDisable, AxisType::Virtual),
    ];
    let axes: Vec<AxisHandle> = modes
        .iter()
        .enumerate()
        .map(|(i, (m, t))| axis(&mut task, &format!("A{i}"), *m, *t))
        .collect();
    for (i, a) in axes.iter().enumerate() {
        let jog = task.add_instruction(format!("Jog{i}"));
        let o = MajOperands {
            speed: 100.0,
            ..MajOperands::default()
        };
        task.maj(*a, jog, &o).unwrap();
    }
    for _ in 0..50 {
        task.update();
    }
    let mgs = task.add_instruction("Mgs");
    task.group_stop(mgs, GroupStop::Programmed);
    // The hard modes act at once.
    assert!(!task.is_servo_on(axes[2]) && !task.axis_status(axes[2]).shutdown);
    assert!(task.axis_status(axes[4]).shutdown);
    assert_eq!(task.axis_state(axes[2]).command_velocity, 0.0);
    // The fast ones ramp at the maximum deceleration (500): 100 → 0 in
    // 0.2 s, 50 updates; the servo stays on meanwhile.
    for _ in 0..49 {
        task.update();
        for k in [0, 1, 3, 5] {
            assert!(task.is_servo_on(axes[k]), "axis {k}");
            assert!(task.axis_state(axes[k]).command_velocity > 0.0, "axis {k}");
        }
        assert!(task.motion_bits(mgs).ip && !task.motion_bits(mgs).pc);
    }
    task.update();
    assert!(task.is_servo_on(axes[0]), "Fast Stop: on");
    assert!(
        !task.is_servo_on(axes[1]) && !task.axis_status(axes[1]).shutdown,
        "Fast Disable: off"
    );
    assert!(task.axis_status(axes[3]).shutdown, "Fast Shutdown: shut down");
    assert!(task.is_servo_on(axes[5]), "a virtual axis has no drive to disable");
    let b = task.motion_bits(mgs);
    assert!(b.pc && !b.ip && b.dn);
}

#[test]
fn status_words_follow_the_axes() {
    let mut task = MotionTask::new(0.004).unwrap();
    let a = axis(&mut task, "A", ProgrammedStopMode::FastStop, AxisType::Servo);
    assert_eq!(task.group_status().group_status, GroupStatus::GROUP_SYNCED);
    let b = task
        .add_axis(
            AxisConfig {
                inhibited: true,
                ..AxisConfig::new("B", AxisKind::Linear)
            },
            0.0,
        )
        .unwrap();
    let s = task.group_status();
    assert_eq!(
        s.group_status,
        GroupStatus::GROUP_SYNCED | GroupStatus::AXIS_INHIBIT_STATUS
    );
    assert_eq!(
        (s.motion_fault, s.servo_fault, s.group_fault, s.axis_fault),
        (0, 0, 0, 0)
    );
    // MGSP latches each axis; the inhibited one too.
    task.axes[a.0 as usize].command.position = 12.5;
    task.axes[a.0 as usize].actual = 12.25;
    let strobe = task.add_instruction("Strobe");
    task.group_strobe(strobe);
    assert_eq!(task.strobe_positions(a), (12.25, 12.5));
    assert_eq!(task.strobe_positions(b), (0.0, 0.0));
    assert!(task.motion_bits(strobe).dn);
}

/// A fast-disabled axis whose joint still coasts (its fed position moves
/// after the drive is off) does not hold back `.PC`.
#[test]
fn a_disabled_axis_that_coasts_does_not_hold_back_pc() {
    let mut task = MotionTask::new(0.004).unwrap();
    let a = axis(&mut task, "A", ProgrammedStopMode::FastStop, AxisType::Servo);
    let b = axis(&mut task, "B", ProgrammedStopMode::FastStop, AxisType::Servo);
    let jog = task.add_instruction("Jog");
    let fast = MajOperands {
        speed: 100.0,
        ..MajOperands::default()
    };
    task.maj(a, jog, &fast).unwrap();
    let jog_b = task.add_instruction("JogB");
    task.maj(b, jog_b, &MajOperands { speed: 10.0, ..fast }).unwrap();
    for _ in 0..50 {
        task.update();
    }
    let mgs = task.add_instruction("Mgs");
    task.group_stop(mgs, GroupStop::FastDisable);
    // B's joint lags: after its drive is off its fed position keeps moving.
    let mut fed = task.axis_state(b).command_position;
    for _ in 0..100 {
        fed += 0.05;
        task.feed_actual_position(b, fed);
        task.feed_actual_position(a, task.axis_state(a).command_position);
        task.update();
    }
    assert!(!task.is_servo_on(b) && !task.is_servo_on(a));
    assert!(task.motion_bits(mgs).pc && !task.motion_bits(mgs).ip);
}
