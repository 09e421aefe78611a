//! MCCP: the clamped-spline oracle, linear/cubic junctions, the Status
//! lifecycle and every error code.

use super::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Reference values made once by `oracle.py` (scipy `CubicSpline` with
/// clamped boundary conditions); see the script's header.
const ORACLE: &str = include_str!("oracle.csv");

fn cubic(points: &[(f64, f64)]) -> Vec<CamElement> {
    points
        .iter()
        .map(|&(master, slave)| CamElement {
            master,
            slave,
            segment_type: 1,
        })
        .collect()
}

#[test]
fn all_cubic_cams_match_an_independent_clamped_spline() {
    let mut cams: Vec<(CamProfile, usize)> = Vec::new();
    let mut checked = vec![0usize; 0];
    for line in ORACLE.lines() {
        let f: Vec<&str> = line.split(',').collect();
        match f[0] {
            "cam" => {
                let s0: f64 = f[2].parse().unwrap();
                let s1: f64 = f[3].parse().unwrap();
                let pts: Vec<(f64, f64)> = f[4]
                    .split(';')
                    .map(|p| {
                        let (a, b) = p.split_once(':').unwrap();
                        (a.parse().unwrap(), b.parse().unwrap())
                    })
                    .collect();
                let cam = cubic(&pts);
                cams.push((CamProfile::calculate(&cam, cam.len(), s0, s1).unwrap(), 0));
                checked.push(0);
            }
            "pt" => {
                let id: usize = f[1].parse().unwrap();
                let v: Vec<f64> = f[2..6].iter().map(|s| s.parse().unwrap()).collect();
                let p = cams[id].0.eval(v[0]);
                assert!(
                    (p.slave - v[1]).abs() <= 1e-9,
                    "cam {id} at {}: {} vs {}",
                    v[0],
                    p.slave,
                    v[1]
                );
                assert!(
                    (p.slope - v[2]).abs() <= 1e-9,
                    "cam {id} at {}: slope {} vs {}",
                    v[0],
                    p.slope,
                    v[2]
                );
                assert!(
                    (p.curvature - v[3]).abs() <= 1e-9,
                    "cam {id} at {}: curvature {} vs {}",
                    v[0],
                    p.curvature,
                    v[3]
                );
                checked[id] += 1;
            }
            other => panic!("unexpected oracle line kind {other}"),
        }
    }
    assert_eq!(cams.len(), 5);
    assert!(checked.iter().all(|&n| n >= 1000), "{checked:?}");
    // The boundary slopes are the ones asked (non-zero in every oracle cam).
    let (p, _) = &cams[0];
    assert!((p.eval(0.0).slope - 1.0).abs() < 1e-12);
    assert!((p.eval(40.0).slope + 2.0).abs() < 1e-12);
}

fn junction_checks(p: &CamProfile) {
    let el = p.elements();
    for i in 1..el.len() - 1 {
        let prev = &el[i - 1];
        let h = el[i].master - prev.master;
        let end_pos = prev.c0 + h * (prev.c1 + h * (prev.c2 + h * prev.c3));
        let end_slope = prev.c1 + h * (2.0 * prev.c2 + 3.0 * prev.c3 * h);
        let scale = 1.0 + el[i].slave.abs();
        assert!((end_pos - el[i].c0).abs() <= 1e-9 * scale, "position jump at [{i}]");
        assert!((end_pos - el[i].slave).abs() <= 1e-9 * scale, "misses point [{i}]");
        // Slope continuity holds at every junction touching a cubic segment.
        if prev.segment_type == SegmentType::Cubic || el[i].segment_type == SegmentType::Cubic {
            assert!(
                (end_slope - el[i].c1).abs() <= 1e-9 * (1.0 + end_slope.abs()),
                "slope jump at [{i}]: {end_slope} vs {}",
                el[i].c1
            );
        }
    }
}

#[test]
fn mixed_linear_and_cubic_runs_are_continuous_in_position_and_slope() {
    // L C C L C L C C C: runs touching lines on both sides and at both ends.
    let pts = [0.0, 5.0, 9.0, 12.0, 20.0, 22.0, 30.0, 31.0, 40.0, 45.0];
    let slaves = [0.0, 2.0, 7.0, 6.0, 10.0, 12.0, 11.0, 15.0, 14.0, 20.0];
    let types = [0, 1, 1, 0, 1, 0, 1, 1, 1, 0];
    let cam: Vec<CamElement> = (0..pts.len())
        .map(|i| CamElement {
            master: pts[i],
            slave: slaves[i],
            segment_type: types[i],
        })
        .collect();
    let p = CamProfile::calculate(&cam, cam.len(), 3.0, -4.0).unwrap();
    junction_checks(&p);
    // First segment linear: Start Slope is not used.
    assert!((p.eval(0.0).slope - 0.4).abs() < 1e-12);
    // Last segment cubic: End Slope is used.
    assert!((p.eval(45.0).slope + 4.0).abs() < 1e-12);

    let mut rng = ChaCha8Rng::seed_from_u64(6);
    for _ in 0..500 {
        let n = rng.random_range(2..30);
        let mut x = rng.random_range(-100.0..100.0);
        let cam: Vec<CamElement> = (0..n)
            .map(|_| {
                x += rng.random_range(0.01..20.0);
                CamElement {
                    master: x,
                    slave: rng.random_range(-50.0..50.0),
                    segment_type: rng.random_range(0..2),
                }
            })
            .collect();
        let p = CamProfile::calculate(&cam, n, rng.random_range(-5.0..5.0), rng.random_range(-5.0..5.0)).unwrap();
        junction_checks(&p);
    }
}

#[test]
fn coefficients_are_local_to_each_segment() {
    let cam = [
        CamElement {
            master: 10.0,
            slave: 1.0,
            segment_type: 0,
        },
        CamElement {
            master: 12.0,
            slave: 5.0,
            segment_type: 0,
        },
    ];
    let p = CamProfile::calculate(&cam, 2, 0.0, 0.0).unwrap();
    let e = p.elements()[0];
    assert_eq!((e.c0, e.c1, e.c2, e.c3), (1.0, 2.0, 0.0, 0.0));
    assert_eq!(p.eval(11.0).slave, 3.0);
    // Outside the range: clamped to the end values.
    assert_eq!(p.eval(0.0).slave, 1.0);
    assert_eq!(p.eval(99.0).slave, 5.0);
}

#[test]
fn status_lifecycle_and_errors_30_31() {
    let cam = cubic(&[(0.0, 0.0), (1.0, 1.0)]);
    let mut tag = CamProfileTag::new(10);
    assert_eq!(tag.status(), 0);
    assert_eq!(tag.acquire(), Err(0));
    tag.calculate(&cam, 2, 0.0, 0.0).unwrap();
    assert_eq!(tag.status(), 2);
    let _a = tag.acquire().unwrap();
    let _b = tag.acquire().unwrap();
    assert_eq!(tag.status(), 4);
    let e = tag.calculate(&cam, 2, 0.0, 0.0).unwrap_err();
    assert_eq!(e, MccpError::CamProfileBeingUsed { status: 4, users: 2 });
    assert_eq!(e.err(), 31);
    tag.release();
    tag.release();
    tag.release();
    assert_eq!(tag.status(), 2);
    tag.calculate(&cam, 2, 0.0, 0.0).unwrap();
    tag.set_status(1);
    assert_eq!(tag.acquire(), Err(1));
    let e = tag.calculate(&cam, 2, 0.0, 0.0).unwrap_err();
    assert_eq!(e.err(), 30);
    assert_eq!(tag.status(), 1);
    tag.set_status(0);
    tag.calculate(&cam, 2, 0.0, 0.0).unwrap();
    assert_eq!(tag.status(), 2);
}

#[test]
fn every_mccp_error_code_with_exerr_and_segment() {
    let good = cubic(&[(0.0, 0.0), (1.0, 1.0), (2.0, 0.0), (3.0, 2.0)]);
    let mut tag = CamProfileTag::new(3);
    let code = |e: MccpError| (e.err(), e.exerr(), e.segment());

    // 26: EXERR = number of elements in the CAM array.
    let e = tag.calculate(&good, 5, 0.0, 0.0).unwrap_err();
    assert_eq!(code(e), (26, 4, 0));
    let e = tag.calculate(&good, 1, 0.0, 0.0).unwrap_err();
    assert_eq!(code(e), (26, 4, 0));
    // 27: EXERR = number of points asked.
    let e = tag.calculate(&good, 4, 0.0, 0.0).unwrap_err();
    assert_eq!(code(e), (27, 4, 0));
    assert_eq!(tag.status(), 0);
    let mut tag = CamProfileTag::new(10);
    // 28 with SEGMENT.
    let mut bad = good.clone();
    bad[2].segment_type = 7;
    assert_eq!(code(tag.calculate(&bad, 4, 0.0, 0.0).unwrap_err()), (28, 0, 2));
    // The last point's type is never used.
    bad[2].segment_type = 1;
    bad[3].segment_type = 7;
    tag.calculate(&bad, 4, 0.0, 0.0).unwrap();
    // 29 with SEGMENT.
    let mut bad = good.clone();
    bad[3].master = 2.0;
    assert_eq!(code(tag.calculate(&bad, 4, 0.0, 0.0).unwrap_err()), (29, 0, 3));
    bad[3].master = 1.5;
    assert_eq!(code(tag.calculate(&bad, 4, 0.0, 0.0).unwrap_err()), (29, 0, 3));
    // 179 with SEGMENT: NaN, infinity, overflow.
    let mut bad = good.clone();
    bad[1].slave = f64::NAN;
    assert_eq!(code(tag.calculate(&bad, 4, 0.0, 0.0).unwrap_err()), (179, 0, 1));
    let mut bad = good.clone();
    bad[2].master = f64::INFINITY;
    assert_eq!(code(tag.calculate(&bad, 4, 0.0, 0.0).unwrap_err()), (179, 0, 2));
    let overflow = [
        CamElement {
            master: 0.0,
            slave: -1e308,
            segment_type: 0,
        },
        CamElement {
            master: 1e-10,
            slave: 1e308,
            segment_type: 0,
        },
    ];
    assert_eq!(code(tag.calculate(&overflow, 2, 0.0, 0.0).unwrap_err()), (179, 0, 0));
    assert_eq!(tag.status(), 0);
    // 13: slopes.
    assert_eq!(code(tag.calculate(&good, 4, f64::NAN, 0.0).unwrap_err()), (13, 3, 0));
    assert_eq!(
        code(tag.calculate(&good, 4, 0.0, f64::INFINITY).unwrap_err()),
        (13, 4, 0)
    );

    let mut bits = MotionInstructionBits::default();
    MccpError::IllegalCamOrder { segment: 3 }.write_to(&mut bits);
    assert!(bits.er);
    assert_eq!((bits.err, bits.segment), (29, 3));
}

#[test]
fn edited_profiles_are_validated() {
    let p = CamProfile::calculate(&cubic(&[(0.0, 0.0), (1.0, 1.0), (2.0, 0.0)]), 3, 0.0, 0.0).unwrap();
    let mut el = p.elements().to_vec();
    assert_eq!(CamProfile::from_elements(el.clone()).unwrap(), p);
    el[1].c2 = f64::NAN;
    assert_eq!(
        CamProfile::from_elements(el.clone()).unwrap_err(),
        MccpError::InvalidCamProfileElement { segment: 1 }
    );
    el[1].c2 = 0.0;
    el[2].master = 0.5;
    assert_eq!(
        CamProfile::from_elements(el).unwrap_err(),
        MccpError::IllegalCamOrder { segment: 2 }
    );
}

/// Guards against an MCCP refused for its operands (Length, profile size,
/// slopes) wiping the profile already calculated in the tag (Status 0).
#[test]
fn operand_errors_leave_a_calculated_profile_untouched() {
    let cam = cubic(&[(0.0, 0.0), (1.0, 1.0), (2.0, 0.0)]);
    let mut tag = CamProfileTag::new(2);
    tag.calculate(&cam, 2, 0.0, 0.0).unwrap();
    let before = tag.clone();
    for (length, start, end, err) in [
        (1, 0.0, 0.0, 26),
        (4, 0.0, 0.0, 26),
        (3, 0.0, 0.0, 27),
        (2, f64::NAN, 0.0, 13),
        (2, 0.0, f64::INFINITY, 13),
    ] {
        assert_eq!(tag.calculate(&cam, length, start, end).unwrap_err().err(), err);
        assert_eq!(tag, before, "ERR {err}");
    }
    // An element error happens while the profile is being written.
    let bad = cubic(&[(0.0, 0.0), (0.0, 1.0)]);
    assert_eq!(tag.calculate(&bad, 2, 0.0, 0.0).unwrap_err().err(), 29);
    assert_eq!((tag.status(), tag.profile().is_none()), (0, true));
}

/// `Cam[start]`: the check counts the elements from `start`, the EXERR of ERR
/// 26 is the whole array's size.
#[test]
fn err_26_from_an_element_reports_the_array_size() {
    use crate::task::MotionTask;
    let cam = cubic(&[(0.0, 0.0), (1.0, 1.0), (2.0, 0.0), (3.0, 2.0), (4.0, 1.0)]);
    let mut task = MotionTask::new(0.004).unwrap();
    let profile = task.add_cam_profile("Profile", 4);
    let mccp = task.add_instruction("MCCP_1");
    let e = task.mccp_from(mccp, &cam, 2, 4, 0.0, 0.0, profile).unwrap_err();
    assert_eq!((e.err(), e.exerr()), (26, 5));
    let bits = task.motion_bits(mccp);
    assert_eq!((bits.er, bits.err, bits.exerr), (true, 26, 5));
    task.mccp_from(mccp, &cam, 2, 3, 0.0, 0.0, profile).unwrap();
    assert_eq!(task.cam_profile(profile).profile().unwrap().elements()[0].master, 2.0);
}
