//! `twin bench`: the real-time factors of scenes, each run several
//! times in each mode.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use anyhow::{Context, Result};
use twin::run::Twin;
use twin::scene;

use crate::BenchArgs;
use crate::run::Trace;

/// The scenes `twin bench` measures: files as given, folders' `*.toml`
/// files in name order.
fn bench_scenes(given: &[PathBuf]) -> Result<Vec<PathBuf>> {
    let given = if given.is_empty() {
        vec![PathBuf::from("scenes")]
    } else {
        given.to_vec()
    };
    let mut scenes = Vec::new();
    for path in given {
        if path.is_dir() {
            let mut found: Vec<PathBuf> = fs::read_dir(&path)
                .with_context(|| format!("cannot read the folder {}", path.display()))?
                .filter_map(|e| Some(e.ok()?.path()))
                .filter(|p| p.extension().is_some_and(|x| x == "toml"))
                .collect();
            found.sort();
            scenes.extend(found);
        } else {
            scenes.push(path);
        }
    }
    if scenes.is_empty() {
        anyhow::bail!("no scene to measure");
    }
    Ok(scenes)
}

/// Runs `twin` to the end (or to what stops a run), calling `each` after
/// every update; the wall time of it all, s.
fn run_to_end(twin: &mut Twin, mut each: impl FnMut(&Twin)) -> f64 {
    let started = Instant::now();
    for _ in 0..twin.total_updates() {
        twin.step();
        each(twin);
        if twin.stopped() {
            break;
        }
    }
    started.elapsed().as_secs_f64()
}

/// One scene's figures (see `twin bench --help`).
struct BenchRow {
    name: String,
    physics_rtf: f64,
    steps_per_s: f64,
    bare_steps_per_s: Option<f64>,
    kinematic_rtf: f64,
    /// The live collision checks per physics step, µs (scenes with
    /// `[collision]`).
    collision_us: Option<f64>,
    /// The parts world and the sensors per parts step, µs (scenes with a
    /// cell; sensors: with sensors).
    parts_us: Option<f64>,
    sensors_us: Option<f64>,
    /// Shares of the outputs run: program, planner, sweep, physics,
    /// collision, trace, recording, frames.
    split: [f64; 8],
}

fn bench_scene(path: &Path, runs: u32, render: bool) -> Result<BenchRow> {
    let load = |plant: scene::PlantMode| -> Result<Twin> {
        let mut scene = scene::load(path)?;
        scene.plant = plant;
        Ok(Twin::new(scene)?)
    };
    // Physics: one run that records its physics steps for the replay and
    // times the collision checks; then the best of plain runs, as `twin
    // run` runs (recording the steps and timing the stages would add
    // their own cost), each followed by a bare replay, so that both see
    // the machine in the same state.
    let mut twin = load(scene::PlantMode::Physics)?;
    twin.record_for_bench();
    run_to_end(&mut twin, |_| {});
    let replay = twin
        .plant()
        .physics_replay()
        .context("the physics plant records its steps")?;
    let steps = replay.steps() as f64;
    let (mut wall, mut bare) = (f64::INFINITY, f64::INFINITY);
    for _ in 0..runs {
        let mut plain = load(scene::PlantMode::Physics)?;
        wall = wall.min(run_to_end(&mut plain, |_| {}));
        bare = bare.min(replay.run(twin.plant().model())?);
    }
    let simulated = twin.time_s();
    let collision_us = (twin.scene().collision.is_some() && steps > 0.0)
        .then(|| 1e6 * twin.plant().times().unwrap_or_default().collision_s / steps);
    let times = twin.plant().times().unwrap_or_default();
    let parts_steps = twin.plant().material().map(|m| (simulated / m.step_s()).round());
    let parts_us = parts_steps.filter(|n| *n > 0.0).map(|n| 1e6 * times.parts_s / n);
    let sensors_us = parts_steps
        .filter(|n| *n > 0.0 && !twin.plant().sensors().is_empty())
        .map(|n| 1e6 * times.sensors_s / n);
    // The kinematic plant.
    let mut kinematic = f64::INFINITY;
    for _ in 0..runs {
        let mut twin = load(scene::PlantMode::Kinematic)?;
        kinematic = kinematic.min(run_to_end(&mut twin, |_| {}));
    }
    // Once with every output, into a temporary folder.
    let dir = std::env::temp_dir().join(format!("twin-bench-{}", std::process::id()));
    fs::create_dir_all(&dir).with_context(|| format!("cannot create {}", dir.display()))?;
    let mut twin = load(scene::PlantMode::Physics)?;
    twin.record_for_bench();
    let mut trace = Trace::create(&dir.join("bench.csv"), &twin)?;
    let targets = twin::output::RecordingTargets {
        save: Some(dir.join("bench.rrd")),
        ..Default::default()
    };
    // A lean build (no `rerun` feature) measures without a recording.
    let targets = if cfg!(feature = "rerun") {
        targets
    } else {
        twin::output::RecordingTargets::default()
    };
    let mut recording = twin::output::session::Recording::new(&twin, &targets)?;
    let mut frames = twin::output::session::Frames::new(&twin, Some(&dir.join("frames")), render)?;
    let (mut trace_s, mut recording_s, mut frames_s) = (0.0, 0.0, 0.0);
    let mut failed = None;
    let outputs_wall = run_to_end(&mut twin, |twin| {
        let t = Instant::now();
        trace.row(twin);
        let u = Instant::now();
        if let Err(e) = recording.log(twin) {
            failed.get_or_insert(e.to_string());
        }
        let v = Instant::now();
        if let Err(e) = frames.capture(twin) {
            failed.get_or_insert(e.to_string());
        }
        let w = Instant::now();
        trace_s += (u - t).as_secs_f64();
        recording_s += (v - u).as_secs_f64();
        frames_s += (w - v).as_secs_f64();
    });
    let t = Instant::now();
    let finished = recording.finish(&twin);
    let recording_end_s = t.elapsed().as_secs_f64();
    let t = Instant::now();
    trace.finish()?;
    let trace_end_s = t.elapsed().as_secs_f64();
    recording_s += recording_end_s;
    trace_s += trace_end_s;
    let _ = fs::remove_dir_all(&dir);
    if let Some(e) = failed.or_else(|| finished.failures.first().map(ToString::to_string)) {
        anyhow::bail!("{}: an output failed while measuring: {e}", path.display());
    }
    let total = outputs_wall + recording_end_s + trace_end_s;
    let stages = twin.stage_times().unwrap_or_default();
    let plant = twin.plant().times().unwrap_or_default();
    let share = |x: f64| if total > 0.0 { x / total } else { 0.0 };
    Ok(BenchRow {
        name: path
            .file_stem()
            .map_or_else(String::new, |s| s.to_string_lossy().into_owned()),
        physics_rtf: simulated / wall,
        steps_per_s: steps / wall,
        bare_steps_per_s: (steps > 0.0).then(|| steps / bare),
        kinematic_rtf: simulated / kinematic,
        collision_us,
        parts_us,
        sensors_us,
        split: [
            share(stages.program_s),
            share(stages.planner_s),
            share(stages.sweep_s),
            share(plant.physics_s),
            share(plant.collision_s),
            share(trace_s),
            share(recording_s),
            share(frames_s),
        ],
    })
}

pub(crate) fn bench(args: &BenchArgs) -> Result<ExitCode> {
    let scenes = bench_scenes(&args.scenes)?;
    outln!(
        "| scene | physics xRT | steps/s | bare steps/s | twin/bare | kinematic xRT | collision µs | parts µs | sensors µs | program | planner | sweep | physics | collision | trace | recording | frames |"
    );
    outln!(
        "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |"
    );
    for path in &scenes {
        let row = bench_scene(path, args.runs, !args.no_render)?;
        let (bare, ratio) = match row.bare_steps_per_s {
            Some(b) => (format!("{b:.0}"), format!("{:.2}", b / row.steps_per_s)),
            None => ("-".to_string(), "-".to_string()),
        };
        let split: Vec<String> = row.split.iter().map(|x| format!("{:.0} %", 100.0 * x)).collect();
        let collision = row.collision_us.map_or_else(|| "-".to_string(), |c| format!("{c:.2}"));
        let parts = row.parts_us.map_or_else(|| "-".to_string(), |c| format!("{c:.1}"));
        let sensors = row.sensors_us.map_or_else(|| "-".to_string(), |c| format!("{c:.1}"));
        outln!(
            "| {} | {:.1} | {:.0} | {bare} | {ratio} | {:.0} | {collision} | {parts} | {sensors} | {} |",
            row.name,
            row.physics_rtf,
            row.steps_per_s,
            row.kinematic_rtf,
            split.join(" | ")
        );
    }
    Ok(ExitCode::SUCCESS)
}
