//! STL loading (binary and ASCII) into the shared [`TriMesh`].
//!
//! A small parser of our own rather than a crate: the format is tiny, and
//! owning it lets every error name the file and say exactly what is wrong
//! (truncation, a header that lies about its triangle count, NaN coordinates),
//! which the URDF loader then wraps with the link that referenced the mesh.
//!
//! Choices the format leaves open:
//! - Vertices are not shared: each triangle gets its own three vertices so the
//!   flat per-face normals of a CAD export render as crisp facets.
//! - Normals come from the triangle's winding (counter-clockwise is the front,
//!   as [`TriMesh`] requires); the normal stored in the file is used only for a
//!   degenerate (zero-area) triangle, and `+Z` when that one is zero too.
//!   Exporters often write zero or stale normals; the winding is what renderers
//!   and physics agree on.
//! - A file is binary when its length is exactly `84 + 50 · n` for the
//!   triangle count `n` in its header, even if it starts with `solid` (many
//!   binary exporters write that word into the 80-byte header). Otherwise a
//!   file starting with `solid` and free of NUL bytes is read as ASCII, and
//!   anything else as binary.

use std::path::{Path, PathBuf};

use crate::plant::mesh::TriMesh;

/// Bytes in a binary STL header: 80 free bytes plus the `u32` triangle count.
const BINARY_HEADER_BYTES: usize = 84;
/// Bytes per binary STL triangle: normal, three vertices (12 `f32`) and a `u16`.
const BINARY_TRIANGLE_BYTES: usize = 50;

/// Why an STL file could not be loaded. Every variant names the file.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum StlError {
    /// The file could not be read (missing, permissions, ...).
    #[error("cannot read STL file {path}")]
    Read {
        /// The file.
        path: PathBuf,
        /// The I/O failure.
        #[source]
        source: std::io::Error,
    },
    /// Text that is not an ASCII STL (it does not start with `solid`): an
    /// OBJ, a URDF or any other text file given where an STL is expected.
    #[error(
        "{path} is not an STL file: it is text that does not start with 'solid' (meshes here must be STL, binary or ASCII)"
    )]
    NotStl {
        /// The file.
        path: PathBuf,
    },
    /// The file ends before the data its header or syntax promises.
    #[error("STL file {path} is truncated: expected at least {expected_bytes} bytes, found {actual_bytes}")]
    Truncated {
        /// The file.
        path: PathBuf,
        /// Bytes the header (binary) or an unfinished facet (ASCII) needs.
        expected_bytes: usize,
        /// Bytes actually present.
        actual_bytes: usize,
    },
    /// A binary file holds more triangle records than its header declares.
    #[error("STL file {path} declares {declared} triangles but holds data for {in_file}")]
    TriangleCountMismatch {
        /// The file.
        path: PathBuf,
        /// Triangle count written in the header.
        declared: u32,
        /// Complete 50-byte triangle records present after the header.
        in_file: usize,
    },
    /// A vertex coordinate is NaN or infinite.
    #[error("STL file {path} has a non-finite coordinate in triangle {triangle}")]
    NonFinite {
        /// The file.
        path: PathBuf,
        /// Zero-based index of the offending triangle.
        triangle: usize,
    },
    /// An ASCII file does not follow the `facet normal / outer loop / vertex` grammar.
    #[error("ASCII STL file {path} is malformed at line {line}")]
    MalformedAscii {
        /// The file.
        path: PathBuf,
        /// One-based line number where parsing failed.
        line: usize,
    },
    /// The file contains no triangles at all.
    #[error("STL file {path} contains no triangles")]
    Empty {
        /// The file.
        path: PathBuf,
    },
}

/// Loads an STL file (binary or ASCII) as a flat-shaded [`TriMesh`] in the
/// file's own units (URDF meshes are in metres before their `scale`).
///
/// # Errors
/// [`StlError::Read`] when the file cannot be read, otherwise whatever
/// [`parse_stl`] reports.
pub fn load_stl(path: &Path) -> Result<TriMesh, StlError> {
    let bytes = std::fs::read(path).map_err(|source| StlError::Read {
        path: path.to_path_buf(),
        source,
    })?;
    parse_stl(&bytes, path)
}

/// Parses STL bytes (binary or ASCII; see the module docs for how the two are
/// told apart). `path` is used only to name the file in errors.
///
/// # Errors
/// [`StlError::NotStl`], [`StlError::Truncated`], [`StlError::TriangleCountMismatch`],
/// [`StlError::NonFinite`], [`StlError::MalformedAscii`] or [`StlError::Empty`].
///
/// # Examples
/// ```
/// let ascii = "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n";
/// let mesh = twin::plant::stl::parse_stl(ascii.as_bytes(), std::path::Path::new("t.stl")).unwrap();
/// assert_eq!(mesh.indices, vec![0, 1, 2]);
/// assert_eq!(mesh.normals[0], [0.0, 0.0, 1.0]);
/// ```
pub fn parse_stl(bytes: &[u8], path: &Path) -> Result<TriMesh, StlError> {
    let declared = declared_binary_count(bytes);
    let exact_binary = declared.is_some_and(|n| {
        (n as usize)
            .checked_mul(BINARY_TRIANGLE_BYTES)
            .and_then(|b| b.checked_add(BINARY_HEADER_BYTES))
            == Some(bytes.len())
    });
    // Binary files almost always contain NUL bytes (the triangle count's high
    // bytes, zero attribute words); ASCII ones never do.
    let text = !bytes.contains(&0);
    let looks_ascii = bytes.trim_ascii_start().starts_with(b"solid") && text;
    if !exact_binary && !looks_ascii && text && std::str::from_utf8(bytes).is_ok() {
        return Err(StlError::NotStl {
            path: path.to_path_buf(),
        });
    }
    let triangles = if exact_binary || !looks_ascii {
        parse_binary(bytes, path)?
    } else {
        parse_ascii(bytes, path)?
    };
    if triangles.is_empty() {
        return Err(StlError::Empty {
            path: path.to_path_buf(),
        });
    }
    for (triangle, t) in triangles.iter().enumerate() {
        if t.vertices.iter().flatten().any(|c| !c.is_finite()) {
            return Err(StlError::NonFinite {
                path: path.to_path_buf(),
                triangle,
            });
        }
    }
    Ok(to_trimesh(&triangles))
}

/// One STL facet as stored in the file.
struct Facet {
    normal: [f32; 3],
    vertices: [[f32; 3]; 3],
}

fn declared_binary_count(bytes: &[u8]) -> Option<u32> {
    let count: [u8; 4] = bytes.get(80..84)?.try_into().ok()?;
    Some(u32::from_le_bytes(count))
}

fn parse_binary(bytes: &[u8], path: &Path) -> Result<Vec<Facet>, StlError> {
    let declared = declared_binary_count(bytes).ok_or_else(|| StlError::Truncated {
        path: path.to_path_buf(),
        expected_bytes: BINARY_HEADER_BYTES,
        actual_bytes: bytes.len(),
    })?;
    let body = &bytes[BINARY_HEADER_BYTES..];
    let in_file = body.len() / BINARY_TRIANGLE_BYTES;
    if in_file < declared as usize {
        return Err(StlError::Truncated {
            path: path.to_path_buf(),
            expected_bytes: BINARY_HEADER_BYTES + declared as usize * BINARY_TRIANGLE_BYTES,
            actual_bytes: bytes.len(),
        });
    }
    if in_file > declared as usize {
        return Err(StlError::TriangleCountMismatch {
            path: path.to_path_buf(),
            declared,
            in_file,
        });
    }
    let f32_at = |record: &[u8], i: usize| {
        let mut b = [0u8; 4];
        b.copy_from_slice(&record[4 * i..4 * i + 4]);
        f32::from_le_bytes(b)
    };
    Ok(body
        .chunks_exact(BINARY_TRIANGLE_BYTES)
        .map(|record| {
            let v = |k: usize| [f32_at(record, k), f32_at(record, k + 1), f32_at(record, k + 2)];
            Facet {
                normal: v(0),
                vertices: [v(3), v(6), v(9)],
            }
        })
        .collect())
}

fn parse_ascii(bytes: &[u8], path: &Path) -> Result<Vec<Facet>, StlError> {
    let malformed = |line: usize| StlError::MalformedAscii {
        path: path.to_path_buf(),
        line,
    };
    let text = String::from_utf8_lossy(bytes);
    let mut facets = Vec::new();
    // State of the facet being read: its normal and the vertices seen so far.
    let mut current: Option<([f32; 3], Vec<[f32; 3]>)> = None;
    let mut ended = false;
    for (i, raw) in text.lines().enumerate() {
        let line_no = i + 1;
        let mut words = raw.split_whitespace();
        let Some(keyword) = words.next() else {
            continue;
        };
        let rest: Vec<&str> = words.collect();
        match keyword {
            "solid" if i == 0 || facets.is_empty() && current.is_none() => {}
            "facet" if current.is_none() => {
                let normal = match rest.as_slice() {
                    ["normal", x, y, z] => parse3(x, y, z).ok_or_else(|| malformed(line_no))?,
                    _ => return Err(malformed(line_no)),
                };
                current = Some((normal, Vec::with_capacity(3)));
            }
            "outer" if current.is_some() && rest == ["loop"] => {}
            "vertex" => {
                let (_, vertices) = current.as_mut().ok_or_else(|| malformed(line_no))?;
                let v = match rest.as_slice() {
                    [x, y, z] => parse3(x, y, z).ok_or_else(|| malformed(line_no))?,
                    _ => return Err(malformed(line_no)),
                };
                if vertices.len() == 3 {
                    return Err(malformed(line_no));
                }
                vertices.push(v);
            }
            "endloop" if current.is_some() => {}
            "endfacet" => {
                let (normal, vertices) = current.take().ok_or_else(|| malformed(line_no))?;
                let vertices: [[f32; 3]; 3] = vertices.try_into().map_err(|_| malformed(line_no))?;
                facets.push(Facet { normal, vertices });
            }
            "endsolid" if current.is_none() => {
                ended = true;
                break;
            }
            _ => return Err(malformed(line_no)),
        }
    }
    if current.is_some() || !ended {
        // The text stops inside a facet or before `endsolid`.
        return Err(StlError::Truncated {
            path: path.to_path_buf(),
            expected_bytes: bytes.len() + 1,
            actual_bytes: bytes.len(),
        });
    }
    Ok(facets)
}

/// Parses three ASCII numbers; NaN and infinities parse and are caught later
/// with the triangle index.
fn parse3(x: &str, y: &str, z: &str) -> Option<[f32; 3]> {
    Some([x.parse().ok()?, y.parse().ok()?, z.parse().ok()?])
}

fn to_trimesh(facets: &[Facet]) -> TriMesh {
    let mut mesh = TriMesh {
        positions: Vec::with_capacity(facets.len() * 3),
        normals: Vec::with_capacity(facets.len() * 3),
        indices: Vec::with_capacity(facets.len() * 3),
    };
    for facet in facets {
        let normal = winding_normal(&facet.vertices)
            .or_else(|| normalized(facet.normal))
            .unwrap_or([0.0, 0.0, 1.0]);
        for v in facet.vertices {
            let index = u32::try_from(mesh.positions.len()).unwrap_or(u32::MAX);
            mesh.indices.push(index);
            mesh.positions.push(v);
            mesh.normals.push(normal);
        }
    }
    mesh
}

pub(crate) fn winding_normal([a, b, c]: &[[f32; 3]; 3]) -> Option<[f32; 3]> {
    let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let v = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
    normalized([
        u[1] * v[2] - u[2] * v[1],
        u[2] * v[0] - u[0] * v[2],
        u[0] * v[1] - u[1] * v[0],
    ])
}

fn normalized(n: [f32; 3]) -> Option<[f32; 3]> {
    let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    (len.is_finite() && len > f32::EPSILON * 16.0).then(|| [n[0] / len, n[1] / len, n[2] / len])
}

#[cfg(test)]
#[allow(clippy::unwrap_used)] // a failed unwrap is a failed test
mod tests {
    use super::*;

    fn binary(triangles: &[[[f32; 3]; 4]], declared: u32) -> Vec<u8> {
        let mut bytes = vec![0u8; 80];
        bytes[..5].copy_from_slice(b"solid"); // binary exporters do this; must still parse as binary
        bytes.extend_from_slice(&declared.to_le_bytes());
        for t in triangles {
            for v in t {
                for c in v {
                    bytes.extend_from_slice(&c.to_le_bytes());
                }
            }
            bytes.extend_from_slice(&0u16.to_le_bytes());
        }
        bytes
    }

    const TRI: [[f32; 3]; 4] = [[0.0; 3], [0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    const P: &str = "part.stl";

    #[test]
    fn binary_triangle_gets_winding_normal_when_file_normal_is_zero() {
        let mesh = parse_stl(&binary(&[TRI, TRI], 2), Path::new(P)).unwrap();
        assert_eq!(mesh.positions.len(), 6);
        assert_eq!(mesh.indices, vec![0, 1, 2, 3, 4, 5]);
        assert_eq!(mesh.positions[1], [1.0, 0.0, 0.0]);
        assert!(mesh.normals.iter().all(|n| *n == [0.0, 0.0, 1.0]));
    }

    #[test]
    fn clockwise_winding_faces_down() {
        let cw = [[0.0, 0.0, 1.0], [0.0; 3], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]];
        let mesh = parse_stl(&binary(&[cw], 1), Path::new(P)).unwrap();
        assert_eq!(mesh.normals[0], [0.0, 0.0, -1.0]);
    }

    #[test]
    fn degenerate_triangle_falls_back_to_file_normal() {
        let flat = [[2.0, 0.0, 0.0], [0.0; 3], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]];
        let mesh = parse_stl(&binary(&[flat], 1), Path::new(P)).unwrap();
        assert_eq!(mesh.normals[0], [1.0, 0.0, 0.0]);
    }

    #[test]
    fn text_that_is_not_ascii_stl_is_named_as_such() {
        let obj = b"# A triangle\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
        let e = parse_stl(obj, Path::new("guard.obj")).unwrap_err();
        assert!(matches!(e, StlError::NotStl { .. }), "{e}");
        assert!(e.to_string().starts_with("guard.obj is not an STL file"), "{e}");
    }

    #[test]
    fn binary_truncated_is_reported_with_file() {
        let mut bytes = binary(&[TRI, TRI], 2);
        bytes.truncate(bytes.len() - 7);
        match parse_stl(&bytes, Path::new(P)) {
            Err(StlError::Truncated {
                path,
                expected_bytes,
                actual_bytes,
            }) => {
                assert_eq!(path, Path::new(P));
                assert_eq!(expected_bytes, 184);
                assert_eq!(actual_bytes, 177);
            }
            other => panic!("unexpected {other:?}"),
        }
        assert!(matches!(
            parse_stl(&[0u8; 40], Path::new(P)),
            Err(StlError::Truncated { .. })
        ));
    }

    #[test]
    fn binary_with_extra_triangles_is_a_count_mismatch() {
        let bytes = binary(&[TRI, TRI, TRI], 2);
        assert!(matches!(
            parse_stl(&bytes, Path::new(P)),
            Err(StlError::TriangleCountMismatch {
                declared: 2,
                in_file: 3,
                ..
            })
        ));
    }

    #[test]
    fn nan_coordinate_names_triangle() {
        let mut bad = TRI;
        bad[2][1] = f32::NAN;
        assert!(matches!(
            parse_stl(&binary(&[TRI, bad], 2), Path::new(P)),
            Err(StlError::NonFinite { triangle: 1, .. })
        ));
        let ascii = "solid a\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex nan 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid a\n";
        assert!(matches!(
            parse_stl(ascii.as_bytes(), Path::new(P)),
            Err(StlError::NonFinite { triangle: 0, .. })
        ));
    }

    #[test]
    fn ascii_parses_and_matches_binary() {
        let ascii = "solid cube\n  facet normal 0 0 0\n    outer loop\n      vertex 0 0 0\n      vertex 1 0 0\n      vertex 0 1 0\n    endloop\n  endfacet\nendsolid cube\n";
        let a = parse_stl(ascii.as_bytes(), Path::new(P)).unwrap();
        let b = parse_stl(&binary(&[TRI], 1), Path::new(P)).unwrap();
        assert_eq!(a, b);
    }

    #[test]
    fn ascii_errors_name_line_or_truncation() {
        let two_vertices =
            "solid a\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nendloop\nendfacet\nendsolid a\n";
        assert!(matches!(
            parse_stl(two_vertices.as_bytes(), Path::new(P)),
            Err(StlError::MalformedAscii { line: 7, .. })
        ));
        let cut = "solid a\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n";
        assert!(matches!(
            parse_stl(cut.as_bytes(), Path::new(P)),
            Err(StlError::Truncated { .. })
        ));
        let garbage = "solid a\nfacet normal x 0 1\n";
        assert!(matches!(
            parse_stl(garbage.as_bytes(), Path::new(P)),
            Err(StlError::MalformedAscii { line: 2, .. })
        ));
    }

    #[test]
    fn empty_and_missing_files_are_errors() {
        assert!(matches!(
            parse_stl(&binary(&[], 0), Path::new(P)),
            Err(StlError::Empty { .. })
        ));
        assert!(matches!(
            load_stl(Path::new("/nonexistent/dir/part.stl")),
            Err(StlError::Read { .. })
        ));
    }
}
