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
/// header's brackets (`[x]`, `[[x]]` at a line's start) do not nest. A
/// dotted key nests its value once per dot (`a.b.c = { … }` opens three
/// levels), as the parsed document does.
pub fn too_deep(text: &str) -> Option<usize> {
    let bytes = text.as_bytes();
    // Per open bracket: the levels it opened (1 + its key's dots).
    let mut open: Vec<(u8, usize)> = Vec::new();
    let mut depth = 0usize;
    // Dots of the key being read, and of the key whose value comes next.
    let (mut key_dots, mut value_dots) = (0usize, 0usize);
    let mut in_key = true;
    let mut i = 0;
    let mut line_start = true;
    while i < bytes.len() {
        let c = bytes[i];
        let in_table = open.last().is_none_or(|(b, _)| *b == b'{');
        match c {
            b'\n' => {
                line_start = true;
                if open.is_empty() {
                    in_key = true;
                    key_dots = 0;
                    value_dots = 0;
                }
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
            b'[' if line_start && open.is_empty() => {
                // A table header: up to its closing bracket on this line;
                // its dots nest the table's keys as a dotted key's do.
                let mut dots = 0;
                while i < bytes.len() && bytes[i] != b'\n' && bytes[i] != b']' {
                    if bytes[i] == b'.' {
                        dots += 1;
                        if dots > MAX_TOML_NESTING {
                            return Some(i);
                        }
                    }
                    i += 1;
                }
            }
            b'.' if in_key && in_table => {
                key_dots += 1;
                if depth + key_dots > MAX_TOML_NESTING {
                    return Some(i);
                }
            }
            b'=' if in_key && in_table => {
                in_key = false;
                value_dots = key_dots;
                key_dots = 0;
            }
            b'[' | b'{' => {
                let levels = 1 + std::mem::take(&mut value_dots);
                depth += levels;
                if depth > MAX_TOML_NESTING {
                    return Some(i);
                }
                open.push((c, levels));
                in_key = c == b'{';
                key_dots = 0;
            }
            b']' | b'}' => {
                if let Some((_, levels)) = open.pop() {
                    depth -= levels;
                }
                value_dots = 0;
            }
            b',' => {
                in_key = in_table;
                key_dots = 0;
                value_dots = 0;
            }
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
        // Floats and dotted keys in arrays' tables do not add up.
        let floats = format!("a = [{}]\n", "1.5, ".repeat(1000));
        assert_eq!(too_deep(&floats), None);
    }

    #[test]
    fn a_key_or_header_of_more_dots_than_the_bound_is_found_at_its_dot() {
        let key = format!("x{} = 1\n", ".a".repeat(65));
        assert_eq!(too_deep(&key), Some(1 + 2 * 64));
        assert_eq!(too_deep(&format!("x{} = 1\n", ".a".repeat(64))), None);
        let header = format!("[x{}]\ny = 1\n", ".a".repeat(65));
        assert_eq!(too_deep(&header), Some(2 + 2 * 64));
    }

    #[test]
    fn a_dotted_key_nests_its_value_once_per_dot() {
        // 24 tables under keys of 60 dots: 1,464 levels (it overflowed the
        // stack deserializing a tag's value).
        let key = "a.".repeat(60);
        let text = format!("value = {}1{}\n", format!("{{{key}b = ").repeat(24), "}".repeat(24));
        assert!(too_deep(&text).is_some());
        // 1 + 2 dots + 1 + 2 dots: 6 levels.
        assert_eq!(too_deep("v = { a.b.c = { d.e.f = 1 } }\n"), None);
        // `v`'s table opens 1 level, each under `a.b.c` 3 more, and the
        // innermost `a.b.c = 1` 2 more: 3 n levels for n tables.
        let just = format!("v = {}1{}\n", "{a.b.c = ".repeat(21), "}".repeat(21));
        assert_eq!(too_deep(&just), None, "63 levels");
        let past = format!("v = {}1{}\n", "{a.b.c = ".repeat(22), "}".repeat(22));
        assert!(too_deep(&past).is_some(), "66 levels");
    }
}
