//! What a run's recording logs once, as static data, before the first
//! update: the robot the way Rerun's URDF importer lays it out, the
//! world-fixed meshes, the series' names and colours, the routines' text
//! and the scene's cameras.

use super::super::{FrameTransform, Recorder, RecordingError, TF_STATIC_ENTITY, visual_entity_path};
use super::paths::entity_part;
use crate::plant::mesh::TriMesh;
use crate::run::Twin;

/// A series' static style: its path, its lines' names and colours.
pub(super) type Style = (String, Vec<String>, Vec<[f32; 4]>);

/// A link's visual: its path, its link's frame, mesh, colour and pose in
/// the link (translation, `xyzw` rotation).
type LinkVisual = (String, String, TriMesh, [f32; 4], ([f64; 3], [f64; 4]));

/// A world-fixed mesh: path, mesh, colour, world-from-mesh pose.
type WorldMesh = (String, TriMesh, [f32; 4], ([f32; 3], [f32; 4], [f32; 3]));

/// A camera: path, world-from-camera pose (+X right, +Y down, +Z ahead),
/// vertical field of view in radians, image size in pixels.
type CameraView = (String, ([f64; 3], [f64; 4]), f64, [u32; 2]);

/// The static part of a run's recording (module doc).
pub(in crate::output::recording) struct Static {
    /// The robot's root entity and its root link's frame.
    robot: (String, String),
    visuals: Vec<LinkVisual>,
    world: Vec<WorldMesh>,
    /// The joints' origins between their links' frames, at `tf_static`.
    joints: Vec<FrameTransform>,
    styles: Vec<Style>,
    /// Per routine: its entity and its text as a Markdown document.
    routines: Vec<(String, String)>,
    cameras: Vec<CameraView>,
}

impl Static {
    /// The static part of `twin`'s recording, with the series' `styles`.
    pub(in crate::output::recording) fn of(twin: &Twin, styles: Vec<Style>) -> Static {
        let plant = twin.plant();
        let model = plant.model();
        let robot = super::super::robot_entity_path(&model.name);
        let mut count = vec![0usize; model.links.len()];
        let mut visuals = Vec::new();
        let mut world = Vec::new();
        for part in plant.visuals() {
            let pose = part.parent_from_mesh;
            let (t, q) = (pose.translation.vector, pose.rotation.coords);
            match part.link {
                Some(i) => {
                    let link = &model.links[i];
                    let k = count[i];
                    count[i] += 1;
                    let name = link.visuals.get(k).and_then(|v| v.name.as_deref());
                    visuals.push((
                        visual_entity_path(&robot, &link.name, name, k),
                        link.name.clone(),
                        part.mesh.clone(),
                        part.color_rgba,
                        ([t.x, t.y, t.z], [q.x, q.y, q.z, q.w]),
                    ));
                }
                None => world.push((
                    format!("{}/{}", part.group, entity_part(&part.name)),
                    part.mesh.clone(),
                    part.color_rgba,
                    (
                        [t.x as f32, t.y as f32, t.z as f32],
                        [q.x as f32, q.y as f32, q.z as f32, q.w as f32],
                        [1.0, 1.0, 1.0],
                    ),
                )),
            }
        }
        let joints = model
            .joints
            .iter()
            .map(|j| {
                let pose = j.parent_from_joint;
                let (t, q) = (pose.translation.vector, pose.rotation.coords);
                (
                    model.links[j.parent.0].name.clone(),
                    model.links[j.child.0].name.clone(),
                    [t.x, t.y, t.z],
                    [q.x, q.y, q.z, q.w],
                )
            })
            .collect();
        Static {
            robot: (robot, model.links[model.root.0].name.clone()),
            visuals,
            world,
            joints,
            styles,
            routines: routines(twin),
            cameras: twin.scene().cameras.iter().filter_map(camera_view).collect(),
        }
    }

    /// Logs it all, at the start of the recording.
    pub(in crate::output::recording) fn log(&self, recorder: &mut Recorder) -> Result<(), RecordingError> {
        recorder.log_frame_static(&self.robot.0, &self.robot.1)?;
        for (path, frame, mesh, rgba, pose) in &self.visuals {
            recorder.log_visual_static(path, frame, mesh, *rgba, *pose)?;
        }
        if !self.joints.is_empty() {
            recorder.send_static_frame_transforms(TF_STATIC_ENTITY, &self.joints)?;
        }
        for (path, mesh, rgba, pose) in &self.world {
            recorder.log_link_mesh_static(path, mesh, *rgba, *pose)?;
        }
        for (path, names, colors) in &self.styles {
            recorder.log_series_styles(path, names, colors)?;
        }
        for (path, markdown) in &self.routines {
            recorder.log_markdown_static(path, markdown)?;
        }
        for (path, pose, fov_y_rad, size_px) in &self.cameras {
            recorder.log_camera_static(path, *pose, *fov_y_rad, *size_px)?;
        }
        Ok(())
    }
}

/// Each routine of each program as a Markdown document at
/// `routines/<program>/<routine>`: its file's path and its text in a code
/// block (fenced with more backticks than any run of them in the text).
fn routines(twin: &Twin) -> Vec<(String, String)> {
    let scene = twin.scene();
    let mut out = Vec::new();
    for program in scene.tasks.iter().flat_map(|t| &t.programs) {
        for routine in std::iter::once(&program.main).chain(&program.routines) {
            let Some(file) = scene.files.iter().find(|f| f.path == routine.path) else {
                continue;
            };
            let longest = file.text.split(|c| c != '`').map(str::len).max().unwrap_or(0);
            let fence = "`".repeat(longest.max(2) + 1);
            let language = match routine.path.extension().and_then(|e| e.to_str()) {
                Some("st") => "pascal",
                _ => "text",
            };
            let markdown = format!(
                "**{}** — `{}`\n\n{fence}{language}\n{}\n{fence}\n",
                routine.name,
                routine.path.display(),
                file.text.trim_end()
            );
            let path = format!("routines/{}/{}", entity_part(&program.name), entity_part(&routine.name));
            if !out.iter().any(|(p, _)| p == &path) {
                out.push((path, markdown));
            }
        }
    }
    out
}

/// A scene camera as a pinhole at `cameras/<name>`: looking from its
/// position at its target with +Z up on screen, as the renderer draws it.
/// `None` for a camera whose view is degenerate (the renderer refuses it).
fn camera_view(camera: &crate::scene::Camera) -> Option<CameraView> {
    use nalgebra::{Matrix3, Rotation3, UnitQuaternion, Vector3};
    let eye = Vector3::from(camera.position_m);
    let ahead = (Vector3::from(camera.target_m) - eye).try_normalize(1e-12)?;
    let right = ahead.cross(&Vector3::z()).try_normalize(1e-12)?;
    let down = ahead.cross(&right);
    let rotation = Rotation3::from_matrix_unchecked(Matrix3::from_columns(&[right, down, ahead]));
    let q = UnitQuaternion::from_rotation_matrix(&rotation).into_inner().coords;
    Some((
        format!("cameras/{}", entity_part(&camera.name)),
        (camera.position_m, [q.x, q.y, q.z, q.w]),
        camera.fov_deg.to_radians(),
        [camera.width, camera.height],
    ))
}
