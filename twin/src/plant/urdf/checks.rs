//! The physical quantities of a URDF, checked before anything is built.
//!
//! A NaN origin, a negative or absurd mass, an inertia that no body can
//! have, or a box of 10³⁰⁰ m does not fail loudly downstream: rapier and
//! parry turn it into NaN poses, panics deep in their solvers, or a body
//! that silently drops out of collision checking. So every number is
//! checked here, and the error names the file, the link or joint, the
//! element and its line:
//!
//! | element | rule |
//! | --- | --- |
//! | every `<origin>` `xyz`, `rpy` | finite; `xyz` within ±[`MAX_LENGTH_M`] |
//! | `<inertial><mass value>` | finite, ≥ 0, ≤ [`MAX_MASS_KG`] (0: no inertial) |
//! | `<inertial><inertia>` (with a mass) | finite; symmetric positive-definite (every principal moment > 0); each principal moment at most the sum of the other two (the triangle inequality every rigid body obeys, to 10⁻⁶ relative); the largest at most mass × [`MAX_LENGTH_M`]² (what the mass could have if it lay that far from its centre: a larger moment is not a body a scene can hold, and it makes the multibody diverge) |
//! | `<box size>`, `<sphere radius>`, `<cylinder>`/`<capsule>` `radius`, `length` | finite, > 0, ≤ [`MAX_LENGTH_M`] |
//! | `<mesh scale>` | finite, non-zero, magnitude ≤ 10⁶ |
//! | `<limit>` `lower`, `upper`, `effort`, `velocity` | finite; `lower ≤ upper`; `effort`, `velocity` ≥ 0 |
//! | `<dynamics>` `damping`, `friction` | finite, ≥ 0 |
//! | the `<link>`s, the `<joint>`s | at most [`MAX_LINKS`] each (the first past it is named) |

use std::path::Path;

use nalgebra::{Matrix3, SymmetricEigen};

use super::error::UrdfError;
pub use crate::scene::MAX_LENGTH_M;

/// The largest link mass, kg.
pub const MAX_MASS_KG: f64 = 1e7;

/// What is wrong, where.
struct Finding {
    owner: String,
    element: String,
    problem: String,
}

/// Checks every physical quantity of `robot` (module doc); `xml` is the
/// file's text, for the line of the offending element.
pub(super) fn check(robot: &urdf_rs::Robot, xml: &str, path: &Path) -> Result<(), UrdfError> {
    let Some(f) = first_finding(robot) else {
        return Ok(());
    };
    Err(UrdfError::Physical {
        path: path.to_path_buf(),
        line: line_of(xml, &f.owner, &f.element),
        owner: f.owner,
        element: f.element,
        problem: f.problem,
    })
}

/// The most links, and the most joints, a robot may have. Rapier's
/// multibody keeps a Jacobian of every link over every joint, so its
/// memory and the work of each physics step grow with links × joints
/// (10,000 links took 4.8 GB to build); real cells have tens of links.
pub const MAX_LINKS: usize = 256;

/// The first problem of the robot's links, then of its joints, in
/// document order; first of all, more links or joints than [`MAX_LINKS`].
fn first_finding(robot: &urdf_rs::Robot) -> Option<Finding> {
    let too_many = |kind: &str, count: usize, name: &str| Finding {
        owner: format!("{kind} {name}"),
        element: kind.to_owned(),
        problem: format!("the robot has {count} {kind}s, more than the {MAX_LINKS} a robot may have"),
    };
    if let Some(l) = robot.links.get(MAX_LINKS) {
        return Some(too_many("link", robot.links.len(), &l.name));
    }
    if let Some(j) = robot.joints.get(MAX_LINKS) {
        return Some(too_many("joint", robot.joints.len(), &j.name));
    }
    robot
        .links
        .iter()
        .find_map(link_finding)
        .or_else(|| robot.joints.iter().find_map(joint_finding))
}

/// Makes the findings of one owner (`link base`): element, problem.
fn finding(owner: String) -> impl Fn(&str, String) -> Finding {
    move |element, problem| Finding {
        owner: owner.clone(),
        element: element.to_owned(),
        problem,
    }
}

/// The first problem of a link: its inertial, then its visuals' and
/// collisions' origins and geometry.
fn link_finding(link: &urdf_rs::Link) -> Option<Finding> {
    let at = finding(format!("link {}", link.name));
    let i = &link.inertial;
    if let Some(p) = pose_problem(&i.origin) {
        return Some(at("inertial/origin", p));
    }
    let mass = i.mass.value;
    if !(mass.is_finite() && (0.0..=MAX_MASS_KG).contains(&mass)) {
        return Some(at(
            "inertial/mass",
            format!("value must be within 0..={MAX_MASS_KG:e} kg, got {mass}"),
        ));
    }
    if mass > 0.0
        && let Some(p) = inertia_problem(&i.inertia, mass)
    {
        return Some(at("inertial/inertia", p));
    }
    for (kind, shapes) in [
        (
            "visual",
            link.visual.iter().map(|v| (&v.origin, &v.geometry)).collect::<Vec<_>>(),
        ),
        (
            "collision",
            link.collision.iter().map(|c| (&c.origin, &c.geometry)).collect(),
        ),
    ] {
        for (k, (origin, geometry)) in shapes.into_iter().enumerate() {
            if let Some(p) = pose_problem(origin) {
                return Some(at(&format!("{kind}[{k}]/origin"), p));
            }
            if let Some((element, p)) = geometry_problem(geometry) {
                return Some(at(&format!("{kind}[{k}]/geometry/{element}"), p));
            }
        }
    }
    None
}

/// The first problem of a joint: its origin, limits and dynamics.
fn joint_finding(joint: &urdf_rs::Joint) -> Option<Finding> {
    let at = finding(format!("joint {}", joint.name));
    if let Some(p) = pose_problem(&joint.origin) {
        return Some(at("origin", p));
    }
    let l = &joint.limit;
    for (name, v) in [
        ("lower", l.lower),
        ("upper", l.upper),
        ("effort", l.effort),
        ("velocity", l.velocity),
    ] {
        if !v.is_finite() {
            return Some(at("limit", format!("{name} must be finite, got {v}")));
        }
    }
    if l.lower > l.upper {
        return Some(at("limit", format!("lower {} is above upper {}", l.lower, l.upper)));
    }
    for (name, v) in [("effort", l.effort), ("velocity", l.velocity)] {
        if v < 0.0 {
            return Some(at("limit", format!("{name} must not be negative, got {v}")));
        }
    }
    if let Some(d) = &joint.dynamics {
        for (name, v) in [("damping", d.damping), ("friction", d.friction)] {
            if !(v.is_finite() && v >= 0.0) {
                return Some(at("dynamics", format!("{name} must be finite and ≥ 0, got {v}")));
            }
        }
    }
    None
}

fn pose_problem(pose: &urdf_rs::Pose) -> Option<String> {
    let (xyz, rpy) = (*pose.xyz, *pose.rpy);
    if !xyz.iter().chain(&rpy).all(|v| v.is_finite()) {
        return Some(format!("xyz {xyz:?} and rpy {rpy:?} must be finite"));
    }
    xyz.iter()
        .any(|v| v.abs() > MAX_LENGTH_M)
        .then(|| format!("xyz {xyz:?} is farther than {MAX_LENGTH_M:e} m"))
}

fn length_problem(name: &str, v: f64) -> Option<String> {
    (!(v.is_finite() && v > 0.0 && v <= MAX_LENGTH_M))
        .then(|| format!("{name} must be within (0, {MAX_LENGTH_M:e}] m, got {v}"))
}

fn geometry_problem(geometry: &urdf_rs::Geometry) -> Option<(&'static str, String)> {
    match geometry {
        urdf_rs::Geometry::Box { size } => size.iter().find_map(|v| length_problem("size", *v)).map(|p| ("box", p)),
        urdf_rs::Geometry::Sphere { radius } => length_problem("radius", *radius).map(|p| ("sphere", p)),
        urdf_rs::Geometry::Cylinder { radius, length } => length_problem("radius", *radius)
            .or_else(|| length_problem("length", *length))
            .map(|p| ("cylinder", p)),
        urdf_rs::Geometry::Capsule { radius, length } => length_problem("radius", *radius)
            .or_else(|| length_problem("length", *length))
            .map(|p| ("capsule", p)),
        urdf_rs::Geometry::Mesh { scale, .. } => scale.as_ref().and_then(|s| {
            s.iter()
                .any(|v| !(v.is_finite() && *v != 0.0 && v.abs() <= 1e6))
                .then(|| {
                    (
                        "mesh",
                        format!("scale {:?} must be finite, non-zero and at most 1e6", **s),
                    )
                })
        }),
    }
}

fn inertia_problem(i: &urdf_rs::Inertia, mass_kg: f64) -> Option<String> {
    let values = [i.ixx, i.ixy, i.ixz, i.iyy, i.iyz, i.izz];
    if !values.iter().all(|v| v.is_finite()) {
        return Some(format!("ixx..izz {values:?} must be finite"));
    }
    let m = Matrix3::new(i.ixx, i.ixy, i.ixz, i.ixy, i.iyy, i.iyz, i.ixz, i.iyz, i.izz);
    let mut moments: Vec<f64> = SymmetricEigen::new(m).eigenvalues.iter().copied().collect();
    moments.sort_by(f64::total_cmp);
    if moments[0] <= 0.0 {
        return Some(format!(
            "not positive-definite: principal moments {moments:?} kg·m² (every one must be > 0)"
        ));
    }
    let largest = mass_kg * MAX_LENGTH_M * MAX_LENGTH_M;
    if moments[2] > largest {
        return Some(format!(
            "principal moment {} kg·m² is more than mass × {MAX_LENGTH_M:e} m squared ({largest:e} kg·m²): no body in a scene has it",
            moments[2]
        ));
    }
    let tolerance = 1e-6 * moments[2];
    (moments[2] > moments[0] + moments[1] + tolerance).then(|| {
        format!(
            "principal moments {moments:?} kg·m² break the triangle inequality ({} > {} + {}): no rigid body has them",
            moments[2], moments[0], moments[1]
        )
    })
}

/// The line of `element` (`a/b[k]/c`) under `owner` (`link NAME` or
/// `joint NAME`), if the text has it.
fn line_of(xml: &str, owner: &str, element: &str) -> Option<usize> {
    let doc = roxmltree::Document::parse(xml).ok()?;
    let (tag, name) = owner.split_once(' ')?;
    let mut node = doc
        .root_element()
        .children()
        .find(|n| n.has_tag_name(tag) && n.attribute("name") == Some(name))?;
    for step in element.split('/') {
        let (step_tag, index) = match step.split_once('[') {
            Some((t, rest)) => (t, rest.trim_end_matches(']').parse::<usize>().unwrap_or(0)),
            None => (step, 0),
        };
        let next = if matches!(step_tag, "box" | "sphere" | "cylinder" | "capsule" | "mesh") {
            // The geometry's shape is its only element child.
            node.children().find(|n| n.is_element())
        } else {
            node.children().filter(|n| n.has_tag_name(step_tag)).nth(index)
        };
        // An element urdf-rs defaulted has no line: its parent's.
        let Some(n) = next else { break };
        node = n;
    }
    Some(doc.text_pos_at(node.range().start).row as usize)
}

#[cfg(test)]
mod tests {
    use super::super::RobotModel;
    use super::*;

    /// A two-link arm with `link` and `joint` spliced in as the arm's and
    /// the joint's inner elements: `link` from line 4, the joint's
    /// `<limit>` on line 7 and `joint` on line 8 (for a one-line `link`).
    fn urdf(link: &str, joint: &str) -> String {
        format!(
            "<robot name=\"r\">\n<link name=\"base\"/>\n<link name=\"arm\">\n{link}\n</link>\n\
             <joint name=\"j\" type=\"revolute\"><parent link=\"base\"/><child link=\"arm\"/>\n\
             <axis xyz=\"0 0 1\"/><limit lower=\"-1\" upper=\"1\" effort=\"10\" velocity=\"1\"/>\n\
             {joint}\n</joint>\n</robot>"
        )
    }

    const GOOD_INERTIAL: &str = "<inertial><mass value=\"2\"/><inertia ixx=\"0.04\" ixy=\"0\" ixz=\"0\" iyy=\"0.04\" iyz=\"0\" izz=\"0.01\"/></inertial>";

    fn finding(xml: &str) -> (String, String, Option<usize>, String) {
        match RobotModel::from_urdf_str(xml, Path::new("r.urdf")) {
            Err(e @ UrdfError::Physical { .. }) => {
                let text = e.to_string();
                let UrdfError::Physical {
                    owner, element, line, ..
                } = e
                else {
                    unreachable!()
                };
                (owner, element, line, text)
            }
            other => panic!("expected a physical error, got {other:?}"),
        }
    }

    #[test]
    fn every_reproducer_names_its_link_or_joint_element_and_line() {
        let cases = [
            // A joint origin of NaN used to panic in nalgebra's LU.
            (urdf(GOOD_INERTIAL, "<origin xyz=\"nan 0 0\"/>"), "joint j", "origin", 8),
            // A NaN inertial origin made the tool position NaN with exit 0.
            (
                urdf(
                    "<inertial><origin xyz=\"nan 0 0\"/><mass value=\"1\"/><inertia ixx=\"1\" iyy=\"1\" izz=\"1\" ixy=\"0\" ixz=\"0\" iyz=\"0\"/></inertial>",
                    "",
                ),
                "link arm",
                "inertial/origin",
                4,
            ),
            (
                urdf(
                    "<inertial><mass value=\"-2\"/><inertia ixx=\"1\" iyy=\"1\" izz=\"1\" ixy=\"0\" ixz=\"0\" iyz=\"0\"/></inertial>",
                    "",
                ),
                "link arm",
                "inertial/mass",
                4,
            ),
            // Not positive-definite.
            (
                urdf(
                    "<inertial><mass value=\"1\"/><inertia ixx=\"1\" ixy=\"2\" ixz=\"0\" iyy=\"1\" iyz=\"0\" izz=\"1\"/></inertial>",
                    "",
                ),
                "link arm",
                "inertial/inertia",
                4,
            ),
            // Absurd: izz far above ixx + iyy.
            (
                urdf(
                    "<inertial><mass value=\"1\"/><inertia ixx=\"1e-6\" ixy=\"0\" ixz=\"0\" iyy=\"1e-6\" iyz=\"0\" izz=\"1e3\"/></inertial>",
                    "",
                ),
                "link arm",
                "inertial/inertia",
                4,
            ),
            // 1e20 on a 4 kg link passed and the multibody diverged (J1 at
            // 27,565° after 12 ms, exit 0).
            (
                urdf(
                    "<inertial><mass value=\"4\"/><inertia ixx=\"1e20\" ixy=\"0\" ixz=\"0\" iyy=\"1e20\" iyz=\"0\" izz=\"1e20\"/></inertial>",
                    "",
                ),
                "link arm",
                "inertial/inertia",
                4,
            ),
            // A box of 1e300 m used to panic in parry's EPA.
            (
                urdf(
                    "<collision><geometry><box size=\"1e300 1 1\"/></geometry></collision>",
                    "",
                ),
                "link arm",
                "collision[0]/geometry/box",
                4,
            ),
            // A zero or negative sphere silently left collision checking.
            (
                urdf("<collision><geometry><sphere radius=\"0\"/></geometry></collision>", ""),
                "link arm",
                "collision[0]/geometry/sphere",
                4,
            ),
            (
                urdf(
                    "<visual><geometry><box size=\"1 1 1\"/></geometry></visual>\n<visual><geometry><cylinder radius=\"-1\" length=\"1\"/></geometry></visual>",
                    "",
                ),
                "link arm",
                "visual[1]/geometry/cylinder",
                5,
            ),
            (
                urdf(GOOD_INERTIAL, "").replace("lower=\"-1\" upper=\"1\"", "lower=\"1\" upper=\"-1\""),
                "joint j",
                "limit",
                7,
            ),
        ];
        for (xml, owner, element, line) in cases {
            let (o, e, l, text) = finding(&xml);
            assert_eq!(
                (o.as_str(), e.as_str(), l),
                (owner, element, Some(line)),
                "{text}\n{xml}"
            );
            assert!(
                text.starts_with(&format!("r.urdf:{line}: {owner}: <{element}>: ")),
                "{text}"
            );
        }
    }

    #[test]
    fn plausible_robots_pass() {
        let xml = urdf(
            &format!("{GOOD_INERTIAL}<collision><geometry><sphere radius=\"0.05\"/></geometry></collision>"),
            "<origin xyz=\"0 0 0.5\" rpy=\"0 0 1.57\"/><dynamics damping=\"0.1\" friction=\"0\"/>",
        );
        RobotModel::from_urdf_str(&xml, Path::new("r.urdf")).expect("loads");
    }
}
