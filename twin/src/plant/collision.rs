//! Collision checking with parry: the robot's collision bodies (URDF
//! `<collision>` shapes per link, plus an optional tool shape), the scene's
//! obstacles, live checks of one robot pose, collision events over time,
//! and the pre-flight sweep of a planned path.
//!
//! # Bodies
//! A robot *body* is a URDF link with at least one `<collision>` element
//! (box, cylinder, sphere, or an STL mesh approximated as set by
//! `collision.meshes`: one convex hull by default, or a convex
//! decomposition), or the scene's tool shape (named `collision.tool.name`,
//! carried by a link). Obstacles are the scene's `[[obstacles]]`.
//!
//! # Checks ([`CollisionModel::check`])
//! * Every robot body against every obstacle: the distance (clearance) and,
//!   when they touch or overlap, a contact. The obstacles' bounding boxes
//!   are in a tree (parry's `Bvh`, the broad phase): the clearance is found
//!   best first, visiting only obstacles whose boxes are nearer than the
//!   best distance so far, and contacts are looked for among the obstacles
//!   whose boxes meet the body's — the result is the same as checking every
//!   pair, the cost grows with the obstacles near the robot.
//! * With `self_collision`, every pair of robot bodies that are not
//!   *adjacent*. Links joined through a chain of fixed joints form one
//!   rigid group (they never move relative to each other, so a mounting
//!   plate, flange or sensor link fixed to a link counts as that link);
//!   two bodies are adjacent when their links are in the same rigid group
//!   or in two groups joined by one movable joint (any link of one group
//!   the parent, any link of the other the child). A tool is adjacent to
//!   its link's group and that group's neighbours too.
//! * Pairs in `allowed_pairs` are never reported (nor used for clearance).
//!
//! A contact carries the penetration depth (≥ 0), the contact point — the
//! midpoint of the two shapes' deepest points — and the normal, a unit
//! vector in the world frame pointing from the second body into the first
//! (the direction that separates the first body, a robot link, from the
//! obstacle: the obstacle's outward surface normal).
//!
//! # Events ([`monitor::Monitor`])
//! The live check runs after every physics step: the discrete check of the
//! step's end pose ([`CollisionModel::check`]: depth, clearance) and the
//! continuous detection over the step ([`CollisionModel::first_touches`]):
//! each body moves rigidly from its previous pose to its new one (constant
//! linear and angular velocity, parry's nonlinear shape casting) against
//! the obstacles (and the other bodies with self-collision); pairs farther
//! apart at the start than the bodies' points can move in the step, and
//! pairs whose swept boxes do not meet, are not cast. The plant runs both
//! through [`CollisionModel::check_step`], which gives the same results
//! for less: a body whose link has not moved keeps the previous check's
//! clearance and contacts, and a body is placed at the step's start only
//! when a bound of its link's motion exceeds its clearance there.
//!
//! An event opens at
//! the first check where a pair touches; its `start_s` is the pair's first
//! touch inside the step that ended there (interpolated: the continuous
//! detection's time of impact), else that check's time. It closes at the
//! first check where the pair no longer touches (`end_s` is that check's
//! time). A pair that touched during a step and no longer touches at its
//! end (a contact shorter than a step: a fast, small tool through a thin
//! part) is an event that opened and closed in that step (depth 0, the
//! point and normal at the first touch). An event keeps the maximum depth
//! and the point and normal at that depth.
//!
//! # Pre-flight sweep ([`CollisionModel::sweep`])
//! Conservative advancement along a [`sweep::PathSampler`]: each body's points move
//! at most `L_b · Δs` for a parameter step `Δs`, where `L_b = Σ_j
//! |dq_j/ds|max · R_jb` sums over the joints above the body (`R_jb`: an upper
//! bound of the distance from joint `j`'s origin to any point of the body in
//! any configuration, for revolute joints; 1 for prismatic ones). At a
//! sample with clearance `d_b` no contact can happen within `d_b / L_b`, so
//! the sweep steps by `max(min_b d_b / L_b, h)` with
//! `h = sweep_resolution_m / max_b L_b`. A step longer than the clearance
//! allows (the `h` floor) is then settled: with the distances at both ends,
//! `d_b(a) + d_b(b) > L_b · (b − a)` rules out a contact in between;
//! otherwise the interval is halved, earlier half first, down to
//! `ε = SWEEP_TOLERANCE · length`. **Bound**: every contact of the planned
//! path that lasts at least `ε` is found, and the reported parameter `s_p`
//! lies in `[s_c, s_c + ε]` where `s_c` is the first contact (never early);
//! the report's `step_bound` is `ε`. Past the sample budget
//! ([`sweep::MAX_SWEEP_SAMPLES`] steps, [`sweep::MAX_REFINE_SAMPLES`] to settle them) the
//! bound is the step `h` again, and `step_bound` says so.

use crate::plant::convert::pose_to_rapier;
use crate::plant::urdf::RobotModel;
use crate::scene::{CollisionSettings, Obstacle};
use nalgebra::Isometry3;
use rapier3d_f64::math::{Pose, Vector};
use rapier3d_f64::parry::bounding_volume::{Aabb, BoundingVolume};
use rapier3d_f64::parry::partitioning::{Bvh, BvhBuildStrategy};
use rapier3d_f64::parry::query;
use rapier3d_f64::parry::shape::SharedShape;

mod bodies;
mod build;
mod live;
pub mod monitor;
pub mod sweep;
pub use bodies::{Body, CheckResult, CollisionModelError, Contact, ContactPoint};
use bodies::{LocalSphere, RobotBody};
pub use build::{MAX_DECOMPOSITION_TRIANGLES, MAX_DECOMPOSITION_TRIANGLES_TOTAL};
use build::{allowed_pairs, obstacle_shapes, reach_of, robot_bodies, self_pairs, vec3};
pub(crate) use build::{pose_from_xyz_rpy_deg, scene_shape, shape_of};

/// A contact deeper than this, m, is an overlap whatever the rounding of
/// the distance query that would confirm it: the body's clearance is 0.
const CLEAR_OVERLAP_M: f64 = 1e-9;

/// How much a body's bounding box is grown for the broad phase, m: shapes
/// that just touch (distance 0) always have overlapping boxes.
const BOX_MARGIN_M: f64 = 1e-6;

/// The distance between two boxes (0 when they overlap): a lower bound of
/// the distance between anything inside them.
fn box_distance(a: &Aabb, b: &Aabb) -> f64 {
    let gap = (a.mins - b.maxs).max(b.mins - a.maxs).max(Vector::ZERO);
    gap.length()
}

/// Every robot body's shapes placed in the world, in one vector (bodies
/// in order; `placement[b]` is body `b`'s shapes).
struct Placement<'a> {
    shapes: Vec<Placed<'a>>,
    /// Where each body's shapes start in `shapes`, and their end.
    starts: &'a [usize],
}

impl<'a> Placement<'a> {
    /// The bodies' shapes, in body order.
    fn bodies(&self) -> impl Iterator<Item = &[Placed<'a>]> {
        self.starts.windows(2).map(|w| &self.shapes[w[0]..w[1]])
    }
}

impl<'a> std::ops::Index<usize> for Placement<'a> {
    type Output = [Placed<'a>];
    fn index(&self, body: usize) -> &[Placed<'a>] {
        &self.shapes[self.starts[body]..self.starts[body + 1]]
    }
}

/// A shape placed in the world with its bounding sphere there.
struct Placed<'a> {
    pose: Pose,
    shape: &'a SharedShape,
    center: Vector,
    radius: f64,
}

impl<'a> Placed<'a> {
    fn new(pose: Pose, shape: &'a SharedShape, sphere: LocalSphere) -> Self {
        Placed {
            pose,
            shape,
            center: pose * sphere.center,
            radius: sphere.radius,
        }
    }

    /// A lower bound of the distance between the two shapes.
    fn lower_bound(&self, other: &Placed<'_>) -> f64 {
        (self.center - other.center).length() - self.radius - other.radius
    }
}

/// The collision world of a scene.
#[derive(Clone)]
pub struct CollisionModel {
    bodies: Vec<RobotBody>,
    obstacle_names: Vec<String>,
    obstacles: Vec<(Pose, SharedShape)>,
    /// Per body, per shape, and per obstacle: the local bounding sphere
    /// (computed once: a mesh hull's takes a pass over its vertices).
    body_spheres: Vec<Vec<LocalSphere>>,
    obstacle_spheres: Vec<LocalSphere>,
    /// Where each body's shapes start in a [`Placement`] (and their end).
    shape_starts: Vec<usize>,
    /// Per body, the largest distance from its link's origin to a point of
    /// it (over its shapes' bounding spheres), m.
    body_radius: Vec<f64>,
    /// Per body, per obstacle: whether the pair is checked.
    checked: Vec<Vec<bool>>,
    /// Per body, how many obstacles it is checked against.
    checked_count: Vec<usize>,
    /// The obstacles' world bounding boxes in a tree (leaf = obstacle
    /// index): the broad phase, so a check visits the obstacles near a
    /// body, not all of them.
    obstacle_tree: Bvh,
    /// Per body, the obstacle nearest at the last check: where the next
    /// search starts.
    last_nearest: Vec<std::cell::Cell<Option<usize>>>,
    /// Buffers reused by the checks.
    scratch: Scratch,
    /// Robot body pairs to check.
    self_pairs: Vec<(usize, usize)>,
    /// Per body, per model joint: R_jb (0 where joint j does not move the body).
    reach: Vec<Vec<f64>>,
}

/// Buffers a check reuses from one call to the next (a check runs every
/// physics step); a clone starts with empty ones.
#[derive(Default)]
struct Scratch {
    /// Parry's penetration solver.
    epa: std::cell::RefCell<rapier3d_f64::parry::query::epa::EPA>,
    /// Obstacle indices ([`CollisionModel::near_obstacles`]).
    near: std::cell::Cell<Vec<usize>>,
}

impl Clone for Scratch {
    fn clone(&self) -> Self {
        Self::default()
    }
}

impl std::fmt::Debug for CollisionModel {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("CollisionModel")
            .field("bodies", &self.body_names())
            .field("obstacles", &self.obstacle_names)
            .field("self_pairs", &self.self_pairs)
            .finish_non_exhaustive()
    }
}

impl CollisionModel {
    /// Builds the bodies, obstacles and checked pairs of a scene.
    ///
    /// # Errors
    /// [`CollisionModelError`] for an unknown tool link or allowed-pair
    /// name, a degenerate mesh, or a tool mesh that cannot be loaded.
    pub fn new(
        model: &RobotModel,
        obstacles: &[Obstacle],
        settings: &CollisionSettings,
    ) -> Result<CollisionModel, CollisionModelError> {
        build::decomposition_budget(model, obstacles, settings)?;
        let bodies = robot_bodies(model, settings)?;
        let obstacle_shapes = obstacle_shapes(obstacles, settings)?;
        let obstacle_names: Vec<String> = obstacles.iter().map(|o| o.name.clone()).collect();
        let allowed = allowed_pairs(&bodies, &obstacle_names, settings)?;
        let is_allowed = |a: Body, b: Body| {
            let mut pair = [a, b];
            pair.sort();
            allowed.contains(&pair)
        };
        let checked: Vec<Vec<bool>> = (0..bodies.len())
            .map(|b| {
                (0..obstacle_shapes.len())
                    .map(|o| !is_allowed(Body::Robot(b), Body::Obstacle(o)))
                    .collect()
            })
            .collect();
        let self_pairs = if settings.self_collision {
            self_pairs(model, &bodies, is_allowed)
        } else {
            Vec::new()
        };
        let reach = bodies.iter().map(|b| reach_of(model, b)).collect();
        let boxes: Vec<Aabb> = obstacle_shapes
            .iter()
            .map(|(pose, shape)| shape.compute_aabb(pose))
            .collect();
        let obstacle_tree = Bvh::from_leaves(BvhBuildStrategy::default(), &boxes);
        let body_spheres: Vec<Vec<LocalSphere>> = bodies
            .iter()
            .map(|b| b.shapes.iter().map(|(_, s)| LocalSphere::of(s)).collect())
            .collect();
        let obstacle_spheres = obstacle_shapes.iter().map(|(_, s)| LocalSphere::of(s)).collect();
        let body_radius = bodies.iter().zip(&body_spheres).map(|(b, s)| b.radius(s)).collect();
        let shape_starts = std::iter::once(0)
            .chain(bodies.iter().scan(0, |end, b| {
                *end += b.shapes.len();
                Some(*end)
            }))
            .collect();
        Ok(CollisionModel {
            shape_starts,
            bodies,
            body_spheres,
            obstacle_spheres,
            body_radius,
            obstacle_names,
            obstacles: obstacle_shapes,
            last_nearest: vec![std::cell::Cell::new(None); checked.len()],
            scratch: Scratch::default(),
            checked_count: checked.iter().map(|row| row.iter().filter(|&&c| c).count()).collect(),
            checked,
            obstacle_tree,
            self_pairs,
            reach,
        })
    }

    /// Robot body names (links with collision shapes in URDF order, then the tool).
    pub fn body_names(&self) -> Vec<&str> {
        self.bodies.iter().map(|b| b.name.as_str()).collect()
    }

    /// The URDF link index carrying each robot body.
    pub fn body_links(&self) -> Vec<usize> {
        self.bodies.iter().map(|b| b.link).collect()
    }

    /// A body's name.
    pub fn name(&self, body: Body) -> &str {
        match body {
            Body::Robot(i) => &self.bodies[i].name,
            Body::Obstacle(i) => &self.obstacle_names[i],
        }
    }

    /// Robot body pairs checked for self-collision (indices into [`Self::body_names`]).
    pub fn self_pairs(&self) -> &[(usize, usize)] {
        &self.self_pairs
    }

    /// Body `body`'s shapes placed where `world_from_link` puts its link.
    fn body_placed<'a>(
        &'a self,
        body: usize,
        world_from_link: &[Isometry3<f64>],
    ) -> impl Iterator<Item = Placed<'a>> + 'a {
        let b = &self.bodies[body];
        let world = pose_to_rapier(&world_from_link[b.link]);
        b.shapes
            .iter()
            .zip(&self.body_spheres[body])
            .map(move |((local, s), sphere)| Placed::new(world * *local, s, *sphere))
    }

    fn world_shapes<'a>(&'a self, body: usize, world_from_link: &[Isometry3<f64>]) -> Vec<Placed<'a>> {
        self.body_placed(body, world_from_link).collect()
    }

    fn placed_obstacle(&self, o: usize) -> [Placed<'_>; 1] {
        let (pose, shape) = &self.obstacles[o];
        [Placed::new(*pose, shape, self.obstacle_spheres[o])]
    }

    fn placed_bodies(&self, world_from_link: &[Isometry3<f64>]) -> Placement<'_> {
        let mut shapes = Vec::with_capacity(self.shape_starts.last().copied().unwrap_or_default());
        for b in 0..self.bodies.len() {
            shapes.extend(self.body_placed(b, world_from_link));
        }
        Placement {
            shapes,
            starts: &self.shape_starts,
        }
    }

    /// Appends body `b`'s contacts with every obstacle checked against it
    /// whose box meets the body's (`body`), in obstacle order.
    fn obstacle_contacts(&self, b: usize, shapes: &[Placed<'_>], body: &Aabb, contacts: &mut Vec<Contact>) {
        self.near_obstacles(b, body, |o| {
            if let Some((depth_m, point, normal)) = self.contact_between(shapes, &self.placed_obstacle(o)) {
                contacts.push(Contact {
                    a: Body::Robot(b),
                    b: Body::Obstacle(o),
                    at: ContactPoint {
                        depth_m,
                        point_in_world: point,
                        normal_in_world: normal,
                    },
                });
            }
        });
    }

    /// Calls `each` with every obstacle checked against body `b` whose
    /// box meets `aabb`, in obstacle order.
    fn near_obstacles(&self, b: usize, aabb: &Aabb, mut each: impl FnMut(usize)) {
        let mut near = self.scratch.near.take();
        near.clear();
        near.extend(
            self.obstacle_tree
                .intersect_aabb(aabb)
                .map(|o| o as usize)
                .filter(|&o| self.checked[b][o]),
        );
        near.sort_unstable();
        for &o in &near {
            each(o);
        }
        self.scratch.near.set(near);
    }

    /// Deepest contact between two shape sets, if they touch.
    fn contact_between(&self, a: &[Placed<'_>], b: &[Placed<'_>]) -> Option<(f64, [f64; 3], [f64; 3])> {
        let mut best: Option<(f64, [f64; 3], [f64; 3])> = None;
        for pa in a {
            for pb in b {
                if pa.lower_bound(pb) > 0.0 {
                    continue;
                }
                let Some(c) = self.contact(pa, pb) else {
                    continue;
                };
                if c.dist > 0.0 {
                    continue;
                }
                let depth = -c.dist;
                if best.is_none_or(|(d, _, _)| depth > d) {
                    let mid = (c.point1 + c.point2) * 0.5;
                    best = Some((depth, vec3(mid), vec3(c.normal2)));
                }
            }
        }
        best
    }

    /// `query::contact` of two placed shapes with no prediction, the same
    /// numbers; for two convex shapes that neither are balls nor half
    /// spaces (parry's GJK, then EPA when they overlap) it reuses one EPA,
    /// where parry's own makes a new one, and its buffers, on every call
    /// (a resting contact is an overlap every physics step).
    fn contact(&self, pa: &Placed<'_>, pb: &Placed<'_>) -> Option<query::Contact> {
        use rapier3d_f64::parry::query::gjk::{self, CsoPoint, GJKResult, VoronoiSimplex};
        use rapier3d_f64::parry::shape::HalfSpace;
        let (s1, s2) = (pa.shape.as_ref(), pb.shape.as_ref());
        let general = s1.as_ball().is_none()
            && s2.as_ball().is_none()
            && s1.as_shape::<HalfSpace>().is_none()
            && s2.as_shape::<HalfSpace>().is_none();
        let (true, Some(g1), Some(g2)) = (general, s1.as_support_map(), s2.as_support_map()) else {
            return query::contact(&pa.pose, s1, &pb.pose, s2, 0.0).ok().flatten();
        };
        let pos12 = pa.pose.inv_mul(&pb.pose);
        let mut simplex = VoronoiSimplex::new();
        let dir = pos12.translation.try_normalize().unwrap_or(Vector::X);
        simplex.reset(CsoPoint::from_shapes(&pos12, g1, g2, dir));
        let closest = match gjk::closest_points(&pos12, g1, g2, 0.0, true, &mut simplex) {
            GJKResult::Intersection => self.scratch.epa.borrow_mut().closest_points(&pos12, g1, g2, &simplex),
            GJKResult::ClosestPoints(p1, p2, n) => Some((p1, p2, n)),
            _ => None,
        };
        let (point1, point2_1, normal1) = closest?;
        let dist = (point2_1 - point1).dot(normal1);
        let point2 = pos12.inverse_transform_point(point2_1);
        let normal2 = pos12.rotation.inverse() * -normal1;
        let mut c = query::Contact::new(point1, point2, normal1, normal2, dist);
        c.transform_by_mut(&pa.pose, &pb.pose);
        Some(c)
    }

    /// The smallest distance between two shape sets, or `cutoff` when none
    /// is below it (bounding spheres skip pairs that cannot be closer).
    fn distance_between(a: &[Placed<'_>], b: &[Placed<'_>], cutoff: f64) -> f64 {
        let mut d = cutoff;
        for pa in a {
            for pb in b {
                if pa.lower_bound(pb) >= d {
                    continue;
                }
                if let Ok(x) = query::distance(&pa.pose, pa.shape.as_ref(), &pb.pose, pb.shape.as_ref()) {
                    d = d.min(x.distance);
                }
            }
        }
        d
    }

    /// The world bounding box of a body's shapes, grown by [`BOX_MARGIN_M`]
    /// (so that shapes that just touch have overlapping boxes).
    fn body_box(shapes: &[Placed<'_>]) -> Option<Aabb> {
        let mut boxes = shapes.iter().map(|p| p.shape.compute_aabb(&p.pose));
        let first = boxes.next()?;
        Some(boxes.fold(first, |a, b| a.merged(&b)).loosened(BOX_MARGIN_M))
    }

    /// Body `b`'s clearance: the smallest distance to an obstacle it is
    /// checked against (0 when touching, infinite without one). Best first
    /// through the obstacle tree: a subtree whose box is farther than the
    /// best distance so far is not visited.
    ///
    /// The search starts from the obstacle that was nearest at the last
    /// check (robots move little between checks), so most subtrees are
    /// pruned at once; the result does not depend on it.
    fn nearest_obstacle(&self, b: usize, shapes: &[Placed<'_>]) -> f64 {
        let last = self.last_nearest[b].get();
        let start = last.map_or(f64::INFINITY, |o| {
            Self::distance_between(shapes, &self.placed_obstacle(o), f64::INFINITY)
        });
        // The last nearest is the only obstacle the body is checked against.
        if last.is_some() && self.checked_count[b] == 1 {
            return start;
        }
        let Some(body) = Self::body_box(shapes) else {
            return f64::INFINITY;
        };
        let found = self.obstacle_tree.find_best(
            start,
            |node, _| box_distance(&body, &node.aabb()),
            |o, best| {
                let o = o as usize;
                (self.checked[b][o] && Some(o) != last)
                    .then(|| Self::distance_between(shapes, &self.placed_obstacle(o), best))
            },
        );
        match found {
            Some((o, d)) => {
                self.last_nearest[b].set(Some(o as usize));
                d
            }
            None => start,
        }
    }

    /// Checks one robot pose (`world_from_link` of every URDF link, in model order).
    pub fn check(&self, world_from_link: &[Isometry3<f64>]) -> CheckResult {
        self.check_placed(&self.placed_bodies(world_from_link), world_from_link, None)
    }

    /// The discrete check of bodies placed at `to`. With `reuse` (the link
    /// poses of a previous check and its result), a body whose link stands
    /// where it stood then, and a self pair of two such bodies, take their
    /// results from it.
    fn check_placed(
        &self,
        shapes: &Placement<'_>,
        to: &[Isometry3<f64>],
        reuse: Option<(&[Isometry3<f64>], &CheckResult)>,
    ) -> CheckResult {
        let mut clearance_m = vec![f64::INFINITY; self.bodies.len()];
        let mut contacts = Vec::new();
        let same = |b: usize| {
            let link = self.bodies[b].link;
            reuse.filter(|(from, _)| from[link] == to[link]).map(|(_, r)| r)
        };
        for (b, body_shapes) in shapes.bodies().enumerate() {
            if let Some(previous) = same(b) {
                clearance_m[b] = previous.clearance_m[b];
                contacts.extend(
                    previous
                        .contacts
                        .iter()
                        .filter(|c| c.a == Body::Robot(b) && matches!(c.b, Body::Obstacle(_))),
                );
                continue;
            }
            let Some(body) = Self::body_box(body_shapes) else {
                clearance_m[b] = self.nearest_obstacle(b, body_shapes);
                continue;
            };
            // A body that touched at the previous check likely still does:
            // its contacts first (where they start in `contacts`), and an
            // overlap deeper than rounding could blur means a clearance of
            // 0 (what the distance gives for shapes that overlap) without
            // measuring it.
            let touched = reuse.is_some_and(|(_, r)| r.clearance_m[b] <= 0.0);
            let found = touched.then(|| {
                let before = contacts.len();
                self.obstacle_contacts(b, body_shapes, &body, &mut contacts);
                before
            });
            if found.is_some_and(|before| contacts[before..].iter().any(|c| c.at.depth_m > CLEAR_OVERLAP_M)) {
                clearance_m[b] = 0.0;
                continue;
            }
            clearance_m[b] = self.nearest_obstacle(b, body_shapes);
            match (clearance_m[b] > 0.0, found) {
                // Clear after all: the contacts found first do not count.
                (true, Some(before)) => contacts.truncate(before),
                (true, None) | (false, Some(_)) => {}
                // Touching: the contacts with every obstacle whose box
                // meets the body's, in obstacle order.
                (false, None) => self.obstacle_contacts(b, body_shapes, &body, &mut contacts),
            }
        }
        for &(a, b) in &self.self_pairs {
            if let (Some(previous), Some(_)) = (same(a), same(b)) {
                contacts.extend(
                    previous
                        .contacts
                        .iter()
                        .filter(|c| c.a == Body::Robot(a) && c.b == Body::Robot(b)),
                );
                continue;
            }
            if let Some((depth_m, point, normal)) = self.contact_between(&shapes[a], &shapes[b]) {
                contacts.push(Contact {
                    a: Body::Robot(a),
                    b: Body::Robot(b),
                    at: ContactPoint {
                        depth_m,
                        point_in_world: point,
                        normal_in_world: normal,
                    },
                });
            }
        }
        CheckResult { contacts, clearance_m }
    }

    /// Per body, the smallest distance to anything it is checked against
    /// (obstacles and self pairs), m.
    fn distances(&self, world_from_link: &[Isometry3<f64>]) -> Vec<f64> {
        let shapes = self.placed_bodies(world_from_link);
        let mut d: Vec<f64> = (0..self.bodies.len())
            .map(|b| self.nearest_obstacle(b, &shapes[b]))
            .collect();
        for &(a, b) in &self.self_pairs {
            let x = Self::distance_between(&shapes[a], &shapes[b], d[a].max(d[b]));
            d[a] = d[a].min(x);
            d[b] = d[b].min(x);
        }
        d
    }
}

#[cfg(test)]
mod tests;
