//! An axis' watch event: what MAW arms and what a crossing of the watch
//! position sets (the instructions are `task/instructions/maw.rs` and
//! `mdw.rs`). A leaf: the arming instruction's control structure is a type
//! parameter.

/// The watch event of one axis; `C` is the control structure of the MAW
/// that armed it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Watch<C> {
    /// The arming: forward (`true`) or reverse, and the MAW.
    pub(crate) armed: Option<(bool, C)>,
    /// `WatchPosition`: the set-point of the last arming, axis units.
    pub position: f64,
    /// `WatchEventStatus`: the event occurred since the last arming.
    pub event: bool,
    /// Events so far (for the event tasks triggered by them).
    pub events: u64,
    /// When the last event occurred, s: the crossing interpolated inside
    /// its coarse update.
    pub event_time_s: f64,
    /// The actual position at the last check, axis units.
    pub(crate) last_actual: f64,
}

impl<C> Default for Watch<C> {
    fn default() -> Self {
        Watch {
            armed: None,
            position: 0.0,
            event: false,
            events: 0,
            event_time_s: 0.0,
            last_actual: 0.0,
        }
    }
}

impl<C> Watch<C> {
    /// `WatchEventArmedStatus`.
    #[must_use]
    pub fn armed(&self) -> bool {
        self.armed.is_some()
    }
}

/// Where, as a fraction of the way from `from` to `to` (in (0, 1]), a
/// position moving `forward` (increasing) or back crosses `target`; on a
/// modulo axis (`period`) any position `target` + k · period. `None` when
/// it does not cross it in that direction. Reaching the target counts;
/// leaving it does not.
#[must_use]
pub fn crossing(from: f64, to: f64, target: f64, forward: bool, period: Option<f64>) -> Option<f64> {
    if !(from.is_finite() && to.is_finite()) || (forward && to <= from) || (!forward && to >= from) {
        return None;
    }
    let point = match period {
        // The first position congruent to the target past `from`.
        Some(p) if forward => target + p * ((from - target) / p).floor() + p,
        Some(p) => target + p * ((from - target) / p).ceil() - p,
        None => target,
    };
    let crossed = if forward {
        from < point && point <= to
    } else {
        to <= point && point < from
    };
    crossed.then(|| (point - from) / (to - from))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crossings_by_direction_and_on_a_modulo_axis() {
        assert_eq!(crossing(0.0, 2.0, 1.5, true, None), Some(0.75));
        assert_eq!(crossing(0.0, 2.0, 1.5, false, None), None);
        assert_eq!(crossing(2.0, 0.0, 1.5, false, None), Some(0.25));
        assert_eq!(crossing(1.5, 2.0, 1.5, true, None), None, "leaving it is no crossing");
        assert_eq!(crossing(1.0, 1.5, 1.5, true, None), Some(1.0), "reaching it is");
        // 350 → 370 on a 360 axis crosses 5 (at 365).
        assert_eq!(crossing(350.0, 370.0, 5.0, true, Some(360.0)), Some(0.75));
        assert_eq!(crossing(370.0, 350.0, 5.0, false, Some(360.0)), Some(0.25));
        assert_eq!(crossing(10.0, 20.0, 5.0, true, Some(360.0)), None);
    }
}
