//! Add-On Instructions (1756-PM010) in ladder and Structured Text: Input
//! and Output copies, InOut by reference, Required and Constant
//! parameters, the EnableInFalse and Prescan routines, a fault inside an
//! instruction, nesting and recursion, motion on an InOut axis, and the
//! verifier's errors. Each test writes AOI exports and a scene of the
//! indexing table with one 4 ms task, binds it to a planner and scans.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use twin::program::Program;
use twin::program::types::Value;

mod common;

/// A parameter: name, data type, usage, required, constant, default.
type Param<'a> = (&'a str, &'a str, &'a str, bool, bool, Option<&'a str>);

/// An AOI definition element.
struct Aoi<'a> {
    name: &'a str,
    params: &'a [Param<'a>],
    /// Local tags: name, data type, dimensions.
    locals: &'a [(&'a str, &'a str, u32)],
    /// Routines: name, `RLL` or `ST`, lines (rungs or ST lines).
    routines: &'a [(&'a str, &'a str, &'a [&'a str])],
    prescan: bool,
    enable_in_false: bool,
}

fn definition(a: &Aoi<'_>) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "<AddOnInstructionDefinition Name=\"{}\" Revision=\"1.0\" ExecutePrescan=\"{}\" ExecutePostscan=\"false\" ExecuteEnableInFalse=\"{}\">",
        a.name, a.prescan, a.enable_in_false
    );
    s.push_str("<Parameters>\n<Parameter Name=\"EnableIn\" TagType=\"Base\" DataType=\"BOOL\" Usage=\"Input\" Required=\"false\" Visible=\"false\"/>\n<Parameter Name=\"EnableOut\" TagType=\"Base\" DataType=\"BOOL\" Usage=\"Output\" Required=\"false\" Visible=\"false\"/>\n");
    for (name, ty, usage, required, constant, default) in a.params {
        let (ty, dims) = match ty.split_once('[') {
            Some((t, d)) => (t, format!(" Dimensions=\"{}\"", d.trim_end_matches(']'))),
            None => (*ty, String::new()),
        };
        let _ = write!(
            s,
            "<Parameter Name=\"{name}\" TagType=\"Base\" DataType=\"{ty}\"{dims} Usage=\"{usage}\" Required=\"{required}\" Visible=\"true\" Constant=\"{constant}\""
        );
        match default {
            Some(v) => {
                let _ = writeln!(
                    s,
                    ">\n<DefaultData Format=\"L5K\">\n<![CDATA[{v}]]>\n</DefaultData>\n</Parameter>"
                );
            }
            None => s.push_str("/>\n"),
        }
    }
    s.push_str("</Parameters>\n<LocalTags>\n");
    for (name, ty, dims) in a.locals {
        let dims = if *dims > 0 {
            format!(" Dimensions=\"{dims}\"")
        } else {
            String::new()
        };
        let _ = writeln!(
            s,
            "<LocalTag Name=\"{name}\" DataType=\"{ty}\"{dims} ExternalAccess=\"None\"/>"
        );
    }
    s.push_str("</LocalTags>\n<Routines>\n");
    for (name, kind, lines) in a.routines {
        let _ = writeln!(s, "<Routine Name=\"{name}\" Type=\"{kind}\">");
        if *kind == "RLL" {
            s.push_str("<RLLContent>\n");
            for (k, l) in lines.iter().enumerate() {
                let _ = writeln!(
                    s,
                    "<Rung Number=\"{k}\" Type=\"N\">\n<Text>\n<![CDATA[{l}]]>\n</Text>\n</Rung>"
                );
            }
            s.push_str("</RLLContent>\n");
        } else {
            s.push_str("<STContent>\n");
            for (k, l) in lines.iter().enumerate() {
                let _ = writeln!(s, "<Line Number=\"{k}\">\n<![CDATA[{l}]]>\n</Line>");
            }
            s.push_str("</STContent>\n");
        }
        s.push_str("</Routine>\n");
    }
    s.push_str("</Routines>\n</AddOnInstructionDefinition>\n");
    s
}

fn export(defs: &[Aoi<'_>]) -> String {
    let body: String = defs.iter().map(definition).collect();
    format!(
        "<?xml version=\"1.0\" encoding=\"UTF-8\" standalone=\"yes\"?>\n<RSLogix5000Content SchemaRevision=\"1.0\" TargetName=\"{}\" TargetType=\"AddOnInstructionDefinition\" ContainsContext=\"true\">\n<Controller Use=\"Context\" Name=\"C\">\n<AddOnInstructionDefinitions Use=\"Context\">\n{body}</AddOnInstructionDefinitions>\n</Controller>\n</RSLogix5000Content>\n",
        defs[0].name
    )
}

/// A scene in `target/aoi-tests/<name>/` naming `exports` (file, text),
/// with `tags` and a program whose main routine is `main` (`Main.rll` or
/// `Main.st`) and `others`.
fn scene(
    name: &str,
    exports: &[(&str, String)],
    tags: &[(&str, &str)],
    routines: &[(&str, &str)],
    extra: &str,
) -> PathBuf {
    let dir = common::fresh_dir("aoi-tests", name);
    for (file, text) in exports {
        std::fs::write(dir.join(file), text).unwrap();
    }
    for (file, text) in routines {
        std::fs::write(dir.join(file), text).unwrap();
    }
    let list: Vec<String> = exports.iter().map(|(f, _)| format!("\"{f}\"")).collect();
    let tags: String = tags
        .iter()
        .map(|(n, t)| format!("[[tags]]\nname = \"{n}\"\ntype = \"{t}\"\n"))
        .collect();
    let others: Vec<String> = routines[1..].iter().map(|(f, _)| format!("\"{f}\"")).collect();
    let text = format!(
        "add_on_instructions = [{}]\n{}{tags}[[tasks]]\nname = \"T\"\nperiod_ms = 4.0\npriority = 5\n[[tasks.programs]]\nname = \"P\"\nmain = \"{}\"\nroutines = [{}]\n{extra}\n",
        list.join(", "),
        common::indexing_table_head(),
        routines[0].0,
        others.join(", ")
    );
    let path = dir.join("scene.toml");
    std::fs::write(&path, text).unwrap();
    path
}

struct Run {
    program: Program,
    task: planner::task::MotionTask,
}

impl Run {
    fn load(path: &Path) -> Result<Run, String> {
        let scene = twin::scene::load(path).map_err(|e| e.to_string())?;
        let mut task = planner::task::MotionTask::new(scene.coarse_update_s()).map_err(|e| e.to_string())?;
        for a in &scene.axes {
            task.add_axis(a.config.clone(), 0.0).map_err(|e| e.to_string())?;
        }
        let program = Program::bind(&scene, &mut task).map_err(|e| e.to_string())?;
        Ok(Run { program, task })
    }

    fn scans(&mut self, n: usize) -> &mut Self {
        for _ in 0..n {
            self.program.scan(&mut self.task);
            self.task.update();
        }
        self
    }

    /// `Tag`, `Tag[i]`, `Tag.Member`, `Tag[i].Member.Member` …
    fn value(&self, name: &str) -> Value {
        let mem = self.program.controller().memory();
        let mut parts = name.split('.');
        let tag = parts.next().unwrap();
        let (base, index) = match tag.split_once('[') {
            Some((b, i)) => (b, i.trim_end_matches(']').parse::<usize>().unwrap()),
            None => (tag, 0),
        };
        let k = mem.find(base).unwrap_or_else(|| panic!("no tag {base}"));
        let info = &mem.tags[k];
        let mut slot = info.base + index * info.stride();
        let mut kind = info.kind;
        for m in parts {
            let twin::program::memory::Kind::User(id) = kind else {
                panic!("{name}: {m} of a non-structure")
            };
            let member = mem
                .layouts
                .get(id)
                .member(m)
                .unwrap_or_else(|| panic!("{name}: no member {m}"));
            slot += member.slot;
            kind = match member.elem {
                twin::program::layout::Elem::User(inner) => twin::program::memory::Kind::User(inner),
                _ => twin::program::memory::Kind::Axis,
            };
        }
        mem.slots[slot]
    }

    fn f(&self, name: &str) -> f64 {
        self.value(name).as_f64()
    }
}

fn load(path: &Path) -> Run {
    Run::load(path).unwrap_or_else(|e| panic!("{e}"))
}

fn refused(path: &Path) -> String {
    match Run::load(path) {
        Ok(_) => panic!("{} was accepted", path.display()),
        Err(e) => e,
    }
}

const SCALE: Aoi<'static> = Aoi {
    name: "Scale",
    params: &[
        ("In", "REAL", "Input", true, false, None),
        ("Gain", "REAL", "Input", false, false, Some("2.0")),
        ("Out", "REAL", "Output", true, false, None),
    ],
    locals: &[("Calls", "DINT", 0)],
    routines: &[("Logic", "ST", &["Out := In * Gain;", "Calls := Calls + 1;"])],
    prescan: false,
    enable_in_false: false,
};

#[test]
fn inputs_are_copied_in_and_outputs_out_and_other_parameters_are_members() {
    let tags = &[
        ("S1", "Scale"),
        ("S2", "Scale"),
        ("X", "REAL"),
        ("Y", "REAL"),
        ("Z", "REAL"),
    ];
    // Ladder and Structured Text calls of one instruction.
    let main = "Scale(S1,X,Y);\nMOV(3.0,S2.Gain) JSR(Sub,0);\n";
    let sub = "Scale(S2, X * 2.0, Z);\n";
    let path = scene(
        "copies",
        &[("Scale.L5X", export(&[SCALE]))],
        tags,
        &[("Main.rll", main), ("Sub.st", sub)],
        "[[tags]]\nname = \"X0\"\ntype = \"REAL\"\nvalue = 1.5\n",
    );
    let mut run = load(&path);
    assert_eq!(run.f("S1.Gain"), 2.0, "the parameter's default");
    run.program.memory_mut();
    run.scans(1);
    assert_eq!(run.f("Y"), 0.0);
    // X is an Input: the instance takes the argument's value at each call.
    let mem = run.program.memory_mut();
    let k = mem.find("X").unwrap();
    let slot = mem.tags[k].base;
    mem.slots[slot] = Value::Real(1.5);
    run.scans(1);
    assert_eq!(run.f("S1.In"), 1.5);
    assert_eq!(run.f("Y"), 3.0, "Out = In × Gain (2, the default)");
    assert_eq!(run.f("Z"), 9.0, "Gain 3 set as a member; In = X × 2");
    assert_eq!(run.value("S1.Calls").as_i64(), 2);
    assert!(run.value("S1.EnableOut").truthy());
}

#[test]
fn an_inout_is_the_callers_tag_and_a_false_rung_runs_enable_in_false() {
    let bump = Aoi {
        name: "Bump",
        params: &[
            ("Count", "DINT", "InOut", true, false, None),
            ("Step", "DINT", "Input", true, false, None),
            ("Idle", "BOOL", "Output", false, false, None),
        ],
        locals: &[],
        routines: &[
            ("Logic", "RLL", &["ADD(Count,Step,Count) OTU(Idle);"]),
            ("EnableInFalse", "RLL", &["OTL(Idle);"]),
        ],
        prescan: false,
        enable_in_false: true,
    };
    let tags = &[
        ("B1", "Bump"),
        ("B2", "Bump"),
        ("A", "DINT"),
        ("C", "DINT"),
        ("Go", "BOOL"),
        ("Out", "BOOL"),
    ];
    let main = "XIC(Go) Bump(B1,A,1) OTE(Out);\nBump(B2,C,10);\n";
    let path = scene(
        "inout",
        &[("Bump.L5X", export(&[bump]))],
        tags,
        &[("Main.rll", main)],
        "",
    );
    let mut run = load(&path);
    run.scans(3);
    assert_eq!(run.value("A").as_i64(), 0, "a FALSE rung: Logic does not run");
    assert!(run.value("B1.Idle").truthy(), "EnableInFalse ran");
    assert!(!run.value("B1.EnableOut").truthy() && !run.value("Out").truthy());
    assert_eq!(run.value("C").as_i64(), 30, "the caller's tag, by reference");
    let mem = run.program.memory_mut();
    let k = mem.find("Go").unwrap();
    let slot = mem.tags[k].base;
    mem.slots[slot] = Value::Bool(true);
    run.scans(2);
    assert_eq!(run.value("A").as_i64(), 2);
    assert!(!run.value("B1.Idle").truthy());
    assert!(run.value("Out").truthy(), "the rung goes on with EnableOut");
}

#[test]
fn the_prescan_routine_runs_once_at_prescan_for_each_call() {
    let init = Aoi {
        name: "Init",
        params: &[("Seed", "DINT", "Output", false, false, None)],
        locals: &[("Runs", "DINT", 0)],
        routines: &[
            ("Logic", "ST", &["Runs := Runs + 1;"]),
            ("Prescan", "ST", &["Seed := 42;", "Runs := 0;"]),
        ],
        prescan: true,
        enable_in_false: false,
    };
    let tags = &[("I1", "Init"), ("Never", "BOOL")];
    let path = scene(
        "prescan",
        &[("Init.L5X", export(&[init]))],
        tags,
        &[("Main.rll", "XIC(Never) Init(I1);\n")],
        "",
    );
    let mut run = load(&path);
    run.scans(2);
    assert_eq!(
        run.value("I1.Seed").as_i64(),
        42,
        "Prescan ran though the rung was never TRUE"
    );
    assert_eq!(run.value("I1.Runs").as_i64(), 0);
}

#[test]
fn a_fault_inside_an_instruction_cancels_the_rest_of_it_and_the_scan_goes_on_after_the_call() {
    let poke = Aoi {
        name: "Poke",
        params: &[
            ("Arr", "DINT[4]", "InOut", true, false, None),
            ("Idx", "DINT", "Input", true, false, None),
            ("Done", "BOOL", "Output", false, false, None),
        ],
        locals: &[],
        routines: &[("Logic", "RLL", &["MOV(7,Arr[Idx]) OTL(Done);"])],
        prescan: false,
        enable_in_false: false,
    };
    let fault = "GSV(PROGRAM, THIS, MajorFaultRecord, Record[0]);\nRecord[2] := 0;\nSSV(PROGRAM, THIS, MajorFaultRecord, Record[0]);\nHandled := Handled + 1;\n";
    let tags = &[
        ("P1", "Poke"),
        ("Arr", "DINT[4]"),
        ("Idx", "DINT"),
        ("After", "BOOL"),
        ("Record", "DINT[11]"),
        ("Handled", "DINT"),
    ];
    let main = "Poke(P1,Arr,Idx) OTE(After);\n";
    let extra = "fault_routine = \"Fault\"\n[[tags]]\nname = \"Nine\"\ntype = \"DINT\"\nvalue = 9\n";
    let main = main.replace("Arr,Idx", "Arr,Nine");
    let path = scene(
        "fault",
        &[("Poke.L5X", export(&[poke]))],
        tags,
        &[("Main.rll", &main), ("Fault.st", fault)],
        extra,
    );
    let mut run = load(&path);
    run.scans(1);
    let c = run.program.controller();
    assert!(c.major_fault().is_none(), "{:?}", c.major_fault());
    let cleared = c.cleared_faults();
    assert_eq!((cleared[0].fault_type, cleared[0].code), (4, 20));
    assert!(cleared[0].routine.ends_with("Poke.L5X"), "{:?}", cleared[0].routine);
    assert_eq!(run.value("Handled").as_i64(), 1);
    assert!(
        !run.value("P1.Done").truthy(),
        "the rest of the instruction was cancelled"
    );
    assert!(run.value("After").truthy(), "the scan went on after the call");
}

#[test]
fn instructions_nest_and_a_motion_instruction_runs_on_an_inout_axis() {
    let move_to = Aoi {
        name: "MoveTo",
        params: &[
            ("Axis", "AXIS_CIP_DRIVE", "InOut", true, false, None),
            ("Ctl", "MOTION_INSTRUCTION", "InOut", true, false, None),
            ("Pos", "REAL", "Input", true, false, None),
        ],
        locals: &[],
        routines: &[(
            "Logic",
            "RLL",
            &[
                "MAM(Axis,Ctl,0,Pos,360,Units per sec,3600,Units per sec2,3600,Units per sec2,Trapezoidal,100,100,% of Time,Disabled,0,0,None,0,0);",
            ],
        )],
        prescan: false,
        enable_in_false: false,
    };
    // Station wraps MoveTo: two levels.
    let station = Aoi {
        name: "Station",
        params: &[
            ("Axis", "AXIS_CIP_DRIVE", "InOut", true, false, None),
            ("Ctl", "MOTION_INSTRUCTION", "InOut", true, false, None),
        ],
        locals: &[("Inner", "MoveTo", 0)],
        routines: &[("Logic", "RLL", &["MoveTo(Inner,Axis,Ctl,90.0);"])],
        prescan: false,
        enable_in_false: false,
    };
    let tags = &[
        ("St", "Station"),
        ("Mso1", "MOTION_INSTRUCTION"),
        ("Mam1", "MOTION_INSTRUCTION"),
        ("Pos", "REAL"),
    ];
    let main = "MSO(Table,Mso1);\nXIC(Mso1.DN) Station(St,Table,Mam1);\nMOV(Table.CommandPosition,Pos);\n";
    let path = scene(
        "motion",
        &[("MoveTo.L5X", export(&[move_to, station]))],
        tags,
        &[("Main.rll", main)],
        "",
    );
    let mut run = load(&path);
    run.scans(200);
    assert!((run.f("Pos") - 90.0).abs() < 1e-6, "{}", run.f("Pos"));
}

#[test]
fn the_verifier_refuses_what_studio_refuses() {
    let tags = &[("S1", "Scale"), ("X", "REAL"), ("Y", "REAL"), ("N", "DINT")];
    let write = |name: &str, main: &str, aois: &[Aoi<'_>]| {
        scene(name, &[("A.L5X", export(aois))], tags, &[("Main.rll", main)], "")
    };
    let e = refused(&write("missing", "Scale(S1,X);\n", &[SCALE]));
    assert!(e.contains("Scale is missing its required parameter(s) Out"), "{e}");
    let e = refused(&write("question", "Scale(S1,X,?);\n", &[SCALE]));
    assert!(e.contains("required parameter Out is '?'"), "{e}");
    let e = refused(&write("instance", "Scale(X,X,Y);\n", &[SCALE]));
    assert!(e.contains("Scale's instance must be a Scale tag"), "{e}");
    let constant = Aoi {
        name: "Clamp",
        params: &[("V", "DINT", "InOut", true, true, None)],
        locals: &[],
        routines: &[("Logic", "RLL", &["GRT(V,10) MOV(10,V);"])],
        prescan: false,
        enable_in_false: false,
    };
    let tags2 = &[("C1", "Clamp"), ("N", "DINT"), ("X", "REAL")];
    let path = scene(
        "constant",
        &[("A.L5X", export(&[constant]))],
        tags2,
        &[("Main.rll", "Clamp(C1,N);\n")],
        "",
    );
    let e = refused(&path);
    assert!(e.contains("V is a constant InOut parameter"), "{e}");
    let wrong = Aoi {
        name: "Clamp",
        params: &[("V", "DINT", "InOut", true, false, None)],
        locals: &[],
        routines: &[("Logic", "RLL", &["NOP();"])],
        prescan: false,
        enable_in_false: false,
    };
    let path = scene(
        "type",
        &[("A.L5X", export(&[wrong]))],
        tags2,
        &[("Main.rll", "Clamp(C1,X);\n")],
        "",
    );
    let e = refused(&path);
    assert!(e.contains("Clamp.V is DINT, got X (REAL)"), "{e}");
    let jsr = Aoi {
        name: "Jumps",
        params: &[],
        locals: &[],
        routines: &[("Logic", "RLL", &["JSR(Main,0);"])],
        prescan: false,
        enable_in_false: false,
    };
    let path = scene(
        "jsr",
        &[("A.L5X", export(&[jsr]))],
        &[("J1", "Jumps")],
        &[("Main.rll", "Jumps(J1);\n")],
        "",
    );
    let e = refused(&path);
    assert!(
        e.contains("Jumps/Logic rung 0: Add-On Instruction Jumps: JSR is not allowed inside an instruction"),
        "{e}"
    );
    let global = Aoi {
        name: "Peek",
        params: &[],
        locals: &[],
        routines: &[("Logic", "ST", &["N := 1;"])],
        prescan: false,
        enable_in_false: false,
    };
    let path = scene(
        "global",
        &[("A.L5X", export(&[global]))],
        &[("P1", "Peek"), ("N", "DINT")],
        &[("Main.rll", "Peek(P1);\n")],
        "",
    );
    let e = refused(&path);
    assert!(
        e.contains("Peek/Logic: Add-On Instruction Peek: 'N' is none of its parameters and local tags"),
        "{e}"
    );
    // An instruction's name.
    let mov = Aoi {
        name: "MOV",
        params: &[],
        locals: &[],
        routines: &[("Logic", "RLL", &["NOP();"])],
        prescan: false,
        enable_in_false: false,
    };
    let path = scene(
        "taken",
        &[("A.L5X", export(&[mov]))],
        &[("N", "DINT")],
        &[("Main.rll", "NOP();\n")],
        "",
    );
    assert!(refused(&path).contains("Add-On Instruction MOV: the name is taken by an instruction"));
    // One instruction in two exports, differently.
    let mut other = SCALE;
    other.params = &[
        ("In", "REAL", "Input", true, false, None),
        ("Gain", "REAL", "Input", false, false, Some("7.0")),
        ("Out", "REAL", "Output", true, false, None),
    ];
    let path = scene(
        "twice",
        &[("A.L5X", export(&[SCALE])), ("B.L5X", export(&[other]))],
        &[("S1", "Scale"), ("X", "REAL"), ("Y", "REAL")],
        &[("Main.rll", "Scale(S1,X,Y);\n")],
        "",
    );
    let e = refused(&path);
    assert!(
        e.contains("Add-On Instruction Scale is defined twice, differently (first at"),
        "{e}"
    );
    // An instruction that calls itself through an InOut instance.
    let ping = Aoi {
        name: "Ping",
        params: &[("Me", "Ping", "InOut", true, false, None)],
        locals: &[],
        routines: &[("Logic", "RLL", &["Ping(Me,Me);"])],
        prescan: false,
        enable_in_false: false,
    };
    let path = scene(
        "recursive",
        &[("A.L5X", export(&[ping]))],
        &[("P1", "Ping")],
        &[("Main.rll", "Ping(P1,P1);\n")],
        "",
    );
    let e = refused(&path);
    assert!(e.contains("Add-On Instruction Ping calls itself (Ping → Ping)"), "{e}");
    // A local tag of the instruction's own type.
    let itself = Aoi {
        name: "Box",
        params: &[],
        locals: &[("Inner", "Box", 0)],
        routines: &[("Logic", "RLL", &["NOP();"])],
        prescan: false,
        enable_in_false: false,
    };
    let path = scene(
        "itself",
        &[("A.L5X", export(&[itself]))],
        &[("B1", "Box")],
        &[("Main.rll", "Box(B1);\n")],
        "",
    );
    assert!(refused(&path).contains("Add-On Instruction Box contains itself: Box → Inner (Box)"));
    // Nine levels: L1 calls L2 … calls L9.
    let names: Vec<String> = (1..=9).map(|k| format!("L{k}")).collect();
    let rungs: Vec<String> = (1..=9)
        .map(|k| {
            if k < 9 {
                format!("L{}(Inner);", k + 1)
            } else {
                "NOP();".to_owned()
            }
        })
        .collect();
    let locals: Vec<[(&str, &str, u32); 1]> = (1..=9)
        .map(|k| [("Inner", if k < 9 { names[k].as_str() } else { "DINT" }, 0)])
        .collect();
    let rung_refs: Vec<[&str; 1]> = rungs.iter().map(|r| [r.as_str()]).collect();
    let routines: Vec<[(&str, &str, &[&str]); 1]> = rung_refs.iter().map(|r| [("Logic", "RLL", &r[..])]).collect();
    let chain: Vec<Aoi<'_>> = (0..9)
        .map(|k| Aoi {
            name: &names[k],
            params: &[],
            locals: &locals[k],
            routines: &routines[k],
            prescan: false,
            enable_in_false: false,
        })
        .collect();
    let path = scene(
        "deep",
        &[("A.L5X", export(&chain))],
        &[("Top", "L1")],
        &[("Main.rll", "L1(Top);\n")],
        "",
    );
    let e = refused(&path);
    assert!(e.contains("nested deeper than 7 levels"), "{e}");
    // A web of 30 instructions, each holding two of the next: refused at
    // once (2^29 values), each type counted once.
    let names: Vec<String> = (1..=30).map(|k| format!("W{k}")).collect();
    let locals: Vec<[(&str, &str, u32); 2]> = (0..30)
        .map(|k| {
            let next = if k < 29 { names[k + 1].as_str() } else { "DINT" };
            [("P", next, 0), ("Q", next, 0)]
        })
        .collect();
    let nop: [(&str, &str, &[&str]); 1] = [("Logic", "RLL", &["NOP();"])];
    let web: Vec<Aoi<'_>> = (0..30)
        .map(|k| Aoi {
            name: &names[k],
            params: &[],
            locals: &locals[k],
            routines: &nop,
            prescan: false,
            enable_in_false: false,
        })
        .collect();
    let path = scene(
        "web",
        &[("A.L5X", export(&web))],
        &[("Top", "W1")],
        &[("Main.rll", "NOP();\n")],
        "",
    );
    let started = std::time::Instant::now();
    let e = refused(&path);
    assert!(
        e.contains("Add-On Instruction W1: an instance would hold more than 1000000 values"),
        "{e}"
    );
    assert!(started.elapsed().as_secs() < 20, "{:?}", started.elapsed());
}

/// `scenes/conveyor_ladder.toml`: conveyor_pick's cell run by a ladder
/// routine with the Valve, CartMove and Jog instructions delivers every
/// box it spawns, and its valve never alarms (its expectations).
#[test]
fn the_ladder_conveyor_cell_delivers_every_part_it_spawns() {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_twin"))
        .arg("test")
        .arg(common::root().join("scenes/conveyor_ladder.toml"))
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(stdout.contains("conveyor_ladder.toml  8 expectations"), "{stdout}");
    assert!(stdout.contains("2 passed, 0 failed"), "{stdout}");
}

#[test]
fn an_instance_inside_an_instruction_starts_at_its_defaults_too() {
    let outer = Aoi {
        name: "Outer",
        params: &[
            ("In", "REAL", "Input", true, false, None),
            ("Out", "REAL", "Output", true, false, None),
        ],
        locals: &[("S", "Scale", 0)],
        routines: &[("Logic", "ST", &["Scale(S, In, Out);"])],
        prescan: false,
        enable_in_false: false,
    };
    let tags = &[("O1", "Outer"), ("Os", "Outer[2]"), ("X", "REAL"), ("Y", "REAL")];
    let path = scene(
        "nested_defaults",
        &[("Scale.L5X", export(&[SCALE, outer]))],
        tags,
        &[("Main.rll", "MOV(10.0,X) Outer(O1,X,Y);\n")],
        "",
    );
    let mut run = load(&path);
    assert_eq!(run.f("Os[1].S.Gain"), 2.0, "an array element's nested instance");
    run.scans(1);
    assert_eq!(run.f("O1.S.Gain"), 2.0);
    assert_eq!(run.f("Y"), 20.0);
}
