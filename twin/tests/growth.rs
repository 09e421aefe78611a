//! Work that grows with an input's size grows linearly (issue 39): each
//! input is generated at n and 10 n, and the bytes allocated while it
//! loads (and runs, below) may grow at most 12 times. Counted by this
//! test binary's allocator, not timed.
//!
//! One test function measures every input in turn, so that no other test
//! of this binary allocates meanwhile.

use stats_alloc::{INSTRUMENTED_SYSTEM, Region, StatsAlloc};
use std::alloc::System;

mod common;

#[global_allocator]
static GLOBAL: &StatsAlloc<System> = &INSTRUMENTED_SYSTEM;

/// Bytes allocated while `f` runs.
fn allocated(f: impl FnOnce()) -> u64 {
    let region = Region::new(GLOBAL);
    f();
    let change = region.change();
    (change.bytes_allocated + change.bytes_reallocated.max(0) as usize) as u64
}

/// A scene on the chain of `n` links, its first joint an axis, one
/// coarse update long.
fn chain_scene(name: &str, n: usize) -> std::path::PathBuf {
    let dir = common::fresh_dir("growth", name);
    std::fs::write(dir.join("chain.urdf"), common::chain_urdf(n)).expect("urdf");
    let path = dir.join("chain.toml");
    std::fs::write(
        &path,
        "name = \"chain\"\nduration_s = 0.004\ncoarse_update_ms = 4.0\nphysics_step_ms = 1.0\n\
         [robot]\nurdf = \"chain.urdf\"\n\
         [[axes]]\nname = \"J1\"\njoint = \"j1\"\nkind = \"rotary\"\nunits = \"rad\"\n\
         max_velocity = 1.0\nmax_acceleration = 10.0\nmax_deceleration = 10.0\nmax_jerk = 100.0\n\
         in_position_window = 0.01\nmotor = { stiffness = 1000.0, damping = 60.0 }\n",
    )
    .expect("scene");
    path
}

/// A scene of `n` DINT tags and a periodic task of `n` programs, each
/// with the same main routine.
fn tags_scene(name: &str, n: usize) -> std::path::PathBuf {
    let dir = common::fresh_dir("growth", name);
    std::fs::write(dir.join("Main.st"), "T0 := T0 + 1;\n").expect("routine");
    let urdf = common::root().join("twin/tests/fixtures/robots/indexing_table.urdf");
    let mut s = format!(
        "name = \"tags\"\nduration_s = 0.004\ncoarse_update_ms = 4.0\nphysics_step_ms = 1.0\n[robot]\nurdf = {urdf:?}\n"
    );
    for i in 0..n {
        s.push_str(&format!("[[tags]]\nname = \"T{i}\"\ntype = \"DINT\"\n"));
    }
    s.push_str("[[tasks]]\nname = \"Cyclic\"\nperiod_ms = 4.0\npriority = 5\n");
    for i in 0..n {
        s.push_str(&format!("[[tasks.programs]]\nname = \"P{i}\"\nmain = \"Main.st\"\n"));
    }
    let path = dir.join("tags.toml");
    std::fs::write(&path, s).expect("scene");
    path
}

/// Loads `scene` and builds its twin; with `step`, runs one update.
fn load(scene: &std::path::Path, step: bool) {
    let s = twin::scene::load(scene).unwrap_or_else(|e| panic!("{e}"));
    let mut t = twin::run::Twin::new(s).unwrap_or_else(|e| panic!("{e:#}"));
    if step {
        t.step();
    }
}

/// The links of a URDF are measured loading (the URDF read and checked,
/// the plant built): rapier's multibody steps in work that grows with
/// links × joints, which [`twin::plant::urdf::checks::MAX_LINKS`] bounds.
/// Tags and programs are measured loading and running an update.
#[test]
fn work_grows_linearly_with_links_tags_and_programs() {
    type Make = Box<dyn Fn(&str, usize) -> std::path::PathBuf>;
    let inputs: [(&str, Make, usize, bool); 2] = [
        ("URDF links", Box::new(chain_scene), 20, false),
        ("tags and programs", Box::new(tags_scene), 100, true),
    ];
    for (what, make, n, step) in inputs {
        let small = make(&format!("{what}-small").replace(' ', "_"), n);
        let large = make(&format!("{what}-large").replace(' ', "_"), 10 * n);
        // Once before measuring: lazily built tables are not the input's.
        load(&small, step);
        let a = allocated(|| load(&small, step));
        let b = allocated(|| load(&large, step));
        let ratio = b as f64 / a as f64;
        eprintln!("{what}: {n} → {a} bytes, {} → {b} bytes: {ratio:.2}×", 10 * n);
        assert!(
            ratio <= 12.0,
            "{what}: 10× the input allocates {ratio:.1}× ({a} → {b} bytes)"
        );
    }
}
