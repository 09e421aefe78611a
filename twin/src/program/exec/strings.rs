//! The string instructions and string comparisons (1756-RM003, "ASCII
//! String Instructions" and "ASCII Conversion Instructions").
//!
//! A string is `LEN` then `DATA`; instructions read the `LEN` characters
//! and write `LEN` and the characters they produce, leaving the rest of
//! `DATA` as it was. Faults, all major, as RM003 lists them:
//! * 4/51: a `LEN` below 0 or above its `DATA` length, or a result longer
//!   than the destination's `DATA` (CONCAT, INSERT, MID, DELETE, UPPER,
//!   LOWER);
//! * 4/52: DTOS or RTOS text longer than the destination;
//! * 4/53: STOD or STOR value beyond the destination type;
//! * 4/56: a Start or Quantity outside the source (Start from 1 to the
//!   source's `DATA` length, Start + Quantity − 1 at most that length).
//!
//! Choices where RM003 says nothing:
//! * MID copies from `DATA` (characters past `LEN` included, as the
//!   Start/Quantity rule allows); DELETE removes what lies inside `LEN`;
//!   INSERT puts Source B's first character at Start (past the end of A:
//!   at its end); FIND of an empty Search gives 0.
//! * RTOS writes six decimals (`2.718500`), or a six-decimal mantissa and
//!   a three-digit exponent (`1.234560e+008`) below 0.0001 and from 10⁷
//!   up; non-finite values write `1.#INF`, `-1.#INF` or `1.#QNAN`.
//! * STOD skips leading characters until a digit (or a minus sign before
//!   one) and converts that group of digits, a fraction's integer part
//!   only; STOR the same with a fraction and an exponent; no digits gives
//!   0.
//! * Comparisons compare character codes, a string that is a prefix of
//!   the other the smaller.

use super::{Exec, R};
use crate::program::ir::{StrArgs, StrAt, StrOp};
use crate::program::types::{DataType, Value};
use crate::st::ast::BinaryOp;

impl Exec<'_> {
    /// The slot of a string's `LEN` (computed subscripts checked).
    fn str_slot(&mut self, s: &StrAt) -> R<usize> {
        Ok(s.base + self.term_offset(&s.terms, |t| t.slots)?)
    }

    /// A string's `LEN` characters (4/51 when `LEN` is out of range).
    fn read_string(&mut self, s: &StrAt) -> R<Vec<u8>> {
        let at = self.str_slot(s)?;
        let len = self.mem.slots[at].as_i64();
        if !(0..=s.capacity as i64).contains(&len) {
            return Err(self.raise(
                4,
                51,
                format!("{}.LEN is {len}: outside its DATA of {} characters", s.name, s.capacity),
            ));
        }
        Ok((0..len as usize)
            .map(|k| self.mem.slots[at + 1 + k].as_i64() as u8)
            .collect())
    }

    /// Writes `text` as the string's `LEN` and first characters; `code`
    /// is the fault when it does not fit.
    fn write_string(&mut self, s: &StrAt, text: &[u8], code: u8) -> R<()> {
        let at = self.str_slot(s)?;
        if text.len() > s.capacity {
            return Err(self.raise(
                4,
                code,
                format!(
                    "the result has {} characters, {} holds {}",
                    text.len(),
                    s.name,
                    s.capacity
                ),
            ));
        }
        self.mem.slots[at] = Value::Int(text.len() as i64);
        for (k, b) in text.iter().enumerate() {
            self.mem.slots[at + 1 + k] = Value::Int(i64::from(*b as i8));
        }
        Ok(())
    }

    /// Start (1-based) and Quantity checked against a source's `DATA`
    /// length (4/56); the 0-based start.
    fn start_and_quantity(&mut self, start: i64, qty: i64, s: &StrAt) -> R<usize> {
        let cap = s.capacity as i64;
        if start < 1 || start > cap || qty < 0 || start - 1 + qty > cap {
            return Err(self.raise(
                4,
                56,
                format!(
                    "Start {start}, Quantity {qty}: outside {} (Start 1 to {cap}, Start + Quantity − 1 at most {cap})",
                    s.name
                ),
            ));
        }
        Ok((start - 1) as usize)
    }

    pub(super) fn string_instruction(&mut self, op: StrOp, args: &StrArgs) -> R<()> {
        match args {
            StrArgs::Join(a, b, start, dest) => {
                let mut text = self.read_string(a)?;
                let other = self.read_string(b)?;
                let at = match start {
                    None => text.len(),
                    Some(start) => {
                        let start = self.eval(start).as_i64();
                        self.check()?;
                        self.start_and_quantity(start, 0, a)?.min(text.len())
                    }
                };
                text.splice(at..at, other);
                self.write_string(dest, &text, 51)
            }
            StrArgs::Cut(source, qty, start, dest) => {
                let qty = self.eval(qty).as_i64();
                self.check()?;
                let start = self.eval(start).as_i64();
                self.check()?;
                let from = self.start_and_quantity(start, qty, source)?;
                let qty = qty as usize;
                let text = if op == StrOp::Mid {
                    // The LEN check first, then the DATA characters asked.
                    self.read_string(source)?;
                    let at = self.str_slot(source)?;
                    (from..from + qty)
                        .map(|k| self.mem.slots[at + 1 + k].as_i64() as u8)
                        .collect()
                } else {
                    let mut text = self.read_string(source)?;
                    let end = (from + qty).min(text.len());
                    if from < end {
                        text.drain(from..end);
                    }
                    text
                };
                self.write_string(dest, &text, 51)
            }
            StrArgs::Find(source, search, start, place, ty) => {
                let text = self.read_string(source)?;
                let wanted = self.read_string(search)?;
                let start = self.eval(start).as_i64();
                self.check()?;
                let from = self.start_and_quantity(start, 0, source)?;
                let found = if wanted.is_empty() || from >= text.len() {
                    0
                } else {
                    text[from..]
                        .windows(wanted.len())
                        .position(|w| w == wanted.as_slice())
                        .map_or(0, |k| (from + k + 1) as i64)
                };
                self.store(place, *ty, Value::Int(found));
                self.check()
            }
            StrArgs::Case(source, dest) => {
                let mut text = self.read_string(source)?;
                if op == StrOp::Upper {
                    text.make_ascii_uppercase();
                } else {
                    text.make_ascii_lowercase();
                }
                self.write_string(dest, &text, 51)
            }
            StrArgs::FromNumber(value, dest) => {
                let v = self.eval(value);
                self.check()?;
                let text = if op == StrOp::Dtos {
                    v.as_i64().to_string()
                } else {
                    real_text(v.as_f64() as f32)
                };
                self.write_string(dest, text.as_bytes(), 52)
            }
            StrArgs::ToNumber(source, place, ty) => {
                let text = self.read_string(source)?;
                let value = if op == StrOp::Stod {
                    integer_in(&text)
                } else {
                    real_in(&text)
                };
                // STOD writes an integer, STOR a REAL (checked at load).
                let fits = match (value, ty) {
                    (Value::Int(i), t) => t.wrap(i128::from(i)) == i,
                    (Value::Real(x), DataType::Real) => x.is_finite() && (x as f32).is_finite(),
                    (Value::Real(x), _) => x.is_finite(),
                    (Value::Bool(_), _) => true,
                };
                if !fits {
                    return Err(self.raise(
                        4,
                        53,
                        format!("'{}' is beyond {}", String::from_utf8_lossy(&text), ty.name()),
                    ));
                }
                self.store(place, *ty, value);
                self.check()
            }
        }
    }

    /// `A op B` for two strings.
    pub(super) fn compare_strings(&mut self, op: BinaryOp, a: &StrAt, b: &StrAt) -> Value {
        let (x, y) = match (self.read_string(a), self.read_string(b)) {
            (Ok(x), Ok(y)) => (x, y),
            (Err(f), _) | (_, Err(f)) => {
                self.fail(f);
                return Value::Bool(false);
            }
        };
        Value::Bool(match op {
            BinaryOp::Eq => x == y,
            BinaryOp::Ne => x != y,
            BinaryOp::Lt => x < y,
            BinaryOp::Le => x <= y,
            BinaryOp::Gt => x > y,
            _ => x >= y,
        })
    }
}

/// RTOS's text of a REAL (module doc).
fn real_text(x: f32) -> String {
    if x.is_nan() {
        return "1.#QNAN".to_owned();
    }
    if x.is_infinite() {
        return if x > 0.0 { "1.#INF" } else { "-1.#INF" }.to_owned();
    }
    let m = x.abs();
    if m == 0.0 || (1e-4..1e7).contains(&m) {
        return format!("{:.6}", f64::from(x));
    }
    let text = format!("{:.6e}", f64::from(x));
    let (mantissa, exponent) = text.split_once('e').unwrap_or((&text, "0"));
    let e: i32 = exponent.parse().unwrap_or(0);
    format!("{mantissa}e{}{:03}", if e < 0 { '-' } else { '+' }, e.abs())
}

/// Where STOD and STOR start: the first digit, or a minus sign (STOR: or
/// a point) right before one.
fn number_start(text: &[u8], point: bool) -> Option<usize> {
    (0..text.len()).find(|&k| {
        let next_digit = text.get(k + 1).is_some_and(u8::is_ascii_digit);
        text[k].is_ascii_digit() || (text[k] == b'-' || point && text[k] == b'.') && next_digit
    })
}

/// STOD's value: the first group of digits with its minus sign.
fn integer_in(text: &[u8]) -> Value {
    let Some(start) = number_start(text, false) else {
        return Value::Int(0);
    };
    let negative = text[start] == b'-';
    let digits = text[start + usize::from(negative)..]
        .iter()
        .take_while(|c| c.is_ascii_digit());
    let mut v: i128 = 0;
    for d in digits {
        v = (v * 10 + i128::from(d - b'0')).min(i128::from(u64::MAX) * 2);
    }
    let v = if negative { -v } else { v };
    Value::Int(v.clamp(i128::from(i64::MIN), i128::from(i64::MAX)) as i64)
}

/// STOR's value: sign, digits, fraction and exponent from the first
/// number.
fn real_in(text: &[u8]) -> Value {
    let Some(start) = number_start(text, true) else {
        return Value::Real(0.0);
    };
    let rest = &text[start..];
    let mut end = usize::from(rest[0] == b'-');
    let digits = |from: usize| rest[from..].iter().take_while(|c| c.is_ascii_digit()).count();
    end += digits(end);
    if rest.get(end) == Some(&b'.') {
        end += 1 + digits(end + 1);
    }
    if matches!(rest.get(end), Some(b'e' | b'E')) {
        let sign = usize::from(matches!(rest.get(end + 1), Some(b'+' | b'-')));
        let n = digits(end + 1 + sign);
        if n > 0 {
            end += 1 + sign + n;
        }
    }
    let s = String::from_utf8_lossy(&rest[..end]);
    Value::Real(s.parse::<f64>().unwrap_or(0.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rtos_text() {
        assert_eq!(real_text(2.718_5), "2.718500");
        assert_eq!(real_text(0.0), "0.000000");
        assert_eq!(real_text(-2.5), "-2.500000");
        assert_eq!(real_text(123_456_000.0), "1.234560e+008");
        assert_eq!(real_text(0.000_01), "1.000000e-005");
    }

    #[test]
    fn stod_and_stor_read_the_first_number() {
        assert_eq!(integer_in(b"abc-42/7"), Value::Int(-42));
        assert_eq!(integer_in(b"x12.9"), Value::Int(12));
        assert_eq!(integer_in(b"none"), Value::Int(0));
        assert_eq!(integer_in(b"a-b7"), Value::Int(7));
        assert_eq!(real_in(b"T=-1.5e2C"), Value::Real(-150.0));
        assert_eq!(real_in(b"v .25"), Value::Real(0.25));
        assert_eq!(real_in(b"3e"), Value::Real(3.0));
    }
}
