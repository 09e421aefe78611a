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

/// The byte of the first start tag nested deeper than `max` elements, if
/// any: a scan of the tags alone (comments, CDATA, processing
/// instructions and declarations skipped, quoted attribute values
/// respected), run before the XML parser, which recurses once per level
/// and would exhaust a thread's stack on a file of thousands of unclosed
/// elements. Malformed markup is left for the parser to report.
pub(super) fn too_deep(text: &str, max: usize) -> Option<usize> {
    let b = text.as_bytes();
    let mut depth = 0usize;
    let mut i = 0;
    while let Some(k) = memchr(b'<', &b[i..]) {
        let at = i + k;
        let rest = &text[at..];
        let skip_to = |close: &str| rest.find(close).map(|e| at + e + close.len());
        let next = if rest.starts_with("<!--") {
            skip_to("-->")
        } else if rest.starts_with("<![CDATA[") {
            skip_to("]]>")
        } else if rest.starts_with("<?") {
            skip_to("?>")
        } else if rest.starts_with("<!") {
            skip_to(">")
        } else if rest.starts_with("</") {
            depth = depth.saturating_sub(1);
            skip_to(">")
        } else {
            // A start tag: its end is the first '>' outside quotes.
            let mut quote = None;
            let mut end = None;
            for (j, &c) in b[at + 1..].iter().enumerate() {
                match (quote, c) {
                    (Some(q), c) if c == q => quote = None,
                    (Some(_), _) => {}
                    (None, b'"' | b'\'') => quote = Some(c),
                    (None, b'>') => {
                        end = Some(at + 1 + j);
                        break;
                    }
                    _ => {}
                }
            }
            end.map(|e| {
                if b[e - 1] != b'/' {
                    depth += 1;
                    if depth > max {
                        return usize::MAX;
                    }
                }
                e + 1
            })
        };
        match next {
            Some(usize::MAX) => return Some(at),
            Some(n) => i = n,
            None => return None,
        }
    }
    None
}

fn memchr(needle: u8, hay: &[u8]) -> Option<usize> {
    hay.iter().position(|&c| c == needle)
}
