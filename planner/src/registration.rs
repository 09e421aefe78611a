//! An axis' registration inputs: what MAR arms and what an event latches
//! (the instruction is `task/instructions/mar.rs`; MDR disarms). A leaf:
//! the arming instruction's control structure is a type parameter.

/// How an input is armed: the edge and the window.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Arm {
    /// The event is the input's falling edge (`negative_edge`).
    pub falling: bool,
    /// The window, when windowed: (Minimum, Maximum).
    pub window: Option<(f64, f64)>,
}

/// One registration input of an axis; `C` is the control structure of the
/// MAR that armed it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RegistrationInput<C> {
    /// The arming and the MAR that made it.
    pub(crate) armed: Option<(Arm, C)>,
    /// `RegEventNStatus`: an event occurred since the last arming.
    pub event: bool,
    /// `RegistrationNPosition`: the actual position at the last event,
    /// axis units.
    pub position: f64,
    /// Events so far (for the event tasks triggered by them).
    pub events: u64,
}

impl<C> Default for RegistrationInput<C> {
    fn default() -> Self {
        RegistrationInput {
            armed: None,
            event: false,
            position: 0.0,
            events: 0,
        }
    }
}

impl<C> RegistrationInput<C> {
    /// `RegEventNArmedStatus`.
    #[must_use]
    pub fn armed(&self) -> bool {
        self.armed.is_some()
    }
}

/// Whether `position` lies in the window `(min, max)`; on a modulo axis
/// (`rotary`, position unwound) `min > max` is a window across the unwind.
#[must_use]
pub fn in_window((min, max): (f64, f64), position: f64, rotary: bool) -> bool {
    if rotary && min > max {
        position >= min || position <= max
    } else {
        min <= position && position <= max
    }
}
