//! Validation of the scene's top level: settings, robot, axes, cameras,
//! obstacles and snapshots (tags and the program have files of their own).

use std::collections::{BTreeMap, HashMap};
use std::ops::Range;
use std::path::Path;

use planner::axis::AxisConfig;
use planner::homing::{HomeDirection, HomeMode, HomeSequence, Homing};
use planner::servo::{AxisType, FaultAction};
use toml::Spanned;

use super::context::{Ctx, NameKind, Names, ShapeFields};
use super::error::{Problem, SceneError};
use super::model::{
    Axis, Camera, DEFAULT_PHYSICS_SUBSTEPS, MAX_AXIS_ACCELERATION, MAX_AXIS_JERK, MAX_AXIS_SPEED, MAX_DRIVE_TORQUE,
    MAX_DURATION_S, MAX_FEEDFORWARD_PCT, MAX_IMAGE_PX, MAX_LENGTH_M, MAX_LOOP_BANDWIDTH_STEP, MAX_MESH_SCALE,
    MAX_PHYSICS_SUBSTEPS, MIN_PHYSICS_STEP_MS, MotorGains, Obstacle, Robot, Scene, ServoGains, Shape, Snapshots,
};
use super::raw::{
    AxisConfiguration, RawAxis, RawCamera, RawDrive, RawObstacle, RawRobot, RawScene, RawSnapshots, ShapeKind,
};

impl Ctx<'_> {
    pub(super) fn validate(&self, raw: RawScene, path: &Path) -> Result<Scene, SceneError> {
        let base = path.parent().unwrap_or_else(|| Path::new(""));
        let name = match &raw.name {
            Some(n) => self.file_name_part(n, "name")?,
            None => path
                .file_stem()
                .map_or_else(String::new, |s| s.to_string_lossy().into_owned()),
        };
        let duration_s = self.positive(&raw.duration_s, "duration_s")?;
        if duration_s > MAX_DURATION_S {
            let problem = Problem::OutOfRange {
                value: duration_s,
                min: 0.0,
                max: MAX_DURATION_S,
                exclusive: false,
            };
            return Err(self.invalid(&raw.duration_s, "duration_s", problem));
        }
        // The coarse update lives on the MOTION_GROUP tag; the scene's
        // `coarse_update_ms` is its shorthand. One of them, or both the same.
        let group = raw.tags.iter().enumerate().find_map(|(i, t)| {
            let period = t.coarse_update_ms.as_ref()?;
            // Another type's is refused with the tags.
            t.ty.get_ref()
                .trim()
                .eq_ignore_ascii_case("MOTION_GROUP")
                .then(|| (period, format!("tags[{i}].coarse_update_ms")))
        });
        let (period, field) = match (&raw.coarse_update_ms, &group) {
            (Some(scene), Some((tag, field))) if scene.get_ref() != tag.get_ref() => {
                let why = format!(
                    "the MOTION_GROUP tag's coarse_update_ms is {} (the scene's coarse_update_ms is its shorthand: give one)",
                    tag.get_ref()
                );
                return Err(self.invalid(scene, "coarse_update_ms", Problem::Rule { why }));
            }
            (Some(scene), _) => (scene, "coarse_update_ms".to_owned()),
            (None, Some((tag, field))) => (*tag, field.clone()),
            (None, None) => {
                let why =
                    "required: the coarse update period, ms (or a MOTION_GROUP tag's coarse_update_ms)".to_owned();
                return Err(self.invalid(&raw.duration_s, "coarse_update_ms", Problem::Rule { why }));
            }
        };
        let coarse_update_ms = self.finite(period, &field)?;
        if !(1.0..=32.0).contains(&coarse_update_ms) {
            let problem = Problem::OutOfRange {
                value: coarse_update_ms,
                min: 1.0,
                max: 32.0,
                exclusive: false,
            };
            return Err(self.invalid(period, field, problem));
        }
        let physics_step_ms = self.positive(&raw.physics_step_ms, "physics_step_ms")?;
        if physics_step_ms < MIN_PHYSICS_STEP_MS {
            let problem = Problem::OutOfRange {
                value: physics_step_ms,
                min: MIN_PHYSICS_STEP_MS,
                max: coarse_update_ms,
                exclusive: false,
            };
            return Err(self.invalid(&raw.physics_step_ms, "physics_step_ms", problem));
        }
        let ratio = coarse_update_ms / physics_step_ms;
        if (ratio - ratio.round()).abs() > 1e-9 || ratio.round() < 1.0 {
            let problem = Problem::StepNotDivisor {
                physics_step_ms,
                coarse_update_ms,
            };
            return Err(self.invalid(&raw.physics_step_ms, "physics_step_ms", problem));
        }
        let physics_substeps = match &raw.physics_substeps {
            Some(n) => {
                let value = *n.get_ref();
                if !(1..=MAX_PHYSICS_SUBSTEPS as i64).contains(&value) {
                    let problem = Problem::OutOfRange {
                        value: value as f64,
                        min: 1.0,
                        max: MAX_PHYSICS_SUBSTEPS as f64,
                        exclusive: false,
                    };
                    return Err(self.invalid(n, "physics_substeps", problem));
                }
                value as usize
            }
            None => DEFAULT_PHYSICS_SUBSTEPS,
        };

        let robot = self.robot(&raw.robot, base)?;
        let mut names: Names = HashMap::new();
        let axes = self.axes(&raw.axes, &robot, &mut names)?;
        self.loops_stable(&raw, &axes, physics_step_ms / 1000.0 / physics_substeps as f64)?;
        let cameras = self.cameras(&raw.cameras, coarse_update_ms)?;
        let obstacles = self.obstacles(&raw.obstacles, base)?;
        let data_types = self.data_types(&raw.data_types)?;
        let add_on_instructions = self.add_on_instructions(&raw.add_on_instructions, base)?;
        // The instructions' data types follow the scene's.
        let data_types = if add_on_instructions.is_empty() {
            data_types
        } else {
            self.data_types.borrow().clone()
        };
        let tags = self.tags(&raw.tags, &axes, &mut names, "tags")?;
        let aliases = self.aliases(&raw.aliases, &mut names, "aliases")?;
        let program = self.program(&raw.program, duration_s)?;
        let tasks = self.tasks(&raw.tasks, &axes, (&names, &tags), base)?;
        let controller = self.controller_settings(raw.controller.as_ref(), (&axes, &names, base), &tasks)?;
        let snapshots = match &raw.snapshots {
            Some(s) => Some(self.snapshots(s, &cameras)?),
            None => None,
        };
        let collision = match &raw.collision {
            Some(c) => Some(self.collision(c, base)?),
            None => None,
        };
        let cell = self.cell(
            &raw,
            base,
            &super::cell::CellTiming {
                coarse_update_ms,
                physics_step_ms,
                duration_s,
                axes: &axes,
                obstacles: &obstacles,
            },
        )?;
        let trace_tags = self.trace_tags(raw.trace.as_ref().map_or(&[], |t| t.tags.as_slice()))?;
        let trace_rungs = self.trace_rungs(raw.trace.as_ref().map_or(&[], |t| t.rungs.as_slice()), &tasks)?;
        let expectations = self.expectations(&raw.expect, "expect", duration_s, None, &[])?;
        let test = self.test_settings(raw.test.as_ref())?;
        let variants = self.variants(
            &raw.variants,
            &super::expect::VariantScope {
                tags: &tags,
                tasks: &tasks,
                axes: &axes,
                duration_s,
                expectations: &expectations,
            },
        )?;
        Ok(Scene {
            physics_substeps,
            plant: match raw.plant {
                Some(super::raw::PlantWord::Kinematic) => super::model::PlantMode::Kinematic,
                Some(super::raw::PlantWord::Physics) | None => super::model::PlantMode::Physics,
            },
            collision,
            name,
            path: path.to_owned(),
            duration_s,
            coarse_update_ms,
            physics_step_ms,
            robot,
            axes,
            cameras,
            obstacles,
            data_types,
            tags,
            program,
            tasks,
            controller,
            trace_tags,
            trace_rungs,
            add_on_instructions,
            files: self.files.borrow().clone(),
            l5x: self.l5x.clone(),
            aliases,
            snapshots,
            expectations,
            test,
            variants,
            variant: None,
            cell,
        })
    }

    pub(super) fn robot(&self, raw: &RawRobot, base: &Path) -> Result<Robot, SceneError> {
        let urdf = self.existing_file(&raw.urdf, "robot.urdf", base)?;
        let mut initial_joints = BTreeMap::new();
        let mut initial_joint_locations = BTreeMap::new();
        for (joint, value) in &raw.initial_joints {
            let v = self.finite(value, &format!("robot.initial_joints.{joint}"))?;
            initial_joints.insert(joint.clone(), v);
            initial_joint_locations.insert(joint.clone(), self.loc(value));
        }
        Ok(Robot {
            urdf,
            urdf_location: self.loc(&raw.urdf),
            initial_joints,
            initial_joint_locations,
        })
    }

    /// An axis' drive and state fields (`axis_configuration`,
    /// `servo_on_at_start`, `position_error_*`, `holding_brake`,
    /// `brake_release_delay_ms`); a virtual axis takes none of the drive
    /// fields.
    fn drive_options(
        &self,
        a: &RawAxis,
        has_joint: bool,
        f: &dyn Fn(&str) -> String,
    ) -> Result<DriveOptions, SceneError> {
        if !has_joint {
            let given: [(Option<Range<usize>>, &'static str); 6] = [
                (a.drive.as_ref().map(Spanned::span), "drive"),
                (a.axis_configuration.as_ref().map(Spanned::span), "axis_configuration"),
                (a.servo_on_at_start.as_ref().map(Spanned::span), "servo_on_at_start"),
                (
                    a.position_error_tolerance.as_ref().map(Spanned::span),
                    "position_error_tolerance",
                ),
                (a.holding_brake.as_ref().map(Spanned::span), "holding_brake"),
                (
                    a.brake_release_delay_ms.as_ref().map(Spanned::span),
                    "brake_release_delay_ms",
                ),
            ];
            if let Some((Some(span), field)) = given.into_iter().find(|(s, _)| s.is_some()) {
                return Err(self.invalid_at(span, f(field), Problem::NoDrive { field }));
            }
        }
        let axis_type = match a.axis_configuration.as_ref().map(|c| *c.get_ref()) {
            _ if !has_joint => AxisType::Virtual,
            Some(AxisConfiguration::FeedbackOnly) => AxisType::FeedbackOnly,
            _ => AxisType::Servo,
        };
        let position_error_tolerance = match &a.position_error_tolerance {
            Some(t) => Some(self.positive(t, &f("position_error_tolerance"))?),
            None => None,
        };
        let servo_enable_delay_s = match &a.brake_release_delay_ms {
            Some(d) => self.non_negative(d, &f("brake_release_delay_ms"))? / 1000.0,
            None => 0.0,
        };
        if let (Some(m), Some(_)) = (&a.motor, &a.drive) {
            return Err(self.invalid(m, f("motor"), Problem::SpringAndServo));
        }
        let servo = match (&a.drive, &a.motor) {
            (_, Some(_)) => None,
            _ if !has_joint => None,
            (Some(d), None) => Some(self.servo_gains(d.get_ref(), f)?),
            (None, None) => Some(ServoGains::default()),
        };
        Ok(DriveOptions {
            servo,
            axis_type,
            start_servo_on: a.servo_on_at_start.as_ref().is_none_or(|s| *s.get_ref()),
            servo_enable_delay_s,
            position_error_tolerance,
            position_error_action: a
                .position_error_action
                .as_ref()
                .map_or(FaultAction::StopDrive, |x| x.get_ref().planner()),
            holding_brake: a.holding_brake.as_ref().is_some_and(|b| *b.get_ref()),
        })
    }

    /// An axis' homing attributes (`home_*`, axis units): active by
    /// default, passive by default on a feedback-only axis.
    fn homing(&self, a: &RawAxis, axis_type: AxisType, f: &dyn Fn(&str) -> String) -> Result<Homing, SceneError> {
        use super::raw::{HomeDirectionWord as D, HomeModeWord, HomeSequenceWord};
        let mode = match &a.home_mode {
            Some(m) if *m.get_ref() == HomeModeWord::Active && axis_type == AxisType::FeedbackOnly => {
                return Err(self.invalid(m, f("home_mode"), Problem::ActiveHomingWithoutDrive));
            }
            Some(m) if *m.get_ref() == HomeModeWord::Passive => HomeMode::Passive,
            Some(_) => HomeMode::Active,
            None if axis_type == AxisType::FeedbackOnly => HomeMode::Passive,
            None => HomeMode::Active,
        };
        if let Some(s) = &a.home_sequence
            && *s.get_ref() != HomeSequenceWord::Immediate
        {
            let sequence = s.get_ref().word();
            return Err(self.invalid(s, f("home_sequence"), Problem::HomeSequenceNotSimulated { sequence }));
        }
        let finite = |v: &Option<Spanned<f64>>, name: &str| match v {
            Some(v) => {
                let x = self.finite(v, &f(name))?;
                self.at_most(v, &f(name), &[x], planner::axis::MAX_POSITION)?;
                Ok(x)
            }
            None => Ok(0.0),
        };
        let non_negative = |v: &Option<Spanned<f64>>, name: &str| match v {
            Some(v) => self.non_negative(v, &f(name)),
            None => Ok(0.0),
        };
        Ok(Homing {
            mode,
            sequence: HomeSequence::Immediate,
            position: finite(&a.home_position, "home_position")?,
            offset: finite(&a.home_offset, "home_offset")?,
            direction: match a.home_direction.as_ref().map(|d| *d.get_ref()) {
                None | Some(D::UnidirectionalForward) => HomeDirection::UnidirectionalForward,
                Some(D::BidirectionalForward) => HomeDirection::BidirectionalForward,
                Some(D::UnidirectionalReverse) => HomeDirection::UnidirectionalReverse,
                Some(D::BidirectionalReverse) => HomeDirection::BidirectionalReverse,
            },
            speed: non_negative(&a.home_speed, "home_speed")?,
            return_speed: non_negative(&a.home_return_speed, "home_return_speed")?,
        })
    }

    /// Each servo drive's loops are closed explicitly at the physics
    /// substep, which is stable only while 2π × bandwidth × substep stays
    /// at most [`MAX_LOOP_BANDWIDTH_STEP`]: a bandwidth past it is refused
    /// at its field, a default bandwidth too fast for the scene's step at
    /// `physics_step_ms`.
    fn loops_stable(&self, raw: &RawScene, axes: &[Axis], substep_s: f64) -> Result<(), SceneError> {
        let max_hz = MAX_LOOP_BANDWIDTH_STEP / (std::f64::consts::TAU * substep_s);
        for (i, (axis, a)) in axes.iter().zip(&raw.axes).enumerate() {
            let Some(g) = &axis.servo else { continue };
            let d = a.drive.as_ref().map(|d| d.get_ref());
            let loops = [
                (
                    "position_loop_bandwidth_hz",
                    g.position_loop_bandwidth_hz,
                    d.and_then(|d| d.position_loop_bandwidth_hz.as_ref()),
                ),
                (
                    "position_integrator_bandwidth_hz",
                    g.position_integrator_bandwidth_hz,
                    d.and_then(|d| d.position_integrator_bandwidth_hz.as_ref()),
                ),
                (
                    "velocity_loop_bandwidth_hz",
                    g.velocity_loop_bandwidth_hz,
                    d.and_then(|d| d.velocity_loop_bandwidth_hz.as_ref()),
                ),
                (
                    "velocity_integrator_bandwidth_hz",
                    g.velocity_integrator_bandwidth_hz,
                    d.and_then(|d| d.velocity_integrator_bandwidth_hz.as_ref()),
                ),
            ];
            for (name, hz, given) in loops {
                if hz <= max_hz {
                    continue;
                }
                let why = format!(
                    "a {hz} Hz loop closed every {:.4} ms physics substep is unstable: 2π × bandwidth × substep \
                     = {:.3} passes {MAX_LOOP_BANDWIDTH_STEP}; keep axes[{i}].drive.{name} at most {max_hz:.1} Hz \
                     or shorten physics_step_ms / raise physics_substeps",
                    substep_s * 1000.0,
                    std::f64::consts::TAU * hz * substep_s
                );
                return Err(match given {
                    Some(v) => self.invalid(v, format!("axes[{i}].drive.{name}"), Problem::Rule { why }),
                    None => self.invalid(&raw.physics_step_ms, "physics_step_ms", Problem::Rule { why }),
                });
            }
        }
        Ok(())
    }

    /// `[[axes]] drive`: the servo gains, defaults for what it leaves out.
    fn servo_gains(&self, d: &RawDrive, f: &dyn Fn(&str) -> String) -> Result<ServoGains, SceneError> {
        let g = ServoGains::default();
        let field = |name: &str| f(&format!("drive.{name}"));
        let positive = |v: &Option<Spanned<f64>>, name: &str, default: f64| self.positive_or(v, &field(name), default);
        let non_negative =
            |v: &Option<Spanned<f64>>, name: &str, default: f64| self.non_negative_or(v, &field(name), default);
        let feedforward = |v: &Option<Spanned<f64>>, name: &str, default: f64| match v {
            Some(v) => self.in_range(v, &field(name), 0.0, MAX_FEEDFORWARD_PCT),
            None => Ok(default),
        };
        let torque_limit_negative = match &d.torque_limit_negative {
            Some(v) => {
                let x = self.finite(v, &field("torque_limit_negative"))?;
                if !(-MAX_DRIVE_TORQUE..0.0).contains(&x) {
                    let problem = Problem::OutOfRange {
                        value: x,
                        min: -MAX_DRIVE_TORQUE,
                        max: 0.0,
                        exclusive: true,
                    };
                    return Err(self.invalid(v, field("torque_limit_negative"), problem));
                }
                Some(x)
            }
            None => None,
        };
        Ok(ServoGains {
            position_loop_bandwidth_hz: positive(
                &d.position_loop_bandwidth_hz,
                "position_loop_bandwidth_hz",
                g.position_loop_bandwidth_hz,
            )?,
            position_integrator_bandwidth_hz: non_negative(
                &d.position_integrator_bandwidth_hz,
                "position_integrator_bandwidth_hz",
                g.position_integrator_bandwidth_hz,
            )?,
            velocity_loop_bandwidth_hz: positive(
                &d.velocity_loop_bandwidth_hz,
                "velocity_loop_bandwidth_hz",
                g.velocity_loop_bandwidth_hz,
            )?,
            velocity_integrator_bandwidth_hz: non_negative(
                &d.velocity_integrator_bandwidth_hz,
                "velocity_integrator_bandwidth_hz",
                g.velocity_integrator_bandwidth_hz,
            )?,
            velocity_feedforward_gain_pct: feedforward(
                &d.velocity_feedforward_gain_pct,
                "velocity_feedforward_gain_pct",
                g.velocity_feedforward_gain_pct,
            )?,
            acceleration_feedforward_gain_pct: feedforward(
                &d.acceleration_feedforward_gain_pct,
                "acceleration_feedforward_gain_pct",
                g.acceleration_feedforward_gain_pct,
            )?,
            torque_limit_positive: match &d.torque_limit_positive {
                Some(v) => Some(self.bounded(v, &field("torque_limit_positive"), MAX_DRIVE_TORQUE)?),
                None => None,
            },
            torque_limit_negative,
            system_inertia: match &d.system_inertia {
                Some(v) => Some(self.positive(v, &field("system_inertia"))?),
                None => None,
            },
        })
    }

    pub(super) fn axes(&self, raw: &[RawAxis], robot: &Robot, names: &mut Names) -> Result<Vec<Axis>, SceneError> {
        let mut joints: HashMap<String, (usize, String)> = HashMap::new();
        let mut axes = Vec::with_capacity(raw.len());
        for (i, a) in raw.iter().enumerate() {
            let f = |field: &str| format!("axes[{i}].{field}");
            let name = self.identifier(&a.name, &f("name"))?;
            self.unique(names, &a.name, &f("name"), NameKind::Axis)?;
            let joint = match &a.joint {
                Some(spanned) => {
                    let joint = self.nonempty_name(spanned, &f("joint"))?;
                    if let Some((_, other_axis)) = joints.get(&joint) {
                        let problem = Problem::SharedJoint {
                            joint: joint.clone(),
                            other_axis: other_axis.clone(),
                        };
                        return Err(self.invalid(spanned, f("joint"), problem));
                    }
                    joints.insert(joint.clone(), (i, name.clone()));
                    Some(joint)
                }
                None => None,
            };
            let kind = *a.kind.get_ref();
            let units = *a.units.get_ref();
            if !units.fits(kind) {
                return Err(self.invalid(&a.units, f("units"), Problem::UnitsMismatch { units, kind }));
            }
            let modulo_period = match &a.modulo_period {
                Some(p) => Some(self.positive(p, &f("modulo_period"))?),
                None => None,
            };
            let max_velocity = self.bounded(&a.max_velocity, &f("max_velocity"), MAX_AXIS_SPEED)?;
            let max_acceleration = self.bounded(&a.max_acceleration, &f("max_acceleration"), MAX_AXIS_ACCELERATION)?;
            let max_deceleration = self.bounded(&a.max_deceleration, &f("max_deceleration"), MAX_AXIS_ACCELERATION)?;
            let max_jerk = self.bounded(&a.max_jerk, &f("max_jerk"), MAX_AXIS_JERK)?;
            let in_position_window = self.positive(&a.in_position_window, &f("in_position_window"))?;
            let position_range_window = match &a.position_range_window {
                Some(w) => self.non_negative(w, &f("position_range_window"))?,
                None => 5.0,
            };
            let modulo_tolerance_window = match &a.modulo_tolerance_window {
                Some(w) => {
                    let window = self.non_negative(w, &f("modulo_tolerance_window"))?;
                    // The planner's rule (AxisConfig): under half the period.
                    if let Some(period) = modulo_period
                        && window >= period / 2.0
                    {
                        let problem = Problem::OutOfRange {
                            value: window,
                            min: 0.0,
                            max: period / 2.0,
                            exclusive: true,
                        };
                        return Err(self.invalid(w, f("modulo_tolerance_window"), problem));
                    }
                    window
                }
                None => 0.0,
            };
            let motor = match &a.motor {
                Some(m) => {
                    let gains = *m.get_ref();
                    for (value, field) in [(gains.stiffness, "stiffness"), (gains.damping, "damping")] {
                        let spanned = Spanned::new(m.span(), value);
                        self.non_negative(&spanned, &f(&format!("motor.{field}")))?;
                    }
                    gains
                }
                None => MotorGains::default(),
            };
            let joint_si = joint.as_ref().and_then(|j| robot.initial_joints.get(j)).copied();
            let initial_position = match (&a.initial_position, joint_si) {
                (Some(p), joint_si) => {
                    let value = self.finite(p, &f("initial_position"))?;
                    self.at_most(p, &f("initial_position"), &[value], planner::axis::MAX_POSITION)?;
                    if let Some(si) = joint_si {
                        let as_si = value * units.si_per_unit();
                        if (as_si - si).abs() > 1e-9 * (1.0 + si.abs()) {
                            let problem = Problem::InitialPositionMismatch {
                                initial_position: value,
                                units,
                                joint: joint.clone().unwrap_or_default(),
                                joint_position_si: si,
                            };
                            return Err(self.invalid(p, f("initial_position"), problem));
                        }
                    }
                    value
                }
                (None, Some(si)) => si / units.si_per_unit(),
                (None, None) => 0.0,
            };
            let soft_travel_limits = match &a.soft_travel_limits {
                Some(l) => {
                    let [min, max] = self.finite_array(l, &f("soft_travel_limits"))?;
                    self.at_most(l, &f("soft_travel_limits"), &[min, max], planner::axis::MAX_POSITION)?;
                    if min >= max {
                        return Err(self.invalid(
                            l,
                            f("soft_travel_limits"),
                            Problem::SoftTravelLimitsOrder { min, max },
                        ));
                    }
                    if let Some(period) = modulo_period {
                        return Err(self.invalid(
                            l,
                            f("soft_travel_limits"),
                            Problem::SoftTravelLimitsOnModulo { period },
                        ));
                    }
                    if !(min..=max).contains(&initial_position) {
                        let problem = Problem::OutsideSoftTravelLimits {
                            position: initial_position,
                            min,
                            max,
                        };
                        return Err(match &a.initial_position {
                            Some(p) => self.invalid(p, f("initial_position"), problem),
                            None => self.invalid(l, f("soft_travel_limits"), problem),
                        });
                    }
                    Some((min, max))
                }
                None => None,
            };
            let soft_travel_limit_checking = a.soft_travel_limit_checking.as_ref().is_none_or(|c| *c.get_ref());
            if let (Some(c), Some(_)) = (&a.soft_travel_limit_checking, &a.soft_travel_limits)
                && !soft_travel_limit_checking
            {
                return Err(self.invalid(c, f("soft_travel_limit_checking"), Problem::SoftTravelLimitsUnchecked));
            }
            let drive = self.drive_options(a, joint.is_some(), &f)?;
            let servo = drive.servo;
            let homing = self.homing(a, drive.axis_type, &f)?;
            axes.push(Axis {
                name: name.clone(),
                joint,
                joint_location: a.joint.as_ref().map_or_else(|| self.loc(&a.name), |j| self.loc(j)),
                kind,
                units,
                config: AxisConfig {
                    modulo_period,
                    max_velocity,
                    max_acceleration,
                    max_deceleration,
                    max_jerk,
                    in_position_window,
                    target_position_monitoring: a.target_position_monitoring.unwrap_or(true),
                    position_range_monitoring: a.position_range_monitoring.unwrap_or(false),
                    position_range_window,
                    allow_motion_on_coupled_slave: a.allow_motion_on_coupled_slave.unwrap_or(false),
                    modulo_tolerance_window,
                    soft_travel_limits,
                    soft_overtravel_action: a
                        .soft_overtravel_action
                        .as_ref()
                        .map_or(FaultAction::StopPlanner, |x| x.get_ref().planner()),
                    axis_type: drive.axis_type,
                    inhibited: a.inhibit_axis.unwrap_or(false),
                    start_servo_on: drive.start_servo_on,
                    servo_enable_delay_s: drive.servo_enable_delay_s,
                    position_error_tolerance: drive.position_error_tolerance,
                    position_error_action: drive.position_error_action,
                    homing,
                    programmed_stop_mode: a
                        .programmed_stop_mode
                        .as_ref()
                        .map_or(Default::default(), |m| m.get_ref().planner()),
                    output_cam_execution_targets: match &a.output_cam_execution_targets {
                        Some(n) => self.int_in_range(n, &f("output_cam_execution_targets"), 0, 8)? as u32,
                        None => 4,
                    },
                    ..AxisConfig::new(name, kind.planner_kind())
                },
                initial_position,
                motor,
                servo,
                holding_brake: drive.holding_brake,
                soft_travel_limit_checking,
                location: self.loc(&a.name),
            });
        }
        Ok(axes)
    }

    pub(super) fn cameras(&self, raw: &[RawCamera], coarse_update_ms: f64) -> Result<Vec<Camera>, SceneError> {
        let mut seen: HashMap<String, (usize, ())> = HashMap::new();
        let mut cameras = Vec::with_capacity(raw.len());
        for (i, c) in raw.iter().enumerate() {
            let f = |field: &str| format!("cameras[{i}].{field}");
            let name = self.file_name_part(&c.name, &f("name"))?;
            self.unique(&mut seen, &c.name, &f("name"), ())?;
            let position_m = self.finite_array(&c.position, &f("position"))?;
            let target_m = self.finite_array(&c.target, &f("target"))?;
            self.at_most(&c.position, &f("position"), &position_m, MAX_LENGTH_M)?;
            self.at_most(&c.target, &f("target"), &target_m, MAX_LENGTH_M)?;
            if position_m == target_m {
                return Err(self.invalid(&c.target, f("target"), Problem::DegenerateCamera));
            }
            // The image's up is world +Z: a camera looking straight up or
            // down has none.
            let d: Vec<f64> = (0..3).map(|k| target_m[k] - position_m[k]).collect();
            let horizontal = d[0].hypot(d[1]);
            if horizontal <= 1e-6 * d[2].abs() {
                return Err(self.invalid(&c.target, f("target"), Problem::CameraAlongUp));
            }
            let fov_deg = self.finite(&c.fov_deg, &f("fov_deg"))?;
            if !(fov_deg > 0.0 && fov_deg < 180.0) {
                let problem = Problem::OutOfRange {
                    value: fov_deg,
                    min: 0.0,
                    max: 180.0,
                    exclusive: true,
                };
                return Err(self.invalid(&c.fov_deg, f("fov_deg"), problem));
            }
            for (v, field) in [(&c.width, "width"), (&c.height, "height")] {
                if *v.get_ref() == 0 {
                    return Err(self.invalid(v, f(field), Problem::NotPositive { value: 0.0 }));
                }
                if *v.get_ref() > MAX_IMAGE_PX {
                    let problem = Problem::OutOfRange {
                        value: f64::from(*v.get_ref()),
                        min: 1.0,
                        max: f64::from(MAX_IMAGE_PX),
                        exclusive: false,
                    };
                    return Err(self.invalid(v, f(field), problem));
                }
            }
            let fps = self.positive(&c.fps, &f("fps"))?;
            let max_fps = 1000.0 / coarse_update_ms;
            if fps > max_fps * (1.0 + 1e-12) {
                return Err(self.invalid(&c.fps, f("fps"), Problem::FpsAboveUpdateRate { fps, max_fps }));
            }
            cameras.push(Camera {
                name,
                position_m,
                target_m,
                fov_deg,
                width: *c.width.get_ref(),
                height: *c.height.get_ref(),
                fps,
                show_sensors: c.show_sensors.as_ref().is_some_and(|v| *v.get_ref()),
                location: self.loc(&c.name),
            });
        }
        Ok(cameras)
    }

    pub(super) fn obstacles(&self, raw: &[RawObstacle], base: &Path) -> Result<Vec<Obstacle>, SceneError> {
        let mut seen: HashMap<String, (usize, ())> = HashMap::new();
        let mut obstacles = Vec::with_capacity(raw.len());
        for (i, o) in raw.iter().enumerate() {
            let f = |field: &str| format!("obstacles[{i}].{field}");
            let name = self.nonempty_name(&o.name, &f("name"))?;
            self.unique(&mut seen, &o.name, &f("name"), ())?;
            let fields = ShapeFields {
                kind: &o.shape,
                size: &o.size,
                radius: &o.radius,
                length: &o.length,
                file: &o.file,
                scale: &o.scale,
            };
            let shape = self.shape(&fields, base, &f)?;
            let position_m = self.finite_array(&o.position, &f("position"))?;
            self.at_most(&o.position, &f("position"), &position_m, MAX_LENGTH_M)?;
            let rpy_deg = match &o.rpy_deg {
                Some(r) => self.finite_array(r, &f("rpy_deg"))?,
                None => [0.0; 3],
            };
            let color = self.color_or(&o.color, &f("color"), [0.6, 0.6, 0.6, 1.0])?;
            obstacles.push(Obstacle {
                name,
                shape,
                position_m,
                rpy_deg,
                color,
                location: self.loc(&o.name),
            });
        }
        Ok(obstacles)
    }

    /// A shape from its kind and fields: each kind takes its own fields
    /// and no other (the rules of `[[obstacles]]`, also used for the tool).
    pub(super) fn shape(
        &self,
        fields: &ShapeFields<'_>,
        base: &Path,
        f: &dyn Fn(&str) -> String,
    ) -> Result<Shape, SceneError> {
        let ShapeFields {
            kind: kind_at,
            size,
            radius,
            length,
            file,
            scale,
        } = *fields;
        let kind = *kind_at.get_ref();
        let shape_name = kind.name();
        let needs: &[&'static str] = match kind {
            ShapeKind::Box => &["size"],
            ShapeKind::Cylinder => &["radius", "length"],
            ShapeKind::Sphere => &["radius"],
            ShapeKind::Mesh => &["file", "scale"],
        };
        let given = [
            ("size", size.as_ref().map(Spanned::span)),
            ("radius", radius.as_ref().map(Spanned::span)),
            ("length", length.as_ref().map(Spanned::span)),
            ("file", file.as_ref().map(Spanned::span)),
            ("scale", scale.as_ref().map(Spanned::span)),
        ];
        for (field, span) in given {
            if let Some(span) = span
                && !needs.contains(&field)
            {
                let problem = Problem::ExtraShapeField {
                    shape: shape_name,
                    field,
                };
                return Err(self.invalid_at(span, f(field), problem));
            }
        }
        let missing = |field: &'static str| self.missing_shape_field(kind_at, f("shape"), shape_name, field);
        Ok(match kind {
            ShapeKind::Box => Shape::Box {
                size_m: self.bounded_array(size.as_ref().ok_or_else(|| missing("size"))?, &f("size"), MAX_LENGTH_M)?,
            },
            ShapeKind::Cylinder => Shape::Cylinder {
                radius_m: self.bounded(
                    radius.as_ref().ok_or_else(|| missing("radius"))?,
                    &f("radius"),
                    MAX_LENGTH_M,
                )?,
                length_m: self.bounded(
                    length.as_ref().ok_or_else(|| missing("length"))?,
                    &f("length"),
                    MAX_LENGTH_M,
                )?,
            },
            ShapeKind::Sphere => Shape::Sphere {
                radius_m: self.bounded(
                    radius.as_ref().ok_or_else(|| missing("radius"))?,
                    &f("radius"),
                    MAX_LENGTH_M,
                )?,
            },
            ShapeKind::Mesh => {
                let file = file.as_ref().ok_or_else(|| missing("file"))?;
                Shape::Mesh {
                    path: self.existing_file(file, &f("file"), base)?,
                    scale: match scale {
                        Some(s) => self.bounded_array(s, &f("scale"), MAX_MESH_SCALE)?,
                        None => [1.0; 3],
                    },
                }
            }
        })
    }

    pub(super) fn snapshots(&self, raw: &RawSnapshots, cameras: &[Camera]) -> Result<Snapshots, SceneError> {
        if cameras.is_empty() {
            return Err(self.invalid(&raw.frames, "snapshots.frames", Problem::NoCamera));
        }
        let mut frames: Vec<u32> = Vec::with_capacity(raw.frames.get_ref().len());
        for frame in raw.frames.get_ref() {
            if frames.contains(frame.get_ref()) {
                let problem = Problem::DuplicateFrame {
                    frame: *frame.get_ref(),
                };
                return Err(self.invalid(frame, "snapshots.frames", problem));
            }
            frames.push(*frame.get_ref());
        }
        frames.sort_unstable();
        Ok(Snapshots { frames })
    }
}

/// An axis' drive and state options, validated.
struct DriveOptions {
    servo: Option<ServoGains>,
    axis_type: AxisType,
    start_servo_on: bool,
    servo_enable_delay_s: f64,
    position_error_tolerance: Option<f64>,
    position_error_action: FaultAction,
    holding_brake: bool,
}
