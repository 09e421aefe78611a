//! The `twin` command line: runs a scene headless and writes frames, a
//! trace, a summary and a Rerun recording; or checks a scene.

use anyhow::{Context, Result};
use clap::{Parser, Subcommand};
use std::fs;
use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;
use twin::run::Twin;
use twin::scene;

const EXAMPLES: &str = "\
Examples:
  twin run scenes/indexing_table.toml --frames out --save out.rrd --trace out.csv
  twin run scenes/indexing_table.toml --connect            # stream to a Rerun viewer on 127.0.0.1:9876
  twin run scenes/indexing_table.toml --no-render --summary out.json --duration 0.5
  twin run scenes/scara_pick.toml --no-render --plant kinematic   # program test, no dynamics
  twin check scenes/indexing_table.toml

Exit codes:
  0 success; 2 an instruction reported an error; 3 a collision aborted the run;
  4 a major controller fault stopped it; 64 usage error; 65 invalid input
  (scene, routine, URDF, mesh); 74 an output cannot be written or a viewer reached";

/// Exit codes (README, "Errors and exit codes"): 2, 3 and 4 are what a run reports,
/// the others follow sysexits.h.
mod exit {
    /// An instruction reported an error; the run went to its end.
    pub const INSTRUCTION_ERROR: u8 = 2;
    /// A collision with `collision.reaction = "abort"` ended the run.
    pub const COLLISION_ABORT: u8 = 3;
    /// A major controller fault stopped the run.
    pub const MAJOR_FAULT: u8 = 4;
    /// The physics state became non-finite and stopped the run.
    pub const PHYSICS_FAULT: u8 = 5;
    /// Unknown flag or subcommand, a bad flag value, a flag this build lacks.
    pub const USAGE: u8 = 64;
    /// The scene, a routine, the URDF or a mesh is invalid.
    pub const INVALID_INPUT: u8 = 65;
    /// An output cannot be written, or a viewer cannot be reached.
    pub const OUTPUT: u8 = 74;
}

/// Physics-backed digital twin for PLC motion programs.
#[derive(Debug, Parser)]
#[command(name = "twin", version, about, after_help = EXAMPLES)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Run a scene: program → planner → physics, with optional outputs.
    #[command(after_help = EXAMPLES)]
    Run(RunArgs),
    /// Parse and validate a scene (file, URDF, meshes, program) without running it.
    #[command(after_help = "Example:\n  twin check scenes/indexing_table.toml")]
    Check {
        /// Scene file (TOML).
        scene: PathBuf,
    },
    /// Measure scenes: the physics plant against a bare rapier simulation
    /// replaying the same drive commands, the kinematic plant, and where a
    /// run with every output spends its time.
    #[command(after_help = BENCH_HELP)]
    Bench(BenchArgs),
}

const BENCH_HELP: &str = "\
Columns, per scene (best of --runs plain runs; one more run records the
drive commands and times the collision checks; the outputs run once):
  physics xRT     simulated / wall time of the physics plant, no outputs
  steps/s         the twin's physics steps per wall second, no outputs
  bare steps/s    a bare simulation of the same robot (drives, step, substeps)
                  replaying the drive commands the twin gave each step
  twin/bare       how much longer the twin takes than the bare simulation
  kinematic xRT   simulated / wall time of the kinematic plant (--plant kinematic)
  collision µs    the live collision checks (discrete and continuous) per
                  physics step, µs, no outputs (- without [collision])
  then the share of a run with a trace, a recording and frames spent in the
  program, the planner, the pre-flight sweeps, the physics, the live collision
  checks, the trace, the recording and the frames (the rest: bookkeeping).

Example:
  twin bench scenes/ --runs 3";

#[derive(Debug, clap::Args)]
struct BenchArgs {
    /// Scene files, or folders whose `*.toml` scenes are measured (default: scenes/).
    scenes: Vec<PathBuf>,
    /// Timed runs per scene and plant; the best counts.
    #[arg(long, value_name = "N", default_value_t = 3, value_parser = clap::value_parser!(u32).range(1..=100))]
    runs: u32,
    /// Leave the frames out of the outputs run (no GPU or Vulkan needed).
    #[arg(long)]
    no_render: bool,
}

#[derive(Debug, clap::Args)]
struct RunArgs {
    /// Scene file (TOML).
    scene: PathBuf,
    /// Write PNG frames of every camera into DIR (`<camera>-<frame>.png`).
    #[arg(long, value_name = "DIR")]
    frames: Option<PathBuf>,
    /// Save a Rerun recording to FILE.rrd.
    #[arg(long, value_name = "FILE.rrd")]
    save: Option<PathBuf>,
    /// Stream to a Rerun viewer (default address 127.0.0.1:9876).
    #[arg(long, value_name = "ADDR", num_args = 0..=1, default_missing_value = "127.0.0.1:9876")]
    connect: Option<String>,
    /// Start a Rerun viewer (`rerun` on PATH) and stream to it.
    #[arg(long)]
    spawn: bool,
    /// Write the recording to standard output (`| rerun -`); the summary
    /// then goes to stderr.
    #[arg(long)]
    stdout: bool,
    /// Serve the recording over gRPC at ADDR (default 127.0.0.1:9876; give
    /// 0.0.0.0:9876 for other machines) for viewers to connect to
    /// (`rerun rerun+http://ADDR/proxy`); after the run it goes on
    /// serving until Ctrl-C.
    #[arg(long, value_name = "ADDR", num_args = 0..=1, default_missing_value = "127.0.0.1:9876")]
    serve: Option<String>,
    /// Write the per-update trace to FILE.csv.
    #[arg(long, value_name = "FILE.csv")]
    trace: Option<PathBuf>,
    /// Write the run summary to FILE.json.
    #[arg(long, value_name = "FILE.json")]
    summary: Option<PathBuf>,
    /// Do not render frames (no GPU or Vulkan needed).
    #[arg(long)]
    no_render: bool,
    /// Run for S seconds of simulated time instead of the scene's
    /// `duration_s` (steps after the end are not reached).
    #[arg(long, value_name = "S", value_parser = parse_duration)]
    duration: Option<f64>,
    /// How the plant moves the joints, instead of the scene's `plant`:
    /// `physics` (drives, gravity, contacts) or `kinematic` (the joints
    /// follow the setpoints exactly, as a CIP axis in Controller Loop Back
    /// test mode; for program tests, many times faster).
    #[arg(long, value_name = "MODE", value_parser = parse_plant)]
    plant: Option<scene::PlantMode>,
}

/// A `--plant` mode by name.
fn parse_plant(text: &str) -> Result<scene::PlantMode, String> {
    scene::PlantMode::NAMES
        .iter()
        .find(|(name, _)| *name == text.trim())
        .map(|(_, mode)| *mode)
        .ok_or_else(|| format!("expected physics or kinematic, found {text:?}"))
}

/// A `--duration`: seconds, positive, finite, at most 10⁶ (11.6 days).
fn parse_duration(text: &str) -> Result<f64, String> {
    let s: f64 = text
        .trim()
        .parse()
        .map_err(|_| format!("expected seconds (a number), found {text:?}"))?;
    if !(s > 0.0 && s <= scene::MAX_DURATION_S) {
        return Err(format!("expected seconds in (0, 1e6], found {text}"));
    }
    Ok(s)
}

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        // --help and --version print to stdout and succeed; a usage error
        // prints clap's message (with a suggestion for a near miss).
        Err(e) => {
            let _ = e.print();
            return ExitCode::from(if e.use_stderr() { exit::USAGE } else { 0 });
        }
    };
    let renders = match &cli.command {
        Command::Run(args) => args.frames.is_some() && !args.no_render,
        Command::Bench(args) => !args.no_render,
        Command::Check { .. } => false,
    };
    if renders && let Some(code) = rerun_with_runtime_dir() {
        return code;
    }
    let result = match cli.command {
        Command::Check { scene } => check(&scene),
        Command::Run(args) => run(&args),
        Command::Bench(args) => bench(&args),
    };
    match result {
        Ok(code) => code,
        Err(e) => {
            // The error and its causes on one line, each cause once.
            let mut text = String::new();
            for cause in e.chain() {
                let part = cause.to_string();
                if !text.contains(&part) {
                    if !text.is_empty() {
                        text.push_str(": ");
                    }
                    text.push_str(&part);
                }
            }
            eprintln!("error: {}", text.replace('\n', " "));
            ExitCode::from(exit_code(&e))
        }
    }
}

/// Mesa's Vulkan drivers print "error: XDG_RUNTIME_DIR is invalid or not
/// set in the environment" when a process without one renders (a CI box, a
/// container, `sudo`). When it is missing or unusable, this runs the same
/// command again with a private one (`<tmp>/twin-runtime-<uid>`, mode 0700,
/// as the XDG spec asks) and returns its exit code; `None` when there is
/// nothing to do (or no such folder can be made: the run goes on as is).
#[cfg(unix)]
fn rerun_with_runtime_dir() -> Option<ExitCode> {
    use std::os::unix::fs::{DirBuilderExt as _, MetadataExt as _, PermissionsExt as _};
    let uid = fs::metadata("/proc/self").ok()?.uid();
    let usable = |dir: &Path| {
        fs::metadata(dir).is_ok_and(|m| m.is_dir() && m.uid() == uid && m.permissions().mode() & 0o077 == 0)
    };
    if std::env::var_os("XDG_RUNTIME_DIR").is_some_and(|d| usable(Path::new(&d))) {
        return None;
    }
    let dir = std::env::temp_dir().join(format!("twin-runtime-{uid}"));
    let _ = fs::DirBuilder::new().mode(0o700).create(&dir);
    if !usable(&dir) {
        return None;
    }
    let status = std::process::Command::new(std::env::current_exe().ok()?)
        .args(std::env::args_os().skip(1))
        .env("XDG_RUNTIME_DIR", &dir)
        .status()
        .ok()?;
    Some(ExitCode::from(
        status.code().map_or(1, |c| u8::try_from(c).unwrap_or(1)),
    ))
}

#[cfg(not(unix))]
fn rerun_with_runtime_dir() -> Option<ExitCode> {
    None
}

/// The exit code of a failed command, from what failed.
fn exit_code(e: &anyhow::Error) -> u8 {
    use twin::output::session::OutputError;
    for cause in e.chain() {
        if cause.is::<scene::SceneError>() || cause.is::<twin::run::RunError>() {
            return exit::INVALID_INPUT;
        }
        if let Some(OutputError::NoRerun { .. }) = cause.downcast_ref::<OutputError>() {
            return exit::USAGE;
        }
        if cause.is::<Refused>() {
            return exit::USAGE;
        }
    }
    exit::OUTPUT
}

fn load(path: &Path) -> Result<Twin> {
    let scene = scene::load(path)?;
    Ok(Twin::new(scene)?)
}

fn check(path: &Path) -> Result<ExitCode> {
    let twin = load(path)?;
    let scene = twin.scene();
    println!(
        "{}: ok ({} axes, {} program steps, {} tasks, {} cameras, {:.3} s)",
        path.display(),
        twin.plant().axes().len(),
        scene.program.len(),
        scene.tasks.len(),
        scene.cameras.len(),
        scene.duration_s
    );
    print!("{}", resolved(&twin));
    Ok(ExitCode::SUCCESS)
}

/// What a scene resolved to: the robot, each axis with its joint, units
/// and limits, the cameras and the tags.
fn resolved(twin: &Twin) -> String {
    use std::fmt::Write as _;
    let (scene, plant) = (twin.scene(), twin.plant());
    let model = plant.model();
    let mut s = String::new();
    let _ = writeln!(
        s,
        "robot: {} ({} links, {} joints); coarse update {} ms, physics step {} ms",
        scene.robot.urdf.display(),
        model.links.len(),
        model.joints.len(),
        scene.coarse_update_ms,
        scene.physics_step_ms
    );
    if scene.plant != scene::PlantMode::Physics {
        let _ = writeln!(s, "plant: {} (the joints follow the setpoints)", scene.plant.name());
    }
    if !scene.axes.is_empty() {
        let _ = writeln!(s, "axes:");
    }
    for axis in &scene.axes {
        let c = &axis.config;
        let u = axis.units;
        let joint = match axis
            .joint
            .as_deref()
            .and_then(|j| model.joint_by_name(j).map(|i| (j, i)))
        {
            Some((name, i)) => {
                let joint = &model.joints[i.0];
                let si = if matches!(u, scene::Units::Deg | scene::Units::Rad) {
                    "rad"
                } else {
                    "m"
                };
                let limits = joint.limits.as_ref().map_or(String::new(), |l| {
                    format!(", URDF limits [{}, {}] {si}", l.lower, l.upper)
                });
                let kind = format!("{:?}", joint.kind).to_lowercase();
                format!("joint {name} ({kind}{limits}), 1 {u} = {} {si}", u.si_per_unit())
            }
            None => "virtual (no joint)".to_string(),
        };
        let _ = writeln!(
            s,
            "  {} ({}, {u}): {joint}; max velocity {} {u}/s, acceleration {} {u}/s², deceleration {} {u}/s², jerk {}",
            axis.name,
            axis.kind,
            c.max_velocity,
            c.max_acceleration,
            c.max_deceleration,
            if c.max_jerk > 0.0 {
                format!("{} {u}/s³", c.max_jerk)
            } else {
                "none (trapezoidal)".to_string()
            },
        );
    }
    if !scene.cameras.is_empty() {
        let _ = writeln!(s, "cameras:");
    }
    for c in &scene.cameras {
        let _ = writeln!(
            s,
            "  {}: {}x{} px at {} fps, {}° field of view, from {:?} m looking at {:?} m",
            c.name, c.width, c.height, c.fps, c.fov_deg, c.position_m, c.target_m
        );
    }
    if !scene.tags.is_empty() {
        let _ = writeln!(s, "tags:");
    }
    for t in &scene.tags {
        let _ = writeln!(s, "  {}: {}", t.name, t.ty);
    }
    s
}

/// What each update is written to; an output that fails is reported and
/// dropped, the others go on.
struct UpdateSinks<'a> {
    frames: &'a mut Option<twin::output::session::Frames>,
    recording: &'a mut Option<twin::output::session::Recording>,
    trace: &'a mut Option<Trace>,
    failures: &'a mut Vec<anyhow::Error>,
}

impl UpdateSinks<'_> {
    fn write(&mut self, twin: &Twin) {
        if let Some(f) = self.frames.as_mut()
            && let Err(e) = f.capture(twin)
        {
            self.failures
                .push(anyhow::Error::new(e).context("--frames: stopped writing frames"));
            *self.frames = None;
        }
        if let Some(r) = self.recording.as_mut()
            && let Err(e) = r.log(twin)
        {
            self.failures
                .push(anyhow::Error::new(e).context("the recording stopped"));
            *self.recording = None;
        }
        if let Some(t) = self.trace.as_mut() {
            t.row(twin);
        }
    }
}

/// An output file written beside its path and moved onto it when complete,
/// so a failed or interrupted run leaves an earlier file at the path as it
/// was. A path that exists and is not a regular file (a FIFO, a device) is
/// written directly.
struct OutputFile {
    flag: &'static str,
    path: PathBuf,
    temp: Option<PathBuf>,
}

impl OutputFile {
    fn new(flag: &'static str, path: &Path) -> OutputFile {
        let special = fs::metadata(path).is_ok_and(|m| !m.is_file());
        let temp = (!special).then(|| {
            let name = path
                .file_name()
                .map_or_else(Default::default, |n| n.to_string_lossy().into_owned());
            path.with_file_name(format!(".{name}.twin-{}.tmp", std::process::id()))
        });
        OutputFile {
            flag,
            path: path.to_path_buf(),
            temp,
        }
    }

    /// The path to write now.
    fn writing(&self) -> &Path {
        self.temp.as_deref().unwrap_or(&self.path)
    }

    /// Moves the finished file onto its path.
    fn commit(mut self) -> Result<()> {
        if let Some(temp) = self.temp.take() {
            let moved = fs::rename(&temp, &self.path);
            if moved.is_err() {
                let _ = fs::remove_file(&temp);
            }
            moved.with_context(|| format!("{}: cannot write {}", self.flag, self.path.display()))?;
        }
        Ok(())
    }

    /// Removes what was written (the path keeps its earlier file); also
    /// what dropping an uncommitted file does.
    fn discard(&self) {
        if let Some(temp) = &self.temp {
            let _ = fs::remove_file(temp);
        }
    }
}

impl Drop for OutputFile {
    fn drop(&mut self) {
        self.discard();
    }
}

/// The `--trace` CSV: a row per update; the first write error stops it and
/// is reported at the end, naming the flag and the path.
struct Trace {
    writer: std::io::BufWriter<fs::File>,
    file: OutputFile,
    failed: Option<std::io::Error>,
}

impl Trace {
    fn create(path: &Path, twin: &Twin) -> Result<Trace> {
        let file = OutputFile::new("--trace", path);
        let f =
            fs::File::create(file.writing()).with_context(|| format!("--trace: cannot create {}", path.display()))?;
        let mut trace = Trace {
            writer: std::io::BufWriter::new(f),
            file,
            failed: None,
        };
        trace.line(&twin::output::trace::header(twin).join(","));
        Ok(trace)
    }

    fn row(&mut self, twin: &Twin) {
        if self.failed.is_none() {
            self.line(&twin::output::trace::row(twin).join(","));
        }
    }

    fn line(&mut self, line: &str) {
        if let Err(e) = writeln!(self.writer, "{line}") {
            self.failed = Some(e);
        }
    }

    fn finish(mut self) -> Result<()> {
        let flushed = match self.failed.take() {
            Some(e) => Err(e),
            None => self.writer.flush(),
        };
        if let Err(e) = flushed {
            return Err(anyhow::Error::new(e).context(format!("--trace: cannot write {}", self.file.path.display())));
        }
        self.file.commit()
    }
}

/// Refuses two outputs on one path and an output on a file the scene
/// reads: either would silently lose data.
fn check_output_paths(args: &RunArgs, inputs: &[PathBuf]) -> Result<()> {
    let outputs = [
        ("--trace", &args.trace),
        ("--summary", &args.summary),
        ("--save", &args.save),
        ("--frames", &args.frames),
    ];
    let inputs: Vec<PathBuf> = inputs.iter().map(|p| same_file(p)).collect();
    let mut seen: Vec<(&str, PathBuf)> = Vec::new();
    for (flag, path) in outputs {
        let Some(path) = path else { continue };
        let key = same_file(path);
        if let Some((other, _)) = seen.iter().find(|(_, k)| *k == key) {
            return Err(Refused(format!("{flag} {}: {other} writes there too", path.display())).into());
        }
        if inputs.contains(&key) {
            return Err(Refused(format!(
                "{flag} {}: the scene reads this file; it would be overwritten",
                path.display()
            ))
            .into());
        }
        seen.push((flag, key));
    }
    Ok(())
}

/// A path as compared for sameness: an existing file with its links
/// resolved; a new one as its resolved folder and its name.
fn same_file(path: &Path) -> PathBuf {
    if let Ok(p) = fs::canonicalize(path) {
        return p;
    }
    let absolute = std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf());
    match (
        absolute.parent().and_then(|d| fs::canonicalize(d).ok()),
        absolute.file_name(),
    ) {
        (Some(dir), Some(name)) => dir.join(name),
        _ => absolute,
    }
}

/// Flags that cannot go together (exit code 64).
#[derive(Debug)]
struct Refused(String);

impl std::fmt::Display for Refused {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for Refused {}

/// Whether a viewer address (`host:port` or `rerun+http://host:port/proxy`)
/// resolves to this machine only (loopback). An address that does not
/// resolve counts as this machine: connecting reports it.
fn is_this_machine(addr: &str) -> bool {
    use std::net::ToSocketAddrs as _;
    let host_port = addr
        .split_once("://")
        .map_or(addr, |(_, rest)| rest.split('/').next().unwrap_or_default());
    host_port
        .to_socket_addrs()
        .map_or(true, |mut addrs| addrs.all(|a| a.ip().is_loopback()))
}

/// Creates the folder an output file goes into.
fn parent_dir(flag: &str, path: &Path) -> Result<()> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        fs::create_dir_all(dir).with_context(|| format!("{flag}: cannot create folder {}", dir.display()))?;
    }
    Ok(())
}

fn run(args: &RunArgs) -> Result<ExitCode> {
    let wall = Instant::now();
    let mut scene = scene::load(&args.scene)?;
    if let Some(s) = args.duration {
        scene.duration_s = s;
    }
    if let Some(mode) = args.plant {
        scene.plant = mode;
    }
    check_output_paths(args, &scene.input_files())?;
    let mut twin = Twin::new(scene)?;
    for (flag, path) in [
        ("--trace", &args.trace),
        ("--summary", &args.summary),
        ("--save", &args.save),
    ] {
        if let Some(p) = path {
            parent_dir(flag, p)?;
        }
    }
    // Outputs that fail during the run are reported at the end; the others
    // are still written.
    let mut failures: Vec<anyhow::Error> = Vec::new();
    let mut trace = match &args.trace {
        Some(p) => Some(Trace::create(p, &twin)?),
        None => None,
    };
    let mut frames = Some(twin::output::session::Frames::new(
        &twin,
        args.frames.as_deref(),
        !args.no_render,
    )?);
    let rrd = args.save.as_deref().map(|p| OutputFile::new("--save", p));
    let targets = twin::output::RecordingTargets {
        save: rrd.as_ref().map(|f| f.writing().to_path_buf()),
        connect: args.connect.clone(),
        spawn: args.spawn,
        stdout: args.stdout,
        serve: args.serve.clone(),
    };
    if let Some(addr) = &args.connect
        && !is_this_machine(addr)
    {
        eprintln!(
            "warning: --connect {addr}: not this machine; the recording travels unencrypted over the network, \
             and the viewer there accepts any sender"
        );
    }
    let mut recording = Some(twin::output::session::Recording::new(&twin, &targets)?);
    let mut stats = twin::output::session::Stats::new(&twin);

    let total = twin.total_updates();
    let mut progress = Progress::new(total, twin.scene().coarse_update_ms / 1000.0);
    let mut sinks = UpdateSinks {
        frames: &mut frames,
        recording: &mut recording,
        trace: &mut trace,
        failures: &mut failures,
    };
    sinks.write(&twin);
    for _ in 0..total {
        twin.step();
        stats.observe(&twin);
        sinks.write(&twin);
        progress.tick(twin.task().updates(), &wall);
        if twin.stopped() {
            break;
        }
    }
    progress.finish();
    if let Some(t) = trace
        && let Err(e) = t.finish()
    {
        failures.push(e);
    }
    // An unfinished recording is not moved onto --save's path (dropping
    // its OutputFile removes it).
    // A viewer that failed costs the file nothing (and the other way round).
    let served = match recording.map(|r| r.finish(&twin)) {
        Some(finished) => {
            for e in finished.failures {
                failures.push(anyhow::Error::new(e).context("the recording did not finish"));
            }
            if finished.files_complete
                && let Some(Err(e)) = rrd.map(OutputFile::commit)
            {
                failures.push(e);
            }
            finished.served
        }
        None => Default::default(),
    };
    let written = frames.as_ref().map_or(0, |f| f.written());
    if let (Some(f), Some(dir)) = (&frames, &args.frames) {
        let stale = f.stale();
        if let Some(first) = stale.first() {
            eprintln!(
                "warning: --frames {}: {} frames of an earlier, longer run remain (from {}); they are not from this run",
                dir.display(),
                stale.len(),
                first.file_name().unwrap_or_default().to_string_lossy()
            );
        }
    }
    let summary = stats.summary(&twin, wall.elapsed().as_secs_f64(), written);
    if args.stdout {
        // Standard output carries the recording.
        eprint!("{}", summary.human());
    } else {
        print!("{}", summary.human());
    }
    if let Some(p) = &args.summary {
        let file = OutputFile::new("--summary", p);
        let written = fs::write(file.writing(), summary.json())
            .with_context(|| format!("--summary: cannot write {}", p.display()))
            .and_then(|()| file.commit());
        if let Err(e) = written {
            failures.push(e);
        }
    }
    let code = if let Some(f) = &summary.physics_fault {
        eprintln!("error: {f} (check the URDF's masses and inertias and the drives' gains)");
        exit::PHYSICS_FAULT
    } else if summary.collision_abort {
        eprintln!("error: the run was aborted by a collision (collision.reaction = \"abort\")");
        exit::COLLISION_ABORT
    } else if let Some(f) = twin.program().controller().major_fault() {
        eprintln!("error: the controller stopped on a {f}");
        exit::MAJOR_FAULT
    } else if summary.any_error() {
        eprintln!("error: an instruction reported an error (see the summary above)");
        exit::INSTRUCTION_ERROR
    } else {
        0
    };
    for e in &failures {
        eprintln!("error: {e:#}");
    }
    for address in served.addresses() {
        eprintln!("serving the recording at {address} until Ctrl-C (open it with `rerun {address}`)");
    }
    // What the user must see goes out before the wait (stdout may be a pipe).
    std::io::stdout().flush()?;
    served.wait();
    // Lost output outweighs how the run went: the user must not trust a
    // partial set of files.
    Ok(ExitCode::from(if failures.is_empty() { code } else { exit::OUTPUT }))
}

/// A one-line progress bar on stderr (indicatif), shown for runs longer
/// than a second of wall time and only when stderr is a terminal: the
/// simulated time reached, the real-time factor and the ETA.
struct Progress {
    bar: indicatif::ProgressBar,
    total: u64,
    update_s: f64,
    shown: bool,
}

impl Progress {
    fn new(total: u64, update_s: f64) -> Self {
        let bar = indicatif::ProgressBar::with_draw_target(Some(total.max(1)), indicatif::ProgressDrawTarget::hidden());
        if let Ok(style) = indicatif::ProgressStyle::with_template("[{bar:30}] {percent:>3}% {msg} ETA {eta}")
            .map(|s| s.progress_chars("#>-"))
        {
            bar.set_style(style);
        }
        Self {
            bar,
            total,
            update_s,
            shown: false,
        }
    }

    fn tick(&mut self, done: u64, wall: &Instant) {
        let elapsed_s = wall.elapsed().as_secs_f64();
        if !self.shown {
            if elapsed_s < 1.0 || !std::io::stderr().is_terminal() {
                return;
            }
            self.bar.set_draw_target(indicatif::ProgressDrawTarget::stderr());
            self.shown = true;
        }
        let sim_s = done as f64 * self.update_s;
        self.bar.set_message(format!(
            "{sim_s:.2}/{:.2} s simulated, {:.2}x real time",
            self.total as f64 * self.update_s,
            sim_s / elapsed_s
        ));
        self.bar.set_position(done);
    }

    fn finish(&self) {
        if self.shown {
            self.bar.finish();
        }
    }
}

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
    // Physics, no outputs: the best of plain runs, as `twin run` runs
    // (recording the steps and timing the stages would add their own
    // cost), then one run that records its physics steps for the replay
    // and times the collision checks.
    let mut wall = f64::INFINITY;
    for _ in 0..runs {
        let mut twin = load(scene::PlantMode::Physics)?;
        wall = wall.min(run_to_end(&mut twin, |_| {}));
    }
    let mut twin = load(scene::PlantMode::Physics)?;
    twin.record_for_bench();
    run_to_end(&mut twin, |_| {});
    let replay = twin
        .plant()
        .physics_replay()
        .context("the physics plant records its steps")?;
    let steps = replay.steps() as f64;
    let bare = (0..runs)
        .map(|_| replay.run(twin.plant().model()))
        .collect::<Result<Vec<f64>, _>>()?
        .into_iter()
        .fold(f64::INFINITY, f64::min);
    let simulated = twin.time_s();
    let collision_us = (twin.scene().collision.is_some() && steps > 0.0)
        .then(|| 1e6 * twin.plant().times().unwrap_or_default().collision_s / steps);
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

fn bench(args: &BenchArgs) -> Result<ExitCode> {
    let scenes = bench_scenes(&args.scenes)?;
    println!(
        "| scene | physics xRT | steps/s | bare steps/s | twin/bare | kinematic xRT | collision µs | program | planner | sweep | physics | collision | trace | recording | frames |"
    );
    println!(
        "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |"
    );
    for path in &scenes {
        let row = bench_scene(path, args.runs, !args.no_render)?;
        let (bare, ratio) = match row.bare_steps_per_s {
            Some(b) => (format!("{b:.0}"), format!("{:.2}", b / row.steps_per_s)),
            None => ("-".to_string(), "-".to_string()),
        };
        let split: Vec<String> = row.split.iter().map(|x| format!("{:.0} %", 100.0 * x)).collect();
        let collision = row.collision_us.map_or_else(|| "-".to_string(), |c| format!("{c:.2}"));
        println!(
            "| {} | {:.1} | {:.0} | {bare} | {ratio} | {:.0} | {collision} | {} |",
            row.name,
            row.physics_rtf,
            row.steps_per_s,
            row.kinematic_rtf,
            split.join(" | ")
        );
    }
    Ok(ExitCode::SUCCESS)
}
