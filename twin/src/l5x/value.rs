//! A tag's value as Studio writes it: `Decorated`, `String` or `L5K` data.

use super::xml::{At, L5xError, MAX_XML_DEPTH, Node, children, start_tag};

/// The most elements one array value may hold.
pub const MAX_ARRAY_VALUES: usize = 1_000_000;

/// A value read from the file.
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    /// A BOOL (or a bit).
    Bool(bool),
    /// An integer of any width.
    Int(i64),
    /// A REAL or LREAL.
    Float(f64),
    /// A string's text (escapes decoded).
    Str(String),
    /// Array elements in row-major order.
    Array(Vec<Value>),
    /// Structure members by name, in file order.
    Struct(Vec<(String, Value)>),
}

/// The value of tag `node` of type `data_type`: `None` when it has no
/// data the twin reads.
pub(super) fn read(text: &str, node: Node<'_, '_>, data_type: &str) -> Result<Option<At<Value>>, L5xError> {
    read_in(text, node, data_type, "Data")
}

/// As [`read`], from the children named `element` (`DefaultData` of an
/// Add-On Instruction's parameter or local tag).
pub(super) fn read_in(
    text: &str,
    node: Node<'_, '_>,
    data_type: &str,
    element: &'static str,
) -> Result<Option<At<Value>>, L5xError> {
    let data = |format: &str| children(node, element).find(|d| d.attribute("Format") == Some(format));
    if let Some(d) = data("Decorated") {
        let Some(first) = d.children().find(Node::is_element) else {
            return Ok(None);
        };
        return Ok(Some(At {
            value: decorated(text, first)?,
            span: start_tag(text, first),
        }));
    }
    if let Some(d) = data("String") {
        let raw = cdata(text, d).unwrap_or_default();
        let span = start_tag(text, d);
        return Ok(Some(At {
            value: Value::Str(string_literal(raw).map_err(|m| L5xError {
                span: span.clone(),
                message: m,
            })?),
            span,
        }));
    }
    if let Some(d) = data("L5K") {
        let raw = cdata(text, d).unwrap_or_default();
        let span = start_tag(text, d);
        let _ = data_type;
        return l5k(raw)
            .map(|v| {
                Some(At {
                    value: v,
                    span: span.clone(),
                })
            })
            .map_err(|m| L5xError {
                span,
                message: format!("L5K data: {m}"),
            });
    }
    Ok(None)
}

fn cdata<'t>(text: &'t str, node: Node<'_, '_>) -> Option<&'t str> {
    let raw = &text[node.range()];
    let open = raw.find("<![CDATA[")? + "<![CDATA[".len();
    let len = raw[open..].find("]]>")?;
    Some(&raw[open..open + len])
}

fn bad(node: Node<'_, '_>, text: &str, message: String) -> L5xError {
    L5xError {
        span: start_tag(text, node),
        message,
    }
}

fn decorated(text: &str, node: Node<'_, '_>) -> Result<Value, L5xError> {
    let name = node.tag_name().name();
    match name {
        "DataValue" | "DataValueMember" => {
            let ty = node.attribute("DataType").unwrap_or("");
            if ty.eq_ignore_ascii_case("STRING")
                || node.attribute("Radix") == Some("ASCII") && cdata(text, node).is_some()
            {
                let raw = cdata(text, node).unwrap_or_default();
                return string_literal(raw).map(Value::Str).map_err(|m| bad(node, text, m));
            }
            let Some(v) = node.attribute_node("Value") else {
                return Err(bad(node, text, format!("<{name}> has no Value attribute")));
            };
            scalar(v.value(), ty).map_err(|m| L5xError {
                span: v.range_value(),
                message: m,
            })
        }
        "Array" | "ArrayMember" => {
            let mut out = Vec::new();
            for e in children(node, "Element") {
                if out.len() >= MAX_ARRAY_VALUES {
                    return Err(bad(e, text, format!("more than {MAX_ARRAY_VALUES} elements")));
                }
                let ty = node.attribute("DataType").unwrap_or("");
                out.push(match e.attribute_node("Value") {
                    Some(v) => scalar(v.value(), ty).map_err(|m| L5xError {
                        span: v.range_value(),
                        message: m,
                    })?,
                    None => match e.children().find(Node::is_element) {
                        Some(s) => decorated(text, s)?,
                        None => return Err(bad(e, text, "<Element> has neither a Value nor a structure".to_owned())),
                    },
                });
            }
            Ok(Value::Array(out))
        }
        "Structure" | "StructureMember" => {
            let ty = node.attribute("DataType").unwrap_or("");
            let members: Vec<(String, Value)> = node
                .children()
                .filter(Node::is_element)
                .map(|m| {
                    let member = m.attribute("Name").unwrap_or("").to_owned();
                    decorated(text, m).map(|v| (member, v))
                })
                .collect::<Result<_, _>>()?;
            // A string structure (`LEN`, `DATA`): its text.
            let is_string = members.iter().any(|(n, _)| n.eq_ignore_ascii_case("DATA"))
                && members
                    .iter()
                    .all(|(n, _)| n.eq_ignore_ascii_case("DATA") || n.eq_ignore_ascii_case("LEN"));
            if (is_string || ty.eq_ignore_ascii_case("STRING"))
                && let Some((_, Value::Str(s))) = members.iter().find(|(n, _)| n.eq_ignore_ascii_case("DATA"))
            {
                return Ok(Value::Str(s.clone()));
            }
            Ok(Value::Struct(members))
        }
        other => Err(bad(node, text, format!("<{other}> is not Decorated data"))),
    }
}

/// A number as Studio writes it for `data_type`.
fn scalar(raw: &str, data_type: &str) -> Result<Value, String> {
    let t = raw.trim();
    if data_type.eq_ignore_ascii_case("BOOL") || data_type.eq_ignore_ascii_case("BIT") {
        return match t {
            "0" | "false" => Ok(Value::Bool(false)),
            "1" | "true" => Ok(Value::Bool(true)),
            _ => Err(format!("Value=\"{raw}\": a BOOL is 0 or 1")),
        };
    }
    if data_type.eq_ignore_ascii_case("REAL") || data_type.eq_ignore_ascii_case("LREAL") {
        return float(t)
            .map(Value::Float)
            .ok_or_else(|| format!("Value=\"{raw}\": not a number"));
    }
    number(t).ok_or_else(|| format!("Value=\"{raw}\": not a number"))
}

fn float(t: &str) -> Option<f64> {
    match t {
        "1.#QNAN" | "-1.#QNAN" | "1.#IND" | "-1.#IND" => Some(f64::NAN),
        "1.#INF" | "1.$" => Some(f64::INFINITY),
        "-1.#INF" | "-1.$" => Some(f64::NEG_INFINITY),
        _ => t
            .parse::<f64>()
            .ok()
            .filter(|_| !t.eq_ignore_ascii_case("nan") && !t.contains("inf")),
    }
}

/// An integer (decimal, `16#`, `8#`, `2#`, `_` separators, `'c'` ASCII)
/// or a float.
fn number(t: &str) -> Option<Value> {
    let (neg, body) = t.strip_prefix('-').map_or((false, t), |b| (true, b));
    let radix = [("16#", 16), ("8#", 8), ("2#", 2)]
        .iter()
        .find_map(|(p, r)| body.strip_prefix(p).map(|d| (*r, d)));
    if let Some((r, digits)) = radix {
        let digits: String = digits.chars().filter(|c| *c != '_').collect();
        let v = u64::from_str_radix(&digits, r).ok()? as i64;
        return Some(Value::Int(if neg { v.wrapping_neg() } else { v }));
    }
    if let Some(inner) = body.strip_prefix('\'').and_then(|b| b.strip_suffix('\'')) {
        let s = string_literal(&format!("'{inner}'")).ok()?;
        let mut v: i64 = 0;
        for b in s.bytes() {
            v = v.checked_mul(256)?.checked_add(i64::from(b))?;
        }
        return Some(Value::Int(v));
    }
    let plain: String = t.chars().filter(|c| *c != '_').collect();
    if let Ok(i) = plain.parse::<i64>() {
        return Some(Value::Int(i));
    }
    float(&plain).map(Value::Float)
}

/// A Logix string literal `'text'` with `$` escapes (`$$`, `$'`, `$L`,
/// `$N`, `$P`, `$R`, `$T`, `$hh`).
fn string_literal(raw: &str) -> Result<String, String> {
    let t = raw.trim();
    let Some(inner) = t
        .strip_prefix('\'')
        .and_then(|s| s.strip_suffix('\''))
        .filter(|_| t.len() >= 2)
    else {
        if t.is_empty() {
            return Ok(String::new());
        }
        return Err(format!("string data {t:?}: expected text in single quotes"));
    };
    let mut out = String::new();
    let mut chars = inner.chars();
    while let Some(c) = chars.next() {
        if c != '$' {
            out.push(c);
            continue;
        }
        match chars.next() {
            Some('$') => out.push('$'),
            Some('\'') => out.push('\''),
            Some('L' | 'l' | 'N' | 'n') => out.push('\n'),
            Some('P' | 'p') => out.push('\u{c}'),
            Some('R' | 'r') => out.push('\r'),
            Some('T' | 't') => out.push('\t'),
            Some(h) if h.is_ascii_hexdigit() => {
                let l = chars
                    .next()
                    .filter(char::is_ascii_hexdigit)
                    .ok_or("a $ escape needs two hex digits")?;
                let code = u8::from_str_radix(&format!("{h}{l}"), 16).map_err(|e| e.to_string())?;
                out.push(char::from(code));
            }
            _ => return Err(format!("string data {t:?}: unknown $ escape")),
        }
    }
    // Studio pads a string's DATA with $00 up to its length.
    Ok(out.trim_end_matches('\0').to_owned())
}

/// L5K data: a number, a quoted string, or `[ … ]` of them.
fn l5k(raw: &str) -> Result<Value, String> {
    let mut p = L5k {
        s: raw.as_bytes(),
        at: 0,
        raw,
    };
    let v = p.value(0)?;
    p.ws();
    if p.at < p.s.len() {
        let rest: String = raw[p.at..].chars().take(20).collect();
        return Err(format!("unexpected {rest:?} after the value"));
    }
    Ok(v)
}

struct L5k<'a> {
    s: &'a [u8],
    at: usize,
    raw: &'a str,
}

impl L5k<'_> {
    fn ws(&mut self) {
        while self.at < self.s.len() && self.s[self.at].is_ascii_whitespace() {
            self.at += 1;
        }
    }

    fn value(&mut self, depth: usize) -> Result<Value, String> {
        if depth > MAX_XML_DEPTH {
            return Err("brackets nested too deep".to_owned());
        }
        self.ws();
        match self.s.get(self.at) {
            Some(b'[') => {
                self.at += 1;
                let mut out = Vec::new();
                loop {
                    self.ws();
                    if self.s.get(self.at) == Some(&b']') {
                        self.at += 1;
                        return Ok(Value::Array(out));
                    }
                    if out.len() >= MAX_ARRAY_VALUES {
                        return Err(format!("more than {MAX_ARRAY_VALUES} elements"));
                    }
                    out.push(self.value(depth + 1)?);
                    self.ws();
                    match self.s.get(self.at) {
                        Some(b',') => self.at += 1,
                        Some(b']') => {}
                        _ => return Err("expected ',' or ']'".to_owned()),
                    }
                }
            }
            Some(b'\'') => {
                let start = self.at;
                self.at += 1;
                while self.at < self.s.len() && self.s[self.at] != b'\'' {
                    self.at += if self.s[self.at] == b'$' { 2 } else { 1 };
                }
                self.at = (self.at + 1).min(self.s.len());
                let lit = self.raw.get(start..self.at).ok_or("a string cut inside a character")?;
                string_literal(lit).map(Value::Str)
            }
            Some(_) => {
                let start = self.at;
                while self.at < self.s.len()
                    && !matches!(self.s[self.at], b',' | b']')
                    && !self.s[self.at].is_ascii_whitespace()
                {
                    self.at += 1;
                }
                let t = self.raw.get(start..self.at).ok_or("a number cut inside a character")?;
                number(t).ok_or_else(|| format!("{t:?} is not a number"))
            }
            None => Err("no value".to_owned()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::{Value, l5k, number, string_literal};

    #[test]
    fn numbers_take_every_radix_studio_writes() {
        assert_eq!(number("16#00FF"), Some(Value::Int(255)));
        assert_eq!(number("2#0000_0101"), Some(Value::Int(5)));
        assert_eq!(number("8#17"), Some(Value::Int(15)));
        assert_eq!(number("-42"), Some(Value::Int(-42)));
        assert_eq!(number("1.50000000e+000"), Some(Value::Float(1.5)));
        assert_eq!(number("'A'"), Some(Value::Int(65)));
        assert_eq!(number("abc"), None);
    }

    #[test]
    fn strings_decode_dollar_escapes_and_drop_padding() {
        assert_eq!(string_literal("'a$'b$$c$0D$00$00'").unwrap(), "a'b$c\r");
        assert!(string_literal("'a$G'").is_err());
        assert!(string_literal("abc").is_err());
    }

    #[test]
    fn l5k_reads_nested_arrays_and_strings() {
        let v = l5k("[[1,2],[3,4.5],'x$'y']").unwrap();
        assert_eq!(
            v,
            Value::Array(vec![
                Value::Array(vec![Value::Int(1), Value::Int(2)]),
                Value::Array(vec![Value::Int(3), Value::Float(4.5)]),
                Value::Str("x'y".to_owned()),
            ])
        );
        assert!(l5k("[1,2").is_err());
        assert!(l5k("[1 2]").is_err());
    }
}
