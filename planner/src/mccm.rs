//! MCCM, Motion Coordinated Circular Move: a 2D or 3D arc or full circle
//! through the primary axes of a coordinate system.
//!
//! # What the spec says, and how it is implemented
//! * **Dimension** is the number of primary axes: 2 → a 2D circle in the
//!   plane of the two axes; 3 → a 3D circle, even when the three points lie
//!   in a coordinate plane. Any other count is ERR 13, EXERR 0.
//! * **Move Type × Circle Type** (the spec's behaviour table): the end point
//!   is `Position` (absolute) or old position + `Position` (incremental);
//!   the via point / center is the array (absolute) or old position + array
//!   (incremental); **Center Incremental** is always old position + array;
//!   **Radius** is the first array element whatever the move type. For a
//!   full circle the end point is "any second point along the circle": the
//!   move goes once round and ends at its start.
//! * **Direction** (codes 0–3): 2D — 0 CW, 1 CCW, 2 CW full, 3 CCW full,
//!   as seen from the + perpendicular of the plane (the right-hand rule:
//!   CCW turns the first axis toward the second). 3D — 0 shortest,
//!   1 longest, 2 shortest full, 3 longest full. (The spec's table is
//!   garbled; these are the Logix enumerations it abbreviates.)
//! * **Via**: the via point always decides the turning sense (start → via →
//!   end); Direction only selects partial (0, 1) or full (2, 3).
//!   Errors: 44 collinear points, 45 end = start.
//! * **Center** (and center incremental): 2D — CW/CCW as above; end = start
//!   is legal and gives a full circle with every direction. 3D — the plane
//!   is start, center, end; shortest turns the short way from start to end,
//!   longest the long way; the full variants turn once round in that sense.
//!   Errors: 44 start, center, end collinear (3D), 45 end = start (3D),
//!   46 |R1 − R2| > 0.15 · R1.
//! * **Radius** (2D only, else ERR 25): a positive radius takes the arc of
//!   at most 180°, a negative one the arc of at least 180°, in the
//!   direction given; the full variants go once round the circle that the
//!   partial move would use. Errors: 45 end = start, 49 |R| < 0.001 or
//!   |R| shorter than half the chord.
//!
//! # Choices where the spec is silent
//! * ERR 46 compares |R1 − R2| (the spec writes R1 − R2; an end point
//!   outside the circle is as wrong as one inside). Within 15 % the path is
//!   a planar spiral whose radius changes linearly with the angle, so it
//!   ends exactly at the programmed end point; its path length is measured
//!   as `k · angle` with `k = √(R_max² + (ΔR/angle)²)`, which is never
//!   shorter than the true length, so the vector speed never exceeds the
//!   programmed speed (it is slightly lower on the smaller radius).
//! * ERR 49 also applies to center and via circles whose radius is below
//!   0.001 (a circle that small has no usable plane).
//! * A semicircle programmed with the radius (|R| = half chord) is legal.
//! * The geometry errors come after every ERR 13 check, ERR 54 last.
//! * Coordinates so large that the circle's radius or length overflows
//!   are ERR 13 with the Via/Center/Radius operand's index.

use crate::coord::{
    CoordFault, CoordMove, CoordMoveError, CoordMoveInputs, MoveContext, MoveType, OperandIndex, PathGeometry,
    finish_move, out_of_range, primary_of, resolve_move_type_and_position, same_point,
};
use crate::instruction::Refusal;
use crate::vector::{V3, add, cross, dot, norm, scale, sub};
use std::f64::consts::{PI, TAU};

/// The arc an MCCM path follows (it lives with the path geometry).
pub use crate::coord::Arc;

/// The smallest radius a circle may have (ERR 49 below), coordinate units.
pub const MIN_RADIUS: f64 = 0.001;

/// Circle Type 0–3.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CircleType {
    /// `0` — via point.
    Via,
    /// `1` — center (absolute or incremental with the move type).
    Center,
    /// `2` — radius (2D only).
    Radius,
    /// `3` — center, always incremental from the start point.
    CenterIncremental,
}

impl CircleType {
    /// The type for a Logix code, or `None`.
    pub fn from_code(code: i64) -> Option<Self> {
        Some(match code {
            0 => Self::Via,
            1 => Self::Center,
            2 => Self::Radius,
            3 => Self::CenterIncremental,
            _ => return None,
        })
    }
}

/// MCCM operands: the shared coordinated-move operands plus the circle's.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct MccmInputs {
    /// Move type, position, dynamics, termination, merge, lock, events.
    pub common: CoordMoveInputs,
    /// Circle Type (0 via, 1 center, 2 radius, 3 center incremental).
    pub circle_type: i64,
    /// Via/Center/Radius: the via point or center (one element per primary
    /// axis at least), or the radius in element 0.
    pub via_center_radius: Vec<f64>,
    /// Direction (0–3, see the module doc).
    pub direction: i64,
}

/// MCCM: verifies the operands against the system and start point and
/// builds the move.
///
/// # Errors
/// [`CoordMoveError`] with the spec's ERR/EXERR: 13 (operand index, see
/// [`OperandIndex::MCCM`]), 25, 44, 45, 46, 49, 54.
///
/// # Examples
/// A 2D half circle through a via point, then the same points on a 3D
/// system with the radius circle type, which is 2D only (ERR 25):
/// ```
/// use planner::coord::{CoordMoveInputs, CoordinateSystem, CoordinateSystemConfig, MoveContext};
/// use planner::instruction::LogixFault;
/// use planner::mccm::{MccmInputs, mccm};
/// let xy = CoordinateSystem::new(CoordinateSystemConfig {
///     axis_count: 2,
///     primary_axes: 2,
///     ..CoordinateSystemConfig::new("XY")
/// })
/// .unwrap();
/// let ctx = MoveContext { system: &xy, axis_max_decel: &[10.0, 10.0], start: &[1.0, 0.0], has_master: false };
/// let inputs = MccmInputs {
///     common: CoordMoveInputs { position: vec![-1.0, 0.0], ..Default::default() },
///     circle_type: 0,
///     via_center_radius: vec![0.0, 1.0],
///     direction: 0,
/// };
/// let arc = mccm(&inputs, &ctx).unwrap();
/// assert!((arc.path().length() - std::f64::consts::PI).abs() < 1e-12);
///
/// let xyz = CoordinateSystem::new(CoordinateSystemConfig::new("XYZ")).unwrap();
/// let ctx = MoveContext { system: &xyz, axis_max_decel: &[10.0; 3], start: &[1.0, 0.0, 0.0], has_master: false };
/// let radius = MccmInputs {
///     common: CoordMoveInputs { position: vec![-1.0, 0.0, 0.0], ..Default::default() },
///     circle_type: 2,
///     via_center_radius: vec![1.0],
///     direction: 0,
/// };
/// let e = mccm(&radius, &ctx).unwrap_err();
/// assert_eq!((e.err(), e.exerr()), (25, 0));
/// ```
pub fn mccm(inputs: &MccmInputs, ctx: &MoveContext<'_>) -> Result<CoordMove, CoordMoveError> {
    let idx = OperandIndex::MCCM;
    let sys = ctx.system.config();
    let dim = sys.primary_axes;
    if !(dim == 2 || dim == 3) {
        return Err(out_of_range(idx.coordinate_system));
    }
    let resolved = resolve_move_type_and_position(&inputs.common, ctx, &idx)?;
    let circle = CircleType::from_code(inputs.circle_type).ok_or(out_of_range(idx.circle_type))?;
    let vcr = &inputs.via_center_radius;
    let needed = if circle == CircleType::Radius { 1 } else { dim };
    if vcr.len() < needed || vcr[..needed].iter().any(|v| !v.is_finite()) {
        return Err(out_of_range(idx.via_center_radius));
    }
    if !(0..=3).contains(&inputs.direction) {
        return Err(out_of_range(idx.direction));
    }
    let direction = inputs.direction;
    let start = resolved.start.clone();
    let end = resolved.end.clone();
    let p0 = primary_of(&start, dim);
    let p1 = primary_of(&end, dim);
    let aux = || -> V3 {
        let mut v = [0.0; 3];
        v[..dim].copy_from_slice(&vcr[..dim]);
        let incremental = match circle {
            CircleType::CenterIncremental => true,
            _ => resolved.move_type == MoveType::Incremental,
        };
        if incremental { add(p0, v) } else { v }
    };
    let geometry = move || -> Result<PathGeometry, CoordMoveError> {
        let full = direction >= 2;
        let arc = match circle {
            CircleType::Via => via_arc(p0, aux(), p1, full)?,
            CircleType::Center | CircleType::CenterIncremental => center_arc(p0, aux(), p1, direction, dim)?,
            CircleType::Radius => {
                if dim == 3 {
                    return Err(Refusal::Instruction(CoordFault::RadiusIn3d));
                }
                radius_arc(p0, vcr[0], p1, direction)?
            }
        };
        if !arc.is_finite() {
            // Coordinates so large that the circle overflows.
            return Err(out_of_range(idx.via_center_radius));
        }
        let mut end = end;
        if full {
            // A full circle ends where it started; `Position` only defined the circle.
            end[..dim].copy_from_slice(&start[..dim]);
        }
        Ok(PathGeometry::circular(start, end, dim, arc))
    };
    finish_move(&inputs.common, ctx, &idx, geometry)
}

fn check_radius(r: f64) -> Result<(), CoordMoveError> {
    if r < MIN_RADIUS {
        Err(Refusal::Instruction(CoordFault::RadiusTooSmall { radius: r }))
    } else {
        Ok(())
    }
}

fn collinear(a: V3, b: V3) -> bool {
    let (na, nb) = (norm(a), norm(b));
    na == 0.0 || nb == 0.0 || norm(cross(a, b)) <= 1e-9 * na * nb
}

/// Angle from `u` to `v` turning positively about `normal`, in [0, 2π).
fn angle_about(u: V3, v: V3, normal: V3) -> f64 {
    let a = norm(cross(u, v)).atan2(dot(u, v));
    let a = if dot(cross(u, v), normal) < 0.0 { TAU - a } else { a };
    if a >= TAU { 0.0 } else { a }
}

fn via_arc(p0: V3, via: V3, p1: V3, full: bool) -> Result<Arc, CoordMoveError> {
    if same_point(p0, p1) {
        return Err(Refusal::Instruction(CoordFault::EndpointEqualsStartpoint));
    }
    let (a, b) = (sub(via, p0), sub(p1, p0));
    if same_point(via, p0) || same_point(via, p1) || collinear(a, b) {
        return Err(Refusal::Instruction(CoordFault::Collinear));
    }
    let normal = cross(a, b);
    // Circumcenter of p0, via, p1.
    let (x, y) = (sub(p0, p1), sub(via, p1));
    let xy = cross(x, y);
    let num = cross(sub(scale(y, dot(x, x)), scale(x, dot(y, y))), xy);
    let center = add(p1, scale(num, 1.0 / (2.0 * dot(xy, xy))));
    let r = norm(sub(p0, center));
    check_radius(r)?;
    let angle = if full {
        TAU
    } else {
        angle_about(sub(p0, center), sub(p1, center), normal)
    };
    Ok(Arc::new(p0, r, center, normal, angle))
}

fn center_arc(p0: V3, center: V3, p1: V3, direction: i64, dim: usize) -> Result<Arc, CoordMoveError> {
    let (r0, r1) = (sub(p0, center), sub(p1, center));
    let (rs, re) = (norm(r0), norm(r1));
    let closed = same_point(p0, p1);
    if dim == 3 {
        if closed {
            return Err(Refusal::Instruction(CoordFault::EndpointEqualsStartpoint));
        }
        if collinear(r0, r1) {
            return Err(Refusal::Instruction(CoordFault::Collinear));
        }
    }
    check_radius(rs)?;
    if (rs - re).abs() > 0.15 * rs {
        return Err(Refusal::Instruction(CoordFault::RadiusMismatch {
            r_start: rs,
            r_end: re,
        }));
    }
    let full = direction >= 2;
    if dim == 2 {
        // CW (0, 2) turns about −z, CCW (1, 3) about +z.
        let normal = if direction % 2 == 0 {
            [0.0, 0.0, -1.0]
        } else {
            [0.0, 0.0, 1.0]
        };
        if closed || full {
            return Ok(Arc::new(p0, rs, center, normal, TAU));
        }
        let angle = angle_about(r0, r1, normal);
        return Ok(Arc::new(p0, re, center, normal, angle));
    }
    let short_normal = cross(r0, r1);
    let short = angle_about(r0, r1, short_normal);
    let (normal, angle, end_r) = match direction {
        0 => (short_normal, short, re),
        1 => (scale(short_normal, -1.0), TAU - short, re),
        2 => (short_normal, TAU, rs),
        _ => (scale(short_normal, -1.0), TAU, rs),
    };
    Ok(Arc::new(p0, end_r, center, normal, angle))
}

fn radius_arc(p0: V3, radius: f64, p1: V3, direction: i64) -> Result<Arc, CoordMoveError> {
    if same_point(p0, p1) {
        return Err(Refusal::Instruction(CoordFault::EndpointEqualsStartpoint));
    }
    let r = radius.abs();
    let chord = sub(p1, p0);
    let d = norm(chord);
    let h = d / 2.0;
    if r < MIN_RADIUS || r < h * (1.0 - 1e-12) {
        return Err(Refusal::Instruction(CoordFault::RadiusTooSmall { radius }));
    }
    let ccw = direction % 2 == 1;
    let normal = if ccw { [0.0, 0.0, 1.0] } else { [0.0, 0.0, -1.0] };
    // The center of the short arc lies to the left of the chord for CCW,
    // to the right for CW; a negative radius takes the other center.
    let left = cross(normal, scale(chord, 1.0 / d));
    let q = (r * r - h * h).max(0.0).sqrt();
    let side = if radius > 0.0 { 1.0 } else { -1.0 };
    let center = add(scale(add(p0, p1), 0.5), scale(left, side * q));
    let angle = if direction >= 2 {
        TAU
    } else {
        let a = angle_about(sub(p0, center), sub(p1, center), normal);
        // Exactly half a turn: the sign of the radius decides nothing; keep π.
        if q == 0.0 { PI } else { a }
    };
    Ok(Arc::new(p0, r, center, normal, angle))
}

#[cfg(test)]
pub(crate) mod tests;
