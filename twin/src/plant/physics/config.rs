//! What a [`RobotSim`](super::RobotSim) is built from — the options, the
//! drives — and why building one fails.

use rapier3d_f64::prelude::Group;

use crate::plant::servo_drive::ServoGains;

/// The collision group every robot link is a member of and filters out.
pub(super) const ROBOT_GROUP: Group = Group::GROUP_32;
/// Radius (m) of the solid sphere whose inertia a link without `<inertial>` gets.
pub(super) const DEFAULT_INERTIA_RADIUS_M: f64 = 0.05;

/// A motor on one joint: gains of rapier's acceleration-based motor model.
#[derive(Debug, Clone, PartialEq)]
pub struct JointDrive {
    /// Name of the URDF joint (revolute, continuous or prismatic).
    pub joint: String,
    /// Position gain in 1/s² (acceleration per unit of position error).
    pub stiffness: f64,
    /// Velocity gain in 1/s (acceleration per unit of velocity error).
    pub damping: f64,
    /// Largest motor force in N·m (rotary) or N (linear); `None` for no limit.
    pub max_force: Option<f64>,
    /// A servo drive's loops (`plant/servo_drive.rs`): the joint is driven
    /// by their torque, and `stiffness`/`damping` are only its holding
    /// brake's; `None` for the spring drive above.
    pub servo: Option<ServoGains>,
}

impl JointDrive {
    /// A critically damped drive with natural frequency `natural_frequency_hz`:
    /// `stiffness = ω²`, `damping = 2ω` with `ω = 2π · natural_frequency_hz`,
    /// no force limit. Keep the frequency well below `1 / (2 · step_s)`.
    ///
    /// # Examples
    /// ```
    /// let drive = twin::plant::physics::JointDrive::critically_damped("platter_joint", 10.0);
    /// assert!((drive.damping - 4.0 * std::f64::consts::PI * 10.0).abs() < 1e-12);
    /// ```
    pub fn critically_damped(joint: &str, natural_frequency_hz: f64) -> JointDrive {
        let omega = std::f64::consts::TAU * natural_frequency_hz;
        JointDrive {
            joint: joint.to_string(),
            stiffness: omega * omega,
            damping: 2.0 * omega,
            max_force: None,
            servo: None,
        }
    }

    /// A servo drive with `gains`; its holding brake (used while the drive
    /// is off and braked) is a critically damped 30 Hz hold.
    pub fn servo(joint: &str, gains: ServoGains) -> JointDrive {
        JointDrive {
            servo: Some(gains),
            ..JointDrive::critically_damped(joint, BRAKE_HZ)
        }
    }
}

/// Natural frequency of a servo-driven joint's holding brake, Hz.
const BRAKE_HZ: f64 = 30.0;

/// World and solver settings for a [`RobotSim`](super::RobotSim).
#[derive(Debug, Clone, PartialEq)]
pub struct PhysicsOptions {
    /// Length of one [`RobotSim::step`](super::RobotSim::step) in seconds (default: 0.002, a 500 Hz servo cycle).
    pub step_s: f64,
    /// Gravity in the world frame, m/s² (default: `[0, 0, -9.81]`, URDF is Z-up).
    pub gravity_mps2: [f64; 3],
    /// Mass given to links without `<inertial>`, kg (default: 0.1).
    pub default_link_mass_kg: f64,
    /// rapier steps per [`RobotSim::step`](super::RobotSim::step), each `step_s / substeps` long
    /// with one solver iteration (default: 4, matching rapier's default of
    /// four TGS substeps). Substepping here rather than inside rapier lets
    /// each substep's motor target advance along the setpoint velocity;
    /// rapier's internal substeps reuse one target and lag by several mrad.
    pub substeps: usize,
    /// Joints whose child links (and everything below them) are *posed*
    /// rather than simulated (default: none): kinematic bodies placed every
    /// substep where their parents and the joints' drive setpoints put
    /// them, outside the multibody. A parallel robot's virtual joints
    /// (platform, forearms), which only follow the arms' kinematics, are
    /// posed: the multibody keeps the arms' few degrees of freedom, and the
    /// arms' drives do not carry the linkage's inertia.
    pub posed_joints: Vec<String>,
}

impl Default for PhysicsOptions {
    fn default() -> Self {
        PhysicsOptions {
            step_s: 0.002,
            gravity_mps2: [0.0, 0.0, -9.81],
            default_link_mass_kg: 0.1,
            substeps: 4,
            posed_joints: Vec::new(),
        }
    }
}

/// Why a [`RobotSim`](super::RobotSim) could not be built.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum PhysicsError {
    /// A drive or initial position names a joint the model does not have.
    #[error("unknown joint {joint}")]
    UnknownJoint {
        /// The name as given.
        joint: String,
    },
    /// A drive or initial position names a fixed joint.
    #[error("joint {joint} is fixed and cannot be driven or positioned")]
    FixedJoint {
        /// The joint.
        joint: String,
    },
    /// Two drives name the same joint.
    #[error("joint {joint} has more than one drive")]
    DuplicateDrive {
        /// The joint.
        joint: String,
    },
    /// A drive gain is negative or not finite, or `max_force` is not positive.
    #[error("joint {joint}: invalid drive gains (stiffness {stiffness}, damping {damping}, max force {max_force:?})")]
    InvalidDrive {
        /// The joint.
        joint: String,
        /// The given stiffness, 1/s².
        stiffness: f64,
        /// The given damping, 1/s.
        damping: f64,
        /// The given force limit.
        max_force: Option<f64>,
    },
    /// An option is out of range (non-positive or non-finite step, non-finite
    /// gravity, non-positive default mass, zero substeps).
    #[error("invalid physics option {option}")]
    InvalidOption {
        /// The field of [`PhysicsOptions`].
        option: &'static str,
    },
    /// An initial joint position is not finite.
    #[error("joint {joint}: initial position {position} is not finite")]
    InvalidInitialPosition {
        /// The joint.
        joint: String,
        /// The given position (rad or m).
        position: f64,
    },
    /// A link's collision mesh has no usable convex hull (flat or degenerate).
    #[error("link {link}: collision mesh has no 3-D convex hull")]
    DegenerateCollisionMesh {
        /// The link.
        link: String,
    },
    /// rapier refused to add a joint to the multibody.
    #[error("joint {joint} could not be added to the multibody")]
    Multibody {
        /// The joint.
        joint: String,
    },
}
