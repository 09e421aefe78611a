//! The live check of one physics step: the discrete check of its end pose
//! and the continuous detection over it ([`CollisionModel::check_step`],
//! [`CollisionModel::first_touches`]). The module doc of [`super`] says
//! what they find and how the step's check reuses the previous one.

use super::bodies::{Body, CheckResult, Contact, ContactPoint};
use super::build::vec3;
use super::{CollisionModel, Placed, Placement, box_distance};
use nalgebra::Isometry3;
use rapier3d_f64::math::{Pose, Vector};
use rapier3d_f64::parry::bounding_volume::BoundingVolume;
use rapier3d_f64::parry::query;

impl CollisionModel {
    /// The live check of one physics step ending at `to`: [`Self::check`]
    /// of `to` and, with the step's start `from` (its poses and their
    /// check), [`Self::first_touches`] over the step. The result equals
    /// those two calls'; it costs less:
    /// * the bodies are placed at `to` once for both;
    /// * a body whose link has exactly its pose in `from` (the base, a
    ///   link at rest) keeps its clearance and contacts from `from`'s
    ///   check, and a self pair of two such bodies its contact;
    /// * a body whose clearance at `from` is at least the distance its
    ///   points move in the step cannot touch an obstacle in it, and one
    ///   checked against a single obstacle that it touches at `from` has
    ///   its event open already: neither is cast.
    pub fn check_step(
        &self,
        from: Option<(&[Isometry3<f64>], &CheckResult)>,
        to: &[Isometry3<f64>],
    ) -> (CheckResult, Vec<(f64, Contact)>) {
        let end = self.placed_bodies(to);
        let Some((from, checked)) = from else {
            return (self.check_placed(&end, to, None), Vec::new());
        };
        let touches = self.first_touches_placed(from, to, &end, Some(&checked.clearance_m));
        (self.check_placed(&end, to, Some((from, checked))), touches)
    }

    /// Continuous detection between two poses of the robot (`from`, then
    /// `to`, one physics step apart): every checked pair that touches at
    /// some time during the motion, with the fraction `τ ∈ [0, 1]` of the
    /// step at which it first touches and the contact there (depth 0:
    /// touching). Each body moves rigidly from its pose in `from` to its
    /// pose in `to` (parry's nonlinear shape casting: constant linear and
    /// angular velocity); obstacles stand still. Only pairs whose swept
    /// boxes meet are cast, and only pairs not already touching at `from`
    /// (their event is open).
    pub fn first_touches(&self, from: &[Isometry3<f64>], to: &[Isometry3<f64>]) -> Vec<(f64, Contact)> {
        self.first_touches_placed(from, to, &self.placed_bodies(to), None)
    }

    /// [`Self::first_touches`] of placed bodies; `start_clearance_m`, when
    /// given, is each body's clearance at `start` ([`CheckResult::clearance_m`]).
    fn first_touches_placed(
        &self,
        from: &[Isometry3<f64>],
        to: &[Isometry3<f64>],
        end: &Placement<'_>,
        start_clearance_m: Option<&[f64]>,
    ) -> Vec<(f64, Contact)> {
        // Per body, once placed: its shapes at the start and how far they
        // move. A body is placed, and its motion bounded shape by shape,
        // only where the cheap bound of its link's motion allows a touch
        // (the list is made at the first).
        let mut start: Vec<Option<(Vec<Placed<'_>>, f64)>> = Vec::new();
        // Cast only pairs that could touch and do not at the start.
        let could_touch = |d: f64, reach: f64| d > 0.0 && d < reach;
        let mut found = Vec::new();
        for (b, s1) in end.bodies().enumerate() {
            // Every obstacle is at least the clearance away at the start.
            let clear = |reach: f64| reach == 0.0 || start_clearance_m.is_some_and(|d| d[b] >= reach);
            // A body checked against one obstacle and touching at the
            // start touches that one: its event is open, nothing to cast.
            let resting = self.checked_count[b] == 1 && start_clearance_m.is_some_and(|d| d[b] <= 0.0);
            if resting
                || clear(self.link_motion_bound(b, from, to))
                || clear(self.place_start(b, from, end, &mut start))
            {
                continue;
            }
            let Some((s0, reach)) = start[b].as_ref().map(|(s0, moved)| (s0.as_slice(), *moved)) else {
                continue;
            };
            let (Some(box0), Some(box1)) = (Self::body_box(s0), Self::body_box(s1)) else {
                continue;
            };
            let swept = box0.merged(&box1);
            self.near_obstacles(b, &swept, |o| {
                let obstacle = self.placed_obstacle(o);
                if !could_touch(Self::distance_between(s0, &obstacle, reach), reach) {
                    return;
                }
                let fixed = [(obstacle[0].pose, obstacle[0].pose)];
                if let Some(hit) = Self::first_touch(s0, s1, &obstacle, &fixed) {
                    found.push((
                        hit.0,
                        Contact {
                            a: Body::Robot(b),
                            b: Body::Obstacle(o),
                            ..hit.1
                        },
                    ));
                }
            });
        }
        for &(a, b) in &self.self_pairs {
            if self.link_motion_bound(a, from, to) + self.link_motion_bound(b, from, to) == 0.0 {
                continue;
            }
            let reach = self.place_start(a, from, end, &mut start) + self.place_start(b, from, end, &mut start);
            let (Some((start_a, _)), Some((start_b, _))) = (start[a].as_ref(), start[b].as_ref()) else {
                continue;
            };
            let (Some(box_a), Some(box_b)) = (Self::body_box(start_a), Self::body_box(start_b)) else {
                continue;
            };
            if reach == 0.0
                || box_distance(&box_a, &box_b) >= reach
                || !could_touch(Self::distance_between(start_a, start_b, reach), reach)
            {
                continue;
            }
            let motion_b: Vec<(Pose, Pose)> = start_b.iter().zip(&end[b]).map(|(p, q)| (p.pose, q.pose)).collect();
            if let Some(hit) = Self::first_touch(start_a, &end[a], start_b, &motion_b) {
                found.push((
                    hit.0,
                    Contact {
                        a: Body::Robot(a),
                        b: Body::Robot(b),
                        ..hit.1
                    },
                ));
            }
        }
        found
    }

    /// Places body `b` at `from` once (`start[b]`) with how far its points
    /// move from there to `end` ([`Self::displacement`]); returns that.
    fn place_start<'a>(
        &'a self,
        b: usize,
        from: &[Isometry3<f64>],
        end: &Placement<'a>,
        start: &mut Vec<Option<(Vec<Placed<'a>>, f64)>>,
    ) -> f64 {
        if start.is_empty() {
            start.resize_with(self.bodies.len(), || None);
        }
        start[b]
            .get_or_insert_with(|| {
                let s0 = self.world_shapes(b, from);
                let moved = Self::displacement(&s0, &end[b]);
                (s0, moved)
            })
            .1
    }

    /// An upper bound of how far any point of body `b` moves between two
    /// poses of its link: `|Δt| + 2 sin(θ/2) · r`, with `θ` the link's turn
    /// and `r` the largest distance from the link origin to a point of the
    /// body (a point `p` moves by `|Δt + (R₁R₀⁻¹ − I) R₀p| ≤ |Δt| +
    /// 2 sin(θ/2) |p|`; `sin(θ/2)` is the length of the turn quaternion's
    /// vector part), grown by 10⁻⁹ of itself for rounding. Looser than
    /// [`Self::displacement`], and needs no placing.
    fn link_motion_bound(&self, b: usize, from: &[Isometry3<f64>], to: &[Isometry3<f64>]) -> f64 {
        let link = self.bodies[b].link;
        let (p, q) = (&from[link], &to[link]);
        if p == q {
            return 0.0;
        }
        let turn = q.rotation * p.rotation.inverse();
        let chord = 2.0 * turn.imag().norm() * self.body_radius[b];
        ((q.translation.vector - p.translation.vector).norm() + chord) * (1.0 + 1e-9)
    }

    /// An upper bound of how far any point of a body's shapes moves from
    /// their poses in `s0` to those in `s1`: per shape, its bounding
    /// sphere's centre's displacement plus the turn's angle times the
    /// sphere's radius.
    fn displacement(s0: &[Placed<'_>], s1: &[Placed<'_>]) -> f64 {
        s0.iter()
            .zip(s1)
            .map(|(p, q)| {
                if p.pose == q.pose {
                    return 0.0;
                }
                let angle = (q.pose.rotation * p.pose.rotation.inverse()).to_scaled_axis().length();
                (q.center - p.center).length() + angle * p.radius
            })
            .fold(0.0, f64::max)
    }

    /// The first touch of two shape sets moving rigidly over one step:
    /// `a` from its shapes' poses in `a0` to those in `a1`, `b` from the
    /// first to the second pose of each of its shapes (`b0` gives the
    /// shapes). The fraction of the step, and the contact then (placeholder
    /// bodies).
    fn first_touch(
        a0: &[Placed<'_>],
        a1: &[Placed<'_>],
        b0: &[Placed<'_>],
        b_poses: &[(Pose, Pose)],
    ) -> Option<(f64, Contact)> {
        use rapier3d_f64::parry::query::NonlinearRigidMotion;
        let motion = |p: Pose, q: Pose| {
            let turn = q.rotation * p.rotation.inverse();
            NonlinearRigidMotion::new(p, Vector::ZERO, q.translation - p.translation, turn.to_scaled_axis())
        };
        let mut best: Option<(f64, Contact)> = None;
        for (pa, qa) in a0.iter().zip(a1) {
            let ma = motion(pa.pose, qa.pose);
            for (pb, &(p, q)) in b0.iter().zip(b_poses) {
                let mb = motion(p, q);
                let Ok(Some(hit)) =
                    query::cast_shapes_nonlinear(&ma, pa.shape.as_ref(), &mb, pb.shape.as_ref(), 0.0, 1.0, true)
                else {
                    continue;
                };
                let tau = hit.time_of_impact.clamp(0.0, 1.0);
                if best.as_ref().is_some_and(|(t, _)| *t <= tau) {
                    continue;
                }
                // The contact at that time, as the discrete check gives it.
                let (wa, wb) = (ma.position_at_time(tau), mb.position_at_time(tau));
                let Ok(Some(c)) = query::contact(&wa, pa.shape.as_ref(), &wb, pb.shape.as_ref(), 1e-6) else {
                    continue;
                };
                let mid = (c.point1 + c.point2) * 0.5;
                best = Some((
                    tau,
                    Contact {
                        a: Body::Robot(0),
                        b: Body::Robot(0),
                        at: ContactPoint {
                            depth_m: 0.0,
                            point_in_world: vec3(mid),
                            normal_in_world: vec3(c.normal2),
                        },
                    },
                ));
            }
        }
        best
    }
}
