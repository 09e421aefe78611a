//! Scene errors: one [`SceneError`] per file problem, displayed as
//! `FILE:LINE:COLUMN: FIELD: what is wrong`, and the [`Problem`] it names.

use crate::source::{Diagnostic, Label, SourceFile};
use std::fmt;
use std::ops::Range;
use std::path::PathBuf;
use std::sync::Arc;

use super::model::{AxisKind, BaseType, Location, TagType, Units};

/// What is wrong with a field's value.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum Problem {
    /// NaN or infinite.
    #[error("must be a finite number, got {value}")]
    NotFinite {
        /// The value.
        value: f64,
    },
    /// Zero or negative where a positive value is needed.
    #[error("must be greater than 0, got {value}")]
    NotPositive {
        /// The value.
        value: f64,
    },
    /// Negative where zero or more is needed.
    #[error("must not be negative, got {value}")]
    Negative {
        /// The value.
        value: f64,
    },
    /// Outside an inclusive (or, when `exclusive`, open) range.
    #[error("must be between {} and {}{}, got {}", short(*min), short(*max), if *exclusive { " (exclusive)" } else { "" }, short(*value))]
    OutOfRange {
        /// The value.
        value: f64,
        /// Lower bound.
        min: f64,
        /// Upper bound.
        max: f64,
        /// Whether the bounds themselves are excluded.
        exclusive: bool,
    },
    /// The physics step does not divide the coarse update period.
    #[error("physics_step_ms = {physics_step_ms} does not divide coarse_update_ms = {coarse_update_ms} exactly")]
    StepNotDivisor {
        /// The physics step, ms.
        physics_step_ms: f64,
        /// The coarse update period, ms.
        coarse_update_ms: f64,
    },
    /// A camera asks for more frames per second than the coarse updates
    /// give (frames are rendered at updates, one per update at most).
    #[error(
        "fps = {fps} is above the coarse update rate of {max_fps} per second (coarse_update_ms); frames are rendered at updates"
    )]
    FpsAboveUpdateRate {
        /// The camera's fps.
        fps: f64,
        /// 1000 / coarse_update_ms.
        max_fps: f64,
    },
    /// A name used twice.
    #[error("duplicate name '{name}' (first declared on line {first_line})")]
    DuplicateName {
        /// The name.
        name: String,
        /// Line of the first declaration.
        first_line: usize,
    },
    /// An empty name.
    #[error("must not be empty")]
    Empty,
    /// A rule of a table's fields that no other problem states (which
    /// fields go together, what a device needs).
    #[error("{why}")]
    Rule {
        /// The rule, in words.
        why: String,
    },
    /// A name that becomes part of an output file's name but could leave
    /// its folder or hide the file.
    #[error("'{name}' cannot be part of a file name: {why}")]
    NotAFileName {
        /// The name.
        name: String,
        /// What is wrong with it.
        why: &'static str,
    },
    /// Not an ST identifier.
    #[error("'{name}' is not a valid tag name (letters, digits and '_', not starting with a digit)")]
    InvalidName {
        /// The name.
        name: String,
    },
    /// A referenced file that does not exist, or is not a regular file
    /// (a folder, a device, a FIFO).
    #[error("file '{}' {}", path.display(), if path.exists() { "is not a regular file (a folder, a device or a FIFO)" } else { "does not exist" })]
    MissingFile {
        /// The resolved path.
        path: PathBuf,
    },
    /// A program step with both `at_s` and `when`.
    #[error("has both 'at_s' and 'when'; give exactly one")]
    BothTriggers,
    /// A program step with neither `at_s` nor `when`.
    #[error("has neither 'at_s' nor 'when'; give exactly one")]
    NoTrigger,
    /// `after_s` on a step that is not triggered by `when`.
    #[error("'after_s' applies only to steps triggered by 'when'")]
    AfterWithoutWhen,
    /// `at_s` past the end of the run.
    #[error("at_s = {at_s} is after the end of the run (duration_s = {duration_s})")]
    AfterEnd {
        /// The step time, s.
        at_s: f64,
        /// The run duration, s.
        duration_s: f64,
    },
    /// A data type that contains itself, directly or through others.
    #[error("data type {cycle} contains itself: a structure cannot hold its own type")]
    RecursiveDataType {
        /// The chain, `A → B → A`.
        cycle: String,
    },
    /// A data type named like a predefined type.
    #[error("'{name}' is a predefined data type: name the data type otherwise")]
    PredefinedTypeName {
        /// The name.
        name: String,
    },
    /// A data type with neither members nor `string_length`, or both.
    #[error("a data type has members (a structure) or string_length (a string type): {what}")]
    DataTypeShape {
        /// What was given.
        what: &'static str,
    },
    /// A member type a data type cannot hold.
    #[error(
        "a data type's member is a number, BOOL, a string type, another data type, an instruction's structure (FBD_TIMER …) or a MOTION_INSTRUCTION, not {base} (declare {base} tags instead)"
    )]
    MemberTypeNotAllowed {
        /// The type's name.
        base: &'static str,
    },
    /// A member array of more than one dimension.
    #[error("'{type_name}': a member array has one dimension (Logix); give it as dimension = N")]
    MemberDimensions {
        /// The type as written.
        type_name: String,
    },
    /// A value naming a member its data type does not have.
    #[error("{ty} has no member '{member}' (members: {members})")]
    UnknownMember {
        /// The data type.
        ty: &'static str,
        /// The name written.
        member: String,
        /// The members it has.
        members: String,
    },
    /// A string value longer than its type holds, or not ASCII.
    #[error("'{text}' does not fit {ty}: {why}")]
    BadString {
        /// The string type.
        ty: &'static str,
        /// The value (shortened).
        text: String,
        /// What is wrong.
        why: String,
    },
    /// A tag type not in the known list.
    #[error("unknown tag type '{type_name}', expected one of {}, or a [[data_types]] name, optionally as an array TYPE[N]", BaseType::all_names().join(", "))]
    UnknownTagType {
        /// The type as written.
        type_name: String,
    },
    /// `TYPE[0]` or a malformed array length.
    #[error("array length in '{type_name}' must be a whole number of at least 1")]
    BadArrayLength {
        /// The type as written.
        type_name: String,
    },
    /// An array of more than three dimensions (or a CAM array of more than
    /// one).
    #[error("'{type_name}' has {count} dimensions: Logix arrays have one to three (CAM and CAM_PROFILE arrays one)")]
    TooManyDimensions {
        /// The type as written.
        type_name: String,
        /// How many were written.
        count: usize,
    },
    /// An array longer than its type allows.
    #[error("'{type_name}' has more than {max} elements ({why})")]
    ArrayTooLong {
        /// The type as written.
        type_name: String,
        /// The most elements allowed.
        max: usize,
        /// Where the limit comes from.
        why: &'static str,
    },
    /// An array of a type that cannot be an array here.
    #[error("{base} cannot be declared as an array")]
    ArrayNotAllowed {
        /// The element type name.
        base: &'static str,
    },
    /// An initial value that does not fit the tag type.
    #[error("value does not fit type {ty}: expected {expected}")]
    ValueMismatch {
        /// The tag type.
        ty: TagType,
        /// What would fit.
        expected: &'static str,
    },
    /// An initial value on a type that takes none.
    #[error("{ty} tags take no initial value")]
    ValueNotAllowed {
        /// The tag type.
        ty: TagType,
    },
    /// A type that needs an initial value.
    #[error("{ty} tags need a value ({expected})")]
    ValueRequired {
        /// The tag type.
        ty: TagType,
        /// What to give.
        expected: &'static str,
    },
    /// A `coordinate_system` or `geometry` table on a tag that is not a
    /// coordinate system.
    #[error("only COORDINATE_SYSTEM tags take coordinate_system and geometry tables")]
    CoordinateSystemOnly,
    /// A second `MOTION_GROUP` tag, or one in a program.
    #[error("a controller has one MOTION_GROUP, a controller tag ({why})")]
    OneMotionGroup {
        /// What is wrong: `'G1' is already it`, `not a program's`.
        why: String,
    },
    /// An `options` table on a tag that is not an MC_MoveModulo instance.
    #[error("only MC_MoveModulo instances take an options table (ST_MoveOptions)")]
    MoveOptionsOnly,
    /// An `ST_MoveOptions` member the twin does not simulate, set.
    #[error("{member} is not simulated: {why}")]
    OptionNotSimulated {
        /// The member.
        member: &'static str,
        /// What the twin does instead.
        why: &'static str,
    },
    /// An unknown MCT geometry type.
    #[error("unknown geometry '{name}', expected one of {expected}")]
    UnknownGeometry {
        /// The name given.
        name: String,
        /// The accepted names.
        expected: String,
    },
    /// A tag type only the controller scope may declare.
    #[error("{ty} tags are controller-scoped: declare it in [[tags]]")]
    ControllerScopeOnly {
        /// The type.
        ty: &'static str,
    },
    /// A routine listed twice in a program.
    #[error("routine '{name}' is listed twice in this program (a routine's name is its file stem)")]
    DuplicateRoutine {
        /// The routine name.
        name: String,
    },
    /// A word that is not one of a field's words.
    #[error("unknown {what} '{word}', expected {expected}")]
    UnknownWord {
        /// What the field names.
        what: &'static str,
        /// The word as written.
        word: String,
        /// The accepted words.
        expected: String,
    },
    /// A task field that does not apply to the task's type.
    #[error("'{field}' does not apply to {kind} tasks")]
    TaskFieldNotApplicable {
        /// The field.
        field: &'static str,
        /// The task type.
        kind: &'static str,
    },
    /// A task field its type needs.
    #[error("{kind} tasks need '{field}'{hint}")]
    TaskFieldRequired {
        /// The field.
        field: &'static str,
        /// The task type.
        kind: &'static str,
        /// What to write.
        hint: &'static str,
    },
    /// `constant = true` on a tag the planner keeps.
    #[error("{ty} tags cannot be constant: the instructions write them")]
    ConstantNotAllowed {
        /// The type.
        ty: TagType,
    },
    /// `usage` on a controller tag.
    #[error("usage applies to program tags: a controller tag is every program's already")]
    UsageOnControllerTag,
    /// A `connection` on a tag that is not an Input, Output or InOut
    /// parameter.
    #[error(
        "a connection belongs to an Input, Output or InOut parameter: give usage = \"input\", \"output\" or \"inout\""
    )]
    ConnectionWithoutParameter,
    /// An InOut parameter without its connection.
    #[error("an InOut parameter needs a connection: the tag it stands for (1756-PM021)")]
    InOutNeedsConnection,
    /// A connection that cannot be made.
    #[error("connection '{text}': {why}")]
    BadConnection {
        /// As written.
        text: String,
        /// Why not.
        why: String,
    },
    /// A second continuous task.
    #[error("a controller has at most one continuous task (the first is '{first}')")]
    SecondContinuousTask {
        /// The first one.
        first: String,
    },
    /// A fault routine that is not one of the program's routines.
    #[error("no routine '{name}' in this program: the fault routine is one of its 'routines' (not 'main'){}", if routines.is_empty() { String::new() } else { format!("; routines: {routines}") })]
    UnknownFaultRoutine {
        /// The name.
        name: String,
        /// The program's routines.
        routines: String,
    },
    /// A `[trace] rungs` entry that names no ladder rung.
    #[error("'{text}' names no rung: {why}")]
    UnknownRung {
        /// As written.
        text: String,
        /// What is wrong.
        why: String,
    },
    /// A date and time not written as RFC 3339 UTC.
    #[error("'{text}' is not a UTC date and time such as 2026-11-27T08:00:00Z ({why})")]
    BadDateTime {
        /// As written.
        text: String,
        /// What is wrong.
        why: &'static str,
    },
    /// A routine dialect other than `logix` or `iec`.
    #[error("unknown dialect '{name}', expected \"logix\" or \"iec\"")]
    UnknownDialect {
        /// The dialect as written.
        name: String,
    },
    /// A coordinate system naming an undeclared axis.
    #[error("unknown axis '{name}'")]
    UnknownAxis {
        /// The name.
        name: String,
        /// The declared axis nearest to it, for the `help:` line.
        nearest: Option<String>,
    },
    /// Axis units that do not fit its kind.
    #[error("units '{units}' do not fit a {kind} axis (rotary: deg or rad; linear: m or mm)")]
    UnitsMismatch {
        /// The units.
        units: Units,
        /// The axis kind.
        kind: AxisKind,
    },
    /// `initial_position` disagrees with `robot.initial_joints`.
    #[error(
        "initial_position = {initial_position} {units} disagrees with robot.initial_joints.{joint} = {joint_position_si} (SI)"
    )]
    InitialPositionMismatch {
        /// The axis' initial position, axis units.
        initial_position: f64,
        /// The axis units.
        units: Units,
        /// The joint.
        joint: String,
        /// The joint's initial position, rad or m.
        joint_position_si: f64,
    },
    /// `soft_travel_limits` not ordered `[min, max]` with min < max.
    #[error("soft_travel_limits = [{min}, {max}] must have min < max")]
    SoftTravelLimitsOrder {
        /// The first element.
        min: f64,
        /// The second element.
        max: f64,
    },
    /// `soft_travel_limit_checking = false` with `soft_travel_limits`.
    #[error("soft_travel_limit_checking = false turns the soft_travel_limits given off; remove one of them")]
    SoftTravelLimitsUnchecked,
    /// `soft_travel_limits` on a modulo axis.
    #[error("soft_travel_limits are not allowed on a modulo axis (modulo_period = {period})")]
    SoftTravelLimitsOnModulo {
        /// The modulo period.
        period: f64,
    },
    /// The initial position outside the soft travel limits.
    #[error("initial position {position} is outside soft_travel_limits = [{min}, {max}]")]
    OutsideSoftTravelLimits {
        /// The initial position, axis units.
        position: f64,
        /// Lower limit.
        min: f64,
        /// Upper limit.
        max: f64,
    },
    /// Both drives on one axis.
    #[error("give 'motor' (a spring drive) or 'drive' (a servo drive), not both")]
    SpringAndServo,
    /// A homing sequence that needs a sensor the twin does not simulate.
    #[error(
        "home_sequence '{sequence}' is not simulated (the twin has no home switch, encoder marker or torque sensing): use \"immediate\""
    )]
    HomeSequenceNotSimulated {
        /// The sequence word.
        sequence: &'static str,
    },
    /// Active homing on a feedback-only axis.
    #[error("home_mode \"active\" moves the axis: a feedback-only axis has no drive (use \"passive\")")]
    ActiveHomingWithoutDrive,
    /// A drive field on a virtual axis.
    #[error("a virtual axis (no joint) has no drive: '{field}' applies only to an axis with a joint")]
    NoDrive {
        /// The field.
        field: &'static str,
    },
    /// Two axes driving one joint.
    #[error("joint '{joint}' is already driven by axis '{other_axis}'")]
    SharedJoint {
        /// The joint.
        joint: String,
        /// The first axis driving it.
        other_axis: String,
    },
    /// A shape without one of its parameters.
    #[error("shape '{shape}' needs field '{field}'")]
    MissingShapeField {
        /// The shape kind.
        shape: &'static str,
        /// The missing field.
        field: &'static str,
    },
    /// A parameter of another shape.
    #[error("field '{field}' does not apply to shape '{shape}'")]
    ExtraShapeField {
        /// The shape kind.
        shape: &'static str,
        /// The extra field.
        field: &'static str,
    },
    /// A camera looking at its own position.
    #[error("camera target must differ from its position")]
    DegenerateCamera,
    /// A camera that looks straight up or down (world +Z is the image's up).
    #[error(
        "the camera looks straight up or down, so the image has no up direction (world +Z); move the target sideways a little"
    )]
    CameraAlongUp,
    /// Cam points whose master positions do not increase.
    #[error("cam master positions must increase strictly (point {index})")]
    CamNotIncreasing {
        /// Index of the first offending point.
        index: usize,
    },
    /// Snapshots without any camera.
    #[error("snapshots need at least one [[cameras]] entry")]
    NoCamera,
    /// A snapshot frame listed twice.
    #[error("frame {frame} is listed twice")]
    DuplicateFrame {
        /// The frame.
        frame: u32,
    },
    /// A URDF joint that does not exist (for the integrator's checks).
    #[error("the URDF has no joint '{joint}'")]
    UnknownJoint {
        /// The joint.
        joint: String,
    },
    /// An `[[expect]]` with no kind, or with more than one.
    #[error("give exactly one of always, never, eventually, at_end, sequence, cycle{}", if found.is_empty() { String::new() } else { format!(" (found {})", found.join(" and ")) })]
    ExpectKinds {
        /// The kinds given.
        found: Vec<&'static str>,
    },
    /// An option of another kind of expectation.
    #[error("'{option}' does not apply to '{kind}' ({kind} takes {takes})")]
    ExpectOption {
        /// The option given.
        option: &'static str,
        /// The expectation's kind.
        kind: &'static str,
        /// The options the kind takes.
        takes: &'static str,
    },
    /// A `sequence` with no condition.
    #[error("a sequence needs at least one condition")]
    EmptySequence,
    /// A time past the end of the run.
    #[error("{option} = {value} is after the end of the run (duration_s = {duration_s}{})", if let Some(v) = variant { format!(" in variant '{v}'") } else { String::new() })]
    PastEnd {
        /// The option.
        option: &'static str,
        /// Its value, s.
        value: f64,
        /// The run's duration, s.
        duration_s: f64,
        /// The variant whose duration it is, if any.
        variant: Option<String>,
    },
    /// A window whose start is after its end.
    #[error("{low} = {low_s} is after {high} = {high_s}")]
    WindowOrder {
        /// The start's option.
        low: &'static str,
        /// The start, s.
        low_s: f64,
        /// The end's option.
        high: &'static str,
        /// The end, s.
        high_s: f64,
    },
    /// A variant setting a tag the scene does not declare.
    #[error("unknown tag '{name}': a variant sets a declared tag's initial value (a controller tag, or Program.Tag)")]
    UnknownVariantTag {
        /// The name.
        name: String,
        /// The declared tag nearest to it, for the `help:` line.
        nearest: Option<String>,
    },
    /// An expected exit code that a run does not end with.
    #[error(
        "exit code {code} is not one a run ends with: 0 (ran to its end), 2 (an instruction error), 3 (a collision abort), 4 (a major fault) or 5 (a physics fault)"
    )]
    NotRunExitCode {
        /// The code.
        code: i64,
    },
}

/// An error loading a scene. `Display` is one line:
/// `FILE:LINE:COLUMN: FIELD: what is wrong`; [`SceneError::diagnostic`]
/// adds the source line with a caret and the `help:` lines.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SceneError {
    /// The file could not be read.
    Read {
        /// The scene file.
        path: PathBuf,
        /// The I/O error.
        #[source]
        source: std::io::Error,
    },
    /// The file is not UTF-8 text.
    NotUtf8 {
        /// The scene file.
        path: PathBuf,
        /// 1-based line of the first byte that is not UTF-8.
        line: usize,
        /// 1-based column (characters) of that byte.
        column: usize,
    },
    /// TOML syntax, an unknown or missing field, or a value of the wrong type.
    Toml {
        /// The scene file.
        file: PathBuf,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// The table the error is in (`axes[1]`, `robot`), if any.
        table: Option<String>,
        /// For a value of the wrong type, its field (`axes[0].max_velocity`).
        field: Option<String>,
        /// The TOML/serde message (for a value of the wrong type: `expected
        /// a number, found "fast"`).
        message: String,
        /// The scene's text and the bytes the TOML parser points at.
        at: Option<Box<(Arc<SourceFile>, Range<usize>)>>,
    },
    /// A `call`, `when`, trace tag or routine that is not valid Structured
    /// Text, or a routine file that cannot be read.
    Syntax(Box<Diagnostic>),
    /// A value that parses but is not allowed.
    Invalid {
        /// The scene file.
        file: PathBuf,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// The field, e.g. `axes[0].max_velocity`.
        field: String,
        /// What is wrong.
        problem: Box<Problem>,
        /// The scene's text and the bytes of the value at fault.
        at: Option<Box<(Arc<SourceFile>, Range<usize>)>>,
    },
}

impl SceneError {
    /// The 1-based line and column, when the error has a place in the file.
    #[must_use]
    pub fn location(&self) -> Option<Location> {
        match self {
            SceneError::Read { .. } => None,
            SceneError::NotUtf8 { line, column, .. }
            | SceneError::Toml { line, column, .. }
            | SceneError::Invalid { line, column, .. } => Some(Location {
                line: *line,
                column: *column,
            }),
            SceneError::Syntax(d) => d.location().map(|(_, line, column)| Location { line, column }),
        }
    }

    /// The field path, for syntax and validation errors.
    #[must_use]
    pub fn field(&self) -> Option<&str> {
        match self {
            SceneError::Invalid { field, .. } => Some(field),
            SceneError::Syntax(d) => d.field.as_deref(),
            SceneError::Toml { table, field, .. } => field.as_deref().or(table.as_deref()),
            SceneError::Read { .. } | SceneError::NotUtf8 { .. } => None,
        }
    }

    /// The validation problem, for [`SceneError::Invalid`].
    #[must_use]
    pub fn problem(&self) -> Option<&Problem> {
        match self {
            SceneError::Invalid { problem, .. } => Some(problem.as_ref()),
            _ => None,
        }
    }

    /// The error as a [`Diagnostic`]: the one-line text, the source line
    /// with a caret under the value at fault, and `help:` lines.
    #[must_use]
    pub fn diagnostic(&self) -> Diagnostic {
        match self {
            SceneError::Syntax(d) => (**d).clone(),
            SceneError::Invalid {
                file,
                line,
                column,
                field,
                problem,
                at,
            } => {
                let mut d = Diagnostic::error(problem.to_string()).in_field(field.clone());
                d = match at {
                    Some(at) => d.with_label(Label::new(&at.0, at.1.clone(), problem.label())),
                    None => d.at_place(file.clone(), *line, *column),
                };
                match problem.help() {
                    Some(help) => d.with_help(help),
                    None => d,
                }
            }
            SceneError::Toml {
                file, line, column, at, ..
            } => {
                // The one-line text, field and message together, as Display
                // gives them: the first line stays what scripts grep.
                let text = self.to_string();
                let prefix = format!("{}:{line}:{column}: ", file.display());
                let message = text.strip_prefix(&prefix).unwrap_or(&text).to_owned();
                let d = Diagnostic::error(message);
                let d = match at {
                    Some(at) => d.with_label(Label::new(&at.0, at.1.clone(), "here")),
                    None => d.at_place(file.clone(), *line, *column),
                };
                match unknown_field_nearest(&text) {
                    Some(n) => d.with_help(format!("did you mean '{n}'?")),
                    None => d,
                }
            }
            SceneError::NotUtf8 { path, line, column } => {
                Diagnostic::error("not UTF-8 text (a scene is a TOML text file)").at_place(path.clone(), *line, *column)
            }
            SceneError::Read { path, source } => {
                Diagnostic::error(format!("{}: cannot read the scene file: {source}", path.display()))
            }
        }
    }
}

impl From<SceneError> for Diagnostic {
    fn from(e: SceneError) -> Self {
        e.diagnostic()
    }
}

impl Problem {
    /// What the caret's label says.
    fn label(&self) -> String {
        match self {
            Problem::DuplicateName { .. } => "declared again here".to_owned(),
            Problem::MissingFile { .. } => "no such file".to_owned(),
            Problem::UnknownAxis { .. } => "no axis of that name in [[axes]]".to_owned(),
            _ => String::new(),
        }
    }

    /// A `help:` line, where the problem has an obvious fix.
    fn help(&self) -> Option<String> {
        match self {
            Problem::UnknownAxis { nearest: Some(n), .. } | Problem::UnknownVariantTag { nearest: Some(n), .. } => {
                Some(format!("did you mean '{n}'?"))
            }
            Problem::UnknownTagType { type_name } => {
                let names = BaseType::all_names();
                let base = type_name.split('[').next().unwrap_or_default();
                crate::source::diag::nearest(base, names.iter().copied())
                    .map(|n| format!("did you mean '{}'?", type_name.replacen(base, n, 1)))
            }
            Problem::BothTriggers | Problem::NoTrigger => {
                Some("give a step at_s = <seconds> or when = \"<tag>.<bit>\"".to_owned())
            }
            _ => None,
        }
    }
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SceneError::Read { path, source } => write!(f, "{}: cannot read the scene file: {source}", path.display()),
            SceneError::NotUtf8 { path, line, column } => write!(
                f,
                "{}:{line}:{column}: not UTF-8 text (a scene is a TOML text file)",
                path.display()
            ),
            SceneError::Toml {
                file,
                line,
                column,
                table,
                field,
                message,
                ..
            } => {
                write!(f, "{}:{line}:{column}: ", file.display())?;
                if let Some(field) = field {
                    write!(f, "{field}: ")?;
                } else if let Some(table) = table {
                    write!(f, "in {table}: ")?;
                }
                // serde quotes names with backticks; keep the message on one line.
                f.write_str(&message.trim().replace('`', "'").replace('\n', " "))
            }
            SceneError::Syntax(d) => d.fmt(f),
            SceneError::Invalid {
                file,
                line,
                column,
                field,
                problem,
                ..
            } => {
                write!(f, "{}:{line}:{column}: {field}: {problem}", file.display())
            }
        }
    }
}

/// For serde's `unknown field 'x', expected one of 'a', 'b', …` (quotes as
/// the one-line text has them), the expected field nearest to `x`.
fn unknown_field_nearest(text: &str) -> Option<String> {
    let rest = &text[text.find("unknown field '")? + "unknown field '".len()..];
    let (field, rest) = rest.split_once('\'')?;
    let expected = &rest[rest.find("expected one of ")? + "expected one of ".len()..];
    let known: Vec<&str> = expected.split(", ").map(|k| k.trim_matches('\'')).collect();
    crate::source::diag::nearest(field, known).map(str::to_owned)
}

/// A number as a message writes it: plainly between 10⁻⁴ and 10¹⁵ in
/// magnitude (and 0), in exponent form past them (`1e300`, not three
/// hundred digits).
fn short(x: f64) -> String {
    if x == 0.0 || !x.is_finite() || (1e-4..1e15).contains(&x.abs()) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}
