//! Servo drives: the cascaded loops of a CIP servo drive, as the Logix
//! `AXIS_CIP_DRIVE` attributes name them, closed at every physics substep
//! on the joint's measured position and velocity.
//!
//! ```text
//!   position loop (P + optional I)          velocity loop (PI)          torque
//!   e = p* − p                              ev = v_ref − v
//!   v_ref = Kp·(e + ωpi·∫e) + Kvff·v*  →   τ = J·(Kv·(ev + ωvi·∫ev) + Kaff·a*)  → clamp to the torque limits
//! ```
//!
//! * `Kp = 2π·PositionLoopBandwidth`, `ωpi = 2π·PositionIntegratorBandwidth`,
//!   `Kv = 2π·VelocityLoopBandwidth`, `ωvi = 2π·VelocityIntegratorBandwidth`
//!   (all in Hz), `Kvff`, `Kaff` the feed-forward gains in percent,
//!   `J` the `SystemInertia` (kg·m² or kg), `p*`, `v*`, `a*` the command.
//! * The torque is clamped to `[TorqueLimitNegative, TorqueLimitPositive]`
//!   (N·m or N: the twin has no motor catalogue to express them in % of a
//!   rated torque). The velocity integrator does not wind up while the
//!   torque is clamped in the direction it would push.
//! * A command the torque cannot follow — a step far larger than the
//!   torque limits can stop within the position loop's reach — makes the
//!   cascade overshoot and, for steps of about a radian on a 20 Hz position
//!   loop, oscillate, as a real drive's would. The planner's commands are
//!   profiled and never step; a following error beyond
//!   `position_error_tolerance` faults the axis first.
//! * Defaults ([`ServoGains::default`]): velocity loop 80 Hz with a 15 Hz
//!   integrator, position loop 20 Hz, no position integrator, 100 % velocity
//!   and acceleration feed-forward, the torque limits of the URDF joint's
//!   `effort`, and the inertia the joint moves in the current pose
//!   (recomputed every coarse update, so the loops keep their bandwidths
//!   as the arm folds and stretches; a fixed `SystemInertia` turns that
//!   off). The velocity integrator
//!   carries a gravity load, so a loaded arm holds its position with no
//!   standstill error. The loops run explicitly at the physics substep:
//!   keep `2π·VelocityLoopBandwidth · substep` well below 1 (80 Hz at a
//!   0.25 ms substep is 0.13).

use std::f64::consts::TAU;

pub use crate::scene::ServoGains;

/// What the loop follows over one substep: the command position at its
/// start, its velocity and acceleration (joint SI units).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Setpoint {
    /// Position, rad or m.
    pub position: f64,
    /// Velocity, rad/s or m/s.
    pub velocity: f64,
    /// Acceleration, rad/s² or m/s².
    pub acceleration: f64,
}

/// One drive's loops and their state.
#[derive(Debug, Clone, PartialEq)]
pub struct ServoLoop {
    gains: ServoGains,
    inertia: f64,
    position_integral: f64,
    velocity_integral: f64,
    torque: f64,
    peak_torque: f64,
}

impl ServoLoop {
    /// A drive with `gains` moving `inertia` (kg·m² or kg, > 0).
    pub fn new(gains: ServoGains, inertia: f64) -> Self {
        Self {
            gains,
            inertia,
            position_integral: 0.0,
            velocity_integral: 0.0,
            torque: 0.0,
            peak_torque: 0.0,
        }
    }

    /// Changes the gains and limits (an SSV of a drive attribute); the
    /// integrators keep what they hold.
    pub fn set_gains(&mut self, gains: ServoGains) {
        self.gains = gains;
    }

    /// Changes the inertia the loops scale by (kg·m² or kg, > 0).
    pub fn set_inertia(&mut self, inertia: f64) {
        self.inertia = inertia;
    }

    /// The torque (N·m or N) of the last [`ServoLoop::torque`] (0 after a
    /// reset).
    pub fn last_torque(&self) -> f64 {
        self.torque
    }

    /// The holding torque of the joint's brake: the larger of the drive's
    /// torque limits (`f64::MAX` without limits).
    pub fn brake_torque(&self) -> f64 {
        let hi = self.gains.torque_limit_positive.map(f64::abs);
        let lo = self.gains.torque_limit_negative.map(f64::abs);
        match (hi, lo) {
            (Some(a), Some(b)) => a.max(b),
            (Some(a), None) | (None, Some(a)) => a,
            (None, None) => f64::MAX,
        }
    }

    /// The largest |torque| since the loop was made (resets do not clear
    /// it).
    pub fn peak_torque(&self) -> f64 {
        self.peak_torque
    }

    /// The drive is disabled: the integrators and the torque are cleared,
    /// so an enable starts from nothing stored.
    pub fn reset(&mut self) {
        self.position_integral = 0.0;
        self.velocity_integral = 0.0;
        self.torque = 0.0;
    }

    /// The torque for one substep of `dt_s` seconds, from the joint's
    /// measured position `q` and velocity `qd`.
    pub fn torque(&mut self, sp: Setpoint, q: f64, qd: f64, dt_s: f64) -> f64 {
        let g = &self.gains;
        let kp = TAU * g.position_loop_bandwidth_hz;
        let kpi = TAU * g.position_integrator_bandwidth_hz;
        let kv = TAU * g.velocity_loop_bandwidth_hz;
        let kvi = TAU * g.velocity_integrator_bandwidth_hz;
        let e = sp.position - q;
        if kpi > 0.0 {
            self.position_integral += e * dt_s;
        }
        let v_ref = kp * (e + kpi * self.position_integral) + g.velocity_feedforward_gain_pct / 100.0 * sp.velocity;
        let ev = v_ref - qd;
        let integral = if kvi > 0.0 {
            self.velocity_integral + ev * dt_s
        } else {
            0.0
        };
        let aff = g.acceleration_feedforward_gain_pct / 100.0 * sp.acceleration;
        let wanted = self.inertia * (kv * (ev + kvi * integral) + aff);
        let hi = g.torque_limit_positive.unwrap_or(f64::INFINITY);
        let lo = g.torque_limit_negative.unwrap_or(f64::NEG_INFINITY);
        let torque = wanted.clamp(lo, hi);
        // Anti-windup: integrate unless the clamp holds the push back.
        let clamped_up = wanted > hi && ev > 0.0;
        let clamped_down = wanted < lo && ev < 0.0;
        if !(clamped_up || clamped_down) {
            self.velocity_integral = integral;
        }
        self.torque = if torque.is_finite() { torque } else { 0.0 };
        self.peak_torque = self.peak_torque.max(self.torque.abs());
        self.torque
    }
}

/// The inertia joint `joint` moves with the links at `world_from_link`
/// (every link of `model`, in its order) (kg·m² about a
/// revolute axis, kg along a prismatic one): every link beyond the joint,
/// its inertia about the axis plus its mass times its centre's squared
/// distance from the axis. A link without `<inertial>` counts with
/// `default_mass_kg` and the inertia of a solid sphere of `default_radius_m`
/// (as the physics gives it).
pub fn joint_inertia(
    model: &super::urdf::RobotModel,
    joint: usize,
    world_from_link: &[nalgebra::Isometry3<f64>],
    default_mass_kg: f64,
    default_radius_m: f64,
) -> f64 {
    use nalgebra::{Matrix3, Vector3};
    let j = &model.joints[joint];
    let child = j.child.0;
    let world_from_child = world_from_link[child];
    let axis = world_from_child.rotation * j.axis.into_inner();
    let origin = world_from_child.translation.vector;
    let prismatic = j.kind == super::urdf::JointKind::Prismatic;
    let mut total = 0.0;
    let mut stack = vec![child];
    while let Some(l) = stack.pop() {
        let link = &model.links[l];
        stack.extend(link.child_joints.iter().map(|c| model.joints[c.0].child.0));
        let (mass, com, inertia) = match &link.inertial {
            Some(i) => {
                let r = i.link_from_inertial.rotation.to_rotation_matrix();
                (
                    i.mass_kg,
                    i.link_from_inertial.translation.vector,
                    r.matrix() * i.inertia_kgm2 * r.matrix().transpose(),
                )
            }
            None => (
                default_mass_kg,
                Vector3::zeros(),
                Matrix3::identity() * (0.4 * default_mass_kg * default_radius_m * default_radius_m),
            ),
        };
        if prismatic {
            total += mass;
            continue;
        }
        let pose = world_from_link[l];
        let r = pose.rotation.to_rotation_matrix();
        let world_inertia = r.matrix() * inertia * r.matrix().transpose();
        let c = pose * nalgebra::Point3::from(com) - nalgebra::Point3::from(origin);
        let off_axis = c - axis * axis.dot(&c);
        total += axis.dot(&(world_inertia * axis)) + mass * off_axis.norm_squared();
    }
    total
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A rigid inertia under a constant load torque, integrated exactly at
    /// the loop's rate: the loop holds it with no standstill error, and
    /// tracks a ramp with its feed-forward.
    fn simulate(gains: ServoGains, load: f64, target: impl Fn(f64) -> Setpoint, seconds: f64) -> (f64, f64, f64) {
        let j = 2.0;
        let dt = 0.000_25;
        let mut l = ServoLoop::new(gains, j);
        let (mut q, mut qd, mut peak) = (0.0f64, 0.0f64, 0.0f64);
        let n = (seconds / dt) as usize;
        for k in 0..n {
            let sp = target(k as f64 * dt);
            let tau = l.torque(sp, q, qd, dt);
            peak = peak.max(tau.abs());
            qd += (tau + load) / j * dt;
            q += qd * dt;
        }
        (q, qd, peak)
    }

    #[test]
    fn a_gravity_load_is_held_with_no_standstill_error() {
        let (q, qd, _) = simulate(ServoGains::default(), -150.0, |_| Setpoint::default(), 2.0);
        assert!(q.abs() < 1e-6 && qd.abs() < 1e-5, "q {q} qd {qd}");
        // Without the velocity integrator a P-P cascade leaves an error
        // of load / (J·Kv·Kp).
        let p_only = ServoGains {
            velocity_integrator_bandwidth_hz: 0.0,
            ..ServoGains::default()
        };
        let (q, _, _) = simulate(p_only, -150.0, |_| Setpoint::default(), 2.0);
        let expected = -150.0 / (2.0 * TAU * 80.0 * TAU * 20.0);
        assert!(
            (q - expected).abs() < 1e-6 * expected.abs().max(1.0),
            "{q} vs {expected}"
        );
    }

    #[test]
    fn the_torque_never_leaves_its_limits_and_the_integrator_does_not_wind_up() {
        let gains = ServoGains {
            torque_limit_positive: Some(50.0),
            torque_limit_negative: Some(-40.0),
            ..ServoGains::default()
        };
        // A step of 0.1 rad: the loops ask for more than 50 N·m for a while
        // (the clamp binds), then the axis settles on the step: the
        // integrator has not wound up.
        let step = |_| Setpoint {
            position: 0.1,
            ..Setpoint::default()
        };
        let (q, qd, peak) = simulate(gains, 0.0, step, 3.0);
        assert_eq!(peak, 50.0);
        assert!((q - 0.1).abs() < 1e-6 && qd.abs() < 1e-5, "{q} {qd}");
    }

    #[test]
    fn feed_forward_tracks_a_ramp_closely() {
        let ramp = |t: f64| Setpoint {
            position: 0.5 * t,
            velocity: 0.5,
            acceleration: 0.0,
        };
        let (q, qd, _) = simulate(ServoGains::default(), 0.0, ramp, 1.0);
        // The last substep integrates to t = 1 s.
        assert!((q - 0.5).abs() < 1e-4, "{q}");
        assert!((qd - 0.5).abs() < 1e-3);
    }
}
