//! Load-time check that a URDF robot and the MCT geometry driving it agree.
//!
//! A scene that maps a transform's target axes to URDF joints must describe
//! the same robot twice: once as a URDF chain (what the physics simulates and
//! the renderer draws) and once as MCT geometry parameters (what the planner
//! inverts). [`check`] poses both at [`CONFIGURATIONS`] joint configurations
//! spread over the URDF joint limits and compares
//!
//! * the tool point: the origin of [`ChainMapping::tool_link`] in the frame
//!   of [`ChainMapping::base_link`] (the MCT robot frame) against the MCT
//!   forward kinematics (all three coordinates; the first two for a
//!   two-dimensional geometry without a shared third axis);
//! * for the parallel geometries (Delta 3D, Delta 2D, SCARA Delta), whose
//!   forearms close loops a URDF tree cannot express ([`pose_parallel`]):
//!   the platform hangs on virtual prismatic joints
//!   ([`ChainMapping::platform_joints`], along the base frame's X, Y, Z)
//!   posed at the MCT forward kinematics, and each forearm hangs from its
//!   upper arm on a virtual universal joint (yaw about Z, then pitch about Y
//!   of the elbow frame) posed to point at its ball joint on the platform;
//!   the distance from each forearm's tip to its ball is then zero exactly
//!   when the URDF's upper arms, forearms, base and platform radii and tool
//!   offset are the geometry's.
//!
//! Any difference above [`TOLERANCE_M`] refuses the robot with
//! [`KinematicsCheckError::Mismatch`], which says where, by how much and at
//! which configuration. Configurations where a parallel robot's forearms
//! cannot meet are skipped; at least [`MIN_CONFIGURATIONS`] must remain.
//!
//! Joint values: the URDF joint position equals the MCT axis position in
//! kinematic units (radians for revolute joints, metres for prismatic ones):
//! the URDF's zero pose must be the axes' zero, and the geometry's zero-angle
//! offsets describe where that pose sits in the kinematic equations.

use nalgebra::{Point3, Vector3};
use planner::mct::{Geometry, GeometryKind, JointKind as MctJointKind};

use crate::plant::urdf::{JointIndex, JointKind, LinkIndex, RobotModel};

/// Largest accepted difference, metres.
pub const TOLERANCE_M: f64 = 1e-6;

/// Number of configurations tried.
pub const CONFIGURATIONS: usize = 12;

/// Fewest configurations that must be valid for the check to count.
pub const MIN_CONFIGURATIONS: usize = 4;

/// How the transform's target axes and the tool map onto the URDF.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ChainMapping {
    /// The URDF joint each target axis drives, J1 first (the SCARA
    /// geometries' shared third axis included).
    pub joints: Vec<String>,
    /// The link whose frame is the MCT robot frame.
    pub base_link: String,
    /// The link whose origin is the tool point.
    pub tool_link: String,
    /// Parallel geometries: the prismatic joints that pose the platform along
    /// the base frame's X, Y (and Z) axes (default: none).
    pub platform_joints: Vec<String>,
    /// Parallel geometries: each forearm's virtual universal joint at the
    /// elbow, `[yaw about Z, pitch about Y]`, arm 1 first (default: none).
    pub forearm_joints: Vec<[String; 2]>,
    /// Parallel geometries: the link at each forearm's far end (L2 from the
    /// elbow), arm 1 first (default: none).
    pub forearm_tip_links: Vec<String>,
    /// Parallel geometries: the link at each arm's ball joint on the
    /// platform, arm 1 first (default: none).
    pub ball_links: Vec<String>,
}

/// What was measured.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Measure {
    /// The tool point.
    Tool,
    /// The distance from forearm `arm`'s tip to its ball joint (1-based).
    Forearm {
        /// 1-based arm number.
        arm: usize,
    },
}

impl std::fmt::Display for Measure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Tool => write!(f, "tool point"),
            Self::Forearm { arm } => write!(f, "forearm {arm} tip (distance to its ball joint on the platform)"),
        }
    }
}

/// Why a URDF robot does not match its MCT geometry.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum KinematicsCheckError {
    /// A link named in the mapping is not in the URDF.
    #[error("URDF has no link '{name}'")]
    UnknownLink {
        /// The name.
        name: String,
    },
    /// A joint named in the mapping is not in the URDF.
    #[error("URDF has no joint '{name}'")]
    UnknownJoint {
        /// The name.
        name: String,
    },
    /// A mapped joint's type does not fit the geometry's joint (J`axis`).
    #[error("URDF joint '{name}' for J{axis} is {found:?}, the MCT geometry needs a {expected:?} joint")]
    JointKind {
        /// The joint.
        name: String,
        /// 1-based target axis.
        axis: usize,
        /// URDF type.
        found: JointKind,
        /// What the geometry needs.
        expected: MctJointKind,
    },
    /// The mapping lists a different number of joints or markers than the
    /// geometry needs.
    #[error("the mapping gives {given} {what}, the MCT geometry needs {needed}")]
    Count {
        /// `"joints"`, `"platform joints"`, `"forearm joints"`,
        /// `"forearm tip links"` or `"ball links"`.
        what: &'static str,
        /// How many were given.
        given: usize,
        /// How many are needed.
        needed: usize,
    },
    /// URDF and MCT disagree.
    #[error(
        "URDF and MCT geometry disagree: {measure} off by {deviation_m:.3e} m (tolerance {tolerance_m:.0e} m) at joint configuration {configuration:?} (rad/m)"
    )]
    Mismatch {
        /// What differs.
        measure: Measure,
        /// By how much, metres.
        deviation_m: f64,
        /// The tolerance, metres.
        tolerance_m: f64,
        /// The joint configuration, J1 first (rad or m).
        configuration: Vec<f64>,
    },
    /// The geometry's axes are not URDF joint positions: an articulated
    /// dependent robot measures its elbow from the horizontal (a URDF joint
    /// turns relative to its parent link), an H-bot's two motors share one
    /// belt (a URDF has an X and a Y slide). Such a robot would be simulated
    /// wrongly, so it is refused rather than reported as a mismatch.
    #[error("an MCT {kind:?} target cannot drive URDF joints one axis per joint: {reason}")]
    Unsupported {
        /// The geometry.
        kind: GeometryKind,
        /// Why.
        reason: &'static str,
    },
    /// Too few configurations could be posed (a parallel robot whose
    /// forearms cannot meet within the URDF joint limits).
    #[error(
        "only {valid} of {CONFIGURATIONS} joint configurations reach a valid MCT position; need {MIN_CONFIGURATIONS}"
    )]
    TooFewConfigurations {
        /// How many were valid.
        valid: usize,
    },
}

/// The outcome of a passing check.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CheckReport {
    /// Configurations compared.
    pub configurations: usize,
    /// Largest difference seen, metres.
    pub max_deviation_m: f64,
}

struct Resolved {
    joints: Vec<JointIndex>,
    base: LinkIndex,
    tool: LinkIndex,
    platform: Vec<JointIndex>,
    forearms: Vec<[JointIndex; 2]>,
    tips: Vec<LinkIndex>,
    balls: Vec<LinkIndex>,
}

fn resolve(model: &RobotModel, geometry: &Geometry, m: &ChainMapping) -> Result<Resolved, KinematicsCheckError> {
    let link = |name: &String| {
        model
            .link_by_name(name)
            .ok_or_else(|| KinematicsCheckError::UnknownLink { name: name.clone() })
    };
    let joint = |name: &String| {
        model
            .joint_by_name(name)
            .ok_or_else(|| KinematicsCheckError::UnknownJoint { name: name.clone() })
    };
    let reason = match geometry.kind() {
        GeometryKind::ArticulatedDependent => {
            Some("its last joint's angle is measured from the horizontal, a URDF joint's from its parent link")
        }
        GeometryKind::CartesianHBot => Some("its two motors drive X1 and X2 together through one belt"),
        _ => None,
    };
    if let Some(reason) = reason {
        return Err(KinematicsCheckError::Unsupported {
            kind: geometry.kind(),
            reason,
        });
    }
    let needed = geometry.dimension() + usize::from(geometry.shares_third_axis());
    let count = |what, given: usize, needed: usize| {
        if given == needed {
            Ok(())
        } else {
            Err(KinematicsCheckError::Count { what, given, needed })
        }
    };
    count("joints", m.joints.len(), needed)?;
    let joints = m.joints.iter().map(joint).collect::<Result<Vec<_>, _>>()?;
    let kinds = geometry.joint_kinds();
    for (i, &j) in joints.iter().enumerate() {
        let found = model.joint(j).kind;
        let fits = match kinds[i] {
            MctJointKind::Revolute => matches!(found, JointKind::Revolute | JointKind::Continuous),
            MctJointKind::Prismatic => found == JointKind::Prismatic,
        };
        if !fits {
            return Err(KinematicsCheckError::JointKind {
                name: m.joints[i].clone(),
                axis: i + 1,
                found,
                expected: kinds[i],
            });
        }
    }
    // A parallel robot has one arm and one platform joint per dimension.
    let arms = if geometry.parallel_forearm_length().is_some() {
        geometry.dimension()
    } else {
        0
    };
    count("platform joints", m.platform_joints.len(), arms)?;
    count("forearm joints", m.forearm_joints.len(), arms)?;
    count("forearm tip links", m.forearm_tip_links.len(), arms)?;
    count("ball links", m.ball_links.len(), arms)?;
    Ok(Resolved {
        joints,
        base: link(&m.base_link)?,
        tool: link(&m.tool_link)?,
        platform: m.platform_joints.iter().map(joint).collect::<Result<_, _>>()?,
        forearms: m
            .forearm_joints
            .iter()
            .map(|[yaw, pitch]| Ok([joint(yaw)?, joint(pitch)?]))
            .collect::<Result<_, KinematicsCheckError>>()?,
        tips: m.forearm_tip_links.iter().map(link).collect::<Result<_, _>>()?,
        balls: m.ball_links.iter().map(link).collect::<Result<_, _>>()?,
    })
}

/// The origin of `link` in the base (MCT robot) frame at URDF joint
/// positions `q`.
fn base_from(model: &RobotModel, r: &Resolved, q: &[f64], link: LinkIndex) -> Point3<f64> {
    let world = model.world_from_link(q);
    world[r.base.0].inverse() * world[link.0] * Point3::origin()
}

/// The full URDF joint vector for target joints `config` with the tool at
/// `x`: driven joints set, and for a parallel robot the platform and forearm
/// joints posed (see [`pose_parallel`]). `tool_at_zero` is the tool in the
/// base frame with every joint at 0.
fn pose(model: &RobotModel, r: &Resolved, config: &[f64], x: [f64; 3], tool_at_zero: Point3<f64>) -> Vec<f64> {
    let mut q = vec![0.0; model.joints.len()];
    for (&j, &v) in r.joints.iter().zip(config) {
        q[j.0] = v;
    }
    // The platform's tool lands on the forward kinematics when the URDF's
    // tool offset is the geometry's.
    for (axis, &j) in r.platform.iter().enumerate() {
        q[j.0] = x[axis] - tool_at_zero[axis];
    }
    for (&[yaw, pitch], &ball) in r.forearms.iter().zip(&r.balls) {
        let world = model.world_from_link(&q);
        let joint = model.joint(yaw);
        let elbow = world[joint.parent.0] * joint.parent_from_joint;
        let d: Vector3<f64> = elbow.inverse() * world[ball.0] * Point3::origin() - Point3::origin();
        // Yaw within ±90° (a forearm reaching inward pitches past 90°
        // instead), so the virtual joints never wrap at ±180° while the
        // forearm swings through the vertical plane of its arm.
        let (mut horizontal, mut yaw_x, mut yaw_y) = (d.x.hypot(d.y), d.x, d.y);
        if d.x < 0.0 {
            (horizontal, yaw_x, yaw_y) = (-horizontal, -d.x, -d.y);
        }
        q[yaw.0] = yaw_y.atan2(yaw_x);
        q[pitch.0] = (-d.z).atan2(horizontal);
    }
    q
}

/// The URDF joint positions of a robot whose target joints are at `joints`
/// (J1 first, URDF units: rad or m; geometry lengths in coordinate units of
/// `metres_per_unit` metres): the driven joints, and for a parallel geometry the
/// virtual platform and forearm joints posed from the MCT forward kinematics
/// (the twin uses this to pose the links it cannot simulate as a closed
/// chain).
///
/// # Errors
/// [`KinematicsCheckError`] for a mapping that does not fit the model, and
/// [`KinematicsCheckError::TooFewConfigurations`] with `valid: 0` when the
/// joints have no MCT position.
pub fn pose_parallel(
    model: &RobotModel,
    geometry: &Geometry,
    mapping: &ChainMapping,
    joints: &[f64],
    metres_per_unit: f64,
) -> Result<Vec<f64>, KinematicsCheckError> {
    let r = resolve(model, geometry, mapping)?;
    let mut q3 = [0.0; 3];
    for (q, j) in q3.iter_mut().zip(joints) {
        *q = *j;
    }
    let kinds = geometry.joint_kinds();
    for (i, q) in q3.iter_mut().enumerate() {
        if kinds[i] == MctJointKind::Prismatic {
            *q /= metres_per_unit;
        }
    }
    let x = geometry
        .forward(q3)
        .map_err(|_| KinematicsCheckError::TooFewConfigurations { valid: 0 })?
        .map(|v| v * metres_per_unit);
    let tool_at_zero = base_from(model, &r, &vec![0.0; model.joints.len()], r.tool);
    Ok(pose(
        model,
        &r,
        &joints[..joints.len().min(r.joints.len())],
        x,
        tool_at_zero,
    ))
}

/// The joint configurations tried: a low-discrepancy spread over each mapped
/// joint's URDF limits (±π for a continuous joint).
fn configurations(model: &RobotModel, joints: &[JointIndex]) -> Vec<Vec<f64>> {
    const GOLDEN: f64 = 0.618_033_988_749_894_9;
    const SILVER: f64 = 0.414_213_562_373_095_1;
    (0..CONFIGURATIONS)
        .map(|k| {
            joints
                .iter()
                .enumerate()
                .map(|(i, &j)| {
                    let (lo, hi) = match model.joint(j).limits {
                        Some(l) => (l.lower, l.upper),
                        None => (-std::f64::consts::PI, std::f64::consts::PI),
                    };
                    let f = (0.5 + k as f64 * GOLDEN + i as f64 * SILVER).fract();
                    // Keep clear of the limits themselves (often singular).
                    lo + (0.05 + 0.9 * f) * (hi - lo)
                })
                .collect()
        })
        .collect()
}

/// Checks that `model`, mapped by `mapping`, has the kinematics of
/// `geometry`, whose lengths are in coordinate units of `metres_per_unit`
/// metres (prismatic joints move in those units too).
///
/// # Errors
/// [`KinematicsCheckError`]: a geometry whose axes are not URDF joint
/// positions (articulated dependent, H-bot), an unknown link or joint, a
/// joint of the wrong type, a wrong count, too few valid configurations, or a mismatch above
/// [`TOLERANCE_M`] (the first configuration where one occurs).
pub fn check(
    model: &RobotModel,
    geometry: &Geometry,
    mapping: &ChainMapping,
    metres_per_unit: f64,
) -> Result<CheckReport, KinematicsCheckError> {
    let r = resolve(model, geometry, mapping)?;
    let kinds = geometry.joint_kinds();
    let compared = if geometry.dimension() == 3 || geometry.shares_third_axis() {
        3
    } else {
        2
    };
    let tool_at_zero = base_from(model, &r, &vec![0.0; model.joints.len()], r.tool);
    let mut valid = 0;
    let mut max_deviation_m: f64 = 0.0;
    for config in configurations(model, &r.joints) {
        // URDF joint values (rad, m) → MCT joint values (rad, coordinate units).
        let mut q3 = [0.0; 3];
        for (i, &v) in config.iter().enumerate() {
            q3[i] = if kinds[i] == MctJointKind::Prismatic {
                v / metres_per_unit
            } else {
                v
            };
        }
        let Ok(x) = geometry.forward(q3) else { continue };
        let x = x.map(|v| v * metres_per_unit);
        let q = pose(model, &r, &config, x, tool_at_zero);
        valid += 1;
        let mismatch = |measure, deviation_m: f64| KinematicsCheckError::Mismatch {
            measure,
            deviation_m,
            tolerance_m: TOLERANCE_M,
            configuration: config.clone(),
        };
        let tool = base_from(model, &r, &q, r.tool);
        let d = (0..compared).map(|i| (tool[i] - x[i]).powi(2)).sum::<f64>().sqrt();
        if d.is_nan() || d > TOLERANCE_M {
            return Err(mismatch(Measure::Tool, d));
        }
        max_deviation_m = max_deviation_m.max(d);
        for (arm, (&tip, &ball)) in r.tips.iter().zip(&r.balls).enumerate() {
            let d = (base_from(model, &r, &q, tip) - base_from(model, &r, &q, ball)).norm();
            if d.is_nan() || d > TOLERANCE_M {
                return Err(mismatch(Measure::Forearm { arm: arm + 1 }, d));
            }
            max_deviation_m = max_deviation_m.max(d);
        }
    }
    if valid < MIN_CONFIGURATIONS {
        return Err(KinematicsCheckError::TooFewConfigurations { valid });
    }
    Ok(CheckReport {
        configurations: valid,
        max_deviation_m,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use planner::mct::{GeometryKind, GeometryParams};
    use std::path::{Path, PathBuf};

    fn robot_path(name: &str) -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("../scenes/robots/{name}/{name}.urdf"))
    }

    fn text(name: &str) -> String {
        std::fs::read_to_string(robot_path(name)).expect("robot URDF is readable")
    }

    fn model(name: &str, xml: &str) -> RobotModel {
        RobotModel::from_urdf_str(xml, &robot_path(name)).expect("URDF loads")
    }

    fn strings(v: &[&str]) -> Vec<String> {
        v.iter().map(|s| s.to_string()).collect()
    }

    fn scara() -> (Geometry, ChainMapping) {
        let params = GeometryParams {
            link_lengths: [0.35, 0.25, 0.0],
            ..Default::default()
        };
        let mapping = ChainMapping {
            joints: strings(&["j1", "j2", "j3"]),
            base_link: "mct_base".into(),
            tool_link: "tool".into(),
            ..Default::default()
        };
        (
            Geometry::new(GeometryKind::ScaraIndependent, &params, 2).unwrap(),
            mapping,
        )
    }

    fn articulated() -> (Geometry, ChainMapping) {
        let params = GeometryParams {
            link_lengths: [0.4, 0.35, 0.0],
            base_offsets: [0.05, 0.0, 0.4],
            ..Default::default()
        };
        let mapping = ChainMapping {
            joints: strings(&["j1", "j2", "j3"]),
            base_link: "base_link".into(),
            tool_link: "tool".into(),
            ..Default::default()
        };
        (
            Geometry::new(GeometryKind::ArticulatedIndependent, &params, 3).unwrap(),
            mapping,
        )
    }

    fn delta() -> (Geometry, ChainMapping) {
        let params = GeometryParams {
            link_lengths: [0.3, 0.8, 0.0],
            base_offsets: [0.2, 0.0, 0.0],
            end_effector_offsets: [0.05, 0.0, -0.05],
            ..Default::default()
        };
        let mapping = ChainMapping {
            joints: strings(&["j1", "j2", "j3"]),
            base_link: "delta_base".into(),
            tool_link: "tool".into(),
            platform_joints: strings(&["platform_x", "platform_y", "platform_z"]),
            forearm_joints: (1..=3)
                .map(|i| [format!("forearm_{i}_yaw"), format!("forearm_{i}_pitch")])
                .collect(),
            forearm_tip_links: strings(&["forearm_1_tip", "forearm_2_tip", "forearm_3_tip"]),
            ball_links: strings(&["ball_1", "ball_2", "ball_3"]),
        };
        (Geometry::new(GeometryKind::Delta3d, &params, 3).unwrap(), mapping)
    }

    #[test]
    fn the_scene_robots_match_their_mct_geometry() {
        for (name, (geometry, mapping)) in [("scara", scara()), ("articulated", articulated()), ("delta", delta())] {
            let report =
                check(&model(name, &text(name)), &geometry, &mapping, 1.0).unwrap_or_else(|e| panic!("{name}: {e}"));
            assert!(report.configurations >= MIN_CONFIGURATIONS, "{name}: {report:?}");
            assert!(report.max_deviation_m < 1e-9, "{name}: {report:?}");
        }
    }

    /// Replaces exactly one occurrence of `from` in robot `name`'s URDF.
    fn altered(name: &str, from: &str, to: &str) -> RobotModel {
        let xml = text(name);
        assert_eq!(xml.matches(from).count(), 1, "{from}");
        model(name, &xml.replace(from, to))
    }

    #[test]
    fn a_wrong_link_length_is_refused_saying_by_how_much() {
        // SCARA L1 1 cm too long in the URDF: the tool moves by exactly 1 cm.
        let (g, m) = scara();
        let bad = altered(
            "scara",
            r#"<origin xyz="0.35 0 0.05"/>"#,
            r#"<origin xyz="0.36 0 0.05"/>"#,
        );
        match check(&bad, &g, &m, 1.0) {
            Err(KinematicsCheckError::Mismatch {
                measure: Measure::Tool,
                deviation_m,
                ..
            }) => assert!((deviation_m - 0.01).abs() < 1e-9, "{deviation_m}"),
            other => panic!("{other:?}"),
        }
        // Articulated upper arm 2 cm short.
        let (g, m) = articulated();
        let bad = altered(
            "articulated",
            r#"<origin xyz="0.4 0 0"/>"#,
            r#"<origin xyz="0.38 0 0"/>"#,
        );
        match check(&bad, &g, &m, 1.0) {
            Err(e @ KinematicsCheckError::Mismatch { deviation_m, .. }) => {
                assert!((deviation_m - 0.02).abs() < 1e-9, "{e}");
            }
            other => panic!("{other:?}"),
        }
        // Delta upper arm 2 1 cm long (its forearm hangs 1 cm further out),
        // then every forearm 1 cm long: forearm tips miss their balls.
        let (g, m) = delta();
        let xml = text("delta");
        let arm2 = xml.find(r#"<joint name="forearm_2_yaw""#).expect("joint");
        let mut bad = xml.clone();
        let at = arm2 + xml[arm2..].find(r#"<origin xyz="0.3 0 0"/>"#).expect("origin");
        bad.replace_range(
            at..at + r#"<origin xyz="0.3 0 0"/>"#.len(),
            r#"<origin xyz="0.31 0 0"/>"#,
        );
        match check(&model("delta", &bad), &g, &m, 1.0) {
            Err(KinematicsCheckError::Mismatch {
                measure: Measure::Forearm { arm: 2 },
                deviation_m,
                ..
            }) => assert!(deviation_m > 1e-3 && deviation_m < 0.011, "{deviation_m}"),
            other => panic!("{other:?}"),
        }
        let long = xml.replace(r#"<origin xyz="0.8 0 0"/>"#, r#"<origin xyz="0.81 0 0"/>"#);
        assert_eq!(long.matches(r#"<origin xyz="0.81 0 0"/>"#).count(), 3);
        match check(&model("delta", &long), &g, &m, 1.0) {
            Err(KinematicsCheckError::Mismatch {
                measure: Measure::Forearm { arm: 1 },
                deviation_m,
                ..
            }) => assert!((deviation_m - 0.01).abs() < 1e-9, "{deviation_m}"),
            other => panic!("{other:?}"),
        }
        // The MCT side wrong instead: a Delta forearm 1 mm longer than drawn.
        let params = GeometryParams {
            link_lengths: [0.3, 0.801, 0.0],
            base_offsets: [0.2, 0.0, 0.0],
            end_effector_offsets: [0.05, 0.0, -0.05],
            ..Default::default()
        };
        let g = Geometry::new(GeometryKind::Delta3d, &params, 3).unwrap();
        assert!(matches!(
            check(&model("delta", &xml), &g, &m, 1.0),
            Err(KinematicsCheckError::Mismatch { .. })
        ));
    }

    #[test]
    fn a_zero_angle_offset_or_tool_offset_missing_from_the_geometry_is_refused() {
        let (_, m) = articulated();
        let params = GeometryParams {
            link_lengths: [0.4, 0.35, 0.0],
            base_offsets: [0.05, 0.0, 0.4],
            zero_angles_deg: [0.0, 0.0, 1.0],
            ..Default::default()
        };
        let g = Geometry::new(GeometryKind::ArticulatedIndependent, &params, 3).unwrap();
        assert!(matches!(
            check(&model("articulated", &text("articulated")), &g, &m, 1.0),
            Err(KinematicsCheckError::Mismatch {
                measure: Measure::Tool,
                ..
            })
        ));
        let (_, m) = delta();
        let params = GeometryParams {
            link_lengths: [0.3, 0.8, 0.0],
            base_offsets: [0.2, 0.0, 0.0],
            end_effector_offsets: [0.05, 0.0, 0.0],
            ..Default::default()
        };
        let g = Geometry::new(GeometryKind::Delta3d, &params, 3).unwrap();
        assert!(matches!(
            check(&model("delta", &text("delta")), &g, &m, 1.0),
            Err(KinematicsCheckError::Mismatch { .. })
        ));
    }

    /// A URDF written in the test: `joints` are `(name, type, origin xyz,
    /// axis xyz)` chained from `base` to `tool`.
    fn chain_urdf(joints: &[(&str, &str, &str, &str)]) -> RobotModel {
        let mut xml = String::from(r#"<robot name="t"><link name="base"/>"#);
        let mut parent = "base".to_string();
        for (i, (name, kind, xyz, axis)) in joints.iter().enumerate() {
            let child = if i + 1 == joints.len() {
                "tool".to_string()
            } else {
                format!("link{i}")
            };
            xml += &format!(
                r#"<link name="{child}"/><joint name="{name}" type="{kind}"><parent link="{parent}"/><child link="{child}"/><origin xyz="{xyz}"/><axis xyz="{axis}"/><limit lower="-1.5" upper="1.5" effort="1" velocity="1"/></joint>"#
            );
            parent = child;
        }
        xml += "</robot>";
        RobotModel::from_urdf_str(&xml, Path::new("in_memory.urdf")).expect("URDF loads")
    }

    fn chain_mapping(joints: &[&str]) -> ChainMapping {
        ChainMapping {
            joints: strings(joints),
            base_link: "base".into(),
            tool_link: "tool".into(),
            ..Default::default()
        }
    }

    #[test]
    fn a_gantry_and_a_planar_articulated_arm_are_checked_and_a_wrong_offset_is_refused() {
        // Gantry: X, Y, Z slides; base offsets (0.1, 0.2, 0.3) and tool 0.05 below.
        let gantry = |tool_z: &str| {
            chain_urdf(&[
                ("x", "prismatic", "0.1 0.2 0.3", "1 0 0"),
                ("y", "prismatic", "0 0 0", "0 1 0"),
                ("z", "prismatic", &format!("0 0 {tool_z}"), "0 0 1"),
            ])
        };
        let params = GeometryParams {
            base_offsets: [0.1, 0.2, 0.3],
            end_effector_offsets: [0.0, 0.0, -0.05],
            ..Default::default()
        };
        let g = Geometry::new(GeometryKind::CartesianGantry, &params, 3).unwrap();
        let m = chain_mapping(&["x", "y", "z"]);
        let report = check(&gantry("-0.05"), &g, &m, 1.0).unwrap();
        assert_eq!(report.configurations, CONFIGURATIONS);
        assert!(report.max_deviation_m < 1e-12, "{report:?}");
        match check(&gantry("-0.06"), &g, &m, 1.0) {
            Err(KinematicsCheckError::Mismatch { deviation_m, .. }) => {
                assert!((deviation_m - 0.01).abs() < 1e-12, "{deviation_m}")
            }
            other => panic!("{other:?}"),
        }
        // The same gantry in millimetre coordinate units.
        let mm = GeometryParams {
            base_offsets: [100.0, 200.0, 300.0],
            end_effector_offsets: [0.0, 0.0, -50.0],
            ..Default::default()
        };
        let g_mm = Geometry::new(GeometryKind::CartesianGantry, &mm, 3).unwrap();
        assert!(check(&gantry("-0.05"), &g_mm, &m, 1e-3).is_ok());
        // Articulated independent 2D in the base X-Y plane: L1 0.4, L2 0.3,
        // zero angles (10°, -20°) in the URDF's joint origins.
        let planar = |l2: f64| {
            let (z1, z2) = (10f64.to_radians(), (-20f64).to_radians());
            let mut xml = String::from(
                r#"<robot name="p"><link name="base"/><link name="a"/><link name="b"/><link name="tool"/>"#,
            );
            xml += &format!(
                r#"<joint name="j1" type="revolute"><parent link="base"/><child link="a"/><origin xyz="0.05 0.02 0" rpy="0 0 {z1}"/><axis xyz="0 0 1"/><limit lower="-1.5" upper="1.5" effort="1" velocity="1"/></joint>"#
            );
            xml += &format!(
                r#"<joint name="j2" type="revolute"><parent link="a"/><child link="b"/><origin xyz="0.4 0 0" rpy="0 0 {z2}"/><axis xyz="0 0 1"/><limit lower="-1.5" upper="1.5" effort="1" velocity="1"/></joint>"#
            );
            xml += &format!(
                r#"<joint name="t" type="fixed"><parent link="b"/><child link="tool"/><origin xyz="{l2} 0 0"/></joint></robot>"#
            );
            RobotModel::from_urdf_str(&xml, Path::new("planar.urdf")).expect("URDF loads")
        };
        let params = GeometryParams {
            link_lengths: [0.4, 0.3, 0.0],
            base_offsets: [0.05, 0.02, 0.0],
            zero_angles_deg: [10.0, -20.0, 0.0],
            ..Default::default()
        };
        let g = Geometry::new(GeometryKind::ArticulatedIndependent, &params, 2).unwrap();
        let m = chain_mapping(&["j1", "j2"]);
        let report = check(&planar(0.3), &g, &m, 1.0).unwrap();
        assert!(report.max_deviation_m < 1e-12, "{report:?}");
        match check(&planar(0.31), &g, &m, 1.0) {
            Err(KinematicsCheckError::Mismatch { deviation_m, .. }) => {
                assert!((deviation_m - 0.01).abs() < 1e-12, "{deviation_m}")
            }
            other => panic!("{other:?}"),
        }
    }

    /// A Delta 2D in the base X-Y plane (X2 = the URDF's Y): upper arms at
    /// (±X1b, X2b) pointing ±X at zero and turning down (−Y) for positive
    /// angles, forearms on virtual yaw/pitch joints, the platform on virtual
    /// X and Y slides, balls at ±X1e, the tool X2e above the platform centre.
    /// With `scara`, a SCARA Delta: the arms turn towards +Y (its work space)
    /// and the tool hangs on the shared third axis, a quill `j3` along Z.
    fn delta_2d_urdf(forearm_m: f64, scara: bool) -> RobotModel {
        let (l1, x1b, x2b, x1e, x2e) = (0.3, 0.2, 0.1, 0.05, -0.05);
        let limit = r#"<limit lower="-0.3" upper="1.2" effort="1" velocity="1"/>"#;
        let free = r#"<limit lower="-10" upper="10" effort="1" velocity="1"/>"#;
        let mut xml = String::from(
            r#"<robot name="d2"><link name="base"/><link name="platform"/><link name="px"/><link name="tool"/>"#,
        );
        xml += &format!(
            r#"<joint name="platform_x" type="prismatic"><parent link="base"/><child link="px"/><axis xyz="1 0 0"/>{free}</joint>
<joint name="platform_y" type="prismatic"><parent link="px"/><child link="platform"/><axis xyz="0 1 0"/>{free}</joint>
<joint name="{tool_joint}" type="{tool_kind}"><parent link="platform"/><child link="tool"/><origin xyz="0 {x2e} 0"/><axis xyz="0 0 1"/>{free}</joint>"#,
            tool_joint = if scara { "j3" } else { "tool_mount" },
            tool_kind = if scara { "prismatic" } else { "fixed" },
        );
        let (down, up) = if scara {
            ("0 0 1", "0 0 -1")
        } else {
            ("0 0 -1", "0 0 1")
        };
        for (i, sign, yaw, axis) in [(1, 1.0, 0.0, down), (2, -1.0, std::f64::consts::PI, up)] {
            xml += &format!(
                r#"<link name="arm_{i}"/><link name="fa_{i}_y"/><link name="fa_{i}"/><link name="forearm_{i}_tip"/><link name="ball_{i}"/>
<joint name="j{i}" type="revolute"><parent link="base"/><child link="arm_{i}"/><origin xyz="{x} {x2b} 0" rpy="0 0 {yaw}"/><axis xyz="{axis}"/>{limit}</joint>
<joint name="forearm_{i}_yaw" type="revolute"><parent link="arm_{i}"/><child link="fa_{i}_y"/><origin xyz="{l1} 0 0"/><axis xyz="0 0 1"/>{free}</joint>
<joint name="forearm_{i}_pitch" type="revolute"><parent link="fa_{i}_y"/><child link="fa_{i}"/><axis xyz="0 1 0"/>{free}</joint>
<joint name="forearm_{i}_end" type="fixed"><parent link="fa_{i}"/><child link="forearm_{i}_tip"/><origin xyz="{forearm_m} 0 0"/></joint>
<joint name="ball_{i}_mount" type="fixed"><parent link="platform"/><child link="ball_{i}"/><origin xyz="{b} 0 0"/></joint>"#,
                x = sign * x1b,
                b = sign * x1e,
            );
        }
        xml += "</robot>";
        RobotModel::from_urdf_str(&xml, Path::new("delta_2d.urdf")).expect("URDF loads")
    }

    #[test]
    fn delta_2d_and_scara_delta_are_checked_with_their_virtual_joints_and_a_long_forearm_is_refused() {
        let params = GeometryParams {
            link_lengths: [0.3, 0.8, 0.0],
            base_offsets: [0.2, 0.1, 0.0],
            end_effector_offsets: [0.05, -0.05, 0.0],
            ..Default::default()
        };
        let mapping = |scara: bool| ChainMapping {
            joints: strings(if scara { &["j1", "j2", "j3"] } else { &["j1", "j2"] }),
            base_link: "base".into(),
            tool_link: "tool".into(),
            platform_joints: strings(&["platform_x", "platform_y"]),
            forearm_joints: (1..=2)
                .map(|i| [format!("forearm_{i}_yaw"), format!("forearm_{i}_pitch")])
                .collect(),
            forearm_tip_links: strings(&["forearm_1_tip", "forearm_2_tip"]),
            ball_links: strings(&["ball_1", "ball_2"]),
        };
        for (kind, scara) in [(GeometryKind::Delta2d, false), (GeometryKind::ScaraDelta, true)] {
            let g = Geometry::new(kind, &params, 2).unwrap();
            let m = mapping(scara);
            let report = check(&delta_2d_urdf(0.8, scara), &g, &m, 1.0).unwrap_or_else(|e| panic!("{kind:?}: {e}"));
            assert!(report.configurations >= MIN_CONFIGURATIONS, "{kind:?}: {report:?}");
            assert!(report.max_deviation_m < 1e-9, "{kind:?}: {report:?}");
            match check(&delta_2d_urdf(0.81, scara), &g, &m, 1.0) {
                Err(KinematicsCheckError::Mismatch {
                    measure: Measure::Forearm { arm: 1 },
                    deviation_m,
                    ..
                }) => assert!((deviation_m - 0.01).abs() < 1e-9, "{kind:?}: {deviation_m}"),
                other => panic!("{kind:?}: {other:?}"),
            }
        }
        // Upper arms turning towards +Y (the SCARA Delta's URDF) under the
        // Delta 2D geometry, whose work space is −Y: refused.
        let g = Geometry::new(GeometryKind::Delta2d, &params, 2).unwrap();
        assert!(matches!(
            check(&delta_2d_urdf(0.8, true), &g, &mapping(false), 1.0),
            Err(KinematicsCheckError::Mismatch { .. })
        ));
    }

    /// An articulated dependent robot or an H-bot was reported as a
    /// geometry mismatch (wrong link lengths?) although a URDF tree cannot
    /// express its axes at all.
    #[test]
    fn articulated_dependent_and_hbot_targets_are_refused_as_unsupported() {
        let arm = chain_urdf(&[
            ("j1", "revolute", "0 0 0", "0 0 1"),
            ("j2", "revolute", "0 0 0.4", "0 -1 0"),
            ("j3", "revolute", "0.4 0 0", "0 -1 0"),
        ]);
        let params = GeometryParams {
            link_lengths: [0.4, 0.35, 0.0],
            ..Default::default()
        };
        let g = Geometry::new(GeometryKind::ArticulatedDependent, &params, 3).unwrap();
        assert!(matches!(
            check(&arm, &g, &chain_mapping(&["j1", "j2", "j3"]), 1.0),
            Err(KinematicsCheckError::Unsupported {
                kind: GeometryKind::ArticulatedDependent,
                ..
            })
        ));
        let slides = chain_urdf(&[
            ("x", "prismatic", "0 0 0", "1 0 0"),
            ("y", "prismatic", "0 0 0", "0 1 0"),
        ]);
        let g = Geometry::new(GeometryKind::CartesianHBot, &GeometryParams::default(), 2).unwrap();
        assert!(matches!(
            check(&slides, &g, &chain_mapping(&["x", "y"]), 1.0),
            Err(KinematicsCheckError::Unsupported {
                kind: GeometryKind::CartesianHBot,
                ..
            })
        ));
    }

    #[test]
    fn mapping_errors_name_the_joint_or_link() {
        let (g, mut m) = scara();
        let robot = model("scara", &text("scara"));
        m.tool_link = "gripper".into();
        assert_eq!(
            check(&robot, &g, &m, 1.0),
            Err(KinematicsCheckError::UnknownLink { name: "gripper".into() })
        );
        let (g, mut m) = scara();
        m.joints = strings(&["j1", "j3", "j2"]);
        assert!(matches!(
            check(&robot, &g, &m, 1.0),
            Err(KinematicsCheckError::JointKind { axis: 2, .. })
        ));
        m.joints = strings(&["j1", "j2"]);
        assert!(matches!(
            check(&robot, &g, &m, 1.0),
            Err(KinematicsCheckError::Count {
                what: "joints",
                given: 2,
                needed: 3
            })
        ));
    }
}
