//! MCT calls bound to the planner: `MCT(Source System, Target System,
//! Motion Control, Orientation, Translation)`.
//!
//! * Orientation and Translation are `REAL[3]` operands (`Orient[0]` or a
//!   whole array tag, three elements from there).
//! * The `geometry` tables of the source and target `COORDINATE_SYSTEM`
//!   tags give the planner each system's geometry and transform dimension
//!   (a system without one is a Cartesian gantry of its primary axes).
//! * The check that the target robot's URDF has the geometry's kinematics
//!   is the plant's (`plant/transform.rs`).

use super::bind::{Bind, LogixStep};
use crate::st::Expr;
use planner::task::{MotionTask, TransformGeometry};
use std::sync::Arc;

/// Binds an MCT call.
///
/// # Errors
/// A message naming the operand at fault.
pub fn bind(b: &mut Bind<'_, '_>) -> Result<LogixStep, String> {
    let source = b.coordinate_system("Source System")?;
    let target = b.coordinate_system("Target System")?;
    let control = b.motion_control()?;
    let orientation = b.vector3("Orientation")?;
    let translation = b.vector3("Translation")?;
    for (system, name) in [(source, "Source System"), (target, "Target System")] {
        let Expr::Ident(tag) = b.operand(name).1 else { continue };
        if let Some(g) = b.ctx.scene.tag(tag).and_then(|t| t.geometry.as_ref()) {
            b.ctx.task.set_transform_geometry(
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
