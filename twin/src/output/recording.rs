//! Rerun recordings of a twin run: robot meshes, link transforms, scalar
//! series, text logs and tool-centre trails, saved to an `.rrd` file and/or
//! streamed to a live Rerun viewer over gRPC.
//!
//! # Layout of a recording
//!
//! - A URDF robot is logged the way Rerun's own URDF importer logs it (so
//!   that `rerun robot.urdf` and a twin recording share entity paths and
//!   frames, and a layout saved for one applies to the other): the root
//!   entity `<robot name>` in the root link's named frame; each visual at
//!   `<robot>/visual_geometries/<link>/<name or visual_i>` in its link's
//!   frame (the link's name), placed by an instance pose; the joints'
//!   origins at [`TF_STATIC_ENTITY`]; the joints' motion (and the root
//!   link's pose in the world, [`WORLD_FRAME`]) as transforms between the
//!   named frames at [`TRANSFORMS_ENTITY`].
//! - `RIGHT_HAND_Z_UP` view coordinates are logged once (static) at the root
//!   `/`: URDF and every [`TriMesh`] here are Z-up.
//! - Everything that changes over time is logged on the [`SIM_TIME_TIMELINE`]
//!   (`sim_time`), a duration timeline in seconds of simulated time, set with
//!   [`Recorder::set_time_s`]. It is the only timeline: Rerun's wall-clock
//!   `log_time` is switched off (a replay's wall clock means nothing, and
//!   each timeline costs the file's footer an index column per component).
//!
//! # Sinks
//!
//! A [`Recorder`] can write to several [`Sink`](sinks::Sink)s at once (for example `--save`
//! and `--connect` together); Rerun then tees every message to each of them.
//!
//! Choices made here where Rerun leaves room:
//! - [`Sink::Connect`](sinks::Sink::Connect) checks that something accepts TCP connections at the
//!   address before the stream is created, and fails with
//!   [`RecordingError::Connect`] if not. Rerun's own gRPC client would instead
//!   retry in the background and buffer; once its queue is full, logging
//!   blocks, which would stall a simulation whose viewer is not running. A
//!   viewer that goes away *during* a run is still Rerun's business (it
//!   retries, and [`Recorder::finish`] reports a failed flush).
//! - An `.rrd` file only gets its footer when its sink is dropped, so
//!   [`Recorder::finish`] must be called before the process exits.

use std::time::Duration;

use rerun::sink::SinkFlushError;
use rerun::{RecordingStream, TimeCell};

use crate::plant::mesh::TriMesh;

mod error;
pub mod run;
pub mod sinks;

pub use error::{MeshDefect, Quantity, RecordingError};

/// What [`Recorder::finish`] leaves running: the [`Sink::Serve`](sinks::Sink::Serve) servers,
/// if any.
#[derive(Default)]
pub struct Served {
    stream: Option<RecordingStream>,
    addresses: Vec<String>,
}

impl std::fmt::Debug for Served {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Served")
            .field("addresses", &self.addresses)
            .finish_non_exhaustive()
    }
}

impl Served {
    /// The servers' addresses (`rerun+http://host:port/proxy`), for
    /// `rerun --connect`; empty when nothing is served.
    pub fn addresses(&self) -> &[String] {
        &self.addresses
    }

    /// Serves for as long as the process lives (Ctrl-C ends it); returns at
    /// once when nothing is served.
    pub fn wait(self) {
        if self.stream.is_some() {
            loop {
                std::thread::park();
            }
        }
    }
}

/// Name of the timeline carrying simulated time (a duration timeline).
pub const SIM_TIME_TIMELINE: &str = "sim_time";

/// Where the joints' origins are logged (static), as Rerun's URDF
/// importer logs them.
pub const TF_STATIC_ENTITY: &str = "tf_static";

/// Where the joints' and the root link's transforms are logged over time,
/// as Rerun's URDF examples log them.
pub const TRANSFORMS_ENTITY: &str = "transforms";

/// The world's frame: the implicit frame of the root entity `/`, which the
/// obstacles, trails and parts are in and the robot's root link is placed in.
pub const WORLD_FRAME: &str = "tf#/";

/// How long [`Recorder::finish`] waits for all sinks to take the pending data.
const FINISH_FLUSH_TIMEOUT: Duration = Duration::from_secs(20);

/// Severity of a [`Recorder::log_text`] entry (Rerun's standard levels).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[non_exhaustive]
pub enum TextLevel {
    /// Fine-grained tracing.
    Trace,
    /// Debugging detail.
    Debug,
    /// Normal progress (instruction started, done).
    Info,
    /// Something unexpected that the run survived.
    Warn,
    /// A failure (an instruction error, a collision).
    Error,
    /// A failure that stops the run.
    Critical,
}

impl TextLevel {
    /// Rerun's name for this level.
    pub fn as_str(self) -> &'static str {
        use rerun::components::TextLogLevel;
        match self {
            Self::Trace => TextLogLevel::TRACE,
            Self::Debug => TextLogLevel::DEBUG,
            Self::Info => TextLogLevel::INFO,
            Self::Warn => TextLogLevel::WARN,
            Self::Error => TextLogLevel::ERROR,
            Self::Critical => TextLogLevel::CRITICAL,
        }
    }
}

/// A live Rerun recording stream of one twin run.
///
/// Logging calls are cheap: Rerun batches and writes on background threads.
/// Call [`Recorder::finish`] at the end of the run.
pub struct Recorder {
    stream: RecordingStream,
    /// Current `sim_time` in nanoseconds; `None` before the first [`Recorder::set_time_s`].
    sim_time_ns: Option<i64>,
    /// Human-readable list of the sinks, for errors.
    sink_names: String,
    /// The addresses of the [`Sink::Serve`](sinks::Sink::Serve) servers.
    served: Vec<String>,
}

impl std::fmt::Debug for Recorder {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Recorder")
            .field("sinks", &self.sink_names)
            .field("sim_time_ns", &self.sim_time_ns)
            .finish_non_exhaustive()
    }
}

/// Simulated seconds as the `sim_time` index, in nanoseconds (`None` for a
/// NaN or infinite time).
pub fn sim_time_ns(sim_time_s: f64) -> Option<i64> {
    // `as` saturates; ±292 years of simulated time is plenty.
    sim_time_s.is_finite().then(|| (sim_time_s * 1e9).round() as i64)
}

impl Recorder {
    /// Sets the `sim_time` of everything logged afterwards, in seconds of
    /// simulated time. Negative times are allowed; a NaN or infinite time is
    /// ignored (the previous time stays).
    pub fn set_time_s(&mut self, sim_time_s: f64) {
        if let Some(ns) = sim_time_ns(sim_time_s) {
            self.sim_time_ns = Some(ns);
        }
    }

    /// Sets the `sim_time` of everything logged afterwards, in nanoseconds.
    pub fn set_time_ns(&mut self, sim_time_ns: i64) {
        self.sim_time_ns = Some(sim_time_ns);
    }

    /// Starts sending everything logged so far on to the sinks, without
    /// waiting (Rerun otherwise gathers small logs for up to 200 ms).
    ///
    /// # Errors
    ///
    /// [`RecordingError::Flush`] when a sink has already failed.
    pub fn flush_async(&self) -> Result<(), RecordingError> {
        self.stream.flush_async().map_err(|source| RecordingError::Flush {
            sinks: self.sink_names.clone(),
            source,
        })
    }

    /// The current `sim_time` in nanoseconds (the index of everything
    /// logged now), if [`Self::set_time_s`] has been called.
    pub fn time_ns(&self) -> Option<i64> {
        self.sim_time_ns
    }

    /// The current `sim_time` in seconds, if [`Self::set_time_s`] has been called.
    pub fn time_s(&self) -> Option<f64> {
        self.sim_time_ns.map(|ns| ns as f64 * 1e-9)
    }

    /// Logs a mesh once, as static data, at `entity_path` (a world-fixed
    /// part: an obstacle, a conveyor), with its fixed `parent_from_mesh`
    /// transform relative to the parent entity: translation in metres,
    /// rotation as an `xyzw` quaternion, per-axis scale. `color_rgba` is
    /// sRGB with alpha, each channel in `0..=1` (clamped).
    ///
    /// # Errors
    ///
    /// [`RecordingError::InvalidMesh`] for malformed meshes,
    /// [`RecordingError::InvalidValue`] for a non-finite or degenerate
    /// transform, [`RecordingError::Log`] if Rerun refuses the data.
    pub fn log_link_mesh_static(
        &mut self,
        entity_path: &str,
        mesh: &TriMesh,
        color_rgba: [f32; 4],
        local_from_mesh: ([f32; 3], [f32; 4], [f32; 3]),
    ) -> Result<(), RecordingError> {
        use rerun::archetypes::Transform3D;

        check_mesh(mesh).map_err(|defect| RecordingError::InvalidMesh {
            entity_path: entity_path.to_owned(),
            defect,
        })?;
        let (translation, rotation_xyzw, scale) = local_from_mesh;
        let invalid = |quantity| RecordingError::InvalidValue {
            entity_path: entity_path.to_owned(),
            quantity,
        };
        if !translation.iter().all(|v| v.is_finite()) {
            return Err(invalid(Quantity::Translation));
        }
        if !scale.iter().all(|v| v.is_finite() && *v != 0.0) {
            return Err(invalid(Quantity::Scale));
        }
        let rotation = unit_quaternion(rotation_xyzw.map(f64::from)).ok_or_else(|| invalid(Quantity::Rotation))?;

        let mesh_from_link = Transform3D::from_translation_rotation_scale(
            translation,
            rerun::datatypes::Quaternion::from_xyzw(rotation),
            scale,
        );
        let archetype = mesh_archetype(mesh, color_rgba);
        self.log_static(entity_path, &[&mesh_from_link as &dyn rerun::AsComponents, &archetype])
    }

    /// Logs a robot link's visual mesh once, as static data, the way
    /// Rerun's URDF importer lays it out: at `entity_path`
    /// ([`visual_entity_path`]) in the link's named frame `frame` (the link's
    /// name), placed in it by `link_from_mesh` (translation in metres,
    /// `xyzw` rotation) as an instance pose. `color_rgba` as in
    /// [`Self::log_link_mesh_static`].
    ///
    /// # Errors
    ///
    /// [`RecordingError::InvalidMesh`] for a malformed mesh,
    /// [`RecordingError::InvalidValue`] for a non-finite or degenerate pose,
    /// [`RecordingError::Log`] if Rerun refuses the data.
    pub fn log_visual_static(
        &mut self,
        entity_path: &str,
        frame: &str,
        mesh: &TriMesh,
        color_rgba: [f32; 4],
        link_from_mesh: ([f64; 3], [f64; 4]),
    ) -> Result<(), RecordingError> {
        check_mesh(mesh).map_err(|defect| RecordingError::InvalidMesh {
            entity_path: entity_path.to_owned(),
            defect,
        })?;
        let (translation, rotation) = checked_pose(entity_path, link_from_mesh)?;
        let pose = rerun::archetypes::InstancePoses3D::new()
            .with_translations([translation])
            .with_quaternions([rotation]);
        // One call: one chunk (a chunk costs the file writer more than its bytes).
        let frame = rerun::archetypes::CoordinateFrame::new(frame);
        let mesh = mesh_archetype(mesh, color_rgba);
        self.log_static(entity_path, &[&frame as &dyn rerun::AsComponents, &pose, &mesh])
    }

    /// Logs, static, that `entity_path` and what it holds are in the named
    /// frame `frame`.
    ///
    /// # Errors
    ///
    /// [`RecordingError::Log`] if Rerun refuses the data.
    pub fn log_frame_static(&mut self, entity_path: &str, frame: &str) -> Result<(), RecordingError> {
        self.log_static(entity_path, &rerun::archetypes::CoordinateFrame::new(frame))
    }

    /// Logs, static and in one chunk, transforms between named frames:
    /// each row is (parent frame, child frame, `parent_from_child`
    /// translation in metres, `xyzw` rotation). Rerun's URDF importer logs
    /// a robot's joint origins so, at `tf_static`.
    ///
    /// # Errors
    ///
    /// [`RecordingError::InvalidValue`] for a non-finite or degenerate
    /// pose, [`RecordingError::Log`] if Rerun refuses the data.
    pub fn send_static_frame_transforms(
        &mut self,
        entity_path: &str,
        rows: &[FrameTransform],
    ) -> Result<(), RecordingError> {
        let columns = frame_transform_columns(entity_path, rows)?;
        self.stream
            .send_columns(entity_path, [], columns)
            .map_err(|source| RecordingError::Log {
                entity_path: entity_path.to_owned(),
                source,
            })
    }

    /// Logs a whole column of transforms from the named frame `child` to
    /// `parent` in one chunk at `entity_path` (many frames may share the
    /// entity, as Rerun's URDF examples do with `transforms`): row `i` at
    /// `sim_time` `times_ns[i]` (ns).
    ///
    /// # Errors
    ///
    /// [`RecordingError::InvalidValue`] for a non-finite or degenerate
    /// pose, [`RecordingError::Log`] if Rerun refuses the data.
    pub fn send_frame_transform_column(
        &mut self,
        entity_path: &str,
        times_ns: &[i64],
        rows: &[FrameTransform],
    ) -> Result<(), RecordingError> {
        if times_ns.len() != rows.len() {
            return Err(RecordingError::InvalidValue {
                entity_path: entity_path.to_owned(),
                quantity: Quantity::ColumnLength,
            });
        }
        let columns = frame_transform_columns(entity_path, rows)?;
        self.send_timed_columns(entity_path, times_ns, Ok(columns))
    }

    /// Logs a whole column of a series of `width` values at `entity_path` in
    /// one chunk: `values[i * width..(i + 1) * width]` at `sim_time`
    /// `times_ns[i]` (ns). Each of the `width` values is its own line in a
    /// plot, named by [`Self::log_series_styles`]. With `states` (labels,
    /// lanes), row `i`'s labels `labels[i * lanes..(i + 1) * lanes]` go in
    /// the same chunk as the entity's state lanes (`StateChange`; an empty
    /// label is a gap).
    ///
    /// # Errors
    ///
    /// [`RecordingError::InvalidValue`] when the lengths disagree,
    /// [`RecordingError::Log`] if Rerun refuses the data.
    pub fn send_scalars_column(
        &mut self,
        entity_path: &str,
        times_ns: &[i64],
        values: &[f64],
        width: usize,
        states: Option<(&[String], usize)>,
    ) -> Result<(), RecordingError> {
        let rows = times_ns.len();
        let states_fit =
            states.is_none_or(|(labels, lanes)| lanes > 0 && rows.checked_mul(lanes) == Some(labels.len()));
        if width == 0 || rows.checked_mul(width) != Some(values.len()) || !states_fit {
            return Err(RecordingError::InvalidValue {
                entity_path: entity_path.to_owned(),
                quantity: Quantity::ColumnLength,
            });
        }
        let scalars = rerun::archetypes::Scalars::new(values.iter().copied()).columns(std::iter::repeat_n(width, rows));
        let columns: Result<Vec<rerun::SerializedComponentColumn>, _> = match states {
            None => scalars.map(Iterator::collect),
            Some((labels, lanes)) => scalars.and_then(|scalars| {
                let states = rerun::archetypes::StateChange::new()
                    .with_state(labels.iter().map(String::as_str))
                    .columns(std::iter::repeat_n(lanes, rows))?;
                Ok(scalars.chain(states).collect())
            }),
        };
        self.send_timed_columns(entity_path, times_ns, columns)
    }

    /// Names and colours the lines of the series at `entity_path`, one per
    /// value (static).
    ///
    /// # Errors
    ///
    /// [`RecordingError::Log`] if Rerun refuses the data.
    pub fn log_series_styles(
        &mut self,
        entity_path: &str,
        names: &[String],
        colors_rgba: &[[f32; 4]],
    ) -> Result<(), RecordingError> {
        let style = rerun::archetypes::SeriesLines::new()
            .with_names(names.iter().map(String::as_str))
            .with_colors(colors_rgba.iter().map(|c| rgba32(*c)));
        self.log_static(entity_path, &style)
    }

    /// Logs the state `label` of `entity_path` from the current `sim_time`
    /// on (a lane of Rerun's state timeline view; an empty label is a gap).
    ///
    /// # Errors
    ///
    /// [`RecordingError::Log`] if Rerun refuses the data.
    pub fn log_state(&mut self, entity_path: &str, label: &str) -> Result<(), RecordingError> {
        self.log_timed(entity_path, &rerun::archetypes::StateChange::single(label))
    }

    /// Logs a Markdown document once, static.
    ///
    /// # Errors
    ///
    /// [`RecordingError::Log`] if Rerun refuses the data.
    pub fn log_markdown_static(&mut self, entity_path: &str, markdown: &str) -> Result<(), RecordingError> {
        let document =
            rerun::archetypes::TextDocument::new(markdown).with_media_type(rerun::components::MediaType::markdown());
        self.log_static(entity_path, &document)
    }

    /// Logs a pinhole camera once, static, with its pose in the world
    /// (`world_from_camera`, the camera looking along +Z with +X right and
    /// +Y down), its vertical field of view (radians) and its image size in
    /// pixels.
    ///
    /// # Errors
    ///
    /// [`RecordingError::InvalidValue`] for a non-finite or degenerate
    /// pose, [`RecordingError::Log`] if Rerun refuses the data.
    pub fn log_camera_static(
        &mut self,
        entity_path: &str,
        world_from_camera: ([f64; 3], [f64; 4]),
        fov_y_rad: f64,
        size_px: [u32; 2],
    ) -> Result<(), RecordingError> {
        let (translation, rotation) = checked_pose(entity_path, world_from_camera)?;
        let pose = rerun::archetypes::Transform3D::from_translation_rotation(translation, rotation);
        let [w, h] = size_px;
        let pinhole = rerun::archetypes::Pinhole::from_fov_and_aspect_ratio(fov_y_rad as f32, w as f32 / h as f32)
            .with_resolution([w as f32, h as f32])
            .with_image_plane_distance(0.15);
        self.log_static(entity_path, &[&pose as &dyn rerun::AsComponents, &pinhole])
    }

    /// Logs an 8-bit RGB image (rows top to bottom) at the current `sim_time`.
    ///
    /// # Errors
    ///
    /// [`RecordingError::InvalidValue`] when the bytes do not fill the
    /// size, [`RecordingError::Log`] if Rerun refuses the data.
    pub fn log_rgb_image(&mut self, entity_path: &str, rgb: Vec<u8>, size_px: [u32; 2]) -> Result<(), RecordingError> {
        if rgb.len() as u64 != 3 * u64::from(size_px[0]) * u64::from(size_px[1]) {
            return Err(RecordingError::InvalidValue {
                entity_path: entity_path.to_owned(),
                quantity: Quantity::ColumnLength,
            });
        }
        self.log_timed(entity_path, &rerun::archetypes::Image::from_rgb24(rgb, size_px))
    }

    /// Logs the pose of the entity relative to its parent entity
    /// (`parent_from_entity`): translation in metres, rotation as an `xyzw`
    /// quaternion (normalised here), at the current `sim_time`.
    ///
    /// # Errors
    ///
    /// [`RecordingError::InvalidValue`] for a NaN/infinite translation or a
    /// zero/non-finite quaternion, [`RecordingError::Log`] if Rerun refuses.
    pub fn log_transform(
        &mut self,
        entity_path: &str,
        translation_m: [f64; 3],
        rotation_xyzw: [f64; 4],
    ) -> Result<(), RecordingError> {
        let (translation, rotation) = checked_pose(entity_path, (translation_m, rotation_xyzw))?;
        let transform = rerun::archetypes::Transform3D::from_translation_rotation(translation, rotation);
        self.log_timed(entity_path, &transform)
    }

    /// Sends serialized component columns as one chunk at `entity_path`,
    /// indexed by `sim_time` `times_ns` (ns).
    fn send_timed_columns(
        &mut self,
        entity_path: &str,
        times_ns: &[i64],
        columns: rerun::SerializationResult<impl IntoIterator<Item = rerun::SerializedComponentColumn>>,
    ) -> Result<(), RecordingError> {
        let log_error = |source| RecordingError::Log {
            entity_path: entity_path.to_owned(),
            source,
        };
        let time = rerun::log::TimeColumn::new_duration_nanos(SIM_TIME_TIMELINE, times_ns.iter().copied());
        self.stream
            .send_columns(entity_path, [time], columns.map_err(|e| log_error(e.into()))?)
            .map_err(log_error)
    }

    /// Logs a text entry at the current `sim_time`.
    ///
    /// # Errors
    ///
    /// [`RecordingError::Log`] if Rerun refuses the data.
    pub fn log_text(&mut self, entity_path: &str, level: TextLevel, text: &str) -> Result<(), RecordingError> {
        let entry = rerun::archetypes::TextLog::new(text).with_level(level.as_str());
        self.log_timed(entity_path, &entry)
    }

    /// Logs a polyline (metres, in the entity's frame) at the current
    /// `sim_time`, replacing the previous one at that path; e.g. the
    /// tool-centre trail so far. `color_rgba` as in
    /// [`Self::log_link_mesh_static`].
    ///
    /// # Errors
    ///
    /// [`RecordingError::InvalidValue`] for a NaN/infinite point,
    /// [`RecordingError::Log`] if Rerun refuses the data.
    pub fn log_line_strip(
        &mut self,
        entity_path: &str,
        points_m: &[[f64; 3]],
        color_rgba: [f32; 4],
    ) -> Result<(), RecordingError> {
        if !points_m.iter().flatten().all(|v| v.is_finite()) {
            return Err(RecordingError::InvalidValue {
                entity_path: entity_path.to_owned(),
                quantity: Quantity::Point,
            });
        }
        // Rerun stores positions as f32; millimetre-level precision within
        // kilometres is plenty for a work cell.
        let strip: Vec<[f32; 3]> = points_m.iter().map(|p| p.map(|v| v as f32)).collect();
        let strips = rerun::archetypes::LineStrips3D::new([strip])
            .with_colors([rgba32(color_rgba)])
            .with_radii([rerun::components::Radius::new_ui_points(1.5)]);
        self.log_timed(entity_path, &strips)
    }

    /// Logs arrows (e.g. contact normals) at the current `sim_time`,
    /// replacing the previous ones at that path: `origins_m` in the entity's
    /// frame, `vectors_m` from each origin. Empty slices clear the arrows.
    ///
    /// # Errors
    ///
    /// [`RecordingError::InvalidValue`] for a NaN/infinite value,
    /// [`RecordingError::Log`] if Rerun refuses the data.
    pub fn log_arrows(
        &mut self,
        entity_path: &str,
        origins_m: &[[f64; 3]],
        vectors_m: &[[f64; 3]],
        color_rgba: [f32; 4],
    ) -> Result<(), RecordingError> {
        if !origins_m.iter().chain(vectors_m).flatten().all(|v| v.is_finite()) {
            return Err(RecordingError::InvalidValue {
                entity_path: entity_path.to_owned(),
                quantity: Quantity::Point,
            });
        }
        let f32s = |v: &[[f64; 3]]| -> Vec<[f32; 3]> { v.iter().map(|p| p.map(|x| x as f32)).collect() };
        let arrows = rerun::archetypes::Arrows3D::from_vectors(f32s(vectors_m))
            .with_origins(f32s(origins_m))
            .with_colors([rgba32(color_rgba)]);
        self.log_timed(entity_path, &arrows)
    }

    /// Logs a mesh at the current `sim_time` (e.g. a highlight over a
    /// colliding link), in the entity's frame, with one colour.
    ///
    /// # Errors
    ///
    /// [`RecordingError::InvalidMesh`] for a malformed mesh,
    /// [`RecordingError::Log`] if Rerun refuses the data.
    pub fn log_mesh_timed(
        &mut self,
        entity_path: &str,
        mesh: &TriMesh,
        color_rgba: [f32; 4],
    ) -> Result<(), RecordingError> {
        check_mesh(mesh).map_err(|defect| RecordingError::InvalidMesh {
            entity_path: entity_path.to_owned(),
            defect,
        })?;
        self.log_timed(entity_path, &mesh_archetype(mesh, color_rgba))
    }

    /// Clears what an entity and its children show from the current `sim_time` on.
    ///
    /// # Errors
    ///
    /// [`RecordingError::Log`] if Rerun refuses the data.
    pub fn log_clear(&mut self, entity_path: &str) -> Result<(), RecordingError> {
        self.log_timed(entity_path, &rerun::archetypes::Clear::recursive())
    }

    /// Flushes everything to every sink and closes the stream, which writes
    /// the `.rrd` footer. Must be called before the process exits; dropping a
    /// `Recorder` also closes the stream but cannot report errors.
    ///
    /// # Errors
    ///
    /// [`RecordingError::Flush`] when not everything reached the sinks (a
    /// viewer that went away, a full disk, or a timeout of 20 s). The stream
    /// is closed and the file finished either way.
    ///
    /// With a [`Sink::Serve`](sinks::Sink::Serve) server, the files are finished and the stream
    /// stays open: the returned [`Served`] keeps the server up.
    pub fn finish(self) -> Result<Served, RecordingError> {
        let Self {
            stream,
            sink_names,
            served,
            ..
        } = self;
        let flushed = stream.flush_with_timeout(FINISH_FLUSH_TIMEOUT);
        // Closes the file sinks now, which writes their footers, whatever the
        // viewer connections are doing.
        stream.finalize_deferred_sinks();
        if !served.is_empty() {
            return match flushed {
                Ok(()) => Ok(Served {
                    stream: Some(stream),
                    addresses: served,
                }),
                Err(source) => Err(RecordingError::Flush {
                    sinks: sink_names,
                    source,
                }),
            };
        }
        // Dropping the last handle shuts down the gRPC clients, and Rerun waits
        // without limit for a viewer that is connected but stuck. Do it on a
        // helper thread and stop waiting after a while: the files are complete.
        let (done_tx, done_rx) = std::sync::mpsc::channel();
        let dropper = std::thread::Builder::new()
            .name("twin_recording_close".to_owned())
            .spawn(move || {
                drop(stream);
                done_tx.send(()).ok();
            });
        let closed = match dropper {
            Ok(_) => done_rx.recv_timeout(FINISH_FLUSH_TIMEOUT).is_ok(),
            // No thread: the stream was dropped with the failed closure; assume closed.
            Err(_) => true,
        };
        match (flushed, closed) {
            (Ok(()), true) => Ok(Served::default()),
            (Err(source), _) => Err(RecordingError::Flush {
                sinks: sink_names,
                source,
            }),
            (Ok(()), false) => Err(RecordingError::Flush {
                sinks: sink_names,
                source: SinkFlushError::Timeout,
            }),
        }
    }

    fn log_static(&mut self, entity_path: &str, archetype: &impl rerun::AsComponents) -> Result<(), RecordingError> {
        self.stream
            .log_static(entity_path, archetype)
            .map_err(|source| RecordingError::Log {
                entity_path: entity_path.to_owned(),
                source,
            })
    }

    fn log_timed(&mut self, entity_path: &str, archetype: &impl rerun::AsComponents) -> Result<(), RecordingError> {
        // Rerun keeps the current time per thread; setting it on every call
        // keeps `sim_time` right even when the Recorder moves between threads.
        if let Some(ns) = self.sim_time_ns {
            self.stream
                .set_time(SIM_TIME_TIMELINE, TimeCell::from_duration_nanos(ns));
        }
        self.stream
            .log(entity_path, archetype)
            .map_err(|source| RecordingError::Log {
                entity_path: entity_path.to_owned(),
                source,
            })
    }
}

/// The robot's root entity, as Rerun's URDF importer names it: the
/// `<robot name>` of the URDF, one entity-path part.
pub fn robot_entity_path(robot_name: &str) -> String {
    rerun::EntityPathPart::new(robot_name).escaped_string()
}

/// The entity of a link's visual, as Rerun's URDF importer names it:
/// `<robot>/visual_geometries/<link>/<name>`, the visual's `name`
/// attribute or `visual_<index>` (its index among the link's visuals).
/// Names are escaped as entity-path parts, so a `/` or space in a URDF
/// name does not split the path.
///
/// # Examples
///
/// ```
/// use twin::output::recording::{robot_entity_path, visual_entity_path};
/// let robot = robot_entity_path("scara");
/// assert_eq!(visual_entity_path(&robot, "forearm", None, 1), "scara/visual_geometries/forearm/visual_1");
/// assert_eq!(visual_entity_path(&robot, "base link", Some("column"), 0), "scara/visual_geometries/base\\ link/column");
/// ```
pub fn visual_entity_path(robot_path: &str, link: &str, name: Option<&str>, index: usize) -> String {
    let part = |name: &str| rerun::EntityPathPart::new(name).escaped_string();
    let visual = name.map_or_else(|| format!("visual_{index}"), part);
    format!("{robot_path}/visual_geometries/{}/{visual}", part(link))
}

/// A pose (translation in metres, `xyzw` rotation) as Rerun stores it,
/// the rotation normalised: [`RecordingError::InvalidValue`] naming
/// `entity_path` for a NaN or infinite translation, or a zero or
/// non-finite quaternion.
fn checked_pose(
    entity_path: &str,
    (translation_m, rotation_xyzw): ([f64; 3], [f64; 4]),
) -> Result<([f32; 3], rerun::datatypes::Quaternion), RecordingError> {
    let invalid = |quantity| RecordingError::InvalidValue {
        entity_path: entity_path.to_owned(),
        quantity,
    };
    if !translation_m.iter().all(|v| v.is_finite()) {
        return Err(invalid(Quantity::Translation));
    }
    let rotation = unit_quaternion(rotation_xyzw).ok_or_else(|| invalid(Quantity::Rotation))?;
    Ok((
        translation_m.map(|v| v as f32),
        rerun::datatypes::Quaternion::from_xyzw(rotation),
    ))
}

/// A transform between two named frames: parent frame, child frame,
/// `parent_from_child` translation in metres and `xyzw` rotation.
pub type FrameTransform = (String, String, [f64; 3], [f64; 4]);

/// The columns of [`FrameTransform`] rows, checked.
fn frame_transform_columns(
    entity_path: &str,
    rows: &[FrameTransform],
) -> Result<Vec<rerun::SerializedComponentColumn>, RecordingError> {
    let invalid = |quantity| RecordingError::InvalidValue {
        entity_path: entity_path.to_owned(),
        quantity,
    };
    if !rows.iter().flat_map(|r| r.2).all(f64::is_finite) {
        return Err(invalid(Quantity::Translation));
    }
    let rotations = rows
        .iter()
        .map(|r| unit_quaternion(r.3).map(rerun::datatypes::Quaternion::from_xyzw))
        .collect::<Option<Vec<_>>>()
        .ok_or_else(|| invalid(Quantity::Rotation))?;
    rerun::archetypes::Transform3D::update_fields()
        .with_many_translation(rows.iter().map(|r| r.2.map(|v| v as f32)))
        .with_many_quaternion(rotations)
        .with_many_parent_frame(rows.iter().map(|r| r.0.as_str()))
        .with_many_child_frame(rows.iter().map(|r| r.1.as_str()))
        .columns_of_unit_batches()
        .map(|c| c.collect())
        .map_err(|e| RecordingError::Log {
            entity_path: entity_path.to_owned(),
            source: e.into(),
        })
}

/// A mesh with one colour, as Rerun's archetype.
fn mesh_archetype(mesh: &TriMesh, color_rgba: [f32; 4]) -> rerun::archetypes::Mesh3D {
    let mut archetype =
        rerun::archetypes::Mesh3D::new(mesh.positions.iter().copied()).with_albedo_factor(rgba32(color_rgba));
    if !mesh.indices.is_empty() {
        archetype = archetype.with_triangle_indices(
            mesh.indices
                .chunks_exact(3)
                .map(|t| rerun::datatypes::UVec3D::new(t[0], t[1], t[2])),
        );
    }
    if !mesh.normals.is_empty() {
        archetype = archetype.with_vertex_normals(mesh.normals.iter().copied());
    }
    archetype
}

fn check_mesh(mesh: &TriMesh) -> Result<(), MeshDefect> {
    let vertex_count = mesh.positions.len();
    if !mesh.indices.len().is_multiple_of(3) {
        return Err(MeshDefect::PartialTriangle {
            index_count: mesh.indices.len(),
        });
    }
    if let Some(&index) = mesh
        .indices
        .iter()
        .find(|&&i| usize::try_from(i).map_or(true, |i| i >= vertex_count))
    {
        return Err(MeshDefect::IndexOutOfRange { index, vertex_count });
    }
    if !mesh.normals.is_empty() && mesh.normals.len() != vertex_count {
        return Err(MeshDefect::NormalCountMismatch {
            normal_count: mesh.normals.len(),
            vertex_count,
        });
    }
    let finite = |v: &[f32; 3]| v.iter().all(|c| c.is_finite());
    let bad_position = mesh.positions.iter().position(|p| !finite(p));
    let bad_normal = mesh.normals.iter().position(|n| !finite(n));
    match (bad_position, bad_normal) {
        (Some(a), Some(b)) => Err(MeshDefect::NonFiniteVertex { vertex: a.min(b) }),
        (Some(vertex), None) | (None, Some(vertex)) => Err(MeshDefect::NonFiniteVertex { vertex }),
        (None, None) => Ok(()),
    }
}

/// Normalises an `xyzw` quaternion; `None` if it is zero or not finite.
fn unit_quaternion(xyzw: [f64; 4]) -> Option<[f32; 4]> {
    let norm = xyzw.iter().map(|c| c * c).sum::<f64>().sqrt();
    (norm.is_finite() && norm > 1e-12).then(|| xyzw.map(|c| (c / norm) as f32))
}

/// sRGB(A) in `0..=1` to Rerun's 8-bit colour; out-of-range channels are clamped, NaN becomes 0.
fn rgba32(color_rgba: [f32; 4]) -> rerun::datatypes::Rgba32 {
    let [r, g, b, a] = color_rgba.map(|c| (c.clamp(0.0, 1.0) * 255.0).round() as u8);
    rerun::datatypes::Rgba32::from_unmultiplied_rgba(r, g, b, a)
}

#[cfg(test)]
mod tests;
