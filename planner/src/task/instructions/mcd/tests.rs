//! MCD through the task: a move's speed lowered with a new jerk and no
//! step, a jog's speed and rates changed, what MCD leaves alone, and each
//! operand's ERR 13.

use super::*;
use crate::axis::{AxisConfig, AxisKind};
use crate::dynamics::MoveDynamics;
use crate::instruction::LogixFault;
use crate::task::instructions::maj::MajOperands;
use crate::task::instructions::mam::MamOperands;

const DT: f64 = 0.004;

fn setup() -> (MotionTask, AxisHandle) {
    let mut task = MotionTask::new(DT).unwrap();
    let config = AxisConfig {
        max_velocity: 200.0,
        max_acceleration: 2000.0,
        max_deceleration: 2000.0,
        max_jerk: 40_000.0,
        ..AxisConfig::new("X", AxisKind::Linear)
    };
    let x = task.add_axis(config, 0.0).unwrap();
    (task, x)
}

/// An S-curve MAM to 400 at 100 units/s, 1000 units/s², jerk 20,000.
fn s_curve_move() -> MamOperands {
    MamOperands {
        position: 400.0,
        dynamics: MoveDynamics {
            speed: 100.0,
            speed_units: 0,
            accel_rate: 1000.0,
            accel_units: 0,
            decel_rate: 1000.0,
            decel_units: 0,
            profile: 1,
            accel_jerk: 20_000.0,
            decel_jerk: 20_000.0,
            jerk_units: 0,
        },
        ..MamOperands::default()
    }
}

#[test]
fn mcd_lowers_a_moves_speed_with_the_new_jerk_and_no_step() {
    let (mut task, x) = setup();
    let mv = task.add_instruction("Move");
    task.mam(x, mv, &s_curve_move()).unwrap();
    for _ in 0..100 {
        task.update();
    }
    let cruise = task.axis_state(x);
    assert!((cruise.command_velocity - 100.0).abs() < 1e-9, "{cruise:?}");
    let change = task.add_instruction("Change");
    let o = McdOperands {
        speed: Change::to(40.0),
        decel_jerk: Change::to(2_000.0),
        ..McdOperands::default()
    };
    task.mcd(x, change, &o).unwrap();
    let b = task.motion_bits(change);
    assert!(b.dn && !b.er && !b.ip, "{b:?}");
    assert!(task.motion_bits(mv).ip);
    let mut last = task.axis_state(x);
    let mut peak_jerk = 0.0f64;
    let mut reached = None;
    for i in 0..4000 {
        task.update();
        let s = task.axis_state(x);
        // No velocity step: the change in one update is at most the
        // deceleration limit's worth; the acceleration moves by at most the
        // new jerk's worth.
        assert!(
            (s.command_velocity - last.command_velocity).abs() <= 1000.0 * DT + 1e-9,
            "{i}: {s:?}"
        );
        assert!(
            (s.command_acceleration - last.command_acceleration).abs() <= 2_000.0 * DT * (1.0 + 1e-9) + 1e-9,
            "{i}"
        );
        peak_jerk = peak_jerk.max(s.command_jerk.abs());
        if reached.is_none() && (s.command_velocity - 40.0).abs() < 1e-9 {
            reached = Some(i);
        }
        last = s;
        if task.motion_bits(mv).pc {
            break;
        }
    }
    // Lowering 60 units/s with jerk 2,000 peaks the deceleration at
    // √(60·2000) ≈ 346 (under the 1,000 limit) and takes 2·√(60/2000) ≈
    // 0.346 s ≈ 86.6 updates (with the old jerk: 0.11 s).
    let reached = reached.expect("the new speed is reached");
    assert!((86..=87).contains(&reached), "{reached}");
    assert!(peak_jerk <= 20_000.0 + 1e-6, "{peak_jerk}");
    assert!(task.motion_bits(mv).pc, "the move still ends at its target");
    assert!((task.axis_state(x).command_position - 400.0).abs() < 1e-9);
}

#[test]
fn mcd_changes_a_jogs_speed_and_rates_and_leaves_other_motion_alone() {
    let (mut task, x) = setup();
    let jog = task.add_instruction("Jog");
    let o = MajOperands {
        speed: 50.0,
        speed_units: 0,
        accel_rate: 500.0,
        accel_units: 0,
        decel_rate: 500.0,
        decel_units: 0,
        ..MajOperands::default()
    };
    task.maj(x, jog, &o).unwrap();
    for _ in 0..50 {
        task.update();
    }
    assert!((task.axis_state(x).command_velocity - 50.0).abs() < 1e-9);
    let change = task.add_instruction("Change");
    // Motion Type move: no move runs, nothing changes, .DN all the same.
    let as_move = McdOperands {
        speed: Change::to(10.0),
        ..McdOperands::default()
    };
    task.mcd(x, change, &as_move).unwrap();
    assert!(task.motion_bits(change).dn);
    task.update();
    assert!((task.axis_state(x).command_velocity - 50.0).abs() < 1e-9);
    // Jog: 50 % of the maximum speed (100) at 100 % of the maximum accel.
    let faster = McdOperands {
        motion_type: 0,
        speed: Change::to(50.0),
        speed_units: 1,
        accel: Change::to(100.0),
        accel_units: 1,
        ..McdOperands::default()
    };
    task.mcd(x, change, &faster).unwrap();
    task.update();
    assert!((task.axis_state(x).command_velocity - (50.0 + 2000.0 * DT)).abs() < 1e-9);
    for _ in 0..20 {
        task.update();
    }
    assert!((task.axis_state(x).command_velocity - 100.0).abs() < 1e-9);
    assert!(task.motion_bits(jog).ip, "the jog goes on");
    // Speed 0: the jog ramps to rest at its (unchanged) decel and stays in
    // process.
    let halt = McdOperands {
        motion_type: 0,
        speed: Change::to(0.0),
        ..McdOperands::default()
    };
    task.mcd(x, change, &halt).unwrap();
    for _ in 0..49 {
        task.update();
        assert!(task.axis_state(x).command_velocity > 0.0);
    }
    task.update();
    assert!(task.axis_state(x).command_velocity.abs() < 1e-9);
    assert!(task.motion_bits(jog).ip);
}

#[test]
fn each_operand_out_of_range_names_its_faceplate_index() {
    let (task, x) = setup();
    let axis = task.axis_config(x);
    let ok = McdOperands::default();
    let exerr = |o: McdOperands| Mcd::new(&o, axis).unwrap_err().exerr();
    let yes = |value| Change::to(value);
    assert_eq!(exerr(McdOperands { motion_type: 2, ..ok }), 2);
    assert_eq!(
        exerr(McdOperands {
            speed: Change { flag: 2, value: 1.0 },
            ..ok
        }),
        3
    );
    assert_eq!(exerr(McdOperands { speed: yes(0.0), ..ok }), 4, "a move needs a speed");
    assert_eq!(
        exerr(McdOperands {
            accel: Change { flag: 7, value: 1.0 },
            ..ok
        }),
        5
    );
    assert_eq!(exerr(McdOperands { accel: yes(-1.0), ..ok }), 6);
    assert_eq!(
        exerr(McdOperands {
            decel: Change { flag: -1, value: 1.0 },
            ..ok
        }),
        7
    );
    assert_eq!(
        exerr(McdOperands {
            decel: yes(f64::NAN),
            ..ok
        }),
        8
    );
    assert_eq!(
        exerr(McdOperands {
            accel_jerk: Change { flag: 3, value: 1.0 },
            ..ok
        }),
        9
    );
    assert_eq!(
        exerr(McdOperands {
            accel_jerk: yes(0.0),
            ..ok
        }),
        10
    );
    assert_eq!(
        exerr(McdOperands {
            decel_jerk: Change { flag: 9, value: 1.0 },
            ..ok
        }),
        11
    );
    assert_eq!(
        exerr(McdOperands {
            decel_jerk: yes(150.0),
            jerk_units: 2,
            ..ok
        }),
        12,
        "% of time is at most 100"
    );
    assert_eq!(
        exerr(McdOperands {
            speed: yes(1.0),
            speed_units: 4,
            ..ok
        }),
        13
    );
    assert_eq!(
        exerr(McdOperands {
            accel: yes(1.0),
            accel_units: 2,
            ..ok
        }),
        14
    );
    assert_eq!(
        exerr(McdOperands {
            decel: yes(1.0),
            decel_units: 3,
            ..ok
        }),
        15
    );
    assert_eq!(
        exerr(McdOperands {
            accel_jerk: yes(1.0),
            jerk_units: 5,
            ..ok
        }),
        16
    );
    // A value whose Change is no is not checked; a jog may be changed to
    // speed 0.
    assert!(
        Mcd::new(
            &McdOperands {
                speed: Change {
                    flag: 0,
                    value: f64::NAN
                },
                ..ok
            },
            axis
        )
        .is_ok()
    );
    assert!(
        Mcd::new(
            &McdOperands {
                motion_type: 0,
                speed: yes(0.0),
                ..ok
            },
            axis
        )
        .is_ok()
    );
    // A refused MCD sets .ER with the codes and leaves the motion as it was.
    let (mut task, x) = setup();
    let mv = task.add_instruction("Move");
    task.mam(x, mv, &s_curve_move()).unwrap();
    task.update();
    let before = task.axis_state(x);
    let change = task.add_instruction("Change");
    let e = task
        .mcd(x, change, &McdOperands { speed: yes(-5.0), ..ok })
        .unwrap_err();
    assert_eq!((e.err(), e.exerr()), (13, 4));
    let b = task.motion_bits(change);
    assert!(b.er && !b.dn);
    task.update();
    let after = task.axis_state(x);
    assert!(after.command_velocity > before.command_velocity);
}
