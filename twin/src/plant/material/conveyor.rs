//! A conveyor's belt: its speed from an axis or a VFD, its travel for the
//! encoder, and the contact hook that makes the belt carry parts.

use nalgebra::{Isometry3, Vector3};
use rapier3d_f64::math::Vector;
use rapier3d_f64::prelude::{ColliderHandle, ContactModificationContext, ModifiableContacts, PhysicsHooks};

use crate::plant::convert::vector_to_rapier;
use crate::scene::{Conveyor, ConveyorDrive, DeviceFault, FaultKind};

/// A belt's state.
#[derive(Debug, Clone)]
pub struct ConveyorState {
    /// The belt's direction of travel in the world (its local +x).
    direction: Vector3<f64>,
    /// What drives it: an axis index, or a VFD's ramp.
    axis: Option<usize>,
    accel_mps2: f64,
    max_speed_mps: f64,
    faults: Vec<DeviceFault>,
    /// The commanded speed (VFD: from its outputs; axis: its actual
    /// velocity), m/s.
    command_mps: f64,
    /// The belt's speed now, m/s.
    speed_mps: f64,
    /// Its speed over the step before, m/s.
    previous_speed_mps: f64,
    /// The belt's travel since the start, m.
    travel_m: f64,
}

impl ConveyorState {
    pub(super) fn new(c: &Conveyor, world_from_belt: Isometry3<f64>) -> ConveyorState {
        let (axis, accel_mps2, max_speed_mps) = match &c.drive {
            ConveyorDrive::Axis(a) => (Some(*a), f64::INFINITY, f64::INFINITY),
            ConveyorDrive::Vfd(v) => (None, v.accel_mps2, v.max_speed_mps),
        };
        ConveyorState {
            direction: world_from_belt.rotation * Vector3::x(),
            axis,
            accel_mps2,
            max_speed_mps,
            faults: c.faults.clone(),
            command_mps: 0.0,
            speed_mps: 0.0,
            previous_speed_mps: 0.0,
            travel_m: 0.0,
        }
    }

    /// The axis that drives the belt, if any.
    #[must_use]
    pub fn axis(&self) -> Option<usize> {
        self.axis
    }

    /// A VFD's outputs: run, reverse, speed in % of `max_speed_mps`.
    pub fn set_vfd(&mut self, run: bool, reverse: bool, speed_pct: f64) {
        let pct = if speed_pct.is_finite() {
            speed_pct.clamp(0.0, 100.0)
        } else {
            0.0
        };
        let sign = if reverse { -1.0 } else { 1.0 };
        self.command_mps = if run {
            sign * self.max_speed_mps * pct / 100.0
        } else {
            0.0
        };
    }

    /// An axis-driven belt: the axis' actual velocity, m/s.
    pub fn set_axis_speed(&mut self, speed_mps: f64) {
        self.command_mps = if speed_mps.is_finite() { speed_mps } else { 0.0 };
    }

    /// One step of `dt` from `t`: the ramp (a stalled belt stands still),
    /// the travel.
    pub(super) fn advance(&mut self, t: f64, dt: f64) {
        let target = if DeviceFault::active(&self.faults, FaultKind::Stalled, t) {
            self.speed_mps = 0.0;
            0.0
        } else {
            self.command_mps
        };
        let before = self.speed_mps;
        self.previous_speed_mps = before;
        let dv = self.accel_mps2 * dt;
        self.speed_mps = if (target - self.speed_mps).abs() <= dv {
            target
        } else {
            self.speed_mps + dv.copysign(target - self.speed_mps)
        };
        self.travel_m += 0.5 * (before + self.speed_mps) * dt;
    }

    /// The belt's speed now, m/s (negative: backwards).
    #[must_use]
    pub fn speed_mps(&self) -> f64 {
        self.speed_mps
    }

    /// The belt's velocity in the world now, m/s.
    #[must_use]
    pub fn velocity_mps(&self) -> Vector3<f64> {
        self.direction * self.speed_mps
    }

    /// Its velocity over the step before the one [`ConveyorState::advance`]
    /// last set, m/s.
    #[must_use]
    pub fn previous_velocity_mps(&self) -> Vector3<f64> {
        self.direction * self.previous_speed_mps
    }

    /// The belt's travel since the start, m.
    #[must_use]
    pub fn travel_m(&self) -> f64 {
        self.travel_m
    }

    pub(super) fn belt_velocity(&self) -> Vector {
        vector_to_rapier(&self.velocity_mps())
    }
}

/// The contact hook: a part touching a belt is given the belt's velocity
/// as the contact's tangent velocity.
pub(super) struct BeltHooks<'a> {
    pub(super) belts: &'a [(ColliderHandle, Vector)],
}

impl PhysicsHooks for BeltHooks<'_> {
    fn modify_solver_contacts(&self, context: &mut ContactModificationContext) {
        let velocity = |h: ColliderHandle| self.belts.iter().find(|(b, _)| *b == h).map(|(_, v)| *v);
        // rapier's tangent velocity is the first body's surface relative
        // to the second's: a belt first moves its surface forwards.
        let v = match (velocity(context.collider1), velocity(context.collider2)) {
            (Some(v), None) => v,
            (None, Some(v)) => -v,
            _ => return,
        };
        if let ModifiableContacts::Rigid(m) = &mut context.contacts {
            let n = *m.normal;
            let tangent = v - n * n.dot(v);
            for c in m.solver_contacts.iter_mut() {
                c.tangent_velocity = tangent;
            }
        }
    }
}
