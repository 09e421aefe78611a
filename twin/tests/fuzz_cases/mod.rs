//! Seeded mutation fuzzing of every file the twin reads: scene TOML,
//! Structured Text routines, URDF, STL, COLLADA and a Studio 5000 export.
//!
//! Case `n` draws from `ChaCha8Rng::seed_from_u64(SEED + n)`: a target
//! (every tenth case the L5X export of `scenes/l5x/scara_pick.toml` or of
//! its ladder twin `scara_pick_ladder.toml`, in turn, loaded
//! with that scene through [`twin::scene::parse_with_l5x`]; the others by
//! weight: scenes 32 %, Add-On Instruction exports 8 % (loaded with
//! `scenes/conveyor_ladder.toml`), ST routines 10 %, ladder routines 12 %,
//! URDF 18 %, STL 12 %, COLLADA 8 %), a
//! shipped file of that kind (or a generated COLLADA document), and one to
//! three mutations — a number replaced by an extreme (NaN, ±inf, ±1e300,
//! 2³², 1e-300, -0, …), a line deleted, duplicated or moved, a character
//! from XML/TOML/ST syntax inserted, a span repeated up to 2,000 times
//! (deep nesting, huge arrays), the text cut short; bytes flipped, cut or
//! overwritten with NaN floats in binary STL. The mutant goes through the
//! twin's own entry point: [`twin::scene::parse`] (every 25th scene that
//! loads is also built with `Twin::new` and run for 25 updates),
//! [`Sandbox::new`] or [`Sandbox::ladder`] and 5 scans,
//! [`RobotModel::from_urdf_str`],
//! [`parse_stl`], [`parse_dae`].
//!
//! A case fails when it panics, takes longer than [`CASE_LIMIT`], or its
//! error does not name its file (a routine's error its `line:column`; a URDF
//! structure error its link or joint, the scene naming the file). Stack
//! overflows and aborts cannot be caught: they end the process, which
//! fails the suite just the same.

#![allow(dead_code)] // shared by the test and the example; each uses a part

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};
use twin::plant::dae::parse_dae;
use twin::plant::stl::parse_stl;
use twin::plant::urdf::RobotModel;
use twin::program::sandbox::Sandbox;

/// Case `n` is seeded with `SEED + n`.
pub const SEED: u64 = 0xF022_0000_0000;

/// The longest a case may take (debug build, shared cores).
pub const CASE_LIMIT: Duration = Duration::from_secs(10);

/// Values a mutation puts where a number was.
const EXTREMES: [&str; 16] = [
    "nan",
    "NaN",
    "inf",
    "-inf",
    "1e300",
    "-1e300",
    "1e-300",
    "-0",
    "0",
    "-1",
    "4294967296",
    "18446744073709551616",
    "1e-12",
    "2147483648",
    "-2147483649",
    "1e30",
];

/// Characters a mutation inserts.
const SYNTAX: &[u8] = b"<>/\"'=[]{}(),;:.#\n\\-+*& \t0123456789abcXYZ_";

/// The files the mutants start from.
pub struct Corpus {
    scenes: Vec<(PathBuf, String)>,
    routines: Vec<String>,
    /// Ladder routines: the shipped `.rll` files and [`LADDER_SAMPLE`].
    ladders: Vec<String>,
    /// The shipped Add-On Instruction exports (`scenes/aoi`).
    aois: Vec<(PathBuf, String)>,
    /// The scene that uses them (`scenes/conveyor_ladder.toml`).
    aoi_scene: String,
    urdfs: Vec<(PathBuf, String)>,
    stls: Vec<(PathBuf, Vec<u8>)>,
    dae: String,
    /// The L5X example's scene (path, text) and export.
    l5x: Vec<(PathBuf, String, String)>,
}

/// What a case fed, and how it ended badly.
#[derive(Debug)]
pub struct Failure {
    pub case: u64,
    pub target: &'static str,
    pub what: String,
}

fn files(dir: &Path, ext: &str, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    let mut entries: Vec<_> = entries.filter_map(Result::ok).map(|e| e.path()).collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            files(&p, ext, out);
        } else if p.extension().is_some_and(|e| e == ext) {
            out.push(p);
        }
    }
}

impl Corpus {
    /// The shipped scenes, routines, robots and meshes under `root/scenes`.
    pub fn load(root: &Path) -> Corpus {
        let scenes_dir = root.join("scenes");
        let read = |ext: &str| {
            let mut paths = Vec::new();
            files(&scenes_dir, ext, &mut paths);
            paths
        };
        let text = |p: &PathBuf| std::fs::read_to_string(p).expect("corpus file");
        Corpus {
            scenes: read("toml")
                .into_iter()
                .filter(|p| p.parent() == Some(scenes_dir.as_path()))
                .map(|p| {
                    let t = text(&p);
                    (p, t)
                })
                .collect(),
            routines: read("st").iter().map(text).collect(),
            ladders: read("rll")
                .iter()
                .map(text)
                .chain(std::iter::once(LADDER_SAMPLE.to_owned()))
                .collect(),
            aois: {
                let mut paths = Vec::new();
                files(&scenes_dir.join("aoi"), "L5X", &mut paths);
                paths.sort();
                paths
                    .into_iter()
                    .map(|p| {
                        let t = text(&p);
                        (p, t)
                    })
                    .collect()
            },
            aoi_scene: text(&scenes_dir.join("conveyor_ladder.toml")),
            urdfs: read("urdf")
                .into_iter()
                .map(|p| {
                    let t = text(&p);
                    (p, t)
                })
                .collect(),
            stls: read("stl")
                .into_iter()
                .map(|p| {
                    let b = std::fs::read(&p).expect("corpus file");
                    (p, b)
                })
                .collect(),
            dae: tetrahedron_dae(),
            l5x: ["scara_pick", "scara_pick_ladder"]
                .iter()
                .map(|name| {
                    let scene = scenes_dir.join(format!("l5x/{name}.toml"));
                    let scene_text = text(&scene);
                    let export = text(&scenes_dir.join(format!("l5x/{name}.L5X")));
                    (scene, scene_text, export)
                })
                .collect(),
        }
    }
}

/// The tags a ladder mutant runs with (the sample's, and the shipped
/// routines' where they share names; others are refused at load, named).
pub const LADDER_TAGS: &[(&str, &str)] = &[
    ("Start", "BOOL"),
    ("Stop", "BOOL"),
    ("Run", "BOOL"),
    ("Fault", "BOOL"),
    ("Eye", "BOOL"),
    ("T1", "TIMER"),
    ("Tmr", "TIMER[2]"),
    ("C1", "COUNTER"),
    ("R1", "CONTROL"),
    ("F1", "CONTROL"),
    ("Count", "DINT"),
    ("Idx", "DINT"),
    ("X", "REAL"),
    ("Arr", "DINT[10]"),
    ("Bits", "DINT[4]"),
    ("Fifo", "DINT[8]"),
    ("Part", "DINT"),
    ("Out", "DINT"),
    ("Mso1", "MOTION_INSTRUCTION"),
    ("Mam1", "MOTION_INSTRUCTION"),
];

/// A ladder routine that uses most of the instruction set, mutated with
/// the shipped `.rll` files.
pub const LADDER_SAMPLE: &str = "\
# Start/stop seal-in, a fault timer, a part counter.
XIC(Start)[XIC(Run) ,XIO(Stop) ]XIO(Fault) OTE(Run);
XIC(Run) XIO(Eye) TON(T1,500,0);
XIC(T1.DN) OTL(Fault);
XIC(Stop) OTU(Fault) RES(T1);
XIC(Eye) ONS(Bits[3].0) CTU(C1,10,0) ADD(Count,1,Count);
[GRT(Count,5) LES(Count,100) ,LIM(10,Count,0) ]MOV(Count,Arr[Idx]) CPT(X,SQR(Count) * 2.5 + ATN(1.0));
MEQ(Count,16#F,3) MVM(Count,16#FF00,Out) SWPB(Out,REVERSE,Out) BTD(Count,0,Out,4,8);
XIC(Eye) BSL(Bits[0],R1,Run,64);
XIC(Eye) FFL(Count,Fifo[0],F1,8,0);
XIC(Stop) FFU(Fifo[0],Part,F1,8,0);
CMP(Count MOD 7 = 0 AND X > 1.5) OSR(Bits[3].1,Bits[3].2) COP(Arr[0],Fifo[0],4);
XIC(Run) MSO(Conv,Mso1);
XIC(Mso1.DN) XIC(Run) MAM(Conv,Mam1,1,10,50,Units per sec,100,Units per sec2,100,Units per sec2,Trapezoidal,100,100,% of Time,Disabled,0,0,None,0,0);
XIO(Run) TND();
LBL(Tail) ADD(Idx,1,Idx) GEQ(Idx,10) CLR(Idx);
";

/// A small COLLADA document (mesh-loader's reader is fuzzed through it).
fn tetrahedron_dae() -> String {
    "<?xml version=\"1.0\" encoding=\"utf-8\"?>\n<COLLADA xmlns=\"http://www.collada.org/2005/11/COLLADASchema\" version=\"1.4.1\">\n\
     <asset><unit meter=\"0.001\"/><up_axis>Z_UP</up_axis></asset>\n<library_geometries>\n\
     <geometry id=\"g0\"><mesh><source id=\"g0-pos\"><float_array id=\"g0-arr\" count=\"12\">0 0 0 1 0 0 0 1 0 0 0 1</float_array>\n\
     <technique_common><accessor source=\"#g0-arr\" count=\"4\" stride=\"3\"><param name=\"X\" type=\"float\"/>\
     <param name=\"Y\" type=\"float\"/><param name=\"Z\" type=\"float\"/></accessor></technique_common></source>\n\
     <vertices id=\"g0-vtx\"><input semantic=\"POSITION\" source=\"#g0-pos\"/></vertices>\n\
     <triangles count=\"4\"><input semantic=\"VERTEX\" source=\"#g0-vtx\" offset=\"0\"/><p>0 2 1 0 1 3 0 3 2 1 2 3</p></triangles>\n\
     </mesh></geometry>\n</library_geometries>\n<library_visual_scenes><visual_scene id=\"scene\">\n\
     <node id=\"n0\"><translate>0 0 0</translate><instance_geometry url=\"#g0\"/></node>\n\
     </visual_scene></library_visual_scenes>\n<scene><instance_visual_scene url=\"#scene\"/></scene>\n</COLLADA>\n"
        .to_owned()
}

/// Byte ranges of the number-like tokens of `text`.
fn numbers(text: &str) -> Vec<(usize, usize)> {
    let b = text.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        let starts = b[i].is_ascii_digit() || (b[i] == b'-' && b.get(i + 1).is_some_and(u8::is_ascii_digit));
        let inside_word = i > 0 && (b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_');
        if starts && !inside_word {
            let start = i;
            i += 1;
            while i < b.len() && (b[i].is_ascii_alphanumeric() || matches!(b[i], b'.' | b'-' | b'+' | b'_' | b'#')) {
                i += 1;
            }
            out.push((start, i));
        } else {
            i += 1;
        }
    }
    out
}

/// A char boundary at or before `i`.
fn boundary(text: &str, mut i: usize) -> usize {
    i = i.min(text.len());
    while !text.is_char_boundary(i) {
        i -= 1;
    }
    i
}

/// `text` with one to three mutations (module doc).
pub fn mutate_text(rng: &mut ChaCha8Rng, text: &str) -> String {
    let mut t = text.to_owned();
    for _ in 0..rng.random_range(1..=3) {
        let lines: Vec<&str> = t.split('\n').collect();
        t = match rng.random_range(0..9) {
            0..=2 => {
                let spans = numbers(&t);
                if spans.is_empty() {
                    t
                } else {
                    let (a, b) = spans[rng.random_range(0..spans.len())];
                    let v = EXTREMES[rng.random_range(0..EXTREMES.len())];
                    format!("{}{v}{}", &t[..a], &t[b..])
                }
            }
            3 => {
                let k = rng.random_range(0..lines.len());
                lines
                    .iter()
                    .enumerate()
                    .filter(|(i, _)| *i != k)
                    .map(|(_, l)| *l)
                    .collect::<Vec<_>>()
                    .join("\n")
            }
            4 => {
                let k = rng.random_range(0..lines.len());
                let mut l = lines.clone();
                l.insert(k, lines[k]);
                l.join("\n")
            }
            5 => {
                let (a, b) = (rng.random_range(0..lines.len()), rng.random_range(0..lines.len()));
                let mut l = lines.clone();
                l.swap(a, b);
                l.join("\n")
            }
            6 => {
                let at = boundary(&t, rng.random_range(0..=t.len()));
                let c = SYNTAX[rng.random_range(0..SYNTAX.len())] as char;
                format!("{}{c}{}", &t[..at], &t[at..])
            }
            7 => {
                let a = boundary(&t, rng.random_range(0..=t.len()));
                let b = boundary(&t, (a + rng.random_range(1..40)).min(t.len()));
                let times = if rng.random_bool(0.5) {
                    rng.random_range(2..10)
                } else {
                    rng.random_range(100..2000)
                };
                format!("{}{}{}", &t[..a], t[a..b].repeat(times), &t[b..])
            }
            _ => {
                let at = boundary(&t, rng.random_range(0..=t.len()));
                t[..at].to_owned()
            }
        };
    }
    t
}

/// `bytes` of a binary STL with one to three mutations.
fn mutate_bytes(rng: &mut ChaCha8Rng, bytes: &[u8]) -> Vec<u8> {
    let mut b = bytes.to_vec();
    for _ in 0..rng.random_range(1..=3) {
        if b.is_empty() {
            break;
        }
        match rng.random_range(0..5) {
            0 => {
                let i = rng.random_range(0..b.len());
                b[i] ^= 1 << rng.random_range(0..8);
            }
            1 => b.truncate(rng.random_range(0..b.len())),
            2 => {
                let i = rng.random_range(0..b.len());
                let v = [f32::NAN, f32::INFINITY, -f32::INFINITY, f32::MAX, 1e-45][rng.random_range(0..5)];
                for (k, byte) in v.to_le_bytes().into_iter().enumerate() {
                    if let Some(slot) = b.get_mut(i + k) {
                        *slot = byte;
                    }
                }
            }
            3 if b.len() >= 84 => {
                let n: u32 = [0, 1, u32::MAX, 0x8000_0000, rng.random()][rng.random_range(0..5)];
                b[80..84].copy_from_slice(&n.to_le_bytes());
            }
            _ => {
                let i = rng.random_range(0..=b.len());
                let junk: Vec<u8> = (0..rng.random_range(1..60)).map(|_| rng.random()).collect();
                b.splice(i..i, junk);
            }
        }
    }
    b
}

fn panic_text(payload: &(dyn std::any::Any + Send)) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| (*s).to_owned())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "a panic".to_owned())
}

/// Runs case `n`; `Err` describes how it failed (module doc).
pub fn run_case(corpus: &Corpus, root: &Path, n: u64) -> Result<(), Failure> {
    let mut rng = ChaCha8Rng::seed_from_u64(SEED + n);
    let pick = rng.random_range(0..100);
    // Every tenth case mutates the L5X export.
    let target = match pick {
        _ if n.is_multiple_of(10) => "l5x",
        0..32 => "scene",
        32..40 => "aoi",
        40..50 => "routine",
        50..62 => "ladder",
        62..80 => "urdf",
        80..92 => "stl",
        _ => "dae",
    };
    if std::env::var_os("FUZZ_VERBOSE").is_some() {
        eprintln!("case {n}: {target}");
    }
    let started = Instant::now();
    let outcome = catch_unwind(AssertUnwindSafe(|| -> Result<(), String> {
        match target {
            "aoi" => {
                let (original, text) = &corpus.aois[rng.random_range(0..corpus.aois.len())];
                let mutant = mutate_text(&mut rng, text);
                let (path, scene_text) = aoi_scene(corpus, root, Some((original, &mutant)))?;
                match twin::scene::parse(&path, &scene_text) {
                    Err(e) => named_in_scene(&e.to_string()),
                    Ok(scene) if n.is_multiple_of(50) => run_briefly(scene, &named_in_scene),
                    Ok(_) => Ok(()),
                }
            }
            "scene" => {
                let (original, text) = &corpus.scenes[rng.random_range(0..corpus.scenes.len())];
                let mutant = mutate_text(&mut rng, text);
                // Beside the original, so relative references resolve.
                let path = original.with_file_name("fuzz_case.toml");
                match twin::scene::parse(&path, &mutant) {
                    Err(e) => named_in_scene(&e.to_string()),
                    Ok(scene) if n.is_multiple_of(25) => run_briefly(scene, &named_in_scene),
                    Ok(_) => Ok(()),
                }
            }
            "l5x" => {
                let (scene, text, export) = &corpus.l5x[(n / 10) as usize % corpus.l5x.len()];
                let mutant = mutate_text(&mut rng, export);
                let file = |ext: &str| {
                    scene
                        .with_extension(ext)
                        .file_name()
                        .unwrap()
                        .to_string_lossy()
                        .into_owned()
                };
                let (l5x, toml) = (file("L5X"), file("toml"));
                let in_either = |m: &str| named(m, &l5x).or_else(|_| named(m, &toml));
                match twin::scene::parse_with_l5x(scene, text, Some(&mutant)) {
                    Err(e) => in_either(&e.to_string()),
                    Ok(scene) if n.is_multiple_of(50) => run_briefly(scene, &in_either),
                    Ok(_) => Ok(()),
                }
            }
            "routine" => {
                let text = &corpus.routines[rng.random_range(0..corpus.routines.len())];
                let mutant = mutate_text(&mut rng, text);
                let tags = [
                    ("State", "DINT"),
                    ("Count", "DINT"),
                    ("X", "REAL"),
                    ("Y", "REAL"),
                    ("Arr", "REAL[10]"),
                    ("Flag", "BOOL"),
                    ("T1", "FBD_TIMER"),
                ];
                scanned(Sandbox::new(&tags, &mutant), "Main.st:")
            }
            "ladder" => {
                let text = &corpus.ladders[rng.random_range(0..corpus.ladders.len())];
                let mutant = mutate_text(&mut rng, text);
                scanned(Sandbox::ladder(&["Conv"], LADDER_TAGS, &mutant), "Main.rll:")
            }
            "urdf" => {
                let (path, text) = &corpus.urdfs[rng.random_range(0..corpus.urdfs.len())];
                let mutant = mutate_text(&mut rng, text);
                match RobotModel::from_urdf_str(&mutant, path) {
                    Ok(_) => Ok(()),
                    Err(e) => {
                        let m = e.to_string();
                        let name = path
                            .file_name()
                            .map(|f| f.to_string_lossy().into_owned())
                            .unwrap_or_default();
                        let structural = ["link ", "joint ", "URDF "].iter().any(|p| m.starts_with(p));
                        if m.contains(&name) || structural {
                            Ok(())
                        } else {
                            Err(format!("a URDF error naming neither its file nor a link or joint: {m}"))
                        }
                    }
                }
            }
            "stl" => {
                let (path, bytes) = &corpus.stls[rng.random_range(0..corpus.stls.len())];
                let mutant = mutate_bytes(&mut rng, bytes);
                match parse_stl(&mutant, path) {
                    Ok(_) => Ok(()),
                    Err(e) => named(&e.to_string(), &path.file_name().unwrap_or_default().to_string_lossy()),
                }
            }
            _ => {
                let mutant = mutate_text(&mut rng, &corpus.dae);
                match parse_dae(mutant.as_bytes(), &root.join("fuzz_case.dae")) {
                    Ok(_) => Ok(()),
                    Err(e) => named(&e.to_string(), "fuzz_case.dae"),
                }
            }
        }
    }));
    let what = match outcome {
        Ok(Ok(())) => None,
        Ok(Err(e)) => Some(e),
        Err(payload) => {
            let place = LAST_PANIC.with(|p| p.borrow_mut().take()).unwrap_or_default();
            Some(format!("panicked: {}{place}", panic_text(payload.as_ref())))
        }
    }
    .or_else(|| {
        let took = started.elapsed();
        (took > CASE_LIMIT).then(|| format!("took {took:?}"))
    });
    match what {
        None => Ok(()),
        Some(what) => Err(Failure { case: n, target, what }),
    }
}

/// A scene that loaded, built and run for 25 updates of at most 0.1 s;
/// an error building it must satisfy `named`.
fn run_briefly(mut scene: twin::scene::Scene, named: &dyn Fn(&str) -> Result<(), String>) -> Result<(), String> {
    scene.duration_s = scene.duration_s.min(0.1);
    match twin::run::Twin::new(scene) {
        Err(e) => named(&e.to_string()),
        Ok(mut t) => {
            for _ in 0..25 {
                t.step();
            }
            Ok(())
        }
    }
}

/// A sandbox that compiled scans five times; one that did not names its
/// routine's `file:line:column` (an undeclared type is the sandbox's own
/// refusal).
fn scanned(sandbox: Result<Sandbox, String>, file: &str) -> Result<(), String> {
    match sandbox {
        Ok(mut s) => {
            for _ in 0..5 {
                s.scan();
            }
            Ok(())
        }
        Err(e) => {
            let placed = e
                .strip_prefix(file)
                .and_then(|rest| rest.split_once(':'))
                .and_then(|(l, rest)| Some((l.parse::<usize>().ok()?, rest.split_once(':')?.0.parse::<usize>().ok()?)))
                .is_some();
            if placed || e.starts_with("unknown type") {
                Ok(())
            } else {
                Err(format!("a routine error without its line:column: {e}"))
            }
        }
    }
}

/// A scene's error names the scene or the file it refers to that is wrong
/// (a routine, the URDF, a mesh).
fn named_in_scene(message: &str) -> Result<(), String> {
    let files = ["fuzz_case.toml", ".st:", ".rll:", ".L5X:", ".urdf", ".stl", ".dae"];
    if files.iter().any(|f| message.contains(f)) {
        Ok(())
    } else {
        Err(format!(
            "an error naming neither the scene nor a file it refers to: {message}"
        ))
    }
}

fn named(message: &str, file: &str) -> Result<(), String> {
    if message.contains(file) {
        Ok(())
    } else {
        Err(format!("an error not naming {file}: {message}"))
    }
}

/// Runs `cases`; returns the failures. Callers silence the panic hook
/// first ([`silence_panics`]): each failure keeps its own message.
pub fn run_cases(corpus: &Corpus, root: &Path, cases: std::ops::Range<u64>) -> Vec<Failure> {
    cases.filter_map(|n| run_case(corpus, root, n).err()).collect()
}

/// Panics caught by a case print nothing (the failure carries the
/// message); the hook that printed them, to put back before reporting.
pub fn silence_panics() -> Box<dyn Fn(&std::panic::PanicHookInfo<'_>) + Sync + Send + 'static> {
    let hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(|info| {
        let place = info
            .location()
            .map(|l| format!(" at {}:{}", l.file(), l.line()))
            .unwrap_or_default();
        LAST_PANIC.with(|p| *p.borrow_mut() = Some(place));
    }));
    hook
}

thread_local! {
    /// Where the last panic on this thread happened.
    static LAST_PANIC: std::cell::RefCell<Option<String>> = const { std::cell::RefCell::new(None) };
}

/// The ladder conveyor scene (path, text) with its Add-On Instruction
/// exports in a folder of this thread's own, one of them replaced by
/// `mutant` (its original's path, its text).
pub fn aoi_scene(corpus: &Corpus, root: &Path, mutant: Option<(&PathBuf, &str)>) -> Result<(PathBuf, String), String> {
    let dir = root
        .join("target/fuzz-aoi")
        .join(format!("{:?}", std::thread::current().id()).replace(['(', ')'], ""));
    std::fs::create_dir_all(dir.join("aoi")).map_err(|e| e.to_string())?;
    for (p, t) in &corpus.aois {
        let name = p.file_name().unwrap_or_default();
        let text = match mutant {
            Some((original, m)) if original == p => m,
            _ => t.as_str(),
        };
        std::fs::write(dir.join("aoi").join(name), text).map_err(|e| e.to_string())?;
    }
    // Its robot and routine where they are: paths from `scenes/`.
    let scenes = root.join("scenes");
    let from_scenes = |sub: &str| format!("\"{}/", scenes.join(sub).display());
    let text = corpus
        .aoi_scene
        .replace("\"robots/", &from_scenes("robots"))
        .replace("\"routines/", &from_scenes("routines"));
    Ok((dir.join("fuzz_case.toml"), text))
}

/// The text mutant of case `n` and the file it came from (STL cases:
/// `None`), for reproducing a failure by hand.
pub fn mutant_of(corpus: &Corpus, n: u64) -> Option<(PathBuf, String)> {
    let mut rng = ChaCha8Rng::seed_from_u64(SEED + n);
    let pick: i32 = rng.random_range(0..100);
    match pick {
        _ if n.is_multiple_of(10) => {
            let (scene, _, export) = &corpus.l5x[(n / 10) as usize % corpus.l5x.len()];
            Some((scene.with_extension("L5X"), mutate_text(&mut rng, export)))
        }
        32..40 => {
            let (p, t) = &corpus.aois[rng.random_range(0..corpus.aois.len())];
            Some((p.clone(), mutate_text(&mut rng, t)))
        }
        0..32 => {
            let (p, t) = &corpus.scenes[rng.random_range(0..corpus.scenes.len())];
            Some((p.clone(), mutate_text(&mut rng, t)))
        }
        40..50 => {
            let t = &corpus.routines[rng.random_range(0..corpus.routines.len())];
            Some((PathBuf::from("routine.st"), mutate_text(&mut rng, t)))
        }
        50..62 => {
            let t = &corpus.ladders[rng.random_range(0..corpus.ladders.len())];
            Some((PathBuf::from("Main.rll"), mutate_text(&mut rng, t)))
        }
        62..80 => {
            let (p, t) = &corpus.urdfs[rng.random_range(0..corpus.urdfs.len())];
            Some((p.clone(), mutate_text(&mut rng, t)))
        }
        80..92 => None,
        _ => Some((PathBuf::from("fuzz_case.dae"), mutate_text(&mut rng, &corpus.dae))),
    }
}
