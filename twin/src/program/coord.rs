//! Coordinated motion calls bound to the planner: MCLM, MCCM and MCS, and
//! the `COORDINATE_SYSTEM` tags they name.
//!
//! * A `COORDINATE_SYSTEM` tag becomes a planner coordinate system on its
//!   first use by a call: its `value` lists the member axes (primary first),
//!   its `coordinate_system` table the dynamics and tolerances
//!   (`scenes/README.md`).
//! * Operands follow the manuals' order and formats ([`super::bind`]).
//!   Array operands (`Pos[0]`) pass the array from that element to its
//!   end; a short array gives ERR 13 at run time.
//! * Event Distance and Calculated Data take `0` or an array tag. The
//!   calculated data stay in the planner (scene tags do not change during a
//!   run); [`planner::task::MotionTask::coord_calculated_data`] has them.
//! * Master-driven moves (units per master unit) follow the axis the
//!   system's `master_axis` names (the twin does not simulate MDCC, whose
//!   link this field stands for); without one they fail at run time with
//!   ERR 13 (EXERR: speed units).

use super::bind::{Bind, LogixContext, LogixStep, declared_tag};
use crate::scene::{BaseType, TagValue};
use crate::st::Expr;
use planner::coord::{CoordMoveInputs, McsInputs};
use planner::mccm::MccmInputs;
use planner::task::{CoordCall, CoordHandle, InstructionHandle, MotionTask};
use std::sync::Arc;

/// Binds an MCLM, MCCM or MCS call.
///
/// # Errors
/// A message naming the operand at fault.
pub fn bind(b: &mut Bind<'_, '_>) -> Result<LogixStep, String> {
    let mnemonic = b.instruction.mnemonic;
    let system = b.coordinate_system("Coordinate System")?;
    let control = b.motion_control()?;
    let call = match mnemonic {
        "MCCM" => CoordCall::Mccm(MccmInputs {
            common: move_inputs(b)?,
            circle_type: b.integer("Circle Type")?,
            via_center_radius: b.values("Via/Center/Radius")?,
            direction: b.integer("Direction")?,
        }),
        "MCLM" => CoordCall::Mclm(move_inputs(b)?),
        _ => CoordCall::Mcs(McsInputs {
            stop_type: b.code("Stop Type")?,
            change_decel: b.code("Change Decel")?,
            decel_rate: b.number("Decel Rate")?,
            decel_units: b.code("Decel Units")?,
            change_decel_jerk: b.code("Change Decel Jerk")?,
            decel_jerk: b.number("Decel Jerk")?,
            jerk_units: b.code("Jerk Units")?,
        }),
    };
    Ok(step(mnemonic, system, control, call))
}

fn step(instruction: &'static str, system: CoordHandle, control: InstructionHandle, call: CoordCall) -> LogixStep {
    LogixStep {
        instruction,
        control: Some(control),
        run: Arc::new(move |task: &mut MotionTask| task.execute_coordinated(system, control, call.clone())),
    }
}

/// The operands MCLM and MCCM share, read in their call order.
fn move_inputs(b: &Bind<'_, '_>) -> Result<CoordMoveInputs, String> {
    let inputs = CoordMoveInputs {
        move_type: b.integer("Move Type")?,
        position: b.values("Position")?,
        dynamics: b.dynamics()?,
        termination_type: b.integer("Termination Type")?,
        merge: b.code("Merge")?,
        merge_speed: b.code("Merge Speed")?,
        command_tolerance: b.number("Command Tolerance")?,
        lock_position: b.number("Lock Position")?,
        lock_direction: b.code("Lock Direction")?,
        event_distance: b.optional_array("Event Distance")?,
    };
    // Calculated Data: 0 or an array tag (the values stay in the planner).
    b.optional_array("Calculated Data")?;
    Ok(inputs)
}

impl Bind<'_, '_> {
    /// A coordinate-system operand, the system created on its first use.
    ///
    /// # Errors
    /// See [`coordinate_system`].
    pub fn coordinate_system(&mut self, name: &str) -> Result<CoordHandle, String> {
        let (spec, e) = self.operand(name);
        coordinate_system(self.ctx, spec.name, e)
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
    let tag = declared_tag(ctx.scene, what, name, "COORDINATE_SYSTEM")?;
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
    let handle = ctx
        .task
        .add_coordinate_system(settings.system.clone(), &axes)
        .map_err(|e| format!("{what} {name}: {e}"))?;
    if let Some(master) = &settings.master_axis {
        let master = ctx.axis(what, &Expr::Ident(master.clone()))?;
        ctx.task.set_coordinate_system_master(handle, Some(master));
    }
    Ok(handle)
}

#[cfg(test)]
mod tests {
    use crate::run::Twin;
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

    /// The handle of the control structure called `name`.
    fn instruction(twin: &Twin, name: &str) -> planner::task::InstructionHandle {
        let bound = twin.program().instructions().iter().find(|b| b.name == name);
        bound.unwrap_or_else(|| panic!("no instruction {name}")).handle
    }

    fn with_xy_table(table: &str) -> String {
        let t = text();
        assert!(t.contains(XY_TABLE));
        t.replacen(XY_TABLE, table, 1)
    }

    #[test]
    fn coordinate_system_settings_parse_with_defaults() {
        let s = scene(&text()).unwrap();
        let xy = s.tag("XY").unwrap().coordinate_system.clone().unwrap();
        let c = &xy.system;
        assert_eq!((c.primary_axes, c.max_speed, c.command_tolerance), (2, 250.0, 25.0));
        assert_eq!((c.name.as_str(), c.axis_count), ("XY", 2));
        assert_eq!(xy.tool_link.as_deref(), Some("tool"));
        let s = scene(&with_xy_table("")).unwrap();
        let xy = s.tag("XY").unwrap().coordinate_system.clone().unwrap();
        let c = &xy.system;
        assert_eq!((c.primary_axes, c.max_speed, c.max_decel), (2, 1.0, 10.0));
        assert_eq!((c.command_tolerance, c.actual_tolerance), (0.1, 0.01));
        assert_eq!(xy.tool_link, None);
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
        // The operand count is checked when the scene loads.
        let t = text().replacen("none, 0, 0)\"", "none, 0)\"", 1);
        let e = scene(&t).unwrap_err().to_string();
        assert!(e.contains("MCLM takes 22 operands"), "{e}");
        // A word of another operand is refused when the scene loads.
        let t = text().replacen("200, unitspersec, 1000", "200, unitspersec³, 1000", 1);
        let e = scene(&t).unwrap_err().to_string();
        assert!(
            e.contains("'unitspersec³' for Speed Units (its words: unitspersec (0)"),
            "{e}"
        );
        let t = text().replacen("200, unitspersec, 1000", "200, 3, 1000", 1);
        let e = err(t.clone());
        assert!(e.contains("Speed Units 3: expected one of unitspersec (0)"), "{e}");
        // The error points at the operand, in the `call` field.
        let (line, text_line) = t
            .lines()
            .enumerate()
            .find(|(_, l)| l.contains("200, 3, 1000"))
            .expect("edited line");
        let column = text_line[..text_line.find("3, 1000").expect("operand")].chars().count() + 1;
        assert!(e.contains(&format!(":{}:{column}: program[", line + 1)), "{e}");
        assert!(e.contains("].call: Speed Units 3"), "{e}");
        let t = text().replacen("MCLM(XYZ, L1,", "MCLM(OnCircle, L1,", 1);
        assert!(err(t).contains("Coordinate System OnCircle: is a REAL[2] tag"));
        let t = text().replacen("MCLM(XYZ, L1,", "MCLM(X, L1,", 1);
        let e = err(t);
        assert!(
            e.contains("Coordinate System X: is an axis, expected a COORDINATE_SYSTEM tag"),
            "{e}"
        );
        let t = with_xy_table("coordinate_system = { tool_link = \"nozzle\" }");
        let xy = scene(&t).unwrap().tags.iter().position(|t| t.name == "XY").unwrap();
        let e = err(t);
        assert!(e.contains("tool_link 'nozzle' is not a link"), "{e}");
        assert!(e.contains(&format!("tags[{xy}].coordinate_system.tool_link")), "{e}");
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
        let z = twin.plant().axes().iter().find(|a| a.name == "Z").unwrap().handle;
        assert_eq!(twin.task().coordinate_system_master(xy), Some(z));
        let c1 = instruction(&twin, "C1");
        for _ in 0..1000 {
            twin.step();
        }
        let b = twin.task().motion_bits(c1);
        assert!(b.dn && b.ip && !b.pc && !b.er, "{b:?}");
        let x = twin.plant().axes()[0].handle;
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
        let c1 = instruction(&twin, "C1");
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
        let header = crate::output::trace::header(&twin);
        let first = header.iter().position(|h| h == "XYZ.MotionStatus").unwrap();
        assert_eq!(header[first + 10], "XYZ.CoordMotionLockStatus");
        assert_eq!(header[first + 11], "XYZ.tool_x");
        assert_eq!(header[first + 14], "XY.MotionStatus");
        assert_eq!(crate::output::trace::row(&twin).len(), header.len());
        assert_eq!(twin.plant().tool_trails().len(), 2);
        // The tool centre at all joints 0 is 0.39 m under the rails at z = 0.6 m.
        let p = twin.plant().tool_trails()[0].points_in_world[0];
        assert!(
            (p[0]).abs() < 1e-6 && (p[1]).abs() < 1e-6 && (p[2] - 0.21).abs() < 1e-3,
            "{p:?}"
        );
    }
}
