//! Collision model, events and sweep against analytic geometry.

use super::monitor::{CollisionEvent, Monitor};
use super::sweep::{MAX_REFINE_SAMPLES, MAX_SWEEP_SAMPLES, PathSampler, SWEEP_TOLERANCE};
use super::*;
use crate::scene::{AllowedPair, Location, MeshApproximation, Obstacle, Preflight, Reaction, Shape};
use nalgebra::{Translation3, UnitQuaternion, Vector3};
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
    assert!((e.deepest.depth_m - 0.01).abs() < 1e-3, "depth {}", e.deepest.depth_m);
    let n = Vector3::from(e.deepest.normal_in_world);
    let angle = n.angle(&-Vector3::x());
    assert!(angle < 1e-3, "normal {n:?}");
    // The point lies between the face and the ball's deepest point.
    assert!(
        (e.deepest.point_in_world[0] - 0.455).abs() < 1e-3,
        "{:?}",
        e.deepest.point_in_world
    );
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
    assert!((e.deepest.depth_m - 0.09).abs() < 1e-9);
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

#[test]
fn a_tool_is_a_body_of_its_own_adjacent_to_its_link_and_its_neighbours() {
    let model = arm();
    let mut s = settings();
    s.tool = Some(crate::scene::Tool {
        name: "gripper".into(),
        link: "l3".into(),
        link_location: Location::default(),
        shape: Shape::Sphere { radius_m: 0.05 },
        position_m: [0.45, 0.0, 0.0],
        rpy_deg: [0.0; 3],
    });
    let post = [obstacle("post", Shape::Sphere { radius_m: 0.05 }, [1.35, 0.0, 0.0])];
    let world = CollisionModel::new(&model, &post, &s).unwrap();
    assert_eq!(world.body_names(), vec!["l1", "l2", "l3", "gripper"]);
    // l1-l3 and l1-gripper; the gripper rides on l3 next to l2.
    assert_eq!(world.self_pairs(), &[(0, 2), (0, 3)]);
    // Straight arm: the tool centre sits at 1.25 m, 0.1 m from the post's.
    let result = world.check(&model.world_from_link(&[0.0, 0.0, 0.0]));
    assert!(result.contacts.is_empty());
    assert!(
        (result.clearance_m[3] - 0.0).abs() < 1e-9,
        "touching: {:?}",
        result.clearance_m
    );
    let result = world.check(
        &model
            .world_from_link(&[0.0, 0.0, 0.0])
            .iter()
            .map(|p| Isometry3::from_parts(Translation3::new(0.01, 0.0, 0.0), UnitQuaternion::identity()) * p)
            .collect::<Vec<_>>(),
    );
    assert_eq!(result.contacts.len(), 1);
    assert_eq!(world.name(result.contacts[0].a), "gripper");
    assert!((result.contacts[0].at.depth_m - 0.01).abs() < 1e-9);
    s.tool.as_mut().unwrap().link = "nope".into();
    assert!(matches!(
        CollisionModel::new(&model, &post, &s),
        Err(CollisionModelError::UnknownToolLink { .. })
    ));
}

/// A U-shaped STL (two 0.1 m prongs 0.3 m apart on a base), as ASCII text.
fn u_shape_stl() -> String {
    let mut mesh = crate::plant::mesh::TriMesh::cuboid([0.5, 0.1, 0.1]);
    for x in [-0.2f32, 0.2] {
        let prong = crate::plant::mesh::TriMesh::cuboid([0.1, 0.1, 0.5]).transformed(&[
            [1.0, 0.0, 0.0, 0.0],
            [0.0, 1.0, 0.0, 0.0],
            [0.0, 0.0, 1.0, 0.0],
            [x, 0.0, 0.3, 1.0],
        ]);
        mesh.append(&prong);
    }
    let mut text = String::from("solid u\n");
    for t in mesh.indices.chunks_exact(3) {
        text.push_str("facet normal 0 0 0\nouter loop\n");
        for &i in t {
            let [x, y, z] = mesh.positions[i as usize];
            text.push_str(&format!("vertex {x} {y} {z}\n"));
        }
        text.push_str("endloop\nendfacet\n");
    }
    text.push_str("endsolid u\n");
    text
}

#[test]
fn convex_decomposition_follows_a_concave_mesh_that_a_hull_fills() {
    let dir = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../target/collision-tests");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("u.stl");
    std::fs::write(&path, u_shape_stl()).unwrap();
    // The ball (radius 0.05, on the slider at x = 0) sits between the prongs.
    let u = [obstacle("u", Shape::Mesh { path, scale: [1.0; 3] }, [0.0, 0.0, -0.4])];
    let model = slider();
    let hull = CollisionModel::new(&model, &u, &settings()).unwrap();
    let pose = model.world_from_link(&[0.0]);
    assert_eq!(hull.check(&pose).contacts.len(), 1, "the hull fills the U");
    let mut s = settings();
    s.meshes = MeshApproximation::ConvexDecomposition;
    let parts = CollisionModel::new(&model, &u, &s).unwrap();
    let result = parts.check(&pose);
    assert!(result.contacts.is_empty(), "{:?}", result.contacts);
    // The ball is 0.1 m from each prong's inner face (x = ±0.15) and 0.2 m
    // above the base; VHACD's hulls may bulge a little.
    assert!(
        result.clearance_m[0] > 0.05 && result.clearance_m[0] < 0.11,
        "{:?}",
        result.clearance_m
    );
}

/// l1 carries a plate and a flange through two fixed joints; l2 turns on
/// the flange, l3 on l2. Every link's box reaches over its neighbours.
fn arm_with_fixed_chain() -> RobotModel {
    let link = |name: &str, length: f64| {
        format!(
            r#"<link name="{name}"><collision><origin xyz="{} 0 0"/><geometry><box size="{} 0.05 0.05"/></geometry></collision></link>"#,
            length / 2.0,
            length + 0.04
        )
    };
    let urdf = format!(
        r#"<robot name="fixed_chain"><link name="base"/>{}{}{}{}{}
        <joint name="j1" type="continuous"><parent link="base"/><child link="l1"/><axis xyz="0 0 1"/></joint>
        <joint name="plate_mount" type="fixed"><parent link="l1"/><child link="plate"/><origin xyz="0.4 0 0"/></joint>
        <joint name="flange_mount" type="fixed"><parent link="plate"/><child link="flange"/><origin xyz="0.02 0 0"/></joint>
        <joint name="j2" type="continuous"><parent link="flange"/><child link="l2"/><origin xyz="0.02 0 0"/><axis xyz="0 0 1"/></joint>
        <joint name="j3" type="continuous"><parent link="l2"/><child link="l3"/><origin xyz="0.4 0 0"/><axis xyz="0 0 1"/></joint>
        </robot>"#,
        link("l1", 0.4),
        link("plate", 0.02),
        link("flange", 0.02),
        link("l2", 0.4),
        link("l3", 0.44),
    );
    RobotModel::from_urdf_str(&urdf, Path::new("fixed_chain.urdf")).unwrap()
}

#[test]
fn links_joined_by_fixed_joints_are_one_rigid_group_for_adjacency() {
    let model = arm_with_fixed_chain();
    let world = CollisionModel::new(&model, &[], &settings()).unwrap();
    assert_eq!(world.body_names(), vec!["l1", "plate", "flange", "l2", "l3"]);
    // {l1, plate, flange} is one group, adjacent to l2 across j2; l3 is
    // adjacent to l2 only.
    assert_eq!(world.self_pairs(), &[(0, 4), (1, 4), (2, 4)]);
    // Straight: every box overlaps its neighbours, none reports.
    let straight = world.check(&model.world_from_link(&[0.0; 5]));
    assert!(straight.contacts.is_empty(), "{:?}", straight.contacts);
    // l2 folded back over the group (j2 = π) is adjacent and still silent;
    // l3 folded back onto l2 lies along the group's links (l1 and the
    // plate and flange at the elbow) and reports.
    let pi = std::f64::consts::PI;
    let q: Vec<f64> = model
        .joints
        .iter()
        .map(|j| match j.name.as_str() {
            "j3" => pi,
            _ => 0.0,
        })
        .collect();
    let folded = world.check(&model.world_from_link(&q));
    let names: Vec<(&str, &str)> = folded
        .contacts
        .iter()
        .map(|c| (world.name(c.a), world.name(c.b)))
        .collect();
    assert!(names.contains(&("l1", "l3")), "{names:?}");
    assert!(names.iter().all(|(_, b)| *b == "l3"), "{names:?}");
}

/// A robot whose one link collides through `<mesh filename="{file}"/>`.
fn mesh_robot(file: &str, urdf_dir: &Path) -> RobotModel {
    let urdf = format!(
        r#"<robot name="m"><link name="base"><collision><geometry><mesh filename="{file}" scale="1 2 1"/></geometry></collision></link></robot>"#
    );
    RobotModel::from_urdf_str(&urdf, &urdf_dir.join("robot.urdf")).unwrap()
}

#[test]
fn a_dae_collision_mesh_gets_the_same_convex_hull_as_the_equivalent_stl() {
    let dir = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../target/collision-tests-dae");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("u.stl"), u_shape_stl()).unwrap();
    // The same U, in millimetres, Y up: the loader must bring it back to
    // metres and Z up for the hulls to agree.
    let mut u = crate::plant::mesh::TriMesh::cuboid([0.5, 0.1, 0.1]);
    for x in [-0.2f32, 0.2] {
        u.append(&crate::plant::mesh::TriMesh::cuboid([0.1, 0.1, 0.5]).transformed(&[
            [1.0, 0.0, 0.0, 0.0],
            [0.0, 1.0, 0.0, 0.0],
            [0.0, 0.0, 1.0, 0.0],
            [x, 0.0, 0.3, 1.0],
        ]));
    }
    // Z-up metres → Y-up millimetres: (x, y, z) → 1000 · (x, z, −y).
    let u_mm_y_up = u.transformed(&[
        [1000.0, 0.0, 0.0, 0.0],
        [0.0, 0.0, -1000.0, 0.0],
        [0.0, 1000.0, 0.0, 0.0],
        [0.0, 0.0, 0.0, 1.0],
    ]);
    let doc = crate::plant::dae::test_docs::collada(
        r#"<unit meter="0.001"/><up_axis>Y_UP</up_axis>"#,
        &[(&u_mm_y_up, [0.0; 3])],
        true,
    );
    std::fs::write(dir.join("u.dae"), doc).unwrap();
    let hull_points = |file: &str| {
        let model = mesh_robot(file, &dir);
        let collision = CollisionModel::new(&model, &[], &settings()).unwrap();
        let shapes = &collision.bodies[0].shapes;
        assert_eq!(shapes.len(), 1);
        let hull = shapes[0].1.as_convex_polyhedron().expect("a convex hull");
        let mut points: Vec<[f64; 3]> = hull.points().iter().map(|p| [p.x, p.y, p.z]).collect();
        points.sort_by(|a, b| a.partial_cmp(b).unwrap());
        points
    };
    let from_stl = hull_points("u.stl");
    let from_dae = hull_points("u.dae");
    assert_eq!(from_stl.len(), 8, "{from_stl:?}");
    assert_eq!(from_stl.len(), from_dae.len());
    for (s, d) in from_stl.iter().zip(&from_dae) {
        assert!(s.iter().zip(d).all(|(a, b)| (a - b).abs() < 1e-6), "{s:?} vs {d:?}");
    }
    // The URDF scale (y doubled) reaches both.
    assert!(from_dae.iter().any(|p| (p[1] - 0.1).abs() < 1e-6));
}

#[test]
fn a_sweep_of_an_absurdly_long_path_ends_within_its_sample_budget() {
    // `Position := 1e30` used to hang the pre-flight: its samples grew
    // with the path's length (and s + step stopped advancing).
    let model = arm();
    let far = [obstacle("far", Shape::Sphere { radius_m: 0.1 }, [0.0, 2.0, 0.0])];
    let world = CollisionModel::new(&model, &far, &settings()).unwrap();
    for end_rad in [1e6, 1e30, f64::MAX] {
        let report = world.sweep(&model, &Turn { end_rad }, 0.001);
        assert!(
            report.samples <= MAX_SWEEP_SAMPLES + MAX_REFINE_SAMPLES + 1,
            "{end_rad}: {} samples",
            report.samples
        );
        assert!(
            report.step_bound >= end_rad / MAX_SWEEP_SAMPLES as f64,
            "{end_rad}: {report:?}"
        );
        assert!(report.collision.is_none());
    }
    // A short path keeps its resolution.
    let report = world.sweep(&model, &Turn { end_rad: 3.0 }, 0.001);
    assert!(report.step_bound < 0.01, "{report:?}");
}

/// Guards the broad phase: the obstacle tree and the warm-started nearest
/// search give exactly the clearances and contacts of checking every pair,
/// over seeded random obstacle fields and arm poses (some touching).
#[test]
fn the_broad_phase_finds_exactly_what_every_pair_finds() {
    use rand::{Rng, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(17);
    let model = arm();
    let mut touching = 0;
    for field in 0..20 {
        let n = rng.random_range(1..80);
        let obstacles: Vec<Obstacle> = (0..n)
            .map(|k| {
                let position = [
                    rng.random_range(-2.0..2.0),
                    rng.random_range(-2.0..2.0),
                    rng.random_range(-0.3..0.3),
                ];
                let shape = match k % 3 {
                    0 => Shape::Box {
                        size_m: [
                            rng.random_range(0.02..0.3),
                            rng.random_range(0.02..0.3),
                            rng.random_range(0.02..0.3),
                        ],
                    },
                    1 => Shape::Sphere {
                        radius_m: rng.random_range(0.01..0.2),
                    },
                    _ => Shape::Cylinder {
                        radius_m: rng.random_range(0.01..0.2),
                        length_m: rng.random_range(0.02..0.4),
                    },
                };
                obstacle(&format!("o{k}"), shape, position)
            })
            .collect();
        let world = CollisionModel::new(&model, &obstacles, &settings()).unwrap();
        for _ in 0..20 {
            let q = [
                rng.random_range(-3.2..3.2),
                rng.random_range(-3.2..3.2),
                rng.random_range(-3.2..3.2),
            ];
            let poses = model.world_from_link(&q);
            let got = world.check(&poses);
            // Every pair, the slow way.
            let shapes = world.placed_bodies(&poses);
            for (b, body) in shapes.bodies().enumerate() {
                let mut clearance = f64::INFINITY;
                let mut contacts = Vec::new();
                for o in 0..obstacles.len() {
                    let obstacle = world.placed_obstacle(o);
                    clearance = clearance.min(CollisionModel::distance_between(body, &obstacle, f64::INFINITY));
                    if let Some((depth, _, _)) = world.contact_between(body, &obstacle) {
                        contacts.push((o, depth));
                    }
                }
                assert_eq!(got.clearance_m[b], clearance, "field {field}, body {b}, q {q:?}");
                let found: Vec<(usize, f64)> = got
                    .contacts
                    .iter()
                    .filter_map(|c| match (c.a, c.b) {
                        (Body::Robot(x), Body::Obstacle(o)) if x == b => Some((o, c.at.depth_m)),
                        _ => None,
                    })
                    .collect();
                assert_eq!(found, contacts, "field {field}, body {b}, q {q:?}");
                touching += contacts.len();
            }
        }
    }
    assert!(touching > 50, "{touching} contacts: the fields must reach the arm");
}

/// Guards the live check's shortcuts: `check_step`, reusing the bodies at
/// rest and skipping casts the start clearance rules out, gives exactly the
/// discrete check and the continuous detection computed afresh, along
/// seeded random walks of the arm (self-collision on) through random
/// obstacle fields where each joint either stands or moves.
#[test]
fn a_live_step_equals_its_check_and_detection_computed_afresh() {
    use rand::{Rng, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(18);
    let model = arm();
    let (mut reused, mut touches, mut still_touching) = (0, 0, 0);
    for _ in 0..10 {
        let obstacles: Vec<Obstacle> = (0..rng.random_range(1..30))
            .map(|k| {
                let position = [rng.random_range(-1.2..1.2), rng.random_range(-1.2..1.2), 0.0];
                let size_m = [rng.random_range(0.02..0.2); 3];
                obstacle(&format!("o{k}"), Shape::Box { size_m }, position)
            })
            .collect();
        let world = CollisionModel::new(&model, &obstacles, &settings()).unwrap();
        let mut q = [
            rng.random_range(-3.2..3.2),
            rng.random_range(-3.2..3.2),
            rng.random_range(-3.2..3.2),
        ];
        let mut from = model.world_from_link(&q);
        let mut checked = world.check(&from);
        for _ in 0..200 {
            for x in &mut q {
                if rng.random_bool(0.5) {
                    *x += rng.random_range(-0.08..0.08);
                }
            }
            let to = model.world_from_link(&q);
            let (got, got_touches) = world.check_step(Some((&from, &checked)), &to);
            let expected = world.check(&to);
            assert_eq!(got, expected, "q {q:?}");
            assert_eq!(got_touches, world.first_touches(&from, &to), "q {q:?}");
            reused += usize::from(from[1] == to[1]);
            touches += got_touches.len();
            // Bodies that touched before and overlap now: their clearance
            // comes from their contacts, not from a distance query.
            still_touching += got
                .contacts
                .iter()
                .filter(|c| c.at.depth_m > CLEAR_OVERLAP_M)
                .filter_map(|c| if let Body::Robot(b) = c.a { Some(b) } else { None })
                .filter(|&b| checked.clearance_m[b] <= 0.0)
                .count();
            (from, checked) = (to, got);
        }
    }
    assert!(
        reused > 300 && touches > 20 && still_touching > 20,
        "{reused} steps with l1 at rest, {touches} touches, {still_touching} bodies still touching"
    );
}

/// The slider's ball moving from x = `from` to `to` (m).
struct Slide {
    from: f64,
    to: f64,
}

impl PathSampler for Slide {
    fn length(&self) -> f64 {
        (self.to - self.from).abs()
    }
    fn joint_positions(&self, s: f64) -> Vec<f64> {
        vec![self.from + s * (self.to - self.from).signum()]
    }
    fn joint_rate_bounds(&self) -> Vec<f64> {
        vec![1.0]
    }
    fn time_s(&self, s: f64) -> f64 {
        s
    }
}

/// Guards against the sweep stepping over a contact shorter than its step
/// (issue 18: a 5 mm step missed a 4 mm contact) and reporting it a whole
/// step late: a 2 mm plate crossed by the 0.1 m ball with steps of 0.5 m is
/// found, at the analytic first contact to within 1e-6 of the path.
#[test]
fn the_sweep_finds_a_contact_shorter_than_its_step_at_the_analytic_parameter() {
    let model = slider();
    let plate = [obstacle(
        "plate",
        Shape::Box {
            size_m: [0.002, 0.4, 0.4],
        },
        [0.3, 0.0, 0.0],
    )];
    let world = CollisionModel::new(&model, &plate, &settings()).unwrap();
    // From x = -0.2 to 0.8: the ball (r 0.05) touches the plate's face at
    // x = 0.299 - 0.05 = 0.249, i.e. s = 0.449 of a 1.0 m path; it is in
    // contact for 0.102 m only, less than the 0.5 m steps.
    let path = Slide { from: -0.2, to: 0.8 };
    let report = world.sweep(&model, &path, 0.5);
    let c = report.collision.expect("the plate is found");
    let analytic = 0.449;
    assert_eq!(report.step_bound, SWEEP_TOLERANCE * 1.0);
    assert!(
        c.parameter >= analytic - 1e-12 && c.parameter <= analytic + report.step_bound + 1e-12,
        "predicted {} analytic {analytic}",
        c.parameter
    );
    assert_eq!((c.a.as_str(), c.b.as_str()), ("ball", "plate"));
    // A near miss at 2 mm is no contact.
    let beside = [obstacle(
        "beside",
        Shape::Box {
            size_m: [0.002, 0.4, 0.4],
        },
        [0.3, 0.252, 0.0],
    )];
    let world = CollisionModel::new(&model, &beside, &settings()).unwrap();
    let report = world.sweep(&model, &path, 0.5);
    assert!(report.collision.is_none(), "{report:?}");
}

/// A ball of radius 0.5 mm on a prismatic joint along world x.
fn small_ball() -> RobotModel {
    let urdf = r#"<robot name="small">
      <link name="base"/>
      <link name="ball"><collision><geometry><sphere radius="0.0005"/></geometry></collision></link>
      <joint name="x" type="prismatic"><parent link="base"/><child link="ball"/><axis xyz="1 0 0"/>
        <limit lower="-1" upper="1" effort="10" velocity="10"/></joint>
    </robot>"#;
    RobotModel::from_urdf_str(urdf, Path::new("small.urdf")).unwrap()
}

/// Runs the live checks of `positions` (one per step of `dt` s, from t =
/// 0) as the plant does: discrete check at each step's end plus the
/// continuous detection over the step.
fn live_events(model: &RobotModel, world: &CollisionModel, dt: f64, positions: &[Vec<f64>]) -> Vec<CollisionEvent> {
    let mut monitor = Monitor::default();
    let mut previous = model.world_from_link(&positions[0]);
    monitor.observe(world, 0.0, &world.check(&previous));
    for (k, q) in positions.iter().enumerate().skip(1) {
        let poses = model.world_from_link(q);
        let t = k as f64 * dt;
        let touches: Vec<(f64, Contact)> = world
            .first_touches(&previous, &poses)
            .into_iter()
            .map(|(tau, c)| (t - dt * (1.0 - tau), c))
            .collect();
        monitor.observe_from(world, t, &world.check(&poses), &touches);
        previous = poses;
    }
    monitor.events().to_vec()
}

/// Guards against tunnelling (issue 18): a 1 mm sphere at 3 m/s crossing
/// a 2 mm plate with 2 ms steps lands in no step inside the 3 mm contact
/// window; the continuous detection reports the contact at its analytic
/// time (the ball's surface reaching the plate's face) to within 1e-4 s,
/// and a 2 mm near miss reports nothing.
#[test]
fn a_small_fast_sphere_cannot_tunnel_through_a_thin_plate() {
    let model = small_ball();
    let plate = [obstacle(
        "plate",
        Shape::Box {
            size_m: [0.002, 0.2, 0.2],
        },
        [0.0, 0.0, 0.0],
    )];
    let world = CollisionModel::new(&model, &plate, &settings()).unwrap();
    let (dt, speed) = (0.002, 3.0);
    let positions: Vec<Vec<f64>> = (0..40).map(|k| vec![-0.05 + speed * dt * k as f64]).collect();
    // No sample inside |x| <= 1.5 mm.
    assert!(positions.iter().all(|q| q[0].abs() > 0.0015));
    let events = live_events(&model, &world, dt, &positions);
    assert_eq!(events.len(), 1, "{events:?}");
    let analytic = (0.05 - 0.0015) / speed;
    assert!(
        (events[0].start_s - analytic).abs() < 1e-4,
        "{} vs {analytic}",
        events[0].start_s
    );
    assert_eq!((events[0].a.as_str(), events[0].b.as_str()), ("ball", "plate"));
    assert!(events[0].end_s.is_some_and(|e| e > events[0].start_s));
    // The normal points from the plate into the ball, against the motion.
    assert!(
        events[0].deepest.normal_in_world[0] < -0.99,
        "{:?}",
        events[0].deepest.normal_in_world
    );
    // 2 mm beside the plate's edge: nothing.
    let beside = [obstacle(
        "plate",
        Shape::Box {
            size_m: [0.002, 0.2, 0.2],
        },
        [0.0, 0.1025, 0.0],
    )];
    let world_beside = CollisionModel::new(&model, &beside, &settings()).unwrap();
    assert!(live_events(&model, &world_beside, dt, &positions).is_empty());
    // Accelerating from rest at 100 m/s²: within a step the motion is taken
    // as uniform, which errs by a·dt²/8 in position, far below 1e-4 s.
    let accel = 100.0;
    let positions: Vec<Vec<f64>> = (0..30)
        .map(|k| {
            let t = dt * k as f64;
            vec![-0.05 + 0.5 * accel * t * t]
        })
        .collect();
    let events = live_events(&model, &world, dt, &positions);
    assert_eq!(events.len(), 1, "{events:?}");
    let analytic = (2.0 * (0.05 - 0.0015) / accel).sqrt();
    assert!(
        (events[0].start_s - analytic).abs() < 1e-4,
        "{} vs {analytic}",
        events[0].start_s
    );
}

/// A thin rotating link sweeping a 2 mm post between two steps whose
/// poses both clear it: found at the analytic angle.
#[test]
fn a_link_sweeping_a_thin_post_between_two_steps_is_found_at_the_analytic_time() {
    let model = arm();
    let (r, post_r, angle) = (0.3_f64, 0.002, 0.25_f64);
    let post = [obstacle(
        "post",
        Shape::Cylinder {
            radius_m: post_r,
            length_m: 0.4,
        },
        [r * angle.cos(), r * angle.sin(), 0.0],
    )];
    let world = CollisionModel::new(&model, &post, &settings()).unwrap();
    // One 10 ms step turns the arm from 0 to 0.5 rad: both ends clear.
    let dt = 0.01;
    let positions = vec![vec![0.0, 0.0, 0.0], vec![0.5, 0.0, 0.0]];
    for q in &positions {
        assert!(world.check(&model.world_from_link(q)).contacts.is_empty());
    }
    let events = live_events(&model, &world, dt, &positions);
    assert_eq!(events.len(), 1, "{events:?}");
    // The link's face (half width 25 mm) reaches the post's surface.
    let touch = angle - ((0.025 + post_r) / r).asin();
    let analytic = dt * touch / 0.5;
    assert!(
        (events[0].start_s - analytic).abs() < 1e-4,
        "{} vs {analytic}",
        events[0].start_s
    );
    assert_eq!((events[0].a.as_str(), events[0].b.as_str()), ("l1", "post"));
}
