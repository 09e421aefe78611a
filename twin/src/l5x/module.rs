//! I/O modules (`Modules/Module`): their connections and the shape of the
//! input and output tags the controller makes for them.
//!
//! A tag's name follows the module's place (1756-PM004, *I/O tags*):
//! `Local:<slot>:I` for a module in the controller's chassis,
//! `<Adapter>:<slot>:I` in a remote chassis (its parent's name and its
//! slot, the address of its upstream backplane port), `<Module>:I` for a
//! device on Ethernet (its upstream port an Ethernet one). The suffixes are
//! the connection's `InputTagSuffix`/`OutputTagSuffix`, `I`/`O` by default.
//! The tag's structure is the one its Decorated data shows (`Data`,
//! `Fault`, a 5069 module's `Pt00.Data` …).

use super::xml::{At, L5xError, MAX_XML_DEPTH, Node, child, children, start_tag};

/// The most members a module tag's structure may have, all levels.
const MAX_IO_MEMBERS: usize = 10_000;

/// A module of the export.
#[derive(Debug, Clone, PartialEq)]
pub struct Module {
    /// `Name`.
    pub name: At<String>,
    /// `CatalogNumber`.
    pub catalog: String,
    /// `ParentModule`.
    pub parent: String,
    /// The upstream port's `Type` and `Address`.
    pub port: Option<(String, String)>,
    /// `Inhibited="true"`.
    pub inhibited: bool,
    /// `Communications/Connections/Connection`.
    pub connections: Vec<Connection>,
}

/// One connection of a module.
#[derive(Debug, Clone, PartialEq)]
pub struct Connection {
    /// `RPI`, µs.
    pub rpi_us: Option<At<String>>,
    /// The input tag: its suffix and shape.
    pub input: Option<(String, IoType)>,
    /// The output tag: its suffix and shape.
    pub output: Option<(String, IoType)>,
}

/// The structure of a module tag, from its Decorated data.
#[derive(Debug, Clone, PartialEq)]
pub struct IoType {
    /// Its `DataType` (`AB:1756_DI:I:0`).
    pub data_type: At<String>,
    /// Its members in order.
    pub members: Vec<IoMember>,
}

/// A member of a module tag's structure.
#[derive(Debug, Clone, PartialEq)]
pub struct IoMember {
    /// `Name`.
    pub name: String,
    /// `DataType`.
    pub data_type: String,
    /// `Dimensions` of an array member (0: none).
    pub dimension: u64,
    /// A structure member's own structure.
    pub nested: Option<IoType>,
}

impl Module {
    /// The prefix of its tags' names (`Local:3`, `Rack1:2`, `Drive1`).
    #[must_use]
    pub fn tag_prefix(&self) -> String {
        match &self.port {
            Some((kind, address)) if !kind.eq_ignore_ascii_case("Ethernet") && !address.is_empty() => {
                format!("{}:{address}", self.parent)
            }
            _ => self.name.value.clone(),
        }
    }
}

pub(super) fn read(text: &str, node: Node<'_, '_>) -> Result<Module, L5xError> {
    let attr = |n: Node<'_, '_>, a: &str| n.attribute(a).unwrap_or("").to_owned();
    let Some(name) = node.attribute_node("Name") else {
        return Err(L5xError {
            span: start_tag(text, node),
            message: "<Module> has no Name attribute".to_owned(),
        });
    };
    let port = child(node, "Ports").and_then(|ports| {
        children(ports, "Port")
            .find(|p| p.attribute("Upstream") == Some("true"))
            .map(|p| (attr(p, "Type"), attr(p, "Address")))
    });
    let mut connections = Vec::new();
    if let Some(cs) = child(node, "Communications").and_then(|c| child(c, "Connections")) {
        for c in children(cs, "Connection") {
            let tag = |element: &'static str,
                       suffix_attr: &str,
                       default: &str|
             -> Result<Option<(String, IoType)>, L5xError> {
                let Some(t) = child(c, element) else { return Ok(None) };
                let suffix = c
                    .attribute(suffix_attr)
                    .filter(|s| !s.is_empty())
                    .unwrap_or(default)
                    .to_owned();
                let structure = children(t, "Data")
                    .find(|d| d.attribute("Format") == Some("Decorated"))
                    .and_then(|d| d.children().find(|n| n.has_tag_name("Structure")));
                match structure {
                    Some(s) => Ok(Some((suffix, io_type(text, s, 0, &mut 0)?))),
                    None => Ok(None),
                }
            };
            connections.push(Connection {
                rpi_us: c.attribute_node("RPI").map(|a| At {
                    value: a.value().to_owned(),
                    span: a.range_value(),
                }),
                input: tag("InputTag", "InputTagSuffix", "I")?,
                output: tag("OutputTag", "OutputTagSuffix", "O")?,
            });
        }
    }
    Ok(Module {
        name: At {
            value: name.value().to_owned(),
            span: name.range_value(),
        },
        catalog: attr(node, "CatalogNumber"),
        parent: attr(node, "ParentModule"),
        port,
        inhibited: node.attribute("Inhibited") == Some("true"),
        connections,
    })
}

fn io_type(text: &str, node: Node<'_, '_>, depth: usize, count: &mut usize) -> Result<IoType, L5xError> {
    let bad = |n: Node<'_, '_>, message: String| L5xError {
        span: start_tag(text, n),
        message,
    };
    if depth > MAX_XML_DEPTH {
        return Err(bad(node, "module tag structures nested too deep".to_owned()));
    }
    let Some(ty) = node.attribute_node("DataType") else {
        return Err(bad(
            node,
            format!("<{}> has no DataType attribute", node.tag_name().name()),
        ));
    };
    let mut members = Vec::new();
    for m in node.children().filter(Node::is_element) {
        *count += 1;
        if *count > MAX_IO_MEMBERS {
            return Err(bad(m, format!("a module tag of more than {MAX_IO_MEMBERS} members")));
        }
        let name = m.attribute("Name").unwrap_or("").to_owned();
        let data_type = m.attribute("DataType").unwrap_or("").to_owned();
        if name.is_empty() || data_type.is_empty() {
            return Err(bad(m, format!("<{}> needs a Name and a DataType", m.tag_name().name())));
        }
        let (dimension, nested) = match m.tag_name().name() {
            "DataValueMember" => (0, None),
            "ArrayMember" => {
                let dims = m.attribute("Dimensions").unwrap_or("");
                let n = dims
                    .trim()
                    .parse::<u64>()
                    .ok()
                    .filter(|n| (1..=1_000_000).contains(n))
                    .ok_or_else(|| {
                        bad(
                            m,
                            format!("Dimensions=\"{dims}\": a module tag's array has 1 to 1000000 elements"),
                        )
                    })?;
                (n, None)
            }
            "StructureMember" => (0, Some(io_type(text, m, depth + 1, count)?)),
            other => return Err(bad(m, format!("<{other}> is not a member of Decorated data"))),
        };
        members.push(IoMember {
            name,
            data_type,
            dimension,
            nested,
        });
    }
    Ok(IoType {
        data_type: At {
            value: ty.value().to_owned(),
            span: ty.range_value(),
        },
        members,
    })
}
