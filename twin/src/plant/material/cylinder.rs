//! A pneumatic cylinder: a kinematic box that strokes along its local +x
//! at a constant speed (`stroke_m` in `extend_ms`, back in `retract_ms`).
//! Single-acting (no `retract` output): it extends while `extend` is on
//! and the spring returns it otherwise. Double-acting: `extend` alone
//! extends, `retract` alone retracts, neither or both hold it where it is
//! (a 5/3 closed-centre valve). A `stalled` cylinder stands still.

use nalgebra::{Isometry3, Translation3, Vector3};

use crate::scene::{Cylinder, DeviceFault, FaultKind};

/// A cylinder's state.
#[derive(Debug, Clone)]
pub struct CylinderState {
    world_from_retracted: Isometry3<f64>,
    direction: Vector3<f64>,
    stroke_m: f64,
    extend_mps: f64,
    retract_mps: f64,
    spring_return: bool,
    faults: Vec<DeviceFault>,
    extend: bool,
    retract: bool,
    /// Travel from the retracted end, m.
    position_m: f64,
}

/// How near an end a cylinder's reed switch closes, m.
const END_SWITCH_M: f64 = 1e-4;

impl CylinderState {
    pub(super) fn new(c: &Cylinder, world_from_retracted: Isometry3<f64>) -> CylinderState {
        CylinderState {
            direction: world_from_retracted.rotation * Vector3::x(),
            world_from_retracted,
            stroke_m: c.stroke_m,
            extend_mps: c.stroke_m / c.extend_s,
            retract_mps: c.stroke_m / c.retract_s,
            spring_return: c.retract.is_none(),
            faults: c.faults.clone(),
            extend: false,
            retract: false,
            position_m: 0.0,
        }
    }

    /// The valve's outputs.
    pub fn set_valve(&mut self, extend: bool, retract: bool) {
        self.extend = extend;
        self.retract = retract;
    }

    /// One step of `dt` from `t`.
    pub(super) fn advance(&mut self, t: f64, dt: f64) {
        if DeviceFault::active(&self.faults, FaultKind::Stalled, t) {
            return;
        }
        let outward = if self.spring_return {
            Some(self.extend)
        } else {
            match (self.extend, self.retract) {
                (true, false) => Some(true),
                (false, true) => Some(false),
                _ => None,
            }
        };
        match outward {
            Some(true) => self.position_m = (self.position_m + self.extend_mps * dt).min(self.stroke_m),
            Some(false) => self.position_m = (self.position_m - self.retract_mps * dt).max(0.0),
            None => {}
        }
    }

    /// The box's pose now.
    #[must_use]
    pub fn world_from_box(&self) -> Isometry3<f64> {
        Translation3::from(self.direction * self.position_m) * self.world_from_retracted
    }

    /// Travel from the retracted end, m.
    #[must_use]
    pub fn position_m(&self) -> f64 {
        self.position_m
    }

    /// At the extended end (its reed switch).
    #[must_use]
    pub fn extended(&self) -> bool {
        self.position_m >= self.stroke_m - END_SWITCH_M
    }

    /// At the retracted end.
    #[must_use]
    pub fn retracted(&self) -> bool {
        self.position_m <= END_SWITCH_M
    }
}
