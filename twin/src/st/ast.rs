//! The syntax tree of Structured Text, as written — a routine, a
//! `[[program]]` call (a one-statement routine) or an expression: names
//! are not resolved and nothing is typed yet (the program stage compiles
//! it). Every node knows its [`Span`] in its file.

pub use crate::source::Span;

/// A routine: its statements in order (Structured Text), or its rungs
/// (ladder).
#[derive(Debug, Clone, PartialEq)]
pub struct Routine {
    /// The statements (none in a ladder routine).
    pub body: Vec<Stmt>,
    /// A ladder routine's rungs, in order; `None` for Structured Text.
    pub rungs: Option<Vec<Rung>>,
}

/// A ladder rung: instructions in series, branches among them, as the
/// neutral text of an L5X export writes it
/// (`XIC(Start)[XIO(Fault) OTE(Run) ,TON(T1,?,?) ];`).
#[derive(Debug, Clone, PartialEq)]
pub struct Rung {
    /// Its number in the routine (Studio numbers rungs from 0).
    pub number: u32,
    /// The instructions and branches, left to right.
    pub elements: Vec<Element>,
    /// The whole rung, its `;` included.
    pub span: Span,
}

/// One element of a rung or of a branch's leg.
#[derive(Debug, Clone, PartialEq)]
pub enum Element {
    /// An instruction: `XIC(Start)`, `TON(T1,?,?)`, `NOP()`.
    Instruction(Call),
    /// A branch `[leg ,leg …]`: each leg's elements (a leg may be empty:
    /// a wire), top to bottom, and where the branch is.
    Branch(Vec<Vec<Element>>, Span),
}

impl Element {
    /// Calls `f` on every instruction of `elements`, those inside branches
    /// included, left to right, top to bottom.
    pub fn visit<'a>(elements: &'a [Element], f: &mut dyn FnMut(&'a Call)) {
        for e in elements {
            match e {
                Element::Instruction(c) => f(c),
                Element::Branch(legs, _) => {
                    for leg in legs {
                        Element::visit(leg, f);
                    }
                }
            }
        }
    }

    /// As [`Element::visit`], with each instruction mutable.
    pub fn visit_mut(elements: &mut [Element], f: &mut dyn FnMut(&mut Call)) {
        for e in elements {
            match e {
                Element::Instruction(c) => f(c),
                Element::Branch(legs, _) => {
                    for leg in legs {
                        Element::visit_mut(leg, f);
                    }
                }
            }
        }
    }
}

impl Routine {
    /// Every instruction call of the routine, those inside `IF`, `CASE`
    /// and loops (or a rung's branches) included, in text order.
    #[must_use]
    pub fn calls(&self) -> Vec<&Call> {
        let mut out = Vec::new();
        visit(&self.body, &mut |s| {
            if let StmtKind::Call(c) = &s.kind {
                out.push(c);
            }
        });
        for rung in self.rungs.iter().flatten() {
            Element::visit(&rung.elements, &mut |c| out.push(c));
        }
        out
    }

    /// Whether it is a ladder routine.
    #[must_use]
    pub fn is_ladder(&self) -> bool {
        self.rungs.is_some()
    }

    /// Every assignment's target, those inside `IF`, `CASE` and loops
    /// included, in text order (none in a ladder routine).
    #[must_use]
    pub fn assignment_targets(&self) -> Vec<&Ref> {
        let mut out = Vec::new();
        visit(&self.body, &mut |s| {
            if let StmtKind::Assign { target, .. } = &s.kind {
                out.push(target);
            }
        });
        out
    }
}

/// Calls `f` on every statement, nested ones after the statement holding
/// them, in text order.
/// Calls `f` on every reference of `statements`, subscripts and bit
/// numbers inside references included, for a pass that rewrites names (an
/// alias to its target).
pub fn refs_mut(statements: &mut [Stmt], f: &mut dyn FnMut(&mut Ref)) {
    for s in statements {
        match &mut s.kind {
            StmtKind::Assign { target, value, .. } => {
                ref_mut(target, f);
                value.refs_mut(f);
            }
            StmtKind::If { branches, otherwise } => {
                for (c, body) in branches {
                    c.refs_mut(f);
                    refs_mut(body, f);
                }
                refs_mut(otherwise, f);
            }
            StmtKind::Case {
                selector,
                arms,
                otherwise,
            } => {
                selector.refs_mut(f);
                for (_, body) in arms {
                    refs_mut(body, f);
                }
                refs_mut(otherwise, f);
            }
            StmtKind::For {
                counter,
                from,
                to,
                by,
                body,
            } => {
                ref_mut(counter, f);
                from.refs_mut(f);
                to.refs_mut(f);
                if let Some(b) = by {
                    b.refs_mut(f);
                }
                refs_mut(body, f);
            }
            StmtKind::While { condition, body } => {
                condition.refs_mut(f);
                refs_mut(body, f);
            }
            StmtKind::Repeat { body, until } => {
                refs_mut(body, f);
                until.refs_mut(f);
            }
            StmtKind::Call(c) => c.refs_mut(f),
            StmtKind::Exit | StmtKind::Empty => {}
        }
    }
}

/// Calls `f` on every instruction call of `statements`, those inside
/// `IF`, `CASE` and loops included.
pub fn calls_mut(statements: &mut [Stmt], f: &mut dyn FnMut(&mut Call)) {
    for s in statements {
        match &mut s.kind {
            StmtKind::Call(c) => f(c),
            StmtKind::If { branches, otherwise } => {
                for (_, body) in branches {
                    calls_mut(body, f);
                }
                calls_mut(otherwise, f);
            }
            StmtKind::Case { arms, otherwise, .. } => {
                for (_, body) in arms {
                    calls_mut(body, f);
                }
                calls_mut(otherwise, f);
            }
            StmtKind::For { body, .. } | StmtKind::While { body, .. } | StmtKind::Repeat { body, .. } => {
                calls_mut(body, f);
            }
            _ => {}
        }
    }
}

fn ref_mut(r: &mut Ref, f: &mut dyn FnMut(&mut Ref)) {
    f(r);
    for a in &mut r.path {
        match a {
            Access::Index(subs) => {
                for e in subs {
                    e.refs_mut(f);
                }
            }
            Access::BitExpr(e) => e.refs_mut(f),
            Access::Member(..) | Access::Bit(_) => {}
        }
    }
}

impl Call {
    /// Calls `f` on every reference in the arguments (see [`refs_mut`]).
    pub fn refs_mut(&mut self, f: &mut dyn FnMut(&mut Ref)) {
        for a in &mut self.args {
            if let Some(e) = &mut a.expr {
                e.refs_mut(f);
            }
        }
    }
}

impl Expr {
    /// Calls `f` on every reference in the expression (see [`refs_mut`]).
    pub fn refs_mut(&mut self, f: &mut dyn FnMut(&mut Ref)) {
        match &mut self.kind {
            ExprKind::Ref(r) => ref_mut(r, f),
            ExprKind::Unary(_, e) => e.refs_mut(f),
            ExprKind::Binary(first, rest) => {
                first.refs_mut(f);
                for (_, e) in rest {
                    e.refs_mut(f);
                }
            }
            ExprKind::Function(_, _, args) => {
                for e in args {
                    e.refs_mut(f);
                }
            }
            ExprKind::Int(_) | ExprKind::Real(_) | ExprKind::Bool(_) => {}
        }
    }
}

fn visit<'a>(statements: &'a [Stmt], f: &mut dyn FnMut(&'a Stmt)) {
    for s in statements {
        f(s);
        match &s.kind {
            StmtKind::If { branches, otherwise } => {
                for (_, body) in branches {
                    visit(body, f);
                }
                visit(otherwise, f);
            }
            StmtKind::Case { arms, otherwise, .. } => {
                for (_, body) in arms {
                    visit(body, f);
                }
                visit(otherwise, f);
            }
            StmtKind::For { body, .. } | StmtKind::While { body, .. } | StmtKind::Repeat { body, .. } => {
                visit(body, f);
            }
            _ => {}
        }
    }
}

/// A statement and where it is.
#[derive(Debug, Clone, PartialEq)]
pub struct Stmt {
    /// What it does.
    pub kind: StmtKind,
    /// Its first token (the keyword of an `IF`, a call's name, an
    /// assignment's target).
    pub span: Span,
}

/// The statements of the Logix ST dialect.
#[derive(Debug, Clone, PartialEq)]
pub enum StmtKind {
    /// `target := value;` (retentive) or `target [:=] value;`
    /// (non-retentive: also cleared at prescan).
    Assign {
        /// What is written.
        target: Ref,
        /// The value.
        value: Expr,
        /// `false` for `[:=]`.
        retentive: bool,
    },
    /// `IF c THEN … ELSIF c THEN … ELSE … END_IF;`
    If {
        /// Each condition with its statements, in order.
        branches: Vec<(Expr, Vec<Stmt>)>,
        /// The `ELSE` statements.
        otherwise: Vec<Stmt>,
    },
    /// `CASE selector OF 1: … 2, 3: … 4..6: … ELSE … END_CASE;`
    Case {
        /// The numeric selector.
        selector: Expr,
        /// Each arm's labels and statements.
        arms: Vec<(Vec<CaseLabel>, Vec<Stmt>)>,
        /// The `ELSE` statements.
        otherwise: Vec<Stmt>,
    },
    /// `FOR i := a TO b BY s DO … END_FOR;`
    For {
        /// The counter.
        counter: Box<Ref>,
        /// Initial value.
        from: Box<Expr>,
        /// Final value.
        to: Box<Expr>,
        /// Step (1 when absent).
        by: Option<Box<Expr>>,
        /// The body.
        body: Vec<Stmt>,
    },
    /// `WHILE c DO … END_WHILE;`
    While {
        /// Checked before each pass.
        condition: Expr,
        /// The body.
        body: Vec<Stmt>,
    },
    /// `REPEAT … UNTIL c END_REPEAT;`
    Repeat {
        /// The body.
        body: Vec<Stmt>,
        /// Checked after each pass.
        until: Expr,
    },
    /// `EXIT;` leaves the innermost loop.
    Exit,
    /// An instruction call `NAME(arg, …);` (a motion instruction, a timer,
    /// `JSR`, `COP` …) or a function-block call with named inputs
    /// `Instance(Input := value, …);` (IEC dialect).
    Call(Call),
    /// `;` alone.
    Empty,
}

/// A `CASE` label: a value or an inclusive range.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CaseLabel {
    /// One value.
    Value(i64),
    /// `low..high`.
    Range(i64, i64),
}

impl CaseLabel {
    /// Whether `x` matches.
    #[must_use]
    pub fn matches(self, x: i64) -> bool {
        match self {
            CaseLabel::Value(v) => x == v,
            CaseLabel::Range(a, b) => (a.min(b)..=a.max(b)).contains(&x),
        }
    }
}

/// A call: `NAME(operand, …)` (positional, a Logix instruction) or
/// `Instance(Input := value, …)` (named, a PLCopen function block).
#[derive(Debug, Clone, PartialEq)]
pub struct Call {
    /// The instruction or instance name, as written.
    pub name: String,
    /// Where the name is.
    pub name_span: Span,
    /// The arguments; all named or all positional.
    pub args: Vec<Arg>,
    /// The whole call, name to `)`.
    pub span: Span,
}

/// One argument of a call, kept both as written and as an expression: an
/// enumeration word of an operand (`%ofTime`, `s-curve`) is recognised
/// from its text once the operand is known.
#[derive(Debug, Clone, PartialEq)]
pub struct Arg {
    /// `Some(input)` for `input := value`, with where the input's name is.
    pub name: Option<(String, Span)>,
    /// The value's text as written (white space trimmed).
    pub text: String,
    /// The value as an expression, when it is one.
    pub expr: Option<Expr>,
    /// Where the value is.
    pub span: Span,
}

/// A reference to a tag, an element, a member or a bit.
#[derive(Debug, Clone, PartialEq)]
pub struct Ref {
    /// The tag name, as written.
    pub name: String,
    /// What follows the name, in order.
    pub path: Vec<Access>,
    /// The whole reference.
    pub span: Span,
}

impl Ref {
    /// Where the tag name is.
    #[must_use]
    pub fn name_span(&self) -> Span {
        Span {
            end: (self.span.start + self.name.len() as u32).min(self.span.end),
            ..self.span
        }
    }
}

/// One step of a reference.
#[derive(Debug, Clone, PartialEq)]
pub enum Access {
    /// `[i]` (one subscript a dimension).
    Index(Vec<Expr>),
    /// `.Member`, and where the member's name is.
    Member(String, Span),
    /// `.5`: a bit by number.
    Bit(u32),
    /// `.[i]`: a bit by expression.
    BitExpr(Box<Expr>),
}

/// An expression and where it is.
#[derive(Debug, Clone, PartialEq)]
pub struct Expr {
    /// What it is.
    pub kind: ExprKind,
    /// The whole expression.
    pub span: Span,
}

/// The expressions of the dialect.
#[derive(Debug, Clone, PartialEq)]
pub enum ExprKind {
    /// An integer literal.
    Int(i128),
    /// A real literal.
    Real(f64),
    /// `TRUE` / `FALSE`.
    Bool(bool),
    /// A tag, element, member or bit.
    Ref(Ref),
    /// `-x`, `NOT x`.
    Unary(UnaryOp, Box<Expr>),
    /// `a op b op c …`: operators of one precedence level applied left to
    /// right (`((a op b) op c) …`), at least one. A chain is one level of
    /// nesting however long it is, so no traversal recurses per operator.
    Binary(Box<Expr>, Vec<(BinaryOp, Expr)>),
    /// `NAME(a, …)`: a function (`ABS`, `SIN`, `SIZE` …), and where its
    /// name is.
    Function(String, Span, Vec<Expr>),
}

/// Unary operators.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum UnaryOp {
    /// `-`.
    Neg,
    /// `NOT` (logical on BOOL, bitwise on integers).
    Not,
}

/// Binary operators, from the highest precedence to the lowest.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BinaryOp {
    /// `**`.
    Pow,
    /// `*`.
    Mul,
    /// `/`.
    Div,
    /// `MOD`.
    Mod,
    /// `+`.
    Add,
    /// `-`.
    Sub,
    /// `<`.
    Lt,
    /// `<=`.
    Le,
    /// `>`.
    Gt,
    /// `>=`.
    Ge,
    /// `=`.
    Eq,
    /// `<>`.
    Ne,
    /// `&`, `AND`.
    And,
    /// `XOR`.
    Xor,
    /// `OR`.
    Or,
}

impl BinaryOp {
    /// Whether it compares (its result is BOOL whatever it computes in).
    #[must_use]
    pub fn is_comparison(self) -> bool {
        matches!(
            self,
            BinaryOp::Lt | BinaryOp::Le | BinaryOp::Gt | BinaryOp::Ge | BinaryOp::Eq | BinaryOp::Ne
        )
    }

    /// The operator as written.
    #[must_use]
    pub fn symbol(self) -> &'static str {
        match self {
            BinaryOp::Pow => "**",
            BinaryOp::Mul => "*",
            BinaryOp::Div => "/",
            BinaryOp::Mod => "MOD",
            BinaryOp::Add => "+",
            BinaryOp::Sub => "-",
            BinaryOp::Lt => "<",
            BinaryOp::Le => "<=",
            BinaryOp::Gt => ">",
            BinaryOp::Ge => ">=",
            BinaryOp::Eq => "=",
            BinaryOp::Ne => "<>",
            BinaryOp::And => "AND",
            BinaryOp::Xor => "XOR",
            BinaryOp::Or => "OR",
        }
    }
}
