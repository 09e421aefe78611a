//! Validation of the `[[program]]` steps: triggers, and every `call` and
//! `when` checked against the declared names and the instruction catalogue.

use toml::Spanned;

use crate::st::{self, Args, Call, Expr};
use planner::catalogue::{self, CallStyle, Instruction, Operand};

use super::{
    BaseType, Ctx, FunctionBlock, Location, NameKind, Names, Problem, RawStep, SceneError, Step, TagType, Trigger,
};

impl Ctx<'_> {
    pub(super) fn program(&self, raw: &[RawStep], duration_s: f64, names: &Names) -> Result<Vec<Step>, SceneError> {
        let mut steps = Vec::with_capacity(raw.len());
        for (i, s) in raw.iter().enumerate() {
            let f = |field: &str| format!("program[{i}].{field}");
            let trigger = match (&s.at_s, &s.when) {
                (Some(_), Some(when)) => {
                    return Err(self.invalid(when, f("when"), Problem::BothTriggers));
                }
                (None, None) => {
                    return Err(self.invalid(&s.call, format!("program[{i}]"), Problem::NoTrigger));
                }
                (Some(at), None) => {
                    if let Some(after) = &s.after_s {
                        return Err(self.invalid(after, f("after_s"), Problem::AfterWithoutWhen));
                    }
                    let time_s = self.non_negative(at, &f("at_s"))?;
                    if time_s > duration_s {
                        return Err(self.invalid(
                            at,
                            f("at_s"),
                            Problem::AfterEnd {
                                at_s: time_s,
                                duration_s,
                            },
                        ));
                    }
                    Trigger::At { time_s }
                }
                (None, Some(when)) => {
                    let condition = st::parse_condition(when.get_ref()).map_err(|e| self.syntax(when, f("when"), e))?;
                    self.check_reference(when, &condition, &f("when"), names)?;
                    let delay_s = match &s.after_s {
                        Some(after) => self.non_negative(after, &f("after_s"))?,
                        None => 0.0,
                    };
                    Trigger::When {
                        condition: condition.value,
                        delay_s,
                    }
                }
            };
            let call = st::parse_call(s.call.get_ref()).map_err(|e| self.syntax(&s.call, f("call"), e))?;
            self.check_call(&s.call, &call, &f("call"), names)?;
            let spans: Vec<st::Span> = match &call.args {
                Args::Positional(operands) => operands.iter().map(|o| o.span).collect(),
                Args::Named(inputs) => inputs.iter().map(|(_, value)| value.span).collect(),
            };
            let operand_locations = spans
                .iter()
                .map(|span| self.string_location(&s.call, span.column()))
                .collect();
            steps.push(Step {
                trigger,
                call,
                call_text: s.call.get_ref().clone(),
                location: self.loc(&s.call),
                operand_locations,
            });
        }
        Ok(steps)
    }

    /// Errors for a name inside a `call`/`when` string at `span` (characters).
    pub(super) fn invalid_in(
        &self,
        text: &Spanned<String>,
        span: st::Span,
        field: &str,
        problem: Problem,
    ) -> SceneError {
        let Location { line, column } = self.string_location(text, span.column());
        SceneError::Invalid {
            file: self.file.clone(),
            line,
            column,
            field: field.to_owned(),
            problem,
        }
    }

    /// Checks that a reference's root names a tag or axis, and that a direct
    /// index into an array tag is in bounds.
    pub(super) fn check_reference(
        &self,
        text: &Spanned<String>,
        expr: &st::Spanned<Expr>,
        field: &str,
        names: &Names,
    ) -> Result<(), SceneError> {
        let Some(root) = expr.value.root_ident() else {
            return Ok(());
        };
        let Some((_, kind)) = names.get(&root.to_lowercase()) else {
            return Err(self.invalid_in(text, expr.span, field, Problem::UnknownTag { name: root.to_owned() }));
        };
        if let (
            Expr::Index(base, index),
            NameKind::Tag(TagType {
                array_len: Some(len), ..
            }),
        ) = (&expr.value, kind)
            && matches!(**base, Expr::Ident(_))
            && usize::try_from(*index).map_or(true, |i| i >= *len)
        {
            let problem = Problem::IndexOutOfBounds {
                name: root.to_owned(),
                index: *index,
                len: *len,
            };
            return Err(self.invalid_in(text, expr.span, field, problem));
        }
        Ok(())
    }

    /// Checks a call against the instruction catalogue: a positional call
    /// names a simulated Logix instruction and has its operand count, a
    /// named call names an instance of a function-block tag and inputs the
    /// block has, and every bare-word operand is a declared tag/axis or one
    /// of *that operand's* enumeration words.
    pub(super) fn check_call(
        &self,
        text: &Spanned<String>,
        call: &Call,
        field: &str,
        names: &Names,
    ) -> Result<(), SceneError> {
        match &call.args {
            Args::Named(inputs) => {
                let block = self.function_block(text, &call.name, field, names)?;
                let instruction = catalogue::find(block.name());
                for (input, value) in inputs {
                    let operand = match instruction {
                        Some(i) => Some(self.input(text, i, input, field)?),
                        None => None,
                    };
                    self.check_operand(text, value, operand, field, names)?;
                }
            }
            Args::Positional(operands) => {
                let instruction = self.positional_instruction(text, &call.name, field, names)?;
                if operands.len() != instruction.operands.len() {
                    let problem = Problem::OperandCount {
                        instruction,
                        got: operands.len(),
                    };
                    let at = operands
                        .get(instruction.operands.len())
                        .map_or(call.name.span, |extra| extra.span);
                    return Err(self.invalid_in(text, at, field, problem));
                }
                for (value, operand) in operands.iter().zip(instruction.operands) {
                    self.check_operand(text, value, Some(operand), field, names)?;
                }
            }
        }
        Ok(())
    }

    /// The function block a named call's instance tag holds.
    fn function_block(
        &self,
        text: &Spanned<String>,
        name: &st::Spanned<String>,
        field: &str,
        names: &Names,
    ) -> Result<FunctionBlock, SceneError> {
        let written = &name.value;
        let problem = match names.get(&written.to_lowercase()) {
            Some((
                _,
                NameKind::Tag(TagType {
                    base: BaseType::FunctionBlock(block),
                    ..
                }),
            )) => return Ok(*block),
            Some((_, other)) => Problem::NotCallable {
                name: written.clone(),
                kind: kind_of(*other),
            },
            None if is_not_simulated(written) => Problem::NotSimulated {
                name: written.to_ascii_uppercase(),
                simulated: catalogue::positional_mnemonics(),
            },
            None if catalogue::find(written).is_some_and(|i| i.style == CallStyle::Positional) => {
                Problem::NamedLogixCall { name: written.clone() }
            }
            None => Problem::UnknownTag { name: written.clone() },
        };
        Err(self.invalid_in(text, name.span, field, problem))
    }

    /// The catalogue's description of a named input of `block`.
    fn input(
        &self,
        text: &Spanned<String>,
        block: &'static Instruction,
        input: &st::Spanned<String>,
        field: &str,
    ) -> Result<&'static Operand, SceneError> {
        block.operand(&input.value).map(|(_, o)| o).ok_or_else(|| {
            let problem = Problem::UnknownInput {
                name: input.value.clone(),
                block,
            };
            self.invalid_in(text, input.span, field, problem)
        })
    }

    /// The catalogue entry of a positional call's instruction.
    fn positional_instruction(
        &self,
        text: &Spanned<String>,
        name: &st::Spanned<String>,
        field: &str,
        names: &Names,
    ) -> Result<&'static Instruction, SceneError> {
        let written = &name.value;
        if let Some(instruction) = catalogue::find(written).filter(|i| i.style == CallStyle::Positional) {
            return Ok(instruction);
        }
        let problem = if is_not_simulated(written) {
            Problem::NotSimulated {
                name: written.to_ascii_uppercase(),
                simulated: catalogue::positional_mnemonics(),
            }
        } else if let Some((_, kind)) = names.get(&written.to_lowercase()) {
            Problem::NotAnInstruction {
                name: written.clone(),
                kind: kind_of(*kind),
            }
        } else {
            Problem::UnknownInstruction { name: written.clone() }
        };
        Err(self.invalid_in(text, name.span, field, problem))
    }

    /// Checks one operand: a bare word is a declared tag/axis or one of the
    /// operand's words; a reference names a declared tag within bounds.
    /// `operand` is `None` for the inputs of a block the catalogue does not
    /// describe (the binding refuses the block); such a word must be a
    /// declared name.
    fn check_operand(
        &self,
        text: &Spanned<String>,
        expr: &st::Spanned<Expr>,
        operand: Option<&'static Operand>,
        field: &str,
        names: &Names,
    ) -> Result<(), SceneError> {
        let Expr::Ident(word) = &expr.value else {
            return self.check_reference(text, expr, field, names);
        };
        if names.contains_key(&word.to_lowercase()) || operand.is_some_and(|o| o.code_of(word).is_some()) {
            return Ok(());
        }
        // A word that cannot be an enumeration value is read as a tag name.
        let has_words = operand.is_some_and(|o| !o.kind.words().is_empty());
        let problem = match operand {
            Some(o) if has_words || word.get(..3).is_some_and(|p| p.eq_ignore_ascii_case("MC_")) => {
                Problem::UnknownOperand {
                    name: word.clone(),
                    operand: o,
                }
            }
            _ => Problem::UnknownTag { name: word.clone() },
        };
        Err(self.invalid_in(text, expr.span, field, problem))
    }
}

/// What a declared name is, for messages (`an axis`, `a REAL[2] tag`).
fn kind_of(kind: NameKind) -> String {
    match kind {
        NameKind::Axis => "an axis".to_owned(),
        NameKind::Tag(ty) => format!("a {ty} tag"),
    }
}

/// Whether `name` is a Logix motion instruction the twin does not simulate.
fn is_not_simulated(name: &str) -> bool {
    catalogue::NOT_SIMULATED.iter().any(|m| m.eq_ignore_ascii_case(name))
}
