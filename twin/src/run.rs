//! A scene running: the stages in order, one coarse update at a time.
//!
//! ```text
//! scene ──▶ program ──▶ planner ──▶ plant ──▶ outputs
//!             scan      update     physics    trace, summary,
//!                                  feedback   frames, recording
//! ```
//!
//! Each update the [`Program`] fires its due steps into the planner, the
//! planner computes the new setpoints, the [`Plant`] sweeps the moves that
//! started, runs the physics steps and feeds the joints back as actual
//! positions. The outputs (module [`crate::output`]) read the result
//! through [`Twin`]'s accessors. The timing is the plant's
//! ([`crate::plant`], "Timing"); the steps' rules the program's
//! ([`crate::program`]).

use crate::plant::{Plant, PlantError};
use crate::program::Program;
use crate::scene::Scene;
use crate::source::Diagnostic;
use planner::task::{MotionTask, TaskError};
use std::path::PathBuf;
use thiserror::Error;

/// Why a scene cannot run. Each variant names the scene file and the place.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum RunError {
    /// The planner refuses the coarse update period.
    #[error("{scene}: {source}")]
    Planner {
        /// Scene file.
        scene: PathBuf,
        /// What failed.
        #[source]
        source: TaskError,
    },
    /// The plant cannot be built (URDF, joints, physics, collision, …).
    #[error(transparent)]
    Plant(#[from] PlantError),
    /// The program does not compile: a routine, a step's call or trigger,
    /// a traced tag.
    #[error(transparent)]
    Program(#[from] Box<Diagnostic>),
}

impl RunError {
    /// The error as a diagnostic (see [`Diagnostic::render`]): the
    /// program's own, or the plant's with the scene line it points at.
    #[must_use]
    pub fn diagnostic(&self) -> Diagnostic {
        match self {
            RunError::Program(d) => (**d).clone(),
            RunError::Plant(e) => e.diagnostic(),
            RunError::Planner { .. } => Diagnostic::error(self.to_string()),
        }
    }
}

/// A loaded, bound scene, ready to step.
pub struct Twin {
    scene: Scene,
    task: MotionTask,
    program: Program,
    plant: Plant,
    io: CellIo,
    /// `twin bench`: wall time by stage.
    times: Option<StageTimes>,
    /// The scheduled output modules (tags with `scheduled_output`).
    scheduled: Vec<ScheduledRun>,
}

/// A scheduled output module: the switches its output cam made, each with
/// when its device acted and where the axis was then.
#[derive(Debug)]
struct ScheduledRun {
    tag: String,
    axis: planner::task::AxisHandle,
    target: u32,
    response_s: f64,
    /// The axis' actual position at the last coarse updates: (s, position).
    history: std::collections::VecDeque<(f64, f64)>,
    /// Switches whose device has not acted yet.
    pending: Vec<planner::output_cam::Switch>,
    done: Vec<ScheduledSwitch>,
}

/// One switch of a scheduled output (the summary lists them).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct ScheduledSwitch {
    /// The output bit.
    pub bit: u32,
    /// On or off.
    pub on: bool,
    /// When the module switched it, s (interpolated inside the update).
    pub switch_s: f64,
    /// When the device acted (`switch_s` + `response_ms`), s.
    pub device_s: f64,
    /// The axis' actual position then (interpolated between updates).
    pub axis_position: f64,
}

/// The most switches a scheduled output keeps for the summary.
pub const MAX_SCHEDULED_SWITCHES: usize = 10_000;

impl ScheduledRun {
    /// After an update: the cam's new switches wait for their device; the
    /// ones whose device has acted by `now_s` get the axis position then.
    fn collect(&mut self, task: &MotionTask, now_s: f64) {
        let position = task.axis_state(self.axis).actual_position;
        self.history.push_back((now_s, position));
        while self.history.len() > 4096 {
            self.history.pop_front();
        }
        self.pending
            .extend(task.output_cam_switches(self.axis, self.target).iter().copied());
        let history = &self.history;
        let at = |t: f64| -> Option<f64> {
            let k = history.iter().position(|(ht, _)| *ht >= t)?;
            let (t1, p1) = history[k];
            if k == 0 || t1 == t {
                return Some(p1);
            }
            let (t0, p0) = history[k - 1];
            Some(p0 + (p1 - p0) * (t - t0) / (t1 - t0))
        };
        let response = self.response_s;
        let mut left = Vec::new();
        for s in self.pending.drain(..) {
            let device_s = s.time_s + response;
            match at(device_s) {
                Some(axis_position) if self.done.len() < MAX_SCHEDULED_SWITCHES => self.done.push(ScheduledSwitch {
                    bit: s.bit,
                    on: s.on,
                    switch_s: s.time_s,
                    device_s,
                    axis_position,
                }),
                Some(_) => {}
                None => left.push(s),
            }
        }
        self.pending = left;
    }
}

/// A run's wall time by stage (`twin bench`; [`Twin::record_for_bench`]).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct StageTimes {
    /// The program's scan (steps or tasks), s.
    pub program_s: f64,
    /// The planner's update, s.
    pub planner_s: f64,
    /// The pre-flight sweeps of moves that started, s.
    pub sweep_s: f64,
    /// The plant's update: physics and live collision checks
    /// ([`crate::plant::PlantTimes`] splits it), s.
    pub plant_s: f64,
}

impl std::fmt::Debug for Twin {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Twin")
            .field("scene", &self.scene.path)
            .field("time_s", &self.time_s())
            .finish_non_exhaustive()
    }
}

impl Twin {
    /// Builds the plant (URDF, physics, axes in the planner), binds the
    /// program to the planner, and binds the tool trails of the coordinate
    /// systems the program uses.
    ///
    /// # Errors
    /// [`RunError`] naming the scene file and the place that is wrong.
    pub fn new(scene: Scene) -> Result<Twin, RunError> {
        let mut task = MotionTask::new(scene.coarse_update_s()).map_err(|source| RunError::Planner {
            scene: scene.path.clone(),
            source,
        })?;
        let mut plant = Plant::new(&scene, &mut task)?;
        let mut program = Program::bind(&scene, &mut task)?;
        plant.bind_tool_trails(&scene, &task)?;
        let io = CellIo::bind(&scene, &mut task, &mut program)?;
        let scheduled = scene
            .tags
            .iter()
            .filter_map(|t| {
                let s = t.scheduled_output?;
                Some(ScheduledRun {
                    tag: t.name.clone(),
                    axis: task.axis_handles().nth(s.axis)?,
                    target: s.execution_target,
                    response_s: s.response_s,
                    history: Default::default(),
                    pending: Vec::new(),
                    done: Vec::new(),
                })
            })
            .collect();
        Ok(Twin {
            scene,
            task,
            program,
            plant,
            io,
            times: None,
            scheduled,
        })
    }

    /// One coarse update: the program's scan, the planner update, the
    /// pre-flight sweep of moves that started, the physics steps and the
    /// feedback of actual positions.
    pub fn step(&mut self) {
        // With `twin bench`'s timing on, each stage's wall time.
        let mut timer = self.times.as_mut().map(|times| (times, std::time::Instant::now()));
        let mut lap = |stage: fn(&mut StageTimes) -> &mut f64| {
            if let Some((times, at)) = timer.as_mut() {
                let now = std::time::Instant::now();
                *stage(times) += (now - *at).as_secs_f64();
                *at = now;
            }
        };
        self.io.inputs(self.task.time_s(), &mut self.plant, &mut self.program);
        self.program.scan(&mut self.task);
        for (axis, gains) in self.program.take_drive_changes() {
            self.plant.set_servo_gains(axis, gains);
        }
        self.io.outputs(self.task.time_s(), &self.program, &mut self.plant);
        lap(|t| &mut t.program_s);
        self.task.update();
        self.program.sync_output_cams(&mut self.task);
        lap(|t| &mut t.planner_s);
        self.plant.after_planner_update(&mut self.task);
        lap(|t| &mut t.sweep_s);
        self.plant.advance(&mut self.task);
        lap(|t| &mut t.plant_s);
        let now_s = self.task.time_s();
        for s in &mut self.scheduled {
            s.collect(&self.task, now_s);
        }
    }

    /// Each scheduled output module's tag and its switches so far.
    pub fn scheduled_switches(&self) -> impl Iterator<Item = (&str, &[ScheduledSwitch])> {
        self.scheduled.iter().map(|s| (s.tag.as_str(), s.done.as_slice()))
    }

    /// `twin bench`: from now on, time every stage of [`Twin::step`]
    /// ([`Twin::stage_times`]) and record the physics for a bare replay
    /// ([`Plant::physics_replay`]).
    pub fn record_for_bench(&mut self) {
        self.times = Some(StageTimes::default());
        self.plant.record_for_bench();
    }

    /// The wall time by stage since [`Twin::record_for_bench`].
    pub fn stage_times(&self) -> Option<StageTimes> {
        self.times
    }

    /// The scene.
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// The planner.
    pub fn task(&self) -> &MotionTask {
        &self.task
    }

    /// The bound program.
    pub fn program(&self) -> &Program {
        &self.program
    }

    /// The bound program, to set a tag as an operator would.
    pub fn program_mut(&mut self) -> &mut Program {
        &mut self.program
    }

    /// The plant.
    pub fn plant(&self) -> &Plant {
        &self.plant
    }

    /// The plant and the planner, for sweeping a path by hand
    /// ([`Plant::preflight_path`]).
    pub fn plant_mut(&mut self) -> (&mut Plant, &MotionTask) {
        (&mut self.plant, &self.task)
    }

    /// Compiles an expression of the scene in controller scope, naming
    /// `columns` too ([`Program::compile_expression`]).
    ///
    /// # Errors
    /// A diagnostic pointing into the expression.
    pub fn compile_expression(
        &mut self,
        expr: &crate::st::ast::Expr,
        columns: &[crate::program::ir::Column],
    ) -> Result<crate::program::ir::CExpr, Box<Diagnostic>> {
        self.program
            .compile_expression(&self.scene, &mut self.task, expr, columns)
    }

    /// The value of an expression [`Twin::compile_expression`] compiled,
    /// now, with the trace columns' values `columns`.
    pub fn evaluate(&mut self, e: &crate::program::ir::CExpr, columns: &[f64]) -> crate::program::types::Value {
        self.program.evaluate(&mut self.task, e, columns)
    }

    /// The routines' assignments to input tags: (`routine:line:col`, tag).
    pub fn input_writes(&mut self) -> Vec<(String, String)> {
        self.program.input_writes(&self.scene, &mut self.task)
    }

    /// Simulated time of the last update, seconds.
    pub fn time_s(&self) -> f64 {
        self.task.time_s()
    }

    /// Number of coarse updates in the scene's duration.
    pub fn total_updates(&self) -> u64 {
        (self.scene.duration_s / self.scene.coarse_update_s()).round() as u64
    }

    /// Whether something ended the run before its duration: a collision
    /// with `reaction = "abort"`, a major controller fault, or a physics
    /// fault.
    pub fn stopped(&self) -> bool {
        self.plant.collision_abort()
            || self.program.controller().major_fault().is_some()
            || self.plant.physics_fault().is_some()
    }
}

/// The cell's devices bound to tag memory: what `run.rs` copies into the
/// program before each update's scans (inputs) and out of it after them
/// (outputs), so that the plant never sees the program.
#[derive(Debug, Default)]
struct CellIo {
    sensors: Vec<SensorIo>,
    conveyors: Vec<ConveyorIo>,
    /// Per source, its `on` output.
    sources: Vec<Option<IoPoint>>,
    cylinders: Vec<ActuatorIo>,
    grippers: Vec<ActuatorIo>,
}

/// A cylinder's or a gripper's points: two outputs (extend and retract,
/// grip and release) and up to two inputs (extended and retracted,
/// holding).
#[derive(Debug, Default)]
struct ActuatorIo {
    first: Option<IoPoint>,
    second: Option<IoPoint>,
    status: [Option<IoPoint>; 2],
}

#[derive(Debug)]
struct SensorIo {
    tag: IoPoint,
    value: Option<(IoPoint, IoKind)>,
    count: Option<IoPoint>,
    vision: Option<VisionIo>,
}

/// A camera's points: its trigger (output) and its results (inputs).
#[derive(Debug)]
struct VisionIo {
    trigger: IoPoint,
    position: Option<IoPoint>,
    angle: Option<IoPoint>,
    type_id: Option<IoPoint>,
}

#[derive(Debug, Default)]
struct ConveyorIo {
    run: Option<IoPoint>,
    reverse: Option<IoPoint>,
    speed: Option<IoPoint>,
    running: Option<IoPoint>,
    encoder: Option<(IoPoint, f64)>,
}

use crate::program::io::{IoEntry, IoPoint};
use crate::program::types::Value;
use crate::scene::{ConveyorDrive, IoDirection, IoKind, IoTag, SensorKind, SourceTrigger};

impl CellIo {
    /// Binds every device's tags, inputs first in scene order.
    fn bind(scene: &Scene, task: &mut MotionTask, program: &mut Program) -> Result<CellIo, RunError> {
        let mut bind = |tag: &IoTag, kind: IoKind, direction: IoDirection, device: &str, role: &str| {
            let entry = IoEntry {
                tag: tag.text.clone(),
                direction,
                device: device.to_owned(),
                role: role.to_owned(),
                field: tag.field.clone(),
            };
            program.bind_io(scene, task, tag, kind, entry)
        };
        let mut io = CellIo::default();
        for s in &scene.cell.sensors {
            let role = s.kind.word();
            let tag = bind(&s.tag, IoKind::Bool, IoDirection::Input, &s.name, role)?;
            let value_kind = match s.kind {
                SensorKind::Diffuse { .. } | SensorKind::Clearance { .. } => IoKind::Real,
                _ => IoKind::Dint,
            };
            let value = match &s.value_tag {
                Some(t) => Some((bind(t, value_kind, IoDirection::Input, &s.name, "value")?, value_kind)),
                None => None,
            };
            let count = match &s.count_tag {
                Some(t) => Some(bind(t, IoKind::Dint, IoDirection::Input, &s.name, "count")?),
                None => None,
            };
            let vision = match &s.kind {
                SensorKind::Vision(spec) => Some(VisionIo {
                    trigger: bind(&spec.trigger, IoKind::Bool, IoDirection::Output, &s.name, "trigger")?,
                    position: match &spec.position_tag {
                        Some(t) => Some(bind(t, IoKind::Real3, IoDirection::Input, &s.name, "position")?),
                        None => None,
                    },
                    angle: match &spec.angle_tag {
                        Some(t) => Some(bind(t, IoKind::Real, IoDirection::Input, &s.name, "angle")?),
                        None => None,
                    },
                    type_id: match &spec.type_tag {
                        Some(t) => Some(bind(t, IoKind::Dint, IoDirection::Input, &s.name, "type")?),
                        None => None,
                    },
                }),
                _ => None,
            };
            io.sensors.push(SensorIo {
                tag,
                value,
                count,
                vision,
            });
        }
        for c in &scene.cell.conveyors {
            let mut cio = ConveyorIo::default();
            if let ConveyorDrive::Vfd(v) = &c.drive {
                cio.run = Some(bind(&v.run, IoKind::Bool, IoDirection::Output, &c.name, "run")?);
                if let Some(t) = &v.reverse {
                    cio.reverse = Some(bind(t, IoKind::Bool, IoDirection::Output, &c.name, "reverse")?);
                }
                if let Some(t) = &v.speed {
                    cio.speed = Some(bind(t, IoKind::Real, IoDirection::Output, &c.name, "speed %")?);
                }
                if let Some(t) = &v.running_tag {
                    cio.running = Some(bind(t, IoKind::Bool, IoDirection::Input, &c.name, "running")?);
                }
                if let Some(t) = &v.encoder_tag {
                    cio.encoder = Some((
                        bind(t, IoKind::Dint, IoDirection::Input, &c.name, "encoder")?,
                        v.counts_per_m,
                    ));
                }
            }
            io.conveyors.push(cio);
        }
        for s in &scene.cell.sources {
            io.sources.push(match &s.trigger {
                SourceTrigger::On(t) => Some(bind(t, IoKind::Bool, IoDirection::Output, &s.name, "spawn")?),
                _ => None,
            });
        }
        let mut optional = |t: &Option<IoTag>, direction: IoDirection, device: &str, role: &str| match t {
            Some(t) => bind(t, IoKind::Bool, direction, device, role).map(Some),
            None => Ok(None),
        };
        for c in &scene.cell.cylinders {
            io.cylinders.push(ActuatorIo {
                first: optional(&Some(c.extend.clone()), IoDirection::Output, &c.name, "extend")?,
                second: optional(&c.retract, IoDirection::Output, &c.name, "retract")?,
                status: [
                    optional(&c.extended_tag, IoDirection::Input, &c.name, "extended")?,
                    optional(&c.retracted_tag, IoDirection::Input, &c.name, "retracted")?,
                ],
            });
        }
        for g in &scene.cell.grippers {
            io.grippers.push(ActuatorIo {
                first: optional(&Some(g.grip.clone()), IoDirection::Output, &g.name, "grip")?,
                second: optional(&g.release, IoDirection::Output, &g.name, "release")?,
                status: [optional(&g.holding_tag, IoDirection::Input, &g.name, "holding")?, None],
            });
        }
        Ok(io)
    }

    /// Before the scans at `t`: the inputs into tag memory.
    fn inputs(&self, t: f64, plant: &mut Plant, program: &mut Program) {
        for (k, s) in self.sensors.iter().enumerate() {
            let sensor = &mut plant.sensors_mut()[k];
            if let (Some(v), Some(r)) = (&s.vision, sensor.vision_result(t)) {
                program.write_input(s.tag, Value::Bool(r.found));
                if let Some(p) = v.position {
                    program.write_inputs3(p, r.position);
                }
                if let Some(p) = v.angle {
                    program.write_input(p, Value::Real(r.angle_deg));
                }
                if let Some(p) = v.type_id {
                    program.write_input(p, Value::Int(i64::from(r.type_id)));
                }
                continue;
            }
            let on = sensor.tag_at(t);
            let value = sensor.value_taken();
            program.write_input(s.tag, Value::Bool(on));
            match s.value {
                Some((p, IoKind::Real)) => program.write_input(p, Value::Real(value)),
                Some((p, _)) => program.write_input(p, Value::Int(value as i64)),
                None => {}
            }
            if let Some(p) = s.count {
                program.write_input(p, Value::Int(value as i64));
            }
        }
        let Some(material) = plant.material() else { return };
        for (c, io) in material.cylinders().zip(&self.cylinders) {
            for (point, on) in io.status.iter().zip([c.extended(), c.retracted()]) {
                if let Some(p) = point {
                    program.write_input(*p, Value::Bool(on));
                }
            }
        }
        for (g, io) in material.grippers().iter().zip(&self.grippers) {
            if let Some(p) = io.status[0] {
                program.write_input(p, Value::Bool(g.part() != 0));
            }
        }
        for (c, io) in material.conveyors().iter().zip(&self.conveyors) {
            if let Some(p) = io.running {
                program.write_input(p, Value::Bool(c.speed_mps().abs() > 1e-9));
            }
            if let Some((p, counts_per_m)) = io.encoder {
                // A DINT counter wraps; the travel in counts is exact to
                // 2^53.
                let counts = (c.travel_m() * counts_per_m).floor() as i64;
                program.write_input(p, Value::Int(counts));
            }
        }
    }

    /// After the scans at `t`: the outputs to the devices.
    fn outputs(&self, t: f64, program: &Program, plant: &mut Plant) {
        for (k, s) in self.sensors.iter().enumerate() {
            if let Some(v) = &s.vision {
                plant.vision_trigger(k, program.read_output(v.trigger).truthy(), t);
            }
        }
        let Some(material) = plant.material_mut() else { return };
        let bool_of = |p: Option<IoPoint>| p.is_some_and(|p| program.read_output(p).truthy());
        for (k, io) in self.conveyors.iter().enumerate() {
            if io.run.is_none() {
                continue;
            }
            let speed = io.speed.map_or(100.0, |p| program.read_output(p).as_f64());
            material.conveyors_mut()[k].set_vfd(bool_of(io.run), bool_of(io.reverse), speed);
        }
        for (k, on) in self.sources.iter().enumerate() {
            if let Some(p) = on {
                material.set_source_trigger(k, program.read_output(*p).truthy());
            }
        }
        for (k, io) in self.cylinders.iter().enumerate() {
            material
                .cylinder_mut(k)
                .set_valve(bool_of(io.first), bool_of(io.second));
        }
        for (k, io) in self.grippers.iter().enumerate() {
            material.grippers_mut()[k].set_outputs(bool_of(io.first), bool_of(io.second));
        }
    }
}
