//! A running scan's frame stack: one entry per block, loop, routine call
//! and fault routine it is inside (`super`'s module doc).

use crate::program::ir::{CStmt, Place};
use crate::program::types::DataType;

/// Where a running scan is: one entry per block, loop and routine call it
/// is inside, innermost last. The interpreter runs them in a loop, not by
/// recursion, so that a scan can stop between any two statements (a
/// higher-priority task, a coarse update) and resume there ([`super::Paused`]).
#[derive(Debug, Clone, Copy)]
pub(super) enum Frame<'r> {
    /// A block's statements, `pc` the next one; `sub` is which block of
    /// the statement holding it this is (of a routine: the routine).
    Block { stmts: &'r [CStmt], pc: usize, sub: u32 },
    /// A FOR, WHILE or REPEAT between passes (`started`: after its first).
    Loop { stmt: &'r CStmt, started: bool },
    /// A JSR into a routine: the caller's routine and line to return to,
    /// and where the values its RET hands back go.
    Call {
        caller: usize,
        line: u32,
        returns: &'r [(Place, DataType)],
        power: super::power::Power,
    },
    /// The program's fault routine, running for the fault raised at the
    /// caller's routine and line (and the caller's rung, when ladder).
    FaultRoutine {
        caller: usize,
        line: u32,
        power: super::power::Power,
    },
}

/// An empty frame stack of any lifetime, in the allocation of `frames`
/// (`collect` of a mapped `into_iter` reuses it: the layouts are equal).
pub(super) fn recycle<'a, 'b>(mut frames: Vec<Frame<'a>>) -> Vec<Frame<'b>> {
    frames.clear();
    frames.into_iter().map(|_| unreachable!("the stack is empty")).collect()
}

#[cfg(test)]
mod tests {
    #[test]
    fn a_recycled_frame_stack_keeps_its_allocation() {
        let frames: Vec<super::Frame<'static>> = Vec::with_capacity(16);
        let ptr = frames.as_ptr() as usize;
        let again: Vec<super::Frame<'_>> = super::recycle(frames);
        assert!(again.capacity() >= 16);
        assert_eq!(again.as_ptr() as usize, ptr);
    }
}
