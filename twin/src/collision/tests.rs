//! Collision model, events and sweep against analytic geometry.

use super::*;
use crate::scene::{AllowedPair, Location, Obstacle, Preflight, Reaction};
use std::path::Path;

fn settings() -> CollisionSettings {
    CollisionSettings {
        reaction: Reaction::Report,
        meshes: MeshApproximation::ConvexHull,
        self_collision: true,
        allowed_pairs: Vec::new(),
        preflight: Preflight::Report,
        sweep_resolution_m: 0.001,
        tool: None,
        location: Location::default(),
    }
}

fn obstacle(name: &str, shape: Shape, position_m: [f64; 3]) -> Obstacle {
    Obstacle {
        name: name.to_string(),
        shape,
        position_m,
        rpy_deg: [0.0; 3],
        color: [0.5; 4],
        location: Location::default(),
    }
}

/// A ball of radius 0.05 m on a prismatic joint along world x.
fn slider() -> RobotModel {
    let urdf = r#"<robot name="slider">
      <link name="base"/>
      <link name="ball"><collision><geometry><sphere radius="0.05"/></geometry></collision></link>
      <joint name="x" type="prismatic"><parent link="base"/><child link="ball"/><axis xyz="1 0 0"/>
        <limit lower="-1" upper="1" effort="10" velocity="1"/></joint>
    </robot>"#;
    RobotModel::from_urdf_str(urdf, Path::new("slider.urdf")).unwrap()
}

/// Three 0.4 m boxes in a row on revolute joints about z; neighbours overlap
/// at the joints.
fn arm() -> RobotModel {
    let link = |name: &str| {
        format!(
            r#"<link name="{name}"><collision><origin xyz="0.2 0 0"/><geometry><box size="0.44 0.05 0.05"/></geometry></collision></link>"#
        )
    };
    let urdf = format!(
        r#"<robot name="arm"><link name="base"/>{}{}{}
        <joint name="j1" type="continuous"><parent link="base"/><child link="l1"/><axis xyz="0 0 1"/></joint>
        <joint name="j2" type="continuous"><parent link="l1"/><child link="l2"/><origin xyz="0.4 0 0"/><axis xyz="0 0 1"/></joint>
        <joint name="j3" type="continuous"><parent link="l2"/><child link="l3"/><origin xyz="0.4 0 0"/><axis xyz="0 0 1"/></joint>
        </robot>"#,
        link("l1"),
        link("l2"),
        link("l3")
    );
    RobotModel::from_urdf_str(&urdf, Path::new("arm.urdf")).unwrap()
}

#[test]
fn sphere_meets_box_at_the_analytic_time_depth_and_normal() {
    let model = slider();
    // Box face at x = 0.45; the ball touches it when its centre is at 0.40.
    let boxes = [obstacle(
        "fixture",
        Shape::Box {
            size_m: [0.1, 0.4, 0.4],
        },
        [0.5, 0.0, 0.0],
    )];
    let world = CollisionModel::new(&model, &boxes, &settings()).unwrap();
    let (speed_mps, dt, rest_m) = (0.1, 0.002, 0.41);
    let mut monitor = Monitor::default();
    for k in 0..=6000 {
        let t = k as f64 * dt;
        let x = (speed_mps * t).min(rest_m);
        let poses = model.world_from_link(&[x]);
        let result = world.check(&poses);
        monitor.observe(&world, t, &result);
        let expected = (0.45 - 0.05 - x).max(0.0);
        assert!((result.clearance_m[0] - expected).abs() < 1e-9, "clearance at {t}");
    }
    let events = monitor.events();
    assert_eq!(events.len(), 1, "{events:?}");
    let e = &events[0];
    let analytic_s = 0.40 / speed_mps;
    assert!((e.start_s - analytic_s).abs() <= dt + 1e-12, "start {}", e.start_s);
    assert_eq!(e.end_s, None);
    assert_eq!((e.a.as_str(), e.b.as_str()), ("ball", "fixture"));
    assert!((e.max_depth_m - 0.01).abs() < 1e-3, "depth {}", e.max_depth_m);
    let n = Vector3::from(e.normal_in_world);
    let angle = n.angle(&-Vector3::x());
    assert!(angle < 1e-3, "normal {n:?}");
    // The point lies between the face and the ball's deepest point.
    assert!((e.point_in_world[0] - 0.455).abs() < 1e-3, "{:?}", e.point_in_world);
}

#[test]
fn the_event_ends_when_the_pair_separates() {
    let model = slider();
    let boxes = [obstacle("ball_stop", Shape::Sphere { radius_m: 0.05 }, [0.3, 0.0, 0.0])];
    let world = CollisionModel::new(&model, &boxes, &settings()).unwrap();
    let mut monitor = Monitor::default();
    for (t, x) in [(0.0, 0.0), (1.0, 0.25), (2.0, 0.29), (3.0, 0.1)] {
        monitor.observe(&world, t, &world.check(&model.world_from_link(&[x])));
    }
    let e = &monitor.events()[0];
    assert_eq!((e.start_s, e.end_s), (1.0, Some(3.0)));
    assert!((e.max_depth_m - 0.09).abs() < 1e-9);
    assert!(monitor.colliding().is_empty());
}

#[test]
fn adjacent_links_and_allowed_pairs_never_report() {
    let model = arm();
    let mut s = settings();
    let world = CollisionModel::new(&model, &[], &s).unwrap();
    // Only l1-l3 is checked (l1-l2 and l2-l3 are adjacent and overlap at the joints).
    assert_eq!(world.self_pairs(), &[(0, 2)]);
    let straight = model.world_from_link(&[0.0, 0.0, 0.0]);
    assert!(world.check(&straight).contacts.is_empty());
    // Folded back: l3 lies on l1.
    let pi = std::f64::consts::PI;
    let folded = model.world_from_link(&[0.0, pi, pi]);
    let contacts = world.check(&folded).contacts;
    assert_eq!(contacts.len(), 1, "{contacts:?}");
    assert_eq!((world.name(contacts[0].a), world.name(contacts[0].b)), ("l1", "l3"));
    s.allowed_pairs.push(AllowedPair {
        a: "l3".into(),
        b: "l1".into(),
        location: Location::default(),
    });
    let world = CollisionModel::new(&model, &[], &s).unwrap();
    assert!(world.check(&folded).contacts.is_empty());
    s.allowed_pairs[0].a = "nope".into();
    assert!(matches!(
        CollisionModel::new(&model, &[], &s),
        Err(CollisionModelError::UnknownPairBody { .. })
    ));
}

/// l1 alone turning about z: the sweep parameter is the joint angle.
struct Turn {
    end_rad: f64,
}

impl PathSampler for Turn {
    fn length(&self) -> f64 {
        self.end_rad
    }
    fn joint_positions(&self, s: f64) -> Vec<f64> {
        vec![s, 0.0, 0.0]
    }
    fn joint_rate_bounds(&self) -> Vec<f64> {
        vec![1.0, 0.0, 0.0]
    }
    fn time_s(&self, s: f64) -> f64 {
        s
    }
}

#[test]
fn sweep_predicts_the_first_contact_within_its_bound_and_misses_nothing() {
    let model = arm();
    // A thin post on the +y axis (x in ±0.01, y in 0.55..0.65): the straight
    // arm turning from +x towards +y first touches the post's corner
    // (0.01, 0.55) with its leading face (offset 0.025 m from its axis).
    let post = [obstacle(
        "post",
        Shape::Box {
            size_m: [0.02, 0.1, 0.5],
        },
        [0.0, 0.6, 0.0],
    )];
    let world = CollisionModel::new(&model, &post, &settings()).unwrap();
    let report = world.sweep(&model, &Turn { end_rad: 3.0 }, 0.001);
    let c = report.collision.clone().expect("predicted");
    // Analytic first contact: the corner c = (0.01, 0.55) reaches the
    // leading face, c · (−sin θ, cos θ) = 0.025.
    let analytic = {
        let (mut lo, mut hi) = (0.0_f64, std::f64::consts::FRAC_PI_2);
        for _ in 0..100 {
            let mid = 0.5 * (lo + hi);
            if 0.55 * mid.cos() - 0.01 * mid.sin() > 0.025 {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        lo
    };
    assert!(
        c.parameter >= analytic - 1e-6 && c.parameter <= analytic + report.step_bound + 1e-9,
        "predicted {} analytic {analytic} bound {}",
        c.parameter,
        report.step_bound
    );
    assert_eq!(
        (c.a.as_str(), c.b.as_str()),
        ("l2", "post"),
        "the post at radius 0.55..0.65 is on l2"
    );
    // A post out of reach: nothing.
    let far = [obstacle("far", Shape::Sphere { radius_m: 0.1 }, [0.0, 2.0, 0.0])];
    let world = CollisionModel::new(&model, &far, &settings()).unwrap();
    assert!(world.sweep(&model, &Turn { end_rad: 3.0 }, 0.001).collision.is_none());
}
