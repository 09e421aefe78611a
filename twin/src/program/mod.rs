//! The program: what the PLC side executes each coarse update.
//!
//! **In:** the scene's `[[program]]` steps and `[[tasks]]` (parsed by
//! [`crate::st`]), its tags and axes, and the planner its axes were added
//! to. **Out:** instruction calls into the planner
//! ([`planner::task::instructions::Instruction::execute`]), live tag
//! values, faults.
//!
//! The stage is one compiler and one interpreter for everything a user
//! writes in Structured Text and ladder (a rung's instructions are
//! statements on a rung-condition register, their operands compiled as
//! Structured Text's; an Add-On Instruction call a routine of its own):
//! * [`memory`] lays out tag memory; [`bindings`] binds the planner
//!   handles the program names, on first use;
//! * [`compile`] compiles routines, step calls and scene expressions into
//!   [`ir`]: names resolved, expressions typed, each instruction call bound
//!   to its catalogue entry ([`planner::task::instructions`]) with its
//!   operands by kind; errors are [`crate::source::Diagnostic`]s;
//! * [`exec`] evaluates the compiled form (it imports no compiler);
//! * [`controller`] is the task engine: periodic tasks scanned with their
//!   timing, prescan and faults; [`steps`] are the `[[program]]` steps;
//!   [`sandbox`] is the engine without a plant, for tests.
//!
//! # Program steps
//! Each step fires once. A `when` step is armed once the step before it has
//! fired (the list is a sequence, like SFC transitions) and is due `after_s`
//! after the first update at which its condition is TRUE; an `at_s` step is
//! due at its time. A step fires at the first coarse update that starts at
//! or after it is due; every trigger is read first, then the due steps
//! execute in list order, just before the planner update. A function-block
//! call sets the inputs it names; the others keep their last value, as PLC
//! block inputs do. A Logix call is one scan of a rung that has just
//! become true (a one-shot rung): the instruction executes once, with the
//! scene's tag values (read when the scene loads: steps do not see tasks'
//! writes), and the rung is false again from the next scan on; what the
//! instruction then does with its control structure (`.EN`, `.DN`, `.ER`,
//! `.IP`, `.AC`, `.PC`, …) is the instruction's own rule. `when` is a BOOL
//! expression of the controller's scope: a control-structure bit
//! (`MC1.PC`), a function-block output (`MoveTable.Done`), a tag.

pub mod axis_attributes;
pub mod bindings;
pub mod compile;
pub mod controller;
pub mod exec;
pub mod io;
pub mod ir;
pub mod layout;
pub mod memory;
pub mod sandbox;
pub mod steps;
pub mod system;
pub mod types;

use crate::scene::{Dialect, Scene};
use crate::source::Diagnostic;
use bindings::{Bindings, Declarations, Env, FbBinding, InstructionBinding};
use compile::Compiler;
use controller::Controller;
use ir::Place;
use memory::Memory;
use planner::task::MotionTask;
use planner::task::instructions::Instruction;
use steps::Step;
use types::{DataType, Value};

/// The scene's program bound to the planner.
pub struct Program {
    bindings: Bindings,
    steps: Vec<Step>,
    plc: Controller,
    traced: Vec<TracedTag>,
    io: io::IoMap,
}

impl std::fmt::Debug for Program {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Program")
            .field("steps", &self.steps.len())
            .field("controller", &self.plc)
            .finish_non_exhaustive()
    }
}

/// A `[trace] tags` entry bound to what it reads.
#[derive(Debug, Clone)]
pub struct TracedTag {
    /// The reference as written (the trace column's name).
    pub name: String,
    place: Place,
    ty: DataType,
    /// A string (STRING or a user string type), traced as its text.
    text: Option<ir::StrAt>,
    /// The recording's entity path when it is not `tags/<name>`: a traced
    /// rung's `program/<program>/<routine>/<rung>`.
    pub entity: Option<String>,
}

impl TracedTag {
    /// Whether the tag is a REAL (single precision), whose value the trace
    /// writes rounded to `f32`.
    pub fn single_precision(&self) -> bool {
        self.ty == DataType::Real && self.text.is_none()
    }

    /// Whether it is a ULINT, whose 64 bits the trace writes unsigned.
    pub fn unsigned_64(&self) -> bool {
        self.ty == DataType::Ulint
    }

    /// Whether it is a string, which the trace writes as text.
    pub fn is_text(&self) -> bool {
        self.text.is_some()
    }

    /// Its data type.
    pub fn data_type(&self) -> DataType {
        self.ty
    }
}

impl Program {
    /// Compiles the program: every task's routines, then every step's call
    /// and trigger, then the traced tags — binding the planner handles they
    /// name in that order of first use — and checks the calls whose
    /// operands are all constant ([`Program::warnings`]).
    ///
    /// # Errors
    /// The first error, as a diagnostic pointing into its file.
    pub fn bind(scene: &Scene, task: &mut MotionTask) -> Result<Program, Box<Diagnostic>> {
        // An Add-On Instruction may not take an instruction's name (the
        // scene checked data types and motion instructions).
        for a in &scene.add_on_instructions {
            if compile::ladder::find(&a.name).is_some() || ir::General::find(&a.name).is_some() {
                return Err(Box::new(scene.files.error(
                    a.span,
                    format!("Add-On Instruction {}: the name is taken by an instruction", a.name),
                    "",
                )));
            }
        }
        if let Some((name, at, slots)) = memory::over_budget(scene) {
            return Err(Box::new(Diagnostic::error(format!(
                "{}:{}:{}: tag {name}: the tags would take {slots} values with it, more than the {} a scene may have (twin's budget for tag memory)",
                scene.path.display(),
                at.line,
                at.column,
                memory::MAX_TAG_SLOTS
            ))));
        }
        let mut mem = Memory::of_scene(scene);
        // A slot for each traced rung's condition-out, after the tags'.
        let traced_rungs: Vec<_> = scene
            .trace_rungs
            .iter()
            .map(|t| {
                mem.slots.push(Value::Bool(false));
                mem.types.push(DataType::Bool);
                (t, mem.slots.len() - 1)
            })
            .collect();
        let decls = Declarations::of(scene);
        let mut bindings = Bindings::default();
        let mut env = Env {
            scene,
            decls: &decls,
            files: &scene.files,
            task,
            bindings: &mut bindings,
        };
        let mut programs = Vec::with_capacity(scene.tasks.len());
        for t in &scene.tasks {
            let mut compiled = Vec::with_capacity(t.programs.len());
            for p in &t.programs {
                compiled.push(compile::scene::program(p, &mem, &mut env, &traced_rungs)?);
            }
            programs.push(compiled);
        }
        let handler = match &scene.controller.fault_handler {
            Some(p) => Some(compile::scene::program(p, &mem, &mut env, &traced_rungs)?),
            None => None,
        };
        let steps = compile::scene::steps(scene, &mem, &mut env)?;
        compile::scene::aliases(scene, &mem, &mut env)?;
        let steps = steps.into_iter().map(Step::new).collect();
        // A display operand sets its member once: two that differ (a
        // timer's Preset written 500 in one rung and 800 in another) are an
        // error, as the member holds one value.
        let mut set: std::collections::HashMap<usize, (Value, crate::source::Span)> = std::collections::HashMap::new();
        for (slot, v, span) in programs.iter().flatten().chain(&handler).flat_map(|p| &p.init) {
            if let Some((first, at)) = set.get(slot)
                && first != v
            {
                let (line, column) = scene.files.line_column(*at);
                let file = scene.files.path(at.file).display().to_string();
                return Err(Box::new(scene.files.error(
                    *span,
                    format!(
                        "this display operand sets {} where {file}:{line}:{column} sets {}: one member holds one value (write '?' in all but one)",
                        v.as_i64(),
                        first.as_i64()
                    ),
                    "",
                )));
            }
            set.insert(*slot, (*v, *span));
            mem.slots[*slot] = mem.types[*slot].store(*v).0;
        }
        let plc = Controller::new(scene, mem, programs, handler);
        let mut traced = Vec::with_capacity(scene.trace_tags.len() + traced_rungs.len());
        for (index, t) in scene.trace_tags.iter().enumerate() {
            let mut compiler = Compiler::new(plc.memory(), None, &[], Dialect::Logix, &mut env, false);
            let in_field = |d: Box<Diagnostic>| Box::new((*d).in_field(format!("trace.tags[{index}]")));
            if let Some(text) = compiler.traced_string(&compiler.dealias_expr(&t.expr)) {
                traced.push(TracedTag {
                    name: t.text.clone(),
                    place: Place::FirstScan,
                    ty: DataType::Sint,
                    text: Some(text.map_err(in_field)?),
                    entity: None,
                });
                continue;
            }
            let (place, ty) = compiler.traced(&compiler.dealias_expr(&t.expr)).map_err(in_field)?;
            traced.push(TracedTag {
                name: t.text.clone(),
                place,
                ty,
                text: None,
                entity: None,
            });
        }
        for (t, slot) in &traced_rungs {
            traced.push(TracedTag {
                name: t.text.clone(),
                place: Place::Slot(*slot),
                ty: DataType::Bool,
                text: None,
                entity: Some(format!("program/{}/{}/{}", t.program, t.routine, t.rung)),
            });
        }
        Ok(Program {
            bindings,
            steps,
            plc,
            traced,
            io: io::IoMap::default(),
        })
    }

    /// One scan: fires the steps due at the planner's current time, then
    /// runs the task triggers due (their calls take effect at the next
    /// planner update).
    pub fn scan(&mut self, task: &mut MotionTask) {
        self.sync_output_cams(task);
        if !self.steps.is_empty() {
            let (mem, scratch, refusals) = self.plc.step_context();
            steps::fire(&mut self.steps, mem, scratch, task, refusals);
            self.plc.cap_refusals();
        }
        self.plc.scan(task);
    }

    /// The Output and Input words of the axes' output cams (MAOC): the
    /// bits the cams drove in the last update go to their Output tags, the
    /// Input tags' values to the cams (for their enable bits). The run
    /// calls it right after each planner update, so that the update's trace
    /// row shows the bits the update switched; a scan does it too.
    pub fn sync_output_cams(&mut self, task: &mut MotionTask) {
        let words = task.output_cam_words();
        if words.is_empty() {
            return;
        }
        let mem = self.plc.memory_mut();
        for w in words {
            let word = mem.slots[w.output].as_i64() as u32;
            let merged = (word & !w.mask) | (w.bits & w.mask);
            mem.slots[w.output] = Value::Int(i64::from(merged as i32));
            task.set_output_cam_input(w.axis, w.target, mem.slots[w.input].as_i64() as u32);
        }
    }

    /// The `[trace] tags` entries.
    pub fn traced_tags(&self) -> &[TracedTag] {
        &self.traced
    }

    /// A traced tag's value now (a string's: its LEN).
    pub fn traced(&self, t: &TracedTag, task: &MotionTask) -> Value {
        match &t.text {
            Some(s) => self.plc.memory().slots[s.base],
            None => self.plc.peek(&t.place, task),
        }
    }

    /// A traced string's text now, as the trace writes it: Logix's `$`
    /// escapes for `$`, `'` and the characters outside printable ASCII
    /// (`$0D`), and `$2C` for a comma, so that no trace cell holds one;
    /// `None` for a tag that is not a string.
    pub fn traced_text(&self, t: &TracedTag) -> Option<String> {
        let s = t.text.as_ref()?;
        let slots = &self.plc.memory().slots;
        let len = usize::try_from(slots[s.base].as_i64()).unwrap_or(0).min(s.capacity);
        let mut out = String::with_capacity(len);
        for k in 0..len {
            match slots[s.base + 1 + k].as_i64() as u8 {
                b'$' => out.push_str("$$"),
                b'\'' => out.push_str("$'"),
                b',' => out.push_str("$2C"),
                c @ 0x20..=0x7E => out.push(char::from(c)),
                c => out.push_str(&format!("${c:02X}")),
            }
        }
        Some(out)
    }

    /// A traced tag's value now as the number the trace writes: BOOL 0/1,
    /// integers (exact up to 2^53), REAL rounded to single precision.
    pub fn traced_number(&self, t: &TracedTag, task: &MotionTask) -> f64 {
        match self.traced(t, task) {
            Value::Bool(b) => f64::from(u8::from(b)),
            Value::Int(i) if t.unsigned_64() => i as u64 as f64,
            Value::Int(i) => i as f64,
            Value::Real(x) if t.single_precision() => f64::from(x as f32),
            Value::Real(x) => x,
        }
    }

    /// The servo drive attributes the program's SSVs changed since the
    /// last call: (axis index in the scene, the drive's attributes now).
    pub fn take_drive_changes(&mut self) -> Vec<(usize, crate::scene::ServoGains)> {
        self.plc.take_drive_changes()
    }

    /// The task engine: tag memory, faults, costs.
    pub fn controller(&self) -> &Controller {
        &self.plc
    }

    /// Tag memory, to write a tag as a test or a sandbox does.
    pub fn memory_mut(&mut self) -> &mut Memory {
        self.plc.memory_mut()
    }

    /// The controller, to change a setting as a sandbox does.
    pub fn controller_mut(&mut self) -> &mut Controller {
        &mut self.plc
    }

    /// The function-block instances, in the order the program first calls them.
    pub fn fbs(&self) -> &[FbBinding] {
        &self.bindings.fbs
    }

    /// The `MOTION_INSTRUCTION` tags the program executes with, in the order
    /// the program first uses them.
    pub fn instructions(&self) -> &[InstructionBinding] {
        &self.bindings.instructions
    }

    /// Whether the program calls `instruction` (a step or a routine).
    pub fn calls(&self, instruction: &Instruction) -> bool {
        self.bindings.calls(instruction)
    }

    /// Compiles a scene expression in controller scope that may also name
    /// `columns` (an expectation): tags, `Program.Tag`, axis and
    /// coordinate-system members, instruction bits, functions, and the
    /// trace columns.
    ///
    /// # Errors
    /// A diagnostic pointing into the expression.
    pub fn compile_expression(
        &mut self,
        scene: &Scene,
        task: &mut MotionTask,
        expr: &crate::st::ast::Expr,
        columns: &[ir::Column],
    ) -> Result<ir::CExpr, Box<Diagnostic>> {
        self.with_compiler(scene, task, None, columns, |compiler| {
            let expr = compiler.dealias_expr(expr).into_owned();
            compiler.expr(&expr)
        })
    }

    /// The value of an expression [`Program::compile_expression`]
    /// compiled, now, reading the trace columns from `columns`.
    pub fn evaluate(&mut self, task: &mut MotionTask, e: &ir::CExpr, columns: &[f64]) -> Value {
        let (mem, scratch, _) = self.plc.step_context();
        exec::evaluate_with_columns(mem, task, scratch, e, columns)
    }

    /// Calls whose constant operands the instruction refuses whenever they
    /// run, found at load.
    pub fn warnings(&self) -> &[Diagnostic] {
        &self.bindings.warnings
    }
}

impl Program {
    /// Binds a device's tag ([`io`]): resolved, its type checked against
    /// `kind`, an input checked against the inputs bound before it.
    ///
    /// # Errors
    /// A diagnostic at the reference, in its field.
    pub fn bind_io(
        &mut self,
        scene: &Scene,
        task: &mut MotionTask,
        tag: &crate::scene::IoTag,
        kind: crate::scene::IoKind,
        entry: io::IoEntry,
    ) -> Result<io::IoPoint, Box<Diagnostic>> {
        let in_field = |d: Box<Diagnostic>| Box::new((*d).in_field(tag.field.clone()));
        let (place, _) = self.resolve(scene, task, None, &tag.expr).map_err(in_field)?;
        let mem = self.plc.memory();
        let fail = |message: String| {
            Box::new(
                scene
                    .files
                    .error(tag.expr.span, message, "")
                    .in_field(tag.field.clone()),
            )
        };
        let Some(point) = io::point_of(&place, mem) else {
            return Err(fail(format!(
                "'{}' is not a point of tag memory: an I/O tag is a tag, an element or member with constant subscripts, or a bit of one",
                tag.text
            )));
        };
        let three = kind != crate::scene::IoKind::Real3
            || (1..3).all(|k| point.next(k, mem).is_some_and(|p| p.fits(crate::scene::IoKind::Real)));
        if !point.fits(kind) || !three {
            return Err(fail(format!(
                "'{}' is {}; this needs {}",
                tag.text,
                point.describe(),
                kind.describe()
            )));
        }
        self.io.add(point, entry, &tag.text).map_err(fail)?;
        Ok(point)
    }

    /// Writes three REALs from `point` on (a `Real3` point).
    pub fn write_inputs3(&mut self, point: io::IoPoint, values: [f64; 3]) {
        for (k, v) in values.into_iter().enumerate() {
            if let Some(p) = point.next(k, self.plc.memory()) {
                p.write(self.plc.memory_mut(), Value::Real(v));
            }
        }
    }

    /// Writes an input into tag memory ([`io`]).
    pub fn write_input(&mut self, point: io::IoPoint, value: Value) {
        point.write(self.plc.memory_mut(), value);
    }

    /// Reads an output from tag memory.
    #[must_use]
    pub fn read_output(&self, point: io::IoPoint) -> Value {
        point.read(self.plc.memory())
    }

    /// A reference resolved to its place and type, in controller scope or
    /// in a program's (`scope`: the program, its routines' names, the
    /// routine's dialect).
    fn resolve(
        &mut self,
        scene: &Scene,
        task: &mut MotionTask,
        scope: Option<(&str, &[String], Dialect)>,
        expr: &crate::st::ast::Expr,
    ) -> Result<(Place, DataType), Box<Diagnostic>> {
        self.with_compiler(scene, task, scope, &[], |compiler| {
            let expr = compiler.dealias_expr(expr).into_owned();
            compiler.traced(&expr)
        })
    }

    /// Runs `f` with a compiler over tag memory, in controller scope or in
    /// a program's (`scope`: the program, its routines' names, the
    /// routine's dialect), that may also name the trace `columns`, binding
    /// what it names into the program.
    fn with_compiler<R>(
        &mut self,
        scene: &Scene,
        task: &mut MotionTask,
        scope: Option<(&str, &[String], Dialect)>,
        columns: &[ir::Column],
        f: impl FnOnce(&mut Compiler<'_, '_, '_>) -> R,
    ) -> R {
        let decls = Declarations::of(scene);
        let mut env = Env {
            scene,
            decls: &decls,
            files: &scene.files,
            task,
            bindings: &mut self.bindings,
        };
        let (program, routines, dialect) = scope.map_or((None, &[][..], Dialect::Logix), |(p, r, d)| (Some(p), r, d));
        let mut compiler = Compiler::new(self.plc.memory(), program, routines, dialect, &mut env, false);
        compiler.columns = columns;
        f(&mut compiler)
    }

    /// The I/O points bound, for `twin check`.
    #[must_use]
    pub fn io(&self) -> &io::IoMap {
        &self.io
    }

    /// The routines' assignments to input tags, and a ladder
    /// instruction's writes (a routine may write one,
    /// as on a controller; the next input update overwrites it), for
    /// `twin check`: (`routine:line:col`, the tag as the device names it).
    pub fn input_writes(&mut self, scene: &Scene, task: &mut MotionTask) -> Vec<(String, String)> {
        let mut out = Vec::new();
        for p in scene.tasks.iter().flat_map(|t| &t.programs) {
            let defs: Vec<_> = std::iter::once(&p.main).chain(&p.routines).collect();
            let names: Vec<String> = defs.iter().map(|r| r.name.clone()).collect();
            for def in &defs {
                // Assignments, and the operands ladder instructions write.
                let mut targets = def.routine.assignment_targets();
                let rung_calls = if def.routine.is_ladder() {
                    def.routine.calls()
                } else {
                    Vec::new()
                };
                for c in rung_calls {
                    for &k in compile::ladder::written_operands(&c.name) {
                        if let Some(crate::st::ast::Expr {
                            kind: crate::st::ast::ExprKind::Ref(r),
                            ..
                        }) = c.args.get(k).and_then(|a| a.expr.as_ref())
                        {
                            targets.push(r);
                        }
                    }
                }
                for target in targets {
                    let expr = crate::st::ast::Expr {
                        kind: crate::st::ast::ExprKind::Ref(target.clone()),
                        span: target.span,
                    };
                    let scope = Some((p.name.as_str(), names.as_slice(), def.dialect));
                    let Ok((place, _)) = self.resolve(scene, task, scope, &expr) else {
                        continue;
                    };
                    let Some(point) = io::point_of(&place, self.plc.memory()) else {
                        continue;
                    };
                    if let Some(e) = self.io.input_at(point) {
                        let (line, column) = scene.files.line_column(target.span);
                        let file = scene.files.path(target.span.file).display().to_string();
                        out.push((format!("{file}:{line}:{column}"), e.tag.clone()));
                    }
                }
            }
        }
        out
    }
}

/// The lines of `scenes/README.md` between `<!-- NAME: … -->` and
/// `<!-- /NAME -->`: a table generated from a catalogue, which a test
/// keeps equal to it.
#[cfg(test)]
pub(crate) fn scene_readme_block(name: &str) -> String {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../scenes/README.md");
    let readme = std::fs::read_to_string(path).expect("scenes/README.md");
    let start = readme.find(&format!("<!-- {name}:")).expect("the block's start marker");
    let body = &readme[start..];
    let body = &body[body.find('\n').expect("a line") + 1..];
    let end = body.find(&format!("<!-- /{name} -->")).expect("the block's end marker");
    body[..end].to_owned()
}

#[cfg(test)]
mod tests;
