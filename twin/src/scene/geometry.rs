//! The `geometry` table of a `COORDINATE_SYSTEM` tag: the MCT geometry of a
//! robot's joint coordinate system (its Logix Geometry and Offsets tabs) and
//! how its chain maps onto the URDF, for the load-time kinematics check
//! ([`crate::plant::kinematics_check`]).

use super::context::Ctx;
use super::model::GeometrySettings;
use super::raw::RawGeometry;

use super::error::{Problem, SceneError};
use super::raw::Numbers;
use planner::mct::{GeometryKind, GeometryParams};
use toml::Spanned;

/// The geometry names accepted in `type`, with their kinds.
pub const GEOMETRY_TYPES: &[(&str, GeometryKind)] = &[
    ("cartesian_gantry", GeometryKind::CartesianGantry),
    ("cartesian_hbot", GeometryKind::CartesianHBot),
    ("articulated_independent", GeometryKind::ArticulatedIndependent),
    ("articulated_dependent", GeometryKind::ArticulatedDependent),
    ("scara_independent", GeometryKind::ScaraIndependent),
    ("delta_3d", GeometryKind::Delta3d),
    ("delta_2d", GeometryKind::Delta2d),
    ("scara_delta", GeometryKind::ScaraDelta),
];

impl Ctx<'_> {
    pub(super) fn geometry(
        &self,
        raw: &Spanned<RawGeometry>,
        members: usize,
        field: &str,
    ) -> Result<GeometrySettings, SceneError> {
        let f = |x: &str| format!("{field}.{x}");
        let r = raw.get_ref();
        let Some(&(_, kind)) = GEOMETRY_TYPES
            .iter()
            .find(|(n, _)| n.eq_ignore_ascii_case(r.kind.get_ref()))
        else {
            let names: Vec<&str> = GEOMETRY_TYPES.iter().map(|(n, _)| *n).collect();
            return Err(self.invalid(
                &r.kind,
                f("type"),
                Problem::UnknownGeometry {
                    name: r.kind.get_ref().clone(),
                    expected: names.join(", "),
                },
            ));
        };
        let natural = match kind {
            GeometryKind::ScaraIndependent | GeometryKind::Delta2d | GeometryKind::ScaraDelta => 2,
            GeometryKind::Delta3d => 3,
            _ => members.min(3),
        };
        let transform_dimension = match &r.transform_dimension {
            Some(d) => self.int_in_range(d, &f("transform_dimension"), 1, 3)? as usize,
            None => natural,
        };
        let three = |v: &Option<Spanned<Numbers<3>>>, name: &str| match v {
            Some(v) => self.finite_array(v, &f(name)),
            None => Ok([0.0; 3]),
        };
        let link_lengths = match &r.link_lengths {
            Some(v) => {
                let [l1, l2] = self.finite_array(v, &f("link_lengths"))?;
                [l1, l2, 0.0]
            }
            None => [0.0; 3],
        };
        let names = |v: &Option<Vec<Spanned<String>>>, name: &str| -> Result<Vec<String>, SceneError> {
            v.iter().flatten().map(|s| self.nonempty_name(s, &f(name))).collect()
        };
        Ok(GeometrySettings {
            kind,
            transform_dimension,
            params: GeometryParams {
                link_lengths,
                base_offsets: three(&r.base_offsets, "base_offsets")?,
                end_effector_offsets: three(&r.end_effector_offsets, "end_effector_offsets")?,
                zero_angles_deg: three(&r.zero_angles_deg, "zero_angles_deg")?,
            },
            base_link: r
                .base_link
                .as_ref()
                .map(|l| self.nonempty_name(l, &f("base_link")))
                .transpose()?,
            tool_link: r
                .tool_link
                .as_ref()
                .map(|l| self.nonempty_name(l, &f("tool_link")))
                .transpose()?,
            platform_joints: names(&r.platform_joints, "platform_joints")?,
            forearm_joints: r
                .forearm_joints
                .iter()
                .flatten()
                .map(|[a, b]| {
                    Ok([
                        self.nonempty_name(a, &f("forearm_joints"))?,
                        self.nonempty_name(b, &f("forearm_joints"))?,
                    ])
                })
                .collect::<Result<_, SceneError>>()?,
            forearm_tip_links: names(&r.forearm_tip_links, "forearm_tip_links")?,
            ball_links: names(&r.ball_links, "ball_links")?,
            location: self.loc(raw),
        })
    }
}
