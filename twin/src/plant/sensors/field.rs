//! When a sensor's field and a body overlap inside one step, from their
//! motion: each moves rigidly from its pose at the step's start to its pose
//! at its end (constant linear and angular velocity, parry's nonlinear
//! shape casting, as the live collision check's continuous detection
//! does). A body that enters and leaves the field inside the step gives
//! both times, so a pulse shorter than a step is seen.

use rapier3d_f64::math::{Pose, Vector};
use rapier3d_f64::parry::query::{self, NonlinearRigidMotion};
use rapier3d_f64::parry::shape::Shape;

/// A shape moving over a step: its pose at the start and at the end.
#[derive(Clone, Copy)]
pub struct Moving<'a> {
    /// The shape.
    pub shape: &'a dyn Shape,
    /// Pose at the step's start.
    pub start: Pose,
    /// Pose at the step's end.
    pub end: Pose,
}

impl Moving<'_> {
    /// The motion over the step's fraction `[0, 1]`, forwards or backwards.
    fn motion(&self, backwards: bool) -> NonlinearRigidMotion {
        let (from, to) = if backwards {
            (self.end, self.start)
        } else {
            (self.start, self.end)
        };
        let linvel = to.translation - from.translation;
        let angvel = (to.rotation * from.rotation.inverse()).to_scaled_axis();
        NonlinearRigidMotion::new(from, Vector::ZERO, linvel, angvel)
    }

    fn at(&self, end: bool) -> Pose {
        if end { self.end } else { self.start }
    }
}

/// Whether two shapes overlap at poses `a` and `b` (an unsupported pair:
/// no).
#[must_use]
pub fn overlaps(a: &dyn Shape, pa: &Pose, b: &dyn Shape, pb: &Pose) -> bool {
    query::intersection_test(pa, a, pb, b).is_ok_and(|hit| hit.intersecting)
}

/// The first time in `[0, 1]` at which the two, moving, touch.
fn first_touch(field: &Moving<'_>, body: &Moving<'_>, backwards: bool) -> Option<f64> {
    query::cast_shapes_nonlinear(
        &field.motion(backwards),
        field.shape,
        &body.motion(backwards),
        body.shape,
        0.0,
        1.0,
        true,
    )
    .ok()
    .flatten()
    .map(|hit| hit.time_of_impact.clamp(0.0, 1.0))
}

/// The part of the step, as fractions `(enter, leave)` of it, during which
/// the field and the body overlap; `None` when they never do. One
/// interval a step: a body that leaves and comes back inside one step is
/// seen as staying.
#[must_use]
pub fn overlap_in_step(field: &Moving<'_>, body: &Moving<'_>) -> Option<(f64, f64)> {
    let at = |end: bool| overlaps(field.shape, &field.at(end), body.shape, &body.at(end));
    match (at(false), at(true)) {
        (true, true) => Some((0.0, 1.0)),
        (true, false) => Some((0.0, 1.0 - first_touch(field, body, true).unwrap_or(0.0))),
        (false, true) => Some((first_touch(field, body, false).unwrap_or(1.0), 1.0)),
        (false, false) => {
            let enter = first_touch(field, body, false)?;
            if enter >= 1.0 {
                return None;
            }
            let leave = 1.0 - first_touch(field, body, true).unwrap_or(1.0 - enter);
            Some((enter, leave.max(enter)))
        }
    }
}

/// The union of intervals of one step as the changes of the detected state
/// inside it: `(fraction, detected)` in time order, starting from
/// `detected_at_start` (changes at the very start are folded into it).
#[must_use]
pub fn changes_of(mut intervals: Vec<(f64, f64)>, detected_at_start: bool) -> (Vec<(f64, bool)>, bool) {
    intervals.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut merged: Vec<(f64, f64)> = Vec::with_capacity(intervals.len());
    for (a, b) in intervals {
        match merged.last_mut() {
            Some(last) if a <= last.1 => last.1 = last.1.max(b),
            _ => merged.push((a, b)),
        }
    }
    let mut changes = Vec::new();
    let mut state = detected_at_start;
    // Nothing overlaps at the step's start: what was seen is gone.
    if state && merged.first().is_none_or(|(a, _)| *a > 0.0) {
        changes.push((0.0, false));
        state = false;
    }
    for (a, b) in merged {
        if !state {
            changes.push((a, true));
            state = true;
        }
        if b < 1.0 {
            changes.push((b, false));
            state = false;
        }
    }
    (changes, state)
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;
    use rapier3d_f64::parry::shape::{Ball, Cuboid, Segment};

    fn at(x: f64) -> Pose {
        Pose::from_translation(Vector::new(x, 0.0, 0.0))
    }

    #[test]
    fn a_box_crossing_a_beam_inside_one_step_gives_both_edges() {
        // A 10 mm box moving 100 mm in the step across a beam at x = 0.05:
        // it touches the beam from x_centre = 0.045 to 0.055.
        let beam = Segment::new(Vector::new(0.05, -1.0, 0.0), Vector::new(0.05, 1.0, 0.0));
        let cube = Cuboid::new(Vector::splat(0.005));
        let field = Moving {
            shape: &beam,
            start: Pose::IDENTITY,
            end: Pose::IDENTITY,
        };
        let body = Moving {
            shape: &cube,
            start: at(0.0),
            end: at(0.1),
        };
        let (a, b) = overlap_in_step(&field, &body).unwrap();
        assert!((a - 0.45).abs() < 1e-4, "{a}");
        assert!((b - 0.55).abs() < 1e-4, "{b}");
        let (changes, end) = changes_of(vec![(a, b)], false);
        assert_eq!(changes.len(), 2);
        assert!(!end);
    }

    #[test]
    fn a_ball_staying_clear_or_inside_gives_no_edge() {
        let zone = Cuboid::new(Vector::splat(0.1));
        let ball = Ball::new(0.01);
        let field = Moving {
            shape: &zone,
            start: Pose::IDENTITY,
            end: Pose::IDENTITY,
        };
        let inside = Moving {
            shape: &ball,
            start: at(0.0),
            end: at(0.01),
        };
        assert_eq!(overlap_in_step(&field, &inside), Some((0.0, 1.0)));
        let clear = Moving {
            shape: &ball,
            start: at(0.5),
            end: at(0.6),
        };
        assert_eq!(overlap_in_step(&field, &clear), None);
        assert_eq!(changes_of(vec![], true), (vec![(0.0, false)], false));
        assert_eq!(changes_of(vec![(0.0, 1.0)], true), (vec![], true));
    }
}
