use super::*;

/// A renderer, or `None` (with a skip line) when this machine has no
/// Vulkan adapter. In CI or with `TWIN_REQUIRE_GPU=1` a missing adapter fails.
fn renderer_or_skip(test: &str) -> Option<Renderer> {
    match Renderer::new() {
        Ok(renderer) => Some(renderer),
        Err(RenderError::NoAdapter) => {
            let required =
                std::env::var_os("CI").is_some() || std::env::var("TWIN_REQUIRE_GPU").is_ok_and(|v| v == "1");
            assert!(
                !required,
                "{test}: {NO_ADAPTER_HINT} (CI or TWIN_REQUIRE_GPU=1 requires one)"
            );
            eprintln!("SKIPPED {test}: {NO_ADAPTER_HINT}");
            None
        }
        Err(other) => panic!("{test}: renderer failed to start: {other}"),
    }
}

fn translation(x: f32, y: f32, z: f32) -> [[f32; 4]; 4] {
    [
        [1.0, 0.0, 0.0, 0.0],
        [0.0, 1.0, 0.0, 0.0],
        [0.0, 0.0, 1.0, 0.0],
        [x, y, z, 1.0],
    ]
}

const BOX_CENTRE: [f32; 3] = [0.0, 0.0, 0.3];
const BOX_HALF: f32 = 0.2;
const CYLINDER_CENTRE: [f32; 3] = [0.75, 0.45, 0.25];
const SPHERE_CENTRE: [f32; 3] = [-0.65, -0.6, 0.3];
const RED: [f32; 4] = [0.85, 0.18, 0.12, 1.0];
const BLUE: [f32; 4] = [0.15, 0.35, 0.85, 1.0];
const GREEN: [f32; 4] = [0.2, 0.75, 0.25, 1.0];
const MAGENTA: [f32; 4] = [0.9, 0.1, 0.9, 1.0];

struct Scene {
    camera: Camera,
    items: Vec<DrawItem>,
    lines: Vec<LineStrip>,
    /// A small magenta sphere right behind the box as seen from the camera.
    hidden_centre: [f32; 3],
    hidden: DrawItem,
}

fn scene(renderer: &mut Renderer) -> Scene {
    let camera = Camera {
        eye_in_world: [3.0, -3.0, 1.6],
        target_in_world: [0.0, 0.0, 0.3],
        width_px: 320,
        height_px: 240,
        ..Camera::default()
    };
    let cuboid = renderer.upload_mesh(&TriMesh::cuboid([2.0 * BOX_HALF; 3]));
    let cylinder = renderer.upload_mesh(&TriMesh::cylinder(0.15, 0.5, 48));
    let sphere = renderer.upload_mesh(&TriMesh::sphere(0.2, 24, 48));
    let small = renderer.upload_mesh(&TriMesh::sphere(0.06, 12, 24));
    let item = |mesh, [x, y, z]: [f32; 3], color_rgba| DrawItem {
        mesh,
        world_from_mesh: translation(x, y, z),
        color_rgba,
        tint_rgba: None,
    };
    let eye = camera.eye_in_world;
    let away = (glam::Vec3::from(BOX_CENTRE) - glam::Vec3::from(eye))
        .try_normalize()
        .expect("eye is not on the box");
    let hidden_centre: [f32; 3] = std::array::from_fn(|k| BOX_CENTRE[k] + 0.45 * away[k]);
    let trail = LineStrip {
        points_in_world: (0..=40)
            .map(|i| {
                let a = i as f32 / 40.0 * std::f32::consts::PI;
                [0.9 * a.cos(), -0.9 * a.sin(), 0.05]
            })
            .collect(),
        color_rgba: MAGENTA,
    };
    Scene {
        camera,
        items: vec![
            item(cuboid, BOX_CENTRE, RED),
            item(cylinder, CYLINDER_CENTRE, BLUE),
            item(sphere, SPHERE_CENTRE, GREEN),
        ],
        lines: vec![trail],
        hidden_centre,
        hidden: item(small, hidden_centre, MAGENTA),
    }
}

fn pixel_at(img: &image::RgbaImage, camera: &Camera, point: [f32; 3]) -> [u8; 4] {
    let [x, y] = camera.project_to_pixel(point).expect("point in front of the camera");
    assert!(
        x >= 0.0 && y >= 0.0 && x < img.width() as f32 && y < img.height() as f32,
        "{point:?} off screen"
    );
    img.get_pixel(x as u32, y as u32).0
}

fn luma(p: [u8; 4]) -> f32 {
    0.2126 * f32::from(p[0]) + 0.7152 * f32::from(p[1]) + 0.0722 * f32::from(p[2])
}

fn dominant(p: [u8; 4], channel: usize) -> bool {
    (0..3)
        .filter(|&k| k != channel)
        .all(|k| i32::from(p[channel]) > i32::from(p[k]) + 40)
}

fn save(img: &image::RgbaImage, name: &str) {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../target/render-test");
    std::fs::create_dir_all(&dir).expect("create target/render-test");
    img.save_with_format(dir.join(name), image::ImageFormat::Png)
        .expect("save png");
}

use std::path::Path;

#[test]
fn scene_shows_shapes_grid_lighting_and_background() {
    let Some(mut renderer) = renderer_or_skip("scene_shows_shapes_grid_lighting_and_background") else {
        return;
    };
    let s = scene(&mut renderer);
    let img = renderer.render(&s.camera, &s.items, &s.lines).expect("render");
    save(&img, "scene.png");
    assert_eq!(img.dimensions(), (320, 240));

    // Background in the top corners (above the horizon).
    for x in [0, img.width() - 1] {
        let p = img.get_pixel(x, 0).0;
        for k in 0..4 {
            assert!(p[k].abs_diff(BACKGROUND_RGBA8[k]) <= 1, "corner {x}: {p:?}");
        }
    }
    // Each object's colour at its projected centre.
    assert!(dominant(pixel_at(&img, &s.camera, BOX_CENTRE), 0), "box is red");
    assert!(
        dominant(pixel_at(&img, &s.camera, CYLINDER_CENTRE), 2),
        "cylinder is blue"
    );
    assert!(dominant(pixel_at(&img, &s.camera, SPHERE_CENTRE), 1), "sphere is green");

    // Faces turned towards the key light are brighter than those turned away.
    let light = s.camera.key_light_dir_in_world().expect("valid camera");
    let mut faces: Vec<(f32, f32)> = [[0.0, 0.0, 1.0], [0.0, -1.0, 0.0], [1.0, 0.0, 0.0]]
        .iter()
        .map(|n: &[f32; 3]| {
            let face_centre: [f32; 3] = std::array::from_fn(|k| BOX_CENTRE[k] + 0.9 * BOX_HALF * n[k]);
            (
                glam::Vec3::from(*n).dot(glam::Vec3::from(light)),
                luma(pixel_at(&img, &s.camera, face_centre)),
            )
        })
        .collect();
    faces.sort_by(|a, b| a.0.total_cmp(&b.0));
    assert!(
        faces[0].0 < faces[2].0 - 0.3,
        "test needs faces lit differently: {faces:?}"
    );
    assert!(
        faces[0].1 + 20.0 < faces[1].1 && faces[1].1 + 10.0 < faces[2].1,
        "brightness follows the light: {faces:?}"
    );

    // The ground grid: the red X axis and green Y axis on z = 0, and grey
    // lines darkening the ground near the camera.
    let near = |point: [f32; 3], test: &dyn Fn([u8; 4]) -> bool| {
        let [x, y] = s.camera.project_to_pixel(point).expect("in front");
        (-2..=2).any(|dy: i32| {
            (-2..=2).any(|dx: i32| {
                let (px, py) = (x as i32 + dx, y as i32 + dy);
                px >= 0 && py >= 0 && test(img.get_pixel(px as u32, py as u32).0)
            })
        })
    };
    assert!(
        near([1.6, 0.0, 0.0], &|p| i32::from(p[0]) > i32::from(p[1]) + 30),
        "X axis is red"
    );
    assert!(
        near([0.0, -1.6, 0.0], &|p| i32::from(p[1]) > i32::from(p[0]) + 15),
        "Y axis is green"
    );
    assert!(
        near([1.0, -1.0, 0.0], &|p| luma(p) < luma(BACKGROUND_RGBA8) - 30.0),
        "major lines darken"
    );
    assert!(
        near([1.3, -1.3, 0.0], &|p| luma(p) < luma(BACKGROUND_RGBA8) - 12.0),
        "minor lines darken"
    );
    // The trail (magenta, at z = 0.05 in front of the box).
    assert!(
        near([0.0, -0.9, 0.05], &|p| i32::from(p[0]) > i32::from(p[1]) + 40
            && i32::from(p[2]) > i32::from(p[1]) + 40),
        "trail drawn"
    );
}

#[test]
fn renders_are_byte_identical_and_survive_size_changes() {
    let Some(mut renderer) = renderer_or_skip("renders_are_byte_identical_and_survive_size_changes") else {
        return;
    };
    let s = scene(&mut renderer);
    let first = renderer.render(&s.camera, &s.items, &s.lines).expect("render");
    let second = renderer.render(&s.camera, &s.items, &s.lines).expect("render");
    assert!(first == second, "two renders differ");
    let small = Camera {
        width_px: 97,
        height_px: 61,
        ..s.camera
    };
    let odd = renderer.render(&small, &s.items, &s.lines).expect("odd size");
    assert_eq!(odd.dimensions(), (97, 61));
    assert!(
        dominant(pixel_at(&odd, &small, BOX_CENTRE), 0),
        "box is red at any size"
    );
    let third = renderer.render(&s.camera, &s.items, &s.lines).expect("render");
    assert!(first == third, "render after a size change differs");
    // A second renderer on the same machine gives the same bytes.
    let mut other = Renderer::new().expect("second renderer");
    let s2 = scene(&mut other);
    assert!(other.render(&s2.camera, &s2.items, &s2.lines).expect("render") == first);
}

#[test]
fn depth_test_hides_objects_behind_others_in_any_draw_order() {
    let Some(mut renderer) = renderer_or_skip("depth_test_hides_objects_behind_others_in_any_draw_order") else {
        return;
    };
    let s = scene(&mut renderer);
    let box_item = s.items[0];
    let alone = renderer.render(&s.camera, &[s.hidden], &[]).expect("render");
    assert!(
        dominant(pixel_at(&alone, &s.camera, s.hidden_centre), 0) || {
            let p = pixel_at(&alone, &s.camera, s.hidden_centre);
            p[0] > p[1] + 40 && p[2] > p[1] + 40
        },
        "the small sphere is visible on its own"
    );
    for order in [[box_item, s.hidden], [s.hidden, box_item]] {
        let img = renderer.render(&s.camera, &order, &[]).expect("render");
        let p = pixel_at(&img, &s.camera, s.hidden_centre);
        assert!(dominant(p, 0) && p[2] < 100, "box hides the sphere: {p:?}");
    }
}

#[test]
fn tint_and_mirrored_transforms_render_sensibly() {
    let Some(mut renderer) = renderer_or_skip("tint_and_mirrored_transforms_render_sensibly") else {
        return;
    };
    let s = scene(&mut renderer);
    let mut tinted = s.items[1];
    tinted.tint_rgba = Some([1.0, 0.0, 0.0, 1.0]);
    let img = renderer.render(&s.camera, &[tinted], &[]).expect("render");
    assert!(
        dominant(pixel_at(&img, &s.camera, CYLINDER_CENTRE), 0),
        "fully tinted cylinder is red"
    );

    // Mirroring the box in Y must not darken its lit faces.
    let plain = renderer.render(&s.camera, &s.items[..1], &[]).expect("render");
    let mut mirrored = s.items[0];
    mirrored.world_from_mesh[1][1] = -1.0;
    let flipped = renderer.render(&s.camera, &[mirrored], &[]).expect("render");
    let top: [f32; 3] = [BOX_CENTRE[0], BOX_CENTRE[1], BOX_CENTRE[2] + 0.9 * BOX_HALF];
    let (a, b) = (pixel_at(&plain, &s.camera, top), pixel_at(&flipped, &s.camera, top));
    assert!((luma(a) - luma(b)).abs() < 3.0, "mirrored top {b:?} vs {a:?}");
}

#[test]
fn bad_input_is_an_error_not_a_panic() {
    let Some(mut renderer) = renderer_or_skip("bad_input_is_an_error_not_a_panic") else {
        return;
    };
    let s = scene(&mut renderer);
    let zero = Camera {
        width_px: 0,
        ..s.camera
    };
    assert!(matches!(
        renderer.render(&zero, &s.items, &[]),
        Err(RenderError::EmptyImage { width_px: 0, .. })
    ));
    let huge = Camera {
        width_px: u32::MAX / 2,
        ..s.camera
    };
    assert!(matches!(
        renderer.render(&huge, &s.items, &[]),
        Err(RenderError::ImageTooLarge { .. })
    ));
    let blind = Camera {
        fov_y_deg: 0.0,
        ..s.camera
    };
    assert!(matches!(
        renderer.render(&blind, &[], &[]),
        Err(RenderError::FieldOfView { .. })
    ));
    let on_target = Camera {
        eye_in_world: s.camera.target_in_world,
        ..s.camera
    };
    assert!(matches!(
        renderer.render(&on_target, &[], &[]),
        Err(RenderError::Camera {
            problem: CameraProblem::EyeOnTarget
        })
    ));
    let top_down = Camera {
        eye_in_world: [0.0, 0.0, 5.0],
        target_in_world: [0.0, 0.0, 0.0],
        ..s.camera
    };
    assert!(matches!(
        renderer.render(&top_down, &[], &[]),
        Err(RenderError::Camera {
            problem: CameraProblem::UpAlongView
        })
    ));

    let mut broken = TriMesh::cuboid([1.0; 3]);
    broken.indices.push(999);
    broken.indices.extend_from_slice(&[0, 1]);
    let bad = renderer.upload_mesh(&broken);
    let mut bad_item = s.items[0];
    bad_item.mesh = bad;
    assert!(matches!(
        renderer.render(&s.camera, &[s.items[1], bad_item], &[]),
        Err(RenderError::InvalidMesh {
            item: 1,
            problem: MeshProblem::IndexOutOfRange { index: 999, .. },
            ..
        })
    ));
    let mut unknown = s.items[0];
    unknown.mesh = MeshId(9999);
    assert!(matches!(
        renderer.render(&s.camera, &[unknown], &[]),
        Err(RenderError::UnknownMesh { item: 0, mesh: 9999 })
    ));
    let mut nan = s.items[0];
    nan.world_from_mesh[3][0] = f32::NAN;
    assert!(matches!(
        renderer.render(&s.camera, &[nan], &[]),
        Err(RenderError::NonFiniteItem { item: 0 })
    ));
    let bad_line = LineStrip {
        points_in_world: vec![[0.0; 3], [f32::INFINITY, 0.0, 0.0]],
        color_rgba: MAGENTA,
    };
    assert!(matches!(
        renderer.render(&s.camera, &[], &[bad_line]),
        Err(RenderError::NonFiniteLine { strip: 0, point: 1 })
    ));

    // A strip reaching behind the camera renders (that segment is dropped).
    let behind: [f32; 3] = std::array::from_fn(|k| 2.0 * s.camera.eye_in_world[k] - s.camera.target_in_world[k]);
    let through_eye = LineStrip {
        points_in_world: vec![[0.0; 3], [0.5, 0.0, 0.0], behind],
        color_rgba: MAGENTA,
    };
    renderer
        .render(&s.camera, &[], &[through_eye])
        .expect("strip through the eye");

    // Empty meshes and short strips draw nothing, and the renderer still works.
    let empty = renderer.upload_mesh(&TriMesh::default());
    let mut empty_item = s.items[0];
    empty_item.mesh = empty;
    let short = LineStrip {
        points_in_world: vec![[0.0; 3]],
        color_rgba: MAGENTA,
    };
    let img = renderer
        .render(&s.camera, &[empty_item], &[short])
        .expect("render after errors");
    assert_eq!(img.get_pixel(0, 0).0, BACKGROUND_RGBA8);
}

#[test]
fn frame_time_640x480() {
    let Some(mut renderer) = renderer_or_skip("frame_time_640x480") else {
        return;
    };
    let s = scene(&mut renderer);
    let camera = Camera {
        width_px: 640,
        height_px: 480,
        ..s.camera
    };
    save(
        &renderer.render(&camera, &s.items, &s.lines).expect("warm-up"),
        "scene-640x480.png",
    );
    let frames = 10;
    let start = std::time::Instant::now();
    for _ in 0..frames {
        renderer.render(&camera, &s.items, &s.lines).expect("render");
    }
    let per_frame = start.elapsed() / frames;
    eprintln!(
        "640x480 frame on {} ({:?}, {}x MSAA): {per_frame:?}",
        renderer.adapter_info().name,
        renderer.adapter_info().device_type,
        renderer.sample_count()
    );
}
