//! Material flow: workpieces (parts) as dynamic bodies in a rapier world
//! of their own, the sources that spawn them, the sinks that take them
//! out, the conveyors that carry them.
//!
//! # The parts world
//! Stepped every `parts_step_ms` (default: the coarse update), gravity
//! along world −z. In it:
//! * each part is a dynamic body with its type's shape, mass, friction and
//!   restitution;
//! * the robot's links that have collision shapes are kinematic bodies
//!   placed each step at the pose the robot's own simulation (physics or
//!   kinematic) gave them at the step's end: they push parts, nothing
//!   pushes them;
//! * obstacles and conveyors are fixed.
//!
//! # Conveyors
//! A belt is a fixed box whose contacts are given a tangent velocity
//! (rapier's `SolverContact::tangent_velocity`, set in a contact
//! modification hook): friction drives a part towards the belt's speed,
//! so parts slip when pushed against a stopper and queue behind one
//! another. A part at rest on a belt with nothing near *rides* it
//! (module [`ride`]): it moves with the belt as a kinematic body until
//! something could change that, which spares the solver most of a busy
//! belt's parts. A belt follows a linear axis' actual velocity, or a VFD: the
//! `run` output (with `reverse`) and `speed` (% of `max_speed_mps`), ramped
//! at `accel_mps2`. Its `encoder_tag` counts belt travel at
//! `counts_per_m`, wrapping as a DINT does.
//!
//! # Sources and sinks
//! A source spawns at its times (`every_s`, `at_s`, with seeded jitter),
//! or at each rise of its `on` output, up to `count` parts; a spawn whose
//! part would overlap a part already there waits until the place is free
//! (an occupied source waits). `skip` leaves out the listed spawns (a
//! missing part, for bad-case tests). A part whose centre enters a sink's
//! box is removed as `delivered` or `rejected`; a part 1 m below the
//! lowest surface of the cell (and of z = 0) is `lost`. Part ids are
//! 1, 2, … in spawn order. At most [`MAX_LIVE_PARTS`] parts live at once:
//! past that the sources stop and the summary says so.

mod conveyor;
mod cylinder;
mod gripper;
mod ride;
mod spawn;

pub use conveyor::ConveyorState;
pub use cylinder::CylinderState;
pub use gripper::GripperState;
use nalgebra::Isometry3;
use nalgebra::Vector3;
use rapier3d_f64::math::{Pose, Vector};
use rapier3d_f64::parry::bounding_volume::BoundingVolume;
use rapier3d_f64::parry::shape::SharedShape;
use rapier3d_f64::prelude::{
    ActiveHooks, ColliderBuilder, ColliderHandle, PhysicsWorld, RigidBodyBuilder, RigidBodyHandle, RigidBodyType,
};
use spawn::SourceState;

use crate::plant::collision::{pose_from_xyz_rpy_deg, scene_shape, shape_of};
use crate::plant::convert::pose_to_rapier;
use crate::plant::urdf::RobotModel;
use crate::scene::{MAX_LIVE_PARTS, MeshApproximation, Scene, SinkOutcome, Source};

/// How far below the lowest surface a part is lost, m.
const LOST_BELOW_M: f64 = 1.0;

/// The most part events the summary keeps.
pub const MAX_PART_EVENTS: usize = 1000;

/// A part type's collision shape, built once.
#[derive(Clone)]
pub struct PartShape {
    /// The shape.
    pub shape: SharedShape,
    /// The shape's pose in the part frame (a cylinder turned onto z).
    pub part_from_shape: Pose,
    /// Material (lower case; empty when none is given).
    pub material: String,
    /// The radius of a sphere about the part frame's origin that holds
    /// the shape, m.
    pub radius_m: f64,
}

/// A part in the cell.
#[derive(Debug, Clone)]
pub struct LivePart {
    /// Id: 1, 2, … in spawn order.
    pub id: u64,
    /// Index into the scene's part types.
    pub part_type: usize,
    /// The source that spawned it.
    pub source: usize,
    /// When it was spawned, s.
    pub spawned_s: f64,
    body: RigidBodyHandle,
    /// Its pose at the start of the last step (where it was spawned, for
    /// a part spawned then).
    before: Pose,
}

/// A robot link's body in the parts world.
struct LinkBody {
    link: usize,
    body: RigidBodyHandle,
    /// Its collision shapes, in the link frame.
    shapes: Vec<(Pose, SharedShape)>,
}

/// What happened to a part.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct PartEvent {
    /// When, s.
    pub time_s: f64,
    /// The part's id.
    pub part: u64,
    /// `spawned`, `delivered`, `rejected` or `lost`.
    pub event: &'static str,
    /// The source or sink (empty for `lost`).
    pub at: String,
}

/// The parts' counts over the run.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PartCounts {
    /// Parts spawned.
    pub spawned: u64,
    /// Parts that reached a `delivered` sink.
    pub delivered: u64,
    /// Parts that reached a `rejected` sink.
    pub rejected: u64,
    /// Parts dropped by a gripper.
    pub dropped: u64,
    /// Parts that fell out of the cell.
    pub lost: u64,
    /// Per sink, the parts it took.
    pub per_sink: Vec<u64>,
    /// Sum of the delivered parts' times in the cell, s.
    pub delivered_flow_s: f64,
    /// Whether a source stopped at [`MAX_LIVE_PARTS`].
    pub capped: bool,
    /// The largest pick offset (the part centre's distance from the TCP's
    /// z axis), m (`None`: nothing was picked).
    pub max_pick_offset_m: Option<f64>,
}

/// A fixed sink box.
struct SinkBox {
    world_from_sink: Isometry3<f64>,
    half_m: [f64; 3],
    outcome: SinkOutcome,
    name: String,
}

/// The parts world and its devices.
pub struct Material {
    world: PhysicsWorld,
    step_s: f64,
    shapes: Vec<PartShape>,
    parts: Vec<LivePart>,
    links: Vec<LinkBody>,
    sources: Vec<SourceState>,
    sinks: Vec<SinkBox>,
    conveyors: Vec<ConveyorState>,
    /// Each belt's box, by conveyor index.
    belts: Vec<ride::BeltBox>,
    cylinders: Vec<(CylinderState, RigidBodyHandle)>,
    grippers: Vec<GripperState>,
    /// The scene's sources and part types (what spawns take).
    sources_def: Vec<Source>,
    part_types: Vec<crate::scene::PartType>,
    /// Obstacles' shapes in the world, by obstacle index (for sensors).
    obstacles: Vec<(Pose, SharedShape)>,
    lost_below_z: f64,
    next_id: u64,
    counts: PartCounts,
    events: Vec<PartEvent>,
    time_s: f64,
    /// A pick or a release changed a link's payload.
    payload_changed: bool,
}

impl std::fmt::Debug for Material {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Material")
            .field("parts", &self.parts.len())
            .field("time_s", &self.time_s)
            .finish_non_exhaustive()
    }
}

/// Why the parts world cannot be built.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum MaterialError {
    /// A part type's or obstacle's shape cannot be built.
    #[error("{what}: {source}")]
    Shape {
        /// The part type or obstacle, named.
        what: String,
        /// Why.
        #[source]
        source: crate::plant::collision::CollisionModelError,
    },
    /// A source's part, at its nominal spawn pose, would be inside a fixed
    /// body of the cell (rapier would throw it out).
    #[error(
        "a {part_type} spawned here would be {depth_mm:.1} mm inside {what}; move the source clear of it (a part may touch it)"
    )]
    SpawnsInside {
        /// The source's index.
        source_index: usize,
        /// The part type's name.
        part_type: String,
        /// What it would be inside (`conveyor 'Belt'`).
        what: String,
        /// How deep, mm.
        depth_mm: f64,
    },
    /// A gripper's link is not in the URDF.
    #[error("the URDF has no link '{link}' (links: {known})")]
    UnknownLink {
        /// The gripper's index.
        gripper: usize,
        /// The name given.
        link: String,
        /// The URDF's links.
        known: String,
    },
}

impl Material {
    /// The parts world of `scene`'s cell: its obstacles and belts fixed,
    /// the links of `model` with collision shapes kinematic at `world_from_link`.
    ///
    /// # Errors
    /// [`MaterialError`] when a shape (an STL part type, an obstacle's
    /// mesh) cannot be built.
    pub fn new(
        scene: &Scene,
        model: &RobotModel,
        world_from_link: &[Isometry3<f64>],
    ) -> Result<Material, MaterialError> {
        let cell = &scene.cell;
        let mut world = PhysicsWorld::new();
        world.gravity = Vector::new(0.0, 0.0, -9.81);
        let step_s = cell.parts_step_ms / 1000.0;
        world.integration_parameters.dt = step_s;
        // Two solver iterations: parts resting and sliding on belts and
        // against stoppers settle as well as with rapier's default four
        // (the cell tests' tolerances hold), for about half the solver's
        // time.
        world.integration_parameters.num_solver_iterations = 2;
        // rapier recycles a contact pair's points, normal included, while
        // the pair has moved less than this since they were computed; at
        // its default (5 cm) a part kept the side contact of a stopper that
        // had dropped below the belt and stayed behind it. 1 mm is what
        // parry's own manifold update allows.
        world.integration_parameters.normalized_contact_recycle_distance = 0.001;
        let shapes = cell
            .part_types
            .iter()
            .map(|p| {
                let fail = |source| MaterialError::Shape {
                    what: format!("part type {}", p.name),
                    source,
                };
                let geometry = scene_shape(&p.shape, &p.name).map_err(fail)?;
                let (local, shape) = shape_of(&geometry, MeshApproximation::ConvexHull, &p.name)
                    .map_err(fail)?
                    .ok_or_else(|| {
                        fail(crate::plant::collision::CollisionModelError::DegenerateMesh { body: p.name.clone() })
                    })?;
                let part_from_shape = pose_to_rapier(&local);
                let sphere = shape.compute_bounding_sphere(&part_from_shape);
                Ok(PartShape {
                    radius_m: sphere.center().length() + sphere.radius(),
                    shape,
                    part_from_shape,
                    material: p.material.clone(),
                })
            })
            .collect::<Result<Vec<_>, MaterialError>>()?;
        let mut lowest = 0.0_f64;
        // The cell's fixed bodies (obstacles, belts, cylinders retracted),
        // named, for the spawn check.
        let mut solids: Vec<(String, Pose, SharedShape)> = Vec::new();
        let mut obstacles = Vec::with_capacity(scene.obstacles.len());
        for o in &scene.obstacles {
            let fail = |source| MaterialError::Shape {
                what: format!("obstacle {}", o.name),
                source,
            };
            let geometry = scene_shape(&o.shape, &o.name).map_err(fail)?;
            let Some((local, shape)) = shape_of(&geometry, MeshApproximation::ConvexHull, &o.name).map_err(fail)?
            else {
                continue;
            };
            let pose = pose_to_rapier(&(pose_from_xyz_rpy_deg(o.position_m, o.rpy_deg) * local));
            lowest = lowest.min(shape.compute_aabb(&pose).mins.z);
            world.insert_collider(ColliderBuilder::new(shape.clone()).position(pose), None);
            solids.push((format!("obstacle '{}'", o.name), pose, shape.clone()));
            obstacles.push((pose, shape));
        }
        let mut belts = Vec::with_capacity(cell.conveyors.len());
        let mut conveyors = Vec::with_capacity(cell.conveyors.len());
        for c in &cell.conveyors {
            let world_from_belt = pose_from_xyz_rpy_deg(c.position_m, c.rpy_deg);
            let shape = SharedShape::cuboid(c.size_m[0] / 2.0, c.size_m[1] / 2.0, c.size_m[2] / 2.0);
            let pose = pose_to_rapier(&world_from_belt);
            lowest = lowest.min(shape.compute_aabb(&pose).mins.z);
            solids.push((format!("conveyor '{}'", c.name), pose, shape.clone()));
            let collider = ColliderBuilder::new(shape)
                .position(pose)
                .friction(c.friction)
                .active_hooks(ActiveHooks::MODIFY_SOLVER_CONTACTS);
            belts.push(ride::BeltBox {
                collider: world.insert_collider(collider, None),
                world_from_belt,
                half_m: Vector3::from(c.size_m) / 2.0,
                friction: c.friction,
                ride: c.ride,
            });
            conveyors.push(ConveyorState::new(c, world_from_belt));
        }
        let mut cylinders = Vec::with_capacity(cell.cylinders.len());
        for c in &cell.cylinders {
            let state = CylinderState::new(c, pose_from_xyz_rpy_deg(c.position_m, c.rpy_deg));
            let body = world.insert_body(
                RigidBodyBuilder::kinematic_position_based().pose(pose_to_rapier(&state.world_from_box())),
            );
            let shape = SharedShape::cuboid(c.size_m[0] / 2.0, c.size_m[1] / 2.0, c.size_m[2] / 2.0);
            solids.push((
                format!("cylinder '{}' (retracted)", c.name),
                pose_to_rapier(&state.world_from_box()),
                shape.clone(),
            ));
            world.insert_collider(ColliderBuilder::new(shape), Some(body));
            cylinders.push((state, body));
        }
        spawns_clear(&cell.sources, &cell.part_types, &shapes, &solids)?;
        let mut grippers = Vec::with_capacity(cell.grippers.len());
        for (k, g) in cell.grippers.iter().enumerate() {
            let link =
                model
                    .links
                    .iter()
                    .position(|l| l.name == g.link.0)
                    .ok_or_else(|| MaterialError::UnknownLink {
                        gripper: k,
                        link: g.link.0.clone(),
                        known: model
                            .links
                            .iter()
                            .map(|l| l.name.as_str())
                            .collect::<Vec<_>>()
                            .join(", "),
                    })?;
            grippers.push(GripperState::new(
                g,
                link,
                pose_from_xyz_rpy_deg(g.position_m, g.rpy_deg),
            ));
        }
        let mut links = Vec::new();
        for (l, link) in model.links.iter().enumerate() {
            let mut link_shapes = Vec::new();
            for c in &link.collisions {
                if let Ok(Some((local, shape))) = shape_of(&c.geometry, MeshApproximation::ConvexHull, &link.name) {
                    link_shapes.push((pose_to_rapier(&(c.link_from_collision * local)), shape));
                }
            }
            if link_shapes.is_empty() {
                continue;
            }
            let pose = pose_to_rapier(&world_from_link[l]);
            let body = world.insert_body(RigidBodyBuilder::kinematic_position_based().pose(pose));
            for (local, shape) in &link_shapes {
                world.insert_collider(ColliderBuilder::new(shape.clone()).position(*local), Some(body));
            }
            links.push(LinkBody {
                link: l,
                body,
                shapes: link_shapes,
            });
        }
        let sinks = cell
            .sinks
            .iter()
            .map(|s| SinkBox {
                world_from_sink: pose_from_xyz_rpy_deg(s.position_m, s.rpy_deg),
                half_m: s.size_m.map(|x| x / 2.0),
                outcome: s.outcome,
                name: s.name.clone(),
            })
            .collect();
        let sources = cell
            .sources
            .iter()
            .enumerate()
            .map(|(k, s)| SourceState::new(s, k))
            .collect();
        Ok(Material {
            world,
            step_s,
            shapes,
            parts: Vec::new(),
            links,
            sources,
            sinks,
            conveyors,
            belts,
            cylinders,
            grippers,
            sources_def: cell.sources.clone(),
            part_types: cell.part_types.clone(),
            obstacles,
            lost_below_z: lowest - LOST_BELOW_M,
            next_id: 1,
            counts: PartCounts {
                per_sink: vec![0; cell.sinks.len()],
                ..PartCounts::default()
            },
            events: Vec::new(),
            time_s: 0.0,
            payload_changed: false,
        })
    }

    /// The step, s.
    #[must_use]
    pub fn step_s(&self) -> f64 {
        self.step_s
    }

    /// A source's `on` output, read after an update's scans: a rise asks
    /// for a part.
    pub fn set_source_trigger(&mut self, source: usize, on: bool) {
        self.sources[source].set_trigger(on);
    }

    /// The conveyors, in scene order.
    #[must_use]
    pub fn conveyors(&self) -> &[ConveyorState] {
        &self.conveyors
    }

    /// The conveyors, to set their commands.
    pub fn conveyors_mut(&mut self) -> &mut [ConveyorState] {
        &mut self.conveyors
    }

    /// One parts step to `t1`, the links at `links0` at its start: spawns
    /// what is due, moves the links to `world_from_link` (their poses at
    /// `t1`), steps the world; then [`Material::finish_step`] removes what
    /// left the cell.
    pub fn step(&mut self, t1: f64, links0: &[Isometry3<f64>], world_from_link: &[Isometry3<f64>]) {
        let t0 = self.time_s;
        self.spawn_due(t0);
        for p in &mut self.parts {
            p.before = *self.world.bodies[p.body].position();
        }
        for l in &self.links {
            let pose = pose_to_rapier(&world_from_link[l.link]);
            self.world.bodies[l.body].set_next_kinematic_position(pose);
        }
        for c in &mut self.conveyors {
            c.advance(t0, self.step_s);
        }
        for (c, body) in &mut self.cylinders {
            c.advance(t0, self.step_s);
            self.world.bodies[*body].set_next_kinematic_position(pose_to_rapier(&c.world_from_box()));
        }
        self.grip(t0, links0, world_from_link);
        self.ride();
        let belts: Vec<(ColliderHandle, Vector)> = self
            .belts
            .iter()
            .zip(&self.conveyors)
            .map(|(b, c)| (b.collider, c.belt_velocity()))
            .collect();
        self.world.step_with_events(&conveyor::BeltHooks { belts: &belts }, &());
        self.time_s = t1;
    }

    /// Before a step, the belts' speeds for it set: the parts that ride
    /// belts (module [`ride`]).
    fn ride(&mut self) {
        let held: Vec<u64> = self.grippers.iter().filter_map(|g| g.held.map(|h| h.part)).collect();
        for p in &self.parts {
            if held.contains(&p.id) {
                ride::forget(&mut self.world, p.body);
                continue;
            }
            let rider = ride::Rider {
                body: p.body,
                friction: self.part_types[p.part_type].friction,
                radius_m: self.shapes[p.part_type].radius_m,
            };
            ride::update(&mut self.world, &self.belts, &self.conveyors, &rider, self.step_s);
        }
    }

    /// The grippers over the step from `t0`, the links ending at
    /// `links1`: picks, drops, places, and the held parts moved with their
    /// links (module [`gripper`]).
    fn grip(&mut self, t0: f64, links0: &[Isometry3<f64>], links1: &[Isometry3<f64>]) {
        let dt = self.step_s;
        for k in 0..self.grippers.len() {
            let engaged = self.grippers[k].engaged(t0);
            let g = &mut self.grippers[k];
            if !engaged {
                g.engaged_since = None;
            } else if g.engaged_since.is_none() {
                g.engaged_since = Some(t0);
            }
            let ready = g.engaged_since.is_some_and(|since| t0 - since >= g.engage_s - 1e-12);
            if let Some(held) = g.held {
                if !engaged {
                    let dropped = self.grippers[k].grip && !self.grippers[k].release;
                    self.let_go(k, held, if dropped { "dropped" } else { "placed" });
                    continue;
                }
            } else if ready && !g.dropped {
                let link = g.link;
                self.pick(k, &links0[link]);
            }
            let Some(mut held) = self.grippers[k].held else {
                continue;
            };
            let Some(index) = self.parts.iter().position(|p| p.id == held.part) else {
                self.grippers[k].held = None;
                continue;
            };
            let body = self.parts[index].body;
            let link = self.grippers[k].link;
            let next = links1[link] * held.link_from_part;
            let now = crate::plant::convert::pose_from_rapier(self.world.bodies[body].position());
            let velocity = (next.translation.vector - now.translation.vector) / dt;
            let acceleration = (velocity - held.velocity) / dt;
            let mass = self.world.bodies[body].mass();
            let force = mass * (acceleration - nalgebra::Vector3::new(0.0, 0.0, -9.81)).norm();
            if held.steps >= 2 && force > self.grippers[k].max_force_n {
                self.let_go(k, held, "dropped");
                continue;
            }
            held.velocity = velocity;
            held.steps += 1;
            self.grippers[k].held = Some(held);
            self.world.bodies[body].set_next_kinematic_position(pose_to_rapier(&next));
        }
    }

    /// Gripper `k`, its link at `world_from_link`, picks the part nearest
    /// its TCP within reach, if any.
    fn pick(&mut self, k: usize, world_from_link: &Isometry3<f64>) {
        let g = &self.grippers[k];
        let world_from_link = *world_from_link;
        let tcp = world_from_link * g.link_from_tcp;
        let point = Vector::new(tcp.translation.x, tcp.translation.y, tcp.translation.z);
        let held_by_others: Vec<u64> = self.grippers.iter().filter_map(|o| o.held.map(|h| h.part)).collect();
        let mut best: Option<(f64, usize)> = None;
        for (i, p) in self.parts.iter().enumerate() {
            if held_by_others.contains(&p.id) {
                continue;
            }
            let s = &self.shapes[p.part_type];
            let at = *self.world.bodies[p.body].position() * s.part_from_shape;
            let d = s.shape.distance_to_point(&at, point, true);
            if d <= g.reach_m && best.is_none_or(|(b, _)| d < b) {
                best = Some((d, i));
            }
        }
        let Some((_, i)) = best else { return };
        let body = self.parts[i].body;
        let world_from_part = crate::plant::convert::pose_from_rapier(self.world.bodies[body].position());
        let offset = world_from_part.translation.vector - tcp.translation.vector;
        let z = tcp.rotation * Vector3::z();
        let lateral = (offset - z * offset.dot(&z)).norm();
        self.counts.max_pick_offset_m = Some(self.counts.max_pick_offset_m.map_or(lateral, |m| m.max(lateral)));
        let rb = &mut self.world.bodies[body];
        rb.set_body_type(RigidBodyType::KinematicPositionBased, true);
        self.grippers[k].held = Some(gripper::Held {
            part: self.parts[i].id,
            link_from_part: world_from_link.inverse() * world_from_part,
            velocity: Vector3::zeros(),
            steps: 0,
        });
        self.payload_changed = true;
    }

    /// Gripper `k` lets its part go: a dynamic body again with the
    /// velocity it had; a drop is counted.
    fn let_go(&mut self, k: usize, held: gripper::Held, how: &'static str) {
        self.grippers[k].held = None;
        self.payload_changed = true;
        let Some(p) = self.parts.iter().find(|p| p.id == held.part) else {
            return;
        };
        let body = p.body;
        let rb = &mut self.world.bodies[body];
        rb.set_body_type(RigidBodyType::Dynamic, true);
        rb.set_linvel(crate::plant::convert::vector_to_rapier(&held.velocity), true);
        if how == "dropped" {
            self.grippers[k].dropped = true;
            self.counts.dropped += 1;
            let t = self.time_s;
            self.event(t, held.part, "dropped", String::new());
        }
    }

    /// Whether a pick or a release changed the links' payloads since the
    /// last call.
    pub fn take_payload_changed(&mut self) -> bool {
        std::mem::take(&mut self.payload_changed)
    }

    /// Each link's payload now: (link, the held parts' mass properties in
    /// the link frame), links without one left out.
    #[must_use]
    pub fn payloads(&self) -> Vec<(usize, rapier3d_f64::prelude::MassProperties)> {
        let mut out: Vec<(usize, rapier3d_f64::prelude::MassProperties)> = Vec::new();
        for g in &self.grippers {
            let Some(h) = g.held else { continue };
            let Some(p) = self.parts.iter().find(|p| p.id == h.part) else {
                continue;
            };
            let local = self.world.bodies[p.body].mass_properties().local_mprops;
            let in_link = local.transform_by(&pose_to_rapier(&h.link_from_part));
            match out.iter_mut().find(|(l, _)| *l == g.link) {
                Some((_, m)) => *m += in_link,
                None => out.push((g.link, in_link)),
            }
        }
        out
    }

    /// The grippers, in scene order.
    #[must_use]
    pub fn grippers(&self) -> &[GripperState] {
        &self.grippers
    }

    /// The grippers, to set their outputs.
    pub fn grippers_mut(&mut self) -> &mut [GripperState] {
        &mut self.grippers
    }

    /// The cylinders, in scene order.
    pub fn cylinders(&self) -> impl Iterator<Item = &CylinderState> {
        self.cylinders.iter().map(|(c, _)| c)
    }

    /// Cylinder `k`, to set its valve.
    pub fn cylinder_mut(&mut self, k: usize) -> &mut CylinderState {
        &mut self.cylinders[k].0
    }

    /// After the sensors saw the step: removes the parts in a sink or lost.
    pub fn finish_step(&mut self) {
        let t = self.time_s;
        let mut k = 0;
        while k < self.parts.len() {
            let p = &self.parts[k];
            let at = *self.world.bodies[p.body].position();
            let centre = nalgebra::Point3::new(at.translation.x, at.translation.y, at.translation.z);
            let sink = self.sinks.iter().position(|s| {
                let local = s.world_from_sink.inverse_transform_point(&centre);
                (0..3).all(|i| local[i].abs() <= s.half_m[i])
            });
            let lost = at.translation.z < self.lost_below_z;
            if sink.is_none() && !lost {
                k += 1;
                continue;
            }
            let part = self.parts.remove(k);
            self.world.remove_body_with_colliders(part.body, true);
            let (event, name) = match sink {
                Some(s) => {
                    self.counts.per_sink[s] += 1;
                    match self.sinks[s].outcome {
                        SinkOutcome::Delivered => {
                            self.counts.delivered += 1;
                            self.counts.delivered_flow_s += t - part.spawned_s;
                        }
                        SinkOutcome::Rejected => self.counts.rejected += 1,
                    }
                    (self.sinks[s].outcome.word(), self.sinks[s].name.clone())
                }
                None => {
                    self.counts.lost += 1;
                    ("lost", String::new())
                }
            };
            self.event(t, part.id, event, name);
        }
    }

    fn event(&mut self, time_s: f64, part: u64, event: &'static str, at: String) {
        if self.events.len() < MAX_PART_EVENTS {
            self.events.push(PartEvent {
                time_s,
                part,
                event,
                at,
            });
        }
    }

    /// Spawns the parts due at `t`.
    fn spawn_due(&mut self, t: f64) {
        for k in 0..self.sources.len() {
            while let Some((pose, number)) = self.sources[k].due(&self.sources_def[k], t) {
                if self.parts.len() >= MAX_LIVE_PARTS {
                    self.counts.capped = true;
                    self.sources[k].stop();
                    break;
                }
                let source = &self.sources_def[k];
                let shape = &self.shapes[source.part_type];
                if self.occupied(&shape.shape, &(pose * shape.part_from_shape)) {
                    // Wait for the place to clear; the spawn stays due.
                    break;
                }
                self.sources[k].spawned(source);
                if source.skip.contains(&number) {
                    continue;
                }
                let part_type = &self.part_types[source.part_type];
                let body = self.world.insert_body(
                    RigidBodyBuilder::dynamic()
                        .pose(pose)
                        .can_sleep(false)
                        .user_data(ride::PART_BODY),
                );
                let collider = ColliderBuilder::new(shape.shape.clone())
                    .position(shape.part_from_shape)
                    .mass(part_type.mass_kg)
                    .friction(part_type.friction)
                    .restitution(part_type.restitution);
                self.world.insert_collider(collider, Some(body));
                let id = self.next_id;
                self.next_id += 1;
                self.parts.push(LivePart {
                    id,
                    part_type: source.part_type,
                    source: k,
                    spawned_s: t,
                    body,
                    before: pose,
                });
                self.counts.spawned += 1;
                let name = source.name.clone();
                self.event(t, id, "spawned", name);
            }
        }
    }

    /// Whether a shape at `pose` would overlap a live part.
    fn occupied(&self, shape: &SharedShape, pose: &Pose) -> bool {
        let aabb = shape.compute_aabb(pose);
        self.parts.iter().any(|p| {
            let s = &self.shapes[p.part_type];
            let at = *self.world.bodies[p.body].position() * s.part_from_shape;
            s.shape.compute_aabb(&at).intersects(&aabb)
                && crate::plant::sensors::field::overlaps(shape.as_ref(), pose, s.shape.as_ref(), &at)
        })
    }

    /// The live parts, in spawn order.
    #[must_use]
    pub fn parts(&self) -> &[LivePart] {
        &self.parts
    }

    /// A part's pose now (its frame: the part type's shape centred on it).
    #[must_use]
    pub fn part_pose(&self, part: &LivePart) -> Pose {
        *self.world.bodies[part.body].position()
    }

    /// Whether a part rides a belt now (module [`ride`]).
    #[must_use]
    pub fn rides(&self, part: &LivePart) -> bool {
        ride::rides(&self.world, part.body)
    }

    /// A part's pose at the start of the last step (its spawn pose for a
    /// part spawned then).
    #[must_use]
    pub fn part_pose_before(&self, part: &LivePart) -> Pose {
        part.before
    }

    /// Part type `k`'s `type_id`.
    #[must_use]
    pub fn type_id(&self, k: usize) -> i32 {
        self.part_types[k].type_id
    }

    /// The part types' shapes.
    #[must_use]
    pub fn shapes(&self) -> &[PartShape] {
        &self.shapes
    }

    /// The robot links with collision shapes: (link index, shapes in the
    /// link frame).
    pub fn link_shapes(&self) -> impl Iterator<Item = (usize, &[(Pose, SharedShape)])> {
        self.links.iter().map(|l| (l.link, l.shapes.as_slice()))
    }

    /// The obstacles' shapes in the world, by obstacle index.
    #[must_use]
    pub fn obstacle_shapes(&self) -> &[(Pose, SharedShape)] {
        &self.obstacles
    }

    /// The counts so far.
    #[must_use]
    pub fn counts(&self) -> &PartCounts {
        &self.counts
    }

    /// The first [`MAX_PART_EVENTS`] part events.
    #[must_use]
    pub fn events(&self) -> &[PartEvent] {
        &self.events
    }
}

/// How deep a source's part may start inside a fixed body, m: a part put
/// down touching a belt is fine; one spawned into it is a scene mistake.
const SPAWN_OVERLAP_M: f64 = 1e-4;

/// Each source's part at its nominal spawn pose is clear of `solids`
/// (within [`SPAWN_OVERLAP_M`]).
fn spawns_clear(
    sources: &[Source],
    part_types: &[crate::scene::PartType],
    shapes: &[PartShape],
    solids: &[(String, Pose, SharedShape)],
) -> Result<(), MaterialError> {
    for (k, s) in sources.iter().enumerate() {
        let shape = &shapes[s.part_type];
        let at = pose_to_rapier(&pose_from_xyz_rpy_deg(s.position_m, s.rpy_deg)) * shape.part_from_shape;
        for (what, pose, solid) in solids {
            let contact = rapier3d_f64::parry::query::contact(&at, shape.shape.as_ref(), pose, solid.as_ref(), 0.0);
            if let Ok(Some(c)) = contact
                && c.dist < -SPAWN_OVERLAP_M
            {
                return Err(MaterialError::SpawnsInside {
                    source_index: k,
                    part_type: part_types[s.part_type].name.clone(),
                    what: what.clone(),
                    depth_mm: -c.dist * 1000.0,
                });
            }
        }
    }
    Ok(())
}

#[cfg(test)]
#[allow(clippy::unwrap_used)] // a failed unwrap is a failed test
mod tests {
    use super::*;

    /// A scene with one belt along x (top at z = 0.8), a box source above
    /// its start and a sink at its end.
    fn belt_scene(extra: &str) -> Scene {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes");
        let text = format!(
            r#"
name = "belt"
duration_s = 10.0
coarse_update_ms = 4.0
physics_step_ms = 2.0
[robot]
urdf = "robots/indexing_table/indexing_table.urdf"
[[part_types]]
name = "Box"
shape = "box"
size = [0.1, 0.08, 0.06]
mass_kg = 0.5
[[sources]]
name = "In"
part_type = "Box"
position = [-1.0, 1.0, 0.831]
at_s = [0.0]
[[conveyors]]
name = "Belt"
position = [0.0, 1.0, 0.75]
size = [3.0, 0.3, 0.1]
axis = "Feed"
{extra}
"#
        );
        let path = dir.join("_belt_test.toml");
        crate::scene::parse(&path, &text).unwrap()
    }

    #[test]
    fn a_belt_carries_a_part_at_its_speed() {
        let scene = belt_scene(
            r#"[[axes]]
name = "Feed"
kind = "linear"
units = "m"
max_velocity = 1.0
max_acceleration = 10.0
max_deceleration = 10.0
max_jerk = 100.0
in_position_window = 0.001
initial_position = 0.0"#,
        );
        let model = RobotModel::load(&scene.robot.urdf).unwrap();
        let links = vec![Isometry3::identity(); model.links.len()];
        let mut m = Material::new(&scene, &model, &links).unwrap();
        m.conveyors_mut()[0].set_axis_speed(0.25);
        let mut t = 0.0;
        for _ in 0..500 {
            t += m.step_s();
            m.step(t, &links, &links);
            m.finish_step();
        }
        let p = &m.parts()[0];
        let pose = m.part_pose(p);
        assert!(
            (pose.translation.z - 0.83).abs() < 2e-3,
            "resting on the belt: {pose:?}"
        );
        // 2 s at 0.25 m/s, less the time to take up the speed.
        let travelled = pose.translation.x + 1.0;
        assert!(travelled > 0.45 && travelled < 0.5, "{travelled}");
        let v = m.world.bodies[p.body].linvel();
        assert!((v.x - 0.25).abs() < 1e-3, "{v:?}");
    }
}
