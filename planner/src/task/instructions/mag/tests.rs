//! Gearing through the task: the slave follows ratio × the master's
//! displacement, the clutch ramps in, the directions, superimposed moves,
//! and what ends a gearing.

use super::*;
use crate::instruction::LogixFault;
use crate::task::{AxisHandle, MotionTask};
use crate::axis::{AxisConfig, AxisKind};
use crate::dynamics::MoveDynamics;
use crate::task::instructions::maj::MajOperands;
use crate::task::instructions::mas::MasOperands;
use crate::task::instructions::mam::MamOperands;

const DT: f64 = 0.004;

fn setup() -> (MotionTask, AxisHandle, AxisHandle) {
    let mut task = MotionTask::new(DT).unwrap();
    let config = |name: &str| AxisConfig {
        max_velocity: 200.0,
        max_acceleration: 2000.0,
        max_deceleration: 2000.0,
        ..AxisConfig::new(name, AxisKind::Linear)
    };
    let master = task.add_axis(config("Master"), 0.0).unwrap();
    let slave = task.add_axis(config("Slave"), 5.0).unwrap();
    (task, master, slave)
}

fn jog(speed: f64) -> MajOperands {
    MajOperands {
        speed,
        speed_units: 0,
        accel_rate: 1000.0,
        accel_units: 0,
        decel_rate: 1000.0,
        decel_units: 0,
        ..MajOperands::default()
    }
}

fn pos(task: &MotionTask, axis: AxisHandle) -> f64 {
    task.axis_state(axis).command_position
}

#[test]
fn a_locked_gear_follows_ratio_times_the_master_displacement() {
    let (mut task, master, slave) = setup();
    let gear = task.add_instruction("Gear");
    let o = MagOperands {
        ratio: 2.5,
        master_reference: 1,
        ..MagOperands::default()
    };
    task.mag(slave, master, gear, &o).unwrap();
    let b = task.motion_bits(gear);
    assert!(b.dn && b.ip && !b.er);
    assert_eq!(task.gearing_status(slave), (true, true));
    assert!(task.axis_status(slave).gearing);
    let mj = task.add_instruction("Jog");
    task.maj(master, mj, &jog(40.0)).unwrap();
    for _ in 0..200 {
        task.update();
        let (m, s) = (pos(&task, master), pos(&task, slave));
        assert!((s - (5.0 + 2.5 * m)).abs() < 1e-9, "{s} vs {m}");
    }
    // MAS Gear ends it; the slave ramps to rest and the master goes on.
    let stop = task.add_instruction("Stop");
    task.mas(
        slave,
        stop,
        &MasOperands {
            stop_type: 3,
            ..MasOperands::default()
        },
    )
    .unwrap();
    assert!(!task.motion_bits(gear).ip);
    assert_eq!(task.gearing_status(slave), (false, false));
    for _ in 0..100 {
        task.update();
    }
    assert_eq!(task.axis_state(slave).command_velocity, 0.0);
    assert!(task.axis_state(master).command_velocity > 39.0);
}

#[test]
fn the_clutch_ramps_the_slave_in_at_its_acceleration_then_locks() {
    let (mut task, master, slave) = setup();
    let mj = task.add_instruction("Jog");
    task.maj(master, mj, &jog(50.0)).unwrap();
    for _ in 0..50 {
        task.update();
    }
    let gear = task.add_instruction("Gear");
    let o = MagOperands {
        ratio: 2.0,
        direction: 1,
        master_reference: 1,
        clutch: 0,
        accel_rate: 500.0,
        accel_units: 0,
        ..MagOperands::default()
    };
    task.mag(slave, master, gear, &o).unwrap();
    assert_eq!(task.gearing_status(slave), (true, false), "slipping");
    let mut previous = 0.0;
    let mut updates = 0;
    while !task.gearing_status(slave).1 {
        task.update();
        updates += 1;
        let v = task.axis_state(slave).command_velocity;
        assert!(
            (v - previous).abs() <= 500.0 * DT + 1e-9,
            "the clutch holds its acceleration"
        );
        previous = v;
        assert!(updates < 100);
    }
    // Opposite: -100 units/s reached at 500 units/s² in 0.2 s.
    assert_eq!(updates, 50);
    task.update();
    assert!((task.axis_state(slave).command_velocity + 100.0).abs() < 1e-9);
}

#[test]
fn reverse_and_unchanged_are_relative_to_the_running_gearing() {
    let (mut task, master, slave) = setup();
    let (g1, g2, g3) = (
        task.add_instruction("G1"),
        task.add_instruction("G2"),
        task.add_instruction("G3"),
    );
    let o = MagOperands {
        ratio: 1.0,
        direction: 1,
        master_reference: 1,
        ..MagOperands::default()
    };
    task.mag(slave, master, g1, &o).unwrap();
    let reverse = MagOperands {
        direction: 2,
        ratio: 0.5,
        ..o
    };
    task.mag(slave, master, g2, &reverse).unwrap();
    assert!(!task.motion_bits(g1).ip, "superseded");
    let unchanged = MagOperands {
        direction: 3,
        ratio: 3.0,
        ..o
    };
    task.mag(slave, master, g3, &unchanged).unwrap();
    let mj = task.add_instruction("Jog");
    task.maj(master, mj, &jog(10.0)).unwrap();
    for _ in 0..100 {
        task.update();
    }
    // Opposite, reversed to same, unchanged: +3 × the master.
    let (m, s) = (pos(&task, master), pos(&task, slave));
    assert!((s - (5.0 + 3.0 * m)).abs() < 1e-9);
}

#[test]
fn a_mam_with_merge_disabled_rides_on_the_gearing_and_one_that_merges_ends_it() {
    let (mut task, master, slave) = setup();
    let gear = task.add_instruction("Gear");
    let o = MagOperands {
        master_reference: 1,
        ..MagOperands::default()
    };
    task.mag(slave, master, gear, &o).unwrap();
    let mj = task.add_instruction("Jog");
    task.maj(master, mj, &jog(20.0)).unwrap();
    for _ in 0..20 {
        task.update();
    }
    let mv = task.add_instruction("Move");
    let mam = MamOperands {
        move_type: 1,
        position: 10.0,
        merge: 0,
        dynamics: MoveDynamics {
            speed: 100.0,
            speed_units: 0,
            accel_rate: 1000.0,
            accel_units: 0,
            decel_rate: 1000.0,
            decel_units: 0,
            ..MamOperands::default().dynamics
        },
        ..MamOperands::default()
    };
    task.mam(slave, mv, &mam).unwrap();
    for _ in 0..200 {
        task.update();
    }
    assert!(task.motion_bits(mv).pc && task.motion_bits(gear).ip);
    let (m, s) = (pos(&task, master), pos(&task, slave));
    assert!((s - (5.0 + m + 10.0)).abs() < 1e-9, "{s} {m}");
    let merging = MamOperands { merge: 1, ..mam };
    task.mam(slave, mv, &merging).unwrap();
    assert!(!task.motion_bits(gear).ip, "a merge ends the gearing");
    assert!(!task.gearing_status(slave).0);
}

#[test]
fn a_servo_off_slave_or_the_master_as_its_own_slave_is_refused() {
    let (mut task, master, slave) = setup();
    let gear = task.add_instruction("Gear");
    let o = MagOperands::default();
    let e = task.mag(slave, slave, gear, &o).unwrap_err();
    assert_eq!((e.err(), e.exerr()), (13, MAG.exerr("Master Axis")));
    let msf = task.add_instruction("MSF");
    task.msf(slave, msf).unwrap();
    let e = task.mag(slave, master, gear, &o).unwrap_err();
    assert_eq!(e.err(), 5);
    assert!(task.motion_bits(gear).er);
}

#[test]
fn a_disable_ends_the_gearing() {
    let (mut task, master, slave) = setup();
    let gear = task.add_instruction("Gear");
    task.mag(slave, master, gear, &MagOperands::default()).unwrap();
    let msf = task.add_instruction("MSF");
    task.msf(slave, msf).unwrap();
    assert!(!task.motion_bits(gear).ip);
    assert!(!task.axis_status(slave).gearing);
}


fn slave() -> AxisConfig {
    AxisConfig {
        max_acceleration: 400.0,
        ..AxisConfig::new("S", AxisKind::Rotary)
    }
}

#[test]
fn each_operand_out_of_range_is_named_by_its_faceplate_number() {
    let ok = MagOperands::default();
    for (o, name) in [
        (MagOperands { direction: 4, ..ok }, "Direction"),
        (MagOperands { ratio: 10.0, ..ok }, "Ratio"),
        (MagOperands { ratio: 0.0, ..ok }, "Ratio"),
        (MagOperands { ratio: f64::NAN, ..ok }, "Ratio"),
        (
            MagOperands {
                ratio_format: 1,
                slave_counts: 0,
                ..ok
            },
            "Slave Counts",
        ),
        (
            MagOperands {
                ratio_format: 1,
                master_counts: 0,
                ..ok
            },
            "Master Counts",
        ),
        (MagOperands { ratio_format: 2, ..ok }, "Ratio Format"),
        (
            MagOperands {
                master_reference: 2,
                ..ok
            },
            "Master Reference",
        ),
        (MagOperands { clutch: 2, ..ok }, "Clutch"),
        (
            MagOperands {
                clutch: 0,
                accel_rate: 0.0,
                ..ok
            },
            "Accel Rate",
        ),
        (
            MagOperands {
                clutch: 0,
                accel_units: 3,
                ..ok
            },
            "Accel Units",
        ),
    ] {
        let e = Mag::new(&o, &slave()).unwrap_err();
        assert_eq!((e.err(), e.exerr()), (13, MAG.exerr(name)), "{name}");
    }
}

#[test]
fn ratio_formats_directions_and_clutch_units() {
    let o = MagOperands {
        ratio: -2.5,
        ..MagOperands::default()
    };
    let m = Mag::new(&o, &slave()).unwrap();
    assert_eq!(m.effective_ratio(None), -2.5, "the ratio is sign sensitive");
    let fraction = MagOperands {
        ratio_format: 1,
        slave_counts: 1,
        master_counts: 3,
        direction: 1,
        clutch: 0,
        accel_rate: 50.0,
        accel_units: 1,
        ..MagOperands::default()
    };
    let m = Mag::new(&fraction, &slave()).unwrap();
    assert_eq!(m.effective_ratio(None), -1.0 / 3.0);
    assert_eq!(m.clutch_accel, Some(200.0));
    let reverse = Mag {
        direction: GearDirection::Reverse,
        ..m
    };
    assert_eq!(reverse.effective_ratio(Some(-1.0)), 1.0 / 3.0);
    assert_eq!(reverse.effective_ratio(None), -1.0 / 3.0);
    let unchanged = Mag {
        direction: GearDirection::Unchanged,
        ..m
    };
    assert_eq!(unchanged.effective_ratio(Some(-1.0)), -1.0 / 3.0);
}

/// A MAG gearing an axis to itself is refused at load (its check) as it is
/// when it executes: ERR 13 on the Master Axis, which carries no value.
#[test]
fn an_axis_geared_to_itself_is_refused_by_the_check() {
    use crate::task::{Arg, Args};
    let mut task = MotionTask::new(0.004).unwrap();
    let x = task.add_axis(AxisConfig::new("X", AxisKind::Linear), 0.0).unwrap();
    let mc = task.add_instruction("MC1");
    // MAG(X, X, MC1, same, 2.0, 1, 1, actual, real, disabled, 0, unitspersec2)
    let args = [
        Arg::Axis(x),
        Arg::Axis(x),
        Arg::Control(mc),
        Arg::Integer(0),
        Arg::Number(2.0),
        Arg::Integer(1),
        Arg::Integer(1),
        Arg::Integer(0),
        Arg::Integer(0),
        Arg::Integer(1),
        Arg::Number(0.0),
        Arg::Integer(0),
    ];
    let e = MAG.check(&task, &Args::new(&args)).unwrap_err();
    assert_eq!((e.err(), e.exerr()), (13, MAG.exerr("Master Axis")));
    assert!(!e.to_string().contains('='), "no value: {e}");
    let e = MAG.execute(&mut task, &Args::new(&args)).unwrap_err();
    assert_eq!((e.err(), e.exerr()), (13, 1));
}
