//! What the program binds to the planner when it loads: each
//! `MOTION_INSTRUCTION`, `COORDINATE_SYSTEM` and `CAM_PROFILE` tag and each
//! function-block instance the program names becomes a planner handle on
//! its first use, in the order the program first names them (the trace's
//! and the recording's order); and the instructions the program calls.

use crate::scene::{BaseType, Scene, Tag, TagValue};
use crate::source::{Diagnostic, Files};
use planner::task::instructions::Instruction;
use planner::task::{
    AxisHandle, CamProfileHandle, CoordHandle, FbHandle, InstructionHandle, MotionTask, TransformGeometry,
};
use std::collections::HashMap;

/// A function-block instance of the program.
#[derive(Debug, Clone)]
pub struct FbBinding {
    /// Instance tag name (`Program.Tag` for a program tag).
    pub name: String,
    /// Planner handle.
    pub handle: FbHandle,
}

/// A `MOTION_INSTRUCTION` tag of the program (a Logix control structure).
#[derive(Debug, Clone)]
pub struct InstructionBinding {
    /// Tag name (`Program.Tag` for a program tag).
    pub name: String,
    /// Planner handle.
    pub handle: InstructionHandle,
}

/// An MCT call's source and target systems, by tag name.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TransformLink {
    /// The source system's tag.
    pub source: String,
    /// The target system's tag.
    pub target: String,
}

/// The handles bound so far, and what the program calls.
#[derive(Debug, Default)]
pub struct Bindings {
    /// Control structures, in first-use order.
    pub instructions: Vec<InstructionBinding>,
    /// Function-block instances, in first-use order.
    pub fbs: Vec<FbBinding>,
    /// Every instruction the program calls, once each.
    pub calls: Vec<&'static Instruction>,
    /// Warnings found at load (calls whose constant operands the
    /// instruction refuses).
    pub warnings: Vec<Diagnostic>,
}

impl Bindings {
    /// Whether the program calls `instruction` (a step or a routine).
    #[must_use]
    pub fn calls(&self, instruction: &Instruction) -> bool {
        self.calls.contains(&instruction)
    }
}

/// The tag declarations by qualified name (lower case): controller tags,
/// then each program's as `Program.Tag`.
#[derive(Debug, Default)]
pub struct Declarations<'s> {
    by_name: HashMap<String, &'s Tag>,
}

impl<'s> Declarations<'s> {
    /// The declarations of `scene`.
    #[must_use]
    pub fn of(scene: &'s Scene) -> Self {
        let mut by_name = HashMap::new();
        for t in &scene.tags {
            by_name.insert(t.name.to_lowercase(), t);
        }
        for p in scene.programs() {
            for t in &p.tags {
                by_name.insert(format!("{}.{}", p.name, t.name).to_lowercase(), t);
            }
        }
        Declarations { by_name }
    }

    /// The declaration of the tag stored as `name` (qualified for a
    /// program tag).
    #[must_use]
    pub fn get(&self, name: &str) -> Option<&'s Tag> {
        self.by_name.get(&name.to_lowercase()).copied()
    }
}

/// What the compiler binds with: the scene, its declarations and files,
/// the planner and the handles bound so far.
pub struct Env<'e, 's> {
    /// The scene.
    pub scene: &'s Scene,
    /// Its tag declarations.
    pub decls: &'e Declarations<'s>,
    /// Its files (for diagnostics).
    pub files: &'e Files,
    /// The planner: its axes are the scene's `[[axes]]`.
    pub task: &'e mut MotionTask,
    /// The handles bound so far.
    pub bindings: &'e mut Bindings,
}

impl Env<'_, '_> {
    /// The planner axis called `name` (case-insensitive).
    #[must_use]
    pub fn axis(&self, name: &str) -> Option<AxisHandle> {
        self.task
            .axis_handles()
            .find(|h| self.task.axis_config(*h).name.eq_ignore_ascii_case(name))
    }

    /// The control structure of the `MOTION_INSTRUCTION` tag stored as
    /// `name`, added to the planner on its first use.
    pub fn control(&mut self, name: &str) -> InstructionHandle {
        if let Some(b) = self
            .bindings
            .instructions
            .iter()
            .find(|b| b.name.eq_ignore_ascii_case(name))
        {
            return b.handle;
        }
        let handle = self.task.add_instruction(name.to_owned());
        self.bindings.instructions.push(InstructionBinding {
            name: name.to_owned(),
            handle,
        });
        handle
    }

    /// The cam profile of the `CAM_PROFILE` tag stored as `name` (`len`
    /// elements), added to the planner on its first use.
    pub fn cam_profile(&mut self, name: &str, len: usize) -> CamProfileHandle {
        self.task
            .find_cam_profile(name)
            .unwrap_or_else(|| self.task.add_cam_profile(name.to_owned(), len))
    }

    /// The coordinate system of the controller tag `tag`, added to the
    /// planner on its first use with its member axes, settings, master
    /// axis and MCT geometry.
    ///
    /// # Errors
    /// The planner's refusal of the system (as a message).
    pub fn coordinate_system(&mut self, tag: &Tag) -> Result<CoordHandle, String> {
        if let Some(h) = self
            .task
            .coord_handles()
            .find(|h| self.task.coord_config(*h).name.eq_ignore_ascii_case(&tag.name))
        {
            return Ok(h);
        }
        let (Some(TagValue::Axes(members)), Some(settings), BaseType::CoordinateSystem) =
            (&tag.value, &tag.coordinate_system, tag.ty.base)
        else {
            return Err(format!("'{}' is a {} tag, not a COORDINATE_SYSTEM", tag.name, tag.ty));
        };
        let mut axes = Vec::with_capacity(members.len());
        for m in members {
            axes.push(
                self.axis(m)
                    .ok_or_else(|| format!("axis '{m}' is not in the planner"))?,
            );
        }
        let handle = self
            .task
            .add_coordinate_system(settings.system.clone(), &axes)
            .map_err(|e| e.to_string())?;
        if let Some(master) = &settings.master_axis {
            let master = self
                .axis(master)
                .ok_or_else(|| format!("axis '{master}' is not in the planner"))?;
            self.task.set_coordinate_system_master(handle, Some(master));
        }
        if let Some(g) = &tag.geometry {
            self.task.set_transform_geometry(
                handle,
                TransformGeometry {
                    kind: g.kind,
                    params: g.params,
                    transform_dimension: g.transform_dimension,
                },
            );
        }
        Ok(handle)
    }

    /// The function-block instance of the tag stored as `name`, created on
    /// its first call with the axis that call names.
    ///
    /// # Errors
    /// A message when the first call names no axis, or a later call
    /// another axis.
    pub fn instance(&mut self, name: &str, axis: Option<AxisHandle>) -> Result<FbHandle, String> {
        if let Some(b) = self.bindings.fbs.iter().find(|f| f.name.eq_ignore_ascii_case(name)) {
            if axis.is_some_and(|new| new != self.task.fb_axis(b.handle)) {
                return Err(format!(
                    "'{name}' was called with another axis before; an instance drives one axis"
                ));
            }
            return Ok(b.handle);
        }
        let axis = axis.ok_or_else(|| format!("the first call of '{name}' must name its axis (Axis := ...)"))?;
        let handle = self.task.add_move_modulo(name.to_owned(), axis);
        if let Some(tag) = self.decls.get(name) {
            let inputs = planner::modulo::MoveModuloInputs {
                options: tag.move_options,
                ..self.task.move_modulo_inputs(handle)
            };
            self.task.set_move_modulo_inputs(handle, inputs);
        }
        self.bindings.fbs.push(FbBinding {
            name: name.to_owned(),
            handle,
        });
        Ok(handle)
    }

    /// Notes that the program calls `instruction`.
    pub fn note_call(&mut self, instruction: &'static Instruction) {
        if !self.bindings.calls(instruction) {
            self.bindings.calls.push(instruction);
        }
    }
}
