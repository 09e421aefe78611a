//! Logix cam and single-axis calls: MCCP, MAPC, MRP, MAM, and the MAJ jog /
//! MAS stop that also drive cam masters, bound to planner calls (see
//! [`super::bind`]).
//!
//! Operands are the manual's, in its order:
//! * `MCCP(MotionControl, Cam, Length, StartSlope, EndSlope, CamProfile)` —
//!   `Cam` is a `CAM[N]` tag or element (`Cam[0]`: the elements from that
//!   index; elements the scene does not list are the controller's initial
//!   values, master 0, slave 0, linear), `CamProfile` a `CAM_PROFILE[N]` tag
//!   (element `[0]` only).
//! * `MAPC(SlaveAxis, MasterAxis, MotionControl, Direction, CamProfile,
//!   SlaveScaling, MasterScaling, ExecutionMode, ExecutionSchedule,
//!   MasterLockPosition, CamLockPosition, CamType, MasterReference,
//!   MasterDirection)` — enumerations by word or number: Direction
//!   `Same Opposite Reverse Unchanged`; ExecutionMode `Once Continuous
//!   Persistent`; ExecutionSchedule `Immediate Pending ForwardOnly ReverseOnly
//!   Bidirectional`; CamType `NewCam ReplaceAndRestart ReplaceAndContinue`;
//!   MasterReference `Actual Command`; MasterDirection `Bidirectional
//!   ForwardOnly ReverseOnly`.
//! * `MRP(Axis, MotionControl, Type, PositionSelect, Position)` — Type
//!   `Absolute Relative`, PositionSelect `Actual Command`.
//! * `MAJ(Axis, MotionControl, Direction, Speed, SpeedUnits, AccelRate,
//!   AccelUnits, DecelRate, DecelUnits, Profile)` — the manual's first ten
//!   operands (the jerk, merge and lock operands are not simulated):
//!   Direction `Forward Reverse`, units `UnitsPerSec` / `UnitsPerSec2` or
//!   `%ofMaximum`, Profile `Trapezoidal S-Curve`.
//! * `MAM(Axis, MotionControl, MoveType, Position, Speed, SpeedUnits,
//!   AccelRate, AccelUnits, DecelRate, DecelUnits, Profile, AccelJerk,
//!   DecelJerk, JerkUnits, Merge, MergeSpeed, LockPosition, LockDirection,
//!   EventDistance, CalculatedData)` — Merge `Disabled Enabled`, MergeSpeed
//!   `Programmed Current`; the rules are [`planner::mam`]'s.
//! * `MAG(SlaveAxis, MasterAxis, MotionControl, Direction, Ratio,
//!   SlaveCounts, MasterCounts, MasterReference, RatioFormat, Clutch,
//!   AccelRate, AccelUnits)` — Direction `Same Opposite Reverse Unchanged`,
//!   MasterReference `Actual Command`, RatioFormat `Real
//!   Fraction_Slave_Master_Counts`, Clutch `Enabled Disabled`; the rules are
//!   [`planner::mag`]'s.
//! * `MAS(Axis, MotionControl, StopType, ChangeDecel, DecelRate, DecelUnits)`
//!   — the manual's first six operands: StopType `All Jog Move Gear Home Tune
//!   Test TimeCam PositionCam MasterOffsetMove DirectControl`, ChangeDecel
//!   `No Yes`.
//!
//! Each call is one scan of a one-shot rung: the planner executes it, and
//! `.EN` clears at the next coarse update once `.DN` or `.ER` is set.

use super::bind::{Bind, LogixContext, LogixStep, declared_tag};
use crate::scene::{BaseType, SegmentType, TagValue};
use crate::st::Expr;
use planner::jog::{MajOperands, MasOperands};
use planner::mag::MagOperands;
use planner::mam::MamOperands;
use planner::mapc::MapcOperands;
use planner::mccp::CamElement;
use planner::task::{CamProfileHandle, MapcCall};

/// Binds an MCCP, MAPC, MRP, MAJ, MAM, MAG or MAS call.
///
/// # Errors
/// A message naming the operand at fault.
pub fn bind(b: &mut Bind<'_, '_>) -> Result<LogixStep, String> {
    match b.instruction.mnemonic {
        "MCCP" => mccp(b),
        "MAPC" => mapc(b),
        "MRP" => mrp(b),
        "MAJ" => maj(b),
        "MAM" => mam(b),
        "MAG" => mag(b),
        _ => mas(b),
    }
}

/// The `CAM_PROFILE` tag an operand names, added to the planner on first use.
fn cam_profile(ctx: &mut LogixContext<'_>, operand: &Expr) -> Result<CamProfileHandle, String> {
    let what = "Cam Profile";
    let name = match operand {
        Expr::Ident(name) => name,
        Expr::Index(base, 0) => match base.as_ref() {
            Expr::Ident(name) => name,
            _ => return Err(format!("{what} {operand}: expected a CAM_PROFILE tag")),
        },
        Expr::Index(_, _) => {
            return Err(format!(
                "{what} {operand}: only element [0] of a CAM_PROFILE array is allowed"
            ));
        }
        _ => return Err(format!("{what} {operand}: expected a CAM_PROFILE tag")),
    };
    let tag = declared_tag(ctx.scene, what, name, "CAM_PROFILE")?;
    if tag.ty.base != BaseType::CamProfile {
        return Err(format!("{what} {name}: is a {} tag, expected CAM_PROFILE", tag.ty));
    }
    Ok(ctx.task.find_cam_profile(&tag.name).unwrap_or_else(|| {
        ctx.task
            .add_cam_profile(tag.name.clone(), tag.ty.array_len.unwrap_or(1))
    }))
}

/// The cam points an operand names (`Cam[2]`: from element 2), as MCCP sees
/// them.
/// The whole CAM array the operand names and the index it starts at.
fn cam_points(ctx: &LogixContext<'_>, operand: &Expr) -> Result<(Vec<CamElement>, usize), String> {
    let what = "Cam";
    let (name, start) = match operand {
        Expr::Ident(name) => (name, 0usize),
        Expr::Index(base, i) => match (base.as_ref(), usize::try_from(*i)) {
            (Expr::Ident(name), Ok(i)) => (name, i),
            _ => return Err(format!("{what} {operand}: expected a CAM tag or element")),
        },
        _ => return Err(format!("{what} {operand}: expected a CAM tag or element, e.g. Cam[0]")),
    };
    let Some(tag) = ctx.scene.tag(name) else {
        return Err(format!("{what} {operand}: '{name}' is not a declared tag"));
    };
    let value = ctx.values.tag_value(name);
    let Some(TagValue::CamPoints(points)) = value.as_deref() else {
        return Err(format!("{what} {operand}: '{name}' is not a CAM tag with points"));
    };
    // The elements the scene leaves out hold the controller's initial values
    // (master 0, slave 0, linear), as in a CAM[N] tag on the controller.
    let size = tag.ty.array_len.unwrap_or(1).max(points.len());
    if start >= size {
        return Err(format!(
            "{what} {operand}: '{name}' has {size} elements, none from [{start}]"
        ));
    }
    let mut elements: Vec<CamElement> = points
        .iter()
        .map(|p| CamElement {
            master: p.master,
            slave: p.slave,
            segment_type: match p.segment_type {
                SegmentType::Linear => 0,
                _ => 1,
            },
        })
        .collect();
    elements.resize(size, CamElement::default());
    Ok((elements, start))
}

fn count(b: &Bind<'_, '_>, name: &str) -> Result<usize, String> {
    let x = b.number(name)?;
    if x >= 0.0 && x.fract() == 0.0 && x <= f64::from(u16::MAX) {
        Ok(x as usize)
    } else {
        let (spec, e) = b.operand(name);
        Err(format!("{} {e}: expected a UINT (0..=65535)", spec.name))
    }
}

impl Bind<'_, '_> {
    fn cam_profile(&mut self, name: &str) -> Result<CamProfileHandle, String> {
        let (_, e) = self.operand(name);
        cam_profile(self.ctx, e)
    }
}

fn mccp(b: &mut Bind<'_, '_>) -> Result<LogixStep, String> {
    let control = b.motion_control()?;
    let (cam, start) = cam_points(b.ctx, b.operand("Cam").1)?;
    let length = count(b, "Length")?;
    let start_slope = b.number("Start Slope")?;
    let end_slope = b.number("End Slope")?;
    let profile = b.cam_profile("Cam Profile")?;
    Ok(LogixStep::one_shot("MCCP", control, move |task| {
        // The outcome is in the control structure (.DN or .ER/ERR/EXERR/SEGMENT).
        let _ = task.mccp_from(control, &cam, start, length, start_slope, end_slope, profile);
    }))
}

fn mapc(b: &mut Bind<'_, '_>) -> Result<LogixStep, String> {
    let slave = b.axis("Slave Axis")?;
    let master = b.axis("Master Axis")?;
    let control = b.motion_control()?;
    let direction = b.code_i32("Direction")?;
    let profile = b.cam_profile("Cam Profile")?;
    let o = MapcOperands {
        direction,
        slave_scaling: b.number("Slave Scaling")?,
        master_scaling: b.number("Master Scaling")?,
        execution_mode: b.code_i32("Execution Mode")?,
        execution_schedule: b.code_i32("Execution Schedule")?,
        master_lock_position: b.number("Master Lock Position")?,
        cam_lock_position: b.number("Cam Lock Position")?,
        cam_type: b.code_i32("Cam Type")?,
        master_reference: b.code_i32("Master Reference")?,
        master_direction: b.code_i32("Master Direction")?,
    };
    b.ctx.task.declare_cam_slave(slave);
    let call = MapcCall {
        slave,
        master,
        motion_control: control,
        cam_profile: profile,
        operands: o,
    };
    Ok(LogixStep::one_shot("MAPC", control, move |task| {
        let _ = task.mapc(call);
    }))
}

fn mrp(b: &mut Bind<'_, '_>) -> Result<LogixStep, String> {
    let axis = b.axis("Axis")?;
    let control = b.motion_control()?;
    let kind = b.code_i32("Type")?;
    let select = b.code_i32("Position Select")?;
    let position = b.number("Position")?;
    Ok(LogixStep::one_shot("MRP", control, move |task| {
        let _ = task.mrp(axis, control, kind, select, position);
    }))
}

fn maj(b: &mut Bind<'_, '_>) -> Result<LogixStep, String> {
    let axis = b.axis("Axis")?;
    let control = b.motion_control()?;
    let o = MajOperands {
        direction: b.code_i32("Direction")?,
        speed: b.number("Speed")?,
        speed_units: b.code_i32("Speed Units")?,
        accel_rate: b.number("Accel Rate")?,
        accel_units: b.code_i32("Accel Units")?,
        decel_rate: b.number("Decel Rate")?,
        decel_units: b.code_i32("Decel Units")?,
        profile: b.code_i32("Profile")?,
    };
    Ok(LogixStep::one_shot("MAJ", control, move |task| {
        let _ = task.maj(axis, control, &o);
    }))
}

fn mam(b: &mut Bind<'_, '_>) -> Result<LogixStep, String> {
    let axis = b.axis("Axis")?;
    let control = b.motion_control()?;
    let o = MamOperands {
        move_type: b.integer("Move Type")?,
        position: b.number("Position")?,
        dynamics: b.dynamics()?,
        merge: b.code("Merge")?,
        merge_speed: b.code("Merge Speed")?,
        lock_direction: b.code("Lock Direction")?,
    };
    b.number("Lock Position")?;
    b.optional_array("Event Distance")?;
    b.optional_array("Calculated Data")?;
    Ok(LogixStep::one_shot("MAM", control, move |task| {
        let _ = task.mam(axis, control, &o);
    }))
}

fn mag(b: &mut Bind<'_, '_>) -> Result<LogixStep, String> {
    let slave = b.axis("Slave Axis")?;
    let master = b.axis("Master Axis")?;
    let control = b.motion_control()?;
    let o = MagOperands {
        direction: b.code_i32("Direction")?,
        ratio: b.number("Ratio")?,
        slave_counts: dint(b.integer("Slave Counts")?, "Slave Counts")?,
        master_counts: dint(b.integer("Master Counts")?, "Master Counts")?,
        master_reference: b.code_i32("Master Reference")?,
        ratio_format: b.code_i32("Ratio Format")?,
        clutch: b.code_i32("Clutch")?,
        accel_rate: b.number("Accel Rate")?,
        accel_units: b.code_i32("Accel Units")?,
    };
    Ok(LogixStep::one_shot("MAG", control, move |task| {
        let _ = task.mag(slave, master, control, &o);
    }))
}

/// A DINT operand's value.
fn dint(x: i64, what: &str) -> Result<i32, String> {
    i32::try_from(x).map_err(|_| format!("{what} {x}: outside the DINT range"))
}

fn mas(b: &mut Bind<'_, '_>) -> Result<LogixStep, String> {
    let axis = b.axis("Axis")?;
    let control = b.motion_control()?;
    let o = MasOperands {
        stop_type: b.code_i32("Stop Type")?,
        change_decel: b.code_i32("Change Decel")?,
        decel_rate: b.number("Decel Rate")?,
        decel_units: b.code_i32("Decel Units")?,
    };
    Ok(LogixStep::one_shot("MAS", control, move |task| {
        let _ = task.mas(axis, control, &o);
    }))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::program::InstructionBinding;
    use crate::scene::{Scene, load};
    use crate::st::parse_call;
    use planner::axis::{AxisConfig, AxisKind};
    use planner::task::MotionTask;
    use std::path::Path;

    fn scene() -> Scene {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/rotary_knife.toml");
        load(&path).expect("scene loads")
    }

    fn compile_text(text: &str, scene: &Scene, task: &mut MotionTask) -> Result<LogixStep, String> {
        let call = parse_call(text).expect("parses");
        let crate::st::Args::Positional(ops) = &call.args else {
            panic!("positional")
        };
        let operands: Vec<Expr> = ops.iter().map(|o| o.value.clone()).collect();
        let mut instructions: Vec<InstructionBinding> = Vec::new();
        let mut ctx = LogixContext {
            scene,
            values: scene,
            task,
            instructions: &mut instructions,
        };
        super::super::compile_logix(&call.name.value, &operands, &mut ctx).map_err(|e| e.message)
    }

    #[test]
    fn cam_calls_bind_and_bad_operands_are_named() {
        let scene = scene();
        let mut task = MotionTask::new(0.004).expect("period");
        let conveyor = task
            .add_axis(AxisConfig::new("Conveyor", AxisKind::Linear), 0.0)
            .expect("axis");
        let knife = task
            .add_axis(AxisConfig::new("Knife", AxisKind::Rotary), 0.0)
            .expect("axis");
        let _ = (conveyor, knife);

        let mccp = compile_text(
            "MCCP(MCCP_1, KnifeCam[0], 4, 1.2, 1.2, KnifeProfile[0])",
            &scene,
            &mut task,
        )
        .expect("MCCP binds");
        (mccp.run)(&mut task);
        let p = task.find_cam_profile("KnifeProfile").expect("profile added");
        assert_eq!(task.cam_profile(p).status(), 2);
        assert_eq!(task.cam_profile(p).capacity(), 4);

        let e = compile_text(
            "MCCP(MCCP_1, KnifeCam[0], 4, 1.2, 1.2, KnifeProfile[1])",
            &scene,
            &mut task,
        )
        .expect_err("element 1");
        assert!(e.contains("only element [0]"), "{e}");
        let e = compile_text("MCCP(MCCP_1, KnifeCam[4], 4, 0, 0, KnifeProfile)", &scene, &mut task)
            .expect_err("CAM[4] has no element 4");
        assert!(e.starts_with("Cam KnifeCam[4]"), "{e}");
        // Length beyond the CAM array: ERR 26 with EXERR = the size of the
        // CAM tag (4), not the 3 elements from [1].
        let long = compile_text("MCCP(MCCP_2, KnifeCam[1], 4, 0, 0, KnifeProfile2)", &scene, &mut task)
            .expect("binds; the error is the instruction's");
        (long.run)(&mut task);
        let b = task.motion_bits(long.control.expect("control"));
        assert_eq!((b.er, b.err, b.exerr), (true, 26, 4));
        let e = compile_text(
            "MAPC(Knife, Conveyor, MAPC_1, Sideways, KnifeProfile[0], 1, 1, Continuous, Immediate, 0, 0, NewCam, Command, ForwardOnly)",
            &scene,
            &mut task,
        )
        .expect_err("bad word");
        assert!(e.starts_with("Direction Sideways"), "{e}");
        let e = compile_text("MAS(Conveyor, Stop, All, Yes, 100)", &scene, &mut task).expect_err("5 operands");
        assert!(e.starts_with("MAS takes 6 operands"), "{e}");

        assert!(!task.is_cam_slave(knife));
        let mapc = compile_text(
            "MAPC(Knife, Conveyor, MAPC_1, Same, KnifeProfile[0], 1, 1, Continuous, Immediate, 0, 0, NewCam, Command, ForwardOnly)",
            &scene,
            &mut task,
        )
        .expect("MAPC binds");
        assert!(task.is_cam_slave(knife) && !task.is_cam_slave(conveyor));
        (mapc.run)(&mut task);
        let control = mapc.control.expect("control structure");
        assert!(task.motion_bits(control).ip);
        assert_eq!(task.cam_profile(p).status(), 3);
        task.update();
        assert!(task.motion_bits(control).en, ".EN during the scan's update");
        task.update();
        assert!(!task.motion_bits(control).en, "the one-shot rung is false");
    }
}
