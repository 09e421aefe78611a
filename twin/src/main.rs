//! The `twin` command line: runs a scene headless and writes frames, a
//! trace, a summary and a Rerun recording; or checks a scene.

use anyhow::{Context, Result, bail};
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
  twin run scenes/indexing_table.toml --no-render --summary out.json
  twin check scenes/indexing_table.toml";

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
    /// Write the per-update trace to FILE.csv.
    #[arg(long, value_name = "FILE.csv")]
    trace: Option<PathBuf>,
    /// Write the run summary to FILE.json.
    #[arg(long, value_name = "FILE.json")]
    summary: Option<PathBuf>,
    /// Do not render frames (no GPU or Vulkan needed).
    #[arg(long)]
    no_render: bool,
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Check { scene } => check(&scene),
        Command::Run(args) => run(&args),
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
            ExitCode::from(2)
        }
    }
}

fn load(path: &Path) -> Result<Twin> {
    let scene = scene::load(path)?;
    Ok(Twin::new(scene)?)
}

fn check(path: &Path) -> Result<ExitCode> {
    let twin = load(path)?;
    println!(
        "{}: ok ({} axes, {} program steps, {} tasks, {} cameras, {:.3} s)",
        path.display(),
        twin.plant().axes().len(),
        twin.scene().program.len(),
        twin.scene().tasks.len(),
        twin.scene().cameras.len(),
        twin.scene().duration_s
    );
    Ok(ExitCode::SUCCESS)
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
    let mut twin = load(&args.scene)?;
    for (flag, path) in [
        ("--trace", &args.trace),
        ("--summary", &args.summary),
        ("--save", &args.save),
    ] {
        if let Some(p) = path {
            parent_dir(flag, p)?;
        }
    }
    let mut trace = match &args.trace {
        Some(p) => {
            let f = fs::File::create(p).with_context(|| format!("--trace: cannot create {}", p.display()))?;
            let mut w = std::io::BufWriter::new(f);
            writeln!(w, "{}", twin::output::trace::header(&twin).join(","))?;
            Some((w, p.clone()))
        }
        None => None,
    };
    let mut frames = twin::output::session::Frames::new(&twin, args.frames.as_deref(), !args.no_render)?;
    let mut recording = twin::output::session::Recording::new(&twin, args.save.as_deref(), args.connect.as_deref())?;
    let mut stats = twin::output::session::Stats::new(&twin);

    let total = twin.total_updates();
    let mut progress = Progress::new(total);
    frames.capture(&twin)?;
    recording.log(&twin)?;
    if let Some((w, _)) = trace.as_mut() {
        writeln!(w, "{}", twin::output::trace::row(&twin).join(","))?;
    }
    for _ in 0..total {
        twin.step();
        stats.observe(&twin);
        frames.capture(&twin)?;
        recording.log(&twin)?;
        if let Some((w, _)) = trace.as_mut() {
            writeln!(w, "{}", twin::output::trace::row(&twin).join(","))?;
        }
        progress.tick(twin.task().updates(), &wall);
        if twin.plant().collision_abort() || twin.program().controller().major_fault().is_some() {
            break;
        }
    }
    progress.finish();
    if let Some((mut w, p)) = trace {
        w.flush()
            .with_context(|| format!("--trace: cannot write {}", p.display()))?;
    }
    recording.finish()?;
    let summary = stats.summary(&twin, wall.elapsed().as_secs_f64(), frames.written());
    print!("{}", summary.human());
    if let Some(p) = &args.summary {
        fs::write(p, summary.json()).with_context(|| format!("--summary: cannot write {}", p.display()))?;
    }
    if summary.collision_abort {
        eprintln!("error: the run was aborted by a collision (collision.reaction = \"abort\")");
        return Ok(ExitCode::from(3));
    }
    if let Some(f) = twin.program().controller().major_fault() {
        eprintln!("error: the controller stopped on a {f}");
        return Ok(ExitCode::from(4));
    }
    if summary.any_error() {
        bail!("an instruction reported an error (see the summary above)");
    }
    Ok(ExitCode::SUCCESS)
}

/// A one-line progress bar on stderr, for runs longer than a second of wall
/// time, only when stderr is a terminal.
struct Progress {
    total: u64,
    shown: bool,
    last_percent: u64,
}

impl Progress {
    fn new(total: u64) -> Self {
        Self {
            total: total.max(1),
            shown: false,
            last_percent: u64::MAX,
        }
    }

    fn tick(&mut self, done: u64, wall: &Instant) {
        if !std::io::stderr().is_terminal() || wall.elapsed().as_secs_f64() < 1.0 {
            return;
        }
        let percent = done * 100 / self.total;
        if percent != self.last_percent {
            let filled = (percent / 5) as usize;
            eprint!("\r[{}{}] {percent:3}%", "#".repeat(filled), " ".repeat(20 - filled));
            self.last_percent = percent;
            self.shown = true;
        }
    }

    fn finish(&self) {
        if self.shown {
            eprintln!();
        }
    }
}
