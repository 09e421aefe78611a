//! Collision-checking speed: one live check (every physics step) of a
//! 6-link arm against 10, 20 and 400 obstacles, and the pre-flight sweep
//! of one arc.
//!
//! Run with `cargo bench -p twin --profile dev --bench collision` (the
//! dependencies, parry included, are optimised in the dev profile).

#![allow(missing_docs)]

use criterion::{Criterion, criterion_group, criterion_main};
use std::fmt::Write as _;
use std::hint::black_box;
use std::path::{Path, PathBuf};
use twin::plant::collision::CollisionModel;
use twin::plant::collision::sweep::PathSampler;
use twin::plant::urdf::RobotModel;

const LINKS: usize = 6;
const LINK_M: f64 = 0.25;

/// A 6-link serial arm: alternating z and y revolute joints, each link a
/// 0.25 m box with a sphere at its end (two collision shapes per link).
fn urdf() -> String {
    let mut s = String::from(
        "<robot name=\"arm6\"><link name=\"base\"><collision><origin xyz=\"0 0 0.1\"/><geometry><cylinder radius=\"0.1\" length=\"0.2\"/></geometry></collision></link>",
    );
    for i in 1..=LINKS {
        let _ = writeln!(
            s,
            "<link name=\"l{i}\"><collision><origin xyz=\"{h} 0 0\"/><geometry><box size=\"{LINK_M} 0.06 0.06\"/></geometry></collision>\
             <collision><origin xyz=\"{LINK_M} 0 0\"/><geometry><sphere radius=\"0.04\"/></geometry></collision></link>",
            h = LINK_M / 2.0
        );
        let parent = if i == 1 {
            "base".to_string()
        } else {
            format!("l{}", i - 1)
        };
        let (origin, axis) = if i == 1 {
            ("0 0 0.2", "0 0 1")
        } else if i % 2 == 0 {
            ("0.25 0 0", "0 1 0")
        } else {
            ("0.25 0 0", "0 0 1")
        };
        let _ = writeln!(
            s,
            "<joint name=\"j{i}\" type=\"continuous\"><parent link=\"{parent}\"/><child link=\"l{i}\"/><origin xyz=\"{origin}\"/><axis xyz=\"{axis}\"/></joint>"
        );
    }
    s.push_str("</robot>\n");
    s
}

/// `n` obstacles (boxes, cylinders, spheres) outside the arm's reach at the
/// benchmark pose, so every pair is a distance query and none a contact:
/// the first 10 on a ring of radius 1.9 m (the ones near the arm, the same
/// in every case), the others on rings of 20 from 2.6 m outward, every
/// 0.4 m.
fn scene_text(n: usize) -> String {
    let mut s = String::from(
        "duration_s = 1.0\ncoarse_update_ms = 4.0\nphysics_step_ms = 2.0\n[robot]\nurdf = \"arm6.urdf\"\n[collision]\n",
    );
    for k in 0..n {
        let (a, r) = if k < 10 {
            (k as f64 * std::f64::consts::TAU / 10.0, 1.9)
        } else {
            let j = k - 10;
            (
                (j % 20) as f64 * std::f64::consts::TAU / 20.0,
                2.6 + 0.4 * (j / 20) as f64,
            )
        };
        let (x, y) = (r * a.cos(), r * a.sin());
        let shape = match k % 3 {
            0 => "shape = \"box\"\nsize = [0.2, 0.2, 0.6]".to_string(),
            1 => "shape = \"cylinder\"\nradius = 0.1\nlength = 0.6".to_string(),
            _ => "shape = \"sphere\"\nradius = 0.15".to_string(),
        };
        let _ = write!(
            s,
            "[[obstacles]]\nname = \"o{k}\"\n{shape}\nposition = [{x}, {y}, 0.3]\n"
        );
    }
    s
}

fn setup(obstacles: usize) -> (RobotModel, CollisionModel) {
    let dir: PathBuf = Path::new(env!("CARGO_MANIFEST_DIR")).join("../target/bench-collision");
    std::fs::create_dir_all(&dir).expect("bench dir");
    let urdf_path = dir.join("arm6.urdf");
    std::fs::write(&urdf_path, urdf()).expect("write urdf");
    let model = RobotModel::load(&urdf_path).expect("urdf");
    let scene = twin::scene::parse(&dir.join("bench.toml"), &scene_text(obstacles)).expect("scene");
    let settings = scene.collision.clone().expect("[collision]");
    let world = CollisionModel::new(&model, &scene.obstacles, &settings).expect("collision model");
    (model, world)
}

/// Joint 1 turning a full arc of `end_rad` with the arm bent.
struct Arc {
    end_rad: f64,
}

impl PathSampler for Arc {
    fn length(&self) -> f64 {
        self.end_rad
    }
    fn joint_positions(&self, s: f64) -> Vec<f64> {
        vec![s, 0.3, 0.2, -0.4, 0.1, 0.2]
    }
    fn joint_rate_bounds(&self) -> Vec<f64> {
        vec![1.0, 0.0, 0.0, 0.0, 0.0, 0.0]
    }
    fn time_s(&self, s: f64) -> f64 {
        s
    }
}

fn collision(c: &mut Criterion) {
    let q = [0.4, 0.3, 0.2, -0.4, 0.1, 0.2];
    // The broad phase: the cost of a check grows with the obstacles near
    // the arm, not with all of them (issue 17: 400 within 1.5x of 10).
    for n in [10, 20, 400] {
        let (model, world) = setup(n);
        let poses = model.world_from_link(&q);
        assert!(world.check(&poses).contacts.is_empty());
        c.bench_function(&format!("check_6_links_{n}_obstacles_per_physics_step"), |b| {
            b.iter(|| world.check(black_box(&poses)))
        });
    }
    // The continuous detection over one 1 ms physics step of the arm
    // turning at 1 rad/s per joint, on top of the discrete check.
    {
        let (model, world) = setup(20);
        let from = model.world_from_link(&q);
        let q1: Vec<f64> = q.iter().map(|x| x + 0.001).collect();
        let to = model.world_from_link(&q1);
        c.bench_function(
            "check_and_continuous_detection_6_links_20_obstacles_per_physics_step",
            |b| {
                b.iter(|| {
                    black_box(world.check(black_box(&to)));
                    black_box(world.first_touches(black_box(&from), black_box(&to)))
                })
            },
        );
    }
    let (model, world) = setup(20);
    let arc = Arc {
        end_rad: std::f64::consts::PI,
    };
    let report = world.sweep(&model, &arc, 0.001);
    assert!(report.collision.is_none());
    eprintln!(
        "sweep of one 180 deg arc: {} samples, bound {:.2e} rad",
        report.samples, report.step_bound
    );
    c.bench_function("preflight_sweep_one_180deg_arc_6_links_20_obstacles", |b| {
        b.iter(|| world.sweep(&model, black_box(&arc), 0.001))
    });
}

criterion_group!(benches, collision);
criterion_main!(benches);
