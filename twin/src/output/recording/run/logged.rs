//! The recording thread's side of a run's recording: the series it keeps
//! per update, what it makes of each batch, and when it sends the
//! gathered samples (the parent module's doc says what and when).

use planner::instruction::{FbOutputs, MotionInstructionBits};

use super::super::{Recorder, RecordingError, Served, TextLevel};
use super::batch::{AXIS_RGBA, Batch, FLUSH_UPDATES, IDLE_FLUSH_UPDATES, Item, LIVE_FLUSH, StaticMesh, TRAIL_RGBA};
use crate::output::COLLISION_TINT_RGBA;
use crate::output::status::{Status, describe};
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
    /// Per URDF joint: (parent link, child link) and the child's pose
    /// relative to its parent.
    poses: Vec<((usize, usize), PoseSeries)>,
    links: usize,
    /// Every scalar series, in the order of [`Batch::values`]: per axis
    /// cmd_pos, act_pos, cmd_vel, act_vel; the drives' torques; traced
    /// tags; clearances.
    scalars: Vec<Series>,
    /// Per function block: its name, outputs then ErrorID, the last outputs.
    fbs: Vec<(String, Vec<Series>, FbOutputs)>,
    /// Per control structure: its name, bits then codes, the last bits.
    instructions: Vec<(String, Vec<Series>, MotionInstructionBits)>,
}

/// A scalar series' path, name and colour in the plots.
pub(super) type Style = (String, String, [f32; 4]);

impl Series {
    /// The series of `twin`'s link poses, axes, drives, instructions, tags
    /// and clearances, and the (path, name, colour) of those plotted with
    /// a name.
    pub(super) fn of(twin: &Twin, link_paths: &[String]) -> (AllSeries, Vec<Style>) {
        let plant = twin.plant();
        let mut styles = Vec::new();
        let mut scalars = Vec::new();
        for (k, a) in plant.axes().iter().enumerate() {
            let color = AXIS_RGBA[k % AXIS_RGBA.len()];
            let lighter = color.map(|c| c + (1.0 - c) * 0.5);
            for (leaf, what, rgba) in [
                ("cmd_pos", "command position", color),
                ("act_pos", "actual position", lighter),
                ("cmd_vel", "command velocity", color),
                ("act_vel", "actual velocity", lighter),
            ] {
                let path = format!("axes/{}/{leaf}", entity_part(&a.name));
                styles.push((path.clone(), format!("{} {what}", a.name), rgba));
                scalars.push(Series::new(path));
            }
        }
        for (k, a) in plant.axes().iter().enumerate() {
            let path = format!("axes/{}/torque", entity_part(&a.name));
            if plant.drive_torque(k).is_some() {
                styles.push((
                    path.clone(),
                    format!("{} torque", a.name),
                    AXIS_RGBA[k % AXIS_RGBA.len()],
                ));
            }
            scalars.push(Series::new(path));
        }
        let program = twin.program();
        scalars.extend(program.traced_tags().iter().map(|t| match &t.entity {
            Some(path) => Series::new(path.clone()),
            None => Series::new(format!("tags/{}", entity_part(&t.name))),
        }));
        if plant.collision_enabled() {
            scalars.extend(
                plant
                    .collision_bodies()
                    .iter()
                    .map(|b| Series::new(format!("collisions/clearance/{}", entity_part(b)))),
            );
        }
        let fbs = program
            .fbs()
            .iter()
            .map(|fb| status_series(&fb.name, FbOutputs::default()))
            .collect();
        let instructions = program
            .instructions()
            .iter()
            .map(|ins| status_series(&ins.name, MotionInstructionBits::default()))
            .collect();
        let model = plant.model();
        let poses = model
            .joints
            .iter()
            .map(|j| ((j.parent.0, j.child.0), PoseSeries::new(link_paths[j.child.0].clone())))
            .collect();
        let series = AllSeries {
            poses,
            links: model.links.len(),
            scalars,
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

    /// The recording thread: logs the static meshes and the series'
    /// styles, takes in batches until the run's side closes the channel,
    /// then sends the last samples and closes the stream.
    pub(super) fn run(
        mut self,
        meshes: &[StaticMesh],
        styles: &[Style],
        batches: &std::sync::mpsc::Receiver<Batch>,
        returns: &std::sync::mpsc::Sender<Batch>,
    ) -> Result<Served, RecordingError> {
        self.recorder.set_time_ns(0);
        for (path, mesh, rgba, local) in meshes {
            self.recorder.log_link_mesh_static(path, mesh, *rgba, *local)?;
        }
        for (path, name, rgba) in styles {
            self.recorder.log_series_style(path, name, *rgba)?;
        }
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
        for series in self.all_scalars() {
            series.close();
        }
        self.flush()?;
        self.recorder.finish()
    }

    /// Takes in a batch: every update's samples, the instruction log lines
    /// of what changed, and the items in order.
    fn take(&mut self, batch: &mut Batch) -> Result<(), RecordingError> {
        let scalars = self.series.scalars.len();
        let (fbs, instructions) = (self.series.fbs.len(), self.series.instructions.len());
        let mut items = batch.items.drain(..).peekable();
        for (u, &t) in batch.times_ns.iter().enumerate() {
            while let Some((_, t_item, item)) = items.next_if(|(before, _, _)| *before <= u) {
                self.log_item(t_item, item)?;
            }
            self.recorder.set_time_ns(t);
            let poses = &batch.world_from_link[u * self.series.links..(u + 1) * self.series.links];
            for ((parent, child), series) in &mut self.series.poses {
                let (translation, rotation) = parent_from_child(poses[*parent], poses[*child]);
                series.observe(t, translation, rotation);
            }
            for (series, value) in self
                .series
                .scalars
                .iter_mut()
                .zip(&batch.values[u * scalars..(u + 1) * scalars])
            {
                if let Some(v) = value {
                    series.observe(t, *v);
                }
            }
            let recorder = &mut self.recorder;
            observe_statuses(recorder, t, &mut self.series.fbs, &batch.fbs[u * fbs..(u + 1) * fbs])?;
            let updated = &batch.instructions[u * instructions..(u + 1) * instructions];
            observe_statuses(recorder, t, &mut self.series.instructions, updated)?;
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

    /// Every scalar series: axes, drives, tags, clearances, then the
    /// instructions'.
    fn all_scalars(&mut self) -> impl Iterator<Item = &mut Series> {
        self.scalar_series().1
    }

    /// The recorder, and every scalar series.
    fn scalar_series(&mut self) -> (&mut Recorder, impl Iterator<Item = &mut Series>) {
        let scalars = self
            .series
            .scalars
            .iter_mut()
            .chain(self.series.fbs.iter_mut().flat_map(|(_, s, _)| s))
            .chain(self.series.instructions.iter_mut().flat_map(|(_, s, _)| s));
        (&mut self.recorder, scalars)
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
            Item::Clear { path } => r.log_clear(&path),
            Item::Mesh { path, mesh } => r.log_mesh_timed(&path, &mesh, COLLISION_TINT_RGBA),
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
        }
    }

    /// Every series' gathered samples, one column each; then everything
    /// on its way to the sinks.
    fn flush(&mut self) -> Result<(), RecordingError> {
        self.pending_updates = 0;
        if let Some(at) = &mut self.live {
            *at = std::time::Instant::now();
        }
        for (_, pose) in &mut self.series.poses {
            pose.flush(&mut self.recorder)?;
        }
        let (recorder, scalars) = self.scalar_series();
        for series in scalars {
            series.flush(recorder)?;
        }
        self.recorder.flush_async()
    }
}

/// Takes in one update's outputs of the function blocks or control
/// structures: each one's series sample its bits then its codes, and a
/// change of its outputs is a line of the instruction log.
fn observe_statuses<S: Status>(
    recorder: &mut Recorder,
    t_ns: i64,
    rows: &mut [(String, Vec<Series>, S)],
    update: &[S],
) -> Result<(), RecordingError> {
    for ((name, series, previous), status) in rows.iter_mut().zip(update) {
        let values = status
            .named_bits()
            .map(|(_, bit)| f64::from(u8::from(bit)))
            .chain(status.named_codes().map(|(_, code)| code));
        for (s, v) in series.iter_mut().zip(values) {
            s.observe(t_ns, v);
        }
        if std::mem::replace(previous, *status) != *status {
            let level = if status.failed() {
                TextLevel::Error
            } else {
                TextLevel::Info
            };
            recorder.log_text("instructions/log", level, &format!("{name}: {}", describe(*status)))?;
        }
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

/// A function block's or control structure's series (its bits, then its
/// codes), with the outputs it starts from.
fn status_series<S: Status>(name: &str, start: S) -> (String, Vec<Series>, S) {
    let part = entity_part(name);
    let series = start
        .named_bits()
        .map(|(leaf, _)| leaf)
        .chain(start.named_codes().map(|(leaf, _)| leaf))
        .map(|leaf| Series::new(format!("instructions/{part}/{leaf}")))
        .collect();
    (name.to_owned(), series, start)
}

/// A name as one entity-path part (a `/`, `.` or space stays inside it).
pub(super) fn entity_part(name: &str) -> String {
    rerun::EntityPathPart::new(name).escaped_string()
}

/// A scalar series gathered where it changes (module doc).
pub(super) struct Series {
    path: String,
    times_ns: Vec<i64>,
    values: Vec<f64>,
    /// The last sample taken in, and whether it is gathered.
    last: Option<(i64, f64, bool)>,
}

impl Series {
    pub(super) fn new(path: String) -> Self {
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
        let mut s = Series::new("x".into());
        // 0 0 0 1 1 2 2 2 NaN NaN: gathered 0@0, 0@2 (before the change), 1@3,
        // 1@4, 2@5, 2@7, NaN@8; close adds NaN@9.
        for (t, v) in [0.0, 0.0, 0.0, 1.0, 1.0, 2.0, 2.0, 2.0, f64::NAN, f64::NAN]
            .into_iter()
            .enumerate()
        {
            s.observe(t as i64, v);
        }
        s.close();
        assert_eq!(s.times_ns, [0, 2, 3, 4, 5, 7, 8, 9]);
        let expected = [0.0, 0.0, 1.0, 1.0, 2.0, 2.0, f64::NAN, f64::NAN];
        assert!(
            s.values.iter().zip(expected).all(|(a, b)| a.to_bits() == b.to_bits()),
            "{:?}",
            s.values
        );
        // The latest sample at or before each update is that update's value.
        for (t, v) in [0.0, 0.0, 0.0, 1.0, 1.0, 2.0, 2.0, 2.0, f64::NAN, f64::NAN]
            .into_iter()
            .enumerate()
        {
            let i = s.times_ns.partition_point(|&x| x <= t as i64) - 1;
            assert_eq!(s.values[i].to_bits(), v.to_bits(), "update {t}");
        }
    }
}
