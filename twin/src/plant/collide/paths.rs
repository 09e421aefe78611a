//! The paths a pre-flight sweep follows: a MoveModulo move's axis
//! profile, and a coordinated move's path (through its axes' joints or
//! through an MCT transform's inverse kinematics), each with bounds of its
//! joints' rates along the path.

use super::super::axes::AxisJoint;
use super::super::collision::sweep::PathSampler;
use super::super::transform::ParallelRig;
use super::super::urdf::RobotModel;
use planner::coord::{CoordMove, PathGeometry};
use planner::mct::instruction::Transform;
use planner::mct::{PositionError, Vec3};
use planner::profile::Profile;

/// An MC_MoveModulo profile as a path: `s` = axis units travelled.
pub(super) struct AxisMovePath {
    pub(super) profile: Profile,
    pub(super) start: f64,
    pub(super) direction: f64,
    pub(super) axis: AxisJoint,
    pub(super) base: Vec<f64>,
}

/// The time at which a nondecreasing path profile reaches `s` (bisection).
pub(super) fn profile_time_of(profile: &Profile, start: f64, direction: f64, s: f64) -> f64 {
    let (mut lo, mut hi) = (0.0, profile.duration_s());
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if (profile.sample(mid).position - start) * direction < s {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    hi
}

/// Joint positions of the robot with a coordinate system's axes at
/// `coordinates` (one per axis of the system, coordinate units): each axis
/// drives its joint (`None`: an axis without a joint), every other joint
/// keeps its value in `base`. The one place where coordinates become joint
/// positions: a coordinate transform (MCT) replaces this mapping.
pub(super) fn joints_from_coordinates(axes: &[Option<AxisJoint>], coordinates: &[f64], base: &[f64]) -> Vec<f64> {
    let mut q = base.to_vec();
    for (a, c) in axes.iter().zip(coordinates) {
        if let Some(a) = a {
            q[a.joint] = a.joint_position(*c);
        }
    }
    q
}

/// An MCLM line or MCCM arc as a path: `s` = path length along the move
/// from its programmed start point, coordinate units.
pub(super) struct CoordMovePath {
    pub(super) path: PathGeometry,
    pub(super) profile: Profile,
    pub(super) axes: Vec<Option<AxisJoint>>,
    pub(super) base: Vec<f64>,
    pub(super) rates: Vec<f64>,
    /// The transform the system is the source of, with its sampled path.
    pub(super) transform: Option<TransformPath>,
}

/// Grid points per path for the transform's rate estimate
/// ([`TransformPath`]).
const TRANSFORM_GRID: usize = 1024;

/// Safety factor of the transform's joint-rate estimate over the largest
/// finite difference on the grid.
const TRANSFORM_RATE_MARGIN: f64 = 2.0;

/// How an MCT source system's coordinates become joint positions.
#[derive(Clone)]
pub(super) struct TransformMapping {
    pub(super) transform: Transform,
    /// Per transform source axis, its index in the system's coordinates.
    pub(super) source_index: Vec<usize>,
    /// Per transform target axis, its joint.
    pub(super) target: Vec<Option<AxisJoint>>,
    /// A parallel robot's virtual joints, posed from the target joints.
    pub(super) rig: Option<(ParallelRig, RobotModel)>,
}

/// A move of an MCT source system, sampled on a grid of
/// [`TRANSFORM_GRID`] steps: the joints at each grid point (revolute
/// joints unwrapped point to point from the transform's last command, on
/// its arm solution) are the references the sweep's samples unwrap to.
pub(super) struct TransformPath {
    pub(super) mapping: TransformMapping,
    pub(super) step: f64,
    /// Per grid point: target joints (axis units), virtual joints.
    pub(super) references: Vec<(Vec3, Vec<f64>)>,
    /// The path length up to which every grid point is reachable.
    pub(super) reach: f64,
    /// First point the transform cannot reach: path length, why.
    pub(super) unreachable: Option<(f64, PositionError)>,
}

impl TransformMapping {
    /// Joint positions at coordinates `p` (the system's axes), with the
    /// target joints and virtual joints unwrapped near `near`.
    pub(super) fn joints(
        &self,
        axes: &[Option<AxisJoint>],
        p: &[f64],
        base: &[f64],
        near: &(Vec3, Vec<f64>),
    ) -> Result<(Vec<f64>, Vec3, Vec<f64>), PositionError> {
        let mut q = joints_from_coordinates(axes, p, base);
        let mut source = [0.0; 3];
        for (x, &i) in source.iter_mut().zip(&self.source_index) {
            *x = p[i];
        }
        let j = self.transform.joints_near(source, near.0)?;
        for (k, a) in self.target.iter().enumerate() {
            if let Some(a) = a {
                q[a.joint] = a.joint_position(j[k]);
            }
        }
        let mut virtual_q = Vec::new();
        if let Some((rig, model)) = &self.rig {
            let arms: Vec<f64> = self.target.iter().map(|a| a.map_or(0.0, |a| q[a.joint])).collect();
            virtual_q = rig
                .virtual_pose(model, &arms, &near.1)
                .ok_or(PositionError::NotFinite)?;
            for (&joint, v) in rig.virtual_joints().iter().zip(&virtual_q) {
                q[joint] = *v;
            }
        }
        Ok((q, j, virtual_q))
    }
}

impl TransformPath {
    /// Samples the transform along `path` on the grid, raising `rates` to
    /// the joint speeds the grid shows (with a margin).
    pub(super) fn sample(
        mapping: TransformMapping,
        path: &PathGeometry,
        axes: &[Option<AxisJoint>],
        base: &[f64],
        rates: &mut [f64],
    ) -> Self {
        let length = path.length();
        let n = path.start().len();
        let step = length / TRANSFORM_GRID as f64;
        let (mut p, mut d) = (vec![0.0; n], vec![0.0; n]);
        let mut at = |s: f64, near: &(Vec3, Vec<f64>)| {
            path.point(s, &mut p, &mut d);
            mapping.joints(axes, &p, base, near)
        };
        let start_near = (
            mapping.transform.joint_command().positions,
            mapping
                .rig
                .as_ref()
                .map(|(r, _)| r.previous().to_vec())
                .unwrap_or_default(),
        );
        let mut references = Vec::with_capacity(TRANSFORM_GRID + 1);
        let mut estimate = vec![0.0_f64; base.len()];
        let mut previous: Option<Vec<f64>> = None;
        let mut unreachable = None;
        for i in 0..=TRANSFORM_GRID {
            let s = if i == TRANSFORM_GRID { length } else { i as f64 * step };
            let near = references.last().cloned().unwrap_or_else(|| start_near.clone());
            match at(s, &near) {
                Ok((q, j, v)) => {
                    if let Some(prev) = &previous {
                        for (e, (a, b)) in estimate.iter_mut().zip(q.iter().zip(prev)) {
                            *e = e.max((a - b).abs() / step);
                        }
                    }
                    previous = Some(q);
                    references.push((j, v));
                }
                Err(e) => {
                    // The first unreachable point: bisection between
                    // the last reachable grid point and this one.
                    let (mut lo, mut hi, mut why) = (s - step, s, e);
                    if i > 0 {
                        for _ in 0..60 {
                            let mid = 0.5 * (lo + hi);
                            match at(mid, &near) {
                                Ok(_) => lo = mid,
                                Err(e) => (hi, why) = (mid, e),
                            }
                        }
                    } else {
                        hi = 0.0;
                    }
                    unreachable = Some((hi, why));
                    break;
                }
            }
        }
        for (r, e) in rates.iter_mut().zip(&estimate) {
            *r = r.max(TRANSFORM_RATE_MARGIN * e);
        }
        let reach = unreachable.as_ref().map_or(length, |(s, _)| {
            // The last reachable grid point.
            (s / step).floor().min(references.len().saturating_sub(1) as f64) * step
        });
        TransformPath {
            mapping,
            step,
            references,
            reach,
            unreachable,
        }
    }
}

impl CoordMovePath {
    pub(super) fn new(
        mv: &CoordMove,
        profile: &Profile,
        primary: usize,
        axes: Vec<Option<AxisJoint>>,
        base: Vec<f64>,
        transform: Option<TransformMapping>,
    ) -> Self {
        let path = mv.path().clone();
        let length = path.length();
        let is_arc = path.arc().is_some();
        let mut rates = vec![0.0; base.len()];
        for (i, a) in axes.iter().enumerate() {
            let Some(a) = a else { continue };
            let per_s = if is_arc && i < primary {
                1.0
            } else if length > 0.0 {
                (path.end()[i] - path.start()[i]).abs() / length
            } else {
                0.0
            };
            rates[a.joint] += per_s * a.si_per_unit.abs() * (1.0 + 1e-9);
        }
        let transform = transform.map(|mapping| TransformPath::sample(mapping, &path, &axes, &base, &mut rates));
        Self {
            path,
            profile: profile.clone(),
            axes,
            base,
            rates,
            transform,
        }
    }
}

impl PathSampler for CoordMovePath {
    fn length(&self) -> f64 {
        self.transform.as_ref().map_or(self.path.length(), |t| t.reach)
    }
    fn joint_positions(&self, s: f64) -> Vec<f64> {
        let n = self.path.start().len();
        let (mut p, mut d) = (vec![0.0; n], vec![0.0; n]);
        self.path.point(s, &mut p, &mut d);
        match &self.transform {
            None => joints_from_coordinates(&self.axes, &p, &self.base),
            Some(t) => {
                let k = if t.step > 0.0 {
                    ((s / t.step).floor().max(0.0) as usize).min(t.references.len().saturating_sub(1))
                } else {
                    0
                };
                let Some(near) = t.references.get(k) else {
                    return joints_from_coordinates(&self.axes, &p, &self.base);
                };
                // Between two reachable grid points a point that is not
                // reachable keeps the grid point's joints.
                t.mapping
                    .joints(&self.axes, &p, &self.base, near)
                    .map(|(q, _, _)| q)
                    .unwrap_or_else(|_| {
                        let mut p0 = vec![0.0; n];
                        self.path.point(k as f64 * t.step, &mut p0, &mut d);
                        t.mapping
                            .joints(&self.axes, &p0, &self.base, near)
                            .map(|(q, _, _)| q)
                            .unwrap_or_else(|_| self.base.clone())
                    })
            }
        }
    }
    fn joint_rate_bounds(&self) -> Vec<f64> {
        self.rates.clone()
    }
    fn time_s(&self, s: f64) -> f64 {
        profile_time_of(&self.profile, 0.0, 1.0, s)
    }
}

impl PathSampler for AxisMovePath {
    fn length(&self) -> f64 {
        (self.profile.final_state().position - self.start).abs()
    }
    fn joint_positions(&self, s: f64) -> Vec<f64> {
        let mut q = self.base.clone();
        q[self.axis.joint] = self.axis.joint_position(self.start + self.direction * s);
        q
    }
    fn joint_rate_bounds(&self) -> Vec<f64> {
        let mut r = vec![0.0; self.base.len()];
        r[self.axis.joint] = self.axis.si_per_unit.abs();
        r
    }
    fn time_s(&self, s: f64) -> f64 {
        profile_time_of(&self.profile, self.start, self.direction, s)
    }
}
