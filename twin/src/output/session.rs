//! What a run produces besides the trace: rendered frames, the Rerun
//! recording, and the summary.

#[cfg(feature = "rerun")]
pub use crate::output::recording::Served;
#[cfg(feature = "rerun")]
pub use crate::output::recording::run::{Finished, Recording};
use crate::output::status::{describe, error_codes};
#[cfg(feature = "render")]
use crate::plant::visuals::{column_major, world_from_visual};
use crate::run::Twin;
use planner::instruction::MotionInstructionBits;
use serde::Serialize;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use thiserror::Error;

/// Why an output of a run cannot be written.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum OutputError {
    /// A frame directory or PNG cannot be written.
    #[error("--frames: cannot write {path}: {message}")]
    Frame {
        /// The file or directory.
        path: PathBuf,
        /// What failed.
        message: String,
    },
    /// `--save`, `--connect`, `--spawn` or `--stdout` asked of a twin built
    /// without Rerun.
    #[error(
        "{flag}: this twin was built without Rerun recordings (cargo feature `rerun`); \
         build it with the default features to save or stream a recording"
    )]
    NoRerun {
        /// The flag that asked for a recording.
        flag: &'static str,
    },
}

pub use crate::output::COLLISION_TINT_RGBA;

/// A frame as the recording keeps it: RGB, at most `max_width_px` wide
/// (scaled down with its aspect kept).
#[cfg(feature = "render")]
fn kept_image(name: &str, image: &image::RgbaImage, max_width_px: u32) -> KeptImage {
    let (w, h) = image.dimensions();
    let scaled;
    let image = if w > max_width_px {
        let height = ((u64::from(h) * u64::from(max_width_px)).div_ceil(u64::from(w))).max(1) as u32;
        scaled = image::imageops::resize(image, max_width_px, height, image::imageops::FilterType::Triangle);
        &scaled
    } else {
        image
    };
    let size = [image.width(), image.height()];
    let rgb = image.pixels().flat_map(|p| [p[0], p[1], p[2]]).collect();
    (name.to_owned(), rgb, size)
}

/// Writes `image` as a PNG at `path`, encoded for speed (fast deflate, the
/// Sub filter): a frame is written every few updates, and files a third
/// larger than the best compression are the better trade.
#[cfg(feature = "render")]
fn write_png(path: &Path, image: &image::RgbaImage) -> image::ImageResult<()> {
    use image::ImageEncoder;
    use image::codecs::png::{CompressionType, FilterType, PngEncoder};
    let file = std::io::BufWriter::new(std::fs::File::create(path)?);
    PngEncoder::new_with_quality(file, CompressionType::Fast, FilterType::Sub).write_image(
        image.as_raw(),
        image.width(),
        image.height(),
        image::ExtendedColorType::Rgba8,
    )
}

/// Renders every camera at its frame rate into a directory.
pub struct Frames {
    #[cfg(feature = "render")]
    inner: Option<FramesInner>,
    written: usize,
    /// [`Frames::keep_images`]: the widest a kept image is, and the images
    /// rendered since [`Frames::take_images`].
    kept: Option<(u32, Vec<KeptImage>)>,
}

pub use crate::output::KeptImage;

/// The widest a frame kept for the recording is, pixels (`--save-frames`).
pub const KEPT_IMAGE_MAX_WIDTH_PX: u32 = 640;

#[cfg(feature = "render")]
struct FramesInner {
    renderer: crate::output::render::Renderer,
    /// GPU meshes of the plant's visuals, in the same order.
    meshes: Vec<crate::output::render::MeshId>,
    /// GPU meshes of the part types, then of the cylinders, in scene order.
    part_meshes: Vec<crate::output::render::MeshId>,
    dir: PathBuf,
    /// Per camera: name, camera, fps, next frame, whether it draws the
    /// sensors.
    cameras: Vec<(String, crate::output::render::Camera, f64, u64, bool)>,
    /// [`Frames::only_at`]: one picture per camera at the first update at
    /// or after this time, and no other; cleared once taken.
    at_s: Option<f64>,
    /// [`Frames::only_numbers`]: the frame numbers rendered (the others
    /// are passed over).
    only: Option<Vec<u64>>,
}

impl Frames {
    /// Prepares rendering into `dir` (nothing when `dir` is `None` or
    /// rendering is off). Without a Vulkan adapter the run continues
    /// without frames, and one line on stderr says how to get them.
    ///
    /// # Errors
    /// [`OutputError`] when the directory cannot be created or the renderer fails.
    pub fn new(twin: &Twin, dir: Option<&Path>, render: bool) -> Result<Frames, OutputError> {
        let Some(dir) = dir.filter(|_| render) else {
            return Ok(Frames {
                #[cfg(feature = "render")]
                inner: None,
                written: 0,
                kept: None,
            });
        };
        #[cfg(feature = "render")]
        {
            let mut renderer = match crate::output::render::Renderer::new() {
                Ok(r) => r,
                Err(crate::output::render::RenderError::NoAdapter) => {
                    eprintln!("{}", crate::output::render::NO_ADAPTER_HINT);
                    return Ok(Frames {
                        inner: None,
                        written: 0,
                        kept: None,
                    });
                }
                Err(e) => {
                    return Err(OutputError::Frame {
                        path: dir.to_path_buf(),
                        message: e.to_string(),
                    });
                }
            };
            std::fs::create_dir_all(dir).map_err(|e| OutputError::Frame {
                path: dir.to_path_buf(),
                message: e.to_string(),
            })?;
            let meshes = twin
                .plant()
                .visuals()
                .iter()
                .map(|p| renderer.upload_mesh(&p.mesh))
                .collect();
            let part_meshes = twin
                .scene()
                .cell
                .part_types
                .iter()
                .map(|p| p.shape.clone())
                .chain(
                    twin.scene()
                        .cell
                        .cylinders
                        .iter()
                        .map(|c| crate::scene::Shape::Box { size_m: c.size_m }),
                )
                .map(|shape| renderer.upload_mesh(&crate::plant::visuals::shape_mesh(&shape).unwrap_or_default()))
                .collect();
            let f32x3 = |v: [f64; 3]| v.map(|x| x as f32);
            let cameras = twin
                .scene()
                .cameras
                .iter()
                .map(|c| {
                    let cam = crate::output::render::Camera {
                        eye_in_world: f32x3(c.position_m),
                        target_in_world: f32x3(c.target_m),
                        up_in_world: [0.0, 0.0, 1.0],
                        fov_y_deg: c.fov_deg as f32,
                        width_px: c.width,
                        height_px: c.height,
                    };
                    (c.name.clone(), cam, c.fps, 0u64, c.show_sensors)
                })
                .collect();
            Ok(Frames {
                inner: Some(FramesInner {
                    renderer,
                    meshes,
                    part_meshes,
                    dir: dir.to_path_buf(),
                    cameras,
                    at_s: None,
                    only: None,
                }),
                written: 0,
                kept: None,
            })
        }
        #[cfg(not(feature = "render"))]
        {
            let _ = (twin, dir);
            eprintln!("twin was built without the `render` feature: frames are not rendered");
            Ok(Frames { written: 0, kept: None })
        }
    }

    /// Instead of every camera's frames at its fps, one picture of each
    /// camera at the first update at or after `time_s`, written as
    /// `<camera>-t<time>.png` (`twin run --frames-at`, `twin test
    /// --artifacts`).
    #[must_use]
    #[cfg_attr(not(feature = "render"), allow(unused_mut))]
    pub fn only_at(mut self, time_s: f64) -> Frames {
        #[cfg(feature = "render")]
        if let Some(inner) = self.inner.as_mut() {
            inner.at_s = Some(time_s);
        }
        #[cfg(not(feature = "render"))]
        let _ = time_s;
        self
    }

    /// Only the frames numbered `numbers` (of every camera) are rendered,
    /// under their usual names; the others are passed over (`twin run
    /// --frames-only`, what `twin test` asks for a scene's `[snapshots]`).
    #[must_use]
    #[cfg_attr(not(feature = "render"), allow(unused_mut))]
    pub fn only_numbers(mut self, numbers: &[u64]) -> Frames {
        #[cfg(feature = "render")]
        if let Some(inner) = self.inner.as_mut() {
            inner.only = Some(numbers.to_vec());
        }
        #[cfg(not(feature = "render"))]
        let _ = numbers;
        self
    }

    /// Renders the cameras whose next frame time has come (frame `k` of a
    /// camera is due at `k / fps` seconds: the first update at or after it).
    ///
    /// # Errors
    /// [`OutputError::Frame`] when rendering or writing a PNG fails.
    pub fn capture(&mut self, twin: &Twin) -> Result<(), OutputError> {
        #[cfg(feature = "render")]
        if let Some(inner) = self.inner.as_mut() {
            let t = twin.time_s();
            let eps = 1e-9;
            let picture = match inner.at_s {
                Some(at) if t + eps >= at => true,
                Some(_) => return Ok(()),
                None => false,
            };
            let due = |next: u64, fps: f64| picture || next as f64 / fps <= t + eps;
            if let Some(only) = &inner.only
                && !picture
            {
                // At most one frame of a camera is due at an update (its fps
                // is at most the update rate): pass over one not asked for.
                for (_, _, fps, next, _) in &mut inner.cameras {
                    if due(*next, *fps) && !only.contains(next) {
                        *next += 1;
                    }
                }
            }
            if !inner.cameras.iter().any(|(_, _, fps, next, _)| due(*next, *fps)) {
                return Ok(());
            }
            let links = twin.plant().world_from_link();
            let colliding = twin.plant().colliding_links();
            let items: Vec<crate::output::render::DrawItem> = twin
                .plant()
                .visuals()
                .iter()
                .zip(&inner.meshes)
                .map(|(p, id)| crate::output::render::DrawItem {
                    mesh: *id,
                    world_from_mesh: column_major(&world_from_visual(p, links)),
                    color_rgba: p.color_rgba,
                    tint_rgba: p.link.filter(|l| colliding.contains(l)).map(|_| COLLISION_TINT_RGBA),
                })
                .collect();
            // Tool-centre trails of the coordinate systems, orange.
            let lines: Vec<crate::output::render::LineStrip> = twin
                .plant()
                .tool_trails()
                .iter()
                .map(|t| crate::output::render::LineStrip {
                    points_in_world: t.points_in_world.iter().map(|p| p.map(|x| x as f32)).collect(),
                    color_rgba: [1.0, 0.45, 0.0, 1.0],
                })
                .collect();
            let mut items = items;
            if let Some(m) = twin.plant().material() {
                let types = &twin.scene().cell.part_types;
                items.extend(m.parts().iter().map(|p| crate::output::render::DrawItem {
                    mesh: inner.part_meshes[p.part_type],
                    world_from_mesh: column_major(&crate::plant::convert::pose_from_rapier(&m.part_pose(p))),
                    color_rgba: types[p.part_type].color.map(|c| c as f32),
                    tint_rgba: None,
                }));
                let cylinders = &twin.scene().cell.cylinders;
                items.extend(m.cylinders().zip(cylinders).enumerate().map(|(k, (c, def))| {
                    crate::output::render::DrawItem {
                        mesh: inner.part_meshes[types.len() + k],
                        world_from_mesh: column_major(&c.world_from_box()),
                        color_rgba: def.color.map(|x| x as f32),
                        tint_rgba: None,
                    }
                }));
            }
            // The sensors' beams and rays: green clear, red detecting.
            let isometries: Vec<nalgebra::Isometry3<f64>> =
                links.iter().map(crate::plant::convert::isometry_from_arrays).collect();
            let mut sensor_lines = lines.clone();
            for s in twin.plant().sensors() {
                let color = if s.output() {
                    [0.9, 0.1, 0.1, 1.0]
                } else {
                    [0.1, 0.8, 0.2, 1.0]
                };
                for (a, b) in s.lines_in_world(&isometries) {
                    sensor_lines.push(crate::output::render::LineStrip {
                        points_in_world: vec![a.map(|x| x as f32), b.map(|x| x as f32)],
                        color_rgba: color,
                    });
                }
            }
            for (name, cam, fps, next, show_sensors) in &mut inner.cameras {
                if !due(*next, *fps) {
                    continue;
                }
                let drawn = if *show_sensors { &sensor_lines } else { &lines };
                let image = inner
                    .renderer
                    .render(cam, &items, drawn)
                    .map_err(|e| OutputError::Frame {
                        path: inner.dir.clone(),
                        message: e.to_string(),
                    })?;
                let path = if picture {
                    inner
                        .dir
                        .join(format!("{name}-t{}.png", crate::output::trace::number(t)))
                } else {
                    inner.dir.join(format!("{name}-{next:05}.png"))
                };
                write_png(&path, &image).map_err(|e| OutputError::Frame {
                    path: path.clone(),
                    message: e.to_string(),
                })?;
                if let Some((max_width, kept)) = &mut self.kept {
                    kept.push(kept_image(name, &image, *max_width));
                }
                *next += 1;
                self.written += 1;
            }
            if picture {
                // Taken: no frame after it.
                inner.at_s = Some(f64::INFINITY);
            }
        }
        #[cfg(not(feature = "render"))]
        let _ = twin;
        Ok(())
    }

    /// PNG files written so far.
    pub fn written(&self) -> usize {
        self.written
    }

    /// Keeps a copy of each frame rendered from now on, scaled down to at
    /// most `max_width_px` wide, for [`Frames::take_images`]
    /// (`--save-frames`: the recording logs them).
    pub fn keep_images(&mut self, max_width_px: u32) {
        self.kept = Some((max_width_px.max(1), Vec::new()));
    }

    /// The frames kept since the last call ([`Frames::keep_images`]).
    pub fn take_images(&mut self) -> Vec<KeptImage> {
        self.kept.as_mut().map(|(_, k)| std::mem::take(k)).unwrap_or_default()
    }

    /// Frames in the folder named like this run's (`<camera>-<frame>.png`)
    /// but past the last frame it wrote: left by an earlier, longer run.
    /// They are not removed (they may be someone's); the caller says so.
    pub fn stale(&self) -> Vec<PathBuf> {
        #[cfg(feature = "render")]
        if let Some(inner) = &self.inner {
            let Ok(entries) = std::fs::read_dir(&inner.dir) else {
                return Vec::new();
            };
            let mut stale: Vec<PathBuf> = entries
                .filter_map(Result::ok)
                .map(|e| e.path())
                .filter(|p| {
                    let Some(file) = p.file_name().and_then(|f| f.to_str()) else {
                        return false;
                    };
                    inner.cameras.iter().any(|(name, _, _, next, _)| {
                        file.strip_prefix(name.as_str())
                            .and_then(|rest| rest.strip_prefix('-'))
                            .and_then(|rest| rest.strip_suffix(".png"))
                            .filter(|digits| digits.len() >= 5 && digits.bytes().all(|b| b.is_ascii_digit()))
                            .and_then(|digits| digits.parse::<u64>().ok())
                            .is_some_and(|frame| frame >= *next)
                    })
                })
                .collect();
            stale.sort();
            return stale;
        }
        Vec::new()
    }
}

/// Whether a frame of one of `cameras` may be written under `file_name`
/// in the `--frames` folder: `<camera>-<frame>.png`, or
/// `<camera>-t<seconds>.png` with `--frames-at`. Another file in that
/// folder (a trace, a summary) is left alone by the frames.
pub fn frame_may_take(file_name: &str, cameras: &[crate::scene::Camera]) -> bool {
    cameras.iter().any(|c| {
        file_name
            .strip_prefix(c.name.as_str())
            .and_then(|rest| rest.strip_prefix('-'))
            .is_some_and(|rest| rest.len() > ".png".len() && rest.to_ascii_lowercase().ends_with(".png"))
    })
}

/// The recording of a twin built without the `rerun` feature: it logs
/// nothing, and refuses to be asked for a file or a viewer.
#[cfg(not(feature = "rerun"))]
#[derive(Debug)]
pub struct Recording;

#[cfg(not(feature = "rerun"))]
impl Recording {
    /// Succeeds when no recording is asked for.
    ///
    /// # Errors
    /// [`OutputError::NoRerun`] naming the first flag that asks for one.
    pub fn new(_twin: &Twin, targets: &crate::output::RecordingTargets) -> Result<Recording, OutputError> {
        match targets.first_flag() {
            Some(flag) => Err(OutputError::NoRerun { flag }),
            None => Ok(Recording),
        }
    }

    /// Logs nothing.
    ///
    /// # Errors
    /// Never.
    pub fn log(&mut self, _twin: &Twin) -> Result<(), OutputError> {
        Ok(())
    }

    /// Logs nothing.
    pub fn images(&mut self, _twin: &Twin, _images: Vec<KeptImage>) {}

    /// Nothing to flush.
    pub fn finish(self, _twin: &Twin) -> Finished {
        Finished {
            served: Served,
            files_complete: true,
            failures: Vec::new(),
        }
    }
}

/// How a recording ended: in a twin built without the `rerun` feature,
/// with nothing recorded.
#[cfg(not(feature = "rerun"))]
#[derive(Debug, Default)]
pub struct Finished {
    /// Nothing is served.
    pub served: Served,
    /// Always true: there are no files.
    pub files_complete: bool,
    /// Always empty.
    pub failures: Vec<OutputError>,
}

/// Nothing is served by a twin built without the `rerun` feature.
#[cfg(not(feature = "rerun"))]
#[derive(Debug, Default)]
pub struct Served;

#[cfg(not(feature = "rerun"))]
impl Served {
    /// No addresses.
    pub fn addresses(&self) -> &[String] {
        &[]
    }

    /// Returns at once.
    pub fn wait(self) {}
}

/// Per-run statistics gathered each update.
#[derive(Debug, Clone)]
pub struct Stats {
    max_following_error: Vec<f64>,
    outcomes: Vec<InstructionOutcome>,
    previous: Vec<planner::instruction::FbOutputs>,
    logix_outcomes: Vec<InstructionOutcome>,
    previous_bits: Vec<MotionInstructionBits>,
    /// Per axis: its `MotionFault` word and whether its position error
    /// exceeded the tolerance, in the last update.
    previous_faults: Vec<(u32, bool)>,
    axis_faults: Vec<AxisFaultEvent>,
    axis_fault_count: u64,
}

fn is_zero(n: &u64) -> bool {
    *n == 0
}

/// The most axis fault events a summary lists (all are counted).
pub const MAX_AXIS_FAULT_EVENTS: usize = 256;

/// An axis fault as it was recorded (a rising bit of the axis'
/// `MotionFault` word, or its position error exceeding the tolerance).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AxisFaultEvent {
    /// The axis.
    pub axis: String,
    /// Simulated time of the update that recorded it, s.
    pub time_s: f64,
    /// The exception, as Logix names it: `Soft Travel Limit - Positive`,
    /// `Soft Travel Limit - Negative`, `Excessive Position Error`.
    pub fault: &'static str,
    /// The exception action the axis took (Logix's word, e.g.
    /// `StopPlanner`).
    pub action: &'static str,
    /// The actual position then, axis units.
    pub actual_position: f64,
}

/// The instruction events of a run as lines of text, as they happen
/// (`twin run -v`): a change of an instance's outputs (`MC1: .EN .IP`, with
/// the error's meaning), a controller fault, an axis fault; each with the
/// simulated time.
#[derive(Debug)]
pub struct EventLines {
    fbs: Vec<planner::instruction::FbOutputs>,
    instructions: Vec<MotionInstructionBits>,
    faults: usize,
    axes: Vec<(u32, bool)>,
}

impl EventLines {
    /// Starts from `twin`'s outputs now (no event for them).
    pub fn new(twin: &Twin) -> EventLines {
        let (task, program) = (twin.task(), twin.program());
        EventLines {
            fbs: program.fbs().iter().map(|fb| task.outputs(fb.handle)).collect(),
            instructions: program
                .instructions()
                .iter()
                .map(|ins| task.motion_bits(ins.handle))
                .collect(),
            faults: program.controller().fault_log().len(),
            axes: twin
                .plant()
                .axes()
                .iter()
                .map(|a| (task.motion_faults(a.handle).0, task.position_error_exceeded(a.handle)))
                .collect(),
        }
    }

    /// The events since the last call, one line each.
    pub fn take(&mut self, twin: &Twin) -> Vec<String> {
        let (task, program) = (twin.task(), twin.program());
        let at = format!("t = {:.3} s", twin.time_s());
        let mut lines = Vec::new();
        for (fb, previous) in program.fbs().iter().zip(&mut self.fbs) {
            let now = task.outputs(fb.handle);
            if std::mem::replace(previous, now) != now {
                lines.push(format!("{at}  {}: {}", fb.name, describe(now)));
            }
        }
        for (ins, previous) in program.instructions().iter().zip(&mut self.instructions) {
            let now = task.motion_bits(ins.handle);
            if std::mem::replace(previous, now) != now {
                lines.push(format!("{at}  {}: {}", ins.name, describe(now)));
            }
        }
        let log = program.controller().fault_log();
        lines.extend(log.iter().skip(self.faults).map(|f| format!("{at}  {f}")));
        self.faults = log.len();
        for (a, previous) in twin.plant().axes().iter().zip(&mut self.axes) {
            for f in crate::output::axis_faults::new_axis_faults(twin, a, previous) {
                lines.push(format!(
                    "{at}  axis {}: {} ({}), action {}",
                    a.name, f.fault, f.meaning, f.action
                ));
            }
        }
        lines
    }
}

/// How one instance (or control structure) did over the run. For a Logix
/// control structure `done` counts rises of `.DN` (the instruction was
/// executed: a motion instruction accepted its move, MCCP calculated its
/// profile, MSO enabled the drive), `completed` rises of `.PC` (a move
/// reached its end), `errors` rises of `.ER`, and `aborted` the times `.IP`
/// fell without `.PC` or `.ER` (the process was stopped or replaced by
/// another instruction). For a PLCopen function block `done` counts rises
/// of `Done`.
#[derive(Debug, Clone, Default, Serialize)]
pub struct InstructionOutcome {
    /// Instance name.
    pub name: String,
    /// Times `Done` (`.DN`) rose.
    pub done: u32,
    /// Times `.PC` rose (Logix control structures; absent for a function
    /// block).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub completed: Option<u32>,
    /// Times `CommandAborted` rose.
    pub aborted: u32,
    /// Times `Error` rose.
    pub errors: u32,
    /// Last non-zero ErrorID, with its meaning.
    pub last_error: Option<String>,
    /// Outputs at the end of the run, in words.
    pub final_outputs: String,
}

impl InstructionOutcome {
    /// Counts one update's rising edges: `done`, `completed` (a Logix
    /// structure's `.PC`), `aborted`, and an error (with its description)
    /// when one rose.
    fn count(&mut self, done: bool, completed: Option<bool>, aborted: bool, error: Option<String>) {
        self.done += u32::from(done);
        if let Some(pc) = completed {
            *self.completed.get_or_insert(0) += u32::from(pc);
        }
        self.aborted += u32::from(aborted);
        if let Some(error) = error {
            self.errors += 1;
            self.last_error = Some(error);
        }
    }

    /// No outcome yet for the instance or control structure `name`.
    fn named(name: &str) -> InstructionOutcome {
        InstructionOutcome {
            name: name.to_string(),
            ..InstructionOutcome::default()
        }
    }
}

/// The run summary (`--summary` JSON and the stdout text).
#[derive(Debug, Clone, Serialize)]
pub struct Summary {
    /// Scene name.
    pub scene: String,
    /// Simulated time, s.
    pub simulated_s: f64,
    /// Wall time, s.
    pub wall_s: f64,
    /// Simulated / wall time.
    pub real_time_factor: f64,
    /// Coarse updates run.
    pub updates: u64,
    /// Which plant ran: `physics` or `kinematic` (scene `plant`, `--plant`).
    pub plant: &'static str,
    /// Per function-block instance (program order), then per control
    /// structure (program order).
    pub instructions: Vec<InstructionOutcome>,
    /// Per axis: name and max |command − actual| in axis units.
    pub max_following_error: Vec<(String, f64)>,
    /// Per axis with a servo drive: name and the largest |torque| of any
    /// physics substep, N·m or N (empty without servo drives).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub max_torque: Vec<(String, f64)>,
    /// PNG frames written.
    pub frames_written: usize,
    /// Collision events (scenes with `[collision]`), in start order.
    pub collisions: Vec<crate::plant::collision::monitor::CollisionEvent>,
    /// Collisions predicted by the pre-flight sweep.
    pub predicted_collisions: Vec<crate::plant::collide::Prediction>,
    /// Per collision body: the smallest clearance over the run, m (null: no obstacle).
    pub min_clearance_m: Vec<(String, Option<f64>)>,
    /// Whether an `abort` collision reaction ended the run early.
    pub collision_abort: bool,
    /// A scene that names a Studio 5000 export: the export, what it holds
    /// that the twin does not simulate, and what `not_simulated` skipped.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub l5x: Option<L5xSummary>,
    /// Axis faults in the order they were recorded (at most
    /// [`MAX_AXIS_FAULT_EVENTS`]; empty: none).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub axis_faults: Vec<AxisFaultEvent>,
    /// How many axis faults were recorded in all.
    #[serde(skip_serializing_if = "is_zero")]
    pub axis_fault_count: u64,
    /// Set when the physics state diverged (non-finite, or a joint or link ran away) and stopped the run.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub physics_fault: Option<crate::plant::PhysicsFault>,
    /// Set when `twin run --max-wall S` stopped the run: the wall-time
    /// limit, s, and the simulated time reached.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub wall_limit: Option<WallLimit>,
    /// Scenes with `[[tasks]]`: what the tasks did and cost, and their
    /// faults.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tasks: Option<TasksSummary>,
    /// The variant that ran (`twin run --variant`), if any.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub variant: Option<String>,
    /// Each `[[expect]]`'s result (empty: the scene has none).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub expectations: Vec<crate::output::expect::Outcome>,
    /// Scenes with parts: what became of them.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub parts: Option<PartsSummary>,
    /// Per sensor: its output's edges, time on and missed pulses.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub sensors: Vec<SensorSummary>,
    /// Per scheduled output module (a tag's `scheduled_output`): every
    /// switch, at its interpolated time, with when its device acted and
    /// where the axis was then.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub scheduled_outputs: Vec<ScheduledOutputSummary>,
}

/// A run stopped by `--max-wall` between two coarse updates.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct WallLimit {
    /// The limit, s of wall time.
    pub max_wall_s: f64,
    /// Simulated time the run reached, s.
    pub time_s: f64,
}

/// One scheduled output module's part of the summary.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ScheduledOutputSummary {
    /// The Output tag.
    pub tag: String,
    /// Its switches in time order.
    pub switches: Vec<crate::run::ScheduledSwitch>,
}

/// What a scene took from its Studio 5000 export, in the summary.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct L5xSummary {
    /// The export, as the scene names it.
    pub file: String,
    /// What is not simulated: `L5X line: what`.
    pub not_simulated: Vec<String>,
    /// What `[controller] not_simulated` skipped (`Program/Routine`).
    pub skipped: Vec<String>,
}

/// The parts' part of the summary.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PartsSummary {
    /// Parts spawned.
    pub spawned: u64,
    /// Parts taken by a `delivered` sink.
    pub delivered: u64,
    /// Parts taken by a `rejected` sink.
    pub rejected: u64,
    /// Parts a gripper dropped.
    pub dropped: u64,
    /// Parts that fell out of the cell (1 m under its lowest surface).
    pub lost: u64,
    /// Parts still in the cell at the end.
    pub in_process: u64,
    /// Delivered parts per minute of simulated time.
    pub throughput_per_min: f64,
    /// Mean time from spawn to delivery, s (null: none delivered).
    pub flow_time_s: Option<f64>,
    /// The largest offset of a held part from the gripper's TCP at its
    /// pick, mm (null: nothing was picked).
    pub max_pick_offset_mm: Option<f64>,
    /// Per sink: name and parts taken.
    pub per_sink: Vec<(String, u64)>,
    /// Set when a source stopped at the live-part limit.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub capped: bool,
    /// The first part events (at most 1,000).
    pub events: Vec<crate::plant::material::PartEvent>,
}

/// One sensor's part of the summary.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SensorSummary {
    /// The sensor.
    pub name: String,
    /// Rising edges of its output.
    pub edges: u64,
    /// Time its output was on, s.
    pub on_s: f64,
    /// Output pulses no input update saw (a design fault: raise the RPI
    /// rate, use COS, or stretch the pulse).
    pub missed_pulses: u64,
}

/// One task's part of the summary (its `TASK` object's values at the end).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TaskSummary {
    /// The task.
    pub name: String,
    /// Scans started.
    pub scans: i64,
    /// Triggers ignored because the task was still running or waiting.
    pub overlaps: i64,
    /// The last scan's elapsed time, µs.
    pub last_scan_us: i64,
    /// The longest scan's elapsed time, µs.
    pub max_scan_us: i64,
}

/// The task engine's part of the summary.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TasksSummary {
    /// Program scans run.
    pub scans: u64,
    /// Statements executed.
    pub statements: u64,
    /// Wall time spent in the tasks, s.
    pub task_wall_s: f64,
    /// That wall time as a share of the run's.
    pub task_share: f64,
    /// The major fault that stopped the run, if any.
    pub major_fault: Option<crate::program::controller::Fault>,
    /// Minor faults recorded (all counted).
    pub minor_fault_count: i64,
    /// The first minor faults, in order.
    pub minor_faults: Vec<crate::program::controller::Fault>,
    /// Major faults a program's fault routine cleared, in order.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub cleared_faults: Vec<crate::program::controller::Fault>,
    /// Each task's scans, scan times and overlaps, in scene order.
    pub per_task: Vec<TaskSummary>,
    /// Motion instructions whose operand values were refused at run time
    /// (the first 1,000).
    pub refused: Vec<String>,
    /// How many refusals there were in all.
    pub refused_count: u64,
}

impl Stats {
    /// Empty statistics for `twin`'s axes and instances.
    pub fn new(twin: &Twin) -> Stats {
        Stats {
            max_following_error: vec![0.0; twin.plant().axes().len()],
            outcomes: twin
                .program()
                .fbs()
                .iter()
                .map(|f| InstructionOutcome::named(&f.name))
                .collect(),
            previous: vec![Default::default(); twin.program().fbs().len()],
            logix_outcomes: twin
                .program()
                .instructions()
                .iter()
                .map(|b| InstructionOutcome::named(&b.name))
                .collect(),
            previous_bits: vec![Default::default(); twin.program().instructions().len()],
            previous_faults: vec![(0, false); twin.plant().axes().len()],
            axis_faults: Vec::new(),
            axis_fault_count: 0,
        }
    }

    /// Records the faults that rose on `axis` (index `i`) this update: a
    /// bit of its `MotionFault` word, or its position error exceeding the
    /// tolerance (unless that exception's action is Ignore).
    fn observe_faults(&mut self, twin: &Twin, i: usize, axis: &crate::plant::axes::AxisBinding) {
        for f in crate::output::axis_faults::new_axis_faults(twin, axis, &mut self.previous_faults[i]) {
            self.axis_fault_count += 1;
            if self.axis_faults.len() < MAX_AXIS_FAULT_EVENTS {
                self.axis_faults.push(AxisFaultEvent {
                    axis: axis.name.clone(),
                    time_s: twin.time_s(),
                    fault: f.fault,
                    action: f.action,
                    actual_position: twin.task().axis_state(axis.handle).actual_position,
                });
            }
        }
    }

    /// Takes in the current update.
    pub fn observe(&mut self, twin: &Twin) {
        for (i, a) in twin.plant().axes().iter().enumerate() {
            let s = twin.task().axis_state(a.handle);
            let e = (s.command_position - s.actual_position).abs();
            if e > self.max_following_error[i] {
                self.max_following_error[i] = e;
            }
            self.observe_faults(twin, i, a);
        }
        for (i, fb) in twin.program().fbs().iter().enumerate() {
            let o = twin.task().outputs(fb.handle);
            let p = std::mem::replace(&mut self.previous[i], o);
            let error = (o.error && !p.error).then(|| {
                format!(
                    "16#{:04X}: {}",
                    o.error_id,
                    planner::modulo::ErrorId(o.error_id).meaning()
                )
            });
            self.outcomes[i].count(o.done && !p.done, None, o.command_aborted && !p.command_aborted, error);
        }
        for (i, ins) in twin.program().instructions().iter().enumerate() {
            let b = twin.task().motion_bits(ins.handle);
            let p = std::mem::replace(&mut self.previous_bits[i], b);
            let error = (b.er && !p.er).then(|| error_codes(b));
            self.logix_outcomes[i].count(
                b.dn && !p.dn,
                Some(b.pc && !p.pc),
                p.ip && !b.ip && !b.pc && !b.er,
                error,
            );
        }
    }

    /// The summary at the end of the run.
    pub fn summary(&self, twin: &Twin, wall_s: f64, frames_written: usize) -> Summary {
        let mut instructions = self.outcomes.clone();
        for (out, fb) in instructions.iter_mut().zip(twin.program().fbs()) {
            out.final_outputs = describe(twin.task().outputs(fb.handle));
        }
        for (out, ins) in self.logix_outcomes.iter().zip(twin.program().instructions()) {
            let mut out = out.clone();
            out.final_outputs = describe(twin.task().motion_bits(ins.handle));
            instructions.push(out);
        }
        Summary {
            scene: twin.scene().name.clone(),
            simulated_s: twin.time_s(),
            wall_s,
            real_time_factor: if wall_s > 0.0 {
                twin.time_s() / wall_s
            } else {
                f64::INFINITY
            },
            updates: twin.task().updates(),
            plant: twin.scene().plant.name(),
            instructions,
            max_following_error: twin
                .plant()
                .axes()
                .iter()
                .zip(&self.max_following_error)
                .map(|(a, e)| (a.name.clone(), *e))
                .collect(),
            max_torque: twin
                .plant()
                .axes()
                .iter()
                .enumerate()
                .filter_map(|(k, a)| Some((a.name.clone(), twin.plant().drive_peak_torque(k)?)))
                .collect(),
            frames_written,
            collisions: twin.plant().collision_events().to_vec(),
            predicted_collisions: twin.plant().predicted_collisions().to_vec(),
            min_clearance_m: twin
                .plant()
                .collision_bodies()
                .into_iter()
                .zip(twin.plant().min_clearance_m())
                .map(|(b, d)| (b, d.is_finite().then_some(d)))
                .collect(),
            collision_abort: twin.plant().collision_abort(),
            l5x: twin.scene().l5x.as_ref().map(|l| L5xSummary {
                file: l.path.display().to_string(),
                not_simulated: l.report.iter().map(|(line, text)| format!("{line}: {text}")).collect(),
                skipped: l.skipped.clone(),
            }),
            axis_faults: self.axis_faults.clone(),
            axis_fault_count: self.axis_fault_count,
            physics_fault: twin.plant().physics_fault().cloned(),
            wall_limit: None,
            tasks: (!twin.scene().tasks.is_empty()).then(|| {
                let c = twin.program().controller();
                let task_wall_s = c.stats().wall.as_secs_f64();
                TasksSummary {
                    scans: c.stats().scans,
                    statements: c.stats().statements,
                    task_wall_s,
                    task_share: if wall_s > 0.0 { task_wall_s / wall_s } else { 0.0 },
                    major_fault: c.major_fault().cloned(),
                    minor_fault_count: c.minor_fault_count(),
                    minor_faults: c.minor_faults().to_vec(),
                    cleared_faults: c.cleared_faults().to_vec(),
                    per_task: c
                        .system()
                        .tasks
                        .iter()
                        .map(|t| TaskSummary {
                            name: t.name.clone(),
                            scans: t.scans,
                            overlaps: t.overlap_count,
                            last_scan_us: t.last_scan_us,
                            max_scan_us: t.max_scan_us,
                        })
                        .collect(),
                    refused: c.refusals().to_vec(),
                    refused_count: c.refusal_count(),
                }
            }),
            variant: twin.scene().variant.clone(),
            expectations: Vec::new(),
            parts: twin
                .plant()
                .material()
                .filter(|_| !twin.scene().cell.part_types.is_empty())
                .map(|m| {
                    let c = m.counts();
                    PartsSummary {
                        spawned: c.spawned,
                        delivered: c.delivered,
                        rejected: c.rejected,
                        dropped: c.dropped,
                        lost: c.lost,
                        in_process: m.parts().len() as u64,
                        throughput_per_min: if twin.time_s() > 0.0 {
                            c.delivered as f64 * 60.0 / twin.time_s()
                        } else {
                            0.0
                        },
                        flow_time_s: (c.delivered > 0).then(|| c.delivered_flow_s / c.delivered as f64),
                        max_pick_offset_mm: c.max_pick_offset_m.map(|m| m * 1000.0),
                        per_sink: twin
                            .scene()
                            .cell
                            .sinks
                            .iter()
                            .zip(&c.per_sink)
                            .map(|(s, n)| (s.name.clone(), *n))
                            .collect(),
                        capped: c.capped,
                        events: m.events().to_vec(),
                    }
                }),
            sensors: twin
                .plant()
                .sensors()
                .iter()
                .map(|s| {
                    let st = s.stats(twin.time_s());
                    SensorSummary {
                        name: s.name.clone(),
                        edges: st.edges,
                        on_s: st.on_s,
                        missed_pulses: st.missed_pulses,
                    }
                })
                .collect(),
            scheduled_outputs: twin
                .scheduled_switches()
                .map(|(tag, switches)| ScheduledOutputSummary {
                    tag: tag.to_owned(),
                    switches: switches.to_vec(),
                })
                .collect(),
        }
    }
}

impl Summary {
    /// Whether any instance reported an error during the run.
    pub fn any_error(&self) -> bool {
        self.instructions.iter().any(|i| i.errors > 0)
    }

    /// How many expectations failed.
    pub fn failed_expectations(&self) -> usize {
        self.expectations.iter().filter(|e| !e.passed).count()
    }

    /// The summary as pretty JSON.
    pub fn json(&self) -> String {
        let mut s = serde_json::to_string_pretty(self).unwrap_or_else(|e| format!("{{\"error\": \"{e}\"}}"));
        s.push('\n');
        s
    }

    /// The summary as text for a person.
    pub fn human(&self) -> String {
        let mut s = String::new();
        let _ = writeln!(
            s,
            "scene {}{}: {:.3} s simulated in {:.3} s wall, real-time factor {:.2} ({} updates)",
            self.scene,
            self.variant.as_ref().map_or(String::new(), |v| format!("[{v}]")),
            self.simulated_s,
            self.wall_s,
            self.real_time_factor,
            self.updates
        );
        if self.plant != crate::scene::PlantMode::Physics.name() {
            let _ = writeln!(
                s,
                "  plant: {} (the joints follow the setpoints; no dynamics, no following error)",
                self.plant
            );
        }
        for i in &self.instructions {
            let _ = match i.completed {
                Some(completed) => write!(
                    s,
                    "  {}: done {}, completed {}, aborted {}, errors {}; now {}",
                    i.name, i.done, completed, i.aborted, i.errors, i.final_outputs
                ),
                None => write!(
                    s,
                    "  {}: done {}, aborted {}, errors {}; now {}",
                    i.name, i.done, i.aborted, i.errors, i.final_outputs
                ),
            };
            if let Some(e) = &i.last_error {
                let _ = write!(s, "; last error {e}");
            }
            s.push('\n');
        }
        for (name, e) in &self.max_following_error {
            let _ = writeln!(s, "  axis {name}: max |cmd - act| = {e:.6}");
        }
        for (name, t) in &self.max_torque {
            let _ = writeln!(s, "  axis {name}: max |torque| = {t:.3}");
        }
        for f in &self.axis_faults {
            let _ = writeln!(
                s,
                "  axis {}: {} at {:.3} s (actual position {:.6}), action {}",
                f.axis, f.fault, f.time_s, f.actual_position, f.action
            );
        }
        if self.axis_fault_count > self.axis_faults.len() as u64 {
            let _ = writeln!(
                s,
                "  … {} axis faults in all (the first {} listed)",
                self.axis_fault_count,
                self.axis_faults.len()
            );
        }
        for e in &self.collisions {
            let end = e
                .end_s
                .map_or_else(|| "end of run".to_string(), |t| format!("{t:.4} s"));
            let _ = writeln!(
                s,
                "  collision {} <-> {}: {:.4} s .. {end}, max depth {:.4} m at [{:.4}, {:.4}, {:.4}], normal [{:.3}, {:.3}, {:.3}]",
                e.a,
                e.b,
                e.start_s,
                e.deepest.depth_m,
                e.deepest.point_in_world[0],
                e.deepest.point_in_world[1],
                e.deepest.point_in_world[2],
                e.deepest.normal_in_world[0],
                e.deepest.normal_in_world[1],
                e.deepest.normal_in_world[2]
            );
        }
        for p in &self.predicted_collisions {
            let _ = writeln!(
                s,
                "  pre-flight {} (started {:.4} s): {} <-> {} at parameter {:.4} (at {:.4} s, bound {:.2e}){}",
                p.instance,
                p.started_s,
                p.collision.a,
                p.collision.b,
                p.collision.parameter,
                p.predicted_at_s,
                p.collision.bound,
                if p.rejected { ", rejected" } else { "" }
            );
            if let Some(why) = &p.out_of_reach {
                let _ = writeln!(s, "    out of reach of the transform: {why}");
            }
        }
        for (b, d) in &self.min_clearance_m {
            if let Some(d) = d {
                let _ = writeln!(s, "  {b}: min clearance {d:.5} m");
            }
        }
        if self.collision_abort {
            let _ = writeln!(s, "  run aborted by a collision");
        }
        if let Some(f) = &self.physics_fault {
            let _ = writeln!(s, "  run stopped: {f}");
        }
        if let Some(t) = &self.tasks {
            let _ = writeln!(
                s,
                "  tasks: {} scans, {} statements, {:.3} s wall ({:.1} % of the run)",
                t.scans,
                t.statements,
                t.task_wall_s,
                100.0 * t.task_share
            );
            let fault_line = |s: &mut String, what: &str, f: &crate::program::controller::Fault| {
                let _ = writeln!(
                    s,
                    "  {what} type {} code {} at {:.3} s: task {}, program {}, {}:{}: {}",
                    f.fault_type,
                    f.code,
                    f.time_s,
                    f.task,
                    f.program,
                    f.routine.display(),
                    f.line,
                    f.message
                );
            };
            if let Some(f) = &t.major_fault {
                fault_line(&mut s, "MAJOR FAULT", f);
            }
            for f in &t.cleared_faults {
                fault_line(&mut s, "cleared fault", f);
            }
            if t.minor_fault_count > 0 {
                let _ = writeln!(s, "  minor faults: {}", t.minor_fault_count);
                for f in t.minor_faults.iter().take(5) {
                    let _ = writeln!(
                        s,
                        "    type {} code {} at {:.3} s: {}:{}: {}",
                        f.fault_type,
                        f.code,
                        f.time_s,
                        f.routine.display(),
                        f.line,
                        f.message
                    );
                }
            }
            for r in &t.refused {
                let _ = writeln!(s, "  refused at run time: {r}");
            }
            if t.refused_count > t.refused.len() as u64 {
                let _ = writeln!(
                    s,
                    "  refused at run time: {} more not listed ({} in all)",
                    t.refused_count - t.refused.len() as u64,
                    t.refused_count
                );
            }
        }
        if let Some(p) = &self.parts {
            let _ = writeln!(
                s,
                "  parts: {} spawned, {} delivered, {} rejected, {} dropped, {} lost, {} in process; {:.1} per min{}",
                p.spawned,
                p.delivered,
                p.rejected,
                p.dropped,
                p.lost,
                p.in_process,
                p.throughput_per_min,
                p.flow_time_s
                    .map_or(String::new(), |f| format!(", mean flow time {f:.3} s"))
            );
            if p.capped {
                let _ = writeln!(
                    s,
                    "  parts: a source stopped at the {} live-part limit",
                    crate::scene::MAX_LIVE_PARTS
                );
            }
        }
        for x in &self.sensors {
            let _ = writeln!(
                s,
                "  sensor {}: {} edges, on {:.3} s{}",
                x.name,
                x.edges,
                x.on_s,
                if x.missed_pulses > 0 {
                    format!(", {} pulses missed by the input module", x.missed_pulses)
                } else {
                    String::new()
                }
            );
        }
        for o in &self.scheduled_outputs {
            let _ = writeln!(s, "  scheduled output {}: {} switches", o.tag, o.switches.len());
            for w in o.switches.iter().take(20) {
                let _ = writeln!(
                    s,
                    "    bit {} {} at {:.6} s, device at {:.6} s, axis at {:.4}",
                    w.bit,
                    if w.on { "on " } else { "off" },
                    w.switch_s,
                    w.device_s,
                    w.axis_position
                );
            }
        }
        let _ = writeln!(s, "  frames written: {}", self.frames_written);
        if !self.expectations.is_empty() {
            let failed = self.failed_expectations();
            let _ = writeln!(
                s,
                "expectations: {} passed, {failed} failed",
                self.expectations.len() - failed
            );
            for e in &self.expectations {
                let _ = writeln!(s, "  {} {}", if e.passed { "PASS" } else { "FAIL" }, e.message);
            }
        }
        s
    }
}

#[cfg(all(test, feature = "render"))]
mod kept_tests {
    /// A kept frame is RGB and at most the given width, its aspect kept.
    #[test]
    fn kept_frames_are_scaled_down_to_the_width() {
        let image = image::RgbaImage::from_fn(1280, 720, |x, y| {
            image::Rgba([(x % 256) as u8, (y % 256) as u8, 7, 255])
        });
        let (name, rgb, size) = super::kept_image("iso", &image, 640);
        assert_eq!((name.as_str(), size), ("iso", [640, 360]));
        assert_eq!(rgb.len(), 640 * 360 * 3);
        assert!(
            rgb.chunks_exact(3).all(|p| p[2] == 7),
            "the blue channel, alpha dropped"
        );
        let small = image::RgbaImage::new(320, 200);
        let (_, rgb, size) = super::kept_image("iso", &small, 640);
        assert_eq!((size, rgb.len()), ([320, 200], 320 * 200 * 3), "not scaled up");
    }
}
