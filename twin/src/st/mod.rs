//! Structured Text, one front-end for every text a user writes in it:
//! routines (`[[tasks]]`), the single calls of `[[program]]` steps (a call
//! is a one-statement routine), and the expressions a scene holds (a
//! step's `when`, `[trace] tags`); and ladder rungs (`*.rll`, an L5X's RLL
//! routines), whose instructions, operands and CPT/CMP expressions are the
//! same tokens and calls (`parse::parse_ladder`). [`lex`] → [`parse`] →
//! [`ast`]; names are resolved and types checked by the program stage's
//! compiler.
//!
//! Calls take two shapes, the two the specs use:
//! * **Positional** (Rockwell Logix instructions): the operands in the
//!   order of the manual's faceplate, e.g.
//!   `MCCM(CS1, MC1, 0, Pos[0], 1, Ctr[0], 0, 100, unitspersec, 50, %ofmaximum, ...);`
//! * **Named** (PLCopen / Beckhoff function blocks called on an instance
//!   tag): `MoveTable(Axis := Table, Execute := TRUE, Position := 90.0);`
//!
//! Every node carries its [`crate::source::Span`], a byte range of its
//! file, also for a text parsed from inside a scene's string.
//!
//! # Examples
//!
//! ```
//! use twin::source::{Files, Source};
//! use twin::st::parse::parse_call;
//!
//! let mut files = Files::default();
//! let id = files.add("step", "MoveTable(Axis := Table, Position := 90.0);");
//! let call = parse_call(&Source::file(&files, id)).unwrap();
//! assert_eq!(call.name, "MoveTable");
//! assert_eq!(call.args[1].name.as_ref().unwrap().0, "Position");
//! assert_eq!(call.args[1].text, "90.0");
//! ```

pub mod ast;
pub mod lex;
pub mod parse;
