//! MCT instruction: every EXERR, scan semantics, bidirectional following,
//! kept arm solution, re-execution, status bits, and the singularity guard.

use super::*;
use crate::mct::{PositionError, SINGULARITY_MARGIN_RAD};
use transform::stop_travel;

const DT: f64 = 0.004;

fn system(id: u32, axes: &[u32], dimension: usize, geometry: GeometryKind, params: GeometryParams) -> TransformSystem {
    TransformSystem {
        id: SystemId(id),
        in_motion_group: true,
        axes: axes.iter().map(|&a| AxisId(a)).collect(),
        transform_dimension: dimension,
        geometry,
        params,
    }
}

fn cartesian(id: u32, axes: &[u32], dimension: usize) -> TransformSystem {
    system(
        id,
        axes,
        dimension,
        GeometryKind::CartesianGantry,
        GeometryParams::default(),
    )
}

fn scara_params() -> GeometryParams {
    GeometryParams {
        link_lengths: [0.4, 0.3, 0.0],
        base_offsets: [0.0, 0.0, 0.0],
        end_effector_offsets: [0.0, 0.0, 0.0],
        zero_angles_deg: [0.0, 0.0, 0.0],
    }
}

/// Cartesian X, Y, Z (axes 1, 2, 3) → SCARA J1, J2 (axes 11, 12) sharing Z.
fn scara_pair() -> (TransformSystem, TransformSystem) {
    (
        cartesian(1, &[1, 2, 3], 2),
        system(2, &[11, 12, 3], 2, GeometryKind::ScaraIndependent, scara_params()),
    )
}

fn joints3() -> [JointAxis; 3] {
    [JointAxis {
        max_speed: 360.0,
        max_deceleration: 3600.0,
        limits: None,
    }; 3]
}

fn idle(_: AxisId) -> AxisCondition {
    AxisCondition::default()
}

fn request<'a>(
    source: &'a TransformSystem,
    target: &'a TransformSystem,
    joint_axes: &'a [JointAxis],
    joints: Vec3,
) -> MctRequest<'a> {
    MctRequest {
        source,
        target,
        orientation_deg: [0.0; 3],
        translation: [0.0; 3],
        joint_axes,
        joints,
        condition: &idle,
    }
}

fn codes(r: Result<(TransformId, Vec3), MctError>) -> (i32, i32) {
    let e = r.unwrap_err();
    (e.err(), e.exerr())
}

#[test]
fn exerr_1_to_4_and_17_and_operand_errors() {
    let j = joints3();
    let mut t = TransformTable::new();
    let (s, g) = (cartesian(1, &[1, 2, 3], 3), cartesian(2, &[11, 12, 13], 3));
    let ungrouped = TransformSystem {
        in_motion_group: false,
        ..g.clone()
    };
    assert_eq!(codes(t.execute(&request(&s, &ungrouped, &j, [0.0; 3]), None)), (61, 1));
    assert_eq!(codes(t.execute(&request(&s, &s, &j, [0.0; 3]), None)), (61, 2));
    for dimension in [0, 4] {
        let bad = TransformSystem {
            transform_dimension: dimension,
            ..s.clone()
        };
        assert_eq!(
            codes(t.execute(&request(&bad, &g, &j, [0.0; 3]), None)),
            (61, 3),
            "{dimension}"
        );
        let bad = TransformSystem {
            transform_dimension: dimension,
            ..g.clone()
        };
        assert_eq!(
            codes(t.execute(&request(&s, &bad, &j, [0.0; 3]), None)),
            (61, 4),
            "{dimension}"
        );
    }
    let two_axes = cartesian(1, &[1, 2], 3);
    assert_eq!(codes(t.execute(&request(&two_axes, &g, &j, [0.0; 3]), None)), (61, 3));
    let s2 = cartesian(1, &[1, 2, 3], 2);
    assert_eq!(
        t.execute(&request(&s2, &g, &j, [0.0; 3]), None).unwrap_err(),
        MctError::DimensionMismatch {
            source_dimension: 2,
            target_dimension: 3
        }
    );
    assert_eq!(codes(t.execute(&request(&s2, &g, &j, [0.0; 3]), None)), (61, 17));
    let mut r = request(&s, &g, &j, [0.0; 3]);
    r.orientation_deg[1] = f64::NAN;
    assert_eq!(codes(t.execute(&r, None)), (13, 3));
    let mut r = request(&s, &g, &j, [0.0; 3]);
    r.translation[2] = f64::INFINITY;
    assert_eq!(codes(t.execute(&r, None)), (13, 4));
    // A planar transform cannot tilt its plane or move along X3.
    let (ps, pt) = scara_pair();
    let mut r = request(&ps, &pt, &j, [0.0, 90.0, 0.0]);
    r.orientation_deg[0] = 5.0;
    assert_eq!(codes(t.execute(&r, None)), (13, 3));
    let mut r = request(&ps, &pt, &j, [0.0, 90.0, 0.0]);
    r.translation[2] = 0.1;
    assert_eq!(codes(t.execute(&r, None)), (13, 4));
    assert!(t.is_empty());
}

#[test]
fn exerr_5_to_11_between_transforms() {
    let j = joints3();
    let mut t = TransformTable::new();
    let (a, b) = (cartesian(1, &[1, 2, 3], 3), cartesian(2, &[11, 12, 13], 3));
    t.execute(&request(&a, &b, &j, [0.0; 3]), None).unwrap();
    // 5: A is already a source.
    let c = cartesian(3, &[21, 22, 23], 3);
    assert_eq!(codes(t.execute(&request(&a, &c, &j, [0.0; 3]), None)), (61, 5));
    // 6: B is already a target.
    assert_eq!(codes(t.execute(&request(&c, &b, &j, [0.0; 3]), None)), (61, 6));
    // 7: a source axis of A→B used as a source axis again.
    let d = cartesian(4, &[31, 2, 33], 3);
    assert_eq!(
        t.execute(&request(&d, &c, &j, [0.0; 3]), None).unwrap_err(),
        MctError::AxisInUse { axis: AxisId(2) }
    );
    // A chain B→C is allowed (B's axes are a target of one, a source of the other) …
    t.execute(&request(&b, &c, &j, [0.0; 3]), None).unwrap();
    // … 8: but C→A closes the loop.
    assert_eq!(codes(t.execute(&request(&c, &a, &j, [0.0; 3]), None)), (61, 8));
    // 9: an axis in both systems.
    let e = cartesian(5, &[41, 42, 43], 3);
    let f = cartesian(6, &[51, 42, 53], 3);
    assert_eq!(
        t.execute(&request(&e, &f, &j, [0.0; 3]), None).unwrap_err(),
        MctError::SharedAxis { axis: AxisId(42) }
    );
    // 13, 14, 10: axis conditions, in that order.
    let g = cartesian(7, &[61, 62, 63], 3);
    let all_bad = |a: AxisId| AxisCondition {
        shutdown: a == AxisId(62),
        inhibited: a == AxisId(61),
        motion_process: a == AxisId(41),
    };
    let mut r = request(&e, &g, &j, [0.0; 3]);
    r.condition = &all_bad;
    assert_eq!(
        t.execute(&r, None).unwrap_err(),
        MctError::AxisShutdown { axis: AxisId(62) }
    );
    assert_eq!(codes(t.execute(&r, None)), (61, 13));
    let inhibited = |a: AxisId| AxisCondition {
        inhibited: a == AxisId(61),
        motion_process: a == AxisId(41),
        ..Default::default()
    };
    r.condition = &inhibited;
    assert_eq!(codes(t.execute(&r, None)), (61, 14));
    let moving = |a: AxisId| AxisCondition {
        motion_process: a == AxisId(41),
        ..Default::default()
    };
    r.condition = &moving;
    assert_eq!(
        t.execute(&r, None).unwrap_err(),
        MctError::MotionInProcess { axis: AxisId(41) }
    );
    // 11: the table is full after MAX_ACTIVE_TRANSFORMS.
    let mut n = t.len();
    let mut id = 100;
    while n < MAX_ACTIVE_TRANSFORMS {
        let s = cartesian(id, &[id * 10, id * 10 + 1, id * 10 + 2], 3);
        let g = cartesian(id + 1, &[id * 10 + 3, id * 10 + 4, id * 10 + 5], 3);
        t.execute(&request(&s, &g, &j, [0.0; 3]), None).unwrap();
        n += 1;
        id += 2;
    }
    assert_eq!(codes(t.execute(&request(&e, &g, &j, [0.0; 3]), None)), (61, 11));
}

#[test]
fn exerr_12_15_16_from_the_target_geometry() {
    let j = joints3();
    let mut t = TransformTable::new();
    let (s, g) = scara_pair();
    let zero_link = TransformSystem {
        params: GeometryParams {
            link_lengths: [0.4, 0.0, 0.0],
            ..scara_params()
        },
        ..g.clone()
    };
    assert_eq!(codes(t.execute(&request(&s, &zero_link, &j, [0.0; 3]), None)), (61, 12));
    // 16: source dimension 3, or a different third axis.
    let s3 = TransformSystem {
        transform_dimension: 3,
        ..s.clone()
    };
    let g3 = TransformSystem {
        transform_dimension: 3,
        ..g.clone()
    };
    assert_eq!(codes(t.execute(&request(&s3, &g3, &j, [0.0; 3]), None)), (61, 16));
    let other_z = cartesian(1, &[1, 2, 4], 2);
    assert_eq!(codes(t.execute(&request(&other_z, &g, &j, [0.0; 3]), None)), (61, 16));
    let scara_delta = system(
        2,
        &[11, 12, 3],
        2,
        GeometryKind::ScaraDelta,
        GeometryParams {
            link_lengths: [0.3, 0.5, 0.0],
            ..Default::default()
        },
    );
    let two_axis_source = cartesian(1, &[1, 2], 2);
    assert_eq!(
        codes(t.execute(&request(&two_axis_source, &scara_delta, &j, [0.0; 3]), None)),
        (61, 16)
    );
    // 15: Delta with X1b − X1e < 0, and with L1 + (X1b − X1e) > L2.
    let s3 = cartesian(1, &[1, 2, 3], 3);
    let delta = |base: f64, l1: f64| {
        system(
            2,
            &[11, 12, 13],
            3,
            GeometryKind::Delta3d,
            GeometryParams {
                link_lengths: [l1, 0.8, 0.0],
                base_offsets: [base, 0.0, 0.0],
                end_effector_offsets: [0.05, 0.0, 0.0],
                ..Default::default()
            },
        )
    };
    assert_eq!(
        codes(t.execute(&request(&s3, &delta(0.04, 0.3), &j, [0.0; 3]), None)),
        (61, 15)
    );
    assert_eq!(
        codes(t.execute(&request(&s3, &delta(0.2, 0.7), &j, [0.0; 3]), None)),
        (61, 15)
    );
    // 4: a Delta 3D target of dimension 2.
    let s2 = cartesian(1, &[1, 2, 3], 2);
    let flat = TransformSystem {
        transform_dimension: 2,
        ..delta(0.2, 0.3)
    };
    assert_eq!(codes(t.execute(&request(&s2, &flat, &j, [0.0; 3]), None)), (61, 4));
    assert!(t.is_empty());
}

#[test]
fn err_67_when_the_joints_have_no_transform_position_at_start() {
    let mut t = TransformTable::new();
    let s = cartesian(1, &[1, 2, 3], 3);
    let delta = system(
        2,
        &[11, 12, 13],
        3,
        GeometryKind::Delta3d,
        GeometryParams {
            link_lengths: [0.3, 0.8, 0.0],
            base_offsets: [0.2, 0.0, 0.0],
            end_effector_offsets: [0.05, 0.0, 0.0],
            ..Default::default()
        },
    );
    let j = joints3();
    assert_eq!(
        codes(t.execute(&request(&s, &delta, &j, [180.0, 0.0, 0.0]), None)),
        (67, 0)
    );
    let limited = [JointAxis {
        limits: Some((-10.0, 80.0)),
        ..j[0]
    }; 3];
    assert!(matches!(
        t.execute(&request(&s, &delta, &limited, [20.0, 20.0, 85.0]), None),
        Err(MctError::Position(PositionError::BeyondJointLimit { joint: 2, .. }))
    ));
    assert!(
        t.execute(&request(&s, &delta, &limited, [20.0, 20.0, 20.0]), None)
            .is_ok()
    );
}

#[test]
fn scan_is_transitional_and_sets_the_bits_of_the_spec() {
    let j = joints3();
    let (s, g) = scara_pair();
    let mut t = TransformTable::new();
    let mut mct = Mct::new();
    let r = request(&s, &g, &j, [0.0, 90.0, 0.25]);
    let start = mct.scan(true, &mut t, &r).expect("started");
    let b = mct.bits();
    assert!(b.en && b.dn && b.ip && !b.er, "{b:?}");
    // Source = forward kinematics of the joints: L1 along X1, L2 along X2.
    assert!(
        (start[0] - 0.4).abs() < 1e-15 && (start[1] - 0.3).abs() < 1e-15 && start[2] == 0.25,
        "{start:?}"
    );
    // Rung held true: no second execution.
    assert!(mct.scan(true, &mut t, &r).is_none());
    // Rung false: .EN clears (DN set), the transform keeps running.
    mct.scan(false, &mut t, &r);
    let b = mct.bits();
    assert!(!b.en && b.dn && b.ip, "{b:?}");
    assert!(t.transform_source_status(SystemId(1)) && t.transform_target_status(SystemId(2)));
    for axis in [1, 2, 3, 11, 12] {
        assert!(t.transform_state_status(AxisId(axis)), "{axis}");
    }
    assert!(!t.transform_state_status(AxisId(13)));
    // MCS cancels: .IP off, status bits off, .DN stays.
    mct.cancel(&mut t);
    let b = mct.bits();
    assert!(!b.ip && b.dn, "{b:?}");
    assert!(!t.transform_source_status(SystemId(1)) && !t.transform_target_status(SystemId(2)));
    assert!(!t.transform_state_status(AxisId(11)));
    // Prescan clears everything.
    mct.prescan();
    let b = mct.bits();
    assert!(!b.en && !b.dn && !b.er && !b.ip);
    // An error: .ER with ERR/EXERR; the rung going false clears .EN.
    let bad = TransformSystem {
        in_motion_group: false,
        ..g.clone()
    };
    let r = request(&s, &bad, &j, [0.0, 90.0, 0.0]);
    assert!(mct.scan(true, &mut t, &r).is_none());
    let b = mct.bits();
    assert!(b.en && b.er && !b.dn && (b.err, b.exerr) == (61, 1), "{b:?}");
    mct.scan(false, &mut t, &r);
    assert!(!mct.bits().en);
}

#[test]
fn bidirectional_following_and_controlled_by_transform() {
    let j = joints3();
    let (s, g) = scara_pair();
    let mut t = TransformTable::new();
    let (id, start) = t.execute(&request(&s, &g, &j, [10.0, 60.0, 0.0]), None).unwrap();
    let tr = t.get_mut(id).unwrap();
    // Source moves: joints follow, and FK of the joint command is the source.
    let target = [start[0] - 0.001, start[1] + 0.0005, 0.01];
    let cmd = tr.follow_source(target, DT).unwrap();
    let back = tr.source_of(cmd.positions).unwrap();
    for i in 0..2 {
        assert!((back[i] - target[i]).abs() < 1e-12);
    }
    assert!(t.controlled_by_transform_status(AxisId(11)) && !t.controlled_by_transform_status(AxisId(1)));
    // Joints move: the source follows.
    let tr = t.get_mut(id).unwrap();
    let joints = [cmd.positions[0] + 0.5, cmd.positions[1] - 0.5, 0.01];
    let src = tr.follow_joints(joints, DT).unwrap();
    let expected = tr.source_of(joints).unwrap();
    assert_eq!(src.positions, expected);
    assert!(t.controlled_by_transform_status(AxisId(1)) && !t.controlled_by_transform_status(AxisId(11)));
}

#[test]
fn cartesian_moves_keep_the_arm_solution_and_joint_moves_can_flip_it() {
    let j = joints3();
    let (s, g) = scara_pair();
    let mut t = TransformTable::new();
    // Left arm: negative elbow.
    let (id, start) = t.execute(&request(&s, &g, &j, [80.0, -70.0, 0.0]), None).unwrap();
    let tr = t.get_mut(id).unwrap();
    assert_eq!(tr.solution(), ArmSolution::LEFT_ARM);
    // A straight Cartesian move of 10 cm in X1 keeps the elbow negative.
    let n = 2000;
    for k in 1..=n {
        let x = [start[0] + 0.1 * k as f64 / n as f64, start[1], 0.0];
        let cmd = tr.follow_source(x, DT).unwrap();
        assert!(cmd.positions[1] < 0.0, "{cmd:?}");
    }
    // Moving J2 through 0 (a joint move) flips to the right arm.
    let mut q = tr.joint_command().positions;
    while q[1] < 20.0 {
        q[1] += 1.0;
        tr.follow_joints(q, DT).unwrap();
    }
    assert_eq!(tr.solution(), ArmSolution::RIGHT_ARM);
    let here = tr.source_command().positions;
    let cmd = tr.follow_source([here[0] - 0.0001, here[1], 0.0], DT).unwrap();
    assert!(cmd.positions[1] > 0.0);
}

#[test]
fn re_execution_picks_up_orientation_translation_and_geometry() {
    let j = joints3();
    let (s, g) = scara_pair();
    let mut t = TransformTable::new();
    let mut mct = Mct::new();
    let joints = [30.0, 45.0, 0.1];
    let first = mct.scan(true, &mut t, &request(&s, &g, &j, joints)).unwrap();
    mct.scan(false, &mut t, &request(&s, &g, &j, joints));
    let mut r = request(&s, &g, &j, joints);
    r.orientation_deg = [0.0, 0.0, 90.0];
    r.translation = [0.1, -0.2, 0.0];
    let second = mct.scan(true, &mut t, &r).unwrap();
    // source = R·(target − t), R = Rz(90°): (x, y) → (−y, x).
    let (tx, ty) = (first[0] - 0.1, first[1] + 0.2);
    assert!(
        (second[0] + ty).abs() < 1e-15 && (second[1] - tx).abs() < 1e-15,
        "{first:?} {second:?}"
    );
    assert_eq!(t.len(), 1, "the restart replaces the transform");
    mct.scan(false, &mut t, &r);
    let longer = TransformSystem {
        params: GeometryParams {
            link_lengths: [0.5, 0.3, 0.0],
            ..scara_params()
        },
        ..g.clone()
    };
    let third = mct.scan(true, &mut t, &request(&s, &longer, &j, joints)).unwrap();
    let id = mct.transform().unwrap();
    let expected = t.get(id).unwrap().source_of(joints).unwrap();
    assert_eq!(third, expected);
    assert!((third[0] - first[0] - 0.1 * 30f64.to_radians().cos()).abs() < 1e-15);
}

#[test]
fn re_execution_on_other_systems_replaces_the_link_and_a_failed_one_keeps_it() {
    let j = joints3();
    let (s, g) = scara_pair();
    let (a, b) = (cartesian(5, &[51, 52, 53], 3), cartesian(6, &[61, 62, 63], 3));
    let mut t = TransformTable::new();
    let mut mct = Mct::new();
    mct.scan(true, &mut t, &request(&s, &g, &j, [30.0, 45.0, 0.1])).unwrap();
    mct.scan(false, &mut t, &request(&s, &g, &j, [30.0, 45.0, 0.1]));
    // A failing re-execution (EXERR 1): the running transform stays.
    let ungrouped = TransformSystem {
        in_motion_group: false,
        ..b.clone()
    };
    assert!(mct.scan(true, &mut t, &request(&a, &ungrouped, &j, [0.0; 3])).is_none());
    let bits = mct.bits();
    assert!(bits.er && bits.ip && (bits.err, bits.exerr) == (61, 1), "{bits:?}");
    assert!(t.transform_source_status(SystemId(1)) && mct.transform().is_some());
    mct.scan(false, &mut t, &request(&a, &b, &j, [0.0; 3]));
    // Other systems: the old link ends, the new one runs.
    mct.scan(true, &mut t, &request(&a, &b, &j, [0.0; 3])).unwrap();
    assert_eq!(t.len(), 1);
    assert!(!t.transform_source_status(SystemId(1)) && !t.transform_state_status(AxisId(11)));
    assert!(t.transform_source_status(SystemId(5)) && t.transform_target_status(SystemId(6)));
}

#[test]
fn a_circle_under_mct_stays_on_the_circle_through_the_joint_commands() {
    // The tool point computed by forward kinematics from the joint command
    // positions lies on the programmed circle.
    let j = joints3();
    let (s, g) = scara_pair();
    let mut t = TransformTable::new();
    let (id, start) = t.execute(&request(&s, &g, &j, [20.0, 70.0, 0.0]), None).unwrap();
    let tr = t.get_mut(id).unwrap();
    let (radius, centre) = (0.05, [start[0] - 0.05, start[1]]);
    let n = 2000;
    for k in 0..=n {
        let a = 2.0 * std::f64::consts::PI * k as f64 / n as f64;
        let x = [centre[0] + radius * a.cos(), centre[1] + radius * a.sin(), 0.0];
        let cmd = tr.follow_source(x, DT).unwrap();
        let tool = tr.geometry().forward(cmd.positions.map(f64::to_radians)).unwrap();
        let r = (tool[0] - centre[0]).hypot(tool[1] - centre[1]);
        assert!((r - radius).abs() < 1e-9, "{k}: {r}");
    }
}

#[test]
fn approaching_a_singularity_never_commands_a_joint_above_its_maximum_speed() {
    // A SCARA tool driven radially outward at 0.5 m/s, through full stretch:
    // the transform must stop it before any joint speed exceeds 360°/s.
    let j = joints3();
    let (s, g) = scara_pair();
    for (start_elbow, solution) in [(40.0, ArmSolution::RIGHT_ARM), (-40.0, ArmSolution::LEFT_ARM)] {
        let mut t = TransformTable::new();
        let mut mct = Mct::new();
        let r = request(&s, &g, &j, [0.0, start_elbow, 0.0]);
        let start = mct.scan(true, &mut t, &r).unwrap();
        let id = mct.transform().unwrap();
        let tr = t.get_mut(id).unwrap();
        assert_eq!(tr.solution(), solution);
        let speed = 0.5;
        let mut fault = None;
        let mut k = 0;
        while fault.is_none() {
            k += 1;
            let reach = start[0] + speed * DT * k as f64;
            assert!(reach < 1.0, "never stopped");
            match tr.follow_source([reach, 0.0, 0.0], DT) {
                Ok(cmd) => {
                    for (v, axis) in cmd.velocities.iter().zip(&j) {
                        assert!(v.abs() <= axis.max_speed, "{cmd:?}");
                        assert!(v.is_finite());
                    }
                }
                Err(e) => fault = Some(e),
            }
        }
        let fault = fault.unwrap();
        // The guard is the speed limit, well before the geometric margin.
        assert!(
            matches!(fault, TransformFault::JointSpeed { max: 360.0, .. }),
            "{fault:?}"
        );
        mct.fault(&fault);
        let b = mct.bits();
        assert!(b.er && b.dn && !b.ip && b.err == 67, "{b:?}");
        let elbow = tr.joint_command().positions[1].to_radians().abs();
        assert!(elbow > SINGULARITY_MARGIN_RAD, "{elbow}");
        // Controlled stop: speeds only fall, never above the maximum.
        let mut previous = tr.joint_command().velocities;
        let mut steps = 0;
        loop {
            let (cmd, at_rest) = tr.stop_step(DT);
            for i in 0..3 {
                assert!(cmd.velocities[i].abs() <= previous[i].abs());
                assert!(cmd.velocities[i].abs() <= j[i].max_speed);
            }
            previous = cmd.velocities;
            steps += 1;
            if at_rest {
                break;
            }
            assert!(steps < 1000);
        }
        t.cancel(id);
        assert!(t.is_empty());
    }
}

#[test]
fn a_target_beyond_reach_is_an_error_and_changes_nothing() {
    let j = joints3();
    let (s, g) = scara_pair();
    let mut t = TransformTable::new();
    let (id, _) = t.execute(&request(&s, &g, &j, [0.0, 90.0, 0.0]), None).unwrap();
    let tr = t.get_mut(id).unwrap();
    let before = tr.joint_command();
    assert!(matches!(
        tr.follow_source([0.8, 0.0, 0.0], DT),
        Err(TransformFault::Position(PositionError::OutOfReach { .. }))
    ));
    assert!(matches!(
        tr.follow_source([0.7, 0.0, 0.0], DT),
        Err(TransformFault::Position(PositionError::Singularity { .. }))
    ));
    assert_eq!(tr.joint_command(), before);
}

#[test]
fn revolute_joints_are_unwrapped_to_the_nearest_turn() {
    let j = joints3();
    let (s, g) = scara_pair();
    let mut t = TransformTable::new();
    let (id, start) = t.execute(&request(&s, &g, &j, [719.0, 90.0, 0.0]), None).unwrap();
    let tr = t.get_mut(id).unwrap();
    let cmd = tr.follow_source([start[0], start[1] + 0.001, 0.0], DT).unwrap();
    assert!((cmd.positions[0] - 719.0).abs() < 1.0, "{cmd:?}");
}

#[test]
fn random_straight_moves_never_command_a_joint_above_its_speed_or_nan() {
    // Seeded random straight Cartesian moves at random speeds from random
    // start poses, many of them through or beyond a singularity or out of
    // reach: every joint command is finite and within its axis' speed, and
    // a fault always ends in a controlled stop that reaches rest.
    use rand::{Rng, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(77);
    let cart3 = cartesian(1, &[1, 2, 3], 3);
    let articulated = system(
        2,
        &[11, 12, 13],
        3,
        GeometryKind::ArticulatedIndependent,
        GeometryParams {
            link_lengths: [0.4, 0.35, 0.0],
            base_offsets: [0.05, 0.0, 0.4],
            ..Default::default()
        },
    );
    let delta = system(
        2,
        &[11, 12, 13],
        3,
        GeometryKind::Delta3d,
        GeometryParams {
            link_lengths: [0.3, 0.8, 0.0],
            base_offsets: [0.2, 0.0, 0.0],
            end_effector_offsets: [0.05, 0.0, -0.05],
            ..Default::default()
        },
    );
    let (scara_source, scara_target) = scara_pair();
    let j = joints3();
    let (mut faults, mut completed) = (0, 0);
    for case in 0..600 {
        let (source, target, start): (&TransformSystem, &TransformSystem, Vec3) = match case % 3 {
            0 => (
                &scara_source,
                &scara_target,
                [rng.random_range(-150.0..150.0), rng.random_range(10.0..170.0), 0.0],
            ),
            1 => (
                &cart3,
                &articulated,
                [
                    rng.random_range(-90.0..90.0),
                    rng.random_range(-20.0..80.0),
                    rng.random_range(-150.0..-10.0),
                ],
            ),
            _ => (&cart3, &delta, [0; 3].map(|_| rng.random_range(10.0..60.0))),
        };
        let mut t = TransformTable::new();
        let Ok((id, from)) = t.execute(&request(source, target, &j, start), None) else {
            continue;
        };
        let tr = t.get_mut(id).unwrap();
        let to: Vec3 = [0; 3].map(|_| rng.random_range(-0.8..0.8));
        let to = [
            to[0],
            to[1],
            if target.geometry == GeometryKind::ScaraIndependent {
                0.0
            } else {
                to[2]
            },
        ];
        let speed = rng.random_range(0.05..2.0);
        let length = (0..3).map(|i| (to[i] - from[i]).powi(2)).sum::<f64>().sqrt();
        let steps = ((length / speed / DT).ceil() as usize).max(1);
        let mut fault = None;
        for k in 1..=steps {
            let s = k as f64 / steps as f64;
            let x = [0, 1, 2].map(|i| from[i] + (to[i] - from[i]) * s);
            match tr.follow_source(x, DT) {
                Ok(cmd) => {
                    for ((v, p), axis) in cmd.velocities.iter().zip(cmd.positions).zip(&j) {
                        assert!(v.is_finite() && v.abs() <= axis.max_speed, "case {case}: {cmd:?}");
                        assert!(p.is_finite());
                    }
                }
                Err(e) => {
                    fault = Some(e);
                    break;
                }
            }
        }
        match fault {
            None => completed += 1,
            Some(_) => {
                faults += 1;
                let mut n = 0;
                loop {
                    let (cmd, at_rest) = tr.stop_step(DT);
                    assert!(cmd.velocities.iter().zip(&j).all(|(v, a)| v.abs() <= a.max_speed));
                    n += 1;
                    if at_rest {
                        break;
                    }
                    assert!(n < 10_000, "case {case}: the stop never ends");
                }
            }
        }
    }
    assert!(
        faults > 50 && completed > 50,
        "{faults} faults, {completed} completed moves"
    );
}

#[test]
fn the_predicted_stopping_travel_is_what_the_controlled_stop_travels() {
    use rand::{Rng, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(67);
    for case in 0..2000 {
        let dt = rng.random_range(0.0005..0.02);
        let dv = rng.random_range(0.01..100.0) * dt;
        // Whole multiples of the step are the edge case of the formula.
        let v = if case % 4 == 0 {
            dv * f64::from(rng.random_range(0..50))
        } else {
            rng.random_range(-500.0..500.0)
        };
        let (mut p, mut u) = (0.0, v);
        while u != 0.0 {
            let u1 = if u.abs() <= dv { 0.0 } else { u - dv * u.signum() };
            p += 0.5 * (u + u1) * dt;
            u = u1;
        }
        let predicted = stop_travel(v, dv, dt).copysign(v);
        assert!(
            (p - predicted).abs() <= 1e-9 * (1.0 + p.abs()),
            "v {v} dv {dv} dt {dt}: {p} vs {predicted}"
        );
    }
}

/// MCTP agrees with MCT's own transform on every geometry: forward, the
/// source position MCT starts a transform at from the same joints; inverse
/// (on the arm solution the joints stand in), the joints MCT commands for
/// that position — both within 1e-9 — with an orientation and a
/// translation.
#[test]
fn mctp_agrees_with_mcts_own_transform_on_every_geometry() {
    use rand::{Rng, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(38);
    let j = joints3();
    let cart3 = cartesian(1, &[1, 2, 3], 3);
    let cart2 = cartesian(1, &[1, 2, 3], 2);
    let articulated = GeometryParams {
        link_lengths: [0.4, 0.35, 0.0],
        base_offsets: [0.05, 0.0, 0.4],
        ..Default::default()
    };
    let delta = GeometryParams {
        link_lengths: [0.3, 0.8, 0.0],
        base_offsets: [0.2, 0.0, 0.0],
        end_effector_offsets: [0.05, 0.0, -0.05],
        ..Default::default()
    };
    let scara_delta = GeometryParams {
        link_lengths: [0.3, 0.5, 0.0],
        base_offsets: [0.1, 0.0, 0.0],
        ..Default::default()
    };
    let cases: Vec<(&TransformSystem, TransformSystem, [std::ops::Range<f64>; 3])> = vec![
        (
            &cart3,
            cartesian(2, &[11, 12, 13], 3),
            [-0.5..0.5, -0.5..0.5, -0.5..0.5],
        ),
        (
            &cart2,
            system(
                2,
                &[11, 12, 13],
                2,
                GeometryKind::CartesianHBot,
                GeometryParams::default(),
            ),
            [-0.5..0.5, -0.5..0.5, 0.0..0.0],
        ),
        (
            &cart3,
            system(2, &[11, 12, 13], 3, GeometryKind::ArticulatedIndependent, articulated),
            [-90.0..90.0, -20.0..80.0, -150.0..-10.0],
        ),
        (
            &cart3,
            system(2, &[11, 12, 13], 3, GeometryKind::ArticulatedDependent, articulated),
            [-90.0..90.0, 10.0..80.0, -100.0..-20.0],
        ),
        (
            &cart2,
            system(2, &[11, 12, 3], 2, GeometryKind::ScaraIndependent, scara_params()),
            [-150.0..150.0, 10.0..170.0, 0.0..0.0],
        ),
        (
            &cart3,
            system(2, &[11, 12, 13], 3, GeometryKind::Delta3d, delta),
            [10.0..60.0, 10.0..60.0, 10.0..60.0],
        ),
        (
            &cart2,
            system(2, &[11, 12, 13], 2, GeometryKind::Delta2d, delta),
            [10.0..60.0, 10.0..60.0, 0.0..0.0],
        ),
        (
            &cart2,
            system(2, &[11, 12, 3], 2, GeometryKind::ScaraDelta, scara_delta),
            [40.0..100.0, 80.0..140.0, 0.0..0.0],
        ),
    ];
    for (source, target, ranges) in &cases {
        let three = target.transform_dimension == 3;
        let orientation = if three { [10.0, -5.0, 30.0] } else { [0.0, 0.0, 30.0] };
        let translation = if three { [0.1, -0.05, 0.02] } else { [0.1, -0.05, 0.0] };
        let mut agreed = 0;
        for _ in 0..200 {
            let joints: Vec3 = [0, 1, 2].map(|i| {
                let r = ranges[i].clone();
                if r.is_empty() { r.start } else { rng.random_range(r) }
            });
            let r = MctRequest {
                orientation_deg: orientation,
                translation,
                ..request(source, target, &j, joints)
            };
            let mut table = TransformTable::new();
            let Ok((id, position)) = table.execute(&r, None) else {
                continue;
            };
            let forward = calculate(&r, TransformDirection::Forward, joints).unwrap();
            for i in 0..3 {
                assert!(
                    (forward[i] - position[i]).abs() < 1e-9,
                    "{:?}: {forward:?} vs {position:?}",
                    target.geometry
                );
            }
            let mct_joints = table.get(id).unwrap().joints_of(position).unwrap();
            let inverse = calculate(&r, TransformDirection::Inverse, position).unwrap();
            for i in 0..3 {
                assert!(
                    (inverse[i] - mct_joints[i]).abs() < 1e-9 && (inverse[i] - joints[i]).abs() < 1e-6,
                    "{:?}: {inverse:?} vs MCT {mct_joints:?} from {joints:?}",
                    target.geometry
                );
            }
            agreed += 1;
        }
        assert!(agreed >= 100, "{:?}: only {agreed} starts", target.geometry);
    }
}

#[test]
fn mctp_chooses_a_serial_arm_and_refuses_what_mct_refuses() {
    let (s, g) = scara_pair();
    let j = joints3();
    // Right arm (elbow +60°) now; the left arm reaches the same point with
    // the elbow at −60°.
    let r = request(&s, &g, &j, [0.0, 60.0, 0.0]);
    let x = calculate(&r, TransformDirection::Forward, [0.0, 60.0, 0.0]).unwrap();
    let left = calculate(&r, TransformDirection::InverseLeftArm, x).unwrap();
    let right = calculate(&r, TransformDirection::InverseRightArm, x).unwrap();
    assert!(
        (right[1] - 60.0).abs() < 1e-9 && (left[1] + 60.0).abs() < 1e-9,
        "{left:?} {right:?}"
    );
    let back = calculate(&r, TransformDirection::Forward, left).unwrap();
    assert!((0..3).all(|i| (back[i] - x[i]).abs() < 1e-12));
    // The elbow far round (+100°): the left arm is −100°, not 260°.
    let r = request(&s, &g, &j, [0.0, 100.0, 0.0]);
    let x = calculate(&r, TransformDirection::Forward, [0.0, 100.0, 0.0]).unwrap();
    let left = calculate(&r, TransformDirection::InverseLeftArm, x).unwrap();
    assert!((left[1] + 100.0).abs() < 1e-9, "{left:?}");
    // Out of reach: ERR 67; the same system twice: ERR 61 EXERR 2.
    let far = calculate(&r, TransformDirection::Inverse, [2.0, 0.0, 0.0]).unwrap_err();
    assert_eq!(far.err(), 67);
    let same = calculate(&request(&s, &s, &j, [0.0; 3]), TransformDirection::Forward, [0.0; 3]).unwrap_err();
    assert_eq!((same.err(), same.exerr()), (61, 2));
}
