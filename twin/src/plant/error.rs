//! Why the plant of a scene cannot be built.

use super::collision::CollisionModelError;
use super::physics::PhysicsError;
use super::stl::StlError;
use super::urdf::UrdfError;
use crate::source::Diagnostic;
use planner::task::TaskError;
use std::path::PathBuf;
use thiserror::Error;

/// Why the plant of a scene cannot be built. Each variant names the scene
/// file and the place.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum PlantError {
    /// The robot's URDF (or a mesh it references) cannot be loaded.
    #[error("{scene}: robot.urdf: {source}")]
    Urdf {
        /// Scene file.
        scene: PathBuf,
        /// What failed (boxed: URDF errors are large).
        #[source]
        source: Box<UrdfError>,
    },
    /// An axis is mapped to a joint the URDF does not have (or cannot drive).
    #[error("{scene}:{line}:{column}: axes[{index}].joint: {message}")]
    Joint {
        /// Scene file.
        scene: PathBuf,
        /// Index of the axis in `[[axes]]`.
        index: usize,
        /// Line of the field.
        line: usize,
        /// Column of the field.
        column: usize,
        /// What is wrong.
        message: String,
    },
    /// The physics world cannot be built.
    #[error("{scene}: robot: {source}")]
    Physics {
        /// Scene file.
        scene: PathBuf,
        /// What failed.
        #[source]
        source: PhysicsError,
    },
    /// The planner refuses an axis.
    #[error("{scene}: {source}")]
    Planner {
        /// Scene file.
        scene: PathBuf,
        /// What failed.
        #[source]
        source: TaskError,
    },
    /// An obstacle's mesh file cannot be loaded.
    #[error("{scene}:{line}:{column}: obstacles[{index}].file: obstacle '{obstacle}': {source}")]
    ObstacleMesh {
        /// Scene file.
        scene: PathBuf,
        /// Index of the obstacle in `[[obstacles]]`.
        index: usize,
        /// Line of the obstacle.
        line: usize,
        /// Column of the obstacle.
        column: usize,
        /// Obstacle name.
        obstacle: String,
        /// Why the STL file failed (names the file).
        #[source]
        source: StlError,
    },
    /// A transform's target robot (URDF) does not have the kinematics of its
    /// `geometry` table.
    #[error("{scene}:{line}:{column}: tags.geometry: {message}")]
    Kinematics {
        /// Scene file.
        scene: PathBuf,
        /// Line of the `geometry` table.
        line: usize,
        /// Column of the `geometry` table.
        column: usize,
        /// What disagrees, and by how much.
        message: String,
    },
    /// A coordinate system's `tool_link` is not a link of the URDF.
    #[error("{scene}:{line}:{column}: tags[{index}].coordinate_system.tool_link: {message}")]
    ToolLink {
        /// Scene file.
        scene: PathBuf,
        /// Index of the tag in `[[tags]]`.
        index: usize,
        /// Line of the `coordinate_system` table.
        line: usize,
        /// Column of the table.
        column: usize,
        /// What is wrong.
        message: String,
    },
    /// The `[collision]` table names something the robot or scene lacks, or
    /// a collision shape cannot be built.
    #[error("{scene}:{line}:{column}: {source}")]
    Collision {
        /// Scene file.
        scene: PathBuf,
        /// Line of the field (or of the `[collision]` table).
        line: usize,
        /// Column of the field.
        column: usize,
        /// What is wrong.
        #[source]
        source: CollisionModelError,
    },
    /// A cell device (a sensor, a part type) names a link the URDF lacks,
    /// or a shape of it cannot be built.
    #[error("{scene}:{line}:{column}: {field}: {message}")]
    Cell {
        /// Scene file.
        scene: PathBuf,
        /// Line of the field.
        line: usize,
        /// Column of the field.
        column: usize,
        /// The field (`sensors[2].link`).
        field: String,
        /// What is wrong.
        message: String,
    },
}

impl PlantError {
    /// The error as a diagnostic: where it has a place in the scene file,
    /// the rendering shows that line with a caret under the value. The
    /// first line is the error's own text.
    #[must_use]
    pub fn diagnostic(&self) -> Diagnostic {
        // The error and its causes (a mesh's own error under the URDF's).
        let text = crate::source::diag::with_causes(self);
        let place = match self {
            PlantError::Joint {
                scene, line, column, ..
            }
            | PlantError::ObstacleMesh {
                scene, line, column, ..
            }
            | PlantError::Kinematics {
                scene, line, column, ..
            }
            | PlantError::ToolLink {
                scene, line, column, ..
            }
            | PlantError::Collision {
                scene, line, column, ..
            }
            | PlantError::Cell {
                scene, line, column, ..
            } => Some((scene, *line, *column)),
            PlantError::Urdf { .. } | PlantError::Physics { .. } | PlantError::Planner { .. } => None,
        };
        match place {
            Some((scene, line, column)) => {
                let prefix = format!("{}:{line}:{column}: ", scene.display());
                let message = text.strip_prefix(&prefix).unwrap_or(&text).to_owned();
                Diagnostic::error(message)
                    .at_place(scene.clone(), line, column)
                    .labelled_from_file()
            }
            None => Diagnostic::error(text),
        }
    }
}
