//! Validation of the `[[program]]` steps: their triggers, and every `call`
//! and `when` parsed with the Structured Text front-end (the program stage
//! compiles them against the tags, axes and instruction catalogue, so a
//! wrong name or operand is reported at load with its place in the
//! string).

use toml::Spanned;

use super::context::Ctx;
use super::error::{Problem, SceneError};
use super::model::{Step, Trigger};
use super::raw::RawStep;
use crate::st::parse::{parse_call, parse_expression};

impl Ctx<'_> {
    pub(super) fn program(&self, raw: &[RawStep], duration_s: f64) -> Result<Vec<Step>, SceneError> {
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
                    let condition = self.parse_in(when, &f("when"), parse_expression)?;
                    let delay_s = match &s.after_s {
                        Some(after) => self.non_negative(after, &f("after_s"))?,
                        None => 0.0,
                    };
                    Trigger::When { condition, delay_s }
                }
            };
            let call = self.parse_in(&s.call, &f("call"), parse_call)?;
            steps.push(Step {
                trigger,
                call,
                location: self.loc(&s.call),
            });
        }
        Ok(steps)
    }

    /// The `[trace] tags` entries, parsed.
    pub(super) fn trace_tags(&self, raw: &[Spanned<String>]) -> Result<Vec<super::model::TraceTag>, SceneError> {
        raw.iter()
            .enumerate()
            .map(|(i, s)| {
                let expr = self.parse_in(s, &format!("trace.tags[{i}]"), parse_expression)?;
                Ok(super::model::TraceTag {
                    text: s.get_ref().trim().to_owned(),
                    expr,
                })
            })
            .collect()
    }
}
