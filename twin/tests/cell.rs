//! The cell: parts, sources, sinks, conveyors and sensors against analytic
//! answers — free fall through a beam and a zone, a diffuse eye's
//! distance, a pulse shorter than the RPI, injected faults, a VFD's ramp
//! and encoder — and bad inputs, each refused with its place and field.

mod common;

use std::path::{Path, PathBuf};
use twin::run::Twin;

const G: f64 = 9.81;

/// A scene on the indexing table fixture with `body` after the head; the
/// routine `Main` (if given) runs in a 4 ms task.
fn scene(name: &str, body: &str, routine: Option<&str>) -> PathBuf {
    let dir = common::fresh_dir("cell-tests", name);
    // Top-level keys go before the head's tables.
    let (root, body) = match body.strip_prefix("parts_step_ms") {
        Some(rest) => {
            let end = rest.find('\n').map_or(rest.len(), |k| k + 1);
            (format!("parts_step_ms{}", &rest[..end]), &rest[end..])
        }
        None => (String::new(), body),
    };
    let mut text = root + &common::indexing_table_head() + body;
    if let Some(r) = routine {
        std::fs::write(dir.join("Main.st"), r).expect("routine");
        text += "[[tasks]]\nname = \"T\"\nperiod_ms = 4.0\npriority = 5\n[[tasks.programs]]\nname = \"P\"\nmain = \"Main.st\"\n";
    }
    let path = dir.join("scene.toml");
    std::fs::write(&path, text).expect("scene");
    path
}

fn twin(path: &Path) -> Twin {
    let scene = twin::scene::load(path).unwrap_or_else(|e| panic!("{e}"));
    Twin::new(scene).unwrap_or_else(|e| panic!("{e}"))
}

/// The error loading and binding `path` gives, as its text.
fn refusal(path: &Path) -> String {
    match twin::scene::load(path) {
        Err(e) => e.to_string(),
        Ok(scene) => match Twin::new(scene) {
            Err(e) => e.diagnostic().render(false),
            Ok(_) => panic!("{} loads", path.display()),
        },
    }
}

fn run_for(t: &mut Twin, seconds: f64) {
    let n = (seconds / 0.004).round() as usize;
    for _ in 0..n {
        t.step();
    }
}

fn sensor<'a>(t: &'a Twin, name: &str) -> &'a twin::plant::sensors::SensorSim {
    t.plant()
        .sensors()
        .iter()
        .find(|s| s.name == name)
        .unwrap_or_else(|| panic!("no sensor {name}"))
}

fn tag_value(t: &Twin, name: &str) -> twin::program::types::Value {
    let mem = t.program().controller().memory();
    let k = mem.find(name).unwrap_or_else(|| panic!("no tag {name}"));
    mem.slots[mem.tags[k].base]
}

const CUBE: &str = "[[part_types]]\nname = \"Cube\"\nshape = \"box\"\nsize = [0.01, 0.01, 0.01]\nmass_kg = 0.01\n";

fn tags(list: &[(&str, &str)]) -> String {
    list.iter()
        .map(|(n, t)| format!("[[tags]]\nname = \"{n}\"\ntype = \"{t}\"\n"))
        .collect()
}

/// A 10 mm cube dropped from rest at z0 = 1 m falls through a beam at
/// z = 0.5 m and a zone 0.3–0.4 m: the bottom face reaches a height h at
/// t = √(2 (z0 − 0.005 − h) / g). Each edge is within one parts step
/// (4 ms) of that instant (rapier's symplectic Euler lags by half a step).
#[test]
fn a_falling_part_crosses_a_beam_and_a_zone_at_the_analytic_times() {
    let body = tags(&[("Eye", "BOOL"), ("Inside", "BOOL"), ("Count", "DINT")])
        + CUBE
        + "[[sources]]\nname = \"Drop\"\npart_type = \"Cube\"\nposition = [0.0, 0.0, 1.0]\nat_s = [0.0]\n\
           [[sensors]]\nname = \"Beam\"\nkind = \"beam\"\ntag = \"Eye\"\nfrom = [0.0, -0.2, 0.5]\nto = [0.0, 0.2, 0.5]\n\
           [[sensors]]\nname = \"Zone\"\nkind = \"zone\"\ntag = \"Inside\"\ncount_tag = \"Count\"\nshape = \"box\"\n\
           size = [0.2, 0.2, 0.1]\nposition = [0.0, 0.0, 0.35]\n";
    let mut t = twin(&scene("fall", &body, None));
    run_for(&mut t, 0.4);
    let at = |h: f64| (2.0 * h / G).sqrt();
    let beam = sensor(&t, "Beam").edges().to_vec();
    assert_eq!(beam.len(), 2, "{beam:?}");
    let (rise, fall) = (beam[0], beam[1]);
    assert!(rise.1 && !fall.1);
    let step = 0.004;
    assert!(
        (rise.0 - at(0.495)).abs() < step,
        "beam on at {} vs {}",
        rise.0,
        at(0.495)
    );
    assert!(
        (fall.0 - at(0.505)).abs() < step,
        "beam off at {} vs {}",
        fall.0,
        at(0.505)
    );
    let zone = sensor(&t, "Zone").edges().to_vec();
    assert_eq!(zone.len(), 2, "{zone:?}");
    assert!((zone[0].0 - at(1.0 - 0.005 - 0.4)).abs() < step, "zone entry {zone:?}");
    assert!((zone[1].0 - at(1.0 + 0.005 - 0.3)).abs() < step, "zone exit {zone:?}");
    // Between the two, the count is 1: the tag at a scan inside.
    let mut t = twin(&scene("fall-count", &body, None));
    run_for(&mut t, (at(0.595) + at(0.705)) / 2.0);
    t.step();
    assert_eq!(tag_value(&t, "Count").as_i64(), 1);
    assert!(tag_value(&t, "Inside").truthy());
}

/// A part at rest on a block, seen by a diffuse eye along +x: the distance
/// is the gap to its face, within 1e-6 m, scaled through `scale`; with
/// nothing in range it is the range.
#[test]
fn a_diffuse_eye_reports_the_distance_to_the_face_it_sees() {
    let body = tags(&[("Seen", "BOOL"), ("Dist", "REAL"), ("Raw", "BOOL"), ("RawDist", "REAL")])
        + CUBE
        + "[[obstacles]]\nname = \"Block\"\nshape = \"box\"\nsize = [0.2, 0.2, 0.1]\nposition = [0.3, 0.0, 0.05]\n\
           [[sources]]\nname = \"Put\"\npart_type = \"Cube\"\nposition = [0.3, 0.0, 0.1051]\nat_s = [0.0]\n\
           [[sensors]]\nname = \"Eye\"\nkind = \"diffuse\"\ntag = \"Seen\"\nvalue_tag = \"Dist\"\nposition = [0.0, 0.0, 0.105]\n\
           range_m = 0.5\nscale = [[0.0, 4.0], [0.5, 20.0]]\n\
           [[sensors]]\nname = \"Eye2\"\nkind = \"diffuse\"\ntag = \"Raw\"\nvalue_tag = \"RawDist\"\nposition = [0.0, 0.0, 0.105]\n\
           range_m = 0.2\n";
    let mut t = twin(&scene("diffuse", &body, None));
    run_for(&mut t, 0.3);
    t.step();
    let gap = 0.3 - 0.005;
    let dist = tag_value(&t, "Dist").as_f64();
    let want = 4.0 + gap * 16.0 / 0.5;
    assert!((dist - want).abs() < 1e-3 * 32.0, "scaled {dist} vs {want}");
    assert!(tag_value(&t, "Seen").truthy());
    // The second eye's range ends before the part.
    assert!(!tag_value(&t, "Raw").truthy());
    assert!((tag_value(&t, "RawDist").as_f64() - 0.2).abs() < 1e-7);
    // The part's face where the physics put it.
    let m = t.plant().material().expect("a parts world");
    let x = m.part_pose(&m.parts()[0]).translation.x;
    let exact = x - 0.005;
    let unscaled = (dist - 4.0) * 0.5 / 16.0;
    assert!((unscaled - exact).abs() < 1e-6, "{unscaled} vs {exact}");
}

/// A 10 mm cube falling at about 5 m/s through a beam: a 2 ms pulse. An
/// input module updating every 10 ms (no COS) sees no update inside it: a
/// missed pulse, and the tag never turns on. With COS the module takes it
/// (a scan sees it only if one falls inside the pulse).
#[test]
fn a_pulse_shorter_than_the_rpi_is_missed_without_cos() {
    // The bottom reaches z = 0 at t = 0.5125 s (+ half a step).
    let drop = 0.5 * G * 0.5125_f64.powi(2);
    let body = |cos: bool| {
        tags(&[("Eye", "BOOL"), ("Seen", "DINT")])
            + CUBE
            + &format!(
                "[[sources]]\nname = \"Drop\"\npart_type = \"Cube\"\nposition = [0.0, 0.0, {}]\nat_s = [0.0]\n\
                 [[sensors]]\nname = \"Beam\"\nkind = \"beam\"\ntag = \"Eye\"\nfrom = [0.0, -0.2, 0.0]\nto = [0.0, 0.2, 0.0]\n\
                 rpi_ms = 10.0\ncos = {cos}\n",
                drop + 0.005
            )
    };
    let routine = "IF Eye THEN Seen := Seen + 1; END_IF;\n";
    let mut t = twin(&scene("pulse", &body(false), Some(routine)));
    run_for(&mut t, 0.6);
    let edges = sensor(&t, "Beam").edges().to_vec();
    assert_eq!(edges.len(), 2, "{edges:?}");
    let width = edges[1].0 - edges[0].0;
    assert!((0.0015..0.0025).contains(&width), "pulse {width} s");
    assert_eq!(sensor(&t, "Beam").stats(t.time_s()).missed_pulses, 1);
    assert_eq!(tag_value(&t, "Seen").as_i64(), 0, "no scan saw it");

    let mut c = twin(&scene("pulse-cos", &body(true), Some(routine)));
    run_for(&mut c, 0.6);
    assert_eq!(
        sensor(&c, "Beam").stats(c.time_s()).missed_pulses,
        0,
        "COS took the pulse"
    );
}

/// Each fault kind: `stuck_on` and `stuck_off` override a sensor for their
/// window; `stalled` stops a belt whatever its VFD is told.
#[test]
fn injected_faults_override_what_the_devices_do() {
    let body = tags(&[("A", "BOOL"), ("B", "BOOL"), ("Run", "BOOL")])
        + CUBE
        + "[[sources]]\nname = \"Put\"\npart_type = \"Cube\"\nposition = [-0.4, 0.0, 0.556]\nat_s = [0.0]\n\
           [[conveyors]]\nname = \"Belt\"\nposition = [0.0, 0.0, 0.5]\nsize = [1.0, 0.2, 0.1]\nrun = \"Run\"\nmax_speed_mps = 0.5\n\
           faults = [{ kind = \"stalled\", from_s = 0.2, to_s = 0.6 }]\n\
           [[sensors]]\nname = \"On\"\nkind = \"zone\"\ntag = \"A\"\nshape = \"sphere\"\nradius = 0.01\nposition = [2.0, 0.0, 2.0]\n\
           faults = [{ kind = \"stuck_on\", from_s = 0.1, to_s = 0.3 }]\n\
           [[sensors]]\nname = \"Off\"\nkind = \"zone\"\ntag = \"B\"\nshape = \"box\"\nsize = [2.0, 1.0, 1.0]\nposition = [0.0, 0.0, 0.5]\n\
           faults = [{ kind = \"stuck_off\", from_s = 0.5 }]\n";
    let mut t = twin(&scene("faults", &body, Some("Run := TRUE;\n")));
    run_for(&mut t, 0.3);
    let x0 = {
        let m = t.plant().material().expect("parts");
        m.part_pose(&m.parts()[0]).translation.x
    };
    run_for(&mut t, 0.2);
    let x1 = {
        let m = t.plant().material().expect("parts");
        m.part_pose(&m.parts()[0]).translation.x
    };
    assert!((x1 - x0).abs() < 0.005, "a stalled belt carries nothing: {x0} → {x1}");
    assert_eq!(t.plant().material().expect("parts").conveyors()[0].speed_mps(), 0.0);
    run_for(&mut t, 0.3);
    let on = sensor(&t, "On").edges().to_vec();
    assert_eq!(on.len(), 2, "{on:?}");
    assert!((on[0].0 - 0.1).abs() < 1e-9 && (on[1].0 - 0.3).abs() < 1e-9, "{on:?}");
    let off = sensor(&t, "Off").edges().to_vec();
    assert_eq!(off.len(), 2, "the part is seen, then stuck off at 0.5 s: {off:?}");
    assert!((off[1].0 - 0.5).abs() < 1e-9, "{off:?}");
    assert!(!tag_value(&t, "B").truthy());
    let belt_moved = t.plant().material().expect("parts").conveyors()[0].speed_mps();
    assert_eq!(belt_moved, 0.5, "the belt runs again after the stall");
}

/// A VFD belt ramps at accel_mps2 to speed % of max_speed_mps, reports
/// running, and counts its travel in encoder counts.
#[test]
fn a_vfd_belt_ramps_and_counts_its_travel() {
    let body = tags(&[
        ("Run", "BOOL"),
        ("Rev", "BOOL"),
        ("Pct", "REAL"),
        ("Moving", "BOOL"),
        ("Enc", "DINT"),
    ]) + "[[conveyors]]\nname = \"Belt\"\nposition = [0.0, 0.0, 0.5]\nsize = [1.0, 0.2, 0.1]\nrun = \"Run\"\nreverse = \"Rev\"\n\
           speed = \"Pct\"\nmax_speed_mps = 0.8\naccel_mps2 = 2.0\nrunning_tag = \"Moving\"\nencoder_tag = \"Enc\"\ncounts_per_m = 10000\n";
    let mut t = twin(&scene("vfd", &body, Some("Run := TRUE;\nPct := 50.0;\n")));
    t.step();
    assert!(!tag_value(&t, "Moving").truthy(), "still at the first scan");
    run_for(&mut t, 1.0);
    let belt = &t.plant().material().expect("parts").conveyors()[0];
    assert_eq!(belt.speed_mps(), 0.4);
    // The first scan's outputs act from its update on: a 0.2 s ramp to
    // 0.4 m/s (0.04 m), then 0.4 m/s.
    let travel = belt.travel_m();
    let want = 0.04 + 0.4 * (t.time_s() - 0.2);
    assert!((travel - want).abs() < 1e-9, "{travel} vs {want}");
    t.step();
    assert!(tag_value(&t, "Moving").truthy());
    let enc = tag_value(&t, "Enc").as_i64();
    let counts = (t.plant().material().expect("parts").conveyors()[0].travel_m() * 10000.0).floor() as i64;
    assert!((enc - counts).abs() <= 20, "{enc} vs {counts} (one update behind)");
}

/// A belt with a VFD (`Run`, `Pct` of 0.5 m/s, ramping at `accel_mps2`),
/// a 10 mm cube dropped on it at rest, a beam across it at x = 0.2 m and a
/// sink past its end; `extra` goes on the conveyor. `Clock` (DINT) is
/// for the routine's own use.
fn riding_scene(name: &str, accel_mps2: f64, extra: &str, routine: &str) -> PathBuf {
    let body = tags(&[("Run", "BOOL"), ("Pct", "REAL"), ("Eye", "BOOL"), ("Clock", "DINT")])
        + CUBE
        + "[[sources]]\nname = \"Feed\"\npart_type = \"Cube\"\nposition = [-0.45, 0.0, 0.5555]\nat_s = [0.0]\n"
        + &format!(
            "[[conveyors]]\nname = \"Belt\"\nposition = [0.0, 0.0, 0.5]\nsize = [1.0, 0.2, 0.1]\nrun = \"Run\"\n\
             speed = \"Pct\"\nmax_speed_mps = 0.5\naccel_mps2 = {accel_mps2}\n{extra}"
        )
        + "[[sensors]]\nname = \"Beam\"\nkind = \"beam\"\ntag = \"Eye\"\nfrom = [0.2, -0.2, 0.555]\nto = [0.2, 0.2, 0.555]\n\
           [[sinks]]\nname = \"End\"\nposition = [0.7, 0.0, 0.2]\nsize = [0.3, 0.4, 0.3]\n";
    scene(name, &body, Some(routine))
}

/// What [`ride_record`] saw.
struct RideRecord {
    /// Every 0.1 s: the part's x, m, and whether it rode.
    xs: Vec<(f64, bool)>,
    /// The beam's edges: time, s, and state.
    edges: Vec<(f64, bool)>,
    /// When the part was delivered, s.
    delivered: Vec<f64>,
}

/// Runs `path` for 3 s.
fn ride_record(path: &Path) -> RideRecord {
    let mut t = twin(path);
    let mut xs = Vec::new();
    for _ in 0..30 {
        run_for(&mut t, 0.1);
        let m = t.plant().material().expect("parts");
        if let Some(p) = m.parts().first() {
            xs.push((m.part_pose(p).translation.x, m.rides(p)));
        }
    }
    let m = t.plant().material().expect("parts");
    let delivered = m
        .events()
        .iter()
        .filter(|e| e.event == "delivered")
        .map(|e| e.time_s)
        .collect();
    RideRecord {
        xs,
        edges: sensor(&t, "Beam").edges().to_vec(),
        delivered,
    }
}

/// A part at rest on a running belt rides it (a kinematic body, no
/// contacts to solve) and moves as the solver moves it with `ride =
/// false`: within 0.1 mm all along (40 µm here), its beam edges and its
/// delivery within one parts step. It boards once it has settled (at the belt's
/// 2 m/s² ramp, well inside friction's 0.6 g) and alights before the
/// belt's end, falling into the sink.
#[test]
fn a_part_riding_a_belt_moves_as_the_solver_moves_it() {
    let routine = "Run := TRUE;\nPct := 100.0;\n";
    let riding = ride_record(&riding_scene("ride", 2.0, "", routine));
    let solved = ride_record(&riding_scene("ride-off", 2.0, "ride = false\n", routine));
    assert!(riding.xs.iter().any(|(_, r)| *r), "it rode: {:?}", riding.xs);
    assert!(solved.xs.iter().all(|(_, r)| !*r), "ride = false: never");
    assert_eq!(riding.xs.len(), solved.xs.len(), "{:?} vs {:?}", riding.xs, solved.xs);
    for ((a, _), (b, _)) in riding.xs.iter().zip(&solved.xs) {
        assert!((a - b).abs() < 1e-4, "x {a} riding vs {b} solved");
    }
    assert_eq!(riding.edges.len(), 2, "{:?}", riding.edges);
    assert_eq!(riding.edges.len(), solved.edges.len());
    for (a, b) in riding.edges.iter().zip(&solved.edges) {
        assert!(a.1 == b.1 && (a.0 - b.0).abs() <= 0.004 + 1e-9, "edge {a:?} vs {b:?}");
    }
    assert_eq!(riding.delivered.len(), 1, "delivered");
    assert_eq!(solved.delivered.len(), 1);
    assert!((riding.delivered[0] - solved.delivered[0]).abs() <= 0.004 + 1e-9);
}

/// On a belt climbing at 5°, the pull of gravity along it (0.86 m/s²) is
/// well inside half of friction's grip, and the part rides; at 20° (3.4
/// m/s² against 2.8) it is solved all the way, though friction (0.7 for
/// the solver, tan 20° = 0.36) still carries it. Either way it climbs as
/// the solver alone moves it.
#[test]
fn a_part_rides_a_gently_climbing_belt_and_is_solved_on_a_steep_one() {
    for (pitch_deg, rides) in [(5.0_f64, true), (20.0, false)] {
        let (sin, cos) = pitch_deg.to_radians().sin_cos();
        // 0.3 m down the belt, 0.5 mm above its top face.
        let (x, z) = (-0.3 * cos - 0.0555 * sin, 0.5 - 0.3 * sin + 0.0555 * cos);
        let run = |name: &str, extra: &str| {
            let body = tags(&[("Run", "BOOL")])
                + CUBE
                + &format!(
                    "[[sources]]\nname = \"Feed\"\npart_type = \"Cube\"\nposition = [{x}, 0.0, {z}]\nrpy_deg = [0.0, {pitch}, 0.0]\nat_s = [0.0]\n\
                     [[conveyors]]\nname = \"Belt\"\nposition = [0.0, 0.0, 0.5]\nrpy_deg = [0.0, {pitch}, 0.0]\n\
                     size = [1.0, 0.2, 0.1]\nrun = \"Run\"\nmax_speed_mps = 0.2\naccel_mps2 = 1.0\n{extra}",
                    pitch = -pitch_deg,
                );
            let mut t = twin(&scene(name, &body, Some("Run := TRUE;\n")));
            let mut rode = false;
            for _ in 0..250 {
                t.step();
                let m = t.plant().material().expect("parts");
                rode |= m.rides(&m.parts()[0]);
            }
            let m = t.plant().material().expect("parts");
            (rode, m.part_pose(&m.parts()[0]).translation)
        };
        let (rode, at) = run(&format!("climb-{pitch_deg}"), "");
        let (_, solved) = run(&format!("climb-{pitch_deg}-off"), "ride = false\n");
        assert_eq!(rode, rides, "{pitch_deg}°");
        assert!(
            (at - solved).length() < 1e-4,
            "{pitch_deg}°: {at:?} riding vs {solved:?} solved"
        );
        assert!(at.z > z + 0.1 * sin, "{pitch_deg}°: it climbed to {at:?}");
    }
}

/// A belt that speeds up faster than friction can follow (20 m/s² against
/// 0.6 g) makes its riding part alight and slip; one that ramps at
/// 1 m/s² carries it through the ramp. Either way the part ends where the
/// solver alone puts it.
#[test]
fn a_belt_speeding_up_faster_than_friction_follows_makes_its_part_slip() {
    // 10 % until 0.3 s, then 100 %.
    let routine = "Run := TRUE;\nIF Clock < 75 THEN Clock := Clock + 1; Pct := 10.0; ELSE Pct := 100.0; END_IF;\n";
    for (accel, rides_through) in [(20.0, false), (1.0, true)] {
        let ride = |name: &str, extra: &str| {
            let mut t = twin(&riding_scene(name, accel, extra, routine));
            run_for(&mut t, 0.29);
            let m = t.plant().material().expect("parts");
            assert_eq!(
                m.rides(&m.parts()[0]),
                extra.is_empty(),
                "riding at 10 % (accel {accel})"
            );
            let mut rode_through = true;
            for _ in 0..60 {
                t.step();
                let m = t.plant().material().expect("parts");
                rode_through &= m.rides(&m.parts()[0]);
            }
            let m = t.plant().material().expect("parts");
            (rode_through, m.part_pose(&m.parts()[0]).translation.x)
        };
        let (rode_through, x) = ride(&format!("slip-{accel}"), "");
        assert_eq!(rode_through, rides_through, "accel {accel}");
        let (_, solved) = ride(&format!("slip-{accel}-off"), "ride = false\n");
        assert!(
            (x - solved).abs() < 1e-4,
            "accel {accel}: x {x} riding vs {solved} solved"
        );
    }
}

/// A source with `on` spawns at each rise of its output, up to `count`, in
/// the parts step that follows the scan raising it; a cylinder stalled by a
/// fault stands still whatever its valve does, and moves on after.
#[test]
fn a_source_spawns_on_each_rise_and_a_stalled_cylinder_stands_still() {
    let body = tags(&[("Feed", "BOOL"), ("Tick", "DINT"), ("Out", "BOOL")])
        + CUBE
        + "[[sources]]\nname = \"OnDemand\"\npart_type = \"Cube\"\nposition = [0.0, 0.0, 0.3]\non = \"Feed\"\ncount = 3\n\
           [[sinks]]\nname = \"Floor\"\nposition = [0.0, 0.0, 0.05]\nsize = [0.5, 0.5, 0.1]\n\
           [[cylinders]]\nname = \"Push\"\nposition = [1.0, 0.0, 0.5]\nsize = [0.05, 0.05, 0.05]\nstroke_m = 0.1\n\
           extend_ms = 100.0\nextend = \"Out\"\nfaults = [{ kind = \"stalled\", from_s = 0.04, to_s = 0.2 }]\n";
    // Feed rises every 25 scans (0.1 s): at 0, 0.1, 0.2, 0.3 and 0.4 s.
    let routine = "Feed := (Tick MOD 25) < 5;\nTick := Tick + 1;\nOut := TRUE;\n";
    let mut t = twin(&scene("source-on", &body, Some(routine)));
    run_for(&mut t, 0.1);
    let stalled_at = t
        .plant()
        .material()
        .expect("parts")
        .cylinders()
        .next()
        .expect("cylinder")
        .position_m();
    run_for(&mut t, 0.08);
    let m = t.plant().material().expect("parts");
    let cylinder = m.cylinders().next().expect("cylinder");
    assert_eq!(cylinder.position_m(), stalled_at, "stalled from 0.04 s to 0.2 s");
    assert!((stalled_at - 0.04).abs() < 0.005, "1 m/s for 0.04 s: {stalled_at}");
    run_for(&mut t, 0.42);
    let m = t.plant().material().expect("parts");
    assert!(
        m.cylinders().next().expect("cylinder").extended(),
        "moves on after the stall"
    );
    let spawns: Vec<f64> = m
        .events()
        .iter()
        .filter(|e| e.event == "spawned")
        .map(|e| e.time_s)
        .collect();
    assert_eq!(spawns.len(), 3, "count = 3 of five rises: {spawns:?}");
    for (k, at) in spawns.iter().enumerate() {
        let rise = 0.1 * k as f64;
        assert!(
            *at >= rise && *at <= rise + 0.008 + 1e-9,
            "spawn {k} at {at}, rise at {rise}"
        );
    }
}

/// Sources: `every_s` with `count`, `skip`, seeded jitter (the same seed,
/// the same parts); sinks count delivered and rejected parts; a part that
/// falls off the cell is lost.
#[test]
fn sources_sinks_and_lost_parts_are_counted_and_repeatable() {
    let body = CUBE.to_owned()
        + "[[sources]]\nname = \"Every\"\npart_type = \"Cube\"\nposition = [0.0, 0.0, 0.3]\nevery_s = 0.1\ncount = 5\nskip = [2]\n\
           jitter = { time_s = 0.02, position_m = [0.01, 0.01, 0.0], yaw_deg = 10.0, seed = 7 }\n\
           [[sources]]\nname = \"Miss\"\npart_type = \"Cube\"\nposition = [3.0, 0.0, 0.3]\nat_s = [0.0]\n\
           [[sinks]]\nname = \"Good\"\nposition = [0.0, 0.0, 0.05]\nsize = [0.5, 0.5, 0.1]\n\
           [[sinks]]\nname = \"Bad\"\nposition = [5.0, 0.0, 0.05]\nsize = [0.5, 0.5, 0.1]\nas = \"rejected\"\n";
    let path = scene("sources", &body, None);
    let mut a = twin(&path);
    run_for(&mut a, 1.6);
    let counts = a.plant().material().expect("parts").counts().clone();
    assert_eq!(counts.spawned, 5, "5 spawns of Every less the skipped one, and Miss");
    assert_eq!(counts.delivered, 4);
    assert_eq!(counts.rejected, 0);
    assert_eq!(counts.lost, 1, "Miss falls past 1 m under the lowest surface");
    let mut b = twin(&path);
    run_for(&mut b, 1.6);
    assert_eq!(
        a.plant().material().expect("parts").events(),
        b.plant().material().expect("parts").events(),
        "seeded: the same run twice"
    );
    let spawn_times: Vec<f64> = a
        .plant()
        .material()
        .expect("parts")
        .events()
        .iter()
        .filter(|e| e.event == "spawned" && e.at == "Every")
        .map(|e| e.time_s)
        .collect();
    assert_eq!(spawn_times.len(), 4);
    for (k, t) in spawn_times.iter().enumerate() {
        let nominal = [0.0, 0.2, 0.3, 0.4][k];
        assert!((t - nominal).abs() <= 0.02 + 0.004 + 1e-9, "spawn {k} at {t}");
    }
}

/// Bad cell inputs: each refused with one line naming the file, line,
/// column and field.
#[test]
fn bad_cell_inputs_name_their_place_and_field() {
    let eye = tags(&[("Eye", "BOOL"), ("N", "DINT"), ("R", "REAL"), ("DI", "DINT")]);
    let beam = |extra: &str| {
        format!(
            "{eye}[[sensors]]\nname = \"B\"\nkind = \"beam\"\ntag = \"Eye\"\nfrom = [0.0, 0.0, 0.0]\nto = [0.0, 1.0, 0.0]\n{extra}"
        )
    };
    let rows: Vec<(String, &str)> = vec![
        (
            beam("").replace("tag = \"Eye\"", "tag = \"Nope\""),
            "sensors[0].tag: 'Nope' is not a controller tag",
        ),
        (
            beam("").replace("tag = \"Eye\"", "tag = \"R\""),
            "sensors[0].tag: 'R' is REAL; this needs a BOOL",
        ),
        (
            beam(
                "[[sensors]]\nname = \"C\"\nkind = \"beam\"\ntag = \"Eye\"\nfrom = [0.0, 0.0, 0.0]\nto = [1.0, 0.0, 0.0]\n",
            ),
            "sensors[1].tag: 'Eye' is written by beam 'B' already",
        ),
        (
            beam("").replace("tag = \"Eye\"", "tag = \"DI.3\"")
                + "[[sensors]]\nname = \"C\"\nkind = \"beam\"\ntag = \"DI\"\nfrom = [0.0, 0.0, 0.0]\nto = [1.0, 0.0, 0.0]\n",
            "sensors[1].tag: 'DI' is DINT; this needs a BOOL",
        ),
        (
            beam(
                "[[conveyors]]\nname = \"C\"\nposition = [0.0, 0.0, 0.0]\nsize = [1.0, 0.2, 0.1]\nrun = \"Eye\"\nmax_speed_mps = 1.0\n",
            ),
            "conveyors[0].run: 'Eye' is an input already (sensors[0].tag of 'B'): a tag is an input or an output, not both",
        ),
        (
            beam("").replace("kind = \"beam\"", "kind = \"laser\""),
            "sensors[0].kind: unknown sensor kind 'laser'",
        ),
        (
            beam("range_m = 1.0\n"),
            "sensors[0].range_m: 'range_m' does not apply to a beam sensor",
        ),
        (
            beam("").replace("to = [0.0, 1.0, 0.0]", "to = [0.0, 0.0, 0.0]"),
            "sensors[0].to: the beam's 'to' must differ",
        ),
        (
            beam("value_tag = \"N\"\n"),
            "sensors[0].value_tag: a beam's value_tag is a light curtain's bitmask",
        ),
        (
            beam("link = \"no_such_link\"\n"),
            "sensors[0].link: the URDF has no link 'no_such_link'",
        ),
        (beam("rpi_ms = 0.0\n"), "sensors[0].rpi_ms: must be between 0.2 and 750"),
        (
            beam("faults = [{ kind = \"stalled\", from_s = 0.1 }]\n"),
            "sensors[0].faults[0].kind: unknown fault kind for this device 'stalled'",
        ),
        (
            beam("faults = [{ kind = \"stuck_on\", from_s = 0.5, to_s = 0.1 }]\n"),
            "sensors[0].faults[0].to_s: from_s = 0.5 is after to_s = 0.1",
        ),
        (
            CUBE.replace("mass_kg = 0.01", "mass_kg = -1.0"),
            "part_types[0].mass_kg: must be greater than 0",
        ),
        (
            CUBE.to_owned()
                + "[[sources]]\nname = \"S\"\npart_type = \"Sphere\"\nposition = [0.0, 0.0, 1.0]\nevery_s = 1.0\n",
            "sources[0].part_type: unknown part type 'Sphere'",
        ),
        (
            CUBE.to_owned() + "[[sources]]\nname = \"S\"\npart_type = \"Cube\"\nposition = [0.0, 0.0, 1.0]\n",
            "sources[0].name: give one of every_s, on or at_s",
        ),
        (
            eye.clone()
                + CUBE
                + "[[sources]]\nname = \"S\"\npart_type = \"Cube\"\nposition = [0.0, 0.0, 0.5]\nevery_s = 1.0\n\
                   [[conveyors]]\nname = \"C\"\nposition = [0.0, 0.0, 0.5]\nsize = [1.0, 0.2, 0.1]\nrun = \"Eye\"\nmax_speed_mps = 1.0\n",
            "sources[0].position: a Cube spawned here would be 55.0 mm inside conveyor 'C'",
        ),
        (
            CUBE.to_owned()
                + "[[sources]]\nname = \"S\"\npart_type = \"Cube\"\nposition = [0.0, 0.0, 1.0]\nat_s = [0.5, 0.2]\n",
            "sources[0].at_s[1]: the times must not decrease",
        ),
        (
            "[[sinks]]\nname = \"K\"\nposition = [0.0, 0.0, 0.0]\nsize = [1.0, 1.0, 1.0]\nas = \"scrap\"\n".to_owned(),
            "sinks[0].as: unknown sink outcome 'scrap'",
        ),
        (
            "[[conveyors]]\nname = \"C\"\nposition = [0.0, 0.0, 0.0]\nsize = [1.0, 0.2, 0.1]\n".to_owned(),
            "conveyors[0].name: give 'axis'",
        ),
        (
            "[[conveyors]]\nname = \"C\"\nposition = [0.0, 0.0, 0.0]\nsize = [1.0, 0.2, 0.1]\naxis = \"Table\"\n"
                .to_owned(),
            "conveyors[0].axis: a conveyor follows a linear axis",
        ),
        (
            eye.clone()
                + "[[conveyors]]\nname = \"C\"\nposition = [0.0, 0.0, 0.0]\nsize = [1.0, 0.2, 0.1]\nrun = \"Eye\"\n",
            "conveyors[0].max_speed_mps: a VFD conveyor needs max_speed_mps",
        ),
        (
            eye.clone()
                + "[[conveyors]]\nname = \"C\"\nposition = [0.0, 0.0, 0.0]\nsize = [1.0, 0.2, 0.1]\nrun = \"Eye\"\nmax_speed_mps = 1.0\nspeed = \"N\"\n",
            "conveyors[0].speed: 'N' is DINT; this needs a REAL",
        ),
        (
            "parts_step_ms = 3.0\n".to_owned(),
            "parts_step_ms: must be a multiple of physics_step_ms",
        ),
        (
            eye.clone()
                + "[[sensors]]\nname = \"G\"\nkind = \"clearance\"\ntag = \"Eye\"\nbetween = [[\"parts\"], [\"robot\"]]\n",
            "sensors[0].below_m: a clearance sensor needs 'below_m'",
        ),
        (
            eye.clone()
                + "[[sensors]]\nname = \"V\"\nkind = \"vision\"\ntag = \"Eye\"\ntrigger = \"DI.0\"\nshape = \"sphere\"\nradius = 0.1\nposition_tag = \"R\"\n",
            "sensors[0].position_tag: 'R' is REAL; this needs the first of three REALs",
        ),
    ];
    let mut failures = Vec::new();
    for (k, (body, want)) in rows.iter().enumerate() {
        let path = scene(&format!("bad-{k}"), body, None);
        let e = refusal(&path);
        let first = e.lines().next().unwrap_or_default();
        let field = want.split(':').next().unwrap_or_default();
        if !e.contains(want) || !first.contains("scene.toml:") || !first.contains(field) {
            failures.push(format!("row {k}: want '{want}', got: {first}"));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The gantry fixture: X, Y, Z prismatic axes in mm, the tool's TCP at
/// z = 0.21 m + Z, and a table (obstacle) whose top is at z = 0.05 m.
fn gantry_scene(name: &str, body: &str, routine: &str) -> PathBuf {
    let dir = common::fresh_dir("cell-tests", name);
    let urdf = common::root().join("scenes/robots/gantry/gantry.urdf");
    let axis = |n: &str, j: &str| {
        format!(
            "[[axes]]\nname = \"{n}\"\njoint = \"{j}\"\nkind = \"linear\"\nunits = \"mm\"\nmax_velocity = 500.0\n\
             max_acceleration = 5000.0\nmax_deceleration = 5000.0\nmax_jerk = 50000.0\nin_position_window = 0.2\n\
             motor = {{ stiffness = 142122.3, damping = 754.0 }}\n"
        )
    };
    let text = format!(
        "duration_s = 3.0\ncoarse_update_ms = 4.0\nphysics_step_ms = 1.0\n[robot]\nurdf = {urdf:?}\n{}{}{}\
         [[obstacles]]\nname = \"Table\"\nshape = \"box\"\nsize = [0.7, 0.7, 0.05]\nposition = [0.0, 0.0, 0.025]\n\
         [[part_types]]\nname = \"Block\"\nshape = \"box\"\nsize = [0.04, 0.04, 0.04]\nmass_kg = 0.1\n\
         [[sources]]\nname = \"Put\"\npart_type = \"Block\"\nposition = [0.003, 0.0, 0.0705]\nat_s = [0.0]\n\
         [[tags]]\nname = \"Grip\"\ntype = \"BOOL\"\n[[tags]]\nname = \"Holding\"\ntype = \"BOOL\"\n\
         [[tags]]\nname = \"State\"\ntype = \"DINT\"\n[[tags]]\nname = \"MZ\"\ntype = \"MOTION_INSTRUCTION\"\n\
         [[tags]]\nname = \"MX\"\ntype = \"MOTION_INSTRUCTION\"\n{body}\
         [[tasks]]\nname = \"T\"\nperiod_ms = 4.0\npriority = 5\n[[tasks.programs]]\nname = \"P\"\nmain = \"Main.st\"\n",
        axis("X", "x_joint"),
        axis("Y", "y_joint"),
        axis("Z", "z_joint"),
    );
    std::fs::write(dir.join("Main.st"), routine).expect("routine");
    let path = dir.join("scene.toml");
    std::fs::write(&path, text).expect("scene");
    path
}

const GRIPPER: &str = "[[grippers]]\nname = \"Cup\"\nkind = \"vacuum\"\nlink = \"tool\"\ngrip = \"Grip\"\nholding_tag = \"Holding\"\n\
                       build_up_ms = 40.0\nreach_m = 0.003\n";

/// Down to 2 mm over the block, vacuum on, up 100 mm, across 200 mm,
/// down, vacuum off.
const PICK: &str = "CASE State OF\n\
  0: MAM(Z, MZ, 0, -118, 200, UnitsPerSec, 2000, UnitsPerSec2, 2000, UnitsPerSec2, trapezoidal, 100, 100, %ofTime, disabled, programmed, 0, none, 0, 0); State := 1;\n\
  1: IF MZ.PC THEN Grip := TRUE; State := 2; END_IF;\n\
  2: IF Holding THEN MAM(Z, MZ, 0, 0, 200, UnitsPerSec, 2000, UnitsPerSec2, 2000, UnitsPerSec2, trapezoidal, 100, 100, %ofTime, disabled, programmed, 0, none, 0, 0); State := 3; END_IF;\n\
  3: IF MZ.PC THEN MAM(X, MX, 0, 200, 200, UnitsPerSec, 2000, UnitsPerSec2, 2000, UnitsPerSec2, trapezoidal, 100, 100, %ofTime, disabled, programmed, 0, none, 0, 0); State := 4; END_IF;\n\
  4: IF MX.PC THEN MAM(Z, MZ, 0, -100, 200, UnitsPerSec, 2000, UnitsPerSec2, 2000, UnitsPerSec2, trapezoidal, 100, 100, %ofTime, disabled, programmed, 0, none, 0, 0); State := 5; END_IF;\n\
  5: IF MZ.PC THEN Grip := FALSE; State := 6; END_IF;\n\
END_CASE;\n";

/// A vacuum cup picks the block where it lies (3 mm off the TCP's axis:
/// held there, not snapped), carries it and places it 200 mm on; the
/// holding tag follows; the pick offset is recorded.
#[test]
fn a_vacuum_gripper_picks_carries_and_places_a_part_where_it_holds_it() {
    let mut t = twin(&gantry_scene("gripper", GRIPPER, PICK));
    let mut held_at = None;
    let mut lifted = 0.0_f64;
    for _ in 0..1100 {
        t.step();
        let m = t.plant().material().expect("parts");
        if held_at.is_none() && m.grippers()[0].part() != 0 {
            held_at = Some(t.time_s());
        }
        lifted = lifted.max(m.part_pose(&m.parts()[0]).translation.z);
    }
    assert!(held_at.is_some(), "picked");
    let (header, row) = (twin::output::trace::header(&t), twin::output::trace::row(&t));
    assert_eq!(header.len(), row.len(), "a cell per column");
    assert!(header.iter().any(|h| h == "Cup.part"));
    let m = t.plant().material().expect("parts");
    assert_eq!(m.grippers()[0].part(), 0, "placed");
    assert!(lifted > 0.0705 + 0.115, "lifted with the tool: {lifted}");
    let pose = m.part_pose(&m.parts()[0]);
    assert!(
        (pose.translation.x - 0.203).abs() < 0.002,
        "placed 200 mm on, keeping its offset: {pose:?}"
    );
    assert!(
        (pose.translation.z - 0.07).abs() < 0.002,
        "resting on the table: {pose:?}"
    );
    let offset = m.counts().max_pick_offset_m.expect("one pick");
    assert!((offset - 0.003).abs() < 5e-4, "pick offset {offset}");
    assert_eq!(m.counts().dropped, 0);
}

/// A held part weighs on the robot: with the block lifted and Z standing
/// while X carries it, Z's servo drive (the default one, no `motor`)
/// pushes harder by the extra weight when the block is 2 kg instead of
/// 0.1 kg: 1.9 kg × g = 18.6 N, within 1 % (18.64 here).
#[test]
fn a_held_part_adds_its_weight_to_the_drive_that_carries_it() {
    let z_force = |name: &str, mass: &str| {
        let path = gantry_scene(name, GRIPPER, PICK);
        let text = std::fs::read_to_string(&path).expect("scene");
        let text = text
            .replace("mass_kg = 0.1", mass)
            .replace("motor = { stiffness = 142122.3, damping = 754.0 }\n", "");
        std::fs::write(&path, text).expect("scene");
        let mut t = twin(&path);
        for _ in 0..1100 {
            t.step();
            if tag_value(&t, "State").as_i64() == 4 {
                // X is moving; Z stands at the top with the block.
                run_for(&mut t, 0.1);
                let m = t.plant().material().expect("parts");
                assert_ne!(m.grippers()[0].part(), 0, "held");
                return t.plant().drive_torque(2).expect("Z's servo drive");
            }
        }
        panic!("{name}: never carried");
    };
    let light = z_force("payload-light", "mass_kg = 0.1");
    let heavy = z_force("payload-heavy", "mass_kg = 2.0");
    let want = 1.9 * G;
    let extra = heavy - light;
    assert!(
        (extra - want).abs() < 0.05 * want,
        "Z pushes {extra} N more, want {want}: {light} vs {heavy}"
    );
}

/// A part heavier than the grip holds is dropped; so is one whose vacuum
/// fails (`no_vacuum`).
#[test]
fn a_weak_grip_or_a_lost_vacuum_drops_the_part() {
    let weak = GRIPPER.to_owned() + "max_force_n = 0.5\n";
    let mut t = twin(&gantry_scene("gripper-weak", &weak, PICK));
    run_for(&mut t, 1.5);
    let m = t.plant().material().expect("parts");
    assert_eq!(m.counts().dropped, 1, "0.98 N of weight on a 0.5 N grip");
    let lost = GRIPPER.to_owned() + "faults = [{ kind = \"no_vacuum\", from_s = 0.8 }]\n";
    let mut t = twin(&gantry_scene("gripper-vacuum", &lost, PICK));
    run_for(&mut t, 2.0);
    let m = t.plant().material().expect("parts");
    assert_eq!(m.counts().dropped, 1, "{:?}", m.events());
    assert!(
        m.events()
            .iter()
            .any(|e| e.event == "dropped" && (e.time_s - 0.8).abs() < 0.005)
    );
}

/// A stopper cylinder holds parts back on a running belt (they slip and
/// queue), reports its ends, and lets them go when it retracts.
#[test]
fn a_stopper_holds_parts_on_a_running_belt_until_it_retracts() {
    let body = tags(&[("Run", "BOOL"), ("Up", "BOOL"), ("IsUp", "BOOL"), ("IsDown", "BOOL")])
        + CUBE
        + "[[sources]]\nname = \"Feed\"\npart_type = \"Cube\"\nposition = [-0.4, 0.0, 0.556]\nevery_s = 0.2\ncount = 3\n\
           [[conveyors]]\nname = \"Belt\"\nposition = [0.0, 0.0, 0.5]\nsize = [1.0, 0.2, 0.1]\nrun = \"Run\"\nmax_speed_mps = 0.5\n\
           [[cylinders]]\nname = \"Stop\"\nposition = [0.2, 0.0, 0.48]\nrpy_deg = [0.0, -90.0, 0.0]\nsize = [0.1, 0.2, 0.02]\n\
           stroke_m = 0.06\nextend_ms = 60.0\nretract_ms = 30.0\nextend = \"Up\"\nextended_tag = \"IsUp\"\nretracted_tag = \"IsDown\"\n";
    let routine = "Run := TRUE;\nUp := Latch;\n";
    let mut t = twin(&scene("stopper", &(tags(&[("Latch", "BOOL")]) + &body), Some(routine)));
    // Up from the start.
    let latch = {
        let mem = t.program().controller().memory();
        mem.tags[mem.find("Latch").expect("Latch")].base
    };
    t.program_mut().memory_mut().slots[latch] = twin::program::types::Value::Bool(true);
    run_for(&mut t, 0.1);
    assert!(tag_value(&t, "IsUp").truthy() && !tag_value(&t, "IsDown").truthy());
    run_for(&mut t, 2.0);
    let m = t.plant().material().expect("parts");
    let xs: Vec<f64> = m.parts().iter().map(|p| m.part_pose(p).translation.x).collect();
    assert_eq!(xs.len(), 3);
    // Queued against the stopper (within 5 cm of it or of one another),
    // none rides the belt: the solver holds them back.
    assert!(m.parts().iter().all(|p| !m.rides(p)));
    // The stopper's face is at x = 0.19: the cubes queue behind it, 10 mm apart.
    for (k, x) in xs.iter().enumerate() {
        let want = 0.19 - 0.005 - 0.01 * k as f64;
        assert!((x - want).abs() < 0.002, "cube {k} at {x}, want {want}: {xs:?}");
    }
    t.program_mut().memory_mut().slots[latch] = twin::program::types::Value::Bool(false);
    run_for(&mut t, 0.04);
    assert!(tag_value(&t, "IsDown").truthy(), "retracted in 30 ms");
    run_for(&mut t, 1.0);
    let m = t.plant().material().expect("parts");
    assert!(
        m.parts()
            .iter()
            .all(|p| m.part_pose(p).translation.x > 0.3 || m.part_pose(p).translation.z < 0.4)
    );
}

/// The shipped `conveyor_pick` (issue acceptance): 20 boxes spawned and
/// delivered, none rejected, dropped or lost, every pick within 2 mm of the
/// TCP's axis; a rerun's trace is byte-identical. Its kinematic variant
/// (`twin test`) checks the counts on the other plant.
#[test]
fn conveyor_pick_delivers_every_box_within_two_millimetres_and_reruns_identically() {
    let path = common::root().join("scenes/conveyor_pick.toml");
    let run = || {
        let mut t = twin(&path);
        let mut trace = String::new();
        for _ in 0..t.total_updates() {
            t.step();
            twin::output::trace::write_row(&t, &mut trace);
            trace.push('\n');
        }
        (t, trace)
    };
    let (t, first) = run();
    let (_, second) = run();
    assert!(first == second, "the rerun's trace differs");
    let m = t.plant().material().expect("parts");
    let c = m.counts();
    assert_eq!(
        (c.spawned, c.delivered, c.rejected, c.dropped, c.lost),
        (20, 20, 0, 0, 0)
    );
    assert!(m.parts().is_empty());
    let offset_mm = c.max_pick_offset_m.expect("picks") * 1000.0;
    assert!(offset_mm <= 2.0, "largest pick offset {offset_mm} mm");
}

/// MOTION-RM002, MAR: a sensor wired to registration input 1 of a jogging
/// axis latches the axis' position at the instant the part's bottom face
/// crosses the beam (found from the part's own simulated motion, linear
/// inside a parts step) within 1e-4 s; `.PC`, `RegEvent1Status` and the
/// event task on `axis_registration_1` follow.
#[test]
fn a_registration_sensor_latches_the_axis_position_at_the_crossing() {
    let axis = "[[axes]]\nname = \"Conv\"\nkind = \"linear\"\nunits = \"mm\"\nmax_velocity = 1000.0\nmax_acceleration = 10000.0\n\
                max_deceleration = 10000.0\nmax_jerk = 1000000.0\nin_position_window = 0.1\n";
    let body = axis.to_owned()
        + &tags(&[
            ("Eye", "BOOL"),
            ("Latched", "REAL"),
            ("Events", "DINT"),
            ("State", "DINT"),
        ])
        + "[[tags]]\nname = \"R\"\ntype = \"MOTION_INSTRUCTION\"\n[[tags]]\nname = \"J\"\ntype = \"MOTION_INSTRUCTION\"\n"
        + CUBE
        + "[[sources]]\nname = \"Drop\"\npart_type = \"Cube\"\nposition = [0.0, 0.0, 1.0]\nat_s = [0.2]\n\
           [[sensors]]\nname = \"RegEye\"\nkind = \"beam\"\ntag = \"Eye\"\nfrom = [0.0, -0.2, 0.5]\nto = [0.0, 0.2, 0.5]\n\
           registration = { axis = \"Conv\", input = 1 }\n\
           [[tasks]]\nname = \"OnReg\"\ntype = \"event\"\ntrigger = \"axis_registration_1\"\naxis = \"Conv\"\npriority = 4\n\
           [[tasks.programs]]\nname = \"Count\"\nmain = \"Count.st\"\n";
    let routine = "CASE State OF\n\
                   0: MAJ(Conv, J, forward, 300.0, unitspersec, 10000.0, unitspersec2, 10000.0, unitspersec2, trapezoidal);\n\
                      MAR(Conv, R, positive_edge, disabled, 0.0, 0.0, 1);\n\
                      State := 1;\n\
                   1: IF R.PC THEN Latched := Conv.Registration1Position; State := 2; END_IF;\n\
                   END_CASE;\n";
    let path = scene("registration", &body, Some(routine));
    std::fs::write(path.with_file_name("Count.st"), "Events := Events + 1;\n").expect("routine");
    let mut t = twin(&path);
    let mut samples = Vec::new();
    for _ in 0..200 {
        t.step();
        let m = t.plant().material().expect("parts");
        if let Some(p) = m.parts().first() {
            let z = m.part_pose(p).translation.z;
            let conv = t.task().axis_state(t.plant().axes()[1].handle).command_position;
            samples.push((t.time_s(), z - 0.005, conv));
        }
    }
    // The bottom face reaches z = 0.5 between two samples: linear inside.
    let k = samples.iter().position(|s| s.1 <= 0.5).expect("the part crossed");
    let (a, b) = (samples[k - 1], samples[k]);
    let f = (a.1 - 0.5) / (a.1 - b.1);
    let crossing_s = a.0 + f * (b.0 - a.0);
    let conv_at_crossing = a.2 + f * (b.2 - a.2);
    let edge_s = sensor(&t, "RegEye").edges()[0].0;
    assert!(
        (edge_s - crossing_s).abs() < 1e-4,
        "edge at {edge_s} s, crossing at {crossing_s} s"
    );
    let reg = *t.task().registration(t.plant().axes()[1].handle, 1).expect("input 1");
    assert!(reg.event && !reg.armed());
    assert!(
        (reg.position - conv_at_crossing).abs() < 300.0 * 1e-4,
        "latched {} mm, the axis was at {conv_at_crossing} mm",
        reg.position
    );
    assert!(
        (tag_value(&t, "Latched").as_f64() - reg.position).abs() < 1e-3,
        "the routine read it"
    );
    assert_eq!(tag_value(&t, "Events").as_i64(), 1, "the event task ran once");
}

/// MOTION-RM002, MAW: a forward watch at 30 mm on a jogging virtual axis
/// fires once the actual position passes it, at the crossing interpolated
/// inside its coarse update; `.PC`, `WatchEventStatus`, `WatchPosition`
/// and the event task on `axis_watch` follow, and MDW disarms a second
/// watch before it fires.
#[test]
fn a_watch_fires_at_the_crossing_and_triggers_its_event_task() {
    let axis = "[[axes]]\nname = \"Conv\"\nkind = \"linear\"\nunits = \"mm\"\nmax_velocity = 1000.0\nmax_acceleration = 100000.0\n\
                max_deceleration = 100000.0\nmax_jerk = 10000000.0\nin_position_window = 0.1\n";
    let body = axis.to_owned()
        + &tags(&[
            ("Events", "DINT"),
            ("State", "DINT"),
            ("Fired", "BOOL"),
            ("Armed", "BOOL"),
            ("At", "REAL"),
            ("W", "MOTION_INSTRUCTION"),
            ("W2", "MOTION_INSTRUCTION"),
            ("D", "MOTION_INSTRUCTION"),
            ("J", "MOTION_INSTRUCTION"),
        ])
        + "[[tasks]]\nname = \"OnWatch\"\ntype = \"event\"\ntrigger = \"axis_watch\"\naxis = \"Conv\"\npriority = 4\n\
           [[tasks.programs]]\nname = \"Count\"\nmain = \"Count.st\"\n";
    let routine = "CASE State OF\n\
                   0: MAJ(Conv, J, forward, 200.0, unitspersec, 100000.0, unitspersec2, 100000.0, unitspersec2, trapezoidal);\n\
                      MAW(Conv, W, forward, 30.0);\n\
                      State := 1;\n\
                   1: IF W.PC THEN At := Conv.WatchPosition; State := 2; END_IF;\n\
                   2: MAW(Conv, W2, forward, 1000.0); State := 3;\n\
                   3: MDW(Conv, D); State := 4;\n\
                   END_CASE;\n\
                   Fired := Conv.WatchEventStatus; Armed := Conv.WatchEventArmedStatus;\n";
    let path = scene("watch", &body, Some(routine));
    std::fs::write(path.with_file_name("Count.st"), "Events := Events + 1;\n").expect("routine");
    let mut t = twin(&path);
    let conv = t.plant().axes()[1].handle;
    let mut before = (t.time_s(), t.task().axis_state(conv).actual_position);
    let mut crossing_s = None;
    for _ in 0..100 {
        t.step();
        let now = (t.time_s(), t.task().axis_state(conv).actual_position);
        if crossing_s.is_none() && before.1 < 30.0 && now.1 >= 30.0 {
            crossing_s = Some(before.0 + (30.0 - before.1) / (now.1 - before.1) * (now.0 - before.0));
        }
        before = now;
    }
    let w = *t.task().watch(conv);
    let crossing_s = crossing_s.expect("the axis passed 30 mm");
    assert!(
        (w.event_time_s - crossing_s).abs() < 1e-9,
        "{} vs {crossing_s}",
        w.event_time_s
    );
    assert_eq!(w.events, 1);
    assert!(!w.event, "the second MAW cleared WatchEventStatus");
    assert!(!w.armed(), "MDW disarmed the second watch");
    assert_eq!(w.position, 1000.0, "WatchPosition: the last set-point");
    assert_eq!(tag_value(&t, "At").as_f64(), 30.0);
    assert_eq!(tag_value(&t, "Armed").as_i64(), 0);
    assert_eq!(tag_value(&t, "Events").as_i64(), 1, "the event task ran once");
}

/// Where each bead of `glue_gun` (or its variant) starts and ends, against
/// the element edge it belongs to, mm: the conveyor's actual position when
/// the valve acts (the scheduled output's switch time plus the valve's
/// 12 ms response), within its 400 mm board.
fn glue_beads(variant: Option<&str>) -> Vec<(bool, f64)> {
    let path = common::root().join("scenes/glue_gun.toml");
    let scene = twin::scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
    let scene = match variant {
        Some(v) => scene.with_variant(v).expect("the variant"),
        None => scene,
    };
    let mut t = Twin::new(scene).unwrap_or_else(|e| panic!("{e}"));
    for _ in 0..t.total_updates() {
        t.step();
    }
    let (tag, switches) = t.scheduled_switches().next().expect("a scheduled output");
    assert_eq!(tag, "Gun");
    let edges = [
        (true, 100.0),
        (false, 140.0),
        (true, 200.0),
        (false, 260.0),
        (true, 320.0),
        (false, 340.0),
    ];
    switches
        .iter()
        .map(|s| {
            let local = s.axis_position.rem_euclid(400.0);
            let (_, edge) = edges
                .iter()
                .filter(|(on, _)| *on == s.on)
                .min_by(|a, b| (a.1 - local).abs().total_cmp(&(b.1 - local).abs()))
                .expect("an edge");
            (s.on, local - edge)
        })
        .collect()
}

/// MOTION-RM002, MAOC with a scheduled output: at 500 mm/s with the
/// valve's 12 ms compensated (LatchDelay = UnlatchDelay = 0.012 s), every
/// bead starts and ends within 0.1 mm of its place; without the
/// compensation, 6 mm late.
#[test]
fn the_glue_gun_places_every_bead_with_its_compensation() {
    let beads = glue_beads(None);
    assert_eq!(beads.len(), 18, "three beads on each of three boards: {beads:?}");
    for (on, error) in &beads {
        assert!(
            error.abs() < 0.1,
            "{} {error} mm off",
            if *on { "start" } else { "end" }
        );
    }
    let late = glue_beads(Some("uncompensated"));
    assert_eq!(late.len(), 18);
    for (_, error) in &late {
        assert!((error - 6.0).abs() < 0.1, "{error} mm late");
    }
}

/// Where each cut of `knife_registration` (or its variant) lands behind its
/// sheet's leading edge, mm: the knife's actual angle passing 180° (mod
/// 360°) against the sheet under the knife (x = 0) at that instant, both
/// interpolated between updates.
fn knife_cuts(variant: Option<&str>) -> Vec<f64> {
    let path = common::root().join("scenes/knife_registration.toml");
    let scene = twin::scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
    let scene = match variant {
        Some(v) => scene.with_variant(v).expect("the variant"),
        None => scene,
    };
    let mut t = Twin::new(scene).unwrap_or_else(|e| panic!("{e}"));
    let knife = t.plant().axes()[1].handle;
    let sheets = |t: &Twin| -> Vec<(u64, f64)> {
        let m = t.plant().material().expect("parts");
        m.parts().iter().map(|p| (p.id, m.part_pose(p).translation.x)).collect()
    };
    let mut before = (t.time_s(), t.task().axis_state(knife).actual_position, sheets(&t));
    let mut cuts = Vec::new();
    for _ in 0..t.total_updates() {
        t.step();
        let now = (t.time_s(), t.task().axis_state(knife).actual_position, sheets(&t));
        let (a0, a1) = (before.1, now.1);
        let k = ((a1 - 180.0) / 360.0).floor();
        let blade = 180.0 + 360.0 * k;
        if a0 < blade && a1 >= blade {
            let f = (blade - a0) / (a1 - a0);
            for (id, x1) in &now.2 {
                let Some((_, x0)) = before.2.iter().find(|(i, _)| i == id) else {
                    continue;
                };
                let centre = x0 + f * (x1 - x0);
                if (centre - 0.0).abs() < 0.15 {
                    cuts.push((centre + 0.15) * 1000.0);
                }
            }
        }
        before = now;
    }
    cuts
}

/// The acceptance for `knife_registration`: with MAR every cut
/// lands within 0.5 mm of 100 mm behind its sheet's edge at 300 mm/s;
/// scanning the eye's tag instead (4 ms RPI, 4 ms task) misses by up to
/// 300 mm/s × 8 ms = 2.4 mm.
#[test]
fn registration_cuts_land_within_half_a_millimetre_and_scanned_ones_do_not() {
    let latched = knife_cuts(None);
    assert_eq!(latched.len(), 5, "{latched:?}");
    for c in &latched {
        assert!((c - 100.0).abs() <= 0.5, "a cut at {c} mm from the edge: {latched:?}");
    }
    let scanned = knife_cuts(Some("scanned"));
    assert_eq!(scanned.len(), 5, "{scanned:?}");
    let worst = scanned.iter().map(|c| (c - 100.0).abs()).fold(0.0, f64::max);
    assert!(
        worst > 0.5 && worst <= 2.4 + 0.5,
        "scanned cuts miss by {worst} mm: {scanned:?}"
    );
}

/// A clearance sensor between the parts and an obstacle gives their
/// distance (within 1e-6 m of the gap between the cube's face and the
/// wall's, from the cube's simulated pose) and sets its BOOL below
/// `below_m`.
#[test]
fn a_clearance_sensor_measures_the_gap_between_two_groups() {
    let body = tags(&[("Close", "BOOL"), ("Gap", "REAL")])
        + CUBE
        + "[[obstacles]]\nname = \"Block\"\nshape = \"box\"\nsize = [0.2, 0.2, 0.1]\nposition = [0.3, 0.0, 0.05]\n\
           [[obstacles]]\nname = \"Wall\"\nshape = \"box\"\nsize = [0.02, 0.2, 0.1]\nposition = [0.35, 0.0, 0.15]\n\
           [[sources]]\nname = \"Put\"\npart_type = \"Cube\"\nposition = [0.3, 0.0, 0.1051]\nat_s = [0.0]\n\
           [[sensors]]\nname = \"Gauge\"\nkind = \"clearance\"\ntag = \"Close\"\nvalue_tag = \"Gap\"\n\
           between = [[\"parts\"], [\"Wall\"]]\nbelow_m = 0.05\n";
    let mut t = twin(&scene("clearance", &body, None));
    run_for(&mut t, 0.3);
    t.step();
    let m = t.plant().material().expect("parts");
    let x = m.part_pose(&m.parts()[0]).translation.x;
    let exact = (0.35 - 0.01) - (x + 0.005);
    let gap = tag_value(&t, "Gap").as_f64();
    assert!((gap - exact).abs() < 1e-6, "{gap} vs {exact}");
    assert!(tag_value(&t, "Close").truthy(), "{gap} m < 0.05 m");
}

/// A camera triggered by the program reports, `latency_ms` later, the part
/// nearest its field's centre: found, its position in a link's frame (mm,
/// within 0.1 mm of its simulated pose), its angle about z and its
/// `type_id`.
#[test]
fn a_vision_sensor_reports_the_part_after_its_latency() {
    let body = tags(&[("Snap", "BOOL"), ("Found", "BOOL"), ("Angle", "REAL"), ("Kind", "DINT")])
        + "[[tags]]\nname = \"Pos\"\ntype = \"REAL[3]\"\n"
        + &CUBE.replace("mass_kg = 0.01", "mass_kg = 0.01\ntype_id = 7")
        + "[[obstacles]]\nname = \"Block\"\nshape = \"box\"\nsize = [0.2, 0.2, 0.1]\nposition = [0.3, 0.0, 0.05]\n\
           [[sources]]\nname = \"Put\"\npart_type = \"Cube\"\nposition = [0.31, -0.02, 0.1051]\nrpy_deg = [0.0, 0.0, 30.0]\nat_s = [0.0]\n\
           [[sensors]]\nname = \"Cam\"\nkind = \"vision\"\ntag = \"Found\"\ntrigger = \"Snap\"\nposition = [0.3, 0.0, 0.5]\n\
           shape = \"box\"\nsize = [0.2, 0.2, 1.0]\nlatency_ms = 40.0\nposition_tag = \"Pos[0]\"\nangle_tag = \"Angle\"\ntype_tag = \"Kind\"\nunits = \"mm\"\n";
    let routine = "Snap := T >= 100;\nT := T + 1;\n";
    let mut t = twin(&scene("vision", &(tags(&[("T", "DINT")]) + &body), Some(routine)));
    // The trigger rises at the scan of update 100 (t = 0.4 s).
    run_for(&mut t, 0.4 + 0.036);
    assert!(!tag_value(&t, "Found").truthy(), "not before its latency");
    run_for(&mut t, 0.008);
    assert!(tag_value(&t, "Found").truthy(), "40 ms after the trigger");
    let m = t.plant().material().expect("parts");
    let pose = m.part_pose(&m.parts()[0]);
    let mem = t.program().controller().memory();
    let base = mem.tags[mem.find("Pos").expect("Pos")].base;
    let pos: Vec<f64> = (0..3).map(|k| mem.slots[base + k].as_f64()).collect();
    let want = [
        pose.translation.x * 1000.0,
        pose.translation.y * 1000.0,
        pose.translation.z * 1000.0,
    ];
    for k in 0..3 {
        assert!((pos[k] - want[k]).abs() < 0.1, "{pos:?} vs {want:?}");
    }
    assert!((tag_value(&t, "Angle").as_f64() - 30.0).abs() < 0.05);
    assert_eq!(tag_value(&t, "Kind").as_i64(), 7);
}

/// `twin check`'s I/O list: each device's tags with their direction, and a
/// routine's assignment to an input tag named by file, line and column.
#[test]
fn the_io_list_names_each_point_and_the_routines_writing_inputs() {
    let body = tags(&[("Eye", "BOOL"), ("DI", "DINT"), ("Run", "BOOL")])
        + "[[conveyors]]\nname = \"Belt\"\nposition = [0.0, 0.0, 0.5]\nsize = [1.0, 0.2, 0.1]\nrun = \"Run\"\nmax_speed_mps = 0.5\n\
           [[sensors]]\nname = \"PE\"\nkind = \"beam\"\ntag = \"DI.2\"\nfrom = [0.0, -0.2, 0.6]\nto = [0.0, 0.2, 0.6]\n";
    let routine = "Run := TRUE;\nIF Eye THEN\n  DI := 0;\nEND_IF;\n";
    let path = scene("io-list", &body, Some(routine));
    let mut t = twin(&path);
    let entries: Vec<_> = t.program().io().entries().cloned().collect();
    let list: Vec<(String, twin::scene::IoDirection, String)> = entries
        .iter()
        .map(|e| (e.tag.clone(), e.direction, e.device.clone()))
        .collect();
    assert_eq!(
        list,
        vec![
            ("DI.2".to_owned(), twin::scene::IoDirection::Input, "PE".to_owned()),
            ("Run".to_owned(), twin::scene::IoDirection::Output, "Belt".to_owned()),
        ]
    );
    let writes = t.input_writes();
    assert_eq!(writes.len(), 1, "{writes:?}");
    assert!(writes[0].0.ends_with("Main.st:3:3"), "{writes:?}");
    assert_eq!(writes[0].1, "DI.2");
}

/// A `scheduled_output` is a controller DINT on an axis' execution target.
#[test]
fn a_scheduled_output_names_a_dint_an_axis_and_one_of_its_targets() {
    for (tag, needle) in [
        (
            "[[tags]]\nname = \"G\"\ntype = \"REAL\"\nscheduled_output = { axis = \"Table\" }\n",
            "a scheduled output is a controller DINT tag",
        ),
        (
            "[[tags]]\nname = \"G\"\ntype = \"DINT\"\nscheduled_output = { axis = \"Table\", execution_target = 4 }\n",
            "execution targets 0 to 3",
        ),
        (
            "[[tags]]\nname = \"G\"\ntype = \"DINT\"\nscheduled_output = { axis = \"Nope\" }\n",
            "Nope",
        ),
        (
            "[[tags]]\nname = \"G\"\ntype = \"DINT\"\nscheduled_output = { axis = \"Table\" }\n[[tags]]\nname = \"H\"\ntype = \"DINT\"\nscheduled_output = { axis = \"Table\", execution_target = 0 }\n",
            "'G' is already the scheduled output",
        ),
    ] {
        let path = scene("scheduled", tag, None);
        let e = refusal(&path);
        assert!(e.contains(needle) && e.contains("scheduled_output"), "{e}");
    }
}

/// The coarse update lives on the MOTION_GROUP tag; the scene's
/// `coarse_update_ms` is its shorthand: either, or both the same.
#[test]
fn the_motion_group_tag_carries_the_coarse_update() {
    let group = |ms: f64| format!("[[tags]]\nname = \"Group\"\ntype = \"MOTION_GROUP\"\ncoarse_update_ms = {ms:?}\n");
    let same = scene("group-same", &group(4.0), None);
    assert_eq!(
        twin::scene::load(&same)
            .unwrap_or_else(|e| panic!("{e}"))
            .coarse_update_ms,
        4.0
    );
    let other = scene("group-other", &group(8.0), None);
    let e = refusal(&other);
    assert!(e.contains("coarse_update_ms") && e.contains("MOTION_GROUP"), "{e}");
    // Only on the group tag.
    let wrong = scene(
        "group-wrong",
        "[[tags]]\nname = \"N\"\ntype = \"REAL\"\ncoarse_update_ms = 2.0\n",
        None,
    );
    assert!(refusal(&wrong).contains("only a MOTION_GROUP tag"));
    // On the tag alone: the scene's period.
    let text = std::fs::read_to_string(&other)
        .expect("scene")
        .replace("coarse_update_ms = 4.0\n", "");
    std::fs::write(&other, text).expect("scene");
    let scene = twin::scene::load(&other).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(scene.coarse_update_ms, 8.0);
}
