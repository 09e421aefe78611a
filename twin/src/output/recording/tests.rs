use std::path::{Path, PathBuf};

use super::sinks::{DEFAULT_CONNECT_ADDR, Sink};
use super::*;

fn test_dir() -> PathBuf {
    // Cargo runs unit tests from the package root; the workspace target dir is one up.
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .join("target")
        .join("recording-test");
    std::fs::create_dir_all(&dir).expect("create target/recording-test");
    dir
}

fn tetrahedron() -> TriMesh {
    TriMesh {
        positions: vec![[0.0, 0.0, 0.0], [0.1, 0.0, 0.0], [0.0, 0.1, 0.0], [0.0, 0.0, 0.1]],
        normals: vec![
            [-0.577, -0.577, -0.577],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ],
        indices: vec![0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3],
    }
}

const IDENTITY_LOCAL: ([f32; 3], [f32; 4], [f32; 3]) = ([0.0; 3], [0.0, 0.0, 0.0, 1.0], [1.0; 3]);

/// Nothing listens on this port: bind a listener to get a free port, then close it.
fn closed_local_port() -> u16 {
    let listener = std::net::TcpListener::bind("127.0.0.1:0").expect("bind a free port");
    listener.local_addr().expect("local addr").port()
}

#[test]
fn records_a_small_sequence_to_an_rrd_file() {
    let path = test_dir().join("test.rrd");
    let _ = std::fs::remove_file(&path);

    let paths = ["robot/base", "robot/base/j1/arm", "robot/base/j1/arm/j2/tool"];
    let mut rec = Recorder::new("twin_recording_test", &[Sink::File(path.clone())]).expect("open recording");
    for link_path in &paths {
        rec.log_link_mesh_static(
            &format!("{link_path}/visual_0"),
            &tetrahedron(),
            [0.8, 0.5, 0.1, 1.0],
            ([0.0, 0.0, 0.05], [0.0, 0.0, 0.0, 1.0], [1.0, 1.0, 2.0]),
        )
        .expect("mesh");
    }
    rec.log_series_styles(
        "plots/j1_position",
        &["j1 position".to_owned()],
        &[[0.2, 0.4, 1.0, 1.0]],
    )
    .expect("series style");
    let mut trail = Vec::new();
    for step in 0..10 {
        let t = f64::from(step) * 0.1;
        rec.set_time_s(t);
        let (s, c) = (t / 2.0).sin_cos();
        rec.log_transform(paths[1], [0.0, 0.0, 0.3], [0.0, 0.0, s, c])
            .expect("transform");
        rec.log_transform(paths[2], [0.4, 0.0, 0.0], [0.0, s, 0.0, c])
            .expect("transform");
        rec.send_scalars_column("plots/j1_position", &[rec.time_ns().expect("time")], &[t], 1, None)
            .expect("scalar");
        trail.push([0.4 * t.cos(), 0.4 * t.sin(), 0.3]);
        rec.log_line_strip("world/tcp_trail", &trail, [1.0, 0.0, 0.0, 1.0])
            .expect("trail");
    }
    rec.log_text("log", TextLevel::Info, "program done").expect("text");
    assert_eq!(rec.time_s(), Some(0.9));
    rec.finish().expect("finish");

    let size = std::fs::metadata(&path).expect("rrd exists").len();
    assert!(size > 0, "{} is empty", path.display());
}

#[test]
fn save_and_connect_together_reach_a_listening_viewer() {
    // A plain TCP listener stands in for a viewer: it accepts the probe.
    // Nothing speaks gRPC, so the flush in `finish` fails, naming the viewer;
    // the file is still written.
    let listener = std::net::TcpListener::bind("127.0.0.1:0").expect("bind");
    let addr = listener.local_addr().expect("addr").to_string();
    let path = test_dir().join("tee.rrd");
    let mut rec = Recorder::new(
        "twin_recording_test",
        &[Sink::File(path.clone()), Sink::Connect(addr.clone())],
    )
    .expect("open recording");
    rec.set_time_s(0.5);
    rec.send_scalars_column("plots/x", &[0], &[1.0], 1, None)
        .expect("scalar");
    drop(listener);
    if let Err(err) = rec.finish() {
        assert!(matches!(err, RecordingError::Flush { .. }), "{err:?}");
    }
    assert!(std::fs::metadata(&path).expect("rrd exists").len() > 0);
}

/// Manual check against a real viewer or server, e.g.
/// `rerun --port 19877 --save /tmp/rx.rrd &` then
/// `TWIN_RERUN_TEST_CONNECT=127.0.0.1:19877 cargo test -p twin -- --ignored streams_to`.
#[test]
#[ignore = "needs a running Rerun viewer at TWIN_RERUN_TEST_CONNECT"]
fn streams_to_a_running_viewer() {
    let addr = std::env::var("TWIN_RERUN_TEST_CONNECT").unwrap_or_else(|_| DEFAULT_CONNECT_ADDR.to_owned());
    let mut rec = Recorder::new("twin_recording_test", &[Sink::Connect(addr)]).expect("connect");
    rec.log_link_mesh_static("robot/base/visual_0", &tetrahedron(), [0.5; 4], IDENTITY_LOCAL)
        .expect("mesh");
    for step in 0..5 {
        rec.set_time_s(f64::from(step) * 0.1);
        rec.send_scalars_column("plots/x", &[rec.time_ns().expect("time")], &[f64::from(step)], 1, None)
            .expect("scalar");
    }
    rec.finish().expect("finish");
}

#[test]
fn connect_with_nothing_listening_errors_without_panicking() {
    let addr = format!("127.0.0.1:{}", closed_local_port());
    let err = Recorder::new("twin_recording_test", &[Sink::Connect(addr.clone())]).expect_err("no viewer");
    match err {
        RecordingError::Connect { addr: named, .. } => assert_eq!(named, addr),
        other => panic!("expected Connect, got {other:?}"),
    }
}

#[test]
fn failed_connect_creates_no_file() {
    let path = test_dir().join("never.rrd");
    let _ = std::fs::remove_file(&path);
    let addr = format!("rerun+http://127.0.0.1:{}/proxy", closed_local_port());
    let result = Recorder::new("twin_recording_test", &[Sink::File(path.clone()), Sink::Connect(addr)]);
    assert!(matches!(result, Err(RecordingError::Connect { .. })));
    assert!(!path.exists());
}

#[test]
fn bad_addresses_and_paths_are_errors() {
    for addr in ["", "no-port", "127.0.0.1:notaport", "ftp://127.0.0.1:9876/x"] {
        let result = Recorder::new("t", &[Sink::Connect(addr.to_owned())]);
        assert!(
            matches!(result, Err(RecordingError::InvalidAddress { .. })),
            "{addr:?}: {result:?}"
        );
    }
    let missing_dir = test_dir().join("no-such-dir").join("x.rrd");
    match Recorder::new("t", &[Sink::File(missing_dir.clone())]) {
        Err(RecordingError::CreateFile { path, .. }) => assert_eq!(path, missing_dir),
        other => panic!("expected CreateFile, got {other:?}"),
    }
    assert!(matches!(Recorder::new("t", &[]), Err(RecordingError::NoSinks)));
    let twice = test_dir().join("twice.rrd");
    assert!(matches!(
        Recorder::new("t", &[Sink::File(twice.clone()), Sink::File(twice)]),
        Err(RecordingError::DuplicateFile { .. })
    ));
}

#[test]
fn invalid_values_are_rejected() {
    let path = test_dir().join("invalid.rrd");
    let mut rec = Recorder::new("t", &[Sink::File(path)]).expect("open");
    rec.set_time_s(f64::NAN);
    assert_eq!(rec.time_s(), None);
    let bad = |r: Result<(), RecordingError>, q: Quantity| {
        assert!(matches!(r, Err(RecordingError::InvalidValue { quantity, .. }) if quantity == q));
    };
    bad(
        rec.log_transform("a", [f64::NAN, 0.0, 0.0], [0.0, 0.0, 0.0, 1.0]),
        Quantity::Translation,
    );
    bad(rec.log_transform("a", [0.0; 3], [0.0; 4]), Quantity::Rotation);
    bad(
        rec.log_line_strip("a", &[[0.0, f64::INFINITY, 0.0]], [1.0; 4]),
        Quantity::Point,
    );
    bad(
        rec.log_link_mesh_static("a", &tetrahedron(), [1.0; 4], ([0.0; 3], [0.0; 4], [1.0; 3])),
        Quantity::Rotation,
    );
    bad(
        rec.log_link_mesh_static(
            "a",
            &tetrahedron(),
            [1.0; 4],
            ([0.0; 3], [0.0, 0.0, 0.0, 1.0], [0.0; 3]),
        ),
        Quantity::Scale,
    );
    rec.finish().expect("finish");
}

#[test]
fn mesh_defects_are_named() {
    let mut mesh = tetrahedron();
    assert_eq!(check_mesh(&mesh), Ok(()));
    mesh.indices.push(0);
    assert_eq!(check_mesh(&mesh), Err(MeshDefect::PartialTriangle { index_count: 13 }));
    mesh.indices.extend([1, 9]);
    assert_eq!(
        check_mesh(&mesh),
        Err(MeshDefect::IndexOutOfRange {
            index: 9,
            vertex_count: 4
        })
    );
    let mut mesh = tetrahedron();
    mesh.normals.pop();
    assert_eq!(
        check_mesh(&mesh),
        Err(MeshDefect::NormalCountMismatch {
            normal_count: 3,
            vertex_count: 4
        })
    );
    let mut mesh = tetrahedron();
    mesh.positions[2][1] = f32::NAN;
    assert_eq!(check_mesh(&mesh), Err(MeshDefect::NonFiniteVertex { vertex: 2 }));
    let mut mesh = tetrahedron();
    mesh.normals.clear();
    assert_eq!(check_mesh(&mesh), Ok(()), "normals are optional");
    let path = test_dir().join("bad-mesh.rrd");
    let mut rec = Recorder::new("t", &[Sink::File(path)]).expect("open");
    mesh.indices.push(0);
    assert!(matches!(
        rec.log_link_mesh_static("m", &mesh, [1.0; 4], IDENTITY_LOCAL),
        Err(RecordingError::InvalidMesh { .. })
    ));
    rec.finish().expect("finish");
}

#[test]
fn visual_paths_follow_rerun_s_urdf_importer() {
    let robot = robot_entity_path("arm 1");
    assert_eq!(robot, "arm\\ 1");
    assert_eq!(
        visual_entity_path(&robot, "base", None, 0),
        "arm\\ 1/visual_geometries/base/visual_0"
    );
    assert_eq!(
        visual_entity_path(&robot, "base", Some("column"), 3),
        "arm\\ 1/visual_geometries/base/column"
    );
    // Escaping keeps one entity-path part per name.
    let path = visual_entity_path(&robot, "a/b", Some("c.d e"), 0);
    let parsed = rerun::EntityPath::from(path.as_str());
    let parts: Vec<String> = parsed.iter().map(|p| p.unescaped_str().to_owned()).collect();
    assert_eq!(parts, ["arm 1", "visual_geometries", "a/b", "c.d e"], "{path}");
}

#[test]
fn frame_transforms_are_checked() {
    let path = test_dir().join("frames.rrd");
    let _ = std::fs::remove_file(&path);
    let mut rec = Recorder::new("twin_recording_test", &[Sink::File(path.clone())]).expect("open recording");
    let row = |t: [f64; 3], q: [f64; 4]| ("base".to_owned(), "arm".to_owned(), t, q);
    rec.send_static_frame_transforms("tf_static", &[row([0.0, 0.0, 0.5], [0.0, 0.0, 0.0, 1.0])])
        .expect("static transforms");
    assert!(matches!(
        rec.send_frame_transform_column("transforms", &[0], &[row([f64::NAN, 0.0, 0.0], [0.0, 0.0, 0.0, 1.0])]),
        Err(RecordingError::InvalidValue {
            quantity: Quantity::Translation,
            ..
        })
    ));
    assert!(matches!(
        rec.send_frame_transform_column("transforms", &[0], &[row([0.0; 3], [0.0; 4])]),
        Err(RecordingError::InvalidValue {
            quantity: Quantity::Rotation,
            ..
        })
    ));
    assert!(matches!(
        rec.send_frame_transform_column("transforms", &[0, 1], &[row([0.0; 3], [0.0, 0.0, 0.0, 1.0])]),
        Err(RecordingError::InvalidValue {
            quantity: Quantity::ColumnLength,
            ..
        })
    ));
    assert!(matches!(
        rec.send_scalars_column("s", &[0, 1], &[1.0, 2.0, 3.0], 2, None),
        Err(RecordingError::InvalidValue {
            quantity: Quantity::ColumnLength,
            ..
        })
    ));
    let labels = ["IP".to_owned(), "PC".to_owned()];
    assert!(matches!(
        rec.send_scalars_column("s", &[0, 1], &[1.0, 2.0, 3.0, 4.0], 2, Some((&labels[..1], 1))),
        Err(RecordingError::InvalidValue {
            quantity: Quantity::ColumnLength,
            ..
        })
    ));
    rec.send_scalars_column("s", &[0, 1], &[1.0, 2.0, 3.0, 4.0], 2, Some((&labels, 1)))
        .expect("two values and a state a row");
    rec.finish().expect("finish");
}

#[test]
fn colors_are_clamped_and_rounded() {
    assert_eq!(rgba32([0.0, 0.5, 1.0, 2.0]).to_array(), [0, 128, 255, 255]);
    assert_eq!(rgba32([f32::NAN, -1.0, 0.2, 1.0]).to_array(), [0, 0, 51, 255]);
}

#[test]
fn quaternions_are_normalised() {
    assert_eq!(unit_quaternion([0.0, 0.0, 0.0, 2.0]), Some([0.0, 0.0, 0.0, 1.0]));
    assert_eq!(unit_quaternion([0.0, 0.0, f64::NAN, 1.0]), None);
}
