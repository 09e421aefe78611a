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
//! | entity | what | when |
//! | --- | --- | --- |
//! | `robot/<link>/<joint>/<link>/…` | link poses (parent from link), meshes static | when a pose changes |
//! | `obstacles/<part>` | fixed parts, static | once |
//! | `axes/<axis>/cmd_pos`, `act_pos`, `cmd_vel`, `act_vel`, `torque` | axis units, units/s, N·m or N | when the value changes |
//! | `instructions/<fb>/Done` … `Error`, `ErrorID` | function-block outputs | when they change |
//! | `instructions/<tag>/EN` … `DECEL`, `ERR`, `EXERR`, `SEGMENT` | control-structure bits and codes | when they change |
//! | `instructions/log` | one line per change of an instruction's status | on change |
//! | `tags/<reference>` | each `[trace] tags` entry, as the trace writes it | when it changes |
//! | `tool_trails/<system>/<k>` | the tool-centre path, piece `k` (m, world; systems sharing a tool link share the first one's trail) | every 100 updates and at the end, the new part only |
//! | `collisions/clearance/<body>` | clearance, m (infinite while nothing is in range) | when it changes |
//! | `collisions/contacts` | contact normals scaled by depth | when the contacts change |
//! | `collisions/log` | collision events and pre-flight predictions | as they happen |
//! | `robot/…/collision_highlight` | red copies of colliding links | while they collide |
//!
//! A series is logged where its value changes, and also at the update
//! before a change (so a plot steps instead of ramping between two
//! changes) and at the last update: its value at every update is the
//! latest sample at or before it, which equals the trace. Samples are
//! gathered per series and sent as one column (Rerun's columnar API, a
//! fraction of the cost of logging them one by one): for a file every
//! [`FLUSH_UPDATES`] updates and at the end, for a live viewer also every
//! [`LIVE_FLUSH`] of wall time.
//!
//! # Layout
//!
//! The recording carries a default blueprint ([`blueprint`]): the cell in
//! 3D with the tool trails and contacts; per coordinate system (and one
//! group for the axes in none) a position view (command and actual) and a
//! velocity view; a program view with the instruction bits and traced tags;
//! the instruction and collision logs; `sim_time` as the active timeline.

use std::collections::BTreeMap;

use planner::instruction::{FbOutputs, MotionInstructionBits};

use super::{Recorder, RecordingError, Sink, TextLevel, urdf_entity_paths};
use crate::output::status::{describe, describe_bits};
use crate::output::{COLLISION_TINT_RGBA, RecordingTargets};
use crate::plant::parts::column_major;
use crate::run::Twin;

/// The Rerun application id of every twin recording.
pub const APPLICATION_ID: &str = "twin";

/// Samples gathered for a file are sent to Rerun every this many coarse
/// updates (and at the end).
pub const FLUSH_UPDATES: u64 = 2048;

/// Samples gathered for a live viewer are sent at least this often (wall
/// time), so the plots follow the run.
pub const LIVE_FLUSH: std::time::Duration = std::time::Duration::from_millis(100);

/// Tool trails get a new piece every this many coarse updates.
const TRAIL_UPDATES: u64 = 100;

/// Colour of the tool trails.
const TRAIL_RGBA: [f32; 4] = [1.0, 0.45, 0.0, 1.0];

/// One colour per axis, in axis order (repeating); the actual value is
/// drawn lighter than the command.
const AXIS_RGBA: [[f32; 4]; 8] = [
    [0.12, 0.47, 0.71, 1.0],
    [0.84, 0.15, 0.16, 1.0],
    [0.17, 0.63, 0.17, 1.0],
    [0.58, 0.40, 0.74, 1.0],
    [1.00, 0.50, 0.05, 1.0],
    [0.55, 0.34, 0.29, 1.0],
    [0.89, 0.47, 0.76, 1.0],
    [0.09, 0.75, 0.81, 1.0],
];

/// Streams a run to Rerun (see the module doc); a no-op when no sink is
/// asked for.
pub struct Recording {
    inner: Option<Logged>,
}

/// The recorder and what it needs to log only what changed.
struct Logged {
    recorder: Recorder,
    link_paths: Vec<String>,
    /// Per URDF joint: its child link's pose relative to its parent link.
    poses: Vec<PoseSeries>,
    /// Per axis: cmd_pos, act_pos, cmd_vel, act_vel.
    axes: Vec<[Series; 4]>,
    /// Per axis: the drive's torque, for an axis with a servo drive.
    torques: Vec<Option<Series>>,
    /// Per function block: its outputs, then ErrorID; and the last outputs.
    fbs: Vec<(Vec<Series>, FbOutputs)>,
    /// Per control structure: its bits, then its codes; and the last bits.
    instructions: Vec<(Vec<Series>, MotionInstructionBits)>,
    tags: Vec<Series>,
    clearances: Vec<Series>,
    /// Per tool trail: points logged so far, pieces logged so far, and
    /// whether it is logged (the first of the systems sharing its link).
    trails: Vec<(usize, usize, bool)>,
    /// The contact arrows last logged (origins, vectors).
    contacts: (Vec<[f64; 3]>, Vec<[f64; 3]>),
    logged_events: usize,
    logged_predictions: usize,
    highlighted: Vec<usize>,
    /// Updates logged since the last flush.
    pending_updates: u64,
    /// With a live viewer: when the samples were last sent.
    live: Option<std::time::Instant>,
}

impl Recording {
    /// Opens the sinks asked for (none: a no-op recording), logs the static
    /// meshes, the series' names and colours and the default blueprint.
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
        if sinks.is_empty() {
            return Ok(Recording { inner: None });
        }
        let mut recorder = Recorder::open(APPLICATION_ID, Some(&twin.scene().name), Some(blueprint(twin)), &sinks)?;
        recorder.set_time_s(0.0);
        let model = twin.plant().model();
        let names: Vec<&str> = model.links.iter().map(|l| l.name.as_str()).collect();
        let joints: Vec<(&str, usize, usize)> = model
            .joints
            .iter()
            .map(|j| (j.name.as_str(), j.parent.0, j.child.0))
            .collect();
        let link_paths = urdf_entity_paths(&names, &joints, model.root.0);
        let mut count = vec![0usize; model.links.len()];
        for part in twin.plant().parts() {
            let path = match part.link {
                Some(i) => {
                    count[i] += 1;
                    format!("{}/visual_{}", link_paths[i], count[i] - 1)
                }
                None => format!("obstacles/{}", part.name),
            };
            let pose = part.parent_from_mesh;
            let t = pose.translation.vector;
            let q = pose.rotation.coords;
            let local = (
                [t.x as f32, t.y as f32, t.z as f32],
                [q.x as f32, q.y as f32, q.z as f32, q.w as f32],
                [1.0, 1.0, 1.0],
            );
            recorder.log_link_mesh_static(&path, &part.mesh, part.color_rgba, local)?;
        }

        let plant = twin.plant();
        let mut axes = Vec::new();
        let mut torques = Vec::new();
        for (k, a) in plant.axes().iter().enumerate() {
            let color = AXIS_RGBA[k % AXIS_RGBA.len()];
            let lighter = color.map(|c| c + (1.0 - c) * 0.5);
            let series = [
                ("cmd_pos", "command position", color),
                ("act_pos", "actual position", lighter),
                ("cmd_vel", "command velocity", color),
                ("act_vel", "actual velocity", lighter),
            ]
            .map(|(leaf, what, rgba)| {
                (
                    Series::new(format!("axes/{}/{leaf}", entity_part(&a.name))),
                    format!("{} {what}", a.name),
                    rgba,
                )
            });
            for (s, name, rgba) in &series {
                recorder.log_series_style(&s.path, name, *rgba)?;
            }
            axes.push(series.map(|(s, _, _)| s));
            let torque = plant
                .drive_torque(k)
                .map(|_| Series::new(format!("axes/{}/torque", entity_part(&a.name))));
            if let Some(s) = &torque {
                recorder.log_series_style(&s.path, &format!("{} torque", a.name), color)?;
            }
            torques.push(torque);
        }
        let program = twin.program();
        let fbs = program
            .fbs()
            .iter()
            .map(|fb| {
                let mut names: Vec<&str> = FbOutputs::default().bits().iter().map(|(n, _)| *n).collect();
                names.push("ErrorID");
                (instruction_series(&fb.name, &names), FbOutputs::default())
            })
            .collect();
        let zero = MotionInstructionBits::default();
        let instructions = program
            .instructions()
            .iter()
            .map(|ins| {
                let names: Vec<&str> = zero
                    .bits()
                    .iter()
                    .map(|(n, _)| *n)
                    .chain(zero.codes().iter().map(|(n, _)| *n))
                    .collect();
                (instruction_series(&ins.name, &names), zero)
            })
            .collect();
        let tags = program
            .traced_tags()
            .iter()
            .map(|t| Series::new(format!("tags/{}", entity_part(&t.name))))
            .collect();
        let clearances = plant
            .collision_bodies()
            .iter()
            .map(|b| Series::new(format!("collisions/clearance/{}", entity_part(b))))
            .collect();
        let poses = model
            .joints
            .iter()
            .map(|j| PoseSeries::new(link_paths[j.child.0].clone()))
            .collect();
        Ok(Recording {
            inner: Some(Logged {
                recorder,
                link_paths,
                poses,
                axes,
                torques,
                fbs,
                instructions,
                tags,
                clearances,
                trails: plant
                    .tool_trails()
                    .iter()
                    .enumerate()
                    .map(|(i, t)| (0, 0, !plant.tool_trails()[..i].iter().any(|u| u.link == t.link)))
                    .collect(),
                contacts: (Vec::new(), Vec::new()),
                logged_events: 0,
                logged_predictions: 0,
                highlighted: Vec::new(),
                pending_updates: 0,
                live: targets.live().then(std::time::Instant::now),
            }),
        })
    }

    /// Takes in the current update; sends what has gathered when it is
    /// time to (module doc).
    ///
    /// # Errors
    /// [`RecordingError`] when logging fails.
    pub fn log(&mut self, twin: &Twin) -> Result<(), RecordingError> {
        let Some(logged) = self.inner.as_mut() else {
            return Ok(());
        };
        logged.update(twin)
    }

    /// Logs the tool trails' last pieces, sends what has gathered, flushes
    /// and closes the stream (the `.rrd` gets its footer). `twin` is the
    /// twin as last logged.
    ///
    /// # Errors
    /// [`RecordingError`] when logging or flushing fails.
    pub fn finish(self, twin: &Twin) -> Result<(), RecordingError> {
        let Some(mut logged) = self.inner else {
            return Ok(());
        };
        logged.log_trails(twin)?;
        logged.close()?;
        logged.recorder.finish()
    }
}

impl Logged {
    fn update(&mut self, twin: &Twin) -> Result<(), RecordingError> {
        // The series' samples are indexed like everything logged now.
        self.recorder.set_time_s(twin.time_s());
        let t = self.recorder.time_ns().unwrap_or(0);
        let (task, program, plant) = (twin.task(), twin.program(), twin.plant());

        // Link poses relative to their parent link (the entity tree).
        let model = plant.model();
        let poses = plant.world_from_link();
        for (joint, series) in model.joints.iter().zip(&mut self.poses) {
            let (translation, rotation) = parent_from_child(poses[joint.parent.0], poses[joint.child.0]);
            series.observe(t, translation, rotation);
        }

        for (k, a) in plant.axes().iter().enumerate() {
            let s = task.axis_state(a.handle);
            let values = [
                s.command_position,
                s.actual_position,
                s.command_velocity,
                s.actual_velocity,
            ];
            for (series, value) in self.axes[k].iter_mut().zip(values) {
                series.observe(t, value);
            }
            if let (Some(series), Some(torque)) = (&mut self.torques[k], plant.drive_torque(k)) {
                series.observe(t, torque);
            }
        }

        for (fb, (series, previous)) in program.fbs().iter().zip(&mut self.fbs) {
            let o = task.outputs(fb.handle);
            let values = o
                .bits()
                .map(|(_, b)| f64::from(u8::from(b)))
                .into_iter()
                .chain([f64::from(o.error_id)]);
            for (s, v) in series.iter_mut().zip(values) {
                s.observe(t, v);
            }
            if std::mem::replace(previous, o) != o {
                let level = if o.error { TextLevel::Error } else { TextLevel::Info };
                self.recorder
                    .log_text("instructions/log", level, &format!("{}: {}", fb.name, describe(o)))?;
            }
        }
        for (ins, (series, previous)) in program.instructions().iter().zip(&mut self.instructions) {
            let b = task.motion_bits(ins.handle);
            let values = b
                .bits()
                .map(|(_, bit)| f64::from(u8::from(bit)))
                .into_iter()
                .chain(b.codes().map(|(_, c)| f64::from(c)));
            for (s, v) in series.iter_mut().zip(values) {
                s.observe(t, v);
            }
            if std::mem::replace(previous, b) != b {
                let level = if b.er { TextLevel::Error } else { TextLevel::Info };
                self.recorder.log_text(
                    "instructions/log",
                    level,
                    &format!("{}: {}", ins.name, describe_bits(b)),
                )?;
            }
        }
        for (tag, series) in program.traced_tags().iter().zip(&mut self.tags) {
            series.observe(t, program.traced_number(tag, task));
        }

        if task.updates().is_multiple_of(TRAIL_UPDATES) {
            self.log_trails(twin)?;
        }
        if plant.collision_enabled() {
            self.log_collisions(twin)?;
        }
        self.pending_updates += 1;
        if self.pending_updates >= FLUSH_UPDATES || self.live.is_some_and(|at| at.elapsed() >= LIVE_FLUSH) {
            self.flush()?;
        }
        Ok(())
    }

    /// The part of each tool trail not logged yet, as a new piece (which
    /// starts at the last point logged, so the pieces join). Systems that
    /// share a tool link share one trail, the first one's.
    fn log_trails(&mut self, twin: &Twin) -> Result<(), RecordingError> {
        for (trail, (logged, pieces, _)) in twin
            .plant()
            .tool_trails()
            .iter()
            .zip(&mut self.trails)
            .filter(|(_, (_, _, owner))| *owner)
        {
            let points = &trail.points_in_world;
            let from = logged.saturating_sub(1);
            if points.len() > *logged && points.len() - from >= 2 {
                let path = format!("tool_trails/{}/{pieces}", entity_part(&trail.system));
                self.recorder.log_line_strip(&path, &points[from..], TRAIL_RGBA)?;
                *logged = points.len();
                *pieces += 1;
            }
        }
        Ok(())
    }

    /// Clearance series, contact arrows, event text log, red highlights.
    fn log_collisions(&mut self, twin: &Twin) -> Result<(), RecordingError> {
        let plant = twin.plant();
        let t = self.recorder.time_ns().unwrap_or(0);
        for (series, d) in self.clearances.iter_mut().zip(plant.clearance_m()) {
            // Infinite while nothing is in range, as in the trace.
            series.observe(t, d);
        }
        let contacts = plant.contacts();
        let origins: Vec<[f64; 3]> = contacts.iter().map(|c| c.point_in_world).collect();
        // Arrow length: the depth, at least 5 cm so that a touch is visible.
        let vectors: Vec<[f64; 3]> = contacts
            .iter()
            .map(|c| c.normal_in_world.map(|n| n * c.depth_m.max(0.05)))
            .collect();
        if (&origins, &vectors) != (&self.contacts.0, &self.contacts.1) {
            self.recorder
                .log_arrows("collisions/contacts", &origins, &vectors, COLLISION_TINT_RGBA)?;
            self.contacts = (origins, vectors);
        }
        for e in &plant.collision_events()[self.logged_events..] {
            let text = format!(
                "collision {} <-> {} at {:.4} s, depth {:.4} m, point {:?}, normal {:?}",
                e.a, e.b, e.start_s, e.max_depth_m, e.point_in_world, e.normal_in_world
            );
            self.recorder.log_text("collisions/log", TextLevel::Warn, &text)?;
        }
        self.logged_events = plant.collision_events().len();
        for p in &plant.predicted_collisions()[self.logged_predictions..] {
            let text = match &p.out_of_reach {
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
            };
            self.recorder.log_text("collisions/log", TextLevel::Warn, &text)?;
        }
        self.logged_predictions = plant.predicted_collisions().len();
        let colliding = plant.colliding_links();
        if colliding != self.highlighted {
            for &l in &self.highlighted {
                if !colliding.contains(&l) {
                    self.recorder
                        .log_clear(&format!("{}/collision_highlight", self.link_paths[l]))?;
                }
            }
            for &l in &colliding {
                if self.highlighted.contains(&l) {
                    continue;
                }
                for (k, part) in plant.parts().iter().filter(|p| p.link == Some(l)).enumerate() {
                    let mesh = part.mesh.transformed(&column_major(&part.parent_from_mesh));
                    self.recorder.log_mesh_timed(
                        &format!("{}/collision_highlight/{k}", self.link_paths[l]),
                        &mesh,
                        COLLISION_TINT_RGBA,
                    )?;
                }
            }
            self.highlighted = colliding;
        }
        Ok(())
    }

    /// Every series' gathered samples, one column each.
    fn flush(&mut self) -> Result<(), RecordingError> {
        self.pending_updates = 0;
        if let Some(at) = &mut self.live {
            *at = std::time::Instant::now();
        }
        for pose in &mut self.poses {
            pose.flush(&mut self.recorder)?;
        }
        let (recorder, scalars) = self.scalar_series();
        for series in scalars {
            series.flush(recorder)?;
        }
        Ok(())
    }

    /// The recorder, and every scalar series.
    fn scalar_series(&mut self) -> (&mut Recorder, impl Iterator<Item = &mut Series>) {
        let scalars = self
            .axes
            .iter_mut()
            .flatten()
            .chain(self.torques.iter_mut().flatten())
            .chain(self.fbs.iter_mut().flat_map(|(s, _)| s))
            .chain(self.instructions.iter_mut().flat_map(|(s, _)| s))
            .chain(&mut self.tags)
            .chain(&mut self.clearances);
        (&mut self.recorder, scalars)
    }

    /// The last trail pieces, every series' value at the last update, and
    /// what has gathered.
    fn close(&mut self) -> Result<(), RecordingError> {
        for series in self.scalar_series().1 {
            series.close();
        }
        self.flush()
    }
}

/// The pose of a child link in its parent's frame, from both world poses
/// (translation, `xyzw` unit quaternion): conj(q_p)·q_c, and the offset
/// t_c − t_p turned by conj(q_p).
fn parent_from_child((t_p, q_p): ([f64; 3], [f64; 4]), (t_c, q_c): ([f64; 3], [f64; 4])) -> ([f64; 3], [f64; 4]) {
    let inv = [-q_p[0], -q_p[1], -q_p[2], q_p[3]];
    let d = [t_c[0] - t_p[0], t_c[1] - t_p[1], t_c[2] - t_p[2]];
    (rotate(inv, d), quaternion_product(inv, q_c))
}

/// The Hamilton product a·b of `xyzw` quaternions.
fn quaternion_product(a: [f64; 4], b: [f64; 4]) -> [f64; 4] {
    let [ax, ay, az, aw] = a;
    let [bx, by, bz, bw] = b;
    [
        aw * bx + ax * bw + ay * bz - az * by,
        aw * by - ax * bz + ay * bw + az * bx,
        aw * bz + ax * by - ay * bx + az * bw,
        aw * bw - ax * bx - ay * by - az * bz,
    ]
}

/// `v` turned by the unit `xyzw` quaternion `q`: v + 2w(u×v) + 2u×(u×v).
fn rotate(q: [f64; 4], v: [f64; 3]) -> [f64; 3] {
    let [x, y, z, w] = q;
    let cross = |a: [f64; 3], b: [f64; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    let u = [x, y, z];
    let uv = cross(u, v);
    let uuv = cross(u, uv);
    [
        v[0] + 2.0 * (w * uv[0] + uuv[0]),
        v[1] + 2.0 * (w * uv[1] + uuv[1]),
        v[2] + 2.0 * (w * uv[2] + uuv[2]),
    ]
}

/// A function block's or control structure's series, named by `leaves`.
fn instruction_series(name: &str, leaves: &[&str]) -> Vec<Series> {
    let name = entity_part(name);
    leaves
        .iter()
        .map(|leaf| Series::new(format!("instructions/{name}/{leaf}")))
        .collect()
}

/// A name as one entity-path part (a `/`, `.` or space stays inside it).
fn entity_part(name: &str) -> String {
    rerun::EntityPathPart::new(name).escaped_string()
}

/// A scalar series gathered where it changes (module doc).
struct Series {
    path: String,
    times_ns: Vec<i64>,
    values: Vec<f64>,
    /// The last sample taken in, and whether it is gathered.
    last: Option<(i64, f64, bool)>,
}

impl Series {
    fn new(path: String) -> Self {
        Self {
            path,
            times_ns: Vec::new(),
            values: Vec::new(),
            last: None,
        }
    }

    /// Takes in the value at `t_ns`: gathered when it differs from the last
    /// one (bit for bit, so a NaN that stays NaN is no change), together
    /// with the last one if that was not gathered.
    fn observe(&mut self, t_ns: i64, value: f64) {
        match self.last {
            Some((_, last, _)) if last.to_bits() == value.to_bits() => {
                if let Some(l) = &mut self.last {
                    l.0 = t_ns;
                    l.2 = false;
                }
                return;
            }
            Some((t_last, last, false)) => self.push(t_last, last),
            _ => {}
        }
        self.push(t_ns, value);
        self.last = Some((t_ns, value, true));
    }

    /// Gathers the last sample if it is not yet (the plot reaches the end).
    fn close(&mut self) {
        if let Some((t, v, false)) = self.last {
            self.push(t, v);
            self.last = Some((t, v, true));
        }
    }

    fn push(&mut self, t_ns: i64, value: f64) {
        self.times_ns.push(t_ns);
        self.values.push(value);
    }

    fn flush(&mut self, rec: &mut Recorder) -> Result<(), RecordingError> {
        if !self.times_ns.is_empty() {
            rec.send_scalar_column(&self.path, &self.times_ns, &self.values)?;
            self.times_ns.clear();
            self.values.clear();
        }
        Ok(())
    }
}

/// A link's pose gathered where it changes.
struct PoseSeries {
    path: String,
    times_ns: Vec<i64>,
    translations_m: Vec<[f64; 3]>,
    rotations_xyzw: Vec<[f64; 4]>,
    last: Option<([f64; 3], [f64; 4])>,
}

impl PoseSeries {
    fn new(path: String) -> Self {
        Self {
            path,
            times_ns: Vec::new(),
            translations_m: Vec::new(),
            rotations_xyzw: Vec::new(),
            last: None,
        }
    }

    fn observe(&mut self, t_ns: i64, translation_m: [f64; 3], rotation_xyzw: [f64; 4]) {
        if self.last == Some((translation_m, rotation_xyzw)) {
            return;
        }
        self.last = Some((translation_m, rotation_xyzw));
        self.times_ns.push(t_ns);
        self.translations_m.push(translation_m);
        self.rotations_xyzw.push(rotation_xyzw);
    }

    fn flush(&mut self, rec: &mut Recorder) -> Result<(), RecordingError> {
        if !self.times_ns.is_empty() {
            rec.send_transform_column(&self.path, &self.times_ns, &self.translations_m, &self.rotations_xyzw)?;
            self.times_ns.clear();
            self.translations_m.clear();
            self.rotations_xyzw.clear();
        }
        Ok(())
    }
}

/// The default layout of a run's recording (module doc).
pub fn blueprint(twin: &Twin) -> rerun::blueprint::Blueprint {
    use rerun::blueprint::components::PanelState;
    use rerun::blueprint::{
        Blueprint, ContainerLike, Horizontal, SelectionPanel, Spatial3DView, Tabs, TextLogView, TimePanel,
        TimeSeriesView, Vertical,
    };

    let (task, plant) = (twin.task(), twin.plant());
    let cell = Spatial3DView::new("Cell").with_origin("/").with_contents([
        "/robot/**",
        "/obstacles/**",
        "/tool_trails/**",
        "/collisions/contacts",
    ]);

    // Axis groups: each coordinate system, then the axes in none.
    let name_of: BTreeMap<_, _> = plant.axes().iter().map(|a| (a.handle, a.name.as_str())).collect();
    let mut groups: Vec<(String, Vec<&str>)> = task
        .coord_handles()
        .map(|h| {
            let axes = task
                .coord_axes(h)
                .iter()
                .filter_map(|a| name_of.get(a).copied())
                .collect();
            (task.coord_config(h).name.clone(), axes)
        })
        .collect();
    let single: Vec<&str> = plant
        .axes()
        .iter()
        .filter(|a| !groups.iter().any(|(_, axes)| axes.contains(&a.name.as_str())))
        .map(|a| a.name.as_str())
        .collect();
    if !single.is_empty() {
        groups.push(("Axes".to_string(), single));
    }
    let series = |axes: &[&str], leaves: &[&str]| -> Vec<String> {
        axes.iter()
            .flat_map(|a| leaves.iter().map(move |l| format!("/axes/{}/{l}", entity_part(a))))
            .collect()
    };
    let group_views: Vec<ContainerLike> = groups
        .iter()
        .map(|(name, axes)| {
            let mut views: Vec<ContainerLike> = vec![
                TimeSeriesView::new(format!("{name} position"))
                    .with_contents(series(axes, &["cmd_pos", "act_pos"]))
                    .into(),
                TimeSeriesView::new(format!("{name} velocity"))
                    .with_contents(series(axes, &["cmd_vel", "act_vel"]))
                    .into(),
            ];
            let driven: Vec<&str> = axes
                .iter()
                .copied()
                .filter(|a| {
                    plant
                        .axes()
                        .iter()
                        .position(|b| b.name == *a)
                        .is_some_and(|k| plant.drive_torque(k).is_some())
                })
                .collect();
            if !driven.is_empty() {
                views.push(
                    TimeSeriesView::new(format!("{name} torque"))
                        .with_contents(series(&driven, &["torque"]))
                        .into(),
                );
            }
            Vertical::new(views).with_name(name.clone()).into()
        })
        .collect();

    let mut state: Vec<ContainerLike> = vec![
        TimeSeriesView::new("Program")
            .with_contents(["/instructions/**", "/tags/**"])
            .into(),
    ];
    let mut logs: Vec<ContainerLike> = vec![
        TextLogView::new("Instruction log")
            .with_origin("/instructions/log")
            .with_contents(["/instructions/log"])
            .into(),
    ];
    if plant.collision_enabled() {
        state.push(
            TimeSeriesView::new("Clearance")
                .with_origin("/collisions/clearance")
                .into(),
        );
        logs.push(
            TextLogView::new("Collision log")
                .with_origin("/collisions/log")
                .with_contents(["/collisions/log"])
                .into(),
        );
    }
    let mut right: Vec<ContainerLike> = Vec::new();
    if !group_views.is_empty() {
        right.push(Tabs::new(group_views).into());
    }
    right.push(Tabs::new(state).into());
    let left = Vertical::new([cell.into(), Tabs::new(logs).into()]).with_row_shares([3.0, 1.0]);
    Blueprint::new(Horizontal::new([left.into(), Vertical::new(right).into()]))
        .with_time_panel(TimePanel::new().with_timeline(super::SIM_TIME_TIMELINE))
        .with_selection_panel(SelectionPanel::new().with_state(PanelState::Collapsed))
}

#[cfg(test)]
mod tests;
