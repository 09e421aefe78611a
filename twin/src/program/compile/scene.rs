//! Compiling a scene's program: every task's routines, then every
//! `[[program]]` step's call and trigger.

use super::{Compiler, Result};
use crate::program::bindings::Env;
use crate::program::ir::{CompiledProgram, CompiledStep, StepTrigger};
use crate::program::memory::Memory;
use crate::scene::{Dialect, ProgramDef, Scene, Trigger};

/// Compiles a program's routines: its function-block calls first (so that
/// their outputs compile wherever they are read), then every routine.
///
/// # Errors
/// The first compile error, pointing into its routine.
pub fn program(
    p: &ProgramDef,
    mem: &Memory,
    env: &mut Env<'_, '_>,
    traced: &[(&crate::scene::TraceRung, usize)],
) -> Result<CompiledProgram> {
    let defs: Vec<_> = std::iter::once(&p.main).chain(&p.routines).collect();
    let names: Vec<String> = defs.iter().map(|r| r.name.clone()).collect();
    for def in defs.iter().filter(|d| d.dialect == Dialect::Iec) {
        let mut compiler = Compiler::new(mem, Some(&p.name), &names, def.dialect, env, true);
        compiler.bind_blocks(&def.routine.body)?;
    }
    let mut routines = Vec::with_capacity(defs.len());
    let mut init = Vec::new();
    let mut added: Vec<crate::program::ir::AoiRoutine> = Vec::new();
    for def in &defs {
        let mut compiler = Compiler::new(mem, Some(&p.name), &names, def.dialect, env, true);
        compiler.aoi_base = defs.len() + added.len();
        if let Some(rungs) = &def.routine.rungs {
            compiler.traced_rungs = traced
                .iter()
                .filter(|(t, _)| t.program == p.name && t.routine == def.name)
                .map(|(t, slot)| (t.rung, *slot))
                .collect();
            let compiled = if mem.aliases.is_empty() {
                compiler.rungs(rungs)
            } else {
                let mut rungs = rungs.clone();
                for r in &mut rungs {
                    crate::st::ast::Element::visit_mut(&mut r.elements, &mut |c| {
                        c.refs_mut(&mut |r| compiler.dealias(r));
                    });
                }
                compiler.rungs(&rungs)
            };
            let files = compiler.env.files;
            routines.push(compiled.map_err(|d| super::ladder::in_rung(d, rungs, files, &p.name, &def.name))?);
        } else if mem.aliases.is_empty() {
            routines.push(compiler.block(&def.routine.body)?);
        } else {
            let mut body = def.routine.body.clone();
            crate::st::ast::refs_mut(&mut body, &mut |r| compiler.dealias(r));
            routines.push(compiler.block(&body)?);
        }
        init.append(&mut compiler.init);
        added.append(&mut compiler.aoi_routines);
    }
    let mut routine_paths: Vec<_> = defs.iter().map(|d| d.path.clone()).collect();
    let aoi_from = routines.len();
    let mut prescan = Vec::new();
    for r in added {
        if r.prescan {
            prescan.push(routines.len());
        }
        routine_paths.push(r.path);
        routines.push(r.body);
    }
    Ok(CompiledProgram {
        name: p.name.clone(),
        routine_paths,
        routines,
        init,
        aoi_from,
        aoi_prescan: prescan,
    })
}

/// Compiles every step of the scene: its call, then its `when`, in order
/// (a `when` may read the outputs of the instances earlier calls bound).
/// The warnings a call gives are about its `call` field.
///
/// # Errors
/// The first error, pointing into the step's string.
pub fn steps(scene: &Scene, mem: &Memory, env: &mut Env<'_, '_>) -> Result<Vec<CompiledStep>> {
    let mut steps = Vec::with_capacity(scene.program.len());
    for (index, step) in scene.program.iter().enumerate() {
        let field = |f: &str| format!("program[{index}].{f}");
        let warned = env.bindings.warnings.len();
        let mut compiler = Compiler::new(mem, None, &[], Dialect::Logix, env, false);
        let mut call = step.call.clone();
        call.refs_mut(&mut |r| compiler.dealias(r));
        let call = compiler
            .instruction_call(&call)
            .map_err(|d| Box::new((*d).in_field(field("call"))))?;
        let trigger = match &step.trigger {
            Trigger::At { time_s } => StepTrigger::At(*time_s),
            Trigger::When { condition, delay_s } => StepTrigger::When {
                condition: compiler
                    .condition(&compiler.dealias_expr(condition))
                    .map_err(|d| Box::new((*d).in_field(field("when"))))?,
                delay_s: *delay_s,
            },
        };
        for w in &mut env.bindings.warnings[warned..] {
            w.field = Some(field("call"));
        }
        steps.push(CompiledStep { trigger, call, index });
    }
    Ok(steps)
}

/// Checks that every alias stands for something readable in its scope
/// (after the routines, so that they bind the planner first, in their
/// order).
///
/// # Errors
/// An alias whose target names nothing, pointing into its `alias_for`.
pub fn aliases(scene: &Scene, mem: &Memory, env: &mut Env<'_, '_>) -> Result<()> {
    let scopes =
        std::iter::once((None, &scene.aliases)).chain(scene.programs().map(|p| (Some(p.name.as_str()), &p.aliases)));
    for (program, aliases) in scopes {
        for a in aliases {
            let mut compiler = Compiler::new(mem, program, &[], Dialect::Logix, env, false);
            let mut target = a.target.clone();
            compiler.dealias(&mut target);
            if mem.alias(program, &target.name).is_some() {
                let d = compiler.error(
                    a.target.span,
                    format!("alias '{}' stands for itself through other aliases", a.name),
                    "an alias circle",
                );
                return Err(d);
            }
            let expr = crate::st::ast::Expr {
                span: a.target.span,
                kind: crate::st::ast::ExprKind::Ref(target),
            };
            compiler.traced(&expr).map_err(|d| {
                Box::new((*d).with_note(format!("alias '{}' stands for {}", a.name, show_ref(&a.target))))
            })?;
        }
    }
    Ok(())
}

fn show_ref(r: &crate::st::ast::Ref) -> String {
    let mut s = r.name.clone();
    for a in &r.path {
        match a {
            crate::st::ast::Access::Member(m, _) => {
                s.push('.');
                s.push_str(m);
            }
            crate::st::ast::Access::Bit(b) => {
                s.push('.');
                s.push_str(&b.to_string());
            }
            crate::st::ast::Access::Index(_) => s.push_str("[…]"),
            crate::st::ast::Access::BitExpr(_) => s.push_str(".[…]"),
        }
    }
    s
}
