//! What the reader and the value reader share: positions, errors and
//! element helpers.

use std::ops::Range;

/// The deepest element nesting accepted (Studio writes about 12).
pub const MAX_XML_DEPTH: usize = 64;

pub(super) type Node<'a, 'i> = roxmltree::Node<'a, 'i>;

/// A value and the bytes of the file it was read from.
#[derive(Debug, Clone, PartialEq)]
pub struct At<T> {
    /// The value.
    pub value: T,
    /// Its bytes in the L5X (an attribute's value, an element's start tag).
    pub span: Range<usize>,
}

/// A problem with the file, at its bytes.
#[derive(Debug, Clone, PartialEq)]
pub struct L5xError {
    /// Where.
    pub span: Range<usize>,
    /// What is wrong, one line.
    pub message: String,
}

pub(super) fn children<'a, 'i>(node: Node<'a, 'i>, name: &'static str) -> impl Iterator<Item = Node<'a, 'i>> {
    node.children().filter(move |c| c.has_tag_name(name))
}

pub(super) fn child<'a, 'i>(node: Node<'a, 'i>, name: &'static str) -> Option<Node<'a, 'i>> {
    children(node, name).next()
}

/// The start tag's bytes of an element.
pub(super) fn start_tag(text: &str, node: Node<'_, '_>) -> Range<usize> {
    let r = node.range();
    let end = text[r.clone()].find('>').map_or(r.end, |i| r.start + i + 1);
    r.start..end
}
