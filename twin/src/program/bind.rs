//! Positional Logix instruction calls (`MCCM(CS1, MC1, …)`): resolving their
//! operands through the instruction catalogue and binding them to the
//! planner.
//!
//! # Execution model
//! A program step holding a Logix call is **one scan of a rung that has just
//! become true** (a one-shot rung): the instruction executes once, with the
//! operand values of the scene, and the rung is false again from the next
//! scan on. What the instruction then does with its control structure
//! (`.EN`, `.DN`, `.ER`, `.IP`, `.AC`, `.PC`, …) is the instruction's own rule,
//! kept in the planner.
//!
//! Operand values are read when the scene is loaded (scene tags do not
//! change during a run); instructions that produce data at run time (a cam
//! profile from MCCP, say) keep it in the planner.
//!
//! # Operands
//! [`planner::catalogue`] describes each instruction's operands; a
//! [`Bind`] reads them by their catalogue name, so every message names the
//! operand as the manual does. An enumeration operand takes one of its
//! words (case-insensitive) or an integer: with the **Immediate** format
//! the integer must be one of the operand's codes and a tag is refused (the
//! controller's verifier refuses both); with **Immediate or Tag** any
//! integer is passed on and the instruction reports a value out of range at
//! run time with ERR 13 and the operand's faceplate index as EXERR.
//!
//! # Adding an instruction
//! Describe it in the catalogue (`planner/src/catalogue.rs`), give it a
//! planner module, and bind it in its family's file here
//! (`program/coord.rs`, `program/cam.rs`, `program/mct.rs`).

use super::InstructionBinding;
use crate::scene::{BaseType, Scene, Tag, TagValue};
use crate::st::Expr;
use planner::catalogue::{Format, Instruction, Operand};
use planner::dynamics::MoveDynamics;
use planner::task::{AxisHandle, InstructionHandle, MotionTask};
use std::borrow::Cow;
use std::cell::Cell;
use std::fmt;
use std::sync::Arc;

/// Why a call cannot be bound: what is wrong, and the operand (call
/// position) it is about when there is one, so that the error can point
/// at it in the scene file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BindError {
    /// Call position of the operand at fault.
    pub operand: Option<usize>,
    /// What is wrong, naming the operand as the manual does.
    pub message: String,
}

impl From<String> for BindError {
    fn from(message: String) -> Self {
        BindError { operand: None, message }
    }
}

impl fmt::Display for BindError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

/// A compiled Logix call: what one scan of its rung does to the planner.
#[derive(Clone)]
pub struct LogixStep {
    /// The instruction mnemonic (upper case), for messages.
    pub instruction: &'static str,
    /// The control structure the call executes with, if it has one.
    pub control: Option<InstructionHandle>,
    /// Executes the instruction once.
    pub run: Arc<dyn Fn(&mut MotionTask) + Send + Sync>,
}

impl LogixStep {
    /// A call executed as one scan of a one-shot rung: `run`, then the rung
    /// goes false at the next coarse update (so `.EN` clears once `.DN` or
    /// `.ER` is set).
    pub fn one_shot(
        instruction: &'static str,
        control: InstructionHandle,
        run: impl Fn(&mut MotionTask) + Send + Sync + 'static,
    ) -> LogixStep {
        LogixStep {
            instruction,
            control: Some(control),
            run: Arc::new(move |task: &mut MotionTask| {
                run(task);
                task.rung_false_next_scan(control);
            }),
        }
    }
}

impl fmt::Debug for LogixStep {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("LogixStep")
            .field("instruction", &self.instruction)
            .field("control", &self.control)
            .finish_non_exhaustive()
    }
}

/// The values of tags, by name: the scene's initial values for program
/// steps, the live tag memory for Structured Text routines.
pub trait TagValues {
    /// The current value of the tag called `name` (case-insensitive).
    fn tag_value(&self, name: &str) -> Option<Cow<'_, TagValue>>;
}

impl TagValues for Scene {
    fn tag_value(&self, name: &str) -> Option<Cow<'_, TagValue>> {
        self.tag(name).and_then(|t| t.value.as_ref()).map(Cow::Borrowed)
    }
}

/// What a Logix call's operands may refer to while the scene is bound.
pub struct LogixContext<'a> {
    /// The scene (tag declarations; for a routine, with its program's tags
    /// added under their qualified names).
    pub scene: &'a Scene,
    /// Where operand values are read.
    pub values: &'a dyn TagValues,
    /// The planner (its axes are the scene's `[[axes]]`).
    pub task: &'a mut MotionTask,
    /// The `MOTION_INSTRUCTION` tags bound so far (first-use order).
    pub instructions: &'a mut Vec<InstructionBinding>,
}

impl LogixContext<'_> {
    /// The control structure named by `operand` (a `MOTION_INSTRUCTION`
    /// tag), bound on its first use.
    ///
    /// # Errors
    /// A message naming the operand when it is not such a tag.
    pub fn instruction(&mut self, what: &str, operand: &Expr) -> Result<InstructionHandle, String> {
        let Expr::Ident(name) = operand else {
            return Err(format!("{what} {operand}: expected a MOTION_INSTRUCTION tag"));
        };
        let tag = declared_tag(self.scene, what, name, "MOTION_INSTRUCTION")?;
        if tag.ty.base != BaseType::MotionInstruction || tag.ty.array_len.is_some() {
            return Err(format!(
                "{what} {name}: is a {} tag, expected MOTION_INSTRUCTION",
                tag.ty
            ));
        }
        if let Some(b) = self.instructions.iter().find(|b| b.name.eq_ignore_ascii_case(name)) {
            return Ok(b.handle);
        }
        let handle = self.task.add_instruction(tag.name.clone());
        self.instructions.push(InstructionBinding {
            name: tag.name.clone(),
            handle,
        });
        Ok(handle)
    }

    /// The axis named by `operand`.
    ///
    /// # Errors
    /// A message naming the operand when no `[[axes]]` entry has that name.
    pub fn axis(&self, what: &str, operand: &Expr) -> Result<AxisHandle, String> {
        let Expr::Ident(name) = operand else {
            return Err(format!("{what} {operand}: expected an axis name"));
        };
        axis_named(self.task, name).ok_or_else(|| format!("{what} {name}: no axis of that name in [[axes]]"))
    }

    /// The number an operand stands for: a literal, a REAL/DINT tag with a
    /// value, or an element of such an array tag.
    ///
    /// # Errors
    /// A message naming the operand otherwise.
    pub fn number(&self, what: &str, operand: &Expr) -> Result<f64, String> {
        number(operand, self.values)
            .ok_or_else(|| format!("{what} {operand}: expected a number or a REAL/DINT tag with a value"))
    }

    /// An integer operand (a literal or an integer-valued tag).
    ///
    /// # Errors
    /// A message naming the operand when it is not a whole number.
    pub fn integer(&self, what: &str, operand: &Expr) -> Result<i64, String> {
        let x = self.number(what, operand)?;
        if x.fract() == 0.0 && x.abs() < 1e15 {
            Ok(x as i64)
        } else {
            Err(format!("{what} {operand}: expected an integer, got {x}"))
        }
    }

    /// An enumeration operand as the catalogue describes it (module doc).
    ///
    /// # Errors
    /// A message listing the operand's words otherwise.
    pub fn code(&self, spec: &Operand, operand: &Expr) -> Result<i64, String> {
        let what = spec.name;
        let constant = matches!(spec.format, Format::Immediate | Format::Input);
        if let Expr::Ident(w) = operand {
            if let Some(code) = spec.code_of(w) {
                return Ok(code);
            }
            if constant && self.scene.tag(w).is_some() {
                return Err(format!(
                    "{what} {operand}: the operand's format is {} (a constant), not a tag: write one of {}",
                    spec.format.name(),
                    spec.word_list()
                ));
            }
        }
        let list = spec.word_list();
        match self.integer(what, operand) {
            Ok(code) if !constant || spec.has_code(code) => Ok(code),
            Ok(_) => Err(format!("{what} {operand}: expected one of {list}")),
            Err(_) if constant => Err(format!("{what} {operand}: expected one of {list}")),
            Err(_) => Err(format!("{what} {operand}: expected one of {list} or an integer")),
        }
    }

    /// `count` consecutive numbers starting at an array element (`Pos[0]`,
    /// the Logix way of passing an array operand) or at a whole array tag.
    ///
    /// # Errors
    /// A message when the tag is not a numeric array with a value, or is
    /// shorter than `count` from the start element.
    pub fn numbers(&self, what: &str, operand: &Expr, count: usize) -> Result<Vec<f64>, String> {
        let (name, start) = array_start(what, operand)?;
        let value = self.values.tag_value(name);
        let Some(TagValue::Array(items)) = value.as_deref() else {
            return Err(format!(
                "{what} {operand}: '{name}' is not a REAL/DINT array tag with a value"
            ));
        };
        if start + count > items.len() {
            return Err(format!(
                "{what} {operand}: needs {count} elements from [{start}], '{name}' has {}",
                items.len()
            ));
        }
        items[start..start + count]
            .iter()
            .map(|v| match v {
                TagValue::Real(x) => Ok(*x),
                TagValue::Integer(i) => Ok(*i as f64),
                _ => Err(format!("{what} {operand}: '{name}' holds non-numeric elements")),
            })
            .collect()
    }

    /// An array operand from its element to the end of the array, or a
    /// single number (a radius).
    ///
    /// # Errors
    /// A message naming the operand when it is neither.
    pub fn values(&self, what: &str, operand: &Expr) -> Result<Vec<f64>, String> {
        let (name, start) = match operand {
            Expr::Index(..) | Expr::Ident(_) => array_start(what, operand)?,
            _ => return self.number(what, operand).map(|x| vec![x]),
        };
        match self.values.tag_value(name).as_deref() {
            Some(TagValue::Array(items)) => {
                let len = items.len().saturating_sub(start);
                self.numbers(what, operand, len)
            }
            _ => self.number(what, operand).map(|x| vec![x]),
        }
    }

    /// `0` (none) or an array tag / element.
    ///
    /// # Errors
    /// A message naming the operand when it is neither.
    pub fn optional_array(&self, what: &str, operand: &Expr) -> Result<Vec<f64>, String> {
        let refused = || format!("{what} {operand}: expected 0 or a REAL array tag");
        match operand {
            Expr::Integer(0) => Ok(Vec::new()),
            Expr::Number(x) if *x == 0.0 => Ok(Vec::new()),
            Expr::Ident(name) if !matches!(self.values.tag_value(name).as_deref(), Some(TagValue::Array(_))) => {
                self.values(what, operand)?;
                Err(refused())
            }
            Expr::Ident(_) | Expr::Index(..) => self.values(what, operand),
            _ => Err(refused()),
        }
    }
}

/// The tag name and start element of an array operand (`Pos[2]` or `Pos`).
fn array_start<'e>(what: &str, operand: &'e Expr) -> Result<(&'e str, usize), String> {
    match operand {
        Expr::Ident(name) => Ok((name, 0)),
        Expr::Index(base, i) => match (base.as_ref(), usize::try_from(*i)) {
            (Expr::Ident(name), Ok(i)) => Ok((name, i)),
            _ => Err(format!("{what} {operand}: expected an array tag or element")),
        },
        _ => Err(format!(
            "{what} {operand}: expected an array tag or element, e.g. Pos[0]"
        )),
    }
}

/// The planner axis whose name is `name` (case-insensitive).
pub fn axis_named(task: &MotionTask, name: &str) -> Option<AxisHandle> {
    task.axis_handles()
        .find(|h| task.axis_config(*h).name.eq_ignore_ascii_case(name))
}

/// The numeric value of an operand: a literal, a REAL/DINT tag, or an
/// element of an array tag.
pub fn number(expr: &Expr, values: &dyn TagValues) -> Option<f64> {
    let numeric = |v: &TagValue| match v {
        TagValue::Real(x) => Some(*x),
        TagValue::Integer(i) => Some(*i as f64),
        _ => None,
    };
    match expr {
        Expr::Number(x) => Some(*x),
        Expr::Integer(i) => Some(*i as f64),
        Expr::Ident(name) => values.tag_value(name).as_deref().and_then(numeric),
        Expr::Index(base, i) => match (base.as_ref(), usize::try_from(*i)) {
            (Expr::Ident(name), Ok(i)) => match values.tag_value(name).as_deref() {
                Some(TagValue::Array(items)) => items.get(i).and_then(numeric),
                _ => None,
            },
            _ => None,
        },
        _ => None,
    }
}

/// One positional call being bound: its catalogue entry, its operands and
/// the binding context. Operands are read by their catalogue names.
pub struct Bind<'b, 'a> {
    /// The instruction.
    pub instruction: &'static Instruction,
    operands: &'b [Expr],
    /// What the operands refer to.
    pub ctx: &'b mut LogixContext<'a>,
    /// Call position of the operand read last: a failed read is about it.
    last: Cell<Option<usize>>,
}

impl<'b, 'a> Bind<'b, 'a> {
    /// Checks the operand count against the catalogue.
    ///
    /// # Errors
    /// A message giving the expected operands.
    pub fn new(
        instruction: &'static Instruction,
        operands: &'b [Expr],
        ctx: &'b mut LogixContext<'a>,
    ) -> Result<Self, String> {
        if operands.len() != instruction.operands.len() {
            return Err(format!(
                "{} takes {} operands ({}), got {}",
                instruction.mnemonic,
                instruction.operands.len(),
                instruction.operand_names(),
                operands.len()
            ));
        }
        Ok(Bind {
            instruction,
            operands,
            ctx,
            last: Cell::new(None),
        })
    }

    /// The catalogue entry and the expression of the operand called `name`.
    ///
    /// # Panics
    /// When the instruction has no such operand: the binding files name
    /// operands exactly as the catalogue does (a test binds every
    /// instruction).
    pub fn operand(&self, name: &str) -> (&'static Operand, &'b Expr) {
        let (i, spec) = self
            .instruction
            .operand(name)
            .unwrap_or_else(|| panic!("{} has no operand '{name}' in the catalogue", self.instruction.mnemonic));
        self.last.set(Some(i));
        (spec, &self.operands[i])
    }

    /// The call position of the operand read last (the one a failed read
    /// is about).
    pub fn last_operand(&self) -> Option<usize> {
        self.last.get()
    }

    /// A number operand.
    ///
    /// # Errors
    /// See [`LogixContext::number`].
    pub fn number(&self, name: &str) -> Result<f64, String> {
        let (spec, e) = self.operand(name);
        self.ctx.number(spec.name, e)
    }

    /// An integer operand without words (Move Type, Termination Type …).
    ///
    /// # Errors
    /// See [`LogixContext::integer`].
    pub fn integer(&self, name: &str) -> Result<i64, String> {
        let (spec, e) = self.operand(name);
        self.ctx.integer(spec.name, e)
    }

    /// An enumeration operand.
    ///
    /// # Errors
    /// See [`LogixContext::code`].
    pub fn code(&self, name: &str) -> Result<i64, String> {
        let (spec, e) = self.operand(name);
        self.ctx.code(spec, e)
    }

    /// An enumeration operand as the planner's `i32`.
    ///
    /// # Errors
    /// See [`LogixContext::code`].
    pub fn code_i32(&self, name: &str) -> Result<i32, String> {
        // Codes of Immediate operands are the catalogue's small numbers; an
        // Immediate or Tag integer out of i32 saturates, still out of range.
        self.code(name)
            .map(|c| c.clamp(i64::from(i32::MIN), i64::from(i32::MAX)) as i32)
    }

    /// Speed to Jerk Units, the operands MAM, MCLM and MCCM share, read in
    /// their call order.
    ///
    /// # Errors
    /// See [`Bind::number`] and [`Bind::code`].
    pub fn dynamics(&self) -> Result<MoveDynamics, String> {
        Ok(MoveDynamics {
            speed: self.number("Speed")?,
            speed_units: self.code("Speed Units")?,
            accel_rate: self.number("Accel Rate")?,
            accel_units: self.code("Accel Units")?,
            decel_rate: self.number("Decel Rate")?,
            decel_units: self.code("Decel Units")?,
            profile: self.code("Profile")?,
            accel_jerk: self.number("Accel Jerk")?,
            decel_jerk: self.number("Decel Jerk")?,
            jerk_units: self.code("Jerk Units")?,
        })
    }

    /// An array operand (or a radius).
    ///
    /// # Errors
    /// See [`LogixContext::values`].
    pub fn values(&self, name: &str) -> Result<Vec<f64>, String> {
        let (spec, e) = self.operand(name);
        self.ctx.values(spec.name, e)
    }

    /// `REAL[3]` from an array element.
    ///
    /// # Errors
    /// See [`LogixContext::numbers`].
    pub fn vector3(&self, name: &str) -> Result<[f64; 3], String> {
        let (spec, e) = self.operand(name);
        let v = self.ctx.numbers(spec.name, e, 3)?;
        Ok([v[0], v[1], v[2]])
    }

    /// `0` or a REAL array.
    ///
    /// # Errors
    /// See [`LogixContext::optional_array`].
    pub fn optional_array(&self, name: &str) -> Result<Vec<f64>, String> {
        let (spec, e) = self.operand(name);
        self.ctx.optional_array(spec.name, e)
    }

    /// An axis operand.
    ///
    /// # Errors
    /// See [`LogixContext::axis`].
    pub fn axis(&self, name: &str) -> Result<AxisHandle, String> {
        let (spec, e) = self.operand(name);
        self.ctx.axis(spec.name, e)
    }

    /// The `Motion Control` operand, bound on its first use.
    ///
    /// # Errors
    /// See [`LogixContext::instruction`].
    pub fn motion_control(&mut self) -> Result<InstructionHandle, String> {
        let (spec, e) = self.operand("Motion Control");
        self.ctx.instruction(spec.name, e)
    }
}

/// The tag an operand names, or a message: an axis where a tag of type
/// `expected` is needed, or no such name.
///
/// # Errors
/// The message, naming the operand.
pub fn declared_tag<'s>(scene: &'s Scene, what: &str, name: &str, expected: &str) -> Result<&'s Tag, String> {
    scene.tag(name).ok_or_else(|| {
        if scene.axis(name).is_some() {
            format!("{what} {name}: is an axis, expected a {expected} tag")
        } else {
            format!("{what} {name}: not a declared tag")
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::load;
    use planner::axis::{AxisConfig, AxisKind};
    use planner::catalogue;
    use std::path::Path;

    fn scene() -> Scene {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/indexing_table.toml");
        load(&path).expect("fixture loads")
    }

    fn ident(s: &str) -> Expr {
        Expr::Ident(s.to_string())
    }

    fn index(s: &str, i: i64) -> Expr {
        Expr::Index(Box::new(ident(s)), i)
    }

    #[test]
    fn operands_resolve_to_tags_axes_numbers_and_words() {
        let scene = scene();
        let mut task = MotionTask::new(0.004).expect("period");
        let table = task
            .add_axis(AxisConfig::new("Table", AxisKind::Rotary), 0.0)
            .expect("axis");
        let mut instructions = Vec::new();
        let mut ctx = LogixContext {
            scene: &scene,
            values: &scene,
            task: &mut task,
            instructions: &mut instructions,
        };

        let mc1 = ctx
            .instruction("Motion Control", &ident("mc1"))
            .expect("MC1 is a control structure");
        assert_eq!(ctx.instruction("Motion Control", &ident("MC1")), Ok(mc1), "bound once");
        assert!(
            ctx.instruction("Motion Control", &ident("Pos")).is_err(),
            "REAL[2] is not one"
        );
        assert!(ctx.instruction("Motion Control", &ident("Nope")).is_err());
        assert_eq!(ctx.axis("Axis", &ident("table")), Ok(table));
        assert!(ctx.axis("Axis", &ident("Slide")).is_err(), "not bound here");

        assert_eq!(ctx.numbers("Position", &index("Pos", 0), 2), Ok(vec![90.0, 100.0]));
        assert_eq!(ctx.numbers("Position", &ident("Pos"), 1), Ok(vec![90.0]));
        assert!(
            ctx.numbers("Position", &index("Pos", 1), 2).is_err(),
            "runs off the end"
        );
        assert!(ctx.numbers("Position", &ident("Count"), 1).is_err(), "not an array");
        assert_eq!(ctx.number("Speed", &ident("Count")), Ok(3.0));
        assert_eq!(ctx.number("Speed", &index("Pos", 1)), Ok(100.0));
        assert_eq!(ctx.number("Speed", &Expr::Number(-2.5)), Ok(-2.5));
        assert!(ctx.number("Speed", &ident("Enable")).is_err(), "BOOL is not a number");

        // Profile is Immediate: a word or one of its codes, never a tag.
        let profile = catalogue::MCLM.operand("Profile").expect("operand").1;
        assert_eq!(ctx.code(profile, &ident("S-Curve")), Ok(1));
        assert_eq!(ctx.code(profile, &Expr::Integer(0)), Ok(0));
        assert!(ctx.code(profile, &Expr::Integer(2)).is_err());
        assert!(ctx.code(profile, &ident("linear")).is_err());
        assert!(
            ctx.code(profile, &ident("Count")).is_err(),
            "a tag for an Immediate operand"
        );
        // Jerk Units is Immediate or Tag: any integer reaches the instruction.
        let jerk = catalogue::MCLM.operand("Jerk Units").expect("operand").1;
        assert_eq!(ctx.code(jerk, &ident("%OFTIME")), Ok(2));
        assert_eq!(ctx.code(jerk, &Expr::Integer(9)), Ok(9));
        assert_eq!(ctx.code(jerk, &ident("Count")), Ok(3));
        assert!(ctx.code(jerk, &ident("s-curve")).is_err(), "a Profile word");

        assert_eq!(instructions.len(), 1);
        assert_eq!(instructions[0].name, "MC1", "the declared spelling");
        assert_eq!(task.instruction_name(mc1), "MC1");
        assert_eq!(task.motion_bits(mc1), Default::default());
    }

    #[test]
    fn an_instruction_the_twin_does_not_simulate_is_refused_by_name() {
        let scene = scene();
        let mut task = MotionTask::new(0.004).expect("period");
        let mut instructions = Vec::new();
        let mut ctx = LogixContext {
            scene: &scene,
            values: &scene,
            task: &mut task,
            instructions: &mut instructions,
        };
        let e = super::super::compile_logix("mdcc", &[], &mut ctx).expect_err("not simulated");
        assert!(e.message.starts_with("MDCC is a Logix motion instruction"), "{e}");
        assert_eq!(
            super::super::compile_logix("MRP", &[ident("a")], &mut ctx).map(|_| ()),
            Err(BindError::from(
                "MRP takes 5 operands (Axis, Motion Control, Type, Position Select, Position), got 1".to_string()
            ))
        );
    }
}
