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

/// A one-joint arm whose 4 kg forearm hangs 0.3 m off a horizontal joint,
/// with `collision` inside the forearm's `<link>`, and a scene on it (a
/// servo drive holding it against gravity) with `axis` and `drive` added
/// to the axis' table; both written under `target/<group>/<name>/`.
#[allow(dead_code)]
pub fn one_joint_arm(group: &str, name: &str, collision: &str, axis: &str, drive: &str) -> PathBuf {
    let dir = fresh_dir(group, name);
    std::fs::write(
        dir.join("arm.urdf"),
        format!(
            r#"<robot name="arm">
  <link name="base"/>
  <link name="forearm">
    <inertial><origin xyz="0.3 0 0"/><mass value="4"/>
      <inertia ixx="0.01" iyy="0.05" izz="0.05" ixy="0" ixz="0" iyz="0"/></inertial>
    {collision}
  </link>
  <joint name="j1" type="revolute">
    <parent link="base"/><child link="forearm"/><origin xyz="0 0 1"/><axis xyz="0 1 0"/>
    <limit lower="-3" upper="3" effort="200" velocity="5"/>
  </joint>
</robot>
"#
        ),
    )
    .expect("write URDF");
    let path = dir.join("arm.toml");
    std::fs::write(
        &path,
        format!(
            "name = \"arm\"\nduration_s = 0.5\ncoarse_update_ms = 4.0\nphysics_step_ms = 1.0\n\
             [robot]\nurdf = \"arm.urdf\"\n\
             [[axes]]\nname = \"J1\"\njoint = \"j1\"\nkind = \"rotary\"\nunits = \"deg\"\n\
             max_velocity = 180.0\nmax_acceleration = 1800.0\nmax_deceleration = 1800.0\nmax_jerk = 18000.0\n\
             in_position_window = 0.1\n{axis}\ndrive = {{ {drive} }}\n"
        ),
    )
    .expect("write scene");
    path
}
