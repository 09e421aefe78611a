//! Riding: a part at rest on a belt (running or standing) moves with the
//! belt instead of being solved.
//!
//! A part resting on a belt, touching nothing else and moving at the
//! belt's velocity, is carried by static friction: its motion is the
//! belt's, and solving its contacts every step only reproduces that (a busy
//! belt's parts are most of the parts world's cost, and rapier never
//! recycles the contacts of a belt, whose contact hook runs every step).
//! Such a part *boards* its belt: it becomes a kinematic body moving at the
//! belt's velocity, with no contacts to solve. It is a dynamic body again
//! (it *alights*) before anything could make it move otherwise:
//! * the belt changes speed faster than friction can follow: the
//!   acceleration the part would need (with the pull of gravity along an
//!   inclined belt) exceeds half of what friction gives, `μ g cos θ`, with
//!   `μ` the lower of the part's and the belt's coefficients;
//! * within the next step the part's footprint (a sphere around it) would
//!   reach the edge or end of the belt's top face;
//! * something other than the belt comes within [`NEAR_M`] of the part's
//!   bounding box (a link, a cylinder, an obstacle, a part that is not
//!   moving with the belt), or any part at all within [`CLOSE_M`]: parts
//!   riding the same belt, or resting on it at its speed, move together
//!   and only count when that close.
//!
//! A part boards when it touches the belt alone (within rapier's 2 cm
//! prediction distance nothing else is near), flat (the contact normal
//! along the belt's) and resting (each contact point within 0.1 mm of
//! touching), with its velocity within [`REST_SPEED_MPS`] of the belt's
//! and its spin under [`REST_SPIN_RADPS`], and none of the conditions
//! above holds. It keeps its pose; its velocity becomes the belt's and its
//! spin zero, which is where the solver was taking it. A gripper that
//! picks a riding part takes it as it takes any other; a sink or a sensor
//! sees it as any other.

use nalgebra::{Isometry3, Point3, Vector3};
use rapier3d_f64::parry::bounding_volume::BoundingVolume;
use rapier3d_f64::prelude::{ColliderHandle, PhysicsWorld, QueryFilter, RigidBodyHandle, RigidBodyType};

use super::conveyor::ConveyorState;
use crate::plant::convert::{pose_from_rapier, vector_from_rapier, vector_to_rapier};

/// What comes this near a riding part's bounding box, unless it is a part
/// moving with the belt, makes the part alight, m. At the default 4 ms
/// parts step, a body approaching at up to 5 m/s (2 cm a step) is seen at
/// least one step before it comes within the 2 cm at which rapier starts
/// solving a contact.
pub const NEAR_M: f64 = 0.05;

/// Any part this near a riding part's bounding box makes it alight, m.
pub const CLOSE_M: f64 = 0.01;

/// A part boards a belt when its velocity is within this of the belt's, m/s.
pub const REST_SPEED_MPS: f64 = 1e-3;

/// … and its angular speed under this, rad/s.
pub const REST_SPIN_RADPS: f64 = 1e-2;

/// A part boards only when each of its contact points with the belt is
/// within this of touching, m (a part at rest sinks a few 10 µm in).
const TOUCH_M: f64 = 1e-4;

/// The share of the friction limit a belt's acceleration may use while
/// its parts ride.
const FRICTION_SHARE: f64 = 0.5;

/// A part body's `user_data`: this bit, and in the low bits its belt's
/// index + 1 while it rides (0 while it does not).
pub(super) const PART_BODY: u128 = 1 << 64;

/// Gravity in the parts world, m/s².
const GRAVITY: Vector3<f64> = Vector3::new(0.0, 0.0, -9.81);

/// A belt's box, for riding.
pub(super) struct BeltBox {
    pub(super) collider: ColliderHandle,
    pub(super) world_from_belt: Isometry3<f64>,
    /// Half its size along the belt's x, y and z, m.
    pub(super) half_m: Vector3<f64>,
    pub(super) friction: f64,
    /// Parts may ride it (the conveyor's `ride`).
    pub(super) ride: bool,
}

/// A part that may ride: its body (dynamic or riding), its friction and
/// the radius of a sphere about its origin that holds it.
pub(super) struct Rider {
    pub(super) body: RigidBodyHandle,
    pub(super) friction: f64,
    pub(super) radius_m: f64,
}

/// Before a step of `dt`, the belts' velocities for it set (`conveyors`,
/// by the same index as `belts`): a riding part follows its belt or
/// alights; a resting one boards.
pub(super) fn update(world: &mut PhysicsWorld, belts: &[BeltBox], conveyors: &[ConveyorState], part: &Rider, dt: f64) {
    match riding_of(world.bodies[part.body].user_data) {
        Some(b) => {
            if !keeps_riding(world, belts, conveyors, part, b, dt) {
                set_riding(world, part.body, None);
                world.bodies[part.body].set_body_type(RigidBodyType::Dynamic, true);
            }
        }
        None => {
            if let Some(b) = at_rest_on(world, belts, conveyors, part.body)
                && keeps_riding(world, belts, conveyors, part, b, dt)
            {
                let body = &mut world.bodies[part.body];
                body.set_body_type(RigidBodyType::KinematicVelocityBased, true);
                body.set_angvel(vector_to_rapier(&Vector3::zeros()), true);
                set_riding(world, part.body, Some(b));
            }
        }
    }
}

/// Whether `body` rides a belt.
pub(super) fn rides(world: &PhysicsWorld, body: RigidBodyHandle) -> bool {
    riding_of(world.bodies[body].user_data).is_some()
}

/// A part a gripper holds rides nothing (the gripper moves its body).
pub(super) fn forget(world: &mut PhysicsWorld, body: RigidBodyHandle) {
    set_riding(world, body, None);
}

/// The belt `body` (dynamic) rests on, flat and at the belt's last step's
/// velocity, touching nothing else.
fn at_rest_on(
    world: &PhysicsWorld,
    belts: &[BeltBox],
    conveyors: &[ConveyorState],
    body: RigidBodyHandle,
) -> Option<usize> {
    let rb = &world.bodies[body];
    if !rb.is_dynamic() {
        return None;
    }
    let collider = *rb.colliders().first()?;
    let mut on = None;
    for pair in world.narrow_phase.contact_pairs_with(collider) {
        if !pair.has_any_active_contact() {
            continue;
        }
        let other = if pair.collider1 == collider {
            pair.collider2
        } else {
            pair.collider1
        };
        let b = belts.iter().position(|b| b.collider == other)?;
        if on.is_some() || !belts[b].ride {
            return None;
        }
        let up = belts[b].world_from_belt.rotation * Vector3::z();
        let touching = pair.manifolds().iter().filter(|m| !m.data.solver_contacts.is_empty());
        let flat = touching
            .clone()
            .all(|m| vector_from_rapier(m.data.normal).dot(&up).abs() > 0.999);
        let resting = touching.flat_map(|m| m.points.iter()).all(|p| p.dist <= TOUCH_M);
        if !(flat && resting) {
            return None;
        }
        on = Some(b);
    }
    let b = on?;
    let v = vector_from_rapier(rb.linvel());
    let w = vector_from_rapier(rb.angvel());
    ((v - conveyors[b].previous_velocity_mps()).norm() < REST_SPEED_MPS && w.norm() < REST_SPIN_RADPS).then_some(b)
}

/// Whether `part`, moving with belt `b` over the last step, rides it
/// through the next; if so its velocity becomes the belt's.
fn keeps_riding(
    world: &mut PhysicsWorld,
    belts: &[BeltBox],
    conveyors: &[ConveyorState],
    part: &Rider,
    b: usize,
    dt: f64,
) -> bool {
    let belt = &belts[b];
    let (before, now) = (conveyors[b].previous_velocity_mps(), conveyors[b].velocity_mps());
    let up = belt.world_from_belt.rotation * Vector3::z();
    let mu = belt.friction.min(part.friction);
    let gravity_along = GRAVITY - up * up.dot(&GRAVITY);
    let needed = (now - before) / dt - gravity_along;
    let grip = FRICTION_SHARE * mu * (-up.dot(&GRAVITY)).max(0.0);
    if needed.norm() > grip {
        return false;
    }
    let at = pose_from_rapier(world.bodies[part.body].position());
    let centre = belt
        .world_from_belt
        .inverse_transform_point(&Point3::from(at.translation.vector));
    let reach = part.radius_m + now.norm() * dt;
    if centre.z <= belt.half_m.z || centre.x.abs() + reach > belt.half_m.x || centre.y.abs() + reach > belt.half_m.y {
        return false;
    }
    if near(world, belts[b].collider, before, part.body, b) {
        return false;
    }
    world.bodies[part.body].set_linvel(vector_to_rapier(&now), true);
    true
}

/// Whether something other than belt `b` (its collider, its velocity over
/// the last step) and the parts moving with it comes near `body`.
fn near(world: &PhysicsWorld, belt: ColliderHandle, velocity: Vector3<f64>, body: RigidBodyHandle, b: usize) -> bool {
    let Some(&collider) = world.bodies[body].colliders().first() else {
        return false;
    };
    let aabb = world.colliders[collider].compute_aabb();
    let wide = aabb.loosened(NEAR_M);
    let close = aabb.loosened(CLOSE_M);
    let filter = QueryFilter::default().exclude_collider(collider);
    world.intersect_aabb_conservative(wide, filter).any(|(h, co)| {
        if h == belt {
            return false;
        }
        let other_aabb = co.compute_aabb();
        if !other_aabb.intersects(&wide) {
            return false;
        }
        let moving_along = co.parent().is_some_and(|p| {
            let other = &world.bodies[p];
            if other.user_data & PART_BODY == 0 {
                return false;
            }
            match riding_of(other.user_data) {
                Some(r) => r == b,
                None => {
                    other.is_dynamic()
                        && (vector_from_rapier(other.linvel()) - velocity).norm() < REST_SPEED_MPS
                        && vector_from_rapier(other.angvel()).norm() < REST_SPIN_RADPS
                }
            }
        });
        !moving_along || other_aabb.intersects(&close)
    })
}

fn set_riding(world: &mut PhysicsWorld, body: RigidBodyHandle, belt: Option<usize>) {
    world.bodies[body].user_data = PART_BODY | belt.map_or(0, |b| b as u128 + 1);
}

/// The belt a part body's `user_data` says it rides.
fn riding_of(user_data: u128) -> Option<usize> {
    match user_data & !PART_BODY {
        0 => None,
        b => Some(b as usize - 1),
    }
}
