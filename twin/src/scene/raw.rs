//! The raw (serde) layer: the TOML as written, with spans, before any check.
//! Unknown fields are errors (`deny_unknown_fields`).

use super::model::{MeshApproximation, Preflight, Reaction};
use std::collections::BTreeMap;

use serde::Deserialize;
use serde::de::{self, Deserializer, SeqAccess, Visitor};
use toml::Spanned;

use super::model::{AxisKind, MotorGains, Units};

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawScene {
    pub(super) name: Option<Spanned<String>>,
    pub(super) duration_s: Spanned<f64>,
    pub(super) coarse_update_ms: Option<Spanned<f64>>,
    pub(super) physics_step_ms: Spanned<f64>,
    pub(super) robot: RawRobot,
    #[serde(default)]
    pub(super) axes: Vec<RawAxis>,
    #[serde(default)]
    pub(super) cameras: Vec<RawCamera>,
    #[serde(default)]
    pub(super) obstacles: Vec<RawObstacle>,
    #[serde(default)]
    pub(super) data_types: Vec<RawDataType>,
    #[serde(default)]
    pub(super) add_on_instructions: Vec<Spanned<String>>,
    #[serde(default)]
    pub(super) tags: Vec<RawTag>,
    #[serde(default)]
    pub(super) aliases: Vec<RawAlias>,
    #[serde(default)]
    pub(super) program: Vec<RawStep>,
    #[serde(default)]
    pub(super) tasks: Vec<RawTask>,
    pub(super) controller: Option<RawController>,
    pub(super) snapshots: Option<RawSnapshots>,
    pub(super) trace: Option<RawTrace>,
    pub(super) collision: Option<RawCollision>,
    pub(super) plant: Option<PlantWord>,
    pub(super) physics_substeps: Option<Spanned<i64>>,
    #[serde(default)]
    pub(super) expect: Vec<RawExpect>,
    pub(super) test: Option<RawTest>,
    #[serde(default)]
    pub(super) variants: Vec<RawVariant>,
    #[serde(default)]
    pub(super) part_types: Vec<RawPartType>,
    #[serde(default)]
    pub(super) sources: Vec<RawSource>,
    #[serde(default)]
    pub(super) sinks: Vec<RawSink>,
    #[serde(default)]
    pub(super) conveyors: Vec<RawConveyor>,
    #[serde(default)]
    pub(super) sensors: Vec<RawSensor>,
    #[serde(default)]
    pub(super) cylinders: Vec<RawCylinder>,
    #[serde(default)]
    pub(super) grippers: Vec<RawGripper>,
    pub(super) parts_step_ms: Option<Spanned<f64>>,
}

/// `[[expect]]`: a name and exactly one kind, with that kind's options
/// (`scene/expect.rs` checks which go together).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawExpect {
    pub(super) name: Spanned<String>,
    pub(super) always: Option<Spanned<String>>,
    pub(super) never: Option<Spanned<String>>,
    pub(super) eventually: Option<Spanned<String>>,
    pub(super) at_end: Option<Spanned<String>>,
    pub(super) sequence: Option<Spanned<Vec<Spanned<String>>>>,
    pub(super) cycle: Option<Spanned<String>>,
    pub(super) from_s: Option<Spanned<f64>>,
    pub(super) to_s: Option<Spanned<f64>>,
    #[serde(rename = "while")]
    pub(super) guard: Option<Spanned<String>>,
    pub(super) after_s: Option<Spanned<f64>>,
    pub(super) by_s: Option<Spanned<f64>>,
    pub(super) within_s: Option<Spanned<f64>>,
    pub(super) min_s: Option<Spanned<f64>>,
    pub(super) max_s: Option<Spanned<f64>>,
    pub(super) count: Option<Spanned<i64>>,
}

/// `[test]`: what `twin test` expects of the run as a whole.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawTest {
    pub(super) exit_code: Option<Spanned<i64>>,
    pub(super) timeout_s: Option<Spanned<f64>>,
}

/// `[[variants]]`: the scene run again with other initial tag values, a
/// duration, a plant, an expected exit code and more expectations.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawVariant {
    pub(super) name: Spanned<String>,
    #[serde(default)]
    pub(super) tags: BTreeMap<String, Spanned<toml::Value>>,
    pub(super) duration_s: Option<Spanned<f64>>,
    pub(super) plant: Option<Spanned<PlantWord>>,
    pub(super) exit_code: Option<Spanned<i64>>,
    #[serde(default)]
    pub(super) expect: Vec<RawExpect>,
}

/// `plant`: the plant modes.
#[derive(Deserialize, Clone, Copy, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub(super) enum PlantWord {
    Physics,
    Kinematic,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawRobot {
    pub(super) urdf: Spanned<String>,
    #[serde(default)]
    pub(super) initial_joints: BTreeMap<String, Spanned<f64>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawAxis {
    pub(super) name: Spanned<String>,
    pub(super) joint: Option<Spanned<String>>,
    pub(super) kind: Spanned<AxisKind>,
    pub(super) modulo_period: Option<Spanned<f64>>,
    pub(super) units: Spanned<Units>,
    pub(super) max_velocity: Spanned<f64>,
    pub(super) max_acceleration: Spanned<f64>,
    pub(super) max_deceleration: Spanned<f64>,
    pub(super) max_jerk: Spanned<f64>,
    pub(super) in_position_window: Spanned<f64>,
    pub(super) target_position_monitoring: Option<bool>,
    pub(super) position_range_monitoring: Option<bool>,
    pub(super) position_range_window: Option<Spanned<f64>>,
    pub(super) allow_motion_on_coupled_slave: Option<bool>,
    pub(super) modulo_tolerance_window: Option<Spanned<f64>>,
    pub(super) initial_position: Option<Spanned<f64>>,
    pub(super) soft_travel_limits: Option<Spanned<Numbers<2>>>,
    pub(super) soft_travel_limit_checking: Option<Spanned<bool>>,
    pub(super) soft_overtravel_action: Option<Spanned<ExceptionAction>>,
    pub(super) motor: Option<Spanned<MotorGains>>,
    pub(super) axis_configuration: Option<Spanned<AxisConfiguration>>,
    pub(super) inhibit_axis: Option<bool>,
    pub(super) servo_on_at_start: Option<Spanned<bool>>,
    pub(super) position_error_tolerance: Option<Spanned<f64>>,
    pub(super) position_error_action: Option<Spanned<ExceptionAction>>,
    pub(super) holding_brake: Option<Spanned<bool>>,
    pub(super) programmed_stop_mode: Option<Spanned<StopModeWord>>,
    pub(super) output_cam_execution_targets: Option<Spanned<i64>>,
    pub(super) brake_release_delay_ms: Option<Spanned<f64>>,
    pub(super) drive: Option<Spanned<RawDrive>>,
    pub(super) home_mode: Option<Spanned<HomeModeWord>>,
    pub(super) home_sequence: Option<Spanned<HomeSequenceWord>>,
    pub(super) home_position: Option<Spanned<f64>>,
    pub(super) home_offset: Option<Spanned<f64>>,
    pub(super) home_direction: Option<Spanned<HomeDirectionWord>>,
    pub(super) home_speed: Option<Spanned<f64>>,
    pub(super) home_return_speed: Option<Spanned<f64>>,
}

/// `[[axes]] home_mode`: Logix `HomeMode`.
#[derive(Deserialize, Clone, Copy, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub(super) enum HomeModeWord {
    Passive,
    Active,
}

/// `[[axes]] home_sequence`: Logix `HomeSequence` (only `immediate` is
/// simulated; the others are named so that the refusal says why).
#[derive(Deserialize, Clone, Copy, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub(super) enum HomeSequenceWord {
    Immediate,
    Switch,
    Marker,
    SwitchMarker,
    TorqueLevel,
    TorqueLevelMarker,
}

impl HomeSequenceWord {
    pub(super) fn word(self) -> &'static str {
        match self {
            Self::Immediate => "immediate",
            Self::Switch => "switch",
            Self::Marker => "marker",
            Self::SwitchMarker => "switch_marker",
            Self::TorqueLevel => "torque_level",
            Self::TorqueLevelMarker => "torque_level_marker",
        }
    }
}

/// `[[axes]] home_direction`: Logix `HomeDirection`.
#[derive(Deserialize, Clone, Copy, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub(super) enum HomeDirectionWord {
    UnidirectionalForward,
    BidirectionalForward,
    UnidirectionalReverse,
    BidirectionalReverse,
}

/// `[[axes]] drive`: a servo drive's gains and limits, each optional.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawDrive {
    pub(super) position_loop_bandwidth_hz: Option<Spanned<f64>>,
    pub(super) position_integrator_bandwidth_hz: Option<Spanned<f64>>,
    pub(super) velocity_loop_bandwidth_hz: Option<Spanned<f64>>,
    pub(super) velocity_integrator_bandwidth_hz: Option<Spanned<f64>>,
    pub(super) velocity_feedforward_gain_pct: Option<Spanned<f64>>,
    pub(super) acceleration_feedforward_gain_pct: Option<Spanned<f64>>,
    pub(super) torque_limit_positive: Option<Spanned<f64>>,
    pub(super) torque_limit_negative: Option<Spanned<f64>>,
    pub(super) system_inertia: Option<Spanned<f64>>,
}

/// `[[axes]] axis_configuration`: Logix's Axis Configuration words.
#[derive(Deserialize, Clone, Copy, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub(super) enum AxisConfiguration {
    PositionLoop,
    FeedbackOnly,
}

/// `[[axes]] programmed_stop_mode`: Logix `ProgrammedStopMode`.
#[derive(Deserialize, Clone, Copy, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub(super) enum StopModeWord {
    FastStop,
    FastDisable,
    HardDisable,
    FastShutdown,
    HardShutdown,
}

impl StopModeWord {
    pub(super) fn planner(self) -> planner::axis::ProgrammedStopMode {
        use planner::axis::ProgrammedStopMode as M;
        match self {
            Self::FastStop => M::FastStop,
            Self::FastDisable => M::FastDisable,
            Self::HardDisable => M::HardDisable,
            Self::FastShutdown => M::FastShutdown,
            Self::HardShutdown => M::HardShutdown,
        }
    }
}

/// `[[axes]] position_error_action`, `soft_overtravel_action`: the
/// exception actions.
#[derive(Deserialize, Clone, Copy, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub(super) enum ExceptionAction {
    Ignore,
    Alarm,
    FaultStatusOnly,
    StopPlanner,
    StopDrive,
    Shutdown,
}

impl ExceptionAction {
    pub(super) fn planner(self) -> planner::servo::FaultAction {
        use planner::servo::FaultAction as F;
        match self {
            Self::Ignore => F::Ignore,
            Self::Alarm => F::Alarm,
            Self::FaultStatusOnly => F::FaultStatusOnly,
            Self::StopPlanner => F::StopPlanner,
            Self::StopDrive => F::StopDrive,
            Self::Shutdown => F::Shutdown,
        }
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawCamera {
    pub(super) name: Spanned<String>,
    pub(super) position: Spanned<Numbers<3>>,
    pub(super) target: Spanned<Numbers<3>>,
    pub(super) fov_deg: Spanned<f64>,
    pub(super) width: Spanned<u32>,
    pub(super) height: Spanned<u32>,
    pub(super) fps: Spanned<f64>,
    pub(super) show_sensors: Option<Spanned<bool>>,
}

#[derive(Deserialize, Clone, Copy, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub(super) enum ShapeKind {
    Box,
    Cylinder,
    Sphere,
    Mesh,
}

impl ShapeKind {
    pub(super) fn name(self) -> &'static str {
        match self {
            ShapeKind::Box => "box",
            ShapeKind::Cylinder => "cylinder",
            ShapeKind::Sphere => "sphere",
            ShapeKind::Mesh => "mesh",
        }
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawObstacle {
    pub(super) name: Spanned<String>,
    pub(super) shape: Spanned<ShapeKind>,
    pub(super) size: Option<Spanned<Numbers<3>>>,
    pub(super) radius: Option<Spanned<f64>>,
    pub(super) length: Option<Spanned<f64>>,
    pub(super) file: Option<Spanned<String>>,
    pub(super) scale: Option<Spanned<Numbers<3>>>,
    pub(super) position: Spanned<Numbers<3>>,
    pub(super) rpy_deg: Option<Spanned<Numbers<3>>>,
    pub(super) color: Option<Spanned<Numbers<4>>>,
}

/// `[[data_types]]`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawDataType {
    pub(super) name: Spanned<String>,
    pub(super) description: Option<String>,
    pub(super) members: Option<Spanned<Vec<RawMember>>>,
    pub(super) string_length: Option<Spanned<i64>>,
}

/// One of a data type's `members`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawMember {
    pub(super) name: Spanned<String>,
    #[serde(rename = "type")]
    pub(super) ty: Spanned<String>,
    pub(super) dimension: Option<Spanned<i64>>,
    pub(super) description: Option<String>,
}

/// `[[aliases]]`: a name for another tag, member, element or bit.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawAlias {
    pub(super) name: Spanned<String>,
    pub(super) alias_for: Spanned<String>,
    pub(super) description: Option<Spanned<String>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawTag {
    pub(super) name: Spanned<String>,
    #[serde(rename = "type")]
    pub(super) ty: Spanned<String>,
    pub(super) value: Option<Spanned<toml::Value>>,
    pub(super) coordinate_system: Option<Spanned<RawCoordinateSystem>>,
    pub(super) geometry: Option<Spanned<RawGeometry>>,
    pub(super) options: Option<Spanned<RawMoveOptions>>,
    pub(super) usage: Option<Spanned<String>>,
    pub(super) connection: Option<Spanned<String>>,
    pub(super) constant: Option<Spanned<bool>>,
    pub(super) description: Option<String>,
    pub(super) external_access: Option<Spanned<String>>,
    pub(super) scheduled_output: Option<Spanned<RawScheduledOutput>>,
    /// A `MOTION_GROUP` tag's coarse update period.
    pub(super) coarse_update_ms: Option<Spanned<f64>>,
}

/// `[[tags]] scheduled_output`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawScheduledOutput {
    pub(super) axis: Spanned<String>,
    pub(super) execution_target: Option<Spanned<i64>>,
    pub(super) response_ms: Option<Spanned<f64>>,
}

/// An `MC_MoveModulo` instance's `Options` input (`ST_MoveOptions`), as
/// its declaration initialises it; the members by their Tc2_MC2 names.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawMoveOptions {
    #[serde(rename = "EnableBlendingPosition")]
    pub(super) enable_blending_position: Option<Spanned<bool>>,
    #[serde(rename = "BlendingPosition")]
    pub(super) blending_position: Option<Spanned<f64>>,
    #[serde(rename = "IgnorePositionMonitoring")]
    pub(super) ignore_position_monitoring: Option<bool>,
    #[serde(rename = "EnableStopPositionMonitoring")]
    pub(super) enable_stop_position_monitoring: Option<bool>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawCoordinateSystem {
    pub(super) primary_axes: Option<Spanned<i64>>,
    pub(super) max_speed: Option<Spanned<f64>>,
    pub(super) max_accel: Option<Spanned<f64>>,
    pub(super) max_decel: Option<Spanned<f64>>,
    pub(super) max_accel_jerk: Option<Spanned<f64>>,
    pub(super) max_decel_jerk: Option<Spanned<f64>>,
    pub(super) command_tolerance: Option<Spanned<f64>>,
    pub(super) actual_tolerance: Option<Spanned<f64>>,
    pub(super) tool_link: Option<Spanned<String>>,
    pub(super) master_axis: Option<Spanned<String>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawStep {
    pub(super) at_s: Option<Spanned<f64>>,
    pub(super) when: Option<Spanned<String>>,
    pub(super) after_s: Option<Spanned<f64>>,
    pub(super) call: Spanned<String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawTask {
    pub(super) name: Spanned<String>,
    #[serde(rename = "type")]
    pub(super) kind: Option<Spanned<String>>,
    pub(super) period_ms: Option<Spanned<f64>>,
    pub(super) priority: Option<Spanned<i64>>,
    pub(super) watchdog_ms: Option<Spanned<f64>>,
    pub(super) trigger: Option<Spanned<String>>,
    pub(super) axis: Option<Spanned<String>>,
    pub(super) timeout_ms: Option<Spanned<f64>>,
    pub(super) inhibit: Option<bool>,
    #[serde(default)]
    pub(super) programs: Vec<RawProgram>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawProgram {
    pub(super) name: Spanned<String>,
    pub(super) main: Spanned<RawRoutine>,
    #[serde(default)]
    pub(super) routines: Vec<Spanned<RawRoutine>>,
    #[serde(default)]
    pub(super) tags: Vec<RawTag>,
    #[serde(default)]
    pub(super) aliases: Vec<RawAlias>,
    pub(super) fault_routine: Option<Spanned<String>>,
    pub(super) disabled: Option<bool>,
}

/// `[controller]`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawController {
    pub(super) report_overflow_faults: Option<bool>,
    pub(super) statement_us: Option<Spanned<f64>>,
    pub(super) start_time: Option<Spanned<String>>,
    pub(super) fault_handler: Option<RawProgram>,
}

/// A routine: a path, or `{ file = "…", dialect = "iec" }`.
#[derive(Deserialize)]
#[serde(untagged)]
pub(super) enum RawRoutine {
    Path(String),
    Table {
        file: String,
        #[serde(default)]
        dialect: Option<String>,
    },
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawTrace {
    #[serde(default)]
    pub(super) tags: Vec<Spanned<String>>,
    #[serde(default)]
    pub(super) rungs: Vec<Spanned<String>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawSnapshots {
    pub(super) frames: Spanned<Vec<Spanned<u32>>>,
}

/// Exactly `N` numbers, as a TOML array (integers are taken as floats). An
/// array of another length is an error naming both lengths, never
/// truncated.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Numbers<const N: usize>(pub(super) [f64; N]);

impl<'de, const N: usize> Deserialize<'de> for Numbers<N> {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct Exactly<const N: usize>;
        impl<'de, const N: usize> Visitor<'de> for Exactly<N> {
            type Value = Numbers<N>;
            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                write!(f, "an array of {N} numbers")
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Numbers<N>, A::Error> {
                let mut values = [0.0; N];
                let mut len = 0;
                while let Some(value) = seq.next_element::<f64>()? {
                    if len < N {
                        values[len] = value;
                    }
                    len += 1;
                }
                if len == N {
                    Ok(Numbers(values))
                } else {
                    Err(de::Error::invalid_length(len, &self))
                }
            }
        }
        deserializer.deserialize_seq(Exactly::<N>)
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawCollision {
    pub(super) reaction: Option<Spanned<Reaction>>,
    pub(super) meshes: Option<Spanned<MeshApproximation>>,
    pub(super) self_collision: Option<Spanned<bool>>,
    #[serde(default)]
    pub(super) allowed_pairs: Vec<Spanned<[String; 2]>>,
    pub(super) preflight: Option<Spanned<Preflight>>,
    pub(super) sweep_resolution_m: Option<Spanned<f64>>,
    pub(super) tool: Option<RawTool>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawTool {
    pub(super) name: Option<Spanned<String>>,
    pub(super) link: Spanned<String>,
    pub(super) shape: Spanned<ShapeKind>,
    pub(super) size: Option<Spanned<Numbers<3>>>,
    pub(super) radius: Option<Spanned<f64>>,
    pub(super) length: Option<Spanned<f64>>,
    pub(super) file: Option<Spanned<String>>,
    pub(super) scale: Option<Spanned<Numbers<3>>>,
    pub(super) position: Option<Spanned<Numbers<3>>>,
    pub(super) rpy_deg: Option<Spanned<Numbers<3>>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawGeometry {
    #[serde(rename = "type")]
    pub(super) kind: Spanned<String>,
    pub(super) transform_dimension: Option<Spanned<i64>>,
    pub(super) link_lengths: Option<Spanned<Numbers<2>>>,
    pub(super) base_offsets: Option<Spanned<Numbers<3>>>,
    pub(super) end_effector_offsets: Option<Spanned<Numbers<3>>>,
    pub(super) zero_angles_deg: Option<Spanned<Numbers<3>>>,
    pub(super) base_link: Option<Spanned<String>>,
    pub(super) tool_link: Option<Spanned<String>>,
    pub(super) platform_joints: Option<Vec<Spanned<String>>>,
    pub(super) forearm_joints: Option<Vec<[Spanned<String>; 2]>>,
    pub(super) forearm_tip_links: Option<Vec<Spanned<String>>>,
    pub(super) ball_links: Option<Vec<Spanned<String>>>,
}

/// `[[part_types]]`: a workpiece's shape (as an obstacle's) and material.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawPartType {
    pub(super) name: Spanned<String>,
    pub(super) shape: Spanned<ShapeKind>,
    pub(super) size: Option<Spanned<Numbers<3>>>,
    pub(super) radius: Option<Spanned<f64>>,
    pub(super) length: Option<Spanned<f64>>,
    pub(super) file: Option<Spanned<String>>,
    pub(super) scale: Option<Spanned<Numbers<3>>>,
    pub(super) mass_kg: Spanned<f64>,
    pub(super) friction: Option<Spanned<f64>>,
    pub(super) restitution: Option<Spanned<f64>>,
    pub(super) color: Option<Spanned<Numbers<4>>>,
    pub(super) material: Option<Spanned<String>>,
    pub(super) type_id: Option<Spanned<i64>>,
}

/// A device's `faults = [{ kind, from_s, to_s }]` entry.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawFault {
    pub(super) kind: Spanned<String>,
    pub(super) from_s: Spanned<f64>,
    pub(super) to_s: Option<Spanned<f64>>,
}

/// A source's `jitter` table.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawJitter {
    pub(super) time_s: Option<Spanned<f64>>,
    pub(super) position_m: Option<Spanned<Numbers<3>>>,
    pub(super) yaw_deg: Option<Spanned<f64>>,
    pub(super) seed: Option<Spanned<i64>>,
}

/// `[[sources]]`: where and when parts appear.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawSource {
    pub(super) name: Spanned<String>,
    pub(super) part_type: Spanned<String>,
    pub(super) position: Spanned<Numbers<3>>,
    pub(super) rpy_deg: Option<Spanned<Numbers<3>>>,
    pub(super) every_s: Option<Spanned<f64>>,
    pub(super) start_s: Option<Spanned<f64>>,
    pub(super) on: Option<Spanned<String>>,
    pub(super) at_s: Option<Spanned<Vec<Spanned<f64>>>>,
    pub(super) count: Option<Spanned<i64>>,
    pub(super) jitter: Option<Spanned<RawJitter>>,
    pub(super) skip: Option<Spanned<Vec<Spanned<i64>>>>,
}

/// `[[sinks]]`: a box that removes the parts whose centre enters it.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawSink {
    pub(super) name: Spanned<String>,
    pub(super) position: Spanned<Numbers<3>>,
    pub(super) rpy_deg: Option<Spanned<Numbers<3>>>,
    pub(super) size: Spanned<Numbers<3>>,
    #[serde(rename = "as")]
    pub(super) outcome: Option<Spanned<String>>,
}

/// `[[conveyors]]`: a belt (a box running along its local +x).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawConveyor {
    pub(super) name: Spanned<String>,
    pub(super) position: Spanned<Numbers<3>>,
    pub(super) rpy_deg: Option<Spanned<Numbers<3>>>,
    pub(super) size: Spanned<Numbers<3>>,
    pub(super) friction: Option<Spanned<f64>>,
    pub(super) color: Option<Spanned<Numbers<4>>>,
    pub(super) axis: Option<Spanned<String>>,
    pub(super) run: Option<Spanned<String>>,
    pub(super) reverse: Option<Spanned<String>>,
    pub(super) speed: Option<Spanned<String>>,
    pub(super) max_speed_mps: Option<Spanned<f64>>,
    pub(super) accel_mps2: Option<Spanned<f64>>,
    pub(super) running_tag: Option<Spanned<String>>,
    pub(super) encoder_tag: Option<Spanned<String>>,
    pub(super) counts_per_m: Option<Spanned<f64>>,
    pub(super) ride: Option<Spanned<bool>>,
    #[serde(default)]
    pub(super) faults: Vec<RawFault>,
}

/// `[[sensors]]`: one entry for every kind; `scene/cell.rs` checks which
/// fields a kind takes.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawSensor {
    pub(super) name: Spanned<String>,
    pub(super) kind: Spanned<String>,
    pub(super) tag: Spanned<String>,
    pub(super) link: Option<Spanned<String>>,
    pub(super) position: Option<Spanned<Numbers<3>>>,
    pub(super) rpy_deg: Option<Spanned<Numbers<3>>>,
    pub(super) detects: Option<Spanned<Vec<Spanned<String>>>>,
    pub(super) invert: Option<Spanned<bool>>,
    pub(super) on_delay_ms: Option<Spanned<f64>>,
    pub(super) off_delay_ms: Option<Spanned<f64>>,
    pub(super) rpi_ms: Option<Spanned<f64>>,
    pub(super) cos: Option<Spanned<bool>>,
    pub(super) from: Option<Spanned<Numbers<3>>>,
    pub(super) to: Option<Spanned<Numbers<3>>>,
    pub(super) count: Option<Spanned<i64>>,
    pub(super) pitch_m: Option<Spanned<f64>>,
    pub(super) value_tag: Option<Spanned<String>>,
    pub(super) range_m: Option<Spanned<f64>>,
    pub(super) scale: Option<Spanned<[Numbers<2>; 2]>>,
    pub(super) shape: Option<Spanned<ShapeKind>>,
    pub(super) size: Option<Spanned<Numbers<3>>>,
    pub(super) radius: Option<Spanned<f64>>,
    pub(super) length: Option<Spanned<f64>>,
    pub(super) materials: Option<Spanned<Vec<Spanned<String>>>>,
    pub(super) count_tag: Option<Spanned<String>>,
    pub(super) registration: Option<Spanned<RawRegistration>>,
    pub(super) between: Option<Spanned<[Vec<Spanned<String>>; 2]>>,
    pub(super) below_m: Option<Spanned<f64>>,
    pub(super) trigger: Option<Spanned<String>>,
    pub(super) latency_ms: Option<Spanned<f64>>,
    pub(super) position_tag: Option<Spanned<String>>,
    pub(super) angle_tag: Option<Spanned<String>>,
    pub(super) type_tag: Option<Spanned<String>>,
    pub(super) frame: Option<Spanned<String>>,
    pub(super) units: Option<Spanned<String>>,
    #[serde(default)]
    pub(super) faults: Vec<RawFault>,
}

/// A sensor's `registration = { axis, input }`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawRegistration {
    pub(super) axis: Spanned<String>,
    pub(super) input: Spanned<i64>,
}

/// `[[cylinders]]`: a pneumatic stopper, pusher or diverter.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawCylinder {
    pub(super) name: Spanned<String>,
    pub(super) position: Spanned<Numbers<3>>,
    pub(super) rpy_deg: Option<Spanned<Numbers<3>>>,
    pub(super) size: Spanned<Numbers<3>>,
    pub(super) stroke_m: Spanned<f64>,
    pub(super) extend_ms: Spanned<f64>,
    pub(super) retract_ms: Option<Spanned<f64>>,
    pub(super) extend: Spanned<String>,
    pub(super) retract: Option<Spanned<String>>,
    pub(super) extended_tag: Option<Spanned<String>>,
    pub(super) retracted_tag: Option<Spanned<String>>,
    pub(super) color: Option<Spanned<Numbers<4>>>,
    #[serde(default)]
    pub(super) faults: Vec<RawFault>,
}

/// `[[grippers]]`: a vacuum cup or fingers on a link.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawGripper {
    pub(super) name: Spanned<String>,
    pub(super) kind: Spanned<String>,
    pub(super) link: Spanned<String>,
    pub(super) position: Option<Spanned<Numbers<3>>>,
    pub(super) rpy_deg: Option<Spanned<Numbers<3>>>,
    pub(super) grip: Spanned<String>,
    pub(super) release: Option<Spanned<String>>,
    pub(super) holding_tag: Option<Spanned<String>>,
    pub(super) build_up_ms: Option<Spanned<f64>>,
    pub(super) close_ms: Option<Spanned<f64>>,
    pub(super) reach_m: Option<Spanned<f64>>,
    pub(super) max_force_n: Option<Spanned<f64>>,
    #[serde(default)]
    pub(super) faults: Vec<RawFault>,
}
