//! The controller's system objects a program reads with `GSV` and sets
//! with `SSV` (1756-RM003, "Get System Value and Set System Value"): each
//! task's and program's status, the fault log, the wall clock and the
//! motion group. [`ATTRIBUTES`] is the one catalogue of the classes and
//! attributes the twin models: the compiler looks names up in it, and the
//! scene README's table is written from it.
//!
//! Times are µs. An attribute of type `DINT[n]` is read into (and set
//! from) `n` consecutive DINTs starting at the element the operand names,
//! as the controller copies it.

/// A class of system object.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Class {
    /// `TASK`: a task's status and settings.
    Task,
    /// `PROGRAM`: a program's status and fault records.
    Program,
    /// `WALLCLOCKTIME`: the controller's clock.
    WallClockTime,
    /// `FAULTLOG`: counts and bits of the faults since the start.
    FaultLog,
    /// `MOTIONGROUP`: the motion group.
    MotionGroup,
}

impl Class {
    /// Every class by its name.
    pub const NAMES: [(&'static str, Class); 5] = [
        ("TASK", Class::Task),
        ("PROGRAM", Class::Program),
        ("WALLCLOCKTIME", Class::WallClockTime),
        ("FAULTLOG", Class::FaultLog),
        ("MOTIONGROUP", Class::MotionGroup),
    ];

    /// The class called `name` (case-insensitive).
    #[must_use]
    pub fn find(name: &str) -> Option<Class> {
        Class::NAMES
            .iter()
            .find(|(n, _)| n.eq_ignore_ascii_case(name))
            .map(|(_, c)| *c)
    }

    /// Its name.
    #[must_use]
    pub fn name(self) -> &'static str {
        Class::NAMES.iter().find(|(_, c)| *c == self).map_or("?", |(n, _)| n)
    }

    /// Whether an instance names one object (a task, a program); the
    /// others have one object and take any instance name (Logix writes
    /// none).
    #[must_use]
    pub fn has_instances(self) -> bool {
        matches!(self, Class::Task | Class::Program)
    }
}

/// An attribute of a class.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Attr {
    /// TASK and PROGRAM `LastScanTime`.
    LastScanTime,
    /// TASK and PROGRAM `MaxScanTime`.
    MaxScanTime,
    /// TASK `MaxInterval`.
    MaxInterval,
    /// TASK `MinInterval`.
    MinInterval,
    /// TASK `StartTime`.
    StartTime,
    /// TASK `OverlapCount`.
    OverlapCount,
    /// TASK `Priority`.
    Priority,
    /// TASK `Rate`.
    Rate,
    /// TASK `Watchdog`.
    Watchdog,
    /// TASK `Status`.
    Status,
    /// TASK `InhibitTask`.
    InhibitTask,
    /// TASK `EnableTimeOut`.
    EnableTimeOut,
    /// TASK `DisableUpdateOutputs`.
    DisableUpdateOutputs,
    /// TASK and PROGRAM `Instance`.
    Instance,
    /// PROGRAM `MajorFaultRecord`.
    MajorFaultRecord,
    /// PROGRAM `MinorFaultRecord`.
    MinorFaultRecord,
    /// PROGRAM `DisableFlag`.
    DisableFlag,
    /// WALLCLOCKTIME `CurrentValue`.
    CurrentValue,
    /// WALLCLOCKTIME `DateTime`.
    DateTime,
    /// WALLCLOCKTIME `LocalDateTime`.
    LocalDateTime,
    /// FAULTLOG `MajorEvents`.
    MajorEvents,
    /// FAULTLOG `MinorEvents`.
    MinorEvents,
    /// FAULTLOG `MajorFaultBits`.
    MajorFaultBits,
    /// FAULTLOG `MinorFaultBits`.
    MinorFaultBits,
    /// MOTIONGROUP `CoarseUpdatePeriod`.
    CoarseUpdatePeriod,
}

/// What a program may do with an attribute.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Access {
    /// GSV only.
    Get,
    /// GSV and SSV.
    GetSet,
}

/// An attribute's entry: its class and name, its Logix type (`INT`,
/// `DINT`, or `DINT` × `words` for an array), whether SSV may set it, its
/// unit and what it holds.
#[derive(Debug, Clone, Copy)]
pub struct Attribute {
    /// Its class.
    pub class: Class,
    /// Its name.
    pub name: &'static str,
    /// Which attribute.
    pub attr: Attr,
    /// Its type, as RM003 writes it.
    pub ty: &'static str,
    /// DINTs it takes (1 for a scalar).
    pub words: usize,
    /// GSV only, or GSV and SSV.
    pub access: Access,
    /// Its unit (empty for none).
    pub unit: &'static str,
    /// What it holds.
    pub doc: &'static str,
}

/// An [`Attribute`], one row of the catalogue.
#[allow(clippy::too_many_arguments)]
const fn attribute(
    class: Class,
    name: &'static str,
    attr: Attr,
    ty: &'static str,
    words: usize,
    access: Access,
    unit: &'static str,
    doc: &'static str,
) -> Attribute {
    Attribute {
        class,
        name,
        attr,
        ty,
        words,
        access,
        unit,
        doc,
    }
}

use Access::{Get, GetSet};
use Attr as A;
use Class as C;

/// Every system attribute the twin models (1756-RM003, GSV/SSV objects).
pub const ATTRIBUTES: [Attribute; 28] = [
    attribute(
        C::Task,
        "LastScanTime",
        A::LastScanTime,
        "DINT",
        1,
        GetSet,
        "µs",
        "elapsed time of the task's last scan, higher-priority tasks and coarse updates included",
    ),
    attribute(
        C::Task,
        "MaxScanTime",
        A::MaxScanTime,
        "DINT",
        1,
        GetSet,
        "µs",
        "longest LastScanTime since the start (SSV resets it)",
    ),
    attribute(
        C::Task,
        "MaxInterval",
        A::MaxInterval,
        "DINT[2]",
        2,
        GetSet,
        "µs",
        "longest time between two successive scan starts (low, high DINT)",
    ),
    attribute(
        C::Task,
        "MinInterval",
        A::MinInterval,
        "DINT[2]",
        2,
        GetSet,
        "µs",
        "shortest time between two successive scan starts (low, high DINT)",
    ),
    attribute(
        C::Task,
        "StartTime",
        A::StartTime,
        "DINT[2]",
        2,
        Get,
        "µs",
        "WALLCLOCKTIME when the last scan started (low, high DINT)",
    ),
    attribute(
        C::Task,
        "OverlapCount",
        A::OverlapCount,
        "DINT",
        1,
        GetSet,
        "",
        "triggers ignored because the task was still running or waiting (SSV 0 resets it)",
    ),
    attribute(
        C::Task,
        "Priority",
        A::Priority,
        "INT",
        1,
        Get,
        "",
        "1 (highest) to 15; a continuous task reads 0",
    ),
    attribute(
        C::Task,
        "Rate",
        A::Rate,
        "DINT",
        1,
        Get,
        "µs",
        "a periodic task's period, an event task's timeout (0 without one), 0 for a continuous task",
    ),
    attribute(
        C::Task,
        "Watchdog",
        A::Watchdog,
        "DINT",
        1,
        Get,
        "µs",
        "the watchdog time",
    ),
    attribute(
        C::Task,
        "Status",
        A::Status,
        "DINT",
        1,
        GetSet,
        "",
        "bit 0: an EVENT instruction triggered the last scan; bit 1: its timeout did; bit 2: an overlap occurred (SSV clears bits)",
    ),
    attribute(
        C::Task,
        "InhibitTask",
        A::InhibitTask,
        "DINT",
        1,
        GetSet,
        "",
        "1 while the task is inhibited (its triggers ignored)",
    ),
    attribute(
        C::Task,
        "EnableTimeOut",
        A::EnableTimeOut,
        "DINT",
        1,
        Get,
        "",
        "1 when an event task has a timeout",
    ),
    attribute(
        C::Task,
        "DisableUpdateOutputs",
        A::DisableUpdateOutputs,
        "DINT",
        1,
        GetSet,
        "",
        "stored; the twin has no output modules to update",
    ),
    attribute(
        C::Task,
        "Instance",
        A::Instance,
        "DINT",
        1,
        Get,
        "",
        "the task's number, in [[tasks]] order from 1",
    ),
    attribute(
        C::Program,
        "LastScanTime",
        A::LastScanTime,
        "DINT",
        1,
        GetSet,
        "µs",
        "elapsed time of the program's last scan",
    ),
    attribute(
        C::Program,
        "MaxScanTime",
        A::MaxScanTime,
        "DINT",
        1,
        GetSet,
        "µs",
        "longest LastScanTime since the start (SSV resets it)",
    ),
    attribute(
        C::Program,
        "MajorFaultRecord",
        A::MajorFaultRecord,
        "DINT[11]",
        11,
        GetSet,
        "",
        "the last instruction fault: TimeLow, TimeHigh (µs), Type + Code × 65536, Info[8]; the fault routine clears the fault by setting word 2 (Type and Code) to 0",
    ),
    attribute(
        C::Program,
        "MinorFaultRecord",
        A::MinorFaultRecord,
        "DINT[11]",
        11,
        GetSet,
        "",
        "the last minor fault, in the same layout",
    ),
    attribute(
        C::Program,
        "DisableFlag",
        A::DisableFlag,
        "SINT",
        1,
        GetSet,
        "",
        "1 while the program is disabled (not scanned)",
    ),
    attribute(
        C::Program,
        "Instance",
        A::Instance,
        "DINT",
        1,
        Get,
        "",
        "the program's number, in scene order from 1",
    ),
    attribute(
        C::WallClockTime,
        "CurrentValue",
        A::CurrentValue,
        "DINT[2]",
        2,
        Get,
        "µs",
        "µs since 1970-01-01T00:00:00Z (low, high DINT), from [controller] start_time",
    ),
    attribute(
        C::WallClockTime,
        "DateTime",
        A::DateTime,
        "DINT[7]",
        7,
        Get,
        "",
        "year, month, day, hour, minute, second, µs (UTC)",
    ),
    attribute(
        C::WallClockTime,
        "LocalDateTime",
        A::LocalDateTime,
        "DINT[7]",
        7,
        Get,
        "",
        "as DateTime: the twin's controller runs on UTC",
    ),
    attribute(
        C::FaultLog,
        "MajorEvents",
        A::MajorEvents,
        "INT",
        1,
        GetSet,
        "",
        "major faults since the start",
    ),
    attribute(
        C::FaultLog,
        "MinorEvents",
        A::MinorEvents,
        "INT",
        1,
        GetSet,
        "",
        "minor faults since the start",
    ),
    attribute(
        C::FaultLog,
        "MajorFaultBits",
        A::MajorFaultBits,
        "DINT",
        1,
        GetSet,
        "",
        "bit n: a major fault of type n occurred",
    ),
    attribute(
        C::FaultLog,
        "MinorFaultBits",
        A::MinorFaultBits,
        "DINT",
        1,
        GetSet,
        "",
        "bit 4: an instruction minor fault; bit 6: a task overlap",
    ),
    attribute(
        C::MotionGroup,
        "CoarseUpdatePeriod",
        A::CoarseUpdatePeriod,
        "DINT",
        1,
        Get,
        "µs",
        "the coarse update period",
    ),
];

/// The attribute `name` of `class` (case-insensitive).
#[must_use]
pub fn find(class: Class, name: &str) -> Option<&'static Attribute> {
    ATTRIBUTES
        .iter()
        .find(|a| a.class == class && a.name.eq_ignore_ascii_case(name))
}

/// The attribute names of `class`, for messages.
#[must_use]
pub fn names(class: Class) -> Vec<&'static str> {
    ATTRIBUTES.iter().filter(|a| a.class == class).map(|a| a.name).collect()
}

/// The table of [`ATTRIBUTES`] as `scenes/README.md` writes it (*System
/// objects*).
#[must_use]
pub fn markdown_table() -> String {
    let mut out = String::from(
        "| class | attribute | type | unit | access | what it holds |\n| --- | --- | --- | --- | --- | --- |\n",
    );
    for a in &ATTRIBUTES {
        let access = match a.access {
            Access::Get => "GSV",
            Access::GetSet => "GSV, SSV",
        };
        out.push_str(&format!(
            "| `{}` | `{}` | {} | {} | {access} | {} |\n",
            a.class.name(),
            a.name,
            a.ty,
            a.unit,
            a.doc
        ));
    }
    out
}

/// `Status` bit 0: an EVENT instruction triggered the last scan.
pub const STATUS_EVENT: i64 = 1;
/// `Status` bit 1: the event task's timeout triggered the last scan.
pub const STATUS_TIMEOUT: i64 = 2;
/// `Status` bit 2: a trigger overlapped.
pub const STATUS_OVERLAP: i64 = 4;

/// A task's status.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TaskStatus {
    /// Its name.
    pub name: String,
    /// `Priority` (0 for the continuous task).
    pub priority: i64,
    /// `Rate`, µs.
    pub rate_us: i64,
    /// `Watchdog`, µs.
    pub watchdog_us: i64,
    /// `EnableTimeOut`.
    pub enable_timeout: bool,
    /// `LastScanTime`, µs.
    pub last_scan_us: i64,
    /// `MaxScanTime`, µs.
    pub max_scan_us: i64,
    /// `MaxInterval`, µs.
    pub max_interval_us: i64,
    /// `MinInterval`, µs (0 until two scans started).
    pub min_interval_us: i64,
    /// `StartTime`, wall clock µs.
    pub start_time_us: i64,
    /// `OverlapCount`.
    pub overlap_count: i64,
    /// `Status`.
    pub status: i64,
    /// `InhibitTask`.
    pub inhibit: bool,
    /// `DisableUpdateOutputs`.
    pub disable_update_outputs: bool,
    /// Scans run.
    pub scans: i64,
    /// When the last scan started, on the controller's clock, ns.
    pub last_start_ns: Option<i64>,
}

impl TaskStatus {
    /// A scan that took `elapsed_us` ended: `LastScanTime`, `MaxScanTime`.
    pub fn scan_ended(&mut self, elapsed_us: i64) {
        self.last_scan_us = elapsed_us;
        self.max_scan_us = self.max_scan_us.max(elapsed_us);
    }
}

/// A program's status.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ProgramStatus {
    /// Its name.
    pub name: String,
    /// Its task's index.
    pub task: usize,
    /// `LastScanTime`, µs.
    pub last_scan_us: i64,
    /// `MaxScanTime`, µs.
    pub max_scan_us: i64,
    /// `MajorFaultRecord`.
    pub major_record: [i64; 11],
    /// `MinorFaultRecord`.
    pub minor_record: [i64; 11],
    /// `DisableFlag`.
    pub disabled: bool,
}

impl ProgramStatus {
    /// A scan that took `elapsed_us` ended: `LastScanTime`, `MaxScanTime`.
    pub fn scan_ended(&mut self, elapsed_us: i64) {
        self.last_scan_us = elapsed_us;
        self.max_scan_us = self.max_scan_us.max(elapsed_us);
    }
}

/// The system objects' state.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct System {
    /// Each task's status, in scene order.
    pub tasks: Vec<TaskStatus>,
    /// Each program's status, in scene order (task by task).
    pub programs: Vec<ProgramStatus>,
    /// FAULTLOG `MajorEvents`.
    pub major_events: i64,
    /// FAULTLOG `MinorEvents`.
    pub minor_events: i64,
    /// FAULTLOG `MajorFaultBits`.
    pub major_fault_bits: i64,
    /// FAULTLOG `MinorFaultBits`.
    pub minor_fault_bits: i64,
    /// The wall clock at the start of the run, µs since 1970.
    pub start_time_us: i64,
    /// The coarse update period, µs.
    pub coarse_update_us: i64,
    /// Each axis' servo drive attributes as the controller last set them
    /// (scene order; `None` for an axis without a servo drive).
    pub drives: Vec<Option<crate::scene::ServoGains>>,
    /// The axes whose drive attributes an SSV changed since the plant last
    /// took them ([`crate::program::Program::take_drive_changes`]).
    pub drive_changes: Vec<usize>,
}

impl System {
    /// The wall clock at `clock_ns` on the controller's clock.
    #[must_use]
    pub fn wall_clock_us(&self, clock_ns: i64) -> i64 {
        self.start_time_us + clock_ns.div_euclid(1000)
    }

    /// A fault record: the time, type and code, no Info.
    #[must_use]
    pub fn record(&self, clock_ns: i64, fault_type: u8, code: u8) -> [i64; 11] {
        let t = self.wall_clock_us(clock_ns);
        let mut r = [0; 11];
        r[0] = i64::from(t as u32 as i32);
        r[1] = t >> 32;
        r[2] = i64::from(fault_type) | i64::from(code) << 16;
        r
    }

    /// Reads attribute `attr` of object `instance` (a task's or program's
    /// index) into `out` (its words).
    pub fn get(&self, class: Class, attr: Attr, instance: usize, clock_ns: i64, out: &mut [i64]) {
        let split = |v: i64, out: &mut [i64]| {
            out[0] = i64::from(v as u32 as i32);
            out[1] = v >> 32;
        };
        let flag = |b: bool| i64::from(b);
        match (class, attr) {
            (Class::Task, a) => {
                let t = &self.tasks[instance];
                match a {
                    A::LastScanTime => out[0] = t.last_scan_us,
                    A::MaxScanTime => out[0] = t.max_scan_us,
                    A::MaxInterval => split(t.max_interval_us, out),
                    A::MinInterval => split(t.min_interval_us, out),
                    A::StartTime => split(t.start_time_us, out),
                    A::OverlapCount => out[0] = t.overlap_count,
                    A::Priority => out[0] = t.priority,
                    A::Rate => out[0] = t.rate_us,
                    A::Watchdog => out[0] = t.watchdog_us,
                    A::Status => out[0] = t.status,
                    A::InhibitTask => out[0] = flag(t.inhibit),
                    A::EnableTimeOut => out[0] = flag(t.enable_timeout),
                    A::DisableUpdateOutputs => out[0] = flag(t.disable_update_outputs),
                    _ => out[0] = instance as i64 + 1,
                }
            }
            (Class::Program, a) => {
                let p = &self.programs[instance];
                match a {
                    A::LastScanTime => out[0] = p.last_scan_us,
                    A::MaxScanTime => out[0] = p.max_scan_us,
                    A::MajorFaultRecord => out.copy_from_slice(&p.major_record),
                    A::MinorFaultRecord => out.copy_from_slice(&p.minor_record),
                    A::DisableFlag => out[0] = flag(p.disabled),
                    _ => out[0] = instance as i64 + 1,
                }
            }
            (Class::WallClockTime, A::CurrentValue) => split(self.wall_clock_us(clock_ns), out),
            (Class::WallClockTime, _) => out.copy_from_slice(&date_time(self.wall_clock_us(clock_ns))),
            (Class::FaultLog, A::MajorEvents) => out[0] = self.major_events,
            (Class::FaultLog, A::MinorEvents) => out[0] = self.minor_events,
            (Class::FaultLog, A::MajorFaultBits) => out[0] = self.major_fault_bits,
            (Class::FaultLog, _) => out[0] = self.minor_fault_bits,
            (Class::MotionGroup, _) => out[0] = self.coarse_update_us,
        }
    }

    /// Sets attribute `attr` of object `instance` from `words`; the
    /// compiler let only settable attributes through.
    pub fn set(&mut self, class: Class, attr: Attr, instance: usize, words: &[i64]) {
        let joined = |w: &[i64]| (w[0] as u32 as i64) | (w[1] << 32);
        let v = words[0];
        match class {
            Class::Task => {
                let t = &mut self.tasks[instance];
                match attr {
                    A::LastScanTime => t.last_scan_us = v,
                    A::MaxScanTime => t.max_scan_us = v,
                    A::MaxInterval => t.max_interval_us = joined(words),
                    A::MinInterval => t.min_interval_us = joined(words),
                    A::OverlapCount => t.overlap_count = v,
                    A::Status => t.status = v,
                    A::InhibitTask => t.inhibit = v != 0,
                    A::DisableUpdateOutputs => t.disable_update_outputs = v != 0,
                    _ => unreachable!("read-only TASK attribute"),
                }
            }
            Class::Program => {
                let p = &mut self.programs[instance];
                match attr {
                    A::LastScanTime => p.last_scan_us = v,
                    A::MaxScanTime => p.max_scan_us = v,
                    A::MajorFaultRecord => p.major_record.copy_from_slice(words),
                    A::MinorFaultRecord => p.minor_record.copy_from_slice(words),
                    A::DisableFlag => p.disabled = v != 0,
                    _ => unreachable!("read-only PROGRAM attribute"),
                }
            }
            Class::FaultLog => match attr {
                A::MajorEvents => self.major_events = v,
                A::MinorEvents => self.minor_events = v,
                A::MajorFaultBits => self.major_fault_bits = v,
                _ => self.minor_fault_bits = v,
            },
            Class::WallClockTime | Class::MotionGroup => unreachable!("read-only class"),
        }
    }
}

/// Year, month, day, hour, minute, second, µs of `us` since 1970 (UTC).
#[must_use]
pub fn date_time(us: i64) -> [i64; 7] {
    let days = us.div_euclid(86_400_000_000);
    let rest = us.rem_euclid(86_400_000_000);
    // Civil from days (proleptic Gregorian).
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    [
        year,
        month,
        day,
        rest / 3_600_000_000,
        rest / 60_000_000 % 60,
        rest / 1_000_000 % 60,
        rest % 1_000_000,
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn date_time_splits_microseconds_since_1970() {
        assert_eq!(date_time(0), [1970, 1, 1, 0, 0, 0, 0]);
        assert_eq!(date_time(946_684_800_000_000), [2000, 1, 1, 0, 0, 0, 0]);
        assert_eq!(date_time(1_709_210_096_500_000), [2024, 2, 29, 12, 34, 56, 500_000]);
        assert_eq!(date_time(1_795_766_400_000_001), [2026, 11, 27, 8, 0, 0, 1]);
    }

    #[test]
    fn every_attribute_is_found_by_its_class_and_name() {
        for a in &ATTRIBUTES {
            assert_eq!(
                find(a.class, &a.name.to_ascii_lowercase()).map(|x| x.attr),
                Some(a.attr)
            );
            assert!(a.words >= 1 && a.words <= 11);
        }
        assert!(find(Class::Task, "Nope").is_none());
    }

    #[test]
    fn the_scene_readme_lists_every_attribute_as_the_catalogue_has_it() {
        assert_eq!(
            crate::program::scene_readme_block("system-objects"),
            markdown_table(),
            "scenes/README.md's system objects table is out of date"
        );
    }

    #[test]
    fn a_record_splits_the_time_and_packs_type_and_code() {
        let sys = System {
            start_time_us: 0x1_2345_6789,
            ..System::default()
        };
        let r = sys.record(0, 4, 20);
        assert_eq!((r[0], r[1], r[2]), (0x2345_6789, 1, 4 + 20 * 65536));
        let mut out = [0; 2];
        sys.get(Class::WallClockTime, Attr::CurrentValue, 0, 5_000, &mut out);
        assert_eq!(out, [0x2345_6789 + 5, 1]);
    }
}
