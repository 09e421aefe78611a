//! Axis states through the task: the state instructions' bits and
//! transitions, the state every motion instruction needs with its ERR and
//! EXERR, the fault reaction, and seeded random instruction sequences.

use super::*;
use crate::axis::{AxisConfig, AxisKind};
use crate::coord::{CoordMoveInputs, CoordinateSystemConfig};
use crate::dynamics::MoveDynamics;
use crate::instruction::LogixFault;
use crate::modulo::{MoveModuloError, MoveModuloInputs};
use crate::task::engine::CoordCall;
use crate::task::instructions::maj::{MajError as JogError, MajOperands};
use crate::task::instructions::mas::MasOperands;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

const DT: f64 = 0.004;

fn config(name: &str) -> AxisConfig {
    AxisConfig {
        max_velocity: 100.0,
        max_acceleration: 1000.0,
        max_deceleration: 1000.0,
        modulo_period: Some(360.0),
        start_servo_on: false,
        ..AxisConfig::new(name, AxisKind::Rotary)
    }
}

fn jog(speed: f64) -> MajOperands {
    MajOperands {
        speed,
        ..MajOperands::default()
    }
}

fn one(config: AxisConfig) -> (MotionTask, AxisHandle, InstructionHandle) {
    let mut task = MotionTask::new(DT).unwrap();
    let axis = task.add_axis(config, 10.0).unwrap();
    let mi = task.add_instruction("MC");
    (task, axis, mi)
}

fn err(task: &MotionTask, mi: InstructionHandle) -> (bool, i32, i32) {
    let b = task.motion_bits(mi);
    (b.er, b.err, b.exerr)
}

fn enable(task: &mut MotionTask, axis: AxisHandle, mso: InstructionHandle) {
    task.mso(axis, mso).unwrap();
    for _ in 0..SERVO_ENABLE_UPDATES {
        task.update();
    }
    assert!(task.motion_bits(mso).dn && task.is_servo_on(axis));
}

#[test]
fn a_servo_off_axis_refuses_motion_until_mso_has_closed_the_loop() {
    let (mut task, axis, mi) = one(config("A"));
    assert_eq!(task.cip_axis_state(axis), CipAxisState::Stopped);
    assert!(!task.axis_status(axis).servo_action);
    assert_eq!(
        task.maj(axis, mi, &jog(10.0)),
        Err(JogError::from(StateError::ServoOff))
    );
    assert_eq!(err(&task, mi), (true, 5, 0));
    let mso = task.add_instruction("MSO");
    task.mso(axis, mso).unwrap();
    let b = task.motion_bits(mso);
    assert!(b.en && !b.dn && !b.er, "MSO is done only when the loop is closed");
    assert_eq!(task.cip_axis_state(axis), CipAxisState::Starting);
    assert_eq!(
        task.maj(axis, mi, &jog(10.0)),
        Err(JogError::from(StateError::ServoOff))
    );
    for _ in 0..SERVO_ENABLE_UPDATES - 1 {
        task.update();
        assert!(!task.motion_bits(mso).dn);
    }
    task.update();
    assert!(task.motion_bits(mso).dn);
    assert_eq!(task.cip_axis_state(axis), CipAxisState::Running);
    let s = task.axis_status(axis);
    assert!(s.servo_action && s.drive_enable);
    task.maj(axis, mi, &jog(10.0)).unwrap();
    task.update();
    assert!(task.axis_status(axis).jogging);
    assert!(task.axis_state(axis).command_velocity > 0.0);
    // A second MSO on a servo-on axis: done at once, nothing changes.
    task.mso(axis, mso).unwrap();
    assert!(task.motion_bits(mso).dn && task.axis_status(axis).jogging);
}

#[test]
fn the_brake_release_delay_lengthens_the_enable() {
    let (mut task, axis, mso) = one(AxisConfig {
        servo_enable_delay_s: 0.1,
        ..config("A")
    });
    task.mso(axis, mso).unwrap();
    let mut updates = 0;
    while !task.motion_bits(mso).dn {
        task.update();
        updates += 1;
        assert!(updates < 1000);
    }
    assert_eq!(updates, 25, "0.1 s at 4 ms");
}

#[test]
fn msf_ends_a_jog_at_once_and_the_command_follows_the_actual_position() {
    let (mut task, axis, mi) = one(AxisConfig {
        start_servo_on: true,
        ..config("A")
    });
    task.maj(axis, mi, &jog(50.0)).unwrap();
    for _ in 0..20 {
        task.update();
        let p = task.axis_state(axis).command_position;
        task.feed_actual_position(axis, p - 0.5);
    }
    let msf = task.add_instruction("MSF");
    task.msf(axis, msf).unwrap();
    assert!(task.motion_bits(msf).dn);
    assert!(!task.motion_bits(mi).ip, "the jog ended");
    assert_eq!(task.cip_axis_state(axis), CipAxisState::Stopped);
    // The joint coasts: the command follows what is fed back.
    for k in 0..10 {
        let fed = 40.0 + f64::from(k);
        task.feed_actual_position(axis, fed);
        task.update();
        let s = task.axis_state(axis);
        assert_eq!(s.command_position, fed);
        assert!(!s.has_job);
    }
    // MSO on an axis still moving: Axis In Motion.
    let mso = task.add_instruction("MSO");
    assert_eq!(task.mso(axis, mso), Err(StateError::InMotion));
    assert_eq!(err(&task, mso), (true, 22, 0));
    // At rest: MSO enables where the axis is, without a jump.
    task.feed_actual_position(axis, 49.0);
    task.update();
    task.mso(axis, mso).unwrap();
    for _ in 0..SERVO_ENABLE_UPDATES {
        task.update();
        assert_eq!(task.axis_state(axis).command_position, 49.0);
    }
    assert!(task.motion_bits(mso).dn && task.is_servo_on(axis));
}

#[test]
fn shutdown_needs_masr_and_mafr_does_not_clear_it() {
    let (mut task, axis, mi) = one(AxisConfig {
        start_servo_on: true,
        ..config("A")
    });
    let (masd, masr, mafr, mso) = (
        task.add_instruction("MASD"),
        task.add_instruction("MASR"),
        task.add_instruction("MAFR"),
        task.add_instruction("MSO"),
    );
    task.masd(axis, masd).unwrap();
    assert_eq!(task.cip_axis_state(axis), CipAxisState::Shutdown);
    assert!(task.axis_status(axis).shutdown);
    assert_eq!(task.maj(axis, mi, &jog(1.0)), Err(JogError::from(StateError::Shutdown)));
    assert_eq!(err(&task, mi), (true, 7, 0));
    assert_eq!(task.mso(axis, mso), Err(StateError::Shutdown));
    task.mafr(axis, mafr).unwrap();
    assert_eq!(task.cip_axis_state(axis), CipAxisState::Shutdown);
    task.masr(axis, masr).unwrap();
    assert_eq!(
        task.cip_axis_state(axis),
        CipAxisState::Stopped,
        "servo off after the reset"
    );
    enable(&mut task, axis, mso);
}

#[test]
fn feedback_only_and_inhibited_axes_refuse_with_8_and_53() {
    let (mut task, axis, mi) = one(AxisConfig {
        axis_type: AxisType::FeedbackOnly,
        ..config("Encoder")
    });
    assert_eq!(task.mso(axis, mi), Err(StateError::AxisType));
    assert_eq!(err(&task, mi), (true, 8, 0));
    assert_eq!(task.msf(axis, mi), Err(StateError::AxisType));
    assert_eq!(task.maj(axis, mi, &jog(1.0)), Err(JogError::from(StateError::AxisType)));
    let fb = task.add_move_modulo("Move", axis);
    task.set_move_modulo_inputs(
        fb,
        MoveModuloInputs {
            execute: true,
            position: 90.0,
            velocity: 10.0,
            ..Default::default()
        },
    );
    task.update();
    let out = task.outputs(fb);
    assert!(out.error);
    assert_eq!(
        out.error_id,
        MoveModuloError::AxisNotReady(StateError::AxisType).error_id().0
    );

    let (mut task, axis, mi) = one(AxisConfig {
        inhibited: true,
        start_servo_on: true,
        ..config("A")
    });
    assert_eq!(task.cip_axis_state(axis), CipAxisState::AxisInhibited);
    assert!(task.axis_status(axis).inhibit && !task.axis_status(axis).servo_action);
    for r in [
        task.mso(axis, mi),
        task.masd(axis, mi),
        task.masr(axis, mi),
        task.mafr(axis, mi),
    ] {
        assert_eq!(r, Err(StateError::Inhibited));
    }
    let stop = MasOperands::default();
    assert_eq!(task.mas(axis, mi, &stop), Err(JogError::from(StateError::Inhibited)));
    assert_eq!(err(&task, mi), (true, 53, 0));
}

#[test]
fn a_coordinated_move_names_the_axis_at_fault_by_its_index() {
    let mut task = MotionTask::new(DT).unwrap();
    let on = AxisConfig::new("X", AxisKind::Linear);
    let x = task.add_axis(on.clone(), 0.0).unwrap();
    let off = AxisConfig {
        name: "Y".into(),
        start_servo_on: false,
        ..on
    };
    let y = task.add_axis(off, 0.0).unwrap();
    let cs = crate::task::tests::two_axis_system(&mut task, "CS", x, y);
    let call = CoordCall::Mclm(CoordMoveInputs {
        position: vec![1.0, 1.0],
        dynamics: MoveDynamics {
            speed: 10.0,
            accel_rate: 50.0,
            decel_rate: 50.0,
            ..CoordMoveInputs::default().dynamics
        },
        ..Default::default()
    });
    let h = task.add_coord_instruction("Line", cs, call.clone());
    let fire = |task: &mut MotionTask| {
        task.set_coord_instruction(h, false, call.clone());
        task.update();
        task.set_coord_instruction(h, true, call.clone());
        task.update();
        let b = task.coord_bits(h);
        (b.er, b.err, b.exerr)
    };
    assert_eq!(fire(&mut task), (true, 5, 1));
    let mcsd = task.add_instruction("MCSD");
    task.mcsd(cs, mcsd).unwrap();
    assert_eq!(task.cip_axis_state(x), CipAxisState::Shutdown);
    assert_eq!(task.cip_axis_state(y), CipAxisState::Shutdown);
    assert_eq!(fire(&mut task), (true, 7, 0));
    task.mcsr(cs, mcsd).unwrap();
    assert_eq!(task.cip_axis_state(x), CipAxisState::Stopped);
    let mso = task.add_instruction("MSO");
    enable(&mut task, x, mso);
    enable(&mut task, y, mso);
    assert_eq!(fire(&mut task), (false, 0, 0));
    assert!(task.coordinated_motion_status(x));
}

#[test]
fn an_excessive_position_error_takes_the_configured_action() {
    let tolerance = 2.0;
    for (action, state) in [
        (FaultAction::StopDrive, CipAxisState::Faulted),
        (FaultAction::Shutdown, CipAxisState::Shutdown),
        (FaultAction::StopPlanner, CipAxisState::Running),
        (FaultAction::FaultStatusOnly, CipAxisState::Running),
    ] {
        let (mut task, axis, mi) = one(AxisConfig {
            start_servo_on: true,
            position_error_tolerance: Some(tolerance),
            position_error_action: action,
            ..config("A")
        });
        task.maj(axis, mi, &jog(50.0)).unwrap();
        // The joint is stuck at 10: the error grows until it trips.
        let mut tripped = false;
        for _ in 0..200 {
            task.feed_actual_position(axis, 10.0);
            task.update();
            if !task.axis_faults(axis).is_clear() {
                tripped = true;
                break;
            }
            let e = task.axis_state(axis).command_position - 10.0;
            assert!(e.abs() <= tolerance, "{action:?}: no fault at error {e}");
        }
        assert!(tripped, "{action:?}");
        assert_eq!(task.axis_faults(axis).0, AxisFaults::MOTION, "{action:?}");
        assert_eq!(task.cip_axis_state(axis), state, "{action:?}");
        let jog_runs = task.motion_bits(mi).ip;
        assert_eq!(jog_runs, action == FaultAction::FaultStatusOnly, "{action:?}");
        if action == FaultAction::StopDrive {
            let (mso, mafr) = (task.add_instruction("MSO"), task.add_instruction("MAFR"));
            assert_eq!(task.mso(axis, mso), Err(StateError::Faulted));
            assert_eq!(err(&task, mso), (true, 20, 0));
            task.mafr(axis, mafr).unwrap();
            assert!(task.axis_faults(axis).is_clear());
            assert_eq!(task.cip_axis_state(axis), CipAxisState::Stopped, "MSO again");
        }
        if action == FaultAction::StopPlanner {
            assert!(task.axis_status(axis).stopping);
        }
    }
}

#[test]
fn virtual_axes_are_on_and_come_back_on_after_a_shutdown_reset() {
    let (mut task, axis, mi) = one(AxisConfig {
        axis_type: AxisType::Virtual,
        ..config("V")
    });
    assert!(task.is_servo_on(axis));
    assert!(!task.axis_status(axis).drive_enable, "no drive");
    task.masd(axis, mi).unwrap();
    assert_eq!(task.cip_axis_state(axis), CipAxisState::Shutdown);
    task.masr(axis, mi).unwrap();
    assert_eq!(task.cip_axis_state(axis), CipAxisState::Running);
}

/// Random sequences of MSO, MSF, MASD, MASR, MAFR, MAJ, MAS, MAM and
/// MC_MoveModulo on a fed axis: nothing panics, a servo-off axis is never
/// commanded away from where it is, and every refusal carries a
/// documented ERR.
#[test]
fn random_state_sequences_never_move_a_disabled_axis() {
    const DOCUMENTED: [i32; 8] = [5, 7, 8, 13, 16, 20, 22, 53];
    let mut refusals = 0;
    for seed in 0..200u64 {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let config = AxisConfig {
            axis_type: if rng.random_bool(0.1) {
                AxisType::FeedbackOnly
            } else {
                AxisType::Servo
            },
            inhibited: rng.random_bool(0.05),
            start_servo_on: rng.random_bool(0.5),
            position_error_tolerance: rng.random_bool(0.5).then_some(5.0),
            ..config("A")
        };
        let config = AxisConfig {
            homing: crate::homing::Homing {
                mode: if config.axis_type == AxisType::FeedbackOnly || rng.random_bool(0.3) {
                    crate::homing::HomeMode::Passive
                } else {
                    crate::homing::HomeMode::Active
                },
                position: rng.random_range(-50.0..50.0),
                ..Default::default()
            },
            ..config
        };
        let (mut task, axis, mi) = one(config);
        let fb = task.add_move_modulo("Move", axis);
        // A drive that closes a random part of its following error each
        // update (the plant); a disabled one stays where it is. `actual` is
        // the joint's position; the axis reads it shifted by the position
        // redefinitions (MAH).
        let mut actual = task.axis_state(axis).actual_position;
        let mut execute = false;
        for _ in 0..400 {
            let r = match rng.random_range(0..11) {
                0 => task.mso(axis, mi).err().map(StateError::err),
                1 => task.msf(axis, mi).err().map(StateError::err),
                2 => task.masd(axis, mi).err().map(StateError::err),
                3 => task.masr(axis, mi).err().map(StateError::err),
                4 => task.mafr(axis, mi).err().map(StateError::err),
                5 => {
                    let speed = rng.random_range(-150.0..150.0);
                    task.maj(axis, mi, &jog(speed)).err().map(|e| e.err())
                }
                6 => task.mas(axis, mi, &MasOperands::default()).err().map(|e| e.err()),
                7 => {
                    execute = !execute;
                    let inputs = MoveModuloInputs {
                        execute,
                        position: rng.random_range(0.0..360.0),
                        velocity: 50.0,
                        ..Default::default()
                    };
                    task.set_move_modulo_inputs(fb, inputs);
                    None
                }
                8 => {
                    let o = crate::task::instructions::mam::MamOperands {
                        move_type: rng.random_range(0..5),
                        position: rng.random_range(0.0..720.0),
                        ..crate::task::instructions::mam::MamOperands::default()
                    };
                    task.mam(axis, mi, &o).err().map(|e| e.err())
                }
                9 => task.mah(axis, mi).err().map(StateError::err),
                _ => None,
            };
            if let Some(code) = r {
                refusals += 1;
                assert!(DOCUMENTED.contains(&code), "seed {seed}: ERR {code}");
                assert_eq!(task.motion_bits(mi).err, code);
            }
            let enabled_before = task.is_drive_enabled(axis);
            task.update();
            let s = task.axis_state(axis);
            assert!(s.command_position.is_finite() && s.actual_position.is_finite());
            let offset = task.position_offset(axis);
            if !enabled_before && !task.is_drive_enabled(axis) {
                assert!(
                    (s.command_position - (actual + offset)).abs() < 1e-9,
                    "seed {seed}: a servo-off axis follows its actual position"
                );
                assert!(!s.has_job, "seed {seed}");
            }
            if task.is_drive_enabled(axis) {
                actual += (s.command_position - offset - actual) * rng.random_range(0.3..1.0);
            }
            task.feed_actual_position(axis, actual + offset);
        }
    }
    assert!(refusals > 1000, "the sequences exercise refusals: {refusals}");
}

fn homing(mode: crate::homing::HomeMode, position: f64) -> crate::homing::Homing {
    crate::homing::Homing {
        mode,
        position,
        ..Default::default()
    }
}

#[test]
fn mah_from_rest_homes_in_its_own_scan() {
    use crate::homing::HomeMode;
    let (mut task, axis, mi) = one(AxisConfig {
        homing: homing(HomeMode::Active, 25.0),
        modulo_period: None,
        ..config("A")
    });
    // Active homing needs the servo on.
    assert_eq!(task.mah(axis, mi), Err(StateError::ServoOff));
    assert_eq!(err(&task, mi), (true, 5, 0));
    assert!(!task.axis_status(axis).homed);
    let mso = task.add_instruction("MSO");
    enable(&mut task, axis, mso);
    task.mah(axis, mi).unwrap();
    let b = task.motion_bits(mi);
    assert!(b.en && b.dn && b.pc && !b.ip && !b.er);
    let s = task.axis_state(axis);
    assert_eq!((s.command_position, s.actual_position), (25.0, 25.0));
    let st = task.axis_status(axis);
    assert!(st.homed && !st.homing);
    // The redefinition holds through the next updates.
    task.update();
    assert_eq!(task.axis_state(axis).command_position, 25.0);
}

#[test]
fn active_mah_stops_a_jog_first_and_refuses_motion_while_homing() {
    use crate::homing::HomeMode;
    let (mut task, axis, mi) = one(AxisConfig {
        homing: homing(HomeMode::Active, -5.0),
        modulo_period: None,
        ..config("A")
    });
    let mso = task.add_instruction("MSO");
    enable(&mut task, axis, mso);
    let jog_mi = task.add_instruction("Jog");
    task.maj(axis, jog_mi, &jog(80.0)).unwrap();
    for _ in 0..50 {
        task.update();
    }
    let home = task.add_instruction("Home");
    task.mah(axis, home).unwrap();
    let b = task.motion_bits(home);
    assert!(b.dn && b.ip && !b.pc);
    assert!(!task.motion_bits(jog_mi).ip, "the jog is cancelled");
    assert!(task.axis_status(axis).homing);
    // Motion and a second MAH are refused while homing.
    assert_eq!(task.maj(axis, mi, &jog(10.0)), Err(JogError::from(StateError::Homing)));
    assert_eq!(err(&task, mi), (true, 16, 0));
    let again = task.add_instruction("Again");
    assert_eq!(task.mah(axis, again), Err(StateError::Homing));
    let mut updates = 0;
    while task.motion_bits(home).ip {
        task.update();
        updates += 1;
        assert!(updates < 100, "the stop ends");
    }
    // 80 units/s at 1000 units/s² stops in 0.08 s.
    assert!((15..=30).contains(&updates), "{updates}");
    let b = task.motion_bits(home);
    assert!(b.pc && !b.er);
    let s = task.axis_state(axis);
    assert_eq!((s.command_position, s.command_velocity), (-5.0, 0.0));
    assert!(task.axis_status(axis).homed && !task.axis_status(axis).homing);
    task.maj(axis, mi, &jog(10.0)).unwrap();
}

#[test]
fn passive_mah_works_servo_off_and_on_feedback_only_axes() {
    use crate::homing::HomeMode;
    for axis_type in [AxisType::Servo, AxisType::FeedbackOnly] {
        let (mut task, axis, mi) = one(AxisConfig {
            axis_type,
            homing: homing(HomeMode::Passive, 90.0),
            modulo_period: None,
            ..config("A")
        });
        task.mah(axis, mi).unwrap();
        assert!(task.motion_bits(mi).pc);
        assert_eq!(task.axis_state(axis).actual_position, 90.0);
        assert!(task.axis_status(axis).homed);
    }
    // Active homing needs a drive.
    let (mut task, axis, mi) = one(AxisConfig {
        axis_type: AxisType::FeedbackOnly,
        homing: homing(HomeMode::Active, 0.0),
        ..config("A")
    });
    assert_eq!(task.mah(axis, mi), Err(StateError::AxisType));
    assert_eq!(err(&task, mi), (true, 8, 0));
}

#[test]
fn a_disable_ends_a_homing_in_process() {
    use crate::homing::HomeMode;
    let (mut task, axis, _) = one(AxisConfig {
        homing: homing(HomeMode::Active, 0.0),
        ..config("A")
    });
    let mso = task.add_instruction("MSO");
    enable(&mut task, axis, mso);
    let jog_mi = task.add_instruction("Jog");
    task.maj(axis, jog_mi, &jog(80.0)).unwrap();
    for _ in 0..20 {
        task.update();
    }
    let home = task.add_instruction("Home");
    task.mah(axis, home).unwrap();
    let off = task.add_instruction("MSF");
    task.msf(axis, off).unwrap();
    let b = task.motion_bits(home);
    assert!(!b.ip && !b.pc);
    assert!(!task.axis_status(axis).homing && !task.axis_status(axis).homed);
}

/// Axes X and Y (both `config`, renamed) in a coordinate system, 0.4 s
/// into an MCLM to (50, 50) at 40 units/s.
fn line_under_way(config: AxisConfig) -> (MotionTask, AxisHandle, AxisHandle) {
    let mut task = MotionTask::new(DT).unwrap();
    let x = task.add_axis(config.clone(), 0.0).unwrap();
    let y = task
        .add_axis(
            AxisConfig {
                name: "Y".into(),
                ..config
            },
            0.0,
        )
        .unwrap();
    let cs = task
        .add_coordinate_system(
            CoordinateSystemConfig {
                axis_count: 2,
                primary_axes: 2,
                max_speed: 100.0,
                max_accel: 500.0,
                max_decel: 500.0,
                ..CoordinateSystemConfig::new("CS")
            },
            &[x, y],
        )
        .unwrap();
    let call = CoordCall::Mclm(CoordMoveInputs {
        position: vec![50.0, 50.0],
        dynamics: MoveDynamics {
            speed: 40.0,
            accel_rate: 200.0,
            decel_rate: 200.0,
            ..CoordMoveInputs::default().dynamics
        },
        ..Default::default()
    });
    let h = task.add_coord_instruction("Line", cs, call.clone());
    task.set_coord_instruction(h, true, call);
    for _ in 0..100 {
        task.update();
    }
    (task, x, y)
}

#[test]
fn active_mah_during_a_coordinated_move_waits_for_the_path_to_stop() {
    use crate::homing::HomeMode;
    let config = AxisConfig {
        homing: homing(HomeMode::Active, 100.0),
        ..AxisConfig::new("X", AxisKind::Linear)
    };
    let (mut task, x, y) = line_under_way(config);
    assert!(task.coordinated_motion_status(x));
    let home = task.add_instruction("Home");
    task.mah(x, home).unwrap();
    assert!(task.motion_bits(home).ip && task.axis_status(x).homing);
    let mut updates = 0;
    while task.motion_bits(home).ip {
        task.update();
        updates += 1;
        assert!(updates < 200, "the path stops and the homing ends");
    }
    assert!(task.motion_bits(home).pc);
    assert!(!task.coordinated_motion_status(x) && !task.coordinated_motion_status(y));
    let (sx, sy) = (task.axis_state(x), task.axis_state(y));
    assert_eq!((sx.command_velocity, sy.command_velocity), (0.0, 0.0));
    assert!((sx.command_position - 100.0).abs() < 1e-9, "homed to 100");
    assert!(sy.command_position < 50.0, "Y stopped short of the target");
}

#[test]
fn a_disable_during_a_coordinated_move_brings_the_other_axes_to_rest() {
    let config = AxisConfig {
        max_deceleration: 400.0,
        ..AxisConfig::new("X", AxisKind::Linear)
    };
    let (mut task, x, y) = line_under_way(config);
    let vy = task.axis_state(y).command_velocity;
    assert!(vy > 20.0, "{vy}");
    let msf = task.add_instruction("MSF");
    task.msf(x, msf).unwrap();
    assert!(!task.coordinated_motion_status(y));
    // Y ramps down at its 400 units/s² instead of keeping the path's speed.
    let mut updates = 0;
    while task.axis_state(y).command_velocity != 0.0 {
        task.update();
        updates += 1;
        assert!(updates < 100, "Y comes to rest");
    }
    assert!(updates as f64 * DT >= vy / 400.0 - 2.0 * DT, "{updates} updates");
    let p = task.axis_state(y).command_position;
    task.update();
    assert_eq!(task.axis_state(y).command_position, p);
}

fn reverse(speed: f64) -> MajOperands {
    MajOperands {
        direction: 1,
        ..jog(speed)
    }
}

/// A linear servo-on axis at 0 with soft travel limits [−10, 10].
fn limited(action: FaultAction) -> (MotionTask, AxisHandle, InstructionHandle) {
    one_at(
        AxisConfig {
            modulo_period: None,
            start_servo_on: true,
            soft_travel_limits: Some((-10.0, 10.0)),
            soft_overtravel_action: action,
            ..config("Lift")
        },
        0.0,
    )
}

fn one_at(config: AxisConfig, position: f64) -> (MotionTask, AxisHandle, InstructionHandle) {
    let mut task = MotionTask::new(DT).unwrap();
    let axis = task.add_axis(config, position).unwrap();
    let mi = task.add_instruction("MC");
    (task, axis, mi)
}

fn mam_to(position: f64) -> crate::task::instructions::mam::MamOperands {
    crate::task::instructions::mam::MamOperands {
        position,
        ..crate::task::instructions::mam::MamOperands::default()
    }
}

/// Runs updates with the actual position following the command (at most
/// `n`) until the axis records a motion fault; the update count.
fn run_until_fault(task: &mut MotionTask, axis: AxisHandle, n: usize) -> Option<usize> {
    for k in 0..n {
        let p = task.axis_state(axis).command_position;
        task.feed_actual_position(axis, p);
        task.update();
        if !task.motion_faults(axis).is_clear() {
            return Some(k);
        }
    }
    None
}

/// Guards against a move past a soft travel limit going on with no fault
/// (issue: "A SCARA quill driven past its URDF limit gets no error"): the
/// actual position crossing the limit raises Soft Travel Limit - Positive,
/// Stop Planner ramps the command to rest, a move further out fails with
/// ERR 9 and a move back in runs.
#[test]
fn a_move_past_a_soft_travel_limit_faults_and_a_further_move_out_fails_with_err_9() {
    let (mut task, axis, mi) = limited(FaultAction::StopPlanner);
    task.mam(axis, mi, &mam_to(50.0)).unwrap();
    run_until_fault(&mut task, axis, 1000).expect("the fault rises");
    let faults = task.motion_faults(axis);
    assert!(faults.positive() && !faults.negative());
    assert_eq!(task.axis_faults(axis).0, AxisFaults::MOTION);
    let s = task.axis_state(axis);
    assert!(s.actual_position > 10.0, "{s:?}");
    // The MAM is stopped: no longer in process, never complete.
    let b = task.motion_bits(mi);
    assert!(!b.ip && !b.pc, "{b:?}");
    assert!(task.axis_status(axis).stopping && task.is_servo_on(axis));
    // It comes to rest beyond the limit by at most the stopping distance
    // at maximum deceleration (100 units/s, 1000 units/s²: 5 units).
    for _ in 0..100 {
        let p = task.axis_state(axis).command_position;
        task.feed_actual_position(axis, p);
        task.update();
    }
    let rest = task.axis_state(axis);
    // (Plus the crossing update and the fed position's one-update lag, at
    // most 0.4 units each.)
    assert!(
        rest.command_velocity == 0.0 && rest.command_position < 10.0 + 5.0 + 0.8 + 1e-9,
        "{rest:?}"
    );
    // Further out: ERR 9 on MAM and MAJ; the axis keeps its place.
    let out = task.add_instruction("OUT");
    assert_eq!(
        task.mam(axis, out, &mam_to(rest.command_position + 1.0)),
        Err(crate::task::instructions::mam::MamError::from(StateError::Overtravel))
    );
    assert_eq!(err(&task, out), (true, 9, 0));
    assert_eq!(
        task.maj(axis, out, &jog(10.0)),
        Err(JogError::from(StateError::Overtravel))
    );
    assert_eq!(err(&task, out), (true, 9, 0));
    // Back in: runs, raises nothing new, and completes inside.
    let back = task.add_instruction("BACK");
    task.mam(axis, back, &mam_to(0.0)).unwrap();
    for _ in 0..500 {
        let p = task.axis_state(axis).command_position;
        task.feed_actual_position(axis, p);
        task.update();
    }
    assert!(task.motion_bits(back).pc);
    assert_eq!(task.motion_faults(axis), faults, "latched until MAFR");
    let mafr = task.add_instruction("MAFR");
    task.mafr(axis, mafr).unwrap();
    assert!(task.motion_faults(axis).is_clear() && task.axis_faults(axis).is_clear());
    // Inside again, a move out runs until it crosses the limit again.
    task.mam(axis, out, &mam_to(-20.0)).unwrap();
    run_until_fault(&mut task, axis, 1000).expect("the fault rises again");
    assert!(task.motion_faults(axis).negative());
    assert!(task.axis_state(axis).actual_position < -10.0);
}

#[test]
fn a_soft_overtravel_takes_the_configured_action() {
    for (action, state, recorded) in [
        (FaultAction::StopDrive, CipAxisState::Faulted, true),
        (FaultAction::Shutdown, CipAxisState::Shutdown, true),
        (FaultAction::StopPlanner, CipAxisState::Running, true),
        (FaultAction::FaultStatusOnly, CipAxisState::Running, true),
        (FaultAction::Ignore, CipAxisState::Running, false),
    ] {
        let (mut task, axis, mi) = limited(action);
        task.maj(axis, mi, &reverse(50.0)).unwrap();
        let fault = run_until_fault(&mut task, axis, 200);
        assert_eq!(fault.is_some(), recorded, "{action:?}");
        assert_eq!(task.cip_axis_state(axis), state, "{action:?}");
        let jog_runs = task.motion_bits(mi).ip;
        let runs_on = matches!(action, FaultAction::FaultStatusOnly | FaultAction::Ignore);
        assert_eq!(jog_runs, runs_on, "{action:?}");
        if action == FaultAction::StopDrive {
            // MAFR, MSO while beyond the limit: standing still raises
            // nothing (the manual's recovery path), and a jog back in runs.
            let (mafr, mso) = (task.add_instruction("MAFR"), task.add_instruction("MSO"));
            // The drive is off: the joint comes to rest where it is.
            let p = task.axis_state(axis).actual_position;
            for _ in 0..2 {
                task.feed_actual_position(axis, p);
                task.update();
            }
            task.mafr(axis, mafr).unwrap();
            enable(&mut task, axis, mso);
            for _ in 0..10 {
                let p = task.axis_state(axis).command_position;
                task.feed_actual_position(axis, p);
                task.update();
            }
            assert!(task.motion_faults(axis).is_clear());
            assert!(task.axis_state(axis).actual_position < -10.0);
            let out = task.add_instruction("OUT");
            assert_eq!(
                task.maj(axis, out, &reverse(10.0)),
                Err(JogError::from(StateError::Overtravel)),
                "beyond the limit, out is refused without a latched fault too"
            );
            task.maj(axis, out, &jog(10.0)).unwrap();
            assert_eq!(run_until_fault(&mut task, axis, 100), None);
        }
    }
}

#[test]
fn a_feedback_only_axis_faults_whenever_it_is_outside() {
    let (mut task, axis, _) = one_at(
        AxisConfig {
            modulo_period: None,
            axis_type: AxisType::FeedbackOnly,
            soft_travel_limits: Some((-10.0, 10.0)),
            soft_overtravel_action: FaultAction::FaultStatusOnly,
            ..config("Encoder")
        },
        0.0,
    );
    task.feed_actual_position(axis, 9.0);
    task.update();
    assert!(task.motion_faults(axis).is_clear());
    task.feed_actual_position(axis, 10.5);
    task.update();
    assert!(task.motion_faults(axis).positive());
    let mafr = task.add_instruction("MAFR");
    task.mafr(axis, mafr).unwrap();
    task.update();
    assert!(task.motion_faults(axis).positive(), "still outside: raised again");
}

#[test]
fn a_coordinated_move_further_out_fails_with_err_9_naming_the_axis() {
    let mut task = MotionTask::new(DT).unwrap();
    let free = AxisConfig::new("X", AxisKind::Linear);
    let x = task.add_axis(free.clone(), 0.0).unwrap();
    let y = task
        .add_axis(
            AxisConfig {
                name: "Y".into(),
                soft_travel_limits: Some((-1.0, 1.0)),
                ..free
            },
            0.0,
        )
        .unwrap();
    let cs = crate::task::tests::two_axis_system(&mut task, "CS", x, y);
    let mrp = task.add_instruction("MRP");
    task.mrp(y, mrp, 0, 0, 1.5).unwrap();
    assert!(task.motion_faults(y).positive());
    let line = |to: [f64; 2]| {
        CoordCall::Mclm(CoordMoveInputs {
            position: to.to_vec(),
            dynamics: MoveDynamics {
                speed: 10.0,
                accel_rate: 50.0,
                decel_rate: 50.0,
                ..CoordMoveInputs::default().dynamics
            },
            ..Default::default()
        })
    };
    let h = task.add_coord_instruction("Line", cs, line([1.0, 2.0]));
    let fire = |task: &mut MotionTask, to: [f64; 2]| {
        task.set_coord_instruction(h, false, line(to));
        task.update();
        task.set_coord_instruction(h, true, line(to));
        task.update();
        let b = task.coord_bits(h);
        (b.er, b.err, b.exerr)
    };
    assert_eq!(fire(&mut task, [1.0, 2.0]), (true, 9, 1));
    assert_eq!(fire(&mut task, [1.0, 0.0]), (false, 0, 0));
}
