//! MAOC and MDOC through the task: a once cam on a jogging axis, its
//! words and switches, compensation, the pending cam, continuous wrap,
//! MDOC, and the refusals.

use super::*;
use crate::axis::{AxisConfig, AxisKind};
use crate::task::instructions::maj::MajOperands;

const DT: f64 = 0.004;

/// A conveyor jogging at 500 mm/s from 0.
fn conveyor() -> (MotionTask, AxisHandle) {
    let mut task = MotionTask::new(DT).unwrap();
    let config = AxisConfig {
        max_velocity: 1000.0,
        max_acceleration: 1e7,
        max_deceleration: 1e7,
        ..AxisConfig::new("Conv", AxisKind::Linear)
    };
    let x = task.add_axis(config, 0.0).unwrap();
    let jog = task.add_instruction("Jog");
    let o = MajOperands {
        speed: 500.0,
        speed_units: 0,
        accel_rate: 1e7,
        accel_units: 0,
        decel_rate: 1e7,
        decel_units: 0,
        ..MajOperands::default()
    };
    task.maj(x, jog, &o).unwrap();
    (task, x)
}

fn bead(bit: i64, left: f64, right: f64) -> OutputCamElement {
    OutputCamElement {
        output_bit: bit,
        latch_type: 1,
        unlatch_type: 1,
        left,
        right,
        ..Default::default()
    }
}

fn operands<'a>(
    cams: &'a [OutputCamElement],
    comp: &'a [OutputCompensation],
    mode: i64,
    schedule: i64,
) -> MaocOperands<'a> {
    MaocOperands {
        target: 0,
        words: (7, 8),
        cams: Some(cams),
        compensation: Some(comp),
        range: (0.0, 400.0),
        codes: (mode, schedule, 1),
        arm: (0.0, 0.0),
    }
}

#[test]
fn a_once_cam_switches_its_bit_ends_past_its_range_and_a_pending_cam_follows() {
    let (mut task, x) = conveyor();
    let cams = [bead(2, 100.0, 150.0)];
    let mc = task.add_instruction("Cam1");
    task.maoc(x, mc, &operands(&cams, &[], 0, 0)).unwrap();
    assert!(task.motion_bits(mc).dn && task.motion_bits(mc).ip);
    let mut on = Vec::new();
    let mut switches = Vec::new();
    for k in 0..60 {
        task.update();
        let words = task.output_cam_words();
        assert_eq!(words.len(), 1);
        assert_eq!((words[0].output, words[0].input, words[0].mask), (7, 8, 1 << 2));
        if words[0].bits != 0 {
            on.push(k);
        }
        switches.extend(task.output_cam_switches(x, 0).iter().copied());
    }
    // 2 mm an update (the jog reaches its speed 25 µs late: at t the axis
    // is at 500 (t − 25 µs)): on from the update after 100 mm.
    assert_eq!(on.first(), Some(&50));
    assert_eq!(switches.len(), 1, "{switches:?}");
    let pending = task.add_instruction("Cam2");
    let second = [bead(3, 10.0, 20.0)];
    task.maoc(x, pending, &operands(&second, &[], 0, 1)).unwrap();
    assert_eq!(task.output_cam_status(x, 0), (true, true));
    let mut k = 60;
    while task.motion_bits(mc).ip {
        task.update();
        k += 1;
        assert!(k < 400);
    }
    // Past 400 mm: .PC, the pending cam is armed from there.
    assert!(task.motion_bits(mc).pc);
    assert_eq!(task.output_cam_status(x, 0), (true, false));
    let mut second_on = None;
    let mut latched_at = None;
    for j in 0..20 {
        task.update();
        if task.output_cam_words()[0].bits & 1 << 3 != 0 && second_on.is_none() {
            second_on = Some(j);
        }
        if let Some(s) = task.output_cam_switches(x, 0).iter().find(|s| s.bit == 3 && s.on) {
            latched_at = Some(s.time_s);
        }
    }
    assert!(second_on.is_some_and(|j| (3..=5).contains(&j)), "{second_on:?}");
    // Armed where the first cam left its range (400 mm), not where the
    // update found the axis: its 10 mm edge at 410 mm, 0.82 s (and the
    // jog's 25 µs).
    let latched_at = latched_at.expect("the pending cam latched");
    assert!((latched_at - 0.820_025).abs() < 1e-9, "{latched_at}");
    // MDOC: the bit goes off, the MAOC leaves .IP without .PC.
    task.disarm_output_cam(x, 0, true);
    assert!(!task.motion_bits(pending).ip && !task.motion_bits(pending).pc);
    assert_eq!(task.output_cam_words()[0].bits, 0, "off once more");
    assert!(task.output_cam_words().is_empty(), "then released");
}

#[test]
fn a_continuous_cam_repeats_every_range_and_compensation_switches_early() {
    let (mut task, x) = conveyor();
    let cams = [bead(0, 100.0, 150.0)];
    let mut comp = [OutputCompensation::default(); 1];
    comp[0].latch_delay = 0.012;
    comp[0].unlatch_delay = 0.012;
    let mc = task.add_instruction("Cam");
    task.maoc(x, mc, &operands(&cams, &comp, 1, 0)).unwrap();
    let mut ons = Vec::new();
    for _ in 0..450 {
        task.update();
        for s in task.output_cam_switches(x, 0) {
            if s.on {
                ons.push(s.time_s);
            }
        }
    }
    // Latch at 100 − 6 mm = 94 mm of each 400 mm: 0.188 s (and the jog's
    // 25 µs start), then every 0.8 s.
    assert_eq!(ons.len(), 3, "{ons:?}");
    for (n, t) in ons.iter().enumerate() {
        assert!((t - (0.188_025 + 0.8 * n as f64)).abs() < 1e-9, "{ons:?}");
    }
}

#[test]
fn refusals() {
    let (mut task, x) = conveyor();
    let mc = task.add_instruction("Cam");
    let cams = [bead(0, 100.0, 150.0)];
    let e = |task: &mut MotionTask, o: MaocOperands<'_>| {
        let e = task.maoc(x, mc, &o).unwrap_err();
        (e.err(), e.exerr(), e.segment())
    };
    let ok = operands(&cams, &[], 0, 2);
    assert_eq!(e(&mut task, MaocOperands { target: 4, ..ok }), (35, 0, 0));
    assert_eq!(
        e(
            &mut task,
            MaocOperands {
                range: (5.0, 5.0),
                ..ok
            }
        ),
        (13, 7, 0)
    );
    assert_eq!(
        e(
            &mut task,
            MaocOperands {
                range: (f64::NAN, 5.0),
                ..ok
            }
        ),
        (13, 6, 0)
    );
    assert_eq!(
        e(
            &mut task,
            MaocOperands {
                arm: (0.0, 500.0),
                ..ok
            }
        ),
        (13, 12, 0)
    );
    assert_eq!(e(&mut task, MaocOperands { cams: None, ..ok }), (13, 5, 0));
    assert_eq!(
        e(
            &mut task,
            MaocOperands {
                arm: (f64::NAN, 0.0),
                ..ok
            }
        ),
        (13, 11, 0)
    );
    assert_eq!(e(&mut task, MaocOperands { codes: (3, 2, 1), ..ok }), (13, 9, 0));
    let bad = [bead(0, 1.0, 2.0), bead(40, 1.0, 2.0)];
    assert_eq!(e(&mut task, MaocOperands { cams: Some(&bad), ..ok }), (36, 0, 1));
    let comp = [OutputCompensation {
        mode: 9,
        ..Default::default()
    }];
    assert_eq!(
        e(
            &mut task,
            MaocOperands {
                compensation: Some(&comp),
                ..ok
            }
        ),
        (37, 0, 0)
    );
    assert!(task.motion_bits(mc).er);
    assert_eq!(task.output_cam_status(x, 0), (false, false));
}

/// A once cam whose element ends at the range's end: its bit goes off
/// where the cam crosses the end, inside the update, not at the update.
#[test]
fn an_element_ending_at_the_range_end_switches_off_at_the_crossing() {
    let (mut task, x) = conveyor();
    let cams = [bead(1, 300.0, 401.0)];
    let mc = task.add_instruction("Cam");
    task.maoc(x, mc, &operands(&cams, &[], 0, 0)).unwrap();
    let mut off = None;
    for _ in 0..250 {
        task.update();
        if let Some(s) = task.output_cam_switches(x, 0).iter().find(|s| !s.on) {
            off = Some(s.time_s);
        }
    }
    // Right is clamped to the end, 400 mm: 0.8 s (and the jog's 25 µs),
    // between two updates (0.8 s falls on one; the crossing is 25 µs
    // after it).
    let off = off.expect("switched off");
    assert!((off - 0.800_025).abs() < 1e-9, "{off}");
    assert!(task.motion_bits(mc).pc);
}
