//! MCT in the twin: the positional `MCT(Source System, Target System,
//! Motion Control, Orientation, Translation)` call and the load-time check
//! that each transform's target robot (its URDF chain) has the kinematics of
//! the target system's `geometry` table.
//!
//! * Orientation and Translation are REAL[3] operands (`Orient[0]` or a
//!   whole array tag, three elements from there).
//! * The `geometry` tables of the source and target `COORDINATE_SYSTEM`
//!   tags give the planner each system's geometry and transform dimension
//!   (a system without one is a Cartesian gantry of its primary axes).
//! * MCT takes revolute joint axes in degrees (as Logix), so a target axis
//!   on a revolute URDF joint must have `units = "deg"`; the geometry's
//!   lengths are in the source system's coordinate units.
//! * [`check_transforms`] runs [`crate::kinematics_check::check`] for every
//!   MCT call of the program and refuses the scene on a mismatch, naming the
//!   `geometry` table's line and the distance. A geometry the planner
//!   refuses (a zero link length, …) is not checked here: the MCT reports it
//!   at run time with its ERR/EXERR, as on the controller.

use super::logix::{LogixContext, LogixStep, expect_operands};
use super::{AxisBinding, RunError};
use crate::kinematics_check::{ChainMapping, check};
use crate::scene::{Scene, TagValue};
use crate::st::{Args, Expr};
use crate::urdf::RobotModel;
use planner::mct::{Geometry, JointKind};
use planner::task::{MotionTask, TransformGeometry};
use std::sync::Arc;

const MCT_OPERANDS: &[&str] = &[
    "Source System",
    "Target System",
    "Motion Control",
    "Orientation",
    "Translation",
];

/// Compiles an MCT call; `None` for any other instruction.
pub fn compile(upper: &str, operands: &[Expr], ctx: &mut LogixContext<'_>) -> Option<Result<LogixStep, String>> {
    (upper == "MCT").then(|| compile_mct(operands, ctx))
}

fn compile_mct(operands: &[Expr], ctx: &mut LogixContext<'_>) -> Result<LogixStep, String> {
    expect_operands("MCT", operands, MCT_OPERANDS)?;
    let n = |i: usize| MCT_OPERANDS[i];
    let source = super::coord::coordinate_system(ctx, n(0), &operands[0])?;
    let target = super::coord::coordinate_system(ctx, n(1), &operands[1])?;
    let control = ctx.instruction(n(2), &operands[2])?;
    let three = |i: usize| -> Result<[f64; 3], String> {
        let v = ctx.numbers(n(i), &operands[i], 3)?;
        Ok([v[0], v[1], v[2]])
    };
    let orientation = three(3)?;
    let translation = three(4)?;
    for (system, operand) in [(source, &operands[0]), (target, &operands[1])] {
        let Expr::Ident(name) = operand else { continue };
        if let Some(g) = ctx.scene.tag(name).and_then(|t| t.geometry.as_ref()) {
            ctx.task.set_transform_geometry(
                system,
                TransformGeometry {
                    kind: g.kind,
                    params: g.params,
                    transform_dimension: g.transform_dimension,
                },
            );
        }
    }
    Ok(LogixStep {
        instruction: "MCT",
        control: Some(control),
        run: Arc::new(move |task: &mut MotionTask| task.execute_mct(control, source, target, orientation, translation)),
    })
}

/// Checks every transform of the program: the target system's URDF chain
/// against its MCT geometry.
///
/// # Errors
/// [`RunError::Kinematics`] naming the `geometry` table's line, with the
/// mismatch (what, by how much, at which joint configuration), a mapping
/// error, or a revolute joint axis not in degrees.
pub(super) fn check_transforms(scene: &Scene, model: &RobotModel, axes: &[AxisBinding]) -> Result<(), RunError> {
    for step in &scene.program {
        let Args::Positional(operands) = &step.call.args else {
            continue;
        };
        if !step.call.name.value.eq_ignore_ascii_case("MCT") || operands.len() != MCT_OPERANDS.len() {
            continue;
        }
        let (Expr::Ident(source), Expr::Ident(target)) = (&operands[0].value, &operands[1].value) else {
            continue;
        };
        let (Some(source), Some(target)) = (scene.tag(source), scene.tag(target)) else {
            continue;
        };
        let Some(settings) = &target.geometry else { continue };
        let fail = |message: String| RunError::Kinematics {
            scene: scene.path.clone(),
            line: settings.location.line,
            column: settings.location.column,
            message: format!("coordinate system '{}': {message}", target.name),
        };
        let Ok(geometry) = Geometry::new(settings.kind, &settings.params, settings.transform_dimension) else {
            continue;
        };
        let members = |tag: &crate::scene::Tag| match &tag.value {
            Some(TagValue::Axes(m)) => m.clone(),
            _ => Vec::new(),
        };
        let binding = |name: &String| axes.iter().find(|a| a.name.eq_ignore_ascii_case(name));
        let metres_per_unit = members(source).first().and_then(binding).map_or(1.0, |b| b.si_per_unit);
        let needed = geometry.dimension() + usize::from(geometry.shares_third_axis());
        let kinds = geometry.joint_kinds();
        let mut joints = Vec::new();
        for (i, member) in members(target).iter().take(needed).enumerate() {
            let axis = scene
                .axes
                .iter()
                .find(|a| a.name.eq_ignore_ascii_case(member))
                .ok_or_else(|| fail(format!("member '{member}' is not an axis")))?;
            if kinds[i] == JointKind::Revolute
                && binding(member).is_some_and(|b| (b.si_per_unit - 1f64.to_radians()).abs() > 1e-15)
            {
                return Err(fail(format!(
                    "J{} axis '{member}' is on a revolute joint: MCT needs its units in deg",
                    i + 1
                )));
            }
            let Some(joint) = &axis.joint else {
                return Err(fail(format!(
                    "J{} axis '{member}' is virtual: a transform's target axes drive joints",
                    i + 1
                )));
            };
            joints.push(joint.clone());
        }
        let (Some(base_link), Some(tool_link)) = (&settings.base_link, &settings.tool_link) else {
            return Err(fail(
                "a transform's target geometry needs base_link and tool_link to be checked against the URDF".into(),
            ));
        };
        let mapping = ChainMapping {
            joints,
            base_link: base_link.clone(),
            tool_link: tool_link.clone(),
            platform_joints: settings.platform_joints.clone(),
            forearm_joints: settings.forearm_joints.clone(),
            forearm_tip_links: settings.forearm_tip_links.clone(),
            ball_links: settings.ball_links.clone(),
        };
        check(model, &geometry, &mapping, metres_per_unit).map_err(|e| fail(e.to_string()))?;
    }
    Ok(())
}
