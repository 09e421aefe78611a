//! MCT kinematics speed: forward and inverse kinematics per geometry, one
//! call each, at a typical working pose (arm solution of that pose).

#![allow(missing_docs)]

use criterion::{Criterion, criterion_group, criterion_main};
use planner::mct::{Geometry, GeometryKind, GeometryParams};
use std::hint::black_box;

fn geometries() -> Vec<(&'static str, Geometry, [f64; 3])> {
    let serial = GeometryParams {
        link_lengths: [0.45, 0.35, 0.0],
        base_offsets: [0.05, 0.02, 0.3],
        end_effector_offsets: [0.03, -0.01, -0.04],
        zero_angles_deg: [10.0, -20.0, 35.0],
    };
    let delta = GeometryParams {
        link_lengths: [0.3, 0.8, 0.0],
        base_offsets: [0.2, 0.0, 0.05],
        end_effector_offsets: [0.05, 0.0, -0.1],
        zero_angles_deg: [0.0; 3],
    };
    let cartesian = GeometryParams {
        base_offsets: [0.5, -0.25, 1.0],
        ..Default::default()
    };
    let g = |kind, params: &GeometryParams, dim| Geometry::new(kind, params, dim).expect("valid geometry");
    vec![
        (
            "cartesian_gantry",
            g(GeometryKind::CartesianGantry, &cartesian, 3),
            [0.1, 0.2, 0.3],
        ),
        (
            "cartesian_hbot",
            g(GeometryKind::CartesianHBot, &cartesian, 3),
            [0.1, 0.2, 0.3],
        ),
        (
            "articulated_independent_3d",
            g(GeometryKind::ArticulatedIndependent, &serial, 3),
            [0.3, 0.4, 0.9],
        ),
        (
            "articulated_independent_2d",
            g(GeometryKind::ArticulatedIndependent, &serial, 2),
            [0.3, 0.9, 0.0],
        ),
        (
            "articulated_dependent_3d",
            g(GeometryKind::ArticulatedDependent, &serial, 3),
            [0.3, 0.4, 1.2],
        ),
        (
            "scara_independent",
            g(GeometryKind::ScaraIndependent, &serial, 2),
            [0.3, 0.9, 0.1],
        ),
        ("delta_3d", g(GeometryKind::Delta3d, &delta, 3), [0.3, 0.5, 0.4]),
        ("delta_2d", g(GeometryKind::Delta2d, &delta, 2), [0.3, 0.5, 0.0]),
        ("scara_delta", g(GeometryKind::ScaraDelta, &delta, 2), [0.3, 0.5, 0.1]),
    ]
}

fn kinematics(c: &mut Criterion) {
    for (name, g, q) in geometries() {
        let x = g.forward(q).expect("reachable pose");
        let solution = g.solution(q).expect("pose has a solution");
        c.bench_function(&format!("forward_{name}"), |b| b.iter(|| g.forward(black_box(q))));
        c.bench_function(&format!("inverse_{name}"), |b| {
            b.iter(|| g.inverse(black_box(x), solution))
        });
    }
}

criterion_group!(benches, kinematics);
criterion_main!(benches);
