//! `twin test`: scenes run as tests — each scene and each of its variants
//! a run in a child process of this binary, several at a time, their
//! expectations, exit codes and snapshots checked, with a console report,
//! a JUnit file, failure artifacts and deterministic sharding.
//!
//! A run is a scene file or one of its `[[variants]]`, named
//! `scenes/knife_cut.toml` or `scenes/knife_cut.toml[250 mm]`. A child
//! process per run keeps a crash, a hang (killed at the timeout) or a
//! memory blow-up to that run: the report is still written.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::fs;
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitCode, Stdio};
use std::time::{Duration, Instant};

use anyhow::{Context, Result};
use twin::scene;

use crate::exit;
use crate::run::Refused;

/// `twin test`'s own exit codes (README, "Use it in CI").
mod code {
    /// Every run passed.
    pub const PASSED: u8 = 0;
    /// A run failed or errored.
    pub const FAILED: u8 = 1;
}

#[derive(Debug, clap::Args)]
pub(crate) struct TestArgs {
    /// Scene files, or folders searched recursively for `*.toml` (default: scenes/).
    paths: Vec<PathBuf>,
    /// Runs at a time (default: the available cores).
    #[arg(short = 'j', long = "jobs", value_name = "N", value_parser = clap::value_parser!(u32).range(1..=1024))]
    jobs: Option<u32>,
    /// Wall times of earlier runs (JSON, run name → seconds): read to start
    /// the longest runs first, then updated.
    #[arg(long, value_name = "FILE")]
    durations: Option<PathBuf>,
    /// Kill a run after S seconds of wall time (a scene's `[test]
    /// timeout_s` takes precedence).
    #[arg(long, value_name = "S", default_value_t = 600.0, value_parser = parse_seconds)]
    timeout: f64,
    /// Golden images of the scenes' `[snapshots]`.
    #[arg(long, value_name = "DIR", default_value = "snapshots")]
    snapshots: PathBuf,
    /// Rewrite the golden images from this run's frames.
    #[arg(long)]
    update_snapshots: bool,
    /// Render nothing: snapshots and failure pictures are skipped.
    #[arg(long)]
    no_render: bool,
    /// Write a JUnit XML report to FILE.
    #[arg(long, value_name = "FILE")]
    junit: Option<PathBuf>,
    /// For each failed run, write its camera pictures at the first failing
    /// update, summary, trace and recording under DIR/<run>/.
    #[arg(long, value_name = "DIR")]
    artifacts: Option<PathBuf>,
    /// Run only shard I of N (1-based; runs sorted by name, the k-th to
    /// shard k mod N + 1), or `auto`: from CI_NODE_INDEX/CI_NODE_TOTAL
    /// (GitLab) or JOB_COMPLETION_INDEX (0-based, Kubernetes) with --shards.
    #[arg(long, value_name = "I/N|auto")]
    shard: Option<String>,
    /// With `--shard auto` and JOB_COMPLETION_INDEX: the number of shards.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..))]
    shards: Option<u32>,
    /// Print the runs (of the shard) and run nothing.
    #[arg(long)]
    list: bool,
    /// Run each run N times; a run fails when its traces differ.
    #[arg(long, value_name = "N", default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=100))]
    repeat: u32,
}

fn parse_seconds(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(s) if s > 0.0 && s.is_finite() => Ok(s),
        _ => Err(format!("expected seconds (a positive number), found {text:?}")),
    }
}

/// A shard: 1-based index of a count.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Shard {
    index: u32,
    count: u32,
}

/// `I/N`, `auto` (with the environment `env` gives).
fn parse_shard(text: &str, shards: Option<u32>, env: &dyn Fn(&str) -> Option<String>) -> Result<Shard, String> {
    let number = |name: &str, v: &str| {
        v.trim()
            .parse::<u32>()
            .map_err(|_| format!("{name} = {v:?} is not a whole number"))
    };
    let shard = if text == "auto" {
        if let (Some(i), Some(n)) = (env("CI_NODE_INDEX"), env("CI_NODE_TOTAL")) {
            Shard {
                index: number("CI_NODE_INDEX", &i)?,
                count: number("CI_NODE_TOTAL", &n)?,
            }
        } else if let Some(i) = env("JOB_COMPLETION_INDEX") {
            let Some(count) = shards else {
                return Err("--shard auto with JOB_COMPLETION_INDEX needs --shards N".to_owned());
            };
            Shard {
                index: number("JOB_COMPLETION_INDEX", &i)? + 1,
                count,
            }
        } else {
            return Err(
                "--shard auto: set CI_NODE_INDEX and CI_NODE_TOTAL (GitLab parallel), or JOB_COMPLETION_INDEX with --shards N (a Kubernetes Indexed Job)"
                    .to_owned(),
            );
        }
    } else {
        let Some((i, n)) = text.split_once('/') else {
            return Err(format!("--shard {text}: expected I/N (e.g. 1/3) or auto"));
        };
        Shard {
            index: number("I", i)?,
            count: number("N", n)?,
        }
    };
    if shard.count == 0 || shard.index == 0 || shard.index > shard.count {
        return Err(format!(
            "--shard {}/{}: I must be from 1 to N",
            shard.index, shard.count
        ));
    }
    Ok(shard)
}

/// One run: a scene, or one of its variants.
#[derive(Debug, Clone)]
struct Run {
    /// `scenes/knife_cut.toml[250 mm]`.
    name: String,
    /// The scene file.
    scene: PathBuf,
    /// The variant, if any.
    variant: Option<String>,
    /// What the run is expected to exit with (before expectations).
    exit_code: u8,
    /// Its timeout, s.
    timeout_s: f64,
    /// Simulated duration, s (to order runs without durations).
    duration_s: f64,
    /// The expectations' names, in order (to report one that never ran).
    expectations: Vec<String>,
    /// Snapshot frames and camera names, when the scene has `[snapshots]`.
    snapshots: Option<(String, Vec<String>, Vec<u32>)>,
    /// The scene's plant.
    plant: &'static str,
    /// Why the scene did not load (an errored run).
    load_error: Option<String>,
}

/// What happened to one run.
#[derive(Debug, Clone, Default)]
struct RunResult {
    wall_s: f64,
    /// The run's exit code, if it exited.
    exit: Option<i32>,
    timed_out: bool,
    /// The run's own message when it did not run to a summary.
    error: Option<String>,
    /// Each expectation: name, passed, message, failing time.
    expectations: Vec<(String, bool, String, Option<f64>)>,
    /// The `run` testcase's failure, if any.
    run_failure: Option<String>,
    /// The `snapshots` testcase: Ok(n compared), Err(failures), or skipped.
    snapshots: Option<Snapshots>,
    /// Attachments (failure pictures, trace, summary, recording).
    attachments: Vec<PathBuf>,
    stderr_tail: String,
}

#[derive(Debug, Clone)]
// Without the renderer (the lean build) no frame is compared.
#[cfg_attr(not(feature = "render"), allow(dead_code))]
enum Snapshots {
    Passed(usize),
    Failed(Vec<String>),
    Skipped(String),
}

impl RunResult {
    fn passed(&self) -> bool {
        self.error.is_none()
            && self.run_failure.is_none()
            && self.expectations.iter().all(|e| e.1)
            && !matches!(self.snapshots, Some(Snapshots::Failed(_)))
    }
}

/// Finds the scene files: files as given, folders searched recursively
/// for `*.toml`; sorted by path, each once.
fn discover(paths: &[PathBuf]) -> Result<Vec<PathBuf>> {
    let mut found = Vec::new();
    for p in paths {
        if p.is_dir() {
            walk(p, &mut found).with_context(|| format!("cannot read folder {}", p.display()))?;
        } else if p.is_file() {
            found.push(p.clone());
        } else {
            return Err(Refused(format!("{}: no such file or folder", p.display())).into());
        }
    }
    found.sort();
    found.dedup();
    Ok(found)
}

fn walk(dir: &Path, out: &mut Vec<PathBuf>) -> std::io::Result<()> {
    let mut entries: Vec<_> = fs::read_dir(dir)?.collect::<Result<_, _>>()?;
    entries.sort_by_key(fs::DirEntry::path);
    for e in entries {
        let path = e.path();
        if e.file_type()?.is_dir() {
            walk(&path, out)?;
        } else if path.extension().is_some_and(|x| x == "toml") {
            out.push(path);
        }
    }
    Ok(())
}

/// The runs of the scene files: each scene, then each of its variants; a
/// scene that does not load is one errored run.
fn runs_of(files: &[PathBuf], timeout_s: f64) -> Vec<Run> {
    let mut runs = Vec::new();
    for file in files {
        let name = file.display().to_string();
        match scene::load(file) {
            Ok(s) => {
                let mut add = |s: &scene::Scene, variant: Option<String>| {
                    runs.push(Run {
                        name: match &variant {
                            Some(v) => format!("{name}[{v}]"),
                            None => name.clone(),
                        },
                        scene: file.clone(),
                        variant,
                        exit_code: s.test.exit_code,
                        timeout_s: s.test.timeout_s.unwrap_or(timeout_s),
                        duration_s: s.duration_s,
                        expectations: s.expectations.iter().map(|e| e.name.clone()).collect(),
                        snapshots: s.snapshots.as_ref().filter(|_| !s.cameras.is_empty()).map(|snap| {
                            (
                                s.name.clone(),
                                s.cameras.iter().map(|c| c.name.clone()).collect(),
                                snap.frames.clone(),
                            )
                        }),
                        plant: s.plant.name(),
                        load_error: None,
                    });
                };
                add(&s, None);
                for v in &s.variants {
                    if let Some(with) = s.with_variant(&v.name) {
                        add(&with, Some(v.name.clone()));
                    }
                }
            }
            Err(e) => runs.push(Run {
                name,
                scene: file.clone(),
                variant: None,
                exit_code: 0,
                timeout_s,
                duration_s: 0.0,
                expectations: Vec::new(),
                snapshots: None,
                plant: "",
                load_error: Some(e.to_string()),
            }),
        }
    }
    runs
}

/// The runs of shard `s`: sorted by name, the k-th (from 0) in shard
/// k mod N + 1.
fn shard_runs(mut runs: Vec<Run>, shard: Option<Shard>) -> Vec<Run> {
    runs.sort_by(|a, b| a.name.cmp(&b.name));
    match shard {
        Some(s) => runs
            .into_iter()
            .enumerate()
            .filter(|(k, _)| (*k as u32) % s.count + 1 == s.index)
            .map(|(_, r)| r)
            .collect(),
        None => runs,
    }
}

/// Checks that an output file can be written, before anything runs.
fn check_writable_file(flag: &str, path: &Path) -> Result<()> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        fs::create_dir_all(dir).with_context(|| format!("{flag}: cannot create folder {}", dir.display()))?;
    }
    fs::OpenOptions::new()
        .create(true)
        .append(true)
        .open(path)
        .with_context(|| format!("{flag}: cannot write {}", path.display()))?;
    Ok(())
}

fn check_writable_dir(flag: &str, dir: &Path) -> Result<()> {
    fs::create_dir_all(dir).with_context(|| format!("{flag}: cannot create folder {}", dir.display()))?;
    let probe = dir.join(format!(".twin-test-{}.probe", std::process::id()));
    fs::write(&probe, b"").with_context(|| format!("{flag}: cannot write into {}", dir.display()))?;
    let _ = fs::remove_file(probe);
    Ok(())
}

/// A child running one attempt of a run.
struct Running {
    index: usize,
    attempt: u32,
    child: Child,
    started: Instant,
    deadline: Instant,
    dir: PathBuf,
}

/// The files of attempt `attempt` of run `index` under the work folder.
fn attempt_dir(work: &Path, index: usize, attempt: u32) -> PathBuf {
    work.join(format!("run{index}-{attempt}"))
}

pub(crate) fn test(args: &TestArgs) -> Result<ExitCode> {
    let shard = match &args.shard {
        Some(text) => Some(parse_shard(text, args.shards, &|k| std::env::var(k).ok()).map_err(Refused)?),
        None => None,
    };
    if args.shards.is_some() && args.shard.as_deref() != Some("auto") {
        return Err(Refused("--shards goes with --shard auto".to_owned()).into());
    }
    let paths = if args.paths.is_empty() {
        vec![PathBuf::from("scenes")]
    } else {
        args.paths.clone()
    };
    let files = discover(&paths)?;
    let runs = shard_runs(runs_of(&files, args.timeout), shard);
    if args.list {
        for r in &runs {
            outln!("{}", r.name);
        }
        return Ok(ExitCode::SUCCESS);
    }
    // Outputs that cannot be written stop everything before it runs.
    if let Some(j) = &args.junit {
        check_writable_file("--junit", j)?;
    }
    if let Some(a) = &args.artifacts {
        check_writable_dir("--artifacts", a)?;
    }
    let durations: BTreeMap<String, f64> = args
        .durations
        .as_ref()
        .and_then(|p| fs::read_to_string(p).ok())
        .and_then(|t| serde_json::from_str(&t).ok())
        .unwrap_or_default();
    let work = std::env::temp_dir().join(format!("twin-test-{}", std::process::id()));
    fs::create_dir_all(&work).with_context(|| format!("cannot create {}", work.display()))?;
    let jobs = args.jobs.map_or_else(
        || std::thread::available_parallelism().map_or(1, std::num::NonZero::get),
        |j| j as usize,
    );
    let exe = std::env::current_exe().context("cannot find the twin binary")?;
    let wall = Instant::now();

    // Longest first: the durations file, else the simulated duration.
    let mut order: Vec<usize> = (0..runs.len()).collect();
    order.sort_by(|&a, &b| {
        let key = |r: &Run| durations.get(&r.name).copied().unwrap_or(r.duration_s);
        key(&runs[b]).total_cmp(&key(&runs[a]))
    });
    let mut results: Vec<RunResult> = vec![RunResult::default(); runs.len()];
    let mut queue: std::collections::VecDeque<(usize, u32)> = order
        .iter()
        .flat_map(|&i| (0..args.repeat).map(move |k| (i, k)))
        .collect();
    let mut running: Vec<Running> = Vec::new();
    let render = !args.no_render;
    let mut left: Vec<u32> = vec![args.repeat; runs.len()];
    loop {
        while running.len() < jobs
            && let Some((index, attempt)) = queue.pop_front()
        {
            // A run that errored before it started is reported once.
            if left[index] == 0 {
                continue;
            }
            let run = &runs[index];
            if let Some(e) = &run.load_error {
                results[index].error = Some(e.clone());
                left[index] = 0;
                report_line(&runs[index], &results[index]);
                continue;
            }
            let dir = attempt_dir(&work, index, attempt);
            let _ = fs::create_dir_all(&dir);
            let mut cmd = Command::new(&exe);
            cmd.arg("run").arg(&run.scene);
            if let Some(v) = &run.variant {
                cmd.arg("--variant").arg(v);
            }
            cmd.arg("--summary").arg(dir.join("summary.json"));
            if args.repeat > 1 {
                cmd.arg("--trace").arg(dir.join("trace.csv"));
            }
            if render
                && attempt == 0
                && let Some((_, _, frames)) = &run.snapshots
            {
                let numbers: Vec<String> = frames.iter().map(u32::to_string).collect();
                cmd.arg("--frames")
                    .arg(dir.join("frames"))
                    .arg("--frames-only")
                    .arg(numbers.join(","));
            } else {
                cmd.arg("--no-render");
            }
            cmd.stdin(Stdio::null())
                .stdout(fs::File::create(dir.join("stdout.txt")).map_or_else(|_| Stdio::null(), Stdio::from))
                .stderr(fs::File::create(dir.join("stderr.txt")).map_or_else(|_| Stdio::null(), Stdio::from));
            let started = Instant::now();
            match cmd.spawn() {
                Ok(child) => running.push(Running {
                    index,
                    attempt,
                    child,
                    started,
                    deadline: started + Duration::from_secs_f64(run.timeout_s),
                    dir,
                }),
                Err(e) => {
                    results[index].error = Some(format!("cannot start {}: {e}", exe.display()));
                    left[index] = 0;
                    report_line(&runs[index], &results[index]);
                }
            }
        }
        if running.is_empty() {
            break;
        }
        std::thread::sleep(Duration::from_millis(10));
        let mut k = 0;
        while k < running.len() {
            let r = &mut running[k];
            let status = match r.child.try_wait() {
                Ok(Some(status)) => Some((status.code(), false)),
                Ok(None) if Instant::now() >= r.deadline => {
                    let _ = r.child.kill();
                    let _ = r.child.wait();
                    Some((None, true))
                }
                Ok(None) => None,
                Err(_) => Some((None, false)),
            };
            let Some((exit, timed_out)) = status else {
                k += 1;
                continue;
            };
            let done = running.swap_remove(k);
            let run = &runs[done.index];
            let result = &mut results[done.index];
            let wall_s = done.started.elapsed().as_secs_f64();
            if done.attempt == 0 {
                result.wall_s = wall_s;
                result.exit = exit;
                result.timed_out = timed_out;
                finish_attempt(run, result, &done.dir, args, render);
            }
            left[done.index] -= 1;
            if left[done.index] == 0 {
                if args.repeat > 1 && result.error.is_none() {
                    compare_repeats(result, &work, done.index, args.repeat);
                }
                report_line(run, result);
            }
        }
    }
    let total_wall_s = wall.elapsed().as_secs_f64();

    // Artifacts of the failed runs: re-run each with every output at the
    // first failing update (runs are deterministic).
    if let Some(dir) = &args.artifacts {
        for (run, result) in runs.iter().zip(results.iter_mut()) {
            // A run that did not end by itself (a crash, a timeout) has
            // no first failing update to show.
            if !result.passed() && result.error.is_none() {
                artifacts(&exe, run, result, dir, render);
            }
        }
    }

    // The report.
    let failed: Vec<(&Run, &RunResult)> = runs.iter().zip(&results).filter(|(_, r)| !r.passed()).collect();
    if !failed.is_empty() {
        outln!();
    }
    for (run, result) in &failed {
        outln!("{}:", run.name);
        for line in failure_lines(run, result) {
            outln!("  {line}");
        }
    }
    let passed = runs.len() - failed.len();
    let skipped = results
        .iter()
        .filter(|r| matches!(r.snapshots, Some(Snapshots::Skipped(_))))
        .count();
    let mut last = format!("{passed} passed, {} failed", failed.len());
    if skipped > 0 {
        let _ = write!(last, ", {skipped} skipped");
    }
    let summed: f64 = results.iter().map(|r| r.wall_s).sum();
    outln!(
        "{last} ({} runs in {total_wall_s:.2} s wall; {summed:.2} s of runs)",
        runs.len()
    );

    let mut write_failures = Vec::new();
    if let Some(j) = &args.junit {
        let xml = junit(&runs, &results, total_wall_s);
        if let Err(e) = fs::write(j, xml) {
            write_failures.push(format!("--junit: cannot write {}: {e}", j.display()));
        }
    }
    if let Some(p) = &args.durations {
        let mut all = durations;
        for (run, result) in runs.iter().zip(&results) {
            if result.wall_s > 0.0 {
                all.insert(run.name.clone(), (result.wall_s * 1000.0).round() / 1000.0);
            }
        }
        let text = serde_json::to_string_pretty(&all).unwrap_or_default() + "\n";
        if let Err(e) = fs::write(p, text) {
            write_failures.push(format!("--durations: cannot write {}: {e}", p.display()));
        }
    }
    let _ = fs::remove_dir_all(&work);
    std::io::stdout().flush()?;
    if !write_failures.is_empty() {
        for f in write_failures {
            eprintln!("error: {f}");
        }
        return Ok(ExitCode::from(exit::OUTPUT));
    }
    Ok(ExitCode::from(if failed.is_empty() {
        code::PASSED
    } else {
        code::FAILED
    }))
}

/// The run's line on the console as it ends.
fn report_line(run: &Run, r: &RunResult) {
    let word = if r.error.is_some() {
        "ERROR"
    } else if r.passed() {
        "PASS"
    } else {
        "FAIL"
    };
    let count = run.expectations.len();
    outln!(
        "{word:<5} {}  {count} expectation{}  {:.2} s",
        run.name,
        if count == 1 { "" } else { "s" },
        r.wall_s
    );
    let _ = std::io::stdout().flush();
}

/// Reads what one attempt left: its summary's expectations, its exit code
/// against the expected one, its snapshots.
fn finish_attempt(run: &Run, result: &mut RunResult, dir: &Path, args: &TestArgs, render: bool) {
    let stderr = fs::read_to_string(dir.join("stderr.txt")).unwrap_or_default();
    result.stderr_tail = tail(&stderr, 20);
    if result.timed_out {
        result.error = Some(format!("timed out: killed after {} s of wall time", run.timeout_s));
        return;
    }
    let summary: Option<serde_json::Value> = fs::read_to_string(dir.join("summary.json"))
        .ok()
        .and_then(|t| serde_json::from_str(&t).ok());
    let Some(summary) = summary else {
        let what = match result.exit {
            Some(c) => format!("exit code {c}"),
            None => "killed by a signal".to_owned(),
        };
        let first = stderr
            .lines()
            .find(|l| l.starts_with("error"))
            .or_else(|| stderr.lines().next())
            .unwrap_or("")
            .to_owned();
        result.error = Some(format!("the run ended without a summary ({what}): {first}"));
        return;
    };
    for e in summary["expectations"].as_array().into_iter().flatten() {
        result.expectations.push((
            e["name"].as_str().unwrap_or_default().to_owned(),
            e["passed"].as_bool().unwrap_or(false),
            e["message"].as_str().unwrap_or_default().to_owned(),
            e["time_s"].as_f64(),
        ));
    }
    // Exit code 6 is the expectations'; the run itself then ended with 0.
    let code = result
        .exit
        .map(|c| if c == i32::from(exit::EXPECTATION_FAILED) { 0 } else { c });
    if code != Some(i32::from(run.exit_code)) {
        let first_error = stderr.lines().find(|l| l.starts_with("error")).unwrap_or("");
        result.run_failure = Some(format!(
            "exit code {} where [test] exit_code = {}{}",
            code.map_or("none".to_owned(), |c| c.to_string()),
            run.exit_code,
            if first_error.is_empty() {
                String::new()
            } else {
                format!(": {first_error}")
            }
        ));
    }
    if let Some((scene_name, cameras, frames)) = &run.snapshots {
        result.snapshots = Some(if !render {
            Snapshots::Skipped("--no-render".to_owned())
        } else {
            compare_snapshots(scene_name, cameras, frames, &dir.join("frames"), args, &stderr)
        });
    }
}

/// The last `n` lines of a text.
fn tail(text: &str, n: usize) -> String {
    let lines: Vec<&str> = text.lines().collect();
    lines[lines.len().saturating_sub(n)..].join("\n")
}

/// Compares a run's frames with the golden images (`twin/tests/scenes.rs`
/// names them: `<scene>-<frame>` for the first camera,
/// `<scene>-<camera>-<frame>` for the others).
#[cfg(feature = "render")]
fn compare_snapshots(
    scene_name: &str,
    cameras: &[String],
    frames: &[u32],
    dir: &Path,
    args: &TestArgs,
    stderr: &str,
) -> Snapshots {
    use twin::output::snapshot::{SnapshotPolicy, Tolerance, check_snapshot};
    let first = cameras
        .first()
        .map(|c| dir.join(format!("{c}-{:05}.png", frames.first().copied().unwrap_or(0))));
    if !first.is_some_and(|p| p.exists()) {
        let why = stderr
            .lines()
            .find(|l| l.contains("Vulkan") || l.contains("adapter"))
            .unwrap_or("no frames were rendered");
        return Snapshots::Skipped(why.trim().to_owned());
    }
    let policy = SnapshotPolicy {
        update: args.update_snapshots,
        ci: true,
    };
    let artifacts = args
        .artifacts
        .clone()
        .unwrap_or_else(|| std::env::temp_dir().join("twin-snapshots"));
    let mut failures = Vec::new();
    let mut compared = 0;
    for (i, camera) in cameras.iter().enumerate() {
        for &f in frames {
            let path = dir.join(format!("{camera}-{f:05}.png"));
            let name = if i == 0 {
                format!("{scene_name}-{f}")
            } else {
                format!("{scene_name}-{camera}-{f}")
            };
            match image::open(&path) {
                Ok(img) => {
                    match check_snapshot(
                        &name,
                        &img.to_rgba8(),
                        &args.snapshots,
                        &artifacts,
                        Tolerance::default(),
                        policy,
                    ) {
                        Ok(_) => compared += 1,
                        Err(e) => failures.push(e.to_string()),
                    }
                }
                Err(_) if !path.exists() => failures.push(format!(
                    "snapshot {name}: camera {camera} frame {f} was not rendered (is it past the end of the run?)"
                )),
                Err(e) => failures.push(format!("{}: {e}", path.display())),
            }
        }
    }
    if failures.is_empty() {
        Snapshots::Passed(compared)
    } else {
        Snapshots::Failed(failures)
    }
}

#[cfg(not(feature = "render"))]
fn compare_snapshots(_: &str, _: &[String], _: &[u32], _: &Path, _: &TestArgs, _: &str) -> Snapshots {
    Snapshots::Skipped("twin was built without the `render` feature".to_owned())
}

/// A 64-bit FNV-1a digest, for naming a trace in a message.
fn digest(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, b| {
        (h ^ u64::from(*b)).wrapping_mul(0x0100_0000_01b3)
    })
}

/// `--repeat`: the attempts' traces must be identical.
fn compare_repeats(result: &mut RunResult, work: &Path, index: usize, repeat: u32) {
    let read = |k: u32| fs::read(attempt_dir(work, index, k).join("trace.csv")).unwrap_or_default();
    let first = read(0);
    for k in 1..repeat {
        let other = read(k);
        if digest(&other) == digest(&first) && other == first {
            continue;
        }
        let (a, b) = (String::from_utf8_lossy(&first), String::from_utf8_lossy(&other));
        let header: Vec<&str> = a.lines().next().unwrap_or("").split(',').collect();
        let place = a
            .lines()
            .zip(b.lines())
            .enumerate()
            .find(|(_, (x, y))| x != y)
            .map(|(row, (x, y))| {
                let col = x.split(',').zip(y.split(',')).position(|(p, q)| p != q).unwrap_or(0);
                let (p, q) = (x.split(',').nth(col).unwrap_or(""), y.split(',').nth(col).unwrap_or(""));
                format!(
                    "row {row} (time_s {}), column {}: {p} then {q}",
                    x.split(',').next().unwrap_or(""),
                    header.get(col).unwrap_or(&"?")
                )
            })
            .unwrap_or_else(|| format!("{} rows then {}", a.lines().count(), b.lines().count()));
        result.run_failure = Some(format!(
            "not deterministic: the trace of repeat {} (digest {:016x}) differs from the first ({:016x}) at {place}",
            k + 1,
            digest(&other),
            digest(&first)
        ));
        return;
    }
}

/// Re-runs a failed run with every output, the pictures at its first
/// failing update, into `root/<run>/`.
fn artifacts(exe: &Path, run: &Run, result: &mut RunResult, root: &Path, render: bool) {
    let safe: String = run
        .name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || matches!(c, '.' | '-' | '_') {
                c
            } else {
                '_'
            }
        })
        .collect();
    let dir = root.join(safe.trim_start_matches('.'));
    if fs::create_dir_all(&dir).is_err() {
        return;
    }
    // The earliest failure of any expectation (the end of the run when
    // none has a time: an exit code, a snapshot).
    let at_s = result
        .expectations
        .iter()
        .filter(|e| !e.1)
        .filter_map(|e| e.3)
        .min_by(f64::total_cmp)
        .unwrap_or(run.duration_s);
    let mut cmd = Command::new(exe);
    cmd.arg("run").arg(&run.scene);
    if let Some(v) = &run.variant {
        cmd.arg("--variant").arg(v);
    }
    let (summary, trace, rrd) = (dir.join("summary.json"), dir.join("trace.csv"), dir.join("run.rrd"));
    cmd.arg("--summary").arg(&summary).arg("--trace").arg(&trace);
    if cfg!(feature = "rerun") {
        cmd.arg("--save").arg(&rrd);
    }
    if render {
        cmd.arg("--frames").arg(&dir).arg("--frames-at").arg(format!("{at_s}"));
    } else {
        cmd.arg("--no-render");
    }
    cmd.stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(fs::File::create(dir.join("stderr.txt")).map_or_else(|_| Stdio::null(), Stdio::from));
    // The same time limit as the run itself.
    if let Ok(mut child) = cmd.spawn() {
        let deadline = Instant::now() + Duration::from_secs_f64(run.timeout_s);
        while matches!(child.try_wait(), Ok(None)) {
            if Instant::now() >= deadline {
                let _ = child.kill();
                let _ = child.wait();
                break;
            }
            std::thread::sleep(Duration::from_millis(10));
        }
    }
    let mut files: Vec<PathBuf> = fs::read_dir(&dir)
        .map(|d| d.filter_map(|e| e.ok().map(|e| e.path())).collect())
        .unwrap_or_default();
    files.sort();
    result.attachments = files
        .into_iter()
        .filter(|p| {
            p.extension()
                .is_some_and(|x| x == "png" || x == "json" || x == "csv" || x == "rrd")
        })
        .collect();
}

/// The lines that explain a failed run.
fn failure_lines(run: &Run, r: &RunResult) -> Vec<String> {
    let mut out = Vec::new();
    if let Some(e) = &r.error {
        out.push(e.clone());
    }
    if let Some(f) = &r.run_failure {
        out.push(f.clone());
    }
    for (_, passed, message, _) in &r.expectations {
        if !passed {
            out.push(message.clone());
        }
    }
    if r.error.is_none() && r.expectations.is_empty() && !run.expectations.is_empty() {
        out.push("no expectation was reported".to_owned());
    }
    if let Some(Snapshots::Failed(f)) = &r.snapshots {
        out.extend(f.iter().cloned());
    }
    for a in &r.attachments {
        out.push(format!("attached: {}", a.display()));
    }
    out
}

/// Escapes text for an XML element (line ends kept) or, with `attribute`,
/// for an attribute value (line ends and tabs become spaces: readers
/// differ on character references).
fn escape(text: &str, attribute: bool) -> String {
    let mut s = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => s.push_str("&amp;"),
            '<' => s.push_str("&lt;"),
            '>' => s.push_str("&gt;"),
            '"' => s.push_str("&quot;"),
            '\'' => s.push_str("&apos;"),
            '\n' | '\t' if !attribute => s.push(c),
            '\n' | '\t' | '\r' => s.push(' '),
            // XML 1.0 has no other control characters.
            c if (c as u32) < 0x20 => s.push('?'),
            c => s.push(c),
        }
    }
    s
}

/// [`escape`] for an attribute.
fn xml(text: &str) -> String {
    escape(text, true)
}

/// [`escape`] for an element's text.
fn xml_text(text: &str) -> String {
    escape(text, false)
}

/// The JUnit report: a `<testsuite>` per scene file, its runs' testcases
/// (`run`, each expectation, `snapshots`) with `classname` the run.
fn junit(runs: &[Run], results: &[RunResult], wall_s: f64) -> String {
    struct Case {
        classname: String,
        name: String,
        time_s: f64,
        outcome: Option<(&'static str, String, String)>,
        skipped: Option<String>,
        out: String,
    }
    /// A suite's test cases and properties.
    type Suite = (Vec<Case>, Vec<(String, String)>);
    let mut suites: BTreeMap<&Path, Suite> = BTreeMap::new();
    for (run, r) in runs.iter().zip(results) {
        let (cases, props) = suites.entry(run.scene.as_path()).or_default();
        if props.is_empty() {
            props.push(("twin_version".to_owned(), env!("CARGO_PKG_VERSION").to_owned()));
            if !run.plant.is_empty() {
                props.push(("plant".to_owned(), run.plant.to_owned()));
            }
        }
        if let Some(v) = &run.variant {
            props.push(("variant".to_owned(), v.clone()));
        }
        let attachments: String = r
            .attachments
            .iter()
            .map(|p| format!("[[ATTACHMENT|{}]]\n", p.display()))
            .collect();
        let run_outcome = if let Some(e) = &r.error {
            Some(("error", if r.timed_out { "timeout" } else { "run" }, e.clone()))
        } else {
            r.run_failure.as_ref().map(|f| ("failure", "exit_code", f.clone()))
        };
        cases.push(Case {
            classname: run.name.clone(),
            name: "run".to_owned(),
            time_s: r.wall_s,
            outcome: run_outcome.map(|(k, t, m)| (k, t.to_owned(), m)),
            skipped: None,
            out: if r.error.is_some() || r.run_failure.is_some() {
                format!("{attachments}{}", r.stderr_tail)
            } else {
                String::new()
            },
        });
        if r.error.is_none() {
            for (name, passed, message, _) in &r.expectations {
                cases.push(Case {
                    classname: run.name.clone(),
                    name: name.clone(),
                    time_s: 0.0,
                    outcome: (!passed).then(|| ("failure", "expectation".to_owned(), message.clone())),
                    skipped: None,
                    out: if *passed { String::new() } else { attachments.clone() },
                });
            }
        }
        if let Some(s) = &r.snapshots {
            let (outcome, skipped, out) = match s {
                Snapshots::Passed(n) => (None, None, format!("{n} frames match their golden images")),
                Snapshots::Failed(f) => (
                    Some(("failure", "snapshot".to_owned(), f.join("\n"))),
                    None,
                    String::new(),
                ),
                Snapshots::Skipped(why) => (None, Some(why.clone()), String::new()),
            };
            cases.push(Case {
                classname: run.name.clone(),
                name: "snapshots".to_owned(),
                time_s: 0.0,
                outcome,
                skipped,
                out,
            });
        }
    }
    let count = |cases: &[Case], kind: &str| {
        cases
            .iter()
            .filter(|c| c.outcome.as_ref().is_some_and(|o| o.0 == kind))
            .count()
    };
    let all: Vec<&Case> = suites.values().flat_map(|(c, _)| c).collect();
    let mut s = String::from("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    let _ = writeln!(
        s,
        "<testsuites name=\"twin test\" tests=\"{}\" failures=\"{}\" errors=\"{}\" time=\"{wall_s:.3}\">",
        all.len(),
        all.iter()
            .filter(|c| c.outcome.as_ref().is_some_and(|o| o.0 == "failure"))
            .count(),
        all.iter()
            .filter(|c| c.outcome.as_ref().is_some_and(|o| o.0 == "error"))
            .count(),
    );
    for (file, (cases, props)) in &suites {
        let time: f64 = cases.iter().map(|c| c.time_s).sum();
        let _ = writeln!(
            s,
            "  <testsuite name=\"{}\" tests=\"{}\" failures=\"{}\" errors=\"{}\" skipped=\"{}\" time=\"{time:.3}\" file=\"{}\">",
            xml(&file.display().to_string()),
            cases.len(),
            count(cases, "failure"),
            count(cases, "error"),
            cases.iter().filter(|c| c.skipped.is_some()).count(),
            xml(&file.display().to_string()),
        );
        s.push_str("    <properties>\n");
        for (k, v) in props {
            let _ = writeln!(s, "      <property name=\"{}\" value=\"{}\"/>", xml(k), xml(v));
        }
        s.push_str("    </properties>\n");
        for c in cases {
            let _ = write!(
                s,
                "    <testcase classname=\"{}\" name=\"{}\" time=\"{:.3}\"",
                xml(&c.classname),
                xml(&c.name),
                c.time_s
            );
            if c.outcome.is_none() && c.skipped.is_none() && c.out.is_empty() {
                s.push_str("/>\n");
                continue;
            }
            s.push_str(">\n");
            if let Some((kind, ty, message)) = &c.outcome {
                let _ = writeln!(
                    s,
                    "      <{kind} type=\"{}\" message=\"{}\">{}</{kind}>",
                    xml(ty),
                    xml(message.lines().next().unwrap_or("")),
                    xml_text(message)
                );
            }
            if let Some(why) = &c.skipped {
                let _ = writeln!(s, "      <skipped message=\"{}\"/>", xml(why));
            }
            if !c.out.is_empty() {
                let _ = writeln!(s, "      <system-out>{}</system-out>", xml_text(&c.out));
            }
            s.push_str("    </testcase>\n");
        }
        s.push_str("  </testsuite>\n");
    }
    s.push_str("</testsuites>\n");
    s
}

#[cfg(test)]
mod tests {
    use super::{Shard, parse_shard, xml, xml_text};

    fn no_env(_: &str) -> Option<String> {
        None
    }

    #[test]
    fn shards_are_one_based_and_checked() {
        assert_eq!(parse_shard("2/3", None, &no_env), Ok(Shard { index: 2, count: 3 }));
        for bad in ["0/3", "4/3", "1/0", "x/3", "3"] {
            assert!(parse_shard(bad, None, &no_env).is_err(), "{bad}");
        }
        let gitlab = |k: &str| match k {
            "CI_NODE_INDEX" => Some("3".to_owned()),
            "CI_NODE_TOTAL" => Some("4".to_owned()),
            _ => None,
        };
        assert_eq!(parse_shard("auto", None, &gitlab), Ok(Shard { index: 3, count: 4 }));
        let k8s = |k: &str| (k == "JOB_COMPLETION_INDEX").then(|| "0".to_owned());
        assert_eq!(parse_shard("auto", Some(5), &k8s), Ok(Shard { index: 1, count: 5 }));
        assert!(parse_shard("auto", None, &k8s).is_err());
        assert!(parse_shard("auto", None, &no_env).is_err());
    }

    #[test]
    fn xml_text_is_escaped() {
        assert_eq!(xml("a<b & \"c\"\n"), "a&lt;b &amp; &quot;c&quot; ");
        assert_eq!(xml_text("a\nb\u{1}"), "a\nb?");
    }
}
