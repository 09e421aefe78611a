//! MCCM known values (the spec's Move Type × Circle Type table and the
//! Circular Programming Reference Guide, row by row), every error code with
//! its ERR/EXERR, and seeded random arcs.

use super::*;
use crate::coord::{CoordMoveInputs, CoordinateSystem, CoordinateSystemConfig};
use crate::dynamics::MoveDynamics;
use crate::instruction::LogixFault;
use crate::profile::jerk_from_percent_of_time;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn system(primary: usize) -> CoordinateSystem {
    CoordinateSystem::new(CoordinateSystemConfig {
        axis_count: primary,
        primary_axes: primary,
        max_speed: 100.0,
        max_accel: 1000.0,
        max_decel: 1000.0,
        max_accel_jerk: 10000.0,
        max_decel_jerk: 10000.0,
        ..CoordinateSystemConfig::new("CS")
    })
    .unwrap()
}

fn inputs(move_type: i64, position: &[f64], circle_type: i64, vcr: &[f64], direction: i64) -> MccmInputs {
    MccmInputs {
        common: CoordMoveInputs {
            move_type,
            position: position.to_vec(),
            dynamics: MoveDynamics {
                speed: 10.0,
                accel_rate: 100.0,
                decel_rate: 100.0,
                ..CoordMoveInputs::default().dynamics
            },
            ..Default::default()
        },
        circle_type,
        via_center_radius: vcr.to_vec(),
        direction,
    }
}

fn build(sys: &CoordinateSystem, start: &[f64], i: &MccmInputs) -> Result<CoordMove, (i32, i32)> {
    let decels = vec![1.0; start.len()];
    let ctx = MoveContext {
        system: sys,
        axis_max_decel: &decels,
        start,
        has_master: false,
    };
    mccm(i, &ctx).map_err(|e| (e.err(), e.exerr()))
}

fn close(a: V3, b: V3) -> bool {
    norm(sub(a, b)) < 1e-9 * (1.0 + norm(a) + norm(b))
}

/// Checks center, radius, swept angle, turning sense (normal) and end.
#[track_caller]
fn assert_arc(m: &CoordMove, center: V3, radius: f64, angle: f64, normal: V3, end: &[f64]) {
    let arc = m.path().arc().expect("an arc");
    assert!(close(arc.center(), center), "center {:?} != {center:?}", arc.center());
    assert!(
        (arc.radius_start() - radius).abs() < 1e-9,
        "radius {}",
        arc.radius_start()
    );
    assert!(
        (arc.angle_rad() - angle).abs() < 1e-9,
        "angle {} != {angle}",
        arc.angle_rad()
    );
    assert!(close(arc.normal(), normal), "normal {:?} != {normal:?}", arc.normal());
    assert_eq!(m.path().end(), end);
    assert!((m.path().length() - radius * angle).abs() < 1e-9);
}

const Z: V3 = [0.0, 0.0, 1.0];
const NZ: V3 = [0.0, 0.0, -1.0];

// Start (3, 2), circle of radius 1 about (2, 2); half circle CCW to (1, 2)
// through (2, 3). Each row of the spec's table programs exactly that arc.
const START: [f64; 2] = [3.0, 2.0];

#[test]
fn table_absolute_via() {
    // "The via/center/radius position array defines a position along the circle …
    // the Position parameter array defines the endpoint of the arc."
    let m = build(&system(2), &START, &inputs(0, &[1.0, 2.0], 0, &[2.0, 3.0], 0)).unwrap();
    assert_arc(&m, [2.0, 2.0, 0.0], 1.0, PI, Z, &[1.0, 2.0]);
}

#[test]
fn table_incremental_via() {
    // "The sum of the via/center/radius position array and the old position defines
    // the position along the circle … the sum of Position and the old position the endpoint."
    let m = build(&system(2), &START, &inputs(1, &[-2.0, 0.0], 0, &[-1.0, 1.0], 0)).unwrap();
    assert_arc(&m, [2.0, 2.0, 0.0], 1.0, PI, Z, &[1.0, 2.0]);
}

#[test]
fn table_absolute_center() {
    let m = build(&system(2), &START, &inputs(0, &[1.0, 2.0], 1, &[2.0, 2.0], 1)).unwrap();
    assert_arc(&m, [2.0, 2.0, 0.0], 1.0, PI, Z, &[1.0, 2.0]);
}

#[test]
fn table_incremental_center() {
    let m = build(&system(2), &START, &inputs(1, &[-2.0, 0.0], 1, &[-1.0, 0.0], 1)).unwrap();
    assert_arc(&m, [2.0, 2.0, 0.0], 1.0, PI, Z, &[1.0, 2.0]);
}

#[test]
fn table_radius_absolute_and_incremental() {
    // "The via/center/radius position single value defines the arc radius … the
    // position parameter array follows the Move Type to define the endpoint."
    // A quarter circle CCW from (3, 2) to (2, 3): center (2, 2) for +R.
    let m = build(&system(2), &START, &inputs(0, &[2.0, 3.0], 2, &[1.0], 1)).unwrap();
    assert_arc(&m, [2.0, 2.0, 0.0], 1.0, PI / 2.0, Z, &[2.0, 3.0]);
    let m = build(&system(2), &START, &inputs(1, &[-1.0, 1.0], 2, &[1.0], 1)).unwrap();
    assert_arc(&m, [2.0, 2.0, 0.0], 1.0, PI / 2.0, Z, &[2.0, 3.0]);
    // A negative radius takes the other center and the long way (≥ 180°).
    let m = build(&system(2), &START, &inputs(0, &[2.0, 3.0], 2, &[-1.0], 1)).unwrap();
    assert_arc(&m, [3.0, 3.0, 0.0], 1.0, 1.5 * PI, Z, &[2.0, 3.0]);
}

#[test]
fn table_absolute_center_incremental() {
    // The center is always start + array; Position stays absolute.
    let m = build(&system(2), &START, &inputs(0, &[1.0, 2.0], 3, &[-1.0, 0.0], 1)).unwrap();
    assert_arc(&m, [2.0, 2.0, 0.0], 1.0, PI, Z, &[1.0, 2.0]);
}

#[test]
fn table_incremental_center_incremental() {
    let m = build(&system(2), &START, &inputs(1, &[-2.0, 0.0], 3, &[-1.0, 0.0], 1)).unwrap();
    assert_arc(&m, [2.0, 2.0, 0.0], 1.0, PI, Z, &[1.0, 2.0]);
}

#[test]
fn table_full_circle_position_is_any_second_point() {
    // "For a full circle case, the Position parameter array defines any second point
    // along the circle except the endpoint": the move goes once round and ends at its start.
    let sys = system(2);
    for (mt, pos, ct, vcr) in [
        (0, [1.0, 2.0], 0, [2.0, 3.0]),   // absolute via: start → (2, 3) → (1, 2) is CCW
        (1, [-2.0, 0.0], 0, [-1.0, 1.0]), // incremental via
        (0, [2.0, 3.0], 1, [2.0, 2.0]),   // absolute center
        (1, [-1.0, 1.0], 1, [-1.0, 0.0]), // incremental center
        (0, [2.0, 3.0], 3, [-1.0, 0.0]),  // absolute center incremental
        (1, [-1.0, 1.0], 3, [-1.0, 0.0]), // incremental center incremental
    ] {
        let m = build(&sys, &START, &inputs(mt, &pos, ct, &vcr, 3)).unwrap();
        assert_arc(&m, [2.0, 2.0, 0.0], 1.0, TAU, Z, &START);
    }
    // Radius, full: once round the circle the partial move would use.
    let m = build(&sys, &START, &inputs(0, &[2.0, 3.0], 2, &[1.0], 2)).unwrap();
    assert_arc(&m, [3.0, 3.0, 0.0], 1.0, TAU, NZ, &START);
}

// --- Circular Programming Reference Guide: Radius ---

#[test]
fn guide_radius_2d_only_error_25() {
    let r = build(&system(3), &[0.0, 0.0, 0.0], &inputs(0, &[1.0, 1.0, 0.0], 2, &[1.0], 0));
    assert_eq!(r.map(|_| ()), Err((25, 0)));
}

#[test]
fn guide_radius_errors_45_and_49() {
    let sys = system(2);
    assert_eq!(
        build(&sys, &START, &inputs(0, &START, 2, &[1.0], 0)).map(|_| ()),
        Err((45, 0))
    );
    // R < 0.001.
    let tiny = [3.0005, 2.0];
    assert_eq!(
        build(&sys, &START, &inputs(0, &tiny, 2, &[0.0009], 0)).map(|_| ()),
        Err((49, 0))
    );
    // R too short to span the points (chord 2, R 0.99).
    assert_eq!(
        build(&sys, &START, &inputs(0, &[1.0, 2.0], 2, &[-0.99], 0)).map(|_| ()),
        Err((49, 0))
    );
    // Exactly spanning (a semicircle) is legal.
    let m = build(&sys, &START, &inputs(0, &[1.0, 2.0], 2, &[1.0], 0)).unwrap();
    assert_arc(&m, [2.0, 2.0, 0.0], 1.0, PI, NZ, &[1.0, 2.0]);
}

#[test]
fn guide_radius_cw_ccw_seen_from_plus_perpendicular() {
    let sys = system(2);
    // From (3, 2) to (2, 3), R = 1: CW short way passes (3, 3)'s side: center (3, 3).
    let m = build(&sys, &START, &inputs(0, &[2.0, 3.0], 2, &[1.0], 0)).unwrap();
    assert_arc(&m, [3.0, 3.0, 0.0], 1.0, PI / 2.0, NZ, &[2.0, 3.0]);
    let m = build(&sys, &START, &inputs(0, &[2.0, 3.0], 2, &[-1.0], 0)).unwrap();
    assert_arc(&m, [2.0, 2.0, 0.0], 1.0, 1.5 * PI, NZ, &[2.0, 3.0]);
    // Every interpolated point turns the way asked: CW means decreasing polar angle.
    let arc = m.path().arc().unwrap();
    let a0 = |p: V3| (p[1] - 2.0).atan2(p[0] - 2.0);
    let (p1, p2) = (arc.point(0.1), arc.point(0.2));
    assert!(a0(p2) < a0(p1));
}

// --- Center ---

#[test]
fn guide_center_2d_end_equals_start_is_a_full_circle_for_every_direction() {
    let sys = system(2);
    for dir in 0..4 {
        let m = build(&sys, &START, &inputs(0, &START, 1, &[2.0, 2.0], dir)).unwrap();
        let normal = if dir % 2 == 0 { NZ } else { Z };
        assert_arc(&m, [2.0, 2.0, 0.0], 1.0, TAU, normal, &START);
    }
}

#[test]
fn guide_center_2d_cw_and_ccw() {
    let sys = system(2);
    let m = build(&sys, &START, &inputs(0, &[2.0, 3.0], 1, &[2.0, 2.0], 0)).unwrap();
    assert_arc(&m, [2.0, 2.0, 0.0], 1.0, 1.5 * PI, NZ, &[2.0, 3.0]);
    let m = build(&sys, &START, &inputs(0, &[2.0, 3.0], 1, &[2.0, 2.0], 1)).unwrap();
    assert_arc(&m, [2.0, 2.0, 0.0], 1.0, 0.5 * PI, Z, &[2.0, 3.0]);
    // Collinear start, center and end is legal in 2D (a half circle).
    let m = build(&sys, &START, &inputs(0, &[1.0, 2.0], 1, &[2.0, 2.0], 0)).unwrap();
    assert_arc(&m, [2.0, 2.0, 0.0], 1.0, PI, NZ, &[1.0, 2.0]);
}

#[test]
fn guide_center_error_46_start_end_radius_mismatch() {
    let sys = system(2);
    // R1 = 1; R2 = 0.84 and 1.16 are out, 0.86 and 1.14 in (a spiral).
    for (r2, err) in [(0.84, true), (0.86, false), (1.14, false), (1.16, true)] {
        let end = [2.0, 2.0 + r2];
        let r = build(&sys, &START, &inputs(0, &end, 1, &[2.0, 2.0], 1));
        if err {
            assert_eq!(r.map(|_| ()), Err((46, 0)), "{r2}");
        } else {
            let m = r.unwrap();
            let arc = m.path().arc().unwrap();
            assert!((arc.radius_end() - r2).abs() < 1e-12);
            let (mut p, mut d) = ([0.0; 2], [0.0; 2]);
            m.path().point(m.path().length(), &mut p, &mut d);
            assert_eq!(p, end);
            assert!(close(arc.point(arc.angle_rad()), [end[0], end[1], 0.0]));
        }
    }
}

#[test]
fn guide_center_3d_errors_44_45_and_shortest_longest() {
    let sys = system(3);
    let s = [1.0, 0.0, 5.0];
    let c = [0.0, 0.0, 5.0];
    // 45: end = start (3D only).
    assert_eq!(build(&sys, &s, &inputs(0, &s, 1, &c, 2)).map(|_| ()), Err((45, 0)));
    // 44: start, center, end collinear (3D only).
    assert_eq!(
        build(&sys, &s, &inputs(0, &[-1.0, 0.0, 5.0], 1, &c, 0)).map(|_| ()),
        Err((44, 0))
    );
    // A quarter circle in the x-y plane at z = 5 is still a 3D arc.
    let end = [0.0, 1.0, 5.0];
    let m = build(&sys, &s, &inputs(0, &end, 1, &c, 0)).unwrap();
    assert_arc(&m, c, 1.0, PI / 2.0, Z, &end);
    let m = build(&sys, &s, &inputs(0, &end, 1, &c, 1)).unwrap();
    assert_arc(&m, c, 1.0, 1.5 * PI, NZ, &end);
    // Full: the end point defines the shortest sense; longest full turns the other way.
    let m = build(&sys, &s, &inputs(0, &end, 1, &c, 2)).unwrap();
    assert_arc(&m, c, 1.0, TAU, Z, &s);
    let m = build(&sys, &s, &inputs(0, &end, 1, &c, 3)).unwrap();
    assert_arc(&m, c, 1.0, TAU, NZ, &s);
    // 46 in 3D too.
    assert_eq!(
        build(&sys, &s, &inputs(0, &[0.0, 1.3, 5.0], 1, &c, 0)).map(|_| ()),
        Err((46, 0))
    );
}

// --- Via ---

#[test]
fn guide_via_errors_44_45_both_dimensions() {
    for dim in [2, 3] {
        let sys = system(dim);
        let s = vec![0.0; dim];
        let mut e = vec![0.0; dim];
        e[0] = 2.0;
        let mut v = vec![0.0; dim];
        v[0] = 1.0;
        assert_eq!(build(&sys, &s, &inputs(0, &e, 0, &v, 0)).map(|_| ()), Err((44, 0)));
        assert_eq!(build(&sys, &s, &inputs(0, &e, 0, &s, 0)).map(|_| ()), Err((44, 0)));
        v[1] = 1.0;
        assert_eq!(build(&sys, &s, &inputs(0, &s, 0, &v, 0)).map(|_| ()), Err((45, 0)));
    }
}

#[test]
fn guide_via_point_always_determines_direction() {
    let sys = system(2);
    // Through (2, 1) from (3, 2) to (1, 2) is CW whatever Direction says (0 or 1).
    for dir in [0, 1] {
        let m = build(&sys, &START, &inputs(0, &[1.0, 2.0], 0, &[2.0, 1.0], dir)).unwrap();
        assert_arc(&m, [2.0, 2.0, 0.0], 1.0, PI, NZ, &[1.0, 2.0]);
    }
    // 3D: a tilted circle through three points; shortest/longest do not apply.
    let sys = system(3);
    let s = [1.0, 0.0, 0.0];
    let via = [0.0, 1.0, 0.0];
    let end = [0.0, 0.0, 1.0];
    let m = build(&sys, &s, &inputs(0, &end, 0, &via, 1)).unwrap();
    let arc = m.path().arc().unwrap();
    let c = 1.0 / 3.0;
    let r = (2.0_f64 / 3.0).sqrt();
    let n = 1.0 / 3.0_f64.sqrt();
    assert_arc(&m, [c, c, c], r, 4.0 * PI / 3.0, [n, n, n], &end);
    // The via point lies on the path, between start and end.
    let to_via = angle_about(sub(s, arc.center()), sub(via, arc.center()), arc.normal());
    assert!(close(arc.point(to_via), via) && to_via < arc.angle_rad());
}

// --- ERR 13 for every operand, ERR 54 ---

#[test]
fn parameter_out_of_range_names_each_operand() {
    let sys2 = system(2);
    let ok = inputs(0, &[1.0, 2.0], 1, &[2.0, 2.0], 1);
    let err = |i: &MccmInputs| build(&sys2, &START, i).map(|_| ());
    // 0: the system must have 2 or 3 primary axes.
    assert_eq!(build(&system(1), &[0.0], &ok).map(|_| ()), Err((13, 0)));
    let mut cases: Vec<(MccmInputs, i32)> = Vec::new();
    let with = |f: &dyn Fn(&mut MccmInputs)| {
        let mut i = ok.clone();
        f(&mut i);
        i
    };
    cases.push((with(&|i| i.common.move_type = 2), 2));
    cases.push((with(&|i| i.common.move_type = -1), 2));
    cases.push((with(&|i| i.common.position = vec![1.0]), 3));
    cases.push((with(&|i| i.circle_type = 4), 4));
    cases.push((with(&|i| i.circle_type = -1), 4));
    cases.push((with(&|i| i.via_center_radius = vec![2.0]), 5));
    cases.push((
        with(&|i| {
            i.circle_type = 2;
            i.via_center_radius = vec![];
        }),
        5,
    ));
    cases.push((with(&|i| i.direction = 4), 6));
    cases.push((with(&|i| i.direction = -1), 6));
    cases.push((with(&|i| i.common.dynamics.speed = -0.1), 7));
    cases.push((with(&|i| i.common.dynamics.speed_units = 2), 8));
    cases.push((with(&|i| i.common.dynamics.accel_rate = 0.0), 9));
    cases.push((with(&|i| i.common.dynamics.accel_units = 3), 10));
    cases.push((with(&|i| i.common.dynamics.decel_rate = 0.0), 11));
    cases.push((with(&|i| i.common.dynamics.decel_units = -1), 12));
    cases.push((with(&|i| i.common.dynamics.profile = 2), 13));
    cases.push((with(&|i| i.common.termination_type = 7), 14));
    cases.push((with(&|i| i.common.termination_type = -1), 14));
    cases.push((with(&|i| i.common.merge = 3), 15));
    cases.push((with(&|i| i.common.merge_speed = 2), 16));
    cases.push((
        with(&|i| {
            i.common.dynamics.profile = 1;
            i.common.dynamics.accel_jerk = 0.0;
        }),
        17,
    ));
    cases.push((
        with(&|i| {
            i.common.dynamics.profile = 1;
            i.common.dynamics.decel_jerk = 150.0;
        }),
        18,
    ));
    cases.push((
        with(&|i| {
            i.common.dynamics.profile = 1;
            i.common.dynamics.jerk_units = 3;
        }),
        19,
    ));
    cases.push((
        with(&|i| {
            i.common.termination_type = 6;
            i.common.command_tolerance = f64::NAN;
        }),
        20,
    ));
    cases.push((with(&|i| i.common.lock_direction = 5), 22));
    cases.push((with(&|i| i.common.event_distance = vec![-1.0]), 23));
    for (i, exerr) in cases {
        assert_eq!(err(&i), Err((13, exerr)), "{i:?}");
    }
    // ERR 13 comes before the geometry errors: a collinear via with a bad speed.
    let mut i = inputs(0, &[5.0, 2.0], 0, &[4.0, 2.0], 0);
    assert_eq!(err(&i), Err((44, 0)));
    i.common.dynamics.speed = -1.0;
    assert_eq!(err(&i), Err((13, 7)));
    // Termination types 0–6 are all accepted.
    for tt in 0..=6 {
        assert!(err(&with(&|i| i.common.termination_type = tt)).is_ok());
    }
}

#[test]
fn error_54_names_the_axis_or_minus_one() {
    let sys = system(3);
    let ok = inputs(0, &[0.0, 1.0, 0.0], 1, &[0.0, 0.0, 0.0], 0);
    let ctx = MoveContext {
        system: &sys,
        axis_max_decel: &[5.0, 0.0, 5.0],
        start: &[1.0, 0.0, 0.0],
        has_master: false,
    };
    assert_eq!(
        mccm(&ok, &ctx).map(|_| ()).map_err(|e| (e.err(), e.exerr())),
        Err((54, 1))
    );
    let zero = CoordinateSystem::new(CoordinateSystemConfig {
        max_decel: 0.0,
        ..sys.config().clone()
    })
    .unwrap();
    let ctx = MoveContext {
        system: &zero,
        axis_max_decel: &[5.0; 3],
        ..ctx
    };
    assert_eq!(
        mccm(&ok, &ctx).map(|_| ()).map_err(|e| (e.err(), e.exerr())),
        Err((54, -1))
    );
}

#[test]
fn percent_of_time_jerk_follows_the_spec_formula() {
    let sys = system(2);
    let mut i = inputs(0, &[1.0, 2.0], 1, &[2.0, 2.0], 1);
    i.common.dynamics.profile = 1;
    i.common.dynamics.speed = 8.0;
    i.common.dynamics.accel_rate = 40.0;
    i.common.dynamics.decel_rate = 20.0;
    i.common.dynamics.accel_jerk = 100.0;
    i.common.dynamics.decel_jerk = 25.0;
    i.common.dynamics.jerk_units = 2;
    let m = build(&sys, &START, &i).unwrap();
    let crate::profile::Shape::SCurve { accel_jerk, decel_jerk } = m.limits().unwrap().shape() else {
        panic!("an S-curve")
    };
    // j = a²/v · (200/% − 1): 40²/8 · 1 = 200, 20²/8 · 7 = 350.
    assert_eq!(accel_jerk, 200.0);
    assert_eq!(decel_jerk, 350.0);
    assert_eq!(jerk_from_percent_of_time(25.0, 20.0, 8.0), Ok(decel_jerk));
    // % of maximum uses the system's maximum jerks.
    i.common.dynamics.jerk_units = 1;
    i.common.dynamics.accel_jerk = 10.0;
    let m = build(&sys, &START, &i).unwrap();
    let crate::profile::Shape::SCurve { accel_jerk, .. } = m.limits().unwrap().shape() else {
        panic!("an S-curve")
    };
    assert_eq!(accel_jerk, 1000.0);
}

// --- Seeded random arcs ---

pub(crate) struct RandomArc {
    pub(crate) inputs: MccmInputs,
    pub(crate) start: Vec<f64>,
    pub(crate) center: V3,
    pub(crate) radius: f64,
    pub(crate) dim: usize,
}

/// A random circle (2D or 3D), start on it, and operands for a random circle
/// type, move type and direction that program an arc of that circle.
pub(crate) fn random_arc(rng: &mut ChaCha8Rng) -> RandomArc {
    let dim = if rng.random_bool(0.5) { 2 } else { 3 };
    let radius = 10f64.powf(rng.random_range(-1.5..2.0));
    let mut center = [0.0; 3];
    for c in center.iter_mut().take(dim) {
        *c = rng.random_range(-100.0..100.0);
    }
    let normal = if dim == 2 {
        if rng.random_bool(0.5) { Z } else { NZ }
    } else {
        loop {
            let v = [
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
            ];
            let l = norm(v);
            if l > 0.1 && l < 1.0 {
                break scale(v, 1.0 / l);
            }
        }
    };
    let seed = if dim == 2 { [1.0, 0.0, 0.0] } else { [0.3, -0.5, 0.8] };
    let u = {
        let a = cross(normal, seed);
        let a = if norm(a) < 0.1 {
            cross(normal, [0.0, 1.0, 0.0])
        } else {
            a
        };
        scale(a, 1.0 / norm(a))
    };
    let w = cross(normal, u);
    let at = |phi: f64| add(center, add(scale(u, radius * phi.cos()), scale(w, radius * phi.sin())));
    let theta = rng.random_range(0.05..TAU - 0.05);
    let p0 = at(0.0);
    let p1 = at(theta);
    let via = at(rng.random_range(0.02..theta - 0.02));
    let circle = if dim == 2 {
        rng.random_range(0..4)
    } else {
        [0, 1, 3][rng.random_range(0..3)]
    };
    let full = rng.random_bool(0.2);
    let move_type = rng.random_range(0..2);
    let start: Vec<f64> = p0[..dim].to_vec();
    let rel = |p: V3| -> Vec<f64> {
        (0..dim)
            .map(|i| if move_type == 1 { p[i] - p0[i] } else { p[i] })
            .collect()
    };
    let ccw = normal == Z;
    let (vcr, direction) = match circle {
        0 => (rel(via), if full { 2 } else { 0 }),
        1 | 3 => {
            let v = if circle == 3 {
                (0..dim).map(|i| center[i] - p0[i]).collect()
            } else {
                rel(center)
            };
            let d = if dim == 2 {
                i64::from(ccw)
            } else if theta <= PI {
                0
            } else {
                1
            };
            (v, d + if full { 2 } else { 0 })
        }
        _ => {
            let r = if theta <= PI { radius } else { -radius };
            (vec![r], i64::from(ccw) + if full { 2 } else { 0 })
        }
    };
    let mut inputs = inputs(move_type, &rel(p1), circle, &vcr, direction);
    inputs.common.dynamics.profile = rng.random_range(0..2);
    inputs.common.dynamics.speed = rng.random_range(0.5..50.0);
    inputs.common.dynamics.accel_rate = rng.random_range(5.0..500.0);
    inputs.common.dynamics.decel_rate = rng.random_range(5.0..500.0);
    inputs.common.dynamics.accel_jerk = rng.random_range(10.0..100.0);
    inputs.common.dynamics.decel_jerk = rng.random_range(10.0..100.0);
    RandomArc {
        inputs,
        start,
        center,
        radius,
        dim,
    }
}

/// ≥ 10,000 random arcs over every circle type, move type, direction, 2D and
/// 3D, partial and full: every interpolated point is on the circle (radius
/// within 1e-9) and in its plane, the path ends exactly at the programmed end
/// point, and the path profile keeps the programmed speed, accel/decel and
/// jerk.
#[test]
fn random_arcs_stay_on_the_circle_and_within_limits() {
    let mut rng = ChaCha8Rng::seed_from_u64(0x4343_4d20);
    let systems = [system(2), system(3)];
    let mut per_type = [0usize; 4];
    for case in 0..10_000 {
        let r = random_arc(&mut rng);
        let sys = &systems[r.dim - 2];
        let m = build(sys, &r.start, &r.inputs).unwrap_or_else(|e| panic!("case {case}: {e:?} {:?}", r.inputs));
        per_type[r.inputs.circle_type as usize] += 1;
        let arc = m.path().arc().unwrap();
        assert!(close(arc.center(), r.center), "case {case}");
        let n = arc.normal();
        let (mut p, mut d) = (vec![0.0; r.dim], vec![0.0; r.dim]);
        let length = m.path().length();
        for k in 0..=64 {
            let s = length * f64::from(k) / 64.0;
            m.path().point(s, &mut p, &mut d);
            let q = sub(primary_of(&p, r.dim), arc.center());
            assert!((norm(q) - r.radius).abs() <= 1e-9, "case {case}: radius {}", norm(q));
            assert!(dot(q, n).abs() <= 1e-9, "case {case}: off plane");
            // |dP/ds| = 1: the path length is the arc length.
            assert!((norm(primary_of(&d, r.dim)) - 1.0).abs() < 1e-9);
        }
        m.path().point(length, &mut p, &mut d);
        let expected_end: Vec<f64> = if r.inputs.direction >= 2 {
            r.start.clone()
        } else if r.inputs.common.move_type == 1 {
            r.start
                .iter()
                .zip(&r.inputs.common.position)
                .map(|(a, b)| a + b)
                .collect()
        } else {
            r.inputs.common.position.clone()
        };
        assert_eq!(p, expected_end, "case {case}: end point");
        // Path dynamics: speed, accel/decel, jerk within the programmed limits.
        let limits = *m.limits().unwrap();
        let profile = m.rest_profile();
        let (jmax, amax) = match limits.shape() {
            crate::profile::Shape::SCurve { accel_jerk, decel_jerk } => (
                accel_jerk.max(decel_jerk),
                limits.acceleration().max(limits.deceleration()),
            ),
            crate::profile::Shape::Trapezoidal => (0.0, limits.acceleration().max(limits.deceleration())),
        };
        let steps = 100;
        for k in 0..=steps {
            let t = profile.duration_s() * f64::from(k) / f64::from(steps);
            let s = profile.sample(t);
            assert!(s.velocity <= limits.velocity() * (1.0 + 1e-9), "case {case}: speed");
            assert!(s.velocity >= -1e-9, "case {case}: backwards");
            assert!(s.acceleration.abs() <= amax * (1.0 + 1e-9), "case {case}: accel");
            if jmax > 0.0 {
                assert!(s.jerk.abs() <= jmax * (1.0 + 1e-9), "case {case}: jerk");
            }
        }
        assert!((profile.final_state().position - length).abs() <= 1e-12 * (1.0 + length));
    }
    assert!(per_type.iter().all(|&n| n > 1000), "{per_type:?}");
}

/// Arbitrary operand values (NaN, infinities, huge and tiny numbers, codes
/// out of range) never panic: each gives an error or a move whose path and
/// profile are finite.
#[test]
fn arbitrary_operands_give_an_error_or_a_finite_move() {
    let mut rng = ChaCha8Rng::seed_from_u64(0xf422);
    let specials = [
        f64::NAN,
        f64::INFINITY,
        -f64::INFINITY,
        0.0,
        -0.0,
        1e-300,
        -1e-300,
        1e300,
        -1e300,
    ];
    let pick = |rng: &mut ChaCha8Rng| {
        if rng.random_bool(0.2) {
            specials[rng.random_range(0..specials.len())]
        } else {
            rng.random_range(-10.0..10.0)
        }
    };
    let (mut ok, mut err) = (0, 0);
    for _ in 0..20_000 {
        let dim = rng.random_range(2..4);
        let sys = system(dim);
        let start: Vec<f64> = (0..dim).map(|_| rng.random_range(-10.0..10.0)).collect();
        let mut i = inputs(
            rng.random_range(-1..3),
            &(0..dim).map(|_| pick(&mut rng)).collect::<Vec<_>>(),
            rng.random_range(-1..5),
            &(0..rng.random_range(0..4)).map(|_| pick(&mut rng)).collect::<Vec<_>>(),
            rng.random_range(-1..5),
        );
        i.common.dynamics.speed = pick(&mut rng).abs();
        i.common.dynamics.accel_rate = pick(&mut rng).abs();
        i.common.dynamics.decel_rate = pick(&mut rng).abs();
        i.common.dynamics.profile = rng.random_range(0..2);
        i.common.dynamics.accel_jerk = pick(&mut rng);
        i.common.dynamics.decel_jerk = pick(&mut rng);
        i.common.dynamics.speed_units = [0, 1, 4][rng.random_range(0..3)];
        match build(&sys, &start, &i) {
            Ok(m) => {
                ok += 1;
                let l = m.path().length();
                assert!(l.is_finite(), "{i:?}");
                let (mut p, mut d) = (vec![0.0; dim], vec![0.0; dim]);
                for k in 0..=8 {
                    m.path().point(l * f64::from(k) / 8.0, &mut p, &mut d);
                    assert!(p.iter().chain(&d).all(|x| x.is_finite()), "{i:?}");
                }
                let profile = m.rest_profile();
                assert!(profile.duration_s().is_finite() || m.limits().is_none(), "{i:?}");
            }
            Err(_) => err += 1,
        }
    }
    assert!(ok > 100 && err > 100, "{ok} {err}");
}
