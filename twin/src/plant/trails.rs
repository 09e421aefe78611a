//! Tool-centre trails: the world positions of the `tool_link` of each
//! coordinate system the program uses, one point every 0.5 mm of travel.

use super::error::PlantError;
use super::urdf::RobotModel;
use crate::scene::Scene;
use planner::task::MotionTask;

/// The tool-centre trail of one coordinate system.
#[derive(Debug, Clone)]
pub struct ToolTrail {
    /// Coordinate-system tag name.
    pub system: String,
    /// The URDF link whose origin is the tool centre (model link index).
    pub link: usize,
    /// Its world positions so far (m), one every 0.5 mm of travel.
    pub points_in_world: Vec<[f64; 3]>,
}

/// Minimum travel between two trail points, m.
const TRAIL_STEP_M: f64 = 0.0005;

/// Binds the `tool_link` of every coordinate system the program uses, in
/// the order the program first uses the systems.
///
/// # Errors
/// [`PlantError::ToolLink`] naming the scene line when the URDF has no such link.
pub(crate) fn tool_trails(scene: &Scene, model: &RobotModel, task: &MotionTask) -> Result<Vec<ToolTrail>, PlantError> {
    let mut trails = Vec::new();
    for h in task.coord_handles() {
        let name = &task.coord_config(h).name;
        let Some(settings) = scene.tag(name).and_then(|t| t.coordinate_system.as_ref()) else {
            continue;
        };
        let Some(link_name) = &settings.tool_link else { continue };
        let Some(link) = model.links.iter().position(|l| &l.name == link_name) else {
            let mut names: Vec<&str> = model.links.iter().map(|l| l.name.as_str()).collect();
            names.sort_unstable();
            return Err(PlantError::ToolLink {
                scene: scene.path.clone(),
                index: scene
                    .tags
                    .iter()
                    .position(|t| t.name.eq_ignore_ascii_case(name))
                    .unwrap_or_default(),
                line: settings.location.line,
                column: settings.location.column,
                message: format!(
                    "coordinate system '{name}': tool_link '{link_name}' is not a link of {} (links: {})",
                    scene.robot.urdf.display(),
                    names.join(", ")
                ),
            });
        };
        trails.push(ToolTrail {
            system: name.clone(),
            link,
            points_in_world: Vec::new(),
        });
    }
    Ok(trails)
}

/// Appends the tool centres' world positions (`links`: every link's world
/// pose, translation first) to their trails.
pub(crate) fn record(trails: &mut [ToolTrail], links: &[([f64; 3], [f64; 4])]) {
    for trail in trails {
        let p = links[trail.link].0;
        let far = trail.points_in_world.last().is_none_or(|q| {
            let d = [p[0] - q[0], p[1] - q[1], p[2] - q[2]];
            (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt() >= TRAIL_STEP_M
        });
        if far {
            trail.points_in_world.push(p);
        }
    }
}
