//! The `twin` command line: runs a scene headless and writes frames, a
//! trace, a summary and a Rerun recording; or checks a scene.

use anyhow::Result;
use clap::{Parser, Subcommand};
use std::fs;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use twin::run::Twin;
use twin::scene;
use twin::source::Diagnostic;
use twin::source::diag::stderr_wants_color;

/// Writes to standard output; a closed output (`twin check … | head`)
/// ends the writing quietly instead of panicking: the reader is gone, and
/// the run's files are written all the same.
macro_rules! out {
    ($($t:tt)*) => {
        $crate::emit(&format!($($t)*))
    };
}

/// [`out!`] with a newline.
macro_rules! outln {
    () => {
        $crate::emit("\n")
    };
    ($($t:tt)*) => {
        $crate::emit(&format!("{}\n", format_args!($($t)*)))
    };
}

/// What [`out!`] writes with.
pub(crate) fn emit(text: &str) {
    use std::io::Write;
    let _ = std::io::stdout().write_all(text.as_bytes());
}

mod bench;
mod import;
mod run;
mod test;

const EXAMPLES: &str = "\
Examples:
  twin run scenes/indexing_table.toml --frames out --save out.rrd --trace out.csv
  twin run scenes/indexing_table.toml --connect            # stream to a Rerun viewer on 127.0.0.1:9876
  twin run scenes/indexing_table.toml --no-render --summary out.json --duration 0.5
  twin run scenes/scara_pick.toml --no-render --plant kinematic   # program test, no dynamics
  twin check scenes/indexing_table.toml

Exit codes:
  0 success; 2 an instruction reported an error; 3 a collision aborted the run;
  4 a major controller fault stopped it; 5 the physics diverged;
  6 an expectation ([[expect]]) failed and none of 2-5 happened; 7 --max-wall
  stopped the run before its end (none of 2-5 first); 64 usage
  error (also --stdout on a terminal); 65 invalid input (scene, routine,
  URDF, mesh); 66 the scene file does not exist or is not a readable file;
  74 an output cannot be written or a viewer reached (it outweighs the
  others)";

/// Exit codes (README, "Errors and exit codes"): 2, 3 and 4 are what a run reports,
/// the others follow sysexits.h.
mod exit {
    /// An instruction reported an error; the run went to its end.
    pub const INSTRUCTION_ERROR: u8 = 2;
    /// A collision with `collision.reaction = "abort"` ended the run.
    pub const COLLISION_ABORT: u8 = 3;
    /// A major controller fault stopped the run.
    pub const MAJOR_FAULT: u8 = 4;
    /// The physics state diverged (non-finite, or a joint or link ran away) and stopped the run.
    pub const PHYSICS_FAULT: u8 = 5;
    /// The run went to its end with none of 2–5, and an `[[expect]]`
    /// failed.
    pub const EXPECTATION_FAILED: u8 = 6;
    /// `--max-wall` stopped the run before its end (none of 2–5 first).
    pub const WALL_LIMIT: u8 = 7;
    /// Unknown flag or subcommand, a bad flag value, a flag this build lacks.
    pub const USAGE: u8 = 64;
    /// The scene, a routine, the URDF or a mesh is invalid.
    pub const INVALID_INPUT: u8 = 65;
    /// The scene file given does not exist or cannot be read as a file.
    pub const NO_INPUT: u8 = 66;
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
    /// Write the standalone scene a scene naming an L5X export stands for:
    /// the scene file and its routines, each item commented with its L5X line.
    #[command(after_help = IMPORT_HELP)]
    Import(import::ImportArgs),
    /// Measure scenes: the physics plant against a bare rapier simulation
    /// replaying the same drive commands, the kinematic plant, and where a
    /// run with every output spends its time.
    #[command(after_help = BENCH_HELP)]
    Bench(BenchArgs),
    /// Run scenes as tests: every scene and variant in a child process,
    /// several at a time; their expectations, exit codes and snapshots
    /// checked; a console report, JUnit, failure artifacts, sharding.
    #[command(after_help = TEST_HELP)]
    Test(test::TestArgs),
}

const IMPORT_HELP: &str = "\
OUT.toml is written with `routines/<Program>/<Routine>.st` beside it; paths
in it are relative to its folder. Importing twice writes the same files, and
the written scene runs as the scene naming the export does.

Exit codes:
  0 written; 64 usage (the scene names no export); 65 invalid input;
  74 a file cannot be written

Example:
  twin import scenes/l5x/scara_pick.toml -o imported/scara_pick.toml";

const TEST_HELP: &str = "\
A run is a scene or one of its [[variants]] (`scenes/knife_cut.toml[250 mm]`).
It passes when it exits as its [test] exit_code says (default 0), every
[[expect]] holds and its [snapshots] match.

Exit codes:
  0 every run passed; 1 a run failed or errored; 64 usage (`--shard 4/3`);
  74 --junit or --artifacts cannot be written (checked before anything runs)

Examples:
  twin test scenes/ -j 2 --junit target/junit.xml
  twin test scenes/ --shard 2/3 --artifacts target/failures
  twin test scenes/ --shard auto --shards 4      # a Kubernetes Indexed Job";

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
  parts µs        the parts world per parts step (spawns, belts, cylinders,
                  grippers, rapier, sinks), µs (- without a cell)
  sensors µs      the sensors' checks per parts step, µs (- without sensors)
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
    /// With --frames: only one picture per camera, at the first update at
    /// or after S seconds (`<camera>-t<time>.png`).
    #[arg(long, value_name = "S", requires = "frames", value_parser = parse_time)]
    frames_at: Option<f64>,
    /// With --frames: only the frames numbered N,N,… of every camera
    /// (`<camera>-<N>.png`), the others not rendered.
    #[arg(long, value_name = "N,N,…", requires = "frames", value_delimiter = ',')]
    frames_only: Option<Vec<u64>>,
    /// Save a Rerun recording to FILE.rrd.
    #[arg(long, value_name = "FILE.rrd")]
    save: Option<PathBuf>,
    /// With --frames and a recording: log every frame in the recording too
    /// (scaled down to at most 640 pixels wide), under its camera.
    #[arg(long, requires = "frames")]
    save_frames: bool,
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
    /// Run the scene's variant NAME (`[[variants]]`): its initial tag
    /// values, duration, plant and expectations.
    #[arg(long, value_name = "NAME")]
    variant: Option<String>,
    /// How the plant moves the joints, instead of the scene's `plant`:
    /// `physics` (drives, gravity, contacts) or `kinematic` (the joints
    /// follow the setpoints exactly, as a CIP axis in Controller Loop Back
    /// test mode; for program tests, many times faster).
    #[arg(long, value_name = "MODE", value_parser = parse_plant)]
    plant: Option<scene::PlantMode>,
    /// Stop the run after S seconds of wall time (checked between coarse
    /// updates), writing every output up to there; exit code 7.
    #[arg(long, value_name = "S", value_parser = parse_wall)]
    max_wall: Option<f64>,
    /// Quiet: print the summary only when the run fails (an exit code
    /// other than 0); errors are printed either way.
    #[arg(short, long, conflicts_with = "verbose")]
    quiet: bool,
    /// Verbose: print each instruction event (a change of an
    /// instruction's outputs, a fault) on stderr as it happens.
    #[arg(short, long)]
    verbose: bool,
}

/// A `--max-wall`: seconds of wall time, positive and finite.
fn parse_wall(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(s) if s > 0.0 && s.is_finite() => Ok(s),
        _ => Err(format!("expected seconds of wall time (more than 0), found {text:?}")),
    }
}

/// A `--plant` mode by name.
fn parse_plant(text: &str) -> Result<scene::PlantMode, String> {
    scene::PlantMode::NAMES
        .iter()
        .find(|(name, _)| *name == text.trim())
        .map(|(_, mode)| *mode)
        .ok_or_else(|| format!("expected physics or kinematic, found {text:?}"))
}

/// A `--frames-at`: seconds, zero or more, finite.
fn parse_time(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(s) if s >= 0.0 && s.is_finite() => Ok(s),
        _ => Err(format!("expected seconds (zero or more), found {text:?}")),
    }
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
        Command::Check { .. } | Command::Test(_) | Command::Import(_) => false,
    };
    if renders && let Some(code) = rerun_with_runtime_dir() {
        return code;
    }
    let result = match cli.command {
        Command::Check { scene } => check(&scene),
        Command::Run(args) => run::run(&args),
        Command::Bench(args) => bench::bench(&args),
        Command::Test(args) => test::test(&args),
        Command::Import(args) => import::import(&args),
    };
    match result {
        Ok(code) => code,
        Err(e) => {
            // A scene or program error renders with its source line.
            if let Some(d) = diagnostic(&e) {
                eprint!("{}", d.render(stderr_wants_color()));
                return ExitCode::from(exit_code(&e));
            }
            // The error and its causes on one line, each cause once.
            let text = twin::source::diag::with_causes(e.as_ref());
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
        // The scene file itself missing or not a file: sysexits' EX_NOINPUT.
        if let Some(scene::SceneError::Read { source, .. }) = cause.downcast_ref::<scene::SceneError>()
            && matches!(
                source.kind(),
                std::io::ErrorKind::NotFound | std::io::ErrorKind::PermissionDenied | std::io::ErrorKind::InvalidInput
            )
        {
            return exit::NO_INPUT;
        }
        if cause.is::<scene::SceneError>() || cause.is::<twin::run::RunError>() {
            return exit::INVALID_INPUT;
        }
        #[cfg(feature = "rerun")]
        if let Some(twin::output::recording::RecordingError::StdoutIsTerminal) =
            cause.downcast_ref::<twin::output::recording::RecordingError>()
        {
            return exit::USAGE;
        }
        if let Some(OutputError::NoRerun { .. }) = cause.downcast_ref::<OutputError>() {
            return exit::USAGE;
        }
        if cause.is::<run::Refused>() {
            return exit::USAGE;
        }
    }
    exit::OUTPUT
}

/// The diagnostic of an error that is a scene's or a program's (not one
/// wrapped in a context: its chain prints as one line).
fn diagnostic(e: &anyhow::Error) -> Option<Diagnostic> {
    if let Some(s) = e.downcast_ref::<scene::SceneError>() {
        return Some(s.diagnostic());
    }
    e.downcast_ref::<twin::run::RunError>()
        .map(twin::run::RunError::diagnostic)
}

/// Loads a scene, binds its program and compiles its expectations,
/// printing the program's warnings (calls the instruction refuses
/// whatever the state) to stderr.
fn load(path: &Path) -> Result<Twin> {
    let scene = scene::load(path)?;
    let mut twin = Twin::new(scene)?;
    print_warnings(&twin);
    twin::output::expect::Expectations::new(&mut twin).map_err(twin::run::RunError::Program)?;
    Ok(twin)
}

/// The program's load-time warnings, rendered, on stderr.
pub(crate) fn print_warnings(twin: &Twin) {
    let color = stderr_wants_color();
    for w in twin.program().warnings() {
        eprint!("{}", w.render(color));
    }
}

fn check(path: &Path) -> Result<ExitCode> {
    let mut twin = load(path)?;
    let scene = twin.scene();
    outln!(
        "{}: ok ({} axes, {} program steps, {} tasks, {} cameras, {:.3} s)",
        path.display(),
        twin.plant().axes().len(),
        scene.program.len(),
        scene.tasks.len(),
        scene.cameras.len(),
        scene.duration_s
    );
    out!("{}", programs(twin.scene()));
    out!("{}", resolved(&twin));
    out!("{}", io_list(&mut twin));
    out!("{}", l5x_report(twin.scene()));
    // The process ends here: freeing a large project's program piece by
    // piece would take a tenth of the load's time for nothing.
    std::mem::forget(twin);
    Ok(ExitCode::SUCCESS)
}

/// Each task's programs with their routines: how many are Structured
/// Text and how many ladder, with the ladder routines' rungs, and the
/// Add-On Instructions they call.
fn programs(scene: &scene::Scene) -> String {
    use std::fmt::Write as _;
    let mut s = String::new();
    for t in &scene.tasks {
        for p in &t.programs {
            let routines: Vec<_> = std::iter::once(&p.main).chain(&p.routines).collect();
            let ladder: Vec<_> = routines.iter().filter_map(|r| r.routine.rungs.as_ref()).collect();
            let rungs: usize = ladder.iter().map(|r| r.len()).sum();
            // Add-On Instruction calls by instruction, in first-call order.
            let mut calls: Vec<(&str, usize)> = Vec::new();
            for c in routines.iter().flat_map(|r| r.routine.calls()) {
                if let Some(a) = scene
                    .add_on_instructions
                    .iter()
                    .find(|a| a.name.eq_ignore_ascii_case(&c.name))
                {
                    match calls.iter_mut().find(|(n, _)| *n == a.name) {
                        Some((_, k)) => *k += 1,
                        None => calls.push((&a.name, 1)),
                    }
                }
            }
            let aois = if calls.is_empty() {
                String::new()
            } else {
                let list: Vec<String> = calls.iter().map(|(n, k)| format!("{n} ×{k}")).collect();
                format!(
                    "; {} Add-On Instruction call(s): {}",
                    calls.iter().map(|c| c.1).sum::<usize>(),
                    list.join(", ")
                )
            };
            let _ = writeln!(
                s,
                "program {} (task {}): {} routine(s), {} Structured Text, {} ladder ({rungs} rungs){aois}",
                p.name,
                t.name,
                routines.len(),
                routines.len() - ladder.len(),
                ladder.len()
            );
        }
    }
    s
}

/// What a scene's L5X export holds that the twin does not simulate, with
/// its lines, and what `not_simulated` skipped.
fn l5x_report(scene: &scene::Scene) -> String {
    use std::fmt::Write as _;
    let mut s = String::new();
    let Some(l5x) = &scene.l5x else { return s };
    let _ = writeln!(
        s,
        "L5X {}: {} not simulated, {} skipped",
        l5x.path.display(),
        l5x.report.len(),
        l5x.skipped.len()
    );
    for (line, text) in &l5x.report {
        let _ = writeln!(s, "  {}:{line}: {text}", l5x.path.display());
    }
    for item in &l5x.skipped {
        let _ = writeln!(s, "  skipped (not_simulated): {item}");
    }
    s
}

/// The cell's I/O list (tag, direction, device, kind) and the routines'
/// writes to input tags.
fn io_list(twin: &mut Twin) -> String {
    use std::fmt::Write as _;
    let mut s = String::new();
    let entries: Vec<_> = twin.program().io().entries().cloned().collect();
    if entries.is_empty() {
        return s;
    }
    let width = entries.iter().map(|e| e.tag.len()).max().unwrap_or(0);
    let _ = writeln!(s, "I/O (tag, direction, device, kind):");
    for e in &entries {
        let direction = match e.direction {
            scene::IoDirection::Input => "input ",
            _ => "output",
        };
        let _ = writeln!(s, "  {:width$}  {direction}  {}  {}", e.tag, e.device, e.role);
    }
    for (at, tag) in twin.input_writes() {
        let _ = writeln!(
            s,
            "  note: {at} writes the input tag {tag}; the next input update overwrites it"
        );
    }
    s
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
    if scene.data_types.len() > 1 {
        let _ = writeln!(s, "data types (bytes as the controller lays them out):");
    }
    let layouts = twin::program::layout::Layouts::of(&scene.data_types);
    for (k, d) in scene.data_types.iter().enumerate().skip(1) {
        let l = layouts.get(k as u16);
        let what = match d.string_length {
            Some(n) => format!("string of {n} characters"),
            None => {
                let members: Vec<String> = d
                    .members
                    .iter()
                    .zip(&l.members)
                    .map(|(m, at)| match (m.ty.base, m.ty.array_len) {
                        (twin::scene::BaseType::Bool, None) => format!("{} BOOL @{}.{}", m.name, at.byte, at.bit),
                        _ => format!("{} {} @{}", m.name, m.ty, at.byte),
                    })
                    .collect();
                members.join(", ")
            }
        };
        let _ = writeln!(s, "  {}: {} bytes; {what}", d.name, l.bytes);
    }
    if !scene.tags.is_empty() {
        let _ = writeln!(s, "tags:");
    }
    for t in &scene.tags {
        let _ = writeln!(s, "  {}: {}", t.name, t.ty);
    }
    s
}
