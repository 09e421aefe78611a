//! A gripper on a robot link: a vacuum cup or fingers with a TCP.
//!
//! * **Picking.** `grip` on (and `release` off) for `build_up_ms`
//!   (`close_ms` for fingers) engages it; then the part nearest the TCP
//!   within `reach_m` (the distance from the TCP to the part's surface) is
//!   held where it is, never snapped to the TCP: it rides on the link at
//!   the pose it had when picked. Each pick's offset — the part centre's
//!   distance from the TCP's z axis — is recorded (`max_pick_offset_mm`).
//! * **Holding.** A held part is a kinematic body moved with the link; its
//!   mass and inertia are added to the link in the robot's multibody, so
//!   the drives carry it (physics plant).
//! * **Dropping.** When the part's weight plus its inertial force
//!   (m · |a − g|, the acceleration from its motion over the last two
//!   parts steps) exceeds `max_force_n`, or a vacuum gripper loses its
//!   vacuum (`no_vacuum`), the part falls: it is `dropped`. The gripper
//!   picks again only after `grip` went off.
//! * **Placing.** `grip` off (or `release` on) lets go at once: the part
//!   is a dynamic body again, with the velocity it had on the link.

use nalgebra::{Isometry3, Vector3};

use crate::scene::{DeviceFault, FaultKind, Gripper, GripperKind};

/// A gripper's state.
#[derive(Debug, Clone)]
pub struct GripperState {
    /// The link it is on.
    pub link: usize,
    pub(super) link_from_tcp: Isometry3<f64>,
    pub(super) kind: GripperKind,
    pub(super) engage_s: f64,
    pub(super) reach_m: f64,
    pub(super) max_force_n: f64,
    pub(super) faults: Vec<DeviceFault>,
    pub(super) grip: bool,
    pub(super) release: bool,
    /// Since when `grip` has been on (and `release` off), s.
    pub(super) engaged_since: Option<f64>,
    /// The part held and its pose on the link.
    pub(super) held: Option<Held>,
    /// It dropped a part: it picks again only after `grip` went off.
    pub(super) dropped: bool,
}

/// A held part.
#[derive(Debug, Clone, Copy)]
pub(super) struct Held {
    pub(super) part: u64,
    pub(super) link_from_part: Isometry3<f64>,
    /// The part centre's velocity over the last step, m/s (for its
    /// inertial force and its release).
    pub(super) velocity: Vector3<f64>,
    /// Steps it has been held.
    pub(super) steps: u32,
}

impl GripperState {
    pub(super) fn new(g: &Gripper, link: usize, link_from_tcp: Isometry3<f64>) -> GripperState {
        GripperState {
            link,
            link_from_tcp,
            kind: g.kind,
            engage_s: g.engage_s,
            reach_m: g.reach_m,
            max_force_n: g.max_force_n,
            faults: g.faults.clone(),
            grip: false,
            release: false,
            engaged_since: None,
            held: None,
            dropped: false,
        }
    }

    /// The gripper's outputs.
    pub fn set_outputs(&mut self, grip: bool, release: bool) {
        self.grip = grip;
        self.release = release;
        if !grip {
            self.dropped = false;
        }
    }

    /// Whether it has vacuum (or its fingers closed) at `t`.
    pub(super) fn engaged(&self, t: f64) -> bool {
        let no_vacuum = self.kind == GripperKind::Vacuum && DeviceFault::active(&self.faults, FaultKind::NoVacuum, t);
        !no_vacuum && self.grip && !self.release
    }

    /// The held part's id (0: none).
    #[must_use]
    pub fn part(&self) -> u64 {
        self.held.map_or(0, |h| h.part)
    }
}
