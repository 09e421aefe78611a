//! Instruction calls: each operand evaluated into the value the catalogue
//! says the instruction takes ([`planner::task::Arg`]), then the call
//! handed to the instruction ([`MotionTask::execute`]). Arrays and CAM
//! arrays are read from tag memory into a [`Scratch`], kept from call to
//! call, so a call builds nothing on the heap once warm.
//!
//! An element operand whose subscript lies outside its array is
//! [`Arg::NoElement`]: the instruction refuses it (ERR 13 with the
//! operand's faceplate index), as the controller refuses such an operand.
//! A refusal of an operand's value (ERR 13) is also kept in the scan's
//! refusals, which the summary lists.

use super::scratch::MAX_OPERANDS;
use super::{Exec, R};
use crate::program::ir::{MotionCall, Operand};
use crate::program::memory::Memory;
use crate::program::types::Value;
use planner::catalogue::Kind;
use planner::instruction::Fault;
use planner::mccp::CamElement;
use planner::task::{Arg, Args};

/// Where an array operand's values are in the scratch.
#[derive(Debug, Clone, Copy)]
enum Slice {
    None,
    Numbers(usize, usize),
    Cams(usize, usize, usize),
    OutputCams(usize, usize),
    Compensations(usize, usize),
    NoElement,
}

impl Exec<'_> {
    /// Executes an instruction call of a routine.
    pub(super) fn motion_call(&mut self, call: &MotionCall) -> R<()> {
        if let Err(fault) = self.execute_call(call)?
            && fault.err() == 13
        {
            let refusal = refusal_text(call, &fault);
            self.refusals
                .push(format!("{} (line {}): {refusal}", call.instruction.mnemonic, self.line));
        }
        Ok(())
    }

    /// Evaluates the operands (a fault while evaluating, a subscript out of
    /// range say, stops the statement) and executes the call: the
    /// instruction's refusal, if it refused.
    pub(super) fn execute_call(&mut self, call: &MotionCall) -> R<Result<(), Fault>> {
        let n = call.operands.len().min(MAX_OPERANDS);
        let mut values = [Value::Int(0); MAX_OPERANDS];
        let mut slices = [Slice::None; MAX_OPERANDS];
        self.scratch.numbers.clear();
        self.scratch.cams.clear();
        self.scratch.output_cams.clear();
        self.scratch.compensations.clear();
        for (i, op) in call.operands.iter().take(n).enumerate() {
            match op {
                Operand::Fixed(_) | Operand::Values(_) | Operand::CamPoints(..) => {}
                Operand::Number(e) | Operand::Integer(e) | Operand::Bool(e) => values[i] = self.eval(e),
                Operand::ControlAt(handles, index, name) => {
                    // Outside the array: the fault stops the statement below.
                    let k = self
                        .control_at(handles, index, name)
                        .map_or(0, |h| handles.iter().position(|x| *x == h).unwrap_or(0));
                    values[i] = Value::Int(k as i64);
                }
                Operand::Scalar(e) => {
                    let x = self.eval(e).as_f64();
                    let at = self.scratch.numbers.len();
                    self.scratch.numbers.push(x);
                    slices[i] = Slice::Numbers(at, at + 1);
                }
                Operand::Array(a) => {
                    let start = self.eval(&a.start).as_i64();
                    slices[i] = match usize::try_from(start) {
                        Ok(s) if s <= a.len => {
                            let at = self.scratch.numbers.len();
                            let slots = &self.mem.slots[a.base + s..a.base + a.len];
                            self.scratch.numbers.extend(slots.iter().map(|v| v.as_f64()));
                            Slice::Numbers(at, self.scratch.numbers.len())
                        }
                        _ => Slice::NoElement,
                    };
                }
                Operand::Cam(a) => {
                    let start = self.eval(&a.start).as_i64();
                    let at = self.scratch.cams.len();
                    read_cam(self.mem, a.base, a.len, &mut self.scratch.cams);
                    let start = usize::try_from(start).unwrap_or(a.len);
                    slices[i] = Slice::Cams(at, self.scratch.cams.len(), start);
                }
                Operand::Structures(a, structure) => {
                    let start = self.eval(&a.start).as_i64();
                    slices[i] = match usize::try_from(start) {
                        Ok(s) if s < a.len => read_structures(self.mem, a, s, *structure, self.scratch),
                        _ => Slice::NoElement,
                    };
                }
            }
        }
        self.check()?;
        let scratch = &*self.scratch;
        let mut args = [Arg::Absent; MAX_OPERANDS];
        for (i, op) in call.operands.iter().take(n).enumerate() {
            args[i] = match op {
                Operand::Fixed(a) => *a,
                Operand::ControlAt(handles, ..) => Arg::Control(handles[values[i].as_i64() as usize]),
                Operand::Number(_) => Arg::Number(values[i].as_f64()),
                Operand::Integer(_) => Arg::Integer(values[i].as_i64()),
                Operand::Bool(_) => Arg::Bool(values[i].truthy()),
                Operand::Values(v) => Arg::Array(v),
                Operand::CamPoints(points, start) => Arg::Cam(points, *start),
                Operand::Scalar(_) | Operand::Array(_) | Operand::Cam(_) | Operand::Structures(..) => match slices[i] {
                    Slice::Numbers(a, b) => Arg::Array(&scratch.numbers[a..b]),
                    Slice::Cams(a, b, start) => Arg::Cam(&scratch.cams[a..b], start),
                    Slice::OutputCams(a, b) => Arg::OutputCams(&scratch.output_cams[a..b]),
                    Slice::Compensations(a, b) => Arg::Compensations(&scratch.compensations[a..b]),
                    Slice::NoElement | Slice::None => Arg::NoElement,
                },
            };
        }
        let args = Args {
            values: &args[..n],
            instance: call.instance,
        };
        let result = call.instruction.execute(self.task, &args);
        // Output operands: what the instruction wrote goes to the array's
        // elements from the one named (MCTP's Transform Position), or to
        // the REAL tags in order (MCSV's values).
        if let Some(values) = self.task.take_output() {
            let mut reals = values.iter();
            for (i, op) in call.operands.iter().take(n).enumerate() {
                let kind = call.instruction.operands[i].kind;
                match (op, slices[i]) {
                    (Operand::Array(a), Slice::Numbers(from, to))
                        if kind == Kind::OutputVector3 && to - from >= values.len() =>
                    {
                        let first = a.base + a.len - (to - from);
                        for (k, x) in values.iter().enumerate() {
                            let slot = first + k;
                            self.mem.slots[slot] = self.mem.types[slot].store(Value::Real(*x)).0;
                        }
                    }
                    (Operand::Fixed(Arg::Reference(slot)), _) if kind == Kind::OutputReal => {
                        if let Some(x) = reals.next() {
                            self.mem.slots[*slot] = self.mem.types[*slot].store(Value::Real(*x)).0;
                        }
                    }
                    _ => {}
                }
            }
        }
        Ok(result)
    }
}

/// `ERR 13 (parameter out of range) EXERR 9 (Profile): the planner's
/// sentence`.
pub(in crate::program) fn refusal_text(call: &MotionCall, fault: &Fault) -> String {
    format!(
        "{}: {fault}",
        call.instruction.refusal_codes(fault.err(), fault.exerr())
    )
}

/// The elements of an `OUTPUT_CAM` or `OUTPUT_COMPENSATION` array from
/// element `start` to its end, read into the scratch.
fn read_structures(
    mem: &Memory,
    a: &crate::program::ir::ArrayAt,
    start: usize,
    structure: crate::program::types::Structure,
    scratch: &mut super::scratch::Scratch,
) -> Slice {
    use crate::program::types::Structure as S;
    let size = structure.size();
    let at = |k: usize, m: usize| mem.slots[a.base + k * size + m];
    match structure {
        S::OutputCam => {
            let first = scratch.output_cams.len();
            for k in start..a.len {
                scratch.output_cams.push(planner::output_cam::OutputCamElement {
                    output_bit: at(k, 0).as_i64(),
                    latch_type: at(k, 1).as_i64(),
                    unlatch_type: at(k, 2).as_i64(),
                    left: at(k, 3).as_f64(),
                    right: at(k, 4).as_f64(),
                    duration: at(k, 5).as_f64(),
                    enable_type: at(k, 6).as_i64(),
                    enable_bit: at(k, 7).as_i64(),
                });
            }
            Slice::OutputCams(first, scratch.output_cams.len())
        }
        _ => {
            let first = scratch.compensations.len();
            for k in start..a.len {
                scratch.compensations.push(planner::output_cam::OutputCompensation {
                    offset: at(k, 0).as_f64(),
                    latch_delay: at(k, 1).as_f64(),
                    unlatch_delay: at(k, 2).as_f64(),
                    mode: at(k, 3).as_i64(),
                    cycle_time: at(k, 4).as_f64(),
                    duty_cycle: at(k, 5).as_f64(),
                });
            }
            Slice::Compensations(first, scratch.compensations.len())
        }
    }
}

/// The elements of a CAM array in tag memory: master, slave, and the
/// segment type, 0 linear and any other value cubic (the controller's
/// MCCP reads the member the same way: zero or not).
fn read_cam(mem: &Memory, base: usize, len: usize, out: &mut Vec<CamElement>) {
    for i in 0..len {
        let at = base + 3 * i;
        out.push(CamElement {
            master: mem.slots[at].as_f64(),
            slave: mem.slots[at + 1].as_f64(),
            segment_type: i32::from(mem.slots[at + 2].as_i64() != 0),
        });
    }
}
