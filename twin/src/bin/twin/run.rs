//! `twin run`: one scene run to its end (or `--duration`), each update
//! written to the outputs asked for.

use std::fs;
use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use anyhow::{Context, Result};
use twin::output::expect::Expectations;
use twin::run::Twin;
use twin::scene;

use crate::{RunArgs, exit};

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
        if let (Some(r), Some(f)) = (self.recording.as_mut(), self.frames.as_mut()) {
            r.images(twin, f.take_images());
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
pub(crate) struct Trace {
    writer: std::io::BufWriter<fs::File>,
    file: OutputFile,
    failed: Option<std::io::Error>,
    /// The row being written, its buffer reused from update to update.
    row: String,
}

impl Trace {
    pub(crate) fn create(path: &Path, twin: &Twin) -> Result<Trace> {
        let file = OutputFile::new("--trace", path);
        let f =
            fs::File::create(file.writing()).with_context(|| format!("--trace: cannot create {}", path.display()))?;
        let mut trace = Trace {
            writer: std::io::BufWriter::new(f),
            file,
            failed: None,
            row: String::new(),
        };
        trace.line(&twin::output::trace::header(twin).join(","));
        Ok(trace)
    }

    pub(crate) fn row(&mut self, twin: &Twin) {
        if self.failed.is_none() {
            let mut line = std::mem::take(&mut self.row);
            line.clear();
            twin::output::trace::write_row(twin, &mut line);
            self.line(&line);
            self.row = line;
        }
    }

    fn line(&mut self, line: &str) {
        let written = self.writer.write_all(line.as_bytes());
        if let Err(e) = written.and_then(|()| self.writer.write_all(b"\n")) {
            self.failed = Some(e);
        }
    }

    pub(crate) fn finish(mut self) -> Result<()> {
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

/// Refuses two outputs on one path, an output on a file the scene reads
/// and an output in the `--frames` folder under a name a frame takes:
/// each would silently lose data.
fn check_output_paths(args: &RunArgs, inputs: &[PathBuf], cameras: &[twin::scene::Camera]) -> Result<()> {
    let outputs = [
        ("--trace", &args.trace),
        ("--summary", &args.summary),
        ("--save", &args.save),
        ("--frames", &args.frames),
    ];
    let inputs: Vec<PathBuf> = inputs.iter().map(|p| same_file(p)).collect();
    let frames = args.frames.as_deref().map(same_file);
    let mut seen: Vec<(&str, PathBuf)> = Vec::new();
    for (flag, path) in outputs {
        let Some(path) = path else { continue };
        let key = same_file(path);
        if flag != "--frames"
            && let Some(dir) = &frames
            && key.parent() == Some(dir.as_path())
            && key
                .file_name()
                .and_then(|f| f.to_str())
                .is_some_and(|f| twin::output::session::frame_may_take(f, cameras))
        {
            return Err(Refused(format!(
                "{flag} {}: a frame of the --frames folder takes this name (<camera>-<frame>.png)",
                path.display()
            ))
            .into());
        }
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
/// resolved; a new one as its deepest existing folder, resolved, and the
/// rest of the path with `.` and `..` worked out (`out/n/../n/z` and
/// `out/n/z` are one path even before `out/n` exists).
pub(crate) fn same_file(path: &Path) -> PathBuf {
    if let Ok(p) = fs::canonicalize(path) {
        return p;
    }
    let absolute = std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf());
    let mut base = absolute.as_path();
    let mut rest = Vec::new();
    let resolved = loop {
        if let Ok(p) = fs::canonicalize(base) {
            break p;
        }
        match (base.parent(), base.components().next_back()) {
            (Some(parent), Some(last)) => {
                rest.push(last);
                base = parent;
            }
            _ => break PathBuf::new(),
        }
    };
    let mut out = resolved;
    for c in rest.into_iter().rev() {
        match c {
            std::path::Component::ParentDir => {
                out.pop();
            }
            std::path::Component::CurDir => {}
            other => out.push(other),
        }
    }
    out
}

/// Flags that cannot go together (exit code 64).
#[derive(Debug)]
pub(crate) struct Refused(pub(crate) String);

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

pub(crate) fn run(args: &RunArgs) -> Result<ExitCode> {
    let wall = Instant::now();
    let mut scene = scene::load(&args.scene)?;
    if let Some(name) = &args.variant {
        scene = match scene.with_variant(name) {
            Some(v) => v,
            None => {
                let names: Vec<&str> = scene.variants.iter().map(|v| v.name.as_str()).collect();
                return Err(Refused(format!(
                    "--variant {name}: {} has {}",
                    args.scene.display(),
                    if names.is_empty() {
                        "no [[variants]]".to_owned()
                    } else {
                        format!("the variants {}", names.join(", "))
                    }
                ))
                .into());
            }
        };
    }
    if let Some(s) = args.duration {
        scene.duration_s = s;
    }
    if let Some(mode) = args.plant {
        scene.plant = mode;
    }
    check_output_paths(args, &scene.input_files(), &scene.cameras)?;
    let mut twin = Twin::new(scene)?;
    // The robot's meshes are inputs too (the URDF names them).
    let mut inputs = twin.scene().input_files();
    inputs.extend(twin.plant().model().mesh_files());
    check_output_paths(args, &inputs, &twin.scene().cameras)?;
    crate::print_warnings(&twin);
    let mut expectations = Expectations::new(&mut twin).map_err(twin::run::RunError::Program)?;
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
    let mut frames = Some({
        let f = twin::output::session::Frames::new(&twin, args.frames.as_deref(), !args.no_render)?;
        let f = match &args.frames_only {
            Some(numbers) => f.only_numbers(numbers),
            None => f,
        };
        let mut f = match args.frames_at {
            Some(at) => f.only_at(at),
            None => f,
        };
        if args.save_frames {
            f.keep_images(twin::output::session::KEPT_IMAGE_MAX_WIDTH_PX);
        }
        f
    });
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
    if args.save_frames && targets.first_flag().is_none() {
        return Err(Refused(
            "--save-frames: the frames go into a recording; add --save, --connect, --spawn, --stdout or --serve"
                .to_owned(),
        )
        .into());
    }
    let mut recording = Some(twin::output::session::Recording::new(&twin, &targets)?);
    let mut events = args.verbose.then(|| twin::output::session::EventLines::new(&twin));
    let mut stats = twin::output::session::Stats::new(&twin);

    let total = twin.total_updates();
    let mut progress = Progress::new(total, twin.scene().coarse_update_s());
    let mut sinks = UpdateSinks {
        frames: &mut frames,
        recording: &mut recording,
        trace: &mut trace,
        failures: &mut failures,
    };
    sinks.write(&twin);
    expectations.observe(&mut twin);
    let mut wall_limit = None;
    for _ in 0..total {
        twin.step();
        stats.observe(&twin);
        if let Some(events) = &mut events {
            for line in events.take(&twin) {
                progress.println(&line);
            }
        }
        sinks.write(&twin);
        expectations.observe(&mut twin);
        progress.tick(twin.task().updates(), &wall);
        if twin.stopped() {
            break;
        }
        if let Some(max_wall_s) = args.max_wall
            && wall.elapsed().as_secs_f64() >= max_wall_s
            && twin.task().updates() < total
        {
            wall_limit = Some(twin::output::session::WallLimit {
                max_wall_s,
                time_s: twin.time_s(),
            });
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
    let mut summary = stats.summary(&twin, wall.elapsed().as_secs_f64(), written);
    summary.expectations = expectations.outcomes();
    summary.wall_limit = wall_limit;
    // The file first: a closed standard output must not cost it.
    if let Some(p) = &args.summary {
        let file = OutputFile::new("--summary", p);
        let written = fs::write(file.writing(), summary.json())
            .with_context(|| format!("--summary: cannot write {}", p.display()))
            .and_then(|()| file.commit());
        if let Err(e) = written {
            failures.push(e);
        }
    }
    let (code, why) = if let Some(f) = &summary.physics_fault {
        (
            exit::PHYSICS_FAULT,
            format!("{f} (check the URDF's masses and inertias and the drives' gains)"),
        )
    } else if summary.collision_abort {
        (
            exit::COLLISION_ABORT,
            "the run was aborted by a collision (collision.reaction = \"abort\")".to_owned(),
        )
    } else if let Some(f) = twin.program().controller().major_fault() {
        (exit::MAJOR_FAULT, format!("the controller stopped on a {f}"))
    } else if summary.any_error() {
        (
            exit::INSTRUCTION_ERROR,
            "an instruction reported an error (see the summary above)".to_owned(),
        )
    } else if let Some(w) = &summary.wall_limit {
        (
            exit::WALL_LIMIT,
            format!(
                "--max-wall {} s stopped the run at t = {:.3} s of its {:.3} s; the outputs end there",
                w.max_wall_s,
                w.time_s,
                total as f64 * twin.scene().coarse_update_s()
            ),
        )
    } else if summary.failed_expectations() > 0 {
        (
            exit::EXPECTATION_FAILED,
            format!(
                "{} of {} expectations failed (see above)",
                summary.failed_expectations(),
                summary.expectations.len()
            ),
        )
    } else {
        (0, String::new())
    };
    // -q: the summary only when something went wrong.
    if !args.quiet || code != 0 || !failures.is_empty() {
        if args.stdout {
            // Standard output carries the recording.
            eprint!("{}", summary.human());
        } else {
            out!("{}", summary.human());
        }
    }
    if code != 0 {
        eprintln!("error: {why}");
    }
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

    /// A line on stderr, above the bar when it is shown.
    fn println(&self, line: &str) {
        if self.shown {
            self.bar.suspend(|| eprintln!("{line}"));
        } else {
            eprintln!("{line}");
        }
    }
}
