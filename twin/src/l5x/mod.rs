//! Studio 5000 exports (L5X, 1756-RM084): the XML read into a [`Project`]
//! whose every name and value keeps its byte range in the file, so that a
//! later stage can point at the attribute a problem comes from.
//!
//! This stage reads; it does not decide what a scene makes of the project
//! (`scene/import.rs` turns a [`Project`] into scene text). It refuses only
//! what makes the file unreadable as a controller export: malformed XML, a
//! root that is not `RSLogix5000Content` with `TargetType="Controller"`,
//! an element or attribute Studio always writes that is missing, nesting
//! deeper than [`MAX_XML_DEPTH`] or a file larger than [`MAX_L5X_BYTES`].
//! Elements it does not know are skipped; what it knows but the twin does
//! not simulate is listed in [`Project::not_simulated`] with its place.
//!
//! The XML parser is roxmltree (already a dependency, for COLLADA): it
//! keeps every node's and attribute's byte range, which the one-line
//! errors at the L5X position need. The `l5x` crate's serde model drops
//! positions, so it was not used.
//!
//! Values are read as Studio writes them: `Decorated` data first
//! (`DataValue`, `Array`/`Element`, `Structure`/`DataValueMember`/
//! `ArrayMember`/`StructureMember`), else `String` data for strings, else
//! the `L5K` text for numbers and arrays of numbers. Integers may carry a
//! radix (`16#00FF`, `2#0101`, `8#17`) and `_` separators.

mod module;
mod value;
mod xml;

use std::ops::Range;

pub use module::{Connection, IoMember, IoType, Module};
pub use value::Value;
pub use xml::{At, L5xError, MAX_XML_DEPTH};
use xml::{Node, child, children, start_tag};

/// The largest export read, bytes.
pub const MAX_L5X_BYTES: usize = 256 * 1024 * 1024;
/// The most `Line Number`s an ST routine may skip at once.
const MAX_LINE_GAP: u64 = 10_000;

/// The attributes of one parameters element (`AxisParameters`,
/// `CoordinateSystemParameters`, `MotionGroupParameters`), in file order.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Params {
    /// The element's start tag.
    pub element: Range<usize>,
    /// Name, value and the value's bytes.
    pub attrs: Vec<(String, At<String>)>,
}

impl Params {
    /// The attribute `name`.
    #[must_use]
    pub fn get(&self, name: &str) -> Option<&At<String>> {
        self.attrs.iter().find(|(n, _)| n == name).map(|(_, v)| v)
    }
}

/// An axis tag (`AXIS_CIP_DRIVE`, `AXIS_VIRTUAL`, or another axis type,
/// which the scene refuses by name).
#[derive(Debug, Clone, PartialEq)]
pub struct AxisTag {
    /// `Name`.
    pub name: At<String>,
    /// `DataType`.
    pub data_type: At<String>,
    /// `Data Format="Axis"`/`AxisParameters`.
    pub params: Params,
}

/// A `COORDINATE_SYSTEM` tag.
#[derive(Debug, Clone, PartialEq)]
pub struct CoordinateSystemTag {
    /// `Name`.
    pub name: At<String>,
    /// `Data Format="CoordinateSystem"`/`CoordinateSystemParameters`.
    pub params: Params,
}

/// A member of a user data type.
#[derive(Debug, Clone, PartialEq)]
pub struct Member {
    /// `Name`.
    pub name: At<String>,
    /// `DataType` (`BIT` for a BOOL packed into a hidden SINT).
    pub data_type: At<String>,
    /// `Dimension` (0: not an array).
    pub dimension: At<u64>,
    /// `Hidden="true"`: the host of packed BOOLs.
    pub hidden: bool,
    /// `Description`.
    pub description: String,
}

/// A `DataType` of `Class="User"`.
#[derive(Debug, Clone, PartialEq)]
pub struct DataType {
    /// `Name`.
    pub name: At<String>,
    /// `Family="StringFamily"`: a string type of this many characters.
    pub string_length: Option<u64>,
    /// `Members/Member`.
    pub members: Vec<Member>,
    /// `Description`.
    pub description: String,
}

/// A tag: controller or program scope.
#[derive(Debug, Clone, PartialEq)]
pub struct Tag {
    /// `Name`.
    pub name: At<String>,
    /// `DataType` (none on an alias).
    pub data_type: Option<At<String>>,
    /// `Dimensions`, as written (`"6 3"`).
    pub dimensions: Option<At<String>>,
    /// `AliasFor` on an alias.
    pub alias_for: Option<At<String>>,
    /// `Constant="true"`.
    pub constant: bool,
    /// `ExternalAccess`.
    pub external_access: Option<At<String>>,
    /// `Usage` of a program parameter.
    pub usage: Option<At<String>>,
    /// `Description`.
    pub description: String,
    /// The value Studio wrote.
    pub value: Option<At<Value>>,
    /// The `Tag` start tag.
    pub span: Range<usize>,
}

/// A routine.
#[derive(Debug, Clone, PartialEq)]
pub struct Routine {
    /// `Name`.
    pub name: At<String>,
    /// `Type` (`ST`, `RLL`, `FBD`, `SFC`).
    pub kind: At<String>,
    /// An ST routine's text: its `STContent/Line`s joined by `\n` (text
    /// line *i* is `Line Number="i"`); or an RLL routine's: its
    /// `RLLContent/Rung` texts, one a line (text line *i* is the *i*-th
    /// rung); and the file byte of each text byte (one past the end too).
    pub text: Option<(std::sync::Arc<str>, std::sync::Arc<[u32]>)>,
}

/// A program.
#[derive(Debug, Clone, PartialEq)]
pub struct Program {
    /// `Name`.
    pub name: At<String>,
    /// `MainRoutineName`.
    pub main: Option<At<String>>,
    /// `FaultRoutineName`.
    pub fault: Option<At<String>>,
    /// `Disabled="true"`.
    pub disabled: bool,
    /// `UseAsFolder="true"`: no logic of its own.
    pub use_as_folder: bool,
    /// `Tags/Tag`.
    pub tags: Vec<Tag>,
    /// `Routines/Routine`.
    pub routines: Vec<Routine>,
    /// Parameter connections: (this program's parameter, the other end).
    pub connections: Vec<(At<String>, At<String>)>,
}

/// A task.
#[derive(Debug, Clone, PartialEq)]
pub struct Task {
    /// `Name`.
    pub name: At<String>,
    /// `Type`: `CONTINUOUS`, `PERIODIC`, `EVENT`.
    pub kind: At<String>,
    /// `Rate` (ms): the period, or an event task's timeout.
    pub rate: Option<At<String>>,
    /// `Priority`.
    pub priority: Option<At<String>>,
    /// `Watchdog` (ms).
    pub watchdog: Option<At<String>>,
    /// `InhibitTask="true"`.
    pub inhibit: bool,
    /// `EventInfo EventTrigger`.
    pub event_trigger: Option<At<String>>,
    /// `EventInfo EventTag` (the axis of a registration trigger).
    pub event_tag: Option<At<String>>,
    /// `EventInfo EnableTimeout="true"`.
    pub enable_timeout: bool,
    /// `ScheduledPrograms/ScheduledProgram Name`, in order.
    pub programs: Vec<At<String>>,
}

/// An Add-On Instruction's parameter (1756-PM010).
#[derive(Debug, Clone, PartialEq)]
pub struct AoiParameter {
    /// `Name`.
    pub name: At<String>,
    /// `DataType`.
    pub data_type: At<String>,
    /// `Dimensions` (an InOut array).
    pub dimensions: Option<At<String>>,
    /// `Usage`: `Input`, `Output` or `InOut`.
    pub usage: At<String>,
    /// `Required="true"`: a call passes it.
    pub required: bool,
    /// `Visible="true"`.
    pub visible: bool,
    /// `Constant="true"` (an InOut the instruction may not write).
    pub constant: bool,
    /// `DefaultData`.
    pub default: Option<At<Value>>,
    /// `Description`.
    pub description: String,
}

/// An Add-On Instruction's local tag.
#[derive(Debug, Clone, PartialEq)]
pub struct AoiLocal {
    /// `Name`.
    pub name: At<String>,
    /// `DataType`.
    pub data_type: At<String>,
    /// `Dimensions`.
    pub dimensions: Option<At<String>>,
    /// `DefaultData`.
    pub default: Option<At<Value>>,
}

/// An `AddOnInstructionDefinition`.
#[derive(Debug, Clone, PartialEq)]
pub struct AoiDefinition {
    /// `Name`.
    pub name: At<String>,
    /// `Revision`.
    pub revision: Option<String>,
    /// `Description`.
    pub description: String,
    /// `ExecutePrescan="true"`: the Prescan routine runs at prescan.
    pub execute_prescan: bool,
    /// `ExecutePostscan="true"` (SFC actions only: never runs here).
    pub execute_postscan: bool,
    /// `ExecuteEnableInFalse="true"`: the EnableInFalse routine runs on a
    /// FALSE rung.
    pub execute_enable_in_false: bool,
    /// `Parameters/Parameter` in definition order, `EnableIn` and
    /// `EnableOut` included.
    pub parameters: Vec<AoiParameter>,
    /// `LocalTags/LocalTag`.
    pub local_tags: Vec<AoiLocal>,
    /// `Routines/Routine`: `Logic`, `Prescan`, `Postscan`, `EnableInFalse`.
    pub routines: Vec<Routine>,
    /// The element's bytes in the file (for an export of its own).
    pub span: Range<usize>,
}

/// What the twin does not simulate, found in the file.
#[derive(Debug, Clone, PartialEq)]
pub struct Note {
    /// Its bytes.
    pub span: Range<usize>,
    /// What it is, one line.
    pub text: String,
    /// The name `not_simulated` gives it (`Program/Routine`, a tag), when it
    /// changes behaviour if skipped.
    pub item: Option<String>,
}

/// A controller export, as read.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Project {
    /// `Controller Name`.
    pub controller: String,
    /// `MajorFaultProgram`.
    pub major_fault_program: Option<At<String>>,
    /// `ReportMinorOverflow`.
    pub report_minor_overflow: Option<At<String>>,
    /// `MotionGroupParameters` of the motion group tag, with its name.
    pub motion_group: Option<(At<String>, Params)>,
    /// Axis tags, in file order.
    pub axes: Vec<AxisTag>,
    /// Coordinate system tags.
    pub coordinate_systems: Vec<CoordinateSystemTag>,
    /// User data types.
    pub data_types: Vec<DataType>,
    /// The other controller tags.
    pub tags: Vec<Tag>,
    /// Programs, in file order.
    pub programs: Vec<Program>,
    /// Tasks, in file order.
    pub tasks: Vec<Task>,
    /// I/O modules, in file order.
    pub modules: Vec<Module>,
    /// Add-On Instruction definitions, in file order.
    pub aois: Vec<AoiDefinition>,
    /// What is not simulated.
    pub not_simulated: Vec<Note>,
}

/// Reads an Add-On Instruction export (`TargetType=
/// "AddOnInstructionDefinition"`): its definition, the one marked
/// `Use="Target"` (or the only one), and the others it uses.
///
/// # Errors
/// The first problem, at its bytes.
pub fn read_aoi_export(text: &str) -> Result<Vec<AoiDefinition>, L5xError> {
    let doc = parse_xml(text)?;
    let root = doc.root_element();
    let r = Reader { text };
    if !root.has_tag_name("RSLogix5000Content") {
        return Err(r.err(
            start_tag(text, root),
            format!(
                "<{}> is not a Studio 5000 export (RSLogix5000Content)",
                root.tag_name().name()
            ),
        ));
    }
    let target = r.required(root, "TargetType")?;
    if target.value != "AddOnInstructionDefinition" {
        return Err(r.err(
            target.span,
            format!(
                "a {} export: export the Add-On Instruction (right-click it > Export Add-On Instruction)",
                target.value
            ),
        ));
    }
    let defs = child(root, "Controller").and_then(|c| child(c, "AddOnInstructionDefinitions"));
    let mut out = Vec::new();
    for a in defs.into_iter().flat_map(|d| children(d, "AddOnInstructionDefinition")) {
        out.push(r.aoi(a)?);
    }
    if out.is_empty() {
        return Err(r.err(
            start_tag(text, root),
            "the export holds no <AddOnInstructionDefinition>",
        ));
    }
    Ok(out)
}

fn parse_xml(text: &str) -> Result<roxmltree::Document<'_>, L5xError> {
    if text.len() > MAX_L5X_BYTES {
        return Err(L5xError {
            span: 0..0,
            message: format!("the file is {} bytes; at most {MAX_L5X_BYTES} are read", text.len()),
        });
    }
    if let Some(at) = xml::too_deep(text, MAX_XML_DEPTH) {
        return Err(L5xError {
            span: at..at,
            message: format!("elements nested deeper than {MAX_XML_DEPTH}"),
        });
    }
    let options = roxmltree::ParsingOptions {
        allow_dtd: false,
        ..roxmltree::ParsingOptions::default()
    };
    let doc = roxmltree::Document::parse_with_options(text, options).map_err(|e| {
        let pos = e.pos();
        L5xError {
            span: byte_of(text, pos.row as usize, pos.col as usize)..byte_of(text, pos.row as usize, pos.col as usize),
            message: format!("malformed XML: {e}"),
        }
    })?;
    check_depth(doc.root_element())?;
    Ok(doc)
}

/// Reads an export.
///
/// # Errors
/// The first problem, at its bytes.
pub fn read(text: &str) -> Result<Project, L5xError> {
    let doc = parse_xml(text)?;
    let r = Reader { text };
    r.project(doc.root_element())
}

fn byte_of(text: &str, row: usize, col: usize) -> usize {
    let line_start: usize = text
        .split_inclusive('\n')
        .take(row.saturating_sub(1))
        .map(str::len)
        .sum();
    let line = &text[line_start.min(text.len())..];
    line_start
        + line
            .char_indices()
            .nth(col.saturating_sub(1))
            .map_or(line.len(), |(i, _)| i)
}

fn check_depth(root: Node<'_, '_>) -> Result<(), L5xError> {
    for node in root.descendants().filter(Node::is_element) {
        let depth = node.ancestors().filter(Node::is_element).count();
        if depth > MAX_XML_DEPTH {
            return Err(L5xError {
                span: node.range().start..node.range().start,
                message: format!("elements nested {depth} deep; at most {MAX_XML_DEPTH} are read"),
            });
        }
        if depth == MAX_XML_DEPTH {
            // Its children are deeper: report the first of them.
            if let Some(c) = node.children().find(Node::is_element) {
                return Err(L5xError {
                    span: c.range().start..c.range().start,
                    message: format!("elements nested deeper than {MAX_XML_DEPTH}"),
                });
            }
        }
    }
    Ok(())
}

struct Reader<'t> {
    text: &'t str,
}

impl Reader<'_> {
    fn err(&self, span: Range<usize>, message: impl Into<String>) -> L5xError {
        L5xError {
            span,
            message: message.into(),
        }
    }

    fn attr(&self, node: Node<'_, '_>, name: &str) -> Option<At<String>> {
        node.attribute_node(name).map(|a| At {
            value: a.value().to_owned(),
            span: a.range_value(),
        })
    }

    fn required(&self, node: Node<'_, '_>, name: &str) -> Result<At<String>, L5xError> {
        self.attr(node, name).ok_or_else(|| {
            self.err(
                start_tag(self.text, node),
                format!("<{}> has no {name} attribute", node.tag_name().name()),
            )
        })
    }

    fn flag(&self, node: Node<'_, '_>, name: &str) -> Result<bool, L5xError> {
        match self.attr(node, name) {
            None => Ok(false),
            Some(a) => match a.value.to_ascii_lowercase().as_str() {
                "true" => Ok(true),
                "false" => Ok(false),
                _ => Err(self.err(a.span, format!("{name}=\"{}\": expected true or false", a.value))),
            },
        }
    }

    fn description(&self, node: Node<'_, '_>) -> String {
        child(node, "Description")
            .map(|d| {
                d.descendants()
                    .filter(Node::is_text)
                    .filter_map(|n| n.text())
                    .collect::<String>()
                    .trim()
                    .to_owned()
            })
            .unwrap_or_default()
    }

    fn params(&self, node: Node<'_, '_>) -> Params {
        Params {
            element: start_tag(self.text, node),
            attrs: node
                .attributes()
                .map(|a| {
                    (
                        a.name().to_owned(),
                        At {
                            value: a.value().to_owned(),
                            span: a.range_value(),
                        },
                    )
                })
                .collect(),
        }
    }

    fn project(&self, root: Node<'_, '_>) -> Result<Project, L5xError> {
        if !root.has_tag_name("RSLogix5000Content") {
            return Err(self.err(
                start_tag(self.text, root),
                format!(
                    "<{}> is not a Studio 5000 export (RSLogix5000Content)",
                    root.tag_name().name()
                ),
            ));
        }
        let target = self.required(root, "TargetType")?;
        if target.value != "Controller" {
            return Err(self.err(
                target.span,
                format!(
                    "a {} export: export the controller (File > Save As, .L5X) so that its tasks, motion group and axes come with it",
                    target.value
                ),
            ));
        }
        let Some(controller) = child(root, "Controller") else {
            return Err(self.err(start_tag(self.text, root), "the export has no <Controller>"));
        };
        let mut p = Project {
            controller: self.required(controller, "Name")?.value,
            major_fault_program: self
                .attr(controller, "MajorFaultProgram")
                .filter(|a| !a.value.is_empty()),
            report_minor_overflow: self.attr(controller, "ReportMinorOverflow"),
            ..Project::default()
        };
        if let Some(a) = self
            .attr(controller, "PowerLossProgram")
            .filter(|a| !a.value.is_empty())
        {
            p.not_simulated.push(Note {
                span: a.span,
                text: format!("power-loss program {}: the twin has no power loss", a.value),
                item: None,
            });
        }
        if let Some(types) = child(controller, "DataTypes") {
            for t in children(types, "DataType") {
                self.data_type(t, &mut p)?;
            }
        }
        if let Some(modules) = child(controller, "Modules") {
            for m in children(modules, "Module") {
                let module = module::read(self.text, m)?;
                if module.inhibited {
                    p.not_simulated.push(Note {
                        span: module.name.span.clone(),
                        text: format!(
                            "module {}: inhibited on the controller; the twin's sensors update its input tags all the same",
                            module.name.value
                        ),
                        item: None,
                    });
                }
                p.modules.push(module);
            }
        }
        if let Some(aois) = child(controller, "AddOnInstructionDefinitions") {
            for a in children(aois, "AddOnInstructionDefinition") {
                p.aois.push(self.aoi(a)?);
            }
        }
        if let Some(tags) = child(controller, "Tags") {
            for t in children(tags, "Tag") {
                self.controller_tag(t, &mut p)?;
            }
        }
        if let Some(programs) = child(controller, "Programs") {
            for prog in children(programs, "Program") {
                let program = self.program(prog, &mut p.not_simulated)?;
                p.programs.push(program);
            }
        }
        if let Some(tasks) = child(controller, "Tasks") {
            for t in children(tasks, "Task") {
                p.tasks.push(self.task(t)?);
            }
        }
        Ok(p)
    }

    fn data_type(&self, node: Node<'_, '_>, p: &mut Project) -> Result<(), L5xError> {
        let name = self.required(node, "Name")?;
        let class = self.attr(node, "Class").map(|c| c.value);
        if class.as_deref().is_some_and(|c| c != "User") {
            return Ok(());
        }
        let family = self.attr(node, "Family").map(|f| f.value);
        let mut members = Vec::new();
        if let Some(ms) = child(node, "Members") {
            for m in children(ms, "Member") {
                let dimension = match self.attr(m, "Dimension") {
                    None => At {
                        value: 0,
                        span: start_tag(self.text, m),
                    },
                    Some(d) => At {
                        value: d.value.trim().parse::<u64>().map_err(|_| {
                            self.err(
                                d.span.clone(),
                                format!("Dimension=\"{}\": expected a whole number", d.value),
                            )
                        })?,
                        span: d.span,
                    },
                };
                members.push(Member {
                    name: self.required(m, "Name")?,
                    data_type: self.required(m, "DataType")?,
                    dimension,
                    hidden: self.flag(m, "Hidden")?,
                    description: self.description(m),
                });
            }
        }
        let string_length = if family.as_deref() == Some("StringFamily") {
            let data = members.iter().find(|m| m.name.value.eq_ignore_ascii_case("DATA"));
            Some(data.map_or(82, |m| m.dimension.value))
        } else {
            None
        };
        p.data_types.push(DataType {
            name,
            string_length,
            members,
            description: self.description(node),
        });
        Ok(())
    }

    fn controller_tag(&self, node: Node<'_, '_>, p: &mut Project) -> Result<(), L5xError> {
        let data_type = self.attr(node, "DataType");
        match data_type.as_ref().map(|d| d.value.as_str()) {
            Some(t) if t.starts_with("AXIS_") => {
                let name = self.required(node, "Name")?;
                let params = self.data_element(node, "Axis", "AxisParameters", &name)?;
                p.axes.push(AxisTag {
                    name,
                    data_type: data_type.expect("matched"),
                    params,
                });
            }
            Some("COORDINATE_SYSTEM") => {
                let name = self.required(node, "Name")?;
                let params = self.data_element(node, "CoordinateSystem", "CoordinateSystemParameters", &name)?;
                p.coordinate_systems.push(CoordinateSystemTag { name, params });
            }
            Some("MOTION_GROUP") => {
                let name = self.required(node, "Name")?;
                if let Some((first, _)) = &p.motion_group {
                    return Err(self.err(
                        name.span,
                        format!(
                            "a second motion group, {}; a controller has one ({})",
                            name.value, first.value
                        ),
                    ));
                }
                let params = self.data_element(node, "MotionGroup", "MotionGroupParameters", &name)?;
                p.motion_group = Some((name, params));
            }
            _ => p.tags.push(self.tag(node)?),
        }
        Ok(())
    }

    fn data_element(
        &self,
        node: Node<'_, '_>,
        format: &str,
        element: &'static str,
        name: &At<String>,
    ) -> Result<Params, L5xError> {
        let params = children(node, "Data")
            .filter(|d| d.attribute("Format") == Some(format))
            .find_map(|d| child(d, element));
        params.map(|e| self.params(e)).ok_or_else(|| {
            self.err(
                start_tag(self.text, node),
                format!("{} has no <Data Format=\"{format}\"><{element}>", name.value),
            )
        })
    }

    fn tag(&self, node: Node<'_, '_>) -> Result<Tag, L5xError> {
        let name = self.required(node, "Name")?;
        let tag_type = self
            .attr(node, "TagType")
            .map_or_else(|| "Base".to_owned(), |t| t.value);
        let alias_for = if tag_type == "Alias" {
            Some(self.required(node, "AliasFor")?)
        } else {
            None
        };
        let data_type = if alias_for.is_some() {
            self.attr(node, "DataType")
        } else {
            Some(self.required(node, "DataType")?)
        };
        let value = match &data_type {
            Some(d) if alias_for.is_none() => value::read(self.text, node, &d.value)?,
            _ => None,
        };
        Ok(Tag {
            name,
            data_type,
            dimensions: self.attr(node, "Dimensions"),
            alias_for,
            constant: self.flag(node, "Constant")?,
            external_access: self.attr(node, "ExternalAccess"),
            usage: self.attr(node, "Usage"),
            description: self.description(node),
            value,
            span: start_tag(self.text, node),
        })
    }

    fn program(&self, node: Node<'_, '_>, notes: &mut Vec<Note>) -> Result<Program, L5xError> {
        let name = self.required(node, "Name")?;
        let mut program = Program {
            main: self.attr(node, "MainRoutineName").filter(|a| !a.value.is_empty()),
            fault: self.attr(node, "FaultRoutineName").filter(|a| !a.value.is_empty()),
            disabled: self.flag(node, "Disabled")?,
            use_as_folder: self.flag(node, "UseAsFolder")?,
            tags: Vec::new(),
            routines: Vec::new(),
            connections: Vec::new(),
            name,
        };
        if let Some(tags) = child(node, "Tags") {
            for t in children(tags, "Tag") {
                let tag = self.tag(t)?;
                if let Some(cs) = child(t, "ParameterConnections") {
                    for c in children(cs, "ParameterConnection") {
                        program
                            .connections
                            .push((self.required(c, "EndPoint1")?, self.required(c, "EndPoint2")?));
                    }
                }
                program.tags.push(tag);
            }
        }
        if let Some(routines) = child(node, "Routines") {
            for r in children(routines, "Routine") {
                let routine = self.routine(r, &program.name.value)?;
                if !runs(&routine.kind.value) {
                    notes.push(Note {
                        span: routine.kind.span.clone(),
                        text: format!(
                            "routine {}/{}: {} routines are not simulated",
                            program.name.value, routine.name.value, routine.kind.value
                        ),
                        item: Some(format!("{}/{}", program.name.value, routine.name.value)),
                    });
                }
                program.routines.push(routine);
            }
        }
        Ok(program)
    }

    fn aoi(&self, node: Node<'_, '_>) -> Result<AoiDefinition, L5xError> {
        let name = self.required(node, "Name")?;
        if let Some(e) = node.descendants().find(|n| n.has_tag_name("EncodedData")) {
            return Err(self.err(
                start_tag(self.text, e),
                format!(
                    "Add-On Instruction {} is source-protected (EncodedData): export it without protection",
                    name.value
                ),
            ));
        }
        let mut parameters = Vec::new();
        if let Some(ps) = child(node, "Parameters") {
            for p in children(ps, "Parameter") {
                let data_type = self.required(p, "DataType")?;
                parameters.push(AoiParameter {
                    name: self.required(p, "Name")?,
                    default: value::read_in(self.text, p, &data_type.value, "DefaultData")?,
                    data_type,
                    dimensions: self.attr(p, "Dimensions"),
                    usage: self.required(p, "Usage")?,
                    required: self.flag(p, "Required")?,
                    visible: self.flag(p, "Visible")?,
                    constant: self.flag(p, "Constant")?,
                    description: self.description(p),
                });
            }
        }
        let mut local_tags = Vec::new();
        if let Some(ls) = child(node, "LocalTags") {
            for l in children(ls, "LocalTag") {
                let data_type = self.required(l, "DataType")?;
                local_tags.push(AoiLocal {
                    name: self.required(l, "Name")?,
                    default: value::read_in(self.text, l, &data_type.value, "DefaultData")?,
                    data_type,
                    dimensions: self.attr(l, "Dimensions"),
                });
            }
        }
        let mut routines = Vec::new();
        if let Some(rs) = child(node, "Routines") {
            for r in children(rs, "Routine") {
                routines.push(self.routine(r, &name.value)?);
            }
        }
        Ok(AoiDefinition {
            revision: self.attr(node, "Revision").map(|r| r.value),
            description: self.description(node),
            execute_prescan: self.flag(node, "ExecutePrescan")?,
            execute_postscan: self.flag(node, "ExecutePostscan")?,
            execute_enable_in_false: self.flag(node, "ExecuteEnableInFalse")?,
            parameters,
            local_tags,
            routines,
            span: node.range(),
            name,
        })
    }

    fn routine(&self, node: Node<'_, '_>, program: &str) -> Result<Routine, L5xError> {
        let name = self.required(node, "Name")?;
        let kind = self.required(node, "Type")?;
        let mut routine = Routine { name, kind, text: None };
        if !runs(&routine.kind.value) {
            return Ok(routine);
        }
        if let Some(e) = node.descendants().find(|n| n.has_tag_name("EncodedData")) {
            return Err(self.err(
                start_tag(self.text, e),
                format!(
                    "routine {program}/{} is source-protected (EncodedData): export it without protection",
                    routine.name.value
                ),
            ));
        }
        if routine.kind.value == "RLL" {
            routine.text = Some(self.rungs(node, program, &routine.name.value)?);
            return Ok(routine);
        }
        let Some(content) = child(node, "STContent") else {
            return Err(self.err(
                start_tag(self.text, node),
                format!("ST routine {program}/{} has no <STContent>", routine.name.value),
            ));
        };
        let (mut text, mut map) = (String::new(), Vec::new());
        let mut lines = 0u64;
        for line in children(content, "Line") {
            let number = self.required(line, "Number")?;
            let n: u64 = number.value.trim().parse().map_err(|_| {
                self.err(
                    number.span.clone(),
                    format!("Line Number=\"{}\": expected a whole number", number.value),
                )
            })?;
            if n < lines || n > lines + MAX_LINE_GAP {
                let problem = if n < lines {
                    "repeats or goes back"
                } else {
                    "leaves too many lines out"
                };
                return Err(self.err(
                    number.span,
                    format!("Line Number=\"{n}\" {problem} (line {lines} expected)"),
                ));
            }
            // Lines Studio left out (none in a normal export) are empty.
            while lines <= n {
                if lines > 0 {
                    map.push(number.span.start as u32);
                    text.push('\n');
                }
                lines += 1;
            }
            self.line_text(line, &mut text, &mut map);
        }
        map.push(node.range().end as u32);
        routine.text = Some((text.into(), map.into()));
        Ok(routine)
    }

    /// An RLL routine's rungs, one a line: each `Rung`'s `Text` (its CDATA,
    /// line breaks inside made spaces), mapped byte for byte into the
    /// file. A rung with an online edit pending (`Type` other than `N`) is
    /// refused: the export holds both the old and the new rung.
    fn rungs(
        &self,
        node: Node<'_, '_>,
        program: &str,
        routine: &str,
    ) -> Result<(std::sync::Arc<str>, std::sync::Arc<[u32]>), L5xError> {
        let (mut text, mut map) = (String::new(), Vec::new());
        let Some(content) = child(node, "RLLContent") else {
            map.push(node.range().end as u32);
            return Ok((text.into(), map.into()));
        };
        for (k, rung) in children(content, "Rung").enumerate() {
            let number = self.attr(rung, "Number").map_or_else(|| k.to_string(), |n| n.value);
            if let Some(t) = self.attr(rung, "Type")
                && t.value != "N"
            {
                return Err(self.err(
                    t.span,
                    format!(
                        "{program}/{routine} rung {number} has an online edit pending (Type=\"{}\"): accept or cancel the edits in Studio 5000 (Logic > On-line Edits), then export again",
                        t.value
                    ),
                ));
            }
            if k > 0 {
                map.push(rung.range().start as u32);
                text.push('\n');
            }
            match child(rung, "Text") {
                Some(t) => {
                    let start = text.len();
                    self.line_text(t, &mut text, &mut map);
                    // One rung a line: a line break inside the text is a space.
                    let rest: String = text[start..].replace(['\r', '\n'], " ");
                    text.truncate(start);
                    text.push_str(&rest);
                }
                None => {
                    // A rung without text is an empty rung.
                    map.push(rung.range().start as u32);
                    text.push(';');
                }
            }
        }
        map.push(node.range().end as u32);
        Ok((text.into(), map.into()))
    }

    /// Appends a `Line`'s text (its CDATA sections, else its text) and the
    /// file byte of each of its bytes.
    fn line_text(&self, line: Node<'_, '_>, text: &mut String, map: &mut Vec<u32>) {
        let raw = &self.text[line.range()];
        let base = line.range().start;
        let mut found = false;
        let mut at = 0;
        while let Some(open) = raw[at..].find("<![CDATA[") {
            let start = at + open + "<![CDATA[".len();
            let Some(len) = raw[start..].find("]]>") else { break };
            text.push_str(&raw[start..start + len]);
            map.extend((base + start..base + start + len).map(|b| b as u32));
            at = start + len + 3;
            found = true;
        }
        if !found {
            let content: String = line.children().filter_map(|n| n.text()).collect();
            let start = start_tag(self.text, line).end as u32;
            map.extend(std::iter::repeat_n(start, content.len()));
            text.push_str(&content);
        }
    }

    fn task(&self, node: Node<'_, '_>) -> Result<Task, L5xError> {
        let event = child(node, "EventInfo");
        let mut programs = Vec::new();
        if let Some(s) = child(node, "ScheduledPrograms") {
            for p in children(s, "ScheduledProgram") {
                programs.push(self.required(p, "Name")?);
            }
        }
        Ok(Task {
            name: self.required(node, "Name")?,
            kind: self.required(node, "Type")?,
            rate: self.attr(node, "Rate"),
            priority: self.attr(node, "Priority"),
            watchdog: self.attr(node, "Watchdog"),
            inhibit: self.flag(node, "InhibitTask")?,
            event_trigger: event.and_then(|e| self.attr(e, "EventTrigger")),
            event_tag: event.and_then(|e| self.attr(e, "EventTag")),
            enable_timeout: match event {
                Some(e) => self.flag(e, "EnableTimeout")?,
                None => false,
            },
            programs,
        })
    }
}

/// Whether the twin runs a routine of this `Type`: Structured Text and
/// ladder.
#[must_use]
pub fn runs(kind: &str) -> bool {
    matches!(kind, "ST" | "RLL")
}

#[cfg(test)]
mod tests;
