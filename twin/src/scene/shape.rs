//! The scene's leaf vocabulary: places in the file and shapes, which the
//! model and the cell model both use.

use std::path::PathBuf;

/// A 1-based line and column (in characters) in the scene file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct Location {
    /// 1-based line.
    pub line: usize,
    /// 1-based column, counted in characters.
    pub column: usize,
}

/// The geometry of an obstacle, metres.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum Shape {
    /// Axis-aligned box (in the obstacle frame) with full edge lengths.
    Box {
        /// Full size along x, y, z, metres.
        size_m: [f64; 3],
    },
    /// Cylinder along the obstacle frame's z axis.
    Cylinder {
        /// Radius, metres.
        radius_m: f64,
        /// Full length, metres.
        length_m: f64,
    },
    /// Sphere.
    Sphere {
        /// Radius, metres.
        radius_m: f64,
    },
    /// A mesh file (resolved relative to the scene file), scaled per axis.
    Mesh {
        /// The mesh file.
        path: PathBuf,
        /// Scale factors along x, y, z.
        scale: [f64; 3],
    },
}
