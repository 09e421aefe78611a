//! Expectations (`[[expect]]`): conditions on a run, checked on every
//! trace row — from t = 0, after each coarse update, whether or not a
//! trace is written — and their results.
//!
//! A condition is a Logix BOOL expression compiled in controller scope by
//! the program's compiler ([`Twin::compile_expression`]): tags,
//! `Program.Tag`, axis and coordinate-system members, instruction bits,
//! functions. Every trace column is a name too, read at full precision
//! (`J1.act_pos`, `tool.clearance_m`, `collision.count`, `Cart.tool_z`);
//! a tag reference that is also one of the twin's own columns is refused
//! at load, naming both. What happens between two updates is invisible,
//! as in the trace.
//!
//! The kinds (README, "Expectations"):
//! * `always` / `never`: the condition is TRUE (FALSE) at every row in
//!   [`from_s`, `to_s`] where the `while` guard is TRUE;
//! * `eventually`: TRUE at some row in [`after_s`, `by_s`];
//! * `at_end`: TRUE at the last row (where the run ended, also when it
//!   stopped early);
//! * `sequence`: each condition rises (a row where it is TRUE after one
//!   where it was FALSE), each one's first rise not before the previous
//!   one's, the last within `within_s` of the first;
//! * `cycle`: the times between consecutive rises all lie in [`min_s`,
//!   `max_s`], and there are at least `count` of them.
//!
//! An `always` / `never` whose window and guard let no row through fails
//! (it would pass whatever the run did). A failure names the first
//! failing time, the values of the names in the
//! condition there, how long it stayed failed and, when the condition is
//! a comparison, its worst value over that stretch:
//! `expect 'tool keeps 5 mm' failed at 3.412 s: tool.clearance_m = 0.0031
//! (>= 0.005); false in 37 updates to 3.56 s, worst 0.0012`.

use crate::output::trace::{self, Values};
use crate::program::ir::{CExpr, CKind, Column};
use crate::program::types::Value;
use crate::run::Twin;
use crate::scene::{Condition, ExpectKind, Expectation};
use crate::source::Diagnostic;
use crate::st::ast::{Access, BinaryOp, Expr, ExprKind};

/// Half a microsecond: times compare with this tolerance.
const EPS_S: f64 = 5e-7;

/// One expectation's result.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Outcome {
    /// Its name.
    pub name: String,
    /// Its kind (`always`, `never`, `eventually`, `at_end`, `sequence`,
    /// `cycle`).
    pub kind: &'static str,
    /// Whether it held.
    pub passed: bool,
    /// When it failed (the first failing row), or when it was met (an
    /// `eventually`'s first TRUE row, a `sequence`'s last rise); `None`
    /// when there is no such time.
    pub time_s: Option<f64>,
    /// The failure message (module doc); for a pass, what was seen.
    pub message: String,
}

/// A condition compiled, with what a failure message shows.
struct Compiled {
    /// The condition.
    expr: CExpr,
    /// The text as written.
    text: String,
    /// Each name the condition reads, with its text, compiled alone.
    names: Vec<(String, CExpr)>,
    /// The condition as a comparison whose worst value is tracked.
    comparison: Option<Comparison>,
}

/// `L op R`, with the side that varies.
struct Comparison {
    op: BinaryOp,
    /// What is tracked: the side that is not constant, or `L - R`.
    tracked: CExpr,
    /// `(op R)` when R is constant, for the message.
    bound: Option<String>,
}

/// The names of a condition with their values at one row.
type Named = Vec<(String, Value)>;

/// The values of a condition's names at one row, formatted.
fn show_names(values: &[(String, Value)]) -> String {
    values
        .iter()
        .map(|(n, v)| format!("{n} = {}", show_value(*v)))
        .collect::<Vec<_>>()
        .join(", ")
}

fn show_value(v: Value) -> String {
    match v {
        Value::Bool(b) => if b { "TRUE" } else { "FALSE" }.to_owned(),
        Value::Int(i) => i.to_string(),
        Value::Real(x) => short(x),
    }
}

/// A number for a message: at most 6 significant digits, as the trace
/// writes short numbers.
fn short(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return trace::number(x);
    }
    let digits = 6 - (x.abs().log10().floor() as i32 + 1);
    let rounded = if (0..=17).contains(&digits) {
        let p = 10f64.powi(digits);
        (x * p).round() / p
    } else {
        x
    };
    trace::number(rounded)
}

/// A time for a message.
fn time(t: f64) -> String {
    format!("{} s", short(t))
}

/// Where the check of one expectation stands.
enum State {
    Always {
        never: bool,
        from_s: f64,
        to_s: Option<f64>,
        guard: Option<Compiled>,
        failure: Option<Failure>,
        /// Rows checked (inside the window, the guard TRUE).
        checked: u64,
    },
    Eventually {
        after_s: f64,
        by_s: Option<f64>,
        met_s: Option<f64>,
        best: Option<f64>,
        last: Option<(f64, Named)>,
    },
    AtEnd {
        last: Option<(f64, bool, Named)>,
    },
    Sequence {
        within_s: Option<f64>,
        was: Vec<Option<bool>>,
        first_rise: Vec<Option<f64>>,
        true_at_start: Vec<bool>,
    },
    Cycle {
        min_s: f64,
        max_s: Option<f64>,
        count: u32,
        was: Option<bool>,
        last_rise: Option<f64>,
        cycles: u32,
        violation: Option<(u32, f64, f64)>,
    },
}

/// The first failing stretch of an `always` / `never`.
struct Failure {
    at_s: f64,
    values: Named,
    rows: u64,
    until_s: f64,
    worst: Option<f64>,
    open: bool,
}

struct Check {
    name: String,
    kind: &'static str,
    conditions: Vec<Compiled>,
    state: State,
}

/// A run's expectations, compiled, and where each stands.
pub struct Expectations {
    checks: Vec<Check>,
    row: Values,
    last_s: f64,
}

impl std::fmt::Debug for Expectations {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Expectations")
            .field("checks", &self.checks.len())
            .finish_non_exhaustive()
    }
}

/// The trace's columns as names an expectation may read.
pub fn columns(twin: &Twin) -> Vec<Column> {
    let mut row = Values::default();
    row.read(twin);
    trace::header(twin)
        .into_iter()
        .zip(row.types)
        .map(|(name, ty)| Column {
            of_tag: of_tag(&name),
            name,
            ty,
        })
        .collect()
}

/// Whether a column belongs to the tag its first part names (an axis, a
/// coordinate system, an instruction, a block, a traced tag) rather than
/// to something that is not a tag (module [`trace`]'s list).
fn of_tag(name: &str) -> bool {
    !(matches!(name, "time_s" | "collision.count" | "plant.kinematic") || name.ends_with(".clearance_m"))
}

impl Expectations {
    /// Compiles the scene's expectations against `twin`'s program and
    /// trace columns.
    ///
    /// # Errors
    /// The first expression that does not compile or is not BOOL, as a
    /// diagnostic pointing into it with its field.
    pub fn new(twin: &mut Twin) -> Result<Expectations, Box<Diagnostic>> {
        let expectations = twin.scene().expectations.clone();
        // Compiling may bind an instruction tag the program does not use,
        // which adds trace columns: compile again against the new ones.
        let mut cols = columns(twin);
        let checks = loop {
            let checks = expectations
                .iter()
                .map(|e| compile_check(twin, e, &cols))
                .collect::<Result<Vec<_>, _>>()?;
            let now = columns(twin);
            if now == cols {
                break checks;
            }
            cols = now;
        };
        Ok(Expectations {
            checks,
            row: Values::default(),
            last_s: 0.0,
        })
    }

    /// Whether the scene has none.
    pub fn is_empty(&self) -> bool {
        self.checks.is_empty()
    }

    /// Checks every expectation on `twin`'s row now (call it before the
    /// first update and after each).
    pub fn observe(&mut self, twin: &mut Twin) {
        if self.checks.is_empty() {
            return;
        }
        self.row.read(twin);
        let t = twin.time_s();
        self.last_s = t;
        let row = &self.row.values;
        for check in &mut self.checks {
            observe(check, twin, row, t);
        }
    }

    /// Each expectation's result, as of the last row observed.
    pub fn outcomes(&self) -> Vec<Outcome> {
        self.checks.iter().map(|c| outcome(c, self.last_s)).collect()
    }
}

fn compile_check(twin: &mut Twin, e: &Expectation, cols: &[Column]) -> Result<Check, Box<Diagnostic>> {
    let checked: Vec<&Condition> = match &e.kind {
        ExpectKind::Always { condition, .. }
        | ExpectKind::Eventually { condition, .. }
        | ExpectKind::AtEnd { condition }
        | ExpectKind::Cycle { condition, .. } => vec![condition],
        ExpectKind::Sequence { steps, .. } => steps.iter().collect(),
    };
    let conditions = checked
        .into_iter()
        .map(|c| compile_condition(twin, c, cols))
        .collect::<Result<Vec<_>, _>>()?;
    let state = match &e.kind {
        ExpectKind::Always {
            never,
            from_s,
            to_s,
            guard,
            ..
        } => State::Always {
            never: *never,
            from_s: *from_s,
            to_s: *to_s,
            guard: match guard {
                Some(g) => Some(compile_condition(twin, g, cols)?),
                None => None,
            },
            failure: None,
            checked: 0,
        },
        ExpectKind::Eventually { after_s, by_s, .. } => State::Eventually {
            after_s: *after_s,
            by_s: *by_s,
            met_s: None,
            best: None,
            last: None,
        },
        ExpectKind::AtEnd { .. } => State::AtEnd { last: None },
        ExpectKind::Sequence { steps, within_s } => State::Sequence {
            within_s: *within_s,
            was: vec![None; steps.len()],
            first_rise: vec![None; steps.len()],
            true_at_start: vec![false; steps.len()],
        },
        ExpectKind::Cycle {
            min_s, max_s, count, ..
        } => State::Cycle {
            min_s: *min_s,
            max_s: *max_s,
            count: *count,
            was: None,
            last_rise: None,
            cycles: 0,
            violation: None,
        },
    };
    Ok(Check {
        name: e.name.clone(),
        kind: e.kind.name(),
        conditions,
        state,
    })
}

fn compile_condition(twin: &mut Twin, c: &Condition, cols: &[Column]) -> Result<Compiled, Box<Diagnostic>> {
    let in_field = |d: Box<Diagnostic>| Box::new((*d).in_field(c.field.clone()));
    let expr = twin.compile_expression(&c.expr, cols).map_err(in_field)?;
    if expr.ty != crate::program::types::Ty::Bool {
        let ty = expr.ty.name();
        let d = twin
            .scene()
            .files
            .error(
                c.expr.span,
                format!("the condition is {ty}: compare it"),
                format!("this is {ty}"),
            )
            .with_help(format!("an expectation is a BOOL expression, e.g. {} > 0", c.text));
        return Err(in_field(Box::new(d)));
    }
    let mut refs = Vec::new();
    collect_refs(&c.expr, &mut refs);
    let mut names: Vec<(String, CExpr)> = Vec::new();
    for r in refs {
        let text = source_text(twin, r);
        if names.iter().any(|(n, _)| n.eq_ignore_ascii_case(&text)) {
            continue;
        }
        let e = twin.compile_expression(r, cols).map_err(in_field)?;
        names.push((text, e));
    }
    let comparison = match &c.expr.kind {
        ExprKind::Binary(l, rest)
            if let [
                (op @ (BinaryOp::Lt | BinaryOp::Le | BinaryOp::Gt | BinaryOp::Ge | BinaryOp::Eq | BinaryOp::Ne), r),
            ] = rest.as_slice() =>
        {
            let left = twin.compile_expression(l, cols).map_err(in_field)?;
            let right = twin.compile_expression(r, cols).map_err(in_field)?;
            let constant = |e: &CExpr| matches!(e.kind, CKind::Const(_));
            match (constant(&left), constant(&right)) {
                (false, true) => Some(Comparison {
                    op: *op,
                    tracked: left,
                    bound: Some(format!("{} {}", op.symbol(), source_text(twin, r))),
                }),
                (true, false) => Some(Comparison {
                    op: mirror(*op),
                    tracked: right,
                    bound: Some(format!("{} {}", mirror(*op).symbol(), source_text(twin, l))),
                }),
                (false, false) if left.ty != crate::program::types::Ty::Bool => {
                    // L - R, compiled from the two sides.
                    let diff = Expr {
                        kind: ExprKind::Binary(l.clone(), vec![(BinaryOp::Sub, r.clone())]),
                        span: c.expr.span,
                    };
                    twin.compile_expression(&diff, cols).ok().map(|tracked| Comparison {
                        op: *op,
                        tracked,
                        bound: None,
                    })
                }
                _ => None,
            }
        }
        _ => None,
    };
    Ok(Compiled {
        expr,
        text: c.text.clone(),
        names,
        comparison,
    })
}

/// `a op b` as `b op' a`.
fn mirror(op: BinaryOp) -> BinaryOp {
    match op {
        BinaryOp::Lt => BinaryOp::Gt,
        BinaryOp::Le => BinaryOp::Ge,
        BinaryOp::Gt => BinaryOp::Lt,
        BinaryOp::Ge => BinaryOp::Le,
        other => other,
    }
}

/// The references an expression reads, in order (subscripts included).
fn collect_refs<'a>(e: &'a Expr, out: &mut Vec<&'a Expr>) {
    match &e.kind {
        ExprKind::Ref(r) => {
            out.push(e);
            for a in &r.path {
                match a {
                    Access::Index(subs) => subs.iter().for_each(|s| collect_refs(s, out)),
                    Access::BitExpr(b) => collect_refs(b, out),
                    Access::Member(..) | Access::Bit(_) => {}
                }
            }
        }
        ExprKind::Unary(_, a) => collect_refs(a, out),
        ExprKind::Binary(first, rest) => {
            collect_refs(first, out);
            rest.iter().for_each(|(_, b)| collect_refs(b, out));
        }
        ExprKind::Function(_, _, args) => args.iter().for_each(|a| collect_refs(a, out)),
        ExprKind::Int(_) | ExprKind::Real(_) | ExprKind::Bool(_) => {}
    }
}

/// An expression's text as written.
fn source_text(twin: &Twin, e: &Expr) -> String {
    let file = twin.scene().files.get(e.span.file);
    file.text
        .get(e.span.range())
        .map_or_else(|| format!("{:?}", e.kind), |t| t.trim().to_owned())
}

fn truthy(twin: &mut Twin, e: &CExpr, row: &[f64]) -> bool {
    twin.evaluate(e, row).truthy()
}

fn number(twin: &mut Twin, e: &CExpr, row: &[f64]) -> f64 {
    twin.evaluate(e, row).as_f64()
}

fn name_values(twin: &mut Twin, c: &Compiled, row: &[f64]) -> Named {
    c.names
        .iter()
        .map(|(n, e)| (n.clone(), twin.evaluate(e, row)))
        .collect()
}

/// Of two values of a comparison's tracked side, the one further from
/// making the condition `want` (`worse`) or nearer to it (`!worse`).
fn pick(cmp: &Comparison, want: bool, worse: bool, a: f64, b: f64) -> f64 {
    // Whether a larger tracked value makes the condition more TRUE.
    let larger_is_truer = match cmp.op {
        BinaryOp::Gt | BinaryOp::Ge => Some(true),
        BinaryOp::Lt | BinaryOp::Le => Some(false),
        _ => None,
    };
    match larger_is_truer {
        Some(up) => {
            let take_larger = up != want;
            let take_larger = if worse { take_larger } else { !take_larger };
            if take_larger { a.max(b) } else { a.min(b) }
        }
        // `=` / `<>`: the distance from equality (tracked as L or L - R).
        None => {
            let far = (cmp.op == BinaryOp::Eq) == want;
            let far = if worse { far } else { !far };
            if (a.abs() > b.abs()) == far { a } else { b }
        }
    }
}

fn observe(check: &mut Check, twin: &mut Twin, row: &[f64], t: f64) {
    let Check { conditions, state, .. } = check;
    match state {
        State::Always {
            never,
            from_s,
            to_s,
            guard,
            failure,
            checked,
        } => {
            let inside = t >= *from_s - EPS_S && to_s.is_none_or(|to| t <= to + EPS_S);
            if !inside {
                if let Some(f) = failure {
                    f.open = false;
                }
                return;
            }
            if let Some(g) = guard
                && !truthy(twin, &g.expr, row)
            {
                if let Some(f) = failure {
                    f.open = false;
                }
                return;
            }
            *checked += 1;
            let c = &conditions[0];
            let ok = truthy(twin, &c.expr, row) != *never;
            let want = !*never;
            let tracked = c.comparison.as_ref().map(|cmp| (cmp, number(twin, &cmp.tracked, row)));
            match failure {
                None if !ok => {
                    *failure = Some(Failure {
                        at_s: t,
                        values: name_values(twin, c, row),
                        rows: 1,
                        until_s: t,
                        worst: tracked.map(|(_, x)| x),
                        open: true,
                    });
                }
                Some(f) if f.open => {
                    if ok {
                        f.open = false;
                    } else {
                        f.rows += 1;
                        f.until_s = t;
                        if let (Some((cmp, x)), Some(w)) = (tracked, f.worst) {
                            f.worst = Some(pick(cmp, want, true, w, x));
                        }
                    }
                }
                _ => {}
            }
        }
        State::Eventually {
            after_s,
            by_s,
            met_s,
            best,
            last,
        } => {
            if met_s.is_some() || t < *after_s - EPS_S || by_s.is_some_and(|by| t > by + EPS_S) {
                return;
            }
            let c = &conditions[0];
            if truthy(twin, &c.expr, row) {
                *met_s = Some(t);
                return;
            }
            if let Some(cmp) = &c.comparison {
                let x = number(twin, &cmp.tracked, row);
                *best = Some(best.map_or(x, |b| pick(cmp, true, false, b, x)));
            }
            *last = Some((t, name_values(twin, c, row)));
        }
        State::AtEnd { last } => {
            let c = &conditions[0];
            let ok = truthy(twin, &c.expr, row);
            *last = Some((t, ok, name_values(twin, c, row)));
        }
        State::Sequence {
            was,
            first_rise,
            true_at_start,
            ..
        } => {
            for (k, c) in conditions.iter().enumerate() {
                let now = truthy(twin, &c.expr, row);
                match was[k] {
                    None => true_at_start[k] = now,
                    Some(false) if now && first_rise[k].is_none() => first_rise[k] = Some(t),
                    _ => {}
                }
                was[k] = Some(now);
            }
        }
        State::Cycle {
            min_s,
            max_s,
            was,
            last_rise,
            cycles,
            violation,
            ..
        } => {
            let now = truthy(twin, &conditions[0].expr, row);
            if *was == Some(false) && now {
                if let Some(prev) = *last_rise {
                    *cycles += 1;
                    let period = t - prev;
                    let outside = period < *min_s - EPS_S || max_s.is_some_and(|max| period > max + EPS_S);
                    if outside && violation.is_none() {
                        *violation = Some((*cycles, prev, t));
                    }
                }
                *last_rise = Some(t);
            }
            *was = Some(now);
        }
    }
}

fn outcome(check: &Check, last_s: f64) -> Outcome {
    let head = format!("expect '{}'", check.name);
    let (passed, time_s, message) = match &check.state {
        State::Always {
            never,
            failure,
            checked,
            from_s,
            to_s,
            guard,
        } => {
            let c = &check.conditions[0];
            match failure {
                // Nothing was checked: the expectation would pass whatever
                // the run did.
                None if *checked == 0 => (
                    false,
                    None,
                    format!(
                        "{head} failed: no update was checked (from {} to {}{})",
                        time(*from_s),
                        time(to_s.unwrap_or(last_s)),
                        guard
                            .as_ref()
                            .map_or(String::new(), |g| format!(", while {} was never TRUE", g.text))
                    ),
                ),
                None => (true, None, format!("{head} held over {checked} updates: {}", c.text)),
                Some(f) => {
                    let values = match (&c.comparison, c.names.as_slice()) {
                        (Some(Comparison { bound: Some(b), .. }), [_]) => format!("{} ({b})", show_names(&f.values)),
                        _ => format!(
                            "{} ({} is {})",
                            show_names(&f.values),
                            c.text,
                            if *never { "TRUE" } else { "FALSE" }
                        ),
                    };
                    let state = if *never { "true" } else { "false" };
                    let updates = if f.rows == 1 { "update" } else { "updates" };
                    let mut m = format!(
                        "{head} failed at {}: {values}; {state} in {} {updates} to {}",
                        time(f.at_s),
                        f.rows,
                        time(f.until_s)
                    );
                    if let Some(w) = f.worst {
                        m.push_str(&format!(", worst {}", short(w)));
                    }
                    (false, Some(f.at_s), m)
                }
            }
        }
        State::Eventually {
            after_s,
            by_s,
            met_s,
            best,
            last,
        } => {
            let c = &check.conditions[0];
            match met_s {
                Some(t) => (true, Some(*t), format!("{head} met at {}: {}", time(*t), c.text)),
                None => {
                    let end = by_s.unwrap_or(last_s);
                    let mut m = format!(
                        "{head} failed at {}: {} was never TRUE from {} to {}",
                        time(end),
                        c.text,
                        time(*after_s),
                        time(end)
                    );
                    if by_s.is_some_and(|by| last_s < by - EPS_S) {
                        m.push_str(&format!(" (the run ended at {})", time(last_s)));
                    }
                    if let Some((t, values)) = last {
                        m.push_str(&format!("; at {}: {}", time(*t), show_names(values)));
                    }
                    if let Some(b) = best {
                        m.push_str(&format!(", best {}", short(*b)));
                    }
                    (false, Some(end.min(last_s)), m)
                }
            }
        }
        State::AtEnd { last } => {
            let c = &check.conditions[0];
            match last {
                Some((t, true, _)) => (
                    true,
                    Some(*t),
                    format!("{head} held at the end ({}): {}", time(*t), c.text),
                ),
                Some((t, false, values)) => (
                    false,
                    Some(*t),
                    format!(
                        "{head} failed at {} (the end): {} ({} is FALSE)",
                        time(*t),
                        show_names(values),
                        c.text
                    ),
                ),
                None => (false, None, format!("{head} failed: the run has no row")),
            }
        }
        State::Sequence {
            within_s,
            first_rise,
            true_at_start,
            ..
        } => sequence_outcome(&head, &check.conditions, first_rise, true_at_start, *within_s),
        State::Cycle {
            min_s,
            max_s,
            count,
            cycles,
            violation,
            ..
        } => {
            let c = &check.conditions[0];
            let range = format!("[{}, {}]", time(*min_s), max_s.map_or("∞".to_owned(), time));
            if let Some((k, from, to)) = violation {
                (
                    false,
                    Some(*to),
                    format!(
                        "{head} failed at {}: cycle {k} of {} took {} (from {} to {}), outside {range}",
                        time(*to),
                        c.text,
                        time(to - from),
                        time(*from),
                        time(*to)
                    ),
                )
            } else if cycles < count {
                (
                    false,
                    Some(last_s),
                    format!(
                        "{head} failed at {}: {} completed {cycles} cycles, fewer than count = {count}",
                        time(last_s),
                        c.text
                    ),
                )
            } else {
                (
                    true,
                    None,
                    format!("{head} held: {cycles} cycles of {}, each in {range}", c.text),
                )
            }
        }
    };
    Outcome {
        name: check.name.clone(),
        kind: check.kind,
        passed,
        time_s,
        message,
    }
}

fn sequence_outcome(
    head: &str,
    conditions: &[Compiled],
    first_rise: &[Option<f64>],
    true_at_start: &[bool],
    within_s: Option<f64>,
) -> (bool, Option<f64>, String) {
    let never_rose = |k: usize| {
        let start = if true_at_start[k] {
            " (it was TRUE from the start: a rise is FALSE → TRUE)"
        } else {
            ""
        };
        format!("'{}' never rose{start}", conditions[k].text)
    };
    for k in 0..conditions.len() {
        let Some(rise) = first_rise[k] else {
            let after = match k.checked_sub(1).and_then(|p| first_rise[p].map(|t| (p, t))) {
                Some((p, t)) => format!(" after '{}' rose at {}", conditions[p].text, time(t)),
                None => String::new(),
            };
            return (
                false,
                None,
                format!("{head} failed: step {} {}{after}", k + 1, never_rose(k)),
            );
        };
        if k > 0 {
            match first_rise[k - 1] {
                Some(prev) if rise < prev - EPS_S => {
                    return (
                        false,
                        Some(rise),
                        format!(
                            "{head} failed at {}: step {} '{}' rose before step {} '{}' (at {})",
                            time(rise),
                            k + 1,
                            conditions[k].text,
                            k,
                            conditions[k - 1].text,
                            time(prev)
                        ),
                    );
                }
                _ => {}
            }
        }
    }
    let first = first_rise[0].unwrap_or_default();
    let last = first_rise[conditions.len() - 1].unwrap_or_default();
    if let Some(w) = within_s
        && last - first > w + EPS_S
    {
        return (
            false,
            Some(last),
            format!(
                "{head} failed at {}: the sequence took {} from {} to {}, more than within_s = {}",
                time(last),
                time(last - first),
                time(first),
                time(last),
                time(w)
            ),
        );
    }
    let rises = first_rise
        .iter()
        .map(|t| time(t.unwrap_or_default()))
        .collect::<Vec<_>>()
        .join(", ");
    (true, Some(last), format!("{head} held: rises at {rises}"))
}

#[cfg(test)]
mod tests {
    use super::short;

    #[test]
    fn message_numbers_have_six_significant_digits() {
        assert_eq!(short(0.0031), "0.0031");
        assert_eq!(short(3.560_000_000_1), "3.56");
        assert_eq!(short(123_456.78), "123457");
        assert_eq!(short(-0.000_012_345_67), "-0.0000123457");
        assert_eq!(short(0.0), "0");
    }
}
