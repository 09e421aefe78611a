//! Logix cam calls: MCCP, MAPC, MRP, and the MAJ jog / MAS stop that drive
//! cam masters, compiled to planner calls (see [`super::logix`]).
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
//! * `MAS(Axis, MotionControl, StopType, ChangeDecel, DecelRate, DecelUnits)`
//!   — the manual's first six operands: StopType `All Jog Move Gear Home Tune
//!   Test TimeCam PositionCam MasterOffsetMove DirectControl`, ChangeDecel
//!   `No Yes`.
//!
//! Each call is one scan of a one-shot rung: the planner executes it, and
//! `.EN` clears at the next coarse update once `.DN` or `.ER` is set.

use super::logix::{LogixContext, LogixStep, expect_operands};
use crate::scene::{BaseType, SegmentType, TagValue};
use crate::st::Expr;
use planner::jog::{MajOperands, MasOperands};
use planner::mapc::MapcOperands;
use planner::mccp::CamElement;
use planner::task::{CamProfileHandle, MapcCall, MotionTask};
use std::sync::Arc;

/// The instructions of this module.
pub const CAM_INSTRUCTIONS: &[&str] = &["MAJ", "MAPC", "MAS", "MCCP", "MRP"];

/// Compiles one of [`CAM_INSTRUCTIONS`]; `None` for any other name.
pub fn compile(upper: &str, operands: &[Expr], ctx: &mut LogixContext<'_>) -> Option<Result<LogixStep, String>> {
    Some(match upper {
        "MCCP" => mccp(operands, ctx),
        "MAPC" => mapc(operands, ctx),
        "MRP" => mrp(operands, ctx),
        "MAJ" => maj(operands, ctx),
        "MAS" => mas(operands, ctx),
        _ => return None,
    })
}

fn step(
    instruction: &'static str,
    control: planner::task::InstructionHandle,
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
    let tag = ctx
        .scene
        .tag(name)
        .ok_or_else(|| format!("{what} {name}: not a declared tag"))?;
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
fn cam_points(ctx: &LogixContext<'_>, operand: &Expr) -> Result<Vec<CamElement>, String> {
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
    let Some(TagValue::CamPoints(points)) = tag.value.as_ref() else {
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
    Ok(elements.split_off(start))
}

fn count(ctx: &LogixContext<'_>, what: &str, operand: &Expr) -> Result<usize, String> {
    let x = ctx.number(what, operand)?;
    if x >= 0.0 && x.fract() == 0.0 && x <= f64::from(u16::MAX) {
        Ok(x as usize)
    } else {
        Err(format!("{what} {operand}: expected a UINT (0..=65535)"))
    }
}

fn choice_i32(ctx: &LogixContext<'_>, what: &str, operand: &Expr, words: &[&str]) -> Result<i32, String> {
    ctx.choice(what, operand, words).map(|i| i as i32)
}

fn mccp(operands: &[Expr], ctx: &mut LogixContext<'_>) -> Result<LogixStep, String> {
    expect_operands(
        "MCCP",
        operands,
        &[
            "Motion Control",
            "Cam",
            "Length",
            "Start Slope",
            "End Slope",
            "Cam Profile",
        ],
    )?;
    let control = ctx.instruction("Motion Control", &operands[0])?;
    let cam = cam_points(ctx, &operands[1])?;
    let length = count(ctx, "Length", &operands[2])?;
    let start_slope = ctx.number("Start Slope", &operands[3])?;
    let end_slope = ctx.number("End Slope", &operands[4])?;
    let profile = cam_profile(ctx, &operands[5])?;
    Ok(step("MCCP", control, move |task| {
        // The outcome is in the control structure (.DN or .ER/ERR/EXERR/SEGMENT).
        let _ = task.mccp(control, &cam, length, start_slope, end_slope, profile);
    }))
}

fn mapc(operands: &[Expr], ctx: &mut LogixContext<'_>) -> Result<LogixStep, String> {
    expect_operands(
        "MAPC",
        operands,
        &[
            "Slave Axis",
            "Master Axis",
            "Motion Control",
            "Direction",
            "Cam Profile",
            "Slave Scaling",
            "Master Scaling",
            "Execution Mode",
            "Execution Schedule",
            "Master Lock Position",
            "Cam Lock Position",
            "Cam Type",
            "Master Reference",
            "Master Direction",
        ],
    )?;
    let slave = ctx.axis("Slave Axis", &operands[0])?;
    let master = ctx.axis("Master Axis", &operands[1])?;
    let control = ctx.instruction("Motion Control", &operands[2])?;
    let direction = choice_i32(
        ctx,
        "Direction",
        &operands[3],
        &["Same", "Opposite", "Reverse", "Unchanged"],
    )?;
    let profile = cam_profile(ctx, &operands[4])?;
    let o = MapcOperands {
        direction,
        slave_scaling: ctx.number("Slave Scaling", &operands[5])?,
        master_scaling: ctx.number("Master Scaling", &operands[6])?,
        execution_mode: choice_i32(
            ctx,
            "Execution Mode",
            &operands[7],
            &["Once", "Continuous", "Persistent"],
        )?,
        execution_schedule: choice_i32(
            ctx,
            "Execution Schedule",
            &operands[8],
            &["Immediate", "Pending", "ForwardOnly", "ReverseOnly", "Bidirectional"],
        )?,
        master_lock_position: ctx.number("Master Lock Position", &operands[9])?,
        cam_lock_position: ctx.number("Cam Lock Position", &operands[10])?,
        cam_type: choice_i32(
            ctx,
            "Cam Type",
            &operands[11],
            &["NewCam", "ReplaceAndRestart", "ReplaceAndContinue"],
        )?,
        master_reference: choice_i32(ctx, "Master Reference", &operands[12], &["Actual", "Command"])?,
        master_direction: choice_i32(
            ctx,
            "Master Direction",
            &operands[13],
            &["Bidirectional", "ForwardOnly", "ReverseOnly"],
        )?,
    };
    ctx.task.declare_cam_slave(slave);
    let call = MapcCall {
        slave,
        master,
        motion_control: control,
        cam_profile: profile,
        operands: o,
    };
    Ok(step("MAPC", control, move |task| {
        let _ = task.mapc(call);
    }))
}

fn mrp(operands: &[Expr], ctx: &mut LogixContext<'_>) -> Result<LogixStep, String> {
    expect_operands(
        "MRP",
        operands,
        &["Axis", "Motion Control", "Type", "Position Select", "Position"],
    )?;
    let axis = ctx.axis("Axis", &operands[0])?;
    let control = ctx.instruction("Motion Control", &operands[1])?;
    let kind = choice_i32(ctx, "Type", &operands[2], &["Absolute", "Relative"])?;
    let select = choice_i32(ctx, "Position Select", &operands[3], &["Actual", "Command"])?;
    let position = ctx.number("Position", &operands[4])?;
    Ok(step("MRP", control, move |task| {
        let _ = task.mrp(axis, control, kind, select, position);
    }))
}

const RATE_UNITS: [&str; 2] = ["UnitsPerSec", "%ofMaximum"];
const ACCEL_UNITS: [&str; 2] = ["UnitsPerSec2", "%ofMaximum"];

fn maj(operands: &[Expr], ctx: &mut LogixContext<'_>) -> Result<LogixStep, String> {
    expect_operands(
        "MAJ",
        operands,
        &[
            "Axis",
            "Motion Control",
            "Direction",
            "Speed",
            "Speed Units",
            "Accel Rate",
            "Accel Units",
            "Decel Rate",
            "Decel Units",
            "Profile",
        ],
    )?;
    let axis = ctx.axis("Axis", &operands[0])?;
    let control = ctx.instruction("Motion Control", &operands[1])?;
    let o = MajOperands {
        direction: choice_i32(ctx, "Direction", &operands[2], &["Forward", "Reverse"])?,
        speed: ctx.number("Speed", &operands[3])?,
        speed_units: choice_i32(ctx, "Speed Units", &operands[4], &RATE_UNITS)?,
        accel_rate: ctx.number("Accel Rate", &operands[5])?,
        accel_units: choice_i32(ctx, "Accel Units", &operands[6], &ACCEL_UNITS)?,
        decel_rate: ctx.number("Decel Rate", &operands[7])?,
        decel_units: choice_i32(ctx, "Decel Units", &operands[8], &ACCEL_UNITS)?,
        profile: choice_i32(ctx, "Profile", &operands[9], &["Trapezoidal", "S-Curve"])?,
    };
    Ok(step("MAJ", control, move |task| {
        let _ = task.maj(axis, control, &o);
    }))
}

fn mas(operands: &[Expr], ctx: &mut LogixContext<'_>) -> Result<LogixStep, String> {
    expect_operands(
        "MAS",
        operands,
        &[
            "Axis",
            "Motion Control",
            "Stop Type",
            "Change Decel",
            "Decel Rate",
            "Decel Units",
        ],
    )?;
    let axis = ctx.axis("Axis", &operands[0])?;
    let control = ctx.instruction("Motion Control", &operands[1])?;
    let o = MasOperands {
        stop_type: choice_i32(
            ctx,
            "Stop Type",
            &operands[2],
            &[
                "All",
                "Jog",
                "Move",
                "Gear",
                "Home",
                "Tune",
                "Test",
                "TimeCam",
                "PositionCam",
                "MasterOffsetMove",
                "DirectControl",
            ],
        )?,
        change_decel: choice_i32(ctx, "Change Decel", &operands[3], &["No", "Yes"])?,
        decel_rate: ctx.number("Decel Rate", &operands[4])?,
        decel_units: choice_i32(ctx, "Decel Units", &operands[5], &ACCEL_UNITS)?,
    };
    Ok(step("MAS", control, move |task| {
        let _ = task.mas(axis, control, &o);
    }))
}

/// Trace columns for the cam slaves (axes some MAPC names as its slave), in
/// axis order: `<axis>.PositionCamStatus`, `.PositionCamLockStatus`,
/// `.PositionCamPendingStatus` (0/1), `.VelocityLimitExceeded`,
/// `.AccelLimitExceeded` (0/1: the command exceeded the axis' configured
/// maximum, which camming ignores).
pub fn trace_header(task: &MotionTask, axes: &[super::AxisBinding]) -> Vec<String> {
    let mut h = Vec::new();
    for a in axes.iter().filter(|a| task.is_cam_slave(a.handle)) {
        for c in COLUMNS {
            h.push(format!("{}.{c}", a.name));
        }
    }
    h
}

const COLUMNS: [&str; 5] = [
    "PositionCamStatus",
    "PositionCamLockStatus",
    "PositionCamPendingStatus",
    "VelocityLimitExceeded",
    "AccelLimitExceeded",
];

/// The values of [`trace_header`]'s columns now.
pub fn trace_row(task: &MotionTask, axes: &[super::AxisBinding]) -> Vec<String> {
    let mut row = Vec::new();
    for a in axes.iter().filter(|a| task.is_cam_slave(a.handle)) {
        let s = task.slave_cam_status(a.handle);
        let l = task.limits_exceeded(a.handle);
        for b in [s.position_cam, s.lock, s.pending, l.velocity, l.acceleration] {
            row.push(if b { "1" } else { "0" }.to_string());
        }
    }
    row
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::run::{AxisBinding, InstructionBinding};
    use crate::scene::{Scene, load};
    use crate::st::parse_call;
    use planner::axis::{AxisConfig, AxisKind};
    use std::path::Path;

    fn scene() -> Scene {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/rotary_knife.toml");
        load(&path).expect("scene loads")
    }

    fn compile_text(
        text: &str,
        scene: &Scene,
        task: &mut MotionTask,
        axes: &[AxisBinding],
    ) -> Result<LogixStep, String> {
        let call = parse_call(text).expect("parses");
        let crate::st::Args::Positional(ops) = &call.args else {
            panic!("positional")
        };
        let operands: Vec<Expr> = ops.iter().map(|o| o.value.clone()).collect();
        let mut instructions: Vec<InstructionBinding> = Vec::new();
        let mut ctx = LogixContext {
            scene,
            task,
            axes,
            instructions: &mut instructions,
        };
        super::super::logix::compile(&call.name.value, &operands, &mut ctx)
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
        let binding = |name: &str, handle| AxisBinding {
            name: name.to_string(),
            handle,
            drive: Some(0),
            si_per_unit: 1.0,
            in_position_window: 0.1,
        };
        let axes = vec![binding("Conveyor", conveyor), binding("Knife", knife)];

        let mccp = compile_text(
            "MCCP(MCCP_1, KnifeCam[0], 4, 1.2, 1.2, KnifeProfile[0])",
            &scene,
            &mut task,
            &axes,
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
            &axes,
        )
        .expect_err("element 1");
        assert!(e.contains("only element [0]"), "{e}");
        let e = compile_text(
            "MCCP(MCCP_1, KnifeCam[4], 4, 0, 0, KnifeProfile)",
            &scene,
            &mut task,
            &axes,
        )
        .expect_err("CAM[4] has no element 4");
        assert!(e.starts_with("Cam KnifeCam[4]"), "{e}");
        // Length beyond the CAM array: ERR 26 with EXERR = its element count.
        let long = compile_text(
            "MCCP(MCCP_2, KnifeCam[1], 4, 0, 0, KnifeProfile2)",
            &scene,
            &mut task,
            &axes,
        )
        .expect("binds; the error is the instruction's");
        (long.run)(&mut task);
        let b = task.motion_bits(long.control.expect("control"));
        assert_eq!((b.er, b.err, b.exerr), (true, 26, 3));
        let e = compile_text(
            "MAPC(Knife, Conveyor, MAPC_1, Sideways, KnifeProfile[0], 1, 1, Continuous, Immediate, 0, 0, NewCam, Command, ForwardOnly)",
            &scene,
            &mut task,
            &axes,
        )
        .expect_err("bad word");
        assert!(e.starts_with("Direction Sideways"), "{e}");
        let e = compile_text("MAS(Conveyor, Stop, All, Yes, 100)", &scene, &mut task, &axes).expect_err("5 operands");
        assert!(e.starts_with("MAS takes 6 operands"), "{e}");

        assert!(!task.is_cam_slave(knife));
        let mapc = compile_text(
            "MAPC(Knife, Conveyor, MAPC_1, Same, KnifeProfile[0], 1, 1, Continuous, Immediate, 0, 0, NewCam, Command, ForwardOnly)",
            &scene,
            &mut task,
            &axes,
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
