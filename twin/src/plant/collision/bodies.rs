//! The bodies the collision model checks, what a check finds, and why a
//! model cannot be built.

use rapier3d_f64::math::{Pose, Vector};
use rapier3d_f64::parry::shape::SharedShape;
use serde::Serialize;

use crate::plant::stl::StlError;

/// One side of a checked pair.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Body {
    /// A robot body, index into [`CollisionModel::body_names`](super::CollisionModel::body_names).
    Robot(usize),
    /// An obstacle, index into the scene's `[[obstacles]]`.
    Obstacle(usize),
}

/// Why the collision model cannot be built.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum CollisionModelError {
    /// `collision.tool.link` names no URDF link.
    #[error("collision.tool.link: the URDF has no link '{link}'")]
    UnknownToolLink {
        /// The name.
        link: String,
        /// Line of the field.
        line: usize,
        /// Column of the field.
        column: usize,
    },
    /// An `allowed_pairs` entry names no body.
    #[error("collision.allowed_pairs: '{name}' is no collision body (links with <collision>, the tool, obstacles)")]
    UnknownPairBody {
        /// The name.
        name: String,
        /// Line of the entry.
        line: usize,
        /// Column of the entry.
        column: usize,
    },
    /// A mesh has no 3-D convex hull.
    #[error("{body}: collision mesh has no 3-D convex hull")]
    DegenerateMesh {
        /// Link, tool or obstacle name.
        body: String,
    },
    /// A collision mesh reaches farther than [`crate::scene::MAX_LENGTH_M`]
    /// from its frame once scaled: parry's continuous collision checks
    /// crawl on it (10⁴ m costs seconds an update, 10³⁰ m never ends).
    #[error("{body}: collision mesh reaches {extent_m:e} m from its frame once scaled, more than {max_m:e} m")]
    MeshTooLarge {
        /// Link, tool or obstacle name.
        body: String,
        /// The largest scaled coordinate's magnitude, m.
        extent_m: f64,
        /// The bound, m.
        max_m: f64,
    },
    /// A mesh for `meshes = "convex_decomposition"` has more triangles
    /// than the decomposition may take.
    #[error(
        "{body}: collision mesh has {triangles} triangles, more than the {max} that meshes = \"convex_decomposition\" \
         decomposes (simplify the mesh, or use meshes = \"convex_hull\")"
    )]
    DecompositionTooLarge {
        /// Link, tool or obstacle name.
        body: String,
        /// Its triangles.
        triangles: usize,
        /// The bound ([`super::build::MAX_DECOMPOSITION_TRIANGLES`]).
        max: usize,
    },
    /// The meshes for `meshes = "convex_decomposition"` have more
    /// triangles together than the decomposition may take in one scene.
    #[error(
        "collision meshes to decompose have {triangles} triangles together, more than the {max} a scene may have \
         with meshes = \"convex_decomposition\" (simplify them, or use meshes = \"convex_hull\")"
    )]
    DecompositionBudget {
        /// Their triangles.
        triangles: usize,
        /// The bound ([`super::build::MAX_DECOMPOSITION_TRIANGLES_TOTAL`]).
        max: usize,
    },
    /// A tool or obstacle mesh file cannot be loaded.
    #[error("{body}: {source}")]
    Mesh {
        /// Tool or obstacle name.
        body: String,
        /// Why (names the file).
        #[source]
        source: StlError,
    },
}

/// A contact between two bodies at one pose.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Contact {
    /// First body (always a robot body).
    pub a: Body,
    /// Second body (an obstacle or another robot body).
    pub b: Body,
    /// Where they touch, and how deep.
    pub at: ContactPoint,
}

/// Where two bodies touch, and how deep. In a collision event
/// ([`super::monitor::CollisionEvent`]) it is the deepest contact seen,
/// and the summary names its depth `max_depth_m`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ContactPoint {
    /// Penetration depth, m (0 when just touching).
    #[serde(rename = "max_depth_m")]
    pub depth_m: f64,
    /// Contact point in the world, m.
    pub point_in_world: [f64; 3],
    /// Unit normal in the world, from the second body into the first.
    pub normal_in_world: [f64; 3],
}

/// The result of one check.
#[derive(Debug, Clone, PartialEq)]
pub struct CheckResult {
    /// Contacts, in pair order (robot bodies, then obstacles, then self pairs).
    pub contacts: Vec<Contact>,
    /// Per robot body: the smallest distance to any obstacle, m (0 when
    /// touching; infinite without obstacles).
    pub clearance_m: Vec<f64>,
}

/// A shape's bounding sphere in its own frame: centre and radius, m.
#[derive(Debug, Clone, Copy)]
pub(super) struct LocalSphere {
    pub(super) center: Vector,
    pub(super) radius: f64,
}

impl LocalSphere {
    pub(super) fn of(shape: &SharedShape) -> Self {
        let sphere = shape.compute_local_bounding_sphere();
        LocalSphere {
            center: sphere.center,
            radius: sphere.radius,
        }
    }
}

#[derive(Debug, Clone)]
pub(super) struct RobotBody {
    pub(super) name: String,
    pub(super) link: usize,
    pub(super) shapes: Vec<(Pose, SharedShape)>,
}

impl RobotBody {
    /// The radius about the carrying link's origin of the ball that holds
    /// every shape of the body, given their bounding spheres.
    pub(super) fn radius(&self, spheres: &[LocalSphere]) -> f64 {
        self.shapes
            .iter()
            .zip(spheres)
            .map(|((local, _), sphere)| (*local * sphere.center).length() + sphere.radius)
            .fold(0.0, f64::max)
    }
}
