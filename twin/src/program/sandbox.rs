//! A controller with one task (4 ms) of one program and no plant, for
//! testing routines: declare tags, give the routine's text, scan.
//!
//! ```
//! use twin::program::{sandbox::Sandbox, types::Value};
//! let mut s = Sandbox::new(&[("A", "DINT"), ("X", "REAL")], "X := 2.5; A := X + 0.5;").unwrap();
//! s.scan();
//! assert_eq!(s.value("A"), Some(Value::Int(3)));
//! ```

use super::Program;
use super::controller::Controller;
use super::memory;
use super::types::Value;
use crate::scene::{
    Axis, AxisKind, BaseType, Dialect, Location, ProgramDef, Robot, RoutineDef, Scene, Tag, TagType, Task, Units,
};
use crate::source::{Files, Source};
use crate::st::parse::{parse_ladder, parse_routine};
use planner::axis::AxisConfig;
use planner::task::MotionTask;
use std::path::PathBuf;

/// See the module doc.
pub struct Sandbox {
    program: Program,
    task: MotionTask,
}

impl Sandbox {
    /// Declares `tags` (name, type as in a scene: `DINT`, `REAL[4]`,
    /// `FBD_TIMER`, `STRING` …; zero initial values) and compiles `routine`.
    ///
    /// # Errors
    /// `Main.st:LINE:COLUMN: message` for a routine that does not parse or
    /// compile, or a message naming an unknown type.
    pub fn new(tags: &[(&str, &str)], routine: &str) -> Result<Sandbox, String> {
        Sandbox::with_axes(&[], tags, routine)
    }

    /// As [`Sandbox::new`], with virtual linear axes (millimetres, the
    /// planner's default limits) that the routine's motion instructions
    /// may name.
    ///
    /// # Errors
    /// As [`Sandbox::new`].
    pub fn with_axes(axes: &[&str], tags: &[(&str, &str)], routine: &str) -> Result<Sandbox, String> {
        Sandbox::build(axes, tags, routine, false)
    }

    /// As [`Sandbox::with_axes`], the routine a ladder routine (`Main.rll`:
    /// one rung a line).
    ///
    /// # Errors
    /// As [`Sandbox::new`].
    pub fn ladder(axes: &[&str], tags: &[(&str, &str)], rungs: &str) -> Result<Sandbox, String> {
        Sandbox::build(axes, tags, rungs, true)
    }

    fn build(axes: &[&str], tags: &[(&str, &str)], routine: &str, ladder: bool) -> Result<Sandbox, String> {
        let axes: Vec<Axis> = axes
            .iter()
            .map(|name| Axis {
                name: (*name).to_owned(),
                joint: None,
                joint_location: Location::default(),
                kind: AxisKind::Linear,
                units: Units::Mm,
                config: AxisConfig::new(*name, planner::axis::AxisKind::Linear),
                soft_travel_limit_checking: false,
                initial_position: 0.0,
                motor: Default::default(),
                servo: None,
                holding_brake: false,
                location: Location::default(),
            })
            .collect();
        let mut declared = Vec::with_capacity(tags.len());
        for (name, ty) in tags {
            let (base, len) = match ty.split_once('[') {
                Some((b, rest)) => (b, rest.trim_end_matches(']').parse::<usize>().ok()),
                None => (*ty, None),
            };
            let base = if base.eq_ignore_ascii_case("STRING") {
                BaseType::User(crate::scene::STRING_TYPE)
            } else {
                BaseType::parse(base).ok_or_else(|| format!("unknown type {ty}"))?
            };
            declared.push(Tag {
                name: (*name).to_owned(),
                ty: TagType::new(base, len),
                value: None,
                coordinate_system: None,
                geometry: None,
                move_options: Default::default(),
                usage: Default::default(),
                connection: None,
                constant: false,
                description: String::new(),
                external_access: Default::default(),
                scheduled_output: None,
                location: Location::default(),
            });
        }
        let mut files = Files::default();
        let file = if ladder { "Main.rll" } else { "Main.st" };
        let id = files.add(file, routine);
        let source = Source::file(&files, id);
        let parsed = if ladder {
            parse_ladder(&source)
        } else {
            parse_routine(&source)
        }
        .map_err(|e| e.to_string())?;
        let main = RoutineDef {
            name: "Main".into(),
            path: PathBuf::from(file),
            dialect: Dialect::Logix,
            routine: parsed,
        };
        let scene = Scene {
            name: "sandbox".into(),
            path: PathBuf::from("sandbox.toml"),
            duration_s: 1.0,
            coarse_update_ms: 4.0,
            physics_step_ms: 1.0,
            plant: Default::default(),
            physics_substeps: crate::scene::DEFAULT_PHYSICS_SUBSTEPS,
            robot: Robot {
                urdf: PathBuf::new(),
                urdf_location: Location::default(),
                initial_joints: Default::default(),
                initial_joint_locations: Default::default(),
            },
            axes,
            cameras: Vec::new(),
            obstacles: Vec::new(),
            data_types: vec![crate::scene::DataTypeDef::string()],
            tags: declared,
            program: Vec::new(),
            controller: Default::default(),
            tasks: vec![Task {
                name: "T".into(),
                kind: crate::scene::TaskKind::Periodic { period_ms: 4.0 },
                priority: 5,
                watchdog_ms: crate::scene::DEFAULT_WATCHDOG_MS,
                inhibit: false,
                programs: vec![ProgramDef {
                    name: "P".into(),
                    tags: Vec::new(),
                    aliases: Vec::new(),
                    main,
                    routines: Vec::new(),
                    fault_routine: None,
                    disabled: false,
                    location: Location::default(),
                }],
                location: Location::default(),
            }],
            trace_tags: Vec::new(),
            trace_rungs: Vec::new(),
            add_on_instructions: Vec::new(),
            expectations: Vec::new(),
            test: Default::default(),
            variants: Vec::new(),
            variant: None,
            cell: Default::default(),
            files,
            l5x: None,
            aliases: Vec::new(),
            snapshots: None,
            collision: None,
        };
        let mut task = MotionTask::new(0.004).map_err(|e| e.to_string())?;
        for a in &scene.axes {
            task.add_axis(a.config.clone(), 0.0).map_err(|e| e.to_string())?;
        }
        let program = Program::bind(&scene, &mut task).map_err(|e| e.to_string())?;
        Ok(Sandbox { program, task })
    }

    /// One coarse update with the scan due in it.
    pub fn scan(&mut self) {
        self.program.scan(&mut self.task);
        self.task.update();
        self.program.sync_output_cams(&mut self.task);
    }

    /// The prescan alone (the first [`Sandbox::scan`] runs it otherwise),
    /// to see what it leaves.
    pub fn prescan(&mut self) {
        self.program.controller_mut().prescan_once(&mut self.task);
    }

    /// A scalar tag's value, or an element's (`Arr[3]`), or a structure
    /// member's (`T1.ACC`, `Tmr[1].ACC`).
    #[must_use]
    pub fn value(&self, name: &str) -> Option<Value> {
        let mem = self.program.controller().memory();
        self.slot(name).map(|k| mem.slots[k])
    }

    /// The slot of a scalar tag, an element or a structure member.
    fn slot(&self, name: &str) -> Option<usize> {
        let mem = self.program.controller().memory();
        let (base, rest) = match name.split_once('[') {
            Some((b, r)) => (b, Some(r)),
            None => (name, None),
        };
        let (index, member) = match rest {
            Some(r) => {
                let (i, after) = r.split_once(']')?;
                (Some(i), after.strip_prefix('.'))
            }
            None => (None, None),
        };
        let (tag_name, member) = match (base.split_once('.'), member) {
            (Some((t, m)), None) => (t, Some(m)),
            _ => (base, member),
        };
        let info = &mem.tags[mem.find(tag_name)?];
        let index: usize = match index {
            Some(i) => i.parse().ok().filter(|i| *i < info.len.unwrap_or(0))?,
            None => 0,
        };
        let offset = match (info.kind, member) {
            (memory::Kind::Structure(s), Some(m)) => s.member(m)?.0,
            (memory::Kind::User(id), Some(m)) => mem.layouts.get(id).member(m)?.slot,
            (memory::Kind::Scalar(_), None) => 0,
            _ => return None,
        };
        Some(info.base + index * info.stride() + offset)
    }

    /// Sets a tag, element or member (`A`, `Arr[2]`, `T1.PRE`) to `value`,
    /// as a program's assignment would.
    ///
    /// # Panics
    /// When there is no such tag.
    pub fn set(&mut self, name: &str, value: Value) {
        let slot = self.slot(name).unwrap_or_else(|| panic!("no tag {name}"));
        let mem = self.program.memory_mut();
        mem.slots[slot] = mem.types[slot].store(value).0;
    }

    /// Sets the nominal time of a statement or ladder instruction
    /// (`[controller] statement_us`, 1 µs unless set): a routine whose
    /// scan would outlast the 4 ms task needs less.
    pub fn set_statement_us(&mut self, us: f64) {
        self.program.controller_mut().set_statement_us(us);
    }

    /// The controller (faults, statistics).
    #[must_use]
    pub fn controller(&self) -> &Controller {
        self.program.controller()
    }

    /// The program (its bindings and warnings).
    #[must_use]
    pub fn program(&self) -> &Program {
        &self.program
    }
}
