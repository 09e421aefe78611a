//! The nesting of a scene's arrays and inline tables, checked before the
//! TOML parser sees the text: the parser bounds the nesting of values it
//! accepts, but its recovery from some malformed nestings recurses per
//! level without a bound (20,000 unclosed `{ [` overflowed the main
//! thread's stack and aborted the process).

/// The deepest nesting of arrays and inline tables a scene may have
/// (real scenes nest three or four).
pub const MAX_TOML_NESTING: usize = 64;

/// The byte offset of the first `[` or `{` that opens a level past
/// [`MAX_TOML_NESTING`], scanning as TOML does: brackets inside strings
/// (basic, literal, multi-line) and comments do not count, and a table
/// header's brackets (`[x]`, `[[x]]` at a line's start) do not nest.
pub fn too_deep(text: &str) -> Option<usize> {
    let bytes = text.as_bytes();
    let mut depth = 0usize;
    let mut i = 0;
    let mut line_start = true;
    while i < bytes.len() {
        let c = bytes[i];
        match c {
            b'\n' => {
                line_start = true;
                i += 1;
                continue;
            }
            b' ' | b'\t' | b'\r' => {
                i += 1;
                continue;
            }
            b'#' => {
                while i < bytes.len() && bytes[i] != b'\n' {
                    i += 1;
                }
                continue;
            }
            b'"' | b'\'' => {
                i = string_end(bytes, i);
                line_start = false;
                continue;
            }
            b'[' if line_start && depth == 0 => {
                // A table header: up to its closing bracket on this line.
                while i < bytes.len() && bytes[i] != b'\n' && bytes[i] != b']' {
                    i += 1;
                }
            }
            b'[' | b'{' => {
                depth += 1;
                if depth > MAX_TOML_NESTING {
                    return Some(i);
                }
            }
            b']' | b'}' => depth = depth.saturating_sub(1),
            _ => {}
        }
        line_start = false;
        i += 1;
    }
    None
}

/// The offset after the string that starts at `start` (a quote), or the
/// text's end when it is not closed.
fn string_end(bytes: &[u8], start: usize) -> usize {
    let quote = bytes[start];
    let triple = bytes.get(start..start + 3) == Some(&[quote, quote, quote][..]);
    let mut i = start + if triple { 3 } else { 1 };
    while i < bytes.len() {
        let c = bytes[i];
        if c == b'\\' && quote == b'"' {
            i += 2;
            continue;
        }
        if !triple && c == b'\n' {
            return i;
        }
        if c == quote && (!triple || bytes.get(i..i + 3) == Some(&[quote, quote, quote][..])) {
            return i + if triple { 3 } else { 1 };
        }
        i += 1;
    }
    bytes.len()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unclosed_inline_tables_past_the_bound_are_found_where_they_pass_it() {
        let line = "coordinate_system = { [\"X\", \"Y\"]\n";
        let text = format!("name = \"x\"\n{}", line.repeat(100));
        let at = too_deep(&text).expect("found");
        // Line k of them leaves k levels open and its `[` opens level
        // k + 1: the 64th (file line 65) opens level 65.
        let before = &text[..at];
        assert_eq!(before.matches('\n').count() + 1, 65);
        assert_eq!(&text[at..=at], "[");
        assert_eq!(too_deep(&format!("name = \"x\"\n{}", line.repeat(63))), None);
    }

    #[test]
    fn brackets_in_strings_comments_and_headers_do_not_nest() {
        let text = format!(
            "[[axes]]\nname = \"{}\"\n# {}\nx = '''\n{}'''\n[tasks.programs]\ny = [[1, 2], {{ a = [3] }}]\n",
            "[".repeat(500),
            "{".repeat(500),
            "[".repeat(500)
        );
        assert_eq!(too_deep(&text), None);
        let deep = format!("a = {}1{}\n", "[".repeat(65), "]".repeat(65));
        assert_eq!(too_deep(&deep), Some(4 + 64));
    }
}
