//! Seeded random round trips for every geometry, EXERR validation of the
//! geometry parameters.

use super::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

const SAMPLES: usize = 10_000;
const TOL: f64 = 1e-9;

/// Every geometry with non-zero offsets and zero angles, and the range of the
/// kinematic angles θ = q + Z to sample (radians; lengths for prismatic).
type Fixture = (&'static str, Geometry, [(f64, f64); 3]);

fn fixtures() -> Vec<Fixture> {
    let pi = PI - 1e-6;
    let serial = GeometryParams {
        link_lengths: [0.45, 0.35, 0.0],
        base_offsets: [0.05, 0.02, 0.3],
        end_effector_offsets: [0.03, -0.01, -0.04],
        zero_angles_deg: [10.0, -20.0, 35.0],
    };
    let delta = GeometryParams {
        link_lengths: [0.3, 0.8, 0.0],
        base_offsets: [0.2, 0.1, 0.05],
        end_effector_offsets: [0.05, -0.02, -0.1],
        zero_angles_deg: [5.0, -7.0, 12.0],
    };
    let cartesian = GeometryParams {
        base_offsets: [0.5, -0.25, 1.0],
        end_effector_offsets: [0.1, 0.2, -0.3],
        ..Default::default()
    };
    let g = |kind, params: &GeometryParams, dim| Geometry::new(kind, params, dim).unwrap();
    let lin = (-2.0, 2.0);
    let rev = (-pi, pi);
    let knee = (-0.7, 1.5);
    vec![
        ("gantry", g(GeometryKind::CartesianGantry, &cartesian, 3), [lin; 3]),
        ("h-bot", g(GeometryKind::CartesianHBot, &cartesian, 3), [lin; 3]),
        (
            "articulated independent 3d",
            g(GeometryKind::ArticulatedIndependent, &serial, 3),
            [rev; 3],
        ),
        (
            "articulated independent 2d",
            g(GeometryKind::ArticulatedIndependent, &serial, 2),
            [rev, rev, (0.0, 0.0)],
        ),
        (
            "articulated dependent 3d",
            g(GeometryKind::ArticulatedDependent, &serial, 3),
            [rev; 3],
        ),
        (
            "articulated dependent 2d",
            g(GeometryKind::ArticulatedDependent, &serial, 2),
            [rev, rev, (0.0, 0.0)],
        ),
        (
            "scara independent",
            g(GeometryKind::ScaraIndependent, &serial, 2),
            [rev, rev, lin],
        ),
        ("delta 3d", g(GeometryKind::Delta3d, &delta, 3), [knee; 3]),
        (
            "delta 2d",
            g(GeometryKind::Delta2d, &delta, 2),
            [knee, knee, (0.0, 0.0)],
        ),
        ("scara delta", g(GeometryKind::ScaraDelta, &delta, 2), [knee, knee, lin]),
    ]
}

fn zero_rad(g: &Geometry) -> Vec3 {
    match g {
        Geometry::Articulated(a) => a.zero_rad,
        Geometry::ScaraIndependent(s) => s.zero_rad,
        Geometry::Delta3d(d) => d.arms.zero_rad,
        Geometry::FiveBar(f) => f.arms.zero_rad,
        Geometry::CartesianGantry(_) | Geometry::CartesianHBot(_) => [0.0; 3],
    }
}

fn joint_distance(g: &Geometry, a: Vec3, b: Vec3) -> f64 {
    let kinds = g.joint_kinds();
    (0..3)
        .map(|i| match kinds[i] {
            JointKind::Revolute => wrap_pi(a[i] - b[i]).abs(),
            JointKind::Prismatic => (a[i] - b[i]).abs(),
        })
        .fold(0.0, f64::max)
}

fn distance(a: Vec3, b: Vec3) -> f64 {
    (0..3).map(|i| (a[i] - b[i]).abs()).fold(0.0, f64::max)
}

fn branches(g: &Geometry) -> usize {
    match g {
        Geometry::CartesianGantry(_) | Geometry::CartesianHBot(_) => 0,
        Geometry::Articulated(a) if a.dimension == 3 => 2,
        Geometry::Articulated(_) | Geometry::ScaraIndependent(_) => 1,
        Geometry::Delta3d(_) => 3,
        Geometry::FiveBar(_) => 2,
    }
}

#[test]
fn random_round_trips_on_the_same_and_the_other_arm_solutions() {
    for (seed, (name, g, range)) in fixtures().into_iter().enumerate() {
        let mut rng = ChaCha8Rng::seed_from_u64(1000 + seed as u64);
        let z = zero_rad(&g);
        let (mut checked, mut refused, mut unreachable, mut other_solutions) = (0, 0, 0, 0);
        // Round trips inverse(forward(q)) = q on q's own solution, per value
        // of solution bit 0 (right arm / left arm, or Delta knee 1 outward /
        // inward): each value gets at least SAMPLES.
        let mut per_bit0 = [0usize; 2];
        let wanted = |per: &[usize; 2]| {
            if branches(&g) == 0 {
                per[0] >= SAMPLES
            } else {
                per[0] >= SAMPLES && per[1] >= SAMPLES
            }
        };
        let mut drawn = 0;
        while !wanted(&per_bit0) {
            drawn += 1;
            assert!(
                drawn < 40 * SAMPLES,
                "{name}: only {per_bit0:?} round trips per arm solution"
            );
            let mut q = [0.0; 3];
            for i in 0..3 {
                let (lo, hi) = range[i];
                let theta = if hi > lo { rng.random_range(lo..hi) } else { lo };
                q[i] = if g.joint_kinds()[i] == JointKind::Revolute && hi > lo {
                    wrap_pi(theta - z[i])
                } else {
                    theta
                };
            }
            let x = match g.forward(q) {
                Ok(x) => x,
                Err(PositionError::OutOfReach { .. }) => {
                    // Only a Delta's forearms can fail to meet.
                    assert!(
                        matches!(g, Geometry::Delta3d(_) | Geometry::FiveBar(_)),
                        "{name}: {q:?}"
                    );
                    unreachable += 1;
                    continue;
                }
                Err(e) => panic!("{name}: forward({q:?}): {e}"),
            };
            let s = g.solution(q).unwrap();
            match g.inverse(x, s) {
                Ok(back) => {
                    assert!(
                        joint_distance(&g, back, q) < TOL,
                        "{name}: q {q:?} -> x {x:?} -> {back:?}"
                    );
                    let again = g.forward(back).unwrap();
                    assert!(distance(again, x) < TOL, "{name}: {x:?} -> {again:?}");
                    assert_eq!(g.solution(back).unwrap(), s, "{name}: {q:?}");
                    checked += 1;
                    per_bit0[usize::from(s.flipped(0))] += 1;
                }
                Err(PositionError::Singularity { angle_rad, .. }) => {
                    assert!(
                        !(2.0 * SINGULARITY_MARGIN_RAD..=PI - 2.0 * SINGULARITY_MARGIN_RAD).contains(&angle_rad),
                        "{name}: {q:?}"
                    );
                    refused += 1;
                    continue;
                }
                Err(e) => panic!("{name}: inverse({x:?}, {s:?}) of q {q:?}: {e}"),
            }
            // Every other arm solution reaches the same point, and is the
            // solution its joints report.
            for chain in 0..branches(&g) {
                let other = s.with(chain, !s.flipped(chain));
                if let Ok(q2) = g.inverse(x, other) {
                    let x2 = g.forward(q2).unwrap();
                    assert!(distance(x2, x) < TOL, "{name}: {other:?} {x:?} -> {x2:?}");
                    assert_eq!(g.solution(q2).unwrap(), other, "{name}: {q2:?}");
                    assert!(
                        joint_distance(&g, q2, q) > 1e-6,
                        "{name}: other solution equals the first"
                    );
                    // And q2 is itself a configuration whose round trip on
                    // its own solution gives it back (this is how the
                    // solutions that joint sampling rarely meets, such as a
                    // Delta knee turned inward, get their round trips).
                    let back2 = g.inverse(x2, other).unwrap();
                    assert!(
                        joint_distance(&g, back2, q2) < TOL,
                        "{name}: q2 {q2:?} -> x {x2:?} -> {back2:?}"
                    );
                    if chain == 0 {
                        per_bit0[usize::from(other.flipped(0))] += 1;
                    }
                    other_solutions += 1;
                }
            }
        }
        assert!(
            checked > drawn * 8 / 10,
            "{name}: only {checked} round trips of {drawn} ({refused} singular, {unreachable} unreachable)"
        );
        assert!(refused < drawn / 100, "{name}: {refused} singular refusals");
        if branches(&g) > 0 {
            assert!(
                other_solutions > checked / 2,
                "{name}: only {other_solutions} other solutions"
            );
        }
    }
}

#[test]
fn forward_of_inverse_of_random_workspace_points() {
    // Points drawn in a box around the work space, not from joint samples:
    // each one is either reached exactly or refused with a typed error.
    for (seed, (name, g, _)) in fixtures().into_iter().enumerate() {
        let mut rng = ChaCha8Rng::seed_from_u64(2000 + seed as u64);
        let mut reached = 0;
        for _ in 0..SAMPLES {
            let x: Vec3 = match g {
                Geometry::Delta3d(_) => [
                    rng.random_range(-0.5..0.5),
                    rng.random_range(-0.5..0.5),
                    rng.random_range(-1.2..-0.3),
                ],
                Geometry::FiveBar(f) if !f.scara => [rng.random_range(-0.6..0.6), rng.random_range(-1.0..0.0), 0.0],
                Geometry::FiveBar(_) => [
                    rng.random_range(-0.6..0.6),
                    rng.random_range(0.2..1.2),
                    rng.random_range(-1.0..1.0),
                ],
                _ if g.dimension() == 2 && !g.shares_third_axis() => {
                    [rng.random_range(-0.9..0.9), rng.random_range(-0.9..0.9), 0.0]
                }
                _ => [0; 3].map(|_| rng.random_range(-0.9..0.9)),
            };
            let s = ArmSolution::from_bits(rng.random_range(0..8u8));
            match g.inverse(x, s) {
                Ok(q) => {
                    let back = g.forward(q).unwrap();
                    assert!(distance(back, x) < TOL, "{name}: {x:?} -> {q:?} -> {back:?}");
                    reached += 1;
                }
                Err(PositionError::OutOfReach { excess, .. }) => assert!(excess >= 0.0, "{name}"),
                Err(PositionError::Singularity { .. }) => {}
                Err(PositionError::OtherAssembly { depth }) => {
                    assert!(
                        matches!(g, Geometry::Delta3d(_) | Geometry::FiveBar(_)) && depth > 0.0,
                        "{name}"
                    )
                }
                Err(e) => panic!("{name}: {x:?}: {e}"),
            }
        }
        assert!(reached > SAMPLES / 10, "{name}: only {reached} points reached");
    }
}

#[test]
fn exerr_of_every_geometry_error() {
    let ok = GeometryParams {
        link_lengths: [0.3, 0.8, 0.0],
        base_offsets: [0.2, 0.0, 0.0],
        end_effector_offsets: [0.05, 0.0, 0.0],
        ..Default::default()
    };
    let err = |kind, p: &GeometryParams, dim| Geometry::new(kind, p, dim).unwrap_err();
    // EXERR 12: zero link length.
    let zero_l2 = GeometryParams {
        link_lengths: [0.3, 0.0, 0.0],
        ..ok
    };
    for kind in [
        GeometryKind::ArticulatedIndependent,
        GeometryKind::ArticulatedDependent,
        GeometryKind::ScaraIndependent,
        GeometryKind::Delta2d,
        GeometryKind::ScaraDelta,
    ] {
        let e = err(kind, &zero_l2, 2);
        assert_eq!((e.err(), e.exerr()), (61, 12), "{kind:?}");
        assert_eq!(e, GeometryError::LinkLength { link: 2, value: 0.0 });
    }
    assert_eq!(err(GeometryKind::Delta3d, &zero_l2, 3).exerr(), 12);
    // Cartesian geometries have no links.
    assert!(Geometry::new(GeometryKind::CartesianGantry, &zero_l2, 3).is_ok());
    // EXERR 15: X1b − X1e < 0 (Delta and SCARA Delta).
    let inside_out = GeometryParams {
        base_offsets: [0.04, 0.0, 0.0],
        ..ok
    };
    for (kind, dim) in [
        (GeometryKind::Delta3d, 3),
        (GeometryKind::Delta2d, 2),
        (GeometryKind::ScaraDelta, 2),
    ] {
        let e = err(kind, &inside_out, dim);
        assert_eq!(e.exerr(), 15, "{kind:?}");
        assert_eq!(
            e,
            GeometryError::DeltaOffsets {
                base: 0.04,
                effector: 0.05
            }
        );
    }
    // EXERR 15: L1 + (X1b − X1e) > L2 (Delta only; SCARA Delta accepts it).
    let long_l1 = GeometryParams {
        link_lengths: [0.7, 0.8, 0.0],
        ..ok
    };
    let e = err(GeometryKind::Delta3d, &long_l1, 3);
    assert_eq!(e.exerr(), 15);
    assert!(matches!(e, GeometryError::DeltaReach { l1: 0.7, l2: 0.8, .. }));
    assert_eq!(err(GeometryKind::Delta2d, &long_l1, 2).exerr(), 15);
    assert!(Geometry::new(GeometryKind::ScaraDelta, &long_l1, 2).is_ok());
    // Exactly L1 + (X1b − X1e) = L2 is allowed.
    let exact = GeometryParams {
        link_lengths: [0.65, 0.8, 0.0],
        base_offsets: [0.2, 0.0, 0.0],
        end_effector_offsets: [0.05, 0.0, 0.0],
        ..Default::default()
    };
    assert!(Geometry::new(GeometryKind::Delta3d, &exact, 3).is_ok());
    // EXERR 16: the SCARA geometries need transform dimension 2.
    for kind in [GeometryKind::ScaraIndependent, GeometryKind::ScaraDelta] {
        let e = err(kind, &ok, 3);
        assert_eq!((e.err(), e.exerr()), (61, 16), "{kind:?}");
    }
    // EXERR 4: a target dimension the geometry cannot have.
    for (kind, dim) in [
        (GeometryKind::Delta3d, 2),
        (GeometryKind::Delta2d, 3),
        (GeometryKind::ArticulatedIndependent, 1),
        (GeometryKind::CartesianHBot, 1),
        (GeometryKind::CartesianGantry, 4),
        (GeometryKind::CartesianGantry, 0),
    ] {
        assert_eq!(err(kind, &ok, dim).exerr(), 4, "{kind:?} {dim}");
    }
    // Negative and non-finite lengths are EXERR 12 too; a NaN offset is refused.
    let negative = GeometryParams {
        link_lengths: [-0.3, 0.8, 0.0],
        ..ok
    };
    assert_eq!(err(GeometryKind::ScaraIndependent, &negative, 2).exerr(), 12);
    let nan = GeometryParams {
        end_effector_offsets: [0.0, f64::NAN, 0.0],
        ..ok
    };
    assert!(matches!(
        err(GeometryKind::ScaraIndependent, &nan, 2),
        GeometryError::NotFinite {
            field: "end_effector_offsets",
            ..
        }
    ));
}

#[test]
fn non_finite_positions_are_refused_not_propagated() {
    for (name, g, _) in fixtures() {
        assert_eq!(g.forward([f64::NAN, 0.0, 0.0]), Err(PositionError::NotFinite), "{name}");
        assert_eq!(
            g.inverse([0.0, f64::INFINITY, 0.0], ArmSolution::default()),
            Err(PositionError::NotFinite),
            "{name}"
        );
    }
}
