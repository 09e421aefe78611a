//! Triangle meshes shared by the URDF loader, the renderer and the Rerun logger.
//!
//! Coordinates are in metres, in the frame of whatever owns the mesh (a URDF
//! link's visual origin, an obstacle). URDF is Z-up; so is every mesh here.

/// An indexed triangle mesh with per-vertex normals (counter-clockwise front faces).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TriMesh {
    /// Vertex positions in metres.
    pub positions: Vec<[f32; 3]>,
    /// Unit vertex normals, one per position.
    pub normals: Vec<[f32; 3]>,
    /// Triangle list, three indices per triangle.
    pub indices: Vec<u32>,
}

/// Smallest number of segments around a round primitive (a triangle prism).
const MIN_SEGMENTS: u32 = 3;
/// Smallest number of latitude bands of a sphere.
const MIN_RINGS: u32 = 2;

impl TriMesh {
    /// The largest magnitude of any vertex coordinate once scaled by
    /// `scale` (per axis), m.
    #[must_use]
    pub fn extent_m(&self, scale: [f64; 3]) -> f64 {
        self.positions
            .iter()
            .flat_map(|p| (0..3).map(move |k| (f64::from(p[k]) * scale[k]).abs()))
            .fold(0.0, f64::max)
    }

    /// A box centred at the origin with edge lengths `size_xyz` (metres) along
    /// X, Y and Z, as URDF's `<box size="x y z"/>`.
    ///
    /// Each face has its own four vertices so its normals are flat. Sizes are
    /// used as absolute values; a non-finite size gives non-finite positions,
    /// which the renderer reports as an invalid mesh.
    ///
    /// # Examples
    /// ```
    /// let cube = twin::plant::mesh::TriMesh::cuboid([1.0, 2.0, 3.0]);
    /// assert_eq!(cube.indices.len(), 36);
    /// assert!((cube.signed_volume() - 6.0).abs() < 1e-9);
    /// ```
    #[must_use]
    pub fn cuboid(size_xyz: [f32; 3]) -> TriMesh {
        let h = size_xyz.map(|s| 0.5 * s.abs());
        let mut mesh = TriMesh::default();
        // For each face: outward normal, and the two in-face axes (u, v)
        // chosen so that u x v = normal (counter-clockwise seen from outside).
        let faces: [([f32; 3], [f32; 3], [f32; 3]); 6] = [
            ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]),
            ([-1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]),
            ([0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]),
            ([0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]),
            ([0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]),
            ([0.0, 0.0, -1.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]),
        ];
        for (normal, u, v) in faces {
            let base = index(mesh.positions.len());
            for (su, sv) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                let p = std::array::from_fn(|k| (normal[k] + su * u[k] + sv * v[k]) * h[k]);
                mesh.positions.push(p);
                mesh.normals.push(normal);
            }
            mesh.indices
                .extend_from_slice(&[base, base + 1, base + 2, base, base + 2, base + 3]);
        }
        mesh
    }

    /// A cylinder along Z centred at the origin, as URDF's
    /// `<cylinder radius=".." length=".."/>`: it spans z = -length/2 ..
    /// +length/2 (metres).
    ///
    /// The side has smooth (radial) normals, the two caps flat ones.
    /// `segments` is the number of facets around the axis (at least 3).
    /// Dimensions are used as absolute values.
    ///
    /// # Examples
    /// ```
    /// let c = twin::plant::mesh::TriMesh::cylinder(0.5, 2.0, 64);
    /// let exact = std::f64::consts::PI * 0.25 * 2.0;
    /// assert!((c.signed_volume() - exact).abs() < 0.01 * exact);
    /// ```
    #[must_use]
    pub fn cylinder(radius: f32, length: f32, segments: u32) -> TriMesh {
        let r = radius.abs();
        let hz = 0.5 * length.abs();
        let n = segments.max(MIN_SEGMENTS);
        let mut mesh = TriMesh::default();
        let ring = |i: u32| {
            // Angle computed in f64 so the seam closes exactly at i = n.
            let a = std::f64::consts::TAU * f64::from(i % n) / f64::from(n);
            [a.cos() as f32, a.sin() as f32]
        };
        // Side: n + 1 columns of (bottom, top) so the seam can be split.
        for i in 0..n {
            let [c0, s0] = ring(i);
            let [c1, s1] = ring(i + 1);
            let base = index(mesh.positions.len());
            mesh.positions.extend_from_slice(&[
                [r * c0, r * s0, -hz],
                [r * c1, r * s1, -hz],
                [r * c1, r * s1, hz],
                [r * c0, r * s0, hz],
            ]);
            mesh.normals
                .extend_from_slice(&[[c0, s0, 0.0], [c1, s1, 0.0], [c1, s1, 0.0], [c0, s0, 0.0]]);
            mesh.indices
                .extend_from_slice(&[base, base + 1, base + 2, base, base + 2, base + 3]);
        }
        // Caps: a centre vertex and a ring with flat normals.
        for (z, nz) in [(hz, 1.0_f32), (-hz, -1.0)] {
            let centre = index(mesh.positions.len());
            mesh.positions.push([0.0, 0.0, z]);
            mesh.normals.push([0.0, 0.0, nz]);
            for i in 0..n {
                let [c, s] = ring(i);
                mesh.positions.push([r * c, r * s, z]);
                mesh.normals.push([0.0, 0.0, nz]);
            }
            for i in 0..n {
                let a = centre + 1 + i;
                let b = centre + 1 + (i + 1) % n;
                if nz > 0.0 {
                    mesh.indices.extend_from_slice(&[centre, a, b]);
                } else {
                    mesh.indices.extend_from_slice(&[centre, b, a]);
                }
            }
        }
        mesh
    }

    /// A UV sphere centred at the origin, as URDF's `<sphere radius=".."/>`
    /// (metres), with smooth normals.
    ///
    /// `rings` is the number of latitude bands (at least 2), `segments` the
    /// number of longitude facets (at least 3). The poles lie on ±Z.
    ///
    /// # Examples
    /// ```
    /// let s = twin::plant::mesh::TriMesh::sphere(1.0, 48, 96);
    /// let exact = 4.0 / 3.0 * std::f64::consts::PI;
    /// assert!((s.signed_volume() - exact).abs() < 0.01 * exact);
    /// ```
    #[must_use]
    pub fn sphere(radius: f32, rings: u32, segments: u32) -> TriMesh {
        let r = radius.abs();
        let rings = rings.max(MIN_RINGS);
        let n = segments.max(MIN_SEGMENTS);
        let mut mesh = TriMesh::default();
        for j in 0..=rings {
            // Polar angle from +Z.
            let theta = std::f64::consts::PI * f64::from(j) / f64::from(rings);
            let (st, ct) = if j == 0 {
                (0.0, 1.0)
            } else if j == rings {
                (0.0, -1.0)
            } else {
                (theta.sin(), theta.cos())
            };
            for i in 0..=n {
                let phi = std::f64::consts::TAU * f64::from(i % n) / f64::from(n);
                let normal = [(st * phi.cos()) as f32, (st * phi.sin()) as f32, ct as f32];
                mesh.positions.push(normal.map(|c| c * r));
                mesh.normals.push(normal);
            }
        }
        let stride = n + 1;
        for j in 0..rings {
            for i in 0..n {
                let a = j * stride + i;
                let b = a + 1;
                let c = a + stride;
                let d = c + 1;
                // Skip the zero-area triangles at the poles.
                if j != 0 {
                    mesh.indices.extend_from_slice(&[a, c, b]);
                }
                if j != rings - 1 {
                    mesh.indices.extend_from_slice(&[b, c, d]);
                }
            }
        }
        mesh
    }

    /// This mesh with `new_from_mesh` (a column-major 4x4 affine matrix, may
    /// include scale or a mirror) applied: positions are transformed,
    /// normals by the inverse transpose and renormalised, and the winding is
    /// flipped when the matrix mirrors so front faces stay counter-clockwise.
    ///
    /// A singular matrix (zero scale on an axis) keeps positions correct but
    /// leaves the normals of collapsed faces at whatever direction survives.
    #[must_use]
    pub fn transformed(&self, new_from_mesh: &[[f32; 4]; 4]) -> TriMesh {
        let m = new_from_mesh;
        let linear =
            |v: [f32; 3]| -> [f32; 3] { std::array::from_fn(|r| m[0][r] * v[0] + m[1][r] * v[1] + m[2][r] * v[2]) };
        let cof = cofactor3([
            [m[0][0], m[0][1], m[0][2]],
            [m[1][0], m[1][1], m[1][2]],
            [m[2][0], m[2][1], m[2][2]],
        ]);
        let det = m[0][0] * cof[0][0] + m[0][1] * cof[0][1] + m[0][2] * cof[0][2];
        let sign = if det < 0.0 { -1.0 } else { 1.0 };
        let positions = self
            .positions
            .iter()
            .map(|&p| {
                let q = linear(p);
                [q[0] + m[3][0], q[1] + m[3][1], q[2] + m[3][2]]
            })
            .collect();
        let normals = self
            .normals
            .iter()
            .map(|&n| {
                // Cofactor matrix = det * inverse transpose; the sign of det
                // is restored so mirrored normals still point outward.
                let t: [f32; 3] =
                    std::array::from_fn(|r| sign * (cof[0][r] * n[0] + cof[1][r] * n[1] + cof[2][r] * n[2]));
                normalized(t).unwrap_or(n)
            })
            .collect();
        let mut indices = self.indices.clone();
        if det < 0.0 {
            for tri in indices.chunks_exact_mut(3) {
                tri.swap(1, 2);
            }
        }
        TriMesh {
            positions,
            normals,
            indices,
        }
    }

    /// Appends `other`'s vertices and triangles to this mesh (both in the same frame).
    pub fn append(&mut self, other: &TriMesh) {
        let base = index(self.positions.len());
        self.positions.extend_from_slice(&other.positions);
        self.normals.extend_from_slice(&other.normals);
        self.indices.extend(other.indices.iter().map(|&i| base + i));
    }

    /// Signed volume enclosed by the triangles (cubic metres), by the
    /// divergence theorem. Positive for a closed mesh with counter-clockwise,
    /// outward-facing triangles; indices out of range are skipped.
    #[must_use]
    pub fn signed_volume(&self) -> f64 {
        let p = |i: u32| self.positions.get(i as usize).map(|v| v.map(f64::from));
        self.indices
            .chunks_exact(3)
            .filter_map(|t| Some((p(t[0])?, p(t[1])?, p(t[2])?)))
            .map(|(a, b, c)| {
                let cross = [
                    b[1] * c[2] - b[2] * c[1],
                    b[2] * c[0] - b[0] * c[2],
                    b[0] * c[1] - b[1] * c[0],
                ];
                (a[0] * cross[0] + a[1] * cross[1] + a[2] * cross[2]) / 6.0
            })
            .sum()
    }
}

/// Converts a vertex count to a `u32` index, saturating (meshes past 4 G
/// vertices are rejected by the renderer's validation anyway).
fn index(len: usize) -> u32 {
    u32::try_from(len).unwrap_or(u32::MAX)
}

/// The cofactor matrix of a 3x3 matrix given as columns: `cof[c][r]` is the
/// cofactor of element (row r, column c). Equals det * inverse transpose.
fn cofactor3(m: [[f32; 3]; 3]) -> [[f32; 3]; 3] {
    let col = |a: [f32; 3], b: [f32; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    // Columns of the cofactor matrix are cross products of the other columns.
    [col(m[1], m[2]), col(m[2], m[0]), col(m[0], m[1])]
}

/// `v / |v|`, or `None` when `v` has no usable length.
fn normalized(v: [f32; 3]) -> Option<[f32; 3]> {
    let len = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    (len.is_finite() && len > 1e-30).then(|| v.map(|c| c / len))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check_well_formed(mesh: &TriMesh) {
        assert_eq!(mesh.positions.len(), mesh.normals.len());
        assert_eq!(mesh.indices.len() % 3, 0);
        assert!(!mesh.indices.is_empty());
        for &i in &mesh.indices {
            assert!((i as usize) < mesh.positions.len(), "index {i} out of range");
        }
        for n in &mesh.normals {
            let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
            assert!((len - 1.0).abs() < 1e-5, "normal {n:?} not unit");
        }
    }

    /// Every triangle's geometric normal agrees with its vertex normals
    /// (counter-clockwise winding seen from where the normals point).
    fn check_winding_matches_normals(mesh: &TriMesh) {
        for t in mesh.indices.chunks_exact(3) {
            let [a, b, c] = [0, 1, 2].map(|k| mesh.positions[t[k] as usize].map(f64::from));
            let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
            let v = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
            let g = [
                u[1] * v[2] - u[2] * v[1],
                u[2] * v[0] - u[0] * v[2],
                u[0] * v[1] - u[1] * v[0],
            ];
            for &k in t {
                let n = mesh.normals[k as usize].map(f64::from);
                assert!(
                    g[0] * n[0] + g[1] * n[1] + g[2] * n[2] > 0.0,
                    "triangle {t:?} faces inward"
                );
            }
        }
    }

    /// Every edge is shared by exactly two triangles in opposite directions
    /// (after welding coincident positions): the surface is closed.
    fn check_closed(mesh: &TriMesh) {
        use std::collections::BTreeMap;
        let key = |i: u32| mesh.positions[i as usize].map(|c| (c * 1e5).round() as i64);
        let mut edges: BTreeMap<([i64; 3], [i64; 3]), i32> = BTreeMap::new();
        for t in mesh.indices.chunks_exact(3) {
            for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
                let (ka, kb) = (key(a), key(b));
                if ka == kb {
                    continue;
                }
                if ka < kb {
                    *edges.entry((ka, kb)).or_default() += 1;
                } else {
                    *edges.entry((kb, ka)).or_default() -= 1;
                }
            }
        }
        for (edge, balance) in edges {
            assert_eq!(balance, 0, "edge {edge:?} is not shared by opposite triangles");
        }
    }

    #[test]
    fn cuboid_is_closed_outward_and_has_exact_volume() {
        let m = TriMesh::cuboid([0.2, 0.4, 0.6]);
        check_well_formed(&m);
        check_winding_matches_normals(&m);
        check_closed(&m);
        assert!((m.signed_volume() - 0.048).abs() < 1e-7);
        for p in &m.positions {
            assert!((p[0].abs() - 0.1).abs() < 1e-7);
            assert!((p[2].abs() - 0.3).abs() < 1e-7);
        }
    }

    #[test]
    fn cylinder_follows_urdf_convention_and_volume_converges() {
        let m = TriMesh::cylinder(0.1, 0.5, 48);
        check_well_formed(&m);
        check_winding_matches_normals(&m);
        check_closed(&m);
        let (zmin, zmax) = m
            .positions
            .iter()
            .fold((f32::MAX, f32::MIN), |(lo, hi), p| (lo.min(p[2]), hi.max(p[2])));
        assert_eq!((zmin, zmax), (-0.25, 0.25));
        // An inscribed n-gon prism has area n/2 r^2 sin(2 pi / n).
        let n = 48.0_f64;
        let r = f64::from(0.1_f32);
        let prism = 0.5 * n * r * r * (std::f64::consts::TAU / n).sin() * f64::from(0.5_f32);
        assert!((m.signed_volume() - prism).abs() < 1e-6 * prism.max(1.0));
        // Side normals are radial and horizontal.
        for (p, nrm) in m.positions.iter().zip(&m.normals) {
            if nrm[2] == 0.0 {
                let radial = [p[0] / 0.1, p[1] / 0.1];
                assert!((radial[0] - nrm[0]).abs() < 1e-5 && (radial[1] - nrm[1]).abs() < 1e-5);
            }
        }
    }

    #[test]
    fn sphere_is_closed_outward_and_volume_converges() {
        let m = TriMesh::sphere(0.3, 24, 48);
        check_well_formed(&m);
        check_winding_matches_normals(&m);
        check_closed(&m);
        let exact = 4.0 / 3.0 * std::f64::consts::PI * 0.027;
        let v = m.signed_volume();
        assert!(v > 0.97 * exact && v < exact, "volume {v} vs {exact}");
        for p in &m.positions {
            let r = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
            assert!((r - 0.3).abs() < 1e-6);
        }
    }

    #[test]
    fn too_few_segments_are_raised_to_the_minimum() {
        let c = TriMesh::cylinder(1.0, 1.0, 0);
        check_well_formed(&c);
        check_closed(&c);
        let s = TriMesh::sphere(1.0, 0, 1);
        check_well_formed(&s);
        check_closed(&s);
        assert!(s.signed_volume() > 0.0);
    }

    #[test]
    fn negative_dimensions_are_taken_as_absolute() {
        assert_eq!(TriMesh::cuboid([-1.0, 2.0, -3.0]), TriMesh::cuboid([1.0, 2.0, 3.0]));
        assert_eq!(TriMesh::cylinder(-1.0, -2.0, 8), TriMesh::cylinder(1.0, 2.0, 8));
    }

    #[test]
    fn transformed_scales_volume_and_keeps_mirrored_meshes_outward() {
        let m = TriMesh::cuboid([1.0, 1.0, 1.0]);
        // Scale x by 2, mirror y, translate.
        let t = [
            [2.0, 0.0, 0.0, 0.0],
            [0.0, -1.0, 0.0, 0.0],
            [0.0, 0.0, 3.0, 0.0],
            [5.0, 6.0, 7.0, 1.0],
        ];
        let moved = m.transformed(&t);
        check_well_formed(&moved);
        check_winding_matches_normals(&moved);
        check_closed(&moved);
        assert!((moved.signed_volume() - 6.0).abs() < 1e-4);
        // Rotation of 90 degrees about Z maps +X normals to +Y.
        let rz = [
            [0.0, 1.0, 0.0, 0.0],
            [-1.0, 0.0, 0.0, 0.0],
            [0.0, 0.0, 1.0, 0.0],
            [0.0, 0.0, 0.0, 1.0],
        ];
        let r = m.transformed(&rz);
        assert_eq!(m.normals[0], [1.0, 0.0, 0.0]);
        assert!((r.normals[0][1] - 1.0).abs() < 1e-6);
    }

    #[test]
    fn append_offsets_indices() {
        let mut a = TriMesh::cuboid([1.0, 1.0, 1.0]);
        let b = TriMesh::cuboid([1.0, 1.0, 1.0]).transformed(&[
            [1.0, 0.0, 0.0, 0.0],
            [0.0, 1.0, 0.0, 0.0],
            [0.0, 0.0, 1.0, 0.0],
            [3.0, 0.0, 0.0, 1.0],
        ]);
        a.append(&b);
        check_well_formed(&a);
        check_closed(&a);
        assert!((a.signed_volume() - 2.0).abs() < 1e-6);
    }
}
