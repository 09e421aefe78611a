//! Ladder rungs: the rung condition carried from instruction to
//! instruction, as 1756-RM003's "Execution" tables give each
//! instruction's action on a TRUE and a FALSE rung-condition-in.
//!
//! A rung is a run of statements ([`Ladder::Start`] … [`Ladder::End`]),
//! each instruction one statement, so that a rung's `JSR` enters its
//! routine like a Structured Text call, the scan can stop between two
//! instructions for a higher-priority task, and the watchdog counts
//! instructions. [`Power`] is the rung's state: its condition, and for
//! each open branch the condition it started with and the OR of its
//! finished legs; a `JSR` keeps the caller's and the called routine starts
//! its own.
//!
//! Choices the reference leaves open, and what the twin does:
//! * timers measure whole milliseconds between executions, the remainder
//!   carried (as `TONR` does), and stop at `PRE`: `ACC` never passes it;
//! * a negative `PRE` or `ACC` at a timer's execution is major fault 4/34;
//! * `BSL`/`BSR`, `FFL`/`FFU`, `LFL`/`LFU` act on the rung's
//!   false-to-true transition (their `.EN`/`.EU` clear); an unload clears
//!   the element it vacates; a `LEN` larger than the array, or a
//!   negative `LEN` or `POS`, sets `.ER` and moves nothing;
//! * MCR zones do not span routines: a `JSR`'d routine starts outside any
//!   zone.

use super::power::{MAX_LEGS, Power, bit, with};
use super::{Exec, R};
use crate::program::ir::{
    ArrayAt, Ladder, MATH_C, MATH_N, MATH_V, MATH_Z, MotionCall, OutputKind, Place, StackKind, StackValue, SwapOrder,
    TimerKind,
};
use crate::program::types::{
    CT_DN, CT_EM, CT_EN, CT_ER, CT_EU, CT_LEN, CT_POS, CT_UL, DataType, LC_ACC, LC_CD, LC_CU, LC_DN, LC_OV, LC_PRE,
    LC_UN, LT_ACC, LT_DN, LT_EN, LT_LAST, LT_PRE, LT_TT, Structure, Ty, Value,
};
use planner::instruction::MotionInstructionBits;

impl Exec<'_> {
    /// Executes one ladder instruction.
    pub(super) fn ladder(&mut self, op: &Ladder) -> R<()> {
        let rc = self.power.rc;
        if matches!(
            op,
            Ladder::Start(_) | Ladder::End(_) | Ladder::Open | Ladder::Leg | Ladder::Close
        ) {
            // The rung's structure is not an instruction: it takes no time.
            self.steps -= 1;
            self.clock_ns -= self.statement_ns;
        }
        match op {
            Ladder::Start(_) => {
                self.power.rc = !self.power.mcr_off;
                self.power.depth = 0;
            }
            Ladder::End(trace) => {
                if let Some(slot) = trace {
                    self.mem.slots[*slot] = Value::Bool(rc);
                }
            }
            Ladder::Open => {
                let d = self.power.depth.min(MAX_LEGS - 1);
                self.power.starts = with(self.power.starts, d, rc);
                self.power.legs = with(self.power.legs, d, false);
                self.power.depth = d + 1;
            }
            Ladder::Leg => {
                let d = self.power.depth.saturating_sub(1);
                self.power.legs = with(self.power.legs, d, bit(self.power.legs, d) || rc);
                self.power.rc = bit(self.power.starts, d);
            }
            Ladder::Close => {
                let d = self.power.depth.saturating_sub(1);
                self.power.rc = bit(self.power.legs, d) || rc;
                self.power.depth = d;
            }
            Ladder::Examine(e) => {
                if rc {
                    let v = self.eval(e).truthy();
                    self.check()?;
                    self.power.rc = v;
                }
            }
            Ladder::Lim(low, test, high) => {
                if rc {
                    let (l, t, h) = (self.eval(low), self.eval(test), self.eval(high));
                    self.check()?;
                    self.power.rc = limit(l, t, h);
                }
            }
            Ladder::Afi => self.power.rc = false,
            Ladder::Output(kind, place) => match kind {
                OutputKind::Energize => self.write_bit(place, rc)?,
                OutputKind::Latch if rc => self.write_bit(place, true)?,
                OutputKind::Unlatch if rc => self.write_bit(place, false)?,
                OutputKind::Latch | OutputKind::Unlatch => {}
            },
            Ladder::Ons(storage) => {
                if rc {
                    let stored = self.load(storage).truthy();
                    self.check()?;
                    if stored {
                        self.power.rc = false;
                    } else {
                        self.write_bit(storage, true)?;
                    }
                } else {
                    self.write_bit(storage, false)?;
                }
            }
            Ladder::Edge {
                rising,
                storage,
                output,
            } => {
                let stored = self.load(storage).truthy();
                self.check()?;
                let (store, out) = match (rising, rc) {
                    (true, true) => (true, !stored),
                    (true, false) => (false, false),
                    (false, true) => (true, false),
                    (false, false) => (false, stored),
                };
                self.write_bit(storage, store)?;
                self.write_bit(output, out)?;
            }
            Ladder::Timer(kind, inst) => {
                let base = self.instance_base(inst);
                self.check()?;
                self.ladder_timer(*kind, base, rc, &inst.name)?;
            }
            Ladder::Counter(up, inst) => {
                let base = self.instance_base(inst);
                self.check()?;
                self.ladder_counter(*up, base, rc);
            }
            Ladder::Res(inst) => {
                if rc {
                    let base = self.instance_base(inst);
                    self.check()?;
                    reset(&mut self.mem.slots, base, inst.structure);
                }
            }
            Ladder::Compute {
                target,
                ty,
                value,
                flags,
                carry,
            } => {
                if rc {
                    self.overflowed = false;
                    let v = self.eval(value);
                    self.check()?;
                    let c = match carry {
                        Some((add, a, b)) => {
                            let (x, y) = (self.eval(a).as_i64(), self.eval(b).as_i64());
                            carried(*add, x, y, value.ty)
                        }
                        None => false,
                    };
                    let stored = ty.store(v).0;
                    self.store(target, *ty, v);
                    self.check()?;
                    let mut set = 0;
                    if stored.as_f64() < 0.0 {
                        set |= MATH_N;
                    }
                    if stored.as_f64() == 0.0 {
                        set |= MATH_Z;
                    }
                    if self.overflowed {
                        set |= MATH_V;
                    }
                    if c {
                        set |= MATH_C;
                    }
                    self.math_flags = (self.math_flags & !flags) | (set & flags);
                }
            }
            Ladder::Swpb(source, order, dest, ty) => {
                if rc {
                    let x = self.eval(source).as_i64();
                    self.check()?;
                    let swapped = swap(x, *order, ty.bits());
                    self.store(dest, *ty, Value::Int(swapped));
                    self.check()?;
                    self.set_nz(swapped as f64);
                }
            }
            Ladder::Btd {
                source,
                source_bit,
                dest,
                ty,
                dest_bit,
                length,
            } => {
                if rc {
                    let x = self.eval(source).as_i64();
                    let (sb, db, n) = (
                        self.eval(source_bit).as_i64(),
                        self.eval(dest_bit).as_i64(),
                        self.eval(length).as_i64(),
                    );
                    let old = self.load(dest).as_i64();
                    self.check()?;
                    let v = bit_distribute(x, sb, old, db, n, ty.bits());
                    self.store(dest, *ty, Value::Int(v));
                    self.check()?;
                }
            }
            Ladder::Motion(call) => self.transitional(call, rc)?,
            Ladder::Mcr => {
                if self.power.mcr_open {
                    self.power.mcr_open = false;
                    self.power.mcr_off = false;
                } else {
                    self.power.mcr_open = true;
                    self.power.mcr_off = !rc;
                }
            }
            Ladder::Shift {
                left,
                array,
                control,
                source,
            } => {
                let base = self.instance_base(control);
                self.check()?;
                self.shift(*left, array, base, source, rc)?;
            }
            Ladder::Stack {
                kind,
                array,
                control,
                value,
            } => {
                let base = self.instance_base(control);
                self.check()?;
                self.stack(*kind, array, base, value, rc)?;
            }
            Ladder::OnTrue(_) | Ladder::Jmp(_) | Ladder::Tnd => {
                unreachable!("control flow is executed by stmt")
            }
        }
        Ok(())
    }

    /// The rung condition now.
    pub(super) fn rung_condition(&self) -> bool {
        self.power.rc
    }

    /// The rung state, to keep across a routine call.
    pub(super) fn take_power(&mut self) -> Power {
        std::mem::take(&mut self.power)
    }

    /// Puts back the rung state a call kept.
    pub(super) fn restore_power(&mut self, p: Power) {
        self.power = p;
    }

    fn write_bit(&mut self, place: &Place, on: bool) -> R<()> {
        self.store(place, DataType::Bool, Value::Bool(on));
        self.check()
    }

    fn set_nz(&mut self, x: f64) {
        let mut set = 0;
        if x < 0.0 {
            set |= MATH_N;
        }
        if x == 0.0 {
            set |= MATH_Z;
        }
        self.math_flags = (self.math_flags & !(MATH_N | MATH_Z | MATH_V)) | set;
    }

    fn ladder_timer(&mut self, kind: TimerKind, base: usize, rc: bool, name: &str) -> R<()> {
        let slots = &mut self.mem.slots;
        let flag = |slots: &[Value], k: usize| slots[base + k].truthy();
        let on = |slots: &mut [Value], k: usize, v: bool| slots[base + k] = Value::Bool(v);
        let timing = match kind {
            TimerKind::On | TimerKind::Retentive => rc,
            TimerKind::Off => !rc,
        };
        if !timing {
            match kind {
                TimerKind::On => {
                    for k in [LT_EN, LT_TT, LT_DN] {
                        on(slots, k, false);
                    }
                    slots[base + LT_ACC] = Value::Int(0);
                }
                TimerKind::Retentive => {
                    on(slots, LT_EN, false);
                    on(slots, LT_TT, false);
                }
                TimerKind::Off => {
                    on(slots, LT_EN, true);
                    on(slots, LT_TT, false);
                    on(slots, LT_DN, true);
                    slots[base + LT_ACC] = Value::Int(0);
                }
            }
            return Ok(());
        }
        let (pre, mut acc) = (slots[base + LT_PRE].as_i64(), slots[base + LT_ACC].as_i64());
        if pre < 0 || acc < 0 {
            return Err(self.raise(4, 34, format!("timer {name}: negative PRE ({pre}) or ACC ({acc})")));
        }
        let slots = &mut self.mem.slots;
        on(slots, LT_EN, kind != TimerKind::Off);
        // TON and RTO time until done; TOF until it clears DN.
        let done = flag(slots, LT_DN);
        let running = if kind == TimerKind::Off { done } else { !done };
        if !running {
            on(slots, LT_TT, false);
            return Ok(());
        }
        if flag(slots, LT_TT) {
            let last = slots[base + LT_LAST].as_i64();
            let ms = (self.now_us - last).max(0) / 1000;
            slots[base + LT_LAST] = Value::Int(last + ms * 1000);
            acc = acc.saturating_add(ms);
        } else {
            on(slots, LT_TT, true);
            slots[base + LT_LAST] = Value::Int(self.now_us);
        }
        if acc >= pre {
            acc = pre;
            on(slots, LT_TT, false);
            on(slots, LT_DN, kind != TimerKind::Off);
        }
        slots[base + LT_ACC] = Value::Int(acc);
        Ok(())
    }

    fn ladder_counter(&mut self, up: bool, base: usize, rc: bool) {
        let slots = &mut self.mem.slots;
        let (edge, over, under) = if up {
            (LC_CU, LC_OV, LC_UN)
        } else {
            (LC_CD, LC_UN, LC_OV)
        };
        let mut acc = slots[base + LC_ACC].as_i64() as i32;
        if rc && !slots[base + edge].truthy() {
            let limit = if up { i32::MAX } else { i32::MIN };
            if acc == limit {
                // Wrapping past the end: the opposite flag cancels, else
                // this one is set.
                if slots[base + under].truthy() {
                    slots[base + under] = Value::Bool(false);
                } else {
                    slots[base + over] = Value::Bool(true);
                }
            }
            acc = if up { acc.wrapping_add(1) } else { acc.wrapping_sub(1) };
            slots[base + LC_ACC] = Value::Int(i64::from(acc));
        }
        slots[base + edge] = Value::Bool(rc);
        let pre = slots[base + LC_PRE].as_i64();
        slots[base + LC_DN] = Value::Bool(i64::from(acc) >= pre);
    }

    /// A motion instruction in ladder: it executes when the rung is TRUE
    /// and its `.EN` is clear; a FALSE rung clears `.EN` once `.DN` or
    /// `.ER` is set.
    fn transitional(&mut self, call: &MotionCall, rc: bool) -> R<()> {
        let control = match call.control {
            Some(h) => Some(h),
            None => call.operands.iter().find_map(|o| match o {
                crate::program::ir::Operand::ControlAt(handles, index, name) => self.control_at(handles, index, name),
                _ => None,
            }),
        };
        self.check()?;
        let Some(control) = control else {
            if rc {
                self.motion_call(call)?;
            }
            return Ok(());
        };
        let bits = self.task.motion_bits(control);
        if rc {
            if !bits.en {
                self.motion_call(call)?;
            }
        } else if bits.en && (bits.dn || bits.er) {
            self.task
                .set_motion_bits(control, MotionInstructionBits { en: false, ..bits });
        }
        Ok(())
    }

    /// The words of a BSL/BSR array and the bits `LEN` covers, or `.ER`.
    fn control_len(&mut self, array: &ArrayAt, base: usize, per_element: i64) -> R<Option<(usize, i64)>> {
        let len = self.mem.slots[base + CT_LEN].as_i64();
        let start = self.eval(&array.start).as_i64();
        self.check()?;
        let room = (array.len as i64 - start) * per_element;
        if len < 0 || start < 0 || len > room {
            self.mem.slots[base + CT_ER] = Value::Bool(true);
            return Ok(None);
        }
        self.mem.slots[base + CT_ER] = Value::Bool(false);
        Ok(Some((array.base + start as usize, len)))
    }

    fn shift(
        &mut self,
        left: bool,
        array: &ArrayAt,
        base: usize,
        source: &crate::program::ir::CExpr,
        rc: bool,
    ) -> R<()> {
        if !rc {
            self.mem.slots[base + CT_EN] = Value::Bool(false);
            self.mem.slots[base + CT_DN] = Value::Bool(false);
            return Ok(());
        }
        if self.mem.slots[base + CT_EN].truthy() {
            return Ok(());
        }
        self.mem.slots[base + CT_EN] = Value::Bool(true);
        let input = self.eval(source).truthy();
        self.check()?;
        let Some((first, len)) = self.control_len(array, base, 32)? else {
            return Ok(());
        };
        let len = len as usize;
        let words = &mut self.mem.slots[first..first + len.div_ceil(32)];
        let get = |w: &[Value], i: usize| (w[i / 32].as_i64() >> (i % 32)) & 1 == 1;
        let put = |w: &mut [Value], i: usize, on: bool| {
            let x = w[i / 32].as_i64() as i32;
            let m = 1i32 << (i % 32);
            w[i / 32] = Value::Int(i64::from(if on { x | m } else { x & !m }));
        };
        if len > 0 {
            if left {
                let out = get(words, len - 1);
                for i in (1..len).rev() {
                    let b = get(words, i - 1);
                    put(words, i, b);
                }
                put(words, 0, input);
                self.mem.slots[base + CT_UL] = Value::Bool(out);
            } else {
                let out = get(words, 0);
                for i in 0..len - 1 {
                    let b = get(words, i + 1);
                    put(words, i, b);
                }
                put(words, len - 1, input);
                self.mem.slots[base + CT_UL] = Value::Bool(out);
            }
        }
        self.mem.slots[base + CT_DN] = Value::Bool(true);
        Ok(())
    }

    fn stack(&mut self, kind: StackKind, array: &ArrayAt, base: usize, value: &StackValue, rc: bool) -> R<()> {
        let load = matches!(kind, StackKind::FifoLoad | StackKind::LifoLoad);
        let enable = if load { CT_EN } else { CT_EU };
        let was = self.mem.slots[base + enable].truthy();
        self.mem.slots[base + enable] = Value::Bool(rc);
        if rc && !was {
            let pos = self.mem.slots[base + CT_POS].as_i64();
            if let Some((first, len)) = self.control_len(array, base, 1)? {
                if pos < 0 || pos > len {
                    self.mem.slots[base + CT_ER] = Value::Bool(true);
                } else {
                    let (first, len, pos) = (first, len as usize, pos as usize);
                    match value {
                        StackValue::Load(source) if pos < len => {
                            let v = self.eval(source);
                            self.check()?;
                            let (stored, bad) = array.ty.store(v);
                            if bad {
                                self.overflow("the value loaded does not fit the array");
                            }
                            self.mem.slots[first + pos] = stored;
                            self.mem.slots[base + CT_POS] = Value::Int(pos as i64 + 1);
                        }
                        StackValue::Unload(dest, ty) if pos > 0 => {
                            let at = if kind == StackKind::FifoUnload { 0 } else { pos - 1 };
                            let v = self.mem.slots[first + at];
                            if kind == StackKind::FifoUnload {
                                self.mem.slots.copy_within(first + 1..first + pos, first);
                            }
                            self.mem.slots[first + pos - 1] = array.ty.store(Value::Int(0)).0;
                            self.mem.slots[base + CT_POS] = Value::Int(pos as i64 - 1);
                            self.store(dest, *ty, v);
                            self.check()?;
                        }
                        _ => {}
                    }
                }
            }
        }
        let (pos, len) = (
            self.mem.slots[base + CT_POS].as_i64(),
            self.mem.slots[base + CT_LEN].as_i64(),
        );
        self.mem.slots[base + CT_DN] = Value::Bool(pos >= len);
        self.mem.slots[base + CT_EM] = Value::Bool(pos == 0);
        Ok(())
    }
}

/// LIM: between Low and High inclusive, or (Low above High) outside the
/// open range between them.
fn limit(low: Value, test: Value, high: Value) -> bool {
    let (l, t, h) = (low.as_f64(), test.as_f64(), high.as_f64());
    if l <= h { l <= t && t <= h } else { t >= l || t <= h }
}

/// Whether an integer ADD (`add`) or SUB of `x` and `y` in `ty` carries
/// out of (borrows into) its top bit, as unsigned numbers.
fn carried(add: bool, x: i64, y: i64, ty: Ty) -> bool {
    if ty == Ty::Dint {
        let (a, b) = (u64::from(x as u32), u64::from(y as u32));
        if add { a + b > u64::from(u32::MAX) } else { a < b }
    } else {
        let (a, b) = (x as u64, y as u64);
        if add { a.checked_add(b).is_none() } else { a < b }
    }
}

/// SWPB on a value of `bits` bits.
fn swap(x: i64, order: SwapOrder, bits: u32) -> i64 {
    if bits <= 16 {
        return i64::from((x as u16).swap_bytes() as i16);
    }
    let w = x as u32;
    let r = match order {
        SwapOrder::Reverse => w.swap_bytes(),
        SwapOrder::Word => w.rotate_left(16),
        SwapOrder::HighLow => ((w & 0x00FF_00FF) << 8) | ((w >> 8) & 0x00FF_00FF),
    };
    i64::from(r as i32)
}

/// BTD: `n` bits of `x` from bit `sb` into `old` from bit `db` (bits past
/// the destination's width are lost), as the destination's bit pattern.
fn bit_distribute(x: i64, sb: i64, old: i64, db: i64, n: i64, bits: u32) -> i64 {
    let mut v = old;
    for i in 0..n.clamp(0, 64) {
        let (s, d) = (sb + i, db + i);
        if !(0..64).contains(&s) || !(0..i64::from(bits)).contains(&d) {
            continue;
        }
        let on = (x >> s) & 1 == 1;
        v = if on { v | 1 << d } else { v & !(1 << d) };
    }
    // Back to the signed value of the destination's width.
    let shift = 64 - bits;
    (v << shift) >> shift
}

/// RES: a TIMER's, COUNTER's or CONTROL's accumulated value and bits
/// cleared.
fn reset(slots: &mut [Value], base: usize, s: Structure) {
    let cleared = |slots: &mut [Value], from: usize, to: usize| {
        for v in &mut slots[base + from..base + to] {
            *v = Value::Bool(false);
        }
    };
    match s {
        Structure::LadderTimer => {
            cleared(slots, LT_EN, LT_DN + 1);
            slots[base + LT_ACC] = Value::Int(0);
        }
        Structure::LadderCounter => {
            cleared(slots, LC_CU, LC_UN + 1);
            slots[base + LC_ACC] = Value::Int(0);
        }
        _ => {
            cleared(slots, CT_EN, CT_LEN);
            slots[base + CT_POS] = Value::Int(0);
        }
    }
}
