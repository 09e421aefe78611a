//! Output cam elements: the checks, latching and unlatching by position,
//! duration and enable, compensation, and the switch times.

use super::*;

fn position(bit: i64, left: f64, right: f64) -> OutputCamElement {
    OutputCamElement {
        output_bit: bit,
        latch_type: 1,
        unlatch_type: 1,
        left,
        right,
        ..Default::default()
    }
}

/// Runs `cam` at `speed` from `from` for `updates` steps of 4 ms; the
/// driven bits after each step and every switch.
fn run(cam: &OutputCam, from: f64, speed: f64, updates: usize, input: u32) -> (Vec<u32>, Vec<Switch>) {
    let (mut latches, mut switches, mut words) = (Vec::new(), Vec::new(), Vec::new());
    let dt = 0.004;
    let mut output = 0;
    for k in 0..updates {
        let step = Step {
            from: from + speed * dt * k as f64,
            to: from + speed * dt * (k + 1) as f64,
            speed,
            t0_s: dt * k as f64,
            t1_s: dt * (k + 1) as f64,
            input,
            output,
        };
        output = cam.evaluate(&mut latches, &step, &mut switches);
        words.push(output);
    }
    (words, switches)
}

#[test]
fn checks_name_the_element_or_the_bit() {
    let range = (0.0, 100.0);
    let e = |x: OutputCamElement| OutputCam::new(&[position(0, 1.0, 2.0), x], &[], range).unwrap_err();
    assert_eq!(
        e(position(32, 1.0, 2.0)),
        OutputCamFault::IllegalOutputCam {
            element: 1,
            why: "OutputBit is not 0–31"
        }
    );
    assert!(matches!(
        e(position(1, 5.0, 5.0)),
        OutputCamFault::IllegalOutputCam { element: 1, .. }
    ));
    let timed = OutputCamElement {
        unlatch_type: 2,
        duration: 0.0,
        ..position(1, 1.0, 2.0)
    };
    assert!(matches!(e(timed), OutputCamFault::IllegalOutputCam { element: 1, .. }));
    let enable = OutputCamElement {
        latch_type: 2,
        enable_bit: 40,
        ..position(1, 1.0, 2.0)
    };
    assert!(matches!(e(enable), OutputCamFault::IllegalOutputCam { element: 1, .. }));
    // Latch and unlatch codes out of range are Inactive, not errors.
    let odd = OutputCamElement {
        latch_type: 9,
        unlatch_type: -1,
        ..position(1, 1.0, 2.0)
    };
    assert!(OutputCam::new(&[odd], &[], range).is_ok());
    let comp = |c: OutputCompensation| {
        OutputCam::new(&[position(0, 1.0, 2.0)], &[OutputCompensation::default(), c], range).unwrap_err()
    };
    use crate::instruction::LogixFault;
    let f = comp(OutputCompensation {
        mode: 4,
        ..Default::default()
    });
    assert_eq!((f.err(), f.segment()), (37, 1));
    let f = comp(OutputCompensation {
        latch_delay: -0.01,
        ..Default::default()
    });
    assert_eq!((f.err(), f.segment()), (37, 1));
    let f = comp(OutputCompensation {
        mode: 2,
        cycle_time: 0.0,
        ..Default::default()
    });
    assert_eq!((f.err(), f.segment()), (37, 1));
}

#[test]
fn a_position_element_switches_at_its_edges_and_compensation_moves_them() {
    // 500 mm/s, a bead from 100 to 150 mm: on at 0.2 s, off at 0.3 s.
    let cam = OutputCam::new(&[position(3, 100.0, 150.0)], &[], (0.0, 1000.0)).unwrap();
    let (words, switches) = run(&cam, 0.0, 500.0, 100, 0);
    assert_eq!(switches.len(), 2);
    assert!((switches[0].time_s - 0.2).abs() < 1e-12 && switches[0].on && switches[0].bit == 3);
    assert!((switches[1].time_s - 0.3).abs() < 1e-12 && !switches[1].on);
    assert_eq!(words[50], 1 << 3, "on in the update that reaches 102 mm");
    assert_eq!(words[49] & 1 << 3, 1 << 3, "on at exactly 100 mm");
    assert_eq!(words[76], 0);
    // 12 ms latch and unlatch delays: both edges 6 mm (12 ms) earlier.
    let comp = OutputCompensation {
        latch_delay: 0.012,
        unlatch_delay: 0.012,
        ..Default::default()
    };
    let mut comps = [OutputCompensation::default(); 4];
    comps[3] = comp;
    let cam = OutputCam::new(&[position(3, 100.0, 150.0)], &comps, (0.0, 1000.0)).unwrap();
    let (_, switches) = run(&cam, 0.0, 500.0, 100, 0);
    assert!((switches[0].time_s - 0.188).abs() < 1e-12, "{switches:?}");
    assert!((switches[1].time_s - 0.288).abs() < 1e-12);
}

#[test]
fn duration_enable_pulsed_and_inverted_outputs() {
    // Duration 20 ms from the latch at 100 mm (0.2 s at 500 mm/s).
    let timed = OutputCamElement {
        unlatch_type: 2,
        duration: 0.02,
        ..position(0, 100.0, 150.0)
    };
    let cam = OutputCam::new(&[timed], &[], (0.0, 1000.0)).unwrap();
    let (_, switches) = run(&cam, 0.0, 500.0, 100, 0);
    assert_eq!(switches.len(), 2, "no second latch while still inside: {switches:?}");
    assert!((switches[1].time_s - 0.22).abs() < 1e-12);
    // Position and enable on input bit 5: nothing without the input.
    let gated = OutputCamElement {
        latch_type: 3,
        unlatch_type: 4,
        enable_type: 0,
        enable_bit: 5,
        ..position(1, 100.0, 150.0)
    };
    let cam = OutputCam::new(&[gated], &[], (0.0, 1000.0)).unwrap();
    assert!(run(&cam, 0.0, 500.0, 100, 0).1.is_empty());
    assert_eq!(run(&cam, 0.0, 500.0, 100, 1 << 5).1.len(), 2);
    // Inverted: on outside the element; pulsed: 25 % of 8 ms cycles.
    let mut comps = [OutputCompensation::default(); 2];
    comps[0].mode = 1;
    comps[1] = OutputCompensation {
        mode: 2,
        cycle_time: 0.008,
        duty_cycle: 50.0,
        ..Default::default()
    };
    let cam = OutputCam::new(
        &[position(0, 100.0, 150.0), position(1, 100.0, 150.0)],
        &comps,
        (0.0, 1000.0),
    )
    .unwrap();
    let (words, _) = run(&cam, 0.0, 500.0, 100, 0);
    assert_eq!(words[10] & 1, 1, "inverted: on before the element");
    assert_eq!(words[60] & 1, 0, "inverted: off inside it");
    let pulses: Vec<u32> = words[50..58].iter().map(|w| w >> 1 & 1).collect();
    assert!(pulses.contains(&0) && pulses.contains(&1), "{pulses:?}");
}

#[test]
fn switches_follow_the_bit_not_its_elements() {
    // Two overlapping elements on one bit: one switch on, one off.
    let cam = OutputCam::new(
        &[position(0, 100.0, 150.0), position(0, 120.0, 180.0)],
        &[],
        (0.0, 1000.0),
    )
    .unwrap();
    let (_, switches) = run(&cam, 0.0, 500.0, 100, 0);
    let times: Vec<(bool, f64)> = switches.iter().map(|s| (s.on, s.time_s)).collect();
    assert_eq!(times.len(), 2, "{times:?}");
    assert!(times[0].0 && (times[0].1 - 0.2).abs() < 1e-12);
    assert!(!times[1].0 && (times[1].1 - 0.36).abs() < 1e-12);
    // An inverted bit switches off at the latch edge and on at the unlatch.
    let mut comps = [OutputCompensation::default(); 2];
    comps[0].mode = 1;
    comps[1] = OutputCompensation {
        mode: 2,
        cycle_time: 0.008,
        duty_cycle: 50.0,
        ..Default::default()
    };
    let cam = OutputCam::new(
        &[position(0, 100.0, 150.0), position(1, 100.0, 150.0)],
        &comps,
        (0.0, 1000.0),
    )
    .unwrap();
    let (words, switches) = run(&cam, 0.0, 500.0, 100, 0);
    let bit0: Vec<bool> = switches.iter().filter(|s| s.bit == 0).map(|s| s.on).collect();
    assert_eq!(bit0, [false, true]);
    // A pulsed bit: a switch for every change of the word, at the update.
    let pulses = switches.iter().filter(|s| s.bit == 1).count();
    let changes = words.windows(2).filter(|w| (w[0] ^ w[1]) & 2 != 0).count() + usize::from(words[0] & 2 != 0);
    assert_eq!(pulses, changes);
    assert!(pulses > 4, "{pulses}");
}
