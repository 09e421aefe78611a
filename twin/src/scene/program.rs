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

    /// The `[trace] rungs` entries: `Program/Routine:N`, each naming a rung
    /// of a ladder routine of a program of `tasks`.
    pub(super) fn trace_rungs(
        &self,
        raw: &[Spanned<String>],
        tasks: &[super::model::Task],
    ) -> Result<Vec<super::model::TraceRung>, SceneError> {
        let mut out: Vec<super::model::TraceRung> = Vec::with_capacity(raw.len());
        for (i, s) in raw.iter().enumerate() {
            let text = s.get_ref().trim();
            let bad = |why: String| {
                let problem = super::error::Problem::UnknownRung {
                    text: text.to_owned(),
                    why,
                };
                self.invalid(s, format!("trace.rungs[{i}]"), problem)
            };
            let Some((path, number)) = text.rsplit_once(':') else {
                return Err(bad("write Program/Routine:N (N the rung's number, from 0)".to_owned()));
            };
            let Some((program, routine)) = path.split_once('/') else {
                return Err(bad("write Program/Routine:N (N the rung's number, from 0)".to_owned()));
            };
            let Ok(rung) = number.trim().parse::<u32>() else {
                return Err(bad(format!("'{number}' is not a rung number")));
            };
            let Some(p) = tasks
                .iter()
                .flat_map(|t| &t.programs)
                .find(|p| p.name.eq_ignore_ascii_case(program))
            else {
                return Err(bad(format!("no program '{program}'")));
            };
            let Some(r) = std::iter::once(&p.main)
                .chain(&p.routines)
                .find(|r| r.name.eq_ignore_ascii_case(routine))
            else {
                return Err(bad(format!("program {} has no routine '{routine}'", p.name)));
            };
            let Some(rungs) = &r.routine.rungs else {
                return Err(bad(format!("{}/{} is Structured Text, not ladder", p.name, r.name)));
            };
            if rung as usize >= rungs.len() {
                return Err(bad(format!(
                    "{}/{} has {} rungs (0 to {})",
                    p.name,
                    r.name,
                    rungs.len(),
                    rungs.len().saturating_sub(1)
                )));
            }
            let entry = super::model::TraceRung {
                text: format!("{}/{}:{rung}", p.name, r.name),
                program: p.name.clone(),
                routine: r.name.clone(),
                rung,
            };
            if out.iter().any(|o| o.text == entry.text) {
                return Err(bad("traced twice".to_owned()));
            }
            out.push(entry);
        }
        Ok(out)
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
