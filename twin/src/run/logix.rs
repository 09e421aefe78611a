//! Positional Logix instruction calls (`MCCM(CS1, MC1, …)`): resolving their
//! operands and binding them to the planner.
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
//! # Adding an instruction
//! Each instruction family has a `compile` in its own module (`run/coord.rs`,
//! `run/cam.rs`, `run/mct.rs`) that answers `None` for names it does not
//! own; [`compile`] asks each in turn. A family's `compile` checks the operand
//! count, resolves each operand with the [`LogixContext`] helpers (errors
//! name the operand by its manual name) and returns a [`LogixStep`] whose
//! closure calls the planner; add the mnemonic to [`SIMULATED`].

use super::{AxisBinding, InstructionBinding, number};
use crate::scene::{BaseType, Scene, TagValue};
use crate::st::Expr;
use planner::task::{AxisHandle, InstructionHandle, MotionTask};
use std::fmt;
use std::sync::Arc;

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

impl fmt::Debug for LogixStep {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("LogixStep")
            .field("instruction", &self.instruction)
            .field("control", &self.control)
            .finish_non_exhaustive()
    }
}

/// What a Logix call's operands may refer to while the scene is bound.
pub struct LogixContext<'a> {
    /// The scene.
    pub scene: &'a Scene,
    /// The planner.
    pub task: &'a mut MotionTask,
    /// The scene's axes.
    pub axes: &'a [AxisBinding],
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
        let tag = self
            .scene
            .tag(name)
            .ok_or_else(|| format!("{what} {name}: not a declared tag"))?;
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
        self.axes
            .iter()
            .find(|b| b.name.eq_ignore_ascii_case(name))
            .map(|b| b.handle)
            .ok_or_else(|| format!("{what} {name}: no axis of that name in [[axes]]"))
    }

    /// The number an operand stands for: a literal, a REAL/DINT tag with a
    /// value, or an element of such an array tag.
    ///
    /// # Errors
    /// A message naming the operand otherwise.
    pub fn number(&self, what: &str, operand: &Expr) -> Result<f64, String> {
        number(operand, self.scene)
            .ok_or_else(|| format!("{what} {operand}: expected a number or a REAL/DINT tag with a value"))
    }

    /// An enumeration operand: one of `words` (case-insensitive; returns its
    /// index in `words`), or the integer the manual gives it (`0..words.len()`).
    ///
    /// # Errors
    /// A message listing the words when the operand is neither.
    pub fn choice(&self, what: &str, operand: &Expr, words: &[&str]) -> Result<usize, String> {
        let found = match operand {
            Expr::Ident(w) => words.iter().position(|x| x.eq_ignore_ascii_case(w)),
            Expr::Integer(i) => usize::try_from(*i).ok().filter(|i| *i < words.len()),
            _ => None,
        };
        found.ok_or_else(|| {
            let list: Vec<String> = words.iter().enumerate().map(|(i, w)| format!("{w} ({i})")).collect();
            format!("{what} {operand}: expected one of {}", list.join(", "))
        })
    }

    /// `count` consecutive numbers starting at an array element (`Pos[0]`,
    /// the Logix way of passing an array operand) or at a whole array tag.
    ///
    /// # Errors
    /// A message when the tag is not a numeric array with a value, or is
    /// shorter than `count` from the start element.
    pub fn numbers(&self, what: &str, operand: &Expr, count: usize) -> Result<Vec<f64>, String> {
        let (name, start) = match operand {
            Expr::Ident(name) => (name, 0usize),
            Expr::Index(base, i) => match (base.as_ref(), usize::try_from(*i)) {
                (Expr::Ident(name), Ok(i)) => (name, i),
                _ => return Err(format!("{what} {operand}: expected an array tag or element")),
            },
            _ => {
                return Err(format!(
                    "{what} {operand}: expected an array tag or element, e.g. Pos[0]"
                ));
            }
        };
        let Some(TagValue::Array(items)) = self.scene.tag(name).and_then(|t| t.value.as_ref()) else {
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
}

/// Binds one positional call to the planner.
///
/// # Errors
/// A message naming the operand at fault, or saying that the instruction is
/// not simulated.
pub fn compile(name: &str, operands: &[Expr], ctx: &mut LogixContext<'_>) -> Result<LogixStep, String> {
    let upper = name.to_ascii_uppercase();
    if let Some(step) = super::coord::compile(&upper, operands, ctx) {
        return step;
    }
    if let Some(step) = super::cam::compile(&upper, operands, ctx) {
        return step;
    }
    if let Some(step) = super::mct::compile(&upper, operands, ctx) {
        return step;
    }
    Err(format!(
        "{upper} is a Logix motion instruction the twin does not simulate (it simulates: {})",
        SIMULATED.join(", ")
    ))
}

/// Checks that a call has exactly the manual's operand count.
///
/// # Errors
/// A message giving the expected operands.
pub fn expect_operands(instruction: &str, operands: &[Expr], names: &[&str]) -> Result<(), String> {
    if operands.len() == names.len() {
        Ok(())
    } else {
        Err(format!(
            "{instruction} takes {} operands ({}), got {}",
            names.len(),
            names.join(", "),
            operands.len()
        ))
    }
}

/// The Logix instructions the twin simulates: `cam::CAM_INSTRUCTIONS` and
/// `coord::COORD_INSTRUCTIONS` (a test keeps the lists in step).
pub const SIMULATED: &[&str] = &["MAJ", "MAPC", "MAS", "MCCM", "MCCP", "MCLM", "MCS", "MCT", "MRP"];

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::load;
    use planner::axis::{AxisConfig, AxisKind};
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
        let axes = vec![AxisBinding {
            name: "Table".to_string(),
            handle: table,
            drive: Some(0),
            si_per_unit: 1.0,
            in_position_window: 0.1,
        }];
        let mut instructions = Vec::new();
        let mut ctx = LogixContext {
            scene: &scene,
            task: &mut task,
            axes: &axes,
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

        let profiles = ["trapezoidal", "s-curve"];
        assert_eq!(ctx.choice("Profile", &ident("S-Curve"), &profiles), Ok(1));
        assert_eq!(ctx.choice("Profile", &Expr::Integer(0), &profiles), Ok(0));
        assert!(ctx.choice("Profile", &Expr::Integer(2), &profiles).is_err());
        assert!(ctx.choice("Profile", &ident("linear"), &profiles).is_err());

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
            task: &mut task,
            axes: &[],
            instructions: &mut instructions,
        };
        let e = compile("mdcc", &[], &mut ctx).expect_err("not simulated");
        assert!(e.starts_with("MDCC is a Logix motion instruction"), "{e}");
        assert_eq!(
            expect_operands("MRP", &[ident("a")], &["Axis", "Motion Control"]),
            Err("MRP takes 2 operands (Axis, Motion Control), got 1".to_string())
        );
    }
}
