//! Ladder routines compiled: each rung a run of statements
//! ([`Ladder::Start`], its instructions and branches in order,
//! [`Ladder::End`]), each instruction bound by [`LADDER`], the one
//! catalogue of the ladder instructions the twin simulates. Operands are
//! compiled as Structured Text's are (one name resolution, one type
//! system): a comparison is the expression `A = B`, ADD the expression
//! `A + B` stored into Dest, so arithmetic, conversion and faults are the
//! Structured Text engine's. JSR, COP, FLL, SIZE, GSV, SSV and EVENT are
//! Structured Text's own instructions, executed on a TRUE rung; a motion
//! instruction is bound by the motion catalogue and executed on the
//! rung's transition.
//!
//! A display operand (Preset and Accum of a timer or counter, Length and
//! Position of the CONTROL instructions) is `?` or a number: the
//! instruction uses the structure's member, and a number is that member's
//! value at load.

use super::{Compiler, Result, constant, err};
use crate::program::ir::{
    CExpr, CStmt, General, Instance, Ladder, MATH_C, MATH_N, MATH_V, MATH_Z, OutputKind, Place, SKind, StackKind,
    StackValue, SwapOrder, TimerKind,
};
use crate::program::types::{CT_LEN, CT_POS, DataType, LC_ACC, LC_PRE, LT_ACC, LT_PRE, Structure, Ty, Value};
use crate::source::Span;
use crate::st::ast::{Arg, BinaryOp, Call, Element, Expr, ExprKind, Rung, UnaryOp};

/// What a ladder instruction is, for binding and docs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Op {
    /// XIC, XIO.
    Examine(bool),
    /// OTE, OTL, OTU.
    Output(OutputKind),
    /// ONS.
    Ons,
    /// OSR (`true`), OSF.
    Edge(bool),
    /// TON, TOF, RTO.
    Timer(TimerKind),
    /// CTU (`true`), CTD.
    Counter(bool),
    /// RES.
    Res,
    /// EQU NEQ LES LEQ GRT GEQ.
    Compare(BinaryOp),
    /// LIM.
    Lim,
    /// MEQ.
    Meq,
    /// CMP.
    Cmp,
    /// ADD SUB MUL DIV MOD AND OR XOR.
    Binary(BinaryOp),
    /// NEG.
    Neg,
    /// ABS.
    Abs,
    /// SQR.
    Sqr,
    /// SIN COS TAN ASN ACS ATN LN LOG DEG RAD TRN TOD FRD (Source, Dest):
    /// the Structured Text function of that name.
    Function(&'static str),
    /// NOT.
    Not,
    /// CPT.
    Cpt,
    /// MOV.
    Mov,
    /// MVM.
    Mvm,
    /// CLR.
    Clr,
    /// SWPB.
    Swpb,
    /// BTD.
    Btd,
    /// BSL (`true`), BSR.
    Shift(bool),
    /// FFL FFU LFL LFU.
    Stack(StackKind),
    /// A Structured Text instruction executed on a TRUE rung.
    General,
    /// JMP.
    Jmp,
    /// LBL.
    Lbl,
    /// TND.
    Tnd,
    /// MCR.
    Mcr,
    /// AFI.
    Afi,
    /// NOP.
    Nop,
}

/// Every ladder instruction the twin simulates (besides the motion
/// instructions of the catalogue): mnemonic, operands, what it is.
pub const LADDER: &[(&str, &[&str], Op)] = &[
    ("XIC", &["Data Bit"], Op::Examine(true)),
    ("XIO", &["Data Bit"], Op::Examine(false)),
    ("OTE", &["Data Bit"], Op::Output(OutputKind::Energize)),
    ("OTL", &["Data Bit"], Op::Output(OutputKind::Latch)),
    ("OTU", &["Data Bit"], Op::Output(OutputKind::Unlatch)),
    ("ONS", &["Storage Bit"], Op::Ons),
    ("OSR", &["Storage Bit", "Output Bit"], Op::Edge(true)),
    ("OSF", &["Storage Bit", "Output Bit"], Op::Edge(false)),
    ("TON", &["Timer", "Preset", "Accum"], Op::Timer(TimerKind::On)),
    ("TOF", &["Timer", "Preset", "Accum"], Op::Timer(TimerKind::Off)),
    ("RTO", &["Timer", "Preset", "Accum"], Op::Timer(TimerKind::Retentive)),
    ("CTU", &["Counter", "Preset", "Accum"], Op::Counter(true)),
    ("CTD", &["Counter", "Preset", "Accum"], Op::Counter(false)),
    ("RES", &["Structure"], Op::Res),
    ("EQU", &["Source A", "Source B"], Op::Compare(BinaryOp::Eq)),
    ("NEQ", &["Source A", "Source B"], Op::Compare(BinaryOp::Ne)),
    ("LES", &["Source A", "Source B"], Op::Compare(BinaryOp::Lt)),
    ("LEQ", &["Source A", "Source B"], Op::Compare(BinaryOp::Le)),
    ("GRT", &["Source A", "Source B"], Op::Compare(BinaryOp::Gt)),
    ("GEQ", &["Source A", "Source B"], Op::Compare(BinaryOp::Ge)),
    ("LIM", &["Low Limit", "Test", "High Limit"], Op::Lim),
    ("MEQ", &["Source", "Mask", "Compare"], Op::Meq),
    ("CMP", &["Expression"], Op::Cmp),
    ("ADD", &["Source A", "Source B", "Dest"], Op::Binary(BinaryOp::Add)),
    ("SUB", &["Source A", "Source B", "Dest"], Op::Binary(BinaryOp::Sub)),
    ("MUL", &["Source A", "Source B", "Dest"], Op::Binary(BinaryOp::Mul)),
    ("DIV", &["Source A", "Source B", "Dest"], Op::Binary(BinaryOp::Div)),
    ("MOD", &["Source A", "Source B", "Dest"], Op::Binary(BinaryOp::Mod)),
    ("NEG", &["Source", "Dest"], Op::Neg),
    ("ABS", &["Source", "Dest"], Op::Abs),
    ("SQR", &["Source", "Dest"], Op::Sqr),
    ("SIN", &["Source", "Dest"], Op::Function("SIN")),
    ("COS", &["Source", "Dest"], Op::Function("COS")),
    ("TAN", &["Source", "Dest"], Op::Function("TAN")),
    ("ASN", &["Source", "Dest"], Op::Function("ASIN")),
    ("ACS", &["Source", "Dest"], Op::Function("ACOS")),
    ("ATN", &["Source", "Dest"], Op::Function("ATAN")),
    ("LN", &["Source", "Dest"], Op::Function("LN")),
    ("LOG", &["Source", "Dest"], Op::Function("LOG")),
    ("DEG", &["Source", "Dest"], Op::Function("DEG")),
    ("RAD", &["Source", "Dest"], Op::Function("RAD")),
    ("TRN", &["Source", "Dest"], Op::Function("TRUNC")),
    ("TOD", &["Source", "Dest"], Op::Function("TOD")),
    ("FRD", &["Source", "Dest"], Op::Function("FRD")),
    ("XPY", &["Source X", "Source Y", "Dest"], Op::Binary(BinaryOp::Pow)),
    ("CPT", &["Dest", "Expression"], Op::Cpt),
    ("MOV", &["Source", "Dest"], Op::Mov),
    ("MVM", &["Source", "Mask", "Dest"], Op::Mvm),
    ("CLR", &["Dest"], Op::Clr),
    ("AND", &["Source A", "Source B", "Dest"], Op::Binary(BinaryOp::And)),
    ("OR", &["Source A", "Source B", "Dest"], Op::Binary(BinaryOp::Or)),
    ("XOR", &["Source A", "Source B", "Dest"], Op::Binary(BinaryOp::Xor)),
    ("NOT", &["Source", "Dest"], Op::Not),
    ("SWPB", &["Source", "Order Mode", "Dest"], Op::Swpb),
    ("BTD", &["Source", "Source Bit", "Dest", "Dest Bit", "Length"], Op::Btd),
    ("BSL", &["Array", "Control", "Source Bit", "Length"], Op::Shift(true)),
    ("BSR", &["Array", "Control", "Source Bit", "Length"], Op::Shift(false)),
    (
        "FFL",
        &["Source", "FIFO", "Control", "Length", "Position"],
        Op::Stack(StackKind::FifoLoad),
    ),
    (
        "FFU",
        &["FIFO", "Dest", "Control", "Length", "Position"],
        Op::Stack(StackKind::FifoUnload),
    ),
    (
        "LFL",
        &["Source", "LIFO", "Control", "Length", "Position"],
        Op::Stack(StackKind::LifoLoad),
    ),
    (
        "LFU",
        &["LIFO", "Dest", "Control", "Length", "Position"],
        Op::Stack(StackKind::LifoUnload),
    ),
    ("JSR", &[], Op::General),
    ("SBR", &[], Op::General),
    ("RET", &[], Op::General),
    ("COP", &[], Op::General),
    ("CPS", &[], Op::General),
    ("FLL", &[], Op::General),
    ("SIZE", &[], Op::General),
    ("GSV", &[], Op::General),
    ("SSV", &[], Op::General),
    ("EVENT", &[], Op::General),
    ("CONCAT", &[], Op::General),
    ("MID", &[], Op::General),
    ("FIND", &[], Op::General),
    ("INSERT", &[], Op::General),
    ("DELETE", &[], Op::General),
    ("UPPER", &[], Op::General),
    ("LOWER", &[], Op::General),
    ("DTOS", &[], Op::General),
    ("STOD", &[], Op::General),
    ("RTOS", &[], Op::General),
    ("STOR", &[], Op::General),
    ("JMP", &["Label Name"], Op::Jmp),
    ("LBL", &["Label Name"], Op::Lbl),
    ("TND", &[], Op::Tnd),
    ("MCR", &[], Op::Mcr),
    ("AFI", &[], Op::Afi),
    ("NOP", &[], Op::Nop),
];

/// Ladder instructions of the Logix set the twin does not simulate: named
/// in the refusal as such rather than as unknown.
pub const LADDER_NOT_SIMULATED: &[&str] = &[
    "MSG", "PID", "PIDE", "SQO", "SQI", "SQL", "FAL", "FSC", "FBC", "DDT", "DTR", "AVE", "SRT", "STD", "FOR", "BRK",
    "UID", "UIE", "IOT", "SFP", "SFR", "ALM", "SCL", "SCRV", "TONR", "TOFR", "RTOR", "CTUD", "OSRI", "OSFI", "JXR",
    "ABL", "ACB", "ACL", "AHL", "ARD", "ARL", "AWA", "AWT", "CPM", "TRND", "DEDT", "LDLG", "LDL2", "HPF", "LPF",
    "NTCH", "INTG", "PI", "PMUL", "SOC", "UPDN", "MAVE", "MAXC", "MINC", "MSTD", "RESD", "SETD", "TOT", "DFF", "JKFF",
    "SSUM", "ESEL", "HLL", "RLIM", "SEL", "SNEG", "MUX", "CC", "IMC", "MMC", "RMPS", "POSP", "SRTP", "FGEN",
];

/// The operands a ladder instruction writes (by index), for the check
/// that an Add-On Instruction writes no constant InOut parameter.
#[must_use]
pub fn written_operands(name: &str) -> &'static [usize] {
    let Some((_, _, op)) = find(name) else { return &[] };
    match op {
        Op::Output(_) | Op::Ons | Op::Res | Op::Clr => &[0],
        Op::Edge(_) => &[0, 1],
        Op::Timer(_) | Op::Counter(_) => &[0],
        Op::Binary(_) | Op::Mvm | Op::Swpb | Op::Btd => &[2],
        Op::Neg | Op::Abs | Op::Sqr | Op::Function(_) | Op::Not | Op::Mov => &[1],
        Op::Cpt => &[0],
        Op::Shift(_) => &[0, 1],
        Op::Stack(StackKind::FifoLoad | StackKind::LifoLoad) => &[1, 2],
        Op::Stack(_) => &[0, 1, 2],
        _ => &[],
    }
}

/// The ladder instruction called `name` (case-insensitive).
#[must_use]
pub fn find(name: &str) -> Option<&'static (&'static str, &'static [&'static str], Op)> {
    LADDER.iter().find(|(n, ..)| n.eq_ignore_ascii_case(name))
}

/// A jump waiting for its label's statement.
struct Pending {
    stmt: usize,
    label: String,
    span: Span,
}

impl Compiler<'_, '_, '_> {
    /// Compiles a ladder routine's rungs.
    ///
    /// # Errors
    /// The first compile error, pointing into the rung.
    pub fn rungs(&mut self, rungs: &[Rung]) -> Result<Vec<CStmt>> {
        self.ladder = true;
        let mut out: Vec<CStmt> = Vec::with_capacity(rungs.len() * 4);
        let mut labels: Vec<(String, usize, Span)> = Vec::new();
        let mut jumps: Vec<Pending> = Vec::new();
        for rung in rungs {
            let line = self.env.files.line(rung.span) as u32;
            let start = out.len();
            out.push(CStmt {
                kind: SKind::Ladder(Box::new(Ladder::Start(rung.number))),
                line,
            });
            for (k, e) in rung.elements.iter().enumerate() {
                if let Element::Instruction(call) = e
                    && call.name.eq_ignore_ascii_case("LBL")
                {
                    if k != 0 {
                        return err(self, call.span, "LBL must be the rung's first instruction");
                    }
                    let label = self.label(call)?;
                    if let Some((_, _, first)) = labels.iter().find(|(l, ..)| l.eq_ignore_ascii_case(&label.0)) {
                        let first = *first;
                        return Err(Box::new(
                            (*self.error(call.span, format!("label {} is defined twice", label.0), "again here"))
                                .with_label(self.env.files.label(first, "first here")),
                        ));
                    }
                    labels.push((label.0, start, call.span));
                }
            }
            self.elements(&rung.elements, &mut out, &mut jumps, line)?;
            let traced = self
                .traced_rungs
                .iter()
                .find(|(n, _)| *n == rung.number)
                .map(|(_, slot)| *slot);
            out.push(CStmt {
                kind: SKind::Ladder(Box::new(Ladder::End(traced))),
                line,
            });
        }
        for j in jumps {
            let Some((_, at, _)) = labels.iter().find(|(l, ..)| l.eq_ignore_ascii_case(&j.label)) else {
                return err(
                    self,
                    j.span,
                    format!("JMP to {}: no LBL {} in this routine", j.label, j.label),
                );
            };
            out[j.stmt].kind = SKind::Ladder(Box::new(Ladder::Jmp(*at)));
        }
        out.shrink_to_fit();
        Ok(out)
    }

    fn elements(
        &mut self,
        elements: &[Element],
        out: &mut Vec<CStmt>,
        jumps: &mut Vec<Pending>,
        line: u32,
    ) -> Result<()> {
        let push = |out: &mut Vec<CStmt>, l: Ladder| {
            out.push(CStmt {
                kind: SKind::Ladder(Box::new(l)),
                line,
            });
        };
        for e in elements {
            match e {
                Element::Instruction(call) => {
                    self.plain_operands(call)?;
                    let line = self.env.files.line(call.span) as u32;
                    if find(&call.name).is_none()
                        && let Some(aoi) = self.find_aoi(&call.name)
                    {
                        for kind in self.aoi_call(aoi, call, true)? {
                            out.push(CStmt { kind, line });
                        }
                        continue;
                    }
                    if let Some(op) = self.instruction(call, out.len(), jumps)? {
                        out.push(CStmt { kind: op, line });
                    }
                }
                Element::Branch(legs, _) => {
                    push(out, Ladder::Open);
                    for (k, leg) in legs.iter().enumerate() {
                        if k > 0 {
                            push(out, Ladder::Leg);
                        }
                        self.elements(leg, out, jumps, line)?;
                    }
                    push(out, Ladder::Close);
                }
            }
        }
        Ok(())
    }

    /// One instruction; `None` for one that does nothing (NOP, LBL).
    fn instruction(&mut self, call: &Call, at: usize, jumps: &mut Vec<Pending>) -> Result<Option<SKind>> {
        let Some(&(name, operands, op)) = find(&call.name) else {
            if planner::task::instructions::find(&call.name).is_some() {
                return match self.call(call)? {
                    SKind::Motion(m) => Ok(Some(ladder(Ladder::Motion(m)))),
                    other => Ok(Some(ladder(Ladder::OnTrue(other)))),
                };
            }
            return Err(self.unknown_rung_instruction(call));
        };
        if op == Op::General {
            // Checked against Structured Text's own operand rules.
            if General::find(name).is_none() {
                return Err(self.unknown_rung_instruction(call));
            }
            return Ok(Some(ladder(Ladder::OnTrue(self.call(call)?))));
        }
        self.argc(call, name, operands.len())?;
        let a = &call.args;
        let l = match op {
            Op::Examine(on) => {
                let c = self.bit(&a[0], name)?;
                Ladder::Examine(if on {
                    c
                } else {
                    CExpr {
                        kind: crate::program::ir::CKind::Not(Box::new(c)),
                        ty: Ty::Bool,
                    }
                })
            }
            Op::Output(kind) => Ladder::Output(kind, self.bit_target(&a[0], name)?),
            Op::Ons => Ladder::Ons(self.bit_target(&a[0], name)?),
            Op::Edge(rising) => Ladder::Edge {
                rising,
                storage: self.bit_target(&a[0], name)?,
                output: self.bit_target(&a[1], name)?,
            },
            Op::Timer(kind) => {
                let inst = self.instance(&a[0], &[Structure::LadderTimer], name)?;
                self.display(&inst, &a[1], LT_PRE, "Preset")?;
                self.display(&inst, &a[2], LT_ACC, "Accum")?;
                Ladder::Timer(kind, inst)
            }
            Op::Counter(up) => {
                let inst = self.instance(&a[0], &[Structure::LadderCounter], name)?;
                self.display(&inst, &a[1], LC_PRE, "Preset")?;
                self.display(&inst, &a[2], LC_ACC, "Accum")?;
                Ladder::Counter(up, inst)
            }
            Op::Res => Ladder::Res(self.instance(
                &a[0],
                &[Structure::LadderTimer, Structure::LadderCounter, Structure::Control],
                name,
            )?),
            Op::Compare(cmp) => {
                Ladder::Examine(self.condition(&binary(self.rung_operand(&a[0])?, cmp, self.rung_operand(&a[1])?))?)
            }
            Op::Lim => Ladder::Lim(self.number(&a[0])?, self.number(&a[1])?, self.number(&a[2])?),
            Op::Meq => {
                let (s, m, c) = (
                    self.rung_operand(&a[0])?,
                    self.rung_operand(&a[1])?,
                    self.rung_operand(&a[2])?,
                );
                let e = binary(
                    binary(s, BinaryOp::And, m.clone()),
                    BinaryOp::Eq,
                    binary(c, BinaryOp::And, m),
                );
                Ladder::Examine(self.condition(&e)?)
            }
            Op::Cmp => Ladder::Examine(self.condition(&self.expression(&a[0])?)?),
            Op::Binary(bop) => {
                let (x, y) = (self.rung_operand(&a[0])?, self.rung_operand(&a[1])?);
                let value = self.expr(&binary(x.clone(), bop, y.clone()))?;
                let carry = if matches!(bop, BinaryOp::Add | BinaryOp::Sub) && value.ty.is_integer() {
                    Some((bop == BinaryOp::Add, self.expr(&x)?, self.expr(&y)?))
                } else {
                    None
                };
                let flags = if carry.is_some() {
                    MATH_N | MATH_Z | MATH_V | MATH_C
                } else {
                    MATH_N | MATH_Z | MATH_V
                };
                self.compute(&a[2], value, flags, carry)?
            }
            Op::Neg => {
                let x = self.rung_operand(&a[0])?;
                let span = x.span;
                let value = self.expr(&Expr {
                    kind: ExprKind::Unary(UnaryOp::Neg, Box::new(x)),
                    span,
                })?;
                self.compute(&a[1], value, MATH_N | MATH_Z | MATH_V, None)?
            }
            Op::Abs | Op::Sqr | Op::Function(_) => {
                let x = self.rung_operand(&a[0])?;
                let f = match op {
                    Op::Abs => "ABS",
                    Op::Sqr => "SQRT",
                    Op::Function(f) => f,
                    _ => unreachable!("matched"),
                };
                let value = self.function(f, x)?;
                self.compute(&a[1], value, MATH_N | MATH_Z | MATH_V, None)?
            }
            Op::Not => {
                let x = self.rung_operand(&a[0])?;
                let span = x.span;
                let value = self.expr(&Expr {
                    kind: ExprKind::Unary(UnaryOp::Not, Box::new(x)),
                    span,
                })?;
                self.compute(&a[1], value, MATH_N | MATH_Z | MATH_V, None)?
            }
            Op::Cpt => {
                let value = self.expr(&self.expression(&a[1])?)?;
                self.compute(&a[0], value, MATH_N | MATH_Z | MATH_V, None)?
            }
            Op::Mov => {
                let value = self.expr(&self.rung_operand(&a[0])?)?;
                self.compute(&a[1], value, MATH_N | MATH_Z | MATH_V, None)?
            }
            Op::Mvm => {
                let (s, m) = (self.rung_operand(&a[0])?, self.rung_operand(&a[1])?);
                let d = self.rung_operand(&a[2])?;
                let span = m.span;
                let keep = Expr {
                    kind: ExprKind::Unary(UnaryOp::Not, Box::new(m.clone())),
                    span,
                };
                let e = binary(
                    binary(s, BinaryOp::And, m),
                    BinaryOp::Or,
                    binary(d, BinaryOp::And, keep),
                );
                let value = self.expr(&e)?;
                self.compute(&a[2], value, MATH_N | MATH_Z | MATH_V, None)?
            }
            Op::Clr => self.compute(&a[0], constant(Value::Int(0), Ty::Dint), MATH_N | MATH_Z | MATH_V, None)?,
            Op::Swpb => {
                let source = self.integer_arg(&a[0])?;
                let order = match a[1].text.to_ascii_uppercase().as_str() {
                    "REVERSE" => SwapOrder::Reverse,
                    "WORD" => SwapOrder::Word,
                    "HIGH/LOW" | "HIGHLOW" => SwapOrder::HighLow,
                    _ => {
                        return err(
                            self,
                            a[1].span,
                            format!("SWPB Order Mode '{}': expected REVERSE, WORD or HIGH/LOW", a[1].text),
                        );
                    }
                };
                let (dest, ty) = self.integer_target(&a[2], name)?;
                Ladder::Swpb(source, order, dest, ty)
            }
            Op::Btd => {
                let (dest, ty) = self.integer_target(&a[2], name)?;
                Ladder::Btd {
                    source: self.integer_arg(&a[0])?,
                    source_bit: self.integer_arg(&a[1])?,
                    dest,
                    ty,
                    dest_bit: self.integer_arg(&a[3])?,
                    length: self.integer_arg(&a[4])?,
                }
            }
            Op::Shift(left) => {
                let array = self.array_at(&a[0], "Array")?;
                if !array.ty.is_integer() || array.ty.bits() != 32 {
                    return err(
                        self,
                        a[0].span,
                        format!("{name} Array: expected a DINT array, got {}", array.ty.name()),
                    );
                }
                let control = self.instance(&a[1], &[Structure::Control], name)?;
                self.display(&control, &a[3], CT_LEN, "Length")?;
                Ladder::Shift {
                    left,
                    array,
                    control,
                    source: self.bit(&a[2], name)?,
                }
            }
            Op::Stack(kind) => {
                let load = matches!(kind, StackKind::FifoLoad | StackKind::LifoLoad);
                let (array_arg, other) = if load { (&a[1], &a[0]) } else { (&a[0], &a[1]) };
                let array = self.array_at(array_arg, if load { "FIFO" } else { "Dest" })?;
                let control = self.instance(&a[2], &[Structure::Control], name)?;
                self.display(&control, &a[3], CT_LEN, "Length")?;
                self.display(&control, &a[4], CT_POS, "Position")?;
                let value = if load {
                    StackValue::Load(self.value_arg(other)?)
                } else {
                    let (place, ty) = self.target_arg(other)?;
                    StackValue::Unload(place, ty)
                };
                Ladder::Stack {
                    kind,
                    array,
                    control,
                    value,
                }
            }
            Op::Jmp => {
                let (label, span) = self.label(call)?;
                jumps.push(Pending { stmt: at, label, span });
                Ladder::Tnd
            }
            Op::Lbl | Op::Nop => return Ok(None),
            Op::Tnd => Ladder::Tnd,
            Op::Mcr => Ladder::Mcr,
            Op::Afi => Ladder::Afi,
            Op::General => unreachable!("handled above"),
        };
        Ok(Some(ladder(l)))
    }

    fn label(&self, call: &Call) -> Result<(String, Span)> {
        self.argc(call, &call.name.to_ascii_uppercase(), 1)?;
        let a = &call.args[0];
        let ok = a
            .text
            .chars()
            .next()
            .is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
            && a.text.chars().all(|c| c.is_ascii_alphanumeric() || c == '_');
        if !ok {
            return err(self, a.span, format!("'{}' is not a label name", a.text));
        }
        Ok((a.text.clone(), a.span))
    }

    fn rung_operand(&self, a: &Arg) -> Result<Expr> {
        match &a.expr {
            Some(e) => Ok(e.clone()),
            None => Err(self.error(
                a.span,
                format!("'{}' is not an operand: expected a tag or a number", shorten(&a.text)),
                "not a tag or number",
            )),
        }
    }

    /// A ladder operand is a tag or a number (1756-RM003: Immediate or
    /// Tag); only CPT's and CMP's are expressions.
    fn plain_operands(&self, call: &Call) -> Result<()> {
        let upper = call.name.to_ascii_uppercase();
        let motion = planner::task::instructions::find(&call.name);
        for (k, a) in call.args.iter().enumerate() {
            if (upper == "CPT" && k == 1) || (upper == "CMP" && k == 0) || (upper == "SWPB" && k == 1) {
                continue;
            }
            // An enumeration word that reads as an expression (`S-Curve`).
            if motion
                .and_then(|m| m.operands.get(k))
                .is_some_and(|spec| spec.code_of(a.text.trim()).is_some())
            {
                continue;
            }
            let plain = match &a.expr {
                None => true,
                Some(e) => match &e.kind {
                    ExprKind::Ref(_) | ExprKind::Int(_) | ExprKind::Real(_) | ExprKind::Bool(_) => true,
                    ExprKind::Unary(UnaryOp::Neg, x) => matches!(x.kind, ExprKind::Int(_) | ExprKind::Real(_)),
                    _ => false,
                },
            };
            if !plain {
                return err(
                    self,
                    a.span,
                    format!(
                        "{upper}'s operand '{}' is an expression: a ladder operand is a tag or a number (compute it first with CPT)",
                        shorten(&a.text)
                    ),
                );
            }
        }
        Ok(())
    }

    /// A CPT or CMP expression, with the ladder function names (`SQR`,
    /// `ACS`, `ASN`, `ATN`, `TRN`) as their Structured Text functions.
    fn expression(&self, a: &Arg) -> Result<Expr> {
        let mut e = self.rung_operand(a)?;
        rename_functions(&mut e);
        Ok(e)
    }

    fn number(&mut self, a: &Arg) -> Result<CExpr> {
        let c = self.expr(&self.rung_operand(a)?)?;
        if c.ty == Ty::Bool {
            return err(self, a.span, format!("'{}': expected a number, got BOOL", a.text));
        }
        Ok(c)
    }

    fn function(&mut self, name: &str, x: Expr) -> Result<CExpr> {
        let span = x.span;
        self.expr(&Expr {
            kind: ExprKind::Function(name.to_owned(), span, vec![x]),
            span,
        })
    }

    /// A bit an input instruction examines: a BOOL or a bit of an integer.
    fn bit(&mut self, a: &Arg, name: &str) -> Result<CExpr> {
        let c = self.expr(&self.rung_operand(a)?)?;
        if c.ty != Ty::Bool {
            return err(
                self,
                a.span,
                format!(
                    "{name} '{}': expected a BOOL or a bit (Tag.5), got {}",
                    a.text,
                    c.ty.name()
                ),
            );
        }
        Ok(c)
    }

    /// A bit an instruction writes.
    fn bit_target(&mut self, a: &Arg, name: &str) -> Result<Place> {
        let (place, ty) = self.target_arg(a)?;
        if ty != DataType::Bool {
            return err(
                self,
                a.span,
                format!(
                    "{name} '{}': expected a BOOL or a bit (Tag.5), got {}",
                    a.text,
                    ty.name()
                ),
            );
        }
        Ok(place)
    }

    fn integer_target(&mut self, a: &Arg, name: &str) -> Result<(Place, DataType)> {
        let (place, ty) = self.target_arg(a)?;
        if !ty.is_integer() {
            return err(
                self,
                a.span,
                format!("{name} '{}': expected an integer tag, got {}", a.text, ty.name()),
            );
        }
        Ok((place, ty))
    }

    fn compute(&mut self, dest: &Arg, value: CExpr, flags: u8, carry: Option<(bool, CExpr, CExpr)>) -> Result<Ladder> {
        let (target, ty) = self.target_arg(dest)?;
        if ty == DataType::Bool && value.ty != Ty::Bool {
            return err(
                self,
                dest.span,
                format!("Dest '{}' is a BOOL: expected a number", dest.text),
            );
        }
        Ok(Ladder::Compute {
            target,
            ty,
            value,
            flags,
            carry,
        })
    }

    /// A display operand: `?`, or a number the member `offset` of the
    /// structure takes at load.
    fn display(&mut self, inst: &Instance, a: &Arg, offset: usize, what: &str) -> Result<()> {
        if a.text == "?" {
            return Ok(());
        }
        let value = match &a.expr {
            Some(Expr {
                kind: ExprKind::Int(i), ..
            }) => i64::try_from(*i).ok().filter(|v| i32::try_from(*v).is_ok()),
            Some(Expr {
                kind: ExprKind::Unary(UnaryOp::Neg, inner),
                ..
            }) => match inner.kind {
                ExprKind::Int(i) => i64::try_from(-i).ok().filter(|v| i32::try_from(*v).is_ok()),
                _ => None,
            },
            _ => None,
        };
        let Some(v) = value else {
            return err(
                self,
                a.span,
                format!(
                    "{what} '{}': a display value, '?' or a whole number (the instruction uses the structure's member)",
                    a.text
                ),
            );
        };
        if inst.index.is_none() && inst.terms.is_empty() {
            self.init.push((inst.base + offset, Value::Int(v), a.span));
        }
        Ok(())
    }

    fn unknown_rung_instruction(&self, call: &Call) -> super::Error {
        let upper = call.name.to_ascii_uppercase();
        if LADDER_NOT_SIMULATED.contains(&upper.as_str())
            || planner::task::instructions::NOT_SIMULATED.contains(&upper.as_str())
        {
            return self.error(
                call.name_span,
                format!("{upper} is a Logix instruction the twin does not simulate in ladder"),
                "not simulated",
            );
        }
        let d = self.error(
            call.name_span,
            format!("unknown ladder instruction '{}'", call.name),
            "not an instruction the twin knows",
        );
        let known = LADDER
            .iter()
            .map(|(n, ..)| *n)
            .chain(planner::task::instructions::INSTRUCTIONS.iter().map(|i| i.mnemonic));
        super::suggest(d, &call.name, known)
    }
}

/// An error inside a ladder routine, naming its rung (`Cell/Main rung
/// 12`) besides its file, line and column.
pub(super) fn in_rung(
    d: super::Error,
    rungs: &[crate::st::ast::Rung],
    files: &crate::source::Files,
    program: &str,
    routine: &str,
) -> super::Error {
    if d.field.is_some() {
        return d;
    }
    let Some(label) = d.labels.first() else { return d };
    let at = label.range.start as u32;
    let rung = rungs
        .iter()
        .find(|r| files.path(r.span.file) == label.file.path.as_path() && (r.span.start..=r.span.end).contains(&at));
    match rung {
        Some(r) => Box::new((*d).in_field(format!("{program}/{routine} rung {}", r.number))),
        None => d,
    }
}

/// An operand's text for a message: at most 60 characters.
fn shorten(text: &str) -> String {
    match text.char_indices().nth(60) {
        Some((i, _)) => format!("{}…", &text[..i]),
        None => text.to_owned(),
    }
}

fn ladder(l: Ladder) -> SKind {
    SKind::Ladder(Box::new(l))
}

fn binary(a: Expr, op: BinaryOp, b: Expr) -> Expr {
    let span = a.span.to(b.span);
    Expr {
        kind: ExprKind::Binary(Box::new(a), vec![(op, b)]),
        span,
    }
}

/// The ladder spellings of the functions, as Structured Text names them.
fn rename_functions(e: &mut Expr) {
    match &mut e.kind {
        ExprKind::Function(name, _, args) => {
            let st = match name.to_ascii_uppercase().as_str() {
                "SQR" => Some("SQRT"),
                "ACS" => Some("ACOS"),
                "ASN" => Some("ASIN"),
                "ATN" => Some("ATAN"),
                "TRN" => Some("TRUNC"),
                _ => None,
            };
            if let Some(st) = st {
                *name = st.to_owned();
            }
            for a in args {
                rename_functions(a);
            }
        }
        ExprKind::Unary(_, a) => rename_functions(a),
        ExprKind::Binary(first, rest) => {
            rename_functions(first);
            for (_, x) in rest {
                rename_functions(x);
            }
        }
        ExprKind::Int(_) | ExprKind::Real(_) | ExprKind::Bool(_) | ExprKind::Ref(_) => {}
    }
}
