//! What can be wrong with a URDF file, each case naming the file and,
//! where the parser or the checks know it, the line and the element.

use std::path::PathBuf;

use crate::plant::dae::DaeError;
use crate::plant::stl::StlError;

/// Why a URDF file could not be turned into a [`RobotModel`](super::RobotModel).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum UrdfError {
    /// The URDF file could not be read.
    #[error("cannot read URDF file {path}")]
    Read {
        /// The URDF file.
        path: PathBuf,
        /// The I/O failure.
        #[source]
        source: std::io::Error,
    },
    /// The XML is malformed or not a URDF robot.
    #[error("invalid URDF in {path}{}", line.map(|l| format!(" near line {l}")).unwrap_or_default())]
    Parse {
        /// The URDF file.
        path: PathBuf,
        /// One-based line number, when the XML parser reports one.
        line: Option<u32>,
        /// The parser's error.
        #[source]
        source: urdf_rs::UrdfError,
    },
    /// A physical quantity no robot can have (see [`super::checks`]).
    #[error("{path}:{}: {owner}: <{element}>: {problem}", line.map_or_else(|| "?".to_owned(), |l| l.to_string()))]
    Physical {
        /// The URDF file.
        path: PathBuf,
        /// The element's line (or its nearest written parent's).
        line: Option<usize>,
        /// `link NAME` or `joint NAME`.
        owner: String,
        /// The element, as a path below the owner (`inertial/inertia`,
        /// `visual[0]/geometry/box`).
        element: String,
        /// What is wrong.
        problem: String,
    },
    /// Elements nested deeper than the XML readers can follow.
    #[error("{path}:{line}: elements nested deeper than {max} levels")]
    TooDeep {
        /// The URDF file.
        path: PathBuf,
        /// The line of the first element too deep.
        line: usize,
        /// [`crate::plant::xml::MAX_XML_DEPTH`].
        max: usize,
    },
    /// A mesh file referenced by a link does not exist at any resolved location.
    #[error("link {link}: mesh file {filename} not found (looked for {path})")]
    MeshMissing {
        /// The link whose visual or collision references the mesh.
        link: String,
        /// The file name as written in the URDF.
        filename: String,
        /// The first resolved path that was tried.
        path: PathBuf,
    },
    /// A mesh file exists but could not be loaded.
    #[error("link {link}: cannot load mesh {path}")]
    Mesh {
        /// The link whose visual or collision references the mesh.
        link: String,
        /// The resolved mesh file.
        path: PathBuf,
        /// What is wrong with the file.
        #[source]
        source: StlError,
    },
    /// A COLLADA (`.dae`) mesh file exists but could not be loaded.
    #[error("link {link}: cannot load mesh {path}")]
    ColladaMesh {
        /// The link whose visual or collision references the mesh.
        link: String,
        /// The resolved mesh file.
        path: PathBuf,
        /// What is wrong with the file.
        #[source]
        source: DaeError,
    },
    /// A `<collision>` mesh reaches farther than
    /// [`crate::scene::MAX_LENGTH_M`] from its frame once scaled.
    #[error(
        "link {link}: collision mesh {path} reaches {extent_m:e} m from its frame once scaled, more than {max_m:e} m"
    )]
    CollisionMeshTooLarge {
        /// The link.
        link: String,
        /// The resolved mesh file.
        path: PathBuf,
        /// The largest scaled coordinate's magnitude, m.
        extent_m: f64,
        /// The bound, m.
        max_m: f64,
    },
    /// A mesh file is in a format other than STL or COLLADA.
    #[error("link {link}: mesh {path} has unsupported format {extension:?} (only STL and COLLADA .dae are supported)")]
    UnsupportedMeshFormat {
        /// The link whose visual or collision references the mesh.
        link: String,
        /// The resolved mesh file.
        path: PathBuf,
        /// Its extension, lower-cased ("" when it has none).
        extension: String,
    },
    /// A geometry type this loader does not support (capsule).
    #[error("link {link}: unsupported geometry {geometry}")]
    UnsupportedGeometry {
        /// The link.
        link: String,
        /// The geometry element name.
        geometry: &'static str,
    },
    /// A joint type this loader does not support (floating, planar, spherical).
    #[error("joint {joint}: unsupported joint type {joint_type}")]
    UnsupportedJointType {
        /// The joint.
        joint: String,
        /// The URDF type name.
        joint_type: &'static str,
    },
    /// A movable joint's axis has zero length or is not finite.
    #[error("joint {joint}: axis {axis:?} is not a usable direction")]
    InvalidAxis {
        /// The joint.
        joint: String,
        /// The axis as written.
        axis: [f64; 3],
    },
    /// A joint names a parent or child link that the file does not define.
    #[error("joint {joint}: link {link} does not exist")]
    MissingLink {
        /// The joint.
        joint: String,
        /// The missing link's name.
        link: String,
    },
    /// Two links share a name.
    #[error("link name {link} is used twice")]
    DuplicateLink {
        /// The name.
        link: String,
    },
    /// Two joints share a name.
    #[error("joint name {joint} is used twice")]
    DuplicateJoint {
        /// The name.
        joint: String,
    },
    /// The file defines no link.
    #[error("URDF defines no links")]
    NoLinks,
    /// More than one link is no joint's child.
    #[error("URDF has more than one root link: {links:?}")]
    MultipleRoots {
        /// The root candidates, in file order.
        links: Vec<String>,
    },
    /// A link is the child of more than one joint.
    #[error("link {link} is the child of several joints: {joints:?}")]
    MultipleParents {
        /// The link.
        link: String,
        /// The joints naming it as child, in file order.
        joints: Vec<String>,
    },
    /// Some links form a cycle (they cannot be reached from the root).
    #[error("URDF joints form a cycle through links {links:?}")]
    Cycle {
        /// The links on or behind the cycle, in file order.
        links: Vec<String>,
    },
}
