//! How a run's recording names its entities.

use crate::program::TracedTag;
use crate::run::Twin;

/// A name as one entity-path part (a `/`, `.` or space stays inside it).
pub(super) fn entity_part(name: &str) -> String {
    rerun::EntityPathPart::new(name).escaped_string()
}

/// The program a `Program.Tag` reference names (`None`: a controller tag).
pub(super) fn program_of<'a>(twin: &'a Twin, reference: &str) -> Option<&'a str> {
    let (head, _) = reference.split_once('.')?;
    twin.scene()
        .tasks
        .iter()
        .flat_map(|t| &t.programs)
        .map(|p| p.name.as_str())
        .find(|p| *p == head)
}

/// The entity of a numeric traced tag's series: a traced rung's own
/// (`program/<program>/<routine>/<rung>`), else its program's
/// `tags/<program>`, or `tags` for a controller tag (and a seed
/// program's).
pub(super) fn tag_entity(twin: &Twin, tag: &TracedTag) -> String {
    if let Some(path) = &tag.entity {
        return path.clone();
    }
    match program_of(twin, &tag.name) {
        Some(program) => format!("tags/{}", entity_part(program)),
        None => "tags".to_owned(),
    }
}

/// The entity of a function block's or control structure's outputs and
/// state lane: `instructions/<instance>`.
pub(super) fn instruction_entity(name: &str) -> String {
    format!("instructions/{}", entity_part(name))
}
