//! The cell's sensors: what each sees in the parts world, step by step,
//! and the signal it gives the program.
//!
//! Each parts step, a sensor's field (sensor frame, carried by its `link`
//! or fixed in the world) is checked against the bodies it `detects`:
//! parts (all, or some types; an inductive proximity sensor only those of
//! its `materials`), robot links (their collision shapes), obstacles.
//! [`field`] finds when inside the step each body is in the field, from
//! the bodies' motion; the union of those intervals is the detection, whose
//! changes go through [`signal`] (faults, invert, delays, input module).
//!
//! | kind | field | `tag` (BOOL) | `value_tag` / `count_tag` |
//! |---|---|---|---|
//! | `beam` | the segment `from`–`to` | a body breaks the beam | — |
//! | `beam` + `count`, `pitch_m` | `count` segments, beam `i` moved `i · pitch_m` along the sensor's z | any beam broken | DINT: bit `i` set while beam `i` is broken |
//! | `diffuse` | the ray from the sensor along its +x, `range_m` long | a body within range | REAL: the distance, m, or linearly scaled by `scale`; `range_m` (scaled) when nothing is seen |
//! | `proximity` | a box, sphere or cylinder (z-axis) | a body in the field | — |
//! | `zone` | a box, sphere or cylinder | occupied | DINT: bodies inside (a part, a link, an obstacle: one each) |
//!
//! Values (`value_tag`, `count_tag`) are measured at the end of each parts
//! step and taken by the input module at its updates (as the BOOL; with
//! COS, every step).

pub mod field;
pub mod signal;

use nalgebra::Isometry3;
use rapier3d_f64::math::{Pose, Vector};
use rapier3d_f64::parry::bounding_volume::{Aabb, BoundingVolume};
use rapier3d_f64::parry::query::Ray;
use rapier3d_f64::parry::shape::{Segment, SharedShape};

use crate::plant::collision::{pose_from_xyz_rpy_deg, shape_of};
use crate::plant::convert::pose_to_rapier;
use crate::plant::material::Material;
use crate::plant::urdf::{Geometry, RobotModel};
use crate::scene::{Detect, MeshApproximation, Scene, SensorKind, Shape};
use field::{Moving, changes_of, overlap_in_step};
pub use signal::{Signal, SignalStats};

/// What a sensor detects, resolved.
#[derive(Debug, Clone, Default)]
struct Targets {
    all_parts: bool,
    part_types: Vec<usize>,
    robot: bool,
    links: Vec<usize>,
    obstacles: Vec<usize>,
}

/// A sensor's field, in the sensor frame.
#[derive(Clone)]
enum FieldShape {
    /// Through-beams (one, or a curtain's).
    Beams(Vec<Segment>),
    /// A diffuse eye's ray along +x.
    Ray { range_m: f64, scale: Option<[[f64; 2]; 2]> },
    /// A proximity field or a zone: the shape, its pose in the sensor frame.
    Volume {
        shape: SharedShape,
        local: Pose,
        materials: Vec<String>,
    },
    /// The distance between two groups of bodies.
    Clearance { groups: Box<[Targets; 2]>, below_m: f64 },
    /// A camera's field of view.
    Vision(Box<Vision>),
}

/// A vision sensor's settings and its last result.
#[derive(Clone)]
struct Vision {
    shape: SharedShape,
    local: Pose,
    latency_s: f64,
    /// The link whose frame the position is in.
    frame: Option<usize>,
    millimetres: bool,
    trigger_was: bool,
    /// A result on its way: (when it arrives, s; what it says).
    pending: Option<(f64, VisionResult)>,
    result: VisionResult,
}

/// What a camera reports.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct VisionResult {
    /// A part was in the field.
    pub found: bool,
    /// Its centre in the frame (m, or mm with `units = "mm"`).
    pub position: [f64; 3],
    /// Its angle about the frame's z, degrees in (−180, 180].
    pub angle_deg: f64,
    /// Its type's `type_id`.
    pub type_id: i32,
}

/// One sensor running.
#[derive(Clone)]
pub struct SensorSim {
    /// Its name.
    pub name: String,
    field: FieldShape,
    mount: Option<usize>,
    mount_from_sensor: Isometry3<f64>,
    targets: Targets,
    signal: Signal,
    /// Detected at the end of the last step.
    detected: bool,
    /// The value measured at the end of the last step (curtain bitmask,
    /// distance, count).
    value: f64,
    /// The value the input module last took.
    value_taken: f64,
    /// The registration input it is wired to: (axis index, input 1 or 2).
    pub registration: Option<(usize, u8)>,
}

/// A body the sensors can see, over one step.
struct Body<'a> {
    moving: Moving<'a>,
    /// Swept box.
    aabb: Aabb,
    /// What it is.
    what: Seen,
}

#[derive(Clone, Copy, PartialEq)]
enum Seen {
    Part { part_type: usize, id: u64 },
    Link(usize),
    Obstacle(usize),
}

impl SensorSim {
    fn sees(&self, what: Seen, material: &Material) -> bool {
        if !names(&self.targets, what) {
            return false;
        }
        match (&self.field, what) {
            (FieldShape::Volume { materials, .. }, Seen::Part { part_type, .. }) if !materials.is_empty() => {
                materials.contains(&material.shapes()[part_type].material)
            }
            _ => true,
        }
    }

    /// A vision sensor's trigger output after the scans: whether it rose
    /// (then [`SensorSim::vision_capture`] takes the picture). Another
    /// kind never rises.
    pub fn vision_rises(&mut self, on: bool) -> bool {
        let FieldShape::Vision(v) = &mut self.field else {
            return false;
        };
        let rose = on && !v.trigger_was;
        v.trigger_was = on;
        rose
    }

    /// A vision sensor's picture at `t`: the part nearest its field's
    /// centre; the result arrives `latency` later
    /// ([`SensorSim::vision_result`]).
    pub fn vision_capture(&mut self, t: f64, material: &Material, links: &[Isometry3<f64>]) {
        let world_from_sensor = self.world_from_sensor(links);
        let all_parts = self.targets.all_parts;
        let part_types = self.targets.part_types.clone();
        let FieldShape::Vision(v) = &mut self.field else { return };
        let field = pose_to_rapier(&world_from_sensor) * v.local;
        let centre = field.translation;
        let mut best: Option<(f64, &crate::plant::material::LivePart)> = None;
        for p in material.parts() {
            let seen = all_parts || part_types.contains(&p.part_type);
            let at = material.part_pose(p).translation;
            if !seen || !v.shape.contains_point(&field, at) {
                continue;
            }
            let d = (at - centre).length();
            if best.is_none_or(|(b, _)| d < b) {
                best = Some((d, p));
            }
        }
        let result = match best {
            None => VisionResult::default(),
            Some((_, p)) => {
                let frame = v.frame.map_or_else(Isometry3::identity, |l| links[l]);
                let part = crate::plant::convert::pose_from_rapier(&material.part_pose(p));
                let relative = frame.inverse() * part;
                let scale = if v.millimetres { 1000.0 } else { 1.0 };
                let x = relative.rotation * nalgebra::Vector3::x();
                VisionResult {
                    found: true,
                    position: [
                        relative.translation.x * scale,
                        relative.translation.y * scale,
                        relative.translation.z * scale,
                    ],
                    angle_deg: x.y.atan2(x.x).to_degrees(),
                    type_id: material.type_id(p.part_type),
                }
            }
        };
        v.pending = Some((t + v.latency_s, result));
    }

    /// A vision sensor's result as it stands at `t` (the last one that
    /// arrived); `None` for another kind.
    pub fn vision_result(&mut self, t: f64) -> Option<VisionResult> {
        let FieldShape::Vision(v) = &mut self.field else {
            return None;
        };
        if let Some((at, r)) = v.pending
            && at <= t + 1e-12
        {
            v.result = r;
            v.pending = None;
        }
        Some(v.result)
    }

    /// The sensor's world pose given the link poses.
    fn world_from_sensor(&self, links: &[Isometry3<f64>]) -> Isometry3<f64> {
        match self.mount {
            Some(l) => links[l] * self.mount_from_sensor,
            None => self.mount_from_sensor,
        }
    }

    /// Whether it rides on a link.
    #[must_use]
    pub fn on_link(&self) -> bool {
        self.mount.is_some()
    }

    /// The output now (after the last step; a camera's: found).
    #[must_use]
    pub fn output(&self) -> bool {
        match &self.field {
            FieldShape::Vision(v) => v.result.found,
            _ => self.signal.output(),
        }
    }

    /// The statistics at `t`.
    #[must_use]
    pub fn stats(&self, t: f64) -> SignalStats {
        self.signal.stats(t)
    }

    /// The tag's value for a scan at `t` (module [`signal`]).
    pub fn tag_at(&mut self, t: f64) -> bool {
        self.signal.tag_at(t)
    }

    /// The lines to draw for it at link poses `links`, in the world: a
    /// beam's segments, a diffuse eye's ray (a zone or proximity field:
    /// none).
    #[must_use]
    pub fn lines_in_world(&self, links: &[Isometry3<f64>]) -> Vec<([f64; 3], [f64; 3])> {
        let pose = self.world_from_sensor(links);
        let at = |v: Vector| {
            let p = pose * nalgebra::Point3::new(v.x, v.y, v.z);
            [p.x, p.y, p.z]
        };
        match &self.field {
            FieldShape::Beams(beams) => beams.iter().map(|b| (at(b.a), at(b.b))).collect(),
            FieldShape::Ray { range_m, .. } => vec![(at(Vector::ZERO), at(Vector::new(*range_m, 0.0, 0.0)))],
            FieldShape::Volume { .. } | FieldShape::Clearance { .. } | FieldShape::Vision(_) => Vec::new(),
        }
    }

    /// The output's changes in the last parts step: (time s, new value).
    #[must_use]
    pub fn step_edges(&self) -> &[(f64, bool)] {
        self.signal.step_changes()
    }

    /// The output's changes so far: (time s, new value).
    #[must_use]
    pub fn edges(&self) -> &[(f64, bool)] {
        self.signal.log()
    }

    /// The value the input module holds (bitmask, distance, count).
    #[must_use]
    pub fn value_taken(&self) -> f64 {
        self.value_taken
    }
}

/// A sensor's field shape as placed in the sensor frame.
fn volume(shape: &Shape, name: &str) -> Option<(Pose, SharedShape)> {
    let geometry = match shape {
        Shape::Box { size_m } => Geometry::Box { size: *size_m },
        Shape::Cylinder { radius_m, length_m } => Geometry::Cylinder {
            radius: *radius_m,
            length: *length_m,
        },
        Shape::Sphere { radius_m } => Geometry::Sphere { radius: *radius_m },
        _ => return None,
    };
    shape_of(&geometry, MeshApproximation::ConvexHull, name)
        .ok()
        .flatten()
        .map(|(local, s)| (pose_to_rapier(&local), s))
}

/// The scene's sensors, built against the robot's links.
///
/// # Errors
/// `(index, field, message)` for a sensor whose `link` or a `detects` link
/// the URDF lacks.
pub fn build(scene: &Scene, model: &RobotModel) -> Result<Vec<SensorSim>, (usize, String, String)> {
    let update_s = scene.coarse_update_s();
    let mut out = Vec::with_capacity(scene.cell.sensors.len());
    for (i, s) in scene.cell.sensors.iter().enumerate() {
        let link_index = |name: &str| model.links.iter().position(|l| l.name == name);
        let known = || {
            model
                .links
                .iter()
                .map(|l| l.name.as_str())
                .collect::<Vec<_>>()
                .join(", ")
        };
        let mount = match &s.link {
            Some((name, _)) => Some(link_index(name).ok_or_else(|| {
                (
                    i,
                    format!("sensors[{i}].link"),
                    format!("the URDF has no link '{name}' (links: {})", known()),
                )
            })?),
            None => None,
        };
        let targets = targets_of(&s.detects, &link_index, &known, |k| {
            format!("sensors[{i}].detects[{k}]")
        })
        .map_err(|(field, message)| (i, field, message))?;
        let field = match &s.kind {
            SensorKind::Beam { from_m, to_m, curtain } => {
                let (count, pitch) = curtain.unwrap_or((1, 0.0));
                FieldShape::Beams(
                    (0..count)
                        .map(|b| {
                            let dz = f64::from(b) * pitch;
                            Segment::new(
                                Vector::new(from_m[0], from_m[1], from_m[2] + dz),
                                Vector::new(to_m[0], to_m[1], to_m[2] + dz),
                            )
                        })
                        .collect(),
                )
            }
            SensorKind::Diffuse { range_m, scale } => FieldShape::Ray {
                range_m: *range_m,
                scale: *scale,
            },
            SensorKind::Proximity { field, materials } => {
                let (local, shape) = volume(field, &s.name)
                    .ok_or_else(|| (i, format!("sensors[{i}].shape"), "the field has no volume".to_owned()))?;
                FieldShape::Volume {
                    shape,
                    local,
                    materials: materials.clone(),
                }
            }
            SensorKind::Zone { field } => {
                let (local, shape) = volume(field, &s.name)
                    .ok_or_else(|| (i, format!("sensors[{i}].shape"), "the zone has no volume".to_owned()))?;
                FieldShape::Volume {
                    shape,
                    local,
                    materials: Vec::new(),
                }
            }
            SensorKind::Clearance { between, below_m } => {
                let mut groups = [Targets::default(), Targets::default()];
                for (g, list) in between.iter().enumerate() {
                    groups[g] = targets_of(list, &link_index, &known, |k| format!("sensors[{i}].between[{g}][{k}]"))
                        .map_err(|(field, message)| (i, field, message))?;
                }
                FieldShape::Clearance {
                    groups: Box::new(groups),
                    below_m: *below_m,
                }
            }
            SensorKind::Vision(v) => {
                let crate::scene::VisionSpec {
                    field,
                    latency_s,
                    frame,
                    millimetres,
                    ..
                } = &**v;
                let (local, shape) = volume(field, &s.name).ok_or_else(|| {
                    (
                        i,
                        format!("sensors[{i}].shape"),
                        "the field of view has no volume".to_owned(),
                    )
                })?;
                let frame = match frame {
                    Some((name, _)) => Some(link_index(name).ok_or_else(|| {
                        (
                            i,
                            format!("sensors[{i}].frame"),
                            format!("the URDF has no link '{name}' (links: {})", known()),
                        )
                    })?),
                    None => None,
                };
                FieldShape::Vision(Box::new(Vision {
                    shape,
                    local,
                    latency_s: *latency_s,
                    frame,
                    millimetres: *millimetres,
                    trigger_was: false,
                    pending: None,
                    result: VisionResult::default(),
                }))
            }
        };
        let idle_value = match &field {
            FieldShape::Ray { range_m, scale } => scaled(*range_m, *scale),
            _ => 0.0,
        };
        out.push(SensorSim {
            name: s.name.clone(),
            field,
            mount,
            mount_from_sensor: pose_from_xyz_rpy_deg(s.position_m, s.rpy_deg),
            targets,
            signal: Signal::new(
                s.invert,
                (s.on_delay_s, s.off_delay_s),
                s.rpi_s.unwrap_or(update_s),
                s.cos,
                s.faults.clone(),
            ),
            detected: false,
            value: idle_value,
            value_taken: idle_value,
            registration: s.registration,
        });
    }
    Ok(out)
}

/// What a `detects` list (or a clearance group) names, resolved; a link
/// the URDF lacks is `(field, message)`.
fn targets_of(
    list: &[Detect],
    link_index: &dyn Fn(&str) -> Option<usize>,
    known: &dyn Fn() -> String,
    field: impl Fn(usize) -> String,
) -> Result<Targets, (String, String)> {
    let mut targets = Targets::default();
    for (k, d) in list.iter().enumerate() {
        match d {
            Detect::Parts => targets.all_parts = true,
            Detect::PartType(p) => targets.part_types.push(*p),
            Detect::Robot => targets.robot = true,
            Detect::Obstacle(o) => targets.obstacles.push(*o),
            Detect::Link(name) => targets.links.push(link_index(name).ok_or_else(|| {
                (
                    field(k),
                    format!(
                        "'{name}' is not 'parts', 'robot', a part type, an obstacle or a URDF link (links: {})",
                        known()
                    ),
                )
            })?),
        }
    }
    Ok(targets)
}

/// Whether `targets` names a body.
fn names(targets: &Targets, what: Seen) -> bool {
    match what {
        Seen::Part { part_type, .. } => targets.all_parts || targets.part_types.contains(&part_type),
        Seen::Link(l) => targets.robot || targets.links.contains(&l),
        Seen::Obstacle(o) => targets.obstacles.contains(&o),
    }
}

/// A diffuse eye's distance through its `scale`.
fn scaled(distance_m: f64, scale: Option<[[f64; 2]; 2]>) -> f64 {
    match scale {
        Some([[d0, v0], [d1, v1]]) => v0 + (distance_m - d0) * (v1 - v0) / (d1 - d0),
        None => distance_m,
    }
}

/// Every body the sensors can see over the step `(t0, t1]`.
fn bodies<'a>(material: &'a Material, links0: &[Isometry3<f64>], links1: &[Isometry3<f64>]) -> Vec<Body<'a>> {
    let mut out = Vec::new();
    let mut push = |shape: &'a SharedShape, start: Pose, end: Pose, what: Seen| {
        let aabb = shape.compute_aabb(&start).merged(&shape.compute_aabb(&end));
        out.push(Body {
            moving: Moving {
                shape: shape.as_ref(),
                start,
                end,
            },
            aabb,
            what,
        });
    };
    for p in material.parts() {
        let s = &material.shapes()[p.part_type];
        push(
            &s.shape,
            material.part_pose_before(p) * s.part_from_shape,
            material.part_pose(p) * s.part_from_shape,
            Seen::Part {
                part_type: p.part_type,
                id: p.id,
            },
        );
    }
    for (link, shapes) in material.link_shapes() {
        let (a, b) = (pose_to_rapier(&links0[link]), pose_to_rapier(&links1[link]));
        for (local, shape) in shapes {
            push(shape, a * *local, b * *local, Seen::Link(link));
        }
    }
    for (k, (pose, shape)) in material.obstacle_shapes().iter().enumerate() {
        push(shape, *pose, *pose, Seen::Obstacle(k));
    }
    out
}

/// One parts step `(t0, t1]` for every sensor: the links at `links0` at
/// its start and `links1` at its end.
pub fn step(
    sensors: &mut [SensorSim],
    material: &Material,
    (t0, t1): (f64, f64),
    links0: &[Isometry3<f64>],
    links1: &[Isometry3<f64>],
) {
    if sensors.is_empty() {
        return;
    }
    let all = bodies(material, links0, links1);
    let dt = t1 - t0;
    for s in sensors.iter_mut() {
        if let FieldShape::Vision(_) = s.field {
            continue;
        }
        if let FieldShape::Clearance { groups, below_m } = &s.field {
            let distance = clearance(&all, groups);
            let below = distance < *below_m;
            let changes: Vec<(f64, bool)> = if below == s.detected {
                Vec::new()
            } else {
                vec![(t1, below)]
            };
            s.detected = below;
            s.value = distance;
            s.signal.feed(t0, t1, &changes);
            if s.signal.updated_in(t0, t1) {
                s.value_taken = s.value;
            }
            continue;
        }
        let a = pose_to_rapier(&s.world_from_sensor(links0));
        let b = pose_to_rapier(&s.world_from_sensor(links1));
        let candidates: Vec<&Body<'_>> = all.iter().filter(|x| s.sees(x.what, material)).collect();
        let mut intervals = Vec::new();
        let mut value = 0.0;
        let mut seen_at_end: Vec<Seen> = Vec::new();
        let mut overlap_with = |shape: &dyn rapier3d_f64::parry::shape::Shape, local: Pose| {
            let field = Moving {
                shape,
                start: a * local,
                end: b * local,
            };
            let field_box = shape.compute_aabb(&field.start).merged(&shape.compute_aabb(&field.end));
            let mut any_at_end = false;
            for body in &candidates {
                if !field_box.intersects(&body.aabb) {
                    continue;
                }
                if let Some((enter, leave)) = overlap_in_step(&field, &body.moving) {
                    intervals.push((enter, leave));
                    if leave >= 1.0 {
                        any_at_end = true;
                        if !seen_at_end.contains(&body.what) {
                            seen_at_end.push(body.what);
                        }
                    }
                }
            }
            any_at_end
        };
        match &s.field {
            FieldShape::Beams(beams) => {
                let mut mask = 0u32;
                for (k, beam) in beams.iter().enumerate() {
                    if overlap_with(beam, Pose::IDENTITY) {
                        mask |= 1 << k;
                    }
                }
                value = f64::from(mask);
            }
            FieldShape::Ray { range_m, scale } => {
                let segment = Segment::new(Vector::ZERO, Vector::new(*range_m, 0.0, 0.0));
                overlap_with(&segment, Pose::IDENTITY);
                let ray = Ray::new(b.translation, b.rotation * Vector::X);
                let nearest = candidates
                    .iter()
                    .filter_map(|body| body.moving.shape.cast_ray(&body.moving.end, &ray, *range_m, true))
                    .fold(*range_m, f64::min);
                value = scaled(nearest, *scale);
            }
            FieldShape::Volume { shape, local, .. } => {
                overlap_with(shape.as_ref(), *local);
            }
            FieldShape::Clearance { .. } | FieldShape::Vision(_) => {}
        }
        if let FieldShape::Volume { .. } = s.field {
            value = seen_at_end.len() as f64;
        }
        let (changes, detected) = changes_of(intervals, s.detected);
        s.detected = detected;
        s.value = value;
        let absolute: Vec<(f64, bool)> = changes.iter().map(|&(f, d)| (t0 + f * dt, d)).collect();
        s.signal.feed(t0, t1, &absolute);
        if s.signal.updated_in(t0, t1) {
            s.value_taken = s.value;
        }
    }
}

/// The smallest distance between a body of one group and a body of the
/// other (a body in both is not measured against itself), at the step's
/// end, m; infinite when a group is empty.
fn clearance(all: &[Body<'_>], groups: &[Targets; 2]) -> f64 {
    let a: Vec<&Body<'_>> = all.iter().filter(|x| names(&groups[0], x.what)).collect();
    let b: Vec<&Body<'_>> = all.iter().filter(|x| names(&groups[1], x.what)).collect();
    let mut best = f64::INFINITY;
    for x in &a {
        let xa = x.moving.shape.compute_aabb(&x.moving.end);
        for y in &b {
            if x.what == y.what {
                continue;
            }
            let ya = y.moving.shape.compute_aabb(&y.moving.end);
            let gap = (xa.mins - ya.maxs).max(ya.mins - xa.maxs).max(Vector::ZERO).length();
            if gap >= best {
                continue;
            }
            if let Ok(d) =
                rapier3d_f64::parry::query::distance(&x.moving.end, x.moving.shape, &y.moving.end, y.moving.shape)
            {
                best = best.min(d.distance);
            }
        }
    }
    best
}
