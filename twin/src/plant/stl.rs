//! STL loading (binary and ASCII) into the shared [`TriMesh`].
//!
//! mesh-loader (already here for COLLADA) reads the file; this module
//! decides what the file is, checks what mesh-loader lets pass, and names
//! the file and the defect in every error, which the URDF loader then wraps
//! with the link that referenced the mesh:
//! - a binary file's header count is checked against its size (mesh-loader
//!   trusts the size, so a file cut at a triangle boundary would silently
//!   lose triangles): [`StlError::Truncated`], [`StlError::TriangleCountMismatch`];
//! - NaN and infinite coordinates parse, and are refused with the
//!   triangle's index ([`StlError::NonFinite`]);
//! - an ASCII grammar error carries mesh-loader's line, column and reason
//!   ([`StlError::MalformedAscii`]).
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
    /// A binary file has bytes after its last triangle that are not a line
    /// break.
    #[error("STL file {path} has {bytes} stray bytes after its {declared} triangles")]
    TrailingBytes {
        /// The file.
        path: PathBuf,
        /// Triangle count written in the header.
        declared: u32,
        /// Bytes after the last triangle.
        bytes: usize,
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
    #[error("ASCII STL file {path} is malformed at {at}")]
    MalformedAscii {
        /// The file.
        path: PathBuf,
        /// Where and why (boxed: errors stay small).
        at: Box<AsciiDefect>,
    },
    /// The file contains no triangles at all.
    #[error("STL file {path} contains no triangles")]
    Empty {
        /// The file.
        path: PathBuf,
    },
}

/// Where an ASCII STL file breaks the grammar, and how.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct AsciiDefect {
    /// One-based line number where parsing failed.
    pub line: usize,
    /// One-based column.
    pub column: usize,
    /// What was expected there (mesh-loader's words).
    pub reason: String,
}

impl std::fmt::Display for AsciiDefect {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "line {}, column {}: {}", self.line, self.column, self.reason)
    }
}

/// Loads an STL file (binary or ASCII) as a flat-shaded [`TriMesh`] in the
/// file's own units (URDF meshes are in metres before their `scale`).
///
/// # Errors
/// [`StlError::Read`] when the file cannot be read, otherwise whatever
/// [`parse_stl`] reports.
pub fn load_stl(path: &Path) -> Result<TriMesh, StlError> {
    let bytes = crate::source::read_bounded(path, crate::source::InputKind::Mesh).map_err(|source| StlError::Read {
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
/// [`StlError::TrailingBytes`], [`StlError::NonFinite`], [`StlError::MalformedAscii`]
/// or [`StlError::Empty`].
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
    if exact_binary || !looks_ascii {
        check_binary_size(bytes, path)?;
    }
    let scene = mesh_loader::stl::from_slice(bytes).map_err(|e| malformed(&e, path))?;
    let triangles: Vec<Facet> = scene
        .meshes
        .iter()
        .flat_map(|mesh| {
            mesh.faces.iter().map(|face| {
                let corner = |k: usize| face[k] as usize;
                Facet {
                    normal: mesh.normals.get(corner(0)).copied().unwrap_or_default(),
                    vertices: [0, 1, 2].map(|k| mesh.vertices.get(corner(k)).copied().unwrap_or([f32::NAN; 3])),
                }
            })
        })
        .collect();
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

/// A binary file holds exactly the triangles its header declares.
fn check_binary_size(bytes: &[u8], path: &Path) -> Result<(), StlError> {
    let declared = declared_binary_count(bytes).ok_or_else(|| StlError::Truncated {
        path: path.to_path_buf(),
        expected_bytes: BINARY_HEADER_BYTES,
        actual_bytes: bytes.len(),
    })?;
    let in_file = (bytes.len() - BINARY_HEADER_BYTES) / BINARY_TRIANGLE_BYTES;
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
    // Some exporters end the file with a line break; anything else is not
    // a triangle.
    let rest = &bytes[BINARY_HEADER_BYTES + in_file * BINARY_TRIANGLE_BYTES..];
    if !rest.is_empty() && rest != b"\n" && rest != b"\r\n" {
        return Err(StlError::TrailingBytes {
            path: path.to_path_buf(),
            declared,
            bytes: rest.len(),
        });
    }
    Ok(())
}

/// mesh-loader's error, `"<reason> (<line>:<column>)"`, as
/// [`StlError::MalformedAscii`] (binary files reach it only through
/// [`check_binary_size`], which refuses every size it would).
fn malformed(e: &std::io::Error, path: &Path) -> StlError {
    let text = e.to_string();
    let (reason, place) = text
        .strip_suffix(')')
        .and_then(|t| t.rsplit_once(" ("))
        .unwrap_or((text.as_str(), ""));
    let mut numbers = place.split(':').map(|n| n.parse::<usize>().unwrap_or(0));
    StlError::MalformedAscii {
        path: path.to_path_buf(),
        at: Box::new(AsciiDefect {
            line: numbers.next().unwrap_or(0),
            column: numbers.next().unwrap_or(0),
            reason: reason.to_owned(),
        }),
    }
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
    fn ascii_errors_name_line_column_and_reason() {
        let cases = [
            // A facet with two vertices: `endloop` comes where the third is due.
            (
                "solid a\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nendloop\nendfacet\nendsolid a\n",
                6,
            ),
            // The text stops inside a facet.
            ("solid a\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n", 5),
            // A word where a number is due.
            ("solid a\nfacet normal x 0 1\n", 2),
        ];
        for (text, expected_line) in cases {
            match parse_stl(text.as_bytes(), Path::new(P)) {
                Err(ref e @ StlError::MalformedAscii { ref at, .. }) => {
                    let (line, column) = (at.line, at.column);
                    assert_eq!(line, expected_line, "{e}");
                    assert!(column >= 1, "{e}");
                    let message = e.to_string();
                    assert!(
                        message.starts_with(&format!(
                            "ASCII STL file {P} is malformed at line {line}, column {column}: "
                        )),
                        "{message}"
                    );
                    assert!(!message.ends_with(": "), "a reason: {message}");
                }
                other => panic!("{text:?}: unexpected {other:?}"),
            }
        }
    }

    #[test]
    fn binary_with_stray_bytes_after_its_triangles_is_refused() {
        let mut bytes = binary(&[TRI], 1);
        bytes.extend_from_slice(b"xyz");
        assert!(matches!(
            parse_stl(&bytes, Path::new(P)),
            Err(StlError::TrailingBytes {
                declared: 1,
                bytes: 3,
                ..
            })
        ));
        let mut newline = binary(&[TRI], 1);
        newline.push(b'\n');
        assert_eq!(parse_stl(&newline, Path::new(P)).unwrap().indices.len(), 3);
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
