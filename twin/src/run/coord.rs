//! Coordinated motion in the twin: MCLM, MCCM and MCS calls, the
//! `COORDINATE_SYSTEM` tags they name, the coordinate-system trace columns
//! and the tool-centre trail.
//!
//! * A `COORDINATE_SYSTEM` tag becomes a planner coordinate system on its
//!   first use by a call: its `value` lists the member axes (primary first),
//!   its `coordinate_system` table the dynamics and tolerances
//!   (`scenes/README.md`).
//! * Operands follow the manuals' order. Enumerations take the manual's
//!   words (`unitspersec`, `%ofmaximum`, `s-curve`, `coordinatedmotion`, …)
//!   or any integer: an integer outside the enumeration is passed on, so the
//!   instruction reports it at run time as the controller does (ERR 13 with
//!   the operand's EXERR). Array operands (`Pos[0]`) pass the array from
//!   that element to its end; a short array gives ERR 13 at run time.
//! * Event Distance and Calculated Data take `0` or an array tag. The
//!   calculated data stay in the planner (scene tags do not change during a
//!   run); [`planner::task::MotionTask::coord_calculated_data`] has them.
//! * Master-driven moves (units per master unit) follow the axis the
//!   system's `master_axis` names (the twin does not simulate MDCC, whose
//!   link this field stands for); without one they fail at run time with
//!   ERR 13 (EXERR: speed units).

use super::logix::{LogixContext, LogixStep, expect_operands};
use super::{RunError, Twin};
use crate::scene::{BaseType, TagValue};
use crate::st::Expr;
use planner::coord::{CoordMoveInputs, CoordStatus, CoordinateSystemConfig, McsInputs};
use planner::mccm::MccmInputs;
use planner::task::{CoordCall, CoordHandle, MotionTask};
use std::sync::Arc;

const MCCM_OPERANDS: &[&str] = &[
    "Coordinate System",
    "Motion Control",
    "Move Type",
    "Position",
    "Circle Type",
    "Via/Center/Radius",
    "Direction",
    "Speed",
    "Speed Units",
    "Accel Rate",
    "Accel Units",
    "Decel Rate",
    "Decel Units",
    "Profile",
    "Accel Jerk",
    "Decel Jerk",
    "Jerk Units",
    "Termination Type",
    "Merge",
    "Merge Speed",
    "Command Tolerance",
    "Lock Position",
    "Lock Direction",
    "Event Distance",
    "Calculated Data",
];

const MCS_OPERANDS: &[&str] = &[
    "Coordinate System",
    "Motion Control",
    "Stop Type",
    "Change Decel",
    "Decel Rate",
    "Decel Units",
    "Change Decel Jerk",
    "Decel Jerk",
    "Jerk Units",
];

const SPEED_UNITS: &[(&str, i64)] = &[("unitspersec", 0), ("%ofmaximum", 1), ("unitspermasterunit", 4)];
const ACCEL_UNITS: &[(&str, i64)] = &[
    ("unitspersec²", 0),
    ("unitspersec2", 0),
    ("%ofmaximum", 1),
    ("unitspermasterunit²", 4),
    ("unitspermasterunit2", 4),
];
const JERK_UNITS: &[(&str, i64)] = &[
    ("unitspersec³", 0),
    ("unitspersec3", 0),
    ("%ofmaximum", 1),
    ("%oftime", 2),
    ("unitspermasterunit³", 4),
    ("unitspermasterunit3", 4),
    ("%oftimemasterdriven", 6),
];
const PROFILE: &[(&str, i64)] = &[("trapezoidal", 0), ("s-curve", 1)];
const MERGE: &[(&str, i64)] = &[("disabled", 0), ("coordinatedmotion", 1), ("allmotion", 2)];
const MERGE_SPEED: &[(&str, i64)] = &[("programmed", 0), ("current", 1)];
const LOCK_DIRECTION: &[(&str, i64)] = &[
    ("none", 0),
    ("immediateforwardonly", 1),
    ("immediatereverseonly", 2),
    ("positionforward", 3),
    ("positionreverse", 4),
];
const STOP_TYPE: &[(&str, i64)] = &[("all", 0), ("coordinatedmove", 1), ("coordinatedtransform", 2)];
const NO_YES: &[(&str, i64)] = &[("no", 0), ("yes", 1)];
const MCS_DECEL_UNITS: &[(&str, i64)] = &[("unitspersec²", 0), ("unitspersec2", 0), ("%ofmaximum", 1)];
const MCS_JERK_UNITS: &[(&str, i64)] = &[
    ("unitspersec³", 0),
    ("unitspersec3", 0),
    ("%ofmaximum", 1),
    ("%oftime", 2),
];

/// The instructions this module compiles.
pub const COORD_INSTRUCTIONS: &[&str] = &["MCCM", "MCLM", "MCS"];

/// Compiles MCLM, MCCM and MCS calls; `None` for any other instruction.
pub fn compile(upper: &str, operands: &[Expr], ctx: &mut LogixContext<'_>) -> Option<Result<LogixStep, String>> {
    let result = match upper {
        "MCCM" => compile_mccm(operands, ctx),
        "MCLM" => compile_mclm(operands, ctx),
        "MCS" => compile_mcs(operands, ctx),
        _ => return None,
    };
    Some(result)
}

fn step(
    instruction: &'static str,
    system: CoordHandle,
    control: planner::task::InstructionHandle,
    call: CoordCall,
) -> LogixStep {
    LogixStep {
        instruction,
        control: Some(control),
        run: Arc::new(move |task: &mut MotionTask| task.execute_coordinated(system, control, call.clone())),
    }
}

fn compile_mccm(operands: &[Expr], ctx: &mut LogixContext<'_>) -> Result<LogixStep, String> {
    expect_operands("MCCM", operands, MCCM_OPERANDS)?;
    let o = |i: usize| &operands[i];
    let system = coordinate_system(ctx, MCCM_OPERANDS[0], o(0))?;
    let control = ctx.instruction(MCCM_OPERANDS[1], o(1))?;
    let mut rest: Vec<&Expr> = vec![o(2), o(3)];
    rest.extend(operands[7..].iter());
    let common = move_inputs(ctx, &rest, &MCCM_OPERANDS[2..4], &MCCM_OPERANDS[7..])?;
    let inputs = MccmInputs {
        common,
        circle_type: integer(ctx, MCCM_OPERANDS[4], o(4))?,
        via_center_radius: values(ctx, MCCM_OPERANDS[5], o(5))?,
        direction: integer(ctx, MCCM_OPERANDS[6], o(6))?,
    };
    Ok(step("MCCM", system, control, CoordCall::Mccm(inputs)))
}

fn compile_mclm(operands: &[Expr], ctx: &mut LogixContext<'_>) -> Result<LogixStep, String> {
    let names: Vec<&str> = MCCM_OPERANDS
        .iter()
        .enumerate()
        .filter(|(i, _)| !(4..=6).contains(i))
        .map(|(_, n)| *n)
        .collect();
    expect_operands("MCLM", operands, &names)?;
    let system = coordinate_system(ctx, names[0], &operands[0])?;
    let control = ctx.instruction(names[1], &operands[1])?;
    let rest: Vec<&Expr> = operands[2..].iter().collect();
    let inputs = move_inputs(ctx, &rest, &names[2..4], &names[4..])?;
    Ok(step("MCLM", system, control, CoordCall::Mclm(inputs)))
}

/// Move Type, Position, then Speed … Calculated Data (the operands MCLM and
/// MCCM share, in their order).
fn move_inputs(ctx: &LogixContext<'_>, o: &[&Expr], head: &[&str], tail: &[&str]) -> Result<CoordMoveInputs, String> {
    let t = |i: usize| tail[i];
    let x = |i: usize| o[2 + i];
    let inputs = CoordMoveInputs {
        move_type: integer(ctx, head[0], o[0])?,
        position: values(ctx, head[1], o[1])?,
        speed: ctx.number(t(0), x(0))?,
        speed_units: code(ctx, t(1), x(1), SPEED_UNITS)?,
        accel_rate: ctx.number(t(2), x(2))?,
        accel_units: code(ctx, t(3), x(3), ACCEL_UNITS)?,
        decel_rate: ctx.number(t(4), x(4))?,
        decel_units: code(ctx, t(5), x(5), ACCEL_UNITS)?,
        profile: code(ctx, t(6), x(6), PROFILE)?,
        accel_jerk: ctx.number(t(7), x(7))?,
        decel_jerk: ctx.number(t(8), x(8))?,
        jerk_units: code(ctx, t(9), x(9), JERK_UNITS)?,
        termination_type: integer(ctx, t(10), x(10))?,
        merge: code(ctx, t(11), x(11), MERGE)?,
        merge_speed: code(ctx, t(12), x(12), MERGE_SPEED)?,
        command_tolerance: ctx.number(t(13), x(13))?,
        lock_position: ctx.number(t(14), x(14))?,
        lock_direction: code(ctx, t(15), x(15), LOCK_DIRECTION)?,
        event_distance: optional_array(ctx, t(16), x(16))?,
    };
    // Calculated Data: 0 or an array tag (the values stay in the planner).
    optional_array(ctx, t(17), x(17))?;
    Ok(inputs)
}

fn compile_mcs(operands: &[Expr], ctx: &mut LogixContext<'_>) -> Result<LogixStep, String> {
    expect_operands("MCS", operands, MCS_OPERANDS)?;
    let n = |i: usize| MCS_OPERANDS[i];
    let o = |i: usize| &operands[i];
    let system = coordinate_system(ctx, n(0), o(0))?;
    let control = ctx.instruction(n(1), o(1))?;
    let inputs = McsInputs {
        stop_type: code(ctx, n(2), o(2), STOP_TYPE)?,
        change_decel: code(ctx, n(3), o(3), NO_YES)?,
        decel_rate: ctx.number(n(4), o(4))?,
        decel_units: code(ctx, n(5), o(5), MCS_DECEL_UNITS)?,
        change_decel_jerk: code(ctx, n(6), o(6), NO_YES)?,
        decel_jerk: ctx.number(n(7), o(7))?,
        jerk_units: code(ctx, n(8), o(8), MCS_JERK_UNITS)?,
    };
    Ok(step("MCS", system, control, CoordCall::Mcs(inputs)))
}

/// An enumeration operand: one of `words`, or an integer (checked by the
/// instruction at run time).
fn code(ctx: &LogixContext<'_>, what: &str, operand: &Expr, words: &[(&str, i64)]) -> Result<i64, String> {
    if let Expr::Ident(w) = operand
        && let Some((_, c)) = words.iter().find(|(x, _)| x.eq_ignore_ascii_case(w))
    {
        return Ok(*c);
    }
    integer(ctx, what, operand).map_err(|_| {
        let list: Vec<String> = words.iter().map(|(w, c)| format!("{w} ({c})")).collect();
        format!("{what} {operand}: expected one of {} or an integer", list.join(", "))
    })
}

/// An integer operand (a literal or an integer-valued tag).
fn integer(ctx: &LogixContext<'_>, what: &str, operand: &Expr) -> Result<i64, String> {
    let x = ctx.number(what, operand)?;
    if x.fract() == 0.0 && x.abs() < 1e15 {
        Ok(x as i64)
    } else {
        Err(format!("{what} {operand}: expected an integer, got {x}"))
    }
}

/// An array operand from its element to the end of the array, or a single
/// number (a radius).
fn values(ctx: &LogixContext<'_>, what: &str, operand: &Expr) -> Result<Vec<f64>, String> {
    let (name, start) = match operand {
        Expr::Index(base, i) => match (base.as_ref(), usize::try_from(*i)) {
            (Expr::Ident(name), Ok(i)) => (name, i),
            _ => return Err(format!("{what} {operand}: expected an array tag or element")),
        },
        Expr::Ident(name) => (name, 0),
        _ => return ctx.number(what, operand).map(|x| vec![x]),
    };
    match ctx.scene.tag(name).and_then(|t| t.value.as_ref()) {
        Some(TagValue::Array(items)) => {
            let len = items.len().saturating_sub(start);
            ctx.numbers(what, operand, len)
        }
        _ => ctx.number(what, operand).map(|x| vec![x]),
    }
}

/// `0` (none) or an array tag / element.
fn optional_array(ctx: &LogixContext<'_>, what: &str, operand: &Expr) -> Result<Vec<f64>, String> {
    match operand {
        Expr::Integer(0) => Ok(Vec::new()),
        Expr::Number(x) if *x == 0.0 => Ok(Vec::new()),
        Expr::Ident(_) | Expr::Index(..) => {
            let v = values(ctx, what, operand)?;
            match operand {
                Expr::Ident(name)
                    if !matches!(
                        ctx.scene.tag(name).and_then(|t| t.value.as_ref()),
                        Some(TagValue::Array(_))
                    ) =>
                {
                    Err(format!("{what} {operand}: expected 0 or a REAL array tag"))
                }
                _ => Ok(v),
            }
        }
        _ => Err(format!("{what} {operand}: expected 0 or a REAL array tag")),
    }
}

/// The coordinate system named by `operand`, created on its first use.
pub(super) fn coordinate_system(ctx: &mut LogixContext<'_>, what: &str, operand: &Expr) -> Result<CoordHandle, String> {
    let Expr::Ident(name) = operand else {
        return Err(format!("{what} {operand}: expected a COORDINATE_SYSTEM tag"));
    };
    if let Some(h) = ctx
        .task
        .coord_handles()
        .find(|h| ctx.task.coord_config(*h).name.eq_ignore_ascii_case(name))
    {
        return Ok(h);
    }
    let tag = ctx
        .scene
        .tag(name)
        .ok_or_else(|| format!("{what} {name}: not a declared tag"))?;
    let (Some(TagValue::Axes(members)), Some(settings), BaseType::CoordinateSystem) =
        (&tag.value, &tag.coordinate_system, tag.ty.base)
    else {
        return Err(format!(
            "{what} {name}: is a {} tag, expected COORDINATE_SYSTEM",
            tag.ty
        ));
    };
    let axes = members
        .iter()
        .map(|m| ctx.axis(what, &Expr::Ident(m.clone())))
        .collect::<Result<Vec<_>, _>>()?;
    let config = CoordinateSystemConfig {
        axis_count: axes.len(),
        primary_axes: settings.primary_axes,
        max_speed: settings.max_speed,
        max_accel: settings.max_accel,
        max_decel: settings.max_decel,
        max_accel_jerk: settings.max_accel_jerk,
        max_decel_jerk: settings.max_decel_jerk,
        command_tolerance: settings.command_tolerance,
        actual_tolerance: settings.actual_tolerance,
        ..CoordinateSystemConfig::new(tag.name.clone())
    };
    let handle = ctx
        .task
        .add_coordinate_system(config, &axes)
        .map_err(|e| format!("{what} {name}: {e}"))?;
    if let Some(master) = &settings.master_axis {
        let master = ctx.axis(what, &Expr::Ident(master.clone()))?;
        ctx.task.set_coordinate_system_master(handle, Some(master));
    }
    Ok(handle)
}

/// The tool-centre trail of one coordinate system.
#[derive(Debug, Clone)]
pub struct ToolTrail {
    /// Coordinate-system tag name.
    pub system: String,
    /// The URDF link whose origin is the tool centre (model link index).
    pub link: usize,
    /// Its world positions so far (m), one every 0.5 mm of travel.
    pub points_in_world: Vec<[f64; 3]>,
}

/// Minimum travel between two trail points, m.
const TRAIL_STEP_M: f64 = 0.0005;

/// Binds the `tool_link` of every coordinate system the program uses.
///
/// # Errors
/// [`RunError::ToolLink`] naming the scene line when the URDF has no such link.
pub(super) fn tool_trails(twin: &Twin) -> Result<Vec<ToolTrail>, RunError> {
    let mut trails = Vec::new();
    for h in twin.task.coord_handles() {
        let name = &twin.task.coord_config(h).name;
        let Some(settings) = twin.scene.tag(name).and_then(|t| t.coordinate_system.as_ref()) else {
            continue;
        };
        let Some(link_name) = &settings.tool_link else { continue };
        let Some(link) = twin.model.links.iter().position(|l| &l.name == link_name) else {
            let mut names: Vec<&str> = twin.model.links.iter().map(|l| l.name.as_str()).collect();
            names.sort_unstable();
            return Err(RunError::ToolLink {
                scene: twin.scene.path.clone(),
                line: settings.location.line,
                column: settings.location.column,
                message: format!(
                    "coordinate system '{name}': tool_link '{link_name}' is not a link of {} (links: {})",
                    twin.scene.robot.urdf.display(),
                    names.join(", ")
                ),
            });
        };
        trails.push(ToolTrail {
            system: name.clone(),
            link,
            points_in_world: Vec::new(),
        });
    }
    Ok(trails)
}

impl Twin {
    /// The tool-centre trails of the coordinate systems that name a
    /// `tool_link`, in the order the program first uses the systems.
    pub fn tool_trails(&self) -> &[ToolTrail] {
        &self.trails
    }

    /// Appends the tool centres' current world positions to their trails.
    pub(super) fn record_trails(&mut self) {
        if self.trails.is_empty() {
            return;
        }
        let links = self.sim.world_from_link();
        for trail in &mut self.trails {
            let p = links[trail.link].0;
            let far = trail.points_in_world.last().is_none_or(|q| {
                let d = [p[0] - q[0], p[1] - q[1], p[2] - q[2]];
                (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt() >= TRAIL_STEP_M
            });
            if far {
                trail.points_in_world.push(p);
            }
        }
    }

    pub(super) fn coord_trace_header(&self, h: &mut Vec<String>) {
        for cs in self.task.coord_handles() {
            let name = &self.task.coord_config(cs).name;
            for (bit, _) in CoordStatus::default().bits() {
                h.push(format!("{name}.{bit}"));
            }
            if self.trails.iter().any(|t| &t.system == name) {
                for c in ["tool_x", "tool_y", "tool_z"] {
                    h.push(format!("{name}.{c}"));
                }
            }
        }
    }

    pub(super) fn coord_trace_row(&self, row: &mut Vec<String>) {
        let links = if self.trails.is_empty() {
            Vec::new()
        } else {
            self.sim.world_from_link()
        };
        for cs in self.task.coord_handles() {
            let name = &self.task.coord_config(cs).name;
            for (_, bit) in self.task.coord_status(cs).bits() {
                row.push(if bit { "1" } else { "0" }.to_string());
            }
            if let Some(t) = self.trails.iter().find(|t| &t.system == name) {
                for x in links[t.link].0 {
                    row.push(format!("{x}"));
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{Problem, Scene, SceneError, parse};
    use std::path::{Path, PathBuf};

    fn path() -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/gantry_arcs.toml")
    }

    fn text() -> String {
        std::fs::read_to_string(path()).expect("gantry scene")
    }

    fn scene(text: &str) -> Result<Scene, SceneError> {
        parse(&path(), text)
    }

    const XY_TABLE: &str = "coordinate_system = { max_speed = 250.0, max_accel = 2000.0, max_decel = 2000.0, max_accel_jerk = 20000.0, max_decel_jerk = 20000.0, command_tolerance = 25.0, actual_tolerance = 0.2, tool_link = \"tool\" }";

    fn with_xy_table(table: &str) -> String {
        let t = text();
        assert!(t.contains(XY_TABLE));
        t.replacen(XY_TABLE, table, 1)
    }

    #[test]
    fn simulated_lists_every_compiled_instruction() {
        for name in super::super::cam::CAM_INSTRUCTIONS.iter().chain(COORD_INSTRUCTIONS) {
            assert!(super::super::logix::SIMULATED.contains(name), "{name}");
        }
    }

    #[test]
    fn coordinate_system_settings_parse_with_defaults() {
        let s = scene(&text()).unwrap();
        let xy = s.tag("XY").unwrap().coordinate_system.clone().unwrap();
        assert_eq!((xy.primary_axes, xy.max_speed, xy.command_tolerance), (2, 250.0, 25.0));
        assert_eq!(xy.tool_link.as_deref(), Some("tool"));
        let s = scene(&with_xy_table("")).unwrap();
        let xy = s.tag("XY").unwrap().coordinate_system.clone().unwrap();
        assert_eq!((xy.primary_axes, xy.max_speed, xy.max_decel), (2, 1.0, 10.0));
        assert_eq!(
            (xy.command_tolerance, xy.actual_tolerance, xy.tool_link),
            (0.1, 0.01, None)
        );
        assert!(s.tag("OnCircle").unwrap().coordinate_system.is_none());
    }

    #[test]
    fn coordinate_system_settings_errors_name_the_field() {
        let field = |e: SceneError| match e {
            SceneError::Invalid { field, problem, .. } => (field, problem),
            other => panic!("{other}"),
        };
        let (f, p) = field(scene(&with_xy_table("coordinate_system = { primary_axes = 3 }")).unwrap_err());
        assert!(f.ends_with("coordinate_system.primary_axes"), "{f}");
        assert!(matches!(p, Problem::OutOfRange { .. }));
        let (f, p) = field(scene(&with_xy_table("coordinate_system = { max_speed = 0.0 }")).unwrap_err());
        assert!(f.ends_with("coordinate_system.max_speed") && matches!(p, Problem::NotPositive { .. }));
        let (f, p) = field(scene(&with_xy_table("coordinate_system = { command_tolerance = -1.0 }")).unwrap_err());
        assert!(f.ends_with("coordinate_system.command_tolerance") && matches!(p, Problem::Negative { .. }));
        assert!(scene(&with_xy_table("coordinate_system = { bogus = 1.0 }")).is_err());
        let on_real = text().replacen(
            "value = [100.0, 0.0]\n",
            "value = [100.0, 0.0]\ncoordinate_system = { max_speed = 1.0 }\n",
            1,
        );
        let (f, p) = field(scene(&on_real).unwrap_err());
        assert!(
            f.ends_with("coordinate_system") && matches!(p, Problem::CoordinateSystemOnly),
            "{f}"
        );
    }

    #[test]
    fn calls_name_the_operand_at_fault() {
        let err = |t: String| match Twin::new(scene(&t).unwrap()) {
            Err(e) => e.to_string(),
            Ok(_) => panic!("compiles"),
        };
        let t = text().replacen("none, 0, 0)\"", "none, 0)\"", 1);
        assert!(err(t).contains("MCLM takes 22 operands"));
        let t = text().replacen("200, unitspersec, 1000", "200, unitspersec³, 1000", 1);
        let e = err(t);
        assert!(
            e.contains("Speed Units unitspersec³: expected one of unitspersec (0)"),
            "{e}"
        );
        let t = text().replacen("MCLM(XYZ, L1,", "MCLM(OnCircle, L1,", 1);
        assert!(err(t).contains("Coordinate System OnCircle: is a REAL[2] tag"));
        let t = with_xy_table("coordinate_system = { tool_link = \"nozzle\" }");
        let e = err(t);
        assert!(e.contains("tool_link 'nozzle' is not a link"), "{e}");
    }

    #[test]
    fn a_master_axis_drives_master_driven_moves() {
        // The full circle in units per master unit, driven by Z (which stands
        // still once L1 is done): it starts and waits at its start point.
        let t = with_xy_table("coordinate_system = { master_axis = \"z\" }").replacen(
            "3, 200, unitspersec, 1000, unitspersec2, 1000, unitspersec2, s-curve, 100, 100, %oftime,",
            "3, 2, unitspermasterunit, 10, unitspermasterunit2, 10, unitspermasterunit2, s-curve, 100, 100, %oftimemasterdriven,",
            1,
        );
        assert!(t.contains("unitspermasterunit2, s-curve"));
        let mut twin = Twin::new(scene(&t).unwrap()).unwrap();
        let xy = twin
            .task()
            .coord_handles()
            .find(|h| twin.task().coord_config(*h).name == "XY")
            .unwrap();
        let z = twin.axes().iter().find(|a| a.name == "Z").unwrap().handle;
        assert_eq!(twin.task().coordinate_system_master(xy), Some(z));
        let c1 = twin.instructions().iter().find(|b| b.name == "C1").unwrap().handle;
        for _ in 0..1000 {
            twin.step();
        }
        let b = twin.task().motion_bits(c1);
        assert!(b.dn && b.ip && !b.pc && !b.er, "{b:?}");
        let x = twin.axes()[0].handle;
        assert_eq!(
            twin.task().axis_state(x).command_position,
            -100.0,
            "waits for the master"
        );
        let bad = with_xy_table("coordinate_system = { master_axis = \"W\" }");
        assert!(scene(&bad).is_err());
    }

    #[test]
    fn out_of_range_codes_fail_at_run_time_with_err_and_exerr() {
        // Direction 7 on the full circle: ERR 13, EXERR 6 (Direction).
        let t = text().replacen("1, Origin[0], 3, 200", "1, Origin[0], 7, 200", 1);
        let mut twin = Twin::new(scene(&t).unwrap()).unwrap();
        let c1 = twin.instructions().iter().find(|b| b.name == "C1").unwrap().handle;
        for _ in 0..1000 {
            twin.step();
            if twin.task().motion_bits(c1).er {
                break;
            }
        }
        let b = twin.task().motion_bits(c1);
        assert!(b.er && !b.dn && (b.err, b.exerr) == (13, 6), "{b:?}");
    }

    #[test]
    fn coordinate_systems_are_bound_once_and_traced_in_first_use_order() {
        let twin = Twin::new(scene(&text()).unwrap()).unwrap();
        let names: Vec<&str> = twin
            .task()
            .coord_handles()
            .map(|h| twin.task().coord_config(h).name.as_str())
            .collect();
        assert_eq!(names, ["XYZ", "XY"]);
        let header = twin.trace_header();
        let first = header.iter().position(|h| h == "XYZ.MotionStatus").unwrap();
        assert_eq!(header[first + 10], "XYZ.CoordMotionLockStatus");
        assert_eq!(header[first + 11], "XYZ.tool_x");
        assert_eq!(header[first + 14], "XY.MotionStatus");
        assert_eq!(twin.trace_row().len(), header.len());
        assert_eq!(twin.tool_trails().len(), 2);
        // The tool centre at all joints 0 is 0.39 m under the rails at z = 0.6 m.
        let p = twin.tool_trails()[0].points_in_world[0];
        assert!(
            (p[0]).abs() < 1e-6 && (p[1]).abs() < 1e-6 && (p[2] - 0.21).abs() < 1e-3,
            "{p:?}"
        );
    }
}
