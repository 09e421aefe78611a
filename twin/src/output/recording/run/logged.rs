//! The recording thread's side of a run's recording: the series it keeps
//! per update, what it makes of each batch, and when it sends the
//! gathered samples (the parent module's doc says what and when).

use planner::instruction::{FbOutputs, MotionInstructionBits};

use super::super::{FrameTransform, Recorder, RecordingError, Served, TextLevel};
use super::batch::{AXIS_RGBA, Batch, FLUSH_UPDATES, IDLE_FLUSH_UPDATES, Item, LIVE_FLUSH, TRAIL_RGBA};
use super::fixed::{Static, Style};
use super::paths::{entity_part, instruction_entity, tag_entity};
use crate::output::COLLISION_TINT_RGBA;
use crate::output::status::{Status, describe};
use crate::output::trace;
use crate::program::types::DataType;
use crate::run::Twin;

/// The recording thread's side: the recorder and the series.
pub(super) struct Logged {
    recorder: Recorder,
    series: AllSeries,
    /// Updates taken in since the last flush.
    pending_updates: u64,
    /// Updates gathered before an idle flush (module doc).
    idle_flush_updates: u64,
    /// With a live viewer: when the samples were last sent.
    live: Option<std::time::Instant>,
}

/// What the recording thread keeps per update (see [`Logged`]).
pub(super) struct AllSeries {
    /// Per URDF joint: (parent link, child link) and the child's pose in
    /// its parent's frame; then the root link's pose in the world.
    poses: Vec<((usize, Option<usize>), PoseSeries)>,
    links: usize,
    /// Values in a batch's update row ([`Batch::values`]).
    width: usize,
    /// Every series of values: the trace's columns grouped (module doc).
    groups: Vec<Series>,
    /// Per function block: its name, its series (in `groups`) and last
    /// outputs (none before the first update).
    fbs: Vec<(String, usize, Option<FbOutputs>)>,
    /// Per control structure: its name, its series and last bits.
    instructions: Vec<(String, usize, Option<MotionInstructionBits>)>,
}

/// Whether a trace column's series is also a state lane.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Lane {
    /// No lane.
    No,
    /// The column's value is its own lane (an integer or bit tag).
    Value,
    /// The series has one lane, its instruction's state word
    /// ([`Status::lane`]), set by [`observe_statuses`].
    Instruction,
}

/// Where the recording logs a trace column: the series' entity path and
/// its lane; `None` for `time_s` and string tags (logged as text).
fn series_path(twin: &Twin, column: &trace::Column) -> Option<(String, Lane)> {
    use trace::Group;
    let path = match &column.group {
        Group::Time => return None,
        Group::Axis(axis) => match column.leaf.as_str() {
            "cmd_pos" | "act_pos" | "sup_pos" => format!("axes/{}/position", entity_part(axis)),
            "cmd_vel" | "sup_vel" => format!("axes/{}/velocity", entity_part(axis)),
            "torque" => format!("axes/{}/torque", entity_part(axis)),
            "cmd_acc" => "axes/acceleration".to_owned(),
            _ => "axes/status".to_owned(),
        },
        Group::Instruction(name) => return Some((instruction_entity(name), Lane::Instruction)),
        Group::CollisionCount => "collisions/count".to_owned(),
        Group::Clearance => "collisions/clearance".to_owned(),
        Group::System(cs) => format!("coordinate_systems/{}/status", entity_part(cs)),
        Group::Tool(cs) => format!("coordinate_systems/{}/tool", entity_part(cs)),
        Group::Sensor => "cell/sensors".to_owned(),
        Group::Conveyor => "cell/conveyors".to_owned(),
        Group::Gripper => "cell/grippers".to_owned(),
        Group::Cylinder => "cell/cylinders".to_owned(),
        Group::Parts => "cell/parts".to_owned(),
        Group::Tag(k) => {
            let tag = &twin.program().traced_tags()[*k];
            if tag.is_text() {
                return None;
            }
            let lane = if matches!(tag.data_type(), DataType::Real | DataType::Lreal) {
                Lane::No
            } else {
                Lane::Value
            };
            return Some((tag_entity(twin, tag), lane));
        }
        Group::Plant => "plant/kinematic".to_owned(),
    };
    Some((path, Lane::No))
}

/// The colour of an axis' line: the axis' own for a command, lighter for
/// the actual value, darker for the superimposed part.
fn axis_rgba(k: usize, leaf: &str) -> [f32; 4] {
    let color = AXIS_RGBA[k % AXIS_RGBA.len()];
    match leaf {
        "act_pos" | "act_vel" => color.map(|c| c + (1.0 - c) * 0.5),
        "sup_pos" | "sup_vel" => [color[0] * 0.6, color[1] * 0.6, color[2] * 0.6, 1.0],
        _ => color,
    }
}

impl Series {
    /// The series of `twin`'s link poses and of the trace's columns
    /// grouped (module doc), with their styles. A batch's update row
    /// ([`Batch::values`]) holds the trace's values after `time_s`, then
    /// each axis' actual velocity.
    pub(super) fn of(twin: &Twin) -> (AllSeries, Vec<Style>) {
        let plant = twin.plant();
        let columns = trace::columns(twin);
        let axis_index = |name: &str| plant.axes().iter().position(|a| a.name == name);
        // (path, lanes, names, colours, value indices)
        type Group = (String, Lanes, Vec<String>, Vec<[f32; 4]>, Vec<usize>);
        fn place(groups: &mut Vec<Group>, path: String, lane: Lane, name: String, rgba: [f32; 4], index: usize) {
            let k = match groups.iter().position(|g| g.0 == path) {
                Some(k) => k,
                None => {
                    groups.push((path, Lanes::Values(Vec::new()), Vec::new(), Vec::new(), Vec::new()));
                    groups.len() - 1
                }
            };
            let g = &mut groups[k];
            match (lane, &mut g.1) {
                (Lane::Instruction, lanes) => *lanes = Lanes::Set,
                (Lane::Value, Lanes::Values(v)) => v.push(g.4.len()),
                _ => {}
            }
            g.2.push(name);
            g.3.push(rgba);
            g.4.push(index);
        }
        let mut groups: Vec<Group> = Vec::new();
        let palette = |k: usize| AXIS_RGBA[k % AXIS_RGBA.len()];
        let velocities = columns.len() - 1;
        for (index, column) in columns.iter().enumerate().skip(1).map(|(k, c)| (k - 1, c)) {
            let Some((path, lane)) = series_path(twin, column) else {
                continue;
            };
            let rgba = match &column.group {
                trace::Group::Axis(a) => axis_rgba(axis_index(a).unwrap_or(0), &column.leaf),
                _ => palette(groups.iter().find(|g| g.0 == path).map_or(0, |g| g.2.len())),
            };
            place(&mut groups, path.clone(), lane, column.name.clone(), rgba, index);
            if let (trace::Group::Axis(a), "cmd_vel") = (&column.group, column.leaf.as_str())
                && let Some(k) = axis_index(a)
            {
                place(
                    &mut groups,
                    path,
                    Lane::No,
                    format!("{a}.act_vel"),
                    axis_rgba(k, "act_vel"),
                    velocities + k,
                );
            }
        }
        let styles = groups
            .iter()
            .map(|(path, _, names, colors, _)| (path.clone(), names.clone(), colors.clone()))
            .collect();
        let groups: Vec<Series> = groups
            .into_iter()
            .map(|(path, lanes, _, _, indices)| Series::new(path, indices, lanes))
            .collect();
        let program = twin.program();
        let series_of = |name: &str| {
            let path = instruction_entity(name);
            groups
                .iter()
                .position(|s: &Series| s.path == path)
                .unwrap_or(usize::MAX)
        };
        let fbs = program
            .fbs()
            .iter()
            .map(|fb| (fb.name.clone(), series_of(&fb.name), None))
            .collect();
        let instructions = program
            .instructions()
            .iter()
            .map(|ins| (ins.name.clone(), series_of(&ins.name), None))
            .collect();
        let model = plant.model();
        let mut poses: Vec<((usize, Option<usize>), PoseSeries)> = model
            .joints
            .iter()
            .map(|j| {
                let frames = (
                    model.links[j.parent.0].name.clone(),
                    model.links[j.child.0].name.clone(),
                );
                ((j.child.0, Some(j.parent.0)), PoseSeries::new(frames))
            })
            .collect();
        poses.push((
            (model.root.0, None),
            PoseSeries::new((
                super::super::WORLD_FRAME.to_owned(),
                model.links[model.root.0].name.clone(),
            )),
        ));
        let series = AllSeries {
            poses,
            links: model.links.len(),
            width: velocities + plant.axes().len(),
            groups,
            fbs,
            instructions,
        };
        (series, styles)
    }
}

impl Logged {
    pub(super) fn new(recorder: Recorder, series: AllSeries, live: bool) -> Logged {
        Logged {
            recorder,
            series,
            pending_updates: 0,
            idle_flush_updates: IDLE_FLUSH_UPDATES,
            live: live.then(std::time::Instant::now),
        }
    }

    /// The recording thread: logs the static part (meshes, frames, series
    /// styles, routines, cameras), takes in batches until the run's side
    /// closes the channel, then sends the last samples and closes the
    /// stream.
    pub(super) fn run(
        mut self,
        fixed: &Static,
        batches: &std::sync::mpsc::Receiver<Batch>,
        returns: &std::sync::mpsc::Sender<Batch>,
    ) -> Result<Served, RecordingError> {
        self.recorder.set_time_ns(0);
        fixed.log(&mut self.recorder)?;
        // Static data on its way to the sinks while the run goes on.
        self.recorder.flush_async()?;
        loop {
            let mut batch = match batches.try_recv() {
                Ok(batch) => batch,
                Err(std::sync::mpsc::TryRecvError::Empty) => {
                    // Idle: send what has gathered now rather than at the end.
                    if self.pending_updates >= self.idle_flush_updates {
                        self.idle_flush_updates = (2 * self.idle_flush_updates).min(FLUSH_UPDATES);
                        self.flush()?;
                    }
                    match batches.recv() {
                        Ok(batch) => batch,
                        Err(_) => break,
                    }
                }
                Err(std::sync::mpsc::TryRecvError::Disconnected) => break,
            };
            self.take(&mut batch)?;
            // Emptied, back to the run's thread, which fills it again: the
            // run's allocator arena is then used by the run's thread alone
            // (freeing its memory here would take the arena's lock, which
            // the simulation waits for).
            batch.clear();
            let _ = returns.send(batch);
        }
        for series in &mut self.series.groups {
            series.close();
        }
        self.flush()?;
        self.recorder.finish()
    }

    /// Takes in a batch: every update's samples, the instruction log lines
    /// and state lanes of what changed, and the items in order.
    fn take(&mut self, batch: &mut Batch) -> Result<(), RecordingError> {
        let width = self.series.width;
        let (fbs, instructions) = (self.series.fbs.len(), self.series.instructions.len());
        let mut items = batch.items.drain(..).peekable();
        for (u, &t) in batch.times_ns.iter().enumerate() {
            while let Some((_, t_item, item)) = items.next_if(|(before, _, _)| *before <= u) {
                self.log_item(t_item, item)?;
            }
            self.recorder.set_time_ns(t);
            let poses = &batch.world_from_link[u * self.series.links..(u + 1) * self.series.links];
            for ((child, parent), series) in &mut self.series.poses {
                let (translation, rotation) = match parent {
                    Some(parent) => parent_from_child(poses[*parent], poses[*child]),
                    None => poses[*child],
                };
                series.observe(t, translation, rotation);
            }
            // The instructions' lanes first: their series take them in below.
            let (recorder, groups) = (&mut self.recorder, &mut self.series.groups);
            observe_statuses(
                recorder,
                groups,
                &mut self.series.fbs,
                &batch.fbs[u * fbs..(u + 1) * fbs],
            )?;
            let updated = &batch.instructions[u * instructions..(u + 1) * instructions];
            observe_statuses(recorder, groups, &mut self.series.instructions, updated)?;
            let row = &batch.values[u * width..(u + 1) * width];
            for series in &mut self.series.groups {
                series.observe(t, row);
            }
            self.pending_updates += 1;
            if self.pending_updates >= FLUSH_UPDATES {
                self.flush()?;
            }
        }
        for (_, t_item, item) in items {
            self.log_item(t_item, item)?;
        }
        if self.live.is_some_and(|at| at.elapsed() >= LIVE_FLUSH) {
            self.flush()?;
        }
        Ok(())
    }

    fn log_item(&mut self, t_ns: i64, item: Item) -> Result<(), RecordingError> {
        self.recorder.set_time_ns(t_ns);
        let r = &mut self.recorder;
        match item {
            Item::Trail { path, points } => r.log_line_strip(&path, &points, TRAIL_RGBA),
            Item::Arrows { origins, vectors } => {
                r.log_arrows("collisions/contacts", &origins, &vectors, COLLISION_TINT_RGBA)
            }
            Item::Text { path, level, text } => r.log_text(&path, level, &text),
            Item::State { path, label } => r.log_state(&path, &label),
            Item::Clear { path } => r.log_clear(&path),
            Item::Mesh { path, frame, mesh } => {
                r.log_frame_static(&path, &frame)?;
                r.log_mesh_timed(&path, &mesh, COLLISION_TINT_RGBA)
            }
            Item::Part { path, mesh, pose } => {
                if let Some((mesh, color)) = mesh {
                    r.log_mesh_timed(&path, &mesh, color)?;
                }
                r.log_transform(&path, pose.0, pose.1)
            }
            Item::Lines { path, segments, color } => {
                for (k, (a, b)) in segments.iter().enumerate() {
                    r.log_line_strip(&format!("{path}/{k}"), &[*a, *b], color)?;
                }
                Ok(())
            }
            Item::Image { path, rgb, size_px } => r.log_rgb_image(&path, rgb, size_px),
        }
    }

    /// Every series' gathered samples, one column each; then everything
    /// on its way to the sinks.
    fn flush(&mut self) -> Result<(), RecordingError> {
        self.pending_updates = 0;
        if let Some(at) = &mut self.live {
            *at = std::time::Instant::now();
        }
        // Every link's poses in one chunk.
        let (mut times_ns, mut rows) = (Vec::new(), Vec::new());
        for (_, pose) in &mut self.series.poses {
            pose.drain_into(&mut times_ns, &mut rows);
        }
        if !times_ns.is_empty() {
            self.recorder
                .send_frame_transform_column(super::super::TRANSFORMS_ENTITY, &times_ns, &rows)?;
        }
        for series in &mut self.series.groups {
            series.flush(&mut self.recorder)?;
        }
        self.recorder.flush_async()
    }
}

/// Takes in one update's outputs of the function blocks or control
/// structures: a change of its outputs is a line of the instruction log,
/// and its state word ([`Status::lane`]) the label its series gathers
/// next (every instance has its lane from the first update: a gap while
/// idle).
fn observe_statuses<S: Status + Default>(
    recorder: &mut Recorder,
    groups: &mut [Series],
    rows: &mut [(String, usize, Option<S>)],
    update: &[S],
) -> Result<(), RecordingError> {
    for ((name, series, previous), status) in rows.iter_mut().zip(update) {
        let first = previous.is_none();
        let before = previous.replace(*status).unwrap_or_default();
        if (first || before != *status)
            && let Some(series) = groups.get_mut(*series)
        {
            series.set_label(status.lane());
        }
        if before == *status {
            continue;
        }
        let level = if status.failed() {
            TextLevel::Error
        } else {
            TextLevel::Info
        };
        recorder.log_text("instructions/log", level, &format!("{name}: {}", describe(*status)))?;
    }
    Ok(())
}

/// The pose of a child link in its parent's frame, from both world poses
/// (translation, `xyzw` unit quaternion): conj(q_p)·q_c, and the offset
/// t_c − t_p turned by conj(q_p).
pub(super) fn parent_from_child(
    (t_p, q_p): ([f64; 3], [f64; 4]),
    (t_c, q_c): ([f64; 3], [f64; 4]),
) -> ([f64; 3], [f64; 4]) {
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

/// Which values of a series are also state lanes.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(super) enum Lanes {
    /// These of its values, one lane each (their text); none: no lanes.
    Values(Vec<usize>),
    /// One lane whose label is set from outside ([`Series::set_label`]).
    Set,
}

/// A series of one or more values (the lines of one entity) gathered where
/// any of them changes (module doc), with its state lanes' labels, which
/// change only where its values do and are sent in the same chunk.
pub(super) struct Series {
    path: String,
    /// Where its values are in an update's row.
    columns: Vec<usize>,
    lanes: Lanes,
    times_ns: Vec<i64>,
    /// `columns.len()` values per time.
    values: Vec<f64>,
    /// The lanes' labels per time (empty without lanes).
    states: Vec<String>,
    /// The last values taken in, when, and whether they are gathered.
    last: Vec<f64>,
    last_at: Option<(i64, bool)>,
    /// The lanes' labels now, and at the last update taken in.
    labels: Vec<String>,
    last_labels: Vec<String>,
}

impl Series {
    pub(super) fn new(path: String, columns: Vec<usize>, lanes: Lanes) -> Self {
        // A label per lane from the start (a gap until one is set).
        let count = match &lanes {
            Lanes::Values(v) => v.len(),
            Lanes::Set => 1,
        };
        let labels = vec![String::new(); count];
        Self {
            path,
            columns,
            lanes,
            times_ns: Vec::new(),
            values: Vec::new(),
            states: Vec::new(),
            last: Vec::new(),
            last_at: None,
            last_labels: labels.clone(),
            labels,
        }
    }

    /// The label of a [`Lanes::Set`] series from the next update taken in
    /// on (it changes only where its values do).
    fn set_label(&mut self, label: String) {
        if let [only] = self.labels.as_mut_slice() {
            *only = label;
        }
    }

    /// Takes in the values at `t_ns` from an update's `row`: gathered when
    /// one differs from the last ones (bit for bit, so a NaN that stays NaN
    /// is no change), together with the last ones if those were not
    /// gathered. Whether they changed.
    fn observe(&mut self, t_ns: i64, row: &[f64]) -> bool {
        let same = self.last_at.is_some()
            && self
                .columns
                .iter()
                .zip(&self.last)
                .all(|(&k, last)| row[k].to_bits() == last.to_bits());
        if same {
            self.last_at = Some((t_ns, false));
            return false;
        }
        if let Some((t_last, false)) = self.last_at {
            self.times_ns.push(t_last);
            self.values.extend_from_slice(&self.last);
            self.states.extend_from_slice(&self.last_labels);
        }
        self.last.clear();
        self.last.extend(self.columns.iter().map(|&k| row[k]));
        if let Lanes::Values(lanes) = &self.lanes {
            self.labels = lanes.iter().map(|&k| trace::number(self.last[k])).collect();
        }
        self.times_ns.push(t_ns);
        self.values.extend_from_slice(&self.last);
        self.states.extend_from_slice(&self.labels);
        self.last_labels.clone_from(&self.labels);
        self.last_at = Some((t_ns, true));
        true
    }

    /// Gathers the last values if they are not yet (the plot reaches the end).
    fn close(&mut self) {
        if let Some((t, false)) = self.last_at {
            self.times_ns.push(t);
            self.values.extend_from_slice(&self.last);
            self.states.extend_from_slice(&self.last_labels);
            self.last_at = Some((t, true));
        }
    }

    fn flush(&mut self, rec: &mut Recorder) -> Result<(), RecordingError> {
        if !self.times_ns.is_empty() {
            let lanes = self.labels.len();
            let states = (lanes > 0).then_some((self.states.as_slice(), lanes));
            rec.send_scalars_column(&self.path, &self.times_ns, &self.values, self.columns.len(), states)?;
            self.times_ns.clear();
            self.values.clear();
            self.states.clear();
        }
        Ok(())
    }
}

/// A link's pose gathered where it changes.
struct PoseSeries {
    /// (parent frame, child frame).
    frames: (String, String),
    times_ns: Vec<i64>,
    translations_m: Vec<[f64; 3]>,
    rotations_xyzw: Vec<[f64; 4]>,
    last: Option<([f64; 3], [f64; 4])>,
}

impl PoseSeries {
    fn new(frames: (String, String)) -> Self {
        Self {
            frames,
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

    /// Moves the gathered poses into `times_ns` and `rows` (a transform
    /// between its two frames each).
    fn drain_into(&mut self, times_ns: &mut Vec<i64>, rows: &mut Vec<FrameTransform>) {
        times_ns.append(&mut self.times_ns);
        rows.extend(
            self.translations_m
                .drain(..)
                .zip(self.rotations_xyzw.drain(..))
                .map(|(t, q)| (self.frames.0.clone(), self.frames.1.clone(), t, q)),
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    fn random_pose(rng: &mut impl Rng) -> nalgebra::Isometry3<f64> {
        let axis = nalgebra::Vector3::new(
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
        );
        nalgebra::Isometry3::new(
            nalgebra::Vector3::new(
                rng.random_range(-2.0..2.0),
                rng.random_range(-2.0..2.0),
                rng.random_range(-2.0..2.0),
            ),
            axis * rng.random_range(0.0..3.0),
        )
    }

    fn parts(p: &nalgebra::Isometry3<f64>) -> ([f64; 3], [f64; 4]) {
        let t = p.translation.vector;
        let q = p.rotation.coords;
        ([t.x, t.y, t.z], [q.x, q.y, q.z, q.w])
    }

    #[test]
    fn parent_from_child_equals_the_isometry_product() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(15);
        for _ in 0..1000 {
            let (world_from_parent, world_from_child) = (random_pose(&mut rng), random_pose(&mut rng));
            let expected = parts(&(world_from_parent.inverse() * world_from_child));
            let (t, q) = parent_from_child(parts(&world_from_parent), parts(&world_from_child));
            for k in 0..3 {
                assert!((t[k] - expected.0[k]).abs() < 1e-12, "{t:?} vs {:?}", expected.0);
            }
            // q and −q are the same rotation.
            let sign = if q.iter().zip(expected.1).map(|(a, b)| a * b).sum::<f64>() < 0.0 {
                -1.0
            } else {
                1.0
            };
            for k in 0..4 {
                assert!((sign * q[k] - expected.1[k]).abs() < 1e-12, "{q:?} vs {:?}", expected.1);
            }
        }
    }

    #[test]
    fn a_series_gathers_changes_and_the_sample_before_each() {
        // Two values: the first 0 0 0 1 1 2 2 2 NaN NaN, the second 5
        // throughout except 6 at update 6. Gathered: 0@0, 0@2 (before the
        // change), 1@3, 1@4 (before the change), 2@5, 2 6@6, 2@7, NaN@8;
        // close adds NaN@9.
        let first = [0.0, 0.0, 0.0, 1.0, 1.0, 2.0, 2.0, 2.0, f64::NAN, f64::NAN];
        let second = |t: usize| if t == 6 { 6.0 } else { 5.0 };
        let mut s = Series::new("x".into(), vec![2, 0], Lanes::Values(Vec::new()));
        let mut changes = 0;
        for (t, v) in first.into_iter().enumerate() {
            changes += usize::from(s.observe(t as i64, &[second(t), -1.0, v]));
        }
        s.close();
        assert_eq!(changes, 6, "changes at 0, 3, 5, 6, 7, 8");
        assert_eq!(s.times_ns, [0, 2, 3, 4, 5, 6, 7, 8, 9]);
        assert!(s.states.is_empty(), "no lanes, no states");
        // The latest sample at or before each update is that update's value.
        for (t, v) in first.into_iter().enumerate() {
            let i = s.times_ns.partition_point(|&x| x <= t as i64) - 1;
            assert_eq!(s.values[2 * i].to_bits(), v.to_bits(), "update {t}");
            assert_eq!(s.values[2 * i + 1], second(t), "update {t}");
        }
    }

    #[test]
    fn a_series_lanes_labels_go_with_its_rows() {
        // A value lane on the second value: its label is that value's
        // text at each gathered row, the row before a change included.
        let mut s = Series::new("x".into(), vec![0, 1], Lanes::Values(vec![1]));
        for (t, v) in [(0, 1.0), (1, 1.0), (2, 2.0), (3, 2.0)] {
            s.observe(t, &[0.5, v]);
        }
        s.close();
        assert_eq!(s.times_ns, [0, 1, 2, 3]);
        assert_eq!(s.states, ["1", "1", "2", "2"]);
        // A set lane: the label given before the update that changes.
        let mut s = Series::new("y".into(), vec![0], Lanes::Set);
        s.set_label(String::new());
        s.observe(0, &[0.0]);
        s.observe(1, &[0.0]);
        s.set_label("IP".to_owned());
        s.observe(2, &[1.0]);
        s.close();
        assert_eq!(s.times_ns, [0, 1, 2]);
        assert_eq!(s.states, ["", "", "IP"]);
    }
}
