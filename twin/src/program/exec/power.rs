//! A ladder rung's state as the scan carries it: its condition, its
//! open branches, the MCR zone (the `ladder` module executes it; a call
//! frame keeps the caller's).

/// The deepest branch nesting [`Power`] holds (the parser's bound).
pub(super) const MAX_LEGS: u8 = crate::st::parse::MAX_BRANCH_NESTING as u8;

/// A rung's state: its condition, its open branches, the MCR zone.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Power {
    /// The rung condition at this point.
    pub rc: bool,
    /// Bit `d`: the condition branch `d` started with.
    pub(super) starts: u32,
    /// Bit `d`: the OR of branch `d`'s finished legs.
    pub(super) legs: u32,
    /// Open branches.
    pub(super) depth: u8,
    /// An MCR zone is open.
    pub(super) mcr_open: bool,
    /// The open zone's MCR was FALSE: its rungs run FALSE.
    pub(super) mcr_off: bool,
}

pub(super) fn bit(word: u32, d: u8) -> bool {
    word >> d & 1 == 1
}

pub(super) fn with(word: u32, d: u8, on: bool) -> u32 {
    if on { word | 1 << d } else { word & !(1 << d) }
}
