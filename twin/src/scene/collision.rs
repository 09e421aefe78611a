//! The scene's `[collision]` table: what the twin checks for collisions,
//! how it reacts, and the pre-flight sweep of planned moves. Documented
//! field by field in `scenes/README.md`; names of links are checked against
//! the URDF by [`crate::collision`].

use super::context::Ctx;
use super::context::ShapeFields;
use super::error::{Problem, SceneError};
use super::model::{AllowedPair, CollisionSettings, MeshApproximation, Preflight, Reaction, Tool};
use super::raw::{RawCollision, RawTool};
use std::path::Path;

impl Ctx<'_> {
    pub(super) fn collision(&self, raw: &RawCollision, base: &Path) -> Result<CollisionSettings, SceneError> {
        let sweep_resolution_m = match &raw.sweep_resolution_m {
            Some(v) => self.positive(v, "collision.sweep_resolution_m")?,
            None => 0.001,
        };
        let mut allowed_pairs = Vec::new();
        for (i, p) in raw.allowed_pairs.iter().enumerate() {
            let [a, b] = p.get_ref().clone();
            if a.trim().is_empty() || b.trim().is_empty() {
                return Err(self.invalid(p, format!("collision.allowed_pairs[{i}]"), Problem::Empty));
            }
            allowed_pairs.push(AllowedPair {
                a,
                b,
                location: self.loc(p),
            });
        }
        let tool = match &raw.tool {
            Some(t) => Some(self.tool(t, base)?),
            None => None,
        };
        // The table's place: its header line, else its first field.
        let header = self
            .text
            .match_indices("[collision")
            .find(|(at, _)| {
                self.text[..*at]
                    .rsplit('\n')
                    .next()
                    .is_some_and(|l| l.trim().is_empty())
            })
            .map(|(at, _)| at);
        let first = [
            header,
            raw.reaction.as_ref().map(|s| s.span().start),
            raw.meshes.as_ref().map(|s| s.span().start),
            raw.self_collision.as_ref().map(|s| s.span().start),
            raw.preflight.as_ref().map(|s| s.span().start),
            raw.sweep_resolution_m.as_ref().map(|s| s.span().start),
        ]
        .into_iter()
        .flatten()
        .min()
        .unwrap_or(0);
        Ok(CollisionSettings {
            reaction: raw.reaction.as_ref().map_or_else(Reaction::default, |r| *r.get_ref()),
            meshes: raw
                .meshes
                .as_ref()
                .map_or_else(MeshApproximation::default, |m| *m.get_ref()),
            self_collision: raw.self_collision.as_ref().is_none_or(|s| *s.get_ref()),
            allowed_pairs,
            preflight: raw.preflight.as_ref().map_or_else(Preflight::default, |p| *p.get_ref()),
            sweep_resolution_m,
            tool,
            location: self.location(first),
        })
    }

    fn tool(&self, t: &RawTool, base: &Path) -> Result<Tool, SceneError> {
        let f = |field: &str| format!("collision.tool.{field}");
        let name = match &t.name {
            Some(n) => self.identifier(n, &f("name"))?,
            None => "tool".to_string(),
        };
        let link = self.nonempty_name(&t.link, &f("link"))?;
        let fields = ShapeFields {
            kind: &t.shape,
            size: &t.size,
            radius: &t.radius,
            length: &t.length,
            file: &t.file,
            scale: &t.scale,
        };
        let shape = self.shape(&fields, base, &f)?;
        let position_m = match &t.position {
            Some(p) => self.finite_array(p, &f("position"))?,
            None => [0.0; 3],
        };
        let rpy_deg = match &t.rpy_deg {
            Some(r) => self.finite_array(r, &f("rpy_deg"))?,
            None => [0.0; 3],
        };
        Ok(Tool {
            name,
            link,
            link_location: self.loc(&t.link),
            shape,
            position_m,
            rpy_deg,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{Location, SceneError, Shape, parse};
    use std::path::PathBuf;

    fn fixtures() -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures")
    }

    fn with_collision(table: &str) -> Result<crate::scene::Scene, SceneError> {
        let text = std::fs::read_to_string(fixtures().join("indexing_table.toml")).unwrap();
        parse(&fixtures().join("case.toml"), &format!("{text}\n{table}"))
    }

    #[test]
    fn absent_table_means_no_checks_and_an_empty_one_the_defaults() {
        assert_eq!(with_collision("").unwrap().collision, None);
        let c = with_collision("[collision]\n").unwrap().collision.unwrap();
        assert_eq!(
            c,
            CollisionSettings {
                location: c.location,
                ..CollisionSettings::default()
            }
        );
        assert_eq!(c.reaction, Reaction::Report);
        assert_eq!(c.preflight, Preflight::Report);
        assert_eq!(c.meshes, MeshApproximation::ConvexHull);
        assert!(c.self_collision);
        assert_eq!(c.sweep_resolution_m, 0.001);
        // Its place is the header line.
        let lines = std::fs::read_to_string(fixtures().join("indexing_table.toml"))
            .unwrap()
            .lines()
            .count();
        assert_eq!(
            c.location,
            Location {
                line: lines + 2,
                column: 1
            }
        );
    }

    #[test]
    fn every_field_is_read() {
        let c = with_collision(
            "[collision]\nreaction = \"stop\"\nmeshes = \"convex_decomposition\"\nself_collision = false\n\
             allowed_pairs = [[\"platter\", \"guard\"]]\npreflight = \"reject\"\nsweep_resolution_m = 0.002\n\
             [collision.tool]\nname = \"Payload\"\nlink = \"platter\"\nshape = \"box\"\nsize = [0.1, 0.2, 0.3]\n\
             position = [0.1, 0.0, 0.05]\nrpy_deg = [0.0, 0.0, 90.0]\n",
        )
        .unwrap()
        .collision
        .unwrap();
        assert_eq!(c.reaction, Reaction::Stop);
        assert_eq!(c.meshes, MeshApproximation::ConvexDecomposition);
        assert!(!c.self_collision);
        assert_eq!(
            (c.allowed_pairs[0].a.as_str(), c.allowed_pairs[0].b.as_str()),
            ("platter", "guard")
        );
        assert_eq!(c.preflight, Preflight::Reject);
        assert_eq!(c.sweep_resolution_m, 0.002);
        let tool = c.tool.unwrap();
        assert_eq!((tool.name.as_str(), tool.link.as_str()), ("Payload", "platter"));
        assert_eq!(
            tool.shape,
            Shape::Box {
                size_m: [0.1, 0.2, 0.3]
            }
        );
        assert_eq!(tool.position_m, [0.1, 0.0, 0.05]);
        assert_eq!(tool.rpy_deg, [0.0, 0.0, 90.0]);
    }

    #[test]
    fn bad_fields_name_line_column_and_field() {
        let base_lines = std::fs::read_to_string(fixtures().join("indexing_table.toml"))
            .unwrap()
            .lines()
            .count();
        // Unknown enumeration value (serde): points at the value's line.
        let e = with_collision("[collision]\nreaction = \"halt\"\n").unwrap_err();
        assert_eq!(e.location().map(|l| l.line), Some(base_lines + 3), "{e}");
        assert!(e.to_string().contains("halt"), "{e}");
        // Out of range.
        let e = with_collision("[collision]\nsweep_resolution_m = 0.0\n").unwrap_err();
        assert_eq!(e.field(), Some("collision.sweep_resolution_m"), "{e}");
        assert_eq!(
            e.location(),
            Some(Location {
                line: base_lines + 3,
                column: 22
            })
        );
        // A field of another shape.
        let e = with_collision(
            "[collision.tool]\nlink = \"platter\"\nshape = \"sphere\"\nradius = 0.1\nsize = [1.0, 1.0, 1.0]\n",
        )
        .unwrap_err();
        assert_eq!(e.field(), Some("collision.tool.size"), "{e}");
        // A missing shape field.
        let e =
            with_collision("[collision.tool]\nlink = \"platter\"\nshape = \"cylinder\"\nradius = 0.1\n").unwrap_err();
        assert_eq!(e.field(), Some("collision.tool.shape"), "{e}");
        // An empty pair member.
        let e = with_collision("[collision]\nallowed_pairs = [[\"platter\", \"\"]]\n").unwrap_err();
        assert_eq!(e.field(), Some("collision.allowed_pairs[0]"), "{e}");
        // Unknown field.
        let e = with_collision("[collision]\nreacton = \"stop\"\n").unwrap_err();
        assert!(e.to_string().contains("reacton"), "{e}");
    }
}
