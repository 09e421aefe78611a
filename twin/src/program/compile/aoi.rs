//! Add-On Instruction calls (1756-PM010), in ladder `Valve(V101,Coil)` and
//! in Structured Text `Valve(V101, Coil);`: the instance, then the
//! required parameters in definition order (`EnableIn` and `EnableOut`
//! never appear); the others are set and read as the instance's members
//! (`V101.Timeout`).
//!
//! Each call site gets a routine of its own, appended to the program's
//! routines and entered like a `JSR`: the instruction's routines with
//! every parameter and local tag made the instance's member
//! (`Timeout` → `V101.Timeout`) and every InOut parameter the call's
//! argument (`Axis` → `Conv`), so an InOut is passed by reference and a
//! motion instruction inside runs on the caller's axis. The call site:
//!
//! 1. `EnableIn` := the rung condition (ladder) or TRUE (Structured Text);
//! 2. each required Input's argument copied into the instance;
//! 3. the routine: when `EnableIn`, `EnableOut` := TRUE and `Logic`;
//!    otherwise `EnableOut` := FALSE and, if the instruction executes it,
//!    `EnableInFalse`;
//! 4. each required Output copied out to its argument;
//! 5. ladder: the rung condition AND `EnableOut`.
//!
//! Verifier errors at load: a required parameter missing or `?`, an
//! argument of the wrong type, a write to a constant InOut, a JSR inside
//! an instruction, a name an instruction's routine uses that is none of
//! its parameters and local tags, nesting deeper than [`MAX_AOI_NESTING`],
//! an instruction that calls itself (directly or through others).

use super::{Compiler, Result, err, load};
use crate::program::ir::{AoiRoutine, CStmt, Ladder, OutputKind, SKind};
use crate::program::memory::Kind;
use crate::program::types::{DataType, Ty, Value};
use crate::scene::{AoiDef, AoiUsage};
use crate::source::Span;
use crate::st::ast::{Access, Call, Element, Expr, ExprKind, Ref, Routine};

/// The deepest an Add-On Instruction may call others (1756-PM010: eight
/// levels with the first).
pub const MAX_AOI_NESTING: usize = 7;

impl<'s> Compiler<'_, '_, 's> {
    /// The Add-On Instruction called `name`, if the scene has one.
    pub(super) fn find_aoi(&self, name: &str) -> Option<&'s AoiDef> {
        let scene: &'s crate::scene::Scene = self.env.scene;
        scene
            .add_on_instructions
            .iter()
            .find(|a| a.name.eq_ignore_ascii_case(name))
    }

    /// The statements of a call site (module doc).
    pub(super) fn aoi_call(&mut self, aoi: &AoiDef, call: &Call, ladder: bool) -> Result<Vec<SKind>> {
        if call.args.iter().any(|a| a.name.is_some()) {
            return err(
                self,
                call.span,
                format!(
                    "{} takes its instance and required parameters in order, without names",
                    aoi.name
                ),
            );
        }
        let required: Vec<_> = aoi.required().collect();
        if call.args.len() != required.len() + 1 {
            let missing: Vec<&str> = required
                .iter()
                .skip(call.args.len().saturating_sub(1))
                .map(|p| p.name.as_str())
                .collect();
            let names: Vec<&str> = required.iter().map(|p| p.name.as_str()).collect();
            let d = self.error(
                call.span,
                if missing.is_empty() {
                    format!(
                        "{} takes its instance and {} required parameter(s) ({}), got {} operands",
                        aoi.name,
                        required.len(),
                        names.join(", "),
                        call.args.len()
                    )
                } else {
                    format!(
                        "{} is missing its required parameter(s) {}: it takes the instance, then {}",
                        aoi.name,
                        missing.join(", "),
                        names.join(", ")
                    )
                },
                "",
            );
            return Err(d);
        }
        for (p, a) in required.iter().zip(&call.args[1..]) {
            if a.text == "?" {
                return err(
                    self,
                    a.span,
                    format!(
                        "{}'s required parameter {} is '?': give it a tag or a value",
                        aoi.name, p.name
                    ),
                );
            }
        }
        let instance = match &call.args[0].expr {
            Some(Expr {
                kind: ExprKind::Ref(r), ..
            }) => r.clone(),
            _ => {
                return err(
                    self,
                    call.args[0].span,
                    format!("{}'s first operand is its instance: a {} tag", aoi.name, aoi.name),
                );
            }
        };
        self.check_instance(aoi, &instance)?;
        let routine = self.aoi_routine(aoi, &instance, call)?;
        let member = |name: &str| member_ref(&instance, name, instance.span);
        let mut out = Vec::new();
        let (enable_in, _) = self.writable(&member("EnableIn"))?;
        out.push(if ladder {
            SKind::Ladder(Box::new(Ladder::Output(OutputKind::Energize, enable_in)))
        } else {
            SKind::Assign {
                target: enable_in,
                ty: DataType::Bool,
                value: super::constant(Value::Bool(true), Ty::Bool),
                retentive: true,
            }
        });
        let mut outputs = Vec::new();
        for (p, a) in required.iter().zip(&call.args[1..]) {
            match p.usage {
                AoiUsage::Input => {
                    let value = self.value_arg(a)?;
                    let bool_param = p.ty.is_some_and(|t| t.base == crate::scene::BaseType::Bool);
                    if value.ty.is_real() && bool_param {
                        return err(
                            self,
                            a.span,
                            format!("{}.{} is BOOL, got {}", aoi.name, p.name, value.ty.name()),
                        );
                    }
                    let (target, ty) = self.writable(&member(&p.name))?;
                    out.push(SKind::Assign {
                        target,
                        ty,
                        value,
                        retentive: true,
                    });
                }
                AoiUsage::Output => {
                    let (target, ty) = self.target_arg(a)?;
                    let (place, pty) = self.place(&member(&p.name))?;
                    outputs.push(SKind::Assign {
                        target,
                        ty,
                        value: load(place, pty),
                        retentive: true,
                    });
                }
                AoiUsage::InOut => {}
            }
        }
        out.push(SKind::Jsr {
            routine,
            inputs: Vec::new(),
            returns: Vec::new(),
        });
        out.extend(outputs);
        if ladder {
            let (place, ty) = self.place(&member("EnableOut"))?;
            out.push(SKind::Ladder(Box::new(Ladder::Examine(load(place, ty)))));
        }
        Ok(out)
    }

    /// The instance is a tag (or an element, a member) of the
    /// instruction's data type.
    fn check_instance(&mut self, aoi: &AoiDef, r: &Ref) -> Result<()> {
        let Some(k) = self.resolve(&r.name) else {
            return Err(self.unknown_name(&r.name, r.name_span()));
        };
        let info = &self.mem.tags[k];
        let simple = r.path.is_empty() || matches!(r.path.as_slice(), [Access::Index(_)]);
        if simple && !(info.kind == Kind::User(aoi.data_type.index) && (r.path.is_empty() == info.len.is_none())) {
            return err(
                self,
                r.span,
                format!(
                    "{}'s instance must be a {} tag, got {} ({})",
                    aoi.name, aoi.name, r.name, info.type_name
                ),
            );
        }
        Ok(())
    }

    /// Compiles the call site's routine: the instruction's routines
    /// rewritten for this instance and these arguments; its index in the
    /// program's routines.
    fn aoi_routine(&mut self, aoi: &AoiDef, instance: &Ref, call: &Call) -> Result<usize> {
        if self.aoi_stack.iter().any(|n| n.eq_ignore_ascii_case(&aoi.name)) {
            let chain = self.aoi_stack.join(" → ");
            return err(
                self,
                call.name_span,
                format!(
                    "Add-On Instruction {} calls itself ({chain} → {}): an instruction cannot be recursive",
                    aoi.name, aoi.name
                ),
            );
        }
        if self.aoi_stack.len() >= MAX_AOI_NESTING {
            return err(
                self,
                call.name_span,
                format!(
                    "Add-On Instructions nested deeper than {MAX_AOI_NESTING} levels ({} → {})",
                    self.aoi_stack.join(" → "),
                    aoi.name
                ),
            );
        }
        // Arguments by reference, checked.
        let mut inouts: Vec<(String, Ref, bool)> = Vec::new();
        let required: Vec<_> = aoi.required().collect();
        for (p, a) in required.iter().zip(&call.args[1..]) {
            if p.usage != AoiUsage::InOut {
                continue;
            }
            let Some(Expr {
                kind: ExprKind::Ref(r), ..
            }) = &a.expr
            else {
                return err(
                    self,
                    a.span,
                    format!(
                        "{}.{} is an InOut parameter: pass a tag, not '{}'",
                        aoi.name, p.name, a.text
                    ),
                );
            };
            self.check_inout(aoi, p, r, a.span)?;
            inouts.push((p.name.clone(), r.clone(), p.constant));
        }
        let k = self.aoi_base + self.aoi_routines.len();
        self.aoi_routines.push(AoiRoutine {
            path: aoi.logic.path.clone(),
            body: Vec::new(),
            prescan: false,
        });
        self.aoi_stack.push(aoi.name.clone());
        let result = (|| -> Result<Vec<CStmt>> {
            let logic = self.aoi_body(aoi, &aoi.logic, instance, &inouts)?;
            let otherwise = match &aoi.enable_in_false {
                Some(r) => self.aoi_body(aoi, r, instance, &inouts)?,
                None => Vec::new(),
            };
            let line = self.env.files.line(aoi.span) as u32;
            let member = |name: &str| member_ref(instance, name, aoi.span);
            let (enable_in, ty) = self.place(&member("EnableIn"))?;
            let (enable_out, _) = self.writable(&member("EnableOut"))?;
            let set_out = |on: bool| CStmt {
                kind: SKind::Assign {
                    target: enable_out.clone(),
                    ty: DataType::Bool,
                    value: super::constant(Value::Bool(on), Ty::Bool),
                    retentive: true,
                },
                line,
            };
            let mut then = vec![set_out(true)];
            then.extend(logic);
            let mut els = vec![set_out(false)];
            els.extend(otherwise);
            let mut body = vec![CStmt {
                kind: SKind::If(vec![(load(enable_in, ty), then)], els),
                line,
            }];
            body.shrink_to_fit();
            if let Some(p) = &aoi.prescan {
                let pre = self.aoi_body(aoi, p, instance, &inouts)?;
                self.aoi_routines.push(AoiRoutine {
                    path: p.path.clone(),
                    body: pre,
                    prescan: true,
                });
            }
            Ok(body)
        })();
        self.aoi_stack.pop();
        self.aoi_routines[k - self.aoi_base].body = result?;
        Ok(k)
    }

    /// One of the instruction's routines, rewritten and compiled.
    fn aoi_body(
        &mut self,
        aoi: &AoiDef,
        def: &crate::scene::RoutineDef,
        instance: &Ref,
        inouts: &[(String, Ref, bool)],
    ) -> Result<Vec<CStmt>> {
        // An error names the instruction's routine (and rung).
        let which = def.name.get(aoi.name.len() + 1..).unwrap_or(&def.name);
        let result = self.aoi_routine_body(aoi, &def.routine, instance, inouts);
        result.map_err(|d| match &def.routine.rungs {
            Some(rungs) => super::ladder::in_rung(d, rungs, self.env.files, &aoi.name, which),
            None if d.field.is_none() => Box::new((*d).in_field(format!("{}/{which}", aoi.name))),
            None => d,
        })
    }

    fn aoi_routine_body(
        &mut self,
        aoi: &AoiDef,
        routine: &Routine,
        instance: &Ref,
        inouts: &[(String, Ref, bool)],
    ) -> Result<Vec<CStmt>> {
        let mut r = routine.clone();
        // What the routine names: parameters and local tags only; no JSR;
        // no write to a constant InOut.
        for c in r.calls() {
            if c.name.eq_ignore_ascii_case("JSR") {
                return err(
                    self,
                    c.name_span,
                    format!(
                        "Add-On Instruction {}: JSR is not allowed inside an instruction",
                        aoi.name
                    ),
                );
            }
        }
        for (name, _, constant) in inouts {
            if *constant && let Some(span) = writes(&r, name) {
                return err(
                    self,
                    span,
                    format!(
                        "Add-On Instruction {}: {name} is a constant InOut parameter: the instruction may not write it",
                        aoi.name
                    ),
                );
            }
        }
        // An operand's enumeration word (`Trapezoidal`) is not a name.
        let words = &mut |c: &mut Call| {
            if let Some(ins) = planner::task::instructions::find(&c.name) {
                for (spec, a) in ins.operands.iter().zip(&mut c.args) {
                    if spec.code_of(a.text.trim()).is_some() {
                        a.expr = None;
                    }
                }
            }
        };
        crate::st::ast::calls_mut(&mut r.body, words);
        for rung in r.rungs.iter_mut().flatten() {
            Element::visit_mut(&mut rung.elements, words);
        }
        let mut bad: Option<(String, Span)> = None;
        let mut rewrite = |x: &mut Ref| {
            if bad.is_some() || x.name.starts_with("S:") || x.name.starts_with("s:") {
                return;
            }
            if let Some((_, arg, _)) = inouts.iter().find(|(n, ..)| n.eq_ignore_ascii_case(&x.name)) {
                let mut path = arg.path.clone();
                path.append(&mut x.path);
                *x = Ref {
                    name: arg.name.clone(),
                    path,
                    span: x.span,
                };
                return;
            }
            let own = ["EnableIn", "EnableOut"]
                .iter()
                .any(|n| n.eq_ignore_ascii_case(&x.name))
                || aoi
                    .parameters
                    .iter()
                    .any(|p| p.usage != AoiUsage::InOut && p.name.eq_ignore_ascii_case(&x.name))
                || aoi.locals.iter().any(|l| l.eq_ignore_ascii_case(&x.name));
            if !own {
                bad = Some((x.name.clone(), x.name_span()));
                return;
            }
            let mut path = instance.path.clone();
            path.push(Access::Member(x.name.clone(), x.name_span()));
            path.append(&mut x.path);
            *x = Ref {
                name: instance.name.clone(),
                path,
                span: x.span,
            };
        };
        crate::st::ast::refs_mut(&mut r.body, &mut rewrite);
        for rung in r.rungs.iter_mut().flatten() {
            Element::visit_mut(&mut rung.elements, &mut |c| {
                // An instruction's name is not a reference; a label is
                // not either.
                if c.name.eq_ignore_ascii_case("JMP") || c.name.eq_ignore_ascii_case("LBL") {
                    return;
                }
                c.refs_mut(&mut rewrite);
            });
        }
        if let Some((name, span)) = bad {
            return err(
                self,
                span,
                format!(
                    "Add-On Instruction {}: '{name}' is none of its parameters and local tags (an instruction reaches other tags through InOut parameters)",
                    aoi.name
                ),
            );
        }
        // Compile as the routine's own language, then restore the caller's.
        let (ladder, traced, loops) = (self.ladder, std::mem::take(&mut self.traced_rungs), self.loops);
        self.loops = 0;
        let out = match &r.rungs {
            Some(rungs) => self.rungs(rungs),
            None => {
                self.ladder = false;
                self.block(&r.body)
            }
        };
        self.ladder = ladder;
        self.traced_rungs = traced;
        self.loops = loops;
        out
    }

    /// An InOut argument: an axis for an axis parameter, else a tag of the
    /// parameter's type (a plain tag's type is checked; an element or a
    /// member is checked where the instruction uses it).
    fn check_inout(&mut self, aoi: &AoiDef, p: &crate::scene::AoiParam, r: &Ref, span: Span) -> Result<()> {
        let wrong = |c: &Self, got: &str| {
            err::<()>(
                c,
                span,
                format!("{}.{} is {}, got {} ({got})", aoi.name, p.name, p.data_type, r.name),
            )
        };
        let Some(k) = self.resolve(&r.name) else {
            return Err(self.unknown_name(&r.name, r.name_span()));
        };
        let info = &self.mem.tags[k];
        let is_axis = info.kind == Kind::Axis;
        if p.ty.is_none() {
            return if is_axis && r.path.is_empty() {
                Ok(())
            } else {
                wrong(self, info.type_name)
            };
        }
        if is_axis {
            return wrong(self, "an axis");
        }
        if r.path.is_empty() && !info.type_name.eq_ignore_ascii_case(&p.data_type) {
            return wrong(self, info.type_name);
        }
        Ok(())
    }
}

/// `base.member` (a member of the instance).
fn member_ref(base: &Ref, member: &str, span: Span) -> Ref {
    let mut path = base.path.clone();
    path.push(Access::Member(member.to_owned(), span));
    Ref {
        name: base.name.clone(),
        path,
        span,
    }
}

/// Where a routine writes `name` (an assignment's target, or an operand
/// a ladder instruction writes), if it does.
fn writes(r: &Routine, name: &str) -> Option<Span> {
    let named = |x: &Ref| x.name.eq_ignore_ascii_case(name);
    if let Some(t) = r.assignment_targets().into_iter().find(|t| named(t)) {
        return Some(t.span);
    }
    let mut found = None;
    for rung in r.rungs.iter().flatten() {
        Element::visit(&rung.elements, &mut |c| {
            if found.is_some() {
                return;
            }
            let dest = super::ladder::written_operands(&c.name);
            for &k in dest {
                if let Some(Expr {
                    kind: ExprKind::Ref(x), ..
                }) = c.args.get(k).and_then(|a| a.expr.as_ref())
                    && named(x)
                {
                    found = Some(x.span);
                }
            }
        });
    }
    found
}
