use std::collections::BTreeMap;

use super::*;

/// A shipped scene's twin, and a recording of it opened with `--save`
/// into `target/test-output/recording-run/<file>` (that path).
fn open(scene: &str, file: &str) -> (Twin, Recording, std::path::PathBuf) {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let dir = root.join("target/test-output/recording-run");
    std::fs::create_dir_all(&dir).expect("dir");
    let scene = root.join(format!("scenes/{scene}.toml"));
    let twin = Twin::new(crate::scene::load(&scene).expect("scene")).expect("twin");
    let path = dir.join(file);
    let targets = RecordingTargets {
        save: Some(path.clone()),
        ..RecordingTargets::default()
    };
    let recording = Recording::new(&twin, &targets).expect("open");
    (twin, recording, path)
}

/// A shipped scene run for `updates` coarse updates with `--save` (see
/// [`open`]); the twin as last logged and the file, finished.
fn record(scene: &str, file: &str, updates: usize) -> (Twin, std::path::PathBuf) {
    let (mut twin, mut recording, path) = open(scene, file);
    recording.log(&twin).expect("log");
    for _ in 0..updates {
        twin.step();
        recording.log(&twin).expect("log");
    }
    let finished = recording.finish(&twin);
    assert!(
        finished.files_complete && finished.failures.is_empty(),
        "{:?}",
        finished.failures
    );
    (twin, path)
}

/// Every chunk of an `.rrd` file with the kind and application id of its
/// store, read back with Rerun's own decoder.
fn chunks_in(path: &std::path::Path) -> Vec<(rerun::StoreKind, String, rerun::log::Chunk)> {
    use rerun::external::re_log_encoding::DecoderApp;
    use rerun::log::{Chunk, LogMsg};

    let file = std::io::BufReader::new(std::fs::File::open(path).expect("rrd"));
    DecoderApp::decode_lazy(file)
        .filter_map(|msg| match msg.expect("decodes") {
            LogMsg::ArrowMsg(store, arrow) => Some((
                store.kind(),
                store.application_id().to_string(),
                Chunk::from_arrow_msg(&arrow).expect("chunk"),
            )),
            _ => None,
        })
        .collect()
}

/// The `(class, display name)` of every view, the timeline of the time
/// panel and the application id of the blueprint in an `.rrd` file.
fn blueprint_in(path: &std::path::Path) -> (Vec<(String, String)>, Vec<String>, Vec<String>) {
    use rerun::external::arrow::array::{Array as _, StringArray};

    let mut views: BTreeMap<String, (String, String)> = BTreeMap::new();
    let (mut timelines, mut applications) = (Vec::new(), Vec::new());
    for (kind, application, chunk) in chunks_in(path) {
        if kind != rerun::StoreKind::Blueprint {
            continue;
        }
        applications.push(application);
        let entity = chunk.entity_path().to_string();
        for column in chunk.components().0.values() {
            let values = column.list_array.values();
            let Some(strings) = values.as_any().downcast_ref::<StringArray>() else {
                continue;
            };
            let strings: Vec<String> = (0..strings.len()).map(|i| strings.value(i).to_owned()).collect();
            let slot = views.entry(entity.clone()).or_default();
            match column.descriptor.component.as_str() {
                "ViewBlueprint:class_identifier" => slot.0 = strings.concat(),
                "ViewBlueprint:display_name" => slot.1 = strings.concat(),
                "TimePanelBlueprint:timeline" => timelines.extend(strings),
                _ => {}
            }
        }
    }
    let views = views.into_values().filter(|(class, _)| !class.is_empty()).collect();
    (views, timelines, applications)
}

#[test]
fn a_recording_opens_with_the_default_layout() {
    let (twin, path) = record("gantry_collision", "gantry_collision.rrd", 5);
    let (views, timelines, applications) = blueprint_in(&path);
    let has = |class: &str, name: &str| views.iter().any(|(c, n)| c == class && n == name);
    assert!(has("3D", "Cell"), "{views:?}");
    // A position and a velocity view for gantry_collision's coordinate system.
    let system = &twin
        .task()
        .coord_config(twin.task().coord_handles().next().expect("a system"))
        .name;
    assert!(has("TimeSeries", &format!("{system} position")), "{views:?}");
    assert!(has("TimeSeries", &format!("{system} velocity")), "{views:?}");
    assert!(views.iter().any(|(c, _)| c == "StateTimeline"), "{views:?}");
    assert!(has("TimeSeries", "Clearance"), "{views:?}");
    assert!(has("TextLog", "Instruction log"), "{views:?}");
    assert!(has("TextLog", "Collision log"), "{views:?}");
    assert_eq!(timelines, [crate::output::recording::SIM_TIME_TIMELINE]);
    assert!(
        !applications.is_empty() && applications.iter().all(|a| a == APPLICATION_ID),
        "{applications:?}"
    );
}

/// heavy_arm's recording: fewer than 100 entities in all (the layout's
/// included), one per instruction holding its bits and codes as named
/// lines and its state lane, and the robot's visuals in its links' named
/// frames.
#[test]
fn heavy_arm_records_an_entity_per_instruction_and_named_frames() {
    let (twin, path) = record("heavy_arm", "heavy_arm_entities.rrd", 40);
    let chunks = chunks_in(&path);
    let entities: std::collections::BTreeSet<String> =
        chunks.iter().map(|(_, _, c)| c.entity_path().to_string()).collect();
    assert!(entities.len() < 100, "{} entities: {entities:?}", entities.len());
    let components = |entity: &str| -> Vec<String> {
        chunks
            .iter()
            .filter(|(_, _, c)| c.entity_path().to_string() == entity)
            .flat_map(|(_, _, c)| {
                c.components()
                    .0
                    .values()
                    .map(|col| col.descriptor.component.to_string())
                    .collect::<Vec<_>>()
            })
            .collect()
    };
    for ins in twin.program().instructions() {
        let entity = format!("/instructions/{}", entity_part(&ins.name));
        let have = components(&entity);
        for component in ["Scalars:scalars", "SeriesLines:names", "StateChange:state"] {
            assert!(have.iter().any(|c| c == component), "{entity}: {have:?}");
        }
    }
    let model = twin.plant().model();
    for link in model.links.iter().filter(|l| !l.visuals.is_empty()) {
        let prefix = format!("/{}/visual_geometries/{}/", model.name, entity_part(&link.name));
        let visual = entities
            .iter()
            .find(|e| e.starts_with(&prefix))
            .unwrap_or_else(|| panic!("no visual under {prefix}: {entities:?}"));
        assert!(
            components(visual).iter().any(|c| c == "CoordinateFrame:frame"),
            "{visual}"
        );
    }
    for entity in ["/tf_static", "/transforms", "/axes/status", "/axes/acceleration"] {
        assert!(entities.contains(entity), "{entity}: {entities:?}");
    }
}

#[test]
fn no_sink_is_a_no_op() {
    let scene = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/indexing_table.toml");
    let twin = Twin::new(crate::scene::load(&scene).expect("scene")).expect("twin");
    let mut recording = Recording::new(&twin, &RecordingTargets::default()).expect("open");
    recording.log(&twin).expect("log");
    let finished = recording.finish(&twin);
    assert!(
        finished.files_complete && finished.failures.is_empty(),
        "{:?}",
        finished.failures
    );
}

#[test]
fn the_tool_trail_is_logged_in_pieces_up_to_the_end() {
    // 150 updates: a piece at update 100, the rest at the end.
    let (twin, path) = record("gantry_arcs", "gantry_arcs_trail.rrd", 150);
    let trail = &twin.plant().tool_trails()[0];
    assert!(trail.points_in_world.len() > 10, "the tool moved");
    let mut pieces = BTreeMap::new();
    for (kind, _, chunk) in chunks_in(&path) {
        let entity = chunk.entity_path().to_string();
        if kind == rerun::StoreKind::Recording && entity.starts_with("/tool_trails/") {
            *pieces.entry(entity).or_insert(0) += chunk.num_rows();
        }
    }
    // gantry_arcs' XY and XYZ systems share their tool link: one trail.
    assert!(twin.plant().tool_trails().iter().all(|t| t.link == trail.link));
    let system = entity_part(&trail.system);
    assert_eq!(
        pieces.keys().cloned().collect::<Vec<_>>(),
        [format!("/tool_trails/{system}/0"), format!("/tool_trails/{system}/1")],
        "{pieces:?}"
    );
    assert!(
        pieces.values().all(|&rows| rows == 1),
        "each piece logged once: {pieces:?}"
    );
}

/// The recording thread hands its batches back emptied, buffers kept, so
/// that the run's thread alone allocates and frees them.
#[test]
fn batches_come_back_emptied_for_reuse() {
    let (mut twin, mut recording, _) = open("indexing_table", "given_back.rrd");
    for _ in 0..BATCH_UPDATES {
        twin.step();
        recording.log(&twin).expect("log");
    }
    let feed = recording.inner.as_ref().expect("a file sink");
    let back = feed
        .returned
        .recv_timeout(std::time::Duration::from_secs(30))
        .expect("the first batch comes back");
    assert!(back.times_ns.is_empty() && back.values.is_empty() && back.world_from_link.is_empty());
    assert!(
        back.times_ns.capacity() >= BATCH_UPDATES,
        "{}",
        back.times_ns.capacity()
    );
    assert!(back.values.capacity() >= BATCH_UPDATES, "{}", back.values.capacity());
    let finished = recording.finish(&twin);
    assert!(finished.files_complete, "{:?}", finished.failures);
}

/// `--save-frames`: a frame handed to the recording is logged as an image
/// under its camera, whose pinhole (pose, field of view, size) is logged
/// once.
#[test]
fn frames_are_logged_under_their_camera_s_pinhole() {
    let (mut twin, mut recording, path) = open("indexing_table", "frames.rrd");
    recording.log(&twin).expect("log");
    twin.step();
    recording.log(&twin).expect("log");
    let rgb: Vec<u8> = (0..4 * 2 * 3).map(|k| k as u8).collect();
    recording.images(&twin, vec![("iso".to_owned(), rgb, [4, 2])]);
    let finished = recording.finish(&twin);
    assert!(finished.files_complete, "{:?}", finished.failures);
    let components: Vec<String> = chunks_in(&path)
        .iter()
        .filter(|(_, _, c)| c.entity_path().to_string() == "/cameras/iso")
        .flat_map(|(_, _, c)| {
            c.components()
                .0
                .values()
                .map(|col| col.descriptor.component.to_string())
                .collect::<Vec<_>>()
        })
        .collect();
    for component in [
        "Pinhole:image_from_camera",
        "Pinhole:resolution",
        "Transform3D:quaternion",
        "Image:buffer",
    ] {
        assert!(components.iter().any(|c| c == component), "{component}: {components:?}");
    }
}
