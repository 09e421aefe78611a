//! The trace: one CSV row per coarse update, columns in this order (groups
//! absent when the scene has nothing of that kind):
//!
//! * `time_s`;
//! * per axis `<axis>.cmd_pos`, `.cmd_vel`, `.cmd_acc`, `.act_pos`;
//! * per function-block instance `<fb>.Done`, `.Busy`, `.Active`,
//!   `.CommandAborted`, `.Error`, `.ErrorID`;
//! * per control structure `<tag>.EN`, `.DN`, `.ER`, `.IP`, `.AC`, `.PC`,
//!   `.ACCEL`, `.DECEL`, `.ERR`, `.EXERR`, `.SEGMENT`;
//! * with `[collision]`: `collision.count`, `<body>.clearance_m`;
//! * per cam slave `<axis>.PositionCamStatus`, `.PositionCamLockStatus`,
//!   `.PositionCamPendingStatus`, `.VelocityLimitExceeded`,
//!   `.AccelLimitExceeded` (the command exceeded the axis' configured
//!   maximum, which camming ignores);
//! * per coordinate system its status bits and, with a `tool_link`,
//!   `<cs>.tool_x`, `.tool_y`, `.tool_z`;
//! * when the program calls MCT: per coordinate system
//!   `<cs>.TransformSourceStatus`, `.TransformTargetStatus`, then per axis
//!   `<axis>.TransformStateStatus`, `.ControlledByTransformStatus`;
//! * when the program calls MAM, or MAJ together with MCLM or MCCM (the
//!   programs whose single-axis motion can run superimposed on a cam or a
//!   coordinated move): per axis `<axis>.sup_pos`, `.sup_vel`, the
//!   superimposed part of `cmd_pos` and `cmd_vel` (0 without one; the rest
//!   is the cam's or the path's);
//! * when the program calls a state instruction (MSO, MSF, MASD, MASR,
//!   MAFR, MAH, MCSD, MCSR): per axis `<axis>.CIPAxisState` (2 Stopped, 3
//!   Starting, 4 Running, 8 Faulted, 10 Shutdown, 11 Axis Inhibited) and
//!   `.AxisFault`;
//! * per axis with soft travel limits `<axis>.MotionFault`: 2 after a Soft
//!   Travel Limit - Positive, 4 after a Negative one (latched until MAFR or
//!   MASR), 0 otherwise;
//! * per axis with a servo drive (a `joint` and no `motor`):
//!   `<axis>.torque`, the drive's torque in the last physics substep of the
//!   update, N·m (rotary joint) or N (prismatic), 0 while the drive is off;
//! * per axis `<axis>.overshoot`: 1 while the single-axis profile running
//!   on it (MC_MoveModulo, MAM, MAJ, a stop ramp) is overshooting — above
//!   the programmed maximum speed because the state it started from could
//!   not keep it (a stop issued while accelerating with a smaller decel
//!   jerk, a speed lowered mid-move), or past its target, to which it comes
//!   back (the overshoot the MCCM document warns of when the deceleration is
//!   decreased while a move decelerates);
//! * with a cell: per sensor `<sensor>.state`, its output (after invert
//!   and delays; the tag is the input module's copy of it); with a parts
//!   world, per conveyor `<conveyor>.speed_mps` (the belt's speed, negative
//!   backwards), per gripper `<gripper>.part` (the id of the part it holds,
//!   0 for none), per cylinder `<cylinder>.position_m` (its travel from
//!   the retracted end), then `parts.in_cell` (live parts),
//!   `parts.delivered`, `parts.rejected`, `parts.dropped` and `parts.lost`
//!   (counts so far);
//! * each `[trace] tags` entry, named as written (`State`, `Pos[0]`,
//!   `Pick.Count`, `MC1.PC`): BOOL as 0/1, integers in full, REAL at single
//!   precision;
//! * in a run of the kinematic plant (`plant = "kinematic"`, `--plant
//!   kinematic`), `plant.kinematic`, always 1: the trace says which plant
//!   ran (a physics run has no such column).
//!
//! Numbers are the shortest text that reads back as the same value
//! ([`number`]): positional (`0.25`, `90`), with an exponent below 1e-5
//! and from 1e16 in magnitude (`1.5e-20`) so that values near zero stay
//! short; deterministic, so reruns write identical files.

use crate::program::types::{DataType, Value};
use crate::run::Twin;
use planner::coord::CoordStatus;
use planner::instruction::{FbOutputs, MotionInstructionBits};
use planner::task::instructions::{mafr, mah, maj, mam, masd, masr, mccm, mclm, mcsd, mcsr, mct, msf, mso};

/// A number as the trace writes it (module doc): Rust's shortest
/// round-trip text, positional for magnitudes in [1e-5, 1e16) and zero,
/// with an exponent otherwise (`1e-20`, not twenty zeros); `inf`, `-inf`
/// and `NaN` as Rust writes them.
pub fn number(x: f64) -> String {
    let mut text = String::new();
    write_shortest(&mut text, x, x);
    text
}

/// [`number`] for a single-precision value (a REAL tag).
pub fn number_f32(x: f32) -> String {
    let mut text = String::new();
    write_shortest(&mut text, x, f64::from(x));
    text
}

/// Appends `x`'s shortest round-trip text, with an exponent when `value`
/// (`x` widened) is nonzero and finite outside [1e-5, 1e16) in magnitude.
fn write_shortest<T: std::fmt::Display + std::fmt::LowerExp>(text: &mut String, x: T, value: f64) {
    use std::fmt::Write;
    let a = value.abs();
    // Writing to a String cannot fail.
    let _ = if a.is_finite() && a != 0.0 && !(1e-5..1e16).contains(&a) {
        write!(text, "{x:e}")
    } else {
        write!(text, "{x}")
    };
}

/// What a trace column belongs to: the recording logs the columns of one
/// group as one series of several values (`output::recording::run`).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Group {
    /// `time_s`: the recording's timeline, not a series.
    Time,
    /// An axis' column (`<axis>.<leaf>`): its name.
    Axis(String),
    /// A function block's outputs or a control structure's bits and codes:
    /// the instance's name.
    Instruction(String),
    /// `collision.count`.
    CollisionCount,
    /// A collision body's clearance.
    Clearance,
    /// A coordinate system's status bits: its name.
    System(String),
    /// A coordinate system's tool centre (`tool_x`, `tool_y`, `tool_z`): its name.
    Tool(String),
    /// A sensor's state.
    Sensor,
    /// A conveyor's speed.
    Conveyor,
    /// The part a gripper holds.
    Gripper,
    /// A cylinder's travel.
    Cylinder,
    /// The parts counts.
    Parts,
    /// A `[trace] tags` entry: its index in `Program::traced_tags`.
    Tag(usize),
    /// `plant.kinematic`.
    Plant,
}

/// A trace column: its name, what it belongs to, and its name within
/// that (`cmd_pos`, `EN`, a body's or sensor's name, a tag's reference).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Column {
    /// The column's name in the header.
    pub name: String,
    /// What it belongs to.
    pub group: Group,
    /// Its name within the group.
    pub leaf: String,
}

impl Column {
    /// `<owner>.<leaf>`.
    fn of(group: Group, owner: &str, leaf: &str) -> Column {
        Column {
            name: format!("{owner}.{leaf}"),
            group,
            leaf: leaf.to_owned(),
        }
    }
}

/// The trace's column names (module doc).
pub fn header(twin: &Twin) -> Vec<String> {
    columns(twin).into_iter().map(|c| c.name).collect()
}

/// The trace's columns in order (module doc), with what each belongs to.
pub fn columns(twin: &Twin) -> Vec<Column> {
    let (task, program, plant) = (twin.task(), twin.program(), twin.plant());
    let axis = |a: &crate::plant::axes::AxisBinding, leaf: &str| Column::of(Group::Axis(a.name.clone()), &a.name, leaf);
    let mut h = vec![Column {
        name: "time_s".to_string(),
        group: Group::Time,
        leaf: "time_s".to_string(),
    }];
    for a in plant.axes() {
        for c in ["cmd_pos", "cmd_vel", "cmd_acc", "act_pos"] {
            h.push(axis(a, c));
        }
    }
    let instruction = |name: &str, leaf: &str| Column::of(Group::Instruction(name.to_owned()), name, leaf);
    for fb in program.fbs() {
        for (c, _) in FbOutputs::default().bits() {
            h.push(instruction(&fb.name, c));
        }
        h.push(instruction(&fb.name, "ErrorID"));
    }
    let zero = MotionInstructionBits::default();
    for ins in program.instructions() {
        for (c, _) in zero.bits() {
            h.push(instruction(&ins.name, c));
        }
        for (c, _) in zero.codes() {
            h.push(instruction(&ins.name, c));
        }
    }
    if plant.collision_enabled() {
        h.push(Column::of(Group::CollisionCount, "collision", "count"));
        h.extend(plant.collision_bodies().iter().map(|b| Column {
            name: format!("{b}.clearance_m"),
            group: Group::Clearance,
            leaf: b.clone(),
        }));
    }
    for a in plant.axes().iter().filter(|a| task.is_cam_slave(a.handle)) {
        for c in CAM_COLUMNS {
            h.push(axis(a, c));
        }
    }
    for cs in task.coord_handles() {
        let name = &task.coord_config(cs).name;
        for (bit, _) in CoordStatus::default().bits() {
            h.push(Column::of(Group::System(name.clone()), name, bit));
        }
        if plant.tool_trails().iter().any(|t| &t.system == name) {
            for c in ["tool_x", "tool_y", "tool_z"] {
                h.push(Column::of(Group::Tool(name.clone()), name, c));
            }
        }
    }
    if uses_mct(twin) {
        for cs in task.coord_handles() {
            let name = &task.coord_config(cs).name;
            h.push(Column::of(Group::System(name.clone()), name, "TransformSourceStatus"));
            h.push(Column::of(Group::System(name.clone()), name, "TransformTargetStatus"));
        }
        for a in plant.axes() {
            h.push(axis(a, "TransformStateStatus"));
            h.push(axis(a, "ControlledByTransformStatus"));
        }
    }
    if superimposes(twin) {
        for a in plant.axes() {
            h.push(axis(a, "sup_pos"));
            h.push(axis(a, "sup_vel"));
        }
    }
    if uses_states(twin) {
        for a in plant.axes() {
            h.push(axis(a, "CIPAxisState"));
            h.push(axis(a, "AxisFault"));
        }
    }
    for a in plant.axes() {
        if task.axis_config(a.handle).soft_travel_limits.is_some() {
            h.push(axis(a, "MotionFault"));
        }
    }
    for (k, a) in plant.axes().iter().enumerate() {
        if plant.drive_torque(k).is_some() {
            h.push(axis(a, "torque"));
        }
    }
    for a in plant.axes() {
        h.push(axis(a, "overshoot"));
    }
    let named = |group: Group, owner: &str, leaf: &str| Column {
        name: format!("{owner}.{leaf}"),
        group,
        leaf: owner.to_owned(),
    };
    h.extend(plant.sensors().iter().map(|s| named(Group::Sensor, &s.name, "state")));
    if plant.material().is_some() {
        let cell = &twin.scene().cell;
        h.extend(
            cell.conveyors
                .iter()
                .map(|c| named(Group::Conveyor, &c.name, "speed_mps")),
        );
        h.extend(cell.grippers.iter().map(|g| named(Group::Gripper, &g.name, "part")));
        h.extend(
            cell.cylinders
                .iter()
                .map(|c| named(Group::Cylinder, &c.name, "position_m")),
        );
        for c in ["in_cell", "delivered", "rejected", "dropped", "lost"] {
            h.push(Column::of(Group::Parts, "parts", c));
        }
    }
    h.extend(program.traced_tags().iter().enumerate().map(|(k, t)| Column {
        name: t.name.clone(),
        group: Group::Tag(k),
        leaf: t.name.clone(),
    }));
    if twin.scene().plant == crate::scene::PlantMode::Kinematic {
        h.push(Column::of(Group::Plant, "plant", "kinematic"));
    }
    h
}

const CAM_COLUMNS: [&str; 5] = [
    "PositionCamStatus",
    "PositionCamLockStatus",
    "PositionCamPendingStatus",
    "VelocityLimitExceeded",
    "AccelLimitExceeded",
];

/// One update's row, a cell per [`header`] column.
pub fn row(twin: &Twin) -> Vec<String> {
    let mut line = String::new();
    write_row(twin, &mut line);
    line.split(',').map(str::to_owned).collect()
}

/// Appends one update's row to `line`, cells separated by commas, without
/// the line's end. No cell holds a comma: numbers, integers, bits, and
/// strings escaped ([`crate::program::Program::traced_text`]).
pub fn write_row(twin: &Twin, line: &mut String) {
    write_cells(twin, &mut Row { line, cells: 0 });
}

/// What a row's cells are written into: text for the CSV ([`write_row`]),
/// numbers for the expectations ([`Values`]).
pub trait Cells {
    /// A number (f64).
    fn number(&mut self, x: f64);
    /// A single-precision number (a REAL tag).
    fn real32(&mut self, x: f32);
    /// A bit.
    fn bit(&mut self, b: bool);
    /// An integer.
    fn int(&mut self, i: i64);
    /// An unsigned 64-bit integer (a ULINT tag).
    fn uint(&mut self, u: u64);
    /// A string's text (escaped: no comma, [`crate::program::Program::traced_text`]).
    fn text(&mut self, s: &str);
}

/// One update's row as numbers at full precision, with each column's
/// type: what an expectation reads a trace column from.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Values {
    /// A value per [`header`] column.
    pub values: Vec<f64>,
    /// A type per column: BOOL for bits, DINT for integers, REAL for a
    /// REAL tag, LREAL for the other numbers.
    pub types: Vec<DataType>,
}

impl Values {
    /// Fills the row with `twin`'s values now.
    pub fn read(&mut self, twin: &Twin) {
        self.values.clear();
        self.types.clear();
        write_cells(twin, self);
    }
}

impl Cells for Values {
    fn number(&mut self, x: f64) {
        self.values.push(x);
        self.types.push(DataType::Lreal);
    }

    fn real32(&mut self, x: f32) {
        self.values.push(f64::from(x));
        self.types.push(DataType::Real);
    }

    fn bit(&mut self, b: bool) {
        self.values.push(f64::from(u8::from(b)));
        self.types.push(DataType::Bool);
    }

    fn int(&mut self, i: i64) {
        self.values.push(i as f64);
        self.types.push(DataType::Dint);
    }

    fn uint(&mut self, u: u64) {
        self.values.push(u as f64);
        self.types.push(DataType::Dint);
    }

    /// Text is not a number: an expectation reads a string's members.
    fn text(&mut self, _: &str) {
        self.values.push(f64::NAN);
        self.types.push(DataType::Lreal);
    }
}

/// Writes one update's row into `row`, a cell per [`header`] column.
pub fn write_cells(twin: &Twin, row: &mut impl Cells) {
    let (task, program, plant) = (twin.task(), twin.program(), twin.plant());
    row.number(twin.time_s());
    for a in plant.axes() {
        let s = task.axis_state(a.handle);
        for x in [
            s.command_position,
            s.command_velocity,
            s.command_acceleration,
            s.actual_position,
        ] {
            row.number(x);
        }
    }
    for fb in program.fbs() {
        let o = task.outputs(fb.handle);
        o.bits().into_iter().for_each(|(_, b)| row.bit(b));
        row.int(i64::from(o.error_id));
    }
    for ins in program.instructions() {
        let b = task.motion_bits(ins.handle);
        b.bits().into_iter().for_each(|(_, x)| row.bit(x));
        b.codes().into_iter().for_each(|(_, code)| row.int(i64::from(code)));
    }
    if plant.collision_enabled() {
        row.int(plant.collision_events().len() as i64);
        plant.clearance_m().into_iter().for_each(|x| row.number(x));
    }
    for a in plant.axes().iter().filter(|a| task.is_cam_slave(a.handle)) {
        let s = task.slave_cam_status(a.handle);
        let l = task.limits_exceeded(a.handle);
        for b in [s.position_cam, s.lock, s.pending, l.velocity, l.acceleration] {
            row.bit(b);
        }
    }
    coord_row(twin, row);
    if uses_mct(twin) {
        for cs in task.coord_handles() {
            row.bit(task.transform_source_status(cs));
            row.bit(task.transform_target_status(cs));
        }
        for a in plant.axes() {
            row.bit(task.transform_state_status(a.handle));
            row.bit(task.controlled_by_transform_status(a.handle));
        }
    }
    if superimposes(twin) {
        for a in plant.axes() {
            let s = task.superimposed(a.handle).unwrap_or_default();
            row.number(s.position);
            row.number(s.velocity);
        }
    }
    if uses_states(twin) {
        for a in plant.axes() {
            row.int(i64::from(task.cip_axis_state(a.handle).code()));
            row.int(i64::from(task.axis_faults(a.handle).0));
        }
    }
    for a in plant.axes() {
        if task.axis_config(a.handle).soft_travel_limits.is_some() {
            row.int(i64::from(task.motion_faults(a.handle).0));
        }
    }
    for k in 0..plant.axes().len() {
        if let Some(torque) = plant.drive_torque(k) {
            row.number(torque);
        }
    }
    for a in plant.axes() {
        row.bit(task.profile_overshoot(a.handle));
    }
    for s in plant.sensors() {
        row.bit(s.output());
    }
    if let Some(m) = plant.material() {
        m.conveyors().iter().for_each(|c| row.number(c.speed_mps()));
        m.grippers().iter().for_each(|g| row.int(g.part() as i64));
        m.cylinders().for_each(|c| row.number(c.position_m()));
        let c = m.counts();
        row.int(m.parts().len() as i64);
        for n in [c.delivered, c.rejected, c.dropped, c.lost] {
            row.int(n as i64);
        }
    }
    for t in program.traced_tags() {
        if let Some(text) = program.traced_text(t) {
            row.text(&text);
            continue;
        }
        match program.traced(t, task) {
            Value::Bool(b) => row.bit(b),
            Value::Int(i) if t.unsigned_64() => row.uint(i as u64),
            Value::Int(i) => row.int(i),
            Value::Real(x) if t.single_precision() => row.real32(x as f32),
            Value::Real(x) => row.number(x),
        }
    }
    if twin.scene().plant == crate::scene::PlantMode::Kinematic {
        row.bit(true);
    }
}

/// A row being written into a line: each cell after the first starts
/// with a comma.
struct Row<'a> {
    line: &'a mut String,
    cells: usize,
}

impl Row<'_> {
    /// The line, ready for the next cell's text.
    fn cell(&mut self) -> &mut String {
        if self.cells > 0 {
            self.line.push(',');
        }
        self.cells += 1;
        self.line
    }
}

impl Cells for Row<'_> {
    fn number(&mut self, x: f64) {
        write_shortest(self.cell(), x, x);
    }

    fn real32(&mut self, x: f32) {
        write_shortest(self.cell(), x, f64::from(x));
    }

    fn bit(&mut self, b: bool) {
        self.cell().push(if b { '1' } else { '0' });
    }

    fn int(&mut self, i: i64) {
        use std::fmt::Write;
        // Writing to a String cannot fail.
        let _ = write!(self.cell(), "{i}");
    }

    fn uint(&mut self, u: u64) {
        use std::fmt::Write;
        // Writing to a String cannot fail.
        let _ = write!(self.cell(), "{u}");
    }

    fn text(&mut self, s: &str) {
        self.cell().push_str(s);
    }
}

fn coord_row(twin: &Twin, row: &mut impl Cells) {
    let (task, plant) = (twin.task(), twin.plant());
    let links = plant.world_from_link();
    for cs in task.coord_handles() {
        let name = &task.coord_config(cs).name;
        task.coord_status(cs).bits().into_iter().for_each(|(_, b)| row.bit(b));
        if let Some(t) = plant.tool_trails().iter().find(|t| &t.system == name) {
            for x in links[t.link].0 {
                row.number(x);
            }
        }
    }
}

/// Whether the program calls MCT.
fn uses_mct(twin: &Twin) -> bool {
    twin.program().calls(&mct::MCT)
}

/// Whether the program's single-axis motion can be superimposed: a MAM,
/// or a MAJ where coordinated moves run.
fn superimposes(twin: &Twin) -> bool {
    let p = twin.program();
    p.calls(&mam::MAM) || (p.calls(&maj::MAJ) && (p.calls(&mclm::MCLM) || p.calls(&mccm::MCCM)))
}

/// Whether the program calls a state instruction.
fn uses_states(twin: &Twin) -> bool {
    [
        &mso::MSO,
        &msf::MSF,
        &masd::MASD,
        &masr::MASR,
        &mafr::MAFR,
        &mah::MAH,
        &mcsd::MCSD,
        &mcsr::MCSR,
    ]
    .iter()
    .any(|i| twin.program().calls(i))
}

#[cfg(test)]
mod tests {
    use super::{number, number_f32};
    use rand::{Rng, SeedableRng};

    #[test]
    fn numbers_are_short_near_zero_and_read_back_exactly() {
        for (x, text) in [
            (0.0, "0"),
            (-0.0, "-0"),
            (90.0, "90"),
            (0.25, "0.25"),
            (1e-5, "0.00001"),
            (9.9e-6, "9.9e-6"),
            (-2.5e-7, "-2.5e-7"),
            (1e-20, "1e-20"),
            (1.5e16, "1.5e16"),
            (f64::INFINITY, "inf"),
        ] {
            assert_eq!(number(x), text);
        }
        assert_eq!(number(f64::NAN), "NaN");
        assert_eq!(number_f32(1e-7), "1e-7");
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(15);
        for _ in 0..100_000 {
            let x = f64::from_bits(rng.random::<u64>());
            if x.is_nan() {
                continue;
            }
            let text = number(x);
            assert_eq!(text.parse::<f64>().map(f64::to_bits), Ok(x.to_bits()), "{text}");
            // At most 17 significant digits, a sign, a point and an exponent.
            assert!(text.len() <= 24, "{text}");
            let y = f32::from_bits(rng.random::<u32>());
            if !y.is_nan() {
                assert_eq!(number_f32(y).parse::<f32>().map(f32::to_bits), Ok(y.to_bits()));
            }
        }
    }
}
