//! What the plant keeps for collision checking: the model, the events so
//! far, the clearances and the pre-flight predictions.

use super::super::collision::monitor::Monitor;
use super::super::collision::sweep::PredictedCollision;
use super::super::collision::{CheckResult, CollisionModel, CollisionModelError};
use super::super::urdf::RobotModel;
use crate::scene::CollisionSettings;
use serde::Serialize;

/// A pre-flight sweep that predicted a collision.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Prediction {
    /// The instance (MC_MoveModulo) or `MOTION_INSTRUCTION` tag (MCLM,
    /// MCCM) whose move was swept.
    pub instance: String,
    /// Time the move started (the update it became Active), s.
    pub started_s: f64,
    /// What the sweep found; `parameter` is in axis units travelled
    /// (MC_MoveModulo) or coordinate units of path length (MCLM, MCCM).
    pub collision: PredictedCollision,
    /// Simulated time at which the plan reaches the collision, s
    /// (`started_s + collision.time_s`).
    pub predicted_at_s: f64,
    /// Whether the move was rejected.
    pub rejected: bool,
    /// Set when the finding is not a collision but a point of the path
    /// that the coordinate transform (MCT) cannot reach (out of reach,
    /// singular, beyond a joint's soft travel limit): why. `collision.a` is
    /// then the transform's target system, `collision.b` its source,
    /// `collision.parameter` the first unreachable path length and
    /// `depth_m` 0.
    pub out_of_reach: Option<String>,
}

pub(crate) struct CollideState {
    pub(super) settings: CollisionSettings,
    pub(super) model: CollisionModel,
    pub(super) monitor: Monitor,
    pub(super) last: CheckResult,
    pub(super) clearance_in_update: Vec<f64>,
    pub(super) min_clearance: Vec<f64>,
    pub(super) previous_active: Vec<bool>,
    pub(super) predictions: Vec<Prediction>,
    pub(super) abort: bool,
    /// The link poses at the last live check: where the continuous
    /// detection sweeps from.
    pub(super) previous: Option<Vec<nalgebra::Isometry3<f64>>>,
}

impl CollideState {
    pub(crate) fn new(
        twin_model: &RobotModel,
        scene: &crate::scene::Scene,
    ) -> Option<Result<Self, CollisionModelError>> {
        let settings = scene.collision.clone()?;
        Some(
            CollisionModel::new(twin_model, &scene.obstacles, &settings).map(|model| {
                let n = model.body_names().len();
                CollideState {
                    settings,
                    model,
                    monitor: Monitor::default(),
                    last: CheckResult {
                        contacts: Vec::new(),
                        clearance_m: vec![f64::INFINITY; n],
                    },
                    clearance_in_update: vec![f64::INFINITY; n],
                    min_clearance: vec![f64::INFINITY; n],
                    previous_active: Vec::new(),
                    predictions: Vec::new(),
                    abort: false,
                    previous: None,
                }
            }),
        )
    }
}
