//! COLLADA (`.dae`) loading into the shared [`TriMesh`], for URDF link
//! `<visual>` and `<collision>` meshes (ROS robot descriptions very often
//! ship COLLADA rather than STL).
//!
//! The document is parsed by the `mesh-loader` crate (openrr, the authors of
//! `urdf-rs`) rather than by XML code of our own; its result is then brought
//! into the URDF convention (metres, `+Z` up) here. What is applied, and by whom:
//! - **Node transforms** (`<matrix>`, `<translate>`, `<rotate>`, `<scale>`, ...)
//!   of the `<node>`s that instance a geometry in a visual scene: applied by
//!   mesh-loader. A geometry instanced several times appears once, with the
//!   transform of its last instance (mesh-loader keeps one instance per
//!   geometry). `<instance_node>` references are not followed.
//! - **`<unit meter="…">`**: mesh-loader folds it into the root of the
//!   visual scene named by `<scene><instance_visual_scene>`, so it reaches
//!   only geometries instanced there; this loader scales every *other*
//!   geometry (not instanced, or a document without a `<scene>`) by the unit
//!   itself, so the whole document ends up in metres.
//! - **`<up_axis>`**: ignored by mesh-loader; applied here after the unit:
//!   `Y_UP` turns `+Y` onto `+Z` (a +90° rotation about X,
//!   `(x, y, z) → (x, −z, y)`), `X_UP` turns `+X` onto `+Z` (a −90° rotation
//!   about Y, `(x, y, z) → (−z, y, x)`), `Z_UP` (the URDF convention) leaves
//!   the mesh as is. A missing `<up_axis>` means `Y_UP`, the COLLADA schema's
//!   default (assimp, behind RViz, reads it the same way).
//! - **URDF `<mesh scale="…">`**: *not* applied here; like the STL loader this
//!   returns the mesh before that scale, which the URDF model keeps beside it
//!   ([`crate::plant::urdf::Geometry::Mesh`]) and the renderer and collision model
//!   apply.
//!
//! Other choices:
//! - All geometries and all their primitives (`<triangles>`, `<polylist>`,
//!   `<polygons>`, triangulated by mesh-loader) are merged into one triangle
//!   mesh in the document's frame. Lines and points contribute nothing.
//! - Normals are flat, from each triangle's counter-clockwise winding (as for
//!   STL); normals stored in the file are not used, `+Z` for a zero-area
//!   triangle.
//! - Materials and textures are not read (a URDF `<material>` colours the
//!   visual).
//! - The file must be UTF-8 (or ASCII) text.
//! - A document mesh-loader cannot read, or one that makes it panic (it
//!   indexes arrays with indices from the file), is [`DaeError::Malformed`];
//!   one without a single triangle is [`DaeError::Empty`].

use std::cell::Cell;
use std::collections::HashSet;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};
use std::sync::Once;

thread_local! {
    /// Set while [`quietly`] runs on this thread.
    static QUIET: Cell<bool> = const { Cell::new(false) };
}

/// Runs `f`, turning a panic into `Err` without the panic's message on
/// stderr: the caller reports it as the file's error. The process' panic
/// hook is wrapped once so that it stays silent for a panic inside
/// `quietly` on the same thread and prints every other panic as before.
fn quietly<T>(f: impl FnOnce() -> T) -> std::thread::Result<T> {
    static WRAP: Once = Once::new();
    WRAP.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if !QUIET.with(Cell::get) {
                previous(info);
            }
        }));
    });
    QUIET.with(|q| q.set(true));
    let result = catch_unwind(AssertUnwindSafe(f));
    QUIET.with(|q| q.set(false));
    result
}

use crate::plant::mesh::TriMesh;
use crate::plant::stl::winding_normal;

/// Why a COLLADA file could not be loaded. Every variant names the file.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum DaeError {
    /// The file could not be read (missing, permissions, ...).
    #[error("cannot read COLLADA file {path}")]
    Read {
        /// The file.
        path: PathBuf,
        /// The I/O failure.
        #[source]
        source: std::io::Error,
    },
    /// The file is not valid UTF-8 XML or not a COLLADA document mesh-loader
    /// can read (the reason says where, when the parser knows).
    #[error("COLLADA file {path} is malformed: {reason}")]
    Malformed {
        /// The file.
        path: PathBuf,
        /// What the XML or COLLADA parser reported.
        reason: String,
    },
    /// A vertex coordinate is NaN or infinite (after unit and up-axis).
    #[error("COLLADA file {path} has a non-finite coordinate in triangle {triangle}")]
    NonFinite {
        /// The file.
        path: PathBuf,
        /// Zero-based index of the offending triangle in the merged mesh.
        triangle: usize,
    },
    /// The document contains no triangles at all.
    #[error("COLLADA file {path} contains no triangles")]
    Empty {
        /// The file.
        path: PathBuf,
    },
}

/// Loads a COLLADA file as one flat-shaded [`TriMesh`] in metres with `+Z`
/// up, before any URDF `scale` (see the module docs for what is applied).
///
/// # Errors
/// [`DaeError::Read`] when the file cannot be read, otherwise whatever
/// [`parse_dae`] reports.
pub fn load_dae(path: &Path) -> Result<TriMesh, DaeError> {
    let bytes = crate::source::read_bounded(path, crate::source::InputKind::Mesh).map_err(|source| DaeError::Read {
        path: path.to_path_buf(),
        source,
    })?;
    parse_dae(&bytes, path)
}

/// The first `count`, `offset` or `stride` attribute (with its line) that
/// sizes more than the file can hold: mesh-loader reserves memory for
/// `count × (largest offset + 1)` indices before reading them, so
/// `count="4294967296"` or `offset="4294967295"` would abort the process.
/// Every element takes at least a byte of the file, and no input has more
/// than [`MAX_INPUT_OFFSET`] companions.
fn count_beyond_the_file(doc: &roxmltree::Document<'_>) -> Option<(String, usize)> {
    let text = doc.input_text();
    doc.descendants().filter(roxmltree::Node::is_element).find_map(|node| {
        ["count", "offset", "stride"].into_iter().find_map(|name| {
            let value = node.attribute(name)?.trim();
            let limit = if name == "count" {
                text.len() as u64
            } else {
                MAX_INPUT_OFFSET
            };
            let fits = value.parse::<u64>().is_ok_and(|n| n <= limit);
            // Non-numbers are mesh-loader's to report.
            (!fits && value.bytes().all(|b| b.is_ascii_digit())).then(|| {
                (
                    format!("{name}=\"{value}\""),
                    doc.text_pos_at(node.range().start).row as usize,
                )
            })
        })
    })
}

/// The largest `offset` or `stride` a COLLADA element may give.
const MAX_INPUT_OFFSET: u64 = 64;

/// Parses COLLADA bytes. `path` is used only to name the file in errors.
///
/// # Errors
/// [`DaeError::Malformed`], [`DaeError::NonFinite`] or [`DaeError::Empty`].
pub fn parse_dae(bytes: &[u8], path: &Path) -> Result<TriMesh, DaeError> {
    let malformed = |reason: String| DaeError::Malformed {
        path: path.to_path_buf(),
        reason,
    };
    let text = std::str::from_utf8(bytes).map_err(|e| malformed(format!("not UTF-8 text ({e})")))?;
    if let Some(line) = crate::plant::xml::too_deep(text) {
        return Err(malformed(format!(
            "elements nested deeper than {} levels at line {line}",
            crate::plant::xml::MAX_XML_DEPTH
        )));
    }
    // One XML parse serves the size check and the <asset> reading.
    let doc = roxmltree::Document::parse(text).map_err(|e| malformed(format!("invalid XML: {e}")))?;
    if let Some((attribute, line)) = count_beyond_the_file(&doc) {
        return Err(malformed(format!(
            "{attribute} at line {line} sizes more than the file can hold ({} bytes)",
            text.len()
        )));
    }
    let asset = Asset::read(&doc).map_err(malformed)?;
    let scene = quietly(|| mesh_loader::collada::from_str(text))
        .map_err(|_| malformed("the COLLADA parser failed on inconsistent indices or sources".to_string()))?
        .map_err(|e| malformed(e.to_string()))?;

    let mut triangles: Vec<[[f32; 3]; 3]> = Vec::new();
    for mesh in &scene.meshes {
        // mesh-loader names each mesh after its geometry's id.
        let unit = if asset.unit_applied_by_loader.contains(&mesh.name) {
            1.0
        } else {
            asset.unit_m
        };
        for face in &mesh.faces {
            let mut corners = [[0.0f32; 3]; 3];
            for (corner, &i) in corners.iter_mut().zip(face) {
                let v = mesh
                    .vertices
                    .get(i as usize)
                    .ok_or_else(|| malformed(format!("geometry {:?} has a face index out of range", mesh.name)))?;
                *corner = asset.up_axis.to_z_up(v.map(|c| c * unit));
            }
            triangles.push(corners);
        }
    }
    if triangles.is_empty() {
        return Err(DaeError::Empty {
            path: path.to_path_buf(),
        });
    }
    if let Some(triangle) = triangles
        .iter()
        .position(|t| t.iter().flatten().any(|c| !c.is_finite()))
    {
        return Err(DaeError::NonFinite {
            path: path.to_path_buf(),
            triangle,
        });
    }
    let mut mesh = TriMesh {
        positions: Vec::with_capacity(triangles.len() * 3),
        normals: Vec::with_capacity(triangles.len() * 3),
        indices: Vec::with_capacity(triangles.len() * 3),
    };
    for t in &triangles {
        let normal = winding_normal(t).unwrap_or([0.0, 0.0, 1.0]);
        for v in t {
            mesh.indices
                .push(u32::try_from(mesh.positions.len()).unwrap_or(u32::MAX));
            mesh.positions.push(*v);
            mesh.normals.push(normal);
        }
    }
    Ok(mesh)
}

/// The COLLADA `<up_axis>`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum UpAxis {
    X,
    Y,
    Z,
}

impl UpAxis {
    /// `v` in a frame with `+Z` up (see the module docs for the rotations).
    fn to_z_up(self, [x, y, z]: [f32; 3]) -> [f32; 3] {
        match self {
            UpAxis::X => [-z, y, x],
            UpAxis::Y => [x, -z, y],
            UpAxis::Z => [x, y, z],
        }
    }
}

/// What this loader needs from the document beyond mesh-loader's meshes.
struct Asset {
    /// `<unit meter>` (1 when absent).
    unit_m: f32,
    up_axis: UpAxis,
    /// Ids of the geometries instanced in the scene's visual scene, which
    /// mesh-loader has already scaled by the unit.
    unit_applied_by_loader: HashSet<String>,
}

impl Asset {
    fn read(doc: &roxmltree::Document<'_>) -> Result<Asset, String> {
        let root = doc.root_element();
        if root.tag_name().name() != "COLLADA" {
            return Err(format!("root element is <{}>, not <COLLADA>", root.tag_name().name()));
        }
        let mut unit_m = 1.0f32;
        let mut up_axis = UpAxis::Y; // the COLLADA schema's default, as assimp reads it
        if let Some(asset) = root.children().find(|n| is(n, "asset")) {
            for child in asset.children().filter(roxmltree::Node::is_element) {
                match child.tag_name().name() {
                    "unit" => {
                        if let Some(meter) = child.attribute("meter") {
                            unit_m = meter
                                .trim()
                                .parse::<f32>()
                                .ok()
                                .filter(|u| u.is_finite() && *u > 0.0)
                                .ok_or_else(|| format!("<unit meter={meter:?}> is not a positive number"))?;
                        }
                    }
                    "up_axis" => {
                        up_axis = match child.text().unwrap_or_default().trim() {
                            "X_UP" => UpAxis::X,
                            "Y_UP" => UpAxis::Y,
                            "Z_UP" => UpAxis::Z,
                            other => return Err(format!("<up_axis> {other:?} is not X_UP, Y_UP or Z_UP")),
                        };
                    }
                    _ => {}
                }
            }
        }
        let scene_id = root
            .children()
            .find(|n| is(n, "scene"))
            .and_then(|s| s.children().find(|n| is(n, "instance_visual_scene")))
            .and_then(|i| i.attribute("url"))
            .and_then(|u| u.strip_prefix('#'));
        let unit_applied_by_loader = scene_id
            .and_then(|id| {
                root.descendants()
                    .find(|n| is(n, "visual_scene") && n.attribute("id") == Some(id))
            })
            .map(|visual_scene| {
                visual_scene
                    .descendants()
                    .filter(|n| is(n, "instance_geometry"))
                    .filter_map(|n| n.attribute("url")?.strip_prefix('#').map(str::to_string))
                    .collect()
            })
            .unwrap_or_default();
        Ok(Asset {
            unit_m,
            up_axis,
            unit_applied_by_loader,
        })
    }
}

/// Whether `node` is the element `name` (any namespace: COLLADA files put
/// everything in the COLLADA schema namespace).
fn is(node: &roxmltree::Node<'_, '_>, name: &str) -> bool {
    node.is_element() && node.tag_name().name() == name
}

/// COLLADA documents for tests (here and in the URDF and collision tests).
#[cfg(test)]
pub(crate) mod test_docs {
    use crate::plant::mesh::TriMesh;
    use std::fmt::Write;

    /// One geometry per `(mesh, translation)`, each instanced in the visual
    /// scene by a node with that `<translate>` when `instanced`, and `asset`
    /// (e.g. `<unit meter="0.001"/><up_axis>Y_UP</up_axis>`) in `<asset>`.
    pub(crate) fn collada(asset: &str, geometries: &[(&TriMesh, [f32; 3])], instanced: bool) -> String {
        let mut doc = format!(
            "<?xml version=\"1.0\" encoding=\"utf-8\"?>\n<COLLADA xmlns=\"http://www.collada.org/2005/11/COLLADASchema\" version=\"1.4.1\">\n<asset>{asset}</asset>\n<library_geometries>\n"
        );
        for (g, (mesh, _)) in geometries.iter().enumerate() {
            let floats: Vec<String> = mesh.positions.iter().flatten().map(f32::to_string).collect();
            let indices: Vec<String> = mesh.indices.iter().map(u32::to_string).collect();
            let _ = writeln!(
                doc,
                "<geometry id=\"g{g}\"><mesh><source id=\"g{g}-pos\"><float_array id=\"g{g}-arr\" count=\"{}\">{}</float_array>\
                 <technique_common><accessor source=\"#g{g}-arr\" count=\"{}\" stride=\"3\"><param name=\"X\" type=\"float\"/>\
                 <param name=\"Y\" type=\"float\"/><param name=\"Z\" type=\"float\"/></accessor></technique_common></source>\
                 <vertices id=\"g{g}-vtx\"><input semantic=\"POSITION\" source=\"#g{g}-pos\"/></vertices>\
                 <triangles count=\"{}\"><input semantic=\"VERTEX\" source=\"#g{g}-vtx\" offset=\"0\"/><p>{}</p></triangles>\
                 </mesh></geometry>",
                floats.len(),
                floats.join(" "),
                mesh.positions.len(),
                mesh.indices.len() / 3,
                indices.join(" ")
            );
        }
        doc.push_str("</library_geometries>\n<library_visual_scenes><visual_scene id=\"scene\">\n");
        if instanced {
            for (g, (_, [x, y, z])) in geometries.iter().enumerate() {
                let _ = writeln!(
                    doc,
                    "<node id=\"n{g}\"><translate>{x} {y} {z}</translate><instance_geometry url=\"#g{g}\"/></node>"
                );
            }
        }
        doc.push_str("</visual_scene></library_visual_scenes>\n<scene><instance_visual_scene url=\"#scene\"/></scene>\n</COLLADA>\n");
        doc
    }
}

#[cfg(test)]
#[allow(clippy::unwrap_used)] // a failed unwrap is a failed test
mod tests {
    use super::test_docs::collada;
    use super::*;

    const P: &str = "part.dae";

    fn bounds(mesh: &TriMesh) -> ([f32; 3], [f32; 3]) {
        let mut lo = [f32::MAX; 3];
        let mut hi = [f32::MIN; 3];
        for p in &mesh.positions {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        (lo, hi)
    }

    fn assert_near(a: [f32; 3], b: [f32; 3]) {
        assert!(a.iter().zip(&b).all(|(x, y)| (x - y).abs() < 1e-6), "{a:?} != {b:?}");
    }

    #[test]
    fn millimetre_cube_is_scaled_to_metres_instanced_or_not() {
        let cube = TriMesh::cuboid([1000.0; 3]);
        let asset = r#"<unit name="millimeter" meter="0.001"/><up_axis>Z_UP</up_axis>"#;
        for instanced in [true, false] {
            let mesh = parse_dae(collada(asset, &[(&cube, [0.0; 3])], instanced).as_bytes(), Path::new(P)).unwrap();
            assert_eq!(mesh.indices.len(), cube.indices.len(), "instanced: {instanced}");
            let (lo, hi) = bounds(&mesh);
            assert_near(lo, [-0.5; 3]);
            assert_near(hi, [0.5; 3]);
            assert!((mesh.signed_volume() - 1.0).abs() < 1e-6, "{}", mesh.signed_volume());
        }
    }

    #[test]
    fn y_up_document_is_turned_z_up_and_missing_up_axis_means_y_up() {
        // 0.1 wide (x), 0.3 tall along the document's up axis (y), 0.2 deep (z).
        let block = TriMesh::cuboid([0.1, 0.3, 0.2]).transformed(&[
            [1.0, 0.0, 0.0, 0.0],
            [0.0, 1.0, 0.0, 0.0],
            [0.0, 0.0, 1.0, 0.0],
            [0.0, 0.15, 0.0, 1.0],
        ]);
        for asset in ["<up_axis>Y_UP</up_axis>", ""] {
            let mesh = parse_dae(collada(asset, &[(&block, [0.0; 3])], true).as_bytes(), Path::new(P)).unwrap();
            let (lo, hi) = bounds(&mesh);
            assert_near(lo, [-0.05, -0.1, 0.0]);
            assert_near(hi, [0.05, 0.1, 0.3]);
            // A rotation keeps the triangles' outward orientation.
            assert!(mesh.signed_volume() > 0.0);
        }
        let z_up = parse_dae(
            collada("<up_axis>Z_UP</up_axis>", &[(&block, [0.0; 3])], true).as_bytes(),
            Path::new(P),
        )
        .unwrap();
        assert_near(bounds(&z_up).1, [0.05, 0.3, 0.1]);
        let x_up = parse_dae(
            collada("<up_axis>X_UP</up_axis>", &[(&block, [0.0; 3])], true).as_bytes(),
            Path::new(P),
        )
        .unwrap();
        // +X (0.05) becomes +Z; -Z (-0.1) becomes +X.
        assert_near(bounds(&x_up).1, [0.1, 0.3, 0.05]);
    }

    #[test]
    fn two_geometries_merge_with_their_node_transforms() {
        let cube = TriMesh::cuboid([0.1; 3]);
        let doc = collada(
            "<up_axis>Z_UP</up_axis>",
            &[(&cube, [0.0; 3]), (&cube, [1.0, 0.0, 0.0])],
            true,
        );
        let mesh = parse_dae(doc.as_bytes(), Path::new(P)).unwrap();
        assert_eq!(mesh.indices.len(), 2 * cube.indices.len());
        let (lo, hi) = bounds(&mesh);
        assert_near(lo, [-0.05; 3]);
        assert_near(hi, [1.05, 0.05, 0.05]);
        assert!((mesh.signed_volume() - 2.0e-3).abs() < 1e-9);
        // Flat normals from the winding: every normal is a unit axis vector.
        assert!(
            mesh.normals
                .iter()
                .all(|n| n.iter().map(|c| c.abs()).sum::<f32>() == 1.0)
        );
    }

    #[test]
    fn malformed_documents_are_errors_naming_the_file() {
        let cube = TriMesh::cuboid([0.1; 3]);
        let good = collada("", &[(&cube, [0.0; 3])], true);
        let bad_index = good.replacen("<p>0 ", "<p>999 ", 1);
        assert_ne!(bad_index, good);
        let cases = [
            good[..good.len() / 2].to_string(),
            "<robot/>".to_string(),
            "<COLLADA/>".to_string(),
            good.replace(
                r#"version="1.4.1">"#,
                r#"version="1.4.1"><asset><unit meter="-1"/></asset>"#,
            ),
            bad_index,
        ];
        for (i, text) in cases.iter().enumerate() {
            match parse_dae(text.as_bytes(), Path::new(P)) {
                Err(e @ DaeError::Malformed { .. }) => {
                    assert!(e.to_string().contains(P), "case {i}: {e}");
                }
                other => panic!("case {i}: unexpected {other:?}"),
            }
        }
        assert!(matches!(
            parse_dae(&[0xff, 0xfe, 0x00], Path::new(P)),
            Err(DaeError::Malformed { .. })
        ));
    }

    #[test]
    fn empty_and_missing_files_are_errors() {
        // A document whose one geometry has vertices but no primitives.
        let cube = collada("", &[(&TriMesh::cuboid([0.1; 3]), [0.0; 3])], true);
        let (start, end) = (cube.find("<triangles").unwrap(), cube.find("</triangles>").unwrap());
        let no_triangles = format!("{}{}", &cube[..start], &cube[end + "</triangles>".len()..]);
        assert!(matches!(
            parse_dae(no_triangles.as_bytes(), Path::new(P)),
            Err(DaeError::Empty { path }) if path == Path::new(P)
        ));
        // mesh-loader requires at least one <geometry> in <library_geometries>.
        assert!(matches!(
            parse_dae(collada("", &[], true).as_bytes(), Path::new(P)),
            Err(DaeError::Malformed { .. })
        ));
        assert!(matches!(
            load_dae(Path::new("/nonexistent/dir/part.dae")),
            Err(DaeError::Read { .. })
        ));
    }

    #[test]
    fn a_collada_file_nested_thousands_deep_is_refused_not_a_stack_overflow() {
        let text = format!(
            "<?xml version=\"1.0\"?>\n<COLLADA>{}{}</COLLADA>",
            "<node>".repeat(20_000),
            "</node>".repeat(20_000)
        );
        match parse_dae(text.as_bytes(), Path::new("deep.dae")) {
            Err(e @ DaeError::Malformed { .. }) => {
                assert!(e.to_string().contains("nested deeper than 256 levels at line 2"), "{e}")
            }
            other => panic!("unexpected {other:?}"),
        }
    }

    #[test]
    fn a_count_beyond_the_file_is_refused_not_an_allocation_abort() {
        // count="4294967296" made mesh-loader reserve 103 GB and abort.
        let doc = collada("", &[(&TriMesh::sphere(0.1, 4, 8), [0.0; 3])], true);
        for (from, to) in [
            ("<triangles count=\"", "<triangles count=\"4294967296"),
            ("offset=\"0\"", "offset=\"4294967295\""),
        ] {
            let at = doc.find(from).expect("in the document");
            let bad = format!("{}{to}{}", &doc[..at], &doc[at + from.len()..]);
            let bad = if from.starts_with("<triangles") {
                // Drop the original count's digits.
                let start = at + to.len();
                let end = start + bad[start..].find('"').expect("quote");
                format!("{}{}", &bad[..start], &bad[end..])
            } else {
                bad
            };
            match parse_dae(bad.as_bytes(), Path::new(P)) {
                Err(e @ DaeError::Malformed { .. }) => {
                    assert!(e.to_string().contains("sizes more than the file can hold"), "{e}")
                }
                other => panic!("unexpected {other:?}"),
            }
        }
    }
}
