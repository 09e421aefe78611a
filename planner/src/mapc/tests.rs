//! MAPC operands and the position cam process on its own (no task): operand
//! numbers, and seeded random master walks against the position law.

use super::*;
use crate::mccp::{CamElement, CamProfile};
use axis::{CamEvent, CamRequest, PositionCamAxis, SlaveCamStatus, cam_value};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::sync::Arc;

#[test]
fn operand_numbers_map_to_the_spec_enumerations() {
    let d = MapcOperands::default();
    let m = Mapc::new(&d).unwrap();
    assert_eq!(
        (m.direction, m.execution_mode, m.execution_schedule, m.cam_type),
        (
            CamDirection::Same,
            ExecutionMode::Once,
            ExecutionSchedule::Immediate,
            CamType::NewCam
        )
    );
    assert_eq!(
        (
            m.master_reference,
            m.master_direction,
            m.slave_scaling,
            m.master_scaling
        ),
        (MasterReference::Actual, MasterDirection::Bidirectional, 1.0, 1.0)
    );
    let dirs = [
        CamDirection::Same,
        CamDirection::Opposite,
        CamDirection::Reverse,
        CamDirection::Unchanged,
    ];
    for (i, want) in dirs.into_iter().enumerate() {
        let o = MapcOperands {
            direction: i as i32,
            ..d
        };
        assert_eq!(Mapc::new(&o).unwrap().direction, want);
    }
    let modes = [
        ExecutionMode::Once,
        ExecutionMode::Continuous,
        ExecutionMode::Persistent,
    ];
    for (i, want) in modes.into_iter().enumerate() {
        let o = MapcOperands {
            execution_mode: i as i32,
            ..d
        };
        assert_eq!(Mapc::new(&o).unwrap().execution_mode, want);
    }
    let schedules = [
        ExecutionSchedule::Immediate,
        ExecutionSchedule::Pending,
        ExecutionSchedule::ForwardOnly,
        ExecutionSchedule::ReverseOnly,
        ExecutionSchedule::Bidirectional,
    ];
    for (i, want) in schedules.into_iter().enumerate() {
        let o = MapcOperands {
            execution_schedule: i as i32,
            ..d
        };
        assert_eq!(Mapc::new(&o).unwrap().execution_schedule, want);
    }
    let types = [CamType::NewCam, CamType::ReplaceAndRestart, CamType::ReplaceAndContinue];
    for (i, want) in types.into_iter().enumerate() {
        let o = MapcOperands {
            cam_type: i as i32,
            ..d
        };
        assert_eq!(Mapc::new(&o).unwrap().cam_type, want);
    }
    let refs = [MasterReference::Actual, MasterReference::Command];
    for (i, want) in refs.into_iter().enumerate() {
        let o = MapcOperands {
            master_reference: i as i32,
            ..d
        };
        assert_eq!(Mapc::new(&o).unwrap().master_reference, want);
    }
    let mdirs = [
        MasterDirection::Bidirectional,
        MasterDirection::ForwardOnly,
        MasterDirection::ReverseOnly,
    ];
    for (i, want) in mdirs.into_iter().enumerate() {
        let o = MapcOperands {
            master_direction: i as i32,
            ..d
        };
        assert_eq!(Mapc::new(&o).unwrap().master_direction, want);
    }
}

fn random_profile(rng: &mut ChaCha8Rng) -> Arc<CamProfile> {
    let n = rng.random_range(2..12);
    let mut x = rng.random_range(-10.0..10.0);
    let cam: Vec<CamElement> = (0..n)
        .map(|_| {
            x += rng.random_range(0.5..10.0);
            CamElement {
                master: x,
                slave: rng.random_range(-20.0..20.0),
                segment_type: rng.random_range(0..2),
            }
        })
        .collect();
    Arc::new(CamProfile::calculate(&cam, n, rng.random_range(-2.0..2.0), rng.random_range(-2.0..2.0)).unwrap())
}

fn request(profile: Arc<CamProfile>, mapc: Mapc) -> CamRequest<u32, u8> {
    CamRequest {
        tag: 1,
        master: 0,
        mapc,
        profile,
        master_period: None,
    }
}

#[test]
fn random_master_walks_follow_the_position_law() {
    let mut rng = ChaCha8Rng::seed_from_u64(0x6a9c);
    for case in 0..300 {
        let profile = random_profile(&mut rng);
        let (x0, xn) = profile.master_range();
        let ms = rng.random_range(0.2..3.0);
        let ss = rng.random_range(-3.0..3.0);
        let master_direction = [
            MasterDirection::Bidirectional,
            MasterDirection::ForwardOnly,
            MasterDirection::ReverseOnly,
        ][case % 3];
        let cam_lock = rng.random_range(x0..=xn);
        let mapc = Mapc {
            slave_scaling: ss,
            master_scaling: ms,
            execution_mode: ExecutionMode::Continuous,
            cam_lock_position: cam_lock,
            master_direction,
            ..Mapc::new(&MapcOperands::default()).unwrap()
        };
        let mut cam: PositionCamAxis<u32, u8> = PositionCamAxis::default();
        let m0 = rng.random_range(-50.0..50.0);
        let s0 = rng.random_range(-50.0..50.0);
        let events = cam.start(request(profile.clone(), mapc), s0, |_| m0).unwrap();
        assert_eq!(events, vec![CamEvent::Active(1)]);
        let f = |u: f64| cam_value(&profile, ExecutionMode::Continuous, u);
        let mut m = m0;
        let mut clutch = m0;
        let mut slave = s0;
        for _ in 0..200 {
            m += rng.random_range(-5.0..5.0);
            clutch = match master_direction {
                MasterDirection::Bidirectional => m,
                MasterDirection::ForwardOnly => clutch.max(m),
                MasterDirection::ReverseOnly => clutch.min(m),
            };
            let (s, ev) = cam.update(slave, |_| m);
            assert!(ev.is_empty());
            slave = s.unwrap();
            let u = cam_lock + (clutch - m0) / ms;
            let want = s0 + ss * (f(u) - f(cam_lock));
            assert!(
                (slave - want).abs() < 1e-8 * (1.0 + want.abs()),
                "case {case}: {slave} vs {want}"
            );
            assert_eq!(cam.status().lock, clutch == m);
        }
    }
}

#[test]
fn continuous_unwinding_adds_the_rise_per_cycle_without_jumps() {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    for _ in 0..200 {
        let p = random_profile(&mut rng);
        let (x0, xn) = p.master_range();
        let (y0, yn) = p.slave_range();
        let period = xn - x0;
        for _ in 0..20 {
            let u = rng.random_range(x0 - 3.0 * period..xn + 3.0 * period);
            let a = cam_value(&p, ExecutionMode::Continuous, u);
            let b = cam_value(&p, ExecutionMode::Continuous, u + period);
            assert!((b - a - (yn - y0)).abs() < 1e-9 * (1.0 + a.abs() + b.abs()));
        }
        // Continuous across the boundary itself.
        let eps = 1e-9;
        let left = cam_value(&p, ExecutionMode::Continuous, xn - eps);
        let right = cam_value(&p, ExecutionMode::Continuous, xn + eps);
        assert!((left - right).abs() < 1e-6 * (1.0 + p.eval(xn).slope.abs() + p.eval(x0).slope.abs()));
    }
}

#[test]
fn reruns_are_bit_identical() {
    let run = || {
        let mut rng = ChaCha8Rng::seed_from_u64(99);
        let p = random_profile(&mut rng);
        let lock = p.master_range().0;
        let mapc = Mapc {
            cam_lock_position: lock,
            execution_mode: ExecutionMode::Persistent,
            ..Mapc::new(&MapcOperands::default()).unwrap()
        };
        let mut cam: PositionCamAxis<u32, u8> = PositionCamAxis::default();
        cam.start(request(p, mapc), 0.0, |_| 0.0).unwrap();
        let mut m = 0.0;
        let mut out = Vec::new();
        let mut s = 0.0;
        for _ in 0..100 {
            m += rng.random_range(-1.0..2.0);
            s = cam.update(s, |_| m).0.unwrap_or(s);
            out.push(s.to_bits());
        }
        out
    };
    assert_eq!(run(), run());
}

/// Once and Persistent under random master walks: the slave follows the
/// clamped profile, Lock Status is "following and inside the range", a Once
/// cam completes exactly when the coordinate leaves the range (slave at the
/// boundary value, never moving again) and a Persistent cam never ends.
#[test]
fn random_master_walks_once_and_persistent() {
    let mut rng = ChaCha8Rng::seed_from_u64(0x0ce);
    for case in 0..400 {
        let profile = random_profile(&mut rng);
        let (x0, xn) = profile.master_range();
        let ms = rng.random_range(0.2..3.0) * if rng.random_bool(0.2) { -1.0 } else { 1.0 };
        let ss = rng.random_range(-3.0..3.0);
        let once = case % 2 == 0;
        let master_direction = [
            MasterDirection::Bidirectional,
            MasterDirection::ForwardOnly,
            MasterDirection::ReverseOnly,
        ][(case / 2) % 3];
        let cam_lock = rng.random_range(x0..=xn);
        let mapc = Mapc {
            slave_scaling: ss,
            master_scaling: ms,
            execution_mode: if once {
                ExecutionMode::Once
            } else {
                ExecutionMode::Persistent
            },
            cam_lock_position: cam_lock,
            master_direction,
            ..Mapc::new(&MapcOperands::default()).unwrap()
        };
        let mut cam: PositionCamAxis<u32, u8> = PositionCamAxis::default();
        let m0 = rng.random_range(-50.0..50.0);
        let s0 = rng.random_range(-50.0..50.0);
        cam.start(request(profile.clone(), mapc), s0, |_| m0).unwrap();
        let f = |u: f64| profile.eval(u).slave;
        let (mut m, mut clutch, mut slave) = (m0, m0, s0);
        let mut ended_at: Option<f64> = None;
        for _ in 0..200 {
            m += rng.random_range(-5.0..5.0);
            clutch = match master_direction {
                MasterDirection::Bidirectional => m,
                MasterDirection::ForwardOnly => clutch.max(m),
                MasterDirection::ReverseOnly => clutch.min(m),
            };
            let (s, ev) = cam.update(slave, |_| m);
            let u = cam_lock + (clutch - m0) / ms;
            let inside = (x0..=xn).contains(&u);
            if let Some(end) = ended_at {
                // A completed Once cam never moves the slave again.
                assert!(ev.is_empty() && s.is_none(), "case {case}");
                assert_eq!(slave, end);
                assert_eq!(cam.status(), SlaveCamStatus::default());
                continue;
            }
            slave = s.unwrap();
            let want = s0 + ss * (f(u.clamp(x0, xn)) - f(cam_lock));
            assert!(
                (slave - want).abs() < 1e-8 * (1.0 + want.abs()),
                "case {case}: {slave} vs {want}"
            );
            if once && !inside {
                assert_eq!(ev, vec![CamEvent::Ended { tag: 1, complete: true }], "case {case}");
                ended_at = Some(slave);
                assert_eq!(cam.status(), SlaveCamStatus::default());
                continue;
            }
            assert!(ev.is_empty(), "case {case}");
            let status = cam.status();
            assert!(status.position_cam && !status.pending);
            assert_eq!(status.lock, clutch == m && inside, "case {case}");
        }
    }
}
