//! URDF → [`RobotModel`]: an index arena of links and joints with resolved
//! geometry, colours and meshes.
//!
//! Parsing is urdf-rs 0.9's; this module validates the tree (every joint's
//! links exist, one root, no cycles, no link with two parents), resolves mesh
//! file names, loads the meshes (STL, and COLLADA `.dae` via [`crate::plant::dae`]) and turns `<origin>` elements into
//! nalgebra isometries via [`crate::plant::convert`].
//!
//! Frames: each link's frame is the URDF link frame; `parent_from_joint` is
//! the joint's `<origin>` in its parent link frame, and the child link frame
//! coincides with the joint frame at zero joint position. Everything is in
//! metres, radians and kilograms, Z up, as in the file.
//!
//! Choices the URDF spec leaves open:
//! - Mesh file names are resolved relative to the URDF file's directory;
//!   `package://pkg/rest` is looked up as `<A>/pkg/rest` for the URDF
//!   directory and each of its ancestors `A` (and as `<A>/rest` when `A` is
//!   itself named `pkg`), and `file://` paths are taken as they are (relative
//!   ones again from the URDF directory).
//! - A visual's colour is its inline `<material><color>`; otherwise the colour
//!   of the robot-level `<material>` with the same name; otherwise none.
//! - A link without `<inertial>` (urdf-rs reads it as mass 0) gets
//!   [`Link::inertial`] `None`; the physics side picks a default.
//! - Capsules (a urdf-rs extension), floating, planar and spherical joints are
//!   rejected with an error rather than approximated.

use std::collections::{BTreeMap, VecDeque};
use std::path::{Component, Path, PathBuf};

use nalgebra::{Isometry3, Matrix3, Translation3, Unit, UnitQuaternion, Vector3};

pub mod checks;
mod error;

pub use error::UrdfError;

use crate::plant::convert::isometry_from_urdf_pose;
use crate::plant::dae::load_dae;
use crate::plant::mesh::TriMesh;
use crate::plant::stl::load_stl;

/// Index of a link in [`RobotModel::links`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct LinkIndex(pub usize);

/// Index of a joint in [`RobotModel::joints`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct JointIndex(pub usize);

/// A validated kinematic tree loaded from URDF.
#[derive(Debug, Clone)]
pub struct RobotModel {
    /// The `<robot name="..">`.
    pub name: String,
    /// Links in file order.
    pub links: Vec<Link>,
    /// Joints in file order.
    pub joints: Vec<Joint>,
    /// The one link that is no joint's child.
    pub root: LinkIndex,
    /// Joints ordered so that every joint's parent link is placed before it
    /// (breadth-first from the root, ties in file order).
    topological_joints: Vec<JointIndex>,
}

/// One URDF `<link>`.
#[derive(Debug, Clone)]
pub struct Link {
    /// The link's unique name.
    pub name: String,
    /// Shapes to draw, in the link frame.
    pub visuals: Vec<Visual>,
    /// Shapes for collision, in the link frame.
    pub collisions: Vec<Collision>,
    /// Mass properties; `None` when the file gives none (or a mass of 0).
    pub inertial: Option<Inertial>,
    /// The joint whose child this link is (`None` for the root).
    pub parent_joint: Option<JointIndex>,
    /// Joints whose parent this link is, in file order.
    pub child_joints: Vec<JointIndex>,
}

/// One `<visual>` of a link.
#[derive(Debug, Clone)]
pub struct Visual {
    /// The optional `name` attribute.
    pub name: Option<String>,
    /// Pose of the geometry in the link frame (the visual's `<origin>`).
    pub link_from_visual: Isometry3<f64>,
    /// The shape.
    pub geometry: Geometry,
    /// Material name, if any (inline or a reference to a robot-level material).
    pub material_name: Option<String>,
    /// Colour as linear `[r, g, b, a]` in 0..=1, resolved from the inline
    /// material or the robot-level material of the same name.
    pub color_rgba: Option<[f32; 4]>,
}

/// One `<collision>` of a link.
#[derive(Debug, Clone)]
pub struct Collision {
    /// The optional `name` attribute.
    pub name: Option<String>,
    /// Pose of the geometry in the link frame (the collision's `<origin>`).
    pub link_from_collision: Isometry3<f64>,
    /// The shape.
    pub geometry: Geometry,
}

/// A link's `<inertial>`.
#[derive(Debug, Clone, PartialEq)]
pub struct Inertial {
    /// Pose of the inertial frame (its origin is the centre of mass) in the link frame.
    pub link_from_inertial: Isometry3<f64>,
    /// Mass in kg (> 0).
    pub mass_kg: f64,
    /// Symmetric inertia tensor about the centre of mass, in the inertial frame, kg·m².
    pub inertia_kgm2: Matrix3<f64>,
}

/// A visual or collision shape. Primitives are centred on their frame origin.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum Geometry {
    /// A box with full edge lengths `size` (x, y, z) in metres.
    Box {
        /// Edge lengths in metres.
        size: [f64; 3],
    },
    /// A cylinder along the frame's Z axis.
    Cylinder {
        /// Radius in metres.
        radius: f64,
        /// Full length along Z in metres.
        length: f64,
    },
    /// A sphere.
    Sphere {
        /// Radius in metres.
        radius: f64,
    },
    /// A triangle mesh loaded from a file.
    Mesh {
        /// The resolved file the mesh was loaded from.
        path: PathBuf,
        /// Per-axis scale to apply to `mesh` (URDF `scale`, default `[1, 1, 1]`).
        scale: [f64; 3],
        /// The mesh in file units (STL) or in metres, Z up (COLLADA, see
        /// [`crate::plant::dae`]), *not yet scaled* by `scale`.
        mesh: TriMesh,
    },
}

/// The joint types this loader supports.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum JointKind {
    /// Rotation about [`Joint::axis`] within [`Joint::limits`]; position in radians.
    Revolute,
    /// Unlimited rotation about [`Joint::axis`]; position in radians, unwrapped.
    Continuous,
    /// Translation along [`Joint::axis`]; position in metres.
    Prismatic,
    /// No motion.
    Fixed,
}

impl JointKind {
    /// Whether the joint has one degree of freedom (not [`JointKind::Fixed`]).
    pub fn is_movable(self) -> bool {
        !matches!(self, JointKind::Fixed)
    }
}

/// A joint's `<limit>`, in the joint's units (rad or m).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointLimits {
    /// Lower position limit (rad or m).
    pub lower: f64,
    /// Upper position limit (rad or m).
    pub upper: f64,
    /// Maximum effort (N·m or N).
    pub effort: f64,
    /// Maximum speed (rad/s or m/s).
    pub velocity: f64,
}

/// One URDF `<joint>`.
#[derive(Debug, Clone)]
pub struct Joint {
    /// The joint's unique name.
    pub name: String,
    /// Its type.
    pub kind: JointKind,
    /// The parent link.
    pub parent: LinkIndex,
    /// The child link (whose frame is the joint frame).
    pub child: LinkIndex,
    /// The joint frame in the parent link frame (the joint's `<origin>`).
    pub parent_from_joint: Isometry3<f64>,
    /// Unit axis of motion in the joint frame (default X, as in URDF).
    pub axis: Unit<Vector3<f64>>,
    /// Position/effort/velocity limits: `Some` for revolute and prismatic
    /// joints, `None` for continuous and fixed ones.
    pub limits: Option<JointLimits>,
}

impl Joint {
    /// `joint_from_child` at joint position `q` (rad or m): a rotation about,
    /// or translation along, [`Joint::axis`]; identity for fixed joints.
    pub fn joint_from_child(&self, q: f64) -> Isometry3<f64> {
        match self.kind {
            JointKind::Revolute | JointKind::Continuous => {
                Isometry3::from_parts(Translation3::identity(), UnitQuaternion::from_axis_angle(&self.axis, q))
            }
            JointKind::Prismatic => Isometry3::from_parts(
                Translation3::from(self.axis.into_inner() * q),
                UnitQuaternion::identity(),
            ),
            JointKind::Fixed => Isometry3::identity(),
        }
    }
}

impl RobotModel {
    /// Reads and validates a URDF file, loading its meshes.
    ///
    /// # Errors
    /// [`UrdfError::Read`] when the file cannot be read, otherwise as
    /// [`RobotModel::from_urdf_str`].
    pub fn load(path: &Path) -> Result<RobotModel, UrdfError> {
        let xml = crate::source::read_text_bounded(path, crate::source::InputKind::Urdf).map_err(|source| {
            UrdfError::Read {
                path: path.to_path_buf(),
                source,
            }
        })?;
        Self::from_urdf_str(&xml, path)
    }

    /// Parses URDF text. `urdf_path` names the file in errors, and its
    /// directory is where relative mesh file names are resolved from.
    ///
    /// # Errors
    /// [`UrdfError::Parse`] for bad XML; the mesh, geometry, joint and tree
    /// variants of [`UrdfError`] for content this loader cannot use.
    ///
    /// # Examples
    /// ```
    /// let xml = r#"<robot name="r">
    ///   <link name="base"/> <link name="arm"/>
    ///   <joint name="j" type="continuous"><parent link="base"/><child link="arm"/>
    ///     <origin xyz="0 0 1"/><axis xyz="0 0 1"/></joint>
    /// </robot>"#;
    /// let model = twin::plant::urdf::RobotModel::from_urdf_str(xml, std::path::Path::new("r.urdf")).unwrap();
    /// let world_from_link = model.world_from_link(&[0.5]);
    /// assert_eq!(world_from_link[1].translation.z, 1.0);
    /// ```
    pub fn from_urdf_str(xml: &str, urdf_path: &Path) -> Result<RobotModel, UrdfError> {
        if let Some(line) = crate::plant::xml::too_deep(xml) {
            return Err(UrdfError::TooDeep {
                path: urdf_path.to_path_buf(),
                line,
                max: crate::plant::xml::MAX_XML_DEPTH,
            });
        }
        let robot = urdf_rs::read_from_string(xml).map_err(|source| UrdfError::Parse {
            path: urdf_path.to_path_buf(),
            line: line_of(&source),
            source,
        })?;
        checks::check(&robot, xml, urdf_path)?;
        let urdf_dir = urdf_path.parent().unwrap_or(Path::new("")).to_path_buf();
        build(&robot, &urdf_dir)
    }

    /// The mesh files the robot's visuals and collisions were loaded
    /// from, each once (the run's inputs, never to be overwritten).
    pub fn mesh_files(&self) -> Vec<PathBuf> {
        let mut files: Vec<PathBuf> = Vec::new();
        for link in &self.links {
            let geometries = link.visuals.iter().map(|v| &v.geometry);
            for g in geometries.chain(link.collisions.iter().map(|c| &c.geometry)) {
                if let Geometry::Mesh { path, .. } = g
                    && !files.contains(path)
                {
                    files.push(path.clone());
                }
            }
        }
        files
    }

    /// The link called `name`, if any.
    pub fn link_by_name(&self, name: &str) -> Option<LinkIndex> {
        self.links.iter().position(|l| l.name == name).map(LinkIndex)
    }

    /// The joint called `name`, if any.
    pub fn joint_by_name(&self, name: &str) -> Option<JointIndex> {
        self.joints.iter().position(|j| j.name == name).map(JointIndex)
    }

    /// The link at `index`. Panics if the index is not from this model.
    pub fn link(&self, index: LinkIndex) -> &Link {
        &self.links[index.0]
    }

    /// The joint at `index`. Panics if the index is not from this model.
    pub fn joint(&self, index: JointIndex) -> &Joint {
        &self.joints[index.0]
    }

    /// Joints in an order where each joint's parent link is placed by an
    /// earlier joint (or is the root).
    pub fn topological_joints(&self) -> &[JointIndex] {
        &self.topological_joints
    }

    /// Forward kinematics: `world_from_link` for every link (in
    /// [`RobotModel::links`] order), with the root link at the world origin.
    ///
    /// `q[i]` is the position of `joints[i]` (rad for revolute/continuous, m
    /// for prismatic; ignored for fixed joints). Missing trailing entries are
    /// taken as 0, so `&[]` gives the zero configuration.
    pub fn world_from_link(&self, q: &[f64]) -> Vec<Isometry3<f64>> {
        let mut world_from_link = vec![Isometry3::identity(); self.links.len()];
        for &JointIndex(j) in &self.topological_joints {
            let joint = &self.joints[j];
            let qj = q.get(j).copied().unwrap_or(0.0);
            world_from_link[joint.child.0] =
                world_from_link[joint.parent.0] * joint.parent_from_joint * joint.joint_from_child(qj);
        }
        world_from_link
    }
}

/// The line number in the XML parser's message (RustyXML writes
/// `Line: 2, Column: 12`); urdf-rs exposes no structured field, and some of
/// its errors (improper nesting, schema mismatches) carry no position at all.
fn line_of(error: &urdf_rs::UrdfError) -> Option<u32> {
    let text = error.to_string().to_ascii_lowercase();
    text.match_indices("line").find_map(|(at, _)| {
        let rest = text[at + 4..].trim_start_matches([':', ' ']);
        let digits: String = rest.chars().take_while(char::is_ascii_digit).collect();
        digits.parse().ok()
    })
}

fn build(robot: &urdf_rs::Robot, urdf_dir: &Path) -> Result<RobotModel, UrdfError> {
    if robot.links.is_empty() {
        return Err(UrdfError::NoLinks);
    }
    let mut link_index: BTreeMap<&str, usize> = BTreeMap::new();
    for (i, link) in robot.links.iter().enumerate() {
        if link_index.insert(&link.name, i).is_some() {
            return Err(UrdfError::DuplicateLink {
                link: link.name.clone(),
            });
        }
    }
    let mut joint_names: BTreeMap<&str, usize> = BTreeMap::new();
    for (i, joint) in robot.joints.iter().enumerate() {
        if joint_names.insert(&joint.name, i).is_some() {
            return Err(UrdfError::DuplicateJoint {
                joint: joint.name.clone(),
            });
        }
    }
    let materials: BTreeMap<&str, [f32; 4]> = robot
        .materials
        .iter()
        .filter_map(|m| Some((m.name.as_str(), rgba(m.color.as_ref()?))))
        .collect();

    let mut links = robot
        .links
        .iter()
        .map(|l| convert_link(l, urdf_dir, &materials))
        .collect::<Result<Vec<_>, _>>()?;

    let mut joints = Vec::with_capacity(robot.joints.len());
    for (j, joint) in robot.joints.iter().enumerate() {
        let find = |name: &str| {
            link_index
                .get(name)
                .copied()
                .map(LinkIndex)
                .ok_or_else(|| UrdfError::MissingLink {
                    joint: joint.name.clone(),
                    link: name.to_string(),
                })
        };
        let parent = find(&joint.parent.link)?;
        let child = find(&joint.child.link)?;
        let converted = convert_joint(joint, parent, child)?;
        links[parent.0].child_joints.push(JointIndex(j));
        joints.push(converted);
    }

    let root = link_parents(&mut links, &joints)?;
    let topological_joints = topological_order(&links, &joints, root)?;

    Ok(RobotModel {
        name: robot.name.clone(),
        links,
        joints,
        root: LinkIndex(root),
        topological_joints,
    })
}

/// Sets each link's parent joint (exactly one per non-root link) and
/// returns the one root.
fn link_parents(links: &mut [Link], joints: &[Joint]) -> Result<usize, UrdfError> {
    let mut parents: Vec<Vec<usize>> = vec![Vec::new(); links.len()];
    for (j, joint) in joints.iter().enumerate() {
        parents[joint.child.0].push(j);
    }
    for (l, ps) in parents.iter().enumerate() {
        match ps.as_slice() {
            [] => {}
            [j] => links[l].parent_joint = Some(JointIndex(*j)),
            many => {
                return Err(UrdfError::MultipleParents {
                    link: links[l].name.clone(),
                    joints: many.iter().map(|&j| joints[j].name.clone()).collect(),
                });
            }
        }
    }
    let roots: Vec<usize> = (0..links.len()).filter(|&l| parents[l].is_empty()).collect();
    let root = match roots.as_slice() {
        [root] => *root,
        [] => {
            return Err(UrdfError::Cycle {
                links: links.iter().map(|l| l.name.clone()).collect(),
            });
        }
        many => {
            return Err(UrdfError::MultipleRoots {
                links: many.iter().map(|&l| links[l].name.clone()).collect(),
            });
        }
    };
    Ok(root)
}

/// The joints breadth-first from the root; a link not reached hangs on a
/// cycle.
fn topological_order(links: &[Link], joints: &[Joint], root: usize) -> Result<Vec<JointIndex>, UrdfError> {
    let mut reached = vec![false; links.len()];
    reached[root] = true;
    let mut topological_joints = Vec::with_capacity(joints.len());
    let mut queue = VecDeque::from([root]);
    while let Some(l) = queue.pop_front() {
        for &JointIndex(j) in &links[l].child_joints {
            let child = joints[j].child.0;
            if !reached[child] {
                reached[child] = true;
                topological_joints.push(JointIndex(j));
                queue.push_back(child);
            }
        }
    }
    if reached.iter().any(|r| !r) {
        return Err(UrdfError::Cycle {
            links: links
                .iter()
                .zip(&reached)
                .filter(|(_, r)| !**r)
                .map(|(l, _)| l.name.clone())
                .collect(),
        });
    }
    Ok(topological_joints)
}

fn rgba(color: &urdf_rs::Color) -> [f32; 4] {
    color.rgba.0.map(|c| c as f32)
}

fn convert_link(
    link: &urdf_rs::Link,
    urdf_dir: &Path,
    materials: &BTreeMap<&str, [f32; 4]>,
) -> Result<Link, UrdfError> {
    let visuals = link
        .visual
        .iter()
        .map(|v| {
            let (material_name, color_rgba) = match &v.material {
                Some(m) => {
                    let name = (!m.name.is_empty()).then(|| m.name.clone());
                    let color = m
                        .color
                        .as_ref()
                        .map(rgba)
                        .or_else(|| materials.get(m.name.as_str()).copied());
                    (name, color)
                }
                None => (None, None),
            };
            Ok(Visual {
                name: v.name.clone(),
                link_from_visual: isometry_from_urdf_pose(&v.origin),
                geometry: convert_geometry(&v.geometry, &link.name, urdf_dir)?,
                material_name,
                color_rgba,
            })
        })
        .collect::<Result<Vec<_>, UrdfError>>()?;
    let collisions = link
        .collision
        .iter()
        .map(|c| {
            let geometry = convert_geometry(&c.geometry, &link.name, urdf_dir)?;
            // Bounded whether or not the scene checks collisions: the
            // physics and the parts world build their shapes too.
            if let Geometry::Mesh { path, scale, mesh } = &geometry {
                let extent_m = mesh.extent_m(*scale);
                if extent_m > crate::scene::MAX_LENGTH_M {
                    return Err(UrdfError::CollisionMeshTooLarge {
                        link: link.name.clone(),
                        path: path.clone(),
                        extent_m,
                        max_m: crate::scene::MAX_LENGTH_M,
                    });
                }
            }
            Ok(Collision {
                name: c.name.clone(),
                link_from_collision: isometry_from_urdf_pose(&c.origin),
                geometry,
            })
        })
        .collect::<Result<Vec<_>, UrdfError>>()?;
    let i = &link.inertial;
    let inertial = (i.mass.value > 0.0).then(|| {
        let t = &i.inertia;
        Inertial {
            link_from_inertial: isometry_from_urdf_pose(&i.origin),
            mass_kg: i.mass.value,
            inertia_kgm2: Matrix3::new(
                t.ixx, t.ixy, t.ixz, //
                t.ixy, t.iyy, t.iyz, //
                t.ixz, t.iyz, t.izz,
            ),
        }
    });
    Ok(Link {
        name: link.name.clone(),
        visuals,
        collisions,
        inertial,
        parent_joint: None,
        child_joints: Vec::new(),
    })
}

fn convert_geometry(geometry: &urdf_rs::Geometry, link: &str, urdf_dir: &Path) -> Result<Geometry, UrdfError> {
    Ok(match geometry {
        urdf_rs::Geometry::Box { size } => Geometry::Box { size: size.0 },
        urdf_rs::Geometry::Cylinder { radius, length } => Geometry::Cylinder {
            radius: *radius,
            length: *length,
        },
        urdf_rs::Geometry::Sphere { radius } => Geometry::Sphere { radius: *radius },
        urdf_rs::Geometry::Capsule { .. } => {
            return Err(UrdfError::UnsupportedGeometry {
                link: link.to_string(),
                geometry: "capsule",
            });
        }
        urdf_rs::Geometry::Mesh { filename, scale } => {
            let candidates = mesh_candidates(filename, urdf_dir);
            let Some(path) = candidates.iter().find(|p| p.is_file()).cloned() else {
                return Err(UrdfError::MeshMissing {
                    link: link.to_string(),
                    filename: filename.clone(),
                    path: candidates.into_iter().next().unwrap_or_default(),
                });
            };
            let extension = path
                .extension()
                .map(|e| e.to_string_lossy().to_ascii_lowercase())
                .unwrap_or_default();
            let mesh = match extension.as_str() {
                "stl" => load_stl(&path).map_err(|source| UrdfError::Mesh {
                    link: link.to_string(),
                    path: path.clone(),
                    source,
                })?,
                "dae" => load_dae(&path).map_err(|source| UrdfError::ColladaMesh {
                    link: link.to_string(),
                    path: path.clone(),
                    source,
                })?,
                _ => {
                    return Err(UrdfError::UnsupportedMeshFormat {
                        link: link.to_string(),
                        path,
                        extension,
                    });
                }
            };
            Geometry::Mesh {
                path,
                scale: scale.as_ref().map_or([1.0; 3], |s| s.0),
                mesh,
            }
        }
    })
}

/// Where a URDF mesh `filename` may live, most likely first (see the module docs).
fn mesh_candidates(filename: &str, urdf_dir: &Path) -> Vec<PathBuf> {
    if let Some(rest) = filename.strip_prefix("package://") {
        let (package, inner) = rest.split_once('/').unwrap_or((rest, ""));
        let mut candidates = Vec::new();
        for ancestor in urdf_dir.ancestors() {
            candidates.push(ancestor.join(package).join(inner));
            if ancestor.file_name().is_some_and(|n| n == package) {
                candidates.push(ancestor.join(inner));
            }
        }
        return candidates;
    }
    let plain = filename.strip_prefix("file://").unwrap_or(filename);
    let path = Path::new(plain);
    if path.is_absolute()
        || path
            .components()
            .next()
            .is_some_and(|c| matches!(c, Component::Prefix(_)))
    {
        vec![path.to_path_buf()]
    } else {
        vec![urdf_dir.join(path)]
    }
}

fn convert_joint(joint: &urdf_rs::Joint, parent: LinkIndex, child: LinkIndex) -> Result<Joint, UrdfError> {
    let unsupported = |joint_type| UrdfError::UnsupportedJointType {
        joint: joint.name.clone(),
        joint_type,
    };
    let kind = match joint.joint_type {
        urdf_rs::JointType::Revolute => JointKind::Revolute,
        urdf_rs::JointType::Continuous => JointKind::Continuous,
        urdf_rs::JointType::Prismatic => JointKind::Prismatic,
        urdf_rs::JointType::Fixed => JointKind::Fixed,
        urdf_rs::JointType::Floating => return Err(unsupported("floating")),
        urdf_rs::JointType::Planar => return Err(unsupported("planar")),
        urdf_rs::JointType::Spherical => return Err(unsupported("spherical")),
    };
    let raw_axis = joint.axis.xyz.0;
    let axis = Vector3::from(raw_axis);
    let axis = if kind.is_movable() {
        if !axis.iter().all(|c| c.is_finite()) {
            return Err(UrdfError::InvalidAxis {
                joint: joint.name.clone(),
                axis: raw_axis,
            });
        }
        Unit::try_new(axis, 1e-12).ok_or_else(|| UrdfError::InvalidAxis {
            joint: joint.name.clone(),
            axis: raw_axis,
        })?
    } else {
        Unit::try_new(axis, 1e-12).unwrap_or_else(Vector3::x_axis)
    };
    let limits = matches!(kind, JointKind::Revolute | JointKind::Prismatic).then(|| JointLimits {
        lower: joint.limit.lower,
        upper: joint.limit.upper,
        effort: joint.limit.effort,
        velocity: joint.limit.velocity,
    });
    Ok(Joint {
        name: joint.name.clone(),
        kind,
        parent,
        child,
        parent_from_joint: isometry_from_urdf_pose(&joint.origin),
        axis,
        limits,
    })
}

#[cfg(test)]
#[allow(clippy::unwrap_used)] // a failed unwrap is a failed test
mod tests {
    use super::*;
    use crate::plant::dae::DaeError;
    use crate::plant::stl::StlError;
    use std::f64::consts::FRAC_PI_2;

    const ARM: &str = r#"<robot name="arm">
      <material name="red"><color rgba="1 0 0 1"/></material>
      <link name="base">
        <visual><geometry><box size="0.2 0.2 0.1"/></geometry><material name="red"/></visual>
      </link>
      <link name="upper">
        <inertial><origin xyz="0 0 0.25"/><mass value="2"/>
          <inertia ixx="0.04" ixy="0" ixz="0" iyy="0.04" iyz="0" izz="0.01"/></inertial>
        <visual><origin xyz="0 0 0.25"/><geometry><cylinder radius="0.05" length="0.5"/></geometry>
          <material name="blue"><color rgba="0 0 1 1"/></material></visual>
        <collision><geometry><sphere radius="0.1"/></geometry></collision>
      </link>
      <link name="slider"/>
      <joint name="shoulder" type="revolute">
        <parent link="base"/><child link="upper"/>
        <origin xyz="0 0 0.1"/><axis xyz="0 1 0"/>
        <limit lower="-1.5" upper="1.5" effort="10" velocity="2"/>
      </joint>
      <joint name="slide" type="prismatic">
        <parent link="upper"/><child link="slider"/>
        <origin xyz="0 0 0.5" rpy="0 0 1.5707963267948966"/><axis xyz="1 0 0"/>
        <limit lower="0" upper="0.3" effort="100" velocity="0.5"/>
      </joint>
    </robot>"#;

    fn parse(xml: &str) -> Result<RobotModel, UrdfError> {
        RobotModel::from_urdf_str(xml, Path::new("/tmp/does-not-matter/robot.urdf"))
    }

    #[test]
    fn arm_structure_materials_and_inertia() {
        let m = parse(ARM).unwrap();
        assert_eq!(m.name, "arm");
        assert_eq!(m.root, LinkIndex(0));
        assert_eq!(m.link_by_name("upper"), Some(LinkIndex(1)));
        assert_eq!(m.joint_by_name("slide"), Some(JointIndex(1)));
        assert_eq!(m.joint_by_name("nope"), None);
        let base = m.link(LinkIndex(0));
        assert_eq!(base.visuals[0].color_rgba, Some([1.0, 0.0, 0.0, 1.0]));
        assert_eq!(base.visuals[0].material_name.as_deref(), Some("red"));
        assert!(base.inertial.is_none());
        let upper = m.link(LinkIndex(1));
        assert_eq!(upper.visuals[0].color_rgba, Some([0.0, 0.0, 1.0, 1.0]));
        assert_eq!(
            upper.visuals[0].geometry,
            Geometry::Cylinder {
                radius: 0.05,
                length: 0.5
            }
        );
        assert_eq!(upper.collisions[0].geometry, Geometry::Sphere { radius: 0.1 });
        let inertial = upper.inertial.as_ref().unwrap();
        assert_eq!(inertial.mass_kg, 2.0);
        assert_eq!(inertial.inertia_kgm2[(2, 2)], 0.01);
        assert_eq!(upper.parent_joint, Some(JointIndex(0)));
        assert_eq!(base.child_joints, vec![JointIndex(0)]);
        let shoulder = m.joint(JointIndex(0));
        assert_eq!(shoulder.kind, JointKind::Revolute);
        assert_eq!(shoulder.limits.unwrap().upper, 1.5);
        assert_eq!(shoulder.axis.into_inner(), Vector3::y());
    }

    #[test]
    fn forward_kinematics_known_values() {
        let m = parse(ARM).unwrap();
        let zero = m.world_from_link(&[]);
        assert!((zero[2].translation.vector - Vector3::new(0.0, 0.0, 0.6)).norm() < 1e-12);
        // Shoulder +90° about Y tips the arm's +Z onto world +X; slide moves
        // 0.2 m along its X, which the yaw of its origin turns onto the arm's +Y.
        let q = m.world_from_link(&[FRAC_PI_2, 0.2]);
        let slider = q[2].translation.vector;
        assert!((slider - Vector3::new(0.5, 0.2, 0.1)).norm() < 1e-12, "{slider}");
    }

    #[test]
    fn missing_link_names_joint_and_link() {
        let xml = ARM.replace(r#"<child link="slider"/>"#, r#"<child link="ghost"/>"#);
        match parse(&xml) {
            Err(UrdfError::MissingLink { joint, link }) => {
                assert_eq!(joint, "slide");
                assert_eq!(link, "ghost");
            }
            other => panic!("unexpected {other:?}"),
        }
    }

    #[test]
    fn two_roots_are_rejected() {
        let xml = ARM.replace(
            r#"<link name="slider"/>"#,
            r#"<link name="slider"/><link name="loose"/>"#,
        );
        match parse(&xml) {
            Err(UrdfError::MultipleRoots { links }) => assert_eq!(links, vec!["base", "loose"]),
            other => panic!("unexpected {other:?}"),
        }
    }

    #[test]
    fn cycles_are_rejected() {
        let xml = r#"<robot name="c"><link name="base"/><link name="a"/><link name="b"/>
          <joint name="ab" type="fixed"><parent link="a"/><child link="b"/></joint>
          <joint name="ba" type="fixed"><parent link="b"/><child link="a"/></joint></robot>"#;
        match parse(xml) {
            Err(UrdfError::Cycle { links }) => assert_eq!(links, vec!["a", "b"]),
            other => panic!("unexpected {other:?}"),
        }
        let xml = r#"<robot name="c"><link name="a"/><link name="b"/>
          <joint name="ab" type="fixed"><parent link="a"/><child link="b"/></joint>
          <joint name="ba" type="fixed"><parent link="b"/><child link="a"/></joint></robot>"#;
        assert!(matches!(parse(xml), Err(UrdfError::Cycle { .. })));
    }

    #[test]
    fn two_parents_are_rejected() {
        let xml = r#"<robot name="c"><link name="a"/><link name="b"/><link name="c"/>
          <joint name="ac" type="fixed"><parent link="a"/><child link="c"/></joint>
          <joint name="ab" type="fixed"><parent link="a"/><child link="b"/></joint>
          <joint name="bc" type="fixed"><parent link="b"/><child link="c"/></joint></robot>"#;
        assert!(matches!(parse(xml), Err(UrdfError::MultipleParents { link, .. }) if link == "c"));
    }

    #[test]
    fn invalid_xml_names_file_and_line() {
        let err = parse("<robot name=\"x\">\n<link name=a/>\n</robot>").unwrap_err();
        match err {
            UrdfError::Parse { path, line, source } => {
                assert_eq!(path, Path::new("/tmp/does-not-matter/robot.urdf"));
                assert_eq!(line, Some(2), "{source:?}");
            }
            other => panic!("unexpected {other:?}"),
        }
        // Improper nesting is reported without a position.
        let err = parse("<robot name=\"x\">\n<link name=\"a\">\n</robot>").unwrap_err();
        assert!(matches!(err, UrdfError::Parse { line: None, .. }));
    }

    #[test]
    fn unreadable_file_is_read_error() {
        assert!(matches!(
            RobotModel::load(Path::new("/nonexistent/robot.urdf")),
            Err(UrdfError::Read { .. })
        ));
    }

    #[test]
    fn unsupported_joint_and_zero_axis_are_rejected() {
        let xml = ARM.replace(r#"type="prismatic""#, r#"type="floating""#);
        assert!(matches!(
            parse(&xml),
            Err(UrdfError::UnsupportedJointType {
                joint_type: "floating",
                ..
            })
        ));
        let xml = ARM.replace(r#"<axis xyz="0 1 0"/>"#, r#"<axis xyz="0 0 0"/>"#);
        assert!(matches!(parse(&xml), Err(UrdfError::InvalidAxis { joint, .. }) if joint == "shoulder"));
    }

    fn temp_dir(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("twin-urdf-{name}-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    const TRIANGLE_STL: &str = "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n";

    fn with_mesh(filename: &str) -> String {
        format!(
            r#"<robot name="m"><link name="base"><visual><geometry>
              <mesh filename="{filename}" scale="2 2 2"/></geometry></visual></link></robot>"#
        )
    }

    #[test]
    fn meshes_resolve_relative_package_and_file_urls() {
        let dir = temp_dir("resolve");
        let pkg = dir.join("my_pkg");
        std::fs::create_dir_all(pkg.join("urdf")).unwrap();
        std::fs::create_dir_all(pkg.join("meshes")).unwrap();
        let stl = pkg.join("meshes/tri.stl");
        std::fs::write(&stl, TRIANGLE_STL).unwrap();
        let urdf = pkg.join("urdf/robot.urdf");
        for filename in [
            "../meshes/tri.stl".to_string(),
            "package://my_pkg/meshes/tri.stl".to_string(),
            format!("file://{}", stl.display()),
        ] {
            let m = RobotModel::from_urdf_str(&with_mesh(&filename), &urdf).unwrap();
            match &m.links[0].visuals[0].geometry {
                Geometry::Mesh { path, scale, mesh } => {
                    assert_eq!(path.canonicalize().unwrap(), stl.canonicalize().unwrap());
                    assert_eq!(*scale, [2.0; 3]);
                    assert_eq!(mesh.indices.len(), 3);
                }
                other => panic!("{filename}: {other:?}"),
            }
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn dae_meshes_load_in_metres_with_the_urdf_scale_kept_aside() {
        let dir = temp_dir("dae");
        let cube = TriMesh::cuboid([100.0; 3]);
        let doc = crate::plant::dae::test_docs::collada(
            r#"<unit meter="0.01"/><up_axis>Z_UP</up_axis>"#,
            &[(&cube, [0.0; 3])],
            true,
        );
        std::fs::write(dir.join("CUBE.DAE"), doc).unwrap();
        let m = RobotModel::from_urdf_str(&with_mesh("CUBE.DAE"), &dir.join("robot.urdf")).unwrap();
        match &m.links[0].visuals[0].geometry {
            Geometry::Mesh { path, scale, mesh } => {
                assert_eq!(*path, dir.join("CUBE.DAE"));
                assert_eq!(*scale, [2.0; 3]);
                assert_eq!(mesh.indices.len(), cube.indices.len());
                assert!((mesh.signed_volume() - 1.0).abs() < 1e-6, "{}", mesh.signed_volume());
            }
            other => panic!("{other:?}"),
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn mesh_errors_name_link_and_file() {
        let dir = temp_dir("errors");
        let urdf = dir.join("robot.urdf");
        match RobotModel::from_urdf_str(&with_mesh("missing.stl"), &urdf) {
            Err(UrdfError::MeshMissing { link, filename, path }) => {
                assert_eq!(link, "base");
                assert_eq!(filename, "missing.stl");
                assert_eq!(path, dir.join("missing.stl"));
            }
            other => panic!("unexpected {other:?}"),
        }
        std::fs::write(dir.join("broken.stl"), [0u8; 30]).unwrap();
        match RobotModel::from_urdf_str(&with_mesh("broken.stl"), &urdf) {
            Err(UrdfError::Mesh {
                link,
                path,
                source: StlError::Truncated { .. },
            }) => {
                assert_eq!(link, "base");
                assert_eq!(path, dir.join("broken.stl"));
            }
            other => panic!("unexpected {other:?}"),
        }
        std::fs::write(dir.join("part.dae"), "<COLLADA/>").unwrap();
        match RobotModel::from_urdf_str(&with_mesh("part.dae"), &urdf) {
            Err(
                e @ UrdfError::ColladaMesh {
                    source: DaeError::Malformed { .. },
                    ..
                },
            ) => {
                let UrdfError::ColladaMesh { link, path, source } = &e else {
                    unreachable!()
                };
                assert_eq!(link, "base");
                assert_eq!(*path, dir.join("part.dae"));
                assert!(source.to_string().contains("part.dae"), "{source}");
            }
            other => panic!("unexpected {other:?}"),
        }
        std::fs::write(dir.join("part.obj"), "v 0 0 0\n").unwrap();
        match RobotModel::from_urdf_str(&with_mesh("part.obj"), &urdf) {
            Err(UrdfError::UnsupportedMeshFormat { link, extension, .. }) => {
                assert_eq!(link, "base");
                assert_eq!(extension, "obj");
            }
            other => panic!("unexpected {other:?}"),
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn indexing_table_loads_with_its_mesh_and_colours() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/robots/indexing_table/indexing_table.urdf");
        let m = RobotModel::load(&path).unwrap();
        assert_eq!(m.name, "indexing_table");
        assert_eq!(m.link(m.root).name, "base_link");
        let joint = m.joint(m.joint_by_name("platter_joint").unwrap());
        assert_eq!(joint.kind, JointKind::Continuous);
        assert_eq!(joint.axis.into_inner(), Vector3::z());
        let platter = m.link_by_name("platter").unwrap();
        assert_eq!(joint.child, platter);
        let fixtures = ["fixture_vblock", "fixture_clamp", "fixture_pin", "fixture_ball"];
        let mut colours = Vec::new();
        for name in fixtures {
            let link = m.link(m.link_by_name(name).unwrap());
            assert_eq!(m.joint(link.parent_joint.unwrap()).parent, platter, "{name}");
            assert!(link.inertial.is_some(), "{name}");
            colours.push(link.visuals[0].color_rgba.unwrap());
        }
        colours.sort_by(|a, b| a.partial_cmp(b).unwrap());
        colours.dedup();
        assert_eq!(colours.len(), 4, "fixtures must be told apart by colour");
        let vblock = m.link(m.link_by_name("fixture_vblock").unwrap());
        match &vblock.visuals[0].geometry {
            Geometry::Mesh { path, mesh, .. } => {
                assert!(path.ends_with("meshes/vblock_fixture.stl"));
                assert_eq!(mesh.indices.len(), 28 * 3);
                let top = mesh.positions.iter().map(|p| p[2]).fold(f32::MIN, f32::max);
                assert!((top - 0.08).abs() < 1e-6);
            }
            other => panic!("{other:?}"),
        }
        // A quarter turn of the platter carries the V-block (at +X) to +Y.
        let i = m.link_by_name("fixture_vblock").unwrap().0;
        let world_from_link = m.world_from_link(&[std::f64::consts::FRAC_PI_2]);
        let p = world_from_link[i].translation.vector;
        assert!((p - Vector3::new(0.0, 0.22, 0.76)).norm() < 1e-9, "{p}");
    }

    #[test]
    fn a_urdf_nested_thousands_deep_is_refused_not_a_stack_overflow() {
        let xml = format!(
            "<robot name=\"r\">\n<link name=\"base\">{}{}</link></robot>",
            "<visual>".repeat(20_000),
            "</visual>".repeat(20_000)
        );
        match RobotModel::from_urdf_str(&xml, Path::new("deep.urdf")) {
            Err(e @ UrdfError::TooDeep { line: 2, .. }) => {
                assert!(
                    e.to_string()
                        .starts_with("deep.urdf:2: elements nested deeper than 256"),
                    "{e}"
                );
            }
            other => panic!("unexpected {other:?}"),
        }
    }
}
