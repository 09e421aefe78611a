//! Path geometry: the line or arc (planar spiral) through the primary axes,
//! with non-primary axes moving linearly with the path fraction.

use crate::vector::{V3, add, cross, dot, norm, scale, sub};

/// A path: the line or arc through the primary axes, with non-primary axes
/// moving linearly with the path fraction.
#[derive(Debug, Clone, PartialEq)]
pub struct PathGeometry {
    start: Vec<f64>,
    end: Vec<f64>,
    primary: usize,
    length: f64,
    shape: Shape,
}

#[derive(Debug, Clone, PartialEq)]
enum Shape {
    Line { direction: V3 },
    Arc(Arc),
}

impl PathGeometry {
    pub(crate) fn line(start: Vec<f64>, end: Vec<f64>, primary: usize) -> Self {
        let p0 = primary_of(&start, primary);
        let p1 = primary_of(&end, primary);
        let mut length = norm(sub(p1, p0));
        let direction = if length > 0.0 {
            scale(sub(p1, p0), 1.0 / length)
        } else {
            [0.0; 3]
        };
        if length == 0.0 {
            // Only non-primary axes move: their distance is the path length.
            length = start[primary..]
                .iter()
                .zip(&end[primary..])
                .map(|(a, b)| (b - a) * (b - a))
                .sum::<f64>()
                .sqrt();
        }
        Self {
            start,
            end,
            primary,
            length,
            shape: Shape::Line { direction },
        }
    }

    pub(crate) fn circular(start: Vec<f64>, end: Vec<f64>, primary: usize, arc: Arc) -> Self {
        Self {
            length: arc.length(),
            start,
            end,
            primary,
            shape: Shape::Arc(arc),
        }
    }

    /// Path length in coordinate units.
    pub fn length(&self) -> f64 {
        self.length
    }
    /// Start point (all axes).
    pub fn start(&self) -> &[f64] {
        &self.start
    }
    /// End point (all axes); exactly the programmed end point.
    pub fn end(&self) -> &[f64] {
        &self.end
    }
    /// The arc, for an arc path.
    pub fn arc(&self) -> Option<&Arc> {
        match &self.shape {
            Shape::Arc(a) => Some(a),
            Shape::Line { .. } => None,
        }
    }

    /// Position and derivative d(position)/ds of every axis at path length
    /// `s` (clamped to [0, length]); exactly the end point at the end.
    pub fn point(&self, s: f64, position: &mut [f64], per_s: &mut [f64]) {
        let n = self.start.len();
        let s = s.clamp(0.0, self.length);
        if s >= self.length {
            position[..n].copy_from_slice(&self.end);
        }
        let frac = if self.length > 0.0 { s / self.length } else { 1.0 };
        let inv = if self.length > 0.0 { 1.0 / self.length } else { 0.0 };
        let (p, d) = match &self.shape {
            Shape::Line { direction } => {
                let p0 = primary_of(&self.start, self.primary);
                (add(p0, scale(*direction, s)), *direction)
            }
            Shape::Arc(arc) => arc.point_at_length(s),
        };
        let primary_zero = matches!(self.shape, Shape::Line { direction } if direction == [0.0; 3]);
        for i in 0..n {
            let (pi, di) = if i < self.primary && !primary_zero {
                (p[i], d[i])
            } else {
                let delta = self.end[i] - self.start[i];
                (self.start[i] + delta * frac, delta * inv)
            };
            if s < self.length {
                position[i] = pi;
            }
            per_s[i] = di;
        }
    }

    /// Unit tangent of the primary axes at path length `s`.
    pub fn tangent(&self, s: f64) -> V3 {
        let n = self.start.len();
        let mut p = vec![0.0; n];
        let mut d = vec![0.0; n];
        self.point(s, &mut p, &mut d);
        let t = primary_of(&d, self.primary);
        let l = norm(t);
        if l > 0.0 { scale(t, 1.0 / l) } else { t }
    }
}

pub(crate) fn primary_of(v: &[f64], primary: usize) -> V3 {
    let mut p = [0.0; 3];
    p[..primary].copy_from_slice(&v[..primary]);
    p
}

/// A planar circular arc (or spiral, for a center circle whose end radius
/// differs from its start radius by at most 15 %), in the primary axes
/// padded to 3 components.
///
/// `point(φ) = center + r(φ) · (cos φ · u + sin φ · w)`, `w = normal × u`,
/// `r(φ) = r_start + (r_end − r_start) · φ / angle`, φ from 0 to `angle`:
/// the motion turns positively about `normal`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Arc {
    center: V3,
    u: V3,
    w: V3,
    normal: V3,
    r_start: f64,
    r_end: f64,
    angle_rad: f64,
    length_per_rad: f64,
}

impl Arc {
    pub(crate) fn new(start: V3, end_radius: f64, center: V3, normal: V3, angle_rad: f64) -> Self {
        let radial = sub(start, center);
        let r_start = norm(radial);
        let u = scale(radial, 1.0 / r_start);
        let nl = norm(normal);
        let normal = scale(normal, 1.0 / nl);
        // Re-orthogonalise: u ⟂ normal exactly up to rounding.
        let u = {
            let v = sub(u, scale(normal, dot(u, normal)));
            scale(v, 1.0 / norm(v))
        };
        let w = cross(normal, u);
        let dr = (end_radius - r_start) / angle_rad;
        let length_per_rad = (r_start.max(end_radius).powi(2) + dr * dr).sqrt();
        Self {
            center,
            u,
            w,
            normal,
            r_start,
            r_end: end_radius,
            angle_rad,
            length_per_rad,
        }
    }

    pub(crate) fn is_finite(&self) -> bool {
        [self.center, self.u, self.w, self.normal]
            .iter()
            .flatten()
            .chain(
                [
                    self.r_start,
                    self.r_end,
                    self.angle_rad,
                    self.length_per_rad,
                    self.length(),
                ]
                .iter(),
            )
            .all(|x| x.is_finite())
    }

    /// The center.
    pub fn center(&self) -> V3 {
        self.center
    }
    /// Unit normal; the motion turns positively about it.
    pub fn normal(&self) -> V3 {
        self.normal
    }
    /// Radius at the start.
    pub fn radius_start(&self) -> f64 {
        self.r_start
    }
    /// Radius at the end (equal to the start radius except for center
    /// circles with a mismatch within 15 %).
    pub fn radius_end(&self) -> f64 {
        self.r_end
    }
    /// Swept angle in radians (2π for a full circle).
    pub fn angle_rad(&self) -> f64 {
        self.angle_rad
    }
    /// Path length (exact for a circle: radius × angle).
    pub fn length(&self) -> f64 {
        self.length_per_rad * self.angle_rad
    }
    /// The point at angle `phi_rad` from the start.
    pub fn point(&self, phi_rad: f64) -> V3 {
        self.point_and_derivative(phi_rad).0
    }

    fn point_and_derivative(&self, phi: f64) -> (V3, V3) {
        let dr = (self.r_end - self.r_start) / self.angle_rad;
        let r = self.r_start + dr * phi;
        let (s, c) = phi.sin_cos();
        let radial = add(scale(self.u, c), scale(self.w, s));
        let tangential = add(scale(self.u, -s), scale(self.w, c));
        (
            add(self.center, scale(radial, r)),
            add(scale(radial, dr), scale(tangential, r)),
        )
    }

    /// Point and d(point)/ds at path length `s`.
    pub(crate) fn point_at_length(&self, s: f64) -> (V3, V3) {
        let (p, d) = self.point_and_derivative(s / self.length_per_rad);
        (p, scale(d, 1.0 / self.length_per_rad))
    }
}
