//! What a twin run logs to Rerun, where, and the layout the recording
//! opens with.
//!
//! # Identity
//!
//! Every scene records under one application id, [`APPLICATION_ID`], so a
//! layout a user saves in the viewer applies to every scene; the recording
//! is named after the scene, and its id is `<scene>-<unix time in ms>`.
//!
//! # Entities
//!
//! Every trace column (`output::trace`) has its line in the recording,
//! named after the column (`SeriesLines` names: `J1.cmd_pos`, `MC1.EN`,
//! `Main.State`); the lines of one thing share an entity, so a view shows
//! them together and the recording stays small (heavy_arm: 95 entities,
//! layout included).
//!
//! | entity | what | when |
//! | --- | --- | --- |
//! | `<robot>` | the root link's named frame, static | once |
//! | `<robot>/visual_geometries/<link>/<visual>` | link meshes in their link's named frame, static (Rerun's URDF importer's paths: `<visual>` is the visual's `name` or `visual_<i>`) | once |
//! | `tf_static` | the joints' origins between their links' frames, static | once |
//! | `transforms` | each joint's child link in its parent's frame, and the root link in the world (`tf#/`) | when a pose changes |
//! | `<robot>/collision_highlight/<link>/<k>` | red copies of a colliding link's visuals | while it collides |
//! | `cameras/<camera>` | the scene camera as a pinhole (pose, field of view, size), static; with `--save-frames` its frames (at most 640 px wide) | once; per frame |
//! | `obstacles/<part>`, `conveyors/<part>` | fixed parts, static | once |
//! | `axes/<axis>/position` | `cmd_pos`, `act_pos` (and `sup_pos`) | when a value changes |
//! | `axes/<axis>/velocity` | `cmd_vel`, `act_vel` (not traced), `sup_vel` | when a value changes |
//! | `axes/<axis>/torque` | the servo drive's torque | when it changes |
//! | `axes/acceleration` | every axis' `cmd_acc` | when a value changes |
//! | `axes/status` | every axis' status columns: cam and transform bits, `CIPAxisState`, `AxisFault`, `MotionFault`, `overshoot` | when a value changes |
//! | `instructions/<instance>` | its outputs (`Done` … `ErrorID`; `EN` … `SEGMENT`) as lines, and its state lane (`IP`, `PC`, `ER 54`, `Error 16#4605`; a gap while idle) | when they change |
//! | `instructions/log` | one line per change of an instruction's outputs, with the error's meaning | on change |
//! | `coordinate_systems/<cs>/status`, `…/tool` | status bits (and MCT's), tool centre | when a value changes |
//! | `collisions/count`, `collisions/clearance` | collision events so far; each body's clearance, m | when a value changes |
//! | `cell/sensors`, `cell/conveyors`, `cell/grippers`, `cell/cylinders`, `cell/parts` | the cell's columns | when a value changes |
//! | `tags/<program>`, `tags` | a program's (a controller's) `[trace] tags`: a line each, and a state lane each for BOOL and integer tags | when a value changes |
//! | `tags/<reference>` | a traced string: its text as a text log line and a state lane | when it changes |
//! | `program/<program>/<routine>/<rung>` | each `[trace] rungs` entry: the rung's condition-out, 0/1, and its lane | when it changes |
//! | `plant/kinematic` | 1 in a run of the kinematic plant | once |
//! | `routines/<program>/<routine>` | the routine's text, a Markdown document, static | once |
//! | `tool_trails/<system>/<k>` | the tool-centre path, piece `k` (m, world; systems sharing a tool link share the first one's trail) | every 100 updates and at the end, the new part only |
//! | `collisions/contacts` | contact normals scaled by depth | when the contacts change |
//! | `collisions/log` | collision events and pre-flight predictions | as they happen |
//! | `controller/log` | each controller fault record (major, minor, cleared: time, type, code, task, program, routine, line, what it means) and each axis fault (Excessive Position Error, soft travel limits: what it means, its action) | at the update they happen in |
//! | `parts/<id>`, `cylinders/<name>`, `sensors/<name>` | the parts world's bodies and the sensors' beams | as they move |
//!
//! A series is logged where its value changes, and also at the update
//! before a change (so a plot steps instead of ramping between two
//! changes) and at the last update: its value at every update is the
//! latest sample at or before it, which equals the trace. Samples are
//! gathered per series and sent as one column (Rerun's columnar API, a
//! fraction of the cost of logging them one by one): every
//! [`FLUSH_UPDATES`] updates; whenever the recording thread is idle with
//! [`IDLE_FLUSH_UPDATES`] gathered, a threshold that doubles with each such
//! flush up to [`FLUSH_UPDATES`] (early flushes leave little to send after
//! the last update of a short run; few, long columns keep a long run's
//! chunks — and the memory Rerun keeps per chunk for the file's footer —
//! few); and at the end; for a live viewer also every [`LIVE_FLUSH`] of
//! wall time.
//!
//! # Threads
//!
//! The run's thread copies each update's numbers (link poses, axis
//! values, instruction outputs, tags, clearances) into a batch and hands
//! it over every [`BATCH_UPDATES`] updates; a `twin_recording` thread
//! starts the stream, logs the static meshes, and does everything else, so
//! that Rerun's encoding and writing overlap the simulation. It gives each
//! batch back emptied, to be filled again: the run's thread alone
//! allocates and frees the batches' memory (freeing it on another thread
//! would take the lock of the run's allocator arena, which the
//! simulation, allocating every step, would then wait for). The file and
//! standard-output sinks (`--save`, `--stdout`) and the viewers and
//! servers (`--connect`, `--spawn`, `--serve`) are two streams of one
//! recording (one id), each on its own thread with its own copy of the
//! batches: a viewer that accepts the connection and stops reading stalls
//! only its own thread, which is given up after [`STALL_WAIT`] without a
//! free batch slot (or at the end, [`FINISH_WAIT`]), while the file is
//! finished. At most [`BATCHES_IN_FLIGHT`] batches wait per thread (the
//! run waits beyond that), and an error on a recording thread reaches the
//! run at its next hand-over or at the end ([`Finished`]). Opening the
//! sinks (files, viewer connections) stays on the run's thread, so a bad
//! `--save` path or an absent viewer fails before the run.
//!
//! # Layout
//!
//! The recording carries a default blueprint ([`blueprint`]): the cell in
//! 3D with the robot, the cameras, the tool trails and contacts; per
//! coordinate system (and one group for the axes in none) a position, a
//! velocity and a torque view; a tab per program (and `Controller` for
//! controller-scoped tags and instructions) with a state timeline, one
//! lane per instruction and traced tag, above its routines' text; with
//! `[collision]` a clearance view; the instruction, controller and
//! collision logs; `sim_time` as the active timeline.

use super::sinks::Sink;
use super::{Recorder, RecordingError, Served, TextLevel, sim_time_ns};
use crate::output::{RecordingTargets, trace};
use crate::plant::mesh::TriMesh;
use crate::plant::visuals::column_major;
use crate::run::Twin;

mod batch;
mod fixed;
mod layout;
mod logged;
mod paths;

use batch::{Batch, Item};
pub use batch::{FLUSH_UPDATES, IDLE_FLUSH_UPDATES, LIVE_FLUSH};
use fixed::Static;
pub use layout::blueprint;
use logged::{Logged, Series};
use paths::entity_part;

/// The Rerun application id of every twin recording.
pub const APPLICATION_ID: &str = "twin";

/// Tool trails get a new piece every this many coarse updates.
const TRAIL_UPDATES: u64 = 100;

/// Updates between two logs of the parts' poses.
const PART_UPDATES: u64 = 5;

/// Streams a run to Rerun (see the module doc); a no-op when no sink is
/// asked for.
///
/// The run's thread only copies each update's numbers into a batch; a
/// recording thread (`twin_recording`) owns the [`Recorder`], keeps the
/// series, decides what changed and sends it, so that encoding and
/// writing the recording overlap the simulation.
pub struct Recording {
    inner: Option<Feed>,
}

/// Batches go to the recording thread every this many coarse updates.
pub const BATCH_UPDATES: usize = 64;

/// The longest the run waits for room to hand the recording thread a batch
/// before it drops the recording (reported; the run and its other outputs
/// go on).
pub const STALL_WAIT: std::time::Duration = std::time::Duration::from_secs(20);

/// The longest the end of a run waits for the recording to be finished
/// (the recorder's own flush and close wait 20 s each).
pub const FINISH_WAIT: std::time::Duration = std::time::Duration::from_secs(45);

/// Batches waiting for the recording thread at most; the run waits when
/// the recording falls this far behind (bounded memory).
pub const BATCHES_IN_FLIGHT: usize = 8;

/// The run's side of a recording: the batch being filled, and what it
/// needs to send only the new part of trails, events and contacts.
struct Feed {
    /// The recording threads still taking batches: one for the file and
    /// standard-output sinks, one for the viewers and servers.
    workers: Vec<Worker>,
    /// Why a recording thread was given up (the others went on).
    failures: Vec<(Part, RecordingError)>,
    batch: Batch,
    /// Batches the recording threads have emptied and given back, to be
    /// filled again (see [`Batch::clear`]).
    returned: std::sync::mpsc::Receiver<Batch>,
    /// Per tool trail: points sent so far, pieces sent so far, and
    /// whether it is logged (the first of the systems sharing its link).
    trails: Vec<(usize, usize, bool)>,
    /// The contact arrows last sent (origins, vectors).
    contacts: (Vec<[f64; 3]>, Vec<[f64; 3]>),
    logged_events: usize,
    logged_predictions: usize,
    logged_faults: usize,
    /// Each traced string's text last logged (`None` for other tags).
    logged_texts: Vec<Option<String>>,
    highlighted: Vec<usize>,
    /// The robot's root entity.
    robot: String,
    /// The update's trace values, read into.
    row: trace::Values,
    /// Per axis: its fault words last seen ([`crate::output::axis_faults::new_axis_faults`]).
    previous_faults: Vec<(u32, bool)>,
    /// The parts logged so far (ids, ascending): a part gone from the cell
    /// is cleared.
    logged_parts: Vec<u64>,
    /// Each sensor's state last logged.
    logged_sensors: Vec<Option<bool>>,
    /// Each cylinder's travel last logged, m.
    logged_cylinders: Vec<f64>,
    /// The part types' meshes and colours.
    part_meshes: Vec<(TriMesh, [f32; 4])>,
    /// With a live viewer: when the last batch was sent.
    live: Option<std::time::Instant>,
}

/// Which sinks a recording thread writes to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Part {
    /// `--save` and `--stdout`: they never wait for anyone.
    Files,
    /// `--connect`, `--spawn`, `--serve`: a viewer may stop reading.
    Viewers,
}

/// A recording thread as the run's side sees it.
struct Worker {
    part: Part,
    sender: std::sync::mpsc::SyncSender<Batch>,
    /// The thread's result, sent when it ends (it is never joined: a thread
    /// stuck on a viewer must not hold the run).
    done: std::sync::mpsc::Receiver<Result<Served, RecordingError>>,
}

/// How a recording ended.
#[derive(Debug, Default)]
pub struct Finished {
    /// The servers kept up (`--serve`).
    pub served: Served,
    /// Whether the file and standard-output sinks got everything (a
    /// `--save` file has its footer): true when there were none.
    pub files_complete: bool,
    /// Why a part of the recording did not finish (a viewer that stopped
    /// reading, a full disk); the other part is unaffected.
    pub failures: Vec<RecordingError>,
}

impl Recording {
    /// Opens the sinks asked for (none: a no-op recording) and starts the
    /// recording thread, which logs the static meshes, the series' names
    /// and colours and (with the stream) the default blueprint.
    ///
    /// # Errors
    /// [`RecordingError`] when a sink cannot be opened.
    pub fn new(twin: &Twin, targets: &RecordingTargets) -> Result<Recording, RecordingError> {
        let mut sinks = Vec::new();
        if let Some(p) = &targets.save {
            sinks.push(Sink::File(p.clone()));
        }
        if let Some(a) = &targets.connect {
            sinks.push(Sink::Connect(a.clone()));
        }
        if targets.spawn {
            sinks.push(Sink::Spawn);
        }
        if targets.stdout {
            sinks.push(Sink::Stdout);
        }
        if let Some(a) = &targets.serve {
            sinks.push(Sink::Serve(a.clone()));
        }
        if sinks.is_empty() {
            return Ok(Recording { inner: None });
        }
        // Two streams of one recording, each on its own thread, so that a
        // viewer that stops reading cannot hold up the file. The viewers are
        // opened first: an absent one fails before any file is created.
        let (files, viewers): (Vec<Sink>, Vec<Sink>) = sinks
            .into_iter()
            .partition(|s| matches!(s, Sink::File(_) | Sink::Stdout));
        let name = Some(twin.scene().name.as_str());
        let open = |sinks: &[Sink]| -> Result<Option<super::sinks::OpenSinks>, RecordingError> {
            if sinks.is_empty() {
                return Ok(None);
            }
            Recorder::open_sinks(APPLICATION_ID, name, Some(blueprint(twin)), sinks).map(Some)
        };
        let viewers = open(&viewers)?;
        let mut files = open(&files)?;
        if let (Some(f), Some(v)) = (files.as_mut(), viewers.as_ref()) {
            f.same_recording_as(v);
        }
        let (returns, returned) = std::sync::mpsc::channel();
        let mut workers = Vec::new();
        for (part, sinks) in [(Part::Files, files), (Part::Viewers, viewers)] {
            let Some(sinks) = sinks else { continue };
            let (series, styles) = Series::of(twin);
            let fixed = Static::of(twin, styles);
            let live = part == Part::Viewers;
            let (sender, receiver) = std::sync::mpsc::sync_channel(BATCHES_IN_FLIGHT);
            let (done_tx, done) = std::sync::mpsc::channel();
            let returns = returns.clone();
            std::thread::Builder::new()
                .name("twin_recording".to_owned())
                .spawn(move || {
                    let result = sinks
                        .start()
                        .and_then(|recorder| Logged::new(recorder, series, live).run(&fixed, &receiver, &returns));
                    let _ = done_tx.send(result);
                })
                .map_err(|source| RecordingError::Worker {
                    why: format!("cannot start the recording thread: {source}"),
                })?;
            workers.push(Worker { part, sender, done });
        }
        let plant = twin.plant();
        Ok(Recording {
            inner: Some(Feed {
                workers,
                failures: Vec::new(),
                batch: Batch::default(),
                returned,
                trails: plant
                    .tool_trails()
                    .iter()
                    .enumerate()
                    .map(|(i, t)| (0, 0, !plant.tool_trails()[..i].iter().any(|u| u.link == t.link)))
                    .collect(),
                contacts: (Vec::new(), Vec::new()),
                logged_events: 0,
                logged_predictions: 0,
                logged_faults: 0,
                logged_texts: Vec::new(),
                highlighted: Vec::new(),
                robot: super::robot_entity_path(&plant.model().name),
                row: trace::Values::default(),
                previous_faults: vec![(0, false); plant.axes().len()],
                logged_parts: Vec::new(),
                logged_sensors: Vec::new(),
                logged_cylinders: Vec::new(),
                part_meshes: twin
                    .scene()
                    .cell
                    .part_types
                    .iter()
                    .map(|p| {
                        (
                            crate::plant::visuals::shape_mesh(&p.shape).unwrap_or_default(),
                            p.color.map(|c| c as f32),
                        )
                    })
                    .collect(),
                live: targets.live().then(std::time::Instant::now),
            }),
        })
    }

    /// Takes in the current update; hands a batch to the recording thread
    /// when it is time to (module doc).
    ///
    /// # Errors
    /// [`RecordingError`] when the recording thread has stopped on an
    /// error (that error).
    pub fn log(&mut self, twin: &Twin) -> Result<(), RecordingError> {
        let Some(feed) = self.inner.as_mut() else {
            return Ok(());
        };
        feed.take(twin);
        let live_due = feed.live.is_some_and(|at| at.elapsed() >= LIVE_FLUSH / 4);
        if feed.batch.times_ns.len() >= BATCH_UPDATES || live_due {
            if let Some(at) = &mut feed.live {
                *at = std::time::Instant::now();
            }
            let next = feed.given_back();
            let batch = std::mem::replace(&mut feed.batch, next);
            if let Err(e) = feed.send(batch) {
                self.inner = None;
                return Err(e);
            }
        }
        Ok(())
    }

    /// Logs rendered frames (`--save-frames`) at `cameras/<camera>`, at the
    /// update last taken in.
    pub fn images(&mut self, twin: &Twin, images: Vec<crate::output::KeptImage>) {
        let Some(feed) = self.inner.as_mut() else { return };
        let t = sim_time_ns(twin.time_s()).unwrap_or(0);
        for (camera, rgb, size_px) in images {
            let path = format!("cameras/{}", entity_part(&camera));
            feed.push(t, Item::Image { path, rgb, size_px });
        }
    }

    /// Logs the tool trails' last pieces, hands over what has gathered, and
    /// waits for the recording threads to send everything, flush and close
    /// their streams (a `.rrd` gets its footer), together at most
    /// [`FINISH_WAIT`]. `twin` is the twin as last logged. With `--serve`,
    /// the server stays up in the returned [`Finished::served`]. A part
    /// that failed (a viewer that stopped reading) costs the other nothing:
    /// see [`Finished`].
    pub fn finish(self, twin: &Twin) -> Finished {
        let Some(mut feed) = self.inner else {
            return Finished {
                files_complete: true,
                ..Finished::default()
            };
        };
        let t = sim_time_ns(twin.time_s()).unwrap_or(0);
        feed.trails(twin, t);
        let batch = std::mem::take(&mut feed.batch);
        let _ = feed.send(batch);
        feed.join(FINISH_WAIT)
    }
}

impl Feed {
    /// An empty batch to fill: one given back by a recording thread, or a
    /// new one. With two recording threads two come back for each one
    /// handed over: the others are freed here.
    fn given_back(&self) -> Batch {
        let mut back = self.returned.try_iter();
        let batch = back.next().unwrap_or_default();
        back.for_each(drop);
        batch
    }

    /// Copies the update's numbers into the batch, and queues the new part
    /// of the trails, the collision events and the contacts.
    fn take(&mut self, twin: &Twin) {
        let (task, program, plant) = (twin.task(), twin.program(), twin.plant());
        let t = sim_time_ns(twin.time_s()).unwrap_or(0);
        let b = &mut self.batch;
        b.times_ns.push(t);
        b.world_from_link.extend(plant.world_from_link());
        self.row.read(twin);
        b.values.extend_from_slice(&self.row.values[1..]);
        b.values
            .extend(plant.axes().iter().map(|a| task.axis_state(a.handle).actual_velocity));
        b.fbs.extend(program.fbs().iter().map(|fb| task.outputs(fb.handle)));
        b.instructions
            .extend(program.instructions().iter().map(|ins| task.motion_bits(ins.handle)));
        if task.updates().is_multiple_of(TRAIL_UPDATES) {
            self.trails(twin, t);
        }
        if plant.collision_enabled() {
            self.collisions(twin, t);
        }
        if task.updates().is_multiple_of(PART_UPDATES) {
            self.parts(twin, t);
        }
        self.sensors(twin, t);
        self.texts(twin, t);
        let log = program.controller().fault_log();
        if log.len() > self.logged_faults {
            let new: Vec<(TextLevel, String)> = log[self.logged_faults..]
                .iter()
                .map(|f| {
                    let level = if f.major && !f.cleared {
                        TextLevel::Error
                    } else {
                        TextLevel::Warn
                    };
                    (level, f.to_string())
                })
                .collect();
            self.logged_faults = log.len();
            for (level, text) in new {
                self.push(
                    t,
                    Item::Text {
                        path: "controller/log".into(),
                        level,
                        text,
                    },
                );
            }
        }
        for (k, a) in plant.axes().iter().enumerate() {
            for fault in crate::output::axis_faults::new_axis_faults(twin, a, &mut self.previous_faults[k]) {
                let text = format!(
                    "axis {}: {} ({}) at {:.3} s, action {}, actual position {}",
                    a.name,
                    fault.fault,
                    fault.meaning,
                    twin.time_s(),
                    fault.action,
                    trace::number(task.axis_state(a.handle).actual_position)
                );
                self.push(
                    t,
                    Item::Text {
                        path: "controller/log".into(),
                        level: TextLevel::Error,
                        text,
                    },
                );
            }
        }
    }

    /// The live parts' poses at `parts/<id>` (with the mesh the first
    /// time); a part that left the cell is cleared.
    fn parts(&mut self, twin: &Twin, t_ns: i64) {
        let Some(m) = twin.plant().material() else { return };
        let live: Vec<u64> = m.parts().iter().map(|p| p.id).collect();
        for id in std::mem::take(&mut self.logged_parts) {
            if live.binary_search(&id).is_err() {
                self.push(
                    t_ns,
                    Item::Clear {
                        path: format!("parts/{id}"),
                    },
                );
            } else {
                self.logged_parts.push(id);
            }
        }
        let cylinders = &twin.scene().cell.cylinders;
        for (k, (c, def)) in m.cylinders().zip(cylinders).enumerate() {
            let first = self.logged_cylinders.len() <= k;
            if !first && self.logged_cylinders[k] == c.position_m() {
                continue;
            }
            if first {
                self.logged_cylinders.push(c.position_m());
            } else {
                self.logged_cylinders[k] = c.position_m();
            }
            let mesh = first.then(|| {
                let shape = crate::scene::Shape::Box { size_m: def.size_m };
                (
                    crate::plant::visuals::shape_mesh(&shape).unwrap_or_default(),
                    def.color.map(|x| x as f32),
                )
            });
            self.push(
                t_ns,
                Item::Part {
                    path: format!("cylinders/{}", entity_part(&def.name)),
                    mesh,
                    pose: crate::plant::convert::isometry_to_arrays(&c.world_from_box()),
                },
            );
        }
        for p in m.parts() {
            let pose =
                crate::plant::convert::isometry_to_arrays(&crate::plant::convert::pose_from_rapier(&m.part_pose(p)));
            let new = self.logged_parts.binary_search(&p.id).is_err();
            if new {
                self.logged_parts.push(p.id);
            }
            let mesh = new.then(|| self.part_meshes.get(p.part_type).cloned()).flatten();
            self.push(
                t_ns,
                Item::Part {
                    path: format!("parts/{}", p.id),
                    mesh,
                    pose,
                },
            );
        }
        self.logged_parts.sort_unstable();
    }

    /// Each sensor's beams or ray at `sensors/<name>` when its state
    /// changes (a sensor on a link: every time the parts are logged).
    fn sensors(&mut self, twin: &Twin, t_ns: i64) {
        let plant = twin.plant();
        let sensors = plant.sensors();
        if sensors.is_empty() {
            return;
        }
        self.logged_sensors.resize(sensors.len(), None);
        let links: Vec<nalgebra::Isometry3<f64>> = plant
            .world_from_link()
            .iter()
            .map(crate::plant::convert::isometry_from_arrays)
            .collect();
        let moving = twin.task().updates().is_multiple_of(PART_UPDATES);
        for (k, s) in sensors.iter().enumerate() {
            let on = s.output();
            if self.logged_sensors[k] == Some(on) && !(moving && s.on_link()) {
                continue;
            }
            self.logged_sensors[k] = Some(on);
            let segments = s.lines_in_world(&links);
            if segments.is_empty() {
                continue;
            }
            let color = if on { [0.9, 0.1, 0.1, 1.0] } else { [0.1, 0.8, 0.2, 1.0] };
            self.push(
                t_ns,
                Item::Lines {
                    path: format!("sensors/{}", entity_part(&s.name)),
                    segments,
                    color,
                },
            );
        }
    }

    /// A traced string's text, logged at `tags/<reference>` when it
    /// changes (its text as the trace writes it).
    fn texts(&mut self, twin: &Twin, t_ns: i64) {
        let program = twin.program();
        let tags = program.traced_tags();
        self.logged_texts.resize(tags.len(), None);
        for (k, tag) in tags.iter().enumerate() {
            let Some(text) = program.traced_text(tag) else { continue };
            if self.logged_texts[k].as_deref() == Some(text.as_str()) {
                continue;
            }
            self.logged_texts[k] = Some(text.clone());
            let path = format!("tags/{}", entity_part(&tag.name));
            self.push(
                t_ns,
                Item::State {
                    path: path.clone(),
                    label: text.clone(),
                },
            );
            self.push(
                t_ns,
                Item::Text {
                    path: path.into(),
                    level: TextLevel::Info,
                    text,
                },
            );
        }
    }

    /// Queues an item after the updates gathered so far.
    fn push(&mut self, t_ns: i64, item: Item) {
        self.batch.items.push((self.batch.times_ns.len(), t_ns, item));
    }

    /// The part of each tool trail not sent yet, as a new piece (which
    /// starts at the last point sent, so the pieces join). Systems that
    /// share a tool link share one trail, the first one's.
    fn trails(&mut self, twin: &Twin, t_ns: i64) {
        for k in 0..self.trails.len() {
            let (sent, pieces, owner) = self.trails[k];
            let trail = &twin.plant().tool_trails()[k];
            let all = &trail.points_in_world;
            let from = sent.saturating_sub(1);
            if owner && all.len() > sent && all.len() - from >= 2 {
                let path = format!("tool_trails/{}/{pieces}", entity_part(&trail.system));
                let points = all[from..].to_vec();
                self.trails[k] = (all.len(), pieces + 1, owner);
                self.push(t_ns, Item::Trail { path, points });
            }
        }
    }

    /// Contact arrows when they change, new events and predictions as text,
    /// red highlights of the colliding links.
    fn collisions(&mut self, twin: &Twin, t_ns: i64) {
        let plant = twin.plant();
        let contacts = plant.contacts();
        let origins: Vec<[f64; 3]> = contacts.iter().map(|c| c.at.point_in_world).collect();
        // Arrow length: the depth, at least 5 cm so that a touch is visible.
        let vectors: Vec<[f64; 3]> = contacts
            .iter()
            .map(|c| c.at.normal_in_world.map(|n| n * c.at.depth_m.max(0.05)))
            .collect();
        if (&origins, &vectors) != (&self.contacts.0, &self.contacts.1) {
            self.contacts = (origins.clone(), vectors.clone());
            self.push(t_ns, Item::Arrows { origins, vectors });
        }
        let events = &plant.collision_events()[self.logged_events..];
        let texts: Vec<String> = events
            .iter()
            .map(|e| {
                format!(
                    "collision {} <-> {} at {:.4} s, depth {:.4} m, point {:?}, normal {:?}",
                    e.a, e.b, e.start_s, e.deepest.depth_m, e.deepest.point_in_world, e.deepest.normal_in_world
                )
            })
            .chain(
                plant.predicted_collisions()[self.logged_predictions..]
                    .iter()
                    .map(|p| match &p.out_of_reach {
                        Some(why) => format!(
                            "pre-flight: {} leaves the workspace of {} at parameter {:.4} (t +{:.4} s): {why}",
                            p.instance, p.collision.a, p.collision.parameter, p.collision.time_s
                        ),
                        None => format!(
                            "pre-flight: {} predicts {} <-> {} at parameter {:.4} (t +{:.4} s){}",
                            p.instance,
                            p.collision.a,
                            p.collision.b,
                            p.collision.parameter,
                            p.collision.time_s,
                            if p.rejected { ", move rejected" } else { "" }
                        ),
                    }),
            )
            .collect();
        for text in texts {
            self.push(
                t_ns,
                Item::Text {
                    path: "collisions/log".into(),
                    level: TextLevel::Warn,
                    text,
                },
            );
        }
        self.logged_events = plant.collision_events().len();
        self.logged_predictions = plant.predicted_collisions().len();
        let colliding = plant.colliding_links();
        if colliding != self.highlighted {
            for l in std::mem::take(&mut self.highlighted) {
                if !colliding.contains(&l) {
                    let path = self.highlight_path(plant, l);
                    self.push(t_ns, Item::Clear { path });
                }
            }
            for &l in &colliding {
                if self.highlighted.contains(&l) {
                    continue;
                }
                let frame = plant.model().links[l].name.clone();
                let link_path = self.highlight_path(plant, l);
                for (k, part) in plant.visuals().iter().filter(|p| p.link == Some(l)).enumerate() {
                    let mesh = part.mesh.transformed(&column_major(&part.parent_from_mesh));
                    let path = format!("{link_path}/{k}");
                    let frame = frame.clone();
                    self.push(t_ns, Item::Mesh { path, frame, mesh });
                }
            }
            self.highlighted = colliding;
        }
    }

    /// The entity of a link's red collision highlight:
    /// `<robot>/collision_highlight/<link>`, in the link's frame.
    fn highlight_path(&self, plant: &crate::plant::Plant, link: usize) -> String {
        format!(
            "{}/collision_highlight/{}",
            self.robot,
            entity_part(&plant.model().links[link].name)
        )
    }

    /// Hands a batch to every recording thread, waiting at most
    /// [`STALL_WAIT`] for room in each (a thread takes nothing while a
    /// viewer that accepted the connection does not read): one that
    /// stalls or has stopped is given up, the others go on.
    ///
    /// # Errors
    /// When no recording thread is left: why they stopped.
    fn send(&mut self, batch: Batch) -> Result<(), RecordingError> {
        let mut kept = Vec::with_capacity(self.workers.len());
        let last = self.workers.len().saturating_sub(1);
        let mut batch = Some(batch);
        for (k, worker) in std::mem::take(&mut self.workers).into_iter().enumerate() {
            let mine = if k == last { batch.take() } else { batch.clone() };
            let Some(mine) = mine else { continue };
            match worker.hand(mine) {
                Ok(()) => kept.push(worker),
                Err(e) => self.failures.push((worker.part, e)),
            }
        }
        self.workers = kept;
        if self.workers.is_empty() {
            return Err(self.failure());
        }
        Ok(())
    }

    /// The failures so far as one error.
    fn failure(&mut self) -> RecordingError {
        let mut failures = std::mem::take(&mut self.failures);
        match failures.len() {
            0 => RecordingError::Worker {
                why: "the recording thread stopped".to_owned(),
            },
            1 => failures.remove(0).1,
            _ => RecordingError::Worker {
                why: failures
                    .iter()
                    .map(|(_, e)| e.to_string())
                    .collect::<Vec<_>>()
                    .join("; "),
            },
        }
    }

    /// Closes the channels and waits, at most `wait` in all, for each
    /// recording thread's result.
    fn join(mut self, wait: std::time::Duration) -> Finished {
        let deadline = std::time::Instant::now() + wait;
        let mut finished = Finished::default();
        // The files first: they never wait for a viewer.
        self.workers.sort_by_key(|w| w.part == Part::Viewers);
        for worker in std::mem::take(&mut self.workers) {
            let Worker { part, sender, done } = worker;
            drop(sender);
            let left = deadline.saturating_duration_since(std::time::Instant::now());
            let result = match done.recv_timeout(left) {
                Ok(result) => result,
                Err(std::sync::mpsc::RecvTimeoutError::Timeout) => Err(RecordingError::Worker {
                    why: format!(
                        "nothing came back within {} s (a viewer that accepted the connection but does not read?)",
                        wait.as_secs()
                    ),
                }),
                Err(std::sync::mpsc::RecvTimeoutError::Disconnected) => Err(RecordingError::Worker {
                    why: "the recording thread panicked".to_owned(),
                }),
            };
            match result {
                Ok(served) => {
                    if part == Part::Viewers {
                        finished.served = served;
                    }
                }
                Err(e) => self.failures.push((part, e)),
            }
        }
        // Every file thread either finished or failed.
        finished.files_complete = !self.failures.iter().any(|(part, _)| *part == Part::Files);
        finished.failures = self.failures.into_iter().map(|(_, e)| e).collect();
        finished
    }
}

impl Worker {
    /// Hands `batch` over, waiting at most [`STALL_WAIT`] for room.
    fn hand(&self, mut batch: Batch) -> Result<(), RecordingError> {
        let since = std::time::Instant::now();
        loop {
            match self.sender.try_send(batch) {
                Ok(()) => return Ok(()),
                Err(std::sync::mpsc::TrySendError::Full(b)) if since.elapsed() < STALL_WAIT => {
                    batch = b;
                    std::thread::sleep(std::time::Duration::from_millis(1));
                }
                Err(std::sync::mpsc::TrySendError::Full(_)) => {
                    return Err(RecordingError::Worker {
                        why: format!(
                            "the recording took nothing for {} s (a viewer that accepted the connection but does not read?); it is dropped, the run goes on",
                            STALL_WAIT.as_secs()
                        ),
                    });
                }
                // The thread has ended: its result says why.
                Err(std::sync::mpsc::TrySendError::Disconnected(_)) => {
                    return Err(match self.done.try_recv() {
                        Ok(Err(e)) => e,
                        _ => RecordingError::Worker {
                            why: "the recording thread stopped".to_owned(),
                        },
                    });
                }
            }
        }
    }
}

#[cfg(test)]
mod tests;
