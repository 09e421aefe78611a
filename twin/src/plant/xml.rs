//! Limits on the XML files the plant reads (URDF, COLLADA).
//!
//! urdf-rs and mesh-loader's COLLADA reader (and roxmltree) build or walk
//! the document recursively, one stack frame or more per nesting level, so
//! a file nested thousands of levels deep (a mutated or hostile URDF)
//! would overflow the stack and abort the process. Real robot
//! descriptions and CAD exports nest a few tens of levels;
//! [`MAX_XML_DEPTH`] refuses anything deeper first, with a byte scan that
//! keeps no stack.

/// The deepest element nesting a URDF or COLLADA file may have.
pub const MAX_XML_DEPTH: usize = 256;

/// The 1-based line of the first element nested deeper than
/// [`MAX_XML_DEPTH`], if any. Only the nesting is read (comments, CDATA,
/// processing instructions, declarations and quoted attribute values are
/// skipped); whether the text is well-formed is its parser's to say.
pub fn too_deep(text: &str) -> Option<usize> {
    let b = text.as_bytes();
    let (mut i, mut line, mut depth) = (0usize, 1usize, 0usize);
    // Skips to just past `end`, counting lines; false when it never comes.
    let skip_to = |i: &mut usize, line: &mut usize, end: &[u8]| -> bool {
        while *i < b.len() {
            if b[*i..].starts_with(end) {
                *i += end.len();
                return true;
            }
            if b[*i] == b'\n' {
                *line += 1;
            }
            *i += 1;
        }
        false
    };
    while i < b.len() {
        match b[i] {
            b'\n' => {
                line += 1;
                i += 1;
            }
            b'<' => {
                let rest = &b[i..];
                let start_line = line;
                let complete = if rest.starts_with(b"<!--") {
                    skip_to(&mut i, &mut line, b"-->")
                } else if rest.starts_with(b"<![CDATA[") {
                    skip_to(&mut i, &mut line, b"]]>")
                } else if rest.starts_with(b"<?") {
                    skip_to(&mut i, &mut line, b"?>")
                } else if rest.starts_with(b"<!") {
                    // A declaration; a DOCTYPE's internal subset ends with "]>".
                    let subset = rest.iter().take_while(|&&c| c != b'>').any(|&c| c == b'[');
                    skip_to(&mut i, &mut line, if subset { b"]>" } else { b">" })
                } else {
                    let closing = rest.starts_with(b"</");
                    // To the tag's '>', outside quoted attribute values.
                    let mut quote = None;
                    let mut self_closing = false;
                    i += 1;
                    while i < b.len() {
                        let c = b[i];
                        if c == b'\n' {
                            line += 1;
                        }
                        match quote {
                            Some(q) if c == q => quote = None,
                            Some(_) => {}
                            None if c == b'"' || c == b'\'' => quote = Some(c),
                            None if c == b'>' => {
                                self_closing = b[i - 1] == b'/';
                                break;
                            }
                            None => {}
                        }
                        i += 1;
                    }
                    i += 1;
                    if closing {
                        depth = depth.saturating_sub(1);
                    } else if !self_closing {
                        depth += 1;
                        if depth > MAX_XML_DEPTH {
                            return Some(start_line);
                        }
                    }
                    true
                };
                if !complete {
                    return None;
                }
            }
            _ => i += 1,
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    fn nested(levels: usize) -> String {
        format!(
            "<robot name=\"r\">\n{}{}</robot>",
            "<a>".repeat(levels),
            "</a>".repeat(levels)
        )
    }

    #[test]
    fn deep_nesting_is_found_without_recursion() {
        assert_eq!(too_deep(&nested(20_000)), Some(2));
        assert_eq!(too_deep(&nested(MAX_XML_DEPTH - 1)), None);
        assert_eq!(too_deep("<not xml"), None);
        // What is not an element does not nest.
        let quiet = format!(
            "<?xml version=\"1.0\"?>\n<!DOCTYPE r [<!ENTITY e \"<a>\">]>\n<r a=\"<b>\"><!-- {} --><![CDATA[{}]]><c/></r>",
            "<a>".repeat(1000),
            "<a>".repeat(1000)
        );
        assert_eq!(too_deep(&quiet), None);
        let deep_later = format!("<r>\n\n{}", "<a>".repeat(MAX_XML_DEPTH));
        assert_eq!(too_deep(&deep_later), Some(3));
    }
}
