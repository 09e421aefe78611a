//! Paths the integration tests share.

use std::path::{Path, PathBuf};

/// The workspace root.
pub fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("workspace root")
        .to_path_buf()
}

/// `target/<group>/<name>` under the workspace root.
pub fn out_path(group: &str, name: &str) -> PathBuf {
    root().join("target").join(group).join(name)
}

/// [`out_path`], emptied and created.
pub fn fresh_dir(group: &str, name: &str) -> PathBuf {
    let dir = out_path(group, name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("create test output dir");
    dir
}

/// A shipped scene's text without its own expectations: the tables from its
/// `# What this run must show` comment on. A test that edits the scene
/// (its program, its duration) checks other things than the expectations
/// of the scene as shipped.
#[allow(dead_code)]
pub fn shipped_scene_text(path: &Path) -> String {
    let mut text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    if let Some(at) = text.find("# What this run must show") {
        text.truncate(at);
    }
    text
}

/// The head of a test scene on the indexing table fixture: 4 ms coarse
/// updates, 2 s, and its rotary `Table` axis on a spring drive. Tests add
/// their axes, tags and tasks after it.
#[allow(dead_code)]
pub fn indexing_table_head() -> String {
    let urdf = root().join("twin/tests/fixtures/robots/indexing_table.urdf");
    format!(
        "duration_s = 2.0\ncoarse_update_ms = 4.0\nphysics_step_ms = 1.0\n\
         [robot]\nurdf = {urdf:?}\n\
         [[axes]]\nname = \"Table\"\njoint = \"platter_joint\"\nkind = \"rotary\"\nunits = \"deg\"\n\
         max_velocity = 720.0\nmax_acceleration = 3600.0\nmax_deceleration = 3600.0\nmax_jerk = 36000.0\n\
         in_position_window = 0.1\nmotor = {{ stiffness = 35530.6, damping = 377.0 }}\n"
    )
}

/// A URDF chain of `joints` revolute joints and `joints + 1` links
/// (`l0` … `lN`, each 1 kg, 0.1 m on from its parent; link `lk` on line
/// 2k + 1).
#[allow(dead_code)]
pub fn chain_urdf(joints: usize) -> String {
    let mut s = String::from("<robot name=\"chain\">\n<link name=\"l0\"/>\n");
    for i in 1..=joints {
        s.push_str(&format!(
            "<link name=\"l{i}\"><inertial><mass value=\"1\"/>\
             <inertia ixx=\"0.01\" iyy=\"0.01\" izz=\"0.01\" ixy=\"0\" ixz=\"0\" iyz=\"0\"/></inertial></link>\n\
             <joint name=\"j{i}\" type=\"revolute\"><parent link=\"l{p}\"/><child link=\"l{i}\"/>\
             <origin xyz=\"0 0 0.1\"/><axis xyz=\"0 0 1\"/>\
             <limit lower=\"-1\" upper=\"1\" effort=\"10\" velocity=\"1\"/></joint>\n",
            p = i - 1
        ));
    }
    s.push_str("</robot>\n");
    s
}

/// A binary STL of `triangles` (each three corners, metres).
#[allow(dead_code)]
pub fn binary_stl(triangles: &[[[f32; 3]; 3]]) -> Vec<u8> {
    let mut b = vec![0u8; 80];
    b.extend((triangles.len() as u32).to_le_bytes());
    for t in triangles {
        b.extend([0u8; 12]);
        for c in t.iter().flatten() {
            b.extend(c.to_le_bytes());
        }
        b.extend([0u8; 2]);
    }
    b
}

/// The four faces of a tetrahedron `size_m` across, wound outwards.
#[allow(dead_code)]
pub fn tetrahedron(size_m: f32) -> Vec<[[f32; 3]; 3]> {
    let [o, x, y, z] = [
        [0.0, 0.0, 0.0],
        [size_m, 0.0, 0.0],
        [0.0, size_m, 0.0],
        [0.0, 0.0, size_m],
    ];
    vec![[o, y, x], [o, x, z], [o, z, y], [x, y, z]]
}
